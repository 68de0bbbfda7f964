//! The temporal upscaler's guide (`shaders/primary_depth.wesl`): each output pixel's G-buffer
//! depth (znear / view-axis distance, 0 for background), negated where the surface emits,
//! in a storage buffer, one `f32` per pixel in rows.
//!
//! The upscaler reads it to tell which surface each output pixel shows where its nearest
//! render samples, 1.5–2 output pixels apart, straddle a silhouette or an emitter's edge
//! (`solari_denoise::TemporalUpscaler::encode`'s `guide`). Two samples are of one surface
//! when their depths are within 1.1× of each other and both emit or neither: a lamp low over
//! a floor, or a light panel in a ceiling, is within 1.1× of the depth behind its edge, and
//! by depth alone its light spread a pixel into the dark around it along a moving camera.
//! Only the straddling pixels trace a primary ray of their own (unjittered, through the
//! scene's tracing backend, its first try no farther than the pixel's last depth, as the
//! traced G-buffer's; whether the hit emits as the G-buffer writes it: front faces, or
//! double-sided materials); the others copy their nearest sample's value from the
//! render-size G-buffer, which is what the upscaler would decide by anyway. 4 bytes a pixel
//! and nothing else: the buffer keeps last frame's depth for the first try.
//!
//! ```no_run
//! # use solari_scene::{gbuffer::GBuffer, gpu::Gpu, gpu_scene::{GpuScene, TraceVariant},
//! #     model::Camera, pass::FrameContext, primary_depth::PrimaryDepth};
//! # fn f(gpu: &Gpu, gpu_scene: &GpuScene, gbuffer: &GBuffer, camera: &Camera) -> Result<(), solari_scene::error::GpuError> {
//! // A 640 × 360 guide for a G-buffer rendered at half that size and already encoded.
//! let guide = PrimaryDepth::new(gpu, gpu_scene.backend, TraceVariant::for_scene(gpu_scene), (640, 360))?;
//! guide.prepare(gpu, camera);
//! let mut encoder = gpu.device.create_command_encoder(&Default::default());
//! guide.encode(&mut encoder, &FrameContext::new(0, (640, 360), camera, None), gpu_scene, gbuffer)?;
//! gpu.queue.submit([encoder.finish()]);
//! // guide.depth(): 640 × 360 f32, row by row (negative: an emitting surface).
//! # Ok(()) }
//! ```

use crate::bindings::{Buf, BufferGroup};
use crate::error::GpuError;
use crate::gbuffer::GBuffer;
use crate::gbuffer_input::GBufferSource;
use crate::gpu::{Gpu, ShaderChecks};
use crate::gpu_scene::{GpuScene, TraceVariant};
use crate::gpu_types::GpuView;
use crate::model::Camera;
use crate::pass::{FrameContext, Ran};
use crate::shaders::{Backend, compose};

/// G-buffer depths within this factor of each other count as one surface, in the guide and in
/// the upscaler's moving clamp (WGSL: `gbuffer_read.wesl`'s `SAME_SURFACE_DEPTH_RATIO`).
pub const SAME_SURFACE_DEPTH_RATIO: f32 = 1.1;

/// Whether two samples are of one surface: G-buffer depths within
/// [`SAME_SURFACE_DEPTH_RATIO`] of each other (or both background, 0), and both emitting or
/// neither. WGSL twin: `gbuffer_read.wesl`'s `same_surface` (held to it by
/// `solari-denoise`'s `tests/upscale_surface.rs`).
pub fn same_surface(depth_a: f32, emits_a: bool, depth_b: f32, emits_b: bool) -> bool {
    let r = SAME_SURFACE_DEPTH_RATIO;
    depth_a <= depth_b * r
        && depth_a * r >= depth_b
        && (depth_a > 0.0) == (depth_b > 0.0)
        && emits_a == emits_b
}

/// The pass's profiler scope and report name.
pub const PASS_LABELS: [&str; 1] = ["upscale_guide"];

/// Group 2 of `primary_depth.wesl`: the view and the depth it writes (group 1 is the
/// render-size G-buffer's reader group).
const BINDINGS: BufferGroup = BufferGroup::new(
    2,
    0,
    &[("depth_view", Buf::Uniform), ("depth_out", Buf::ReadWrite)],
);

/// The upscaler's guide at one output size (see the module docs).
pub struct PrimaryDepth {
    pipeline: wgpu::ComputePipeline,
    variant: TraceVariant,
    view: wgpu::Buffer,
    depth: wgpu::Buffer,
    group: wgpu::BindGroup,
    size: (u32, u32),
}

impl PrimaryDepth {
    /// The pass for scenes uploaded with `backend` whose shape fits `variant`
    /// ([`TraceVariant::for_scene`]), at `size` pixels; a size whose buffer is over the
    /// device's storage binding limit, or empty, is refused.
    pub fn new(
        gpu: &Gpu,
        backend: Backend,
        variant: TraceVariant,
        size: (u32, u32),
    ) -> Result<Self, GpuError> {
        if size.0 == 0 || size.1 == 0 {
            return Err(GpuError::Validation(format!(
                "primary depth: {}×{} pixels",
                size.0, size.1
            )));
        }
        let bytes = size.0 as u64 * size.1 as u64 * 4;
        gpu.check_storage_binding("primary depth", bytes)?;
        let layout = BINDINGS.layout(gpu, "solari_scene/primary_depth");
        let scene_layout = GpuScene::layout_for(gpu, backend);
        let pipeline = gpu.compute_pipeline(
            "solari_scene/primary_depth",
            &compose("primary_depth", backend, &[])?,
            &[
                Some(&scene_layout),
                Some(&GBuffer::reader_layout(gpu)),
                Some(&layout),
            ],
            ShaderChecks::BoundsOnly,
            variant.constants(),
        )?;
        let view = gpu.uniform_buffer("solari_scene/primary_depth_view", &GpuView::default());
        // Zero: no last depth, so the first frame's rays are unbounded.
        let depth = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solari_scene/primary_depth"),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let group = BINDINGS.bind(
            gpu,
            "solari_scene/primary_depth",
            &layout,
            &[("depth_view", &view), ("depth_out", &depth)],
        );
        Ok(Self {
            pipeline,
            variant,
            view,
            depth,
            group,
            size,
        })
    }

    /// The scene shape the pipeline was specialised for.
    pub fn variant(&self) -> TraceVariant {
        self.variant
    }

    /// Pixels across and down.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Uploads this frame's camera (its view at [`PrimaryDepth::size`], unjittered; the
    /// G-buffer given to [`PrimaryDepth::encode`] must have been rendered from it).
    pub fn prepare(&self, gpu: &Gpu, camera: &Camera) {
        let view = GpuView::new(camera, self.size.0, self.size.1);
        gpu.queue
            .write_buffer(&self.view, 0, bytemuck::bytes_of(&view));
    }

    /// Records the pass (profiler scope [`PASS_LABELS`]`[0]`) into [`PrimaryDepth::depth`]
    /// from this frame's render-size `gbuffer` (jitter and depth; any size up to the
    /// guide's). `scene` must have the shape the pass was built for ([`TraceVariant::check`]).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        scene: &GpuScene,
        gbuffer: &dyn GBufferSource,
    ) -> Result<Ran, GpuError> {
        self.variant.check(scene)?;
        let (w, h) = gbuffer.size();
        if w > self.size.0 || h > self.size.1 {
            return Err(GpuError::Validation(format!(
                "primary depth: a {w}×{h} G-buffer for a {}×{} guide",
                self.size.0, self.size.1
            )));
        }
        let gbuffer_group = gbuffer.bind_group()?;
        let mut ran = Ran::none();
        frame.scope(PASS_LABELS[0], encoder, &mut ran, |e| {
            let mut pass = e.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(PASS_LABELS[0]),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, scene.bind_group(), &[]);
            pass.set_bind_group(1, gbuffer_group, &[]);
            pass.set_bind_group(2, &self.group, &[]);
            pass.dispatch_workgroups(self.size.0.div_ceil(8), self.size.1.div_ceil(8), 1);
        });
        Ok(ran)
    }

    /// The guide: one `f32` per pixel, rows top to bottom, the G-buffer depth negated where
    /// the surface emits.
    pub fn depth(&self) -> &wgpu::Buffer {
        &self.depth
    }

    /// Bytes of GPU memory the pass holds (the depth buffer and the view).
    pub fn memory_bytes(&self) -> u64 {
        self.depth.size() + self.view.size()
    }
}
