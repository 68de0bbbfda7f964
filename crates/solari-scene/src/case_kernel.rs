//! A compute kernel run once per case, for the GPU-twin tests: cases go in, one result per
//! case comes out ([`Gpu::run_cases`]), so a shader function can be held to its Rust twin.

use crate::GpuError;
use crate::gpu::{Gpu, ShaderChecks};

/// A pipeline whose group `io_group` holds the cases (binding 0, read) and the results
/// (binding 1, read-write), with its own layout for that group.
pub struct CaseKernel {
    label: String,
    pipeline: wgpu::ComputePipeline,
    io_layout: wgpu::BindGroupLayout,
    io_group: usize,
}

impl CaseKernel {
    /// Builds the kernel from composed `wgsl` (entry point `main`) over `layouts`, whose slot
    /// `io_group` must be `None`: the case buffers' layout goes there.
    pub fn new(
        gpu: &Gpu,
        label: &str,
        wgsl: &str,
        layouts: &[Option<&wgpu::BindGroupLayout>],
        io_group: usize,
    ) -> Result<Self, GpuError> {
        Self::with_constants(gpu, label, wgsl, layouts, io_group, &[])
    }

    /// [`CaseKernel::new`] with pipeline-overridable `constants` (`(id, value)`), for code
    /// that a pass compiles in only under an override.
    pub fn with_constants(
        gpu: &Gpu,
        label: &str,
        wgsl: &str,
        layouts: &[Option<&wgpu::BindGroupLayout>],
        io_group: usize,
        constants: &[(&str, f64)],
    ) -> Result<Self, GpuError> {
        if layouts.get(io_group).is_none_or(|l| l.is_some()) {
            return Err(GpuError::Validation(format!(
                "case kernel {label}: layout slot {io_group} must be the empty (None) case slot"
            )));
        }
        let io_layout = gpu.buffer_layout(
            label,
            &[
                wgpu::BufferBindingType::Storage { read_only: true },
                wgpu::BufferBindingType::Storage { read_only: false },
            ],
        );
        let layouts: Vec<_> = layouts
            .iter()
            .enumerate()
            .map(|(i, l)| if i == io_group { Some(&io_layout) } else { *l })
            .collect();
        let pipeline =
            gpu.compute_pipeline(label, wgsl, &layouts, ShaderChecks::BoundsOnly, constants)?;
        Ok(Self {
            label: label.to_owned(),
            pipeline,
            io_layout,
            io_group,
        })
    }

    /// One result per case, with `groups` bound at the other slots (the case slot's entry is
    /// ignored).
    pub fn run<I: bytemuck::Pod, O: bytemuck::Pod>(
        &self,
        gpu: &Gpu,
        groups: &[Option<&wgpu::BindGroup>],
        cases: &[I],
    ) -> Result<Vec<O>, GpuError> {
        let mut groups = groups.to_vec();
        if groups.len() <= self.io_group {
            groups.resize(self.io_group + 1, None);
        }
        groups[self.io_group] = None;
        gpu.run_cases(&self.label, &self.pipeline, &self.io_layout, &groups, cases)
    }

    /// Builds a kernel whose groups below `io_group` are empty (a shader of pure functions)
    /// and runs it once on `cases`: the whole set-up of a twin test whose shader binds
    /// nothing but its cases.
    pub fn run_pure<I: bytemuck::Pod, O: bytemuck::Pod>(
        gpu: &Gpu,
        label: &str,
        wgsl: &str,
        io_group: usize,
        cases: &[I],
    ) -> Result<Vec<O>, GpuError> {
        let (empty_layout, empty) = gpu.empty_group();
        let mut layouts = vec![Some(&empty_layout); io_group];
        layouts.push(None);
        let kernel = Self::new(gpu, label, wgsl, &layouts, io_group)?;
        kernel.run(gpu, &vec![Some(&empty); io_group], cases)
    }

    /// [`CaseKernel::run_pure`] on a test shader: `source` composed as module `name` (its
    /// entry point `main`) with a crate's `modules`, the set-up every twin test shares.
    pub fn run_test_module<I: bytemuck::Pod, O: bytemuck::Pod>(
        gpu: &Gpu,
        modules: Vec<(&'static str, &'static str)>,
        name: &'static str,
        source: &'static str,
        io_group: usize,
        cases: &[I],
    ) -> Result<Vec<O>, GpuError> {
        let modules: Vec<_> = modules.into_iter().chain([(name, source)]).collect();
        let wgsl = crate::shaders::compose(name, crate::shaders::Backend::Software, &modules)?;
        Self::run_pure(gpu, name, &wgsl, io_group, cases)
    }
}
