//! Specular GI: the indirect light of each pixel's specular lobe, the part of the bounce that
//! ReSTIR GI (diffuse lobe only) and the diffuse world cache cannot give. Without it metals
//! reflect only what DI gives them: they look black wherever the light is indirect.
//!
//! ## The algorithm (after Solari 0.18 "Specular GI" and 0.19 "Path Termination")
//!
//! One compute pass, after ReSTIR GI, adding to the same lit image.
//!
//! - **Rough pixels** (perceptual roughness above
//!   [`SpecularGiSettings::rough_threshold`], when ReSTIR GI ran this frame) trace nothing:
//!   they weigh this frame's final GI reservoir ([`crate::RestirGi::reservoirs`]) by the
//!   specular lobe, `L · f_spec · cos · W`.
//!   ReSTIR GI's target function includes the specular lobe, so its reservoirs also serve
//!   rough metals, which have no diffuse lobe.
//! - **Other pixels** trace a path. The first direction samples the specular lobe alone
//!   (bounded VNDF, or the mirror's reflection with weight F); later ones the whole BRDF.
//!   At every hit: emission, MIS-weighted (balance heuristic, safe for the mirror's infinite
//!   pdf) against one light-tile sample of next-event estimation; then either the end in the
//!   world cache or one more bounce. Emission met by the first segment is DI's (weight 0),
//!   except behind a mirror, where DI sees nothing. Misses add the environment and the sun
//!   discs they look into, MIS-weighted as emitters are. The last vertex's light sample,
//!   with no ray after it, takes weight 1.
//! - **Termination** ([`SpecularGiSettings::cache_termination`]): the path's spread grows
//!   by `t² · ½α²/(1 − α²)` per segment (α of the surface it left; the primary's α over the
//!   camera distance to start, Bevy's form); once a segment is longer than √3 cells and the
//!   spread exceeds a cell², the hit's directional albedo toward the ray times the cache's
//!   irradiance ends the path (as at a ReSTIR GI hit). With termination on, a path also ends
//!   in the cache at its last bounce ([`SpecularGiSettings::max_bounces`]); with it off, no
//!   path reads the cache: it stops after its last bounce's light sample, and the light
//!   beyond is lost.
//!
//! - **Primary surface replacement** (after Solari 0.19 "Primary Surface Replacement", bound
//!   with [`PsrBindings`]): where the primary surface is a mirror metal (metallic 1,
//!   roughness below the BRDF's mirror threshold 0.02), the path follows the mirror
//!   bounces to the first other surface (or its last bounce) and writes that surface as the
//!   pixel's G-buffer override ([`solari_scene::gbuffer_override`]): its point and normals
//!   mapped into the mirror world by the chained reflections (`x ↦ M x + c`, one Householder
//!   reflection per mirror), so its depth is the unfolded path length along the view ray;
//!   its albedos times the mirrors' reflectance, so demodulation divides the reflection by
//!   what it is made of; the emission seen through the mirrors; and the motion of its
//!   mirror-world point between last frame's view and this one (the hit's instance moved by
//!   its own transforms, the mirrors taken as static). Exact for flat mirrors; a curved
//!   mirror gets a plausible guide, not an exact one. Smooth non-metals keep their own
//!   guides (Solari found replacing them worse).
//!
//!   The pass stores every pixel's override slot each frame (an override or none), so the
//!   override buffer may be shared scratch. It may even be the buffer that holds this frame's
//!   GI reservoirs (plain path GI keeps them in the renderer's scratch, as the overrides
//!   are): a pixel reads its own reservoir before it stores its own slot, and both are 32
//!   bytes, so no pixel's store reaches a reservoir another pixel still has to read. The
//!   shader then writes the overrides through the reservoirs' binding, since a shader may
//!   assume that two bindings do not alias.
//!
//! Cost: up to `2 × max_bounces` rays per traced pixel (one segment and one shadow ray per
//! bounce); none for rough pixels. Replacement adds no ray: it rides on the mirror pixels'
//! own path.

use crate::di::{PassLayouts, check_encode, layout_with_cache, pass_pipeline, record};
use crate::gi::RestirGi;
use bytemuck::{Pod, Zeroable};
use solari_lights::{LightTileSettings, LightTiles};
use solari_scene::GpuError;
use solari_scene::bindings::{Buf, BufferGroup};
use solari_scene::gbuffer_input::GBufferSource;
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::{GpuScene, TraceVariant};
use solari_scene::pass::{FrameContext, Ran};
use solari_scene::shaders::Backend;
use solari_worldcache::WorldCache;

/// Most bounces a specular path may take (the shader loop's bound).
pub const MAX_SPECULAR_BOUNCES: u32 = 8;

/// Bind group 2 of `specular_gi.wesl` below the world cache's bindings, by WGSL name.
pub const SPECULAR_BINDINGS: BufferGroup = BufferGroup::new(
    2,
    0,
    &[
        ("spec_params", Buf::Uniform),
        // Read-write: the overrides may share its buffer (see the module docs).
        ("spec_gi", Buf::ReadWrite),
        ("spec_lit", Buf::ReadWrite),
        ("spec_overrides", Buf::ReadWrite),
        ("spec_previous_transforms", Buf::Read),
    ],
);

/// The pass's label (dispatch, profiler scope and report name).
pub const SPECULAR_PASS_LABELS: [&str; 1] = ["specular_gi"];

/// Specular GI's knobs, each with its default and its cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecularGiSettings {
    /// Pixels rougher than this (perceptual roughness) reuse ReSTIR GI's reservoir instead of
    /// tracing (default 0.4, Solari's). Lower saves rays on glossy surfaces and blurs their
    /// reflections toward the diffuse reservoir's noise; it applies only when ReSTIR GI runs.
    pub rough_threshold: f32,
    /// Path segments after the primary surface (default 3, Solari's; 1–8). Each costs up to
    /// two rays per traced pixel.
    pub max_bounces: u32,
    /// One light-tile sample with a shadow ray at every path vertex (default on). Off, lights
    /// reach the path only where it hits them, which is noisy for small lights.
    pub next_event: bool,
    /// End paths in the world cache once their spread covers a cell, and at their last
    /// bounce (default on). Off, paths run their full `max_bounces`, take a light sample at
    /// their last hit and stop there: no cache approximation, but the light of later
    /// bounces is lost (darker), and every traced pixel pays for all its bounces.
    pub cache_termination: bool,
    /// Longest ray (default unbounded); a miss is lit by the scene's environment.
    pub max_ray_distance: f32,
}

impl Default for SpecularGiSettings {
    fn default() -> Self {
        Self {
            rough_threshold: 0.4,
            max_bounces: 3,
            next_event: true,
            cache_termination: true,
            max_ray_distance: f32::MAX,
        }
    }
}

impl SpecularGiSettings {
    /// Checks every knob is in range; the error names the bad one.
    pub fn validate(&self) -> Result<(), GpuError> {
        let bad = |what: String| {
            Err(GpuError::Validation(format!(
                "specular GI settings: {what}"
            )))
        };
        if !(0.0..=1.0).contains(&self.rough_threshold) {
            return bad(format!(
                "rough_threshold is {}, expected a roughness in [0, 1]",
                self.rough_threshold
            ));
        }
        if self.max_bounces == 0 || self.max_bounces > MAX_SPECULAR_BOUNCES {
            return bad(format!(
                "max_bounces is {}, expected 1 to {MAX_SPECULAR_BOUNCES}",
                self.max_bounces
            ));
        }
        if self.max_ray_distance.is_nan() || self.max_ray_distance <= 0.0 {
            return bad(format!(
                "max_ray_distance is {}, expected a positive distance",
                self.max_ray_distance
            ));
        }
        Ok(())
    }
}

/// `SPECULAR_FLAG_*` in `specular_gi.wesl`.
mod flags {
    pub const REUSE_GI: u32 = 1;
    pub const NEE: u32 = 2;
    pub const CACHE_END: u32 = 4;
    pub const PSR: u32 = 8;
    pub const OVERRIDES_IN_GI: u32 = 16;
    pub const INDIRECT_ONLY: u32 = 32;
}

// A pixel's override and its GI reservoir take the same 32 bytes, so a pixel's store of one
// can never reach another pixel's copy of the other (flags::OVERRIDES_IN_GI).
const _: () = assert!(
    size_of::<crate::GpuGiReservoir>() as u64 == solari_scene::gbuffer_override::OVERRIDE_BYTES
);

/// What primary surface replacement writes and reads, both the G-buffer's:
/// [`solari_scene::gbuffer::GBuffer::overrides`] (enable them first with
/// [`solari_scene::gbuffer::GBuffer::enable_overrides`]) and
/// [`solari_scene::gbuffer::GBuffer::previous_transforms`] (rebind when
/// [`solari_scene::gbuffer::GBuffer::transforms_generation`] changes).
#[derive(Clone, Copy, Debug)]
pub struct PsrBindings<'a> {
    /// The per-pixel override buffer (it may be ReSTIR GI's reservoir buffer, when both are
    /// in the same shared scratch).
    pub overrides: &'a wgpu::Buffer,
    /// Last frame's instance transforms.
    pub previous_transforms: &'a wgpu::Buffer,
}

/// WGSL twin: `SpecularParams` in `specular_gi.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuSpecularParams {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Frame index (seeds random numbers).
    pub frame: u32,
    /// `SPECULAR_FLAG_*` bits.
    pub flags: u32,
    /// [`SpecularGiSettings::rough_threshold`].
    pub rough_threshold: f32,
    /// [`SpecularGiSettings::max_bounces`].
    pub max_bounces: u32,
    /// Light-tile samples in all.
    pub tile_samples: u32,
    /// [`SpecularGiSettings::max_ray_distance`].
    pub max_ray_distance: f32,
}

const _: () = assert!(size_of::<GpuSpecularParams>() == 32);

/// Specular GI: reads the scene (group 0), the G-buffer (group 1), the world cache and
/// optionally ReSTIR GI's reservoirs (group 2, [`SpecularGi::bind`]) and the lights and
/// tiles (group 3, [`LightTiles::reader_group`]); adds to a lit image, and with
/// [`PsrBindings`] writes mirror pixels' G-buffer overrides.
pub struct SpecularGi {
    settings: SpecularGiSettings,
    variant: TraceVariant,
    size: (u32, u32),
    tile_samples: u32,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    // Stands in for ReSTIR GI's reservoirs when it does not run (bindings must not dangle).
    no_reservoirs: wgpu::Buffer,
    // Stand in for the override buffer and the transforms without replacement (two: one is
    // written, the other read, and a buffer may not be both in one dispatch).
    no_psr: [wgpu::Buffer; 2],
    group: Option<wgpu::BindGroup>,
    reuse_gi: bool,
    psr: bool,
    // The override buffer is the GI reservoirs' (flags::OVERRIDES_IN_GI).
    overrides_in_gi: bool,
    // `set_indirect_only`.
    indirect_only: bool,
}

impl SpecularGi {
    /// Builds the pipeline for scenes uploaded with `backend` and traced with `variant`, for
    /// `width × height` pixels and light tiles of `tiles`. Bind it ([`SpecularGi::bind`])
    /// before the first frame.
    pub fn new(
        gpu: &Gpu,
        backend: Backend,
        variant: TraceVariant,
        width: u32,
        height: u32,
        settings: SpecularGiSettings,
        tiles: LightTileSettings,
    ) -> Result<Self, GpuError> {
        settings.validate()?;
        if width == 0 || height == 0 {
            return Err(GpuError::Validation(format!(
                "specular GI image size {width}×{height} is empty"
            )));
        }
        let variant = variant.for_backend(backend);
        let layout = layout_with_cache(gpu, &SPECULAR_BINDINGS, "solari_restir/specular_gi");
        let lights_layout = LightTiles::reader_layout(gpu);
        let shared = PassLayouts::new(gpu, backend);
        let layouts = shared.with(&layout, &lights_layout);
        let pipeline = pass_pipeline(
            gpu,
            backend,
            &crate::specular_modules(),
            &layouts,
            "specular_gi",
            &tiles.reader_constants(variant.constants()),
        )?;
        let params = gpu.uniform_buffer(
            "solari_restir/specular_params",
            &GpuSpecularParams::zeroed(),
        );
        let no_reservoirs = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solari_restir/specular_no_reservoirs"),
            size: size_of::<crate::GpuGiReservoir>() as u64,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        // One override (32 bytes) and one transform (48).
        let no_psr = [32, 48].map(|size| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("solari_restir/specular_no_psr"),
                size,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            })
        });
        Ok(Self {
            settings,
            variant,
            size: (width, height),
            tile_samples: u32::try_from(tiles.sample_count()).unwrap_or(u32::MAX),
            pipeline,
            layout,
            params,
            no_reservoirs,
            no_psr,
            group: None,
            reuse_gi: false,
            psr: false,
            overrides_in_gi: false,
            indirect_only: false,
        })
    }

    /// Binds the world cache, the image to add to (`width × height` `vec4<f32>`, for
    /// example [`crate::RestirDi::output`]), ReSTIR GI, whose final reservoirs rough
    /// pixels reuse (`None`: every pixel traces), and the G-buffer's buffers for primary
    /// surface replacement (`None`: no replacement). Call it again after any of them was
    /// rebuilt or resized.
    pub fn bind(
        &mut self,
        gpu: &Gpu,
        cache: &WorldCache,
        target: &wgpu::Buffer,
        gi: Option<&RestirGi>,
        psr: Option<PsrBindings>,
    ) -> Result<(), GpuError> {
        let pixels = self.size.0 as u64 * self.size.1 as u64;
        if let Some(p) = psr
            && p.overrides.size() < pixels * solari_scene::gbuffer_override::OVERRIDE_BYTES
        {
            return Err(GpuError::Validation(format!(
                "specular GI: the override buffer holds {} bytes, {:?} pixels need {}",
                p.overrides.size(),
                self.size,
                pixels * solari_scene::gbuffer_override::OVERRIDE_BYTES
            )));
        }
        if let Some(gi) = gi
            && gi.size() != self.size
        {
            return Err(GpuError::Validation(format!(
                "specular GI: built for {:?} pixels, ReSTIR GI has {:?}",
                self.size,
                gi.size()
            )));
        }
        let reservoirs = gi.map_or(&self.no_reservoirs, |g| g.reservoirs());
        // One buffer in two read-write bindings would be aliasing the shader may not expect:
        // the overrides are then written through `spec_gi`.
        let overrides_in_gi = psr.is_some_and(|p| p.overrides == reservoirs);
        let overrides = match psr {
            Some(p) if !overrides_in_gi => p.overrides,
            _ => &self.no_psr[0],
        };
        let mut entries = SPECULAR_BINDINGS.entries(&[
            ("spec_params", &self.params),
            ("spec_gi", reservoirs),
            ("spec_lit", target),
            ("spec_overrides", overrides),
            (
                "spec_previous_transforms",
                psr.map_or(&self.no_psr[1], |p| p.previous_transforms),
            ),
        ]);
        entries.extend(cache.bind_group_entries());
        self.group = Some(gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("solari_restir/specular_gi"),
            layout: &self.layout,
            entries: &entries,
        }));
        self.reuse_gi = gi.is_some();
        self.psr = psr.is_some();
        self.overrides_in_gi = overrides_in_gi;
        Ok(())
    }

    /// The settings in use.
    pub fn settings(&self) -> SpecularGiSettings {
        self.settings
    }

    /// Changes the settings (the pass keeps no history).
    pub fn set_settings(&mut self, settings: SpecularGiSettings) -> Result<(), GpuError> {
        settings.validate()?;
        self.settings = settings;
        Ok(())
    }

    /// GPU memory the pass holds, in bytes (parameters and the stand-ins: no per-pixel
    /// buffers; the override buffer is the G-buffer's).
    pub fn memory_bytes(&self) -> u64 {
        let stand_ins: u64 = self.no_psr.iter().map(|b| b.size()).sum();
        self.params.size() + self.no_reservoirs.size() + stand_ins
    }

    /// With `true`, from the next [`SpecularGi::prepare`] on, the pass adds indirect light
    /// only: what its first segment meets (an emitter or the environment, which reached the
    /// eye after one scattering event) is left out at mirrors too, where it otherwise counts
    /// because direct light evaluates no mirror lobe. With
    /// [`crate::RestirDi::set_indirect_only`] this makes a frame of indirect light alone.
    /// Off by default.
    pub fn set_indirect_only(&mut self, on: bool) {
        self.indirect_only = on;
    }

    /// Whether primary surface replacement is bound ([`SpecularGi::bind`]).
    pub fn replaces_surfaces(&self) -> bool {
        self.psr
    }

    /// Image size in pixels.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Writes the frame's parameters.
    pub fn prepare(&self, gpu: &Gpu, frame: &FrameContext) {
        let s = self.settings;
        let mut bits = 0;
        if self.reuse_gi {
            bits |= flags::REUSE_GI;
        }
        if s.next_event {
            bits |= flags::NEE;
        }
        if s.cache_termination {
            bits |= flags::CACHE_END;
        }
        if self.psr {
            bits |= flags::PSR;
        }
        if self.overrides_in_gi {
            bits |= flags::OVERRIDES_IN_GI;
        }
        if self.indirect_only {
            bits |= flags::INDIRECT_ONLY;
        }
        let params = GpuSpecularParams {
            width: self.size.0,
            height: self.size.1,
            frame: frame.index,
            flags: bits,
            rough_threshold: s.rough_threshold,
            max_bounces: s.max_bounces,
            tile_samples: self.tile_samples,
            max_ray_distance: s.max_ray_distance,
        };
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
    }

    /// Records the pass in a profiler scope named [`SPECULAR_PASS_LABELS`]`[0]`. Run it after
    /// ReSTIR GI (whose final reservoirs it reads) and the light tiles; `lights` is the tiles'
    /// reader group.
    ///
    /// Errors, recording nothing, before [`SpecularGi::bind`], when the pipeline was
    /// specialised for a scene shape that `scene` no longer has, or when the G-buffer's or
    /// the frame's size is not this pass's.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        scene: &GpuScene,
        gbuffer: &dyn GBufferSource,
        lights: &wgpu::BindGroup,
    ) -> Result<Ran, GpuError> {
        check_encode(
            "specular GI",
            self.variant,
            self.size,
            scene,
            gbuffer,
            frame,
        )?;
        let Some(group) = self.group.as_ref() else {
            return Err(GpuError::Validation(
                "specular GI: encode before bind (no cache or target bound)".into(),
            ));
        };
        let groups = [scene.bind_group(), gbuffer.bind_group()?, group, lights];
        let workgroups = [self.size.0.div_ceil(8), self.size.1.div_ceil(8)];
        let mut ran = Ran::none();
        let label = SPECULAR_PASS_LABELS[0];
        frame.scope(label, encoder, &mut ran, |e| {
            record(e, label, &self.pipeline, &groups, workgroups)
        });
        Ok(ran)
    }
}
