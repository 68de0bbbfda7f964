//! The light list, selection and sample resolution against analytic answers.

// `!(x > 0.0)` is deliberate: it rejects NaN along with non-positive values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod common;

use glam::{Mat4, Vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_lights::analytic::polygon_irradiance;
use solari_lights::{AliasTable, LIGHT_GONE, Light, LightList, Selection};
use solari_scene::{DirectionalLight, Instance, Material, Mesh, Scene};

/// A unit square in the xz plane at the origin, facing down (-y), as two triangles.
fn down_quad() -> Mesh {
    Mesh {
        name: "quad".into(),
        positions: vec![
            Vec3::new(-0.5, 0.0, -0.5),
            Vec3::new(0.5, 0.0, -0.5),
            Vec3::new(0.5, 0.0, 0.5),
            Vec3::new(-0.5, 0.0, 0.5),
        ],
        // Counter-clockwise seen from below: normal -y.
        indices: vec![0, 1, 2, 0, 2, 3],
        ..Default::default()
    }
}

fn emitter(emissive: Vec3) -> Material {
    Material {
        emissive,
        ..Default::default()
    }
}

/// Quads placed by `transforms`, each with its own material.
fn scene_of(quads: &[(Mat4, Vec3)]) -> Scene {
    let mut scene = Scene {
        meshes: vec![down_quad()],
        ..Default::default()
    };
    for (i, (m, e)) in quads.iter().enumerate() {
        scene.materials.push(emitter(*e));
        scene.instances.push(Instance {
            name: format!("light{i}"),
            mesh: 0,
            material: i as u32,
            transform: *m,
        });
    }
    scene
}

/// Light-sampling irradiance estimate (seed 17, as these tests were tuned with).
fn estimate(list: &LightList, sel: Selection, x: Vec3, n: Vec3, samples: usize) -> (f64, f64) {
    common::estimate(list, sel, x, n, samples, 17)
}

#[test]
fn alias_table_draws_in_proportion_to_weights() {
    let weights = [3.0, 0.0, 1.0, 7.5, f32::NAN, 0.25, 12.0, -4.0, 1.0];
    let table = AliasTable::new(&weights);
    let total: f32 = [3.0, 1.0, 7.5, 0.25, 12.0, 1.0].iter().sum();
    let mut rng = Pcg32::seed_from_u64(1);
    let n = 1_000_000;
    let mut counts = [0u64; 9];
    for _ in 0..n {
        counts[table.sample(rng.random(), rng.random())] += 1;
    }
    let (mut chi2, mut dof) = (0.0, 0usize);
    for (i, &w) in weights.iter().enumerate() {
        let p = if w.is_finite() && w > 0.0 {
            w / total
        } else {
            0.0
        };
        assert!(
            (table.pmf[i] - p).abs() < 1e-6,
            "pmf[{i}] = {}",
            table.pmf[i]
        );
        if p == 0.0 {
            assert_eq!(counts[i], 0, "weight {w} was drawn");
            continue;
        }
        let e = p as f64 * n as f64;
        chi2 += (counts[i] as f64 - e).powi(2) / e;
        dof += 1;
    }
    // 99.99th percentile of chi-square with 5 degrees of freedom is 25.7.
    assert!(chi2 < 25.7 && dof == 6, "chi-square {chi2} ({dof} cells)");
    // All-zero weights fall back to uniform.
    let uniform = AliasTable::new(&[0.0, 0.0, f32::INFINITY]);
    assert!(uniform.pmf.iter().all(|&p| (p - 1.0 / 3.0).abs() < 1e-6));
}

#[test]
fn lights_that_cannot_contribute_are_left_out_and_reported() {
    let mut scene = scene_of(&[
        (Mat4::IDENTITY, Vec3::ONE),
        (Mat4::IDENTITY, Vec3::ZERO),
        (Mat4::from_scale(Vec3::new(1.0, 1.0, 0.0)), Vec3::ONE),
        (Mat4::IDENTITY, Vec3::new(f32::NAN, 1.0, 1.0)),
    ]);
    scene.directional_lights.push(DirectionalLight {
        name: "black".into(),
        direction: -Vec3::Y,
        irradiance: Vec3::ZERO,
        angular_diameter: 0.01,
    });
    scene.directional_lights.push(DirectionalLight {
        name: "not finite".into(),
        direction: -Vec3::Y,
        irradiance: Vec3::new(1.0, f32::NAN, 1.0),
        angular_diameter: 0.01,
    });
    scene.directional_lights.push(DirectionalLight {
        name: "black, no direction".into(),
        direction: Vec3::NAN,
        irradiance: Vec3::ZERO,
        angular_diameter: 0.01,
    });
    let list = LightList::build(&scene);
    assert_eq!(list.len(), 1);
    assert_eq!(list.report.zero_area, vec![2]);
    assert_eq!(list.report.non_finite_emission, vec![3]);
    // A black light is switched off: left out, and not reported as a problem. One not
    // finite, or a black one without a direction, is broken.
    assert_eq!(list.report.off_directional, vec![0]);
    assert_eq!(list.report.dark_directional, vec![1, 2]);
    let lines = list.report.lines().join("\n");
    assert!(lines.contains("2 black or broken directional"), "{lines}");
    let off = list.report.off_line().expect("one light off");
    assert!(
        off.contains("1 light(s) switched off") && off.contains("[0]"),
        "{off}"
    );
    // A scene with nothing bright has an empty list, and sampling it gives nothing.
    let dark = LightList::build(&scene_of(&[(Mat4::IDENTITY, Vec3::ZERO)]));
    assert!(dark.is_empty());
    assert!(
        dark.sample(Selection::Power, Vec3::ZERO, [0.5; 4])
            .is_none()
    );
}

#[test]
fn sampling_elements_count_triangles_and_analytic_lights() {
    // Two bright quads (two triangles each) and a black one, which is left out.
    let mut scene = scene_of(&[
        (Mat4::IDENTITY, Vec3::ONE),
        (Mat4::from_translation(Vec3::Y), Vec3::ONE),
        (Mat4::IDENTITY, Vec3::ZERO),
    ]);
    assert_eq!(LightList::build(&scene).sampling_elements(), 4);
    let sun = |irradiance| DirectionalLight {
        name: "sun".into(),
        direction: -Vec3::Y,
        irradiance,
        angular_diameter: 0.01,
    };
    scene.directional_lights.push(sun(Vec3::ONE));
    // A black sun is no light, so no element either.
    scene.directional_lights.push(sun(Vec3::ZERO));
    assert_eq!(LightList::build(&scene).sampling_elements(), 5);
    // An environment map is a continuum of directions: unbounded.
    let map = solari_scene::EnvironmentMap::new(2, 1, vec![Vec3::ONE; 2]).unwrap();
    scene.environment_radiance = Vec3::ONE;
    scene.environment_map = Some(std::sync::Arc::new(map));
    assert_eq!(LightList::build(&scene).sampling_elements(), u32::MAX);
    assert_eq!(LightList::build(&Scene::default()).sampling_elements(), 0);
}

#[test]
fn translation_follows_keys_and_drops_removed_lights() {
    let t = |y: f32| Mat4::from_translation(Vec3::new(0.0, y, 0.0));
    let before = scene_of(&[
        (t(1.0), Vec3::ONE),
        (t(2.0), Vec3::ONE),
        (t(3.0), Vec3::ONE),
    ]);
    let mut after = before.clone();
    // Light 0 dims to black (gone), light 2 moves (same light), light 1 changes material.
    after.materials[0].emissive = Vec3::ZERO;
    after.instances[2].transform = t(5.0);
    after.materials.push(emitter(Vec3::splat(2.0)));
    after.instances[1].material = 3;
    let (a, b) = (LightList::build(&before), LightList::build(&after));
    let map = b.translation_from(&a);
    assert_eq!(map, vec![LIGHT_GONE, LIGHT_GONE, 1]);
    assert_eq!(a.translation_from(&a), vec![0, 1, 2]);
}

#[test]
fn area_light_irradiance_matches_the_analytic_answer() {
    // A bright small quad and a dim large one, so the two selections differ.
    let small =
        Mat4::from_translation(Vec3::new(0.3, 1.0, 0.0)) * Mat4::from_scale(Vec3::splat(0.3));
    let large =
        Mat4::from_translation(Vec3::new(-0.5, 1.5, 0.2)) * Mat4::from_scale(Vec3::splat(2.0));
    let scene = scene_of(&[(small, Vec3::splat(50.0)), (large, Vec3::splat(0.5))]);
    let list = LightList::build(&scene);
    let corners = |m: &Mat4| {
        down_quad()
            .positions
            .iter()
            .map(|p| m.transform_point3(*p))
            .collect::<Vec<_>>()
    };
    for x in [
        Vec3::ZERO,
        Vec3::new(0.7, 0.2, -0.4),
        Vec3::new(-1.0, 0.0, 1.0),
    ] {
        let n = Vec3::Y;
        let exact = polygon_irradiance(x, n, &corners(&small), 50.0)
            + polygon_irradiance(x, n, &corners(&large), 0.5);
        for sel in [Selection::Uniform, Selection::Power] {
            let (e, se) = estimate(&list, sel, x, n, 200_000);
            assert!(
                (e - exact).abs() < 4.0 * se + 2e-3 * exact,
                "{sel:?} at {x}: estimate {e:.5} ± {se:.5}, exact {exact:.5}"
            );
        }
    }
}

#[test]
fn power_selection_beats_uniform_when_lights_differ() {
    let small =
        Mat4::from_translation(Vec3::new(0.3, 1.0, 0.0)) * Mat4::from_scale(Vec3::splat(0.3));
    let mut quads = vec![(small, Vec3::splat(50.0))];
    for i in 0..8 {
        let far = Mat4::from_translation(Vec3::new(-3.0 + i as f32, 4.0, 3.0));
        quads.push((far, Vec3::splat(0.05)));
    }
    let list = LightList::build(&scene_of(&quads));
    let (_, se_uniform) = estimate(&list, Selection::Uniform, Vec3::ZERO, Vec3::Y, 50_000);
    let (_, se_power) = estimate(&list, Selection::Power, Vec3::ZERO, Vec3::Y, 50_000);
    eprintln!("standard error: uniform {se_uniform:.5}, power {se_power:.5}");
    assert!(se_power < 0.5 * se_uniform);
}

#[test]
fn sun_disk_delivers_its_irradiance() {
    for diameter in [0.0f32, 0.0093, 0.2] {
        let mut scene = scene_of(&[]);
        scene.directional_lights.push(DirectionalLight {
            name: "sun".into(),
            direction: Vec3::new(0.0, -1.0, 0.0),
            irradiance: Vec3::splat(3.0),
            angular_diameter: diameter,
        });
        let list = LightList::build(&scene);
        assert!(matches!(list.lights[0], Light::Directional { .. }));
        let (e, se) = estimate(&list, Selection::Power, Vec3::ZERO, Vec3::Y, 100_000);
        // L = E / (π sin² r) makes a facing surface receive exactly E.
        assert!((e - 3.0).abs() <= 4.0 * se + 1e-4, "d={diameter}: {e}");
        let tilted = Vec3::new(0.6, 0.8, 0.0);
        let (et, se) = estimate(&list, Selection::Power, Vec3::ZERO, tilted, 100_000);
        assert!(
            (et - 2.4).abs() < 4.0 * se + 0.02,
            "d={diameter}: tilted {et}"
        );
    }
}

#[test]
fn emissive_pdf_matches_the_sampling_pdf() {
    let scene = scene_of(&[
        (Mat4::from_translation(Vec3::Y), Vec3::ONE),
        (
            Mat4::from_translation(Vec3::new(1.0, 2.0, 0.0)) * Mat4::from_rotation_z(0.3),
            Vec3::splat(4.0),
        ),
    ]);
    let list = LightList::build(&scene);
    let mut rng = Pcg32::seed_from_u64(2);
    let x = Vec3::new(0.1, -0.5, 0.2);
    for sel in [Selection::Uniform, Selection::Power] {
        for _ in 0..1000 {
            let u = [rng.random(), rng.random(), rng.random(), rng.random()];
            let Some(s) = list.sample(sel, x, u) else {
                continue;
            };
            let Light::Emissive { first_triangle, .. } = list.lights[s.light as usize] else {
                unreachable!()
            };
            let tri = list.triangles[first_triangle as usize];
            let n = tri.e1.cross(tri.e2).normalize();
            let y = x + s.direction * s.distance;
            let p = list.emissive_pdf(sel, s.light as usize, x, y, n);
            assert!((p - s.pdf).abs() <= 1e-3 * s.pdf, "{p} vs {}", s.pdf);
        }
    }
}

#[test]
fn absurd_emission_and_degenerate_points_stay_finite() {
    let scene = scene_of(&[
        (Mat4::IDENTITY, Vec3::splat(1e30)),
        (Mat4::from_scale(Vec3::splat(1e15)), Vec3::splat(1e30)),
    ]);
    let list = LightList::build(&scene);
    assert!(list.power_table.pmf.iter().all(|p| p.is_finite()));
    let mut rng = Pcg32::seed_from_u64(9);
    for x in [
        Vec3::ZERO,
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::new(0.5, 0.0, 0.5),
    ] {
        for _ in 0..200 {
            let u = [rng.random(), rng.random(), rng.random(), rng.random()];
            if let Some(s) = list.sample(Selection::Power, x, u) {
                assert!(s.pdf.is_finite() && s.pdf > 0.0 && s.direction.is_finite());
                assert!(s.radiance.is_finite());
            }
        }
    }
}

/// A textured emitter's power counts its texture's mean (in linear light), and its samples
/// are flagged so the GPU's readers multiply in the texel; an out-of-range texture index is
/// treated as no texture rather than trusted.
#[test]
fn emissive_textures_weigh_power_and_flag_samples() {
    let mut scene = scene_of(&[
        (Mat4::from_translation(Vec3::Y), Vec3::splat(2.0)),
        (
            Mat4::from_translation(Vec3::new(3.0, 1.0, 0.0)),
            Vec3::splat(2.0),
        ),
    ]);
    // Half the texels white, half black: a mean of one half.
    scene
        .textures
        .push(solari_scene::textured_scene::checker_texture("checker", 8));
    scene.materials[0].emissive_texture = Some(0);
    let list = LightList::build(&scene);
    assert!(
        (list.power[0] / list.power[1] - 0.5).abs() < 0.01,
        "{:?}",
        list.power
    );
    let s = list
        .resolve(
            Selection::Uniform,
            list.generate(Selection::Uniform, [0.1, 0.5, 0.5, 0.5])
                .unwrap(),
        )
        .unwrap();
    assert!(s.textured);
    let packed = solari_lights::PackedLightSample::pack(&s).unpack().unwrap();
    assert!(packed.textured && !packed.punctual);
    scene.materials[0].emissive_texture = Some(7);
    let list = LightList::build(&scene);
    assert_eq!(list.power[0], list.power[1]);
    assert!(matches!(
        list.lights[0],
        Light::Emissive {
            emissive_texture: None,
            ..
        }
    ));
}

/// The environment map as a light: irradiance estimated by light sampling alone (its
/// importance distribution, selection against a sun) equals a quadrature of the map, for a
/// map with a small hot spot that BRDF sampling would rarely find.
#[test]
fn environment_sampling_is_unbiased() {
    let (w, h) = (64, 32);
    let texels = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            if (20..22).contains(&x) && (5..7).contains(&y) {
                Vec3::new(2000.0, 1500.0, 1000.0)
            } else {
                Vec3::new(0.3 + 0.02 * (x % 7) as f32, 0.5, 0.9)
            }
        })
        .collect();
    let map = solari_scene::EnvironmentMap::new(w, h, texels).unwrap();
    let mut scene = solari_scene::Scene {
        environment_radiance: Vec3::splat(0.7),
        environment_map: Some(std::sync::Arc::new(map)),
        ..Default::default()
    };
    scene
        .directional_lights
        .push(solari_scene::DirectionalLight {
            name: "sun".into(),
            direction: Vec3::new(0.2, -1.0, 0.1).normalize(),
            irradiance: Vec3::splat(3.0),
            angular_diameter: 0.0,
        });
    let list = LightList::build(&scene);
    assert_eq!(list.len(), 2);
    assert!(list.environment.is_some());
    for n in [Vec3::Y, Vec3::new(1.0, 0.5, -0.3).normalize()] {
        // Quadrature over the sphere of radiance × max(cos, 0), plus the sun.
        let (nt, np) = (1024, 2048);
        let mut expected = 0.0f64;
        for i in 0..nt {
            let theta = (i as f64 + 0.5) / nt as f64 * std::f64::consts::PI;
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * std::f64::consts::TAU;
                let d = Vec3::new(
                    (theta.sin() * phi.cos()) as f32,
                    theta.cos() as f32,
                    (theta.sin() * phi.sin()) as f32,
                );
                let cos = d.dot(n).max(0.0) as f64;
                let dw = theta.sin()
                    * (std::f64::consts::PI / nt as f64)
                    * (std::f64::consts::TAU / np as f64);
                expected += scene.environment(d).x as f64 * cos * dw;
            }
        }
        let sun = scene.directional_lights[0].clone();
        expected += 3.0 * (-sun.direction).dot(n).max(0.0) as f64;
        for selection in [Selection::Uniform, Selection::Power] {
            let (mean, se) = common::estimate(&list, selection, Vec3::ZERO, n, 400_000, 11);
            eprintln!("n {n} {selection:?}: {mean:.3} ± {se:.3}, quadrature {expected:.3}");
            assert!(
                (mean - expected).abs() < 4.0 * se + 2e-3 * expected,
                "n {n} {selection:?}: {mean} ± {se} against {expected}"
            );
        }
    }
}

/// The identities a BRDF-sampled ReSTIR DI candidate stores resolve back to the point or
/// direction the ray found, within the 16-bit cells' precision: every emissive triangle of
/// the many-lights scene at random points, and random directions on an environment map.
#[test]
fn sample_ids_of_found_points_and_directions_resolve_back() {
    let mut rng = Pcg32::seed_from_u64(21);
    for (name, scene) in common::scenes() {
        let list = LightList::build(&scene);
        for (i, light) in list.lights.iter().enumerate() {
            let Light::Emissive {
                first_triangle,
                triangle_count,
                ..
            } = *light
            else {
                continue;
            };
            for t in &list.triangles[first_triangle as usize..][..triangle_count as usize] {
                let (u, v): (f32, f32) = (rng.random(), rng.random());
                let (u, v) = if u + v > 1.0 {
                    (1.0 - u, 1.0 - v)
                } else {
                    (u, v)
                };
                let y = t.v0 + t.e1 * u + t.e2 * v;
                let id = list
                    .emissive_sample_id(i as u32, t.primitive, y)
                    .expect("a triangle of the light");
                let back = list.resolve(Selection::Power, id).expect("resolves");
                let size = t.e1.length().max(t.e2.length());
                assert!(
                    (back.position - y).length() <= 1e-3 * size,
                    "{name} light {i}: {y} came back as {}",
                    back.position
                );
            }
            assert!(
                list.emissive_sample_id(i as u32, u32::MAX, Vec3::ZERO)
                    .is_none()
            );
        }
    }
    let texels = (0..32 * 16)
        .map(|i| Vec3::splat(1.0 + (i % 7) as f32))
        .collect();
    let scene = Scene {
        environment_radiance: Vec3::ONE,
        environment_map: Some(std::sync::Arc::new(
            solari_scene::EnvironmentMap::new(32, 16, texels).unwrap(),
        )),
        ..Default::default()
    };
    let list = LightList::build(&scene);
    for _ in 0..1000 {
        let d = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
        .normalize();
        let id = list.environment_sample_id(d).expect("an environment light");
        let back = list.resolve(Selection::Power, id).expect("resolves");
        assert!(
            (back.position - d).length() < 1e-3,
            "{d} came back as {}",
            back.position
        );
    }
}

/// The directional lights lie between the emitters and the environment (or the point lights):
/// `first_directional` finds them, which the GPU's sun-disc test (`sun_disc_light`) relies on.
#[test]
fn directional_lights_are_found_between_emitters_and_the_environment() {
    let sun = |name: &str| DirectionalLight {
        name: name.into(),
        direction: -Vec3::Y,
        irradiance: Vec3::ONE,
        angular_diameter: 0.01,
    };
    let mut scene = scene_of(&[(Mat4::IDENTITY, Vec3::ONE), (Mat4::IDENTITY, Vec3::ONE)]);
    let list = LightList::build(&scene);
    assert_eq!(
        list.first_directional(),
        2,
        "no sun: the range is empty at its end"
    );
    scene.directional_lights.push(sun("a"));
    scene.directional_lights.push(sun("b"));
    let list = LightList::build(&scene);
    assert_eq!(list.first_directional(), 2);
    assert_eq!(list.first_punctual, 4);
    let map = solari_scene::EnvironmentMap::new(2, 1, vec![Vec3::ONE; 2]).unwrap();
    scene.environment_radiance = Vec3::ONE;
    scene.environment_map = Some(std::sync::Arc::new(map));
    let list = LightList::build(&scene);
    assert_eq!(list.first_directional(), 2);
    assert_eq!(list.environment.as_ref().map(|e| e.light), Some(4));
    for l in &list.lights[2..4] {
        assert!(matches!(l, Light::Directional { .. }));
    }
    // Suns and a point light, no environment: the suns end where the point lights begin.
    let mut with_point = scene_of(&[(Mat4::IDENTITY, Vec3::ONE)]);
    with_point.directional_lights.push(sun("a"));
    with_point
        .punctual_lights
        .push(solari_scene::model::PunctualLight {
            name: "bulb".into(),
            kind: solari_scene::model::PunctualKind::Point,
            position: Vec3::Y,
            direction: -Vec3::Y,
            intensity: Vec3::ONE,
            range: None,
            radius: 0.0,
        });
    let list = LightList::build(&with_point);
    assert_eq!(list.first_directional(), 1);
    assert_eq!(list.first_punctual, 2);
    assert!(list.environment.is_none());
    // Suns alone.
    let mut alone = Scene::default();
    alone.directional_lights.push(sun("only"));
    assert_eq!(LightList::build(&alone).first_directional(), 0);
}
