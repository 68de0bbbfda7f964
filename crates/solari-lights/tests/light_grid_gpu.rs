//! GPU twin test: `light_grid.wesl` finds the same cell, picks and lists the same lights and
//! gives the same selection factor as `LightGrid` on the CPU, and `light_sample_on` names the
//! same sample as `LightList::generate_on` (lavapipe in CI).

mod common;

use bytemuck::{Pod, Zeroable};
use common::CaseKernel;
use glam::{Vec3, Vec4};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_lights::{
    GpuLights, LIGHT_GRID_ON, LightGrid, LightGridSettings, LightList, LightSampleId, Selection,
};
use solari_scene::gpu::test_gpu;
use solari_scene::model::{PunctualKind, PunctualLight};

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Case {
    x: [f32; 3],
    light: u32,
    u: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GpuResult {
    cell: [u32; 2],
    pick: u32,
    contains: u32,
    factor: f32,
    id: LightSampleId,
}

const _: () = assert!(size_of::<Case>() == 32 && size_of::<GpuResult>() == 32);

/// The bundled many_lights scene (400 emissive lights) with 300 point lights scattered
/// through it and an environment map: every kind of light that a grid lists or a sample
/// names a part of.
fn scene() -> solari_scene::Scene {
    let mut scene = solari_scene::load_gltf(solari_testdata::scene("many_lights"))
        .expect("bundled many_lights scene");
    let (lo, hi) = scene.bounds();
    let mut rng = Pcg32::seed_from_u64(5);
    for _ in 0..300 {
        let f = Vec3::new(rng.random(), rng.random(), rng.random());
        scene.punctual_lights.push(PunctualLight {
            name: "p".into(),
            kind: PunctualKind::Point,
            position: lo + (hi - lo) * f,
            direction: Vec3::NEG_Y,
            intensity: Vec3::splat(rng.random_range(0.5..5.0)),
            range: None,
            radius: 0.0,
        });
    }
    let texels = (0..16 * 8)
        .map(|i| Vec3::new(0.3, 0.5, 1.0) * (1.0 + (i % 5) as f32))
        .collect();
    let map = solari_scene::EnvironmentMap::new(16, 8, texels).expect("map");
    scene.environment_map = Some(std::sync::Arc::new(map));
    scene.environment_radiance = Vec3::ONE;
    assert!(scene.environment_is_light());
    scene
}

#[test]
fn gpu_light_grid_matches_the_cpu_twin() {
    let Some(gpu) = test_gpu() else { return };
    let kernel = CaseKernel::with_constants(
        &gpu,
        "light_grid_test",
        include_str!("../shaders/light_grid_test.wesl"),
        &GpuLights::layout(&gpu),
        &[LIGHT_GRID_ON],
    );
    let scene = scene();
    let list = LightList::build(&scene);
    let n = list.lights.len() as u32;
    assert!(n > 700, "{n} lights");
    let (lo, hi) = scene.bounds();
    let mut rng = Pcg32::seed_from_u64(9);
    // Small capacities fill cells (truncated lists); large ones list most lights.
    for (max_cells, capacity) in [(64, 4), (512, 16), (27, 256)] {
        let settings = LightGridSettings {
            max_cells,
            capacity,
            ..Default::default()
        };
        let grid = LightGrid::build(&list, (lo, hi), &settings).expect("grid");
        for selection in [Selection::Uniform, Selection::Power] {
            let lights = GpuLights::with_grid(&gpu, &list, selection, Some(&grid)).expect("upload");
            let pad = (hi - lo) * 0.2;
            let cases: Vec<Case> = (0..4000)
                .map(|i| {
                    let f = Vec3::new(rng.random(), rng.random(), rng.random());
                    let x = match i % 50 {
                        // Outside the bounds and non-finite points still find a cell.
                        0 => Vec3::NAN,
                        1 => Vec3::new(f32::INFINITY, -f32::INFINITY, 0.0),
                        _ => (lo - pad) + (hi - lo + 2.0 * pad) * f,
                    };
                    let cell = grid.cell_of(x);
                    // Half the cases ask about a listed light, so both branches are seen.
                    let listed = grid.lights_in(cell);
                    let light = if i % 2 == 0 && !listed.is_empty() {
                        listed[rng.random_range(0..listed.len())]
                    } else {
                        rng.random_range(0..n)
                    };
                    Case {
                        x: x.into(),
                        light,
                        u: Vec4::new(rng.random(), rng.random(), rng.random(), rng.random()).into(),
                    }
                })
                .collect();
            let results: Vec<GpuResult> = kernel.run(&gpu, &lights.bind_group, &cases);
            let mut failures = Vec::new();
            for (c, r) in cases.iter().zip(&results) {
                let x = Vec3::from(c.x);
                let cell = grid.cell_of(x);
                let listed = grid.lights_in(cell);
                let pick = if listed.is_empty() {
                    u32::MAX
                } else {
                    listed[((c.u[0] * listed.len() as f32) as usize).min(listed.len() - 1)]
                };
                let p = list.selection_pdf(selection, c.light as usize);
                let factor = grid.selection_factor(cell, c.light, p);
                let id = list
                    .generate_on(c.light, [c.u[1], c.u[2], c.u[3]])
                    .expect("the light exists");
                let ok = r.cell[1] as usize == listed.len()
                    && r.pick == pick
                    && (r.contains == 1) == listed.binary_search(&c.light).is_ok()
                    && (r.factor - factor).abs() <= 1e-5 * factor.abs().max(1.0)
                    && r.id == id;
                if !ok {
                    failures.push(format!(
                        "x {x:?} light {}: gpu {r:?}; cpu count {} pick {pick} factor {factor} \
                         id {id:?}",
                        c.light,
                        listed.len()
                    ));
                }
            }
            assert!(
                failures.is_empty(),
                "{max_cells} cells × {capacity}, {selection:?}: {} of {} differ, first: {}",
                failures.len(),
                cases.len(),
                failures[0]
            );
        }
    }
}
