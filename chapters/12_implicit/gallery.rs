//! Chapter 12, surfaces without a formula, as `raylab check` judges it:
//! the reference passes both levels; its bug gallery (a step without the
//! Lipschitz factor, Newton without its bracket, a forward-difference
//! normal with `h = 1e-7`, an absolute tolerance, a loop with no budget,
//! a march that stops where it starts)
//! fails chapter 12 on the case that names the mistake; a correct
//! alternative (the other tetrahedron) passes.

use raylab::check::{ChapterVerdict, CheckOptions, Status, check_chapter};
use raylab::course::Chapters;
use raylab::shapes::{Bracket, Implicit, NormalMethod};
use raylab::{Ray, Reference, Vec3};

fn options() -> CheckOptions {
    CheckOptions {
        failures_dir: std::env::temp_dir().join("raylab-chapter-12-tests"),
        write_images: false,
        forbid_answer_key: false,
        fresh: None,
    }
}

/// Checks chapter 12 with `C` and asserts that it fails on checkpoint
/// `case`, with nothing earlier to blame.
fn assert_caught<C: Chapters>(case: &str) -> ChapterVerdict {
    let verdict = check_chapter::<C>(12, &options());
    let text = verdict.text();
    assert_eq!(verdict.status, Status::Fail, "{text}");
    assert_eq!(verdict.failing_case(), Some(case), "{text}");
    assert_eq!(verdict.needs, None, "{text}");
    verdict
}

#[test]
fn the_reference_passes_chapter_12_at_both_levels() {
    let verdict = check_chapter::<Reference>(12, &options());
    assert!(verdict.robust(), "{}", verdict.text());
}

/// The reference's march with the step and the stopping test given:
/// `step(radius, lipschitz)` is the distance moved, `near(radius, t)`
/// whether the point counts as on the surface, `budget` whether the step
/// budget and `t_max` stop it. It over-relaxes as the reference does
/// (the gap test and its fallback), so that each bug is the only one.
fn march(
    surface: &Implicit,
    ray: &Ray,
    (t_min, t_max): (f32, f32),
    step: fn(f32, f32) -> f32,
    near: fn(f32, f32, f32) -> bool,
    budget: bool,
) -> Option<f32> {
    let speed = ray.dir.length();
    let mut relaxation = surface.march().relaxation;
    let mut t = t_min;
    let mut last: Option<(f32, f32)> = None;
    let mut steps = 0;
    loop {
        if budget && steps >= surface.march().max_steps {
            return None;
        }
        steps += 1;
        let value = surface.distance(ray.at(t)).abs();
        let moved = step(value, surface.lipschitz());
        if let Some((last_t, last_moved)) = last
            && relaxation > 1.0
            && last_moved + moved < (t - last_t) * speed
        {
            relaxation = 1.0;
            t = last_t + last_moved / speed;
            last = None;
            continue;
        }
        if budget && !(t < t_max) {
            return None;
        }
        if near(value, t * speed, surface.march().tolerance) && t > t_min {
            return Some(t);
        }
        if budget && !value.is_finite() {
            return None;
        }
        last = Some((t, moved));
        t += relaxation * moved / speed;
    }
}

// ---------------------------------------------------------------------------
// The bug gallery.

/// Bug: the step is the function's value, as if every function were a
/// distance: over a bump, whose slope is up to `L` times a distance's, it
/// jumps past the surface.
struct StepWithoutLipschitz;
impl Chapters for StepWithoutLipschitz {
    fn sphere_trace(surface: &Implicit, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let step = |value: f32, _lipschitz: f32| value;
        let near = |value: f32, travelled: f32, tolerance: f32| value < tolerance * travelled;
        march(surface, ray, (t_min, t_max), step, near, true)
    }
}

#[test]
fn a_step_without_the_lipschitz_factor_is_caught() {
    assert_caught::<StepWithoutLipschitz>("march-divides-by-the-lipschitz-constant");
}

/// Bug: Newton's step taken wherever it goes, the bracket ignored.
struct NewtonWithoutBracket;
impl Chapters for NewtonWithoutBracket {
    fn newton_bracketed(
        g: &dyn Fn(f32) -> (f32, f32),
        bracket: Bracket,
        tolerance: f32,
        max_iterations: u32,
    ) -> f32 {
        let mut t = bracket.low;
        for _ in 0..max_iterations {
            let (value, slope) = g(t);
            let step = value / slope;
            t -= step;
            if !(step.abs() > tolerance) {
                break;
            }
        }
        t
    }
}

#[test]
fn newton_without_a_bracket_is_caught() {
    assert_caught::<NewtonWithoutBracket>("newton-step-out-of-the-bracket-bisects");
}

/// Bug: a forward difference with a step of `1e-7`, where `f32` spaces
/// the values 6e-8 apart: the difference is mostly rounding.
struct ForwardDifferenceTinyStep;
impl Chapters for ForwardDifferenceTinyStep {
    fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3 {
        if surface.march().normal == NormalMethod::Analytic {
            return Reference::implicit_normal(surface, point);
        }
        let h = 1e-7;
        let at = surface.distance(point);
        Vec3::new(
            surface.distance(point + h * Vec3::X) - at,
            surface.distance(point + h * Vec3::Y) - at,
            surface.distance(point + h * Vec3::Z) - at,
        )
        .normalize_or_zero()
    }
}

#[test]
fn a_forward_difference_with_a_tiny_step_is_caught() {
    assert_caught::<ForwardDifferenceTinyStep>("normal-central-on-a-torus");
}

/// Bug: the march stops where it starts when that point is already
/// within the cone: a hit at `t = t_min`, which the range excludes (a
/// march started at a box's entry, or at the surface a ray leaves).
struct StopsWhereItStarts;
impl Chapters for StopsWhereItStarts {
    fn sphere_trace(surface: &Implicit, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let radius = surface.distance(ray.at(t_min)).abs() / surface.lipschitz();
        if radius < surface.march().tolerance * t_min * ray.dir.length() {
            return Some(t_min);
        }
        Reference::sphere_trace(surface, ray, t_min, t_max)
    }
}

#[test]
fn a_march_that_stops_where_it_starts_is_caught() {
    assert_caught::<StopsWhereItStarts>("march-hits-only-past-t-min");
}

/// Bug: an absolute tolerance. Every checkpoint passes, but it is not the
/// cone the lesson asks for: the built-in scene's image differs, and at
/// 10,000 units the function's rounding exceeds it and the march never
/// stops (the hard case `intersect-far-small-sphere`).
struct AbsoluteTolerance;
impl Chapters for AbsoluteTolerance {
    fn sphere_trace(surface: &Implicit, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let step = |value: f32, lipschitz: f32| value / lipschitz;
        let near = |value: f32, _travelled: f32, tolerance: f32| value < tolerance;
        march(surface, ray, (t_min, t_max), step, near, true)
    }
}

#[test]
fn an_absolute_tolerance_fails_the_image() {
    let verdict = check_chapter::<AbsoluteTolerance>(12, &options());
    let text = verdict.text();
    assert_eq!(verdict.status, Status::Fail, "{text}");
    assert_eq!(verdict.failing_case(), None, "{text}");
    assert!(verdict.image.is_some_and(|image| !image.passed), "{text}");
    let hard = raylab::check::catalog::robustness(12);
    let far = hard
        .iter()
        .find(|case| case.name == "intersect-far-small-sphere")
        .expect("the case");
    assert!(
        matches!(
            far.run::<AbsoluteTolerance>(),
            raylab::check::Outcome::Fail { .. }
        ),
        "the far sphere is missed"
    );
}

/// Bug: a loop with neither a step budget nor `t_max`: on a miss, `t`
/// grows to infinity, the point becomes NaN, and it never ends (the
/// check's evaluation limit ends it).
struct NeverStops;
impl Chapters for NeverStops {
    fn sphere_trace(surface: &Implicit, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let step = |value: f32, lipschitz: f32| value / lipschitz;
        let near = |value: f32, travelled: f32, tolerance: f32| value < tolerance * travelled;
        march(surface, ray, (t_min, t_max), step, near, false)
    }
}

#[test]
fn a_loop_that_never_stops_on_a_miss_is_caught() {
    let verdict = assert_caught::<NeverStops>("march-beside-a-sphere-misses");
    assert!(
        verdict.text().contains("did not stop"),
        "{}",
        verdict.text()
    );
}

// ---------------------------------------------------------------------------
// Correct alternatives.

/// The other tetrahedron, corners `-k`: the same gradient, other roundings.
struct OtherTetrahedron;
impl Chapters for OtherTetrahedron {
    fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3 {
        if surface.march().normal != NormalMethod::Tetrahedron {
            return Reference::implicit_normal(surface, point);
        }
        let h = surface.march().normal_step;
        [
            Vec3::new(-1.0, 1.0, 1.0),
            Vec3::new(1.0, 1.0, -1.0),
            Vec3::new(1.0, -1.0, 1.0),
            Vec3::new(-1.0, -1.0, -1.0),
        ]
        .into_iter()
        .map(|corner| corner * surface.distance(point + h * corner))
        .sum::<Vec3>()
        .normalize_or_zero()
    }
}

#[test]
fn the_other_tetrahedron_passes() {
    let verdict = check_chapter::<OtherTetrahedron>(12, &options());
    assert!(verdict.robust(), "{}", verdict.text());
}
