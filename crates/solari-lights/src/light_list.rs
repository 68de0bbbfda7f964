//! The light list: which lights a scene has, their stable keys and their selection weights.

use crate::alias::AliasTable;
use glam::Vec3;
use solari_scene::Scene;
use solari_scene::brdf::luminance;
use solari_scene::model::PunctualKind;

/// Marks a light that no longer exists in a translation table.
pub const LIGHT_GONE: u32 = u32::MAX;

/// What identifies a light across frames: the same key means the same light.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LightKey {
    /// An emissive instance, by instance index, mesh and material (so a replaced instance at
    /// the same index is a new light).
    Emissive {
        /// Index into `Scene::instances`.
        instance: u32,
        /// Its mesh.
        mesh: u32,
        /// Its material.
        material: u32,
    },
    /// A directional light, by index into `Scene::directional_lights`.
    Directional {
        /// Index into `Scene::directional_lights`.
        index: u32,
    },
    /// The environment map (there is at most one), by the identity of its data (the `Arc`'s
    /// address): a new map is a new light, so temporal reuse drops samples of the old one.
    Environment {
        /// `Arc::as_ptr` of `Scene::environment_map`.
        map: usize,
    },
    /// A point or spot light, by index into `Scene::punctual_lights`.
    Punctual {
        /// Index into `Scene::punctual_lights`.
        index: u32,
    },
}

/// A spot light's cone as glTF's `KHR_lights_punctual` defines its falloff: light leaving at
/// angle θ from the axis is scaled by `clamp(cos θ · scale + offset, 0, 1)²`, which is 1 inside
/// the inner cone and 0 outside the outer one. A point light's cone is [`SpotCone::NONE`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotCone {
    /// Unit axis: the direction the spot shines in.
    pub axis: Vec3,
    /// `1 / max(cos inner − cos outer, 0.001)`; 0 for no cone.
    pub scale: f32,
    /// `−cos outer · scale`; 1 for no cone.
    pub offset: f32,
}

impl SpotCone {
    /// No cone: every direction at full strength.
    pub const NONE: SpotCone = SpotCone {
        axis: Vec3::Z,
        scale: 0.0,
        offset: 1.0,
    };

    /// The cone of a spot shining along `axis` with glTF's inner and outer angles (radians).
    /// Angles are clamped to glTF's valid range, 0 ≤ inner ≤ outer ≤ π/2.
    pub fn new(axis: Vec3, inner: f32, outer: f32) -> Self {
        let outer = outer.clamp(0.0, std::f32::consts::FRAC_PI_2);
        let inner = inner.clamp(0.0, outer);
        let scale = 1.0 / (inner.cos() - outer.cos()).max(0.001);
        SpotCone {
            axis: axis.normalize_or(Vec3::NEG_Z),
            scale,
            offset: -outer.cos() * scale,
        }
    }

    /// The factor on light leaving along unit direction `travel`.
    pub fn attenuation(&self, travel: Vec3) -> f32 {
        let a = (self.axis.dot(travel) * self.scale + self.offset).clamp(0.0, 1.0);
        a * a
    }

    /// The cosine of the outer cone's half-angle, beyond which the spot gives no light;
    /// `None` for a point light (no cone).
    pub fn cos_outer(&self) -> Option<f32> {
        (self.scale != 0.0).then(|| -self.offset / self.scale)
    }

    /// The solid angle the spot lights, counting the falloff as full strength out to the
    /// outer cone (for selection by power only).
    pub fn lit_solid_angle(&self) -> f32 {
        self.cos_outer()
            .map_or(4.0 * std::f32::consts::PI, |cos_outer| {
                2.0 * std::f32::consts::PI * (1.0 - cos_outer)
            })
    }
}

/// One light.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// An instance with an emissive material; its triangles are
    /// `LightList::triangles[first_triangle..][..triangle_count]`.
    Emissive {
        /// Index into `Scene::instances`.
        instance: u32,
        /// First of its triangles in [`LightList::triangles`].
        first_triangle: u32,
        /// How many triangles it has (all with positive area).
        triangle_count: u32,
        /// Total world-space area.
        area: f32,
        /// Emitted radiance (the material's emissive factor; textures modulate it on the GPU).
        radiance: Vec3,
        /// Whether it emits from both faces (double-sided material).
        double_sided: bool,
        /// Whether the instance's transform mirrors (negative determinant). Its triangles'
        /// world-space edges then wind the other way, so the emitting (front) face, which is
        /// the mesh's own winding, faces along −(e1 × e2) rather than e1 × e2.
        mirrored: bool,
        /// The material's emissive texture, if any: the GPU's light readers multiply each
        /// sample's radiance by its texel (`light_emission.wesl`), and the light's power
        /// counts the texture's mean.
        emissive_texture: Option<u32>,
    },
    /// A directional light seen as a disk of uniform radiance.
    Directional {
        /// Unit direction towards the light (opposite to the direction light travels).
        to_light: Vec3,
        /// Irradiance on a surface facing the light.
        irradiance: Vec3,
        /// Cosine of the disk's angular radius; 1 for a delta (zero-size) light.
        cos_radius: f32,
    },
    /// The environment map, importance-sampled by [`LightList::environment`]: radiance from
    /// direction `d` is `radiance × map(d)`.
    Environment {
        /// The factor on the map (`Scene::environment_radiance`).
        radiance: Vec3,
    },
    /// A point or spot light: a delta light at `position` when `radius` is 0, else a sphere
    /// whose outward-facing surface has uniform radiance `intensity / (π radius²)`, which gives
    /// the same intensity as the delta light from afar. Spot lights scale the light leaving
    /// each point by their cone's falloff along the direction it leaves in. Point lights have
    /// no surface the camera sees directly (as in glTF viewers); their reflections do.
    Point {
        /// World position (the sphere's centre).
        position: Vec3,
        /// Sphere radius; 0 for a delta light.
        radius: f32,
        /// Radiant intensity per channel (W/sr).
        intensity: Vec3,
        /// The spot's cone, or [`SpotCone::NONE`] for a point light.
        cone: SpotCone,
    },
}

impl Light {
    /// The nearest front-facing hit of the ray `o + t d` (`d` unit) on this sphere light,
    /// within (0, `t_max`); `None` for a miss, a ray from inside (the far side faces away: the
    /// emitter is one-sided), a delta point light or another kind. Solved about the projection
    /// of the centre on the ray, which keeps precision for small spheres far away. WGSL twin:
    /// `sphere_light_hit` in `light_sampling.wesl`, which the reference tracer's BRDF rays use.
    pub fn sphere_hit(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        let Light::Point {
            position, radius, ..
        } = *self
        else {
            return None;
        };
        self.sphere()?;
        let oc = position - o;
        let b = oc.dot(d);
        let off = oc - b * d;
        let h2 = radius * radius - off.dot(off);
        if !(h2 > 0.0) {
            return None;
        }
        let t = b - h2.sqrt();
        (t > 0.0 && t < t_max).then_some(t)
    }

    /// A sphere light's surface radiance (`intensity / (π r²)`), and its area `4π r²`; `None`
    /// for a delta point light and for other kinds.
    pub fn sphere(&self) -> Option<(Vec3, f32)> {
        match *self {
            Light::Point {
                radius, intensity, ..
            } if radius > 0.0 => {
                let r2 = radius * radius;
                Some((
                    intensity / (std::f32::consts::PI * r2),
                    4.0 * std::f32::consts::PI * r2,
                ))
            }
            _ => None,
        }
    }
}

/// A directional light's disk as sampled: the radiance that makes a facing surface receive
/// `irradiance` (E = L π sin² r) and the disk's solid angle 2π(1 − cos r). `None` for a delta
/// light (zero diameter). The CPU sampler and the GPU upload both use it.
pub fn sun_disk(irradiance: Vec3, cos_radius: f32) -> Option<(Vec3, f32)> {
    if cos_radius >= 1.0 {
        return None;
    }
    let sin2 = 1.0 - cos_radius * cos_radius;
    Some((
        irradiance / (std::f32::consts::PI * sin2),
        2.0 * std::f32::consts::PI * (1.0 - cos_radius),
    ))
}

/// An emissive triangle in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmissiveTriangle {
    /// Triangle index within its mesh.
    pub primitive: u32,
    /// World-space corner 0.
    pub v0: Vec3,
    /// World-space edge v1 − v0.
    pub e1: Vec3,
    /// World-space edge v2 − v0.
    pub e2: Vec3,
    /// World-space area.
    pub area: f32,
    /// Cumulative area fraction of its light up to and including this triangle (the last is 1).
    pub cdf: f32,
}

/// How the light to sample is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Selection {
    /// Every light equally likely (what Solari does).
    Uniform,
    /// Proportional to emitted power, through an alias table.
    #[default]
    Power,
}

/// Lights left out of a [`LightList`], and why (reported, not silently dropped).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightListReport {
    /// Emissive instances whose emission was not finite (left out).
    pub non_finite_emission: Vec<u32>,
    /// Emissive instances whose triangles all had zero area (left out).
    pub zero_area: Vec<u32>,
    /// Emissive triangles of zero or non-finite area skipped inside kept lights.
    pub skipped_triangles: usize,
    /// Directional lights left out as broken: irradiance not finite or with no channel above
    /// zero (but not exactly zero: that is [`LightListReport::off_directional`]), or no
    /// direction. (`Scene::validate` refuses most of these at load.)
    pub dark_directional: Vec<u32>,
    /// Point and spot lights left out as broken: intensity not finite or with no channel
    /// above zero (but not exactly zero: [`LightListReport::off_punctual`]), a position or
    /// axis not finite, or a cone that lights nothing.
    pub dark_punctual: Vec<u32>,
    /// Directional lights switched off: irradiance exactly zero, the rest well formed. Left
    /// out, and not a problem: [`LightListReport::lines`] does not list them (a scene that
    /// switches its lights would otherwise warn at every switch).
    pub off_directional: Vec<u32>,
    /// Point and spot lights switched off: intensity exactly zero, the rest well formed (left
    /// out, not listed by [`LightListReport::lines`]).
    pub off_punctual: Vec<u32>,
    /// Point and spot lights whose radius was negative, not finite, or so small that the
    /// sphere's radiance would not be finite: rendered as delta lights.
    pub radius_to_delta: Vec<u32>,
}

impl LightListReport {
    /// One line naming the lights switched off (left out as they should be), or `None`.
    /// Worth a debug log, not a warning.
    pub fn off_line(&self) -> Option<String> {
        let n = self.off_directional.len() + self.off_punctual.len();
        (n > 0).then(|| {
            format!(
                "{n} light(s) switched off (zero power) left out: directional {:?}, point/spot {:?}",
                self.off_directional, self.off_punctual
            )
        })
    }

    /// One human-readable line per kind of problem; empty when every light was kept as given
    /// or switched off ([`LightListReport::off_line`]).
    pub fn lines(&self) -> Vec<String> {
        let mut out = Vec::new();
        let mut push = |v: &[u32], what: &str| {
            if !v.is_empty() {
                out.push(format!("{} {what}: {v:?}", v.len()));
            }
        };
        push(
            &self.non_finite_emission,
            "emissive instance(s) with non-finite emission left out",
        );
        push(
            &self.zero_area,
            "emissive instance(s) of zero area left out",
        );
        push(
            &self.dark_directional,
            "black or broken directional light(s) left out",
        );
        push(
            &self.dark_punctual,
            "black or broken point/spot light(s) left out",
        );
        push(
            &self.radius_to_delta,
            "point/spot light(s) whose radius cannot make a finite sphere rendered as delta lights",
        );
        if self.skipped_triangles > 0 {
            out.push(format!(
                "{} emissive triangle(s) of zero or non-finite area skipped",
                self.skipped_triangles
            ));
        }
        out
    }
}

/// A sampled environment: its map and the distribution directions are drawn from.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentLight {
    /// Index of [`Light::Environment`] in [`LightList::lights`].
    pub light: u32,
    /// The map (shared with the scene).
    pub map: std::sync::Arc<solari_scene::EnvironmentMap>,
    /// Its importance-sampling distribution.
    pub distribution: crate::environment::EnvironmentDistribution,
}

/// Every light of a scene that can contribute, with both selection distributions.
#[derive(Clone, Debug, Default)]
pub struct LightList {
    /// The lights.
    pub lights: Vec<Light>,
    /// Each light's key, parallel to `lights`.
    pub keys: Vec<LightKey>,
    /// Emissive triangles, grouped per light.
    pub triangles: Vec<EmissiveTriangle>,
    /// Each light's emitted power (W, luminance-weighted), parallel to `lights`.
    pub power: Vec<f32>,
    /// Power-proportional selection.
    pub power_table: AliasTable,
    /// What was left out.
    pub report: LightListReport,
    /// Index of the first point or spot light (they follow every other light).
    pub first_punctual: u32,
    /// The environment, when it is a light ([`Scene::environment_is_light`]).
    pub environment: Option<EnvironmentLight>,
}

impl LightList {
    /// Collects the lights of `scene`. Black emitters, zero-area emitters and lights with
    /// non-finite values are left out and listed in [`LightList::report`].
    pub fn build(scene: &Scene) -> Self {
        let mut list = LightList::default();
        for (index, inst) in scene.instances.iter().enumerate() {
            let Some(material) = scene.materials.get(inst.material as usize) else {
                continue;
            };
            let Some(mesh) = scene.meshes.get(inst.mesh as usize) else {
                continue;
            };
            if !material.is_emissive() {
                continue;
            }
            if !material.emissive.is_finite() {
                list.report.non_finite_emission.push(index as u32);
                continue;
            }
            let first = list.triangles.len();
            let mut area = 0.0f64;
            for t in 0..mesh.triangle_count() {
                let [a, b, c] = mesh.triangle(t).map(|p| inst.transform.transform_point3(p));
                let (e1, e2) = (b - a, c - a);
                let tri_area = 0.5 * e1.cross(e2).length();
                if !(tri_area > 0.0 && tri_area.is_finite() && a.is_finite()) {
                    list.report.skipped_triangles += 1;
                    continue;
                }
                area += tri_area as f64;
                list.triangles.push(EmissiveTriangle {
                    primitive: t as u32,
                    v0: a,
                    e1,
                    e2,
                    area: tri_area,
                    cdf: area as f32,
                });
            }
            if list.triangles.len() == first {
                list.report.zero_area.push(index as u32);
                continue;
            }
            for tri in &mut list.triangles[first..] {
                tri.cdf = (tri.cdf as f64 / area) as f32;
            }
            if let Some(last) = list.triangles.last_mut() {
                last.cdf = 1.0;
            }
            let sides = if material.double_sided { 2.0 } else { 1.0 };
            let emissive_texture = material
                .emissive_texture
                .filter(|t| (*t as usize) < scene.textures.len());
            let mean =
                emissive_texture.map_or(Vec3::ONE, |t| scene.textures[t as usize].mean_linear());
            list.power.push(
                luminance(material.emissive * mean) * area as f32 * std::f32::consts::PI * sides,
            );
            list.keys.push(LightKey::Emissive {
                instance: index as u32,
                mesh: inst.mesh,
                material: inst.material,
            });
            list.lights.push(Light::Emissive {
                instance: index as u32,
                first_triangle: first as u32,
                triangle_count: (list.triangles.len() - first) as u32,
                area: area as f32,
                radiance: material.emissive,
                double_sided: material.double_sided,
                mirrored: inst.transform.determinant() < 0.0,
                emissive_texture,
            });
        }
        // A directional light's power: its irradiance over the scene's cross-section.
        let (lo, hi) = scene.bounds();
        let radius = if lo.is_finite() && hi.is_finite() {
            0.5 * (hi - lo).length()
        } else {
            1.0
        };
        for (index, light) in scene.directional_lights.iter().enumerate() {
            let dir = light.direction.normalize_or_zero();
            let lit = light.irradiance.is_finite()
                && light.irradiance.max_element() > 0.0
                && dir != Vec3::ZERO;
            if !lit {
                if light.irradiance == Vec3::ZERO && dir.is_finite() && dir != Vec3::ZERO {
                    list.report.off_directional.push(index as u32);
                } else {
                    list.report.dark_directional.push(index as u32);
                }
                continue;
            }
            let radius_angle =
                (0.5 * light.angular_diameter).clamp(0.0, 0.5 * std::f32::consts::PI);
            list.power
                .push(luminance(light.irradiance) * std::f32::consts::PI * radius * radius);
            list.keys.push(LightKey::Directional {
                index: index as u32,
            });
            list.lights.push(Light::Directional {
                to_light: -dir,
                irradiance: light.irradiance,
                cos_radius: radius_angle.cos(),
            });
        }
        // The environment map: its irradiance on a surface facing the whole sky (π times its
        // mean radiance) over the scene's cross-section, as for a directional light.
        if scene.environment_is_light()
            && let Some(map) = &scene.environment_map
            && let Some(distribution) = crate::environment::EnvironmentDistribution::new(map)
        {
            let mean = scene.environment_radiance * map.mean_radiance();
            list.power.push(
                (luminance(mean) * std::f32::consts::PI * std::f32::consts::PI * radius * radius)
                    .min(f32::MAX),
            );
            list.keys.push(LightKey::Environment {
                map: std::sync::Arc::as_ptr(map) as usize,
            });
            list.environment = Some(EnvironmentLight {
                light: list.lights.len() as u32,
                map: map.clone(),
                distribution,
            });
            list.lights.push(Light::Environment {
                radiance: scene.environment_radiance,
            });
        }
        list.first_punctual = list.lights.len() as u32;
        for (index, light) in scene.punctual_lights.iter().enumerate() {
            let index = index as u32;
            let cone = match light.kind {
                PunctualKind::Point => SpotCone::NONE,
                PunctualKind::Spot { inner, outer } => SpotCone::new(light.direction, inner, outer),
            };
            let lit = light.intensity.is_finite()
                && light.intensity.max_element() > 0.0
                && light.position.is_finite()
                && cone.axis.is_finite()
                && cone.lit_solid_angle() > 0.0;
            if !lit {
                let well_formed = light.position.is_finite()
                    && cone.axis.is_finite()
                    && cone.lit_solid_angle() > 0.0;
                if light.intensity == Vec3::ZERO && well_formed {
                    list.report.off_punctual.push(index);
                } else {
                    list.report.dark_punctual.push(index);
                }
                continue;
            }
            let mut radius = light.radius;
            let sphere_ok = radius > 0.0
                && (light.intensity / (std::f32::consts::PI * radius * radius)).is_finite();
            if !sphere_ok {
                if radius != 0.0 {
                    list.report.radius_to_delta.push(index);
                }
                radius = 0.0;
            }
            // Clamped so an absurd intensity still gets picked (an infinite weight would
            // count as zero).
            list.power
                .push((luminance(light.intensity) * cone.lit_solid_angle()).min(f32::MAX));
            list.keys.push(LightKey::Punctual { index });
            list.lights.push(Light::Point {
                position: light.position,
                radius,
                intensity: light.intensity,
                cone,
            });
        }
        list.power_table = AliasTable::new(&list.power);
        list
    }

    /// Whether the list holds point or spot lights (passes built with
    /// [`crate::LightTileSettings::point_lights`] off ignore them).
    pub fn has_point_lights(&self) -> bool {
        !self.punctual_range().is_empty()
    }

    /// Whether an emissive light has an emissive texture (passes built with
    /// [`crate::LightTileSettings::emissive_textures`] off shade it with its factor alone).
    pub fn has_emissive_textures(&self) -> bool {
        self.lights.iter().any(|l| {
            matches!(
                l,
                Light::Emissive {
                    emissive_texture: Some(_),
                    ..
                }
            )
        })
    }

    /// The point and spot lights: `lights[first..first + count]` (they come last).
    pub fn punctual_range(&self) -> std::ops::Range<usize> {
        self.first_punctual as usize..self.lights.len()
    }

    /// The index of the first directional light. The directional lights follow the emissive
    /// ones and come before the environment light (if any) and the point and spot lights, so
    /// they end where [`LightList::environment`]'s light or [`LightList::first_punctual`]
    /// begins; with none, this is that end.
    pub fn first_directional(&self) -> u32 {
        let end = self
            .environment
            .as_ref()
            .map_or(self.first_punctual, |e| e.light);
        let mut first = end as usize;
        while first > 0 && matches!(self.lights[first - 1], Light::Directional { .. }) {
            first -= 1;
        }
        first as u32
    }

    /// Number of lights.
    pub fn len(&self) -> usize {
        self.lights.len()
    }

    /// How many separate things light sampling chooses among: each emissive triangle, each
    /// directional, point or spot light; `u32::MAX` with an environment map (a continuum of
    /// directions). A measure of how hard a scene's lights are to sample, which is what
    /// decides whether ReSTIR DI's reuse pays (`RestirDiSettings::reuse_light_threshold`).
    pub fn sampling_elements(&self) -> u32 {
        let mut n = 0u32;
        for l in &self.lights {
            n = n.saturating_add(match *l {
                Light::Emissive { triangle_count, .. } => triangle_count,
                Light::Environment { .. } => u32::MAX,
                _ => 1,
            });
        }
        n
    }

    /// Whether the scene has no light that can contribute (passes that need lights skip).
    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }

    /// Probability that `selection` picks `light`.
    pub fn selection_pdf(&self, selection: Selection, light: usize) -> f32 {
        match selection {
            Selection::Uniform => 1.0 / self.lights.len() as f32,
            Selection::Power => self.power_table.pmf[light],
        }
    }

    /// Picks a light index from one uniform number.
    pub fn select(&self, selection: Selection, u: f32) -> usize {
        let n = self.lights.len();
        let x = u.clamp(0.0, 1.0) * n as f32;
        let slot = (x as usize).min(n - 1);
        match selection {
            Selection::Uniform => slot,
            // The fraction left in u after choosing the slot is a fresh uniform number.
            Selection::Power => self.power_table.sample(u, x - slot as f32),
        }
    }

    /// For each light of `previous`, its index in `self`, or [`LIGHT_GONE`]: lets temporal
    /// reuse follow lights across frames and drop removed ones.
    pub fn translation_from(&self, previous: &LightList) -> Vec<u32> {
        let current: std::collections::HashMap<LightKey, u32> = self
            .keys
            .iter()
            .enumerate()
            .map(|(i, k)| (*k, i as u32))
            .collect();
        previous
            .keys
            .iter()
            .map(|k| current.get(k).copied().unwrap_or(LIGHT_GONE))
            .collect()
    }
}
