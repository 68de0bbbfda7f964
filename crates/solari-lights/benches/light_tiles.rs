//! Light-tile filling's GPU time per scene (Solari's default 128 tiles × 1024 samples), from
//! encoder timestamps around the pass ([`PassTimer::time_span`]); throughput in samples. Three
//! cases per scene: the pass alone (`<scene>/<n>_lights`, a wait after each repetition, so the
//! mostly idle GPU lowers its clock); right after the traced G-buffer in the same command
//! buffer (`.../after_gbuffer`, 1920×1080); and G-buffer + tiles frames submitted back to back
//! (`.../in_flight`, [`FrameSpanTimer`]). The last two read within 1% of each other and within
//! 9% of the pass's cost inside the real frame, which `cargo bench -p solari-renderer --bench
//! frame` times (benches/RESULTS.md, "Criterion benches against the CLI").
//!
//! `cargo bench -p solari-lights --bench light_tiles`: the bundled scenes and every scene in
//! `../shared/scenes` when it is there. Under `cargo test` (CI, lavapipe) each case runs
//! once with 4 tiles of 256 samples: the bench must run, not be timed.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use solari_lights::{GpuLights, LightList, LightTileSettings, LightTiles, Selection};
use solari_scene::gbuffer::GBuffer;
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::gpu_timer::{FrameSpanTimer, PassTimer, full_bench};
use solari_scene::pass::FrameContext;
use std::time::Duration;

fn light_tiles(c: &mut Criterion) {
    let full = full_bench();
    let settings = if full {
        LightTileSettings::default()
    } else {
        LightTileSettings {
            tiles: 4,
            samples_per_tile: 256,
            ..Default::default()
        }
    };
    let gpu = Gpu::new().expect("a GPU adapter");
    let timer = PassTimer::new(&gpu).unwrap_or_else(|e| panic!("{e}"));
    let frames = FrameSpanTimer::new(&gpu, 16).unwrap_or_else(|e| panic!("{e}"));
    let mut group = c.benchmark_group("light_tiles");
    group.sample_size(20);
    group.throughput(Throughput::Elements(settings.sample_count()));
    for (name, path) in solari_testdata::bench_scenes(full) {
        let scene = solari_scene::load_gltf(&path).expect("scene loads");
        let list = LightList::build(&scene);
        if list.is_empty() {
            continue;
        }
        let lights = GpuLights::new(&gpu, &list, Selection::Power).expect("lights");
        // Specialised for the scene's lights as `RealtimeRenderer` builds them, so the bench
        // times the pass the frame runs.
        let specialised = LightTileSettings {
            point_lights: list.has_point_lights(),
            environment: list.environment.is_some(),
            ..settings
        };
        let tiles = LightTiles::new(&gpu, specialised).expect("tiles");
        let camera = scene.camera(None).expect("camera");
        group.bench_function(format!("{name}/{}_lights", list.len()), |b| {
            b.iter_custom(|iters| {
                let mut ms = 0.0;
                for frame in 0..iters {
                    let context = FrameContext::new(frame as u32, (64, 64), &camera, None);
                    tiles.prepare(&gpu, &context);
                    ms += timer
                        .time_span(&gpu, |e| {
                            tiles.encode(e, &context, &lights);
                            Ok(())
                        })
                        .expect("timed tiles");
                }
                Duration::from_secs_f64(ms * 1e-3)
            })
        });
        // In the frame's context: after the G-buffer, recorded untimed just before.
        let size = if full { (1920, 1080) } else { (64, 64) };
        let backend = gpu.backend(Default::default()).expect("backend");
        let gpu_scene =
            GpuScene::new(&gpu, &scene, backend, &GpuSceneOptions::default()).expect("upload");
        let variant = TraceVariant::for_scene(&gpu_scene);
        let mut gbuffer =
            GBuffer::traced(&gpu, backend, variant, size.0, size.1).expect("G-buffer");
        group.bench_function(format!("{name}/{}_lights/after_gbuffer", list.len()), |b| {
            b.iter_custom(|iters| {
                let mut ms = 0.0;
                for frame in 0..iters {
                    let context = FrameContext::new(frame as u32, size, &camera, None);
                    tiles.prepare(&gpu, &context);
                    gbuffer.prepare(&gpu, &scene, &camera).expect("prepare");
                    ms += timer
                        .time_span_after(
                            &gpu,
                            |e| gbuffer.encode(e, &context, &gpu_scene).map(drop),
                            |e| {
                                tiles.encode(e, &context, &lights);
                                Ok(())
                            },
                        )
                        .expect("timed tiles");
                }
                Duration::from_secs_f64(ms * 1e-3)
            })
        });
        // As the frame loop runs it: G-buffer then tiles, frames submitted back to back
        // (no wait between them), each frame's tiles span read after the batch.
        group.bench_function(format!("{name}/{}_lights/in_flight", list.len()), |b| {
            b.iter_custom(|iters| {
                let mut ms = 0.0;
                let mut done = 0u64;
                while done < iters {
                    let batch = (iters - done).min(u64::from(frames.capacity())) as u32;
                    let spans = frames
                        .time(
                            &gpu,
                            batch,
                            |i, e| {
                                let context =
                                    FrameContext::new(done as u32 + i, size, &camera, None);
                                tiles.prepare(&gpu, &context);
                                gbuffer.prepare(&gpu, &scene, &camera)?;
                                gbuffer.encode(e, &context, &gpu_scene).map(drop)
                            },
                            |i, e| {
                                let context =
                                    FrameContext::new(done as u32 + i, size, &camera, None);
                                tiles.encode(e, &context, &lights);
                                Ok(())
                            },
                        )
                        .expect("timed tiles");
                    ms += spans.iter().sum::<f64>();
                    done += u64::from(batch);
                }
                Duration::from_secs_f64(ms * 1e-3)
            })
        });
    }
    group.finish();
}

criterion_group!(benches, light_tiles);
criterion_main!(benches);
