//! `--quality auto` for the commands that render in real time (`render --mode realtime`,
//! `view`): the start-up probe on this adapter, the error table (the shipped one or
//! `--quality-table`), the choice, and the line and JSON that report it.

use crate::cli::{RealtimeArgs, SceneArgs};
use crate::cli_values::QualityArg;
use solari_renderer::auto_quality::{self, ErrorTable};
use solari_renderer::{QualitySetting, QualityTier, RealtimeSettings};
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::GpuScene;
use solari_scene::shaders::Backend;
use solari_scene::{Camera, Scene};
use std::time::Instant;

/// What `--quality auto` chose and on what grounds.
#[derive(Clone, Debug, PartialEq)]
pub struct QualityReport {
    /// The grid point's name (`solari_renderer::QualitySetting::name`).
    pub chosen: String,
    /// Its predicted GPU ms per frame on this adapter.
    pub predicted_ms: f64,
    /// The budget.
    pub budget_ms: f64,
    /// Its expected relMSE as a multiple of the best measured.
    pub expected_error: f64,
    /// Whether it is predicted to fit (when nothing fits, the cheapest point is taken).
    pub fits: bool,
    /// Grid points predicted to fit.
    pub fitting: usize,
    /// Grid points the table has errors for (all 24 in the shipped table).
    pub considered: usize,
    /// The table's scene whose measurements were used (`None`: the worst case over the
    /// table's scenes).
    pub table_scene: Option<String>,
    /// Seconds the probe took.
    pub probe_seconds: f64,
    /// Every grid point's predicted GPU ms per frame, by name.
    pub predicted: Vec<(String, f64)>,
}

impl QualityReport {
    /// One line for the terminal.
    pub fn line(&self) -> String {
        format!(
            "quality auto: {} (predicted {:.2} ms of a {:.1} ms budget{}; {} of {} settings fit; \
             expected error {:.2}x the best, from {}), probed in {:.2} s",
            self.chosen,
            self.predicted_ms,
            self.budget_ms,
            if self.fits {
                ""
            } else {
                ": nothing fits, the cheapest taken"
            },
            self.fitting,
            self.considered,
            self.expected_error,
            self.table_scene
                .as_ref()
                .map_or("the worst case over the table's scenes".to_string(), |s| {
                    format!("the table's {s}")
                }),
            self.probe_seconds
        )
    }

    /// The report as JSON (the `quality` field of `render --json`).
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "chosen": self.chosen, "predicted_ms": self.predicted_ms,
            "budget_ms": self.budget_ms, "expected_error": self.expected_error,
            "fits": self.fits, "fitting": self.fitting, "considered": self.considered,
            "table_scene": self.table_scene,
            "probe_s": self.probe_seconds,
            "predicted_ms_per_setting": self.predicted.iter()
                .map(|(n, ms)| (n.clone(), serde_json::json!(ms)))
                .collect::<serde_json::Map<_, _>>(),
        })
    }
}

/// The name a scene is looked up by in an error table: the file's stem, `cornell_box` for
/// the built-in box (the bundled scene of that name), `None` for generated scenes.
pub fn table_scene_name(scene: &SceneArgs) -> Option<String> {
    if scene.generated.is_some() || scene.light_field.is_some() {
        return None;
    }
    match &scene.scene {
        Some(p) => p.file_stem().map(|s| s.to_string_lossy().into_owned()),
        None => Some("cornell_box".into()),
    }
}

/// The table `--quality-table` names, or the shipped one.
pub fn error_table(args: &RealtimeArgs) -> Result<ErrorTable, String> {
    match &args.quality_table {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .map_err(|e| format!("--quality-table {}: {e}", p.display()))?;
            ErrorTable::parse_csv(&text)
                .map_err(|e| format!("--quality-table {}: {e}", p.display()))
        }
        None => Ok(ErrorTable::builtin()),
    }
}

/// The scene and device a choice is made for.
pub struct Target<'a> {
    /// The device.
    pub gpu: &'a Gpu,
    /// Its tracing backend.
    pub backend: Backend,
    /// The CPU scene.
    pub scene: &'a Scene,
    /// The uploaded scene.
    pub gpu_scene: &'a GpuScene,
    /// The camera the probe renders from.
    pub camera: &'a Camera,
    /// The output size.
    pub size: (u32, u32),
    /// The name the table knows the scene by ([`table_scene_name`]).
    pub table_name: Option<String>,
}

/// `settings` as `--quality auto` chooses them (the probe runs here), or unchanged for any
/// other `--quality`. An adapter without timestamp queries cannot be probed: the default tier
/// (the library defaults) is used and a warning says why.
pub fn resolve(
    args: &RealtimeArgs,
    target: &Target,
    settings: RealtimeSettings,
) -> Result<(RealtimeSettings, Option<QualityReport>), String> {
    if args.quality != Some(QualityArg::Auto) {
        return Ok((settings, None));
    }
    let table = error_table(args)?;
    let start = Instant::now();
    let model = match auto_quality::probe(
        target.gpu,
        target.backend,
        target.scene,
        target.gpu_scene,
        target.camera,
        target.size,
        &settings,
    )
    .map_err(|e| format!("quality auto: the probe failed: {e}"))?
    {
        Some(m) => m,
        None => {
            log::warn!(
                "quality auto: this adapter cannot time passes (no timestamp queries); using \
                 the {} tier (the defaults)",
                QualityTier::default().name()
            );
            return Ok((QualityTier::default().apply(&settings), None));
        }
    };
    let probe_seconds = start.elapsed().as_secs_f64();
    let own = target.table_name.clone().filter(|n| table.has_scene(n));
    let errors = table.expected_errors(own.as_deref());
    let choice = auto_quality::choose(args.budget_ms as f64, &model, &errors)
        .ok_or("quality auto: the table has no setting to choose from")?;
    let report = QualityReport {
        chosen: choice.setting.name(),
        predicted_ms: choice.predicted_ms,
        budget_ms: args.budget_ms as f64,
        expected_error: choice.expected_error,
        fits: choice.fits,
        fitting: choice.fitting,
        considered: errors.len(),
        table_scene: own,
        probe_seconds,
        predicted: QualitySetting::grid()
            .iter()
            .map(|g| (g.name(), model.predict(g)))
            .collect(),
    };
    let chosen = choice.setting.apply(&settings);
    chosen.validate()?;
    Ok((chosen, Some(report)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;
    use solari_renderer::FrameView;
    use solari_scene::gpu_scene::GpuSceneOptions;

    #[derive(Parser)]
    struct Wrapper {
        #[command(flatten)]
        realtime: RealtimeArgs,
    }

    fn args(line: &[&str]) -> RealtimeArgs {
        Wrapper::parse_from(std::iter::once("test").chain(line.iter().copied())).realtime
    }

    // `--quality auto` on `gpu` for the built-in box at 64×64.
    fn resolve_on(
        gpu: &Gpu,
        line: &[&str],
    ) -> Result<(RealtimeSettings, Option<QualityReport>), String> {
        let backend = gpu.backend(Default::default()).expect("backend");
        let scene = solari_scene::default_scene::cornell_box();
        let gpu_scene =
            GpuScene::new(gpu, &scene, backend, &GpuSceneOptions::default()).expect("upload");
        let camera = scene.camera(None).expect("camera");
        let args = args(line);
        let settings = args.settings(FrameView::Lit)?;
        let target = Target {
            gpu,
            backend,
            scene: &scene,
            gpu_scene: &gpu_scene,
            camera: &camera,
            size: (64, 64),
            table_name: Some("cornell_box".into()),
        };
        resolve(&args, &target, settings)
    }

    #[test]
    fn auto_without_timestamps_falls_back_to_the_default_tier() {
        let Some(full) = solari_scene::gpu::test_gpu() else {
            return;
        };
        // With timestamps the probe runs and reports its choice.
        let (_, report) = resolve_on(&full, &["--quality", "auto", "--budget-ms", "8"]).unwrap();
        let report = report.expect("a probed choice");
        assert!(report.considered > 0 && report.budget_ms == 8.0);
        drop(full);
        // Without, the default tier and no report (a warning says why).
        let gpu = solari_scene::gpu::Gpu::new_without(wgpu::Features::TIMESTAMP_QUERY).unwrap();
        let line = ["--quality", "auto", "--budget-ms", "8"];
        let (settings, report) = resolve_on(&gpu, &line).unwrap();
        assert_eq!(report, None);
        let plain = args(&line).settings(FrameView::Lit).unwrap();
        assert_eq!(settings, QualityTier::default().apply(&plain));
    }
}
