//! The cache's addressing on the CPU: the twin of `shaders/world_cache_hash.wesl` (cell
//! level, cell coordinates, normal bucket, key, checksum) and of the probing in
//! `world_cache.wesl`, so tests can check the GPU computes the same cells and can predict
//! where a cell may live in the table.

use solari_scene::rng::pcg_hash;

/// The checksum of an empty slot (a real checksum is never this).
pub const EMPTY_CHECKSUM: u32 = 0;
/// The coarsest level of detail: cells are at most `cell_size × 2^15`.
pub const MAX_LEVEL: u32 = 15;

/// How positions map to cells: the quantities `WorldCacheParams` carries to the shaders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellGrid {
    /// Edge of the finest cells, in world units.
    pub cell_size: f32,
    /// `1 / cell_size`, computed once on the CPU so both sides multiply by the same value.
    pub inv_cell_size: f32,
    /// `1 / lod_distance` (0: one level everywhere).
    pub inv_lod_distance: f32,
    /// Table size minus one (the size is a power of two).
    pub mask: u32,
}

impl CellGrid {
    /// The grid for finest cells of `cell_size`, levels that double every `lod_distance`
    /// (see [`crate::WorldCacheSettings::lod_distance`]) and a table of `capacity` slots
    /// (a power of two).
    pub fn new(cell_size: f32, lod_distance: f32, capacity: u32) -> Self {
        Self {
            cell_size,
            inv_cell_size: 1.0 / cell_size,
            inv_lod_distance: if lod_distance.is_finite() {
                1.0 / lod_distance
            } else {
                0.0
            },
            mask: capacity - 1,
        }
    }

    /// Level of detail of a point `distance` from the camera: `floor(log2(1 + d / lod))`,
    /// at most [`MAX_LEVEL`] (also for non-finite distances).
    pub fn level(&self, distance: f32) -> u32 {
        self.level_with(distance, 1.0)
    }

    /// [`CellGrid::level`] with soft transitions ([`crate::WorldCacheSettings::soft_lod`]):
    /// one level coarser when `lod_u` (uniform in \[0, 1)) is below the cube of the
    /// fractional part of `log2(1 + d / lod)`; `lod_u` ≥ 1 never steps up.
    pub fn level_with(&self, distance: f32, lod_u: f32) -> u32 {
        let x = 1.0 + distance * self.inv_lod_distance;
        if x.is_nan() || x >= 65536.0 {
            return MAX_LEVEL;
        }
        let l = x.log2();
        let whole = l.floor();
        let f = l - whole;
        let up = u32::from(lod_u < f * f * f);
        (whole as u32 + up).min(MAX_LEVEL)
    }

    /// Edge length of cells at `level`.
    pub fn size_at(&self, level: u32) -> f32 {
        self.cell_size * (1u32 << level) as f32
    }

    /// Integer cell coordinates of `position` at `level` (`floor(p / size)`, by a
    /// multiplication with an exact power-of-two scaling of `inv_cell_size`).
    pub fn coords(&self, position: [f32; 3], level: u32) -> [i32; 3] {
        let inv = self.inv_cell_size * (1.0 / (1u32 << level) as f32);
        position.map(|p| (p * inv).floor().clamp(-1e9, 1e9) as i32)
    }

    /// The cell holding a surface point seen from `view`, with the light-leak rule: when
    /// `ray_length` (the query ray's length; infinite for none) is shorter than the cell,
    /// the finest level is used instead.
    pub fn cell(
        &self,
        position: [f32; 3],
        normal: [f32; 3],
        view: [f32; 3],
        ray_length: f32,
    ) -> Cell {
        self.cell_with(position, normal, view, ray_length, 1.0)
    }

    /// [`CellGrid::cell`] at the level [`CellGrid::level_with`] gives for `lod_u`.
    pub fn cell_with(
        &self,
        position: [f32; 3],
        normal: [f32; 3],
        view: [f32; 3],
        ray_length: f32,
        lod_u: f32,
    ) -> Cell {
        let d = position
            .iter()
            .zip(view)
            .map(|(p, v)| (p - v) * (p - v))
            .sum::<f32>()
            .sqrt();
        let mut level = self.level_with(d, lod_u);
        if ray_length < self.size_at(level) {
            level = 0;
        }
        let coords = self.coords(position, level);
        let tag = normal_bucket(normal) | (level << 3);
        Cell {
            key: cell_key(coords, tag) & self.mask,
            checksum: cell_checksum(coords, tag),
            level,
        }
    }
}

/// Where a cell is looked up first, and how it is recognised.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cell {
    /// First slot probed.
    pub key: u32,
    /// Stored in the slot to tell this cell from others hashed nearby; never
    /// [`EMPTY_CHECKSUM`].
    pub checksum: u32,
    /// Level of detail.
    pub level: u32,
}

/// The axis-aligned direction closest to `n`, 0..6 (+x, −x, +y, −y, +z, −z): surfaces
/// meeting at a corner or the two sides of a thin wall fall in different cells.
pub fn normal_bucket(n: [f32; 3]) -> u32 {
    let a = n.map(f32::abs);
    if a[0] >= a[1] && a[0] >= a[2] {
        if n[0] >= 0.0 { 0 } else { 1 }
    } else if a[1] >= a[2] {
        if n[1] >= 0.0 { 2 } else { 3 }
    } else if n[2] >= 0.0 {
        4
    } else {
        5
    }
}

/// Slot hash: a chain of PCG rounds (the workspace's RNG hash) over the cell descriptor.
pub fn cell_key(coords: [i32; 3], tag: u32) -> u32 {
    let mut k = pcg_hash(coords[0] as u32);
    k = pcg_hash(k.wrapping_add(coords[1] as u32));
    k = pcg_hash(k.wrapping_add(coords[2] as u32));
    pcg_hash(k.wrapping_add(tag))
}

// An unrelated integer hash (Wellons' "lowbias32") so key collisions do not imply checksum
// collisions.
fn mix32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

/// Collision check hash of the same descriptor, never [`EMPTY_CHECKSUM`].
pub fn cell_checksum(coords: [i32; 3], tag: u32) -> u32 {
    let mut c = mix32(coords[0] as u32 ^ 0x9e37_79b9);
    c = mix32(c.wrapping_add(coords[1] as u32));
    c = mix32(c.wrapping_add(coords[2] as u32));
    c = mix32(c.wrapping_add(tag));
    c.max(1)
}

/// The slots a lookup of `cell` visits, in order: linear probing from the key for
/// `max_steps` slots.
pub fn probe_sequence(cell: Cell, mask: u32, max_steps: u32) -> impl Iterator<Item = u32> {
    (0..max_steps).map(move |i| cell.key.wrapping_add(i) & mask)
}

/// Outcome of [`insert`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Probe {
    /// The cell was already at this slot.
    Found(u32),
    /// The cell was created at this slot.
    Created(u32),
    /// Every probed slot holds another cell: the query returns nothing.
    Full,
}

/// The lookup-or-insert of `world_cache_find` run sequentially on a table of checksums.
pub fn insert(checksums: &mut [u32], cell: Cell, max_steps: u32) -> Probe {
    let mask = checksums.len() as u32 - 1;
    for slot in probe_sequence(cell, mask, max_steps) {
        let c = &mut checksums[slot as usize];
        if *c == cell.checksum {
            return Probe::Found(slot);
        }
        if *c == EMPTY_CHECKSUM {
            *c = cell.checksum;
            return Probe::Created(slot);
        }
    }
    Probe::Full
}
