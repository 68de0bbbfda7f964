//! Image output and input: linear EXR for data, tone-mapped PNG for looking.
//!
//! The PNG tone curve is stated so images can be compared: radiance × 2^exposure, then
//! Narkowicz's fitted ACES curve (`x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14)`), then the
//! sRGB transfer function. Non-finite pixels are written black in the PNG. Files are written
//! by the caller; `solari-app`'s `output` module checks paths first and writes atomically.

use image::{ImageBuffer, Rgb};
use std::path::Path;

/// Encodes linear radiance as a 32-bit float RGB EXR file in memory.
pub fn encode_exr(width: u32, height: u32, pixels: &[[f32; 3]]) -> Result<Vec<u8>, String> {
    let data: Vec<f32> = pixels.iter().flatten().copied().collect();
    let img: ImageBuffer<Rgb<f32>, Vec<f32>> = ImageBuffer::from_raw(width, height, data)
        .ok_or_else(|| {
            format!(
                "{} pixels do not make a {width}x{height} image",
                pixels.len()
            )
        })?;
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::OpenExr)
        .map_err(|e| format!("EXR encoding: {e}"))?;
    Ok(out.into_inner())
}

/// Reads an EXR (or any format `image` reads) as linear RGB f32.
///
/// The file goes through the importer's limits: a regular file of at most 2 GiB whose header
/// declares at most 2^26 pixels (see [`solari_scene::ImportLimits`]), checked before decoding.
pub fn read_linear(path: &Path) -> Result<(u32, u32, Vec<[f32; 3]>), String> {
    let limits = solari_scene::ImportLimits::default();
    let bytes = solari_scene::asset_io::read_file_limited(path, limits.max_file_bytes)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let name = path.display().to_string();
    solari_scene::texture::check_image_header(&bytes, &name, &limits)?;
    let img = image::load_from_memory(&bytes).map_err(|e| format!("{name}: {e}"))?;
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

/// Encodes a tone-mapped 8-bit sRGB PNG file in memory.
pub fn encode_png(
    width: u32,
    height: u32,
    pixels: &[[f32; 3]],
    exposure_ev: f32,
) -> Result<Vec<u8>, String> {
    encode_png_rgb8(width, height, &tone_map(pixels, exposure_ev))
}

/// Encodes 8-bit RGB rows as a PNG file in memory.
pub fn encode_png_rgb8(width: u32, height: u32, rgb8: &[u8]) -> Result<Vec<u8>, String> {
    if rgb8.len() as u64 != width as u64 * height as u64 * 3 {
        return Err(format!(
            "{} bytes do not make a {width}x{height} RGB image",
            rgb8.len()
        ));
    }
    let mut out = std::io::Cursor::new(Vec::new());
    image::write_buffer_with_format(
        &mut out,
        rgb8,
        width,
        height,
        image::ExtendedColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| format!("PNG encoding: {e}"))?;
    Ok(out.into_inner())
}
