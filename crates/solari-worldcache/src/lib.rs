//! # solari-worldcache
//!
//! A world-space radiance cache for the Solari workspace: surfaces are split into cells by a
//! spatial hash (no build step; cells appear where something looks), each cell keeps a running
//! estimate of the light arriving at it, and a few rays per cell per frame keep the estimate
//! fresh. Cells read each other, so light takes one more bounce every frame: over frames the
//! cache holds full multi-bounce diffuse light. ReSTIR GI ends its paths in it; on its own it
//! is the cheapest GI tier ([`WorldCache::encode_gi`]: albedo × cached indirect light).
//!
//! ## What a cell stores
//!
//! Irradiance over π, `(1/π) ∫ L(ω) cos θ dω`, at the point that created the cell, treating
//! every surface as Lambertian (Solari's choice): a surface of albedo ρ there reflects
//! `ρ ×` that. Two sums are kept: everything, and the part not from the light list
//! (`indirect`: light after at least one bounce, and the environment), so a pixel whose
//! direct light comes from ReSTIR DI can add only the rest.
//!
//! ## Addressing (after Solari 0.17–0.19)
//!
//! - **Level of detail**: cells are [`WorldCacheSettings::cell_size`] near the camera and
//!   double in size every [`WorldCacheSettings::lod_distance`] (`level = floor(log2(1 + d /
//!   lod_distance))`); with [`WorldCacheSettings::soft_lod`] (default on) a lookup near a
//!   level's far edge lands one level coarser with probability `fract(level)³`, so the
//!   levels blend instead of meeting at a hard distance.
//! - **Descriptor**: integer cell coordinates at that level, the level, and the axis
//!   direction closest to the geometric normal (six buckets, so a wall and the floor meeting
//!   it, or the two sides of a thin wall, never share a cell).
//! - **Key and checksum**: two unrelated hashes of the descriptor (PCG rounds for the slot,
//!   Wellons' lowbias32 for the checksum); **linear probing** for at most
//!   [`WorldCacheSettings::max_search_steps`] slots; **insertion by compare-exchange** of the
//!   empty checksum, after which the creator records the cell's position and normal.
//! - **Jitter** ([`WorldCacheSettings::jitter`]): lookups from the GI pass and from cell
//!   updates move up to half a cell in the tangent plane (the debug view's do not).
//! - **Light-leak rule** ([`WorldCacheSettings::leak_rule`]): a query at the end of a ray
//!   shorter than its cell uses the finest level.
//! - **Full table**: a lookup that finds only other cells returns nothing (zero light) and
//!   counts an overflow ([`CacheStats::overflows`]); no other cell is touched.
//!
//! The Rust twin of the addressing is [`hash`]; tests compare it with the GPU bit for bit.
//!
//! ## Upkeep, each frame
//!
//! 1. **Decay**: every cell loses a frame of life; dead cells free their slots. A pixel's
//!    query renews a cell to [`WorldCacheSettings::lifetime`]; another cell's query only
//!    raises it to the asking cell's remaining life (Solari 0.18), so once no pixel sees an
//!    area its cells die within `lifetime` frames.
//! 2. **Compaction**: a parallel prefix sum over 1,024-slot blocks lists live cells densely
//!    and sizes the next passes' indirect dispatch.
//! 3. **Update**: per live cell, one direct-light sample (RIS over
//!    [`WorldCacheSettings::direct_candidates`] light-tile samples, one shadow ray) and one
//!    cosine-distributed ray of at most [`WorldCacheSettings::max_ray_distance`] that reads
//!    the cache where it lands. Past [`WorldCacheSettings::update_budget`] live cells, each
//!    updates with probability budget / live cells.
//! 4. **Blend**: each new sample enters the cell's running mean with weight
//!    `1 / min(samples, cap)`; the cap falls from
//!    [`WorldCacheSettings::max_temporal_samples`] toward 1 as the cell's luminance changes
//!    (an adaptive factor after Guillaume Boissé, as in Solari 0.18), and while the cell is
//!    young it is at most [`warm_up_window`] of its count
//!    ([`WorldCacheSettings::warm_up_exponent`]): a cell's first samples read neighbours that
//!    are still filling, and a plain running mean kept that darkness for dozens of frames.
//!    Non-finite samples are dropped. After [`WorldCache::follow_light_change`] the blend
//!    averages at most [`WorldCacheSettings::light_change_samples`] samples for a few frames:
//!    the adaptive factor sees a change only once the mean has moved, and a switched-off
//!    light's bounce light, fed from cell to cell, otherwise faded over dozens of frames.
//! 5. **Warm-up rounds**: in the first [`WorldCacheSettings::warm_up_frames`] frames after
//!    the table is made or emptied, and the frames after [`WorldCache::follow_light_change`],
//!    update and blend run [`WorldCacheSettings::warm_up_rounds`] times, each round with its
//!    own random numbers and reading what the last one blended, so light crosses several
//!    bounces a frame while the cache is cold or the lights have just changed.
//!
//! ## Known limits
//!
//! - Deleting a dead cell from the middle of a probing run can hide a live cell further down
//!   the run; the next lookup creates a fresh copy and the hidden one dies of age. The cell
//!   loses its history once, nothing is corrupted.
//! - In a closed room whose surfaces reflect everything (albedo 1) light has no way out and
//!   the true answer is unbounded; the cache then grows each frame, as it should.
//! - An indirect ray that hits nothing within `max_ray_distance` counts as reaching the
//!   environment.
//!
//! ## Use
//!
//! Per frame, after the light tiles: [`WorldCache::prepare`], [`WorldCache::encode`], and
//! after the direct light [`WorldCache::encode_gi`] (or [`WorldCache::encode_view`]); when
//! the lights change, [`WorldCache::follow_light_change`] before the next `prepare`. The
//! real-time renderer in `solari-renderer` is the worked example; the README has a compiled one.

pub mod cache;
pub mod hash;
pub mod settings;

pub use cache::{
    CACHE_BINDINGS, CacheStats, DISPATCH_BINDINGS, FIRST_BINDING, PASS_LABELS, TARGET_BINDINGS,
    WorldCache,
};
pub use settings::{
    CELL_CHECK, GpuCacheCell, GpuCacheParams, GpuNewSample, MAX_SETTING_FRAMES,
    MAX_WARM_UP_EXPONENT, MAX_WARM_UP_ROUNDS, WorldCacheSettings, warm_up_window,
};

/// The crate's importable WGSL modules, by module name: `world_cache` (bindings, lookup,
/// `query_world_cache`) and `world_cache_hash` (addressing).
pub const MODULES: &[(&str, &str)] = &[
    ("world_cache", include_str!("../shaders/world_cache.wesl")),
    (
        "world_cache_hash",
        include_str!("../shaders/world_cache_hash.wesl"),
    ),
    (
        "world_cache_scan",
        include_str!("../shaders/world_cache_scan.wesl"),
    ),
];

/// The crate's entry-point shaders, by module name.
pub const ENTRY_POINTS: &[(&str, &str)] = &[
    (
        "world_cache_decay",
        include_str!("../shaders/world_cache_decay.wesl"),
    ),
    (
        "world_cache_count",
        include_str!("../shaders/world_cache_count.wesl"),
    ),
    (
        "world_cache_offsets",
        include_str!("../shaders/world_cache_offsets.wesl"),
    ),
    (
        "world_cache_compact",
        include_str!("../shaders/world_cache_compact.wesl"),
    ),
    (
        "world_cache_update",
        include_str!("../shaders/world_cache_update.wesl"),
    ),
    (
        "world_cache_blend",
        include_str!("../shaders/world_cache_blend.wesl"),
    ),
    (
        "world_cache_gi",
        include_str!("../shaders/world_cache_gi.wesl"),
    ),
    (
        "world_cache_view",
        include_str!("../shaders/world_cache_view.wesl"),
    ),
];

/// Every module the crate's shaders need beyond `solari-scene`'s: its own and the lights'.
pub fn modules() -> Vec<(&'static str, &'static str)> {
    [
        solari_lights::MODULES,
        solari_lights::tiles::ENTRY_POINTS,
        MODULES,
        ENTRY_POINTS,
    ]
    .concat()
}

/// The README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
