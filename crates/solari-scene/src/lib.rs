//! # solari-scene
//!
//! The scene layer of the Solari workspace: a CPU scene model with glTF 2.0 import, GPU
//! context creation, upload of geometry, materials and textures, and two ray-tracing backends
//! (hardware ray queries and a software BVH) behind one WGSL interface.
//!
//! ```no_run
//! use solari_scene::{load_gltf, default_scene};
//! let scene = load_gltf("scene.gltf").unwrap_or_else(|e| {
//!     eprintln!("{e}");
//!     default_scene::cornell_box()
//! });
//! println!("{:?}", scene.stats());
//! ```

pub mod asset_io;
pub mod bindings;
pub mod brdf;
pub mod bvh;
pub mod case_kernel;
pub mod default_scene;
pub mod environment;
pub mod error;
pub mod finite_check;
pub mod gbuffer;
pub mod gbuffer_debug;
pub mod gbuffer_input;
pub mod gbuffer_override;
mod gbuffer_raster;
mod gbuffer_traced;
pub mod generated_scene;
pub mod geometry;
pub mod gltf_check;
pub mod gltf_import;
pub mod gpu;
pub mod gpu_scene;
pub mod gpu_timer;
pub mod gpu_types;
pub mod model;
pub mod packing;
pub mod pass;
pub mod primary_depth;
pub mod ray_differentials;
pub mod render_setup;
pub mod rng;
pub mod scratch;
pub mod shaders;
pub mod texture;
pub mod textured_scene;
pub mod trace_cpu;
pub mod trace_pass;
pub mod validate;
pub mod view_pass;

pub use asset_io::ImportLimits;
pub use environment::{EnvironmentMap, EnvironmentOptions};
pub use error::{GpuError, SceneError};
pub use gltf_import::{ImportOptions, import_slice, load_gltf, load_gltf_with};
pub use model::*;
pub use validate::{MAX_COORDINATE, MAX_RADIANCE};

/// The README's examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
