//! Render-level robustness: scenes built to provoke shadow acne (a floor
//! that is a sphere of radius 1e5, a ball resting on a plane, two touching
//! balls) render with no shadow ray hitting the surface it left and no NaN
//! sample, while the same scenes with a naive fixed offset do show acne, so
//! these tests can fail.
//!
//! Acne is counted twice: by the renderer (`RayCounts::self_shadow_hits`,
//! which only sees the first blocker in scene order) and by an independent
//! log here (see [`AcneLog`]).

use raylab::scene::OffsetRule;
use raylab::{Ray, RayCounts, RayKind, RayLog, RenderSettings, Scene, Shape, Stage, nearest_hit};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

/// A ball resting on a floor that is a sphere of radius 1e5 (its top at
/// y = 0), and two balls touching each other, one of them glass.
const HUGE_FLOOR: &str = r#"
background = [0.55, 0.7, 0.9]
[camera]
position = [0.0, 1.5, -6.0]
look_at = [0.0, 0.8, 0.0]
[[lights]]
position = [-4.0, 6.0, -3.0]
[[objects]]
name = "floor"
sphere = { center = [0.0, -100000.0, 0.0], radius = 100000.0 }
material = { color = [0.9, 0.9, 0.85], checker = { color = [0.2, 0.2, 0.25], size = 1.0 } }
[[objects]]
name = "resting ball"
sphere = { center = [-1.5, 1.0, 0.5], radius = 1.0 }
material = { color = [0.8, 0.2, 0.1], specular = 0.5, reflectivity = 0.3 }
[[objects]]
name = "left of the touching pair"
sphere = { center = [0.6, 0.7, -0.5], radius = 0.7 }
material = { color = [0.1, 0.3, 0.85], specular = 0.5 }
[[objects]]
name = "right of the touching pair"
sphere = { center = [2.0, 0.7, -0.5], radius = 0.7 }
material = { color = [0.9, 0.9, 0.9], transparency = 0.8, ior = 1.5, specular = 0.5 }
"#;

/// The same arrangement on a plane floor, tilted slightly so that its
/// projected points are not exact, far from the origin (coordinates near
/// 1000, where one ulp is 6e-5).
const PLANE_FLOOR: &str = r#"
background = [0.55, 0.7, 0.9]
[camera]
position = [1000.0, 1001.5, 994.0]
look_at = [1000.0, 1000.8, 1000.0]
[[lights]]
position = [996.0, 1006.0, 997.0]
[[objects]]
name = "floor"
plane = { point = [1000.0, 1000.0, 1000.0], normal = [0.01, 1.0, 0.02] }
material = { color = [0.9, 0.9, 0.85], checker = { color = [0.2, 0.2, 0.25], size = 1.0 } }
[[objects]]
name = "resting ball"
sphere = { center = [998.5, 1001.0, 1000.5], radius = 1.0 }
material = { color = [0.8, 0.2, 0.1], specular = 0.5, reflectivity = 0.3 }
[[objects]]
name = "left of the touching pair"
sphere = { center = [1000.6, 1000.7, 999.5], radius = 0.7 }
material = { color = [0.1, 0.3, 0.85], specular = 0.5 }
[[objects]]
name = "right of the touching pair"
sphere = { center = [1002.0, 1000.7, 999.5], radius = 0.7 }
material = { color = [0.9, 0.9, 0.9], transparency = 0.8, ior = 1.5, specular = 0.5 }
"#;

/// Independently of the tracer's own count, finds shadow rays that hit
/// the surface they start on. The tracer lights a hit right after casting
/// the ray that found it, so every shadow ray belongs to the hit of the last
/// non-shadow ray cast; this log finds that hit again with `nearest_hit` and
/// asks the shape it is on (not just the first blocker in scene order)
/// whether it blocks the shadow ray. Going into a sphere is the one way a
/// shadow ray truly meets its own surface (decided in `f64`); any other
/// such hit is acne.
struct AcneLog<'a> {
    shapes: &'a [Shape],
    lit_object: Option<usize>,
    self_hits: u64,
}

impl RayLog for AcneLog<'_> {
    fn cast(&mut self, kind: RayKind, ray: &Ray, t_min: f32, t_max: f32) {
        if kind != RayKind::Shadow {
            self.lit_object = nearest_hit(self.shapes, ray, t_min, t_max).map(|hit| hit.object);
            return;
        }
        let object = self.lit_object.expect("a shadow ray follows a hit");
        let shape = &self.shapes[object];
        let into_itself = match shape {
            Shape::Sphere(s) => {
                let outward = ray.origin.as_dvec3() - s.center().as_dvec3();
                ray.dir.as_dvec3().dot(outward) < 0.0
            }
            Shape::Plane(_) => false,
        };
        if !into_itself && shape.intersect(ray, t_min, t_max).is_some() {
            self.self_hits += 1;
        }
    }
}

struct Outcome {
    counts: RayCounts,
    independent_self_hits: u64,
}

fn render(text: &str, chapter: u8, rule: OffsetRule, epsilon: f32) -> Outcome {
    let scene = Scene::parse(text, "robustness scene").expect("the test scene is valid");
    let settings = RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        ray_offset: rule,
        fixed_epsilon: epsilon,
        ..scene.render
    };
    let stage = Stage::new(&scene, chapter, settings).expect("valid settings");
    let mut log = AcneLog {
        shapes: stage.shapes(),
        lit_object: None,
        self_hits: 0,
    };
    let mut tracer = stage.tracer(Some(&mut log));
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            tracer.pixel(x, y);
        }
    }
    let counts = tracer.counts();
    Outcome {
        counts,
        independent_self_hits: log.self_hits,
    }
}

fn assert_clean(name: &str, text: &str, chapter: u8) {
    let outcome = render(text, chapter, OffsetRule::Scaled, 0.0);
    let counts = outcome.counts;
    println!("{name}, chapter {chapter}, scaled offset: {counts:?}");
    assert!(
        counts.shadow > 1000,
        "{name}: too few shadow rays to mean anything"
    );
    assert_eq!(counts.self_shadow_hits, 0, "{name}: renderer counted acne");
    assert_eq!(
        outcome.independent_self_hits, 0,
        "{name}: independent acne count"
    );
    assert_eq!(counts.non_finite_samples, 0, "{name}: NaN samples");
}

fn assert_acne(name: &str, text: &str, epsilon: f32) {
    let outcome = render(text, 4, OffsetRule::Fixed, epsilon);
    println!(
        "{name}, chapter 4, fixed epsilon {epsilon}: {:?}, independent count {}",
        outcome.counts, outcome.independent_self_hits
    );
    assert!(
        outcome.counts.self_shadow_hits > 0,
        "{name}: a fixed epsilon of {epsilon} should show acne"
    );
    assert!(outcome.independent_self_hits >= outcome.counts.self_shadow_hits);
}

#[test]
fn huge_floor_sphere_renders_without_acne_or_nan() {
    assert_clean("huge floor", HUGE_FLOOR, 4);
    // Every effect on (reflection, glass), where NaN would come from.
    assert_clean("huge floor", HUGE_FLOOR, 8);
}

#[test]
fn plane_floor_far_from_the_origin_renders_without_acne_or_nan() {
    assert_clean("plane floor", PLANE_FLOOR, 4);
    assert_clean("plane floor", PLANE_FLOOR, 8);
}

#[test]
fn a_naive_offset_shows_acne_in_the_same_scenes() {
    // No offset at all: the projected hit point is inside the surface about
    // half the time.
    assert_acne("huge floor", HUGE_FLOOR, 0.0);
    assert_acne("plane floor", PLANE_FLOOR, 0.0);
    // The default fixed epsilon is far below the rounding of a point on a
    // sphere of radius 1e5 (about 6e-3).
    assert_acne("huge floor", HUGE_FLOOR, 1e-4);
}
