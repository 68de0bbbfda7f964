//! Light tiles on the GPU (lavapipe in CI): the presampling pass draws the same samples as the
//! Rust twin, packing loses no measurable energy, tile estimates are unbiased, and the pass is
//! skipped or refused cleanly where it cannot run.

mod common;

use bytemuck::{Pod, Zeroable};
use common::{CaseKernel, scenes};
use glam::Vec3;
use rand::{Rng as _, SeedableRng};
use rand_pcg::Pcg32;
use solari_lights::tiles::{ENTRY_POINTS, LIGHT_TILE_SALT, PACKED_NORMAL_BITS};
use solari_lights::{
    GpuLights, LightList, LightSampleId, LightTileSettings, LightTiles, MODULES, PackedLightSample,
    Selection,
};
use solari_scene::GpuError;
use solari_scene::gpu::{Gpu, test_gpu};
use solari_scene::pass::FrameContext;
use solari_scene::rng::Rng;
use solari_scene::shaders::{Backend, compose};

const FRAME: u32 = 7;

/// Frame `index` of the Cornell box's camera (tiles read only the index).
fn frame(index: u32) -> FrameContext<'static> {
    let camera = solari_scene::default_scene::cornell_box()
        .camera(None)
        .expect("camera");
    FrameContext::new(index, (64, 64), &camera, None)
}

/// Runs the presampling pass once and reads back the records and their identities.
fn presample(
    gpu: &Gpu,
    tiles: &LightTiles,
    lights: &GpuLights,
) -> (Vec<PackedLightSample>, Vec<LightSampleId>) {
    let context = frame(FRAME);
    tiles.prepare(gpu, &context);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let ran = tiles.encode(&mut encoder, &context, lights);
    assert_eq!(ran.labels(), solari_lights::PASS_LABELS, "the pass ran");
    gpu.queue.submit([encoder.finish()]);
    let n = tiles.settings().sample_count();
    let samples = gpu
        .read_buffer(tiles.samples_buffer(), n * 32)
        .expect("read samples");
    let ids = gpu
        .read_buffer(tiles.ids_buffer(), n * 12)
        .expect("read ids");
    (
        bytemuck::cast_slice(&samples).to_vec(),
        bytemuck::cast_slice(&ids).to_vec(),
    )
}

/// The four numbers the pass drew for sample `i`.
fn numbers(i: u32) -> [f32; 4] {
    let mut rng = Rng::seed([i, 0], FRAME, LIGHT_TILE_SALT);
    [
        rng.next_f32(),
        rng.next_f32(),
        rng.next_f32(),
        rng.next_f32(),
    ]
}

fn close(a: f32, b: f32, tol: f32) -> bool {
    a == b || (a - b).abs() <= tol * a.abs().max(b.abs()).max(1e-6)
}

/// Received irradiance (luminance) of a sample at point x with normal n, and its weight.
fn irradiance_term(
    list: &LightList,
    light: u32,
    s: &solari_lights::ResolvedLightSample,
    x: Vec3,
    n: Vec3,
) -> f64 {
    let Some(seen) = s.toward(list, light, x) else {
        return 0.0;
    };
    let lum = seen.radiance.dot(Vec3::new(0.2126, 0.7152, 0.0722));
    (lum * n.dot(seen.direction).max(0.0) / seen.pdf) as f64
}

#[test]
fn presampled_tiles_match_the_cpu_twin_and_packing_keeps_energy() {
    let Some(gpu) = test_gpu() else { return };
    let settings = LightTileSettings {
        tiles: 16,
        samples_per_tile: 256,
        ..Default::default()
    };
    let tiles = LightTiles::new(&gpu, settings).expect("tiles");
    let mut rng = Pcg32::seed_from_u64(3);
    for (name, scene) in scenes() {
        let list = LightList::build(&scene);
        let (lo, hi) = scene.bounds();
        let extent = (hi - lo).max_element();
        for selection in [Selection::Uniform, Selection::Power] {
            let lights = GpuLights::new(&gpu, &list, selection).expect("lights");
            let (records, ids) = presample(&gpu, &tiles, &lights);
            let mut bad = Vec::new();
            // Packing error, as contribution to the irradiance at random points: exact
            // (CPU-resolved) against the GPU's packed records.
            let (mut exact, mut packed, mut abs_diff) = (0.0f64, 0.0f64, 0.0f64);
            for (i, (record, id)) in records.iter().zip(&ids).enumerate() {
                let cpu_id = list.generate(selection, numbers(i as u32)).unwrap();
                let cpu = list.resolve(selection, cpu_id).expect("valid sample");
                let want = PackedLightSample::pack(&cpu);
                let mask = (1u32 << PACKED_NORMAL_BITS) - 1;
                let axis = |p: u32, shift: u32| ((p >> shift) & mask) as i64;
                let ok = *id == cpu_id
                    && (0..3).all(|k| {
                        (record.position[k] - want.position[k]).abs() <= 1e-6 * extent
                            && close(record.radiance[k], want.radiance[k], 1e-6)
                    })
                    && close(record.inverse_pdf, want.inverse_pdf, 1e-5)
                    && record.normal_flags >> 28 == want.normal_flags >> 28
                    && (axis(record.normal_flags, 0) - axis(want.normal_flags, 0)).abs() <= 1
                    && (axis(record.normal_flags, PACKED_NORMAL_BITS)
                        - axis(want.normal_flags, PACKED_NORMAL_BITS))
                    .abs()
                        <= 1;
                if !ok {
                    bad.push(format!(
                        "{i}: gpu {id:?} {record:?}\n    cpu {cpu_id:?} {want:?}"
                    ));
                }
                let unpacked = record.unpack().expect("non-empty record");
                for _ in 0..4 {
                    let x = lo + (hi - lo) * Vec3::new(rng.random(), rng.random(), rng.random());
                    let n = Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - 1.0;
                    let n = n.normalize_or(Vec3::Y);
                    let e = irradiance_term(&list, id.light, &cpu, x, n);
                    let p = irradiance_term(&list, id.light, &unpacked, x, n);
                    exact += e;
                    packed += p;
                    abs_diff += (e - p).abs();
                }
            }
            let bias = (packed - exact) / exact;
            let mean_abs = abs_diff / exact;
            eprintln!(
                "{name} {selection:?}: {} samples, {} mismatches; packing error: mean {bias:+.2e}, \
                 mean absolute {mean_abs:.2e} (of mean contribution)",
                records.len(),
                bad.len()
            );
            assert!(
                bad.is_empty(),
                "{name} {selection:?}: {} of {} differ, first:\n{}",
                bad.len(),
                records.len(),
                bad[..bad.len().min(4)].join("\n")
            );
            assert!(
                bias.abs() < 1e-3 && mean_abs < 1e-3,
                "{name}: packing loses energy"
            );
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct TileCase {
    x: [f32; 3],
    index: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct TileResult {
    direction: [f32; 3],
    distance: f32,
    radiance: [f32; 3],
    pdf: f32,
    light: u32,
    flags: u32,
    _pad: [u32; 2],
}

#[test]
fn tile_readers_see_the_samples_the_cpu_sees_and_estimates_are_unbiased() {
    let Some(gpu) = test_gpu() else { return };
    let tiles = LightTiles::new(&gpu, LightTileSettings::default()).expect("tiles");
    let kernel = CaseKernel::new(
        &gpu,
        "light_tile_test",
        include_str!("../shaders/light_tile_test.wesl"),
        &LightTiles::reader_layout(&gpu),
    );
    let mut rng = Pcg32::seed_from_u64(11);
    for (name, scene) in scenes() {
        let list = LightList::build(&scene);
        let (lo, hi) = scene.bounds();
        let lights = GpuLights::new(&gpu, &list, Selection::Power).expect("lights");
        let (records, ids) = presample(&gpu, &tiles, &lights);
        let group = tiles.reader_group(&gpu, &lights);
        let cases: Vec<TileCase> = (0..4000)
            .map(|_| TileCase {
                x: (lo + (hi - lo) * Vec3::new(rng.random(), rng.random(), rng.random())).into(),
                index: rng.random_range(0..records.len() as u32),
            })
            .collect();
        let results: Vec<TileResult> = kernel.run(&gpu, &group, &cases);
        let mut bad = 0;
        for (c, r) in cases.iter().zip(&results) {
            let i = c.index as usize;
            let cpu = records[i]
                .unpack()
                .unwrap()
                .toward(&list, ids[i].light, c.x.into());
            let ok = match cpu {
                None => r.flags & 1 == 0,
                Some(s) => {
                    r.flags & 1 == 1
                        && r.light == s.light
                        && (r.flags >> 1 == 1) == s.delta
                        && (Vec3::from(r.direction) - s.direction).abs().max_element() < 1e-4
                        && close(r.pdf, s.pdf, 1e-3)
                        && (0..3).all(|k| close(r.radiance[k], s.radiance[k], 1e-6))
                }
            };
            bad += usize::from(!ok);
        }
        // Points within float noise of an emitter's plane may flip sides.
        assert!(bad <= 4, "{name}: {bad} of {} reads differ", cases.len());

        // Unbiasedness: irradiance at a few points from all 131,072 tile samples against as
        // many independent draws of the CPU sampler.
        for _ in 0..4 {
            let x = lo + (hi - lo) * Vec3::new(rng.random(), rng.random(), rng.random());
            let n = (Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - 1.0)
                .normalize_or(Vec3::Y);
            let stats = |values: Vec<f64>| {
                let m = values.iter().sum::<f64>() / values.len() as f64;
                let var =
                    values.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (values.len() - 1) as f64;
                (m, var / values.len() as f64)
            };
            let tile_values = records
                .iter()
                .zip(&ids)
                .map(|(r, id)| irradiance_term(&list, id.light, &r.unpack().unwrap(), x, n))
                .collect();
            let cpu_values = (0..records.len())
                .map(|_| {
                    let u = [rng.random(), rng.random(), rng.random(), rng.random()];
                    list.sample(Selection::Power, x, u).map_or(0.0, |s| {
                        let lum = s.radiance.dot(Vec3::new(0.2126, 0.7152, 0.0722));
                        (lum * n.dot(s.direction).max(0.0) / s.pdf) as f64
                    })
                })
                .collect();
            let (mt, vt) = stats(tile_values);
            let (mc, vc) = stats(cpu_values);
            let sigma = (vt + vc).sqrt();
            eprintln!("{name} at {x}: tiles {mt:.5} cpu {mc:.5} (σ {sigma:.2e})");
            assert!(
                (mt - mc).abs() <= 4.5 * sigma + 1e-6 * mc.abs(),
                "{name}: tile irradiance {mt} vs independent {mc} (σ {sigma})"
            );
        }
    }
}

#[test]
fn no_lights_skip_the_pass_and_bad_settings_are_refused() {
    let Some(gpu) = test_gpu() else { return };
    let mut scene = solari_scene::default_scene::cornell_box();
    for m in &mut scene.materials {
        m.emissive = Vec3::ZERO;
    }
    let list = LightList::build(&scene);
    assert!(list.is_empty());
    let lights = GpuLights::new(&gpu, &list, Selection::Power).expect("lights");
    let tiles = LightTiles::new(&gpu, LightTileSettings::default()).expect("tiles");
    let context = frame(0);
    tiles.prepare(&gpu, &context);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let ran = tiles.encode(&mut encoder, &context, &lights);
    assert!(ran.is_empty(), "no lights: skipped");
    gpu.queue.submit([encoder.finish()]);

    for settings in [
        LightTileSettings {
            tiles: 0,
            samples_per_tile: 1024,
            ..Default::default()
        },
        LightTileSettings {
            tiles: 128,
            samples_per_tile: 0,
            ..Default::default()
        },
    ] {
        assert!(matches!(
            LightTiles::new(&gpu, settings),
            Err(GpuError::Validation(_))
        ));
    }
    let huge = LightTileSettings {
        tiles: u32::MAX,
        samples_per_tile: u32::MAX,
        ..Default::default()
    };
    match LightTiles::new(&gpu, huge) {
        Err(GpuError::OverLimit { .. }) => {}
        other => panic!("expected OverLimit, got {:?}", other.err()),
    }
}

/// CPU-only: the presampling shader composes and validates, and every shader of this crate
/// states its loop bounds.
#[test]
fn presample_shader_validates() {
    let wgsl = compose(
        "presample_light_tiles",
        Backend::Software,
        &[MODULES, ENTRY_POINTS].concat(),
    )
    .expect("compose");
    solari_scene::shaders::validate("presample_light_tiles", &wgsl).expect("valid");
    let tests = [
        include_str!("../shaders/light_tile_test.wesl"),
        include_str!("../shaders/light_sample_test.wesl"),
    ];
    for (i, source) in MODULES
        .iter()
        .chain(ENTRY_POINTS)
        .map(|m| m.1)
        .chain(tests)
        .enumerate()
    {
        let missing = solari_scene::shaders::loops_without_bound(source);
        assert!(
            missing.is_empty(),
            "shader {i}: loops without a bound at lines {missing:?}"
        );
    }
}
