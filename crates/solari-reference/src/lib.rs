//! # solari-reference
//!
//! The ground truth every Solari component is measured against, as a library: the reference
//! path tracer ([`path_tracer`]), image error metrics ([`metrics`]: RMSE, relMSE, FLIP) and
//! image input and output ([`image_io`]: linear EXR, tone-mapped PNG). [`scene_image`] renders
//! a whole scene's reference in one call and [`rmse`] compares two images cheaply, for
//! component crates' tests.

pub mod image_io;
pub mod metrics;
pub mod path_tracer;
pub mod scene_image;

pub use metrics::rmse;
pub use path_tracer::{ReferenceImage, ReferenceRenderer, ReferenceSettings};
pub use scene_image::{centre_image, reference_image};

/// The README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
