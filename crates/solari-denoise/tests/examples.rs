//! Runs this crate's examples, so CI runs them (on lavapipe) with the tests.

#[allow(dead_code)] // `main` is for `cargo run --example`
#[path = "../examples/denoise_noise.rs"]
mod denoise_noise;

#[test]
fn denoise_noise_example_runs() {
    if solari_scene::gpu::test_gpu().is_none() {
        return;
    }
    denoise_noise::run(&[]).expect("the denoise_noise example");
}
