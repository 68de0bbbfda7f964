//! Both backends render the same primary-ray images of every bundled test scene and the built-in
//! scene: instance ids per pixel must match except along silhouette ties, and albedo must
//! match where the instance does.

use solari_scene::gpu::test_gpu;
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::gpu_types::GpuView;
use solari_scene::shaders::Backend;
use solari_scene::view_pass::{DebugView, ViewPass};
use solari_scene::*;

#[test]
fn backends_render_the_same_images() {
    let Some(gpu) = test_gpu() else { return };
    if !gpu.has_ray_query() {
        assert_ne!(
            std::env::var("SOLARI_REQUIRE_GPU").as_deref(),
            Ok("1"),
            "ray queries required"
        );
        return;
    }
    let mut scenes = vec![
        default_scene::cornell_box(),
        textured_scene::textured_spheres(),
    ];
    for path in solari_testdata::all_scenes() {
        scenes.push(load_gltf(path).unwrap());
    }
    let (w, h) = (96, 96);
    let options = GpuSceneOptions {
        max_texture_size: 64,
        ..Default::default()
    };
    for scene in &scenes {
        let camera = scene.camera(None).unwrap();
        let mut images = Vec::new();
        for backend in [Backend::Software, Backend::RayQuery] {
            let gs = GpuScene::new(&gpu, scene, backend, &options).unwrap();
            // The specialised single-instance traversal where it applies: it must render the
            // same image as ray queries too.
            let pass = ViewPass::primary(&gpu, backend, TraceVariant::for_scene(&gs)).unwrap();
            let mut per_view = Vec::new();
            for v in [DebugView::Instance, DebugView::Albedo] {
                let mut view = GpuView::new(&camera, w, h);
                view.view_mode = v as u32;
                let bytes = pass
                    .run(&gpu, &gs, &pass.target(&gpu, &view).unwrap())
                    .unwrap();
                per_view.push(bytemuck::cast_slice::<u8, [f32; 4]>(&bytes).to_vec());
            }
            images.push(per_view);
        }
        let (sw, rq) = (&images[0], &images[1]);
        let mut differing = 0;
        for i in 0..(w * h) as usize {
            let same_instance = sw[0][i][0].to_bits() == rq[0][i][0].to_bits();
            if !same_instance {
                differing += 1;
            } else if sw[0][i][1].to_bits() == rq[0][i][1].to_bits() {
                // Same triangle: the albedo (interpolated and textured) must match closely.
                for c in 0..3 {
                    assert!(
                        (sw[1][i][c] - rq[1][i][c]).abs() < 2e-3,
                        "{camera:?} pixel {i}: {:?} vs {:?}",
                        sw[1][i],
                        rq[1][i]
                    );
                }
            }
        }
        // Silhouette pixels may fall either way; no more than 0.5% of the image.
        assert!(
            differing * 200 <= (w * h) as usize,
            "{}: {differing} pixels differ",
            camera.name
        );
    }
}
