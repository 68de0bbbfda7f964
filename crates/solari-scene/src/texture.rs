//! Texture decoding (with size limits read from the image header before decoding) and
//! mip-chain generation.

use crate::asset_io::ImportLimits;
use crate::model::{ColorSpace, MipLevel, Texture};

/// Decodes an encoded image (PNG, JPEG) into RGBA8 with a full mip chain, under the default
/// [`ImportLimits`].
///
/// Mips are box-filtered in linear light for sRGB textures (averaging encoded values would
/// darken them) and directly for data textures.
pub fn decode_texture(
    bytes: &[u8],
    name: &str,
    color_space: ColorSpace,
    repeat: bool,
) -> Result<Texture, String> {
    let level0 = decode_image(bytes, name, &ImportLimits::default())?;
    Ok(texture_from_level0(level0, name, color_space, repeat))
}

/// Decodes an encoded image into RGBA8 level 0. The header's size is checked against
/// `limits` before any pixel memory is allocated, and the decoder itself is capped too.
pub fn decode_image(bytes: &[u8], name: &str, limits: &ImportLimits) -> Result<MipLevel, String> {
    let (w, h) = check_image_header(bytes, name, limits)?;
    let pixels = w as u64 * h as u64;
    let mut decoder = reader(bytes, name)?;
    let mut caps = image::Limits::default();
    caps.max_image_width = Some(w);
    caps.max_image_height = Some(h);
    // RGBA of 32-bit floats is the widest a decoder produces, plus its own buffers.
    caps.max_alloc = Some(pixels * 16 + (64 << 20));
    decoder.limits(caps);
    let img = decoder
        .decode()
        .map_err(|e| format!("cannot decode {name}: {e}"))?;
    let rgba = img.to_rgba8();
    let (w, h) = rgba.dimensions();
    Ok(MipLevel {
        width: w,
        height: h,
        rgba8: rgba.into_raw(),
    })
}

fn reader<'a>(
    bytes: &'a [u8],
    name: &str,
) -> Result<image::ImageReader<std::io::Cursor<&'a [u8]>>, String> {
    image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("cannot read {name}: {e}"))
}

/// The size an encoded image's header declares, refused when it is empty or over `limits`
/// (nothing is decoded).
pub fn check_image_header(
    bytes: &[u8],
    name: &str,
    limits: &ImportLimits,
) -> Result<(u32, u32), String> {
    let (w, h) = reader(bytes, name)?
        .into_dimensions()
        .map_err(|e| format!("cannot decode {name}: {e}"))?;
    if w == 0 || h == 0 {
        return Err(format!("{name} has zero size"));
    }
    let pixels = w as u64 * h as u64;
    if w > limits.max_image_side || h > limits.max_image_side || pixels > limits.max_image_pixels {
        return Err(format!(
            "{name} is {w}x{h}, over the image limit ({} pixels, {} per side)",
            limits.max_image_pixels, limits.max_image_side
        ));
    }
    Ok((w, h))
}

/// A texture with a full mip chain from a decoded level 0.
pub fn texture_from_level0(
    level0: MipLevel,
    name: &str,
    color_space: ColorSpace,
    repeat: bool,
) -> Texture {
    Texture {
        name: name.to_string(),
        color_space,
        mips: build_mips(level0, color_space),
        repeat,
    }
}

/// Builds the full mip chain down to 1×1 from level 0.
pub fn build_mips(level0: MipLevel, cs: ColorSpace) -> Vec<MipLevel> {
    let mut mips = vec![level0];
    loop {
        let prev = mips.last().expect("level 0 exists");
        if prev.width == 1 && prev.height == 1 {
            break;
        }
        let next = downsample(prev, cs);
        mips.push(next);
    }
    mips
}

impl Texture {
    /// The mean colour of the texture in linear light (RGB), over its full-resolution level:
    /// what a light's emitted power needs. (The smallest mip is that mean too, but stored in
    /// 8-bit sRGB, 0.6% off for a black-and-white checker.)
    pub fn mean_linear(&self) -> glam::Vec3 {
        let Some(level) = self.mips.first() else {
            return glam::Vec3::ONE;
        };
        let lut: [f64; 256] = std::array::from_fn(|c| match self.color_space {
            ColorSpace::Srgb => srgb_to_linear(c as u8) as f64,
            _ => c as f64 / 255.0,
        });
        let mut sum = [0.0f64; 3];
        let mut n = 0usize;
        for t in level.rgba8.chunks_exact(4) {
            for k in 0..3 {
                sum[k] += lut[t[k] as usize];
            }
            n += 1;
        }
        let n = n.max(1) as f64;
        glam::Vec3::new(
            (sum[0] / n) as f32,
            (sum[1] / n) as f32,
            (sum[2] / n) as f32,
        )
    }
}

fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb(l: f32) -> u8 {
    let l = l.clamp(0.0, 1.0);
    let c = if l <= 0.0031308 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (c * 255.0 + 0.5) as u8
}

fn downsample(src: &MipLevel, cs: ColorSpace) -> MipLevel {
    let w = (src.width / 2).max(1);
    let h = (src.height / 2).max(1);
    let mut out = vec![0u8; (w * h * 4) as usize];
    for y in 0..h {
        for x in 0..w {
            for c in 0..4 {
                let mut sum = 0.0;
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let sx = (x * 2 + dx).min(src.width - 1);
                    let sy = (y * 2 + dy).min(src.height - 1);
                    let v = src.rgba8[((sy * src.width + sx) * 4 + c) as usize];
                    sum += if cs == ColorSpace::Srgb && c < 3 {
                        srgb_to_linear(v)
                    } else {
                        v as f32 / 255.0
                    };
                }
                let avg = sum * 0.25;
                out[((y * w + x) * 4 + c) as usize] = if cs == ColorSpace::Srgb && c < 3 {
                    linear_to_srgb(avg)
                } else {
                    (avg * 255.0 + 0.5) as u8
                };
            }
        }
    }
    MipLevel {
        width: w,
        height: h,
        rgba8: out,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mip_chain_reaches_one_texel_and_keeps_mean() {
        let (w, h) = (8u32, 4u32);
        let rgba8: Vec<u8> = (0..w * h * 4).map(|i| ((i * 37) % 256) as u8).collect();
        let mips = build_mips(
            MipLevel {
                width: w,
                height: h,
                rgba8: rgba8.clone(),
            },
            ColorSpace::Linear,
        );
        assert_eq!(mips.len(), 4);
        assert_eq!((mips[3].width, mips[3].height), (1, 1));
        let mean0: f32 = rgba8.iter().step_by(4).map(|&v| v as f32).sum::<f32>() / (w * h) as f32;
        assert!((mips[3].rgba8[0] as f32 - mean0).abs() <= 2.0);
    }

    #[test]
    fn srgb_mips_average_in_linear_light() {
        // Black and white checker: the linear mean is 0.5, which sRGB-encodes to 188, not 128.
        let rgba8 = vec![
            0, 0, 0, 255, 255, 255, 255, 255, 255, 255, 255, 255, 0, 0, 0, 255,
        ];
        let mips = build_mips(
            MipLevel {
                width: 2,
                height: 2,
                rgba8,
            },
            ColorSpace::Srgb,
        );
        assert!((mips[1].rgba8[0] as i32 - 188).abs() <= 1);
    }

    #[test]
    fn garbage_bytes_are_an_error() {
        assert!(decode_texture(b"not an image", "x", ColorSpace::Srgb, true).is_err());
    }
}
