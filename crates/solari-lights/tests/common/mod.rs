//! Shared by the GPU tests of this crate: the test scenes and a case kernel (one input and one
//! output storage buffer in group 2, the lights in group 3).

use glam::Vec3;
use solari_lights::MODULES;
use solari_scene::gpu::{Gpu, ShaderChecks};
use solari_scene::shaders::{Backend, compose};
use solari_scene::{DirectionalLight, Scene};

/// The built-in Cornell box, the bundled many_lights scene (400 lights), and the box with two
/// sun disks (soft and delta) and its emitter made double-sided.
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

/// A compute kernel run over a list of cases (`Gpu::run_cases`).
pub struct CaseKernel {
    name: &'static str,
    pipeline: wgpu::ComputePipeline,
    io_layout: wgpu::BindGroupLayout,
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
        let (empty_layout, empty) = gpu.empty_group();
        let io_layout = gpu.buffer_layout(
            name,
            &[
                wgpu::BufferBindingType::Storage { read_only: true },
                wgpu::BufferBindingType::Storage { read_only: false },
            ],
        );
        let extra: Vec<(&str, &str)> = MODULES.iter().copied().chain([(name, source)]).collect();
        let wgsl = compose(name, Backend::Software, &extra).expect("compose");
        let pipeline = gpu
            .compute_pipeline(
                name,
                &wgsl,
                &[
                    Some(&empty_layout),
                    Some(&empty_layout),
                    Some(&io_layout),
                    Some(group3),
                ],
                ShaderChecks::BoundsOnly,
                &[],
            )
            .expect("pipeline");
        Self {
            name,
            pipeline,
            io_layout,
            empty,
        }
    }

    /// One output per case, with `group3` bound.
    pub fn run<I: bytemuck::Pod, O: bytemuck::Pod>(
        &self,
        gpu: &Gpu,
        group3: &wgpu::BindGroup,
        cases: &[I],
    ) -> Vec<O> {
        gpu.run_cases(
            self.name,
            &self.pipeline,
            &self.io_layout,
            &[Some(&self.empty), Some(&self.empty), None, Some(group3)],
            cases,
        )
        .expect("dispatch")
    }
}
