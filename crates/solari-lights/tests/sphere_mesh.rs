//! A tessellated sphere light: the irradiance it gives against Lambert's exact formula for its
//! triangles, and against the closed form for a sphere of the same area, level by level.
//!
//! The light's pdf and emission use each triangle's geometric (flat) normal, not the mesh's
//! interpolated one: the emitting surface is the triangles themselves, so converting the area
//! pdf to solid angle needs the true cosine of the surface that was sampled (the Jacobian of
//! that surface), and a BRDF ray that hits an emitter sees the same flat triangle, so MIS
//! compares the two pdfs of one surface. Interpolated normals would describe a smooth sphere
//! that is not what is sampled: at a silhouette they can face away from a point that sees the
//! triangle's front, and the estimate would be biased by the difference.

mod common;

use glam::{Mat4, Vec3};
use solari_lights::analytic::polygon_irradiance;
use solari_lights::{Light, LightList, Selection};
use solari_scene::{Instance, Material, Scene};

/// A sphere light of radius `radius` at `centre` tessellated `segments × rings`.
fn sphere_light(segments: u32, rings: u32, centre: Vec3, radius: f32, l: f32) -> Scene {
    Scene {
        meshes: vec![solari_scene::textured_scene::uv_sphere(
            "ball", segments, rings,
        )],
        instances: vec![Instance {
            name: "ball".into(),
            mesh: 0,
            material: 0,
            transform: Mat4::from_translation(centre) * Mat4::from_scale(Vec3::splat(radius)),
        }],
        materials: vec![Material {
            emissive: Vec3::splat(l),
            ..Default::default()
        }],
        ..Default::default()
    }
}

#[test]
fn tessellated_sphere_light_matches_lambert_and_approaches_the_sphere() {
    let (centre, radius, l) = (Vec3::new(0.3, 2.0, -0.2), 0.5f32, 3.0f32);
    let x = Vec3::ZERO;
    let n = Vec3::Y;
    let mut previous_gap = f64::INFINITY;
    for (segments, rings) in [(8, 4), (16, 8), (32, 16), (64, 32), (128, 64)] {
        let scene = sphere_light(segments, rings, centre, radius, l);
        let list = LightList::build(&scene);
        let Light::Emissive { area, .. } = list.lights[0] else {
            panic!("an emissive light")
        };
        // Exact for the polyhedron: the front-facing triangles tile its silhouette.
        let mesh = &scene.meshes[0];
        let m = scene.instances[0].transform;
        let exact: f64 = (0..mesh.triangle_count())
            .map(|t| {
                polygon_irradiance(
                    x,
                    n,
                    &mesh.triangle(t).map(|p| m.transform_point3(p)),
                    l as f64,
                )
            })
            .sum();
        // The closed form for a sphere of the same area (π L R² cos θ / d²).
        let r_eff = (area as f64 / (4.0 * std::f64::consts::PI)).sqrt();
        let to = (centre - x).as_dvec3();
        let sphere = std::f64::consts::PI * l as f64 * r_eff * r_eff * (to.y / to.length())
            / to.length_squared();
        // Light sampling's estimate.
        let (mean, se) =
            common::estimate(&list, Selection::Power, x, n, 1_000_000, segments as u64);
        let gap = (exact / sphere - 1.0).abs();
        eprintln!(
            "{segments}x{rings}: estimate {mean:.5} ± {se:.5}, Lambert {exact:.5}, sphere of equal \
             area {sphere:.5} (tessellation error {:.3}%)",
            100.0 * gap
        );
        assert!(
            (mean - exact).abs() <= 4.0 * se + 1e-4 * exact,
            "{segments}x{rings}: estimate {mean} ± {se} vs {exact}"
        );
        // The tessellation error shrinks with the level, to below 0.1% at 128 × 64.
        assert!(
            gap < previous_gap,
            "{segments}x{rings}: {gap} after {previous_gap}"
        );
        previous_gap = gap;
    }
    assert!(previous_gap < 1e-3, "{previous_gap}");
}
