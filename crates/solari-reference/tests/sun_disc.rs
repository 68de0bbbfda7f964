//! The reference tracer's sun discs: a directional light of non-zero size is light sampling's
//! and BRDF sampling's at once. A polished metal floor seen from straight above, under a sun
//! straight overhead whose disc covers every reflected view ray, reflects the disc's radiance
//! times its directional albedo (1 for a white metal this smooth). BRDF sampling finds the
//! disc nearly always and light sampling nearly never lands in the narrow lobe, so MIS gives
//! the BRDF's rays most of the weight: if they did not count the disc, the floor would read
//! almost black (4% of the disc's radiance before the tracer counted them).

mod env_common;

use env_common::{direct_light_image, quad, seen_from_above};
use glam::{Vec3, Vec4};
use solari_lights::light_list::sun_disk;
use solari_scene::Scene;
use solari_scene::brdf::{self, BrdfMaterial, BrdfModel};
use solari_scene::gpu::test_gpu;
use solari_scene::gpu_types::GpuView;
use solari_scene::model::{DirectionalLight, Material, SUN_ANGULAR_DIAMETER};

const SIZE: u32 = 32;
/// 20°: the disc's edge lies 10° from its centre; the camera's rays leave the vertical by at
/// most 4° and the lobe (roughness 0.05) is a fraction of a degree wide.
const ANGULAR_DIAMETER: f32 = 20.0 * std::f32::consts::PI / 180.0;

fn metal_floor_under_the_sun(roughness: f32) -> Scene {
    // A 40 m floor facing up, shared with the environment tests.
    let floor = quad("floor", 20.0, 0.0);
    let metal = Material {
        name: "white metal".into(),
        base_color: Vec4::ONE,
        metallic: 1.0,
        roughness,
        ..Default::default()
    };
    Scene {
        directional_lights: vec![DirectionalLight {
            name: "sun".into(),
            direction: Vec3::NEG_Y,
            irradiance: Vec3::ONE,
            angular_diameter: ANGULAR_DIAMETER,
        }],
        // 0.1 rad across: the corner pixels' rays leave the vertical by about 4°.
        ..seen_from_above(floor, metal, 0.1)
    }
}

#[test]
fn a_polished_metal_reflects_the_suns_disc() {
    let Some(gpu) = test_gpu() else { return };
    let (disc_radiance, _) = sun_disk(Vec3::ONE, (0.5 * ANGULAR_DIAMETER).cos()).unwrap();
    // Roughness 0.05: the glossy lobe, where both strategies meet under MIS; 0: the mirror
    // lobe, a delta that light sampling cannot reach, whose ray alone carries the disc.
    for roughness in [0.05, 0.0] {
        let img = direct_light_image(&gpu, &metal_floor_under_the_sun(roughness), SIZE, 64);
        let mean = img.pixels.iter().map(|p| p[0] as f64).sum::<f64>() / img.pixels.len() as f64;
        let ratio = mean / disc_radiance.x as f64;
        let worst = img
            .pixels
            .iter()
            .map(|p| (p[0] as f64 / disc_radiance.x as f64 - 1.0).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "roughness {roughness}: the floor reflects {ratio:.4} of the disc's radiance \
             {:.3} (worst pixel off by {worst:.4})",
            disc_radiance.x
        );
        assert!(
            (ratio - 1.0).abs() < 0.02,
            "roughness {roughness}: the floor reflects {ratio:.4} of the sun disc's radiance"
        );
        assert!(
            worst < 0.1,
            "roughness {roughness}: a pixel off by {worst:.4}"
        );
    }
}

/// Radiance a pixel-centre view of the floor at `x` receives from the disc (the red channel),
/// integrated over the disc on the CPU with the BRDF's twin: the floor's normal is +y, so the
/// tangent frame takes world (x, y, z) to (x, z, y), a mirror that an isotropic BRDF ignores.
fn expected_from_disc(m: &BrdfMaterial, eye: Vec3, x: Vec3, cos_radius: f32, radiance: f32) -> f64 {
    let wo = (eye - x).normalize();
    let wo_t = Vec3::new(wo.x, wo.z, wo.y);
    let n = 128;
    let mut sum = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            // Uniform in solid angle over the cap about +y, midpoints of an n × n grid.
            let cos_t = 1.0 - (i as f32 + 0.5) / n as f32 * (1.0 - cos_radius);
            let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
            let phi = 2.0 * std::f32::consts::PI * (j as f32 + 0.5) / n as f32;
            let wi_t = Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
            sum += brdf::eval(m, wo_t, wi_t).x as f64;
        }
    }
    let solid_angle = 2.0 * std::f64::consts::PI * (1.0 - cos_radius as f64);
    sum / (n * n) as f64 * solid_angle * radiance as f64
}

/// The sun's real size (0.53°) on a floor of roughness 0.05, whose lobe is about as wide as
/// the disc: light samples and BRDF rays each find a share of the reflection, and their MIS
/// weights must add up to one. Against the disc's integral of the BRDF, pixel by pixel.
#[test]
fn the_suns_reflection_splits_between_light_samples_and_brdf_rays() {
    let Some(gpu) = test_gpu() else { return };
    let size = 16;
    let roughness = 0.05;
    let mut scene = metal_floor_under_the_sun(roughness);
    scene.directional_lights[0].angular_diameter = SUN_ANGULAR_DIAMETER;
    // 0.002 rad across: every pixel's mirror direction within 0.06° of the zenith.
    scene.cameras[0].yfov = 0.002;
    let cos_radius = (0.5 * SUN_ANGULAR_DIAMETER).cos();
    let (disc_radiance, _) = sun_disk(Vec3::ONE, cos_radius).unwrap();
    let img = direct_light_image(&gpu, &scene, size, 1024);
    let m = BrdfMaterial {
        base_color: Vec3::ONE,
        metallic: 1.0,
        roughness,
        dielectric_f0: Vec3::splat(0.04),
        dielectric_f90: 1.0,
        model: BrdfModel::Layered,
    };
    let eye = Vec3::new(0.0, 3.0, 0.0);
    let view = GpuView::new(&scene.camera(None).unwrap(), size, size);
    let (f, r, u) = (
        Vec3::from(view.forward),
        Vec3::from(view.right),
        Vec3::from(view.up),
    );
    let (mut got, mut want) = (0.0, 0.0);
    for (i, p) in img.pixels.iter().enumerate() {
        let (px, py) = (
            (i as u32 % size) as f32 + 0.5,
            (i as u32 / size) as f32 + 0.5,
        );
        let ndc = (px / size as f32 * 2.0 - 1.0, 1.0 - py / size as f32 * 2.0);
        let d = f + r * (ndc.0 * view.tan_half_fov * view.aspect) + u * (ndc.1 * view.tan_half_fov);
        let x = eye + d * (-eye.y / d.y);
        got += p[0] as f64;
        want += expected_from_disc(&m, eye, x, cos_radius, disc_radiance.x);
    }
    eprintln!(
        "the sun on roughness {roughness}: image {:.1}, the disc's integral {:.1} (mean per pixel)",
        got / (size * size) as f64,
        want / (size * size) as f64
    );
    assert!(
        (got / want - 1.0).abs() < 0.02,
        "the sun's reflection: image {got:.1} against the disc's integral {want:.1}"
    );
}
