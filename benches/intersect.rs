//! Time of one ray-primitive test: the plane, the stable sphere formula and
//! the textbook one, near and far. `cargo bench --bench intersect`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use raylab::{Plane, Ray, Sphere, Vec3};

fn rays() -> Vec<Ray> {
    // A fan of rays from the origin, some hitting and some missing.
    (0..64)
        .map(|i| {
            let x = (i % 8) as f32 / 8.0 - 0.5;
            let y = (i / 8) as f32 / 8.0 - 0.5;
            Ray::new(Vec3::ZERO, Vec3::new(x, y, 1.0).normalize())
        })
        .collect()
}

fn intersectors(c: &mut Criterion) {
    let rays = rays();
    let plane = Plane::new(Vec3::new(0.0, -1.0, 0.0), Vec3::Y);
    let near = Sphere::new(Vec3::new(0.0, 0.0, 5.0), 1.5);
    let far = Sphere::new(Vec3::new(0.0, 0.0, 1000.0), 300.0);
    let mut group = c.benchmark_group("intersect 64 rays");
    group.bench_function("plane", |b| {
        b.iter(|| {
            rays.iter()
                .filter_map(|ray| plane.intersect(black_box(ray), 0.0, f32::INFINITY))
                .count()
        })
    });
    for (name, sphere) in [("near", near), ("far", far)] {
        group.bench_function(format!("sphere stable, {name}"), |b| {
            b.iter(|| {
                rays.iter()
                    .filter_map(|ray| sphere.intersect(black_box(ray), 0.0, f32::INFINITY))
                    .count()
            })
        });
        group.bench_function(format!("sphere textbook, {name}"), |b| {
            b.iter(|| {
                rays.iter()
                    .filter_map(|ray| sphere.intersect_textbook(black_box(ray), 0.0, f32::INFINITY))
                    .count()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, intersectors);
criterion_main!(benches);
