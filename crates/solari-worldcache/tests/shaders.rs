//! CPU-only: the cache's shaders compose and validate for both tracing backends, every loop
//! carries its `// bound:` note, and the Rust mirrors have the sizes and offsets naga gives
//! their WGSL twins.

use solari_scene::shaders::{Backend, StructLayout, compose, struct_layouts, validate};
use solari_worldcache::{
    ENTRY_POINTS, GpuCacheCell, GpuCacheParams, GpuNewSample, MODULES, modules,
};
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
    for (name, source) in MODULES.iter().chain(ENTRY_POINTS) {
        let missing = solari_scene::shaders::loops_without_bound(source);
        assert!(
            missing.is_empty(),
            "{name}: loops without a bound at lines {missing:?}"
        );
    }
}

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
        "WorldCacheParams",
        size_of::<GpuCacheParams>(),
        &[
            ("frame", offset_of!(GpuCacheParams, frame)),
            ("mask", offset_of!(GpuCacheParams, mask)),
            ("flags", offset_of!(GpuCacheParams, flags)),
            (
                "max_ray_distance",
                offset_of!(GpuCacheParams, max_ray_distance),
            ),
            ("light_count", offset_of!(GpuCacheParams, light_count)),
            ("height", offset_of!(GpuCacheParams, height)),
        ],
    );
    check(
        "CacheCell",
        size_of::<GpuCacheCell>(),
        &[
            ("normal", offset_of!(GpuCacheCell, normal)),
            ("irradiance", offset_of!(GpuCacheCell, irradiance)),
            ("indirect", offset_of!(GpuCacheCell, indirect)),
        ],
    );
    check(
        "NewSample",
        size_of::<GpuNewSample>(),
        &[
            ("updated", offset_of!(GpuNewSample, updated)),
            ("indirect", offset_of!(GpuNewSample, indirect)),
        ],
    );
}
