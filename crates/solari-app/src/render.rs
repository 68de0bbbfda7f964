//! `solari render`: primary-ray debug views, or the reference path tracer (EXR + PNG).

use crate::cli::{Prepared, RenderArgs, parse_size};
use indicatif::{ProgressBar, ProgressStyle};
use solari_app::image_io;
use solari_app::reference::{ReferenceRenderer, ReferenceSettings, SAFETY_CAP};
use solari_lights::{LightList, Selection};
use solari_scene::gpu_scene::TraceVariant;
use solari_scene::gpu_types::{GpuView, NO_HIT};
use solari_scene::view_pass::{DebugView, ViewPass};
use std::time::Instant;

/// Converts the pass output to 8-bit RGBA for `view`.
pub fn to_rgba8(pixels: &[[f32; 4]], view: DebugView) -> Vec<u8> {
    let srgb = |l: f32| {
        let l = if l.is_finite() {
            l.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let c = if l <= 0.0031308 {
            l * 12.92
        } else {
            1.055 * l.powf(1.0 / 2.4) - 0.055
        };
        (c * 255.0 + 0.5) as u8
    };
    let unorm = |x: f32| {
        if x.is_finite() {
            (x.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
        } else {
            0
        }
    };
    let max_depth = pixels
        .iter()
        .map(|p| p[0])
        .filter(|d| d.is_finite() && *d > 0.0)
        .fold(0.0f32, f32::max);
    let mut out = Vec::with_capacity(pixels.len() * 4);
    for p in pixels {
        let rgb = match view {
            DebugView::Albedo => [srgb(p[0]), srgb(p[1]), srgb(p[2])],
            DebugView::Normal => [unorm(p[0]), unorm(p[1]), unorm(p[2])],
            DebugView::Depth => {
                // Near is bright; misses are black.
                let v = if p[0] > 0.0 && max_depth > 0.0 {
                    unorm(1.0 - 0.9 * p[0] / max_depth)
                } else {
                    0
                };
                [v, v, v]
            }
            DebugView::Instance => {
                let id = p[0].to_bits();
                if id == NO_HIT {
                    [0, 0, 0]
                } else {
                    // A hashed, well-spread colour per instance.
                    let h = id
                        .wrapping_mul(0x9E37_79B9)
                        .rotate_left(13)
                        .wrapping_mul(0x85EB_CA6B);
                    [
                        (h >> 24) as u8 | 0x30,
                        (h >> 16) as u8 | 0x30,
                        (h >> 8) as u8 | 0x30,
                    ]
                }
            }
        };
        out.extend_from_slice(&[rgb[0], rgb[1], rgb[2], 255]);
    }
    out
}

pub fn run(args: &RenderArgs) -> Result<(), String> {
    match args.mode.as_str() {
        "debug" => run_debug(args),
        "reference" => run_reference(args),
        "realtime" => crate::realtime_cmd::run(args),
        other => Err(format!(
            "--mode {other}: expected debug, reference or realtime"
        )),
    }
}

fn run_reference(args: &RenderArgs) -> Result<(), String> {
    let start = Instant::now();
    let (w, h) = parse_size(&args.size)?;
    let selection = match args.selection.as_str() {
        "power" => Selection::Power,
        "uniform" => Selection::Uniform,
        other => return Err(format!("--selection {other}: expected power or uniform")),
    };
    if args.spp == 0 {
        return Err("--spp must be at least 1".into());
    }
    let Prepared {
        name,
        scene,
        camera,
        gpu,
        backend,
        gpu_scene,
        ..
    } = args.scene.prepare()?;
    let lights = LightList::build(&scene);
    if lights.report != Default::default() {
        log::warn!("{name}: lights left out: {:?}", lights.report);
    }
    let renderer = ReferenceRenderer::new(&gpu, backend, TraceVariant::for_scene(&gpu_scene))
        .map_err(|e| e.to_string())?;
    let settings = ReferenceSettings {
        spp: args.spp,
        max_bounces: args.max_bounces.unwrap_or(u32::MAX),
        selection,
        pixel_centre: args.pixel_centre,
    };
    let bar = if args.json {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(args.spp as u64)
    };
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} spp  {elapsed} elapsed, ETA {eta}")
            .map_err(|e| e.to_string())?,
    );
    let image = renderer
        .render(
            &gpu,
            &gpu_scene,
            &lights,
            &camera,
            w,
            h,
            &settings,
            |done| bar.set_position(done as u64),
        )
        .map_err(|e| e.to_string())?;
    bar.finish_and_clear();
    let exr = args
        .exr
        .clone()
        .unwrap_or_else(|| args.out.with_extension("exr"));
    image_io::write_exr(&exr, w, h, &image.pixels)?;
    image_io::write_png(&args.out, w, h, &image.pixels, args.exposure)?;
    if image.capped_paths > 0 {
        log::warn!(
            "{} paths reached the safety cap of {SAFETY_CAP} bounces",
            image.capped_paths
        );
    }
    if image.rejected_samples > 0 {
        log::warn!(
            "{} non-finite path samples were dropped",
            image.rejected_samples
        );
    }
    let elapsed = start.elapsed().as_secs_f64();
    if args.json {
        let v = serde_json::json!({"scene": name, "mode": "reference", "png": args.out, "exr": exr,
            "width": w, "height": h, "spp": args.spp, "max_bounces": args.max_bounces,
            "selection": args.selection, "tracer": backend.name(), "adapter": gpu.info.name,
            "render_seconds": image.seconds, "seconds": elapsed,
            "capped_paths": image.capped_paths, "rejected_samples": image.rejected_samples});
        println!("{v}");
    } else {
        println!(
            "wrote {} and {} ({w}x{h}, {} spp, {} tracer on {}): rendered in {:.2} s, {elapsed:.2} s in all",
            exr.display(),
            args.out.display(),
            args.spp,
            backend.name(),
            gpu.info.name,
            image.seconds
        );
    }
    Ok(())
}

fn run_debug(args: &RenderArgs) -> Result<(), String> {
    let start = Instant::now();
    let view_name = args.view.as_deref().unwrap_or("albedo");
    let view_kind = DebugView::parse(view_name).ok_or_else(|| {
        format!(
            "--view {}: expected albedo, normal, depth or instance",
            view_name
        )
    })?;
    let (w, h) = parse_size(&args.size)?;
    let Prepared {
        name,
        scene: _,
        camera,
        gpu,
        backend,
        gpu_scene,
        ..
    } = args.scene.prepare()?;
    let pass = ViewPass::primary(&gpu, backend, TraceVariant::for_scene(&gpu_scene))
        .map_err(|e| e.to_string())?;
    let mut view = GpuView::new(&camera, w, h);
    view.view_mode = view_kind as u32;
    let target = pass.target(&gpu, &view).map_err(|e| e.to_string())?;
    let bytes = pass
        .run(&gpu, &gpu_scene, &target)
        .map_err(|e| e.to_string())?;
    let pixels: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
    let rgba = to_rgba8(pixels, view_kind);
    image::save_buffer(&args.out, &rgba, w, h, image::ExtendedColorType::Rgba8)
        .map_err(|e| format!("{}: {e}", args.out.display()))?;
    let elapsed = start.elapsed().as_secs_f64();
    if args.json {
        let v = serde_json::json!({"scene": name, "out": args.out, "view": view_name, "width": w, "height": h,
            "tracer": backend.name(), "adapter": gpu.info.name, "camera": camera.name, "seconds": elapsed});
        println!("{v}");
    } else {
        println!(
            "wrote {} ({w}x{h}, {} view, {} tracer on {}) in {elapsed:.2} s",
            args.out.display(),
            view_name,
            backend.name(),
            gpu.info.name
        );
    }
    Ok(())
}
