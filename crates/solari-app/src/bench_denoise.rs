//! `solari bench-denoise`: the fallback denoiser's cost, error and frame-to-frame change on a
//! static view, frame by frame. For each à-trous iteration count it runs ReSTIR DI (no GI)
//! with the fallback denoiser and writes one CSV row per frame: the denoiser's mean GPU ms
//! (from a separate run without read-backs: reading every frame back idles the GPU long
//! enough to drop its clocks, which made the same passes read 5× slower on the H200), the
//! RMSE of the raw frame, of the mean of all raw frames so far (plain accumulation) and of
//! the denoised frame against a direct-only reference, the denoised image's energy against
//! the reference's, and the RMS change from the previous frame (raw and denoised), which on
//! a static view is pure flicker. `cargo run -p solari-benches --bin plot-denoise` draws it.

use crate::bench_io::{emit_csv, errors, frame_bar, load_reference};
use solari_app::cli::{BenchDenoiseArgs, Prepared};
use solari_denoise::DenoiserKind;
use solari_denoise::fallback::PASS_LABELS;
use solari_renderer::{Antialias, RealtimeRenderer, RealtimeSettings};
use std::time::{Duration, Instant};

/// The CSV header; one row per (iterations, frame).
const HEADER: &str = "scene,width,height,tracer,adapter,iterations,frame,denoise_ms,\
                      rmse_raw,rmse_raw_mean,rmse_denoised,energy_denoised,\
                      change_raw,change_denoised";

/// Untimed leading frames of the timing run, at least.
const TIMING_WARMUP: u32 = 8;

/// Untimed lead of the timing run, at least.
const TIMING_WARMUP_TIME: Duration = Duration::from_secs(1);

/// A frame's linear RGB, row by row.
type Image = Vec<[f32; 3]>;

/// Drops alpha.
fn rgb(px: &[[f32; 4]]) -> Image {
    px.iter().map(|p| [p[0], p[1], p[2]]).collect()
}

/// Sum of all channels (f64, non-finite values count as zero so one bad pixel cannot hide
/// the rest; the denoiser's own tests check finiteness).
fn energy(px: &[[f32; 3]]) -> f64 {
    px.iter()
        .flatten()
        .map(|v| if v.is_finite() { *v as f64 } else { 0.0 })
        .sum()
}

pub fn run(args: &BenchDenoiseArgs) -> Result<(), String> {
    let (w, h) = args.size;
    // Checked before the scene loads (`BenchDenoiseArgs::check`).
    let sweep = args.sweep()?;
    let reference =
        load_reference(Some(&args.reference), w, h)?.ok_or("--reference is required")?;
    let reference_energy = energy(&reference).max(f64::MIN_POSITIVE);
    let Prepared {
        name,
        scene,
        camera,
        gpu,
        backend,
        gpu_scene,
        ..
    } = args.scene.prepare()?;
    let per_setting = args.timed_frames as u64 + args.frames as u64;
    let bar = frame_bar(sweep.len() as u64 * per_setting, false)?;
    let mut lines = vec![HEADER.to_string()];
    for denoise in sweep {
        let it = denoise.atrous_iterations;
        let settings = RealtimeSettings {
            timestamps: true,
            denoiser: Some(DenoiserKind::Fallback),
            denoise,
            // The denoiser's own output, unjittered, against the pixel-centre reference.
            antialias: Antialias::Off,
            ..RealtimeSettings::direct_only()
        };
        let new_renderer = || {
            RealtimeRenderer::new(&gpu, backend, &scene, &gpu_scene, w, h, settings)
                .map_err(|e| e.to_string())
        };
        let mut renderer = new_renderer()?;
        // Warm up for a while as well as a few frames: the GPU's clocks take time to rise
        // after the read-back-bound error run.
        let start = Instant::now();
        let mut warm = 0;
        while warm < TIMING_WARMUP || start.elapsed() < TIMING_WARMUP_TIME {
            renderer
                .render(&gpu, &scene, &gpu_scene, &camera)
                .map_err(|e| e.to_string())?;
            warm += 1;
        }
        let (mut ms, mut timed) = (0.0, 0);
        for _ in 0..args.timed_frames {
            let report = renderer
                .render(&gpu, &scene, &gpu_scene, &camera)
                .map_err(|e| e.to_string())?;
            let times: Vec<f64> = PASS_LABELS
                .iter()
                .filter_map(|p| report.gpu_ms(p))
                .collect();
            if times.len() == PASS_LABELS.len() {
                ms += times.iter().sum::<f64>();
                timed += 1;
            }
            bar.inc(1);
        }
        // NaN when nothing was timed (--timed-frames 0, or no timestamp queries).
        let denoise_ms = if timed > 0 {
            ms / timed as f64
        } else {
            f64::NAN
        };
        if timed == 0 && args.timed_frames > 0 {
            log::warn!("{}: no GPU timestamps; denoise_ms is NaN", gpu.info.name);
        }
        let mut renderer = new_renderer()?;
        let mut raw_sum = vec![[0.0f64; 3]; (w * h) as usize];
        // (raw, denoised) of the previous frame.
        let mut previous: Option<(Image, Image)> = None;
        for frame in 1..=args.frames {
            renderer
                .render(&gpu, &scene, &gpu_scene, &camera)
                .map_err(|e| e.to_string())?;
            let raw = rgb(&renderer.read_noisy(&gpu).map_err(|e| e.to_string())?);
            let denoised = rgb(&renderer.read_output(&gpu).map_err(|e| e.to_string())?);
            for (s, p) in raw_sum.iter_mut().zip(&raw) {
                for c in 0..3 {
                    s[c] += p[c] as f64;
                }
            }
            let mean: Image = raw_sum
                .iter()
                .map(|s| s.map(|v| (v / frame as f64) as f32))
                .collect();
            let (change_raw, change_denoised) = match &previous {
                Some((r, d)) => (errors(&raw, r).0, errors(&denoised, d).0),
                None => (f64::NAN, f64::NAN),
            };
            lines.push(format!(
                "{name},{w},{h},{},{},{it},{frame},{denoise_ms:.4},{:.6},{:.6},{:.6},{:.5},\
                 {change_raw:.6},{change_denoised:.6}",
                backend.name(),
                gpu.info.name.replace(',', " "),
                errors(&raw, &reference).0,
                errors(&mean, &reference).0,
                errors(&denoised, &reference).0,
                energy(&denoised) / reference_energy,
            ));
            previous = Some((raw, denoised));
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    emit_csv(&lines, args.csv.as_ref())
}
