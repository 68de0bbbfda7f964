//! ReSTIR DI over a G-buffer that your own renderer draws: this example rasterises the
//! built-in Cornell box with a vertex-buffer pipeline of its own (as an engine would, not
//! Solari's G-buffer pass), binds those textures with `ExternalGBuffer`, and runs light
//! tiles and ReSTIR DI on them. To show the binding is faithful it renders the same frames
//! on Solari's raster G-buffer too and compares the two images.
//!
//! ```sh
//! cargo run --release -p solari-restir --example own_gbuffer [-- software|ray-query]
//! ```

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use solari_lights::{GpuLights, LightList, LightTileSettings, LightTiles, Selection};
use solari_restir::{RestirDi, RestirDiSettings};
use solari_scene::gbuffer::{
    DEPTH_FORMAT, EMISSION_FORMAT, GBUFFER_FORMAT, GBuffer, MOTION_FORMAT, view_projection,
};
use solari_scene::gbuffer_input::{ExternalGBuffer, GBufferSource, GBufferViews};
use solari_scene::gpu::{Gpu, TracerChoice, buffer_layout_entry};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::pass::FrameContext;
use solari_scene::shaders::{Backend, compose};
use solari_scene::{Camera, Scene, default_scene};

const SIZE: (u32, u32) = (128, 128);
/// The raster depth test's format (the example's own choice; readers never see it).
const DEPTH_TEST_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
const FRAMES: u32 = 8;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    run(&args)
}

/// The example, with its command-line arguments: an optional tracer (`auto`, `software`,
/// `ray-query`; the default is `auto`, which `SOLARI_TRACER` overrides).
pub fn run(args: &[String]) -> Result<(), Box<dyn std::error::Error>> {
    let choice = match args.first() {
        Some(name) => TracerChoice::parse(name).ok_or(format!("unknown tracer '{name}'"))?,
        None => TracerChoice::Auto.with_env_override()?,
    };
    let scene = default_scene::cornell_box();
    let camera = scene.camera(None).ok_or("the scene has no camera")?;
    let gpu = Gpu::new()?;
    let backend = gpu.backend(choice)?;
    // Shadow rays still trace Solari's copy of the scene.
    let gpu_scene = GpuScene::new(&gpu, &scene, backend, &GpuSceneOptions::default())?;
    let list = LightList::build(&scene);
    let lights = GpuLights::new(&gpu, &list, Selection::Power)?;
    let tile_settings = LightTileSettings::default();
    let tiles = LightTiles::new(&gpu, tile_settings)?;
    let lights_group = tiles.reader_group(&gpu, &lights);
    let light_count = list.len() as u32;

    // Your renderer: its own mesh format, pipeline and two sets of targets it alternates.
    let own = OwnGBufferPass::new(&gpu, &scene, SIZE)?;
    let targets = [0, 1].map(|i| Targets::new(&gpu, SIZE, i));
    let mut external = ExternalGBuffer::new(&gpu, SIZE.0, SIZE.1)?;
    // Solari's raster G-buffer, for the comparison.
    let mut solari_gbuffer = GBuffer::new(&gpu, backend, SIZE.0, SIZE.1)?;

    let variant = TraceVariant::for_scene(&gpu_scene);
    let di_settings = RestirDiSettings::default();
    let new_di = || {
        RestirDi::new(
            &gpu,
            backend,
            variant,
            SIZE.0,
            SIZE.1,
            di_settings,
            tile_settings,
        )
    };
    let (mut di_own, mut di_solari) = (new_di()?, new_di()?);

    for frame in 0..FRAMES {
        let (now, before) = (
            &targets[frame as usize % 2],
            &targets[1 - frame as usize % 2],
        );
        // What every pass shares this frame (a still camera: last frame's view is the same).
        let context = FrameContext::new(frame, SIZE, &camera, Some(&camera));
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        own.encode(&gpu, &mut encoder, &camera, now);
        external.prepare(
            &gpu,
            &camera,
            now.views(),
            (frame > 0).then(|| before.views()),
        )?;
        solari_gbuffer.prepare(&gpu, &scene, &camera)?;
        solari_gbuffer.encode(&mut encoder, &context, &gpu_scene)?;
        tiles.prepare(&gpu, &context);
        tiles.encode(&mut encoder, &context, &lights);
        for (di, gbuffer) in [
            (&mut di_own, &external as &dyn GBufferSource),
            (&mut di_solari, &solari_gbuffer),
        ] {
            di.prepare(&gpu, &context, gbuffer, &lights)?;
            di.encode(
                &mut encoder,
                &context,
                &gpu_scene,
                gbuffer,
                &lights_group,
                light_count,
            )?;
        }
        gpu.queue.submit([encoder.finish()]);
    }

    let read = |di: &RestirDi| -> Result<Vec<[f32; 4]>, solari_scene::GpuError> {
        let bytes = gpu.read_buffer(di.output(), SIZE.0 as u64 * SIZE.1 as u64 * 16)?;
        Ok(bytemuck::cast_slice(&bytes).to_vec())
    };
    gpu.check_errors()?;
    let (a, b) = (read(&di_own)?, read(&di_solari)?);
    let luminance = |p: &[f32; 4]| (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) as f64;
    let mean = |img: &[[f32; 4]]| img.iter().map(luminance).sum::<f64>() / img.len() as f64;
    let (mean_own, mean_solari) = (mean(&a), mean(&b));
    let rmse = (a
        .iter()
        .zip(&b)
        .map(|(p, q)| (luminance(p) - luminance(q)).powi(2))
        .sum::<f64>()
        / a.len() as f64)
        .sqrt();
    let covered = a.iter().filter(|p| p[3] > 0.5).count();
    println!(
        "{FRAMES} frames of ReSTIR DI at {}x{} on {backend:?}; lights: {}",
        SIZE.0,
        SIZE.1,
        list.len()
    );
    println!("own G-buffer:    mean luminance {mean_own:.4}, {covered} pixels covered");
    println!("Solari G-buffer: mean luminance {mean_solari:.4}");
    println!("RMSE between the two: {rmse:.4}");
    if !(mean_own > 0.0 && a.iter().flatten().all(|v| v.is_finite())) {
        return Err("ReSTIR DI on the own G-buffer gave a black or non-finite image".into());
    }
    // Same surfaces and the same random numbers: only edge pixels and rounding may differ
    // (on lavapipe: means equal to 4 digits, RMSE 0.1% of the mean).
    let relative = (mean_own - mean_solari).abs() / mean_solari;
    if relative > 0.01 || rmse > 0.02 * mean_solari {
        return Err(format!(
            "the own G-buffer's light differs from Solari's: means {mean_own} vs {mean_solari}, RMSE {rmse}"
        )
        .into());
    }
    Ok(())
}

/// One vertex of the example's own mesh format: world position and flat normal with the
/// material baked in, as a simple engine might keep it.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Vertex {
    position: [f32; 3],
    roughness: f32,
    normal: [f32; 3],
    metallic: f32,
    base_color: [f32; 3],
    dielectric_f90: f32,
    emissive: [f32; 3],
    double_sided: f32,
    dielectric_f0: [f32; 3],
    _pad: f32,
}

/// The camera uniform of the example's shader.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ViewUniform {
    view_proj: [[f32; 4]; 4],
}

/// The example's G-buffer shader. It writes Solari's encoding with `pack_gbuffer`; depth
/// comes from the same reversed-Z projection (`view_projection`) that the readers expect, and
/// is written twice: to the depth buffer the raster test uses, and as a colour (the R32Float
/// depth target the readers bind).
const SHADER: &str = r#"
import package::gbuffer::{GBufferSurface, pack_gbuffer};

struct ViewUniform { view_proj: mat4x4<f32> }
@group(0) @binding(0) var<uniform> view: ViewUniform;

struct VertexIn {
    @location(0) position_roughness: vec4<f32>,
    @location(1) normal_metallic: vec4<f32>,
    @location(2) base_f90: vec4<f32>,
    @location(3) emissive_sides: vec4<f32>,
    @location(4) f0: vec4<f32>,
}

struct VertexOut {
    @builtin(position) position: vec4<f32>,
    @location(0) normal_metallic: vec4<f32>,
    @location(1) base_f90: vec4<f32>,
    @location(2) emissive_sides: vec4<f32>,
    @location(3) f0_roughness: vec4<f32>,
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.position = view.view_proj * vec4<f32>(v.position_roughness.xyz, 1.0);
    out.normal_metallic = v.normal_metallic;
    out.base_f90 = v.base_f90;
    out.emissive_sides = v.emissive_sides;
    out.f0_roughness = vec4<f32>(v.f0.xyz, v.position_roughness.w);
    return out;
}

struct GBufferOut {
    @location(0) gbuffer: vec4<u32>,
    @location(1) emission: vec4<f32>,
    @location(2) motion: vec2<f32>,
    @location(3) depth: f32,
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> GBufferOut {
    // Normals face the viewer; emitters shine from their front unless double-sided.
    let n = normalize(in.normal_metallic.xyz) * select(-1.0, 1.0, front);
    var s: GBufferSurface;
    s.base_color = in.base_f90.xyz;
    s.roughness = in.f0_roughness.w;
    s.metallic = in.normal_metallic.w;
    s.dielectric_f0 = in.f0_roughness.xyz;
    s.dielectric_f90 = in.base_f90.w;
    s.emissive = select(vec3<f32>(0.0), in.emissive_sides.xyz, front || in.emissive_sides.w > 0.5);
    s.shading_normal = n;
    s.geometric_normal = n;
    let packed = pack_gbuffer(s);
    // A still camera and scene: no motion.
    return GBufferOut(packed.texel, packed.emission, vec2<f32>(0.0), in.position.z);
}
"#;

/// The example's G-buffer pass: a plain vertex-buffer raster pipeline.
struct OwnGBufferPass {
    pipeline: wgpu::RenderPipeline,
    vertices: wgpu::Buffer,
    vertex_count: u32,
    view: wgpu::Buffer,
    group: wgpu::BindGroup,
    size: (u32, u32),
}

impl OwnGBufferPass {
    fn new(gpu: &Gpu, scene: &Scene, size: (u32, u32)) -> Result<Self, Box<dyn std::error::Error>> {
        let vertices = flatten(scene);
        let wgsl = compose("own_gbuffer", Backend::Software, &[("own_gbuffer", SHADER)])?;
        let module = gpu
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("own_gbuffer"),
                source: wgpu::ShaderSource::Wgsl(wgsl.into()),
            });
        let view = gpu.uniform_buffer("own_gbuffer/view", &ViewUniform::zeroed());
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("own_gbuffer/view"),
                entries: &[buffer_layout_entry(
                    0,
                    wgpu::BufferBindingType::Uniform,
                    wgpu::ShaderStages::VERTEX,
                )],
            });
        let group = gpu.bind_buffers("own_gbuffer/view", &layout, &[&view]);
        let pipeline_layout = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("own_gbuffer"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        let attributes = wgpu::vertex_attr_array![
            0 => Float32x4, 1 => Float32x4, 2 => Float32x4, 3 => Float32x4, 4 => Float32x4
        ];
        let target = |format| {
            Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })
        };
        let pipeline = gpu
            .device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("own_gbuffer"),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: size_of::<Vertex>() as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &attributes,
                    })],
                },
                primitive: wgpu::PrimitiveState::default(),
                // Reversed Z: nearer is greater, cleared to 0 (infinitely far).
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_TEST_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Greater),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &[
                        target(GBUFFER_FORMAT),
                        target(EMISSION_FORMAT),
                        target(MOTION_FORMAT),
                        target(DEPTH_FORMAT),
                    ],
                }),
                multiview_mask: None,
                cache: None,
            });
        let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("own_gbuffer/vertices"),
            size: (vertices.len() * size_of::<Vertex>()) as u64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        gpu.queue
            .write_buffer(&buffer, 0, bytemuck::cast_slice(&vertices));
        Ok(Self {
            pipeline,
            vertices: buffer,
            vertex_count: vertices.len() as u32,
            view,
            group,
            size,
        })
    }

    fn encode(&self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, camera: &Camera, t: &Targets) {
        let view_proj = view_projection(camera, self.size.0, self.size.1);
        let uniform = ViewUniform {
            view_proj: view_proj.to_cols_array_2d(),
        };
        gpu.queue
            .write_buffer(&self.view, 0, bytemuck::bytes_of(&uniform));
        let color = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("own_gbuffer"),
            color_attachments: &[
                color(&t.gbuffer),
                color(&t.emission),
                color(&t.motion),
                color(&t.depth),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth_test,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.draw(0..self.vertex_count, 0..1);
    }
}

/// One set of the example's render targets, in the formats `ExternalGBuffer` reads.
struct Targets {
    gbuffer: wgpu::TextureView,
    emission: wgpu::TextureView,
    motion: wgpu::TextureView,
    depth: wgpu::TextureView,
    // The raster depth test's own buffer; readers see `depth`.
    depth_test: wgpu::TextureView,
}

impl Targets {
    fn new(gpu: &Gpu, (width, height): (u32, u32), index: usize) -> Self {
        let make = |name: &str, format| {
            let usage =
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
            let label = format!("own_gbuffer/{name}_{index}");
            gpu.texture_2d(&label, (width, height), format, usage)
                .create_view(&Default::default())
        };
        Self {
            gbuffer: make("gbuffer", GBUFFER_FORMAT),
            emission: make("emission", EMISSION_FORMAT),
            motion: make("motion", MOTION_FORMAT),
            depth: make("depth", DEPTH_FORMAT),
            depth_test: make("depth_test", DEPTH_TEST_FORMAT),
        }
    }

    fn views(&self) -> GBufferViews<'_> {
        GBufferViews {
            gbuffer: &self.gbuffer,
            emission: &self.emission,
            motion: &self.motion,
            depth: &self.depth,
        }
    }
}

/// The scene's triangles in world space, one vertex per corner, with flat normals from the
/// winding and each instance's material (the Cornell box has no textures).
fn flatten(scene: &Scene) -> Vec<Vertex> {
    let mut out = Vec::new();
    for instance in &scene.instances {
        let mesh = &scene.meshes[instance.mesh as usize];
        let m = &scene.materials[instance.material as usize];
        let to_world: Mat4 = instance.transform;
        for tri in mesh.indices.chunks_exact(3) {
            let p = [tri[0], tri[1], tri[2]]
                .map(|i| to_world.transform_point3(mesh.positions[i as usize]));
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or(Vec3::Y);
            for position in p {
                out.push(Vertex {
                    position: position.into(),
                    roughness: m.roughness,
                    normal: n.into(),
                    metallic: m.metallic,
                    base_color: m.base_color.truncate().into(),
                    dielectric_f90: m.dielectric_f90,
                    emissive: m.emissive.into(),
                    double_sided: m.double_sided as u32 as f32,
                    dielectric_f0: m.dielectric_f0.into(),
                    _pad: 0.0,
                });
            }
        }
    }
    out
}
