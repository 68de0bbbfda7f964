//! Ray differentials of primary rays (Igehy 1999), the traced G-buffer's texture footprint:
//! CPU twin of `hit.wesl`'s `triangle_barycentric_differentials`, tested against the GPU and
//! against offset rays intersected directly (`tests/ray_differentials.rs`).

use glam::{Vec2, Vec3};

/// How a hit's barycentrics (the weights of corners 1 and 2) change per pixel, for each of
/// `ddir` (the ray direction's change per pixel right and down), on a triangle of world-space
/// edges `e1`, `e2` hit at parameter `t` along `dir` from a pinhole (all rays share the
/// origin). Zero for an edge-on or degenerate triangle (the G-buffer then reads mip 0).
pub fn barycentric_differentials(
    e1: Vec3,
    e2: Vec3,
    t: f32,
    dir: Vec3,
    ddir: [Vec3; 2],
) -> [Vec2; 2] {
    let n = e1.cross(e2);
    let nn = n.dot(n);
    let dn = dir.dot(n);
    // NaN counts as degenerate, as the WGSL's `!(nn > 0.0)` does.
    if nn.is_nan() || nn <= 0.0 || dn == 0.0 {
        return [Vec2::ZERO; 2];
    }
    ddir.map(|d| {
        let dp = t * (d - dir * (d.dot(n) / dn));
        Vec2::new(dp.cross(e2).dot(n), e1.cross(dp).dot(n)) / nn
    })
}
