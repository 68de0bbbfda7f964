//! The fallback denoiser's knobs and their GPU mirror.

use solari_scene::GpuError;

/// The largest [`FallbackSettings::max_history`]: the history stores its length as an f16,
/// which holds whole frames exactly up to 2048.
pub const MAX_HISTORY_LIMIT: f32 = 2048.0;

/// The taps of one à-trous iteration, on a grid of holes `step` pixels apart
/// ([`FallbackSettings::atrous_kernel`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AtrousKernel {
    /// The 13 taps of the 5×5 B3-spline kernel within two steps of the centre by Manhattan
    /// distance, with their B3 weights (the default): the 12 it leaves out carry 14% of the
    /// kernel's weight. The à-trous iterations take 27–30% less time than with
    /// [`AtrousKernel::Full`] at the same measured error (H100, 1920×1080; crate docs).
    #[default]
    Diamond,
    /// All 25 taps of the 5×5 B3-spline kernel, as SVGF.
    Full,
}

impl AtrousKernel {
    /// The name the CLI and reports use (`diamond`, `full`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Diamond => "diamond",
            Self::Full => "full",
        }
    }

    /// The kernel [`AtrousKernel::name`] names, if any.
    pub fn parse(name: &str) -> Option<Self> {
        [Self::Diamond, Self::Full]
            .into_iter()
            .find(|k| k.name() == name)
    }
}

/// Every knob of [`crate::FallbackDenoiser`], with the defaults the tests and benchmarks use.
///
/// Lengths are in frames; luminance tolerances are in units of the signal's own standard
/// deviation, so one set of settings fits dim and bright scenes alike.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FallbackSettings {
    /// Most frames the temporal average spans (default 32). Past it the history becomes an
    /// exponential average with factor 1/`max_history`: longer is smoother on static views
    /// and slower to follow changes that the fast-history test misses. At most
    /// [`MAX_HISTORY_LIMIT`] (the stored length is an f16).
    pub max_history: f32,
    /// Edge-aware à-trous iterations, with steps 1, 2, 4, … pixels (default 5: taps up to
    /// 62 pixels from the centre, inside a 125×125 square, or the diamond within it with
    /// [`AtrousKernel::Diamond`]). 1–8. Each costs one full-screen pass.
    pub atrous_iterations: u32,
    /// Which taps each à-trous iteration reads (default [`AtrousKernel::Diamond`], 13).
    pub atrous_kernel: AtrousKernel,
    /// Feed the first iteration's output back as the colour history, as SVGF does (default
    /// off): steadier under motion, but the luminance-weighted blur then compounds over
    /// frames: on 1% fireflies the output mean reads +56% with it against +9% without
    /// (`cargo test --release -p solari-denoise --test fallback -- --nocapture`, lavapipe).
    pub history_feedback: bool,
    /// Luminance edge-stopping, in standard deviations of the pixel's (3×3 prefiltered)
    /// variance (SVGF's σ_l, default 4). Larger blurs more across shading changes.
    pub phi_luminance: f32,
    /// Normal edge-stopping exponent on the cosine between shading normals (SVGF's σ_n,
    /// default 128: 20° apart weighs 0.0004).
    pub phi_normal: f32,
    /// Depth edge-stopping: distance from the centre pixel's tangent plane, as a fraction of
    /// its view distance, that weighs 1/e (default 0.005; at least [`PHI_MIN`]).
    pub phi_depth: f32,
    /// Specular-lobe edge-stopping (default 8; 0: off). Glossy reflections change with the
    /// normal far faster than diffuse light: a neighbour whose shading normal is δ radians
    /// away weighs about exp(−phi_lobe · (δ/α)²) (2(1 − cos δ) stands for δ²), α being the centre's GGX α (roughness², at least
    /// 0.01), mixed in by the share of the centre's reflectance that is specular. Without it
    /// the young-history filter spreads a metal sphere's sun highlight: sun_boxes at 256 px,
    /// frame 1, RMSE 0.238 against 0.020 with it (raw 0.008; `solari bench-denoise`).
    pub phi_lobe: f32,
    /// Firefly limit: a sample brighter than this many times the pixel's recent mean
    /// luminance is clamped and the excess carried into later frames (default 8; 0 turns
    /// suppression off). Energy is moved in time, not removed: see the crate docs.
    pub firefly_clamp: f32,
    /// History length below which samples are not clamped (default 4): without history
    /// there is no mean to compare with.
    pub firefly_min_history: f32,
    /// At least 1/`firefly_spread` of a clamped sample's energy (with its carry) is released
    /// each frame (default 16), so a firefly is spread over at most about this many frames
    /// even where the mean is near zero.
    pub firefly_spread: f32,
    /// Length of the fast history used to detect stale history, in frames (default 4).
    pub fast_history: f32,
    /// Fast history reset: when a pixel's fast (4-frame) and long luminance averages of its
    /// own samples differ by more than this many standard deviations of the fast average
    /// (σ relative to the mean, measured in calm frames) plus 10%, the long average is
    /// clamped into that band, the colour history rescaled with it and its length held at
    /// [`FallbackSettings::reset_length`] (default 4; 0 turns it off). Lights switched off,
    /// opened doors and moving shadows then catch up in tens of frames instead of hundreds.
    /// Its price is a bias on noise with heavy tails (a burst of fireflies reads as a
    /// change): see the crate docs.
    pub reset_sigma: f32,
    /// History length while the fast reset holds (default 4): the average then follows a
    /// change with factor 1/4 per frame.
    pub reset_length: f32,
    /// History length below which the fast reset is not tested (default 4; at most
    /// `reset_length`, or the reset would let go after one frame): young histories follow
    /// changes anyway.
    pub reset_min_history: f32,
    /// How long a young history leans on a spatial variance estimate (default 4, where SVGF
    /// switches). Variance is blended geometrically from an estimate over the 5×5
    /// neighbourhood (raised by this over the history length while shorter) at length 1 to
    /// the pixel's own temporal estimate at twice this length. A hard switch made the image
    /// pop when it happened (RMS frame-to-frame change doubled that frame); an arithmetic
    /// blend let the spatial estimate, which also holds the image's own contrast, dominate
    /// to the end (`solari bench-denoise`). With [`crate::DenoiserInputs::shadow`], a window
    /// whose shadows all have penumbrae under a pixel is estimated over the shadow-free
    /// signal instead, so its hard shadow edges do not count as noise, and that estimate
    /// caps the temporal variance at any history length.
    pub spatial_variance_frames: f32,
    /// Whether the lighting carries the G-buffer's emission (default true), which is exact,
    /// so the filter takes it out and puts it back. False for lighting without it (the
    /// real-time renderer's view of indirect light alone): emission is then neither taken
    /// out nor put back, and an emitter shows only the light it reflects. The real-time
    /// renderer sets it from its view (false for `FrameView::Indirect` only), whatever its
    /// `RealtimeSettings::denoise` holds.
    pub emission_in_lighting: bool,
}

impl Default for FallbackSettings {
    fn default() -> Self {
        Self {
            max_history: 32.0,
            atrous_iterations: 5,
            atrous_kernel: AtrousKernel::Diamond,
            history_feedback: false,
            phi_luminance: 4.0,
            phi_normal: 128.0,
            phi_depth: 0.005,
            phi_lobe: 8.0,
            firefly_clamp: 8.0,
            firefly_min_history: 4.0,
            firefly_spread: 16.0,
            fast_history: 4.0,
            reset_sigma: 4.0,
            reset_length: 4.0,
            reset_min_history: 4.0,
            spatial_variance_frames: 4.0,
            emission_in_lighting: true,
        }
    }
}

/// Smallest `phi_depth` [`FallbackSettings::validate`] accepts: below it the depth weight's
/// divisor (phi_depth times a view depth) can underflow, and a tap exactly on the centre's
/// plane then weighs 0 × ∞ = NaN. At 1e-6 the depth weight already
/// keeps only taps within a millionth of the view distance of the plane.
pub const PHI_MIN: f32 = 1e-6;

/// Largest edge-stopping factor (`phi_*`) [`FallbackSettings::validate`] accepts. phi_lobe's
/// product overflows f32 to infinity near 1e38, and times the zero of exactly matching normals
/// that is NaN; the other factors share the bound, far above any useful value.
pub const PHI_MAX: f32 = 1e30;

impl FallbackSettings {
    /// Refuses values that make no sense, naming the knob.
    pub fn validate(&self) -> Result<(), GpuError> {
        let bad = |name: &str, why: &str| {
            Err(GpuError::Validation(format!(
                "fallback denoiser: {name} {why}"
            )))
        };
        let finite = [
            ("max_history", self.max_history),
            ("phi_luminance", self.phi_luminance),
            ("phi_normal", self.phi_normal),
            ("phi_depth", self.phi_depth),
            ("phi_lobe", self.phi_lobe),
            ("firefly_clamp", self.firefly_clamp),
            ("firefly_min_history", self.firefly_min_history),
            ("firefly_spread", self.firefly_spread),
            ("fast_history", self.fast_history),
            ("reset_sigma", self.reset_sigma),
            ("reset_min_history", self.reset_min_history),
            ("reset_length", self.reset_length),
            ("spatial_variance_frames", self.spatial_variance_frames),
        ];
        for (name, v) in finite {
            if !v.is_finite() || v < 0.0 {
                return bad(name, &format!("must be finite and ≥ 0, got {v}"));
            }
        }
        if !(1.0..=MAX_HISTORY_LIMIT).contains(&self.max_history) {
            return bad(
                "max_history",
                "must be 1–2048 frames (the history stores its length as f16)",
            );
        }
        if !(1..=8).contains(&self.atrous_iterations) {
            return bad(
                "atrous_iterations",
                &format!("must be 1–8, got {}", self.atrous_iterations),
            );
        }
        if self.phi_luminance <= 0.0 {
            return bad("phi_luminance", "must be > 0");
        }
        // The depth weight divides by phi_depth times a view depth, and the weights multiply
        // the phi factors by terms that can be exactly zero: a tiny divisor or a huge factor
        // overflows to infinity, and infinity times zero is NaN.
        if self.phi_depth < PHI_MIN {
            return bad(
                "phi_depth",
                &format!("must be at least {PHI_MIN:e}, got {}", self.phi_depth),
            );
        }
        for (name, v) in [
            ("phi_luminance", self.phi_luminance),
            ("phi_normal", self.phi_normal),
            ("phi_depth", self.phi_depth),
            ("phi_lobe", self.phi_lobe),
        ] {
            if v > PHI_MAX {
                return bad(name, &format!("must be at most {PHI_MAX:e}, got {v}"));
            }
        }
        if self.fast_history < 1.0 {
            return bad("fast_history", "must be at least 1 frame");
        }
        if self.firefly_spread < 1.0 {
            return bad("firefly_spread", "must be at least 1 frame");
        }
        if self.firefly_clamp > 0.0 && self.firefly_clamp < 1.0 {
            return bad(
                "firefly_clamp",
                "below 1 would clamp the mean itself; use 0 to turn it off",
            );
        }
        if self.reset_min_history < 1.0 {
            return bad("reset_min_history", "must be at least 1 frame");
        }
        if self.reset_length < 1.0 || self.reset_length > self.max_history {
            return bad("reset_length", "must be between 1 and max_history");
        }
        if self.reset_min_history > self.reset_length {
            return bad(
                "reset_min_history",
                "must not exceed reset_length (the reset would hold for one frame only)",
            );
        }
        Ok(())
    }

    /// The GPU parameters for one frame.
    pub fn gpu(&self, width: u32, height: u32, reset: bool) -> GpuDenoiseParams {
        GpuDenoiseParams {
            width,
            height,
            reset: reset as u32,
            shadow: 0,
            max_history: self.max_history,
            phi_luminance: self.phi_luminance,
            phi_normal: self.phi_normal,
            phi_depth: self.phi_depth,
            firefly_clamp: self.firefly_clamp,
            firefly_min_history: self.firefly_min_history,
            firefly_spread: self.firefly_spread,
            fast_alpha: 1.0 / self.fast_history,
            reset_sigma: self.reset_sigma,
            reset_min_history: self.reset_min_history,
            spatial_variance_frames: self.spatial_variance_frames,
            reset_length: self.reset_length,
            phi_lobe: self.phi_lobe,
            frame: 0,
            no_emission: (!self.emission_in_lighting).into(),
            _pad1: 0,
        }
    }
}

/// The per-frame uniform (WGSL `DenoiseParams`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuDenoiseParams {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// 1: ignore history this frame.
    pub reset: u32,
    /// 1: the `shadow` binding holds [`crate::DenoiserInputs::shadow`] (0: a placeholder).
    pub shadow: u32,
    /// [`FallbackSettings::max_history`].
    pub max_history: f32,
    /// [`FallbackSettings::phi_luminance`].
    pub phi_luminance: f32,
    /// [`FallbackSettings::phi_normal`].
    pub phi_normal: f32,
    /// [`FallbackSettings::phi_depth`].
    pub phi_depth: f32,
    /// [`FallbackSettings::firefly_clamp`].
    pub firefly_clamp: f32,
    /// [`FallbackSettings::firefly_min_history`].
    pub firefly_min_history: f32,
    /// [`FallbackSettings::firefly_spread`].
    pub firefly_spread: f32,
    /// 1 / [`FallbackSettings::fast_history`].
    pub fast_alpha: f32,
    /// [`FallbackSettings::reset_sigma`].
    pub reset_sigma: f32,
    /// [`FallbackSettings::reset_min_history`].
    pub reset_min_history: f32,
    /// [`FallbackSettings::spatial_variance_frames`].
    pub spatial_variance_frames: f32,
    /// [`FallbackSettings::reset_length`].
    pub reset_length: f32,
    /// [`FallbackSettings::phi_lobe`].
    pub phi_lobe: f32,
    /// Frames the denoiser has recorded (wrapping): seeds the history's stochastic rounding
    /// ([`crate::history`]).
    pub frame: u32,
    /// 1: the lighting holds no emission (not [`FallbackSettings::emission_in_lighting`]).
    pub no_emission: u32,
    /// Padding.
    pub _pad1: u32,
}

const _: () = assert!(size_of::<GpuDenoiseParams>() == 80);

/// Per-dispatch uniform (WGSL `PassParams`): which signal, which iteration.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuPassParams {
    /// À-trous step in pixels (1, 2, 4, …; 0 for the temporal and variance passes).
    pub step: u32,
    /// Padding (history feedback is the `denoise_atrous_feedback` pipeline's own job, so no
    /// flag says it).
    pub _pad0: u32,
    /// 1: the last iteration, which remodulates and writes the output.
    pub last: u32,
    /// 0 combined, 1 diffuse, 2 specular: which albedo demodulates.
    pub signal: u32,
    /// 1: add to the output instead of overwriting it (the second of split signals).
    pub accumulate: u32,
    /// 1: the last iteration writes the output over its own filter result (one signal: the
    /// filter buffer is the output, so the denoiser keeps no separate one).
    pub output_in_filter: u32,
    /// 1: read the centre's guide words through `transient_ro` (this dispatch binds the
    /// transient words' buffer read-only elsewhere), 0: through `transient`.
    pub centre_ro: u32,
    /// Padding.
    pub _pad: u32,
}

const _: () = assert!(size_of::<GpuPassParams>() == 32);
