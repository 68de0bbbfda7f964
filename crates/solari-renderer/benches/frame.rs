//! The whole real-time frame's GPU time per scene (G-buffer, light tiles, world cache, ReSTIR
//! DI, cache GI, specular GI, fallback denoiser: the CLI's `solari render --mode realtime --gi
//! cache --denoiser fallback`, G-buffer producer chosen by measurement as the CLI's `auto`),
//! the sum of the renderer's own per-pass timestamps; throughput in pixels. Beside it, each
//! component's passes timed inside that frame (`<scene>/<backend>/<component>`): a pass of a
//! few microseconds costs what its neighbours leave in the caches, so its figure alone (the
//! component's own bench) and in the frame can differ by more than the bench's noise
//! (benches/RESULTS.md, "Criterion benches against the CLI").
//!
//! `cargo bench -p solari-renderer --bench frame`: 1920×1080, the bundled scenes and every
//! scene in `../shared/scenes` when it is there. Under `cargo test` (CI, lavapipe) each case
//! runs once at 64×64: the bench must run, not be timed.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use solari_denoise::DenoiserKind;
use solari_renderer::{FrameReport, GBufferChoice, GiMode, RealtimeRenderer, RealtimeSettings};
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
use solari_scene::gpu_timer::full_bench;
use std::time::Duration;

/// Components timed inside the frame: name, then the report rows (passes) summed.
const COMPONENTS: [(&str, &[&str]); 4] = [
    ("light_tiles", &["light_tiles"]),
    ("restir_di", &["di_initial_temporal", "di_spatial_shade"]),
    (
        "world_cache",
        &[
            "world_cache_decay",
            "world_cache_compact",
            "world_cache_update",
            "world_cache_blend",
            "world_cache_gi",
        ],
    ),
    (
        "fallback_denoiser",
        &["denoise_temporal", "denoise_variance", "denoise_atrous"],
    ),
];

fn frame(c: &mut Criterion) {
    let full = full_bench();
    let (w, h) = if full { (1920, 1080) } else { (64, 64) };
    let gpu = Gpu::new().expect("a GPU adapter");
    let backend = gpu.backend(Default::default()).expect("backend");
    let settings = RealtimeSettings {
        gbuffer: GBufferChoice::Auto,
        gi: GiMode::WorldCache,
        denoiser: Some(DenoiserKind::Fallback),
        timestamps: true,
        ..Default::default()
    };
    let mut group = c.benchmark_group("frame");
    group.sample_size(20);
    group.throughput(Throughput::Elements(w as u64 * h as u64));
    for (name, path) in solari_testdata::bench_scenes(full) {
        let scene = solari_scene::load_gltf(&path).expect("scene loads");
        let camera = scene.camera(None).expect("camera");
        let gpu_scene =
            GpuScene::new(&gpu, &scene, backend, &GpuSceneOptions::default()).expect("upload");
        let mut renderer = RealtimeRenderer::new(&gpu, backend, &scene, &gpu_scene, w, h, settings)
            .expect("renderer");
        // None: every timed pass (the whole frame).
        let cases = std::iter::once((String::new(), None))
            .chain(COMPONENTS.map(|(c, passes)| (format!("/{c}"), Some(passes))));
        for (suffix, passes) in cases {
            let id = format!("{name}/{}{suffix}", backend.name());
            group.bench_function(id, |b| {
                b.iter_custom(|iters| {
                    let mut ms = 0.0;
                    for _ in 0..iters {
                        let report = renderer
                            .render(&gpu, &scene, &gpu_scene, &camera)
                            .expect("frame");
                        ms += timed_ms(&report, passes, &gpu);
                    }
                    Duration::from_secs_f64(ms * 1e-3)
                })
            });
        }
    }
    group.finish();
}

/// The GPU time of `passes` (every timed pass for `None`) in one frame's report. Panics where
/// the adapter gave no timestamps, or none of the named passes ran: a bench must not time
/// nothing.
fn timed_ms(report: &FrameReport, passes: Option<&[&str]>, gpu: &Gpu) -> f64 {
    let timed: Vec<(&str, f64)> = report
        .passes
        .iter()
        .filter_map(|p| p.gpu_ms.map(|ms| (p.name, ms)))
        .collect();
    assert!(
        !timed.is_empty(),
        "adapter '{}' gave no timestamps: GPU time cannot be measured",
        gpu.info.name
    );
    match passes {
        None => timed.iter().map(|(_, ms)| ms).sum(),
        Some(names) => {
            // A component may run fewer passes than it has (DI without reuse runs one), but
            // never none.
            let ran: Vec<f64> = timed
                .iter()
                .filter(|(p, _)| names.contains(p))
                .map(|(_, ms)| *ms)
                .collect();
            assert!(
                !ran.is_empty(),
                "none of the passes {names:?} ran in the frame"
            );
            ran.iter().sum()
        }
    }
}

criterion_group!(benches, frame);
criterion_main!(benches);
