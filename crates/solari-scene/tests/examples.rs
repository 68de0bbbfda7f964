//! Runs this crate's examples, so CI runs them (on lavapipe) with the tests.

#[allow(dead_code)] // `main` is for `cargo run --example`
#[path = "../examples/trace_rays.rs"]
mod trace_rays;

#[test]
fn trace_rays_example_runs() {
    if solari_scene::gpu::test_gpu().is_none() {
        return;
    }
    trace_rays::run(&[]).expect("the trace_rays example");
}
