//! The fallback denoiser's history as stored (`shaders/denoise_history.wesl`, whose twin this
//! is): 24 bytes a pixel instead of the 48 of its twelve `f32`s.
//!
//! Every value but the length is non-negative, so each is an unsigned float of our own with 7
//! exponent bits, covering 2⁻⁶²..2⁶⁵ (scenes in physical light units and absurdly dim or bright
//! lights all fit, where f16 stops at 65,504; with 6 exponent bits, 2⁻³⁰..2³³, a light of
//! 10⁻¹² left the means so coarse that the stale-history test misfired and biased the output
//! by 2.4%), and as many mantissa bits as the value needs:
//!
//! | values | mantissa bits | step (of the value) |
//! |---|---|---|
//! | colour (the output) | 14 ([`COLOR_BITS`]) | 2⁻¹⁴..2⁻¹⁵ |
//! | mean, fast and long mean luminance (the stale-history test compares them against a ±10% band) | 9 ([`MEAN_BITS`]) | 2⁻⁹..2⁻¹⁰ |
//! | luminance deviation, firefly carry, calm deviation | 5 ([`DETAIL_BITS`]) | 2⁻⁵..2⁻⁶ |
//!
//! Below 2⁻⁶² the codes step linearly by 2^−(62 + mantissa bits); above the largest code
//! (2⁶⁵ less one step) values are clamped to it: the denoiser's demodulated light saturates at
//! 3.7·10¹⁹. Zero, negative and NaN values store 0.
//!
//! Each value is rounded stochastically: up with a probability equal to its fraction of the
//! step. Rounded to nearest, an exponential average whose step is below half a code would
//! stall (f16 with 32 frames of history stops 1.6% short of its target); rounded
//! stochastically it is right on average, at the price of noise of less than one step per
//! frame. The second moment is stored as a deviation, so the variance does not vanish into the
//! rounding of the mean. The history length is an f16, exact for whole frames up to 2048
//! ([`crate::settings::MAX_HISTORY_LIMIT`]).

use crate::fallback::GpuHistory;
use bytemuck::{Pod, Zeroable};
use solari_scene::rng::Rng;

/// One pixel's history as the GPU stores it (WGSL `PackedHistory`), bits low to high: `color`
/// r, g, b (21 bits each, one spare); `stats` length (f16), mean, fast mean, long mean (16
/// each); `detail` deviation, carry r, g, b, calm deviation (12 each, four spare).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct PackedHistory {
    /// Colour.
    pub color: [u32; 2],
    /// History length and the means.
    pub stats: [u32; 2],
    /// Deviation, firefly carry and calm deviation.
    pub detail: [u32; 2],
}

const _: () = assert!(size_of::<PackedHistory>() == 24);

/// Mantissa bits of the colour.
pub const COLOR_BITS: u32 = 14;
/// Mantissa bits of the mean, fast and long mean luminance.
pub const MEAN_BITS: u32 = 9;
/// Mantissa bits of the deviation, the carry and the calm deviation.
pub const DETAIL_BITS: u32 = 5;

/// The largest code with `mantissa` bits (about 3.7·10¹⁹).
pub fn code_max(mantissa: u32) -> u32 {
    (1 << (7 + mantissa)) - 1
}

/// `v` as a code with `mantissa` bits (1..=23) above 7 exponent bits, rounded up with the
/// probability of its fraction of the step, drawn from the top `23 − mantissa` bits of
/// `random`. Zero, negative and NaN values give 0; values above the largest code give
/// [`code_max`].
pub fn encode_unsigned(v: f32, mantissa: u32, random: u32) -> u32 {
    let dropped = 23 - mantissa;
    let dither = random >> (32 - dropped);
    let bits = v.to_bits();
    if bits == 0 || bits > 0x7f80_0000 {
        return 0;
    }
    if bits < 0x2080_0000 {
        // Below 2⁻⁶²: linear codes, as f16's subnormals.
        let scale = f32::from_bits((189 + mantissa) << 23);
        let fraction = dither as f32 * f32::from_bits((127 - dropped) << 23);
        return ((v * scale + fraction) as u32).min(1 << mantissa);
    }
    // The dither carries into the kept mantissa bits with exactly the dropped bits'
    // probability (and into the exponent at the end of a binade).
    let rounded = bits + dither;
    let exponent = rounded >> 23;
    if exponent >= 192 {
        return code_max(mantissa);
    }
    ((exponent - 64) << mantissa) | ((rounded >> dropped) & ((1 << mantissa) - 1))
}

/// The value of a code with `mantissa` bits (exact: every code is an `f32`).
pub fn decode_unsigned(code: u32, mantissa: u32) -> f32 {
    let exponent = code >> mantissa;
    if exponent == 0 {
        return code as f32 * f32::from_bits((65 - mantissa) << 23);
    }
    let fraction = code & ((1 << mantissa) - 1);
    f32::from_bits(((exponent + 64) << 23) | (fraction << (23 - mantissa)))
}

/// `h` stored as the temporal pass stores it (WGSL `pack_history`), drawing each value's
/// rounding from `rng` in the shader's order: colour r, g, b, then mean, fast, long, then
/// deviation, carry r, g, b, calm deviation. The length must be a whole number of frames.
pub fn pack(h: &GpuHistory, rng: &mut Rng) -> PackedHistory {
    let mut draw = |v: f32, mantissa| encode_unsigned(v, mantissa, rng.next_u32());
    let [r, g, b] = [h.color[0], h.color[1], h.color[2]].map(|c| draw(c, COLOR_BITS));
    let length = half::f16::from_f32(h.color[3]).to_bits() as u32;
    let [mean, fast, long] = [h.moments[0], h.moments[2], h.moments[3]].map(|m| draw(m, MEAN_BITS));
    let deviation = (h.moments[1] - h.moments[0] * h.moments[0]).max(0.0).sqrt();
    let [deviation, carry_r, carry_g, carry_b, calm] =
        [deviation, h.carry[0], h.carry[1], h.carry[2], h.carry[3]].map(|v| draw(v, DETAIL_BITS));
    PackedHistory {
        color: [r | (g << 21), (g >> 11) | (b << 10)],
        stats: [length | (mean << 16), fast | (long << 16)],
        detail: [
            deviation | (carry_r << 12) | (carry_g << 24),
            (carry_g >> 8) | (carry_b << 4) | (calm << 16),
        ],
    }
}

/// The history as the passes read it: the codes decoded and the second moment rebuilt as
/// mean² + deviation² (WGSL `unpack_history`).
pub fn unpack(p: &PackedHistory) -> GpuHistory {
    let [c0, c1] = p.color;
    let [s0, s1] = p.stats;
    let [d0, d1] = p.detail;
    let color = [
        c0 & 0x1f_ffff,
        (c0 >> 21) | ((c1 & 0x3ff) << 11),
        (c1 >> 10) & 0x1f_ffff,
    ]
    .map(|c| decode_unsigned(c, COLOR_BITS));
    let length = half::f16::from_bits(s0 as u16).to_f32();
    let [mean, fast, long] =
        [s0 >> 16, s1 & 0xffff, s1 >> 16].map(|c| decode_unsigned(c, MEAN_BITS));
    let [deviation, r, g, b, calm] = [
        d0 & 0xfff,
        (d0 >> 12) & 0xfff,
        (d0 >> 24) | ((d1 & 0xf) << 8),
        (d1 >> 4) & 0xfff,
        (d1 >> 16) & 0xfff,
    ]
    .map(|c| decode_unsigned(c, DETAIL_BITS));
    GpuHistory {
        color: [color[0], color[1], color[2], length],
        moments: [mean, mean * mean + deviation * deviation, fast, long],
        carry: [r, g, b, calm],
    }
}

/// The step between `v`'s code with `mantissa` bits and the next one up: how far one
/// stochastic rounding can move it.
pub fn code_step(v: f32, mantissa: u32) -> f32 {
    let code = encode_unsigned(v, mantissa, 0);
    if code == code_max(mantissa) {
        return 0.0;
    }
    decode_unsigned(code + 1, mantissa) - decode_unsigned(code, mantissa)
}

#[cfg(test)]
mod tests {
    use super::*;

    const WIDTHS: [u32; 3] = [COLOR_BITS, MEAN_BITS, DETAIL_BITS];

    #[test]
    fn codes_are_monotonic_and_exact() {
        for m in WIDTHS {
            let mut last = -1.0;
            for code in 0..=code_max(m) {
                let v = decode_unsigned(code, m);
                assert!(v > last, "{m} bits, code {code}: {v} after {last}");
                last = v;
                // A value that is a code rounds to itself whatever the dither.
                for random in [0, 1 << 31, u32::MAX] {
                    assert_eq!(encode_unsigned(v, m, random), code, "{v} ({m} bits)");
                }
            }
            assert_eq!(decode_unsigned(1 << m, m), 2f32.powi(-62));
            assert_eq!(
                decode_unsigned(code_max(m), m),
                2f32.powi(65) - 2f32.powi(64 - m as i32)
            );
        }
    }

    #[test]
    fn rounding_is_stochastic_and_unbiased() {
        for m in WIDTHS {
            let draws = 1u32 << (23 - m);
            for v in [0.3f32, 1.0 + 1e-4, 7.77e7, 1e-12, 3.1e-20, 1.3e-38] {
                let mean: f64 = (0..draws)
                    .map(|d| decode_unsigned(encode_unsigned(v, m, d << (32 - (23 - m))), m) as f64)
                    .sum::<f64>()
                    / draws as f64;
                // Exact to the dither's resolution (below 2⁻³⁰, where the value has more
                // bits than the dither, its mean is off by up to that much).
                let tolerance = 2.0 * code_step(v, m) as f64 / draws as f64;
                assert!(
                    (mean - v as f64).abs() <= tolerance + 1e-45,
                    "{v} ({m} bits): mean {mean}"
                );
            }
        }
    }

    #[test]
    fn out_of_range_values_are_clamped() {
        for m in WIDTHS {
            for v in [0.0, -0.0, -1.0, f32::NAN, -f32::NAN, f32::NEG_INFINITY] {
                assert_eq!(encode_unsigned(v, m, u32::MAX), 0, "{v}");
            }
            for v in [3.7e19, 1e20, f32::MAX, f32::INFINITY] {
                assert_eq!(encode_unsigned(v, m, 0), code_max(m), "{v}");
            }
        }
    }
}
