//! Both tracing backends agree with the CPU reference on thousands of random and adversarial
//! rays over every bundled test scene and the built-in scene (GPU: lavapipe in CI).
//!
//! `t` must agree to 1e-4 relative, scaled by 1/|cos θ| between the ray and the triangle
//! normal (the condition number of a ray-plane intersection: at grazing angles a rounding of
//! the origin moves `t` by that much in any exact algorithm, and the ray-query hardware path
//! intersects with a different algorithm than ours).
//!
//! Documented ties (counted; among the plain random rays they must stay under 1%):
//! - two triangles hit at the same `t` (a shared edge or vertex, or coplanar overlap): either
//!   primitive is accepted when the CPU finds the same `t` for the GPU's triangle;
//! - a hit within 1e-4 (in barycentrics) of a triangle's edge that the other side does not see,
//!   reporting a miss or a farther hit instead: a ray through the boundary edge of a mesh,
//!   where rounding decides whether it passes. The near-edge hit must be real (the CPU finds
//!   the same `t` on that triangle, in f64). A nearer GPU hit that the f64 check confirms is
//!   accepted even away from an edge: then the f32 reference is the one that missed.

use glam::{Vec2, Vec3};
use rand::{Rng, SeedableRng};
use solari_scene::gpu::{Gpu, test_gpu};
use solari_scene::gpu_scene::{GpuScene, GpuSceneOptions, TraceVariant};
use solari_scene::gpu_types::{GpuRay, GpuRayHit, NO_HIT};
use solari_scene::shaders::Backend;
use solari_scene::trace_cpu::{
    CpuTracer, RAY_FLAG_CULL_BACK_FACING, RAY_FLAG_TERMINATE_ON_FIRST_HIT, RayHit,
};
use solari_scene::trace_pass::TraceRaysPass;
use solari_scene::*;

fn scenes() -> Vec<(String, Scene)> {
    let mut out = vec![("built-in".to_string(), default_scene::cornell_box())];
    // One instance under a rotated, scaled, translated transform: exercises the specialised
    // single-instance traversal's object-space ray.
    let mut single = default_scene::cornell_box();
    let mut block = single.instances[7].clone();
    block.transform = glam::Mat4::from_scale_rotation_translation(
        Vec3::new(1.5, 0.7, 1.2),
        glam::Quat::from_euler(glam::EulerRot::XYZ, 0.3, 0.8, -0.2),
        Vec3::new(3.0, -1.0, 2.0),
    ) * block.transform;
    single.instances = vec![block.clone()];
    out.push(("single transformed instance".to_string(), single.clone()));
    // The same block untransformed: the traversal that skips the object-space transform.
    block.transform = glam::Mat4::IDENTITY;
    single.instances = vec![block];
    out.push(("single untransformed instance".to_string(), single));
    // Mirrored instances (negative determinants): facing is the mesh's own winding.
    out.push(("mirrored instances".to_string(), mirrored_scene()));
    out.push((
        "textured spheres".to_string(),
        textured_scene::textured_spheres(),
    ));
    for name in solari_testdata::SCENES {
        out.push((
            name.to_string(),
            load_gltf(solari_testdata::scene(name)).unwrap(),
        ));
    }
    out
}

fn ray(o: Vec3, d: Vec3, t_min: f32, flags: u32) -> GpuRay {
    GpuRay {
        origin: o.into(),
        t_min,
        direction: d.into(),
        t_max: f32::MAX,
        flags,
        emitters_only: 0,
        _pad: [0; 2],
    }
}

fn random_dir(rng: &mut impl Rng) -> Vec3 {
    loop {
        let v = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

/// A random point on a random triangle of a random instance, with its world normal.
fn surface_point(scene: &Scene, rng: &mut impl Rng) -> (Vec3, Vec3, [Vec3; 3]) {
    let inst = &scene.instances[rng.random_range(0..scene.instances.len())];
    let mesh = &scene.meshes[inst.mesh as usize];
    let t = rng.random_range(0..mesh.triangle_count());
    let w = mesh.triangle(t).map(|p| inst.transform.transform_point3(p));
    let (mut u, mut v) = (rng.random::<f32>(), rng.random::<f32>());
    if u + v > 1.0 {
        (u, v) = (1.0 - u, 1.0 - v);
    }
    let p = w[0] + (w[1] - w[0]) * u + (w[2] - w[0]) * v;
    let n = (w[1] - w[0]).cross(w[2] - w[0]).normalize_or_zero();
    (p, n, w)
}

/// Thousands of rays of every adversarial kind for one scene.
fn make_rays(scene: &Scene, seed: u64) -> Vec<GpuRay> {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
    let (lo, hi) = scene.bounds();
    let extent = (hi - lo).length();
    let eps = extent * 1e-4;
    let mut rays = Vec::new();
    let inside = |rng: &mut rand_pcg::Pcg64| {
        Vec3::new(
            rng.random_range(lo.x..=hi.x),
            rng.random_range(lo.y..=hi.y),
            rng.random_range(lo.z..=hi.z),
        )
    };
    // Random rays from inside the bounds and from outside towards the scene.
    for _ in 0..1500 {
        rays.push(ray(inside(&mut rng), random_dir(&mut rng), 0.0, 0));
    }
    for _ in 0..500 {
        let target = inside(&mut rng);
        let o = (lo + hi) * 0.5 + random_dir(&mut rng) * extent * 1.5;
        rays.push(ray(o, target - o, 0.0, 0));
    }
    // Rays leaving surfaces, to either side, with a small t_min.
    for _ in 0..800 {
        let (p, _, _) = surface_point(scene, &mut rng);
        rays.push(ray(p, random_dir(&mut rng), eps, 0));
    }
    // Grazing rays: nearly in a triangle's plane, aimed at a point on it.
    for _ in 0..500 {
        let (p, n, _) = surface_point(scene, &mut rng);
        let t = n.any_orthonormal_vector();
        let tilt: f32 = rng.random_range(-1e-3..1e-3);
        let d = (t + n * tilt).normalize();
        rays.push(ray(p - d * extent * 0.3, d, 0.0, 0));
    }
    // Rays through shared edges and vertices.
    for _ in 0..600 {
        let (_, _, w) = surface_point(scene, &mut rng);
        let k = rng.random_range(0..3);
        let target = if rng.random_bool(0.5) {
            (w[k] + w[(k + 1) % 3]) * 0.5
        } else {
            w[k]
        };
        let o = target + random_dir(&mut rng) * extent * 0.5;
        rays.push(ray(o, target - o, 0.0, 0));
    }
    // Rays from inside closed boxes (instance centres) and flag variants.
    for i in 0..200 {
        let inst = &scene.instances[i % scene.instances.len()];
        let (a, b) = scene.meshes[inst.mesh as usize].bounds();
        let c = inst.transform.transform_point3((a + b) * 0.5);
        let flags = match i % 3 {
            0 => 0,
            1 => RAY_FLAG_CULL_BACK_FACING,
            _ => RAY_FLAG_TERMINATE_ON_FIRST_HIT,
        };
        // A flat instance's centre lies on its surface: start past rounding distance.
        rays.push(ray(c, random_dir(&mut rng), eps, flags));
    }
    for _ in 0..300 {
        rays.push(ray(
            inside(&mut rng),
            random_dir(&mut rng),
            0.0,
            RAY_FLAG_CULL_BACK_FACING,
        ));
    }
    rays
}

/// Barycentric distance from an edge within which a hit counts as "on the edge".
const EDGE_EPSILON: f32 = 1e-4;

fn near_edge(b: Vec2) -> bool {
    let w = 1.0 - b.x - b.y;
    b.x.abs() < EDGE_EPSILON || b.y.abs() < EDGE_EPSILON || w.abs() < EDGE_EPSILON
}

/// Number of plain random rays at the start of `make_rays`' list.
const RANDOM_RAYS: usize = 2000;

/// Allowed |Δt| for a hit at `t` on a triangle by the ray `o + t d`: 1e-4 relative plus the
/// rounding of the origin and hit point (a few ulps of their magnitude), both divided by
/// |cos θ| (the conditioning of a ray-plane intersection).
fn t_tolerance(cpu: &CpuTracer, inst: u32, prim: u32, o: Vec3, d: Vec3, t: f32) -> f32 {
    let cos = cpu
        .normal(inst, prim)
        .map(|n| n.dot(d.normalize()).abs())
        .unwrap_or(1.0);
    let magnitude = o.abs().max_element().max((o + d * t).abs().max_element());
    (1e-4 * t.abs() + 16.0 * f32::EPSILON * magnitude / d.length()) / cos.max(1e-3)
}

/// Whether a GPU hit lies on its triangle up to rounding, measured in f64: the world
/// coordinates' (a few ulps of their magnitude) plus the slide along the ray that `t`'s own
/// tolerance allows (`t_tolerance`, which grows as 1/|cos θ|). A rounding of the triangle
/// (merged BVHs hold it in world space, the reference in object space) moves hits at edges
/// and vertices, also of sliver triangles whose barycentrics swing widely there, and slides
/// the crossing point of a grazing ray: no barycentric check can arbitrate those.
fn on_triangle_within_rounding(cpu: &CpuTracer, o: Vec3, d: Vec3, g: &GpuRayHit) -> bool {
    let p = o + d * g.t;
    let ulps = 16.0 * f32::EPSILON * o.abs().max(p.abs()).max_element();
    let slide = d.length() * t_tolerance(cpu, g.instance, g.primitive, o, d, g.t);
    cpu.point_distance(g.instance, g.primitive, p)
        .is_some_and(|dist| dist <= (ulps + slide) as f64)
}

/// Whether the reference's hit lies at an edge of its triangle: within 1e-4 in barycentrics,
/// or within rounding in space (as `on_triangle_within_rounding` measures it), which is what
/// counts on tiny or sliver triangles.
fn cpu_hit_near_edge(cpu: &CpuTracer, o: Vec3, d: Vec3, c: &RayHit) -> bool {
    if near_edge(c.barycentrics) {
        return true;
    }
    let p = o + d * c.t;
    let ulps = 16.0 * f32::EPSILON * o.abs().max(p.abs()).max_element();
    let slide = d.length() * t_tolerance(cpu, c.instance, c.primitive, o, d, c.t);
    cpu.edge_distance(c.instance, c.primitive, p)
        .is_some_and(|dist| dist <= (ulps + slide) as f64)
}

/// Compares GPU hits with the CPU reference; returns (indices of ties, mismatches as text).
fn compare(cpu: &CpuTracer, rays: &[GpuRay], hits: &[GpuRayHit]) -> (Vec<usize>, Vec<String>) {
    let mut ties = Vec::new();
    let mut bad = Vec::new();
    for (i, (r, g)) in rays.iter().zip(hits).enumerate() {
        let o = Vec3::from(r.origin);
        let d = Vec3::from(r.direction);
        if r.flags & RAY_FLAG_TERMINATE_ON_FIRST_HIT != 0 {
            // Any hit will do; it must be a hit exactly when the closest-hit query hits, and
            // the hit must lie on the reported triangle.
            let c = cpu.trace(
                o,
                d,
                r.t_min,
                r.t_max,
                r.flags & !RAY_FLAG_TERMINATE_ON_FIRST_HIT,
            );
            if c.is_some() != (g.instance != NO_HIT) {
                bad.push(format!("ray {i} (any-hit): cpu {c:?} gpu {g:?}"));
            } else if g.instance != NO_HIT {
                let t = cpu.hit_t(g.instance, g.primitive, o, d, EDGE_EPSILON);
                let tol = t_tolerance(cpu, g.instance, g.primitive, o, d, g.t);
                if t.is_none_or(|t| (t - g.t).abs() > tol) {
                    bad.push(format!(
                        "ray {i} (any-hit): gpu hit {g:?} not on its triangle (cpu t {t:?})"
                    ));
                }
            }
            continue;
        }
        let c: Option<RayHit> = cpu.trace(o, d, r.t_min, r.t_max, r.flags);
        match (c, g.instance != NO_HIT) {
            (None, false) => {}
            (Some(c), true) => {
                let t_ok =
                    (c.t - g.t).abs() <= t_tolerance(cpu, c.instance, c.primitive, o, d, c.t);
                if c.instance == g.instance && c.primitive == g.primitive {
                    if !t_ok || c.front_face != (g.front_face == 1) {
                        bad.push(format!("ray {i}: cpu {c:?} gpu {g:?}"));
                    }
                } else {
                    let alt = cpu.hit_t(g.instance, g.primitive, o, d, EDGE_EPSILON);
                    let gtol = t_tolerance(cpu, g.instance, g.primitive, o, d, g.t);
                    let alt_ok = alt.is_some_and(|t| (t - g.t).abs() <= gtol);
                    if t_ok && alt_ok {
                        ties.push(i);
                    } else if g.t < c.t && alt_ok {
                        // The GPU's hit is real (checked in f64) and nearer: the f32 reference
                        // missed it (an edge or grazing case). Counted with the ties.
                        ties.push(i);
                    } else if (c.t < g.t
                        && (alt_ok || on_triangle_within_rounding(cpu, o, d, g))
                        && cpu_hit_near_edge(cpu, o, d, &c))
                        || (g.t <= c.t + t_tolerance(cpu, c.instance, c.primitive, o, d, c.t)
                            && on_triangle_within_rounding(cpu, o, d, g))
                    {
                        // Farther than the reference's hit at an edge the GPU slipped past,
                        // or not farther and on its triangle up to rounding.
                        ties.push(i);
                    } else {
                        let dist = cpu.point_distance(g.instance, g.primitive, o + d * g.t);
                        bad.push(format!(
                            "ray {i}: cpu {c:?} gpu {g:?} (cpu t on gpu's triangle {alt:?}, \
                             gpu hit point {dist:?} from it)"
                        ));
                    }
                }
            }
            (Some(c), false) if cpu_hit_near_edge(cpu, o, d, &c) => ties.push(i),
            (None, true) if near_edge(Vec2::from(g.barycentrics)) => ties.push(i),
            (None, true) => {
                // A hit the f32 reference missed away from an edge: a grazing ray, where the
                // crossing point slides along the ray with any rounding (merged BVHs meet it
                // in world space, the reference in object space). Real if f64 confirms it.
                let alt = cpu.hit_t(g.instance, g.primitive, o, d, EDGE_EPSILON);
                let gtol = t_tolerance(cpu, g.instance, g.primitive, o, d, g.t);
                if alt.is_some_and(|t| (t - g.t).abs() <= gtol)
                    || on_triangle_within_rounding(cpu, o, d, g)
                {
                    ties.push(i);
                } else {
                    bad.push(format!(
                        "ray {i}: cpu None gpu {g:?} (cpu t on gpu's triangle {alt:?})"
                    ));
                }
            }
            (c, _) => bad.push(format!("ray {i} {r:?}: cpu {c:?} gpu {g:?}")),
        }
    }
    (ties, bad)
}

/// `scene` on the GPU with tiny textures (traversal reads none), merged or two-level.
fn upload(
    gpu: &Gpu,
    scene: &Scene,
    backend: Backend,
    merge: bool,
) -> Result<GpuScene, solari_scene::GpuError> {
    let options = GpuSceneOptions {
        max_texture_size: 16,
        merge_instances: merge,
        ..Default::default()
    };
    GpuScene::new(gpu, scene, backend, &options)
}

fn backends(gpu: &Gpu) -> Vec<Backend> {
    let mut v = vec![Backend::Software];
    if gpu.has_ray_query() {
        v.push(Backend::RayQuery);
    } else if std::env::var("SOLARI_REQUIRE_GPU").as_deref() == Ok("1") {
        panic!(
            "SOLARI_REQUIRE_GPU=1 but adapter '{}' has no ray queries (need lavapipe from Mesa >= 24.1)",
            gpu.info.name
        );
    }
    v
}

#[test]
fn both_backends_agree_with_the_cpu_reference_on_every_scene() {
    let Some(gpu) = test_gpu() else { return };
    let mut report = Vec::new();
    for backend in backends(&gpu) {
        let general = TraceRaysPass::new(&gpu, backend, TraceVariant::General)
            .unwrap_or_else(|e| panic!("{e}"));
        // Merging changes nothing for ray queries: their scenes are traced once.
        let merges: &[bool] = match backend {
            Backend::Software => &[false, true],
            Backend::RayQuery => &[false],
        };
        for ((name, scene), &merge) in scenes()
            .into_iter()
            .flat_map(|s| merges.iter().map(move |m| (s.clone(), m)))
        {
            let cpu = CpuTracer::new(&scene);
            let gs = upload(&gpu, &scene, backend, merge).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(
                gs.is_merged(),
                merge,
                "{name}: every test scene fits the merge rule"
            );
            let name = format!("{name}{}", if merge { ", merged" } else { "" });
            // Scenes are also traced by every specialised traversal they fit.
            let specialised: Vec<_> = [
                TraceVariant::SingleInstance,
                TraceVariant::SingleUntransformed,
                TraceVariant::Merged,
            ]
            .into_iter()
            .filter(|v| v.for_backend(backend) == *v && v.check(&gs).is_ok())
            .map(|v| (v, TraceRaysPass::new(&gpu, backend, v).unwrap()))
            .collect();
            if backend == Backend::Software {
                let expected = match name.as_str() {
                    _ if merge => 1,
                    "single transformed instance" => 1,
                    "single untransformed instance" => 2,
                    _ => 0,
                };
                assert_eq!(specialised.len(), expected, "{name}: specialised variants");
                assert_eq!(
                    TraceVariant::for_scene(&gs),
                    specialised.last().map_or(TraceVariant::General, |s| s.0),
                    "{name}: for_scene picks the most specialised variant"
                );
            }
            let passes = std::iter::once((TraceVariant::General, &general))
                .chain(specialised.iter().map(|(v, p)| (*v, p)));
            for (variant, pass) in passes {
                let rays = make_rays(&scene, 42);
                let hits = pass.trace(&gpu, &gs, &rays).unwrap();
                let (tie_list, bad) = compare(&cpu, &rays, &hits);
                let ties = tie_list.len();
                let random_ties = tie_list.iter().filter(|&&i| i < RANDOM_RAYS).count();
                let hit_count = hits.iter().filter(|h| h.instance != NO_HIT).count();
                report.push(format!("{backend:?} {name} ({:?}): {} rays, {hit_count} hits, {ties} ties ({random_ties} among random rays), {} mismatches", variant, rays.len(), bad.len()));
                // Known open problem, in the driver's path rather than ours: lavapipe's ray queries
                // miss grazing hits in the millimetre-scale `metal_rough_spheres` (rays with
                // t ≈ 3e-3) and disagree on a few edge/vertex rays into `many_lights`' small
                // spheres (9 and 5 of 4400 with seed 42). The ray-query path gets a printed budget
                // of 0.5%; the software path, ours to fix, gets none.
                let budget = if backend == Backend::RayQuery {
                    rays.len() / 200
                } else {
                    0
                };
                if !bad.is_empty() {
                    eprintln!(
                        "{backend:?} {name}: {} mismatches:\n{}",
                        bad.len(),
                        bad.join("\n")
                    );
                }
                assert!(
                    bad.len() <= budget,
                    "{backend:?} {name}: {} mismatches of {} (budget {budget}):\n{}",
                    bad.len(),
                    rays.len(),
                    bad[..bad.len().min(10)].join("\n")
                );
                assert!(
                    random_ties * 100 <= RANDOM_RAYS,
                    "{backend:?} {name}: {random_ties} ties among random rays is more than 1%"
                );
                assert!(
                    hit_count * 4 > rays.len(),
                    "{name}: too few hits ({hit_count}) for a meaningful test"
                );
            }
        }
    }
    eprintln!("{}", report.join("\n"));
}

#[test]
fn moving_adding_and_removing_instances_updates_the_top_level_only() {
    let Some(gpu) = test_gpu() else { return };
    let mut scene = default_scene::cornell_box();
    for backend in backends(&gpu) {
        let pass = TraceRaysPass::new(&gpu, backend, TraceVariant::General).unwrap();
        let two_level = GpuSceneOptions {
            merge_instances: false,
            ..Default::default()
        };
        let mut gs = GpuScene::new(&gpu, &scene, backend, &two_level).unwrap();
        // A software traversal specialised for one instance refuses this many-instance scene.
        for variant in [
            TraceVariant::SingleInstance,
            TraceVariant::SingleUntransformed,
        ] {
            let single = TraceRaysPass::new(&gpu, backend, variant).unwrap();
            assert_eq!(
                single.trace(&gpu, &gs, &[]).is_err(),
                backend == Backend::Software
            );
        }
        let blas_nodes = gs.software_bvh().map(|b| b.blas_node_count);
        // Move the tall block up by 10 m, add a copy of the short block, remove the floor.
        scene.instances[7].transform = glam::Mat4::from_translation(Vec3::Y * 10.0);
        let mut copy = scene.instances[6].clone();
        copy.transform = glam::Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0));
        scene.instances.push(copy);
        scene.instances.remove(0);
        gs.set_instances(&gpu, &scene).unwrap();
        assert_eq!(
            gs.software_bvh().map(|b| b.blas_node_count),
            blas_nodes,
            "BLASes must not be rebuilt"
        );
        let rays = make_rays(&scene, 7);
        let hits = pass.trace(&gpu, &gs, &rays).unwrap();
        let (_, bad) = compare(&CpuTracer::new(&scene), &rays, &hits);
        assert!(
            bad.is_empty(),
            "{backend:?}: {}",
            bad[..bad.len().min(5)].join("\n")
        );
        scene = default_scene::cornell_box();
    }
}

#[test]
fn a_merged_scene_keeps_its_bvh_for_material_changes_and_splits_when_instances_move() {
    let Some(gpu) = test_gpu() else { return };
    let mut scene = default_scene::cornell_box();
    let mut gs =
        GpuScene::new(&gpu, &scene, Backend::Software, &GpuSceneOptions::default()).unwrap();
    assert!(gs.is_merged(), "merging is the default");
    assert_eq!(TraceVariant::for_scene(&gs), TraceVariant::Merged);
    let merged = TraceRaysPass::new(&gpu, Backend::Software, TraceVariant::Merged).unwrap();
    let general = TraceRaysPass::new(&gpu, Backend::Software, TraceVariant::General).unwrap();
    // Traversals specialised for one unmerged instance refuse a merged scene, and the merged
    // one refuses an unmerged scene (below).
    for v in [
        TraceVariant::SingleInstance,
        TraceVariant::SingleUntransformed,
    ] {
        let pass = TraceRaysPass::new(&gpu, Backend::Software, v).unwrap();
        let err = pass.trace(&gpu, &gs, &[]).unwrap_err().to_string();
        assert!(err.contains("merged"), "{err}");
    }
    let check = |gs: &GpuScene, scene: &Scene, pass: &TraceRaysPass, what: &str| {
        let rays = make_rays(scene, 11);
        let hits = pass.trace(&gpu, gs, &rays).unwrap();
        let (_, bad) = compare(&CpuTracer::new(scene), &rays, &hits);
        assert!(
            bad.is_empty(),
            "{what}: {}",
            bad[..bad.len().min(5)].join("\n")
        );
    };
    // A material swap (a light switched off, as the soak does) keeps the merged BVH.
    let nodes = gs.software_bvh().unwrap().nodes.len();
    scene.instances[2].material = scene.instances[0].material;
    gs.set_instances(&gpu, &scene).unwrap();
    assert!(gs.is_merged(), "a material change keeps the merged BVH");
    assert_eq!(gs.software_bvh().unwrap().nodes.len(), nodes);
    check(&gs, &scene, &merged, "merged after a material change");
    check(&gs, &scene, &general, "general on a merged scene");
    // Moving one instance splits the scene into the two-level BVH, which traces it right.
    scene.instances[7].transform = glam::Mat4::from_translation(Vec3::Y * 0.5);
    gs.set_instances(&gpu, &scene).unwrap();
    assert!(!gs.is_merged(), "a moved instance splits the merged BVH");
    assert_eq!(TraceVariant::for_scene(&gs), TraceVariant::General);
    let err = merged.trace(&gpu, &gs, &[]).unwrap_err().to_string();
    assert!(err.contains("TraceVariant::for_scene"), "{err}");
    check(&gs, &scene, &general, "two-level after the split");
    // Later moves only rebuild the top level.
    let blas_nodes = gs.software_bvh().unwrap().blas_node_count;
    scene.instances[7].transform = glam::Mat4::from_translation(Vec3::Y * 0.25);
    gs.set_instances(&gpu, &scene).unwrap();
    assert_eq!(gs.software_bvh().unwrap().blas_node_count, blas_nodes);
    check(&gs, &scene, &general, "two-level after a second move");
}

/// `scene` with only the instances whose material emits, and each one's index in `scene`.
fn emitters_only(scene: &Scene) -> (Scene, Vec<u32>) {
    let kept: Vec<u32> = solari_scene::bvh::emitter_layout(scene)
        .iter()
        .map(|e| e.0)
        .collect();
    let mut out = scene.clone();
    out.instances = kept
        .iter()
        .map(|&k| scene.instances[k as usize].clone())
        .collect();
    (out, kept)
}

/// Emitter-only rays: `make_rays`' rays (flags cleared: `trace_emitters` has none), then rays
/// from random surface points aimed at random points on emitters, through whatever occludes
/// them. Returns the rays and where the aimed ones start.
fn emitter_rays(scene: &Scene, emitters: &Scene, seed: u64) -> (Vec<GpuRay>, usize) {
    let mut rays = make_rays(scene, seed);
    let aimed = rays.len();
    let mut rng = rand_pcg::Pcg64::seed_from_u64(seed + 1);
    if !emitters.instances.is_empty() {
        for _ in 0..1500 {
            let (o, n, _) = surface_point(scene, &mut rng);
            let (target, _, _) = surface_point(emitters, &mut rng);
            // Off the surface along its normal, so the start is not on an emitter's plane.
            let o = o + n * 1e-3;
            rays.push(ray(o, target - o, 0.0, 0));
        }
    }
    for r in &mut rays {
        r.flags = 0;
        r.emitters_only = 1;
    }
    (rays, aimed)
}

/// The light states the emitter tests walk through, in order: as loaded; one emitter off and a
/// plain instance on (`switch_lights`); every emitter off.
const LIGHT_STATES: [&str; 3] = ["as loaded", "switched", "all off"];

/// Puts `scene` into `state` of [`LIGHT_STATES`] from the one before it: "switched" swaps the
/// materials of emitter `lit` and plain instance `dark`; "all off" gives every emissive
/// instance `lit`'s material (plain by then).
fn switch_lights(scene: &mut Scene, state: &str, lit: usize, dark: usize) {
    match state {
        "switched" => {
            let (on, off) = (
                scene.instances[lit].material,
                scene.instances[dark].material,
            );
            scene.instances[lit].material = off;
            scene.instances[dark].material = on;
        }
        "all off" => {
            let off = scene.instances[lit].material;
            for i in &mut scene.instances {
                if scene.materials[i.material as usize].is_emissive() {
                    i.material = off;
                }
            }
        }
        _ => {}
    }
}

#[test]
fn emitter_rays_see_only_emitters_through_occluders_and_follow_light_switches() {
    let Some(gpu) = test_gpu() else { return };
    let mut report = Vec::new();
    for backend in backends(&gpu) {
        let merges: &[bool] = match backend {
            Backend::Software => &[false, true],
            Backend::RayQuery => &[false],
        };
        let general = TraceRaysPass::new(&gpu, backend, TraceVariant::General).unwrap();
        let merged = TraceRaysPass::new(&gpu, backend, TraceVariant::Merged).unwrap();
        for (name, original) in [
            ("built-in".to_string(), default_scene::cornell_box()),
            (
                "many_lights".to_string(),
                load_gltf(solari_testdata::scene("many_lights")).unwrap(),
            ),
            (
                "emissive_strength_test".to_string(),
                load_gltf(solari_testdata::scene("emissive_strength_test")).unwrap(),
            ),
        ] {
            for &merge in merges {
                let mut scene = original.clone();
                let mut gs = upload(&gpu, &scene, backend, merge).unwrap();
                let emissive: Vec<usize> = solari_scene::bvh::emitter_layout(&scene)
                    .iter()
                    .map(|e| e.0 as usize)
                    .collect();
                let dark = scene
                    .instances
                    .iter()
                    .position(|i| !scene.materials[i.material as usize].is_emissive())
                    .unwrap();
                assert!(!emissive.is_empty(), "{name}: has emitters");
                // As loaded; with the first emitter switched off and a plain instance
                // switched on; with every emitter off (nothing to find).
                for state in LIGHT_STATES {
                    switch_lights(&mut scene, state, emissive[0], dark);
                    if state != "as loaded" {
                        gs.set_instances(&gpu, &scene).unwrap();
                    }
                    assert_eq!(
                        gs.is_merged(),
                        merge,
                        "{name} {state}: material changes keep the BVH's kind"
                    );
                    let (emitters, kept) = emitters_only(&scene);
                    let cpu_emitters = CpuTracer::new(&emitters);
                    let cpu_all = CpuTracer::new(&scene);
                    let (rays, aimed) = emitter_rays(&scene, &emitters, 5);
                    let passes: &[&TraceRaysPass] = if gs.is_merged() {
                        &[&general, &merged]
                    } else {
                        &[&general]
                    };
                    for (k, pass) in passes.iter().enumerate() {
                        let mut hits = pass.trace(&gpu, &gs, &rays).unwrap();
                        // The GPU names the scene's instances, the reference the emitters'.
                        for h in hits.iter_mut().filter(|h| h.instance != NO_HIT) {
                            h.instance =
                                kept.iter()
                                    .position(|&k| k == h.instance)
                                    .unwrap_or_else(|| {
                                        panic!(
                                            "{name} {state}: hit instance {} emits nothing",
                                            h.instance
                                        )
                                    }) as u32;
                        }
                        let (_, bad) = compare(&cpu_emitters, &rays, &hits);
                        let budget = if backend == Backend::RayQuery {
                            rays.len() / 200
                        } else {
                            0
                        };
                        assert!(
                            bad.len() <= budget,
                            "{backend:?} {name} {state} merged {merge}: {} mismatches of {}:\n{}",
                            bad.len(),
                            rays.len(),
                            bad[..bad.len().min(5)].join("\n")
                        );
                        let hits_aimed = hits[aimed..]
                            .iter()
                            .filter(|h| h.instance != NO_HIT)
                            .count();
                        // Aimed rays whose first surface in the whole scene emits nothing: the
                        // emitter ray must pass such occluders.
                        let occluded = rays[aimed..]
                            .iter()
                            .zip(&hits[aimed..])
                            .filter(|(r, h)| {
                                h.instance != NO_HIT
                                    && cpu_all
                                        .trace(
                                            r.origin.into(),
                                            r.direction.into(),
                                            0.0,
                                            f32::MAX,
                                            0,
                                        )
                                        .is_some_and(|c| {
                                            !scene.materials[scene.instances[c.instance as usize]
                                                .material
                                                as usize]
                                                .is_emissive()
                                        })
                            })
                            .count();
                        report.push(format!(
                            "{backend:?} {name} {state} merged {merge} ({} traversal): {} rays, {} mismatches, aimed {hits_aimed}/{} hit ({occluded} through an occluder)",
                            ["general", "merged"][k],
                            rays.len(),
                            bad.len(),
                            rays.len() - aimed
                        ));
                        if state == "all off" {
                            assert!(
                                hits.iter().all(|h| h.instance == NO_HIT),
                                "{name}: no emitter left, no hit"
                            );
                        } else {
                            assert!(
                                hits_aimed * 100 >= (rays.len() - aimed) * 95,
                                "{backend:?} {name} {state}: only {hits_aimed} of {} rays aimed at emitters found one",
                                rays.len() - aimed
                            );
                            assert!(
                                occluded * 20 >= rays.len() - aimed,
                                "{name} {state}: too few occluded emitter rays ({occluded}) for a meaningful test"
                            );
                        }
                    }
                }
            }
        }
    }
    eprintln!("{}", report.join("\n"));
}

#[test]
fn emitter_rays_without_an_emitter_bvh_see_the_first_surface_only_where_it_emits() {
    // Without an emitter BVH (turned off here; over its size rule or the binding limit in
    // use) `trace_emitters` returns the scene's closest hit when that emits and a miss
    // otherwise: the plain closest-hit ray of the same traversal, filtered by material.
    let Some(gpu) = test_gpu() else { return };
    use solari_scene::gpu_scene::EmitterTracing;
    let general = TraceRaysPass::new(&gpu, Backend::Software, TraceVariant::General).unwrap();
    let mut report = Vec::new();
    for (name, original) in [
        ("built-in", default_scene::cornell_box()),
        (
            "many_lights",
            load_gltf(solari_testdata::scene("many_lights")).unwrap(),
        ),
    ] {
        for merge in [false, true] {
            let mut scene = original.clone();
            let options = GpuSceneOptions {
                max_texture_size: 16,
                merge_instances: merge,
                emitter_bvh: false,
                ..Default::default()
            };
            let mut gs = GpuScene::new(&gpu, &scene, Backend::Software, &options).unwrap();
            let lit = solari_scene::bvh::emitter_layout(&scene)[0].0 as usize;
            let dark = scene
                .instances
                .iter()
                .position(|i| !scene.materials[i.material as usize].is_emissive())
                .unwrap();
            for state in LIGHT_STATES {
                switch_lights(&mut scene, state, lit, dark);
                if state != "as loaded" {
                    gs.set_instances(&gpu, &scene).unwrap();
                }
                let expected_tracing = if state == "all off" {
                    EmitterTracing::NoEmitters
                } else {
                    EmitterTracing::FirstSurface
                };
                assert_eq!(gs.emitter_tracing(), expected_tracing, "{name} {state}");
                let (emitters, _) = emitters_only(&scene);
                let (rays, aimed) = emitter_rays(&scene, &emitters, 7);
                let hits = general.trace(&gpu, &gs, &rays).unwrap();
                let plain: Vec<GpuRay> = rays
                    .iter()
                    .map(|r| GpuRay {
                        emitters_only: 0,
                        ..*r
                    })
                    .collect();
                let closest = general.trace(&gpu, &gs, &plain).unwrap();
                let emits = |h: &GpuRayHit| {
                    h.instance != NO_HIT
                        && scene.materials[scene.instances[h.instance as usize].material as usize]
                            .is_emissive()
                };
                for (i, (h, c)) in hits.iter().zip(&closest).enumerate() {
                    if emits(c) {
                        assert_eq!(h, c, "{name} {state} merged {merge}: ray {i}");
                    } else {
                        assert_eq!(
                            h.instance, NO_HIT,
                            "{name} {state} merged {merge}: ray {i} {h:?}"
                        );
                    }
                }
                let seen = hits[aimed..]
                    .iter()
                    .filter(|h| h.instance != NO_HIT)
                    .count();
                let hidden = closest[aimed..].iter().filter(|c| !emits(c)).count();
                report.push(format!(
                    "{name} {state} merged {merge}: {} rays, aimed at emitters {seen} hit, {hidden} hidden",
                    rays.len()
                ));
                if state != "all off" {
                    // Both kinds occur, so the filter is exercised both ways.
                    assert!(
                        seen > 0 && hidden > 0,
                        "{name} {state}: {seen} seen, {hidden} hidden"
                    );
                }
            }
        }
    }
    eprintln!("{}", report.join("\n"));
}

#[test]
fn the_emitter_bvh_follows_its_size_rule() {
    use solari_scene::bvh::{
        BvhQuality, EMITTERS_IN_SCENE, MERGE_MAX_TRIANGLES, SoftwareBvh, emitter_triangle_count,
        emitters_fit,
    };
    let mut scene = default_scene::cornell_box();
    assert!(emitters_fit(&scene));
    // The light becomes a 301,088-triangle grid, instanced until its copies pass both
    // bounds: more than MERGE_MAX_TRIANGLES and more than twice the meshes' triangles.
    let light = solari_scene::bvh::emitter_layout(&scene)[0].0 as usize;
    let n = 388u32;
    let mesh = &mut scene.meshes[scene.instances[light].mesh as usize];
    mesh.positions = (0..=n)
        .flat_map(|y| (0..=n).map(move |x| Vec3::new(x as f32, 5.0, y as f32) / n as f32))
        .collect();
    mesh.normals = vec![-Vec3::Y; mesh.positions.len()];
    mesh.uvs = vec![Vec2::ZERO; mesh.positions.len()];
    mesh.tangents = vec![glam::Vec4::X; mesh.positions.len()];
    mesh.indices = (0..n)
        .flat_map(|y| (0..n).map(move |x| y * (n + 1) + x))
        .flat_map(|i| [i, i + 1, i + n + 2, i, i + n + 2, i + n + 1])
        .collect();
    let copies = MERGE_MAX_TRIANGLES / mesh.triangle_count() + 1;
    let inst = scene.instances[light].clone();
    scene
        .instances
        .extend(std::iter::repeat_n(inst, copies - 1));
    assert!(!emitters_fit(&scene), "{}", emitter_triangle_count(&scene));
    // Over the rule the BVH has no emitter BVH (and no copies): emitters in the scene.
    let bvh = SoftwareBvh::build(&scene, BvhQuality::Fastest);
    assert_eq!(bvh.emitter_root, EMITTERS_IN_SCENE);
    assert!(!bvh.has_emitter_bvh());
    assert_eq!(
        bvh.triangles.len(),
        bvh.emitter_start.1 as usize,
        "no emitter copies"
    );
    scene.instances.pop();
    assert!(emitters_fit(&scene), "{}", emitter_triangle_count(&scene));
}

/// Built without the emitter BVH from the start, the BVH is the one a build with it becomes
/// when switched off, merged or two-level (so the CLI's `--emitter-bvh off` builds it once).
#[test]
fn a_bvh_built_without_the_emitter_bvh_equals_one_switched_off() {
    use solari_scene::bvh::{BvhQuality, EMITTERS_IN_SCENE, SoftwareBvh};
    let scene = default_scene::cornell_box();
    let q = BvhQuality::Fastest;
    let bytes = |b: &SoftwareBvh| {
        let nodes: &[u8] = bytemuck::cast_slice(&b.nodes);
        let tris: &[u8] = bytemuck::cast_slice(&b.triangles);
        (
            nodes.to_vec(),
            tris.to_vec(),
            b.tlas_instances.clone(),
            b.tlas_root,
        )
    };
    type Build = fn(&Scene, BvhQuality, bool) -> SoftwareBvh;
    let builds: [(Build, &str); 2] = [
        (SoftwareBvh::build_with, "two-level"),
        (SoftwareBvh::build_merged_with, "merged"),
    ];
    for (build, name) in builds {
        let with = build(&scene, q, true);
        assert!(with.has_emitter_bvh(), "{name}");
        let mut switched = with.clone();
        switched.set_emitter_bvh(false, &scene, q);
        let without = build(&scene, q, false);
        assert_eq!(without.emitter_root, EMITTERS_IN_SCENE, "{name}");
        assert!(bytes(&without) == bytes(&switched), "{name}");
        assert!(
            bytes(&without) != bytes(&with),
            "{name}: the emitter copies are gone"
        );
        // And it stays off through later rebuilds, as a switched-off one does.
        let mut rebuilt = without.clone();
        rebuilt.rebuild_emitters(&scene, q);
        assert!(bytes(&rebuilt) == bytes(&without), "{name}");
    }
}

#[test]
fn merging_follows_its_size_rule() {
    use solari_scene::bvh::{MERGE_MAX_TRIANGLES, merge_fits, merge_triangle_counts};
    let mut scene = default_scene::cornell_box();
    let (merged, meshes) = merge_triangle_counts(&scene);
    assert!(merged <= meshes * 2 && merge_fits(&scene));
    // One mesh instanced until the copies pass both bounds: more than MERGE_MAX_TRIANGLES
    // and more than twice the meshes' triangles.
    let mesh_tris = scene.meshes[scene.instances[0].mesh as usize].triangle_count();
    let copies = MERGE_MAX_TRIANGLES / mesh_tris + 1;
    let inst = scene.instances[0].clone();
    scene.instances = vec![inst; copies];
    assert!(!merge_fits(&scene), "{:?}", merge_triangle_counts(&scene));
    scene.instances.truncate(copies - 1);
    assert!(merge_fits(&scene), "{:?}", merge_triangle_counts(&scene));
}

/// The built-in scene with some instances mirrored (negative determinants).
fn mirrored_scene() -> Scene {
    let mut scene = default_scene::cornell_box();
    for (k, inst) in scene.instances.iter_mut().enumerate().skip(5) {
        let flip = if k % 2 == 0 {
            Vec3::new(-1.0, 1.0, 1.0)
        } else {
            Vec3::new(1.0, 1.0, -1.3)
        };
        inst.transform = glam::Mat4::from_scale(flip) * inst.transform;
    }
    scene
}

#[test]
fn merged_traversal_reports_what_the_two_level_one_reports_on_mirrored_instances() {
    // A merged BVH meets mirrored instances' triangles in world space, where they wind the
    // other way; traversal flips the front-face bit back (`MERGED_MIRRORED`), so hits and
    // back-face culling are those of the two-level traversal, which meets them in object space.
    // (Both also agree with the CPU reference there: `mirrored instances` in `scenes`.)
    let Some(gpu) = test_gpu() else { return };
    let scene = mirrored_scene();
    let rays = make_rays(&scene, 5);
    let trace = |merge: bool, variant: TraceVariant| {
        let options = GpuSceneOptions {
            merge_instances: merge,
            ..Default::default()
        };
        let gs = GpuScene::new(&gpu, &scene, Backend::Software, &options).unwrap();
        assert_eq!(gs.is_merged(), merge);
        let pass = TraceRaysPass::new(&gpu, Backend::Software, variant).unwrap();
        pass.trace(&gpu, &gs, &rays).unwrap()
    };
    let two_level = trace(false, TraceVariant::General);
    let cpu = CpuTracer::new(&scene);
    for (variant, merged) in [
        (TraceVariant::Merged, trace(true, TraceVariant::Merged)),
        (TraceVariant::General, trace(true, TraceVariant::General)),
    ] {
        let mut ties = 0;
        let mut random_ties = 0;
        let mut culled = 0;
        for (i, ((a, b), r)) in two_level.iter().zip(&merged).zip(&rays).enumerate() {
            culled += (r.flags & RAY_FLAG_CULL_BACK_FACING != 0 && a.instance != NO_HIT) as usize;
            if r.flags & RAY_FLAG_TERMINATE_ON_FIRST_HIT != 0 {
                // Any hit will do: only hit or miss must agree.
                assert_eq!(
                    a.instance == NO_HIT,
                    b.instance == NO_HIT,
                    "{variant:?} ray {i}"
                );
            } else if a.instance == b.instance && a.primitive == b.primitive {
                assert_eq!(
                    a.front_face, b.front_face,
                    "{variant:?} ray {i}: {a:?} {b:?}"
                );
                if a.instance != NO_HIT {
                    let (o, d) = (Vec3::from(r.origin), Vec3::from(r.direction));
                    let tol = t_tolerance(&cpu, a.instance, a.primitive, o, d, a.t);
                    assert!((a.t - b.t).abs() <= tol, "{variant:?} ray {i}: {a:?} {b:?}");
                }
            } else {
                // World and object space round differently: only at edges and grazing rays.
                let near =
                    |h: &GpuRayHit| h.instance == NO_HIT || near_edge(Vec2::from(h.barycentrics));
                assert!(
                    near(a) || near(b) || (a.t - b.t).abs() < 1e-3 * a.t.max(b.t),
                    "{variant:?} ray {i}: {a:?} {b:?}"
                );
                ties += 1;
                random_ties += (i < RANDOM_RAYS) as usize;
            }
        }
        // Most of the list is edge, vertex and grazing rays, built to sit on rounding.
        assert!(
            random_ties * 100 <= RANDOM_RAYS && ties * 10 <= rays.len(),
            "{variant:?}: {ties} ties, {random_ties} among random rays"
        );
        assert!(
            culled > 50,
            "the rays must include back-face culled ones ({culled})"
        );
    }
}

#[test]
fn a_merged_bvh_over_the_binding_limit_falls_back_to_two_levels() {
    // One mesh instanced 300 times: the merged triangles (300 copies) pass a 64 KiB binding
    // limit that the two-level BVH (one copy) stays under.
    let Some(gpu) = solari_scene::gpu::test_gpu_with_limits(|l| wgpu::Limits {
        max_storage_buffer_binding_size: 64 << 10,
        ..l
    }) else {
        return;
    };
    let mut scene = default_scene::cornell_box();
    let block = scene.instances[7].clone();
    scene.instances.truncate(7);
    for k in 0..300 {
        let mut copy = block.clone();
        let (x, z) = ((k % 20) as f32, (k / 20) as f32);
        copy.transform = glam::Mat4::from_translation(Vec3::new(x, 3.0, z) * 0.1)
            * glam::Mat4::from_scale(Vec3::splat(0.05));
        scene.instances.push(copy);
    }
    assert!(
        solari_scene::bvh::merge_fits(&scene),
        "the size rule allows it"
    );
    let gs = GpuScene::new(&gpu, &scene, Backend::Software, &GpuSceneOptions::default())
        .expect("falls back instead of failing");
    assert!(!gs.is_merged(), "over the binding limit: two-level");
    let pass = TraceRaysPass::new(&gpu, Backend::Software, TraceVariant::for_scene(&gs)).unwrap();
    // As many random rays as the ray buffer's 64 KiB allow.
    let rays = &make_rays(&scene, 3)[..1000];
    let hits = pass.trace(&gpu, &gs, rays).unwrap();
    let (_, bad) = compare(&CpuTracer::new(&scene), rays, &hits);
    assert!(bad.is_empty(), "{}", bad[..bad.len().min(5)].join("\n"));
    assert!(hits.iter().filter(|h| h.instance != NO_HIT).count() > 500);
}
