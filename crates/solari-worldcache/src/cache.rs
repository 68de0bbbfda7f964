//! The world cache's buffers, its upkeep passes and its pixel passes.

use crate::hash::CellGrid;
use crate::settings::{
    CONTROL_HEADER_BYTES, GpuCacheCell, GpuCacheParams, GpuNewSample, WorldCacheSettings, flags,
};
use bytemuck::Zeroable;
use solari_lights::{LightTileSettings, LightTiles};
use solari_scene::GpuError;
use solari_scene::bindings::{Buf, BufferGroup};
use solari_scene::gbuffer::GBuffer;
use solari_scene::gbuffer_input::GBufferSource;
use solari_scene::gpu::{Gpu, ShaderChecks};
use solari_scene::gpu_scene::{GpuScene, TraceVariant};
use solari_scene::pass::{FrameContext, Ran};
use solari_scene::shaders::{Backend, compose};

/// Profiler scope labels, in frame order: the four upkeep steps (the compaction's three
/// dispatches share one scope), then the pixel passes (cache-only GI, or the debug view).
pub const PASS_LABELS: [&str; 6] = [
    "world_cache_decay",
    "world_cache_compact",
    "world_cache_update",
    "world_cache_blend",
    "world_cache_gi",
    "world_cache_view",
];

/// First binding of the cache in bind group 2 (a consumer's own bindings go below it).
pub const FIRST_BINDING: u32 = 16;

/// The cache's bindings in group 2 (`world_cache.wesl`), by WGSL name.
pub const CACHE_BINDINGS: BufferGroup = BufferGroup::new(
    2,
    FIRST_BINDING,
    &[
        ("cache_params", Buf::Uniform),
        ("cache_checksums", Buf::ReadWrite),
        ("cache_life", Buf::ReadWrite),
        ("cache_cells", Buf::ReadWrite),
        ("cache_active", Buf::ReadWrite),
        ("cache_new_samples", Buf::ReadWrite),
        ("cache_control", Buf::ReadWrite),
    ],
);

/// Group 3 of the compaction's offsets pass: the indirect dispatch arguments.
pub const DISPATCH_BINDINGS: BufferGroup =
    BufferGroup::new(3, 0, &[("dispatch_args", Buf::ReadWrite)]);

/// Group 3 of the pixel passes (cache GI, the debug view): the image they add to.
pub const TARGET_BINDINGS: BufferGroup = BufferGroup::new(3, 0, &[("lit", Buf::ReadWrite)]);

/// Counters of the last frame, read back by [`WorldCache::read_stats`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CacheStats {
    /// Cells alive after the frame's decay (the cells the update passes walked).
    pub active_cells: u32,
    /// Lookups that found every probed slot taken by other cells and returned nothing.
    pub overflows: u32,
    /// Update rounds the GPU blended in the frame's upkeep ([`WorldCache::update_rounds`];
    /// 0 when no cell was alive to update).
    pub update_rounds: u32,
}

impl CacheStats {
    /// Bytes of the counters at the start of the control buffer (its whole header, so the
    /// copy and the mapping stay 8-byte aligned).
    pub const BYTES: u64 = 16;

    /// The counters from the first [`CacheStats::BYTES`] bytes read back.
    pub fn from_bytes(bytes: &[u8]) -> Self {
        let words: [u32; 4] = bytemuck::pod_read_unaligned(&bytes[..Self::BYTES as usize]);
        Self {
            active_cells: words[0],
            overflows: words[1],
            update_rounds: words[2],
        }
    }
}

/// The world cache: a fixed-size hash table of surface cells, each holding irradiance that a
/// few rays per frame keep up to date (see the crate docs). Its bindings live in group 2 at
/// bindings [`FIRST_BINDING`] and up.
pub struct WorldCache {
    settings: WorldCacheSettings,
    tiles: LightTileSettings,
    params: wgpu::Buffer,
    checksums: wgpu::Buffer,
    life: wgpu::Buffer,
    cells: wgpu::Buffer,
    active: wgpu::Buffer,
    new_samples: wgpu::Buffer,
    // Whether `new_samples` is shared scratch (`use_scratch`), not counted as the cache's.
    new_samples_shared: bool,
    control: wgpu::Buffer,
    dispatch: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    group: wgpu::BindGroup,
    dispatch_group: wgpu::BindGroup,
    target_layout: wgpu::BindGroupLayout,
    pipelines: Pipelines,
    // What the update pipeline was specialised for: checked against the scene at encode.
    variant: TraceVariant,
    size: (u32, u32),
    // Frames left in which the blend averages at most `light_change_samples`
    // (`follow_light_change`).
    short_history: u32,
    // Frames left that run `warm_up_rounds` update rounds (from a new or emptied table, or a
    // light change).
    warm_up_left: u32,
    // Update rounds this frame's `encode_update` records (set by `prepare`).
    rounds: u32,
}

struct Pipelines {
    decay: wgpu::ComputePipeline,
    count: wgpu::ComputePipeline,
    offsets: wgpu::ComputePipeline,
    compact: wgpu::ComputePipeline,
    update: wgpu::ComputePipeline,
    blend: wgpu::ComputePipeline,
    gi: wgpu::ComputePipeline,
    view: wgpu::ComputePipeline,
}

// The table's buffers at a capacity.
struct Table {
    checksums: wgpu::Buffer,
    life: wgpu::Buffer,
    cells: wgpu::Buffer,
    active: wgpu::Buffer,
    new_samples: wgpu::Buffer,
    control: wgpu::Buffer,
}

fn table(gpu: &Gpu, capacity: u32) -> Result<Table, GpuError> {
    let slots = capacity as u64;
    let buffer = |label: &str, size: u64| -> Result<wgpu::Buffer, GpuError> {
        gpu.check_storage_binding(&format!("world cache {label} ({capacity} slots)"), size)?;
        // Created zeroed: every slot empty, no life, no light.
        Ok(gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }))
    };
    Ok(Table {
        checksums: buffer("solari_worldcache/checksums", slots * 4)?,
        life: buffer("solari_worldcache/life", slots * 4)?,
        cells: buffer(
            "solari_worldcache/cells",
            slots * size_of::<GpuCacheCell>() as u64,
        )?,
        active: buffer("solari_worldcache/active", slots * 4)?,
        new_samples: buffer(
            "solari_worldcache/new_samples",
            slots * size_of::<GpuNewSample>() as u64,
        )?,
        control: buffer(
            "solari_worldcache/control",
            CONTROL_HEADER_BYTES + slots / 1024 * 4,
        )?,
    })
}

// Records one dispatch (direct or indirect) in its own compute pass.
fn record(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    groups: &[(u32, &wgpu::BindGroup)],
    size: Dispatch,
) {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: None,
    });
    pass.set_pipeline(pipeline);
    for (i, g) in groups {
        pass.set_bind_group(*i, *g, &[]);
    }
    match size {
        Dispatch::Direct(x, y) => pass.dispatch_workgroups(x, y, 1),
        Dispatch::Indirect(buffer) => pass.dispatch_workgroups_indirect(buffer, 0),
    }
}

#[derive(Clone, Copy)]
enum Dispatch<'a> {
    Direct(u32, u32),
    Indirect(&'a wgpu::Buffer),
}

impl WorldCache {
    /// Builds the passes for scenes uploaded with `backend` and traced with `variant`, and
    /// allocates an empty table. `tiles` must be the settings of the [`LightTiles`] whose
    /// reader group [`WorldCache::encode_update`] gets. Errors name a bad setting or a table
    /// over the device's buffer limit.
    pub fn new(
        gpu: &Gpu,
        backend: Backend,
        variant: TraceVariant,
        settings: WorldCacheSettings,
        tiles: LightTileSettings,
    ) -> Result<Self, GpuError> {
        settings.validate()?;
        let variant = variant.for_backend(backend);
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("solari_worldcache/cache"),
                entries: &Self::layout_entries(wgpu::ShaderStages::COMPUTE),
            });
        let dispatch_layout = DISPATCH_BINDINGS.layout(gpu, "solari_worldcache/dispatch");
        let target_layout = TARGET_BINDINGS.layout(gpu, "solari_worldcache/target");
        let scene_layout = GpuScene::layout_for(gpu, backend);
        let gbuffer_layout = GBuffer::reader_layout(gpu);
        let lights_layout = LightTiles::reader_layout(gpu);
        let modules = crate::modules();
        let pipeline = |entry: &str,
                        layouts: [Option<&wgpu::BindGroupLayout>; 4],
                        constants: &[(&str, f64)]|
         -> Result<_, GpuError> {
            let wgsl = compose(entry, backend, &modules)?;
            gpu.compute_pipeline(
                &format!("solari_worldcache/{entry}"),
                &wgsl,
                &layouts,
                ShaderChecks::BoundsOnly,
                constants,
            )
        };
        let own = [None, None, Some(&layout), None];
        let pipelines = Pipelines {
            decay: pipeline("world_cache_decay", own, &[])?,
            count: pipeline("world_cache_count", own, &[])?,
            offsets: pipeline(
                "world_cache_offsets",
                [None, None, Some(&layout), Some(&dispatch_layout)],
                &[],
            )?,
            compact: pipeline("world_cache_compact", own, &[])?,
            update: pipeline(
                "world_cache_update",
                [
                    Some(&scene_layout),
                    None,
                    Some(&layout),
                    Some(&lights_layout),
                ],
                &tiles.reader_constants(variant.constants()),
            )?,
            blend: pipeline("world_cache_blend", own, &[])?,
            gi: pipeline(
                "world_cache_gi",
                [
                    None,
                    Some(&gbuffer_layout),
                    Some(&layout),
                    Some(&target_layout),
                ],
                &[],
            )?,
            view: pipeline(
                "world_cache_view",
                [
                    None,
                    Some(&gbuffer_layout),
                    Some(&layout),
                    Some(&target_layout),
                ],
                &[],
            )?,
        };
        let params = gpu.uniform_buffer("solari_worldcache/params", &GpuCacheParams::zeroed());
        let dispatch = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solari_worldcache/dispatch"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
            mapped_at_creation: false,
        });
        let dispatch_group = DISPATCH_BINDINGS.bind(
            gpu,
            "solari_worldcache/dispatch",
            &dispatch_layout,
            &[("dispatch_args", &dispatch)],
        );
        let t = table(gpu, settings.capacity)?;
        let group = Self::group_for(gpu, &layout, &params, &t);
        Ok(Self {
            settings,
            tiles,
            params,
            checksums: t.checksums,
            life: t.life,
            cells: t.cells,
            active: t.active,
            new_samples: t.new_samples,
            new_samples_shared: false,
            control: t.control,
            dispatch,
            layout,
            group,
            dispatch_group,
            target_layout,
            pipelines,
            variant,
            size: (0, 0),
            short_history: 0,
            warm_up_left: settings.warm_up_frames,
            rounds: 1,
        })
    }

    fn group_for(
        gpu: &Gpu,
        layout: &wgpu::BindGroupLayout,
        params: &wgpu::Buffer,
        t: &Table,
    ) -> wgpu::BindGroup {
        let buffers = [
            params,
            &t.checksums,
            &t.life,
            &t.cells,
            &t.active,
            &t.new_samples,
            &t.control,
        ];
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("solari_worldcache/cache"),
            layout,
            entries: &Self::entries_of(buffers),
        })
    }

    fn entries_of(buffers: [&wgpu::Buffer; 7]) -> Vec<wgpu::BindGroupEntry<'_>> {
        let [params, checksums, life, cells, active, new_samples, control] = buffers;
        CACHE_BINDINGS.entries(&[
            ("cache_params", params),
            ("cache_checksums", checksums),
            ("cache_life", life),
            ("cache_cells", cells),
            ("cache_active", active),
            ("cache_new_samples", new_samples),
            ("cache_control", control),
        ])
    }

    /// Layout entries of the cache's bindings (group 2, bindings 16–22: the parameters
    /// uniform, then checksums, life, cells, active list, new samples, control), for a pass
    /// that reads the cache with `world_cache.wesl` and keeps its own bindings below 16.
    pub fn layout_entries(visibility: wgpu::ShaderStages) -> Vec<wgpu::BindGroupLayoutEntry> {
        CACHE_BINDINGS.layout_entries(visibility)
    }

    /// Bind group entries matching [`WorldCache::layout_entries`]. They stay valid until
    /// [`WorldCache::set_settings`] changes the capacity.
    pub fn bind_group_entries(&self) -> Vec<wgpu::BindGroupEntry<'_>> {
        Self::entries_of([
            &self.params,
            &self.checksums,
            &self.life,
            &self.cells,
            &self.active,
            &self.new_samples,
            &self.control,
        ])
    }

    /// The cell array ([`crate::GpuCacheCell`] per slot, `settings().capacity` slots; empty
    /// slots are zero), for the non-finite detector with [`crate::CELL_CHECK`].
    pub fn cells_buffer(&self) -> &wgpu::Buffer {
        &self.cells
    }

    /// The traversal the update pipeline was built for (after [`TraceVariant::for_backend`]).
    /// [`WorldCache::encode_update`] refuses a scene this variant cannot trace.
    pub fn variant(&self) -> TraceVariant {
        self.variant
    }

    /// The settings in use.
    pub fn settings(&self) -> WorldCacheSettings {
        self.settings
    }

    /// Changes the settings. A new capacity reallocates (and so empties) the table; other
    /// knobs keep the cached light.
    pub fn set_settings(
        &mut self,
        gpu: &Gpu,
        settings: WorldCacheSettings,
    ) -> Result<(), GpuError> {
        settings.validate()?;
        if settings.capacity != self.settings.capacity {
            let t = table(gpu, settings.capacity)?;
            self.group = Self::group_for(gpu, &self.layout, &self.params, &t);
            self.checksums = t.checksums;
            self.life = t.life;
            self.cells = t.cells;
            self.active = t.active;
            self.new_samples = t.new_samples;
            self.new_samples_shared = false;
            self.control = t.control;
            self.warm_up_left = settings.warm_up_frames;
        }
        self.settings = settings;
        Ok(())
    }

    /// Bytes of scratch [`WorldCache::use_scratch`] needs: the new samples (32 bytes a slot,
    /// 16 MiB at the default capacity), which live from the update pass to the blend pass.
    pub fn scratch_bytes(&self) -> u64 {
        self.settings.capacity as u64 * size_of::<crate::GpuNewSample>() as u64
    }

    /// Keeps the new samples in `scratch` ([`solari_scene::scratch`], at least
    /// [`WorldCache::scratch_bytes`]) instead of their own buffer, which is freed. The update
    /// pass writes a sample for every cell it walks and the blend pass, the next dispatch,
    /// reads exactly those, so passes recorded outside [`WorldCache::encode`] may use the
    /// scratch for anything. Rebind the passes built over [`WorldCache::bind_group_entries`]
    /// afterwards. A new capacity ([`WorldCache::set_settings`]) brings back an own buffer.
    pub fn use_scratch(&mut self, gpu: &Gpu, scratch: &wgpu::Buffer) -> Result<(), GpuError> {
        solari_scene::scratch::check("world cache", scratch, self.scratch_bytes())?;
        self.new_samples = scratch.clone();
        self.new_samples_shared = true;
        self.group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("solari_worldcache/cache"),
            layout: &self.layout,
            entries: &self.bind_group_entries(),
        });
        Ok(())
    }

    /// Empties the table (every cell dies; light starts again from zero, with
    /// [`WorldCacheSettings::warm_up_rounds`] for the next
    /// [`WorldCacheSettings::warm_up_frames`] frames).
    pub fn clear(&mut self, gpu: &Gpu) {
        self.warm_up_left = self.settings.warm_up_frames;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        for b in [&self.checksums, &self.life, &self.cells, &self.control] {
            encoder.clear_buffer(b, 0, None);
        }
        gpu.queue.submit([encoder.finish()]);
    }

    /// GPU memory the cache holds, in bytes ([`WorldCacheSettings::memory_bytes`], less the
    /// new samples when they are in shared scratch).
    pub fn memory_bytes(&self) -> u64 {
        let shared = if self.new_samples_shared {
            self.scratch_bytes()
        } else {
            0
        };
        self.settings.memory_bytes() - shared
    }

    /// The bind group a consumer's pipeline can use at group 2 when it needs nothing else
    /// there (its layout is [`WorldCache::layout_entries`] alone).
    pub fn bind_group(&self) -> &wgpu::BindGroup {
        &self.group
    }

    /// Its layout.
    pub fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// A group-3 bind group for the pixel passes around `target`: `width × height`
    /// `vec4<f32>` (row by row from the top left, the layout of ReSTIR DI's output).
    pub fn target_group(&self, gpu: &Gpu, target: &wgpu::Buffer) -> wgpu::BindGroup {
        TARGET_BINDINGS.bind(
            gpu,
            "solari_worldcache/target",
            &self.target_layout,
            &[("lit", target)],
        )
    }

    /// Writes the frame's parameters: from `frame` the camera position (levels of detail
    /// follow it), the frame index and the pixel passes' image size; and the light count (0:
    /// no direct-light samples).
    pub fn prepare(&mut self, gpu: &Gpu, frame: &FrameContext, light_count: u32) {
        let (view_position, size) = (frame.eye(), frame.size);
        let frame = frame.index;
        let s = self.settings;
        let grid = CellGrid::new(s.cell_size, s.lod_distance, s.capacity);
        let mut bits = 0;
        if s.jitter {
            bits |= flags::JITTER;
        }
        if s.leak_rule {
            bits |= flags::LEAK_RULE;
        }
        if s.soft_lod {
            bits |= flags::SOFT_LOD;
        }
        self.rounds = 1;
        if self.warm_up_left > 0 {
            self.warm_up_left -= 1;
            self.rounds = s.warm_up_rounds;
        }
        let mut max_temporal_samples = s.max_temporal_samples;
        if self.short_history > 0 {
            self.short_history -= 1;
            max_temporal_samples = max_temporal_samples.min(s.light_change_samples);
        }
        let params = GpuCacheParams {
            view_position,
            frame,
            cell_size: grid.cell_size,
            inv_cell_size: grid.inv_cell_size,
            inv_lod_distance: grid.inv_lod_distance,
            mask: grid.mask,
            lifetime: s.lifetime,
            max_search_steps: s.max_search_steps,
            flags: bits,
            update_budget: s.update_budget,
            max_temporal_samples,
            max_ray_distance: if s.max_ray_distance.is_finite() {
                s.max_ray_distance
            } else {
                f32::MAX
            },
            direct_candidates: s.direct_candidates,
            light_count,
            tile_count: self.tiles.tiles,
            samples_per_tile: self.tiles.samples_per_tile,
            width: size.0,
            height: size.1,
            warm_up_exponent: s.warm_up_exponent,
            _pad: [0; 3],
        };
        self.size = size;
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
    }

    /// Update rounds the frame last prepared records: [`WorldCacheSettings::warm_up_rounds`]
    /// in the [`WorldCacheSettings::warm_up_frames`] frames after the table was made or
    /// emptied and in the [`WorldCacheSettings::light_change_frames`] frames after
    /// [`WorldCache::follow_light_change`], 1 otherwise.
    pub fn update_rounds(&self) -> u32 {
        self.rounds
    }

    /// Whether frames of [`WorldCacheSettings::warm_up_rounds`] are still ahead (the next
    /// [`WorldCache::prepare`] starts one).
    pub fn warming_up(&self) -> bool {
        self.warm_up_left > 0
    }

    /// Tells the cache that the lights changed (switched, added, removed, rescaled): for the
    /// next [`WorldCacheSettings::light_change_frames`] frames (from the next
    /// [`WorldCache::prepare`]) each cell averages at most
    /// [`WorldCacheSettings::light_change_samples`] samples, so the cached light follows
    /// within a few frames instead of fading over dozens; the counts then grow back. For the
    /// same frames the upkeep runs [`WorldCacheSettings::warm_up_rounds`] update rounds, so
    /// the change crosses several bounces between cells a frame (a bulb switched off on
    /// lavapipe's Cornell box: the image's mean RMSE over the 16 frames after the switch
    /// 1.01-1.25 with one round, 0.24-0.37 with four; `benches/RESULTS.md`, "Update rounds
    /// for a cold cache"). The cells are noisier for those frames, and the rounds cost the
    /// update and blend passes again. `RealtimeRenderer` calls it from `set_lights` when
    /// enough of the lights' power changed.
    pub fn follow_light_change(&mut self) {
        self.short_history = self.settings.light_change_frames;
        self.warm_up_left = self.warm_up_left.max(self.settings.light_change_frames);
    }

    /// Records decay and compaction: cells lose a frame of life (dead ones free their
    /// slots) and the live ones are listed densely for the update passes.
    pub fn encode_maintain(&self, encoder: &mut wgpu::CommandEncoder, frame: &FrameContext) -> Ran {
        let mut ran = Ran::none();
        let own = [(2, &self.group)];
        let slots = self.settings.capacity;
        let p = &self.pipelines;
        frame.scope(PASS_LABELS[0], encoder, &mut ran, |e| {
            record(
                e,
                PASS_LABELS[0],
                &p.decay,
                &own,
                Dispatch::Direct(slots / 256, 1),
            )
        });
        frame.scope(PASS_LABELS[1], encoder, &mut ran, |e| {
            let blocks = slots / 1024;
            record(
                e,
                "world_cache_count",
                &p.count,
                &own,
                Dispatch::Direct(blocks, 1),
            );
            record(
                e,
                "world_cache_offsets",
                &p.offsets,
                &[(2, &self.group), (3, &self.dispatch_group)],
                Dispatch::Direct(1, 1),
            );
            record(
                e,
                "world_cache_write",
                &p.compact,
                &own,
                Dispatch::Direct(blocks, 1),
            );
        });
        ran
    }

    /// Records the update (a new sample per live cell, stochastic past the budget) and the
    /// blend, both sized on the GPU by the compaction, [`WorldCache::update_rounds`] times
    /// (each round's dispatches in scopes of the same labels). `lights` is the light tiles'
    /// reader group ([`LightTiles::reader_group`]) for this frame.
    ///
    /// Errors, recording nothing, when the update pipeline was specialised for a scene shape
    /// that `scene` no longer has (for example one instance, and the scene has grown): it
    /// would trace instance 0 alone. Build a new cache with [`TraceVariant::for_scene`].
    pub fn encode_update(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        scene: &GpuScene,
        lights: &wgpu::BindGroup,
    ) -> Result<Ran, GpuError> {
        self.variant.check(scene)?;
        let mut ran = Ran::none();
        let p = &self.pipelines;
        let size = Dispatch::Indirect(&self.dispatch);
        // Each round reads what the last one blended; the blend counts the rounds on the
        // GPU (`CacheControl::round`), which salts the next round's random numbers.
        for _ in 0..self.rounds {
            frame.scope(PASS_LABELS[2], encoder, &mut ran, |e| {
                record(
                    e,
                    PASS_LABELS[2],
                    &p.update,
                    &[(0, scene.bind_group()), (2, &self.group), (3, lights)],
                    size,
                )
            });
            frame.scope(PASS_LABELS[3], encoder, &mut ran, |e| {
                record(e, PASS_LABELS[3], &p.blend, &[(2, &self.group)], size)
            });
        }
        Ok(ran)
    }

    /// Records the whole upkeep: [`WorldCache::encode_maintain`] then
    /// [`WorldCache::encode_update`], refusing (before recording anything) a scene the
    /// update pipeline cannot trace. Returns the four upkeep labels.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        scene: &GpuScene,
        lights: &wgpu::BindGroup,
    ) -> Result<Ran, GpuError> {
        self.variant.check(scene)?;
        let mut ran = self.encode_maintain(encoder, frame);
        ran.extend(self.encode_update(encoder, frame, scene, lights)?);
        Ok(ran)
    }

    /// Records cache-only GI: every G-buffer pixel adds its diffuse albedo × the cache's
    /// indirect irradiance to `target` ([`WorldCache::target_group`]), renewing the cells it
    /// reads. Run it after the upkeep and after whatever wrote the direct light. `gbuffer` is
    /// Solari's raster G-buffer or your own ([`solari_scene::gbuffer_input`]); errors,
    /// recording nothing, when its size is not the cache's.
    pub fn encode_gi(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        gbuffer: &dyn GBufferSource,
        target: &wgpu::BindGroup,
    ) -> Result<Ran, GpuError> {
        self.pixels(encoder, frame, 4, &self.pipelines.gi, gbuffer, target)
    }

    /// Records the debug view: every pixel of `target` shows its cell's irradiance, tinted
    /// per cell (background black, magenta where the table was full).
    /// Errors as [`WorldCache::encode_gi`] does.
    pub fn encode_view(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        gbuffer: &dyn GBufferSource,
        target: &wgpu::BindGroup,
    ) -> Result<Ran, GpuError> {
        self.pixels(encoder, frame, 5, &self.pipelines.view, gbuffer, target)
    }

    fn pixels(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        label: usize,
        pipeline: &wgpu::ComputePipeline,
        gbuffer: &dyn GBufferSource,
        target: &wgpu::BindGroup,
    ) -> Result<Ran, GpuError> {
        solari_scene::gbuffer_input::check_size("world cache", self.size, gbuffer)?;
        let groups = [(1, gbuffer.bind_group()?), (2, &self.group), (3, target)];
        let size = Dispatch::Direct(self.size.0.div_ceil(8), self.size.1.div_ceil(8));
        let mut ran = Ran::none();
        frame.scope(PASS_LABELS[label], encoder, &mut ran, |e| {
            record(e, PASS_LABELS[label], pipeline, &groups, size)
        });
        Ok(ran)
    }

    /// The last frame's counters. Blocks until the GPU is done.
    pub fn read_stats(&self, gpu: &Gpu) -> Result<CacheStats, GpuError> {
        let bytes = gpu.read_buffer(&self.control, CacheStats::BYTES)?;
        Ok(CacheStats::from_bytes(&bytes))
    }

    /// Records a copy of this frame's counters into `readback` (at least
    /// [`CacheStats::BYTES`], `COPY_DST`), to read later with [`CacheStats::from_bytes`]
    /// without waiting for frames submitted since.
    pub fn copy_stats(&self, encoder: &mut wgpu::CommandEncoder, readback: &wgpu::Buffer) {
        encoder.copy_buffer_to_buffer(&self.control, 0, readback, 0, CacheStats::BYTES);
    }

    /// Every slot: (checksum, remaining life, contents). Blocks until the GPU is done; for
    /// tests, tools and saving a warm cache.
    pub fn read_cells(&self, gpu: &Gpu) -> Result<Vec<(u32, u32, GpuCacheCell)>, GpuError> {
        let n = self.settings.capacity as u64;
        let checksums = gpu.read_buffer(&self.checksums, n * 4)?;
        let life = gpu.read_buffer(&self.life, n * 4)?;
        let cells = gpu.read_buffer(&self.cells, n * size_of::<GpuCacheCell>() as u64)?;
        let checksums: &[u32] = bytemuck::cast_slice(&checksums);
        let life: &[u32] = bytemuck::cast_slice(&life);
        let cells: &[GpuCacheCell] = bytemuck::cast_slice(&cells);
        Ok((0..n as usize)
            .map(|i| (checksums[i], life[i], cells[i]))
            .collect())
    }

    /// Replaces every slot's contents (as [`WorldCache::read_cells`] returns them); the
    /// slice must have one entry per slot.
    pub fn write_cells(
        &self,
        gpu: &Gpu,
        slots: &[(u32, u32, GpuCacheCell)],
    ) -> Result<(), GpuError> {
        if slots.len() != self.settings.capacity as usize {
            return Err(GpuError::Validation(format!(
                "world cache: {} slots given for a table of {}",
                slots.len(),
                self.settings.capacity
            )));
        }
        let checksums: Vec<u32> = slots.iter().map(|s| s.0).collect();
        let life: Vec<u32> = slots.iter().map(|s| s.1).collect();
        let cells: Vec<GpuCacheCell> = slots.iter().map(|s| s.2).collect();
        gpu.queue
            .write_buffer(&self.checksums, 0, bytemuck::cast_slice(&checksums));
        gpu.queue
            .write_buffer(&self.life, 0, bytemuck::cast_slice(&life));
        gpu.queue
            .write_buffer(&self.cells, 0, bytemuck::cast_slice(&cells));
        Ok(())
    }

    /// The dense list of live slots the last compaction wrote. Blocks until the GPU is done.
    pub fn read_active(&self, gpu: &Gpu) -> Result<Vec<u32>, GpuError> {
        let count = self.read_stats(gpu)?.active_cells as u64;
        if count == 0 {
            return Ok(Vec::new());
        }
        let bytes = gpu.read_buffer(&self.active, count * 4)?;
        Ok(bytemuck::cast_slice(&bytes).to_vec())
    }
}
