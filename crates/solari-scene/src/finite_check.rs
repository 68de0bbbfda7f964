//! The non-finite detector: counts NaN/infinite values, negative values where a quantity
//! cannot be negative (radiance, weights, probabilities), and values over a stated bound
//! (overflows, such as a reservoir's confidence above its cap), in each pass's output, on
//! the GPU, every frame.
//!
//! A renderer registers its passes as *slots* (in frame order) and, after recording a pass,
//! records a check of each of that pass's outputs into the pass's slot. One compute dispatch
//! per output reads it once (a workgroup adds its counts to the slot with one atomic), so
//! the cost is a read of each checked buffer: about 0.1 ms for a few hundred MB on the H200.
//! The counts come back with [`FiniteChecker::read`]; the first slot with a non-zero count
//! names the pass that produced the first bad value of the frame (a later pass that merely
//! reads it counts too, which is why order matters).
//!
//! WGSL side: `shaders/finite_check*.wesl`.

use crate::error::GpuError;
use crate::gpu::{Gpu, ShaderChecks};
use crate::shaders::{Backend, compose};
use bytemuck::{Pod, Zeroable};
use std::collections::HashMap;

/// Rust twin of `CheckParams` in `finite_check.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuCheckParams {
    /// Records (buffers) or texture width.
    pub count: u32,
    /// Texture height; 1 for buffers.
    pub rows: u32,
    /// 32-bit words per record.
    pub stride_words: u32,
    /// Bit i: word/channel i is an f32 to check.
    pub float_mask: u32,
    /// Bit i: word/channel i must not be negative either.
    pub non_negative_mask: u32,
    /// The slot's counters.
    pub slot: u32,
    /// Bit i: word/channel i must not exceed `upper_bound` either.
    pub upper_mask: u32,
    /// The bound of `upper_mask`'s values.
    pub upper_bound: f32,
}

const _: () = assert!(size_of::<GpuCheckParams>() == 32);

/// Which 32-bit words of each record of a buffer to check.
#[derive(Clone, Copy, Debug)]
pub struct RecordLayout {
    /// Words per record (1 to 32).
    pub stride_words: u32,
    /// Bit i: word i is an f32 (checked for NaN and infinity).
    pub float_mask: u32,
    /// Bit i: word i must not be negative (a subset of `float_mask`).
    pub non_negative_mask: u32,
    /// Bit i: word i must not exceed `upper_bound` (a subset of `float_mask`); counted as
    /// overflows, apart from non-finite values.
    pub upper_mask: u32,
    /// The bound for `upper_mask`.
    pub upper_bound: f32,
}

impl PartialEq for RecordLayout {
    fn eq(&self, o: &Self) -> bool {
        self.key() == o.key()
    }
}

impl Eq for RecordLayout {}

impl std::hash::Hash for RecordLayout {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.key().hash(state);
    }
}

impl RecordLayout {
    /// `vec4<f32>` records whose four values are all non-negative (radiance and a weight).
    pub const RGBA_NON_NEGATIVE: Self = Self {
        stride_words: 4,
        float_mask: 0xf,
        non_negative_mask: 0xf,
        upper_mask: 0,
        upper_bound: 0.0,
    };

    fn key(&self) -> [u32; 5] {
        [
            self.stride_words,
            self.float_mask,
            self.non_negative_mask,
            self.upper_mask,
            self.upper_bound.to_bits(),
        ]
    }
}

/// Non-finite and negative counts of one slot in one frame.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FiniteCount {
    /// The slot's name (a pass).
    pub name: String,
    /// NaN or infinite values.
    pub non_finite: u64,
    /// Negative values where only non-negative ones are valid.
    pub negative: u64,
    /// Finite values over their stated bound (overflows; not counted by [`Self::is_clean`]).
    pub over: u64,
}

impl FiniteCount {
    /// Whether no non-finite or negative value was found.
    pub fn is_clean(&self) -> bool {
        self.non_finite == 0 && self.negative == 0
    }
}

/// The first slot of `counts` with a finding, in frame order.
pub fn first_offender(counts: &[FiniteCount]) -> Option<&FiniteCount> {
    counts.iter().find(|c| !c.is_clean())
}

#[derive(Clone, PartialEq, Eq, Hash)]
enum Source {
    Buffer(wgpu::Buffer, u64, RecordLayout),
    Texture(wgpu::Texture, u32, u32),
}

/// The detector: slots, counters, pipelines and the bind groups of every output checked so
/// far (kept, since the same resources come back every frame or every other frame).
pub struct FiniteChecker {
    names: Vec<String>,
    counters: wgpu::Buffer,
    // One read-back buffer per frame in flight, used in turn.
    readbacks: Vec<wgpu::Buffer>,
    next_readback: usize,
    buffer_pipeline: wgpu::ComputePipeline,
    texture_pipeline: wgpu::ComputePipeline,
    layouts: [wgpu::BindGroupLayout; 2],
    groups: HashMap<(usize, Source), (wgpu::BindGroup, [u32; 3])>,
}

fn entry(binding: u32, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty,
        count: None,
    }
}

fn buffer_entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    entry(
        binding,
        wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
    )
}

impl FiniteChecker {
    /// Builds the pipelines and the counters for `slots` (pass names, in frame order), for
    /// one frame at a time.
    pub fn new(gpu: &Gpu, slots: &[&str]) -> Result<Self, GpuError> {
        Self::with_frames_in_flight(gpu, slots, 1)
    }

    /// As [`FiniteChecker::new`], with a read-back buffer for each of `frames` frames in
    /// flight, so a frame's counts can be read while later frames run
    /// ([`FiniteChecker::end_frame`] says which buffer a frame used).
    pub fn with_frames_in_flight(
        gpu: &Gpu,
        slots: &[&str],
        frames: usize,
    ) -> Result<Self, GpuError> {
        let wgsl = ["buffer", "texture"]
            .map(|kind| compose(&format!("finite_check_{kind}"), Backend::Software, &[]));
        let [wgsl_buffer, wgsl_texture] = wgsl;
        let wgsl = [wgsl_buffer?, wgsl_texture?];
        let common = [
            buffer_entry(0, wgpu::BufferBindingType::Uniform),
            buffer_entry(1, wgpu::BufferBindingType::Storage { read_only: false }),
        ];
        let data = [
            buffer_entry(2, wgpu::BufferBindingType::Storage { read_only: true }),
            entry(
                3,
                wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
            ),
        ];
        let layouts = data.map(|d| {
            gpu.device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("solari_scene/finite_check"),
                    entries: &[common[0], common[1], d],
                })
        });
        let pipeline =
            |module: &wgpu::ShaderModule, layout: &wgpu::BindGroupLayout, label: &str| {
                let pl = gpu
                    .device
                    .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                        label: Some("solari_scene/finite_check"),
                        bind_group_layouts: &[Some(layout)],
                        immediate_size: 0,
                    });
                gpu.device
                    .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                        label: Some(label),
                        layout: Some(&pl),
                        module,
                        entry_point: Some("main"),
                        compilation_options: Default::default(),
                        cache: None,
                    })
            };
        let (buffer_pipeline, texture_pipeline) = gpu.scoped(|| {
            let pipeline = |i: usize, label: &str| {
                let module = gpu.shader_module(label, &wgsl[i], ShaderChecks::BoundsOnly);
                pipeline(&module, &layouts[i], label)
            };
            (
                pipeline(0, "solari_scene/finite_check_buffer"),
                pipeline(1, "solari_scene/finite_check_texture"),
            )
        })?;
        let bytes = (slots.len().max(1) * 12) as u64;
        let counters = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solari_scene/finite_counters"),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let readbacks = (0..frames.max(1))
            .map(|_| {
                gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("solari_scene/finite_readback"),
                    size: bytes,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            })
            .collect();
        Ok(Self {
            names: slots.iter().map(|s| s.to_string()).collect(),
            counters,
            readbacks,
            next_readback: 0,
            buffer_pipeline,
            texture_pipeline,
            layouts,
            groups: HashMap::new(),
        })
    }

    /// The slot names, in frame order.
    pub fn slots(&self) -> &[String] {
        &self.names
    }

    /// The index of slot `name`.
    pub fn slot(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// Zeroes the counters; record it before the frame's first check.
    pub fn begin_frame(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.counters, 0, None);
    }

    /// Checks the first `records` records of `buffer` (which needs `STORAGE` usage) laid out
    /// as `layout`, into `slot`.
    pub fn check_buffer(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        slot: usize,
        buffer: &wgpu::Buffer,
        records: u64,
        layout: RecordLayout,
    ) -> Result<(), GpuError> {
        if records == 0 {
            return Ok(());
        }
        if !(1..=32).contains(&layout.stride_words)
            || records * layout.stride_words as u64 * 4 > buffer.size()
            || records > u32::MAX as u64
        {
            return Err(GpuError::Validation(format!(
                "finite check of {:?}: {records} records of {} words do not fit its {} bytes",
                self.names.get(slot),
                layout.stride_words,
                buffer.size()
            )));
        }
        let groups = records.div_ceil(256);
        let x = groups.min(65535) as u32;
        let y = groups.div_ceil(x as u64) as u32;
        let params = GpuCheckParams {
            count: records as u32,
            rows: 1,
            stride_words: layout.stride_words,
            float_mask: layout.float_mask,
            non_negative_mask: layout.non_negative_mask & layout.float_mask,
            slot: slot as u32,
            upper_mask: layout.upper_mask & layout.float_mask,
            upper_bound: layout.upper_bound,
        };
        let key = (slot, Source::Buffer(buffer.clone(), records, layout));
        self.record(
            gpu,
            encoder,
            key,
            params,
            [x, y, 1],
            |gpu, layout, uniform, counters| {
                gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("solari_scene/finite_check"),
                    layout,
                    entries: &[bind(0, uniform), bind(1, counters), bind(2, buffer)],
                })
            },
        )
    }

    /// Checks a float colour texture (`Rgba16Float`, `Rg16Float`, `Rgba32Float`…): channels in
    /// `float_mask` for NaN/infinity, those in `non_negative_mask` for negative values too.
    pub fn check_texture(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        slot: usize,
        texture: &wgpu::Texture,
        float_mask: u32,
        non_negative_mask: u32,
    ) -> Result<(), GpuError> {
        let (w, h) = (texture.width(), texture.height());
        let params = GpuCheckParams {
            count: w,
            rows: h,
            stride_words: 4,
            float_mask: float_mask & 0xf,
            non_negative_mask: non_negative_mask & float_mask & 0xf,
            slot: slot as u32,
            upper_mask: 0,
            upper_bound: 0.0,
        };
        let key = (
            slot,
            Source::Texture(texture.clone(), float_mask, non_negative_mask),
        );
        let dispatch = [w.div_ceil(16), h.div_ceil(16), 1];
        self.record(
            gpu,
            encoder,
            key,
            params,
            dispatch,
            |gpu, layout, uniform, counters| {
                let view = texture.create_view(&Default::default());
                gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("solari_scene/finite_check"),
                    layout,
                    entries: &[
                        bind(0, uniform),
                        bind(1, counters),
                        wgpu::BindGroupEntry {
                            binding: 3,
                            resource: wgpu::BindingResource::TextureView(&view),
                        },
                    ],
                })
            },
        )
    }

    fn record(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        key: (usize, Source),
        params: GpuCheckParams,
        dispatch: [u32; 3],
        make: impl FnOnce(&Gpu, &wgpu::BindGroupLayout, &wgpu::Buffer, &wgpu::Buffer) -> wgpu::BindGroup,
    ) -> Result<(), GpuError> {
        if key.0 >= self.names.len() {
            return Err(GpuError::Validation(format!(
                "finite check: slot {} of {}",
                key.0,
                self.names.len()
            )));
        }
        let kind = match key.1 {
            Source::Buffer(..) => 0,
            Source::Texture(..) => 1,
        };
        if !self.groups.contains_key(&key) {
            // Resized or rebuilt resources leave stale entries; the live set is small.
            if self.groups.len() >= 256 {
                self.groups.clear();
            }
            let uniform = gpu.uniform_buffer("solari_scene/finite_check_params", &params);
            let group = make(gpu, &self.layouts[kind], &uniform, &self.counters);
            self.groups.insert(key.clone(), (group, dispatch));
        }
        let (group, dispatch) = &self.groups[&key];
        let pipeline = [&self.buffer_pipeline, &self.texture_pipeline][kind];
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("solari_scene/finite_check"),
            timestamp_writes: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(dispatch[0], dispatch[1], dispatch[2]);
        Ok(())
    }

    /// Copies the counters for [`FiniteChecker::read`]; record it after the frame's last check.
    /// Returns the read-back buffer used, for [`FiniteChecker::read_frame`].
    pub fn end_frame(&mut self, encoder: &mut wgpu::CommandEncoder) -> usize {
        let slot = self.next_readback;
        self.next_readback = (slot + 1) % self.readbacks.len();
        let readback = &self.readbacks[slot];
        encoder.copy_buffer_to_buffer(&self.counters, 0, readback, 0, self.counters.size());
        slot
    }

    /// The counts of the last frame ended, per slot in frame order. Blocks until the GPU is
    /// done with all submitted work.
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<FiniteCount>, GpuError> {
        let n = self.readbacks.len();
        self.read_frame(gpu, (self.next_readback + n - 1) % n, None)
    }

    /// The counts of the frame whose [`FiniteChecker::end_frame`] returned `readback`, once
    /// `submission` (the submission that holds that frame) has finished; later frames keep
    /// running.
    pub fn read_frame(
        &self,
        gpu: &Gpu,
        readback: usize,
        submission: Option<wgpu::SubmissionIndex>,
    ) -> Result<Vec<FiniteCount>, GpuError> {
        let bytes = gpu.map_read_after(&self.readbacks[readback], submission)?;
        let words: &[u32] = bytemuck::cast_slice(&bytes);
        Ok(self
            .names
            .iter()
            .enumerate()
            .map(|(i, name)| FiniteCount {
                name: name.clone(),
                non_finite: words[3 * i] as u64,
                negative: words[3 * i + 1] as u64,
                over: words[3 * i + 2] as u64,
            })
            .collect())
    }
}

fn bind(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}
