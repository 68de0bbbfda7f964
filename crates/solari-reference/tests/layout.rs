//! CPU-only: the path tracer's uniform mirror has the size naga gives its WGSL twin.

use solari_reference::path_tracer::{MODULES, ReferenceParams};
use solari_scene::shaders::{Backend, compose, validate};

/// The modules the path tracer composes with beyond solari-scene's.
fn extra() -> Vec<(&'static str, &'static str)> {
    solari_lights::MODULES
        .iter()
        .chain(MODULES)
        .copied()
        .collect()
}

#[test]
fn reference_params_match_naga_layout() {
    let extra = extra();
    for backend in Backend::ALL {
        let wgsl = compose("reference", backend, &extra).expect("compose");
        let module = validate("reference", &wgsl).expect("valid");
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).expect("layout");
        let (handle, ty) = module
            .types
            .iter()
            .find(|(_, t)| {
                t.name
                    .as_deref()
                    .is_some_and(|n| n.ends_with("ReferenceParams"))
            })
            .expect("ReferenceParams in the composed shader");
        let naga::TypeInner::Struct { members, .. } = &ty.inner else {
            panic!("not a struct")
        };
        assert_eq!(layouter[handle].size as usize, size_of::<ReferenceParams>());
        let offset = |name: &str| {
            members
                .iter()
                .find(|m| m.name.as_deref() == Some(name))
                .unwrap()
                .offset
        };
        assert_eq!(
            offset("max_bounces") as usize,
            std::mem::offset_of!(ReferenceParams, max_bounces)
        );
        assert_eq!(
            offset("sample_index") as usize,
            std::mem::offset_of!(ReferenceParams, sample_index)
        );
        assert_eq!(
            offset("safety_cap") as usize,
            std::mem::offset_of!(ReferenceParams, safety_cap)
        );
        assert_eq!(
            offset("pixel_centre") as usize,
            std::mem::offset_of!(ReferenceParams, pixel_centre)
        );
    }
}

#[test]
fn bindings_are_bound_by_their_wgsl_names() {
    use solari_reference::path_tracer::REFERENCE_BINDINGS;
    use solari_scene::bindings::check_groups;
    use solari_scene::view_pass::VIEW_BINDINGS;
    let extra = extra();
    let groups = [
        &VIEW_BINDINGS,
        &REFERENCE_BINDINGS,
        &solari_lights::LIGHT_BINDINGS,
        &solari_lights::ENVIRONMENT_BINDINGS,
    ];
    check_groups(&[("reference", &groups)], &extra).unwrap_or_else(|e| panic!("{e}"));
}
