//! The portable spatiotemporal denoiser (after SVGF): temporal accumulation with
//! reprojection, variance estimation and an edge-aware à-trous wavelet filter, per signal.

use crate::denoiser::{Denoiser, DenoiserInputs, Encoded, Inputs, Lighting, Requirements};
use crate::history::PackedHistory;
use crate::settings::{AtrousKernel, FallbackSettings, GpuDenoiseParams, GpuPassParams};
use bytemuck::Zeroable;
use solari_scene::GpuError;
use solari_scene::bindings::{Buf, BufferGroup};
use solari_scene::gbuffer::GBuffer;
use solari_scene::gpu::{Gpu, ShaderChecks};
use solari_scene::pass::{FrameContext, Ran};
use solari_scene::shaders::{Backend, compose};

/// Bind group 0 of the fallback denoiser's shaders (`denoise_common.wesl`), by WGSL name.
pub const FALLBACK_BINDINGS: BufferGroup = BufferGroup::new(
    0,
    0,
    &[
        ("params", Buf::Uniform),
        ("noisy", Buf::Read),
        ("history_before", Buf::Read),
        ("history_now", Buf::ReadWrite),
        ("filter_in", Buf::Read),
        ("filter_out", Buf::ReadWrite),
        ("guide", Buf::ReadWrite),
        ("denoised", Buf::ReadWrite),
        ("pass_params", Buf::Uniform),
        ("shadow", Buf::Read),
        ("transient", Buf::ReadWrite),
        ("transient_ro", Buf::Read),
    ],
);

/// Profiler scopes of the fallback's passes: temporal accumulation, variance, and all à-trous
/// iterations together (per signal, so split lighting records each twice).
pub const PASS_LABELS: [&str; 3] = ["denoise_temporal", "denoise_variance", "denoise_atrous"];

/// One pixel's history (WGSL `History`), in demodulated units, as the passes see it: stored
/// packed in 24 bytes ([`crate::history`]) and decoded by [`FallbackDenoiser::read_history`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuHistory {
    /// Colour (rgb) and history length in frames (w; 0 = none).
    pub color: [f32; 4],
    /// Short-window mean luminance, mean squared luminance, fast (4-frame) mean luminance,
    /// long mean luminance (this pixel's own samples).
    pub moments: [f32; 4],
    /// Firefly energy still to be added (rgb), and the relative luminance deviation of calm
    /// frames that the stale-history test measures against (w).
    pub carry: [f32; 4],
}

const HISTORY_BYTES: u64 = size_of::<PackedHistory>() as u64;

// Bytes per pixel of the transient words (WGSL `transient`, two planes of 16): the new
// history, then in the first plane the variance pass's output.
const TRANSIENT_BYTES: u64 = 32;

// A per-pixel buffer: its own, or the start of a shared scratch buffer.
struct Region {
    buffer: wgpu::Buffer,
    shared: bool,
    // Bytes per pixel.
    stride: u64,
}

impl Region {
    fn own(buffer: wgpu::Buffer, stride: u64) -> Self {
        Self {
            buffer,
            shared: false,
            stride,
        }
    }

    fn binding(&self, pixels: u64) -> wgpu::BufferBinding<'_> {
        wgpu::BufferBinding {
            buffer: &self.buffer,
            offset: 0,
            size: wgpu::BufferSize::new(pixels * self.stride),
        }
    }
}

// One signal's history and bind groups (combined lighting has one signal, split two).
struct Signal {
    history: wgpu::Buffer,
    // Per dispatch: temporal, variance, then each à-trous iteration.
    groups: Vec<wgpu::BindGroup>,
}

/// The fallback denoiser. See the crate docs for the algorithm and its measured bias.
pub struct FallbackDenoiser {
    settings: FallbackSettings,
    size: (u32, u32),
    temporal: wgpu::ComputePipeline,
    variance: wgpu::ComputePipeline,
    atrous: wgpu::ComputePipeline,
    // The first iteration's: with `history_feedback` it also feeds back into the history.
    atrous_first: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    // Per signal slot (0 combined/diffuse, 1 specular) and dispatch.
    pass_params: [Vec<wgpu::Buffer>; 2],
    // Where each pass writes, for n à-trous iterations: the temporal pass puts the new
    // history in `transient` and the variance pass's window data in `output`; the variance
    // pass stores the history (one buffer per signal, not two: last frame's is not read
    // after the temporal pass) and puts its output in `transient`; iteration k writes
    // `output` when n − 1 − k is even, else `second`, so the last writes `output`. With one
    // signal the last iteration writes the denoised image there, so `output` is the output
    // (a separate one cost 16 B per pixel) and always an own buffer.
    //
    // `transient` lives only from the temporal pass to the first iteration, and `second`
    // from the second iteration on, so both may be the same shared scratch buffer
    // (`use_scratch`) when n is odd. When n is even the first iteration writes `second`
    // while it reads `transient`, and one buffer bound read-only and read-write in one
    // dispatch is refused by wgpu: `second` is then its own. The guide is an own buffer for
    // the same reason (binding `filter_in` read-write instead cost the à-trous 4% on the
    // H100).
    output: wgpu::Buffer,
    second: Region,
    transient: Region,
    guide: wgpu::Buffer,
    // The output of split lighting (made when split lighting is first bound), whose second
    // signal adds to the first after both have used the filter buffers.
    split_output: Option<wgpu::Buffer>,
    // Placeholders for bindings a dispatch does not use (and for `shadow` when the inputs
    // bring none, `denoised` when the output goes to a filter buffer): one bound read-only,
    // one read-write.
    no_shadow: wgpu::Buffer,
    no_output: wgpu::Buffer,
    // Built on first use for the lighting (and shadow) buffers given, rebuilt when they
    // change.
    signals: Vec<Signal>,
    bound_to: Vec<wgpu::Buffer>,
    history: bool,
    // Frames recorded (wrapping): seeds the history's stochastic rounding.
    frame: u32,
}

impl FallbackDenoiser {
    /// Builds the passes and allocates `width × height` buffers: 96 bytes per pixel (190 MiB
    /// at 1920×1080) for combined lighting, 40 more for split. [`Denoiser::use_scratch`]
    /// moves 48 of them into shared scratch with an odd `atrous_iterations` (the default 5),
    /// 32 with an even one.
    pub fn new(
        gpu: &Gpu,
        width: u32,
        height: u32,
        settings: FallbackSettings,
    ) -> Result<Self, GpuError> {
        settings.validate()?;
        let pixels = width as u64 * height as u64;
        if pixels == 0 {
            return Err(GpuError::Validation(format!(
                "fallback denoiser: image size {width}×{height} is empty"
            )));
        }
        // The transient bytes are the largest buffer bound whole (32 bytes a pixel).
        gpu.check_storage_binding(
            &format!("fallback denoiser's transient bytes at {width}×{height}"),
            pixels * TRANSIENT_BYTES,
        )?;
        let layout = FALLBACK_BINDINGS.layout(gpu, "solari_denoise/fallback");
        let gbuffer_layout = GBuffer::reader_layout(gpu);
        let modules = crate::modules();
        let pipeline = |entry: &str, constants: &[(&str, f64)]| -> Result<_, GpuError> {
            // The denoiser traces no rays: either backend's composition serves.
            let wgsl = compose(entry, Backend::Software, &modules)?;
            gpu.compute_pipeline(
                &format!("solari_denoise/{entry}"),
                &wgsl,
                &[Some(&layout), Some(&gbuffer_layout)],
                ShaderChecks::BoundsOnly,
                constants,
            )
        };
        let temporal = pipeline("denoise_temporal", &[])?;
        let variance = pipeline("denoise_variance", &[])?;
        // The pipeline constant `ATROUS_DIAMOND` (`@id(7130)` in `denoise_atrous_filter.wesl`;
        // WESL renames declarations, so constants go by id).
        let kernel = [(
            "7130",
            (settings.atrous_kernel == AtrousKernel::Diamond) as u32 as f64,
        )];
        let atrous = pipeline("denoise_atrous", &kernel)?;
        let atrous_first = if settings.history_feedback {
            pipeline("denoise_atrous_feedback", &kernel)?
        } else {
            atrous.clone()
        };
        let params = gpu.uniform_buffer("solari_denoise/params", &GpuDenoiseParams::zeroed());
        let storage = |label: &str, bytes: u64| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes.max(16),
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let output = storage("solari_denoise/filter_output", pixels * 16);
        let second = Region::own(storage("solari_denoise/filter_second", pixels * 16), 16);
        let transient = Region::own(
            storage("solari_denoise/transient", pixels * TRANSIENT_BYTES),
            TRANSIENT_BYTES,
        );
        let guide = storage("solari_denoise/guide", pixels * 8);
        // 32 bytes: at least one element of every array they stand in for.
        let no_shadow = storage("solari_denoise/no_shadow", 32);
        let no_output = storage("solari_denoise/no_output", 32);
        let pass_params = [0u32, 1].map(|slot| {
            (0..settings.atrous_iterations + 2)
                .map(|dispatch| {
                    gpu.uniform_buffer(
                        "solari_denoise/pass",
                        &pass_params(&settings, slot, dispatch, false),
                    )
                })
                .collect::<Vec<_>>()
        });
        Ok(Self {
            settings,
            size: (width, height),
            temporal,
            variance,
            atrous,
            atrous_first,
            layout,
            params,
            pass_params,
            output,
            second,
            transient,
            guide,
            split_output: None,
            no_shadow,
            no_output,
            signals: Vec::new(),
            bound_to: Vec::new(),
            history: false,
            frame: 0,
        })
    }

    /// The settings in use.
    pub fn settings(&self) -> FallbackSettings {
        self.settings
    }

    // Whether `second` may share the scratch with `transient` (see the fields).
    fn second_shares(&self) -> bool {
        self.settings.atrous_iterations % 2 == 1
    }

    /// Drops all history: the next frame starts afresh (as `DenoiserInputs::reset` does).
    pub fn reset(&mut self) {
        self.history = false;
    }

    // (Re)builds per-signal buffers and bind groups for these lighting buffers and this
    // shadow buffer (or the placeholder).
    fn bind(&mut self, gpu: &Gpu, lighting: &Lighting, shadow: Option<&wgpu::Buffer>) {
        let pair;
        let inputs: &[&wgpu::Buffer] = match lighting {
            Lighting::Combined(b) => std::slice::from_ref(b),
            Lighting::Split { diffuse, specular } => {
                pair = [*diffuse, *specular];
                &pair
            }
        };
        let shadow = shadow.unwrap_or(&self.no_shadow);
        // Checked every frame: compare in place, allocate only to rebind.
        let mut key = inputs.iter().copied().chain([shadow]);
        if self.bound_to.len() == inputs.len() + 1
            && self.bound_to.iter().all(|a| key.next() == Some(a))
        {
            return;
        }
        let shadow = shadow.clone();
        let key: Vec<&wgpu::Buffer> = inputs.iter().copied().chain([&shadow]).collect();
        let pixels = self.size.0 as u64 * self.size.1 as u64;
        let split = inputs.len() == 2;
        if split && self.split_output.is_none() {
            self.split_output = Some(gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("solari_denoise/output"),
                size: pixels * 16,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }));
        }
        let denoised = match &self.split_output {
            Some(b) if split => b,
            _ => &self.no_output,
        };
        let n = self.settings.atrous_iterations as usize;
        // Whether à-trous iteration k writes `output` (else `second`): the last one does.
        let writes_output = |k: usize| (n - 1 - k).is_multiple_of(2);
        let second_in_transient = self.second.buffer == self.transient.buffer;
        // Whether a dispatch reads the transient words' buffer as `filter_in` (read-only), so
        // it reads the centre's words through `transient_ro`: the first iteration (the first
        // plane), and later ones that read a `second` sharing that buffer.
        let centre_ro = |dispatch: usize| match dispatch {
            0 | 1 => false,
            2 => true,
            d => second_in_transient && !writes_output(d - 3),
        };
        for slot in 0..2u32 {
            for (dispatch, buffer) in self.pass_params[slot as usize].iter().enumerate() {
                let p = GpuPassParams {
                    centre_ro: centre_ro(dispatch) as u32,
                    ..pass_params(&self.settings, slot, dispatch as u32, split)
                };
                gpu.queue.write_buffer(buffer, 0, bytemuck::bytes_of(&p));
            }
        }
        let whole = wgpu::Buffer::as_entire_buffer_binding;
        let output = whole(&self.output);
        let second = self.second.binding(pixels);
        let transient = self.transient.binding(pixels);
        // The transient words' first plane, where the variance pass leaves its output.
        let first_plane = wgpu::BufferBinding {
            size: wgpu::BufferSize::new(pixels * 16),
            ..transient.clone()
        };
        let (ro, rw) = (whole(&self.no_shadow), whole(&self.no_output));
        self.signals = inputs
            .iter()
            .enumerate()
            .map(|(slot, input)| {
                let history = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("solari_denoise/history"),
                    size: pixels * HISTORY_BYTES,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                let groups = (0..n + 2)
                    .map(|dispatch| {
                        // What each dispatch reads and writes (see the fields); a binding
                        // it does not use gets a placeholder, since a buffer may not be
                        // bound read-only and read-write in one dispatch.
                        let written = |k: usize| {
                            if writes_output(k) {
                                output.clone()
                            } else {
                                second.clone()
                            }
                        };
                        let h = whole(&history);
                        // (history_before, history_now, filter_in, filter_out, transient
                        // for the temporal and variance passes)
                        let (before, now, from, to, words) = match dispatch {
                            0 => (h, rw.clone(), ro.clone(), output.clone(), transient.clone()),
                            1 => (ro.clone(), h, output.clone(), rw.clone(), transient.clone()),
                            2 => (ro.clone(), h, first_plane.clone(), written(0), rw.clone()),
                            d => (ro.clone(), h, written(d - 3), written(d - 2), rw.clone()),
                        };
                        // The centre's words: read-only where `filter_in` reads their buffer.
                        let (words, words_ro) = match dispatch {
                            0 | 1 => (words, ro.clone()),
                            d if centre_ro(d) => (rw.clone(), transient.clone()),
                            _ => (transient.clone(), ro.clone()),
                        };
                        let params = whole(&self.pass_params[slot][dispatch]);
                        let entries = FALLBACK_BINDINGS.range_entries(&[
                            ("params", whole(&self.params)),
                            ("noisy", whole(input)),
                            ("history_before", before),
                            ("history_now", now),
                            ("filter_in", from),
                            ("filter_out", to),
                            ("guide", whole(&self.guide)),
                            ("denoised", whole(denoised)),
                            ("pass_params", params),
                            ("shadow", whole(&shadow)),
                            ("transient", words),
                            ("transient_ro", words_ro),
                        ]);
                        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                            label: Some("solari_denoise/fallback"),
                            layout: &self.layout,
                            entries: &entries,
                        })
                    })
                    .collect();
                Signal { history, groups }
            })
            .collect();
        self.bound_to = key.into_iter().cloned().collect();
        self.history = false;
    }

    /// Reads the current history of signal `slot` (0 combined or diffuse, 1 specular), for
    /// tests. Blocks until the GPU is done.
    pub fn read_history(&self, gpu: &Gpu, slot: usize) -> Result<Vec<GpuHistory>, GpuError> {
        let signal = self.signals.get(slot).ok_or_else(|| {
            GpuError::Validation(format!("fallback denoiser: no signal {slot} bound yet"))
        })?;
        let pixels = self.size.0 as u64 * self.size.1 as u64;
        let bytes = gpu.read_buffer(&signal.history, pixels * HISTORY_BYTES)?;
        let packed: &[PackedHistory] = bytemuck::cast_slice(&bytes);
        Ok(packed.iter().map(crate::history::unpack).collect())
    }
}

fn pass_params(
    settings: &FallbackSettings,
    slot: u32,
    dispatch: u32,
    split: bool,
) -> GpuPassParams {
    let iteration = dispatch.saturating_sub(2);
    let atrous = dispatch >= 2;
    GpuPassParams {
        step: if atrous { 1 << iteration } else { 0 },
        _pad0: 0,
        last: (atrous && iteration + 1 == settings.atrous_iterations) as u32,
        signal: if split { slot + 1 } else { 0 },
        accumulate: (slot == 1) as u32,
        output_in_filter: !split as u32,
        centre_ro: 0,
        _pad: 0,
    }
}

impl Denoiser for FallbackDenoiser {
    fn name(&self) -> &'static str {
        "fallback"
    }

    fn requirements(&self) -> Requirements {
        Requirements {
            features: wgpu::Features::empty(),
            backend: None,
            inputs: Inputs::COMBINED_LIGHTING
                | Inputs::SPLIT_LIGHTING
                | Inputs::GUIDES
                | Inputs::SHADOW,
        }
    }

    fn render_size(&self) -> (u32, u32) {
        self.size
    }

    fn output_size(&self) -> (u32, u32) {
        self.size
    }

    fn pass_labels(&self) -> &'static [&'static str] {
        &PASS_LABELS
    }

    fn encode(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        inputs: &DenoiserInputs,
    ) -> Result<Encoded, GpuError> {
        solari_scene::gbuffer_input::check_size("fallback denoiser", self.size, inputs.gbuffer)?;
        let pixels = self.size.0 as u64 * self.size.1 as u64;
        if let Some(shadow) = inputs.shadow
            && shadow.size() < pixels * 4
        {
            return Err(GpuError::Validation(format!(
                "fallback denoiser: the shadow input holds {} bytes; {}×{} pixels need {} \
                 (one packed u32 each)",
                shadow.size(),
                self.size.0,
                self.size.1,
                pixels * 4
            )));
        }
        self.bind(gpu, &inputs.lighting, inputs.shadow);
        let reset = inputs.reset || !self.history || !inputs.gbuffer.history_valid();
        let (w, h) = self.size;
        self.frame = self.frame.wrapping_add(1);
        let params = GpuDenoiseParams {
            shadow: inputs.shadow.is_some() as u32,
            frame: self.frame,
            ..self.settings.gpu(w, h, reset)
        };
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let workgroups = [w.div_ceil(8), h.div_ceil(8)];
        let gbuffer = inputs.gbuffer.bind_group()?;
        let mut ran = Ran::none();
        for signal in &self.signals {
            let groups = &signal.groups;
            let run = |e: &mut wgpu::CommandEncoder, label, pipeline, group| {
                let mut pass = e.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(label),
                    timestamp_writes: None,
                });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, group, &[]);
                pass.set_bind_group(1, gbuffer, &[]);
                pass.dispatch_workgroups(workgroups[0], workgroups[1], 1);
            };
            frame.scope(PASS_LABELS[0], encoder, &mut ran, |e| {
                run(e, PASS_LABELS[0], &self.temporal, &groups[0])
            });
            frame.scope(PASS_LABELS[1], encoder, &mut ran, |e| {
                run(e, PASS_LABELS[1], &self.variance, &groups[1])
            });
            frame.scope(PASS_LABELS[2], encoder, &mut ran, |e| {
                for (k, group) in groups[2..].iter().enumerate() {
                    let pipeline = if k == 0 {
                        &self.atrous_first
                    } else {
                        &self.atrous
                    };
                    run(e, PASS_LABELS[2], pipeline, group);
                }
            });
        }
        self.history = true;
        Ok(Encoded {
            ran,
            after: Vec::new(),
        })
    }

    /// With split lighting its own buffer; with combined lighting the filter buffer the last
    /// à-trous iteration writes.
    fn output(&self) -> &wgpu::Buffer {
        match (&self.split_output, self.signals.len()) {
            (Some(b), 2) => b,
            _ => &self.output,
        }
    }

    /// The transient words (32 bytes per pixel), and with an odd `atrous_iterations` the
    /// second filter buffer too, which uses them at other times.
    fn scratch_bytes(&self) -> u64 {
        self.size.0 as u64 * self.size.1 as u64 * TRANSIENT_BYTES
    }

    fn use_scratch(&mut self, _gpu: &Gpu, scratch: &wgpu::Buffer) -> Result<(), GpuError> {
        if self.transient.shared && self.transient.buffer == *scratch {
            // Already there: keep the bind groups and the history.
            return Ok(());
        }
        solari_scene::scratch::check("fallback denoiser", scratch, self.scratch_bytes())?;
        self.transient = Region {
            buffer: scratch.clone(),
            shared: true,
            stride: TRANSIENT_BYTES,
        };
        if self.second_shares() {
            self.second = Region {
                buffer: scratch.clone(),
                shared: true,
                stride: 16,
            };
        }
        // Rebind on the next frame (which restarts history).
        self.bound_to.clear();
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        let pixels = self.size.0 as u64 * self.size.1 as u64;
        let regions: u64 = [&self.second, &self.transient]
            .into_iter()
            .filter(|r| !r.shared)
            .map(|r| r.buffer.size())
            .sum();
        let buffers: u64 = regions
            + [&self.output, &self.guide, &self.params]
                .into_iter()
                .chain(&self.split_output)
                .chain(self.pass_params.iter().flatten())
                .map(|b| b.size())
                .sum::<u64>();
        // Histories are made on the first frame, one per signal: count at least one.
        let signals = self.signals.len().max(1) as u64;
        buffers + signals * pixels * HISTORY_BYTES
    }
}
