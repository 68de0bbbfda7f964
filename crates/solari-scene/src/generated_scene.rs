//! Scenes of any size made in code, for scale tests.
//!
//! - [`rock_field`]: a square field of rocks, each its own mesh (a displaced sphere), on a
//!   ground plane under a sun, with a few glowing spheres. With `rock_field(1024, 10_000)` it
//!   holds 10.2 million distinct triangles in 1,029 instances, so loading, BVH builds and
//!   per-frame costs can be measured at a scale no shared scene has.
//! - [`point_light_field`]: a square lit only by thousands of coloured point lights among
//!   posts, for many-light sampling (light tiles against the light grid).

use crate::geometry::generate_normals;
use crate::model::*;
use crate::rng::{Rng, pcg_hash};
use crate::textured_scene::{ground_plane, uv_sphere};
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use rayon::prelude::*;

/// Most rocks, and most triangles per rock, [`rock_field`] accepts.
pub const MAX_ROCKS: u32 = 1 << 16;
/// Most triangles per rock.
pub const MAX_ROCK_TRIANGLES: u32 = 1 << 20;
/// Most triangles in all (2^28: indices of every rock together stay well inside `u32`).
pub const MAX_FIELD_TRIANGLES: u64 = 1 << 28;

// Distance between rock centres, in rock radii.
const SPACING: f32 = 3.0;

/// `rocks` rocks of about `triangles` triangles each (at least 16), every one a distinct
/// mesh, in a square grid; plus the ground, four emissive spheres, a sun and a camera that
/// sees the whole field at a slant. Deterministic. Errors name the argument out of range.
pub fn rock_field(rocks: u32, triangles: u32) -> Result<Scene, String> {
    if !(1..=MAX_ROCKS).contains(&rocks) {
        return Err(format!("rocks must be 1 to {MAX_ROCKS}, not {rocks}"));
    }
    if !(16..=MAX_ROCK_TRIANGLES).contains(&triangles) {
        return Err(format!(
            "triangles per rock must be 16 to {MAX_ROCK_TRIANGLES}, not {triangles}"
        ));
    }
    if rocks as u64 * triangles as u64 > MAX_FIELD_TRIANGLES {
        return Err(format!(
            "{rocks} rocks of {triangles} triangles make more than {MAX_FIELD_TRIANGLES} \
             triangles in all"
        ));
    }
    // A UV sphere of s segments and r rings has 2·s·(r − 1) triangles; keep s ≈ 2r.
    let rings = ((triangles as f32 / 4.0).sqrt().round() as u32 + 1).max(3);
    let segments = (triangles / (2 * (rings - 1))).max(4);
    let side = (rocks as f32).sqrt().ceil() as u32;
    let extent = side as f32 * SPACING;

    let mut materials: Vec<Material> = (0..8)
        .map(|i| {
            let mut rng = Rng(pcg_hash(i));
            let grey = 0.25 + 0.5 * rng.next_f32();
            let tint = Vec3::new(
                1.0,
                0.85 + 0.15 * rng.next_f32(),
                0.7 + 0.3 * rng.next_f32(),
            );
            Material {
                name: format!("rock_{i}"),
                base_color: (tint * grey).extend(1.0),
                roughness: 0.3 + 0.7 * rng.next_f32(),
                metallic: if i == 7 { 1.0 } else { 0.0 },
                ..Default::default()
            }
        })
        .collect();
    let ground_material = materials.len() as u32;
    materials.push(Material {
        name: "ground".into(),
        base_color: Vec4::new(0.45, 0.42, 0.38, 1.0),
        roughness: 0.9,
        ..Default::default()
    });
    let glow_material = materials.len() as u32;
    materials.push(Material {
        name: "glow".into(),
        base_color: Vec4::new(0.2, 0.2, 0.2, 1.0),
        emissive: Vec3::new(12.0, 9.0, 6.0),
        ..Default::default()
    });

    // Each rock depends on its index alone, so they are made in parallel and the field is
    // the same on any number of threads (one thread took 16-18 s for 1024x10000 on the H200
    // host, most of it in the spheres' MikkTSpace tangents).
    let made: Vec<(Mesh, Instance)> = (0..rocks)
        .into_par_iter()
        .map(|i| {
            let mut rng = Rng(pcg_hash(i ^ 0x9e37_79b9));
            let mesh = rock(i, segments, rings, &mut rng);
            let (gx, gz) = ((i % side) as f32, (i / side) as f32);
            let jitter = Vec2::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5) * SPACING * 0.4;
            let scale = 0.6 + 0.8 * rng.next_f32();
            let centre = Vec3::new(
                (gx + 0.5) * SPACING - extent * 0.5 + jitter.x,
                0.6 * scale,
                (gz + 0.5) * SPACING - extent * 0.5 + jitter.y,
            );
            let turn = Quat::from_rotation_y(rng.next_f32() * std::f32::consts::TAU);
            let instance = Instance {
                name: format!("rock_{i}"),
                mesh: i,
                material: rng.next_u32() % 8,
                transform: Mat4::from_scale_rotation_translation(Vec3::splat(scale), turn, centre),
            };
            (mesh, instance)
        })
        .collect();
    let (mut meshes, mut instances): (Vec<Mesh>, Vec<Instance>) = made.into_iter().unzip();
    let ground = meshes.len() as u32;
    meshes.push(ground_plane(extent + 2.0 * SPACING, 1.0));
    instances.push(Instance {
        name: "ground".into(),
        mesh: ground,
        material: ground_material,
        transform: Mat4::IDENTITY,
    });
    let glow = meshes.len() as u32;
    meshes.push(uv_sphere("glow", 16, 8));
    for (k, (x, z)) in [(-0.25, -0.25), (0.25, -0.25), (-0.25, 0.25), (0.25, 0.25)]
        .into_iter()
        .enumerate()
    {
        instances.push(Instance {
            name: format!("glow_{k}"),
            mesh: glow,
            material: glow_material,
            transform: Mat4::from_scale_rotation_translation(
                Vec3::splat(0.5),
                Quat::IDENTITY,
                Vec3::new(x * extent, 3.0, z * extent),
            ),
        });
    }
    let mut camera = Camera::look_at(
        "overview",
        Vec3::new(0.0, 0.35 * extent + 4.0, 0.75 * extent + 4.0),
        Vec3::new(0.0, 0.0, 0.1 * extent),
        Vec3::Y,
        50f32.to_radians(),
    );
    camera.aspect = Some(16.0 / 9.0);
    Ok(Scene {
        meshes,
        instances,
        materials,
        cameras: vec![camera],
        directional_lights: vec![DirectionalLight {
            name: "sun".into(),
            direction: Vec3::new(0.4, -0.8, 0.3).normalize(),
            irradiance: Vec3::new(3.0, 2.8, 2.5),
            angular_diameter: SUN_ANGULAR_DIAMETER,
        }],
        environment_radiance: Vec3::new(0.05, 0.07, 0.1),
        ..Default::default()
    })
}

/// Most lights [`point_light_field`] accepts.
pub const MAX_FIELD_LIGHTS: u32 = 1 << 20;

/// A square of about 4 m² per light, lit only by `lights` coloured point lights (delta,
/// 0.2–2.5 m above the ground, 1–8 W/sr) scattered at random among posts on a 5 m grid, with
/// a camera low over one edge looking across it. No sun and a black sky: every pixel's light
/// comes from the nearby few of thousands. Deterministic. Errors name the argument.
pub fn point_light_field(lights: u32) -> Result<Scene, String> {
    if !(1..=MAX_FIELD_LIGHTS).contains(&lights) {
        return Err(format!(
            "lights must be 1 to {MAX_FIELD_LIGHTS}, not {lights}"
        ));
    }
    let side = (2.0 * (lights as f32).sqrt()).max(10.0);
    let materials = vec![
        Material {
            name: "ground".into(),
            base_color: Vec4::new(0.5, 0.5, 0.5, 1.0),
            roughness: 0.8,
            ..Default::default()
        },
        Material {
            name: "post".into(),
            base_color: Vec4::new(0.7, 0.6, 0.5, 1.0),
            roughness: 0.4,
            ..Default::default()
        },
    ];
    let meshes = vec![ground_plane(side + 4.0, 1.0), uv_sphere("post", 12, 6)];
    let mut instances = vec![Instance {
        name: "ground".into(),
        mesh: 0,
        material: 0,
        transform: Mat4::IDENTITY,
    }];
    let posts = (side / 5.0).floor() as u32;
    for i in 0..posts * posts {
        let (x, z) = ((i % posts) as f32, (i / posts) as f32);
        let centre = Vec3::new(
            (x + 0.5) * 5.0 - 0.5 * side,
            1.0,
            (z + 0.5) * 5.0 - 0.5 * side,
        );
        instances.push(Instance {
            name: format!("post_{i}"),
            mesh: 1,
            material: 1,
            transform: Mat4::from_scale_rotation_translation(
                Vec3::new(0.35, 1.0, 0.35),
                Quat::IDENTITY,
                centre,
            ),
        });
    }
    let mut rng = Rng(pcg_hash(0x5eed_1167));
    let punctual_lights = (0..lights)
        .map(|i| {
            let position = Vec3::new(
                (rng.next_f32() - 0.5) * side,
                0.2 + 2.3 * rng.next_f32(),
                (rng.next_f32() - 0.5) * side,
            );
            // A saturated colour of luminance 1 to 8.
            let tint = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) + 0.15;
            let luminance = 0.2126 * tint.x + 0.7152 * tint.y + 0.0722 * tint.z;
            let intensity = tint / luminance * (1.0 + 7.0 * rng.next_f32());
            PunctualLight {
                name: format!("light_{i}"),
                kind: PunctualKind::Point,
                position,
                direction: Vec3::NEG_Z,
                intensity,
                range: None,
                radius: 0.0,
            }
        })
        .collect();
    let mut camera = Camera::look_at(
        "edge",
        Vec3::new(0.0, 4.0, 0.5 * side + 1.0),
        Vec3::new(0.0, 0.0, 0.5 * side - 25.0),
        Vec3::Y,
        60f32.to_radians(),
    );
    camera.aspect = Some(16.0 / 9.0);
    Ok(Scene {
        meshes,
        instances,
        materials,
        cameras: vec![camera],
        punctual_lights,
        ..Default::default()
    })
}

// A unit sphere pushed in and out by a few random waves: every rock differs.
fn rock(index: u32, segments: u32, rings: u32, rng: &mut Rng) -> Mesh {
    let mut mesh = uv_sphere(&format!("rock_{index}"), segments, rings);
    let waves: Vec<(Vec3, f32, f32)> = (0..4)
        .map(|_| {
            let dir = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0;
            let freq = 1.5 + 3.0 * rng.next_f32();
            let phase = rng.next_f32() * std::f32::consts::TAU;
            (
                dir.normalize_or(Vec3::X) * freq,
                phase,
                0.06 + 0.06 * rng.next_f32(),
            )
        })
        .collect();
    for p in &mut mesh.positions {
        let bump: f32 = waves
            .iter()
            .map(|&(k, phase, amp)| amp * (k.dot(*p) + phase).sin())
            .sum();
        *p *= 1.0 + bump;
    }
    // Flatten the underside a little, so rocks sit on the ground.
    for p in &mut mesh.positions {
        p.y = p.y.max(-0.6);
    }
    mesh.normals = generate_normals(&mesh.positions, &mesh.indices);
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_field_has_the_asked_size_and_is_valid() {
        let scene = rock_field(20, 500).unwrap();
        let rocks: Vec<&Instance> = scene
            .instances
            .iter()
            .filter(|i| i.name.starts_with("rock_"))
            .collect();
        assert_eq!(rocks.len(), 20);
        assert_eq!(scene.instances.len(), 25, "rocks, ground, four glows");
        let tris: Vec<usize> = rocks
            .iter()
            .map(|i| scene.meshes[i.mesh as usize].indices.len() / 3)
            .collect();
        for &t in &tris {
            assert!((400..=600).contains(&t), "{t} triangles for 500 asked");
        }
        // Distinct meshes: no two rocks share positions.
        let first = &scene.meshes[rocks[0].mesh as usize].positions;
        let second = &scene.meshes[rocks[1].mesh as usize].positions;
        assert_ne!(first, second);
        scene.validate().expect("a valid scene");
        assert!(scene.camera(None).is_some());
        assert_eq!(
            rock_field(20, 500).unwrap().meshes[3].positions,
            scene.meshes[3].positions
        );
    }

    #[test]
    fn the_light_field_has_its_lights_inside_the_ground() {
        let scene = point_light_field(400).unwrap();
        assert_eq!(scene.punctual_lights.len(), 400);
        scene.validate().expect("a valid scene");
        let (lo, hi) = scene.bounds();
        for l in &scene.punctual_lights {
            assert!(
                l.position.x >= lo.x && l.position.x <= hi.x,
                "{}",
                l.position
            );
            assert!(
                l.position.z >= lo.z && l.position.z <= hi.z,
                "{}",
                l.position
            );
            assert!(l.intensity.min_element() > 0.0 && l.intensity.is_finite());
        }
        assert_eq!(
            point_light_field(400).unwrap().punctual_lights,
            scene.punctual_lights,
            "deterministic"
        );
        assert!(point_light_field(0).unwrap_err().contains("lights"));
        assert!(
            point_light_field(MAX_FIELD_LIGHTS + 1)
                .unwrap_err()
                .contains("lights")
        );
    }

    #[test]
    fn sizes_out_of_range_are_refused() {
        assert!(rock_field(0, 100).unwrap_err().contains("rocks"));
        assert!(
            rock_field(MAX_ROCKS + 1, 100)
                .unwrap_err()
                .contains("rocks")
        );
        assert!(rock_field(4, 8).unwrap_err().contains("triangles"));
        assert!(
            rock_field(4, MAX_ROCK_TRIANGLES + 1)
                .unwrap_err()
                .contains("triangles")
        );
    }
}
