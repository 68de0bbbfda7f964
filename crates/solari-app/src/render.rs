//! `solari render`: primary-ray debug views written as PNG.

use crate::cli::{RenderArgs, parse_size};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
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
    let start = Instant::now();
    let view_kind = DebugView::parse(&args.view).ok_or_else(|| {
        format!(
            "--view {}: expected albedo, normal, depth or instance",
            args.view
        )
    })?;
    let (w, h) = parse_size(&args.size)?;
    let (name, scene) = args.scene.load()?;
    for warning in scene.warnings.lines() {
        log::warn!("{name}: {warning}");
    }
    let camera = scene
        .camera(args.scene.camera.as_deref())
        .ok_or_else(|| format!("no camera {:?} in {name}", args.scene.camera))?;
    let (gpu, backend) = args.scene.device()?;
    let options = GpuSceneOptions {
        bvh_quality: args.scene.quality()?,
        ..Default::default()
    };
    let gpu_scene = GpuScene::new(&gpu, &scene, backend, &options).map_err(|e| e.to_string())?;
    let pass = ViewPass::primary(&gpu, backend).map_err(|e| e.to_string())?;
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
        let v = serde_json::json!({"scene": name, "out": args.out, "view": args.view, "width": w, "height": h,
            "tracer": backend.name(), "adapter": gpu.info.name, "camera": camera.name, "seconds": elapsed});
        println!("{v}");
    } else {
        println!(
            "wrote {} ({w}x{h}, {} view, {} tracer on {}) in {elapsed:.2} s",
            args.out.display(),
            args.view,
            backend.name(),
            gpu.info.name
        );
    }
    Ok(())
}
