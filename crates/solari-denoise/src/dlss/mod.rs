//! DLSS Ray Reconstruction behind the [`Denoiser`] trait (cargo feature `dlss`).
//!
//! DLSS-RR needs a device created with NVIDIA's Vulkan extensions, so create the GPU with
//! [`create_gpu`], which also reports whether DLSS-RR can run here
//! ([`DlssAvailability`]). [`crate::create`] then offers it only where it is ready.
//!
//! Built with `dlss-mock`, every call goes to a stand-in with `dlss_wgpu`'s signatures
//! (`ngx.rs`) that reports DLSS-RR unavailable, so the integration compiles and its
//! fallback path runs without the SDK.
//!
//! Not done: camera jitter. Solari's G-buffer is not jittered, so DLSS-RR gets zero jitter;
//! its upscaling modes then have less detail to reconstruct than they could. The default
//! mode, [`QUALITY`], is DLAA (no upscaling), where this matters least.

mod ngx;

use crate::denoiser::{Denoiser, DenoiserInputs, Encoded, Inputs, Lighting, Requirements};
use crate::dlss_io::{COPY_LABELS, DlssTextures};
use crate::select::DlssAvailability;
use ngx::{
    DlssFeatureFlags, DlssPerfQualityMode, DlssRayReconstruction, DlssRayReconstructionDepthMode,
    DlssRayReconstructionRenderParameters, DlssRayReconstructionRoughnessMode,
    DlssRayReconstructionSpecularGuide, DlssSdk, FeatureSupport,
};
use solari_scene::GpuError;
use solari_scene::gpu::Gpu;
use solari_scene::pass::{FrameContext, Ran};
use std::sync::{Arc, Mutex};

/// Solari's NGX project id (any fixed UUID identifies an application to NGX).
pub const PROJECT_ID: &str = "6f1c3a52-8d0e-4f7b-9a1e-2c5b7d9e4f10";

/// The perf/quality mode Solari asks for: DLAA, render resolution = output resolution.
pub const QUALITY: DlssPerfQualityMode = DlssPerfQualityMode::Dlaa;

/// Profiler scopes: the input copy (DLSS-RR and the output copy run in command buffers of
/// their own, outside the profiler's reach).
pub const PASS_LABELS: [&str; 1] = [COPY_LABELS[0]];

fn project_id() -> uuid::Uuid {
    uuid::Uuid::parse_str(PROJECT_ID).expect("PROJECT_ID is a valid UUID")
}

/// A loaded DLSS SDK, shared by every DLSS-RR context on the device.
#[derive(Clone)]
pub struct DlssSdkHandle(Arc<Mutex<DlssSdk>>);

impl std::fmt::Debug for DlssSdkHandle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("DlssSdkHandle")
    }
}

/// Creates the GPU through `dlss_wgpu` (Vulkan, with NGX's extensions) and loads the SDK.
/// Where that fails (no Vulkan, no NVIDIA driver, no DLSS-RR, a mock build) the GPU comes from
/// [`Gpu::new`] instead and the availability says why.
pub fn create_gpu() -> Result<(Gpu, DlssAvailability), GpuError> {
    match try_create_gpu() {
        Ok((gpu, availability)) => Ok((gpu, availability)),
        Err(reason) => Ok((Gpu::new()?, DlssAvailability::Unavailable(reason))),
    }
}

fn try_create_gpu() -> Result<(Gpu, DlssAvailability), String> {
    let id = project_id();
    let mut support = FeatureSupport::default();
    let instance = ngx::create_instance(id, &Gpu::instance_descriptor(), &mut support)
        .map_err(|e| format!("cannot create a Vulkan instance for DLSS: {e}"))?;
    let adapter = Gpu::pick_adapter(&instance).map_err(|e| e.to_string())?;
    let info = adapter.get_info();
    if info.backend != wgpu::Backend::Vulkan {
        return Err(format!("{} is not a Vulkan adapter", info.name));
    }
    let (device, queue) = ngx::request_device(
        id,
        &adapter,
        &Gpu::device_descriptor(&adapter),
        &mut support,
        None,
    )
    .map_err(|e| format!("cannot create a DLSS device on {}: {e}", info.name))?;
    let gpu = Gpu::from_parts(instance, adapter, device, queue);
    let availability = if !support.ray_reconstruction_supported {
        DlssAvailability::Unavailable(format!(
            "{} or its driver does not support DLSS Ray Reconstruction{}",
            info.name,
            ngx::MOCK_NOTE
        ))
    } else {
        match DlssSdk::new(id, gpu.device.clone()) {
            Ok(sdk) => DlssAvailability::Ready(DlssSdkHandle(sdk)),
            Err(e) => DlssAvailability::Unavailable(format!("DLSS SDK did not load: {e}")),
        }
    };
    Ok((gpu, availability))
}

/// DLSS Ray Reconstruction as a [`Denoiser`]: copies Solari's lighting and G-buffer into the
/// textures DLSS-RR reads, runs it, and copies its output into a buffer.
pub struct DlssRrDenoiser {
    context: DlssRayReconstruction,
    textures: DlssTextures,
}

impl DlssRrDenoiser {
    /// A context producing `output_size` images; render at [`Denoiser::render_size`].
    pub fn new(gpu: &Gpu, sdk: &DlssSdkHandle, output_size: (u32, u32)) -> Result<Self, GpuError> {
        let context = DlssRayReconstruction::new(
            [output_size.0, output_size.1],
            QUALITY,
            DlssFeatureFlags::HighDynamicRange | DlssFeatureFlags::LowResolutionMotionVectors,
            DlssRayReconstructionRoughnessMode::Packed,
            DlssRayReconstructionDepthMode::Linear,
            Arc::clone(&sdk.0),
            &gpu.device,
            &gpu.queue,
        )
        .map_err(|e| GpuError::Validation(format!("DLSS-RR context: {e}")))?;
        let [rw, rh] = context.render_resolution();
        let textures = DlssTextures::new(gpu, (rw, rh), output_size)?;
        Ok(Self { context, textures })
    }
}

impl Denoiser for DlssRrDenoiser {
    fn name(&self) -> &'static str {
        "dlss-rr"
    }

    fn requirements(&self) -> Requirements {
        Requirements {
            features: wgpu::Features::empty(),
            backend: Some(wgpu::Backend::Vulkan),
            inputs: Inputs::COMBINED_LIGHTING | Inputs::GUIDES,
        }
    }

    fn render_size(&self) -> (u32, u32) {
        self.textures.render_size()
    }

    fn output_size(&self) -> (u32, u32) {
        self.textures.output_size()
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
        let Lighting::Combined(lighting) = inputs.lighting else {
            return Err(GpuError::Validation(
                "DLSS-RR takes combined lighting (it separates signals itself)".into(),
            ));
        };
        self.textures
            .encode_inputs(gpu, encoder, frame.profiler, lighting, inputs.gbuffer)?;
        let mut ran = Ran::none();
        ran.mark(PASS_LABELS[0]);
        let (rw, rh) = self.textures.render_size();
        let t = &self.textures;
        let parameters = DlssRayReconstructionRenderParameters {
            diffuse_albedo: t.input(1),
            specular_albedo: t.input(2),
            normals: t.input(3),
            roughness: None,
            color: t.input(0),
            depth: t.input(4),
            motion_vectors: t.input(5),
            // Solari has no specular motion vectors: the surface's own motion stands in
            // (right for rough reflections; mirror reflections of moving things lag).
            specular_guide: DlssRayReconstructionSpecularGuide::SpecularMotionVectors(t.input(5)),
            transparency_overlay: None,
            color_before_transparency: None,
            screen_space_subsurface_scattering_guide: None,
            depth_of_field_guide: None,
            responsivity_mask: None,
            alpha: None,
            dlss_output_alpha: None,
            dlss_output: &t.output_texture.1,
            reset: inputs.reset || !inputs.gbuffer.history_valid(),
            jitter_offset: [0.0, 0.0],
            partial_texture_size: None,
            // Motion is uv now − uv then; DLSS wants pixels from now to then.
            motion_vector_scale: Some([-(rw as f32), -(rh as f32)]),
        };
        // DLSS-RR records into its own command buffer, so no profiler scope can time it.
        let dlss = self
            .context
            .render(parameters, encoder, &gpu.adapter)
            .map_err(|e| GpuError::Validation(format!("DLSS-RR: {e}")))?;
        let mut after = gpu.device.create_command_encoder(&Default::default());
        self.textures.encode_output(&mut after, None);
        Ok(Encoded {
            ran,
            after: vec![dlss, after.finish()],
        })
    }

    fn output(&self) -> &wgpu::Buffer {
        &self.textures.output
    }

    fn memory_bytes(&self) -> u64 {
        self.textures.memory_bytes()
    }
}
