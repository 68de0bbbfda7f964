//! Debug views of the G-buffer: one channel of this frame's G-buffer per pixel (base colour,
//! normals, roughness, metallic, emission, depth, motion), written into an RGBA output
//! buffer for the viewer and for checking what a G-buffer producer wrote.
//!
//! Works on any [`GBufferSource`]: Solari's raster or traced G-buffer, or a user's own
//! ([`crate::gbuffer_input`]). The output is *display-referred*: present it without exposure
//! or tone curve, sRGB-encoded ([`GBufferChannel::shown`] is the value a pixel shows). Colour
//! channels (base colour, emission) are linear colour clamped to \[0, 1\]; the others are
//! mapped as [`GBufferChannel`]'s variants say.
//!
//! ```no_run
//! # use solari_scene::{gpu::Gpu, gbuffer::GBuffer, pass::FrameContext};
//! # use solari_scene::gbuffer_debug::{GBufferChannel, GBufferDebug};
//! # fn f(gpu: &Gpu, gbuffer: &GBuffer, frame: &FrameContext, out: &wgpu::Buffer)
//! #     -> Result<(), solari_scene::GpuError> {
//! let mut debug = GBufferDebug::new(gpu, out, gbuffer.size())?;
//! debug.prepare(gpu, GBufferChannel::Normal, 20.0);
//! let mut encoder = gpu.device.create_command_encoder(&Default::default());
//! debug.encode(&mut encoder, frame, gbuffer)?;
//! gpu.queue.submit([encoder.finish()]);
//! # Ok(()) }
//! ```

use crate::bindings::{Buf, BufferGroup};
use crate::error::GpuError;
use crate::gbuffer_input::{GBufferSource, check_size, reader_layout};
use crate::gpu::{Gpu, ShaderChecks};
use crate::pass::{FrameContext, Ran};
use crate::shaders::{Backend, compose};
use bytemuck::{Pod, Zeroable};

/// One G-buffer channel to show.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum GBufferChannel {
    /// Base colour after textures (linear, as stored).
    BaseColor = 0,
    /// Shading normal (after normal maps), shown as `n * 0.5 + 0.5`.
    Normal = 1,
    /// Geometric (triangle) normal, shown as `n * 0.5 + 0.5`.
    GeometricNormal = 2,
    /// Roughness, as grey.
    Roughness = 3,
    /// Metallic, as grey.
    Metallic = 4,
    /// Emitted radiance, clamped to 1.
    Emission = 5,
    /// Distance along the view axis, shown as `1 - 0.9 z / far` (near bright) where `far`
    /// is what [`GBufferDebug::prepare`] is given.
    Depth = 6,
    /// Screen motion since last frame, shown as `0.5 + pixels / 32` in red (x) and green
    /// (y): grey when still, saturated at 16 pixels per frame.
    Motion = 7,
}

impl GBufferChannel {
    /// Every channel, in order.
    pub const ALL: [Self; 8] = [
        Self::BaseColor,
        Self::Normal,
        Self::GeometricNormal,
        Self::Roughness,
        Self::Metallic,
        Self::Emission,
        Self::Depth,
        Self::Motion,
    ];

    /// The channel's name: `base-color`, `normal`, `geometric-normal`, `roughness`,
    /// `metallic`, `emission`, `depth` or `motion`.
    pub fn name(self) -> &'static str {
        match self {
            Self::BaseColor => "base-color",
            Self::Normal => "normal",
            Self::GeometricNormal => "geometric-normal",
            Self::Roughness => "roughness",
            Self::Metallic => "metallic",
            Self::Emission => "emission",
            Self::Depth => "depth",
            Self::Motion => "motion",
        }
    }

    /// The channel named `s` ([`GBufferChannel::name`]).
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.name() == s)
    }

    /// The value in \[0, 1\] that an output pixel shows: its sRGB encoding (the present's
    /// transfer function), so `shown(out)` gives back `n * 0.5 + 0.5` for normals, the
    /// roughness for roughness, and so on.
    pub fn shown(linear: f32) -> f32 {
        let l = linear.clamp(0.0, 1.0);
        if l <= 0.003_130_8 {
            l * 12.92
        } else {
            1.055 * l.powf(1.0 / 2.4) - 0.055
        }
    }
}

/// Group 0 of `gbuffer_debug.wesl`, by WGSL name.
pub const GBUFFER_DEBUG_BINDINGS: BufferGroup = BufferGroup::new(
    0,
    0,
    &[
        ("debug_params", Buf::Uniform),
        ("debug_out", Buf::ReadWrite),
    ],
);

/// The pass's label (dispatch, profiler scope and report name).
pub const GBUFFER_DEBUG_LABELS: [&str; 1] = ["gbuffer_debug"];

/// WGSL twin: `GBufferDebugParams`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GpuGBufferDebugParams {
    width: u32,
    height: u32,
    channel: u32,
    depth_far: f32,
}

const _: () = assert!(size_of::<GpuGBufferDebugParams>() == 16);

/// The debug-view pass: reads a G-buffer of `size` pixels, writes one `vec4<f32>` per pixel
/// into the output buffer it was made with.
pub struct GBufferDebug {
    pipeline: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    group: wgpu::BindGroup,
    size: (u32, u32),
}

impl GBufferDebug {
    /// Builds the pass writing into `out` (`STORAGE`, at least `size.0 × size.1 × 16`
    /// bytes). Errors on a smaller buffer.
    pub fn new(gpu: &Gpu, out: &wgpu::Buffer, size: (u32, u32)) -> Result<Self, GpuError> {
        let needed = size.0 as u64 * size.1 as u64 * 16;
        if out.size() < needed {
            return Err(GpuError::Validation(format!(
                "G-buffer debug view: the output buffer holds {} bytes, {}×{} pixels need {needed}",
                out.size(),
                size.0,
                size.1
            )));
        }
        let layout = GBUFFER_DEBUG_BINDINGS.layout(gpu, "solari_scene/gbuffer_debug");
        let params = gpu.uniform_buffer(
            "solari_scene/gbuffer_debug_params",
            &GpuGBufferDebugParams::zeroed(),
        );
        let group = GBUFFER_DEBUG_BINDINGS.bind(
            gpu,
            "solari_scene/gbuffer_debug",
            &layout,
            &[("debug_params", &params), ("debug_out", out)],
        );
        // Backend-independent: the pass traces nothing.
        let wgsl = compose("gbuffer_debug", Backend::Software, &[])?;
        let pipeline = gpu.compute_pipeline(
            "solari_scene/gbuffer_debug",
            &wgsl,
            &[Some(&layout), Some(&reader_layout(gpu))],
            ShaderChecks::BoundsOnly,
            &[],
        )?;
        Ok(Self {
            pipeline,
            params,
            group,
            size,
        })
    }

    /// Sets the channel to show and, for [`GBufferChannel::Depth`], the distance shown
    /// darkest (non-positive or non-finite values fall back to 1).
    pub fn prepare(&mut self, gpu: &Gpu, channel: GBufferChannel, depth_far: f32) {
        let depth_far = if depth_far.is_finite() && depth_far > 0.0 {
            depth_far
        } else {
            1.0
        };
        let params = GpuGBufferDebugParams {
            width: self.size.0,
            height: self.size.1,
            channel: channel as u32,
            depth_far,
        };
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
    }

    /// Records the pass. Errors, recording nothing, on a G-buffer of another size.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        gbuffer: &dyn GBufferSource,
    ) -> Result<Ran, GpuError> {
        check_size("G-buffer debug view", self.size, gbuffer)?;
        let reader = gbuffer.bind_group()?;
        let label = GBUFFER_DEBUG_LABELS[0];
        let mut ran = Ran::none();
        frame.scope(label, encoder, &mut ran, |e| {
            let mut pass = e.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.group, &[]);
            pass.set_bind_group(1, reader, &[]);
            pass.dispatch_workgroups(self.size.0.div_ceil(8), self.size.1.div_ceil(8), 1);
        });
        Ok(ran)
    }
}
