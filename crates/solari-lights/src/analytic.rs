//! Closed forms that light sampling and the reference tracer are tested against.

use glam::Vec3;

/// Irradiance at `x` on a surface with unit normal `n` from a flat convex polygon of uniform
/// radiance `radiance` that emits from its front face (counter-clockwise corners, as the
/// light list treats one-sided emitters): Lambert's formula E = L/2 Σ θᵢ (n · ĉᵢ), where θᵢ
/// is the angle each edge subtends at `x` and ĉᵢ the unit normal of the plane through `x` and
/// that edge. Zero when `x` is behind the polygon. The polygon must lie wholly above the
/// surface at `x`. Computed in f64 with θ from atan2: acos of a dot product near 1 loses the
/// small angles that the edges of fine meshes subtend.
///
/// ```
/// use glam::Vec3;
/// // A small square 10 m overhead, facing down: about L · A / d².
/// let h = 0.05;
/// let square = [
///     Vec3::new(-h, 10.0, -h),
///     Vec3::new(h, 10.0, -h),
///     Vec3::new(h, 10.0, h),
///     Vec3::new(-h, 10.0, h),
/// ];
/// let e = solari_lights::analytic::polygon_irradiance(Vec3::ZERO, Vec3::Y, &square, 2.0);
/// assert!((e / (2.0 * 0.01 / 100.0) - 1.0).abs() < 1e-4);
/// ```
pub fn polygon_irradiance(x: Vec3, n: Vec3, polygon: &[Vec3], radiance: f64) -> f64 {
    if polygon.len() < 3 {
        return 0.0;
    }
    let (x, n) = (x.as_dvec3(), n.as_dvec3());
    let p: Vec<_> = polygon.iter().map(|v| v.as_dvec3()).collect();
    if (p[1] - p[0]).cross(p[2] - p[0]).dot(x - p[0]) <= 0.0 {
        return 0.0;
    }
    let mut sum = 0.0;
    for i in 0..p.len() {
        let a = (p[i] - x).normalize();
        let b = (p[(i + 1) % p.len()] - x).normalize();
        let c = a.cross(b);
        sum += c.length().atan2(a.dot(b)) * n.dot(c.normalize());
    }
    0.5 * radiance * sum.abs()
}
