//! The G-buffer raster pass (lavapipe in CI): it stores what primary rays see at pixel centres,
//! its motion vectors reproject moving instances and a moving camera to where they were, and
//! last frame's targets stay readable after the swap.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec2, Vec3, Vec4};
use solari_scene::gbuffer::{GBuffer, GBufferProducer, view_projection};
use solari_scene::gpu::{Gpu, ShaderChecks, test_gpu};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::gpu_types::GpuView;
use solari_scene::pass::FrameContext;
use solari_scene::shaders::{Backend, compose};
use solari_scene::*;

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct PixelOut {
    gb_base: [f32; 3],
    gb_depth: f32,
    tr_base: [f32; 3],
    tr_instance: u32,
    gb_normal: [f32; 3],
    gb_roughness: f32,
    tr_normal: [f32; 3],
    tr_roughness: f32,
    gb_geometric: [f32; 3],
    gb_metallic: f32,
    tr_geometric: [f32; 3],
    tr_metallic: f32,
    tr_position: [f32; 3],
    tr_view_z: f32,
    motion: [f32; 2],
    gb_f90: f32,
    tr_f90: f32,
}

/// Runs the probe kernel over the G-buffer's current targets.
struct Probe {
    pipeline: wgpu::ComputePipeline,
    view_layout: wgpu::BindGroupLayout,
    io_layout: wgpu::BindGroupLayout,
}

impl Probe {
    fn new(gpu: &Gpu, backend: Backend) -> Self {
        let module = [("gbuffer_test", include_str!("shaders/gbuffer_test.wesl"))];
        let wgsl = compose("gbuffer_test", backend, &module).expect("compose");
        let view_layout = gpu.buffer_layout("view", &[wgpu::BufferBindingType::Uniform]);
        let texture = |binding, sample_type| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let unfiltered = wgpu::TextureSampleType::Float { filterable: false };
        let io_layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("gbuffer_test"),
                entries: &[
                    solari_scene::gpu::buffer_layout_entry(
                        0,
                        wgpu::BufferBindingType::Storage { read_only: false },
                        wgpu::ShaderStages::COMPUTE,
                    ),
                    texture(1, wgpu::TextureSampleType::Uint),
                    texture(2, unfiltered),
                    texture(3, unfiltered),
                    texture(4, unfiltered),
                ],
            });
        let scene_layout = GpuScene::layout_for(gpu, backend);
        let pipeline = gpu
            .compute_pipeline(
                "gbuffer_test",
                &wgsl,
                &[Some(&scene_layout), Some(&view_layout), Some(&io_layout)],
                ShaderChecks::BoundsOnly,
                &[],
            )
            .expect("pipeline");
        Self {
            pipeline,
            view_layout,
            io_layout,
        }
    }

    fn run(
        &self,
        gpu: &Gpu,
        gs: &GpuScene,
        gb: &GBuffer,
        camera: &Camera,
        jitter: [f32; 2],
    ) -> Vec<PixelOut> {
        let (w, h) = gb.size();
        let view = GpuView::new(camera, w, h).with_jitter(jitter);
        let view_buf = gpu.uniform_buffer("view", &view);
        let view_group = gpu.bind_buffers("view", &self.view_layout, &[&view_buf]);
        let bytes = (w * h) as u64 * size_of::<PixelOut>() as u64;
        let out = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pixels"),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let t = gb.current();
        let v = |tex: &wgpu::Texture| tex.create_view(&Default::default());
        let (a, b, c, d) = (v(&t.gbuffer), v(&t.emission), v(&t.motion), v(&t.depth));
        let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("gbuffer_test"),
            layout: &self.io_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: out.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&a),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&b),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&c),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&d),
                },
            ],
        });
        gpu.dispatch(
            "gbuffer_test",
            &self.pipeline,
            &[gs.bind_group(), &view_group, &group],
            [w.div_ceil(8), h.div_ceil(8), 1],
        )
        .expect("probe");
        bytemuck::cast_slice(&gpu.read_buffer(&out, bytes).expect("read")).to_vec()
    }
}

fn render(gpu: &Gpu, gb: &mut GBuffer, gs: &GpuScene, scene: &Scene, camera: &Camera) {
    render_jittered(gpu, gb, gs, scene, camera, [0.0; 2]);
}

fn render_jittered(
    gpu: &Gpu,
    gb: &mut GBuffer,
    gs: &GpuScene,
    scene: &Scene,
    camera: &Camera,
    jitter: [f32; 2],
) {
    gb.prepare_jittered(gpu, scene, camera, jitter)
        .expect("prepare");
    let frame = FrameContext::new(0, gb.size(), camera, None);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let ran = gb.encode(&mut encoder, &frame, gs).expect("encode");
    assert!(ran.contains("gbuffer"));
    gpu.queue.submit([encoder.finish()]);
}

/// Both producers (the traced one as the general two-level variant).
const PRODUCERS: [GBufferProducer; 2] = GBufferProducer::ALL;

fn scenes() -> Vec<(&'static str, Scene)> {
    vec![
        ("cornell_box", default_scene::cornell_box()),
        ("textured_spheres", textured_scene::textured_spheres()),
    ]
}

#[test]
fn gbuffer_stores_what_primary_rays_see() {
    let Some(gpu) = test_gpu() else { return };
    let backend = Backend::Software;
    let probe = Probe::new(&gpu, backend);
    let (w, h) = (96, 80);
    // Unjittered, and with every sample moved off its pixel centre.
    let jitters = [[0.0, 0.0], [0.31, -0.27]];
    for (((name, scene), producer), jitter) in scenes()
        .into_iter()
        .flat_map(|s| PRODUCERS.map(|p| (s.clone(), p)))
        .flat_map(|sp| jitters.map(|j| (sp.clone(), j)))
    {
        let name = format!("{name} ({}, jitter {jitter:?})", producer.name());
        let camera = scene.camera(None).unwrap();
        let options = GpuSceneOptions {
            max_texture_size: 64,
            ..Default::default()
        };
        let gs = GpuScene::new(&gpu, &scene, backend, &options).unwrap();
        let mut gb =
            GBuffer::with_producer(&gpu, backend, producer, TraceVariant::General, w, h).unwrap();
        render_jittered(&gpu, &mut gb, &gs, &scene, &camera, jitter);
        assert!(!gb.history_valid(), "first frame has no history");
        let pixels = probe.run(&gpu, &gs, &gb, &camera, jitter);
        let mut covered = 0;
        let mut bad = Vec::new();
        for (i, p) in pixels.iter().enumerate() {
            let traced = p.tr_instance != u32::MAX;
            let rastered = p.gb_depth > 0.0;
            if traced != rastered {
                bad.push(format!(
                    "pixel {i}: coverage traced {traced} raster {rastered}"
                ));
                continue;
            }
            if !traced {
                continue;
            }
            covered += 1;
            let view_z = camera.znear / p.gb_depth;
            let close3 = |a: [f32; 3], b: [f32; 3], tol: f32| {
                (Vec3::from(a) - Vec3::from(b)).abs().max_element() <= tol
            };
            let same_dir =
                |a: [f32; 3], b: [f32; 3], cos: f32| Vec3::from(a).dot(Vec3::from(b)) > cos;
            // 8-bit √-encoded colour: a step is at most 2/255 of the value's square root. The
            // probe filters textures with ray differentials, as the traced producer does; the
            // rasteriser's derivatives are differences over 2×2 quads, so where a texture
            // changes fast it blends slightly different mips (tests/gbuffer_lod.rs bounds
            // that difference by FLIP).
            let (blend, normal_cos) = match producer {
                GBufferProducer::Raster => (0.1, 0.99),
                GBufferProducer::Traced => (0.0, 0.999),
            };
            let ok = (view_z - p.tr_view_z).abs() <= 1e-3 * p.tr_view_z
                && close3(p.gb_base, p.tr_base, 0.012 + blend)
                && same_dir(p.gb_normal, p.tr_normal, normal_cos)
                && same_dir(p.gb_geometric, p.tr_geometric, 0.999)
                && (p.gb_roughness - p.tr_roughness).abs() <= 0.5 / 255.0 + 1e-6 + blend
                && (p.gb_metallic - p.tr_metallic).abs() <= 0.5 / 255.0 + 1e-6 + blend
                && (p.gb_f90 - p.tr_f90).abs() <= 1e-3
                && Vec2::from(p.motion) == Vec2::ZERO;
            if !ok {
                bad.push(format!("pixel {i}: {p:?} (view z {view_z})"));
            }
        }
        eprintln!(
            "{name}: {covered} covered pixels of {}, {} differ",
            pixels.len(),
            bad.len()
        );
        assert!(covered > pixels.len() / 5, "{name}: too little coverage");
        // Rasterisation and ray tracing may disagree on pixel centres on a shared edge.
        assert!(
            bad.len() * 100 <= pixels.len(),
            "{name}: {} of {} pixels differ; first:\n{}",
            bad.len(),
            pixels.len(),
            bad[..bad.len().min(5)].join("\n")
        );
    }
}

/// Texture coordinates of a world point under `view_proj`.
fn project(view_proj: Mat4, x: Vec3) -> Vec2 {
    let c = view_proj * Vec4::new(x.x, x.y, x.z, 1.0);
    let ndc = Vec2::new(c.x, c.y) / c.w;
    Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5)
}

#[test]
fn motion_vectors_reproject_moving_instances_and_cameras() {
    let Some(gpu) = test_gpu() else { return };
    for producer in PRODUCERS {
        eprintln!("{}:", producer.name());
        check_motion(&gpu, producer);
    }
}

fn check_motion(gpu: &Gpu, producer: GBufferProducer) {
    let backend = Backend::Software;
    let probe = Probe::new(gpu, backend);
    let (w, h) = (96, 96);
    let mut scene = default_scene::cornell_box();
    let camera0 = scene.camera(None).unwrap();
    let mut gs = GpuScene::new(gpu, &scene, backend, &GpuSceneOptions::default()).unwrap();
    let mut gb =
        GBuffer::with_producer(gpu, backend, producer, TraceVariant::General, w, h).unwrap();
    render(gpu, &mut gb, &gs, &scene, &camera0);
    let first_depth = read_depth(gpu, &gb.current().depth);

    // Frame 2: the tall block (instance 7) moves and the camera steps sideways.
    let moved = 7;
    let offset = Vec3::new(0.35, 0.2, -0.25);
    scene.instances[moved].transform =
        Mat4::from_translation(offset) * scene.instances[moved].transform;
    gs.set_instances(gpu, &scene).unwrap();
    let mut camera1 = camera0.clone();
    camera1.transform = Mat4::from_translation(Vec3::new(0.15, -0.05, 0.1)) * camera0.transform;
    render(gpu, &mut gb, &gs, &scene, &camera1);
    assert!(gb.history_valid());
    // Swap, not copy: last frame's depth is now the previous target, untouched.
    assert_eq!(read_depth(gpu, &gb.previous().depth), first_depth);

    let pixels = probe.run(gpu, &gs, &gb, &camera1, [0.0; 2]);
    let vp0 = view_projection(&camera0, w, h);
    let vp1 = view_projection(&camera1, w, h);
    let (mut on_moved, mut checked, mut bad) = (0, 0, Vec::new());
    for (i, p) in pixels.iter().enumerate() {
        if p.tr_instance == u32::MAX || p.gb_depth <= 0.0 {
            continue;
        }
        let x = Vec3::from(p.tr_position);
        let before = if p.tr_instance as usize == moved {
            on_moved += 1;
            x - offset
        } else {
            x
        };
        let expected = project(vp1, x) - project(vp0, before);
        checked += 1;
        // f16 storage: relative 2^-11, plus the pixel-centre position's own float error.
        let err = (Vec2::from(p.motion) - expected).abs().max_element();
        if err > 1e-3 * expected.abs().max_element() + 2e-4 {
            bad.push(format!(
                "pixel {i} (instance {}): motion {:?}, expected {expected}",
                p.tr_instance, p.motion
            ));
        }
    }
    eprintln!(
        "{checked} pixels checked, {on_moved} on the moved block, {} differ",
        bad.len()
    );
    assert!(
        on_moved > 100,
        "the moved block must cover pixels ({on_moved})"
    );
    assert!(
        bad.len() * 100 <= checked,
        "{} of {checked} motion vectors wrong; first:\n{}",
        bad.len(),
        bad[..bad.len().min(5)].join("\n")
    );
}

fn read_depth(gpu: &Gpu, texture: &wgpu::Texture) -> Vec<f32> {
    let bytes = gpu
        .read_texture(texture, wgpu::TextureAspect::All)
        .expect("read depth");
    bytemuck::cast_slice(&bytes).to_vec()
}

#[test]
fn bad_sizes_are_refused() {
    let Some(gpu) = test_gpu() else { return };
    assert!(matches!(
        GBuffer::new(&gpu, Backend::Software, 0, 64),
        Err(GpuError::Validation(_))
    ));
    assert!(matches!(
        GBuffer::new(&gpu, Backend::Software, 1 << 20, 64),
        Err(GpuError::OverLimit { .. })
    ));
}

/// Jitter moves the samples, not the motion vectors: a still scene and camera rendered with a
/// different jitter every frame have zero motion everywhere, for both producers, while the
/// depth they store moves with the samples.
#[test]
fn jitter_leaves_motion_vectors_unjittered() {
    let Some(gpu) = test_gpu() else { return };
    let backend = Backend::Software;
    let scene = default_scene::cornell_box();
    let camera = scene.camera(None).unwrap();
    let gs = GpuScene::new(&gpu, &scene, backend, &GpuSceneOptions::default()).unwrap();
    for producer in PRODUCERS {
        let mut gb =
            GBuffer::with_producer(&gpu, backend, producer, TraceVariant::General, 64, 64).unwrap();
        let mut depths = Vec::new();
        for frame in 0..4 {
            let jitter = solari_scene::gpu_types::halton_jitter(frame);
            render_jittered(&gpu, &mut gb, &gs, &scene, &camera, jitter);
            let bytes = gpu
                .read_texture(&gb.current().motion, wgpu::TextureAspect::All)
                .expect("motion");
            let moving = bytemuck::cast_slice::<u8, u16>(&bytes)
                .iter()
                // f16 ±0 only.
                .filter(|&&h| h & 0x7fff != 0)
                .count();
            assert_eq!(moving, 0, "{}: frame {frame} has motion", producer.name());
            depths.push(read_depth(&gpu, &gb.current().depth));
        }
        assert_ne!(
            depths[0],
            depths[1],
            "{}: jitter moved nothing",
            producer.name()
        );
    }
}

/// Moving the overrides into shared scratch is refused, with the reason, before overrides
/// are enabled and with a scratch smaller than 32 bytes a pixel; with one large enough the
/// overrides are shared, the G-buffer no longer counts them, and the writers' buffer is the
/// scratch.
#[test]
fn override_scratch_is_refused_when_it_cannot_serve() {
    let Some(gpu) = test_gpu() else { return };
    let (w, h) = (24u32, 16u32);
    let mut gb = GBuffer::new(&gpu, Backend::Software, w, h).expect("G-buffer");
    let fits = scratch::allocate(&gpu, 32 * (w * h) as u64).unwrap();
    let e = gb
        .use_override_scratch(&gpu, &fits)
        .unwrap_err()
        .to_string();
    assert!(e.contains("without GBuffer::enable_overrides"), "{e}");
    assert_eq!(gb.override_scratch_bytes(), 0);
    gb.enable_overrides(&gpu).expect("overrides");
    assert_eq!(gb.override_scratch_bytes(), 32 * (w * h) as u64);
    let own = gb.memory_bytes();
    let small = scratch::allocate(&gpu, 32 * (w * h) as u64 - 16).unwrap();
    let e = gb
        .use_override_scratch(&gpu, &small)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("G-buffer overrides") && e.contains("it needs"),
        "{e}"
    );
    assert!(!gb.overrides_shared());
    gb.use_override_scratch(&gpu, &fits).expect("scratch");
    assert!(gb.overrides_shared());
    assert_eq!(gb.overrides(), Some(&fits));
    assert_eq!(own - gb.memory_bytes(), 32 * (w * h) as u64);
    gpu.check_errors().expect("no wgpu error");
}

/// `GBufferSource::camera_moved`: true on the first frame, after a resize and when the camera
/// moves, turns or zooms; false when only the jitter changes (the temporal upscaler's still
/// pipeline keeps a still camera's frames as they were).
#[test]
fn camera_moved_ignores_jitter_and_sees_every_change_of_view() {
    use solari_scene::gbuffer_input::GBufferSource;
    let Some(gpu) = test_gpu() else { return };
    let backend = Backend::Software;
    let scene = default_scene::cornell_box();
    let camera = scene.camera(None).unwrap();
    let gs = GpuScene::new(&gpu, &scene, backend, &GpuSceneOptions::default()).unwrap();
    let mut gb = GBuffer::with_producer(
        &gpu,
        backend,
        GBufferProducer::Traced,
        TraceVariant::General,
        16,
        16,
    )
    .unwrap();
    let frame = |gb: &mut GBuffer, camera: &Camera, jitter: [f32; 2]| {
        render_jittered(&gpu, gb, &gs, &scene, camera, jitter);
        gb.camera_moved()
    };
    assert!(
        frame(&mut gb, &camera, [0.0; 2]),
        "the first frame has no still camera"
    );
    assert!(
        !frame(&mut gb, &camera, [0.3, -0.2]),
        "a new jitter is not a move"
    );
    assert!(!frame(&mut gb, &camera, [-0.4, 0.1]), "nor is another");
    let mut stepped = camera.clone();
    stepped.transform = camera.transform * Mat4::from_translation(Vec3::X * 1e-3);
    assert!(
        frame(&mut gb, &stepped, [0.0; 2]),
        "a millimetre's step is a move"
    );
    assert!(!frame(&mut gb, &stepped, [0.0; 2]));
    let mut turned = stepped.clone();
    turned.transform = stepped.transform * Mat4::from_rotation_y(1e-3);
    assert!(frame(&mut gb, &turned, [0.0; 2]), "a turn is a move");
    let mut zoomed = turned.clone();
    zoomed.yfov *= 0.99;
    assert!(frame(&mut gb, &zoomed, [0.0; 2]), "a zoom is a move");
    assert!(!frame(&mut gb, &zoomed, [0.0; 2]));
    gb.resize(&gpu, 18, 16).unwrap();
    assert!(
        frame(&mut gb, &zoomed, [0.0; 2]),
        "after a resize there is no history to be still against"
    );
}
