//! WGSL composition with WESL. Every call into the `wesl` crate lives in this module, so an
//! upgrade (the crate is pinned to 0.4.0 for this toolchain) touches one place.
//!
//! The crate's modules are embedded in the binary and registered under `package::<name>`;
//! the tracing backend is a WESL feature (`@if(ray_query)`), chosen when a pipeline is built.

use crate::error::GpuError;
use std::borrow::Cow;

/// Which `trace_ray` implementation a shader is composed with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Backend {
    /// Hardware ray queries (`EXPERIMENTAL_RAY_QUERY`).
    RayQuery,
    /// The compute-shader CWBVH traversal; runs on every adapter.
    Software,
}

impl Backend {
    /// Both backends, for tests that loop over them.
    pub const ALL: [Backend; 2] = [Backend::RayQuery, Backend::Software];

    /// The name used on the command line and in `SOLARI_TRACER`.
    pub fn name(self) -> &'static str {
        match self {
            Backend::RayQuery => "ray-query",
            Backend::Software => "software",
        }
    }
}

/// The importable modules of `solari-scene`, by module name.
pub const MODULES: &[(&str, &str)] = &[
    ("scene_types", include_str!("../shaders/scene_types.wesl")),
    (
        "scene_bindings",
        include_str!("../shaders/scene_bindings.wesl"),
    ),
    ("trace", include_str!("../shaders/trace.wesl")),
    ("hit", include_str!("../shaders/hit.wesl")),
    ("rng", include_str!("../shaders/rng.wesl")),
    ("view", include_str!("../shaders/view.wesl")),
    ("frame", include_str!("../shaders/frame.wesl")),
    ("brdf", include_str!("../shaders/brdf.wesl")),
    ("packing", include_str!("../shaders/packing.wesl")),
    ("gbuffer", include_str!("../shaders/gbuffer.wesl")),
    ("gbuffer_read", include_str!("../shaders/gbuffer_read.wesl")),
    (
        "gbuffer_write",
        include_str!("../shaders/gbuffer_write.wesl"),
    ),
    ("finite_check", include_str!("../shaders/finite_check.wesl")),
    ("environment", include_str!("../shaders/environment.wesl")),
    (
        "gbuffer_override",
        include_str!("../shaders/gbuffer_override.wesl"),
    ),
];

/// The entry-point files of `solari-scene`, by module name.
pub const ENTRY_POINTS: &[(&str, &str)] = &[
    ("primary", include_str!("../shaders/primary.wesl")),
    ("trace_rays", include_str!("../shaders/trace_rays.wesl")),
    ("ray_bench", include_str!("../shaders/ray_bench.wesl")),
    ("brdf_test", include_str!("../shaders/brdf_test.wesl")),
    (
        "gbuffer_raster",
        include_str!("../shaders/gbuffer_raster.wesl"),
    ),
    (
        "gbuffer_traced",
        include_str!("../shaders/gbuffer_traced.wesl"),
    ),
    (
        "primary_depth",
        include_str!("../shaders/primary_depth.wesl"),
    ),
    (
        "gbuffer_override_apply",
        include_str!("../shaders/gbuffer_override_apply.wesl"),
    ),
    (
        "gbuffer_debug",
        include_str!("../shaders/gbuffer_debug.wesl"),
    ),
    (
        "finite_check_buffer",
        include_str!("../shaders/finite_check_buffer.wesl"),
    ),
    (
        "finite_check_texture",
        include_str!("../shaders/finite_check_texture.wesl"),
    ),
];

/// Composes the entry module `entry` (one of `extra` or [`ENTRY_POINTS`]) for `backend` into
/// plain WGSL. `extra` adds further modules (other crates' shaders) as `package::<name>`.
pub fn compose(entry: &str, backend: Backend, extra: &[(&str, &str)]) -> Result<String, GpuError> {
    let err = |message: String| GpuError::Shader {
        name: entry.to_string(),
        message,
    };
    let mut resolver = wesl::VirtualResolver::new();
    for (name, source) in MODULES.iter().chain(ENTRY_POINTS).chain(extra) {
        let path: wesl::ModulePath = format!("package::{name}")
            .parse()
            .map_err(|e| err(format!("bad module name {name}: {e:?}")))?;
        resolver.add_module(path, Cow::Borrowed(*source));
    }
    let mut compiler = wesl::Wesl::new("").set_custom_resolver(resolver);
    compiler.set_feature("ray_query", backend == Backend::RayQuery);
    // Wesl's own validator does not know naga's ray-query built-ins; naga validates instead.
    let mut options = wesl::CompileOptions {
        validate: false,
        ..Default::default()
    };
    options.features.flags.insert(
        "ray_query".to_string(),
        (backend == Backend::RayQuery).into(),
    );
    compiler.set_options(options);
    let root: wesl::ModulePath = format!("package::{entry}")
        .parse()
        .map_err(|e| err(format!("{e:?}")))?;
    let compiled = compiler.compile(&root).map_err(|e| err(e.to_string()))?;
    let mut wgsl = compiled.to_string();
    if backend == Backend::RayQuery {
        // An enable directive must open the module; WESL cannot gate directives by feature.
        wgsl = format!("enable wgpu_ray_query;\n{wgsl}");
    }
    Ok(wgsl)
}

/// Lines (1-based) of loops in a WESL source without a `// bound:` comment just above them.
/// Pipelines skip wgpu's forced loop bounding (`ShaderChecks::BoundsOnly`), which is sound
/// only while every loop provably ends, so every crate's shader tests require this be empty.
pub fn loops_without_bound(source: &str) -> Vec<usize> {
    let lines: Vec<&str> = source.lines().collect();
    let mut missing = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let code = line.split("//").next().unwrap_or("").trim_start();
        let is_loop = code.starts_with("loop")
            || code.starts_with("while ")
            || code.starts_with("for ")
            || code.starts_with("for(");
        if is_loop {
            let above = lines[..i]
                .iter()
                .rev()
                .find(|l| !l.trim().is_empty())
                .copied()
                .unwrap_or("");
            if !above.trim_start().starts_with("// bound:") {
                missing.push(i + 1);
            }
        }
    }
    missing
}

/// Parses and validates composed WGSL with naga, as wgpu would, returning the module.
pub fn validate(name: &str, wgsl: &str) -> Result<naga::Module, GpuError> {
    let err = |message: String| GpuError::Shader {
        name: name.to_string(),
        message,
    };
    let module = naga::front::wgsl::parse_str(wgsl).map_err(|e| err(e.emit_to_string(wgsl)))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| err(e.emit_to_string(wgsl)))?;
    Ok(module)
}

/// Size and member offsets of a WGSL struct as naga lays it out.
pub type StructLayout = (u32, std::collections::HashMap<String, u32>);

/// Every named struct of a validated module by its unmangled name (WESL turns
/// `package::module::Name` into `package_..._Name`): what the layout tests compare Rust
/// mirrors with.
pub fn struct_layouts(
    module: &naga::Module,
) -> Result<std::collections::HashMap<String, StructLayout>, GpuError> {
    let mut layouter = naga::proc::Layouter::default();
    layouter
        .update(module.to_ctx())
        .map_err(|e| GpuError::Validation(format!("layout: {e}")))?;
    let mut out = std::collections::HashMap::new();
    for (handle, ty) in module.types.iter() {
        let (Some(name), naga::TypeInner::Struct { members, .. }) = (&ty.name, &ty.inner) else {
            continue;
        };
        let short = name.rsplit('_').next().unwrap_or(name).to_string();
        let offsets = members
            .iter()
            .filter_map(|m| Some((m.name.clone()?, m.offset)))
            .collect();
        out.insert(short, (layouter[handle].size, offsets));
    }
    Ok(out)
}

/// What each crate's shader test checks, in one call: every entry of `entries` composes
/// (with `modules`) and validates for both backends, every loop in `own` (the crate's
/// modules and entries) carries its `// bound:` note, and the software variants' struct
/// layouts come back for [`check_layout`].
pub fn check_crate_shaders(
    own: &[(&str, &str)],
    entries: &[(&str, &str)],
    modules: &[(&str, &str)],
) -> Result<std::collections::HashMap<String, StructLayout>, GpuError> {
    for (name, source) in own {
        let missing = loops_without_bound(source);
        if !missing.is_empty() {
            return Err(GpuError::Validation(format!(
                "{name}: loops without a `// bound:` note at lines {missing:?}"
            )));
        }
    }
    let mut layouts = std::collections::HashMap::new();
    for (entry, _) in entries {
        for backend in Backend::ALL {
            let module = validate(entry, &compose(entry, backend, modules)?)?;
            if backend == Backend::Software {
                layouts.extend(struct_layouts(&module)?);
            }
        }
    }
    Ok(layouts)
}

/// Checks a Rust mirror against naga's layout of the WGSL struct `wgsl`: its size and the
/// offsets of the named members. The error says which differs.
pub fn check_layout(
    layouts: &std::collections::HashMap<String, StructLayout>,
    wgsl: &str,
    size: usize,
    fields: &[(&str, usize)],
) -> Result<(), String> {
    let (wgsl_size, offsets) = layouts.get(wgsl).ok_or(format!("no WGSL struct {wgsl}"))?;
    if *wgsl_size as usize != size {
        return Err(format!("size of {wgsl}: WGSL {wgsl_size}, Rust {size}"));
    }
    for (name, offset) in fields {
        let got = offsets
            .get(*name)
            .ok_or(format!("{wgsl} has no member {name}"))?;
        if *got as usize != *offset {
            return Err(format!("{wgsl}.{name}: WGSL offset {got}, Rust {offset}"));
        }
    }
    Ok(())
}

/// A crate's checked shader layouts, for its tests: [`check_crate_shaders`] and
/// [`check_layout`] with panics that name the problem, so each crate's shader test is a list
/// of mirrors.
pub struct CheckedShaders(std::collections::HashMap<String, StructLayout>);

impl CheckedShaders {
    /// Runs [`check_crate_shaders`]; panics with its error.
    pub fn new(own: &[(&str, &str)], entries: &[(&str, &str)], modules: &[(&str, &str)]) -> Self {
        Self(check_crate_shaders(own, entries, modules).unwrap_or_else(|e| panic!("{e}")))
    }

    /// Panics unless the Rust mirror (`size` bytes, the named member offsets) matches the WGSL
    /// struct `wgsl` ([`check_layout`]).
    pub fn mirror(&self, wgsl: &str, size: usize, fields: &[(&str, usize)]) {
        check_layout(&self.0, wgsl, size, fields).unwrap_or_else(|e| panic!("{e}"))
    }
}
