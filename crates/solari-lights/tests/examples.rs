//! Runs this crate's examples, so CI runs them (on lavapipe) with the tests.

#[allow(dead_code)] // `main` is for `cargo run --example`
#[path = "../examples/light_tiles.rs"]
mod light_tiles;

#[test]
fn light_tiles_example_runs() {
    if solari_scene::gpu::test_gpu().is_none() {
        return;
    }
    light_tiles::run(&[]).expect("the light_tiles example");
}
