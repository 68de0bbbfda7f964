//! # solari-restir
//!
//! ReSTIR DI and ReSTIR GI ([`gi`], with plain path GI) for the Solari workspace. ReSTIR DI: direct light from every light in a scene at a cost of
//! one shadow ray per pixel, by resampling light samples across candidates, frames and
//! neighbouring pixels.
//!
//! ## The algorithm (after Solari 0.18)
//!
//! 1. **Initial RIS** ([`RestirDiSettings::initial_candidates`], default 8): each pixel draws
//!    candidates from one light tile ([`solari_lights::LightTiles`]) shared by its 8×8
//!    workgroup and keeps one with probability proportional to its unshadowed contribution
//!    (the luminance of Le · BRDF · cos · G, with the full BRDF). Optionally
//!    ([`RestirDiSettings::initial_visibility`], off by default because it biases reuse) one
//!    visibility ray tests the choice before reuse, as Solari 0.18 does.
//!    **BRDF-sampled candidates** ([`RestirDiSettings::brdf_candidates`], default 1) join
//!    them on surfaces of roughness 0.02–0.5: a direction drawn from the pixel's BRDF becomes
//!    an environment sample when the environment is a light (every direction, occluded or
//!    not), else a ray through the scene's emitters alone (`trace_emitters` in solari-scene:
//!    a small BVH of the emissive instances) finds the first emitter along it, occluded or
//!    not. Either way the candidate does not depend on visibility, so reuse may move it to a
//!    neighbour with the right MIS weight. Every candidate weighs target / (M_light p_light +
//!    M_brdf p_brdf), both pdfs in the sample's measure (balance heuristic). On a glossy
//!    metal floor under a sky with a small sun the first frame's RMSE fell from 0.665 to
//!    0.100 (`tests/convergence.rs`, 64×64, lavapipe). A point behind another emitter along
//!    the same direction is one the BRDF ray never reaches although its pdf counts it: a
//!    small bias, confined to emitters that hide each other. A scene without an emitter BVH
//!    (thousands of instanced lamps past `bvh::emitters_fit`'s size rule or the binding
//!    limit, or `GpuSceneOptions::emitter_bvh` off) traces the whole scene instead and keeps
//!    only emitters the ray sees: the candidate then depends on visibility, and reuse carries
//!    that small bias too. Sphere and delta lights and sun
//!    disks are left to light sampling. On `interior` (H100, 1080p) the candidates cost 0.30
//!    ms of the initial pass (0.65 → 0.95 ms) where a ray through the whole scene cost 0.63,
//!    and keep its direct light's RMSE at 0.127 against 0.179 without them.
//! 2. **Temporal reuse**: last frame's final reservoir at the motion-vector reprojection,
//!    permuted within 4×4 blocks each frame (falling back to the unpermuted pixel), rejected
//!    where the surfaces differ (tangent-plane distance over 0.3% of the view distance, or
//!    normals over 25° apart), with its light translated to this frame's light list (removed
//!    lights drop the history) and its confidence capped
//!    ([`RestirDiSettings::confidence_cap`], default 20). A light switched on this frame lies
//!    outside last frame's domain: its samples' target there counts as zero
//!    ([`di::appeared_lights`]), so it is not faded in over `confidence_cap` frames.
//! 3. **Spatial reuse**: one neighbour within [`RestirDiSettings::spatial_radius`] (30 px),
//!    up to [`RestirDiSettings::spatial_tries`] (5) tries, halving the radius after each
//!    rejected one.
//! 4. Merges use the **balance heuristic** over confidence-weighted target functions evaluated
//!    at both pixels (generalised RIS).
//! 5. The merged reservoir is stored as next frame's history, and **then** one visibility ray
//!    decides shading; its result is not stored (feeding it forward would bias shadows
//!    outward, Solari 0.18).
//!
//! A frame without reuse (both steps off in the settings, or skipped by
//! [`RestirDiSettings::reuse_light_threshold`] on a scene of few lights) runs steps 1 and 5
//! as one pass: the second pass would only re-read what the first had (4% of the Cornell
//! box's and sun_boxes' frames on an H100, `benches/RESULTS.md`).
//!
//! Samples are identities ([`solari_lights::LightSampleId`]) in the lights' own domain (points
//! on emitters by area, directions for directional lights), so reuse across pixels needs no
//! Jacobian.
//!
//! ## Limits
//!
//! - Only lights in the light list are sampled: a uniform environment (an environment map is
//!   a light) and light reflected by mirror-like surfaces (roughness under the BRDF's mirror
//!   threshold) are not direct light here; the reference tracer's `--max-bounces 1` image
//!   includes both.
//!
//! ## Use
//!
//! Per frame: [`solari_scene::gbuffer::GBuffer::prepare`] and `encode`,
//! [`solari_lights::LightTiles::prepare`] and `encode`, then [`RestirDi::prepare`] and
//! [`RestirDi::encode`]. `solari-renderer`'s `RealtimeRenderer` is the worked example; the crate
//! README has a compiled one.

pub mod di;
pub mod gi;
pub mod gi_reservoir;
pub mod gi_settings;
pub mod reservoir;
pub mod settings;
pub mod specular;

pub use di::{DI_BINDINGS, PASS_LABELS, RestirDi};
pub use gi::{
    ADAPTIVE_CAP_SETTLE_FRAMES, GI_BINDINGS, GI_PASS_LABELS, GI_TARGET_BINDINGS, RestirGi,
};
pub use gi_reservoir::{GpuGiReservoir, gi_reservoir_check};
pub use gi_settings::{GiRate, GlossyHits, GpuGiParams, RestirGiSettings, SpatialVisibility};
pub use reservoir::{GpuReservoir, reservoir_check};
pub use settings::{GpuDiParams, RestirDiSettings};
pub use specular::{PsrBindings, SPECULAR_PASS_LABELS, SpecularGi, SpecularGiSettings};

/// The crate's importable WGSL modules, by module name.
pub const MODULES: &[(&str, &str)] = &[
    (
        "restir_common",
        include_str!("../shaders/restir_common.wesl"),
    ),
    ("restir_di", include_str!("../shaders/restir_di.wesl")),
    (
        "restir_di_math",
        include_str!("../shaders/restir_di_math.wesl"),
    ),
    ("restir_gi", include_str!("../shaders/restir_gi.wesl")),
    ("path_vertex", include_str!("../shaders/path_vertex.wesl")),
    (
        "restir_gi_math",
        include_str!("../shaders/restir_gi_math.wesl"),
    ),
];

/// The crate's entry-point shaders, by module name.
pub const ENTRY_POINTS: &[(&str, &str)] = &[
    (
        "restir_di_initial",
        include_str!("../shaders/restir_di_initial.wesl"),
    ),
    (
        "restir_di_spatial",
        include_str!("../shaders/restir_di_spatial.wesl"),
    ),
    (
        "restir_di_emission",
        include_str!("../shaders/restir_di_emission.wesl"),
    ),
];

/// Every module the crate's shaders need beyond `solari-scene`'s: its own and the lights'.
pub fn modules() -> Vec<(&'static str, &'static str)> {
    [
        solari_lights::MODULES,
        solari_lights::tiles::ENTRY_POINTS,
        MODULES,
        ENTRY_POINTS,
    ]
    .concat()
}

/// ReSTIR GI's entry-point shaders, by module name.
pub const GI_ENTRY_POINTS: &[(&str, &str)] = &[
    (
        "restir_gi_initial",
        include_str!("../shaders/restir_gi_initial.wesl"),
    ),
    (
        "restir_gi_spatial",
        include_str!("../shaders/restir_gi_spatial.wesl"),
    ),
];

/// Every module ReSTIR GI's shaders need beyond `solari-scene`'s: the lights' (for the
/// light samples at glossy hits), the world cache's and this crate's.
pub fn gi_modules() -> Vec<(&'static str, &'static str)> {
    [
        solari_lights::MODULES,
        solari_worldcache::MODULES,
        MODULES,
        GI_ENTRY_POINTS,
    ]
    .concat()
}

/// Specular GI's entry-point shader, by module name.
pub const SPECULAR_ENTRY_POINTS: &[(&str, &str)] =
    &[("specular_gi", include_str!("../shaders/specular_gi.wesl"))];

/// Every module specular GI's shader needs beyond `solari-scene`'s: the lights', the world
/// cache's and this crate's.
pub fn specular_modules() -> Vec<(&'static str, &'static str)> {
    [
        solari_lights::MODULES,
        solari_worldcache::MODULES,
        MODULES,
        SPECULAR_ENTRY_POINTS,
    ]
    .concat()
}

/// The README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
