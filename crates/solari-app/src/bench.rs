//! `solari bench-rays`: BVH build speed and GPU ray throughput, timed with timestamp queries.
//!
//! Workload (the tray_racing peer's): one primary ray per pixel plus one cosine-distributed
//! hemisphere ray from every primary hit, both closest-hit. Also primary rays alone.

use glam::Vec3;
use solari_app::cli::BenchArgs;
use solari_scene::bvh::BvhQuality;
use solari_scene::gpu::{Gpu, ShaderChecks};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::gpu_timer::PassTimer;
use solari_scene::gpu_types::GpuView;
use solari_scene::shaders::Backend;
use solari_scene::view_pass::ViewPass;
use solari_scene::{Camera, Instance, Material, Mesh, Scene};
use std::collections::HashMap;

/// obvhs's procedural "demoscene" heightfield, welded into an indexed mesh, with the seed (0)
/// and camera (eye (0, 0, 1.35) looking along (0, 0.16, -1), yfov 17°) of tray_racing's
/// benchmark, so our rays/s compare with PERFORMANCE.md's figure on the same workload.
pub fn heightfield_scene(res: usize) -> Scene {
    let tris = obvhs::test_util::geometry::demoscene(res, 0);
    let mut index_of: HashMap<[u32; 3], u32> = HashMap::with_capacity(tris.len() / 2);
    let mut positions = Vec::new();
    let mut indices = Vec::with_capacity(tris.len() * 3);
    for t in &tris {
        for v in [t.v0, t.v1, t.v2] {
            let key = [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
            let i = *index_of.entry(key).or_insert_with(|| {
                positions.push(Vec3::from(v));
                (positions.len() - 1) as u32
            });
            indices.push(i);
        }
    }
    let mut mesh = Mesh {
        name: format!("demoscene{res}"),
        positions,
        indices,
        ..Default::default()
    };
    solari_scene::geometry::drop_degenerate_triangles(&mut mesh);
    mesh.normals = solari_scene::geometry::generate_normals(&mesh.positions, &mesh.indices);
    mesh.uvs = vec![glam::Vec2::ZERO; mesh.positions.len()];
    mesh.tangents = mesh
        .normals
        .iter()
        .map(|n| n.any_orthonormal_vector().extend(1.0))
        .collect();
    let eye = Vec3::new(0.0, 0.0, 1.35);
    Scene {
        meshes: vec![mesh],
        instances: vec![Instance {
            name: "terrain".into(),
            mesh: 0,
            material: 0,
            transform: glam::Mat4::IDENTITY,
        }],
        materials: vec![Material::default()],
        cameras: vec![Camera::look_at(
            "demoscene",
            eye,
            eye + Vec3::new(0.0, 0.16, -1.0),
            Vec3::Y,
            17f32.to_radians(),
        )],
        ..Default::default()
    }
}

struct Measurement {
    median_ms: f64,
    rays_per_frame: u64,
}

/// Times `frames` dispatches of the bench pass (after warm-up) and counts the rays traced.
/// Frames run before `measure` times any.
const WARM_UP_FRAMES: u32 = 10;
/// Wall time spent warming up at least, so the GPU's clocks are up when timing starts.
const WARM_UP_SECONDS: f64 = 0.5;

fn measure(
    gpu: &Gpu,
    pass: &ViewPass,
    scene: &GpuScene,
    view: &GpuView,
    frames: u32,
) -> Result<Measurement, String> {
    let target = pass.target(gpu, view).map_err(|e| e.to_string())?;
    let counts = pass.run(gpu, scene, &target).map_err(|e| e.to_string())?;
    let rays_per_frame = ViewPass::bench_ray_count(&counts);
    let timer = PassTimer::new(gpu).map_err(|e| e.to_string())?;
    // Warm up for at least WARM_UP_FRAMES frames and WARM_UP_SECONDS: after a long BVH build
    // the GPU sat idle and its clocks came down; 10 frames of 0.4 ms did not bring them
    // back, and the primary-ray median read 3x slow (metal_rough_spheres, very-slow build,
    // H100).
    let start = std::time::Instant::now();
    let mut warm = 0u32;
    while warm < WARM_UP_FRAMES || start.elapsed().as_secs_f64() < WARM_UP_SECONDS {
        timer
            .time(gpu, |e, ts| pass.encode(e, scene, &target, Some(ts)))
            .map_err(|e| e.to_string())?;
        warm += 1;
    }
    let mut times = Vec::new();
    for frame in 0..frames {
        let mut v = *view;
        v.frame = frame;
        gpu.queue
            .write_buffer(&target.uniform, 0, bytemuck::bytes_of(&v));
        let ms = timer
            .time(gpu, |e, ts| pass.encode(e, scene, &target, Some(ts)))
            .map_err(|e| e.to_string())?;
        times.push(ms);
    }
    times.sort_by(f64::total_cmp);
    Ok(Measurement {
        median_ms: times[times.len() / 2],
        rays_per_frame,
    })
}

pub fn run(args: &BenchArgs) -> Result<(), String> {
    let (w, h) = args.size;
    let (name, scene) = match args.heightfield {
        Some(n) => {
            eprintln!("generating the {n}x{n} heightfield...");
            (format!("heightfield{n}"), heightfield_scene(n as usize))
        }
        None => args.scene.load()?,
    };
    let gpu = Gpu::new().map_err(|e| e.to_string())?;
    if !gpu.features.contains(wgpu::Features::TIMESTAMP_QUERY) {
        return Err(format!(
            "adapter '{}' has no timestamp queries: GPU times cannot be measured",
            gpu.info.name
        ));
    }
    let backends: Vec<Backend> = match args.scene.tracer()? {
        solari_scene::gpu::TracerChoice::Auto => {
            let mut b = vec![Backend::Software];
            if gpu.has_ray_query() {
                b.push(Backend::RayQuery);
            }
            b
        }
        solari_scene::gpu::TracerChoice::Force(b) => vec![
            gpu.backend(solari_scene::gpu::TracerChoice::Force(b))
                .map_err(|e| e.to_string())?,
        ],
    };
    let camera = args.scene.pick_camera(&name, &scene)?;
    let tris = scene.stats().triangles;
    if !args.json {
        println!(
            "# {name}: {tris} triangles, {w}x{h}, adapter {}",
            gpu.info.name
        );
        println!(
            "| backend | preset | checks | traversal | BVH build s | build Mtri/s | primary ms | primary Grays/s | primary+hemi ms | rays/frame | Grays/s |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|");
    }
    for backend in backends {
        // Ray queries build their own structure: one row, whatever the presets.
        let presets: Vec<Option<BvhQuality>> = if backend == Backend::Software {
            args.presets()?.into_iter().map(Some).collect()
        } else {
            vec![None]
        };
        for preset in presets {
            let quality = preset.unwrap_or(BvhQuality::Medium);
            let preset = preset.map_or("-", BvhQuality::name);
            // With `--compare-checks`, a merged scene is also measured two-level.
            let merges = match (backend, args.scene.merge_instances, args.compare_checks) {
                (Backend::Software, true, true) => vec![true, false],
                (Backend::Software, merge, _) => vec![merge],
                (Backend::RayQuery, ..) => vec![false],
            };
            for merge in merges {
                let gs = GpuScene::new(
                    &gpu,
                    &scene,
                    backend,
                    &GpuSceneOptions {
                        bvh_quality: quality,
                        max_texture_size: 256,
                        merge_instances: merge,
                        emitter_bvh: args.scene.emitter_bvh,
                        ..Default::default()
                    },
                )
                .map_err(|e| e.to_string())?;
                // The build times the upload recorded (BVH build alone, no buffer writes).
                let (build_s, build_rate) = match gs.software_bvh() {
                    Some(bvh) => {
                        let s = (bvh.blas_build_time + bvh.tlas_build_time).as_secs_f64();
                        (s, tris as f64 / s / 1e6)
                    }
                    None => (f64::NAN, f64::NAN),
                };
                let best = TraceVariant::for_scene(&gs);
                let mut variants = vec![(ShaderChecks::BoundsOnly, best)];
                if args.compare_checks && backend == Backend::Software {
                    variants.push((ShaderChecks::All, best));
                    variants.push((ShaderChecks::None, best));
                    if best == TraceVariant::SingleUntransformed {
                        variants.push((ShaderChecks::BoundsOnly, TraceVariant::SingleInstance));
                    }
                    if best != TraceVariant::General {
                        variants.push((ShaderChecks::BoundsOnly, TraceVariant::General));
                    }
                }
                for (checks, variant) in variants {
                    let pass = ViewPass::ray_bench(&gpu, backend, checks, variant)
                        .map_err(|e| e.to_string())?;
                    // The general pipeline on a merged scene reads the merge flag at run time.
                    let traversal = match (variant, gs.is_merged()) {
                        (TraceVariant::General, true) => "two-level code, merged BVH",
                        _ => variant.name(),
                    };
                    let mut view = GpuView::new(&camera, w, h);
                    view.view_mode = 0;
                    let primary = measure(&gpu, &pass, &gs, &view, args.frames)?;
                    view.view_mode = 1;
                    let both = measure(&gpu, &pass, &gs, &view, args.frames)?;
                    let primary_rate =
                        primary.rays_per_frame as f64 / (primary.median_ms * 1e-3) / 1e9;
                    let rate = both.rays_per_frame as f64 / (both.median_ms * 1e-3) / 1e9;
                    let checks = checks.name();
                    if args.json {
                        println!(
                            "{}",
                            serde_json::json!({"scene": name, "triangles": tris, "width": w, "height": h,
                        "adapter": gpu.info.name, "backend": backend.name(), "preset": preset, "runtime_checks": checks, "traversal": traversal,
                        "bvh_build_s": build_s, "build_mtris_per_s": build_rate,
                        "primary_ms": primary.median_ms, "primary_rays": primary.rays_per_frame, "primary_grays_per_s": primary_rate,
                        "ao_ms": both.median_ms, "ao_rays": both.rays_per_frame, "ao_grays_per_s": rate, "frames": args.frames})
                        );
                    } else {
                        println!(
                            "| {} | {preset} | {checks} | {traversal} | {build_s:.3} | {build_rate:.2} | {:.3} | {primary_rate:.2} | {:.3} | {:.2} M | {rate:.2} |",
                            backend.name(),
                            primary.median_ms,
                            both.median_ms,
                            both.rays_per_frame as f64 / 1e6
                        );
                    }
                }
            }
        }
    }
    Ok(())
}
