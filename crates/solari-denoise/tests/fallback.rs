//! The fallback denoiser on lavapipe, fed synthetic lighting over a real G-buffer: a Cornell
//! box whose every surface has the same grey albedo and no emission, so that constant
//! radiance is constant demodulated light and the denoiser's output mean can be compared
//! with the input's exactly (`common`). Checks: firefly suppression keeps energy, non-finite
//! input is rejected and not spread, a reset forgets history, settings are validated; and
//! the fallback from DLSS-RR with its reason.
//! Figures are printed for the issue notes (`cargo test -- --nocapture`).

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_denoise::{
    AtrousKernel, DenoiserKind, DlssAvailability, FallbackDenoiser, FallbackSettings, create,
};

mod common;

use common::{Harness, SIZE, luminance};

// Runs `frames` frames of iid input: `base` with probability 1 − p, else `firefly`. Returns
// (mean input luminance, mean output luminance over frames after `warmup`, mean per-pixel
// variance of the output over time).
fn firefly_run(h: &mut Harness, settings: FallbackSettings, frames: u32) -> (f64, f64, f64) {
    let mut denoiser = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
    let mut rng = Pcg32::seed_from_u64(7);
    let n = (SIZE * SIZE) as usize;
    let warmup = 40;
    let (mut sum_in, mut sum_out) = (0.0, 0.0);
    let mut per_pixel = vec![(0.0f64, 0.0f64); n];
    let mut surface = vec![true; n];
    for frame in 0..frames {
        let input: Vec<[f32; 4]> = (0..n)
            .map(|_| {
                let v = if rng.random::<f32>() < 0.01 {
                    50.0
                } else {
                    0.5
                };
                [v, v, v, 1.0]
            })
            .collect();
        let out = h.frame(&mut denoiser, &input, false);
        if frame == 0 {
            // Surfaces only: the background is passed through unfiltered.
            let history = denoiser.read_history(&h.gpu, 0).expect("history");
            surface = history.iter().map(|p| p.color[3] > 0.0).collect();
        }
        if frame >= warmup {
            for (i, (a, b)) in input.iter().zip(&out).enumerate() {
                if !surface[i] {
                    continue;
                }
                sum_in += luminance(*a);
                let l = luminance(*b);
                sum_out += l;
                per_pixel[i].0 += l;
                per_pixel[i].1 += l * l;
            }
        }
    }
    let surfaces = surface.iter().filter(|s| **s).count();
    let count = ((frames - warmup) as usize * surfaces) as f64;
    let t = (frames - warmup) as f64;
    let variance = per_pixel
        .iter()
        .zip(&surface)
        .filter(|(_, s)| **s)
        .map(|((s, s2), _)| s2 / t - (s / t).powi(2))
        .sum::<f64>()
        / surfaces as f64;
    (sum_in / count, sum_out / count, variance)
}

#[test]
fn firefly_suppression_moves_energy_in_time_without_losing_it() {
    let Some(mut h) = Harness::new() else { return };
    let frames = 400;
    // The clamp's own bias, with the stale-history fix off (it reacts to fireflies itself).
    let isolated = |clamp: f32, h: &mut Harness| {
        let settings = FallbackSettings {
            firefly_clamp: clamp,
            reset_sigma: 0.0,
            ..Default::default()
        };
        firefly_run(h, settings, frames)
    };
    let on = isolated(8.0, &mut h);
    let off = isolated(0.0, &mut h);
    let clamp_bias = (on.1 / on.0) / (off.1 / off.0) - 1.0;
    // The whole denoiser with its defaults, and without the clamp.
    let full = firefly_run(&mut h, FallbackSettings::default(), frames);
    let full_off = firefly_run(
        &mut h,
        FallbackSettings {
            firefly_clamp: 0.0,
            ..Default::default()
        },
        frames,
    );
    let feedback = firefly_run(
        &mut h,
        FallbackSettings {
            history_feedback: true,
            ..Default::default()
        },
        frames,
    );
    println!(
        "fireflies: defaults with SVGF's history feedback on: output/input {:.4}",
        feedback.1 / feedback.0
    );
    println!(
        "fireflies (1% of samples at 100x the rest, {SIZE}x{SIZE}, frames 41-{frames}): output/input \
         without the history fix: {:.4} with the clamp, {:.4} without (clamp bias {:+.2}%); \
         defaults: {:.4} with the clamp, {:.4} without",
        on.1 / on.0,
        off.1 / off.0,
        clamp_bias * 100.0,
        full.1 / full.0,
        full_off.1 / full_off.0
    );
    // Stated bound for the clamp's own bias: 2%.
    assert!(clamp_bias.abs() < 0.02, "firefly clamp bias {clamp_bias}");
    // The history fix is biased under such heavy tails (it follows fireflies); the clamp
    // keeps most of them from reaching it. Stated bound for the defaults: 15%.
    assert!(
        (full.1 / full.0 - 1.0).abs() < 0.15,
        "defaults bias {}",
        full.1 / full.0
    );
    assert!((full.1 / full.0 - 1.0).abs() < (full_off.1 / full_off.0 - 1.0).abs());
    // Feedback runs in a pipeline of its own (`denoise_atrous_feedback`): it must act, and it
    // compounds the luminance-weighted blur (the settings' docs quote +56%).
    assert!(
        feedback.1 / feedback.0 > full.1 / full.0 + 0.2,
        "history feedback: output/input {} against {} without",
        feedback.1 / feedback.0,
        full.1 / full.0
    );
}

#[test]
fn non_finite_input_is_rejected_not_spread() {
    let Some(mut h) = Harness::new() else { return };
    let mut denoiser =
        FallbackDenoiser::new(&h.gpu, SIZE, SIZE, FallbackSettings::default()).expect("denoiser");
    let n = (SIZE * SIZE) as usize;
    let bad = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -f32::NAN];
    let mut rng = Pcg32::seed_from_u64(3);
    let mut worst = 0.0f64;
    let mut bad_count = 0;
    for frame in 0..12 {
        // 5% of pixels bad in one channel each frame (fresh positions), on frame 0 too.
        let mut input = vec![[0.5f32, 0.5, 0.5, 1.0]; n];
        for p in input.iter_mut() {
            if rng.random::<f32>() < 0.05 {
                p[rng.random_range(0..3)] = bad[rng.random_range(0..bad.len())];
                bad_count += 1;
            }
        }
        // One whole frame of NaN after history exists.
        if frame == 8 {
            input.fill([f32::NAN; 4]);
        }
        let out = h.frame(&mut denoiser, &input, false);
        for (i, p) in out.iter().enumerate() {
            assert!(
                p.iter().all(|v| v.is_finite()),
                "frame {frame} pixel {i}: non-finite output {p:?}"
            );
            if p[3] > 0.5 {
                // Surfaces: every value stays at the clean input's 0.5 (neighbours fill in).
                worst = worst.max((luminance(*p) - 0.5).abs());
            }
        }
    }
    println!(
        "non-finite input: {bad_count} bad samples plus one all-NaN frame over 12 frames; \
         output finite everywhere, largest deviation from 0.5: {worst:.2e}"
    );
    assert!(worst < 1e-3, "bad samples leaked into the output: {worst}");
}

/// The packed history's range (`solari_denoise::history`): a light far dimmer than f16 could
/// hold, one far brighter, and one past the range, which is clamped. Surfaces' mean output over
/// the last frames must keep the dim and bright levels (the dim one sits in the linear codes,
/// where stochastic rounding keeps the average right) and stay finite past the range.
#[test]
fn the_history_keeps_dim_and_bright_light() {
    let Some(mut h) = Harness::new() else { return };
    let n = (SIZE * SIZE) as usize;
    // Light of 1e-12 (a 6-bit exponent's codes stopped at 2^-30: its output then read 2.4%
    // high), 1e-21 (close to the 7-bit exponent's 2^-62, demodulated), 1e8 (past f16's
    // 65,504), and 1e21 (past the 3.7e19 limit).
    for level in [1e-12f32, 1e-21, 1e8, 1e21] {
        let mut denoiser = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, FallbackSettings::default())
            .expect("denoiser");
        let (mut sum, mut count, mut brightest) = (0.0f64, 0u64, 0.0f32);
        for frame in 0..48 {
            // w = 0.5 in the input: the denoiser writes w = 1 on surfaces and passes the
            // background through with the input's w, so the two can be told apart.
            let out = h.frame(&mut denoiser, &vec![[level, level, level, 0.5]; n], false);
            let surfaces: Vec<&[f32; 4]> = out.iter().filter(|p| p[3] == 1.0).collect();
            assert!(
                surfaces.len() > n / 2,
                "{level}: {} surfaces",
                surfaces.len()
            );
            for p in surfaces {
                assert!(
                    p[..3].iter().all(|v| v.is_finite() && *v >= 0.0),
                    "{level}: frame {frame}: {p:?}"
                );
                brightest = p[..3].iter().fold(brightest, |b, v| b.max(*v));
                if frame >= 32 {
                    sum += luminance(*p);
                    count += 1;
                }
            }
        }
        let ratio = sum / count as f64 / level as f64;
        println!(
            "a constant light of {level:e}: surfaces' mean output is {ratio:.5}× the input, \
             the brightest {brightest:e}"
        );
        if level < 1e19 {
            assert!(
                (ratio - 1.0).abs() < 1e-3,
                "{level}: output {ratio}× the input"
            );
        } else {
            // Clamped where the history's codes end (3.7e19 in demodulated units), then
            // remodulated by the grey box's albedo (below 1): never above the clamp.
            let clamp = solari_denoise::history::decode_unsigned(
                solari_denoise::history::code_max(solari_denoise::history::COLOR_BITS),
                solari_denoise::history::COLOR_BITS,
            );
            assert!(
                brightest <= clamp,
                "{level}: brightest output {brightest:e}"
            );
            assert!(ratio < 0.05, "{level}: output {ratio}× the input");
        }
    }
}

#[test]
fn absurd_values_stay_finite() {
    let Some(mut h) = Harness::new() else { return };
    let mut denoiser =
        FallbackDenoiser::new(&h.gpu, SIZE, SIZE, FallbackSettings::default()).expect("denoiser");
    let n = (SIZE * SIZE) as usize;
    for frame in 0..10 {
        let v = if frame % 2 == 0 { 1e30 } else { 3e38 };
        let input = vec![[v, 0.0, v, 1.0]; n];
        let out = h.frame(&mut denoiser, &input, false);
        assert!(
            out.iter().flatten().all(|v| v.is_finite()),
            "frame {frame}: non-finite output from finite input"
        );
    }
}

#[test]
fn reset_forgets_history_in_one_frame() {
    let Some(mut h) = Harness::new() else { return };
    let mut denoiser =
        FallbackDenoiser::new(&h.gpu, SIZE, SIZE, FallbackSettings::default()).expect("denoiser");
    let n = (SIZE * SIZE) as usize;
    for _ in 0..20 {
        h.frame(&mut denoiser, &vec![[2.0, 2.0, 2.0, 1.0]; n], false);
    }
    let out = h.frame(&mut denoiser, &vec![[0.25, 0.25, 0.25, 1.0]; n], true);
    let worst = out
        .iter()
        .filter(|p| p[3] > 0.5)
        .map(|p| (luminance(*p) - 0.25).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-4, "history survived a reset: off by {worst}");
    let history = denoiser.read_history(&h.gpu, 0).expect("history");
    assert!(
        history
            .iter()
            .all(|p| p.color[3] == 0.0 || p.color[3] == 1.0),
        "history lengths after a reset must be 0 (background) or 1"
    );
}

#[test]
fn fast_reset_follows_a_light_switch() {
    // Noisy input (±50% per pixel) that drops to a tenth: the long history alone takes over
    // 100 frames to get within 10%; the stale-history fix must cut that short.
    let Some(mut h) = Harness::new() else { return };
    let n = (SIZE * SIZE) as usize;
    let lag = |settings: FallbackSettings, h: &mut Harness| {
        let mut denoiser = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
        let mut rng = Pcg32::seed_from_u64(11);
        let mut noisy = |level: f32| -> Vec<[f32; 4]> {
            (0..n)
                .map(|_| {
                    let v = level * (0.5 + rng.random::<f32>());
                    [v, v, v, 1.0]
                })
                .collect()
        };
        for _ in 0..60 {
            h.frame(&mut denoiser, &noisy(1.0), false);
        }
        for frame in 1..=100 {
            let out = h.frame(&mut denoiser, &noisy(0.1), false);
            let surfaces: Vec<f64> = out
                .iter()
                .filter(|p| p[3] > 0.5)
                .map(|p| luminance(*p))
                .collect();
            let mean = surfaces.iter().sum::<f64>() / surfaces.len() as f64;
            if mean < 0.1 * 1.1 {
                return frame;
            }
        }
        101
    };
    let with_reset = lag(FallbackSettings::default(), &mut h);
    let without = lag(
        FallbackSettings {
            reset_sigma: 0.0,
            ..Default::default()
        },
        &mut h,
    );
    println!(
        "light switched to 10%: output within 10% after {with_reset} frames with the fast \
         reset, {without} without"
    );
    // Measured 43 against over 100 (per-pixel noise ±50%: the fix waits for 4 σ).
    assert!(with_reset <= 60, "fast reset too slow: {with_reset} frames");
    assert!(without > 90, "the long history alone should lag: {without}");
}

#[test]
fn bad_settings_are_refused_with_the_knob_named() {
    let cases: [(FallbackSettings, &str); 10] = [
        (
            FallbackSettings {
                atrous_iterations: 0,
                ..Default::default()
            },
            "atrous_iterations",
        ),
        // The stored length is an f16: past 2048 frames it would no longer count whole frames.
        (
            FallbackSettings {
                max_history: 4096.0,
                ..Default::default()
            },
            "max_history",
        ),
        (
            FallbackSettings {
                max_history: f32::NAN,
                ..Default::default()
            },
            "max_history",
        ),
        (
            FallbackSettings {
                firefly_clamp: 0.5,
                ..Default::default()
            },
            "firefly_clamp",
        ),
        (
            FallbackSettings {
                reset_min_history: 8.0,
                ..Default::default()
            },
            "reset_min_history",
        ),
        (
            FallbackSettings {
                reset_min_history: 0.5,
                ..Default::default()
            },
            "reset_min_history",
        ),
        (
            FallbackSettings {
                phi_depth: 0.0,
                ..Default::default()
            },
            "phi_depth",
        ),
        // Positive but so small that phi_depth × view depth underflows (a NaN weight).
        (
            FallbackSettings {
                phi_depth: 1e-39,
                ..Default::default()
            },
            "phi_depth",
        ),
        // Finite but so large that the weights' products overflow (∞ × 0 = NaN).
        (
            FallbackSettings {
                phi_lobe: 3e38,
                ..Default::default()
            },
            "phi_lobe",
        ),
        (
            FallbackSettings {
                phi_normal: 1e31,
                ..Default::default()
            },
            "phi_normal",
        ),
    ];
    for (settings, knob) in cases {
        let e = settings.validate().expect_err(knob).to_string();
        assert!(e.contains(knob), "{e} does not name {knob}");
    }
    FallbackSettings::default().validate().expect("defaults");
}

#[test]
fn explicit_dlss_request_falls_back_with_a_reason() {
    let Some(h) = Harness::new() else { return };
    let availability = if cfg!(feature = "dlss") {
        // The mock build: DLSS-RR is compiled in but never supported.
        solari_denoise::create_gpu().expect("gpu").1
    } else {
        DlssAvailability::NotBuilt
    };
    let created = create(
        &h.gpu,
        Some(DenoiserKind::DlssRr),
        &availability,
        (SIZE, SIZE),
        FallbackSettings::default(),
    )
    .expect("create");
    assert_eq!(created.kind, DenoiserKind::Fallback);
    let why = created.fallback_reason.expect("a reason");
    println!("{why}");
    assert!(why.contains("DLSS-RR unavailable"), "{why}");
    if cfg!(feature = "dlss-mock") {
        assert!(why.contains("dlss-mock"), "{why}");
    }
    // Asking for the best available falls back quietly.
    let best = create(
        &h.gpu,
        None,
        &availability,
        (SIZE, SIZE),
        FallbackSettings::default(),
    )
    .expect("create");
    assert_eq!(best.kind, DenoiserKind::Fallback);
    assert!(best.fallback_reason.is_none());
}

/// A shadow input smaller than the image is refused with the sizes named, before anything is
/// recorded; the right size is taken.
#[test]
fn a_short_shadow_input_is_refused() {
    use solari_denoise::{Denoiser, DenoiserInputs, Lighting};
    let Some(mut h) = Harness::new() else { return };
    let mut denoiser =
        FallbackDenoiser::new(&h.gpu, SIZE, SIZE, FallbackSettings::default()).expect("denoiser");
    let shadow = |bytes: u64| {
        h.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("test shadow"),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        })
    };
    let (short, right) = (shadow(64), shadow((SIZE * SIZE * 4) as u64));
    let mut encoder = h.gbuffer_encoder();
    let camera = solari_scene::default_scene::cornell_box()
        .camera(None)
        .expect("camera");
    let frame = solari_scene::pass::FrameContext::new(0, (SIZE, SIZE), &camera, None);
    for (buffer, ok) in [(&short, false), (&right, true)] {
        let inputs = DenoiserInputs {
            lighting: Lighting::Combined(h.lighting()),
            gbuffer: h.gbuffer(),
            hit_distance: None,
            shadow: Some(buffer),
            reset: false,
        };
        match (denoiser.encode(&h.gpu, &mut encoder, &frame, &inputs), ok) {
            (Ok(_), true) => {}
            (Err(e), false) => {
                let e = e.to_string();
                assert!(e.contains("shadow input holds 64 bytes"), "{e}");
            }
            (Ok(_), false) => panic!("a 64-byte shadow input was taken"),
            (Err(e), true) => panic!("a full-size shadow input was refused: {e}"),
        }
    }
    h.gpu.queue.submit([encoder.finish()]);
}

/// An image whose largest buffer (the transient bytes, 32 a pixel) is over the device's
/// storage binding limit is refused with both sizes named, before anything is allocated; one
/// just under it is built. (Lavapipe device with a 64 KiB limit: 45×45 pixels need 64,800
/// bytes, 46×46 67,712.)
#[test]
fn images_over_the_binding_limit_are_refused_by_name() {
    use solari_scene::GpuError;
    use solari_scene::gpu::test_gpu_with_limits;
    let Some(small) = test_gpu_with_limits(|own| wgpu::Limits {
        max_storage_buffer_binding_size: 1 << 16,
        ..own
    }) else {
        return;
    };
    let settings = FallbackSettings::default();
    match FallbackDenoiser::new(&small, 46, 46, settings) {
        Err(GpuError::OverLimit {
            what,
            needed,
            limit,
        }) => {
            assert!(
                what.contains("transient") && what.contains("46×46"),
                "{what}"
            );
            assert_eq!((needed, limit), (46 * 46 * 32, 1 << 16));
        }
        other => panic!("expected OverLimit, got {:?}", other.err()),
    }
    FallbackDenoiser::new(&small, 45, 45, settings).expect("45×45 fits");
    small.check_errors().expect("no wgpu error");
}

/// One à-trous iteration on the first frame spreads a single lit pixel on a flat wall over
/// exactly its kernel's taps: the diamond reaches the pixels within two steps by
/// Manhattan distance and no corner of the 5×5 square, the full kernel reaches the corners
/// too, and neither reaches three steps.
/// One à-trous iteration over one lit pixel on a flat wall reaches exactly the kernel's taps,
/// each with its B3 weight: with the luminance weight made flat (a huge `phi_luminance`) and
/// coplanar, parallel taps, a pixel q near the centre reads K(centre − q) / ΣK, so its output
/// over the centre's is K(centre − q) / K(0) (the taps are spelled out one by one in
/// `denoise_atrous_filter.wesl`: a wrong offset or weight among them shows here).
#[test]
fn each_kernel_spreads_a_lit_pixel_over_its_taps() {
    let Some(mut h) = Harness::new() else { return };
    let n = (SIZE * SIZE) as usize;
    // Pixel (14, 14): on the back wall, three pixels or more from any edge.
    let centre = 14i32;
    let mut input = vec![[0.0f32, 0.0, 0.0, 1.0]; n];
    input[(centre * SIZE as i32 + centre) as usize] = [1.0, 1.0, 1.0, 1.0];
    let b3 = |d: i32| [0.375f32, 0.25, 0.0625][d.unsigned_abs() as usize];
    for kernel in [AtrousKernel::Diamond, AtrousKernel::Full] {
        let settings = FallbackSettings {
            atrous_iterations: 1,
            atrous_kernel: kernel,
            phi_luminance: 1e6,
            ..FallbackSettings::default()
        };
        let mut d = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
        let out = h.frame(&mut d, &input, true);
        for dy in -3i32..=3 {
            for dx in -3i32..=3 {
                let p = out[((centre + dy) * SIZE as i32 + centre + dx) as usize];
                assert_eq!(p[3], 1.0, "({dx}, {dy}) is not on a surface");
                let lit = p[0] > 0.0;
                let reached = match kernel {
                    AtrousKernel::Diamond => dx.abs() + dy.abs() <= 2,
                    AtrousKernel::Full => dx.abs() <= 2 && dy.abs() <= 2,
                };
                assert_eq!(lit, reached, "{kernel:?}: ({dx}, {dy}) reads {p:?}");
            }
        }
        // Pixels whose own taps all lie on the wall (within three of the centre).
        let at = |dx: i32, dy: i32| out[((centre + dy) * SIZE as i32 + centre + dx) as usize][0];
        for (dx, dy) in [
            (1, 0),
            (-1, 0),
            (0, 1),
            (0, -1),
            (1, 1),
            (-1, 1),
            (1, -1),
            (-1, -1),
        ] {
            let ratio = at(dx, dy) / at(0, 0);
            let expected = b3(dx) * b3(dy) / (b3(0) * b3(0));
            assert!(
                (ratio - expected).abs() <= 1e-4 * expected,
                "{kernel:?}: ({dx}, {dy}) reads {ratio} of the centre, the kernel {expected}"
            );
        }
    }
}

/// Taps past the image's edge are left out, not read from the edge: the filter loads every
/// tap before testing it, from the tap clamped into the image (`denoise_atrous_filter.wesl`),
/// so a clamped tap that counted would read the edge pixel again. With the view narrowed to
/// the back wall, one lit pixel in the middle of each edge, the luminance weight made flat and
/// coplanar taps, the lit pixel's output is K(0) / ΣK over the full kernel's taps inside the
/// image only (with the inside test dropped, the left edge read 0.2507 against 0.2045: its
/// clamped taps read the lit pixel again).
#[test]
fn taps_past_the_edge_are_left_out() {
    let Some(mut h) = Harness::new() else { return };
    h.fov_scale = 0.2;
    let n = (SIZE * SIZE) as usize;
    let s = SIZE as i32;
    let b3 = |d: i32| [0.375f32, 0.25, 0.0625][d.unsigned_abs() as usize];
    let settings = FallbackSettings {
        atrous_iterations: 1,
        atrous_kernel: AtrousKernel::Full,
        phi_luminance: 1e6,
        ..FallbackSettings::default()
    };
    for (x, y) in [(0, s / 2), (s - 1, s / 2), (s / 2, 0), (s / 2, s - 1)] {
        let mut input = vec![[0.0f32, 0.0, 0.0, 1.0]; n];
        input[(y * s + x) as usize] = [1.0, 1.0, 1.0, 1.0];
        let mut d = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
        let out = h.frame(&mut d, &input, true);
        let mut inside = 0.0f32;
        for dy in -2i32..=2 {
            for dx in -2i32..=2 {
                let (qx, qy) = (x + dx, y + dy);
                if qx >= 0 && qy >= 0 && qx < s && qy < s {
                    inside += b3(dx) * b3(dy);
                }
            }
        }
        let expected = b3(0) * b3(0) / inside;
        let got = out[(y * s + x) as usize][0];
        println!("edge pixel ({x}, {y}) reads {got}, the kernel inside the image {expected}");
        assert!(
            (got - expected).abs() <= 1e-3 * expected,
            "edge pixel ({x}, {y}) reads {got}, the kernel inside the image {expected}"
        );
    }
}

/// Taps on the centre's own plane pass the depth test: their plane distance
/// (`denoise_plane.wesl`) is zero up to rounding, at every à-trous step and in the variance
/// pass's window. So on noise over the grey box, the default depth tolerance gives the output
/// of no depth test at all (a tolerance of 1000 view depths) on all but the pixels next to
/// parallel surfaces at other depths. Measured 2,292 of 2,304 pixels; an offset negated at the
/// à-trous call site kept 601, the à-trous plane built for step 1 at every step 715, the
/// variance window's offsets swapped 2,181.
#[test]
fn coplanar_taps_pass_the_depth_test() {
    let Some(mut h) = Harness::new() else { return };
    let n = (SIZE * SIZE) as usize;
    let mut rng = Pcg32::seed_from_u64(23);
    let frames: Vec<Vec<[f32; 4]>> = (0..3)
        .map(|_| {
            (0..n)
                .map(|_| {
                    let v = rng.random_range(0.0..2.0f32);
                    [v, v, v, 1.0]
                })
                .collect()
        })
        .collect();
    let run = |h: &mut Harness, phi_depth: f32| {
        let settings = FallbackSettings {
            phi_depth,
            ..FallbackSettings::default()
        };
        let mut d = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
        let mut out = Vec::new();
        for (k, input) in frames.iter().enumerate() {
            out = h.frame(&mut d, input, k == 0);
        }
        out
    };
    let default = run(&mut h, FallbackSettings::default().phi_depth);
    let off = run(&mut h, 1e3);
    let (mut same, mut surfaces) = (0, 0);
    for (a, b) in default.iter().zip(&off) {
        if a[3] != 1.0 {
            continue;
        }
        surfaces += 1;
        same += ((a[0] - b[0]).abs() <= 1e-3 * a[0].abs().max(1e-3)) as usize;
    }
    let share = same as f64 / surfaces as f64;
    println!("{same} of {surfaces} surface pixels as without a depth test");
    assert!(
        share > 0.98,
        "only {same} of {surfaces} pixels as without a depth test ({share:.3})"
    );
}
