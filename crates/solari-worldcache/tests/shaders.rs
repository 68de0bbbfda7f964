//! CPU-only: the cache's shaders compose and validate for both tracing backends, every loop
//! carries its `// bound:` note, and the Rust mirrors have the sizes and offsets naga gives
//! their WGSL twins.

use solari_scene::shaders::CheckedShaders;
use solari_worldcache::{
    ENTRY_POINTS, GpuCacheCell, GpuCacheParams, GpuNewSample, MODULES, modules,
};
use std::mem::offset_of;

fn layouts() -> CheckedShaders {
    let own: Vec<_> = [MODULES, ENTRY_POINTS].concat();
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
    l.mirror(
        "CacheCell",
        size_of::<GpuCacheCell>(),
        &[
            ("normal", offset_of!(GpuCacheCell, normal)),
            ("irradiance", offset_of!(GpuCacheCell, irradiance)),
            ("indirect", offset_of!(GpuCacheCell, indirect)),
        ],
    );
    l.mirror(
        "NewSample",
        size_of::<GpuNewSample>(),
        &[
            ("updated", offset_of!(GpuNewSample, updated)),
            ("indirect", offset_of!(GpuNewSample, indirect)),
        ],
    );
}

#[test]
fn bindings_are_bound_by_their_wgsl_names() {
    use solari_scene::bindings::check_groups;
    use solari_worldcache::{CACHE_BINDINGS, DISPATCH_BINDINGS, TARGET_BINDINGS};
    let cache = [&CACHE_BINDINGS];
    // The update reads light samples from the tiles, not the light list.
    let update = [&CACHE_BINDINGS, &solari_lights::TILE_BINDINGS];
    check_groups(
        &[
            ("world_cache_decay", &cache),
            ("world_cache_count", &cache),
            (
                "world_cache_offsets",
                &[&CACHE_BINDINGS, &DISPATCH_BINDINGS],
            ),
            ("world_cache_compact", &cache),
            ("world_cache_update", &update),
            ("world_cache_blend", &cache),
            ("world_cache_gi", &[&CACHE_BINDINGS, &TARGET_BINDINGS]),
            ("world_cache_view", &[&CACHE_BINDINGS, &TARGET_BINDINGS]),
        ],
        &modules(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
}
