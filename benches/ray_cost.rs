//! What one visit of a node of an implicit surface's tree costs, in plain
//! rays: the figure behind `raylab::render::NODE_VISITS_PER_RAY`, which
//! the render budgets count marching in. `cargo bench --bench ray_cost`.
//!
//! Two renders of one view, side by side, each the median of five: a grid
//! of spheres, and the same grid as implicit spheres under a displacement
//! so fine that every march spends its whole `march_steps` (two nodes a
//! tree). The time of a plain ray comes from the first, the time of a
//! node visit from the second's extra time over its evaluations.

use std::time::{Duration, Instant};

/// A grid of spheres that fills the view, so that most rays meet one.
const GRID: usize = 6;
const MARCH_STEPS: u32 = 2000;

fn scene(implicit: bool) -> raylab::Scene {
    let mut text = String::from(
        "background = [0.5, 0.6, 0.7]\nambient_light = [1.0, 1.0, 1.0]\n\
         [camera]\nposition = [0.0, 0.0, -10.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_degrees = 30.0\n\
         [render]\nwidth = 64\nheight = 48\nsamples = 1\n",
    );
    text += &format!("march_steps = {MARCH_STEPS}\n");
    for index in 0..GRID * GRID {
        let x = (index % GRID) as f32 - 2.5;
        let y = (index / GRID) as f32 - 2.5;
        let sphere = format!("sphere = {{ center = [{x}, {y}, 0.0], radius = 0.5 }}");
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

/// The median time of five renders, and the render's counts.
fn timed(scene: &raylab::Scene) -> (Duration, raylab::Rendered) {
    let chapter = raylab::chapters::LAST_CHAPTER;
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
    let (plain_time, plain) = timed(&scene(false));
    let (marched_time, marched) = timed(&scene(true));
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
}
