//! A CPU twin of the temporal pass's arithmetic for one pixel of a static view (firefly clamp
//! and carry, the averages, the moments, the stale-history band clamp, rejection of
//! non-finite samples), checked against the GPU history frame by frame on lavapipe.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_denoise::history::{COLOR_BITS, DETAIL_BITS, MEAN_BITS};
use solari_denoise::{FallbackDenoiser, FallbackSettings, GpuHistory};

mod common;

use common::{Harness, SIZE};

/// As `MOMENTS_MIN_ALPHA` in `denoise_temporal.wesl`.
const MOMENTS_MIN_ALPHA: f32 = 0.2;

fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

fn mix(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// One frame of the temporal pass for a pixel whose reprojection is itself, with the
/// demodulated `sample` (None: non-finite, rejected).
fn temporal(s: &FallbackSettings, prev: &GpuHistory, sample: Option<[f32; 3]>) -> GpuHistory {
    let Some(sample) = sample else {
        return *prev;
    };
    let length = prev.color[3];
    let total = [0, 1, 2].map(|c| sample[c] + prev.carry[c]);
    let (mut accepted, mut carry) = (total, [0.0; 3]);
    let total_luminance = luminance(total);
    if s.firefly_clamp > 0.0 && length >= s.firefly_min_history && total_luminance > 0.0 {
        let limit = (s.firefly_clamp * prev.moments[0]).max(total_luminance / s.firefly_spread);
        if total_luminance > limit {
            accepted = total.map(|v| v * (limit / total_luminance));
            carry = [0, 1, 2].map(|c| total[c] - accepted[c]);
        }
    }
    let mut new_length = (length + 1.0).min(s.max_history);
    let alpha = 1.0 / new_length;
    let mut color = [0, 1, 2].map(|c| mix(prev.color[c], accepted[c], alpha));
    let l = luminance(accepted);
    let moment_alpha = alpha.max(MOMENTS_MIN_ALPHA);
    let fast_alpha = 1.0 / s.fast_history;
    let m1 = mix(prev.moments[0], l, moment_alpha);
    let m2 = mix(prev.moments[1], l * l, moment_alpha);
    let fast = mix(prev.moments[2], l, alpha.max(fast_alpha));
    let mut slow = mix(prev.moments[3], l, alpha);
    let sigma_now = (m2 - m1 * m1).max(0.0).sqrt() / m1.max(1e-20);
    let mut sigma_ref = if length > 0.0 {
        prev.carry[3]
    } else {
        sigma_now
    };
    if s.reset_sigma > 0.0 && length >= s.reset_min_history {
        let a = fast_alpha;
        let band = (s.reset_sigma * sigma_ref * (a / (2.0 - a)).sqrt() + 0.1) * fast;
        let fixed = slow.clamp((fast - band).max(0.0), fast + band);
        if fixed != slow {
            new_length = new_length.min(s.reset_length);
            color = if slow > 1e-12 {
                color.map(|v| v * (fixed / slow))
            } else {
                accepted
            };
            slow = fixed;
        } else if (slow - fast).abs() < 0.5 * band {
            sigma_ref = mix(sigma_ref, sigma_now, moment_alpha);
        }
    } else {
        sigma_ref = mix(sigma_ref, sigma_now, moment_alpha);
    }
    GpuHistory {
        color: [color[0], color[1], color[2], new_length],
        moments: [m1, m2, fast, slow],
        carry: [carry[0], carry[1], carry[2], sigma_ref],
    }
}

/// Within the history's rounding: one code step of each stored value (2⁻¹⁴ of the value for
/// the colour, 2⁻⁹ for the means, 2⁻⁵ for the deviation, the carry and the calm deviation),
/// plus the `f32` rounding of a deviation taken from mean² and mean of squares.
fn close(gpu: &GpuHistory, cpu: &GpuHistory) -> bool {
    let near = |g: f32, c: f32, bits: u32, floor: f32| {
        (g - c).abs() <= 2f32.powi(-(bits as i32)) * c.abs().max(g.abs()) + 2e-6 * c.abs() + floor
    };
    let deviation = |h: &GpuHistory| (h.moments[1] - h.moments[0] * h.moments[0]).max(0.0).sqrt();
    // About √(2⁻²³) of the mean: what cancellation leaves of a deviation far below it.
    let cancel = 4e-4 * cpu.moments[0];
    (0..3).all(|k| near(gpu.color[k], cpu.color[k], COLOR_BITS, 1e-6))
        && gpu.color[3] == cpu.color[3]
        && [0, 2, 3]
            .iter()
            .all(|&k| near(gpu.moments[k], cpu.moments[k], MEAN_BITS, 1e-6))
        && near(deviation(gpu), deviation(cpu), DETAIL_BITS, cancel + 1e-6)
        && (0..3).all(|k| near(gpu.carry[k], cpu.carry[k], DETAIL_BITS, 1e-6))
        && near(
            gpu.carry[3],
            cpu.carry[3],
            DETAIL_BITS,
            cancel / cpu.moments[0].max(1e-20),
        )
}

#[test]
fn the_gpu_temporal_pass_matches_its_cpu_twin() {
    let Some(mut h) = Harness::new() else { return };
    let settings = FallbackSettings::default();
    let mut denoiser = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
    let mut rng = Pcg32::seed_from_u64(3);
    let n = (SIZE * SIZE) as usize;
    // Every pixel gets the same radiance each frame: noise, 3% fireflies at 40×, one NaN
    // frame, and the light dropping to a tenth at frame 80. The twin steps each checked pixel
    // from the GPU's own history of the frame before (the stored history is rounded
    // stochastically, so pixels part by a rounding step or so each frame).
    let mut before: Vec<GpuHistory> = vec![GpuHistory::default(); n];
    let mut albedo = None;
    let (mut clamped, mut band_clamped, mut checked) = (0, 0, 0);
    for frame in 0..140 {
        let level = if frame < 80 { 1.0 } else { 0.1 };
        let mut v = level * rng.random_range(0.5f32..1.5);
        if rng.random_bool(0.03) {
            v *= 40.0;
        }
        if frame == 30 {
            v = f32::NAN;
        }
        h.frame(&mut denoiser, &vec![[v, v, v, 1.0]; n], false);
        let history = denoiser.read_history(&h.gpu, 0).expect("history");
        // The pixels with a surface and a history; all saw the same samples.
        let surfaces: Vec<usize> = (0..n).filter(|&k| history[k].color[3] > 0.0).collect();
        assert!(
            surfaces.len() > n / 2,
            "frame {frame}: {} surfaces",
            surfaces.len()
        );
        // The demodulating albedo, from frame 0, where the history is the sample itself, rounded
        // stochastically: the mean over the surfaces is exact to about 1e-5.
        let a = *albedo.get_or_insert_with(|| {
            let sum: f64 = surfaces.iter().map(|&k| history[k].color[0] as f64).sum();
            (v as f64 / (sum / surfaces.len() as f64)) as f32
        });
        let sample = v.is_finite().then_some([v / a; 3]);
        for (j, &k) in surfaces.iter().enumerate().step_by(97) {
            let twin = temporal(&settings, &before[k], sample);
            if j == 0 {
                clamped += (twin.carry[0] > 0.0) as u32;
                band_clamped += (twin.color[3]
                    < (before[k].color[3] + 1.0).min(settings.max_history)
                    && sample.is_some()) as u32;
            }
            assert!(
                close(&history[k], &twin),
                "frame {frame}, pixel {k}: GPU {:?}\nCPU {twin:?}\nbefore {:?}",
                history[k],
                before[k]
            );
            checked += 1;
        }
        before = history;
    }
    println!(
        "temporal twin: {checked} pixel steps over 140 frames agree; the firefly clamp acted \
         on {clamped} frames, the stale-history clamp on {band_clamped}"
    );
    // The twin must exercise both clamps for the comparison to mean something.
    assert!(clamped > 0 && band_clamped > 0);
}

/// The stored history is rounded stochastically, so a small change of light is followed to the
/// end: first 0.4%, then a further 0.02%. Rounded to nearest (tried by fixing the dither at
/// half a step), the average stops once its step, 1/32 of the remaining difference, is under
/// half the colour's 2⁻¹⁴ rounding step: the first change ends at 1.003041×.
#[test]
fn a_small_change_of_light_is_followed_to_the_end() {
    let Some(mut h) = Harness::new() else { return };
    let settings = FallbackSettings::default();
    let mut denoiser = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
    let n = (SIZE * SIZE) as usize;
    let mean = |denoiser: &FallbackDenoiser, h: &Harness| {
        let history = denoiser.read_history(&h.gpu, 0).expect("history");
        let lit: Vec<f64> = history
            .iter()
            .filter(|g| g.color[3] > 0.0)
            .map(|g| g.color[0] as f64)
            .collect();
        lit.iter().sum::<f64>() / lit.len() as f64
    };
    for _ in 0..64 {
        h.frame(&mut denoiser, &vec![[1.0, 1.0, 1.0, 1.0]; n], false);
    }
    let start = mean(&denoiser, &h);
    for _ in 0..400 {
        h.frame(&mut denoiser, &vec![[1.004, 1.004, 1.004, 1.0]; n], false);
    }
    let end = mean(&denoiser, &h) / start;
    println!("a 0.4% brighter light: the history's mean moved by {end:.6}×");
    assert!((end - 1.004).abs() < 2e-4, "ended at {end}× (want 1.004×)");
    for _ in 0..400 {
        h.frame(
            &mut denoiser,
            &vec![[1.0042, 1.0042, 1.0042, 1.0]; n],
            false,
        );
    }
    let end = mean(&denoiser, &h) / start;
    println!("then 0.02% brighter: the history's mean moved by {end:.6}×");
    assert!(
        (end - 1.0042).abs() < 2e-5,
        "ended at {end}× (want 1.0042×)"
    );
}
