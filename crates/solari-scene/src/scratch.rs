//! Per-frame scratch memory that several passes share.
//!
//! Some buffers live only inside one part of a frame: the world cache's new samples (from
//! its update pass to its blend pass), ReSTIR DI's initial reservoirs (written by its first
//! dispatch, read by its second), ReSTIR GI's, the G-buffer's overrides (written by specular
//! GI for every pixel, read by the apply pass), the fallback denoiser's transient bytes and
//! one of its filter buffers, and the temporal upscaler's new accumulation (written by its
//! first dispatch, copied into its history by its second). Passes run one after another, so
//! one buffer can hold each in turn. A renderer asks each component how much it needs
//! (`scratch_bytes`), allocates the largest with [`allocate`], and hands it to each
//! (`use_scratch`). The contract for a
//! component that takes scratch: it reads only what its own dispatches (or, for the
//! overrides, their one writer) of the same frame wrote there, so whatever ran before may
//! have left anything in it.
//!
//! At 1920×1080 with the real-time renderer's defaults on `interior`, its users need 132
//! bytes a pixel and 16 MiB; the one 32-byte-a-pixel scratch saves 214 MiB of that. See
//! `benches/RESULTS.md`, "GPU memory per component".

use crate::error::GpuError;
use crate::gpu::Gpu;

/// Allocates a scratch buffer of `bytes` (at least 16) for passes to share (storage; copies
/// in and out for tests and tools). Each pass binds it whole, so it must fit the device's
/// storage binding limit.
pub fn allocate(gpu: &Gpu, bytes: u64) -> Result<wgpu::Buffer, GpuError> {
    gpu.check_storage_binding("shared scratch buffer", bytes)?;
    Ok(gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("solari/shared_scratch"),
        size: bytes.max(16),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    }))
}

/// Refuses `scratch` for `what` when it is smaller than `needed` bytes or not a storage
/// buffer, naming both sizes.
pub fn check(what: &str, scratch: &wgpu::Buffer, needed: u64) -> Result<(), GpuError> {
    if !scratch.usage().contains(wgpu::BufferUsages::STORAGE) {
        return Err(GpuError::Validation(format!(
            "{what}: the scratch buffer is not a storage buffer (usage {:?})",
            scratch.usage()
        )));
    }
    if scratch.size() < needed {
        return Err(GpuError::Validation(format!(
            "{what}: the scratch buffer holds {} bytes; it needs {needed}",
            scratch.size()
        )));
    }
    Ok(())
}
