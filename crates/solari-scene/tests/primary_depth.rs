//! The temporal upscaler's guide (`primary_depth`) against its CPU twin: at 128×96 over a
//! 64×48 traced G-buffer of the Cornell box, each pixel whose four nearest render samples lie
//! on one surface (depths within 1.1× of the nearest's, and all emitting or none) holds
//! exactly the nearest sample's value (its depth, negated where it emits), and every other
//! pixel what the traced G-buffer finds at 128×96 (its own primary ray): the depth within
//! 1e-5 relative, its sign whether the surface emits; on a first frame (every ray unbounded)
//! and on a second whose camera moved (first tries bounded by the first frame's depth). GPU:
//! lavapipe in CI.

use glam::{Mat4, Vec3};
use solari_scene::gbuffer::GBuffer;
use solari_scene::gpu::{Gpu, test_gpu};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::pass::FrameContext;
use solari_scene::primary_depth::PrimaryDepth;
use solari_scene::shaders::Backend;
use solari_scene::*;

const OUTPUT: (u32, u32) = (128, 96);
const RENDER: (u32, u32) = (64, 48);

/// A traced G-buffer of `size` rendered from `camera` (its second frame when `gb` has one):
/// each pixel's guide value, its depth negated where it emits (`gbuffer_read.wesl`'s
/// `guide_value`).
fn render(gpu: &Gpu, gb: &mut GBuffer, gs: &GpuScene, scene: &Scene, camera: &Camera) -> Vec<f32> {
    gb.prepare(gpu, scene, camera).expect("prepare");
    let frame = FrameContext::new(0, gb.size(), camera, None);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    gb.encode(&mut encoder, &frame, gs).expect("encode");
    gpu.queue.submit([encoder.finish()]);
    let texels = gb.current().read(gpu).expect("read back");
    let emits = |e: &[half::f16; 4]| e[..3].iter().any(|c| c.to_f32() > 0.0);
    texels
        .depth
        .iter()
        .zip(&texels.emission)
        .map(|(&d, e)| if emits(e) && d > 0.0 { -d } else { d })
        .collect()
}

/// The shader's test on two guide values (depth, negated where the surface emits): one depth
/// surface, both emitting or neither.
fn same_surface(a: f32, b: f32) -> bool {
    solari_scene::primary_depth::same_surface(a.abs(), a < 0.0, b.abs(), b < 0.0)
}

/// The depths alone of one surface, as before emission counted: a pixel traced only because
/// an emitter's edge crosses its samples.
fn same_depth(a: f32, b: f32) -> bool {
    same_surface(a.abs(), b.abs())
}

#[test]
fn the_guide_copies_one_surface_and_traces_silhouettes() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let camera = scene.camera(None).unwrap();
    let mut moved = camera.clone();
    moved.transform = camera.transform * Mat4::from_translation(Vec3::new(0.3, -0.1, 0.4));
    let gs = GpuScene::new(&gpu, &scene, Backend::Software, &GpuSceneOptions::default())
        .expect("upload");
    let variant = TraceVariant::for_scene(&gs);
    let traced = |size: (u32, u32)| {
        GBuffer::traced(&gpu, Backend::Software, variant, size.0, size.1).expect("G-buffer")
    };
    let (mut full, mut low) = (traced(OUTPUT), traced(RENDER));
    let guide = PrimaryDepth::new(&gpu, Backend::Software, variant, OUTPUT).expect("guide");
    for (frame, camera) in [&camera, &moved].into_iter().enumerate() {
        let want = render(&gpu, &mut full, &gs, &scene, camera);
        let samples = render(&gpu, &mut low, &gs, &scene, camera);
        guide.prepare(&gpu, camera);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let context = FrameContext::new(0, OUTPUT, camera, None);
        guide
            .encode(&mut encoder, &context, &gs, &low)
            .expect("encode");
        gpu.queue.submit([encoder.finish()]);
        let bytes = gpu
            .read_buffer(guide.depth(), guide.depth().size())
            .expect("read back");
        let got: &[f32] = bytemuck::cast_slice(&bytes);
        let at = |x: i32, y: i32| {
            let (x, y) = (
                x.clamp(0, RENDER.0 as i32 - 1),
                y.clamp(0, RENDER.1 as i32 - 1),
            );
            samples[(y * RENDER.0 as i32 + x) as usize]
        };
        let (mut copied, mut own, mut emitter_edges, mut emitting) = (0, 0, 0, 0);
        for y in 0..OUTPUT.1 {
            for x in 0..OUTPUT.0 {
                let i = (y * OUTPUT.0 + x) as usize;
                // Same aspect: the render position is the output's scaled (no jitter).
                let c = [
                    (x as f32 + 0.5) * RENDER.0 as f32 / OUTPUT.0 as f32,
                    (y as f32 + 0.5) * RENDER.1 as f32 / OUTPUT.1 as f32,
                ];
                let nearest = at(c[0].floor() as i32, c[1].floor() as i32);
                let base = [(c[0] - 0.5).floor() as i32, (c[1] - 0.5).floor() as i32];
                let four = (0..4).map(|k| at(base[0] + (k & 1), base[1] + (k >> 1)));
                let one = four.clone().all(|d| same_surface(d, nearest));
                if !one && four.clone().all(|d| same_depth(d, nearest)) {
                    emitter_edges += 1;
                }
                emitting += usize::from(got[i] < 0.0);
                if one {
                    assert_eq!(got[i], nearest, "frame {frame}: pixel ({x}, {y}) copies");
                    copied += 1;
                } else {
                    let close = (got[i] - want[i]).abs() <= 1e-5 * want[i].abs()
                        || (got[i] == 0.0 && want[i] == 0.0);
                    assert!(
                        close,
                        "frame {frame}: pixel ({x}, {y}) traced {} where the G-buffer has {}",
                        got[i], want[i]
                    );
                    own += 1;
                }
            }
        }
        // The box's blocks and walls give silhouettes; most pixels are inside a surface. The
        // ceiling light lies within 1.1× of the ceiling's depth: its edge is traced for its
        // emission alone.
        assert!(
            own > 100 && copied > 4 * own,
            "frame {frame}: {own} traced, {copied} copied"
        );
        assert!(
            emitter_edges > 10 && emitting > 20,
            "frame {frame}: {emitter_edges} traced at the light's edge, {emitting} emitting"
        );
    }
}

/// An empty guide is refused at construction, and a G-buffer larger than the guide (it maps
/// output pixels into the render image, so the render size must not exceed the output's) at
/// encode, each with an error naming the sizes.
#[test]
fn the_guide_refuses_an_empty_size_and_a_larger_gbuffer() {
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let camera = scene.camera(None).unwrap();
    let gs = GpuScene::new(&gpu, &scene, Backend::Software, &GpuSceneOptions::default())
        .expect("upload");
    let variant = TraceVariant::for_scene(&gs);
    let e = PrimaryDepth::new(&gpu, Backend::Software, variant, (0, 8))
        .err()
        .expect("an empty guide")
        .to_string();
    assert!(e.contains("0×8"), "{e}");
    let guide = PrimaryDepth::new(&gpu, Backend::Software, variant, RENDER).expect("guide");
    let mut larger =
        GBuffer::traced(&gpu, Backend::Software, variant, OUTPUT.0, OUTPUT.1).expect("G-buffer");
    render(&gpu, &mut larger, &gs, &scene, &camera);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let context = FrameContext::new(0, RENDER, &camera, None);
    let e = guide
        .encode(&mut encoder, &context, &gs, &larger)
        .expect_err("a larger G-buffer")
        .to_string();
    assert!(e.contains("128×96") && e.contains("64×48"), "{e}");
}
