//! Rust mirrors of the scene's GPU structs. Each names its WGSL twin; `tests/layout.rs` checks
//! every size against naga's layout of the composed shaders.

use bytemuck::{Pod, Zeroable};

/// WGSL twin: `GpuInstance` in `scene_types.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuInstance {
    /// Rows of the 3×4 world-to-object matrix.
    pub world_to_object: [[f32; 4]; 3],
    /// Rows of the 3×4 object-to-world matrix.
    pub object_to_world: [[f32; 4]; 3],
    /// Rows of the inverse-transpose of the linear part (normals); w unused.
    pub normal_to_world: [[f32; 4]; 3],
    /// First vertex of the mesh in the shared vertex buffer.
    pub vertex_offset: u32,
    /// First index of the mesh in the shared index buffer.
    pub index_offset: u32,
    /// Material index.
    pub material: u32,
    /// Root node of the mesh's software BLAS.
    pub blas_root: u32,
}
const _: () = assert!(size_of::<GpuInstance>() == 160);

/// WGSL twin: `GpuMaterial` in `scene_types.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuMaterial {
    /// Linear base colour factor.
    pub base_color: [f32; 4],
    /// Emitted radiance.
    pub emissive: [f32; 3],
    /// Metallic factor.
    pub metallic: f32,
    /// Dielectric F0.
    pub dielectric_f0: [f32; 3],
    /// Perceptual roughness factor.
    pub roughness: f32,
    /// Layer in the sRGB texture array, or `NO_TEXTURE`.
    pub base_color_texture: u32,
    /// Layer in the linear texture array, or `NO_TEXTURE`.
    pub metallic_roughness_texture: u32,
    /// Layer in the linear texture array, or `NO_TEXTURE`.
    pub normal_texture: u32,
    /// Layer in the sRGB texture array, or `NO_TEXTURE`.
    pub emissive_texture: u32,
    /// Normal map XY scale.
    pub normal_scale: f32,
    /// Bit 0: double sided.
    pub flags: u32,
    /// Dielectric reflectance at grazing angles.
    pub dielectric_f90: f32,
    /// Padding.
    pub _pad: u32,
}
const _: () = assert!(size_of::<GpuMaterial>() == 80);

/// Marks an absent texture in [`GpuMaterial`].
pub const NO_TEXTURE: u32 = u32::MAX;
/// Marks a miss in a [`GpuRayHit`].
pub const NO_HIT: u32 = u32::MAX;

/// WGSL twin: `GpuVertex` in `scene_types.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuVertex {
    /// Object-space position.
    pub position: [f32; 3],
    /// U of the first texture coordinate set.
    pub uv_x: f32,
    /// Object-space unit normal.
    pub normal: [f32; 3],
    /// V of the first texture coordinate set.
    pub uv_y: f32,
    /// Tangent with handedness in w.
    pub tangent: [f32; 4],
}
const _: () = assert!(size_of::<GpuVertex>() == 48);

/// WGSL twin: `GpuSceneInfo` in `scene_types.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuSceneInfo {
    /// Uniform environment radiance.
    pub environment_radiance: [f32; 3],
    /// Number of instances.
    pub instance_count: u32,
    /// Root node of the software TLAS.
    pub tlas_root: u32,
    /// Width and height of each texture-array layer.
    pub texture_layer_size: u32,
    /// `brdf::BrdfModel::gpu_id` of the scene's BRDF.
    pub brdf_model: u32,
    /// 1 when the environment is a sampled light ([`crate::Scene::environment_is_light`]):
    /// paths that escape leave it to next-event estimation or weight it by MIS.
    pub environment_sampled: u32,
    /// 1 when the software BVH is merged (`bvh::SoftwareBvh::build_merged`): one world-space
    /// level whose triangles name their instance.
    pub merged: u32,
    /// Root node of the software backend's emitter BVH (`bvh::SoftwareBvh::emitter_root`;
    /// `bvh::NO_EMITTERS` when no instance emits or with ray queries,
    /// `bvh::EMITTERS_IN_SCENE` when instances emit but it was left out).
    pub emitter_root: u32,
    /// Uniform buffers are sized in 16 bytes.
    pub _pad: [u32; 2],
}
const _: () = assert!(size_of::<GpuSceneInfo>() == 48);

/// WGSL twin: `GpuView` in `view.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuView {
    /// Camera position.
    pub origin: [f32; 3],
    /// tan(yfov / 2).
    pub tan_half_fov: f32,
    /// Unit right vector.
    pub right: [f32; 3],
    /// Width / height.
    pub aspect: f32,
    /// Unit up vector.
    pub up: [f32; 3],
    /// Image width in pixels.
    pub width: u32,
    /// Unit forward vector.
    pub forward: [f32; 3],
    /// Image height in pixels.
    pub height: u32,
    /// Frame index (seeds random numbers).
    pub frame: u32,
    /// Pass-specific mode (the debug view for `primary`).
    pub view_mode: u32,
    /// Near plane distance: turns G-buffer depth into view-axis distance (`znear / depth`).
    pub znear: f32,
    /// Padding.
    pub _pad: u32,
    /// Sub-pixel offset of every sample from its pixel's centre, in pixels (x right, y down;
    /// each in [-0.5, 0.5)): the camera jitter that temporal upscalers and DLSS-RR resolve.
    /// Zero for a still, centred image.
    pub jitter: [f32; 2],
    /// Padding.
    pub _pad1: [u32; 2],
}
const _: () = assert!(size_of::<GpuView>() == 96);

impl GpuView {
    /// The view of `camera` for an image of `width × height` (the image decides the aspect).
    pub fn new(camera: &crate::model::Camera, width: u32, height: u32) -> Self {
        let m = camera.transform;
        let right = m.x_axis.truncate().normalize_or_zero();
        let up = m.y_axis.truncate().normalize_or_zero();
        let forward = -m.z_axis.truncate().normalize_or_zero();
        Self {
            origin: m.w_axis.truncate().into(),
            tan_half_fov: (camera.yfov * 0.5).tan(),
            right: right.into(),
            aspect: width as f32 / height.max(1) as f32,
            up: up.into(),
            width,
            forward: forward.into(),
            height,
            znear: camera.znear.max(1e-6),
            ..Default::default()
        }
    }

    /// The unnormalized direction of the ray through `pixel` (in pixels from the top left,
    /// jitter added): the twin of `view_ray_direction` in `view.wesl`.
    pub fn ray_direction(&self, pixel: glam::Vec2) -> glam::Vec3 {
        use glam::Vec3;
        let size = glam::Vec2::new(self.width as f32, self.height as f32);
        let p = pixel + glam::Vec2::from(self.jitter);
        let ndc = glam::Vec2::new(p.x / size.x * 2.0 - 1.0, 1.0 - p.y / size.y * 2.0);
        Vec3::from(self.forward)
            + Vec3::from(self.right) * (ndc.x * self.tan_half_fov * self.aspect)
            + Vec3::from(self.up) * (ndc.y * self.tan_half_fov)
    }

    /// Where direction `d` appears in this view, in pixels from the top left, the jitter left
    /// out: the inverse of [`GpuView::ray_direction`] for an unjittered view (with jitter,
    /// `ray_direction(p)` projects to `p + jitter`). `None` where `d` points behind the view or
    /// along its image plane. The twin of `view_project_direction` in `view.wesl`, which
    /// returns (−1e9, −1e9) for `None`. The temporal upscaler finds where background (seen at
    /// infinity, so moved by the camera's turn alone) was last frame with it.
    pub fn project_direction(&self, d: glam::Vec3) -> Option<glam::Vec2> {
        use glam::Vec3;
        // NaN fails the comparison too: no position.
        let z = d.dot(Vec3::from(self.forward));
        if z.is_nan() || z <= 0.0 {
            return None;
        }
        let ndc = glam::Vec2::new(
            d.dot(Vec3::from(self.right)) / (z * self.tan_half_fov * self.aspect),
            d.dot(Vec3::from(self.up)) / (z * self.tan_half_fov),
        );
        Some(glam::Vec2::new(
            (ndc.x + 1.0) * 0.5 * self.width as f32,
            (1.0 - ndc.y) * 0.5 * self.height as f32,
        ))
    }

    /// This view with its samples moved `jitter` pixels from the pixel centres
    /// ([`GpuView::jitter`]).
    pub fn with_jitter(self, jitter: [f32; 2]) -> Self {
        Self { jitter, ..self }
    }

    /// Whether `other` sees the scene from the same place in the same directions: the same
    /// origin, axes, field of view and aspect, whatever its jitter, frame, size or mode. A
    /// frame whose view is not the same camera as last frame's moves every background
    /// direction's neighbours (the temporal upscaler's `camera_moved`); the real-time
    /// renderer jitters antialiasing only between frames of the same camera.
    pub fn same_camera(&self, other: &GpuView) -> bool {
        self.origin == other.origin
            && self.right == other.right
            && self.up == other.up
            && self.forward == other.forward
            && self.tan_half_fov == other.tan_half_fov
            && self.aspect == other.aspect
    }
}

/// Camera jitter for frame `frame`: the Halton (2, 3) sequence, 16 offsets in [-0.5, 0.5)²
/// pixels that cover a pixel evenly, repeated.
pub fn halton_jitter(frame: u32) -> [f32; 2] {
    let radical_inverse = |mut i: u32, base: u32| {
        let (mut f, mut r) = (1.0f32, 0.0f32);
        while i > 0 {
            f /= base as f32;
            r += f * (i % base) as f32;
            i /= base;
        }
        r
    };
    // Index 0 of the sequence is (0, 0), a corner: start at 1.
    let i = frame % 16 + 1;
    [radical_inverse(i, 2) - 0.5, radical_inverse(i, 3) - 0.5]
}

/// WGSL twin: `GpuRay` in `trace_rays.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuRay {
    /// Ray origin.
    pub origin: [f32; 3],
    /// Lower bound of the hit interval (exclusive).
    pub t_min: f32,
    /// Ray direction (need not be unit length).
    pub direction: [f32; 3],
    /// Upper bound of the hit interval (exclusive).
    pub t_max: f32,
    /// Ray flags (`trace_cpu::RAY_FLAG_*`).
    pub flags: u32,
    /// 1: trace only the instances whose material emits (WGSL `trace_emitters`, which
    /// ignores `flags`); 0: the whole scene (`trace_ray`).
    pub emitters_only: u32,
    /// Padding.
    pub _pad: [u32; 2],
}
const _: () = assert!(size_of::<GpuRay>() == 48);

/// WGSL twin: `RayHit` in `scene_types.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuRayHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Instance index or [`NO_HIT`].
    pub instance: u32,
    /// Triangle index within the mesh.
    pub primitive: u32,
    /// 1 when the front face was hit.
    pub front_face: u32,
    /// Barycentrics (weights of corners 1 and 2).
    pub barycentrics: [f32; 2],
}
const _: () = assert!(size_of::<GpuRayHit>() == 24);

#[cfg(test)]
mod tests {
    use super::halton_jitter;

    #[test]
    fn jitter_covers_the_pixel_evenly_and_repeats_every_16_frames() {
        let offsets: Vec<[f32; 2]> = (0..16).map(halton_jitter).collect();
        for o in &offsets {
            assert!(o.iter().all(|c| (-0.5..0.5).contains(c)), "{o:?}");
        }
        for (i, a) in offsets.iter().enumerate() {
            for b in &offsets[i + 1..] {
                assert_ne!(a, b, "repeated offset");
            }
        }
        // Each quarter of the pixel gets four samples, and the mean is near the centre.
        for qx in [false, true] {
            for qy in [false, true] {
                let n = offsets
                    .iter()
                    .filter(|o| (o[0] >= 0.0) == qx && (o[1] >= 0.0) == qy)
                    .count();
                assert!((3..=5).contains(&n), "quarter ({qx}, {qy}): {n}");
            }
        }
        let mean = offsets
            .iter()
            .fold([0.0; 2], |m, o| [m[0] + o[0], m[1] + o[1]]);
        assert!(mean.iter().all(|m| (m / 16.0).abs() < 0.05), "{mean:?}");
        assert_eq!(halton_jitter(16), halton_jitter(0));
    }
}
