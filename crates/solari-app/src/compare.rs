//! `solari compare`: error metrics of a test image against a reference.

use solari_app::cli::{CompareArgs, Prepared, SceneArgs};
use solari_app::output::write_atomic;
use solari_lights::{LightList, Selection};
use solari_reference::image_io::read_linear;
use solari_reference::metrics::{Metrics, ReferenceNoise, compare, heatmap, reference_noise};
use solari_reference::path_tracer::{ReferenceRenderer, ReferenceSettings};
use solari_scene::gpu_scene::TraceVariant;

/// Pixels that see an emitter directly: emission-only paths (no bounce) at 4 samples per pixel.
fn emitter_mask(args: &CompareArgs, w: u32, h: u32) -> Result<Option<Vec<bool>>, String> {
    let Some(path) = &args.mask_emitters else {
        return Ok(None);
    };
    let scene_args = SceneArgs {
        scene: (path.as_os_str() != "builtin").then(|| path.clone()),
        generated: None,
        light_field: None,
        tracer: solari_scene::gpu::TracerChoice::Auto,
        camera: args.camera.clone(),
        bvh_quality: solari_scene::bvh::BvhQuality::Medium,
        merge_instances: true,
        emitter_bvh: true,
        // Emission is seen directly (no bounce): the BRDF does not enter.
        brdf: Default::default(),
        // Point lights have no surface a camera sees.
        light_radius: 0.0,
        environment: None,
        environment_intensity: None,
        asset_root: None,
    };
    let Prepared {
        scene,
        camera,
        gpu,
        backend,
        gpu_scene,
        ..
    } = scene_args.prepare()?;
    let renderer = ReferenceRenderer::new(&gpu, backend, TraceVariant::for_scene(&gpu_scene))
        .map_err(|e| e.to_string())?;
    let settings = ReferenceSettings {
        spp: 4,
        max_bounces: 0,
        selection: Selection::Power,
        pixel_centre: false,
        min_bounces: 0,
    };
    let emission = renderer
        .render(
            &gpu,
            &gpu_scene,
            &LightList::build(&scene),
            &camera,
            w,
            h,
            &settings,
            |_| {},
        )
        .map_err(|e| e.to_string())?;
    // Keep pixels with no directly visible emission.
    Ok(Some(
        emission
            .pixels
            .iter()
            .map(|p| p.iter().all(|&c| c <= 0.0))
            .collect(),
    ))
}

fn print(label: &str, m: &Metrics) {
    println!(
        "{label}: RMSE {:.5}  relMSE {:.5}  FLIP {:.4}  FLIP(HDR) {:.4}  mean/reference {:.4}  over {} pixels{}",
        m.rmse,
        m.rel_mse,
        m.flip,
        m.flip_hdr,
        m.mean_ratio,
        m.pixels,
        if m.non_finite > 0 {
            format!(", {} NON-FINITE test pixels", m.non_finite)
        } else {
            String::new()
        }
    );
}

fn print_noise(n: &ReferenceNoise) {
    println!(
        "  the reference's noise: RMSE² {:.3e}, relMSE {:.5}; without it RMSE {:.5}, relMSE {:.5}",
        n.mse, n.rel_mse, n.rmse_excess, n.rel_mse_excess
    );
}

/// Refuses an image with non-finite pixels: every metric over it would be NaN.
fn finite(path: &std::path::Path, pixels: &[[f32; 3]]) -> Result<(), String> {
    let bad = pixels
        .iter()
        .filter(|p| p.iter().any(|c| !c.is_finite()))
        .count();
    if bad == 0 {
        Ok(())
    } else {
        Err(format!(
            "{}: {bad} non-finite pixel(s); metrics over them would be NaN",
            path.display()
        ))
    }
}

pub fn run(args: &CompareArgs) -> Result<(), String> {
    let (w, h, test) = read_linear(&args.test)?;
    let (rw, rh, reference) = read_linear(&args.reference)?;
    if (w, h) != (rw, rh) {
        return Err(format!(
            "{} is {w}x{h} but {} is {rw}x{rh}",
            args.test.display(),
            args.reference.display()
        ));
    }
    finite(&args.test, &test)?;
    finite(&args.reference, &reference)?;
    let (all, map) = compare(&test, &reference, w, h, None)?;
    let mask = emitter_mask(args, w, h)?;
    let masked = match &mask {
        Some(m) => Some(compare(&test, &reference, w, h, Some(m))?.0),
        None => None,
    };
    if let Some(path) = &args.heatmap {
        let png = solari_reference::image_io::encode_png_rgb8(w, h, &heatmap(&map, w, h))?;
        write_atomic(path, &png)?;
    }
    let noise = match &args.reference_variance {
        Some(path) => {
            let (vw, vh, variance) = read_linear(path)?;
            if (vw, vh) != (w, h) {
                return Err(format!(
                    "{} is {vw}x{vh} but the images are {w}x{h}",
                    path.display()
                ));
            }
            let of = |m: &Metrics, mask: Option<&[bool]>| {
                reference_noise(m, &reference, &variance, mask)
                    .map_err(|e| format!("{}: {e}", path.display()))
            };
            let masked_noise = match (&masked, &mask) {
                (Some(m), Some(mask)) => Some(of(m, Some(mask))?),
                _ => None,
            };
            Some((of(&all, None)?, masked_noise))
        }
        None => None,
    };
    if args.json {
        let v = serde_json::json!({"test": args.test, "reference": args.reference,
            "width": w, "height": h, "all": all, "without_emitters": masked,
            "reference_noise": noise.map(|(a, m)| serde_json::json!({
                "variance": args.reference_variance, "all": a, "without_emitters": m}))});
        println!("{v}");
    } else {
        print("all pixels", &all);
        if let Some((n, _)) = &noise {
            print_noise(n);
        }
        if let Some(m) = &masked {
            print("without emitters", m);
            if let Some((_, Some(n))) = &noise {
                print_noise(n);
            }
        }
    }
    Ok(())
}
