//! Light samples: choosing a light and a point or direction on it, resolved for a shading
//! point, with the solid-angle pdf every estimator and MIS weight needs.

use crate::light_list::{Light, LightList, Selection, sun_disk};
use glam::Vec3;
use solari_scene::brdf::{self, BrdfMaterial, orthonormal_basis};
use std::f32::consts::PI;

/// A light sample resolved for one shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Index of the light in the [`LightList`].
    pub light: u32,
    /// Unit direction from the shading point towards the sample.
    pub direction: Vec3,
    /// Distance to the sample point; infinite for directional lights.
    pub distance: f32,
    /// Radiance arriving along `direction` (before visibility). For a delta light, the
    /// irradiance it delivers at normal incidence.
    pub radiance: Vec3,
    /// Solid-angle pdf, selection included; for a delta light, the selection probability.
    pub pdf: f32,
    /// Whether the sample is a delta (zero-size directional) light, which BRDF sampling can
    /// never hit: its MIS weight is one.
    pub delta: bool,
}

impl LightList {
    /// Samples a light for shading point `x` from four uniform numbers: `u[0]` picks the light,
    /// `u[1]` the triangle (by area), `u[2..4]` the point or direction. `None` when there are
    /// no lights, or the sampled point sees `x` from behind (a one-sided emitter) or coincides
    /// with it: such samples contribute nothing, which keeps the estimator unbiased.
    pub fn sample(&self, selection: Selection, x: Vec3, u: [f32; 4]) -> Option<LightSample> {
        if self.lights.is_empty() {
            return None;
        }
        let index = self.select(selection, u[0]);
        let p_select = self.selection_pdf(selection, index);
        match &self.lights[index] {
            Light::Emissive {
                first_triangle,
                triangle_count,
                area,
                radiance,
                double_sided,
                ..
            } => {
                let tris = &self.triangles
                    [*first_triangle as usize..(*first_triangle + *triangle_count) as usize];
                let t = tris.partition_point(|t| t.cdf < u[1]).min(tris.len() - 1);
                let tri = &tris[t];
                // Uniform point on the triangle.
                let su = u[2].sqrt();
                let (b1, b2) = (su * (1.0 - u[3]), su * u[3]);
                let y = tri.v0 + tri.e1 * b1 + tri.e2 * b2;
                let n = tri.e1.cross(tri.e2).normalize_or_zero();
                let to = y - x;
                let d2 = to.length_squared();
                if !(d2 > 0.0 && d2.is_finite()) {
                    return None;
                }
                let distance = d2.sqrt();
                let direction = to / distance;
                let cos_light = -n.dot(direction);
                let cos_light = if *double_sided {
                    cos_light.abs()
                } else {
                    cos_light
                };
                if !(cos_light > 0.0) {
                    return None;
                }
                // Area pdf p_select / area, to solid angle.
                let pdf = p_select / area * d2 / cos_light;
                (pdf.is_finite() && pdf > 0.0).then_some(LightSample {
                    light: index as u32,
                    direction,
                    distance,
                    radiance: *radiance,
                    pdf,
                    delta: false,
                })
            }
            Light::Directional {
                to_light,
                irradiance,
                cos_radius,
            } => {
                let Some((radiance, solid_angle)) = sun_disk(*irradiance, *cos_radius) else {
                    return Some(LightSample {
                        light: index as u32,
                        direction: *to_light,
                        distance: f32::INFINITY,
                        radiance: *irradiance,
                        pdf: p_select,
                        delta: true,
                    });
                };
                // Uniform direction in the cone.
                let cos_t = 1.0 - u[2] * (1.0 - cos_radius);
                let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                let phi = 2.0 * PI * u[3];
                let (t, b) = orthonormal_basis(*to_light);
                let direction =
                    (t * (sin_t * phi.cos()) + b * (sin_t * phi.sin()) + *to_light * cos_t)
                        .normalize();
                Some(LightSample {
                    light: index as u32,
                    direction,
                    distance: f32::INFINITY,
                    radiance,
                    pdf: p_select / solid_angle,
                    delta: false,
                })
            }
        }
    }

    /// Solid-angle pdf with which [`LightList::sample`] would have produced the point `y` with
    /// normal `n_y` on emissive `light`, seen from `x`: the other half of MIS when a BRDF
    /// sample hits an emitter.
    pub fn emissive_pdf(
        &self,
        selection: Selection,
        light: usize,
        x: Vec3,
        y: Vec3,
        n_y: Vec3,
    ) -> f32 {
        let Some(Light::Emissive {
            area, double_sided, ..
        }) = self.lights.get(light)
        else {
            return 0.0;
        };
        let to = y - x;
        let d2 = to.length_squared();
        let cos = -n_y.dot(to / d2.sqrt());
        let cos = if *double_sided { cos.abs() } else { cos };
        if !(cos > 0.0 && d2 > 0.0) {
            return 0.0;
        }
        self.selection_pdf(selection, light) / area * d2 / cos
    }
}

/// The light sample's unshadowed contribution at a surface: BRDF × cos × radiance / pdf, for
/// shading normal `n` and unit direction to the viewer `wo` (world space).
pub fn unshadowed_contribution(
    sample: &LightSample,
    material: &BrdfMaterial,
    n: Vec3,
    wo: Vec3,
) -> Vec3 {
    let (t, b) = orthonormal_basis(n);
    let local = |v: Vec3| Vec3::new(v.dot(t), v.dot(b), v.dot(n));
    let f = brdf::eval(material, local(wo), local(sample.direction));
    let c = f * sample.radiance / sample.pdf;
    if c.is_finite() { c } else { Vec3::ZERO }
}
