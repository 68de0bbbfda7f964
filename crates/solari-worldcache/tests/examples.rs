//! Runs this crate's examples, so CI runs them (on lavapipe) with the tests.

#[allow(dead_code)] // `main` is for `cargo run --example`
#[path = "../examples/furnace.rs"]
mod furnace;

#[test]
fn furnace_example_runs() {
    if solari_scene::gpu::test_gpu().is_none() {
        return;
    }
    furnace::run(&[]).expect("the furnace example");
}
