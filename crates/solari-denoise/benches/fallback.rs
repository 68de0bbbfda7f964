//! The fallback denoiser's GPU time per frame (all its passes) on ReSTIR DI frames per scene,
//! from encoder timestamps around it ([`PassTimer::time_span`]); throughput in pixels. The
//! G-buffer, light tiles and DI it reads are recorded untimed before each timed span.
//!
//! `cargo bench -p solari-denoise --bench fallback`: 1920×1080, default settings, the
//! bundled scenes and every scene in `../shared/scenes` when it is there. Under `cargo test`
//! (CI, lavapipe) each case runs once at 64×64: the bench must run, not be timed.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use solari_denoise::{Denoiser, DenoiserInputs, FallbackDenoiser, FallbackSettings, Lighting};
use solari_lights::LightTileSettings;
use solari_restir::RestirDiSettings;
use solari_scene::gpu::Gpu;
use solari_scene::gpu_timer::{PassTimer, full_bench};
use std::time::Duration;

#[path = "../../solari-restir/tests/common/mod.rs"]
mod direct;

use direct::DirectLight;

fn fallback(c: &mut Criterion) {
    let full = full_bench();
    let (w, h) = if full { (1920, 1080) } else { (64, 64) };
    let gpu = Gpu::new().expect("a GPU adapter");
    let timer = PassTimer::new(&gpu).unwrap_or_else(|e| panic!("{e}"));
    let backend = gpu.backend(Default::default()).expect("backend");
    let mut group = c.benchmark_group("fallback_denoiser");
    group.sample_size(20);
    group.throughput(Throughput::Elements(w as u64 * h as u64));
    for (name, path) in solari_testdata::bench_scenes(full) {
        let scene = solari_scene::load_gltf(&path).expect("scene loads");
        let camera = scene.camera(None).expect("camera");
        let (di, tiles) = (RestirDiSettings::default(), LightTileSettings::default());
        let mut direct = DirectLight::new_sized(&gpu, backend, &scene, (w, h), di, tiles);
        let settings = FallbackSettings::default();
        let mut denoiser = FallbackDenoiser::new(&gpu, w, h, settings).expect("denoiser");
        group.bench_function(format!("{name}/{}", backend.name()), |b| {
            b.iter_custom(|iters| {
                let mut ms = 0.0;
                for _ in 0..iters {
                    let mut encoder = gpu.device.create_command_encoder(&Default::default());
                    direct.encode(&gpu, &scene, &camera, &mut encoder);
                    gpu.queue.submit([encoder.finish()]);
                    let frame = *direct.context();
                    let inputs = DenoiserInputs {
                        lighting: Lighting::Combined(direct.di.output()),
                        gbuffer: &direct.gbuffer,
                        hit_distance: None,
                        shadow: None,
                        reset: false,
                    };
                    ms += timer
                        .time_span(&gpu, |e| {
                            let encoded = denoiser.encode(&gpu, e, &frame, &inputs)?;
                            assert!(
                                encoded.after.is_empty(),
                                "the fallback records only into wgpu"
                            );
                            Ok(())
                        })
                        .expect("timed denoiser");
                }
                Duration::from_secs_f64(ms * 1e-3)
            })
        });
    }
    group.finish();
}

criterion_group!(benches, fallback);
criterion_main!(benches);
