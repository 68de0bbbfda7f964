//! Sample lights with `solari-lights`: list the lights of a scene with 400 emitters, draw one
//! sample on the CPU, fill light tiles on the GPU, and compare how often the tiles picked each
//! light with its selection probability.
//!
//! ```sh
//! cargo run --release -p solari-lights --example light_tiles
//! ```

use glam::Vec3;
use solari_lights::{
    GpuLights, LightList, LightSampleId, LightTileSettings, LightTiles, Selection,
};
use solari_scene::gpu::Gpu;
use solari_scene::load_gltf;
use solari_scene::pass::FrameContext;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    run(&args)
}

/// The example, with its command-line arguments (the crate's tests run it with none).
pub fn run(_args: &[String]) -> Result<(), Box<dyn std::error::Error>> {
    let scene = load_gltf(solari_testdata::scene("many_lights"))?;
    let list = LightList::build(&scene);
    println!("{} lights ({:?})", list.len(), list.report);
    let sample = list.sample(Selection::Power, Vec3::ZERO, [0.3, 0.6, 0.2, 0.9]);
    println!("one CPU sample at the origin: {sample:?}");

    let gpu = Gpu::new()?;
    let lights = GpuLights::new(&gpu, &list, Selection::Power)?;
    let settings = LightTileSettings {
        tiles: 64,
        samples_per_tile: 1024,
        ..Default::default()
    };
    let tiles = LightTiles::new(&gpu, settings)?;
    // The frame's shared context: index 0, seen from the scene's camera (tiles use the index).
    let camera = scene.camera(None).ok_or("the scene has no camera")?;
    let context = FrameContext::new(0, (64, 64), &camera, None);
    tiles.prepare(&gpu, &context);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    tiles.encode(&mut encoder, &context, &lights);
    gpu.queue.submit([encoder.finish()]);
    let n = settings.sample_count();
    let bytes = gpu.read_buffer(tiles.ids_buffer(), n * size_of::<LightSampleId>() as u64)?;
    let ids: &[LightSampleId] = bytemuck::cast_slice(&bytes);

    // Observed frequency against the selection pdf: total variation distance.
    let mut counts = vec![0u64; list.len()];
    for id in ids {
        counts[id.light as usize] += 1;
    }
    let tv: f64 = counts
        .iter()
        .enumerate()
        .map(|(l, &c)| {
            let p = list.selection_pdf(Selection::Power, l) as f64;
            (c as f64 / n as f64 - p).abs()
        })
        .sum::<f64>()
        * 0.5;
    println!("{n} tile samples; total variation from the power pdf: {tv:.4}");
    // With 65,536 samples over 400 lights the expected distance is about 0.03.
    if tv > 0.06 {
        return Err(format!("tile samples do not follow the selection pdf (distance {tv})").into());
    }
    Ok(())
}
