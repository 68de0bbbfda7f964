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
