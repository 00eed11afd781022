//! One render of each chapter's built-in scene at 80x60, with the scene's own
//! samples and depth. `cargo bench --bench chapters`.

use criterion::{Criterion, criterion_group, criterion_main};

fn chapters(c: &mut Criterion) {
    let mut group = c.benchmark_group("render 80x60");
    group.sample_size(10);
    for chapter in 1..=raylab::chapters::LAST_CHAPTER {
        let scene = raylab::builtin::scene(chapter).expect("built-in scene");
        let settings = raylab::RenderSettings {
            width: 80,
            height: 60,
            ..scene.render
        };
        group.bench_function(format!("chapter {chapter}"), |b| {
            b.iter(|| {
                raylab::render(&scene, chapter, &settings, None)
                    .expect("renders")
                    .rays
                    .total()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, chapters);
criterion_main!(benches);
