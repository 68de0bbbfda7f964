//! The world cache on lavapipe, composed with the other components as the renderer does
//! (G-buffer → light tiles → ReSTIR DI → cache upkeep → cache GI; the DI frame is
//! solari-restir's test harness): convergence to the analytic furnaces, cache-only GI against
//! the full-bounce reference (`solari-reference`) in the Cornell box, how fast the cache
//! follows a light switched off and on, cells dying once the camera leaves, a table too small
//! for the view, bad settings, absurd light and a 10,000-frame run in the white furnace.
//! Measured figures are printed for the issue notes
//! (`cargo test --release -p solari-worldcache --test gi -- --nocapture`).

use glam::{Mat4, Vec3};
use solari_scene::finite_check::{FiniteChecker, RecordLayout, first_offender};
use solari_scene::gpu::{Gpu, test_gpu};
use solari_scene::gpu_scene::TraceVariant;
use solari_scene::{Camera, Scene, default_scene, load_gltf};
use solari_worldcache::{CELL_CHECK, CacheStats, GpuCacheCell, WorldCache, WorldCacheSettings};

#[path = "../../solari-restir/tests/common/mod.rs"]
mod direct;

use direct::{DirectLight, di_settings, reference, rmse, tile_settings, total_light_bias};

/// Whether cache GI is added to the direct light, or the cache only kept up to date.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Gi {
    Off,
    WorldCache,
}

/// One scene's direct light (G-buffer, tiles, ReSTIR DI) and world cache, with the
/// non-finite detector over the cache's cells and the lit image on every frame.
struct Setup {
    direct: DirectLight,
    cache: WorldCache,
    target: wgpu::BindGroup,
    gi: Gi,
    checker: FiniteChecker,
    frames_checked: u64,
}

/// The detector's slots: the cells after the upkeep, the image after cache GI.
const SLOTS: [&str; 2] = ["world_cache", "cache_gi"];

fn cache_settings(capacity: u32) -> WorldCacheSettings {
    WorldCacheSettings {
        capacity,
        ..Default::default()
    }
}

fn setup(gpu: &Gpu, scene: &Scene, size: u32, capacity: u32) -> Setup {
    setup_with(gpu, scene, size, cache_settings(capacity), Gi::WorldCache).expect("cache")
}

fn setup_with(
    gpu: &Gpu,
    scene: &Scene,
    size: u32,
    settings: WorldCacheSettings,
    gi: Gi,
) -> Result<Setup, solari_scene::GpuError> {
    let backend = gpu.backend(Default::default()).expect("backend");
    let direct = DirectLight::new(gpu, backend, scene, size, di_settings(), tile_settings());
    let variant = TraceVariant::for_scene(&direct.gpu_scene);
    let cache = WorldCache::new(gpu, backend, variant, settings, tile_settings())?;
    let target = cache.target_group(gpu, direct.di.output());
    Ok(Setup {
        direct,
        cache,
        target,
        gi,
        checker: FiniteChecker::new(gpu, &SLOTS)?,
        frames_checked: 0,
    })
}

impl Setup {
    /// One frame from `camera`, submitted; panics if the cells or the image hold a NaN, an
    /// infinity or a negative value.
    fn frame(&mut self, gpu: &Gpu, scene: &Scene, camera: &Camera) {
        self.direct.prepare(gpu, scene, camera);
        let context = *self.direct.context();
        self.cache
            .prepare(gpu, &context, self.direct.lights.light_count);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        self.checker.begin_frame(&mut encoder);
        self.direct.encode_inputs(&mut encoder);
        self.direct.encode_di(&mut encoder);
        let d = &self.direct;
        self.cache
            .encode(&mut encoder, &context, &d.gpu_scene, &d.lights_group)
            .expect("cache upkeep");
        if self.gi == Gi::WorldCache {
            self.cache
                .encode_gi(&mut encoder, &context, &d.gbuffer, &self.target)
                .expect("cache GI");
        }
        let slots = self.cache.settings().capacity as u64;
        let (w, h) = d.di.size();
        let c = &mut self.checker;
        c.check_buffer(
            gpu,
            &mut encoder,
            0,
            self.cache.cells_buffer(),
            slots,
            CELL_CHECK,
        )
        .expect("check cells");
        let pixels = w as u64 * h as u64;
        c.check_buffer(
            gpu,
            &mut encoder,
            1,
            d.di.output(),
            pixels,
            RecordLayout::RGBA_NON_NEGATIVE,
        )
        .expect("check image");
        c.end_frame(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        let counts = self.checker.read(gpu).expect("detector");
        if let Some(bad) = first_offender(&counts) {
            panic!("frame {}: {bad:?}", self.frames_checked);
        }
        self.frames_checked += 1;
    }

    fn stats(&self, gpu: &Gpu) -> CacheStats {
        self.cache.read_stats(gpu).expect("stats")
    }

    fn read_output(&self, gpu: &Gpu) -> Vec<[f32; 4]> {
        self.direct.read_output(gpu)
    }
}

/// Live cells (life > 0) with at least `min_samples` samples.
fn live_cells(s: &Setup, gpu: &Gpu, min_samples: f32) -> Vec<GpuCacheCell> {
    s.cache
        .read_cells(gpu)
        .unwrap()
        .into_iter()
        .filter(|(_, life, c)| *life > 0 && c.irradiance[3] >= min_samples)
        .map(|(_, _, c)| c)
        .collect()
}

fn mean_se(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (m, (var / n).sqrt())
}

/// Runs `frames` frames of the scene's own camera.
fn run(gpu: &Gpu, scene: &Scene, s: &mut Setup, frames: u32) {
    let camera = scene.camera(None).unwrap();
    for _ in 0..frames {
        s.frame(gpu, scene, &camera);
    }
}

// Green channel of the cells' total and indirect irradiance, split by a predicate on position.
fn cell_means(
    cells: &[GpuCacheCell],
    pick: impl Fn(Vec3) -> bool,
) -> ((f64, f64), (f64, f64), usize) {
    let chosen: Vec<&GpuCacheCell> = cells
        .iter()
        .filter(|c| pick(Vec3::from(c.position)))
        .collect();
    let total: Vec<f64> = chosen.iter().map(|c| c.irradiance[1] as f64).collect();
    let indirect: Vec<f64> = chosen.iter().map(|c| c.indirect[1] as f64).collect();
    (mean_se(&total), mean_se(&indirect), chosen.len())
}

#[test]
fn cache_converges_to_the_analytic_furnaces() {
    let Some(gpu) = test_gpu() else { return };
    // Irradiance / π: total and the part not from the light list.
    // furnace_uniform: I = L = E / (1 - a) = 1, direct part E = 0.2.
    // furnace_sphere (README): wall I = (L_wall - E) / rho_w = 1.92928 (direct (1 - k) E =
    // 0.91); sphere I = L_wall = 1.96464 (direct E = 1).
    type Region = (&'static str, fn(Vec3) -> bool, f64, f64);
    let cases: [(&str, Vec<Region>); 2] = [
        ("furnace_uniform", vec![("all cells", |_| true, 1.0, 0.8)]),
        (
            "furnace_sphere",
            vec![
                ("wall", |p: Vec3| p.length() > 4.0, 1.92928, 1.92928 - 0.91),
                ("sphere", |p: Vec3| p.length() < 2.0, 1.96464, 0.96464),
            ],
        ),
    ];
    for (name, regions) in cases {
        let scene = load_gltf(solari_testdata::scene(name)).expect("scene");
        // A table about 40× the live cells. At 1 << 15 (10% full) a linear probing run once
        // exceeded the former default of 8 steps in the last frame (one overflow, in one of
        // several CI runs; the default is now 32): the check below is that no cell is lost.
        let mut s = setup(&gpu, &scene, 32, 1 << 17);
        // Measured: the uniform furnace's mean settles by frame ~500 (0.984 at 400, 0.989 at
        // 500 and 600); the sphere furnace by ~300.
        run(&gpu, &scene, &mut s, 600);
        // Two snapshots 50 frames apart (about two blend windows) average some noise away.
        let mut cells = live_cells(&s, &gpu, 20.0);
        run(&gpu, &scene, &mut s, 50);
        cells.extend(live_cells(&s, &gpu, 20.0));
        let stats = s.stats(&gpu);
        assert_eq!(stats.overflows, 0);
        for (region, pick, total, indirect) in regions {
            let ((t, tse), (i, ise), n) = cell_means(&cells, pick);
            eprintln!(
                "{name} {region}: {n} cell samples, irradiance {t:.4} ± {tse:.4} (analytic {total:.4}), \
                 indirect {i:.4} ± {ise:.4} (analytic {indirect:.4}); {} live cells",
                stats.active_cells
            );
            assert!(n > 50, "{name} {region}: too few cells ({n})");
            assert!(
                (t - total).abs() < 4.0 * tse + 0.02 * total,
                "{name} {region}: irradiance {t} ± {tse}, expected {total}"
            );
            assert!(
                (i - indirect).abs() < 4.0 * ise + 0.03 * indirect,
                "{name} {region}: indirect {i} ± {ise}, expected {indirect}"
            );
        }
    }
}

/// The renderer keeps the new samples in shared scratch that other passes overwrite
/// (`WorldCache::use_scratch`). With that scratch filled with garbage (random bytes, so NaNs,
/// infinities and huge values among them) before every frame, the uniform furnace's cells
/// still converge to the analytic 1 (as in `cache_converges_to_the_analytic_furnaces`) and
/// never hold a non-finite value (the detector checks every frame): the blend reads only
/// what the update wrote in the same frame. The cache no longer counts the samples, and a
/// scratch too small is refused.
#[test]
fn new_samples_in_a_scratch_full_of_garbage_change_nothing() {
    use rand::{Rng, SeedableRng};
    let Some(gpu) = test_gpu() else { return };
    let scene = load_gltf(solari_testdata::scene("furnace_uniform")).expect("scene");
    let capacity = 1 << 15;
    let mut s = setup(&gpu, &scene, 32, capacity);
    let own = s.cache.memory_bytes();
    let small = solari_scene::scratch::allocate(&gpu, s.cache.scratch_bytes() - 16).unwrap();
    let e = s.cache.use_scratch(&gpu, &small).unwrap_err().to_string();
    assert!(e.contains("world cache") && e.contains("it needs"), "{e}");
    let scratch = solari_scene::scratch::allocate(&gpu, s.cache.scratch_bytes()).unwrap();
    s.cache.use_scratch(&gpu, &scratch).expect("scratch");
    assert_eq!(own - s.cache.memory_bytes(), 32 * capacity as u64);
    let mut rng = rand_pcg::Pcg32::seed_from_u64(11);
    let garbage: Vec<u8> = (0..2 * scratch.size()).map(|_| rng.random()).collect();
    let camera = scene.camera(None).unwrap();
    for frame in 0..500usize {
        // A different window of the garbage each frame.
        let at = (frame * 4099) % scratch.size() as usize;
        gpu.queue
            .write_buffer(&scratch, 0, &garbage[at..at + scratch.size() as usize]);
        s.frame(&gpu, &scene, &camera);
    }
    let cells = live_cells(&s, &gpu, 20.0);
    let ((t, tse), _, n) = cell_means(&cells, |_| true);
    eprintln!("furnace_uniform, new samples in garbage: {n} cells, irradiance {t:.4} ± {tse:.4}");
    assert!(n > 50, "too few cells ({n})");
    assert!(
        (t - 1.0).abs() < 4.0 * tse + 0.03,
        "irradiance {t} ± {tse}, expected 1"
    );
}

/// Mean output over `frames` frames after `warmup`, and the last frame alone.
fn mean_output(
    gpu: &Gpu,
    scene: &Scene,
    s: &mut Setup,
    warmup: u32,
    frames: u32,
) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    run(gpu, scene, s, warmup);
    direct::frame_mean(frames, || {
        run(gpu, scene, s, 1);
        s.read_output(gpu)
    })
}

#[test]
fn cache_gi_is_closer_to_the_full_reference_than_direct_light_alone() {
    let Some(gpu) = test_gpu() else { return };
    let size = 48;
    let scene = default_scene::cornell_box();
    let backend = gpu.backend(Default::default()).unwrap();
    // Full bounces: Russian roulette alone ends the paths.
    let reference = reference(&gpu, backend, &scene, size, 512, u32::MAX);
    let mut errors = Vec::new();
    for gi in [Gi::Off, Gi::WorldCache] {
        let mut s = setup_with(&gpu, &scene, size, cache_settings(1 << 14), gi).expect("cache");
        let (mean, last) = mean_output(&gpu, &scene, &mut s, 200, 64);
        let (e_mean, e_last) = (rmse(&mean, &reference), rmse(&last, &reference));
        let bias = total_light_bias(&mean, &reference);
        eprintln!(
            "cornell {size}x{size} {gi:?}: RMSE vs full reference, one frame {e_last:.4}, \
             mean of 64 frames {e_mean:.4}; total light {:+.1}%",
            bias * 100.0
        );
        errors.push((e_last, e_mean, bias));
    }
    let (off, cache) = (errors[0], errors[1]);
    assert!(
        cache.1 < 0.5 * off.1,
        "64-frame mean: cache GI {} vs DI {}",
        cache.1,
        off.1
    );
    assert!(
        cache.0 < off.0,
        "single frame: cache GI {} vs DI {}",
        cache.0,
        off.0
    );
    assert!(
        cache.2.abs() < 0.06,
        "cache GI total light off by {:+.1}%",
        cache.2 * 100.0
    );
}

/// Mean green indirect irradiance over live cells.
fn mean_indirect(s: &Setup, gpu: &Gpu) -> f64 {
    let cells = live_cells(s, gpu, 0.0);
    cells.iter().map(|c| c.indirect[1] as f64).sum::<f64>() / cells.len().max(1) as f64
}

/// How a cold cache's indirect light filled: see [`fill_from_cold`].
struct Fill {
    /// The live cells' mean indirect irradiance after each frame.
    levels: Vec<f64>,
    /// Its mean over frames 200..300.
    steady: f64,
}

impl Fill {
    /// The first frame whose level exceeds `fraction` of the steady one. Where the curve is
    /// flat near `fraction` the run-to-run noise moves this by several frames: compare
    /// crossings where the curves are steep.
    fn frames_to(&self, fraction: f64) -> Option<usize> {
        let bar = fraction * self.steady;
        self.levels.iter().position(|&l| l > bar).map(|f| f + 1)
    }

    /// The mean shortfall below the steady level over the first 16 frames, as a fraction of
    /// it: the area between the fill curve and its steady level, which averages out the
    /// frame-to-frame noise that moves a single crossing.
    fn shortfall(&self) -> f64 {
        self.levels[..16]
            .iter()
            .map(|&l| (1.0 - l / self.steady).max(0.0))
            .sum::<f64>()
            / 16.0
    }
}

/// 300 frames of the 32² scene from a cold cache, with the live cells' mean indirect
/// irradiance read after each.
fn fill_from_cold(gpu: &Gpu, scene: &Scene, settings: WorldCacheSettings) -> Fill {
    let mut s = setup_with(gpu, scene, 32, settings, Gi::WorldCache).expect("cache");
    let levels: Vec<f64> = (0..300)
        .map(|_| {
            run(gpu, scene, &mut s, 1);
            mean_indirect(&s, gpu)
        })
        .collect();
    let steady = levels[200..].iter().sum::<f64>() / 100.0;
    Fill { levels, steady }
}

/// A cold cache's indirect light reaches its steady level sooner with the young-cell
/// window (`WorldCacheSettings::warm_up_exponent`) than with a plain running mean, and
/// settles at the same level: frames until the mean indirect irradiance of the live cells is
/// within 10% of the level after 300 frames, on the 32² Cornell box.
#[test]
fn young_cells_fill_sooner_and_settle_at_the_same_level() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let fill = |exponent: f32| {
        let settings = WorldCacheSettings {
            warm_up_exponent: exponent,
            // One round a frame: this test is about the window.
            warm_up_rounds: 1,
            ..cache_settings(1 << 14)
        };
        fill_from_cold(&gpu, &scene, settings)
    };
    let (plain, ramp) = (fill(0.0), fill(2.0));
    eprintln!(
        "cornell 32x32, cold cache: indirect within 10% of steady after {:?} frames \
         (running mean, steady {:.4}) and {:?} (warm-up exponent 2, steady {:.4})",
        plain.frames_to(0.9),
        plain.steady,
        ramp.frames_to(0.9),
        ramp.steady
    );
    let (Some(p), Some(r)) = (plain.frames_to(0.9), ramp.frames_to(0.9)) else {
        panic!(
            "never filled: {:?} / {:?}",
            plain.frames_to(0.9),
            ramp.frames_to(0.9)
        );
    };
    // Measured on lavapipe: 18-20 frames against 48-56.
    assert!(
        (r as f64) <= 0.6 * p as f64,
        "the warm-up took {r} frames against the running mean's {p}"
    );
    assert!(
        (ramp.steady / plain.steady - 1.0).abs() < 0.05,
        "steady levels differ: {:.4} with the warm-up, {:.4} without",
        ramp.steady,
        plain.steady
    );
}

/// Warm-up rounds (`WorldCacheSettings::warm_up_rounds`): a cold cache's indirect light comes
/// within 20% of its steady level in fewer frames with four update rounds a frame than with
/// one, falls less short of it over the first 16 frames (`Fill::shortfall`), and settles at
/// the same level; the rounds run in the first `warm_up_frames` frames only (counted on the
/// CPU and by the GPU's blend), again after `clear`, and in the frames after a light change.
/// 32² Cornell box.
#[test]
fn warm_up_rounds_fill_a_cold_cache_sooner_and_settle_at_the_same_level() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let settings = |rounds: u32| WorldCacheSettings {
        warm_up_rounds: rounds,
        warm_up_frames: 8,
        ..cache_settings(1 << 14)
    };
    let fill = |rounds: u32| fill_from_cold(&gpu, &scene, settings(rounds));
    let (one, four) = (fill(1), fill(4));
    let (one_short, four_short) = (one.shortfall(), four.shortfall());
    eprintln!(
        "cornell 32x32, cold cache: within 20% of steady after {:?} frames with one round, {:?} \
         with four; mean shortfall over the first 16 frames {one_short:.3} and {four_short:.3} \
         (steady {:.4} and {:.4})",
        one.frames_to(0.8),
        four.frames_to(0.8),
        one.steady,
        four.steady
    );
    // Four rounds' curve flattens just under 90% of its steady level after the warm-up frames,
    // so the frame that crosses 90% wandered from 9 to 15 between runs of lavapipe (its cells
    // are claimed in thread order) and failed a bound of 0.65x one round's 17-21 in CI. At 80%
    // both curves are steep: measured on lavapipe 7 frames against 11-13 (five runs).
    let (Some(a), Some(b)) = (one.frames_to(0.8), four.frames_to(0.8)) else {
        panic!(
            "never within 20%: {:?} / {:?}",
            one.frames_to(0.8),
            four.frames_to(0.8)
        );
    };
    assert!(
        (b as f64) <= 0.7 * a as f64,
        "four rounds took {b} frames against one round's {a}"
    );
    // The area below the steady level wanders little: measured on lavapipe 0.64-0.67 of one
    // round's (six runs).
    assert!(
        four_short <= 0.75 * one_short,
        "four rounds fell {four_short:.3} short over 16 frames against one round's {one_short:.3}"
    );
    assert!(
        (four.steady / one.steady - 1.0).abs() < 0.05,
        "steady levels differ: {:.4} with four rounds, {:.4} with one",
        four.steady,
        one.steady
    );

    // Which frames run the rounds, on the CPU and on the GPU.
    let mut s = setup_with(&gpu, &scene, 32, settings(3), Gi::WorldCache).expect("cache");
    let mut counted = Vec::new();
    for _ in 0..10 {
        run(&gpu, &scene, &mut s, 1);
        counted.push((s.cache.update_rounds(), s.stats(&gpu).update_rounds));
    }
    // Frame 0's upkeep finds no live cell (the GI pass makes the first ones after it).
    let expected: Vec<(u32, u32)> = (0..10)
        .map(|f| match f {
            0 => (3, 0),
            1..=7 => (3, 3),
            _ => (1, 1),
        })
        .collect();
    assert_eq!(
        counted, expected,
        "(rounds recorded, rounds blended) per frame"
    );
    s.cache.clear(&gpu);
    run(&gpu, &scene, &mut s, 2);
    assert_eq!(
        (s.cache.update_rounds(), s.stats(&gpu).update_rounds),
        (3, 3),
        "rounds after clear"
    );
    // A light change runs the rounds for `light_change_frames` frames (8 by default).
    run(&gpu, &scene, &mut s, 10);
    assert_eq!(s.cache.update_rounds(), 1);
    s.cache.follow_light_change();
    let rounds: Vec<u32> = (0..10)
        .map(|_| {
            run(&gpu, &scene, &mut s, 1);
            s.cache.update_rounds()
        })
        .collect();
    assert_eq!(
        rounds,
        [3, 3, 3, 3, 3, 3, 3, 3, 1, 1],
        "rounds after a light change"
    );
}

#[test]
fn cache_follows_a_light_switched_off_and_on() {
    let Some(gpu) = test_gpu() else { return };
    let lit = default_scene::cornell_box();
    let mut dark = lit.clone();
    for m in &mut dark.materials {
        m.emissive = Vec3::ZERO;
    }
    let mut s = setup(&gpu, &lit, 32, 1 << 14);
    run(&gpu, &lit, &mut s, 300);
    let steady = mean_indirect(&s, &gpu);
    assert!(steady > 0.01, "the lit box has indirect light: {steady}");
    // Off: frames until the cached indirect light is under 5% of what it was.
    s.direct.set_lights(&gpu, &dark);
    let mut off_lag = None;
    for frame in 1..=200 {
        run(&gpu, &dark, &mut s, 1);
        if mean_indirect(&s, &gpu) < 0.05 * steady {
            off_lag = Some(frame);
            break;
        }
    }
    // On again: frames until it is back within 10%.
    s.direct.set_lights(&gpu, &lit);
    let mut on_lag = None;
    for frame in 1..=300 {
        run(&gpu, &lit, &mut s, 1);
        if mean_indirect(&s, &gpu) > 0.9 * steady {
            on_lag = Some(frame);
            break;
        }
    }
    eprintln!(
        "cornell 32x32: steady indirect {steady:.4}; light off: under 5% after {off_lag:?} frames; \
         on again: within 10% after {on_lag:?} frames"
    );
    // Measured 69 and 73-78 frames (default max_temporal_samples 30 and lifetime 30; cell
    // queries race, so runs differ by a few frames).
    assert!(
        off_lag.is_some_and(|f| f <= 100),
        "too slow to go dark: {off_lag:?}"
    );
    assert!(
        on_lag.is_some_and(|f| f <= 150),
        "too slow to light up: {on_lag:?}"
    );
}

#[test]
fn cells_die_once_the_camera_leaves_and_a_small_table_only_overflows() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let lifetime = WorldCacheSettings::default().lifetime;
    let mut s = setup(&gpu, &scene, 32, 1 << 14);
    run(&gpu, &scene, &mut s, 60);
    let inside = s.stats(&gpu).active_cells;
    // Turn the camera around: it sees only background, so no pixel renews any cell.
    let camera = scene.camera(None).unwrap();
    let away = Camera {
        transform: camera.transform * Mat4::from_rotation_y(std::f32::consts::PI),
        ..camera
    };
    let mut counts = Vec::new();
    for _ in 0..lifetime + 2 {
        s.frame(&gpu, &scene, &away);
        counts.push(s.stats(&gpu).active_cells);
    }
    eprintln!("cornell 32x32: {inside} live cells looking in; looking away: {counts:?}");
    assert!(inside > 100);
    // Cells may still create neighbours (with their own, shorter, life) before dying.
    assert!(
        counts.iter().all(|&c| c as f64 <= inside as f64 * 1.05),
        "no growth without pixels: {counts:?}"
    );
    assert_eq!(
        *counts.last().unwrap(),
        0,
        "all cells dead after {} frames",
        lifetime + 2
    );

    // A table far too small for the view: lookups fail and are counted, light stays finite.
    let mut small = setup(&gpu, &scene, 64, 1024);
    run(&gpu, &scene, &mut small, 40);
    let stats = small.stats(&gpu);
    let out = small.read_output(&gpu);
    eprintln!("cornell 64x64, 1024 slots: {stats:?}");
    assert!(stats.overflows > 0 && stats.active_cells <= 1024);
    assert!(out.iter().flatten().all(|x| x.is_finite()));
}

#[test]
fn bad_cache_settings_are_refused_with_a_message() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let bad = [
        WorldCacheSettings {
            capacity: 1000,
            ..Default::default()
        },
        WorldCacheSettings {
            capacity: 1 << 22,
            ..Default::default()
        },
        WorldCacheSettings {
            cell_size: f32::NAN,
            ..Default::default()
        },
        WorldCacheSettings {
            cell_size: 0.0,
            ..Default::default()
        },
        WorldCacheSettings {
            lod_distance: -1.0,
            ..Default::default()
        },
        WorldCacheSettings {
            lifetime: 0,
            ..Default::default()
        },
        WorldCacheSettings {
            max_search_steps: 65,
            ..Default::default()
        },
        WorldCacheSettings {
            max_temporal_samples: f32::INFINITY,
            ..Default::default()
        },
        WorldCacheSettings {
            light_change_samples: 0.5,
            ..Default::default()
        },
        WorldCacheSettings {
            light_change_samples: f32::NAN,
            ..Default::default()
        },
        WorldCacheSettings {
            light_change_frames: 100_001,
            ..Default::default()
        },
        WorldCacheSettings {
            warm_up_exponent: -1.0,
            ..Default::default()
        },
        WorldCacheSettings {
            warm_up_exponent: f32::NAN,
            ..Default::default()
        },
        WorldCacheSettings {
            warm_up_rounds: 0,
            ..Default::default()
        },
        WorldCacheSettings {
            warm_up_rounds: 17,
            ..Default::default()
        },
        WorldCacheSettings {
            warm_up_frames: 100_001,
            ..Default::default()
        },
        WorldCacheSettings {
            update_budget: 0,
            ..Default::default()
        },
        WorldCacheSettings {
            direct_candidates: 0,
            ..Default::default()
        },
        WorldCacheSettings {
            max_ray_distance: f32::NAN,
            ..Default::default()
        },
    ];
    for settings in bad {
        let err = setup_with(&gpu, &scene, 8, settings, Gi::WorldCache)
            .err()
            .unwrap_or_else(|| panic!("{settings:?} accepted"));
        assert!(err.to_string().contains("world cache settings"), "{err}");
    }
}

#[test]
fn ten_thousand_frames_in_the_white_furnace_stay_finite_and_bounded() {
    let Some(gpu) = test_gpu() else { return };
    let scene = load_gltf(solari_testdata::scene("furnace_uniform")).expect("scene");
    // About 11k live cells at the default 0.15 m: a 32k-slot table keeps them under half
    // full (at 16k slots, two thirds full, a lookup overflowed once in a few thousand frames).
    let mut s = setup(&gpu, &scene, 16, 1 << 15);
    let start = scene.camera(None).unwrap();
    let mut means = Vec::new();
    for frame in 0..10_000u32 {
        let camera = start.orbit(&scene, frame);
        s.frame(&gpu, &scene, &camera);
        if (frame + 1) % 1000 == 0 {
            let cells = s.cache.read_cells(&gpu).unwrap();
            assert!(
                cells.iter().all(|(_, _, c)| c
                    .irradiance
                    .iter()
                    .chain(&c.indirect)
                    .all(|x| x.is_finite())),
                "non-finite cell at frame {frame}"
            );
            let out = s.read_output(&gpu);
            assert!(
                out.iter().flatten().all(|x| x.is_finite()),
                "non-finite pixel at frame {frame}"
            );
            let live: Vec<f64> = cells
                .iter()
                .filter(|(_, life, c)| *life > 0 && c.irradiance[3] >= 20.0)
                .map(|(_, _, c)| c.irradiance[1] as f64)
                .collect();
            let mean = live.iter().sum::<f64>() / live.len().max(1) as f64;
            let max = live.iter().cloned().fold(0.0, f64::max);
            let stats = s.stats(&gpu);
            eprintln!(
                "furnace 16x16 frame {}: {} live cells, mean {mean:.4}, max {max:.3}, overflows {}",
                frame + 1,
                stats.active_cells,
                stats.overflows
            );
            means.push((mean, max, stats));
        }
    }
    // Bounded: every mean after the first thousand frames within 3% of the analytic 1.0, no
    // cell far above it, no overflow; no drift between the first and last checks.
    for (mean, max, stats) in &means[1..] {
        assert!((mean - 1.0).abs() < 0.03, "mean {mean}");
        assert!(*max < 3.0, "a cell ran away: {max}");
        assert_eq!(stats.overflows, 0);
    }
    let drift = means.last().unwrap().0 - means[1].0;
    assert!(drift.abs() < 0.01, "drift {drift}");
}

#[test]
fn absurd_light_keeps_the_cache_finite() {
    let Some(gpu) = test_gpu() else { return };
    let mut scene = default_scene::cornell_box();
    // The brightest emission a scene may have: import clamps to it, upload refuses more.
    for m in scene.materials.iter_mut().filter(|m| m.is_emissive()) {
        m.emissive = Vec3::splat(solari_scene::MAX_RADIANCE);
    }
    let mut s = setup(&gpu, &scene, 32, 1 << 14);
    run(&gpu, &scene, &mut s, 60);
    let cells = s.cache.read_cells(&gpu).unwrap();
    let live = cells.iter().filter(|(_, life, _)| *life > 0).count();
    let finite = |c: &GpuCacheCell| {
        c.irradiance
            .iter()
            .chain(&c.indirect)
            .all(|x| x.is_finite())
    };
    assert!(live > 100);
    assert!(
        cells.iter().all(|(_, _, c)| finite(c)),
        "a cell went non-finite"
    );
    let out = s.read_output(&gpu);
    assert!(
        out.iter().flatten().all(|x| x.is_finite()),
        "a pixel went non-finite"
    );
    eprintln!("cornell 32x32 with emission 1e9: {live} live cells, all finite");
}
