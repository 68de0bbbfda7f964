//! Automatic quality's start-up probe on a real adapter (GPU: lavapipe): it times every pass
//! the cost model reads, its predictions order the settings as their work does, the choice
//! follows the budget, and an adapter without timestamp queries is not probed at all.

mod common;

use common::{SIZE, settings, upload};
use solari_renderer::auto_quality::{CostModel, ErrorTable, choose, probe};
use solari_renderer::quality::{QualitySetting, Resolution};
use solari_renderer::{GiMode, RealtimeSettings};
use solari_scene::default_scene;
use solari_scene::gpu::{Gpu, test_gpu};

fn base() -> RealtimeSettings {
    // The probe turns on the GI, reuse and upscaling it times; the denoiser is the user's.
    RealtimeSettings {
        denoiser: Some(solari_denoise::DenoiserKind::Fallback),
        ..settings()
    }
}

fn probe_box(gpu: &Gpu) -> Option<CostModel> {
    probe_box_from(gpu, &base())
}

fn probe_box_from(gpu: &Gpu, base: &RealtimeSettings) -> Option<CostModel> {
    let backend = gpu.backend(Default::default()).expect("backend");
    let scene = default_scene::cornell_box();
    let gpu_scene = upload(gpu, backend, &scene);
    let camera = scene.camera(None).expect("camera");
    probe(
        gpu,
        backend,
        &scene,
        &gpu_scene,
        &camera,
        (SIZE, SIZE),
        base,
    )
    .expect("probe")
}

/// The probe times every frame of its phases whatever timestamp interval the user's settings
/// carry (the CLI's `--time-every`): with the user's, a phase could time none of its frames
/// (here, an interval no probe frame reaches), and the probe reported an adapter without
/// timestamps.
#[test]
fn the_probe_times_every_frame_whatever_the_users_interval() {
    let Some(gpu) = test_gpu() else { return };
    let sparse = RealtimeSettings {
        timestamp_interval: 1_000_000,
        ..base()
    };
    let model = probe_box_from(&gpu, &sparse).expect("a cost model");
    assert!(
        model.full.get("gbuffer").is_some_and(|ms| *ms > 0.0),
        "{model:?}"
    );
    assert!(model.di_no_reuse > 0.0 && model.gi_path > 0.0, "{model:?}");
}

/// A world cache warm-up longer than the probe waits for (`MAX_CACHE_WARM_UP_WAIT` frames
/// past `WARM_UP_SECONDS`) does not hold the probe: with 100,000 warm-up frames it still
/// returns a cost model (it would render every one of them before its first phase).
#[test]
fn the_probe_does_not_wait_out_a_long_cache_warm_up() {
    let Some(gpu) = test_gpu() else { return };
    let mut long = base();
    long.cache.warm_up_frames = 100_000;
    long.cache.warm_up_rounds = 2;
    let model = probe_box_from(&gpu, &long).expect("a cost model");
    assert!(
        model.full.get("gbuffer").is_some_and(|ms| *ms > 0.0),
        "{model:?}"
    );
}

#[test]
fn the_probe_times_what_the_cost_model_reads() {
    let Some(gpu) = test_gpu() else { return };
    let model = probe_box(&gpu).expect("lavapipe has timestamp queries");
    for pass in [
        "gbuffer",
        "light_tiles",
        "di_initial_temporal",
        "di_spatial_shade",
        "gi_initial_temporal",
        "gi_spatial_shade",
        "specular_gi",
        "denoise_atrous",
        "temporal_upscale",
    ] {
        let ms = model.full.get(pass).copied();
        assert!(
            ms.is_some_and(|ms| ms.is_finite() && ms > 0.0),
            "{pass}: {ms:?} ms"
        );
    }
    assert!(model.di_no_reuse > 0.0 && model.gi_path > 0.0, "{model:?}");

    let setting = |resolution, gi, di_reuse| QualitySetting {
        resolution,
        gi,
        di_reuse,
    };
    let grid = QualitySetting::grid();
    for g in &grid {
        let ms = model.predict(g);
        assert!(ms.is_finite() && ms > 0.0, "{}: {ms} ms", g.name());
    }
    // Less work, less predicted time: fewer pixels, and the upscaler only where it runs.
    let half = model.predict(&setting(Resolution::Half, GiMode::Restir, true));
    let native = model.predict(&setting(Resolution::Native, GiMode::Restir, true));
    let aa = model.predict(&setting(Resolution::Antialiased, GiMode::Restir, true));
    assert!(half < native && native < aa, "{half} {native} {aa}");
    let cache = model.predict(&setting(Resolution::Native, GiMode::WorldCache, false));
    assert!(
        cache < native,
        "cache GI without DI reuse {cache} vs {native}"
    );

    // The choice: with room for everything, the least error; with none, the cheapest.
    let errors = ErrorTable::builtin().expected_errors(Some("cornell_box"));
    let best = errors
        .iter()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("the table has settings");
    let roomy = choose(f64::INFINITY, &model, &errors).expect("a choice");
    assert!(roomy.fits && roomy.fitting == errors.len());
    assert_eq!(roomy.expected_error, best.1);
    let tight = choose(0.0, &model, &errors).expect("a choice");
    assert!(!tight.fits && tight.fitting == 0);
    let cheapest = errors
        .iter()
        .map(|(g, _)| model.predict(g))
        .fold(f64::INFINITY, f64::min);
    assert_eq!(tight.predicted_ms, cheapest);
}

#[test]
fn an_adapter_without_timestamps_is_not_probed() {
    let Some(full) = test_gpu() else { return };
    drop(full);
    let gpu = Gpu::new_without(wgpu::Features::TIMESTAMP_QUERY).expect("device");
    assert!(!gpu.features.contains(wgpu::Features::TIMESTAMP_QUERY));
    let started = std::time::Instant::now();
    assert_eq!(probe_box(&gpu), None);
    // No renderer was built (a probe renders 18 frames with everything on).
    println!("probe without timestamps: {:?}", started.elapsed());
}
