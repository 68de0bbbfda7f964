//! The world cache inside the real-time renderer, on lavapipe: the non-finite detector names
//! the cache's pass when a cell is poisoned. The cache's own accuracy and stability tests are
//! in solari-worldcache (`tests/gi.rs`).

use solari_renderer::{GiMode, RealtimeRenderer, RealtimeSettings};
use solari_scene::gpu::{Gpu, test_gpu};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
use solari_scene::shaders::Backend;
use solari_scene::{Scene, default_scene};
use solari_worldcache::WorldCacheSettings;

mod common;

/// The renderer tests' small settings with world-cache GI in a `capacity`-slot table.
fn settings(capacity: u32) -> RealtimeSettings {
    RealtimeSettings {
        gi: GiMode::WorldCache,
        cache: WorldCacheSettings {
            capacity,
            ..Default::default()
        },
        ..common::settings()
    }
}

struct Setup {
    gpu_scene: GpuScene,
    renderer: RealtimeRenderer,
}

fn setup(gpu: &Gpu, scene: &Scene, size: u32, settings: RealtimeSettings) -> (Backend, Setup) {
    let backend = gpu.backend(Default::default()).unwrap();
    let gpu_scene =
        GpuScene::new(gpu, scene, backend, &GpuSceneOptions::default()).expect("scene upload");
    let renderer = RealtimeRenderer::new(gpu, backend, scene, &gpu_scene, size, size, settings)
        .expect("renderer");
    (
        backend,
        Setup {
            gpu_scene,
            renderer,
        },
    )
}

/// Runs `frames` frames of the scene's own camera.
fn run(gpu: &Gpu, scene: &Scene, s: &mut Setup, frames: u32) {
    let camera = scene.camera(None).unwrap();
    for _ in 0..frames {
        s.renderer
            .render(gpu, scene, &s.gpu_scene, &camera)
            .expect("frame");
    }
}

#[test]
fn the_detector_names_the_pass_that_holds_a_poisoned_value() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let (_, mut s) = setup(&gpu, &scene, 16, settings(1 << 14));
    run(&gpu, &scene, &mut s, 3);
    let cache = s.renderer.world_cache().unwrap();
    let mut cells = cache.read_cells(&gpu).unwrap();
    let live = cells.iter().position(|(_, life, _)| *life > 0).unwrap();
    cells[live].2.irradiance[0] = f32::NAN;
    cells[live].2.indirect[1] = -1.0;
    cache.write_cells(&gpu, &cells).unwrap();
    let camera = scene.camera(None).unwrap();
    let err = s
        .renderer
        .render(&gpu, &scene, &s.gpu_scene, &camera)
        .expect_err("the poisoned cell must be reported");
    match err {
        solari_scene::GpuError::NonFinite { pass, .. } => assert_eq!(pass, "world_cache"),
        other => panic!("{other}"),
    }
}

/// Regression: ReSTIR DI once reallocated its output buffer when the light list outgrew its
/// first light-id table (any scene with more than one light), after the GI passes had been
/// bound to the old buffer. Their light was lost, bit for bit (`--gi cache` and `--gi off`
/// gave identical images on many_lights and interior). Every GI mode must now add light on a
/// many-light scene.
#[test]
fn every_gi_mode_adds_light_on_a_scene_with_many_lights() {
    let Some(gpu) = test_gpu() else { return };
    let scene = solari_scene::load_gltf(solari_testdata::scene("many_lights")).expect("scene");
    let mean = |gi: GiMode| {
        let (_, mut s) = setup(
            &gpu,
            &scene,
            32,
            RealtimeSettings {
                gi,
                ..settings(1 << 14)
            },
        );
        run(&gpu, &scene, &mut s, 12);
        let pixels = s.renderer.read_output(&gpu).unwrap();
        pixels
            .iter()
            .map(|p| (p[0] + p[1] + p[2]) as f64)
            .sum::<f64>()
            / pixels.len() as f64
    };
    let off = mean(GiMode::Off);
    for gi in [GiMode::WorldCache, GiMode::Path, GiMode::Restir] {
        let with = mean(gi);
        eprintln!("many_lights 32x32: mean {off:.5} without GI, {with:.5} with {gi:?}");
        assert!(
            with > off * 1.002,
            "{gi:?} adds no light: {with} against {off}"
        );
    }
}

/// The cache's warm-up rounds inside the renderer: the frame reports' cache counters show
/// the rounds the GPU blended, three a frame until `warm_up_frames` have run (frame 0's
/// upkeep has no cell yet), then one; `cache_warming_up` (which the quality probe waits on)
/// turns false exactly then.
#[test]
fn the_caches_warm_up_rounds_run_in_its_first_frames_only() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let mut settings = settings(1 << 14);
    settings.cache.warm_up_rounds = 3;
    settings.cache.warm_up_frames = 4;
    let (_, mut s) = setup(&gpu, &scene, 16, settings);
    let camera = scene.camera(None).unwrap();
    let mut seen = Vec::new();
    for _ in 0..6 {
        let warming = s.renderer.cache_warming_up();
        let report = s
            .renderer
            .render(&gpu, &scene, &s.gpu_scene, &camera)
            .expect("frame");
        let rounds = report.cache.expect("cache counters").update_rounds;
        seen.push((warming, rounds));
    }
    assert_eq!(
        seen,
        [
            (true, 0),
            (true, 3),
            (true, 3),
            (true, 3),
            (false, 1),
            (false, 1)
        ],
        "(warming up before the frame, rounds blended) per frame"
    );
    assert!(!s.renderer.cache_warming_up());
}
