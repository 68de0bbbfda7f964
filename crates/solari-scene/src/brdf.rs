//! The material BRDF, CPU twin of `shaders/brdf.wesl`.
//!
//! A Lambert diffuse layer under a GGX specular layer:
//!
//! - specular: GGX distribution, height-correlated Smith visibility, Schlick Fresnel, plus
//!   Kulla–Conty multiple-scattering compensation (reciprocal, and exactly energy-preserving
//!   for a white metal up to the accuracy of the [`EnergyTable`]);
//! - diffuse: `base_color × (1 − metallic) / π`, weighted by `(1 − F(n·l))(1 − F(n·v))` for
//!   the two crossings of the specular layer (Solari 0.19's layering, which is reciprocal);
//! - a perfect mirror (a delta lobe) below [`MIRROR_ROUGHNESS`], with an infinite pdf that
//!   [`balance_heuristic`] handles.
//!
//! Everything works in tangent space: the normal is +z, `wo` points towards the viewer (or the
//! previous vertex), `wi` towards the light (or the next vertex), both unit length.
//! [`eval`] returns the BRDF times `cos θi` (the cosine lives inside the BRDF, so the mirror
//! needs no special case in callers).
//!
//! Sampling picks a lobe with the Fresnel-weighted energy at `wo` (Solari 0.19), then samples
//! the cosine hemisphere or the GGX distribution of visible normals with Eto and Tokuyoshi's
//! bounded VNDF method (2023). Samples below the surface are rejected (`None`).

// `!(x > 0.0)` is deliberate throughout: it rejects NaN along with non-positive values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use std::sync::OnceLock;

/// Perceptual roughness below which a surface is a perfect mirror. At this roughness GGX's
/// peak density is already ~10⁶, so the mirror is visually identical and numerically safe.
pub const MIRROR_ROUGHNESS: f32 = 0.02;

/// The BRDF inputs of a surface after texture sampling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrdfMaterial {
    /// Linear base colour.
    pub base_color: Vec3,
    /// Metallic factor in \[0, 1\].
    pub metallic: f32,
    /// Perceptual roughness in \[0, 1\] (GGX alpha is its square).
    pub roughness: f32,
    /// Specular colour at normal incidence for the non-metal part.
    pub dielectric_f0: Vec3,
    /// Reflectance at grazing angles for the non-metal part (`KHR_materials_specular`'s
    /// factor); with `dielectric_f0` zero, zero makes the non-metal part exactly Lambertian.
    pub dielectric_f90: f32,
}

impl BrdfMaterial {
    /// Inputs clamped to their valid ranges, non-finite values replaced by defaults, so the
    /// BRDF never sees a value that would give NaN.
    pub fn sanitized(self) -> Self {
        let unit = |x: f32, d: f32| if x.is_finite() { x.clamp(0.0, 1.0) } else { d };
        let unit3 = |v: Vec3, d: f32| Vec3::new(unit(v.x, d), unit(v.y, d), unit(v.z, d));
        Self {
            base_color: unit3(self.base_color, 0.0),
            metallic: unit(self.metallic, 0.0),
            roughness: unit(self.roughness, 1.0),
            dielectric_f0: unit3(self.dielectric_f0, 0.04),
            dielectric_f90: unit(self.dielectric_f90, 1.0),
        }
    }

    /// Specular colour at normal incidence.
    pub fn f0(&self) -> Vec3 {
        self.dielectric_f0.lerp(self.base_color, self.metallic)
    }

    /// Reflectance at grazing angles (1 for metals).
    pub fn f90(&self) -> f32 {
        self.dielectric_f90 + (1.0 - self.dielectric_f90) * self.metallic
    }

    /// Fresnel reflectance of this material at `cos` from the normal (or half vector).
    pub fn fresnel(&self, cos: f32) -> Vec3 {
        fresnel(self.f0(), self.f90(), cos)
    }

    /// Diffuse albedo (metals have none).
    pub fn diffuse_color(&self) -> Vec3 {
        self.base_color * (1.0 - self.metallic)
    }

    /// GGX alpha.
    pub fn alpha(&self) -> f32 {
        self.roughness * self.roughness
    }

    /// Whether the specular lobe is the perfect mirror.
    pub fn is_mirror(&self) -> bool {
        self.roughness < MIRROR_ROUGHNESS
    }
}

/// Schlick's Fresnel approximation between `f0` at normal incidence and `f90` at grazing.
pub fn fresnel(f0: Vec3, f90: f32, cos: f32) -> Vec3 {
    let m = (1.0 - cos.clamp(0.0, 1.0)).powi(5);
    f0 + (Vec3::splat(f90) - f0) * m
}

/// Rec. 709 luminance.
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// GGX normal distribution for the unit half vector `h` (tangent space).
///
/// Written with sin²θ from `h.xy` rather than `1 − cos²θ`: near a sharp lobe's peak `1 − cos θ`
/// is a few float ulps, and the usual form loses all precision there (pdfs off by 20% at
/// roughness 0.02 in f32).
pub fn d_ggx(alpha: f32, h: Vec3) -> f32 {
    let a2 = alpha * alpha;
    let sin2 = h.x * h.x + h.y * h.y;
    let cos2 = h.z * h.z;
    let d = sin2 + a2 * cos2;
    if h.z > 0.0 && d > 0.0 {
        a2 / (PI * d * d)
    } else {
        0.0
    }
}

/// Height-correlated Smith visibility, G₂ / (4 cos θo cos θi).
pub fn v_smith_ggx_correlated(alpha: f32, cos_o: f32, cos_i: f32) -> f32 {
    let a2 = alpha * alpha;
    let lo = cos_i * (cos_o * cos_o * (1.0 - a2) + a2).sqrt();
    let li = cos_o * (cos_i * cos_i * (1.0 - a2) + a2).sqrt();
    let denom = lo + li;
    if denom > 0.0 { 0.5 / denom } else { 0.0 }
}

/// Single-scattering GGX times `cos θi`, with Fresnel one: what [`EnergyTable`] integrates.
fn ggx_single(alpha: f32, wo: Vec3, wi: Vec3) -> f32 {
    let h = (wo + wi).normalize_or_zero();
    d_ggx(alpha, h) * v_smith_ggx_correlated(alpha, wo.z, wi.z) * wi.z
}

/// The lobe a sample came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lobe {
    /// Lambert diffuse.
    Diffuse,
    /// GGX specular.
    Specular,
    /// The perfect mirror (delta distribution).
    Mirror,
}

/// A sampled direction.
#[derive(Clone, Copy, Debug)]
pub struct BrdfSample {
    /// The sampled direction (tangent space).
    pub wi: Vec3,
    /// BRDF × cos θi / pdf: what the path throughput is multiplied by.
    pub weight: Vec3,
    /// Solid-angle pdf of the whole sampling routine in `wi`; infinite for the mirror.
    pub pdf: f32,
    /// Which lobe produced it.
    pub lobe: Lobe,
}

/// Probability of choosing the diffuse lobe, from the Fresnel-weighted energy at `wo`.
pub fn diffuse_probability(m: &BrdfMaterial, cos_o: f32) -> f32 {
    let f = luminance(m.fresnel(cos_o));
    ((1.0 - f) * (1.0 - m.metallic)).clamp(0.0, 1.0)
}

/// Diffuse lobe × cos θi.
pub fn eval_diffuse(m: &BrdfMaterial, wo: Vec3, wi: Vec3) -> Vec3 {
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return Vec3::ZERO;
    }
    let layering = (Vec3::ONE - m.fresnel(wi.z)) * (Vec3::ONE - m.fresnel(wo.z));
    m.diffuse_color() / PI * layering * wi.z
}

/// Specular lobe × cos θi for non-delta directions (zero for the mirror, whose reflection is
/// only reached by sampling).
pub fn eval_specular(m: &BrdfMaterial, wo: Vec3, wi: Vec3) -> Vec3 {
    if !(wo.z > 0.0 && wi.z > 0.0) || m.is_mirror() {
        return Vec3::ZERO;
    }
    let alpha = m.alpha();
    let h = (wo + wi).normalize_or_zero();
    let single =
        d_ggx(alpha, h) * v_smith_ggx_correlated(alpha, wo.z, wi.z) * m.fresnel(wi.dot(h)) * wi.z;
    single + multiple_scattering(alpha, m.f0(), m.f90(), wo.z, wi.z) * wi.z
}

/// Kulla–Conty multiple-scattering lobe (without the cosine), tinted by the average Fresnel.
fn multiple_scattering(alpha: f32, f0: Vec3, f90: f32, cos_o: f32, cos_i: f32) -> Vec3 {
    let table = energy_table();
    let e_avg = table.e_avg(alpha);
    if 1.0 - e_avg < 1e-6 {
        return Vec3::ZERO;
    }
    let f_ms = (1.0 - table.e(cos_o, alpha)) * (1.0 - table.e(cos_i, alpha)) / (PI * (1.0 - e_avg));
    // Average Schlick Fresnel over the hemisphere: F0 + (F90 − F0) / 21.
    let f_avg = f0 + (Vec3::splat(f90) - f0) / 21.0;
    let tint = f_avg * f_avg * e_avg / (Vec3::ONE - f_avg * (1.0 - e_avg));
    tint * f_ms
}

/// The whole BRDF × cos θi (diffuse + specular, no delta part).
pub fn eval(m: &BrdfMaterial, wo: Vec3, wi: Vec3) -> Vec3 {
    eval_diffuse(m, wo, wi) + eval_specular(m, wo, wi)
}

/// Solid-angle pdf of [`sample`] producing `wi` (the mirror's delta part excluded).
pub fn pdf(m: &BrdfMaterial, wo: Vec3, wi: Vec3) -> f32 {
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return 0.0;
    }
    let pd = diffuse_probability(m, wo.z);
    let mut p = pd * wi.z / PI;
    if !m.is_mirror() {
        p += (1.0 - pd) * vndf_pdf(wo, wi, m.alpha());
    }
    p
}

/// Samples a direction from `u` (three uniform numbers in \[0, 1)). `None` for a rejected
/// sample (below the surface, or `wo` itself below it); the caller ends the path there,
/// which keeps the estimator unbiased since the BRDF is zero below the surface.
pub fn sample(m: &BrdfMaterial, wo: Vec3, u: [f32; 3]) -> Option<BrdfSample> {
    if !(wo.z > 0.0) {
        return None;
    }
    let pd = diffuse_probability(m, wo.z);
    if u[0] < pd {
        let wi = sample_cosine_hemisphere(Vec2::new(u[1], u[2]));
        return finish(m, wo, wi, Lobe::Diffuse);
    }
    if m.is_mirror() {
        let wi = Vec3::new(-wo.x, -wo.y, wo.z);
        // The delta lobe's BRDF × cos / pdf is F; divided by the lobe's selection probability.
        let weight = m.fresnel(wo.z) / (1.0 - pd);
        return Some(BrdfSample {
            wi,
            weight,
            pdf: f32::INFINITY,
            lobe: Lobe::Mirror,
        });
    }
    let wi = sample_vndf(wo, m.alpha(), Vec2::new(u[1], u[2]));
    finish(m, wo, wi, Lobe::Specular)
}

/// Samples the specular lobe alone from `u` (two uniform numbers), for passes that own that
/// lobe (specular GI: the diffuse lobe's indirect light is ReSTIR GI's). The weight is
/// [`eval_specular`] × cos / pdf with the bounded-VNDF pdf, or the Fresnel term for the mirror
/// (pdf infinite). `None` below the surface, like [`sample`]. WGSL twin:
/// `brdf_sample_specular`.
pub fn sample_specular(m: &BrdfMaterial, wo: Vec3, u: [f32; 2]) -> Option<BrdfSample> {
    if !(wo.z > 0.0) {
        return None;
    }
    if m.is_mirror() {
        return Some(BrdfSample {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight: m.fresnel(wo.z),
            pdf: f32::INFINITY,
            lobe: Lobe::Mirror,
        });
    }
    let wi = sample_vndf(wo, m.alpha(), Vec2::new(u[0], u[1]));
    if !(wi.z > 0.0) {
        return None;
    }
    let p = vndf_pdf(wo, wi, m.alpha());
    weigh(wi, p, eval_specular(m, wo, wi), Lobe::Specular)
}

fn finish(m: &BrdfMaterial, wo: Vec3, wi: Vec3, lobe: Lobe) -> Option<BrdfSample> {
    // Rejects NaN too.
    if !(wi.z > 0.0) {
        return None;
    }
    weigh(wi, pdf(m, wo, wi), eval(m, wo, wi), lobe)
}

/// The sample in direction `wi` of pdf `p` and BRDF × cos `f`: `None` where the pdf or the
/// weight `f / p` is not positive and finite.
fn weigh(wi: Vec3, p: f32, f: Vec3, lobe: Lobe) -> Option<BrdfSample> {
    if !(p > 0.0 && p.is_finite()) {
        return None;
    }
    let weight = f / p;
    weight.is_finite().then_some(BrdfSample {
        wi,
        weight,
        pdf: p,
        lobe,
    })
}

/// Tangent and bitangent completing the unit vector `n` to a right-handed orthonormal basis
/// (Duff et al. 2017). WGSL twin: `frame::orthonormal_basis` (columns tangent, bitangent, n).
pub fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        Vec3::new(b, s + n.y * n.y * a, -n.y),
    )
}

/// Cosine-weighted direction about +z (pdf cos θ / π), by Malley's method.
pub fn sample_cosine_hemisphere(u: Vec2) -> Vec3 {
    let r = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u.x).max(0.0).sqrt())
}

/// Bounded VNDF sampling of the GGX reflection (Eto & Tokuyoshi 2023): samples the visible
/// normals only from the spherical cap that can reflect above the horizon, then reflects `wo`.
/// The result can still point below the surface; callers reject it.
pub fn sample_vndf(wo: Vec3, alpha: f32, u: Vec2) -> Vec3 {
    // Stretch to the unit-roughness configuration.
    let v = Vec3::new(wo.x * alpha, wo.y * alpha, wo.z).normalize();
    let phi = 2.0 * PI * u.x;
    let bound = vndf_cap_bound(wo, alpha, v.z);
    let z = (1.0 - u.y) * (1.0 + bound) - bound;
    let sin_theta = (1.0 - z * z).max(0.0).sqrt();
    let c = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), z);
    let h_std = v + c;
    let h = Vec3::new(h_std.x * alpha, h_std.y * alpha, h_std.z).normalize();
    2.0 * wo.dot(h) * h - wo
}

/// The cap's lower bound on z in the unit-roughness space: k·v.z for views above the surface.
fn vndf_cap_bound(wo: Vec3, alpha: f32, v_z: f32) -> f32 {
    if wo.z > 0.0 {
        let s = 1.0 + Vec2::new(wo.x, wo.y).length();
        let (a2, s2) = (alpha * alpha, s * s);
        let k = (1.0 - a2) * s2 / (s2 + a2 * wo.z * wo.z);
        k * v_z
    } else {
        v_z
    }
}

/// Solid-angle pdf of [`sample_vndf`] returning `wi`, exact for `wi` above the surface (below
/// it the bounded cap has already removed some normals; those samples are rejected anyway).
pub fn vndf_pdf(wo: Vec3, wi: Vec3, alpha: f32) -> f32 {
    let h = (wo + wi).normalize_or_zero();
    let ndf = d_ggx(alpha, h);
    let a = Vec2::new(wo.x, wo.y) * alpha;
    let len2 = a.length_squared();
    let t = (len2 + wo.z * wo.z).sqrt();
    if wo.z >= 0.0 {
        let s = 1.0 + Vec2::new(wo.x, wo.y).length();
        let (a2, s2) = (alpha * alpha, s * s);
        let k = (1.0 - a2) * s2 / (s2 + a2 * wo.z * wo.z);
        let p = ndf / (2.0 * (k * wo.z + t));
        if p.is_finite() { p } else { 0.0 }
    } else {
        let p = ndf * (t - wo.z) / (2.0 * len2);
        if p.is_finite() { p } else { 0.0 }
    }
}

/// Balance-heuristic MIS weight of a technique with pdf `f` against one with pdf `g`, correct
/// for infinite pdfs (a mirror's): weight 1 when only `f` is infinite, 0 when only `g` is.
pub fn balance_heuristic(f: f32, g: f32) -> f32 {
    if !(f > 0.0) {
        return 0.0;
    }
    let w = 1.0 / (1.0 + g / f);
    if w.is_nan() { 0.5 } else { w.clamp(0.0, 1.0) }
}

/// Samples per axis of the energy table.
pub const ENERGY_TABLE_SIZE: usize = 32;

/// Directional albedo `E(cos θo, roughness)` of single-scattering GGX with Fresnel one, and its
/// cosine-weighted average `E_avg(roughness)`, for the multiple-scattering lobe.
///
/// Nodes are uniform in cos θo and in perceptual roughness (\[0, 1\] each), interpolated
/// bilinearly. `E_avg` is the exact integral of that interpolant, so a white metal's albedo
/// equals the true `E` plus `1 − E_table` at every angle: the only energy error left is the
/// table's own error, which the white furnace test bounds.
#[derive(Clone, Debug)]
pub struct EnergyTable {
    /// `e[r * N + c]`: roughness node r, cosine node c.
    pub e: Vec<f32>,
    /// `e_avg[r]`.
    pub e_avg: Vec<f32>,
}

/// The process-wide table, computed on first use: 0.14 s single-threaded in a release build
/// on the 2-core development machine.
pub fn energy_table() -> &'static EnergyTable {
    static TABLE: OnceLock<EnergyTable> = OnceLock::new();
    TABLE.get_or_init(|| EnergyTable::compute(ENERGY_TABLE_SIZE, 64))
}

impl EnergyTable {
    /// Integrates the table with `strata`² stratified VNDF samples per node (deterministic).
    pub fn compute(n: usize, strata: usize) -> Self {
        let mut e = vec![0.0; n * n];
        let mut e_avg = vec![0.0; n];
        for r in 0..n {
            let roughness = r as f32 / (n - 1) as f32;
            let alpha = roughness * roughness;
            for c in 0..n {
                let cos_o = (c as f32 / (n - 1) as f32).max(1e-3);
                e[r * n + c] = if roughness < MIRROR_ROUGHNESS {
                    1.0
                } else {
                    albedo_single(alpha, cos_o, strata)
                };
            }
            // 2 ∫₀¹ E(μ) μ dμ of the piecewise-linear interpolant, exactly.
            let h = 1.0 / (n - 1) as f64;
            let mut sum = 0.0f64;
            for c in 0..n - 1 {
                let (a, b) = (e[r * n + c] as f64, e[r * n + c + 1] as f64);
                let m0 = c as f64 * h;
                sum += h * (a * m0 + (b - a) * m0 / 2.0 + a * h / 2.0 + (b - a) * h / 3.0);
            }
            e_avg[r] = (2.0 * sum) as f32;
        }
        Self { e, e_avg }
    }

    fn size(&self) -> usize {
        self.e_avg.len()
    }

    fn roughness_coord(&self, alpha: f32) -> (usize, f32) {
        let n = self.size();
        let x = alpha.max(0.0).sqrt().clamp(0.0, 1.0) * (n - 1) as f32;
        let i = (x.floor() as usize).min(n - 2);
        (i, x - i as f32)
    }

    /// `E(cos θo)` at GGX `alpha`, bilinearly interpolated.
    pub fn e(&self, cos_o: f32, alpha: f32) -> f32 {
        let n = self.size();
        let (r, fr) = self.roughness_coord(alpha);
        let x = cos_o.clamp(0.0, 1.0) * (n - 1) as f32;
        let c = (x.floor() as usize).min(n - 2);
        let fc = x - c as f32;
        let at = |r: usize, c: usize| self.e[r * n + c];
        let lo = at(r, c) + (at(r, c + 1) - at(r, c)) * fc;
        let hi = at(r + 1, c) + (at(r + 1, c + 1) - at(r + 1, c)) * fc;
        lo + (hi - lo) * fr
    }

    /// `E_avg` at GGX `alpha`, linearly interpolated.
    pub fn e_avg(&self, alpha: f32) -> f32 {
        let (r, fr) = self.roughness_coord(alpha);
        self.e_avg[r] + (self.e_avg[r + 1] - self.e_avg[r]) * fr
    }
}

/// ∫ single-scattering GGX (F = 1) × cos θi dωi by stratified bounded-VNDF sampling.
fn albedo_single(alpha: f32, cos_o: f32, strata: usize) -> f32 {
    let wo = Vec3::new((1.0 - cos_o * cos_o).max(0.0).sqrt(), 0.0, cos_o);
    let mut sum = 0.0f64;
    for i in 0..strata {
        for j in 0..strata {
            let u = Vec2::new(
                (i as f32 + 0.5) / strata as f32,
                (j as f32 + 0.5) / strata as f32,
            );
            let wi = sample_vndf(wo, alpha, u);
            if wi.z > 0.0 {
                let p = vndf_pdf(wo, wi, alpha);
                if p > 0.0 {
                    sum += (ggx_single(alpha, wo, wi) / p) as f64;
                }
            }
        }
    }
    (sum / (strata * strata) as f64) as f32
}
