//! The real-time renderer: G-buffer → light tiles → world cache upkeep → ReSTIR DI →
//! GI (ReSTIR GI, plain path GI or cache-only, [`GiMode`]) → denoiser, one frame per call, with a report of which passes ran and their
//! GPU times.
//!
//! Passes a frame does not need are skipped: with no lights, neither the light tiles nor
//! ReSTIR DI run, and the frame shows emission only (pass `emission_only`); with
//! [`GiMode::Off`] (and outside [`FrameView::WorldCache`]) the world cache neither runs nor
//! holds memory, and ReSTIR GI runs only in the traced GI modes.
//!
//! With [`RealtimeSettings::finite_check`] on, every pass's output is checked for NaN,
//! infinite and negative values on the GPU every frame ([`solari_scene::finite_check`]), and
//! the counts per pass ([`FINITE_SLOTS`]) come with the frame's report.

use crate::gbuffer_choice::{GBufferChoice, GBufferTiming};
use crate::light_change::{LIGHT_CHANGE_SHARE, power_change_share};
use crate::present::Presenter;
use solari_denoise::{
    Denoiser, DenoiserInputs, DenoiserKind, DlssAvailability, FallbackSettings, Lighting,
    TemporalUpscaler, UpscaleSettings,
};
use solari_lights::{
    GpuLights, LightGrid, LightGridReport, LightGridSettings, LightList, LightTileSettings,
    LightTiles, Selection,
};
use solari_restir::{
    GI_PASS_LABELS, PASS_LABELS as DI_LABELS, PsrBindings, RestirDi, RestirDiSettings, RestirGi,
    RestirGiSettings, SPECULAR_PASS_LABELS, SpecularGi, SpecularGiSettings,
};
use solari_scene::finite_check::{FiniteChecker, FiniteCount, RecordLayout, first_offender};
use solari_scene::gbuffer::GBuffer;
use solari_scene::gbuffer_debug::{GBufferChannel, GBufferDebug};
use solari_scene::gbuffer_input::GBufferSource;
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::{GpuScene, TraceVariant};
use solari_scene::gpu_types::{GpuView, halton_jitter};
use solari_scene::pass::{FrameContext, Ran};
use solari_scene::primary_depth::PrimaryDepth;
use solari_scene::shaders::Backend;
use solari_scene::{Camera, GpuError, Scene};
use solari_worldcache::{CacheStats, WorldCache, WorldCacheSettings};
use wgpu_profiler::{GpuProfiler, GpuProfilerSettings};

use solari_worldcache::PASS_LABELS as CACHE;

/// ReSTIR DI's [`RestirDiSettings::reuse_light_threshold`] in [`RealtimeSettings::default`]:
/// with the fallback denoiser, scenes whose light sampling has at most 64 elements (emissive
/// triangles plus analytic lights, no environment map) skip DI's reuse. The renderer applies
/// the threshold only while the fallback denoiser runs ([`RealtimeRenderer::di_reuse_skipped`]).
///
/// The figures (H100, 1920×1080, defaults with the fallback denoiser; `benches/RESULTS.md`,
/// "ReSTIR DI's reuse against the frame" and "Reuse by the lights' count"): without reuse the
/// frame took 16% less on `interior` (13 elements: 4.91 → 4.14 ms) and 9% less on the Cornell
/// box (2) and sun_boxes (1), with the frame's relMSE against a 1024-spp reference within −6%
/// to +4% (`interior` converged 6% closer to it); on many_lights (32,000 emissive triangles)
/// it raised the error 20–63%. Any threshold from 13 to 31,999 separates those four scenes;
/// 64 keeps reuse for scenes of a few dozen small lights, which nothing measured. Without a
/// denoiser reuse pays even on `interior` (its raw frames' relMSE 25% higher without it),
/// and DLSS-RR is unmeasured: both keep reuse.
pub const DI_REUSE_LIGHT_THRESHOLD: u32 = 64;

/// [`RealtimeSettings::path_gi_shade_apart_triangles`] by default: plain path GI shades in a
/// dispatch of its own ([`RestirGiSettings::shade_apart`]) in scenes of at least this many
/// triangles (counted per instance). Measured on an H100 at 1080p (defaults with the
/// fallback denoiser, three reps): GI's pass −7.9% on `interior` (294,424 triangles; the
/// frame 3.825 → 3.752 ms), −0.9% on many_lights (32,122, within noise), +6.1% on sun_boxes
/// (8,022) and +19% on the Cornell box (32), whose traversal costs too little for the second
/// read of the G-buffer to pay (`benches/RESULTS.md`, "The temporal merge in a dispatch of
/// its own"). Any threshold from 32,123 to 294,424 separates what was measured; 65,536
/// leaves the scenes near many_lights' size as they were.
pub const PATH_GI_SHADE_APART_TRIANGLES: u64 = 65_536;

/// `settings` as the renderer runs them with `denoiser`: the reuse threshold only under the
/// fallback denoiser, where it was measured ([`DI_REUSE_LIGHT_THRESHOLD`]).
fn di_settings_for(settings: RestirDiSettings, denoiser: DenoiserKind) -> RestirDiSettings {
    if denoiser == DenoiserKind::Fallback {
        return settings;
    }
    RestirDiSettings {
        reuse_light_threshold: 0,
        ..settings
    }
}

/// Pass names as [`FrameReport`] lists them, in frame order: the G-buffer, light tiles, the
/// world cache's upkeep ([`solari_worldcache::PASS_LABELS`]), ReSTIR DI
/// ([`solari_restir::PASS_LABELS`]), ReSTIR GI or plain path GI
/// ([`solari_restir::GI_PASS_LABELS`]), cache-only GI or the cache view, specular GI
/// ([`solari_restir::SPECULAR_PASS_LABELS`]) and the G-buffer overrides it wrote (primary
/// surface replacement, [`solari_scene::gbuffer_override::OVERRIDE_PASS_LABELS`]), then the fallback
/// denoiser's passes ([`solari_denoise::fallback::PASS_LABELS`]) or DLSS-RR's input copy
/// (DLSS-RR itself records outside the profiler's reach).
pub const PASS_NAMES: [&str; 21] = [
    solari_scene::gbuffer::PASS_LABELS[0],
    solari_lights::PASS_LABELS[0],
    CACHE[0],
    CACHE[1],
    CACHE[2],
    CACHE[3],
    DI_LABELS[0],
    DI_LABELS[1],
    DI_LABELS[2],
    GI_PASS_LABELS[0],
    GI_PASS_LABELS[1],
    CACHE[4],
    CACHE[5],
    SPECULAR_PASS_LABELS[0],
    solari_scene::gbuffer_override::OVERRIDE_PASS_LABELS[0],
    DENOISE[0],
    DENOISE[1],
    DENOISE[2],
    solari_scene::primary_depth::PASS_LABELS[0],
    solari_denoise::upscale::PASS_LABELS[0],
    solari_denoise::dlss_io::COPY_LABELS[0],
];

use solari_denoise::fallback::PASS_LABELS as DENOISE;

/// The passes whose outputs the non-finite detector checks, in frame order (a slot counts
/// what its pass wrote: the G-buffer's emission, motion and depth; the tile samples; the
/// world cache's cells; ReSTIR DI's reservoirs and image; ReSTIR GI's reservoirs; the image
/// after GI of any kind and specular GI (or the cache view); the denoiser's output).
pub const FINITE_SLOTS: [&str; 7] = [
    "gbuffer",
    "light_tiles",
    "world_cache",
    "restir_di",
    "restir_gi",
    "cache_gi",
    "denoise",
];

// Indices into FINITE_SLOTS, so the frame loop names the slot it checks.
const SLOT_GBUFFER: usize = 0;
const SLOT_TILES: usize = 1;
const SLOT_CACHE: usize = 2;
const SLOT_DI: usize = 3;
const SLOT_GI: usize = 4;
const SLOT_CACHE_GI: usize = 5;
const SLOT_DENOISE: usize = 6;

/// Which of [`PASS_NAMES`] ran this frame, marked by name (a name not in the list is
/// ignored: it has no row in the report).
struct Marks([bool; PASS_NAMES.len()]);

// A frame submitted and not yet reported.
struct InFlight {
    frame: u32,
    // Whether the profiler timed this frame (it then holds a frame of results for it).
    timed: bool,
    ran: Marks,
    submission: wgpu::SubmissionIndex,
    // The detector's read-back buffer for this frame.
    readback: Option<usize>,
    // The world cache counters' read-back buffer for this frame.
    cache_readback: Option<usize>,
}

impl Marks {
    fn mark(&mut self, name: &str) {
        if let Some(i) = PASS_NAMES.iter().position(|n| *n == name) {
            self.0[i] = true;
        }
    }

    // Every pass a component's `encode` reports.
    fn add(&mut self, ran: &Ran) {
        for label in ran.labels() {
            self.mark(label);
        }
    }
}

/// What the renderer does with the non-finite detector.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FiniteCheck {
    /// No checks (no cost).
    #[default]
    Off,
    /// Count per pass every frame and report ([`FrameReport::finite`]), read back with the
    /// frame's report (late with [`RealtimeRenderer::submit`]).
    Count,
    /// As `Count`, and a frame with any finding returns [`GpuError::NonFinite`] naming the
    /// first pass that had one.
    Fail,
}

/// Whether full-scale frames are antialiased: while the camera stands still, the camera is
/// jittered within the pixel and the temporal upscaler ([`solari_denoise::TemporalUpscaler`])
/// accumulates the samples, so each pixel converges to its area average (what the reference
/// tracer's jittered paths give) and edges stop stair-stepping. A frame whose camera moved
/// (and the first) is rendered unjittered and passes through the upscaler unchanged (its
/// history dropped). Below an internal scale of 1 the upscaler runs, jittered, whatever this
/// says.
///
/// Why only a still camera: a jittered sample estimates its pixel's area worse than the
/// centre's does (at an edge, twice the squared error on average) until frames accumulate,
/// and under motion neither the denoiser's history nor the upscaler's held them: jittered
/// every frame, the orbit camera's images were 1.7–420× worse in relMSE (1920×1080 on an H100,
/// `benches/RESULTS.md`, "Antialiasing by default"). Objects that move under a still camera
/// are still accumulated through the motion vectors, and blur somewhat.
///
/// The default, [`Antialias::Auto`], antialiases under the fallback denoiser: on a still
/// camera it cut relMSE of the 136th frame against 1024-spp references 1.9× on the Cornell
/// box, 1.8× on sun_boxes, 1.5× on many_lights and 1.2× on interior for 0.10–0.14 ms a frame
/// at 1920×1080 (H100), at 16 bytes per pixel (32 MiB at 1080p). It leaves DLSS-RR alone (it
/// antialiases by itself) and the raw image ([`DenoiserKind::None`]), which stays one
/// unjittered sample per pixel for those who measure the lighting itself.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Antialias {
    /// On with the fallback denoiser; off with DLSS-RR and without a denoiser.
    #[default]
    Auto,
    /// Always (with the fallback denoiser or none; refused with DLSS-RR, and a best-available
    /// denoiser becomes the fallback).
    On,
    /// Never (one sample at each pixel's centre, as before antialiasing existed).
    Off,
}

impl Antialias {
    /// Parses `auto`, `on` or `off`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "auto" => Some(Self::Auto),
            "on" | "true" => Some(Self::On),
            "off" | "false" => Some(Self::Off),
            _ => None,
        }
    }

    /// `auto`, `on` or `off`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::On => "on",
            Self::Off => "off",
        }
    }

    /// Whether frames denoised by `denoiser` (the one in use) are antialiased.
    pub fn applies(self, denoiser: DenoiserKind) -> bool {
        match self {
            Self::Auto => denoiser == DenoiserKind::Fallback,
            Self::On => denoiser != DenoiserKind::DlssRr,
            Self::Off => false,
        }
    }
}

/// Indirect light. The default, [`GiMode::Path`], is the measured choice (see
/// [`RealtimeSettings::gi`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GiMode {
    /// Direct light only (ReSTIR DI).
    Off,
    /// ReSTIR DI plus albedo × the world cache's indirect irradiance at each pixel: the
    /// cheapest GI tier (blocky where cells are large; no glossy indirect light).
    WorldCache,
    /// Plain path GI: one traced diffuse bounce per pixel, lit by the world cache at its
    /// hit, no reuse ([`solari_restir::RestirGi`] with [`RestirGiSettings::plain`]).
    #[default]
    Path,
    /// ReSTIR GI: the same traced bounce, reused across frames and neighbours
    /// ([`RealtimeSettings::restir_gi`]).
    Restir,
}

impl GiMode {
    /// Parses `off`, `cache`, `path` or `restir`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "off" | "none" => Some(Self::Off),
            "cache" | "world-cache" => Some(Self::WorldCache),
            "path" | "plain" => Some(Self::Path),
            "restir" => Some(Self::Restir),
            _ => None,
        }
    }

    /// Whether the mode traces per-pixel GI rays ([`solari_restir::RestirGi`]).
    pub fn traced(self) -> bool {
        matches!(self, Self::Path | Self::Restir)
    }
}

/// What the frame's output shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FrameView {
    /// The lit image.
    #[default]
    Lit,
    /// The indirect light alone: what the GI passes (diffuse GI and specular GI) add, with
    /// no emission, direct light or environment seen directly, in radiance and through the
    /// denoiser and upscaler as the lit image goes. Light that reached the eye after two or
    /// more scattering events: compare it with a reference of `min_bounces: 2`
    /// (`solari_reference::ReferenceSettings::min_bounces`) to measure GI's own error
    /// without DI's. Every pass runs as for the lit image, so the frame costs what it does;
    /// DI's output is dropped ([`solari_restir::RestirDi::set_indirect_only`]). Not with
    /// DLSS-RR, which takes the lit image as it is. One exception: under a uniform sky that
    /// light sampling does not cover, cache GI ([`GiMode::WorldCache`]) keeps the sky the
    /// pixel's cell sees, which is direct light (the cell stores it with the rest); path and
    /// ReSTIR GI leave it out ([`solari_restir::RestirGi::set_indirect_only`]).
    /// The fallback denoiser's statistics then see the indirect light alone, not the lit
    /// frame, so a denoised indirect view is filtered as the lit frame's share would not be.
    Indirect,
    /// The world cache's cells: each pixel shows its cell's irradiance, tinted per cell.
    WorldCache,
    /// One channel of the G-buffer ([`solari_scene::gbuffer_debug`]), display-referred:
    /// presented and saved without exposure or tone curve ([`FrameView::tone_mapped`]).
    /// The lighting passes still run, so the frame costs what the lit frame does.
    GBuffer(GBufferChannel),
}

impl FrameView {
    /// Parses `lit`, `indirect`, `world-cache` or `gbuffer-CHANNEL` (`gbuffer-normal`,
    /// `gbuffer-base-color`, …: [`GBufferChannel::name`]).
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "lit" => Some(Self::Lit),
            "indirect" => Some(Self::Indirect),
            "world-cache" => Some(Self::WorldCache),
            _ => s
                .strip_prefix("gbuffer-")
                .and_then(GBufferChannel::parse)
                .map(Self::GBuffer),
        }
    }

    /// The view's name, as [`FrameView::parse`] reads it.
    pub fn name(self) -> String {
        match self {
            Self::Lit => "lit".into(),
            Self::Indirect => "indirect".into(),
            Self::WorldCache => "world-cache".into(),
            Self::GBuffer(c) => format!("gbuffer-{}", c.name()),
        }
    }

    /// Whether the output is radiance, shown through exposure and the tone curve (false
    /// for the G-buffer views, whose values are shown as they are, sRGB-encoded).
    pub fn tone_mapped(self) -> bool {
        !matches!(self, Self::GBuffer(_))
    }
}

/// What the renderer does each frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RealtimeSettings {
    /// Which pass writes the G-buffer: raster (the default), traced, or the faster of the two
    /// measured at start-up ([`GBufferChoice::Auto`]; the traced producer wins where raster
    /// hardware is scarce, `benches/RESULTS.md`).
    pub gbuffer: GBufferChoice,
    /// Light-tile presampling (Solari: 128 tiles × 1024 samples).
    pub tiles: LightTileSettings,
    /// ReSTIR DI's knobs. The default sets `reuse_light_threshold` to
    /// [`DI_REUSE_LIGHT_THRESHOLD`], which the renderer applies under the fallback denoiser
    /// only.
    pub di: RestirDiSettings,
    /// Light selection for tile samples (power-proportional by default).
    pub selection: Selection,
    /// A world-space light grid that ReSTIR DI draws most initial candidates from (default
    /// `None`: light tiles alone). For scenes with thousands of local lights, where a tile
    /// sample rarely lies near the pixel (`solari_lights::light_grid`'s docs; time against
    /// error in `benches/RESULTS.md`, "Light grid"). Built on the CPU from the light list at
    /// start-up and in [`RealtimeRenderer::set_lights`]; with it,
    /// [`RestirDiSettings::light_grid`] is set to match.
    pub light_grid: Option<LightGridSettings>,
    /// Indirect light (default [`GiMode::Path`]: one traced bounce per pixel lit by the world
    /// cache, no reuse). Chosen by measurement, last on the H200 with ReSTIR GI at half and
    /// a quarter rate (`benches/RESULTS.md`, "The reference's own noise": GI time at 1080p,
    /// error at 960×540 against 4096-path references with their noise taken out, fallback
    /// denoiser): of the modes whose GI costs no more, it has the lowest error on the Cornell
    /// box, sun_boxes and `interior`, still and moving, and is within 3.5% of the best on
    /// many_lights. ReSTIR GI at a quarter rate costs 0.14–0.27 ms more for 6–13% more error
    /// on `interior` and 9–25% more on the Cornell box. At full rate it costs 0.36–1.10 ms
    /// more; once its adaptive cap stopped on settled views (forty-fifth session, "GI's own
    /// error": the cap had made a still view 1.4% too bright on `interior` and its error 40%
    /// higher) its still error is 14% below path GI's on the Cornell box and 4% on
    /// `interior` (mean of 16 frames: 0.096 against 0.112, 1.896 against 1.974 ×10⁻³), which
    /// path GI with 4 candidates matches (0.092, 1.879) and the default frame's budget on
    /// `interior` (issue 17's 4 ms) does not leave room for. Cache-only GI's error was 21%
    /// higher on `interior` ("GI: the whole matrix").
    pub gi: GiMode,
    /// The world cache's knobs (used with any GI mode or [`FrameView::WorldCache`]).
    pub cache: WorldCacheSettings,
    /// ReSTIR GI's knobs (with [`GiMode::Restir`]; [`GiMode::Path`] uses them with reuse
    /// off).
    pub restir_gi: RestirGiSettings,
    /// Plain path GI ([`GiMode::Path`]) shades in a second dispatch in scenes of at least
    /// this many triangles, counted per instance (default
    /// [`PATH_GI_SHADE_APART_TRIANGLES`], with the figures; 0: always; `u64::MAX`: only where
    /// [`RestirGiSettings::shade_apart`] says so).
    pub path_gi_shade_apart_triangles: u64,
    /// Specular GI, the indirect light of the specular lobe (default on: with path GI it cut
    /// relMSE 1.5× on interior and 3.1× on sun_boxes for 0.08–0.53 ms at 1080p on the H200,
    /// and changed nothing measurable on scenes without glossy surfaces): reflections in
    /// metals and glossy surfaces of everything but the lights themselves (DI's). With any
    /// GI mode; with [`GiMode::Path`] and [`GiMode::Restir`] rough pixels reuse the GI
    /// reservoirs instead of tracing.
    pub specular_gi: bool,
    /// Specular GI's knobs.
    pub specular: SpecularGiSettings,
    /// Primary surface replacement (default on; with specular GI and a denoiser or the
    /// upscaler, which read the guides): mirror-metal pixels give the denoiser the surface
    /// they reflect (its depth through the mirror, normals, albedo and motion) instead of
    /// the flat mirror, so reflections are filtered and reprojected as what they show
    /// ([`solari_restir::specular`]'s docs). Costs 32 bytes per pixel and a pass of 0.033
    /// ms at 1080p on the H200; no rays. Skipped where the scene given to
    /// [`RealtimeRenderer::new`] has no material that can be a mirror metal (metallic 1,
    /// roughness below 0.02 or textured), and, with a warning, where the adapter cannot
    /// write the G-buffer as storage textures.
    pub psr: bool,
    /// What the output shows (default the lit image).
    pub view: FrameView,
    /// Measure each pass with timestamp queries (needs the adapter's timestamp features;
    /// without them times are `None`). Times come with each frame's report (late with
    /// [`RealtimeRenderer::submit`]).
    pub timestamps: bool,
    /// With `timestamps`, time every `timestamp_interval`th frame (frames 0, N, 2N, ...) and
    /// leave the others untimed (their reports' times are `None`). 1, the default, times
    /// every frame. Timing is not free: on an H200 at 1080p a timed frame's wall time was
    /// 0.065-0.08 ms longer than an untimed one's (the queries' resolve and read-back after
    /// the last pass; the passes themselves ran as fast: benches/RESULTS.md), 10% of a 0.7 ms
    /// frame, so a frame loop that reports its wall time times a sample of its frames.
    pub timestamp_interval: u32,
    /// The denoiser: `None` picks the best available (DLSS-RR where it can run, else the
    /// fallback); the default is `Some(DenoiserKind::None)`, the raw image, so that library
    /// users measuring the lighting itself get it unfiltered.
    pub denoiser: Option<DenoiserKind>,
    /// The fallback denoiser's knobs.
    pub denoise: FallbackSettings,
    /// The non-finite detector (default off: it reads every pass's output once).
    pub finite_check: FiniteCheck,
    /// Frames [`RealtimeRenderer::submit`] keeps in flight before it waits for the oldest
    /// (1–3, default 2: the CPU records a frame while the GPU runs the last one).
    /// [`RealtimeRenderer::render`] always waits for its frame.
    pub frames_in_flight: u32,
    /// Fraction of the output's width and height the lighting is rendered at (0.25–1,
    /// default 1). Below 1 the camera is jittered and the temporal upscaler
    /// ([`solari_denoise::TemporalUpscaler`]) brings each frame to the output size. Not with
    /// DLSS-RR, which chooses its own render size. Along a moving camera, 0.5 and 0.67 with
    /// path GI read 1.1–3.1× native's best relMSE on the four bundled scenes (an H200 at
    /// 960×540, with [`RealtimeSettings::upscale_guide`], `benches/RESULTS.md`, "An emitter
    /// is a surface of its own"): a moving frame's own samples fall in a fraction of the
    /// output pixels, and the history that fills the rest places some edges up to a render
    /// pixel off.
    pub internal_scale: f32,
    /// Antialiasing at scale 1, jittered only while the camera stands still (default
    /// [`Antialias::Auto`]: on under the fallback denoiser; the figures are on the type).
    pub antialias: Antialias,
    /// The temporal upscaler's knob.
    pub upscale: UpscaleSettings,
    /// Below an internal scale of 1, trace each output pixel's depth on frames whose camera
    /// moved and let it tell the upscaler which of a pixel's nearest samples lie on its own
    /// surface (default on; [`solari_scene::primary_depth::PrimaryDepth`], which traces only
    /// where those samples straddle a silhouette or an emitter's edge; an emitter and what
    /// lies around it are two surfaces). Along the orbit at 960×540 (mean of frames 32 and
    /// 96, path GI, 0.67 / 0.5; without the guide on an H100 at 07ce27b, with it on an H200:
    /// the native points read within 1–4% on the two, `benches/results/h200_2026-11-28b`,
    /// `native_check`): many_lights 0.241 / 0.299 → 0.024 / 0.027, the Cornell box 0.0031 /
    /// 0.0073 → 0.00087 / 0.0010, interior 0.0101 / 0.0133 → 0.0067 / 0.0077; sun_boxes (no
    /// emitter in view) 7–15% lower. Cost at
    /// 1080p: 0.035–0.12 ms for the guide and 0.07 ms in the upscaler, only on frames whose
    /// camera moved, and 8 MiB (`benches/RESULTS.md`, "An output-resolution depth as the
    /// upscaler's guide" and "An emitter is a surface of its own").
    pub upscale_guide: bool,
}

impl RealtimeSettings {
    /// Whether the frame keeps a world cache: every GI mode reads it, and so do specular GI
    /// and the cache view.
    pub fn needs_cache(&self) -> bool {
        self.gi != GiMode::Off || self.specular_gi || self.view == FrameView::WorldCache
    }

    /// The ReSTIR GI settings the GI mode runs with in a scene of `triangles` triangles
    /// (counted per instance): [`RealtimeSettings::gi_settings`] with plain path GI's
    /// shading apart from `path_gi_shade_apart_triangles` triangles up.
    pub fn gi_settings_for(&self, triangles: u64) -> RestirGiSettings {
        let mut s = self.gi_settings();
        if !s.reuse() && triangles >= self.path_gi_shade_apart_triangles {
            s.shade_apart = true;
        }
        s
    }

    /// The ReSTIR GI settings the GI mode runs with (reuse off for [`GiMode::Path`]), before
    /// the scene-size rule: the renderer runs [`RealtimeSettings::gi_settings_for`].
    pub fn gi_settings(&self) -> RestirGiSettings {
        match self.gi {
            GiMode::Path => RestirGiSettings {
                temporal: false,
                spatial: false,
                ..self.restir_gi
            },
            _ => self.restir_gi,
        }
    }

    /// Whether frames must go through the temporal upscaler (jittered) whichever denoiser
    /// runs: an internal scale below 1 or [`Antialias::On`]. [`Antialias::Auto`] decides
    /// once the denoiser is known: [`RealtimeSettings::upscaling_with`].
    pub fn upscaling(&self) -> bool {
        self.internal_scale < 1.0 || self.antialias == Antialias::On
    }

    /// Whether frames go through the temporal upscaler when `denoiser` is the one in use.
    pub fn upscaling_with(&self, denoiser: DenoiserKind) -> bool {
        self.internal_scale < 1.0 || self.antialias.applies(denoiser)
    }

    /// The render size for an `output` size: each side scaled by
    /// [`RealtimeSettings::internal_scale`], rounded up.
    pub fn render_size(&self, output: (u32, u32)) -> (u32, u32) {
        let scale = |side: u32| ((side as f32 * self.internal_scale).ceil() as u32).clamp(1, side);
        (scale(output.0), scale(output.1))
    }

    /// Checks every component's knobs (the message names the bad one).
    pub fn validate(&self) -> Result<(), String> {
        self.di.validate().map_err(|e| e.to_string())?;
        if let Some(grid) = &self.light_grid {
            grid.check()?;
        }
        if self.needs_cache() {
            self.cache.validate().map_err(|e| e.to_string())?;
        }
        if self.gi.traced() {
            // As the mode runs them: path GI's reuse is off whatever `restir_gi` says.
            self.gi_settings().validate().map_err(|e| e.to_string())?;
        }
        if self.specular_gi {
            self.specular.validate().map_err(|e| e.to_string())?;
        }
        if self.denoiser != Some(DenoiserKind::None) {
            self.denoise.validate().map_err(|e| e.to_string())?;
        }
        if self.tiles.sample_count() == 0 {
            return Err("light tiles need at least one tile and one sample".into());
        }
        if !(0.25..=1.0).contains(&self.internal_scale) {
            return Err(format!(
                "internal scale must be 0.25 to 1, not {}",
                self.internal_scale
            ));
        }
        if self.view == FrameView::Indirect && self.denoiser == Some(DenoiserKind::DlssRr) {
            return Err(
                "the indirect view runs under the fallback denoiser or none: DLSS-RR takes \
                 the lit image as it is"
                    .into(),
            );
        }
        if self.upscaling() && self.denoiser == Some(DenoiserKind::DlssRr) {
            return Err(
                "the temporal upscaler (internal scale below 1, or antialias) is for \
                 the fallback path: DLSS-RR upscales by itself"
                    .into(),
            );
        }
        if self.timestamp_interval == 0 {
            return Err("the timestamp interval must be at least 1 (every frame)".into());
        }
        if !(1..=3).contains(&self.frames_in_flight) {
            return Err(format!(
                "frames in flight must be 1 to 3, not {}",
                self.frames_in_flight
            ));
        }
        Ok(())
    }
}

impl RealtimeSettings {
    /// The defaults with direct light alone (no GI, no specular GI): what the DI and
    /// denoiser benches and the tests of direct light measure against a direct-only
    /// reference.
    pub fn direct_only() -> Self {
        Self {
            gi: GiMode::Off,
            specular_gi: false,
            ..Self::default()
        }
    }
}

impl Default for RealtimeSettings {
    fn default() -> Self {
        Self {
            gbuffer: GBufferChoice::Raster,
            tiles: LightTileSettings::default(),
            di: RestirDiSettings {
                reuse_light_threshold: DI_REUSE_LIGHT_THRESHOLD,
                ..Default::default()
            },
            selection: Selection::Power,
            light_grid: None,
            gi: GiMode::default(),
            cache: WorldCacheSettings::default(),
            restir_gi: RestirGiSettings::default(),
            path_gi_shade_apart_triangles: PATH_GI_SHADE_APART_TRIANGLES,
            specular_gi: true,
            specular: SpecularGiSettings::default(),
            psr: true,
            view: FrameView::Lit,
            timestamps: false,
            timestamp_interval: 1,
            denoiser: Some(DenoiserKind::None),
            denoise: FallbackSettings::default(),
            finite_check: FiniteCheck::Off,
            frames_in_flight: 2,
            internal_scale: 1.0,
            upscale_guide: true,
            antialias: Antialias::Auto,
            upscale: UpscaleSettings::default(),
        }
    }
}

/// One pass of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct PassRun {
    /// One of [`PASS_NAMES`].
    pub name: &'static str,
    /// Whether it was recorded this frame.
    pub ran: bool,
    /// GPU time in milliseconds, when timestamps are on and supported.
    pub gpu_ms: Option<f64>,
}

/// Which passes a frame ran, and their GPU times.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameReport {
    /// Frame index.
    pub frame: u32,
    /// Every pass of [`PASS_NAMES`], in order.
    pub passes: Vec<PassRun>,
    /// Non-finite and negative counts per slot of [`FINITE_SLOTS`], in order (empty when the
    /// detector is off).
    pub finite: Vec<FiniteCount>,
    /// The world cache's counters after this frame (`None` without the cache).
    pub cache: Option<CacheStats>,
    /// Milliseconds from the first timed pass's start to the last one's end on the GPU: the
    /// passes' times plus the gaps between them (barriers, idle between dispatches), which
    /// the passes' sum leaves out. `None` when untimed.
    pub gpu_span_ms: Option<f64>,
}

impl FrameReport {
    /// Whether the pass `name` ran.
    pub fn ran(&self, name: &str) -> bool {
        self.passes.iter().any(|p| p.name == name && p.ran)
    }

    /// GPU time of the pass `name`, if it ran and was timed.
    pub fn gpu_ms(&self, name: &str) -> Option<f64> {
        self.passes
            .iter()
            .find(|p| p.name == name)
            .and_then(|p| p.gpu_ms)
    }
}

/// The frame loop's passes and the light list they were built for.
pub struct RealtimeRenderer {
    settings: RealtimeSettings,
    // Triangles the scene traces (per instance), for `RealtimeSettings::gi_settings_for`.
    scene_triangles: u64,
    // The tile settings the light-reading passes were built with: the user's, with point
    // lights compiled out while the scene has none.
    tiles_built: LightTileSettings,
    backend: Backend,
    gbuffer: GBuffer,
    tiles: LightTiles,
    di: RestirDi,
    // The world cache and its pixel passes' target (ReSTIR DI's output), when GI or the
    // cache view is on.
    cache: Option<(WorldCache, wgpu::BindGroup)>,
    // ReSTIR GI (or plain path GI) and its target group (ReSTIR DI's output), with a traced
    // GI mode.
    gi: Option<(RestirGi, wgpu::BindGroup)>,
    // Specular GI, bound to the world cache, ReSTIR DI's output and ReSTIR GI (if any).
    specular: Option<SpecularGi>,
    // Primary surface replacement in use (the G-buffer has overrides), and the G-buffer's
    // transforms generation specular GI was bound with (None: bound without them).
    psr: bool,
    psr_generation: Option<u64>,
    // The scene upload's generation at the last frame (`GpuScene::generation`).
    scene_generation: Option<u64>,
    list: LightList,
    lights: GpuLights,
    grid_report: Option<LightGridReport>,
    lights_group: wgpu::BindGroup,
    profiler: Option<GpuProfiler>,
    denoiser: Option<Box<dyn Denoiser>>,
    denoiser_kind: DenoiserKind,
    denoiser_fallback: Option<String>,
    reset_next: bool,
    // Last frame's view, for the frame context's previous view (kept as a view rather than
    // a cloned camera, whose name would be an allocation every frame).
    last_view: Option<GpuView>,
    // Made on the first `present`.
    presenter: Option<Presenter>,
    // With a G-buffer view: its pass (writing ReSTIR DI's output after the lighting) and
    // the scene's bounds, whose farthest corner sets the depth view's range.
    gbuffer_debug: Option<(GBufferDebug, [[f32; 3]; 2])>,
    frame: u32,
    checker: Option<FiniteChecker>,
    gbuffer_timing: Option<GBufferTiming>,
    in_flight: std::collections::VecDeque<InFlight>,
    // One read-back buffer per frame in flight for the world cache's counters, used in turn.
    cache_readbacks: Vec<wgpu::Buffer>,
    next_cache_readback: usize,
    upscaler: Option<TemporalUpscaler>,
    // Each output pixel's depth for the upscaler on moving frames
    // (`RealtimeSettings::upscale_guide`).
    guide: Option<PrimaryDepth>,
    // One buffer for what lives only within the passes of ReSTIR DI, GI and the fallback
    // denoiser, which run one after another (`solari_scene::scratch`).
    scratch: Option<wgpu::Buffer>,
}

// The light grid for `list` when one is asked for and there are lights; its summary (with
// the cells that had more lights than their capacity) is logged.
fn build_light_grid(
    scene: &Scene,
    list: &LightList,
    settings: Option<&LightGridSettings>,
) -> Result<Option<LightGrid>, GpuError> {
    let Some(settings) = settings else {
        return Ok(None);
    };
    if list.is_empty() {
        return Ok(None);
    }
    let grid = LightGrid::build(list, scene.bounds(), settings).map_err(GpuError::Validation)?;
    // Full cells are the normal case with thousands of lights (each keeps its strongest),
    // so the count goes in the summary rather than a warning.
    log::info!("{}", grid.report.summary());
    Ok(Some(grid))
}

// The detector over a G-buffer target set: emission and f90 finite and non-negative, motion
// finite, depth (one channel) finite and non-negative.
fn check_gbuffer(
    c: &mut FiniteChecker,
    gpu: &Gpu,
    encoder: &mut wgpu::CommandEncoder,
    t: &solari_scene::gbuffer::GBufferTargets,
) -> Result<(), GpuError> {
    c.check_texture(gpu, encoder, SLOT_GBUFFER, &t.emission, 0xf, 0xf)?;
    c.check_texture(gpu, encoder, SLOT_GBUFFER, &t.motion, 0x3, 0)?;
    c.check_texture(gpu, encoder, SLOT_GBUFFER, &t.depth, 0x1, 0x1)
}

// Whether `m` can shade as a mirror metal (what primary surface replacement looks through):
// metallic 1 and roughness below the BRDF's mirror threshold (0.02), after the
// metallic-roughness texture, which only scales the factors down.
fn may_be_mirror_metal(m: &solari_scene::Material) -> bool {
    m.metallic > 0.9999 && (m.roughness < 0.02 || m.metallic_roughness_texture.is_some())
}

// Gives the G-buffer its override buffer for primary surface replacement; false (with a
// warning) where the adapter cannot write the targets as storage textures.
fn enable_overrides(gpu: &Gpu, gbuffer: &mut GBuffer) -> Result<bool, GpuError> {
    match gbuffer.enable_overrides(gpu) {
        Ok(()) => Ok(true),
        Err(GpuError::Unsupported(why)) => {
            log::warn!("primary surface replacement off: {why}");
            Ok(false)
        }
        Err(e) => Err(e),
    }
}

impl RealtimeRenderer {
    /// Builds every pass for `gpu_scene` (uploaded with `backend` from `scene`) at
    /// `width × height`, without DLSS (see [`RealtimeRenderer::with_dlss`]).
    pub fn new(
        gpu: &Gpu,
        backend: Backend,
        scene: &Scene,
        gpu_scene: &GpuScene,
        width: u32,
        height: u32,
        settings: RealtimeSettings,
    ) -> Result<Self, GpuError> {
        Self::with_dlss(
            gpu,
            backend,
            scene,
            gpu_scene,
            width,
            height,
            settings,
            &DlssAvailability::NotBuilt,
        )
    }

    /// As [`RealtimeRenderer::new`], offering DLSS-RR where `dlss` says it can run (see
    /// [`solari_denoise::create_gpu`]). `width × height` is the output size; with an
    /// upscaling denoiser the lighting passes run at its smaller render size.
    #[allow(clippy::too_many_arguments)]
    pub fn with_dlss(
        gpu: &Gpu,
        backend: Backend,
        scene: &Scene,
        gpu_scene: &GpuScene,
        output_width: u32,
        output_height: u32,
        settings: RealtimeSettings,
        dlss: &DlssAvailability,
    ) -> Result<Self, GpuError> {
        settings.validate().map_err(GpuError::Validation)?;
        let settings = RealtimeSettings {
            di: RestirDiSettings {
                light_grid: settings.light_grid.is_some(),
                ..settings.di
            },
            ..settings
        };
        if output_width == 0 || output_height == 0 {
            return Err(GpuError::Validation(format!(
                "output size {output_width}×{output_height} is empty"
            )));
        }
        // With the temporal upscaler the lighting and its denoiser run at the render size,
        // and DLSS-RR (which upscales by itself) is not the best available.
        let upscaling = settings.upscaling();
        let lighting_size = if upscaling {
            settings.render_size((output_width, output_height))
        } else {
            (output_width, output_height)
        };
        let wanted = match settings.denoiser {
            None if upscaling => Some(DenoiserKind::Fallback),
            w => w,
        };
        let denoise = FallbackSettings {
            // The indirect view's lighting holds no emission for the filter to put back.
            emission_in_lighting: settings.view != FrameView::Indirect,
            ..settings.denoise
        };
        let created = solari_denoise::create(gpu, wanted, dlss, lighting_size, denoise)?;
        // `Antialias::Auto` follows the denoiser that runs (at scale 1, so the sizes above
        // hold either way).
        let upscaling = settings.upscaling_with(created.kind);
        let (width, height) = created
            .denoiser
            .as_ref()
            .map_or(lighting_size, |d| d.render_size());
        let scene_triangles = scene.stats().triangles as u64;
        let (producer, gbuffer_timing) =
            crate::gbuffer_choice::choose(gpu, scene, gpu_scene, settings.gbuffer, (width, height));
        let mut gbuffer = GBuffer::with_producer(
            gpu,
            backend,
            producer,
            TraceVariant::for_scene(gpu_scene),
            width,
            height,
        )?;
        // Replacement only matters to what reads the guides (a denoiser or the upscaler),
        // and only where a material can be a mirror metal.
        let psr = settings.psr
            && settings.specular_gi
            && (created.denoiser.is_some() || upscaling)
            && scene.materials.iter().any(may_be_mirror_metal)
            && enable_overrides(gpu, &mut gbuffer)?;
        let list = LightList::build(scene);
        for line in list.report.lines() {
            log::warn!("lights: {line}");
        }
        if let Some(line) = list.report.off_line() {
            log::debug!("lights: {line}");
        }
        let tiles_built = LightTileSettings {
            point_lights: settings.tiles.point_lights && list.has_point_lights(),
            emissive_textures: settings.tiles.emissive_textures && list.has_emissive_textures(),
            environment: settings.tiles.environment && list.environment.is_some(),
            ..settings.tiles
        };
        let tiles = LightTiles::new(gpu, tiles_built)?;
        let di = RestirDi::new(
            gpu,
            backend,
            TraceVariant::for_scene(gpu_scene),
            width,
            height,
            di_settings_for(settings.di, created.kind),
            tiles_built,
        )?;
        let upscaler = if upscaling {
            Some(TemporalUpscaler::new(
                gpu,
                (width, height),
                (output_width, output_height),
                settings.upscale,
            )?)
        } else {
            None
        };
        let grid = build_light_grid(scene, &list, settings.light_grid.as_ref())?;
        let lights = GpuLights::with_grid(gpu, &list, settings.selection, grid.as_ref())?;
        let lights_group = tiles.reader_group(gpu, &lights);
        let cache = if settings.needs_cache() {
            let cache = WorldCache::new(
                gpu,
                backend,
                TraceVariant::for_scene(gpu_scene),
                settings.cache,
                tiles_built,
            )?;
            let target = cache.target_group(gpu, di.output());
            Some((cache, target))
        } else {
            None
        };
        let gi = match &cache {
            Some((cache, _)) if settings.gi.traced() => {
                let variant = TraceVariant::for_scene(gpu_scene);
                let gi = RestirGi::new(
                    gpu,
                    backend,
                    variant,
                    width,
                    height,
                    settings.gi_settings_for(scene_triangles),
                    cache,
                    tiles_built,
                )?;
                let target = gi.target_group(gpu, di.output(), &tiles, &lights)?;
                Some((gi, target))
            }
            _ => None,
        };
        let specular = match &cache {
            Some((cache, _)) if settings.specular_gi => {
                let variant = TraceVariant::for_scene(gpu_scene);
                let mut specular = SpecularGi::new(
                    gpu,
                    backend,
                    variant,
                    width,
                    height,
                    settings.specular,
                    tiles_built,
                )?;
                // Replacement is bound on the first frame, once the G-buffer has transforms.
                specular.bind(gpu, cache, di.output(), gi.as_ref().map(|(g, _)| g), None)?;
                Some(specular)
            }
            _ => None,
        };
        let gbuffer_debug = match settings.view {
            FrameView::GBuffer(_) => {
                let (lo, hi) = scene.bounds();
                let pass = GBufferDebug::new(gpu, di.output(), (width, height))?;
                Some((pass, [lo.to_array(), hi.to_array()]))
            }
            _ => None,
        };
        let checker = match settings.finite_check {
            FiniteCheck::Off => None,
            _ => Some(FiniteChecker::with_frames_in_flight(
                gpu,
                &FINITE_SLOTS,
                settings.frames_in_flight as usize,
            )?),
        };
        let cache_readbacks = (0..settings.frames_in_flight.max(1))
            .map(|_| {
                gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("solari_renderer/cache_stats_readback"),
                    size: CacheStats::BYTES,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            })
            .collect();
        let profiler = if settings.timestamps {
            Some(
                GpuProfiler::new(&gpu.device, GpuProfilerSettings::default())
                    .map_err(|e| GpuError::Validation(format!("GPU profiler: {e}")))?,
            )
        } else {
            None
        };
        Self {
            settings,
            scene_triangles,
            tiles_built,
            backend,
            gbuffer,
            tiles,
            di,
            cache,
            gi,
            specular,
            psr,
            psr_generation: None,
            scene_generation: None,
            list,
            lights,
            grid_report: grid.map(|g| g.report),
            lights_group,
            profiler,
            denoiser: created.denoiser,
            denoiser_kind: created.kind,
            denoiser_fallback: created.fallback_reason,
            reset_next: false,
            last_view: None,
            presenter: None,
            gbuffer_debug,
            frame: 0,
            checker,
            gbuffer_timing,
            in_flight: Default::default(),
            cache_readbacks,
            next_cache_readback: 0,
            guide: match upscaling && settings.internal_scale < 1.0 && settings.upscale_guide {
                true => Some(PrimaryDepth::new(
                    gpu,
                    backend,
                    TraceVariant::for_scene(gpu_scene),
                    (output_width, output_height),
                )?),
                false => None,
            },
            upscaler,
            scratch: None,
        }
        .with_shared_scratch(gpu)
    }

    // Moves the world cache's new samples, ReSTIR DI's and GI's initial reservoirs, the
    // G-buffer's overrides, the denoiser's transient words and second filter buffer and the
    // temporal upscaler's new accumulation (the frame's last pass) into one scratch buffer,
    // allocated on first use at the largest size asked. Their lifetimes within a frame do
    // not overlap, except GI's, which ends in specular GI, the overrides'
    // writer: that pass reads each pixel's reservoir before it stores the pixel's override
    // (it is bound again here). Called again when the light readers are rebuilt.
    fn share_scratch(&mut self, gpu: &Gpu) -> Result<(), GpuError> {
        let bytes = [
            self.cache.as_ref().map(|(c, _)| c.scratch_bytes()),
            Some(self.di.scratch_bytes()),
            self.gi.as_ref().map(|(g, _)| g.scratch_bytes()),
            self.psr.then(|| self.gbuffer.override_scratch_bytes()),
            self.denoiser.as_ref().map(|d| d.scratch_bytes()),
            self.upscaler.as_ref().map(|u| u.scratch_bytes()),
        ]
        .into_iter()
        .flatten()
        .max()
        .unwrap_or(0);
        if self.scratch.as_ref().is_none_or(|s| s.size() < bytes) {
            self.scratch = Some(solari_scene::scratch::allocate(gpu, bytes)?);
        }
        let scratch = self.scratch.as_ref().expect("allocated above");
        // The cache first: GI and specular GI bind its buffers.
        if let Some((cache, _)) = &mut self.cache {
            cache.use_scratch(gpu, scratch)?;
        }
        self.di.use_scratch(gpu, scratch)?;
        if let (Some((gi, _)), Some((cache, _))) = (&mut self.gi, &self.cache) {
            gi.use_scratch(gpu, scratch, cache)?;
        }
        if self.psr {
            self.gbuffer.use_override_scratch(gpu, scratch)?;
        }
        if let Some(d) = &mut self.denoiser
            && d.scratch_bytes() > 0
        {
            d.use_scratch(gpu, scratch)?;
        }
        if let Some(u) = &mut self.upscaler {
            u.use_scratch(gpu, scratch)?;
        }
        self.bind_specular(gpu)
    }

    fn with_shared_scratch(mut self, gpu: &Gpu) -> Result<Self, GpuError> {
        self.share_scratch(gpu)?;
        Ok(self)
    }

    /// What [`GBufferChoice::Auto`] measured when the renderer was built (`None` for a fixed
    /// choice, or where the measurement could not run and raster was kept).
    pub fn gbuffer_timing(&self) -> Option<GBufferTiming> {
        self.gbuffer_timing
    }

    /// The G-buffer: its producer, targets and history.
    pub fn gbuffer(&self) -> &GBuffer {
        &self.gbuffer
    }

    /// The denoiser in use ([`DenoiserKind::None`]: the raw image).
    pub fn denoiser_kind(&self) -> DenoiserKind {
        self.denoiser_kind
    }

    /// Why the denoiser asked for could not run and another is used, if so.
    pub fn denoiser_fallback_reason(&self) -> Option<&str> {
        self.denoiser_fallback.as_deref()
    }

    /// GPU memory per component, in bytes, in frame order: `gbuffer`, `light_tiles` (the
    /// tiles and the light list), `world_cache` (0 without it), `restir_di`, `restir_gi`
    /// (ReSTIR GI's history reservoirs; path GI's only reservoirs are in `scratch`; 0
    /// without GI), `specular_gi` (0 without),
    /// `denoiser` (with the temporal upscaler's accumulation, when it runs), `scratch` (the
    /// buffer the world cache, DI, GI, the G-buffer's overrides, the denoiser and the
    /// upscaler share for
    /// what lives only within one part of the frame; see [`solari_scene::scratch`]). The scene's own memory is the caller's
    /// ([`GpuScene::memory_bytes`]); the profiler's and the detector's few kilobytes are left
    /// out.
    pub fn memory(&self) -> [(&'static str, u64); 8] {
        [
            ("gbuffer", self.gbuffer.memory_bytes()),
            (
                "light_tiles",
                self.tiles.memory_bytes() + self.lights.memory_bytes(),
            ),
            (
                "world_cache",
                self.cache.as_ref().map_or(0, |(c, _)| c.memory_bytes()),
            ),
            ("restir_di", self.di.memory_bytes()),
            (
                "restir_gi",
                self.gi.as_ref().map_or(0, |(g, _)| g.memory_bytes()),
            ),
            (
                "specular_gi",
                self.specular.as_ref().map_or(0, |s| s.memory_bytes()),
            ),
            (
                "denoiser",
                self.denoiser_memory_bytes()
                    + self.upscaler.as_ref().map_or(0, |u| u.memory_bytes())
                    + self.guide.as_ref().map_or(0, |g| g.memory_bytes()),
            ),
            ("scratch", self.scratch.as_ref().map_or(0, |s| s.size())),
        ]
    }

    /// The scratch buffer the passes share ([`solari_scene::scratch`]; `None` only while
    /// the renderer is being built). No pass may read there what an earlier part of the frame,
    /// or an earlier frame, left: tests fill it with garbage between frames to check that.
    pub fn shared_scratch(&self) -> Option<&wgpu::Buffer> {
        self.scratch.as_ref()
    }

    /// GPU memory the denoiser holds, in bytes.
    pub fn denoiser_memory_bytes(&self) -> u64 {
        self.denoiser.as_ref().map_or(0, |d| d.memory_bytes())
    }

    /// Makes the next frame drop the denoiser's history (camera cut, teleport).
    pub fn reset_history(&mut self) {
        self.reset_next = true;
    }

    /// The noisy lighting of the last frame, before the denoiser, at the render size.
    pub fn read_noisy(&self, gpu: &Gpu) -> Result<Vec<[f32; 4]>, GpuError> {
        let (w, h) = self.di.size();
        let bytes = gpu.read_buffer(self.di.output(), w as u64 * h as u64 * 16)?;
        Ok(bytemuck::cast_slice(&bytes).to_vec())
    }

    /// The traversal ReSTIR DI and the world cache trace with: specialised for the scene
    /// they were built for, rebuilt as two-level when the scene outgrows it.
    pub fn trace_variant(&self) -> TraceVariant {
        self.di.variant()
    }

    // Passes specialised for a single-instance scene would trace instance 0 alone once the
    // scene grows (`GpuScene::set_instances`, or another scene given to `render`): rebuild
    // the traced G-buffer, ReSTIR DI and the world cache for the scene's shape now. Their
    // history goes with them (the scene changed); a shape that still fits (a scene that
    // shrank) keeps them.
    fn fit_tracing_to(&mut self, gpu: &Gpu, gpu_scene: &GpuScene) -> Result<(), GpuError> {
        let di_fits = self.di.variant().check(gpu_scene).is_ok();
        let cache_fits = self
            .cache
            .as_ref()
            .is_none_or(|(c, _)| c.variant().check(gpu_scene).is_ok());
        let gbuffer_fits = self
            .gbuffer
            .trace_variant()
            .is_none_or(|v| v.check(gpu_scene).is_ok());
        let guide_fits = self
            .guide
            .as_ref()
            .is_none_or(|g| g.variant().check(gpu_scene).is_ok());
        if di_fits && cache_fits && gbuffer_fits && guide_fits {
            return Ok(());
        }
        let variant = TraceVariant::for_scene(gpu_scene);
        log::info!(
            "scene shape changed ({} instances): rebuilding the tracing passes as {}",
            gpu_scene.instance_count(),
            variant.name()
        );
        let (w, h) = self.di.size();
        let backend = gpu_scene.backend;
        self.backend = backend;
        if !gbuffer_fits {
            self.gbuffer = GBuffer::traced(gpu, backend, variant, w, h)?;
            if self.psr {
                self.psr = enable_overrides(gpu, &mut self.gbuffer)?;
            }
        }
        if let Some(g) = &mut self.guide
            && !guide_fits
        {
            *g = PrimaryDepth::new(gpu, backend, variant, g.size())?;
        }
        self.rebuild_light_readers(gpu, variant)
    }

    // Rebuilds ReSTIR DI, the world cache, GI and specular GI for `variant` and the tile
    // settings in `tiles_built`; their history goes with them.
    fn rebuild_light_readers(&mut self, gpu: &Gpu, variant: TraceVariant) -> Result<(), GpuError> {
        let (w, h) = self.di.size();
        let (backend, tiles) = (self.backend, self.tiles_built);
        let di = di_settings_for(self.settings.di, self.denoiser_kind);
        self.di = RestirDi::new(gpu, backend, variant, w, h, di, tiles)?;
        if let Some((cache, target)) = &mut self.cache {
            *cache = WorldCache::new(gpu, backend, variant, cache.settings(), tiles)?;
            *target = cache.target_group(gpu, self.di.output());
            if let Some((gi, gi_target)) = &mut self.gi {
                *gi = RestirGi::new(gpu, backend, variant, w, h, gi.settings(), cache, tiles)?;
                *gi_target = gi.target_group(gpu, self.di.output(), &self.tiles, &self.lights)?;
            }
            if let Some(specular) = &mut self.specular {
                let settings = specular.settings();
                *specular = SpecularGi::new(gpu, backend, variant, w, h, settings, tiles)?;
            }
        }
        self.share_scratch(gpu)
    }

    // Binds specular GI (if built) to its inputs, with the G-buffer's overrides and
    // transforms when replacement is on and the G-buffer has uploaded transforms (its first
    // `prepare`); remembers the transforms generation bound (None: bound without them).
    fn bind_specular(&mut self, gpu: &Gpu) -> Result<(), GpuError> {
        self.psr_generation = None;
        let (Some(specular), Some((cache, _))) = (&mut self.specular, &self.cache) else {
            return Ok(());
        };
        let gbuffer = &self.gbuffer;
        let bindings = match (self.psr, gbuffer.overrides(), gbuffer.previous_transforms()) {
            (true, Some(overrides), Some(previous_transforms)) => Some(PsrBindings {
                overrides,
                previous_transforms,
            }),
            _ => None,
        };
        let gi = self.gi.as_ref().map(|(g, _)| g);
        specular.bind(gpu, cache, self.di.output(), gi, bindings)?;
        self.psr_generation = bindings.map(|_| gbuffer.transforms_generation());
        Ok(())
    }

    // Whether this frame's output goes through the denoiser (debug views do not).
    fn denoising(&self) -> bool {
        self.denoiser.is_some()
            && matches!(self.settings.view, FrameView::Lit | FrameView::Indirect)
    }

    /// Rebuilds the light list from `scene` (after lights were added, removed or changed);
    /// temporal reuse follows surviving lights to their new indices and drops removed ones.
    /// Passes built while the scene had no point or spot lights (or no textured emitter, or
    /// no environment map) have that code compiled out; the first ones added rebuild those
    /// passes (their history goes with them). The scene's upload (`GpuScene`) must hold the
    /// same environment: it carries the map the passes read. When more than
    /// [`crate::light_change::LIGHT_CHANGE_SHARE`] of the lights' power changed (a light
    /// switched, added, removed or rescaled; not moved) the world cache and ReSTIR GI shorten
    /// their histories for `WorldCacheSettings::light_change_frames` frames
    /// (`WorldCache::follow_light_change`, `RestirGi::follow_light_change`).
    pub fn set_lights(&mut self, gpu: &Gpu, scene: &Scene) -> Result<(), GpuError> {
        let list = LightList::build(scene);
        for line in list.report.lines() {
            log::warn!("lights: {line}");
        }
        if let Some(line) = list.report.off_line() {
            log::debug!("lights: {line}");
        }
        let translation = list.translation_from(&self.list);
        let wanted = self.settings.tiles;
        let points =
            list.has_point_lights() && wanted.point_lights && !self.tiles_built.point_lights;
        let textures = list.has_emissive_textures()
            && wanted.emissive_textures
            && !self.tiles_built.emissive_textures;
        let environment =
            list.environment.is_some() && wanted.environment && !self.tiles_built.environment;
        if points || textures || environment {
            log::info!(
                "point lights, textured emitters or an environment map added: rebuilding the \
                 passes that read lights"
            );
            self.tiles_built.point_lights |= points;
            self.tiles_built.emissive_textures |= textures;
            self.tiles_built.environment |= environment;
            self.tiles = LightTiles::new(gpu, self.tiles_built)?;
            self.rebuild_light_readers(gpu, self.di.variant())?;
        }
        let grid = build_light_grid(scene, &list, self.settings.light_grid.as_ref())?;
        self.lights = GpuLights::with_grid(gpu, &list, self.settings.selection, grid.as_ref())?;
        self.grid_report = grid.map(|g| g.report);
        self.lights_group = self.tiles.reader_group(gpu, &self.lights);
        if let Some((gi, gi_target)) = &mut self.gi {
            // Glossy hits read the lights through GI's target group.
            *gi_target = gi.target_group(gpu, self.di.output(), &self.tiles, &self.lights)?;
            // Whatever the change, ReSTIR GI's adaptive cap follows it until the view settles.
            gi.unsettle();
        }
        let change = power_change_share(&self.list, &list);
        if change > LIGHT_CHANGE_SHARE {
            // The cache's samples and ReSTIR GI's reused ones hold the old light: both
            // shorten their histories for a few frames.
            if let Some((cache, _)) = &mut self.cache {
                let frames = cache.settings().light_change_frames;
                log::debug!(
                    "{:.0}% of the lights' power changed: the world cache and GI shorten their \
                     histories for {frames} frames",
                    100.0 * change
                );
                cache.follow_light_change();
                if let Some((gi, _)) = &mut self.gi {
                    gi.follow_light_change(frames);
                }
            }
        }
        self.di.set_light_translation(translation);
        self.list = list;
        Ok(())
    }

    /// What the light grid's last build produced; `None` without a grid
    /// ([`RealtimeSettings::light_grid`]) or lights.
    pub fn light_grid_report(&self) -> Option<&LightGridReport> {
        self.grid_report.as_ref()
    }

    /// The light list in use.
    pub fn lights(&self) -> &LightList {
        &self.list
    }

    /// Changes ReSTIR DI's settings (history is kept).
    pub fn set_di_settings(&mut self, settings: RestirDiSettings) -> Result<(), GpuError> {
        self.di
            .set_settings(di_settings_for(settings, self.denoiser_kind))?;
        self.settings.di = settings;
        Ok(())
    }

    /// Whether this frame's ReSTIR DI skipped its reuse by
    /// [`RestirDiSettings::reuse_light_threshold`] (a scene of few lights under the fallback
    /// denoiser: [`DI_REUSE_LIGHT_THRESHOLD`]).
    pub fn di_reuse_skipped(&self) -> bool {
        self.di.reuse_skipped()
    }

    /// Whether the world cache still has frames of extra update rounds ahead
    /// ([`solari_worldcache::WorldCacheSettings::warm_up_rounds`]): those frames cost more
    /// than the ones after them. False without a cache.
    pub fn cache_warming_up(&self) -> bool {
        self.cache.as_ref().is_some_and(|(c, _)| c.warming_up())
    }

    /// The settings the renderer runs with (after the `set_*_settings` calls).
    pub fn settings(&self) -> &RealtimeSettings {
        &self.settings
    }

    /// Specular GI's settings, when it runs.
    pub fn specular_settings(&self) -> Option<SpecularGiSettings> {
        self.specular.as_ref().map(|s| s.settings())
    }

    /// Changes specular GI's settings (it keeps no history). Errors if specular GI was not
    /// built ([`RealtimeSettings::specular_gi`] off) or a knob is out of range.
    pub fn set_specular_settings(&mut self, settings: SpecularGiSettings) -> Result<(), GpuError> {
        let Some(specular) = &mut self.specular else {
            return Err(GpuError::Validation(
                "specular GI is off in this renderer (RealtimeSettings::specular_gi)".into(),
            ));
        };
        specular.set_settings(settings)?;
        self.settings.specular = settings;
        Ok(())
    }

    /// The settings ReSTIR GI runs with, when a traced GI mode is on.
    pub fn gi_settings(&self) -> Option<RestirGiSettings> {
        self.gi.as_ref().map(|(gi, _)| gi.settings())
    }

    /// Whether plain path GI shades in a second dispatch as its pipelines are built
    /// ([`solari_restir::RestirGi::shades_apart`]: never with reuse or with more than one
    /// candidate, whatever [`RestirGiSettings::shade_apart`] says); false without traced GI.
    pub fn gi_shades_apart(&self) -> bool {
        self.gi.as_ref().is_some_and(|(gi, _)| gi.shades_apart())
    }

    /// Changes ReSTIR GI's settings (history is kept). With [`GiMode::Path`] reuse stays
    /// off whatever `settings` say; without a traced GI mode only the stored settings change.
    pub fn set_gi_settings(&mut self, settings: RestirGiSettings) -> Result<(), GpuError> {
        settings.validate()?;
        self.settings.restir_gi = settings;
        if let Some((gi, _)) = &mut self.gi {
            gi.set_settings(self.settings.gi_settings_for(self.scene_triangles))?;
        }
        Ok(())
    }

    /// The world cache, when the settings use it.
    pub fn world_cache(&self) -> Option<&WorldCache> {
        self.cache.as_ref().map(|(c, _)| c)
    }

    /// The world cache's counters for the last frame (`None` without a cache). Blocks until
    /// the GPU is done.
    pub fn cache_stats(&self, gpu: &Gpu) -> Result<Option<CacheStats>, GpuError> {
        self.world_cache().map(|c| c.read_stats(gpu)).transpose()
    }

    /// Renders one frame of `scene` (as uploaded in `gpu_scene`) from `camera`, waits for the
    /// GPU to finish it and returns its report. A frame loop that should not wait uses
    /// [`RealtimeRenderer::submit`] instead.
    pub fn render(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        gpu_scene: &GpuScene,
        camera: &Camera,
    ) -> Result<FrameReport, GpuError> {
        if !self.in_flight.is_empty() {
            return Err(GpuError::Validation(format!(
                "render() with {} frame(s) in flight from submit(): call finish() first",
                self.in_flight.len()
            )));
        }
        let recorded = self.record(gpu, scene, gpu_scene, camera)?;
        self.complete(gpu, recorded)
    }

    /// Records and submits the next frame without waiting for it, so the CPU prepares frame
    /// N + 1 while the GPU runs frame N. Once [`RealtimeSettings::frames_in_flight`] frames
    /// are in flight it waits for the oldest and returns its report (its GPU times and
    /// non-finite counts arrive that many frames late); before that it returns `None`.
    /// [`RealtimeRenderer::finish`] collects the rest. With the non-finite detector set to
    /// [`FiniteCheck::Fail`], the error names the frame that had the bad values, found late.
    pub fn submit(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        gpu_scene: &GpuScene,
        camera: &Camera,
    ) -> Result<Option<FrameReport>, GpuError> {
        let recorded = self.record(gpu, scene, gpu_scene, camera)?;
        self.in_flight.push_back(recorded);
        if self.in_flight.len() >= self.settings.frames_in_flight as usize {
            let oldest = self.in_flight.pop_front().expect("one was just pushed");
            return self.complete(gpu, oldest).map(Some);
        }
        Ok(None)
    }

    /// Waits for every frame still in flight from [`RealtimeRenderer::submit`] and returns
    /// their reports, oldest first.
    pub fn finish(&mut self, gpu: &Gpu) -> Result<Vec<FrameReport>, GpuError> {
        let mut reports = Vec::with_capacity(self.in_flight.len());
        while let Some(oldest) = self.in_flight.pop_front() {
            reports.push(self.complete(gpu, oldest)?);
        }
        Ok(reports)
    }

    /// Frames submitted and not yet reported.
    pub fn frames_in_flight(&self) -> usize {
        self.in_flight.len()
    }

    // Records one frame's passes and submits them.
    fn record(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        gpu_scene: &GpuScene,
        camera: &Camera,
    ) -> Result<InFlight, GpuError> {
        self.fit_tracing_to(gpu, gpu_scene)?;
        // The scene's upload tells the passes that trace paths to leave a sampled sky to
        // light sampling; the light list must then hold it, or its light is lost (or, the
        // other way round, counted twice).
        let sampled = self.list.environment.is_some() && self.tiles_built.environment;
        if gpu_scene.environment_sampled() != sampled {
            return Err(GpuError::Validation(format!(
                "the scene upload {} the environment as a light but the renderer's light list \
                 {}: after GpuScene::set_environment call set_lights with the same scene (and \
                 keep LightTileSettings::environment on for scenes with an environment map)",
                if gpu_scene.environment_sampled() {
                    "treats"
                } else {
                    "does not treat"
                },
                if sampled { "samples it" } else { "does not" }
            )));
        }
        let frame = self.frame;
        self.frame = self.frame.wrapping_add(1);
        // Instances that moved change the indirect light under a still camera: ReSTIR GI's
        // adaptive cap follows until the view settles again.
        if self.scene_generation.replace(gpu_scene.generation()) != Some(gpu_scene.generation())
            && let Some((gi, _)) = &mut self.gi
        {
            gi.unsettle();
        }
        // Untimed frames open no profiler scope and leave the profiler's frames alone.
        let timed =
            self.profiler.is_some() && frame.is_multiple_of(self.settings.timestamp_interval);
        let light_count = self.lights.light_count;
        let (w, h) = self.di.size();
        let view = GpuView::new(camera, w, h);
        // Antialiasing (the upscaler at full scale) jitters only while the camera stands
        // still: a jittered sample is a worse estimate of its pixel's area than the centre's
        // until frames accumulate, and under camera motion the history cannot hold them
        // (the docs of `Antialias`). A moving frame is unjittered and drops the upscaler's
        // history, so it passes the frame through unchanged; so is the first, which has no
        // history to accumulate into.
        let moved = self.last_view.is_none_or(|p| !p.same_camera(&view));
        let antialias_only = self.settings.internal_scale >= 1.0;
        let unjittered = antialias_only && moved;
        // Jittered samples only where the temporal upscaler accumulates them.
        let jitter = if self.upscaler.is_some() && !unjittered {
            halton_jitter(frame)
        } else {
            [0.0; 2]
        };
        self.gbuffer.prepare_jittered(gpu, scene, camera, jitter)?;
        // The G-buffer's transforms are bound by replacement: rebind when they were replaced.
        if self.psr && self.psr_generation != Some(self.gbuffer.transforms_generation()) {
            self.bind_specular(gpu)?;
        }
        let mut context = FrameContext::new(frame, self.di.size(), camera, None)
            .with_profiler(self.profiler.as_ref().filter(|_| timed));
        if let Some(previous) = self.last_view.replace(context.view) {
            context.previous_view = GpuView { frame, ..previous };
        }
        self.tiles.prepare(gpu, &context);
        let indirect_only = self.settings.view == FrameView::Indirect;
        self.di.set_indirect_only(indirect_only);
        self.di
            .prepare(gpu, &context, &self.gbuffer, &self.lights)?;
        if let Some((cache, _)) = &mut self.cache {
            cache.prepare(gpu, &context, light_count);
        }
        if let Some((gi, _)) = &mut self.gi {
            gi.set_indirect_only(indirect_only);
            gi.prepare(gpu, &context, &self.gbuffer)?;
        }
        if let Some(specular) = &mut self.specular {
            specular.set_indirect_only(indirect_only);
            specular.prepare(gpu, &context);
        }
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let mut ran = Marks([false; PASS_NAMES.len()]);
        let denoising = self.denoising();
        let checker = &mut self.checker;
        if let Some(c) = checker.as_ref() {
            c.begin_frame(&mut encoder);
        }
        ran.add(&self.gbuffer.encode(&mut encoder, &context, gpu_scene)?);
        if let Some(c) = checker.as_mut() {
            check_gbuffer(c, gpu, &mut encoder, self.gbuffer.current())?;
        }
        if light_count > 0 {
            ran.add(&self.tiles.encode(&mut encoder, &context, &self.lights));
            if let Some(c) = checker.as_mut() {
                let samples = self.tiles.settings().sample_count();
                c.check_buffer(
                    gpu,
                    &mut encoder,
                    SLOT_TILES,
                    self.tiles.samples_buffer(),
                    samples,
                    solari_lights::SAMPLE_CHECK,
                )?;
            }
        }
        if let Some((cache, _)) = &self.cache {
            ran.add(&cache.encode(&mut encoder, &context, gpu_scene, &self.lights_group)?);
            if let Some(c) = checker.as_mut() {
                let slots = cache.settings().capacity as u64;
                let cells = cache.cells_buffer();
                c.check_buffer(
                    gpu,
                    &mut encoder,
                    SLOT_CACHE,
                    cells,
                    slots,
                    solari_worldcache::CELL_CHECK,
                )?;
            }
        }
        let di_ran = self.di.encode(
            &mut encoder,
            &context,
            gpu_scene,
            &self.gbuffer,
            &self.lights_group,
            light_count,
        )?;
        ran.add(&di_ran);
        let (w, h) = self.di.size();
        let pixels = w as u64 * h as u64;
        if let Some(c) = checker.as_mut() {
            // The final reservoirs this frame wrote: only a frame with reuse (its second
            // pass) keeps them; the light of every frame is checked below.
            if let (true, Some(reservoirs)) = (di_ran.contains(DI_LABELS[1]), self.di.reservoirs())
            {
                let cap = self.settings.di.confidence_cap;
                let layout = solari_restir::reservoir_check(cap);
                c.check_buffer(gpu, &mut encoder, SLOT_DI, reservoirs, pixels, layout)?;
            }
            let rgba = RecordLayout::RGBA_NON_NEGATIVE;
            c.check_buffer(gpu, &mut encoder, SLOT_DI, self.di.output(), pixels, rgba)?;
        }
        if let Some((cache, target)) = &self.cache {
            if self.settings.view == FrameView::WorldCache {
                ran.add(&cache.encode_view(&mut encoder, &context, &self.gbuffer, target)?);
            } else if self.settings.gi == GiMode::WorldCache {
                ran.add(&cache.encode_gi(&mut encoder, &context, &self.gbuffer, target)?);
            } else if let Some((gi, gi_target)) = &mut self.gi {
                ran.add(&gi.encode(&mut encoder, &context, gpu_scene, &self.gbuffer, gi_target)?);
                if let Some(c) = checker.as_mut() {
                    let cap = gi.settings().confidence_cap;
                    let layout = solari_restir::gi_reservoir_check(cap);
                    c.check_buffer(gpu, &mut encoder, SLOT_GI, gi.reservoirs(), pixels, layout)?;
                }
            }
            if let Some(specular) = &self.specular
                && self.settings.view != FrameView::WorldCache
            {
                let lights = &self.lights_group;
                ran.add(&specular.encode(
                    &mut encoder,
                    &context,
                    gpu_scene,
                    &self.gbuffer,
                    lights,
                )?);
                if specular.replaces_surfaces() {
                    ran.add(&self.gbuffer.apply_overrides(&mut encoder, &context)?);
                    if let Some(c) = checker.as_mut() {
                        check_gbuffer(c, gpu, &mut encoder, self.gbuffer.current())?;
                    }
                }
            }
            if let Some(c) = checker.as_mut() {
                let rgba = RecordLayout::RGBA_NON_NEGATIVE;
                c.check_buffer(
                    gpu,
                    &mut encoder,
                    SLOT_CACHE_GI,
                    self.di.output(),
                    pixels,
                    rgba,
                )?;
            }
        }
        if let (Some((debug, bounds)), FrameView::GBuffer(channel)) =
            (&mut self.gbuffer_debug, self.settings.view)
        {
            debug.prepare(gpu, channel, farthest_corner(context.eye(), bounds));
            // Not in PASS_NAMES: a debug view's cost is not the frame's.
            debug.encode(&mut encoder, &context, &self.gbuffer)?;
        }
        let mut after = Vec::new();
        let reset = std::mem::take(&mut self.reset_next);
        let upscaler_reset = reset || unjittered;
        if denoising {
            let denoiser = self.denoiser.as_mut().expect("denoising() checked it");
            // DI's shadow rays tell the denoiser hard shadows from noise, if it reads them.
            let shadow = denoiser
                .requirements()
                .inputs
                .contains(solari_denoise::Inputs::SHADOW)
                .then(|| self.di.shadow());
            let inputs = DenoiserInputs {
                lighting: Lighting::Combined(self.di.output()),
                gbuffer: &self.gbuffer,
                hit_distance: None,
                shadow,
                reset,
            };
            let encoded = denoiser.encode(gpu, &mut encoder, &context, &inputs)?;
            ran.add(&encoded.ran);
            after = encoded.after;
        }
        if let Some(upscaler) = &mut self.upscaler {
            // DLSS-RR never runs with the upscaler (refused at construction), so the
            // denoiser's output is in `encoder`.
            let input = match &self.denoiser {
                Some(d) if denoising => d.output(),
                _ => self.di.output(),
            };
            // The guide only serves the moving pipeline: a still or reset frame skips it.
            let guide = match &self.guide {
                Some(g)
                    if self.gbuffer.camera_moved()
                        && self.gbuffer.history_valid()
                        && !upscaler_reset =>
                {
                    g.prepare(gpu, camera);
                    let at_output = FrameContext::new(frame, g.size(), camera, None)
                        .with_profiler(self.profiler.as_ref().filter(|_| timed));
                    ran.add(&g.encode(&mut encoder, &at_output, gpu_scene, &self.gbuffer)?);
                    Some(g.depth())
                }
                _ => None,
            };
            ran.add(&upscaler.encode(
                gpu,
                &mut encoder,
                &context,
                &self.gbuffer,
                input,
                guide,
                upscaler_reset,
            )?);
        }
        if let Some(p) = self.profiler.as_mut().filter(|_| timed) {
            p.resolve_queries(&mut encoder);
        }
        // The denoiser's output is checked after the command buffers it returned (DLSS-RR
        // writes outside `encoder`).
        let mut last = gpu.device.create_command_encoder(&Default::default());
        let mut readback = None;
        if let Some(c) = checker.as_mut() {
            if denoising {
                let d = self.denoiser.as_ref().expect("denoising() checked it");
                let (ow, oh) = d.output_size();
                let rgba = RecordLayout::RGBA_NON_NEGATIVE;
                let outputs = ow as u64 * oh as u64;
                c.check_buffer(gpu, &mut last, SLOT_DENOISE, d.output(), outputs, rgba)?;
            }
            if let Some(u) = &self.upscaler {
                // The upscaler's output counts with the denoiser's: the frame's last image.
                let (ow, oh) = u.output_size();
                let layout = solari_denoise::upscale::OUTPUT_LAYOUT;
                let outputs = ow as u64 * oh as u64;
                c.check_buffer(gpu, &mut last, SLOT_DENOISE, u.output(), outputs, layout)?;
            }
            readback = Some(c.end_frame(&mut last));
        }
        let mut cache_readback = None;
        if let Some((cache, _)) = &self.cache {
            let slot = self.next_cache_readback;
            self.next_cache_readback = (slot + 1) % self.cache_readbacks.len();
            cache.copy_stats(&mut last, &self.cache_readbacks[slot]);
            cache_readback = Some(slot);
        }
        let submitted = gpu.scoped(|| {
            gpu.queue.submit(
                std::iter::once(encoder.finish())
                    .chain(after)
                    .chain(std::iter::once(last.finish())),
            )
        });
        // The profiler's frame ends whatever happened, so the next frame's queries stay its
        // own (reports pair with profiler frames in order).
        if let Some(p) = self.profiler.as_mut().filter(|_| timed) {
            p.end_frame()
                .map_err(|e| GpuError::Validation(format!("GPU profiler: {e}")))?;
        }
        let submission = submitted?;
        gpu.check_errors()?;
        Ok(InFlight {
            frame,
            timed,
            ran,
            submission,
            readback,
            cache_readback,
        })
    }

    // Waits for a recorded frame and turns its GPU results into its report.
    fn complete(&mut self, gpu: &Gpu, f: InFlight) -> Result<FrameReport, GpuError> {
        gpu.wait_for(f.submission.clone())?;
        let mut times = [None; PASS_NAMES.len()];
        let mut span: Option<(f64, f64)> = None;
        if let Some(p) = self.profiler.as_mut().filter(|_| f.timed) {
            // Frames reach the profiler in order, so its oldest pending frame is this one.
            let results = p.process_finished_frame(gpu.queue.get_timestamp_period());
            if results.is_none() {
                // Its queries were not mapped although the frame is done: this report goes
                // untimed, and the next one would read this frame's times, so say so.
                log::warn!(
                    "frame {}: GPU times not ready; reports may be a frame off",
                    f.frame
                );
            }
            if let Some(results) = results {
                for r in results {
                    if let Some(t) = &r.time {
                        span = Some(
                            span.map_or((t.start, t.end), |(a, b)| (a.min(t.start), b.max(t.end))),
                        );
                    }
                    let ms = r.time.map(|t| (t.end - t.start) * 1e3);
                    // A pass recorded more than once in a frame (the world cache's update
                    // rounds while it is cold) reports the sum of its scopes.
                    if let Some(i) = PASS_NAMES.iter().position(|n| *n == r.label) {
                        times[i] = match (times[i], ms) {
                            (Some(a), Some(b)) => Some(a + b),
                            (a, b) => b.or(a),
                        };
                    }
                }
            }
        }
        let finite = match (self.checker.as_ref(), f.readback) {
            (Some(c), Some(slot)) => c.read_frame(gpu, slot, Some(f.submission.clone()))?,
            _ => Vec::new(),
        };
        let cache = match f.cache_readback {
            Some(slot) => Some(CacheStats::from_bytes(
                &gpu.map_read_after(&self.cache_readbacks[slot], Some(f.submission))?,
            )),
            None => None,
        };
        if self.settings.finite_check == FiniteCheck::Fail
            && let Some(bad) = first_offender(&finite)
        {
            return Err(GpuError::NonFinite {
                frame: f.frame,
                pass: bad.name.clone(),
                non_finite: bad.non_finite,
                negative: bad.negative,
            });
        }
        Ok(FrameReport {
            frame: f.frame,
            finite,
            cache,
            gpu_span_ms: span.map(|(a, b)| (b - a) * 1e3),
            passes: PASS_NAMES
                .iter()
                .zip(f.ran.0)
                .zip(times)
                .map(|((name, ran), gpu_ms)| PassRun {
                    name,
                    ran,
                    gpu_ms: if ran { gpu_ms } else { None },
                })
                .collect(),
        })
    }

    /// The last frame's linear radiance (denoised, when a denoiser is on), row by row from
    /// the top left (w: 1 on surfaces, 0 on background; 1 everywhere after DLSS-RR or the
    /// temporal upscaler, whose outputs have no surface mask), at [`RealtimeRenderer::size`].
    pub fn read_output(&self, gpu: &Gpu) -> Result<Vec<[f32; 4]>, GpuError> {
        if let Some(u) = &self.upscaler {
            let (w, h) = u.output_size();
            let bytes = gpu.read_buffer(u.output(), w as u64 * h as u64 * 16)?;
            // Its w is the accumulated weight, not a mask.
            let mut image: Vec<[f32; 4]> = bytemuck::cast_slice(&bytes).to_vec();
            image.iter_mut().for_each(|p| p[3] = 1.0);
            return Ok(image);
        }
        match &self.denoiser {
            Some(d) if self.denoising() => {
                let (w, h) = d.output_size();
                let bytes = gpu.read_buffer(d.output(), w as u64 * h as u64 * 16)?;
                Ok(bytemuck::cast_slice(&bytes).to_vec())
            }
            _ => self.read_noisy(gpu),
        }
    }

    /// Draws the last frame into `target`, a texture of the caller's (a window's surface
    /// texture or any render target of [`RealtimeRenderer::size`] with `RENDER_ATTACHMENT`
    /// usage), scaled by 2^`exposure_ev`: linear for float formats, tone-mapped for 8- and
    /// 10-bit ones ([`crate::present`] states the curve); a G-buffer view is drawn as it is,
    /// without exposure or tone curve. Submits its own small command buffer after the
    /// frame's. Errors on a target of another size, usage or format.
    pub fn present(
        &mut self,
        gpu: &Gpu,
        target: &wgpu::TextureView,
        exposure_ev: f32,
    ) -> Result<(), GpuError> {
        if self.presenter.is_none() {
            self.presenter = Some(Presenter::new(gpu)?);
        }
        let size = self.size();
        let source = match (&self.upscaler, &self.denoiser) {
            (Some(u), _) => u.output(),
            (None, Some(d)) if self.denoising() => d.output(),
            _ => self.di.output(),
        };
        let presenter = self.presenter.as_mut().expect("made above");
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let exposure = self.settings.view.tone_mapped().then_some(exposure_ev);
        presenter.encode(gpu, &mut encoder, source, size, target, exposure)?;
        gpu.scoped(|| gpu.queue.submit([encoder.finish()]))?;
        Ok(())
    }

    /// Whether frames go through the temporal upscaler: an internal scale below 1, or
    /// antialiasing ([`RealtimeSettings::antialias`]) with the denoiser in use.
    pub fn upscaling(&self) -> bool {
        self.upscaler.is_some()
    }

    /// Output image size in pixels.
    pub fn size(&self) -> (u32, u32) {
        if let Some(u) = &self.upscaler {
            return u.output_size();
        }
        match &self.denoiser {
            Some(d) if self.denoising() => d.output_size(),
            _ => self.di.size(),
        }
    }
}

/// A scripted camera path for `--camera-path`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraPath {
    /// The camera stays put.
    Fixed,
    /// The camera swings ±20° around the vertical axis through the scene's centre, one
    /// period every 240 frames, looking at the same point (sideways motion, as when a player
    /// strafes; it never leaves a closed room like the Cornell box).
    Orbit,
}

impl CameraPath {
    /// Parses `fixed` or `orbit`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "fixed" => Some(Self::Fixed),
            "orbit" => Some(Self::Orbit),
            _ => None,
        }
    }

    /// The camera at `frame` along the path starting from `start`. The orbit path walks every
    /// vertex of `scene` for its pivot on each call; frame loops use [`CameraPath::rig`].
    pub fn camera(self, start: &Camera, scene: &Scene, frame: u32) -> Camera {
        self.rig(start, scene).at(frame)
    }

    /// The path from `start` with everything that depends on the scene computed once (the
    /// orbit's pivot), so each frame's camera costs a matrix product, not a pass over the
    /// scene (on the 1M-triangle metal_rough_spheres that pass took longer than the GPU's
    /// frame).
    pub fn rig(self, start: &Camera, scene: &Scene) -> CameraRig {
        let pivot = match self {
            Self::Fixed => glam::Vec3::ZERO,
            Self::Orbit => Camera::orbit_pivot(scene),
        };
        CameraRig {
            path: self,
            start: start.clone(),
            pivot,
        }
    }
}

/// A [`CameraPath`] bound to its start camera and scene (see [`CameraPath::rig`]).
#[derive(Clone, Debug)]
pub struct CameraRig {
    path: CameraPath,
    start: Camera,
    pivot: glam::Vec3,
}

impl CameraRig {
    /// The camera at `frame`.
    pub fn at(&self, frame: u32) -> Camera {
        match self.path {
            CameraPath::Fixed => self.start.clone(),
            CameraPath::Orbit => self.start.orbit_about(self.pivot, frame),
        }
    }
}

// The distance from `eye` to the farthest corner of the box `bounds` (min, max): the depth
// view's darkest distance. Non-finite for an empty scene, which the pass replaces with 1.
fn farthest_corner(eye: [f32; 3], bounds: &[[f32; 3]; 2]) -> f32 {
    (0..3)
        .map(|a| {
            let d = (eye[a] - bounds[0][a])
                .abs()
                .max((eye[a] - bounds[1][a]).abs());
            d * d
        })
        .sum::<f32>()
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Path GI shades apart from the threshold's triangle count up (and wherever the user's
    /// own setting says so); ReSTIR GI never (its second dispatch is the temporal merge).
    #[test]
    fn path_gi_shades_apart_in_large_scenes() {
        let path = RealtimeSettings {
            gi: GiMode::Path,
            ..Default::default()
        };
        let t = PATH_GI_SHADE_APART_TRIANGLES;
        assert!(!path.gi_settings_for(32).shade_apart);
        assert!(!path.gi_settings_for(t - 1).shade_apart);
        assert!(path.gi_settings_for(t).shade_apart);
        assert!(path.gi_settings_for(294_000).shade_apart);
        let restir = RealtimeSettings {
            gi: GiMode::Restir,
            ..path
        };
        assert!(!restir.gi_settings_for(294_000).shade_apart);
        let always = RealtimeSettings {
            path_gi_shade_apart_triangles: 0,
            ..path
        };
        assert!(always.gi_settings_for(0).shade_apart);
        let never = RealtimeSettings {
            path_gi_shade_apart_triangles: u64::MAX,
            ..path
        };
        assert!(!never.gi_settings_for(u64::MAX - 1).shade_apart);
        let own = RealtimeSettings {
            restir_gi: RestirGiSettings {
                shade_apart: true,
                ..Default::default()
            },
            ..never
        };
        assert!(own.gi_settings_for(32).shade_apart);
        // The other settings are the mode's, untouched.
        let base = path.gi_settings();
        assert_eq!(
            RestirGiSettings {
                shade_apart: false,
                ..path.gi_settings_for(t)
            },
            base
        );
    }

    #[test]
    fn slot_constants_name_their_slots() {
        let named = [
            (SLOT_GBUFFER, "gbuffer"),
            (SLOT_TILES, "light_tiles"),
            (SLOT_CACHE, "world_cache"),
            (SLOT_DI, "restir_di"),
            (SLOT_GI, "restir_gi"),
            (SLOT_CACHE_GI, "cache_gi"),
            (SLOT_DENOISE, "denoise"),
        ];
        for (slot, name) in named {
            assert_eq!(FINITE_SLOTS[slot], name);
        }
    }

    #[test]
    fn a_rig_gives_the_cameras_of_its_path() {
        let scene = solari_scene::default_scene::cornell_box();
        let start = scene.camera(None).unwrap();
        for path in [CameraPath::Fixed, CameraPath::Orbit] {
            let rig = path.rig(&start, &scene);
            for frame in [0, 1, 59, 60, 239, 240, 100_000] {
                let want = match path {
                    CameraPath::Fixed => start.clone(),
                    CameraPath::Orbit => start.orbit(&scene, frame),
                };
                assert_eq!(rig.at(frame), want, "{path:?} frame {frame}");
            }
        }
        // The orbit moves the camera; its pivot stays where it was.
        let rig = CameraPath::Orbit.rig(&start, &scene);
        assert_ne!(rig.at(60).position(), start.position());
        let pivot = Camera::orbit_pivot(&scene);
        let (d0, d1) = (start.position() - pivot, rig.at(60).position() - pivot);
        assert!((d0.length() - d1.length()).abs() < 1e-4 * d0.length().max(1.0));
    }

    #[test]
    fn marks_by_name_and_ignore_unknown_names() {
        let mut ran = Marks([false; PASS_NAMES.len()]);
        ran.mark("light_tiles");
        ran.mark("not_a_pass");
        let marked: Vec<_> = PASS_NAMES.iter().zip(ran.0).filter(|(_, r)| *r).collect();
        assert_eq!(marked, [(&"light_tiles", true)]);
    }
}
