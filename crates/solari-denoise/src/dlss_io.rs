//! The textures DLSS Ray Reconstruction reads and writes, and the two copy passes between
//! them and Solari's buffers. Kept apart from the `dlss` feature so that every build (and
//! CI, which has no DLSS SDK) compiles and tests them.

use solari_scene::GpuError;
use solari_scene::gbuffer::GBuffer;
use solari_scene::gbuffer_input::GBufferSource;
use solari_scene::gpu::{Gpu, ShaderChecks, in_scope};
use solari_scene::shaders::{Backend, compose};
use wgpu_profiler::GpuProfiler;

/// Profiler scopes: the input copy and the output copy.
pub const COPY_LABELS: [&str; 2] = ["dlss_copy_inputs", "dlss_copy_output"];

/// Formats of [`DlssTextures`], in binding order: colour, diffuse albedo, specular albedo,
/// normal + roughness, linear depth, motion.
pub const INPUT_FORMATS: [wgpu::TextureFormat; 6] = [
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::R32Float,
    wgpu::TextureFormat::Rg32Float,
];

/// Format of the denoised texture DLSS writes.
pub const OUTPUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct CopyParams {
    width: u32,
    height: u32,
    _pad: [u32; 2],
}

const _: () = assert!(size_of::<CopyParams>() == 16);

/// DLSS-RR's input textures at the render resolution and its output at the output
/// resolution, with the passes that fill the inputs from Solari's lighting buffer and
/// G-buffer and copy the output to a `vec4<f32>` buffer.
pub struct DlssTextures {
    render: (u32, u32),
    output_size: (u32, u32),
    /// Input textures and their views, in [`INPUT_FORMATS`] order.
    pub inputs: Vec<(wgpu::Texture, wgpu::TextureView)>,
    /// The texture DLSS writes.
    pub output_texture: (wgpu::Texture, wgpu::TextureView),
    /// The output as every Solari denoiser gives it.
    pub output: wgpu::Buffer,
    copy_in: wgpu::ComputePipeline,
    copy_in_layout: wgpu::BindGroupLayout,
    copy_in_params: wgpu::Buffer,
    copy_out: wgpu::ComputePipeline,
    copy_out_group: wgpu::BindGroup,
    // The input copy's group for the lighting buffer last seen.
    bound: Option<(wgpu::Buffer, wgpu::BindGroup)>,
}

impl DlssTextures {
    /// Allocates the textures and builds both copy passes.
    pub fn new(gpu: &Gpu, render: (u32, u32), output_size: (u32, u32)) -> Result<Self, GpuError> {
        let limit = gpu.device.limits().max_texture_dimension_2d;
        for (w, h) in [render, output_size] {
            if w == 0 || h == 0 || w > limit || h > limit {
                return Err(GpuError::Validation(format!(
                    "DLSS-RR: texture size {w}×{h} is empty or over the device's {limit}"
                )));
            }
        }
        let texture = |label: &str, (w, h): (u32, u32), format| {
            let t = gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                // Copies both ways: read-back for tests and tools, and upload so the output
                // copy can be tested without DLSS writing the texture.
                usage: wgpu::TextureUsages::STORAGE_BINDING
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC
                    | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
            let v = t.create_view(&Default::default());
            (t, v)
        };
        let inputs: Vec<_> = INPUT_FORMATS
            .iter()
            .map(|f| texture("solari_denoise/dlss_input", render, *f))
            .collect();
        let output_texture = texture("solari_denoise/dlss_output", output_size, OUTPUT_FORMAT);
        let pixels = output_size.0 as u64 * output_size.1 as u64;
        let output = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solari_denoise/dlss_output"),
            size: pixels * 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });

        let storage_texture = solari_scene::gpu::storage_texture_layout_entry;
        let buffer = |binding, ty| {
            solari_scene::gpu::buffer_layout_entry(binding, ty, wgpu::ShaderStages::COMPUTE)
        };
        let mut entries = vec![
            buffer(0, wgpu::BufferBindingType::Uniform),
            buffer(1, wgpu::BufferBindingType::Storage { read_only: true }),
        ];
        entries.extend(
            INPUT_FORMATS
                .iter()
                .enumerate()
                .map(|(i, f)| storage_texture(2 + i as u32, *f)),
        );
        let copy_in_layout =
            gpu.device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("solari_denoise/dlss_inputs"),
                    entries: &entries,
                });
        let copy_out_layout =
            gpu.device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("solari_denoise/dlss_output"),
                    entries: &[
                        buffer(0, wgpu::BufferBindingType::Uniform),
                        solari_scene::gpu::loaded_texture_layout_entry(
                            1,
                            wgpu::ShaderStages::COMPUTE,
                        ),
                        buffer(2, wgpu::BufferBindingType::Storage { read_only: false }),
                    ],
                });
        let modules = crate::modules();
        let gbuffer_layout = GBuffer::reader_layout(gpu);
        let pipeline = |entry: &str, layouts: &[Option<&wgpu::BindGroupLayout>]| {
            let wgsl = compose(entry, Backend::Software, &modules)?;
            gpu.compute_pipeline(
                &format!("solari_denoise/{entry}"),
                &wgsl,
                layouts,
                ShaderChecks::BoundsOnly,
                &[],
            )
        };
        let copy_in = pipeline(
            "dlss_inputs",
            &[Some(&copy_in_layout), Some(&gbuffer_layout)],
        )?;
        let copy_out = pipeline("dlss_output", &[Some(&copy_out_layout)])?;
        let params = |(width, height): (u32, u32)| CopyParams {
            width,
            height,
            _pad: [0; 2],
        };
        let copy_in_params = gpu.uniform_buffer("solari_denoise/dlss_inputs", &params(render));
        let copy_out_params =
            gpu.uniform_buffer("solari_denoise/dlss_output", &params(output_size));
        let copy_out_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("solari_denoise/dlss_output"),
            layout: &copy_out_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: copy_out_params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&output_texture.1),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: output.as_entire_binding(),
                },
            ],
        });
        Ok(Self {
            render,
            output_size,
            inputs,
            output_texture,
            output,
            copy_in,
            copy_in_layout,
            copy_in_params,
            copy_out,
            copy_out_group,
            bound: None,
        })
    }

    /// The render resolution (of the inputs).
    pub fn render_size(&self) -> (u32, u32) {
        self.render
    }

    /// The output resolution.
    pub fn output_size(&self) -> (u32, u32) {
        self.output_size
    }

    /// Input view `i` in [`INPUT_FORMATS`] order.
    pub fn input(&self, i: usize) -> &wgpu::TextureView {
        &self.inputs[i].1
    }

    /// Records the input copy from `lighting` (combined, one `vec4<f32>` per render pixel) and
    /// `gbuffer`.
    pub fn encode_inputs(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        profiler: Option<&GpuProfiler>,
        lighting: &wgpu::Buffer,
        gbuffer: &dyn GBufferSource,
    ) -> Result<(), GpuError> {
        solari_scene::gbuffer_input::check_size("DLSS-RR inputs", self.render, gbuffer)?;
        if self.bound.as_ref().map(|(b, _)| b) != Some(lighting) {
            let mut entries = vec![
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.copy_in_params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: lighting.as_entire_binding(),
                },
            ];
            entries.extend(self.inputs.iter().enumerate().map(|(i, (_, v))| {
                wgpu::BindGroupEntry {
                    binding: 2 + i as u32,
                    resource: wgpu::BindingResource::TextureView(v),
                }
            }));
            let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("solari_denoise/dlss_inputs"),
                layout: &self.copy_in_layout,
                entries: &entries,
            });
            self.bound = Some((lighting.clone(), group));
        }
        let group = &self.bound.as_ref().expect("bound above").1;
        let gbuffer_group = gbuffer.bind_group()?;
        let (w, h) = self.render;
        in_scope(profiler, COPY_LABELS[0], encoder, |e| {
            let mut pass = e.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(COPY_LABELS[0]),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.copy_in);
            pass.set_bind_group(0, group, &[]);
            pass.set_bind_group(1, gbuffer_group, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        });
        Ok(())
    }

    /// Records the copy of the output texture into [`DlssTextures::output`] (alpha 1 on
    /// every pixel: at the output resolution there is no surface mask to write).
    pub fn encode_output(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: Option<&GpuProfiler>,
    ) {
        let (w, h) = self.output_size;
        in_scope(profiler, COPY_LABELS[1], encoder, |e| {
            let mut pass = e.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(COPY_LABELS[1]),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.copy_out);
            pass.set_bind_group(0, &self.copy_out_group, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        });
    }

    /// GPU memory of the textures and the output buffer, in bytes.
    pub fn memory_bytes(&self) -> u64 {
        let texel = |f: wgpu::TextureFormat| f.block_copy_size(None).unwrap_or(16) as u64;
        let render = self.render.0 as u64 * self.render.1 as u64;
        let output = self.output_size.0 as u64 * self.output_size.1 as u64;
        INPUT_FORMATS
            .iter()
            .map(|f| render * texel(*f))
            .sum::<u64>()
            + output * (texel(OUTPUT_FORMAT) + 16)
    }
}
