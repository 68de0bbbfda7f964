//! The raster G-buffer producer (`shaders/gbuffer_raster.wesl`): one non-indexed draw per
//! instance, vertices pulled from the scene's storage buffers, a reversed-Z depth test against
//! a Depth32Float buffer of its own, and four colour targets (the G-buffer's, depth included).

use crate::error::GpuError;
use crate::gbuffer::{
    DEPTH_FORMAT, EMISSION_FORMAT, GBUFFER_FORMAT, GBufferTargets, MOTION_FORMAT, PASS_LABELS,
};
use crate::gpu::{Gpu, ShaderChecks};
use crate::gpu_scene::GpuScene;
use crate::shaders::{Backend, compose};

// The depth test's format; readers see the R32Float copy (`DEPTH_FORMAT`).
const DEPTH_TEST_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

pub(crate) struct RasterProducer {
    pipeline: wgpu::RenderPipeline,
    // One depth-test buffer serves both target sets: last frame's depth lives in the copy.
    depth_test: wgpu::TextureView,
}

fn depth_test(gpu: &Gpu, size: (u32, u32)) -> wgpu::TextureView {
    gpu.texture_2d(
        "solari_scene/gbuffer_depth_test",
        size,
        DEPTH_TEST_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    )
    .create_view(&Default::default())
}

impl RasterProducer {
    /// `layouts`: groups 1 (view) and 2 (previous transforms).
    pub(crate) fn new(
        gpu: &Gpu,
        backend: Backend,
        layouts: [&wgpu::BindGroupLayout; 2],
        size: (u32, u32),
    ) -> Result<Self, GpuError> {
        let wgsl = compose("gbuffer_raster", backend, &[])?;
        let scene_layout = GpuScene::layout_for(gpu, backend);
        let pipeline = gpu.scoped(|| {
            let module = gpu.shader_module("solari_scene/gbuffer", &wgsl, ShaderChecks::BoundsOnly);
            let layout = gpu
                .device
                .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some("solari_scene/gbuffer"),
                    bind_group_layouts: &[Some(&scene_layout), Some(layouts[0]), Some(layouts[1])],
                    immediate_size: 0,
                });
            let target = |format| {
                Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })
            };
            gpu.device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some("solari_scene/gbuffer"),
                    layout: Some(&layout),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some("vs_main"),
                        compilation_options: Default::default(),
                        buffers: &[],
                    },
                    // No culling: materials may be double-sided, and the G-buffer must match
                    // what rays see either way.
                    primitive: wgpu::PrimitiveState::default(),
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_TEST_FORMAT,
                        depth_write_enabled: Some(true),
                        depth_compare: Some(wgpu::CompareFunction::Greater),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: Default::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some("fs_main"),
                        compilation_options: Default::default(),
                        // 16 + 8 + 4 + 4 bytes per pixel: exactly WebGPU's default limit
                        // on colour attachment bytes per sample (32).
                        targets: &[
                            target(GBUFFER_FORMAT),
                            target(EMISSION_FORMAT),
                            target(MOTION_FORMAT),
                            target(DEPTH_FORMAT),
                        ],
                    }),
                    multiview_mask: None,
                    cache: None,
                })
        })?;
        Ok(Self {
            pipeline,
            depth_test: depth_test(gpu, size),
        })
    }

    /// Bytes of the depth-test buffer.
    pub(crate) fn memory_bytes(&self) -> u64 {
        crate::gpu::texture_bytes(self.depth_test.texture())
    }

    pub(crate) fn resize(&mut self, gpu: &Gpu, size: (u32, u32)) {
        self.depth_test = depth_test(gpu, size);
    }

    /// Draws every instance (`draws`: vertex count and instance index) into `targets`.
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        groups: [&wgpu::BindGroup; 2],
        targets: &GBufferTargets,
        draws: &[(u32, u32)],
    ) {
        let attachment = |v| {
            Some(wgpu::RenderPassColorAttachment {
                view: v,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let [gbuffer, emission, motion, depth] = &targets.views;
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(PASS_LABELS[0]),
            color_attachments: &[
                attachment(gbuffer),
                attachment(emission),
                attachment(motion),
                attachment(depth),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth_test,
                // Reversed Z: 0 is infinitely far.
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, scene.bind_group(), &[]);
        pass.set_bind_group(1, groups[0], &[]);
        pass.set_bind_group(2, groups[1], &[]);
        for &(vertices, instance) in draws {
            pass.draw(0..vertices, instance..instance + 1);
        }
    }
}
