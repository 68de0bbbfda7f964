//! The whole real-time pipeline with `solari-renderer`: render frames of a scene (a glTF
//! path as the first argument, or the built-in Cornell box) with world-cache GI and the
//! fallback denoiser, the non-finite detector on, and write the last frame as a PNG.
//!
//! ```sh
//! cargo run --release -p solari-renderer --example render_frames [-- scene.gltf [out.png]]
//! ```

use solari_denoise::DenoiserKind;
use solari_reference::image_io::encode_png;
use solari_renderer::{FiniteCheck, GiMode, PASS_NAMES, RealtimeRenderer, RealtimeSettings};
use solari_scene::gpu::{Gpu, TracerChoice};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
use solari_scene::{default_scene, load_gltf};
use std::path::PathBuf;
use std::time::Instant;

const SIZE: (u32, u32) = (160, 120);
const FRAMES: u32 = 16;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    run(&args)
}

/// The example, with its command-line arguments (the crate's tests run it with none).
pub fn run(args: &[String]) -> Result<(), Box<dyn std::error::Error>> {
    let mut args = args.iter();
    let scene = match args.next() {
        Some(path) => load_gltf(path)?,
        None => default_scene::cornell_box(),
    };
    let out = args
        .next()
        .map(PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join("solari_render_frames.png"));

    let gpu = Gpu::new()?;
    let backend = gpu.backend(TracerChoice::Auto)?;
    let gpu_scene = GpuScene::new(&gpu, &scene, backend, &GpuSceneOptions::default())?;
    let settings = RealtimeSettings {
        gi: GiMode::WorldCache,
        denoiser: Some(DenoiserKind::Fallback),
        finite_check: FiniteCheck::Fail,
        timestamps: true, // times are None where the adapter has no timestamp queries
        ..Default::default()
    };
    let (w, h) = SIZE;
    let mut renderer = RealtimeRenderer::new(&gpu, backend, &scene, &gpu_scene, w, h, settings)?;
    let camera = scene.camera(None).ok_or("the scene has no camera")?;
    let start = Instant::now();
    let mut report = None;
    for _ in 0..FRAMES {
        report = Some(renderer.render(&gpu, &scene, &gpu_scene, &camera)?);
    }
    let wall = start.elapsed().as_secs_f64() * 1e3 / FRAMES as f64;
    let report = report.expect("at least one frame");
    println!("{FRAMES} frames at {w}x{h} on {backend:?}: {wall:.1} ms a frame (wall)");
    for name in PASS_NAMES.iter().filter(|n| report.ran(n)) {
        match report.gpu_ms(name) {
            Some(ms) => println!("  {name}: {ms:.3} ms"),
            None => println!("  {name}: ran (no timestamps on this adapter)"),
        }
    }
    let pixels: Vec<[f32; 3]> = renderer
        .read_output(&gpu)?
        .iter()
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    let (ow, oh) = renderer.size();
    std::fs::write(&out, encode_png(ow, oh, &pixels, 0.0)?)?;
    println!("wrote {}", out.display());
    Ok(())
}
