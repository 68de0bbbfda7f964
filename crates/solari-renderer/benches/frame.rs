//! The whole real-time frame's GPU time per scene (G-buffer, light tiles, world cache, ReSTIR
//! DI, cache GI, fallback denoiser: the CLI's `solari realtime --gi cache --denoiser
//! fallback`), the sum of the renderer's own per-pass timestamps; throughput in pixels.
//!
//! `cargo bench -p solari-renderer --bench frame`: 1920×1080, the bundled scenes and every
//! scene in `../shared/scenes` when it is there. Under `cargo test` (CI, lavapipe) each case
//! runs once at 64×64: the bench must run, not be timed.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use solari_denoise::DenoiserKind;
use solari_renderer::{GiMode, RealtimeRenderer, RealtimeSettings};
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
use solari_scene::gpu_timer::full_bench;
use std::time::Duration;

fn frame(c: &mut Criterion) {
    let full = full_bench();
    let (w, h) = if full { (1920, 1080) } else { (64, 64) };
    let gpu = Gpu::new().expect("a GPU adapter");
    let backend = gpu.backend(Default::default()).expect("backend");
    let settings = RealtimeSettings {
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
        group.bench_function(format!("{name}/{}", backend.name()), |b| {
            b.iter_custom(|iters| {
                let mut ms = 0.0;
                for _ in 0..iters {
                    let report = renderer
                        .render(&gpu, &scene, &gpu_scene, &camera)
                        .expect("frame");
                    let timed: Vec<f64> = report.passes.iter().filter_map(|p| p.gpu_ms).collect();
                    assert!(
                        !timed.is_empty(),
                        "adapter '{}' gave no timestamps: GPU time cannot be measured",
                        gpu.info.name
                    );
                    ms += timed.iter().sum::<f64>();
                }
                Duration::from_secs_f64(ms * 1e-3)
            })
        });
    }
    group.finish();
}

criterion_group!(benches, frame);
criterion_main!(benches);
