//! Runs this crate's examples, so CI runs them (on lavapipe) with the tests.

#[allow(dead_code)] // `main` is for `cargo run --example`
#[path = "../examples/render_frames.rs"]
mod render_frames;

#[test]
fn render_frames_example_runs() {
    if solari_scene::gpu::test_gpu().is_none() {
        return;
    }
    render_frames::run(&[]).expect("the render_frames example");
}
