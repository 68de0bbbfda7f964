//! Automatic quality: the grid point ([`QualitySetting`]) with the least expected error whose
//! GPU time, predicted for this scene on this adapter, fits a frame budget.
//!
//! - **Time** is measured at start-up ([`probe`]): one renderer at the output size with every
//!   costly option on (ReSTIR GI, specular GI, DI reuse, the upscaler), a few frames, then
//!   DI reuse off through `set_di_settings` (no rebuild), then plain path GI in a renderer of
//!   its own (path GI is built without reuse and runs one pass), each pass timed with
//!   timestamp queries, each renderer after [`WARM_UP_SECONDS`] of untimed frames (an idle
//!   GPU clocks down, and a first run's shader compile leaves it idle for seconds), and at
//!   least the world cache's warm-up frames (its extra update rounds are not a frame's
//!   steady cost).
//!   [`CostModel`] adds up the passes a grid point runs; passes that work per pixel scale
//!   with the point's pixel count as `f + 0.1 (1 - f)` of native (fitted to the sweep's
//!   per-pass times at 0.5 and 0.67, where about 9% of a pass did not shrink with its
//!   pixels), and cache GI, the one pass the probe does not run, is taken as 0.45 × the
//!   G-buffer's time (the sweep's ratios were 0.20–0.42; rounded up to stay on the
//!   safe side of a budget).
//! - **Error** comes from a measured table ([`ErrorTable`]: relMSE of every grid point on a
//!   scene against a reference, as `benches/results/quality_h200.sh` writes it), with the
//!   camera still and, where measured, moving (the orbit camera): a point counts by the worse
//!   of its two errors, each as a multiple of the scene's best, since a user's camera both
//!   moves and stands still (the upscaled points are 1.2–4.1× the best point moving, and
//!   1.7–10.2× still: [`crate::quality`]); the references' own noise, a constant per scene
//!   and camera that pulls every ratio toward 1, is taken out first where the table gives
//!   it ([`ErrorRow::reference_noise`]). A scene the table holds uses its own rows; any
//!   other scene uses, for each point, its worst error over the table's scenes (the choice that was never
//!   far off). [`ErrorTable::builtin`] holds the four bundled scenes: times on an H100, the
//!   still errors (forty-fourth session; ReSTIR GI's forty-fifth) and the noise terms on an H200, the moving errors on
//!   both (`data/quality_h100.csv`'s header says which rows where).

use crate::quality::{QualitySetting, Resolution};
use crate::realtime::{GiMode, RealtimeRenderer, RealtimeSettings};
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::GpuScene;
use solari_scene::shaders::Backend;
use solari_scene::{Camera, GpuError, Scene};
use std::collections::HashMap;
use std::time::Instant;

/// The sweep shipped with the crate (`data/quality_h100.csv`).
const BUILTIN_TABLE: &str = include_str!("../data/quality_h100.csv");

/// Fraction of a per-pixel pass's native time that does not shrink with its pixels.
const FIXED_SHARE: f64 = 0.1;

/// Cache GI's pass time as a multiple of the G-buffer's (the sweep's ratios: 0.20–0.42).
const CACHE_GI_PER_GBUFFER: f64 = 0.45;

/// The least share of a row's measured relMSE that counts as its own once the reference's
/// noise is taken out: a setting can measure below that noise term (the noise is an
/// estimate), and counting it as zero or less would make every ratio to it meaningless.
pub const MIN_OWN_ERROR_SHARE: f64 = 0.05;

/// One measured row: a grid point on a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorRow {
    /// The scene's name (its file's stem).
    pub scene: String,
    /// The grid point.
    pub setting: QualitySetting,
    /// GPU ms per frame where it was measured.
    pub gpu_ms: f64,
    /// relMSE against the scene's reference, camera still (frame 136).
    pub rel_mse: f64,
    /// relMSE along the orbit camera (a moving camera: the mean over the orbit frames the
    /// sweep measured, each against a reference of that frame), where measured.
    pub rel_mse_moving: Option<f64>,
    /// What the still camera's reference's own noise adds to `rel_mse` (0 where the table
    /// does not say): the same for every row of a scene, taken out before rows are compared
    /// (`solari compare --reference-variance`; [`ErrorTable::own_error`]).
    pub reference_noise: f64,
    /// The same for `rel_mse_moving`'s references.
    pub reference_noise_moving: f64,
}

/// Measured time and error of grid points on scenes (module docs).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ErrorTable {
    /// The rows, in file order.
    pub rows: Vec<ErrorRow>,
}

impl ErrorTable {
    /// The table shipped with the crate: cornell_box, sun_boxes, many_lights and interior.
    pub fn builtin() -> Self {
        Self::parse_csv(BUILTIN_TABLE).expect("the shipped table parses")
    }

    /// Reads CSV with the columns `scene`, `setting`, `gpu_ms` and `rel_mse`, and optionally
    /// `rel_mse_moving` (an empty or `nan` cell: not measured), `reference_noise` and
    /// `reference_noise_moving` (what the references' own noise adds to the two; 0 where
    /// absent, empty or `nan`), in any order, other columns ignored, `#` lines skipped, as
    /// `benches/results/quality_table.py` writes it.
    /// Rows whose setting is not a grid point are skipped (auto's own rows silently, others
    /// with a warning); a bad number or a missing column is an error naming the line.
    pub fn parse_csv(text: &str) -> Result<Self, String> {
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
        let (_, header) = lines.next().ok_or("quality table: no header line")?;
        let columns: Vec<&str> = header.split(',').map(str::trim).collect();
        let col = |name: &str| {
            columns
                .iter()
                .position(|c| *c == name)
                .ok_or_else(|| format!("quality table: no {name:?} column in {header:?}"))
        };
        let (scene, setting, gpu_ms, rel_mse) = (
            col("scene")?,
            col("setting")?,
            col("gpu_ms")?,
            col("rel_mse")?,
        );
        let optional = |name: &str| columns.iter().position(|c| *c == name);
        let moving = optional("rel_mse_moving");
        let (noise, noise_moving) = (
            optional("reference_noise"),
            optional("reference_noise_moving"),
        );
        let mut rows = Vec::new();
        for (i, line) in lines {
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            let cell = |c: usize| {
                cells
                    .get(c)
                    .copied()
                    .ok_or_else(|| format!("quality table line {}: too few cells", i + 1))
            };
            let name = cell(setting)?;
            let Some(point) = QualitySetting::parse(name) else {
                // Auto's own rows are expected; anything else is likely a typo.
                if !name.starts_with("auto") {
                    log::warn!(
                        "quality table line {}: {name:?} is not a grid setting",
                        i + 1
                    );
                }
                continue;
            };
            let number = |c: usize| -> Result<f64, String> {
                let v: f64 = cell(c)?.parse().map_err(|_| {
                    format!(
                        "quality table line {}: {:?} is not a number",
                        i + 1,
                        cells[c]
                    )
                })?;
                if v.is_finite() && v >= 0.0 {
                    Ok(v)
                } else {
                    Err(format!("quality table line {}: {v} is out of range", i + 1))
                }
            };
            // An optional column: absent, or an empty or `nan` cell, is not measured.
            let measured = |c: Option<usize>| -> Result<Option<f64>, String> {
                match c {
                    Some(c) if !(cell(c)?.is_empty() || cell(c)?.eq_ignore_ascii_case("nan")) => {
                        number(c).map(Some)
                    }
                    _ => Ok(None),
                }
            };
            rows.push(ErrorRow {
                scene: cell(scene)?.to_owned(),
                setting: point,
                gpu_ms: number(gpu_ms)?,
                rel_mse: number(rel_mse)?,
                rel_mse_moving: measured(moving)?,
                // No noise term measured counts as none (as before the columns).
                reference_noise: measured(noise)?.unwrap_or(0.0),
                reference_noise_moving: measured(noise_moving)?.unwrap_or(0.0),
            });
        }
        if rows.is_empty() {
            return Err("quality table: no rows of grid settings".into());
        }
        let table = Self { rows };
        // A point without a moving figure is judged by its still one alone, which flatters it
        // beside points that have both: say so where a scene's rows are only partly measured.
        for scene in table.scenes() {
            let (with, all) = table
                .rows
                .iter()
                .filter(|r| r.scene == scene)
                .fold((0, 0), |(w, a), r| {
                    (w + r.rel_mse_moving.is_some() as usize, a + 1)
                });
            if with > 0 && with < all {
                log::warn!(
                    "quality table: {scene} has rel_mse_moving for {with} of its {all} settings; \
                     the others are judged by their still error alone"
                );
            }
        }
        Ok(table)
    }

    /// The scenes the table holds, sorted.
    pub fn scenes(&self) -> Vec<String> {
        let mut v: Vec<String> = self.rows.iter().map(|r| r.scene.clone()).collect();
        v.sort();
        v.dedup();
        v
    }

    fn row(&self, scene: &str, setting: &QualitySetting) -> Option<&ErrorRow> {
        self.rows
            .iter()
            .find(|r| r.scene == scene && r.setting == *setting)
    }

    /// GPU ms of `setting` on `scene` where the table was measured.
    pub fn gpu_ms(&self, scene: &str, setting: &QualitySetting) -> Option<f64> {
        self.row(scene, setting).map(|r| r.gpu_ms)
    }

    /// relMSE of `setting` on `scene` along a moving camera, where the table has it.
    pub fn rel_mse_moving(&self, scene: &str, setting: &QualitySetting) -> Option<f64> {
        self.row(scene, setting).and_then(|r| r.rel_mse_moving)
    }

    /// relMSE of `setting` on `scene` with the references' noise taken out (at least
    /// [`MIN_OWN_ERROR_SHARE`] of the measured figure): still, and moving where measured.
    pub fn own_error(&self, scene: &str, setting: &QualitySetting) -> Option<(f64, Option<f64>)> {
        self.row(scene, setting).map(Self::own_of)
    }

    fn own_of(row: &ErrorRow) -> (f64, Option<f64>) {
        let own = |e: f64, noise: f64| (e - noise).max(MIN_OWN_ERROR_SHARE * e);
        (
            own(row.rel_mse, row.reference_noise),
            row.rel_mse_moving
                .map(|m| own(m, row.reference_noise_moving)),
        )
    }

    /// relMSE of `setting` on `scene` as a multiple of the scene's best grid point, each with
    /// the references' noise taken out ([`Self::own_error`]: against 1024-path references a
    /// constant of up to 70% of the figures, which pulls every ratio toward 1): with the
    /// camera still and, where the table has it, moving (each against the best of its own
    /// kind), the larger of the two. A user's camera moves and stops, and a point is only as
    /// good as its worse case: the upscaled points are 1.2 to 4.1 times the best along the
    /// orbit (module docs; 1.7 to 14 times before the upscaler had its guide). A point
    /// without a moving figure counts by its still one alone (`parse_csv` warns where a scene is only partly
    /// measured).
    pub fn relative_error(&self, scene: &str, setting: &QualitySetting) -> Option<f64> {
        let rows = || self.rows.iter().filter(|r| r.scene == scene);
        let ratio = |e: f64, best: f64| if best > 0.0 { e / best } else { 1.0 };
        let (row_still, row_moving) = self.own_error(scene, setting)?;
        let best = rows()
            .map(|r| Self::own_of(r).0)
            .fold(f64::INFINITY, f64::min);
        let still = ratio(row_still, best);
        let Some(moving) = row_moving else {
            return Some(still);
        };
        let best_moving = rows()
            .filter_map(|r| Self::own_of(r).1)
            .fold(f64::INFINITY, f64::min);
        Some(still.max(ratio(moving, best_moving)))
    }

    /// The expected error of every grid point the table covers, for `scene`: its own relative
    /// errors when the table holds the scene, else each point's worst relative error over the
    /// table's scenes (module docs). Points missing for some scene are left out.
    pub fn expected_errors(&self, scene: Option<&str>) -> Vec<(QualitySetting, f64)> {
        let own = scene.filter(|s| self.rows.iter().any(|r| r.scene == *s));
        let scenes = match own {
            Some(s) => vec![s.to_owned()],
            None => self.scenes(),
        };
        QualitySetting::grid()
            .into_iter()
            .filter_map(|g| {
                let mut worst = 0.0f64;
                for s in &scenes {
                    worst = worst.max(self.relative_error(s, &g)?);
                }
                Some((g, worst))
            })
            .collect()
    }

    /// Whether the table holds measurements of `scene`.
    pub fn has_scene(&self, scene: &str) -> bool {
        self.rows.iter().any(|r| r.scene == scene)
    }
}

/// Per-pass GPU times from the start-up probe, in ms at the output size.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CostModel {
    /// Pass name → ms with ReSTIR GI, specular GI, DI reuse and the upscaler on.
    pub full: HashMap<String, f64>,
    /// ReSTIR DI's passes with reuse off.
    pub di_no_reuse: f64,
    /// The GI passes with reuse off (plain path GI).
    pub gi_path: f64,
}

impl CostModel {
    fn ms(&self, pass: &str) -> f64 {
        self.full.get(pass).copied().unwrap_or(0.0)
    }

    /// Predicted GPU ms per frame of `setting` (module docs).
    pub fn predict(&self, setting: &QualitySetting) -> f64 {
        let constant: f64 = [
            "light_tiles",
            "world_cache_decay",
            "world_cache_compact",
            "world_cache_update",
            "world_cache_blend",
        ]
        .iter()
        .map(|p| self.ms(p))
        .sum();
        let di = if setting.di_reuse {
            self.ms("di_initial_temporal") + self.ms("di_spatial_shade")
        } else {
            self.di_no_reuse
        };
        let gi = match setting.gi {
            GiMode::WorldCache => CACHE_GI_PER_GBUFFER * self.ms("gbuffer"),
            GiMode::Restir => self.ms("gi_initial_temporal") + self.ms("gi_spatial_shade"),
            _ => self.gi_path,
        };
        let specular = if setting.specular_gi() {
            self.ms("specular_gi") + self.ms("gbuffer_override")
        } else {
            0.0
        };
        let denoise =
            self.ms("denoise_temporal") + self.ms("denoise_variance") + self.ms("denoise_atrous");
        let per_pixel = self.ms("gbuffer") + di + gi + specular + denoise;
        let f = (setting.resolution.scale() as f64).powi(2);
        let upscale = if setting.resolution.upscaled() {
            self.ms("temporal_upscale")
        } else {
            0.0
        };
        constant + per_pixel * (f + FIXED_SHARE * (1.0 - f)) + upscale
    }
}

/// What automatic quality chose, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct AutoChoice {
    /// The grid point.
    pub setting: QualitySetting,
    /// Its predicted GPU ms per frame.
    pub predicted_ms: f64,
    /// Its expected error (a multiple of the best measured).
    pub expected_error: f64,
    /// Whether it fits the budget (when nothing does, the cheapest point is chosen).
    pub fits: bool,
    /// How many grid points were predicted to fit.
    pub fitting: usize,
}

/// The point of `errors` with the least expected error among those `model` predicts within
/// `budget_ms`; ties go to the cheaper. When none fits, the cheapest. `None` for no points.
pub fn choose(
    budget_ms: f64,
    model: &CostModel,
    errors: &[(QualitySetting, f64)],
) -> Option<AutoChoice> {
    let predicted: Vec<(QualitySetting, f64, f64)> = errors
        .iter()
        .map(|&(g, e)| (g, model.predict(&g), e))
        .collect();
    let fitting: Vec<_> = predicted
        .iter()
        .filter(|(_, ms, _)| *ms <= budget_ms)
        .collect();
    let pick = |v: &[&(QualitySetting, f64, f64)],
                key: fn(&(QualitySetting, f64, f64)) -> (f64, f64)| {
        v.iter()
            .min_by(|a, b| key(a).partial_cmp(&key(b)).expect("finite"))
            .map(|c| **c)
    };
    let n = fitting.len();
    let (setting, predicted_ms, expected_error) = if n > 0 {
        pick(&fitting, |c| (c.2, c.1))?
    } else {
        let all: Vec<_> = predicted.iter().collect();
        pick(&all, |c| (c.1, c.2))?
    };
    Some(AutoChoice {
        setting,
        predicted_ms,
        expected_error,
        fits: n > 0,
        fitting: n,
    })
}

/// Frames the probe renders in each of its three phases (the first of each is not timed).
pub const PROBE_FRAMES: u32 = 6;

/// Seconds each probe renderer keeps the GPU busy (frames in flight, untimed) before its
/// frames are timed. An idle GPU clocks down: on an H100 the SM clock fell from 1980 to 345
/// MHz within 1.5 s of idling (a first run's shader compile takes about 6 s), and the
/// probe's 18 waited-for frames then ran 3-4× slow, predicting the Cornell box's default at
/// 6.1-6.6 ms against 1.53 measured; under full load the clock was back at 1980 MHz within
/// 0.2 s (`benches/RESULTS.md`).
pub const WARM_UP_SECONDS: f64 = 0.3;

/// Most frames a probe renderer waits for the world cache's warm-up rounds to end, past
/// [`WARM_UP_SECONDS`] (the default warm-up is 8 frames): a longer warm-up the user asked
/// for (`WorldCacheSettings::warm_up_frames`, up to 100,000) would otherwise hold the probe
/// that long. Past it the phases time frames that still run the rounds, and a warning says
/// so.
pub const MAX_CACHE_WARM_UP_WAIT: u32 = 64;

// Keeps the GPU busy with `renderer`'s frames for WARM_UP_SECONDS; returns how many.
fn warm_up(
    gpu: &Gpu,
    renderer: &mut RealtimeRenderer,
    scene: &Scene,
    gpu_scene: &GpuScene,
    camera: &Camera,
) -> Result<u32, GpuError> {
    let start = Instant::now();
    let mut frames = 0;
    // bound: WARM_UP_SECONDS of frames, then up to MAX_CACHE_WARM_UP_WAIT more while the
    // world cache's warm-up rounds last (8 frames by default), whose extra update rounds
    // would count in the phase's times on a slow adapter.
    loop {
        let warm = start.elapsed().as_secs_f64() >= WARM_UP_SECONDS;
        if warm && (!renderer.cache_warming_up() || frames >= MAX_CACHE_WARM_UP_WAIT) {
            break;
        }
        renderer.submit(gpu, scene, gpu_scene, camera)?;
        frames += 1;
    }
    if renderer.cache_warming_up() {
        log::warn!(
            "quality auto: the world cache's warm-up rounds outlast the probe's {frames} \
             warm-up frames; its times include them"
        );
    }
    renderer.finish(gpu)?;
    Ok(frames)
}

/// Times the passes of `scene` on this adapter at `size` (module docs): one renderer built
/// from `base` with every costly option on for two phases, then one built for path GI,
/// [`PROBE_FRAMES`] frames in each phase.
/// `Ok(None)` where the adapter has no timestamp queries (nothing can be predicted; no
/// renderer is built); an error where the renderer cannot be built or a frame fails.
pub fn probe(
    gpu: &Gpu,
    backend: Backend,
    scene: &Scene,
    gpu_scene: &GpuScene,
    camera: &Camera,
    size: (u32, u32),
    base: &RealtimeSettings,
) -> Result<Option<CostModel>, GpuError> {
    if !gpu.features.contains(wgpu::Features::TIMESTAMP_QUERY) {
        return Ok(None);
    }
    let full = QualitySetting {
        resolution: Resolution::Antialiased,
        gi: GiMode::Restir,
        di_reuse: true,
    };
    let timed = |setting: QualitySetting| RealtimeSettings {
        timestamps: true,
        // Every frame: the user's interval (the CLI's `--time-every`, 8 by default) left the
        // probe's five timed frames a phase with one timed frame or none, at random by the
        // warm-up's frame count; with none the probe reported an adapter that cannot time
        // passes, and a later phase without times predicted its passes at zero.
        timestamp_interval: 1,
        finite_check: crate::realtime::FiniteCheck::Off,
        ..setting.apply(base)
    };
    let settings = timed(full);
    let mut renderer =
        RealtimeRenderer::new(gpu, backend, scene, gpu_scene, size.0, size.1, settings)?;
    let warm = warm_up(gpu, &mut renderer, scene, gpu_scene, camera)?;
    log::debug!("quality auto: {warm} warm-up frames before the first phase");
    let phase = |r: &mut RealtimeRenderer| -> Result<HashMap<String, f64>, GpuError> {
        let mut sums: HashMap<String, (f64, u32)> = HashMap::new();
        for frame in 0..PROBE_FRAMES {
            let report = r.render(gpu, scene, gpu_scene, camera)?;
            if frame == 0 {
                continue;
            }
            for p in &report.passes {
                if let (true, Some(ms)) = (p.ran, p.gpu_ms) {
                    let e = sums.entry(p.name.to_owned()).or_default();
                    e.0 += ms;
                    e.1 += 1;
                }
            }
        }
        Ok(sums
            .into_iter()
            .map(|(k, (s, n))| (k, s / n as f64))
            .collect())
    };
    let times = phase(&mut renderer)?;
    if !times.contains_key("gbuffer") {
        // The feature is there but the passes came back untimed (timestamps inside passes
        // missing): nothing to predict from.
        return Ok(None);
    }
    let mut di = settings.di;
    di.temporal = false;
    di.spatial = false;
    renderer.set_di_settings(di)?;
    let no_reuse = phase(&mut renderer)?;
    let di_no_reuse = ["di_initial_temporal", "di_spatial_shade"]
        .iter()
        .map(|p| no_reuse.get(*p).copied().unwrap_or(0.0))
        .sum();
    // Plain path GI runs one pass in a `RestirGi` built without reuse; one built for reuse
    // and run without it (`set_gi_settings`) still runs two, which over-predicted the default
    // frame by 0.09-0.15 ms (4-8%) at 1080p on an H100. So the last phase has a renderer of
    // its own, built for path GI.
    drop(renderer);
    let path_gi = timed(QualitySetting {
        gi: GiMode::Path,
        ..full
    });
    let mut renderer =
        RealtimeRenderer::new(gpu, backend, scene, gpu_scene, size.0, size.1, path_gi)?;
    let warm = warm_up(gpu, &mut renderer, scene, gpu_scene, camera)?;
    log::debug!("quality auto: {warm} warm-up frames before the path GI phase");
    let path = phase(&mut renderer)?;
    let gi_path = ["gi_initial_temporal", "gi_spatial_shade"]
        .iter()
        .map(|p| path.get(*p).copied().unwrap_or(0.0))
        .sum();
    Ok(Some(CostModel {
        full: times,
        di_no_reuse,
        gi_path,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cost model from the sweep's own per-pass times (interior, 1080p, H100): the
    /// predictions land within 15% of the measured frame times of all 24 points.
    #[test]
    fn predictions_follow_the_measured_sweep() {
        let full: HashMap<String, f64> = [
            ("denoise_atrous", 1.713),
            ("denoise_temporal", 0.132),
            ("denoise_variance", 0.15),
            ("di_initial_temporal", 1.521),
            ("di_spatial_shade", 1.897),
            ("gbuffer", 0.509),
            ("gbuffer_override", 0.039),
            ("gi_initial_temporal", 1.649),
            ("gi_spatial_shade", 3.95),
            ("light_tiles", 0.02),
            ("specular_gi", 0.64),
            ("temporal_upscale", 0.082),
            ("world_cache_blend", 0.021),
            ("world_cache_compact", 0.031),
            ("world_cache_decay", 0.011),
            ("world_cache_update", 0.145),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_owned(), v))
        .collect();
        let model = CostModel {
            full,
            di_no_reuse: 0.826 + 0.539,
            gi_path: 1.332 + 0.14,
        };
        let table = ErrorTable::builtin();
        for g in QualitySetting::grid() {
            let measured = table.gpu_ms("interior", &g).expect("measured");
            let predicted = model.predict(&g);
            assert!(
                (predicted / measured - 1.0).abs() < 0.15,
                "{}: predicted {predicted:.2} ms, measured {measured:.2}",
                g.name()
            );
        }
    }

    #[test]
    fn choose_takes_the_least_error_that_fits_else_the_cheapest() {
        let model = CostModel {
            full: [("gbuffer", 1.0)].map(|(k, v)| (k.to_owned(), v)).into(),
            di_no_reuse: 0.5,
            gi_path: 1.0,
        };
        let table = ErrorTable::builtin();
        let errors = table.expected_errors(Some("interior"));
        assert_eq!(errors.len(), 24);
        let generous = choose(1e9, &model, &errors).expect("points");
        let best = errors.iter().map(|e| e.1).fold(f64::INFINITY, f64::min);
        assert!(generous.fits && generous.fitting == 24);
        assert_eq!(generous.expected_error, best);
        let none = choose(0.0, &model, &errors).expect("points");
        assert!(!none.fits && none.fitting == 0);
        let cheapest = errors
            .iter()
            .map(|(g, _)| model.predict(g))
            .fold(f64::INFINITY, f64::min);
        assert_eq!(none.predicted_ms, cheapest);
        // Every budget gives a point that fits it, with an error no worse than any cheaper fit.
        for budget in [0.4, 0.8, 1.2, 2.0, 3.0] {
            let c = choose(budget, &model, &errors).expect("points");
            if c.fits {
                assert!(c.predicted_ms <= budget);
                for (g, e) in &errors {
                    if model.predict(g) <= budget {
                        assert!(
                            c.expected_error <= *e,
                            "{budget}: {} over {}",
                            c.setting.name(),
                            g.name()
                        );
                    }
                }
            }
        }
        assert!(choose(1.0, &model, &[]).is_none());
    }

    #[test]
    fn unknown_scenes_get_the_worst_case_over_the_table() {
        let table = ErrorTable::builtin();
        let generic = table.expected_errors(Some("not_measured"));
        assert_eq!(generic, table.expected_errors(None));
        for (g, e) in &generic {
            for s in table.scenes() {
                assert!(*e >= table.relative_error(&s, g).unwrap());
            }
        }
        // The point that is never far off anywhere: native antialiased ReSTIR GI (1.18×, the
        // Cornell box moving, with the references' noise out); path GI's (the defaults)
        // 1.22× (the Cornell box still).
        let best = generic
            .iter()
            .min_by(|a, b| a.1.partial_cmp(&b.1).unwrap())
            .unwrap();
        assert_eq!(best.0.name(), "aa-restir");
        assert!(best.1 < 1.2);
        let defaults = generic.iter().find(|g| g.0.name() == "aa-path").unwrap();
        assert!(defaults.1 < 1.25);
    }

    #[test]
    fn a_point_is_judged_by_the_worse_of_still_and_moving() {
        let t = ErrorTable::parse_csv(
            "scene,setting,gpu_ms,rel_mse,rel_mse_moving\n\
             x,50-path,1,0.01,0.5\n\
             x,100-path,2,0.02,0.01\n\
             x,aa-path,2,0.015,nan\n\
             x,67-path,2,0.012,\n",
        )
        .expect("parses");
        let g = |n: &str| QualitySetting::parse(n).unwrap();
        assert_eq!(t.rows[0].rel_mse_moving, Some(0.5));
        assert_eq!(t.rows[2].rel_mse_moving, None);
        assert_eq!(t.rows[3].rel_mse_moving, None);
        // Best still 0.01 (50-path), best moving 0.01 (100-path).
        assert_eq!(t.relative_error("x", &g("50-path")), Some(50.0));
        assert_eq!(t.relative_error("x", &g("100-path")), Some(2.0));
        // Without a moving figure, the still one alone.
        assert_eq!(t.relative_error("x", &g("aa-path")), Some(1.5));
        let best = t
            .expected_errors(Some("x"))
            .into_iter()
            .min_by(|a, b| a.1.partial_cmp(&b.1).unwrap())
            .unwrap();
        assert_eq!(best.0.name(), "67-path");
        let e = ErrorTable::parse_csv(
            "scene,setting,gpu_ms,rel_mse,rel_mse_moving\nx,100-path,1,0.1,-2",
        )
        .unwrap_err();
        assert!(e.contains("line 2") && e.contains("out of range"), "{e}");
    }

    #[test]
    fn bad_tables_are_refused_with_the_line_named() {
        assert!(ErrorTable::parse_csv("").unwrap_err().contains("no header"));
        assert!(
            ErrorTable::parse_csv("scene,setting,gpu_ms\nx,100-path,1")
                .unwrap_err()
                .contains("rel_mse")
        );
        let e =
            ErrorTable::parse_csv("scene,setting,gpu_ms,rel_mse\nx,100-path,1,abc").unwrap_err();
        assert!(e.contains("line 2") && e.contains("abc"), "{e}");
        let e =
            ErrorTable::parse_csv("scene,setting,gpu_ms,rel_mse\nx,100-path,1,NaN").unwrap_err();
        assert!(e.contains("out of range"), "{e}");
        assert!(
            ErrorTable::parse_csv("scene,setting,gpu_ms,rel_mse\nx,auto8,1,0.1")
                .unwrap_err()
                .contains("no rows")
        );
        let t = ErrorTable::parse_csv(
            "# note\nrel_mse,scene,setting,gpu_ms,extra\n0.1,x,aa-path,2,y\n",
        )
        .expect("columns in any order");
        assert_eq!(t.rows.len(), 1);
        assert_eq!(
            t.relative_error("x", &QualitySetting::parse("aa-path").unwrap()),
            Some(1.0)
        );
        let e = ErrorTable::parse_csv(
            "scene,setting,gpu_ms,rel_mse,reference_noise\nx,100-path,1,0.1,-0.01",
        )
        .unwrap_err();
        assert!(e.contains("out of range"), "{e}");
    }

    /// The references' noise, a constant per scene and camera, comes out before the ratios:
    /// 0.03 and 0.02 against a reference that adds 0.01 are 2× apart, not 1.5×; moving
    /// figures take their own noise; a point measured below the noise counts by
    /// `MIN_OWN_ERROR_SHARE` of its figure; tables without the columns read as before.
    #[test]
    fn the_references_noise_comes_out_before_the_ratios() {
        let p = |n: &str| QualitySetting::parse(n).unwrap();
        let t = ErrorTable::parse_csv(
            "scene,setting,gpu_ms,rel_mse,rel_mse_moving,reference_noise,reference_noise_moving\n\
             x,100-path,2,0.03,0.05,0.01,0.04\n\
             x,aa-path,2,0.02,0.06,0.01,0.04\n\
             x,50-path,1,0.009,0.08,0.01,0.04\n",
        )
        .expect("parses");
        let own = t.own_error("x", &p("100-path")).unwrap();
        assert!((own.0 - 0.02).abs() < 1e-12 && (own.1.unwrap() - 0.01).abs() < 1e-12);
        // Below the noise: 5% of 0.009.
        let below = t.own_error("x", &p("50-path")).unwrap().0;
        assert!((below - MIN_OWN_ERROR_SHARE * 0.009).abs() < 1e-12);
        // Still: 0.02 / 0.00045; moving: 0.01 / 0.01, 0.02 / 0.01 and 0.04 / 0.01.
        let rel = |n: &str| t.relative_error("x", &p(n)).unwrap();
        assert!((rel("aa-path") - 0.01 / (MIN_OWN_ERROR_SHARE * 0.009)).abs() < 1e-9);
        assert!((rel("50-path") - 4.0).abs() < 1e-9);
        let plain = ErrorTable::parse_csv(
            "scene,setting,gpu_ms,rel_mse\nx,100-path,2,0.03\nx,aa-path,2,0.02\n",
        )
        .unwrap();
        assert!((plain.relative_error("x", &p("100-path")).unwrap() - 1.5).abs() < 1e-12);
        assert_eq!(plain.rows[0].reference_noise, 0.0);
        // A sweep from before the noise was recorded writes nan there: no noise.
        let old = ErrorTable::parse_csv(
            "scene,setting,gpu_ms,rel_mse,reference_noise,reference_noise_moving\n\
             x,100-path,2,0.03,nan,\n",
        )
        .unwrap();
        assert_eq!(
            (
                old.rows[0].reference_noise,
                old.rows[0].reference_noise_moving
            ),
            (0.0, 0.0)
        );
    }
}
