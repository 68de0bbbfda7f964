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

/// One side of a ReSTIR DI merge (WGSL twin `DiMergeSide` in `restir_di_math.wesl`): a
/// reservoir's confidence and unbiased contribution weight, and its sample's target function
/// at its own pixel and at the other pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiMergeSide {
    /// Candidates' worth of evidence.
    pub confidence: f32,
    /// Unbiased contribution weight W; 0 where the reservoir holds no valid sample.
    pub weight: f32,
    /// The sample's target at this side's own pixel.
    pub target_here: f32,
    /// The sample's target at the other pixel (0 where it lies outside that pixel's domain,
    /// such as a light that appeared since the other reservoir was made).
    pub target_there: f32,
}

/// The resampling weights `(w_c, w_o)` of a merge of the canonical side `c` with `o`, both in
/// the canonical pixel's terms (WGSL twin `di_merge_weights`): generalised balance-heuristic
/// MIS over the two pixels' confidence-weighted targets, times the sample's target at the
/// canonical pixel, times its W. An empty side (W not positive) weighs exactly 0.
///
/// The two MIS weights a sample gets over the two domains sum to 1 (where its targets are
/// finite and not both zero), which is what keeps the merge unbiased.
pub fn di_merge_weights(c: DiMergeSide, o: DiMergeSide) -> (f32, f32) {
    use solari_scene::brdf::balance_heuristic;
    let mis_c = balance_heuristic(c.confidence * c.target_here, o.confidence * c.target_there);
    let mis_o = balance_heuristic(o.confidence * o.target_here, c.confidence * o.target_there);
    let w_c = if c.weight > 0.0 {
        mis_c * c.target_here * c.weight
    } else {
        0.0
    };
    let w_o = if o.weight > 0.0 {
        mis_o * o.target_there * o.weight
    } else {
        0.0
    };
    (w_c, w_o)
}

/// Which sample a merge keeps (WGSL twin `di_merge_pick`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiPick {
    /// The canonical side's sample.
    Canonical,
    /// The other side's sample.
    Other,
}

/// The pick of a merge with weights `w` for a random `u` in [0, 1): `o`'s sample with
/// probability `w_o / (w_c + w_o)`, and its W, `(w_c + w_o) / ` the picked sample's target at
/// the canonical pixel (`c_target` or `o_target`). `None` where the sum of the weights is not
/// positive and finite (the GPU then draws no random number) or the W is not.
pub fn di_merge_pick(w: (f32, f32), c_target: f32, o_target: f32, u: f32) -> Option<(DiPick, f32)> {
    let sum = w.0 + w.1;
    if !(sum > 0.0 && sum < 3.4e38) {
        return None;
    }
    let (pick, target) = if u * sum < w.1 {
        (DiPick::Other, o_target)
    } else {
        (DiPick::Canonical, c_target)
    };
    let weight = sum / target;
    (weight > 0.0 && weight < 3.4e38).then_some((pick, weight))
}

/// The apparent angular radius of a light from a shading point, for the penumbra a blocker
/// casts (WGSL twin `light_angular_radius_of` in `restir_di_math.wesl`): `kind` is the light
/// record's kind (0 emissive: its whole `area` seen with the sample's `g`, cos / d²; 1
/// directional: `area` is the disk's solid angle; 2 point: `area` = 4π r², over the sample's
/// `distance`; anything else, the sky: a right angle). 0 for delta lights (`area` 0); at most
/// π/2.
pub fn light_angular_radius(kind: u32, area: f32, g: f32, distance: f32) -> f32 {
    use std::f32::consts::{FRAC_PI_2, PI};
    let solid_angle = match kind {
        0 => area * g,
        1 => area,
        2 => {
            let r = (area.max(0.0) / (4.0 * PI)).sqrt();
            return (r / distance.max(r)).clamp(0.0, 1.0).asin();
        }
        _ => return FRAC_PI_2,
    };
    (solid_angle.max(0.0) / PI).sqrt().min(FRAC_PI_2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn side(confidence: f32, weight: f32, here: f32, there: f32) -> DiMergeSide {
        DiMergeSide {
            confidence,
            weight,
            target_here: here,
            target_there: there,
        }
    }

    /// A sample's MIS weights over the two domains sum to 1: c's sample weighs
    /// m_c = c.conf t_c(c) / (c.conf t_c(c) + o.conf t_c(o)) at the canonical pixel, and the
    /// same sample seen as o's would weigh o.conf t_c(o) / (same sum).
    #[test]
    fn mis_weights_partition_unity() {
        let (c, o) = (side(3.0, 1.0, 0.7, 0.2), side(5.0, 1.0, 0.4, 0.9));
        let (w_c, _) = di_merge_weights(c, o);
        let mis_c = w_c / (c.target_here * c.weight);
        let swapped = side(5.0, 1.0, 0.2, 0.7);
        let (_, w_o) = di_merge_weights(side(3.0, 1.0, 0.0, 0.0), swapped);
        let mis_as_o = w_o / (0.7 * swapped.weight);
        assert!(
            (mis_c + mis_as_o - 1.0).abs() < 1e-6,
            "{mis_c} + {mis_as_o}"
        );
    }

    /// The expected contribution of the pick, target × W over the pick's distribution, is
    /// the sum of the weights: the merged reservoir estimates what both did.
    #[test]
    fn the_pick_keeps_the_sum_in_expectation() {
        let w = di_merge_weights(side(2.0, 0.8, 0.5, 0.3), side(1.0, 1.3, 0.6, 0.9));
        let (targets, n) = ((0.5f32, 0.9f32), 100_000);
        let mean = (0..n)
            .map(|i| {
                let u = (i as f32 + 0.5) / n as f32;
                let (pick, weight) = di_merge_pick(w, targets.0, targets.1, u).unwrap();
                let t = if pick == DiPick::Other {
                    targets.1
                } else {
                    targets.0
                };
                (t * weight) as f64
            })
            .sum::<f64>()
            / n as f64;
        assert!(
            (mean / (w.0 + w.1) as f64 - 1.0).abs() < 1e-4,
            "{mean} vs {:?}",
            w
        );
    }

    #[test]
    fn empty_or_unusable_sides_give_no_pick() {
        let empty = side(4.0, 0.0, f32::INFINITY, f32::NAN);
        assert_eq!(di_merge_weights(empty, empty), (0.0, 0.0));
        assert_eq!(di_merge_pick((0.0, 0.0), 1.0, 1.0, 0.5), None);
        assert_eq!(di_merge_pick((f32::MAX, f32::MAX), 1.0, 1.0, 0.5), None);
        // A picked sample whose target is 0 has no finite W.
        assert_eq!(di_merge_pick((0.0, 1.0), 1.0, 0.0, 0.5), None);
    }
}
