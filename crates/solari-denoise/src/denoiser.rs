//! The [`Denoiser`] trait, what it reads ([`DenoiserInputs`]) and what it asks of the adapter
//! ([`Requirements`]).

use solari_scene::GpuError;
use solari_scene::gbuffer_input::GBufferSource;
use solari_scene::gpu::Gpu;
use solari_scene::pass::{FrameContext, Ran};

/// Noisy lighting as the renderer produced it: linear radiance, one `vec4<f32>` per pixel at
/// the render resolution, row by row from the top left; `w` is 1 on surfaces and 0 on the
/// background (which is passed through untouched).
#[derive(Clone, Copy, Debug)]
pub enum Lighting<'a> {
    /// Everything in one image: emission plus diffuse and specular light.
    Combined(&'a wgpu::Buffer),
    /// Diffuse and specular light apart (emission in `diffuse`). A denoiser that keeps two
    /// signals filters each with its own albedo and history, so sharp reflections are not
    /// blurred by the diffuse filter's width.
    Split {
        /// Emission plus diffuse light; on background pixels (no surface) the background
        /// radiance, which is passed through.
        diffuse: &'a wgpu::Buffer,
        /// Specular light.
        specular: &'a wgpu::Buffer,
    },
}

impl Lighting<'_> {
    /// The [`Inputs`] flag this form needs.
    pub fn input(&self) -> Inputs {
        match self {
            Lighting::Combined(_) => Inputs::COMBINED_LIGHTING,
            Lighting::Split { .. } => Inputs::SPLIT_LIGHTING,
        }
    }
}

/// One frame's inputs.
///
/// The guides come from a G-buffer ([`GBufferSource`]: Solari's raster pass or your own),
/// which holds everything the trait promises a denoiser: demodulation albedos (base colour,
/// metallic and specular F0, from which diffuse albedo `base × (1 − metallic)` and specular
/// albedo `mix(F0, base, metallic)` follow), shading normal and roughness, depth, emission
/// and motion vectors, for this frame and the last.
#[derive(Clone, Copy)]
pub struct DenoiserInputs<'a> {
    /// The noisy lighting.
    pub lighting: Lighting<'a>,
    /// This frame's G-buffer: Solari's, after [`solari_scene::gbuffer::GBuffer::encode`] was
    /// recorded into the same encoder, or your own bound by
    /// [`solari_scene::gbuffer_input::ExternalGBuffer`].
    pub gbuffer: &'a dyn GBufferSource,
    /// Optional distance to the hit of each pixel's secondary ray (`f32` per pixel; 0 where
    /// none), for denoisers that size their filter by it. Pass it only when
    /// [`Requirements::inputs`] asks for [`Inputs::HIT_DISTANCE`].
    pub hit_distance: Option<&'a wgpu::Buffer>,
    /// Optional: what each pixel's direct-light shadow ray did (one `u32` per pixel, two
    /// bfloat16 as `solari_scene::packing::pack_bf16x2_unsigned` packs them: the luminance
    /// of the light it removed, and the width in world units of the penumbra its blocker
    /// casts at the pixel; zeros where nothing blocks), as `solari_restir::RestirDi::shadow`
    /// writes it. With it the fallback denoiser tells hard
    /// shadows from noise (a shadow edge whose penumbra is under a pixel is not noise), on
    /// young histories and where a flickering penumbra would open its filter across the
    /// edge. Pass it only when [`Requirements::inputs`] asks for [`Inputs::SHADOW`].
    pub shadow: Option<&'a wgpu::Buffer>,
    /// Drop all history (camera cut, teleport, scene switch).
    pub reset: bool,
}

/// A set of inputs a denoiser reads (a small bit set; combine with `|`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Inputs(u32);

impl Inputs {
    /// [`Lighting::Combined`].
    pub const COMBINED_LIGHTING: Self = Self(1);
    /// [`Lighting::Split`].
    pub const SPLIT_LIGHTING: Self = Self(2);
    /// The G-buffer's guides (albedo, normal, roughness, depth, motion).
    pub const GUIDES: Self = Self(4);
    /// [`DenoiserInputs::hit_distance`].
    pub const HIT_DISTANCE: Self = Self(8);
    /// [`DenoiserInputs::shadow`].
    pub const SHADOW: Self = Self(16);

    /// No inputs.
    pub const fn empty() -> Self {
        Self(0)
    }

    /// Whether every input of `other` is in `self`.
    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }
}

impl std::ops::BitOr for Inputs {
    type Output = Self;
    fn bitor(self, rhs: Self) -> Self {
        Self(self.0 | rhs.0)
    }
}

/// What a denoiser needs from the adapter and the renderer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Requirements {
    /// Device features it uses.
    pub features: wgpu::Features,
    /// The only backend it runs on, if it is tied to one (DLSS-RR: Vulkan).
    pub backend: Option<wgpu::Backend>,
    /// The inputs it accepts; inputs outside this set need not be produced at all.
    pub inputs: Inputs,
}

impl Requirements {
    /// Whether `gpu` can run a denoiser with these requirements; otherwise why not.
    pub fn check(&self, gpu: &Gpu) -> Result<(), String> {
        if !gpu.features.contains(self.features) {
            return Err(format!(
                "{} lacks features {:?}",
                gpu.info.name,
                self.features - gpu.features
            ));
        }
        match self.backend {
            Some(b) if b != gpu.info.backend => Err(format!(
                "needs the {b:?} backend; {} runs on {:?}",
                gpu.info.name, gpu.info.backend
            )),
            _ => Ok(()),
        }
    }
}

/// A denoiser: reads one frame's noisy lighting and guides, writes the denoised image at its
/// output resolution (a denoiser may upscale: render at [`Denoiser::render_size`]).
///
/// Call [`Denoiser::encode`] once per frame after the lighting passes were recorded, submit
/// the encoder and then [`Encoded::after`] in the same submission, and read the result from
/// [`Denoiser::output`].
pub trait Denoiser {
    /// Short name for logs and reports (`fallback`, `dlss-rr`).
    fn name(&self) -> &'static str;

    /// What it needs; the renderer produces only these inputs.
    fn requirements(&self) -> Requirements;

    /// The resolution the renderer must render at.
    fn render_size(&self) -> (u32, u32);

    /// The resolution of [`Denoiser::output`].
    fn output_size(&self) -> (u32, u32);

    /// Profiler scope names of its passes, in the order they run.
    fn pass_labels(&self) -> &'static [&'static str];

    /// Records one frame (each pass in a profiler scope named by its label when `frame`
    /// carries a profiler): what ran, and command buffers to submit after `encoder`'s.
    fn encode(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        inputs: &DenoiserInputs,
    ) -> Result<Encoded, GpuError>;

    /// The denoised image: one `vec4<f32>` per output pixel (linear radiance, `w` as in the
    /// input), row by row from the top left.
    fn output(&self) -> &wgpu::Buffer;

    /// GPU memory it holds, in bytes (a shared scratch buffer is its owner's).
    fn memory_bytes(&self) -> u64;

    /// Bytes of per-frame buffers it can keep in a scratch buffer shared with other passes
    /// ([`solari_scene::scratch`]); 0 (the default) takes none.
    fn scratch_bytes(&self) -> u64 {
        0
    }

    /// Keeps its per-frame buffers in `scratch` (at least [`Denoiser::scratch_bytes`], a
    /// storage buffer) and frees its own; history restarts. Other passes may use `scratch`
    /// before [`Denoiser::encode`]'s work and after it (the output never lives there). The
    /// default takes nothing and succeeds.
    fn use_scratch(&mut self, gpu: &Gpu, scratch: &wgpu::Buffer) -> Result<(), GpuError> {
        let _ = (gpu, scratch);
        Ok(())
    }
}

/// What [`Denoiser::encode`] recorded.
#[derive(Debug)]
pub struct Encoded {
    /// The passes it ran, by label (from [`Denoiser::pass_labels`]).
    pub ran: Ran,
    /// Command buffers that must be submitted right after the encoder's, in order and in the
    /// same submission (denoisers that record outside wgpu, as DLSS-RR does, need them; the
    /// fallback gives none).
    pub after: Vec<wgpu::CommandBuffer>,
}

/// Which denoiser `--denoiser` names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DenoiserKind {
    /// The raw, noisy image.
    None,
    /// [`crate::FallbackDenoiser`]: portable compute, every adapter.
    Fallback,
    /// DLSS Ray Reconstruction: NVIDIA RTX GPUs on Vulkan, in builds with the `dlss` feature.
    DlssRr,
}

impl DenoiserKind {
    /// Parses `none`, `fallback` or `dlss-rr`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "none" | "off" => Some(Self::None),
            "fallback" | "svgf" => Some(Self::Fallback),
            "dlss-rr" | "dlss" => Some(Self::DlssRr),
            _ => None,
        }
    }

    /// The name `parse` accepts.
    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Fallback => "fallback",
            Self::DlssRr => "dlss-rr",
        }
    }
}
