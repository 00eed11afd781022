//! What one visit of a node of an implicit surface's tree and one
//! ray-primitive test cost, in plain rays: the figures behind
//! `raylab::render::NODE_VISITS_PER_RAY` and `TESTS_IN_A_PLAIN_RAY`, in
//! which the render budgets count marching and a stage without a tree of
//! boxes. `cargo bench --bench ray_cost`.
//!
//! Two renders of one view, side by side, each the median of five: a grid
//! of spheres, and the same grid as implicit spheres under a displacement
//! so fine that every march spends its whole `march_steps` (two nodes a
//! tree), both at the last chapter's stage, with its tree of boxes; then
//! the first, larger, at the first stage without a tree, where every ray
//! tests every sphere. The time of a plain ray comes from the first, the
//! time of a node visit from the second's extra time over its
//! evaluations, the time of a test from the third's over its tests.

use std::time::{Duration, Instant};

/// A grid of spheres that fills the view, so that most rays meet one.
const GRID: usize = 6;
const MARCH_STEPS: u32 = 2000;

fn scene(implicit: bool, grid: usize) -> raylab::Scene {
    let mut text = String::from(
        "background = [0.5, 0.6, 0.7]\nambient_light = [1.0, 1.0, 1.0]\n\
         [camera]\nposition = [0.0, 0.0, -10.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_degrees = 30.0\n\
         [render]\nwidth = 128\nheight = 96\nsamples = 1\n",
    );
    text += &format!("march_steps = {MARCH_STEPS}\n");
    let spacing = GRID as f32 / grid as f32;
    for index in 0..grid * grid {
        let x = ((index % grid) as f32 - (grid as f32 - 1.0) / 2.0) * spacing;
        let y = ((index / grid) as f32 - (grid as f32 - 1.0) / 2.0) * spacing;
        let radius = 0.5 * spacing;
        let sphere = format!("sphere = {{ center = [{x}, {y}, 0.0], radius = {radius} }}");
        let shape = if implicit {
            format!(
                "implicit = {{ displace = {{ amplitude = 0.01, frequency = 1e6, shape = {{ \
                 {sphere} }} }} }}"
            )
        } else {
            sphere
        };
        text += &format!(
            "[[objects]]\n{shape}\nmaterial = {{ color = [0.8, 0.3, 0.2], diffuse = 0.9 }}\n"
        );
    }
    raylab::Scene::parse(&text, "ray_cost").expect("the bench's scene parses")
}

/// The median time of five renders at `chapter`, and the render's counts.
fn timed(scene: &raylab::Scene, chapter: u8) -> (Duration, raylab::Rendered) {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..5 {
        let start = Instant::now();
        let rendered = raylab::render(scene, chapter, &scene.render, None).expect("renders");
        times.push(start.elapsed());
        last = Some(rendered);
    }
    times.sort();
    (times[2], last.expect("five renders"))
}

fn main() {
    let last = raylab::chapters::LAST_CHAPTER;
    let (plain_time, plain) = timed(&scene(false, GRID), last);
    let (marched_time, marched) = timed(&scene(true, GRID), last);
    let untreed = (1..=last)
        .find(|&chapter| {
            let effects = raylab::effects::Effects::for_chapter(chapter);
            effects.spheres && !effects.bvh
        })
        .expect("a stage with spheres and no tree");
    let many = 4 * GRID;
    let (tested_time, tested) = timed(&scene(false, many), untreed);
    let plain_rays = plain.rays.total() as f64;
    let per_ray = plain_time.as_secs_f64() / plain_rays;
    let rays = marched.rays.total() as f64;
    // Two nodes a tree: the displacement and its sphere.
    let visits = 2.0 * marched.rays.implicit_evaluations as f64;
    let per_visit = (marched_time.as_secs_f64() - rays * per_ray).max(0.0) / visits;
    println!(
        "plain: {plain_rays:.0} rays in {:.1} ms, {:.0} ns a ray",
        plain_time.as_secs_f64() * 1e3,
        per_ray * 1e9
    );
    println!(
        "marched: {rays:.0} rays, {visits:.2e} node visits in {:.1} ms, {:.2} ns a visit",
        marched_time.as_secs_f64() * 1e3,
        per_visit * 1e9
    );
    println!(
        "a plain ray takes as long as {:.1} node visits (the budget counts {})",
        per_ray / per_visit,
        raylab::render::NODE_VISITS_PER_RAY
    );
    let rays = tested.rays.total() as f64;
    let tests = rays * (many * many) as f64;
    let per_test = (tested_time.as_secs_f64() - rays * per_ray).max(0.0) / tests;
    println!(
        "untreed (chapter {untreed}): {rays:.0} rays, {tests:.2e} sphere tests in {:.1} ms, \
         {:.2} ns a test",
        tested_time.as_secs_f64() * 1e3,
        per_test * 1e9
    );
    println!(
        "a plain ray takes as long as {:.1} tests (the budget counts {})",
        per_ray / per_test,
        raylab::render::TESTS_IN_A_PLAIN_RAY
    );
}
