//! The reference path tracer: progressive f32 accumulation of one path per pixel per
//! dispatch (`shaders/reference.wesl`), with next-event estimation and BRDF sampling combined
//! by MIS and Russian roulette. Beside the sums it keeps each pixel's spread of samples
//! (Welford's running second moment), so a finished image carries the variance of its own
//! mean: the noise it adds to any error measured against it
//! ([`crate::metrics::reference_noise`]).

use bytemuck::{Pod, Zeroable};
use solari_lights::{GpuLights, LightList, Selection};
use solari_scene::bindings::{Buf, BufferGroup};
use solari_scene::gpu::{Gpu, ShaderChecks};
use solari_scene::gpu_scene::{GpuScene, TraceVariant};
use solari_scene::gpu_types::GpuView;
use solari_scene::shaders::{Backend, compose};
use solari_scene::view_pass::VIEW_BINDINGS;
use solari_scene::{Camera, GpuError};
use std::time::Instant;

/// Hard limit on path length. Russian roulette ends paths long before it in any physical
/// scene; paths that reach it are counted in [`ReferenceImage::capped_paths`].
pub const SAFETY_CAP: u32 = 256;

/// Knobs of a reference render.
#[derive(Clone, Copy, Debug)]
pub struct ReferenceSettings {
    /// Paths per pixel.
    pub spp: u32,
    /// Scattering events per path; 1 gives direct light only, `u32::MAX` means no limit
    /// (only Russian roulette and [`SAFETY_CAP`]).
    pub max_bounces: u32,
    /// How next-event estimation picks lights.
    pub selection: Selection,
    /// Trace every path through its pixel's centre instead of a random point in the pixel.
    /// The image then point-samples like a G-buffer (no antialiasing), which is what the
    /// real-time renderer is compared against. Default: false.
    pub pixel_centre: bool,
    /// Leave out light that reaches the eye after fewer scattering events than this. 0 (the
    /// default) leaves nothing out; 1 leaves out emitters and the environment seen directly;
    /// 2 gives indirect light alone, what the real-time renderer's GI passes add
    /// (`solari_renderer::FrameView::Indirect`). The paths are the same at every value (the
    /// random numbers do not depend on it), so with equal seeds the image at 0 is the sum of
    /// the images of `max_bounces: 1` and `min_bounces: 2`. Above `max_bounces` the image is
    /// black.
    pub min_bounces: u32,
}

impl Default for ReferenceSettings {
    fn default() -> Self {
        Self {
            spp: 64,
            max_bounces: u32::MAX,
            selection: Selection::Power,
            pixel_centre: false,
            min_bounces: 0,
        }
    }
}

/// A finished reference render: linear radiance, row-major from the top left.
#[derive(Clone, Debug)]
pub struct ReferenceImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Mean radiance per pixel.
    pub pixels: Vec<[f32; 3]>,
    /// Per pixel and channel, the variance of [`Self::pixels`]' value as an estimate of the
    /// true radiance: the samples' variance over their count (0 below two samples). The
    /// expected squared error of the pixel, which an error metric against this image counts
    /// as if it were the test image's.
    pub variance: Vec<[f32; 3]>,
    /// Paths per pixel.
    pub spp: u32,
    /// Paths that hit [`SAFETY_CAP`] (reported; should be 0).
    pub capped_paths: u32,
    /// Path samples dropped because their value was not finite (reported; should be 0).
    pub rejected_samples: u32,
    /// Wall time of the render.
    pub seconds: f64,
}

/// WGSL twin: `ReferenceParams` in `reference.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ReferenceParams {
    /// Scattering events per path.
    pub max_bounces: u32,
    /// Seeds this dispatch's random numbers.
    pub sample_index: u32,
    /// [`SAFETY_CAP`].
    pub safety_cap: u32,
    /// 1: paths start at pixel centres ([`ReferenceSettings::pixel_centre`]).
    pub pixel_centre: u32,
    /// [`ReferenceSettings::min_bounces`].
    pub min_bounces: u32,
}

const _: () = assert!(size_of::<ReferenceParams>() == 20);

/// The app's own WESL modules.
pub const MODULES: &[(&str, &str)] = &[("reference", include_str!("../shaders/reference.wesl"))];

/// Group 2 of `reference.wesl`, by WGSL name: the running sums, the path counters, the
/// parameters and the running second moments (group 1 is the camera, [`VIEW_BINDINGS`]).
pub const REFERENCE_BINDINGS: BufferGroup = BufferGroup::new(
    2,
    0,
    &[
        ("accumulation", Buf::ReadWrite),
        ("counters", Buf::ReadWrite),
        ("params", Buf::Uniform),
        ("second_moment", Buf::ReadWrite),
    ],
);

/// The compiled path tracer for one backend.
pub struct ReferenceRenderer {
    pipeline: wgpu::ComputePipeline,
    view_layout: wgpu::BindGroupLayout,
    io_layout: wgpu::BindGroupLayout,
    variant: TraceVariant,
}

impl ReferenceRenderer {
    /// Composes and compiles the path tracer for `backend`.
    pub fn new(gpu: &Gpu, backend: Backend, variant: TraceVariant) -> Result<Self, GpuError> {
        let view_layout = VIEW_BINDINGS.layout(gpu, "solari_reference/reference_view");
        let io_layout = REFERENCE_BINDINGS.layout(gpu, "solari_reference/reference_io");
        let extra: Vec<(&str, &str)> = solari_lights::MODULES
            .iter()
            .chain(MODULES)
            .copied()
            .collect();
        let wgsl = compose("reference", backend, &extra)?;
        let scene_layout = GpuScene::layout_for(gpu, backend);
        let lights_layout = GpuLights::layout(gpu);
        let pipeline = gpu.compute_pipeline(
            "solari_reference/reference",
            &wgsl,
            &[
                Some(&scene_layout),
                Some(&view_layout),
                Some(&io_layout),
                Some(&lights_layout),
            ],
            ShaderChecks::BoundsOnly,
            variant.for_backend(backend).constants(),
        )?;
        Ok(Self {
            pipeline,
            view_layout,
            io_layout,
            variant: variant.for_backend(backend),
        })
    }

    /// Starts a progressive render of `camera`'s view: no samples yet.
    pub fn accumulation(
        &self,
        gpu: &Gpu,
        lights: &LightList,
        camera: &Camera,
        width: u32,
        height: u32,
        settings: &ReferenceSettings,
    ) -> Result<ReferenceAccumulation, GpuError> {
        let gpu_lights = GpuLights::new(gpu, lights, settings.selection)?;
        let accum_bytes = width as u64 * height as u64 * 16;
        gpu.check_storage_binding("reference accumulation buffer", accum_bytes)?;
        let storage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST;
        let buffer = |label, size, usage| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let accumulation = buffer(
            "solari_reference/accumulation",
            accum_bytes.max(16),
            storage,
        );
        let second_moment = buffer(
            "solari_reference/second_moment",
            accum_bytes.max(16),
            storage,
        );
        let counters = buffer("solari_reference/reference_counters", 8, storage);
        let view = GpuView::new(camera, width, height);
        let view_buf = gpu.uniform_buffer("solari_reference/reference_view", &view);
        let params = gpu.uniform_buffer(
            "solari_reference/reference_params",
            &ReferenceParams::zeroed(),
        );
        let view_group = VIEW_BINDINGS.bind(
            gpu,
            "solari_reference/reference_view",
            &self.view_layout,
            &[("view", &view_buf)],
        );
        let io_group = REFERENCE_BINDINGS.bind(
            gpu,
            "solari_reference/reference_io",
            &self.io_layout,
            &[
                ("accumulation", &accumulation),
                ("counters", &counters),
                ("params", &params),
                ("second_moment", &second_moment),
            ],
        );
        Ok(ReferenceAccumulation {
            width,
            height,
            settings: *settings,
            view,
            scene_generation: None,
            samples: 0,
            accumulation,
            second_moment,
            counters,
            view_buf,
            params,
            view_group,
            io_group,
            lights: gpu_lights,
            seconds: 0.0,
        })
    }

    /// Adds `n` paths per pixel, calling `progress` with the total after each. Restarts first
    /// if the scene's instances changed since the last call ([`GpuScene::generation`]).
    pub fn add_samples(
        &self,
        gpu: &Gpu,
        scene: &GpuScene,
        acc: &mut ReferenceAccumulation,
        n: u32,
        mut progress: impl FnMut(u32),
    ) -> Result<(), GpuError> {
        self.variant.check(scene)?;
        let start = Instant::now();
        if acc.scene_generation != Some(scene.generation()) {
            acc.reset(gpu);
            acc.scene_generation = Some(scene.generation());
        }
        for _ in 0..n {
            let params = ReferenceParams {
                max_bounces: acc.settings.max_bounces,
                sample_index: acc.samples,
                safety_cap: SAFETY_CAP,
                pixel_centre: acc.settings.pixel_centre.into(),
                min_bounces: acc.settings.min_bounces,
            };
            gpu.queue
                .write_buffer(&acc.params, 0, bytemuck::bytes_of(&params));
            gpu.dispatch(
                "solari_reference/reference",
                &self.pipeline,
                &[
                    scene.bind_group(),
                    &acc.view_group,
                    &acc.io_group,
                    &acc.lights.bind_group,
                ],
                [acc.width.div_ceil(8), acc.height.div_ceil(8), 1],
            )?;
            acc.samples += 1;
            // Keep the queue short so progress means something and memory stays bounded.
            if acc.samples.is_multiple_of(8) {
                gpu.device
                    .poll(wgpu::PollType::wait_indefinitely())
                    .map_err(|e| GpuError::Readback(format!("{e:?}")))?;
            }
            progress(acc.samples);
        }
        acc.seconds += start.elapsed().as_secs_f64();
        Ok(())
    }

    /// Reads back the mean of the samples so far.
    pub fn resolve(
        &self,
        gpu: &Gpu,
        acc: &ReferenceAccumulation,
    ) -> Result<ReferenceImage, GpuError> {
        let bytes = acc.width as u64 * acc.height as u64 * 16;
        let sums = gpu.read_buffer(&acc.accumulation, bytes)?;
        let sums: &[[f32; 4]] = bytemuck::cast_slice(&sums);
        let moments = gpu.read_buffer(&acc.second_moment, bytes)?;
        let moments: &[[f32; 4]] = bytemuck::cast_slice(&moments);
        let count = gpu.read_buffer(&acc.counters, 8)?;
        let count: &[u32] = bytemuck::cast_slice(&count);
        let pixels = sums
            .iter()
            .map(|s| {
                let n = s[3].max(1.0);
                [s[0] / n, s[1] / n, s[2] / n]
            })
            .collect();
        let variance = sums
            .iter()
            .zip(moments)
            .map(|(s, m)| {
                let n = s[3];
                if n < 2.0 {
                    return [0.0; 3];
                }
                // Sample variance M2 / (n - 1), over n for the mean's; rounding can leave
                // M2 a hair below 0 for a pixel whose samples are all equal.
                let scale = 1.0 / ((n - 1.0) * n);
                [0, 1, 2].map(|c| (m[c] * scale).max(0.0))
            })
            .collect();
        Ok(ReferenceImage {
            width: acc.width,
            height: acc.height,
            pixels,
            variance,
            spp: acc.samples,
            capped_paths: count[0],
            rejected_samples: count[1],
            seconds: acc.seconds,
        })
    }

    /// Renders `settings.spp` paths per pixel of `camera`'s view from scratch, calling
    /// `progress` with the number of samples done after each one.
    #[allow(clippy::too_many_arguments)]
    pub fn render(
        &self,
        gpu: &Gpu,
        scene: &GpuScene,
        lights: &LightList,
        camera: &Camera,
        width: u32,
        height: u32,
        settings: &ReferenceSettings,
        progress: impl FnMut(u32),
    ) -> Result<ReferenceImage, GpuError> {
        let start = Instant::now();
        let mut acc = self.accumulation(gpu, lights, camera, width, height, settings)?;
        self.add_samples(gpu, scene, &mut acc, settings.spp, progress)?;
        let mut image = self.resolve(gpu, &acc)?;
        image.seconds = start.elapsed().as_secs_f64();
        Ok(image)
    }
}

/// A progressive reference render: the running sums and what they were rendered with.
/// Changing the camera ([`ReferenceAccumulation::set_camera`]) or the scene's instances
/// restarts it, so stale samples never mix with new ones.
pub struct ReferenceAccumulation {
    width: u32,
    height: u32,
    settings: ReferenceSettings,
    view: GpuView,
    scene_generation: Option<u64>,
    samples: u32,
    accumulation: wgpu::Buffer,
    second_moment: wgpu::Buffer,
    counters: wgpu::Buffer,
    view_buf: wgpu::Buffer,
    params: wgpu::Buffer,
    view_group: wgpu::BindGroup,
    io_group: wgpu::BindGroup,
    lights: GpuLights,
    seconds: f64,
}

impl ReferenceAccumulation {
    /// Paths per pixel accumulated so far.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Drops every sample (the counters too).
    pub fn reset(&mut self, gpu: &Gpu) {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.clear_buffer(&self.accumulation, 0, None);
        encoder.clear_buffer(&self.second_moment, 0, None);
        encoder.clear_buffer(&self.counters, 0, None);
        gpu.queue.submit([encoder.finish()]);
        self.samples = 0;
        self.seconds = 0.0;
    }

    /// Points the render at `camera`; restarts it when the view changed. Returns whether it
    /// restarted.
    pub fn set_camera(&mut self, gpu: &Gpu, camera: &Camera) -> bool {
        let view = GpuView::new(camera, self.width, self.height);
        if bytemuck::bytes_of(&view) == bytemuck::bytes_of(&self.view) {
            return false;
        }
        self.view = view;
        gpu.queue
            .write_buffer(&self.view_buf, 0, bytemuck::bytes_of(&view));
        self.reset(gpu);
        true
    }
}
