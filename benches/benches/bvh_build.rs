//! Software-BVH build speed per shared scene and preset (triangles/s).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use solari_scene::bvh::{BvhQuality, SoftwareBvh};

fn bvh_build(c: &mut Criterion) {
    let mut group = c.benchmark_group("bvh_build");
    group.sample_size(10);
    for path in solari_benches::shared_scenes() {
        let scene = solari_scene::load_gltf(&path).expect("shared scene loads");
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        group.throughput(Throughput::Elements(scene.stats().unique_triangles as u64));
        for q in [
            BvhQuality::Fastest,
            BvhQuality::Medium,
            BvhQuality::VerySlow,
        ] {
            group.bench_function(format!("{name}/{q:?}"), |b| {
                b.iter(|| SoftwareBvh::build(&scene, q))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bvh_build);
criterion_main!(benches);
