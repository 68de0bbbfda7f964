//! Command-line arguments, their up-front checks, and the scene/device setup every command
//! shares.
//!
//! Every value is parsed into its type by clap (see [`crate::cli_values`]), and
//! [`Cli::check`] then checks what parsing cannot (inputs are readable files, outputs can be
//! written, knobs are in range together) before any scene is loaded or GPU work starts, so a
//! mistake costs no render time and leaves no partial output. The fuzz harness drives
//! `Cli::try_parse_from` and `Cli::check` with hostile arguments.

use crate::cli_values::{self as values, QualityArg, ViewArg};
use crate::output::{ImageOutputs, check_writable};
use clap::{Args, Parser, Subcommand, ValueEnum};
use solari_denoise::{AtrousKernel, DenoiserKind, DlssAvailability, FallbackSettings};
use solari_lights::{LightGridSettings, LightTileSettings, Selection};
use solari_renderer::{
    Antialias, CameraPath, DI_REUSE_LIGHT_THRESHOLD, FiniteCheck, FrameView, GBufferChoice, GiMode,
    PATH_GI_SHADE_APART_TRIANGLES, RealtimeSettings,
};
use solari_restir::{
    GiRate, GlossyHits, RestirDiSettings, RestirGiSettings, SpatialVisibility, SpecularGiSettings,
};
use solari_scene::brdf::BrdfModel;
use solari_scene::bvh::BvhQuality;
use solari_scene::gpu::{Gpu, TracerChoice};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
use solari_scene::shaders::Backend;
use solari_scene::{Camera, ImportOptions, Scene, default_scene, load_gltf_with};
use solari_worldcache::WorldCacheSettings;
use std::path::{Path, PathBuf};

/// Real-time ray-traced lighting components: headless tools.
#[derive(Parser, Debug)]
#[command(name = "solari", version, about)]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render headless: a debug view of primary rays, the reference path tracer, or the
    /// real-time renderer.
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
    /// Run the real-time pipeline for many frames with the non-finite detector on every pass,
    /// optionally toggling lights, and print a JSON summary (non-finite counts per pass,
    /// overflows, GPU memory, frame-time percentiles).
    Soak(SoakArgs),
    /// Open a window with the real-time renderer: fly camera (WASD, right-drag to look),
    /// drop a .gltf/.glb to load it, toggles for GI, denoiser, view and quality, per-pass
    /// GPU times and frame time on screen, F12 for a screenshot.
    View(ViewArgs),
}

impl Cli {
    /// Checks what argument parsing cannot, before any work: input files exist and are
    /// regular files, output paths can be written, settings are in range together.
    pub fn check(&self) -> Result<(), String> {
        match &self.command {
            Command::Render(a) => a.check().map(drop),
            Command::Info(a) => a.scene.check(),
            Command::BenchRays(a) => a.check(),
            Command::Compare(a) => a.check(),
            Command::BenchDi(a) => a.check(),
            Command::BenchCache(a) => a.check(),
            Command::BenchDenoise(a) => a.check(),
            Command::Soak(a) => a.check().map(drop),
            Command::View(a) => a.check().map(drop),
        }
    }
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
    /// Seconds spent loading (or generating) the scene on the CPU.
    pub load_seconds: f64,
    /// Seconds spent uploading it, BVH builds included.
    pub upload_seconds: f64,
}

/// Options shared by every command that loads a scene.
#[derive(Args, Clone, Debug)]
pub struct SceneArgs {
    /// A .gltf/.glb file; the built-in Cornell box when absent.
    pub scene: Option<PathBuf>,
    /// Instead of a file, a generated field of ROCKS rocks of about TRIANGLES triangles each,
    /// every rock its own mesh (`1024x10000`: 10.2 M triangles in 1,029 instances), for scale
    /// tests.
    #[arg(
        long,
        value_name = "ROCKSxTRIANGLES",
        value_parser = values::rock_field,
        conflicts_with = "scene"
    )]
    pub generated: Option<(u32, u32)>,
    /// Instead of a file, a generated square lit only by N coloured point lights among
    /// posts (about 4 m² per light, no sun, black sky), for many-light sampling
    /// (`--light-grid`).
    #[arg(long, value_name = "N", conflicts_with_all = ["scene", "generated"])]
    pub light_field: Option<u32>,
    /// Tracing backend: auto, ray-query or software (SOLARI_TRACER overrides).
    #[arg(long, default_value = "auto", value_parser = values::tracer)]
    pub tracer: TracerChoice,
    /// Camera by name or index (default: the file's first, else one framing the scene).
    #[arg(long)]
    pub camera: Option<String>,
    /// BVH build quality for the software backend: fastest, fast, medium, slow, very-slow.
    #[arg(long, default_value = "medium", value_parser = values::bvh_quality)]
    pub bvh_quality: BvhQuality,
    /// Software backend: trace every instance through one merged world-space BVH (no top
    /// level, no per-instance transform; on by default, within a size rule: see
    /// `GpuSceneOptions::merge_instances`). `off` keeps a BVH per mesh under a top level.
    #[arg(long, default_value = "on", num_args = 0..=1, default_missing_value = "on",
          value_parser = clap::builder::BoolishValueParser::new(), action = clap::ArgAction::Set)]
    pub merge_instances: bool,
    /// Software backend: a small BVH over the emissive instances for rays that look only
    /// for emitters (ReSTIR DI's BRDF-sampled candidates; on by default, within a size rule:
    /// see `GpuSceneOptions::emitter_bvh`). `off` traces those rays through the whole scene.
    #[arg(long, default_value = "on", num_args = 0..=1, default_missing_value = "on",
          value_parser = clap::builder::BoolishValueParser::new(), action = clap::ArgAction::Set)]
    pub emitter_bvh: bool,
    /// BRDF for every pass and the reference: layered (energy-conserving: a white furnace
    /// reads 1 at every roughness) or gltf-spec (the glTF specification's Appendix B, for
    /// comparisons with other glTF renderers).
    #[arg(long, default_value = "layered", value_parser = values::brdf)]
    pub brdf: BrdfModel,
    /// Radius in metres of every point and spot light: 0 renders them as delta lights with
    /// hard shadows (glTF's definition), a radius as glowing spheres with soft shadows.
    #[arg(long, default_value = "0", value_name = "METRES", value_parser = values::metres)]
    pub light_radius: f32,
    /// An equirectangular HDR environment map (.hdr or .exr; +Y up, the image's centre
    /// towards -Z) lighting the scene from every direction; replaces the scene's uniform
    /// environment. Larger than 4096 texels wide it is reduced; over 16384 x 8192 refused.
    #[arg(long, value_name = "FILE.hdr|FILE.exr")]
    pub environment: Option<PathBuf>,
    /// Factor on the environment map's radiance. With no map it scales the scene's uniform
    /// environment, or sets a uniform one of this radiance where the scene has none.
    #[arg(long, value_name = "FACTOR", value_parser = values::intensity)]
    pub environment_intensity: Option<f32>,
    /// The folder the scene's buffer and image URIs may reach (default: the scene's own
    /// folder; URIs never leave it).
    #[arg(long)]
    pub asset_root: Option<PathBuf>,
}

/// Checks that `path` names a regular file that can be opened.
pub fn check_input(path: &Path, what: &str) -> Result<(), String> {
    let meta = std::fs::metadata(path).map_err(|e| format!("{what} {}: {e}", path.display()))?;
    if meta.is_dir() {
        return Err(format!(
            "{what} {}: is a folder, not a file",
            path.display()
        ));
    }
    if !meta.is_file() {
        return Err(format!(
            "{what} {}: is not a regular file (device, pipe or socket)",
            path.display()
        ));
    }
    std::fs::File::open(path)
        .map(drop)
        .map_err(|e| format!("{what} {}: {e}", path.display()))
}

impl SceneArgs {
    /// Up-front checks: the scene file, the asset root, the tracer override.
    pub fn check(&self) -> Result<(), String> {
        if let Some(p) = &self.scene {
            check_input(p, "SCENE")?;
        }
        if let Some(p) = &self.environment {
            check_input(p, "--environment")?;
        }
        if let Some(root) = &self.asset_root
            && !root.is_dir()
        {
            return Err(format!("--asset-root {}: not a folder", root.display()));
        }
        self.tracer().map(drop)
    }

    /// Loads the scene (or generates it, or the built-in one), with `--environment`.
    pub fn load(&self) -> Result<(String, Scene), String> {
        let (name, mut scene) = self.load_scene()?;
        if let Some(path) = &self.environment {
            let map = solari_scene::EnvironmentMap::load(path, &Default::default())
                .map_err(|e| e.to_string())?;
            log::info!(
                "{}: {} x {} environment map, mean radiance {:.3}",
                path.display(),
                map.width(),
                map.height(),
                map.mean_radiance()
            );
            scene.environment_map = Some(std::sync::Arc::new(map));
            scene.environment_radiance = glam::Vec3::ONE;
        }
        if let Some(k) = self.environment_intensity {
            if scene.environment_map.is_some() || scene.environment_radiance == glam::Vec3::ZERO {
                scene.environment_radiance = glam::Vec3::splat(k);
            } else {
                scene.environment_radiance *= k;
            }
        }
        Ok((name, scene))
    }

    fn load_scene(&self) -> Result<(String, Scene), String> {
        if let Some(lights) = self.light_field {
            let scene = solari_scene::generated_scene::point_light_field(lights)
                .map_err(|e| format!("--light-field: {e}"))?;
            return Ok((format!("<generated field of {lights} point lights>"), scene));
        }
        if let Some((rocks, triangles)) = self.generated {
            let scene = solari_scene::generated_scene::rock_field(rocks, triangles)
                .map_err(|e| format!("--generated: {e}"))?;
            return Ok((format!("<generated rock field {rocks}x{triangles}>"), scene));
        }
        match &self.scene {
            Some(p) => {
                let options = ImportOptions {
                    asset_root: self.asset_root.clone(),
                    point_light_radius: self.light_radius,
                    ..Default::default()
                };
                Ok((
                    p.display().to_string(),
                    load_gltf_with(p, &options).map_err(|e| e.to_string())?,
                ))
            }
            None => Ok((
                "<built-in cornell box>".into(),
                default_scene::cornell_box(),
            )),
        }
    }

    /// The tracer choice after the `SOLARI_TRACER` override.
    pub fn tracer(&self) -> Result<TracerChoice, String> {
        self.tracer.with_env_override()
    }

    /// The scene's camera (`--camera`), checked.
    pub fn pick_camera(&self, name: &str, scene: &Scene) -> Result<Camera, String> {
        let camera = scene.camera(self.camera.as_deref()).ok_or_else(|| {
            let names: Vec<&str> = scene.cameras.iter().map(|c| c.name.as_str()).collect();
            format!(
                "no camera {:?} in {name} (it has {})",
                self.camera.as_deref().unwrap_or(""),
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            )
        })?;
        camera.validate()?;
        Ok(camera)
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

    /// The upload settings these arguments choose (`--bvh-quality`, `--brdf`,
    /// `--merge-instances`, `--emitter-bvh`).
    pub fn gpu_scene_options(&self) -> GpuSceneOptions {
        GpuSceneOptions {
            bvh_quality: self.bvh_quality,
            brdf: self.brdf,
            merge_instances: self.merge_instances,
            emitter_bvh: self.emitter_bvh,
            ..Default::default()
        }
    }

    /// Loads the scene (logging its import warnings), picks its camera, opens the device and
    /// uploads the scene: what every rendering command starts with.
    pub fn prepare(&self) -> Result<Prepared, String> {
        let start = std::time::Instant::now();
        let (name, scene) = self.load()?;
        let load_seconds = start.elapsed().as_secs_f64();
        for warning in scene.warnings.lines() {
            log::warn!("{name}: {warning}");
        }
        let camera = self.pick_camera(&name, &scene)?;
        let (gpu, backend, dlss) = self.device_with_dlss()?;
        let options = self.gpu_scene_options();
        let start = std::time::Instant::now();
        let gpu_scene =
            GpuScene::new(&gpu, &scene, backend, &options).map_err(|e| e.to_string())?;
        let upload_seconds = start.elapsed().as_secs_f64();
        let stats = scene.stats();
        log::info!(
            "{name}: {stats:?}; loaded in {load_seconds:.2} s, uploaded ({} {} BVH, {}) in \
             {upload_seconds:.2} s, {:.1} MiB on the GPU",
            self.bvh_quality.name(),
            if gpu_scene.is_merged() {
                "merged"
            } else {
                "two-level"
            },
            backend.name(),
            gpu_scene.memory_bytes() as f64 / (1 << 20) as f64
        );
        Ok(Prepared {
            name,
            scene,
            camera,
            gpu,
            backend,
            gpu_scene,
            dlss,
            load_seconds,
            upload_seconds,
        })
    }
}

/// The knobs of the real-time renderer, shared by `render --mode realtime` and `soak`.
#[derive(Args, Clone, Debug)]
pub struct RealtimeArgs {
    /// Quality: a tier (low, medium, high or ultra) sets the internal scale and
    /// antialiasing, GI mode, specular GI and ReSTIR DI reuse together, over those flags (the
    /// tiers and their measured basis: `solari_renderer::quality`); auto times the scene on
    /// this adapter at start-up and takes the setting with the least measured error that fits
    /// `--budget-ms` (`solari_renderer::auto_quality`). Absent: the flags as given, whose
    /// defaults are the ultra tier.
    #[arg(long, value_parser = values::quality)]
    pub quality: Option<QualityArg>,
    /// GPU milliseconds per frame that `--quality auto` must fit (default 16.7: 60 frames a
    /// second).
    #[arg(long, default_value_t = 16.7, value_parser = values::finite)]
    pub budget_ms: f32,
    /// Time-against-error table for `--quality auto` (CSV with scene, setting, gpu_ms and
    /// rel_mse columns, and optionally rel_mse_moving (a moving camera's error: a setting
    /// counts by the worse of the two) and reference_noise / reference_noise_moving (what
    /// the references' own noise adds to each, taken out before settings are compared), as
    /// `benches/results/quality_table.py` writes from a sweep of your own scenes); default:
    /// the table shipped in `solari-renderer`. A scene is
    /// looked up by its file's stem; others get each setting's worst error over the table's
    /// scenes.
    #[arg(long, value_name = "FILE.csv")]
    pub quality_table: Option<PathBuf>,
    /// Camera path, fixed or orbit (a ±20° swing around the scene's centre). Reference and
    /// debug modes render the path's camera at real-time mode's last frame (`--frames`): its
    /// reference.
    #[arg(long, default_value = "fixed", value_parser = values::camera_path)]
    pub camera_path: CameraPath,
    /// G-buffer producer: raster (vertex and fragment shaders), traced (one primary ray per
    /// pixel, a compute pass) or auto (both timed at start-up, the faster kept). The same
    /// texels, found two ways.
    #[arg(long, default_value = "auto", value_parser = values::gbuffer)]
    pub gbuffer: GBufferChoice,
    /// Initial ReSTIR DI candidates per pixel.
    #[arg(long, default_value_t = 8)]
    pub candidates: u32,
    /// BRDF-sampled ReSTIR DI candidates per pixel (0 to 4): rays along the BRDF that find
    /// emitters and the environment, so glossy surfaces reflect lights in DI.
    #[arg(long, default_value_t = 1)]
    pub brdf_candidates: u32,
    /// ReSTIR DI reuse: auto (all, except on scenes of at most 64 light elements under the
    /// fallback denoiser, where reuse buys nothing measurable), all (temporal and spatial),
    /// temporal, spatial or none (plain RIS from the light tiles: each frame's samples stand
    /// alone).
    #[arg(long, value_enum, default_value_t = DiReuse::Auto)]
    pub di_reuse: DiReuse,
    /// ReSTIR DI draws initial candidates from a world-space light grid: SHARE of them
    /// (0 to 0.95; 0.75 when the flag has no value) from the lights listed in the pixel's
    /// cell, the rest from the light tiles, so no light is lost. For scenes with thousands
    /// of lights (benches/RESULTS.md, "Light grid"). Off when absent.
    #[arg(long, value_name = "SHARE", num_args = 0..=1, default_missing_value = "0.75",
          value_parser = values::finite)]
    pub light_grid: Option<f32>,
    #[command(flatten)]
    pub grid: LightGridArgs,
    /// Light tiles as TILESxSAMPLES.
    #[arg(long, default_value = "128x1024", value_parser = values::tiles)]
    pub tiles: LightTileSettings,
    /// Light selection, power or uniform: for tile samples in real time, for next-event
    /// estimation in the reference tracer.
    #[arg(long, default_value = "power", value_parser = values::selection)]
    pub selection: Selection,
    /// Indirect light: off; cache (albedo × the world cache's indirect irradiance at each
    /// pixel); path (one traced diffuse bounce per pixel lit by the world cache, no reuse);
    /// restir (the same bounce with ReSTIR GI's temporal and spatial reuse). Added to ReSTIR
    /// DI. The default, path, is the measured choice (benches/RESULTS.md, "GI: the whole
    /// matrix"): as accurate as reuse at less cost.
    #[arg(long, default_value = "path", value_parser = values::gi)]
    pub gi: GiMode,
    /// With `--gi restir`: which reuse steps run, all (temporal and spatial), temporal (last
    /// frame's reservoir only; the spatial pass then only shades: a third less GI time, frames
    /// more alike) or spatial (one neighbour's reservoir only). `RestirGiSettings::spatial`
    /// gives the measurements of temporal reuse alone.
    #[arg(long, value_enum, default_value_t = GiReuse::All)]
    pub gi_reuse: GiReuse,
    /// ReSTIR GI's first spatial search radius, in pixels.
    #[arg(long, default_value_t = 30.0, value_parser = values::finite)]
    pub gi_spatial_radius: f32,
    /// ReSTIR GI: the most confidence (frames' worth of samples) a history carries into a
    /// frame. `RestirGiSettings::confidence_cap`.
    #[arg(long, default_value_t = 8.0, value_parser = values::finite)]
    pub gi_confidence_cap: f32,
    /// ReSTIR GI refuses reuse where a reconnection Jacobian exceeds this.
    #[arg(long, default_value_t = 2.0, value_parser = values::finite)]
    pub gi_jacobian_bound: f32,
    /// Which visibility rays ReSTIR GI's spatial reuse traces: chosen (one ray, for the
    /// sample the merge chooses; unbiased), both (the neighbour's sample from the pixel and
    /// the pixel's from the neighbour; unbiased, one more ray, and both samples shaded:
    /// less noise, most of it colour, see `--gi-shade-both`)
    /// or neighbour (one ray, the neighbour's sample; biased, darkens indirect light near
    /// occluders). `RestirGiSettings::spatial_visibility` gives the measurements.
    #[arg(long, default_value = "chosen", value_parser = values::gi_spatial_visibility)]
    pub gi_spatial_visibility: SpatialVisibility,
    /// With `--gi-spatial-visibility both` or `neighbour`: shade both samples of the spatial
    /// merge by their resampling weights, not the chosen one alone (on by default; the same
    /// mean, less noise, most of it colour). `RestirGiSettings::shade_both_samples`.
    #[arg(long, default_value = "on", num_args = 0..=1, default_missing_value = "on",
          value_parser = clap::builder::BoolishValueParser::new(), action = clap::ArgAction::Set)]
    pub gi_shade_both: bool,
    /// ReSTIR GI: the share (0–1) of a reusing pixel's light taken from its own reservoir
    /// before spatial reuse, the rest from the spatial merge's chosen sample (both unbiased;
    /// 0 is the merge alone; a merge with both samples shaded ignores it).
    /// `RestirGiSettings::own_sample_share`.
    #[arg(long, default_value_t = 0.5, value_parser = values::finite)]
    pub gi_own_share: f32,
    /// ReSTIR GI: next frame's history is the spatial merge's reservoir (on, the default), or
    /// the pixel's own from before spatial reuse (off: one frame less noisy, frames more
    /// alike; measured worse once denoised on `interior`). `RestirGiSettings::spatial_history`.
    #[arg(long, default_value = "on", num_args = 0..=1, default_missing_value = "on",
          value_parser = clap::builder::BoolishValueParser::new(), action = clap::ArgAction::Set)]
    pub gi_spatial_history: bool,
    /// GI candidate rays per pixel (1–16): more samples per pixel for plain path GI (their
    /// average is shaded), better initial samples for ReSTIR GI (resampled to one by the
    /// target function).
    #[arg(long, default_value_t = 1)]
    pub gi_samples: u32,
    /// How a GI ray's hit on a glossy metal (`--gi-glossy-roughness`) is lit: cache (the
    /// default: the cache's irradiance under a uniform-light model, as at every hit, which
    /// loses a sun's reflection off polished metal onto the surfaces around it), lights (a
    /// light sample through the metal's BRDF, plus the cache's light from everything but the
    /// lights: one shadow ray) or path (a light sample and one BRDF-sampled bounce into the
    /// cache: two rays, noisier). The default by measurement: the other two cost 6–136% of
    /// GI's first pass and left sun_boxes' denoised frame 12–30% worse (benches/RESULTS.md).
    /// `solari_restir::GlossyHits`.
    #[arg(long, default_value = "cache", value_parser = values::gi_glossy_hits)]
    pub gi_glossy_hits: GlossyHits,
    /// The glossy metals of `--gi-glossy-hits`: metallic at least 0.5 and roughness below
    /// this (above 0, at most 1). `RestirGiSettings::glossy_hit_roughness`.
    #[arg(long, default_value_t = 0.5, value_parser = values::finite)]
    pub gi_glossy_roughness: f32,
    /// Permute ReSTIR GI's temporal source pixel within 4×4 blocks (for DLSS-RR; costs
    /// accuracy, see `RestirGiSettings::permutation_sampling`).
    #[arg(long)]
    pub gi_permutation: bool,
    /// GI traced from half the pixels each frame (a checkerboard that flips every frame, at
    /// twice the weight): GI's first pass 20-40% faster, noisier while histories are young.
    /// With `--gi path` or `--gi restir`; see `GiRate::Half`.
    #[arg(long)]
    pub gi_half_rate: bool,
    /// GI traced from a quarter of the pixels each frame (each pixel one frame in four, at
    /// four times the weight) instead of half: with `--gi restir`, its two passes on
    /// `interior` 0.99-1.00 ms instead of 1.30 at half rate (H200, 1080p; 0.97 with
    /// `--gi-trace-fresh off`, whose moving camera's error is 21% higher at a quarter), the
    /// still camera's error the same; with `--gi path` it costs more error than it saves.
    /// See `GiRate::Quarter`.
    #[arg(long, conflicts_with = "gi_half_rate")]
    pub gi_quarter_rate: bool,
    /// With `--gi-half-rate` and `--gi restir`: spatial reuse too only at half the pixels
    /// (those that did not trace this frame, from neighbours that did not either), so the
    /// spatial pass traces half its rays (on by default: 18-34% off that pass on the H200 at
    /// 1080p, the error after 136 frames equal or lower; `--gi-half-rate-spatial off` reuses
    /// at every pixel). See `RestirGiSettings::half_rate_spatial`.
    #[arg(long, default_value = "on", num_args = 0..=1, default_missing_value = "on",
          value_parser = clap::builder::BoolishValueParser::new(), action = clap::ArgAction::Set)]
    pub gi_half_rate_spatial: bool,
    /// ReSTIR GI: a GI ray that hits a world-cache cell with no samples yet draws no sample
    /// instead of a dark one (on by default; `--gi-ignore-cold-cells off` counts it dark, which
    /// keeps the first frames dark while the cache fills). See
    /// `RestirGiSettings::ignore_cold_cells`.
    #[arg(long, default_value = "on", num_args = 0..=1, default_missing_value = "on",
          value_parser = clap::builder::BoolishValueParser::new(), action = clap::ArgAction::Set)]
    pub gi_ignore_cold_cells: bool,
    /// ReSTIR GI: temporal reuse caps the history's confidence lower where the world cache
    /// saw the reused sample's light changing when it was traced, as it does while the cache
    /// fills (on by default; `--gi-adaptive-cap off` keeps the fixed `--gi-confidence-cap`). See
    /// `RestirGiSettings::adaptive_cap`.
    #[arg(long, default_value = "on", num_args = 0..=1, default_missing_value = "on",
          value_parser = clap::builder::BoolishValueParser::new(), action = clap::ArgAction::Set)]
    pub gi_adaptive_cap: bool,
    /// ReSTIR GI: frames a still view (no moved instance or changed light) keeps the adaptive cap before it
    /// stops (it biases a settled view bright; `RestirGiSettings::adaptive_cap_settle_frames`).
    /// `never` keeps it always (the behaviour before).
    #[arg(long, default_value_t = solari_restir::ADAPTIVE_CAP_SETTLE_FRAMES, value_parser = values::settle_frames)]
    pub gi_adaptive_cap_settle: u32,
    /// At `--gi-half-rate` or `--gi-quarter-rate` with ReSTIR GI: a pixel with no history (a
    /// first frame, surface the view uncovered) traces this frame whatever its phase (on by
    /// default: along a moving camera interior's error 21% lower at a quarter, for 0.02-0.03
    /// ms a frame on the H200 at 1080p; `off` makes it wait for its phase). See
    /// `RestirGiSettings::trace_fresh_pixels`.
    #[arg(long, default_value = "on", num_args = 0..=1, default_missing_value = "on",
          value_parser = clap::builder::BoolishValueParser::new(), action = clap::ArgAction::Set)]
    pub gi_trace_fresh: bool,
    /// Plain path GI (`--gi path`) shades in a second dispatch after the one that traces:
    /// auto (in scenes of at least 65,536 triangles, where it measured faster: interior's GI
    /// pass −7.9% on an H100), on or off. See `RestirGiSettings::shade_apart`.
    #[arg(long, value_enum, default_value_t = ShadeApart::Auto)]
    pub gi_shade_apart: ShadeApart,
    /// Specular GI: the indirect light of the specular lobe (reflections of everything but
    /// the lights, which are DI's), traced for glossy and mirror pixels; rough ones reuse
    /// the ReSTIR GI reservoir with `--gi path|restir`. Needs no `--gi` mode. On by default
    /// (measured: 1.5-3x lower error on glossy scenes for at most 0.53 ms at 1080p on the
    /// H200); `--specular-gi off` turns it off (`--specular-gi` alone means on).
    #[arg(long, default_value = "on", num_args = 0..=1, default_missing_value = "on",
          value_parser = clap::builder::BoolishValueParser::new(), action = clap::ArgAction::Set)]
    pub specular_gi: bool,
    /// Specular GI: path segments after the primary surface (1–8).
    #[arg(long, default_value_t = 3)]
    pub specular_bounces: u32,
    /// Specular GI: pixels rougher than this reuse the GI reservoir instead of tracing.
    #[arg(long, default_value_t = 0.4, value_parser = values::finite)]
    pub specular_rough_threshold: f32,
    /// Primary surface replacement: mirror-metal pixels give the denoiser the surface they
    /// reflect (depth through the mirror, normals, albedo, motion) instead of the flat
    /// mirror. With specular GI and a denoiser or `--internal-scale` below 1; on by default,
    /// `--psr off` turns it off.
    #[arg(long, default_value = "on", num_args = 0..=1, default_missing_value = "on",
          value_parser = clap::builder::BoolishValueParser::new(), action = clap::ArgAction::Set)]
    pub psr: bool,
    /// World-cache cell size at the finest level, in scene units.
    #[arg(long, default_value_t = WorldCacheSettings::default().cell_size,
          value_parser = values::finite, allow_hyphen_values = true)]
    pub cache_cell_size: f32,
    /// World-cache cells updated per frame before updates turn stochastic.
    #[arg(long, default_value_t = WorldCacheSettings::default().update_budget)]
    pub cache_budget: u32,
    /// World-cache distance over which cells double in size, in scene units (`inf`: one
    /// level everywhere).
    #[arg(long, default_value_t = WorldCacheSettings::default().lod_distance,
          value_parser = values::positive_or_inf)]
    pub cache_lod_distance: f32,
    /// World cache: a lookup at the end of a ray shorter than its cell uses the finest level
    /// (less light through corners; on by default, `--cache-leak-rule off` to compare).
    #[arg(long, default_value = "on", num_args = 0..=1, default_missing_value = "on",
          value_parser = clap::builder::BoolishValueParser::new(), action = clap::ArgAction::Set)]
    pub cache_leak_rule: bool,
    /// World cache: blend neighbouring levels of detail (a lookup near a level's far edge
    /// lands one level coarser with probability fract³) instead of switching at a hard
    /// distance (on by default).
    #[arg(long, default_value = "on", num_args = 0..=1, default_missing_value = "on",
          value_parser = clap::builder::BoolishValueParser::new(), action = clap::ArgAction::Set)]
    pub cache_soft_lod: bool,
    /// World-cache table slots (a power of two, 1024 to 2097152).
    #[arg(long, default_value_t = WorldCacheSettings::default().capacity)]
    pub cache_capacity: u32,
    /// Frames after a light change (more than a tenth of the lights' power switched, added,
    /// removed or rescaled) in which the world cache averages at most 4 samples and runs
    /// `--cache-warm-up-rounds` update rounds a frame, and ReSTIR GI counts a history as one
    /// sample, so indirect light follows the switch (0: never).
    #[arg(long, default_value_t = WorldCacheSettings::default().light_change_frames)]
    pub cache_light_change_frames: u32,
    /// How fast a young world-cache cell's averaging lengthens: a cell of n samples averages
    /// at most 1 + 29 (n / 30)^E of them, so new cells leave their early, darker samples
    /// within a few frames (0: a plain running mean; at most 16).
    #[arg(long, value_name = "E", default_value_t = WorldCacheSettings::default().warm_up_exponent)]
    pub cache_warm_up: f32,
    /// World-cache update rounds per frame in its first frames (`--cache-warm-up-frames`):
    /// light crosses a bounce between cells per round, so a cold cache fills sooner (1: one
    /// round, as every later frame; at most 16).
    #[arg(long, value_name = "N", default_value_t = WorldCacheSettings::default().warm_up_rounds)]
    pub cache_warm_up_rounds: u32,
    /// Frames after the world cache is made or emptied that run `--cache-warm-up-rounds`
    /// (0: none; at most 100000).
    #[arg(long, value_name = "N", default_value_t = WorldCacheSettings::default().warm_up_frames)]
    pub cache_warm_up_frames: u32,
    /// Denoiser, none, fallback (portable SVGF-style, every GPU) or dlss-rr (NVIDIA DLSS
    /// Ray Reconstruction; builds with `--features dlss` only). Default: the best available
    /// (DLSS-RR where it runs, else the fallback).
    #[arg(long, value_parser = values::denoiser)]
    pub denoiser: Option<DenoiserKind>,
    /// Fallback denoiser: à-trous iterations (1–8).
    #[arg(long, default_value_t = 5)]
    pub denoise_iterations: u32,
    /// Fallback denoiser: the taps of each à-trous iteration, diamond (13 taps of the 5×5
    /// B3 kernel, within two steps by Manhattan distance) or full (all 25, as SVGF).
    #[arg(long, default_value = "diamond", value_parser = values::atrous_kernel)]
    pub denoise_kernel: AtrousKernel,
    /// Fallback denoiser: most frames the temporal average spans.
    #[arg(long, default_value_t = 32.0, value_parser = values::finite, allow_hyphen_values = true)]
    pub denoise_max_history: f32,
    /// Fallback denoiser: firefly limit in multiples of the recent mean (0: off). Clamped
    /// energy is carried into later frames, not removed.
    #[arg(long, default_value_t = 8.0, value_parser = values::finite, allow_hyphen_values = true)]
    pub firefly_clamp: f32,
    /// Count non-finite and negative values in every pass's output, every frame, and stop at
    /// the first frame that has any, naming the first pass that produced one.
    #[arg(long)]
    pub check_finite: bool,
    /// Frames queued on the GPU before the frame loop waits for the oldest (1–3): with 2 the
    /// CPU records a frame while the GPU runs the last, and reports arrive a frame late.
    #[arg(long, default_value_t = 2)]
    pub frames_in_flight: u32,
    /// Time the passes on every Nth frame (1: every frame; a run of fewer than 16 N frames
    /// times every (frames / 16)th, so that 16 are timed). Timing costs a frame 0.065-0.08
    /// ms of wall time on an H200 (the queries' resolve and read-back), 10% of a 0.7 ms
    /// frame, so by default one frame in 8 is timed: the per-pass means and the GPU frame
    /// time come from those, the wall time from every frame, and `--report` lines of the
    /// others carry no times.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..))]
    pub time_every: u32,
    /// Render the lighting at this fraction of the output's width and height (0.25–1;
    /// 0.5 and 0.67 are the usual ones) and bring it to the output size with the temporal
    /// upscaler (jittered camera). Fallback denoiser or none only. Best for a still
    /// camera: a moving one read 1.2-4.1x native's best error on the bundled scenes.
    #[arg(long, default_value_t = 1.0, value_parser = values::finite, allow_hyphen_values = true)]
    pub internal_scale: f32,
    /// With `--internal-scale` below 1: trace each output pixel's depth on frames whose
    /// camera moved, so the upscaler knows which of a pixel's samples lie on its own surface
    /// and which are emitters (on by default: along the orbit 10x lower relMSE on
    /// many_lights, 3.6x on the Cornell box, 1.5x on interior at 0.67, for about 0.2 ms at
    /// 1080p on an H200, moving frames only; `--upscale-guide off` turns it off).
    #[arg(long, default_value = "on", num_args = 0..=1, default_missing_value = "on",
          value_parser = clap::builder::BoolishValueParser::new(), action = clap::ArgAction::Set)]
    pub upscale_guide: bool,
    /// Antialiasing at full scale while the camera stands still (the camera jittered, the
    /// temporal upscaler accumulating the samples per pixel; a moving camera's frames pass
    /// unjittered): auto (on under the fallback denoiser, off with DLSS-RR, which antialiases
    /// by itself, and with `--denoiser none`), on (the flag alone) or off. The figures:
    /// `solari_renderer::Antialias`.
    #[arg(long, default_value = "auto", num_args = 0..=1, default_missing_value = "on",
          value_parser = values::antialias)]
    pub antialias: Antialias,
}

impl RealtimeArgs {
    /// The renderer's settings, every knob checked (the error names the bad one).
    pub fn settings(&self, view: FrameView) -> Result<RealtimeSettings, String> {
        let mut settings = RealtimeSettings {
            gbuffer: self.gbuffer,
            tiles: self.tiles,
            di: RestirDiSettings {
                initial_candidates: self.candidates,
                brdf_candidates: self.brdf_candidates,
                temporal: matches!(
                    self.di_reuse,
                    DiReuse::Auto | DiReuse::All | DiReuse::Temporal
                ),
                spatial: matches!(
                    self.di_reuse,
                    DiReuse::Auto | DiReuse::All | DiReuse::Spatial
                ),
                reuse_light_threshold: match self.di_reuse {
                    DiReuse::Auto => DI_REUSE_LIGHT_THRESHOLD,
                    _ => 0,
                },
                ..Default::default()
            },
            selection: self.selection,
            light_grid: self.light_grid.map(|share| self.grid.settings(share)),
            gi: self.gi,
            path_gi_shade_apart_triangles: match self.gi_shade_apart {
                ShadeApart::Auto => PATH_GI_SHADE_APART_TRIANGLES,
                ShadeApart::On => 0,
                ShadeApart::Off => u64::MAX,
            },
            restir_gi: RestirGiSettings {
                temporal: self.gi_reuse != GiReuse::Spatial,
                spatial: self.gi_reuse != GiReuse::Temporal,
                spatial_radius: self.gi_spatial_radius,
                jacobian_bound: self.gi_jacobian_bound,
                confidence_cap: self.gi_confidence_cap,
                permutation_sampling: self.gi_permutation,
                initial_samples: self.gi_samples,
                spatial_visibility: self.gi_spatial_visibility,
                shade_both_samples: self.gi_shade_both,
                own_sample_share: self.gi_own_share,
                spatial_history: self.gi_spatial_history,
                rate: match (self.gi_half_rate, self.gi_quarter_rate) {
                    (_, true) => GiRate::Quarter,
                    (true, false) => GiRate::Half,
                    (false, false) => GiRate::Full,
                },
                half_rate_spatial: self.gi_half_rate_spatial,
                ignore_cold_cells: self.gi_ignore_cold_cells,
                adaptive_cap: self.gi_adaptive_cap,
                adaptive_cap_settle_frames: self.gi_adaptive_cap_settle,
                trace_fresh_pixels: self.gi_trace_fresh,
                glossy_hits: self.gi_glossy_hits,
                glossy_hit_roughness: self.gi_glossy_roughness,
                ..Default::default()
            },
            specular_gi: self.specular_gi,
            psr: self.psr,
            specular: SpecularGiSettings {
                max_bounces: self.specular_bounces,
                rough_threshold: self.specular_rough_threshold,
                ..Default::default()
            },
            cache: WorldCacheSettings {
                cell_size: self.cache_cell_size,
                update_budget: self.cache_budget,
                lod_distance: self.cache_lod_distance,
                leak_rule: self.cache_leak_rule,
                soft_lod: self.cache_soft_lod,
                capacity: self.cache_capacity,
                light_change_frames: self.cache_light_change_frames,
                warm_up_exponent: self.cache_warm_up,
                warm_up_rounds: self.cache_warm_up_rounds,
                warm_up_frames: self.cache_warm_up_frames,
                ..Default::default()
            },
            view,
            timestamps: true,
            timestamp_interval: self.time_every,
            denoiser: self.denoiser,
            denoise: FallbackSettings {
                atrous_iterations: self.denoise_iterations,
                atrous_kernel: self.denoise_kernel,
                max_history: self.denoise_max_history,
                firefly_clamp: self.firefly_clamp,
                ..Default::default()
            },
            finite_check: if self.check_finite {
                FiniteCheck::Fail
            } else {
                FiniteCheck::Off
            },
            frames_in_flight: self.frames_in_flight,
            internal_scale: self.internal_scale,
            upscale_guide: self.upscale_guide,
            antialias: self.antialias,
            ..Default::default()
        };
        if let Some(QualityArg::Tier(tier)) = self.quality {
            settings = tier.apply(&settings);
        }
        if !(self.budget_ms > 0.0 && self.budget_ms <= 10_000.0) {
            return Err(format!(
                "--budget-ms must be above 0 and at most 10000, not {}",
                self.budget_ms
            ));
        }
        if self.quality_table.is_some() && self.quality != Some(QualityArg::Auto) {
            return Err("--quality-table is for --quality auto".into());
        }
        if let Some(p) = &self.quality_table {
            check_input(p, "--quality-table")?;
            // Parsed now too, so a bad table stops the command before any work.
            crate::quality_choice::error_table(self)?;
        }
        if settings.restir_gi.rate.reduced()
            && matches!(settings.gi, GiMode::Off | GiMode::WorldCache)
        {
            // These modes trace no GI ray (ReSTIR GI refuses it in `validate`, below). Said
            // once: a command may build its settings more than once.
            static WARNED: std::sync::atomic::AtomicBool =
                std::sync::atomic::AtomicBool::new(false);
            if !WARNED.swap(true, std::sync::atomic::Ordering::Relaxed) {
                log::warn!(
                    "--gi-half-rate and --gi-quarter-rate apply to path and ReSTIR GI only: ignored with GI mode {:?}",
                    settings.gi
                );
            }
        }
        settings.validate()?;
        Ok(settings)
    }
}

/// The light grid's layout (`--light-grid-cells`, `--light-grid-capacity`).
#[derive(Args, Clone, Copy, Debug)]
pub struct LightGridArgs {
    /// Most light-grid cells (cubes covering the scene's bounds).
    #[arg(long, default_value_t = LightGridSettings::default().max_cells)]
    pub light_grid_cells: u32,
    /// Most lights listed per light-grid cell; fuller cells keep the strongest (reported).
    #[arg(long, default_value_t = LightGridSettings::default().capacity)]
    pub light_grid_capacity: u32,
}

impl LightGridArgs {
    /// The grid's settings with `share` of the candidates drawn from it.
    pub fn settings(&self, share: f32) -> LightGridSettings {
        LightGridSettings {
            max_cells: self.light_grid_cells,
            capacity: self.light_grid_capacity,
            grid_share: share,
            ..Default::default()
        }
    }
}

/// Which of ReSTIR DI's reuse steps run (`--di-reuse`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DiReuse {
    /// Temporal and spatial reuse, skipped on scenes of few lights under the fallback
    /// denoiser (`solari_renderer::DI_REUSE_LIGHT_THRESHOLD`, with the figures).
    Auto,
    /// Temporal and spatial reuse, always.
    All,
    /// Last frame's reservoir only.
    Temporal,
    /// One neighbour's reservoir only.
    Spatial,
    /// No reuse: resampled importance sampling from the tiles alone.
    None,
}

/// Which of ReSTIR GI's reuse steps run (`--gi-reuse`; `--gi path` is GI with neither).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum GiReuse {
    /// Temporal and spatial reuse (the default).
    All,
    /// Last frame's reservoir only; the spatial pass only shades.
    Temporal,
    /// One neighbour's reservoir only.
    Spatial,
}

/// Whether plain path GI shades in a dispatch of its own (`--gi-shade-apart`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ShadeApart {
    /// In scenes of at least `solari_renderer::PATH_GI_SHADE_APART_TRIANGLES` triangles
    /// (with the figures).
    Auto,
    /// Always.
    On,
    /// Never.
    Off,
}

/// What `render` produces.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Mode {
    /// A primary-ray debug view (see --view).
    Debug,
    /// The reference path tracer.
    Reference,
    /// The real-time renderer (G-buffer, light tiles, ReSTIR DI, optional cache GI and
    /// denoiser) for --frames frames.
    Realtime,
}

/// `solari render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The scene.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// What to render.
    #[arg(long, value_enum, default_value_t = Mode::Debug)]
    pub mode: Mode,
    /// Real-time mode: frames to run; the last one is written. Reference and debug modes
    /// render that last frame's camera (it differs from the first only with `--camera-path
    /// orbit`).
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: u32,
    /// Real-time mode: write the mean of the last N frames instead of the last frame alone
    /// (for error measurements; those frames wait for the GPU, so wall time counts the
    /// frames before them).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub mean_of: u32,
    /// Real-time mode: the renderer's knobs.
    #[command(flatten)]
    pub realtime: RealtimeArgs,
    /// Real-time mode: write each frame's pass report (passes run, GPU ms on the frames
    /// `--time-every` times, null on the others, non-finite counts) as JSON lines.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// What to show. Debug mode: albedo (default), normal, depth or instance. Real-time
    /// mode: lit (default), indirect (the GI passes' light alone: no emission, direct light
    /// or environment seen directly; compare with a `--min-bounces 2` reference), world-cache
    /// (each pixel shows its world-cache cell's irradiance, tinted per cell) or a G-buffer
    /// channel, written without tone curve:
    /// gbuffer-base-color, gbuffer-normal, gbuffer-geometric-normal, gbuffer-roughness,
    /// gbuffer-metallic, gbuffer-emission, gbuffer-depth or gbuffer-motion.
    #[arg(long, value_parser = values::view)]
    pub view: Option<ViewArg>,
    /// Reference mode: paths per pixel.
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=1 << 20))]
    pub spp: u32,
    /// Reference mode: scattering events per path (1: direct light only). Unlimited by
    /// default: Russian roulette ends paths, with a reported safety cap of 256.
    #[arg(long)]
    pub max_bounces: Option<u32>,
    /// Reference mode: leave out light that reaches the eye after fewer scattering events
    /// than this (1: no emitters or environment seen directly; 2: indirect light alone, what
    /// real-time mode's `--view indirect` shows). The paths do not change with it, so with
    /// the same `--spp` the full image is the sum of `--max-bounces 1` and `--min-bounces 2`.
    #[arg(long, default_value_t = 0)]
    pub min_bounces: u32,
    /// Reference mode: start every path at its pixel's centre (no antialiasing), to compare
    /// with renders that point-sample a G-buffer.
    #[arg(long)]
    pub pixel_centre: bool,
    /// Reference mode: also write each pixel's variance (the noise of its mean: the samples'
    /// variance over their count) to this EXR, for `solari compare --reference-variance`,
    /// which takes that noise out of the errors measured against the reference.
    #[arg(long)]
    pub variance_out: Option<PathBuf>,
    /// Exposure in stops applied before the PNG's tone curve (ACES fit, sRGB); ±64.
    #[arg(long, default_value_t = 0.0, value_parser = values::exposure, allow_hyphen_values = true)]
    pub exposure: f32,
    /// Also write the linear image here (the same as another `--out FILE.exr`).
    #[arg(long)]
    pub exr: Option<PathBuf>,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "512x512", value_parser = values::size)]
    pub size: (u32, u32),
    /// Output image; the format follows the extension: .png (tone-mapped) or .exr (linear).
    /// Repeat for several. Default: solari.png in debug mode, solari.png and solari.exr
    /// otherwise.
    #[arg(long)]
    pub out: Vec<PathBuf>,
    /// Print a JSON summary instead of text.
    #[arg(long)]
    pub json: bool,
}

/// What [`RenderArgs::check`] settled.
#[derive(Debug)]
pub struct RenderPlan {
    /// The image files to write.
    pub outputs: ImageOutputs,
    /// The debug view (debug mode).
    pub debug_view: solari_scene::view_pass::DebugView,
    /// The real-time settings (real-time mode).
    pub realtime: Option<RealtimeSettings>,
}

impl RenderArgs {
    /// Up-front checks; the plan holds what they settled.
    pub fn check(&self) -> Result<RenderPlan, String> {
        self.scene.check()?;
        let mut paths = if self.out.is_empty() {
            match self.mode {
                Mode::Debug => vec![PathBuf::from("solari.png")],
                _ => vec![PathBuf::from("solari.png"), PathBuf::from("solari.exr")],
            }
        } else {
            self.out.clone()
        };
        paths.extend(self.exr.iter().cloned());
        if let Some(e) = &self.exr
            && crate::output::ImageFormat::for_path(e)? != crate::output::ImageFormat::Exr
        {
            return Err(format!("--exr {}: must end in .exr", e.display()));
        }
        if let Some(v) = &self.variance_out {
            if self.mode != Mode::Reference {
                return Err("--variance-out: only reference mode knows its noise".into());
            }
            if crate::output::ImageFormat::for_path(v)? != crate::output::ImageFormat::Exr {
                return Err(format!("--variance-out {}: must end in .exr", v.display()));
            }
            check_writable(v, "--variance-out")?;
        }
        if self.min_bounces > 0 && self.mode != Mode::Reference {
            return Err("--min-bounces: only reference mode counts a path's bounces".into());
        }
        if let Some(max) = self.max_bounces
            && self.min_bounces > max
        {
            return Err(format!(
                "--min-bounces {} above --max-bounces {max}: the image would be black",
                self.min_bounces
            ));
        }
        let outputs = ImageOutputs::check(&paths)?;
        let mut debug_view = solari_scene::view_pass::DebugView::Albedo;
        let mut frame_view = FrameView::Lit;
        match (self.mode, self.view) {
            (_, None) => {}
            (Mode::Debug, Some(ViewArg::Debug(v))) => debug_view = v,
            (Mode::Realtime, Some(ViewArg::Frame(v))) => frame_view = v,
            (mode, Some(_)) => {
                return Err(format!(
                    "--view: {} mode shows {}",
                    format!("{mode:?}").to_lowercase(),
                    match mode {
                        Mode::Debug => "albedo, normal, depth or instance",
                        Mode::Realtime => "lit, indirect, world-cache or gbuffer-CHANNEL",
                        Mode::Reference => "only the path-traced image (no --view)",
                    }
                ));
            }
        }
        let realtime = match self.mode {
            Mode::Realtime => {
                if let Some(r) = &self.report {
                    check_writable(r, "--report")?;
                }
                let mut settings = self.realtime.settings(frame_view)?;
                settings.timestamp_interval =
                    timed_interval(self.realtime.time_every, self.frames as u64);
                Some(settings)
            }
            _ => None,
        };
        Ok(RenderPlan {
            outputs,
            debug_view,
            realtime,
        })
    }
}

/// Frames timed in a run of `frames`: every `time_every`th, or more often where that would
/// time fewer than 16 (a short run still reports its passes' times).
fn timed_interval(time_every: u32, frames: u64) -> u32 {
    let most = (frames / 16).clamp(1, u32::MAX as u64) as u32;
    time_every.min(most)
}

/// `solari soak`.
#[derive(Args, Debug)]
pub struct SoakArgs {
    /// The scene.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Frames to run.
    #[arg(long, default_value_t = 10_000, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: u64,
    /// Switch lights every K frames: half of them (every other light) off, then all back
    /// on; a scene with one light turns it off and on.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub toggle_lights: Option<u32>,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080", value_parser = values::size)]
    pub size: (u32, u32),
    /// The renderer's knobs (`--check-finite` is always on in a soak).
    #[command(flatten)]
    pub realtime: RealtimeArgs,
    /// Also write the JSON summary to this file.
    #[arg(long)]
    pub summary: Option<PathBuf>,
    /// Print a progress line to stderr every N frames (0: none).
    #[arg(long, default_value_t = 1000)]
    pub progress_every: u64,
}

impl SoakArgs {
    /// Up-front checks; returns the renderer settings.
    pub fn check(&self) -> Result<RealtimeSettings, String> {
        self.scene.check()?;
        if let Some(p) = &self.summary {
            check_writable(p, "--summary")?;
        }
        if self.realtime.quality == Some(QualityArg::Auto) {
            return Err(
                "--quality auto is for `render --mode realtime` and `view`: a soak runs \
                 fixed settings (give a tier or the flags)"
                    .into(),
            );
        }
        let mut settings = self.realtime.settings(FrameView::Lit)?;
        settings.timestamp_interval = timed_interval(self.realtime.time_every, self.frames);
        // A soak counts every finding to the end instead of stopping at the first.
        settings.finite_check = FiniteCheck::Count;
        Ok(settings)
    }
}

/// `solari view`.
#[derive(Args, Debug)]
pub struct ViewArgs {
    /// The scene (drop another .gltf/.glb on the window to switch).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Window size in physical pixels as WIDTHxHEIGHT (the window may be resized).
    #[arg(long, default_value = "1280x720", value_parser = values::size)]
    pub size: (u32, u32),
    /// The renderer's starting knobs (most can be changed in the window).
    #[command(flatten)]
    pub realtime: RealtimeArgs,
    /// Exposure in EV (stops) for the window and PNG screenshots.
    #[arg(long, default_value_t = 0.0, value_parser = values::finite, allow_hyphen_values = true)]
    pub exposure: f32,
    /// Render this many frames, write `--screenshot` (if given) and close: for scripts and
    /// tests. Without it the window stays open until closed (Esc).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: Option<u32>,
    /// Screenshot file (F12, and after `--frames`): .png is the window as shown, overlay
    /// included unless hidden; .exr is the renderer's linear output. Default for F12:
    /// solari-view-N.png in the working folder.
    #[arg(long, value_name = "FILE.png|FILE.exr")]
    pub screenshot: Option<PathBuf>,
    /// Start with the overlay hidden (F1 toggles it).
    #[arg(long)]
    pub no_ui: bool,
    /// Present without waiting for the display's refresh (frame times then show the
    /// renderer's own pace).
    #[arg(long)]
    pub no_vsync: bool,
}

impl ViewArgs {
    /// Up-front checks; returns the renderer's starting settings (timestamps on, for the
    /// overlay's pass times).
    pub fn check(&self) -> Result<RealtimeSettings, String> {
        self.scene.check()?;
        if let Some(p) = &self.screenshot {
            crate::output::ImageFormat::for_path(p)?;
            check_writable(p, "--screenshot")?;
        }
        let mut settings = self.realtime.settings(FrameView::Lit)?;
        settings.timestamps = true;
        Ok(settings)
    }
}

/// `solari compare`.
#[derive(Args, Debug)]
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
    /// The reference's per-pixel variance (`render --mode reference --variance-out`): also
    /// report how much of RMSE and relMSE the reference's own noise accounts for, and the
    /// errors without it (`rmse_excess`, `rel_mse_excess`). Against a 1024-path reference of
    /// a mostly indirectly lit scene that noise can be as large as a converged real-time
    /// frame's own error.
    #[arg(long)]
    pub reference_variance: Option<PathBuf>,
    /// JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

impl CompareArgs {
    /// Up-front checks.
    pub fn check(&self) -> Result<(), String> {
        check_input(&self.test, "TEST")?;
        check_input(&self.reference, "REFERENCE")?;
        if let Some(v) = &self.reference_variance {
            check_input(v, "--reference-variance")?;
        }
        if let Some(h) = &self.heatmap {
            if crate::output::ImageFormat::for_path(h)? != crate::output::ImageFormat::Png {
                return Err(format!("--heatmap {}: must end in .png", h.display()));
            }
            check_writable(h, "--heatmap")?;
        }
        if let Some(m) = &self.mask_emitters
            && m.as_os_str() != "builtin"
        {
            check_input(m, "--mask-emitters")?;
        }
        Ok(())
    }
}

/// `solari info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// The scene.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Machine-readable output.
    #[arg(long)]
    pub json: bool,
}

/// `solari bench-rays`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// The scene.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Use obvhs's procedural heightfield of N×N vertices instead of a scene (2048: 8.4 M
    /// triangles) with the seed and camera of tray_racing's benchmark (PERFORMANCE.md).
    #[arg(long, value_parser = clap::value_parser!(u32).range(2..=8192))]
    pub heightfield: Option<u32>,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080", value_parser = values::size)]
    pub size: (u32, u32),
    /// Timed frames per measurement (after 10 warm-up frames).
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u32).range(1..))]
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

impl BenchArgs {
    /// The presets to measure.
    pub fn presets(&self) -> Result<Vec<BvhQuality>, String> {
        values::list(&self.presets, "--presets", values::bvh_quality)
    }

    /// Up-front checks.
    pub fn check(&self) -> Result<(), String> {
        self.scene.check()?;
        self.presets().map(drop)
    }
}

/// Sweep options every `bench-*` command shares.
fn check_sweep(
    scene: &SceneArgs,
    frames: u32,
    warmup: u32,
    reference: Option<&PathBuf>,
    csv: Option<&PathBuf>,
) -> Result<(), String> {
    scene.check()?;
    if frames <= warmup {
        return Err(format!(
            "--frames ({frames}) must exceed --warmup ({warmup})"
        ));
    }
    if let Some(r) = reference {
        check_input(r, "--reference")?;
    }
    if let Some(c) = csv {
        check_writable(c, "--csv")?;
    }
    Ok(())
}

/// `solari bench-cache`.
#[derive(Args, Debug)]
pub struct BenchCacheArgs {
    /// The scene.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080", value_parser = values::size)]
    pub size: (u32, u32),
    /// Frames per setting (static camera).
    #[arg(long, default_value_t = 300, value_parser = clap::value_parser!(u32).range(1..=1 << 20))]
    pub frames: u32,
    /// Leading frames per setting left out of timings and the error of the mean (the cache
    /// needs a few hundred frames to gather its bounces).
    #[arg(long, default_value_t = 200)]
    pub warmup: u32,
    /// Finest cell sizes to sweep (comma separated, scene units; default the library's).
    #[arg(long, default_value = "0.15")]
    pub cell_sizes: String,
    /// Update budgets to sweep (comma separated, cells per frame; default the library's).
    #[arg(long, default_value = "200000")]
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

impl BenchCacheArgs {
    /// The swept (cell size, budget) pairs' lists.
    pub fn sweep(&self) -> Result<(Vec<f32>, Vec<u32>), String> {
        let cells = values::list(&self.cell_sizes, "--cell-sizes", values::finite)?;
        let budgets = values::list(&self.budgets, "--budgets", values::number::<u32>)?;
        for c in &cells {
            for b in &budgets {
                WorldCacheSettings {
                    cell_size: *c,
                    update_budget: *b,
                    capacity: self.capacity,
                    ..Default::default()
                }
                .validate()
                .map_err(|e| e.to_string())?;
            }
        }
        Ok((cells, budgets))
    }

    /// Up-front checks.
    pub fn check(&self) -> Result<(), String> {
        check_sweep(
            &self.scene,
            self.frames,
            self.warmup,
            self.reference.as_ref(),
            self.csv.as_ref(),
        )?;
        self.sweep().map(drop)
    }
}

/// `solari bench-di`.
#[derive(Args, Debug)]
pub struct BenchDiArgs {
    /// The scene.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080", value_parser = values::size)]
    pub size: (u32, u32),
    /// Frames per setting (static camera); the last one is compared with --reference.
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=1 << 20))]
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
    /// Light-grid shares to sweep (comma separated; `off` for light tiles alone), as
    /// realtime's `--light-grid`.
    #[arg(long, default_value = "off")]
    pub light_grid: String,
    #[command(flatten)]
    pub grid: LightGridArgs,
    /// Direct-only reference (EXR from `render --mode reference --max-bounces 1
    /// --pixel-centre`) for the error columns.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Frames at the end of each setting whose errors are averaged (as mean squared error)
    /// into the error columns; 1 scores the last frame alone.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub error_frames: u32,
    /// Also write the CSV here.
    #[arg(long)]
    pub csv: Option<PathBuf>,
}

impl BenchDiArgs {
    /// The swept light grids (`None`: tiles alone), each checked.
    pub fn grids(&self) -> Result<Vec<Option<LightGridSettings>>, String> {
        values::list(&self.light_grid, "--light-grid", |s| {
            if s.trim() == "off" {
                return Ok(None);
            }
            let grid = self.grid.settings(values::finite(s)?);
            grid.check()?;
            Ok(Some(grid))
        })
    }

    /// The swept candidate counts and tile settings.
    pub fn sweep(&self) -> Result<(Vec<u32>, Vec<LightTileSettings>), String> {
        let candidates = values::list(&self.candidates, "--candidates", values::number::<u32>)?;
        for c in &candidates {
            RestirDiSettings {
                initial_candidates: *c,
                ..Default::default()
            }
            .validate()
            .map_err(|e| e.to_string())?;
        }
        let tiles = values::list(&self.tiles, "--tiles", values::tiles)?;
        Ok((candidates, tiles))
    }

    /// Up-front checks.
    pub fn check(&self) -> Result<(), String> {
        check_sweep(
            &self.scene,
            self.frames,
            self.warmup,
            self.reference.as_ref(),
            self.csv.as_ref(),
        )?;
        self.grids()?;
        self.sweep().map(drop)
    }
}

/// `solari bench-denoise`.
#[derive(Args, Debug)]
pub struct BenchDenoiseArgs {
    /// The scene.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080", value_parser = values::size)]
    pub size: (u32, u32),
    /// Frames per setting (static camera); every frame is measured.
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=1 << 20))]
    pub frames: u32,
    /// À-trous iteration counts to sweep (comma separated, 1–8).
    #[arg(long, default_value = "5")]
    pub iterations: String,
    /// Frames of the timing run per setting (after at least 8 untimed frames and 1 s),
    /// rendered back to back without read-backs.
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(0..=1 << 20))]
    pub timed_frames: u32,
    /// Most frames the denoiser's temporal average spans.
    #[arg(long, default_value_t = 32.0, value_parser = values::finite, allow_hyphen_values = true)]
    pub max_history: f32,
    /// Specular-lobe edge-stopping (0: off), to measure what it buys.
    #[arg(long, default_value_t = 8.0, value_parser = values::finite, allow_hyphen_values = true)]
    pub phi_lobe: f32,
    /// Direct-only reference (EXR from `render --mode reference --max-bounces 1
    /// --pixel-centre`) at --size.
    #[arg(long)]
    pub reference: PathBuf,
    /// Also write the CSV here.
    #[arg(long)]
    pub csv: Option<PathBuf>,
}

impl BenchDenoiseArgs {
    /// The fallback settings of each swept iteration count.
    pub fn sweep(&self) -> Result<Vec<FallbackSettings>, String> {
        values::list(&self.iterations, "--iterations", values::number::<u32>)?
            .into_iter()
            .map(|atrous_iterations| {
                let s = FallbackSettings {
                    atrous_iterations,
                    max_history: self.max_history,
                    phi_lobe: self.phi_lobe,
                    ..Default::default()
                };
                s.validate().map_err(|e| e.to_string()).map(|()| s)
            })
            .collect()
    }

    /// Up-front checks.
    pub fn check(&self) -> Result<(), String> {
        check_sweep(
            &self.scene,
            self.frames,
            0,
            Some(&self.reference),
            self.csv.as_ref(),
        )?;
        self.sweep().map(drop)
    }
}

#[cfg(test)]
mod tests {
    use super::timed_interval;

    #[test]
    fn short_runs_time_at_least_sixteen_frames() {
        assert_eq!(timed_interval(8, 300), 8);
        assert_eq!(timed_interval(8, 128), 8);
        assert_eq!(timed_interval(8, 127), 7);
        assert_eq!(timed_interval(8, 40), 2);
        assert_eq!(timed_interval(8, 4), 1);
        assert_eq!(timed_interval(8, 0), 1);
        assert_eq!(timed_interval(1, 100_000), 1);
        assert_eq!(timed_interval(32, u64::MAX), 32);
    }
}
