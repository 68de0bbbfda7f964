//! Runs this crate's examples, so CI runs them (on lavapipe) with the tests.

#[allow(dead_code)] // `main` is for `cargo run --example`
#[path = "../examples/own_gbuffer.rs"]
mod own_gbuffer;

#[test]
fn own_gbuffer_example_runs() {
    if solari_scene::gpu::test_gpu().is_none() {
        return;
    }
    own_gbuffer::run(&[]).expect("the own_gbuffer example");
    // The software traversal too, which ray-query adapters would otherwise never run here.
    own_gbuffer::run(&["software".to_string()]).expect("the own_gbuffer example, software");
}
