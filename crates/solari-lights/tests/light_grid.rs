//! The light grid on the CPU (`solari_lights::light_grid`): lists sorted and capped, a light
//! inside a cell listed there, the mixture a distribution that `select` draws from, every
//! light reachable everywhere, and bad settings and degenerate input refused or handled.

use glam::Vec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use solari_lights::light_grid::{MAX_GRID_CELLS, MAX_GRID_SHARE};
use solari_lights::{LightGrid, LightGridSettings, LightList, Selection};
use solari_scene::Scene;
use solari_scene::model::{DirectionalLight, PunctualKind, PunctualLight};

fn point(position: Vec3, intensity: f32) -> PunctualLight {
    PunctualLight {
        name: "p".into(),
        kind: PunctualKind::Point,
        position,
        direction: Vec3::NEG_Y,
        intensity: Vec3::splat(intensity),
        range: None,
        radius: 0.0,
    }
}

/// `n` point lights of random intensity on a 20 m square, 0–2 m up.
fn field(n: usize, seed: u64) -> Scene {
    let mut rng = Pcg64::seed_from_u64(seed);
    Scene {
        punctual_lights: (0..n)
            .map(|_| {
                point(
                    Vec3::new(
                        rng.random_range(-10.0..10.0),
                        rng.random_range(0.0..2.0),
                        rng.random_range(-10.0..10.0),
                    ),
                    rng.random_range(0.5..8.0),
                )
            })
            .collect(),
        ..Default::default()
    }
}

const BOUNDS: (Vec3, Vec3) = (Vec3::new(-10.0, 0.0, -10.0), Vec3::new(10.0, 2.0, 10.0));

fn settings(max_cells: u32, capacity: u32) -> LightGridSettings {
    LightGridSettings {
        max_cells,
        capacity,
        ..Default::default()
    }
}

#[test]
fn lists_are_sorted_capped_and_hold_the_lights_inside_their_cell() {
    let mut scene = field(300, 1);
    for l in &mut scene.punctual_lights {
        l.intensity = Vec3::splat(2.0);
    }
    let list = LightList::build(&scene);
    let grid = LightGrid::build(&list, BOUNDS, &settings(256, 8)).unwrap();
    assert!(grid.cells.len() <= 256);
    for cell in 0..grid.cells.len() {
        let lights = grid.lights_in(cell);
        assert!(lights.len() <= 8);
        assert!(
            lights.windows(2).all(|w| w[0] < w[1]),
            "cell {cell} unsorted"
        );
    }
    // With equal intensities a light inside a cell has the largest bound there, tied only
    // by lights within half a cell of the cell's box: where at most `capacity` lights are
    // that close, every light inside is listed.
    let positions: Vec<Vec3> = scene.punctual_lights.iter().map(|l| l.position).collect();
    let mut checked = 0;
    for (i, &p) in positions.iter().enumerate() {
        let cell = grid.cell_of(p);
        let c = cell as u32;
        let (dx, dy) = (grid.dims.x, grid.dims.y);
        let lo = grid.origin
            + Vec3::new(
                (c % dx) as f32,
                ((c / dx) % dy) as f32,
                (c / (dx * dy)) as f32,
            ) * grid.cell_size;
        let hi = lo + Vec3::splat(grid.cell_size);
        let close = positions
            .iter()
            .filter(|q| (q.clamp(lo, hi) - **q).length() <= 0.5 * grid.cell_size * 1.001)
            .count();
        if close <= 8 {
            assert!(
                grid.lights_in(cell).contains(&(i as u32)),
                "light {i} missing from its cell"
            );
            checked += 1;
        }
    }
    assert!(checked > 50, "only {checked} lights checked");
    let r = &grid.report;
    assert_eq!(r.cells as usize, grid.cells.len());
    assert_eq!(r.entries as usize, grid.entries.len());
    assert!(r.summary().contains("cells"), "{}", r.summary());
    println!("{} ({checked} lights checked)", r.summary());
}

#[test]
fn the_mixture_is_a_distribution_that_reaches_every_light() {
    let scene = field(200, 2);
    let list = LightList::build(&scene);
    for selection in [Selection::Power, Selection::Uniform] {
        let grid = LightGrid::build(&list, BOUNDS, &settings(512, 6)).unwrap();
        for cell in (0..grid.cells.len()).step_by(7) {
            let p: Vec<f32> = (0..list.len() as u32)
                .map(|l| grid.selection_pdf(&list, selection, cell, l))
                .collect();
            let sum: f64 = p.iter().map(|&x| x as f64).sum();
            assert!(
                (sum - 1.0).abs() < 1e-4,
                "cell {cell}: probabilities sum to {sum}"
            );
            assert!(
                p.iter().all(|&x| x > 0.0),
                "cell {cell}: a light is unreachable"
            );
        }
    }
}

#[test]
fn select_draws_each_light_with_its_probability() {
    let scene = field(40, 3);
    let list = LightList::build(&scene);
    let grid = LightGrid::build(&list, BOUNDS, &settings(64, 5)).unwrap();
    let cell = grid.cell_of(Vec3::new(2.0, 1.0, -3.0));
    assert!(!grid.lights_in(cell).is_empty());
    let n = 400_000;
    let mut counts = vec![0u32; list.len()];
    let mut rng = Pcg64::seed_from_u64(4);
    for _ in 0..n {
        let u = [rng.random(), rng.random(), rng.random()];
        counts[grid.select(&list, Selection::Power, cell, u).unwrap() as usize] += 1;
    }
    for (l, &c) in counts.iter().enumerate() {
        let p = grid.selection_pdf(&list, Selection::Power, cell, l as u32) as f64;
        let expected = p * n as f64;
        let sigma = (expected * (1.0 - p)).sqrt().max(1.0);
        assert!(
            (c as f64 - expected).abs() < 5.0 * sigma,
            "light {l}: drawn {c} times, expected {expected:.0} ± {sigma:.0}"
        );
    }
}

#[test]
fn full_cells_are_counted_and_keep_the_strongest() {
    // Fifty lights in one spot and one bright light beside them.
    let mut scene = Scene {
        punctual_lights: (0..50)
            .map(|_| point(Vec3::new(1.0, 1.0, 1.0), 1.0))
            .collect(),
        ..Default::default()
    };
    scene
        .punctual_lights
        .push(point(Vec3::new(1.2, 1.0, 1.0), 100.0));
    let list = LightList::build(&scene);
    let bounds = (Vec3::ZERO, Vec3::splat(8.0));
    let grid = LightGrid::build(&list, bounds, &settings(512, 4)).unwrap();
    let cell = grid.cell_of(Vec3::new(1.0, 1.0, 1.0));
    assert_eq!(grid.lights_in(cell).len(), 4);
    assert!(grid.report.truncated_cells >= 1, "{:?}", grid.report);
    // The bright light is listed wherever it is among the four strongest: in its own cell.
    let bright = grid.cell_of(Vec3::new(1.2, 1.0, 1.0));
    assert!(grid.lights_in(bright).contains(&50));
    assert!(grid.report.summary().contains("truncated"));
}

#[test]
/// A sun bounds every cell by its irradiance: brighter than any point light's bound, it is
/// listed in every cell (a dim one competes with the point lights as their bounds say).
fn directional_lights_are_listed_everywhere() {
    let mut scene = field(100, 5);
    scene.directional_lights.push(DirectionalLight {
        name: "sun".into(),
        direction: Vec3::new(0.3, -1.0, 0.2),
        irradiance: Vec3::splat(100.0),
        angular_diameter: 0.01,
    });
    let list = LightList::build(&scene);
    let sun = list
        .lights
        .iter()
        .position(|l| matches!(l, solari_lights::Light::Directional { .. }))
        .unwrap() as u32;
    let grid = LightGrid::build(&list, BOUNDS, &settings(128, 8)).unwrap();
    for cell in 0..grid.cells.len() {
        assert!(
            grid.lights_in(cell).contains(&sun),
            "cell {cell} lacks the sun"
        );
    }
}

#[test]
fn points_outside_and_nan_find_a_cell() {
    let list = LightList::build(&field(20, 6));
    let grid = LightGrid::build(&list, BOUNDS, &settings(100, 4)).unwrap();
    let n = grid.cells.len();
    for x in [
        Vec3::splat(f32::NAN),
        Vec3::splat(1e30),
        Vec3::splat(-1e30),
        Vec3::new(f32::INFINITY, 0.0, f32::NEG_INFINITY),
    ] {
        assert!(grid.cell_of(x) < n, "{x}");
    }
}

#[test]
fn degenerate_bounds_and_one_light_still_build() {
    let list = LightList::build(&Scene {
        punctual_lights: vec![point(Vec3::new(3.0, 1.0, -2.0), 2.0)],
        ..Default::default()
    });
    for bounds in [
        (Vec3::splat(f32::NAN), Vec3::splat(f32::NAN)),
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        (Vec3::ZERO, Vec3::ZERO),
    ] {
        let grid = LightGrid::build(&list, bounds, &LightGridSettings::default()).unwrap();
        assert!(grid.cell_size.is_finite() && grid.cell_size > 0.0);
        assert!(grid.origin.is_finite());
        let cell = grid.cell_of(Vec3::new(3.0, 1.0, -2.0));
        assert_eq!(grid.lights_in(cell), &[0]);
    }
    // No lights at all: empty cells, and selection has nothing to pick.
    let empty = LightList::build(&Scene::default());
    let grid = LightGrid::build(&empty, BOUNDS, &LightGridSettings::default()).unwrap();
    assert!(grid.entries.is_empty());
    assert_eq!(grid.select(&empty, Selection::Power, 0, [0.5; 3]), None);
}

#[test]
fn bad_settings_are_refused_with_the_knob_named() {
    let list = LightList::build(&field(4, 7));
    for (bad, word) in [
        (
            LightGridSettings {
                grid_share: 1.0,
                ..Default::default()
            },
            "share",
        ),
        (
            LightGridSettings {
                grid_share: f32::NAN,
                ..Default::default()
            },
            "share",
        ),
        (
            LightGridSettings {
                capacity: 0,
                ..Default::default()
            },
            "capacity",
        ),
        (
            LightGridSettings {
                max_cells: MAX_GRID_CELLS + 1,
                ..Default::default()
            },
            "cells",
        ),
        (
            LightGridSettings {
                relative_cutoff: 1.0,
                ..Default::default()
            },
            "cutoff",
        ),
    ] {
        let e = LightGrid::build(&list, BOUNDS, &bad).unwrap_err();
        assert!(e.contains(word), "{e}");
    }
    const { assert!(MAX_GRID_SHARE < 1.0) };
}

/// A spot is listed in every cell it lights and left out of cells wholly outside its outer
/// cone: each cell is probed at a 5 × 5 × 5 lattice, and wherever the cone gives light at a
/// probe (seen from the light's centre) the cell must list the spot. Spots of radius 0 and
/// 0.3, shining down and sideways, among point lights; no capacity or cutoff in the way.
#[test]
fn spots_are_listed_where_their_cone_reaches_and_nowhere_else() {
    let mut scene = field(12, 9);
    let spot = |position: Vec3, direction: Vec3, radius: f32| PunctualLight {
        name: "spot".into(),
        kind: PunctualKind::Spot {
            inner: 0.2,
            outer: 0.45,
        },
        position,
        direction,
        intensity: Vec3::splat(50.0),
        range: None,
        radius,
    };
    scene.punctual_lights.extend([
        spot(Vec3::new(-4.0, 1.9, -4.0), Vec3::NEG_Y, 0.0),
        spot(Vec3::new(5.0, 1.9, 3.0), Vec3::NEG_Y, 0.3),
        spot(Vec3::new(-9.0, 1.0, 6.0), Vec3::X, 0.0),
    ]);
    let list = LightList::build(&scene);
    let spots: Vec<(u32, Vec3, solari_lights::SpotCone)> = list
        .lights
        .iter()
        .enumerate()
        .filter_map(|(i, l)| match *l {
            solari_lights::Light::Point { position, cone, .. } if cone.cos_outer().is_some() => {
                Some((i as u32, position, cone))
            }
            _ => None,
        })
        .collect();
    assert_eq!(spots.len(), 3);
    let settings = LightGridSettings {
        max_cells: 2048,
        capacity: 64,
        relative_cutoff: 0.0,
        ..Default::default()
    };
    let grid = LightGrid::build(&list, BOUNDS, &settings).unwrap();
    for &(light, position, cone) in &spots {
        let mut left_out = 0;
        for cell in 0..grid.cells.len() {
            let c = cell as u32;
            let index = glam::UVec3::new(
                c % grid.dims.x,
                (c / grid.dims.x) % grid.dims.y,
                c / (grid.dims.x * grid.dims.y),
            );
            let lo = grid.origin + index.as_vec3() * grid.cell_size;
            let lit = (0..125).any(|k| {
                let f = Vec3::new((k % 5) as f32, ((k / 5) % 5) as f32, (k / 25) as f32) / 4.0;
                let travel = (lo + f * grid.cell_size - position).normalize_or_zero();
                cone.attenuation(travel) > 0.0
            });
            let listed = grid.lights_in(cell).contains(&light);
            assert!(
                listed || !lit,
                "light {light}: cell {cell} is lit but not listed"
            );
            left_out += !listed as usize;
        }
        eprintln!(
            "light {light}: left out of {left_out} of {} cells",
            grid.cells.len()
        );
        // The cones cover a small part of the 20 × 2 × 20 m box.
        assert!(
            left_out * 2 > grid.cells.len(),
            "light {light}: left out of only {left_out} of {} cells",
            grid.cells.len()
        );
    }
}
