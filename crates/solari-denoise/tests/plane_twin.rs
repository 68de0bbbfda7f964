//! The denoiser's tangent-plane distance (`denoise_plane.wesl`: from the tap's view depth
//! alone, affine in the tap's offset) against the geometric distance of the tap's point from
//! the centre's tangent plane, computed in f64 from both points' positions, on lavapipe:
//! random cameras (orientation, field of view, aspect, image size, jitter), pixels, steps of
//! 1 to 128, offsets of ±2 steps, depths over seven decades, and adversarial cases: taps on
//! the plane (distance 0), normals at grazing angles to the view ray, pixels at the image's
//! corners, and a camera far from the origin.

use bytemuck::{Pod, Zeroable};
use glam::{DMat3, DVec3, Quat, Vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_scene::case_kernel::CaseKernel;
use solari_scene::gpu::test_gpu;
use solari_scene::gpu_types::GpuView;

/// WGSL twin: `Case` in `shaders/denoise_plane_test.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Case {
    view: GpuView,
    pixel_step: [u32; 4],
    offset: [i32; 4],
    normal_depth: [f32; 4],
    tap: [f32; 4],
}

// The view ray's direction through image point `pixel` (in pixels from the top left), as
// `view_ray_direction` defines it, in f64.
fn direction(v: &GpuView, pixel: [f64; 2]) -> DVec3 {
    let (w, h) = (v.width as f64, v.height as f64);
    let x = pixel[0] + v.jitter[0] as f64;
    let y = pixel[1] + v.jitter[1] as f64;
    let ndc = [x / w * 2.0 - 1.0, 1.0 - y / h * 2.0];
    let t = v.tan_half_fov as f64;
    let d = |a: [f32; 3]| DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
    d(v.forward) + d(v.right) * (ndc[0] * t * v.aspect as f64) + d(v.up) * (ndc[1] * t)
}

// The point at view depth `z` on the ray through pixel `p`'s centre.
fn point(v: &GpuView, p: [i64; 2], z: f64) -> DVec3 {
    let o = DVec3::new(v.origin[0] as f64, v.origin[1] as f64, v.origin[2] as f64);
    o + direction(v, [p[0] as f64 + 0.5, p[1] as f64 + 0.5]) * z
}

struct Expected {
    distance: f64,
    // The farther point's distance from the camera: f32 rounding scales with it. (The
    // filters' depth tolerance is 0.005 of the centre's view depth by default.)
    scale: f64,
}

fn expected(c: &Case) -> Expected {
    let v = &c.view;
    let p = [c.pixel_step[0] as i64, c.pixel_step[1] as i64];
    let step = c.pixel_step[2] as i64;
    let q = [
        p[0] + c.offset[0] as i64 * step,
        p[1] + c.offset[1] as i64 * step,
    ];
    let n = DVec3::new(
        c.normal_depth[0] as f64,
        c.normal_depth[1] as f64,
        c.normal_depth[2] as f64,
    );
    let (zc, zq) = (c.normal_depth[3] as f64, c.tap[0] as f64);
    let (pc, pq) = (point(v, p, zc), point(v, q, zq));
    let o = DVec3::new(v.origin[0] as f64, v.origin[1] as f64, v.origin[2] as f64);
    Expected {
        distance: n.dot(pq - pc).abs(),
        scale: (pq - o).length().max((pc - o).length()),
    }
}

fn random_view(rng: &mut Pcg32, far: bool) -> GpuView {
    let axis = Vec3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    )
    .normalize_or(Vec3::Y);
    let basis = DMat3::from_quat(
        Quat::from_axis_angle(axis, rng.random_range(0.0..std::f32::consts::TAU)).as_dquat(),
    );
    let f = |v: DVec3| v.as_vec3().to_array();
    let width = rng.random_range(1..4096u32);
    let height = rng.random_range(1..4096u32);
    let reach = if far { 1e3 } else { 10.0 };
    GpuView {
        origin: [0, 1, 2].map(|_| rng.random_range(-reach..reach)),
        tan_half_fov: rng.random_range(5f32..80.0).to_radians().tan(),
        right: f(basis.x_axis),
        aspect: width as f32 / height as f32,
        up: f(basis.y_axis),
        width,
        forward: f(-basis.z_axis),
        height,
        jitter: [rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5)],
        ..GpuView::default()
    }
}

fn cases() -> Vec<Case> {
    let mut rng = Pcg32::seed_from_u64(0x706c616e);
    (0..8000)
        .map(|k| {
            let view = random_view(&mut rng, k % 9 == 0);
            let corner = k % 13 == 0;
            let p = if corner {
                [
                    [0, view.width - 1][rng.random_range(0..2)],
                    [0, view.height - 1][rng.random_range(0..2)],
                ]
            } else {
                [
                    rng.random_range(0..view.width),
                    rng.random_range(0..view.height),
                ]
            };
            let step = 1u32 << rng.random_range(0..8);
            let offset = [rng.random_range(-2..=2), rng.random_range(-2..=2)];
            let zc = 10f32.powf(rng.random_range(-3.0..4.0));
            let d = direction(&view, [p[0] as f64 + 0.5, p[1] as f64 + 0.5]).normalize();
            let mut n = DVec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            )
            .normalize_or(DVec3::Z);
            if k % 7 == 0 {
                // Grazing: the normal nearly perpendicular to the centre's view ray.
                n = (n - d * n.dot(d) + d * rng.random_range(-1e-3..1e-3)).normalize();
            } else if n.dot(d) > 0.0 {
                n = -n;
            }
            let mut case = Case {
                view,
                pixel_step: [p[0], p[1], step, 0],
                offset: [offset[0], offset[1], 0, 0],
                normal_depth: [n.x as f32, n.y as f32, n.z as f32, zc],
                tap: [zc * rng.random_range(0.5..2.0f32), 0.0, 0.0, 0.0],
            };
            if k % 5 == 0 {
                // The tap on the plane: where the tap's ray meets it (if in front).
                let q = [
                    p[0] as f64 + (offset[0] * step as i32) as f64 + 0.5,
                    p[1] as f64 + (offset[1] * step as i32) as f64 + 0.5,
                ];
                let centre = [p[0] as f64 + 0.5, p[1] as f64 + 0.5];
                let n32 = DVec3::new(n.x as f32 as f64, n.y as f32 as f64, n.z as f32 as f64);
                let zq =
                    n32.dot(direction(&view, centre)) * zc as f64 / n32.dot(direction(&view, q));
                if zq > 0.0 && zq.is_finite() {
                    case.tap[0] = zq as f32;
                }
            }
            case
        })
        .collect()
}

#[test]
fn the_plane_distance_matches_the_geometric_one() {
    let Some(gpu) = test_gpu() else { return };
    let cases = cases();
    let results: Vec<[f32; 4]> = CaseKernel::run_test_module(
        &gpu,
        solari_denoise::modules(),
        "denoise_plane_test",
        include_str!("../shaders/denoise_plane_test.wesl"),
        0,
        &cases,
    )
    .expect("dispatch");
    let mut worst = 0.0f64;
    for (c, r) in cases.iter().zip(&results) {
        let e = expected(c);
        let error = (r[0] as f64 - e.distance).abs() / e.scale;
        worst = worst.max(error);
        assert!(
            error < 4e-6,
            "GPU {} against {} (points {} from the camera: error {error:.2e} of that) for {c:?}",
            r[0],
            e.distance,
            e.scale
        );
    }
    println!("worst error, relative to the points' distance from the camera: {worst:.2e}");
}
