//! Environment maps: radiance arriving from infinitely far away, stored as an equirectangular
//! (latitude–longitude) HDR image.
//!
//! # Convention
//!
//! Row 0 is straight up (+Y, glTF's up axis) and the last row straight down; u runs around the
//! horizon with the image's centre column (u = 0.5) towards −Z, the way a glTF camera with no
//! rotation looks, and u = 0.75 towards +X. A direction `d` maps to
//! `u = 0.5 + atan2(d.x, −d.z) / 2π`, `v = acos(d.y) / π` ([`direction_to_uv`]).
//! Radiance between texel centres is bilinear, wrapping around in u and clamped in v; the WGSL
//! twin (`environment.wesl`) reads the same four texels with the same weights.
//!
//! # Limits and fallbacks
//!
//! - Only HDR images are read: Radiance `.hdr` and OpenEXR `.exr` (8-bit images hold display
//!   values, not radiance).
//! - A file's size is read from its header first: over [`MAX_FILE_TEXELS`] (16384 × 8192) it is
//!   refused before any pixel is decoded, so a 32k × 16k map cannot exhaust memory.
//! - Maps wider than [`EnvironmentOptions::max_width`] (4096 by default, 64 MiB on the GPU) are
//!   halved with a 2 × 2 box filter until they fit; the log says so.
//! - Negative, NaN and infinite texels become 0 and texels above [`crate::MAX_RADIANCE`] are
//!   clamped to it; [`EnvironmentMap::repaired_texels`] counts both and the loader logs a
//!   warning.

use crate::error::SceneError;
use glam::{Vec2, Vec3};
use std::path::Path;

/// The most texels a file may declare (16384 × 8192); larger files are refused unread.
pub const MAX_FILE_TEXELS: u64 = 16384 * 8192;

/// How [`EnvironmentMap::load`] prepares a file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EnvironmentOptions {
    /// Maps wider than this are box-filtered down by halves until they fit (at least 1).
    pub max_width: u32,
}

impl Default for EnvironmentOptions {
    fn default() -> Self {
        // 4096 × 2048 half-float RGBA is 64 MiB on the GPU, and about 5 texels per degree.
        Self { max_width: 4096 }
    }
}

/// An equirectangular environment map in linear radiance (see the module docs for its
/// orientation). Multiplied by `Scene::environment_radiance` when rendered.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    width: u32,
    height: u32,
    texels: Vec<Vec3>,
    repaired: u64,
    // The texels never change after construction, so their solid-angle mean is taken once:
    // the light list and the light grid each read it on every rebuild (a 4096 × 2048 map is
    // 8 M texels).
    mean: Vec3,
}

/// The equirectangular coordinates of unit direction `d` (u in [0, 1), v in [0, 1]).
pub fn direction_to_uv(d: Vec3) -> Vec2 {
    let u = 0.5 + d.x.atan2(-d.z) * (0.5 * std::f32::consts::FRAC_1_PI);
    let v = d.y.clamp(-1.0, 1.0).acos() * std::f32::consts::FRAC_1_PI;
    Vec2::new(u - u.floor(), v)
}

/// The unit direction at equirectangular coordinates `uv`; the inverse of [`direction_to_uv`].
pub fn uv_to_direction(uv: Vec2) -> Vec3 {
    let phi = (uv.x - 0.5) * std::f32::consts::TAU;
    let theta = uv.y * std::f32::consts::PI;
    let s = theta.sin();
    Vec3::new(s * phi.sin(), theta.cos(), -s * phi.cos())
}

impl EnvironmentMap {
    /// A map from `width × height` texels in row-major order. Unusable texels are repaired as
    /// the module docs say; an empty map or a texel count that does not match is refused.
    pub fn new(width: u32, height: u32, texels: Vec<Vec3>) -> Result<Self, String> {
        if width == 0 || height == 0 {
            return Err(format!(
                "an environment map of {width} x {height} texels is empty"
            ));
        }
        if texels.len() as u64 != width as u64 * height as u64 {
            return Err(format!(
                "{} texels given for a {width} x {height} environment map",
                texels.len()
            ));
        }
        let mut map = Self {
            width,
            height,
            texels,
            repaired: 0,
            mean: Vec3::ZERO,
        };
        for t in &mut map.texels {
            let fixed = t.to_array().map(|c| {
                if c.is_nan() || c < 0.0 {
                    0.0
                } else {
                    c.min(crate::MAX_RADIANCE)
                }
            });
            if fixed != t.to_array() {
                map.repaired += 1;
                *t = Vec3::from_array(fixed);
            }
        }
        map.mean = map.solid_angle_mean();
        Ok(map)
    }

    /// One texel of constant radiance: a uniform environment.
    pub fn uniform(radiance: Vec3) -> Result<Self, String> {
        Self::new(1, 1, vec![radiance])
    }

    /// Reads an `.hdr` or `.exr` file, with the checks and fallbacks of the module docs.
    pub fn load(path: impl AsRef<Path>, options: &EnvironmentOptions) -> Result<Self, SceneError> {
        let path = path.as_ref();
        let fail = |reason: String| SceneError::Environment {
            file: path.to_path_buf(),
            reason,
        };
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let format = match ext.as_deref() {
            Some("hdr") => image::ImageFormat::Hdr,
            Some("exr") => image::ImageFormat::OpenExr,
            _ => {
                return Err(fail(
                    "environment maps must be HDR images: Radiance .hdr or OpenEXR .exr".into(),
                ));
            }
        };
        let meta = std::fs::metadata(path).map_err(|e| fail(format!("cannot read: {e}")))?;
        if !meta.is_file() {
            return Err(fail("cannot read: not a regular file".into()));
        }
        let open = || -> Result<image::ImageReader<_>, SceneError> {
            let file = std::fs::File::open(path).map_err(|e| fail(format!("cannot read: {e}")))?;
            Ok(image::ImageReader::with_format(
                std::io::BufReader::new(file),
                format,
            ))
        };
        // The header alone first: a file over the limit is refused before any allocation.
        let (w, h) = open()?
            .into_dimensions()
            .map_err(|e| fail(format!("not a readable {} file: {e}", format_name(format))))?;
        if w as u64 * h as u64 > MAX_FILE_TEXELS {
            return Err(fail(format!(
                "{w} x {h} texels is over the limit of {MAX_FILE_TEXELS} (16384 x 8192); \
                 downsample the map first"
            )));
        }
        let mut reader = open()?;
        let mut limits = image::Limits::default();
        // Decoded as 32-bit float RGBA at most, plus the decoder's own buffers.
        limits.max_alloc = Some(MAX_FILE_TEXELS * 16 + (64 << 20));
        reader.limits(limits);
        let image = reader
            .decode()
            .map_err(|e| fail(format!("not a readable {} file: {e}", format_name(format))))?
            .into_rgb32f();
        let texels = image
            .pixels()
            .map(|p| Vec3::from_array(p.0))
            .collect::<Vec<_>>();
        let mut map = Self::new(w, h, texels).map_err(fail)?;
        if map.repaired > 0 {
            log::warn!(
                "{}: {} texels were negative, not finite or above {:e}: set to 0 or clamped",
                path.display(),
                map.repaired,
                crate::MAX_RADIANCE
            );
        }
        if w != 2 * h {
            log::warn!(
                "{}: {w} x {h} is not 2:1; it is read as equirectangular all the same",
                path.display()
            );
        }
        let max_width = options.max_width.max(1);
        while map.width > max_width {
            map = map.halved();
        }
        if map.width != w {
            log::info!(
                "{}: environment map reduced from {w} x {h} to {} x {} texels (max width {max_width})",
                path.display(),
                map.width,
                map.height
            );
        }
        Ok(map)
    }

    /// Width in texels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The texels, row-major from the top row.
    pub fn texels(&self) -> &[Vec3] {
        &self.texels
    }

    /// The texel at column `x`, row `y`.
    pub fn texel(&self, x: u32, y: u32) -> Vec3 {
        self.texels[(y * self.width + x) as usize]
    }

    /// How many texels were negative, not finite or too bright and were repaired.
    pub fn repaired_texels(&self) -> u64 {
        self.repaired
    }

    /// The largest component of any texel.
    pub fn max_component(&self) -> f32 {
        self.texels
            .iter()
            .fold(0.0f32, |m, t| m.max(t.max_element()))
    }

    /// Radiance arriving from unit direction `d`: bilinear between texel centres, wrapping in
    /// u and clamped in v (CPU twin of `environment_texel` in `environment.wesl`).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        self.radiance_at(direction_to_uv(d))
    }

    /// Radiance at equirectangular coordinates `uv`, filtered as [`Self::radiance`].
    pub fn radiance_at(&self, uv: Vec2) -> Vec3 {
        let (w, h) = (self.width as i64, self.height as i64);
        let fx = uv.x * w as f32 - 0.5;
        let fy = uv.y * h as f32 - 0.5;
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let col = |x: i64| x.rem_euclid(w) as u32;
        let row = |y: i64| y.clamp(0, h - 1) as u32;
        let (x0, y0) = (x0 as i64, y0 as i64);
        let top = self
            .texel(col(x0), row(y0))
            .lerp(self.texel(col(x0 + 1), row(y0)), tx);
        let bottom = self
            .texel(col(x0), row(y0 + 1))
            .lerp(self.texel(col(x0 + 1), row(y0 + 1)), tx);
        top.lerp(bottom, ty)
    }

    /// The mean radiance over the sphere (texels weighted by their solid angle), computed
    /// once when the map was made.
    pub fn mean_radiance(&self) -> Vec3 {
        self.mean
    }

    fn solid_angle_mean(&self) -> Vec3 {
        let mut sum = glam::DVec3::ZERO;
        let mut weight = 0.0f64;
        for y in 0..self.height {
            let w = self.row_solid_angle(y) as f64;
            for x in 0..self.width {
                sum += self.texel(x, y).as_dvec3() * w;
            }
            weight += w * self.width as f64;
        }
        (sum / weight.max(f64::MIN_POSITIVE)).as_vec3()
    }

    /// The solid angle of one texel of row `y`.
    pub fn row_solid_angle(&self, y: u32) -> f32 {
        let pi = std::f64::consts::PI;
        let t0 = y as f64 / self.height as f64 * pi;
        let t1 = (y + 1) as f64 / self.height as f64 * pi;
        ((t0.cos() - t1.cos()) * std::f64::consts::TAU / self.width as f64) as f32
    }

    /// The map at half the width and height (rounded up), each texel the mean of the (up to)
    /// four it covers.
    pub fn halved(&self) -> Self {
        let (w, h) = (self.width.div_ceil(2), self.height.div_ceil(2));
        let mut texels = Vec::with_capacity(w as usize * h as usize);
        for y in 0..h {
            for x in 0..w {
                let mut sum = Vec3::ZERO;
                let mut n = 0.0;
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let (sx, sy) = (2 * x + dx, 2 * y + dy);
                    if sx < self.width && sy < self.height {
                        sum += self.texel(sx, sy);
                        n += 1.0;
                    }
                }
                texels.push(sum / n);
            }
        }
        let mut map = Self {
            width: w,
            height: h,
            texels,
            repaired: self.repaired,
            mean: Vec3::ZERO,
        };
        map.mean = map.solid_angle_mean();
        map
    }
}

fn format_name(format: image::ImageFormat) -> &'static str {
    match format {
        image::ImageFormat::Hdr => "Radiance HDR",
        _ => "OpenEXR",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uv_and_direction_round_trip() {
        for (u, v) in [(0.1, 0.2), (0.5, 0.5), (0.75, 0.9), (0.99, 0.01)] {
            let uv = Vec2::new(u, v);
            let back = direction_to_uv(uv_to_direction(uv));
            assert!((back - uv).abs().max_element() < 1e-5, "{uv} -> {back}");
        }
        assert!((uv_to_direction(Vec2::new(0.5, 0.5)) - Vec3::NEG_Z).length() < 1e-6);
        assert!((uv_to_direction(Vec2::new(0.75, 0.5)) - Vec3::X).length() < 1e-6);
        assert!((uv_to_direction(Vec2::new(0.3, 0.0)) - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn bilinear_reads_texel_centres_exactly_and_wraps_in_u() {
        let texels = (0..8).map(|i| Vec3::splat(i as f32)).collect();
        let map = EnvironmentMap::new(4, 2, texels).unwrap();
        for y in 0..2 {
            for x in 0..4 {
                let uv = Vec2::new((x as f32 + 0.5) / 4.0, (y as f32 + 0.5) / 2.0);
                assert_eq!(map.radiance_at(uv), map.texel(x, y));
            }
        }
        // Halfway between the last and the first column of row 0.
        let seam = map.radiance_at(Vec2::new(0.0, 0.25));
        assert!((seam.x - 1.5).abs() < 1e-6, "{seam}");
    }

    #[test]
    fn repairs_unusable_texels() {
        let map = EnvironmentMap::new(
            3,
            1,
            vec![
                Vec3::new(f32::NAN, 1.0, 1.0),
                Vec3::new(-1.0, f32::INFINITY, 2.0),
                Vec3::ONE,
            ],
        )
        .unwrap();
        assert_eq!(map.repaired_texels(), 2);
        assert_eq!(map.texel(0, 0), Vec3::new(0.0, 1.0, 1.0));
        assert_eq!(map.texel(1, 0), Vec3::new(0.0, crate::MAX_RADIANCE, 2.0));
        assert!(EnvironmentMap::new(0, 1, vec![]).is_err());
        assert!(EnvironmentMap::new(2, 2, vec![Vec3::ONE]).is_err());
    }

    #[test]
    fn halving_keeps_the_mean() {
        let texels = (0..6 * 3).map(|i| Vec3::splat((i % 5) as f32)).collect();
        let map = EnvironmentMap::new(6, 3, texels).unwrap();
        let half = map.halved();
        assert_eq!((half.width(), half.height()), (3, 2));
        let uniform = EnvironmentMap::uniform(Vec3::splat(2.0)).unwrap();
        assert_eq!(uniform.mean_radiance(), Vec3::splat(2.0));
        let total: f32 = (0..map.height())
            .map(|y| map.row_solid_angle(y))
            .sum::<f32>()
            * 6.0;
        assert!((total - 4.0 * std::f32::consts::PI).abs() < 1e-4);
    }
}
