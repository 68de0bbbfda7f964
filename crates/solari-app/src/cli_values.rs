//! Parsers for the command line's typed values: every option is read into its type when the
//! arguments are parsed, so a bad value is refused (with the accepted values named) before
//! any file is read or any GPU work starts.

use solari_denoise::{AtrousKernel, DenoiserKind};
use solari_lights::{LightTileSettings, Selection};
use solari_renderer::{Antialias, CameraPath, FrameView, GBufferChoice, GiMode, QualityTier};
use solari_restir::{GlossyHits, SpatialVisibility};
use solari_scene::brdf::BrdfModel;
use solari_scene::bvh::BvhQuality;
use solari_scene::gpu::TracerChoice;
use solari_scene::view_pass::DebugView;

/// Largest image side the commands accept; the device's own limits are checked later.
pub const MAX_SIDE: u32 = 16384;

/// `WIDTHxHEIGHT`, each side 1 to [`MAX_SIDE`].
pub fn size(s: &str) -> Result<(u32, u32), String> {
    pair(s, "WIDTHxHEIGHT").and_then(|(w, h)| {
        if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE {
            Err(format!("{s}: each side must be 1 to {MAX_SIDE}"))
        } else {
            Ok((w, h))
        }
    })
}

/// `ROCKSxTRIANGLES` for `--generated` (ranges are checked when the field is made).
pub fn rock_field(s: &str) -> Result<(u32, u32), String> {
    pair(s, "ROCKSxTRIANGLES")
}

fn pair(s: &str, shape: &str) -> Result<(u32, u32), String> {
    let (a, b) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{s}: expected {shape}"))?;
    let a: u32 = a
        .trim()
        .parse()
        .map_err(|_| format!("{s}: expected {shape} with whole numbers"))?;
    let b: u32 = b
        .trim()
        .parse()
        .map_err(|_| format!("{s}: expected {shape} with whole numbers"))?;
    Ok((a, b))
}

/// Light tiles as `TILESxSAMPLES`: 1 to 4096 tiles of 1 to 65536 samples, at most 2^24 samples
/// in all (the tiles are rebuilt every frame).
pub fn tiles(s: &str) -> Result<LightTileSettings, String> {
    let (tiles, samples_per_tile) = pair(s, "TILESxSAMPLES, e.g. 128x1024")?;
    if !(1..=4096).contains(&tiles)
        || !(1..=65536).contains(&samples_per_tile)
        || tiles as u64 * samples_per_tile as u64 > 1 << 24
    {
        return Err(format!(
            "{s}: expected 1 to 4096 tiles of 1 to 65536 samples, at most 16777216 in all"
        ));
    }
    Ok(LightTileSettings {
        tiles,
        samples_per_tile,
        ..Default::default()
    })
}

/// A finite number.
pub fn finite(s: &str) -> Result<f32, String> {
    let v: f32 = s.trim().parse().map_err(|_| format!("{s}: not a number"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{s}: must be finite"))
    }
}

/// A count of frames, or `never` (`u32::MAX`: the frames never run out).
pub fn settle_frames(s: &str) -> Result<u32, String> {
    match s.trim() {
        "never" => Ok(u32::MAX),
        t => t
            .parse()
            .map_err(|_| format!("{s}: a number of frames or never")),
    }
}

/// A positive number or `inf` (a distance that may be unbounded).
pub fn positive_or_inf(s: &str) -> Result<f32, String> {
    let v: f32 = s.trim().parse().map_err(|_| format!("{s}: not a number"))?;
    if v > 0.0 && v != f32::NEG_INFINITY && !v.is_nan() {
        Ok(v)
    } else {
        Err(format!("{s}: must be above 0 (or inf)"))
    }
}

/// A length in metres: finite and not negative.
pub fn metres(s: &str) -> Result<f32, String> {
    let v = finite(s)?;
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("{s}: must not be negative"))
    }
}

/// An environment intensity: finite, not negative, at most `MAX_RADIANCE`.
pub fn intensity(s: &str) -> Result<f32, String> {
    let v = finite(s)?;
    if (0.0..=solari_scene::MAX_RADIANCE).contains(&v) {
        Ok(v)
    } else {
        Err(format!(
            "{s}: must be within [0, {:e}]",
            solari_scene::MAX_RADIANCE
        ))
    }
}

/// Exposure in stops: finite, within ±64.
pub fn exposure(s: &str) -> Result<f32, String> {
    let v = finite(s)?;
    if v.abs() <= 64.0 {
        Ok(v)
    } else {
        Err(format!("{s}: exposure must be within ±64 stops"))
    }
}

fn named<T>(s: &str, parsed: Option<T>, expected: &str) -> Result<T, String> {
    parsed.ok_or_else(|| format!("{s}: expected {expected}"))
}

/// `auto`, `ray-query` or `software`.
pub fn tracer(s: &str) -> Result<TracerChoice, String> {
    named(s, TracerChoice::parse(s), "auto, ray-query or software")
}

/// A BVH build preset.
pub fn bvh_quality(s: &str) -> Result<BvhQuality, String> {
    named(
        s,
        BvhQuality::parse(s),
        "fastest, fast, medium, slow or very-slow",
    )
}

/// `layered` or `gltf-spec`.
pub fn brdf(s: &str) -> Result<BrdfModel, String> {
    named(s, BrdfModel::parse(s), "layered or gltf-spec")
}

/// `fixed` or `orbit`.
pub fn camera_path(s: &str) -> Result<CameraPath, String> {
    named(s, CameraPath::parse(s), "fixed or orbit")
}

/// `raster`, `traced` or `auto`.
pub fn gbuffer(s: &str) -> Result<GBufferChoice, String> {
    named(s, GBufferChoice::parse(s), "raster, traced or auto")
}

/// `auto`, `on` or `off` (`--antialias`).
pub fn antialias(s: &str) -> Result<Antialias, String> {
    named(s, Antialias::parse(s), "auto, on or off")
}

/// `off`, `cache`, `path` or `restir`.
pub fn gi(s: &str) -> Result<GiMode, String> {
    named(s, GiMode::parse(s), "off, cache, path or restir")
}

/// `both`, `chosen` or `neighbour` (`--gi-spatial-visibility`).
pub fn gi_spatial_visibility(s: &str) -> Result<SpatialVisibility, String> {
    named(s, SpatialVisibility::parse(s), "both, chosen or neighbour")
}

/// `cache`, `lights` or `path` (`--gi-glossy-hits`).
pub fn gi_glossy_hits(s: &str) -> Result<GlossyHits, String> {
    named(s, GlossyHits::parse(s), "cache, lights or path")
}

/// `diamond` or `full` (`--denoise-kernel`).
pub fn atrous_kernel(s: &str) -> Result<AtrousKernel, String> {
    named(s, AtrousKernel::parse(s), "diamond or full")
}

/// `--quality`: a tier, or automatic.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QualityArg {
    /// A named tier.
    Tier(QualityTier),
    /// Chosen at start-up from measured time against error (`--budget-ms`).
    Auto,
}

/// `auto`, `low`, `medium`, `high` or `ultra`.
pub fn quality(s: &str) -> Result<QualityArg, String> {
    if s == "auto" {
        return Ok(QualityArg::Auto);
    }
    named(s, QualityTier::parse(s), "auto, low, medium, high or ultra").map(QualityArg::Tier)
}

/// `none`, `fallback` or `dlss-rr`.
pub fn denoiser(s: &str) -> Result<DenoiserKind, String> {
    named(s, DenoiserKind::parse(s), "none, fallback or dlss-rr")
}

/// `power` or `uniform`.
pub fn selection(s: &str) -> Result<Selection, String> {
    named(
        s,
        match s {
            "power" => Some(Selection::Power),
            "uniform" => Some(Selection::Uniform),
            _ => None,
        },
        "power or uniform",
    )
}

/// What `--view` shows: a debug view or a real-time view, checked against the mode later.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewArg {
    /// A primary-ray debug view (debug mode).
    Debug(DebugView),
    /// A real-time view (real-time mode).
    Frame(FrameView),
}

/// `albedo`, `normal`, `depth`, `instance` (debug mode) or `lit`, `indirect`, `world-cache`,
/// `gbuffer-CHANNEL` (real time).
pub fn view(s: &str) -> Result<ViewArg, String> {
    if let Some(v) = DebugView::parse(s) {
        return Ok(ViewArg::Debug(v));
    }
    named(
        s,
        FrameView::parse(s).map(ViewArg::Frame),
        "albedo, normal, depth or instance (debug mode), lit, indirect, world-cache or gbuffer-CHANNEL \
         with CHANNEL base-color, normal, geometric-normal, roughness, metallic, emission, depth \
         or motion (real-time mode)",
    )
}

/// A comma-separated list of values each read by `item`; `what` names the option.
pub fn list<T>(
    s: &str,
    what: &str,
    item: impl Fn(&str) -> Result<T, String>,
) -> Result<Vec<T>, String> {
    let items: Vec<T> = s
        .split(',')
        .map(|v| item(v.trim()).map_err(|e| format!("{what}: {e}")))
        .collect::<Result<_, _>>()?;
    if items.is_empty() || items.len() > 64 {
        return Err(format!("{what}: expected 1 to 64 values"));
    }
    Ok(items)
}

/// A `T` from text (for [`list`]).
pub fn number<T: std::str::FromStr>(s: &str) -> Result<T, String> {
    s.parse().map_err(|_| format!("cannot read '{s}'"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_and_tiles_are_bounded() {
        assert_eq!(size("64x32"), Ok((64, 32)));
        for bad in [
            "0x0",
            "100000x100000",
            "64",
            "ax3",
            "-1x4",
            "16385x1",
            "4x",
            "",
        ] {
            assert!(size(bad).is_err(), "{bad}");
        }
        assert!(tiles("128x1024").is_ok());
        for bad in ["0x4", "4x0", "5000x4", "4096x65536", "x"] {
            assert!(tiles(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn numbers_must_be_finite() {
        for bad in ["nan", "NaN", "inf", "-inf", "1e39", "x"] {
            assert!(finite(bad).is_err(), "{bad}");
            assert!(exposure(bad).is_err(), "{bad}");
        }
        assert!(exposure("65").is_err());
        assert_eq!(positive_or_inf("inf"), Ok(f32::INFINITY));
        assert_eq!(positive_or_inf(" 2.5"), Ok(2.5));
        for bad in ["0", "-1", "nan", "-inf", "x"] {
            assert!(positive_or_inf(bad).is_err(), "{bad}");
        }
        assert_eq!(exposure("-2.5"), Ok(-2.5));
        assert_eq!(settle_frames("never"), Ok(u32::MAX));
        assert_eq!(settle_frames(" 32"), Ok(32));
        for bad in ["-1", "x", "1.5", ""] {
            assert!(settle_frames(bad).unwrap_err().contains("never"), "{bad}");
        }
    }

    #[test]
    fn enums_name_their_values() {
        assert!(
            gi("bogus")
                .unwrap_err()
                .contains("off, cache, path or restir")
        );
        assert_eq!(gi("restir"), Ok(GiMode::Restir));
        assert_eq!(gi("path"), Ok(GiMode::Path));
        assert!(view("bogus").unwrap_err().contains("world-cache"));
        assert_eq!(view("lit"), Ok(ViewArg::Frame(FrameView::Lit)));
        assert_eq!(
            view("gbuffer-motion"),
            Ok(ViewArg::Frame(FrameView::GBuffer(
                solari_scene::gbuffer_debug::GBufferChannel::Motion
            )))
        );
        for c in solari_scene::gbuffer_debug::GBufferChannel::ALL {
            let v = FrameView::GBuffer(c);
            assert_eq!(view(&v.name()), Ok(ViewArg::Frame(v)));
        }
        assert!(
            view("gbuffer-bogus")
                .unwrap_err()
                .contains("gbuffer-CHANNEL")
        );
        assert!(list("1,x", "--candidates", number::<u32>).is_err());
        assert_eq!(list("1, 8", "--candidates", number::<u32>), Ok(vec![1, 8]));
        assert_eq!(quality("ultra"), Ok(QualityArg::Tier(QualityTier::Ultra)));
        assert_eq!(quality("auto"), Ok(QualityArg::Auto));
        assert!(
            quality("max")
                .unwrap_err()
                .contains("auto, low, medium, high or ultra")
        );
    }
}
