//! Compact encodings shared by GPU buffers: octahedral unit vectors quantised to a chosen
//! number of bits. WGSL twin: `shaders/packing.wesl` (same arithmetic, including the rounding,
//! so CPU and GPU produce identical bits).

use glam::{Vec2, Vec3};

/// Octahedral encoding of a unit vector into [-1, 1]² (Cigolle et al. 2014, "A Survey of
/// Efficient Representations for Independent Unit Vectors"). Non-finite or zero input encodes
/// +z, so a bad normal cannot turn into NaN bits.
pub fn oct_encode(n: Vec3) -> Vec2 {
    let l1 = n.x.abs() + n.y.abs() + n.z.abs();
    if !(l1 > 0.0 && l1.is_finite()) {
        return Vec2::ZERO;
    }
    let p = Vec2::new(n.x, n.y) / l1;
    if n.z >= 0.0 {
        p
    } else {
        // Fold the lower hemisphere over the diagonals.
        (Vec2::ONE - Vec2::new(p.y.abs(), p.x.abs())) * sign_not_zero(p)
    }
}

/// Inverse of [`oct_encode`]; the result is unit length.
pub fn oct_decode(e: Vec2) -> Vec3 {
    let z = 1.0 - e.x.abs() - e.y.abs();
    let t = (-z).max(0.0);
    let xy = e - t * sign_not_zero(e);
    Vec3::new(xy.x, xy.y, z).normalize()
}

fn sign_not_zero(v: Vec2) -> Vec2 {
    Vec2::new(
        if v.x >= 0.0 { 1.0 } else { -1.0 },
        if v.y >= 0.0 { 1.0 } else { -1.0 },
    )
}

/// Quantises x in [-1, 1] to an unsigned `bits`-bit integer (round to nearest).
pub fn quantize_snorm(x: f32, bits: u32) -> u32 {
    let max = ((1u64 << bits) - 1) as f32;
    // floor(v + 0.5) rather than `round`: WGSL's round is ties-to-even, this is the same on both.
    ((x.clamp(-1.0, 1.0) * 0.5 + 0.5) * max + 0.5).floor() as u32
}

/// Inverse of [`quantize_snorm`].
pub fn dequantize_snorm(q: u32, bits: u32) -> f32 {
    let max = ((1u64 << bits) - 1) as f32;
    (q as f32 / max) * 2.0 - 1.0
}

/// A unit vector in `2 × bits` bits (bits ≤ 16): x in the low `bits`, y above it.
pub fn pack_unit_vector(n: Vec3, bits: u32) -> u32 {
    let e = oct_encode(n);
    quantize_snorm(e.x, bits) | (quantize_snorm(e.y, bits) << bits)
}

/// Inverse of [`pack_unit_vector`]; bits above `2 × bits` are ignored.
pub fn unpack_unit_vector(p: u32, bits: u32) -> Vec3 {
    let mask = (1u32 << bits) - 1;
    oct_decode(Vec2::new(
        dequantize_snorm(p & mask, bits),
        dequantize_snorm((p >> bits) & mask, bits),
    ))
}

/// Largest finite bfloat16 (bits `0x7f7f`).
pub const BF16_MAX: f32 = 3.389_531_4e38;

/// A non-negative value as bfloat16 bits (f32's exponent, 8 significant bits; rounded to
/// nearest, ties to even): relative error at most 2^-8. Negative values and NaN store 0;
/// values above [`BF16_MAX`], infinity included, store it. WGSL twin:
/// `encode_bf16_unsigned`.
pub fn encode_bf16_unsigned(x: f32) -> u32 {
    let v = if x > 0.0 { x.min(BF16_MAX) } else { 0.0 };
    let bits = v.to_bits();
    (bits + 0x7fff + ((bits >> 16) & 1)) >> 16
}

/// Two non-negative values in one word (`x` low, `y` high), as [`encode_bf16_unsigned`].
/// WGSL twin: `pack_bf16x2_unsigned`.
pub fn pack_bf16x2_unsigned(v: [f32; 2]) -> u32 {
    encode_bf16_unsigned(v[0]) | (encode_bf16_unsigned(v[1]) << 16)
}

/// The two values of a [`pack_bf16x2_unsigned`] word. WGSL twin: `unpack_bf16x2`.
pub fn unpack_bf16x2(p: u32) -> [f32; 2] {
    [f32::from_bits(p << 16), f32::from_bits(p & 0xffff_0000)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_vectors_survive_packing_within_the_quantisation_error() {
        let mut worst = [0.0f32; 2];
        let mut state = 1u32;
        let mut rand = || {
            state = state.wrapping_mul(747796405).wrapping_add(2891336453);
            (state >> 8) as f32 / 16777216.0
        };
        let mut dirs = vec![Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
        dirs.push(Vec3::new(1.0, 1.0, -1e-8).normalize());
        for _ in 0..20000 {
            let z = 2.0 * rand() - 1.0;
            let phi = std::f32::consts::TAU * rand();
            let r = (1.0 - z * z).max(0.0).sqrt();
            dirs.push(Vec3::new(r * phi.cos(), r * phi.sin(), z));
        }
        for n in dirs {
            for (i, bits) in [15u32, 16].into_iter().enumerate() {
                let back = unpack_unit_vector(pack_unit_vector(n, bits), bits);
                assert!((back.length() - 1.0).abs() < 1e-5);
                // atan2 of |cross| and dot: acos loses small angles in f32.
                worst[i] = worst[i].max(n.cross(back).length().atan2(n.dot(back)));
            }
        }
        // The grid spacing is 2/(2^bits - 1) in oct space; the worst angle error is about two
        // spacings (1.27e-4 rad at 15 bits, computed in f64).
        assert!(worst[0] < 1.4e-4, "15 bits: {}", worst[0]);
        assert!(worst[1] < 0.7e-4, "16 bits: {}", worst[1]);
    }

    #[test]
    fn bad_vectors_encode_as_plus_z() {
        for n in [Vec3::ZERO, Vec3::NAN, Vec3::new(f32::INFINITY, 0.0, 0.0)] {
            // Zero sits between two levels of an odd-sized grid: +z within one step.
            let back = unpack_unit_vector(pack_unit_vector(n, 16), 16);
            assert!(
                back.is_finite() && back.dot(Vec3::Z) > 1.0 - 1e-6,
                "{n} -> {back}"
            );
        }
    }

    #[test]
    fn bf16_pairs_round_to_nearest_and_clamp_what_they_cannot_hold() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg32::seed_from_u64(9);
        for _ in 0..100_000 {
            // Any positive finite f32 (random exponent and mantissa).
            let x = f32::from_bits(rng.random::<u32>() & 0x7f7f_ffff);
            let y = unpack_bf16x2(pack_bf16x2_unsigned([x, 1.0]))[0];
            if x >= f32::MIN_POSITIVE {
                assert!((y - x).abs() <= x * 2f32.powi(-8), "{x} -> {y}");
            }
            // The nearest: its neighbours in bfloat16 are no closer.
            let code = encode_bf16_unsigned(x);
            for n in [code.saturating_sub(1), code + 1] {
                let other = f32::from_bits(n << 16);
                assert!(
                    (other - x).abs() >= (y - x).abs(),
                    "{x}: {other} is closer than {y}"
                );
            }
        }
        for (x, want) in [
            (0.0, 0.0),
            (-0.0, 0.0),
            (-1.0, 0.0),
            (f32::NAN, 0.0),
            (f32::INFINITY, BF16_MAX),
            (f32::MAX, BF16_MAX),
            (1.0, 1.0),
            // A tie (halfway between 1 and its next bfloat16) goes to the even code, 1.
            (1.0 + 2f32.powi(-8), 1.0),
        ] {
            assert_eq!(
                unpack_bf16x2(pack_bf16x2_unsigned([x, x])),
                [want, want],
                "{x}"
            );
        }
    }
}
