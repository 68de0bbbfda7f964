//! # solari-app
//!
//! The `solari` command-line tool. The library part holds what its tests and the fuzz
//! harness call directly: the command line's parsing and up-front checks, atomic image
//! output, the viewer's fly camera, and `--quality auto`'s choice. The renderer is `solari-renderer`; the reference path tracer, metrics and image
//! I/O are `solari-reference`.

pub mod cli;
pub mod cli_values;
pub mod fly_camera;
pub mod output;
pub mod quality_choice;

/// The README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
