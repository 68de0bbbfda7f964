//! The synthetic-input harness the denoiser tests share: a real G-buffer of a grey Cornell
//! box (every surface the same grey albedo, no emission, so constant radiance is constant
//! demodulated light) and lighting buffers the tests fill each frame.
#![allow(dead_code)]

use glam::Vec3;
use solari_denoise::{Denoiser, DenoiserInputs, Lighting};
use solari_scene::gbuffer::GBuffer;
use solari_scene::gpu::{Gpu, test_gpu};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
use solari_scene::pass::FrameContext;
use solari_scene::{Scene, default_scene};

/// Image side.
pub const SIZE: u32 = 48;

/// The Cornell box with every surface grey (0.5), dielectric and not emissive.
pub fn grey_box() -> Scene {
    let mut scene = default_scene::cornell_box();
    for m in &mut scene.materials {
        m.base_color = glam::Vec4::new(0.5, 0.5, 0.5, 1.0);
        m.metallic = 0.0;
        m.emissive = Vec3::ZERO;
    }
    scene
}

/// A G-buffer of the grey box and lighting buffers the test fills each frame.
pub struct Harness {
    /// The device.
    pub gpu: Gpu,
    /// Added to the camera's position for the next frames (default zero).
    pub camera_offset: Vec3,
    /// The G-buffer's sample offset from the pixel centres for the next frames (default
    /// zero).
    pub jitter: [f32; 2],
    /// Factor on the camera's vertical field of view for the next frames (default 1).
    pub fov_scale: f32,
    scene: Scene,
    gpu_scene: GpuScene,
    gbuffer: GBuffer,
    lighting: wgpu::Buffer,
    specular: wgpu::Buffer,
}

impl Harness {
    /// `None` without a GPU (see `test_gpu`).
    pub fn new() -> Option<Self> {
        let gpu = test_gpu()?;
        let backend = gpu
            .backend(solari_scene::gpu::TracerChoice::Auto)
            .expect("backend");
        let scene = grey_box();
        let gpu_scene =
            GpuScene::new(&gpu, &scene, backend, &GpuSceneOptions::default()).expect("upload");
        let gbuffer = GBuffer::new(&gpu, backend, SIZE, SIZE).expect("gbuffer");
        let buffer = |label| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: (SIZE * SIZE * 16) as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let (lighting, specular) = (buffer("test lighting"), buffer("test specular"));
        Some(Self {
            gpu,
            camera_offset: Vec3::ZERO,
            jitter: [0.0; 2],
            fov_scale: 1.0,
            scene,
            gpu_scene,
            gbuffer,
            lighting,
            specular,
        })
    }

    /// Writes `input` to the (combined or diffuse) lighting buffer and returns it.
    pub fn write_lighting(&self, input: &[[f32; 4]]) -> &wgpu::Buffer {
        self.gpu
            .queue
            .write_buffer(&self.lighting, 0, bytemuck::cast_slice(input));
        &self.lighting
    }

    /// Starts a frame: an encoder with the G-buffer pass recorded, the camera moved by
    /// [`Harness::camera_offset`].
    pub fn gbuffer_encoder(&mut self) -> wgpu::CommandEncoder {
        let mut camera = self.scene.camera(None).expect("camera");
        camera.transform = glam::Mat4::from_translation(self.camera_offset) * camera.transform;
        camera.yfov *= self.fov_scale;
        self.gbuffer
            .prepare_jittered(&self.gpu, &self.scene, &camera, self.jitter)
            .expect("prepare");
        let frame = FrameContext::new(0, (SIZE, SIZE), &camera, None);
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        self.gbuffer
            .encode(&mut encoder, &frame, &self.gpu_scene)
            .expect("G-buffer");
        encoder
    }

    /// The G-buffer.
    pub fn gbuffer(&self) -> &GBuffer {
        &self.gbuffer
    }

    /// The (combined) lighting buffer.
    pub fn lighting(&self) -> &wgpu::Buffer {
        &self.lighting
    }

    /// One frame: G-buffer, then `denoiser` on combined lighting `input`; returns the output.
    pub fn frame(
        &mut self,
        denoiser: &mut dyn Denoiser,
        input: &[[f32; 4]],
        reset: bool,
    ) -> Vec<[f32; 4]> {
        self.run(denoiser, input, None, reset)
    }

    /// One frame with split lighting: `diffuse` and `specular` radiance.
    pub fn frame_split(
        &mut self,
        denoiser: &mut dyn Denoiser,
        diffuse: &[[f32; 4]],
        specular: &[[f32; 4]],
    ) -> Vec<[f32; 4]> {
        self.run(denoiser, diffuse, Some(specular), false)
    }

    fn run(
        &mut self,
        denoiser: &mut dyn Denoiser,
        input: &[[f32; 4]],
        specular: Option<&[[f32; 4]]>,
        reset: bool,
    ) -> Vec<[f32; 4]> {
        self.write_lighting(input);
        if let Some(s) = specular {
            self.gpu
                .queue
                .write_buffer(&self.specular, 0, bytemuck::cast_slice(s));
        }
        let mut encoder = self.gbuffer_encoder();
        let lighting = match specular {
            Some(_) => Lighting::Split {
                diffuse: &self.lighting,
                specular: &self.specular,
            },
            None => Lighting::Combined(&self.lighting),
        };
        let inputs = DenoiserInputs {
            lighting,
            gbuffer: &self.gbuffer,
            hit_distance: None,
            shadow: None,
            reset,
        };
        let camera = self.scene.camera(None).expect("camera");
        let frame = FrameContext::new(0, (SIZE, SIZE), &camera, None);
        let encoded = denoiser
            .encode(&self.gpu, &mut encoder, &frame, &inputs)
            .expect("encode");
        self.gpu
            .queue
            .submit(std::iter::once(encoder.finish()).chain(encoded.after));
        let bytes = self
            .gpu
            .read_buffer(denoiser.output(), (SIZE * SIZE * 16) as u64)
            .expect("read");
        bytemuck::cast_slice(&bytes).to_vec()
    }
}

/// Rec. 709 luminance.
pub fn luminance(c: [f32; 4]) -> f64 {
    0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64
}
