//! A small textured scene made in code: every texture slot a glTF material has (base colour,
//! metallic-roughness, normal map, emission), procedural, so tests and examples exercise
//! texturing without shipping image files.
//!
//! Two spheres over a checkered ground under a uniform white environment: the left sphere is
//! striped base colour with a bumpy normal map and metal bands; the right one has an emissive
//! texture (the scene's only emitter besides the sky); the ground is a checker with a roughness
//! checker of a different period, so texture filtering shows at grazing angles.

use crate::geometry::{generate_normals, generate_tangents};
use crate::model::*;
use crate::texture::build_mips;
use glam::{Mat4, Vec2, Vec3, Vec4};

/// A `w × h` texture whose texel `(x, y)` is `texel(x, y)` (RGBA8), with its mip chain.
pub fn procedural_texture(
    name: &str,
    w: u32,
    h: u32,
    color_space: ColorSpace,
    texel: impl Fn(u32, u32) -> [u8; 4],
) -> Texture {
    let mut rgba8 = Vec::with_capacity((w * h * 4) as usize);
    for y in 0..h {
        for x in 0..w {
            rgba8.extend_from_slice(&texel(x, y));
        }
    }
    Texture {
        name: name.into(),
        color_space,
        mips: build_mips(
            MipLevel {
                width: w,
                height: h,
                rgba8,
            },
            color_space,
        ),
        repeat: true,
    }
}

/// An `n × n` sRGB checker of white and black texels, alternating (for even `n`, half of
/// each: a mean of exactly 0.5 in linear light), with its mip chain.
pub fn checker_texture(name: &str, n: u32) -> Texture {
    procedural_texture(name, n, n, ColorSpace::Srgb, |x, y| {
        if (x + y) % 2 == 0 {
            [255; 4]
        } else {
            [0, 0, 0, 255]
        }
    })
}

/// A unit UV sphere (`segments` around, `rings` from pole to pole) with MikkTSpace tangents.
pub fn uv_sphere(name: &str, segments: u32, rings: u32) -> Mesh {
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    for r in 0..=rings {
        let v = r as f32 / rings as f32;
        let theta = v * std::f32::consts::PI;
        for s in 0..=segments {
            let u = s as f32 / segments as f32;
            let phi = u * std::f32::consts::TAU;
            positions.push(Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            ));
            uvs.push(Vec2::new(u, v));
        }
    }
    let row = segments + 1;
    let mut indices = Vec::new();
    for r in 0..rings {
        for s in 0..segments {
            let a = r * row + s;
            let b = a + row;
            // Counter-clockwise seen from outside; the pole rows lose one zero-area triangle.
            if r != 0 {
                indices.extend([a, b, a + 1]);
            }
            if r != rings - 1 {
                indices.extend([a + 1, b, b + 1]);
            }
        }
    }
    // Smooth normals of a unit sphere are its positions; generating them would crease the seam.
    let normals = positions.clone();
    let mut mesh = Mesh {
        name: name.into(),
        positions,
        normals,
        uvs,
        tangents: Vec::new(),
        indices,
    };
    mesh.tangents = generate_tangents(&mesh);
    mesh
}

/// A square of side `size` on the XZ plane facing +Y, centred on the origin, its UVs
/// repeating `repeat` times (tangents along +X).
pub fn ground_plane(size: f32, repeat: f32) -> Mesh {
    let h = size * 0.5;
    let positions = vec![
        Vec3::new(-h, 0.0, h),
        Vec3::new(h, 0.0, h),
        Vec3::new(h, 0.0, -h),
        Vec3::new(-h, 0.0, -h),
    ];
    let indices = vec![0, 1, 2, 0, 2, 3];
    let normals = generate_normals(&positions, &indices);
    Mesh {
        name: "ground".into(),
        uvs: vec![
            Vec2::new(0.0, repeat),
            Vec2::new(repeat, repeat),
            Vec2::new(repeat, 0.0),
            Vec2::ZERO,
        ],
        tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
        positions,
        normals,
        indices,
    }
}

fn material(name: &str) -> Material {
    Material {
        name: name.into(),
        base_color: Vec4::ONE,
        metallic: 0.0,
        roughness: 1.0,
        ..Default::default()
    }
}

/// The textured test scene (see the module doc). Camera `camera`, 16:9, looking down at the
/// spheres; uniform environment radiance 1.
pub fn textured_spheres() -> Scene {
    let checker = procedural_texture("checker", 64, 64, ColorSpace::Srgb, |x, y| {
        if (x / 8 + y / 8) % 2 == 0 {
            [230, 225, 210, 255]
        } else {
            [40, 60, 90, 255]
        }
    });
    // Metallic in B, roughness in G (glTF's packing); a 12-texel roughness period against the
    // colour's 16 so that both show.
    let ground_mr = procedural_texture("ground_mr", 48, 48, ColorSpace::Linear, |x, y| {
        let rough = if (x / 6 + y / 6) % 2 == 0 { 60 } else { 240 };
        [0, rough, 0, 255]
    });
    let stripes = procedural_texture("stripes", 128, 64, ColorSpace::Srgb, |x, _| {
        [[200, 60, 40, 255], [240, 200, 80, 255], [60, 120, 200, 255]][(x / 8 % 3) as usize]
    });
    let bands = procedural_texture("bands", 64, 64, ColorSpace::Linear, |_, y| {
        let metal = y / 8 % 2 == 0;
        [
            0,
            if metal { 80 } else { 180 },
            if metal { 255 } else { 0 },
            255,
        ]
    });
    // Bumps: a tangent-space normal tilted by a sine field.
    let bumps = procedural_texture("bumps", 64, 64, ColorSpace::Linear, |x, y| {
        let (u, v) = (x as f32 / 64.0, y as f32 / 64.0);
        let dx = 0.5 * (u * std::f32::consts::TAU * 8.0).sin();
        let dy = 0.5 * (v * std::f32::consts::TAU * 4.0).cos();
        let n = Vec3::new(dx, dy, 1.0).normalize();
        let e = |c: f32| ((c * 0.5 + 0.5) * 255.0 + 0.5) as u8;
        [e(n.x), e(n.y), e(n.z), 255]
    });
    let glow = procedural_texture("glow", 64, 32, ColorSpace::Srgb, |x, y| {
        if (x / 4) % 4 == 0 || (y / 4) % 4 == 0 {
            [255, 220, 150, 255]
        } else {
            [0, 0, 0, 255]
        }
    });
    let textures = vec![checker, ground_mr, stripes, bands, bumps, glow];

    let mut ground_m = material("ground");
    ground_m.base_color_texture = Some(0);
    ground_m.metallic_roughness_texture = Some(1);
    let mut striped = material("striped");
    striped.base_color_texture = Some(2);
    striped.metallic = 1.0;
    striped.metallic_roughness_texture = Some(3);
    striped.normal_texture = Some(4);
    let mut glowing = material("glowing");
    glowing.base_color = Vec4::new(0.3, 0.3, 0.3, 1.0);
    glowing.roughness = 0.5;
    glowing.emissive = Vec3::splat(4.0);
    glowing.emissive_texture = Some(5);

    let meshes = vec![ground_plane(8.0, 4.0), uv_sphere("sphere", 48, 24)];
    let instances = vec![
        Instance {
            name: "ground".into(),
            mesh: 0,
            material: 0,
            transform: Mat4::IDENTITY,
        },
        Instance {
            name: "striped_sphere".into(),
            mesh: 1,
            material: 1,
            transform: Mat4::from_translation(Vec3::new(-1.2, 1.0, 0.0)),
        },
        Instance {
            name: "glowing_sphere".into(),
            mesh: 1,
            material: 2,
            transform: Mat4::from_scale_rotation_translation(
                Vec3::splat(0.8),
                glam::Quat::from_rotation_y(0.7),
                Vec3::new(1.3, 0.8, 0.3),
            ),
        },
    ];
    let mut camera = Camera::look_at(
        "camera",
        Vec3::new(0.0, 2.2, 5.0),
        Vec3::new(0.0, 0.8, 0.0),
        Vec3::Y,
        45f32.to_radians(),
    );
    camera.aspect = Some(16.0 / 9.0);
    Scene {
        meshes,
        instances,
        materials: vec![ground_m, striped, glowing],
        textures,
        cameras: vec![camera],
        environment_radiance: Vec3::ONE,
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_is_closed_outward_and_unit() {
        let m = uv_sphere("s", 16, 8);
        for t in 0..m.triangle_count() {
            let [a, b, c] = m.triangle(t);
            let n = (b - a).cross(c - a);
            assert!(n.length() > 0.0, "triangle {t} is degenerate");
            assert!(n.dot(a + b + c) > 0.0, "triangle {t} faces inward");
        }
        assert!(m.positions.iter().all(|p| (p.length() - 1.0).abs() < 1e-5));
        assert_eq!(m.tangents.len(), m.positions.len());
        assert!(m.tangents.iter().all(|t| t.is_finite()));
    }

    #[test]
    fn every_texture_slot_is_used_and_valid() {
        let s = textured_spheres();
        let used: Vec<u32> = s
            .materials
            .iter()
            .flat_map(|m| {
                [
                    m.base_color_texture,
                    m.metallic_roughness_texture,
                    m.normal_texture,
                    m.emissive_texture,
                ]
            })
            .flatten()
            .collect();
        assert_eq!(used.len(), s.textures.len());
        assert!(used.iter().all(|&t| (t as usize) < s.textures.len()));
        assert!(s.stats().emissive_triangles > 0);
    }
}
