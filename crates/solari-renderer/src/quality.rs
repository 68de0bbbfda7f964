//! Quality settings: a grid of 24 points that trade GPU time for error (internal scale, GI
//! mode, ReSTIR DI reuse), four named tiers among them, and the table of their measured time
//! and error that automatic quality ([`crate::auto_quality`]) chooses from.
//!
//! A grid point is `SCALE-GI[-nodi]`: SCALE `50` or `67` (internal scale 0.5 or 0.67 with the
//! temporal upscaler), `100` (native, antialiasing off) or `aa` (native with
//! [`Antialias::Auto`]: jittered and through the upscaler under the fallback denoiser, which
//! the sweep ran; DLSS-RR antialiases by itself, and the raw image stays unjittered); GI
//! `cache` (world-cache GI, specular GI off: it costs 0.6–2 ms without GI reservoirs to
//! reuse), `path` or `restir` (specular GI on); `-nodi`: ReSTIR DI without reuse. Every other
//! knob is the caller's.
//!
//! The tiers, chosen from the grid's sweep on four scenes (`data/quality_h100.csv`; relMSE as
//! a multiple of each scene's best grid point, cornell_box / interior / many_lights /
//! sun_boxes, with the camera still (frame 136) and moving (the orbit camera, frames 32 and
//! 96, each against a reference of its own), and today's GPU ms at 1920×1080 on an H100
//! (`--quality TIER`, fallback denoiser, 300 frames, thirty-third session; the sweep's own
//! times are older and higher). The errors are without the references' own noise (the
//! table's `reference_noise` columns), the still ones measured again on the forty-fourth
//! session's renderer (ReSTIR GI's rows again in the forty-fifth, after its adaptive cap
//! stopped on settled views, which made it the best still point on three scenes): with the
//! noise in, a constant of up to 70% of each figure, the
//! multiples read up to twice as close to 1 (`benches/RESULTS.md`, "The reference's own
//! noise"; the old table's low tier read 3.9 / 2.2 / 1.9 / 5.8 still):
//!
//! | tier | point | error × best, still | moving | GPU ms | why |
//! |---|---|---|---|---|---|
//! | low | `100-cache-nodi` | 6.5 / 5.0 / 3.4 / 9.5 | 2.7 / 1.4 / 1.1 / 2.6 | 1.27 / 2.53 / 2.05 / 1.47 | the cheapest native point (below) |
//! | medium | `100-path-nodi` | 3.3 / 1.8 / 3.3 / 2.2 | 1.1 / 1.0 / 1.0 / 1.0 | 1.52 / 3.74 / 2.54 / 1.84 | native without DI reuse: at most 3.3× the best |
//! | high | `100-path` | 3.3 / 1.8 / 2.4 / 2.2 | 1.0 / 1.0 / 1.0 / 1.05 | 1.52 / 3.74 / 2.80 / 1.84 | native, no antialiasing |
//! | ultra | `aa-path` | 1.22 / 1.05 / 1.00 / 1.08 | 1.0 / 1.0 / 1.0 / 1.04 | 1.62 / 3.88 / 2.93 / 1.97 | within 22% of the best everywhere: the library defaults |
//!
//! The sweep's plainest finding: antialiasing (`aa`) costs 0.10–0.11 ms over native and cut
//! relMSE 1.2–1.7× on every scene (`benches/RESULTS.md`, "Automatic quality"). So the
//! defaults antialias since the thirty-second session, which makes them the ultra tier: the
//! best point of the grid by its worst error until the forty-fifth session, when antialiased
//! ReSTIR GI (`aa-restir`, 1.18× at worst) passed it for 0.3–1.1 ms more GI a frame.
//! Measured again then at 1920×1080 on an H100 with today's passes (`benches/RESULTS.md`,
//! "Antialiasing by default"): 0.10–0.14 ms a frame, relMSE of the 136th frame against
//! 1024-spp references 1.9× lower on the Cornell box, 1.8× on sun_boxes, 1.5× on many_lights,
//! 1.2× on interior, with the camera still. Jittered under a moving camera it was 1.7–420×
//! worse, so antialiasing jitters only while the camera stands still ([`Antialias`]); moving,
//! `aa` points are their native twins.
//!
//! The upscaled points (`50`, `67`) jitter every frame, and along the orbit camera they are
//! worse than native whatever the GI (`benches/RESULTS.md`, "Upscaled points under a moving
//! camera", "The upscaler under motion", "Moving silhouettes", "Occluders out of the clamp",
//! "An output-resolution depth as the upscaler's guide" and "An emitter is a surface of its
//! own"): `50-path-nodi`, the low tier until the thirty-third session, is 1.41 / 1.50 / 1.45
//! / 3.23× the best moving point and 4.1 / 3.0 / 3.8 / 4.5× still without the references'
//! noise (Cornell box / interior / many_lights / sun_boxes; with it in, as the older figures
//! that follow are, 1.35 / 1.30 / 1.29 / 3.05× moving; 9.9 / 2.3
//! / 14 / 3.6× before the upscaler's guide (0a537ed, emitters told apart in a21e69c; the
//! table held no row of the depth-only guide), 9.9 / 13.6 / 179 / 3.5× before the
//! occluder fix in 07ce27b, 87 / 47 / 839 / 6.8× before the motion fix in cd79385; 2.1 / 1.6
//! / 2.1 / 3.5× still). Under motion a frame's own samples cover a quarter of the pixels at
//! half scale, so edges come out up to a render pixel off where the guide cannot place them.
//! So the low tier is native, and automatic quality judges every point by the worse of its
//! still and moving errors ([`crate::auto_quality::ErrorTable::relative_error`]). With the
//! still camera's errors the larger on most points, the upscaled `67` path and ReSTIR points
//! (1.7–3.1× the best still, 1.2–2.2× moving) outrank the native cache points (2.4–9.5× the
//! best still) that cost as much or more on every scene.

use crate::realtime::{Antialias, GiMode, RealtimeSettings};
use solari_denoise::DenoiserKind;

/// The resolution part of a grid point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Resolution {
    /// Internal scale 0.5 and the temporal upscaler.
    Half,
    /// Internal scale 0.67 and the temporal upscaler.
    TwoThirds,
    /// Native, no upscaler.
    Native,
    /// Native, jittered, through the temporal upscaler (antialiased).
    Antialiased,
}

impl Resolution {
    /// Every resolution, fewest pixels first.
    pub const ALL: [Resolution; 4] = [Self::Half, Self::TwoThirds, Self::Native, Self::Antialiased];

    /// `50`, `67`, `100` or `aa`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Half => "50",
            Self::TwoThirds => "67",
            Self::Native => "100",
            Self::Antialiased => "aa",
        }
    }

    /// The internal scale.
    pub fn scale(self) -> f32 {
        match self {
            Self::Half => 0.5,
            Self::TwoThirds => 0.67,
            Self::Native | Self::Antialiased => 1.0,
        }
    }

    /// Whether frames go through the temporal upscaler.
    pub fn upscaled(self) -> bool {
        self != Self::Native
    }
}

/// One point of the quality grid (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QualitySetting {
    /// Internal scale and antialiasing.
    pub resolution: Resolution,
    /// [`GiMode::WorldCache`], [`GiMode::Path`] or [`GiMode::Restir`].
    pub gi: GiMode,
    /// ReSTIR DI's temporal and spatial reuse.
    pub di_reuse: bool,
}

impl QualitySetting {
    /// The 24 grid points.
    pub fn grid() -> Vec<QualitySetting> {
        let mut v = Vec::with_capacity(24);
        for resolution in Resolution::ALL {
            for gi in [GiMode::WorldCache, GiMode::Path, GiMode::Restir] {
                for di_reuse in [true, false] {
                    v.push(Self {
                        resolution,
                        gi,
                        di_reuse,
                    });
                }
            }
        }
        v
    }

    /// The name, `SCALE-GI[-nodi]` (module docs).
    pub fn name(&self) -> String {
        let gi = match self.gi {
            GiMode::WorldCache => "cache",
            GiMode::Restir => "restir",
            _ => "path",
        };
        let nodi = if self.di_reuse { "" } else { "-nodi" };
        format!("{}-{gi}{nodi}", self.resolution.name())
    }

    /// Parses a name [`QualitySetting::name`] gives.
    pub fn parse(s: &str) -> Option<Self> {
        Self::grid().into_iter().find(|g| g.name() == s)
    }

    /// Whether specular GI runs at this point (not with cache GI: module docs).
    pub fn specular_gi(&self) -> bool {
        self.gi != GiMode::WorldCache
    }

    /// `settings` with this point's knobs. With DLSS-RR as the denoiser, which upscales by
    /// itself, the resolution part is left at native (the temporal upscaler cannot run).
    pub fn apply(&self, settings: &RealtimeSettings) -> RealtimeSettings {
        let mut s = *settings;
        let dlss = s.denoiser == Some(DenoiserKind::DlssRr);
        s.internal_scale = if dlss { 1.0 } else { self.resolution.scale() };
        // Auto, not On: DLSS-RR antialiases by itself, and the raw image stays unjittered.
        s.antialias = if self.resolution == Resolution::Antialiased {
            Antialias::Auto
        } else {
            Antialias::Off
        };
        s.gi = self.gi;
        s.specular_gi = self.specular_gi();
        s.di.temporal = self.di_reuse;
        s.di.spatial = self.di_reuse;
        s
    }
}

/// A named grid point (see the module docs for each tier and its basis).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum QualityTier {
    /// `100-cache-nodi`: native, world-cache GI, no DI reuse (module docs: the upscaled
    /// points are cheaper and far worse under a moving camera).
    Low,
    /// `100-path-nodi`: native, no DI reuse.
    Medium,
    /// `100-path`: native, no antialiasing.
    High,
    /// `aa-path`: native, antialiased ([`Antialias::Auto`]): the library defaults.
    #[default]
    Ultra,
}

impl QualityTier {
    /// Every tier, cheapest first.
    pub const ALL: [QualityTier; 4] = [Self::Low, Self::Medium, Self::High, Self::Ultra];

    /// Parses `low`, `medium`, `high` or `ultra`.
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|t| t.name() == s)
    }

    /// The tier's name as [`QualityTier::parse`] reads it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Low => "low",
            Self::Medium => "medium",
            Self::High => "high",
            Self::Ultra => "ultra",
        }
    }

    /// The grid point the tier names.
    pub fn setting(self) -> QualitySetting {
        let (resolution, gi, di_reuse) = match self {
            Self::Low => (Resolution::Native, GiMode::WorldCache, false),
            Self::Medium => (Resolution::Native, GiMode::Path, false),
            Self::High => (Resolution::Native, GiMode::Path, true),
            Self::Ultra => (Resolution::Antialiased, GiMode::Path, true),
        };
        QualitySetting {
            resolution,
            gi,
            di_reuse,
        }
    }

    /// `settings` with this tier's knobs ([`QualitySetting::apply`]); the result passes
    /// [`RealtimeSettings::validate`] whenever `settings` did.
    pub fn apply(self, settings: &RealtimeSettings) -> RealtimeSettings {
        self.setting().apply(settings)
    }

    /// The tier whose knobs `settings` holds, if any (a hand-tuned setting matches none).
    pub fn of(settings: &RealtimeSettings) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|t| t.apply(settings) == *settings)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::auto_quality::ErrorTable;

    #[test]
    fn every_grid_point_and_tier_validates_and_names_round_trip() {
        let grid = QualitySetting::grid();
        assert_eq!(grid.len(), 24);
        for denoiser in [
            None,
            Some(DenoiserKind::None),
            Some(DenoiserKind::Fallback),
            Some(DenoiserKind::DlssRr),
        ] {
            let base = RealtimeSettings {
                denoiser,
                ..Default::default()
            };
            for g in &grid {
                let s = g.apply(&base);
                s.validate()
                    .unwrap_or_else(|e| panic!("{} {denoiser:?}: {e}", g.name()));
                assert_eq!(QualitySetting::parse(&g.name()), Some(*g));
                assert_eq!(g.apply(&s), s);
            }
            for tier in QualityTier::ALL {
                let s = tier.apply(&base);
                assert_eq!(QualityTier::parse(tier.name()), Some(tier));
                // DLSS-RR owns the resolution: tiers that differ only there would match.
                let found = QualityTier::of(&s).expect("a tier");
                assert_eq!(found.apply(&base), s, "{tier:?} {denoiser:?}");
                if denoiser != Some(DenoiserKind::DlssRr) {
                    assert_eq!(found, tier, "{denoiser:?}");
                }
            }
        }
        assert_eq!(QualityTier::parse("max"), None);
        assert_eq!(QualitySetting::parse("100-path-di"), None);
        // The default settings are the ultra tier, the default tier.
        assert_eq!(
            QualityTier::of(&RealtimeSettings::default()),
            Some(QualityTier::Ultra)
        );
        assert_eq!(QualityTier::default(), QualityTier::Ultra);
        let custom = RealtimeSettings {
            internal_scale: 0.8,
            ..Default::default()
        };
        assert_eq!(QualityTier::of(&custom), None);
    }

    /// The tiers' claims hold in the measured table: each costs no less than the one below on
    /// every scene, and its worst error (as a multiple of each scene's best) is no higher.
    #[test]
    fn tiers_are_ordered_by_measured_time_and_error() {
        let table = ErrorTable::builtin();
        let scenes = table.scenes();
        assert_eq!(scenes.len(), 4);
        let worst = |t: QualityTier| {
            scenes
                .iter()
                .map(|s| table.relative_error(s, &t.setting()).expect("measured"))
                .fold(0.0f64, f64::max)
        };
        for pair in QualityTier::ALL.windows(2) {
            for s in &scenes {
                let ms = |t: QualityTier| table.gpu_ms(s, &t.setting()).expect("timed");
                assert!(ms(pair[0]) <= ms(pair[1]), "{s}: {pair:?}");
            }
            assert!(worst(pair[0]) >= worst(pair[1]) * 0.95, "{pair:?}");
        }
        // 1.22 (the Cornell box still, where antialiased ReSTIR GI is best since its
        // adaptive cap stops on settled views) with the references' noise out.
        assert!(worst(QualityTier::Ultra) < 1.25);
    }

    /// Along the orbit camera (the table's moving column, the references' noise out) no tier
    /// is far from the best: the upscaled points, 1.2-4.1× worse there (1.1-3.8× with the
    /// noise in; 1.7-14× before the upscaler's guide,
    /// 2.3-179× before the occluder fix in 07ce27b, 2.9-386× before the silhouette fix in
    /// 92c69a1, 4.8-840× before the motion fix in cd79385), are in none of them. The
    /// half-scale check is a tripwire: an upscaler that follows motion better has to bring a
    /// new table, and this bound, with it (`50-path-nodi` is 1.41-3.23×; interior's 1.50×).
    #[test]
    fn no_tier_falls_apart_under_a_moving_camera() {
        let table = ErrorTable::builtin();
        for s in table.scenes() {
            let moving = |g: &QualitySetting| {
                let (_, moving) = table.own_error(&s, g).expect("measured");
                moving.expect("measured moving")
            };
            let best = QualitySetting::grid()
                .iter()
                .map(moving)
                .fold(f64::INFINITY, f64::min);
            for tier in QualityTier::ALL {
                let e = moving(&tier.setting()) / best;
                assert!(e < 3.0, "{s}: {tier:?} {e:.1}× the best moving");
            }
            let half = QualitySetting::parse("50-path-nodi").unwrap();
            assert!(
                moving(&half) / best > 1.2,
                "{s}: the upscaled points recovered"
            );
        }
    }
}
