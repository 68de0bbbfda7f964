//! CPU-only: the denoiser's shaders compose and validate, every loop carries its `// bound:`
//! note, and the Rust mirrors have the sizes and offsets naga gives their WGSL twins.

use solari_denoise::history::PackedHistory;
use solari_denoise::{ENTRY_POINTS, GpuDenoiseParams, GpuHistory, GpuPassParams, MODULES, modules};
use solari_scene::shaders::CheckedShaders;
use std::mem::offset_of;

fn layouts() -> CheckedShaders {
    let own: Vec<_> = [MODULES, ENTRY_POINTS].concat();
    CheckedShaders::new(&own, ENTRY_POINTS, &modules())
}

#[test]
fn entry_points_compose_and_validate() {
    layouts();
}

#[test]
fn rust_mirrors_match_naga_layouts() {
    let l = layouts();
    l.mirror(
        "DenoiseParams",
        size_of::<GpuDenoiseParams>(),
        &[
            ("reset", offset_of!(GpuDenoiseParams, reset)),
            ("max_history", offset_of!(GpuDenoiseParams, max_history)),
            ("phi_depth", offset_of!(GpuDenoiseParams, phi_depth)),
            (
                "firefly_spread",
                offset_of!(GpuDenoiseParams, firefly_spread),
            ),
            ("fast_alpha", offset_of!(GpuDenoiseParams, fast_alpha)),
            (
                "spatial_variance_frames",
                offset_of!(GpuDenoiseParams, spatial_variance_frames),
            ),
            ("phi_lobe", offset_of!(GpuDenoiseParams, phi_lobe)),
            ("frame", offset_of!(GpuDenoiseParams, frame)),
        ],
    );
    l.mirror(
        "PassParams",
        size_of::<GpuPassParams>(),
        &[
            ("step", offset_of!(GpuPassParams, step)),
            ("signal", offset_of!(GpuPassParams, signal)),
            ("accumulate", offset_of!(GpuPassParams, accumulate)),
        ],
    );
    l.mirror(
        "History",
        size_of::<GpuHistory>(),
        &[
            ("moments", offset_of!(GpuHistory, moments)),
            ("carry", offset_of!(GpuHistory, carry)),
        ],
    );
    l.mirror(
        "PackedHistory",
        size_of::<PackedHistory>(),
        &[
            ("stats", offset_of!(PackedHistory, stats)),
            ("detail", offset_of!(PackedHistory, detail)),
        ],
    );
    use solari_denoise::upscale::GpuUpscaleParams;
    l.mirror(
        "UpscaleParams",
        size_of::<GpuUpscaleParams>(),
        &[
            ("output_size", offset_of!(GpuUpscaleParams, output_size)),
            ("reset", offset_of!(GpuUpscaleParams, reset)),
            ("max_weight", offset_of!(GpuUpscaleParams, max_weight)),
        ],
    );
}

#[test]
fn bindings_are_bound_by_their_wgsl_names() {
    use solari_denoise::fallback::FALLBACK_BINDINGS;
    use solari_scene::bindings::check_groups;
    let own = [&FALLBACK_BINDINGS];
    check_groups(
        &[
            ("denoise_temporal", &own),
            ("denoise_variance", &own),
            ("denoise_atrous", &own),
            ("denoise_atrous_feedback", &own),
            (
                "temporal_upscale",
                &[&solari_denoise::upscale::UPSCALE_BINDINGS],
            ),
            ("upscale_copy", &[&solari_denoise::upscale::COPY_BINDINGS]),
        ],
        &modules(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
}
