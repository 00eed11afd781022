//! Chapter 12, surfaces without a formula, as `raylab check` judges it:
//! the reference passes both levels; its bug gallery fails chapter 12 on
//! the case that names the mistake, one variant of the reference for each
//! clause of the four functions' contract (docs/course.md lists them);
//! correct alternatives (the other tetrahedron, a march over the whole ray
//! rather than the surface's box) pass.

use raylab::check::planted::{self, Plant, Planted, plant};
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
        ..Default::default()
    }
}

/// Checks chapter 12 with `C` and asserts that it fails on checkpoint
/// `case`, with nothing earlier to blame.
fn assert_caught<C: Plant>(case: &str) -> ChapterVerdict {
    planted::assert_caught::<C>(12, case, &options())
}

/// Checks chapter 12 with `C` and asserts that it passes every checkpoint
/// and its image but fails the hard case `case` first: correct, not yet
/// robust.
fn assert_caught_by_hard_case<C: Plant>(case: &str) {
    planted::assert_caught_by_hard_case::<C>(12, case, &options());
}

fn assert_passes_both_levels<C: Plant>() {
    planted::with::<C, _>(|| {
        let verdict = check_chapter::<Planted>(12, &options());
        assert!(verdict.robust(), "{}", verdict.text());
    })
}

#[test]
fn the_reference_passes_chapter_12_at_both_levels() {
    assert_passes_both_levels::<Reference>();
}

// ---------------------------------------------------------------------------
// sphere_trace

/// One mistake in the reference's march, or none.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum MarchSlip {
    NoSlip,
    /// The step is the function's value, as if every function were a
    /// distance (`L` taken for 1).
    StepIgnoresLipschitz,
    /// Half of each safe step: never past the surface, but slow.
    HalfSteps,
    /// `t` moved by the distance stepped, as if the direction were unit.
    StepInDistance,
    /// The step is `f / L` with its sign: from inside, backwards.
    SignedStep,
    /// No stop at `t_max`.
    IgnoresTMax,
    /// Neither a step budget nor `t_max`: on a miss, `t` grows to infinity
    /// and the point becomes NaN (the check's evaluation limit ends it).
    NoBudgetNorTMax,
    /// 256 steps, whatever the settings say.
    BudgetOf256,
    /// The cone `tolerance t`, without the direction's length.
    ConeWithoutLength,
    /// An absolute tolerance, `|f| / L < tolerance`.
    AbsoluteTolerance,
    /// An over-relaxed step never undone.
    NoStepBack,
    /// Balls that only touch taken for overlapping: `r_last + r < step`.
    TouchingBallsOverlap,
    /// After a step back, relaxed steps again.
    RelaxesAgain,
    /// The setting's relaxation ignored: safe steps only.
    NeverRelaxes,
    /// No stop on a NaN radius, and the end of the range tested as
    /// `t >= t_max`, which a NaN `t` never meets: a broken ray spends the
    /// whole budget.
    NanRunsToTheBudget,
}

/// The reference's march with `slip` made, and nothing else changed.
fn march(surface: &Implicit, ray: &Ray, t_min: f32, t_max: f32, slip: MarchSlip) -> Option<f32> {
    use MarchSlip::*;
    let march = surface.march();
    let lipschitz = if slip == StepIgnoresLipschitz {
        1.0
    } else {
        surface.lipschitz()
    };
    let speed = ray.dir.length();
    // How far in the scene's units one unit of t goes.
    let per_t = if slip == StepInDistance { 1.0 } else { speed };
    let budget = match slip {
        BudgetOf256 => 256,
        NoBudgetNorTMax => u32::MAX,
        _ => march.max_steps,
    };
    let mut relaxation = if slip == NeverRelaxes {
        1.0
    } else {
        march.relaxation
    };
    let mut t = t_min;
    let mut last: Option<(f32, f32)> = None;
    for _ in 0..budget {
        let value = surface.distance(ray.at(t));
        let value = if slip == SignedStep {
            value
        } else {
            value.abs()
        };
        let radius = value / lipschitz;
        if let Some((last_t, last_radius)) = last
            && relaxation > 1.0
            && slip != NoStepBack
        {
            let travelled = (t - last_t) * per_t;
            let gap = if slip == TouchingBallsOverlap {
                last_radius + radius < travelled
            } else {
                last_radius + radius <= travelled
            };
            if gap {
                if slip != RelaxesAgain {
                    relaxation = 1.0;
                }
                t = last_t + last_radius / per_t;
                last = None;
                continue;
            }
        }
        let past_the_end = if slip == NanRunsToTheBudget {
            t >= t_max
        } else {
            !(t < t_max)
        };
        if past_the_end && !matches!(slip, IgnoresTMax | NoBudgetNorTMax) {
            return None;
        }
        let cone = match slip {
            ConeWithoutLength => march.tolerance * t,
            AbsoluteTolerance => march.tolerance,
            _ => march.tolerance * t * speed,
        };
        if radius < cone && t > t_min {
            return Some(t);
        }
        if (!radius.is_finite() || !(speed > 0.0))
            && !matches!(slip, NanRunsToTheBudget | NoBudgetNorTMax)
        {
            return None;
        }
        last = Some((t, radius));
        let share = if slip == HalfSteps { 0.5 } else { 1.0 };
        t += share * relaxation * radius / per_t;
    }
    None
}

/// A `Chapters` whose `sphere_trace` is the reference with one slip.
macro_rules! march_variant {
    ($name:ident, $slip:ident) => {
        struct $name;
        plant! {
            $name;
            fn sphere_trace(surface: &Implicit, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
                march(surface, ray, t_min, t_max, MarchSlip::$slip)
            }
        }
    };
}

march_variant!(MarchCopy, NoSlip);
march_variant!(StepWithoutLipschitz, StepIgnoresLipschitz);
march_variant!(HalfSteps, HalfSteps);
march_variant!(StepInDistance, StepInDistance);
march_variant!(SignedStep, SignedStep);
march_variant!(MarchPastTMax, IgnoresTMax);
march_variant!(NeverStops, NoBudgetNorTMax);
march_variant!(BudgetOf256, BudgetOf256);
march_variant!(ConeWithoutLength, ConeWithoutLength);
march_variant!(AbsoluteTolerance, AbsoluteTolerance);
march_variant!(NoStepBack, NoStepBack);
march_variant!(TouchingBallsOverlap, TouchingBallsOverlap);
march_variant!(RelaxesAgain, RelaxesAgain);
march_variant!(NeverRelaxes, NeverRelaxes);
march_variant!(NanRunsToTheBudget, NanRunsToTheBudget);

#[test]
fn the_march_copy_without_a_slip_is_the_reference() {
    assert_passes_both_levels::<MarchCopy>();
}

#[test]
fn a_step_without_the_lipschitz_factor_is_caught() {
    assert_caught::<StepWithoutLipschitz>("march-divides-by-the-lipschitz-constant");
}

#[test]
fn steps_shorter_than_the_distance_are_caught() {
    assert_caught::<HalfSteps>("march-toward-a-sphere-along-its-axis");
}

#[test]
fn t_moved_by_the_distance_stepped_is_caught() {
    assert_caught::<StepInDistance>("march-with-a-direction-not-unit");
}

#[test]
fn a_step_with_the_sign_of_f_is_caught() {
    assert_caught::<SignedStep>("march-from-inside-finds-the-way-out");
}

#[test]
fn a_march_past_t_max_is_caught() {
    assert_caught::<MarchPastTMax>("march-stops-past-t-max");
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

#[test]
fn a_budget_not_the_settings_is_caught() {
    assert_caught::<BudgetOf256>("march-gives-up-after-its-budget");
}

#[test]
fn a_cone_without_the_directions_length_is_caught() {
    assert_caught::<ConeWithoutLength>("march-cone-in-distance");
}

/// An absolute tolerance passes every checkpoint, but it is not the cone
/// the lesson asks for: the built-in scene's image differs, and at 10,000
/// units the function's rounding exceeds it and the march never stops
/// (the hard case `intersect-far-small-sphere`).
#[test]
fn an_absolute_tolerance_fails_the_image() {
    let verdict = planted::check_chapter::<AbsoluteTolerance>(12, &options());
    let text = verdict.text();
    assert_eq!(verdict.status, Status::Fail, "{text}");
    assert_eq!(verdict.failing_case(), None, "{text}");
    assert!(verdict.image.is_some_and(|image| !image.passed), "{text}");
    let hard = raylab::check::by_chapter::robustness(12);
    let far = hard
        .iter()
        .find(|case| case.name == "intersect-far-small-sphere")
        .expect("the case");
    assert!(
        matches!(
            planted::with::<AbsoluteTolerance, _>(|| far.run::<Planted>()),
            raylab::check::Outcome::Fail { .. }
        ),
        "the far sphere is missed"
    );
}

#[test]
fn an_over_relaxed_step_never_undone_is_caught() {
    assert_caught::<NoStepBack>("march-over-relaxed-steps-back");
}

#[test]
fn touching_balls_taken_for_overlapping_are_caught() {
    assert_caught::<TouchingBallsOverlap>("march-over-relaxed-head-on");
}

#[test]
fn relaxing_again_after_a_step_back_is_caught() {
    assert_caught::<RelaxesAgain>("march-over-relaxed-relaxes-no-more");
}

#[test]
fn a_march_that_never_relaxes_is_caught() {
    assert_caught::<NeverRelaxes>("march-over-relaxed-keeps-relaxing");
}

#[test]
fn a_march_on_through_nan_is_caught_by_a_hard_case() {
    assert_caught_by_hard_case::<NanRunsToTheBudget>("intersect-nan-direction");
}

/// The march stops where it starts when that point is already within the
/// cone: a hit at `t = t_min`, which the range excludes (a march started
/// at a box's entry, or at the surface a ray leaves).
struct StopsWhereItStarts;
plant! {
    StopsWhereItStarts;
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

// ---------------------------------------------------------------------------
// newton_bracketed

/// One mistake in the reference's safeguarded Newton, or none.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum NewtonSlip {
    NoSlip,
    /// The first iterate from the bracket's middle, not its low end.
    StartsAtTheMiddle,
    /// A step past the high end bisects; one below the low end is taken.
    BisectsOnlyAbove,
    /// The halves never dropped: Newton kept to the first bracket, and
    /// its midpoint taken for a step that leaves it.
    NeverShrinks,
    /// The half with the sign change dropped.
    KeepsTheWrongHalf,
    /// No stop on a small step: every iteration is made.
    IgnoresTolerance,
    /// No stop where `g` is exactly 0.
    NoZeroStop,
    /// Iterations until the step is small, however many are allowed.
    IgnoresMaxIterations,
    /// The bracket's midpoint returned, not the last point.
    ReturnsTheMidpoint,
    /// Newton's first step, then bisection only.
    NewtonOnceThenBisects,
}

/// The reference's `newton_bracketed` with `slip` made.
fn newton(
    g: &dyn Fn(f32) -> (f32, f32),
    bracket: Bracket,
    tolerance: f32,
    max_iterations: u32,
    slip: NewtonSlip,
) -> f32 {
    use NewtonSlip::*;
    let (mut low, mut high) = (bracket.low, bracket.high);
    let middle = |low: f32, high: f32| 0.5 * (low + high);
    let (mut t, low_positive, (mut value, mut slope)) = if slip == StartsAtTheMiddle {
        let low_positive = g(low).0 > 0.0;
        let t = middle(low, high);
        (t, low_positive, g(t))
    } else {
        let (value, slope) = g(low);
        (low, value > 0.0, (value, slope))
    };
    let iterations = if slip == IgnoresMaxIterations {
        1000
    } else {
        max_iterations
    };
    for iteration in 0..iterations {
        if value == 0.0 && slip != NoZeroStop {
            break;
        }
        let newton = t - value / slope;
        let inside = match slip {
            BisectsOnlyAbove => !(newton > high),
            NeverShrinks => newton >= bracket.low && newton <= bracket.high,
            _ => newton >= low && newton <= high,
        };
        let next = if inside && !(slip == NewtonOnceThenBisects && iteration > 0) {
            newton
        } else if slip == NeverShrinks {
            middle(bracket.low, bracket.high)
        } else {
            middle(low, high)
        };
        let step = next - t;
        t = next;
        (value, slope) = g(t);
        let same_side = (value > 0.0) == low_positive;
        match slip {
            NeverShrinks => {}
            KeepsTheWrongHalf if same_side => high = t,
            KeepsTheWrongHalf => low = t,
            _ if same_side => low = t,
            _ => high = t,
        }
        if step.abs() <= tolerance && slip != IgnoresTolerance {
            break;
        }
    }
    if slip == ReturnsTheMidpoint {
        middle(low, high)
    } else {
        t
    }
}

/// A `Chapters` whose `newton_bracketed` is the reference with one slip.
macro_rules! newton_variant {
    ($name:ident, $slip:ident) => {
        struct $name;
        plant! {
            $name;
            fn newton_bracketed(
                g: &dyn Fn(f32) -> (f32, f32),
                bracket: Bracket,
                tolerance: f32,
                max_iterations: u32,
            ) -> f32 {
                newton(g, bracket, tolerance, max_iterations, NewtonSlip::$slip)
            }
        }
    };
}

newton_variant!(NewtonCopy, NoSlip);
newton_variant!(StartsAtTheMiddle, StartsAtTheMiddle);
newton_variant!(BisectsOnlyAbove, BisectsOnlyAbove);
newton_variant!(NeverShrinks, NeverShrinks);
newton_variant!(KeepsTheWrongHalf, KeepsTheWrongHalf);
newton_variant!(IgnoresTolerance, IgnoresTolerance);
newton_variant!(NoZeroStop, NoZeroStop);
newton_variant!(IgnoresMaxIterations, IgnoresMaxIterations);
newton_variant!(ReturnsTheMidpoint, ReturnsTheMidpoint);
newton_variant!(NewtonOnceThenBisects, NewtonOnceThenBisects);

#[test]
fn the_newton_copy_without_a_slip_is_the_reference() {
    assert_passes_both_levels::<NewtonCopy>();
}

/// Newton's step taken wherever it goes, the bracket ignored.
struct NewtonWithoutBracket;
plant! {
    NewtonWithoutBracket;
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

#[test]
fn newton_started_at_the_middle_is_caught() {
    assert_caught::<StartsAtTheMiddle>("newton-first-iterate-on-a-torus-ray");
}

#[test]
fn a_step_below_the_bracket_taken_is_caught() {
    assert_caught::<BisectsOnlyAbove>("newton-step-below-the-bracket-bisects");
}

#[test]
fn a_bracket_that_never_shrinks_is_caught() {
    assert_caught::<NeverShrinks>("newton-bracket-only-shrinks");
}

#[test]
fn the_wrong_half_kept_is_caught() {
    assert_caught::<KeepsTheWrongHalf>("newton-doubles-its-digits");
}

#[test]
fn newton_that_ignores_its_tolerance_is_caught() {
    assert_caught::<IgnoresTolerance>("newton-stops-when-its-step-is-small");
}

#[test]
fn newton_that_goes_on_from_a_zero_is_caught() {
    assert_caught::<NoZeroStop>("newton-zero-at-a-flat-low-end");
}

#[test]
fn newton_that_ignores_its_iterations_is_caught() {
    assert_caught::<IgnoresMaxIterations>("newton-first-iterate-on-a-torus-ray");
}

#[test]
fn the_brackets_midpoint_returned_is_caught() {
    assert_caught::<ReturnsTheMidpoint>("newton-first-iterate-on-a-torus-ray");
}

#[test]
fn bisection_after_the_first_step_is_caught() {
    assert_caught::<NewtonOnceThenBisects>("newton-doubles-its-digits");
}

// ---------------------------------------------------------------------------
// implicit_normal

/// A forward difference with a step of `1e-7`, where `f32` spaces the
/// values 6e-8 apart: the difference is mostly rounding.
struct ForwardDifferenceTinyStep;
plant! {
    ForwardDifferenceTinyStep;
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

/// Central differences with `h`, made unit.
fn central(surface: &Implicit, point: Vec3, h: f32) -> Vec3 {
    let along =
        |axis: Vec3| surface.distance(point + h * axis) - surface.distance(point - h * axis);
    Vec3::new(along(Vec3::X), along(Vec3::Y), along(Vec3::Z)).normalize_or_zero()
}

/// The lesson's tetrahedron with `h`, made unit.
fn tetrahedron(surface: &Implicit, point: Vec3, h: f32) -> Vec3 {
    [
        Vec3::new(1.0, -1.0, -1.0),
        Vec3::new(-1.0, -1.0, 1.0),
        Vec3::new(-1.0, 1.0, -1.0),
        Vec3::new(1.0, 1.0, 1.0),
    ]
    .into_iter()
    .map(|corner| corner * surface.distance(point + h * corner))
    .sum::<Vec3>()
    .normalize_or_zero()
}

/// Central differences whatever the settings name.
struct AlwaysCentral;
plant! {
    AlwaysCentral;
    fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3 {
        central(surface, point, surface.march().normal_step)
    }
}

#[test]
fn central_differences_for_every_method_are_caught() {
    assert_caught::<AlwaysCentral>("normal-analytic-ignores-the-step");
}

/// The analytic gradient whatever the settings name.
struct AlwaysAnalytic;
plant! {
    AlwaysAnalytic;
    fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3 {
        surface.gradient(point).normalize_or_zero()
    }
}

#[test]
fn the_gradient_for_every_method_is_caught() {
    assert_caught::<AlwaysAnalytic>("normal-central-with-a-wide-step");
}

/// Central differences with `h = 0.001`, whatever `normal_step` says.
struct CentralFixedStep;
plant! {
    CentralFixedStep;
    fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3 {
        if surface.march().normal != NormalMethod::Central {
            return Reference::implicit_normal(surface, point);
        }
        central(surface, point, 1e-3)
    }
}

#[test]
fn central_differences_with_a_step_of_their_own_are_caught() {
    assert_caught::<CentralFixedStep>("normal-central-with-a-wide-step");
}

/// The tetrahedron with `h = 0.001`, whatever `normal_step` says.
struct TetrahedronFixedStep;
plant! {
    TetrahedronFixedStep;
    fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3 {
        if surface.march().normal != NormalMethod::Tetrahedron {
            return Reference::implicit_normal(surface, point);
        }
        tetrahedron(surface, point, 1e-3)
    }
}

#[test]
fn a_tetrahedron_with_a_step_of_its_own_is_caught() {
    assert_caught::<TetrahedronFixedStep>("normal-tetrahedron-with-a-wide-step");
}

/// Central differences where the tetrahedron is asked.
struct TetrahedronAsCentral;
plant! {
    TetrahedronAsCentral;
    fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3 {
        if surface.march().normal != NormalMethod::Tetrahedron {
            return Reference::implicit_normal(surface, point);
        }
        central(surface, point, surface.march().normal_step)
    }
}

#[test]
fn central_differences_for_the_tetrahedron_are_caught() {
    assert_caught::<TetrahedronAsCentral>("normal-tetrahedron-with-a-wide-step");
}

/// The analytic gradient as it comes, not made unit (a distance's gradient
/// is unit already; a bound's is not).
struct GradientNotMadeUnit;
plant! {
    GradientNotMadeUnit;
    fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3 {
        if surface.march().normal != NormalMethod::Analytic {
            return Reference::implicit_normal(surface, point);
        }
        surface.gradient(point)
    }
}

#[test]
fn a_gradient_not_made_unit_is_caught() {
    assert_caught::<GradientNotMadeUnit>("normal-analytic-made-unit");
}

/// The other tetrahedron, corners `-k`: the same gradient, other roundings,
/// and at a wide step a blur that leans the other way.
struct OtherTetrahedron;
plant! {
    OtherTetrahedron;
    fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3 {
        if surface.march().normal != NormalMethod::Tetrahedron {
            return Reference::implicit_normal(surface, point);
        }
        -tetrahedron(surface, point, -surface.march().normal_step)
    }
}

#[test]
fn the_other_tetrahedron_passes() {
    assert_passes_both_levels::<OtherTetrahedron>();
}

// ---------------------------------------------------------------------------
// intersect_implicit

/// One mistake in the reference's `intersect_implicit`, or a correct
/// alternative to it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum IntersectSlip {
    NoSlip,
    /// The march over the whole ray, `t_min` to `t_max`, not clipped to
    /// the surface's box: a correct alternative (the box is a saving).
    WholeRay,
    /// The march's answer, never refined.
    NoNewton,
    /// Newton whatever the setting `newton` says.
    NewtonAlways,
    /// The search for the bracket goes on where `|g|` grows.
    CreepsOnRegardless,
    /// No hit when no bracket closes.
    NoHitWithoutABracket,
    /// The march from `t = 0` rather than `t_min`.
    IgnoresTMin,
    /// No limit at `t_max`.
    IgnoresTMax,
    /// The search creeps by the cone's width in distance,
    /// `tolerance t |d|`, taken for a step in `t`.
    CreepsByDistance,
}

/// The reference's `intersect_implicit` with `slip` made.
fn intersect<C: Chapters>(
    surface: &Implicit,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    slip: IntersectSlip,
) -> Option<f32> {
    use IntersectSlip::*;
    let t_min = if slip == IgnoresTMin { 0.0 } else { t_min };
    let t_max = if slip == IgnoresTMax {
        f32::INFINITY
    } else {
        t_max
    };
    let (enter, leave) = if slip == WholeRay {
        (t_min, t_max)
    } else {
        surface.span(ray, t_min, t_max)?
    };
    let near = C::sphere_trace(surface, ray, enter, leave)?;
    let newton = surface.march().newton || slip == NewtonAlways;
    if !newton || slip == NoNewton {
        return Some(near);
    }
    let g = |t: f32| {
        let point = ray.at(t);
        (
            surface.distance(point),
            surface.gradient(point).dot(ray.dir),
        )
    };
    let cone = match slip {
        CreepsByDistance => surface.march().tolerance * near * ray.dir.length(),
        _ => surface.march().tolerance * near,
    };
    let (mut low, mut at_low) = (near, surface.distance(ray.at(near)));
    for _ in 0..32 {
        if at_low == 0.0 {
            return Some(low);
        }
        let high = (low + cone).min(leave);
        let at_high = surface.distance(ray.at(high));
        if (at_low > 0.0) != (at_high > 0.0) {
            let bracket = Bracket { low, high };
            let t = C::newton_bracketed(&g, bracket, 2.0 * f32::EPSILON * high, 16);
            return (t < t_max).then_some(t);
        }
        if !(at_high.abs() < at_low.abs()) && slip != CreepsOnRegardless {
            break;
        }
        (low, at_low) = (high, at_high);
    }
    if slip == NoHitWithoutABracket {
        return None;
    }
    Some(near)
}

/// A `Chapters` whose `intersect_implicit` is the reference with one slip.
macro_rules! intersect_variant {
    ($name:ident, $slip:ident) => {
        struct $name;
        plant! {
            $name;
            fn intersect_implicit(
                surface: &Implicit,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<f32> {
                intersect::<Planted>(surface, ray, t_min, t_max, IntersectSlip::$slip)
            }
        }
    };
}

intersect_variant!(IntersectCopy, NoSlip);
intersect_variant!(WholeRay, WholeRay);
intersect_variant!(NoNewton, NoNewton);
intersect_variant!(NewtonAlways, NewtonAlways);
intersect_variant!(CreepsOnRegardless, CreepsOnRegardless);
intersect_variant!(NoHitWithoutABracket, NoHitWithoutABracket);
intersect_variant!(IntersectFromZero, IgnoresTMin);
intersect_variant!(IntersectPastTMax, IgnoresTMax);
intersect_variant!(CreepsByDistance, CreepsByDistance);

#[test]
fn the_intersect_copy_without_a_slip_is_the_reference() {
    assert_passes_both_levels::<IntersectCopy>();
}

/// The lesson's march answer stands where no bracket closes, so a march
/// over the whole ray, which stops in its cone somewhere else than one
/// started at the box, is right: `intersect-far-small-sphere` accepts it.
#[test]
fn a_march_over_the_whole_ray_passes_both_levels() {
    assert_passes_both_levels::<WholeRay>();
}

/// Head-on, the march lands on the torus exactly (its function is a
/// distance); the coarse march is where Newton must refine.
#[test]
fn a_march_never_refined_is_caught() {
    assert_caught::<NoNewton>("intersect-refines-a-coarse-march");
}

#[test]
fn newton_against_the_setting_is_caught() {
    assert_caught::<NewtonAlways>("intersect-without-newton-stops-short");
}

#[test]
fn a_search_that_creeps_on_where_g_grows_is_caught() {
    assert_caught::<CreepsOnRegardless>("intersect-thinner-than-the-cone");
}

#[test]
fn no_hit_where_no_bracket_closes_is_caught() {
    assert_caught::<NoHitWithoutABracket>("intersect-thinner-than-the-cone");
}

#[test]
fn an_intersection_from_zero_is_caught() {
    assert_caught::<IntersectFromZero>("intersect-from-the-surface-outward");
}

#[test]
fn an_intersection_past_t_max_is_caught() {
    assert_caught::<IntersectPastTMax>("intersect-beyond-t-max-misses");
}

#[test]
fn a_search_that_creeps_by_distances_is_caught_by_a_hard_case() {
    assert_caught_by_hard_case::<CreepsByDistance>("intersect-a-thin-shell-at-a-slant");
}
