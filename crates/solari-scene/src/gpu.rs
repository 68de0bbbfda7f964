//! GPU context creation and the small helpers every pass and test shares: buffer creation,
//! readback and validation error scopes.

use crate::error::GpuError;
use crate::shaders::Backend;
use std::sync::{Arc, Mutex};

/// Features used when the adapter has them; none is required.
pub const OPTIONAL_FEATURES: wgpu::Features = wgpu::Features::EXPERIMENTAL_RAY_QUERY
    .union(wgpu::Features::TIMESTAMP_QUERY)
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES)
    // Rg16Float storage, for the traced G-buffer's motion vectors.
    .union(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES);

/// The wgpu runtime checks a shader module is compiled with.
///
/// wgpu's forced loop bounding costs the software traversal about 45% of its speed on an H200
/// (bounds checks cost under 1%; `benches/RESULTS.md`), so solari's passes use
/// [`ShaderChecks::BoundsOnly`] and guarantee termination themselves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaderChecks {
    /// wgpu's defaults: bounds checks and forced loop bounding.
    All,
    /// Every check but forced loop bounding. For shaders in which every loop provably ends, as
    /// solari's do.
    BoundsOnly,
    /// No checks at all: for measuring what the checks cost, not for shipping.
    None,
}

impl ShaderChecks {
    /// Short name used in benchmark output.
    pub fn name(self) -> &'static str {
        match self {
            ShaderChecks::All => "all",
            ShaderChecks::BoundsOnly => "bounds",
            ShaderChecks::None => "none",
        }
    }
}

/// A write-only 2D storage texture for compute shaders.
pub fn storage_texture_layout_entry(
    binding: u32,
    format: wgpu::TextureFormat,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
        count: None,
    }
}

/// A 2D float texture read with `textureLoad` (unfilterable), visible to `visibility`.
pub fn loaded_texture_layout_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

/// A whole-buffer bind group layout entry (no dynamic offset, no minimum size).
pub fn buffer_layout_entry(
    binding: u32,
    ty: wgpu::BufferBindingType,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// How to choose the tracing backend.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TracerChoice {
    /// Ray queries when the adapter has them, else software (default).
    #[default]
    Auto,
    /// Force one backend.
    Force(Backend),
}

impl TracerChoice {
    /// Parses `auto`, `ray-query` or `software`.
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "auto" => Self::Auto,
            "ray-query" | "rayquery" | "ray_query" => Self::Force(Backend::RayQuery),
            "software" | "sw" => Self::Force(Backend::Software),
            _ => return None,
        })
    }

    /// The `SOLARI_TRACER` environment variable, if set, overrides `self`.
    pub fn with_env_override(self) -> Result<Self, String> {
        match std::env::var("SOLARI_TRACER") {
            Ok(v) if !v.is_empty() => Self::parse(&v)
                .ok_or_else(|| format!("SOLARI_TRACER={v}: expected auto, ray-query or software")),
            _ => Ok(self),
        }
    }
}

/// Device, queue and what the adapter can do.
pub struct Gpu {
    /// The wgpu instance.
    pub instance: wgpu::Instance,
    /// The chosen adapter.
    pub adapter: wgpu::Adapter,
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Adapter name, driver and backend.
    pub info: wgpu::AdapterInfo,
    /// Features enabled on the device.
    pub features: wgpu::Features,
    /// wgpu errors raised outside any error scope, recorded instead of panicking (wgpu's
    /// default); [`Gpu::check_errors`] turns them into an error.
    uncaptured: Arc<Mutex<Vec<String>>>,
    // Set by `test_gpu`: dropping the device with wgpu errors that nobody checked panics, so
    // a test whose GPU work was refused cannot pass on the data it never wrote.
    strict: bool,
}

impl Drop for Gpu {
    fn drop(&mut self) {
        if !self.strict || std::thread::panicking() {
            return;
        }
        let errors = self
            .uncaptured
            .lock()
            .map(|v| v.clone())
            .unwrap_or_default();
        if !errors.is_empty() {
            panic!(
                "{} wgpu error(s) nobody checked (Gpu::check_errors) during this test; the \
                 first: {}",
                errors.len(),
                errors[0]
            );
        }
    }
}

/// Environment variable that chooses the adapter on a machine with several: an index into
/// the enumeration order (`0`, `1`, ...; `RUST_LOG=info` lists them) or a case-insensitive
/// part of the adapter's name. Unset, the best adapter is taken.
pub const ADAPTER_ENV: &str = "SOLARI_ADAPTER";

/// As [`choose_adapter`], among the adapters marked in `usable` (one flag per adapter): the
/// best usable one, or the requested one if it is usable. A request for an unusable adapter
/// is an error naming it, never a silent switch to another.
pub fn choose_usable_adapter(
    adapters: &[wgpu::AdapterInfo],
    usable: &[bool],
    request: Option<&str>,
) -> Result<usize, GpuError> {
    assert_eq!(adapters.len(), usable.len(), "one flag per adapter");
    if request.is_some() {
        let i = choose_adapter(adapters, request)?;
        if !usable[i] {
            return Err(GpuError::AdapterRequest(format!(
                "{ADAPTER_ENV}={}: adapter {i}, {}, cannot be used here (it cannot present \
                 to the window)",
                request.unwrap_or_default().trim(),
                adapters[i].name
            )));
        }
        return Ok(i);
    }
    let kept: Vec<usize> = (0..adapters.len()).filter(|&i| usable[i]).collect();
    if kept.is_empty() {
        if adapters.is_empty() {
            return Err(GpuError::NoAdapter("none enumerated".into()));
        }
        let names: Vec<&str> = adapters.iter().map(|a| a.name.as_str()).collect();
        return Err(GpuError::NoAdapter(format!(
            "none of the {} adapter(s) can be used here (they cannot present to the window): {}",
            adapters.len(),
            names.join(", ")
        )));
    }
    let infos: Vec<wgpu::AdapterInfo> = kept.iter().map(|&i| adapters[i].clone()).collect();
    Ok(kept[choose_adapter(&infos, None)?])
}

/// Which of `adapters` to use: with `request` (the value of [`ADAPTER_ENV`]) an index or a
/// case-insensitive part of a name, matched exactly as asked (a request no adapter matches is
/// an error that lists them, never a silent fallback, so a benchmark meant for the second
/// GPU cannot run on the first); without it the best by device type (discrete over
/// integrated over virtual over CPU, the first of equals).
pub fn choose_adapter(
    adapters: &[wgpu::AdapterInfo],
    request: Option<&str>,
) -> Result<usize, GpuError> {
    for (i, a) in adapters.iter().enumerate() {
        log::info!(
            "adapter {i}: {} ({:?}, {:?})",
            a.name,
            a.device_type,
            a.backend
        );
    }
    if adapters.is_empty() {
        return Err(GpuError::NoAdapter("none enumerated".into()));
    }
    let list = || {
        adapters
            .iter()
            .enumerate()
            .map(|(i, a)| format!("{i}: {}", a.name))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let Some(request) = request.map(str::trim) else {
        let rank = |a: &wgpu::AdapterInfo| match a.device_type {
            wgpu::DeviceType::DiscreteGpu => 0,
            wgpu::DeviceType::IntegratedGpu => 1,
            wgpu::DeviceType::VirtualGpu => 2,
            wgpu::DeviceType::Cpu => 3,
            wgpu::DeviceType::Other => 4,
        };
        return Ok((0..adapters.len())
            .min_by_key(|&i| rank(&adapters[i]))
            .unwrap_or(0));
    };
    if let Ok(i) = request.parse::<usize>() {
        return if i < adapters.len() {
            Ok(i)
        } else {
            Err(GpuError::AdapterRequest(format!(
                "{ADAPTER_ENV}={request}: only {} adapter(s): {}",
                adapters.len(),
                list()
            )))
        };
    }
    let needle = request.to_lowercase();
    if needle.is_empty() {
        return Err(GpuError::AdapterRequest(format!(
            "{ADAPTER_ENV} is empty: give an index or part of a name ({})",
            list()
        )));
    }
    adapters
        .iter()
        .position(|a| a.name.to_lowercase().contains(&needle))
        .ok_or_else(|| {
            GpuError::AdapterRequest(format!(
                "{ADAPTER_ENV}={request} matches no adapter name: {}",
                list()
            ))
        })
}

impl Gpu {
    /// Creates a device on the best adapter (discrete over integrated over CPU), with every
    /// optional feature the adapter offers and the adapter's own limits. Vulkan, Metal and
    /// DX12 are tried (GL is skipped: it has no storage buffers in compute on some drivers);
    /// `WGPU_BACKEND` overrides.
    pub fn new() -> Result<Self, GpuError> {
        let instance = wgpu::Instance::new(Self::instance_descriptor());
        let adapter = Self::pick_adapter(&instance)?;
        let (device, queue) =
            pollster::block_on(adapter.request_device(&Self::device_descriptor(&adapter)))
                .map_err(|source| GpuError::RequestDevice {
                    adapter: adapter.get_info().name,
                    source,
                })?;
        Ok(Self::from_parts(instance, adapter, device, queue))
    }

    /// As [`Gpu::new`], without `features` even where the adapter has them: to run as on an
    /// adapter that lacks them (tests of fall-backs), or to keep a driver's broken feature
    /// out. Leaving out [`wgpu::Features::TIMESTAMP_QUERY`] leaves out the timestamp
    /// features that depend on it too (inside encoders and passes).
    pub fn new_without(features: wgpu::Features) -> Result<Self, GpuError> {
        let mut features = features;
        if features.contains(wgpu::Features::TIMESTAMP_QUERY) {
            features |= wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
                | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES;
        }
        let instance = wgpu::Instance::new(Self::instance_descriptor());
        let adapter = Self::pick_adapter(&instance)?;
        let mut descriptor = Self::device_descriptor(&adapter);
        descriptor.required_features = descriptor.required_features.difference(features);
        let (device, queue) =
            pollster::block_on(adapter.request_device(&descriptor)).map_err(|source| {
                GpuError::RequestDevice {
                    adapter: adapter.get_info().name,
                    source,
                }
            })?;
        Ok(Self::from_parts(instance, adapter, device, queue))
    }

    /// The instance [`Gpu::new`] creates: primary backends unless `WGPU_BACKEND` says
    /// otherwise, flags from the environment. Public so integrations that must create the
    /// instance themselves (DLSS registers Vulkan extensions) start from the same one.
    pub fn instance_descriptor() -> wgpu::InstanceDescriptor {
        wgpu::InstanceDescriptor {
            backends: wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY),
            flags: wgpu::InstanceFlags::from_env_or_default(),
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        }
    }

    /// The adapter [`Gpu::new`] uses: the one `SOLARI_ADAPTER` names (see
    /// [`choose_adapter`]), else the best: discrete over integrated over virtual over CPU.
    pub fn pick_adapter(instance: &wgpu::Instance) -> Result<wgpu::Adapter, GpuError> {
        Self::pick_adapter_where(instance, |_| true)
    }

    /// As [`Gpu::pick_adapter`], among the adapters `usable` accepts (a window's: those that
    /// can present to its surface), so a machine whose best GPU cannot present still gets
    /// the next one ([`choose_usable_adapter`]).
    pub fn pick_adapter_where(
        instance: &wgpu::Instance,
        usable: impl Fn(&wgpu::Adapter) -> bool,
    ) -> Result<wgpu::Adapter, GpuError> {
        let backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
        let mut adapters = pollster::block_on(instance.enumerate_adapters(backends));
        let infos: Vec<wgpu::AdapterInfo> = adapters.iter().map(|a| a.get_info()).collect();
        let accepted: Vec<bool> = adapters.iter().map(usable).collect();
        let request = std::env::var(ADAPTER_ENV).ok();
        let index =
            choose_usable_adapter(&infos, &accepted, request.as_deref()).map_err(|e| match e {
                GpuError::NoAdapter(why) => {
                    GpuError::NoAdapter(format!("{why}; backends {backends:?}"))
                }
                other => other,
            })?;
        if request.is_some() || accepted.iter().any(|a| !a) {
            log::info!("using adapter {index}, {}", infos[index].name);
        }
        Ok(adapters.swap_remove(index))
    }

    /// What [`Gpu::new`] asks of `adapter`: every feature of [`OPTIONAL_FEATURES`] it has
    /// (ray queries through wgpu's experimental API) and its own limits.
    pub fn device_descriptor(adapter: &wgpu::Adapter) -> wgpu::DeviceDescriptor<'static> {
        let features = adapter.features() & OPTIONAL_FEATURES;
        let experimental = if features.contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY) {
            // SAFETY: ray queries are wgpu's "experimental" API; we accept that it may have
            // driver bugs, and the software backend gives the same results to compare with.
            unsafe { wgpu::ExperimentalFeatures::enabled() }
        } else {
            wgpu::ExperimentalFeatures::disabled()
        };
        wgpu::DeviceDescriptor {
            label: Some("solari"),
            required_features: features,
            required_limits: adapter.limits(),
            experimental_features: experimental,
            ..Default::default()
        }
    }

    /// Wraps a device created elsewhere (for example through `dlss_wgpu`); the features are
    /// read back from the device.
    pub fn from_parts(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
        device: wgpu::Device,
        queue: wgpu::Queue,
    ) -> Self {
        let info = adapter.get_info();
        let features = device.features();
        let uncaptured = Arc::new(Mutex::new(Vec::new()));
        let sink = uncaptured.clone();
        // wgpu panics on an error outside an error scope; an over-limit request from user
        // input (a huge image size) must become an error message instead.
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            log::error!("wgpu: {e}");
            if let Ok(mut v) = sink.lock()
                && v.len() < 64
            {
                v.push(e.to_string());
            }
        }));
        Self {
            instance,
            adapter,
            device,
            queue,
            info,
            features,
            uncaptured,
            strict: false,
        }
    }

    /// The first wgpu error raised outside an error scope since the last call, as
    /// [`GpuError::Wgpu`] (all of them are cleared).
    pub fn check_errors(&self) -> Result<(), GpuError> {
        let mut v = self
            .uncaptured
            .lock()
            .map_err(|e| GpuError::Wgpu(e.to_string()))?;
        match v.drain(..).next() {
            Some(first) => Err(GpuError::Wgpu(first)),
            None => Ok(()),
        }
    }

    /// Whether the device can trace with ray queries.
    pub fn has_ray_query(&self) -> bool {
        self.features
            .contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY)
    }

    /// Resolves a tracer choice against this device.
    pub fn backend(&self, choice: TracerChoice) -> Result<Backend, GpuError> {
        match choice {
            TracerChoice::Auto if self.has_ray_query() => Ok(Backend::RayQuery),
            TracerChoice::Auto => Ok(Backend::Software),
            TracerChoice::Force(Backend::RayQuery) if !self.has_ray_query() => {
                Err(GpuError::NoRayQuery(self.info.name.clone()))
            }
            TracerChoice::Force(b) => Ok(b),
        }
    }

    /// Runs `f` inside a validation error scope and turns a captured error into `Err`.
    pub fn scoped<T>(&self, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = f();
        match pollster::block_on(scope.pop()) {
            Some(e) => Err(GpuError::Wgpu(e.to_string())),
            None => Ok(value),
        }
    }

    /// Refuses `needed` bytes for `what` ([`GpuError::OverLimit`], both sizes named) when a
    /// storage binding that large is over the device's limit: call it before allocating a
    /// buffer that is bound whole.
    pub fn check_storage_binding(&self, what: &str, needed: u64) -> Result<(), GpuError> {
        let limit = self.device.limits().max_storage_buffer_binding_size;
        if needed > limit {
            return Err(GpuError::OverLimit {
                what: what.to_string(),
                needed,
                limit,
            });
        }
        Ok(())
    }

    /// A storage buffer holding `data` (at least 16 bytes, so empty arrays still bind),
    /// checked against the device's binding limit.
    pub fn storage_buffer(
        &self,
        label: &str,
        data: &[u8],
        extra: wgpu::BufferUsages,
    ) -> Result<wgpu::Buffer, GpuError> {
        self.check_storage_binding(label, data.len() as u64)?;
        let size = (data.len() as u64).max(16).next_multiple_of(4);
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | extra,
            mapped_at_creation: false,
        });
        if !data.is_empty() {
            let mut padded = data.to_vec();
            padded.resize(data.len().next_multiple_of(4), 0);
            self.queue.write_buffer(&buffer, 0, &padded);
        }
        Ok(buffer)
    }

    /// A uniform buffer holding `value`, writable later with `queue.write_buffer`.
    pub fn uniform_buffer<T: bytemuck::Pod>(&self, label: &str, value: &T) -> wgpu::Buffer {
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: size_of::<T>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.queue
            .write_buffer(&buffer, 0, bytemuck::bytes_of(value));
        buffer
    }

    /// A 2D texture of one mip level and one layer: what render targets, G-buffers and test
    /// images are.
    pub fn texture_2d(
        &self,
        label: &str,
        (width, height): (u32, u32),
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> wgpu::Texture {
        self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    }

    /// [`Gpu::texture_2d`] filled with `texels` (tightly packed rows, top row first, in the
    /// format's texel layout); `COPY_DST` is added to `usage`. Panics when `texels` is not
    /// exactly one texel per pixel: a caller bug, never user input.
    pub fn texture_2d_with(
        &self,
        label: &str,
        size: (u32, u32),
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
        texels: &[u8],
    ) -> wgpu::Texture {
        let texel_bytes = format
            .block_copy_size(None)
            .expect("an uncompressed colour format");
        assert_eq!(
            texels.len() as u64,
            size.0 as u64 * size.1 as u64 * texel_bytes as u64,
            "{label}: texel data for {}x{} {format:?}",
            size.0,
            size.1
        );
        let texture = self.texture_2d(label, size, format, usage | wgpu::TextureUsages::COPY_DST);
        self.queue.write_texture(
            texture.as_image_copy(),
            texels,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(size.0 * texel_bytes),
                rows_per_image: Some(size.1),
            },
            texture.size(),
        );
        texture
    }

    /// Copies `size` bytes of `buffer` (which needs `COPY_SRC`) back to the CPU. Blocks.
    pub fn read_buffer(&self, buffer: &wgpu::Buffer, size: u64) -> Result<Vec<u8>, GpuError> {
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solari/readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        self.queue.submit([encoder.finish()]);
        self.map_read(&staging)
    }

    /// Waits for the GPU, then maps a `MAP_READ` buffer and returns its bytes (unmapping it
    /// again, so it can be reused). For read-back buffers a pass keeps across frames.
    pub fn map_read(&self, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        self.map_read_after(buffer, None)
    }

    /// Blocks until `submission` has finished on the GPU (and its buffer mappings have been
    /// delivered), leaving later submissions running.
    pub fn wait_for(&self, submission: wgpu::SubmissionIndex) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(submission),
                timeout: None,
            })
            .map(drop)
            .map_err(|e| GpuError::Readback(e.to_string()))
    }

    /// As [`Gpu::map_read`], waiting only for `submission` (the last one that wrote `buffer`)
    /// rather than for all queued work: frames submitted since keep running.
    pub fn map_read_after(
        &self,
        buffer: &wgpu::Buffer,
        submission: Option<wgpu::SubmissionIndex>,
    ) -> Result<Vec<u8>, GpuError> {
        let (tx, rx) = std::sync::mpsc::channel();
        buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: submission,
                timeout: None,
            })
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        rx.recv()
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let data = buffer
            .slice(..)
            .get_mapped_range()
            .map_err(|e| GpuError::Readback(format!("{e:?}")))?
            .to_vec();
        buffer.unmap();
        Ok(data)
    }

    /// Copies mip 0 of a 2D `texture` (which needs `COPY_SRC`) back to the CPU, `aspect`
    /// only, rows tightly packed (the copy's 256-byte row padding removed). Blocks.
    pub fn read_texture(
        &self,
        texture: &wgpu::Texture,
        aspect: wgpu::TextureAspect,
    ) -> Result<Vec<u8>, GpuError> {
        let texel = texture
            .format()
            .block_copy_size(Some(aspect))
            .ok_or_else(|| {
                GpuError::Readback(format!(
                    "{:?} has no single copy size for {aspect:?}",
                    texture.format()
                ))
            })?;
        let (w, h) = (texture.width(), texture.height());
        let row = (w * texel).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solari/texture_readback"),
            size: row as u64 * h as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(h),
                },
            },
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
        self.queue.submit([encoder.finish()]);
        let padded = self.read_buffer(&buffer, row as u64 * h as u64)?;
        Ok(padded
            .chunks(row as usize)
            .flat_map(|r| r[..(w * texel) as usize].iter().copied())
            .collect())
    }

    /// A layout of whole-buffer bindings 0, 1, … of the given types, visible to compute.
    pub fn buffer_layout(
        &self,
        label: &str,
        types: &[wgpu::BufferBindingType],
    ) -> wgpu::BindGroupLayout {
        let entries: Vec<_> = types
            .iter()
            .enumerate()
            .map(|(i, ty)| buffer_layout_entry(i as u32, *ty, wgpu::ShaderStages::COMPUTE))
            .collect();
        self.device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &entries,
            })
    }

    /// A bind group with `buffers` bound whole at bindings 0, 1, ….
    pub fn bind_buffers(
        &self,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        buffers: &[&wgpu::Buffer],
    ) -> wgpu::BindGroup {
        let entries: Vec<_> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout,
            entries: &entries,
        })
    }

    /// An empty layout and its bind group, for group slots a pipeline does not use.
    pub fn empty_group(&self) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
        let layout = self
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("solari/empty"),
                entries: &[],
            });
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("solari/empty"),
            layout: &layout,
            entries: &[],
        });
        (layout, group)
    }

    /// Runs a kernel with one invocation per case and reads its results back: `cases` go to
    /// binding 0 and `cases.len()` values of `O` come from binding 1 of `io_layout`, bound at
    /// the `None` slot of `groups`. Workgroups are 64 wide and fold into y past 65,535, so the
    /// kernel indexes `id.x + id.y * num_workgroups.x * 64`. The GPU-twin tests (through
    /// [`crate::case_kernel::CaseKernel`]) and the trace pass use it.
    pub fn run_cases<I: bytemuck::Pod, O: bytemuck::Pod>(
        &self,
        label: &str,
        pipeline: &wgpu::ComputePipeline,
        io_layout: &wgpu::BindGroupLayout,
        groups: &[Option<&wgpu::BindGroup>],
        cases: &[I],
    ) -> Result<Vec<O>, GpuError> {
        if cases.is_empty() {
            return Ok(Vec::new());
        }
        let input = self.storage_buffer(
            label,
            bytemuck::cast_slice(cases),
            wgpu::BufferUsages::empty(),
        )?;
        let out_bytes = (cases.len() * size_of::<O>()) as u64;
        self.check_storage_binding(&format!("{label} results"), out_bytes)?;
        let output = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: out_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let io = self.bind_buffers(label, io_layout, &[&input, &output]);
        let bound: Vec<&wgpu::BindGroup> = groups.iter().map(|g| g.unwrap_or(&io)).collect();
        let workgroups = (cases.len() as u32).div_ceil(64);
        let x = workgroups.min(65535);
        self.dispatch(label, pipeline, &bound, [x, workgroups.div_ceil(x), 1])?;
        let bytes = self.read_buffer(&output, out_bytes)?;
        Ok(bytemuck::cast_slice(&bytes).to_vec())
    }

    /// Records one compute dispatch with `bind_groups` at groups 0, 1, … and submits it,
    /// inside a validation scope. Blocks only on validation, not on the GPU.
    pub fn dispatch(
        &self,
        label: &str,
        pipeline: &wgpu::ComputePipeline,
        bind_groups: &[&wgpu::BindGroup],
        workgroups: [u32; 3],
    ) -> Result<(), GpuError> {
        self.scoped(|| {
            let mut encoder = self.device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(label),
                    timestamp_writes: None,
                });
                pass.set_pipeline(pipeline);
                for (i, group) in bind_groups.iter().enumerate() {
                    pass.set_bind_group(i as u32, *group, &[]);
                }
                pass.dispatch_workgroups(workgroups[0], workgroups[1], workgroups[2]);
            }
            self.queue.submit([encoder.finish()]);
        })
    }

    /// A shader module from composed WGSL with the given runtime checks (errors surface in the
    /// caller's error scope: see [`Gpu::scoped`]).
    pub fn shader_module(
        &self,
        label: &str,
        wgsl: &str,
        checks: ShaderChecks,
    ) -> wgpu::ShaderModule {
        let desc = wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(wgsl.into()),
        };
        match checks {
            ShaderChecks::All => self.device.create_shader_module(desc),
            ShaderChecks::BoundsOnly | ShaderChecks::None => {
                let runtime = if checks == ShaderChecks::BoundsOnly {
                    wgpu::ShaderRuntimeChecks {
                        force_loop_bounding: false,
                        ..wgpu::ShaderRuntimeChecks::checked()
                    }
                } else {
                    wgpu::ShaderRuntimeChecks::unchecked()
                };
                // SAFETY: every loop in solari's shaders has a constant trip count or its
                // own iteration cap (`tests/shaders.rs` requires a `// bound:` note on
                // each), so no loop can run forever; `None` is for benchmarks only.
                unsafe { self.device.create_shader_module_trusted(desc, runtime) }
            }
        }
    }

    /// Creates a compute pipeline from composed WGSL with the given runtime checks and
    /// pipeline-overridable constants (see [`crate::gpu_scene::TraceVariant`]).
    pub fn compute_pipeline(
        &self,
        label: &str,
        wgsl: &str,
        layouts: &[Option<&wgpu::BindGroupLayout>],
        checks: ShaderChecks,
        constants: &[(&str, f64)],
    ) -> Result<wgpu::ComputePipeline, GpuError> {
        self.scoped(|| {
            let module = self.shader_module(label, wgsl, checks);
            let layout = self
                .device
                .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some(label),
                    bind_group_layouts: layouts,
                    immediate_size: 0,
                });
            self.device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(label),
                    layout: Some(&layout),
                    module: &module,
                    entry_point: Some("main"),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants,
                        ..Default::default()
                    },
                    cache: None,
                })
        })
    }
}

/// Runs `f` on `encoder` inside the profiler scope `label` (directly without a profiler), so
/// a pass records the same way whether timestamps are on or off.
pub fn in_scope<R>(
    profiler: Option<&wgpu_profiler::GpuProfiler>,
    label: &str,
    encoder: &mut wgpu::CommandEncoder,
    f: impl FnOnce(&mut wgpu::CommandEncoder) -> R,
) -> R {
    match profiler {
        Some(p) => f(&mut p.scope(label, encoder)),
        None => f(encoder),
    }
}

/// A device for a GPU test, or `None` (test skipped with a note) when no adapter exists and
/// `SOLARI_REQUIRE_GPU` is not `1`. With `SOLARI_REQUIRE_GPU=1` a missing adapter panics, so
/// CI can never pass with its GPU tests silently skipped. Dropping the device panics if wgpu
/// raised errors that no [`Gpu::check_errors`] call collected: a test whose GPU work was
/// refused (a bad binding, a copy into a buffer without `COPY_DST`) fails instead of reading
/// whatever the buffers held.
pub fn test_gpu() -> Option<Gpu> {
    match Gpu::new() {
        Ok(mut gpu) => {
            gpu.strict = true;
            Some(gpu)
        }
        Err(e) if std::env::var("SOLARI_REQUIRE_GPU").as_deref() == Ok("1") => {
            panic!("SOLARI_REQUIRE_GPU=1 but no GPU device: {e}")
        }
        Err(e) => {
            eprintln!("skipping GPU test: {e}");
            None
        }
    }
}

/// [`test_gpu`]'s adapter with other limits: `limits` gets the adapter's own and returns
/// those to ask for (lower ones, to test what happens over a device's limits). `None` where
/// [`test_gpu`] skips; panics if the adapter refuses the device.
pub fn test_gpu_with_limits(limits: impl FnOnce(wgpu::Limits) -> wgpu::Limits) -> Option<Gpu> {
    let gpu = test_gpu()?;
    let mut desc = Gpu::device_descriptor(&gpu.adapter);
    desc.required_limits = limits(gpu.adapter.limits());
    let (device, queue) =
        pollster::block_on(gpu.adapter.request_device(&desc)).expect("a device with these limits");
    let mut small = Gpu::from_parts(gpu.instance.clone(), gpu.adapter.clone(), device, queue);
    small.strict = true;
    Some(small)
}

/// Bytes a texture's data takes: every mip level of every layer at its format's block size.
/// A lower bound on what the driver allocates (it pads and aligns), for memory reports.
pub fn texture_bytes(texture: &wgpu::Texture) -> u64 {
    let format = texture.format();
    let block = format
        .block_copy_size(None)
        .or_else(|| format.block_copy_size(Some(wgpu::TextureAspect::DepthOnly)))
        .unwrap_or(4) as u64;
    let (bw, bh) = format.block_dimensions();
    let layers = texture.depth_or_array_layers() as u64;
    (0..texture.mip_level_count())
        .map(|level| {
            let w = (texture.width() >> level).max(1).div_ceil(bw) as u64;
            let h = (texture.height() >> level).max(1).div_ceil(bh) as u64;
            w * h * block * layers
        })
        .sum()
}
