//! A world-space light grid for scenes with thousands of lights (Solari 0.19's "Light Grids",
//! the ray-tracing counterpart of clustered light binning).
//!
//! The grid covers the scene's bounds with cubic cells. Each cell lists, sorted by index, the
//! lights that can matter there: the [`LightGridSettings::capacity`] lights with the largest
//! irradiance bound over the cell, among those whose bound reaches
//! [`LightGridSettings::relative_cutoff`] of the cell's largest. A point outside the grid uses
//! the nearest cell.
//!
//! ## Sampling stays unbiased
//!
//! A light list per cell alone would lose every light it leaves out (the seed's prototype has
//! that bias, and breaks when a cell overflows). Here a candidate comes from the cell's list
//! with probability [`LightGridSettings::grid_share`] (uniformly among its lights) and from
//! the global power-proportional selection otherwise, so the probability of light `l` at a
//! point in cell `c` with `n` listed lights is
//!
//! `P(l) = (1 − g) p_select(l) + g [l ∈ c] / n`
//!
//! which is positive wherever `p_select` is: a full cell costs quality, never correctness.
//! Estimators divide by `P(l)`, i.e. multiply the global sample's 1/pdf by
//! `p_select(l) / P(l)` ([`LightGrid::selection_factor`]). Membership is a binary search in
//! the sorted list, so it is exact whoever built the grid.
//!
//! ## Bound
//!
//! A light's irradiance bound at distance `d` is `I / max(d, s/2)²`, with `d` measured from
//! the cell's box to the light's bounding sphere and `s` the cell size; `I` is the luminance
//! intensity (point and spot: their intensity; emissive: power / π per side, i.e. radiance ×
//! area). A spot bounds by 0, and so is not listed, in cells wholly outside its outer cone:
//! the box's bounding sphere, widened by the light's own radius, lies more than the outer
//! half-angle off the axis seen from the light's centre. Directional lights and the
//! environment bound every cell by their irradiance. The bound only orders lights; it never
//! changes what a sample is worth.
//!
//! ## Cost
//!
//! The build is on the CPU, one task per cell over every light (rayon), and runs when the
//! light list changes; [`LightGridReport::build_seconds`] says what it took.

use crate::light_list::{Light, LightList, Selection};
use glam::{UVec3, Vec3};
use rayon::prelude::*;
use solari_scene::brdf::luminance;

/// How the grid is laid out and how much of each light choice it makes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightGridSettings {
    /// Most cells (default 16,384). Cells are cubes sized so the scene's bounds need no more.
    pub max_cells: u32,
    /// Most lights listed per cell (default 32). A cell with more lights above the cutoff
    /// keeps the strongest and is counted in [`LightGridReport::truncated_cells`].
    pub capacity: u32,
    /// Probability that a candidate is drawn from the cell's list rather than from the
    /// global selection (default 0.75; at most [`MAX_GRID_SHARE`] so every light keeps a
    /// positive probability).
    pub grid_share: f32,
    /// A light is listed only where its bound is at least this fraction of the cell's
    /// largest (default 0.001).
    pub relative_cutoff: f32,
}

/// The pipeline constant that turns `LIGHT_GRID` on (`@id(7113)` in `light_grid.wesl`) for
/// a pass that draws candidates from the grid.
pub const LIGHT_GRID_ON: (&str, f64) = ("7113", 1.0);

/// Largest accepted [`LightGridSettings::grid_share`].
pub const MAX_GRID_SHARE: f32 = 0.95;
/// Largest accepted [`LightGridSettings::max_cells`] (2^20).
pub const MAX_GRID_CELLS: u32 = 1 << 20;
/// Largest accepted [`LightGridSettings::capacity`].
pub const MAX_GRID_CAPACITY: u32 = 256;

impl Default for LightGridSettings {
    fn default() -> Self {
        Self {
            max_cells: 16_384,
            capacity: 32,
            grid_share: 0.75,
            relative_cutoff: 1e-3,
        }
    }
}

impl LightGridSettings {
    /// An error naming the first setting out of range.
    pub fn check(&self) -> Result<(), String> {
        if !(1..=MAX_GRID_CELLS).contains(&self.max_cells) {
            return Err(format!(
                "light grid cells must be 1 to {MAX_GRID_CELLS}, not {}",
                self.max_cells
            ));
        }
        if !(1..=MAX_GRID_CAPACITY).contains(&self.capacity) {
            return Err(format!(
                "light grid capacity must be 1 to {MAX_GRID_CAPACITY}, not {}",
                self.capacity
            ));
        }
        if !(0.0..=MAX_GRID_SHARE).contains(&self.grid_share) {
            return Err(format!(
                "light grid share must be 0 to {MAX_GRID_SHARE}, not {}",
                self.grid_share
            ));
        }
        if !(0.0..1.0).contains(&self.relative_cutoff) {
            return Err(format!(
                "light grid cutoff must be at least 0 and below 1, not {}",
                self.relative_cutoff
            ));
        }
        Ok(())
    }
}

/// What a build produced, for logs and benches.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightGridReport {
    /// Cells in the grid.
    pub cells: u32,
    /// Cells that list no light.
    pub empty_cells: u32,
    /// Cells with more lights above the cutoff than [`LightGridSettings::capacity`]: they
    /// keep the strongest (the rest stay reachable through the global share).
    pub truncated_cells: u32,
    /// The longest list.
    pub max_lights: u32,
    /// Mean list length.
    pub mean_lights: f32,
    /// Listed lights over all cells (4 bytes each on the GPU).
    pub entries: u64,
    /// Wall time of the build.
    pub build_seconds: f64,
}

impl LightGridReport {
    /// One line for logs and `solari info`.
    pub fn summary(&self) -> String {
        format!(
            "light grid: {} cells, {:.1} lights per cell (max {}), {} empty, {} truncated at \
             capacity, built in {:.1} ms",
            self.cells,
            self.mean_lights,
            self.max_lights,
            self.empty_cells,
            self.truncated_cells,
            self.build_seconds * 1e3
        )
    }
}

/// The grid: cell layout, each cell's sorted light list, and the share of choices it makes.
#[derive(Clone, Debug)]
pub struct LightGrid {
    /// Corner of cell (0, 0, 0).
    pub origin: Vec3,
    /// Edge of a (cubic) cell.
    pub cell_size: f32,
    /// Cells along x, y and z.
    pub dims: UVec3,
    /// Per cell (x fastest, then y, then z): first entry and count in [`LightGrid::entries`].
    pub cells: Vec<[u32; 2]>,
    /// Light indices, each cell's run sorted ascending.
    pub entries: Vec<u32>,
    /// [`LightGridSettings::grid_share`].
    pub grid_share: f32,
    /// What the build produced.
    pub report: LightGridReport,
}

// Where a light can be and how strong it can be there.
#[derive(Clone, Copy)]
enum Reach {
    // A bounding sphere and a luminance intensity: bound I / d². A spot's cone: its axis and
    // the cosine of its outer half-angle.
    Local {
        centre: Vec3,
        radius: f32,
        intensity: f32,
        cone: Option<(Vec3, f32)>,
    },
    // The same irradiance everywhere (directional lights, the environment).
    Everywhere(f32),
}

fn reach_of(list: &LightList, index: usize) -> Reach {
    match list.lights[index] {
        Light::Emissive {
            first_triangle,
            triangle_count,
            double_sided,
            ..
        } => {
            let tris = &list.triangles[first_triangle as usize..][..triangle_count as usize];
            let (lo, hi) = tris.iter().fold(
                (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), t| {
                    let (a, b, c) = (t.v0, t.v0 + t.e1, t.v0 + t.e2);
                    (lo.min(a).min(b).min(c), hi.max(a).max(b).max(c))
                },
            );
            let sides = if double_sided { 2.0 } else { 1.0 };
            Reach::Local {
                centre: 0.5 * (lo + hi),
                radius: 0.5 * (hi - lo).length(),
                intensity: list.power[index] / (std::f32::consts::PI * sides),
                cone: None,
            }
        }
        Light::Point {
            position,
            radius,
            intensity,
            cone,
        } => Reach::Local {
            centre: position,
            radius,
            intensity: luminance(intensity),
            cone: cone.cos_outer().map(|c| (cone.axis, c)),
        },
        Light::Directional { irradiance, .. } => Reach::Everywhere(luminance(irradiance)),
        // Irradiance on a surface facing the whole sky: π × the mean radiance.
        Light::Environment { radiance } => Reach::Everywhere(
            std::f32::consts::PI
                * luminance(
                    radiance
                        * list
                            .environment
                            .as_ref()
                            .map_or(Vec3::ZERO, |e| e.map.mean_radiance()),
                ),
        ),
    }
}

fn bound(reach: &Reach, lo: Vec3, hi: Vec3, min_distance: f32) -> f32 {
    match *reach {
        Reach::Local {
            centre,
            radius,
            intensity,
            cone,
        } => {
            if let Some((axis, cos_outer)) = cone
                && outside_cone(centre, radius, axis, cos_outer, lo, hi)
            {
                return 0.0;
            }
            let d = ((centre.clamp(lo, hi) - centre).length() - radius).max(min_distance);
            intensity / (d * d)
        }
        Reach::Everywhere(e) => e,
    }
}

// Whether the box [lo, hi] lies wholly outside the cone of half-angle acos(cos_outer) about
// `axis` from a light of `radius` at `centre`: the box's bounding sphere, widened by the
// light's radius, is seen more than that half-angle off the axis. Conservative: false
// wherever unsure (the sphere reaches the light, or any value is not finite).
fn outside_cone(centre: Vec3, radius: f32, axis: Vec3, cos_outer: f32, lo: Vec3, hi: Vec3) -> bool {
    let to_box = 0.5 * (lo + hi) - centre;
    let distance = to_box.length();
    let reach = 0.5 * (hi - lo).length() + radius;
    if !(distance > reach) || !distance.is_finite() {
        return false;
    }
    let off_axis = (axis.dot(to_box) / distance).clamp(-1.0, 1.0).acos();
    let widening = (reach / distance).asin();
    off_axis - widening > cos_outer.clamp(-1.0, 1.0).acos()
}

impl LightGrid {
    /// Builds the grid over `bounds` (the scene's, which the lights' positions extend) for
    /// `list`. Errors name a bad setting or bounds that are not finite.
    pub fn build(
        list: &LightList,
        bounds: (Vec3, Vec3),
        settings: &LightGridSettings,
    ) -> Result<Self, String> {
        settings.check()?;
        let start = std::time::Instant::now();
        let (scene_lo, scene_hi) = bounds;
        let reaches: Vec<Reach> = (0..list.lights.len()).map(|i| reach_of(list, i)).collect();
        let (mut lo, mut hi) = if scene_lo.is_finite() && scene_hi.is_finite() {
            (scene_lo.min(scene_hi), scene_hi.max(scene_lo))
        } else {
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY))
        };
        for r in &reaches {
            if let Reach::Local { centre, .. } = *r
                && centre.is_finite()
            {
                lo = lo.min(centre);
                hi = hi.max(centre);
            }
        }
        if !(lo.is_finite() && hi.is_finite()) {
            (lo, hi) = (Vec3::ZERO, Vec3::ZERO);
        }
        let (cell_size, dims) = layout(hi - lo, settings.max_cells);
        let count = (dims.x * dims.y * dims.z) as usize;
        let capacity = settings.capacity as usize;
        let min_distance = 0.5 * cell_size;
        let lists: Vec<(Vec<u32>, bool)> = (0..count)
            .into_par_iter()
            .map_init(Vec::new, |scratch: &mut Vec<(f32, u32)>, c| {
                let cell = UVec3::new(
                    c as u32 % dims.x,
                    (c as u32 / dims.x) % dims.y,
                    c as u32 / (dims.x * dims.y),
                );
                let cell_lo = lo + cell.as_vec3() * cell_size;
                let cell_hi = cell_lo + Vec3::splat(cell_size);
                scratch.clear();
                let mut strongest = 0.0f32;
                for (i, r) in reaches.iter().enumerate() {
                    let b = bound(r, cell_lo, cell_hi, min_distance);
                    if b > 0.0 && b.is_finite() {
                        strongest = strongest.max(b);
                        scratch.push((b, i as u32));
                    }
                }
                let cutoff = strongest * settings.relative_cutoff;
                scratch.retain(|&(b, _)| b >= cutoff);
                let truncated = scratch.len() > capacity;
                if truncated {
                    // Strongest first; ties broken by index so the build is deterministic.
                    scratch.select_nth_unstable_by(capacity - 1, |a, b| {
                        b.0.total_cmp(&a.0).then(a.1.cmp(&b.1))
                    });
                    scratch.truncate(capacity);
                }
                let mut lights: Vec<u32> = scratch.iter().map(|&(_, i)| i).collect();
                lights.sort_unstable();
                (lights, truncated)
            })
            .collect();
        let mut cells = Vec::with_capacity(count);
        let mut entries = Vec::new();
        let mut report = LightGridReport {
            cells: count as u32,
            ..Default::default()
        };
        for (lights, truncated) in &lists {
            cells.push([entries.len() as u32, lights.len() as u32]);
            entries.extend_from_slice(lights);
            report.empty_cells += lights.is_empty() as u32;
            report.truncated_cells += *truncated as u32;
            report.max_lights = report.max_lights.max(lights.len() as u32);
        }
        report.entries = entries.len() as u64;
        report.mean_lights = entries.len() as f32 / count as f32;
        report.build_seconds = start.elapsed().as_secs_f64();
        Ok(Self {
            origin: lo,
            cell_size,
            dims,
            cells,
            entries,
            grid_share: settings.grid_share,
            report,
        })
    }

    /// The cell holding `x`, or the nearest one for a point outside (cell 0 for NaN).
    /// WGSL twin: `light_grid_cell` in `light_grid.wesl`.
    pub fn cell_of(&self, x: Vec3) -> usize {
        let f = (x - self.origin) / self.cell_size;
        let max = (self.dims - 1).as_vec3();
        // `max(0)` first maps NaN to 0.
        let c = f.max(Vec3::ZERO).min(max).as_uvec3();
        (c.x + self.dims.x * (c.y + self.dims.y * c.z)) as usize
    }

    /// The lights listed in `cell`, ascending.
    pub fn lights_in(&self, cell: usize) -> &[u32] {
        let [first, count] = self.cells[cell];
        &self.entries[first as usize..][..count as usize]
    }

    /// `P(l) / p_select(l)` at `cell` (module docs): what a sample drawn by global selection
    /// has its pdf multiplied by. `p_select` is the light's global selection probability.
    /// WGSL twin: `light_grid_factor`.
    pub fn selection_factor(&self, cell: usize, light: u32, p_select: f32) -> f32 {
        let lights = self.lights_in(cell);
        if lights.is_empty() {
            return 1.0;
        }
        let g = self.grid_share;
        let listed = lights.binary_search(&light).is_ok();
        (1.0 - g)
            + if listed {
                g / (lights.len() as f32 * p_select)
            } else {
                0.0
            }
    }

    /// The probability `P(l)` of choosing `light` at a point in `cell`.
    pub fn selection_pdf(
        &self,
        list: &LightList,
        selection: Selection,
        cell: usize,
        light: u32,
    ) -> f32 {
        let p = list.selection_pdf(selection, light as usize);
        p * self.selection_factor(cell, light, p)
    }

    /// A light chosen at `cell` from three uniform numbers: `u[0]` picks the branch, `u[1]`
    /// the listed light, `u[2]` the global one. `None` for an empty light list.
    pub fn select(
        &self,
        list: &LightList,
        selection: Selection,
        cell: usize,
        u: [f32; 3],
    ) -> Option<u32> {
        if list.is_empty() {
            return None;
        }
        let lights = self.lights_in(cell);
        if !lights.is_empty() && u[0] < self.grid_share {
            let k = ((u[1] * lights.len() as f32) as usize).min(lights.len() - 1);
            return Some(lights[k]);
        }
        Some(list.select(selection, u[2]) as u32)
    }

    /// GPU memory the grid's two buffers take, in bytes.
    pub fn memory_bytes(&self) -> u64 {
        8 * self.cells.len() as u64 + 4 * self.entries.len().max(1) as u64
    }
}

// The smallest cubic cell that covers `extent` in at most `max_cells` cells, and the cells
// per axis. Flat or empty extents get one cell across.
fn layout(extent: Vec3, max_cells: u32) -> (f32, UVec3) {
    let extent = extent.max(Vec3::ZERO);
    let longest = extent.max_element();
    if !(longest > 0.0) {
        return (1.0, UVec3::ONE);
    }
    let dims_for = |s: f32| (extent / s).ceil().max(Vec3::ONE).as_uvec3();
    let fits = |s: f32| {
        let d = dims_for(s);
        (d.x as u64) * (d.y as u64) * (d.z as u64) <= max_cells as u64
    };
    // One cell of the longest edge always fits; halve the interval towards the smallest
    // size that still does.
    let (mut small, mut large) = (longest / max_cells as f32, longest);
    for _ in 0..48 {
        let mid = 0.5 * (small + large);
        if fits(mid) {
            large = mid;
        } else {
            small = mid;
        }
    }
    // A hair larger, so points on the far faces fall inside.
    let s = large * (1.0 + 1e-5);
    (s, dims_for(s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_layout_fits_the_cell_budget_and_covers_the_extent() {
        for (extent, max) in [
            (Vec3::new(10.0, 1.0, 10.0), 16_384),
            (Vec3::new(100.0, 0.0, 3.0), 1000),
            (Vec3::new(1.0, 1.0, 1.0), 1),
            (Vec3::ZERO, 64),
            (Vec3::new(1e-3, 5e4, 2.0), 4096),
        ] {
            let (s, d) = layout(extent, max);
            assert!(d.x * d.y * d.z <= max, "{extent} {max}: {d}");
            assert!((d.as_vec3() * s).cmpge(extent).all(), "{extent}: {d} × {s}");
        }
    }
}
