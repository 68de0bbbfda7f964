//! The bfloat16 pair codec (`packing::pack_bf16x2_unsigned`, `unpack_bf16x2`; ReSTIR DI's
//! shadow report) on lavapipe against its Rust twin, bit for bit: random positive values of
//! every exponent, values at and around the ties and the largest finite bfloat16, and the
//! values it must clamp (negative, NaN, infinity, f32::MAX).

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_scene::case_kernel::CaseKernel;
use solari_scene::gpu::test_gpu;
use solari_scene::packing::{BF16_MAX, pack_bf16x2_unsigned, unpack_bf16x2};

#[test]
fn bf16_pairs_match_the_rust_twin_bit_for_bit() {
    let Some(gpu) = test_gpu() else { return };
    let mut rng = Pcg32::seed_from_u64(3);
    let mut values: Vec<f32> = vec![
        0.0,
        -0.0,
        -1.0,
        f32::NAN,
        -f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::MAX,
        BF16_MAX,
        f32::MIN_POSITIVE,
        f32::from_bits(1),
        1.0,
        1.0 + 2f32.powi(-8),
        1.0 + 3.0 * 2f32.powi(-8),
        65504.0,
        1e-30,
        1e30,
    ];
    // Random bits: every exponent, both signs, NaNs among them.
    values.extend((0..20_000).map(|_| f32::from_bits(rng.random())));
    // Ties: a bfloat16 value plus half its step, and the values either side of it.
    values.extend((0..2_000).flat_map(|_| {
        let code: u32 = rng.random_range(0..0x7f7f);
        let tie = (code << 16) | 0x8000;
        [tie - 1, tie, tie + 1].map(f32::from_bits)
    }));
    let cases: Vec<[u32; 2]> = values
        .chunks(2)
        .map(|p| [p[0].to_bits(), p.get(1).unwrap_or(&0.5).to_bits()])
        .collect();
    let modules = vec![("packing", include_str!("../shaders/packing.wesl"))];
    let results: Vec<[u32; 4]> = CaseKernel::run_test_module(
        &gpu,
        modules,
        "packing_test",
        include_str!("shaders/packing_test.wesl"),
        0,
        &cases,
    )
    .expect("kernel");
    for (c, r) in cases.iter().zip(&results) {
        let pair = [f32::from_bits(c[0]), f32::from_bits(c[1])];
        let packed = pack_bf16x2_unsigned(pair);
        assert_eq!(
            r[0], packed,
            "{pair:?}: packed {:#x}, GPU {:#x}",
            packed, r[0]
        );
        let unpacked = unpack_bf16x2(c[0]).map(f32::to_bits);
        assert_eq!([r[1], r[2]], unpacked, "word {:#x} unpacked", c[0]);
    }
    println!("{} pairs agree", cases.len());
}
