//! ReSTIR GI: per-pixel diffuse indirect light from one traced sample per pixel, reused across
//! frames and neighbouring pixels, with the world cache ending every path.
//!
//! ## The algorithm (after Solari 0.17–0.19)
//!
//! 1. **Initial sample**: a cosine-distributed direction about the shading normal is traced.
//!    At its hit, the radiance toward the pixel is the hit's directional albedo toward the
//!    pixel (what its BRDF reflects under uniform light, a dielectric's specular layer
//!    included) times the world cache's irradiance / π there (its total channel: the hit's
//!    direct light belongs to GI), as the cache's own bounce takes it. (The base colour alone,
//!    the seeds' choice, left `interior`'s lit frame 1.5% dark on an H100: `benches/RESULTS.md`,
//!    "A GI ray's hit reflects the world cache's light with its directional albedo".) The
//!    radiance is the one toward the pixel that traced it; reuse carries it to neighbours
//!    and later frames unchanged, as if the hit reflected alike in every direction.
//!    An emissive hit's own emission is left out (ReSTIR DI owns it), the light it reflects
//!    counts like any hit's; a miss gives a far sample point lit by the scene's constant
//!    environment. W = π / cos. A hit in a cell the cache has not lit yet gives no sample
//!    and no confidence ([`RestirGiSettings::ignore_cold_cells`]).
//!    A hit on a glossy metal can be lit otherwise ([`RestirGiSettings::glossy_hits`]): the
//!    uniform-light model spreads the light such a metal reflects in a narrow cone (a sun's
//!    glint) over every direction, so the surfaces that cone should light read dark (a floor
//!    beside a gold block in the sun: 0.32 of the reference's indirect light, `tests/gi.rs`).
//!    [`GlossyHits::Lights`] adds a light-tile sample through the metal's BRDF (one shadow
//!    ray) to the cache's light from everything but the light list; [`GlossyHits::Path`]
//!    takes a light sample and one BRDF-sampled bounce into the cache (two rays). Both
//!    live in the initial pass's pipeline only when chosen (a pipeline constant), whose
//!    group 3 holds the lights and their tiles beside the target image
//!    ([`RestirGi::target_group`]).
//! 2. **Temporal reuse** of last frame's final reservoir at the reprojected pixel, permuted
//!    within 4×4 blocks, rejected where the surfaces differ; confidence capped
//!    ([`RestirGiSettings::confidence_cap`]; lower where the world cache saw the reused
//!    sample's light changing when it was traced, [`RestirGiSettings::adaptive_cap`], until
//!    the view has settled: [`RestirGiSettings::adaptive_cap_settle_frames`]).
//! 3. **Spatial reuse** of one neighbour ([`RestirGiSettings::spatial_radius`], up to
//!    [`RestirGiSettings::spatial_tries`] tries with the radius halved). By default one
//!    visibility ray per pixel ([`SpatialVisibility::Chosen`]): the merge chooses between
//!    the two samples as if each pixel saw both, then traces the chosen one's ray (the
//!    neighbour's sample from the pixel, or the pixel's from the neighbour) and corrects
//!    that sample's weight by it, which keeps the estimate unbiased. That takes 18–34% off
//!    the spatial pass against tracing both rays, with the same error (H100,
//!    `benches/RESULTS.md`, "One visibility ray"). The tries trace nothing: the rays are
//!    traced after them from one call site, a pixel with one ray in the first round, so a
//!    warp whose pixels settle on different tries or rays traces once; and a ray whose
//!    answer cannot change the merge is not traced. Moving the rays out of the tries took
//!    11–35% off ReSTIR GI ("Spatial reuse without divergent rays").
//! 4. **Merges** are generalised RIS with the balance heuristic over confidence-weighted
//!    target functions (the sample's contribution through the whole BRDF, luminance of
//!    L · f · cos, so that specular GI can reuse the reservoirs of rough pixels), made
//!    comparable by the reconnection Jacobian in both directions; reuse is refused where
//!    either Jacobian exceeds [`RestirGiSettings::jacobian_bound`]. The CPU twin is
//!    [`crate::gi_reservoir`].
//! 5. The merged reservoir is stored for the next frame
//!    ([`RestirGiSettings::spatial_history`]; off, the pixel's own from before spatial
//!    reuse is), then shaded: its contribution times W is added to the target image,
//!    blended with the pixel's own reservoir's from before spatial reuse (half and half by
//!    default, [`RestirGiSettings::own_sample_share`]), or, with two spatial rays, both
//!    samples of the merge by their resampling weights
//!    ([`RestirGiSettings::shade_both_samples`]): one shaded sample keeps the colour of
//!    the surface it came from. Diffuse lobe only; smooth metals (metallic > 0.9999,
//!    roughness ≤ 0.4) skip the passes.
//!
//! With [`RestirGiSettings::plain`] (no reuse) this is plain path GI: the initial sample shaded
//! as it is (several candidates: their average), an unbiased estimate of the
//! cache-terminated bounce, in one pass
//! (`gi_initial_temporal` shades; `gi_spatial_shade` does not run). At
//! [`GiRate::Half`](crate::GiRate::Half), with reuse or without, each frame only half the
//! pixels (a checkerboard that flips every frame) trace, at twice the weight; the others draw
//! an empty sample of confidence 1, which reuse merges like any other: 32–41% off the first
//! pass on `interior` for a noisier young history. With reuse, spatial reuse then runs at the
//! other half ([`RestirGiSettings::half_rate_spatial`], on by default): the pixels that did not
//! trace reuse from neighbours that did not either, so each pixel gets one new sample or one
//! neighbour's reservoir a frame, for a third off the spatial pass on `interior`.
//! [`GiRate::Quarter`](crate::GiRate::Quarter) goes further: each pixel traces one frame in
//! four, at four times the weight, and with reuse spatial reuse runs at the pixels one frame
//! past their traced frame: ReSTIR GI's two passes on `interior` take 0.96 ms at 1080p on an
//! H200 instead of 1.27 at half rate, for the same error with a still camera there (18% more
//! after 96 frames of a moving one). At either rate a pixel with no history traces at once
//! ([`RestirGiSettings::trace_fresh_pixels`], on by default: the moving camera's error at a
//! quarter 21% lower, within 5% of every pixel's; the temporal merge traces it, so the two
//! passes take 0.99–1.00 ms on `interior`).
//!
//! Both passes are specialised by pipeline constants for what the settings run, since code
//! that never runs still costs a kernel its registers: the initial pass is built without its
//! resampling loop for one candidate (the default; 9.5–14% off the pass on an H100), and the
//! spatial pass for [`SpatialVisibility::Chosen`] (the default) settles both possible results
//! of the merge before its one ray, without the general code of the other two (2.2–3.7%),
//! and is built for spatial reuse at half rate only where it runs (read at run time, the
//! choice cost the full-rate pass 1.9–3.2% on an H200). [`RestirGi::prepare`] builds a pass
//! again after a settings change crosses any of these lines.
//! For the same reason, with reuse the initial pass is two dispatches: one traces the new
//! samples and stores them, the next merges them with the history (it traces only for a
//! pixel without history at a reduced rate, a branch that measured no cost where not
//! taken). In one
//! kernel the traversal ran with the registers of the merge: the split takes 25–26% off the
//! pass on `interior`, 15–17% on sun_boxes and many_lights, and costs the Cornell box's
//! trivial traversal 1.4–4.2% for the second dispatch (H100, 1080p, `benches/RESULTS.md`,
//! "The temporal merge in a dispatch of its own"). Plain path GI may shade in a second
//! dispatch as well ([`RestirGiSettings::shade_apart`]), which pays only where traversal is
//! costly.
//!
//! ## Memory
//!
//! Two reservoir buffers of 32 bytes per pixel (66 MB each at 1920×1080): the initial pass
//! reads last frame's final reservoirs before the spatial pass overwrites them, so no third
//! buffer is needed. Built without reuse ([`RestirGiSettings::plain`], the renderer's path
//! GI), it keeps one: nothing reads a history, and the one pass stores each pixel's reservoir
//! where specular GI reads it. Such a `RestirGi` refuses
//! settings that turn reuse on: build a new one with them.

use crate::di::{PassLayouts, check_encode, layout_with_cache, pass_pipeline, record};
use crate::gi_reservoir::GpuGiReservoir;
use crate::gi_settings::{GlossyHits, GpuGiParams, RestirGiSettings, SpatialVisibility, flags};
use crate::settings::flags::reuse;
use bytemuck::Zeroable;
use solari_lights::{GpuLights, LightTileSettings, LightTiles};
use solari_scene::GpuError;
use solari_scene::bindings::{Buf, BufferGroup};
use solari_scene::gbuffer_input::GBufferSource;
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::{GpuScene, TraceVariant};
use solari_scene::pass::{FrameContext, Ran};
use solari_scene::shaders::Backend;
use solari_worldcache::WorldCache;

/// Bind group 2 of the GI shaders (`restir_gi.wesl`) below the world cache's bindings, by
/// WGSL name.
pub const GI_BINDINGS: BufferGroup = BufferGroup::new(
    2,
    0,
    &[
        ("gi_params", Buf::Uniform),
        ("gi_history", Buf::ReadWrite),
        ("gi_initial", Buf::ReadWrite),
    ],
);

/// Bind group 3 of the GI shaders beyond the lights and their tiles (bindings 0–8,
/// [`LightTiles::reader_layout`], read at glossy hits): the image shading adds to.
pub const GI_TARGET_BINDINGS: BufferGroup = BufferGroup::new(3, 9, &[("lit", Buf::ReadWrite)]);

/// The pipeline constant that compiles reuse out of both GI passes (`@id(7120) override
/// GI_REUSE` in `restir_gi.wesl`), for an instance built without reuse.
const REUSE_OFF: (&str, f64) = ("7120", 0.0);

/// The pipeline constant that specialises the spatial pass for [`SpatialVisibility::Chosen`]
/// (`@id(7121) override GI_CHOSEN_ONLY` in `restir_gi.wesl`).
const CHOSEN_ONLY: (&str, f64) = ("7121", 1.0);

/// The pipeline constant that builds the initial pass's resampling of several candidates
/// ([`RestirGiSettings::initial_samples`] above 1; `@id(7122) override GI_MULTI_CANDIDATE`).
const MULTI_CANDIDATE: (&str, f64) = ("7122", 1.0);

/// The pipeline constant that builds the initial pass's second dispatch (`@id(7123) override
/// GI_SECOND_DISPATCH`): with reuse the temporal merge, without it the shading of
/// [`RestirGiSettings::shade_apart`].
const SECOND_DISPATCH: (&str, f64) = ("7123", 1.0);

/// The pipeline constant that has plain path GI's first dispatch leave the shading to the
/// second ([`RestirGiSettings::shade_apart`]; `@id(7124) override GI_SHADE_APART`).
const SHADE_APART: (&str, f64) = ("7124", 1.0);

/// The pipeline constant that builds the spatial pass for spatial reuse at a reduced rate
/// ([`RestirGiSettings::half_rate_spatial`] with [`GiRate::Half`](crate::GiRate::Half) or
/// [`GiRate::Quarter`](crate::GiRate::Quarter); `@id(7125) override GI_HALF_SPATIAL`).
const HALF_SPATIAL: (&str, f64) = ("7125", 1.0);

/// The pipeline constant that builds the initial pass's lighting of glossy hits
/// ([`RestirGiSettings::glossy_hits`], [`GlossyHits::constant`]; `@id(7126) override
/// GI_GLOSSY_HITS`).
const GLOSSY_HITS: &str = "7126";

/// What the initial pass's (first dispatch's) pipeline is specialised for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct InitialForm {
    /// The resampling of several candidates (MULTI_CANDIDATE).
    multi: bool,
    /// Without reuse, the shading left to the second dispatch (SHADE_APART).
    shade_apart: bool,
    /// How glossy hits are lit (GLOSSY_HITS).
    glossy: GlossyHits,
}

/// What the spatial pass's pipeline is specialised for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct SpatialForm {
    /// [`SpatialVisibility::Chosen`] (CHOSEN_ONLY).
    chosen: bool,
    /// Spatial reuse at half rate (HALF_SPATIAL).
    half_rate: bool,
}

/// Labels of the two passes (profiler scopes; the first holds two dispatches with reuse, the
/// one that traces and the temporal merge); plain path GI runs the first alone, one dispatch.
pub const GI_PASS_LABELS: [&str; 2] = ["gi_initial_temporal", "gi_spatial_shade"];

/// The default of [`RestirGiSettings::adaptive_cap_settle_frames`]: frames a view must hold
/// still (the same camera, history kept, no [`RestirGi::unsettle`] and no
/// [`RestirGi::follow_light_change`] whose frames have not run out) before
/// [`RestirGiSettings::adaptive_cap`] stops; past them temporal reuse caps every history at
/// [`RestirGiSettings::confidence_cap`] alone. The world cache's own averaging spans 30
/// samples by default, so after 32 frames its cells have settled and the cap would only
/// weigh histories by the (noisy) light they hold.
pub const ADAPTIVE_CAP_SETTLE_FRAMES: u32 = 32;

/// ReSTIR GI: reads the G-buffer (group 1), the scene (group 0) and the world cache, and adds
/// diffuse indirect light to a target image (`vec4<f32>` per pixel, group 3,
/// [`RestirGi::target_group`]).
pub struct RestirGi {
    settings: RestirGiSettings,
    variant: TraceVariant,
    backend: Backend,
    size: (u32, u32),
    initial: wgpu::ComputePipeline,
    // The initial pass's second dispatch: with reuse the temporal merge (`initial` traces),
    // without it the shading where `shade_apart`.
    second: Option<wgpu::ComputePipeline>,
    // What `initial` was specialised for; a settings change across any of its lines has
    // `prepare` build it again (and `second` too where `shade_apart` moved: a `RestirGi`
    // built without reuse then has its shading in `second`).
    initial_form: InitialForm,
    // None when built without reuse (`in_place`): plain path GI shades in its initial pass.
    spatial: Option<wgpu::ComputePipeline>,
    // What `spatial` was specialised for; a settings change across either line has
    // `prepare` build it again.
    spatial_form: SpatialForm,
    layout: wgpu::BindGroupLayout,
    target_layout: wgpu::BindGroupLayout,
    // The light tiles glossy hits sample (pipeline constants and the sample count).
    tiles: LightTileSettings,
    params: wgpu::Buffer,
    // (history, initial).
    buffers: Option<(wgpu::Buffer, wgpu::Buffer)>,
    // The initial reservoirs are a scratch buffer given by `use_scratch`, counted by its
    // owner.
    initial_shared: bool,
    group: Option<wgpu::BindGroup>,
    frame: u32,
    history: bool,
    // Frames left with the history's confidence capped at 1 (`follow_light_change`).
    short_history: u32,
    // Frames in a row with history, the same camera and no scene or light change: past
    // `ADAPTIVE_CAP_SETTLE_FRAMES` the adaptive cap stops.
    settled: u32,
    // `set_indirect_only`.
    indirect_only: bool,
    // Whether the last `prepare` set the adaptive cap's flag.
    cap_active: bool,
}

// The initial pass's (first dispatch's) pipeline, built for reuse or without it, with the
// resampling of several candidates where `multi`, without reuse leaving the shading to the
// second dispatch where `shade_apart`, and lighting glossy hits as `glossy` says.
fn initial_pipeline(
    gpu: &Gpu,
    backend: Backend,
    variant: TraceVariant,
    layouts: (&wgpu::BindGroupLayout, &wgpu::BindGroupLayout),
    reuse: bool,
    forms: InitialForm,
    tiles: &LightTileSettings,
) -> Result<wgpu::ComputePipeline, GpuError> {
    let InitialForm {
        multi,
        shade_apart,
        glossy,
    } = forms;
    let mut extra = Vec::new();
    if !reuse {
        extra.push(REUSE_OFF);
    }
    if multi {
        extra.push(MULTI_CANDIDATE);
    }
    if !reuse && shade_apart {
        extra.push(SHADE_APART);
    }
    extra.extend(glossy_constant(glossy));
    initial_shader_pipeline(gpu, backend, variant, layouts, &extra, tiles)
}

// The constant that builds `glossy`'s lighting of glossy hits into the initial shader (none
// for the cache's model, the shader's default).
fn glossy_constant(glossy: GlossyHits) -> Option<(&'static str, f64)> {
    (glossy != GlossyHits::Cache).then(|| (GLOSSY_HITS, glossy.constant()))
}

// A pipeline of the initial shader (either dispatch), which reads the lights: with the
// tiles' constants beside `extra`.
fn initial_shader_pipeline(
    gpu: &Gpu,
    backend: Backend,
    variant: TraceVariant,
    layouts: (&wgpu::BindGroupLayout, &wgpu::BindGroupLayout),
    extra: &[(&'static str, f64)],
    tiles: &LightTileSettings,
) -> Result<wgpu::ComputePipeline, GpuError> {
    let entry = "restir_gi_initial";
    gi_pipeline(gpu, backend, variant, layouts, entry, extra, Some(tiles))
}

// The initial pass's second dispatch: with reuse the temporal merge, without it the shading
// of `RestirGiSettings::shade_apart`.
fn second_pipeline(
    gpu: &Gpu,
    backend: Backend,
    variant: TraceVariant,
    layouts: (&wgpu::BindGroupLayout, &wgpu::BindGroupLayout),
    reuse: bool,
    glossy: GlossyHits,
    tiles: &LightTileSettings,
) -> Result<wgpu::ComputePipeline, GpuError> {
    let mut extra = vec![SECOND_DISPATCH];
    if reuse {
        // The temporal merge draws a new sample where a pixel has no history at a reduced
        // rate (`trace_fresh_pixels`): the one the first dispatch would have drawn.
        extra.extend(glossy_constant(glossy));
    } else {
        extra.push(REUSE_OFF);
    }
    initial_shader_pipeline(gpu, backend, variant, layouts, &extra, tiles)
}

// The spatial pass's pipeline, specialised for `form` (reuse on: a `RestirGi` built without
// reuse has no spatial pass).
fn spatial_pipeline(
    gpu: &Gpu,
    backend: Backend,
    variant: TraceVariant,
    layouts: (&wgpu::BindGroupLayout, &wgpu::BindGroupLayout),
    form: SpatialForm,
) -> Result<wgpu::ComputePipeline, GpuError> {
    let mut extra = Vec::new();
    if form.chosen {
        extra.push(CHOSEN_ONLY);
    }
    if form.half_rate {
        extra.push(HALF_SPATIAL);
    }
    gi_pipeline(
        gpu,
        backend,
        variant,
        layouts,
        "restir_gi_spatial",
        &extra,
        None,
    )
}

// The pass specialisations `s` wants: the initial pass's form (plain path GI shades apart
// only where the instance is built without reuse, `in_place`, and draws one candidate:
// several are averaged as they are traced, and only the reservoir they are resampled to is
// stored) and the spatial pass's.
fn wanted_pipelines(s: &RestirGiSettings, in_place: bool) -> (InitialForm, SpatialForm) {
    (
        InitialForm {
            multi: s.initial_samples > 1,
            shade_apart: in_place && s.shade_apart && s.initial_samples == 1,
            glossy: s.glossy_hits,
        },
        SpatialForm {
            chosen: s.spatial_visibility == SpatialVisibility::Chosen,
            half_rate: s.rate.reduced() && s.half_rate_spatial,
        },
    )
}

// A GI pass's pipeline (`entry`) over its own group and the target group (`layouts`), with
// `variant`'s traversal constants, `extra` and, for the initial pass's shader, which reads
// the lights, the light tiles' (`tiles`: a pipeline given a constant its shader does not
// declare is refused, and the spatial pass's declares none).
fn gi_pipeline(
    gpu: &Gpu,
    backend: Backend,
    variant: TraceVariant,
    (layout, target_layout): (&wgpu::BindGroupLayout, &wgpu::BindGroupLayout),
    entry: &str,
    extra: &[(&'static str, f64)],
    tiles: Option<&LightTileSettings>,
) -> Result<wgpu::ComputePipeline, GpuError> {
    let shared = PassLayouts::new(gpu, backend);
    let layouts = shared.with(layout, target_layout);
    let mut constants = match tiles {
        Some(tiles) => tiles.reader_constants(variant.constants()),
        None => variant.constants().to_vec(),
    };
    constants.extend_from_slice(extra);
    let modules = crate::gi_modules();
    pass_pipeline(gpu, backend, &modules, &layouts, entry, &constants)
}

impl RestirGi {
    /// Builds the pipelines for scenes uploaded with `backend` and traced with `variant`,
    /// and allocates `width × height` reservoirs bound with `cache`'s table. `tiles`: the
    /// settings of the light tiles that [`RestirGi::target_group`] will bind, which glossy
    /// hits sample ([`RestirGiSettings::glossy_hit_roughness`]).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        gpu: &Gpu,
        backend: Backend,
        variant: TraceVariant,
        width: u32,
        height: u32,
        settings: RestirGiSettings,
        cache: &WorldCache,
        tiles: LightTileSettings,
    ) -> Result<Self, GpuError> {
        settings.validate()?;
        let variant = variant.for_backend(backend);
        let layout = layout_with_cache(gpu, &GI_BINDINGS, "solari_restir/gi");
        let mut target_entries = LightTiles::reader_layout_entries();
        target_entries.extend(GI_TARGET_BINDINGS.layout_entries(wgpu::ShaderStages::COMPUTE));
        let target_layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("solari_restir/gi_lights_and_target"),
                entries: &target_entries,
            });
        let reuse = settings.reuse();
        let (initial_form, form) = wanted_pipelines(&settings, !reuse);
        let layouts = (&layout, &target_layout);
        let initial =
            initial_pipeline(gpu, backend, variant, layouts, reuse, initial_form, &tiles)?;
        let second = if reuse || initial_form.shade_apart {
            Some(second_pipeline(
                gpu,
                backend,
                variant,
                layouts,
                reuse,
                initial_form.glossy,
                &tiles,
            )?)
        } else {
            None
        };
        let spatial = if settings.reuse() {
            Some(spatial_pipeline(
                gpu,
                backend,
                variant,
                (&layout, &target_layout),
                form,
            )?)
        } else {
            None
        };
        let params = gpu.uniform_buffer("solari_restir/gi_params", &GpuGiParams::zeroed());
        let mut gi = Self {
            settings,
            variant,
            backend,
            size: (0, 0),
            initial,
            second,
            initial_form,
            spatial,
            spatial_form: form,
            layout,
            target_layout,
            tiles,
            params,
            buffers: None,
            initial_shared: false,
            group: None,
            frame: 0,
            history: false,
            short_history: 0,
            settled: 0,
            indirect_only: false,
            cap_active: false,
        };
        gi.resize(gpu, width, height, cache)?;
        Ok(gi)
    }

    /// GPU memory ReSTIR GI holds, in bytes: two reservoirs per pixel (one when built without
    /// reuse; one less when the initial reservoirs live in a shared scratch buffer) and the
    /// parameters.
    pub fn memory_bytes(&self) -> u64 {
        let pixels = self.buffers.as_ref().map_or(0, |(a, b)| {
            a.size() + if self.initial_shared { 0 } else { b.size() }
        });
        pixels + self.params.size()
    }

    /// Bytes of scratch [`RestirGi::use_scratch`] needs: the initial reservoirs (32 bytes per
    /// pixel), which live from the first dispatch of a frame to the last reader of
    /// [`RestirGi::reservoirs`] when built without reuse (specular GI), and to the second
    /// dispatch with reuse.
    pub fn scratch_bytes(&self) -> u64 {
        self.size.0 as u64 * self.size.1 as u64 * size_of::<GpuGiReservoir>() as u64
    }

    /// Keeps the initial reservoirs in `scratch` (at least [`RestirGi::scratch_bytes`], a
    /// storage buffer) instead of a buffer of its own, which is freed, bound again with
    /// `cache`'s table. Built without reuse, [`RestirGi::reservoirs`] is then `scratch`:
    /// bind readers of it (specular GI) after this call, and let nothing else write
    /// `scratch` between GI's dispatches and theirs (see [`solari_scene::scratch`]).
    /// [`RestirGi::resize`] allocates an own buffer again.
    pub fn use_scratch(
        &mut self,
        gpu: &Gpu,
        scratch: &wgpu::Buffer,
        cache: &WorldCache,
    ) -> Result<(), GpuError> {
        solari_scene::scratch::check("ReSTIR GI", scratch, self.scratch_bytes())?;
        let (history, _) = self.buffers.take().expect("resize allocates");
        self.buffers = Some((history, scratch.clone()));
        self.initial_shared = true;
        self.bind(gpu, cache);
        Ok(())
    }

    // Builds the pass's group over `buffers` and `cache`'s table.
    fn bind(&mut self, gpu: &Gpu, cache: &WorldCache) {
        let (history, initial) = self.buffers.as_ref().expect("resize allocates");
        let mut entries = GI_BINDINGS.entries(&[
            ("gi_params", &self.params),
            ("gi_history", history),
            ("gi_initial", initial),
        ]);
        entries.extend(cache.bind_group_entries());
        self.group = Some(gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("solari_restir/gi"),
            layout: &self.layout,
            entries: &entries,
        }));
    }

    /// The settings in use.
    pub fn settings(&self) -> RestirGiSettings {
        self.settings
    }

    /// Changes the settings; history is kept (every knob is valid with any history). A
    /// `RestirGi` built without reuse holds no history buffer and refuses settings that turn
    /// reuse on (build a new one with them).
    pub fn set_settings(&mut self, settings: RestirGiSettings) -> Result<(), GpuError> {
        settings.validate()?;
        if self.in_place() && settings.reuse() {
            return Err(GpuError::Validation(
                "ReSTIR GI was built without reuse (plain path GI keeps one reservoir buffer): \
                 build a new RestirGi to turn temporal or spatial reuse on"
                    .into(),
            ));
        }
        self.settings = settings;
        Ok(())
    }

    /// The traversal the pipelines were built for; [`RestirGi::encode`] refuses a scene this
    /// variant cannot trace.
    pub fn variant(&self) -> TraceVariant {
        self.variant
    }

    /// Reallocates the reservoirs (64 bytes per pixel, 32 without reuse) and binds them with `cache`'s table
    /// (call it too after the cache was rebuilt); history restarts.
    pub fn resize(
        &mut self,
        gpu: &Gpu,
        width: u32,
        height: u32,
        cache: &WorldCache,
    ) -> Result<(), GpuError> {
        let pixels = width as u64 * height as u64;
        if pixels == 0 {
            return Err(GpuError::Validation(format!(
                "ReSTIR GI image size {width}×{height} is empty"
            )));
        }
        let bytes = pixels * size_of::<GpuGiReservoir>() as u64;
        gpu.check_storage_binding("ReSTIR GI reservoirs", bytes)?;
        let buffer = |label: &str, size: u64| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        // Without reuse nothing reads a history: one reservoir stands in for the binding.
        let history = if self.in_place() {
            buffer(
                "solari_restir/gi_history (none: built without reuse)",
                size_of::<GpuGiReservoir>() as u64,
            )
        } else {
            buffer("solari_restir/gi_history", bytes)
        };
        let initial = buffer("solari_restir/gi_initial", bytes);
        self.buffers = Some((history, initial));
        self.initial_shared = false;
        self.bind(gpu, cache);
        self.size = (width, height);
        self.history = false;
        Ok(())
    }

    /// The bind group of the image shading adds to (`width × height` `vec4<f32>`, row by
    /// row), for example [`crate::RestirDi::output`], with the lights and `tiles` (built with
    /// the settings [`RestirGi::new`] was given), which glossy hits sample. Rebuild it when
    /// the light list is re-uploaded.
    ///
    /// Errors when `tiles` was built with other settings than those (the pass would index
    /// past its samples or read them as other kinds of light).
    pub fn target_group(
        &self,
        gpu: &Gpu,
        target: &wgpu::Buffer,
        tiles: &LightTiles,
        lights: &GpuLights,
    ) -> Result<wgpu::BindGroup, GpuError> {
        if tiles.settings() != self.tiles {
            return Err(GpuError::Validation(format!(
                "ReSTIR GI was built for light tiles {:?}, given tiles built with {:?}: build \
                 RestirGi with the tiles' settings",
                self.tiles,
                tiles.settings()
            )));
        }
        let mut entries = tiles.reader_entries(lights);
        entries.extend(GI_TARGET_BINDINGS.entries(&[("lit", target)]));
        Ok(gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("solari_restir/gi_lights_and_target"),
            layout: &self.target_layout,
            entries: &entries,
        }))
    }

    /// Drops history: the next frame uses no temporal reuse (for camera cuts).
    pub fn reset(&mut self) {
        self.history = false;
    }

    /// Tells ReSTIR GI that the lights changed: for the next `frames` frames (from the next
    /// [`RestirGi::prepare`]) temporal reuse counts a history as one frame's sample
    /// (history cap 1), since its samples keep the radiance they were traced with. On
    /// lavapipe's 64² Cornell box with the world cache following too (its
    /// `follow_light_change`), 0.12 of a switched-off bulb's light was left after 8 frames
    /// against 0.22 with the cap left at 4 and 0.27 at 8 (`benches/RESULTS.md`, "The world
    /// cache follows a light switch"). Those frames are as noisy as reuse without history.
    /// Samples traced in those frames carry the settings' cap as usual
    /// ([`RestirGiSettings::adaptive_cap`]), so the shortening ends with its frames.
    pub fn follow_light_change(&mut self, frames: u32) {
        self.short_history = frames;
        self.settled = 0;
    }

    /// Whether the last [`RestirGi::prepare`] ran [`RestirGiSettings::adaptive_cap`] (the
    /// setting on and the view not yet settled).
    pub fn adaptive_cap_active(&self) -> bool {
        self.cap_active
    }

    /// Tells ReSTIR GI that the scene changed other than by its camera (instances moved,
    /// lights moved or changed by any amount): [`RestirGiSettings::adaptive_cap`] runs again
    /// from the next [`RestirGi::prepare`] until the view has been still for
    /// [`RestirGiSettings::adaptive_cap_settle_frames`] frames. ([`RestirGi::follow_light_change`]
    /// does this too.)
    pub fn unsettle(&mut self) {
        self.settled = 0;
    }

    /// With `true`, from the next [`RestirGi::prepare`] on, a GI ray that misses carries no
    /// sky: where light sampling does not cover the environment, GI otherwise adds the sky
    /// seen from the primary surface, which is one scattering event, direct light. With
    /// [`crate::RestirDi::set_indirect_only`] and [`crate::SpecularGi::set_indirect_only`]
    /// this makes a frame of indirect light alone. Off by default.
    pub fn set_indirect_only(&mut self, on: bool) {
        self.indirect_only = on;
    }

    /// Writes the frame's parameters. `gbuffer` is the G-buffer this frame reads (its
    /// history decides whether temporal reuse may run). After [`RestirGi::set_settings`]
    /// moved [`RestirGiSettings::initial_samples`] to or from 1,
    /// [`RestirGiSettings::spatial_visibility`] to or from [`SpatialVisibility::Chosen`], or
    /// changed [`RestirGiSettings::glossy_hits`], it first builds that pass again (a
    /// one-time pipeline compile; the error is that build's).
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        frame: &FrameContext,
        gbuffer: &dyn GBufferSource,
    ) -> Result<(), GpuError> {
        let s = self.settings;
        let (initial_form, form) = wanted_pipelines(&self.settings, self.in_place());
        let apart = initial_form.shade_apart;
        if initial_form != self.initial_form {
            let layouts = (&self.layout, &self.target_layout);
            let reuse = self.built_for_reuse();
            self.initial = initial_pipeline(
                gpu,
                self.backend,
                self.variant,
                layouts,
                reuse,
                initial_form,
                &self.tiles,
            )?;
            if reuse && initial_form.glossy != self.initial_form.glossy {
                // The temporal merge draws fresh pixels' samples as the first dispatch does.
                self.second = Some(second_pipeline(
                    gpu,
                    self.backend,
                    self.variant,
                    layouts,
                    true,
                    initial_form.glossy,
                    &self.tiles,
                )?);
            } else if apart != self.initial_form.shade_apart {
                self.second = if apart {
                    Some(second_pipeline(
                        gpu,
                        self.backend,
                        self.variant,
                        layouts,
                        false,
                        initial_form.glossy,
                        &self.tiles,
                    )?)
                } else {
                    None
                };
            }
            log::debug!(
                "ReSTIR GI: initial pass built again for {} candidates{}{}",
                s.initial_samples,
                if apart { ", shading apart" } else { "" },
                match initial_form.glossy {
                    GlossyHits::Cache => "",
                    GlossyHits::Lights => ", light samples at glossy hits",
                    GlossyHits::Path => ", paths on from glossy hits",
                }
            );
            self.initial_form = initial_form;
        }
        if self.spatial.is_some() && form != self.spatial_form {
            let pipeline = spatial_pipeline(
                gpu,
                self.backend,
                self.variant,
                (&self.layout, &self.target_layout),
                form,
            )?;
            log::debug!(
                "ReSTIR GI: spatial pass built again for {:?}{}",
                s.spatial_visibility,
                if form.half_rate { " at half rate" } else { "" }
            );
            self.spatial = Some(pipeline);
            self.spatial_form = form;
        }
        self.frame = frame.index;
        let history = self.history && gbuffer.history_valid();
        let mut bits = reuse(s.temporal, s.spatial, s.permutation_sampling, history);
        // `Chosen` is the spatial pipeline built above (CHOSEN_ONLY), not a flag.
        if s.spatial_visibility == SpatialVisibility::Both {
            bits |= flags::UNBIASED_SPATIAL;
        }
        if s.shade_both_samples && s.spatial_visibility != SpatialVisibility::Chosen {
            bits |= flags::SHADE_BOTH;
        }
        if s.spatial_history {
            bits |= flags::SPATIAL_HISTORY;
        }
        if s.rate.reduced() {
            bits |= flags::HALF_RATE;
        }
        if s.ignore_cold_cells {
            bits |= flags::IGNORE_COLD;
        }
        // The adaptive cap weighs a history by the sample it holds, which biases a settled
        // view: it runs only while the view or the lights are unsettled.
        let still = history && frame.view.same_camera(&frame.previous_view);
        self.settled = if still && self.short_history == 0 {
            self.settled.saturating_add(1)
        } else {
            0
        };
        self.cap_active = s.adaptive_cap && self.settled <= s.adaptive_cap_settle_frames;
        if self.cap_active {
            bits |= flags::ADAPTIVE_CAP;
        }
        if s.trace_fresh_pixels {
            bits |= flags::TRACE_FRESH;
        }
        if self.indirect_only {
            bits |= flags::INDIRECT_ONLY;
        }
        // After a light change (`follow_light_change`) a history counts as one frame's
        // sample; the caps new samples carry still come from the settings, so the shortening
        // ends with its frames.
        let mut history_cap = s.confidence_cap;
        if self.short_history > 0 {
            self.short_history -= 1;
            history_cap = 1.0;
        }
        let params = GpuGiParams {
            width: self.size.0,
            height: self.size.1,
            frame: frame.index,
            flags: bits,
            spatial_radius: s.spatial_radius,
            confidence_cap: s.confidence_cap,
            spatial_tries: s.spatial_tries,
            jacobian_bound: s.jacobian_bound,
            max_ray_distance: s.max_ray_distance,
            initial_samples: s.initial_samples,
            history_cap,
            rate_shift: s.rate_shift(),
            own_share: s.own_sample_share,
            tile_samples: u32::try_from(self.tiles.sample_count()).unwrap_or(u32::MAX),
            glossy_roughness: s.glossy_hit_roughness,
            pad: 0,
        };
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        Ok(())
    }

    /// Records both passes (built without reuse, the first alone, which shades), each in a
    /// profiler scope named as in [`GI_PASS_LABELS`], and returns which ran. With reuse the
    /// first pass is two dispatches: the new samples are traced, then merged with the
    /// history, so that the traversal does not run with the merge's registers (interior's
    /// pass 25–26% faster on an H100 at 1080p). Run it after the world cache's upkeep and
    /// after whatever wrote the direct light into `target` ([`RestirGi::target_group`]).
    ///
    /// Errors, recording nothing, when the pipelines were specialised for a scene shape that
    /// `scene` no longer has, or for settings that [`RestirGi::set_settings`] changed with
    /// no [`RestirGi::prepare`] since, or when the G-buffer's or the frame's size is not this
    /// pass's.
    pub fn encode(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        scene: &GpuScene,
        gbuffer: &dyn GBufferSource,
        target: &wgpu::BindGroup,
    ) -> Result<Ran, GpuError> {
        check_encode("ReSTIR GI", self.variant, self.size, scene, gbuffer, frame)?;
        // The pipelines are specialised for the settings (`prepare` rebuilds them): run
        // against other settings they would shade another estimator without a word.
        let (initial_form, form) = wanted_pipelines(&self.settings, self.in_place());
        if (self.spatial.is_some() && form != self.spatial_form)
            || initial_form != self.initial_form
        {
            return Err(GpuError::Validation(
                "ReSTIR GI: settings changed since the last prepare; call RestirGi::prepare \
                 before encode"
                    .into(),
            ));
        }
        let group = self.group.as_ref().expect("resize binds the reservoirs");
        let groups = [scene.bind_group(), gbuffer.bind_group()?, group, target];
        let workgroups = [self.size.0.div_ceil(8), self.size.1.div_ceil(8)];
        let mut ran = Ran::none();
        // The first scope holds the initial pass's dispatches: with reuse, the one that
        // traces and the temporal merge; with the shading apart, the one that traces and it.
        let passes = [
            [Some(&self.initial), self.second.as_ref()],
            [self.spatial.as_ref(), None],
        ];
        for (&label, pipelines) in GI_PASS_LABELS.iter().zip(passes) {
            if pipelines[0].is_none() {
                continue;
            }
            frame.scope(label, encoder, &mut ran, |e| {
                for pipeline in pipelines.into_iter().flatten() {
                    record(e, label, pipeline, &groups, workgroups);
                }
            });
        }
        self.history = true;
        Ok(ran)
    }

    /// Whether this instance was built for reuse (both passes); built without it
    /// ([`RestirGiSettings::plain`]), it runs one pass, which shades.
    pub fn built_for_reuse(&self) -> bool {
        self.spatial.is_some()
    }

    /// Whether the initial pass's pipeline holds the resampling of several candidates
    /// ([`RestirGiSettings::initial_samples`] above 1: built without it, the single-candidate
    /// pass was 9.5–14% faster on an H100). After [`RestirGi::set_settings`] moved the count
    /// to or from 1, the next [`RestirGi::prepare`] builds the other.
    pub fn initial_multi_candidate(&self) -> bool {
        self.initial_form.multi
    }

    /// How the initial pass's pipeline lights glossy hits ([`RestirGiSettings::glossy_hits`]:
    /// built for [`GlossyHits::Cache`], it holds no light sampling and one traversal). After
    /// [`RestirGi::set_settings`] changed the setting, the next [`RestirGi::prepare`] builds
    /// the pass again.
    pub fn glossy_hits(&self) -> GlossyHits {
        self.initial_form.glossy
    }

    /// Whether plain path GI shades in the initial pass's second dispatch
    /// ([`RestirGiSettings::shade_apart`]; false when built with reuse, whose second dispatch
    /// is the temporal merge). After [`RestirGi::set_settings`] moved the setting, the next
    /// [`RestirGi::prepare`] builds the pass again.
    pub fn shades_apart(&self) -> bool {
        self.in_place() && self.initial_form.shade_apart
    }

    /// Whether the spatial pass's pipeline is the one specialised for
    /// [`SpatialVisibility::Chosen`] (false when built without reuse). After
    /// [`RestirGi::set_settings`] moved the visibility across that line, the next
    /// [`RestirGi::prepare`] builds the other.
    pub fn spatial_chosen_only(&self) -> bool {
        self.spatial.is_some() && self.spatial_form.chosen
    }

    /// Whether the spatial pass's pipeline is the one built for spatial reuse at a reduced
    /// rate ([`RestirGiSettings::half_rate_spatial`] at
    /// [`GiRate::Half`](crate::GiRate::Half) or [`GiRate::Quarter`](crate::GiRate::Quarter);
    /// false when built without reuse). After
    /// [`RestirGi::set_settings`] moved either across that line, the next
    /// [`RestirGi::prepare`] builds the other.
    pub fn spatial_half_rate(&self) -> bool {
        self.spatial.is_some() && self.spatial_form.half_rate
    }

    // Built without reuse: one reservoir buffer (`buffers.0` a placeholder), one pass.
    fn in_place(&self) -> bool {
        !self.built_for_reuse()
    }

    /// This frame's final reservoirs ([`GpuGiReservoir`] per pixel, row by row), which the
    /// next frame reuses and specular GI's rough pixels shade: the spatial merge's, or with
    /// [`RestirGiSettings::spatial_history`] off each pixel's own from before spatial reuse
    /// (built without reuse: the one reservoir buffer, where each pixel's shade stored its
    /// sample back); layout for the non-finite detector:
    /// [`crate::gi_reservoir::gi_reservoir_check`].
    pub fn reservoirs(&self) -> &wgpu::Buffer {
        let (history, initial) = self.buffers.as_ref().expect("resize allocates");
        if self.in_place() { initial } else { history }
    }

    /// Image size in pixels.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }
}
