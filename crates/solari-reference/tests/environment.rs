//! Environment maps in the reference tracer (GPU: lavapipe in CI): camera rays read the map
//! exactly as the CPU twin does (orientation, bilinear filter, half-float storage and its
//! scale for bright maps), and a Lambertian floor under a map reflects the irradiance that a
//! CPU quadrature of the same map gives.

use glam::{Vec2, Vec3};
use solari_lights::Selection;
use solari_reference::path_tracer::ReferenceSettings;
use solari_scene::gpu::test_gpu;
use solari_scene::gpu_types::GpuView;
use solari_scene::model::{Camera, Material};
use solari_scene::shaders::Backend;

mod env_common;
use env_common::{floor_irradiance, floor_under_sky, quad, scene_with, sky};

#[test]
fn camera_rays_read_the_map_as_the_cpu_twin_does() {
    let Some(gpu) = test_gpu() else { return };
    let size = 64;
    // Looking up and sideways so the view crosses the seam at u = 0 and the bright spot; the
    // only geometry is a small quad far below, out of view.
    let camera = Camera::look_at("sky", Vec3::ZERO, Vec3::new(0.2, 0.6, 1.0), Vec3::Y, 1.6);
    for scale in [1.0, 2.0e4] {
        let scene = scene_with(
            sky(48, 24, scale),
            quad("floor", 0.1, -50.0),
            Material::default(),
            camera.clone(),
        );
        let settings = ReferenceSettings {
            spp: 1,
            max_bounces: 0,
            selection: Selection::Power,
            pixel_centre: true,
            min_bounces: 0,
        };
        let img = solari_reference::reference_image(
            &gpu,
            Backend::Software,
            &scene,
            size,
            size,
            &settings,
        )
        .expect("render");
        let view = GpuView::new(&camera, size, size);
        let mut worst = 0.0f32;
        for (i, p) in img.pixels.iter().enumerate() {
            let pixel = Vec2::new(
                (i as u32 % size) as f32 + 0.5,
                (i as u32 / size) as f32 + 0.5,
            );
            let d = view.ray_direction(pixel).normalize();
            let expected = scene.environment(d);
            let got = Vec3::from_array(*p);
            // Half floats keep 11 bits; directions differ in the last bits of atan2 and acos.
            let err =
                ((got - expected).abs() / expected.max(Vec3::splat(1e-3 * scale))).max_element();
            worst = worst.max(err);
        }
        eprintln!("scale {scale}: worst relative error {worst:.2e}");
        assert!(worst < 4e-3, "scale {scale}: worst relative error {worst}");
    }
}

#[test]
fn a_lambertian_floor_reflects_the_maps_irradiance() {
    let Some(gpu) = test_gpu() else { return };
    let albedo = 0.8;
    let scene = floor_under_sky(albedo);
    let irradiance = floor_irradiance(&scene);
    let expected = irradiance * (albedo as f64 / std::f64::consts::PI);
    let settings = ReferenceSettings {
        spp: 256,
        max_bounces: 1,
        selection: Selection::Power,
        pixel_centre: false,
        min_bounces: 0,
    };
    let img = solari_reference::reference_image(&gpu, Backend::Software, &scene, 16, 16, &settings)
        .expect("render");
    assert_eq!(img.rejected_samples, 0);
    for c in 0..3 {
        let v: Vec<f64> = img.pixels.iter().map(|p| p[c] as f64).collect();
        let n = v.len() as f64;
        let mean = v.iter().sum::<f64>() / n;
        let se = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
        eprintln!(
            "channel {c}: {mean:.5} ± {se:.5}, quadrature {:.5}",
            expected[c]
        );
        assert!(
            (mean - expected[c]).abs() < 0.01 * expected[c] + 4.0 * se,
            "channel {c}: {mean} ± {se} against {}",
            expected[c]
        );
    }
}
