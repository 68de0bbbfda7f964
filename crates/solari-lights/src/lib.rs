//! # solari-lights
//!
//! The light sampling core of the Solari workspace: the light list built from a scene
//! (emissive instances with their triangles, directional lights as sun disks, point and spot
//! lights as delta lights or spheres), light selection
//! (uniform, as Solari does, or proportional to emitted power through an alias table), and the
//! resolution of a light sample at a shading point with its solid-angle pdf. Lights keep
//! stable keys across frames and [`LightList::translation_from`] maps last frame's light
//! indices to this frame's, so temporal reuse never shades with a removed light.
//!
//! ```
//! use solari_lights::{LightList, Selection, unshadowed_contribution};
//! use solari_scene::brdf::BrdfMaterial;
//! use glam::Vec3;
//!
//! let scene = solari_scene::default_scene::cornell_box();
//! let lights = LightList::build(&scene);
//! assert!(!lights.is_empty());
//! // A point on the floor, lit by the ceiling light.
//! let x = Vec3::new(0.0, 0.01, 0.0);
//! if let Some(s) = lights.sample(Selection::Power, x, [0.5, 0.5, 0.3, 0.7]) {
//!     let white = BrdfMaterial {
//!         base_color: Vec3::ONE,
//!         metallic: 0.0,
//!         roughness: 1.0,
//!         dielectric_f0: Vec3::splat(0.04),
//!         dielectric_f90: 1.0,
//!         model: Default::default(),
//!     };
//!     let c = unshadowed_contribution(&s, &white, Vec3::Y, Vec3::Y);
//!     assert!(c.is_finite());
//! }
//! ```
//!
//! The CPU code here is the reference the GPU light-sampling module is tested against.
//! [`LightTiles`] presamples resolved light samples on the GPU for ReSTIR DI (see `tiles`);
//! for scenes with thousands of lights, a [`LightGrid`] lets ReSTIR DI draw most candidates
//! from the lights near each pixel (see `light_grid`).

// `!(x > 0.0)` is deliberate throughout: it rejects NaN along with non-positive values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod alias;
pub mod analytic;
pub mod environment;
pub mod gpu;
pub mod light_grid;
pub mod light_list;
pub mod sample;
pub mod tiles;

pub use alias::{AliasEntry, AliasTable};
pub use gpu::{ENVIRONMENT_BINDINGS, GRID_BINDINGS, GpuLights, LIGHT_BINDINGS, MODULES};
pub use light_grid::{LIGHT_GRID_ON, LightGrid, LightGridReport, LightGridSettings};
pub use light_list::{
    EmissiveTriangle, EnvironmentLight, LIGHT_GONE, Light, LightKey, LightList, LightListReport,
    Selection, SpotCone, sun_disk,
};
pub use sample::{LightSample, LightSampleId, ResolvedLightSample, unshadowed_contribution};
pub use tiles::{
    LightTileSettings, LightTiles, PASS_LABELS, PRESAMPLE_BINDINGS, PackedLightSample,
    SAMPLE_CHECK, TILE_BINDINGS,
};

/// The README's examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
