//! GPU time of one pass from two timestamp queries: the one way every Solari bench measures a
//! pass (`solari bench-rays` and the criterion benches), so their figures can be compared.

use crate::GpuError;
use crate::gpu::Gpu;

/// A pair of timestamp queries bracketing one compute pass, with its resolve buffer. Reuse it
/// for many measurements; each [`PassTimer::time`] waits for its pass to finish.
pub struct PassTimer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    // Mapped after each pass; kept so a measurement allocates nothing.
    readback: wgpu::Buffer,
    period_ns: f64,
}

impl PassTimer {
    /// Creates the queries. Errors (naming the adapter) where timestamp queries are missing.
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        if !gpu.features.contains(wgpu::Features::TIMESTAMP_QUERY) {
            return Err(GpuError::Validation(format!(
                "adapter '{}' has no timestamp queries: GPU times cannot be measured",
                gpu.info.name
            )));
        }
        let queries = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("solari_scene/pass_timer"),
            ty: wgpu::QueryType::Timestamp,
            count: 2,
        });
        let resolve = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solari_scene/pass_timer_resolve"),
            size: 16,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solari_scene/pass_timer_readback"),
            size: 16,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(Self {
            queries,
            resolve,
            readback,
            period_ns: gpu.queue.get_timestamp_period() as f64,
        })
    }

    /// Records one pass with `record`, which must give the query set and first index it
    /// receives to its pass's timestamp writes (as [`crate::view_pass::ViewPass::encode`]
    /// does), submits it and returns the pass's GPU time in milliseconds.
    pub fn time(
        &self,
        gpu: &Gpu,
        record: impl FnOnce(&mut wgpu::CommandEncoder, (&wgpu::QuerySet, u32)) -> Result<(), GpuError>,
    ) -> Result<f64, GpuError> {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        record(&mut encoder, (&self.queries, 0))?;
        encoder.resolve_query_set(&self.queries, 0..2, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, 16);
        gpu.queue.submit([encoder.finish()]);
        let bytes = gpu.map_read(&self.readback)?;
        let ts: [u64; 2] = bytemuck::pod_read_unaligned(&bytes);
        Ok(ts[1].wrapping_sub(ts[0]) as f64 * self.period_ns * 1e-6)
    }

    /// Times everything `record` records (any number of passes) between two timestamps
    /// written on the encoder, submits it and returns the GPU time in milliseconds. For
    /// components of several passes; needs `TIMESTAMP_QUERY_INSIDE_ENCODERS` (an error
    /// naming the adapter otherwise).
    pub fn time_span(
        &self,
        gpu: &Gpu,
        record: impl FnOnce(&mut wgpu::CommandEncoder) -> Result<(), GpuError>,
    ) -> Result<f64, GpuError> {
        self.time_span_after(gpu, |_| Ok(()), record)
    }

    /// As [`PassTimer::time_span`], with `before` recorded untimed in the same command
    /// buffer just ahead of the span: a pass measured in the context a frame gives it (after
    /// the passes that precede it there) rather than alone.
    pub fn time_span_after(
        &self,
        gpu: &Gpu,
        before: impl FnOnce(&mut wgpu::CommandEncoder) -> Result<(), GpuError>,
        record: impl FnOnce(&mut wgpu::CommandEncoder) -> Result<(), GpuError>,
    ) -> Result<f64, GpuError> {
        require_spans(gpu)?;
        self.time(gpu, |encoder, (queries, first)| {
            before(encoder)?;
            encoder.write_timestamp(queries, first);
            record(encoder)?;
            encoder.write_timestamp(queries, first + 1);
            Ok(())
        })
    }
}

/// Times one span per frame over several frames submitted back to back, none waiting for
/// the one before, as a frame loop with frames in flight runs them: a short pass timed alone,
/// with a wait after each repetition, sees a GPU that idles between repetitions and caches
/// that only its own repetitions warm, unlike its place in a frame (benches/RESULTS.md,
/// "Criterion benches against the CLI").
pub struct FrameSpanTimer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    frames: u32,
    period_ns: f64,
}

impl FrameSpanTimer {
    /// Queries for up to `frames` spans (at least 1) per call of [`FrameSpanTimer::time`].
    /// Errors (naming the adapter) where timestamps cannot be written between passes.
    pub fn new(gpu: &Gpu, frames: u32) -> Result<Self, GpuError> {
        require_spans(gpu)?;
        let frames = frames.max(1);
        let bytes = u64::from(frames) * 16;
        let buffer = |label, usage| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        Ok(Self {
            queries: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("solari_scene/frame_span_timer"),
                ty: wgpu::QueryType::Timestamp,
                count: frames * 2,
            }),
            resolve: buffer(
                "solari_scene/frame_span_timer_resolve",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            readback: buffer(
                "solari_scene/frame_span_timer_readback",
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            frames,
            period_ns: gpu.queue.get_timestamp_period() as f64,
        })
    }

    /// The most frames one call times.
    pub fn capacity(&self) -> u32 {
        self.frames
    }

    /// Submits `frames` frames (at most [`FrameSpanTimer::capacity`]), one command buffer
    /// each: `before(frame, encoder)` untimed (uniform uploads belong here: a queue write lands
    /// before the next submission), then `record(frame, encoder)` between two timestamps. Waits
    /// once, after the last, and returns each frame's span in milliseconds.
    pub fn time(
        &self,
        gpu: &Gpu,
        frames: u32,
        mut before: impl FnMut(u32, &mut wgpu::CommandEncoder) -> Result<(), GpuError>,
        mut record: impl FnMut(u32, &mut wgpu::CommandEncoder) -> Result<(), GpuError>,
    ) -> Result<Vec<f64>, GpuError> {
        if frames == 0 || frames > self.frames {
            return Err(GpuError::Validation(format!(
                "{frames} frames asked of a span timer made for 1 to {}",
                self.frames
            )));
        }
        for frame in 0..frames {
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            before(frame, &mut encoder)?;
            encoder.write_timestamp(&self.queries, frame * 2);
            record(frame, &mut encoder)?;
            encoder.write_timestamp(&self.queries, frame * 2 + 1);
            gpu.queue.submit([encoder.finish()]);
        }
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.resolve_query_set(&self.queries, 0..frames * 2, &self.resolve, 0);
        let bytes = u64::from(frames) * 16;
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, bytes);
        gpu.queue.submit([encoder.finish()]);
        let data = gpu.map_read(&self.readback)?;
        // The mapped bytes carry no u64 alignment: read each pair unaligned.
        Ok(data[..bytes as usize]
            .chunks_exact(16)
            .map(|pair| {
                let t: [u64; 2] = bytemuck::pod_read_unaligned(pair);
                t[1].wrapping_sub(t[0]) as f64 * self.period_ns * 1e-6
            })
            .collect())
    }
}

/// Errors (naming the adapter) where timestamps cannot be written between passes on an
/// encoder, which every span needs.
fn require_spans(gpu: &Gpu) -> Result<(), GpuError> {
    let needed = wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
    if gpu.features.contains(needed) {
        return Ok(());
    }
    Err(GpuError::Validation(format!(
        "adapter '{}' cannot write timestamps between passes: a span cannot be timed",
        gpu.info.name
    )))
}

/// Whether a criterion bench runs for real (`cargo bench` passes `--bench`) rather than in
/// criterion's test mode under `cargo test`, where it must run once, small, untimed.
pub fn full_bench() -> bool {
    std::env::args().any(|a| a == "--bench")
}
