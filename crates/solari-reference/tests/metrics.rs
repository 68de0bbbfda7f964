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
