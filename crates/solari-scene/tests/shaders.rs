//! CPU-only: every entry point composes with WESL and validates with naga in every backend
//! variant, and every loop in them states why it ends.

use solari_scene::shaders::{
    Backend, ENTRY_POINTS, MODULES, compose, loops_without_bound, validate,
};

#[test]
fn every_entry_point_validates_in_every_variant() {
    for (name, _) in ENTRY_POINTS {
        for backend in Backend::ALL {
            let wgsl = compose(name, backend, &[]).unwrap_or_else(|e| panic!("{e}"));
            let module = validate(name, &wgsl).unwrap_or_else(|e| panic!("{backend:?}: {e}"));
            // Compute entry points are `main`; raster ones `vs_main` and `fs_main`.
            let names: Vec<&str> = module
                .entry_points
                .iter()
                .map(|e| e.name.as_str())
                .collect();
            assert!(
                names.contains(&"main")
                    || (names.contains(&"vs_main") && names.contains(&"fs_main")),
                "{name} has entry points {names:?}"
            );
        }
    }
}

/// Pipelines skip wgpu's forced loop bounding (`ShaderChecks::BoundsOnly`), which is sound only
/// while every loop provably ends; each must say why in a `// bound:` comment just above it.
#[test]
fn every_shader_loop_states_its_bound() {
    for (name, source) in MODULES.iter().chain(ENTRY_POINTS) {
        let missing = loops_without_bound(source);
        assert!(
            missing.is_empty(),
            "{name}.wesl lines {missing:?}: loops without a `// bound:` comment above them"
        );
    }
}

#[test]
fn crate_shader_check_refuses_an_unbounded_loop_and_a_wrong_layout() {
    let own = [("bad", "fn f() {\n    for (var i = 0u; i < 4u; i++) {}\n}\n")];
    let err = solari_scene::shaders::check_crate_shaders(&own, &[], &[]).unwrap_err();
    assert!(err.to_string().contains("bad"), "{err}");
    let mut layouts = std::collections::HashMap::new();
    layouts.insert("S".to_string(), (8u32, [("b".to_string(), 4u32)].into()));
    let check = solari_scene::shaders::check_layout;
    assert!(check(&layouts, "S", 8, &[("b", 4)]).is_ok());
    assert!(check(&layouts, "S", 12, &[("b", 4)]).is_err());
    assert!(check(&layouts, "S", 8, &[("b", 0)]).is_err());
    assert!(check(&layouts, "T", 8, &[]).is_err());
}

#[test]
fn bindings_are_bound_by_their_wgsl_names() {
    use solari_scene::bindings::check_groups;
    use solari_scene::gbuffer::{GBUFFER_VIEW_BINDINGS, TRANSFORMS_BINDINGS};
    use solari_scene::gbuffer_debug::GBUFFER_DEBUG_BINDINGS;
    use solari_scene::trace_pass::TRACE_RAYS_BINDINGS;
    use solari_scene::view_pass::{PRIMARY_BINDINGS, RAY_BENCH_BINDINGS, VIEW_BINDINGS};
    check_groups(
        &[
            ("primary", &[&VIEW_BINDINGS, &PRIMARY_BINDINGS]),
            ("ray_bench", &[&VIEW_BINDINGS, &RAY_BENCH_BINDINGS]),
            ("trace_rays", &[&TRACE_RAYS_BINDINGS]),
            (
                "gbuffer_raster",
                &[&GBUFFER_VIEW_BINDINGS, &TRANSFORMS_BINDINGS],
            ),
            (
                "gbuffer_traced",
                &[&GBUFFER_VIEW_BINDINGS, &TRANSFORMS_BINDINGS],
            ),
            ("gbuffer_debug", &[&GBUFFER_DEBUG_BINDINGS]),
        ],
        &[],
    )
    .unwrap_or_else(|e| panic!("{e}"));
}
