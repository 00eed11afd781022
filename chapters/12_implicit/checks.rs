//! Chapter 12's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 12`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;
use crate::check::chapter_kinds::ch12_implicit::*;

const TRACE_12: &str = "Sphere tracing";
const LIPSCHITZ_12: &str = "Bounds, not distances: the Lipschitz constant";
const RELAX_12: &str = "Longer steps: over-relaxation";
const TOLERANCE_12: &str = "When to stop: a cone, not a distance";
const NEWTON_12: &str = "Newton's method inside a bracket";
const NORMALS_12: &str = "Normals from the function";
const HARD_12: &str = "The hard cases";

/// Where the image differs when every checkpoint passes: what to look at
/// in the heatmap.
pub const IMAGE_HINT: &str = "on the implicit surfaces: the march's step divided by the Lipschitz constant, its cone tolerance, the bracket that Newton keeps, and the normal's method and step";

/// The unit sphere at the origin.
fn unit_sphere() -> Sdf {
    Sdf::Sphere {
        center: Vec3::ZERO,
        radius: 1.0,
    }
}

/// The torus at the origin around the y axis, radii 1 and 0.25.
fn ring() -> Sdf {
    Sdf::Torus {
        center: Vec3::ZERO,
        major: 1.0,
        minor: 0.25,
    }
}

/// A march question on `tree` marched with `march`: the ray from
/// `ray.0` along `ray.1`, `range.0 < t < range.1`.
struct MarchQuestion {
    name: &'static str,
    section: &'static str,
    says: &'static str,
    marcher: Marcher,
    tree: Sdf,
    march: March,
    ray: (Vec3, Vec3),
    range: (f32, f32),
    expect: Expect,
    /// For a hit: how far before the root the march may stop, as a
    /// multiple of its cone at the root (`tolerance t |d|` over the
    /// cosine of the angle of incidence the question knows).
    cones: f64,
    most_evaluations: Option<u64>,
}

impl From<MarchQuestion> for Case {
    fn from(question: MarchQuestion) -> Case {
        let surface = surface_of(question.tree).with_march(question.march);
        let (origin, dir) = question.ray;
        let (t_min, t_max) = question.range;
        let root = exact_root(&surface, origin, dir, t_min, t_max);
        let expect = match question.expect {
            Expect::Hit => {
                let root = root.unwrap_or(f64::NAN);
                MarchExpect::Hit {
                    root,
                    early: question.cones * f64::from(question.march.tolerance) * root.abs()
                        + 1e-5 * root.abs().max(1.0),
                    late: 1e-5 * root.abs().max(1.0),
                }
            }
            Expect::Miss => MarchExpect::Miss,
            Expect::Either => MarchExpect::Either,
        };
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::March(MarchCase {
                marcher: question.marcher,
                surface,
                ray: Ray::new(origin, dir),
                t_min,
                t_max,
                expect,
                most_evaluations: question.most_evaluations,
            }),
        )
    }
}

/// The exact first root: the sphere's and the torus's in closed form,
/// any other tree's by safe steps in `f64`.
fn exact_root(surface: &Implicit, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> Option<f64> {
    let (o, d, low, high) = (wide(origin), wide(dir), f64::from(t_min), f64::from(t_max));
    match surface.tree() {
        Sdf::Sphere { center, radius } => {
            exact::sphere(wide(*center), f64::from(*radius), o, d, low, high)
        }
        Sdf::Torus {
            center,
            major,
            minor,
        } => exact::torus(
            wide(*center),
            f64::from(*major),
            f64::from(*minor),
            o,
            d,
            low,
            high,
        ),
        tree => exact::first_crossing(tree, f64::from(surface.lipschitz_bound()), o, d, low, high),
    }
}

fn march_with(change: impl FnOnce(&mut March)) -> March {
    let mut march = March::default();
    change(&mut march);
    march
}

fn newton(
    name: &'static str,
    says: &'static str,
    function: NewtonFunction,
    bracket: (f32, f32),
    max_iterations: u32,
    expect: f64,
    within: f64,
) -> Case {
    Case::new(
        name,
        NEWTON_12,
        says,
        CaseKind::Newton(NewtonCase {
            function,
            bracket,
            tolerance: 1e-7,
            max_iterations,
            expect,
            within,
            most_evaluations: None,
        }),
    )
}

/// Newton's first step from `low` on `function`, or the midpoint when
/// it leaves the bracket: the answer of one iteration, in `f64`.
fn first_iterate(function: &NewtonFunction, (low, high): (f32, f32)) -> f64 {
    let (low, high) = (f64::from(low), f64::from(high));
    let (value, slope) = function.exact(low);
    let step = low - value / slope;
    if step >= low && step <= high {
        step
    } else {
        0.5 * (low + high)
    }
}

fn normal(
    name: &'static str,
    says: &'static str,
    tree: Sdf,
    (method, step): (NormalMethod, f32),
    point: Vec3,
    within: f64,
) -> Case {
    let march = march_with(|march| {
        march.normal = method;
        march.normal_step = step;
    });
    Case::new(
        name,
        NORMALS_12,
        says,
        CaseKind::ImplicitNormal(ImplicitNormalCase {
            surface: surface_of(tree).with_march(march),
            point,
            within,
        }),
    )
}

/// Where the tetrahedron's torus is moved to: its corners must be placed
/// around the point, not scaled with it.
const RAISED: Vec3 = Vec3::new(0.0, 2.0, 0.0);

/// The unit sphere less the sphere of radius 0.998: a shell 0.002 thick.
fn thin_shell() -> Sdf {
    Sdf::Difference(
        Box::new(unit_sphere()),
        Box::new(Sdf::Sphere {
            center: Vec3::ZERO,
            radius: 0.998,
        }),
    )
}

/// [`thin_shell`] around a solid ball of radius 0.5 at its centre.
fn shell_around_a_ball() -> Sdf {
    Sdf::Union(vec![
        thin_shell(),
        Sdf::Sphere {
            center: Vec3::ZERO,
            radius: 0.5,
        },
    ])
}

/// The ground: the half space below y = 0.
fn ground() -> Sdf {
    Sdf::Plane {
        point: Vec3::ZERO,
        normal: Vec3::Y,
    }
}

/// `intersect_implicit` with `newton = false` on [`ground`] from `(0, 1, 0)`
/// along `(0.6, -0.8, 0)` with a tolerance of 0.1: the march's own answer,
/// `t = 1.2`, which stops short of the surface at `t = 1.25`, so that an
/// answer Newton refined onto it is told apart.
fn march_stops_short() -> Case {
    let march = march_with(|march| {
        march.tolerance = 0.1;
        march.newton = false;
    });
    let surface = surface_of(ground()).with_march(march);
    let (origin, dir) = (Vec3::Y, Vec3::new(0.6, -0.8, 0.0));
    let root = exact_root(&surface, origin, dir, 0.0, INF).unwrap_or(f64::NAN);
    Case::new(
        "intersect-without-newton-stops-short",
        NEWTON_12,
        "The ground from (0, 1, 0) along (0.6, -0.8, 0) with tolerance 0.1 and newton = false: the march steps 1 (to t = 1, 0.2 above the ground, more than the cone's 0.1), then 0.2 (to t = 1.2, 0.04 above, less than 0.12) and stops: t = 1.2, short of the surface at t = 1.25, is the answer. Newton would pin it onto the surface; without it, the march's answer stands.",
        CaseKind::March(MarchCase {
            marcher: Marcher::Intersect,
            surface,
            ray: Ray::new(origin, dir),
            t_min: 0.0,
            t_max: INF,
            // Anywhere in the cone before the surface, but at least a
            // fifth of the way from the surface to where the march stops.
            expect: MarchExpect::Hit {
                root,
                early: 0.1 * root,
                late: -0.02 * root,
            },
            most_evaluations: None,
        }),
    )
}

/// Fewer evaluations than safe steps take down onto [`ground`] in
/// `march-over-relaxed-keeps-relaxing` (67), and a few more than the
/// relaxed march needs (41).
const RELAXED_GROUND_BUDGET: u64 = 48;

/// Fewer evaluations than a march that relaxes again after each step back
/// spends in `march-over-relaxed-relaxes-no-more` (24), and a few more
/// than one that relaxes no more (17).
const NO_MORE_RELAXING_BUDGET: u64 = 20;

/// A point on [`ring`]: around the axis by `around`, around the tube by
/// `tube` (radians).
fn on_ring(around: f32, tube: f32) -> Vec3 {
    let radial = Vec3::new(around.cos(), 0.0, around.sin());
    radial * (1.0 + 0.25 * tube.cos()) + Vec3::Y * (0.25 * tube.sin())
}

/// A bumpy unit sphere whose bumps' slope makes its function change up to
/// 3 times as fast as a distance (`L = 1 + 0.25 * 8`).
fn bumpy() -> Sdf {
    Sdf::Displace {
        amplitude: 0.25,
        frequency: 8.0,
        shape: Box::new(unit_sphere()),
    }
}

/// Chapter 12's checkpoint cases.
///
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn checkpoints() -> Vec<Case> {
    let quadratic = NewtonFunction::Polynomial(vec![-2.0, 0.0, 1.0]);
    let torus_ray = NewtonFunction::TorusAlongRay {
        major: 1.0,
        minor: 0.25,
        origin: Vec3::new(-3.0, 0.0, 0.0),
        dir: Vec3::X,
    };
    vec![
        MarchQuestion {
            name: "march-toward-a-sphere-along-its-axis",
            section: TRACE_12,
            says: "From (0, 0, -5) toward the unit sphere, the function is 4: one step of 4 lands on the surface at t = 4, and the second evaluation, 0, says so. Far more evaluations means the steps are not the distance.",
            marcher: Marcher::SphereTrace,
            tree: unit_sphere(),
            march: March::default(),
            ray: (Vec3::new(0.0, 0.0, -5.0), Vec3::Z),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 2.0,
            most_evaluations: Some(8),
        }
        .into(),
        MarchQuestion {
            name: "march-with-a-direction-not-unit",
            section: TRACE_12,
            says: "The same sphere along (0, 0, 2): t counts lengths of the direction, so the surface is at t = 2 and each step of distance r moves t by r / 2.",
            marcher: Marcher::SphereTrace,
            tree: unit_sphere(),
            march: March::default(),
            ray: (Vec3::new(0.0, 0.0, -5.0), Vec3::new(0.0, 0.0, 2.0)),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 2.0,
            most_evaluations: Some(8),
        }
        .into(),
        MarchQuestion {
            name: "march-hits-only-past-t-min",
            section: TRACE_12,
            says: "The unit sphere from (0, 0, -5) with t_min = 3.9999: the first point, t = 3.9999, is already within the cone (f = 0.0001 < 0.0001 x 3.9999), but a hit must have t > t_min (a march that starts where the ray enters a box, or leaves a surface, must not stop where it starts): step on, to t = 4.",
            marcher: Marcher::SphereTrace,
            tree: unit_sphere(),
            march: March::default(),
            ray: (Vec3::new(0.0, 0.0, -5.0), Vec3::Z),
            range: (3.9999, INF),
            expect: Expect::Hit,
            cones: 2.0,
            most_evaluations: Some(8),
        }
        .into(),
        MarchQuestion {
            name: "march-beside-a-sphere-misses",
            section: TRACE_12,
            says: "From (0, 2, -5) along +z the ray passes 1 unit above the unit sphere: no hit. Past the sphere each step is about the point's distance from its centre, which then doubles each step; after 68 evaluations its square overflows f32, the radius is infinite, and the march stops there (or one step later, at t = inf), long before its 256 steps.",
            marcher: Marcher::SphereTrace,
            tree: unit_sphere(),
            march: March::default(),
            ray: (Vec3::new(0.0, 2.0, -5.0), Vec3::Z),
            range: (0.0, INF),
            expect: Expect::Miss,
            cones: 2.0,
            most_evaluations: Some(300),
        }
        .into(),
        MarchQuestion {
            name: "march-stops-past-t-max",
            section: TRACE_12,
            says: "The unit sphere from (0, 0, -5) with t_max = 4: the first step reaches t = 4, on the surface but not inside the open range t < t_max, and the march stops there with no hit.",
            marcher: Marcher::SphereTrace,
            tree: unit_sphere(),
            march: March::default(),
            ray: (Vec3::new(0.0, 0.0, -5.0), Vec3::Z),
            range: (0.0, 4.0),
            expect: Expect::Miss,
            cones: 2.0,
            most_evaluations: Some(8),
        }
        .into(),
        MarchQuestion {
            name: "march-from-inside-finds-the-way-out",
            section: TRACE_12,
            says: "From the centre of the unit sphere the function is -1: the surface is 1 away in every direction, so the step is |f| = 1 and the exit is at t = 1.",
            marcher: Marcher::SphereTrace,
            tree: unit_sphere(),
            march: March::default(),
            ray: (Vec3::ZERO, Vec3::Z),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 2.0,
            most_evaluations: Some(8),
        }
        .into(),
        MarchQuestion {
            name: "march-divides-by-the-lipschitz-constant",
            section: LIPSCHITZ_12,
            says: "A unit sphere with bumps of amplitude 0.25 and frequency 8 (L = 3), seen from (0.3, 0.2, -3) along (0, 0.05, 1): a step of f instead of f / L can jump past the first bump the ray meets.",
            marcher: Marcher::SphereTrace,
            tree: bumpy(),
            march: March::default(),
            ray: (Vec3::new(0.3, 0.2, -3.0), Vec3::new(0.0, 0.05, 1.0)),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 40.0,
            most_evaluations: None,
        }
        .into(),
        MarchQuestion {
            name: "march-over-relaxed-steps-back",
            section: RELAX_12,
            says: "Relaxation 1.9 toward the unit sphere from (0, 0, -5) along (0, 0, 2): the first step, 1.9 x 4 = 7.6 in distance (3.8 in t), jumps through it to z = 2.6, where the radius 1.6 and the last one, 4, do not reach across the 7.6 travelled; go back to the last point's safe step, t = 2, and hit there: 3 evaluations (the last point's radius is known: no need to look at it again).",
            marcher: Marcher::SphereTrace,
            tree: unit_sphere(),
            march: march_with(|march| march.relaxation = 1.9),
            ray: (Vec3::new(0.0, 0.0, -5.0), Vec3::new(0.0, 0.0, 2.0)),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 2.0,
            most_evaluations: Some(3),
        }
        .into(),
        MarchQuestion {
            name: "march-over-relaxed-keeps-relaxing",
            section: RELAX_12,
            says: "Relaxation 1.6 down onto the ground (the half space y < 0) from (0, 0.1, 0) along (2, -0.2, 0), 5.7 degrees above it: each step of 1.6 r ends where the new ball and the last overlap (r + r' > 1.6 r), so no step is undone, and the march lands at t = 0.5 in 41 evaluations, where safe steps take 67.",
            marcher: Marcher::SphereTrace,
            tree: ground(),
            march: march_with(|march| march.relaxation = 1.6),
            ray: (Vec3::new(0.0, 0.1, 0.0), Vec3::new(2.0, -0.2, 0.0)),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 12.0,
            most_evaluations: Some(RELAXED_GROUND_BUDGET),
        }
        .into(),
        MarchQuestion {
            name: "march-over-relaxed-head-on",
            section: RELAX_12,
            says: "Relaxation 1.5 straight down onto the ground from (0, 1, 0): the relaxed step, 1.5, ends 0.5 below the surface, where the balls of radius 1 and 0.5 only touch (1 + 0.5 = 1.5, the step). Touching balls leave out the point where they touch, and that point is the surface: a gap, so go back to t = 1 and hit there, in 3 evaluations (with r_last + r < step the march goes on below the ground and never comes back).",
            marcher: Marcher::SphereTrace,
            tree: ground(),
            march: march_with(|march| march.relaxation = 1.5),
            ray: (Vec3::Y, Vec3::NEG_Y),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 2.0,
            most_evaluations: Some(3),
        }
        .into(),
        MarchQuestion {
            name: "march-over-relaxed-relaxes-no-more",
            section: RELAX_12,
            says: "Relaxation 1.5 onto the ground from (0, 1, 0) along (0, -1, 2), 26.6 degrees above it (sin = 0.447): a relaxed step 1.5 h from height h leaves 1 - 1.5 x 0.447 = 0.33 h, and h + 0.33 h < 1.5 h: a gap at the first step, and at every step after it. After going back, relax no more: safe steps, each keeping 1 - 0.447 = 0.553 of the height, land within the cone in 17 evaluations; a march that relaxes again after each step back wastes an evaluation on every gap, 24 in all.",
            marcher: Marcher::SphereTrace,
            tree: ground(),
            march: march_with(|march| march.relaxation = 1.5),
            ray: (Vec3::Y, Vec3::new(0.0, -1.0, 2.0)),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 2.5,
            most_evaluations: Some(NO_MORE_RELAXING_BUDGET),
        }
        .into(),
        MarchQuestion {
            name: "march-cone-in-distance",
            section: TOLERANCE_12,
            says: "The ground from (0, 1, 0) along (0.15, -0.2, 0), a direction of length 0.25, with tolerance 0.1: the cone is tolerance t |d| wide, a distance. At t = 4 the ray is 0.2 above the ground, more than the cone's 0.1 x 4 x 0.25 = 0.1; at t = 4.8 it is 0.04 above, less than 0.12: a hit at t = 4.8, the surface being at t = 5. A cone of tolerance t alone, 0.4 at t = 4, stops there, 20% short.",
            marcher: Marcher::SphereTrace,
            tree: ground(),
            march: march_with(|march| march.tolerance = 0.1),
            ray: (Vec3::Y, Vec3::new(0.15, -0.2, 0.0)),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 1.25,
            most_evaluations: Some(8),
        }
        .into(),
        MarchQuestion {
            name: "march-gives-up-after-its-budget",
            section: TRACE_12,
            says: "The ray of march-over-relaxed-keeps-relaxing, 5.7 degrees above the ground, with safe steps and max_steps = 32: each step keeps 0.9 of the height (1 - sin 5.7 degrees), so landing within the cone takes 67 evaluations, and the march gives up after 32 of them: no hit. The budget is the setting's, not 256.",
            marcher: Marcher::SphereTrace,
            tree: ground(),
            march: march_with(|march| march.max_steps = 32),
            ray: (Vec3::new(0.0, 0.1, 0.0), Vec3::new(2.0, -0.2, 0.0)),
            range: (0.0, INF),
            expect: Expect::Miss,
            cones: 0.0,
            most_evaluations: Some(33),
        }
        .into(),
        newton(
            "newton-first-iterate-on-a-torus-ray",
            "On the ray from (-3, 0, 0) along +x, the torus of radii 1 and 0.25 has the quartic g(t) = ((t - 3)^2 + 0.9375)^2 - 4 (t - 3)^2. One iteration from the bracket's low end t = 1.5: g = 1.16015625, g' = -7.125, so t = 1.5 + 0.16283 = 1.66283.",
            torus_ray.clone(),
            (1.5, 2.0),
            1,
            first_iterate(&torus_ray, (1.5, 2.0)),
            1e-4,
        ),
        newton(
            "newton-step-out-of-the-bracket-bisects",
            "g(t) = t^2 - 2 in [0.1, 2]: Newton from 0.1 goes to 10.05, outside the bracket, so the step is the midpoint, 1.05.",
            quadratic.clone(),
            (0.1, 2.0),
            1,
            1.05,
            1e-5,
        ),
        newton(
            "newton-step-below-the-bracket-bisects",
            "g(t) = 1 + t - t^2 in [0, 2] (g(0) = 1, g(2) = -1): Newton from 0, where g' = 1, goes back to -1, below the bracket, so the step is the midpoint, 1.",
            NewtonFunction::Polynomial(vec![1.0, 1.0, -1.0]),
            (0.0, 2.0),
            1,
            1.0,
            1e-5,
        ),
        newton(
            "newton-flat-slope-bisects",
            "g(t) = t^2 - 2 in [0, 2]: the slope at 0 is 0, Newton's step is infinite, and the midpoint 1 is taken instead.",
            quadratic.clone(),
            (0.0, 2.0),
            1,
            1.0,
            1e-5,
        ),
        newton(
            "newton-doubles-its-digits",
            "g(t) = t^2 - 2 in [1, 2]: 1.5, 1.41667, 1.414216, 1.41421356: four Newton steps reach sqrt(2) to f32's precision, where five halvings of the bracket leave it 1/32 wide and its midpoint, 1.40625, still 0.008 off.",
            quadratic.clone(),
            (1.0, 2.0),
            5,
            std::f64::consts::SQRT_2,
            1e-6,
        ),
        newton(
            "newton-bracket-only-shrinks",
            "g(t) = t^3 - 6 in [-1, 2]: Newton from -1 (g = -7, g' = 3) goes to 1.3333, where g = -3.63 is still negative: the bracket shrinks to [1.3333, 2]. Newton from there goes to 2.014, past 2: the step is the midpoint of the bracket as it is now, 1.6667, not the first bracket's 0.5. Every point where g is evaluated must be in the bracket as it has shrunk; the iterations reach the cube root of 6, 1.8171206.",
            NewtonFunction::Polynomial(vec![-6.0, 0.0, 0.0, 1.0]),
            (-1.0, 2.0),
            8,
            6f64.cbrt(),
            1e-6,
        ),
        Case::new(
            "newton-stops-when-its-step-is-small",
            NEWTON_12,
            "g(t) = t^2 - 2 in [1, 2] with tolerance 0.001 and up to 40 iterations: the steps are 0.5, 0.083, 0.0025 and 2e-6; the last is below the tolerance, so the method stops there, after 5 evaluations of g, with sqrt(2) to f32's precision.",
            CaseKind::Newton(NewtonCase {
                function: quadratic.clone(),
                bracket: (1.0, 2.0),
                tolerance: 1e-3,
                max_iterations: 40,
                expect: std::f64::consts::SQRT_2,
                within: 1e-6,
                most_evaluations: Some(7),
            }),
        ),
        newton(
            "newton-root-at-the-low-end",
            "g(t) = t - 1 in [1, 3]: g is already 0 at the low end, which is the root.",
            NewtonFunction::Polynomial(vec![-1.0, 1.0]),
            (1.0, 3.0),
            8,
            1.0,
            1e-6,
        ),
        newton(
            "newton-zero-at-a-flat-low-end",
            "g(t) = (t - 1)^3 = t^3 - 3 t^2 + 3 t - 1 in [1, 3]: g is exactly 0 at the low end, so stop there, t = 1. Its slope is 0 too: Newton's step would be 0 / 0, bisect to 2, and creep back toward 1 a third of the way each time, still 0.06 off after 8 iterations.",
            NewtonFunction::Polynomial(vec![-1.0, 3.0, -3.0, 1.0]),
            (1.0, 3.0),
            8,
            1.0,
            1e-6,
        ),
        MarchQuestion {
            name: "intersect-a-torus-through-its-tube",
            section: NEWTON_12,
            says: "The torus of radii 1 and 0.25 around y, from (-3, 0, 0) along +x: the ray enters the tube at x = -1.25, t = 1.75.",
            marcher: Marcher::Intersect,
            tree: ring(),
            march: March::default(),
            ray: (Vec3::new(-3.0, 0.0, 0.0), Vec3::X),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 0.0,
            most_evaluations: None,
        }
        .into(),
        MarchQuestion {
            name: "intersect-refines-a-coarse-march",
            section: NEWTON_12,
            says: "With a coarse tolerance of 0.01 the march stops up to 1% short of the unit sphere, seen from (0.2, 0.3, -4) along +z; Newton in the bracket just past it pins the hit to the surface.",
            marcher: Marcher::Intersect,
            tree: unit_sphere(),
            march: march_with(|march| march.tolerance = 0.01),
            ray: (Vec3::new(0.2, 0.3, -4.0), Vec3::Z),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 0.0,
            most_evaluations: None,
        }
        .into(),
        MarchQuestion {
            name: "intersect-without-newton-is-the-march",
            section: NEWTON_12,
            says: "The same with newton = false: the march's own answer, within its cone before the surface.",
            marcher: Marcher::Intersect,
            tree: unit_sphere(),
            march: march_with(|march| {
                march.tolerance = 0.01;
                march.newton = false;
            }),
            ray: (Vec3::new(0.2, 0.3, -4.0), Vec3::Z),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 3.0,
            most_evaluations: None,
        }
        .into(),
        march_stops_short(),
        MarchQuestion {
            name: "intersect-thinner-than-the-cone",
            section: NEWTON_12,
            says: "A shell 0.002 thick (the unit sphere less the sphere of radius 0.998) around a ball of radius 0.5, from (0.1, 0.1, -5) along +z with tolerance 0.1: the march stops on the shell, near t = 4.01. One cone width on (0.4), the ray is in the hollow, where g = 0.107 has grown, not shrunk: the shell is thinner than the cone, so stop searching and let the march's answer stand. Creeping on to t = 4.81 finds g = -0.26 inside the ball, and a root at t = 4.52 that the shell hides.",
            marcher: Marcher::Intersect,
            tree: shell_around_a_ball(),
            march: march_with(|march| march.tolerance = 0.1),
            ray: (Vec3::new(0.1, 0.1, -5.0), Vec3::Z),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 1.0,
            most_evaluations: None,
        }
        .into(),
        MarchQuestion {
            name: "intersect-from-the-surface-outward",
            section: NEWTON_12,
            says: "From (0, 0, -1), a point of the unit sphere, along +z with t_min = 0.001 (a ray leaving a surface): the ray enters the sphere where it starts, at t = 0, before t_min; the first surface past t_min is where it leaves, t = 2.",
            marcher: Marcher::Intersect,
            tree: unit_sphere(),
            march: March::default(),
            ray: (Vec3::NEG_Z, Vec3::Z),
            range: (1e-3, INF),
            expect: Expect::Hit,
            cones: 0.0,
            most_evaluations: None,
        }
        .into(),
        MarchQuestion {
            name: "intersect-beyond-t-max-misses",
            section: NEWTON_12,
            says: "The torus ray of intersect-a-torus-through-its-tube, from (-3, 0, 0) along +x, with t_max = 1.5: the tube is at t = 1.75, beyond t_max: no hit.",
            marcher: Marcher::Intersect,
            tree: ring(),
            march: March::default(),
            ray: (Vec3::new(-3.0, 0.0, 0.0), Vec3::X),
            range: (0.0, 1.5),
            expect: Expect::Miss,
            cones: 0.0,
            most_evaluations: None,
        }
        .into(),
        normal(
            "normal-analytic-on-a-sphere",
            "The unit sphere at (0.6, 0.8, 0): its gradient, (0.6, 0.8, 0).",
            unit_sphere(),
            (NormalMethod::Analytic, 1e-3),
            Vec3::new(0.6, 0.8, 0.0),
            1e-3,
        ),
        normal(
            "normal-central-on-a-torus",
            "Central differences with h = 0.001 at a point of the torus of radii 1 and 0.25, 0.7 radians around its axis and 1.1 around its tube: (f(p + h x) - f(p - h x), ...) made unit.",
            ring(),
            (NormalMethod::Central, 1e-3),
            on_ring(0.7, 1.1),
            1e-3,
        ),
        normal(
            "normal-tetrahedron-on-a-torus",
            "The same point of the torus moved to (0, 2, 0), by the tetrahedron's 4 evaluations: the sum of k f(p + h k) over its corners k = (1, -1, -1), (-1, -1, 1), (-1, 1, -1), (1, 1, 1) (or their opposites), made unit: the gradient's direction to an error of order h times the curvature, 0.0021 radians from the true normal here, with either set of corners. The case compares with the same difference in f64, within 0.01.",
            Sdf::Translate {
                offset: RAISED,
                shape: Box::new(ring()),
            },
            (NormalMethod::Tetrahedron, 1e-3),
            on_ring(0.7, 1.1) + RAISED,
            1e-2,
        ),
        normal(
            "normal-central-with-a-wide-step",
            "Central differences with h = 0.1 on the box of half size 1, at (1, 0.95, 0), 0.05 from an edge: the step reaches past the edge, and the answer is the blurred normal that h gives, not the face's.",
            Sdf::Box {
                center: Vec3::ZERO,
                half_size: Vec3::ONE,
            },
            (NormalMethod::Central, 0.1),
            Vec3::new(1.0, 0.95, 0.0),
            1e-3,
        ),
        normal(
            "normal-analytic-ignores-the-step",
            "The same box and point with normals = \"analytic\" and normal_step = 0.1: the formulas' gradient, the face's normal (1, 0, 0), which no step blurs.",
            Sdf::Box {
                center: Vec3::ZERO,
                half_size: Vec3::ONE,
            },
            (NormalMethod::Analytic, 0.1),
            Vec3::new(1.0, 0.95, 0.0),
            1e-3,
        ),
        normal(
            "normal-tetrahedron-with-a-wide-step",
            "The same box and point by the tetrahedron with h = 0.1: the sum of k f(p + 0.1 k) over its corners (or their opposites), made unit: blurred by the edge as that step blurs it: (0.776, 0.48, -0.41) with the lesson's corners, leaning the other way with the opposite ones; not the face's normal, nor the central difference's (0.949, 0.316, 0).",
            Sdf::Box {
                center: Vec3::ZERO,
                half_size: Vec3::ONE,
            },
            (NormalMethod::Tetrahedron, 0.1),
            Vec3::new(1.0, 0.95, 0.0),
            1e-3,
        ),
        normal(
            "normal-analytic-made-unit",
            "The bumpy unit sphere (bumps of amplitude 0.25 and frequency 8) at (0.6, 0.8, 0): the bumps add 0.25 x 8 x sin(4.8) sin(6.4) cos(0) = -0.232 to the sphere's gradient along z, so the gradient (0.6, 0.8, -0.232) is 1.026 long, and the normal is that made unit, (0.584, 0.779, -0.226).",
            bumpy(),
            (NormalMethod::Analytic, 1e-3),
            Vec3::new(0.6, 0.8, 0.0),
            1e-3,
        ),
    ]
}

/// Chapter 12's hard cases.
///
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn robustness() -> Vec<Case> {
    let torus_ray = NewtonFunction::TorusAlongRay {
        major: 1.0,
        minor: 0.25,
        origin: Vec3::new(-3.0, 0.0, 0.0),
        dir: Vec3::X,
    };
    robust(vec![
        MarchQuestion {
            name: "intersect-far-small-sphere",
            section: TOLERANCE_12,
            says: "A sphere of radius 0.5 at (0.3, 0, 10000), from the origin along +z: at 10,000 units f32 spaces points 0.001 apart, so an absolute tolerance of 0.0001 is never met; the cone's, 1 unit there, is. The sphere is thinner than the cone, so no bracket closes, and the march's answer stands anywhere in its cone before the surface (t = 9999.5 for a march from the origin, 9999.58 for one from the sphere's box).",
            marcher: Marcher::Intersect,
            tree: Sdf::Sphere {
                center: Vec3::new(0.3, 0.0, 10000.0),
                radius: 0.5,
            },
            march: March::default(),
            ray: (Vec3::ZERO, Vec3::Z),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 2.0,
            most_evaluations: None,
        }
        .into(),
        MarchQuestion {
            name: "intersect-a-thin-shell",
            section: HARD_12,
            says: "A shell 0.002 thick (the unit sphere less the sphere of radius 0.998), from (0.1, 0.1, -5) along +z: stepping by a fixed 0.01 could jump over it; steps by the function never do.",
            marcher: Marcher::Intersect,
            tree: thin_shell(),
            march: March::default(),
            ray: (Vec3::new(0.1, 0.1, -5.0), Vec3::Z),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 0.0,
            most_evaluations: None,
        }
        .into(),
        MarchQuestion {
            name: "intersect-a-thin-shell-at-a-slant",
            section: HARD_12,
            says: "The same shell from (0.6, 0.3, -5) along (0, 0, 16), meeting it 42 degrees from its normal: the march stops short, within the cone, and the bracket's search must creep on by cone widths in t (tolerance t), not by the cone's width in distance taken for a step in t (tolerance t |d|, 16 times as far), which steps over both of the shell's surfaces, 0.0027 apart along the ray.",
            marcher: Marcher::Intersect,
            tree: thin_shell(),
            march: March::default(),
            ray: (Vec3::new(0.6, 0.3, -5.0), Vec3::new(0.0, 0.0, 16.0)),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 0.0,
            most_evaluations: None,
        }
        .into(),
        MarchQuestion {
            name: "intersect-refines-a-bumpy-surface",
            section: HARD_12,
            says: "The bumpy sphere (L = 3) with a coarse tolerance of 0.01, from (0.3, 0.2, -3) along (0, 0.1, 2): the march stops well short on a curved bump, and one Newton step is not enough; iterate until the step is below the tolerance you were given.",
            marcher: Marcher::Intersect,
            tree: bumpy(),
            march: march_with(|march| march.tolerance = 0.01),
            ray: (Vec3::new(0.3, 0.2, -3.0), Vec3::new(0.0, 0.1, 2.0)),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 0.0,
            most_evaluations: None,
        }
        .into(),
        MarchQuestion {
            name: "intersect-a-root-at-t-max",
            section: HARD_12,
            says: "Down onto the ground at 45 degrees, from (0, 1, 0) along (1, -1, 0), with t_max = 1, exactly where the ray reaches it: a hit must have t < t_max, so either no hit or a point of the march's cone before it.",
            marcher: Marcher::Intersect,
            tree: ground(),
            march: March::default(),
            ray: (Vec3::Y, Vec3::new(1.0, -1.0, 0.0)),
            range: (0.0, 1.0),
            expect: Expect::Either,
            cones: 0.0,
            most_evaluations: None,
        }
        .into(),
        MarchQuestion {
            name: "intersect-from-inside-the-tube",
            section: HARD_12,
            says: "From (1, 0, 0), on the circle at the heart of the torus's tube, along +x: the exit is 0.25 away.",
            marcher: Marcher::Intersect,
            tree: ring(),
            march: March::default(),
            ray: (Vec3::X, Vec3::X),
            range: (0.0, INF),
            expect: Expect::Hit,
            cones: 0.0,
            most_evaluations: None,
        }
        .into(),
        MarchQuestion {
            name: "intersect-tangent-to-the-torus",
            section: HARD_12,
            says: "From (-3, 0.25, 0) along +x the ray touches the top of the tube at x = -1 and x = 1: rounding decides, but a hit must be on the surface.",
            marcher: Marcher::Intersect,
            tree: ring(),
            march: March::default(),
            ray: (Vec3::new(-3.0, 0.25, 0.0), Vec3::X),
            range: (0.0, INF),
            expect: Expect::Either,
            cones: 0.0,
            most_evaluations: None,
        }
        .into(),
        MarchQuestion {
            name: "intersect-grazing-a-silhouette",
            section: HARD_12,
            says: "From (0, 0.99999, -5) along +z, a hundred-thousandth inside the unit sphere's outline: the steps shrink as the ray skims the surface, and the march must still end (a hit on the surface, or the step budget's miss).",
            marcher: Marcher::Intersect,
            tree: unit_sphere(),
            march: March::default(),
            ray: (Vec3::new(0.0, 0.99999, -5.0), Vec3::Z),
            range: (0.0, INF),
            expect: Expect::Either,
            cones: 0.0,
            most_evaluations: Some(400),
        }
        .into(),
        MarchQuestion {
            name: "intersect-nan-direction",
            section: HARD_12,
            says: "A direction with a NaN: the function is NaN at once, no comparison holds, and the march must stop with no hit rather than spend its budget.",
            marcher: Marcher::Intersect,
            tree: unit_sphere(),
            march: March::default(),
            ray: (Vec3::new(0.0, 0.0, -5.0), Vec3::new(f32::NAN, 0.0, 1.0)),
            range: (0.0, INF),
            expect: Expect::Miss,
            cones: 0.0,
            most_evaluations: Some(8),
        }
        .into(),
        MarchQuestion {
            name: "intersect-zero-direction",
            section: HARD_12,
            says: "A zero direction goes nowhere: no hit, at once.",
            marcher: Marcher::Intersect,
            tree: unit_sphere(),
            march: March::default(),
            ray: (Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO),
            range: (0.0, INF),
            expect: Expect::Miss,
            cones: 0.0,
            most_evaluations: Some(8),
        }
        .into(),
        MarchQuestion {
            name: "intersect-parallel-to-a-plane-ends",
            section: HARD_12,
            says: "Along a half space's surface, 1 above it: the function stays 1 and t grows by 1 a step; with t_max = inf only the step budget stops the march.",
            marcher: Marcher::SphereTrace,
            tree: Sdf::Plane {
                point: Vec3::ZERO,
                normal: Vec3::Y,
            },
            march: March::default(),
            ray: (Vec3::Y, Vec3::X),
            range: (0.0, INF),
            expect: Expect::Miss,
            cones: 0.0,
            most_evaluations: Some(300),
        }
        .into(),
        newton(
            "newton-stays-in-its-bracket-on-the-torus",
            "The torus ray from (-3, 0, 0) along +x, bracket [2, 2.3] around the root t = 2.25 where it leaves the tube: at t = 2 the slope is 0.25, and a free Newton step jumps past 2.25 to t = 2.98, beside g's local maximum at t = 3 (the middle of the hole, g' = 0); the next step flies to t = -10.25 and the iteration ends on the other root, 1.75. The bracket keeps it on t = 2.25.",
            torus_ray,
            (2.0, 2.3),
            16,
            2.25,
            1e-5,
        ),
    ])
}
