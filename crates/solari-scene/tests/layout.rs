//! CPU-only: every Rust mirror of a GPU struct has the size, and its named fields the offsets,
//! that naga computes for the WGSL twin in the composed shaders.

use solari_scene::bvh::GpuTriangle;
use solari_scene::gpu_types::{
    GpuInstance, GpuMaterial, GpuRay, GpuRayHit, GpuSceneInfo, GpuVertex, GpuView,
};
use solari_scene::shaders::{Backend, ENTRY_POINTS, compose, struct_layouts, validate};
use std::collections::HashMap;
use std::mem::offset_of;

/// WGSL struct layouts by unmangled name: (size, member name → offset).
type Layouts = HashMap<String, (u32, HashMap<String, u32>)>;

fn wgsl_layouts() -> Layouts {
    let mut out = Layouts::new();
    for (entry, _) in ENTRY_POINTS {
        let wgsl = compose(entry, Backend::Software, &[]).unwrap();
        out.extend(struct_layouts(&validate(entry, &wgsl).unwrap()).unwrap());
    }
    out
}

macro_rules! check {
    ($layouts:expr, $rust:ty, $wgsl:literal, [$($field:ident),*]) => {{
        let (size, offsets) = $layouts
            .get($wgsl)
            .unwrap_or_else(|| panic!("no WGSL struct {}", $wgsl));
        assert_eq!(size_of::<$rust>() as u32, *size, "size of {}", $wgsl);
        let _ = offsets;
        $(
            let name = stringify!($field);
            let wgsl_offset = offsets
                .get(name)
                .unwrap_or_else(|| panic!("{} has no member {name}", $wgsl));
            assert_eq!(offset_of!($rust, $field) as u32, *wgsl_offset, "{}.{name}", $wgsl);
        )*
    }};
}

#[test]
fn rust_mirrors_match_naga_layouts() {
    let l = wgsl_layouts();
    check!(
        l,
        solari_scene::gbuffer::GpuGBufferView,
        "GBufferView",
        [view_proj, previous_view_proj, view]
    );
    check!(
        l,
        GpuInstance,
        "GpuInstance",
        [
            world_to_object,
            object_to_world,
            normal_to_world,
            vertex_offset,
            index_offset,
            material,
            blas_root
        ]
    );
    check!(
        l,
        GpuMaterial,
        "GpuMaterial",
        [
            base_color,
            emissive,
            metallic,
            dielectric_f0,
            roughness,
            base_color_texture,
            metallic_roughness_texture,
            normal_texture,
            emissive_texture,
            normal_scale,
            flags,
            dielectric_f90
        ]
    );
    check!(
        l,
        GpuVertex,
        "GpuVertex",
        [position, uv_x, normal, uv_y, tangent]
    );
    check!(
        l,
        GpuSceneInfo,
        "GpuSceneInfo",
        [
            environment_radiance,
            instance_count,
            tlas_root,
            texture_layer_size
        ]
    );
    check!(
        l,
        GpuView,
        "GpuView",
        [
            origin,
            tan_half_fov,
            right,
            aspect,
            up,
            width,
            forward,
            height,
            frame,
            view_mode,
            znear,
            jitter
        ]
    );
    check!(
        l,
        GpuRay,
        "GpuRay",
        [origin, t_min, direction, t_max, flags]
    );
    check!(
        l,
        GpuRayHit,
        "RayHit",
        [t, instance, primitive, front_face, barycentrics]
    );
    check!(l, GpuTriangle, "BvhTriangle", [v0, e1, e2]);
    check!(l, obvhs::cwbvh::node::CwBvhNode, "BvhNode", []);
    check!(
        l,
        solari_scene::finite_check::GpuCheckParams,
        "CheckParams",
        [
            count,
            rows,
            stride_words,
            float_mask,
            non_negative_mask,
            slot,
            upper_mask,
            upper_bound
        ]
    );
}
