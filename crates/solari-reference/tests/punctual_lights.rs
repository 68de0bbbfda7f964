//! The reference tracer under point, spot and tessellated sphere lights, against closed forms:
//! a Lambertian floor seen from above reads ρ/π · E, where a delta point light or a sphere
//! wholly above the floor gives E = I cos θ / d², a spot scales that by glTF's cone falloff,
//! and an emissive mesh gives Lambert's polygon formula summed over its triangles. The sphere
//! cases check light sampling and BRDF hits combined by MIS (both halves must be there,
//! weighted right, for the sum to come out).

mod env_common;

use env_common::{direct_light_image, seen_from_above};
use glam::{Vec3, Vec4};
use solari_lights::SpotCone;
use solari_lights::analytic::polygon_irradiance;
use solari_reference::path_tracer::ReferenceImage;
use solari_scene::Scene;
use solari_scene::gpu::test_gpu;
use solari_scene::gpu_types::GpuView;
use solari_scene::model::{Instance, Material, Mesh, PunctualKind, PunctualLight};

const SIZE: u32 = 64;
const ALBEDO: f32 = 0.5;

/// A 40 m Lambertian floor at y = 0 (no specular layer), seen straight down from 3 m.
fn floor_scene(light: PunctualLight) -> Scene {
    let s = 20.0;
    let floor = Mesh {
        name: "floor".into(),
        positions: vec![
            Vec3::new(-s, 0.0, -s),
            Vec3::new(-s, 0.0, s),
            Vec3::new(s, 0.0, s),
            Vec3::new(s, 0.0, -s),
        ],
        normals: vec![Vec3::Y; 4],
        uvs: vec![glam::Vec2::ZERO; 4],
        tangents: vec![Vec4::X; 4],
        indices: vec![0, 1, 2, 0, 2, 3],
    };
    let material = Material {
        name: "lambert".into(),
        base_color: Vec4::new(ALBEDO, ALBEDO, ALBEDO, 1.0),
        metallic: 0.0,
        roughness: 1.0,
        dielectric_f0: Vec3::ZERO,
        dielectric_f90: 0.0,
        ..Default::default()
    };
    Scene {
        punctual_lights: vec![light],
        ..seen_from_above(floor, material, 1.2)
    }
}

/// The floor point each pixel centre sees (the camera's own ray model).
fn floor_points(scene: &Scene) -> Vec<Vec3> {
    let v = GpuView::new(&scene.camera(None).unwrap(), SIZE, SIZE);
    let (o, f, r, u) = (
        Vec3::from(v.origin),
        Vec3::from(v.forward),
        Vec3::from(v.right),
        Vec3::from(v.up),
    );
    (0..SIZE * SIZE)
        .map(|i| {
            let (px, py) = ((i % SIZE) as f32 + 0.5, (i / SIZE) as f32 + 0.5);
            let ndc = (px / SIZE as f32 * 2.0 - 1.0, 1.0 - py / SIZE as f32 * 2.0);
            let d = f + r * (ndc.0 * v.tan_half_fov * v.aspect) + u * (ndc.1 * v.tan_half_fov);
            o + d * (-o.y / d.y)
        })
        .collect()
}

fn render(scene: &Scene, spp: u32) -> Option<ReferenceImage> {
    let gpu = test_gpu()?;
    Some(direct_light_image(&gpu, scene, SIZE, spp))
}

/// Radiance the floor reflects at `x` under `light` (red channel).
fn expected(light: &PunctualLight, x: Vec3) -> f64 {
    let to = light.position - x;
    let d2 = to.length_squared();
    let l = to / d2.sqrt();
    let att = match light.kind {
        PunctualKind::Point => 1.0,
        PunctualKind::Spot { inner, outer } => {
            SpotCone::new(light.direction, inner, outer).attenuation(-l)
        }
    };
    (ALBEDO / std::f32::consts::PI * light.intensity.x * att * l.y.max(0.0) / d2) as f64
}

/// Sum of the image and of the closed form over the pixels `keep` selects.
fn sums(img: &ReferenceImage, want: &[f64], keep: impl Fn(usize) -> bool) -> (f64, f64) {
    let mut s = (0.0, 0.0);
    for (i, (p, w)) in img.pixels.iter().zip(want).enumerate() {
        if keep(i) {
            s.0 += p[0] as f64;
            s.1 += w;
        }
    }
    s
}

fn point(position: Vec3, radius: f32, kind: PunctualKind) -> PunctualLight {
    PunctualLight {
        name: "light".into(),
        kind,
        position,
        direction: Vec3::NEG_Y,
        intensity: Vec3::splat(4.0),
        range: None,
        radius,
    }
}

/// An emissive uv-sphere (64 × 32) of radius 0.5 over the floor: the image against Lambert's
/// formula over its triangles (which is within 0.02% of a sphere of equal area,
/// `solari-lights/tests/sphere_mesh.rs`). Light sampling picks flat triangles and BRDF rays
/// hit them; both use the geometric normal, so MIS compares two pdfs of one surface.
#[test]
fn tessellated_sphere_light_on_a_plane() {
    let mut scene = floor_scene(point(Vec3::ZERO, 0.0, PunctualKind::Point));
    scene.punctual_lights.clear();
    let (centre, radius, l) = (Vec3::new(-0.3, 1.3, 0.2), 0.5f32, 2.0f32);
    scene
        .meshes
        .push(solari_scene::textured_scene::uv_sphere("ball", 64, 32));
    scene.materials.push(Material {
        name: "glow".into(),
        emissive: Vec3::splat(l),
        ..Default::default()
    });
    let transform =
        glam::Mat4::from_translation(centre) * glam::Mat4::from_scale(Vec3::splat(radius));
    scene.instances.push(Instance {
        name: "ball".into(),
        mesh: 1,
        material: 1,
        transform,
    });
    let Some(img) = render(&scene, 256) else {
        return;
    };
    let points = floor_points(&scene);
    let ball = &scene.meshes[1];
    let triangles: Vec<[Vec3; 3]> = (0..ball.triangle_count())
        .map(|t| ball.triangle(t).map(|p| transform.transform_point3(p)))
        .collect();
    // Pixels that see the ball itself read its emission, not the floor: left out.
    let sees_ball = |x: Vec3| {
        let eye = Vec3::new(0.0, 3.0, 0.0);
        let d = (x - eye).normalize();
        let oc = centre - eye;
        let b = oc.dot(d);
        (oc - d * b).length() < radius * 1.01
    };
    let want: Vec<f64> = points
        .iter()
        .map(|x| {
            let e: f64 = triangles
                .iter()
                .map(|t| polygon_irradiance(*x, Vec3::Y, t, l as f64))
                .sum();
            ALBEDO as f64 / std::f64::consts::PI * e
        })
        .collect();
    let (got, exp) = sums(&img, &want, |i| !sees_ball(points[i]));
    eprintln!("tessellated sphere: image {got:.4}, Lambert {exp:.4}");
    assert!((got / exp - 1.0).abs() < 0.01, "{got} vs {exp}");
}

/// An emissive quad with a checker texture (half the texels white, half black: mean 0.5 in
/// linear light), facing down over the floor: the image against Lambert's formula for the quad
/// at the texture's mean radiance. The checker's deviation from its mean cancels to first
/// order in the smooth kernel cos cos / d² (equal counts, alternating), so the closed form
/// holds to well under 1% here.
#[test]
fn emissive_textured_quad_gives_its_mean_power() {
    let mut scene = floor_scene(point(Vec3::ZERO, 0.0, PunctualKind::Point));
    scene.punctual_lights.clear();
    let (h, half, factor) = (1.6f32, 0.25f32, 4.0f32);
    let corners = [
        Vec3::new(-half, h, -half),
        Vec3::new(half, h, -half),
        Vec3::new(half, h, half),
        Vec3::new(-half, h, half),
    ];
    scene.meshes.push(Mesh {
        name: "panel".into(),
        positions: corners.to_vec(),
        normals: vec![Vec3::NEG_Y; 4],
        uvs: vec![
            glam::Vec2::new(0.0, 0.0),
            glam::Vec2::new(1.0, 0.0),
            glam::Vec2::new(1.0, 1.0),
            glam::Vec2::new(0.0, 1.0),
        ],
        tangents: vec![Vec4::X; 4],
        // Counter-clockwise seen from below: the panel faces down.
        indices: vec![0, 1, 2, 0, 2, 3],
    });
    scene
        .textures
        .push(solari_scene::textured_scene::checker_texture("checker", 8));
    scene.materials.push(Material {
        name: "panel".into(),
        emissive: Vec3::splat(factor),
        emissive_texture: Some(0),
        ..Default::default()
    });
    scene.instances.push(Instance {
        name: "panel".into(),
        mesh: 1,
        material: 1,
        transform: glam::Mat4::IDENTITY,
    });
    let Some(img) = render(&scene, 256) else {
        return;
    };
    let points = floor_points(&scene);
    let mean = scene.textures[0].mean_linear().x;
    assert!((mean - 0.5).abs() < 1e-3, "{mean}");
    let want: Vec<f64> = points
        .iter()
        .map(|x| {
            let e = polygon_irradiance(*x, Vec3::Y, &corners, (factor * mean) as f64);
            ALBEDO as f64 / std::f64::consts::PI * e
        })
        .collect();
    // Pixels whose camera ray crosses the panel see its unlit back, not the floor.
    let eye = Vec3::new(0.0, 3.0, 0.0);
    let behind_panel = |x: Vec3| {
        let p = eye + (x - eye) * ((eye.y - h) / (eye.y - x.y));
        p.x.abs() <= half * 1.05 && p.z.abs() <= half * 1.05
    };
    let (got, exp) = sums(&img, &want, |i| !behind_panel(points[i]));
    eprintln!("textured panel: image {got:.4}, mean-power closed form {exp:.4}");
    assert!((got / exp - 1.0).abs() < 0.01, "{got} vs {exp}");
}

#[test]
fn point_light_irradiance_on_a_plane() {
    for (radius, spp) in [(0.0, 4), (0.5, 256)] {
        let light = point(Vec3::new(0.4, 1.2, -0.3), radius, PunctualKind::Point);
        let scene = floor_scene(light.clone());
        let Some(img) = render(&scene, spp) else {
            return;
        };
        let want: Vec<f64> = floor_points(&scene)
            .iter()
            .map(|x| expected(&light, *x))
            .collect();
        let (got, exp) = sums(&img, &want, |_| true);
        eprintln!("radius {radius}: image {got:.4}, closed form {exp:.4}");
        assert!(
            (got / exp - 1.0).abs() < 0.01,
            "radius {radius}: {got} vs {exp}"
        );
        // Per pixel too, where the delta light leaves no noise.
        if radius == 0.0 {
            for (p, w) in img.pixels.iter().zip(&want) {
                assert!((p[0] as f64 - w).abs() <= 2e-3 * w + 1e-6, "{p:?} vs {w}");
            }
        }
    }
}

#[test]
fn spot_light_cone_edge_on_a_plane() {
    let (inner, outer) = (0.3f32, 0.55f32);
    let spot = PunctualKind::Spot { inner, outer };
    for (radius, spp) in [(0.0, 4), (0.05, 256)] {
        let light = point(Vec3::new(0.2, 1.5, 0.1), radius, spot);
        let scene = floor_scene(light.clone());
        let Some(img) = render(&scene, spp) else {
            return;
        };
        let points = floor_points(&scene);
        let want: Vec<f64> = points.iter().map(|x| expected(&light, *x)).collect();
        // Angle off the spot's axis of each pixel's floor point.
        let angle = |i: usize| {
            let l = (points[i] - light.position).normalize();
            l.dot(light.direction).clamp(-1.0, 1.0).acos()
        };
        let band = |lo: f32, hi: f32| {
            let (got, exp) = sums(&img, &want, |i| (lo..hi).contains(&angle(i)));
            eprintln!("radius {radius}, angles {lo}..{hi}: image {got:.4}, closed form {exp:.4}");
            (got, exp)
        };
        let (got, exp) = band(0.0, inner);
        assert!((got / exp - 1.0).abs() < 0.01, "inside: {got} vs {exp}");
        // The falloff band: where the edge is.
        let (got, exp) = band(inner, outer);
        assert!((got / exp - 1.0).abs() < 0.01, "edge: {got} vs {exp}");
        // Outside the cone nothing, up to the sphere's own size.
        let (got, _) = band(outer + 0.05, 3.2);
        let (inside, _) = band(0.0, outer);
        assert!(got <= 1e-4 * inside, "outside: {got}");
    }
}
