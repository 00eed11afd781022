//! Implicit-surface cases (chapter 12): marches along a ray, Newton's
//! iteration inside a bracket, and normals from the function.

use glam::{DVec3, Vec3};

use crate::Ray;
use crate::check::cases::*;
use crate::check::exact::{self, wide};
use crate::course::Chapters;
use crate::shapes::{
    Bracket, CHECK_EVALUATION_LIMIT, Implicit, NormalMethod, Sdf, limit_evaluations,
};

/// Which function a march case calls.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Marcher {
    /// `sphere_trace`: the march alone.
    SphereTrace,
    /// `intersect_implicit`: the march, then Newton.
    Intersect,
}

/// What a march case expects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MarchExpect {
    /// A hit no more than `early` before the exact first root `root` and
    /// no more than `late` past it (in units of `t`): a march stops within
    /// its cone, before the surface, and never past it.
    Hit {
        root: f64,
        early: f64,
        late: f64,
    },
    Miss,
    /// Either; a hit must be within the march's cone of the surface.
    Either,
}

/// `sphere_trace` or `intersect_implicit` on `surface` (its march settings
/// included), with a budget of evaluations: a march that never stops is a
/// failure, not a hung check.
#[derive(Debug, Clone)]
pub struct MarchCase {
    pub marcher: Marcher,
    pub surface: Implicit,
    pub ray: Ray,
    pub t_min: f32,
    pub t_max: f32,
    pub expect: MarchExpect,
    /// The most evaluations of the function the call may make.
    pub most_evaluations: Option<u64>,
}

/// A march's call.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct MarchCall {
    pub marcher: Marcher,
    pub surface: Implicit,
    pub ray: Ray,
    pub t_min: f32,
    pub t_max: f32,
}

impl Kind for MarchCase {
    type Call = MarchCall;
    /// The answer, and how many evaluations of the function it took.
    type Answer = (Option<f32>, u64);

    fn function(&self) -> &'static str {
        match self.marcher {
            Marcher::SphereTrace => "sphere_trace",
            Marcher::Intersect => "intersect_implicit",
        }
    }

    fn inputs(&self) -> String {
        let march = self.surface.march();
        format!(
            "{}(implicit {}, ray from {} along {}, {}) with tolerance {}, {} steps, \
             relaxation {}, newton {}, lipschitz {}",
            self.function(),
            sdf_text(self.surface.tree()),
            vec(self.ray.origin),
            vec(self.ray.dir),
            range(self.t_min, self.t_max),
            num(march.tolerance),
            march.max_steps,
            num(march.relaxation),
            march.newton,
            num(self.surface.lipschitz()),
        )
    }

    fn call(&self) -> MarchCall {
        MarchCall {
            marcher: self.marcher,
            surface: self.surface.clone(),
            ray: self.ray,
            t_min: self.t_min,
            t_max: self.t_max,
        }
    }

    fn ask<C: Chapters>(call: &MarchCall) -> Result<(Option<f32>, u64), String> {
        let MarchCall {
            marcher,
            surface,
            ray,
            t_min,
            t_max,
        } = call;
        let counted = limit_evaluations(CHECK_EVALUATION_LIMIT);
        let got = match marcher {
            Marcher::SphereTrace => C::sphere_trace(surface, ray, *t_min, *t_max),
            Marcher::Intersect => C::intersect_implicit(surface, ray, *t_min, *t_max),
        };
        Ok((got, counted.count()))
    }

    fn judge(&self, (got, used): (Option<f32>, u64), _robust: bool) -> Outcome {
        let MarchCase {
            t_min,
            t_max,
            expect,
            most_evaluations,
            ..
        } = self;
        let show_got = match got {
            Some(t) => format!("Some({}) after {used} evaluations", num(t)),
            None => format!("None (misses) after {used} evaluations"),
        };
        let budget = |text: String| match most_evaluations {
            Some(most) => format!("{text}, in at most {most} evaluations"),
            None => text,
        };
        let within_budget = most_evaluations.is_none_or(|most| used <= most);
        let (pass, expected) = match *expect {
            MarchExpect::Hit { root, early, late } => (
                got.is_some_and(|t| {
                    let in_range = t > *t_min && t < *t_max;
                    let t = f64::from(t);
                    in_range && t.is_finite() && t >= root - early && t <= root + late
                }),
                format!(
                    "Some(t) with {} <= t <= {} (the surface is at t = {}), and t_min < t < t_max",
                    num64(root - early),
                    num64(root + late),
                    num64(root)
                ),
            ),
            MarchExpect::Miss => (got.is_none(), "None (misses)".to_string()),
            MarchExpect::Either => (
                got.is_none_or(|t| self.near_surface(t)),
                "None, or a t within the march's cone of the surface".to_string(),
            ),
        };
        verdict(pass && within_budget, budget(expected), show_got)
    }

    /// The surface, the ray's origin and every `t` scaled by a power of
    /// two ([`Sdf::scaled`]): a march of any formula takes exactly the
    /// same steps, to the last bit, on other numbers.
    fn fresh(&self, draw: &mut Draw) -> Option<MarchCase> {
        let factor = power_of_two(draw);
        let factor64 = f64::from(factor);
        let march = self.surface.march();
        let surface = Implicit::new(self.surface.tree().scaled(factor))
            .ok()?
            .with_march(crate::shapes::March {
                normal_step: march.normal_step * factor,
                ..*march
            });
        let expect = match self.expect {
            MarchExpect::Hit { root, early, late } => MarchExpect::Hit {
                root: root * factor64,
                early: early * factor64,
                late: late * factor64,
            },
            other => other,
        };
        Some(MarchCase {
            surface,
            ray: Ray::new(self.ray.origin * factor, self.ray.dir),
            t_min: self.t_min * factor,
            t_max: self.t_max * factor,
            expect,
            ..self.clone()
        })
    }
}

/// A power of two from 1/8 to 8, not 1: a scale that changes every
/// number of a case and no rounding.
fn power_of_two(draw: &mut Draw) -> f32 {
    let exponent = [-3, -2, -1, 1, 2, 3][draw.below(6) as usize];
    2f32.powi(exponent)
}

impl MarchCase {
    /// Whether the point at `t` is within twice the march's cone of the
    /// surface, measured by the exact function.
    fn near_surface(&self, t: f32) -> bool {
        let (origin, dir) = (wide(self.ray.origin), wide(self.ray.dir));
        let t = f64::from(t);
        let cone = 2.0 * f64::from(self.surface.march().tolerance) * t * dir.length();
        t > f64::from(self.t_min)
            && t < f64::from(self.t_max)
            && exact::sdf_distance(self.surface.tree(), origin + t * dir).abs()
                / f64::from(self.surface.lipschitz_bound())
                <= cone + 1e-5 * (origin.abs().max_element() + 1.0)
    }
}

/// The function a Newton case hands to `newton_bracketed`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum NewtonFunction {
    /// A polynomial in `t`, constant first.
    Polynomial(Vec<f64>),
    /// The torus's quartic polynomial (centred at the origin, around y)
    /// along the ray from `origin` along `dir`.
    TorusAlongRay {
        major: f32,
        minor: f32,
        origin: Vec3,
        dir: Vec3,
    },
}

impl NewtonFunction {
    /// The value and slope at `t`, in `f32`: what the student's code gets.
    pub fn narrow(&self, t: f32) -> (f32, f32) {
        match self {
            NewtonFunction::Polynomial(coefficients) => {
                let value = coefficients
                    .iter()
                    .rev()
                    .fold(0.0f32, |sum, &c| sum * t + c as f32);
                let slope = coefficients
                    .iter()
                    .enumerate()
                    .skip(1)
                    .rev()
                    .fold(0.0f32, |sum, (power, &c)| sum * t + power as f32 * c as f32);
                (value, slope)
            }
            NewtonFunction::TorusAlongRay {
                major,
                minor,
                origin,
                dir,
            } => {
                let point = *origin + t * *dir;
                let ring = point.length_squared() + major * major - minor * minor;
                let value =
                    ring * ring - 4.0 * major * major * (point.x * point.x + point.z * point.z);
                let gradient =
                    4.0 * ring * point - 8.0 * major * major * Vec3::new(point.x, 0.0, point.z);
                (value, gradient.dot(*dir))
            }
        }
    }

    /// The value and slope at `t`, in `f64`: what the expected answers use.
    pub fn exact(&self, t: f64) -> (f64, f64) {
        match self {
            NewtonFunction::Polynomial(coefficients) => {
                let slope: Vec<f64> = coefficients
                    .iter()
                    .enumerate()
                    .skip(1)
                    .map(|(power, c)| power as f64 * c)
                    .collect();
                (
                    exact::polynomial(coefficients, t),
                    exact::polynomial(&slope, t),
                )
            }
            NewtonFunction::TorusAlongRay {
                major,
                minor,
                origin,
                dir,
            } => {
                let (major, minor) = (f64::from(*major), f64::from(*minor));
                let point = wide(*origin) + t * wide(*dir);
                let ring = point.length_squared() + major * major - minor * minor;
                let gradient =
                    4.0 * ring * point - 8.0 * major * major * DVec3::new(point.x, 0.0, point.z);
                (
                    exact::torus_polynomial(major, minor, point),
                    gradient.dot(wide(*dir)),
                )
            }
        }
    }

    fn text(&self) -> String {
        match self {
            NewtonFunction::Polynomial(coefficients) => {
                let terms: Vec<String> = coefficients
                    .iter()
                    .enumerate()
                    .rev()
                    .filter(|(_, c)| **c != 0.0)
                    .map(|(power, c)| match power {
                        0 => num64(*c),
                        1 => format!("{} t", num64(*c)),
                        _ => format!("{} t^{power}", num64(*c)),
                    })
                    .collect();
                format!("g(t) = {}", terms.join(" + "))
            }
            NewtonFunction::TorusAlongRay {
                major,
                minor,
                origin,
                dir,
            } => format!(
                "g(t) = the quartic of the torus at the origin, major {} minor {}, at {} + t {}",
                num(*major),
                num(*minor),
                vec(*origin),
                vec(*dir)
            ),
        }
    }
}

/// `newton_bracketed(g, bracket, tolerance, max_iterations)`: expected
/// `expect` within `within`, and in at most `most_evaluations` calls of
/// `g` when that is given (a method that stops when its step is below the
/// tolerance, not at `max_iterations`). Every case also checks the method's
/// state, not only its answer: each point where `g` is evaluated lies in
/// the bracket as the points before it have shrunk it (the half without
/// the sign change dropped after each), so the bracket only shrinks.
#[derive(Debug, Clone)]
pub struct NewtonCase {
    pub function: NewtonFunction,
    pub bracket: (f32, f32),
    pub tolerance: f32,
    pub max_iterations: u32,
    pub expect: f64,
    pub within: f64,
    pub most_evaluations: Option<u32>,
}

/// `newton_bracketed`'s inputs.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct NewtonCall {
    pub function: NewtonFunction,
    pub bracket: (f32, f32),
    pub tolerance: f32,
    pub max_iterations: u32,
}

/// The most evaluations of `g` a Newton answer lists: far more than any
/// case allows.
const MOST_LISTED: usize = 4096;

/// A Newton answer: the root, how many times `g` was called, and where
/// (the first `MOST_LISTED` calls).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct NewtonAnswer {
    pub root: f32,
    pub calls: u64,
    pub at: Vec<f32>,
}

impl NewtonCase {
    /// The first point of `at` outside the bracket as the points before it
    /// shrank it, and that bracket: the bracket starts as the case's, and
    /// each point where `g` has the sign of `g(low)` becomes its low end,
    /// each where it has the other sign its high end (the ends count as
    /// inside; a zero of `g` moves neither, as the method stops there).
    /// The signs are the student's own: `g` in `f32`, as it was called.
    fn outside_the_bracket(&self, at: &[f32]) -> Option<(f32, (f32, f32))> {
        let (mut low, mut high) = self.bracket;
        let low_positive = self.function.narrow(low).0 > 0.0;
        for &t in at {
            if !(low <= t && t <= high) {
                return Some((t, (low, high)));
            }
            let value = self.function.narrow(t).0;
            if value == 0.0 {
                continue;
            }
            if (value > 0.0) == low_positive {
                low = t;
            } else {
                high = t;
            }
        }
        None
    }
}

impl Kind for NewtonCase {
    type Call = NewtonCall;
    type Answer = NewtonAnswer;

    fn function(&self) -> &'static str {
        "newton_bracketed"
    }

    fn inputs(&self) -> String {
        format!(
            "newton_bracketed({}, Bracket {{ low: {}, high: {} }}, tolerance {}, max_iterations {})",
            self.function.text(),
            num(self.bracket.0),
            num(self.bracket.1),
            num(self.tolerance),
            self.max_iterations
        )
    }

    fn call(&self) -> NewtonCall {
        NewtonCall {
            function: self.function.clone(),
            bracket: self.bracket,
            tolerance: self.tolerance,
            max_iterations: self.max_iterations,
        }
    }

    fn ask<C: Chapters>(call: &NewtonCall) -> Result<NewtonAnswer, String> {
        let calls = std::cell::RefCell::new((0u64, Vec::new()));
        let g = |t: f32| {
            let mut calls = calls.borrow_mut();
            calls.0 += 1;
            if calls.1.len() < MOST_LISTED {
                calls.1.push(t);
            }
            call.function.narrow(t)
        };
        let bracket = Bracket {
            low: call.bracket.0,
            high: call.bracket.1,
        };
        let root = C::newton_bracketed(&g, bracket, call.tolerance, call.max_iterations);
        let (calls, at) = calls.into_inner();
        Ok(NewtonAnswer { root, calls, at })
    }

    fn judge(&self, answer: NewtonAnswer, _robust: bool) -> Outcome {
        let NewtonAnswer {
            root: got,
            calls,
            at,
        } = answer;
        if let Some((t, (low, high))) = self.outside_the_bracket(&at) {
            return verdict(
                false,
                "every point where g is evaluated inside the bracket, which only shrinks: \
                 after each, the half without the sign change is dropped"
                    .into(),
                format!(
                    "g evaluated at {} when the points before it had shrunk the bracket to \
                     [{}, {}]",
                    num(t),
                    num(low),
                    num(high)
                ),
            );
        }
        let expected = format!("{} (within {})", num64(self.expect), num64(self.within));
        let close = got.is_finite() && (f64::from(got) - self.expect).abs() <= self.within;
        match self.most_evaluations {
            Some(most) => verdict(
                close && calls <= u64::from(most),
                format!("{expected}, in at most {most} evaluations of g"),
                format!("{} after {calls} evaluations of g", num(got)),
            ),
            None => verdict(close, expected, num(got)),
        }
    }

    /// `t` scaled by one power of two and `g`'s values by another: every
    /// step of any correct method, its bracket and its answer scale
    /// exactly, and the numbers of the call all change.
    fn fresh(&self, draw: &mut Draw) -> Option<NewtonCase> {
        let (along, value) = (power_of_two(draw), power_of_two(draw));
        let function = match &self.function {
            NewtonFunction::Polynomial(coefficients) => {
                // q(u) = value p(along u): coefficient i times value along^i.
                let mut power = f64::from(value);
                NewtonFunction::Polynomial(
                    coefficients
                        .iter()
                        .map(|c| {
                            let scaled = c * power;
                            power *= f64::from(along);
                            scaled
                        })
                        .collect(),
                )
            }
            // The torus scaled by `value` (its quartic by value^4), the
            // ray's direction by `along` on top.
            NewtonFunction::TorusAlongRay {
                major,
                minor,
                origin,
                dir,
            } => NewtonFunction::TorusAlongRay {
                major: major * value,
                minor: minor * value,
                origin: *origin * value,
                dir: *dir * value * along,
            },
        };
        let along64 = f64::from(along);
        Some(NewtonCase {
            function,
            bracket: (self.bracket.0 / along, self.bracket.1 / along),
            tolerance: self.tolerance / along,
            expect: self.expect / along64,
            within: self.within / along64,
            ..self.clone()
        })
    }
}

/// `implicit_normal(surface, point)` with the surface's normal method:
/// expected the exact gradient's direction (analytic), or the method's
/// differences evaluated in `f64` with the same step (central, either
/// tetrahedron), unit and within `within` radians.
#[derive(Debug, Clone)]
pub struct ImplicitNormalCase {
    pub surface: Implicit,
    pub point: Vec3,
    pub within: f64,
}

impl Kind for ImplicitNormalCase {
    type Call = (Implicit, Vec3);
    type Answer = Vec3;

    fn function(&self) -> &'static str {
        "implicit_normal"
    }

    fn inputs(&self) -> String {
        let march = self.surface.march();
        format!(
            "implicit_normal(implicit {}, {}) with normals {:?}, normal_step {}",
            sdf_text(self.surface.tree()),
            vec(self.point),
            march.normal,
            num(march.normal_step)
        )
    }

    fn call(&self) -> (Implicit, Vec3) {
        (self.surface.clone(), self.point)
    }

    fn ask<C: Chapters>((surface, point): &(Implicit, Vec3)) -> Result<Vec3, String> {
        let _counted = limit_evaluations(CHECK_EVALUATION_LIMIT);
        Ok(C::implicit_normal(surface, *point))
    }

    fn judge(&self, got: Vec3, _robust: bool) -> Outcome {
        let march = self.surface.march();
        let (tree, point, step) = (
            self.surface.tree(),
            wide(self.point),
            f64::from(march.normal_step),
        );
        let expected = exact::difference_normal(tree, point, march.normal, step);
        let g = wide(got);
        // The tetrahedron's corners have a third moment, so its error is of
        // order h and leans one way or the other depending on which
        // tetrahedron: the lesson's corners `k` or the opposite ones `-k`
        // (their sum is minus the lesson's with the step `-h`), and
        // either is right.
        let angle = match march.normal {
            NormalMethod::Tetrahedron => {
                let opposite =
                    -exact::difference_normal(tree, point, NormalMethod::Tetrahedron, -step);
                exact::angle(g, expected).min(exact::angle(g, opposite))
            }
            _ => exact::angle(g, expected),
        };
        let pass = got.is_finite() && (g.length() - 1.0).abs() <= 1e-4 && angle <= self.within;
        verdict(
            pass,
            format!(
                "{} (unit, within {} radians)",
                vec64(expected),
                num64(self.within)
            ),
            vec(got),
        )
    }

    /// The surface, the point and the difference step scaled by a power
    /// of two: the same normal, from other numbers.
    fn fresh(&self, draw: &mut Draw) -> Option<ImplicitNormalCase> {
        let factor = power_of_two(draw);
        let march = self.surface.march();
        let surface = Implicit::new(self.surface.tree().scaled(factor))
            .ok()?
            .with_march(crate::shapes::March {
                normal_step: march.normal_step * factor,
                ..*march
            });
        Some(ImplicitNormalCase {
            surface,
            point: self.point * factor,
            within: self.within,
        })
    }
}

/// The exact normal's method name in a case's sentence.
pub fn method_name(method: NormalMethod) -> &'static str {
    match method {
        NormalMethod::Analytic => "the analytic gradient",
        NormalMethod::Central => "central differences",
        NormalMethod::Tetrahedron => "the tetrahedron's four differences",
    }
}

/// A surface of `tree`, for a case (the tree is a case's own, valid).
pub fn surface_of(tree: Sdf) -> Implicit {
    Implicit::new(tree).unwrap_or_else(|error| panic!("a case's surface is invalid: {error}"))
}
