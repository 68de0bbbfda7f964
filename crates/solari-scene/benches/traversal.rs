//! Ray traversal throughput (rays/s) per scene, backend and ray kind, GPU time from timestamp
//! queries ([`PassTimer`], the same measurement as `solari bench-rays`).
//!
//! `cargo bench -p solari-scene --bench traversal`: 1920×1080, the bundled scenes and every
//! scene in `../shared/scenes` when it is there. Under `cargo test` (CI, lavapipe) criterion
//! runs each case once at 64×64: the bench must run, not be timed.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use solari_scene::gpu::{Gpu, ShaderChecks};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::gpu_timer::{PassTimer, full_bench};
use solari_scene::gpu_types::GpuView;
use solari_scene::shaders::Backend;
use solari_scene::view_pass::ViewPass;
use std::time::Duration;

fn traversal(c: &mut Criterion) {
    let full = full_bench();
    let (w, h) = if full { (1920, 1080) } else { (64, 64) };
    let gpu = Gpu::new().expect("a GPU adapter");
    let timer = match PassTimer::new(&gpu) {
        Ok(t) => t,
        Err(e) => panic!("{e}"),
    };
    let mut group = c.benchmark_group("traversal");
    group.sample_size(20);
    for (name, path) in solari_testdata::bench_scenes(full) {
        let scene = solari_scene::load_gltf(&path).expect("scene loads");
        let camera = scene.camera(None).expect("camera");
        let mut backends = vec![Backend::Software];
        if gpu.has_ray_query() {
            backends.push(Backend::RayQuery);
        }
        for backend in backends {
            let gs =
                GpuScene::new(&gpu, &scene, backend, &GpuSceneOptions::default()).expect("upload");
            let variant = TraceVariant::for_scene(&gs);
            let pass = ViewPass::ray_bench(&gpu, backend, ShaderChecks::BoundsOnly, variant)
                .expect("pipeline");
            // view_mode 0: primary rays; 1: primary plus one hemisphere ray per hit.
            for (kind, mode) in [("primary", 0), ("primary+hemi", 1)] {
                let mut view = GpuView::new(&camera, w, h);
                view.view_mode = mode;
                let target = pass.target(&gpu, &view).expect("target");
                let rays = ViewPass::bench_ray_count(&pass.run(&gpu, &gs, &target).expect("run"));
                group.throughput(Throughput::Elements(rays));
                let id = format!("{name}/{}/{kind}", backend.name());
                group.bench_function(id, |b| {
                    b.iter_custom(|iters| {
                        let mut ms = 0.0;
                        for i in 0..iters {
                            let mut v = view;
                            v.frame = i as u32;
                            gpu.queue
                                .write_buffer(&target.uniform, 0, bytemuck::bytes_of(&v));
                            ms += timer
                                .time(&gpu, |e, ts| pass.encode(e, &gs, &target, Some(ts)))
                                .expect("timed pass");
                        }
                        Duration::from_secs_f64(ms * 1e-3)
                    })
                });
            }
        }
    }
    group.finish();
}

criterion_group!(benches, traversal);
criterion_main!(benches);
