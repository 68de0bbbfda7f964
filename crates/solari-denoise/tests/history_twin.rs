//! The history codec (`denoise_history.wesl`) against its Rust twin
//! (`solari_denoise::history`) on lavapipe, bit for bit, at each of its three widths: every
//! code of the two narrower widths and every 16th of the colour's decoded, values spread over
//! every magnitude with random dithers (and the adversarial ones: zero, negative zero, NaN,
//! infinities, the edges of the linear range and of the largest code), random packed
//! histories unpacked, and random histories packed with the shader's random draws.

use bytemuck::{Pod, Zeroable};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_denoise::GpuHistory;
use solari_denoise::history::{
    COLOR_BITS, DETAIL_BITS, MEAN_BITS, PackedHistory, code_max, decode_unsigned, encode_unsigned,
    pack, unpack,
};
use solari_scene::case_kernel::CaseKernel;
use solari_scene::gpu::test_gpu;
use solari_scene::rng::Rng as ShaderRng;

/// WGSL twin: `Case` in `shaders/denoise_history_test.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Case {
    value: [u32; 4],
    packed: PackedHistory,
    seed: [u32; 2],
    history: GpuHistory,
}

/// WGSL twin: `Outcome`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Outcome {
    codes: [u32; 4],
    color: [f32; 4],
    moments: [f32; 4],
    carry: [f32; 4],
    packed: PackedHistory,
    pad: [u32; 2],
}

fn value(rng: &mut Pcg32, k: u32) -> f32 {
    const EDGES: [f32; 12] = [
        0.0,
        -0.0,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        -1.0,
        2.168_404_3e-19, // 2⁻⁶², the first exponent code
        2.168_404e-19,
        3.689_123e19, // near the largest code
        3.7e19,
        f32::MAX,
        1e-38,
    ];
    match k % 4 {
        0 => EDGES[rng.random_range(0..EDGES.len())],
        _ => 10f32.powf(rng.random_range(-25.0..21.0)),
    }
}

#[test]
fn history_codec_matches_its_rust_twin() {
    let Some(gpu) = test_gpu() else { return };
    let mut rng = Pcg32::seed_from_u64(24);
    let widths = [COLOR_BITS, MEAN_BITS, DETAIL_BITS];
    // Every code of the 16- and 12-bit widths, every 16th of the 21-bit one, then random ones.
    let codes: Vec<(u32, u32)> = widths
        .iter()
        .flat_map(|&m| {
            let stride = if m == COLOR_BITS { 16 } else { 1 };
            (0..=code_max(m)).step_by(stride).map(move |c| (c, m))
        })
        .collect();
    let cases: Vec<Case> = (0..codes.len().max(1 << 18) as u32)
        .map(|k| {
            let mut packed = PackedHistory::default();
            for w in packed
                .color
                .iter_mut()
                .chain(&mut packed.stats)
                .chain(&mut packed.detail)
            {
                *w = rng.random();
            }
            // The length is a whole number of frames.
            packed.stats[0] = (packed.stats[0] & 0xffff_0000)
                | half::f16::from_f32(rng.random_range(0..2049) as f32).to_bits() as u32;
            let (code, m) = codes.get(k as usize).copied().unwrap_or_else(|| {
                let m = widths[k as usize % 3];
                (rng.random_range(0..=code_max(m)), m)
            });
            // A history to pack: every value of any magnitude (the adversarial ones too), the
            // mean of squares below the squared mean now and then, a whole length.
            let any = |rng: &mut Pcg32| {
                let k = rng.random_range(0..4);
                value(rng, k)
            };
            let mean = any(&mut rng);
            let history = GpuHistory {
                color: [
                    any(&mut rng),
                    any(&mut rng),
                    any(&mut rng),
                    rng.random_range(0..2049) as f32,
                ],
                moments: [
                    mean,
                    mean * mean * rng.random_range(0.5..3.0f32),
                    any(&mut rng),
                    any(&mut rng),
                ],
                carry: [any(&mut rng), any(&mut rng), any(&mut rng), any(&mut rng)],
            };
            Case {
                value: [value(&mut rng, k).to_bits(), rng.random(), code, m],
                packed,
                seed: [rng.random(), 0],
                history,
            }
        })
        .collect();
    let results: Vec<Outcome> = CaseKernel::run_test_module(
        &gpu,
        solari_denoise::modules(),
        "denoise_history_test",
        include_str!("../shaders/denoise_history_test.wesl"),
        0,
        &cases,
    )
    .expect("dispatch");
    for (c, r) in cases.iter().zip(&results) {
        let (v, random, code, m) = (
            f32::from_bits(c.value[0]),
            c.value[1],
            c.value[2],
            c.value[3],
        );
        assert_eq!(
            r.codes[0],
            encode_unsigned(v, m, random),
            "encode {v:e} in {m} bits with random bits {random:#x}"
        );
        assert_eq!(
            r.codes[1],
            decode_unsigned(code, m).to_bits(),
            "decode {code} of {m} bits"
        );
        // Packing, bit for bit, except that the deviation (taken from mean² and the mean of
        // squares, which a GPU may fuse) may land one code off.
        let twin = pack(&c.history, &mut ShaderRng(c.seed[0]));
        let deviation = |p: &PackedHistory| (p.detail[0] & 0xfff) as i64;
        let others = |p: &PackedHistory| (p.color, p.stats, [p.detail[0] & !0xfff, p.detail[1]]);
        assert!(
            others(&r.packed) == others(&twin)
                && (deviation(&r.packed) - deviation(&twin)).abs() <= 1,
            "pack {:?}: GPU {:?} CPU {twin:?}",
            c.history,
            r.packed
        );
        let twin = unpack(&c.packed);
        let gpu = [r.color, r.moments, r.carry].concat();
        let cpu = [twin.color, twin.moments, twin.carry].concat();
        for (g, t) in gpu.iter().zip(&cpu) {
            // Bit for bit, except the rebuilt second moment, whose sum may round either way.
            assert!(
                g.to_bits() == t.to_bits() || (g - t).abs() <= 2e-7 * t.abs(),
                "unpack {:?}: GPU {gpu:?} CPU {cpu:?}",
                c.packed
            );
        }
    }
}
