//! The built-in default scene: a Cornell box with an emissive ceiling light, made in code so
//! the app runs with no files at all.
//!
//! Geometry follows the published measured Cornell box data (millimetres scaled by 0.01, +Y
//! up), with the same materials and camera as `shared/scenes/cornell_box`: pure Lambertian
//! surfaces and a single-sided light of radiance (17, 12, 4).

use crate::geometry::generate_normals;
use crate::model::*;
use glam::{Mat4, Vec2, Vec3, Vec4};

fn lambert(name: &str, rgb: [f32; 3]) -> Material {
    Material {
        name: name.into(),
        base_color: Vec3::from(rgb).extend(1.0),
        metallic: 0.0,
        roughness: 1.0,
        dielectric_f0: Vec3::ZERO,
        dielectric_f90: 0.0,
        ..Default::default()
    }
}

/// A mesh of quads, each given as four corners; the winding is chosen so that the face normal
/// points along `facing` (or away from `facing`'s point, see [`box_mesh`]).
fn quads_mesh(name: &str, quads: &[([Vec3; 4], Vec3)]) -> Mesh {
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for (corners, facing) in quads {
        let base = positions.len() as u32;
        let n = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        let order: [usize; 4] = if n.dot(*facing) >= 0.0 {
            [0, 1, 2, 3]
        } else {
            [0, 3, 2, 1]
        };
        positions.extend(order.map(|i| corners[i]));
        indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    let normals = generate_normals_flat(&positions, &indices);
    let uvs = (0..positions.len())
        .map(|i| [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y][i % 4])
        .collect();
    let tangents = normals
        .iter()
        .map(|n: &Vec3| n.any_orthonormal_vector().extend(1.0))
        .collect::<Vec<Vec4>>();
    Mesh {
        name: name.into(),
        positions,
        normals,
        uvs,
        tangents,
        indices,
    }
}

/// Flat normals: every quad has its own four vertices, so smooth generation gives flat results.
fn generate_normals_flat(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    generate_normals(positions, indices)
}

/// A block from its top face (four corners, any order around the rim) down to y = 0.
fn box_mesh(name: &str, top: [[f32; 3]; 4]) -> Mesh {
    let t = top.map(|p| Vec3::from(p) * 0.01);
    let b = t.map(|p| Vec3::new(p.x, 0.0, p.z));
    let center = (t[0] + t[1] + t[2] + t[3]) * 0.25 - Vec3::Y * t[0].y * 0.5;
    let mut quads = vec![(t, Vec3::Y)];
    for i in 0..4 {
        let j = (i + 1) % 4;
        let face = [t[i], t[j], b[j], b[i]];
        let mid = (t[i] + t[j] + b[j] + b[i]) * 0.25;
        quads.push((face, mid - center));
    }
    quads_mesh(name, &quads)
}

/// The built-in Cornell box scene.
pub fn cornell_box() -> Scene {
    let s = 0.01;
    let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z) * s;
    let (w, h, d) = (556.0, 548.8, 559.2);
    let floor = quads_mesh(
        "floor",
        &[(
            [p(0., 0., 0.), p(w, 0., 0.), p(w, 0., d), p(0., 0., d)],
            Vec3::Y,
        )],
    );
    let ceiling = quads_mesh(
        "ceiling",
        &[(
            [p(0., h, 0.), p(w, h, 0.), p(w, h, d), p(0., h, d)],
            -Vec3::Y,
        )],
    );
    let back = quads_mesh(
        "back_wall",
        &[(
            [p(0., 0., d), p(w, 0., d), p(w, h, d), p(0., h, d)],
            -Vec3::Z,
        )],
    );
    let green = quads_mesh(
        "right_wall_green",
        &[(
            [p(0., 0., 0.), p(0., 0., d), p(0., h, d), p(0., h, 0.)],
            Vec3::X,
        )],
    );
    let red = quads_mesh(
        "left_wall_red",
        &[(
            [p(w, 0., 0.), p(w, 0., d), p(w, h, d), p(w, h, 0.)],
            -Vec3::X,
        )],
    );
    let ly = h - 0.3;
    let light = quads_mesh(
        "light",
        &[(
            [
                p(343.0, ly, 227.0),
                p(343.0, ly, 332.0),
                p(213.0, ly, 332.0),
                p(213.0, ly, 227.0),
            ],
            -Vec3::Y,
        )],
    );
    let short_block = box_mesh(
        "short_block",
        [
            [130.0, 165.0, 65.0],
            [82.0, 165.0, 225.0],
            [240.0, 165.0, 272.0],
            [290.0, 165.0, 114.0],
        ],
    );
    let tall_block = box_mesh(
        "tall_block",
        [
            [423.0, 330.0, 247.0],
            [265.0, 330.0, 296.0],
            [314.0, 330.0, 456.0],
            [472.0, 330.0, 406.0],
        ],
    );

    let white = lambert("white", [0.725, 0.71, 0.68]);
    let red_m = lambert("red", [0.63, 0.065, 0.05]);
    let green_m = lambert("green", [0.14, 0.45, 0.091]);
    let mut light_m = lambert("light", [0.78, 0.78, 0.78]);
    light_m.emissive = Vec3::new(17.0, 12.0, 4.0);

    let meshes = vec![
        floor,
        ceiling,
        back,
        green,
        red,
        light,
        short_block,
        tall_block,
    ];
    let materials = vec![white, red_m, green_m, light_m];
    let material_of = [0, 0, 0, 2, 1, 3, 0, 0];
    let instances = meshes
        .iter()
        .enumerate()
        .map(|(i, m)| Instance {
            name: m.name.clone(),
            mesh: i as u32,
            material: material_of[i],
            transform: Mat4::IDENTITY,
        })
        .collect();
    let camera = Camera {
        name: "camera".into(),
        transform: camera_to_world(
            Vec3::new(2.78, 2.73, -8.0),
            Vec3::new(2.78, 2.73, 0.0),
            Vec3::Y,
        ),
        yfov: 0.6860,
        aspect: Some(1.0),
        znear: 0.01,
    };
    Scene {
        meshes,
        instances,
        materials,
        cameras: vec![camera],
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cornell_box_is_closed_facing_inward_and_lit() {
        let scene = cornell_box();
        let stats = scene.stats();
        assert_eq!(stats.instances, 8);
        assert_eq!(stats.triangles, 2 * 6 + 2 * 5 * 2);
        assert_eq!(stats.emissive_triangles, 2);
        let room_center = Vec3::new(2.78, 2.74, 2.8);
        // Walls, floor and ceiling face the room's centre; the light faces down.
        for (i, m) in scene.meshes.iter().enumerate().take(6) {
            for t in 0..m.triangle_count() {
                let [a, b, c] = m.triangle(t);
                let n = (b - a).cross(c - a).normalize();
                let to_center = room_center - (a + b + c) / 3.0;
                assert!(
                    n.dot(to_center) > 0.0,
                    "mesh {i} triangle {t} faces outward"
                );
                assert!((m.normals[m.indices[t * 3] as usize] - n).length() < 1e-5);
            }
        }
        // Block faces point away from the block.
        for m in &scene.meshes[6..] {
            let (lo, hi) = m.bounds();
            let c = (lo + hi) * 0.5;
            for t in 0..m.triangle_count() {
                let [a, b, cc] = m.triangle(t);
                let n = (b - a).cross(cc - a);
                assert!(n.dot((a + b + cc) / 3.0 - c) > 0.0);
            }
        }
    }
}
