//! Light tiles: presampled, resolved light samples in cache-friendly blocks (Wyman & Panteleev
//! 2021, "Rearchitecting Spatiotemporal Resampling for Production", section 5). A pass fills
//! `tiles × samples_per_tile` samples once per frame; ReSTIR DI's initial sampling then reads
//! candidates from one tile per workgroup instead of walking the light list per pixel.
//!
//! ## Record format and its error
//!
//! A [`PackedLightSample`] is 32 bytes, two aligned 16-byte loads: position (or direction) and
//! radiance in full f32, 1/pdf in f32, and the emitter normal octahedrally packed to 14 bits
//! per axis beside four flags. Solari packs into 24 bytes with rgb9e5 radiance and lost energy
//! until it switched to a log encoding; here the radiance is exact, so the only packing error is
//! the normal's (≤ 2.7e-4 rad), which moves the cosine at the emitter. Measured on the shared
//! scenes' tiles: far below the 0.1% of mean contribution allowed (`tests/light_tiles.rs`).
//! The 8 bytes over Solari's record are the price of that exactness.

use crate::gpu::GpuLights;
use crate::sample::ResolvedLightSample;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use solari_scene::GpuError;
use solari_scene::bindings::{Buf, BufferGroup};
use solari_scene::gpu::{Gpu, ShaderChecks};
use solari_scene::packing::{pack_unit_vector, unpack_unit_vector};
use solari_scene::pass::{FrameContext, Ran};
use solari_scene::shaders::{Backend, compose};

/// Bind group 2 of the presampling shader (`presample_light_tiles.wesl`), by WGSL name.
pub const PRESAMPLE_BINDINGS: BufferGroup = BufferGroup::new(
    2,
    0,
    &[
        ("params", Buf::Uniform),
        ("out_samples", Buf::ReadWrite),
        ("out_ids", Buf::ReadWrite),
    ],
);

/// Bindings 4–5 of group 3 for tile readers (`light_tiles.wesl`), after the light list's
/// [`crate::LIGHT_BINDINGS`].
pub const TILE_BINDINGS: BufferGroup = BufferGroup::new(
    3,
    4,
    &[
        ("light_tile_samples", Buf::Read),
        ("light_tile_ids", Buf::Read),
    ],
);

/// The pass's label (dispatch, profiler scope and report name).
pub const PASS_LABELS: [&str; 1] = ["light_tiles"];

/// How many tiles and samples the presampling pass produces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightTileSettings {
    /// Number of tiles (Solari: 128). More tiles decorrelate neighbouring workgroups.
    pub tiles: u32,
    /// Samples per tile (Solari: 1024). More samples per tile give each workgroup more
    /// distinct candidates; the pass costs one light resolve per sample.
    pub samples_per_tile: u32,
    /// Whether point and spot lights are rendered (default true). False compiles their code
    /// out of the presampling pass and of every pass built with these settings (ReSTIR DI,
    /// the world cache, specular GI), which cost 3.8% of `interior`'s frame on the H200 in a
    /// scene that has none; such passes ignore point and spot lights. `RealtimeRenderer`
    /// turns it off by itself for scenes without them.
    pub point_lights: bool,
    /// Whether the passes that shade with light samples apply emitters' emissive textures
    /// (default true). False compiles that code out of them (it cost `interior` 1.8% on the
    /// H200 without any textured emitter), and they then shade with the emissive factor.
    /// `RealtimeRenderer` turns it off by itself for scenes without textured emitters.
    pub emissive_textures: bool,
    /// Whether the environment map is sampled as a light (default true). False compiles
    /// its code out of the presampling pass and every pass built with these settings,
    /// which then ignore it as a light: only for scenes whose environment is not a light
    /// (`Scene::environment_is_light`), where `RealtimeRenderer` turns it off by itself.
    /// With a map, GI leaves the sky to light sampling, so its light would be lost: the
    /// renderer refuses that combination.
    pub environment: bool,
}

impl Default for LightTileSettings {
    fn default() -> Self {
        Self {
            tiles: 128,
            samples_per_tile: 1024,
            point_lights: true,
            emissive_textures: true,
            environment: true,
        }
    }
}

/// Pipeline-overridable constant `LIGHTS_POINT` (`@id(7110)` in `light_sampling.wesl`).
const POINT_LIGHTS_OFF: &[(&str, f64)] = &[("7110", 0.0)];
/// Pipeline-overridable constant `LIGHTS_TEXTURED` (`@id(7111)` in `light_emission.wesl`).
const EMISSIVE_TEXTURES_OFF: &[(&str, f64)] = &[("7111", 0.0)];
/// Pipeline-overridable constant `LIGHTS_ENVIRONMENT` (`@id(7112)` in `light_sampling.wesl`).
const ENVIRONMENT_OFF: &[(&str, f64)] = &[("7112", 0.0)];

impl LightTileSettings {
    /// The pipeline constants that specialise a shader importing `light_sampling` for these
    /// settings, appended to `base` (e.g. a trace variant's).
    pub fn constants<'a>(&self, base: &[(&'a str, f64)]) -> Vec<(&'a str, f64)> {
        let mut c = base.to_vec();
        if !self.point_lights {
            c.extend_from_slice(POINT_LIGHTS_OFF);
        }
        if !self.environment {
            c.extend_from_slice(ENVIRONMENT_OFF);
        }
        c
    }

    /// The same for a pass that shades with light samples and imports `light_emission`
    /// (ReSTIR DI, the world cache, specular GI).
    pub fn reader_constants<'a>(&self, base: &[(&'a str, f64)]) -> Vec<(&'a str, f64)> {
        let mut c = self.constants(base);
        if !self.emissive_textures {
            c.extend_from_slice(EMISSIVE_TEXTURES_OFF);
        }
        c
    }

    /// Total samples.
    pub fn sample_count(&self) -> u64 {
        self.tiles as u64 * self.samples_per_tile as u64
    }
}

/// Bits per axis of the packed emitter normal.
pub const PACKED_NORMAL_BITS: u32 = 14;
// Directional records have no normal: bit 27 marks the environment's.
const FLAG_ENVIRONMENT: u32 = 1 << 27;
const FLAG_TEXTURED: u32 = 1 << 28;
const FLAG_PUNCTUAL: u32 = 1 << 29;
const FLAG_SIDED_OR_DELTA: u32 = 1 << 30;
const FLAG_DIRECTIONAL: u32 = 1 << 31;

/// One light-tile record. WGSL twin: `PackedLightSample` in `light_packing.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PackedLightSample {
    /// Emissive: world point. Directional: unit direction towards the light.
    pub position: [f32; 3],
    /// Octahedral normal in bits 0..28 (directional: bit 27 marks the environment); bit 28
    /// emissive texture; bit 29 point or spot light;
    /// bit 30 double-sided (emissive) or delta (directional, point); bit 31 directional.
    pub normal_flags: u32,
    /// Emitted radiance (irradiance for a delta light).
    pub radiance: [f32; 3],
    /// 1 / pdf (see [`ResolvedLightSample::inverse_pdf`]); 0 for no sample.
    pub inverse_pdf: f32,
}

const _: () = assert!(size_of::<PackedLightSample>() == 32);

/// Which words of a [`PackedLightSample`] the non-finite detector checks: the position (any
/// sign), and the radiance and inverse pdf (non-negative).
pub const SAMPLE_CHECK: solari_scene::finite_check::RecordLayout =
    solari_scene::finite_check::RecordLayout {
        stride_words: 8,
        float_mask: 0b1110_1111,
        non_negative_mask: 0b1110_0000,
        upper_mask: 0,
        upper_bound: 0.0,
    };

impl PackedLightSample {
    /// Packs a resolved sample (the GPU does the same, bit for bit).
    pub fn pack(r: &ResolvedLightSample) -> Self {
        let flags = if r.directional {
            FLAG_DIRECTIONAL
                | if r.delta { FLAG_SIDED_OR_DELTA } else { 0 }
                | if r.environment { FLAG_ENVIRONMENT } else { 0 }
        } else if r.punctual {
            FLAG_PUNCTUAL
                | if r.delta {
                    FLAG_SIDED_OR_DELTA
                } else {
                    pack_unit_vector(r.normal, PACKED_NORMAL_BITS)
                }
        } else {
            pack_unit_vector(r.normal, PACKED_NORMAL_BITS)
                | if r.double_sided {
                    FLAG_SIDED_OR_DELTA
                } else {
                    0
                }
                | if r.textured { FLAG_TEXTURED } else { 0 }
        };
        Self {
            position: r.position.into(),
            normal_flags: flags,
            radiance: r.radiance.into(),
            inverse_pdf: r.inverse_pdf,
        }
    }

    /// The resolved sample back; `None` for an empty record.
    pub fn unpack(&self) -> Option<ResolvedLightSample> {
        if !(self.inverse_pdf > 0.0) {
            return None;
        }
        let directional = self.normal_flags & FLAG_DIRECTIONAL != 0;
        let punctual = self.normal_flags & FLAG_PUNCTUAL != 0;
        let sided_or_delta = self.normal_flags & FLAG_SIDED_OR_DELTA != 0;
        let delta = sided_or_delta && (directional || punctual);
        Some(ResolvedLightSample {
            position: self.position.into(),
            normal: if directional || delta {
                Vec3::ZERO
            } else {
                unpack_unit_vector(self.normal_flags, PACKED_NORMAL_BITS)
            },
            radiance: self.radiance.into(),
            inverse_pdf: self.inverse_pdf,
            directional,
            double_sided: sided_or_delta && !delta,
            delta,
            punctual,
            textured: self.normal_flags & FLAG_TEXTURED != 0 && !(directional || punctual),
            environment: directional && self.normal_flags & FLAG_ENVIRONMENT != 0,
        })
    }
}

/// WGSL twin: `TileParams` in `presample_light_tiles.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuTileParams {
    /// Frame index: a new random stream each frame.
    pub frame: u32,
    /// tiles × samples_per_tile.
    pub sample_count: u32,
    /// Padding.
    pub _pad: [u32; 2],
}

const _: () = assert!(size_of::<GpuTileParams>() == 16);

/// Salt of the presampling pass's random stream (`LIGHT_TILE_SALT` in the shader).
pub const LIGHT_TILE_SALT: u32 = 0x711e5;

/// The light-tile presampling pass and the tiles it fills.
pub struct LightTiles {
    settings: LightTileSettings,
    pipeline: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    samples: wgpu::Buffer,
    ids: wgpu::Buffer,
    out_group: wgpu::BindGroup,
    empty: wgpu::BindGroup,
    reader_layout: wgpu::BindGroupLayout,
}

impl LightTiles {
    /// GPU memory the tiles hold, in bytes.
    pub fn memory_bytes(&self) -> u64 {
        self.params.size() + self.samples.size() + self.ids.size()
    }

    /// Builds the pass and allocates the tiles. Errors on zero-sized settings or tiles over
    /// the device's storage-binding or dispatch limits.
    pub fn new(gpu: &Gpu, settings: LightTileSettings) -> Result<Self, GpuError> {
        let count = settings.sample_count();
        if count == 0 {
            return Err(GpuError::Validation(format!(
                "light tiles need at least one tile and one sample per tile (got {} × {})",
                settings.tiles, settings.samples_per_tile
            )));
        }
        let limits = gpu.device.limits();
        let max_samples = limits.max_compute_workgroups_per_dimension as u64 * 64;
        if count > max_samples {
            return Err(GpuError::OverLimit {
                what: "light tile samples (one dispatch)".into(),
                needed: count,
                limit: max_samples,
            });
        }
        let bytes = count * size_of::<PackedLightSample>() as u64;
        gpu.check_storage_binding("light tile samples (bytes)", bytes)?;
        let storage = |label: &str, size: u64| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let samples = storage("solari_lights/tile_samples", bytes);
        let ids = storage(
            "solari_lights/tile_ids",
            count * size_of::<crate::LightSampleId>() as u64,
        );
        let params = gpu.uniform_buffer("solari_lights/tile_params", &GpuTileParams::zeroed());
        let out_layout = PRESAMPLE_BINDINGS.layout(gpu, "solari_lights/presample");
        let out_group = PRESAMPLE_BINDINGS.bind(
            gpu,
            "solari_lights/presample",
            &out_layout,
            &[
                ("params", &params),
                ("out_samples", &samples),
                ("out_ids", &ids),
            ],
        );
        let (empty_layout, empty) = gpu.empty_group();
        let wgsl = compose(
            "presample_light_tiles",
            Backend::Software,
            &[crate::MODULES, ENTRY_POINTS].concat(),
        )?;
        let lights_layout = GpuLights::layout(gpu);
        let pipeline = gpu.compute_pipeline(
            "solari_lights/presample",
            &wgsl,
            &[
                Some(&empty_layout),
                Some(&empty_layout),
                Some(&out_layout),
                Some(&lights_layout),
            ],
            ShaderChecks::BoundsOnly,
            &settings.constants(&[]),
        )?;
        Ok(Self {
            settings,
            pipeline,
            params,
            samples,
            ids,
            out_group,
            empty,
            reader_layout: Self::reader_layout(gpu),
        })
    }

    /// The settings the tiles were built with.
    pub fn settings(&self) -> LightTileSettings {
        self.settings
    }

    /// Writes this frame's parameters (a new random stream per frame index).
    pub fn prepare(&self, gpu: &Gpu, frame: &FrameContext) {
        let params = GpuTileParams {
            frame: frame.index,
            sample_count: self.settings.sample_count() as u32,
            _pad: [0; 2],
        };
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
    }

    /// Records the presampling dispatch (profiler scope [`PASS_LABELS`]`[0]`). Returns what
    /// ran: nothing for a scene without lights, which has nothing to sample (every consumer
    /// of the tiles is skipped too).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        lights: &GpuLights,
    ) -> Ran {
        let mut ran = Ran::none();
        if lights.light_count == 0 {
            return ran;
        }
        frame.scope(PASS_LABELS[0], encoder, &mut ran, |e| {
            let mut pass = e.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(PASS_LABELS[0]),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.empty, &[]);
            pass.set_bind_group(1, &self.empty, &[]);
            pass.set_bind_group(2, &self.out_group, &[]);
            pass.set_bind_group(3, &lights.bind_group, &[]);
            pass.dispatch_workgroups((self.settings.sample_count() as u32).div_ceil(64), 1, 1);
        });
        ran
    }

    /// The layout of bind group 3 for passes that read tiles: the light list (bindings 0–3)
    /// plus the tile samples (4) and their identities (5), for `light_tiles.wesl`.
    pub fn reader_layout(gpu: &Gpu) -> wgpu::BindGroupLayout {
        let entries = Self::reader_layout_entries();
        gpu.device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("solari_lights/lights_and_tiles"),
                entries: &entries,
            })
    }

    /// The entries of [`LightTiles::reader_layout`] (bindings 0–8), for a pass whose group 3
    /// holds bindings of its own beside them.
    pub fn reader_layout_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
        let stages = wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT;
        let mut entries = GpuLights::layout_entries(stages);
        entries.extend(TILE_BINDINGS.layout_entries(stages));
        entries
    }

    /// The entries of [`LightTiles::reader_group`] over `lights`, for groups that extend it
    /// (laid out with [`LightTiles::reader_layout_entries`] and more).
    pub fn reader_entries<'a>(&'a self, lights: &'a GpuLights) -> Vec<wgpu::BindGroupEntry<'a>> {
        let mut entries = lights.entries();
        entries.extend(TILE_BINDINGS.entries(&[
            ("light_tile_samples", &self.samples),
            ("light_tile_ids", &self.ids),
        ]));
        entries
    }

    /// Bind group 3 for tile readers (see [`LightTiles::reader_layout`]). Rebuild it when the
    /// light list is re-uploaded.
    pub fn reader_group(&self, gpu: &Gpu, lights: &GpuLights) -> wgpu::BindGroup {
        let entries = self.reader_entries(lights);
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("solari_lights/lights_and_tiles"),
            layout: &self.reader_layout,
            entries: &entries,
        })
    }

    /// The packed samples (for tests and tools; needs a read-back copy).
    pub fn samples_buffer(&self) -> &wgpu::Buffer {
        &self.samples
    }

    /// The sample identities, parallel to [`LightTiles::samples_buffer`].
    pub fn ids_buffer(&self) -> &wgpu::Buffer {
        &self.ids
    }
}

/// The crate's entry-point shaders, by module name.
pub const ENTRY_POINTS: &[(&str, &str)] = &[(
    "presample_light_tiles",
    include_str!("../shaders/presample_light_tiles.wesl"),
)];
