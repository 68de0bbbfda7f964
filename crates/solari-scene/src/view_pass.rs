//! Per-pixel passes over a camera view: the primary-ray debug views and the ray-throughput
//! benchmark. Both bind group 0 (scene), 1 (view uniform) and 2 (one output buffer).

use crate::bindings::{Buf, BufferGroup};
use crate::error::GpuError;
use crate::gpu::{Gpu, ShaderChecks};
use crate::gpu_scene::{GpuScene, TraceVariant};
use crate::gpu_types::GpuView;
use crate::shaders::{Backend, compose};

/// What the primary pass writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DebugView {
    /// Base colour after textures (the environment colour on a miss).
    Albedo = 0,
    /// Shading normal mapped to \[0, 1\].
    Normal = 1,
    /// Distance from the camera.
    Depth = 2,
    /// Instance index.
    Instance = 3,
}

impl DebugView {
    /// Parses `albedo`, `normal`, `depth` or `instance`.
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "albedo" => Self::Albedo,
            "normal" => Self::Normal,
            "depth" => Self::Depth,
            "instance" => Self::Instance,
            _ => return None,
        })
    }
}

/// Group 1 of the view passes (`view.wesl`): the camera.
pub const VIEW_BINDINGS: BufferGroup = BufferGroup::new(1, 0, &[("view", Buf::Uniform)]);
/// Group 2 of `primary.wesl`: one `vec4<f32>` per pixel.
pub const PRIMARY_BINDINGS: BufferGroup = BufferGroup::new(2, 0, &[("out_pixels", Buf::ReadWrite)]);
/// Group 2 of `ray_bench.wesl`: one ray count per pixel.
pub const RAY_BENCH_BINDINGS: BufferGroup =
    BufferGroup::new(2, 0, &[("out_counts", Buf::ReadWrite)]);

// What distinguishes the view passes: entry point, label, output group, bytes per pixel.
#[derive(Clone, Copy)]
struct Shape {
    entry: &'static str,
    label: &'static str,
    out: &'static BufferGroup,
    element_size: u64,
}

const PRIMARY: Shape = Shape {
    entry: "primary",
    label: "solari_scene/primary",
    out: &PRIMARY_BINDINGS,
    element_size: 16,
};

const RAY_BENCH: Shape = Shape {
    entry: "ray_bench",
    label: "solari_scene/ray_bench",
    out: &RAY_BENCH_BINDINGS,
    element_size: 4,
};

/// A compute pass over every pixel of a view, writing one output element per pixel.
pub struct ViewPass {
    pipeline: wgpu::ComputePipeline,
    view_layout: wgpu::BindGroupLayout,
    out_layout: wgpu::BindGroupLayout,
    out: &'static BufferGroup,
    element_size: u64,
    label: &'static str,
    variant: TraceVariant,
}

impl ViewPass {
    /// The primary-ray debug-view pass (`primary.wesl`, 16 bytes per pixel).
    pub fn primary(gpu: &Gpu, backend: Backend, variant: TraceVariant) -> Result<Self, GpuError> {
        Self::new(gpu, backend, &PRIMARY, ShaderChecks::BoundsOnly, variant)
    }

    /// Rays a run of the [`ViewPass::ray_bench`] pass traced, from its output (one `u32` per
    /// pixel: 1 = a primary ray only, 2 = plus a hemisphere ray that missed, 3 = one that hit).
    pub fn bench_ray_count(output: &[u8]) -> u64 {
        let counts: &[u32] = bytemuck::cast_slice(output);
        counts.iter().map(|&c| if c >= 2 { 2 } else { 1 }).sum()
    }

    /// The ray-throughput benchmark pass (`ray_bench.wesl`, 4 bytes per pixel), compiled with
    /// the given runtime checks so their cost can be measured.
    pub fn ray_bench(
        gpu: &Gpu,
        backend: Backend,
        checks: ShaderChecks,
        variant: TraceVariant,
    ) -> Result<Self, GpuError> {
        Self::new(gpu, backend, &RAY_BENCH, checks, variant)
    }

    fn new(
        gpu: &Gpu,
        backend: Backend,
        shape: &'static Shape,
        checks: ShaderChecks,
        variant: TraceVariant,
    ) -> Result<Self, GpuError> {
        let Shape {
            entry,
            label,
            out,
            element_size,
        } = *shape;
        let view_layout = VIEW_BINDINGS.layout(gpu, "solari_scene/view");
        let out_layout = out.layout(gpu, label);
        let scene_layout = GpuScene::layout_for(gpu, backend);
        let wgsl = compose(entry, backend, &[])?;
        let pipeline = gpu.compute_pipeline(
            label,
            &wgsl,
            &[Some(&scene_layout), Some(&view_layout), Some(&out_layout)],
            checks,
            variant.for_backend(backend).constants(),
        )?;
        Ok(Self {
            pipeline,
            view_layout,
            out_layout,
            out,
            element_size,
            label,
            variant: variant.for_backend(backend),
        })
    }

    /// Resources for one view size: the view uniform, the output buffer and bind groups.
    pub fn target(&self, gpu: &Gpu, view: &GpuView) -> Result<ViewTarget, GpuError> {
        let pixels = view.width as u64 * view.height as u64;
        let size = pixels * self.element_size;
        gpu.check_storage_binding(&format!("{} output", self.label), size)?;
        let uniform = gpu.uniform_buffer("solari_scene/view", view);
        let output = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(self.label),
            size: size.max(16),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let view_group = VIEW_BINDINGS.bind(
            gpu,
            "solari_scene/view",
            &self.view_layout,
            &[("view", &uniform)],
        );
        let name = self.out.bindings[0].0;
        let out_group = self
            .out
            .bind(gpu, self.label, &self.out_layout, &[(name, &output)]);
        Ok(ViewTarget {
            uniform,
            output,
            view_group,
            out_group,
            view: *view,
            bytes: size,
        })
    }

    /// Records the pass; `timestamps` brackets it with two timestamp queries. Fails when the
    /// pass was specialised for a different scene shape ([`TraceVariant::check`]).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        target: &ViewTarget,
        timestamps: Option<(&wgpu::QuerySet, u32)>,
    ) -> Result<(), GpuError> {
        self.variant.check(scene)?;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(self.label),
            timestamp_writes: timestamps.map(|(set, i)| wgpu::ComputePassTimestampWrites {
                query_set: set,
                beginning_of_pass_write_index: Some(i),
                end_of_pass_write_index: Some(i + 1),
            }),
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, scene.bind_group(), &[]);
        pass.set_bind_group(1, &target.view_group, &[]);
        pass.set_bind_group(2, &target.out_group, &[]);
        pass.dispatch_workgroups(
            target.view.width.div_ceil(8),
            target.view.height.div_ceil(8),
            1,
        );
        Ok(())
    }

    /// Runs the pass once and reads the output back.
    pub fn run(
        &self,
        gpu: &Gpu,
        scene: &GpuScene,
        target: &ViewTarget,
    ) -> Result<Vec<u8>, GpuError> {
        gpu.scoped(|| {
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            self.encode(&mut encoder, scene, target, None)?;
            gpu.queue.submit([encoder.finish()]);
            Ok::<(), GpuError>(())
        })??;
        gpu.read_buffer(&target.output, target.bytes)
    }
}

/// Per-size resources of a [`ViewPass`].
pub struct ViewTarget {
    /// The view uniform buffer (rewrite it with `queue.write_buffer` to change frames).
    pub uniform: wgpu::Buffer,
    /// The output buffer.
    pub output: wgpu::Buffer,
    view_group: wgpu::BindGroup,
    out_group: wgpu::BindGroup,
    /// The view these resources were made for.
    pub view: GpuView,
    bytes: u64,
}
