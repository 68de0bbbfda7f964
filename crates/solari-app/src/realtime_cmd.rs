//! `solari render --mode realtime`: the frame loop on a fixed or scripted camera, a pass
//! report per frame (with `--check-finite`, the non-finite detector's counts, stopping at the
//! first bad frame), and the last frame written to the `--out` files.

use crate::bench_io::frame_bar;
use solari_app::cli::{Prepared, RenderArgs, RenderPlan};
use solari_app::output::AtomicFile;
use solari_app::quality_choice::{Target, resolve, table_scene_name};
use solari_renderer::{FrameReport, PASS_NAMES, RealtimeRenderer};
use std::io::Write;
use std::time::Instant;

pub fn run(args: &RenderArgs, plan: &RenderPlan) -> Result<(), String> {
    let start = Instant::now();
    let (w, h) = args.size;
    let settings = plan
        .realtime
        .expect("the plan of real-time mode holds its settings");
    let path = args.realtime.camera_path;
    let Prepared {
        name,
        scene,
        camera,
        gpu,
        backend,
        gpu_scene,
        dlss,
        load_seconds,
        upload_seconds,
    } = args.scene.prepare()?;
    let target = Target {
        gpu: &gpu,
        backend,
        scene: &scene,
        gpu_scene: &gpu_scene,
        camera: &camera,
        size: (w, h),
        table_name: table_scene_name(&args.scene),
    };
    let (settings, quality) = resolve(&args.realtime, &target, settings)?;
    if let Some(q) = &quality {
        eprintln!("{}", q.line());
    }
    let build_start = Instant::now();
    let mut renderer =
        RealtimeRenderer::with_dlss(&gpu, backend, &scene, &gpu_scene, w, h, settings, &dlss)
            .map_err(|e| e.to_string())?;
    let renderer_seconds = build_start.elapsed().as_secs_f64();
    if let Some(why) = renderer.denoiser_fallback_reason() {
        log::warn!("{why}");
    }
    let gbuffer = renderer.gbuffer();
    log::info!(
        "G-buffer: {}{}",
        gbuffer.producer().name(),
        gbuffer
            .trace_variant()
            .map_or(String::new(), |v| format!(" ({})", v.name()))
    );
    log::info!(
        "denoiser: {} ({:.1} MiB)",
        renderer.denoiser_kind().name(),
        renderer.denoiser_memory_bytes() as f64 / (1 << 20) as f64
    );
    if renderer.lights().is_empty() {
        log::info!("{name} has no lights: light tiles and ReSTIR DI are skipped");
    }
    let mut report = match &args.report {
        Some(p) => Some(AtomicFile::create(p)?),
        None => None,
    };
    let bar = frame_bar(args.frames as u64, args.json)?;
    let mut summary = Summary::default();
    let mut take = |r: FrameReport| -> Result<(), String> {
        log::debug!("{}", report_line(&r));
        if let Some(out) = &mut report {
            writeln!(out.writer(), "{}", report_line(&r)).map_err(|e| e.to_string())?;
        }
        summary.add(&r);
        Ok(())
    };
    // Frames go to the GPU without waiting for it (`submit`); their reports arrive
    // `--frames-in-flight` - 1 frames late. Wall time counts from the second frame (the first
    // builds pipelines) to the last frame's completion.
    let mut loop_start = None;
    // `--mean-of`: the last frames are read back one by one and averaged.
    let mean_from = args.frames - args.mean_of.min(args.frames);
    let mut loop_end = None;
    let mut sum: Vec<[f64; 3]> = Vec::new();
    let rig = path.rig(&camera, &scene);
    for frame in 0..args.frames {
        if frame == 1 {
            loop_start = Some(Instant::now());
        }
        let cam = rig.at(frame);
        if let Some(r) = renderer
            .submit(&gpu, &scene, &gpu_scene, &cam)
            .map_err(|e| e.to_string())?
        {
            take(r)?;
        }
        if args.mean_of > 1 && frame >= mean_from {
            for r in renderer.finish(&gpu).map_err(|e| e.to_string())? {
                take(r)?;
            }
            loop_end.get_or_insert((Instant::now(), frame));
            let pixels = renderer.read_output(&gpu).map_err(|e| e.to_string())?;
            sum.resize(pixels.len(), [0.0; 3]);
            for (s, p) in sum.iter_mut().zip(&pixels) {
                for c in 0..3 {
                    s[c] += p[c] as f64;
                }
            }
        }
        bar.inc(1);
    }
    for r in renderer.finish(&gpu).map_err(|e| e.to_string())? {
        take(r)?;
    }
    // Wall time per frame from the second frame to the last one submitted without waiting.
    let (end, last) = loop_end.unwrap_or((Instant::now(), args.frames));
    let wall_ms = loop_start
        .filter(|_| last > 1)
        .map(|t| (end - t).as_secs_f64() * 1e3 / (last - 1) as f64);
    bar.finish_and_clear();
    let rgb: Vec<[f32; 3]> = if sum.is_empty() {
        let pixels = renderer.read_output(&gpu).map_err(|e| e.to_string())?;
        pixels.iter().map(|p| [p[0], p[1], p[2]]).collect()
    } else {
        let n = args.mean_of.min(args.frames) as f64;
        sum.iter().map(|s| s.map(|v| (v / n) as f32)).collect()
    };
    let (ow, oh) = renderer.size();
    let exposure = renderer
        .settings()
        .view
        .tone_mapped()
        .then_some(args.exposure);
    plan.outputs.write(ow, oh, &rgb, exposure)?;
    if let Some(out) = report {
        out.commit()?;
    }
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
    let passes = summary.passes();
    let memory = renderer.memory();
    let renderer_bytes: u64 = memory.iter().map(|(_, b)| b).sum();
    let scene_bytes = gpu_scene.memory_bytes();
    // GPU time per frame: the passes' means summed.
    let gpu_frame_ms: Option<f64> = passes
        .iter()
        .filter_map(|(_, s)| s.mean_ms)
        .reduce(|a, b| a + b);
    let elapsed = start.elapsed().as_secs_f64();
    let files: Vec<_> = plan.outputs.files.iter().map(|(p, _)| p).collect();
    let applied = *renderer.settings();
    if args.json {
        let per_pass: serde_json::Map<String, serde_json::Value> = passes
            .iter()
            .map(|(n, s)| (n.to_string(), serde_json::json!(s)))
            .collect();
        let grid_json = renderer.light_grid_report().map(|g| {
            serde_json::json!({
                "cells": g.cells, "entries": g.entries, "max_lights": g.max_lights,
                "empty_cells": g.empty_cells, "truncated_cells": g.truncated_cells,
                "build_s": g.build_seconds})
        });
        let mut v = serde_json::json!({"scene": name, "mode": "realtime", "files": files,
            "width": ow, "height": oh, "frames": args.frames,
            "camera_path": format!("{path:?}").to_lowercase(),
            "candidates": applied.di.initial_candidates, "tiles": format!("{}x{}",
                args.realtime.tiles.tiles, args.realtime.tiles.samples_per_tile),
            "tracer": backend.name(), "adapter": gpu.info.name, "passes": per_pass,
            "brdf": args.scene.brdf.name(),
            "seconds": elapsed, "gi": format!("{:?}", applied.gi),
            "specular_gi": applied.specular_gi, "psr": applied.psr,
            "gi_samples": applied.restir_gi.initial_samples,
            "gi_spatial_visibility": applied.restir_gi.spatial_visibility.name(),
            "di_reuse": match (applied.di.temporal, applied.di.spatial) {
                _ if renderer.di_reuse_skipped() => "none",
                (true, true) => "all", (true, false) => "temporal",
                (false, true) => "spatial", (false, false) => "none" },
            "quality": quality.as_ref().map(|q| q.json()),
            "cache_active_cells": cache.map(|c| c.active_cells),
            "cache_overflows": cache.map(|c| c.overflows), "cache_bytes": cache_memory,
            "denoiser": renderer.denoiser_kind().name(),
            "denoiser_fallback": renderer.denoiser_fallback_reason(),
            "gbuffer": renderer.gbuffer().producer().name(),
            "memory_bytes": memory.iter().map(|(n, b)| (n.to_string(), serde_json::json!(b)))
                .chain([("renderer_total".to_string(), serde_json::json!(renderer_bytes)),
                        ("scene".to_string(), serde_json::json!(scene_bytes))])
                .collect::<serde_json::Map<_, _>>(),
            "wall_frame_ms": wall_ms, "fps": wall_ms.map(|m| 1e3 / m),
            "gpu_frame_ms": gpu_frame_ms,
            "frames_in_flight": args.realtime.frames_in_flight,
            "internal_scale": applied.internal_scale,
            "antialias": renderer.upscaling(),
            "load_s": load_seconds, "upload_s": upload_seconds,
            "renderer_build_s": renderer_seconds,
            "triangles": scene.stats().triangles, "instances": scene.instances.len(),
            "finite_checked": args.realtime.check_finite,
            "light_grid": grid_json});
        // (Outside the macro, which reaches its recursion limit with one more field.)
        v["denoise_kernel"] = applied.denoise.atrous_kernel.name().into();
        v["antialias_setting"] = applied.antialias.name().into();
        v["gi_half_rate"] = (applied.restir_gi.rate == solari_restir::GiRate::Half).into();
        v["gi_quarter_rate"] = (applied.restir_gi.rate == solari_restir::GiRate::Quarter).into();
        // In effect: it needs a reduced rate (and acts only with reuse, `gi`).
        v["gi_half_rate_spatial"] =
            (applied.restir_gi.rate.reduced() && applied.restir_gi.half_rate_spatial).into();
        v["gi_ignore_cold_cells"] = applied.restir_gi.ignore_cold_cells.into();
        v["gi_adaptive_cap"] = applied.restir_gi.adaptive_cap.into();
        // In effect: it needs two spatial rays.
        v["gi_shade_both"] = (applied.restir_gi.shade_both_samples
            && applied.restir_gi.spatial_visibility != solari_restir::SpatialVisibility::Chosen)
            .into();
        v["gi_own_share"] = applied.restir_gi.own_sample_share.into();
        v["gi_spatial_history"] = applied.restir_gi.spatial_history.into();
        v["gi_glossy_hits"] = applied.restir_gi.glossy_hits.name().into();
        v["gi_glossy_roughness"] = applied.restir_gi.glossy_hit_roughness.into();
        // In effect: the settings the running ReSTIR GI passes hold (none without traced GI;
        // path GI's without reuse).
        let running = renderer.gi_settings();
        v["gi_temporal_reuse"] = running.is_some_and(|s| s.temporal).into();
        v["gi_spatial_reuse"] = running.is_some_and(|s| s.spatial).into();
        v["gi_confidence_cap"] = applied.restir_gi.confidence_cap.into();
        v["gi_trace_fresh"] = applied.restir_gi.trace_fresh_pixels.into();
        // In effect, as the passes are built (one candidate, no reuse).
        v["gi_shade_apart"] = renderer.gi_shades_apart().into();
        v["cache_light_change_frames"] = applied.cache.light_change_frames.into();
        v["cache_warm_up"] = applied.cache.warm_up_exponent.into();
        v["cache_warm_up_rounds"] = applied.cache.warm_up_rounds.into();
        v["cache_warm_up_frames"] = applied.cache.warm_up_frames.into();
        v["di_reuse_skipped"] = renderer.di_reuse_skipped().into();
        v["gpu_span_ms"] = summary.span_ms().into();
        println!("{v}");
    } else {
        println!(
            "wrote {} ({ow}x{oh}, {} frames, {} tracer on {}, denoiser {}) in {elapsed:.2} s",
            plan.outputs.describe(),
            args.frames,
            backend.name(),
            gpu.info.name,
            renderer.denoiser_kind().name()
        );
        if args.realtime.check_finite {
            println!("non-finite detector: every pass of every frame was finite");
        }
        if renderer.di_reuse_skipped() {
            println!(
                "ReSTIR DI reuse skipped: the scene has few lights and the fallback denoiser \
                 runs (--di-reuse all keeps it)"
            );
        }
        if let Some(wall) = wall_ms {
            let gpu = match (gpu_frame_ms, summary.span_ms()) {
                (Some(g), Some(span)) => {
                    format!("{g:.3} ms in passes, {span:.3} ms first pass to last")
                }
                (Some(g), None) => format!("{g:.3} ms"),
                _ => "untimed".to_string(),
            };
            println!(
                "frame time: wall {wall:.3} ms ({:.0} fps), GPU {gpu}; {} frame(s) in flight, \
                 G-buffer {}",
                1e3 / wall,
                args.realtime.frames_in_flight,
                renderer.gbuffer().producer().name()
            );
        }
        println!(
            "set-up: scene loaded in {load_seconds:.2} s, uploaded (BVH built) in \
             {upload_seconds:.2} s, renderer built in {renderer_seconds:.2} s"
        );
        if let Some(grid) = renderer.light_grid_report() {
            println!("{}", grid.summary());
        }
        let mib = |b: u64| b as f64 / (1 << 20) as f64;
        let parts: Vec<String> = memory
            .iter()
            .map(|(n, b)| format!("{n} {:.1}", mib(*b)))
            .collect();
        println!(
            "GPU memory (MiB): {}; renderer {:.1}, scene {:.1}",
            parts.join(", "),
            mib(renderer_bytes),
            mib(scene_bytes)
        );
        println!("pass                  ran   GPU ms (mean over timed frames after the first)");
        for (n, s) in &passes {
            let ms = s
                .mean_ms
                .map_or("untimed".to_string(), |m| format!("{m:.3}"));
            println!("{n:<21} {:>4}  {ms}", s.frames_ran);
        }
    }
    Ok(())
}

/// One JSON line per frame: every pass, whether it ran and its GPU milliseconds, and the
/// frame's GPU span (null where the frame was not timed).
pub fn report_line(r: &FrameReport) -> String {
    let passes: Vec<serde_json::Value> = r
        .passes
        .iter()
        .map(|p| serde_json::json!({"pass": p.name, "ran": p.ran, "gpu_ms": p.gpu_ms}))
        .collect();
    let finite: Vec<serde_json::Value> = r
        .finite
        .iter()
        .map(|c| serde_json::json!({"pass": c.name, "non_finite": c.non_finite, "negative": c.negative}))
        .collect();
    serde_json::json!({"frame": r.frame, "passes": passes, "gpu_span_ms": r.gpu_span_ms, "finite": finite})
        .to_string()
}

/// Per pass over a run.
#[derive(serde::Serialize)]
pub struct PassSummary {
    /// Frames in which the pass ran.
    pub frames_ran: u64,
    /// Mean GPU time over the frames it ran and was timed, the first frame left out (it
    /// pays for pipeline warm-up).
    pub mean_ms: Option<f64>,
}

/// Running per-pass sums, so a run of any length needs constant memory.
#[derive(Default)]
pub struct Summary {
    // Per pass of PASS_NAMES: frames ran, timed frames after the first, their ms sum.
    ran: [u64; PASS_NAMES.len()],
    timed: [u64; PASS_NAMES.len()],
    ms: [f64; PASS_NAMES.len()],
    frames: u64,
    // Timed frames after the first and the sum of their GPU spans.
    spans: u64,
    span_ms: f64,
}

impl Summary {
    /// Adds one frame's report.
    pub fn add(&mut self, r: &FrameReport) {
        for (i, name) in PASS_NAMES.iter().enumerate() {
            if r.ran(name) {
                self.ran[i] += 1;
            }
            if self.frames > 0
                && let Some(ms) = r.gpu_ms(name)
            {
                self.timed[i] += 1;
                self.ms[i] += ms;
            }
        }
        if self.frames > 0
            && let Some(ms) = r.gpu_span_ms
        {
            self.spans += 1;
            self.span_ms += ms;
        }
        self.frames += 1;
    }

    /// Mean GPU span of a frame (first pass's start to last pass's end, see
    /// [`FrameReport::gpu_span_ms`]), the first frame left out.
    pub fn span_ms(&self) -> Option<f64> {
        (self.spans > 0).then(|| self.span_ms / self.spans as f64)
    }

    /// The summaries in pass order.
    pub fn passes(&self) -> Vec<(&'static str, PassSummary)> {
        PASS_NAMES
            .iter()
            .enumerate()
            .map(|(i, &name)| {
                (
                    name,
                    PassSummary {
                        frames_ran: self.ran[i],
                        mean_ms: (self.timed[i] > 0).then(|| self.ms[i] / self.timed[i] as f64),
                    },
                )
            })
            .collect()
    }
}
