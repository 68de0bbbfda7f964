//! The ReSTIR DI pass pair and its per-pixel buffers.

use crate::reservoir::GpuReservoir;
use crate::settings::{GpuDiParams, RestirDiSettings, flags};
use bytemuck::Zeroable;
use solari_lights::{GpuLights, LIGHT_GRID_ON, LightTileSettings, LightTiles};
use solari_scene::GpuError;
use solari_scene::bindings::{Buf, BufferGroup};
use solari_scene::gbuffer::GBuffer;
use solari_scene::gbuffer_input::GBufferSource;
use solari_scene::gpu::{Gpu, ShaderChecks};
use solari_scene::gpu_scene::{GpuScene, TraceVariant};
use solari_scene::pass::{FrameContext, Ran};
use solari_scene::shaders::{Backend, compose};

/// ReSTIR DI: reads the G-buffer (group 1) and light tiles (group 3), writes shaded radiance
/// (emission plus direct light, linear, one `vec4<f32>` per pixel) to
/// [`RestirDi::output`], and keeps its reservoirs for the next frame.
pub struct RestirDi {
    settings: RestirDiSettings,
    tiles: LightTileSettings,
    // What the tracing pipelines were specialised for: checked against the scene at encode.
    variant: TraceVariant,
    size: (u32, u32),
    backend: Backend,
    initial: wgpu::ComputePipeline,
    spatial: wgpu::ComputePipeline,
    // The initial pass built with `DI_ONE_PASS` (frames without reuse: it shades, and the
    // spatial pass does not run); built in `new` when such frames are likely, else by
    // `prepare` at the first one (`build_one_pass`).
    one_pass: Option<wgpu::ComputePipeline>,
    // Whether the prepared frame runs `one_pass` alone.
    single: bool,
    emission: wgpu::ComputePipeline,
    own_layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    buffers: Option<PixelBuffers>,
    translation: wgpu::Buffer,
    translation_count: u32,
    // A translation set for the next frame, and whether the uploaded table is the identity
    // for this many lights (so unchanged lights cost no upload).
    pending_translation: Option<Vec<u32>>,
    // Whether the uploaded translation carries a bitset of lights new this frame.
    appeared: bool,
    identity_for: Option<u32>,
    frame: u32,
    history: bool,
    // Whether the last `prepare` skipped reuse by `reuse_light_threshold`.
    reuse_skipped: bool,
    // `set_indirect_only`.
    indirect_only: bool,
}

// Per-pixel buffers and their bind group. One final-reservoir buffer is history and result
// at once: the initial pass reads last frame's finals and the spatial pass, a later
// dispatch, overwrites them (a second buffer swapped by parity cost 20 B per pixel). Frames
// without reuse keep no reservoir (nothing would read it): until the first frame with
// reuse, `finals` is a one-reservoir placeholder (`has_finals` false) and costs nothing.
struct PixelBuffers {
    output: wgpu::Buffer,
    shadow: wgpu::Buffer,
    finals: wgpu::Buffer,
    has_finals: bool,
    // Kept for the memory report and rebinding (the bind group holds it too); `shared`: a
    // scratch buffer given by `use_scratch`, counted by its owner.
    initial: wgpu::Buffer,
    shared: bool,
    group: wgpu::BindGroup,
}

const FINALS_LABEL: &str = "solari_restir/di_reservoirs";

// One of DI's per-pixel buffers (storage, readable back for tests and the detector).
fn pixel_buffer(gpu: &Gpu, label: &str, size: u64) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// Bind group 2 of the DI shaders (`restir_di.wesl`), by WGSL name.
pub const DI_BINDINGS: BufferGroup = BufferGroup::new(
    2,
    0,
    &[
        ("params", Buf::Uniform),
        ("reservoirs_initial", Buf::ReadWrite),
        ("reservoirs_final", Buf::ReadWrite),
        ("di_output", Buf::ReadWrite),
        ("light_translation", Buf::Read),
        ("di_shadow", Buf::ReadWrite),
    ],
);

/// Labels of the dispatches (and profiler scopes): initial + temporal, spatial + shade, and
/// the emission copy that replaces both when a scene has no lights. A frame without reuse
/// runs the first alone, which then also shades.
pub const PASS_LABELS: [&str; 3] = ["di_initial_temporal", "di_spatial_shade", "emission_only"];

/// The pipeline constant that builds the initial pass as the whole of DI, for frames without
/// reuse (`@id(7140) override DI_ONE_PASS` in `restir_di_initial.wesl`).
const ONE_PASS: (&str, f64) = ("7140", 1.0);

// The initial pass's pipeline constants: the tile readers', the light grid's when on, and
// `DI_ONE_PASS` for the pipeline that is the whole of DI on frames without reuse.
fn initial_constants(
    tiles: LightTileSettings,
    variant: TraceVariant,
    light_grid: bool,
    one_pass: bool,
) -> Vec<(&'static str, f64)> {
    let mut constants = tiles.reader_constants(variant.constants());
    if light_grid {
        constants.push(LIGHT_GRID_ON);
    }
    if one_pass {
        constants.push(ONE_PASS);
    }
    constants
}

/// Composes entry point `entry` of this crate for `backend` and builds its pipeline over
/// `layouts` (DI's and GI's passes).
pub(crate) fn pass_pipeline(
    gpu: &Gpu,
    backend: Backend,
    modules: &[(&str, &str)],
    layouts: &[Option<&wgpu::BindGroupLayout>],
    entry: &str,
    constants: &[(&str, f64)],
) -> Result<wgpu::ComputePipeline, GpuError> {
    let wgsl = compose(entry, backend, modules)?;
    gpu.compute_pipeline(
        &format!("solari_restir/{entry}"),
        &wgsl,
        layouts,
        ShaderChecks::BoundsOnly,
        constants,
    )
}

/// The bind group layouts every pass of this crate is built over: the scene (group 0), the
/// G-buffer reader (1), the pass's own group (2) and `fourth` (3: the light tiles' reader,
/// or GI's target). Owned here so the passes build their pipelines from one place.
pub(crate) struct PassLayouts {
    scene: wgpu::BindGroupLayout,
    gbuffer: wgpu::BindGroupLayout,
}

impl PassLayouts {
    pub(crate) fn new(gpu: &Gpu, backend: Backend) -> Self {
        Self {
            scene: GpuScene::layout_for(gpu, backend),
            gbuffer: GBuffer::reader_layout(gpu),
        }
    }

    /// Groups 0–3 with `own` as group 2 and `fourth` as group 3.
    pub(crate) fn with<'a>(
        &'a self,
        own: &'a wgpu::BindGroupLayout,
        fourth: &'a wgpu::BindGroupLayout,
    ) -> [Option<&'a wgpu::BindGroupLayout>; 4] {
        [
            Some(&self.scene),
            Some(&self.gbuffer),
            Some(own),
            Some(fourth),
        ]
    }
}

/// The layout of a pass's own group that also holds the world cache (GI and specular GI):
/// `bindings` first, the cache's entries after them.
pub(crate) fn layout_with_cache(
    gpu: &Gpu,
    bindings: &solari_scene::bindings::BufferGroup,
    label: &str,
) -> wgpu::BindGroupLayout {
    let mut entries = bindings.layout_entries(wgpu::ShaderStages::COMPUTE);
    entries.extend(solari_worldcache::WorldCache::layout_entries(
        wgpu::ShaderStages::COMPUTE,
    ));
    gpu.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &entries,
        })
}

/// Refuses to encode `pass` (built for `built` pixels) over a scene its pipelines were not
/// specialised for, or a G-buffer or frame of another size (GI's and specular GI's passes).
pub(crate) fn check_encode(
    pass: &str,
    variant: TraceVariant,
    built: (u32, u32),
    scene: &GpuScene,
    gbuffer: &dyn GBufferSource,
    frame: &FrameContext,
) -> Result<(), GpuError> {
    variant.check(scene)?;
    for (what, size) in [("G-buffer", gbuffer.size()), ("frame", frame.size)] {
        if size != built {
            return Err(GpuError::Validation(format!(
                "{pass}: built for {built:?} pixels, the {what} is {size:?}"
            )));
        }
    }
    Ok(())
}

/// Records one 2D compute dispatch with its four bind groups (DI's and GI's passes).
pub(crate) fn record(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    groups: &[&wgpu::BindGroup; 4],
    workgroups: [u32; 2],
) {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: None,
    });
    pass.set_pipeline(pipeline);
    for (i, g) in groups.iter().enumerate() {
        pass.set_bind_group(i as u32, *g, &[]);
    }
    pass.dispatch_workgroups(workgroups[0], workgroups[1], 1);
}

impl RestirDi {
    /// GPU memory ReSTIR DI holds, in bytes: the per-pixel reservoirs (initial, unless they
    /// live in a shared scratch buffer, and final), image and shadow data, parameters and
    /// the light-id translation table.
    pub fn memory_bytes(&self) -> u64 {
        let pixels = self.buffers.as_ref().map_or(0, |b| {
            let initial = if b.shared { 0 } else { b.initial.size() };
            let finals = if b.has_finals { b.finals.size() } else { 0 };
            b.output.size() + b.shadow.size() + initial + finals
        });
        pixels + self.params.size() + self.translation.size()
    }

    /// Builds the pipelines for scenes uploaded with `backend` and traced with `variant`, and
    /// allocates `width × height` buffers. `tiles` must be the settings of the
    /// [`LightTiles`] whose reader group [`RestirDi::encode`] gets.
    pub fn new(
        gpu: &Gpu,
        backend: Backend,
        variant: TraceVariant,
        width: u32,
        height: u32,
        settings: RestirDiSettings,
        tiles: LightTileSettings,
    ) -> Result<Self, GpuError> {
        settings.validate()?;
        let variant = variant.for_backend(backend);
        let own_layout = DI_BINDINGS.layout(gpu, "solari_restir/di");
        let lights_layout = LightTiles::reader_layout(gpu);
        let shared = PassLayouts::new(gpu, backend);
        let layouts = shared.with(&own_layout, &lights_layout);
        let modules = crate::modules();
        let pipeline = |entry: &str, constants: &[(&str, f64)]| {
            pass_pipeline(gpu, backend, &modules, &layouts, entry, constants)
        };
        let constants = tiles.reader_constants(variant.constants());
        let initial = pipeline(
            "restir_di_initial",
            &initial_constants(tiles, variant, settings.light_grid, false),
        )?;
        let spatial = pipeline("restir_di_spatial", &constants)?;
        let emission = pipeline("restir_di_emission", &[])?;
        let params = gpu.uniform_buffer("solari_restir/di_params", &GpuDiParams::zeroed());
        let translation = gpu.storage_buffer(
            "solari_restir/light_translation",
            bytemuck::bytes_of(&u32::MAX),
            wgpu::BufferUsages::empty(),
        )?;
        let mut di = Self {
            settings,
            tiles,
            variant,
            size: (0, 0),
            backend,
            initial,
            spatial,
            one_pass: None,
            single: false,
            emission,
            own_layout,
            params,
            buffers: None,
            translation,
            translation_count: 0,
            pending_translation: None,
            appeared: false,
            identity_for: None,
            frame: 0,
            history: false,
            reuse_skipped: false,
            indirect_only: false,
        };
        di.resize(gpu, width, height)?;
        if (!settings.temporal && !settings.spatial) || settings.reuse_light_threshold > 0 {
            di.build_one_pass(gpu)?;
        }
        Ok(di)
    }

    /// The traversal the pipelines were built for (after [`TraceVariant::for_backend`]).
    /// [`RestirDi::encode`] refuses a scene this variant cannot trace.
    pub fn variant(&self) -> TraceVariant {
        self.variant
    }

    /// The settings in use.
    pub fn settings(&self) -> RestirDiSettings {
        self.settings
    }

    // The one-pass pipeline, unless built already (layouts as `new` makes them). `new` builds
    // it when the settings make frames without reuse likely, so that the first such frame
    // does not wait for a pipeline; `prepare` builds it otherwise.
    fn build_one_pass(&mut self, gpu: &Gpu) -> Result<(), GpuError> {
        if self.one_pass.is_some() {
            return Ok(());
        }
        let lights_layout = LightTiles::reader_layout(gpu);
        let shared = PassLayouts::new(gpu, self.backend);
        let layouts = shared.with(&self.own_layout, &lights_layout);
        let constants = initial_constants(self.tiles, self.variant, self.settings.light_grid, true);
        let modules = crate::modules();
        let pipeline = pass_pipeline(
            gpu,
            self.backend,
            &modules,
            &layouts,
            "restir_di_initial",
            &constants,
        )?;
        self.one_pass = Some(pipeline);
        Ok(())
    }

    /// With `true`, from the next [`RestirDi::prepare`] on, the output holds no light: black
    /// where a surface is (alpha 1, as always) and on the background, with no shadow data,
    /// while the passes, their rays and their reservoirs run as before. What later passes
    /// add to the output (GI) is then the frame: a view of the indirect light alone, to
    /// measure GI against a reference of indirect light (`min_bounces: 2` in
    /// `solari_reference`). Off by default.
    pub fn set_indirect_only(&mut self, on: bool) {
        self.indirect_only = on;
    }

    /// Whether the last [`RestirDi::prepare`] skipped both reuse steps because the scene's
    /// lights had no more sampling elements than [`RestirDiSettings::reuse_light_threshold`].
    pub fn reuse_skipped(&self) -> bool {
        self.reuse_skipped
    }

    // The final reservoirs, for a frame with reuse: allocated (with history dropped, as
    // nothing holds last frame's) unless they are already.
    fn allocate_finals(&mut self, gpu: &Gpu) {
        let Some(b) = self.buffers.take() else {
            return;
        };
        if b.has_finals {
            self.buffers = Some(b);
            return;
        }
        let pixels = self.size.0 as u64 * self.size.1 as u64;
        let finals = pixel_buffer(gpu, FINALS_LABEL, pixels * size_of::<GpuReservoir>() as u64);
        let group = self.group_for(gpu, &finals, &b.initial, &b.output, &b.shadow);
        self.buffers = Some(PixelBuffers {
            finals,
            has_finals: true,
            group,
            ..b
        });
        self.history = false;
    }

    /// Changes the settings; history is kept (every knob is valid with any history), except
    /// that frames without reuse keep none, so settings that turn reuse back on start
    /// without it. Settings that turn reuse off on an instance built with it have the
    /// one-pass pipeline built by the next [`RestirDi::prepare`] (a one-time pipeline compile
    /// in that frame); settings that turn it on where it never ran have the final
    /// reservoirs allocated there.
    pub fn set_settings(&mut self, settings: RestirDiSettings) -> Result<(), GpuError> {
        settings.validate()?;
        self.settings = settings;
        Ok(())
    }

    /// Reallocates the per-pixel buffers (16 bytes of output, 4 of shadow data and a 20-byte
    /// initial reservoir per pixel, and once a frame reuses, 20 bytes of final reservoir:
    /// frames without reuse keep none); history restarts.
    pub fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        if (width, height) == self.size && self.buffers.is_some() {
            return Ok(());
        }
        let pixels = width as u64 * height as u64;
        if pixels == 0 {
            return Err(GpuError::Validation(format!(
                "ReSTIR DI image size {width}×{height} is empty"
            )));
        }
        let output_bytes = pixels * 16;
        let reservoir_bytes = pixels * size_of::<GpuReservoir>() as u64;
        gpu.check_storage_binding("ReSTIR DI output", output_bytes)?;
        // The reservoirs are the larger: checking the output alone let a size through whose
        // reservoir buffers could not be bound.
        gpu.check_storage_binding("ReSTIR DI reservoirs", reservoir_bytes)?;
        let buffer = |label: &str, size: u64| pixel_buffer(gpu, label, size);
        let finals = buffer(FINALS_LABEL, size_of::<GpuReservoir>() as u64);
        let initial = buffer("solari_restir/di_reservoirs_initial", reservoir_bytes);
        let output = buffer("solari_restir/di_output", output_bytes);
        let shadow = buffer("solari_restir/di_shadow", pixels * 4);
        let group = self.group_for(gpu, &finals, &initial, &output, &shadow);
        self.buffers = Some(PixelBuffers {
            output,
            shadow,
            finals,
            has_finals: false,
            initial,
            shared: false,
            group,
        });
        self.size = (width, height);
        self.history = false;
        Ok(())
    }

    /// Bytes of scratch [`RestirDi::use_scratch`] needs: the initial reservoirs, which live
    /// from the first dispatch of a frame to the second (20 bytes per pixel).
    pub fn scratch_bytes(&self) -> u64 {
        self.size.0 as u64 * self.size.1 as u64 * size_of::<GpuReservoir>() as u64
    }

    /// Keeps the initial reservoirs in `scratch` (at least [`RestirDi::scratch_bytes`], a
    /// storage buffer) instead of a buffer of its own, which is freed: other passes may use
    /// `scratch` outside DI's dispatches (see [`solari_scene::scratch`]). History is kept:
    /// it lives in the final reservoirs. [`RestirDi::resize`] allocates an own buffer again.
    pub fn use_scratch(&mut self, gpu: &Gpu, scratch: &wgpu::Buffer) -> Result<(), GpuError> {
        solari_scene::scratch::check("ReSTIR DI", scratch, self.scratch_bytes())?;
        let b = self.buffers.take().expect("resize allocates the buffers");
        let group = self.group_for(gpu, &b.finals, scratch, &b.output, &b.shadow);
        self.buffers = Some(PixelBuffers {
            initial: scratch.clone(),
            shared: true,
            group,
            ..b
        });
        Ok(())
    }

    fn group_for(
        &self,
        gpu: &Gpu,
        finals: &wgpu::Buffer,
        initial: &wgpu::Buffer,
        output: &wgpu::Buffer,
        shadow: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        DI_BINDINGS.bind(
            gpu,
            "solari_restir/di",
            &self.own_layout,
            &[
                ("params", &self.params),
                ("reservoirs_initial", initial),
                ("reservoirs_final", finals),
                ("di_output", output),
                ("light_translation", &self.translation),
                ("di_shadow", shadow),
            ],
        )
    }

    /// Sets the map from last frame's light indices to this frame's
    /// ([`solari_lights::LightList::translation_from`]) for the next frame. Call it when the
    /// light list changes; frames without a call assume unchanged lights.
    pub fn set_light_translation(&mut self, translation: Vec<u32>) {
        self.pending_translation = Some(translation);
    }

    // Uploads `table`'s first `entries` words as the translation and the rest (if any) as
    // the bitset of lights new this frame.
    fn upload_translation(
        &mut self,
        gpu: &Gpu,
        table: &[u32],
        entries: usize,
    ) -> Result<(), GpuError> {
        let needed = (table.len().max(1) * 4) as u64;
        if self.translation.size() < needed {
            self.translation = gpu.storage_buffer(
                "solari_restir/light_translation",
                bytemuck::cast_slice(table),
                wgpu::BufferUsages::empty(),
            )?;
            // The bind groups hold the old table: rebind them to the new one. The per-pixel
            // buffers stay, so the output buffer that other passes were bound to (GI adding
            // to it, the denoiser reading it) is still the one DI writes; reallocating it
            // here once left those passes writing to an orphaned buffer on any scene with
            // more than one light (their light was lost, bit for bit).
            if let Some(b) = self.buffers.take() {
                let group = self.group_for(gpu, &b.finals, &b.initial, &b.output, &b.shadow);
                self.buffers = Some(PixelBuffers { group, ..b });
            }
        } else if !table.is_empty() {
            gpu.queue
                .write_buffer(&self.translation, 0, bytemuck::cast_slice(table));
        }
        self.translation_count = entries as u32;
        Ok(())
    }

    /// Drops history: the next frame uses no temporal reuse (for camera cuts).
    pub fn reset(&mut self) {
        self.history = false;
    }

    /// Starts `frame` for the scene's uploaded `lights`: uploads the light translation (the
    /// identity unless [`RestirDi::set_light_translation`] gave one) and writes the
    /// parameters. `gbuffer` is the G-buffer this frame reads (its history decides whether
    /// temporal reuse may run); the lights' sampling elements decide whether
    /// [`RestirDiSettings::reuse_light_threshold`] skips reuse.
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        frame: &FrameContext,
        gbuffer: &dyn GBufferSource,
        lights: &GpuLights,
    ) -> Result<(), GpuError> {
        let light_count = lights.light_count;
        let gbuffer_history = gbuffer.history_valid();
        let frame = frame.index;
        match self.pending_translation.take() {
            Some(table) => {
                let appeared = appeared_lights(&table, light_count);
                self.appeared = appeared.iter().any(|w| *w != 0);
                let entries = table.len();
                let mut words = table;
                if self.appeared {
                    words.extend(appeared);
                }
                self.upload_translation(gpu, &words, entries)?;
                self.identity_for = None;
            }
            None if self.identity_for != Some(light_count) => {
                let table: Vec<u32> = (0..light_count).collect();
                self.upload_translation(gpu, &table, table.len())?;
                self.identity_for = Some(light_count);
                self.appeared = false;
            }
            None => {}
        }
        self.frame = frame;
        let s = self.settings;
        let skip = s.skips_reuse(lights.sampling_elements);
        if (s.temporal || s.spatial) && !skip {
            self.allocate_finals(gpu);
        }
        let history = self.history && gbuffer_history;
        if skip != self.reuse_skipped {
            log::info!(
                "ReSTIR DI: reuse {}: the lights have {} sampling elements (reuse_light_threshold {})",
                if skip { "skipped" } else { "resumed" },
                lights.sampling_elements,
                s.reuse_light_threshold
            );
            self.reuse_skipped = skip;
        }
        let (temporal, spatial) = (s.temporal && !skip, s.spatial && !skip);
        self.single = !temporal && !spatial;
        if self.single {
            self.build_one_pass(gpu)?;
        }
        let mut bits = flags::reuse(temporal, spatial, s.permutation_sampling, history);
        if s.initial_visibility {
            bits |= flags::INITIAL_VISIBILITY;
        }
        if self.appeared {
            bits |= flags::APPEARED;
        }
        if self.indirect_only {
            bits |= flags::NO_LIGHT_OUT;
        }
        let params = GpuDiParams {
            width: self.size.0,
            height: self.size.1,
            frame,
            initial_candidates: s.initial_candidates,
            tile_count: self.tiles.tiles,
            samples_per_tile: self.tiles.samples_per_tile,
            spatial_tries: s.spatial_tries,
            flags: bits,
            spatial_radius: s.spatial_radius,
            confidence_cap: s.confidence_cap,
            translation_count: self.translation_count,
            brdf_candidates: s.brdf_candidates,
        };
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        Ok(())
    }

    /// Records the frame's dispatches, each in a profiler scope named as in
    /// [`PASS_LABELS`] when `frame` carries a profiler, and returns which ran. With
    /// `light_count == 0` only the emission copy runs (and history is dropped); on a frame
    /// without reuse (as [`RestirDi::prepare`] set it) the initial pass alone, built to shade;
    /// otherwise initial + temporal, then spatial + shade. `lights` is
    /// [`LightTiles::reader_group`] for this frame's tiles; `gbuffer` is Solari's raster
    /// G-buffer or your own ([`solari_scene::gbuffer_input`]).
    ///
    /// Errors, recording nothing, when the pipelines were specialised for a scene shape that
    /// `scene` no longer has (for example one instance, and the scene has grown): they would
    /// trace instance 0 alone. Build a new `RestirDi` with [`TraceVariant::for_scene`]. Errors
    /// too when the G-buffer's or the frame's size is not this pass's.
    pub fn encode(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        scene: &GpuScene,
        gbuffer: &dyn GBufferSource,
        lights: &wgpu::BindGroup,
        light_count: u32,
    ) -> Result<Ran, GpuError> {
        self.variant.check(scene)?;
        solari_scene::gbuffer_input::check_size("ReSTIR DI", self.size, gbuffer)?;
        if frame.size != self.size {
            return Err(GpuError::Validation(format!(
                "ReSTIR DI: built for {:?} pixels, the frame is {:?}",
                self.size, frame.size
            )));
        }
        let buffers = self.buffers.as_ref().expect("resize allocates the buffers");
        let groups = [
            scene.bind_group(),
            gbuffer.bind_group()?,
            &buffers.group,
            lights,
        ];
        let workgroups = [self.size.0.div_ceil(8), self.size.1.div_ceil(8)];
        let mut ran = Ran::none();
        let mut run = |encoder: &mut wgpu::CommandEncoder, label: &'static str, pipeline| {
            frame.scope(label, encoder, &mut ran, |e| {
                record(e, label, pipeline, &groups, workgroups)
            })
        };
        if light_count == 0 {
            run(encoder, PASS_LABELS[2], &self.emission);
            self.history = false;
        } else if let (true, Some(one_pass)) = (self.single, &self.one_pass) {
            run(encoder, PASS_LABELS[0], one_pass);
            // It keeps no reservoirs: a later frame with reuse starts without history.
            self.history = false;
        } else {
            run(encoder, PASS_LABELS[0], &self.initial);
            run(encoder, PASS_LABELS[1], &self.spatial);
            self.history = true;
        }
        Ok(ran)
    }

    /// Shaded radiance, `width × height` `vec4<f32>` row by row from the top left: rgb is
    /// emission plus direct light, w is 1 where a surface was drawn and 0 on background.
    pub fn output(&self) -> &wgpu::Buffer {
        &self
            .buffers
            .as_ref()
            .expect("resize allocates the buffers")
            .output
    }

    /// What each pixel's final shadow ray did (one `u32` per pixel, row by row, holding two
    /// bfloat16: [`solari_scene::packing::unpack_bf16x2`], WGSL `unpack_bf16x2`): the
    /// luminance of the light it removed (0 where the sample is seen or there is none), and
    /// the width in world units of the penumbra its blocker casts at the pixel (the blocker's
    /// distance × the light's apparent diameter; 0 where nothing blocks). Each keeps f32's
    /// range and 0.4% of its precision, which is all a denoiser needs to tell noise from
    /// hard shadows (`solari_denoise::DenoiserInputs::shadow`); 4 bytes a pixel instead of
    /// 8.
    pub fn shadow(&self) -> &wgpu::Buffer {
        &self
            .buffers
            .as_ref()
            .expect("resize allocates the buffers")
            .shadow
    }

    /// This frame's final reservoirs ([`crate::GpuReservoir`] per pixel, row by row), which
    /// next frame reuses; layout for the non-finite detector: [`crate::reservoir_check`].
    /// `None` until a frame with reuse was prepared: frames without reuse keep no reservoirs
    /// (20 bytes a pixel saved; a renderer at 1080p whose light count turns reuse off saves
    /// 41 MB). Once allocated they stay, and frames without reuse leave them untouched.
    pub fn reservoirs(&self) -> Option<&wgpu::Buffer> {
        self.buffers
            .as_ref()
            .filter(|b| b.has_finals)
            .map(|b| &b.finals)
    }

    /// Image size in pixels.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }
}

/// One bit per light of this frame (`light_count` of them), set where no light of last
/// frame maps to it through `translation` (last frame's index → this frame's, as
/// [`solari_lights::LightList::translation_from`] gives): the lights switched on since.
pub fn appeared_lights(translation: &[u32], light_count: u32) -> Vec<u32> {
    let mut bits = vec![!0u32; light_count.div_ceil(32) as usize];
    if let Some(last) = bits.last_mut()
        && !light_count.is_multiple_of(32)
    {
        *last = (1u32 << (light_count % 32)) - 1;
    }
    for &now in translation {
        if now < light_count {
            bits[(now / 32) as usize] &= !(1u32 << (now % 32));
        }
    }
    bits
}

#[cfg(test)]
mod tests {
    use super::appeared_lights;

    #[test]
    fn appeared_lights_are_those_no_old_light_maps_to() {
        const GONE: u32 = u32::MAX;
        // Three old lights: the first gone, the others now 0 and 34; lights 0..40 now.
        let bits = appeared_lights(&[GONE, 0, 34], 40);
        assert_eq!(bits.len(), 2);
        assert_eq!(bits[0], !1u32, "all of 1..32 new, 0 old");
        assert_eq!(
            bits[1],
            0xff & !(1 << 2),
            "32..40 new but 34; nothing past 40"
        );
        // The identity: nothing new; out-of-range entries are ignored.
        assert!(appeared_lights(&[0, 1, 2, 99], 3).iter().all(|w| *w == 0));
        assert!(appeared_lights(&[], 0).is_empty());
        assert_eq!(appeared_lights(&[], 32), vec![!0u32]);
    }
}
