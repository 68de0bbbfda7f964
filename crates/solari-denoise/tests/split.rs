//! Split lighting (`Lighting::Split`) through the fallback denoiser on lavapipe: each signal is
//! demodulated by its own albedo and filtered on its own, and the two are summed back.
//! (`cargo test --release -p solari-denoise --test split -- --nocapture` prints the figures.)

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_denoise::{Denoiser, FallbackDenoiser, FallbackSettings};

mod common;

use common::{Harness, SIZE, luminance};

const N: usize = (SIZE * SIZE) as usize;

// Inputs carry w = 0.5: surfaces come out with w = 1, background pixels (passed through
// from the diffuse buffer) with the input's w.
fn uniform(v: f32) -> Vec<[f32; 4]> {
    vec![[v, v, v, 0.5]; N]
}

#[test]
fn constant_split_signals_come_back_summed() {
    let Some(mut h) = Harness::new() else { return };
    let mut d =
        FallbackDenoiser::new(&h.gpu, SIZE, SIZE, FallbackSettings::default()).expect("denoiser");
    assert_eq!(d.pass_labels().len(), 3);
    // Different demodulated levels per signal (diffuse albedo 0.5, specular F0 about 0.04),
    // so that mixing up the albedos would show.
    for frame in 0..6 {
        let out = h.frame_split(&mut d, &uniform(0.25), &uniform(0.02));
        let mut surfaces = 0;
        for (i, p) in out.iter().enumerate() {
            // Background: the diffuse buffer's value, untouched.
            let want = if p[3] == 1.0 { 0.27 } else { 0.25 };
            surfaces += (p[3] == 1.0) as usize;
            for c in 0..3 {
                assert!(
                    (p[c] - want).abs() < 1e-4,
                    "frame {frame} pixel {i}: {p:?}, want {want}"
                );
            }
        }
        assert!(surfaces > N / 2, "only {surfaces} surface pixels");
    }
}

// Surfaces must come back at `want` (w = 1); background passes the input's 0.25 through.
fn assert_uniform(out: &[[f32; 4]], want: f32, what: &str) {
    for (i, p) in out.iter().enumerate() {
        let want = if p[3] == 1.0 { want } else { 0.25 };
        assert!(
            p[..3].iter().all(|c| (c - want).abs() < 1e-4),
            "{what}, pixel {i}: {p:?}, want {want}"
        );
    }
}

/// With combined lighting the output is the filter buffer the last à-trous iteration writes,
/// which depends on the iteration count; split lighting has a buffer of its own. One
/// denoiser switched between the two, at every count that picks either filter buffer, gives
/// each frame its own right answer, and combined lighting holds no output buffer.
#[test]
fn the_output_follows_the_lighting_kind_and_the_iteration_count() {
    let Some(mut h) = Harness::new() else { return };
    let pixels = N as u64;
    for iterations in 1..=4 {
        let settings = FallbackSettings {
            atrous_iterations: iterations,
            ..FallbackSettings::default()
        };
        let mut d = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
        let what = |kind: &str, frame: usize| format!("{iterations} iterations, {kind} {frame}");
        for frame in 0..2 {
            assert_uniform(
                &h.frame(&mut d, &uniform(0.25), false),
                0.25,
                &what("combined", frame),
            );
        }
        // Two 16-byte filter buffers, the 8-byte guide, the 32-byte transient words and one
        // 24-byte history; no output.
        let combined = d.memory_bytes();
        assert!(
            (96 * pixels..96 * pixels + 4096).contains(&combined),
            "{iterations} iterations: combined lighting holds {combined} bytes"
        );
        for frame in 0..2 {
            let out = h.frame_split(&mut d, &uniform(0.25), &uniform(0.02));
            assert_uniform(&out, 0.27, &what("split", frame));
        }
        // Split adds the second signal's history and its own output.
        assert_eq!(d.memory_bytes(), combined + pixels * (24 + 16));
        for frame in 0..2 {
            assert_uniform(
                &h.frame(&mut d, &uniform(0.25), false),
                0.25,
                &what("combined again", frame),
            );
        }
    }
}

// Mean absolute luminance error, over surface pixels within 3 columns of the middle, of
// `out` against 0.25 + `specular(x)`.
fn step_error(out: &[[f32; 4]], specular: impl Fn(usize) -> f32) -> f64 {
    let (mut sum, mut n) = (0.0, 0);
    for (i, p) in out.iter().enumerate() {
        let x = i % SIZE as usize;
        if p[3] != 1.0 || (x as f64 - (SIZE as f64 - 1.0) / 2.0).abs() > 3.0 {
            continue;
        }
        let want = 0.25 + specular(x) as f64;
        sum += (luminance(*p) - want).abs();
        n += 1;
    }
    assert!(n > 0, "no pixels near the step");
    sum / n as f64
}

#[test]
fn a_clean_specular_edge_survives_noisy_diffuse_light_when_split() {
    let Some(mut h) = Harness::new() else { return };
    // Noise-free specular light with a sharp step down the middle of the image; noisy diffuse
    // light with a flat mean of 0.25.
    let specular = |x: usize| if x < SIZE as usize / 2 { 0.02 } else { 0.2 };
    let spec: Vec<[f32; 4]> = (0..N)
        .map(|i| {
            let s = specular(i % SIZE as usize);
            [s, s, s, 0.5]
        })
        .collect();
    let settings = FallbackSettings::default();
    let mut split = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
    let mut combined = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
    let mut rng = Pcg32::seed_from_u64(11);
    let (mut e_split, mut e_combined) = (0.0, 0.0);
    let frames = 24;
    for _ in 0..frames {
        let diffuse: Vec<[f32; 4]> = (0..N)
            .map(|_| {
                let v = 0.25 * rng.random_range(0.0f32..2.0);
                [v, v, v, 0.5]
            })
            .collect();
        let sum: Vec<[f32; 4]> = diffuse
            .iter()
            .zip(&spec)
            .map(|(d, s)| [d[0] + s[0], d[1] + s[1], d[2] + s[2], 0.5])
            .collect();
        e_split = step_error(&h.frame_split(&mut split, &diffuse, &spec), specular);
        e_combined = step_error(&h.frame(&mut combined, &sum, false), specular);
    }
    println!(
        "specular step under noisy diffuse, frame {frames}: mean |error| near the step {e_split:.4} \
         split, {e_combined:.4} combined"
    );
    assert!(
        e_split < 0.5 * e_combined,
        "split {e_split} should keep the edge far better than combined {e_combined}"
    );
}

/// The renderer keeps the denoiser's transient words (the new history on its way to the
/// history buffer, then the variance pass's output) and, with an odd iteration count, its
/// second filter buffer in a scratch buffer that ReSTIR DI and GI fill with their
/// reservoirs earlier in the frame. Filled before every
/// frame with earlier outputs (real colours with w = 1, which a filter pass reading what it
/// did not write would take for its own) and random bytes, the scratch changes nothing: the
/// outputs are the same bit for bit over 8 noisy frames, with combined and split lighting and
/// with 5 and 4 iterations (the second filter buffer in the scratch or not). The denoiser
/// counts only its own buffers.
#[test]
fn a_shared_scratch_full_of_garbage_changes_nothing() {
    use solari_scene::scratch;
    let Some(mut h) = Harness::new() else { return };
    let mut rng = Pcg32::seed_from_u64(5);
    let noisy = |rng: &mut Pcg32| -> Vec<[f32; 4]> {
        (0..N)
            .map(|_| {
                let v = rng.random::<f32>() * 0.5;
                [v, v * 0.8, v * 0.6, 0.5]
            })
            .collect()
    };
    for (iterations, split) in [(5, false), (4, false), (5, true)] {
        let settings = FallbackSettings {
            atrous_iterations: iterations,
            ..FallbackSettings::default()
        };
        let new = || FallbackDenoiser::new(&h.gpu, SIZE, SIZE, settings).expect("denoiser");
        let (mut own, mut shared) = (new(), new());
        let scratch = scratch::allocate(&h.gpu, shared.scratch_bytes()).unwrap();
        let before = shared.memory_bytes();
        shared.use_scratch(&h.gpu, &scratch).expect("scratch");
        let moved = if iterations % 2 == 1 { 48 } else { 32 };
        assert_eq!(before - shared.memory_bytes(), moved * N as u64);
        let mut plausible: Vec<u8> = Vec::new();
        for frame in 0..8 {
            let mut bytes: Vec<u8> = (0..scratch.size()).map(|_| rng.random()).collect();
            for (i, b) in plausible.iter().enumerate() {
                bytes[i] = *b;
                bytes[i + scratch.size() as usize - plausible.len()] = *b;
            }
            h.gpu.queue.write_buffer(&scratch, 0, &bytes);
            let (diffuse, specular) = (noisy(&mut rng), noisy(&mut rng));
            let (a, b) = if split {
                (
                    h.frame_split(&mut own, &diffuse, &specular),
                    h.frame_split(&mut shared, &diffuse, &specular),
                )
            } else {
                (
                    h.frame(&mut own, &diffuse, false),
                    h.frame(&mut shared, &diffuse, false),
                )
            };
            let what = format!("{iterations} iterations, split {split}, frame {frame}");
            assert!(a.iter().any(|p| p[3] == 1.0), "{what}: no surface");
            assert!(a == b, "{what}: the outputs differ");
            plausible = bytemuck::cast_slice(&a).to_vec();
        }
    }
    let small = scratch::allocate(&h.gpu, 64).unwrap();
    let mut d = FallbackDenoiser::new(&h.gpu, SIZE, SIZE, FallbackSettings::default()).unwrap();
    let e = d.use_scratch(&h.gpu, &small).unwrap_err().to_string();
    assert!(e.contains("holds 64 bytes"), "{e}");
    h.gpu.check_errors().expect("no wgpu error");
}
