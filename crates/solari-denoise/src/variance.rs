//! Rust twin of the fallback denoiser's variance arithmetic (`denoise_variance_math.wesl`):
//! the variance pass's estimate and the per-pixel data the temporal pass leaves for it, held
//! to the GPU by `tests/variance_twin.rs`.

/// Weighted sums over a pixel's 5×5 window (WGSL `WindowSums`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WindowSums {
    /// Σ w · the taps' mean luminance.
    pub m1: f32,
    /// Σ w · the taps' mean squared luminance.
    pub m2: f32,
    /// As `m1`, over the shadow-free signal (each tap's light plus what its shadow ray
    /// removed).
    pub f1: f32,
    /// As `m2`, over the shadow-free signal.
    pub f2: f32,
    /// Σ w.
    pub weight: f32,
    /// Whether every penumbra in the window is narrower than a pixel.
    pub sharp: bool,
}

fn mix(a: f32, b: f32, t: f32) -> f32 {
    a * (1.0 - t) + b * t
}

/// The luminance variance the à-trous passes get for a pixel with `length` frames of history
/// and `temporal`, the variance of its own moments; `window` holds its window's sums where
/// the pass read them. Where the window is sharp, `temporal` is capped by the shadow-free
/// window's variance; while the history is shorter than 2 × `frames`
/// ([`crate::FallbackSettings::spatial_variance_frames`]) the window's estimate, boosted for
/// few frames, hands over to the temporal one geometrically. Non-finite and negative results
/// give 0.
pub fn pixel_variance(temporal: f32, window: Option<WindowSums>, length: f32, frames: f32) -> f32 {
    let mut variance = temporal;
    if let Some(s) = window {
        let (m1, m2) = if s.sharp { (s.f1, s.f2) } else { (s.m1, s.m2) };
        let (m1, m2) = (m1 / s.weight.max(1e-12), m2 / s.weight.max(1e-12));
        let spread = (m2 - m1 * m1).max(0.0);
        if s.sharp {
            variance = variance.min(spread);
        }
        if length < 2.0 * frames {
            let boost = (frames / length.max(1.0)).max(1.0);
            let t = ((length - 1.0) / (2.0 * frames - 1.0).max(1.0)).clamp(0.0, 1.0);
            let spatial = (spread * boost).max(1e-30);
            variance = mix(spatial.ln(), variance.max(1e-30).ln(), t).exp();
        }
    }
    if variance.is_nan() {
        0.0
    } else {
        variance.max(0.0)
    }
}

/// A penumbra narrower than this many pixels is a hard edge (WGSL `PENUMBRA_SHARP_PIXELS` in
/// `denoise_variance_math.wesl`).
pub const PENUMBRA_SHARP_PIXELS: f32 = 1.0;

/// Albedos below this are raised to it before demodulating (WGSL `ALBEDO_FLOOR` in
/// `denoise_variance_math.wesl`).
pub const ALBEDO_FLOOR: f32 = 0.01;

/// The angle (as the chord between unit vectors) between view directions `d0` and `d1`, as
/// [`window_data`] measures a pixel's angle.
pub fn pixel_angle(d0: [f32; 3], d1: [f32; 3]) -> f32 {
    let unit = |d: [f32; 3]| {
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        d.map(|v| v / l)
    };
    let (a, b) = (unit(d0), unit(d1));
    (0..3)
        .map(|k| (b[k] - a[k]) * (b[k] - a[k]))
        .sum::<f32>()
        .sqrt()
}

/// What the temporal pass stores of a pixel for the variance pass's windows, `[m1, m2,
/// removed, w]` (WGSL `window_data`, which says what each part is): the history's luminance
/// `moments` (w = −1 without history, `history_length` ≤ 0); with `shadow` (the renderer's
/// pair for the pixel, unpacked: the luminance its shadow ray removed, the penumbra width in
/// world units) the removed luminance over `albedo`'s, and w = 1 where the penumbra is
/// narrower than [`PENUMBRA_SHARP_PIXELS`] pixels at `view_z`, a pixel's angle being that
/// between the view directions `d0` and `d1`.
pub fn window_data(
    moments: [f32; 2],
    history_length: f32,
    shadow: Option<[f32; 2]>,
    albedo: [f32; 3],
    d0: [f32; 3],
    d1: [f32; 3],
    view_z: f32,
) -> [f32; 4] {
    if history_length <= 0.0 {
        return [0.0, 0.0, 0.0, -1.0];
    }
    let Some([removed_light, penumbra]) = shadow else {
        return [moments[0], moments[1], 0.0, 1.0];
    };
    // Rec. 709, as the WGSL `luminance`.
    let luminance = 0.2126 * albedo[0] + 0.7152 * albedo[1] + 0.0722 * albedo[2];
    let removed = removed_light / luminance.max(ALBEDO_FLOOR);
    let sharp = penumbra < PENUMBRA_SHARP_PIXELS * pixel_angle(d0, d1) * view_z;
    [
        moments[0],
        moments[1],
        removed,
        if sharp { 1.0 } else { 0.0 },
    ]
}

#[cfg(test)]
mod tests {
    use super::{WindowSums, pixel_variance};

    fn sums(m1: f32, m2: f32, f1: f32, f2: f32, sharp: bool) -> WindowSums {
        WindowSums {
            m1,
            m2,
            f1,
            f2,
            weight: 1.0,
            sharp,
        }
    }

    #[test]
    fn a_sharp_window_caps_and_a_wide_one_does_not() {
        // Shadow-free spread 0.04 − 0.2² = 0; with shadows 0.5 − 0.5² = 0.25.
        let sharp = sums(0.5, 0.5, 0.2, 0.04, true);
        let wide = WindowSums {
            sharp: false,
            ..sharp
        };
        // Past the young window (length 8 of 2 × 4) only the cap acts.
        assert_eq!(pixel_variance(0.3, Some(sharp), 8.0, 4.0), 0.0);
        assert_eq!(pixel_variance(0.3, Some(wide), 8.0, 4.0), 0.3);
        assert_eq!(pixel_variance(0.3, None, 8.0, 4.0), 0.3);
    }

    #[test]
    fn the_young_estimate_hands_over_geometrically() {
        let s = sums(0.5, 0.5, 0.0, 0.0, false);
        // Length 1: the boosted window alone (0.25 × 4).
        assert!((pixel_variance(1e-3, Some(s), 1.0, 4.0) - 1.0).abs() < 1e-6);
        // Halfway (t = 0.5 at length 4.5, where the boost is spent): the geometric mean of
        // 0.25 and 1e-3.
        let want = (0.25 * 1e-3f32).sqrt();
        assert!((pixel_variance(1e-3, Some(s), 4.5, 4.0) - want).abs() < 1e-6 * want.max(1.0));
    }

    #[test]
    fn nan_and_negative_give_zero() {
        assert_eq!(pixel_variance(f32::NAN, None, 20.0, 4.0), 0.0);
        assert_eq!(pixel_variance(-1.0, None, 20.0, 4.0), 0.0);
        assert_eq!(
            pixel_variance(f32::INFINITY, None, 20.0, 4.0),
            f32::INFINITY
        );
    }
}
