//! Helpers shared by the renderer tests (`realtime.rs`, `scene_shape.rs`): small settings,
//! scene upload and the reference tracer's images at pixel centres (`solari-reference`).
#![allow(dead_code)]

use solari_lights::LightTileSettings;
#[allow(unused_imports)] // not every test file compares images
pub use solari_reference::rmse;
use solari_renderer::{Antialias, FiniteCheck, RealtimeRenderer, RealtimeSettings};
use solari_restir::RestirDiSettings;
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
use solari_scene::shaders::Backend;
use solari_scene::{Camera, Scene};

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
            ..Default::default()
        },
        di: RestirDiSettings {
            spatial_radius: 3.0,
            ..Default::default()
        },
        // Every test frame is checked for NaN, infinite and negative values in every pass.
        finite_check: FiniteCheck::Fail,
        // One sample at each pixel's centre, as the pixel-centre references the tests compare
        // with; antialiasing (the default under the fallback denoiser) has its own tests in
        // `upscale.rs`.
        antialias: Antialias::Off,
        // Tests name the GI they exercise; the rest compare with direct-only references.
        ..RealtimeSettings::direct_only()
    }
}

pub fn upload(gpu: &Gpu, backend: Backend, scene: &Scene) -> GpuScene {
    GpuScene::new(gpu, scene, backend, &GpuSceneOptions::default()).expect("scene upload")
}

// The reference images and pixel helpers are solari-restir's test harness's.
#[path = "../../../solari-restir/tests/common/mod.rs"]
mod direct;

#[allow(unused_imports)] // not every test file uses every helper
pub use direct::{frame_mean, luminance, reference, reference_direct, rgb};

/// The Cornell box (or another scene, [`Cornell::with_scene`]) on the test GPU: device,
/// backend, scene, upload and camera.
pub struct Cornell {
    pub gpu: Gpu,
    pub backend: Backend,
    pub scene: Scene,
    pub gpu_scene: GpuScene,
    pub camera: Camera,
}

impl Cornell {
    /// `None` where there is no adapter (and CI does not require one: `test_gpu`'s rule).
    pub fn new() -> Option<Self> {
        Self::with_scene(solari_scene::default_scene::cornell_box())
    }

    /// The same for another scene (with its own camera), in place of the box.
    pub fn with_scene(scene: Scene) -> Option<Self> {
        let gpu = solari_scene::gpu::test_gpu()?;
        let backend = gpu.backend(Default::default()).expect("backend");
        let gpu_scene = upload(&gpu, backend, &scene);
        let camera = scene.camera(None).expect("camera");
        Some(Self {
            gpu,
            backend,
            scene,
            gpu_scene,
            camera,
        })
    }

    /// A `SIZE × SIZE` renderer of the scene with `settings`.
    pub fn renderer(&self, settings: RealtimeSettings) -> RealtimeRenderer {
        self.renderer_of(&self.scene, settings)
    }

    /// A `SIZE × SIZE` renderer built from `scene`'s lights and materials (the box with
    /// lights added or removed) over the box's uploaded geometry, with `settings`.
    pub fn renderer_of(&self, scene: &Scene, settings: RealtimeSettings) -> RealtimeRenderer {
        RealtimeRenderer::new(
            &self.gpu,
            self.backend,
            scene,
            &self.gpu_scene,
            SIZE,
            SIZE,
            settings,
        )
        .expect("renderer")
    }

    /// Renders one frame of `scene` (this box's camera) and returns the output's mean green.
    pub fn mean_green(&self, renderer: &mut RealtimeRenderer, scene: &Scene) -> f64 {
        renderer
            .render(&self.gpu, scene, &self.gpu_scene, &self.camera)
            .expect("frame");
        let pixels = renderer.read_output(&self.gpu).expect("read back");
        pixels.iter().map(|p| p[1] as f64).sum::<f64>() / pixels.len() as f64
    }
}
