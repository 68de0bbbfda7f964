//! The traced G-buffer producer (`shaders/gbuffer_traced.wesl`): one primary ray per pixel
//! (through its centre plus the view's jitter) through the scene's tracing backend, in a compute pass that writes the targets as
//! storage textures.

use crate::error::GpuError;
use crate::gbuffer::{
    DEPTH_FORMAT, EMISSION_FORMAT, GBUFFER_FORMAT, GBufferTargets, MOTION_FORMAT, PASS_LABELS,
};
use crate::gpu::{Gpu, ShaderChecks, loaded_texture_layout_entry, storage_texture_layout_entry};
use crate::gpu_scene::{GpuScene, TraceVariant};
use crate::shaders::{Backend, compose};

// Group 3's storage textures, in binding order (`gbuffer_out`, `emission_out`, `motion_out`,
// `depth_out`).
const OUTPUT_FORMATS: [wgpu::TextureFormat; 4] =
    [GBUFFER_FORMAT, EMISSION_FORMAT, MOTION_FORMAT, DEPTH_FORMAT];

pub(crate) struct TracedProducer {
    pipeline: wgpu::ComputePipeline,
    variant: TraceVariant,
    out_layout: wgpu::BindGroupLayout,
    // Group 3 per target set (frame parity).
    out_groups: [wgpu::BindGroup; 2],
}

impl TracedProducer {
    /// `layouts`: groups 1 (view) and 2 (previous transforms); `variant` already resolved for
    /// `backend`.
    pub(crate) fn new(
        gpu: &Gpu,
        backend: Backend,
        variant: TraceVariant,
        layouts: [&wgpu::BindGroupLayout; 2],
        targets: &[GBufferTargets; 2],
    ) -> Result<Self, GpuError> {
        let out_layout = traced_layout(gpu);
        let wgsl = compose("gbuffer_traced", backend, &[])?;
        let scene_layout = GpuScene::layout_for(gpu, backend);
        let pipeline = gpu.compute_pipeline(
            "solari_scene/gbuffer_traced",
            &wgsl,
            &[
                Some(&scene_layout),
                Some(layouts[0]),
                Some(layouts[1]),
                Some(&out_layout),
            ],
            ShaderChecks::BoundsOnly,
            variant.constants(),
        )?;
        let out_groups = traced_groups(gpu, &out_layout, targets);
        Ok(Self {
            pipeline,
            variant,
            out_layout,
            out_groups,
        })
    }

    /// The scene shape the pipeline was specialised for.
    pub(crate) fn variant(&self) -> TraceVariant {
        self.variant
    }

    /// New target sets (a resize).
    pub(crate) fn retarget(&mut self, gpu: &Gpu, targets: &[GBufferTargets; 2]) {
        self.out_groups = traced_groups(gpu, &self.out_layout, targets);
    }

    /// Traces every pixel of the target set `parity`.
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        groups: [&wgpu::BindGroup; 2],
        parity: usize,
        (width, height): (u32, u32),
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(PASS_LABELS[0]),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, scene.bind_group(), &[]);
        pass.set_bind_group(1, groups[0], &[]);
        pass.set_bind_group(2, groups[1], &[]);
        pass.set_bind_group(3, &self.out_groups[parity], &[]);
        pass.dispatch_workgroups(width.div_ceil(8), height.div_ceil(8), 1);
    }
}

// Binding of `depth_before` in the traced producer's group 3: the other target set's depth,
// last frame's, whose distances bound each ray's first try (`gbuffer_traced.wesl`).
const DEPTH_BEFORE_BINDING: u32 = 4;

// The traced producer's group 3: `out_layout`'s four storage textures and last frame's depth.
fn traced_layout(gpu: &Gpu) -> wgpu::BindGroupLayout {
    layout_of(gpu, "solari_scene/gbuffer_traced_out", true)
}

// One `traced_layout` group per target set: its outputs, and the other set's depth.
fn traced_groups(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    targets: &[GBufferTargets; 2],
) -> [wgpu::BindGroup; 2] {
    groups_of(gpu, layout, targets, true)
}

/// The layout of a group of one target set's four storage textures, in the order
/// `gbuffer_out`, `emission_out`, `motion_out`, `depth_out` (bindings 0-3): the override
/// pass's group 1 (the traced producer's group 3 adds last frame's depth).
pub(crate) fn out_layout(gpu: &Gpu, label: &str) -> wgpu::BindGroupLayout {
    layout_of(gpu, label, false)
}

/// One [`out_layout`] group per target set (frame parity).
pub(crate) fn out_groups(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    targets: &[GBufferTargets; 2],
) -> [wgpu::BindGroup; 2] {
    groups_of(gpu, layout, targets, false)
}

// The four outputs' layout, and with `depth_before` last frame's depth as binding 4.
fn layout_of(gpu: &Gpu, label: &str, depth_before: bool) -> wgpu::BindGroupLayout {
    let mut entries = OUTPUT_FORMATS
        .iter()
        .zip(0..)
        .map(|(&format, binding)| storage_texture_layout_entry(binding, format))
        .collect::<Vec<_>>();
    if depth_before {
        entries.push(loaded_texture_layout_entry(
            DEPTH_BEFORE_BINDING,
            wgpu::ShaderStages::COMPUTE,
        ));
    }
    gpu.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &entries,
        })
}

// One `layout_of` group per target set; with `depth_before`, the other set's depth.
fn groups_of(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    targets: &[GBufferTargets; 2],
    depth_before: bool,
) -> [wgpu::BindGroup; 2] {
    [0, 1].map(|parity| {
        let mut entries: Vec<_> = targets[parity]
            .views
            .iter()
            .zip(0..)
            .map(|(view, binding)| wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::TextureView(view),
            })
            .collect();
        if depth_before {
            entries.push(wgpu::BindGroupEntry {
                binding: DEPTH_BEFORE_BINDING,
                resource: wgpu::BindingResource::TextureView(&targets[parity ^ 1].views[3]),
            });
        }
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("solari_scene/gbuffer_traced_out"),
            layout,
            entries: &entries,
        })
    })
}
