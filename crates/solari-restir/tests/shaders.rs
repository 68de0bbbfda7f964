//! CPU-only: ReSTIR DI's shaders compose and validate for both tracing backends, every loop
//! carries its `// bound:` note, and the Rust mirrors have the sizes and offsets naga gives
//! their WGSL twins (including the G-buffer reader's `FrameViews`).

use solari_restir::{ENTRY_POINTS, GpuDiParams, GpuReservoir, MODULES, modules};
use solari_scene::gbuffer::GpuFrameViews;
use solari_scene::shaders::CheckedShaders;
use std::mem::offset_of;

fn layouts() -> CheckedShaders {
    let reader = include_str!("../../solari-scene/shaders/gbuffer_read.wesl");
    let own: Vec<_> = [MODULES, ENTRY_POINTS, &[("gbuffer_read", reader)]].concat();
    CheckedShaders::new(&own, ENTRY_POINTS, &modules())
}

#[test]
fn entry_points_compose_and_validate_for_both_backends() {
    layouts();
}

#[test]
fn rust_mirrors_match_naga_layouts() {
    let l = layouts();
    l.mirror(
        "Reservoir",
        size_of::<GpuReservoir>(),
        &[
            ("sample", offset_of!(GpuReservoir, sample)),
            ("confidence", offset_of!(GpuReservoir, confidence)),
            ("weight", offset_of!(GpuReservoir, weight)),
        ],
    );
    l.mirror(
        "DiParams",
        size_of::<GpuDiParams>(),
        &[
            ("frame", offset_of!(GpuDiParams, frame)),
            ("flags", offset_of!(GpuDiParams, flags)),
            ("spatial_radius", offset_of!(GpuDiParams, spatial_radius)),
            ("confidence_cap", offset_of!(GpuDiParams, confidence_cap)),
            (
                "translation_count",
                offset_of!(GpuDiParams, translation_count),
            ),
        ],
    );
    l.mirror(
        "FrameViews",
        size_of::<GpuFrameViews>(),
        &[
            ("previous", offset_of!(GpuFrameViews, previous)),
            ("history_valid", offset_of!(GpuFrameViews, history_valid)),
        ],
    );
    l.mirror(
        "GpuView",
        size_of::<solari_scene::gpu_types::GpuView>(),
        &[("znear", offset_of!(solari_scene::gpu_types::GpuView, znear))],
    );
}

#[test]
fn bindings_are_bound_by_their_wgsl_names() {
    use solari_restir::DI_BINDINGS;
    use solari_scene::bindings::check_groups;
    let own = [&DI_BINDINGS][..].to_vec();
    let lights = [
        &solari_lights::LIGHT_BINDINGS,
        &solari_lights::ENVIRONMENT_BINDINGS,
    ];
    let initial: Vec<_> = own
        .iter()
        .chain(&lights)
        .chain(&[&solari_lights::TILE_BINDINGS])
        .copied()
        .collect();
    // The spatial pass reads the light list, not the tiles.
    let spatial: Vec<_> = own.iter().chain(&lights).copied().collect();
    check_groups(
        &[
            ("restir_di_initial", &initial),
            ("restir_di_spatial", &spatial),
            ("restir_di_emission", &own),
        ],
        &modules(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
}

fn gi_layouts() -> CheckedShaders {
    use solari_restir::{GI_ENTRY_POINTS, gi_modules};
    let own: Vec<_> = [MODULES, GI_ENTRY_POINTS].concat();
    CheckedShaders::new(&own, GI_ENTRY_POINTS, &gi_modules())
}

#[test]
fn gi_entry_points_compose_and_mirrors_match() {
    use solari_restir::{GpuGiParams, GpuGiReservoir};
    let l = gi_layouts();
    l.mirror(
        "GiReservoir",
        size_of::<GpuGiReservoir>(),
        &[
            ("position", offset_of!(GpuGiReservoir, position)),
            ("weight", offset_of!(GpuGiReservoir, weight)),
            ("radiance", offset_of!(GpuGiReservoir, radiance)),
            ("normal", offset_of!(GpuGiReservoir, normal)),
            ("confidence", offset_of!(GpuGiReservoir, confidence)),
        ],
    );
    l.mirror(
        "GiParams",
        size_of::<GpuGiParams>(),
        &[
            ("flags", offset_of!(GpuGiParams, flags)),
            ("spatial_radius", offset_of!(GpuGiParams, spatial_radius)),
            ("jacobian_bound", offset_of!(GpuGiParams, jacobian_bound)),
            (
                "max_ray_distance",
                offset_of!(GpuGiParams, max_ray_distance),
            ),
            ("initial_samples", offset_of!(GpuGiParams, initial_samples)),
            ("history_cap", offset_of!(GpuGiParams, history_cap)),
            ("rate_shift", offset_of!(GpuGiParams, rate_shift)),
            ("own_share", offset_of!(GpuGiParams, own_share)),
            ("tile_samples", offset_of!(GpuGiParams, tile_samples)),
            (
                "glossy_roughness",
                offset_of!(GpuGiParams, glossy_roughness),
            ),
        ],
    );
}

#[test]
fn gi_bindings_are_bound_by_their_wgsl_names() {
    use solari_restir::{GI_BINDINGS, GI_TARGET_BINDINGS, gi_modules};
    use solari_scene::bindings::check_groups;
    use solari_worldcache::CACHE_BINDINGS;
    // The initial pass reads the lights and their tiles at glossy hits (group 3 beside `lit`).
    let initial = [
        &GI_BINDINGS,
        &CACHE_BINDINGS,
        &GI_TARGET_BINDINGS,
        &solari_lights::LIGHT_BINDINGS,
        &solari_lights::TILE_BINDINGS,
        &solari_lights::ENVIRONMENT_BINDINGS,
    ];
    let spatial = [&GI_BINDINGS, &GI_TARGET_BINDINGS];
    check_groups(
        &[
            ("restir_gi_initial", &initial),
            ("restir_gi_spatial", &spatial),
        ],
        &gi_modules(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn specular_gi_composes_its_mirror_matches_and_bindings_have_their_names() {
    use solari_restir::specular::{GpuSpecularParams, SPECULAR_BINDINGS};
    use solari_restir::{SPECULAR_ENTRY_POINTS, specular_modules};
    use solari_scene::bindings::check_groups;
    use solari_worldcache::CACHE_BINDINGS;
    let own: Vec<_> = [MODULES, SPECULAR_ENTRY_POINTS].concat();
    let l = CheckedShaders::new(&own, SPECULAR_ENTRY_POINTS, &specular_modules());
    l.mirror(
        "SpecularParams",
        size_of::<GpuSpecularParams>(),
        &[
            ("flags", offset_of!(GpuSpecularParams, flags)),
            (
                "rough_threshold",
                offset_of!(GpuSpecularParams, rough_threshold),
            ),
            ("tile_samples", offset_of!(GpuSpecularParams, tile_samples)),
            (
                "max_ray_distance",
                offset_of!(GpuSpecularParams, max_ray_distance),
            ),
        ],
    );
    let groups = [
        &SPECULAR_BINDINGS,
        &CACHE_BINDINGS,
        &solari_lights::LIGHT_BINDINGS,
        &solari_lights::TILE_BINDINGS,
        &solari_lights::ENVIRONMENT_BINDINGS,
    ];
    check_groups(&[("specular_gi", &groups)], &specular_modules())
        .unwrap_or_else(|e| panic!("{e}"));
}
