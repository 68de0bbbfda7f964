//! Which G-buffer producer the renderer uses, and [`GBufferChoice::Auto`]'s measurement: both
//! producers timed on the scene at the render size when the renderer is built, the faster one
//! kept. The producers write the same texels (`solari_scene::gbuffer`), so the choice is one of
//! cost alone, and it depends on the GPU: raster hardware is scarce on compute GPUs (the
//! H100/H200) and plentiful on desktop ones.

use solari_scene::GpuError;
use solari_scene::gbuffer::{GBuffer, GBufferProducer};
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::{GpuScene, TraceVariant};
use solari_scene::gpu_timer::PassTimer;
use solari_scene::pass::FrameContext;
use solari_scene::{Camera, Scene};

/// How the renderer picks its G-buffer producer ([`crate::RealtimeSettings::gbuffer`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GBufferChoice {
    /// The raster producer (the library default: no start-up measurement, same on every
    /// adapter).
    #[default]
    Raster,
    /// The traced producer (an error where it cannot run:
    /// [`GBufferProducer::traced_support`]).
    Traced,
    /// Time both at start-up ([`measure`]) and keep the faster; raster, with the reason logged,
    /// where GPU time cannot be measured or the traced producer cannot run.
    Auto,
}

impl GBufferChoice {
    /// The name on the command line: `raster`, `traced` or `auto`.
    pub fn name(self) -> &'static str {
        match self {
            GBufferChoice::Raster => "raster",
            GBufferChoice::Traced => "traced",
            GBufferChoice::Auto => "auto",
        }
    }

    /// The choice named `name` ([`GBufferChoice::name`]).
    pub fn parse(name: &str) -> Option<Self> {
        [Self::Raster, Self::Traced, Self::Auto]
            .into_iter()
            .find(|c| c.name() == name)
    }
}

/// What [`measure`] found: each producer's median GPU time and the one chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GBufferTiming {
    /// The raster producer's median GPU milliseconds per frame.
    pub raster_ms: f64,
    /// The traced producer's.
    pub traced_ms: f64,
    /// The faster of the two.
    pub chosen: GBufferProducer,
}

/// Frames per producer left out (pipeline warm-up), then timed.
const WARM_UP: u32 = 2;
const TIMED: u32 = 6;

/// Times both producers on `scene` from `camera` at `size`, interleaved frame by frame so
/// clock changes hit both alike, and returns their medians and the faster one. Costs
/// 2 × 8 G-buffer passes (milliseconds on a discrete GPU). Errors where the adapter cannot
/// time a span of passes or run the traced producer.
pub fn measure(
    gpu: &Gpu,
    scene: &Scene,
    gpu_scene: &GpuScene,
    camera: &Camera,
    size: (u32, u32),
) -> Result<GBufferTiming, GpuError> {
    GBufferProducer::traced_support(gpu)?;
    let timer = PassTimer::new(gpu)?;
    let backend = gpu_scene.backend;
    let variant = TraceVariant::for_scene(gpu_scene);
    let mut producers = [
        GBuffer::new(gpu, backend, size.0, size.1)?,
        GBuffer::traced(gpu, backend, variant, size.0, size.1)?,
    ];
    let mut times = [Vec::new(), Vec::new()];
    for round in 0..WARM_UP + TIMED {
        for (gbuffer, times) in producers.iter_mut().zip(&mut times) {
            gbuffer.prepare(gpu, scene, camera)?;
            let frame = FrameContext::new(round, size, camera, None);
            let ms = timer.time_span(gpu, |e| gbuffer.encode(e, &frame, gpu_scene).map(drop))?;
            if round >= WARM_UP {
                times.push(ms);
            }
        }
    }
    let [raster_ms, traced_ms] = times.map(|mut t| {
        t.sort_by(f64::total_cmp);
        t[t.len() / 2]
    });
    Ok(GBufferTiming {
        raster_ms,
        traced_ms,
        chosen: if traced_ms < raster_ms {
            GBufferProducer::Traced
        } else {
            GBufferProducer::Raster
        },
    })
}

// The producer `choice` asks for; for `Auto`, the faster one measured on the scene's first
// camera, or raster (logged) where that cannot be measured.
pub(crate) fn choose(
    gpu: &Gpu,
    scene: &Scene,
    gpu_scene: &GpuScene,
    choice: GBufferChoice,
    size: (u32, u32),
) -> (GBufferProducer, Option<GBufferTiming>) {
    match choice {
        GBufferChoice::Raster => (GBufferProducer::Raster, None),
        GBufferChoice::Traced => (GBufferProducer::Traced, None),
        GBufferChoice::Auto => {
            let measured = scene
                .camera(None)
                .ok_or_else(|| GpuError::BadScene("no camera to measure from".into()))
                .and_then(|camera| measure(gpu, scene, gpu_scene, &camera, size));
            match measured {
                Ok(t) => {
                    log::info!(
                        "G-buffer auto: raster {:.3} ms, traced {:.3} ms per frame: {}",
                        t.raster_ms,
                        t.traced_ms,
                        t.chosen.name()
                    );
                    (t.chosen, Some(t))
                }
                Err(e) => {
                    log::info!("G-buffer auto: cannot measure ({e}); using raster");
                    (GBufferProducer::Raster, None)
                }
            }
        }
    }
}
