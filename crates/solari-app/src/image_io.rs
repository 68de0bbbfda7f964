//! Image output and input: linear EXR for data, tone-mapped PNG for looking.
//!
//! The PNG tone curve is stated so images can be compared: radiance × 2^exposure, then
//! Narkowicz's fitted ACES curve (`x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14)`), then the
//! sRGB transfer function. Non-finite pixels are written black in the PNG.

use image::{ImageBuffer, Rgb};
use std::path::Path;

/// Writes linear radiance as a 32-bit float RGB EXR.
pub fn write_exr(path: &Path, width: u32, height: u32, pixels: &[[f32; 3]]) -> Result<(), String> {
    let data: Vec<f32> = pixels.iter().flatten().copied().collect();
    let img: ImageBuffer<Rgb<f32>, Vec<f32>> = ImageBuffer::from_raw(width, height, data)
        .ok_or_else(|| {
            format!(
                "{}: pixel count does not match {width}x{height}",
                path.display()
            )
        })?;
    img.save(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Reads an EXR (or any format `image` reads) as linear RGB f32.
pub fn read_linear(path: &Path) -> Result<(u32, u32, Vec<[f32; 3]>), String> {
    let img = image::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let rgb = img.to_rgb32f();
    let (w, h) = rgb.dimensions();
    let pixels = rgb.pixels().map(|p| p.0).collect();
    Ok((w, h, pixels))
}

/// Narkowicz's ACES fit, per channel.
pub fn aces(x: f32) -> f32 {
    let x = x.max(0.0);
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// sRGB transfer function of a value in \[0, 1\].
pub fn srgb_encode(l: f32) -> f32 {
    if l <= 0.0031308 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

/// Tone-maps linear radiance to 8-bit sRGB with the documented curve.
pub fn tone_map(pixels: &[[f32; 3]], exposure_ev: f32) -> Vec<u8> {
    let scale = exposure_ev.exp2();
    let mut out = Vec::with_capacity(pixels.len() * 3);
    for p in pixels {
        for &c in p {
            let v = if c.is_finite() {
                srgb_encode(aces(c * scale))
            } else {
                0.0
            };
            out.push((v * 255.0 + 0.5) as u8);
        }
    }
    out
}

/// Writes a tone-mapped PNG.
pub fn write_png(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[[f32; 3]],
    exposure_ev: f32,
) -> Result<(), String> {
    let bytes = tone_map(pixels, exposure_ev);
    image::save_buffer(path, &bytes, width, height, image::ExtendedColorType::Rgb8)
        .map_err(|e| format!("{}: {e}", path.display()))
}
