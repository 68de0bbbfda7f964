//! The renderer draws its output into the caller's texture: tone-mapped 8-bit targets match
//! the PNG tone curve (`solari_reference::image_io::tone_map`) within one step, float targets
//! hold the linear radiance, and wrong targets are refused with a message (GPU: lavapipe).

mod common;

use common::{SIZE, settings, upload};
use solari_reference::image_io::tone_map;
use solari_renderer::RealtimeRenderer;
use solari_scene::default_scene;
use solari_scene::gpu::{Gpu, test_gpu};

fn target(
    gpu: &Gpu,
    format: wgpu::TextureFormat,
    size: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    gpu.texture_2d("caller's target", (size, size), format, usage)
}

#[test]
fn present_writes_the_frame_into_the_callers_texture() {
    let Some(gpu) = test_gpu() else { return };
    let backend = gpu.backend(Default::default()).expect("backend");
    let scene = default_scene::cornell_box();
    let gpu_scene = upload(&gpu, backend, &scene);
    let mut renderer =
        RealtimeRenderer::new(&gpu, backend, &scene, &gpu_scene, SIZE, SIZE, settings())
            .expect("renderer");
    let camera = scene.camera(None).expect("camera");
    for _ in 0..4 {
        renderer
            .render(&gpu, &scene, &gpu_scene, &camera)
            .expect("frame");
    }
    let linear = renderer.read_output(&gpu).expect("output");
    let rgb: Vec<[f32; 3]> = linear.iter().map(|p| [p[0], p[1], p[2]]).collect();
    let exposure = 1.0;
    let expected = tone_map(&rgb, exposure);
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;

    // 8-bit targets: the shader's sRGB and the hardware's agree with the CPU curve.
    for format in [
        wgpu::TextureFormat::Rgba8Unorm,
        wgpu::TextureFormat::Rgba8UnormSrgb,
    ] {
        let texture = target(&gpu, format, SIZE, usage);
        let view = texture.create_view(&Default::default());
        renderer.present(&gpu, &view, exposure).expect("present");
        let bytes = gpu
            .read_texture(&texture, wgpu::TextureAspect::All)
            .expect("read");
        let mut worst = 0;
        for (i, px) in bytes.chunks_exact(4).enumerate() {
            for c in 0..3 {
                worst = worst.max((px[c] as i32 - expected[i * 3 + c] as i32).abs());
            }
        }
        println!("{format:?}: largest difference from the PNG curve {worst}/255");
        assert!(worst <= 1, "{format:?}: off by {worst}/255");
    }

    // A float target: linear radiance × 2^exposure (f32: exact up to rounding).
    let texture = target(&gpu, wgpu::TextureFormat::Rgba32Float, SIZE, usage);
    let view = texture.create_view(&Default::default());
    renderer.present(&gpu, &view, exposure).expect("present");
    let bytes = gpu
        .read_texture(&texture, wgpu::TextureAspect::All)
        .expect("read");
    let got: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
    for (g, want) in got.iter().zip(&linear) {
        for c in 0..3 {
            let w = want[c] * 2.0;
            assert!(
                (g[c] - w).abs() <= 1e-6 * w.abs().max(1.0),
                "{g:?} vs {want:?}"
            );
        }
    }

    // Refusals name the problem and leave no wgpu error behind.
    let cases = [
        (
            target(&gpu, wgpu::TextureFormat::Rgba8Unorm, SIZE * 2, usage),
            "target is 128×128",
        ),
        (
            target(
                &gpu,
                wgpu::TextureFormat::Rgba8Unorm,
                SIZE,
                wgpu::TextureUsages::TEXTURE_BINDING,
            ),
            "RENDER_ATTACHMENT",
        ),
        (
            target(&gpu, wgpu::TextureFormat::R32Uint, SIZE, usage),
            "cannot write",
        ),
    ];
    for (texture, expected) in cases {
        let view = texture.create_view(&Default::default());
        let err = renderer
            .present(&gpu, &view, 0.0)
            .expect_err("a wrong target was drawn");
        assert!(err.to_string().contains(expected), "{err}");
    }
    let view =
        target(&gpu, wgpu::TextureFormat::Rgba8Unorm, SIZE, usage).create_view(&Default::default());
    assert!(
        renderer.present(&gpu, &view, f32::NAN).is_err(),
        "NaN exposure"
    );
    gpu.check_errors().expect("no wgpu error escaped");
}

#[test]
fn present_bindings_are_bound_by_their_wgsl_names() {
    use solari_renderer::present::{PRESENT_BINDINGS, PRESENT_WGSL};
    let module = solari_scene::shaders::validate("present", PRESENT_WGSL).expect("valid WGSL");
    assert_eq!(PRESENT_BINDINGS.check_wgsl(&module), Ok(2));
}
