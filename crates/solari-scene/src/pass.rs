//! The shape every Solari pass shares, so passes compose without glue:
//!
//! - `new(gpu, …, settings)` builds pipelines and buffers, validating the settings;
//! - `prepare(gpu, &FrameContext, …)` does the frame's CPU work (uniform uploads);
//! - `encode(encoder, &FrameContext, …) -> Result<Ran, GpuError>` records the dispatches and
//!   says which ran (a pass may skip work the scene does not need), each dispatch in a
//!   profiler scope named by its label when the context carries a profiler.
//!
//! Labels: every GPU object is labelled `<crate>/<name>` (`solari_restir/di`), and every
//! dispatch and profiler scope by the pass's name alone (`di_initial_temporal`), which is
//! also the name reports and CSV columns use; each crate lists its names in `PASS_LABELS`.
//!
//! Bindings: a pass declares its bind groups of buffers as [`crate::bindings::BufferGroup`]
//! constants by WGSL name (`DI_BINDINGS`, `CACHE_BINDINGS`, …) and binds buffers by those
//! names; each crate's shader tests check the names and access modes against the composed
//! shaders ([`crate::bindings::check_groups`]). Groups that mix textures (the scene, the
//! G-buffer reader) list their names beside their layout instead
//! ([`crate::gbuffer_input::READER_BINDINGS`]).

use crate::gpu_types::GpuView;
use crate::model::Camera;
use wgpu_profiler::GpuProfiler;

/// What every pass of one frame shares: the frame index, the render size, this frame's and
/// last frame's view, and the profiler.
#[derive(Clone, Copy)]
pub struct FrameContext<'a> {
    /// Frame index: seeds random numbers and alternates history buffers.
    pub index: u32,
    /// Render size in pixels.
    pub size: (u32, u32),
    /// This frame's view at `size`.
    pub view: GpuView,
    /// Last frame's view (this frame's when there is none).
    pub previous_view: GpuView,
    /// Per-pass GPU timing, when on.
    pub profiler: Option<&'a GpuProfiler>,
}

impl<'a> FrameContext<'a> {
    /// Frame `index` of `size` seen from `camera`, after `previous` (None on the first frame
    /// or after a cut); no profiler.
    pub fn new(index: u32, size: (u32, u32), camera: &Camera, previous: Option<&Camera>) -> Self {
        let view_of = |c: &Camera| GpuView {
            frame: index,
            ..GpuView::new(c, size.0, size.1)
        };
        let view = view_of(camera);
        Self {
            index,
            size,
            view,
            previous_view: previous.map_or(view, view_of),
            profiler: None,
        }
    }

    /// The same frame, timed by `profiler`.
    pub fn with_profiler(self, profiler: Option<&'a GpuProfiler>) -> Self {
        Self { profiler, ..self }
    }

    /// The camera position this frame.
    pub fn eye(&self) -> [f32; 3] {
        self.view.origin
    }

    /// Records `f` in a profiler scope named `label` when the frame is timed, and marks
    /// `label` in `ran`.
    pub fn scope<R>(
        &self,
        label: &'static str,
        encoder: &mut wgpu::CommandEncoder,
        ran: &mut Ran,
        f: impl FnOnce(&mut wgpu::CommandEncoder) -> R,
    ) -> R {
        ran.mark(label);
        crate::gpu::in_scope(self.profiler, label, encoder, f)
    }
}

/// Most labels one `Ran` holds (the largest pass, the world cache's upkeep, has four).
pub const MAX_RAN: usize = 16;

/// The dispatches one `encode` recorded, by label (a pass's `PASS_LABELS`), in order. A
/// fixed array, so the frame loop allocates nothing to report what ran.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Ran {
    labels: [&'static str; MAX_RAN],
    len: usize,
}

impl Ran {
    /// Nothing ran.
    pub fn none() -> Self {
        Self::default()
    }

    /// Marks `label` as run (once).
    ///
    /// # Panics
    /// Past [`MAX_RAN`] distinct labels: a pass with that many dispatches is a bug here.
    pub fn mark(&mut self, label: &'static str) {
        if self.contains(label) {
            return;
        }
        assert!(self.len < MAX_RAN, "more than {MAX_RAN} passes in one Ran");
        self.labels[self.len] = label;
        self.len += 1;
    }

    /// Whether `label` ran.
    pub fn contains(&self, label: &str) -> bool {
        self.labels().contains(&label)
    }

    /// Whether nothing ran.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The labels that ran, in order.
    pub fn labels(&self) -> &[&'static str] {
        &self.labels[..self.len]
    }

    /// Adds what `other` ran.
    pub fn extend(&mut self, other: Ran) {
        for label in other.labels() {
            self.mark(label);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Ran;

    #[test]
    fn ran_keeps_labels_once_in_order() {
        let mut a = Ran::none();
        assert!(a.is_empty());
        a.mark("x");
        a.mark("y");
        a.mark("x");
        let mut b = Ran::none();
        b.mark("z");
        b.mark("y");
        a.extend(b);
        assert_eq!(a.labels(), ["x", "y", "z"]);
        assert!(a.contains("z") && !a.contains("w"));
    }
}
