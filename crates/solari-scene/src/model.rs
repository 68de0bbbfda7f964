//! The CPU scene model: what import produces and what the GPU upload consumes.

use glam::{Mat4, Vec2, Vec3, Vec4};

/// A scene ready for upload: unique meshes, the instances that place them, materials,
/// textures, lights and cameras.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Unique triangle meshes. A mesh used by several nodes is stored once.
    pub meshes: Vec<Mesh>,
    /// Placed copies of meshes, with world transforms (the node hierarchy flattened).
    pub instances: Vec<Instance>,
    /// Materials, indexed by [`Instance::material`].
    pub materials: Vec<Material>,
    /// Decoded textures, indexed by the `*_texture` fields of [`Material`].
    pub textures: Vec<Texture>,
    /// Directional lights (`KHR_lights_punctual` type `directional`).
    pub directional_lights: Vec<DirectionalLight>,
    /// Point and spot lights (`KHR_lights_punctual` types `point` and `spot`).
    pub punctual_lights: Vec<PunctualLight>,
    /// Cameras in document order.
    pub cameras: Vec<Camera>,
    /// The environment's radiance (black by default; set by `render_setup.json` or the
    /// application): uniform on its own, or the factor on [`Scene::environment_map`].
    pub environment_radiance: Vec3,
    /// An equirectangular environment map, if any: radiance from direction `d` is
    /// `environment_radiance * map.radiance(d)` ([`Scene::environment`]). Shared, since maps are
    /// large and scenes are cloned.
    pub environment_map: Option<std::sync::Arc<crate::environment::EnvironmentMap>>,
    /// Everything import dropped or does not render yet.
    pub warnings: ImportWarnings,
}

/// An indexed triangle mesh in object space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Name from the file (`mesh name/primitive index`), for messages.
    pub name: String,
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals (generated when the file has none).
    pub normals: Vec<Vec3>,
    /// First texture coordinate set (zero when the file has none).
    pub uvs: Vec<Vec2>,
    /// Tangents with handedness in `w` (generated with MikkTSpace when missing).
    pub tangents: Vec<Vec4>,
    /// Triangle list, three indices per triangle; degenerate triangles already removed.
    pub indices: Vec<u32>,
}

impl Mesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// The three object-space corners of triangle `t`.
    pub fn triangle(&self, t: usize) -> [Vec3; 3] {
        let i = &self.indices[t * 3..t * 3 + 3];
        [
            self.positions[i[0] as usize],
            self.positions[i[1] as usize],
            self.positions[i[2] as usize],
        ]
    }

    /// Object-space bounds `(min, max)`.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }
}

/// One placed mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// Node name, for messages.
    pub name: String,
    /// Index into [`Scene::meshes`].
    pub mesh: u32,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Object-to-world transform.
    pub transform: Mat4,
}

/// How a material's alpha is meant to be used. Only `Opaque` is rendered for now.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AlphaMode {
    /// Alpha ignored.
    #[default]
    Opaque,
    /// Alpha tested against a cutoff (imported; rendered as opaque for now).
    Mask,
    /// Alpha blended (imported; rendered as opaque for now).
    Blend,
}

/// A glTF metallic-roughness material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name from the file.
    pub name: String,
    /// Linear base colour factor (RGBA).
    pub base_color: Vec4,
    /// Texture index of the sRGB base colour texture.
    pub base_color_texture: Option<u32>,
    /// Metallic factor in \[0, 1\].
    pub metallic: f32,
    /// Perceptual roughness factor in \[0, 1\].
    pub roughness: f32,
    /// Texture index of the linear metallic (B) / roughness (G) texture.
    pub metallic_roughness_texture: Option<u32>,
    /// Texture index of the linear tangent-space normal map.
    pub normal_texture: Option<u32>,
    /// Scale of the normal map's XY.
    pub normal_scale: f32,
    /// Emitted radiance: `emissiveFactor × KHR_materials_emissive_strength`.
    pub emissive: Vec3,
    /// Texture index of the sRGB emissive texture (multiplies `emissive`).
    pub emissive_texture: Option<u32>,
    /// Specular reflectance at normal incidence of the dielectric layer, per channel.
    /// From `KHR_materials_ior` and `KHR_materials_specular`; 0.04 (IOR 1.5) by default.
    pub dielectric_f0: Vec3,
    /// Grazing-angle reflectance of the dielectric layer (`KHR_materials_specular`'s
    /// `specularFactor`; 1 by default). Zero together with a zero `dielectric_f0` makes the
    /// non-metal part an exact Lambertian (no specular lobe, no Fresnel weighting of diffuse).
    pub dielectric_f90: f32,
    /// Alpha mode (only opaque is rendered yet).
    pub alpha_mode: AlphaMode,
    /// Alpha cutoff for `AlphaMode::Mask`.
    pub alpha_cutoff: f32,
    /// Whether the glTF material is double sided.
    pub double_sided: bool,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: String::new(),
            base_color: Vec4::ONE,
            base_color_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            emissive: Vec3::ZERO,
            emissive_texture: None,
            dielectric_f0: Vec3::splat(DEFAULT_DIELECTRIC_F0),
            dielectric_f90: 1.0,
            alpha_mode: AlphaMode::Opaque,
            alpha_cutoff: 0.5,
            double_sided: false,
        }
    }
}

/// Reflectance at normal incidence of a dielectric with IOR 1.5, glTF's default.
pub const DEFAULT_DIELECTRIC_F0: f32 = 0.04;

impl Material {
    /// Whether the material emits light (before any texture).
    pub fn is_emissive(&self) -> bool {
        self.emissive.max_element() > 0.0
    }
}

/// Whether a texture stores colour (sRGB-encoded) or data (linear).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ColorSpace {
    /// sRGB-encoded colour: base colour and emissive textures.
    Srgb,
    /// Linear data: metallic-roughness and normal maps.
    Linear,
}

/// A decoded RGBA8 texture with its full mip chain.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Name (image name or URI), for messages.
    pub name: String,
    /// How the texels are encoded.
    pub color_space: ColorSpace,
    /// Mip levels, level 0 first; each is `(width, height, rgba8 texels)`.
    pub mips: Vec<MipLevel>,
    /// Whether the glTF sampler repeats (true) or clamps (false) in U and V.
    pub repeat: bool,
}

/// One level of a texture's mip chain.
#[derive(Clone, Debug, PartialEq)]
pub struct MipLevel {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// RGBA8 texels, row-major.
    pub rgba8: Vec<u8>,
}

/// A light infinitely far away, such as the sun.
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Name from the file.
    pub name: String,
    /// Unit direction the light travels in (world space).
    pub direction: Vec3,
    /// Irradiance on a surface facing the light, per channel (W/m², used 1:1 from glTF).
    pub irradiance: Vec3,
    /// Apparent angular diameter of the light's disk in radians, for soft shadows.
    pub angular_diameter: f32,
}

/// The sun's angular diameter (0.53°), the default for directional lights.
pub const SUN_ANGULAR_DIAMETER: f32 = 0.53 * std::f32::consts::PI / 180.0;

/// The kind of a [`PunctualLight`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PunctualKind {
    /// Omnidirectional point light.
    Point,
    /// Spot light with cone angles in radians.
    Spot {
        /// Inner cone angle.
        inner: f32,
        /// Outer cone angle.
        outer: f32,
    },
}

/// A point or spot light (glTF `KHR_lights_punctual`). With `radius` 0 it is a delta light
/// (hard shadows, as glTF defines it); with a radius it is a sphere of that radius whose
/// uniform radiance gives the same intensity from afar, for soft shadows. `solari_lights`
/// explains the model.
#[derive(Clone, Debug, PartialEq)]
pub struct PunctualLight {
    /// Name from the file.
    pub name: String,
    /// Point or spot.
    pub kind: PunctualKind,
    /// World position.
    pub position: Vec3,
    /// World direction (spot lights).
    pub direction: Vec3,
    /// Radiant intensity per channel (W/sr, used 1:1 from glTF).
    pub intensity: Vec3,
    /// Range, if the file gives one. Not used: light falls off with the inverse square of
    /// distance, as it does physically (import notes lights that set one).
    pub range: Option<f32>,
    /// Radius of the emitting sphere in metres; 0 for a delta light.
    pub radius: f32,
}

/// A perspective camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Name of the camera (or its node).
    pub name: String,
    /// Camera-to-world transform; the camera looks down its local -Z with +Y up.
    pub transform: Mat4,
    /// Vertical field of view in radians.
    pub yfov: f32,
    /// Aspect ratio from the file, if any (the render size decides otherwise).
    pub aspect: Option<f32>,
    /// Near plane distance.
    pub znear: f32,
}

impl Camera {
    /// Frame `frame` of the orbit path (`--camera-path orbit`): this camera swung ±20° about
    /// the vertical through the centre of `scene`'s bounds (the origin for unbounded scenes),
    /// one period every 240 frames: sideways motion, as when a player strafes, that never
    /// leaves a closed room like the Cornell box. Walks every vertex for the bounds: a frame
    /// loop computes [`Camera::orbit_pivot`] once and calls [`Camera::orbit_about`].
    pub fn orbit(&self, scene: &Scene, frame: u32) -> Camera {
        self.orbit_about(Self::orbit_pivot(scene), frame)
    }

    /// The point the orbit path swings about: the centre of `scene`'s bounds, or the origin
    /// for a scene with no finite bounds. Costs one pass over every vertex.
    pub fn orbit_pivot(scene: &Scene) -> Vec3 {
        let (lo, hi) = scene.bounds();
        if lo.is_finite() && hi.is_finite() {
            (lo + hi) * 0.5
        } else {
            Vec3::ZERO
        }
    }

    /// Frame `frame` of the orbit path about `pivot` (see [`Camera::orbit`]).
    pub fn orbit_about(&self, pivot: Vec3, frame: u32) -> Camera {
        let phase = frame as f32 / 240.0 * std::f32::consts::TAU;
        let angle = 20f32.to_radians() * phase.sin();
        let about = Mat4::from_translation(pivot)
            * Mat4::from_rotation_y(angle)
            * Mat4::from_translation(-pivot);
        let mut camera = self.clone();
        camera.transform = about * self.transform;
        camera
    }

    /// A camera at `eye` looking at `target`.
    pub fn look_at(name: &str, eye: Vec3, target: Vec3, up: Vec3, yfov: f32) -> Self {
        Self {
            name: name.to_string(),
            transform: camera_to_world(eye, target, up),
            yfov,
            aspect: None,
            znear: 0.01,
        }
    }

    /// World-space position.
    pub fn position(&self) -> Vec3 {
        self.transform.w_axis.truncate()
    }
}

/// Camera-to-world transform of a camera at `eye` looking at `target` (right-handed, -Z
/// forward). An `up` parallel to the view direction is replaced by any perpendicular vector.
pub fn camera_to_world(eye: Vec3, target: Vec3, up: Vec3) -> Mat4 {
    let forward = (target - eye).try_normalize().unwrap_or(Vec3::NEG_Z);
    let right = forward
        .cross(up)
        .try_normalize()
        .unwrap_or_else(|| forward.any_orthonormal_vector());
    let true_up = right.cross(forward);
    Mat4::from_cols(
        right.extend(0.0),
        true_up.extend(0.0),
        (-forward).extend(0.0),
        eye.extend(1.0),
    )
}

/// What import dropped, converted or does not render yet. Never silent: `solari info` prints it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImportWarnings {
    /// Triangles dropped because their area was zero (or their corners coincide).
    pub degenerate_triangles: usize,
    /// Materials whose alpha mode is not opaque (rendered as opaque for now).
    pub non_opaque_materials: usize,
    /// Point and spot lights whose `range` is ignored (light falls off physically instead).
    pub ignored_light_ranges: usize,
    /// Primitives converted from strips or fans to lists.
    pub converted_topologies: usize,
    /// Primitives skipped because they are points or lines.
    pub skipped_primitives: usize,
    /// Meshes that had no normals (generated).
    pub generated_normals: usize,
    /// Meshes that had a normal map but no tangents (generated).
    pub generated_tangents: usize,
    /// Free-form notes (one line each).
    pub notes: Vec<String>,
}

impl ImportWarnings {
    /// Human-readable warning lines; empty when import was clean.
    pub fn lines(&self) -> Vec<String> {
        let mut out = Vec::new();
        let mut push = |n: usize, what: &str| {
            if n > 0 {
                out.push(format!("{n} {what}"));
            }
        };
        push(self.degenerate_triangles, "zero-area triangle(s) dropped");
        push(
            self.non_opaque_materials,
            "material(s) with alpha mask/blend rendered as opaque",
        );
        push(
            self.ignored_light_ranges,
            "point/spot light range(s) ignored (inverse-square falloff)",
        );
        push(
            self.converted_topologies,
            "strip/fan primitive(s) converted to triangle lists",
        );
        push(self.skipped_primitives, "point/line primitive(s) skipped");
        push(
            self.generated_normals,
            "mesh(es) without normals: normals generated",
        );
        push(
            self.generated_tangents,
            "mesh(es) with a normal map but no tangents: tangents generated",
        );
        out.extend(self.notes.iter().cloned());
        out
    }
}

/// Counts that `solari info` prints.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SceneStats {
    /// Unique meshes.
    pub meshes: usize,
    /// Instances.
    pub instances: usize,
    /// Triangles over all instances.
    pub triangles: usize,
    /// Triangles stored once per unique mesh.
    pub unique_triangles: usize,
    /// Triangles of instances whose material emits.
    pub emissive_triangles: usize,
    /// Directional plus punctual lights.
    pub lights: usize,
    /// Textures.
    pub textures: usize,
}

impl Scene {
    /// Whether the environment is a light that the light list samples (with the map's
    /// importance, `solari_lights`): an environment map that is not black. A uniform
    /// environment is not: GI and the reference gather it where their rays escape. Passes
    /// that trace paths leave a sampled environment to next-event estimation (or weight it by
    /// MIS) where their rays escape (`GpuSceneInfo::environment_sampled`).
    pub fn environment_is_light(&self) -> bool {
        self.environment_map.is_some()
            && self.environment_radiance.max_element() > 0.0
            && self
                .environment_map
                .as_ref()
                .is_some_and(|m| m.max_component() > 0.0)
    }

    /// Radiance arriving from unit direction `d` when nothing is hit: the uniform
    /// environment, or the map times its factor.
    pub fn environment(&self, d: Vec3) -> Vec3 {
        match &self.environment_map {
            Some(map) => self.environment_radiance * map.radiance(d),
            None => self.environment_radiance,
        }
    }

    /// Counts of what the scene holds.
    pub fn stats(&self) -> SceneStats {
        let mut s = SceneStats {
            meshes: self.meshes.len(),
            instances: self.instances.len(),
            lights: self.directional_lights.len() + self.punctual_lights.len(),
            textures: self.textures.len(),
            unique_triangles: self.meshes.iter().map(Mesh::triangle_count).sum(),
            ..Default::default()
        };
        for inst in &self.instances {
            let n = self.meshes[inst.mesh as usize].triangle_count();
            s.triangles += n;
            if self.materials[inst.material as usize].is_emissive() {
                s.emissive_triangles += n;
            }
        }
        s
    }

    /// World-space bounds of all instances.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.instances
            .iter()
            .map(|i| crate::trace_cpu::instance_bounds(self, i))
            .fold(
                (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), (a, b)| (lo.min(a), hi.max(b)),
            )
    }

    /// A camera that frames the whole scene from the front (+Z), for files without one.
    pub fn framing_camera(&self) -> Camera {
        let (lo, hi) = self.bounds();
        let center = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-6);
        let yfov = 45f32.to_radians();
        let dist = radius / (yfov * 0.5).sin();
        let mut cam = Camera::look_at("auto", center + Vec3::Z * dist, center, Vec3::Y, yfov);
        cam.znear = (dist - radius).max(dist * 1e-4);
        cam
    }

    /// Picks a camera by name or index (`None`: the first, else one that frames the scene).
    pub fn camera(&self, wanted: Option<&str>) -> Option<Camera> {
        match wanted {
            None => Some(
                self.cameras
                    .first()
                    .cloned()
                    .unwrap_or_else(|| self.framing_camera()),
            ),
            Some(w) => {
                if let Some(c) = self.cameras.iter().find(|c| c.name == w) {
                    return Some(c.clone());
                }
                w.parse::<usize>()
                    .ok()
                    .and_then(|i| self.cameras.get(i).cloned())
            }
        }
    }
}
