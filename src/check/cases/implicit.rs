//! Implicit-surface cases (chapter 12): marches along a ray, Newton's
//! iteration inside a bracket, and normals from the function.

use super::*;
use crate::shapes::{
    Bracket, CHECK_EVALUATION_LIMIT, Implicit, NormalMethod, Sdf, limit_evaluations,
};

/// Which function a march case calls.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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

impl MarchCase {
    pub fn function(&self) -> &'static str {
        match self.marcher {
            Marcher::SphereTrace => "sphere_trace",
            Marcher::Intersect => "intersect_implicit",
        }
    }

    pub fn inputs(&self) -> String {
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

    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let MarchCase {
            marcher,
            surface,
            ray,
            t_min,
            t_max,
            expect,
            most_evaluations,
        } = self;
        let counted = limit_evaluations(CHECK_EVALUATION_LIMIT);
        let got = match marcher {
            Marcher::SphereTrace => C::sphere_trace(surface, ray, *t_min, *t_max),
            Marcher::Intersect => C::intersect_implicit(surface, ray, *t_min, *t_max),
        };
        let used = counted.count();
        drop(counted);
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
#[derive(Debug, Clone, PartialEq)]
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
/// tolerance, not at `max_iterations`).
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

impl NewtonCase {
    pub fn function(&self) -> &'static str {
        "newton_bracketed"
    }

    pub fn inputs(&self) -> String {
        format!(
            "newton_bracketed({}, Bracket {{ low: {}, high: {} }}, tolerance {}, max_iterations {})",
            self.function.text(),
            num(self.bracket.0),
            num(self.bracket.1),
            num(self.tolerance),
            self.max_iterations
        )
    }

    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let calls = std::cell::Cell::new(0u32);
        let g = |t: f32| {
            calls.set(calls.get() + 1);
            self.function.narrow(t)
        };
        let bracket = Bracket {
            low: self.bracket.0,
            high: self.bracket.1,
        };
        let got = C::newton_bracketed(&g, bracket, self.tolerance, self.max_iterations);
        let expected = format!("{} (within {})", num64(self.expect), num64(self.within));
        let close = got.is_finite() && (f64::from(got) - self.expect).abs() <= self.within;
        match self.most_evaluations {
            Some(most) => verdict(
                close && calls.get() <= most,
                format!("{expected}, in at most {most} evaluations of g"),
                format!("{} after {} evaluations of g", num(got), calls.get()),
            ),
            None => verdict(close, expected, num(got)),
        }
    }
}

/// `implicit_normal(surface, point)` with the surface's normal method:
/// expected the exact gradient's direction (analytic, tetrahedron), or the
/// central difference evaluated in `f64` with the same step, within
/// `within` radians.
#[derive(Debug, Clone)]
pub struct ImplicitNormalCase {
    pub surface: Implicit,
    pub point: Vec3,
    pub within: f64,
}

impl ImplicitNormalCase {
    pub fn function(&self) -> &'static str {
        "implicit_normal"
    }

    pub fn inputs(&self) -> String {
        let march = self.surface.march();
        format!(
            "implicit_normal(implicit {}, {}) with normals {:?}, normal_step {}",
            sdf_text(self.surface.tree()),
            vec(self.point),
            march.normal,
            num(march.normal_step)
        )
    }

    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let counted = limit_evaluations(CHECK_EVALUATION_LIMIT);
        let got = C::implicit_normal(&self.surface, self.point);
        drop(counted);
        let march = self.surface.march();
        // The tetrahedron's corners have a third moment, so its error is of
        // order h (which way it leans depends on which tetrahedron): it is
        // judged against the gradient itself, with its case's wider angle.
        let method = match march.normal {
            NormalMethod::Tetrahedron => NormalMethod::Analytic,
            method => method,
        };
        let expected = exact::difference_normal(
            self.surface.tree(),
            wide(self.point),
            method,
            f64::from(march.normal_step),
        );
        let g = wide(got);
        let pass = got.is_finite()
            && (g.length() - 1.0).abs() <= 1e-4
            && exact::angle(g, expected) <= self.within;
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
