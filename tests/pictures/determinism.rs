//! The image depends only on the scene, the settings and the pixel: never on
//! the number of threads or the order they finish in.

fn render_on(
    threads: usize,
    chapter: u8,
    samples: u32,
    sampling: raylab::Sampling,
) -> raylab::Rendered {
    let scene = raylab::builtin::scene(chapter).expect("built-in scene");
    let settings = raylab::RenderSettings {
        width: 96,
        height: 72,
        samples,
        sampling,
        ..scene.render
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    pool.install(|| raylab::render(&scene, chapter, &settings, None).expect("renders"))
}

#[test]
fn one_thread_and_many_give_identical_images() {
    for (samples, sampling) in [
        (4, raylab::Sampling::Jittered),
        (5, raylab::Sampling::Random),
    ] {
        let single = render_on(1, 8, samples, sampling);
        for threads in [2, 3, 8] {
            let many = render_on(threads, 8, samples, sampling);
            assert!(
                single.rgb == many.rgb,
                "{threads} threads, {samples} {sampling:?} samples"
            );
            assert_eq!(single.rays, many.rays);
        }
    }
}

#[test]
fn the_seed_changes_jittered_samples_and_nothing_else_does() {
    let scene = raylab::builtin::scene(7).expect("built-in scene");
    let base = raylab::RenderSettings {
        width: 64,
        height: 48,
        ..scene.render
    };
    let first = raylab::render(&scene, 7, &base, None).expect("renders");
    let again = raylab::render(&scene, 7, &base, None).expect("renders");
    assert!(first.rgb == again.rgb);
    let reseeded = raylab::RenderSettings { seed: 1, ..base };
    assert!(
        first.rgb
            != raylab::render(&scene, 7, &reseeded, None)
                .expect("renders")
                .rgb
    );
}
