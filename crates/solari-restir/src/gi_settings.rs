//! ReSTIR GI's knobs, each with its default and its cost.

use bytemuck::{Pod, Zeroable};
use solari_scene::GpuError;

/// Every knob of [`crate::RestirGi`]. With `temporal` and `spatial` both off it is plain
/// path GI: one traced sample per pixel, shaded as it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestirGiSettings {
    /// Reuse last frame's reservoir at the reprojected pixel (default on).
    pub temporal: bool,
    /// Reuse one neighbour's reservoir (default on). Costs one visibility ray per pixel.
    pub spatial: bool,
    /// Permute the temporal source pixel within 4×4 blocks each frame (default off). Solari
    /// 0.17 found that DLSS-RR turns unpermuted GI reuse into blotches, so turn it on for
    /// DLSS-RR. It costs accuracy: the permuted pixel's history is reused without a visibility
    /// ray, which measured 0.8% darker on the Cornell box (48², 256-frame mean), and its
    /// single-frame error was 12% higher (`tests/gi.rs`).
    pub permutation_sampling: bool,
    /// Cap on the confidence history carries into a frame (default 8, Bevy's value): higher
    /// is smoother on static views, slower to follow moving light (there is no validation
    /// ray, so moving lights leave trails for about this many frames).
    pub confidence_cap: f32,
    /// First spatial search radius in pixels (default 30), halved after each rejected try.
    pub spatial_radius: f32,
    /// Neighbours tried before spatial reuse gives up for the pixel (default 5).
    pub spatial_tries: u32,
    /// Reuse is refused where either reconnection Jacobian exceeds this (default 2, Solari
    /// 0.17's). It is what keeps reuse from concentrating a sample's weight on pixels that
    /// see it at a much larger solid angle, the source of fireflies and overflow.
    pub jacobian_bound: f32,
    /// Longest GI ray (default unbounded); a miss is lit by the scene's environment.
    pub max_ray_distance: f32,
    /// In spatial reuse, also trace whether the neighbour sees this pixel's own sample, and
    /// count the neighbour in that sample's MIS weight only if it does (default on). Costs
    /// a third ray per pixel (skipped where that sample's value at the neighbour is zero or
    /// the merge is refused anyway). Off, the neighbour counts as if it could have produced every
    /// sample, which darkens indirect light near occluders.
    pub unbiased_spatial: bool,
    /// Candidate rays per pixel for the initial sample (default 1, Solari's; 1 to
    /// [`MAX_GI_INITIAL_SAMPLES`]), combined by resampled importance sampling with the
    /// target function: the pixel keeps one of them, weighted as if sampled in proportion to
    /// the target. Each costs a ray and a cache query; with plain path GI this is how more
    /// samples per pixel are bought.
    pub initial_samples: u32,
}

/// Most initial GI candidates per pixel (the shader loop's bound).
pub const MAX_GI_INITIAL_SAMPLES: u32 = 16;

impl Default for RestirGiSettings {
    fn default() -> Self {
        Self {
            temporal: true,
            spatial: true,
            permutation_sampling: false,
            confidence_cap: 8.0,
            spatial_radius: 30.0,
            spatial_tries: 5,
            jacobian_bound: 2.0,
            max_ray_distance: f32::MAX,
            unbiased_spatial: true,
            initial_samples: 1,
        }
    }
}

impl RestirGiSettings {
    /// Plain path GI: the same initial sample with no reuse.
    pub fn plain() -> Self {
        Self {
            temporal: false,
            spatial: false,
            ..Self::default()
        }
    }

    /// Whether any reuse is on (off: plain path GI).
    pub fn reuse(&self) -> bool {
        self.temporal || self.spatial
    }

    /// Checks every knob is in range; the error names the bad one.
    pub fn validate(&self) -> Result<(), GpuError> {
        let bad = |what: String| Err(GpuError::Validation(format!("ReSTIR GI settings: {what}")));
        crate::settings::check_reuse(
            "ReSTIR GI",
            self.spatial_tries,
            self.confidence_cap,
            self.spatial_radius,
        )?;
        if !(self.jacobian_bound.is_finite() && self.jacobian_bound >= 1.0) {
            return bad(format!(
                "jacobian_bound is {}, expected a finite value of at least 1",
                self.jacobian_bound
            ));
        }
        if !(1..=MAX_GI_INITIAL_SAMPLES).contains(&self.initial_samples) {
            return bad(format!(
                "initial_samples is {}, expected 1 to {MAX_GI_INITIAL_SAMPLES}",
                self.initial_samples
            ));
        }
        if self.max_ray_distance.is_nan() || self.max_ray_distance <= 0.0 {
            return bad(format!(
                "max_ray_distance is {}, expected a positive distance",
                self.max_ray_distance
            ));
        }
        Ok(())
    }
}

/// `GI_FLAG_*` in `restir_gi.wesl` beyond the reuse bits shared with DI
/// (`settings::flags::reuse`).
pub(crate) mod flags {
    pub const UNBIASED_SPATIAL: u32 = 16;
    /// Plain path GI on one reservoir buffer: the shade pass writes its pixel's reservoir
    /// back into `gi_initial` (no history buffer is allocated).
    pub const IN_PLACE: u32 = 32;
}

/// WGSL twin: `GiParams` in `restir_gi.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuGiParams {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Frame index (seeds random numbers).
    pub frame: u32,
    /// `GI_FLAG_*` bits.
    pub flags: u32,
    /// [`RestirGiSettings::spatial_radius`].
    pub spatial_radius: f32,
    /// [`RestirGiSettings::confidence_cap`].
    pub confidence_cap: f32,
    /// [`RestirGiSettings::spatial_tries`].
    pub spatial_tries: u32,
    /// [`RestirGiSettings::jacobian_bound`].
    pub jacobian_bound: f32,
    /// [`RestirGiSettings::max_ray_distance`].
    pub max_ray_distance: f32,
    /// [`RestirGiSettings::initial_samples`].
    pub initial_samples: u32,
    /// Padding.
    pub _pad: [u32; 2],
}

const _: () = assert!(size_of::<GpuGiParams>() == 48);
