//! glTF 2.0 import into the [`Scene`] model.
//!
//! The file is treated as untrusted. Buffers, accessors and images are checked before they
//! are read, URIs resolve only inside the asset's folder, and every read and decoded image
//! has a size limit ([`ImportLimits`]), so a malformed or hostile file gives a [`SceneError`]
//! naming the file and element instead of a panic, a hang or exhausted memory.
//!
//! The `gltf` crate (1.4.1) panics on some malformed input. Every such site we know of is
//! checked before the crate is called (`gltf_check`); as a last resort the import runs under
//! `catch_unwind`, so a panic we do not know of yet becomes [`SceneError::ImporterPanic`]
//! (the fuzz harness counts those as findings).

use crate::asset_io::{AssetFolder, ImportLimits, read_file_limited};
use crate::error::SceneError;
use crate::geometry;
use crate::gltf_check::{
    Usage, check_attribute_indices, check_extent, check_image, check_layout,
    check_required_extensions,
};
use crate::model::*;
use crate::texture::{decode_image, texture_from_level0};
use crate::validate::clamp_radiance;
use glam::{Mat4, Vec2, Vec3, Vec4};
use gltf::mesh::Mode;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Options for [`load_gltf_with`] and [`import_slice`].
#[derive(Clone, Debug)]
pub struct ImportOptions {
    /// Angular diameter given to every directional light, in radians (default: the sun's 0.53°).
    pub sun_angular_diameter: f32,
    /// Radius in metres given to every point and spot light (default 0: delta lights, as
    /// glTF defines them; a radius gives soft shadows).
    pub point_light_radius: f32,
    /// Read `render_setup.json` beside the file (camera and environment for assets without
    /// them). Default true.
    pub read_render_setup: bool,
    /// Size limits on files read and images decoded.
    pub limits: ImportLimits,
    /// The folder that the file's URIs may reach (default: the file's own folder). Widen it
    /// for asset packs whose models share a texture folder beside them (`../textures/`).
    pub asset_root: Option<PathBuf>,
}

impl Default for ImportOptions {
    fn default() -> Self {
        Self {
            sun_angular_diameter: SUN_ANGULAR_DIAMETER,
            point_light_radius: 0.0,
            read_render_setup: true,
            limits: ImportLimits::default(),
            asset_root: None,
        }
    }
}

/// Loads a `.gltf` or `.glb` file with default options.
pub fn load_gltf(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
    load_gltf_with(path, &ImportOptions::default())
}

/// Loads a `.gltf` or `.glb` file.
pub fn load_gltf_with(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<Scene, SceneError> {
    let path = path.as_ref();
    let bytes = read_file_limited(path, options.limits.max_file_bytes).map_err(|reason| {
        SceneError::Unreadable {
            file: path.into(),
            reason,
        }
    })?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut scene = import_slice(&bytes, &base, path, options)?;
    if options.read_render_setup {
        let side = base.join("render_setup.json");
        if side.exists() {
            crate::render_setup::apply(&side, &mut scene)?;
        }
    }
    Ok(scene)
}

/// Imports glTF or GLB from memory. `base` resolves relative URIs (which may not leave
/// `options.asset_root`, by default `base` itself); `file` names the source in errors.
pub fn import_slice(
    bytes: &[u8],
    base: &Path,
    file: &Path,
    options: &ImportOptions,
) -> Result<Scene, SceneError> {
    let guarded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        import_unguarded(bytes, base, file, options)
    }));
    match guarded {
        Ok(result) => result,
        Err(payload) => {
            let message = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(SceneError::ImporterPanic {
                file: file.into(),
                message,
            })
        }
    }
}

fn import_unguarded(
    bytes: &[u8],
    base: &Path,
    file: &Path,
    options: &ImportOptions,
) -> Result<Scene, SceneError> {
    let file = file.to_path_buf();
    let gltf_err = |source| SceneError::Gltf {
        file: file.clone(),
        source,
    };
    let raw = gltf::Gltf::from_slice_without_validation(bytes).map_err(gltf_err)?;
    check_required_extensions(raw.document.as_json()).map_err(|reason| {
        SceneError::Unsupported {
            file: file.clone(),
            reason,
        }
    })?;
    check_attribute_indices(raw.document.as_json()).map_err(|(mesh, primitive, reason)| {
        SceneError::BadPrimitive {
            file: file.clone(),
            mesh,
            primitive,
            reason,
        }
    })?;
    let blob = raw.blob;
    let document = gltf::Document::from_json(raw.document.into_json()).map_err(gltf_err)?;
    let folder = AssetFolder {
        base: base.to_path_buf(),
        root: options
            .asset_root
            .clone()
            .unwrap_or_else(|| base.to_path_buf()),
        max_file_bytes: options.limits.max_file_bytes,
    };
    let buffers = load_buffers(&document, blob, &folder, &file)?;
    let mut importer = Importer {
        file,
        folder,
        buffers,
        scene: Scene::default(),
        mesh_cache: HashMap::new(),
        material_cache: HashMap::new(),
        image_cache: HashMap::new(),
        texture_cache: HashMap::new(),
        image_bytes: 0,
        images_json: document.as_json().images.clone(),
        options: options.clone(),
    };
    importer.import(&document)?;
    importer
        .scene
        .validate()
        .map_err(|reason| SceneError::Invalid {
            file: importer.file.clone(),
            reason,
        })?;
    Ok(importer.scene)
}

fn load_buffers(
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
    folder: &AssetFolder,
    file: &Path,
) -> Result<Vec<Vec<u8>>, SceneError> {
    let mut out = Vec::new();
    for buffer in document.buffers() {
        let index = buffer.index();
        let missing = |reason: String| SceneError::MissingBuffer {
            file: file.into(),
            index,
            reason,
        };
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                missing("no GLB binary chunk (or a second buffer claims it)".into())
            })?,
            gltf::buffer::Source::Uri(uri) => folder.read_uri(uri).map_err(missing)?,
        };
        if data.len() < buffer.length() {
            return Err(SceneError::TruncatedBuffer {
                file: file.into(),
                index,
                declared: buffer.length(),
                actual: data.len(),
            });
        }
        out.push(data);
    }
    Ok(out)
}

struct Importer {
    file: PathBuf,
    folder: AssetFolder,
    buffers: Vec<Vec<u8>>,
    scene: Scene,
    /// (gltf mesh, primitive) → our mesh index (None when the primitive was skipped).
    mesh_cache: HashMap<(usize, usize), Option<u32>>,
    /// gltf material index (None = default material) → our material index.
    material_cache: HashMap<Option<usize>, u32>,
    /// glTF image index → decoded level 0, so an image used by several textures is decoded
    /// once.
    image_cache: HashMap<usize, Arc<MipLevel>>,
    /// (glTF image index, colour space, repeat) → our texture index.
    texture_cache: HashMap<(usize, ColorSpace, bool), u32>,
    /// Decoded level-0 bytes so far, against `limits.max_total_image_bytes`.
    image_bytes: u64,
    /// The images' JSON, checked before the `gltf` crate's `Image::source` unwraps it.
    images_json: Vec<gltf::json::Image>,
    options: ImportOptions,
}

/// Guards against node graphs deeper than any real file (and against cycles).
const MAX_NODE_DEPTH: usize = 256;

impl Importer {
    fn import(&mut self, doc: &gltf::Document) -> Result<(), SceneError> {
        let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
            Some(s) => s.nodes().collect(),
            None => return Err(self.empty("the file has no scene")),
        };
        let mut visited = vec![false; doc.nodes().len()];
        for node in roots {
            self.visit(&node, Mat4::IDENTITY, 0, &mut visited)?;
        }
        if self.scene.instances.is_empty() {
            return Err(self.empty("no node places a mesh with at least one valid triangle"));
        }
        let w = &mut self.scene.warnings;
        w.ignored_light_ranges = self
            .scene
            .punctual_lights
            .iter()
            .filter(|l| l.range.is_some())
            .count();
        w.non_opaque_materials = self
            .scene
            .materials
            .iter()
            .filter(|m| m.alpha_mode != AlphaMode::Opaque)
            .count();
        Ok(())
    }

    fn empty(&self, reason: &str) -> SceneError {
        SceneError::EmptyScene {
            file: self.file.clone(),
            reason: reason.into(),
        }
    }

    fn visit(
        &mut self,
        node: &gltf::Node,
        parent: Mat4,
        depth: usize,
        visited: &mut [bool],
    ) -> Result<(), SceneError> {
        let file = self.file.clone();
        let index = node.index();
        let bad = move |reason: String| SceneError::BadNode {
            file: file.clone(),
            node: index,
            reason,
        };
        if depth > MAX_NODE_DEPTH || visited[node.index()] {
            return Err(bad(
                "the node graph has a cycle or a node with two parents".into()
            ));
        }
        visited[node.index()] = true;
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        if !local.is_finite() {
            return Err(bad("transform is not finite".into()));
        }
        let world = parent * local;
        let name = node
            .name()
            .map(str::to_string)
            .unwrap_or_else(|| format!("node{}", node.index()));

        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                let Some(mesh_index) = self.mesh(&mesh, &prim)? else {
                    continue;
                };
                let material = self.material(prim.material())?;
                self.scene.instances.push(Instance {
                    name: name.clone(),
                    mesh: mesh_index,
                    material,
                    transform: world,
                });
            }
        }
        if let Some(cam) = node.camera() {
            if let gltf::camera::Projection::Perspective(p) = cam.projection() {
                let camera = Camera {
                    name: cam
                        .name()
                        .or(node.name())
                        .map(str::to_string)
                        .unwrap_or_else(|| format!("camera{}", cam.index())),
                    transform: rigid(world),
                    yfov: p.yfov(),
                    aspect: p.aspect_ratio(),
                    znear: p.znear(),
                };
                camera.validate().map_err(&bad)?;
                self.scene.cameras.push(camera);
            } else {
                self.scene
                    .warnings
                    .notes
                    .push(format!("orthographic camera on node {name} ignored"));
            }
        }
        if let Some(light) = node.light() {
            self.light(&light, world, &name).map_err(&bad)?;
        }
        for child in node.children() {
            self.visit(&child, world, depth + 1, visited)?;
        }
        Ok(())
    }

    fn light(
        &mut self,
        light: &gltf::khr_lights_punctual::Light,
        world: Mat4,
        node_name: &str,
    ) -> Result<(), String> {
        use gltf::khr_lights_punctual::Kind;
        let mut color = Vec3::from(light.color()) * light.intensity();
        let name = light.name().unwrap_or(node_name).to_string();
        let forward = (-world.z_axis.truncate())
            .try_normalize()
            .unwrap_or(Vec3::NEG_Z);
        if !(color.is_finite() && color.min_element() >= 0.0) {
            return Err(format!(
                "light {name}: colour × intensity {color} must be finite and non-negative"
            ));
        }
        if clamp_radiance(&mut color) {
            self.scene.warnings.notes.push(format!(
                "light {name}: intensity clamped to {:e} per channel",
                crate::validate::MAX_RADIANCE
            ));
        }
        match light.kind() {
            Kind::Directional => self.scene.directional_lights.push(DirectionalLight {
                name,
                direction: forward,
                irradiance: color,
                angular_diameter: self.options.sun_angular_diameter,
            }),
            kind => self.scene.punctual_lights.push(PunctualLight {
                name,
                kind: match kind {
                    Kind::Spot {
                        inner_cone_angle,
                        outer_cone_angle,
                    } => PunctualKind::Spot {
                        inner: inner_cone_angle,
                        outer: outer_cone_angle,
                    },
                    _ => PunctualKind::Point,
                },
                position: world.w_axis.truncate(),
                direction: forward,
                intensity: color,
                range: light.range(),
                radius: self.options.point_light_radius,
            }),
        }
        Ok(())
    }

    fn check_accessor(&self, acc: &gltf::Accessor, usage: Usage) -> Result<(), SceneError> {
        let buffer_len = acc
            .view()
            .map_or(0, |v| self.buffers[v.buffer().index()].len());
        check_extent(acc, buffer_len)
            .and_then(|()| check_layout(acc, usage))
            .map_err(|reason| SceneError::BadAccessor {
                file: self.file.clone(),
                accessor: acc.index(),
                reason,
            })
    }

    fn mesh(
        &mut self,
        mesh: &gltf::Mesh,
        prim: &gltf::Primitive,
    ) -> Result<Option<u32>, SceneError> {
        let key = (mesh.index(), prim.index());
        if let Some(&cached) = self.mesh_cache.get(&key) {
            return Ok(cached);
        }
        let result = self.build_mesh(mesh, prim)?;
        let index = result.map(|m| {
            self.scene.meshes.push(m);
            (self.scene.meshes.len() - 1) as u32
        });
        self.mesh_cache.insert(key, index);
        Ok(index)
    }

    fn build_mesh(
        &mut self,
        mesh: &gltf::Mesh,
        prim: &gltf::Primitive,
    ) -> Result<Option<Mesh>, SceneError> {
        let bad = |reason: String| SceneError::BadPrimitive {
            file: self.file.clone(),
            mesh: mesh.index(),
            primitive: prim.index(),
            reason,
        };
        match prim.mode() {
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan => {}
            _ => {
                self.scene.warnings.skipped_primitives += 1;
                return Ok(None);
            }
        }
        use gltf::Semantic;
        // Only the attributes read below are checked: others (colours, skins) are ignored.
        for (semantic, acc) in prim.attributes() {
            let usage = match semantic {
                Semantic::Positions => Usage::Position,
                Semantic::Normals => Usage::Normal,
                Semantic::Tangents => Usage::Tangent,
                Semantic::TexCoords(0) => Usage::TexCoord,
                _ => continue,
            };
            self.check_accessor(&acc, usage)?;
        }
        if let Some(acc) = prim.indices() {
            self.check_accessor(&acc, Usage::Indices)?;
        }
        let Some(position_accessor) = prim.get(&Semantic::Positions) else {
            return Err(bad("has no POSITION attribute".into()));
        };
        // An empty accessor gives the readers an underflow (count - 1); it holds no triangle.
        let empty = |s: &Semantic| prim.get(s).is_some_and(|a| a.count() == 0);
        if position_accessor.count() == 0 || prim.indices().is_some_and(|a| a.count() == 0) {
            self.scene.warnings.skipped_primitives += 1;
            return Ok(None);
        }
        for s in [
            Semantic::Normals,
            Semantic::Tangents,
            Semantic::TexCoords(0),
        ] {
            if empty(&s) {
                return Err(bad(format!("{s:?} is empty but POSITION is not")));
            }
        }
        let buffers = &self.buffers;
        let reader = prim.reader(|b| Some(&buffers[b.index()]));
        let positions: Vec<Vec3> = reader
            .read_positions()
            .ok_or_else(|| bad("POSITION cannot be read".into()))?
            .map(Vec3::from)
            .collect();
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(bad(format!(
                "vertex {i} has a non-finite position {:?}",
                positions[i]
            )));
        }
        let limit = crate::validate::MAX_COORDINATE;
        if let Some(i) = positions.iter().position(|p| p.abs().max_element() > limit) {
            return Err(bad(format!(
                "vertex {i} at {} is beyond ±{limit:e}, where f32 cannot resolve geometry",
                positions[i]
            )));
        }
        let n = positions.len();
        let count_check = |what: &str, len: usize| {
            if len == n {
                Ok(())
            } else {
                Err(bad(format!(
                    "{what} has {len} entries but POSITION has {n}"
                )))
            }
        };
        let raw_indices: Vec<u32> = match reader.read_indices() {
            Some(it) => it.into_u32().collect(),
            None => (0..n as u32).collect(),
        };
        if let Some(i) = raw_indices.iter().position(|&v| v as usize >= n) {
            return Err(bad(format!(
                "index {} at position {i} is out of range ({n} vertices)",
                raw_indices[i]
            )));
        }
        let indices = match prim.mode() {
            Mode::TriangleStrip => {
                self.scene.warnings.converted_topologies += 1;
                strip_to_list(&raw_indices)
            }
            Mode::TriangleFan => {
                self.scene.warnings.converted_topologies += 1;
                fan_to_list(&raw_indices)
            }
            _ => {
                if !raw_indices.len().is_multiple_of(3) {
                    return Err(bad(format!(
                        "{} indices is not a multiple of 3",
                        raw_indices.len()
                    )));
                }
                raw_indices
            }
        };
        let uvs: Vec<Vec2> = match reader.read_tex_coords(0) {
            Some(it) => it.into_f32().map(Vec2::from).collect(),
            None => geometry::default_uvs(n),
        };
        count_check("TEXCOORD_0", uvs.len())?;
        let uvs = uvs
            .into_iter()
            .map(|v| if v.is_finite() { v } else { Vec2::ZERO })
            .collect();
        let mut out = Mesh {
            name: format!("{}/{}", mesh.name().unwrap_or("mesh"), prim.index()),
            positions,
            uvs,
            indices,
            ..Default::default()
        };
        self.scene.warnings.degenerate_triangles += geometry::drop_degenerate_triangles(&mut out);
        if out.indices.is_empty() {
            self.scene
                .warnings
                .notes
                .push(format!("mesh {} has no valid triangle: skipped", out.name));
            return Ok(None);
        }
        out.normals = match reader.read_normals() {
            Some(it) => {
                let mut normals: Vec<Vec3> = it.map(Vec3::from).collect();
                count_check("NORMAL", normals.len())?;
                let fixed = geometry::sanitize_normals(&mut normals);
                if fixed > 0 {
                    self.scene.warnings.notes.push(format!(
                        "mesh {}: {fixed} zero or non-finite normal(s) replaced",
                        out.name
                    ));
                }
                normals
            }
            None => {
                self.scene.warnings.generated_normals += 1;
                geometry::generate_normals(&out.positions, &out.indices)
            }
        };
        let has_normal_map = prim.material().normal_texture().is_some();
        out.tangents = match reader.read_tangents() {
            Some(it) => {
                let t: Vec<Vec4> = it.map(Vec4::from).collect();
                count_check("TANGENT", t.len())?;
                t.into_iter()
                    .zip(&out.normals)
                    .map(|(t, n)| geometry::sanitize_tangent(t, *n))
                    .collect()
            }
            None if has_normal_map => {
                self.scene.warnings.generated_tangents += 1;
                geometry::generate_tangents(&out)
            }
            // No normal map reads them: any frame around the normal will do.
            None => out
                .normals
                .iter()
                .map(|n| n.any_orthonormal_vector().extend(1.0))
                .collect(),
        };
        Ok(Some(out))
    }

    fn material(&mut self, m: gltf::Material) -> Result<u32, SceneError> {
        if let Some(&i) = self.material_cache.get(&m.index()) {
            return Ok(i);
        }
        let pbr = m.pbr_metallic_roughness();
        let strength = m.emissive_strength().unwrap_or(1.0);
        let mut emissive = Vec3::from(m.emissive_factor()) * strength;
        if !(emissive.is_finite() && emissive.min_element() >= 0.0) {
            return Err(SceneError::BadMaterial {
                file: self.file.clone(),
                material: m.index().unwrap_or(usize::MAX),
                reason: format!(
                    "emission (emissiveFactor × emissiveStrength) {emissive} must be finite and non-negative"
                ),
            });
        }
        if clamp_radiance(&mut emissive) {
            self.scene.warnings.notes.push(format!(
                "material {}: emission clamped to {:e} per channel",
                m.name().unwrap_or("?"),
                crate::validate::MAX_RADIANCE
            ));
        }
        let ior = m
            .ior()
            .filter(|x| x.is_finite() && *x >= 1.0)
            .unwrap_or(1.5);
        let f0_ior = ((ior - 1.0) / (ior + 1.0)).powi(2);
        let (spec_factor, spec_color) = match m.specular() {
            Some(s) => (s.specular_factor(), Vec3::from(s.specular_color_factor())),
            None => (1.0, Vec3::ONE),
        };
        let dielectric_f0 = (spec_color * f0_ior).min(Vec3::ONE) * spec_factor.clamp(0.0, 1.0);
        let tex = |this: &mut Self,
                   info: Option<gltf::texture::Texture>,
                   cs|
         -> Result<Option<u32>, SceneError> {
            info.map(|t| this.texture(&t, cs)).transpose()
        };
        let base_color_texture = tex(
            self,
            pbr.base_color_texture().map(|i| i.texture()),
            ColorSpace::Srgb,
        )?;
        let metallic_roughness_texture = tex(
            self,
            pbr.metallic_roughness_texture().map(|i| i.texture()),
            ColorSpace::Linear,
        )?;
        let normal = m.normal_texture();
        let normal_scale = normal.as_ref().map(|n| n.scale()).unwrap_or(1.0);
        let normal_texture = tex(self, normal.map(|n| n.texture()), ColorSpace::Linear)?;
        let emissive_texture = tex(
            self,
            m.emissive_texture().map(|i| i.texture()),
            ColorSpace::Srgb,
        )?;
        let clamp01 = |x: f32| {
            if x.is_finite() {
                x.clamp(0.0, 1.0)
            } else {
                0.0
            }
        };
        let base = Vec4::from(pbr.base_color_factor());
        let material = Material {
            name: m.name().unwrap_or("").to_string(),
            base_color: Vec4::new(
                clamp01(base.x),
                clamp01(base.y),
                clamp01(base.z),
                clamp01(base.w),
            ),
            base_color_texture,
            metallic: clamp01(pbr.metallic_factor()),
            roughness: clamp01(pbr.roughness_factor()),
            metallic_roughness_texture,
            normal_texture,
            normal_scale: if normal_scale.is_finite() {
                normal_scale
            } else {
                1.0
            },
            emissive,
            emissive_texture,
            dielectric_f0,
            dielectric_f90: spec_factor.clamp(0.0, 1.0),
            alpha_mode: match m.alpha_mode() {
                gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
                gltf::material::AlphaMode::Mask => AlphaMode::Mask,
                gltf::material::AlphaMode::Blend => AlphaMode::Blend,
            },
            alpha_cutoff: m.alpha_cutoff().unwrap_or(0.5),
            double_sided: m.double_sided(),
        };
        self.scene.materials.push(material);
        let index = (self.scene.materials.len() - 1) as u32;
        self.material_cache.insert(m.index(), index);
        Ok(index)
    }

    fn texture(&mut self, t: &gltf::texture::Texture, cs: ColorSpace) -> Result<u32, SceneError> {
        use gltf::texture::WrappingMode;
        let image = t.source();
        let sampler = t.sampler();
        let repeat = sampler.wrap_s() != WrappingMode::ClampToEdge
            || sampler.wrap_t() != WrappingMode::ClampToEdge;
        let key = (image.index(), cs, repeat);
        if let Some(&i) = self.texture_cache.get(&key) {
            return Ok(i);
        }
        let (level0, name) = self.decoded_image(&image)?;
        let texture = texture_from_level0((*level0).clone(), &name, cs, repeat);
        self.scene.textures.push(texture);
        let index = (self.scene.textures.len() - 1) as u32;
        self.texture_cache.insert(key, index);
        Ok(index)
    }

    /// Level 0 of `image`, decoded on first use.
    fn decoded_image(
        &mut self,
        image: &gltf::Image,
    ) -> Result<(Arc<MipLevel>, String), SceneError> {
        let bad = |reason: String| SceneError::BadImage {
            file: self.file.clone(),
            image: image.index(),
            reason,
        };
        let json = &self.images_json[image.index()];
        check_image(json).map_err(&bad)?;
        let name = image
            .name()
            .map(str::to_string)
            .or_else(|| json.uri.clone())
            .unwrap_or_else(|| format!("image {}", image.index()));
        if let Some(level0) = self.image_cache.get(&image.index()) {
            return Ok((level0.clone(), name));
        }
        let bytes = match image.source() {
            gltf::image::Source::View { view, .. } => {
                let data = &self.buffers[view.buffer().index()];
                let range = view.offset()..view.offset().saturating_add(view.length());
                data.get(range)
                    .ok_or_else(|| bad("buffer view reaches past its buffer".into()))?
                    .to_vec()
            }
            gltf::image::Source::Uri { uri, .. } => self.folder.read_uri(uri).map_err(&bad)?,
        };
        let limits = &self.options.limits;
        let level0 = decode_image(&bytes, &name, limits).map_err(&bad)?;
        self.image_bytes += level0.rgba8.len() as u64;
        if self.image_bytes > limits.max_total_image_bytes {
            return Err(bad(format!(
                "decoded images reach {} bytes, over the limit of {} for one scene",
                self.image_bytes, limits.max_total_image_bytes
            )));
        }
        let level0 = Arc::new(level0);
        self.image_cache.insert(image.index(), level0.clone());
        Ok((level0, name))
    }
}

/// Keeps rotation and translation, drops scale and shear (cameras must stay rigid).
fn rigid(m: Mat4) -> Mat4 {
    let (_, rot, trans) = m.to_scale_rotation_translation();
    Mat4::from_rotation_translation(rot.normalize(), trans)
}

fn strip_to_list(idx: &[u32]) -> Vec<u32> {
    let mut out = Vec::new();
    for i in 2..idx.len() {
        // Alternate winding so every triangle keeps the strip's orientation.
        if i % 2 == 0 {
            out.extend([idx[i - 2], idx[i - 1], idx[i]]);
        } else {
            out.extend([idx[i - 1], idx[i - 2], idx[i]]);
        }
    }
    out
}

fn fan_to_list(idx: &[u32]) -> Vec<u32> {
    let mut out = Vec::new();
    for i in 2..idx.len() {
        out.extend([idx[0], idx[i - 1], idx[i]]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_become_lists() {
        assert_eq!(strip_to_list(&[0, 1, 2, 3]), vec![0, 1, 2, 2, 1, 3]);
        assert_eq!(fan_to_list(&[0, 1, 2, 3]), vec![0, 1, 2, 0, 2, 3]);
        assert!(strip_to_list(&[0, 1]).is_empty());
    }
}
