//! The persistent-thread ray bench traces exactly the inline one's rays: the same count per
//! pixel (primary only, primary + a hemisphere ray that missed, or one that hit) on every
//! bundled scene, at a size that leaves partial tiles, for every traversal specialisation and
//! both backends.

use solari_scene::gpu::{Gpu, ShaderChecks, test_gpu};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::gpu_types::GpuView;
use solari_scene::shaders::Backend;
use solari_scene::view_pass::{RaySchedule, ViewPass};
use solari_scene::*;

fn counts(
    gpu: &Gpu,
    backend: Backend,
    gs: &GpuScene,
    view: &GpuView,
    variant: TraceVariant,
    schedule: RaySchedule,
) -> Vec<u32> {
    let pass =
        ViewPass::ray_bench_scheduled(gpu, backend, ShaderChecks::All, variant, schedule).unwrap();
    let target = pass.target(gpu, view).unwrap();
    // Twice: the pixel counter must start from zero on every dispatch.
    pass.run(gpu, gs, &target).unwrap();
    bytemuck::cast_slice(&pass.run(gpu, gs, &target).unwrap()).to_vec()
}

#[test]
fn persistent_threads_trace_the_inline_rays() {
    let Some(gpu) = test_gpu() else { return };
    let mut scenes = vec![
        default_scene::cornell_box(),
        textured_scene::textured_spheres(),
    ];
    for path in solari_testdata::all_scenes() {
        scenes.push(load_gltf(path).unwrap());
    }
    // 70×45: partial 8×8 tiles on both axes.
    let (w, h) = (70, 45);
    let schedules = [
        // Fewer threads than pixels, so lanes fetch many times; refill at one idle lane
        // and at more lanes than a subgroup has (only when every lane is idle).
        RaySchedule::Persistent {
            threads: 128,
            refill: 1,
        },
        RaySchedule::Persistent {
            threads: 200,
            refill: 1000,
        },
    ];
    let mut backends = vec![Backend::Software];
    if gpu.has_ray_query() {
        backends.push(Backend::RayQuery);
    }
    let mut hemisphere_hits = 0;
    for scene in &scenes {
        let camera = scene.camera(None).unwrap();
        for (backend, merge) in [
            (Backend::Software, false),
            (Backend::Software, true),
            (Backend::RayQuery, false),
        ] {
            if !backends.contains(&backend) {
                continue;
            }
            let options = GpuSceneOptions {
                max_texture_size: 16,
                merge_instances: merge,
                ..Default::default()
            };
            let gs = GpuScene::new(&gpu, scene, backend, &options).unwrap();
            let mut variants = vec![TraceVariant::General];
            if TraceVariant::for_scene(&gs) != TraceVariant::General {
                variants.push(TraceVariant::for_scene(&gs));
            }
            for variant in variants {
                for mode in [0, 1] {
                    let mut view = GpuView::new(&camera, w, h);
                    view.view_mode = mode;
                    view.frame = 3;
                    let inline = counts(&gpu, backend, &gs, &view, variant, RaySchedule::Inline);
                    assert!(inline.iter().all(|&c| (1..=3).contains(&c)));
                    hemisphere_hits += inline.iter().filter(|&&c| c == 3).count();
                    for schedule in schedules {
                        let persistent = counts(&gpu, backend, &gs, &view, variant, schedule);
                        let differ = inline
                            .iter()
                            .zip(&persistent)
                            .filter(|(a, b)| a != b)
                            .count();
                        assert_eq!(
                            differ,
                            0,
                            "{}: {backend:?}, merged {merge}, {}, mode {mode}, {}: {differ} of {} pixels differ",
                            camera.name,
                            variant.name(),
                            schedule.name(),
                            w * h
                        );
                    }
                }
            }
        }
    }
    // The comparison means something only if hemisphere rays hit and miss.
    assert!(hemisphere_hits > 1000, "{hemisphere_hits}");
}

#[test]
fn the_persistent_schedule_needs_subgroups() {
    let Some(gpu) = test_gpu() else { return };
    let schedule = RaySchedule::Persistent {
        threads: 64,
        refill: 8,
    };
    let err = |gpu: &Gpu| {
        ViewPass::ray_bench_scheduled(
            gpu,
            Backend::Software,
            ShaderChecks::All,
            TraceVariant::General,
            schedule,
        )
        .err()
        .map(|e| e.to_string())
    };
    let without = Gpu::new_without(wgpu::Features::SUBGROUP).unwrap();
    let msg = err(&without).expect("refused without subgroups");
    assert!(msg.contains("subgroup") && msg.contains("inline"), "{msg}");
    assert!(err(&gpu).is_none(), "refused with subgroups");
}
