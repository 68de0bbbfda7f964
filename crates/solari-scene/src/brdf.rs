//! The material BRDF, CPU twin of `shaders/brdf.wesl`.
//!
//! Two models, one per scene ([`BrdfModel`], `GpuSceneOptions::brdf`, the CLI's `--brdf`),
//! sharing the specular lobe's shape: GGX distribution, height-correlated Smith visibility,
//! Schlick Fresnel, and a perfect mirror (a delta lobe) below [`MIRROR_ROUGHNESS`], with an
//! infinite pdf that [`balance_heuristic`] handles.
//!
//! - [`BrdfModel::Layered`] (the default) keeps its energy. The specular lobe adds Kulla–Conty
//!   multiple scattering (reciprocal; a white metal reflects everything up to the accuracy of
//!   the [`EnergyTable`]). The diffuse base under the dielectric coating is
//!   `c (1 − E_d(μo)) (1 − E_d(μi)) / (π (1 − E_d,avg))` with `c = base_color × (1 − metallic)`
//!   and `E_d(μ)` the coating's directional albedo (its Fresnel included: [`coating_albedo`]),
//!   so the light the coating does not reflect enters the base and a white dielectric
//!   reflects exactly what arrives: directional albedo `E_s(μo) + c (1 − E_d(μo))`
//!   ([`layered_albedo`]), 1 for a white base at every roughness and reflectance. The seeds'
//!   layering (Solari 0.19: `c/π (1 − F(μo)) (1 − F(μi))`) lost 8–11% of the light at each
//!   bounce off white dielectrics, because it drops what the rough coating scatters back
//!   into the base.
//! - [`BrdfModel::GltfSpec`] is the glTF 2.0 specification's Appendix B (with
//!   `KHR_materials_specular`) as written, for comparisons with other glTF renderers: single
//!   scattering with the separable Smith term the specification writes, and the diffuse base
//!   weighted by `1 − max(F_d(v·h))` at the half vector. It is not energy conserving: a white
//!   dielectric reflects 0.974 of what arrives at roughness 1, and up to 1.72 times it at
//!   grazing angles when smooth (87°; the base's weight at the half vector ignores what the
//!   coating reflected at the view angle).
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

/// Which BRDF a scene is shaded with (module docs). One setting for the reference tracer and
/// every real-time pass: `GpuSceneOptions::brdf` on the GPU, [`BrdfMaterial::model`] here.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BrdfModel {
    /// Energy-conserving layering of a Lambert base under the GGX coating (the default: a
    /// white furnace reads 1 at every roughness, and bounced light is not lost).
    #[default]
    Layered,
    /// The glTF 2.0 specification's Appendix B, exactly (comparisons with other renderers).
    GltfSpec,
}

impl BrdfModel {
    /// Every model, the default first.
    pub const ALL: [BrdfModel; 2] = [BrdfModel::Layered, BrdfModel::GltfSpec];

    /// The name on the command line: `layered` or `gltf-spec`.
    pub fn name(self) -> &'static str {
        match self {
            BrdfModel::Layered => "layered",
            BrdfModel::GltfSpec => "gltf-spec",
        }
    }

    /// The model named `name` ([`BrdfModel::name`]).
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// The value `scene_info.brdf_model` carries to the shaders (`BRDF_MODEL_*` in
    /// `brdf.wesl`).
    pub fn gpu_id(self) -> u32 {
        match self {
            BrdfModel::Layered => 0,
            BrdfModel::GltfSpec => 1,
        }
    }
}

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
    /// The scene's BRDF model.
    pub model: BrdfModel,
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
            model: self.model,
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

    /// Fresnel reflectance of the dielectric coating alone (over the diffuse base).
    pub fn coating_fresnel(&self, cos: f32) -> Vec3 {
        fresnel(self.dielectric_f0, self.dielectric_f90, cos)
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

/// Separable Smith visibility, G₁(o) G₁(i) / (4 cos θo cos θi): the glTF specification's
/// Appendix B form ([`BrdfModel::GltfSpec`]).
pub fn v_smith_ggx_separable(alpha: f32, cos_o: f32, cos_i: f32) -> f32 {
    let a2 = alpha * alpha;
    let g = |c: f32| c + (a2 + (1.0 - a2) * c * c).sqrt();
    let denom = g(cos_o) * g(cos_i);
    if denom > 0.0 { 1.0 / denom } else { 0.0 }
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

/// Diffuse lobe × cos θi: the base under the coating, as the model layers it.
pub fn eval_diffuse(m: &BrdfMaterial, wo: Vec3, wi: Vec3) -> Vec3 {
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return Vec3::ZERO;
    }
    let layering = match m.model {
        BrdfModel::Layered => {
            let avg = Vec3::ONE - coating_albedo_avg(m);
            let through =
                (Vec3::ONE - coating_albedo(m, wo.z)) * (Vec3::ONE - coating_albedo(m, wi.z));
            // A coating that reflects everything (E_d,avg = 1) lets nothing reach the base.
            Vec3::select(
                avg.cmpgt(Vec3::splat(1e-6)),
                through / avg.max(Vec3::splat(1e-6)),
                Vec3::ZERO,
            )
        }
        BrdfModel::GltfSpec => {
            let h = (wo + wi).normalize_or_zero();
            Vec3::splat(1.0 - m.coating_fresnel(wi.dot(h)).max_element())
        }
    };
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
    if m.model == BrdfModel::GltfSpec {
        let v = v_smith_ggx_separable(alpha, wo.z, wi.z);
        return d_ggx(alpha, h) * v * m.fresnel(wi.dot(h)) * wi.z;
    }
    let single =
        d_ggx(alpha, h) * v_smith_ggx_correlated(alpha, wo.z, wi.z) * m.fresnel(wi.dot(h)) * wi.z;
    let table = energy_table();
    let e_avg = table.e_avg(alpha);
    if 1.0 - e_avg < 1e-6 {
        return single;
    }
    let f_ms = (1.0 - table.e(wo.z, alpha)) * (1.0 - table.e(wi.z, alpha)) / (PI * (1.0 - e_avg));
    single + multiple_scattering_tint(alpha, m.f0(), m.f90()) * f_ms * wi.z
}

/// Kulla–Conty's tint of the multiple-scattering lobe for Fresnel `f0`, `f90` (zero where the
/// lobe scatters once only, E_avg = 1): the lobe is this × `(1 − E(μo)) (1 − E(μi)) / (π (1 −
/// E_avg))`, and its albedo this × `(1 − E(μo))`.
fn multiple_scattering_tint(alpha: f32, f0: Vec3, f90: f32) -> Vec3 {
    let e_avg = energy_table().e_avg(alpha);
    if 1.0 - e_avg < 1e-6 {
        return Vec3::ZERO;
    }
    // Average Schlick Fresnel over the hemisphere: F0 + (F90 − F0) / 21.
    let f_avg = f0 + (Vec3::splat(f90) - f0) / 21.0;
    f_avg * f_avg * e_avg / (Vec3::ONE - f_avg * (1.0 - e_avg))
}

/// Directional albedo `∫ f_s cos dωi` of a GGX lobe (its multiple scattering included) with
/// Schlick Fresnel `f0`, `f90`, from the [`EnergyTable`]; exact (the Fresnel at `cos_o`) for
/// the mirror.
fn lobe_albedo(alpha: f32, mirror: bool, f0: Vec3, f90: f32, cos_o: f32) -> Vec3 {
    if mirror {
        return fresnel(f0, f90, cos_o);
    }
    split_albedo(alpha, f0, f90, energy_table().e_split(cos_o, alpha))
}

/// A GGX lobe's albedo from the table's Fresnel split `(A, B)` (at one angle, or averaged):
/// `f0 A + f90 B` for single scattering, plus the multiple-scattering tint over `1 − A − B`.
fn split_albedo(alpha: f32, f0: Vec3, f90: f32, (a, b): (f32, f32)) -> Vec3 {
    f0 * a + Vec3::splat(f90 * b) + multiple_scattering_tint(alpha, f0, f90) * (1.0 - a - b)
}

/// The coating's directional albedo `E_d(μ)`: the dielectric specular lobe (Fresnel
/// `dielectric_f0`, `dielectric_f90`, multiple scattering included) integrated over the
/// hemisphere. What it does not reflect enters the diffuse base ([`BrdfModel::Layered`]).
pub fn coating_albedo(m: &BrdfMaterial, cos: f32) -> Vec3 {
    lobe_albedo(
        m.alpha(),
        m.is_mirror(),
        m.dielectric_f0,
        m.dielectric_f90,
        cos,
    )
}

/// `E_d,avg = 2 ∫ E_d(μ) μ dμ`, the coating's cosine-weighted average albedo.
pub fn coating_albedo_avg(m: &BrdfMaterial) -> Vec3 {
    let (f0, f90) = (m.dielectric_f0, m.dielectric_f90);
    if m.is_mirror() {
        return f0 + (Vec3::splat(f90) - f0) / 21.0;
    }
    let alpha = m.alpha();
    split_albedo(alpha, f0, f90, energy_table().e_split_avg(alpha))
}

/// The directional albedo `∫ f cos dωi` that [`BrdfModel::Layered`] is built to have (delta
/// lobe included): the specular lobe's, plus `c (1 − E_d(μo))` for the diffuse base, with `c =
/// base_color × (1 − metallic)`. 1 for a white dielectric; the white furnace tests hold the
/// BRDF to it. Also what the surface reflects toward `cos_o` under uniform light (by
/// reciprocity), which is how the world cache reflects its irradiance (WGSL `brdf_albedo`),
/// for both models: [`BrdfModel::GltfSpec`] has no closed form, and this approximates it.
pub fn layered_albedo(m: &BrdfMaterial, cos_o: f32) -> Vec3 {
    let specular = lobe_albedo(m.alpha(), m.is_mirror(), m.f0(), m.f90(), cos_o);
    specular + m.diffuse_color() * (Vec3::ONE - coating_albedo(m, cos_o))
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

/// Directional albedo of single-scattering GGX split by Schlick's Fresnel weights, and its
/// cosine-weighted averages, for the multiple-scattering lobe and the layering.
///
/// With `F = f0 (1 − w) + f90 w`, `w = (1 − v·h)⁵`, the albedo of a lobe is `f0 A + f90 B`:
/// `A(μ, r) = ∫ D V (1 − w) cos dωi`, `B(μ, r) = ∫ D V w cos dωi`, and `E = A + B` is the
/// Fresnel-one albedo. Nodes are uniform in √cos θo and in √perceptual roughness (\[0, 1\]
/// each: dense at grazing angles and smooth lobes, where the albedo changes fastest; 0.31%
/// worst white-furnace error at 32 × 32, against 3.7% with uniform nodes), interpolated
/// linearly in cos θo and in √roughness. The averages are exact integrals of that
/// interpolant, so the lobes built on it integrate to what the layering assumes, and the only
/// energy error left is the table's own (the white furnace tests bound it).
#[derive(Clone, Debug)]
pub struct EnergyTable {
    /// `a[r * N + c]`: roughness node r, cosine node c.
    pub a: Vec<f32>,
    /// `b[r * N + c]`.
    pub b: Vec<f32>,
    /// `2 ∫ A(μ) μ dμ` per roughness node.
    pub a_avg: Vec<f32>,
    /// `2 ∫ B(μ) μ dμ` per roughness node.
    pub b_avg: Vec<f32>,
}

/// The process-wide table, computed on first use.
pub fn energy_table() -> &'static EnergyTable {
    static TABLE: OnceLock<EnergyTable> = OnceLock::new();
    TABLE.get_or_init(|| EnergyTable::compute(ENERGY_TABLE_SIZE, 64))
}

/// The cosine of column `c` of `n`: nodes uniform in √μ, dense at grazing angles where the
/// albedo of a smooth lobe changes fastest.
fn cosine_node(c: usize, n: usize) -> f32 {
    let t = c as f32 / (n - 1) as f32;
    t * t
}

/// `2 ∫₀¹ f(μ) μ dμ` of the interpolant that is linear in μ between the nodes `values` at
/// [`cosine_node`]s, exactly.
fn cosine_average(values: &[f32]) -> f32 {
    let n = values.len();
    let mut sum = 0.0f64;
    for c in 0..n - 1 {
        let (m0, m1) = (cosine_node(c, n) as f64, cosine_node(c + 1, n) as f64);
        let (a, b) = (values[c] as f64, values[c + 1] as f64);
        // ∫ (a + (b − a)(μ − m0)/h) μ dμ over [m0, m1], h = m1 − m0.
        let h = m1 - m0;
        sum += h * (a * m0 + (b - a) * m0 / 2.0 + a * h / 2.0 + (b - a) * h / 3.0);
    }
    (2.0 * sum) as f32
}

impl EnergyTable {
    /// Integrates the table with `strata`² stratified VNDF samples per node (deterministic).
    /// The mirror row (roughness 0) holds the exact Fresnel weights.
    pub fn compute(n: usize, strata: usize) -> Self {
        let mut a = vec![0.0; n * n];
        let mut b = vec![0.0; n * n];
        for r in 0..n {
            let t = r as f32 / (n - 1) as f32;
            let roughness = t * t;
            let alpha = roughness * roughness;
            for c in 0..n {
                let cos_o = cosine_node(c, n);
                let (ac, bc) = if roughness < MIRROR_ROUGHNESS {
                    let w = (1.0 - cos_o).powi(5);
                    (1.0 - w, w)
                } else {
                    albedo_single(alpha, cos_o.max(1e-3), strata)
                };
                a[r * n + c] = ac;
                b[r * n + c] = bc;
            }
        }
        let avg = |t: &[f32]| {
            (0..n)
                .map(|r| cosine_average(&t[r * n..(r + 1) * n]))
                .collect()
        };
        Self {
            a_avg: avg(&a),
            b_avg: avg(&b),
            a,
            b,
        }
    }

    fn size(&self) -> usize {
        self.a_avg.len()
    }

    fn roughness_coord(&self, alpha: f32) -> (usize, f32) {
        let n = self.size();
        // Rows uniform in √roughness: dense where smooth lobes change fastest.
        let x = alpha.max(0.0).sqrt().sqrt().clamp(0.0, 1.0) * (n - 1) as f32;
        let i = (x.floor() as usize).min(n - 2);
        (i, x - i as f32)
    }

    /// `(A, B)` at `cos_o` and GGX `alpha`: linear in cos θo between columns and in
    /// √roughness between rows.
    pub fn e_split(&self, cos_o: f32, alpha: f32) -> (f32, f32) {
        let n = self.size();
        let (r, fr) = self.roughness_coord(alpha);
        // The column from √μ, the weight linear in μ (the interpolant the averages integrate).
        let mu = cos_o.clamp(0.0, 1.0);
        let c = ((mu.sqrt() * (n - 1) as f32).floor() as usize).min(n - 2);
        let (m0, m1) = (cosine_node(c, n), cosine_node(c + 1, n));
        let fc = ((mu - m0) / (m1 - m0)).clamp(0.0, 1.0);
        let lerp2 = |t: &[f32]| {
            let at = |r: usize, c: usize| t[r * n + c];
            let lo = at(r, c) + (at(r, c + 1) - at(r, c)) * fc;
            let hi = at(r + 1, c) + (at(r + 1, c + 1) - at(r + 1, c)) * fc;
            lo + (hi - lo) * fr
        };
        (lerp2(&self.a), lerp2(&self.b))
    }

    /// The Fresnel-one albedo `E = A + B` at `cos_o` and GGX `alpha`.
    pub fn e(&self, cos_o: f32, alpha: f32) -> f32 {
        let (a, b) = self.e_split(cos_o, alpha);
        a + b
    }

    /// `(A_avg, B_avg)` at GGX `alpha`, linearly interpolated.
    pub fn e_split_avg(&self, alpha: f32) -> (f32, f32) {
        let (r, fr) = self.roughness_coord(alpha);
        let lerp = |t: &[f32]| t[r] + (t[r + 1] - t[r]) * fr;
        (lerp(&self.a_avg), lerp(&self.b_avg))
    }

    /// `E_avg = A_avg + B_avg` at GGX `alpha`.
    pub fn e_avg(&self, alpha: f32) -> f32 {
        let (a, b) = self.e_split_avg(alpha);
        a + b
    }
}

/// `(A, B)`: ∫ single-scattering GGX × cos θi dωi with Fresnel weights `1 − w` and `w`, by
/// stratified bounded-VNDF sampling.
fn albedo_single(alpha: f32, cos_o: f32, strata: usize) -> (f32, f32) {
    let wo = Vec3::new((1.0 - cos_o * cos_o).max(0.0).sqrt(), 0.0, cos_o);
    let (mut a, mut b) = (0.0f64, 0.0f64);
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
                    let h = (wo + wi).normalize_or_zero();
                    let w = (1.0 - wi.dot(h).clamp(0.0, 1.0)).powi(5) as f64;
                    let f = (ggx_single(alpha, wo, wi) / p) as f64;
                    a += f * (1.0 - w);
                    b += f * w;
                }
            }
        }
    }
    let count = (strata * strata) as f64;
    ((a / count) as f32, (b / count) as f32)
}
