//! Error metrics on constructed images with known answers.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_reference::metrics::compare;

fn gradient(w: u32, h: u32) -> Vec<[f32; 3]> {
    (0..w * h)
        .map(|i| {
            let x = (i % w) as f32 / w as f32;
            [x, 0.5 * x + 0.1, 0.3]
        })
        .collect()
}

#[test]
fn identical_images_have_no_error() {
    let img = gradient(64, 48);
    let (m, map) = compare(&img, &img, 64, 48, None).unwrap();
    assert_eq!(
        (m.rmse, m.rel_mse, m.flip, m.flip_hdr),
        (0.0, 0.0, 0.0, 0.0)
    );
    assert!(map.iter().all(|&v| v == 0.0));
    assert_eq!(m.mean_ratio, 1.0);
}

#[test]
fn mean_ratio_is_the_share_of_the_reference_light() {
    let reference = gradient(32, 16);
    let half: Vec<[f32; 3]> = reference.iter().map(|p| p.map(|c| 0.55 * c)).collect();
    let (m, _) = compare(&half, &reference, 32, 16, None).unwrap();
    assert!((m.mean_ratio - 0.55).abs() < 1e-6, "{}", m.mean_ratio);
    let black = vec![[0.0f32; 3]; reference.len()];
    assert!(
        compare(&reference, &black, 32, 16, None)
            .unwrap()
            .0
            .mean_ratio
            .is_nan()
    );
}

#[test]
fn rmse_and_relative_mse_match_their_definitions() {
    let reference = gradient(32, 32);
    let test: Vec<[f32; 3]> = reference.iter().map(|p| p.map(|c| c + 0.1)).collect();
    let (m, _) = compare(&test, &reference, 32, 32, None).unwrap();
    assert!((m.rmse - 0.1).abs() < 1e-6, "{}", m.rmse);
    let rel: f64 = reference
        .iter()
        .flat_map(|p| p.iter())
        .map(|&b| 0.01 / ((b as f64).powi(2) + 0.01))
        .sum::<f64>()
        / (32.0 * 32.0 * 3.0);
    assert!((m.rel_mse - rel).abs() < 1e-6 * rel.max(1.0));
    assert!(m.flip > 0.0 && m.flip_hdr >= m.flip);
}

#[test]
fn flip_grows_with_noise_and_masks_select_pixels() {
    let reference = gradient(64, 64);
    let mut rng = Pcg32::seed_from_u64(5);
    let noisy = |sigma: f32, rng: &mut Pcg32| -> Vec<[f32; 3]> {
        reference
            .iter()
            .map(|p| p.map(|c| (c + sigma * (rng.random::<f32>() - 0.5)).max(0.0)))
            .collect()
    };
    let (low, _) = compare(&noisy(0.05, &mut rng), &reference, 64, 64, None).unwrap();
    let (high, _) = compare(&noisy(0.4, &mut rng), &reference, 64, 64, None).unwrap();
    assert!(high.flip > 2.0 * low.flip, "{} vs {}", high.flip, low.flip);
    assert!(high.rmse > low.rmse);
    // A mask that keeps only an unchanged half sees no error there.
    let mut test = reference.clone();
    for p in test.iter_mut().skip(32 * 64) {
        *p = [5.0, 5.0, 5.0];
    }
    let mask: Vec<bool> = (0..64 * 64).map(|i| i < 16 * 64).collect();
    let (masked, _) = compare(&test, &reference, 64, 64, Some(&mask)).unwrap();
    assert_eq!(masked.pixels, 16 * 64);
    assert_eq!(masked.rmse, 0.0);
}

#[test]
fn bad_inputs_are_reported() {
    let reference = gradient(8, 8);
    let mut test = reference.clone();
    test[3] = [f32::NAN, 0.0, f32::INFINITY];
    let (m, _) = compare(&test, &reference, 8, 8, None).unwrap();
    assert_eq!(m.non_finite, 1);
    assert!(m.rmse.is_finite() && m.rmse > 0.0);
    assert!(compare(&test[..10], &reference, 8, 8, None).is_err());
    assert!(compare(&test, &reference, 8, 8, Some(&[true; 3])).is_err());
}

#[test]
fn cheap_rmse_equals_the_rmse_compare_reports() {
    let mut rng = Pcg32::seed_from_u64(11);
    let (w, h) = (24, 16);
    let reference: Vec<[f32; 3]> = (0..w * h)
        .map(|_| [rng.random(), rng.random(), rng.random()])
        .collect();
    let test: Vec<[f32; 3]> = reference
        .iter()
        .map(|p| p.map(|c| c + rng.random_range(-0.2..0.2)))
        .collect();
    let (m, _) = compare(&test, &reference, w, h, None).unwrap();
    let cheap = solari_reference::rmse(&test, &reference);
    assert!(
        (cheap - m.rmse).abs() <= 1e-12 * m.rmse,
        "{cheap} vs {}",
        m.rmse
    );
    assert_eq!(solari_reference::rmse(&reference, &reference), 0.0);
    assert!(solari_reference::rmse(&[[f32::NAN, 0.0, 0.0]], &[[0.0; 3]]).is_nan());
}

/// A test image against a noisy reference whose per-pixel variance is known: the noise adds
/// its variance to the measured errors, and `reference_noise` takes it back out.
#[test]
fn the_reference_noise_is_taken_out_of_the_errors() {
    use solari_reference::metrics::reference_noise;
    let (w, h) = (256u32, 256u32);
    let mut rng = Pcg32::seed_from_u64(11);
    let n = (w * h) as usize;
    let truth: Vec<[f32; 3]> = (0..n)
        .map(|_| [0; 3].map(|_| rng.random_range(0.2f32..2.0)))
        .collect();
    // A test image 6% too bright in its left half and noisy everywhere, independently of
    // the reference's noise.
    let test: Vec<[f32; 3]> = truth
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let gain = if (i as u32 % w) < w / 2 { 1.06 } else { 1.0 };
            t.map(|c| c * gain + c * 0.02 * normal(&mut rng))
        })
        .collect();
    // The reference: truth plus Gaussian noise of a known, varying standard deviation, at
    // most 5% of the value: relMSE divides by the noisy reference, which correlates its
    // noise with the error, so its excess is exact only to the order of the reference's
    // relative variance times the test image's relative error (at 10% the excess read 14%
    // high here, at 5% 5% high).
    let sigma: Vec<[f32; 3]> = truth
        .iter()
        .map(|t| t.map(|c| c * rng.random_range(0.0f32..0.05)))
        .collect();
    let reference: Vec<[f32; 3]> = truth
        .iter()
        .zip(&sigma)
        .map(|(t, s)| [0, 1, 2].map(|c| t[c] + s[c] * normal(&mut rng)))
        .collect();
    let variance: Vec<[f32; 3]> = sigma.iter().map(|s| s.map(|c| c * c)).collect();
    let (own, _) = compare(&test, &truth, w, h, None).unwrap();
    let (measured, _) = compare(&test, &reference, w, h, None).unwrap();
    let noise = reference_noise(&measured, &reference, &variance, None).unwrap();
    eprintln!(
        "relMSE against the truth {:.6}, against the reference {:.6}, noise term {:.6}, excess {:.6}",
        own.rel_mse, measured.rel_mse, noise.rel_mse, noise.rel_mse_excess
    );
    // The noise is a large share of the measured error (the check below could fail)...
    assert!(measured.rel_mse > 1.3 * own.rel_mse);
    // ...and with it taken out, RMSE is the test image's own (the MSE's correction is exact
    // in expectation) and relMSE nearly so: 5% high here (43% without the correction; the
    // rest is the noisy denominator's correlation with the error, see above).
    assert!(
        (noise.rel_mse_excess / own.rel_mse - 1.0).abs() < 0.08,
        "excess relMSE {} against {}",
        noise.rel_mse_excess,
        own.rel_mse
    );
    assert!(
        (noise.rmse_excess / own.rmse - 1.0).abs() < 0.02,
        "excess RMSE {} against {}",
        noise.rmse_excess,
        own.rmse
    );
    // A mask selects pixels for the noise as for the errors.
    let right: Vec<bool> = (0..n).map(|i| (i as u32 % w) >= w / 2).collect();
    let (own_right, _) = compare(&test, &truth, w, h, Some(&right)).unwrap();
    let (measured_right, _) = compare(&test, &reference, w, h, Some(&right)).unwrap();
    let noise_right =
        reference_noise(&measured_right, &reference, &variance, Some(&right)).unwrap();
    assert!((noise_right.rel_mse_excess / own_right.rel_mse - 1.0).abs() < 0.08);
    // Bad variance images are refused.
    assert!(reference_noise(&measured, &reference, &variance[1..], None).is_err());
    for bad in [-1e-3, f32::NAN, f32::INFINITY] {
        let mut v = variance.clone();
        v[7][1] = bad;
        assert!(
            reference_noise(&measured, &reference, &v, None).is_err(),
            "{bad}"
        );
    }
    assert!(reference_noise(&measured, &reference, &variance, Some(&right[1..])).is_err());
}

/// A standard normal deviate (Box–Muller).
fn normal(rng: &mut Pcg32) -> f32 {
    let u1: f32 = rng.random_range(f32::EPSILON..1.0);
    let u2: f32 = rng.random_range(0.0..1.0);
    (-2.0 * u1.ln()).sqrt() * (std::f32::consts::TAU * u2).cos()
}
