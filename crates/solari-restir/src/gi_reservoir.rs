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
    /// Radiance leaving the sample point, as f16 bits: `(r | g << 16, b | cap << 16)`, where
    /// cap is the most confidence a history holding the sample may bring
    /// (`RestirGiSettings::adaptive_cap`).
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

/// [`crate::SpatialVisibility::Chosen`]'s merge (WGSL twin `gi_chosen_sum`): the merge chose
/// side `o` (`pick_o`) or `c` with [`merge_weights`], which assume each pixel sees both
/// samples, and the chosen sample's ray found it visible from the other pixel (`seen`) or
/// not. Returns the sum the chosen sample's W is made of (W = sum / its target at `c`'s
/// pixel): the weights' sum times the chosen side's weight with the visibility found over
/// its assumed weight; 0 where `o`'s sample is chosen and hidden; `None` where the merge is
/// refused. Over the choice, each side then gets its weight with true visibility on average
/// (the tests below check that identity), which is what keeps the one-ray merge unbiased.
pub fn chosen_weight_sum(
    c: MergeSide,
    o: MergeSide,
    bound: f32,
    pick_o: bool,
    seen: bool,
) -> Option<f32> {
    let (wc, wo) = merge_weights(c, o, bound)?;
    let sum = wc + wo;
    Some(match (pick_o, seen) {
        (true, false) => 0.0,
        (true, true) | (false, true) => sum,
        (false, false) => {
            let hidden = MergeSide {
                target_there: 0.0,
                ..c
            };
            let (true_wc, _) = merge_weights(hidden, o, bound)?;
            sum * (true_wc / wc)
        }
    })
}

/// The light of a merge with resampling weights `weights` (w_c, w_o) shaded over its choice
/// ([`crate::RestirGiSettings::shade_both_samples`]; WGSL twin `gi_expected_light`):
/// Σ w_i · f(y_i) / p̂(y_i), where `c` and `o` hold each sample's diffuse contribution f and
/// target p̂ at the canonical pixel. The chosen sample's light is f(y) · Σw / p̂(y) and it is
/// chosen with chance w_y / Σw, so this is that light's expectation over the choice (the
/// tests below check the identity); a sample with no weight or no target adds nothing.
pub fn expected_light(weights: (f32, f32), c: ([f32; 3], f32), o: ([f32; 3], f32)) -> [f32; 3] {
    let weighted = |w: f32, (f, target): ([f32; 3], f32)| {
        let scale = w / target;
        if w > 0.0 && scale > 0.0 && scale < 3.4e38 {
            f.map(|x| x * scale)
        } else {
            [0.0; 3]
        }
    };
    let (a, b) = (weighted(weights.0, c), weighted(weights.1, o));
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_expected_light_is_the_chosen_samples_light_averaged_over_the_choice() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg32::seed_from_u64(7);
        for _ in 0..200 {
            let draw = |rng: &mut rand_pcg::Pcg32| {
                let f = [0, 1, 2].map(|_| rng.random_range(0.0..3.0f32));
                // The target is the luminance of a larger BRDF than the diffuse part shaded.
                let target = 0.2126 * f[0] + 0.7152 * f[1] + 0.0722 * f[2];
                (f, target * rng.random_range(1.0..2.0))
            };
            let (c, o) = (draw(&mut rng), draw(&mut rng));
            let w = (rng.random_range(0.0..5.0f32), rng.random_range(0.0..5.0f32));
            let sum = w.0 + w.1;
            // The merge as the spatial pass runs it: o where u·Σw < w_o, else c, and the
            // chosen sample shaded as f(y) · W with W = Σw / p̂(y). Its mean over many picks
            // must be the expected light, within five standard errors.
            let picks = 20_000;
            let (mut mean, mut square) = ([0.0f64; 3], [0.0f64; 3]);
            for _ in 0..picks {
                let (f, target) = if rng.random::<f32>() * sum < w.1 {
                    o
                } else {
                    c
                };
                for k in 0..3 {
                    let light = (f[k] * (sum / target)) as f64;
                    mean[k] += light / picks as f64;
                    square[k] += light * light / picks as f64;
                }
            }
            let want = expected_light(w, c, o);
            for k in 0..3 {
                let error = ((square[k] - mean[k] * mean[k]).max(0.0) / picks as f64).sqrt();
                assert!(
                    (mean[k] - want[k] as f64).abs() <= 5.0 * error + 1e-5,
                    "channel {k}: picks {} against {want:?} (standard error {error})",
                    mean[k]
                );
            }
        }
        // No weight, no light; a zero target adds nothing rather than a NaN.
        assert_eq!(
            expected_light((0.0, 0.0), ([1.0; 3], 1.0), ([1.0; 3], 1.0)),
            [0.0; 3]
        );
        assert_eq!(
            expected_light((1.0, 0.0), ([1.0; 3], 0.0), ([1.0; 3], 1.0)),
            [0.0; 3]
        );
    }

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

    /// The identity behind the one-ray merge: the expected weight each side gets over the
    /// choice (chosen with probability w / sum, then given `chosen_weight_sum`) is its
    /// weight in the two-ray merge, which knows both visibilities before choosing (a hidden
    /// `o` sample there has no weight; a `c` sample hidden from `o`'s pixel loses `o` from
    /// its MIS weight). Random sides, all four visibility cases.
    #[test]
    fn the_chosen_merge_gives_each_side_its_two_ray_weight_on_average() {
        let mut state = 0x9e3779b97f4a7c15u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 40) as f32) / (1u64 << 24) as f32
        };
        let mut checked = 0;
        for _ in 0..20_000 {
            let mut side = |weight_zero: bool| MergeSide {
                confidence: 0.5 + 10.0 * next(),
                weight: if weight_zero { 0.0 } else { 4.0 * next() },
                target_here: 3.0 * next(),
                target_there: if next() < 0.1 { 0.0 } else { 3.0 * next() },
                jacobian: 2.5 * next(),
            };
            let c = side(false);
            let o_empty = c.confidence < 1.5;
            let o = side(o_empty);
            let bound = 2.0;
            let Some((wc, wo)) = merge_weights(c, o, bound) else {
                assert_eq!(chosen_weight_sum(c, o, bound, false, true), None);
                continue;
            };
            let sum = wc + wo;
            if sum.is_nan() || sum <= 0.0 {
                continue;
            }
            for (c_seen, o_seen) in [(true, true), (true, false), (false, true), (false, false)] {
                // The two-ray merge's weights with these visibilities.
                let c_true = MergeSide {
                    target_there: if c_seen { c.target_there } else { 0.0 },
                    ..c
                };
                let o_true = if o_seen {
                    o
                } else {
                    MergeSide {
                        weight: 0.0,
                        target_here: 0.0,
                        target_there: 0.0,
                        jacobian: 0.0,
                        ..o
                    }
                };
                let (true_wc, true_wo) = merge_weights(c_true, o_true, bound).unwrap();
                let expected_c = wc / sum * chosen_weight_sum(c, o, bound, false, c_seen).unwrap();
                let expected_o = wo / sum * chosen_weight_sum(c, o, bound, true, o_seen).unwrap();
                let near = |a: f32, b: f32| (a - b).abs() <= 1e-5 * a.abs().max(b.abs()).max(1e-20);
                assert!(
                    near(expected_c, true_wc),
                    "c: {expected_c} vs {true_wc} ({c:?}, {o:?}, seen {c_seen})"
                );
                assert!(
                    near(expected_o, true_wo),
                    "o: {expected_o} vs {true_wo} ({c:?}, {o:?}, seen {o_seen})"
                );
                checked += 1;
            }
        }
        assert!(checked > 40_000, "only {checked} cases merged");
    }
}
