//! glTF 2.0 import into the [`Scene`] model.
//!
//! Buffers, accessors and images are checked before they are read, so a malformed file gives a
//! [`SceneError`] naming the file and element instead of a panic deep inside a reader.

use crate::error::SceneError;
use crate::geometry;
use crate::model::*;
use crate::texture::decode_texture;
use base64::Engine as _;
use glam::{Mat4, Vec2, Vec3, Vec4};
use gltf::mesh::Mode;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Options for [`load_gltf`].
#[derive(Clone, Debug)]
pub struct ImportOptions {
    /// Angular diameter given to every directional light, in radians (default: the sun's 0.53°).
    pub sun_angular_diameter: f32,
    /// Read `render_setup.json` beside the file (camera and environment for assets without
    /// them). Default true.
    pub read_render_setup: bool,
}

impl Default for ImportOptions {
    fn default() -> Self {
        Self {
            sun_angular_diameter: SUN_ANGULAR_DIAMETER,
            read_render_setup: true,
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
    let bytes = std::fs::read(path).map_err(|source| SceneError::Io {
        file: path.into(),
        source,
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

/// Imports glTF from memory. `base` resolves relative URIs; `file` names the source in errors.
pub fn import_slice(
    bytes: &[u8],
    base: &Path,
    file: &Path,
    options: &ImportOptions,
) -> Result<Scene, SceneError> {
    let file = file.to_path_buf();
    let gltf = gltf::Gltf::from_slice(bytes).map_err(|source| SceneError::Gltf {
        file: file.clone(),
        source,
    })?;
    let buffers = load_buffers(&gltf, base, &file)?;
    let mut importer = Importer {
        file,
        base: base.to_path_buf(),
        buffers,
        scene: Scene::default(),
        mesh_cache: HashMap::new(),
        material_cache: HashMap::new(),
        texture_cache: HashMap::new(),
        options: options.clone(),
    };
    importer.import(&gltf.document)?;
    Ok(importer.scene)
}

fn load_buffers(gltf: &gltf::Gltf, base: &Path, file: &Path) -> Result<Vec<Vec<u8>>, SceneError> {
    let mut out = Vec::new();
    for buffer in gltf.document.buffers() {
        let index = buffer.index();
        let missing = |reason: String| SceneError::MissingBuffer {
            file: file.into(),
            index,
            reason,
        };
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => gltf
                .blob
                .clone()
                .ok_or_else(|| missing("no GLB binary chunk".into()))?,
            gltf::buffer::Source::Uri(uri) => read_uri(uri, base).map_err(missing)?,
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

/// Reads a `data:` URI or a file relative to `base`.
fn read_uri(uri: &str, base: &Path) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, payload) = rest
            .split_once(";base64,")
            .ok_or("data URI is not base64")?;
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|e| format!("bad base64 in data URI: {e}"));
    }
    let path = base.join(percent_decode(uri));
    std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))
}

fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%'
            && i + 2 < bytes.len()
            && let Ok(v) = u8::from_str_radix(&s[i + 1..i + 3], 16)
        {
            out.push(v);
            i += 3;
            continue;
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

struct Importer {
    file: PathBuf,
    base: PathBuf,
    buffers: Vec<Vec<u8>>,
    scene: Scene,
    /// (gltf mesh, primitive) → our mesh index (None when the primitive was skipped).
    mesh_cache: HashMap<(usize, usize), Option<u32>>,
    /// gltf material index (None = default material) → our material index.
    material_cache: HashMap<Option<usize>, u32>,
    /// (gltf texture index, colour space) → our texture index.
    texture_cache: HashMap<(usize, ColorSpace), u32>,
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
        w.unrendered_lights = self.scene.punctual_lights.len();
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
        let bad = |reason: String| SceneError::BadNode {
            file: self.file.clone(),
            node: node.index(),
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
                self.scene.cameras.push(Camera {
                    name: cam
                        .name()
                        .or(node.name())
                        .map(str::to_string)
                        .unwrap_or_else(|| format!("camera{}", cam.index())),
                    transform: rigid(world),
                    yfov: p.yfov(),
                    aspect: p.aspect_ratio(),
                    znear: p.znear(),
                });
            } else {
                self.scene
                    .warnings
                    .notes
                    .push(format!("orthographic camera on node {name} ignored"));
            }
        }
        if let Some(light) = node.light() {
            self.light(&light, world, &name);
        }
        for child in node.children() {
            self.visit(&child, world, depth + 1, visited)?;
        }
        Ok(())
    }

    fn light(&mut self, light: &gltf::khr_lights_punctual::Light, world: Mat4, node_name: &str) {
        use gltf::khr_lights_punctual::Kind;
        let color = Vec3::from(light.color()) * light.intensity();
        let name = light.name().unwrap_or(node_name).to_string();
        let forward = (-world.z_axis.truncate())
            .try_normalize()
            .unwrap_or(Vec3::NEG_Z);
        let color = if color.is_finite() && color.min_element() >= 0.0 {
            color
        } else {
            self.scene.warnings.notes.push(format!(
                "light {name}: non-finite or negative intensity, set to zero"
            ));
            Vec3::ZERO
        };
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
            }),
        }
    }

    fn check_accessor(&self, acc: &gltf::Accessor) -> Result<(), SceneError> {
        let bad = |reason: String| SceneError::BadAccessor {
            file: self.file.clone(),
            accessor: acc.index(),
            reason,
        };
        if acc.sparse().is_some() {
            return Err(bad("sparse accessors are not supported".into()));
        }
        let Some(view) = acc.view() else {
            return Err(bad("has no buffer view".into()));
        };
        let data_len = self.buffers[view.buffer().index()].len();
        let view_end = view.offset().checked_add(view.length());
        if view_end.is_none_or(|e| e > data_len) {
            return Err(bad(format!(
                "buffer view {} (offset {}, length {}) reaches past its buffer of {} bytes",
                view.index(),
                view.offset(),
                view.length(),
                data_len
            )));
        }
        if acc.count() == 0 {
            return Ok(());
        }
        let elem = acc.size();
        let stride = view.stride().unwrap_or(elem);
        let end = (acc.count() - 1)
            .checked_mul(stride)
            .and_then(|x| x.checked_add(acc.offset()))
            .and_then(|x| x.checked_add(elem));
        if end.is_none_or(|e| e > view.length()) {
            return Err(bad(format!(
                "{} elements of {} bytes (stride {stride}) at offset {} do not fit buffer view {} of {} bytes",
                acc.count(),
                elem,
                acc.offset(),
                view.index(),
                view.length()
            )));
        }
        Ok(())
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
        for (_, acc) in prim.attributes() {
            self.check_accessor(&acc)?;
        }
        if let Some(acc) = prim.indices() {
            self.check_accessor(&acc)?;
        }
        let buffers = &self.buffers;
        let reader = prim.reader(|b| Some(&buffers[b.index()]));
        let positions: Vec<Vec3> = reader
            .read_positions()
            .ok_or_else(|| bad("has no POSITION attribute".into()))?
            .map(Vec3::from)
            .collect();
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(bad(format!(
                "vertex {i} has a non-finite position {:?}",
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
        if !emissive.is_finite() || emissive.min_element() < 0.0 {
            self.scene.warnings.notes.push(format!(
                "material {}: non-finite or negative emission {emissive:?} set to zero",
                m.name().unwrap_or("?")
            ));
            emissive = Vec3::ZERO;
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
        if let Some(&i) = self.texture_cache.get(&(t.index(), cs)) {
            return Ok(i);
        }
        let image = t.source();
        let bad = |reason: String| SceneError::BadImage {
            file: self.file.clone(),
            image: image.index(),
            reason,
        };
        let (bytes, name) = match image.source() {
            gltf::image::Source::View { view, .. } => {
                let data = &self.buffers[view.buffer().index()];
                let range = view.offset()..view.offset().saturating_add(view.length());
                let slice = data
                    .get(range)
                    .ok_or_else(|| bad("buffer view reaches past its buffer".into()))?;
                (
                    slice.to_vec(),
                    image.name().unwrap_or("embedded").to_string(),
                )
            }
            gltf::image::Source::Uri { uri, .. } => {
                (read_uri(uri, &self.base).map_err(&bad)?, uri.to_string())
            }
        };
        use gltf::texture::WrappingMode;
        let sampler = t.sampler();
        let repeat = sampler.wrap_s() != WrappingMode::ClampToEdge
            || sampler.wrap_t() != WrappingMode::ClampToEdge;
        let texture = decode_texture(&bytes, &name, cs, repeat).map_err(bad)?;
        self.scene.textures.push(texture);
        let index = (self.scene.textures.len() - 1) as u32;
        self.texture_cache.insert((t.index(), cs), index);
        Ok(index)
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

    #[test]
    fn percent_decoding() {
        assert_eq!(percent_decode("a%20b.png"), "a b.png");
        assert_eq!(percent_decode("100%"), "100%");
        assert_eq!(percent_decode("%zz"), "%zz");
    }
}
