//! `TraceRaysPass`: traces a list of rays on the GPU and reads the hits back. Tests compare it
//! with [`crate::trace_cpu::CpuTracer`]; tools use it to probe a scene.

use crate::error::GpuError;
use crate::gpu::{Gpu, ShaderChecks};
use crate::gpu_scene::{GpuScene, TraceVariant};
use crate::gpu_types::{GpuRay, GpuRayHit};
use crate::shaders::{Backend, compose};

/// Compute pipeline for `trace_rays.wesl`.
pub struct TraceRaysPass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    empty: wgpu::BindGroupLayout,
    variant: TraceVariant,
}

impl TraceRaysPass {
    /// Builds the pipeline for `backend`.
    pub fn new(gpu: &Gpu, backend: Backend, variant: TraceVariant) -> Result<Self, GpuError> {
        let storage = |binding, read_only| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("solari_scene/trace_rays"),
                // binding 0: rays, binding 1: hits
                entries: &[storage(0, true), storage(1, false)],
            });
        let empty = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: None,
                entries: &[],
            });
        let scene_layout = GpuScene::layout_for(gpu, backend);
        let wgsl = compose("trace_rays", backend, &[])?;
        let pipeline = gpu.compute_pipeline(
            "solari_scene/trace_rays",
            &wgsl,
            &[Some(&scene_layout), Some(&empty), Some(&layout)],
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
        if rays.is_empty() {
            return Ok(Vec::new());
        }
        let ray_buf = gpu.storage_buffer(
            "solari_scene/rays",
            bytemuck::cast_slice(rays),
            wgpu::BufferUsages::empty(),
        )?;
        let hit_bytes = (rays.len() * size_of::<GpuRayHit>()) as u64;
        let hit_buf = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solari_scene/hits"),
            size: hit_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("solari_scene/trace_rays"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: ray_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: hit_buf.as_entire_binding(),
                },
            ],
        });
        let empty = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.empty,
            entries: &[],
        });
        let groups = (rays.len() as u32).div_ceil(64);
        // Stay under the 65535 workgroups-per-dimension limit by folding into y.
        let x = groups.min(65535);
        gpu.dispatch(
            "solari_scene/trace_rays",
            &self.pipeline,
            &[scene.bind_group(), &empty, &bind],
            [x, groups.div_ceil(x), 1],
        )?;
        let bytes = gpu.read_buffer(&hit_buf, hit_bytes)?;
        Ok(bytemuck::cast_slice(&bytes).to_vec())
    }
}
