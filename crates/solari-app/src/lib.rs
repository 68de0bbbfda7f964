//! # solari-app
//!
//! Composition of the Solari components, and the `solari` command-line tool. The library
//! part holds what tests and benches call directly: the reference path tracer and image
//! output.

pub mod image_io;
pub mod metrics;
pub mod realtime;
pub mod reference;

/// The README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
