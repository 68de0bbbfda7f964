//! Light samples: choosing a light and a point or direction on it, resolved for a shading
//! point, with the solid-angle pdf every estimator and MIS weight needs.

use crate::light_list::{Light, LightList, Selection, sun_disk};
use bytemuck::{Pod, Zeroable};
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
    /// Whether the sample is a delta (zero-size directional or point) light, which BRDF
    /// sampling can never hit: its MIS weight is one.
    pub delta: bool,
}

/// Which light sample was drawn, in 12 bytes: what a reservoir stores to resolve the same
/// sample again in a later frame (after [`LightList::translation_from`] maps `light`), with
/// identical results on CPU and GPU. WGSL twin: `LightSampleId` in `light_sampling.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct LightSampleId {
    /// Index of the light in the [`LightList`].
    pub light: u32,
    /// Emissive: triangle index within the light (relative to its first triangle, so it
    /// survives other lights being added or removed). Environment: the distribution's cell.
    /// Directional and point: 0.
    pub triangle: u32,
    /// The two numbers that place the point (or direction), as 16-bit cells: low half first.
    pub point: u32,
}

const _: () = assert!(size_of::<LightSampleId>() == 12);

/// A light sample resolved independently of any shading point: the form light tiles store.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResolvedLightSample {
    /// Emissive and point: the world-space point. Directional: the unit direction towards
    /// the light.
    pub position: Vec3,
    /// Emissive and sphere: the unit surface normal (unused for delta and directional lights).
    pub normal: Vec3,
    /// Emitted radiance (before a spot's falloff); for a delta directional light its
    /// irradiance at normal incidence, for a delta point light its intensity.
    pub radiance: Vec3,
    /// 1 / pdf, selection included: area measure for emissive and sphere points, solid angle
    /// for sun disks, 1 / selection probability for delta lights.
    pub inverse_pdf: f32,
    /// Whether this is a directional light.
    pub directional: bool,
    /// Emissive: whether the emitter shines from both faces.
    pub double_sided: bool,
    /// Whether it is a delta (zero-size) light.
    pub delta: bool,
    /// Whether it is a point or spot light (whose cone [`ResolvedLightSample::toward`] reads
    /// from the light list, as the GPU does).
    pub punctual: bool,
    /// Emissive: whether the material has an emissive texture. `radiance` is then the
    /// emissive factor alone: the GPU's light readers multiply in the texel at the sample
    /// (`light_emission.wesl`); the CPU sampler has no textures.
    pub textured: bool,
    /// The environment map (a direction, like a directional light): `radiance` is 1, and the
    /// map's radiance along the direction is multiplied in where the sample is seen (by
    /// [`ResolvedLightSample::toward`] on the CPU, by the light readers on the GPU).
    pub environment: bool,
}

/// The 16-bit cell of a uniform number, and the number at the cell's centre: ids store cells,
/// so a point resolved from an id is the same wherever it is resolved.
fn quantize_u16(u: f32) -> u32 {
    ((u.clamp(0.0, 1.0) * 65536.0) as u32).min(65535)
}

fn cell_centre(q: u32) -> f32 {
    (q as f32 + 0.5) * (1.0 / 65536.0)
}

impl LightList {
    /// Samples a light for shading point `x` from four uniform numbers: `u[0]` picks the light,
    /// `u[1]` the triangle (by area), `u[2..4]` the point or direction. `None` when there are
    /// no lights, or the sampled point sees `x` from behind (a one-sided emitter) or coincides
    /// with it: such samples contribute nothing, which keeps the estimator unbiased.
    pub fn sample(&self, selection: Selection, x: Vec3, u: [f32; 4]) -> Option<LightSample> {
        let (light, triangle) = self.pick(selection, u)?;
        self.resolve_at(selection, light, triangle, [u[2], u[3]])?
            .toward(self, light as u32, x)
    }

    /// Draws a light sample's identity from four uniform numbers (as [`LightList::sample`]
    /// uses them, with the point's two numbers kept to 16-bit cells). `None` without lights.
    pub fn generate(&self, selection: Selection, u: [f32; 4]) -> Option<LightSampleId> {
        let (light, triangle) = self.pick(selection, u)?;
        Some(LightSampleId {
            light: light as u32,
            triangle,
            point: quantize_u16(u[2]) | (quantize_u16(u[3]) << 16),
        })
    }

    /// Resolves a sample identity against this list. `None` when the light or triangle does
    /// not exist (a stale id) or the sample is degenerate.
    pub fn resolve(&self, selection: Selection, id: LightSampleId) -> Option<ResolvedLightSample> {
        let point = [cell_centre(id.point & 0xffff), cell_centre(id.point >> 16)];
        self.resolve_at(selection, id.light as usize, id.triangle, point)
    }

    /// The light index and triangle (within the light) that `u[0]` and `u[1]` select.
    fn pick(&self, selection: Selection, u: [f32; 4]) -> Option<(usize, u32)> {
        if self.lights.is_empty() {
            return None;
        }
        let index = self.select(selection, u[0]);
        Some((index, self.pick_part(index, u[1])))
    }

    /// A sample identity on light `light` from three uniform numbers: `u[0]` picks the
    /// triangle (emissive) or cell (environment), `u[1..]` the point. `None` for a light
    /// that does not exist. WGSL twin: `light_sample_on`.
    pub fn generate_on(&self, light: u32, u: [f32; 3]) -> Option<LightSampleId> {
        if light as usize >= self.lights.len() {
            return None;
        }
        Some(LightSampleId {
            light,
            triangle: self.pick_part(light as usize, u[0]),
            point: quantize_u16(u[1]) | (quantize_u16(u[2]) << 16),
        })
    }

    // The triangle (emissive) or cell (environment) of light `index` that u picks.
    fn pick_part(&self, index: usize, u: f32) -> u32 {
        match &self.lights[index] {
            Light::Emissive {
                first_triangle,
                triangle_count,
                ..
            } => {
                let tris = &self.triangles
                    [*first_triangle as usize..(*first_triangle + *triangle_count) as usize];
                tris.partition_point(|t| t.cdf < u).min(tris.len() - 1) as u32
            }
            Light::Environment { .. } => match &self.environment {
                Some(env) => env.distribution.pick(u),
                None => 0,
            },
            Light::Directional { .. } | Light::Point { .. } => 0,
        }
    }

    fn resolve_at(
        &self,
        selection: Selection,
        light: usize,
        triangle: u32,
        point: [f32; 2],
    ) -> Option<ResolvedLightSample> {
        let entry = self.lights.get(light)?;
        let p_select = self.selection_pdf(selection, light);
        let resolved = match entry {
            Light::Emissive {
                first_triangle,
                triangle_count,
                area,
                radiance,
                double_sided,
                mirrored,
                emissive_texture,
                ..
            } => {
                if triangle >= *triangle_count {
                    return None;
                }
                let tri = &self.triangles[(*first_triangle + triangle) as usize];
                // Uniform point on the triangle.
                let su = point[0].sqrt();
                let (b1, b2) = (su * (1.0 - point[1]), su * point[1]);
                ResolvedLightSample {
                    position: tri.v0 + tri.e1 * b1 + tri.e2 * b2,
                    // The emitting face: the mesh's own winding, which a mirrored
                    // instance's world-space edges reverse.
                    normal: tri.e1.cross(tri.e2).normalize_or_zero()
                        * if *mirrored { -1.0 } else { 1.0 },
                    radiance: *radiance,
                    inverse_pdf: area / p_select,
                    directional: false,
                    double_sided: *double_sided,
                    delta: false,
                    punctual: false,
                    textured: emissive_texture.is_some(),
                    environment: false,
                }
            }
            Light::Environment { .. } => {
                let env = self.environment.as_ref()?;
                if triangle >= env.distribution.cell_count() {
                    return None;
                }
                let pdf = env.distribution.pdf_in_cell(triangle, point);
                ResolvedLightSample {
                    position: env.distribution.direction(triangle, point),
                    normal: Vec3::ZERO,
                    radiance: Vec3::ONE,
                    inverse_pdf: 1.0 / (pdf * p_select),
                    directional: true,
                    double_sided: false,
                    delta: false,
                    punctual: false,
                    textured: false,
                    environment: true,
                }
            }
            Light::Point {
                position,
                radius,
                intensity,
                ..
            } => match entry.sphere() {
                // Uniform point on the sphere: half of them face away from any shading point
                // and are rejected by `toward`, which keeps the estimate unbiased.
                Some((radiance, area)) => {
                    let z = 1.0 - 2.0 * point[0];
                    let s = (1.0 - z * z).max(0.0).sqrt();
                    let phi = 2.0 * PI * point[1];
                    let normal = Vec3::new(s * phi.cos(), s * phi.sin(), z);
                    ResolvedLightSample {
                        position: *position + normal * *radius,
                        normal,
                        radiance,
                        inverse_pdf: area / p_select,
                        directional: false,
                        double_sided: false,
                        delta: false,
                        punctual: true,
                        textured: false,
                        environment: false,
                    }
                }
                None => ResolvedLightSample {
                    position: *position,
                    normal: Vec3::ZERO,
                    radiance: *intensity,
                    inverse_pdf: 1.0 / p_select,
                    directional: false,
                    double_sided: false,
                    delta: true,
                    punctual: true,
                    textured: false,
                    environment: false,
                },
            },
            Light::Directional {
                to_light,
                irradiance,
                cos_radius,
            } => {
                let directional = |position, radiance, inverse_pdf, delta| ResolvedLightSample {
                    position,
                    normal: Vec3::ZERO,
                    radiance,
                    inverse_pdf,
                    directional: true,
                    double_sided: false,
                    delta,
                    punctual: false,
                    textured: false,
                    environment: false,
                };
                let Some((radiance, solid_angle)) = sun_disk(*irradiance, *cos_radius) else {
                    return Some(directional(*to_light, *irradiance, 1.0 / p_select, true));
                };
                // Uniform direction in the cone.
                let cos_t = 1.0 - point[0] * (1.0 - cos_radius);
                let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                let phi = 2.0 * PI * point[1];
                let (t, b) = orthonormal_basis(*to_light);
                let direction =
                    (t * (sin_t * phi.cos()) + b * (sin_t * phi.sin()) + *to_light * cos_t)
                        .normalize();
                directional(direction, radiance, solid_angle / p_select, false)
            }
        };
        (resolved.inverse_pdf > 0.0 && resolved.inverse_pdf.is_finite()).then_some(resolved)
    }

    /// The identity of unit direction `d` on the environment light, to 16-bit cells: what a
    /// BRDF-sampled ReSTIR DI candidate stores (twin of `environment_sample_id` in
    /// `light_sampling.wesl`). `None` without an environment light.
    pub fn environment_sample_id(&self, d: Vec3) -> Option<LightSampleId> {
        let env = self.environment.as_ref()?;
        let dist = &env.distribution;
        let uv = solari_scene::environment::direction_to_uv(d);
        let f = uv * glam::Vec2::new(dist.cells_x as f32, dist.cells_y as f32);
        let cx = (f.x as u32).min(dist.cells_x - 1);
        let cy = (f.y as u32).min(dist.cells_y - 1);
        Some(LightSampleId {
            light: env.light,
            triangle: cy * dist.cells_x + cx,
            point: quantize_u16(f.x - cx as f32) | (quantize_u16(f.y - cy as f32) << 16),
        })
    }

    /// The identity of world point `y` on triangle `primitive` (the mesh's index) of emissive
    /// `light`, to 16-bit cells: the inverse of the area-uniform mapping, what a BRDF ray that
    /// meets an emitter stores (twin of `emissive_sample_id` in `light_sampling.wesl`).
    /// `None` when the light is not emissive or the triangle is not part of it.
    pub fn emissive_sample_id(&self, light: u32, primitive: u32, y: Vec3) -> Option<LightSampleId> {
        let Some(Light::Emissive {
            first_triangle,
            triangle_count,
            ..
        }) = self.lights.get(light as usize)
        else {
            return None;
        };
        let tris =
            &self.triangles[*first_triangle as usize..(*first_triangle + *triangle_count) as usize];
        let index = tris.partition_point(|t| t.primitive < primitive);
        let tri = tris.get(index).filter(|t| t.primitive == primitive)?;
        // Barycentrics of y by least squares in the triangle's plane.
        let d = y - tri.v0;
        let (a, b, c) = (tri.e1.dot(tri.e1), tri.e1.dot(tri.e2), tri.e2.dot(tri.e2));
        let det = a * c - b * b;
        let b1 = ((c * d.dot(tri.e1) - b * d.dot(tri.e2)) / det).clamp(0.0, 1.0);
        let b2 = ((a * d.dot(tri.e2) - b * d.dot(tri.e1)) / det).clamp(0.0, 1.0);
        let su = (b1 + b2).min(1.0);
        let t = if b1 + b2 > 0.0 { b2 / (b1 + b2) } else { 0.5 };
        Some(LightSampleId {
            light,
            triangle: index as u32,
            point: quantize_u16(su * su) | (quantize_u16(t) << 16),
        })
    }

    /// Solid-angle pdf with which [`LightList::sample`] would have produced the unit
    /// direction `d` on the environment (0 when the environment is not a light): the other
    /// half of MIS where a BRDF sample escapes the scene.
    pub fn environment_pdf(&self, selection: Selection, d: Vec3) -> f32 {
        match &self.environment {
            Some(env) => {
                self.selection_pdf(selection, env.light as usize) * env.distribution.pdf(d)
            }
            None => 0.0,
        }
    }

    /// The light of the sun disks (directional lights of non-zero size) that a ray leaving
    /// along the unit direction `d` looks into, each weighted by the balance heuristic of the
    /// ray's solid-angle pdf `ray_pdf` against the pdf with which [`LightList::sample`] draws
    /// `d` on that disk, or by 1 without `ray_pdf` (a delta lobe, or no light sample to weigh
    /// against). Twin of WGSL `sun_disc_light`: what a BRDF-sampled ray that misses the scene
    /// adds.
    pub fn sun_disc_light(&self, selection: Selection, d: Vec3, ray_pdf: Option<f32>) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for (i, light) in self.lights.iter().enumerate() {
            let Light::Directional {
                to_light,
                irradiance,
                cos_radius,
            } = *light
            else {
                continue;
            };
            let Some((radiance, solid_angle)) = crate::light_list::sun_disk(irradiance, cos_radius)
            else {
                continue;
            };
            if !(solid_angle > 0.0) || d.dot(to_light) < cos_radius {
                continue;
            }
            let w = match ray_pdf {
                Some(p) => {
                    let light_pdf = self.selection_pdf(selection, i) / solid_angle;
                    let w = 1.0 / (1.0 + light_pdf / p);
                    if w.is_nan() { 0.5 } else { w.clamp(0.0, 1.0) }
                }
                None => 1.0,
            };
            sum += radiance * w;
        }
        sum
    }

    /// Solid-angle pdf with which [`LightList::sample`] would have produced the point `y` with
    /// normal `n_y` on emissive or sphere `light`, seen from `x`: the other half of MIS when a
    /// BRDF sample hits an emitter.
    pub fn emissive_pdf(
        &self,
        selection: Selection,
        light: usize,
        x: Vec3,
        y: Vec3,
        n_y: Vec3,
    ) -> f32 {
        let (area, double_sided) = match self.lights.get(light) {
            Some(Light::Emissive {
                area, double_sided, ..
            }) => (*area, *double_sided),
            Some(l @ Light::Point { .. }) => match l.sphere() {
                Some((_, area)) => (area, false),
                None => return 0.0,
            },
            _ => return 0.0,
        };
        let to = y - x;
        let d2 = to.length_squared();
        let cos = -n_y.dot(to / d2.sqrt());
        let cos = if double_sided { cos.abs() } else { cos };
        if !(cos > 0.0 && d2 > 0.0) {
            return 0.0;
        }
        self.selection_pdf(selection, light) / area * d2 / cos
    }
}

impl ResolvedLightSample {
    /// This sample of light `light` of `list` as seen from shading point `x`: direction,
    /// distance, radiance (a spot's falloff included) and solid-angle pdf. `None` when `x`
    /// sees a one-sided emitter from behind, is outside a spot's cone, or coincides with the
    /// point.
    pub fn toward(&self, list: &LightList, light: u32, x: Vec3) -> Option<LightSample> {
        if self.directional {
            let radiance = match (&list.environment, self.environment) {
                (Some(env), true) => {
                    let factor = match list.lights.get(light as usize) {
                        Some(Light::Environment { radiance }) => *radiance,
                        _ => return None,
                    };
                    self.radiance * factor * env.map.radiance(self.position)
                }
                (None, true) => return None,
                _ => self.radiance,
            };
            return Some(LightSample {
                light,
                direction: self.position,
                distance: f32::INFINITY,
                radiance,
                pdf: 1.0 / self.inverse_pdf,
                delta: self.delta,
            });
        }
        let to = self.position - x;
        let d2 = to.length_squared();
        if !(d2 > 0.0 && d2.is_finite()) {
            return None;
        }
        let distance = d2.sqrt();
        let direction = to / distance;
        // A spot's falloff along the direction the light leaves in.
        let attenuation = match (self.punctual, list.lights.get(light as usize)) {
            (true, Some(Light::Point { cone, .. })) => cone.attenuation(-direction),
            _ => 1.0,
        };
        if !(attenuation > 0.0) {
            return None;
        }
        if self.delta {
            let radiance = self.radiance * (attenuation / d2);
            return radiance.is_finite().then_some(LightSample {
                light,
                direction,
                distance,
                radiance,
                pdf: 1.0 / self.inverse_pdf,
                delta: true,
            });
        }
        let cos_light = -self.normal.dot(direction);
        let cos_light = if self.double_sided {
            cos_light.abs()
        } else {
            cos_light
        };
        if !(cos_light > 0.0) {
            return None;
        }
        // Area pdf to solid angle.
        let pdf = d2 / (cos_light * self.inverse_pdf);
        (pdf.is_finite() && pdf > 0.0).then_some(LightSample {
            light,
            direction,
            distance,
            radiance: self.radiance * attenuation,
            pdf,
            delta: false,
        })
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
