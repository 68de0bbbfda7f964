//! `solari render`: primary-ray debug views, the reference path tracer, or the real-time
//! renderer; every output's format follows its extension.

use indicatif::{ProgressBar, ProgressStyle};
use solari_app::cli::{Mode, Prepared, RenderArgs, RenderPlan};
use solari_app::output::{ImageFormat, write_atomic};
use solari_lights::LightList;
use solari_reference::image_io;
use solari_reference::path_tracer::{ReferenceRenderer, ReferenceSettings, SAFETY_CAP};
use solari_scene::gpu_scene::TraceVariant;
use solari_scene::gpu_types::{GpuView, NO_HIT};
use solari_scene::view_pass::{DebugView, ViewPass};
use std::time::Instant;

/// Converts the pass output to 8-bit RGB for `view`.
pub fn to_rgb8(pixels: &[[f32; 4]], view: DebugView) -> Vec<u8> {
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
    let mut out = Vec::with_capacity(pixels.len() * 3);
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
        out.extend_from_slice(&rgb);
    }
    out
}

pub fn run(args: &RenderArgs) -> Result<(), String> {
    let plan = args.check()?;
    match args.mode {
        Mode::Debug => run_debug(args, &plan),
        Mode::Reference => run_reference(args, &plan),
        Mode::Realtime => crate::realtime_cmd::run(args, &plan),
    }
}

fn run_reference(args: &RenderArgs, plan: &RenderPlan) -> Result<(), String> {
    let start = Instant::now();
    let (w, h) = args.size;
    let Prepared {
        name,
        scene,
        camera,
        gpu,
        backend,
        gpu_scene,
        ..
    } = args.scene.prepare()?;
    // The camera of real-time mode's last frame under the same `--camera-path` and
    // `--frames`, so a moving camera's frame has its reference.
    let camera = args
        .realtime
        .camera_path
        .camera(&camera, &scene, args.frames - 1);
    let lights = LightList::build(&scene);
    for line in lights.report.lines() {
        log::warn!("{name}: {line}");
    }
    let renderer = ReferenceRenderer::new(&gpu, backend, TraceVariant::for_scene(&gpu_scene))
        .map_err(|e| e.to_string())?;
    let settings = ReferenceSettings {
        spp: args.spp,
        max_bounces: args.max_bounces.unwrap_or(u32::MAX),
        selection: args.realtime.selection,
        pixel_centre: args.pixel_centre,
        min_bounces: args.min_bounces,
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
    plan.outputs
        .write(w, h, &image.pixels, Some(args.exposure))?;
    if let Some(path) = &args.variance_out {
        write_atomic(path, &image_io::encode_exr(w, h, &image.variance)?)?;
    }
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
    let files: Vec<_> = plan.outputs.files.iter().map(|(p, _)| p).collect();
    if args.json {
        let v = serde_json::json!({"scene": name, "mode": "reference", "files": files,
            "width": w, "height": h, "spp": args.spp, "max_bounces": args.max_bounces,
            "min_bounces": args.min_bounces,
            "selection": format!("{:?}", args.realtime.selection).to_lowercase(),
            "brdf": args.scene.brdf.name(),
            "camera_path": format!("{:?}", args.realtime.camera_path).to_lowercase(),
            "camera_frame": args.frames - 1,
            "tracer": backend.name(), "adapter": gpu.info.name,
            "render_seconds": image.seconds, "seconds": elapsed,
            "capped_paths": image.capped_paths, "rejected_samples": image.rejected_samples,
            "variance_file": args.variance_out});
        println!("{v}");
    } else {
        println!(
            "wrote {}{} ({w}x{h}, {} spp, {} tracer on {}): rendered in {:.2} s, {elapsed:.2} s in all",
            plan.outputs.describe(),
            args.variance_out
                .as_ref()
                .map(|v| format!(" and its variance {}", v.display()))
                .unwrap_or_default(),
            args.spp,
            backend.name(),
            gpu.info.name,
            image.seconds
        );
    }
    Ok(())
}

fn run_debug(args: &RenderArgs, plan: &RenderPlan) -> Result<(), String> {
    let start = Instant::now();
    let view_kind = plan.debug_view;
    let (w, h) = args.size;
    let Prepared {
        name,
        scene,
        camera,
        gpu,
        backend,
        gpu_scene,
        ..
    } = args.scene.prepare()?;
    // As reference mode: the camera of real-time mode's last frame under the same
    // `--camera-path` and `--frames`.
    let camera = args
        .realtime
        .camera_path
        .camera(&camera, &scene, args.frames - 1);
    let pass = ViewPass::primary(&gpu, backend, TraceVariant::for_scene(&gpu_scene))
        .map_err(|e| e.to_string())?;
    let mut view = GpuView::new(&camera, w, h);
    view.view_mode = view_kind as u32;
    let target = pass.target(&gpu, &view).map_err(|e| e.to_string())?;
    let bytes = pass
        .run(&gpu, &gpu_scene, &target)
        .map_err(|e| e.to_string())?;
    let pixels: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
    for (path, format) in &plan.outputs.files {
        let encoded = match format {
            ImageFormat::Png => image_io::encode_png_rgb8(w, h, &to_rgb8(pixels, view_kind))?,
            // The pass's values themselves (instance ids as their integer values).
            ImageFormat::Exr => {
                let linear: Vec<[f32; 3]> = pixels
                    .iter()
                    .map(|p| match view_kind {
                        DebugView::Instance if p[0].to_bits() == NO_HIT => [-1.0; 3],
                        DebugView::Instance => [p[0].to_bits() as f32; 3],
                        _ => [p[0], p[1], p[2]].map(|c| if c.is_finite() { c } else { 0.0 }),
                    })
                    .collect();
                image_io::encode_exr(w, h, &linear)?
            }
        };
        write_atomic(path, &encoded)?;
    }
    let elapsed = start.elapsed().as_secs_f64();
    let view_name = format!("{view_kind:?}").to_lowercase();
    let files: Vec<_> = plan.outputs.files.iter().map(|(p, _)| p).collect();
    if args.json {
        let v = serde_json::json!({"scene": name, "files": files, "view": view_name, "width": w, "height": h,
            "tracer": backend.name(), "adapter": gpu.info.name, "camera": camera.name,
            "camera_path": format!("{:?}", args.realtime.camera_path).to_lowercase(),
            "camera_frame": args.frames - 1, "seconds": elapsed});
        println!("{v}");
    } else {
        println!(
            "wrote {} ({w}x{h}, {view_name} view, {} tracer on {}) in {elapsed:.2} s",
            plan.outputs.describe(),
            backend.name(),
            gpu.info.name
        );
    }
    Ok(())
}
