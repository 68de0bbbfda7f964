//! The fallback path's temporal upscaler (`shaders/temporal_upscale.wesl`): the lighting is
//! rendered at a fraction of the output's pixels with the camera jittered
//! ([`solari_scene::gpu_types::halton_jitter`]), and this pass accumulates the jittered
//! samples into an image at the output size: each frame's samples that fall inside the output
//! pixel (a box kernel), last frame's accumulation reprojected through the motion
//! vectors (background, which has none, through the camera's turn) and clamped to the range
//! of this frame's neighbouring samples (the nine around a still pixel, the four nearest a
//! moving one), the two merged by their weights. At a scale of 1 it antialiases (each pixel
//! converges to its area average). DLSS-RR does this itself and does not use it.
//!
//! Under a moving camera the upscaled image is still short of native: at half scale a
//! frame's own samples fall in a quarter of the output pixels, and the history that fills the
//! rest places edges up to a render pixel off. The pass has a pipeline for frames whose
//! camera moved ([`GBufferSource::camera_moved`]): there every pixel is clamped as a moving
//! one, and the samples among a pixel's four nearest that lie in front of the nearest one's
//! surface (more than 10% nearer) are left out of its clamp, so that a pixel beside a moving
//! silhouette, whose history comes with its own surface's motion from where the occluder
//! was, does not keep the occluder's colour. Along the orbit camera (lavapipe, 320×180,
//! relMSE against 256-spp references) the tighter clamp and the background's reprojection
//! took half scale from 14.3 to 7.2 on many_lights frame 8, and leaving the occluders out
//! to 1.04, interior frame 32 from 0.253 to 0.020 (native: 0.089 and 0.014); see
//! `benches/RESULTS.md`.
//!
//! Memory: one accumulation buffer at the output size (16 bytes a pixel) persists from frame
//! to frame and is the output. The pass writes this frame's accumulation elsewhere (it reads
//! last frame's around each pixel, so it cannot write in place) and copies it back: into a
//! work buffer of its own (16 bytes a pixel more), or into scratch that other passes share
//! ([`TemporalUpscaler::use_scratch`]), as the real-time renderer does. Two accumulation
//! buffers and a separate output took 48 bytes a pixel (95 MiB at 1920×1080); the copy, a
//! second dispatch, costs one read and one write of the output per frame.

use bytemuck::{Pod, Zeroable};
use solari_scene::GpuError;
use solari_scene::bindings::{Buf, BufferGroup};
use solari_scene::finite_check::RecordLayout;
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
        ("guide_depth", Buf::Read),
    ],
);

/// Bind group 0 of `upscale_copy.wesl`, the pass's second dispatch: this frame's
/// accumulation copied over last frame's.
pub const COPY_BINDINGS: BufferGroup = BufferGroup::new(
    0,
    0,
    &[
        ("upscale_params", Buf::Uniform),
        ("copy_from", Buf::Read),
        ("copy_to", Buf::ReadWrite),
    ],
);

/// The record layout of [`TemporalUpscaler::output`] for the non-finite detector: four
/// finite, non-negative floats (the colour and the accumulated weight).
pub const OUTPUT_LAYOUT: RecordLayout = RecordLayout::RGBA_NON_NEGATIVE;

/// Pipeline constant of `temporal_upscale.wesl`: the pass built for frames whose camera moved
/// since last frame ([`GBufferSource::camera_moved`]), which leaves a moving silhouette's
/// occluder out of the clamp of the pixels beside it (`@id(7150) override MOVING_CAMERA`).
const MOVING_CAMERA: &str = "7150";

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
    /// 1: `guide_depth` holds each output pixel's depth, negated where it emits
    /// ([`TemporalUpscaler::encode`]'s `guide`).
    pub guided: u32,
    /// Padding.
    pub _pad: u32,
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

/// Where a render-image position (pixels from the top left) lies in the output image. The
/// render view has the output's vertical field of view but its own aspect ratio (its size is
/// rounded up to whole pixels, so `render_w / render_h` differs slightly from the output's),
/// so horizontally the two images meet in NDC scaled by the aspect ratios, not in plain pixel
/// ratios: at 0.67 of 960×540 (644×362) the plain ratio put samples up to 0.33 output pixels
/// off at the image's sides, enough to paint emitter samples into pixels beside the emitter.
/// WGSL twin: `render_to_output` in `temporal_upscale.wesl`.
pub fn render_to_output(p: [f32; 2], render: (u32, u32), output: (u32, u32)) -> [f32; 2] {
    let (rw, rh) = (render.0 as f32, render.1 as f32);
    let (ow, oh) = (output.0 as f32, output.1 as f32);
    let k = (rw / rh) / (ow / oh);
    let ndc_x = p[0] / rw * 2.0 - 1.0;
    [(ndc_x * k + 1.0) * 0.5 * ow, p[1] / rh * oh]
}

/// The inverse of [`render_to_output`]. WGSL twin: `output_to_render`.
pub fn output_to_render(p: [f32; 2], render: (u32, u32), output: (u32, u32)) -> [f32; 2] {
    let (rw, rh) = (render.0 as f32, render.1 as f32);
    let (ow, oh) = (output.0 as f32, output.1 as f32);
    let k = (rw / rh) / (ow / oh);
    let ndc_x = p[0] / ow * 2.0 - 1.0;
    [(ndc_x / k + 1.0) * 0.5 * rw, p[1] / oh * rh]
}

pub use solari_scene::primary_depth::{SAME_SURFACE_DEPTH_RATIO, same_surface};

/// Which of a moving pixel's nearest samples (at most four; G-buffer depths `depth`, whether
/// each `emits`) clamp its history when the output-resolution guide gives the pixel's own
/// surface (`own_depth`, `own_emits`): bit k for sample k. Those on the pixel's surface
/// ([`same_surface`]); where none is, those on the surface of the sample nearest it in depth
/// (smallest |ln(depth / own_depth)|, a sample that emits otherwise than the pixel counting
/// 1000 further): a surface the render missed between its samples. WGSL twin: `own_surface`
/// in `temporal_upscale.wesl` (`tests/upscale_surface.rs`).
pub fn own_surface(depth: &[f32], emits: &[bool], own_depth: f32, own_emits: bool) -> u32 {
    let n = depth.len().min(emits.len()).min(4);
    let mut any_match = false;
    let (mut nearest, mut nearest_score) = (0, 3.0e38f32);
    for k in 0..n {
        any_match |= same_surface(depth[k], emits[k], own_depth, own_emits);
        let penalty = if emits[k] == own_emits { 0.0 } else { 1e3 };
        let score = (depth[k].max(1e-6) / own_depth.max(1e-6)).ln().abs() + penalty;
        if score < nearest_score {
            (nearest, nearest_score) = (k, score);
        }
    }
    if n == 0 {
        return 0;
    }
    let (match_depth, match_emits) = if any_match {
        (own_depth, own_emits)
    } else {
        (depth[nearest], emits[nearest])
    };
    (0..n)
        .filter(|&k| same_surface(depth[k], emits[k], match_depth, match_emits))
        .fold(0, |mask, k| mask | 1 << k)
}

/// The temporal upscaler and its accumulation buffers (see the module docs).
pub struct TemporalUpscaler {
    settings: UpscaleSettings,
    render_size: (u32, u32),
    output_size: (u32, u32),
    // For a still camera, and for one that moved since last frame (MOVING_CAMERA).
    pipeline: wgpu::ComputePipeline,
    moving_pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    copy_pipeline: wgpu::ComputePipeline,
    copy_layout: wgpu::BindGroupLayout,
    // The copy's bind group, for the current `work`.
    copy_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    // The accumulation (rgb, weight) that persists between frames: the output.
    accum: wgpu::Buffer,
    // Where the pass writes this frame's accumulation before the copy into `accum`: a
    // buffer of its own, or shared scratch (`shared`).
    work: wgpu::Buffer,
    shared: bool,
    // The bind group for the input and guide buffers last given (rebuilt when they or
    // `work` change).
    group: Option<(wgpu::Buffer, Option<wgpu::Buffer>, wgpu::BindGroup)>,
    // Bound as the guide when there is none (the shader reads it only when guided).
    no_guide: wgpu::Buffer,
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
        gpu.check_storage_binding("temporal upscaler output", bytes)?;
        let layout = UPSCALE_BINDINGS.layout(gpu, "solari_denoise/upscale");
        let gbuffer_layout = GBuffer::reader_layout(gpu);
        let wgsl = compose("temporal_upscale", Backend::Software, &crate::modules())?;
        let build = |label: &str, moving: bool| {
            gpu.compute_pipeline(
                label,
                &wgsl,
                &[Some(&layout), Some(&gbuffer_layout)],
                ShaderChecks::BoundsOnly,
                &[(MOVING_CAMERA, moving as u32 as f64)],
            )
        };
        let pipeline = build("solari_denoise/temporal_upscale", false)?;
        let moving_pipeline = build("solari_denoise/temporal_upscale_moving", true)?;
        let copy_layout = COPY_BINDINGS.layout(gpu, "solari_denoise/upscale_copy");
        let copy_pipeline = gpu.compute_pipeline(
            "solari_denoise/upscale_copy",
            &compose("upscale_copy", Backend::Software, &crate::modules())?,
            &[Some(&copy_layout)],
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
        let params =
            gpu.uniform_buffer("solari_denoise/upscale_params", &GpuUpscaleParams::zeroed());
        let accum = storage("solari_denoise/upscale_accum");
        let work = storage("solari_denoise/upscale_work");
        let copy_group = copy_group(gpu, &copy_layout, &params, &work, &accum);
        let no_guide = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solari_denoise/upscale_no_guide"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        Ok(Self {
            no_guide,
            settings,
            render_size,
            output_size,
            pipeline,
            moving_pipeline,
            layout,
            copy_pipeline,
            copy_layout,
            copy_group,
            params,
            accum,
            work,
            shared: false,
            group: None,
            history: false,
        })
    }

    /// Bytes of shared scratch [`TemporalUpscaler::use_scratch`] needs: this frame's
    /// accumulation, 16 per output pixel.
    pub fn scratch_bytes(&self) -> u64 {
        self.output_size.0 as u64 * self.output_size.1 as u64 * 16
    }

    /// Writes each frame's accumulation into `scratch` (a storage buffer of at least
    /// [`TemporalUpscaler::scratch_bytes`]; a smaller one is refused naming both sizes, one
    /// without storage usage naming its usage) instead of a buffer of its own, which is
    /// freed. The pass reads nothing there that it did not write in the same frame, so other
    /// passes may use the buffer before it; after it, the scratch holds nothing anyone needs.
    /// The history is kept.
    pub fn use_scratch(&mut self, gpu: &Gpu, scratch: &wgpu::Buffer) -> Result<(), GpuError> {
        if self.shared && self.work == *scratch {
            return Ok(());
        }
        solari_scene::scratch::check("temporal upscaler", scratch, self.scratch_bytes())?;
        gpu.check_storage_binding("temporal upscaler scratch", scratch.size())?;
        self.work = scratch.clone();
        self.shared = true;
        self.group = None;
        self.copy_group = copy_group(
            gpu,
            &self.copy_layout,
            &self.params,
            &self.work,
            &self.accum,
        );
        Ok(())
    }

    /// Records the pass: `input` (one `vec4<f32>` per render pixel, the frame's lighting)
    /// upscaled into [`TemporalUpscaler::output`], reading jitter and motion from `gbuffer`
    /// (which must be [`TemporalUpscaler::render_size`]). `reset` drops the history (camera
    /// cut); it is dropped too on the first frame and when the G-buffer has none.
    ///
    /// `guide`: this frame's G-buffer depth at the output size, negated where the surface
    /// emits, one `f32` per output pixel in rows
    /// ([`solari_scene::primary_depth::PrimaryDepth`]), read on frames whose camera moved: a
    /// moving pixel's history is then clamped by those of its four nearest samples on its own
    /// surface (depth within 1.1×, emitting as the pixel does) and follows their motion, where
    /// without it the nearest sample decides, a choice that is wrong for a pixel's width
    /// along every moving silhouette (`temporal_upscale.wesl`). A buffer smaller than the
    /// output is refused.
    #[allow(clippy::too_many_arguments)]
    pub fn encode(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        gbuffer: &dyn GBufferSource,
        input: &wgpu::Buffer,
        guide: Option<&wgpu::Buffer>,
        reset: bool,
    ) -> Result<Ran, GpuError> {
        let out_pixels = self.output_size.0 as u64 * self.output_size.1 as u64;
        if let Some(g) = guide
            && g.size() < out_pixels * 4
        {
            return Err(GpuError::Validation(format!(
                "temporal upscaler: guide of {} bytes for {out_pixels} output pixels",
                g.size()
            )));
        }
        solari_scene::gbuffer_input::check_size("temporal upscaler", self.render_size, gbuffer)?;
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
            guided: guide.is_some() as u32,
            _pad: 0,
        };
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        if self
            .group
            .as_ref()
            .is_none_or(|(b, g, _)| b != input || g.as_ref() != guide)
        {
            let group = UPSCALE_BINDINGS.bind(
                gpu,
                "solari_denoise/upscale",
                &self.layout,
                &[
                    ("upscale_params", &self.params),
                    ("render_color", input),
                    ("accum_before", &self.accum),
                    ("accum_now", &self.work),
                    ("guide_depth", guide.unwrap_or(&self.no_guide)),
                ],
            );
            self.group = Some((input.clone(), guide.cloned(), group));
        }
        let group = &self.group.as_ref().expect("made above").2;
        let gbuffer_group = gbuffer.bind_group()?;
        let (w, h) = self.output_size;
        let mut ran = Ran::none();
        // The copy back counts in the pass's time: it is what one buffer less costs.
        frame.scope(PASS_LABELS[0], encoder, &mut ran, |e| {
            let mut pass = e.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(PASS_LABELS[0]),
                timestamp_writes: None,
            });
            // A reset frame has no history to tell pixels apart by: the still pipeline, the
            // cheaper (H100, 1080p, the antialiasing pass on a moving camera's unjittered
            // frames, which reset it: 0.114 ms with the moving pipeline, 0.106 with this,
            // 0.102 before either).
            pass.set_pipeline(if gbuffer.camera_moved() && !reset {
                &self.moving_pipeline
            } else {
                &self.pipeline
            });
            pass.set_bind_group(0, group, &[]);
            pass.set_bind_group(1, gbuffer_group, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
            pass.set_pipeline(&self.copy_pipeline);
            pass.set_bind_group(0, &self.copy_group, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        });
        self.history = true;
        Ok(ran)
    }

    /// The upscaled image: one `vec4<f32>` per output pixel, rgb the colour and w the
    /// weight accumulated there (frames of samples, at most about
    /// [`UpscaleSettings::max_weight`] + 1; 0 where no sample has landed yet and the colour is
    /// the nearest sample's). Read it as an image by ignoring w; its layout for
    /// [`solari_scene::finite_check`] is [`OUTPUT_LAYOUT`].
    pub fn output(&self) -> &wgpu::Buffer {
        &self.accum
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
        let work = if self.shared { 0 } else { self.work.size() };
        self.accum.size() + work + self.params.size()
    }
}

fn copy_group(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    params: &wgpu::Buffer,
    from: &wgpu::Buffer,
    to: &wgpu::Buffer,
) -> wgpu::BindGroup {
    COPY_BINDINGS.bind(
        gpu,
        "solari_denoise/upscale_copy",
        layout,
        &[
            ("upscale_params", params),
            ("copy_from", from),
            ("copy_to", to),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};
    use rand::{Rng, SeedableRng};
    use solari_scene::gpu_types::GpuView;

    /// Where the output view sees the direction of `view`'s ray through `p`.
    fn seen_by(output: &GpuView, view: &GpuView, p: [f32; 2]) -> [f32; 2] {
        let d = view.ray_direction(Vec2::from(p));
        let z = d.dot(Vec3::from(output.forward));
        let ndc_x = d.dot(Vec3::from(output.right)) / (z * output.tan_half_fov * output.aspect);
        let ndc_y = d.dot(Vec3::from(output.up)) / (z * output.tan_half_fov);
        [
            (ndc_x + 1.0) * 0.5 * output.width as f32,
            (1.0 - ndc_y) * 0.5 * output.height as f32,
        ]
    }

    /// A render-image position maps to the output pixel position that sees the same
    /// direction, at the internal scales the renderer uses and odd sizes whose rounded render
    /// size changes the aspect most; and the inverse inverts it.
    #[test]
    fn render_positions_map_to_where_the_output_view_sees_them() {
        let camera = solari_scene::Camera::look_at(
            "c",
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-2.0, 0.5, -4.0),
            Vec3::Y,
            0.9,
        );
        let mut rng = rand_pcg::Pcg32::seed_from_u64(4);
        let mut plain_worst = 0.0f32;
        for output in [
            (960u32, 540u32),
            (1920, 1080),
            (97, 31),
            (31, 97),
            (1280, 720),
        ] {
            for scale in [0.25f32, 0.5, 0.67, 0.75, 1.0] {
                let render = (
                    ((output.0 as f32 * scale).ceil() as u32).clamp(1, output.0),
                    ((output.1 as f32 * scale).ceil() as u32).clamp(1, output.1),
                );
                let (rv, ov) = (
                    GpuView::new(&camera, render.0, render.1),
                    GpuView::new(&camera, output.0, output.1),
                );
                for _ in 0..200 {
                    let p = [
                        rng.random_range(0.0..render.0 as f32),
                        rng.random_range(0.0..render.1 as f32),
                    ];
                    let want = seen_by(&ov, &rv, p);
                    let got = render_to_output(p, render, output);
                    for a in 0..2 {
                        assert!(
                            (got[a] - want[a]).abs() < 2e-3 * output.0.max(output.1) as f32 / 100.0,
                            "{output:?} at {scale}: {p:?} -> {got:?}, the view sees {want:?}"
                        );
                    }
                    let back = output_to_render(got, render, output);
                    assert!((back[0] - p[0]).abs() < 1e-3 && (back[1] - p[1]).abs() < 1e-3);
                    // What the plain pixel ratio would have said.
                    let plain = p[0] * output.0 as f32 / render.0 as f32;
                    plain_worst = plain_worst.max((plain - want[0]).abs());
                }
            }
        }
        // The case this mapping fixes: plain ratios were off by over a third of a pixel.
        assert!(plain_worst > 0.3, "{plain_worst}");
    }
}
