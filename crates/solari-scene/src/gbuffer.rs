//! The G-buffer: per pixel, what a primary ray sees at the pixel's sample position (its centre,
//! moved by the view's jitter when [`GBuffer::prepare_jittered`] asks for one: material after
//! textures, normals after normal mapping, depth) plus screen-space motion vectors from last
//! frame's camera and instance transforms.
//!
//! Two producers write the same targets ([`GBufferProducer`]): a raster pass over the scene's
//! meshes, and a compute pass that traces one primary ray per pixel through the scene's
//! tracing backend. Both turn their hit into texels with one WGSL function
//! (`shaders/gbuffer_write.wesl`), so they differ only in how they find the hit.
//!
//! Two sets of targets alternate by frame parity: after [`GBuffer::prepare`], the targets
//! written last frame are [`GBuffer::previous`] for reprojection, and nothing is copied. The
//! motion target is one texture that both sets share, because no pass reads last frame's.
//!
//! | target | format | contents |
//! |---|---|---|
//! | `gbuffer` | Rgba32Uint | x: √base colour rgb + roughness (unorm8); y: √dielectric f0 rgb + metallic (unorm8); z: shading normal, w: geometric normal (octahedral, 16 bits per axis), both facing the viewer |
//! | `emission` | Rgba16Float | emitted radiance (clamped to 65,504, f16's largest), dielectric f90 |
//! | `motion` | Rg16Float | texture coordinates now minus last frame's (x right, y down) |
//! | `depth` | R32Float | reversed Z of an infinite perspective: `znear / view_z`, 0 = background |
//!
//! Depth is a colour format, not a depth format, because compute passes cannot write depth
//! textures: the raster producer tests against a Depth32Float buffer of its own and writes
//! this copy. The square-root encoding spends the 8 bits where colour and f0 are small (f0 =
//! 0.04 comes back as 0.0400 instead of 0.0392). WGSL side: `shaders/gbuffer.wesl`
//! (`unpack_gbuffer`, `view_z_from_depth`). The raster producer pulls vertices from bind
//! group 0, so the adapter must allow storage buffers in vertex shaders (every Vulkan, Metal
//! and D3D12 adapter does); the traced one needs Rg16Float storage textures
//! ([`GBufferProducer::traced_support`]).

use crate::bindings::{Buf, BufferGroup};
use crate::error::GpuError;
use crate::gbuffer_input::{GBufferSource, GBufferViews};
use crate::gbuffer_override::OverridePass;
use crate::gbuffer_raster::RasterProducer;
use crate::gbuffer_traced::TracedProducer;
use crate::gpu::Gpu;
use crate::gpu_scene::{GpuScene, TraceVariant};
use crate::gpu_types::GpuView;
use crate::model::{Camera, Scene};
use crate::pass::{FrameContext, Ran};
use crate::shaders::Backend;
use bytemuck::{Pod, Zeroable};
use glam::Mat4;

/// Group 1 of both producers (`gbuffer_write.wesl`): this and last frame's matrices and this
/// frame's primary rays.
pub const GBUFFER_VIEW_BINDINGS: BufferGroup =
    BufferGroup::new(1, 0, &[("gbuffer_view", Buf::Uniform)]);
/// Group 2 of both producers: last frame's instance transforms, for motion vectors.
pub const TRANSFORMS_BINDINGS: BufferGroup =
    BufferGroup::new(2, 0, &[("previous_transforms", Buf::Read)]);

/// The pass's label (render pass, profiler scope and report name).
pub const PASS_LABELS: [&str; 1] = ["gbuffer"];

/// Format of the packed material-and-normals target.
pub const GBUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// Format of the emission target.
pub const EMISSION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Format of the motion-vector target.
pub const MOTION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;
/// Format of the depth target that readers see (see the module docs for why not a depth
/// format).
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// WGSL twin: `GBufferView` in `gbuffer_write.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuGBufferView {
    /// This frame's world-to-clip matrix ([`view_projection`]).
    pub view_proj: [[f32; 4]; 4],
    /// Last frame's world-to-clip matrix (this frame's on the first frame).
    pub previous_view_proj: [[f32; 4]; 4],
    /// This frame's primary rays (the traced producer's).
    pub view: GpuView,
}

const _: () = assert!(size_of::<GpuGBufferView>() == 224);

/// The world-to-clip matrix the G-buffer rasterises with for `camera` at `width × height`:
/// a reversed-Z infinite perspective, matching the primary rays of `view.wesl` pixel for pixel.
pub fn view_projection(camera: &Camera, width: u32, height: u32) -> Mat4 {
    let aspect = width as f32 / height.max(1) as f32;
    let m = camera.transform;
    // The ray generator uses the transform's normalised axes; build the same rigid view.
    let right = m.x_axis.truncate().normalize_or_zero();
    let up = m.y_axis.truncate().normalize_or_zero();
    let back = m.z_axis.truncate().normalize_or_zero();
    let eye = m.w_axis.truncate();
    let view = Mat4::from_cols(
        right.extend(0.0),
        up.extend(0.0),
        back.extend(0.0),
        eye.extend(1.0),
    )
    .inverse();
    let znear = camera.znear.max(1e-6);
    // Reversed-Z infinite perspective (right-handed, looking down -z): clip.z = znear and
    // clip.w = -z, so depth = znear / distance along the view axis.
    let f = 1.0 / (camera.yfov * 0.5).tan();
    let projection = Mat4::from_cols(
        glam::Vec4::new(f / aspect, 0.0, 0.0, 0.0),
        glam::Vec4::new(0.0, f, 0.0, 0.0),
        glam::Vec4::new(0.0, 0.0, 0.0, -1.0),
        glam::Vec4::new(0.0, 0.0, znear, 0.0),
    );
    projection * view
}

/// WGSL twin: `FrameViews` in `gbuffer_read.wesl`: this frame's and last frame's views, for
/// passes that read the G-buffer (bind group 1).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuFrameViews {
    /// This frame's view.
    pub current: GpuView,
    /// Last frame's view (this frame's when there is no history).
    pub previous: GpuView,
    /// 1 when [`GBuffer::previous`] holds a real previous frame.
    pub history_valid: u32,
    /// Padding.
    pub _pad: [u32; 3],
}

const _: () = assert!(size_of::<GpuFrameViews>() == 208);

/// Which pass writes the G-buffer. Both write the same texels for the same hit; they find it
/// differently, so they cost differently per GPU (`benches/RESULTS.md`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum GBufferProducer {
    /// Rasterise the scene's triangles (vertex and fragment shaders, hardware depth test).
    #[default]
    Raster,
    /// Trace one primary ray per pixel centre (a compute pass), specialised for the scene's
    /// shape like every tracing pass ([`TraceVariant::for_scene`]).
    Traced,
}

impl GBufferProducer {
    /// Both producers.
    pub const ALL: [GBufferProducer; 2] = [GBufferProducer::Raster, GBufferProducer::Traced];

    /// A short name for reports and the command line: `raster` or `traced`.
    pub fn name(self) -> &'static str {
        match self {
            GBufferProducer::Raster => "raster",
            GBufferProducer::Traced => "traced",
        }
    }

    /// The producer named `name` ([`GBufferProducer::name`]).
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    /// Why the traced producer cannot run on this device, if it cannot: it writes the motion
    /// target as a storage texture, and Rg16Float storage is an adapter-specific format
    /// feature (every desktop Vulkan driver we met has it, lavapipe included).
    pub fn traced_support(gpu: &Gpu) -> Result<(), GpuError> {
        let feature = wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES;
        let storage = gpu
            .adapter
            .get_texture_format_features(MOTION_FORMAT)
            .allowed_usages
            .contains(wgpu::TextureUsages::STORAGE_BINDING);
        if gpu.features.contains(feature) && storage {
            Ok(())
        } else {
            Err(GpuError::Unsupported(format!(
                "the traced G-buffer writes {MOTION_FORMAT:?} storage textures, which adapter \
                 '{}' does not offer; use the raster G-buffer",
                gpu.info.name
            )))
        }
    }
}

/// One set of G-buffer targets.
pub struct GBufferTargets {
    /// Material and normals (see the module docs).
    pub gbuffer: wgpu::Texture,
    /// Emitted radiance and f90.
    pub emission: wgpu::Texture,
    /// Motion vectors: one texture that both sets share (no pass reads last frame's), so
    /// [`GBuffer::previous`]'s holds this frame's.
    pub motion: wgpu::Texture,
    /// Reversed-Z depth ([`DEPTH_FORMAT`]).
    pub depth: wgpu::Texture,
    // Views, made once rather than every frame.
    pub(crate) views: [wgpu::TextureView; 4],
}

impl GBufferTargets {
    // Both sets: motion is one texture that both share, since no pass reads last frame's
    // motion (4 bytes a pixel saved).
    fn pair(gpu: &Gpu, size: (u32, u32), producer: GBufferProducer, storage: bool) -> [Self; 2] {
        let motion = target(gpu, "motion", size, MOTION_FORMAT, producer, storage);
        [0, 1].map(|parity| {
            let make = |name: &str, format| {
                target(
                    gpu,
                    &format!("{name}_{parity}"),
                    size,
                    format,
                    producer,
                    storage,
                )
            };
            let gbuffer = make("gbuffer", GBUFFER_FORMAT);
            let emission = make("emission", EMISSION_FORMAT);
            let depth = make("depth", DEPTH_FORMAT);
            let views =
                [&gbuffer, &emission, &motion, &depth].map(|t| t.create_view(&Default::default()));
            Self {
                gbuffer,
                emission,
                motion: motion.clone(),
                depth,
                views,
            }
        })
    }

    fn reader_views(&self) -> GBufferViews<'_> {
        let [gbuffer, emission, motion, depth] = &self.views;
        GBufferViews {
            gbuffer,
            emission,
            motion,
            depth,
        }
    }
}

// One target texture, written as a render attachment by the raster producer and as storage
// by the traced one and by the override pass (`storage`).
fn target(
    gpu: &Gpu,
    name: &str,
    size: (u32, u32),
    format: wgpu::TextureFormat,
    producer: GBufferProducer,
    storage: bool,
) -> wgpu::Texture {
    let written = match producer {
        GBufferProducer::Raster if storage => {
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::STORAGE_BINDING
        }
        GBufferProducer::Raster => wgpu::TextureUsages::RENDER_ATTACHMENT,
        GBufferProducer::Traced => wgpu::TextureUsages::STORAGE_BINDING,
    };
    gpu.texture_2d(
        &format!("solari_scene/gbuffer_{name}"),
        size,
        format,
        written | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC,
    )
}

/// One target set read back to the CPU ([`GBufferTargets::read`]), row-major, one entry per
/// pixel, in the formats of the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct GBufferTexels {
    /// Material and normals words (decode with [`crate::packing::unpack_unit_vector`] and
    /// the square-root colour encoding).
    pub gbuffer: Vec<[u32; 4]>,
    /// Emission rgb and f90.
    pub emission: Vec<[half::f16; 4]>,
    /// Motion vectors.
    pub motion: Vec<[half::f16; 2]>,
    /// Reversed-Z depth (0: background).
    pub depth: Vec<f32>,
}

impl GBufferTargets {
    /// Copies the four targets to the CPU and waits (tests and tools; never per frame).
    pub fn read(&self, gpu: &Gpu) -> Result<GBufferTexels, GpuError> {
        let bytes = |t: &wgpu::Texture| gpu.read_texture(t, wgpu::TextureAspect::All);
        let halves = |b: Vec<u8>| -> Vec<half::f16> {
            bytemuck::cast_slice::<u8, u16>(&b)
                .iter()
                .map(|&h| half::f16::from_bits(h))
                .collect()
        };
        let emission = halves(bytes(&self.emission)?);
        let motion = halves(bytes(&self.motion)?);
        Ok(GBufferTexels {
            gbuffer: bytemuck::cast_slice(&bytes(&self.gbuffer)?).to_vec(),
            emission: emission
                .chunks_exact(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect(),
            motion: motion.chunks_exact(2).map(|c| [c[0], c[1]]).collect(),
            depth: bytemuck::cast_slice(&bytes(&self.depth)?).to_vec(),
        })
    }
}

// The pass that writes the targets.
enum Producer {
    Raster(RasterProducer),
    Traced(TracedProducer),
}

/// The G-buffer: its producer pass and two alternating sets of targets.
pub struct GBuffer {
    producer: Producer,
    kind: GBufferProducer,
    view_buffer: wgpu::Buffer,
    view_group: wgpu::BindGroup,
    transforms_layout: wgpu::BindGroupLayout,
    transforms: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    targets: [GBufferTargets; 2],
    parity: usize,
    size: (u32, u32),
    // Last frame's camera matrix and instance transforms (with meshes, to spot replaced
    // instances), for motion vectors.
    last_view_proj: Option<Mat4>,
    last_instances: Vec<(u32, Mat4)>,
    // (vertex count, instance) per draw, for the raster producer.
    draws: Vec<(u32, u32)>,
    history_valid: bool,
    // This frame's camera differs from last frame's (`GBufferSource::camera_moved`).
    camera_moved: bool,
    // Bind group 1 for readers: views plus both target sets, one group per parity.
    frame_views: wgpu::Buffer,
    last_view: Option<GpuView>,
    reader_layout: wgpu::BindGroupLayout,
    reader_groups: [wgpu::BindGroup; 2],
    // Replacement guides ([`GBuffer::enable_overrides`]).
    overrides: Option<OverridePass>,
    // Bumped whenever `transforms` is reallocated, so passes that bind it can rebind.
    transforms_generation: u64,
}

// Groups 1 and 2 are shared by the raster pipeline's vertex and fragment stages and the
// traced compute pass.
const PRODUCER_STAGES: wgpu::ShaderStages = wgpu::ShaderStages::VERTEX
    .union(wgpu::ShaderStages::FRAGMENT)
    .union(wgpu::ShaderStages::COMPUTE);

fn producer_layout(gpu: &Gpu, label: &str, group: &BufferGroup) -> wgpu::BindGroupLayout {
    gpu.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &group.layout_entries(PRODUCER_STAGES),
        })
}

impl GBuffer {
    /// The raster producer for scenes uploaded with `backend`, with `width × height` targets.
    pub fn new(gpu: &Gpu, backend: Backend, width: u32, height: u32) -> Result<Self, GpuError> {
        Self::with_producer(
            gpu,
            backend,
            GBufferProducer::Raster,
            TraceVariant::General,
            width,
            height,
        )
    }

    /// The traced producer for scenes uploaded with `backend` whose shape fits `variant`
    /// ([`TraceVariant::for_scene`]), with `width × height` targets; fails where
    /// [`GBufferProducer::traced_support`] does.
    pub fn traced(
        gpu: &Gpu,
        backend: Backend,
        variant: TraceVariant,
        width: u32,
        height: u32,
    ) -> Result<Self, GpuError> {
        Self::with_producer(
            gpu,
            backend,
            GBufferProducer::Traced,
            variant,
            width,
            height,
        )
    }

    /// The given producer for scenes uploaded with `backend`, with `width × height` targets;
    /// `variant` specialises the traced producer (the raster one ignores it).
    pub fn with_producer(
        gpu: &Gpu,
        backend: Backend,
        producer: GBufferProducer,
        variant: TraceVariant,
        width: u32,
        height: u32,
    ) -> Result<Self, GpuError> {
        check_size(gpu, width, height)?;
        let view_layout = producer_layout(gpu, "solari_scene/gbuffer_view", &GBUFFER_VIEW_BINDINGS);
        let transforms_layout =
            producer_layout(gpu, "solari_scene/gbuffer_transforms", &TRANSFORMS_BINDINGS);
        let targets = GBufferTargets::pair(gpu, (width, height), producer, false);
        let layouts = [&view_layout, &transforms_layout];
        let made = match producer {
            GBufferProducer::Raster => {
                Producer::Raster(RasterProducer::new(gpu, backend, layouts, (width, height))?)
            }
            GBufferProducer::Traced => {
                GBufferProducer::traced_support(gpu)?;
                let variant = variant.for_backend(backend);
                Producer::Traced(TracedProducer::new(
                    gpu, backend, variant, layouts, &targets,
                )?)
            }
        };
        let view_buffer =
            gpu.uniform_buffer("solari_scene/gbuffer_view", &GpuGBufferView::zeroed());
        let view_group = GBUFFER_VIEW_BINDINGS.bind(
            gpu,
            "solari_scene/gbuffer_view",
            &view_layout,
            &[("gbuffer_view", &view_buffer)],
        );
        let frame_views =
            gpu.uniform_buffer("solari_scene/gbuffer_frame_views", &GpuFrameViews::zeroed());
        let reader_layout = Self::reader_layout(gpu);
        let reader_groups = reader_groups(gpu, &reader_layout, &frame_views, &targets);
        Ok(Self {
            producer: made,
            kind: producer,
            view_buffer,
            view_group,
            transforms_layout,
            transforms: None,
            targets,
            parity: 0,
            size: (width, height),
            last_view_proj: None,
            last_instances: Vec::new(),
            draws: Vec::new(),
            history_valid: false,
            camera_moved: true,
            frame_views,
            last_view: None,
            reader_layout,
            reader_groups,
            overrides: None,
            transforms_generation: 0,
        })
    }

    /// Allocates the override buffer (32 bytes per pixel) and the pass that applies it
    /// ([`crate::gbuffer_override`]); idempotent. The targets must be storage textures: the
    /// raster producer's are rebuilt with storage usage (history restarts once), and an
    /// adapter without [`MOTION_FORMAT`] storage refuses, as for the traced producer
    /// ([`GBufferProducer::traced_support`]).
    pub fn enable_overrides(&mut self, gpu: &Gpu) -> Result<(), GpuError> {
        if self.overrides.is_some() {
            return Ok(());
        }
        GBufferProducer::traced_support(gpu).map_err(|e| match e {
            GpuError::Unsupported(m) => GpuError::Unsupported(format!("G-buffer overrides: {m}")),
            other => other,
        })?;
        if self.kind == GBufferProducer::Raster {
            self.rebuild_targets(gpu, self.size, true);
        }
        self.overrides = Some(OverridePass::new(gpu, &self.targets, self.size)?);
        Ok(())
    }

    /// The per-pixel override buffer that writers bind (WGSL `array<GBufferOverride>`,
    /// row-major), when [`GBuffer::enable_overrides`] made one. A writer stores every pixel's
    /// slot every frame (an override, or none), so it may be shared scratch
    /// ([`GBuffer::use_override_scratch`]).
    pub fn overrides(&self) -> Option<&wgpu::Buffer> {
        self.overrides.as_ref().map(|o| o.buffer())
    }

    /// Scratch bytes the overrides need to move into shared scratch (32 per pixel), or 0
    /// when overrides are not enabled.
    pub fn override_scratch_bytes(&self) -> u64 {
        self.overrides
            .as_ref()
            .map_or(0, |_| OverridePass::bytes(self.size))
    }

    /// Keeps the overrides in `scratch` ([`crate::scratch`]) instead of their own buffer,
    /// which is freed (rebind writers to [`GBuffer::overrides`] afterwards). Safe because
    /// the buffer holds nothing from one frame to the next: the writer stores every pixel
    /// and the apply pass reads them in the same frame, so passes that run before the writer
    /// or after the apply may use the scratch for anything. Errors when overrides are not
    /// enabled or `scratch` is too small; a resize brings back an own buffer.
    pub fn use_override_scratch(
        &mut self,
        gpu: &Gpu,
        scratch: &wgpu::Buffer,
    ) -> Result<(), GpuError> {
        let Some(o) = &mut self.overrides else {
            return Err(GpuError::Validation(
                "GBuffer::use_override_scratch without GBuffer::enable_overrides".into(),
            ));
        };
        o.use_scratch(gpu, scratch)
    }

    /// Whether the overrides live in shared scratch ([`GBuffer::use_override_scratch`]).
    pub fn overrides_shared(&self) -> bool {
        self.overrides.as_ref().is_some_and(|o| o.shared())
    }

    /// Stores every written override into this frame's targets (profiler
    /// scope [`crate::gbuffer_override::OVERRIDE_PASS_LABELS`]`[0]`). Record it after the
    /// passes that must see the primary surfaces and before those that read the guides.
    /// Errors when overrides are not enabled.
    pub fn apply_overrides(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
    ) -> Result<Ran, GpuError> {
        let Some(o) = &self.overrides else {
            return Err(GpuError::Validation(
                "GBuffer::apply_overrides without GBuffer::enable_overrides".into(),
            ));
        };
        debug_assert_eq!(o.size(), self.size);
        Ok(o.record(encoder, frame, self.parity))
    }

    /// Last frame's instance transforms (object-to-world rows, `array<array<vec4<f32>, 3>>`,
    /// this frame's for new instances) as uploaded by [`GBuffer::prepare`]; `None` before the
    /// first prepare. The buffer is replaced when the instance count outgrows it:
    /// [`GBuffer::transforms_generation`] tells binders when.
    pub fn previous_transforms(&self) -> Option<&wgpu::Buffer> {
        self.transforms.as_ref().map(|(b, _)| b)
    }

    /// Counts the reallocations of [`GBuffer::previous_transforms`]'s buffer.
    pub fn transforms_generation(&self) -> u64 {
        self.transforms_generation
    }

    // New target sets (size or usage changed): every group over them is rebuilt and history
    // restarts.
    fn rebuild_targets(&mut self, gpu: &Gpu, size: (u32, u32), storage: bool) {
        self.targets = GBufferTargets::pair(gpu, size, self.kind, storage);
        match &mut self.producer {
            Producer::Raster(p) => p.resize(gpu, size),
            Producer::Traced(p) => p.retarget(gpu, &self.targets),
        }
        self.size = size;
        self.last_view_proj = None;
        self.last_view = None;
        self.last_instances.clear();
        self.history_valid = false;
        self.reader_groups =
            reader_groups(gpu, &self.reader_layout, &self.frame_views, &self.targets);
    }

    /// GPU memory the G-buffer holds, in bytes: both target sets (their shared motion
    /// texture once), the raster producer's depth buffer, the uniforms, last frame's
    /// transforms and the override buffer, unless it is shared scratch.
    pub fn memory_bytes(&self) -> u64 {
        let targets: u64 = self
            .targets
            .iter()
            .flat_map(|t| [&t.gbuffer, &t.emission, &t.depth])
            .chain([&self.targets[0].motion])
            .map(crate::gpu::texture_bytes)
            .sum();
        let producer = match &self.producer {
            Producer::Raster(p) => p.memory_bytes(),
            Producer::Traced(_) => 0,
        };
        let buffers = self.view_buffer.size()
            + self.frame_views.size()
            + self.transforms.as_ref().map_or(0, |(b, _)| b.size());
        let overrides = self.overrides.as_ref().map_or(0, |o| o.memory_bytes());
        targets + producer + buffers + overrides
    }

    /// Which producer writes this G-buffer.
    pub fn producer(&self) -> GBufferProducer {
        self.kind
    }

    /// The scene shape the traced producer's pipeline was specialised for (`None` for the
    /// raster producer, which draws any scene).
    pub fn trace_variant(&self) -> Option<TraceVariant> {
        match &self.producer {
            Producer::Raster(_) => None,
            Producer::Traced(p) => Some(p.variant()),
        }
    }

    /// Reallocates the targets for a new size; history (previous targets, motion) restarts.
    pub fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        check_size(gpu, width, height)?;
        if (width, height) != self.size {
            let storage = self.overrides.is_some();
            self.rebuild_targets(gpu, (width, height), storage);
            if storage {
                self.overrides = Some(OverridePass::new(gpu, &self.targets, self.size)?);
            }
        }
        Ok(())
    }

    /// Starts a frame: swaps the target sets (last frame's become [`GBuffer::previous`]) and
    /// uploads this frame's camera and instance transforms next to last frame's. An instance
    /// whose index is new or whose mesh changed has no history and gets zero motion from its
    /// own transform.
    pub fn prepare(&mut self, gpu: &Gpu, scene: &Scene, camera: &Camera) -> Result<(), GpuError> {
        self.prepare_jittered(gpu, scene, camera, [0.0; 2])
    }

    /// As [`GBuffer::prepare`], with this frame's samples `jitter` pixels from the pixel
    /// centres ([`GpuView::jitter`]). Both producers sample there, readers reconstruct
    /// positions there, and motion vectors stay unjittered: they carry the scene's and the
    /// camera's motion alone.
    pub fn prepare_jittered(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        camera: &Camera,
        jitter: [f32; 2],
    ) -> Result<(), GpuError> {
        let (w, h) = self.size;
        let view_proj = view_projection(camera, w, h);
        self.history_valid = self.last_view_proj.is_some();
        let previous_view_proj = self.last_view_proj.unwrap_or(view_proj);
        self.parity ^= 1;
        let rows = |m: Mat4| {
            let t = m.transpose();
            [
                t.x_axis.to_array(),
                t.y_axis.to_array(),
                t.z_axis.to_array(),
            ]
        };
        let previous: Vec<[[f32; 4]; 3]> = scene
            .instances
            .iter()
            .enumerate()
            .map(|(i, inst)| match self.last_instances.get(i) {
                Some(&(mesh, m)) if mesh == inst.mesh => rows(m),
                _ => rows(inst.transform),
            })
            .collect();
        let bytes: &[u8] = bytemuck::cast_slice(&previous);
        let grow = self
            .transforms
            .as_ref()
            .is_none_or(|(b, _)| b.size() < bytes.len().max(16) as u64);
        if grow {
            let buffer = gpu.storage_buffer(
                "solari_scene/gbuffer_previous_transforms",
                bytes,
                wgpu::BufferUsages::empty(),
            )?;
            let group = TRANSFORMS_BINDINGS.bind(
                gpu,
                "solari_scene/gbuffer_previous_transforms",
                &self.transforms_layout,
                &[("previous_transforms", &buffer)],
            );
            self.transforms = Some((buffer, group));
            self.transforms_generation += 1;
        } else if let Some((buffer, _)) = &self.transforms
            && !bytes.is_empty()
        {
            gpu.queue.write_buffer(buffer, 0, bytes);
        }
        let current = GpuView::new(camera, w, h).with_jitter(jitter);
        let view = GpuGBufferView {
            view_proj: view_proj.to_cols_array_2d(),
            previous_view_proj: previous_view_proj.to_cols_array_2d(),
            view: current,
        };
        gpu.queue
            .write_buffer(&self.view_buffer, 0, bytemuck::bytes_of(&view));
        self.camera_moved = !self.history_valid
            || self
                .last_view
                .is_none_or(|last| !last.same_camera(&current));
        let views = GpuFrameViews {
            current,
            previous: self.last_view.unwrap_or(current),
            history_valid: self.history_valid as u32,
            _pad: [0; 3],
        };
        gpu.queue
            .write_buffer(&self.frame_views, 0, bytemuck::bytes_of(&views));
        self.last_view = Some(current);
        // Reuse last frame's allocations.
        self.draws.clear();
        self.draws
            .extend(scene.instances.iter().enumerate().map(|(i, inst)| {
                (
                    scene.meshes[inst.mesh as usize].indices.len() as u32,
                    i as u32,
                )
            }));
        self.last_view_proj = Some(view_proj);
        self.last_instances.clear();
        self.last_instances
            .extend(scene.instances.iter().map(|i| (i.mesh, i.transform)));
        Ok(())
    }

    /// Records the producer into this frame's targets (profiler scope [`PASS_LABELS`]`[0]`)
    /// and returns what ran. `scene` must be the scene passed to [`GBuffer::prepare`],
    /// uploaded with the backend the pass was built for; a traced producer specialised for
    /// another scene shape is refused ([`TraceVariant::check`]).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        scene: &GpuScene,
    ) -> Result<Ran, GpuError> {
        if let Producer::Traced(p) = &self.producer {
            p.variant().check(scene)?;
        }
        let mut ran = Ran::none();
        let Some((_, transforms)) = &self.transforms else {
            return Err(GpuError::Validation(
                "GBuffer::encode before GBuffer::prepare".into(),
            ));
        };
        let groups = [&self.view_group, transforms];
        frame.scope(PASS_LABELS[0], encoder, &mut ran, |e| {
            match &self.producer {
                Producer::Raster(p) => p.record(e, scene, groups, self.current(), &self.draws),
                Producer::Traced(p) => p.record(e, scene, groups, self.parity, self.size),
            }
        });
        Ok(ran)
    }

    /// The targets of the frame being rendered.
    pub fn current(&self) -> &GBufferTargets {
        &self.targets[self.parity]
    }

    /// Last frame's targets (meaningful when [`GBuffer::history_valid`]).
    pub fn previous(&self) -> &GBufferTargets {
        &self.targets[self.parity ^ 1]
    }

    /// Whether [`GBuffer::previous`] and the motion vectors refer to a real previous frame
    /// (false on the first frame and after a resize).
    pub fn history_valid(&self) -> bool {
        self.history_valid
    }

    /// Target size in pixels.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// The layout of bind group 1 for compute passes that read the G-buffer through
    /// `gbuffer_read.wesl`: [`crate::gbuffer_input::reader_layout`], whose docs list the
    /// bindings.
    pub fn reader_layout(gpu: &Gpu) -> wgpu::BindGroupLayout {
        crate::gbuffer_input::reader_layout(gpu)
    }

    /// Bind group 1 for this frame (see [`GBuffer::reader_layout`]); valid after
    /// [`GBuffer::prepare`].
    pub fn reader_group(&self) -> &wgpu::BindGroup {
        &self.reader_groups[self.parity]
    }
}

// One reader group per parity: `current` is targets[parity], `previous` the other set.
fn reader_groups(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    views: &wgpu::Buffer,
    targets: &[GBufferTargets; 2],
) -> [wgpu::BindGroup; 2] {
    [0, 1].map(|parity| {
        let (now, before) = (&targets[parity], &targets[parity ^ 1]);
        crate::gbuffer_input::reader_group(
            gpu,
            layout,
            views,
            now.reader_views(),
            before.reader_views(),
        )
    })
}

impl GBufferSource for GBuffer {
    fn bind_group(&self) -> Result<&wgpu::BindGroup, GpuError> {
        Ok(self.reader_group())
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

pub(crate) fn check_size(gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
    let limit = gpu.device.limits().max_texture_dimension_2d;
    if width == 0 || height == 0 {
        return Err(GpuError::Validation(format!(
            "G-buffer size {width}×{height} is empty"
        )));
    }
    if width.max(height) > limit {
        return Err(GpuError::OverLimit {
            what: "G-buffer size".into(),
            needed: width.max(height) as u64,
            limit: limit as u64,
        });
    }
    Ok(())
}
