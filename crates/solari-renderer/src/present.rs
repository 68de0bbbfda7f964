//! Writing the renderer's output into the caller's texture: a window's surface texture, an
//! engine's render target, or any texture with `RENDER_ATTACHMENT` usage of the output's
//! size. One fullscreen-triangle draw reads the output buffer (linear radiance, one
//! `vec4<f32>` per pixel) and writes, by the target's format:
//!
//! - float formats (`Rgba16Float`, `Rgba32Float`): linear radiance × 2^exposure, for HDR
//!   targets and further processing;
//! - `*Srgb` formats: the tone curve of the PNG output (Narkowicz's ACES fit after
//!   × 2^exposure), with the hardware's sRGB encoding;
//! - other 8- and 10-bit unorm formats: the same tone curve and the sRGB transfer function
//!   in the shader, so the image matches `solari_reference::image_io::tone_map`.
//!
//! Display-referred sources (the G-buffer debug views) skip exposure and the tone curve and
//! keep the sRGB encoding. Non-finite pixels are written black. A render pass, not a compute pass, so every
//! renderable format works (sRGB formats cannot be storage textures).

use bytemuck::{Pod, Zeroable};
use solari_scene::GpuError;
use solari_scene::bindings::{Buf, BufferGroup};
use solari_scene::gpu::{Gpu, ShaderChecks};
use std::collections::HashMap;

/// The present shader's bindings, by WGSL name.
pub const PRESENT_BINDINGS: BufferGroup =
    BufferGroup::new(0, 0, &[("params", Buf::Uniform), ("image", Buf::Read)]);

/// The present shader (plain WGSL: it needs nothing from the other crates' modules).
pub const PRESENT_WGSL: &str = r#"
struct PresentParams {
    width: u32,
    height: u32,
    // Bit 0: the tone curve; bit 1: the sRGB encoding here (not by the target).
    mode: u32,
    scale: f32,
}

@group(0) @binding(0) var<uniform> params: PresentParams;
@group(0) @binding(1) var<storage, read> image: array<vec4<f32>>;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    // One triangle covering the viewport.
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

fn aces(x: vec3<f32>) -> vec3<f32> {
    let v = max(x, vec3<f32>(0.0));
    return clamp((v * (2.51 * v + 0.03)) / (v * (2.43 * v + 0.59) + 0.14), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn srgb_encode(l: vec3<f32>) -> vec3<f32> {
    return select(1.055 * pow(l, vec3<f32>(1.0 / 2.4)) - 0.055, l * 12.92, l <= vec3<f32>(0.0031308));
}

@fragment
fn fs_main(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = min(vec2<u32>(position.xy), vec2<u32>(params.width - 1u, params.height - 1u));
    let c = image[p.y * params.width + p.x].rgb * params.scale;
    // NaN fails every comparison; infinities fail the bound.
    let finite = all(c == c) && all(abs(c) <= vec3<f32>(3.0e38));
    var out = select(vec3<f32>(0.0), c, finite);
    if (params.mode & 1u) != 0u {
        out = aces(out);
    }
    if (params.mode & 2u) != 0u {
        out = srgb_encode(out);
    }
    return vec4<f32>(out, 1.0);
}
"#;

/// WGSL twin: `PresentParams`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GpuPresentParams {
    width: u32,
    height: u32,
    mode: u32,
    scale: f32,
}

const _: () = assert!(size_of::<GpuPresentParams>() == 16);

/// Draws an output buffer into caller textures (see the module docs).
pub struct Presenter {
    module: wgpu::ShaderModule,
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    params: wgpu::Buffer,
    pipelines: HashMap<wgpu::TextureFormat, wgpu::RenderPipeline>,
    // The group for the last source buffer (the renderer's output changes only on resize).
    group: Option<(wgpu::Buffer, wgpu::BindGroup)>,
}

impl Presenter {
    /// Compiles the shader; pipelines are made per target format on first use.
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        let module = gpu.scoped(|| {
            gpu.shader_module("solari_renderer/present", PRESENT_WGSL, ShaderChecks::All)
        })?;
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("solari_renderer/present"),
                entries: &PRESENT_BINDINGS.layout_entries(wgpu::ShaderStages::FRAGMENT),
            });
        let pipeline_layout = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("solari_renderer/present"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        Ok(Self {
            module,
            layout,
            pipeline_layout,
            params: gpu.uniform_buffer("solari_renderer/present", &GpuPresentParams::zeroed()),
            pipelines: HashMap::new(),
            group: None,
        })
    }

    /// How the shader writes radiance to `format`: 0 linear, 1 tone curve (hardware sRGB),
    /// 3 tone curve and sRGB in the shader (bit 0: tone curve, bit 1: sRGB encoding); `None`
    /// for formats it cannot write (depth, integer, compressed).
    pub fn mode(format: wgpu::TextureFormat) -> Option<u32> {
        use wgpu::TextureFormat as F;
        match format {
            F::Rgba16Float | F::Rgba32Float | F::Rg11b10Ufloat => Some(0),
            f if f.is_srgb() => Some(1),
            F::Rgba8Unorm | F::Bgra8Unorm | F::Rgb10a2Unorm | F::Rgba16Unorm => Some(3),
            _ => None,
        }
    }

    /// Records the draw of `source` (`size.0 × size.1` `vec4<f32>`, row by row from the top
    /// left) into `target`: radiance scaled by 2^`exposure_ev` through the tone curve, or
    /// with `exposure_ev` `None` display-referred values as they are (sRGB-encoded for 8-
    /// and 10-bit targets). Errors, recording nothing, when the target's size differs from
    /// `size`, it lacks `RENDER_ATTACHMENT`, its format cannot be written, or the exposure
    /// is not finite.
    pub fn encode(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        source: &wgpu::Buffer,
        size: (u32, u32),
        target: &wgpu::TextureView,
        exposure_ev: Option<f32>,
    ) -> Result<(), GpuError> {
        let texture = target.texture();
        let format = texture.format();
        let refuse = |why: String| Err(GpuError::Validation(format!("present: {why}")));
        if (texture.width(), texture.height()) != size {
            return refuse(format!(
                "target is {}×{}, the output {}×{}",
                texture.width(),
                texture.height(),
                size.0,
                size.1
            ));
        }
        if !texture
            .usage()
            .contains(wgpu::TextureUsages::RENDER_ATTACHMENT)
        {
            return refuse("the target lacks RENDER_ATTACHMENT usage".into());
        }
        let Some(mode) = Self::mode(format) else {
            return refuse(format!("cannot write {format:?} targets"));
        };
        let (mode, scale) = match exposure_ev {
            Some(ev) if !ev.is_finite() => {
                return refuse(format!("exposure {ev} EV is not finite"));
            }
            Some(ev) => (mode, ev.exp2()),
            // As they are: no tone curve, no exposure.
            None => (mode & !1, 1.0),
        };
        if source.size() < size.0 as u64 * size.1 as u64 * 16 {
            return refuse("the source buffer is smaller than the output".into());
        }
        let params = GpuPresentParams {
            width: size.0,
            height: size.1,
            mode,
            scale,
        };
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        if self.group.as_ref().is_none_or(|(b, _)| b != source) {
            let group = PRESENT_BINDINGS.bind(
                gpu,
                "solari_renderer/present",
                &self.layout,
                &[("params", &self.params), ("image", source)],
            );
            self.group = Some((source.clone(), group));
        }
        if !self.pipelines.contains_key(&format) {
            let pipeline = gpu.scoped(|| self.pipeline(gpu, format))?;
            self.pipelines.insert(format, pipeline);
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("solari_renderer/present"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipelines[&format]);
        pass.set_bind_group(0, &self.group.as_ref().expect("bound above").1, &[]);
        pass.draw(0..3, 0..1);
        Ok(())
    }

    fn pipeline(&self, gpu: &Gpu, format: wgpu::TextureFormat) -> wgpu::RenderPipeline {
        gpu.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("solari_renderer/present"),
                layout: Some(&self.pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &self.module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &self.module,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
    }
}
