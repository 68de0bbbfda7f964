//! CPU reference tracer: the twin of the WGSL `trace_ray`, used by tests and tools.
// Negated comparisons are deliberate: they also reject NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
//!
//! It shares the triangle test ([`intersect_triangle`]) with the GPU code but not the
//! acceleration structure: a plain median-split binary BVH built here, so a traversal bug on
//! the GPU cannot hide behind the same bug on the CPU.

use crate::model::Scene;
use glam::{Mat4, Vec2, Vec3};

/// `trace_ray` flag: accept the first hit found instead of the closest (shadow rays).
pub const RAY_FLAG_TERMINATE_ON_FIRST_HIT: u32 = 0x4;
/// `trace_ray` flag: ignore triangles whose back faces the ray.
pub const RAY_FLAG_CULL_BACK_FACING: u32 = 0x10;

/// Tolerance on barycentric coordinates so that rays through a shared edge hit at least one
/// of its two triangles despite rounding (both may report a hit: a tie).
pub const BARYCENTRIC_EPSILON: f32 = 1e-6;

/// A closest-hit result, as the GPU returns it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// Ray parameter of the hit (`origin + t * direction`).
    pub t: f32,
    /// Instance index.
    pub instance: u32,
    /// Triangle index within the instance's mesh.
    pub primitive: u32,
    /// Barycentrics of the hit (weights of corners 1 and 2).
    pub barycentrics: Vec2,
    /// Whether the ray hit the front (counter-clockwise) face, in world space.
    pub front_face: bool,
}

/// A precomputed triangle: first corner and two edges, the form the GPU stores.
#[derive(Clone, Copy, Debug)]
pub struct EdgeTriangle {
    /// Corner 0.
    pub v0: Vec3,
    /// Corner 1 minus corner 0.
    pub e1: Vec3,
    /// Corner 2 minus corner 0.
    pub e2: Vec3,
}

impl EdgeTriangle {
    /// From three corners.
    pub fn new([a, b, c]: [Vec3; 3]) -> Self {
        Self {
            v0: a,
            e1: b - a,
            e2: c - a,
        }
    }
}

/// Möller–Trumbore with tolerant edges; returns `(t, u, v, det > 0)` for `t_min < t < t_max`.
/// The WGSL twin is `intersect_triangle` in `trace_common.wesl`.
pub fn intersect_triangle(
    tri: &EdgeTriangle,
    origin: Vec3,
    dir: Vec3,
    t_min: f32,
    t_max: f32,
) -> Option<(f32, f32, f32, bool)> {
    intersect_triangle_eps(tri, origin, dir, t_min, t_max, BARYCENTRIC_EPSILON)
}

/// [`intersect_triangle`] with a chosen barycentric tolerance (tests verify ties with a
/// looser one than the tracer uses).
pub fn intersect_triangle_eps(
    tri: &EdgeTriangle,
    origin: Vec3,
    dir: Vec3,
    t_min: f32,
    t_max: f32,
    eps: f32,
) -> Option<(f32, f32, f32, bool)> {
    let pvec = dir.cross(tri.e2);
    let det = tri.e1.dot(pvec);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv_det = 1.0 / det;
    let tvec = origin - tri.v0;
    let u = tvec.dot(pvec) * inv_det;
    if !(u >= -eps && u <= 1.0 + eps) {
        return None;
    }
    let qvec = tvec.cross(tri.e1);
    let v = dir.dot(qvec) * inv_det;
    if !(v >= -eps && u + v <= 1.0 + eps) {
        return None;
    }
    let t = tri.e2.dot(qvec) * inv_det;
    if !(t > t_min && t < t_max) {
        return None;
    }
    Some((t, u, v, det > 0.0))
}

#[derive(Clone, Copy)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    /// Leaf: first triangle; inner: left child (right child is `left + 1`).
    first: u32,
    /// Triangle count for leaves, 0 for inner nodes.
    count: u32,
}

/// A simple binary BVH over one mesh (or over instances).
struct BinaryBvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

impl BinaryBvh {
    fn build(bounds: &[(Vec3, Vec3)]) -> Self {
        // Pad every box a little: the triangle test accepts hits up to BARYCENTRIC_EPSILON
        // outside a triangle, which an exact box would cull.
        let bounds: Vec<(Vec3, Vec3)> = bounds
            .iter()
            .map(|&(lo, hi)| {
                let pad = (hi - lo).max_element() * 1e-5
                    + lo.abs().max(hi.abs()).max_element() * 1e-6
                    + 1e-30;
                (lo - Vec3::splat(pad), hi + Vec3::splat(pad))
            })
            .collect();
        let bounds = &bounds[..];
        let mut order: Vec<u32> = (0..bounds.len() as u32).collect();
        if bounds.is_empty() {
            return Self {
                nodes: Vec::new(),
                order,
            };
        }
        let mut nodes = vec![Node {
            lo: Vec3::ZERO,
            hi: Vec3::ZERO,
            first: 0,
            count: 0,
        }];
        let mut todo = vec![(0usize, 0usize, bounds.len())];
        while let Some((ni, start, end)) = todo.pop() {
            let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
            for &i in &order[start..end] {
                lo = lo.min(bounds[i as usize].0);
                hi = hi.max(bounds[i as usize].1);
            }
            if end - start <= 4 {
                nodes[ni] = Node {
                    lo,
                    hi,
                    first: start as u32,
                    count: (end - start) as u32,
                };
                continue;
            }
            let axis = (hi - lo).max_position();
            let mid = (start + end) / 2;
            let key = |i: &u32| {
                let (a, b) = bounds[*i as usize];
                (a + b)[axis]
            };
            order[start..end].select_nth_unstable_by(mid - start, |a, b| key(a).total_cmp(&key(b)));
            let left = nodes.len();
            nodes.push(Node {
                lo,
                hi,
                first: 0,
                count: 0,
            });
            nodes.push(Node {
                lo,
                hi,
                first: 0,
                count: 0,
            });
            nodes[ni] = Node {
                lo,
                hi,
                first: left as u32,
                count: 0,
            };
            todo.push((left, start, mid));
            todo.push((left + 1, mid, end));
        }
        Self { nodes, order }
    }

    /// Visits candidate leaves' items front to back-ish; `visit` returns the new `t_max`
    /// (or `None` to stop the traversal).
    fn traverse(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        mut t_max: f32,
        mut visit: impl FnMut(u32, f32) -> Option<f32>,
    ) {
        let inv = Vec3::ONE / dir;
        // An empty tree (a scene without instances, a mesh without triangles) has no root.
        let mut stack = if self.nodes.is_empty() {
            Vec::new()
        } else {
            vec![0usize]
        };
        while let Some(ni) = stack.pop() {
            let n = self.nodes[ni];
            let t0 = (n.lo - origin) * inv;
            let t1 = (n.hi - origin) * inv;
            // NaN (0 * inf) on an axis means the origin lies in the slab's plane: keep it.
            let near = t0
                .min(t1)
                .to_array()
                .iter()
                .fold(t_min, |a, &b| if b.is_nan() { a } else { a.max(b) });
            let far = t0
                .max(t1)
                .to_array()
                .iter()
                .fold(t_max, |a, &b| if b.is_nan() { a } else { a.min(b) });
            // Inclusive and slightly widened so grazing rays are never culled wrongly.
            if near > far * (1.0 + 4.0 * f32::EPSILON) + 1e-30 {
                continue;
            }
            if n.count == 0 {
                stack.push(n.first as usize);
                stack.push(n.first as usize + 1);
            } else {
                for &item in &self.order[n.first as usize..(n.first + n.count) as usize] {
                    match visit(item, t_max) {
                        Some(t) => t_max = t,
                        None => return,
                    }
                }
            }
        }
    }
}

/// Transforms a point by the 3×4 part of `m`.
fn xform_point(m: &Mat4, p: Vec3) -> Vec3 {
    m.transform_point3(p)
}

/// CPU reference tracer over a [`Scene`].
pub struct CpuTracer {
    meshes: Vec<(BinaryBvh, Vec<EdgeTriangle>)>,
    tlas: BinaryBvh,
    world_to_object: Vec<Mat4>,
    instance_mesh: Vec<u32>,
}

impl CpuTracer {
    /// Builds the reference structures for `scene`.
    pub fn new(scene: &Scene) -> Self {
        let meshes = scene
            .meshes
            .iter()
            .map(|m| {
                let tris: Vec<EdgeTriangle> = (0..m.triangle_count())
                    .map(|t| EdgeTriangle::new(m.triangle(t)))
                    .collect();
                let bounds: Vec<(Vec3, Vec3)> = (0..m.triangle_count())
                    .map(|t| {
                        let [a, b, c] = m.triangle(t);
                        (a.min(b).min(c), a.max(b).max(c))
                    })
                    .collect();
                (BinaryBvh::build(&bounds), tris)
            })
            .collect();
        let bounds: Vec<(Vec3, Vec3)> = scene
            .instances
            .iter()
            .map(|i| instance_bounds(scene, i))
            .collect();
        Self {
            meshes,
            tlas: BinaryBvh::build(&bounds),
            world_to_object: scene
                .instances
                .iter()
                .map(|i| i.transform.inverse())
                .collect(),
            instance_mesh: scene.instances.iter().map(|i| i.mesh).collect(),
        }
    }

    /// Closest hit (or, with [`RAY_FLAG_TERMINATE_ON_FIRST_HIT`], any hit) in `(t_min, t_max)`.
    pub fn trace(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
        flags: u32,
    ) -> Option<RayHit> {
        let mut best: Option<RayHit> = None;
        self.tlas
            .traverse(origin, dir, t_min, t_max, |inst, t_max_now| {
                let w2o = &self.world_to_object[inst as usize];
                let o = xform_point(w2o, origin);
                let d = w2o.transform_vector3(dir);
                let (bvh, tris) = &self.meshes[self.instance_mesh[inst as usize] as usize];
                let mut local_max = t_max_now;
                let mut stop = false;
                bvh.traverse(o, d, t_min, t_max_now, |tri, tm| {
                    if let Some((t, u, v, det_pos)) =
                        intersect_triangle(&tris[tri as usize], o, d, t_min, tm)
                    {
                        // Facing is the mesh's own winding (object space), glTF's rule: a
                        // mirroring transform reverses the world-space winding, and with it
                        // which winding counts as front, so a mirrored mesh's outside stays
                        // its front.
                        let front = det_pos;
                        if flags & RAY_FLAG_CULL_BACK_FACING != 0 && !front {
                            return Some(tm);
                        }
                        best = Some(RayHit {
                            t,
                            instance: inst,
                            primitive: tri,
                            barycentrics: Vec2::new(u, v),
                            front_face: front,
                        });
                        local_max = t;
                        if flags & RAY_FLAG_TERMINATE_ON_FIRST_HIT != 0 {
                            stop = true;
                            return None;
                        }
                        return Some(t);
                    }
                    Some(tm)
                });
                if stop { None } else { Some(local_max) }
            });
        best
    }

    /// Unit world-space normal of one triangle of one instance (`None` if out of range).
    pub fn normal(&self, instance: u32, primitive: u32) -> Option<Vec3> {
        let (_, tris) = &self.meshes[*self.instance_mesh.get(instance as usize)? as usize];
        let tri = tris.get(primitive as usize)?;
        let n_obj = tri.e1.cross(tri.e2);
        let w2o = self.world_to_object[instance as usize];
        // Normals transform by the inverse transpose of object-to-world, i.e. w2o transposed.
        glam::Mat3::from_mat4(w2o)
            .transpose()
            .mul_vec3(n_obj)
            .try_normalize()
    }

    // One triangle's world-space corners in f64 (`None` if out of range).
    fn world_corners(&self, instance: u32, primitive: u32) -> Option<[glam::DVec3; 3]> {
        let o2w = self
            .world_to_object
            .get(instance as usize)?
            .as_dmat4()
            .inverse();
        let (_, tris) = &self.meshes[self.instance_mesh[instance as usize] as usize];
        let tri = tris.get(primitive as usize)?;
        let a = o2w.transform_point3(tri.v0.as_dvec3());
        let b = a + o2w.transform_vector3(tri.e1.as_dvec3());
        let c = a + o2w.transform_vector3(tri.e2.as_dvec3());
        Some([a, b, c])
    }

    /// How far `point` lies from one given triangle of one instance: the world-space
    /// distance to its nearest point, in f64 (`None` if out of range). For arbitrating
    /// rounding ties: where a rounding of the triangle (a merged BVH holds it in world space)
    /// moves a hit at an edge, a vertex or along a grazing ray, the hit point must still lie
    /// on the triangle up to that rounding.
    pub fn point_distance(&self, instance: u32, primitive: u32, point: Vec3) -> Option<f64> {
        let [a, b, c] = self.world_corners(instance, primitive)?;
        Some(closest_on_triangle(point.as_dvec3(), a, b, c).distance(point.as_dvec3()))
    }

    /// How far `point` lies from the nearest edge of one given triangle of one instance, in
    /// world units and f64 (`None` if out of range): whether a hit sits where rounding may
    /// let a ray slip past the triangle.
    pub fn edge_distance(&self, instance: u32, primitive: u32, point: Vec3) -> Option<f64> {
        let [a, b, c] = self.world_corners(instance, primitive)?;
        let p = point.as_dvec3();
        let segment = |s: glam::DVec3, e: glam::DVec3| {
            let k = ((p - s).dot(e - s) / (e - s).length_squared().max(f64::MIN_POSITIVE))
                .clamp(0.0, 1.0);
            (s + (e - s) * k).distance(p)
        };
        Some(segment(a, b).min(segment(b, c)).min(segment(c, a)))
    }

    /// The `t` at which the ray meets one given triangle of one instance, if it does within
    /// `bary_eps` of its edges (any `t`). Computed in f64, so it can arbitrate rounding ties
    /// between two f32 tracers, sliver triangles included.
    pub fn hit_t(
        &self,
        instance: u32,
        primitive: u32,
        origin: Vec3,
        dir: Vec3,
        bary_eps: f32,
    ) -> Option<f32> {
        use glam::DVec3;
        let w2o = self.world_to_object[instance as usize].as_dmat4();
        let (_, tris) = &self.meshes[self.instance_mesh[instance as usize] as usize];
        let tri = tris.get(primitive as usize)?;
        let (v0, e1, e2) = (tri.v0.as_dvec3(), tri.e1.as_dvec3(), tri.e2.as_dvec3());
        let o = w2o.transform_point3(origin.as_dvec3());
        let d: DVec3 = w2o.transform_vector3(dir.as_dvec3());
        let pvec = d.cross(e2);
        let det = e1.dot(pvec);
        if det == 0.0 {
            return None;
        }
        let tvec = o - v0;
        let u = tvec.dot(pvec) / det;
        let qvec = tvec.cross(e1);
        let v = d.dot(qvec) / det;
        let eps = bary_eps as f64;
        (u >= -eps && v >= -eps && u + v <= 1.0 + eps).then(|| (e2.dot(qvec) / det) as f32)
    }
}

/// World-space bounds of one instance.
pub fn instance_bounds(scene: &Scene, inst: &crate::model::Instance) -> (Vec3, Vec3) {
    let (a, b) = scene.meshes[inst.mesh as usize].bounds();
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 == 0 { a.x } else { b.x },
            if i & 2 == 0 { a.y } else { b.y },
            if i & 4 == 0 { a.z } else { b.z },
        );
        let w = inst.transform.transform_point3(c);
        lo = lo.min(w);
        hi = hi.max(w);
    }
    (lo, hi)
}

// The point of triangle abc nearest p, by the Voronoi regions of its corners and edges
// (Ericson, Real-Time Collision Detection, 5.1.5).
fn closest_on_triangle(
    p: glam::DVec3,
    a: glam::DVec3,
    b: glam::DVec3,
    c: glam::DVec3,
) -> glam::DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn a_scene_without_instances_has_no_hits() {
        // An empty tree has no root node to visit (the emitter reference of a scene whose
        // lights are all off is one).
        let mut scene = crate::default_scene::cornell_box();
        scene.instances.clear();
        let tracer = CpuTracer::new(&scene);
        assert!(
            tracer
                .trace(Vec3::splat(1.0), Vec3::X, 0.0, f32::MAX, 0)
                .is_none()
        );
    }

    #[test]
    fn bvh_traversal_equals_brute_force() {
        let scene = crate::default_scene::cornell_box();
        let tracer = CpuTracer::new(&scene);
        let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
        for _ in 0..2000 {
            let o = Vec3::new(
                rng.random_range(0.5..5.0),
                rng.random_range(0.5..5.0),
                rng.random_range(-1.0..5.0),
            );
            let d = Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            let mut brute: Option<(f32, u32)> = None;
            for (ii, inst) in scene.instances.iter().enumerate() {
                let m = &scene.meshes[inst.mesh as usize];
                for t in 0..m.triangle_count() {
                    if let Some((th, ..)) = intersect_triangle(
                        &EdgeTriangle::new(m.triangle(t)),
                        o,
                        d,
                        0.0,
                        f32::INFINITY,
                    ) && brute.is_none_or(|(bt, _)| th < bt)
                    {
                        brute = Some((th, ii as u32));
                    }
                }
            }
            let hit = tracer.trace(o, d, 0.0, f32::INFINITY, 0);
            assert_eq!(hit.map(|h| h.t), brute.map(|b| b.0));
        }
    }

    #[test]
    fn closest_point_on_a_triangle_is_no_farther_than_any_sampled_point() {
        use glam::DVec3;
        let mut rng = rand_pcg::Pcg64::seed_from_u64(3);
        let mut v = || DVec3::new(rng.random(), rng.random(), rng.random()) * 4.0 - 2.0;
        for _ in 0..200 {
            let (a, b, c, p) = (v(), v(), v(), v());
            let q = closest_on_triangle(p, a, b, c);
            // On the triangle: its barycentrics are in [0, 1].
            let n = (b - a).cross(c - a);
            let area = n.length_squared();
            let u = (q - a).cross(c - a).dot(n) / area;
            let w = (b - a).cross(q - a).dot(n) / area;
            assert!(u >= -1e-9 && w >= -1e-9 && u + w <= 1.0 + 1e-9, "{u} {w}");
            let best = q.distance(p);
            for i in 0..=40 {
                for j in 0..=(40 - i) {
                    let s = a + (b - a) * (i as f64 / 40.0) + (c - a) * (j as f64 / 40.0);
                    assert!(
                        best <= s.distance(p) + 1e-9,
                        "sample nearer than the closest point"
                    );
                }
            }
        }
    }
}
