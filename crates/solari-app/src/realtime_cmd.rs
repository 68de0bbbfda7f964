//! `solari render --mode realtime`: the frame loop on a fixed or scripted camera, a pass
//! report per frame, and the last frame written as EXR + PNG.

use crate::bench_io::frame_bar;
use crate::cli::{Prepared, RenderArgs, parse_size};
use solari_app::image_io;
use solari_app::realtime::{
    CameraPath, FrameReport, FrameView, GiMode, PASS_NAMES, RealtimeRenderer, RealtimeSettings,
};
use solari_denoise::{DenoiserKind, FallbackSettings};
use solari_lights::{LightTileSettings, Selection};
use solari_restir::RestirDiSettings;
use solari_worldcache::WorldCacheSettings;
use std::io::Write;
use std::time::Instant;

/// Settings from the command line.
pub fn settings(args: &RenderArgs) -> Result<RealtimeSettings, String> {
    let (tiles, samples_per_tile) = parse_size(&args.tiles).map_err(|_| {
        format!(
            "--tiles {}: expected TILESxSAMPLES, e.g. 128x1024",
            args.tiles
        )
    })?;
    let selection = match args.selection.as_str() {
        "power" => Selection::Power,
        "uniform" => Selection::Uniform,
        other => return Err(format!("--selection {other}: expected power or uniform")),
    };
    Ok(RealtimeSettings {
        tiles: LightTileSettings {
            tiles,
            samples_per_tile,
        },
        di: RestirDiSettings {
            initial_candidates: args.candidates,
            ..Default::default()
        },
        selection,
        gi: GiMode::parse(&args.gi)
            .ok_or_else(|| format!("--gi {}: expected off or cache", args.gi))?,
        cache: WorldCacheSettings {
            cell_size: args.cache_cell_size,
            update_budget: args.cache_budget,
            capacity: args.cache_capacity,
            ..Default::default()
        },
        view: match args.view.as_deref() {
            None => FrameView::Lit,
            Some(v) => FrameView::parse(v)
                .ok_or_else(|| format!("--view {v}: real-time mode shows lit or world-cache"))?,
        },
        timestamps: true,
        denoiser: match args.denoiser.as_deref() {
            None => None,
            Some(d) => Some(
                DenoiserKind::parse(d)
                    .ok_or_else(|| format!("--denoiser {d}: expected none, fallback or dlss-rr"))?,
            ),
        },
        denoise: FallbackSettings {
            atrous_iterations: args.denoise_iterations,
            max_history: args.denoise_max_history,
            firefly_clamp: args.firefly_clamp,
            ..Default::default()
        },
    })
}

pub fn run(args: &RenderArgs) -> Result<(), String> {
    let start = Instant::now();
    let (w, h) = parse_size(&args.size)?;
    if args.frames == 0 {
        return Err("--frames must be at least 1".into());
    }
    let path = CameraPath::parse(&args.camera_path).ok_or_else(|| {
        format!(
            "--camera-path {}: expected fixed or orbit",
            args.camera_path
        )
    })?;
    let settings = settings(args)?;
    let Prepared {
        name,
        scene,
        camera,
        gpu,
        backend,
        gpu_scene,
        dlss,
    } = args.scene.prepare()?;
    let mut renderer =
        RealtimeRenderer::with_dlss(&gpu, backend, &scene, &gpu_scene, w, h, settings, &dlss)
            .map_err(|e| e.to_string())?;
    if let Some(why) = renderer.denoiser_fallback_reason() {
        log::warn!("{why}");
    }
    log::info!(
        "denoiser: {} ({:.1} MiB)",
        renderer.denoiser_kind().name(),
        renderer.denoiser_memory_bytes() as f64 / (1 << 20) as f64
    );
    if renderer.lights().is_empty() {
        log::info!("{name} has no lights: light tiles and ReSTIR DI are skipped");
    }
    let mut report = match &args.report {
        Some(p) => Some(std::io::BufWriter::new(
            std::fs::File::create(p).map_err(|e| format!("{}: {e}", p.display()))?,
        )),
        None => None,
    };
    let bar = frame_bar(args.frames as u64, args.json)?;
    let mut reports = Vec::with_capacity(args.frames as usize);
    for frame in 0..args.frames {
        let cam = path.camera(&camera, &scene, frame);
        let r = renderer
            .render(&gpu, &scene, &gpu_scene, &cam)
            .map_err(|e| e.to_string())?;
        log::debug!("{}", report_line(&r));
        if let Some(out) = &mut report {
            writeln!(out, "{}", report_line(&r)).map_err(|e| e.to_string())?;
        }
        reports.push(r);
        bar.inc(1);
    }
    bar.finish_and_clear();
    if let Some(mut out) = report {
        out.flush().map_err(|e| e.to_string())?;
    }
    let pixels = renderer.read_output(&gpu).map_err(|e| e.to_string())?;
    let rgb: Vec<[f32; 3]> = pixels.iter().map(|p| [p[0], p[1], p[2]]).collect();
    let exr = args
        .exr
        .clone()
        .unwrap_or_else(|| args.out.with_extension("exr"));
    image_io::write_exr(&exr, w, h, &rgb)?;
    image_io::write_png(&args.out, w, h, &rgb, args.exposure)?;
    let cache = renderer.cache_stats(&gpu).map_err(|e| e.to_string())?;
    let cache_memory = renderer.world_cache().map(|c| c.memory_bytes());
    if let (Some(c), Some(bytes)) = (cache, cache_memory) {
        log::info!(
            "world cache: {} live cells, {} overflows in the last frame, {:.1} MiB",
            c.active_cells,
            c.overflows,
            bytes as f64 / (1 << 20) as f64
        );
        if c.overflows > 0 {
            log::warn!(
                "world cache table full ({} lookups found no slot): raise --cache-capacity",
                c.overflows
            );
        }
    }
    let summary = summarise(&reports);
    let elapsed = start.elapsed().as_secs_f64();
    if args.json {
        let passes: serde_json::Map<String, serde_json::Value> = summary
            .iter()
            .map(|(n, s)| (n.to_string(), serde_json::json!(s)))
            .collect();
        let v = serde_json::json!({"scene": name, "mode": "realtime", "png": args.out, "exr": exr,
            "width": w, "height": h, "frames": args.frames, "camera_path": args.camera_path,
            "candidates": args.candidates, "tiles": args.tiles, "tracer": backend.name(),
            "adapter": gpu.info.name, "passes": passes, "seconds": elapsed, "gi": args.gi,
            "cache_active_cells": cache.map(|c| c.active_cells),
            "cache_overflows": cache.map(|c| c.overflows), "cache_bytes": cache_memory,
            "denoiser": renderer.denoiser_kind().name(),
            "denoiser_fallback": renderer.denoiser_fallback_reason()});
        println!("{v}");
    } else {
        println!(
            "wrote {} and {} ({w}x{h}, {} frames, {} tracer on {}, denoiser {}) in {elapsed:.2} s",
            exr.display(),
            args.out.display(),
            args.frames,
            backend.name(),
            gpu.info.name,
            renderer.denoiser_kind().name()
        );
        println!("pass                  ran   GPU ms (mean over timed frames after the first)");
        for (n, s) in &summary {
            let ms = s
                .mean_ms
                .map_or("untimed".to_string(), |m| format!("{m:.3}"));
            println!("{n:<21} {:>4}  {ms}", s.frames_ran);
        }
    }
    Ok(())
}

/// One JSON line per frame: every pass, whether it ran and its GPU milliseconds.
pub fn report_line(r: &FrameReport) -> String {
    let passes: Vec<serde_json::Value> = r
        .passes
        .iter()
        .map(|p| serde_json::json!({"pass": p.name, "ran": p.ran, "gpu_ms": p.gpu_ms}))
        .collect();
    serde_json::json!({"frame": r.frame, "passes": passes}).to_string()
}

/// Per pass over a run.
#[derive(serde::Serialize)]
pub struct PassSummary {
    /// Frames in which the pass ran.
    pub frames_ran: usize,
    /// Mean GPU time over the frames it ran and was timed, the first frame left out (it
    /// pays for pipeline warm-up).
    pub mean_ms: Option<f64>,
}

/// Summaries in pass order.
pub fn summarise(reports: &[FrameReport]) -> Vec<(&'static str, PassSummary)> {
    PASS_NAMES
        .iter()
        .map(|&name| {
            let frames_ran = reports.iter().filter(|r| r.ran(name)).count();
            let times: Vec<f64> = reports
                .iter()
                .skip(1)
                .filter_map(|r| r.gpu_ms(name))
                .collect();
            let mean_ms =
                (!times.is_empty()).then(|| times.iter().sum::<f64>() / times.len() as f64);
            (
                name,
                PassSummary {
                    frames_ran,
                    mean_ms,
                },
            )
        })
        .collect()
}
