//! The world cache's GPU time per frame (upkeep: decay, compaction, sample tracing and
//! blending; then cache GI over the image) per scene, from encoder timestamps around it
//! ([`PassTimer::time_span`]); throughput in pixels. The G-buffer, light tiles and ReSTIR DI
//! it reads are recorded untimed before each timed span.
//!
//! `cargo bench -p solari-worldcache --bench world_cache`: 1920×1080, default settings, the
//! bundled scenes and every scene in `../shared/scenes` when it is there. Under `cargo test`
//! (CI, lavapipe) each case runs once at 64×64: the bench must run, not be timed.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use solari_lights::LightTileSettings;
use solari_restir::RestirDiSettings;
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::TraceVariant;
use solari_scene::gpu_timer::{PassTimer, full_bench};
use solari_worldcache::{WorldCache, WorldCacheSettings};
use std::time::Duration;

#[path = "../../solari-restir/tests/common/mod.rs"]
mod direct;

use direct::DirectLight;

fn world_cache(c: &mut Criterion) {
    let full = full_bench();
    let (w, h) = if full { (1920, 1080) } else { (64, 64) };
    let gpu = Gpu::new().expect("a GPU adapter");
    let timer = PassTimer::new(&gpu).unwrap_or_else(|e| panic!("{e}"));
    let backend = gpu.backend(Default::default()).expect("backend");
    let mut group = c.benchmark_group("world_cache");
    group.sample_size(20);
    group.throughput(Throughput::Elements(w as u64 * h as u64));
    for (name, path) in solari_testdata::bench_scenes(full) {
        let scene = solari_scene::load_gltf(&path).expect("scene loads");
        let camera = scene.camera(None).expect("camera");
        let tiles = LightTileSettings::default();
        let di = RestirDiSettings::default();
        let mut direct = DirectLight::new_sized(&gpu, backend, &scene, (w, h), di, tiles);
        let variant = TraceVariant::for_scene(&direct.gpu_scene);
        let settings = WorldCacheSettings::default();
        let mut cache = WorldCache::new(&gpu, backend, variant, settings, tiles).expect("cache");
        let target = cache.target_group(&gpu, direct.di.output());
        group.bench_function(format!("{name}/{}", backend.name()), |b| {
            b.iter_custom(|iters| {
                let mut ms = 0.0;
                for _ in 0..iters {
                    direct.prepare(&gpu, &scene, &camera);
                    let context = *direct.context();
                    cache.prepare(&gpu, &context, direct.lights.light_count);
                    let mut encoder = gpu.device.create_command_encoder(&Default::default());
                    direct.encode_inputs(&mut encoder);
                    direct.encode_di(&mut encoder);
                    gpu.queue.submit([encoder.finish()]);
                    ms += timer
                        .time_span(&gpu, |e| {
                            cache.encode(e, &context, &direct.gpu_scene, &direct.lights_group)?;
                            cache.encode_gi(e, &context, &direct.gbuffer, &target)?;
                            Ok(())
                        })
                        .expect("timed cache");
                }
                Duration::from_secs_f64(ms * 1e-3)
            })
        });
    }
    group.finish();
}

criterion_group!(benches, world_cache);
criterion_main!(benches);
