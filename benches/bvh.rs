//! Chapter 11's tree at 100k triangles (raylab's generated torus): the SAH
//! build, its fold into the wide tree, and tracing the 4096 fixed rays of
//! `raylab cost --chapter 11` through the binary and the wide tree, one
//! thread. `cargo bench --bench bvh`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use raylab::Chapters;
use raylab::bvh::BvhOptions;
use raylab::bvh_reports::cost::torus_workload;
use raylab::course::Objects;
use raylab::{Reference, Shape};

const TRIANGLES: usize = 100_000;

fn bvh(c: &mut Criterion) {
    let workload = torus_workload(TRIANGLES).expect("the generator makes 100k triangles");
    let bounds: Vec<_> = workload.shapes.iter().map(Shape::bounds).collect();
    let options = BvhOptions::default();
    let objects = Objects::<Reference>::new(&workload.shapes);
    let tree = Reference::build_bvh(&bounds, &options);
    let wide = Reference::collapse_bvh(&tree, &workload.shapes);

    let mut group = c.benchmark_group(format!("bvh, {} triangles", workload.shapes.len()));
    // A build takes tens of milliseconds: fewer samples keep the run short.
    group.sample_size(10);
    group.bench_function("SAH build", |b| {
        b.iter(|| Reference::build_bvh(black_box(&bounds), &options))
    });
    group.bench_function("fold into the wide tree", |b| {
        b.iter(|| Reference::collapse_bvh(black_box(&tree), &workload.shapes))
    });
    group.bench_function(format!("trace {} rays, wide", workload.rays.len()), |b| {
        b.iter(|| {
            workload
                .rays
                .iter()
                .filter(|ray| {
                    Reference::nearest_hit_wide(&wide, &objects, black_box(ray), 0.0, f32::INFINITY)
                        .is_some()
                })
                .count()
        })
    });
    group.bench_function(format!("trace {} rays", workload.rays.len()), |b| {
        b.iter(|| {
            workload
                .rays
                .iter()
                .filter(|ray| {
                    Reference::nearest_hit_bvh(&tree, &objects, black_box(ray), 0.0, f32::INFINITY)
                        .is_some()
                })
                .count()
        })
    });
    group.finish();
}

criterion_group!(benches, bvh);
criterion_main!(benches);
