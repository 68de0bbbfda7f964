//! The non-finite detector counts exactly what a CPU count finds: NaN and ±infinity in the
//! words or channels it is told are floats, negative values (not −0) where it is told they
//! cannot be, values over a bound where one is given, in buffers (also past one dispatch row of 65,535 workgroups) and float
//! textures; per slot, with the first offending slot named (GPU: lavapipe in CI).

use rand::{Rng, SeedableRng};
use solari_scene::finite_check::{FiniteChecker, FiniteCount, RecordLayout, first_offender};
use solari_scene::gpu::{Gpu, test_gpu};

/// CPU twin: (non-finite, negative, over) over `words` laid out as `layout`.
fn cpu_count(words: &[u32], layout: RecordLayout) -> (u64, u64, u64) {
    let (mut n, mut m, mut o) = (0, 0, 0);
    for record in words.chunks(layout.stride_words as usize) {
        for (w, &bits) in record.iter().enumerate() {
            let bit = 1 << w;
            if layout.float_mask & bit == 0 {
                continue;
            }
            let v = f32::from_bits(bits);
            if !v.is_finite() {
                n += 1;
                continue;
            }
            if layout.non_negative_mask & bit != 0 && v < 0.0 {
                m += 1;
            }
            if layout.upper_mask & bit != 0 && v > layout.upper_bound {
                o += 1;
            }
        }
    }
    (n, m, o)
}

fn storage(gpu: &Gpu, words: &[u32]) -> wgpu::Buffer {
    gpu.storage_buffer(
        "test/words",
        bytemuck::cast_slice(words),
        wgpu::BufferUsages::empty(),
    )
    .unwrap()
}

fn run(
    gpu: &Gpu,
    checker: &mut FiniteChecker,
    record: impl FnOnce(&mut FiniteChecker, &mut wgpu::CommandEncoder),
) -> Vec<FiniteCount> {
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    checker.begin_frame(&mut encoder);
    record(checker, &mut encoder);
    checker.end_frame(&mut encoder);
    gpu.queue.submit([encoder.finish()]);
    let counts = checker.read(gpu).unwrap();
    gpu.check_errors().unwrap();
    counts
}

/// Random finite values with planted NaN, infinities, negatives, −0 and negative denormals.
fn planted(rng: &mut impl Rng, len: usize, bad: usize) -> Vec<u32> {
    let mut words: Vec<u32> = (0..len)
        .map(|_| rng.random_range(0.0f32..100.0).to_bits())
        .collect();
    let specials = [
        f32::NAN.to_bits(),
        0xffc0_0001, // a negative NaN with payload
        f32::INFINITY.to_bits(),
        f32::NEG_INFINITY.to_bits(),
        (-3.5f32).to_bits(),
        (-0.0f32).to_bits(),
        0x8000_0001, // the smallest negative denormal
        f32::MAX.to_bits(),
        u32::MAX,
    ];
    for _ in 0..bad {
        let i = rng.random_range(0..len);
        words[i] = specials[rng.random_range(0..specials.len())];
    }
    words
}

#[test]
fn buffer_counts_match_the_cpu_on_random_plantings() {
    let Some(gpu) = test_gpu() else { return };
    let mut checker = FiniteChecker::new(&gpu, &["first", "second"]).unwrap();
    let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
    for trial in 0..8 {
        let stride = rng.random_range(1..=32u32);
        let records = rng.random_range(1..5000u64);
        let float_mask = if stride == 32 {
            rng.random::<u32>()
        } else {
            rng.random_range(0..1u32 << stride)
        };
        let layout = RecordLayout {
            stride_words: stride,
            float_mask,
            non_negative_mask: rng.random::<u32>() & float_mask,
            upper_mask: rng.random::<u32>() & float_mask,
            upper_bound: rng.random_range(10.0..90.0),
        };
        let words = planted(&mut rng, (records * stride as u64) as usize, trial * 37 + 1);
        let buffer = storage(&gpu, &words);
        let counts = run(&gpu, &mut checker, |c, e| {
            c.check_buffer(&gpu, e, 1, &buffer, records, layout)
                .unwrap()
        });
        let (n, m, o) = cpu_count(&words, layout);
        let c = &counts[1];
        assert_eq!(
            (c.non_finite, c.negative, c.over),
            (n, m, o),
            "trial {trial}"
        );
        assert!(counts[0].is_clean());
        if n + m > 0 {
            assert_eq!(first_offender(&counts).unwrap().name, "second");
        }
    }
}

#[test]
fn slots_accumulate_and_reset_each_frame() {
    let Some(gpu) = test_gpu() else { return };
    let mut checker = FiniteChecker::new(&gpu, &["a", "b", "c"]).unwrap();
    let clean = storage(&gpu, &[1.0f32.to_bits(); 64]);
    let mut dirty_words = [2.0f32.to_bits(); 64];
    dirty_words[5] = f32::NAN.to_bits();
    dirty_words[9] = (-1.0f32).to_bits();
    let dirty = storage(&gpu, &dirty_words);
    let layout = RecordLayout::RGBA_NON_NEGATIVE;
    let counts = run(&gpu, &mut checker, |c, e| {
        c.check_buffer(&gpu, e, 0, &clean, 16, layout).unwrap();
        c.check_buffer(&gpu, e, 1, &dirty, 16, layout).unwrap();
        c.check_buffer(&gpu, e, 1, &dirty, 16, layout).unwrap();
        c.check_buffer(&gpu, e, 2, &dirty, 16, layout).unwrap();
    });
    assert_eq!(counts[1].non_finite, 2);
    assert_eq!(counts[1].negative, 2);
    assert_eq!(first_offender(&counts).unwrap().name, "b");
    // The next frame starts from zero.
    let counts = run(&gpu, &mut checker, |c, e| {
        c.check_buffer(&gpu, e, 0, &clean, 16, layout).unwrap()
    });
    assert!(counts.iter().all(FiniteCount::is_clean), "{counts:?}");
    // A check that does not fit its buffer, or a slot that does not exist, is an error.
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    assert!(
        checker
            .check_buffer(&gpu, &mut encoder, 0, &clean, 17, layout)
            .is_err()
    );
    assert!(
        checker
            .check_buffer(&gpu, &mut encoder, 3, &clean, 1, layout)
            .is_err()
    );
}

#[test]
fn large_buffers_are_covered_past_one_dispatch_row() {
    let Some(gpu) = test_gpu() else { return };
    let records = 65535u64 * 256 + 1000;
    let bytes = records * 4;
    if bytes > gpu.device.limits().max_storage_buffer_binding_size {
        assert_ne!(
            std::env::var("SOLARI_REQUIRE_GPU").as_deref(),
            Ok("1"),
            "binding limit"
        );
        return;
    }
    let mut words = vec![0.5f32.to_bits(); records as usize];
    let tail = [records as usize - 1, records as usize - 999, 65535 * 256];
    for &i in &tail {
        words[i] = f32::INFINITY.to_bits();
    }
    words[3] = (-2.0f32).to_bits();
    let buffer = storage(&gpu, &words);
    let mut checker = FiniteChecker::new(&gpu, &["big"]).unwrap();
    let layout = RecordLayout {
        stride_words: 1,
        float_mask: 1,
        non_negative_mask: 1,
        upper_mask: 0,
        upper_bound: 0.0,
    };
    let counts = run(&gpu, &mut checker, |c, e| {
        c.check_buffer(&gpu, e, 0, &buffer, records, layout)
            .unwrap()
    });
    assert_eq!((counts[0].non_finite, counts[0].negative), (3, 1));
}

fn f16(v: f32) -> u16 {
    // Round-to-nearest f32 → f16 for the values this test uses (normal range, ±0, ±inf, NaN).
    if v.is_nan() {
        return 0x7e00;
    }
    let bits = v.to_bits();
    let sign = ((bits >> 16) & 0x8000) as u16;
    if v.is_infinite() {
        return sign | 0x7c00;
    }
    if v == 0.0 {
        return sign;
    }
    let exp = ((bits >> 23) & 0xff) as i32 - 127 + 15;
    let mant = ((bits >> 13) & 0x3ff) as u16;
    sign | ((exp as u16) << 10) | mant
}

#[test]
fn float_textures_count_their_channels() {
    let Some(gpu) = test_gpu() else { return };
    let (w, h) = (37u32, 21u32);
    let mut rng = rand_pcg::Pcg64::seed_from_u64(11);
    let mut texels: Vec<[f32; 4]> = (0..w * h)
        .map(|_| std::array::from_fn(|_| rng.random_range(0.0f32..4.0)))
        .collect();
    for _ in 0..40 {
        let i = rng.random_range(0..texels.len());
        let c = rng.random_range(0..4);
        texels[i][c] = [f32::NAN, f32::INFINITY, -1.5, -0.0][rng.random_range(0..4)];
    }
    let halves: Vec<u16> = texels.iter().flatten().map(|&v| f16(v)).collect();
    let texture = gpu.texture_2d_with(
        "test/rgba16f",
        (w, h),
        wgpu::TextureFormat::Rgba16Float,
        wgpu::TextureUsages::TEXTURE_BINDING,
        bytemuck::cast_slice(&halves),
    );
    let mut checker = FiniteChecker::new(&gpu, &["tex"]).unwrap();
    for (float_mask, non_negative_mask) in [(0xf, 0xf), (0x7, 0x1), (0x8, 0x0)] {
        let counts = run(&gpu, &mut checker, |c, e| {
            c.check_texture(&gpu, e, 0, &texture, float_mask, non_negative_mask)
                .unwrap()
        });
        let words: Vec<u32> = texels.iter().flatten().map(|v| v.to_bits()).collect();
        let (n, m, _) = cpu_count(
            &words,
            RecordLayout {
                stride_words: 4,
                float_mask,
                non_negative_mask,
                upper_mask: 0,
                upper_bound: 0.0,
            },
        );
        assert_eq!(
            (counts[0].non_finite, counts[0].negative),
            (n, m),
            "masks {float_mask:#x}/{non_negative_mask:#x}"
        );
    }
}
