//! The G-buffer as passes read it: bind group 1 of layout [`reader_layout`], whoever
//! rendered it. Two types implement [`GBufferSource`]: Solari's G-buffer
//! ([`crate::gbuffer::GBuffer`], raster or traced) and [`ExternalGBuffer`], which binds
//! textures that your own renderer wrote, so ReSTIR DI, the world cache's GI and the denoisers
//! run on an engine's G-buffer without Solari's producers.
//!
//! The bindings (WGSL: `gbuffer_read.wesl`):
//!
//! | binding | WGSL name | contents |
//! |---|---|---|
//! | 0 | `frame_views` | [`GpuFrameViews`]: this frame's and last frame's camera |
//! | 1 | `gbuffer_now` | material and normals, [`GBUFFER_FORMAT`] |
//! | 2 | `emission_now` | emission and f90, [`EMISSION_FORMAT`] |
//! | 3 | `motion_now` | motion vectors, [`MOTION_FORMAT`] |
//! | 4 | `depth_now` | reversed-Z depth, [`DEPTH_FORMAT`] (a colour format: write it as a colour target or storage texture beside your depth buffer) |
//! | 5 | `gbuffer_before` | last frame's material and normals |
//! | 6 | `emission_before` | last frame's emission |
//! | 7 | `depth_before` | last frame's depth |
//!
//! The encodings are in [`crate::gbuffer`]'s module docs; WGSL writers can import
//! `package::gbuffer::pack_gbuffer`, and [`crate::gbuffer::view_projection`] is the
//! projection whose depth the readers expect.

use crate::error::GpuError;
use crate::gbuffer::{DEPTH_FORMAT, EMISSION_FORMAT, GBUFFER_FORMAT, GpuFrameViews, MOTION_FORMAT};
use crate::gpu::Gpu;
use crate::gpu_types::GpuView;
use crate::model::Camera;
use bytemuck::Zeroable;

/// The bindings of group 1 by WGSL name, in binding order (binding = index).
pub const READER_BINDINGS: [&str; 8] = [
    "frame_views",
    "gbuffer_now",
    "emission_now",
    "motion_now",
    "depth_now",
    "gbuffer_before",
    "emission_before",
    "depth_before",
];

/// A G-buffer that passes can read: anything that offers bind group 1 of layout
/// [`reader_layout`] for the frame being rendered.
pub trait GBufferSource {
    /// Bind group 1 for this frame; an error when there is none yet (an
    /// [`ExternalGBuffer`] before its first [`ExternalGBuffer::prepare`]).
    fn bind_group(&self) -> Result<&wgpu::BindGroup, GpuError>;
    /// Size in pixels; passes refuse a G-buffer of another size than theirs.
    fn size(&self) -> (u32, u32);
    /// Whether the `*_before` bindings and the motion vectors refer to a real previous frame
    /// (false on the first frame, after a resize or a reset): passes drop history otherwise.
    fn history_valid(&self) -> bool;
    /// Whether this frame's camera differs from last frame's (the jitter aside; true without
    /// history). Passes may specialise for a still camera; the default, true, is always safe.
    fn camera_moved(&self) -> bool {
        true
    }
}

/// The check every pass that reads a G-buffer makes before recording: `gbuffer` has the
/// size `pass` was built for. The error names the pass and both sizes.
pub fn check_size(
    pass: &str,
    built_for: (u32, u32),
    gbuffer: &dyn GBufferSource,
) -> Result<(), GpuError> {
    if gbuffer.size() == built_for {
        return Ok(());
    }
    Err(GpuError::Validation(format!(
        "{pass}: built for {:?} pixels, the G-buffer has {:?}",
        built_for,
        gbuffer.size()
    )))
}

/// The layout of bind group 1 (see the module docs), for compute passes.
pub fn reader_layout(gpu: &Gpu) -> wgpu::BindGroupLayout {
    let stage = wgpu::ShaderStages::COMPUTE;
    let uint = wgpu::TextureSampleType::Uint;
    let float = wgpu::TextureSampleType::Float { filterable: false };
    let sample_types = [uint, float, float, float, uint, float, float];
    let entries: Vec<_> = std::iter::once(crate::gpu::buffer_layout_entry(
        0,
        wgpu::BufferBindingType::Uniform,
        stage,
    ))
    .chain(
        sample_types
            .into_iter()
            .zip(1..)
            .map(|(sample_type, binding)| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: stage,
                ty: wgpu::BindingType::Texture {
                    sample_type,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }),
    )
    .collect();
    gpu.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("solari_scene/gbuffer_reader"),
            entries: &entries,
        })
}

/// One frame's G-buffer textures, as views of the whole (single-mip) texture.
#[derive(Clone, Copy)]
pub struct GBufferViews<'a> {
    /// Material and normals, [`GBUFFER_FORMAT`].
    pub gbuffer: &'a wgpu::TextureView,
    /// Emission and f90, [`EMISSION_FORMAT`].
    pub emission: &'a wgpu::TextureView,
    /// Motion vectors, [`MOTION_FORMAT`] (zero for a still camera and scene).
    pub motion: &'a wgpu::TextureView,
    /// Reversed-Z depth, [`DEPTH_FORMAT`].
    pub depth: &'a wgpu::TextureView,
}

impl<'a> GBufferViews<'a> {
    fn named(&self) -> [(&'static str, &'a wgpu::TextureView, wgpu::TextureFormat); 4] {
        [
            ("gbuffer", self.gbuffer, GBUFFER_FORMAT),
            ("emission", self.emission, EMISSION_FORMAT),
            ("motion", self.motion, MOTION_FORMAT),
            ("depth", self.depth, DEPTH_FORMAT),
        ]
    }

    // Format, size and usage of every texture, so a mismatch is an error that names the
    // texture instead of a wgpu validation panic.
    fn check(&self, which: &str, size: (u32, u32)) -> Result<(), GpuError> {
        for (name, view, format) in self.named() {
            let texture = view.texture();
            let problem = if texture.format() != format {
                Some(format!(
                    "format {:?}, expected {format:?}",
                    texture.format()
                ))
            } else if (texture.width(), texture.height()) != size {
                Some(format!(
                    "{}×{}, expected {}×{}",
                    texture.width(),
                    texture.height(),
                    size.0,
                    size.1
                ))
            } else if !texture
                .usage()
                .contains(wgpu::TextureUsages::TEXTURE_BINDING)
            {
                Some("no TEXTURE_BINDING usage".to_string())
            } else if texture.mip_level_count() != 1 || texture.depth_or_array_layers() != 1 {
                Some("more than one mip level or layer".to_string())
            } else {
                None
            };
            if let Some(problem) = problem {
                return Err(GpuError::Validation(format!(
                    "{which} G-buffer texture '{name}': {problem}"
                )));
            }
        }
        Ok(())
    }
}

/// Makes one reader group (see [`reader_layout`]) over `now` and `before`.
pub fn reader_group(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    frame_views: &wgpu::Buffer,
    now: GBufferViews,
    before: GBufferViews,
) -> wgpu::BindGroup {
    let textures = [
        now.gbuffer,
        now.emission,
        now.motion,
        now.depth,
        before.gbuffer,
        before.emission,
        before.depth,
    ];
    let entries: Vec<wgpu::BindGroupEntry> = std::iter::once(wgpu::BindGroupEntry {
        binding: 0,
        resource: frame_views.as_entire_binding(),
    })
    .chain(
        textures
            .into_iter()
            .zip(1..)
            .map(|(view, binding)| wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::TextureView(view),
            }),
    )
    .collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("solari_scene/gbuffer_reader"),
        layout,
        entries: &entries,
    })
}

// Reader groups kept for recent texture sets: an engine that alternates two sets needs two.
const KEPT_GROUPS: usize = 4;

/// A G-buffer your own renderer wrote, bound for Solari's passes.
///
/// Each frame, after your G-buffer pass is recorded (or submitted), call
/// [`ExternalGBuffer::prepare`] with the camera and this frame's and last frame's textures;
/// then hand `&ExternalGBuffer` to any pass that takes a [`GBufferSource`]. Bind groups are
/// made once per distinct set of textures and reused, so alternating two sets costs nothing
/// per frame.
///
/// ```no_run
/// # use solari_scene::gbuffer_input::{ExternalGBuffer, GBufferViews};
/// # fn demo(gpu: &solari_scene::gpu::Gpu, camera: &solari_scene::Camera,
/// #         now: GBufferViews, before: GBufferViews) -> Result<(), solari_scene::GpuError> {
/// let mut gbuffer = ExternalGBuffer::new(gpu, 1280, 720)?;
/// // every frame:
/// gbuffer.prepare(gpu, camera, now, Some(before))?;
/// # Ok(()) }
/// ```
pub struct ExternalGBuffer {
    layout: wgpu::BindGroupLayout,
    frame_views: wgpu::Buffer,
    size: (u32, u32),
    last_view: Option<GpuView>,
    history_valid: bool,
    // This frame's camera differs from last frame's (`GBufferSource::camera_moved`).
    camera_moved: bool,
    // Most recently used last.
    groups: Vec<([wgpu::TextureView; 7], wgpu::BindGroup)>,
}

impl ExternalGBuffer {
    /// Binds G-buffers of `width × height`.
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Result<Self, GpuError> {
        crate::gbuffer::check_size(gpu, width, height)?;
        Ok(Self {
            layout: reader_layout(gpu),
            frame_views: gpu.uniform_buffer(
                "solari_scene/external_gbuffer_views",
                &GpuFrameViews::zeroed(),
            ),
            size: (width, height),
            last_view: None,
            history_valid: false,
            camera_moved: true,
            groups: Vec::new(),
        })
    }

    /// Starts a frame seen from `camera`: `current` holds this frame's G-buffer, `previous`
    /// last frame's (None on the first frame or after a cut: passes then use no history).
    /// Errors, changing nothing, when a texture has the wrong format, size or usage.
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        camera: &Camera,
        current: GBufferViews,
        previous: Option<GBufferViews>,
    ) -> Result<(), GpuError> {
        self.prepare_jittered(gpu, camera, current, previous, [0.0; 2])
    }

    /// As [`ExternalGBuffer::prepare`], for a G-buffer your renderer drew with its samples
    /// `jitter` pixels off the pixel centres (x right, y down: the point a ray through
    /// centre + jitter meets lands on the pixel centre), so readers reconstruct positions
    /// where you sampled them and the temporal upscaler can accumulate them. Your motion
    /// vectors should stay unjittered.
    pub fn prepare_jittered(
        &mut self,
        gpu: &Gpu,
        camera: &Camera,
        current: GBufferViews,
        previous: Option<GBufferViews>,
        jitter: [f32; 2],
    ) -> Result<(), GpuError> {
        current.check("this frame's", self.size)?;
        if let Some(previous) = &previous {
            previous.check("last frame's", self.size)?;
        }
        let view = GpuView::new(camera, self.size.0, self.size.1).with_jitter(jitter);
        self.history_valid = previous.is_some() && self.last_view.is_some();
        self.camera_moved =
            !self.history_valid || self.last_view.is_none_or(|last| !last.same_camera(&view));
        let before = previous.unwrap_or(current);
        let views = GpuFrameViews {
            current: view,
            previous: if self.history_valid {
                self.last_view.unwrap_or(view)
            } else {
                view
            },
            history_valid: self.history_valid as u32,
            _pad: [0; 3],
        };
        gpu.queue
            .write_buffer(&self.frame_views, 0, bytemuck::bytes_of(&views));
        self.last_view = Some(view);
        let key = [
            current.gbuffer,
            current.emission,
            current.motion,
            current.depth,
            before.gbuffer,
            before.emission,
            before.depth,
        ]
        .map(Clone::clone);
        match self.groups.iter().position(|(k, _)| *k == key) {
            Some(i) => {
                let kept = self.groups.remove(i);
                self.groups.push(kept);
            }
            None => {
                let group = reader_group(gpu, &self.layout, &self.frame_views, current, before);
                if self.groups.len() == KEPT_GROUPS {
                    self.groups.remove(0);
                }
                self.groups.push((key, group));
            }
        }
        Ok(())
    }

    /// Drops history: the next frame's passes use none (camera cuts, teleports).
    pub fn reset(&mut self) {
        self.last_view = None;
        self.history_valid = false;
    }
}

impl GBufferSource for ExternalGBuffer {
    fn bind_group(&self) -> Result<&wgpu::BindGroup, GpuError> {
        self.groups.last().map(|(_, group)| group).ok_or_else(|| {
            GpuError::Validation(
                "ExternalGBuffer::prepare must bind this frame's textures before a pass reads them"
                    .into(),
            )
        })
    }

    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn history_valid(&self) -> bool {
        self.history_valid
    }

    fn camera_moved(&self) -> bool {
        self.camera_moved
    }
}
