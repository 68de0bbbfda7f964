//! GPU twin test: the temporal upscaler's choice of a moving pixel's own-surface samples
//! (`own_surface` in `temporal_upscale.wesl`, under the output-resolution guide) is the Rust
//! twin's (`upscale::own_surface`), bit for bit, on random samples and on adversarial ones:
//! depths exactly at and around the 1.1 ratio, background (0) samples and pixels, emitters
//! beside non-emitters at one depth, and fewer than four samples.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_denoise::modules;
use solari_denoise::upscale::{SAME_SURFACE_DEPTH_RATIO, own_surface, same_surface};
use solari_scene::case_kernel::CaseKernel;
use solari_scene::gpu::test_gpu;
use solari_scene::shaders::{Backend, compose};

/// `upscale_surface_test.wesl`'s `Case`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Case {
    depth: [f32; 4],
    emits: u32,
    four: u32,
    own_depth: f32,
    own_emits: u32,
}

impl Case {
    fn twin(&self) -> u32 {
        let emits: Vec<bool> = (0..4).map(|k| self.emits & (1 << k) != 0).collect();
        let n = self.four as usize;
        own_surface(
            &self.depth[..n],
            &emits[..n],
            self.own_depth,
            self.own_emits != 0,
        )
    }
}

fn adversarial() -> Vec<Case> {
    let o = 0.37f32;
    let r = SAME_SURFACE_DEPTH_RATIO;
    // Depths at, just inside and just outside the ratio either way, background, and far off.
    let depths = [
        o,
        o * r,
        o / r,
        f32::from_bits((o * r).to_bits() + 1),
        f32::from_bits((o * r).to_bits() - 1),
        o * 1.05,
        o * 0.5,
        o * 2.5,
        0.0,
        1e-7,
    ];
    let mut cases = Vec::new();
    let mut i = 0usize;
    for &own_depth in &[o, 0.0] {
        for own_emits in 0..2 {
            for four in 0..=4u32 {
                for emits in 0..16u32 {
                    for _ in 0..8 {
                        // A walk through the depth list: every depth in every slot over the run.
                        let depth = [0, 3, 7, 5].map(|s| depths[(i * (s + 1) + s) % depths.len()]);
                        i += 1;
                        cases.push(Case {
                            depth,
                            emits,
                            four,
                            own_depth,
                            own_emits,
                        });
                    }
                }
            }
        }
    }
    cases
}

fn random(rng: &mut Pcg32, count: usize) -> Vec<Case> {
    (0..count)
        .map(|_| {
            let own_depth = if rng.random_bool(0.1) {
                0.0
            } else {
                rng.random_range(0.01f32..1.0)
            };
            // Mostly near the pixel's depth and of one emission, so that every outcome is
            // reached (all four on one surface included).
            let depth = [(); 4].map(|_| match rng.random_range(0..6) {
                0 => 0.0,
                1 => rng.random_range(0.001f32..1.0),
                2 => own_depth.max(0.01) * rng.random_range(0.8f32..1.25),
                _ => own_depth.max(0.01) * rng.random_range(0.97f32..1.03),
            });
            let emits = match rng.random_range(0..4) {
                0 => rng.random_range(0..16),
                1 => 15,
                _ => 0,
            };
            Case {
                depth,
                emits,
                four: rng.random_range(0..=4),
                own_depth,
                own_emits: rng.random_range(0..2),
            }
        })
        .collect()
}

#[test]
fn gpu_own_surface_matches_the_cpu_twin() {
    let Some(gpu) = test_gpu() else { return };
    let extra: Vec<(&str, &str)> = modules()
        .into_iter()
        .chain([(
            "upscale_surface_test",
            include_str!("../shaders/upscale_surface_test.wesl"),
        )])
        .collect();
    let wgsl = compose("upscale_surface_test", Backend::Software, &extra).expect("compose");
    let mut cases = adversarial();
    let fixed = cases.len();
    cases.extend(random(&mut Pcg32::seed_from_u64(39), 20_000));
    let masks: Vec<u32> =
        CaseKernel::run_pure(&gpu, "upscale_surface_test", &wgsl, 2, &cases).expect("dispatch");
    let mut bits = [0usize; 5];
    for (i, (c, &m)) in cases.iter().zip(&masks).enumerate() {
        assert_eq!(
            m,
            c.twin(),
            "case {i} ({}): {c:?}",
            if i < fixed { "adversarial" } else { "random" }
        );
        bits[m.count_ones() as usize] += 1;
    }
    // The cases reach every outcome from no sample to all four.
    assert!(
        bits.iter().all(|&n| n > 100),
        "masks by samples set: {bits:?}"
    );
}

/// The twin's own rules, on cases small enough to read: the pixel's surface when a sample
/// is on it, else the nearest surface in depth, emission telling surfaces apart.
#[test]
fn own_surface_rules() {
    let r = SAME_SURFACE_DEPTH_RATIO;
    assert!(same_surface(1.0, false, r, false) && same_surface(r, false, 1.0, false));
    assert!(!same_surface(1.0, false, 1.0, true));
    assert!(!same_surface(0.0, false, 1e-9, false) && same_surface(0.0, false, 0.0, false));
    // Two of four on the pixel's depth: those two.
    assert_eq!(
        own_surface(&[1.0, 1.05, 2.0, 0.0], &[false; 4], 1.0, false),
        0b0011
    );
    // The lamp at the floor's depth is not the floor.
    assert_eq!(
        own_surface(
            &[1.0, 1.0, 1.0, 1.0],
            &[true, false, true, false],
            1.0,
            false
        ),
        0b1010
    );
    // None on the pixel's surface: the nearest in depth (2.0 against 0.3 for a pixel at 1),
    // with the samples of its surface.
    assert_eq!(
        own_surface(&[2.0, 0.3, 2.1, 0.0], &[false; 4], 1.0, false),
        0b0101
    );
    // A non-emitting pixel prefers a non-emitting surface however far.
    assert_eq!(own_surface(&[1.2, 5.0], &[true, false], 1.0, false), 0b10);
    assert_eq!(own_surface(&[], &[], 1.0, false), 0);
}
