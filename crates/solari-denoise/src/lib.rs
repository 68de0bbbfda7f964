//! # solari-denoise
//!
//! Denoisers for the Solari workspace behind one trait, [`Denoiser`]: a renderer hands it the
//! noisy lighting of a frame and the G-buffer, and reads back a denoised image.
//!
//! - [`FallbackDenoiser`] runs on every adapter with compute shaders (after SVGF, below).
//! - `dlss::DlssRrDenoiser` (cargo feature `dlss`) wraps NVIDIA's DLSS Ray Reconstruction
//!   through `dlss_wgpu`, on NVIDIA RTX GPUs under Vulkan. [`create`] picks one the adapter
//!   supports and says why when it falls back.
//!
//! ## The fallback, and why SVGF
//!
//! The issue offered SVGF (spatiotemporal variance-guided filtering, Schied et al. 2017) or a
//! recurrent blur after NVIDIA's ReBLUR. The fallback follows SVGF because its inputs are
//! exactly what Solari's renderer has: combined (or split) lighting and a G-buffer. ReBLUR
//! sizes its blur by each sample's hit distance and needs per-signal specular lobe data to do
//! so well; Solari's DI has no secondary hit distance, and ReBLUR's quality over SVGF comes
//! mostly from that. SVGF's à-trous filter is also a fixed number of passes with no
//! recurrent state beyond the temporal history, which keeps its cost flat and easy to
//! measure.
//!
//! Per signal (one for [`Lighting::Combined`], diffuse and specular for [`Lighting::Split`]):
//!
//! 1. **Demodulation**: emission (exact) is subtracted and the rest divided by the albedo
//!    (`base × (1 − metallic)` + `mix(F0, base, metallic)` for combined lighting), so the
//!    filters blur lighting, not texture; the last pass multiplies back and adds emission.
//! 2. **Temporal accumulation**: last frame's history is fetched at the motion-vector
//!    reprojection with bilinear taps, each kept only where the G-buffer sees the same
//!    surface (tangent plane within 0.3% of the view distance, normals within 25°, the same
//!    test ReSTIR DI uses); a pixel with no kept tap is disoccluded and starts over. Each
//!    pixel keeps its history length (up to [`FallbackSettings::max_history`]); the colour is
//!    averaged with weight 1/length. The history is stored in 24 bytes a pixel (12-, 16- and
//!    21-bit floats of our own, rounded stochastically so that a slow average never stalls
//!    short of its target; [`history`]), half its `f32` size, with no change measured in the
//!    denoised error.
//! 3. **Rejecting bad samples**: NaN, infinite and overflowing samples are not accumulated;
//!    the pixel keeps its history, or without one is filled by the spatial filter from its
//!    neighbours. Nothing non-finite reaches the history or the output.
//! 4. **Fireflies**: a sample brighter than [`FallbackSettings::firefly_clamp`] × the recent
//!    mean is scaled down and the excess carried to the pixel's next frame, where it is added
//!    before the same test. Energy is delayed, not removed: at least
//!    1/[`FallbackSettings::firefly_spread`] of it is released each frame. Only a carry still
//!    pending when its pixel is disoccluded or reset is lost.
//! 5. **Fast history reset** (ReBLUR's history fix): a 4-frame luminance average of each
//!    pixel's own samples runs beside its long one; the long one is kept within
//!    [`FallbackSettings::reset_sigma`] deviations of the fast one (deviation measured in calm
//!    frames, relative) plus 10%, the colour history rescaled with it and its length held at
//!    [`FallbackSettings::reset_length`]. A light dropping to 10% is followed within 10% in
//!    43 frames instead of over 100 (tests, ±50% per-pixel noise).
//! 6. **Variance**: from the temporal luminance moments, blended in (geometrically) from a
//!    5×5 neighbourhood estimate over the first 2 ×
//!    [`FallbackSettings::spatial_variance_frames`] frames of a history (SVGF switches at 4
//!    frames; the switch made the image pop). With [`DenoiserInputs::shadow`], where every
//!    penumbra in the window is under a pixel, the window's estimate is taken over the
//!    shadow-free signal and, at any history length, caps the temporal variance, so a
//!    flickering sub-pixel penumbra does not open the filter across a hard shadow edge
//!    (the window's per-pixel data comes from the temporal pass; the arithmetic has a Rust
//!    twin, [`variance::pixel_variance`]). Tried and dropped: the calmest of the window's
//!    four 3×3 corners, meant to keep hard shadow edges; at 1080p on the H200 it made the
//!    first frame worse in the Cornell box (RMSE 0.00073 → 0.00094) and in many_lights
//!    (0.071 → 0.110, energy −5% → −10%) for a small gain on sun_boxes (0.026 → 0.020).
//! 7. **À-trous**: [`FallbackSettings::atrous_iterations`] passes of a B3-spline kernel with
//!    steps 1, 2, 4, … (by default the 13 taps of the 5×5 kernel within two steps by
//!    Manhattan distance, [`AtrousKernel::Diamond`]; all 25 with [`AtrousKernel::Full`]: on
//!    an H100 at 1080p the 13 took 27–30% less time at the same error against full-bounce
//!    references, `benches/RESULTS.md`), weighted by tangent-plane distance (found from each
//!    tap's depth alone, `denoise_plane.wesl`), shading-normal angle (also
//!    against the specular lobe's width, [`FallbackSettings::phi_lobe`], for the specular
//!    share of the pixel) and luminance difference in units of the local standard deviation; variance is filtered
//!    alongside (weights squared). Optionally ([`FallbackSettings::history_feedback`], off
//!    by default) the first pass's result is fed back as the colour history, as SVGF does.
//!
//! ## Measured bias (lavapipe tests)
//!
//! - ReSTIR DI, Cornell box: the long-run mean keeps the raw mean's energy (−0.16%); its
//!   RMSE to the reference grows from 0.0016 to 0.0027 (the spatial blur at edges).
//! - Firefly clamp alone: −1.05% on input with 1% of samples 100× brighter.
//! - The history fix is biased on such heavy tails (+9% with the defaults, +27% without the
//!   clamp): it reads a burst of fireflies as a change in lighting.
//!
//! ## Limits
//!
//! - The first frame after a disocclusion gets the spatial filter alone, with its luminance
//!   guide loosened by the raised young-history variance. The Cornell box's frame 1 at
//!   128 px: RMSE 0.0040 against 0.0075 raw; at 64 px, where the default footprint (±62 px)
//!   spans the whole image, 0.0075 against 0.0077. Without the shadow input, hard,
//!   noise-free sun shadows lose a few pixels of sharpness on young histories (sun_boxes at
//!   1080p is closer to the reference raw than denoised for the first frames); with it, no
//!   frame of sun_boxes' first 16 is worse than its input (96×96, `benches/RESULTS.md`).
//! - Moving objects: the same-surface test compares world positions, so a moving surface
//!   loses its history every frame and shows the spatial filter's result alone (noisier, but
//!   no ghost trail).
//! - One filter for diffuse and specular in combined mode: glossy reflections are blurred by
//!   the luminance-guided filter like diffuse light. Pass [`Lighting::Split`] to keep them
//!   apart.
//!
//! ## Use
//!
//! ```no_run
//! # fn main() -> Result<(), solari_scene::GpuError> {
//! use solari_denoise::{Denoiser, DenoiserInputs, FallbackDenoiser, FallbackSettings, Lighting};
//! # let gpu = solari_scene::gpu::Gpu::new()?;
//! # let backend = gpu.backend(solari_scene::gpu::TracerChoice::Auto)?;
//! # let gbuffer = solari_scene::gbuffer::GBuffer::new(&gpu, backend, 64, 64)?;
//! # let noisy = gpu.device.create_buffer(&wgpu::BufferDescriptor { label: None, size: 64 * 64 * 16, usage: wgpu::BufferUsages::STORAGE, mapped_at_creation: false });
//! let mut denoiser = FallbackDenoiser::new(&gpu, 64, 64, FallbackSettings::default())?;
//! let mut encoder = gpu.device.create_command_encoder(&Default::default());
//! // ... record the G-buffer and the lighting passes that fill `noisy` ...
//! let inputs = DenoiserInputs { lighting: Lighting::Combined(&noisy), gbuffer: &gbuffer, hit_distance: None, shadow: None, reset: false };
//! # let camera = solari_scene::default_scene::cornell_box().camera(None).unwrap();
//! let frame = solari_scene::pass::FrameContext::new(0, (64, 64), &camera, None);
//! let encoded = denoiser.encode(&gpu, &mut encoder, &frame, &inputs)?;
//! gpu.queue.submit(std::iter::once(encoder.finish()).chain(encoded.after));
//! // `denoiser.output()` now holds one vec4<f32> per pixel.
//! # Ok(()) }
//! ```
//!
//! The crate README has a complete example on a real scene.

pub mod denoiser;
#[cfg(feature = "dlss")]
pub mod dlss;
pub mod dlss_io;
pub mod fallback;
pub mod history;
pub mod select;
pub mod settings;
pub mod upscale;
pub mod variance;

pub use denoiser::{
    Denoiser, DenoiserInputs, DenoiserKind, Encoded, Inputs, Lighting, Requirements,
};
pub use fallback::{FallbackDenoiser, GpuHistory};
pub use select::{Created, DlssAvailability, create, create_gpu};
pub use settings::{
    AtrousKernel, FallbackSettings, GpuDenoiseParams, GpuPassParams, PHI_MAX, PHI_MIN,
};
pub use upscale::{TemporalUpscaler, UpscaleSettings};

/// The crate's importable WGSL modules, by module name.
pub const MODULES: &[(&str, &str)] = &[
    (
        "denoise_common",
        include_str!("../shaders/denoise_common.wesl"),
    ),
    (
        "denoise_atrous_filter",
        include_str!("../shaders/denoise_atrous_filter.wesl"),
    ),
    (
        "denoise_history",
        include_str!("../shaders/denoise_history.wesl"),
    ),
    (
        "denoise_plane",
        include_str!("../shaders/denoise_plane.wesl"),
    ),
    (
        "denoise_variance_math",
        include_str!("../shaders/denoise_variance_math.wesl"),
    ),
];

/// The crate's entry-point shaders, by module name.
pub const ENTRY_POINTS: &[(&str, &str)] = &[
    (
        "denoise_temporal",
        include_str!("../shaders/denoise_temporal.wesl"),
    ),
    (
        "denoise_variance",
        include_str!("../shaders/denoise_variance.wesl"),
    ),
    (
        "denoise_atrous",
        include_str!("../shaders/denoise_atrous.wesl"),
    ),
    (
        "denoise_atrous_feedback",
        include_str!("../shaders/denoise_atrous_feedback.wesl"),
    ),
    ("dlss_inputs", include_str!("../shaders/dlss_inputs.wesl")),
    ("dlss_output", include_str!("../shaders/dlss_output.wesl")),
    (
        "temporal_upscale",
        include_str!("../shaders/temporal_upscale.wesl"),
    ),
    ("upscale_copy", include_str!("../shaders/upscale_copy.wesl")),
];

/// Every module the crate's shaders need beyond `solari-scene`'s.
pub fn modules() -> Vec<(&'static str, &'static str)> {
    [MODULES, ENTRY_POINTS].concat()
}

/// The README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
