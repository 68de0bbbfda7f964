//! The traced G-buffer's texture footprint: `hit.wesl`'s `triangle_barycentric_differentials`
//! matches its Rust twin (`ray_differentials`) on random and adversarial cases (GPU: lavapipe
//! in CI), and the twin matches offset rays intersected with the triangle's plane directly.

use bytemuck::{Pod, Zeroable};
use glam::{DVec2, Vec2, Vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_scene::case_kernel::CaseKernel;
use solari_scene::default_scene::cornell_box;
use solari_scene::gpu::test_gpu;
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions};
use solari_scene::ray_differentials::barycentric_differentials;
use solari_scene::shaders::{Backend, compose};

/// WGSL twin: `Case` in `shaders/differentials_test.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Case {
    e1: [f32; 3],
    t: f32,
    e2: [f32; 3],
    _pad0: f32,
    dir: [f32; 3],
    _pad1: f32,
    ddir_dx: [f32; 3],
    _pad2: f32,
    ddir_dy: [f32; 3],
    _pad3: f32,
}

fn vec(rng: &mut Pcg32, scale: f32) -> Vec3 {
    Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 * scale - scale
}

fn cases() -> Vec<Case> {
    let mut rng = Pcg32::seed_from_u64(7);
    (0..4000)
        .map(|i| {
            let e1 = vec(&mut rng, 2.0);
            // Every 50th case degenerate (parallel edges) or edge-on (ray in the plane).
            let e2 = if i % 50 == 0 {
                e1 * 0.5
            } else {
                vec(&mut rng, 2.0)
            };
            let mut dir = vec(&mut rng, 1.0);
            if i % 50 == 25 {
                let n = e1.cross(e2);
                dir -= n * dir.dot(n) / n.dot(n);
            }
            let pixel = rng.random_range(1e-4f32..1e-2);
            Case {
                e1: e1.into(),
                t: rng.random_range(0.1f32..100.0),
                e2: e2.into(),
                dir: dir.into(),
                ddir_dx: (vec(&mut rng, 1.0) * pixel).into(),
                ddir_dy: (vec(&mut rng, 1.0) * pixel).into(),
                ..Zeroable::zeroed()
            }
        })
        .collect()
}

fn twin(c: &Case) -> [Vec2; 2] {
    barycentric_differentials(
        c.e1.into(),
        c.e2.into(),
        c.t,
        c.dir.into(),
        [c.ddir_dx.into(), c.ddir_dy.into()],
    )
}

#[test]
fn gpu_differentials_match_the_cpu_twin() {
    let Some(gpu) = test_gpu() else { return };
    let scene = GpuScene::new(
        &gpu,
        &cornell_box(),
        Backend::Software,
        &GpuSceneOptions::default(),
    )
    .expect("scene");
    let (empty_layout, empty) = gpu.empty_group();
    let module = [(
        "differentials_test",
        include_str!("shaders/differentials_test.wesl"),
    )];
    let wgsl = compose("differentials_test", Backend::Software, &module).expect("compose");
    let layouts = [Some(scene.layout()), Some(&empty_layout), None];
    let kernel = CaseKernel::new(&gpu, "differentials_test", &wgsl, &layouts, 2).expect("kernel");
    let cases = cases();
    let results: Vec<[f32; 4]> = kernel
        .run(&gpu, &[Some(scene.bind_group()), Some(&empty)], &cases)
        .expect("dispatch");
    let mut zero = 0;
    for (i, (c, r)) in cases.iter().zip(&results).enumerate() {
        let [dx, dy] = twin(c);
        let cpu = [dx.x, dx.y, dy.x, dy.y];
        if cpu == [0.0; 4] {
            zero += 1;
        }
        for k in 0..4 {
            // Float rounding of a few dot and cross products, relative to the case's scale.
            let scale = cpu.iter().fold(1e-6f32, |m, v| m.max(v.abs()));
            assert!(
                (r[k] - cpu[k]).abs() <= 1e-3 * scale,
                "case {i} {c:?}: GPU {r:?}, CPU {cpu:?}"
            );
        }
    }
    assert!(
        zero >= 80,
        "the degenerate and edge-on cases give zero ({zero})"
    );
}

/// The twin's answer is what offset rays give: each direction differential, scaled down,
/// intersected with the triangle's plane and solved for barycentrics, changes them by the
/// twin's derivative times the scale.
#[test]
fn the_twin_matches_offset_rays_intersected_directly() {
    let mut rng = Pcg32::seed_from_u64(11);
    let mut checked = 0;
    for _ in 0..2000 {
        let (p0, e1, e2) = (vec(&mut rng, 2.0), vec(&mut rng, 2.0), vec(&mut rng, 2.0));
        let n = e1.cross(e2);
        let origin = vec(&mut rng, 5.0);
        let (u, v) = (rng.random_range(0.1f32..0.4), rng.random_range(0.1f32..0.4));
        let hit = p0 + u * e1 + v * e2;
        let dir = hit - origin;
        // Skip near-grazing views, where the first-order answer is poor by nature.
        if dir.normalize().dot(n.normalize()).abs() < 0.2 {
            continue;
        }
        let ddir = [vec(&mut rng, 1.0), vec(&mut rng, 1.0)];
        let d = barycentric_differentials(e1, e2, 1.0, dir, ddir);
        for (k, dd) in ddir.iter().enumerate() {
            // Central difference in f64, so rounding does not swamp the derivative.
            let (p0, e1, e2, n) = (p0.as_dvec3(), e1.as_dvec3(), e2.as_dvec3(), n.as_dvec3());
            let (origin, dir, dd) = (origin.as_dvec3(), dir.as_dvec3(), dd.as_dvec3());
            let bary_along = |h: f64| {
                // The offset ray meets the plane at t' = dot(p0 - o, n) / dot(dir', n).
                let dir2 = dir + dd * h;
                let q = origin + dir2 * ((p0 - origin).dot(n) / dir2.dot(n)) - p0;
                DVec2::new(q.cross(e2).dot(n), e1.cross(q).dot(n)) / n.dot(n)
            };
            let h = 1e-4;
            let finite = ((bary_along(h) - bary_along(-h)) / (2.0 * h)).as_vec2();
            let err = (finite - d[k]).abs().max_element();
            let scale = d[k].abs().max_element().max(1e-3);
            assert!(
                err <= 1e-3 * scale,
                "offset ray {k}: finite difference {finite}, twin {}",
                d[k]
            );
        }
        checked += 1;
    }
    assert!(checked > 1000, "{checked} cases checked");
}
