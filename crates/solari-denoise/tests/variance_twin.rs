//! The variance pass's arithmetic (`denoise_variance_math.wesl`) against its Rust twin
//! (`solari_denoise::variance::pixel_variance`) on lavapipe: random windows and histories, and
//! adversarial ones (no weight, moments whose spread is negative, variances of 0, 1e-30 and
//! 1e30, lengths of 0, fractional and far past the young window, one frame of young window).
//! NaN inputs are left out: WGSL lets implementations assume none (`min` of a NaN is
//! undefined), and the pass feeds none (the temporal pass rejects non-finite samples).

use bytemuck::{Pod, Zeroable};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_denoise::variance::{WindowSums, pixel_variance};
use solari_scene::case_kernel::CaseKernel;
use solari_scene::gpu::test_gpu;

/// WGSL twin: `Case` in `shaders/denoise_variance_test.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Case {
    sums: [f32; 4],
    more: [f32; 4],
    history: [f32; 4],
}

impl Case {
    fn window(&self) -> Option<WindowSums> {
        (self.more[2] > 0.5).then_some(WindowSums {
            m1: self.sums[0],
            m2: self.sums[1],
            f1: self.sums[2],
            f2: self.sums[3],
            weight: self.more[0],
            sharp: self.more[1] > 0.5,
        })
    }
}

// A value spread over many magnitudes, with exact zeros and the extremes now and then.
fn magnitude(rng: &mut Pcg32) -> f32 {
    match rng.random_range(0..12) {
        0 => 0.0,
        1 => 1e-30,
        2 => 1e30,
        _ => 10f32.powf(rng.random_range(-8.0..4.0)),
    }
}

fn cases() -> Vec<Case> {
    let mut rng = Pcg32::seed_from_u64(18);
    (0..6000)
        .map(|k| {
            let weight = match k % 7 {
                0 => 0.0,
                1 => 1e-13,
                _ => rng.random_range(0.0..25.0f32),
            };
            // Moments as sums of weight × per-tap values; m2 below m1² now and then.
            let mean = magnitude(&mut rng);
            let m1 = weight * mean;
            let m2 = weight * mean * mean * rng.random_range(0.5..3.0f32);
            let removed = if k % 3 == 0 { 0.0 } else { magnitude(&mut rng) };
            let f1 = m1 + weight * removed;
            let f2 = m2 + weight * removed * (2.0 * mean + removed);
            let length = match k % 5 {
                0 => 0.0,
                1 => rng.random_range(0.0..2.0),
                2 => rng.random_range(1.0..40.0f32).floor(),
                _ => rng.random_range(0.0..12.0f32),
            };
            let frames = if k % 11 == 0 {
                1.0
            } else {
                rng.random_range(1.0..8.0f32)
            };
            Case {
                sums: [m1, m2, f1, f2],
                more: [
                    weight,
                    rng.random_bool(0.5) as u32 as f32,
                    rng.random_bool(0.8) as u32 as f32,
                    magnitude(&mut rng),
                ],
                history: [length, frames, 0.0, 0.0],
            }
        })
        .collect()
}

#[test]
fn variance_math_matches_its_rust_twin() {
    let Some(gpu) = test_gpu() else { return };
    let source = include_str!("../shaders/denoise_variance_test.wesl");
    let cases = cases();
    let results: Vec<[f32; 4]> = CaseKernel::run_test_module(
        &gpu,
        solari_denoise::modules(),
        "denoise_variance_test",
        source,
        0,
        &cases,
    )
    .expect("dispatch");
    let (mut capped, mut mixed) = (0, 0);
    for (c, r) in cases.iter().zip(&results) {
        let (temporal, length, frames) = (c.more[3], c.history[0], c.history[1]);
        let twin = pixel_variance(temporal, c.window(), length, frames);
        // exp and log may be approximate in WGSL: lavapipe's are within a few ulp, which the
        // geometric mix scales by |log| (up to 69 at 1e-30).
        let tol = 2e-5 * twin.abs().max(1e-30);
        assert!(
            r[0] == twin || (r[0] - twin).abs() <= tol,
            "GPU {} CPU {twin} for {c:?}",
            r[0]
        );
        assert!(twin >= 0.0 && !twin.is_nan(), "{twin} for {c:?}");
        let young = length < 2.0 * frames;
        match c.window() {
            Some(w) if w.sharp && !young => {
                assert!(
                    twin <= temporal,
                    "a sharp window raised {temporal} to {twin}"
                );
                capped += (twin < temporal) as u32;
            }
            Some(_) if young => mixed += 1,
            _ => {}
        }
    }
    // The cases reach both branches often.
    assert!(
        capped > 300 && mixed > 1000,
        "capped {capped}, mixed {mixed}"
    );
}
