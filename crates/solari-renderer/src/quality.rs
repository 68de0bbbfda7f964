//! Quality tiers: named sets of the knobs that trade GPU time for error (GI mode, specular
//! GI, ReSTIR DI reuse and candidates, denoiser iterations, internal resolution), each chosen
//! from time-against-error measurements on the H200 at 1920×1080 (`benches/RESULTS.md`):
//!
//! | tier | internal scale | GI | specular GI | DI | denoiser iterations | basis |
//! |---|---|---|---|---|---|---|
//! | low | 0.5 + upscaler | cache | off | 4 candidates, no reuse | 3 | "Internal resolution": 0.5 takes 33–39% of native's GPU time; "GI: the whole matrix": cache+nodi is the cheapest row on every scene |
//! | medium | 0.67 + upscaler | path | on | 8 candidates, no reuse | 4 | 0.67 takes 52–57%; path+spec+nodi matched the default's error on three of four scenes for 0.35–1.34 ms less |
//! | high | 1 | path | on | 8 candidates, temporal + spatial reuse | 5 | the library defaults: lowest error at its cost on interior and sun_boxes, within 4% of the lowest everywhere |
//! | ultra | 1, jittered + upscaler (AA) | ReSTIR GI | on | 16 candidates, temporal + spatial reuse | 5 | AA gave the lowest relMSE and FLIP on every scene for 0.08–0.10 ms; ReSTIR GI 1–4% below path GI on three scenes |
//!
//! A tier changes only these knobs; every other setting (tiles, cache, light grid, timestamps)
//! is the caller's. The denoiser kind is left alone too, except that the tiers below `high`
//! need the temporal upscaler, which DLSS-RR replaces: with DLSS-RR chosen, they keep scale 1.

use crate::realtime::{GiMode, RealtimeSettings};
use solari_denoise::DenoiserKind;

/// A named set of quality knobs (see the module docs for each tier's values and basis).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum QualityTier {
    /// Quarter of the pixels, cache-only GI, no reuse: the cheapest frame.
    Low,
    /// 0.67 internal scale, path GI with specular, no DI reuse.
    Medium,
    /// The library defaults.
    #[default]
    High,
    /// Native antialiased, ReSTIR GI, 16 DI candidates.
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

    /// `settings` with this tier's knobs (module docs); the result passes
    /// [`RealtimeSettings::validate`] whenever `settings` did.
    pub fn apply(self, settings: &RealtimeSettings) -> RealtimeSettings {
        let mut s = *settings;
        let (scale, antialias, gi, specular, candidates, reuse, iterations) = match self {
            Self::Low => (0.5, false, GiMode::WorldCache, false, 4, false, 3),
            Self::Medium => (0.67, false, GiMode::Path, true, 8, false, 4),
            Self::High => (1.0, false, GiMode::Path, true, 8, true, 5),
            Self::Ultra => (1.0, true, GiMode::Restir, true, 16, true, 5),
        };
        let dlss = s.denoiser == Some(DenoiserKind::DlssRr);
        s.internal_scale = if dlss { 1.0 } else { scale };
        s.antialias = antialias && !dlss;
        s.gi = gi;
        s.specular_gi = specular;
        s.di.initial_candidates = candidates;
        s.di.temporal = reuse;
        s.di.spatial = reuse;
        s.denoise.atrous_iterations = iterations;
        s
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

    #[test]
    fn every_tier_validates_names_round_trip_and_is_recognised() {
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
            for tier in QualityTier::ALL {
                let s = tier.apply(&base);
                s.validate()
                    .unwrap_or_else(|e| panic!("{tier:?} {denoiser:?}: {e}"));
                assert_eq!(QualityTier::parse(tier.name()), Some(tier));
                assert_eq!(QualityTier::of(&s), Some(tier), "{denoiser:?}");
                // Applying twice changes nothing.
                assert_eq!(tier.apply(&s), s);
            }
        }
        assert_eq!(QualityTier::parse("max"), None);
        // The default settings are the high tier.
        assert_eq!(
            QualityTier::of(&RealtimeSettings::default()),
            Some(QualityTier::High)
        );
        let mut custom = RealtimeSettings::default();
        custom.di.initial_candidates = 3;
        assert_eq!(QualityTier::of(&custom), None);
    }

    #[test]
    fn tiers_get_cheaper_downwards() {
        let base = RealtimeSettings::default();
        let pixels = |t: QualityTier| {
            let (w, h) = t.apply(&base).render_size((1920, 1080));
            w as u64 * h as u64
        };
        let tiers = QualityTier::ALL;
        for pair in tiers.windows(2) {
            assert!(pixels(pair[0]) <= pixels(pair[1]), "{pair:?}");
            let (a, b) = (pair[0].apply(&base), pair[1].apply(&base));
            assert!(a.di.initial_candidates <= b.di.initial_candidates);
            assert!(a.denoise.atrous_iterations <= b.denoise.atrous_iterations);
        }
    }
}
