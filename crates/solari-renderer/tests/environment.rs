//! An environment map in the real-time frame (lavapipe): it is shown where camera rays escape,
//! and it lights surfaces through GI, which gathers it where its rays escape (DI samples only
//! the light list). A Lambertian floor under a map converges to `albedo / π ×` the irradiance
//! that a CPU quadrature of the map gives, in each GI mode that traces rays.

use solari_renderer::{GiMode, RealtimeRenderer, RealtimeSettings};
use solari_scene::gpu::test_gpu;

mod common;
#[path = "../../solari-reference/tests/env_common/mod.rs"]
mod env_common;

use common::{settings, upload};

#[test]
fn a_floor_under_an_environment_map_converges_to_its_irradiance() {
    let Some(gpu) = test_gpu() else { return };
    let backend = gpu.backend(Default::default()).expect("backend");
    let albedo = 0.8;
    let scene = env_common::floor_under_sky(albedo);
    let expected = env_common::floor_irradiance(&scene) * (albedo as f64 / std::f64::consts::PI);
    let gpu_scene = upload(&gpu, backend, &scene);
    let camera = scene.camera(None).expect("camera");
    let size = 32;
    for gi in [GiMode::Path, GiMode::Restir] {
        let s = RealtimeSettings { gi, ..settings() };
        let mut renderer = RealtimeRenderer::new(&gpu, backend, &scene, &gpu_scene, size, size, s)
            .expect("renderer");
        let frames = 48;
        let mut sum = glam::DVec3::ZERO;
        for _ in 0..frames {
            renderer
                .render(&gpu, &scene, &gpu_scene, &camera)
                .expect("frame");
            let pixels = renderer.read_output(&gpu).expect("read back");
            for p in &pixels {
                sum += glam::Vec3::from_array([p[0], p[1], p[2]]).as_dvec3();
            }
        }
        let mean = sum / (frames as f64 * (size * size) as f64);
        eprintln!("{gi:?}: {mean:.4} against {expected:.4}");
        for c in 0..3 {
            assert!(
                (mean[c] / expected[c] - 1.0).abs() < 0.03,
                "{gi:?} channel {c}: {} against {}",
                mean[c],
                expected[c]
            );
        }
    }
}
