//! Trace rays with `solari-scene` alone: load a scene (a glTF path as the first argument, or
//! the built-in Cornell box), upload it, trace one primary ray per pixel of a small image on
//! the GPU, and check every hit against the CPU tracer.
//!
//! ```sh
//! cargo run --release -p solari-scene --example trace_rays [-- scene.gltf]
//! ```

use glam::{Vec3, Vec4Swizzles};
use solari_scene::gpu::{Gpu, TracerChoice};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::gpu_types::{GpuRay, NO_HIT};
use solari_scene::trace_cpu::CpuTracer;
use solari_scene::trace_pass::TraceRaysPass;
use solari_scene::{default_scene, load_gltf};

const SIZE: u32 = 48;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    run(&args)
}

/// The example, with its command-line arguments (the crate's tests run it with none).
pub fn run(args: &[String]) -> Result<(), Box<dyn std::error::Error>> {
    let scene = match args.first() {
        Some(path) => load_gltf(path)?,
        None => default_scene::cornell_box(),
    };
    let gpu = Gpu::new()?;
    let backend = gpu.backend(TracerChoice::Auto)?;
    let gpu_scene = GpuScene::new(&gpu, &scene, backend, &GpuSceneOptions::default())?;
    let pass = TraceRaysPass::new(&gpu, backend, TraceVariant::for_scene(&gpu_scene))?;

    // One ray through each pixel centre of the first camera.
    let camera = scene.camera(None).ok_or("the scene has no camera")?;
    let eye = camera.transform.w_axis.xyz();
    let tan = (camera.yfov * 0.5).tan();
    let aspect = camera.aspect.unwrap_or(1.0);
    let rays: Vec<GpuRay> = (0..SIZE * SIZE)
        .map(|i| {
            let (x, y) = ((i % SIZE) as f32 + 0.5, (i / SIZE) as f32 + 0.5);
            let ndc = [2.0 * x / SIZE as f32 - 1.0, 1.0 - 2.0 * y / SIZE as f32];
            let local = Vec3::new(ndc[0] * tan * aspect, ndc[1] * tan, -1.0);
            let dir = camera.transform.transform_vector3(local).normalize();
            GpuRay {
                origin: eye.into(),
                t_min: 0.0,
                direction: dir.into(),
                t_max: f32::MAX,
                flags: 0,
                emitters_only: 0,
                _pad: [0; 2],
            }
        })
        .collect();
    let hits = pass.trace(&gpu, &gpu_scene, &rays)?;

    // The CPU tracer (an independent BVH) must find the same instance at the same distance.
    let cpu = CpuTracer::new(&scene);
    let mut agree = 0;
    for (ray, hit) in rays.iter().zip(&hits) {
        let (o, d) = (Vec3::from(ray.origin), Vec3::from(ray.direction));
        let reference = cpu.trace(o, d, ray.t_min, ray.t_max, ray.flags);
        let same = match reference {
            None => hit.instance == NO_HIT,
            Some(r) => r.instance == hit.instance && (r.t - hit.t).abs() <= 1e-4 * r.t.max(1.0),
        };
        agree += same as usize;
    }
    let covered = hits.iter().filter(|h| h.instance != NO_HIT).count();
    println!(
        "{backend:?} backend: {} rays, {covered} hits, {agree} agree with the CPU tracer",
        rays.len()
    );
    // Rays through shared edges may pick either triangle; anything more is a bug.
    if agree * 100 < rays.len() * 99 {
        return Err(format!("only {agree} of {} rays agree", rays.len()).into());
    }
    Ok(())
}
