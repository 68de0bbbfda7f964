//! Importance sampling of an environment map: a piecewise-constant distribution over a grid of
//! cells in equirectangular (u, v), sampled with an alias table.
//!
//! A direction is drawn by picking a cell in proportion to its weight and a uniform (u, v) in
//! it, so its solid-angle pdf is `pmf[cell] · cells / (2π² sin θ)` (the equirectangular
//! Jacobian). A cell's weight is the brightest luminance that the map's bilinear filter can
//! return anywhere in it (its texels and their one-texel border) times its solid angle: every
//! direction with radiance has a non-zero pdf, which keeps the estimators unbiased, and bright
//! regions are sampled in proportion to their power. Maps wider than [`MAX_CELLS_X`] are
//! grouped into blocks of texels, which bounds the table at 512 × 256 cells (1.5 MiB on the
//! GPU).

use crate::alias::AliasTable;
use glam::{Vec2, Vec3};
use solari_scene::brdf::luminance;
use solari_scene::environment::{EnvironmentMap, direction_to_uv, uv_to_direction};
use std::f32::consts::PI;

/// The most cells across; wider maps group texels into square blocks.
pub const MAX_CELLS_X: u32 = 512;

/// The sampling distribution of one environment map.
#[derive(Clone, Debug)]
pub struct EnvironmentDistribution {
    /// Cells across (u).
    pub cells_x: u32,
    /// Cells down (v).
    pub cells_y: u32,
    /// Cell selection, row-major from the top row.
    pub table: AliasTable,
}

impl PartialEq for EnvironmentDistribution {
    fn eq(&self, other: &Self) -> bool {
        (self.cells_x, self.cells_y, &self.table.pmf)
            == (other.cells_x, other.cells_y, &other.table.pmf)
    }
}

impl EnvironmentDistribution {
    /// The distribution of `map`; `None` when the map is black.
    pub fn new(map: &EnvironmentMap) -> Option<Self> {
        let (w, h) = (map.width(), map.height());
        let block = w.div_ceil(MAX_CELLS_X).max(1);
        let (cells_x, cells_y) = (w.div_ceil(block), h.div_ceil(block));
        // Each texel's luminance, then the brightest over the texels whose bilinear footprint
        // reaches a cell: its own block widened by one texel (wrapping in u, clamped in v).
        let lum: Vec<f32> = map.texels().iter().map(|t| luminance(*t)).collect();
        let mut weights = Vec::with_capacity((cells_x * cells_y) as usize);
        // The texels whose bilinear footprint reaches the cell's uv span [a, b): from the one
        // whose centre lies at or before a to the one whose centre lies at or after b.
        let window = |c: u32, cells: u32, n: u32| {
            let a = c as f64 * n as f64 / cells as f64 - 0.5;
            let b = (c + 1) as f64 * n as f64 / cells as f64 - 0.5;
            (a.floor() as i64, b.floor() as i64 + 1)
        };
        for cy in 0..cells_y {
            let (y0, y1) = window(cy, cells_y, h);
            let t0 = cy as f32 / cells_y as f32 * PI;
            let t1 = (cy + 1) as f32 / cells_y as f32 * PI;
            let solid_angle = (t0.cos() - t1.cos()) * (2.0 * PI / cells_x as f32);
            for cx in 0..cells_x {
                let (x0, x1) = window(cx, cells_x, w);
                let mut peak = 0.0f32;
                for y in y0..=y1 {
                    let y = y.clamp(0, h as i64 - 1) as u32;
                    for x in x0..=x1 {
                        let x = x.rem_euclid(w as i64) as u32;
                        peak = peak.max(lum[(y * w + x) as usize]);
                    }
                }
                weights.push(peak * solid_angle);
            }
        }
        if !weights.iter().any(|w| *w > 0.0) {
            return None;
        }
        Some(Self {
            cells_x,
            cells_y,
            table: AliasTable::new(&weights),
        })
    }

    /// Number of cells.
    pub fn cell_count(&self) -> u32 {
        self.cells_x * self.cells_y
    }

    /// The cell that uniform number `u` picks: an alias-table draw from one number (the
    /// fraction left after choosing the slot decides between it and its alias), as the GPU
    /// makes it.
    pub fn pick(&self, u: f32) -> u32 {
        let n = self.cell_count();
        let x = u.clamp(0.0, 1.0) * n as f32;
        let slot = (x as u32).min(n - 1);
        self.table.sample(u, x - slot as f32) as u32
    }

    /// The direction at `point` (two numbers in [0, 1)) within `cell`.
    pub fn direction(&self, cell: u32, point: [f32; 2]) -> Vec3 {
        uv_to_direction(self.uv(cell, point))
    }

    fn uv(&self, cell: u32, point: [f32; 2]) -> Vec2 {
        let (cx, cy) = (cell % self.cells_x, cell / self.cells_x);
        Vec2::new(
            (cx as f32 + point[0]) / self.cells_x as f32,
            (cy as f32 + point[1]) / self.cells_y as f32,
        )
    }

    /// Solid-angle pdf of a direction at `point` within `cell` (0 at the poles, where the
    /// mapping degenerates).
    pub fn pdf_in_cell(&self, cell: u32, point: [f32; 2]) -> f32 {
        let Some(p) = self.table.pmf.get(cell as usize) else {
            return 0.0;
        };
        let sin_theta = (self.uv(cell, point).y * PI).sin();
        if !(sin_theta > 0.0) {
            return 0.0;
        }
        p * self.cell_count() as f32 / (2.0 * PI * PI * sin_theta)
    }

    /// Solid-angle pdf of sampling unit direction `d` (the other half of MIS where a path
    /// escapes).
    pub fn pdf(&self, d: Vec3) -> f32 {
        let uv = direction_to_uv(d);
        let cx = ((uv.x * self.cells_x as f32) as u32).min(self.cells_x - 1);
        let cy = ((uv.y * self.cells_y as f32) as u32).min(self.cells_y - 1);
        let p = self.table.pmf[(cy * self.cells_x + cx) as usize];
        let sin_theta = (uv.y * PI).sin();
        if !(sin_theta > 0.0) {
            return 0.0;
        }
        p * self.cell_count() as f32 / (2.0 * PI * PI * sin_theta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(w: u32, h: u32) -> EnvironmentMap {
        let texels = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                if x == 3 && y == 1 {
                    Vec3::splat(50.0)
                } else if y >= h / 2 {
                    Vec3::ZERO
                } else {
                    Vec3::new(0.2, 0.5, 1.0)
                }
            })
            .collect();
        EnvironmentMap::new(w, h, texels).unwrap()
    }

    #[test]
    fn pdf_integrates_to_one_and_matches_sampling() {
        let d = EnvironmentDistribution::new(&map(16, 8)).unwrap();
        // ∫ pdf dω by the midpoint rule.
        let (nt, np) = (800, 1600);
        let mut total = 0.0f64;
        for i in 0..nt {
            let theta = (i as f32 + 0.5) / nt as f32 * PI;
            for j in 0..np {
                let phi = (j as f32 + 0.5) / np as f32 * 2.0 * PI;
                let dir = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                );
                total += d.pdf(dir) as f64 * theta.sin() as f64;
            }
        }
        total *= (PI as f64 / nt as f64) * (2.0 * PI as f64 / np as f64);
        assert!((total - 1.0).abs() < 2e-3, "{total}");
        // A sampled direction's pdf in its cell equals the pdf looked up from the direction.
        for k in 0..200 {
            let u = (k as f32 + 0.5) / 200.0;
            let cell = d.pick(u);
            // Inside the cell: on its border, rounding may look up the neighbour.
            let inner = |x: f32| 0.05 + 0.9 * x.fract();
            let point = [inner(k as f32 * 0.618), inner(k as f32 * 0.382 + 0.1)];
            let dir = d.direction(cell, point);
            let (a, b) = (d.pdf_in_cell(cell, point), d.pdf(dir));
            assert!((a - b).abs() <= 1e-3 * a, "cell {cell}: {a} vs {b}");
        }
    }

    #[test]
    fn black_cells_next_to_light_keep_a_pdf_and_black_maps_have_none() {
        let d = EnvironmentDistribution::new(&map(16, 8)).unwrap();
        // Row 4 is black but the bilinear filter reaches into it from row 3.
        assert!(d.table.pmf[(4 * 16) as usize] > 0.0);
        // Rows 5.. are black and out of reach.
        assert_eq!(d.table.pmf[(6 * 16) as usize], 0.0);
        let black = EnvironmentMap::new(4, 2, vec![Vec3::ZERO; 8]).unwrap();
        assert!(EnvironmentDistribution::new(&black).is_none());
    }

    /// Every direction the bilinear filter gives radiance has a pdf, also where the cell grid
    /// does not divide the map evenly (1280 × 640: blocks of 3 texels, 427 × 214 cells).
    #[test]
    fn every_lit_direction_has_a_pdf_on_uneven_grids() {
        for (w, h) in [(1280, 640), (1100, 550), (16, 8)] {
            // Sparse bright texels in a black map: the cells around each must not be 0.
            let texels = (0..w * h)
                .map(|i| if i % 997 == 0 { Vec3::ONE } else { Vec3::ZERO })
                .collect();
            let map = EnvironmentMap::new(w, h, texels).unwrap();
            let d = EnvironmentDistribution::new(&map).unwrap();
            let mut checked = 0;
            for i in 0..200_000u32 {
                let uv = Vec2::new(
                    (i as f32 * 0.618_034).fract(),
                    (i as f32 * 0.754_877 + 0.01).fract() * 0.98 + 0.01,
                );
                let dir = uv_to_direction(uv);
                if map.radiance(dir).max_element() > 0.0 {
                    checked += 1;
                    assert!(d.pdf(dir) > 0.0, "{w}x{h}: uv {uv} has light but no pdf");
                }
            }
            assert!(checked > 100, "{w}x{h}: {checked} lit directions");
        }
    }

    #[test]
    fn wide_maps_are_grouped_into_at_most_512_cells_across() {
        let d = EnvironmentDistribution::new(&map(2048, 1024)).unwrap();
        assert_eq!((d.cells_x, d.cells_y), (512, 256));
        let sum: f32 = d.table.pmf.iter().sum();
        assert!((sum - 1.0).abs() < 1e-4);
    }
}
