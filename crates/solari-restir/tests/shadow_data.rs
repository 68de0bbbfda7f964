//! What ReSTIR DI's final shadow ray reports (`RestirDi::shadow`), on lavapipe: finite and
//! non-negative everywhere; a blocked sample reports the light it removed together with a
//! positive penumbra width; and the width follows the light's apparent size, so the sun's
//! 0.53° disk casts penumbrae far narrower, relative to the scene, than the Cornell box's
//! ceiling panel.

mod common;

use common::{DirectLight, di_settings, tile_settings};
use solari_scene::gpu::test_gpu;
use solari_scene::packing::unpack_bf16x2;
use solari_scene::{Scene, default_scene, load_gltf};

/// One frame's shadow data (removed luminance, penumbra width) and the scene's diagonal.
fn shadow_data(scene: &Scene, size: u32) -> Option<(Vec<[f32; 2]>, f32)> {
    let gpu = test_gpu()?;
    let backend = gpu.backend(Default::default()).expect("backend");
    let mut direct = DirectLight::new(&gpu, backend, scene, size, di_settings(), tile_settings());
    let camera = scene.camera(None).expect("camera");
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    direct.encode(&gpu, scene, &camera, &mut encoder);
    gpu.queue.submit([encoder.finish()]);
    let bytes = gpu
        .read_buffer(direct.di.shadow(), size as u64 * size as u64 * 4)
        .expect("read back");
    let (lo, hi) = scene.bounds();
    let words: &[u32] = bytemuck::cast_slice(&bytes);
    let data = words.iter().map(|&w| unpack_bf16x2(w)).collect();
    Some((data, (hi - lo).length()))
}

fn median(mut v: Vec<f32>) -> f32 {
    v.sort_by(f32::total_cmp);
    v[v.len() / 2]
}

#[test]
fn blocked_samples_report_their_light_and_a_penumbra_the_light_size_sets() {
    let sun_boxes = load_gltf(solari_testdata::scene("sun_boxes")).expect("scene");
    let cases = [
        ("cornell_box", default_scene::cornell_box()),
        ("sun_boxes", sun_boxes),
    ];
    let mut relative = Vec::new();
    for (name, scene) in cases {
        let Some((data, diagonal)) = shadow_data(&scene, 64) else {
            return;
        };
        assert!(
            data.iter().flatten().all(|v| v.is_finite() && *v >= 0.0),
            "{name}: a negative or non-finite value"
        );
        let blocked: Vec<&[f32; 2]> = data.iter().filter(|s| s[0] > 0.0).collect();
        assert!(
            blocked.len() > 50,
            "{name}: only {} blocked samples",
            blocked.len()
        );
        assert!(
            blocked.iter().all(|s| s[1] > 0.0),
            "{name}: a blocked sample of a light with a size reports no penumbra"
        );
        assert!(
            data.iter().all(|s| s[0] > 0.0 || s[1] == 0.0),
            "{name}: a penumbra where nothing removed light"
        );
        let width = median(blocked.iter().map(|s| s[1] / diagonal).collect());
        eprintln!(
            "{name}: {} of {} pixels blocked, median penumbra {width:.2e} of the scene's diagonal",
            blocked.len(),
            data.len()
        );
        relative.push(width);
    }
    // The sun's disk: at most 2 tan(0.265°) of any blocker distance, itself under the
    // diagonal.
    assert!(relative[1] < 2.0 * 0.265f32.to_radians().tan());
    assert!(
        relative[0] > 10.0 * relative[1],
        "the ceiling panel's penumbrae ({}) are not far wider than the sun's ({})",
        relative[0],
        relative[1]
    );
}
