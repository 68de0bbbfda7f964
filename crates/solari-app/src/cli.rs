//! Command-line arguments, and the scene/device setup every command shares.

use clap::{Args, Parser, Subcommand};
use solari_denoise::DlssAvailability;
use solari_scene::gpu::{Gpu, TracerChoice};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
use solari_scene::shaders::Backend;
use solari_scene::{Camera, Scene, default_scene, load_gltf};
use std::path::PathBuf;

/// Real-time ray-traced lighting components: headless tools.
#[derive(Parser)]
#[command(name = "solari", version, about)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
    /// Render headless: a debug view of primary rays, or the reference path tracer.
    Render(RenderArgs),
    /// Print the adapter, the chosen tracing backend, scene statistics and import warnings.
    Info(InfoArgs),
    /// Measure BVH build speed and GPU ray throughput (primary and hemisphere rays).
    BenchRays(BenchArgs),
    /// Compare a test image with a reference: RMSE, relative MSE and FLIP.
    Compare(CompareArgs),
    /// Time the real-time passes and sweep ReSTIR DI candidates and light-tile settings
    /// against error (CSV).
    BenchDi(BenchDiArgs),
    /// World-cache upkeep times, live cells and memory, and cache-only GI's error against a
    /// full-bounce reference, over cell sizes and update budgets (CSV rows).
    BenchCache(BenchCacheArgs),
    /// The fallback denoiser frame by frame on a static view: GPU ms, error of the raw, the
    /// accumulated and the denoised frame against a direct-only reference, and flicker (CSV).
    BenchDenoise(BenchDenoiseArgs),
}

/// A loaded scene on the device, ready to render.
pub struct Prepared {
    /// The scene's name for messages.
    pub name: String,
    /// The CPU scene.
    pub scene: Scene,
    /// The chosen camera.
    pub camera: Camera,
    /// The device.
    pub gpu: Gpu,
    /// The tracing backend in use.
    pub backend: Backend,
    /// The uploaded scene.
    pub gpu_scene: GpuScene,
    /// Whether DLSS-RR can run on this device, and if not why.
    pub dlss: DlssAvailability,
}

/// Options shared by every command that loads a scene.
#[derive(Args, Clone)]
pub struct SceneArgs {
    /// A .gltf/.glb file; the built-in Cornell box when absent.
    pub scene: Option<PathBuf>,
    /// Tracing backend: auto, ray-query or software (SOLARI_TRACER overrides).
    #[arg(long, default_value = "auto")]
    pub tracer: String,
    /// Camera by name or index (default: the file's first, else one framing the scene).
    #[arg(long)]
    pub camera: Option<String>,
    /// BVH build quality for the software backend: fastest, fast, medium, slow, very-slow.
    #[arg(long, default_value = "medium")]
    pub bvh_quality: String,
}

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// What to render: debug (a primary-ray view, see --view), reference (path traced) or
    /// realtime (G-buffer, light tiles and ReSTIR DI, run for --frames frames).
    #[arg(long, default_value = "debug")]
    pub mode: String,
    /// Real-time mode: frames to run; the last one is written.
    #[arg(long, default_value_t = 64)]
    pub frames: u32,
    /// Real-time mode: camera path, fixed or orbit (a ±20° swing around the scene's centre).
    #[arg(long, default_value = "fixed")]
    pub camera_path: String,
    /// Real-time mode: initial ReSTIR DI candidates per pixel.
    #[arg(long, default_value_t = 8)]
    pub candidates: u32,
    /// Real-time mode: light tiles as TILESxSAMPLES.
    #[arg(long, default_value = "128x1024")]
    pub tiles: String,
    /// Real-time mode: indirect light, off or cache (albedo × the world cache's indirect
    /// irradiance, added to ReSTIR DI).
    #[arg(long, default_value = "off")]
    pub gi: String,
    /// Real-time mode: world-cache cell size at the finest level, in scene units.
    #[arg(long, default_value_t = 0.25)]
    pub cache_cell_size: f32,
    /// Real-time mode: world-cache cells updated per frame before updates turn stochastic.
    #[arg(long, default_value_t = 40_000)]
    pub cache_budget: u32,
    /// Real-time mode: world-cache table slots (a power of two, 1024 to 2097152).
    #[arg(long, default_value_t = 1 << 18)]
    pub cache_capacity: u32,
    /// Real-time mode: denoiser, none, fallback (portable SVGF-style, every GPU) or dlss-rr
    /// (NVIDIA DLSS Ray Reconstruction; builds with `--features dlss` only). Default: the
    /// best available (DLSS-RR where it runs, else the fallback).
    #[arg(long)]
    pub denoiser: Option<String>,
    /// Real-time mode, fallback denoiser: à-trous iterations (1–8).
    #[arg(long, default_value_t = 5)]
    pub denoise_iterations: u32,
    /// Real-time mode, fallback denoiser: most frames the temporal average spans.
    #[arg(long, default_value_t = 32.0)]
    pub denoise_max_history: f32,
    /// Real-time mode, fallback denoiser: firefly limit in multiples of the recent mean
    /// (0: off). Clamped energy is carried into later frames, not removed.
    #[arg(long, default_value_t = 8.0)]
    pub firefly_clamp: f32,
    /// Real-time mode: write each frame's pass report (passes run, GPU ms) as JSON lines.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// What to show. Debug mode: albedo (default), normal, depth or instance. Real-time
    /// mode: lit (default) or world-cache (each pixel shows its world-cache cell's
    /// irradiance, tinted per cell).
    #[arg(long)]
    pub view: Option<String>,
    /// Reference mode: paths per pixel.
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    /// Reference mode: scattering events per path (1: direct light only). Unlimited by
    /// default: Russian roulette ends paths, with a reported safety cap of 256.
    #[arg(long)]
    pub max_bounces: Option<u32>,
    /// Reference mode: start every path at its pixel's centre (no antialiasing), to compare
    /// with renders that point-sample a G-buffer.
    #[arg(long)]
    pub pixel_centre: bool,
    /// Reference mode: light selection for next-event estimation, power or uniform.
    #[arg(long, default_value = "power")]
    pub selection: String,
    /// Reference mode: exposure in stops applied before the PNG's tone curve (ACES fit, sRGB).
    #[arg(long, default_value_t = 0.0)]
    pub exposure: f32,
    /// Reference mode: linear EXR output (default: the PNG path with .exr).
    #[arg(long)]
    pub exr: Option<PathBuf>,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "512x512")]
    pub size: String,
    /// Output PNG.
    #[arg(long, default_value = "solari.png")]
    pub out: PathBuf,
    /// Print a JSON summary instead of text.
    #[arg(long)]
    pub json: bool,
}

#[derive(Args)]
pub struct CompareArgs {
    /// The test image (EXR, or any format `image` reads; treated as linear).
    pub test: PathBuf,
    /// The reference image, same size.
    pub reference: PathBuf,
    /// Write the per-pixel FLIP error (HDR-aware variant) as a magma heat map PNG.
    #[arg(long)]
    pub heatmap: Option<PathBuf>,
    /// Also report metrics that ignore directly visible emitters, found by rendering this
    /// scene's emission at the images' size ("builtin" for the built-in Cornell box).
    #[arg(long)]
    pub mask_emitters: Option<PathBuf>,
    /// Camera of the --mask-emitters scene, by name or index.
    #[arg(long)]
    pub camera: Option<String>,
    /// JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

#[derive(Args)]
pub struct InfoArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Machine-readable output.
    #[arg(long)]
    pub json: bool,
}

#[derive(Args)]
pub struct BenchArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Use obvhs's procedural heightfield of N×N vertices instead of a scene (2048: 8.4 M
    /// triangles) with the seed and camera of tray_racing's benchmark (PERFORMANCE.md).
    #[arg(long)]
    pub heightfield: Option<usize>,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080")]
    pub size: String,
    /// Timed frames per measurement (after 10 warm-up frames).
    #[arg(long, default_value_t = 100)]
    pub frames: u32,
    /// Build presets to measure (comma separated).
    #[arg(long, default_value = "medium")]
    pub presets: String,
    /// Also measure the traversal under wgpu's full runtime checks and under none, next to the
    /// shipped bounds-checks-only build (software backend).
    #[arg(long)]
    pub compare_checks: bool,
    /// JSON lines instead of a table.
    #[arg(long)]
    pub json: bool,
}

#[derive(Args)]
pub struct BenchCacheArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080")]
    pub size: String,
    /// Frames per setting (static camera).
    #[arg(long, default_value_t = 300)]
    pub frames: u32,
    /// Leading frames per setting left out of timings and the error of the mean (the cache
    /// needs a few hundred frames to gather its bounces).
    #[arg(long, default_value_t = 200)]
    pub warmup: u32,
    /// Finest cell sizes to sweep (comma separated, scene units).
    #[arg(long, default_value = "0.25")]
    pub cell_sizes: String,
    /// Update budgets to sweep (comma separated, cells per frame).
    #[arg(long, default_value = "40000")]
    pub budgets: String,
    /// Table slots (a power of two).
    #[arg(long, default_value_t = 1 << 20)]
    pub capacity: u32,
    /// Full-bounce reference (EXR from `render --mode reference --pixel-centre`) for the
    /// error columns.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Also write the rows to this CSV file.
    #[arg(long)]
    pub csv: Option<PathBuf>,
}

#[derive(Args)]
pub struct BenchDiArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080")]
    pub size: String,
    /// Frames per setting (static camera); the last one is compared with --reference.
    #[arg(long, default_value_t = 64)]
    pub frames: u32,
    /// Leading frames per setting left out of the timings.
    #[arg(long, default_value_t = 8)]
    pub warmup: u32,
    /// Initial candidates to sweep (comma separated).
    #[arg(long, default_value = "8")]
    pub candidates: String,
    /// Light-tile settings to sweep as TILESxSAMPLES (comma separated).
    #[arg(long, default_value = "128x1024")]
    pub tiles: String,
    /// Direct-only reference (EXR from `render --mode reference --max-bounces 1
    /// --pixel-centre`) for the error columns.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Also write the CSV here.
    #[arg(long)]
    pub csv: Option<PathBuf>,
}

#[derive(Args)]
pub struct BenchDenoiseArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080")]
    pub size: String,
    /// Frames per setting (static camera); every frame is measured.
    #[arg(long, default_value_t = 64)]
    pub frames: u32,
    /// À-trous iteration counts to sweep (comma separated, 1–8).
    #[arg(long, default_value = "5")]
    pub iterations: String,
    /// Frames of the timing run per setting (after at least 8 untimed frames and 1 s),
    /// rendered back to back without read-backs.
    #[arg(long, default_value_t = 64)]
    pub timed_frames: u32,
    /// Most frames the denoiser's temporal average spans.
    #[arg(long, default_value_t = 32.0)]
    pub max_history: f32,
    /// Specular-lobe edge-stopping (0: off), to measure what it buys.
    #[arg(long, default_value_t = 8.0)]
    pub phi_lobe: f32,
    /// Direct-only reference (EXR from `render --mode reference --max-bounces 1
    /// --pixel-centre`) at --size.
    #[arg(long)]
    pub reference: PathBuf,
    /// Also write the CSV here.
    #[arg(long)]
    pub csv: Option<PathBuf>,
}

/// Parses `WxH`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("--size {s}: expected WIDTHxHEIGHT"))?;
    let w: u32 = w.parse().map_err(|_| format!("--size {s}: bad width"))?;
    let h: u32 = h.parse().map_err(|_| format!("--size {s}: bad height"))?;
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(format!("--size {s}: each side must be 1..=16384"));
    }
    Ok((w, h))
}

impl SceneArgs {
    /// Loads the scene (or the built-in one).
    pub fn load(&self) -> Result<(String, Scene), String> {
        match &self.scene {
            Some(p) => Ok((
                p.display().to_string(),
                load_gltf(p).map_err(|e| e.to_string())?,
            )),
            None => Ok((
                "<built-in cornell box>".into(),
                default_scene::cornell_box(),
            )),
        }
    }

    /// The tracer choice after the `SOLARI_TRACER` override.
    pub fn tracer(&self) -> Result<TracerChoice, String> {
        TracerChoice::parse(&self.tracer)
            .ok_or_else(|| {
                format!(
                    "--tracer {}: expected auto, ray-query or software",
                    self.tracer
                )
            })?
            .with_env_override()
    }

    /// Creates the device and resolves the backend.
    pub fn device(&self) -> Result<(Gpu, Backend), String> {
        self.device_with_dlss()
            .map(|(gpu, backend, _)| (gpu, backend))
    }

    /// Creates the device (through DLSS's Vulkan set-up in builds with the `dlss` feature)
    /// and resolves the backend.
    pub fn device_with_dlss(&self) -> Result<(Gpu, Backend, DlssAvailability), String> {
        let (gpu, dlss) = solari_denoise::create_gpu().map_err(|e| e.to_string())?;
        let backend = gpu.backend(self.tracer()?).map_err(|e| e.to_string())?;
        Ok((gpu, backend, dlss))
    }

    /// Loads the scene (logging its import warnings), picks its camera, opens the device and
    /// uploads the scene: what every rendering command starts with.
    pub fn prepare(&self) -> Result<Prepared, String> {
        let (name, scene) = self.load()?;
        for warning in scene.warnings.lines() {
            log::warn!("{name}: {warning}");
        }
        let camera = scene
            .camera(self.camera.as_deref())
            .ok_or_else(|| format!("no camera {:?} in {name}", self.camera))?;
        let (gpu, backend, dlss) = self.device_with_dlss()?;
        let options = GpuSceneOptions {
            bvh_quality: self.quality()?,
            ..Default::default()
        };
        let gpu_scene =
            GpuScene::new(&gpu, &scene, backend, &options).map_err(|e| e.to_string())?;
        Ok(Prepared {
            name,
            scene,
            camera,
            gpu,
            backend,
            gpu_scene,
            dlss,
        })
    }

    /// The BVH preset.
    pub fn quality(&self) -> Result<solari_scene::bvh::BvhQuality, String> {
        solari_scene::bvh::BvhQuality::parse(&self.bvh_quality).ok_or_else(|| {
            format!(
                "--bvh-quality {}: expected fastest, fast, medium, slow or very-slow",
                self.bvh_quality
            )
        })
    }
}
