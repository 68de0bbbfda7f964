//! The cache's knobs, each with its default and its cost, and the GPU structs they fill.

use bytemuck::{Pod, Zeroable};
use solari_scene::GpuError;

/// Fewest table slots (one compaction block).
pub const MIN_CAPACITY: u32 = 1 << 10;
/// Most table slots: the compaction's scan handles 2,048 blocks of 1,024, and the update's
/// indirect dispatch stays under 65,536 workgroups of 64.
pub const MAX_CAPACITY: u32 = 1 << 21;
/// Most probing steps (the shader loop's bound).
pub const MAX_SEARCH_STEPS: u32 = 64;
/// Most direct-light candidates per cell update (the shader loop's bound).
pub const MAX_DIRECT_CANDIDATES: u32 = 64;
/// Largest [`WorldCacheSettings::warm_up_exponent`].
pub const MAX_WARM_UP_EXPONENT: f32 = 16.0;
/// Most [`WorldCacheSettings::warm_up_rounds`].
pub const MAX_WARM_UP_ROUNDS: u32 = 16;

/// The most frames a frame-count setting may hold ([`WorldCacheSettings::lifetime`],
/// [`WorldCacheSettings::light_change_frames`], [`WorldCacheSettings::warm_up_frames`]):
/// about half an hour at 60 frames a second, past which a count is a mistake, not a choice.
pub const MAX_SETTING_FRAMES: u32 = 100_000;

/// The most samples a cell that has blended `samples` of them averages while young
/// ([`WorldCacheSettings::warm_up_exponent`]): 1 + (most − 1)(samples / most)^exponent,
/// `most` from `samples` = `most` on; `most` itself with the exponent 0. Rust twin of WGSL
/// `world_cache_warm_up_cap`.
pub fn warm_up_window(samples: f32, most: f32, exponent: f32) -> f32 {
    if exponent <= 0.0 || most <= 1.0 {
        return most;
    }
    let age = (samples / most).clamp(0.0, 1.0);
    1.0 + (most - 1.0) * age.powf(exponent)
}

/// Every knob of [`crate::WorldCache`]. Lengths are in world units (metres for glTF).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldCacheSettings {
    /// Table slots, a power of two from 2^10 to 2^21 (default 2^19 = 524,288). Each slot
    /// costs 92 bytes (48 MiB at the default); more slots mean fewer probing collisions and
    /// room for larger views. Changing it clears the cache. With 0.15 m cells the orbit
    /// around `interior` keeps 118–145k cells alive: 2^18 slots lost 131,815 lookups in
    /// 20,000 frames to full probe runs, 2^19 none (`benches/RESULTS.md`).
    pub capacity: u32,
    /// Edge of the finest cells (default 0.15, Solari 0.19's). Smaller cells follow light
    /// more closely (less leaking, sharper variation) but there are more of them to update,
    /// each noisier. Measured against 0.25 (`benches/RESULTS.md`, "World cache: Solari
    /// 0.19's refinements"): with path GI relMSE −6% on interior and −7% on sun_boxes, the
    /// same elsewhere, for 1.7–2.3× the cells; it needs the update budget that holds them.
    pub cell_size: f32,
    /// Distance from the camera over which cells double in size (default 10): level
    /// `floor(log2(1 + d / lod_distance))`, so cells are finest within 10, twice as large
    /// to 30, four times to 70 and so on. Infinite: one level everywhere.
    pub lod_distance: f32,
    /// Frames a cell lives without being queried by a pixel (default 30). A cell queried by
    /// another cell only gets that cell's remaining life, so areas the camera left die out
    /// within this many frames.
    pub lifetime: u32,
    /// Slots a lookup probes before it gives up (default 32, at most 64). A full run makes
    /// the query return nothing and counts an overflow. Linear probing clusters: at the
    /// default 2^18 slots a table 20% full (the `interior` hall at 1080p) holds a cell 8 or
    /// more slots from its home about once per fill, which the former default of 8 lost;
    /// 32 steps are not needed below about half full (`tests/table.rs` checks 40% with the
    /// real hash). Longer runs cost only the lookups that land in a cluster.
    pub max_search_steps: u32,
    /// Cap on the samples averaged per cell (default 30): higher is smoother under static
    /// light, slower to follow changes; the adaptive blend lowers it where the cell's
    /// luminance is changing.
    pub max_temporal_samples: f32,
    /// The most samples a cell averages in the [`WorldCacheSettings::light_change_frames`]
    /// frames after [`crate::WorldCache::follow_light_change`] (default 4; at least 1, at
    /// most [`WorldCacheSettings::max_temporal_samples`] takes effect). The adaptive blend
    /// sees a change only once the running mean has moved, and a cache's indirect light
    /// feeds on itself, so a light switched off faded over dozens of frames: on lavapipe's
    /// 64² Cornell box 0.26–0.28 of a bulb's light was left 16 frames after the switch with
    /// path GI, 0.05–0.07 with this (0.036 averaging 2; `benches/RESULTS.md`, "The world
    /// cache follows a light switch").
    /// Afterwards a cell's count grows back by one a frame, as from a fresh start (with the
    /// [`WorldCacheSettings::warm_up_exponent`] window, which follows the count).
    pub light_change_samples: f32,
    /// Frames [`crate::WorldCache::follow_light_change`] shortens the averaging for (default
    /// 8; 0: never).
    pub light_change_frames: u32,
    /// How fast a young cell's averaging lengthens (default 2; 0 turns the ramp off, at
    /// most [`MAX_WARM_UP_EXPONENT`]): a cell that has blended n samples averages at most
    /// [`warm_up_window`]`(n)` = 1 + (m − 1)(n / m)^e of them, m being
    /// [`WorldCacheSettings::max_temporal_samples`], so the window reaches m when the count
    /// does and old cells blend as before. A cell's first samples read its neighbours
    /// while they are still filling, so a plain running mean (1/n) kept their early
    /// darkness for dozens of frames, and multi-bounce light compounds the lag from cell to
    /// cell. Measured with the renderer's defaults at 960×540 against 1024-spp references on
    /// an H100 (`benches/RESULTS.md`, "Young world-cache cells"), relMSE of a still camera's
    /// frame 8 / frame 32: interior 0.0787 / 0.0185 → 0.0585 / 0.0088, the Cornell box
    /// 0.0067 / 0.0017 → 0.0038 / 0.0006, sun_boxes −25% / −23%; along the orbit, interior's
    /// frame 8 0.0553 → 0.0321; frame 136 and the 16-frame means within ±2%; no time. Its
    /// price: young cells are noisier, and ReSTIR GI, whose histories keep the samples they
    /// chose, reads 1% brighter on interior once converged (relMSE +4.5%). An exponent of 3
    /// was as good for path GI and cost ReSTIR GI +11%.
    pub warm_up_exponent: f32,
    /// Update rounds per frame (the update and blend passes, each round reading the cells
    /// the last one left) in the [`WorldCacheSettings::warm_up_frames`] frames after the
    /// table is made or emptied, and after a light change (default 4; 1 turns them off, at
    /// most [`MAX_WARM_UP_ROUNDS`]). Light crosses one more bounce between cells per round, so a
    /// cold cache holds the light of four bounces after its first updated frame instead of
    /// one, and its cells count four samples a frame (each round draws its own random
    /// numbers). The cost is the update and blend passes again, only in those frames:
    /// `interior` at 1080p on an H200 spent 0.46–0.61 ms a frame in the update instead of
    /// 0.12–0.14 (frames 1–7; the frame +0.42–0.55 ms), and the same afterwards. What it
    /// buys (H200, 960×540, defaults with the fallback denoiser, against 1024-spp
    /// references; `benches/RESULTS.md`, "Update rounds for a cold cache"): relMSE of frame
    /// 4 / frame 8 on `interior` 0.101 / 0.061 → 0.046 / 0.022 (its brightness at frame 8
    /// 74% → 86% of the reference's), the Cornell box −58% / −58%, sun_boxes −34% / −40%,
    /// many_lights −6% / −5%; frames 16 and 32 −47% and −42% on the Cornell box, within
    /// ±2% on `interior` and many_lights, sun_boxes −2% and +8%; the mean of frames 121–136
    /// within ±2% everywhere. Four rounds over eight frames (the default) and over 32 gave
    /// the same young frames; the longer run helped frames 16–32 (`interior` −17% / −10%,
    /// with the same random numbers each round) and cost converged `interior` +2.7%.
    pub warm_up_rounds: u32,
    /// Frames after the table is made or emptied ([`crate::WorldCache::clear`], a new
    /// capacity) that run [`WorldCacheSettings::warm_up_rounds`] (default 8; 0: none; at most
    /// [`MAX_SETTING_FRAMES`]). After [`crate::WorldCache::follow_light_change`] the rounds
    /// run for [`WorldCacheSettings::light_change_frames`] frames instead.
    pub warm_up_frames: u32,
    /// Cells updated per frame before updates become stochastic (default 200,000): above it
    /// each active cell updates with probability budget / active, bounding the cost. At
    /// 40,000 the finer cells of `interior` (90–135k) updated too rarely to converge and its
    /// image lost 2.5–3.5% of its light; updating all of them, the whole upkeep costs 0.31 ms
    /// at 1080p on an H100 (`benches/RESULTS.md`, "World cache: Solari 0.19's refinements").
    pub update_budget: u32,
    /// Light-tile samples resampled for each cell's direct-light sample (default 8, at most
    /// 64); one shadow ray tests the chosen one.
    pub direct_candidates: u32,
    /// Longest indirect ray traced from a cell (default 50). A ray that hits nothing within
    /// it counts as escaping to the environment, so scenes larger than this may see
    /// environment light through distant walls.
    pub max_ray_distance: f32,
    /// Jitter lookups within the surface's tangent plane by up to half a cell (default on):
    /// the GI pass's pixel lookups and the update's cell-to-cell lookups (not the debug
    /// view's). Blurs the cell grid's blocks into noise that accumulation averages away, at
    /// the price of some light leaking across cell borders.
    pub jitter: bool,
    /// Use the finest level when the query ray is shorter than the cell it would land in
    /// (Solari 0.19's light-leak rule; default on): a short ray ends near a corner, where a
    /// coarse cell spans both sides.
    pub leak_rule: bool,
    /// Blend neighbouring levels of detail instead of switching at a hard distance
    /// (Solari 0.19's "gentler LOD transitions"; default on): near the top of a level's
    /// band a lookup lands in the next coarser cell with probability fract(level)³, drawn
    /// per lookup ([`crate::hash::CellGrid::level_with`]). Measured neutral to slightly
    /// better (sun_boxes relMSE −5% with 0.15 m cells) for 14–52% more cells (same
    /// section of `benches/RESULTS.md`).
    pub soft_lod: bool,
}

impl Default for WorldCacheSettings {
    fn default() -> Self {
        Self {
            capacity: 1 << 19,
            cell_size: 0.15,
            lod_distance: 10.0,
            lifetime: 30,
            max_search_steps: 32,
            max_temporal_samples: 30.0,
            light_change_samples: 4.0,
            light_change_frames: 8,
            warm_up_exponent: 2.0,
            warm_up_rounds: 4,
            warm_up_frames: 8,
            update_budget: 200_000,
            direct_candidates: 8,
            max_ray_distance: 50.0,
            jitter: true,
            leak_rule: true,
            soft_lod: true,
        }
    }
}

impl WorldCacheSettings {
    /// Checks every knob is in range; the error names the bad one.
    pub fn validate(&self) -> Result<(), GpuError> {
        let bad = |what: String| {
            Err(GpuError::Validation(format!(
                "world cache settings: {what}"
            )))
        };
        if !self.capacity.is_power_of_two()
            || !(MIN_CAPACITY..=MAX_CAPACITY).contains(&self.capacity)
        {
            return bad(format!(
                "capacity {} must be a power of two from {MIN_CAPACITY} to {MAX_CAPACITY}",
                self.capacity
            ));
        }
        if !(self.cell_size.is_finite() && self.cell_size > 1e-6) {
            return bad(format!(
                "cell_size {} must be finite and above 1e-6",
                self.cell_size
            ));
        }
        if self.lod_distance.is_nan() || self.lod_distance <= 0.0 {
            return bad(format!(
                "lod_distance {} must be positive (infinite for one level)",
                self.lod_distance
            ));
        }
        if !(1..=MAX_SETTING_FRAMES).contains(&self.lifetime) {
            return bad(format!(
                "lifetime {} must be 1 to {MAX_SETTING_FRAMES}",
                self.lifetime
            ));
        }
        if !(1..=MAX_SEARCH_STEPS).contains(&self.max_search_steps) {
            return bad(format!(
                "max_search_steps {} must be 1 to {MAX_SEARCH_STEPS}",
                self.max_search_steps
            ));
        }
        if !(self.max_temporal_samples.is_finite() && self.max_temporal_samples >= 1.0) {
            return bad(format!(
                "max_temporal_samples {} must be finite and at least 1",
                self.max_temporal_samples
            ));
        }
        if !(self.light_change_samples.is_finite() && self.light_change_samples >= 1.0) {
            return bad(format!(
                "light_change_samples {} must be finite and at least 1",
                self.light_change_samples
            ));
        }
        if self.light_change_frames > MAX_SETTING_FRAMES {
            return bad(format!(
                "light_change_frames {} must be at most {MAX_SETTING_FRAMES}",
                self.light_change_frames
            ));
        }
        if !(0.0..=MAX_WARM_UP_EXPONENT).contains(&self.warm_up_exponent) {
            return bad(format!(
                "warm_up_exponent {} must be 0 to {MAX_WARM_UP_EXPONENT}",
                self.warm_up_exponent
            ));
        }
        if self.warm_up_frames > MAX_SETTING_FRAMES {
            return bad(format!(
                "warm_up_frames {} must be at most {MAX_SETTING_FRAMES}",
                self.warm_up_frames
            ));
        }
        if !(1..=MAX_WARM_UP_ROUNDS).contains(&self.warm_up_rounds) {
            return bad(format!(
                "warm_up_rounds {} must be 1 to {MAX_WARM_UP_ROUNDS}",
                self.warm_up_rounds
            ));
        }
        if self.update_budget == 0 {
            return bad("update_budget must be at least 1".into());
        }
        if !(1..=MAX_DIRECT_CANDIDATES).contains(&self.direct_candidates) {
            return bad(format!(
                "direct_candidates {} must be 1 to {MAX_DIRECT_CANDIDATES}",
                self.direct_candidates
            ));
        }
        if self.max_ray_distance.is_nan() || self.max_ray_distance <= 0.0 {
            return bad(format!(
                "max_ray_distance {} must be positive (infinite allowed)",
                self.max_ray_distance
            ));
        }
        Ok(())
    }

    /// Bytes of GPU memory the cache holds at this capacity (table, active list, new
    /// samples, control), excluding the 96-byte parameters ([`GpuCacheParams`]).
    pub fn memory_bytes(&self) -> u64 {
        let slots = self.capacity as u64;
        slots * (4 + 4 + size_of::<GpuCacheCell>() as u64 + 4 + size_of::<GpuNewSample>() as u64)
            + CONTROL_HEADER_BYTES
            + slots / 1024 * 4
            + 16
    }
}

/// `WorldCacheParams::flags` bits.
pub(crate) mod flags {
    pub const JITTER: u32 = 1;
    pub const LEAK_RULE: u32 = 2;
    pub const SOFT_LOD: u32 = 4;
}

/// The uniform every cache pass reads (WGSL `WorldCacheParams`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuCacheParams {
    /// Camera position (level of detail is by distance from it).
    pub view_position: [f32; 3],
    /// Frame index (random seeds).
    pub frame: u32,
    /// See [`crate::hash::CellGrid`].
    pub cell_size: f32,
    /// See [`crate::hash::CellGrid`].
    pub inv_cell_size: f32,
    /// See [`crate::hash::CellGrid`].
    pub inv_lod_distance: f32,
    /// Table size minus one.
    pub mask: u32,
    /// [`WorldCacheSettings::lifetime`].
    pub lifetime: u32,
    /// [`WorldCacheSettings::max_search_steps`].
    pub max_search_steps: u32,
    /// Jitter, leak-rule and soft-LOD bits.
    pub flags: u32,
    /// [`WorldCacheSettings::update_budget`].
    pub update_budget: u32,
    /// [`WorldCacheSettings::max_temporal_samples`].
    pub max_temporal_samples: f32,
    /// [`WorldCacheSettings::max_ray_distance`].
    pub max_ray_distance: f32,
    /// [`WorldCacheSettings::direct_candidates`].
    pub direct_candidates: u32,
    /// Lights in the light list (0: no direct-light sample).
    pub light_count: u32,
    /// Light tiles.
    pub tile_count: u32,
    /// Samples per light tile.
    pub samples_per_tile: u32,
    /// Image width for the pixel passes.
    pub width: u32,
    /// Image height for the pixel passes.
    pub height: u32,
    /// [`WorldCacheSettings::warm_up_exponent`].
    pub warm_up_exponent: f32,
    /// Padding to 16 bytes.
    pub _pad: [u32; 3],
}

const _: () = assert!(size_of::<GpuCacheParams>() == 96);

/// One table slot's contents (WGSL `CacheCell`), as [`crate::WorldCache::read_cells`]
/// returns them.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuCacheCell {
    /// The surface point that created the cell (where its rays start).
    pub position: [f32; 3],
    /// Its normal, octahedral 16 + 16 bits (`packing::pack_unit_vector`).
    pub normal: u32,
    /// Irradiance over π (cosine-weighted mean incident radiance) from everything, rgb; w:
    /// samples averaged so far.
    pub irradiance: [f32; 4],
    /// The part of `irradiance` not from the light list (light arriving after at least one
    /// bounce, and the environment), rgb; w: running luminance change for the adaptive
    /// blend.
    pub indirect: [f32; 4],
}

const _: () = assert!(size_of::<GpuCacheCell>() == 48);

/// Which words of a [`GpuCacheCell`] the non-finite detector checks: the position (any
/// sign), the irradiance with its sample count and the indirect part (non-negative), and the
/// blend's running change (any sign).
pub const CELL_CHECK: solari_scene::finite_check::RecordLayout =
    solari_scene::finite_check::RecordLayout {
        stride_words: 12,
        float_mask: 0b1111_1111_0111,
        non_negative_mask: 0b0111_1111_0000,
        upper_mask: 0,
        upper_bound: 0.0,
    };

/// A cell's new sample between the update and blend passes (WGSL `NewSample`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuNewSample {
    /// Direct-light estimate, rgb.
    pub direct: [f32; 3],
    /// 1 when the cell was updated this frame, 0 when skipped.
    pub updated: u32,
    /// Indirect estimate, rgb.
    pub indirect: [f32; 3],
    /// Padding.
    pub _pad: u32,
}

const _: () = assert!(size_of::<GpuNewSample>() == 32);

/// Bytes before the per-block counts in the control buffer (WGSL `CacheControl`).
pub const CONTROL_HEADER_BYTES: u64 = 16;
