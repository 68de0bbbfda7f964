//! Shared by the tests of this crate: the test scenes, a case kernel (one input and one
//! output storage buffer in group 2, the lights in group 3), and the light-sampling
//! irradiance estimator the analytic tests use.
// Not every test file uses every helper.
#![allow(dead_code)]

use glam::Vec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use solari_lights::{LightList, MODULES, Selection};
use solari_scene::gpu::Gpu;
use solari_scene::model::{PunctualKind, PunctualLight};
use solari_scene::shaders::{Backend, compose};
use solari_scene::{DirectionalLight, Scene};

/// The built-in Cornell box, the bundled many_lights scene (400 lights), and the box with two
/// sun disks (soft and delta), four point and spot lights (delta and sphere), and its emitter
/// made double-sided.
pub fn scenes() -> Vec<(String, Scene)> {
    let mut sunny = solari_scene::default_scene::cornell_box();
    for (d, diameter) in [
        (Vec3::new(0.3, -1.0, 0.2), 0.0093),
        (Vec3::new(-0.5, -1.0, 0.0), 0.0),
    ] {
        sunny.directional_lights.push(DirectionalLight {
            name: "sun".into(),
            direction: d.normalize(),
            irradiance: Vec3::new(5.0, 4.0, 3.0),
            angular_diameter: diameter,
        });
    }
    let (lo, hi) = sunny.bounds();
    let at = |f: Vec3| lo + (hi - lo) * f;
    let spot = PunctualKind::Spot {
        inner: 0.3,
        outer: 0.7,
    };
    for (kind, position, radius) in [
        (PunctualKind::Point, at(Vec3::new(0.3, 0.7, 0.4)), 0.0),
        (
            PunctualKind::Point,
            at(Vec3::new(0.7, 0.5, 0.6)),
            0.05 * (hi - lo).x,
        ),
        (spot, at(Vec3::new(0.5, 0.9, 0.5)), 0.0),
        (spot, at(Vec3::new(0.2, 0.8, 0.7)), 0.03 * (hi - lo).x),
    ] {
        sunny.punctual_lights.push(PunctualLight {
            name: "punctual".into(),
            kind,
            position,
            direction: Vec3::new(0.2, -1.0, 0.1).normalize(),
            intensity: Vec3::new(2.0, 3.0, 4.0),
            range: None,
            radius,
        });
    }
    for m in &mut sunny.materials {
        m.double_sided = true;
    }
    vec![
        (
            "cornell_box".into(),
            solari_scene::default_scene::cornell_box(),
        ),
        (
            "many_lights".into(),
            solari_scene::load_gltf(solari_testdata::scene("many_lights"))
                .expect("bundled many_lights scene"),
        ),
        ("cornell_box+suns".into(), sunny),
    ]
}

/// A case kernel over this crate's modules (`solari_scene::case_kernel`), with the case
/// buffers in group 2 and the lights (or tiles) in group 3.
pub struct CaseKernel {
    kernel: solari_scene::case_kernel::CaseKernel,
    empty: wgpu::BindGroup,
}

impl CaseKernel {
    /// Composes test module `name` (WESL `source`, importing this crate's modules) with
    /// `group3` as its bind group 3 layout.
    pub fn new(
        gpu: &Gpu,
        name: &'static str,
        source: &'static str,
        group3: &wgpu::BindGroupLayout,
    ) -> Self {
        Self::with_constants(gpu, name, source, group3, &[])
    }

    /// [`CaseKernel::new`] with pipeline-overridable constants (`(id, value)`).
    pub fn with_constants(
        gpu: &Gpu,
        name: &'static str,
        source: &'static str,
        group3: &wgpu::BindGroupLayout,
        constants: &[(&str, f64)],
    ) -> Self {
        let (empty_layout, empty) = gpu.empty_group();
        let extra: Vec<(&str, &str)> = MODULES.iter().copied().chain([(name, source)]).collect();
        let wgsl = compose(name, Backend::Software, &extra).expect("compose");
        let layouts = [Some(&empty_layout), Some(&empty_layout), None, Some(group3)];
        let kernel = solari_scene::case_kernel::CaseKernel::with_constants(
            gpu, name, &wgsl, &layouts, 2, constants,
        )
        .expect("pipeline");
        Self { kernel, empty }
    }

    /// One output per case, with `group3` bound.
    pub fn run<I: bytemuck::Pod, O: bytemuck::Pod>(
        &self,
        gpu: &Gpu,
        group3: &wgpu::BindGroup,
        cases: &[I],
    ) -> Vec<O> {
        let groups = [Some(&self.empty), Some(&self.empty), None, Some(group3)];
        self.kernel.run(gpu, &groups, cases).expect("dispatch")
    }
}

/// Irradiance (red channel) at `x` on a surface with normal `n`, estimated by `samples` light
/// samples drawn with `selection` from a stream seeded by `seed`: the mean and its standard
/// error.
pub fn estimate(
    list: &LightList,
    selection: Selection,
    x: Vec3,
    n: Vec3,
    samples: usize,
    seed: u64,
) -> (f64, f64) {
    let mut rng = Pcg32::seed_from_u64(seed);
    let (mut s1, mut s2) = (0.0f64, 0.0f64);
    for _ in 0..samples {
        let u = [rng.random(), rng.random(), rng.random(), rng.random()];
        let v = list.sample(selection, x, u).map_or(0.0, |s| {
            (s.radiance.x * n.dot(s.direction).max(0.0) / s.pdf) as f64
        });
        s1 += v;
        s2 += v * v;
    }
    let m = s1 / samples as f64;
    (
        m,
        ((s2 / samples as f64 - m * m).max(0.0) / samples as f64).sqrt(),
    )
}
