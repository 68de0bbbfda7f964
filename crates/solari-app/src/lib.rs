//! # solari-app
//!
//! Composition of the Solari components, and the `solari` command-line tool. The library
//! part holds what tests and benches call directly: the reference path tracer and image
//! output.

pub mod image_io;
pub mod metrics;
pub mod reference;
