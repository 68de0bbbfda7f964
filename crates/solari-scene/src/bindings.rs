//! Bind groups of whole buffers declared by their WGSL names, so Rust code binds
//! `("params", &buffer)` rather than "the first buffer", and a test can prove the names and
//! kinds match the shaders ([`BufferGroup::check_wgsl`]).
//!
//! ```
//! use solari_scene::bindings::{Buf, BufferGroup};
//! // @group(2) @binding(0) var<uniform> params: …; @binding(1) var<storage, read_write> out: …
//! const OUT: BufferGroup = BufferGroup::new(2, 0, &[("params", Buf::Uniform), ("out", Buf::ReadWrite)]);
//! assert_eq!(OUT.binding("out"), Some(1));
//! ```

use crate::gpu::{Gpu, buffer_layout_entry};

/// How a shader accesses a buffer binding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Buf {
    /// `var<uniform>`.
    Uniform,
    /// `var<storage, read>`.
    Read,
    /// `var<storage, read_write>`.
    ReadWrite,
}

impl Buf {
    /// The wgpu binding type.
    pub fn binding_type(self) -> wgpu::BufferBindingType {
        match self {
            Buf::Uniform => wgpu::BufferBindingType::Uniform,
            Buf::Read => wgpu::BufferBindingType::Storage { read_only: true },
            Buf::ReadWrite => wgpu::BufferBindingType::Storage { read_only: false },
        }
    }
}

/// One bind group's buffer bindings by WGSL name: `bindings[i]` is at binding `first + i` of
/// group `group`.
#[derive(Clone, Copy, Debug)]
pub struct BufferGroup {
    /// The bind group index in the shaders.
    pub group: u32,
    /// The binding of `bindings[0]`.
    pub first: u32,
    /// (WGSL name, access) in binding order.
    pub bindings: &'static [(&'static str, Buf)],
}

impl BufferGroup {
    /// Declares a group (for `const` items).
    pub const fn new(group: u32, first: u32, bindings: &'static [(&'static str, Buf)]) -> Self {
        Self {
            group,
            first,
            bindings,
        }
    }

    /// The binding index of `name`, if declared.
    pub fn binding(&self, name: &str) -> Option<u32> {
        self.bindings
            .iter()
            .position(|(n, _)| *n == name)
            .map(|i| self.first + i as u32)
    }

    /// Layout entries for the group, visible to `stages` (for layouts that add more).
    pub fn layout_entries(&self, stages: wgpu::ShaderStages) -> Vec<wgpu::BindGroupLayoutEntry> {
        self.bindings
            .iter()
            .zip(self.first..)
            .map(|((_, kind), binding)| buffer_layout_entry(binding, kind.binding_type(), stages))
            .collect()
    }

    /// The group's layout for compute passes.
    pub fn layout(&self, gpu: &Gpu, label: &str) -> wgpu::BindGroupLayout {
        gpu.device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &self.layout_entries(wgpu::ShaderStages::COMPUTE),
            })
    }

    /// Bind group entries for `buffers`, given by name in declaration order.
    ///
    /// # Panics
    /// When the names are not exactly the declared ones in order: a bug in the calling pass,
    /// which its tests catch.
    pub fn entries<'a>(
        &self,
        buffers: &[(&str, &'a wgpu::Buffer)],
    ) -> Vec<wgpu::BindGroupEntry<'a>> {
        let ranges: Vec<_> = buffers
            .iter()
            .map(|(n, b)| (*n, b.as_entire_buffer_binding()))
            .collect();
        self.range_entries(&ranges)
    }

    /// As [`BufferGroup::entries`], each name bound to a range of a buffer (passes that
    /// share one scratch buffer between several bindings).
    pub fn range_entries<'a>(
        &self,
        buffers: &[(&str, wgpu::BufferBinding<'a>)],
    ) -> Vec<wgpu::BindGroupEntry<'a>> {
        let given: Vec<&str> = buffers.iter().map(|(n, _)| *n).collect();
        let declared: Vec<&str> = self.bindings.iter().map(|(n, _)| *n).collect();
        assert_eq!(given, declared, "buffers bound out of the declared order");
        buffers
            .iter()
            .zip(self.first..)
            .map(|((_, range), binding)| wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::Buffer(range.clone()),
            })
            .collect()
    }

    /// A bind group of `layout` (made by [`BufferGroup::layout`]) with `buffers` bound by
    /// name (see [`BufferGroup::entries`]).
    pub fn bind(
        &self,
        gpu: &Gpu,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        buffers: &[(&str, &wgpu::Buffer)],
    ) -> wgpu::BindGroup {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout,
            entries: &self.entries(buffers),
        })
    }

    /// Checks the group against a composed shader: every global the shader declares in this
    /// group within the declared bindings has the declared name and access (a shader may
    /// leave bindings it does not use out). The error names the first mismatch.
    pub fn check_wgsl(&self, module: &naga::Module) -> Result<usize, String> {
        let mut checked = 0;
        for (_, global) in module.global_variables.iter() {
            let Some(binding) = &global.binding else {
                continue;
            };
            let end = self.first + self.bindings.len() as u32;
            if binding.group != self.group || !(self.first..end).contains(&binding.binding) {
                continue;
            }
            let (name, kind) = self.bindings[(binding.binding - self.first) as usize];
            let wgsl = global.name.as_deref().unwrap_or("");
            if !is_wesl_name(wgsl, name) {
                return Err(format!(
                    "@group({}) @binding({}) is `{wgsl}` in WGSL, declared as `{name}`",
                    binding.group, binding.binding
                ));
            }
            let access = match global.space {
                naga::AddressSpace::Uniform => Some(Buf::Uniform),
                naga::AddressSpace::Storage { access } => {
                    Some(if access.contains(naga::StorageAccess::STORE) {
                        Buf::ReadWrite
                    } else {
                        Buf::Read
                    })
                }
                _ => None,
            };
            if access != Some(kind) {
                return Err(format!(
                    "`{name}` (@group({}) @binding({})) is {:?} in WGSL, declared {kind:?}",
                    binding.group, binding.binding, global.space
                ));
            }
            checked += 1;
        }
        Ok(checked)
    }
}

/// Checks, for each entry point and the groups it binds, composed with `modules` for both
/// tracing backends: each binding the shader declares in a group has the declared name and
/// access, and each listed group is declared by its shader (so its names were checked).
/// For each crate's shader tests; the error names the entry, backend and binding.
pub fn check_groups(
    entries: &[(&str, &[&BufferGroup])],
    modules: &[(&str, &str)],
) -> Result<(), String> {
    for (entry, groups) in entries {
        for backend in crate::shaders::Backend::ALL {
            let wgsl =
                crate::shaders::compose(entry, backend, modules).map_err(|e| e.to_string())?;
            let module = crate::shaders::validate(entry, &wgsl).map_err(|e| e.to_string())?;
            for group in groups.iter() {
                let checked = group
                    .check_wgsl(&module)
                    .map_err(|e| format!("{entry} ({}): {e}", backend.name()))?;
                if checked == 0 {
                    return Err(format!(
                        "{entry} ({}) declares nothing of group {} from binding {}",
                        backend.name(),
                        group.group,
                        group.first
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Whether `mangled` (a global's name after WESL composition) is the WGSL name `name`: WESL
/// joins the module path and the name with `_`, writing a segment that holds `n` underscores
/// as `_<n><segment>`; the last segment is the name.
fn is_wesl_name(mangled: &str, name: &str) -> bool {
    mangled == name
        || wesl_segments(mangled)
            .last()
            .is_some_and(|last| *last == name)
}

fn wesl_segments(mangled: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = mangled;
    while !rest.is_empty() {
        let digits = rest
            .strip_prefix('_')
            .map(|r| r.len() - r.trim_start_matches(|c: char| c.is_ascii_digit()).len())
            .unwrap_or(0);
        let (segment, after) = if digits > 0 {
            let body = &rest[1 + digits..];
            let underscores: usize = rest[1..1 + digits].parse().unwrap_or(0);
            // The segment runs to its (underscores + 1)-th underscore, or to the end.
            let end = body
                .match_indices('_')
                .nth(underscores)
                .map_or(body.len(), |(i, _)| i);
            (&body[..end], &body[end..])
        } else {
            let end = rest.find('_').unwrap_or(rest.len());
            (&rest[..end], &rest[end..])
        };
        out.push(segment);
        rest = after.strip_prefix('_').unwrap_or(after);
        if segment.is_empty() && after.is_empty() {
            break;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::is_wesl_name;

    #[test]
    fn wesl_names_unmangle() {
        assert!(is_wesl_name("package__1restir_di_params", "params"));
        assert!(is_wesl_name(
            "package__1restir_di__1reservoirs_previous",
            "reservoirs_previous"
        ));
        assert!(!is_wesl_name(
            "package__1restir_di__1reservoirs_previous",
            "previous"
        ));
        assert!(!is_wesl_name("package__1restir_di_params", "di_params"));
        assert!(is_wesl_name("lit", "lit"));
        assert!(is_wesl_name("package__2world_cache_gi_lit", "lit"));
        assert!(!is_wesl_name(
            "package__1world_cache__1cache_cells",
            "cells"
        ));
        assert!(is_wesl_name(
            "package__1world_cache__1cache_cells",
            "cache_cells"
        ));
    }
}
