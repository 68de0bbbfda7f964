//! ReSTIR GI's reuse math on the GPU (`restir_gi_math.wesl`, run by `restir_gi_test.wesl`)
//! against its Rust twins (`solari_restir::gi_reservoir`): the reconnection Jacobian and the
//! merge weights, the one-ray merge's weight sum and the light of a merge shaded over its
//! choice, on random and adversarial cases (coincident points, samples behind a surface,
//! empty reservoirs, zero and huge targets, Jacobians at and over the bound).

use bytemuck::{Pod, Zeroable};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_restir::gi_reservoir::{
    MergeSide, chosen_weight_sum, expected_light, merge_weights, reconnection_jacobian,
};
use solari_scene::case_kernel::CaseKernel;
use solari_scene::gpu::test_gpu;

/// WGSL twin: `Case` in `restir_gi_test.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Case {
    sample: [f32; 4],
    normal: [f32; 4],
    source: [f32; 4],
    dest: [f32; 4],
    c: [f32; 4],
    o: [f32; 4],
    jacobians: [f32; 4],
    light_c: [f32; 4],
    light_o: [f32; 4],
}

/// WGSL twin: `Output` in `restir_gi_test.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Output {
    weights: [f32; 4],
    chosen: [f32; 4],
    light: [f32; 4],
}

fn point(rng: &mut Pcg32) -> [f32; 3] {
    [0, 1, 2].map(|_| rng.random_range(-5.0..5.0))
}

fn unit(rng: &mut Pcg32) -> [f32; 3] {
    let z: f32 = rng.random_range(-1.0..1.0);
    let phi: f32 = rng.random_range(0.0..std::f32::consts::TAU);
    let s = (1.0 - z * z).max(0.0).sqrt();
    [s * phi.cos(), s * phi.sin(), z]
}

/// A target value: mostly ordinary, sometimes zero, tiny or huge.
fn target(rng: &mut Pcg32) -> f32 {
    match rng.random_range(0..10) {
        0 => 0.0,
        1 => 1e-30,
        2 => 1e30,
        _ => rng.random_range(0.0..4.0),
    }
}

fn side(rng: &mut Pcg32) -> [f32; 4] {
    let weight = if rng.random_range(0..5) == 0 {
        0.0
    } else {
        rng.random_range(0.0..10.0)
    };
    // Confidence exactly 0 too: a candidate that found only a cold cache cell
    // (`RestirGiSettings::ignore_cold_cells`) is an empty reservoir of no confidence.
    let confidence = if rng.random_range(0..8) == 0 {
        0.0
    } else {
        rng.random_range(0.0..20.0)
    };
    [confidence, weight, target(rng), target(rng)]
}

/// A sample's diffuse contribution (rgb) and its target: ordinary, or a zero or tiny target.
fn light(rng: &mut Pcg32) -> [f32; 4] {
    let f = [0, 1, 2].map(|_| rng.random_range(0.0..3.0f32));
    let target = match rng.random_range(0..10) {
        0 => 0.0,
        1 => 1e-30,
        _ => 0.2126 * f[0] + 0.7152 * f[1] + 0.0722 * f[2] + rng.random_range(0.0..1.0f32),
    };
    [f[0], f[1], f[2], target]
}

fn cases() -> Vec<Case> {
    let mut rng = Pcg32::seed_from_u64(18);
    (0..4000)
        .map(|i| {
            let sample = point(&mut rng);
            let source = if i % 50 == 0 { sample } else { point(&mut rng) };
            let dest = if i % 40 == 0 { source } else { point(&mut rng) };
            let bound = [1.0, 1.2, 2.0, 1e30][i % 4];
            // Jacobians around the bound, and exactly on it.
            let jacobian = |rng: &mut Pcg32| match rng.random_range(0..6) {
                0 => bound,
                1 => 0.0,
                _ => rng.random_range(0.0..3.0),
            };
            let with = |p: [f32; 3], w: f32| [p[0], p[1], p[2], w];
            Case {
                sample: with(sample, bound),
                normal: with(unit(&mut rng), 0.0),
                source: with(source, 0.0),
                dest: with(dest, 0.0),
                c: side(&mut rng),
                o: side(&mut rng),
                jacobians: [jacobian(&mut rng), jacobian(&mut rng), 0.0, 0.0],
                light_c: light(&mut rng),
                light_o: light(&mut rng),
            }
        })
        .collect()
}

fn close(a: f32, b: f32, tol: f32) -> bool {
    a == b || (a - b).abs() <= tol * a.abs().max(b.abs()).max(1e-30)
}

#[test]
fn gi_reuse_math_matches_its_rust_twin() {
    let Some(gpu) = test_gpu() else { return };
    let source = include_str!("../shaders/restir_gi_test.wesl");
    let cases = cases();
    let results: Vec<Output> = CaseKernel::run_test_module(
        &gpu,
        solari_restir::gi_modules(),
        "restir_gi_test",
        source,
        2,
        &cases,
    )
    .expect("dispatch");
    let (mut refused, mut merged, mut corrected) = (0, 0, 0);
    for (k, out) in cases.iter().zip(&results) {
        let r = out.weights;
        let xyz = |v: [f32; 4]| [v[0], v[1], v[2]];
        let j = reconnection_jacobian(xyz(k.sample), xyz(k.normal), xyz(k.source), xyz(k.dest));
        // inverseSqrt on the GPU may differ from 1/sqrt in the last bits.
        assert!(
            close(r[0], j, 1e-4),
            "Jacobian: GPU {} CPU {j} for {k:?}",
            r[0]
        );
        let side = |v: [f32; 4], jacobian: f32| MergeSide {
            confidence: v[0],
            weight: v[1],
            target_here: v[2],
            target_there: v[3],
            jacobian,
        };
        let cpu = merge_weights(
            side(k.c, k.jacobians[0]),
            side(k.o, k.jacobians[1]),
            k.sample[3],
        );
        match cpu {
            None => {
                assert_eq!(
                    r[3], 1.0,
                    "GPU merged where the twin refused: {k:?} -> {r:?}"
                );
                assert_eq!(out.chosen, [0.0; 4], "a refused merge has no weight: {k:?}");
                refused += 1;
            }
            Some((wc, wo)) => {
                assert_eq!(r[3], 0.0, "GPU refused where the twin merged: {k:?}");
                // The one-ray merge's sums, chosen side by visibility found.
                for (i, (pick_o, seen)) in
                    [(false, true), (false, false), (true, true), (true, false)]
                        .into_iter()
                        .enumerate()
                {
                    let cpu = chosen_weight_sum(
                        side(k.c, k.jacobians[0]),
                        side(k.o, k.jacobians[1]),
                        k.sample[3],
                        pick_o,
                        seen,
                    )
                    .expect("merged");
                    // A NaN sum (no weight at all) is NaN on both sides.
                    assert!(
                        close(out.chosen[i], cpu, 1e-5) || (cpu.is_nan() && out.chosen[i].is_nan()),
                        "chosen sum (pick o {pick_o}, seen {seen}): GPU {} CPU {cpu} for {k:?}",
                        out.chosen[i]
                    );
                }
                if out.chosen[1] != out.chosen[0] && out.chosen[1].is_finite() {
                    corrected += 1;
                }
                assert!(
                    close(r[1], wc, 1e-5),
                    "w_c: GPU {} CPU {wc} for {k:?}",
                    r[1]
                );
                assert!(
                    close(r[2], wo, 1e-5),
                    "w_o: GPU {} CPU {wo} for {k:?}",
                    r[2]
                );
                // The merge shaded over its choice, from the twin's weights.
                let split = |v: [f32; 4]| ([v[0], v[1], v[2]], v[3]);
                let cpu = expected_light((wc, wo), split(k.light_c), split(k.light_o));
                for c in 0..3 {
                    assert!(
                        close(out.light[c], cpu[c], 1e-4),
                        "expected light: GPU {:?} CPU {cpu:?} for {k:?}",
                        out.light
                    );
                }
                merged += 1;
            }
        }
    }
    // Both branches were exercised, and the one-ray correction changed many sums.
    assert!(
        refused > 100 && merged > 1000 && corrected > 500,
        "refused {refused}, merged {merged}, corrected {corrected}"
    );
}
