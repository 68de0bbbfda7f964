//! One-call reference images of a whole scene, for tests that compare a component's output
//! with the ground truth.

use crate::path_tracer::{ReferenceImage, ReferenceRenderer, ReferenceSettings};
use solari_lights::LightList;
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::shaders::Backend;
use solari_scene::{GpuError, Scene};

/// The image component tests compare with: `scene` from its first camera at `size × size`,
/// one path per sample through each pixel's centre (what a G-buffer sees), `spp` paths per
/// pixel of at most `max_bounces` scattering events (`u32::MAX`: Russian roulette alone ends
/// them; 1: direct light only), lights chosen by power.
pub fn centre_image(
    gpu: &Gpu,
    backend: Backend,
    scene: &Scene,
    size: u32,
    spp: u32,
    max_bounces: u32,
) -> Result<Vec<[f32; 3]>, GpuError> {
    let settings = ReferenceSettings {
        spp,
        max_bounces,
        selection: solari_lights::Selection::Power,
        pixel_centre: true,
        min_bounces: 0,
    };
    Ok(reference_image(gpu, backend, scene, size, size, &settings)?.pixels)
}

/// Renders `scene` from its first camera (or the framing camera made for it) at
/// `width × height` with the reference path tracer: the scene is uploaded, its lights are
/// listed and the traversal is specialised for its shape.
pub fn reference_image(
    gpu: &Gpu,
    backend: Backend,
    scene: &Scene,
    width: u32,
    height: u32,
    settings: &ReferenceSettings,
) -> Result<ReferenceImage, GpuError> {
    let gpu_scene = GpuScene::new(gpu, scene, backend, &GpuSceneOptions::default())?;
    let renderer = ReferenceRenderer::new(gpu, backend, TraceVariant::for_scene(&gpu_scene))?;
    let camera = scene
        .camera(None)
        .ok_or_else(|| GpuError::BadScene("the scene has no camera".into()))?;
    renderer.render(
        gpu,
        &gpu_scene,
        &LightList::build(scene),
        &camera,
        width,
        height,
        settings,
        |_| {},
    )
}
