//! The software tracing backend's acceleration structure: compressed wide BVHs (CWBVH, 80-byte
//! nodes with eight quantized children, Ylitie et al. 2017) built on the CPU by `obvhs`, one
//! per mesh plus one over instance bounds, flattened into one node array with absolute
//! indices so the shader needs no per-mesh offsets.
//!
//! Why obvhs: it builds high-quality BVHs fast (PLOC with reinsertion and optional spatial
//! pre-splits) and emits exactly the CWBVH layout the GPU traversal reads, the layout the
//! tray_racing peer traverses at the speeds we benchmark against.

use crate::model::Scene;
use crate::trace_cpu::instance_bounds;
use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec3A};
use obvhs::{BvhBuildParams, aabb::Aabb, cwbvh::node::CwBvhNode, triangle::Triangle};
use std::time::{Duration, Instant};

/// Build-quality presets, trading build time for traversal speed (see `benches/RESULTS.md`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BvhQuality {
    /// Fastest build, slowest traversal: for geometry rebuilt every frame.
    Fastest,
    /// Fast build.
    Fast,
    /// Balanced (default).
    #[default]
    Medium,
    /// Slow build with spatial pre-splits: for static scenes.
    Slow,
    /// Slowest build, fastest traversal.
    VerySlow,
}

impl BvhQuality {
    /// The obvhs build parameters for this preset.
    pub fn params(self) -> BvhBuildParams {
        match self {
            Self::Fastest => BvhBuildParams::very_fast_build(),
            Self::Fast => BvhBuildParams::fast_build(),
            Self::Medium => BvhBuildParams::medium_build(),
            Self::Slow => BvhBuildParams::slow_build(),
            Self::VerySlow => BvhBuildParams::very_slow_build(),
        }
    }

    /// The name [`BvhQuality::parse`] reads.
    pub fn name(self) -> &'static str {
        match self {
            Self::Fastest => "fastest",
            Self::Fast => "fast",
            Self::Medium => "medium",
            Self::Slow => "slow",
            Self::VerySlow => "very-slow",
        }
    }

    /// Parses a preset name (`fastest`, `fast`, `medium`, `slow`, `very-slow`).
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "fastest" => Self::Fastest,
            "fast" => Self::Fast,
            "medium" => Self::Medium,
            "slow" => Self::Slow,
            "very-slow" | "very_slow" => Self::VerySlow,
            _ => return None,
        })
    }
}

/// A triangle as the GPU stores it: corner 0 and two edges, with the mesh-local triangle index
/// in `v0.w` (as bits). WGSL twin: `BvhTriangle` in `scene_bindings.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuTriangle {
    /// Corner 0 (xyz) and the triangle's index in its mesh (w, bit-cast u32).
    pub v0: [f32; 4],
    /// Edge 1 (xyz). In a merged BVH, w holds the triangle's instance (bit-cast u32, with
    /// [`MERGED_MIRRORED`] set when that instance's transform mirrors); unused otherwise.
    pub e1: [f32; 4],
    /// Edge 2 (xyz), w unused.
    pub e2: [f32; 4],
}
const _: () = assert!(size_of::<GpuTriangle>() == 48);
const _: () = assert!(size_of::<CwBvhNode>() == 80);

/// Bit 31 of a merged triangle's instance word (`GpuTriangle::e1`'s w): the instance's
/// transform has a negative determinant, so the world-space triangle winds the other way and
/// traversal flips the front-face bit back to the mesh's own winding.
pub const MERGED_MIRRORED: u32 = 1 << 31;

/// Merging stops paying when instancing would copy too much: a merged BVH holds every
/// instance's triangles, where the two-level one holds each mesh's once. Merge when the copies
/// stay at most this many triangles, or at most [`MERGE_MAX_COPY_FACTOR`] times the meshes' own.
pub const MERGE_MAX_TRIANGLES: usize = 1 << 22;

/// See [`MERGE_MAX_TRIANGLES`].
pub const MERGE_MAX_COPY_FACTOR: usize = 2;

/// Triangles a merged BVH of `scene` would hold, and those of its meshes (what the two-level
/// BVH holds), before spatial splits.
pub fn merge_triangle_counts(scene: &Scene) -> (usize, usize) {
    let merged = scene
        .instances
        .iter()
        .map(|i| scene.meshes[i.mesh as usize].triangle_count())
        .sum();
    let meshes = scene.meshes.iter().map(|m| m.triangle_count()).sum();
    (merged, meshes)
}

/// Whether a merged BVH of `scene` stays within the size rule of [`MERGE_MAX_TRIANGLES`].
pub fn merge_fits(scene: &Scene) -> bool {
    let (merged, meshes) = merge_triangle_counts(scene);
    copies_fit(merged, meshes)
}

// The size rule of `MERGE_MAX_TRIANGLES` for `copies` world-space triangles of a scene whose
// meshes hold `meshes`.
fn copies_fit(copies: usize, meshes: usize) -> bool {
    copies <= MERGE_MAX_TRIANGLES || copies <= meshes.saturating_mul(MERGE_MAX_COPY_FACTOR)
}

/// Triangles the emitter BVH of `scene` would hold: every emissive instance's copy of its
/// mesh ([`emitter_layout`]).
pub fn emitter_triangle_count(scene: &Scene) -> usize {
    emitter_layout(scene)
        .iter()
        .map(|&(_, mesh, _)| scene.meshes[mesh as usize].triangle_count())
        .sum()
}

/// Whether the emitter BVH of `scene` stays within the size rule of [`MERGE_MAX_TRIANGLES`]
/// (the copies it makes against the meshes' own triangles). Beyond it, emitter rays trace
/// the whole scene instead ([`EMITTERS_IN_SCENE`]): thousands of instanced lamps would
/// otherwise copy millions of triangles for one ray of ReSTIR DI.
pub fn emitters_fit(scene: &Scene) -> bool {
    let meshes = scene.meshes.iter().map(|m| m.triangle_count()).sum();
    copies_fit(emitter_triangle_count(scene), meshes)
}

/// The flattened two-level BVH, ready to upload; or, merged, one world-space BVH over every
/// instance's triangles ([`SoftwareBvh::build_merged`]).
#[derive(Clone, Debug, Default)]
pub struct SoftwareBvh {
    /// All nodes: each mesh's BLAS (merged: the one BVH), the emitter BVH, then the TLAS (none
    /// when merged). Indices inside are absolute.
    pub nodes: Vec<CwBvhNode>,
    /// Triangles of all meshes (merged: of all instances, in world space) in BVH leaf order
    /// (with duplicates under spatial splits), then the emitter BVH's.
    pub triangles: Vec<GpuTriangle>,
    /// Instance index for each TLAS leaf slot (merged: empty).
    pub tlas_instances: Vec<u32>,
    /// Root node index of each mesh's BLAS (merged: 0, unused).
    pub blas_roots: Vec<u32>,
    /// Root node index of the TLAS (merged: of the one BVH, where traversal starts).
    pub tlas_root: u32,
    /// Node count of the BLASes and the emitter BVH (the TLAS follows them; merged: all
    /// nodes).
    pub blas_node_count: u32,
    /// Time spent building the BLASes and the emitter BVH (merged: the whole build).
    pub blas_build_time: Duration,
    /// Time spent building the TLAS (merged: zero).
    pub tlas_build_time: Duration,
    /// For a merged BVH, each instance's (mesh, transform) it was built from: the instances
    /// it can trace without a rebuild. `None` for the two-level BVH.
    pub merged_from: Option<Vec<(u32, glam::Mat4)>>,
    /// Root node of the emitter BVH ([`NO_EMITTERS`] when no instance emits): one world-space
    /// level over the triangles of the instances whose material emits, tagged as in a merged
    /// BVH. Rays that look only for emitters (ReSTIR DI's BRDF-sampled candidates, WGSL
    /// `trace_emitters`) start there and skip every other surface. Its nodes and triangles
    /// follow the main BVH's (before the TLAS, whose nodes come last).
    pub emitter_root: u32,
    /// Where the emitter BVH's nodes and triangles start in [`SoftwareBvh::nodes`] and
    /// [`SoftwareBvh::triangles`].
    pub emitter_start: (u32, u32),
    /// The emissive instances the emitter BVH was built from: (instance, mesh, transform).
    pub emitters_from: Vec<(u32, u32, glam::Mat4)>,
    // Set by `set_emitter_bvh(false, ..)`: every rebuild leaves the emitter BVH out.
    emitter_bvh_off: bool,
}

/// [`SoftwareBvh::emitter_root`] of a scene without emissive instances. WGSL twin:
/// `NO_EMITTERS` in `trace.wesl`.
pub const NO_EMITTERS: u32 = u32::MAX;

/// [`SoftwareBvh::emitter_root`] of a scene whose instances emit but which has no emitter BVH
/// (over [`emitters_fit`]'s size rule or the device's binding limit, or turned off with
/// [`SoftwareBvh::set_emitter_bvh`]): emitter rays trace the whole scene and return its
/// first surface when that emits, a miss otherwise. ReSTIR DI's BRDF-sampled candidates
/// then see only the emitters visible along their ray, as before the emitter BVH existed.
/// WGSL twin: `EMITTERS_IN_SCENE` in `trace.wesl`.
pub const EMITTERS_IN_SCENE: u32 = u32::MAX - 1;

/// Whether `instance`'s material in `scene` emits (the emitter BVH holds it).
pub fn instance_emits(scene: &Scene, instance: &crate::model::Instance) -> bool {
    scene
        .materials
        .get(instance.material as usize)
        .is_some_and(|m| m.is_emissive())
}

/// The instances whose material emits, with their mesh and transform: what the emitter BVH
/// holds ([`SoftwareBvh::emitter_root`]).
pub fn emitter_layout(scene: &Scene) -> Vec<(u32, u32, glam::Mat4)> {
    scene
        .instances
        .iter()
        .enumerate()
        .filter(|(_, i)| instance_emits(scene, i))
        .map(|(k, i)| (k as u32, i.mesh, i.transform))
        .collect()
}

/// World-space triangles of `instances` (index into `scene.instances` each), with each one's
/// (instance tag, mesh-local index): the input of a merged or emitter BVH.
fn world_triangles(
    scene: &Scene,
    instances: impl Iterator<Item = u32>,
) -> (Vec<Triangle>, Vec<(u32, u32)>) {
    let (mut tris, mut ids) = (Vec::new(), Vec::new());
    for k in instances {
        let inst = &scene.instances[k as usize];
        let m = inst.transform.as_dmat4();
        let tag = k | if m.determinant() < 0.0 {
            MERGED_MIRRORED
        } else {
            0
        };
        let mesh = &scene.meshes[inst.mesh as usize];
        for t in 0..mesh.triangle_count() {
            // World positions in f64, rounded once: as close to the mesh as f32 allows.
            let [a, b, c] = mesh
                .triangle(t)
                .map(|p| m.transform_point3(p.as_dvec3()).as_vec3());
            tris.push(Triangle {
                v0: a.into(),
                v1: b.into(),
                v2: c.into(),
            });
            ids.push((tag, t as u32));
        }
    }
    (tris, ids)
}

/// Meshes with fewer triangles than this build on one thread. obvhs's parallel build (its
/// `parallel` feature) is 1.8–5× faster on an 8.4M-triangle mesh with 16 cores but 3–4× slower
/// on scenes of small meshes, where thread hand-offs outweigh the work (`benches/RESULTS.md`).
pub const PARALLEL_BUILD_MIN_TRIANGLES: usize = 65_536;

/// Runs a BVH build on all cores when it has at least [`PARALLEL_BUILD_MIN_TRIANGLES`]
/// primitives, else on the calling thread's own one-thread pool.
fn run_build<R: Send>(primitives: usize, build: impl FnOnce() -> R + Send) -> R {
    static SERIAL: std::sync::OnceLock<Option<rayon::ThreadPool>> = std::sync::OnceLock::new();
    if primitives >= PARALLEL_BUILD_MIN_TRIANGLES {
        return build();
    }
    // A pool that cannot start (no threads allowed) just means building on the global pool.
    match SERIAL.get_or_init(|| rayon::ThreadPoolBuilder::new().num_threads(1).build().ok()) {
        Some(pool) => pool.install(build),
        None => build(),
    }
}

/// Builds one mesh's CWBVH and returns (nodes, triangles) with indices relative to 0.
fn build_blas(
    mesh: &crate::model::Mesh,
    quality: BvhQuality,
) -> (Vec<CwBvhNode>, Vec<GpuTriangle>) {
    let tris: Vec<Triangle> = (0..mesh.triangle_count())
        .map(|t| {
            let [a, b, c] = mesh.triangle(t);
            Triangle {
                v0: a.into(),
                v1: b.into(),
                v2: c.into(),
            }
        })
        .collect();
    build_triangles(&tris, quality, |i| (i, 0))
}

/// Builds a CWBVH over `tris` and returns (nodes, triangles in leaf order); `ids` gives each
/// input triangle's (mesh-local index, `e1.w` word).
fn build_triangles(
    tris: &[Triangle],
    quality: BvhQuality,
    ids: impl Fn(u32) -> (u32, u32),
) -> (Vec<CwBvhNode>, Vec<GpuTriangle>) {
    let bvh = run_build(tris.len(), || {
        obvhs::cwbvh::builder::build_cwbvh_from_tris(
            tris,
            quality.params(),
            &mut Duration::default(),
        )
    });
    let triangles = bvh
        .primitive_indices
        .iter()
        .map(|&i| {
            let t = &tris[i as usize];
            let (local, word) = ids(i);
            let e1 = Vec3::from(t.v1 - t.v0);
            let e2 = Vec3::from(t.v2 - t.v0);
            GpuTriangle {
                v0: [t.v0.x, t.v0.y, t.v0.z, f32::from_bits(local)],
                e1: e1.extend(f32::from_bits(word)).into(),
                e2: e2.extend(0.0).into(),
            }
        })
        .collect();
    (bvh.nodes, triangles)
}

fn offset_nodes(nodes: &mut [CwBvhNode], node_offset: u32, prim_offset: u32) {
    for n in nodes {
        n.child_base_idx += node_offset;
        n.primitive_base_idx += prim_offset;
    }
}

impl SoftwareBvh {
    /// Builds every mesh's BLAS and the TLAS.
    pub fn build(scene: &Scene, quality: BvhQuality) -> Self {
        Self::build_with(scene, quality, true)
    }

    /// [`SoftwareBvh::build`] with the emitter BVH (`emitter_bvh`) or, built once, without
    /// it ([`SoftwareBvh::set_emitter_bvh`] off, which after a build with it would have built
    /// it and the TLAS for nothing).
    pub fn build_with(scene: &Scene, quality: BvhQuality, emitter_bvh: bool) -> Self {
        let start = Instant::now();
        let mut out = SoftwareBvh {
            emitter_bvh_off: !emitter_bvh,
            ..Default::default()
        };
        for mesh in &scene.meshes {
            let (mut nodes, tris) = build_blas(mesh, quality);
            let node_offset = out.nodes.len() as u32;
            offset_nodes(&mut nodes, node_offset, out.triangles.len() as u32);
            out.blas_roots.push(node_offset);
            out.nodes.extend(nodes);
            out.triangles.extend(tris);
        }
        out.append_emitters(scene, quality);
        out.blas_build_time = start.elapsed();
        out.rebuild_tlas(scene, quality);
        out
    }

    /// Builds one BVH over every instance's triangles in world space, each triangle tagged
    /// with its instance (`GpuTriangle::e1`'s w). Traversal then has no top level and no
    /// object-space transform: the 1,290-instance `interior` traces as one flat BVH (on an
    /// H100 0.98 ms instead of 1.37 for its primary + hemisphere rays, `benches/RESULTS.md`).
    /// The BVH holds every instance's
    /// copy of its mesh ([`merge_fits`] says when that is reasonable), and moving an
    /// instance means building it again ([`SoftwareBvh::traces_merged`]).
    pub fn build_merged(scene: &Scene, quality: BvhQuality) -> Self {
        Self::build_merged_with(scene, quality, true)
    }

    /// [`SoftwareBvh::build_merged`] with the emitter BVH or without it
    /// ([`SoftwareBvh::build_with`]).
    pub fn build_merged_with(scene: &Scene, quality: BvhQuality, emitter_bvh: bool) -> Self {
        let start = Instant::now();
        let (tris, ids) = world_triangles(scene, 0..scene.instances.len() as u32);
        let (nodes, triangles) = build_triangles(&tris, quality, |i| {
            let (tag, local) = ids[i as usize];
            (local, tag)
        });
        let mut out = Self {
            nodes,
            triangles,
            tlas_instances: Vec::new(),
            blas_roots: vec![0; scene.meshes.len()],
            tlas_root: 0,
            merged_from: Some(merged_layout(scene)),
            emitter_bvh_off: !emitter_bvh,
            ..Self::default()
        };
        out.append_emitters(scene, quality);
        out.blas_build_time = start.elapsed();
        out
    }

    /// Whether the emitter BVH holds exactly `scene`'s emissive instances where they are.
    pub fn emitters_match(&self, scene: &Scene) -> bool {
        self.emitters_from == emitter_layout(scene)
    }

    /// Builds the emitter BVH again for `scene`'s emissive instances (after a material or an
    /// instance changed), and the TLAS after it for a two-level BVH.
    pub fn rebuild_emitters(&mut self, scene: &Scene, quality: BvhQuality) {
        let (nodes, triangles) = self.emitter_start;
        self.nodes.truncate(nodes as usize);
        self.triangles.truncate(triangles as usize);
        self.append_emitters(scene, quality);
        if !self.is_merged() {
            self.rebuild_tlas(scene, quality);
        }
    }

    /// Builds the emitter BVH (`on`, the default) or leaves it out for good, emitter rays
    /// then tracing the whole scene ([`EMITTERS_IN_SCENE`]); rebuilds what follows it when
    /// that changes. Off saves the emitter copies' memory and build time (on each light
    /// switch), at the cost of slower emitter rays and ReSTIR DI's visibility-dependent
    /// BRDF candidates.
    pub fn set_emitter_bvh(&mut self, on: bool, scene: &Scene, quality: BvhQuality) {
        if self.emitter_bvh_off != on {
            return;
        }
        self.emitter_bvh_off = !on;
        self.rebuild_emitters(scene, quality);
    }

    /// Whether emitter rays traverse an emitter BVH (else [`SoftwareBvh::emitter_root`] is
    /// [`NO_EMITTERS`] or [`EMITTERS_IN_SCENE`]).
    pub fn has_emitter_bvh(&self) -> bool {
        self.emitter_root < EMITTERS_IN_SCENE
    }

    // Appends the emitter BVH after the nodes and triangles built so far (each mesh's BLAS or
    // the merged level); the TLAS, if any, is built after it.
    fn append_emitters(&mut self, scene: &Scene, quality: BvhQuality) {
        self.emitter_start = (self.nodes.len() as u32, self.triangles.len() as u32);
        self.emitters_from = emitter_layout(scene);
        self.emitter_root = NO_EMITTERS;
        if !self.emitters_from.is_empty() && (self.emitter_bvh_off || !emitters_fit(scene)) {
            if !self.emitter_bvh_off {
                log::info!(
                    "no emitter BVH: {} triangles in emissive instances against {} in the \
                     meshes (bvh::emitters_fit); emitter rays trace the whole scene",
                    emitter_triangle_count(scene),
                    scene
                        .meshes
                        .iter()
                        .map(|m| m.triangle_count())
                        .sum::<usize>()
                );
            }
            self.emitter_root = EMITTERS_IN_SCENE;
        } else if !self.emitters_from.is_empty() {
            let (tris, ids) = world_triangles(scene, self.emitters_from.iter().map(|e| e.0));
            let (mut nodes, triangles) = build_triangles(&tris, quality, |i| {
                let (tag, local) = ids[i as usize];
                (local, tag)
            });
            let (node_offset, prim_offset) = self.emitter_start;
            offset_nodes(&mut nodes, node_offset, prim_offset);
            self.emitter_root = node_offset;
            self.nodes.extend(nodes);
            self.triangles.extend(triangles);
        }
        self.blas_node_count = self.nodes.len() as u32;
    }

    /// Whether this is a merged BVH that traces `scene`'s instances as they are: the same
    /// meshes under the same transforms (materials may differ: the BVH does not hold them).
    pub fn traces_merged(&self, scene: &Scene) -> bool {
        self.merged_from
            .as_ref()
            .is_some_and(|from| *from == merged_layout(scene))
    }

    /// Rebuilds only the top level (after instances moved, were added or removed). A merged
    /// BVH has no top level: it is built again, whole, for `scene`'s instances.
    pub fn rebuild_tlas(&mut self, scene: &Scene, quality: BvhQuality) {
        if self.is_merged() {
            *self = Self::build_merged(scene, quality);
            return;
        }
        let start = Instant::now();
        self.nodes.truncate(self.blas_node_count as usize);
        let aabbs: Vec<Aabb> = scene
            .instances
            .iter()
            .map(|i| {
                let (lo, hi) = instance_bounds(scene, i);
                Aabb::new(Vec3A::from(lo), Vec3A::from(hi))
            })
            .collect();
        // Same preset as the BLASes, minus pre-splits (they split triangles, not boxes).
        let mut params = quality.params();
        params.pre_split = false;
        let tlas = run_build(aabbs.len(), || {
            obvhs::cwbvh::builder::build_cwbvh(&aabbs, params, &mut Duration::default())
        });
        let mut nodes = tlas.nodes;
        self.tlas_root = self.nodes.len() as u32;
        offset_nodes(&mut nodes, self.tlas_root, 0);
        self.nodes.extend(nodes);
        self.tlas_instances = tlas.primitive_indices;
        self.tlas_build_time = start.elapsed();
    }

    /// Whether this is a merged BVH ([`SoftwareBvh::build_merged`]).
    pub fn is_merged(&self) -> bool {
        self.merged_from.is_some()
    }

    /// Total bytes the GPU buffers take.
    pub fn gpu_bytes(&self) -> u64 {
        (self.nodes.len() * 80 + self.triangles.len() * 48 + self.tlas_instances.len() * 4) as u64
    }
}

fn merged_layout(scene: &Scene) -> Vec<(u32, glam::Mat4)> {
    scene
        .instances
        .iter()
        .map(|i| (i.mesh, i.transform))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rebuilding_the_top_level_of_a_merged_bvh_rebuilds_it_for_the_new_instances() {
        let mut scene = crate::default_scene::cornell_box();
        let mut bvh = SoftwareBvh::build_merged(&scene, BvhQuality::Fastest);
        assert!(bvh.traces_merged(&scene));
        scene.instances[7].transform = glam::Mat4::from_translation(glam::Vec3::Y);
        assert!(
            !bvh.traces_merged(&scene),
            "a moved instance needs a new merged BVH"
        );
        bvh.rebuild_tlas(&scene, BvhQuality::Fastest);
        assert!(bvh.is_merged() && bvh.traces_merged(&scene));
        // The moved block's triangles are where its new transform puts them.
        let mesh = &scene.meshes[scene.instances[7].mesh as usize];
        let moved: Vec<&GpuTriangle> = bvh
            .triangles
            .iter()
            .filter(|t| t.e1[3].to_bits() & !MERGED_MIRRORED == 7)
            .collect();
        assert_eq!(moved.len(), mesh.triangle_count());
        for t in moved {
            let local = t.v0[3].to_bits() as usize;
            let want = mesh.triangle(local)[0] + glam::Vec3::Y;
            assert!((glam::Vec3::new(t.v0[0], t.v0[1], t.v0[2]) - want).length() < 1e-5);
        }
    }
}
