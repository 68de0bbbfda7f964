//! `RestirDiSettings::reuse_light_threshold` on lavapipe: a scene whose lights have no more
//! sampling elements than the threshold renders exactly as with both reuse steps off, one with
//! more exactly as with them on, and a scene that gains lights starts reusing. A frame
//! without reuse runs DI as one pass, where `initial_visibility` changes nothing.

mod common;

use glam::Vec3;
use solari_lights::LightList;
use solari_restir::RestirDiSettings;
use solari_scene::gpu::{Gpu, test_gpu};
use solari_scene::shaders::Backend;
use solari_scene::{DirectionalLight, Scene, default_scene};

use common::{DirectLight, SIZE, di_settings, tile_settings};

const FRAMES: usize = 6;

/// DI's output of `FRAMES` frames of a still camera, and whether each skipped reuse; with
/// `more_lights`, that scene's lights replace `scene`'s before the fourth frame.
fn run(
    gpu: &Gpu,
    backend: Backend,
    scene: &Scene,
    more_lights: Option<&Scene>,
    settings: RestirDiSettings,
) -> (Vec<Vec<[f32; 4]>>, Vec<bool>) {
    let mut direct = DirectLight::new(gpu, backend, scene, SIZE, settings, tile_settings());
    let camera = scene.camera(None).expect("camera");
    let mut images = Vec::new();
    let mut skipped = Vec::new();
    let mut now = scene;
    let reuse = settings.temporal || settings.spatial;
    for frame in 0..FRAMES {
        if frame == 3
            && let Some(more) = more_lights
        {
            direct.set_lights(gpu, more);
            now = more;
        }
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let ran = direct.encode(gpu, now, &camera, &mut encoder);
        gpu.queue.submit([encoder.finish()]);
        images.push(direct.read_output(gpu));
        let skip = direct.di.reuse_skipped();
        skipped.push(skip);
        // Without reuse this frame the first pass does it all.
        assert!(ran.contains("di_initial_temporal"));
        assert_eq!(
            ran.contains("di_spatial_shade"),
            reuse && !skip,
            "frame {frame}"
        );
    }
    (images, skipped)
}

/// `scene` with a sun added: one sampling element more.
fn with_sun(scene: &Scene) -> Scene {
    let mut sunny = scene.clone();
    sunny.directional_lights.push(DirectionalLight {
        name: "sun".into(),
        direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
        irradiance: Vec3::splat(2.0),
        angular_diameter: 0.01,
    });
    sunny
}

fn with_threshold(reuse_light_threshold: u32) -> RestirDiSettings {
    RestirDiSettings {
        reuse_light_threshold,
        ..di_settings()
    }
}

#[test]
fn few_lights_skip_reuse_exactly_and_more_bring_it_back() {
    let Some(gpu) = test_gpu() else { return };
    let backend = gpu.backend(Default::default()).expect("backend");
    let scene = default_scene::cornell_box();
    let elements = LightList::build(&scene).sampling_elements();
    assert!(
        elements >= 2,
        "the Cornell box's lamp has {elements} triangles"
    );

    let (reuse, never) = run(&gpu, backend, &scene, None, with_threshold(0));
    assert!(never.iter().all(|s| !s), "threshold 0 never skips");
    let off = RestirDiSettings {
        temporal: false,
        spatial: false,
        ..di_settings()
    };
    let (plain, _) = run(&gpu, backend, &scene, None, off);
    // Otherwise the comparisons below could not tell the two apart.
    assert_ne!(
        reuse[FRAMES - 1],
        plain[FRAMES - 1],
        "reuse changes the image"
    );

    let (at, skipped) = run(&gpu, backend, &scene, None, with_threshold(elements));
    assert!(
        skipped.iter().all(|s| *s),
        "{elements} elements, threshold {elements}"
    );
    assert_eq!(at, plain, "skipped reuse is reuse off, bit for bit");
    let (below, skipped) = run(&gpu, backend, &scene, None, with_threshold(elements - 1));
    assert!(skipped.iter().all(|s| !s));
    assert_eq!(below, reuse, "above the threshold reuse runs as always");

    // A sun brings one more element: over the threshold from its first frame on.
    let sunny = with_sun(&scene);
    let (_, skipped) = run(
        &gpu,
        backend,
        &scene,
        Some(&sunny),
        with_threshold(elements),
    );
    assert_eq!(skipped, [true, true, true, false, false, false]);
}

#[test]
fn the_threshold_includes_its_count_and_zero_never_skips() {
    let s = with_threshold(13);
    assert!(s.skips_reuse(0) && s.skips_reuse(13));
    assert!(!s.skips_reuse(14));
    assert!(
        !with_threshold(0).skips_reuse(0),
        "0: reuse as temporal/spatial say"
    );
    // An environment map counts as u32::MAX elements: no finite threshold below it skips.
    assert!(!with_threshold(u32::MAX - 1).skips_reuse(u32::MAX));
    assert!(
        !RestirDiSettings::default().skips_reuse(1),
        "the component never skips by default"
    );
}

/// `RestirDiSettings::initial_visibility` acts only in frames with reuse: without reuse the
/// one-pass pipeline does not trace it (the final shadow ray is the same ray and zeroes the
/// same light), so the image is bit for bit the one without it; with reuse it still changes
/// the image (occluded samples no longer reach the neighbours' merges).
#[test]
fn initial_visibility_acts_only_with_reuse() {
    let Some(gpu) = test_gpu() else { return };
    let backend = gpu.backend(Default::default()).expect("backend");
    let scene = default_scene::cornell_box();
    let with = |reuse: bool, initial_visibility: bool| RestirDiSettings {
        temporal: reuse,
        spatial: reuse,
        initial_visibility,
        ..di_settings()
    };
    let (off, _) = run(&gpu, backend, &scene, None, with(false, false));
    let (off_tested, _) = run(&gpu, backend, &scene, None, with(false, true));
    assert_eq!(off, off_tested, "without reuse the setting changes nothing");
    let (on, _) = run(&gpu, backend, &scene, None, with(true, false));
    let (on_tested, _) = run(&gpu, backend, &scene, None, with(true, true));
    assert_ne!(
        on[FRAMES - 1],
        on_tested[FRAMES - 1],
        "with reuse the initial test changes the image"
    );
}

/// Frames without reuse keep no final reservoirs (nothing would read them): none are
/// allocated while the threshold skips reuse, the memory report leaves their 20 bytes a
/// pixel out, and the first frame with reuse allocates them and renders finite light.
#[test]
fn frames_without_reuse_keep_no_reservoirs() {
    let Some(gpu) = test_gpu() else { return };
    let backend = gpu.backend(Default::default()).expect("backend");
    let scene = default_scene::cornell_box();
    let elements = LightList::build(&scene).sampling_elements();
    let sunny = with_sun(&scene);
    let settings = with_threshold(elements);
    let mut direct = DirectLight::new(&gpu, backend, &scene, SIZE, settings, tile_settings());
    let camera = scene.camera(None).expect("camera");
    let reservoir_bytes = (SIZE * SIZE) as u64 * size_of::<solari_restir::GpuReservoir>() as u64;
    let without = direct.di.memory_bytes();
    let mut now = &scene;
    for frame in 0..6 {
        if frame == 3 {
            direct.set_lights(&gpu, &sunny);
            now = &sunny;
        }
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        direct.encode(&gpu, now, &camera, &mut encoder);
        gpu.queue.submit([encoder.finish()]);
        let image = direct.read_output(&gpu);
        assert!(
            image.iter().flatten().all(|v| v.is_finite() && *v >= 0.0),
            "frame {frame}: non-finite or negative light"
        );
        let kept = direct.di.reservoirs().is_some();
        assert_eq!(kept, frame >= 3, "frame {frame}: reservoirs kept {kept}");
        let expected = if kept {
            without + reservoir_bytes
        } else {
            without
        };
        assert_eq!(direct.di.memory_bytes(), expected, "frame {frame}");
    }
}
