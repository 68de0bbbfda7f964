//! The fallback path's temporal upscaler (`shaders/temporal_upscale.wesl`): the lighting is
//! rendered at a fraction of the output's pixels with the camera jittered
//! ([`solari_scene::gpu_types::halton_jitter`]), and this pass accumulates the jittered
//! samples into an image at the output size: each frame's samples that fall inside the output
//! pixel (a box kernel), last frame's accumulation reprojected through the motion
//! vectors and clamped to the range of this frame's neighbouring samples, the two merged by
//! their weights. At a scale of 1 it antialiases (each pixel converges to its area average).
//! DLSS-RR does this itself and does not use it.

use bytemuck::{Pod, Zeroable};
use solari_scene::GpuError;
use solari_scene::bindings::{Buf, BufferGroup};
use solari_scene::gbuffer::GBuffer;
use solari_scene::gbuffer_input::GBufferSource;
use solari_scene::gpu::{Gpu, ShaderChecks};
use solari_scene::pass::{FrameContext, Ran};
use solari_scene::shaders::{Backend, compose};

/// Bind group 0 of `temporal_upscale.wesl`, by WGSL name (group 1 is the G-buffer reader).
pub const UPSCALE_BINDINGS: BufferGroup = BufferGroup::new(
    0,
    0,
    &[
        ("upscale_params", Buf::Uniform),
        ("render_color", Buf::Read),
        ("accum_before", Buf::Read),
        ("accum_now", Buf::ReadWrite),
        ("upscaled", Buf::ReadWrite),
    ],
);

/// The pass's label (profiler scope and report name).
pub const PASS_LABELS: [&str; 1] = ["temporal_upscale"];

/// WGSL twin: `UpscaleParams` in `temporal_upscale.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuUpscaleParams {
    /// Size of the jittered input, in pixels.
    pub render_size: [u32; 2],
    /// Size of the output, in pixels.
    pub output_size: [u32; 2],
    /// 1 drops the history.
    pub reset: u32,
    /// Most weight the history may hold ([`UpscaleSettings::max_weight`]).
    pub max_weight: f32,
    /// Padding.
    pub _pad: [u32; 2],
}

const _: () = assert!(size_of::<GpuUpscaleParams>() == 32);

/// The upscaler's knob.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UpscaleSettings {
    /// Most weight the accumulated history may hold, in frames of full-weight samples
    /// (default 16): more is smoother and slower to follow change.
    pub max_weight: f32,
}

impl Default for UpscaleSettings {
    fn default() -> Self {
        Self { max_weight: 16.0 }
    }
}

/// The temporal upscaler and its accumulation buffers (see the module docs).
pub struct TemporalUpscaler {
    settings: UpscaleSettings,
    render_size: (u32, u32),
    output_size: (u32, u32),
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    accum: [wgpu::Buffer; 2],
    output: wgpu::Buffer,
    // Bind groups per parity for the input buffer last given (rebuilt when it changes).
    groups: Option<(wgpu::Buffer, [wgpu::BindGroup; 2])>,
    parity: usize,
    history: bool,
}

impl TemporalUpscaler {
    /// Builds the pass for `render_size` inputs and `output_size` outputs (each side of the
    /// output at least the input's).
    pub fn new(
        gpu: &Gpu,
        render_size: (u32, u32),
        output_size: (u32, u32),
        settings: UpscaleSettings,
    ) -> Result<Self, GpuError> {
        if render_size.0 == 0
            || render_size.1 == 0
            || output_size.0 < render_size.0
            || output_size.1 < render_size.1
        {
            return Err(GpuError::Validation(format!(
                "temporal upscaler: {}×{} to {}×{} (the output must be at least the input, \
                 neither empty)",
                render_size.0, render_size.1, output_size.0, output_size.1
            )));
        }
        if !(settings.max_weight.is_finite() && settings.max_weight >= 1.0) {
            return Err(GpuError::Validation(format!(
                "temporal upscaler: max_weight {} must be at least 1",
                settings.max_weight
            )));
        }
        let bytes = output_size.0 as u64 * output_size.1 as u64 * 16;
        let limit = gpu.device.limits().max_storage_buffer_binding_size;
        if bytes > limit {
            return Err(GpuError::OverLimit {
                what: "temporal upscaler output".into(),
                needed: bytes,
                limit,
            });
        }
        let layout = UPSCALE_BINDINGS.layout(gpu, "solari_denoise/upscale");
        let gbuffer_layout = GBuffer::reader_layout(gpu);
        let wgsl = compose("temporal_upscale", Backend::Software, &crate::modules())?;
        let pipeline = gpu.compute_pipeline(
            "solari_denoise/temporal_upscale",
            &wgsl,
            &[Some(&layout), Some(&gbuffer_layout)],
            ShaderChecks::BoundsOnly,
            &[],
        )?;
        let storage = |label: &str| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        Ok(Self {
            settings,
            render_size,
            output_size,
            pipeline,
            layout,
            params: gpu
                .uniform_buffer("solari_denoise/upscale_params", &GpuUpscaleParams::zeroed()),
            accum: [
                storage("solari_denoise/upscale_accum_a"),
                storage("solari_denoise/upscale_accum_b"),
            ],
            output: storage("solari_denoise/upscaled"),
            groups: None,
            parity: 0,
            history: false,
        })
    }

    /// Records the pass: `input` (one `vec4<f32>` per render pixel, the frame's lighting)
    /// upscaled into [`TemporalUpscaler::output`], reading jitter and motion from `gbuffer`
    /// (which must be [`TemporalUpscaler::render_size`]). `reset` drops the history (camera
    /// cut); it is dropped too on the first frame and when the G-buffer has none.
    pub fn encode(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        gbuffer: &dyn GBufferSource,
        input: &wgpu::Buffer,
        reset: bool,
    ) -> Result<Ran, GpuError> {
        if gbuffer.size() != self.render_size {
            return Err(GpuError::Validation(format!(
                "temporal upscaler built for {:?} was given a {:?} G-buffer",
                self.render_size,
                gbuffer.size()
            )));
        }
        let pixels = self.render_size.0 as u64 * self.render_size.1 as u64;
        if input.size() < pixels * 16 {
            return Err(GpuError::Validation(format!(
                "temporal upscaler: input of {} bytes for {pixels} pixels",
                input.size()
            )));
        }
        let reset = reset || !self.history || !gbuffer.history_valid();
        let params = GpuUpscaleParams {
            render_size: [self.render_size.0, self.render_size.1],
            output_size: [self.output_size.0, self.output_size.1],
            reset: reset as u32,
            max_weight: self.settings.max_weight,
            _pad: [0; 2],
        };
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        if self.groups.as_ref().is_none_or(|(b, _)| b != input) {
            let groups = [0, 1].map(|parity| {
                UPSCALE_BINDINGS.bind(
                    gpu,
                    "solari_denoise/upscale",
                    &self.layout,
                    &[
                        ("upscale_params", &self.params),
                        ("render_color", input),
                        ("accum_before", &self.accum[parity ^ 1]),
                        ("accum_now", &self.accum[parity]),
                        ("upscaled", &self.output),
                    ],
                )
            });
            self.groups = Some((input.clone(), groups));
        }
        self.parity ^= 1;
        let group = &self.groups.as_ref().expect("made above").1[self.parity];
        let gbuffer_group = gbuffer.bind_group()?;
        let (w, h) = self.output_size;
        let mut ran = Ran::none();
        frame.scope(PASS_LABELS[0], encoder, &mut ran, |e| {
            let mut pass = e.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(PASS_LABELS[0]),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.set_bind_group(1, gbuffer_group, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        });
        self.history = true;
        Ok(ran)
    }

    /// The upscaled image: one `vec4<f32>` per output pixel (alpha 1).
    pub fn output(&self) -> &wgpu::Buffer {
        &self.output
    }

    /// Input size in pixels.
    pub fn render_size(&self) -> (u32, u32) {
        self.render_size
    }

    /// Output size in pixels.
    pub fn output_size(&self) -> (u32, u32) {
        self.output_size
    }

    /// GPU memory the upscaler holds, in bytes.
    pub fn memory_bytes(&self) -> u64 {
        self.accum.iter().map(|b| b.size()).sum::<u64>() + self.output.size() + self.params.size()
    }
}
