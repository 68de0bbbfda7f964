//! Scenes and images over a device's limits give `GpuError::OverLimit` (or the documented
//! texture resampling), never a wgpu panic: checked on a lavapipe device whose limits are
//! lowered on purpose (GPU: lavapipe in CI).

use solari_scene::gbuffer::GBuffer;
use solari_scene::gpu::{Gpu, test_gpu, test_gpu_with_limits};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
use solari_scene::shaders::Backend;
use solari_scene::*;

/// A device on the test adapter with small limits: 64 KiB storage bindings, 64-texel 2D
/// textures, two texture-array layers.
fn small_gpu() -> Option<Gpu> {
    test_gpu_with_limits(|own| wgpu::Limits {
        max_storage_buffer_binding_size: 1 << 16,
        max_texture_dimension_2d: 64,
        max_texture_array_layers: 2,
        ..own
    })
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

/// The built-in Cornell box with its light turned into a 400-triangle grid, instanced
/// `lights` times: its BVH fits `small_gpu`'s 64 KiB bindings, and so does an emitter BVH
/// of one light, but not of four (1,600 copied triangles of 48 bytes).
fn cornell_with_grid_lights(lights: usize) -> Scene {
    let mut scene = default_scene::cornell_box();
    let light = solari_scene::bvh::emitter_layout(&scene)[0].0 as usize;
    let (n, m) = (10u32, 20u32);
    let mesh = &mut scene.meshes[scene.instances[light].mesh as usize];
    mesh.positions = (0..=m)
        .flat_map(|y| {
            (0..=n).map(move |x| glam::Vec3::new(2.0 + x as f32 * 0.1, 5.0, 2.0 + y as f32 * 0.05))
        })
        .collect();
    mesh.normals = vec![-glam::Vec3::Y; mesh.positions.len()];
    mesh.uvs = vec![glam::Vec2::ZERO; mesh.positions.len()];
    mesh.tangents = vec![glam::Vec4::X; mesh.positions.len()];
    mesh.indices = (0..m)
        .flat_map(|y| (0..n).map(move |x| y * (n + 1) + x))
        .flat_map(|i| [i, i + n + 2, i + 1, i, i + n + 1, i + n + 2])
        .collect();
    let inst = scene.instances[light].clone();
    for k in 1..lights {
        let mut copy = inst.clone();
        copy.transform = glam::Mat4::from_translation(glam::Vec3::new(0.0, -0.1 * k as f32, 0.0));
        scene.instances.push(copy);
    }
    scene
}

#[test]
fn an_emitter_bvh_over_the_binding_limit_falls_back_to_the_first_surface() {
    use solari_scene::gpu_scene::EmitterTracing;
    let Some(small) = small_gpu() else { return };
    let Some(gpu) = test_gpu() else { return };
    let options = GpuSceneOptions {
        max_texture_size: 16,
        ..Default::default()
    };
    let four = cornell_with_grid_lights(4);
    // A device with room for it traces emitters alone.
    let gs = GpuScene::new(&gpu, &four, Backend::Software, &options).unwrap();
    assert_eq!(gs.emitter_tracing(), EmitterTracing::EmittersOnly);
    // 64 KiB bindings: neither the merged BVH nor the emitter BVH fits; the two-level BVH
    // without an emitter BVH does.
    let gs = GpuScene::new(&small, &four, Backend::Software, &options).unwrap();
    assert!(!gs.is_merged());
    assert_eq!(gs.emitter_tracing(), EmitterTracing::FirstSurface);
    // One light's emitter BVH fits; switching three more on outgrows it at `set_instances`,
    // which falls back the same way instead of failing.
    let mut scene = four.clone();
    let dark = scene.instances[0].material;
    let lit = scene.instances[scene.instances.len() - 1].material;
    assert!(!scene.materials[dark as usize].is_emissive());
    let first_light = scene.instances.len() - 4;
    for i in &mut scene.instances[first_light + 1..] {
        i.material = dark;
    }
    let mut gs = GpuScene::new(&small, &scene, Backend::Software, &options).unwrap();
    assert_eq!(gs.emitter_tracing(), EmitterTracing::EmittersOnly);
    for i in &mut scene.instances[first_light + 1..] {
        i.material = lit;
    }
    gs.set_instances(&small, &scene).unwrap();
    assert_eq!(gs.emitter_tracing(), EmitterTracing::FirstSurface);
    small.check_errors().unwrap();
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

/// A test device (`test_gpu`) that wgpu refused work on, with nobody checking, fails the test
/// when it is dropped: a copy into a buffer without `COPY_DST` is refused and logged, and a
/// test that went on would read the buffer's old contents. Checked errors are cleared and
/// the drop passes.
#[test]
fn unchecked_wgpu_errors_fail_the_test_at_drop() {
    let refused_copy = |gpu: &Gpu| {
        let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("no copies in"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        gpu.queue.write_buffer(&buffer, 0, &[0u8; 16]);
    };
    let Some(gpu) = test_gpu() else { return };
    refused_copy(&gpu);
    let dropped = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| drop(gpu)));
    let message = dropped.expect_err("the drop must panic");
    let text = message
        .downcast_ref::<String>()
        .cloned()
        .unwrap_or_default();
    assert!(text.contains("nobody checked"), "{text}");
    let gpu = test_gpu().expect("a second device");
    refused_copy(&gpu);
    assert!(gpu.check_errors().is_err(), "the refused copy is reported");
    drop(gpu);
}
