//! Upload of a [`Scene`] to the GPU: bind group 0 (geometry, materials, textures and the
//! acceleration structure of the chosen tracing backend).

use crate::bvh::{BvhQuality, SoftwareBvh, merge_fits, merge_triangle_counts};
use crate::error::GpuError;
use crate::gpu::{Gpu, buffer_layout_entry};
use crate::gpu_types::*;
use crate::model::{ColorSpace, MipLevel, Scene};
use crate::shaders::Backend;
use bytemuck::cast_slice;
use glam::Mat4;

/// Upload settings.
#[derive(Clone, Debug)]
pub struct GpuSceneOptions {
    /// BVH build quality for the software backend. Higher quality costs build time and
    /// traverses faster.
    pub bvh_quality: BvhQuality,
    /// Largest texture-array layer edge in texels. Every texture is resampled to one square
    /// layer size (the largest texture, capped here) so textures work on adapters without
    /// binding arrays; larger values keep detail at the cost of memory. Default 1024.
    pub max_texture_size: u32,
    /// The BRDF every pass shades this scene with (`brdf::BrdfModel`; default the
    /// energy-conserving layered model).
    pub brdf: crate::brdf::BrdfModel,
    /// Software backend: trace all instances through one merged world-space BVH
    /// (`SoftwareBvh::build_merged`) instead of a BVH per mesh under a top level over the
    /// instances. Default on. Merged traversal has no top level and no per-instance transform
    /// (on an H100 the 1,290-instance `interior` traces primary + hemisphere rays in 0.98 ms
    /// instead of 1.37, `benches/RESULTS.md`), but it copies each instance's triangles, so it
    /// applies only
    /// within `bvh::merge_fits`' size rule and the device's binding limit; and moving,
    /// adding or removing an instance ([`GpuScene::set_instances`]) splits the scene into
    /// the two-level BVH for good, since a scene that moved once will move again. Material
    /// changes keep it merged.
    pub merge_instances: bool,
    /// Software backend: build the emitter BVH, a world-space BVH over the instances whose
    /// material emits, so that rays looking only for emitters (ReSTIR DI's BRDF-sampled
    /// candidates, WGSL `trace_emitters`) pass every other surface and skip most of the
    /// scene (on an H100, ReSTIR DI's first pass on `interior` took 0.90 ms with it and
    /// 1.26 without, `benches/RESULTS.md`). Default on. It copies each emissive instance's triangles,
    /// so it applies only within `bvh::emitters_fit`'s size rule and the device's binding
    /// limit; without it ([`EmitterTracing::FirstSurface`]) emitter rays trace the whole
    /// scene and find only emitters they see.
    pub emitter_bvh: bool,
}

/// How rays that look only for emitters (WGSL `trace_emitters`) are traced in a
/// [`GpuScene`] ([`GpuScene::emitter_tracing`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EmitterTracing {
    /// No instance emits: emitter rays miss.
    NoEmitters,
    /// The first emitter along the ray, through any other surface: the emitter BVH, or with
    /// ray queries the instances' emitter mask ([`MASK_EMITTER`]).
    EmittersOnly,
    /// The first surface along the ray if it emits, else a miss: software tracing without an
    /// emitter BVH ([`GpuSceneOptions::emitter_bvh`], `bvh::EMITTERS_IN_SCENE`).
    FirstSurface,
}

impl Default for GpuSceneOptions {
    fn default() -> Self {
        Self {
            bvh_quality: BvhQuality::Medium,
            max_texture_size: 1024,
            brdf: crate::brdf::BrdfModel::default(),
            merge_instances: true,
            emitter_bvh: true,
        }
    }
}

/// Bind group 0 entries: (binding, WGSL name). Kept beside the layout so the order is written
/// out, not implied.
const BINDINGS: &[(u32, &str)] = &[
    (0, "instances"),
    (1, "materials"),
    (2, "vertices"),
    (3, "indices"),
    (4, "textures_srgb"),
    (5, "textures_linear"),
    (6, "texture_sampler"),
    (7, "scene_info"),
    (8, "scene_tlas | bvh_nodes"),
    (9, "bvh_triangles"),
    (10, "tlas_instances"),
    (11, "brdf_energy"),
    (12, "environment_map"),
];

enum Accel {
    RayQuery {
        blas: Vec<wgpu::Blas>,
        tlas: wgpu::Tlas,
    },
    Software {
        // Boxed: the CPU-side BVH is far larger than the ray-query variant.
        bvh: Box<SoftwareBvh>,
        nodes: wgpu::Buffer,
        triangles: wgpu::Buffer,
        tlas_instances: wgpu::Buffer,
    },
}

/// A scene on the GPU.
pub struct GpuScene {
    /// The backend the acceleration structure was built for.
    pub backend: Backend,
    layout: wgpu::BindGroupLayout,
    bind_group: wgpu::BindGroup,
    instances: wgpu::Buffer,
    materials: wgpu::Buffer,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    srgb: wgpu::TextureView,
    linear: wgpu::TextureView,
    sampler: wgpu::Sampler,
    brdf_energy: wgpu::TextureView,
    environment: wgpu::TextureView,
    info: wgpu::Buffer,
    accel: Accel,
    mesh_offsets: Vec<(u32, u32)>,
    options: GpuSceneOptions,
    info_data: GpuSceneInfo,
    // Whether instance 0's transform is exactly the identity (`TraceVariant::SingleUntransformed`).
    first_instance_identity: bool,
    // Whether any instance's material emits (after the last `set_instances`).
    emits: bool,
    generation: u64,
}

fn rows(m: Mat4) -> [[f32; 4]; 3] {
    let t = m.transpose();
    [t.x_axis.into(), t.y_axis.into(), t.z_axis.into()]
}

// The software backend's BVH for `scene`: merged where the options, the size rule and the
// device's binding limit allow, else two-level.
fn software_accel(gpu: &Gpu, scene: &Scene, options: &GpuSceneOptions) -> Result<Accel, GpuError> {
    if options.merge_instances && merge_fits(scene) {
        let bvh = SoftwareBvh::build_merged_with(scene, options.bvh_quality, options.emitter_bvh);
        match upload_software(gpu, bvh, scene, options.bvh_quality) {
            Ok(accel) => return Ok(accel),
            Err(e @ GpuError::OverLimit { .. }) => {
                log::info!("merged BVH over the device's limits ({e}): two-level instead")
            }
            Err(e) => return Err(e),
        }
    } else if options.merge_instances {
        let (merged, meshes) = merge_triangle_counts(scene);
        log::info!(
            "not merging instances: {merged} instanced triangles against {meshes} in the meshes \
             (bvh::merge_fits); two-level BVH"
        );
    }
    let bvh = SoftwareBvh::build_with(scene, options.bvh_quality, options.emitter_bvh);
    upload_software(gpu, bvh, scene, options.bvh_quality)
}

fn log_bvh(bvh: &SoftwareBvh) {
    log::info!(
        "software BVH ({}, {}): {} nodes, {} triangles, {:.1} MiB, BLAS {:?}, TLAS {:?}",
        if bvh.is_merged() {
            "merged"
        } else {
            "two-level"
        },
        match bvh.emitter_root {
            crate::bvh::NO_EMITTERS => "no emitters",
            crate::bvh::EMITTERS_IN_SCENE => "no emitter BVH",
            _ => "emitter BVH",
        },
        bvh.nodes.len(),
        bvh.triangles.len(),
        bvh.gpu_bytes() as f64 / 1048576.0,
        bvh.blas_build_time,
        bvh.tlas_build_time
    );
}

// Uploads `bvh` (built for `scene`; see `fitting_buffers`).
fn upload_software(
    gpu: &Gpu,
    mut bvh: SoftwareBvh,
    scene: &Scene,
    quality: BvhQuality,
) -> Result<Accel, GpuError> {
    log_bvh(&bvh);
    let [nodes, triangles, tlas_instances] = fitting_buffers(gpu, &mut bvh, scene, quality)?;
    Ok(Accel::Software {
        nodes,
        triangles,
        tlas_instances,
        bvh: Box::new(bvh),
    })
}

// `software_buffers`, except that over the device's binding limit with an emitter BVH, `bvh`
// leaves the emitter BVH out (for good) and is tried once more: at upload and at the light
// switches that rebuild it.
fn fitting_buffers(
    gpu: &Gpu,
    bvh: &mut SoftwareBvh,
    scene: &Scene,
    quality: BvhQuality,
) -> Result<[wgpu::Buffer; 3], GpuError> {
    match software_buffers(gpu, bvh) {
        Err(e @ GpuError::OverLimit { .. }) if bvh.has_emitter_bvh() => {
            log::info!(
                "BVH with its emitter BVH over the device's limits ({e}): emitter rays trace \
                 the whole scene"
            );
            bvh.set_emitter_bvh(false, scene, quality);
            log_bvh(bvh);
            software_buffers(gpu, bvh)
        }
        other => other,
    }
}

// The software BVH's buffers: nodes, triangles, TLAS leaf instances.
fn software_buffers(gpu: &Gpu, bvh: &SoftwareBvh) -> Result<[wgpu::Buffer; 3], GpuError> {
    let usage = wgpu::BufferUsages::empty();
    Ok([
        gpu.storage_buffer("solari_scene/bvh_nodes", cast_slice(&bvh.nodes), usage)?,
        gpu.storage_buffer(
            "solari_scene/bvh_triangles",
            cast_slice(&bvh.triangles),
            usage,
        )?,
        gpu.storage_buffer(
            "solari_scene/tlas_instances",
            cast_slice(&bvh.tlas_instances),
            usage,
        )?,
    ])
}

fn normal_rows(m: Mat4) -> [[f32; 4]; 3] {
    let n = glam::Mat3::from_mat4(m).inverse().transpose();
    let n4 = Mat4::from_mat3(n);
    rows(n4)
}

impl GpuScene {
    /// GPU memory the scene holds, in bytes: geometry, materials, textures with their mips,
    /// and the software backend's BVH. Ray-query acceleration structures are left out (wgpu
    /// does not report their size).
    pub fn memory_bytes(&self) -> u64 {
        let buffers = [
            &self.instances,
            &self.materials,
            &self.vertices,
            &self.indices,
            &self.info,
        ]
        .iter()
        .map(|b| b.size())
        .sum::<u64>();
        let textures: u64 = [
            &self.srgb,
            &self.linear,
            &self.brdf_energy,
            &self.environment,
        ]
        .iter()
        .map(|v| crate::gpu::texture_bytes(v.texture()))
        .sum();
        let accel = match &self.accel {
            Accel::RayQuery { .. } => 0,
            Accel::Software {
                nodes,
                triangles,
                tlas_instances,
                ..
            } => nodes.size() + triangles.size() + tlas_instances.size(),
        };
        buffers + textures + accel
    }

    /// The bind group layout for `backend` (group 0).
    pub fn layout_for(gpu: &Gpu, backend: Backend) -> wgpu::BindGroupLayout {
        // Buffers are also visible to vertex shaders: the G-buffer raster pulls vertices.
        let stages =
            wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::VERTEX;
        let storage = |binding| {
            buffer_layout_entry(
                binding,
                wgpu::BufferBindingType::Storage { read_only: true },
                stages,
            )
        };
        let texture = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: wgpu::TextureViewDimension::D2Array,
                multisampled: false,
            },
            count: None,
        };
        let mut entries = vec![
            storage(0),
            storage(1),
            storage(2),
            storage(3),
            texture(4),
            texture(5),
            wgpu::BindGroupLayoutEntry {
                binding: 6,
                visibility: wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
            buffer_layout_entry(7, wgpu::BufferBindingType::Uniform, stages),
        ];
        match backend {
            Backend::RayQuery => entries.push(wgpu::BindGroupLayoutEntry {
                binding: 8,
                visibility: wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::AccelerationStructure {
                    vertex_return: false,
                },
                count: None,
            }),
            Backend::Software => entries.extend([storage(8), storage(9), storage(10)]),
        }
        // Read with textureLoad (filtered by hand, as the CPU twins do).
        let unfiltered = |binding| {
            crate::gpu::loaded_texture_layout_entry(
                binding,
                wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT,
            )
        };
        entries.extend([unfiltered(11), unfiltered(12)]);
        debug_assert!(
            entries
                .iter()
                .all(|e| BINDINGS.iter().any(|b| b.0 == e.binding))
        );
        gpu.device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(match backend {
                    Backend::RayQuery => "solari_scene/scene_layout:ray_query",
                    Backend::Software => "solari_scene/scene_layout:software",
                }),
                entries: &entries,
            })
    }

    /// Uploads `scene` and builds the acceleration structure for `backend`.
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        backend: Backend,
        options: &GpuSceneOptions,
    ) -> Result<Self, GpuError> {
        if backend == Backend::RayQuery && !gpu.has_ray_query() {
            return Err(GpuError::NoRayQuery(gpu.info.name.clone()));
        }
        // Scenes built in code get the checks that import applies to files.
        scene.validate().map_err(GpuError::BadScene)?;
        let mut vertices = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        let mut mesh_offsets = Vec::new();
        for m in &scene.meshes {
            mesh_offsets.push((vertices.len() as u32, indices.len() as u32));
            for i in 0..m.positions.len() {
                vertices.push(GpuVertex {
                    position: m.positions[i].into(),
                    uv_x: m.uvs[i].x,
                    normal: m.normals[i].into(),
                    uv_y: m.uvs[i].y,
                    tangent: m.tangents[i].into(),
                });
            }
            indices.extend_from_slice(&m.indices);
        }
        let rq_usage = if backend == Backend::RayQuery {
            wgpu::BufferUsages::BLAS_INPUT
        } else {
            wgpu::BufferUsages::empty()
        };
        let vertex_buf =
            gpu.storage_buffer("solari_scene/vertices", cast_slice(&vertices), rq_usage)?;
        let index_buf =
            gpu.storage_buffer("solari_scene/indices", cast_slice(&indices), rq_usage)?;

        let (srgb, linear, layer_size, layer_of) =
            upload_textures(gpu, scene, options.max_texture_size)?;
        let materials: Vec<GpuMaterial> = scene
            .materials
            .iter()
            .map(|m| {
                let tex = |t: Option<u32>| t.map(|i| layer_of[i as usize]).unwrap_or(NO_TEXTURE);
                // Materials built in code skip the importer's clamping: the BRDF must never see
                // values outside its ranges.
                let brdf = crate::brdf::BrdfMaterial {
                    base_color: m.base_color.truncate(),
                    metallic: m.metallic,
                    roughness: m.roughness,
                    dielectric_f0: m.dielectric_f0,
                    dielectric_f90: m.dielectric_f90,
                    model: options.brdf,
                }
                .sanitized();
                GpuMaterial {
                    base_color: brdf.base_color.extend(m.base_color.w).into(),
                    emissive: m.emissive.into(),
                    metallic: brdf.metallic,
                    dielectric_f0: brdf.dielectric_f0.into(),
                    roughness: brdf.roughness,
                    base_color_texture: tex(m.base_color_texture),
                    metallic_roughness_texture: tex(m.metallic_roughness_texture),
                    normal_texture: tex(m.normal_texture),
                    emissive_texture: tex(m.emissive_texture),
                    normal_scale: m.normal_scale,
                    flags: m.double_sided as u32,
                    dielectric_f90: brdf.dielectric_f90,
                    _pad: 0,
                }
            })
            .collect();
        let material_buf = gpu.storage_buffer(
            "solari_scene/materials",
            cast_slice(&materials),
            wgpu::BufferUsages::empty(),
        )?;
        let sampler = gpu.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("solari_scene/texture_sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let (environment, environment_scale) = upload_environment(gpu, scene);
        let info_data = GpuSceneInfo {
            environment_radiance: (scene.environment_radiance * environment_scale).into(),
            instance_count: scene.instances.len() as u32,
            tlas_root: 0,
            texture_layer_size: layer_size,
            brdf_model: options.brdf.gpu_id(),
            environment_sampled: scene.environment_is_light() as u32,
            merged: 0,
            emitter_root: crate::bvh::NO_EMITTERS,
            _pad: [0; 2],
        };
        let info = gpu.uniform_buffer("solari_scene/scene_info", &info_data);
        let accel = match backend {
            Backend::Software => software_accel(gpu, scene, options)?,
            Backend::RayQuery => {
                build_ray_query(gpu, scene, &vertex_buf, &index_buf, &mesh_offsets)?
            }
        };
        let layout = Self::layout_for(gpu, backend);
        // Placeholder buffer until the first `set_instances`.
        let instances = gpu.storage_buffer(
            "solari_scene/instances",
            &[0u8; 16],
            wgpu::BufferUsages::empty(),
        )?;
        let mut this = Self {
            backend,
            bind_group: gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("solari_scene/empty"),
                layout: &gpu
                    .device
                    .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                        label: None,
                        entries: &[],
                    }),
                entries: &[],
            }),
            layout,
            instances,
            materials: material_buf,
            vertices: vertex_buf,
            indices: index_buf,
            srgb,
            linear,
            sampler,
            brdf_energy: upload_energy_table(gpu),
            environment,
            info,
            accel,
            mesh_offsets,
            options: options.clone(),
            info_data,
            first_instance_identity: false,
            emits: false,
            generation: 0,
        };
        this.set_instances(gpu, scene)?;
        Ok(this)
    }

    /// Uploads instance transforms and rebuilds only the top level of the acceleration
    /// structure. Use after moving, adding or removing instances (meshes must be unchanged).
    /// A merged scene ([`GpuSceneOptions::merge_instances`]) keeps its BVH when only
    /// materials changed; otherwise it is split, once, into the two-level BVH (its passes
    /// then need [`TraceVariant::for_scene`] again).
    pub fn set_instances(&mut self, gpu: &Gpu, scene: &Scene) -> Result<(), GpuError> {
        self.generation += 1;
        if let Accel::Software { bvh, .. } = &self.accel
            && bvh.is_merged()
            && !bvh.traces_merged(scene)
        {
            // Instances moved: from now on the top level is rebuilt instead of everything.
            log::info!(
                "instances changed in a merged scene: splitting it into per-mesh BVHs under a \
                 top level (two-level traversal from now on)"
            );
            let q = self.options.bvh_quality;
            let mut bvh = SoftwareBvh::build(scene, q);
            bvh.set_emitter_bvh(self.options.emitter_bvh, scene, q);
            self.accel = upload_software(gpu, bvh, scene, q)?;
        }
        if let Accel::Software {
            bvh,
            nodes,
            triangles,
            tlas_instances,
        } = &mut self.accel
            && !bvh.emitters_match(scene)
        {
            // Which instances emit, or where, changed (a light switched, an emitter moved):
            // the emitter BVH sits before the top level, so everything is uploaded again. In
            // place: rebuilding a copy of the scene's BVH grew a soak's process by 11 MB over
            // its first light switches (benches/RESULTS.md).
            bvh.rebuild_emitters(scene, self.options.bvh_quality);
            match fitting_buffers(gpu, bvh, scene, self.options.bvh_quality) {
                Ok([n, t, i]) => (*nodes, *triangles, *tlas_instances) = (n, t, i),
                Err(e) => {
                    // The old buffers stay bound and consistent with the old `scene_info`;
                    // forget the new emitter set so the next call builds it again.
                    bvh.emitters_from.clear();
                    bvh.emitters_from.push((u32::MAX, u32::MAX, Mat4::ZERO));
                    return Err(e);
                }
            }
        }
        let blas_root = |mesh: u32| match &self.accel {
            Accel::Software { bvh, .. } => bvh.blas_roots[mesh as usize],
            Accel::RayQuery { .. } => 0,
        };
        let mut gpu_instances = Vec::with_capacity(scene.instances.len());
        for inst in &scene.instances {
            let m = inst.transform;
            if !m.is_finite() || m.determinant() == 0.0 || !m.determinant().is_finite() {
                return Err(GpuError::Validation(format!(
                    "instance {}: transform is singular or not finite",
                    inst.name
                )));
            }
            let (vo, io) = self.mesh_offsets[inst.mesh as usize];
            gpu_instances.push(GpuInstance {
                world_to_object: rows(m.inverse()),
                object_to_world: rows(m),
                normal_to_world: normal_rows(m),
                vertex_offset: vo,
                index_offset: io,
                material: inst.material,
                blas_root: blas_root(inst.mesh),
            });
        }
        self.instances = gpu.storage_buffer(
            "solari_scene/instances",
            cast_slice(&gpu_instances),
            wgpu::BufferUsages::empty(),
        )?;
        self.info_data.instance_count = scene.instances.len() as u32;
        self.first_instance_identity = scene
            .instances
            .first()
            .is_some_and(|i| i.transform == Mat4::IDENTITY);
        self.emits = scene
            .instances
            .iter()
            .any(|i| crate::bvh::instance_emits(scene, i));
        match &mut self.accel {
            // A merged BVH traces these instances as it is (checked above): nothing to rebuild.
            Accel::Software { bvh, .. } if bvh.is_merged() => {
                self.info_data.tlas_root = bvh.tlas_root;
                self.info_data.merged = 1;
                self.info_data.emitter_root = bvh.emitter_root;
            }
            Accel::Software {
                bvh,
                nodes,
                tlas_instances,
                ..
            } => {
                self.info_data.merged = 0;
                self.info_data.emitter_root = bvh.emitter_root;
                bvh.rebuild_tlas(scene, self.options.bvh_quality);
                let node_bytes: &[u8] = cast_slice(&bvh.nodes);
                if (node_bytes.len() as u64) <= nodes.size() {
                    // The BLAS nodes in front are unchanged: write only the top level.
                    let start =
                        bvh.blas_node_count as usize * size_of::<obvhs::cwbvh::node::CwBvhNode>();
                    gpu.queue
                        .write_buffer(nodes, start as u64, &node_bytes[start..]);
                } else {
                    // Grow with headroom (one more TLAS, at least 64 nodes) so later instance
                    // changes fit without re-uploading the BLASes.
                    let tlas_bytes = node_bytes.len() - bvh.blas_node_count as usize * 80;
                    let mut padded = node_bytes.to_vec();
                    padded.resize(node_bytes.len() + tlas_bytes.max(80 * 64), 0);
                    *nodes = gpu.storage_buffer(
                        "solari_scene/bvh_nodes",
                        &padded,
                        wgpu::BufferUsages::empty(),
                    )?;
                }
                *tlas_instances = gpu.storage_buffer(
                    "solari_scene/tlas_instances",
                    cast_slice(&bvh.tlas_instances),
                    wgpu::BufferUsages::empty(),
                )?;
                self.info_data.tlas_root = bvh.tlas_root;
            }
            Accel::RayQuery { blas, tlas } => {
                if tlas.get().len() < scene.instances.len() {
                    *tlas = gpu.device.create_tlas(&wgpu::CreateTlasDescriptor {
                        label: Some("solari_scene/tlas"),
                        max_instances: (scene.instances.len() as u32).max(1),
                        flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
                        update_mode: wgpu::AccelerationStructureUpdateMode::Build,
                    });
                }
                let slots = tlas.get().len();
                for i in 0..slots {
                    *tlas.get_mut_single(i).expect("in range") =
                        scene.instances.get(i).map(|inst| {
                            let r = rows(inst.transform);
                            let flat: [f32; 12] =
                                [r[0], r[1], r[2]].concat().try_into().expect("12 floats");
                            wgpu::TlasInstance::new(
                                &blas[inst.mesh as usize],
                                flat,
                                i as u32,
                                instance_mask(scene, inst),
                            )
                        });
                }
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                encoder.build_acceleration_structures(std::iter::empty(), std::iter::once(&*tlas));
                gpu.queue.submit([encoder.finish()]);
            }
        }
        gpu.queue
            .write_buffer(&self.info, 0, bytemuck::bytes_of(&self.info_data));
        self.rebind(gpu);
        Ok(())
    }

    /// Uploads `scene`'s environment (its map, or the uniform radiance) in place of the one
    /// the scene was created with: for a sky that changes at run time. A light list built
    /// from the same scene (`solari_lights::LightList::build`) samples the new map; passes
    /// bound to the old bind group must fetch [`GpuScene::bind_group`] again.
    pub fn set_environment(&mut self, gpu: &Gpu, scene: &Scene) {
        self.generation += 1;
        let (environment, scale) = upload_environment(gpu, scene);
        self.environment = environment;
        self.info_data.environment_radiance = (scene.environment_radiance * scale).into();
        self.info_data.environment_sampled = scene.environment_is_light() as u32;
        gpu.queue
            .write_buffer(&self.info, 0, bytemuck::bytes_of(&self.info_data));
        self.rebind(gpu);
    }

    fn rebind(&mut self, gpu: &Gpu) {
        fn buf(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry {
                binding,
                resource: b.as_entire_binding(),
            }
        }
        let mut entries = vec![
            buf(0, &self.instances),
            buf(1, &self.materials),
            buf(2, &self.vertices),
            buf(3, &self.indices),
            wgpu::BindGroupEntry {
                binding: 4,
                resource: wgpu::BindingResource::TextureView(&self.srgb),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: wgpu::BindingResource::TextureView(&self.linear),
            },
            wgpu::BindGroupEntry {
                binding: 6,
                resource: wgpu::BindingResource::Sampler(&self.sampler),
            },
            buf(7, &self.info),
        ];
        match &self.accel {
            Accel::RayQuery { tlas, .. } => entries.push(wgpu::BindGroupEntry {
                binding: 8,
                resource: tlas.as_binding(),
            }),
            Accel::Software {
                nodes,
                triangles,
                tlas_instances,
                ..
            } => entries.extend([buf(8, nodes), buf(9, triangles), buf(10, tlas_instances)]),
        }
        entries.extend([
            wgpu::BindGroupEntry {
                binding: 11,
                resource: wgpu::BindingResource::TextureView(&self.brdf_energy),
            },
            wgpu::BindGroupEntry {
                binding: 12,
                resource: wgpu::BindingResource::TextureView(&self.environment),
            },
        ]);
        self.bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("solari_scene/scene"),
            layout: &self.layout,
            entries: &entries,
        });
    }

    /// Whether the upload treats the environment as a sampled light
    /// ([`Scene::environment_is_light`] when it was made or last set).
    pub fn environment_sampled(&self) -> bool {
        self.info_data.environment_sampled != 0
    }

    /// Bind group 0's layout.
    pub fn layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// Counts changes to the scene's instances ([`GpuScene::set_instances`]), so progressive
    /// renderers know when to restart.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Whether the software BVH is merged ([`GpuSceneOptions::merge_instances`]): one
    /// world-space level over every instance's triangles.
    pub fn is_merged(&self) -> bool {
        matches!(&self.accel, Accel::Software { bvh, .. } if bvh.is_merged())
    }

    /// How rays that look only for emitters are traced now ([`GpuSceneOptions::emitter_bvh`]).
    pub fn emitter_tracing(&self) -> EmitterTracing {
        match &self.accel {
            Accel::Software { bvh, .. } => match bvh.emitter_root {
                crate::bvh::NO_EMITTERS => EmitterTracing::NoEmitters,
                crate::bvh::EMITTERS_IN_SCENE => EmitterTracing::FirstSurface,
                _ => EmitterTracing::EmittersOnly,
            },
            Accel::RayQuery { .. } if self.emits => EmitterTracing::EmittersOnly,
            Accel::RayQuery { .. } => EmitterTracing::NoEmitters,
        }
    }

    /// Instances in the scene as uploaded now (after the last [`GpuScene::set_instances`]).
    pub fn instance_count(&self) -> u32 {
        self.info_data.instance_count
    }

    /// Bind group 0.
    pub fn bind_group(&self) -> &wgpu::BindGroup {
        &self.bind_group
    }

    /// The software BVH, when that backend is in use.
    pub fn software_bvh(&self) -> Option<&SoftwareBvh> {
        match &self.accel {
            Accel::Software { bvh, .. } => Some(bvh),
            Accel::RayQuery { .. } => None,
        }
    }
}

/// Ray-query instance mask bit of every instance: plain rays (cull mask 0xff) see them all.
pub const MASK_ALL: u8 = 0x01;

/// Ray-query instance mask bit of instances whose material emits: `trace_emitters` (WGSL,
/// cull mask `EMITTER_MASK` in trace.wesl) sees only these, as the software backend's
/// emitter BVH holds only these (`bvh::emitter_layout`).
pub const MASK_EMITTER: u8 = 0x02;

fn instance_mask(scene: &Scene, inst: &crate::model::Instance) -> u8 {
    let emits = scene
        .materials
        .get(inst.material as usize)
        .is_some_and(|m| m.is_emissive());
    MASK_ALL | if emits { MASK_EMITTER } else { 0 }
}

fn build_ray_query(
    gpu: &Gpu,
    scene: &Scene,
    vertices: &wgpu::Buffer,
    indices: &wgpu::Buffer,
    offsets: &[(u32, u32)],
) -> Result<Accel, GpuError> {
    let sizes: Vec<wgpu::BlasTriangleGeometrySizeDescriptor> = scene
        .meshes
        .iter()
        .map(|m| wgpu::BlasTriangleGeometrySizeDescriptor {
            vertex_format: wgpu::VertexFormat::Float32x3,
            vertex_count: m.positions.len() as u32,
            index_format: Some(wgpu::IndexFormat::Uint32),
            index_count: Some(m.indices.len() as u32),
            flags: wgpu::AccelerationStructureGeometryFlags::OPAQUE,
        })
        .collect();
    let blas: Vec<wgpu::Blas> = sizes
        .iter()
        .map(|s| {
            gpu.device.create_blas(
                &wgpu::CreateBlasDescriptor {
                    label: Some("solari_scene/blas"),
                    flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
                    update_mode: wgpu::AccelerationStructureUpdateMode::Build,
                },
                wgpu::BlasGeometrySizeDescriptors::Triangles {
                    descriptors: vec![s.clone()],
                },
            )
        })
        .collect();
    let entries: Vec<wgpu::BlasBuildEntry> = blas
        .iter()
        .zip(&sizes)
        .zip(offsets)
        .map(|((b, size), &(vo, io))| wgpu::BlasBuildEntry {
            blas: b,
            geometry: wgpu::BlasGeometries::TriangleGeometries(vec![wgpu::BlasTriangleGeometry {
                size,
                vertex_buffer: vertices,
                first_vertex: vo,
                vertex_stride: size_of::<GpuVertex>() as u64,
                index_buffer: Some(indices),
                first_index: Some(io),
                transform_buffer: None,
                transform_buffer_offset: None,
            }]),
        })
        .collect();
    let tlas = gpu.device.create_tlas(&wgpu::CreateTlasDescriptor {
        label: Some("solari_scene/tlas"),
        max_instances: (scene.instances.len() as u32).max(1),
        flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
        update_mode: wgpu::AccelerationStructureUpdateMode::Build,
    });
    gpu.scoped(|| {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.build_acceleration_structures(entries.iter(), std::iter::empty());
        gpu.queue.submit([encoder.finish()]);
    })?;
    Ok(Accel::RayQuery { blas, tlas })
}

/// Uploads textures into one sRGB and one linear 2D array (one layer each, resampled to a
/// common square size). Returns the views, the layer size and each scene texture's layer.
fn upload_textures(
    gpu: &Gpu,
    scene: &Scene,
    max_size: u32,
) -> Result<(wgpu::TextureView, wgpu::TextureView, u32, Vec<u32>), GpuError> {
    let limits = gpu.device.limits();
    let largest = scene
        .textures
        .iter()
        .map(|t| t.mips[0].width.max(t.mips[0].height))
        .max()
        .unwrap_or(1);
    let size = largest
        .min(max_size.max(1))
        .min(limits.max_texture_dimension_2d)
        .max(1);
    let mut layer_of = Vec::with_capacity(scene.textures.len());
    let (mut srgb_layers, mut linear_layers) = (Vec::new(), Vec::new());
    for t in &scene.textures {
        let list = if t.color_space == ColorSpace::Srgb {
            &mut srgb_layers
        } else {
            &mut linear_layers
        };
        layer_of.push(list.len() as u32);
        list.push(resample(t, size));
    }
    for (n, what) in [
        (srgb_layers.len(), "sRGB texture layers"),
        (linear_layers.len(), "linear texture layers"),
    ] {
        if n as u32 > limits.max_texture_array_layers {
            return Err(GpuError::OverLimit {
                what: what.into(),
                needed: n as u64,
                limit: limits.max_texture_array_layers as u64,
            });
        }
    }
    let make = |layers: Vec<Vec<MipLevel>>, format, label| {
        let white = vec![MipLevel {
            width: 1,
            height: 1,
            rgba8: vec![255; 4],
        }];
        let layers = if layers.is_empty() {
            vec![white]
        } else {
            layers
        };
        let (w, mips) = (layers[0][0].width, layers[0].len() as u32);
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: w,
                height: w,
                depth_or_array_layers: layers.len() as u32,
            },
            mip_level_count: mips,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        for (layer, chain) in layers.iter().enumerate() {
            for (level, mip) in chain.iter().enumerate() {
                gpu.queue.write_texture(
                    wgpu::TexelCopyTextureInfo {
                        texture: &texture,
                        mip_level: level as u32,
                        origin: wgpu::Origin3d {
                            x: 0,
                            y: 0,
                            z: layer as u32,
                        },
                        aspect: wgpu::TextureAspect::All,
                    },
                    &mip.rgba8,
                    wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(mip.width * 4),
                        rows_per_image: Some(mip.height),
                    },
                    wgpu::Extent3d {
                        width: mip.width,
                        height: mip.height,
                        depth_or_array_layers: 1,
                    },
                );
            }
        }
        texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        })
    };
    let srgb = make(
        srgb_layers,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        "solari_scene/textures_srgb",
    );
    let linear = make(
        linear_layers,
        wgpu::TextureFormat::Rgba8Unorm,
        "solari_scene/textures_linear",
    );
    Ok((srgb, linear, size, layer_of))
}

/// The texture's mip chain at `size`×`size` (resampled from level 0 when the size differs).
fn resample(t: &crate::model::Texture, size: u32) -> Vec<MipLevel> {
    let l0 = &t.mips[0];
    if l0.width == size && l0.height == size {
        return t.mips.clone();
    }
    let img = image::RgbaImage::from_raw(l0.width, l0.height, l0.rgba8.clone())
        .expect("mip 0 holds w*h*4 bytes");
    let resized = image::imageops::resize(&img, size, size, image::imageops::FilterType::Triangle);
    crate::texture::build_mips(
        MipLevel {
            width: size,
            height: size,
            rgba8: resized.into_raw(),
        },
        t.color_space,
    )
}

/// The BRDF's energy table ([`crate::brdf::EnergyTable`]) as an Rg32Float texture read with
/// `textureLoad`: N+1 columns per roughness row, `(A, B)(cos θ)` in the first N and `(A_avg,
/// B_avg)` last.
fn upload_energy_table(gpu: &Gpu) -> wgpu::TextureView {
    let table = crate::brdf::energy_table();
    let n = table.a_avg.len();
    let mut texels = Vec::with_capacity((n + 1) * n * 2);
    for r in 0..n {
        for c in 0..n {
            texels.extend([table.a[r * n + c], table.b[r * n + c]]);
        }
        texels.extend([table.a_avg[r], table.b_avg[r]]);
    }
    let texture = gpu.texture_2d_with(
        "solari_scene/brdf_energy",
        (n as u32 + 1, n as u32),
        wgpu::TextureFormat::Rg32Float,
        wgpu::TextureUsages::TEXTURE_BINDING,
        bytemuck::cast_slice(&texels),
    );
    texture.create_view(&Default::default())
}

/// Half floats stop at 65504: maps brighter than this are stored divided by a scale, which
/// multiplies `GpuSceneInfo::environment_radiance` instead.
const ENVIRONMENT_HALF_MAX: f32 = 60000.0;

/// The environment map as an RGBA16F texture (one texel of 1 for a uniform environment) and
/// the factor its texels were divided by.
fn upload_environment(gpu: &Gpu, scene: &Scene) -> (wgpu::TextureView, f32) {
    let uniform;
    let map = match &scene.environment_map {
        Some(map) => map.as_ref(),
        None => {
            uniform = crate::environment::EnvironmentMap::uniform(glam::Vec3::ONE)
                .expect("one texel is a valid map");
            &uniform
        }
    };
    // Over the device's texture limit (only with a raised `EnvironmentOptions::max_width`):
    // halved until it fits, as the loader does.
    let limit = gpu.device.limits().max_texture_dimension_2d;
    let reduced;
    let map = if map.width() > limit || map.height() > limit {
        let mut m = map.halved();
        while m.width() > limit || m.height() > limit {
            m = m.halved();
        }
        log::warn!(
            "environment map reduced from {} x {} to {} x {} texels: the device's limit is {limit}",
            map.width(),
            map.height(),
            m.width(),
            m.height()
        );
        reduced = m;
        &reduced
    } else {
        map
    };
    let scale = (map.max_component() / ENVIRONMENT_HALF_MAX).max(1.0);
    let texels: Vec<u16> = map
        .texels()
        .iter()
        .flat_map(|t| {
            let t = *t / scale;
            [t.x, t.y, t.z, 0.0].map(|c| half::f16::from_f32(c).to_bits())
        })
        .collect();
    let texture = gpu.texture_2d_with(
        "solari_scene/environment_map",
        (map.width(), map.height()),
        wgpu::TextureFormat::Rgba16Float,
        wgpu::TextureUsages::TEXTURE_BINDING,
        bytemuck::cast_slice(&texels),
    );
    (texture.create_view(&Default::default()), scale)
}

/// How a pipeline's software traversal is specialised for the scene it traces.
///
/// A scene with exactly one instance can skip the top level entirely: the traversal starts in
/// that instance's BLAS and the top-level code is compiled out (the WGSL override
/// `TRACE_SINGLE_INSTANCE`), about 11% faster on an H200. When that instance is also
/// untransformed, rays need no object-space transform either (`TRACE_UNTRANSFORMED`), a further
/// 3–4%: the transformed ray is a second live copy of the ray through the whole traversal.
/// A scene whose instances were merged into one world-space BVH ([`GpuSceneOptions::merge_instances`])
/// traces as one untransformed level whose triangles name their instance
/// ([`TraceVariant::Merged`]).
/// A specialised pipeline refuses, at dispatch, scenes it cannot trace;
/// [`TraceVariant::General`] traces any scene (merged ones through a run-time flag).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TraceVariant {
    /// Two-level traversal: any number of instances.
    #[default]
    General,
    /// Single-level traversal of instance 0 (software backend only).
    SingleInstance,
    /// Single-level traversal of instance 0 whose transform is exactly the identity, so rays
    /// stay in world space (software backend only).
    SingleUntransformed,
    /// Single-level world-space traversal of a merged BVH, each hit's instance read from its
    /// triangle (software backend only).
    Merged,
}

impl TraceVariant {
    /// The fastest variant that can trace `scene` as it is now.
    pub fn for_scene(scene: &GpuScene) -> Self {
        if scene.is_merged() {
            return TraceVariant::Merged;
        }
        match (scene.backend, scene.info_data.instance_count) {
            (Backend::Software, 1) if scene.first_instance_identity => {
                TraceVariant::SingleUntransformed
            }
            (Backend::Software, 1) => TraceVariant::SingleInstance,
            _ => TraceVariant::General,
        }
    }

    /// What this variant means for `backend`: ray queries have no top level of ours to skip,
    /// so they always use [`TraceVariant::General`]. Pass constructors apply this.
    pub fn for_backend(self, backend: Backend) -> Self {
        match backend {
            Backend::RayQuery => TraceVariant::General,
            Backend::Software => self,
        }
    }

    /// The pipeline constants that select this variant.
    pub fn constants(self) -> &'static [(&'static str, f64)] {
        match self {
            TraceVariant::General => &[],
            // `@id(7100) override TRACE_SINGLE_INSTANCE` in trace.wesl.
            TraceVariant::SingleInstance => &[("7100", 1.0)],
            // ... and `@id(7101) override TRACE_UNTRANSFORMED`.
            TraceVariant::SingleUntransformed => &[("7100", 1.0), ("7101", 1.0)],
            // ... and `@id(7102) override TRACE_MERGED`.
            TraceVariant::Merged => &[("7100", 1.0), ("7101", 1.0), ("7102", 1.0)],
        }
    }

    /// A short name for reports: `two-level`, `single-instance`, `single-untransformed` or
    /// `merged`.
    pub fn name(self) -> &'static str {
        match self {
            TraceVariant::General => "two-level",
            TraceVariant::SingleInstance => "single-instance",
            TraceVariant::SingleUntransformed => "single-untransformed",
            TraceVariant::Merged => "merged",
        }
    }

    /// An error when a pipeline of this variant cannot trace `scene`.
    pub fn check(self, scene: &GpuScene) -> Result<(), GpuError> {
        let fits = match self {
            TraceVariant::General => true,
            TraceVariant::SingleInstance => {
                scene.backend == Backend::Software
                    && scene.info_data.instance_count == 1
                    && !scene.is_merged()
            }
            TraceVariant::SingleUntransformed => {
                TraceVariant::SingleInstance.check(scene).is_ok() && scene.first_instance_identity
            }
            TraceVariant::Merged => scene.is_merged(),
        };
        if fits {
            return Ok(());
        }
        Err(GpuError::Validation(format!(
            "a pipeline specialised as {} was given a {} scene with {} instances{}{}; rebuild \
             the pass with TraceVariant::for_scene",
            self.name(),
            scene.backend.name(),
            scene.info_data.instance_count,
            if scene.first_instance_identity {
                ""
            } else {
                " (the first one transformed)"
            },
            if scene.is_merged() {
                ", merged"
            } else {
                ", not merged"
            }
        )))
    }
}
