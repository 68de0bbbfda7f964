//! Passes specialised for a single-instance scene (the software traversal without its top
//! level) must never trace a scene that has grown since: the components refuse it, and the
//! renderer rebuilds them for the new shape (GPU: lavapipe in CI, software backend forced,
//! since ray queries are never specialised).

mod common;

use common::{SIZE, luminance, reference_direct, rgb, settings};
use glam::Vec3;
use solari_lights::{GpuLights, LightList, LightTiles, Selection};
use solari_renderer::{GBufferChoice, GiMode, RealtimeRenderer, RealtimeSettings};
use solari_restir::RestirDi;
use solari_scene::gbuffer::GBuffer;
use solari_scene::gpu::test_gpu;
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::pass::FrameContext;
use solari_scene::shaders::Backend;
use solari_scene::{Camera, DirectionalLight, Scene, default_scene};
use solari_worldcache::WorldCache;

/// The Cornell box's floor and blocks under a sun from the side, seen from above: the
/// blocks cast long shadows on the floor. `blocks: false` keeps the floor alone (one
/// instance), with the same camera and sun.
fn shadow_scene(blocks: bool) -> Scene {
    let mut scene = default_scene::cornell_box();
    let keep = ["floor", "short_block", "tall_block"];
    scene.instances.retain(|i| keep.contains(&i.name.as_str()));
    let (lo, hi) = scene.bounds();
    if !blocks {
        scene.instances.retain(|i| i.name == "floor");
    }
    scene.directional_lights.push(DirectionalLight {
        name: "sun".into(),
        direction: Vec3::new(0.8, -0.6, 0.2).normalize(),
        irradiance: Vec3::splat(3.0),
        angular_diameter: 1f32.to_radians(),
    });
    let centre = (lo + hi) * 0.5;
    let eye = centre + Vec3::new(0.0, 1.2, 0.6) * (hi - lo).length();
    scene.cameras = vec![Camera::look_at("above", eye, centre, Vec3::Y, 0.8)];
    scene
}

#[test]
fn restir_di_and_the_world_cache_refuse_a_scene_that_outgrew_their_pipelines() {
    let Some(gpu) = test_gpu() else { return };
    let backend = Backend::Software;
    let (small, grown) = (shadow_scene(false), shadow_scene(true));
    let mut gpu_scene =
        GpuScene::new(&gpu, &small, backend, &GpuSceneOptions::default()).expect("upload");
    let variant = TraceVariant::for_scene(&gpu_scene);
    assert_ne!(variant, TraceVariant::General, "one instance specialises");
    let s = settings();
    let mut di = RestirDi::new(&gpu, backend, variant, SIZE, SIZE, s.di, s.tiles).expect("DI");
    let cache = WorldCache::new(&gpu, backend, variant, s.cache, s.tiles).expect("cache");
    let gbuffer = GBuffer::new(&gpu, backend, SIZE, SIZE).expect("G-buffer");
    let tiles = LightTiles::new(&gpu, s.tiles).expect("tiles");
    let list = LightList::build(&small);
    let lights = GpuLights::new(&gpu, &list, Selection::Power).expect("lights");
    let group = tiles.reader_group(&gpu, &lights);
    let count = list.len() as u32;
    let camera = small.camera(None).expect("camera");
    let frame = FrameContext::new(0, (SIZE, SIZE), &camera, None);

    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    di.encode(&mut encoder, &frame, &gpu_scene, &gbuffer, &group, count)
        .expect("the scene it was built for");
    cache
        .encode(&mut encoder, &frame, &gpu_scene, &group)
        .expect("the scene it was built for");

    gpu_scene.set_instances(&gpu, &grown).expect("grow");
    assert_eq!(gpu_scene.instance_count(), 3);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let err = di
        .encode(&mut encoder, &frame, &gpu_scene, &gbuffer, &group, count)
        .expect_err("DI traced a grown scene with a single-instance pipeline");
    assert!(err.to_string().contains("TraceVariant::for_scene"), "{err}");
    let err = cache
        .encode(&mut encoder, &frame, &gpu_scene, &group)
        .expect_err("the cache traced a grown scene with a single-instance pipeline");
    assert!(err.to_string().contains("3 instances"), "{err}");
}

/// Mean of `frames` frames of the renderer's output after the scene grew, the variant the
/// renderer traced with before and after, and its G-buffer's after.
fn mean_after_growth(
    frames: u32,
    gi: GiMode,
    gbuffer: GBufferChoice,
) -> (
    Vec<[f32; 3]>,
    TraceVariant,
    TraceVariant,
    Option<TraceVariant>,
) {
    let gpu = test_gpu().expect("checked by the caller");
    let backend = Backend::Software;
    let (small, grown) = (shadow_scene(false), shadow_scene(true));
    let mut gpu_scene =
        GpuScene::new(&gpu, &small, backend, &GpuSceneOptions::default()).expect("upload");
    let settings = RealtimeSettings {
        gi,
        gbuffer,
        ..settings()
    };
    let mut renderer =
        RealtimeRenderer::new(&gpu, backend, &small, &gpu_scene, SIZE, SIZE, settings)
            .expect("renderer");
    let camera = small.camera(None).expect("camera");
    for _ in 0..2 {
        renderer
            .render(&gpu, &small, &gpu_scene, &camera)
            .expect("frame");
    }
    let before = renderer.trace_variant();
    gpu_scene.set_instances(&gpu, &grown).expect("grow");
    let mut sum = vec![[0.0f64; 3]; (SIZE * SIZE) as usize];
    for _ in 0..frames {
        renderer
            .render(&gpu, &grown, &gpu_scene, &camera)
            .expect("a frame of the grown scene");
        let out = rgb(&renderer.read_output(&gpu).expect("read back"));
        for (s, p) in sum.iter_mut().zip(out) {
            for c in 0..3 {
                s[c] += p[c] as f64 / frames as f64;
            }
        }
    }
    let mean = sum
        .iter()
        .map(|p| [p[0] as f32, p[1] as f32, p[2] as f32])
        .collect();
    let gbuffer_after = renderer.gbuffer().trace_variant();
    (mean, before, renderer.trace_variant(), gbuffer_after)
}

#[test]
fn the_renderer_rebuilds_its_tracing_when_the_scene_grows_and_shows_the_new_shadows() {
    let Some(gpu) = test_gpu() else { return };
    let backend = Backend::Software;
    let floor_only = reference_direct(&gpu, backend, &shadow_scene(false), SIZE, 256);
    let grown = reference_direct(&gpu, backend, &shadow_scene(true), SIZE, 256);
    // Floor pixels the blocks shadow (or cover): what a traversal of instance 0 alone
    // would still light.
    let changed: Vec<usize> = (0..grown.len())
        .filter(|&i| luminance(grown[i]) < 0.5 * luminance(floor_only[i]))
        .collect();
    assert!(
        changed.len() > 100,
        "the blocks change only {} pixels",
        changed.len()
    );
    let mean_of = |img: &[[f32; 3]]| {
        changed.iter().map(|&i| luminance(img[i])).sum::<f64>() / changed.len() as f64
    };
    let (lit, dark) = (mean_of(&floor_only), mean_of(&grown));
    let cases = [
        (GiMode::Off, GBufferChoice::Raster),
        (GiMode::WorldCache, GBufferChoice::Raster),
        (GiMode::Off, GBufferChoice::Traced),
    ];
    for (gi, producer) in cases {
        let (image, before, after, gbuffer) = mean_after_growth(32, gi, producer);
        assert_ne!(before, TraceVariant::General, "one instance specialises");
        assert_eq!(after, TraceVariant::General, "{gi:?}: not rebuilt");
        let expected = (producer == GBufferChoice::Traced).then_some(TraceVariant::General);
        assert_eq!(gbuffer, expected, "{producer:?} G-buffer after growth");
        assert!(image.iter().flatten().all(|c| c.is_finite()));
        let got = mean_of(&image);
        println!(
            "{gi:?}, {} G-buffer: changed pixels {}: floor alone {lit:.4}, grown scene \
             {dark:.4}, renderer after growth {got:.4}",
            producer.name(),
            changed.len()
        );
        // Cache GI adds indirect light the direct-only reference lacks: allow it a margin.
        let slack = if gi == GiMode::Off { 0.2 } else { 0.35 };
        assert!(
            (got - dark).abs() <= slack * (lit - dark),
            "{gi:?}: shadowed pixels average {got}, the grown scene's reference {dark}, \
             the floor alone {lit}"
        );
    }
}
