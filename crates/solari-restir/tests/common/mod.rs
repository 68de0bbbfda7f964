//! The component frame the ReSTIR DI tests run (G-buffer → light tiles → ReSTIR DI, as the
//! renderer composes them, without it) and the reference tracer's images to compare with
//! (`solari-reference`). solari-worldcache's tests include this file too.
#![allow(dead_code)]

use solari_lights::{
    GpuLights, LightGrid, LightGridSettings, LightList, LightTileSettings, LightTiles, Selection,
};
use solari_reference::centre_image;
#[allow(unused_imports)] // not every including test compares images
pub use solari_reference::rmse;
use solari_restir::{RestirDi, RestirDiSettings};
use solari_scene::gbuffer::GBuffer;
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::pass::{FrameContext, Ran};
use solari_scene::shaders::Backend;
use solari_scene::{Camera, Scene};

/// Image side of the tests.
pub const SIZE: u32 = 64;

/// Small tiles keep lavapipe quick; the sampling is the same as with Solari's 128 × 1024.
pub fn tile_settings() -> LightTileSettings {
    LightTileSettings {
        tiles: 16,
        samples_per_tile: 256,
        ..Default::default()
    }
}

/// DI settings for 64-pixel images: Solari's 30-pixel spatial radius is meant for 900-1080
/// lines; on 64 it would reach half the image, where neighbours' target functions differ so
/// much that reuse stops paying (measured: no gain at 30 px, the ideal √2 at 3 px).
pub fn di_settings() -> RestirDiSettings {
    RestirDiSettings {
        spatial_radius: 3.0,
        ..Default::default()
    }
}

/// The light grid the tests build when [`RestirDiSettings::light_grid`] is on: few cells and
/// short lists, so that small scenes have truncated cells and lights left out of cells.
pub fn grid_settings() -> LightGridSettings {
    LightGridSettings {
        max_cells: 64,
        capacity: 4,
        ..Default::default()
    }
}

// The light list on the GPU, with a grid of `grid` when DI draws from one.
fn upload_lights(
    gpu: &Gpu,
    scene: &Scene,
    list: &LightList,
    di: &RestirDiSettings,
    grid: &LightGridSettings,
) -> GpuLights {
    let grid = di
        .light_grid
        .then(|| LightGrid::build(list, scene.bounds(), grid).expect("grid"));
    GpuLights::with_grid(gpu, list, Selection::Power, grid.as_ref()).expect("lights")
}

/// One scene's G-buffer, lights, light tiles and ReSTIR DI at `size × size`.
pub struct DirectLight {
    /// The tracer the passes were built for.
    pub backend: Backend,
    /// The scene on the GPU.
    pub gpu_scene: GpuScene,
    /// Solari's raster G-buffer.
    pub gbuffer: GBuffer,
    /// The light tiles.
    pub tiles: LightTiles,
    /// The scene's lights.
    pub lights: GpuLights,
    /// Tile reader group for `lights`.
    pub lights_group: wgpu::BindGroup,
    /// ReSTIR DI.
    pub di: RestirDi,
    list: LightList,
    grid: LightGridSettings,
    frame: u32,
    last_camera: Option<Camera>,
    context: Option<FrameContext<'static>>,
}

impl DirectLight {
    /// Uploads `scene` and builds the passes for `size × size` images.
    pub fn new(
        gpu: &Gpu,
        backend: Backend,
        scene: &Scene,
        size: u32,
        di: RestirDiSettings,
        tiles: LightTileSettings,
    ) -> Self {
        Self::new_sized(gpu, backend, scene, (size, size), di, tiles)
    }

    /// Uploads `scene` and builds the passes for `width × height` images.
    pub fn new_sized(
        gpu: &Gpu,
        backend: Backend,
        scene: &Scene,
        size: (u32, u32),
        di: RestirDiSettings,
        tiles: LightTileSettings,
    ) -> Self {
        Self::with_grid(gpu, backend, scene, size, di, tiles, grid_settings())
    }

    /// As [`DirectLight::new_sized`], with `grid`'s layout for the light grid (used when
    /// `di.light_grid` is on).
    pub fn with_grid(
        gpu: &Gpu,
        backend: Backend,
        scene: &Scene,
        (width, height): (u32, u32),
        di: RestirDiSettings,
        tiles: LightTileSettings,
        grid: LightGridSettings,
    ) -> Self {
        let gpu_scene =
            GpuScene::new(gpu, scene, backend, &GpuSceneOptions::default()).expect("upload");
        let list = LightList::build(scene);
        let lights = upload_lights(gpu, scene, &list, &di, &grid);
        let light_tiles = LightTiles::new(gpu, tiles).expect("tiles");
        let lights_group = light_tiles.reader_group(gpu, &lights);
        let variant = TraceVariant::for_scene(&gpu_scene);
        Self {
            backend,
            gbuffer: GBuffer::new(gpu, backend, width, height).expect("G-buffer"),
            di: RestirDi::new(gpu, backend, variant, width, height, di, tiles).expect("DI"),
            tiles: light_tiles,
            lights,
            lights_group,
            gpu_scene,
            list,
            grid,
            frame: 0,
            last_camera: None,
            context: None,
        }
    }

    /// Replaces the lights with `scene`'s, as the renderer does when lights change: reuse
    /// follows surviving lights to their new indices.
    pub fn set_lights(&mut self, gpu: &Gpu, scene: &Scene) {
        let list = LightList::build(scene);
        self.di
            .set_light_translation(list.translation_from(&self.list));
        self.lights = upload_lights(gpu, scene, &list, &self.di.settings(), &self.grid);
        self.lights_group = self.tiles.reader_group(gpu, &self.lights);
        self.list = list;
    }

    /// The context of the frame last prepared.
    pub fn context(&self) -> &FrameContext<'static> {
        self.context
            .as_ref()
            .expect("DirectLight::prepare made a frame context")
    }

    /// Prepares and records one frame's G-buffer, tiles and DI from `camera` into
    /// `encoder`, as the renderer does.
    pub fn encode(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        camera: &Camera,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Ran {
        self.prepare(gpu, scene, camera);
        self.encode_inputs(encoder);
        self.encode_di(encoder)
    }

    /// The CPU side of a frame: the frame context, then the passes' parameters.
    pub fn prepare(&mut self, gpu: &Gpu, scene: &Scene, camera: &Camera) {
        self.prepare_jittered(gpu, scene, camera, [0.0; 2]);
    }

    /// As [`DirectLight::prepare`], with the G-buffer's samples `jitter` pixels off the pixel
    /// centres, as the renderer's temporal upscaler asks.
    pub fn prepare_jittered(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        camera: &Camera,
        jitter: [f32; 2],
    ) {
        let previous = self.last_camera.replace(camera.clone());
        let context = FrameContext::new(self.frame, self.di.size(), camera, previous.as_ref());
        self.frame += 1;
        self.gbuffer
            .prepare_jittered(gpu, scene, camera, jitter)
            .expect("G-buffer");
        self.tiles.prepare(gpu, &context);
        self.di
            .prepare(gpu, &context, &self.gbuffer, &self.lights)
            .expect("DI prepare");
        self.context = Some(context);
    }

    /// Records what DI reads: the G-buffer and the light tiles.
    pub fn encode_inputs(&self, encoder: &mut wgpu::CommandEncoder) {
        self.gbuffer
            .encode(encoder, self.context(), &self.gpu_scene)
            .expect("G-buffer");
        self.tiles.encode(encoder, self.context(), &self.lights);
    }

    /// Records ReSTIR DI.
    pub fn encode_di(&mut self, encoder: &mut wgpu::CommandEncoder) -> Ran {
        let count = self.lights.light_count;
        let context = *self.context();
        self.di
            .encode(
                encoder,
                &context,
                &self.gpu_scene,
                &self.gbuffer,
                &self.lights_group,
                count,
            )
            .expect("DI encode")
    }

    /// One frame, submitted and read back: DI's output (`vec4<f32>` per pixel).
    pub fn render(&mut self, gpu: &Gpu, scene: &Scene, camera: &Camera) -> Vec<[f32; 4]> {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        self.encode(gpu, scene, camera, &mut encoder);
        gpu.queue.submit([encoder.finish()]);
        self.read_output(gpu)
    }

    /// DI's output of the last submitted frame.
    pub fn read_output(&self, gpu: &Gpu) -> Vec<[f32; 4]> {
        let (w, h) = self.di.size();
        let bytes = gpu
            .read_buffer(self.di.output(), w as u64 * h as u64 * 16)
            .expect("read back");
        bytemuck::cast_slice(&bytes).to_vec()
    }
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
    centre_image(gpu, backend, scene, size, spp, max_bounces).expect("reference render")
}

/// Rec. 709 luminance.
pub fn luminance(c: [f32; 3]) -> f64 {
    0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64
}

/// The rgb of `vec4` pixels.
pub fn rgb(pixels: &[[f32; 4]]) -> Vec<[f32; 3]> {
    pixels.iter().map(|p| [p[0], p[1], p[2]]).collect()
}

/// The mean of `frames` images that `next` renders one after another (accumulated in f64),
/// and the last one alone, as rgb.
pub fn frame_mean(
    frames: u32,
    mut next: impl FnMut() -> Vec<[f32; 4]>,
) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    let mut sum: Vec<[f64; 3]> = Vec::new();
    let mut last = Vec::new();
    for _ in 0..frames {
        last = rgb(&next());
        sum.resize(last.len(), [0.0; 3]);
        for (a, b) in sum.iter_mut().zip(&last) {
            for c in 0..3 {
                a[c] += b[c] as f64 / frames as f64;
            }
        }
    }
    let mean = sum.iter().map(|p| p.map(|v| v as f32)).collect();
    (mean, last)
}

/// Total light of `image` over that of `reference`, minus 1 (0: the same total).
pub fn total_light_bias(image: &[[f32; 3]], reference: &[[f32; 3]]) -> f64 {
    let total = |i: &[[f32; 3]]| i.iter().flatten().map(|&x| x as f64).sum::<f64>();
    total(image) / total(reference) - 1.0
}
