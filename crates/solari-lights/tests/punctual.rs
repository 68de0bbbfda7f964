//! Point and spot lights (delta and sphere) against analytic answers, and their bad inputs.

mod common;

use glam::Vec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_lights::{Light, LightKey, LightList, PackedLightSample, Selection, SpotCone};
use solari_scene::Scene;
use solari_scene::model::{PunctualKind, PunctualLight};

fn light(kind: PunctualKind, position: Vec3, radius: f32) -> PunctualLight {
    PunctualLight {
        name: "l".into(),
        kind,
        position,
        direction: Vec3::NEG_Y,
        intensity: Vec3::new(3.0, 2.0, 1.0),
        range: None,
        radius,
    }
}

fn list_of(lights: Vec<PunctualLight>) -> LightList {
    LightList::build(&Scene {
        punctual_lights: lights,
        ..Default::default()
    })
}

/// Light-sampling irradiance estimate, power selection (seed 5).
fn estimate(list: &LightList, x: Vec3, n: Vec3, samples: usize) -> (f64, f64) {
    common::estimate(list, Selection::Power, x, n, samples, 5)
}

/// A point light delivers E = I cos θ / d². So does a sphere of any radius wholly above the
/// receiving plane (a uniformly bright sphere's irradiance is the point source's).
#[test]
fn point_and_sphere_lights_follow_the_inverse_square_law() {
    let centre = Vec3::new(0.4, 1.5, -0.3);
    for radius in [0.0, 0.05, 0.6] {
        let list = list_of(vec![light(PunctualKind::Point, centre, radius)]);
        assert_eq!(list.len(), 1);
        assert_eq!(list.lights[0].sphere().is_some(), radius > 0.0);
        for (x, n) in [
            (Vec3::ZERO, Vec3::Y),
            (
                Vec3::new(-1.0, 0.2, 0.5),
                Vec3::new(0.3, 1.0, 0.1).normalize(),
            ),
        ] {
            let to = centre - x;
            let want = 3.0 * n.dot(to.normalize()) as f64 / to.length_squared() as f64;
            let (e, se) = estimate(&list, x, n, 200_000);
            if radius == 0.0 {
                // One sample is exact.
                assert!((e - want).abs() <= 1e-5 * want, "delta: {e} vs {want}");
            } else {
                assert!(
                    (e - want).abs() <= 4.0 * se + 1e-3 * want && se < 0.01 * want,
                    "r {radius}: {e} ± {se} vs {want}"
                );
            }
        }
    }
}

/// A spot follows glTF's falloff: full inside the inner cone, ((cos θ − cos o) / (cos i −
/// cos o))² between, nothing outside the outer cone; for a sphere spot the falloff applies to
/// the direction light leaves each point in, so a small sphere matches the delta spot.
#[test]
fn spot_cone_edge_follows_the_gltf_falloff() {
    let (inner, outer) = (0.25f32, 0.6f32);
    let spot = PunctualKind::Spot { inner, outer };
    let top = Vec3::new(0.0, 2.0, 0.0);
    for radius in [0.0f32, 0.002] {
        let list = list_of(vec![light(spot, top, radius)]);
        for angle in [0.0f32, 0.2, 0.3, 0.4, 0.5, 0.59, 0.65, 1.0] {
            // A point on the floor seen from the light at `angle` off the axis.
            let x = Vec3::new(2.0 * angle.tan(), 0.0, 0.0);
            let t = ((angle.cos() - outer.cos()) / (inner.cos() - outer.cos())).clamp(0.0, 1.0);
            let d2 = (top - x).length_squared();
            let want = (3.0 * t * t * angle.cos() / d2) as f64;
            let (e, se) = estimate(&list, x, Vec3::Y, if radius > 0.0 { 100_000 } else { 16 });
            // The sphere's points see the floor point at slightly different angles.
            let tol = if radius > 0.0 {
                4.0 * se + 0.01 * want + 1e-4
            } else {
                1e-4 * want
            };
            assert!(
                (e - want).abs() <= tol,
                "r {radius} angle {angle}: {e} vs {want}"
            );
        }
    }
    let cone = SpotCone::new(Vec3::NEG_Y, inner, outer);
    assert_eq!(cone.attenuation(Vec3::NEG_Y), 1.0);
    assert_eq!(cone.attenuation(Vec3::X), 0.0);
    assert_eq!(SpotCone::NONE.attenuation(Vec3::X), 1.0);
    // Inner above outer (invalid glTF): a hard edge at the outer angle.
    let hard = SpotCone::new(Vec3::NEG_Y, 0.9, 0.3);
    let at = |a: f32| hard.attenuation(Vec3::new(a.sin(), -a.cos(), 0.0));
    assert_eq!((at(0.0), at(0.29), at(0.31)), (1.0, 1.0, 0.0));
}

/// MIS needs the pdf of a BRDF ray's hit on a sphere light to be the pdf light sampling gives
/// the same point.
#[test]
fn sphere_light_pdf_matches_the_sampling_pdf() {
    let centre = Vec3::new(0.3, 1.0, 0.2);
    let list = list_of(vec![
        light(PunctualKind::Point, centre, 0.4),
        light(PunctualKind::Point, Vec3::new(-1.0, 1.0, 0.0), 0.0),
    ]);
    let x = Vec3::new(0.0, -0.5, 0.0);
    let mut rng = Pcg32::seed_from_u64(9);
    let mut checked = 0;
    for _ in 0..2000 {
        let u = [rng.random(), rng.random(), rng.random(), rng.random()];
        let Some(s) = list.sample(Selection::Power, x, u) else {
            continue;
        };
        let y = x + s.direction * s.distance;
        let n = (y - centre).normalize();
        let p = list.emissive_pdf(Selection::Power, s.light as usize, x, y, n);
        if s.delta {
            assert_eq!(p, 0.0, "a delta light has no pdf to hit");
        } else {
            assert!((p - s.pdf).abs() <= 1e-3 * s.pdf, "{p} vs {}", s.pdf);
            // The point lies on the sphere, facing x.
            assert!(((y - centre).length() - 0.4).abs() < 1e-4);
            assert!(n.dot(s.direction) < 0.0);
            checked += 1;
        }
    }
    assert!(checked > 300, "{checked} sphere samples");
}

/// Packed tile records keep the point-light flags: delta or sphere, and the sphere's normal.
#[test]
fn packing_keeps_point_lights() {
    let list = list_of(vec![
        light(PunctualKind::Point, Vec3::ONE, 0.0),
        light(
            PunctualKind::Spot {
                inner: 0.1,
                outer: 0.4,
            },
            Vec3::ZERO,
            0.5,
        ),
    ]);
    let mut rng = Pcg32::seed_from_u64(4);
    for _ in 0..200 {
        let u = [rng.random(), rng.random(), rng.random(), rng.random()];
        let id = list.generate(Selection::Uniform, u).unwrap();
        let r = list.resolve(Selection::Uniform, id).unwrap();
        let back = PackedLightSample::pack(&r).unpack().unwrap();
        assert!(back.punctual && r.punctual);
        assert_eq!(back.delta, r.delta);
        assert!(!back.directional && !back.double_sided);
        assert!(
            (back.normal - r.normal).length() < 1e-3,
            "{r:?} vs {back:?}"
        );
        let x = Vec3::new(0.2, -2.0, 0.1);
        let (a, b) = (
            r.toward(&list, id.light, x),
            back.toward(&list, id.light, x),
        );
        assert_eq!(a.is_some(), b.is_some());
        if let (Some(a), Some(b)) = (a, b) {
            assert!((a.radiance - b.radiance).abs().max_element() <= 1e-3 * a.radiance.x);
        }
    }
}

/// Bad input: black or non-finite lights are left out and reported; radii that cannot make a
/// finite sphere become delta lights, reported; cone angles outside glTF's range are clamped;
/// nothing sampled is ever non-finite.
#[test]
fn bad_point_lights_are_reported_not_rendered_as_garbage() {
    let mut lights = vec![
        light(PunctualKind::Point, Vec3::ZERO, 0.0),
        light(PunctualKind::Point, Vec3::ZERO, -1.0),
        light(PunctualKind::Point, Vec3::ZERO, f32::NAN),
        light(PunctualKind::Point, Vec3::ZERO, 1e-30),
        light(PunctualKind::Point, Vec3::splat(f32::INFINITY), 0.1),
        light(
            PunctualKind::Spot {
                inner: 2.0,
                outer: -1.0,
            },
            Vec3::ONE,
            0.0,
        ),
        light(
            PunctualKind::Spot {
                inner: 0.5,
                outer: 9.0,
            },
            Vec3::ONE,
            0.1,
        ),
    ];
    lights[0].intensity = Vec3::ZERO;
    let mut nan_dir = light(
        PunctualKind::Spot {
            inner: 0.1,
            outer: 0.2,
        },
        Vec3::ONE,
        0.0,
    );
    nan_dir.direction = Vec3::NAN;
    lights.push(nan_dir);
    let mut huge = light(PunctualKind::Point, Vec3::new(0.0, 3.0, 0.0), 0.0);
    huge.intensity = Vec3::splat(3e38);
    lights.push(huge);
    let list = list_of(lights);
    // Index 0 is black: switched off, not a problem. Index 5's outer angle clamps to 0: a
    // cone that lights nothing.
    assert_eq!(list.report.off_punctual, vec![0]);
    assert_eq!(list.report.dark_punctual, vec![4, 5]);
    assert!(
        !list.report.lines().join(" ").contains("[0"),
        "{:?}",
        list.report.lines()
    );
    assert_eq!(list.report.radius_to_delta, vec![1, 2, 3]);
    assert_eq!(list.len(), 6);
    assert!(
        list.keys
            .iter()
            .all(|k| matches!(k, LightKey::Punctual { .. }))
    );
    // The spot with outer > π/2 is clamped to a hemisphere; a NaN axis falls back to −z.
    for l in &list.lights {
        let Light::Point { cone, .. } = l else {
            panic!("{l:?}")
        };
        assert!(cone.axis.is_finite() && cone.scale.is_finite() && cone.offset.is_finite());
    }
    let mut rng = Pcg32::seed_from_u64(6);
    for _ in 0..5000 {
        let u = [rng.random(), rng.random(), rng.random(), rng.random()];
        let x = Vec3::new(rng.random(), rng.random(), rng.random()) * 4.0 - 2.0;
        if let Some(s) = list.sample(Selection::Power, x, u) {
            assert!(
                s.radiance.is_finite() && s.pdf.is_finite() && s.pdf > 0.0,
                "{s:?}"
            );
        }
    }
    // At the light's own position nothing is sampled rather than infinity.
    assert!((0..100).all(|i| {
        let u = [i as f32 / 100.0, 0.5, 0.5, 0.5];
        list.sample(Selection::Uniform, Vec3::ONE, u)
            .is_none_or(|s| s.radiance.is_finite())
    }));
}
