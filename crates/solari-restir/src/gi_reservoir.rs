//! ReSTIR GI's reservoir as stored between passes and frames, and a CPU twin of its reuse
//! math (the reconnection Jacobian and the merge's weights), which the tests hold the GPU to.

use bytemuck::{Pod, Zeroable};

/// WGSL twin: `GiReservoir` in `restir_gi.wesl` (32 bytes per pixel).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct GpuGiReservoir {
    /// The sample point: where the pixel's GI ray hit a secondary surface.
    pub position: [f32; 3],
    /// Unbiased contribution weight W (0: no sample).
    pub weight: f32,
    /// Radiance leaving the sample point, as f16 bits: `(r | g << 16, b)`.
    pub radiance: [u32; 2],
    /// The sample point's normal, octahedral 16 + 16 bits.
    pub normal: u32,
    /// Samples' worth of evidence.
    pub confidence: f32,
}

const _: () = assert!(size_of::<GpuGiReservoir>() == 32);

/// Which words of a final [`GpuGiReservoir`] the non-finite detector checks: position and
/// weight finite, weight and confidence non-negative, and confidence at most
/// `2 (confidence_cap + 1)` (history capped when read, plus the new sample, plus one
/// neighbour holding as much).
pub fn gi_reservoir_check(confidence_cap: f32) -> solari_scene::finite_check::RecordLayout {
    solari_scene::finite_check::RecordLayout {
        stride_words: 8,
        float_mask: 0b1000_1111,
        non_negative_mask: 0b1000_1000,
        upper_mask: 0b1000_0000,
        upper_bound: 2.0 * (confidence_cap + 1.0) * (1.0 + 1e-5),
    }
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The reconnection Jacobian of ReSTIR GI (WGSL twin `reconnection_jacobian` in
/// `restir_gi_math.wesl`): moving a
/// sample point `sample` (unit normal `normal`) from the pixel at `from` to the pixel at
/// `to` multiplies its solid-angle density by
/// `(cos toward to / cos toward from) · (|from − s|² / |to − s|²)`. Zero where `to` is behind
/// the sample's surface or the value is not finite.
pub fn reconnection_jacobian(
    sample: [f32; 3],
    normal: [f32; 3],
    from: [f32; 3],
    to: [f32; 3],
) -> f32 {
    let a = sub(from, sample);
    let b = sub(to, sample);
    let (la, lb) = (dot(a, a), dot(b, b));
    let cos_from = dot(normal, a) / la.sqrt();
    let cos_to = dot(normal, b) / lb.sqrt();
    let j = (cos_to / cos_from) * (la / lb);
    // 3.4e38: the shaders' finiteness bound.
    if j > 0.0 && j < 3.4e38 { j } else { 0.0 }
}

/// Balance-heuristic weight of `f` against `g`, correct for infinite values: `solari-scene`'s
/// (the WGSL twin of `balance_heuristic` in its `brdf.wesl`), which both merges' twins use.
pub use solari_scene::brdf::balance_heuristic;

/// One side of a GI merge (WGSL twin `GiMergeSide` in `restir_gi_math.wesl`): a reservoir's confidence and weight, its sample's target
/// function at both pixels, and the Jacobian moving its sample to the other pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MergeSide {
    /// Confidence C.
    pub confidence: f32,
    /// Unbiased contribution weight W (0: no sample).
    pub weight: f32,
    /// Target function of this side's sample at its own pixel.
    pub target_here: f32,
    /// Target function of this side's sample at the other pixel.
    pub target_there: f32,
    /// Jacobian moving this side's sample from its pixel to the other.
    pub jacobian: f32,
}

/// Resampling weights of the canonical side `c` and the other side `o` in the canonical
/// pixel's measure (WGSL twin `gi_merge_weights`), or `None` where `o` is refused
/// because a Jacobian exceeds `bound` (the canonical reservoir is then kept unchanged).
/// `c.target_there` is c's sample at o's pixel; `o.target_there` is o's sample at c's.
pub fn merge_weights(c: MergeSide, o: MergeSide, bound: f32) -> Option<(f32, f32)> {
    let jc = if c.weight > 0.0 { c.jacobian } else { 0.0 };
    let jo = if o.weight > 0.0 { o.jacobian } else { 0.0 };
    if jc > bound || jo > bound {
        return None;
    }
    let mis_c = balance_heuristic(
        c.confidence * c.target_here,
        o.confidence * c.target_there * jc,
    );
    let mis_o = balance_heuristic(
        o.confidence * o.target_here,
        c.confidence * o.target_there * jo,
    );
    Some((
        mis_c * c.target_here * c.weight,
        mis_o * o.target_there * o.weight * jo,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobian_is_one_for_the_same_pixel_and_reciprocal_between_two() {
        let s = [0.3, -0.2, 1.0];
        let n = [0.0, 0.0, -1.0];
        let a = [0.1, 0.2, -1.5];
        let b = [-0.7, 0.4, -0.9];
        assert!((reconnection_jacobian(s, n, a, a) - 1.0).abs() < 1e-6);
        let ab = reconnection_jacobian(s, n, a, b);
        let ba = reconnection_jacobian(s, n, b, a);
        assert!((ab * ba - 1.0).abs() < 1e-5, "{ab} {ba}");
        // Behind the sample's surface: nothing to reuse.
        assert_eq!(reconnection_jacobian(s, n, a, [0.0, 0.0, 2.0]), 0.0);
    }

    #[test]
    fn a_lone_canonical_sample_keeps_its_whole_weight() {
        let c = MergeSide {
            confidence: 1.0,
            weight: 2.0,
            target_here: 0.5,
            target_there: 0.0,
            jacobian: 1.0,
        };
        let none = MergeSide {
            confidence: 0.0,
            weight: 0.0,
            target_here: 0.0,
            target_there: 0.0,
            jacobian: 0.0,
        };
        let (wc, wo) = merge_weights(c, none, 2.0).unwrap();
        assert_eq!((wc, wo), (1.0, 0.0));
    }
}
