//! ReSTIR DI's GPU time per frame (both dispatches: initial + temporal, spatial + shade) per
//! scene, from encoder timestamps around them ([`PassTimer::time_span`]); throughput in
//! pixels. The G-buffer and light tiles it reads are recorded untimed before each timed span.
//!
//! `cargo bench -p solari-restir --bench restir_di`: 1920×1080, Solari's default settings
//! (128 tiles × 1024 samples, spatial radius 30), the bundled scenes and every scene in
//! `../shared/scenes` when it is there. Under `cargo test` (CI, lavapipe) each case runs
//! once at 64×64: the bench must run, not be timed.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use solari_lights::LightTileSettings;
use solari_restir::RestirDiSettings;
use solari_scene::gpu::Gpu;
use solari_scene::gpu_timer::{PassTimer, full_bench};
use std::time::Duration;

#[path = "../tests/common/mod.rs"]
mod common;

use common::DirectLight;

fn restir_di(c: &mut Criterion) {
    let full = full_bench();
    let (w, h) = if full { (1920, 1080) } else { (64, 64) };
    let gpu = Gpu::new().expect("a GPU adapter");
    let timer = PassTimer::new(&gpu).unwrap_or_else(|e| panic!("{e}"));
    let backend = gpu.backend(Default::default()).expect("backend");
    let mut group = c.benchmark_group("restir_di");
    group.sample_size(20);
    group.throughput(Throughput::Elements(w as u64 * h as u64));
    for (name, path) in solari_testdata::bench_scenes(full) {
        let scene = solari_scene::load_gltf(&path).expect("scene loads");
        let camera = scene.camera(None).expect("camera");
        // The harness renders square images; the bench's are 16:9.
        let mut direct = DirectLight::new_sized(
            &gpu,
            backend,
            &scene,
            (w, h),
            RestirDiSettings::default(),
            LightTileSettings::default(),
        );
        group.bench_function(format!("{name}/{}", backend.name()), |b| {
            b.iter_custom(|iters| {
                let mut ms = 0.0;
                for _ in 0..iters {
                    direct.prepare(&gpu, &scene, &camera);
                    let mut encoder = gpu.device.create_command_encoder(&Default::default());
                    direct.encode_inputs(&mut encoder);
                    gpu.queue.submit([encoder.finish()]);
                    ms += timer
                        .time_span(&gpu, |e| {
                            direct.encode_di(e);
                            Ok(())
                        })
                        .expect("timed DI");
                }
                Duration::from_secs_f64(ms * 1e-3)
            })
        });
    }
    group.finish();
}

criterion_group!(benches, restir_di);
criterion_main!(benches);
