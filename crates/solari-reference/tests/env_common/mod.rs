//! Scenes under environment maps, shared by the reference tracer's and the real-time
//! renderer's environment tests (the latter includes this file by path).
#![allow(dead_code)]

use glam::{Mat4, Vec2, Vec3, Vec4};
use solari_scene::model::{Camera, Instance, Material, Mesh};
use solari_scene::{EnvironmentMap, Scene};
use std::sync::Arc;

/// A map with smooth colour gradients, a brighter band near the horizon and a hot spot, at
/// `scale` times its base brightness.
pub fn sky(w: u32, h: u32, scale: f32) -> EnvironmentMap {
    let texels = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            let (u, v) = (x / w as f32, y / h as f32);
            let phase = (u * std::f32::consts::TAU).sin();
            let spot = if (u - 0.3).abs() < 0.06 && (v - 0.3).abs() < 0.06 {
                8.0
            } else {
                0.0
            };
            scale
                * Vec3::new(
                    0.5 + 0.4 * phase + spot,
                    1.0 - v * 0.8 + spot,
                    0.3 + 0.6 * (1.0 - (2.0 * v - 1.0).abs()),
                )
        })
        .collect();
    EnvironmentMap::new(w, h, texels).unwrap()
}

pub fn quad(name: &str, half: f32, y: f32) -> Mesh {
    Mesh {
        name: name.into(),
        positions: vec![
            Vec3::new(-half, y, -half),
            Vec3::new(half, y, -half),
            Vec3::new(half, y, half),
            Vec3::new(-half, y, half),
        ],
        normals: vec![Vec3::Y; 4],
        uvs: vec![Vec2::ZERO; 4],
        tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
        indices: vec![0, 2, 1, 0, 3, 2],
    }
}

/// `mesh` alone under `material` (one instance, untransformed), seen straight down from 3 m
/// above the origin with a vertical field of view of `yfov`; no lights.
pub fn seen_from_above(mesh: Mesh, material: Material, yfov: f32) -> Scene {
    Scene {
        meshes: vec![mesh],
        instances: vec![Instance {
            name: "floor".into(),
            mesh: 0,
            material: 0,
            transform: Mat4::IDENTITY,
        }],
        materials: vec![material],
        cameras: vec![Camera::look_at(
            "down",
            Vec3::new(0.0, 3.0, 0.0),
            Vec3::ZERO,
            Vec3::Z,
            yfov,
        )],
        ..Default::default()
    }
}

/// Direct light only, `spp` paths through each pixel's centre of a `size` × `size` image
/// (software tracing, power-proportional light selection); every sample kept and finite.
pub fn direct_light_image(
    gpu: &solari_scene::gpu::Gpu,
    scene: &Scene,
    size: u32,
    spp: u32,
) -> solari_reference::path_tracer::ReferenceImage {
    let settings = solari_reference::path_tracer::ReferenceSettings {
        spp,
        max_bounces: 1,
        selection: solari_lights::Selection::Power,
        pixel_centre: true,
        min_bounces: 0,
    };
    let img = solari_reference::reference_image(
        gpu,
        solari_scene::shaders::Backend::Software,
        scene,
        size,
        size,
        &settings,
    )
    .expect("render");
    assert_eq!(img.rejected_samples, 0);
    assert!(img.pixels.iter().flatten().all(|c| c.is_finite()));
    img
}

pub fn scene_with(map: EnvironmentMap, mesh: Mesh, material: Material, camera: Camera) -> Scene {
    Scene {
        meshes: vec![mesh],
        instances: vec![Instance {
            name: "quad".into(),
            mesh: 0,
            material: 0,
            transform: Mat4::IDENTITY,
        }],
        materials: vec![material],
        cameras: vec![camera],
        environment_radiance: Vec3::ONE,
        environment_map: Some(Arc::new(map)),
        ..Default::default()
    }
}

/// Irradiance on an upward-facing surface (normal +Y) that sees the whole upper hemisphere of
/// `scene`'s environment, by the midpoint rule.
pub fn floor_irradiance(scene: &Scene) -> glam::DVec3 {
    let (nt, np) = (400, 800);
    let mut irradiance = glam::DVec3::ZERO;
    for i in 0..nt {
        let theta = (i as f64 + 0.5) / nt as f64 * std::f64::consts::FRAC_PI_2;
        for j in 0..np {
            let phi = (j as f64 + 0.5) / np as f64 * std::f64::consts::TAU;
            let d = Vec3::new(
                (theta.sin() * phi.cos()) as f32,
                theta.cos() as f32,
                (theta.sin() * phi.sin()) as f32,
            );
            let dw = theta.sin()
                * (std::f64::consts::FRAC_PI_2 / nt as f64)
                * (std::f64::consts::TAU / np as f64);
            irradiance += scene.environment(d).as_dvec3() * theta.cos() * dw;
        }
    }
    irradiance
}

/// An exactly Lambertian material (no specular layer) of grey `albedo`.
pub fn lambert(albedo: f32) -> Material {
    Material {
        base_color: Vec4::new(albedo, albedo, albedo, 1.0),
        metallic: 0.0,
        roughness: 1.0,
        dielectric_f0: Vec3::ZERO,
        dielectric_f90: 0.0,
        ..Default::default()
    }
}

/// A huge Lambertian floor of `albedo` under the `sky` map, seen straight down through a
/// narrow view, so that every pixel reads `albedo / π × floor_irradiance`.
pub fn floor_under_sky(albedo: f32) -> Scene {
    let camera = Camera::look_at("down", Vec3::new(0.0, 1.0, 0.0), Vec3::ZERO, Vec3::Z, 0.1);
    scene_with(
        sky(32, 16, 1.0),
        quad("floor", 1000.0, 0.0),
        lambert(albedo),
        camera,
    )
}
