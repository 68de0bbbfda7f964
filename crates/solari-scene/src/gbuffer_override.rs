//! G-buffer overrides: replacement guides that a pass writes for some pixels and that replace
//! those pixels' texels in this frame's targets after the lighting passes have read them.
//!
//! Primary surface replacement needs it: a mirror's primary surface is a flat plane, while
//! what the pixel shows is the surface it reflects. Denoisers and upscalers track and filter a
//! pixel by its guides (depth, normals, albedo, motion), so they must see the reflected
//! surface; the lighting passes must still see the mirror. The specular GI pass follows the
//! mirror bounces and writes the reflected surface's override (`solari_restir::SpecularGi`);
//! [`crate::gbuffer::GBuffer::apply_overrides`] then stores every written override into this
//! frame's targets.
//!
//! A writer stores, every frame, something for every pixel of the image: an override, or
//! `GBufferOverride()` (all zero: none). So the buffer holds nothing from frame to frame, and
//! may be shared scratch ([`crate::scratch`], [`crate::gbuffer::GBuffer::use_override_scratch`])
//! that other passes overwrite before the writer runs: 32 bytes per pixel (63 MiB at
//! 1920×1080) that the real-time renderer does not allocate.
//!
//! Because the replacement happens in place, next frame's `*_before` targets hold the
//! replaced pixels too: the denoiser's reprojection compares replaced with replaced, as it
//! must. Lighting passes that reuse last frame's samples see a mirror pixel's previous
//! surface as a different surface and start afresh there, which costs nothing: DI and diffuse
//! GI give a mirror no light.
//!
//! WGSL: `shaders/gbuffer_override.wesl` (`GBufferOverride`, `make_override`, `view_uv`) for
//! writers; `shaders/gbuffer_override_apply.wesl` is the apply pass. Memory: 32 bytes per
//! pixel, allocated by [`crate::gbuffer::GBuffer::enable_overrides`] only, unless shared.

use crate::bindings::{Buf, BufferGroup};
use crate::error::GpuError;
use crate::gbuffer::GBufferTargets;
use crate::gbuffer_traced::{out_groups, out_layout};
use crate::gpu::{Gpu, ShaderChecks};
use crate::pass::{FrameContext, Ran};
use crate::shaders::{Backend, compose};
use bytemuck::{Pod, Zeroable};

/// Bytes per pixel of the override buffer (WGSL `GBufferOverride`).
pub const OVERRIDE_BYTES: u64 = 32;

/// Group 0 of the apply pass, by WGSL name.
pub const APPLY_BINDINGS: BufferGroup = BufferGroup::new(
    0,
    0,
    &[("override_params", Buf::Uniform), ("overrides", Buf::Read)],
);

/// The apply pass's label (dispatch, profiler scope and report name).
pub const OVERRIDE_PASS_LABELS: [&str; 1] = ["gbuffer_override"];

/// WGSL twin: `OverrideParams` in `gbuffer_override_apply.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GpuOverrideParams {
    width: u32,
    height: u32,
    _pad: [u32; 2],
}

const _: () = assert!(size_of::<GpuOverrideParams>() == 16);

/// The override buffer and the pass that applies it to one of two target sets.
pub(crate) struct OverridePass {
    buffer: wgpu::Buffer,
    // Whether `buffer` is shared scratch (not counted as the G-buffer's memory).
    shared: bool,
    params: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    // Group 1 per target set (frame parity).
    out_groups: [wgpu::BindGroup; 2],
    size: (u32, u32),
}

impl OverridePass {
    /// For `targets` of `size` pixels, which must be storage textures.
    pub(crate) fn new(
        gpu: &Gpu,
        targets: &[GBufferTargets; 2],
        size: (u32, u32),
    ) -> Result<Self, GpuError> {
        let bytes = Self::bytes(size);
        gpu.check_storage_binding("G-buffer override buffer", bytes)?;
        // Zero-initialised by wgpu: no pixel has an override.
        let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solari_scene/gbuffer_overrides"),
            size: bytes.max(OVERRIDE_BYTES),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let params = gpu.uniform_buffer(
            "solari_scene/gbuffer_override_params",
            &GpuOverrideParams {
                width: size.0,
                height: size.1,
                _pad: [0; 2],
            },
        );
        let layout = APPLY_BINDINGS.layout(gpu, "solari_scene/gbuffer_override");
        let group = APPLY_BINDINGS.bind(
            gpu,
            "solari_scene/gbuffer_override",
            &layout,
            &[("override_params", &params), ("overrides", &buffer)],
        );
        let out_layout = out_layout(gpu, "solari_scene/gbuffer_override_out");
        // Backend-independent: the pass traces nothing.
        let wgsl = compose("gbuffer_override_apply", Backend::Software, &[])?;
        let pipeline = gpu.compute_pipeline(
            "solari_scene/gbuffer_override_apply",
            &wgsl,
            &[Some(&layout), Some(&out_layout)],
            ShaderChecks::BoundsOnly,
            &[],
        )?;
        let out_groups = out_groups(gpu, &out_layout, targets);
        Ok(Self {
            buffer,
            shared: false,
            params,
            layout,
            pipeline,
            group,
            out_groups,
            size,
        })
    }

    /// The per-pixel overrides (row-major, `OVERRIDE_BYTES` each) that writers bind.
    pub(crate) fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }

    /// Bytes of the override buffer for `size` pixels.
    pub(crate) fn bytes(size: (u32, u32)) -> u64 {
        size.0 as u64 * size.1 as u64 * OVERRIDE_BYTES
    }

    /// Replaces the own buffer by `scratch` (at least [`OverridePass::bytes`]), which the
    /// writers overwrite whole every frame.
    pub(crate) fn use_scratch(
        &mut self,
        gpu: &Gpu,
        scratch: &wgpu::Buffer,
    ) -> Result<(), GpuError> {
        crate::scratch::check("G-buffer overrides", scratch, Self::bytes(self.size))?;
        self.buffer = scratch.clone();
        self.shared = true;
        self.group = APPLY_BINDINGS.bind(
            gpu,
            "solari_scene/gbuffer_override",
            &self.layout,
            &[
                ("override_params", &self.params),
                ("overrides", &self.buffer),
            ],
        );
        Ok(())
    }

    pub(crate) fn shared(&self) -> bool {
        self.shared
    }

    pub(crate) fn memory_bytes(&self) -> u64 {
        let own = if self.shared { 0 } else { self.buffer.size() };
        own + self.params.size()
    }

    pub(crate) fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Applies the overrides to the target set `parity`.
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        parity: usize,
    ) -> Ran {
        let mut ran = Ran::none();
        let label = OVERRIDE_PASS_LABELS[0];
        frame.scope(label, encoder, &mut ran, |e| {
            let mut pass = e.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.group, &[]);
            pass.set_bind_group(1, &self.out_groups[parity], &[]);
            pass.dispatch_workgroups(self.size.0.div_ceil(8), self.size.1.div_ceil(8), 1);
        });
        ran
    }
}
