//! GPU twin test: `light_sampling.wesl` samples the same lights, directions and pdfs as
//! `LightList::sample` (lavapipe in CI).

mod common;

use bytemuck::{Pod, Zeroable};
use common::{CaseKernel, scenes};
use glam::{Vec3, Vec4};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_lights::{GpuLights, Light, LightList, LightSampleId, MODULES, Selection};
use solari_scene::gpu::test_gpu;
use solari_scene::shaders::{Backend, compose};

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Case {
    x: [f32; 3],
    _pad: f32,
    u: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GpuResult {
    direction: [f32; 3],
    distance: f32,
    radiance: [f32; 3],
    pdf: f32,
    light: u32,
    flags: u32,
    emissive_pdf: f32,
    sun_disc: f32,
    emissive_id: LightSampleId,
    environment_id: LightSampleId,
    _pad1: [u32; 2],
}

/// The ray pdf `light_sample_test.wesl` weighs its sun disks with (`SUN_TEST_RAY_PDF` there).
const SUN_TEST_RAY_PDF: f32 = 1000.0;

#[test]
fn gpu_light_sampling_matches_the_cpu_twin() {
    let Some(gpu) = test_gpu() else { return };
    let kernel = CaseKernel::new(
        &gpu,
        "light_sample_test",
        include_str!("../shaders/light_sample_test.wesl"),
        &GpuLights::layout(&gpu),
    );
    let mut rng = Pcg32::seed_from_u64(8);
    // The Cornell box under an environment map with a hot spot.
    let mut sky = solari_scene::default_scene::cornell_box();
    let texels = (0..32 * 16)
        .map(|i| match i {
            70 | 71 => Vec3::new(400.0, 300.0, 200.0),
            _ => Vec3::new(0.2, 0.4, 1.0) * (1.0 + (i % 32) as f32 / 8.0),
        })
        .collect();
    let map = solari_scene::EnvironmentMap::new(32, 16, texels).expect("map");
    sky.environment_map = Some(std::sync::Arc::new(map));
    sky.environment_radiance = Vec3::splat(0.5);
    // The emitter mirrored (negative determinant): its emitting face is -(e1 x e2).
    let mut mirrored = solari_scene::default_scene::cornell_box();
    for inst in &mut mirrored.instances {
        if mirrored.materials[inst.material as usize].is_emissive() {
            inst.transform = glam::Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)) * inst.transform;
        }
    }
    let scenes = scenes().into_iter().chain([
        ("cornell_box+sky".to_string(), sky),
        ("cornell_box, mirrored light".to_string(), mirrored),
    ]);
    for (name, scene) in scenes {
        let list = LightList::build(&scene);
        let (lo, hi) = scene.bounds();
        for selection in [Selection::Uniform, Selection::Power] {
            let gpu_lights = GpuLights::new(&gpu, &list, selection).expect("lights");
            let cases: Vec<Case> = (0..4000)
                .map(|_| Case {
                    x: lo
                        .lerp(hi, rng.random_range(0.0..1.0))
                        .with_y(rng.random_range(lo.y..hi.y))
                        .into(),
                    _pad: 0.0,
                    u: Vec4::new(rng.random(), rng.random(), rng.random(), rng.random()).into(),
                })
                .collect();
            let results: Vec<GpuResult> = kernel.run(&gpu, &gpu_lights.bind_group, &cases);
            let mut failures = Vec::new();
            let rel = |a: f32, b: f32, tol: f32| {
                (a == b) || (a - b).abs() <= tol * a.abs().max(b.abs()).max(1e-6)
            };
            // Ids of emitter points agree to `cells` 16-bit cells (float rounding differs).
            let same_id = |g: LightSampleId, c: Option<LightSampleId>, cells: i64| match c {
                None => g.light == u32::MAX,
                Some(c) => {
                    let near = |a: u32, b: u32| (a as i64 - b as i64).abs() <= cells;
                    g.light == c.light
                        && g.triangle == c.triangle
                        && near(g.point & 0xffff, c.point & 0xffff)
                        && near(g.point >> 16, c.point >> 16)
                }
            };
            for (c, r) in cases.iter().zip(results) {
                let x = Vec3::from(c.x);
                let d = (Vec3::new(c.u[0], c.u[1], c.u[2]) * 2.0 - 1.0).normalize();
                // Environment ids: compared by the direction they resolve to, since a direction on
                // a cell's border may fall either side with the GPU's acos and atan2.
                let env_ok = match list.environment_sample_id(d) {
                    None => r.environment_id.light == u32::MAX,
                    Some(c) => {
                        let at = |id| list.resolve(selection, id).map(|s| s.position);
                        match (at(c), at(r.environment_id)) {
                            (Some(a), Some(b)) => (a - b).length() < 1e-3,
                            _ => false,
                        }
                    }
                };
                let cpu = list.sample(selection, x, c.u);
                let gpu_valid = r.flags & 1 == 1;
                let ok = match cpu {
                    None => !gpu_valid,
                    Some(s) => {
                        let mut ok = gpu_valid
                            && r.light == s.light
                            && (r.flags >> 1 == 1) == s.delta
                            && (Vec3::from(r.direction) - s.direction).abs().max_element() < 1e-4
                            && rel(r.distance, s.distance, 1e-4)
                            && rel(r.pdf, s.pdf, 1e-3);
                        // The GPU leaves the environment's radiance to the light readers.
                        let environment = list.environment.as_ref().map(|e| e.light);
                        let radiance = if environment == Some(s.light) {
                            let p = list.environment_pdf(selection, s.direction);
                            ok &= rel(r.emissive_pdf, p, 1e-3);
                            Vec3::ONE
                        } else {
                            s.radiance
                        };
                        ok &= (0..3).all(|i| rel(r.radiance[i], radiance[i], 1e-5));
                        let y = x + s.direction * s.distance;
                        let normal = match list.lights[s.light as usize] {
                            Light::Emissive {
                                first_triangle,
                                mirrored,
                                ..
                            } => {
                                let t = list.triangles[first_triangle as usize];
                                let side = if mirrored { -1.0 } else { 1.0 };
                                Some(t.e1.cross(t.e2).normalize() * side)
                            }
                            Light::Point { position, .. } if !s.delta => {
                                Some((y - position).normalize())
                            }
                            _ => None,
                        };
                        if let Some(n) = normal {
                            let p = list.emissive_pdf(selection, s.light as usize, x, y, n);
                            ok &= rel(r.emissive_pdf, p, 1e-3);
                        }
                        // The sun disks a BRDF ray along the sample's direction would find.
                        let sun =
                            list.sun_disc_light(selection, s.direction, Some(SUN_TEST_RAY_PDF));
                        ok &= rel(r.sun_disc, sun.x, 1e-3);
                        ok
                    }
                };
                let emissive_cpu = cpu.and_then(|s| match list.lights[s.light as usize] {
                    Light::Emissive { first_triangle, .. } => {
                        let primitive = list.triangles[first_triangle as usize].primitive;
                        list.emissive_sample_id(s.light, primitive, x + s.direction * s.distance)
                    }
                    _ => None,
                });
                let ok = ok && env_ok && same_id(r.emissive_id, emissive_cpu, 1);
                if !ok {
                    failures.push(format!(
                        "x {x} u {:?}: cpu {cpu:?} gpu {r:?}; cpu ids {:?} {emissive_cpu:?}",
                        c.u,
                        list.environment_sample_id(d)
                    ));
                }
            }
            eprintln!(
                "{name} {selection:?}: {} lights, {} cases, {} mismatches",
                list.len(),
                cases.len(),
                failures.len()
            );
            // Samples at points within float noise of an emitter's plane can flip between
            // front and back; allow a handful per 4,000.
            assert!(
                failures.len() <= 4,
                "{name} {selection:?}: {} mismatches, first {:#?}",
                failures.len(),
                &failures[..failures.len().min(3)]
            );
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct HitCase {
    o: [f32; 3],
    light: u32,
    d: [f32; 3],
    t_max: f32,
}

/// `sphere_light_hit` (the reference tracer's BRDF rays against sphere lights) matches its
/// Rust twin `Light::sphere_hit` on rays aimed near and past the spheres, from outside and
/// inside, for every light of the test scenes (emissive, suns and delta points never hit).
#[test]
fn gpu_sphere_hits_match_the_cpu_twin() {
    let Some(gpu) = test_gpu() else { return };
    let kernel = CaseKernel::new(
        &gpu,
        "sphere_hit_test",
        include_str!("../shaders/sphere_hit_test.wesl"),
        &GpuLights::layout(&gpu),
    );
    let mut rng = Pcg32::seed_from_u64(12);
    for (name, scene) in scenes() {
        let list = LightList::build(&scene);
        let gpu_lights = GpuLights::new(&gpu, &list, Selection::Power).expect("lights");
        let (lo, hi) = scene.bounds();
        let cases: Vec<HitCase> = (0..4000)
            .map(|_| {
                let light = rng.random_range(0..list.len() as u32);
                let mut r = || rng.random_range(-0.2f32..1.2);
                let mut o = lo + (hi - lo) * Vec3::new(r(), r(), r());
                // One in ten rays starts inside its sphere: the far side faces away.
                if let Light::Point { position, .. } = list.lights[light as usize]
                    && rng.random_bool(0.1)
                {
                    o = position;
                }
                // Towards the light's centre, spread so some rays miss or graze.
                let target = match list.lights[light as usize] {
                    Light::Point {
                        position, radius, ..
                    } => {
                        position
                            + Vec3::new(rng.random(), rng.random(), rng.random()) * 2.5 * radius
                            - Vec3::splat(1.25 * radius)
                    }
                    _ => lo.lerp(hi, 0.5),
                };
                let d = (target - o).normalize_or(Vec3::Y);
                let t_max = if rng.random_bool(0.2) {
                    rng.random_range(0.0..(hi - lo).length())
                } else {
                    3.4e38
                };
                HitCase {
                    o: o.into(),
                    light,
                    d: d.into(),
                    t_max,
                }
            })
            .collect();
        let results: Vec<f32> = kernel.run(&gpu, &gpu_lights.bind_group, &cases);
        let (mut hits, mut bad) = (0, Vec::new());
        for (c, t) in cases.iter().zip(results) {
            let cpu = list.lights[c.light as usize].sphere_hit(c.o.into(), c.d.into(), c.t_max);
            let ok = match cpu {
                None => t < 0.0,
                Some(want) => (t - want).abs() <= 1e-4 * want.max(1e-3),
            };
            // The twin itself: the hit lies on the sphere, on the side facing the ray.
            if let (
                Some(t),
                Light::Point {
                    position, radius, ..
                },
            ) = (cpu, &list.lights[c.light as usize])
            {
                let y = Vec3::from(c.o) + Vec3::from(c.d) * t;
                assert!(((y - *position).length() - radius).abs() <= 1e-4 * radius.max(1.0));
                assert!(
                    (y - *position).dot(c.d.into()) < 0.0,
                    "{c:?} hit from behind"
                );
            }
            hits += cpu.is_some() as u32;
            if !ok {
                bad.push(format!("{c:?}: cpu {cpu:?} gpu {t}"));
            }
        }
        eprintln!(
            "{name}: {} cases, {hits} hits, {} mismatches",
            cases.len(),
            bad.len()
        );
        // Rays that graze a sphere within float noise may flip between hit and miss.
        assert!(bad.len() <= 4, "{name}: {:#?}", &bad[..bad.len().min(3)]);
        if list.lights.iter().any(|l| l.sphere().is_some()) {
            assert!(hits > 100, "{name}: only {hits} hits");
        }
    }
}

/// naga's size of every named struct in entry module `entry` (names without WESL's prefix).
fn wgsl_sizes(entry: &str, extra: &[(&str, &str)]) -> std::collections::HashMap<String, u32> {
    let extra: Vec<(&str, &str)> = MODULES.iter().chain(extra).copied().collect();
    let wgsl = compose(entry, Backend::Software, &extra).expect("compose");
    let module = solari_scene::shaders::validate(entry, &wgsl).expect("valid");
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    module
        .types
        .iter()
        .filter_map(|(h, t)| {
            let short = t.name.as_deref()?.rsplit('_').next()?.to_string();
            Some((short, layouter[h].size))
        })
        .collect()
}

/// CPU-only: the Rust mirrors have the sizes naga gives their WGSL twins.
#[test]
fn gpu_structs_match_naga_layouts() {
    let test_module = [(
        "light_sample_test",
        include_str!("../shaders/light_sample_test.wesl"),
    )];
    let sizes = wgsl_sizes("light_sample_test", &test_module);
    let tile_sizes = wgsl_sizes("presample_light_tiles", solari_lights::tiles::ENTRY_POINTS);
    let size_of_wgsl = |short: &str| {
        *sizes
            .get(short)
            .or_else(|| tile_sizes.get(short))
            .unwrap_or_else(|| panic!("no WGSL struct {short}"))
    };
    use solari_lights::gpu::{GpuEmissiveTriangle, GpuLight, GpuLightInfo};
    use solari_lights::tiles::GpuTileParams;
    use solari_lights::{LightSampleId, PackedLightSample};
    assert_eq!(size_of_wgsl("GpuLight") as usize, size_of::<GpuLight>());
    assert_eq!(
        size_of_wgsl("GpuEmissiveTriangle") as usize,
        size_of::<GpuEmissiveTriangle>()
    );
    assert_eq!(
        size_of_wgsl("GpuLightInfo") as usize,
        size_of::<GpuLightInfo>()
    );
    assert_eq!(size_of_wgsl("Case") as usize, size_of::<Case>());
    assert_eq!(size_of_wgsl("Result") as usize, size_of::<GpuResult>());
    assert_eq!(
        size_of_wgsl("PackedLightSample") as usize,
        size_of::<PackedLightSample>()
    );
    assert_eq!(
        size_of_wgsl("LightSampleId") as usize,
        size_of::<LightSampleId>()
    );
    assert_eq!(
        size_of_wgsl("TileParams") as usize,
        size_of::<GpuTileParams>()
    );
}
