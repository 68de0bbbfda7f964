//! Texture filtering in the G-buffer. On a checkerboard plane seen at grazing angles, the
//! traced producer (ray differentials) picks the mips the raster one picks (quad derivatives):
//! its albedo is within FLIP 0.05 of the raster one's, while reading mip 0 everywhere, as
//! secondary rays do, aliases far beyond that (GPU: lavapipe in CI).

use glam::{Vec3, Vec4};
use solari_scene::gbuffer::{GBuffer, GBufferProducer};
use solari_scene::gpu::{Gpu, test_gpu};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::gpu_types::GpuView;
use solari_scene::pass::FrameContext;
use solari_scene::shaders::Backend;
use solari_scene::textured_scene::{ground_plane, procedural_texture};
use solari_scene::view_pass::ViewPass;
use solari_scene::*;

const SIZE: (u32, u32) = (160, 96);

/// A 200 × 200 plane whose 64-texel checker (8-texel cells) repeats 100 times, seen from 0.6
/// above it towards the horizon, under no light (albedo is all that is compared).
fn checker_plane() -> Scene {
    let mesh = ground_plane(200.0, 100.0);
    let checker = procedural_texture("checker", 64, 64, ColorSpace::Srgb, |x, y| {
        if (x / 8 + y / 8) % 2 == 0 {
            [240, 240, 240, 255]
        } else {
            [20, 20, 20, 255]
        }
    });
    let material = Material {
        name: "checker".into(),
        base_color: Vec4::ONE,
        base_color_texture: Some(0),
        ..Default::default()
    };
    let mut camera = Camera::look_at(
        "grazing",
        Vec3::new(0.0, 0.6, 20.0),
        Vec3::new(0.3, 0.0, 0.0),
        Vec3::Y,
        50f32.to_radians(),
    );
    camera.aspect = Some(SIZE.0 as f32 / SIZE.1 as f32);
    Scene {
        meshes: vec![mesh],
        instances: vec![Instance {
            name: "plane".into(),
            mesh: 0,
            material: 0,
            transform: glam::Mat4::IDENTITY,
        }],
        materials: vec![material],
        textures: vec![checker],
        cameras: vec![camera],
        ..Default::default()
    }
}

/// The G-buffer's base colour per pixel (black where nothing was hit).
fn gbuffer_albedo(gpu: &Gpu, gs: &GpuScene, scene: &Scene, producer: GBufferProducer) -> Vec<Vec3> {
    let (w, h) = SIZE;
    let variant = TraceVariant::General;
    let mut gb =
        GBuffer::with_producer(gpu, Backend::Software, producer, variant, w, h).expect("G-buffer");
    let camera = scene.camera(None).unwrap();
    gb.prepare(gpu, scene, &camera).expect("prepare");
    let frame = FrameContext::new(0, SIZE, &camera, None);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    gb.encode(&mut encoder, &frame, gs).expect("encode");
    gpu.queue.submit([encoder.finish()]);
    let bytes = gpu
        .read_texture(&gb.current().gbuffer, wgpu::TextureAspect::All)
        .expect("read back");
    let texels: &[[u32; 4]] = bytemuck::cast_slice(&bytes);
    // x: √base colour in unorm8 (`pack_gbuffer`).
    texels
        .iter()
        .map(|t| {
            let c = |i: u32| ((t[0] >> (8 * i)) & 0xff) as f32 / 255.0;
            Vec3::new(c(0), c(1), c(2)) * Vec3::new(c(0), c(1), c(2))
        })
        .collect()
}

/// The primary-ray debug view's albedo: textures read at mip 0.
fn mip0_albedo(gpu: &Gpu, gs: &GpuScene, scene: &Scene) -> Vec<Vec3> {
    let pass = ViewPass::primary(gpu, Backend::Software, TraceVariant::General).expect("pass");
    let camera = scene.camera(None).unwrap();
    let view = GpuView::new(&camera, SIZE.0, SIZE.1);
    let target = pass.target(gpu, &view).expect("target");
    let bytes = pass.run(gpu, gs, &target).expect("run");
    let pixels: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
    pixels.iter().map(|p| Vec3::new(p[0], p[1], p[2])).collect()
}

/// Mean FLIP between two albedo images, each encoded to sRGB bytes.
fn flip(test: &[Vec3], reference: &[Vec3]) -> f32 {
    let srgb = |img: &[Vec3]| -> Vec<u8> {
        img.iter()
            .flat_map(|c| c.to_array())
            .map(|v| {
                let v = v.clamp(0.0, 1.0);
                let e = if v <= 0.0031308 {
                    12.92 * v
                } else {
                    1.055 * v.powf(1.0 / 2.4) - 0.055
                };
                (e * 255.0 + 0.5) as u8
            })
            .collect()
    };
    let (w, h) = SIZE;
    let r = nv_flip::FlipImageRgb8::with_data(w, h, &srgb(reference));
    let t = nv_flip::FlipImageRgb8::with_data(w, h, &srgb(test));
    let map = nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec();
    map.iter().sum::<f32>() / map.len() as f32
}

#[test]
fn traced_texture_filtering_matches_the_rasteriser_at_grazing_angles() {
    let Some(gpu) = test_gpu() else { return };
    let scene = checker_plane();
    let options = GpuSceneOptions::default();
    let gs = GpuScene::new(&gpu, &scene, Backend::Software, &options).expect("upload");
    let raster = gbuffer_albedo(&gpu, &gs, &scene, GBufferProducer::Raster);
    let traced = gbuffer_albedo(&gpu, &gs, &scene, GBufferProducer::Traced);
    let mip0 = mip0_albedo(&gpu, &gs, &scene);
    let covered = raster.iter().filter(|c| c.max_element() > 0.0).count();
    let (traced_flip, mip0_flip) = (flip(&traced, &raster), flip(&mip0, &raster));
    println!(
        "{covered} covered pixels; FLIP against the raster G-buffer: traced {traced_flip:.4}, \
         mip 0 {mip0_flip:.4}"
    );
    assert!(covered * 3 > raster.len(), "the plane must fill the view");
    assert!(
        traced_flip <= 0.05,
        "traced filtering is off: FLIP {traced_flip}"
    );
    assert!(
        mip0_flip >= 2.0 * traced_flip.max(0.02),
        "the scene does not test filtering: mip 0 gives FLIP {mip0_flip}"
    );
}
