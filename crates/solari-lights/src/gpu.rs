//! The light list on the GPU: bind group 3 for `shaders/light_sampling.wesl`.

use crate::light_grid::LightGrid;
use crate::light_list::{Light, LightList, Selection, sun_disk};
use bytemuck::{Pod, Zeroable};
use solari_scene::GpuError;
use solari_scene::bindings::{Buf, BufferGroup};
use solari_scene::gpu::Gpu;

/// Bindings 0–3 of group 3 (`light_sampling.wesl`), by WGSL name: the light list.
pub const LIGHT_BINDINGS: BufferGroup = BufferGroup::new(
    3,
    0,
    &[
        ("lights", Buf::Read),
        ("emissive_triangles", Buf::Read),
        ("light_info", Buf::Uniform),
        ("instance_lights", Buf::Read),
    ],
);

/// Binding 6 of group 3 (`light_sampling.wesl`): the environment's sampling distribution,
/// after the tiles' bindings 4–5.
pub const ENVIRONMENT_BINDINGS: BufferGroup =
    BufferGroup::new(3, 6, &[("environment_cells", Buf::Read)]);

/// Bindings 7–8 of group 3 (`light_grid.wesl`): the light grid's cells and their sorted
/// light lists ([`LightGrid`]); one empty cell stands in when the list has no grid.
pub const GRID_BINDINGS: BufferGroup = BufferGroup::new(
    3,
    7,
    &[
        ("light_grid_cells", Buf::Read),
        ("light_grid_lights", Buf::Read),
    ],
);

/// WGSL twin: `GpuEnvironmentCell` in `light_sampling.wesl`: one cell of
/// [`crate::environment::EnvironmentDistribution`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuEnvironmentCell {
    /// Probability of the cell.
    pub pmf: f32,
    /// Alias-table slot: probability of keeping this cell.
    pub threshold: f32,
    /// Alias-table slot: the cell taken otherwise.
    pub alias_index: u32,
}

const _: () = assert!(size_of::<GpuEnvironmentCell>() == 12);

/// WGSL twin: `GpuLight` in `light_sampling.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuLight {
    /// Emissive: radiance. Directional: disk radiance, or irradiance for a delta light.
    /// Point: sphere radiance, or intensity for a delta light.
    pub radiance: [f32; 3],
    /// Emissive: total area. Directional: the disk's solid angle (0 for a delta light).
    /// Point: the sphere's area (0 for a delta light).
    pub area: f32,
    /// Directional: unit direction towards the light. Point: position.
    pub to_light: [f32; 3],
    /// Directional: cosine of the disk's angular radius. Point: the sphere's radius.
    pub cos_radius: f32,
    /// Kind (0 emissive, 1 directional, 2 point, 3 environment) | 0x100 when double-sided | 0x200 with an
    /// emissive texture.
    pub kind: u32,
    /// Emissive: instance index.
    pub instance: u32,
    /// Emissive: first triangle.
    pub first_triangle: u32,
    /// Emissive: triangle count.
    pub triangle_count: u32,
    /// Probability under power-proportional selection.
    pub power_pmf: f32,
    /// Alias-table slot: probability of keeping this light.
    pub alias_threshold: f32,
    /// Alias-table slot: the light taken otherwise.
    pub alias_index: u32,
    /// Point: the cone's offset ([`crate::SpotCone::offset`]; 1 without a cone).
    pub spot_offset: f32,
    /// Point: the cone's axis.
    pub spot_axis: [f32; 3],
    /// Point: the cone's scale (0 without a cone).
    pub spot_scale: f32,
}

const _: () = assert!(size_of::<GpuLight>() == 80);

/// WGSL twin: `GpuEmissiveTriangle` in `light_sampling.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuEmissiveTriangle {
    /// World-space corner 0.
    pub v0: [f32; 3],
    /// Cumulative area fraction within its light.
    pub cdf: f32,
    /// Edge 1.
    pub e1: [f32; 3],
    /// Area.
    pub area: f32,
    /// Edge 2.
    pub e2: [f32; 3],
    /// Triangle index in its mesh.
    pub primitive: u32,
}

const _: () = assert!(size_of::<GpuEmissiveTriangle>() == 48);

/// WGSL twin: `GpuLightInfo` in `light_sampling.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuLightInfo {
    /// Number of lights.
    pub light_count: u32,
    /// 0 uniform, 1 power-proportional.
    pub selection: u32,
    /// Index of the first point or spot light (they come last).
    pub first_punctual: u32,
    /// Number of sphere lights among them that a BRDF ray can hit (0: none to test).
    pub sphere_count: u32,
    /// Index of the environment light, or `u32::MAX` for none.
    pub environment_light: u32,
    /// The environment distribution's cells across.
    pub environment_cells_x: u32,
    /// Its cells down.
    pub environment_cells_y: u32,
    /// Index of the first directional light: they run up to the environment light, or
    /// without one to [`GpuLightInfo::first_punctual`] (`LightList::build`'s order), so that a
    /// BRDF-sampled ray can look for the sun discs it meets.
    pub first_directional: u32,
    /// The light grid's corner ([`LightGrid::origin`]).
    pub grid_origin: [f32; 3],
    /// Its cell edge.
    pub grid_cell_size: f32,
    /// Its cells per axis; zeros without a grid.
    pub grid_dims: [u32; 3],
    /// [`LightGrid::grid_share`]; 0 without a grid.
    pub grid_share: f32,
}

const _: () = assert!(size_of::<GpuLightInfo>() == 64);

/// The GPU form of a [`LightList`], flattened for upload.
pub fn gpu_lights(list: &LightList) -> (Vec<GpuLight>, Vec<GpuEmissiveTriangle>) {
    let lights = list
        .lights
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let alias = list.power_table.entries[i];
            let mut g = GpuLight {
                power_pmf: list.power_table.pmf[i],
                alias_threshold: alias.threshold,
                alias_index: alias.alias,
                ..Zeroable::zeroed()
            };
            match *l {
                Light::Emissive {
                    instance,
                    first_triangle,
                    triangle_count,
                    area,
                    radiance,
                    double_sided,
                    mirrored,
                    emissive_texture,
                } => {
                    g.radiance = radiance.into();
                    g.area = area;
                    // LIGHT_FLAG_DOUBLE_SIDED, LIGHT_FLAG_TEXTURED, LIGHT_FLAG_MIRRORED.
                    g.kind = if double_sided { 0x100 } else { 0 }
                        | if emissive_texture.is_some() { 0x200 } else { 0 }
                        | if mirrored { 0x400 } else { 0 };
                    g.instance = instance;
                    g.first_triangle = first_triangle;
                    g.triangle_count = triangle_count;
                }
                Light::Directional {
                    to_light,
                    irradiance,
                    cos_radius,
                } => {
                    g.kind = 1;
                    g.to_light = to_light.into();
                    g.cos_radius = cos_radius;
                    let (radiance, solid_angle) =
                        sun_disk(irradiance, cos_radius).unwrap_or((irradiance, 0.0));
                    g.radiance = radiance.into();
                    g.area = solid_angle;
                }
                Light::Environment { .. } => {
                    // The factor lives in the scene's `environment_radiance`, which the GPU's
                    // `environment_radiance(d)` applies with the map.
                    g.kind = 3;
                    g.radiance = [1.0; 3];
                }
                Light::Point {
                    position,
                    radius,
                    intensity,
                    cone,
                } => {
                    g.kind = 2;
                    g.to_light = position.into();
                    g.cos_radius = radius;
                    let (radiance, area) = l.sphere().unwrap_or((intensity, 0.0));
                    g.radiance = radiance.into();
                    g.area = area;
                    g.spot_axis = cone.axis.into();
                    g.spot_scale = cone.scale;
                    g.spot_offset = cone.offset;
                }
            }
            g
        })
        .collect();
    let triangles = list
        .triangles
        .iter()
        .map(|t| GpuEmissiveTriangle {
            v0: t.v0.into(),
            cdf: t.cdf,
            e1: t.e1.into(),
            area: t.area,
            e2: t.e2.into(),
            primitive: t.primitive,
        })
        .collect();
    (lights, triangles)
}

/// Bind group 3: the light list on the GPU.
pub struct GpuLights {
    /// The layout every pass that samples lights includes as group 3.
    pub layout: wgpu::BindGroupLayout,
    /// The bind group.
    pub bind_group: wgpu::BindGroup,
    /// Number of lights (0: passes that need lights can skip).
    pub light_count: u32,
    /// [`LightList::sampling_elements`] of the uploaded list.
    pub sampling_elements: u32,
    /// Whether a light grid was uploaded ([`GpuLights::with_grid`]).
    pub has_grid: bool,
    buffers: [wgpu::Buffer; 7],
}

impl GpuLights {
    /// GPU memory the light list holds, in bytes.
    pub fn memory_bytes(&self) -> u64 {
        self.buffers.iter().map(|b| b.size()).sum()
    }

    /// The layout of bind group 3.
    pub fn layout(gpu: &Gpu) -> wgpu::BindGroupLayout {
        let stages = wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT;
        gpu.device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("solari_lights/lights"),
                entries: &Self::layout_entries(stages),
            })
    }

    /// Bindings 0–3 and 6–8 of group 3 ([`LIGHT_BINDINGS`], [`ENVIRONMENT_BINDINGS`],
    /// [`GRID_BINDINGS`]), for layouts that extend it (light tiles).
    pub fn layout_entries(stages: wgpu::ShaderStages) -> Vec<wgpu::BindGroupLayoutEntry> {
        let mut entries = LIGHT_BINDINGS.layout_entries(stages);
        entries.extend(ENVIRONMENT_BINDINGS.layout_entries(stages));
        entries.extend(GRID_BINDINGS.layout_entries(stages));
        entries
    }

    /// The buffers behind bindings 0–3 and 6–8, in binding order.
    pub fn buffers(&self) -> &[wgpu::Buffer; 7] {
        &self.buffers
    }

    /// The bind-group entries of bindings 0–3 and 6–8, for groups that extend them.
    pub fn entries(&self) -> Vec<wgpu::BindGroupEntry<'_>> {
        entries_of(&self.buffers)
    }

    /// Uploads `list` for sampling with `selection`, without a light grid.
    pub fn new(gpu: &Gpu, list: &LightList, selection: Selection) -> Result<Self, GpuError> {
        Self::with_grid(gpu, list, selection, None)
    }

    /// Uploads `list` for sampling with `selection`, and `grid` (built for this list) for
    /// passes that draw candidates from it (`light_grid.wesl`).
    pub fn with_grid(
        gpu: &Gpu,
        list: &LightList,
        selection: Selection,
        grid: Option<&LightGrid>,
    ) -> Result<Self, GpuError> {
        let (lights, triangles) = gpu_lights(list);
        // Storage bindings must not be empty: one zeroed element stands in.
        let light_bytes = if lights.is_empty() {
            vec![0u8; size_of::<GpuLight>()]
        } else {
            bytemuck::cast_slice(&lights).to_vec()
        };
        let tri_bytes = if triangles.is_empty() {
            vec![0u8; size_of::<GpuEmissiveTriangle>()]
        } else {
            bytemuck::cast_slice(&triangles).to_vec()
        };
        let empty = wgpu::BufferUsages::empty();
        let light_buf = gpu.storage_buffer("solari_lights/lights", &light_bytes, empty)?;
        let tri_buf = gpu.storage_buffer("solari_lights/triangles", &tri_bytes, empty)?;
        // Instance → light, for MIS when a BRDF sample hits an emitter.
        let mut instance_lights = vec![u32::MAX];
        for (i, l) in list.lights.iter().enumerate() {
            if let Light::Emissive { instance, .. } = *l {
                let at = instance as usize;
                if instance_lights.len() <= at {
                    instance_lights.resize(at + 1, u32::MAX);
                }
                instance_lights[at] = i as u32;
            }
        }
        let map_buf = gpu.storage_buffer(
            "solari_lights/instance_lights",
            bytemuck::cast_slice(&instance_lights),
            empty,
        )?;
        let env = list.environment.as_ref();
        let cells: Vec<GpuEnvironmentCell> = match env {
            Some(e) => e
                .distribution
                .table
                .pmf
                .iter()
                .zip(&e.distribution.table.entries)
                .map(|(&pmf, a)| GpuEnvironmentCell {
                    pmf,
                    threshold: a.threshold,
                    alias_index: a.alias,
                })
                .collect(),
            None => vec![GpuEnvironmentCell::zeroed()],
        };
        let cell_buf = gpu.storage_buffer(
            "solari_lights/environment_cells",
            bytemuck::cast_slice(&cells),
            empty,
        )?;
        let info = GpuLightInfo {
            light_count: lights.len() as u32,
            selection: match selection {
                Selection::Uniform => 0,
                Selection::Power => 1,
            },
            first_punctual: list.first_punctual,
            sphere_count: list.lights[list.punctual_range()]
                .iter()
                .filter(|l| l.sphere().is_some())
                .count() as u32,
            environment_light: env.map_or(u32::MAX, |e| e.light),
            environment_cells_x: env.map_or(0, |e| e.distribution.cells_x),
            environment_cells_y: env.map_or(0, |e| e.distribution.cells_y),
            first_directional: list.first_directional(),
            grid_origin: grid.map_or([0.0; 3], |g| g.origin.into()),
            grid_cell_size: grid.map_or(1.0, |g| g.cell_size),
            grid_dims: grid.map_or([0; 3], |g| g.dims.into()),
            grid_share: grid.map_or(0.0, |g| g.grid_share),
        };
        let (grid_cells, grid_lights): (&[[u32; 2]], &[u32]) = match grid {
            Some(g) if !g.entries.is_empty() => (&g.cells, &g.entries),
            Some(g) => (&g.cells, &[0]),
            None => (&[[0, 0]], &[0]),
        };
        let grid_cell_buf = gpu.storage_buffer(
            "solari_lights/grid_cells",
            bytemuck::cast_slice(grid_cells),
            empty,
        )?;
        let grid_light_buf = gpu.storage_buffer(
            "solari_lights/grid_lights",
            bytemuck::cast_slice(grid_lights),
            empty,
        )?;
        let info_buf = gpu.uniform_buffer("solari_lights/info", &info);
        let layout = Self::layout(gpu);
        let buffers = [
            light_buf,
            tri_buf,
            info_buf,
            map_buf,
            cell_buf,
            grid_cell_buf,
            grid_light_buf,
        ];
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("solari_lights/lights"),
            layout: &layout,
            entries: &entries_of(&buffers),
        });
        Ok(Self {
            layout,
            bind_group,
            light_count: info.light_count,
            sampling_elements: list.sampling_elements(),
            has_grid: grid.is_some(),
            buffers,
        })
    }
}

fn entries_of(buffers: &[wgpu::Buffer; 7]) -> Vec<wgpu::BindGroupEntry<'_>> {
    let [
        lights,
        triangles,
        info,
        instances,
        cells,
        grid_cells,
        grid_lights,
    ] = buffers;
    let mut entries = LIGHT_BINDINGS.entries(&[
        ("lights", lights),
        ("emissive_triangles", triangles),
        ("light_info", info),
        ("instance_lights", instances),
    ]);
    entries.extend(ENVIRONMENT_BINDINGS.entries(&[("environment_cells", cells)]));
    entries.extend(GRID_BINDINGS.entries(&[
        ("light_grid_cells", grid_cells),
        ("light_grid_lights", grid_lights),
    ]));
    entries
}

/// The crate's WESL modules, registered as `package::<name>` when passed to
/// `solari_scene::shaders::compose` as `extra`.
pub const MODULES: &[(&str, &str)] = &[
    (
        "light_sampling",
        include_str!("../shaders/light_sampling.wesl"),
    ),
    (
        "light_packing",
        include_str!("../shaders/light_packing.wesl"),
    ),
    ("light_tiles", include_str!("../shaders/light_tiles.wesl")),
    ("light_grid", include_str!("../shaders/light_grid.wesl")),
    (
        "light_emission",
        include_str!("../shaders/light_emission.wesl"),
    ),
];
