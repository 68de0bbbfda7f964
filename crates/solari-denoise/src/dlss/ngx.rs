//! The seam between the integration and `dlss_wgpu`: with the SDK (feature `dlss` alone) the
//! real items; with `dlss-mock` (whose `dlss_wgpu` exports nothing) stand-ins with the same
//! signatures, so `super` type-checks identically in both builds and, at run time, finds
//! DLSS-RR unsupported.

#[cfg(not(feature = "dlss-mock"))]
pub use dlss_wgpu::ray_reconstruction::{
    DlssRayReconstruction, DlssRayReconstructionDepthMode, DlssRayReconstructionRenderParameters,
    DlssRayReconstructionRoughnessMode, DlssRayReconstructionSpecularGuide,
};
#[cfg(not(feature = "dlss-mock"))]
pub use dlss_wgpu::{
    DlssFeatureFlags, DlssPerfQualityMode, DlssSdk, FeatureSupport, create_instance, request_device,
};

/// Appended to "not supported" messages.
#[cfg(not(feature = "dlss-mock"))]
pub const MOCK_NOTE: &str = "";

#[cfg(feature = "dlss-mock")]
pub use mock::*;

#[cfg(feature = "dlss-mock")]
mod mock {
    //! Stand-ins for the `dlss_wgpu` 6.0.0 items the integration uses, same names and
    //! signatures; nothing here reaches NVIDIA's code.
    #![allow(dead_code)]

    use std::sync::{Arc, Mutex};
    use uuid::Uuid;
    use wgpu::{
        Adapter, CommandBuffer, CommandEncoder, Device, DeviceDescriptor, Instance,
        InstanceDescriptor, Limits, Queue, TextureView,
    };

    /// Appended to "not supported" messages.
    pub const MOCK_NOTE: &str =
        " (this binary was built with `dlss-mock`: rebuild with `--features dlss` and the SDK)";

    /// Errors, as `dlss_wgpu::DlssError` (only the variant the mock returns).
    #[derive(Debug)]
    pub enum DlssError {
        /// The mock supports nothing.
        FeatureNotSupported,
    }

    impl std::fmt::Display for DlssError {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("DLSS is not available in a dlss-mock build")
        }
    }

    impl std::error::Error for DlssError {}

    /// As `dlss_wgpu::FeatureSupport`.
    pub struct FeatureSupport {
        pub super_resolution_supported: bool,
        pub ray_reconstruction_supported: bool,
    }

    impl Default for FeatureSupport {
        fn default() -> Self {
            Self {
                super_resolution_supported: true,
                ray_reconstruction_supported: true,
            }
        }
    }

    /// As `dlss_wgpu::create_instance`: a plain instance; marks DLSS unsupported.
    /// (`InstanceDescriptor` is not `Clone`; the integration passes Solari's own descriptor,
    /// which is rebuilt here.)
    pub fn create_instance(
        _project_id: Uuid,
        _instance_descriptor: &InstanceDescriptor,
        feature_support: &mut FeatureSupport,
    ) -> Result<Instance, DlssError> {
        feature_support.super_resolution_supported = false;
        feature_support.ray_reconstruction_supported = false;
        Ok(Instance::new(solari_scene::gpu::Gpu::instance_descriptor()))
    }

    /// As `dlss_wgpu::request_device`: a plain device.
    pub fn request_device(
        _project_id: Uuid,
        adapter: &Adapter,
        device_descriptor: &DeviceDescriptor,
        feature_support: &mut FeatureSupport,
        limits: Option<Limits>,
    ) -> Result<(Device, Queue), String> {
        feature_support.ray_reconstruction_supported = false;
        let mut descriptor = device_descriptor.clone();
        if let Some(limits) = limits {
            descriptor.required_limits = limits;
        }
        pollster::block_on(adapter.request_device(&descriptor)).map_err(|e| e.to_string())
    }

    /// As `dlss_wgpu::DlssSdk`.
    pub struct DlssSdk;

    impl DlssSdk {
        /// Always fails.
        pub fn new(_project_id: Uuid, _device: Device) -> Result<Arc<Mutex<Self>>, DlssError> {
            Err(DlssError::FeatureNotSupported)
        }
    }

    /// As `dlss_wgpu::DlssPerfQualityMode`.
    #[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
    pub enum DlssPerfQualityMode {
        #[default]
        Auto,
        Dlaa,
        Quality,
        Balanced,
        Performance,
        UltraPerformance,
    }

    /// As `dlss_wgpu::DlssFeatureFlags` (the flags the integration uses).
    #[derive(Clone, Copy, PartialEq, Eq, Debug)]
    pub struct DlssFeatureFlags(u32);

    #[allow(non_upper_case_globals)]
    impl DlssFeatureFlags {
        pub const HighDynamicRange: Self = Self(1);
        pub const LowResolutionMotionVectors: Self = Self(2);
        pub const InvertedDepth: Self = Self(8);
    }

    impl std::ops::BitOr for DlssFeatureFlags {
        type Output = Self;
        fn bitor(self, rhs: Self) -> Self {
            Self(self.0 | rhs.0)
        }
    }

    /// As `dlss_wgpu::ray_reconstruction::DlssRayReconstructionRoughnessMode`.
    pub enum DlssRayReconstructionRoughnessMode {
        Unpacked,
        Packed,
    }

    /// As `dlss_wgpu::ray_reconstruction::DlssRayReconstructionDepthMode`.
    pub enum DlssRayReconstructionDepthMode {
        Linear,
        Hardware,
    }

    /// As `dlss_wgpu::ray_reconstruction::DlssRayReconstructionSpecularGuide`.
    pub enum DlssRayReconstructionSpecularGuide<'a> {
        SpecularMotionVectors(&'a TextureView),
        SpecularHitDistance {
            texture_view: &'a TextureView,
            world_to_view_rows_array: [f32; 16],
            view_to_clip_rows_array: [f32; 16],
        },
    }

    /// As `dlss_wgpu::ray_reconstruction::DlssRayReconstructionTransparencyOverlay`.
    pub enum DlssRayReconstructionTransparencyOverlay<'a> {
        Premultiplied(&'a TextureView),
        Separate {
            color: &'a TextureView,
            opacity: &'a TextureView,
        },
    }

    /// As `dlss_wgpu::ray_reconstruction::DlssRayReconstructionRenderParameters`.
    pub struct DlssRayReconstructionRenderParameters<'a> {
        pub diffuse_albedo: &'a TextureView,
        pub specular_albedo: &'a TextureView,
        pub normals: &'a TextureView,
        pub roughness: Option<&'a TextureView>,
        pub color: &'a TextureView,
        pub depth: &'a TextureView,
        pub motion_vectors: &'a TextureView,
        pub specular_guide: DlssRayReconstructionSpecularGuide<'a>,
        pub transparency_overlay: Option<DlssRayReconstructionTransparencyOverlay<'a>>,
        pub color_before_transparency: Option<&'a TextureView>,
        pub screen_space_subsurface_scattering_guide: Option<&'a TextureView>,
        pub depth_of_field_guide: Option<&'a TextureView>,
        pub responsivity_mask: Option<&'a TextureView>,
        pub alpha: Option<&'a TextureView>,
        pub dlss_output_alpha: Option<&'a TextureView>,
        pub dlss_output: &'a TextureView,
        pub reset: bool,
        pub jitter_offset: [f32; 2],
        pub partial_texture_size: Option<[u32; 2]>,
        pub motion_vector_scale: Option<[f32; 2]>,
    }

    /// As `dlss_wgpu::ray_reconstruction::DlssRayReconstruction`; cannot be created.
    pub struct DlssRayReconstruction {
        never: std::convert::Infallible,
    }

    impl DlssRayReconstruction {
        #[allow(clippy::too_many_arguments)]
        pub fn new(
            _upscaled_resolution: [u32; 2],
            _perf_quality_mode: DlssPerfQualityMode,
            _feature_flags: DlssFeatureFlags,
            _roughness_mode: DlssRayReconstructionRoughnessMode,
            _depth_mode: DlssRayReconstructionDepthMode,
            _sdk: Arc<Mutex<DlssSdk>>,
            _device: &Device,
            _queue: &Queue,
        ) -> Result<Self, DlssError> {
            Err(DlssError::FeatureNotSupported)
        }

        pub fn render(
            &mut self,
            _render_parameters: DlssRayReconstructionRenderParameters,
            _command_encoder: &mut CommandEncoder,
            _adapter: &Adapter,
        ) -> Result<CommandBuffer, DlssError> {
            match self.never {}
        }

        pub fn render_resolution(&self) -> [u32; 2] {
            match self.never {}
        }

        pub fn upscaled_resolution(&self) -> [u32; 2] {
            match self.never {}
        }
    }
}
