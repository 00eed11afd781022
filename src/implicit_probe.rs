//! One ray against one implicit surface, step by step: what `raylab probe`
//! shows of chapter 12. The march's answer, and Newton's method on
//! `g(t) = f(o + t d)` from where the ray enters the surface's box, once
//! inside a bracket (the chapter's `newton_bracketed`) and once alone,
//! each iterate with the digits it has right against an `f64` reference.
//! It measures; the command line prints.

use std::cell::RefCell;

use crate::Ray;
use crate::check::exact;
use crate::course::Chapters;
use crate::shapes::{Bracket, Implicit, evaluations};

/// One point Newton's method evaluated `g` at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Iterate {
    pub t: f32,
    /// `g(t)`: the surface's function at the ray's point.
    pub value: f32,
    /// How many significant digits of the first root `t` has right
    /// (`-log10` of the relative error), `None` where `t` is the root to
    /// the reference's precision.
    pub digits: Option<f64>,
    /// Whether it was a Newton step, a bisection, or the start.
    pub step: Step,
}

/// How an iterate was reached.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    Start,
    Newton,
    /// The bracket's midpoint: the Newton step would have left it.
    Bisection,
}

/// What the march and Newton's method did along one ray.
#[derive(Debug, Clone, PartialEq)]
pub struct ImplicitStory {
    /// Where the ray is inside the surface's box; `None` when it misses it.
    pub span: Option<(f32, f32)>,
    /// The first root in `f64` (safe steps of `|f| / L` to within `1e-10`
    /// of the scene's scale): the reference every digit is counted against.
    pub root: Option<f64>,
    /// The chapter's sphere tracing alone, and its evaluations.
    pub march: Option<f32>,
    pub march_evaluations: u64,
    /// Newton in the bracket from the box's entry to the first `f32` past
    /// the root (the sign change a render finds by marching), from its low
    /// end: every point the chapter's `newton_bracketed` evaluated.
    pub bracketed: Option<(Bracket, Vec<Iterate>)>,
    /// Newton alone from the box's entry: `t - g / g'`, nothing to stop it.
    pub alone: Vec<Iterate>,
    /// The chapter's `intersect_implicit`, as a render calls it, and its
    /// evaluations.
    pub answer: Option<f32>,
    pub answer_evaluations: u64,
}

/// Newton's iterations, in the bracket and alone: as many as the
/// chapter's `intersect_implicit` allows itself, enough for `f32`.
pub const NEWTON_STEPS: u32 = 16;

/// How far past the `f64` root (in units in the last place) the bracket's
/// high end is searched for a sign change.
const ULPS_PAST_THE_ROOT: u32 = 64;

/// The march, the bracketed and the free Newton of `ray` against `surface`
/// (hits with `0 < t < inf`), by the chapters `C`.
pub fn story<C: Chapters>(surface: &Implicit, ray: &Ray) -> ImplicitStory {
    let span = surface.span(ray, 0.0, f32::INFINITY);
    let before = evaluations();
    let answer = C::intersect_implicit(surface, ray, 0.0, f32::INFINITY);
    let answer_evaluations = evaluations() - before;
    let Some((enter, leave)) = span else {
        return ImplicitStory {
            span,
            root: None,
            march: None,
            march_evaluations: 0,
            bracketed: None,
            alone: Vec::new(),
            answer,
            answer_evaluations,
        };
    };
    let before = evaluations();
    let march = C::sphere_trace(surface, ray, enter, leave);
    let march_evaluations = evaluations() - before;
    let root = exact::first_crossing(
        surface.tree(),
        f64::from(surface.lipschitz_bound()),
        exact::wide(ray.origin),
        exact::wide(ray.dir),
        f64::from(enter),
        f64::from(leave),
    );
    let g = |t: f32| {
        let point = ray.at(t);
        (
            surface.distance(point),
            surface.gradient(point).dot(ray.dir),
        )
    };
    let iterate = |t: f32, value: f32, step: Step| Iterate {
        t,
        value,
        digits: root.and_then(|root| correct_digits(t, root)),
        step,
    };
    let bracketed = root.and_then(|root| {
        let bracket = bracket_to(&g, enter, root)?;
        let points = RefCell::new(Vec::new());
        // The bracket as the method narrows it, to tell its midpoints
        // (bisections) from Newton's steps.
        let narrowed = RefCell::new((bracket, None::<bool>));
        let recording = |t: f32| {
            let (value, slope) = g(t);
            let (mut now, low_positive) = *narrowed.borrow();
            let step = match low_positive {
                None => Step::Start,
                Some(_) if t == 0.5 * (now.low + now.high) => Step::Bisection,
                Some(_) => Step::Newton,
            };
            let low_positive = low_positive.unwrap_or(value > 0.0);
            if (value > 0.0) == low_positive {
                now.low = t;
            } else {
                now.high = t;
            }
            *narrowed.borrow_mut() = (now, Some(low_positive));
            points.borrow_mut().push(iterate(t, value, step));
            (value, slope)
        };
        C::newton_bracketed(
            &recording,
            bracket,
            2.0 * f32::EPSILON * bracket.high,
            NEWTON_STEPS,
        );
        Some((bracket, points.into_inner()))
    });
    let mut alone = Vec::new();
    let mut t = enter;
    let (mut value, mut slope) = g(t);
    alone.push(iterate(t, value, Step::Start));
    for _ in 0..NEWTON_STEPS {
        let next = t - value / slope;
        if !next.is_finite() {
            break;
        }
        let step = next - t;
        t = next;
        (value, slope) = g(t);
        alone.push(iterate(t, value, Step::Newton));
        if step.abs() <= 2.0 * f32::EPSILON * t.abs() || value == 0.0 {
            break;
        }
    }
    ImplicitStory {
        span,
        root,
        march,
        march_evaluations,
        bracketed,
        alone,
        answer,
        answer_evaluations,
    }
}

/// `[low, high]` with `high` the first `f32` at or past `root` where `g`
/// has the other sign than at `low`; `None` if none is within
/// [`ULPS_PAST_THE_ROOT`] (a root the ray only touches).
fn bracket_to(g: &dyn Fn(f32) -> (f32, f32), low: f32, root: f64) -> Option<Bracket> {
    let low_positive = g(low).0 > 0.0;
    let mut high = (root as f32).max(low);
    for _ in 0..ULPS_PAST_THE_ROOT {
        if (g(high).0 > 0.0) != low_positive {
            return Some(Bracket { low, high });
        }
        high = high.next_up();
    }
    None
}

/// `-log10 |t - root| / |root|`: the significant digits `t` has right.
fn correct_digits(t: f32, root: f64) -> Option<f64> {
    let error = (f64::from(t) - root).abs() / root.abs().max(f64::MIN_POSITIVE);
    (error > 0.0).then(|| -error.log10())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec3;

    /// Chapter 12's torus, marched with the scene's settings, and a ray
    /// from the camera that enters its box well before the tube.
    fn torus_and_ray() -> (Implicit, Ray) {
        let scene = crate::builtin::scene(12).expect("the built-in scene loads");
        let surface = scene.shapes[0]
            .as_implicit()
            .expect("the first object is the torus")
            .with_march(scene.render.march());
        let ray = Ray::new(Vec3::new(0.0, 2.2, -5.5), Vec3::new(-0.33, -0.3, 1.0));
        (surface, ray)
    }

    #[test]
    fn newton_in_its_bracket_finds_the_first_root_and_alone_jumps_past_it() {
        let (surface, ray) = torus_and_ray();
        let story = story::<crate::Reference>(&surface, &ray);
        let root = story.root.expect("the ray crosses the tube");
        let answer = story.answer.expect("the chapter finds the hit");
        assert!(
            (f64::from(answer) - root).abs() < 1e-6 * root,
            "{answer} vs {root}"
        );
        let (bracket, iterates) = story.bracketed.expect("a sign change past the root");
        assert!(bracket.low < bracket.high);
        let last = iterates.last().expect("Newton evaluated g");
        assert!(last.digits.is_none_or(|digits| digits > 6.5), "{last:?}");
        assert_eq!(iterates[0].step, Step::Start);
        // From where the ray enters the box, g rises before it falls: the
        // Newton steps leave the bracket and bisect, until the last ones.
        let bisections = iterates
            .iter()
            .filter(|i| i.step == Step::Bisection)
            .count();
        assert!(bisections >= 5, "{iterates:?}");
        assert_eq!(iterates[iterates.len() - 2].step, Step::Newton);
        // Alone, Newton converges to the tube's far side.
        let alone = story.alone.last().expect("Newton alone evaluated g");
        assert!(alone.value.abs() < 1e-5, "{alone:?}");
        assert!(f64::from(alone.t) > root + 0.1, "{alone:?} vs {root}");
    }

    #[test]
    fn a_ray_that_misses_the_box_makes_no_evaluation() {
        let (surface, _) = torus_and_ray();
        let away = Ray::new(Vec3::new(0.0, 2.2, -5.5), Vec3::new(0.0, 1.0, 0.0));
        let story = story::<crate::Reference>(&surface, &away);
        assert_eq!(story.span, None);
        assert_eq!((story.answer, story.answer_evaluations), (None, 0));
        assert!(story.alone.is_empty() && story.bracketed.is_none());
    }

    #[test]
    fn digits_count_the_relative_error() {
        assert_eq!(correct_digits(2.0, 2.0), None);
        let digits = correct_digits(1.001, 1.0).expect("an error");
        assert!((digits - 3.0).abs() < 1e-3, "{digits}");
    }
}
