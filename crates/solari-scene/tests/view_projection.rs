//! `view_project_direction` (`view.wesl`) against its Rust twin `GpuView::project_direction`
//! on lavapipe, and the twin against `GpuView::ray_direction`, whose inverse it is: random
//! cameras (orientation, position, field of view, image size, jitter) and directions, and
//! adversarial ones: the view's axis, image corners, directions nearly along the image plane,
//! behind the view and exactly on its plane.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Quat, Vec2, Vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_scene::case_kernel::CaseKernel;
use solari_scene::gpu::test_gpu;
use solari_scene::gpu_types::GpuView;
use solari_scene::model::Camera;

/// WGSL twin: `Case` in `shaders/view_project_test.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Case {
    view: GpuView,
    direction: [f32; 4],
}

fn random_view(rng: &mut Pcg32) -> GpuView {
    let axis = Vec3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    )
    .normalize_or(Vec3::Y);
    let camera = Camera {
        name: "random".into(),
        transform: Mat4::from_rotation_translation(
            Quat::from_axis_angle(axis, rng.random_range(-3.1..3.1)),
            Vec3::new(
                rng.random_range(-100.0..100.0),
                rng.random_range(-100.0..100.0),
                rng.random_range(-100.0..100.0),
            ),
        ),
        yfov: rng.random_range(0.1..2.4),
        aspect: None,
        znear: 0.01,
    };
    // Aspect ratios 1:4 to 4:1. (At 3437×17 and a 135° vertical field, nearly 180° across,
    // f32 loses 0.07 pixels on the round trip.)
    let height = rng.random_range(16..3000);
    let width = ((height as f32 * rng.random_range(0.25..4.0)) as u32).max(1);
    let view = GpuView::new(&camera, width, height);
    view.with_jitter([rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5)])
}

/// A pixel position in or around the image (a quarter of its size beyond each side).
fn random_pixel(rng: &mut Pcg32, v: &GpuView) -> Vec2 {
    let (w, h) = (v.width as f32, v.height as f32);
    Vec2::new(
        rng.random_range(-0.25 * w..1.25 * w),
        rng.random_range(-0.25 * h..1.25 * h),
    )
}

#[test]
fn the_projection_inverts_the_view_ray() {
    let mut rng = Pcg32::seed_from_u64(0x51e1);
    for _ in 0..2000 {
        let v = random_view(&mut rng);
        let p = random_pixel(&mut rng, &v);
        let back = v
            .project_direction(v.ray_direction(p))
            .expect("a view ray points ahead");
        let want = p + Vec2::from(v.jitter);
        let scale = v.width.max(v.height) as f32;
        assert!(
            (back - want).abs().max_element() <= 2e-5 * scale,
            "{p} projects back to {back}, not {want}, in {v:?}"
        );
    }
    let v = random_view(&mut rng);
    let (forward, right) = (Vec3::from(v.forward), Vec3::from(v.right));
    assert_eq!(v.project_direction(-forward), None, "behind");
    assert_eq!(v.project_direction(right), None, "on the image plane");
    assert_eq!(v.project_direction(Vec3::NAN), None, "NaN");
}

#[test]
fn gpu_projection_matches_the_cpu_twin() {
    let Some(gpu) = test_gpu() else { return };
    let mut rng = Pcg32::seed_from_u64(0xd17);
    let mut cases = Vec::new();
    for i in 0..4000 {
        let v = random_view(&mut rng);
        let (forward, right, up) = (Vec3::from(v.forward), Vec3::from(v.right), Vec3::from(v.up));
        let d = match i % 8 {
            // The axis, the image's corners and directions nearly along the image plane.
            0 => forward,
            1 => v.with_jitter([0.0; 2]).ray_direction(Vec2::ZERO),
            2 => v.ray_direction(Vec2::new(v.width as f32, v.height as f32)),
            3 => right + forward * rng.random_range(1e-3..1e-2),
            // Behind the view and exactly on its plane.
            4 => -forward + up * rng.random_range(-1.0..1.0),
            5 => right * rng.random_range(-1.0..1.0) + up,
            // Random directions, any length.
            _ => {
                Vec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                ) * rng.random_range(1e-3..1e3)
            }
        };
        cases.push(Case {
            view: v,
            direction: d.extend(0.0).into(),
        });
    }
    let results: Vec<[f32; 4]> = CaseKernel::run_test_module(
        &gpu,
        vec![],
        "view_project_test",
        include_str!("shaders/view_project_test.wesl"),
        0,
        &cases,
    )
    .expect("dispatch");
    let (mut ahead, mut behind, mut on_plane) = (0, 0, 0);
    for (c, r) in cases.iter().zip(&results) {
        let d = Vec3::new(c.direction[0], c.direction[1], c.direction[2]);
        let gpu_p = Vec2::new(r[0], r[1]);
        // Along the image plane the two sides' rounding may put the direction on either side
        // of it: either answer, but a number.
        if d.dot(Vec3::from(c.view.forward)).abs() <= 1e-5 * d.length() {
            on_plane += 1;
            assert!(gpu_p.is_finite(), "{gpu_p} for {d} in {:?}", c.view);
            continue;
        }
        match c.view.project_direction(d) {
            Some(p) => {
                ahead += 1;
                // f32 on both sides, the GPU's divisions less exact: relative to the result.
                let tolerance = 1e-4
                    * p.abs()
                        .max_element()
                        .max(c.view.width.max(c.view.height) as f32);
                assert!(
                    (gpu_p - p).abs().max_element() <= tolerance,
                    "GPU {gpu_p} against CPU {p} for {d} in {:?}",
                    c.view
                );
            }
            None => {
                behind += 1;
                assert_eq!(gpu_p, Vec2::splat(-1e9), "{d} is behind {:?}", c.view);
            }
        }
    }
    println!("{ahead} directions ahead, {behind} behind, {on_plane} on the image plane");
    assert!(
        ahead > 2000 && behind > 800,
        "{ahead} ahead, {behind} behind"
    );
}
