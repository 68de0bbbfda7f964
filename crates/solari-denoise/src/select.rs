//! Choosing a denoiser the adapter supports, with a message when the one asked for cannot
//! run.

use crate::denoiser::{Denoiser, DenoiserKind};
use crate::fallback::FallbackDenoiser;
use crate::settings::FallbackSettings;
use solari_scene::GpuError;
use solari_scene::gpu::Gpu;

/// Whether DLSS Ray Reconstruction can run on this GPU.
#[derive(Clone, Debug)]
pub enum DlssAvailability {
    /// This build has no DLSS support (cargo feature `dlss` off).
    NotBuilt,
    /// Built in, but not usable here; the reason.
    Unavailable(String),
    /// Ready: the GPU was created through `dlss::create_gpu` and the SDK loaded.
    #[cfg(feature = "dlss")]
    Ready(crate::dlss::DlssSdkHandle),
}

impl DlssAvailability {
    /// Why DLSS-RR cannot run, or `None` when it can.
    pub fn unavailable_reason(&self) -> Option<String> {
        match self {
            Self::NotBuilt => Some(
                "this build has no DLSS support (build with `--features dlss` and NVIDIA's \
                 DLSS SDK: see solari-denoise's README)"
                    .into(),
            ),
            Self::Unavailable(why) => Some(why.clone()),
            #[cfg(feature = "dlss")]
            Self::Ready(_) => None,
        }
    }
}

/// The GPU and DLSS availability for a program that may use DLSS-RR: through `dlss_wgpu`
/// in builds with the `dlss` feature, otherwise [`Gpu::new`] and
/// [`DlssAvailability::NotBuilt`].
pub fn create_gpu() -> Result<(Gpu, DlssAvailability), GpuError> {
    #[cfg(feature = "dlss")]
    {
        crate::dlss::create_gpu()
    }
    #[cfg(not(feature = "dlss"))]
    {
        Ok((Gpu::new()?, DlssAvailability::NotBuilt))
    }
}

/// What [`create`] made.
pub struct Created {
    /// The denoiser (`None` for [`DenoiserKind::None`]).
    pub denoiser: Option<Box<dyn Denoiser>>,
    /// Which one it is.
    pub kind: DenoiserKind,
    /// Set when the one asked for could not run and another was used: why.
    pub fallback_reason: Option<String>,
}

/// Makes the denoiser `wanted` (`None`: the best available, DLSS-RR over the fallback) for
/// `output_size` images. An explicit `DlssRr` that cannot run falls back to the fallback
/// denoiser and says why in [`Created::fallback_reason`]; with `None` falling back is the
/// plan, so the reason is only logged.
pub fn create(
    gpu: &Gpu,
    wanted: Option<DenoiserKind>,
    dlss: &DlssAvailability,
    output_size: (u32, u32),
    fallback: FallbackSettings,
) -> Result<Created, GpuError> {
    let (w, h) = output_size;
    let make_fallback = |reason: Option<String>| -> Result<Created, GpuError> {
        Ok(Created {
            denoiser: Some(Box::new(FallbackDenoiser::new(gpu, w, h, fallback)?)),
            kind: DenoiserKind::Fallback,
            fallback_reason: reason,
        })
    };
    match wanted {
        Some(DenoiserKind::None) => Ok(Created {
            denoiser: None,
            kind: DenoiserKind::None,
            fallback_reason: None,
        }),
        Some(DenoiserKind::Fallback) => make_fallback(None),
        Some(DenoiserKind::DlssRr) | None => {
            let explicit = wanted.is_some();
            match try_dlss(gpu, dlss, output_size) {
                Ok(denoiser) => Ok(Created {
                    denoiser: Some(denoiser),
                    kind: DenoiserKind::DlssRr,
                    fallback_reason: None,
                }),
                Err(why) if explicit => make_fallback(Some(format!(
                    "DLSS-RR unavailable: {why}; using the fallback denoiser"
                ))),
                Err(why) => {
                    log::info!("DLSS-RR not used ({why}); denoising with the fallback");
                    make_fallback(None)
                }
            }
        }
    }
}

// Builds DLSS-RR where `dlss` says it can run; otherwise says why not.
#[cfg(feature = "dlss")]
fn try_dlss(
    gpu: &Gpu,
    dlss: &DlssAvailability,
    output_size: (u32, u32),
) -> Result<Box<dyn Denoiser>, String> {
    let DlssAvailability::Ready(sdk) = dlss else {
        return Err(why_unavailable(dlss));
    };
    let denoiser =
        crate::dlss::DlssRrDenoiser::new(gpu, sdk, output_size).map_err(|e| e.to_string())?;
    denoiser.requirements().check(gpu)?;
    Ok(Box::new(denoiser))
}

// Without the `dlss` feature DLSS-RR is never available.
#[cfg(not(feature = "dlss"))]
fn try_dlss(
    _gpu: &Gpu,
    dlss: &DlssAvailability,
    _output_size: (u32, u32),
) -> Result<Box<dyn Denoiser>, String> {
    Err(why_unavailable(dlss))
}

fn why_unavailable(dlss: &DlssAvailability) -> String {
    dlss.unavailable_reason()
        .unwrap_or_else(|| "unknown".into())
}
