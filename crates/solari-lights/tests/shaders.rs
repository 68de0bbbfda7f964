//! CPU-only: the light-tile shaders compose and validate for both tracing backends, every
//! loop carries its `// bound:` note, and every Rust mirror of a light struct has the size and
//! member offsets naga gives its WGSL twin.

use solari_lights::gpu::{GpuEmissiveTriangle, GpuEnvironmentCell, GpuLight, GpuLightInfo};
use solari_lights::tiles::{ENTRY_POINTS, GpuTileParams};
use solari_lights::{LightSampleId, MODULES, PackedLightSample};
use solari_scene::shaders::CheckedShaders;
use std::mem::offset_of;

fn layouts() -> CheckedShaders {
    let all: Vec<_> = [MODULES, ENTRY_POINTS].concat();
    CheckedShaders::new(&all, ENTRY_POINTS, &all)
}

#[test]
fn entry_points_compose_and_validate_for_both_backends() {
    layouts();
}

#[test]
fn rust_mirrors_match_naga_layouts() {
    let l = layouts();
    macro_rules! mirror {
        ($wgsl:literal, $rust:ty, [$($field:ident),*]) => {
            l.mirror(
                $wgsl,
                size_of::<$rust>(),
                &[$((stringify!($field), offset_of!($rust, $field))),*],
            )
        };
    }
    mirror!(
        "GpuLight",
        GpuLight,
        [
            radiance,
            area,
            to_light,
            cos_radius,
            kind,
            instance,
            first_triangle,
            triangle_count,
            power_pmf,
            alias_threshold,
            alias_index
        ]
    );
    mirror!(
        "GpuEmissiveTriangle",
        GpuEmissiveTriangle,
        [v0, cdf, e1, area, e2, primitive]
    );
    mirror!(
        "GpuLightInfo",
        GpuLightInfo,
        [
            light_count,
            selection,
            first_punctual,
            sphere_count,
            environment_light,
            environment_cells_x,
            environment_cells_y,
            first_directional
        ]
    );
    mirror!(
        "GpuEnvironmentCell",
        GpuEnvironmentCell,
        [pmf, threshold, alias_index]
    );
    mirror!(
        "PackedLightSample",
        PackedLightSample,
        [position, normal_flags, radiance, inverse_pdf]
    );
    mirror!("LightSampleId", LightSampleId, [light, triangle, point]);
    mirror!("TileParams", GpuTileParams, [frame, sample_count]);
}

#[test]
fn bindings_are_bound_by_their_wgsl_names() {
    use solari_lights::{ENVIRONMENT_BINDINGS, LIGHT_BINDINGS, PRESAMPLE_BINDINGS};
    use solari_scene::bindings::check_groups;
    let all = [MODULES, ENTRY_POINTS].concat();
    check_groups(
        &[(
            "presample_light_tiles",
            &[&PRESAMPLE_BINDINGS, &LIGHT_BINDINGS, &ENVIRONMENT_BINDINGS],
        )],
        &all,
    )
    .unwrap_or_else(|e| panic!("{e}"));
}
