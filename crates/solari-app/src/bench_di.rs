//! `solari bench-di`: per-pass GPU times of the real-time frame, and a sweep over initial
//! candidates and light-tile settings that records run time against error (a CSV row per
//! setting; `cargo run -p solari-benches --bin plot-sweep` draws it).

use crate::bench_io::{emit_csv, errors, frame_bar, load_reference};
use solari_app::cli::{BenchDiArgs, Prepared};
use solari_lights::{LightGridSettings, LightTileSettings};
use solari_renderer::{RealtimeRenderer, RealtimeSettings};
use solari_restir::RestirDiSettings;

/// One measured setting.
struct Row {
    candidates: u32,
    tiles: LightTileSettings,
    grid: Option<LightGridSettings>,
    // The grid's build time (ms) and truncated cells.
    grid_build: (f64, u32),
    // Mean GPU ms per pass over the timed frames.
    gbuffer: f64,
    light_tiles: f64,
    initial_temporal: f64,
    spatial_shade: f64,
    // (RMSE, relative MSE) over the scored frames (`--error-frames`).
    error: Option<(f64, f64)>,
}

pub fn run(args: &BenchDiArgs) -> Result<(), String> {
    let (w, h) = args.size;
    let (candidates, tiles) = args.sweep()?;
    let grids = args.grids()?;
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
    let mut configs: Vec<(u32, LightTileSettings, Option<LightGridSettings>)> = Vec::new();
    for g in &grids {
        for t in &tiles {
            configs.extend(candidates.iter().map(|c| (*c, *t, *g)));
        }
    }
    let bar = frame_bar(configs.len() as u64 * args.frames as u64, false)?;
    let mut rows = Vec::new();
    for (c, t, g) in configs {
        let settings = RealtimeSettings {
            tiles: t,
            light_grid: g,
            di: RestirDiSettings {
                initial_candidates: c,
                ..Default::default()
            },
            timestamps: true,
            ..RealtimeSettings::direct_only()
        };
        let mut renderer = RealtimeRenderer::new(&gpu, backend, &scene, &gpu_scene, w, h, settings)
            .map_err(|e| e.to_string())?;
        let grid_build = renderer
            .light_grid_report()
            .map_or((0.0, 0), |r| (r.build_seconds * 1e3, r.truncated_cells));
        let mut sums = [0.0f64; 4];
        let names = [
            "gbuffer",
            "light_tiles",
            "di_initial_temporal",
            "di_spatial_shade",
        ];
        // Errors of the last `error_frames` frames: one frame's RMSE among thousands of lights
        // swings with the rare pixel that finds a near light, so several are averaged (as MSE).
        let first_scored = args.frames - args.error_frames.min(args.frames);
        let (mut mse, mut rel, mut scored) = (0.0f64, 0.0f64, 0u32);
        for frame in 0..args.frames {
            let r = renderer
                .render(&gpu, &scene, &gpu_scene, &camera)
                .map_err(|e| e.to_string())?;
            if frame >= args.warmup {
                for (s, n) in sums.iter_mut().zip(names) {
                    *s += r.gpu_ms(n).unwrap_or(0.0);
                }
            }
            if let Some(reference) = &reference
                && frame >= first_scored
            {
                let out = renderer.read_output(&gpu).map_err(|e| e.to_string())?;
                let rgb: Vec<[f32; 3]> = out.iter().map(|p| [p[0], p[1], p[2]]).collect();
                let (e, r) = errors(&rgb, reference);
                mse += e * e;
                rel += r;
                scored += 1;
            }
            bar.inc(1);
        }
        let timed = (args.frames - args.warmup) as f64;
        let error = (scored > 0).then(|| {
            let n = scored as f64;
            ((mse / n).sqrt(), rel / n)
        });
        rows.push(Row {
            candidates: c,
            tiles: t,
            grid: g,
            grid_build,
            gbuffer: sums[0] / timed,
            light_tiles: sums[1] / timed,
            initial_temporal: sums[2] / timed,
            spatial_shade: sums[3] / timed,
            error,
        });
    }
    bar.finish_and_clear();
    let header = "scene,width,height,tracer,adapter,candidates,tiles,samples_per_tile,\
                  light_grid_share,light_grid_build_ms,light_grid_truncated_cells,timed_frames,\
                  gbuffer_ms,light_tiles_ms,di_initial_temporal_ms,di_spatial_shade_ms,\
                  lighting_ms,rmse,rel_mse";
    let mut lines = vec![header.to_string()];
    for r in &rows {
        let (rmse, rel) = r.error.unwrap_or((f64::NAN, f64::NAN));
        lines.push(format!(
            "{name},{w},{h},{},{},{},{},{},{},{:.1},{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{rmse:.6},\
             {rel:.6}",
            backend.name(),
            gpu.info.name.replace(',', " "),
            r.candidates,
            r.tiles.tiles,
            r.tiles.samples_per_tile,
            r.grid
                .map_or("off".to_string(), |g| g.grid_share.to_string()),
            r.grid_build.0,
            r.grid_build.1,
            args.frames - args.warmup,
            r.gbuffer,
            r.light_tiles,
            r.initial_temporal,
            r.spatial_shade,
            r.light_tiles + r.initial_temporal + r.spatial_shade,
        ));
    }
    emit_csv(&lines, args.csv.as_ref())?;
    Ok(())
}
