//! A CPU twin of the temporal pass's arithmetic for one pixel of a static view (firefly clamp
//! and carry, the averages, the moments, the stale-history band clamp, rejection of
//! non-finite samples), checked against the GPU history frame by frame on lavapipe.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
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

fn close(gpu: &[f32; 4], cpu: &[f32; 4]) -> bool {
    gpu.iter()
        .zip(cpu)
        .all(|(g, c)| (g - c).abs() <= 1e-3 * c.abs().max(g.abs()) + 1e-6)
}

#[test]
fn the_gpu_temporal_pass_matches_its_cpu_twin() {
    let Some(mut h) = Harness::new() else { return };
    let settings = FallbackSettings::default();
    let mut denoiser = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
    let mut rng = Pcg32::seed_from_u64(3);
    let n = (SIZE * SIZE) as usize;
    // Every pixel gets the same radiance each frame: noise, 3% fireflies at 40×, one NaN
    // frame, and the light dropping to a tenth at frame 80.
    let mut twin = GpuHistory {
        color: [0.0; 4],
        moments: [0.0; 4],
        carry: [0.0; 4],
    };
    let mut albedo = None;
    let (mut clamped, mut band_clamped) = (0, 0);
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
        let surfaces: Vec<&GpuHistory> = history.iter().filter(|g| g.color[3] > 0.0).collect();
        assert!(
            surfaces.len() > n / 2,
            "frame {frame}: {} surfaces",
            surfaces.len()
        );
        // The demodulating albedo, from frame 0 (the history is the sample itself).
        let a = *albedo.get_or_insert(v / surfaces[0].color[0]);
        let sample = v.is_finite().then_some([v / a; 3]);
        let before = twin;
        twin = temporal(&settings, &twin, sample);
        clamped += (twin.carry[0] > 0.0) as u32;
        band_clamped += (twin.color[3] < (before.color[3] + 1.0).min(settings.max_history)
            && sample.is_some()) as u32;
        for (k, g) in surfaces.iter().enumerate().step_by(97) {
            assert!(
                close(&g.color, &twin.color)
                    && close(&g.moments, &twin.moments)
                    && close(&g.carry, &twin.carry),
                "frame {frame}, surface pixel {k}: GPU {g:?}\nCPU {twin:?}"
            );
        }
    }
    println!(
        "temporal twin: 140 frames agree; the firefly clamp acted on {clamped} frames, the \
         stale-history clamp on {band_clamped}"
    );
    // The twin must exercise both clamps for the comparison to mean something.
    assert!(clamped > 0 && band_clamped > 0);
}
