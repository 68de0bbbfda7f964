//! Image error metrics: RMSE, relative MSE and FLIP, over all pixels or a mask.
//!
//! FLIP comes from NVIDIA's implementation through the `nv-flip` crate (LDR-FLIP on 8-bit
//! sRGB). For HDR images we report LDR-FLIP at exposure 0 after the PNG tone curve
//! ([`crate::image_io::tone_map`]) and an HDR-aware variant in the spirit of HDR-FLIP: the
//! per-pixel maximum of LDR-FLIP over exposures −3..+3 stops in whole stops. It is not
//! NVIDIA's HDR-FLIP (whose exposure range comes from the reference's luminance), so compare
//! its values only with ours.

use crate::image_io::tone_map;

/// Exposures (stops) over which the HDR-aware FLIP takes its per-pixel maximum.
pub const HDR_EXPOSURES: [f32; 7] = [-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0];

/// Errors of a test image against a reference.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Metrics {
    /// Root-mean-square error over pixels and channels.
    pub rmse: f64,
    /// Mean of (test − ref)² / (ref² + 0.01) over pixels and channels.
    pub rel_mse: f64,
    /// Mean LDR-FLIP at exposure 0.
    pub flip: f64,
    /// Mean of the per-pixel maximum LDR-FLIP over [`HDR_EXPOSURES`].
    pub flip_hdr: f64,
    /// Pixels counted (the mask's size, or all).
    pub pixels: usize,
    /// Test pixels that were not finite (counted as errors of the reference's magnitude + 1).
    pub non_finite: usize,
    /// The test image's mean over the reference's (all channels, finite test pixels only):
    /// how much of the reference's light the test image has (1 for none missing). NaN when
    /// the reference is black.
    pub mean_ratio: f64,
}

/// FLIP's viewing condition: 0.7 m from a 24-inch 4K monitor, its default.
fn ppd() -> f32 {
    nv_flip::DEFAULT_PIXELS_PER_DEGREE
}

fn flip_map(test: &[[f32; 3]], reference: &[[f32; 3]], w: u32, h: u32, ev: f32) -> Vec<f32> {
    let r = nv_flip::FlipImageRgb8::with_data(w, h, &tone_map(reference, ev));
    let t = nv_flip::FlipImageRgb8::with_data(w, h, &tone_map(test, ev));
    nv_flip::flip(r, t, ppd()).to_vec()
}

/// Compares `test` with `reference` (both `w`×`h`, row-major linear RGB). `mask` keeps the
/// pixels where it is true. Returns the metrics and the per-pixel HDR-aware FLIP map.
pub fn compare(
    test: &[[f32; 3]],
    reference: &[[f32; 3]],
    w: u32,
    h: u32,
    mask: Option<&[bool]>,
) -> Result<(Metrics, Vec<f32>), String> {
    let n = w as usize * h as usize;
    if test.len() != n || reference.len() != n {
        return Err(format!(
            "image sizes differ: {} and {} pixels for {w}x{h}",
            test.len(),
            reference.len()
        ));
    }
    if mask.is_some_and(|m| m.len() != n) {
        return Err("mask size differs from the images".into());
    }
    let keep = |i: usize| mask.is_none_or(|m| m[i]);
    let ldr = flip_map(test, reference, w, h, 0.0);
    // Exposure 0 is the LDR map itself: start from it rather than computing it again.
    let mut hdr = ldr.clone();
    for ev in HDR_EXPOSURES.into_iter().filter(|&ev| ev != 0.0) {
        for (m, v) in hdr.iter_mut().zip(flip_map(test, reference, w, h, ev)) {
            *m = m.max(v);
        }
    }
    let mut out = Metrics::default();
    let (mut se, mut rel, mut fl, mut fh) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (mut test_sum, mut ref_sum) = (0.0f64, 0.0f64);
    for i in (0..n).filter(|&i| keep(i)) {
        out.pixels += 1;
        let finite = test[i].iter().all(|c| c.is_finite());
        if !finite {
            out.non_finite += 1;
        } else {
            test_sum += test[i].iter().map(|&c| c as f64).sum::<f64>();
            ref_sum += reference[i].iter().map(|&c| c as f64).sum::<f64>();
        }
        for c in 0..3 {
            let b = reference[i][c] as f64;
            let a = if finite {
                test[i][c] as f64
            } else {
                b.abs() + 1.0
            };
            let d = a - b;
            se += d * d;
            rel += d * d / (b * b + 0.01);
        }
        fl += ldr[i] as f64;
        fh += hdr[i] as f64;
    }
    let count = out.pixels.max(1) as f64;
    out.rmse = (se / (3.0 * count)).sqrt();
    out.rel_mse = rel / (3.0 * count);
    out.flip = fl / count;
    out.flip_hdr = fh / count;
    out.mean_ratio = if ref_sum > 0.0 {
        test_sum / ref_sum
    } else {
        f64::NAN
    };
    Ok((out, hdr))
}

/// Root-mean-square difference over every channel of two images of the same size, in f64:
/// [`compare`]'s `rmse` without its mask, FLIP maps and non-finite handling (a NaN pixel
/// gives NaN), cheap enough to call every frame in a test. Panics if the sizes differ (a
/// caller's mistake, like a slice index out of range).
pub fn rmse(image: &[[f32; 3]], reference: &[[f32; 3]]) -> f64 {
    assert_eq!(
        image.len(),
        reference.len(),
        "rmse of images of different sizes"
    );
    if image.is_empty() {
        return 0.0;
    }
    let sum: f64 = image
        .iter()
        .zip(reference)
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] as f64 - b[c] as f64).powi(2)))
        .sum();
    (sum / (image.len() * 3) as f64).sqrt()
}

/// The share of [`compare`]'s errors that the reference's own noise accounts for, from the
/// reference's per-pixel variance ([`crate::path_tracer::ReferenceImage::variance`]).
///
/// A finite-sample reference `r` is the truth plus noise, so for a test image `x` whose
/// errors do not depend on that noise, E[(x − r)²] = (x − truth)² + Var(r) per pixel:
/// every error measured against it carries Var(r) on top of the test image's own. On a
/// scene lit mostly indirectly this is no small term: `interior`'s 1024-spp reference at
/// 960×540 puts more than twice as much into relMSE as a converged real-time frame's own
/// error (`benches/RESULTS.md`, "The reference's own noise"). Subtracting the reference's
/// variance estimate gives an unbiased estimate of the test image's MSE. relMSE divides by
/// the noisy reference, whose noise then correlates with the error, so its excess is right
/// only to the order of the reference's relative variance times the test image's relative
/// error: 5% high in `tests/metrics.rs`'s case, where the uncorrected figure is 43% high.
/// An excess can be slightly negative for a test image closer to the truth than the
/// reference's noise lets one tell.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ReferenceNoise {
    /// The mean of the reference's variance over pixels and channels: what its noise adds to
    /// the MSE (RMSE²).
    pub mse: f64,
    /// The mean of variance / (reference² + 0.01): what its noise adds to relMSE.
    pub rel_mse: f64,
    /// RMSE with the reference's noise taken out: √max(0, RMSE² − `mse`).
    pub rmse_excess: f64,
    /// relMSE less `rel_mse`: the test image's own relMSE against the truth, estimated.
    pub rel_mse_excess: f64,
}

/// [`ReferenceNoise`] of `metrics` (from [`compare`] with the same `reference` and `mask`),
/// given the reference's per-pixel `variance`. Errors if the sizes differ or a variance is
/// negative or not finite.
pub fn reference_noise(
    metrics: &Metrics,
    reference: &[[f32; 3]],
    variance: &[[f32; 3]],
    mask: Option<&[bool]>,
) -> Result<ReferenceNoise, String> {
    if variance.len() != reference.len() {
        return Err(format!(
            "the variance image has {} pixels, the reference {}",
            variance.len(),
            reference.len()
        ));
    }
    if mask.is_some_and(|m| m.len() != reference.len()) {
        return Err("mask size differs from the images".into());
    }
    if let Some(i) = variance
        .iter()
        .position(|v| v.iter().any(|c| !(c.is_finite() && *c >= 0.0)))
    {
        return Err(format!(
            "variance pixel {i} is {:?}: a variance is finite and not negative",
            variance[i]
        ));
    }
    let (mut sum, mut rel, mut count) = (0.0f64, 0.0f64, 0usize);
    for i in (0..reference.len()).filter(|&i| mask.is_none_or(|m| m[i])) {
        count += 1;
        for c in 0..3 {
            let v = variance[i][c] as f64;
            let b = reference[i][c] as f64;
            sum += v;
            rel += v / (b * b + 0.01);
        }
    }
    let n = 3.0 * count.max(1) as f64;
    let (mse, rel_mse) = (sum / n, rel / n);
    Ok(ReferenceNoise {
        mse,
        rel_mse,
        rmse_excess: (metrics.rmse * metrics.rmse - mse).max(0.0).sqrt(),
        rel_mse_excess: metrics.rel_mse - rel_mse,
    })
}

/// A FLIP error map as a colour heat map (magma), 8-bit RGB.
pub fn heatmap(map: &[f32], w: u32, h: u32) -> Vec<u8> {
    let img = nv_flip::FlipImageFloat::with_data(w, h, map);
    img.apply_color_lut(&nv_flip::magma_lut()).to_vec()
}
