//! # solari-renderer
//!
//! The composed real-time frame of the Solari workspace, for a game, a tool or a test that
//! wants the whole pipeline rather than single components: G-buffer → light tiles → world
//! cache upkeep → ReSTIR DI → GI (ReSTIR GI, plain path GI or cache-only) → denoiser, one frame per
//! [`RealtimeRenderer::render`] call, with a report of the passes that ran, their GPU times
//! and (optionally) the non-finite detector's counts per pass.

pub mod auto_quality;
pub mod gbuffer_choice;
pub mod light_change;
pub mod present;
pub mod quality;
pub mod realtime;

pub use auto_quality::{AutoChoice, CostModel, ErrorTable};
pub use gbuffer_choice::{GBufferChoice, GBufferTiming};
pub use present::Presenter;
pub use quality::{QualitySetting, QualityTier, Resolution};
pub use realtime::{
    Antialias, CameraPath, CameraRig, DI_REUSE_LIGHT_THRESHOLD, FINITE_SLOTS, FiniteCheck,
    FrameReport, FrameView, GiMode, PASS_NAMES, PATH_GI_SHADE_APART_TRIANGLES, PassRun,
    RealtimeRenderer, RealtimeSettings,
};
pub use solari_scene::gbuffer::GBufferProducer;

/// The README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
