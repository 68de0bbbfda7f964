//! The cache's table on the GPU (lavapipe in CI) against its Rust twin: addressing bit for
//! bit, probing and insertion under concurrency, a full table, and compaction against a CPU
//! prefix sum on random occupancy.

use bytemuck::{Pod, Zeroable};
use rand::{Rng as _, SeedableRng};
use rand_pcg::Pcg32;
use solari_lights::LightTileSettings;
use solari_scene::gpu::{Gpu, ShaderChecks, test_gpu};
use solari_scene::gpu_scene::TraceVariant;
use solari_scene::gpu_types::GpuView;
use solari_scene::pass::FrameContext;
use solari_scene::shaders::compose;
use solari_worldcache::hash::{CellGrid, EMPTY_CHECKSUM, Probe, insert, probe_sequence};
use solari_worldcache::{GpuCacheCell, WorldCache, WorldCacheSettings};
use std::collections::{HashMap, HashSet};

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct FindCase {
    position: [f32; 3],
    ray_length: f32,
    normal: [f32; 3],
    // The address's level draw (≥ 1: hard level boundaries).
    lod_u: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
struct FindResult {
    key: u32,
    checksum: u32,
    level: u32,
    slot: u32,
}

const NONE: u32 = u32::MAX;
const VIEW: [f32; 3] = [1.5, -2.0, 3.25];

fn cache(gpu: &Gpu, settings: WorldCacheSettings) -> WorldCache {
    let backend = gpu.backend(Default::default()).unwrap();
    let mut c = WorldCache::new(
        gpu,
        backend,
        TraceVariant::General,
        settings,
        LightTileSettings::default(),
    )
    .expect("world cache");
    c.prepare(gpu, &frame(), 0);
    c
}

/// Frame 0 of a 1×1 image seen from `VIEW` (the cache reads the index, eye and size).
fn frame() -> FrameContext<'static> {
    let view = GpuView {
        origin: VIEW,
        ..Default::default()
    };
    FrameContext {
        index: 0,
        size: (1, 1),
        view,
        previous_view: view,
        profiler: None,
    }
}

// Runs the find kernel over `cases` against `cache`'s table.
fn find(gpu: &Gpu, cache: &WorldCache, cases: &[FindCase]) -> Vec<FindResult> {
    let backend = gpu.backend(Default::default()).unwrap();
    let kernel = include_str!("shaders/world_cache_find_test.wesl");
    let mut modules = solari_worldcache::modules();
    modules.push(("world_cache_find_test", kernel));
    let wgsl = compose("world_cache_find_test", backend, &modules).expect("compose");
    let rw = wgpu::BufferBindingType::Storage { read_only: false };
    let io = gpu.buffer_layout(
        "find_test",
        &[wgpu::BufferBindingType::Storage { read_only: true }, rw],
    );
    let (empty_layout, empty) = gpu.empty_group();
    let pipeline = gpu
        .compute_pipeline(
            "find_test",
            &wgsl,
            &[
                Some(&io),
                Some(&empty_layout),
                Some(cache.bind_group_layout()),
            ],
            ShaderChecks::All,
            &[],
        )
        .expect("pipeline");
    gpu.run_cases(
        "find_test",
        &pipeline,
        &io,
        &[None, Some(&empty), Some(cache.bind_group())],
        cases,
    )
    .expect("run")
}

fn random_unit(rng: &mut Pcg32) -> [f32; 3] {
    loop {
        let v: [f32; 3] = std::array::from_fn(|_| rng.random_range(-1.0f32..1.0));
        let l = v.iter().map(|x| x * x).sum::<f32>().sqrt();
        if l > 0.1 && l <= 1.0 {
            return v.map(|x| x / l);
        }
    }
}

fn random_case(rng: &mut Pcg32, extent: f32) -> FindCase {
    FindCase {
        position: std::array::from_fn(|_| rng.random_range(-extent..extent)),
        ray_length: if rng.random_bool(0.3) {
            f32::INFINITY
        } else {
            rng.random_range(0.01f32..4.0)
        },
        normal: random_unit(rng),
        lod_u: 1.0,
    }
}

fn grid(s: &WorldCacheSettings) -> CellGrid {
    CellGrid::new(s.cell_size, s.lod_distance, s.capacity)
}

#[test]
fn gpu_addressing_matches_the_rust_twin() {
    let Some(gpu) = test_gpu() else { return };
    let mut rng = Pcg32::seed_from_u64(5);
    for (cell_size, lod) in [(0.25f32, 10.0f32), (0.07, 1.5), (1.0, f32::INFINITY)] {
        let s = WorldCacheSettings {
            capacity: 1 << 16,
            cell_size,
            lod_distance: lod,
            max_search_steps: 64,
            ..Default::default()
        };
        let c = cache(&gpu, s);
        let cases: Vec<FindCase> = (0..4096).map(|_| random_case(&mut rng, 200.0)).collect();
        let out = find(&gpu, &c, &cases);
        let g = grid(&s);
        let mut levels = HashSet::new();
        for (case, r) in cases.iter().zip(&out) {
            let cpu = g.cell(case.position, case.normal, VIEW, case.ray_length);
            assert_eq!(
                (r.key, r.checksum, r.level),
                (cpu.key, cpu.checksum, cpu.level),
                "cell {cell_size} lod {lod}: {case:?}"
            );
            levels.insert(r.level);
        }
        eprintln!("cell {cell_size}, lod {lod}: 4096 cases agree, levels {levels:?}");
        if lod.is_finite() {
            assert!(levels.len() >= 3, "the cases should span several levels");
        }
    }
}

#[test]
fn soft_levels_match_the_twin_and_step_up_with_probability_fract_cubed() {
    let Some(gpu) = test_gpu() else { return };
    let mut rng = Pcg32::seed_from_u64(17);
    let s = WorldCacheSettings {
        capacity: 1 << 16,
        lod_distance: 2.0,
        max_search_steps: 64,
        soft_lod: true,
        ..Default::default()
    };
    let c = cache(&gpu, s);
    let cases: Vec<FindCase> = (0..8192)
        .map(|_| FindCase {
            ray_length: f32::INFINITY,
            lod_u: rng.random_range(0.0f32..1.0),
            ..random_case(&mut rng, 60.0)
        })
        .collect();
    let out = find(&gpu, &c, &cases);
    let g = grid(&s);
    // Expected and observed step-ups: the sum of fract³ and the count of levels above the
    // hard one.
    let (mut expected, mut stepped) = (0.0f64, 0u32);
    for (case, r) in cases.iter().zip(&out) {
        let cpu = g.cell_with(
            case.position,
            case.normal,
            VIEW,
            case.ray_length,
            case.lod_u,
        );
        assert_eq!(
            (r.key, r.checksum, r.level),
            (cpu.key, cpu.checksum, cpu.level),
            "{case:?}"
        );
        let d = case
            .position
            .iter()
            .zip(VIEW)
            .map(|(p, v)| (p - v) * (p - v))
            .sum::<f32>()
            .sqrt();
        let hard = g.level(d);
        assert!(
            r.level == hard || r.level == hard + 1,
            "{case:?}: {}",
            r.level
        );
        stepped += u32::from(r.level > hard);
        let l = (1.0 + d as f64 / 2.0).log2();
        expected += (l - l.floor()).powi(3);
    }
    // Binomial spread: within four standard deviations.
    let sd = expected.sqrt().max(1.0);
    eprintln!("soft levels: {stepped} step-ups, {expected:.0} expected");
    assert!(
        (stepped as f64 - expected).abs() < 4.0 * sd,
        "{stepped} step-ups against {expected:.0} expected"
    );
    // The draw is the only difference: u ≥ 1 gives the hard level everywhere.
    let hard: Vec<FindCase> = cases
        .iter()
        .map(|c| FindCase { lod_u: 1.0, ..*c })
        .collect();
    for (case, r) in hard.iter().zip(find(&gpu, &c, &hard)) {
        let cpu = g.cell(case.position, case.normal, VIEW, case.ray_length);
        assert_eq!(r.level, cpu.level);
    }
}

#[test]
fn concurrent_insertion_finds_each_cell_once_within_its_probe_run() {
    let Some(gpu) = test_gpu() else { return };
    let mut rng = Pcg32::seed_from_u64(9);
    let s = WorldCacheSettings {
        capacity: 1024,
        max_search_steps: 64,
        // Hard levels: the probes are checked against the twin's cell for each lookup.
        soft_lod: false,
        ..Default::default()
    };
    let c = cache(&gpu, s);
    // 600 distinct surface points, each queried 1 to 4 times in the same dispatch.
    let points: Vec<FindCase> = (0..600)
        .map(|_| FindCase {
            ray_length: f32::INFINITY,
            ..random_case(&mut rng, 30.0)
        })
        .collect();
    let mut cases = Vec::new();
    for p in &points {
        for _ in 0..rng.random_range(1..=4) {
            cases.push(*p);
        }
    }
    // Shuffle so copies of a cell race each other in different workgroups.
    for i in (1..cases.len()).rev() {
        cases.swap(i, rng.random_range(0..=i));
    }
    let out = find(&gpu, &c, &cases);
    let slots = c.read_cells(&gpu).unwrap();
    let mut slot_of: HashMap<u32, u32> = HashMap::new();
    for (case, r) in cases.iter().zip(&out) {
        assert_ne!(r.slot, NONE, "no overflow below capacity");
        let first = *slot_of.entry(r.checksum).or_insert(r.slot);
        assert_eq!(first, r.slot, "every query of one cell gets one slot");
        let cell = grid(&s).cell(case.position, case.normal, VIEW, f32::INFINITY);
        assert!(
            probe_sequence(cell, s.capacity - 1, s.max_search_steps).any(|k| k == r.slot),
            "slot {} outside the probe run from key {}",
            r.slot,
            cell.key
        );
        let (checksum, life, geometry) = slots[r.slot as usize];
        assert_eq!(checksum, r.checksum);
        assert_eq!(life, s.lifetime, "a pixel query gives the full lifetime");
        assert!(geometry.position.iter().all(|x| x.is_finite()));
    }
    let occupied = slots.iter().filter(|s| s.0 != EMPTY_CHECKSUM).count();
    assert_eq!(occupied, slot_of.len(), "one slot per distinct cell");
    assert_eq!(c.read_stats(&gpu).unwrap().overflows, 0);
    eprintln!(
        "{} queries of {} cells: {occupied} slots, none duplicated",
        cases.len(),
        slot_of.len()
    );
}

#[test]
fn a_full_table_returns_nothing_and_leaves_other_cells_alone() {
    let Some(gpu) = test_gpu() else { return };
    let mut rng = Pcg32::seed_from_u64(13);
    let s = WorldCacheSettings {
        capacity: 1024,
        max_search_steps: 4,
        // Hard levels: the probes are checked against the twin's cell for each lookup.
        soft_lod: false,
        ..Default::default()
    };
    let c = cache(&gpu, s);
    // Fill part of the table and give every cell a recognisable light value.
    let first: Vec<FindCase> = (0..400).map(|_| random_case(&mut rng, 50.0)).collect();
    find(&gpu, &c, &first);
    let mut slots = c.read_cells(&gpu).unwrap();
    for (i, slot) in slots.iter_mut().enumerate() {
        if slot.0 != EMPTY_CHECKSUM {
            slot.2.irradiance = [i as f32, 1.0, 2.0, 3.0];
        }
    }
    c.write_cells(&gpu, &slots).unwrap();
    // The counter runs until the next decay: what the flood adds is the difference.
    let before = c.read_stats(&gpu).unwrap().overflows;
    // Then far more new cells than the table holds.
    let flood: Vec<FindCase> = (0..5000).map(|_| random_case(&mut rng, 500.0)).collect();
    let out = find(&gpu, &c, &flood);
    let after = c.read_cells(&gpu).unwrap();
    let failed = out.iter().filter(|r| r.slot == NONE).count();
    let overflows = c.read_stats(&gpu).unwrap().overflows - before;
    eprintln!(
        "5000 new cells into 1024 slots: {failed} lookups failed, {overflows} overflows counted"
    );
    assert!(failed > 3000, "the table cannot hold them: {failed} failed");
    assert_eq!(overflows as usize, failed, "every failure is counted");
    for (i, (before, now)) in slots.iter().zip(&after).enumerate() {
        if before.0 != EMPTY_CHECKSUM {
            assert_eq!(before, now, "slot {i} holding an earlier cell changed");
        }
    }
    for r in out.iter().filter(|r| r.slot != NONE) {
        assert_eq!(after[r.slot as usize].0, r.checksum);
    }
}

#[test]
fn compaction_equals_a_cpu_prefix_sum_on_random_occupancy() {
    let Some(gpu) = test_gpu() else { return };
    let mut rng = Pcg32::seed_from_u64(21);
    for (capacity, fill) in [
        (1024u32, 0.5f64),
        (1 << 16, 0.03),
        (1 << 16, 0.97),
        (1 << 20, 0.2),
    ] {
        let s = WorldCacheSettings {
            capacity,
            ..Default::default()
        };
        let c = cache(&gpu, s);
        let slots: Vec<(u32, u32, GpuCacheCell)> = (0..capacity)
            .map(|i| {
                if rng.random_bool(fill) {
                    let cell = GpuCacheCell {
                        irradiance: [1.0, 2.0, 3.0, 4.0],
                        ..Default::default()
                    };
                    (i | 1, rng.random_range(1..4), cell)
                } else {
                    (0, 0, GpuCacheCell::default())
                }
            })
            .collect();
        c.write_cells(&gpu, &slots).unwrap();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        c.encode_maintain(&mut encoder, &frame());
        gpu.queue.submit([encoder.finish()]);
        let active = c.read_active(&gpu).unwrap();
        // Decay first: a cell with one frame left dies and is not listed.
        let expected: Vec<u32> = (0..capacity).filter(|&i| slots[i as usize].1 > 1).collect();
        assert_eq!(active.len(), expected.len(), "capacity {capacity}");
        assert_eq!(
            active, expected,
            "capacity {capacity}: dense list in slot order"
        );
        let after = c.read_cells(&gpu).unwrap();
        for (i, (before, now)) in slots.iter().zip(&after).enumerate() {
            match before.1 {
                0 => assert_eq!(now.1, 0),
                1 => {
                    assert_eq!(
                        (now.0, now.1),
                        (EMPTY_CHECKSUM, 0),
                        "slot {i} should be freed"
                    );
                    assert_eq!(now.2.irradiance, [0.0; 4]);
                }
                l => assert_eq!((now.0, now.1), (before.0, l - 1), "slot {i}"),
            }
        }
        eprintln!(
            "capacity {capacity}, fill {fill}: {} live cells listed",
            active.len()
        );
    }
}

/// The default probing length holds a table 40% full of real cell keys (random surface points
/// of a 200 m scene at every level) without losing a lookup; the former default of 8 did not
/// (a run of 8 occupied slots turns up at about 20% full, as on the `interior` hall).
#[test]
fn default_probing_holds_a_table_well_past_what_scenes_fill() {
    let s = WorldCacheSettings::default();
    let g = grid(&s);
    let mut rng = Pcg32::seed_from_u64(17);
    let mut table = vec![EMPTY_CHECKSUM; s.capacity as usize];
    let target = s.capacity as usize * 2 / 5;
    let (mut created, mut needed_more_than_8) = (0usize, 0usize);
    while created < target {
        let case = random_case(&mut rng, 200.0);
        let cell = g.cell(case.position, case.normal, [0.0; 3], case.ray_length);
        match insert(&mut table, cell, s.max_search_steps) {
            Probe::Created(slot) => {
                created += 1;
                if slot.wrapping_sub(cell.key) & (s.capacity - 1) >= 8 {
                    needed_more_than_8 += 1;
                }
            }
            Probe::Found(_) => {}
            Probe::Full => panic!(
                "a lookup failed at {created} cells ({:.1}% full)",
                100.0 * created as f64 / s.capacity as f64
            ),
        }
    }
    eprintln!("{created} cells: {needed_more_than_8} sat 8 or more slots from home");
    assert!(
        needed_more_than_8 > 0,
        "the test no longer reaches the old default's limit"
    );
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct WarmUpCase {
    samples: f32,
    most: f32,
    exponent: f32,
    _pad: f32,
}

#[test]
fn gpu_warm_up_window_matches_the_rust_twin() {
    use solari_worldcache::warm_up_window;
    let Some(gpu) = test_gpu() else { return };
    let backend = gpu.backend(Default::default()).unwrap();
    let kernel = include_str!("shaders/world_cache_warm_up_test.wesl");
    let mut modules = solari_worldcache::modules();
    modules.push(("world_cache_warm_up_test", kernel));
    let wgsl = compose("world_cache_warm_up_test", backend, &modules).expect("compose");
    let io = gpu.buffer_layout(
        "warm_up_test",
        &[
            wgpu::BufferBindingType::Storage { read_only: true },
            wgpu::BufferBindingType::Storage { read_only: false },
        ],
    );
    let pipeline = gpu
        .compute_pipeline("warm_up_test", &wgsl, &[Some(&io)], ShaderChecks::All, &[])
        .expect("pipeline");
    let mut rng = Pcg32::seed_from_u64(11);
    let case = |samples: f32, most: f32, exponent: f32| WarmUpCase {
        samples,
        most,
        exponent,
        _pad: 0.0,
    };
    // Edges: no samples, one, the count at and past the window's end, the exponent off,
    // a cap of one sample, the light-change cap below the count.
    let mut cases = vec![
        case(0.0, 30.0, 2.0),
        case(1.0, 30.0, 2.0),
        case(30.0, 30.0, 2.0),
        case(31.0, 30.0, 2.0),
        case(12.0, 30.0, 0.0),
        case(5.0, 1.0, 2.0),
        case(30.0, 4.0, 2.0),
        case(0.0, 30.0, 16.0),
    ];
    cases.extend((0..2000).map(|_| {
        case(
            rng.random_range(0u32..40) as f32,
            rng.random_range(1.0f32..64.0),
            if rng.random_bool(0.1) {
                0.0
            } else {
                rng.random_range(0.0f32..16.0)
            },
        )
    }));
    let got: Vec<f32> = gpu
        .run_cases("warm_up_test", &pipeline, &io, &[None], &cases)
        .expect("run");
    for (c, g) in cases.iter().zip(&got) {
        let want = warm_up_window(c.samples, c.most, c.exponent);
        assert!(
            (g - want).abs() <= 1e-4 * want.max(1.0),
            "{c:?}: GPU {g}, Rust {want}"
        );
        // A window: at least one sample, never past the cap, the whole cap once the count
        // reaches it.
        assert!(
            *g >= 1.0 - 1e-5 && *g <= c.most.max(1.0) + 1e-4,
            "{c:?}: {g}"
        );
        if c.samples >= c.most {
            assert!((g - c.most).abs() <= 1e-4 * c.most, "{c:?}: {g}");
        }
    }
    // Monotone in the count.
    for exponent in [0.5f32, 1.0, 2.0, 4.0] {
        let w: Vec<f32> = (0..=30)
            .map(|n| warm_up_window(n as f32, 30.0, exponent))
            .collect();
        assert!(w.windows(2).all(|p| p[1] >= p[0]), "{exponent}: {w:?}");
        assert_eq!(w[0], 1.0);
        assert_eq!(w[30], 30.0);
    }
}
