//! A denoiser behind the `Denoiser` trait, on its own: draw the Cornell box's G-buffer (lamp
//! removed), feed
//! the fallback denoiser a lighting buffer of known value plus fresh white noise each frame
//! (a static view), and measure how far its output is from the true value against the raw
//! input's error.
//!
//! ```sh
//! cargo run --release -p solari-denoise --example denoise_noise
//! ```

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_denoise::{Denoiser, DenoiserInputs, FallbackDenoiser, FallbackSettings, Lighting};
use solari_scene::default_scene;
use solari_scene::gbuffer::GBuffer;
use solari_scene::gpu::{Gpu, TracerChoice};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
use solari_scene::pass::FrameContext;

const SIZE: u32 = 96;
const FRAMES: u32 = 8;
/// The true lighting everywhere, and the half-width of the uniform noise added to it.
const VALUE: f32 = 0.5;
const NOISE: f32 = 0.4;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    run(&args)
}

/// The example, with its command-line arguments (the crate's tests run it with none).
pub fn run(_args: &[String]) -> Result<(), Box<dyn std::error::Error>> {
    let gpu = Gpu::new()?;
    let backend = gpu.backend(TracerChoice::Auto)?;
    // Without its lamp: the denoiser takes emission out of its input and adds the G-buffer's
    // back, so the test signal must hold emission where the G-buffer does (none here).
    let mut scene = default_scene::cornell_box();
    scene.instances.retain(|i| i.name != "light");
    let camera = scene.camera(None).ok_or("no camera")?;
    let gpu_scene = GpuScene::new(&gpu, &scene, backend, &GpuSceneOptions::default())?;
    let mut gbuffer = GBuffer::new(&gpu, backend, SIZE, SIZE)?;
    let mut denoiser = FallbackDenoiser::new(&gpu, SIZE, SIZE, FallbackSettings::default())?;
    let pixels = (SIZE * SIZE) as usize;
    let lighting = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("example/lighting"),
        size: pixels as u64 * 16,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut rng = Pcg32::seed_from_u64(7);
    let (mut raw_err, mut out_err) = (0.0, 0.0);
    for frame in 0..FRAMES {
        // The lighting pass of a real renderer would go here: the true value plus noise.
        let noisy: Vec<[f32; 4]> = (0..pixels)
            .map(|_| {
                let n = VALUE + rng.random_range(-NOISE..NOISE);
                [n, n, n, 1.0]
            })
            .collect();
        gpu.queue
            .write_buffer(&lighting, 0, bytemuck::cast_slice(&noisy));
        // What every pass shares this frame (a still camera: last frame's view is the same).
        let context = FrameContext::new(frame, (SIZE, SIZE), &camera, Some(&camera));
        gbuffer.prepare(&gpu, &scene, &camera)?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        gbuffer.encode(&mut encoder, &context, &gpu_scene)?;
        let inputs = DenoiserInputs {
            lighting: Lighting::Combined(&lighting),
            gbuffer: &gbuffer,
            hit_distance: None,
            shadow: None,
            reset: false,
        };
        let encoded = denoiser.encode(&gpu, &mut encoder, &context, &inputs)?;
        gpu.queue
            .submit(std::iter::once(encoder.finish()).chain(encoded.after));
        let bytes = gpu.read_buffer(denoiser.output(), pixels as u64 * 16)?;
        let out: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
        let rms = |img: &[[f32; 4]]| {
            let sum: f64 = img.iter().map(|p| ((p[0] - VALUE) as f64).powi(2)).sum();
            (sum / img.len() as f64).sqrt()
        };
        (raw_err, out_err) = (rms(&noisy), rms(out));
        println!("frame {frame}: RMS error raw {raw_err:.4}, denoised {out_err:.4}");
    }
    // A denoiser must never make a frame worse than its input (a NaN error fails too).
    if out_err.is_nan() || out_err >= raw_err {
        return Err(format!("denoised error {out_err} is not below the raw {raw_err}").into());
    }
    Ok(())
}
