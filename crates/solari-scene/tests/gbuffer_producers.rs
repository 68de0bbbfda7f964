//! The two G-buffer producers, raster and traced, write the same targets. On the Cornell box,
//! a textured scene, and a second frame after an instance and the camera moved, at least
//! 99.5% of the pixels that either covers agree: both cover it, with geometric normals within
//! 1e-3, depth within 1e-5 relative and motion within f16 precision, and on untextured
//! scenes the same material words, shading normals and emission too (GPU: lavapipe in CI).
//! The rest are pixel centres on shared edges, which the rasteriser and the ray tracer may
//! give to different triangles. Textured values differ by filtering: the rasteriser's
//! footprint comes from 2×2 quad differences, the traced one's from ray differentials; the
//! albedo is compared as a mean here and by FLIP in `gbuffer_lod.rs`.

use glam::{Mat4, Vec3};
use half::f16;
use solari_scene::gbuffer::{GBuffer, GBufferProducer, GBufferTargets, GBufferTexels as Texels};
use solari_scene::gpu::{Gpu, test_gpu};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::packing::unpack_unit_vector;
use solari_scene::pass::FrameContext;
use solari_scene::shaders::Backend;
use solari_scene::*;

const SIZE: (u32, u32) = (128, 96);

/// One frame's targets, read back.
fn read(gpu: &Gpu, t: &GBufferTargets) -> Texels {
    t.read(gpu).expect("read back")
}

/// Whether two f16 values are at most one step of f16 apart.
fn f16_close(a: f16, b: f16) -> bool {
    let (a, b) = (a.to_f32(), b.to_f32());
    (a - b).abs() <= a.abs().max(b.abs()) * 2f32.powi(-10) + 1e-7
}

/// Why pixel `i` differs, or `None` when the producers agree on it; `textured`: texture-read
/// values (material words, shading normal, emission) are left out.
fn disagreement(r: &Texels, t: &Texels, i: usize, textured: bool) -> Option<&'static str> {
    let (cover_r, cover_t) = (r.depth[i] > 0.0, t.depth[i] > 0.0);
    if cover_r != cover_t {
        return Some("coverage");
    }
    let (a, b) = (r.gbuffer[i], t.gbuffer[i]);
    if !textured && (a[0] != b[0] || a[1] != b[1]) {
        return Some("material");
    }
    let words: &[usize] = if textured { &[3] } else { &[2, 3] };
    for &word in words {
        let (na, nb) = (
            unpack_unit_vector(a[word], 16),
            unpack_unit_vector(b[word], 16),
        );
        if (na - nb).abs().max_element() > 1e-3 {
            return Some("normal");
        }
    }
    if (r.depth[i] - t.depth[i]).abs() > 1e-5 * r.depth[i] {
        return Some("depth");
    }
    let emission = (0..4).all(|c| f16_close(r.emission[i][c], t.emission[i][c]));
    let motion = (0..2).all(|c| f16_close(r.motion[i][c], t.motion[i][c]));
    if !emission && !textured {
        return Some("emission");
    }
    if !motion {
        return Some("motion");
    }
    None
}

fn gbuffer(gpu: &Gpu, producer: GBufferProducer, variant: TraceVariant) -> GBuffer {
    GBuffer::with_producer(gpu, Backend::Software, producer, variant, SIZE.0, SIZE.1)
        .expect("G-buffer")
}

fn render(gpu: &Gpu, gb: &mut GBuffer, gs: &GpuScene, scene: &Scene, camera: &Camera) {
    gb.prepare(gpu, scene, camera).expect("prepare");
    let frame = FrameContext::new(0, gb.size(), camera, None);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    gb.encode(&mut encoder, &frame, gs).expect("encode");
    gpu.queue.submit([encoder.finish()]);
}

/// Base colour from a G-buffer texel (`pack_gbuffer`: √colour in unorm8).
fn base_color(texel: [u32; 4]) -> Vec3 {
    let c = |i: u32| ((texel[0] >> (8 * i)) & 0xff) as f32 / 255.0;
    Vec3::new(c(0), c(1), c(2)).powf(2.0)
}

/// Renders `frames` (scene, camera) pairs with both producers and compares the last frame.
fn compare(gpu: &Gpu, name: &str, frames: &[(Scene, Camera)]) {
    let textured = !frames[0].0.textures.is_empty();
    let options = GpuSceneOptions {
        max_texture_size: 64,
        ..Default::default()
    };
    let mut gs = GpuScene::new(gpu, &frames[0].0, Backend::Software, &options).expect("upload");
    let mut raster = gbuffer(gpu, GBufferProducer::Raster, TraceVariant::General);
    let mut traced = gbuffer(gpu, GBufferProducer::Traced, TraceVariant::General);
    for (scene, camera) in frames {
        gs.set_instances(gpu, scene).expect("instances");
        render(gpu, &mut raster, &gs, scene, camera);
        render(gpu, &mut traced, &gs, scene, camera);
    }
    let (r, t) = (read(gpu, raster.current()), read(gpu, traced.current()));
    let covered = (0..r.depth.len())
        .filter(|&i| r.depth[i] > 0.0 || t.depth[i] > 0.0)
        .count();
    let mut reasons: Vec<(&str, usize)> = Vec::new();
    for i in 0..r.depth.len() {
        if let Some(why) = disagreement(&r, &t, i, textured) {
            match reasons.iter_mut().find(|(w, _)| *w == why) {
                Some((_, n)) => *n += 1,
                None => reasons.push((why, 1)),
            }
        }
    }
    let differ: usize = reasons.iter().map(|(_, n)| n).sum();
    let moving = (0..r.motion.len())
        .filter(|&i| r.motion[i][0] != f16::ZERO || r.motion[i][1] != f16::ZERO)
        .count();
    let both: Vec<usize> = (0..r.depth.len())
        .filter(|&i| r.depth[i] > 0.0 && t.depth[i] > 0.0)
        .collect();
    let albedo_gap = both
        .iter()
        .map(|&i| {
            (base_color(r.gbuffer[i]) - base_color(t.gbuffer[i]))
                .abs()
                .max_element()
        })
        .sum::<f32>()
        / both.len().max(1) as f32;
    eprintln!(
        "{name}: {covered} covered pixels, {differ} differ {reasons:?}, {moving} with motion, \
         mean albedo gap {albedo_gap:.5}"
    );
    assert!(
        albedo_gap <= 0.01,
        "{name}: albedo differs by {albedo_gap} on average"
    );
    assert!(covered * 5 > r.depth.len(), "{name}: too little coverage");
    assert!(
        differ * 200 <= covered,
        "{name}: {differ} of {covered} covered pixels differ ({reasons:?})"
    );
    if frames.len() > 1 {
        assert!(moving * 2 > covered, "{name}: the motion went untested");
    }
}

#[test]
fn raster_and_traced_gbuffers_agree() {
    let Some(gpu) = test_gpu() else { return };
    let cornell = default_scene::cornell_box();
    let camera = cornell.camera(None).unwrap();
    compare(&gpu, "cornell_box", &[(cornell.clone(), camera.clone())]);

    // Mirrored instances (both blocks, mirrored in x about their centres): the rasteriser's
    // screen winding is reversed there, and facing must still be the mesh's own.
    let mut mirrored = cornell.clone();
    for k in [6, 7] {
        let inst = &mut mirrored.instances[k];
        let (lo, hi) = solari_scene::trace_cpu::instance_bounds(&cornell, &cornell.instances[k]);
        let c = (lo + hi) * 0.5;
        inst.transform = Mat4::from_translation(c)
            * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0))
            * Mat4::from_translation(-c)
            * inst.transform;
    }
    compare(
        &gpu,
        "cornell_box, mirrored blocks",
        &[(mirrored, camera.clone())],
    );

    let spheres = textured_scene::textured_spheres();
    let sphere_camera = spheres.camera(None).unwrap();
    compare(&gpu, "textured_spheres", &[(spheres, sphere_camera)]);

    // Frame 2: the tall block (instance 7) moves and the camera steps sideways.
    let mut moved = cornell.clone();
    moved.instances[7].transform =
        Mat4::from_translation(Vec3::new(0.35, 0.2, -0.25)) * moved.instances[7].transform;
    let mut camera1 = camera.clone();
    camera1.transform = Mat4::from_translation(Vec3::new(0.15, -0.05, 0.1)) * camera.transform;
    compare(
        &gpu,
        "cornell_box, moving block and camera",
        &[(cornell, camera), (moved, camera1)],
    );
}

#[test]
fn a_traced_gbuffer_specialised_for_one_instance_refuses_a_grown_scene() {
    let Some(gpu) = test_gpu() else { return };
    let mut scene = default_scene::cornell_box();
    scene.instances.truncate(1);
    let camera = scene.camera(None).unwrap();
    // Two-level BVHs: a merged scene of any size takes the merged traversal.
    let options = GpuSceneOptions {
        merge_instances: false,
        ..Default::default()
    };
    let gs = GpuScene::new(&gpu, &scene, Backend::Software, &options).unwrap();
    let variant = TraceVariant::for_scene(&gs);
    assert_ne!(variant, TraceVariant::General);
    let mut gb = gbuffer(&gpu, GBufferProducer::Traced, variant);
    assert_eq!(gb.trace_variant(), Some(variant));
    render(&gpu, &mut gb, &gs, &scene, &camera);

    let grown = default_scene::cornell_box();
    let gs = GpuScene::new(&gpu, &grown, Backend::Software, &options).unwrap();
    gb.prepare(&gpu, &grown, &camera).unwrap();
    let frame = FrameContext::new(1, gb.size(), &camera, None);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let refused = gb.encode(&mut encoder, &frame, &gs);
    assert!(
        matches!(&refused, Err(GpuError::Validation(m)) if m.contains("specialised")),
        "a one-instance pipeline must refuse {} instances",
        grown.instances.len()
    );
}

#[test]
fn a_first_try_within_last_frames_depth_finds_what_an_unbounded_ray_finds() {
    // The traced producer bounds each ray's first try by last frame's distance at its pixel
    // (plus 0.5%) and tries again, unbounded, after a miss. Its second frame must equal, texel
    // for texel, a first frame of the same view (no depth before it: every ray unbounded):
    // with the camera stepping back (most surfaces now farther: second tries), forward (all
    // nearer) and sideways past a moved block (some of each).
    let Some(gpu) = test_gpu() else { return };
    let scene = default_scene::cornell_box();
    let camera = scene.camera(None).unwrap();
    let step = |v: Vec3| {
        let mut c = camera.clone();
        c.transform = camera.transform * Mat4::from_translation(v);
        c
    };
    let mut moved = scene.clone();
    moved.instances[7].transform =
        Mat4::from_translation(Vec3::new(0.35, 0.2, -0.25)) * moved.instances[7].transform;
    let cases = [
        ("back", scene.clone(), step(Vec3::Z * 1.5)),
        ("forward", scene.clone(), step(Vec3::Z * -1.5)),
        (
            "sideways, block moved",
            moved,
            step(Vec3::new(0.6, -0.1, 0.0)),
        ),
    ];
    for (name, next, next_camera) in cases {
        let mut gs = GpuScene::new(&gpu, &scene, Backend::Software, &Default::default()).unwrap();
        let mut warm = gbuffer(&gpu, GBufferProducer::Traced, TraceVariant::General);
        render(&gpu, &mut warm, &gs, &scene, &camera);
        let before = read(&gpu, warm.current());
        gs.set_instances(&gpu, &next).unwrap();
        render(&gpu, &mut warm, &gs, &next, &next_camera);
        let mut cold = gbuffer(&gpu, GBufferProducer::Traced, TraceVariant::General);
        render(&gpu, &mut cold, &gs, &next, &next_camera);
        let (w, c) = (read(&gpu, warm.current()), read(&gpu, cold.current()));
        // How the depth moved between the frames, per covered pixel (reversed-Z: a smaller
        // value is farther): farther by over the margin means a second try.
        let (mut farther, mut nearer) = (0, 0);
        for i in 0..c.depth.len() {
            if before.depth[i] > 0.0 && c.depth[i] > 0.0 {
                if before.depth[i] > c.depth[i] * 1.005 {
                    farther += 1;
                } else {
                    nearer += 1;
                }
            }
        }
        eprintln!("{name}: {farther} pixels retried, {nearer} found within the bound");
        assert!(farther + nearer > c.depth.len() / 3, "{name}: coverage");
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&w.depth), bits(&c.depth), "{name}: depth");
        assert!(w.gbuffer == c.gbuffer, "{name}: material and normals");
        assert!(w.emission == c.emission, "{name}: emission");
        match name {
            "back" => assert!(
                farther * 2 > farther + nearer,
                "{name}: too few second tries"
            ),
            "forward" => assert!(
                nearer * 2 > farther + nearer,
                "{name}: too few bounded hits"
            ),
            _ => assert!(farther > 0 && nearer > 0, "{name}: both kinds"),
        }
    }
}
