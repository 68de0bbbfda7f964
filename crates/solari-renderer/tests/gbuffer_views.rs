//! The G-buffer debug views (`FrameView::GBuffer`) show what the G-buffer holds: base colour
//! and normals agree with the primary-ray debug views of the same camera (an independent
//! producer: one traced ray per pixel centre, its hit resolved without the G-buffer's
//! packing), depth follows the documented mapping, motion matches the G-buffer's motion
//! texture through its mapping, the background is black, `present` draws the views without
//! exposure or tone curve, and a wrong-sized G-buffer or output is refused (GPU: lavapipe).

mod common;

use common::{SIZE, settings};
use solari_renderer::{FrameView, RealtimeRenderer};
use solari_scene::gbuffer_debug::{GBufferChannel, GBufferDebug};
use solari_scene::gpu_scene::TraceVariant;
use solari_scene::gpu_types::GpuView;
use solari_scene::pass::FrameContext;
use solari_scene::view_pass::{DebugView, ViewPass};
use solari_scene::{Camera, default_scene, textured_scene};

/// A scene on the test GPU with its own camera (`Setup::with_scene`).
type Setup = common::Cornell;

/// The views of a [`Setup`]'s scene.
trait Views {
    fn view_from(
        &self,
        channel: GBufferChannel,
        cameras: &[Camera],
    ) -> (RealtimeRenderer, Vec<[f32; 3]>);
    fn view_of(&self, channel: GBufferChannel) -> (RealtimeRenderer, Vec<[f32; 3]>);
    fn primary(&self, view: DebugView) -> Vec<[f32; 4]>;
}

impl Views for Setup {
    /// What one channel's view shows at every pixel (the output's sRGB encoding) after a
    /// frame from each of `cameras` in turn (the last frame has history: real motion).
    fn view_from(
        &self,
        channel: GBufferChannel,
        cameras: &[Camera],
    ) -> (RealtimeRenderer, Vec<[f32; 3]>) {
        let settings = solari_renderer::RealtimeSettings {
            view: FrameView::GBuffer(channel),
            ..settings()
        };
        let mut renderer = self.renderer(settings);
        for camera in cameras {
            renderer
                .render(&self.gpu, &self.scene, &self.gpu_scene, camera)
                .expect("frame");
        }
        let out = renderer.read_output(&self.gpu).expect("output");
        let shown = out
            .iter()
            .map(|p| {
                if channel == GBufferChannel::BaseColor || channel == GBufferChannel::Emission {
                    [p[0], p[1], p[2]]
                } else {
                    [0, 1, 2].map(|c| GBufferChannel::shown(p[c]))
                }
            })
            .collect();
        (renderer, shown)
    }

    /// [`Setup::view_from`] two frames of the still camera.
    fn view_of(&self, channel: GBufferChannel) -> (RealtimeRenderer, Vec<[f32; 3]>) {
        self.view_from(channel, &[self.camera.clone(), self.camera.clone()])
    }

    /// The primary-ray debug view `view` of the camera: one vec4 per pixel, w = 1 on a hit.
    fn primary(&self, view: DebugView) -> Vec<[f32; 4]> {
        let (gpu, gpu_scene) = (&self.gpu, &self.gpu_scene);
        let pass =
            ViewPass::primary(gpu, self.backend, TraceVariant::for_scene(gpu_scene)).unwrap();
        let mut v = GpuView::new(&self.camera, SIZE, SIZE);
        v.view_mode = view as u32;
        let bytes = pass
            .run(gpu, gpu_scene, &pass.target(gpu, &v).unwrap())
            .unwrap();
        bytemuck::cast_slice::<u8, [f32; 4]>(&bytes).to_vec()
    }
}

// Share of covered pixels (hit in the primary view) where `shown` is within `tolerance`
// of `expected`, and the largest difference there.
fn agreement(shown: &[[f32; 3]], expected: &[[f32; 4]], tolerance: f32) -> (f64, usize) {
    let mut covered = 0;
    let mut close = 0;
    for (s, e) in shown.iter().zip(expected) {
        if e[3] != 1.0 {
            continue;
        }
        covered += 1;
        if (0..3).all(|c| (s[c] - e[c]).abs() <= tolerance) {
            close += 1;
        }
    }
    (close as f64 / covered as f64, covered)
}

#[test]
fn the_views_match_the_primary_ray_views_and_the_materials() {
    // The untextured box, so both producers see the same values at every pixel centre.
    let Some(t) = Setup::with_scene(default_scene::cornell_box()) else {
        return;
    };
    // The G-buffer stores the square root of base colour in 8 bits (at most 0.004 off in
    // linear), normals in 16 bits per axis, roughness and metallic in 8 bits.
    let cases = [
        (GBufferChannel::BaseColor, DebugView::Albedo, 0.005),
        (GBufferChannel::Normal, DebugView::Normal, 1e-3),
        // The box's walls are flat: geometric and shading normals agree.
        (GBufferChannel::GeometricNormal, DebugView::Normal, 1e-3),
    ];
    for (channel, debug, tolerance) in cases {
        let (_, shown) = t.view_of(channel);
        let expected = t.primary(debug);
        let (close, covered) = agreement(&shown, &expected, tolerance);
        assert!(
            covered > (SIZE * SIZE / 2) as usize,
            "too few covered pixels"
        );
        // Raster and ray may disagree at a silhouette pixel.
        assert!(
            close >= 0.995,
            "{channel:?} within {tolerance} on only {:.2}% of covered pixels",
            close * 100.0
        );
    }
    // Roughness, metallic and emission against each pixel's material, found through the
    // primary ray's instance.
    let instances = t.primary(DebugView::Instance);
    let material_at = |i: usize| {
        let id = instances[i][0].to_bits();
        let instance = t.scene.instances.get(id as usize)?;
        Some(&t.scene.materials[instance.material as usize])
    };
    type Expected = fn(&solari_scene::Material) -> [f32; 3];
    let channels: [(GBufferChannel, Expected, f32); 3] = [
        (
            GBufferChannel::Roughness,
            |m| [m.roughness; 3],
            0.5 / 255.0 + 1e-4,
        ),
        (
            GBufferChannel::Metallic,
            |m| [m.metallic; 3],
            0.5 / 255.0 + 1e-4,
        ),
        (
            GBufferChannel::Emission,
            |m| m.emissive.min(glam::Vec3::ONE).to_array(),
            1e-3,
        ),
    ];
    for (channel, value, tolerance) in channels {
        let (_, shown) = t.view_of(channel);
        let mut checked = 0;
        let mut wrong = 0;
        for (i, s) in shown.iter().enumerate() {
            let Some(m) = material_at(i) else { continue };
            checked += 1;
            let e = value(m);
            if (0..3).any(|c| (s[c] - e[c]).abs() > tolerance) {
                wrong += 1;
            }
        }
        assert!(checked > (SIZE * SIZE / 2) as usize);
        assert!(
            wrong * 200 <= checked,
            "{channel:?}: {wrong} of {checked} pixels differ from their material"
        );
    }
}

#[test]
fn textured_base_colour_has_the_primary_views_mean() {
    // The raster pass filters textures at the pixel's footprint, the primary ray reads mip
    // 0: per pixel they differ (median 0.05 at 64×64), but filtering keeps the mean.
    let Some(t) = Setup::with_scene(textured_scene::textured_spheres()) else {
        return;
    };
    let (_, shown) = t.view_of(GBufferChannel::BaseColor);
    let expected = t.primary(DebugView::Albedo);
    let mut sums = [[0.0f64; 3]; 2];
    let mut n = 0;
    for (s, e) in shown.iter().zip(&expected) {
        // Pixels both producers cover.
        if e[3] != 1.0 || *s == [0.0; 3] {
            continue;
        }
        n += 1;
        for c in 0..3 {
            sums[0][c] += s[c] as f64;
            sums[1][c] += e[c] as f64;
        }
    }
    assert!(n > (SIZE * SIZE / 4) as usize, "too few covered pixels");
    for (c, (a, b)) in sums[0].iter().zip(&sums[1]).enumerate() {
        let (a, b) = (a / n as f64, b / n as f64);
        assert!(
            (a - b).abs() <= 0.03 * b.max(0.05),
            "channel {c}: view mean {a:.4}, primary mean {b:.4}"
        );
    }
}

#[test]
fn depth_motion_and_background_follow_their_mappings() {
    let Some(t) = Setup::with_scene(default_scene::cornell_box()) else {
        return;
    };
    let hits = t.primary(DebugView::Depth);

    // Depth: 1 - 0.9 z / far, with far the distance to the scene's farthest corner. At the
    // centre pixels the view axis and the ray agree to within cos(half a pixel's angle).
    let (lo, hi) = t.scene.bounds();
    let eye = t.camera.position();
    let far = (0..3)
        .map(|a| {
            let d = (eye[a] - lo[a]).abs().max((eye[a] - hi[a]).abs());
            d * d
        })
        .sum::<f32>()
        .sqrt();
    let (_, depth) = t.view_of(GBufferChannel::Depth);
    let mid = SIZE / 2;
    for (x, y) in [
        (mid - 1, mid - 1),
        (mid, mid - 1),
        (mid - 1, mid),
        (mid, mid),
    ] {
        let i = (y * SIZE + x) as usize;
        assert!(hits[i][0] > 0.0, "the centre of the box is a wall");
        let expected = 1.0 - 0.9 * hits[i][0] / far;
        assert!(
            (depth[i][0] - expected).abs() < 2e-3,
            "pixel ({x}, {y}): depth shows {} for {expected}",
            depth[i][0]
        );
    }

    // A still camera: no motion, shown as mid grey in red and green.
    let (_, motion) = t.view_of(GBufferChannel::Motion);
    for (i, m) in motion.iter().enumerate() {
        if hits[i][0] > 0.0 {
            assert!(
                (m[0] - 0.5).abs() < 1e-3 && (m[1] - 0.5).abs() < 1e-3,
                "pixel {i}: still camera shows motion {m:?}"
            );
        }
    }

    // A moving camera: every pixel shows the G-buffer's own motion vector through the
    // documented mapping, 0.5 + pixels / 32 (clamped) in red and green, 0.5 in blue.
    let moved = t.camera.orbit(&t.scene, 3);
    let (renderer, shown) = t.view_from(GBufferChannel::Motion, &[t.camera.clone(), moved]);
    let texels = renderer.gbuffer().current().read(&t.gpu).expect("G-buffer");
    let mut moving = 0;
    for (i, (m, s)) in texels.motion.iter().zip(&shown).enumerate() {
        if texels.depth[i] <= 0.0 {
            continue;
        }
        let pixels = [m[0].to_f32() * SIZE as f32, m[1].to_f32() * SIZE as f32];
        moving += usize::from(pixels[0].abs() + pixels[1].abs() > 0.25);
        let expected = pixels.map(|p| 0.5 + (p / 32.0).clamp(-0.5, 0.5));
        assert!(
            (s[0] - expected[0]).abs() < 2e-3
                && (s[1] - expected[1]).abs() < 2e-3
                && (s[2] - 0.5).abs() < 2e-3,
            "pixel {i}: motion {pixels:?} px shows {s:?}, expected {expected:?}"
        );
    }
    assert!(
        moving > (SIZE * SIZE / 4) as usize,
        "the orbit should move pixels: {moving}"
    );
}

#[test]
fn wrong_sizes_are_refused_with_the_sizes_named() {
    let Some(t) = Setup::with_scene(default_scene::cornell_box()) else {
        return;
    };
    let (renderer, _) = t.view_of(GBufferChannel::Normal);
    let out = t.gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("small output"),
        size: 32 * 32 * 16,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    // An output smaller than the image.
    let err = GBufferDebug::new(&t.gpu, &out, (64, 64))
        .err()
        .expect("refused");
    assert!(err.to_string().contains("64×64"), "{err}");
    // A pass built for 32×32 given the renderer's 64×64 G-buffer: nothing is recorded.
    let pass = GBufferDebug::new(&t.gpu, &out, (32, 32)).expect("pass");
    let frame = FrameContext::new(0, (32, 32), &t.camera, None);
    let mut encoder = t.gpu.device.create_command_encoder(&Default::default());
    let err = pass
        .encode(&mut encoder, &frame, renderer.gbuffer())
        .expect_err("refused");
    let msg = err.to_string();
    assert!(
        msg.contains("G-buffer debug view") && msg.contains("(32, 32)") && msg.contains("(64, 64)"),
        "{msg}"
    );
}

#[test]
fn background_is_black_and_present_shows_the_values_as_they_are() {
    // Spheres under a sky: background around them.
    let Some(t) = Setup::with_scene(textured_scene::textured_spheres()) else {
        return;
    };
    let gpu = &t.gpu;
    let hits = t.primary(DebugView::Depth);
    let misses: Vec<usize> = (0..hits.len()).filter(|&i| hits[i][0] < 0.0).collect();
    assert!(misses.len() > 16, "the test needs background pixels");
    for channel in GBufferChannel::ALL {
        let (mut renderer, shown) = t.view_of(channel);
        for &i in &misses {
            // Silhouette pixels may be covered in the G-buffer and not at the ray's centre.
            let near_hit = [
                i.wrapping_sub(1),
                i + 1,
                i.wrapping_sub(SIZE as usize),
                i + SIZE as usize,
            ]
            .iter()
            .any(|&j| hits.get(j).is_some_and(|h| h[0] >= 0.0));
            if !near_hit {
                assert_eq!(shown[i], [0.0; 3], "{channel:?} background pixel {i}");
            }
        }
        // An 8-bit target shows the values as they are: no exposure (asked for +3 EV
        // here), no tone curve.
        let texture = gpu.texture_2d(
            "caller's target",
            (SIZE, SIZE),
            wgpu::TextureFormat::Rgba8Unorm,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        renderer
            .present(gpu, &texture.create_view(&Default::default()), 3.0)
            .expect("present");
        let bytes = gpu
            .read_texture(&texture, wgpu::TextureAspect::All)
            .expect("read");
        let linear = renderer.read_output(gpu).expect("output");
        let mut worst = 0i32;
        for (px, l) in bytes.chunks_exact(4).zip(&linear) {
            for c in 0..3 {
                let expected = (GBufferChannel::shown(l[c]) * 255.0).round() as i32;
                worst = worst.max((px[c] as i32 - expected).abs());
            }
        }
        assert!(
            worst <= 1,
            "{channel:?}: presented bytes differ by {worst}/255"
        );
    }
}
