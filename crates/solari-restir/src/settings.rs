//! ReSTIR DI's knobs, each with its default and its cost.

use bytemuck::{Pod, Zeroable};
use solari_scene::GpuError;

/// Most initial candidates a pixel may draw (the shader loop's bound).
pub const MAX_INITIAL_CANDIDATES: u32 = 1024;
/// Most spatial neighbour tries (the shader loop's bound).
pub const MAX_SPATIAL_TRIES: u32 = 16;

/// Every quality knob of [`crate::RestirDi`]. The defaults are Solari's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestirDiSettings {
    /// Light-tile samples each pixel resamples in initial RIS (default 8). Cost: one light
    /// evaluation (no ray) per candidate; fewer candidates mean noisier initial samples.
    pub initial_candidates: u32,
    /// Reuse last frame's reservoir at the reprojected pixel (default on). Costs one more
    /// reservoir merge per pixel; off, every frame starts afresh.
    ///
    /// Both reuse steps are on by default because scenes with many lights need them: on
    /// many_lights (H100, 1080p, the renderer's defaults with the fallback denoiser) turning
    /// both off raised the frame's relMSE against the full reference 63% in the 8th frame and
    /// 20–23% once converged. On scenes with few large lights they buy nothing after the
    /// denoiser: the Cornell box, sun_boxes and `interior` were within −6% to +4% without
    /// them, and `interior`'s frame took 4.14 ms instead of 4.91 (`benches/RESULTS.md`,
    /// "ReSTIR DI's reuse against the frame"). So the real-time renderer skips both steps on
    /// scenes of few lights under its fallback denoiser
    /// ([`RestirDiSettings::reuse_light_threshold`]).
    pub temporal: bool,
    /// Reuse one neighbour's reservoir (default on). Costs one merge per pixel; see
    /// [`RestirDiSettings::temporal`] for what both steps buy.
    pub spatial: bool,
    /// Skip both reuse steps on scenes whose light sampling chooses among at most this many
    /// elements (`solari_lights::LightList::sampling_elements`: emissive triangles plus
    /// analytic lights; an environment map counts as unbounded), whatever
    /// [`RestirDiSettings::temporal`] and [`RestirDiSettings::spatial`] say. Default 0: reuse
    /// as those two say. Checked every frame against the light list [`crate::RestirDi::prepare`]
    /// is given, so a scene that gains lights starts reusing;
    /// [`crate::RestirDi::reuse_skipped`] tells whether this frame skipped it.
    ///
    /// Why: with a handful of lights, the initial candidates already find the light that
    /// matters, and reuse costs time that a denoiser makes worthless. The real-time renderer
    /// sets 64 when its fallback denoiser runs (`solari_renderer::DI_REUSE_LIGHT_THRESHOLD`,
    /// with the figures); a pass whose frames are seen raw should keep reuse, which cut the
    /// raw frames' error by a fifth even on a scene of 13 elements.
    pub reuse_light_threshold: u32,
    /// Permute the temporal source pixel within 4×4 blocks each frame (default on), which
    /// decorrelates the noise a denoiser sees at no cost in rays.
    pub permutation_sampling: bool,
    /// Cap on the confidence (candidate count) history carries into a frame (default 20):
    /// higher is smoother on static views, slower to follow changes in light.
    pub confidence_cap: f32,
    /// First spatial search radius in pixels (default 30), halved after each rejected try.
    pub spatial_radius: f32,
    /// Neighbours tried before spatial reuse gives up for the pixel (default 5).
    pub spatial_tries: u32,
    /// Trace a shadow ray for each pixel's initial sample and zero it when occluded, before
    /// reuse (Solari 0.18's order; default off). Costs one ray per pixel and removes noise in
    /// shadows, but biases reuse: a neighbour's occluded sample counts in the MIS weights as
    /// if it could have been chosen, so light near shadow edges is lost (measured: the
    /// Cornell box comes out 2.3% dark, a soft-sun scene 12.8%, over 128 frames at 64×64).
    /// Only frames with reuse trace it: without reuse the final shadow ray is the same ray
    /// (it zeroes the light all the same, and the kept sample gives the denoiser its shadow).
    pub initial_visibility: bool,
    /// BRDF-sampled candidates per pixel, beside the tile candidates (default 1, at most
    /// [`MAX_BRDF_CANDIDATES`]). Each draws a direction from the pixel's BRDF: with an
    /// environment map that is a light it is that map's sample (no ray); otherwise one ray
    /// along it through the scene's emitters alone, and the first emissive triangle it meets,
    /// occluded or not, is the sample. The sample joins initial
    /// RIS, weighted against the tile candidates by the balance heuristic. Glossy surfaces then reflect lights and the sky in DI, which
    /// light sampling alone finds only by chance. Only pixels of roughness at most
    /// [`BRDF_CANDIDATE_MAX_ROUGHNESS`] trace them (rougher ones gain little), and never
    /// mirrors (DI leaves them to specular GI). Sphere and delta lights and sun disks are
    /// not hit by these rays and stay with light sampling alone. 0 turns them off.
    pub brdf_candidates: u32,
    /// Draw initial candidates from the light grid uploaded with the light list
    /// (`solari_lights::GpuLights::with_grid`; default off): each candidate comes from the
    /// lights listed in the pixel's grid cell with the grid's share, from the light tiles
    /// otherwise, weighted by the mixture's pdf so no light is lost. For scenes with
    /// thousands of local lights, where a tile sample is rarely near the pixel. Costs one
    /// light resolve per grid candidate and a short binary search per candidate. Without an
    /// uploaded grid every candidate comes from the tiles, as with this off.
    pub light_grid: bool,
}

/// The most BRDF-sampled candidates per pixel ([`RestirDiSettings::brdf_candidates`]).
pub const MAX_BRDF_CANDIDATES: u32 = 4;

/// Roughest surface that traces BRDF-sampled candidates (WGSL `BRDF_CANDIDATE_MAX_ROUGHNESS`).
pub const BRDF_CANDIDATE_MAX_ROUGHNESS: f32 = 0.5;

impl Default for RestirDiSettings {
    fn default() -> Self {
        Self {
            initial_candidates: 8,
            temporal: true,
            spatial: true,
            reuse_light_threshold: 0,
            permutation_sampling: true,
            confidence_cap: 20.0,
            spatial_radius: 30.0,
            spatial_tries: 5,
            initial_visibility: false,
            brdf_candidates: 1,
            light_grid: false,
        }
    }
}

impl RestirDiSettings {
    /// Whether these settings skip reuse for lights of `sampling_elements` elements
    /// ([`RestirDiSettings::reuse_light_threshold`]; 0 never skips).
    pub fn skips_reuse(&self, sampling_elements: u32) -> bool {
        self.reuse_light_threshold > 0 && sampling_elements <= self.reuse_light_threshold
    }

    /// Checks every knob is in range; the error names the bad one.
    pub fn validate(&self) -> Result<(), GpuError> {
        let bad = |what: String| Err(GpuError::Validation(format!("ReSTIR DI settings: {what}")));
        if self.initial_candidates == 0 || self.initial_candidates > MAX_INITIAL_CANDIDATES {
            return bad(format!(
                "initial_candidates is {}, expected 1 to {MAX_INITIAL_CANDIDATES}",
                self.initial_candidates
            ));
        }
        if self.brdf_candidates > MAX_BRDF_CANDIDATES {
            return bad(format!(
                "brdf_candidates is {}, expected at most {MAX_BRDF_CANDIDATES}",
                self.brdf_candidates
            ));
        }
        check_reuse(
            "ReSTIR DI",
            self.spatial_tries,
            self.confidence_cap,
            self.spatial_radius,
        )
    }
}

/// The reuse knobs DI and GI share, checked the same way; the error names the pass and knob.
pub(crate) fn check_reuse(
    pass: &str,
    spatial_tries: u32,
    confidence_cap: f32,
    spatial_radius: f32,
) -> Result<(), GpuError> {
    let bad = |what: String| Err(GpuError::Validation(format!("{pass} settings: {what}")));
    if spatial_tries > MAX_SPATIAL_TRIES {
        return bad(format!(
            "spatial_tries is {spatial_tries}, expected at most {MAX_SPATIAL_TRIES}"
        ));
    }
    if !(confidence_cap.is_finite() && confidence_cap >= 1.0) {
        return bad(format!(
            "confidence_cap is {confidence_cap}, expected a finite value of at least 1"
        ));
    }
    if !(spatial_radius.is_finite() && spatial_radius >= 1.0) {
        return bad(format!(
            "spatial_radius is {spatial_radius}, expected a finite value of at least 1 pixel"
        ));
    }
    Ok(())
}

/// `DI_FLAG_*` in `restir_di.wesl`; the first four are `GI_FLAG_*` in `restir_gi.wesl` too.
pub(crate) mod flags {
    pub const TEMPORAL: u32 = 1;
    pub const SPATIAL: u32 = 2;
    pub const PERMUTATION: u32 = 4;
    pub const HISTORY: u32 = 8;
    pub const INITIAL_VISIBILITY: u32 = 16;
    pub const APPEARED: u32 = 32;
    /// DI only: write no light to the output (`RestirDi::set_indirect_only`).
    pub const NO_LIGHT_OUT: u32 = 64;

    /// The reuse bits DI and GI share.
    pub fn reuse(temporal: bool, spatial: bool, permutation: bool, history: bool) -> u32 {
        [
            (temporal, TEMPORAL),
            (spatial, SPATIAL),
            (permutation, PERMUTATION),
            (history, HISTORY),
        ]
        .iter()
        .filter(|(on, _)| *on)
        .fold(0, |bits, (_, bit)| bits | bit)
    }
}

/// WGSL twin: `DiParams` in `restir_di.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuDiParams {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Frame index (seeds random numbers).
    pub frame: u32,
    /// [`RestirDiSettings::initial_candidates`].
    pub initial_candidates: u32,
    /// Light tiles.
    pub tile_count: u32,
    /// Samples per light tile.
    pub samples_per_tile: u32,
    /// [`RestirDiSettings::spatial_tries`].
    pub spatial_tries: u32,
    /// `DI_FLAG_*` bits.
    pub flags: u32,
    /// [`RestirDiSettings::spatial_radius`].
    pub spatial_radius: f32,
    /// [`RestirDiSettings::confidence_cap`].
    pub confidence_cap: f32,
    /// Entries of the light translation table (0 disables temporal reuse this frame).
    pub translation_count: u32,
    /// [`RestirDiSettings::brdf_candidates`].
    pub brdf_candidates: u32,
}

const _: () = assert!(size_of::<GpuDiParams>() == 48);
