//! GPU twin test: the temporal upscaler's `render_to_output` and `output_to_render`
//! (`temporal_upscale.wesl`) map positions as `upscale::render_to_output` and
//! `upscale::output_to_render` do, at sizes whose rounded render size changes the aspect.
//! Both call `view.wesl`'s `render_to_output_of` / `output_to_render_of`, which the
//! upscaler's depth guide (`solari_scene::primary_depth`) maps with too.

use solari_denoise::modules;
use solari_denoise::upscale::{GpuUpscaleParams, output_to_render, render_to_output};
use solari_scene::bindings::{Buf, BufferGroup};
use solari_scene::case_kernel::CaseKernel;
use solari_scene::gpu::test_gpu;
use solari_scene::shaders::{Backend, compose};

/// Only the parameters (binding 0 of the pass's group 0): the mapping reads nothing else.
const PARAMS: BufferGroup = BufferGroup::new(0, 0, &[("upscale_params", Buf::Uniform)]);

#[test]
fn gpu_upscale_mapping_matches_the_cpu_twin() {
    let Some(gpu) = test_gpu() else { return };
    let extra: Vec<(&str, &str)> = modules()
        .into_iter()
        .chain([(
            "upscale_map_test",
            include_str!("../shaders/upscale_map_test.wesl"),
        )])
        .collect();
    let wgsl = compose("upscale_map_test", Backend::Software, &extra).expect("compose");
    let layout = PARAMS.layout(&gpu, "test/upscale_params");
    let (empty_layout, empty) = gpu.empty_group();
    let kernel = CaseKernel::new(
        &gpu,
        "upscale_map_test",
        &wgsl,
        &[Some(&layout), Some(&empty_layout), None],
        2,
    )
    .expect("pipeline");
    for (output, scale) in [
        ((960u32, 540u32), 0.67f32),
        ((97, 31), 0.67),
        ((31, 97), 0.5),
        ((1920, 1080), 0.25),
    ] {
        let render = (
            ((output.0 as f32 * scale).ceil() as u32).clamp(1, output.0),
            ((output.1 as f32 * scale).ceil() as u32).clamp(1, output.1),
        );
        let params = GpuUpscaleParams {
            render_size: [render.0, render.1],
            output_size: [output.0, output.1],
            reset: 0,
            max_weight: 16.0,
            guided: 0,
            _pad: 0,
        };
        let buffer = gpu.uniform_buffer("test/upscale_params", &params);
        let group = PARAMS.bind(
            &gpu,
            "test/upscale_params",
            &layout,
            &[("upscale_params", &buffer)],
        );
        let cases: Vec<[f32; 4]> = (0..1000)
            .map(|i| {
                let t = i as f32 / 999.0;
                [
                    t * render.0 as f32,
                    (1.0 - t) * render.1 as f32,
                    (1.0 - t) * output.0 as f32,
                    t * output.1 as f32,
                ]
            })
            .collect();
        let results: Vec<[f32; 4]> = kernel
            .run(&gpu, &[Some(&group), Some(&empty), None], &cases)
            .expect("dispatch");
        for (c, r) in cases.iter().zip(&results) {
            let o = render_to_output([c[0], c[1]], render, output);
            let b = output_to_render([c[2], c[3]], render, output);
            let want = [o[0], o[1], b[0], b[1]];
            for k in 0..4 {
                assert!(
                    (r[k] - want[k]).abs() <= 1e-4 * want[k].abs().max(1.0),
                    "{output:?} at {scale}: case {c:?} gave {r:?}, the twin {want:?}"
                );
            }
        }
    }
}
