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
/// in `v0.w` (as bits). WGSL twin: `BvhTriangle` in `trace_software.wesl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuTriangle {
    /// Corner 0 (xyz) and the triangle's index in its mesh (w, bit-cast u32).
    pub v0: [f32; 4],
    /// Edge 1 (xyz), w unused.
    pub e1: [f32; 4],
    /// Edge 2 (xyz), w unused.
    pub e2: [f32; 4],
}
const _: () = assert!(size_of::<GpuTriangle>() == 48);
const _: () = assert!(size_of::<CwBvhNode>() == 80);

/// The flattened two-level BVH, ready to upload.
#[derive(Clone, Debug, Default)]
pub struct SoftwareBvh {
    /// All nodes: each mesh's BLAS, then the TLAS. Indices inside are absolute.
    pub nodes: Vec<CwBvhNode>,
    /// Triangles of all meshes in BVH leaf order (with duplicates under spatial splits).
    pub triangles: Vec<GpuTriangle>,
    /// Instance index for each TLAS leaf slot.
    pub tlas_instances: Vec<u32>,
    /// Root node index of each mesh's BLAS.
    pub blas_roots: Vec<u32>,
    /// Root node index of the TLAS.
    pub tlas_root: u32,
    /// Node count of the BLASes (the TLAS follows them).
    pub blas_node_count: u32,
    /// Time spent building the BLASes.
    pub blas_build_time: Duration,
    /// Time spent building the TLAS.
    pub tlas_build_time: Duration,
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
    let bvh = run_build(tris.len(), || {
        obvhs::cwbvh::builder::build_cwbvh_from_tris(
            &tris,
            quality.params(),
            &mut Duration::default(),
        )
    });
    let triangles = bvh
        .primitive_indices
        .iter()
        .map(|&i| {
            let t = &tris[i as usize];
            let e1 = Vec3::from(t.v1 - t.v0);
            let e2 = Vec3::from(t.v2 - t.v0);
            GpuTriangle {
                v0: [t.v0.x, t.v0.y, t.v0.z, f32::from_bits(i)],
                e1: e1.extend(0.0).into(),
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
        let start = Instant::now();
        let mut out = SoftwareBvh::default();
        for mesh in &scene.meshes {
            let (mut nodes, tris) = build_blas(mesh, quality);
            let node_offset = out.nodes.len() as u32;
            offset_nodes(&mut nodes, node_offset, out.triangles.len() as u32);
            out.blas_roots.push(node_offset);
            out.nodes.extend(nodes);
            out.triangles.extend(tris);
        }
        out.blas_node_count = out.nodes.len() as u32;
        out.blas_build_time = start.elapsed();
        out.rebuild_tlas(scene, quality);
        out
    }

    /// Rebuilds only the top level (after instances moved, were added or removed).
    pub fn rebuild_tlas(&mut self, scene: &Scene, quality: BvhQuality) {
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

    /// Total bytes the GPU buffers take.
    pub fn gpu_bytes(&self) -> u64 {
        (self.nodes.len() * 80 + self.triangles.len() * 48 + self.tlas_instances.len() * 4) as u64
    }
}
