//! One-call reference images of a whole scene, for tests that compare a component's output
//! with the ground truth.

use crate::path_tracer::{ReferenceImage, ReferenceRenderer, ReferenceSettings};
use solari_lights::LightList;
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::shaders::Backend;
use solari_scene::{GpuError, Scene};

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
