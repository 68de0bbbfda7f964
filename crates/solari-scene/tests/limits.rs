//! Scenes and images over a device's limits give `GpuError::OverLimit` (or the documented
//! texture resampling), never a wgpu panic: checked on a lavapipe device whose limits are
//! lowered on purpose (GPU: lavapipe in CI).

use solari_scene::gbuffer::GBuffer;
use solari_scene::gpu::{Gpu, test_gpu};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
use solari_scene::shaders::Backend;
use solari_scene::*;

/// A device on the test adapter with small limits: 64 KiB storage bindings, 64-texel 2D
/// textures, two texture-array layers.
fn small_gpu() -> Option<Gpu> {
    let gpu = test_gpu()?;
    let mut desc = Gpu::device_descriptor(&gpu.adapter);
    desc.required_limits = wgpu::Limits {
        max_storage_buffer_binding_size: 1 << 16,
        max_texture_dimension_2d: 64,
        max_texture_array_layers: 2,
        ..gpu.adapter.limits()
    };
    let (device, queue) = pollster::block_on(gpu.adapter.request_device(&desc)).ok()?;
    Some(Gpu::from_parts(
        gpu.instance.clone(),
        gpu.adapter.clone(),
        device,
        queue,
    ))
}

fn over_limit(r: Result<impl Sized, GpuError>, what: &str) {
    match r {
        Err(GpuError::OverLimit { what: w, .. }) => assert!(w.contains(what), "{w}"),
        Err(e) => panic!("expected an over-limit error for {what}, got {e}"),
        Ok(_) => panic!("{what}: accepted over the device's limit"),
    }
}

#[test]
fn scenes_over_buffer_and_layer_limits_are_refused() {
    let Some(gpu) = small_gpu() else { return };
    let options = GpuSceneOptions::default();
    let big = load_gltf(solari_testdata::scene("interior")).unwrap();
    over_limit(
        GpuScene::new(&gpu, &big, Backend::Software, &options),
        "solari_scene/",
    );
    // Six textures: three sRGB and three linear layers, over the limit of two.
    let textured = textured_scene::textured_spheres();
    over_limit(
        GpuScene::new(&gpu, &textured, Backend::Software, &options),
        "texture layers",
    );
    gpu.check_errors().unwrap();
}

#[test]
fn textures_over_the_size_limit_are_resampled_and_images_refused() {
    let Some(gpu) = small_gpu() else { return };
    // One 128-texel sRGB texture: resampled to the device's 64 (the documented fallback).
    let mut scene = default_scene::cornell_box();
    scene.textures.push(textured_scene::procedural_texture(
        "big",
        128,
        128,
        ColorSpace::Srgb,
        |x, y| [x as u8, y as u8, 0, 255],
    ));
    scene.materials[0].base_color_texture = Some(0);
    GpuScene::new(&gpu, &scene, Backend::Software, &GpuSceneOptions::default()).unwrap();
    // A G-buffer larger than a texture may be.
    assert!(GBuffer::new(&gpu, Backend::Software, 65, 8).is_err());
    gpu.check_errors().unwrap();
}
