//! The reservoir as stored between passes and frames.

use bytemuck::{Pod, Zeroable};
use solari_lights::LightSampleId;

/// WGSL twin: `Reservoir` in `restir_di.wesl` (20 bytes per pixel).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct GpuReservoir {
    /// The chosen light sample; `light == u32::MAX` for none.
    pub sample: LightSampleId,
    /// Candidates' worth of evidence behind the choice.
    pub confidence: f32,
    /// Unbiased contribution weight W.
    pub weight: f32,
}

const _: () = assert!(size_of::<GpuReservoir>() == 20);

/// Which words of a final [`GpuReservoir`] the non-finite detector checks: confidence and
/// weight, both finite and non-negative (the sample id is integers), and the confidence at
/// most `2 (confidence_cap + 1)` (an overflow otherwise): history is capped when read, the
/// initial candidate adds 1, and the spatial pass merges one neighbour holding as much.
pub fn reservoir_check(confidence_cap: f32) -> solari_scene::finite_check::RecordLayout {
    solari_scene::finite_check::RecordLayout {
        stride_words: 5,
        float_mask: 0b11000,
        non_negative_mask: 0b11000,
        upper_mask: 0b01000,
        // Merges add confidences in f32; allow their rounding.
        upper_bound: 2.0 * (confidence_cap + 1.0) * (1.0 + 1e-5),
    }
}
