//! What a scene must satisfy before it is rendered, whether it came from a file or was built
//! in code: finite geometry within a range f32 can resolve, indices in range, lights and
//! emission finite and non-negative, and usable cameras.
//!
//! Import applies the same rules (clamping absurd but finite light values with a warning, see
//! [`MAX_RADIANCE`]); [`Scene::validate`] is what the GPU upload calls, so a scene built in code
//! gets the same guarantees.

use crate::model::{Camera, Scene};
use glam::Vec3;

/// Largest world-space coordinate a scene may use, in scene units (metres by glTF's
/// convention). Beyond it f32 positions are spaced 8 units or more apart, ray offsets and
/// depths lose all meaning, and bounding-box arithmetic of a scene spanning ±1e38 overflows to
/// infinity; such a scene is refused instead of rendering black.
pub const MAX_COORDINATE: f32 = 1.0e8;

/// Largest emitted radiance, light intensity or irradiance per channel. Larger finite values
/// (glTF allows any emissive strength) are clamped to it on import with a warning, so that
/// sums over samples and bounces stay finite in f32 (1e38 emission wrote +Inf into images).
pub const MAX_RADIANCE: f32 = 1.0e9;

impl Camera {
    /// Whether the camera can render: finite, non-degenerate orientation, position within
    /// [`MAX_COORDINATE`], `0 < yfov < π`, a positive finite near plane and aspect ratio.
    pub fn validate(&self) -> Result<(), String> {
        let name = &self.name;
        if !self.transform.is_finite() {
            return Err(format!("camera {name}: transform is not finite"));
        }
        let p = self.position();
        if p.abs().max_element() > MAX_COORDINATE {
            return Err(format!(
                "camera {name}: position {p} is beyond ±{MAX_COORDINATE:e}, where f32 cannot \
                 place rays"
            ));
        }
        let axes = [
            self.transform.x_axis.truncate(),
            self.transform.y_axis.truncate(),
            self.transform.z_axis.truncate(),
        ];
        if axes.iter().any(|a| (a.length() - 1.0).abs() > 1e-3)
            || axes[0].dot(axes[1]).abs() > 1e-3
            || axes[2].dot(axes[0].cross(axes[1])) < 0.999
        {
            return Err(format!(
                "camera {name}: orientation is not a rotation (zero scale, shear or mirror)"
            ));
        }
        if !(self.yfov > 1e-6 && self.yfov < std::f32::consts::PI - 1e-6) {
            return Err(format!(
                "camera {name}: vertical field of view {} rad is outside (0, π)",
                self.yfov
            ));
        }
        if !(self.znear.is_finite() && self.znear > 0.0) {
            return Err(format!(
                "camera {name}: near plane {} must be positive and finite",
                self.znear
            ));
        }
        if let Some(a) = self.aspect
            && !(a.is_finite() && a > 1e-6 && a < 1e6)
        {
            return Err(format!(
                "camera {name}: aspect ratio {a} must be positive and finite"
            ));
        }
        Ok(())
    }
}

fn finite_non_negative(v: Vec3) -> bool {
    v.is_finite() && v.min_element() >= 0.0
}

impl Scene {
    /// Checks what rendering relies on (see the module doc); the message names the element.
    pub fn validate(&self) -> Result<(), String> {
        if self.instances.is_empty() {
            return Err("the scene has no instances".into());
        }
        for (i, m) in self.meshes.iter().enumerate() {
            let n = m.positions.len();
            if m.normals.len() != n || m.uvs.len() != n || m.tangents.len() != n {
                return Err(format!(
                    "mesh {i} ({}): attribute counts differ from its {n} positions",
                    m.name
                ));
            }
            if !m.indices.len().is_multiple_of(3) {
                return Err(format!(
                    "mesh {i} ({}): index count not a multiple of 3",
                    m.name
                ));
            }
            if let Some(bad) = m.indices.iter().find(|&&x| x as usize >= n) {
                return Err(format!(
                    "mesh {i} ({}): index {bad} out of range ({n} vertices)",
                    m.name
                ));
            }
            if let Some(v) = m.positions.iter().position(|p| !p.is_finite()) {
                return Err(format!("mesh {i} ({}): vertex {v} is not finite", m.name));
            }
        }
        for (i, inst) in self.instances.iter().enumerate() {
            if inst.mesh as usize >= self.meshes.len()
                || inst.material as usize >= self.materials.len()
            {
                return Err(format!(
                    "instance {i} ({}): mesh or material index out of range",
                    inst.name
                ));
            }
            if !inst.transform.is_finite() {
                return Err(format!(
                    "instance {i} ({}): transform is not finite",
                    inst.name
                ));
            }
            let (lo, hi) = crate::trace_cpu::instance_bounds(self, inst);
            let reach = lo.abs().max(hi.abs()).max_element();
            if reach.is_nan() || reach > MAX_COORDINATE {
                return Err(format!(
                    "instance {i} ({}) reaches {reach:e}, beyond ±{MAX_COORDINATE:e} where f32 \
                     cannot resolve geometry",
                    inst.name
                ));
            }
        }
        for (i, m) in self.materials.iter().enumerate() {
            if !finite_non_negative(m.emissive) || m.emissive.max_element() > MAX_RADIANCE {
                return Err(format!(
                    "material {i} ({}): emission {} must be finite, non-negative and at most \
                     {MAX_RADIANCE:e}",
                    m.name, m.emissive
                ));
            }
            if !m.base_color.is_finite() || !m.dielectric_f0.is_finite() {
                return Err(format!("material {i} ({}): non-finite factors", m.name));
            }
            for t in [
                m.base_color_texture,
                m.metallic_roughness_texture,
                m.normal_texture,
                m.emissive_texture,
            ]
            .into_iter()
            .flatten()
            {
                if t as usize >= self.textures.len() {
                    return Err(format!(
                        "material {i} ({}): texture {t} out of range",
                        m.name
                    ));
                }
            }
        }
        for l in &self.directional_lights {
            if !finite_non_negative(l.irradiance)
                || l.irradiance.max_element() > MAX_RADIANCE
                || !l.direction.is_finite()
                || (l.direction.length() - 1.0).abs() > 1e-3
                || !(0.0..std::f32::consts::PI).contains(&l.angular_diameter)
            {
                return Err(format!(
                    "directional light {}: irradiance must be finite, non-negative and at most \
                     {MAX_RADIANCE:e}, the direction a unit vector and the angular diameter in \
                     [0, π)",
                    l.name
                ));
            }
        }
        if !finite_non_negative(self.environment_radiance)
            || self.environment_radiance.max_element() > MAX_RADIANCE
        {
            return Err(format!(
                "environment radiance {} must be finite, non-negative and at most {MAX_RADIANCE:e}",
                self.environment_radiance
            ));
        }
        for c in &self.cameras {
            c.validate()?;
        }
        Ok(())
    }
}

/// Clamps each channel of a finite non-negative light value to [`MAX_RADIANCE`]; returns
/// whether it had to.
pub fn clamp_radiance(v: &mut Vec3) -> bool {
    let clamped = v.min(Vec3::splat(MAX_RADIANCE));
    let changed = clamped != *v;
    *v = clamped;
    changed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::default_scene::cornell_box;
    use glam::Mat4;

    #[test]
    fn the_built_in_scenes_are_valid() {
        cornell_box().validate().unwrap();
        crate::textured_scene::textured_spheres()
            .validate()
            .unwrap();
    }

    #[test]
    fn broken_scenes_are_refused_with_the_element_named() {
        type Breaker = Box<dyn Fn(&mut Scene)>;
        let cases: Vec<(&str, Breaker)> = vec![
            (
                "vertex",
                Box::new(|s| s.meshes[0].positions[1].y = f32::NAN),
            ),
            ("index", Box::new(|s| s.meshes[0].indices[2] = 999)),
            (
                "reaches",
                Box::new(|s| s.instances[0].transform = Mat4::from_scale(Vec3::splat(1e37))),
            ),
            (
                "emission",
                Box::new(|s| s.materials[3].emissive.x = f32::INFINITY),
            ),
            ("emission", Box::new(|s| s.materials[3].emissive.y = -1.0)),
            ("field of view", Box::new(|s| s.cameras[0].yfov = f32::NAN)),
            ("field of view", Box::new(|s| s.cameras[0].yfov = 0.0)),
            (
                "position",
                Box::new(|s| s.cameras[0].transform.w_axis.x = 1e30),
            ),
            (
                "orientation",
                Box::new(|s| s.cameras[0].transform.x_axis = glam::Vec4::ZERO),
            ),
            ("near plane", Box::new(|s| s.cameras[0].znear = 0.0)),
            ("aspect", Box::new(|s| s.cameras[0].aspect = Some(f32::NAN))),
            (
                "environment",
                Box::new(|s| s.environment_radiance.z = f32::NAN),
            ),
            ("no instances", Box::new(|s| s.instances.clear())),
        ];
        for (needle, break_it) in cases {
            let mut s = cornell_box();
            break_it(&mut s);
            let e = s.validate().expect_err(needle);
            assert!(e.contains(needle), "{needle}: {e}");
        }
    }

    #[test]
    fn clamping_keeps_direction_and_reports() {
        let mut v = Vec3::new(1e38, 2.0, 0.0);
        assert!(clamp_radiance(&mut v));
        assert_eq!(v, Vec3::new(MAX_RADIANCE, 2.0, 0.0));
        assert!(!clamp_radiance(&mut v));
    }
}
