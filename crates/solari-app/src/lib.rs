//! # solari-app
//!
//! Composition of the Solari components, and the `solari` command-line tool. The library
//! part holds what tests, benches and the fuzz harness call directly: the reference path
//! tracer, the real-time renderer, image input and output, and the command line's parsing
//! and up-front checks.

pub mod cli;
pub mod cli_values;
pub mod image_io;
pub mod metrics;
pub mod output;
pub mod realtime;
pub mod reference;

/// The README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
