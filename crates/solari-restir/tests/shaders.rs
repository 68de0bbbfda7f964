//! CPU-only: ReSTIR DI's shaders compose and validate for both tracing backends, every loop
//! carries its `// bound:` note, and the Rust mirrors have the sizes and offsets naga gives
//! their WGSL twins (including the G-buffer reader's `FrameViews`).

use solari_restir::{ENTRY_POINTS, GpuDiParams, GpuReservoir, MODULES, modules};
use solari_scene::gbuffer::GpuFrameViews;
use solari_scene::shaders::{Backend, StructLayout, compose, struct_layouts, validate};
use std::collections::HashMap;
use std::mem::offset_of;

#[test]
fn entry_points_compose_and_validate_for_both_backends() {
    for (entry, _) in ENTRY_POINTS {
        for backend in Backend::ALL {
            let wgsl = compose(entry, backend, &modules()).expect("compose");
            validate(entry, &wgsl).unwrap_or_else(|e| panic!("{entry} ({backend:?}): {e}"));
        }
    }
    let reader = include_str!("../../solari-scene/shaders/gbuffer_read.wesl");
    for (name, source) in MODULES
        .iter()
        .chain(ENTRY_POINTS)
        .chain(&[("gbuffer_read", reader)])
    {
        let missing = solari_scene::shaders::loops_without_bound(source);
        assert!(
            missing.is_empty(),
            "{name}: loops without a bound at lines {missing:?}"
        );
    }
}

/// (size, member → offset) of every named struct in the composed passes.
fn layouts() -> HashMap<String, StructLayout> {
    let mut out = HashMap::new();
    for (entry, _) in ENTRY_POINTS {
        let wgsl = compose(entry, Backend::Software, &modules()).unwrap();
        out.extend(struct_layouts(&validate(entry, &wgsl).unwrap()).unwrap());
    }
    out
}

#[test]
fn rust_mirrors_match_naga_layouts() {
    let l = layouts();
    let check = |wgsl: &str, size: usize, fields: &[(&str, usize)]| {
        let (wgsl_size, offsets) = l.get(wgsl).unwrap_or_else(|| panic!("no WGSL {wgsl}"));
        assert_eq!(*wgsl_size as usize, size, "size of {wgsl}");
        for (name, offset) in fields {
            assert_eq!(offsets[*name] as usize, *offset, "{wgsl}.{name}");
        }
    };
    check(
        "Reservoir",
        size_of::<GpuReservoir>(),
        &[
            ("sample", offset_of!(GpuReservoir, sample)),
            ("confidence", offset_of!(GpuReservoir, confidence)),
            ("weight", offset_of!(GpuReservoir, weight)),
        ],
    );
    check(
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
    check(
        "FrameViews",
        size_of::<GpuFrameViews>(),
        &[
            ("previous", offset_of!(GpuFrameViews, previous)),
            ("history_valid", offset_of!(GpuFrameViews, history_valid)),
        ],
    );
    check(
        "GpuView",
        size_of::<solari_scene::gpu_types::GpuView>(),
        &[("znear", offset_of!(solari_scene::gpu_types::GpuView, znear))],
    );
}
