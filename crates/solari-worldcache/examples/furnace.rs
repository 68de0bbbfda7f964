//! The world cache alone (with the G-buffer and light tiles it needs): in a white furnace,
//! a closed room whose every surface has albedo 0.8 and emits 0.2, irradiance is 1 (times π)
//! everywhere, 0.8 of it indirect, which the cache's cells must converge to. Also writes the
//! cache's debug view (each cell's irradiance) as a PNG.
//!
//! ```sh
//! cargo run --release -p solari-worldcache --example furnace [-- out.png]
//! ```

use solari_lights::{GpuLights, LightList, LightTileSettings, LightTiles, Selection};
use solari_reference::image_io::encode_png;
use solari_scene::gbuffer::GBuffer;
use solari_scene::gpu::{Gpu, TracerChoice};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::load_gltf;
use solari_scene::pass::FrameContext;
use solari_worldcache::{WorldCache, WorldCacheSettings};
use std::path::PathBuf;

const SIZE: u32 = 24;
const FRAMES: u32 = 400;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    run(&args)
}

/// The example, with its command-line arguments (the crate's tests run it with none).
pub fn run(args: &[String]) -> Result<(), Box<dyn std::error::Error>> {
    let out = args
        .first()
        .map(PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join("solari_worldcache_furnace.png"));
    let scene = load_gltf(solari_testdata::scene("furnace_uniform"))?;
    let camera = scene.camera(None).ok_or("the scene has no camera")?;
    let gpu = Gpu::new()?;
    let backend = gpu.backend(TracerChoice::Auto.with_env_override()?)?;
    let gpu_scene = GpuScene::new(&gpu, &scene, backend, &GpuSceneOptions::default())?;
    let list = LightList::build(&scene);
    let lights = GpuLights::new(&gpu, &list, Selection::Power)?;
    let tile_settings = LightTileSettings::default();
    let tiles = LightTiles::new(&gpu, tile_settings)?;
    let lights_group = tiles.reader_group(&gpu, &lights);
    let mut gbuffer = GBuffer::new(&gpu, backend, SIZE, SIZE)?;
    let variant = TraceVariant::for_scene(&gpu_scene);
    let settings = WorldCacheSettings::default();
    let mut cache = WorldCache::new(&gpu, backend, variant, settings, tile_settings)?;
    // The debug view writes each pixel's cell irradiance here.
    let view = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("furnace view"),
        size: (SIZE * SIZE * 16) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let target = cache.target_group(&gpu, &view);

    for frame in 0..FRAMES {
        // What every pass shares this frame (a still camera: last frame's view is the same).
        let context = FrameContext::new(frame, (SIZE, SIZE), &camera, Some(&camera));
        gbuffer.prepare(&gpu, &scene, &camera)?;
        tiles.prepare(&gpu, &context);
        cache.prepare(&gpu, &context, lights.light_count);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        gbuffer.encode(&mut encoder, &context, &gpu_scene)?;
        tiles.encode(&mut encoder, &context, &lights);
        // Upkeep: age and compact the cells, then trace and blend their new samples.
        cache.encode(&mut encoder, &context, &gpu_scene, &lights_group)?;
        // Pixels look their cells up (creating and renewing them) and show the irradiance.
        cache.encode_view(&mut encoder, &context, &gbuffer, &target)?;
        gpu.queue.submit([encoder.finish()]);
    }
    gpu.check_errors()?;

    let stats = cache.read_stats(&gpu)?;
    // Irradiance is stored divided by π; w counts the samples blended into a cell.
    let cells: Vec<f64> = cache
        .read_cells(&gpu)?
        .into_iter()
        .filter(|(_, life, c)| *life > 0 && c.irradiance[3] >= 20.0)
        .map(|(_, _, c)| c.irradiance[1] as f64)
        .collect();
    let mean = cells.iter().sum::<f64>() / cells.len().max(1) as f64;
    println!(
        "{FRAMES} frames at {SIZE}x{SIZE} on {backend:?}: {} live cells, {} overflows; \
         mean irradiance/π of {} settled cells {mean:.4} (analytic 1.0)",
        stats.active_cells,
        stats.overflows,
        cells.len()
    );
    let bytes = gpu.read_buffer(&view, (SIZE * SIZE * 16) as u64)?;
    let pixels: Vec<[f32; 3]> = bytemuck::cast_slice::<u8, [f32; 4]>(&bytes)
        .iter()
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    std::fs::write(&out, encode_png(SIZE, SIZE, &pixels, 0.0)?)?;
    println!("wrote the cache view to {}", out.display());
    if cells.is_empty() || (mean - 1.0).abs() > 0.03 || stats.overflows > 0 {
        return Err(format!("the cache did not settle at the furnace's irradiance: {mean}").into());
    }
    Ok(())
}
