//! `solari bench-cache`: the world cache's cost and cache-only GI's error. One row per
//! setting (a direct-light-only baseline first, then cell size × update budget): GPU ms per
//! upkeep pass and for the GI pass, live cells, overflows, memory, and RMSE / relative MSE of
//! one frame and of the mean of the timed frames against a full-bounce reference.

use crate::bench_io::{emit_csv, errors, frame_bar, load_reference};
use solari_app::cli::{BenchCacheArgs, Prepared};
use solari_renderer::{GiMode, RealtimeRenderer, RealtimeSettings};
use solari_worldcache::{PASS_LABELS, WorldCacheSettings};

// Passes timed per row: the cache's upkeep, its GI pass, and ReSTIR DI for scale.
const TIMED: [&str; 7] = [
    PASS_LABELS[0],
    PASS_LABELS[1],
    PASS_LABELS[2],
    PASS_LABELS[3],
    PASS_LABELS[4],
    "di_initial_temporal",
    "di_spatial_shade",
];

pub fn run(args: &BenchCacheArgs) -> Result<(), String> {
    let (w, h) = args.size;
    let (cell_sizes, budgets) = args.sweep()?;
    let reference = load_reference(args.reference.as_ref(), w, h)?;
    let Prepared {
        name,
        scene,
        camera,
        gpu,
        backend,
        gpu_scene,
        ..
    } = args.scene.prepare()?;
    // None: the direct-light-only baseline.
    let mut configs: Vec<Option<(f32, u32)>> = vec![None];
    for c in &cell_sizes {
        configs.extend(budgets.iter().map(|b| Some((*c, *b))));
    }
    let bar = frame_bar(configs.len() as u64 * args.frames as u64, false)?;
    let header = "scene,width,height,tracer,adapter,gi,cell_size,budget,capacity,timed_frames,\
                  decay_ms,compact_ms,update_ms,blend_ms,gi_ms,di_initial_temporal_ms,\
                  di_spatial_shade_ms,cache_ms,live_cells,overflows,cache_mib,\
                  rmse_frame,rel_mse_frame,rmse_mean,rel_mse_mean";
    let mut lines = vec![header.to_string()];
    for config in configs {
        let (gi, cache) = match config {
            None => (GiMode::Off, WorldCacheSettings::default()),
            Some((cell_size, update_budget)) => (
                GiMode::WorldCache,
                WorldCacheSettings {
                    cell_size,
                    update_budget,
                    capacity: args.capacity,
                    ..Default::default()
                },
            ),
        };
        let settings = RealtimeSettings {
            gi,
            cache,
            timestamps: true,
            ..RealtimeSettings::direct_only()
        };
        let mut renderer = RealtimeRenderer::new(&gpu, backend, &scene, &gpu_scene, w, h, settings)
            .map_err(|e| e.to_string())?;
        let mut ms = [0.0f64; TIMED.len()];
        let mut mean = vec![[0.0f64; 3]; (w * h) as usize];
        let timed = (args.frames - args.warmup) as f64;
        let mut last = Vec::new();
        for frame in 0..args.frames {
            let r = renderer
                .render(&gpu, &scene, &gpu_scene, &camera)
                .map_err(|e| e.to_string())?;
            if frame >= args.warmup {
                for (s, n) in ms.iter_mut().zip(TIMED) {
                    *s += r.gpu_ms(n).unwrap_or(0.0) / timed;
                }
                if reference.is_some() {
                    let out = renderer.read_output(&gpu).map_err(|e| e.to_string())?;
                    for (m, p) in mean.iter_mut().zip(&out) {
                        for c in 0..3 {
                            m[c] += p[c] as f64 / timed;
                        }
                    }
                    last = out;
                }
            }
            bar.inc(1);
        }
        let (frame_err, mean_err) = match &reference {
            Some(reference) => {
                let rgb: Vec<[f32; 3]> = last.iter().map(|p| [p[0], p[1], p[2]]).collect();
                let m: Vec<[f32; 3]> = mean.iter().map(|p| p.map(|x| x as f32)).collect();
                (errors(&rgb, reference), errors(&m, reference))
            }
            None => ((f64::NAN, f64::NAN), (f64::NAN, f64::NAN)),
        };
        let stats = renderer
            .cache_stats(&gpu)
            .map_err(|e| e.to_string())?
            .unwrap_or_default();
        let mib = renderer
            .world_cache()
            .map_or(0.0, |c| c.memory_bytes() as f64 / (1 << 20) as f64);
        let (cell, budget) = config.unwrap_or((0.0, 0));
        lines.push(format!(
            "{name},{w},{h},{},{},{},{cell},{budget},{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{},{},{mib:.1},{:.6},{:.6},{:.6},{:.6}",
            backend.name(),
            gpu.info.name.replace(',', " "),
            if config.is_some() { "cache" } else { "off" },
            if config.is_some() { args.capacity } else { 0 },
            args.frames - args.warmup,
            ms[0],
            ms[1],
            ms[2],
            ms[3],
            ms[4],
            ms[5],
            ms[6],
            ms[..5].iter().sum::<f64>(),
            stats.active_cells,
            stats.overflows,
            frame_err.0,
            frame_err.1,
            mean_err.0,
            mean_err.1,
        ));
    }
    bar.finish_and_clear();
    emit_csv(&lines, args.csv.as_ref())?;
    Ok(())
}
