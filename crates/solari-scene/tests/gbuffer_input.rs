//! `ExternalGBuffer`: a G-buffer drawn by the caller, bound for Solari's passes. Textures of
//! the wrong format, size or usage are refused with an error that names them; history
//! follows what the caller passes; bind groups are reused across alternating texture sets.
//! (GPU: lavapipe in CI. That passes read such a G-buffer exactly as Solari's own is shown
//! by solari-restir's `own_gbuffer` example and solari-denoise's `external_gbuffer` test.)

use solari_scene::gbuffer::{DEPTH_FORMAT, EMISSION_FORMAT, GBUFFER_FORMAT, MOTION_FORMAT};
use solari_scene::gbuffer_input::{ExternalGBuffer, GBufferSource, GBufferViews};
use solari_scene::gpu::{Gpu, test_gpu};
use solari_scene::{Camera, default_scene};

const SIZE: u32 = 16;

fn texture(
    gpu: &Gpu,
    format: wgpu::TextureFormat,
    size: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::TextureView {
    gpu.texture_2d("test target", (size, size), format, usage)
        .create_view(&Default::default())
}

/// One set of targets; `[gbuffer, emission, motion, depth]`.
fn set(gpu: &Gpu) -> [wgpu::TextureView; 4] {
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
    [GBUFFER_FORMAT, EMISSION_FORMAT, MOTION_FORMAT, DEPTH_FORMAT]
        .map(|f| texture(gpu, f, SIZE, usage))
}

fn views(t: &[wgpu::TextureView; 4]) -> GBufferViews<'_> {
    GBufferViews {
        gbuffer: &t[0],
        emission: &t[1],
        motion: &t[2],
        depth: &t[3],
    }
}

fn camera() -> Camera {
    default_scene::cornell_box().camera(None).expect("camera")
}

#[test]
fn wrong_textures_are_refused_by_name_and_nothing_is_bound() {
    let Some(gpu) = test_gpu() else { return };
    let mut g = ExternalGBuffer::new(&gpu, SIZE, SIZE).expect("new");
    let err = g.bind_group().expect_err("nothing bound before prepare");
    assert!(err.to_string().contains("prepare"), "{err}");

    let good = set(&gpu);
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
    let cases: [(usize, wgpu::TextureView, &str); 4] = [
        (
            0,
            texture(&gpu, wgpu::TextureFormat::Rgba8Unorm, SIZE, usage),
            "'gbuffer': format",
        ),
        (
            1,
            texture(&gpu, EMISSION_FORMAT, SIZE * 2, usage),
            "'emission': 32×32, expected 16×16",
        ),
        (
            2,
            texture(
                &gpu,
                MOTION_FORMAT,
                SIZE,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            ),
            "'motion': no TEXTURE_BINDING",
        ),
        (
            3,
            texture(&gpu, wgpu::TextureFormat::Depth24Plus, SIZE, usage),
            "'depth': format",
        ),
    ];
    for (slot, bad, expected) in cases {
        let mut textures = good.clone();
        textures[slot] = bad;
        let err = g
            .prepare(&gpu, &camera(), views(&textures), None)
            .expect_err("a wrong texture was bound");
        assert!(
            err.to_string().contains(expected),
            "{err} (expected '{expected}')"
        );
        assert!(err.to_string().contains("this frame's"), "{err}");
        // As last frame's texture too.
        let err = g
            .prepare(&gpu, &camera(), views(&good), Some(views(&textures)))
            .expect_err("a wrong previous texture was bound");
        assert!(err.to_string().contains("last frame's"), "{err}");
        assert!(g.bind_group().is_err(), "a refused frame bound nothing");
    }
    assert!(ExternalGBuffer::new(&gpu, 0, SIZE).is_err(), "empty size");
    let limit = gpu.device.limits().max_texture_dimension_2d;
    assert!(
        ExternalGBuffer::new(&gpu, limit + 1, SIZE).is_err(),
        "over the limit"
    );
    assert!(
        gpu.check_errors().is_ok(),
        "no wgpu validation error escaped"
    );
}

#[test]
fn history_follows_the_frames_given_and_groups_are_reused() {
    let Some(gpu) = test_gpu() else { return };
    let mut g = ExternalGBuffer::new(&gpu, SIZE, SIZE).expect("new");
    let (a, b) = (set(&gpu), set(&gpu));
    let cam = camera();
    // A previous frame on the very first call is not history: there is no last camera.
    g.prepare(&gpu, &cam, views(&a), Some(views(&b)))
        .expect("frame 0");
    assert!(!g.history_valid());
    assert!(g.camera_moved(), "no history: nothing to be still against");
    let first = g.bind_group().expect("bound").clone();
    g.prepare(&gpu, &cam, views(&b), Some(views(&a)))
        .expect("frame 1");
    assert!(g.history_valid());
    assert!(!g.camera_moved(), "the same camera");
    let second = g.bind_group().expect("bound").clone();
    assert_ne!(first, second, "another texture set, another group");
    g.prepare(&gpu, &cam, views(&a), Some(views(&b)))
        .expect("frame 2");
    assert_eq!(
        *g.bind_group().expect("bound"),
        first,
        "alternating sets reuse their groups"
    );
    g.prepare(&gpu, &cam, views(&b), None).expect("a cut");
    assert!(!g.history_valid(), "no previous frame given");
    assert!(g.camera_moved());
    g.prepare(&gpu, &cam, views(&a), Some(views(&b)))
        .expect("after the cut");
    assert!(g.history_valid());
    assert!(!g.camera_moved());
    let mut turned = cam.clone();
    turned.transform = cam.transform * glam::Mat4::from_rotation_y(1e-3);
    g.prepare(&gpu, &turned, views(&b), Some(views(&a)))
        .expect("turned");
    assert!(g.camera_moved(), "a turn is a move");
    g.prepare(&gpu, &cam, views(&a), Some(views(&b)))
        .expect("turned back");
    g.reset();
    assert!(!g.history_valid());
    g.prepare(&gpu, &cam, views(&b), Some(views(&a)))
        .expect("after a reset");
    assert!(!g.history_valid(), "a reset drops the last camera");
    assert!(g.camera_moved());
    assert_eq!(g.size(), (SIZE, SIZE));
    assert!(gpu.check_errors().is_ok());
}

#[test]
fn reader_binding_names_match_the_wgsl() {
    let source = solari_scene::shaders::MODULES
        .iter()
        .find(|(name, _)| *name == "gbuffer_read")
        .expect("gbuffer_read module")
        .1;
    let declared: Vec<(u32, String)> = source
        .lines()
        .filter_map(|line| {
            let rest = line.trim().strip_prefix("@group(1) @binding(")?;
            let (binding, rest) = rest.split_once(')')?;
            let name = rest.trim().strip_prefix("var")?;
            // `var<uniform> name: T` or `var name: texture_2d<u32>`.
            let name = match name.strip_prefix('<') {
                Some(rest) => rest.split_once('>')?.1,
                None => name,
            };
            let name = name.trim().split(':').next()?.trim().to_string();
            Some((binding.parse().ok()?, name))
        })
        .collect();
    let expected: Vec<(u32, String)> = solari_scene::gbuffer_input::READER_BINDINGS
        .iter()
        .zip(0..)
        .map(|(n, b)| (b, n.to_string()))
        .collect();
    assert_eq!(declared, expected);
}
