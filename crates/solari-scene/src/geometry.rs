//! Mesh clean-up shared by every importer: degenerate-triangle removal, normal and tangent
// Negated comparisons are deliberate: they also reject NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
//! generation.

use crate::model::Mesh;
use glam::{Vec2, Vec3, Vec4};

/// Removes triangles whose corners coincide or whose area is zero; returns how many went.
///
/// "Zero" is relative to the triangle's size so that tiny but valid triangles (a 7 mm model)
/// stay: the cross product must exceed `1e-12` times the squared longest edge.
pub fn drop_degenerate_triangles(mesh: &mut Mesh) -> usize {
    let before = mesh.indices.len() / 3;
    let positions = &mesh.positions;
    let mut kept = Vec::with_capacity(mesh.indices.len());
    for tri in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| positions[tri[k] as usize]);
        if !is_degenerate(a, b, c) {
            kept.extend_from_slice(tri);
        }
    }
    mesh.indices = kept;
    before - mesh.indices.len() / 3
}

/// Whether a triangle has (relatively) zero area.
pub fn is_degenerate(a: Vec3, b: Vec3, c: Vec3) -> bool {
    let e0 = b - a;
    let e1 = c - a;
    let e2 = c - b;
    let longest = e0
        .length_squared()
        .max(e1.length_squared())
        .max(e2.length_squared());
    let cross = e0.cross(e1).length_squared();
    !(longest > 0.0) || !(cross > 1e-24 * longest * longest) || !cross.is_finite()
}

/// Area-weighted smooth vertex normals. Vertices no triangle touches get +Z.
pub fn generate_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| positions[tri[k] as usize]);
        // Unnormalised cross product: weights by area.
        let n = (b - a).cross(c - a);
        for &i in tri {
            normals[i as usize] += n;
        }
    }
    normals
        .iter()
        .map(|n| n.try_normalize().unwrap_or(Vec3::Z))
        .collect()
}

/// Replaces non-unit or non-finite normals by a valid unit vector (the triangle's, else +Z).
pub fn sanitize_normals(normals: &mut [Vec3]) -> usize {
    let mut fixed = 0;
    for n in normals.iter_mut() {
        match n.try_normalize() {
            Some(u) => *n = u,
            None => {
                *n = Vec3::Z;
                fixed += 1;
            }
        }
    }
    fixed
}

struct MikkGeometry<'a> {
    mesh: &'a Mesh,
    tangents: Vec<Vec4>,
}

impl bevy_mikktspace::Geometry for MikkGeometry<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.indices.len() / 3
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.positions[self.mesh.indices[face * 3 + vert] as usize].into()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.normals[self.mesh.indices[face * 3 + vert] as usize].into()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.mesh.uvs[self.mesh.indices[face * 3 + vert] as usize].into()
    }
    fn set_tangent(
        &mut self,
        tangent: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        // Welded vertices receive the same tangent from every face in practice; the last wins.
        if let Some(t) = tangent {
            self.tangents[self.mesh.indices[face * 3 + vert] as usize] =
                Vec4::from(t.tangent_encoded());
        }
    }
}

/// MikkTSpace tangents (the glTF convention). Falls back to an arbitrary frame around the
/// normal where UVs are degenerate.
pub fn generate_tangents(mesh: &Mesh) -> Vec<Vec4> {
    let mut geo = MikkGeometry {
        mesh,
        tangents: vec![Vec4::ZERO; mesh.positions.len()],
    };
    if mesh.indices.is_empty() || bevy_mikktspace::generate_tangents(&mut geo).is_err() {
        geo.tangents.iter_mut().for_each(|t| *t = Vec4::ZERO);
    }
    let mut tangents = geo.tangents;
    for (t, n) in tangents.iter_mut().zip(&mesh.normals) {
        *t = sanitize_tangent(*t, *n);
    }
    tangents
}

/// Makes a tangent unit, orthogonal to `n` and finite, with handedness ±1.
pub fn sanitize_tangent(t: Vec4, n: Vec3) -> Vec4 {
    let w = if t.w < 0.0 { -1.0 } else { 1.0 };
    let tt = t.truncate();
    let ortho = tt - n * n.dot(tt);
    match ortho.try_normalize() {
        Some(u) => u.extend(w),
        None => n.any_orthonormal_vector().extend(1.0),
    }
}

/// Fills missing UVs with zeros so every attribute array has one entry per vertex.
pub fn default_uvs(count: usize) -> Vec<Vec2> {
    vec![Vec2::ZERO; count]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degenerate_detection_is_scale_free() {
        let s = 1e-4;
        assert!(!is_degenerate(Vec3::ZERO, Vec3::X * s, Vec3::Y * s));
        assert!(is_degenerate(Vec3::ZERO, Vec3::X, Vec3::X * 2.0));
        assert!(is_degenerate(Vec3::ONE, Vec3::ONE, Vec3::ONE));
        assert!(is_degenerate(Vec3::ZERO, Vec3::X * f32::NAN, Vec3::Y));
    }

    #[test]
    fn generated_normals_face_outward_of_ccw_triangle() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let n = generate_normals(&p, &[0, 1, 2]);
        for v in n {
            assert!((v - Vec3::Z).length() < 1e-6);
        }
    }

    #[test]
    fn sanitized_tangent_is_orthonormal() {
        let n = Vec3::new(0.3, 0.4, 0.5).normalize();
        for t in [
            Vec4::ZERO,
            Vec4::new(f32::NAN, 0.0, 0.0, 1.0),
            Vec4::new(1.0, 2.0, 3.0, -1.0),
        ] {
            let s = sanitize_tangent(t, n);
            assert!(s.is_finite());
            assert!((s.truncate().length() - 1.0).abs() < 1e-5);
            assert!(s.truncate().dot(n).abs() < 1e-5);
            assert!(s.w == 1.0 || s.w == -1.0);
        }
    }
}
