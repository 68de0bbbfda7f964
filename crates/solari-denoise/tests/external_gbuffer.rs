//! The fallback denoiser and the temporal upscaler on a G-buffer the caller drew (bound by
//! `ExternalGBuffer`) give exactly what they give on Solari's own G-buffer: here the caller's
//! textures are copies of Solari's, alternated between two sets as an engine would, under a
//! moving, jittered camera so that history, reprojection and jitter take part (GPU: lavapipe
//! in CI).

use glam::Vec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_denoise::{
    Denoiser, DenoiserInputs, FallbackDenoiser, FallbackSettings, Lighting, TemporalUpscaler,
    UpscaleSettings,
};
use solari_scene::gbuffer::{DEPTH_FORMAT, EMISSION_FORMAT, GBUFFER_FORMAT, MOTION_FORMAT};
use solari_scene::gbuffer_input::{ExternalGBuffer, GBufferViews};
use solari_scene::gpu::Gpu;
use solari_scene::gpu_types::halton_jitter;
use solari_scene::pass::FrameContext;

mod common;

use common::{Harness, SIZE, grey_box};

/// One set of the caller's targets: `[gbuffer, emission, motion, depth]` textures.
fn targets(gpu: &Gpu) -> [wgpu::Texture; 4] {
    [GBUFFER_FORMAT, EMISSION_FORMAT, MOTION_FORMAT, DEPTH_FORMAT].map(|format| {
        let usage = wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::TEXTURE_BINDING;
        gpu.texture_2d("caller's target", (SIZE, SIZE), format, usage)
    })
}

#[test]
fn the_fallback_denoiser_and_upscaler_read_an_external_gbuffer_exactly_as_their_own() {
    let Some(mut h) = Harness::new() else { return };
    let settings = FallbackSettings::default();
    let mut own = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
    let mut external_denoiser =
        FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
    let mut external = ExternalGBuffer::new(&h.gpu, SIZE, SIZE).expect("external");
    // Upscaling to twice the size, on each G-buffer.
    let upscaler = || {
        TemporalUpscaler::new(
            &h.gpu,
            (SIZE, SIZE),
            (2 * SIZE, 2 * SIZE),
            UpscaleSettings::default(),
        )
        .expect("upscaler")
    };
    let (mut own_upscaler, mut external_upscaler) = (upscaler(), upscaler());
    // One upscaler keeps its work buffer, the other writes into shared scratch (refused when
    // too small): the images must not differ either way, and the shared one holds 16 bytes
    // per output pixel less.
    let outputs = (4 * SIZE * SIZE) as u64;
    let small = solari_scene::scratch::allocate(&h.gpu, 16 * outputs - 16).expect("scratch");
    let e = external_upscaler
        .use_scratch(&h.gpu, &small)
        .expect_err("too small")
        .to_string();
    assert!(e.contains(&(16 * outputs).to_string()), "{e}");
    let scratch = solari_scene::scratch::allocate(&h.gpu, 16 * outputs).expect("scratch");
    external_upscaler
        .use_scratch(&h.gpu, &scratch)
        .expect("scratch taken");
    assert_eq!(
        own_upscaler.memory_bytes() - external_upscaler.memory_bytes(),
        16 * outputs
    );
    let sets = [targets(&h.gpu), targets(&h.gpu)];
    let views: Vec<Vec<wgpu::TextureView>> = sets
        .iter()
        .map(|s| {
            s.iter()
                .map(|t| t.create_view(&Default::default()))
                .collect()
        })
        .collect();
    let bind = |i: usize| GBufferViews {
        gbuffer: &views[i][0],
        emission: &views[i][1],
        motion: &views[i][2],
        depth: &views[i][3],
    };
    let base_camera = grey_box().camera(None).expect("camera");
    let mut rng = Pcg32::seed_from_u64(3);
    let n = (SIZE * SIZE) as usize;
    let bytes = (n * 16) as u64;
    let mut compared = 0;
    for frame in 0..8usize {
        h.camera_offset = Vec3::new(0.02 * frame as f32, 0.0, 0.0);
        h.jitter = halton_jitter(frame as u32);
        let input: Vec<[f32; 4]> = (0..n)
            .map(|_| {
                let v = 0.5 + rng.random::<f32>();
                [v, v * 0.8, v * 0.6, 1.0]
            })
            .collect();
        h.write_lighting(&input);
        let mut encoder = h.gbuffer_encoder();
        // The caller's copy of this frame's G-buffer, in the set of this frame's parity.
        let now = frame % 2;
        let solari = h.gbuffer().current();
        for (from, to) in [
            &solari.gbuffer,
            &solari.emission,
            &solari.motion,
            &solari.depth,
        ]
        .into_iter()
        .zip(&sets[now])
        {
            encoder.copy_texture_to_texture(from.as_image_copy(), to.as_image_copy(), from.size());
        }
        let mut camera = base_camera.clone();
        camera.transform = glam::Mat4::from_translation(h.camera_offset) * camera.transform;
        let previous = (frame > 0).then(|| bind(1 - now));
        external
            .prepare_jittered(&h.gpu, &camera, bind(now), previous, h.jitter)
            .expect("bind the caller's G-buffer");
        let mut after = Vec::new();
        let lighting = Lighting::Combined(h.write_lighting(&input));
        for (denoiser, gbuffer) in [
            (
                &mut own,
                h.gbuffer() as &dyn solari_scene::gbuffer_input::GBufferSource,
            ),
            (&mut external_denoiser, &external),
        ] {
            let inputs = DenoiserInputs {
                lighting,
                gbuffer,
                hit_distance: None,
                shadow: None,
                reset: false,
            };
            let context = FrameContext::new(frame as u32, (SIZE, SIZE), &camera, None);
            let encoded = denoiser.encode(&h.gpu, &mut encoder, &context, &inputs);
            after.extend(encoded.expect("encode").after);
        }
        let context = FrameContext::new(frame as u32, (SIZE, SIZE), &camera, None);
        for (upscaler, gbuffer, denoised) in [
            (
                &mut own_upscaler,
                h.gbuffer() as &dyn solari_scene::gbuffer_input::GBufferSource,
                own.output(),
            ),
            (
                &mut external_upscaler,
                &external,
                external_denoiser.output(),
            ),
        ] {
            upscaler
                .encode(
                    &h.gpu,
                    &mut encoder,
                    &context,
                    gbuffer,
                    denoised,
                    None,
                    false,
                )
                .expect("upscale");
        }
        h.gpu
            .queue
            .submit(std::iter::once(encoder.finish()).chain(after));
        let a = h.gpu.read_buffer(own.output(), bytes).expect("read");
        let b = h
            .gpu
            .read_buffer(external_denoiser.output(), bytes)
            .expect("read");
        let (a, b): (&[[f32; 4]], &[[f32; 4]]) =
            (bytemuck::cast_slice(&a), bytemuck::cast_slice(&b));
        assert!(
            a.iter().any(|p| p[3] > 0.0),
            "frame {frame}: the box was drawn"
        );
        let differing = a.iter().zip(b).filter(|(p, q)| p != q).count();
        assert_eq!(differing, 0, "frame {frame}: {differing} pixels differ");
        let up = 4 * bytes;
        let a = h.gpu.read_buffer(own_upscaler.output(), up).expect("read");
        let b = h
            .gpu
            .read_buffer(external_upscaler.output(), up)
            .expect("read");
        assert_eq!(a, b, "frame {frame}: the upscaled images differ");
        compared += n;
    }
    assert!(h.gpu.check_errors().is_ok());
    println!("{compared} pixels over 8 frames identical on both G-buffers");
}

/// A depth guide smaller than the upscaler's output (one `f32` per output pixel) is refused
/// with an error that names its size, and nothing is recorded.
#[test]
fn the_upscaler_refuses_a_guide_smaller_than_its_output() {
    let Some(mut h) = Harness::new() else { return };
    let mut upscaler = TemporalUpscaler::new(
        &h.gpu,
        (SIZE, SIZE),
        (2 * SIZE, 2 * SIZE),
        UpscaleSettings::default(),
    )
    .expect("upscaler");
    let outputs = (4 * SIZE * SIZE) as u64;
    let guide = solari_scene::scratch::allocate(&h.gpu, 4 * outputs - 4).expect("buffer");
    let mut encoder = h.gbuffer_encoder();
    let camera = grey_box().camera(None).expect("camera");
    let frame = FrameContext::new(0, (SIZE, SIZE), &camera, None);
    let lighting = h.lighting().clone();
    let e = upscaler
        .encode(
            &h.gpu,
            &mut encoder,
            &frame,
            h.gbuffer(),
            &lighting,
            Some(&guide),
            false,
        )
        .expect_err("a short guide")
        .to_string();
    assert!(e.contains(&(4 * outputs - 4).to_string()), "{e}");
}
