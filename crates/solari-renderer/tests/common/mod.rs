//! Helpers shared by the renderer tests (`realtime.rs`, `scene_shape.rs`): small settings,
//! scene upload and the reference tracer's images at pixel centres (`solari-reference`).
#![allow(dead_code)]

use solari_lights::{LightTileSettings, Selection};
#[allow(unused_imports)] // not every test file compares images
pub use solari_reference::rmse;
use solari_reference::{ReferenceSettings, reference_image};
use solari_renderer::{FiniteCheck, RealtimeSettings};
use solari_restir::RestirDiSettings;
use solari_scene::Scene;
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
use solari_scene::shaders::Backend;

/// Image side of the renderer tests.
pub const SIZE: u32 = 64;

// Small tiles keep lavapipe quick; the sampling is the same as with Solari's 128 × 1024. The
// spatial radius shrinks with the image: Solari's 30 px are meant for 900-1080 lines, and on
// 64 they would reach half the image, where neighbours' target functions differ so much that
// reuse stops paying (measured: no gain at 30 px, the ideal √2 at 3 px).
pub fn settings() -> RealtimeSettings {
    RealtimeSettings {
        tiles: LightTileSettings {
            tiles: 16,
            samples_per_tile: 256,
        },
        di: RestirDiSettings {
            spatial_radius: 3.0,
            ..Default::default()
        },
        // Every test frame is checked for NaN, infinite and negative values in every pass.
        finite_check: FiniteCheck::Fail,
        ..Default::default()
    }
}

pub fn upload(gpu: &Gpu, backend: Backend, scene: &Scene) -> GpuScene {
    GpuScene::new(gpu, scene, backend, &GpuSceneOptions::default()).expect("scene upload")
}

/// The reference tracer's direct-only image at pixel centres (what the G-buffer sees),
/// `size × size`.
pub fn reference_direct(
    gpu: &Gpu,
    backend: Backend,
    scene: &Scene,
    size: u32,
    spp: u32,
) -> Vec<[f32; 3]> {
    reference(gpu, backend, scene, size, spp, 1)
}

/// The reference tracer's image at pixel centres with paths of at most `max_bounces`
/// scattering events (`u32::MAX`: Russian roulette alone ends them), `size × size`.
pub fn reference(
    gpu: &Gpu,
    backend: Backend,
    scene: &Scene,
    size: u32,
    spp: u32,
    max_bounces: u32,
) -> Vec<[f32; 3]> {
    let settings = ReferenceSettings {
        spp,
        max_bounces,
        selection: Selection::Power,
        pixel_centre: true,
    };
    reference_image(gpu, backend, scene, size, size, &settings)
        .expect("reference render")
        .pixels
}

pub fn luminance(c: [f32; 3]) -> f64 {
    0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64
}

pub fn rgb(pixels: &[[f32; 4]]) -> Vec<[f32; 3]> {
    pixels.iter().map(|p| [p[0], p[1], p[2]]).collect()
}
