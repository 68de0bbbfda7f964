//! ReSTIR DI's merge arithmetic and the lights' angular radius (for the shadow report's
//! penumbra) on the GPU (`restir_di_math.wesl`, run by `restir_di_test.wesl`) against their
//! Rust twins (`solari_restir::reservoir`): the resampling weights and the pick, on random reservoirs and adversarial ones (empty sides, zero, tiny
//! and huge targets, weights whose products overflow, zero confidences, a sample outside the
//! other domain, random numbers at the ends of [0, 1)).

use bytemuck::{Pod, Zeroable};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_restir::reservoir::{
    DiMergeSide, DiPick, di_merge_pick, di_merge_weights, light_angular_radius,
};
use solari_scene::case_kernel::CaseKernel;
use solari_scene::gpu::test_gpu;

/// WGSL twin: `Case` in `restir_di_test.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Case {
    c: [f32; 4],
    o: [f32; 4],
    u: [f32; 4],
    light: [f32; 4],
}

/// A light for the angular radius: kind (0–3, as a float), area (0 for delta lights, tiny,
/// ordinary, huge), g (cos / d², 0 to large) and a positive distance (0 with a delta point
/// light divides 0 by 0, outside what the twin promises, as for NaN targets below).
fn light(rng: &mut Pcg32) -> [f32; 4] {
    let area = match rng.random_range(0..8) {
        0 => 0.0,
        1 => 1e-6,
        2 => 1e6,
        _ => rng.random_range(0.0..4.0),
    };
    [
        rng.random_range(0..4) as f32,
        area,
        rng.random_range(0.0..50.0),
        rng.random_range(1e-3..100.0),
    ]
}

/// A target value: mostly ordinary, sometimes zero, tiny or huge. Never infinite or NaN:
/// WGSL lets an implementation assume neither occurs (on lavapipe a NaN target gave 0 where
/// the twin's `balance_heuristic` gives 0.5), so the twin holds for finite inputs only; scene
/// validation refuses non-finite lights, and the non-finite detector counts any that appear.
fn target(rng: &mut Pcg32) -> f32 {
    match rng.random_range(0..20) {
        0..=1 => 0.0,
        2 => 1e-30,
        3 => 1e30,
        _ => rng.random_range(0.0..10.0),
    }
}

/// One side: confidence, W (sometimes 0: an empty reservoir; sometimes huge), target at its
/// own pixel and at the other (0 there a tenth of the time: outside the other's domain).
fn side(rng: &mut Pcg32) -> [f32; 4] {
    let confidence = match rng.random_range(0..10) {
        0 => 0.0,
        _ => rng.random_range(0.5..40.0),
    };
    let weight = match rng.random_range(0..10) {
        0 => 0.0,
        1 => 1e35,
        _ => rng.random_range(0.0..5.0),
    };
    let there = if rng.random_range(0..10) == 0 {
        0.0
    } else {
        target(rng)
    };
    [confidence, weight, target(rng), there]
}

fn cases() -> Vec<Case> {
    let mut rng = Pcg32::seed_from_u64(19);
    (0..6000)
        .map(|i| {
            let u = match i % 7 {
                0 => 0.0,
                1 => 1.0 - f32::EPSILON / 2.0,
                _ => rng.random_range(0.0..1.0),
            };
            Case {
                c: side(&mut rng),
                o: side(&mut rng),
                u: [u, 0.0, 0.0, 0.0],
                light: light(&mut rng),
            }
        })
        .collect()
}

fn close(a: f32, b: f32, tol: f32) -> bool {
    a == b || (a.is_nan() && b.is_nan()) || (a - b).abs() <= tol * a.abs().max(b.abs())
}

#[test]
fn di_merge_math_matches_its_rust_twin() {
    let Some(gpu) = test_gpu() else { return };
    let source = include_str!("../shaders/restir_di_test.wesl");
    let cases = cases();
    let results: Vec<[[f32; 4]; 2]> = CaseKernel::run_test_module(
        &gpu,
        solari_restir::modules(),
        "restir_di_test",
        source,
        2,
        &cases,
    )
    .expect("dispatch");
    let (mut picked, mut none, mut others) = (0, 0, 0);
    for (k, [r, radius]) in cases.iter().zip(&results) {
        let l = k.light;
        let twin = light_angular_radius(l[0] as u32, l[1], l[2], l[3]);
        // WGSL lets asin be approximate: lavapipe's is off by up to 3e-4 relative (a
        // penumbra 0.03% wider or narrower, for a gate at one pixel).
        assert!(
            (radius[0] - twin).abs() <= 1e-3 * twin.max(1e-3),
            "angular radius: GPU {} CPU {twin} for {l:?}",
            radius[0]
        );
        assert!(
            (0.0..=std::f32::consts::FRAC_PI_2).contains(&twin),
            "{twin} for {l:?}"
        );
        let side = |v: [f32; 4]| DiMergeSide {
            confidence: v[0],
            weight: v[1],
            target_here: v[2],
            target_there: v[3],
        };
        let (c, o) = (side(k.c), side(k.o));
        let w = di_merge_weights(c, o);
        assert!(
            close(r[0], w.0, 1e-6) && close(r[1], w.1, 1e-6),
            "weights: GPU ({}, {}) CPU {w:?} for {k:?}",
            r[0],
            r[1]
        );
        // The GPU's own weights decide its pick; where u·sum lies within rounding of w_o the
        // two may part, so the twin is asked with the GPU's weights.
        let gpu_w = (r[0], r[1]);
        let sum = gpu_w.0 + gpu_w.1;
        let edge = (k.u[0] * sum - gpu_w.1).abs() <= 1e-6 * sum.abs();
        let cpu = di_merge_pick(gpu_w, c.target_here, o.target_there, k.u[0]);
        match cpu {
            None => {
                assert_eq!(
                    (r[2], r[3]),
                    (0.0, 0.0),
                    "GPU picked where the twin did not: {k:?} -> {r:?}"
                );
                none += 1;
            }
            Some((pick, weight)) => {
                if edge {
                    continue;
                }
                let which = if pick == DiPick::Other { 2.0 } else { 1.0 };
                assert_eq!(r[2], which, "pick: GPU {} CPU {pick:?} for {k:?}", r[2]);
                assert!(
                    close(r[3], weight, 1e-6),
                    "W: GPU {} CPU {weight} for {k:?}",
                    r[3]
                );
                picked += 1;
                if pick == DiPick::Other {
                    others += 1;
                }
            }
        }
    }
    // The cases reach every branch.
    assert!(
        picked > 2000 && none > 500 && others > 500,
        "{picked} picked ({others} other), {none} none"
    );
}
