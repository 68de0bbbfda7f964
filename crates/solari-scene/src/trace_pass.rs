//! `TraceRaysPass`: traces a list of rays on the GPU and reads the hits back. Tests compare it
//! with [`crate::trace_cpu::CpuTracer`]; tools use it to probe a scene.

use crate::bindings::{Buf, BufferGroup};
use crate::error::GpuError;
use crate::gpu::{Gpu, ShaderChecks};
use crate::gpu_scene::{GpuScene, TraceVariant};
use crate::gpu_types::{GpuRay, GpuRayHit};
use crate::shaders::{Backend, compose};

/// Group 2 of `trace_rays.wesl`: the rays in, one hit out per ray (bound by
/// [`crate::gpu::Gpu::run_cases`], which binds input then output).
pub const TRACE_RAYS_BINDINGS: BufferGroup =
    BufferGroup::new(2, 0, &[("rays", Buf::Read), ("hits", Buf::ReadWrite)]);

/// Compute pipeline for `trace_rays.wesl`.
pub struct TraceRaysPass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    // Kept with the pass: group 1 is unused but must be bound.
    empty: wgpu::BindGroup,
    variant: TraceVariant,
}

impl TraceRaysPass {
    /// Builds the pipeline for `backend`.
    pub fn new(gpu: &Gpu, backend: Backend, variant: TraceVariant) -> Result<Self, GpuError> {
        let layout = TRACE_RAYS_BINDINGS.layout(gpu, "solari_scene/trace_rays");
        let (empty_layout, empty) = gpu.empty_group();
        let scene_layout = GpuScene::layout_for(gpu, backend);
        let wgsl = compose("trace_rays", backend, &[])?;
        let pipeline = gpu.compute_pipeline(
            "solari_scene/trace_rays",
            &wgsl,
            &[Some(&scene_layout), Some(&empty_layout), Some(&layout)],
            ShaderChecks::BoundsOnly,
            variant.for_backend(backend).constants(),
        )?;
        Ok(Self {
            pipeline,
            layout,
            empty,
            variant: variant.for_backend(backend),
        })
    }

    /// Traces `rays` against `scene` and returns one hit per ray. Blocks until done.
    pub fn trace(
        &self,
        gpu: &Gpu,
        scene: &GpuScene,
        rays: &[GpuRay],
    ) -> Result<Vec<GpuRayHit>, GpuError> {
        self.variant.check(scene)?;
        gpu.run_cases(
            "solari_scene/trace_rays",
            &self.pipeline,
            &self.layout,
            &[Some(scene.bind_group()), Some(&self.empty), None],
            rays,
        )
    }
}
