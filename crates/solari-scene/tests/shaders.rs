//! CPU-only: every entry point composes with WESL and validates with naga in every backend
//! variant, and every loop in them states why it ends.

use solari_scene::shaders::{Backend, ENTRY_POINTS, MODULES, compose, validate};

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

/// Pipelines skip wgpu's forced loop bounding (`ShaderChecks::BoundsOnly`), which is sound only
/// while every loop provably ends; each must say why in a `// bound:` comment just above it.
#[test]
fn every_shader_loop_states_its_bound() {
    for (name, source) in MODULES.iter().chain(ENTRY_POINTS) {
        let lines: Vec<&str> = source.lines().collect();
        for (i, line) in lines.iter().enumerate() {
            let code = line.split("//").next().unwrap().trim_start();
            let is_loop = code.starts_with("loop")
                || code.starts_with("while ")
                || code.starts_with("for ")
                || code.starts_with("for(");
            if is_loop {
                let above = lines[..i]
                    .iter()
                    .rev()
                    .find(|l| !l.trim().is_empty())
                    .copied()
                    .unwrap_or("");
                assert!(
                    above.trim_start().starts_with("// bound:"),
                    "{name}.wesl line {}: loop without a `// bound:` comment above it",
                    i + 1
                );
            }
        }
    }
}
