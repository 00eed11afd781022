//! Every chapter's checkpoint and robustness cases, as data.
//!
//! Checkpoints are well-conditioned questions whose answers a student can
//! work out by hand; robustness cases are the hard inputs of
//! tests/hard_cases.rs (grazing and tangent rays, far and huge spheres,
//! origins on surfaces, the critical angle, NaN and infinite input), where
//! only a numerically careful formula is right. Expected intersection
//! parameters and directions come from `exact` (f64, separate formulas);
//! shading cases compare with raylab's reference chapters on the same point.

use glam::Vec3;

use super::cases::{Case, CaseKind, ExpectT, Level, SampleRule, Shading, TreeShape, vec};
use super::exact::{self, wide};
use crate::bvh::{BvhOptions, SplitRule};
use crate::course::PhongTerms;
use crate::{Material, Plane, Ray, Sampling, Shape, Sphere};

const INF: f32 = f32::INFINITY;

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

fn robust(cases: Vec<Case>) -> Vec<Case> {
    cases
        .into_iter()
        .map(|case| Case {
            level: Level::Robustness,
            ..case
        })
        .collect()
}

/// What an intersection case expects, before the exact `t` is filled in.
#[derive(Clone, Copy)]
enum E {
    Hit,
    Miss,
    Either,
}

#[allow(clippy::too_many_arguments)]
fn plane_case(
    name: &'static str,
    section: &'static str,
    says: &str,
    point: Vec3,
    normal: Vec3,
    ray: (Vec3, Vec3),
    range: (f32, f32),
    expect: E,
) -> Case {
    let plane = Plane::new(point, normal);
    let expect = match expect {
        E::Hit => ExpectT::Hit(
            exact::plane(
                wide(plane.point()),
                wide(plane.normal()),
                wide(ray.0),
                wide(ray.1),
                f64::from(range.0),
                f64::from(range.1),
            )
            .unwrap_or(f64::NAN),
        ),
        E::Miss => ExpectT::Miss,
        E::Either => ExpectT::Either,
    };
    Case::new(
        name,
        section,
        says,
        CaseKind::Plane {
            point,
            normal,
            ray: Ray::new(ray.0, ray.1),
            t_min: range.0,
            t_max: range.1,
            expect,
        },
    )
}

#[allow(clippy::too_many_arguments)]
fn sphere_case(
    name: &'static str,
    section: &'static str,
    says: &str,
    center: Vec3,
    radius: f32,
    ray: (Vec3, Vec3),
    range: (f32, f32),
    expect: E,
) -> Case {
    let expect = match expect {
        E::Hit => ExpectT::Hit(
            exact::sphere(
                wide(center),
                f64::from(radius),
                wide(ray.0),
                wide(ray.1),
                f64::from(range.0),
                f64::from(range.1),
            )
            .unwrap_or(f64::NAN),
        ),
        E::Miss => ExpectT::Miss,
        E::Either => ExpectT::Either,
    };
    Case::new(
        name,
        section,
        says,
        CaseKind::Sphere {
            center,
            radius,
            ray: Ray::new(ray.0, ray.1),
            t_min: range.0,
            t_max: range.1,
            expect,
        },
    )
}

const ALL: (f32, f32) = (0.0, INF);

// ---------------------------------------------------------------------------
// Chapter 1: planes.

const EQUATION_1: &str = "The equation";
const CODE_1: &str = "The code: `intersect_plane`";

pub fn chapter_1() -> Vec<Case> {
    let floor = (Vec3::ZERO, Vec3::Y);
    let p = |name, section, says, plane: (Vec3, Vec3), ray, range, expect| {
        plane_case(name, section, says, plane.0, plane.1, ray, range, expect)
    };
    vec![
        p(
            "plane-straight-down",
            EQUATION_1,
            "a ray from (0, 2, 0) straight down, along (0, -1, 0), meets the floor y = 0 \
             at t = 2: t = dot(point - origin, n) / dot(dir, n) = (0 - 2) / -1",
            floor,
            (v(0.0, 2.0, 0.0), -Vec3::Y),
            ALL,
            E::Hit,
        ),
        p(
            "plane-parallel",
            EQUATION_1,
            "a ray from (0, 1, -5) along +z runs parallel to the floor y = 0 \
             (dot(dir, n) = 0): expected no hit",
            floor,
            (v(0.0, 1.0, -5.0), Vec3::Z),
            ALL,
            E::Miss,
        ),
        p(
            "plane-direction-not-unit",
            EQUATION_1,
            "a ray from (0, 3, 0) along (4, -3, 0) meets the floor y = 0 at the point (4, 0, 0), \
             that is at t = 1: t counts lengths of the direction, not scene units",
            floor,
            (v(0.0, 3.0, 0.0), v(4.0, -3.0, 0.0)),
            ALL,
            E::Hit,
        ),
        p(
            "plane-behind",
            EQUATION_1,
            "a ray from (0, 1, 0) going up, along (0, 1, 0), has the floor y = 0 behind it \
             (t = -1): expected no hit",
            floor,
            (v(0.0, 1.0, 0.0), Vec3::Y),
            ALL,
            E::Miss,
        ),
        p(
            "plane-from-behind",
            EQUATION_1,
            "planes are two-sided: a ray from the origin along (0, 0, 0.5) meets the wall z = 5 \
             (normal +z, facing the other way) at t = 10",
            (v(0.0, 0.0, 5.0), Vec3::Z),
            (Vec3::ZERO, v(0.0, 0.0, 0.5)),
            ALL,
            E::Hit,
        ),
        p(
            "plane-beyond-t-max",
            EQUATION_1,
            "a ray from (0, 1, 0) straight down meets the floor at t = 1, beyond t_max = 0.5: \
             expected no hit",
            floor,
            (v(0.0, 1.0, 0.0), -Vec3::Y),
            (0.0, 0.5),
            E::Miss,
        ),
        p(
            "plane-at-t-max",
            EQUATION_1,
            "a ray from (0, 1, 0) straight down meets the floor at t = 1 exactly, and t must be \
             strictly less than t_max = 1: expected no hit",
            floor,
            (v(0.0, 1.0, 0.0), -Vec3::Y),
            (0.0, 1.0),
            E::Miss,
        ),
        p(
            "plane-before-t-min",
            EQUATION_1,
            "a ray from (0, 1, 0) straight down meets the floor at t = 1, before t_min = 2 (the \
             caller wants hits beyond 2 only): expected no hit",
            floor,
            (v(0.0, 1.0, 0.0), -Vec3::Y),
            (2.0, INF),
            E::Miss,
        ),
        p(
            "plane-origin-on-it",
            EQUATION_1,
            "a ray starting on the floor, from (0, 0, 0) along (0, -1, 0), meets it at t = 0, \
             and t must be strictly greater than t_min = 0: expected no hit",
            floor,
            (Vec3::ZERO, -Vec3::Y),
            ALL,
            E::Miss,
        ),
        p(
            "plane-slanted",
            EQUATION_1,
            "a ray from the origin along (1, 1, 1) meets the plane through (1, 2, 3) with normal \
             (1, 1, 1) at t = 6 / 3 = 2 (the normal's length does not matter)",
            (v(1.0, 2.0, 3.0), Vec3::ONE),
            (Vec3::ZERO, Vec3::ONE),
            ALL,
            E::Hit,
        ),
    ]
}

pub fn chapter_1_robustness() -> Vec<Case> {
    let floor = (Vec3::ZERO, Vec3::Y);
    let p = |name, says, plane: (Vec3, Vec3), ray, range, expect| {
        plane_case(name, CODE_1, says, plane.0, plane.1, ray, range, expect)
    };
    robust(vec![
        p(
            "plane-nearly-parallel",
            "nearly parallel, slope 1e-6, from (0, 1, 0): a genuine hit at t = 1e6",
            floor,
            (v(0.0, 1.0, 0.0), v(1.0, -1e-6, 0.0)),
            ALL,
            E::Hit,
        ),
        p(
            "plane-parallel-within-rounding",
            "slope 1e-8: parallel as far as f32 can tell; either answer, but a hit must lie on the plane",
            floor,
            (v(0.0, 1.0, 0.0), v(1.0, -1e-8, 0.0)),
            ALL,
            E::Either,
        ),
        p(
            "plane-tiny-direction",
            "a direction of length 1e-20 straight down from (0, 1, 0): a hit at t = 1e20 \
             (a fixed 'parallel' threshold such as 1e-6 on dot(dir, n) wrongly misses)",
            floor,
            (v(0.0, 1.0, 0.0), v(0.0, -1e-20, 0.0)),
            ALL,
            E::Hit,
        ),
        p(
            "plane-grazing-far",
            "grazing ray 1e4 along and 1 above the floor: hit at t = 1",
            floor,
            (v(-1e4, 1.0, 0.0), v(1e4, -1.0, 0.0)),
            ALL,
            E::Hit,
        ),
        p(
            "plane-far-away",
            "a wall 1e6 away: t = 1e6",
            (v(0.0, 0.0, 1e6), -Vec3::Z),
            (Vec3::ZERO, Vec3::Z),
            ALL,
            E::Hit,
        ),
        p(
            "plane-large-coordinates",
            "slanted plane through (1e5, 1e5, 1e5) with normal (1, 2, 3), seen from close by",
            (v(1e5, 1e5, 1e5), v(1.0, 2.0, 3.0)),
            (v(1e5 - 10.0, 1e5 + 3.0, 1e5 - 7.0), v(0.3, 0.1, 0.9)),
            ALL,
            E::Hit,
        ),
        p(
            "plane-in-the-plane",
            "a ray lying in the floor (0 / 0): no hit",
            floor,
            (Vec3::ZERO, v(1.0, 0.0, 1.0)),
            ALL,
            E::Miss,
        ),
        p(
            "plane-zero-normal",
            "a plane made with a zero normal (its fields are NaN): no hit",
            (Vec3::ZERO, Vec3::ZERO),
            (v(0.0, 1.0, 0.0), -Vec3::Y),
            ALL,
            E::Miss,
        ),
        p(
            "plane-nan-origin",
            "a NaN in the origin: no hit",
            floor,
            (v(0.0, f32::NAN, 0.0), -Vec3::Y),
            ALL,
            E::Miss,
        ),
        p(
            "plane-infinite-direction",
            "an infinite direction (inf / inf): no hit",
            floor,
            (v(0.0, 1.0, 0.0), v(0.0, -INF, 0.0)),
            ALL,
            E::Miss,
        ),
        p(
            "plane-infinite-origin",
            "an infinite origin: no hit",
            floor,
            (v(0.0, INF, 0.0), -Vec3::Y),
            ALL,
            E::Miss,
        ),
    ])
}

// ---------------------------------------------------------------------------
// Chapter 2: spheres.

const EQUATION_2: &str = "The equation";
const ROOTS_2: &str = "Two ways to compute the roots";

pub fn chapter_2() -> Vec<Case> {
    let ball = (v(0.0, 0.0, 5.0), 1.0);
    let s = |name, section, says, sphere: (Vec3, f32), ray, range, expect| {
        sphere_case(name, section, says, sphere.0, sphere.1, ray, range, expect)
    };
    vec![
        s(
            "sphere-nearer-root",
            EQUATION_2,
            "a ray from the origin along +z meets the unit sphere centred at (0, 0, 5) twice, \
             at t = 4 and t = 6; from outside, the hit is the nearer: expected t = 4",
            ball,
            (Vec3::ZERO, Vec3::Z),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-direction-not-unit",
            EQUATION_2,
            "the same ray with direction (0, 0, 2): a = dot(dir, dir) = 4, and the hit is at t = 2 \
             (t counts lengths of the direction; a quadratic that assumes a = 1 gets this wrong)",
            ball,
            (Vec3::ZERO, v(0.0, 0.0, 2.0)),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-origin-inside",
            EQUATION_2,
            "from the centre (0, 0, 5) along +z the roots are -1 and 1; the one in front, t = 1, \
             is the hit (from inside, the far root)",
            ball,
            (v(0.0, 0.0, 5.0), Vec3::Z),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-behind",
            EQUATION_2,
            "a ray from the origin along -z has the sphere at (0, 0, 5) behind it (roots -6 and -4): \
             expected no hit",
            ball,
            (Vec3::ZERO, -Vec3::Z),
            ALL,
            E::Miss,
        ),
        s(
            "sphere-beside",
            EQUATION_2,
            "a ray from (2, 0, 0) along +z passes 2 from the centre of the unit sphere at (0, 0, 5): \
             expected no hit (negative discriminant)",
            ball,
            (v(2.0, 0.0, 0.0), Vec3::Z),
            ALL,
            E::Miss,
        ),
        s(
            "sphere-off-axis",
            EQUATION_2,
            "a ray from (0, 0.6, 0) along +z meets the unit sphere at (0, 0, 5) where \
             z = 5 - sqrt(1 - 0.36) = 4.2: expected t = 4.2",
            ball,
            (v(0.0, 0.6, 0.0), Vec3::Z),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-near-root-below-t-min",
            EQUATION_2,
            "from the origin along +z with t_min = 4.5: the near root 4 is too close, \
             the far root t = 6 is the hit",
            ball,
            (Vec3::ZERO, Vec3::Z),
            (4.5, INF),
            E::Hit,
        ),
        s(
            "sphere-beyond-t-max",
            EQUATION_2,
            "from the origin along +z with t_max = 3.9: both roots (4 and 6) are beyond it: \
             expected no hit",
            ball,
            (Vec3::ZERO, Vec3::Z),
            (0.0, 3.9),
            E::Miss,
        ),
        s(
            "sphere-inside-heading-back",
            EQUATION_2,
            "from (0, 0, 4.5), inside, along -z: roots 0.5 and -1.5; expected t = 0.5",
            ball,
            (v(0.0, 0.0, 4.5), -Vec3::Z),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-inside-slanted",
            EQUATION_2,
            "from the origin along (1, 1, 0), inside the sphere of radius 5 at (3, 0, 0): \
             t^2 - 3t - 8 = 0, so t = (3 + sqrt(41)) / 2 = 4.7016",
            (v(3.0, 0.0, 0.0), 5.0),
            (Vec3::ZERO, v(1.0, 1.0, 0.0)),
            ALL,
            E::Hit,
        ),
        // "Behind" means below t_min, not below 0: code that skips a sphere
        // whose roots are both negative is right only while t_min >= 0.
        s(
            "sphere-behind-negative-t-min",
            EQUATION_2,
            "a ray from the origin along -z, with t_min = -10: the sphere at (0, 0, 5) is \
             behind the origin (roots -6 and -4) but not behind t_min; the point at t_min is \
             outside and in front of it, so the hit is the nearer root: expected t = -6",
            ball,
            (Vec3::ZERO, -Vec3::Z),
            (-10.0, INF),
            E::Hit,
        ),
        s(
            "sphere-at-t-max",
            EQUATION_2,
            "from the origin along +z with t_max = 4: the near root is exactly 4, and the \
             interval (t_min, t_max) is open: expected no hit",
            ball,
            (Vec3::ZERO, Vec3::Z),
            (0.0, 4.0),
            E::Miss,
        ),
        s(
            "sphere-inside-at-t-max",
            EQUATION_2,
            "from the centre (0, 0, 5) along +z with t_max = 1: the far root is exactly 1, \
             not inside the open interval (0, 1): expected no hit",
            ball,
            (v(0.0, 0.0, 5.0), Vec3::Z),
            (0.0, 1.0),
            E::Miss,
        ),
    ]
}

pub fn chapter_2_robustness() -> Vec<Case> {
    let s = |name, says, sphere: (Vec3, f32), ray, range, expect| {
        sphere_case(name, ROOTS_2, says, sphere.0, sphere.1, ray, range, expect)
    };
    let tiny_far = (v(0.0, 0.0, 10.0), 1e-3);
    let unit_at_5 = (v(0.0, 0.0, 5.0), 1.0);
    let unit = (Vec3::ZERO, 1.0);
    robust(vec![
        s(
            "sphere-tiny-far-central",
            "a sphere of radius 1e-3 at (0, 0, 10), 1e4 radii away, central ray: b^2 - 4ac \
             cancels 8 digits (t = 9.999)",
            tiny_far,
            (Vec3::ZERO, Vec3::Z),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-tiny-far-half",
            "the same tiny far sphere, ray half a radius off centre",
            tiny_far,
            (Vec3::ZERO, v(5e-4, 0.0, 10.0)),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-tiny-far-grazing",
            "the same tiny far sphere, ray 0.9 radius off centre (grazing)",
            tiny_far,
            (Vec3::ZERO, v(9e-4, 0.0, 10.0)),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-tiny-far-miss",
            "the same tiny far sphere, ray 1.1 radius off centre: no hit",
            tiny_far,
            (Vec3::ZERO, v(1.1e-3, 0.0, 10.0)),
            ALL,
            E::Miss,
        ),
        s(
            "sphere-far-away",
            "a unit sphere 1e5 away (t = 99999)",
            (v(0.0, 0.0, 1e5), 1.0),
            (Vec3::ZERO, Vec3::Z),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-origin-on-surface-in",
            "origin exactly on the surface at (1, 0, 0), heading in: roots 0 and 2, \
             expected t = 2 (not a tiny rounding root)",
            unit,
            (v(1.0, 0.0, 0.0), -Vec3::X),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-origin-on-surface-out",
            "origin exactly on the surface at (1, 0, 0), heading out: roots -2 and 0: no hit",
            unit,
            (v(1.0, 0.0, 0.0), Vec3::X),
            ALL,
            E::Miss,
        ),
        s(
            "sphere-inside-near-surface",
            "origin inside, 1e-3 from the surface, heading out: t = 0.001",
            unit,
            (v(0.0, 0.0, 0.999), Vec3::Z),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-tangent",
            "an exactly tangent ray from (1, 0, 0) along +z: rounding decides, a hit must lie on the surface",
            unit_at_5,
            (v(1.0, 0.0, 0.0), Vec3::Z),
            ALL,
            E::Either,
        ),
        s(
            "sphere-near-tangent-inside",
            "a ray 1e-4 of the radius inside the tangent: a hit, t = 4.986",
            unit_at_5,
            (v(0.9999, 0.0, 0.0), Vec3::Z),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-near-tangent-outside",
            "a ray 1e-4 of the radius outside the tangent: no hit",
            unit_at_5,
            (v(1.0001, 0.0, 0.0), Vec3::Z),
            ALL,
            E::Miss,
        ),
        // The extreme-scale hits (this one, -1e20 and coordinates-1e20
        // below) are judged against `exact::sphere` like every robustness
        // hit: within ROUNDINGS u (|t| + S / (|d| cos)), S the size of the
        // scene (`cases::judge_t`). For these central rays that is 52 to 56
        // u of t, relative (3e-6), and no tighter on purpose: it is what the
        // stable formula guarantees itself (`root_error`, 16 u ((|oc| (1 +
        // r / W) + r) / |d| + |t|), about 60 u of t when the half chord W
        // is r), while the reference chapters land 0.2 to 1.2 u from the
        // exact root on the extreme-scale hits (measured).
        s(
            "sphere-ground-just-below",
            "from 0.003 above a ground sphere of radius 1e5, heading down at 17 degrees: \
             O - C rounds to a point on the surface and the f32 near root comes out 0, \
             not beyond t_min = 0, but the exact one is t = 0.0030006, the hit (not the far \
             side of the ground, t = 183486)",
            (v(0.0, -1e5, 0.0), 1e5),
            (v(0.3, 3e-3, -0.2), v(-0.3, -1.0, 0.0)),
            ALL,
            E::Hit,
        ),
        // Two rays that skim a large sphere and miss it by less than f32
        // can resolve at that size: the f32 roots come out real, and only
        // their error bound (`root_error`, large near tangency: it grows as
        // r / W, W the half chord) sends them to the f64 solve, which finds
        // no hit. A bound a few times too small trusts the false near root.
        // (Expected: no hit, as `exact::sphere` finds; the test
        // `skim_cases_miss_in_exact_arithmetic` below checks it.)
        s(
            "sphere-skim-over-ground",
            "from 0.0505 above the top of a ground sphere of radius 1e5, heading (1, -0.001, 0): \
             the ray would touch the sphere from a height of 0.05; from 0.0505 its line passes \
             5e-4 above it, no hit. f32 rounds O - C to multiples of 0.0078 and finds roots \
             66.05 and 139.53 around the tangent point t = 100",
            (v(0.0, -1e5, 0.0), 1e5),
            (v(0.0, 0.0505, 0.0), v(1.0, -0.001, 0.0)),
            ALL,
            E::Miss,
        ),
        s(
            "sphere-skim-over-hill",
            "from 0.05001 above the top of a sphere of radius 1000, heading (1, -0.01, 0): \
             the ray would touch the sphere from a height of 0.05; from 0.05001 its line passes \
             1.1e-5 above it, no hit. f32 finds two roots an ulp apart at t = 9.9995",
            (v(0.0, -1e3, 0.0), 1e3),
            (v(0.0, 0.05001, 0.0), v(1.0, -0.01, 0.0)),
            ALL,
            E::Miss,
        ),
        // The band case of `choose_root` from inside, where the error bound
        // is made of the radius and |t| (the origin is the centre, |O - C| =
        // 0): the f32 near root lands on t_min itself, and only a bound that
        // counts r / |d| and |t| sends it to the f64 solve.
        s(
            "sphere-centre-t-min-just-below",
            "from the centre of the unit sphere along (0, 0, 3), roots -1/3 and 1/3, with \
             t_min = -0.33333334 (the f32 nearest -1/3, just below it): the point at t_min is \
             just outside, and the hit is the near root, t = -1/3 (f32 computes the near root \
             as -0.33333334, t_min itself), not the far one",
            unit,
            (Vec3::ZERO, v(0.0, 0.0, 3.0)),
            (-1.0 / 3.0, INF),
            E::Hit,
        ),
        s(
            "sphere-direction-1e-21",
            "a direction of length 1e-21: dot(dir, dir) = 1e-42 underflows (t = 4e21)",
            unit_at_5,
            (Vec3::ZERO, v(0.0, 0.0, 1e-21)),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-direction-1e20",
            "a direction of length 1e20: dot(dir, dir) = 1e40 overflows f32 (t = 4e-20)",
            unit_at_5,
            (Vec3::ZERO, v(0.0, 0.0, 1e20)),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-millions",
            "a sphere of radius 1e3 at coordinates in the millions",
            (v(1e6, -2e6, 3e6), 1e3),
            (v(1e6, -2e6, 2.9e6), Vec3::Z),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-huge-floor",
            "a huge sphere used as a floor (radius 1e5), seen from 1.5 above at a 10 degree slope",
            (v(0.0, -1e5, 0.0), 1e5),
            (v(0.0, 1.5, -6.0), v(0.0, -0.173_648_18, 0.984_807_7)),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-coordinates-1e20",
            "coordinates near 1e20: dot(oc, oc) = 1e40 overflows (t = 9e19)",
            (v(0.0, 0.0, 1e20), 1e19),
            (Vec3::ZERO, Vec3::Z),
            ALL,
            E::Hit,
        ),
        // The extreme-scale cases above reach the rescaled path with the
        // ray entering from outside, and `choose_root` solves again in f64
        // whenever the f32 near root is within its error bound of t_min: a
        // rescaled path that returned nonsense roots (say (0, 0)) was
        // rescued by that second solve and passed them. These ask for what
        // only the rescaled roots themselves can give: the far root, the
        // reject of a miss that underflows once scaled, and a direction
        // whose square underflows beside a sphere whose square does too.
        s(
            "sphere-inside-radius-1e19",
            "from inside a sphere of radius 1e19, 5e8 off its centre, along a direction of \
             length 1e20 (dot(dir, dir) = 1e40 overflows f32): the far root, t = 0.1",
            (Vec3::ZERO, 1e19),
            (v(3e8, 4e8, 0.0), v(0.0, 0.0, 1e20)),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-far-miss-1e23",
            "a unit sphere 1.1e23 away, the ray passing sqrt(2) from its centre (1 off in x and \
             1 in y): no hit. Scaled so that the distance is about 1, the miss distance is \
             1e-23 and its square underflows to 0, which looks like a ray through the centre",
            // At 1.1e23 the two f32 roots of that false "hit" differ by an
            // ulp, so the hit would be reported; at 1e23 they happen to be
            // equal, the error bound is infinite, and `choose_root`'s f64
            // solve would hide the mistake.
            (v(1.0, 1.0, 1.1e23), 1.0),
            (Vec3::ZERO, Vec3::Z),
            ALL,
            E::Miss,
        ),
        s(
            "sphere-tiny-direction-tiny-sphere",
            "a sphere of radius 1e-10 at (0, 0, 5e-10), direction of length 1e-21: dot(dir, dir) \
             = 1e-42 and r^2 = 1e-20 are both below 2^-60, the first a subnormal (t = 4e11)",
            (v(0.0, 0.0, 5e-10), 1e-10),
            (Vec3::ZERO, v(0.0, 0.0, 1e-21)),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-coordinates-2-to-the-100",
            "a unit sphere at z = 2^100 (1.3e30), along a direction of length 2^29 (5.4e8): \
             dot(dir, dir) = 2^58 and r^2 = 1 are in range, but dot(dir, oc) = -2^129 \
             overflows f32 (t = 2^71 = 2.4e21)",
            // Powers of two, so that the f64 reference is exact too: at
            // 1e30 its own rounding of the foot (1e14) would swamp r = 1.
            (v(0.0, 0.0, 2f32.powi(100)), 1.0),
            (Vec3::ZERO, v(0.0, 0.0, 2f32.powi(29))),
            ALL,
            E::Hit,
        ),
        s(
            "sphere-nan-origin",
            "a NaN in the origin: no hit",
            unit_at_5,
            (v(f32::NAN, 0.0, 0.0), Vec3::Z),
            ALL,
            E::Miss,
        ),
        s(
            "sphere-zero-direction",
            "a zero direction: no hit",
            unit_at_5,
            (Vec3::ZERO, Vec3::ZERO),
            ALL,
            E::Miss,
        ),
        s(
            "sphere-infinite-radius",
            "an infinite radius: no hit",
            (v(0.0, 0.0, 5.0), INF),
            (Vec3::ZERO, Vec3::Z),
            ALL,
            E::Miss,
        ),
        s(
            "sphere-nan-t-max",
            "t_max = NaN: no hit",
            unit_at_5,
            (Vec3::ZERO, Vec3::Z),
            (0.0, f32::NAN),
            E::Miss,
        ),
    ])
}

// ---------------------------------------------------------------------------
// Chapter 3: the nearest hit.

const NEAREST_3: &str = "The fix: `nearest_hit`";

fn nearest(
    name: &'static str,
    says: &str,
    shapes: Vec<Shape>,
    ray: (Vec3, Vec3),
    range: (f32, f32),
    expect: Option<(usize, f64)>,
) -> Case {
    Case::new(
        name,
        NEAREST_3,
        says,
        CaseKind::Nearest {
            shapes,
            ray: Ray::new(ray.0, ray.1),
            t_min: range.0,
            t_max: range.1,
            expect,
        },
    )
}

pub fn chapter_3() -> Vec<Case> {
    let three = || -> Vec<Shape> {
        vec![
            Plane::new(v(0.0, 0.0, 10.0), Vec3::Z).into(),
            Sphere::new(v(0.0, 0.0, 6.0), 1.0).into(),
            Sphere::new(v(0.0, 0.0, 3.0), 1.0).into(),
        ]
    };
    let axis = (Vec3::ZERO, Vec3::Z);
    vec![
        nearest(
            "nearest-of-three",
            "a wall z = 10 (object 0), a unit sphere at z = 6 (object 1) and one at z = 3 \
             (object 2), listed far to near; a ray from the origin along +z: expected object 2 at t = 2",
            three(),
            axis,
            ALL,
            Some((2, 2.0)),
        ),
        nearest(
            "nearest-listed-first",
            "a unit sphere at z = 3 (object 0) before a wall z = 10 (object 1): expected object 0 at t = 2",
            vec![
                Sphere::new(v(0.0, 0.0, 3.0), 1.0).into(),
                Plane::new(v(0.0, 0.0, 10.0), Vec3::Z).into(),
            ],
            axis,
            ALL,
            Some((0, 2.0)),
        ),
        nearest(
            "nearest-t-min",
            "the three objects with t_min = 4.5: the sphere at z = 3 ends at t = 4, so the next \
             hit is object 1 at t = 5",
            three(),
            axis,
            (4.5, INF),
            Some((1, 5.0)),
        ),
        nearest(
            "nearest-t-max",
            "the three objects with t_max = 1.5: nothing that close: expected no hit",
            three(),
            axis,
            (0.0, 1.5),
            None,
        ),
        nearest(
            "nearest-empty",
            "an empty list of objects: expected no hit",
            Vec::new(),
            axis,
            ALL,
            None,
        ),
        nearest(
            "nearest-all-behind",
            "the three objects, ray along -z: all behind: expected no hit",
            three(),
            (Vec3::ZERO, -Vec3::Z),
            ALL,
            None,
        ),
    ]
}

pub fn chapter_3_robustness() -> Vec<Case> {
    // 100 spheres of radius 0.25 along +z, listed far to near.
    let row: Vec<Shape> = (1..=100)
        .rev()
        .map(|z| Sphere::new(v(0.0, 0.0, z as f32), 0.25).into())
        .collect();
    robust(vec![
        nearest(
            "nearest-hundred-reversed",
            "100 spheres of radius 0.25 at z = 100, 99, ..., 1 (that order): expected the last \
             listed, object 99, at t = 0.75",
            row,
            (Vec3::ZERO, Vec3::Z),
            ALL,
            Some((99, 0.75)),
        ),
        nearest(
            "nearest-nested",
            "a sphere of radius 2 at (0, 0, 5) around one of radius 1 at (0, 0, 5.5), inner \
             listed first: from the origin the outer is met first, object 1 at t = 3",
            vec![
                Sphere::new(v(0.0, 0.0, 5.5), 1.0).into(),
                Sphere::new(v(0.0, 0.0, 5.0), 2.0).into(),
            ],
            (Vec3::ZERO, Vec3::Z),
            ALL,
            Some((1, 3.0)),
        ),
        nearest(
            "nearest-nan-t-max",
            "t_max = NaN: expected no hit",
            vec![Sphere::new(v(0.0, 0.0, 3.0), 1.0).into()],
            (Vec3::ZERO, Vec3::Z),
            (0.0, f32::NAN),
            None,
        ),
    ])
}

// ---------------------------------------------------------------------------
// Chapter 4: shadows.

const SHADOW_RAYS_4: &str = "Shadow rays";
const WHERE_4: &str = "Where a shadow ray starts";
const OFFSET_4: &str = "The error-scaled offset";

/// A floor (object 0) and a unit ball resting on it (object 1).
fn floor_and_ball(lights: &str) -> String {
    floor_and_ball_in([1.0, 1.0, 1.0], lights)
}

/// A dim, coloured ambient light for [`floor_and_ball_in`]: each channel a
/// power of two, so the expected ambient terms are exact.
const DIM_AMBIENT: [f32; 3] = [0.5, 0.25, 1.0];

/// [`floor_and_ball`] under the ambient light `ambient`.
fn floor_and_ball_in(ambient: [f32; 3], lights: &str) -> String {
    let [r, g, b] = ambient;
    format!(
        r#"
background = [0.55, 0.7, 0.9]
ambient_light = [{r:?}, {g:?}, {b:?}]
[camera]
position = [0.0, 2.0, -6.0]
look_at = [0.0, 0.0, 0.0]
{lights}
[[objects]]
name = "floor"
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }}
material = {{ color = [0.5, 0.5, 0.5], ambient = 0.2, diffuse = 0.6, specular = 0.5, shininess = 8 }}
[[objects]]
name = "ball"
sphere = {{ center = [0.0, 1.0, 0.0], radius = 1.0 }}
material = {{ color = [0.8, 0.2, 0.2], ambient = 0.2, diffuse = 0.6 }}
"#
    )
}

/// One tilted floor, its point not representable in binary: the plane
/// where a shadow ray without an offset shows acne.
const TILTED_FLOOR: &str = "[camera]\nposition = [0.0, 2.0, -6.0]\nlook_at = [0.0, 0.0, 0.0]\n\
                            [[lights]]\nposition = [-4.0, 6.0, -3.0]\n\
                            [[objects]]\nplane = { point = [0.3, 0.1, 0.7], normal = [0.01, 1.0, 0.02] }\n";

const LIGHT_ABOVE: &str = "[[lights]]\nposition = [0.0, 10.0, 0.0]\n";
const TWO_LIGHTS: &str = "[[lights]]\nposition = [0.0, 10.0, 0.0]\n\
                          [[lights]]\nposition = [10.0, 0.5, 0.0]\nintensity = 0.5\n";

/// Rays from `light` to a grid of 64 points of the ball (`center`,
/// `radius`) that face it: every point they reach sees the light.
fn rays_from_light(light: Vec3, center: Vec3, radius: f32) -> Vec<Ray> {
    let toward = (center - light).normalize();
    let side = toward.cross(Vec3::Y).normalize();
    let up = side.cross(toward);
    let mut rays = Vec::new();
    for i in 0..8 {
        for j in 0..8 {
            let (a, b) = ((i as f32 - 3.5) / 5.0, (j as f32 - 3.5) / 5.0);
            let target = center + radius * (a * side + b * up);
            rays.push(Ray::new(light, target - light));
        }
    }
    rays
}

fn surface(shape: Shape, origin: Vec3, toward: Vec3) -> crate::SurfacePoint {
    let ray = Ray::new(origin, toward - origin);
    let t = shape.intersect(&ray, 0.0, INF).unwrap_or(1.0);
    shape.surface_point(&ray, t)
}

pub fn chapter_4() -> Vec<Case> {
    let floor: Shape = Plane::new(Vec3::ZERO, Vec3::Y).into();
    let ball: Shape = Sphere::new(v(0.0, 1.0, 0.0), 1.0).into();
    let floor_point = surface(floor, v(0.5, 4.0, 0.0), v(0.5, 0.0, 2.0));
    let ball_top = surface(ball, v(0.3, 5.0, 0.2), v(0.0, 1.0, 0.0));
    let offset = |name, section, says, surface, dir| {
        Case::new(
            name,
            section,
            says,
            CaseKind::Offset {
                surface,
                dir,
                at_most: 1e-2,
            },
        )
    };
    let shadow = |name, says, rays: Vec<Ray>, light, expect, lights: &str| {
        Case::new(
            name,
            SHADOW_RAYS_4,
            says,
            CaseKind::Shadow {
                scene: floor_and_ball(lights),
                object: if rays.len() > 1 { 1 } else { 0 },
                rays,
                light,
                expect,
            },
        )
    };
    let flat = |name, says, ray: (Vec3, Vec3), lights: &str| {
        Case::new(
            name,
            SHADOW_RAYS_4,
            says,
            CaseKind::Shade {
                shading: Shading::Flat,
                scene: floor_and_ball(lights),
                ray: Ray::new(ray.0, ray.1),
                depth: 0,
            },
        )
    };
    // A slanted ray that reaches the floor point (0.2, 0, 0), next to where
    // the ball touches the floor, without touching the ball.
    let under_ball = (v(5.0, 0.5, 0.0), v(-4.8, -0.5, 0.0));
    let beside_ball = (v(3.0, 5.0, 0.0), -Vec3::Y);
    let light_above = v(0.0, 10.0, 0.0);
    vec![
        offset(
            "offset-floor-up",
            WHERE_4,
            format!(
                "a shadow ray leaving the floor point {} upward, along (0.3, 1, 0.2), must start \
                 above the floor by at least the point's error bound dot(|n|, error), and by \
                 less than 0.01",
                vec(floor_point.point)
            ),
            floor_point,
            v(0.3, 1.0, 0.2),
        ),
        offset(
            "offset-floor-down",
            WHERE_4,
            "the same floor point, a ray leaving downward along (0.3, -1, 0) (through the \
             surface, as a refracted ray does): it must start below the floor"
                .to_string(),
            floor_point,
            v(0.3, -1.0, 0.0),
        ),
        offset(
            "offset-ball-out",
            WHERE_4,
            format!(
                "a ray leaving the top of the unit ball at {} upward must start outside the ball",
                vec(ball_top.point)
            ),
            ball_top,
            v(0.2, 1.0, 0.0),
        ),
        offset(
            "offset-ball-in",
            WHERE_4,
            "the same point of the ball, a ray going into it: it must start inside".to_string(),
            ball_top,
            v(0.1, -1.0, 0.3),
        ),
        shadow(
            "shadow-under-ball",
            "the floor point (0.2, 0, 0), next to where the unit ball at (0, 1, 0) touches the \
             floor, with a light straight above at (0, 10, 0): the ball is between them, \
             expected in shadow",
            vec![Ray::new(under_ball.0, under_ball.1)],
            light_above,
            true,
            LIGHT_ABOVE,
        ),
        shadow(
            "shadow-beside-ball",
            "the floor point (3, 0, 0), light at (0, 10, 0): nothing between them, expected lit",
            vec![Ray::new(beside_ball.0, beside_ball.1)],
            light_above,
            false,
            LIGHT_ABOVE,
        ),
        shadow(
            "shadow-blocker-beyond-light",
            "the floor point (3, 0, 0), light at (2, 0.5, 0): the ball lies on the same line but \
             beyond the light (t > 1 on a shadow ray from the point to the light), expected lit",
            vec![Ray::new(beside_ball.0, beside_ball.1)],
            v(2.0, 0.5, 0.0),
            false,
            LIGHT_ABOVE,
        ),
        shadow(
            "shadow-no-acne",
            "64 rays from the light at (-4, 6, -3) to the unit ball at (0, 1, 0): every point they \
             reach sees the light, so none may be in shadow (a shadow ray must not hit the \
             surface it leaves: shadow acne)",
            rays_from_light(v(-4.0, 6.0, -3.0), v(0.0, 1.0, 0.0), 1.0),
            v(-4.0, 6.0, -3.0),
            false,
            LIGHT_ABOVE,
        ),
        Case::new(
            "shadow-no-acne-plane",
            SHADOW_RAYS_4,
            "64 rays from the light at (-4, 6, -3) to a floor through (0.3, 0.1, 0.7), tilted to \
             the normal (0.01, 1, 0.02): every point they reach sees the light, so none may be in \
             shadow. A tilted plane's points are rounded in every coordinate, so a shadow ray \
             started exactly on it meets it again just past its origin (chapter 2's stable \
             sphere test hides this on balls; the offset is what keeps planes clean)",
            CaseKind::Shadow {
                scene: TILTED_FLOOR.to_string(),
                object: 0,
                rays: rays_from_light(v(-4.0, 6.0, -3.0), v(0.3, 0.1, 0.7), 2.0),
                light: v(-4.0, 6.0, -3.0),
                expect: false,
            },
        ),
        flat(
            "flat-lit",
            "the floor point (3, 0, 0) (albedo 0.5, k_a = 0.2, k_d = 0.6, white ambient light), \
             lit by the light at (0, 10, 0): expected 0.2 * 0.5 + 0.6 * 0.5 = 0.4 in each channel",
            beside_ball,
            LIGHT_ABOVE,
        ),
        flat(
            "flat-shadowed",
            "the floor point (0.2, 0, 0) under the ball, light at (0, 10, 0): only ambient, \
             expected 0.2 * 0.5 = 0.1",
            under_ball,
            LIGHT_ABOVE,
        ),
        flat(
            "flat-two-lights",
            "the floor point (0.2, 0, 0), the light above hidden by the ball, a second light of \
             intensity 0.5 low on the right at (10, 0.5, 0) reaching it: expected \
             0.1 + 0.6 * 0.5 * 0.5 = 0.25",
            under_ball,
            TWO_LIGHTS,
        ),
        flat(
            "flat-light-below",
            "the floor point (3, 0, 0) seen from above, light below the floor at (0, -5, 0): it \
             lights the other side only, expected 0.1",
            beside_ball,
            "[[lights]]\nposition = [0.0, -5.0, 0.0]\n",
        ),
        Case::new(
            "flat-dim-ambient",
            SHADOW_RAYS_4,
            "the floor point (3, 0, 0) lit from (0, 10, 0) as in flat-lit, under a dim, coloured \
             ambient light (0.5, 0.25, 1): the ambient term is albedo * k_a * ambient light, \
             0.1 * (0.5, 0.25, 1), and the light's share 0.3 is not scaled by it: expected \
             (0.35, 0.325, 0.4)",
            CaseKind::Shade {
                shading: Shading::Flat,
                scene: floor_and_ball_in(DIM_AMBIENT, LIGHT_ABOVE),
                ray: Ray::new(beside_ball.0, beside_ball.1),
                depth: 0,
            },
        ),
    ]
}

pub fn chapter_4_robustness() -> Vec<Case> {
    let far_ball: Shape = Sphere::new(v(1e4, 1.0, 1e4), 1.0).into();
    let side = surface(
        far_ball,
        v(1e4 - 5.0, 1.0, 1e4 + 0.3),
        v(1e4, 1.0, 1e4 + 0.3),
    );
    let small: Shape = Sphere::new(v(0.1, 0.1, 0.1), 0.01).into();
    let small_point = surface(small, v(0.1, 0.5, 0.1), v(0.1, 0.1, 0.1));
    let ball: Shape = Sphere::new(v(0.0, 1.0, 0.0), 1.0).into();
    let ball_side = surface(ball, v(-5.0, 1.0, 0.0), v(0.0, 1.0, 0.0));
    let offset = |name, says: &str, surface, dir| {
        Case::new(
            name,
            OFFSET_4,
            says,
            CaseKind::Offset {
                surface,
                dir,
                at_most: 0.0,
            },
        )
    };
    let far_scene = r#"
[camera]
position = [9990.0, 5.0, 9990.0]
look_at = [10000.0, 1.0, 10000.0]
[[lights]]
position = [9996.0, 6.0, 9997.0]
[[objects]]
sphere = { center = [10000.0, 1.0, 10000.0], radius = 1.0 }
"#;
    robust(vec![
        offset(
            "offset-far-ball",
            "the side of a unit ball at (1e4, 1, 1e4): its point's error bound is about 5e-3, \
             so a fixed push of 1e-4 leaves the origin where rounding can put it inside",
            side,
            v(-1.0, 0.5, 0.0),
        ),
        offset(
            "offset-grazing",
            "a ray leaving the side of the unit ball at (0, 1, 0) almost along the surface \
             (dot(dir, n) = 1e-3): pushing along dir barely moves it off the surface",
            ball_side,
            v(-1e-3, 1.0, 0.0),
        ),
        offset(
            "offset-small-ball",
            "a ball of radius 0.01 at (0.1, 0.1, 0.1): its error bound is 5e-8, and a push of \
             more than 16 error bounds detaches shadows from small objects",
            small_point,
            v(0.0, 1.0, 0.0),
        ),
        Case::new(
            "shadow-no-acne-far",
            SHADOW_RAYS_4,
            "64 rays from the light at (9996, 6, 9997) to a unit ball at (1e4, 1, 1e4): every \
             point they reach sees the light, none may be in shadow",
            CaseKind::Shadow {
                scene: far_scene.to_string(),
                object: 0,
                rays: rays_from_light(v(9996.0, 6.0, 9997.0), v(1e4, 1.0, 1e4), 1.0),
                light: v(9996.0, 6.0, 9997.0),
                expect: false,
            },
        ),
    ])
}

// ---------------------------------------------------------------------------
// Chapter 5: Phong.

const TERMS_5: &str = "The three terms";

#[allow(clippy::too_many_arguments)]
fn phong(
    name: &'static str,
    says: &str,
    material: (f32, f32, u32),
    albedo: Vec3,
    normal: Vec3,
    to_light: Vec3,
    to_eye: Vec3,
    light: Vec3,
    expect: (Vec3, Vec3),
) -> Case {
    Case::new(
        name,
        TERMS_5,
        says,
        CaseKind::PhongTerms {
            material: Material {
                diffuse: material.0,
                specular: material.1,
                shininess: material.2,
                ..Material::default()
            },
            albedo,
            normal,
            to_light,
            to_eye,
            light,
            expect: PhongTerms {
                diffuse: expect.0,
                specular: expect.1,
            },
        },
    )
}

pub fn chapter_5() -> Vec<Case> {
    let half_sqrt3 = 3f32.sqrt() / 2.0;
    let mirror = v(1.0, 1.0, 0.0).normalize();
    let off_mirror = v(0.5, half_sqrt3, 0.0);
    let cos15 = f64::from(mirror.dot(off_mirror));
    let shade = |name, says, ray: (Vec3, Vec3), lights: &str| {
        Case::new(
            name,
            TERMS_5,
            says,
            CaseKind::Shade {
                shading: Shading::Phong,
                scene: floor_and_ball(lights),
                ray: Ray::new(ray.0, ray.1),
                depth: 0,
            },
        )
    };
    vec![
        phong(
            "phong-diffuse-cosine",
            "a light 60 degrees from the normal (0, 1, 0), to_light = (0.866, 0.5, 0), white, \
             albedo (1, 0.5, 0.25), k_d = 0.8: diffuse = albedo * k_d * cos 60 = (0.4, 0.2, 0.1), \
             no specular (k_s = 0)",
            (0.8, 0.0, 1),
            v(1.0, 0.5, 0.25),
            Vec3::Y,
            v(half_sqrt3, 0.5, 0.0),
            Vec3::Y,
            Vec3::ONE,
            (v(0.4, 0.2, 0.1), Vec3::ZERO),
        ),
        phong(
            "phong-specular-peak",
            "light from (-1, 1, 0)/sqrt 2, eye exactly in the mirror direction (1, 1, 0)/sqrt 2, \
             k_s = 0.5, shininess 10: specular = 0.5 * 1^10 = 0.5 (k_d = 0: no diffuse)",
            (0.0, 0.5, 10),
            Vec3::ONE,
            Vec3::Y,
            v(-1.0, 1.0, 0.0).normalize(),
            mirror,
            Vec3::ONE,
            (Vec3::ZERO, Vec3::splat(0.5)),
        ),
        phong(
            "phong-specular-off-peak",
            "the same light, eye 15 degrees off the mirror direction at (0.5, 0.866, 0): \
             specular = 0.5 * cos(15)^10 = 0.3535",
            (0.0, 0.5, 10),
            Vec3::ONE,
            Vec3::Y,
            v(-1.0, 1.0, 0.0).normalize(),
            off_mirror,
            Vec3::ONE,
            (Vec3::ZERO, Vec3::splat((0.5 * cos15.powi(10)) as f32)),
        ),
        phong(
            "phong-light-behind",
            "a light behind the surface (to_light = (0, -1, 0), normal (0, 1, 0)): both terms 0",
            (1.0, 1.0, 8),
            Vec3::ONE,
            Vec3::Y,
            -Vec3::Y,
            Vec3::Y,
            Vec3::ONE,
            (Vec3::ZERO, Vec3::ZERO),
        ),
        phong(
            "phong-highlight-untinted",
            "a red surface (albedo (1, 0, 0), k_d = 0.5, k_s = 0.5, shininess 1) lit and seen \
             along its normal by a light (1, 0.9, 0.7): diffuse (0.5, 0, 0); the highlight has \
             the light's colour, not the albedo's: specular (0.5, 0.45, 0.35)",
            (0.5, 0.5, 1),
            v(1.0, 0.0, 0.0),
            Vec3::Y,
            Vec3::Y,
            Vec3::Y,
            v(1.0, 0.9, 0.7),
            (v(0.5, 0.0, 0.0), v(0.5, 0.45, 0.35)),
        ),
        shade(
            "phong-sum-lit",
            "the floor point (3, 0, 0) (albedo 0.5, k_a = 0.2, k_d = 0.6, k_s = 0.5, shininess 8) \
             lit from (0, 10, 0), seen from straight above: cos i = 10 / sqrt(109) = 0.958, so \
             diffuse 0.1 + 0.6 * 0.5 * 0.958 = 0.3873, and the mirrored light makes the same \
             angle with the eye: specular 0.5 * 0.958^8 = 0.354",
            (v(3.0, 5.0, 0.0), -Vec3::Y),
            LIGHT_ABOVE,
        ),
        shade(
            "phong-sum-one-hidden",
            "the floor point (0.2, 0, 0) under the ball: the light above is hidden, the light of \
             intensity 0.5 at (10, 0.5, 0) is not: diffuse 0.1 + 0.6 * 0.5 * 0.5 * 0.05095 = 0.1076",
            (v(5.0, 0.5, 0.0), v(-4.8, -0.5, 0.0)),
            TWO_LIGHTS,
        ),
        Case::new(
            "phong-sum-dim-ambient",
            TERMS_5,
            "phong-sum-lit under a dim, coloured ambient light (0.5, 0.25, 1): the ambient term \
             is albedo * k_a * ambient light = 0.1 * (0.5, 0.25, 1), the light's terms are as \
             before: diffuse (0.3373, 0.3123, 0.3873), specular 0.354",
            CaseKind::Shade {
                shading: Shading::Phong,
                scene: floor_and_ball_in(DIM_AMBIENT, LIGHT_ABOVE),
                ray: Ray::new(v(3.0, 5.0, 0.0), -Vec3::Y),
                depth: 0,
            },
        ),
    ]
}

pub fn chapter_5_robustness() -> Vec<Case> {
    robust(vec![phong(
        "phong-grazing-light",
        "a light grazing the surface, cos i = 1e-7: tiny but not negative, never NaN",
        (1.0, 0.0, 8),
        Vec3::ONE,
        Vec3::Y,
        v(1.0, 1e-7, 0.0),
        Vec3::Y,
        Vec3::ONE,
        (Vec3::splat(1e-7), Vec3::ZERO),
    )])
}

// ---------------------------------------------------------------------------
// Chapter 6: reflection.

const FORMULA_6: &str = "The reflection formula";
const RECURSION_6: &str = "The recursion";

fn reflect_case(name: &'static str, section: &'static str, says: &str, d: Vec3, n: Vec3) -> Case {
    Case::new(name, section, says, CaseKind::Reflect { d, n })
}

/// A mirror floor (object 0, k_r = 0.5, grey 0.4 lit by ambient light only)
/// and a red ball above it; no lights.
const MIRROR_SCENE: &str = r#"
background = [0.55, 0.7, 0.9]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, -5.0]
look_at = [0.0, 0.0, 0.0]
[render]
max_depth = 5
[[objects]]
name = "mirror floor"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [0.4, 0.4, 0.4], ambient = 1.0, diffuse = 0.0, reflectivity = 0.5 }
[[objects]]
name = "red ball"
sphere = { center = [0.0, 1.0, 4.0], radius = 1.0 }
material = { color = [0.9, 0.1, 0.1], ambient = 1.0, diffuse = 0.0 }
"#;

/// Two facing mirrors, a floor (object 0) and a ceiling at height 2, each
/// k_r = 0.5 and grey 0.4 lit by ambient light only (its own share
/// (1 - 0.5) * 0.4 = 0.2); no lights. A slanted ray bounces between them
/// for ever: only `max_depth` and `min_contribution` (`render`, a TOML
/// table body) end the recursion, and the colour tells how many bounces
/// were traced: 0.2 * (1 + 0.5 + 0.25 + ...), one term per point shaded.
fn two_mirrors(render: &str) -> String {
    format!(
        r#"
background = [0.55, 0.7, 0.9]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, -5.0]
look_at = [0.0, 1.0, 0.0]
[render]
{render}
[[objects]]
name = "mirror floor"
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }}
material = {{ color = [0.4, 0.4, 0.4], ambient = 1.0, diffuse = 0.0, reflectivity = 0.5 }}
[[objects]]
name = "mirror ceiling"
plane = {{ point = [0.0, 2.0, 0.0], normal = [0.0, -1.0, 0.0] }}
material = {{ color = [0.4, 0.4, 0.4], ambient = 1.0, diffuse = 0.0, reflectivity = 0.5 }}
"#
    )
}

pub fn chapter_6() -> Vec<Case> {
    let mirror = |name, says, ray: (Vec3, Vec3), depth| {
        Case::new(
            name,
            RECURSION_6,
            says,
            CaseKind::Shade {
                shading: Shading::Mirror,
                scene: MIRROR_SCENE.to_string(),
                ray: Ray::new(ray.0, ray.1),
                depth,
            },
        )
    };
    let between_mirrors = |name, says, render: &str| {
        Case::new(
            name,
            RECURSION_6,
            says,
            CaseKind::Shade {
                shading: Shading::Mirror,
                scene: two_mirrors(render),
                ray: Ray::new(v(0.0, 1.0, 0.0), v(0.0, -1.0, 1.0)),
                depth: 0,
            },
        )
    };
    vec![
        reflect_case(
            "reflect-floor",
            FORMULA_6,
            "(1, -1, 0) bouncing off a floor with normal (0, 1, 0) leaves along (1, 1, 0)",
            v(1.0, -1.0, 0.0),
            Vec3::Y,
        ),
        reflect_case(
            "reflect-normal-length",
            FORMULA_6,
            "the normal's length does not matter: (1, -2, 3) off a normal (0, 7, 0) gives (1, 2, 3)",
            v(1.0, -2.0, 3.0),
            v(0.0, 7.0, 0.0),
        ),
        reflect_case(
            "reflect-normal-flipped",
            FORMULA_6,
            "nor its orientation: (1, -2, 3) off a normal (0, -0.25, 0) gives (1, 2, 3)",
            v(1.0, -2.0, 3.0),
            v(0.0, -0.25, 0.0),
        ),
        reflect_case(
            "reflect-normal-incidence",
            FORMULA_6,
            "straight at a wall: (0, 0, -2) off a normal (0, 0, 1) comes back as (0, 0, 2), \
             the same length",
            v(0.0, 0.0, -2.0),
            Vec3::Z,
        ),
        reflect_case(
            "reflect-45-mirror",
            FORMULA_6,
            "a mirror at 45 degrees (normal (-1, 1, 0)) turns +x into +y",
            Vec3::X,
            v(-1.0, 1.0, 0.0),
        ),
        mirror(
            "mirror-sees-sky",
            "a ray from (0, 1, -5) along (0, -1, 1) meets the mirror floor (k_r = 0.5, own colour \
             0.4) at (0, 0, -4) and is reflected to the sky (0.55, 0.7, 0.9): expected \
             (1 - 0.5) * 0.4 + 0.5 * sky = (0.475, 0.55, 0.65)",
            (v(0.0, 1.0, -5.0), v(0.0, -1.0, 1.0)),
            0,
        ),
        mirror(
            "mirror-sees-ball",
            "a ray from (0, 1, 1) along (0, -1, 1.5) meets the mirror floor at (0, 0, 2.5) and is \
             reflected into the red ball (0.9, 0.1, 0.1): expected 0.2 + 0.5 * ball = (0.65, 0.25, 0.25)",
            (v(0.0, 1.0, 1.0), v(0.0, -1.0, 1.5)),
            0,
        ),
        mirror(
            "mirror-depth-limit",
            "the sky case at depth 5 = max_depth: no more bounces, only the local share \
             (1 - 0.5) * 0.4 = 0.2",
            (v(0.0, 1.0, -5.0), v(0.0, -1.0, 1.0)),
            5,
        ),
        between_mirrors(
            "mirror-depth-counts-bounces",
            "a ray from (0, 1, 0) along (0, -1, 1) between two facing mirrors (k_r = 0.5, own \
             share 0.2 each), max_depth = 2: the floor at depth 0, the ceiling at depth 1, the \
             floor again at depth 2 = max_depth, where the recursion stops. Expected \
             0.2 + 0.5 * (0.2 + 0.5 * 0.2) = 0.35 (each reflected ray one deeper; without the \
             limit the weights alone stop it after 10 points, 0.3996)",
            "max_depth = 2",
        ),
        between_mirrors(
            "mirror-min-contribution",
            "the same ray between the two mirrors with max_depth = 5 but min_contribution = 0.2: \
             the reflected rays weigh 0.5 and 0.25 in the pixel, the next would weigh 0.125 < 0.2 \
             and is not cast. Expected 0.2 + 0.5 * (0.2 + 0.5 * 0.2) = 0.35 (each reflected \
             ray's weight is its parent's times k_r; traced to max_depth, 0.39375)",
            "max_depth = 5\nmin_contribution = 0.2",
        ),
    ]
}

pub fn chapter_6_robustness() -> Vec<Case> {
    let r = |name, says, d, n| reflect_case(name, FORMULA_6, says, d, n);
    robust(vec![
        r(
            "reflect-huge-direction",
            "a direction (3e38, -3e38, 0) near f32::MAX: 2 (d.n) overflows, the answer (3e38, 3e38, 0) does not",
            v(3e38, -3e38, 0.0),
            Vec3::Y,
        ),
        r(
            "reflect-tiny-normal",
            "a normal of length 1e-30: n.n underflows to 0",
            v(1.0, -1.0, 0.5),
            v(0.0, 1e-30, 1e-30),
        ),
        r(
            "reflect-huge-normal",
            "a normal of length 1e30: n.n overflows",
            v(1.0, -1.0, 0.5),
            v(1e30, 1e30, 0.0),
        ),
        r(
            "reflect-tiny-direction",
            "a direction of length 1e-20 keeps its length",
            v(1e-20, -2e-20, 3e-20),
            v(0.2, 0.9, -0.4),
        ),
        r(
            "reflect-awkward-normal",
            "a slanted normal with awkward components",
            v(0.1, 0.7, -0.3),
            v(0.577, -0.123, 0.808),
        ),
        r(
            "reflect-zero-normal",
            "a zero normal: NaN, not a plausible direction",
            Vec3::X,
            Vec3::ZERO,
        ),
    ])
}

// ---------------------------------------------------------------------------
// Chapter 7: anti-aliasing.

const SAMPLES_7: &str = "Where the samples go";

/// A wall of white and black checkers of size 1 whose corner is on the
/// camera's axis, seen in 3 x 3 pixels: the middle pixel's four quarters see
/// white, black, black, white. Ambient light only, `k_a = 1`: each sample is
/// exactly 1 or 0.
const QUARTERS_SCENE: &str = r#"
background = [1.0, 1.0, 1.0]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 0.0, -5.0]
look_at = [0.0, 0.0, 0.0]
fov_degrees = 45.0
[render]
width = 3
height = 3
samples = 4
sampling = "grid"
[[objects]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, -1.0] }
[objects.material]
color = [1.0, 1.0, 1.0]
ambient = 1.0
diffuse = 0.0
checker = { color = [0.0, 0.0, 0.0], size = 1.0 }
"#;

fn samples_case(
    name: &'static str,
    says: &str,
    sampling: Sampling,
    count: u32,
    pixels: Vec<(u32, u32)>,
    seed: u64,
    rule: SampleRule,
) -> Case {
    Case::new(
        name,
        SAMPLES_7,
        says,
        CaseKind::SampleOffsets {
            sampling,
            count,
            pixels,
            seed,
            rule,
        },
    )
}

/// Chapter 7's own scene at the reference size: what `pixel_color` is
/// checked on, pixel by pixel, along three rows that cross edges.
fn chapter_7_scene() -> String {
    crate::stage::chapter(7)
        .map(|info| {
            info.scene
                .replace(
                    "width = 640",
                    &format!("width = {}", crate::stage::REFERENCE_WIDTH),
                )
                .replace(
                    "height = 480",
                    &format!("height = {}", crate::stage::REFERENCE_HEIGHT),
                )
        })
        .unwrap_or_default()
}

pub fn chapter_7() -> Vec<Case> {
    let rows: Vec<(u32, u32)> = [44u32, 60, 84]
        .iter()
        .flat_map(|&y| (0..crate::stage::REFERENCE_WIDTH).map(move |x| (x, y)))
        .collect();
    vec![
        samples_case(
            "samples-grid-4",
            "4 grid samples in pixel (3, 7): the centres of its quarters, (0.25, 0.25), \
             (0.75, 0.25), (0.25, 0.75) and (0.75, 0.75), in any order",
            Sampling::Grid,
            4,
            vec![(3, 7)],
            1,
            SampleRule::GridCentres,
        ),
        samples_case(
            "samples-grid-9",
            "9 grid samples: the centres of a 3 x 3 grid of cells, (1/6, 1/6) to (5/6, 5/6)",
            Sampling::Grid,
            9,
            vec![(0, 0), (5, 2)],
            0,
            SampleRule::GridCentres,
        ),
        samples_case(
            "samples-jittered-16",
            "16 jittered samples in pixels (10, 20), (0, 0) and (159, 119), seed 42: one in each \
             cell of a 4 x 4 grid, all inside [0, 1)^2",
            Sampling::Jittered,
            16,
            vec![(10, 20), (0, 0), (159, 119)],
            42,
            SampleRule::OnePerCell,
        ),
        samples_case(
            "samples-random-4",
            "4 random samples: inside [0, 1)^2, not all at the same point",
            Sampling::Random,
            4,
            vec![(5, 6), (100, 50)],
            9,
            SampleRule::InsidePixel,
        ),
        samples_case(
            "samples-random-5",
            "5 random samples: random sampling takes any count, not only squares (5 has no \
             whole square root: floor(sqrt 5) = 2); inside [0, 1)^2, not all at the same point",
            Sampling::Random,
            5,
            vec![(5, 6), (100, 50)],
            9,
            SampleRule::InsidePixel,
        ),
        samples_case(
            "samples-seed-changes-them",
            "4 random samples in pixels (5, 6) and (100, 50) with seed 1, then with seed 0: the \
             seed changes the samples (it is hashed with the pixel and the index), so the two \
             sets must differ",
            Sampling::Random,
            4,
            vec![(5, 6), (100, 50)],
            1,
            SampleRule::UnlikeSeed(0),
        ),
        Case::new(
            "pixel-quarters",
            SAMPLES_7,
            "the middle pixel of a 3 x 3 view of a black and white checker whose corner is on the \
             axis: its four grid samples see 1, 0, 0, 1; expected their mean in linear light, 0.5 \
             (averaging sRGB codes instead gives 0.21)",
            CaseKind::PixelColor {
                scene: QUARTERS_SCENE.to_string(),
                pixels: vec![(1, 1)],
            },
        ),
        Case::new(
            "pixel-mean-of-own-samples",
            SAMPLES_7,
            "every pixel of rows 44, 60 and 84 of the chapter 7 scene at 160 x 120 (they cross \
             the balls' edges): expected the mean, in linear light, of the pixel's own 4 samples, \
             at the offsets sample_offset gives; nothing from neighbouring pixels",
            CaseKind::PixelColor {
                scene: chapter_7_scene(),
                pixels: rows,
            },
        ),
    ]
}

pub fn chapter_7_robustness() -> Vec<Case> {
    let mut pixels: Vec<(u32, u32)> = (0..20_000).map(|x| (x, 3)).collect();
    pixels.push((109_417, 17));
    robust(vec![
        samples_case(
            "samples-jittered-never-1",
            "4 jittered samples in each of 20,000 pixels: (column + r) / 2 can round up to 1.0 \
             in f32 (pixel (109417, 17), sample 1 does); every offset must stay below 1",
            Sampling::Jittered,
            4,
            pixels.clone(),
            0,
            SampleRule::OnePerCell,
        ),
        samples_case(
            "samples-random-never-1",
            "4 random samples in each of 20,000 pixels: every offset inside [0, 1)^2",
            Sampling::Random,
            4,
            pixels,
            0,
            SampleRule::InsidePixel,
        ),
    ])
}

// ---------------------------------------------------------------------------
// Chapter 8: refraction.

const SNELL_8: &str = "Snell-Descartes";
const TIR_8: &str = "Total internal reflection";
const ENTERING_8: &str = "Entering and leaving";

fn refract_case(
    name: &'static str,
    section: &'static str,
    says: &str,
    d: Vec3,
    n: Vec3,
    eta: f32,
) -> Case {
    Case::new(name, section, says, CaseKind::Refract { d, n, eta })
}

/// Incident direction at `degrees` from the normal +y, travelling down.
fn at_angle(degrees: f64) -> Vec3 {
    let a = degrees.to_radians();
    Vec3::new(a.sin() as f32, -a.cos() as f32, 0.0)
}

/// A water surface y = 0 (object 0: k_t = 0.9, k_r = 0.1, no light of its
/// own, index 1.33) over a red and blue checkered floor y = -2 lit by
/// ambient light only; no lights.
const WATER_SCENE: &str = r#"
background = [0.55, 0.7, 0.9]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, -5.0]
look_at = [0.0, 0.0, 0.0]
[render]
max_depth = 5
[[objects]]
name = "water surface"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, reflectivity = 0.1, transparency = 0.9, ior = 1.33 }
[[objects]]
name = "floor"
plane = { point = [0.0, -2.0, 0.0], normal = [0.0, 1.0, 0.0] }
[objects.material]
color = [0.9, 0.1, 0.1]
ambient = 1.0
diffuse = 0.0
checker = { color = [0.1, 0.1, 0.9], size = 1.5 }
"#;

/// A glass pane y = 0 (object 0: k_r = k_t = 0.5, tinted (1, 0.5, 0.25),
/// index 1.5) between two fainter panes, a floor y = -2 (colour 0.8,
/// k_t = 0.75) and a ceiling y = 2 (colour 0.4, k_t = 0.75), index 1, all
/// lit by ambient light only (ambient = 1, no lights). With
/// `min_contribution = 0.5` the pane's two rays are cast (weight 0.5 each)
/// but the floor's and the ceiling's are not (0.5 x 0.75 < 0.5): every
/// share is a fraction, and the answer is a few products by hand.
const PANES_SCENE: &str = r#"
background = [0.2, 0.4, 0.6]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, -5.0]
look_at = [0.0, 0.0, 0.0]
[render]
max_depth = 5
min_contribution = 0.5
[[objects]]
name = "pane"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [1.0, 0.5, 0.25], ambient = 1.0, diffuse = 0.0, reflectivity = 0.5, transparency = 0.5, ior = 1.5 }
[[objects]]
name = "floor pane"
plane = { point = [0.0, -2.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [0.8, 0.8, 0.8], ambient = 1.0, diffuse = 0.0, transparency = 0.75, ior = 1.0 }
[[objects]]
name = "ceiling pane"
plane = { point = [0.0, 2.0, 0.0], normal = [0.0, -1.0, 0.0] }
material = { color = [0.4, 0.4, 0.4], ambient = 1.0, diffuse = 0.0, transparency = 0.75, ior = 1.0 }
"#;

/// The ray of the panes cases: from (0, 1, 0) down at 45 degrees, meeting
/// the pane at (1, 0, 0).
const PANES_RAY: (Vec3, Vec3) = (Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, -1.0, 0.0));

pub fn chapter_8() -> Vec<Case> {
    let glass = 1.5f32;
    let water = |name, section, says, ray: (Vec3, Vec3), depth| {
        Case::new(
            name,
            section,
            says,
            CaseKind::Shade {
                shading: Shading::Glass,
                scene: WATER_SCENE.to_string(),
                ray: Ray::new(ray.0, ray.1),
                depth,
            },
        )
    };
    vec![
        refract_case(
            "refract-normal-incidence",
            SNELL_8,
            "straight down into glass, (0, -2, 0) through a normal (0, 1, 0), eta = 1/1.5: \
             straight on, as a unit vector (0, -1, 0)",
            v(0.0, -2.0, 0.0),
            Vec3::Y,
            1.0 / glass,
        ),
        refract_case(
            "refract-air-to-glass-45",
            SNELL_8,
            "air to glass at 45 degrees, (1, -1, 0) through (0, 1, 0), eta = 1/1.5: \
             sin t = sin 45 / 1.5 = 0.4714, so the unit direction (0.4714, -0.8819, 0)",
            v(1.0, -1.0, 0.0),
            Vec3::Y,
            1.0 / glass,
        ),
        refract_case(
            "refract-glass-to-air",
            SNELL_8,
            "glass to air, (0.4, 0.9165, 0) through (0, 1, 0), eta = 1.5: sin i = 0.4, \
             sin t = 0.6, so (0.6, 0.8, 0): away from the normal",
            v(0.4, (1.0f32 - 0.16).sqrt(), 0.0),
            Vec3::Y,
            glass,
        ),
        refract_case(
            "refract-normal-either-way",
            SNELL_8,
            "the 45 degree case with the normal given as (0, -3, 0): its length and side do not \
             matter, expected (0.4714, -0.8819, 0)",
            v(1.0, -1.0, 0.0),
            v(0.0, -3.0, 0.0),
            1.0 / glass,
        ),
        refract_case(
            "refract-same-medium",
            SNELL_8,
            "eta = 1 (same medium on both sides): the ray goes straight on, as a unit vector",
            v(0.3, -0.5, 0.8),
            Vec3::Y,
            1.0,
        ),
        refract_case(
            "refract-total-internal-reflection",
            TIR_8,
            "glass to air at 60 degrees, past the critical angle asin(1/1.5) = 41.8 degrees: \
             sin t would be 1.5 * 0.866 = 1.3 > 1, expected None",
            at_angle(60.0),
            Vec3::Y,
            glass,
        ),
        water(
            "glass-entering",
            ENTERING_8,
            "a ray from (0, 1, 0.7) along (1, -1, 0) enters water (index 1.33, k_t = 0.9, \
             k_r = 0.1) at (1, 0, 0.7): entering, eta = 1/1.33, it bends toward the normal \
             (sin t = 0.53) and meets the checkered floor y = -2 at x = 2.26; expected \
             0.9 * that floor colour + 0.1 * the sky",
            (v(0.0, 1.0, 0.7), v(1.0, -1.0, 0.0)),
            0,
        ),
        water(
            "glass-total-internal-reflection",
            TIR_8,
            "an eye under water at (0, -1, 0.7) looking up along (1, 0.2, 0): leaving the water \
             at 79 degrees from the normal, past the critical angle (48.8 degrees), nothing \
             crosses; the transmitted share joins the reflected one: expected \
             (0.1 + 0.9) * the floor colour at (15, -2, 0.7)",
            (v(0.0, -1.0, 0.7), v(1.0, 0.2, 0.0)),
            0,
        ),
        Case::new(
            "glass-fractional-shares",
            ENTERING_8,
            "a glass pane (k_r = k_t = 0.5, tinted (1, 0.5, 0.25)) between a floor and a ceiling \
             pane (k_t = 0.75, own light 0.25 x 0.8 and 0.25 x 0.4), min_contribution 0.5, a ray \
             from (0, 1, 0) along (1, -1, 0): 0 x its own light + 0.5 x (1, 0.5, 0.25) x 0.2 \
             through + 0.5 x 0.1 reflected = (0.15, 0.1, 0.075); the rays it casts carry the \
             weights 0.5, so the floor's and ceiling's (0.5 x 0.75 < 0.5) are not cast",
            CaseKind::Shade {
                shading: Shading::Glass,
                scene: PANES_SCENE.to_string(),
                ray: Ray::new(PANES_RAY.0, PANES_RAY.1),
                depth: 0,
            },
        ),
        water(
            "glass-depth-limit",
            ENTERING_8,
            "the entering ray at depth 5 = max_depth: no more rays, only the surface's own \
             light, which is 0 here",
            (v(0.0, 1.0, 0.7), v(1.0, -1.0, 0.0)),
            5,
        ),
    ]
}

pub fn chapter_8_robustness() -> Vec<Case> {
    let glass = 1.5f32;
    let water = 1.33f32;
    let critical = (1.0 / 1.5f64).asin().to_degrees();
    let r = |name, section, says, d, n, eta| refract_case(name, section, says, d, n, eta);
    robust(vec![
        r(
            "refract-just-below-critical",
            TIR_8,
            "glass to air 0.01 degree below the critical angle: cos t = 0.01, the refracted ray \
             exists and skims the surface",
            at_angle(critical - 0.01),
            Vec3::Y,
            glass,
        ),
        r(
            "refract-just-above-critical",
            TIR_8,
            "glass to air 0.01 degree above the critical angle: None",
            at_angle(critical + 0.01),
            Vec3::Y,
            glass,
        ),
        r(
            "refract-grazing",
            SNELL_8,
            "air to glass at 89.99 degrees: cos i = 1.7e-4",
            at_angle(89.99),
            Vec3::Y,
            1.0 / glass,
        ),
        r(
            "refract-near-normal",
            SNELL_8,
            "near-normal incidence, 1e-4 degree: sin^2 i from 1 - cos^2 i would be noise",
            at_angle(1e-4),
            Vec3::Y,
            1.0 / glass,
        ),
        r(
            "refract-nested-media",
            SNELL_8,
            "glass into water at 40 degrees, eta = 1.5 / 1.33",
            at_angle(40.0),
            Vec3::Y,
            glass / water,
        ),
        r(
            "refract-unnormalised-input",
            SNELL_8,
            "air to glass at 45 degrees with d = (3, -3, 0) and n = (0, 0.25, 0)",
            v(3.0, -3.0, 0.0),
            v(0.0, 0.25, 0.0),
            1.0 / glass,
        ),
        r(
            "refract-same-medium-short-direction",
            SNELL_8,
            "eta = 1 with the short direction (1e-4, -2e-4, 2e-4), length 3e-4: straight on, \
             as a unit vector (1/3, -2/3, 2/3) (a shortcut for eta = 1 that keeps a direction \
             already unit must not keep this one)",
            v(1e-4, -2e-4, 2e-4),
            Vec3::Y,
            1.0,
        ),
        r(
            "refract-zero-normal",
            SNELL_8,
            "a zero normal: None",
            at_angle(30.0),
            Vec3::ZERO,
            1.0 / glass,
        ),
        r(
            "refract-nan-direction",
            SNELL_8,
            "a NaN direction: None",
            v(f32::NAN, -1.0, 0.0),
            Vec3::Y,
            1.0 / glass,
        ),
        r(
            "refract-nan-eta",
            SNELL_8,
            "eta = NaN: None",
            at_angle(30.0),
            Vec3::Y,
            f32::NAN,
        ),
        r(
            "refract-zero-eta",
            SNELL_8,
            "eta = 0: None",
            at_angle(30.0),
            Vec3::Y,
            0.0,
        ),
    ])
}

// ---------------------------------------------------------------------------
// Chapter 9: glass done right.

const FRESNEL_9: &str = "Fresnel, from the boundary conditions";
const SCHLICK_9: &str = "Schlick's approximation";
const STACK_9: &str = "Which media meet: the medium stack";
const ABSORPTION_9: &str = "Absorption: Beer-Lambert";

/// The exact unpolarised reflectance, written from the Fresnel equations in
/// `f64` (independently of the chapter's code).
fn exact_fresnel(cos_i: f64, n1: f64, n2: f64) -> f64 {
    let sin2_t = (n1 / n2).powi(2) * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_s = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    let r_p = (n1 * cos_t - n2 * cos_i) / (n1 * cos_t + n2 * cos_i);
    (r_s * r_s + r_p * r_p) / 2.0
}

fn reflectance(
    name: &'static str,
    section: &'static str,
    says: &str,
    schlick: bool,
    (cos_i, n1, n2): (f32, f32, f32),
    expect: f64,
) -> Case {
    Case::new(
        name,
        section,
        says,
        CaseKind::Reflectance {
            schlick,
            cos_i,
            n1,
            n2,
            expect,
        },
    )
}

/// A glass ball (ior 1.5, Fresnel exact) holding a water ball (1.33) over a
/// floor: the ray from the camera meets the glass first.
const NESTED_SCENE: &str = r#"
background = [0.55, 0.7, 0.9]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, -6.0]
look_at = [0.0, 1.0, 0.0]
[render]
max_depth = 6
min_contribution = 0.0
[[lights]]
position = [-4.0, 6.0, -3.0]
[[objects]]
name = "glass"
sphere = { center = [0.0, 1.0, 0.0], radius = 1.0 }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.5, fresnel = "exact", absorption = [0.2, 0.05, 0.0] }
[[objects]]
name = "water"
sphere = { center = [0.0, 1.0, 0.0], radius = 0.6 }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.33, fresnel = "schlick" }
[[objects]]
name = "floor"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
[objects.material]
color = [0.9, 0.9, 0.85]
checker = { color = [0.15, 0.15, 0.2], size = 1.0 }
"#;

pub fn chapter_9() -> Vec<Case> {
    let cos45 = std::f32::consts::FRAC_1_SQRT_2;
    let shade = |name, says: &str, ray: (Vec3, Vec3)| {
        Case::new(
            name,
            STACK_9,
            says,
            CaseKind::Shade {
                shading: Shading::Dielectric,
                scene: NESTED_SCENE.to_string(),
                ray: Ray::new(ray.0, ray.1),
                depth: 0,
            },
        )
    };
    vec![
        reflectance(
            "fresnel-normal-incidence",
            FRESNEL_9,
            "air to glass head-on: cos_i = 1, n1 = 1, n2 = 1.5: R = ((1 - 1.5) / (1 + 1.5))^2 = 0.04",
            false,
            (1.0, 1.0, 1.5),
            0.04,
        ),
        reflectance(
            "schlick-normal-incidence",
            SCHLICK_9,
            "the same with Schlick: R0 = 0.04, and (1 - cos_i)^5 = 0 head-on: 0.04",
            true,
            (1.0, 1.0, 1.5),
            0.04,
        ),
        reflectance(
            "fresnel-45-degrees",
            FRESNEL_9,
            "air to glass at 45 degrees: sin t = 0.7071 / 1.5 = 0.4714, cos t = 0.8819; \
             r_s = (0.7071 - 1.5 x 0.8819) / (0.7071 + 1.5 x 0.8819) = -0.3034, \
             r_p = (0.8819 - 1.5 x 0.7071) / (0.8819 + 1.5 x 0.7071) = -0.0921: \
             R = (r_s^2 + r_p^2) / 2 = 0.0503",
            false,
            (cos45, 1.0, 1.5),
            exact_fresnel(f64::from(cos45), 1.0, 1.5),
        ),
        reflectance(
            "fresnel-total-internal-reflection",
            FRESNEL_9,
            "glass to air at 60 degrees (cos_i = 0.5): sin t = 1.5 x 0.866 = 1.3 > 1, no \
             transmitted ray: R = 1 exactly",
            false,
            (0.5, 1.5, 1.0),
            1.0,
        ),
        reflectance(
            "fresnel-grazing",
            FRESNEL_9,
            "air to glass at grazing incidence (cos_i = 0): everything is reflected, R = 1",
            false,
            (0.0, 1.0, 1.5),
            1.0,
        ),
        reflectance(
            "schlick-leaving-glass",
            SCHLICK_9,
            "glass to air with cos_i = 0.9: Schlick takes the cosine in the less dense medium, \
             here the transmitted one: sin t = 1.5 x 0.4359 = 0.6538, cos t = 0.7566, \
             R = 0.04 + 0.96 x (1 - 0.7566)^5 = 0.04081 (with cos_i it would be 0.04001)",
            true,
            (0.9, 1.5, 1.0),
            {
                let cos_t = (1.0 - 2.25 * (1.0 - 0.81f64)).sqrt();
                0.04 + 0.96 * (1.0 - cos_t).powi(5)
            },
        ),
        reflectance(
            "schlick-past-the-critical-angle",
            SCHLICK_9,
            "glass to air at 60 degrees (cos_i = 0.5), past the critical angle of 41.8 degrees: \
             no transmitted ray, so R = 1, with Schlick too",
            true,
            (0.5, 1.5, 1.0),
            1.0,
        ),
        reflectance(
            "fresnel-water-in-glass",
            FRESNEL_9,
            "from glass (1.5) into water (1.33) head-on: R = ((1.5 - 1.33) / (1.5 + 1.33))^2 = \
             0.00361, ten times less than into air: the pair of media matters",
            false,
            (1.0, 1.5, 1.33),
            ((1.5f64 - 1.33) / (1.5 + 1.33)).powi(2),
        ),
        Case::new(
            "transmittance-slab",
            ABSORPTION_9,
            "through 2 units of glass absorbing (0.5, 0.1, 0) per unit: exp(-1) = 0.3679, \
             exp(-0.2) = 0.8187 and 1",
            CaseKind::Transmittance {
                absorption: v(0.5, 0.1, 0.0),
                distance: 2.0,
            },
        ),
        shade(
            "dielectric-nested-balls",
            "a ray from (0, 1, -6) along +z meets a glass ball (ior 1.5, exact Fresnel, absorbing) \
             holding a water ball (ior 1.33, Schlick): expected the reference colour, with every \
             crossing between the right pair of media",
            (v(0.0, 1.0, -6.0), Vec3::Z),
        ),
        Case::new(
            "dielectric-fractional-shares",
            STACK_9,
            "chapter 8's glass-fractional-shares scene, no Fresnel (fresnel = \"none\": R = 0): \
             a pane with k_r = k_t = 0.5, tinted (1, 0.5, 0.25), of its own light 1 - 0.5 - 0.5 = \
             0; the transmitted ray (weight 0.5) sees the floor's own light 0.2, the reflected \
             one (weight 0.5) the ceiling's, 0.1, neither casting further (0.5 x 0.75 < \
             min_contribution 0.5): expected (0.15, 0.1, 0.075)",
            CaseKind::Shade {
                shading: Shading::Dielectric,
                scene: PANES_SCENE.to_string(),
                ray: Ray::new(PANES_RAY.0, PANES_RAY.1),
                depth: 0,
            },
        ),
        shade(
            "dielectric-off-centre",
            "the same balls, the ray from (0.3, 1.2, -6) along +z: it crosses glass and water at \
             an angle, where Fresnel's share and the bending both depend on the pair of media",
            (v(0.3, 1.2, -6.0), Vec3::Z),
        ),
    ]
}

pub fn chapter_9_robustness() -> Vec<Case> {
    let critical = (1.0f64 / 1.5).asin();
    let just_below = (critical - 1e-4).cos() as f32;
    let just_above = (critical + 1e-4).cos() as f32;
    vec![
        reflectance(
            "fresnel-just-below-the-critical-angle",
            FRESNEL_9,
            "glass to air 1e-4 rad before the critical angle: R is continuous and rises steeply \
             to 1 (a square-root singularity): no NaN, no value above 1",
            false,
            (just_below, 1.5, 1.0),
            exact_fresnel(f64::from(just_below), 1.5, 1.0),
        ),
        reflectance(
            "fresnel-just-past-the-critical-angle",
            FRESNEL_9,
            "glass to air 1e-4 rad past the critical angle: total internal reflection, R = 1",
            false,
            (just_above, 1.5, 1.0),
            1.0,
        ),
        reflectance(
            "fresnel-equal-media",
            FRESNEL_9,
            "water to water (1.33 to 1.33): no boundary, nothing reflected, R = 0 (not 0/0)",
            false,
            (0.3, 1.33, 1.33),
            0.0,
        ),
        reflectance(
            "fresnel-zero-index",
            FRESNEL_9,
            "n1 = 0, not an index (no medium has one below 1, and 0 makes n1 / n2 = 0): \
             expected NaN, a loud answer, not a plausible R",
            false,
            (0.8, 0.0, 1.5),
            f64::NAN,
        ),
        reflectance(
            "schlick-negative-index",
            SCHLICK_9,
            "n2 = -1.5, not an index: expected NaN (Schlick's R0 = ((1 + 1.5) / (1 - 1.5))^2 \
             = 25 would be no reflectance at all)",
            true,
            (0.8, 1.0, -1.5),
            f64::NAN,
        ),
        reflectance(
            "schlick-nearly-grazing",
            SCHLICK_9,
            "air to glass with cos_i = 1e-7: R = 0.04 + 0.96 (1 - 1e-7)^5, just below 1",
            true,
            (1e-7, 1.0, 1.5),
            0.04 + 0.96 * (1.0 - f64::from(1e-7f32)).powi(5),
        ),
        Case::new(
            "transmittance-no-absorption-forever",
            ABSORPTION_9,
            "a channel that absorbs nothing keeps everything even over an infinite distance \
             (0 x inf would be NaN): (0, 0, 0) over inf gives (1, 1, 1)",
            CaseKind::Transmittance {
                absorption: Vec3::ZERO,
                distance: f32::INFINITY,
            },
        ),
    ]
}

// ---------------------------------------------------------------------------
// Chapter 11: the bounding volume hierarchy.

const SLAB_11: &str = "The slab test";
const NAN_11: &str = "Why NaN cannot sneak in";
const ROUNDING_11: &str = "Rounding: widening the interval";
const BUILD_11: &str = "Building the tree";
const SAH_11: &str = "Where to cut: the surface-area heuristic";
const WALK_11: &str = "Walking the tree: the nearest hit";
const ANY_11: &str = "Any hit, for shadows";
const PLANES_11: &str = "Why planes stay out";

/// The box of every `hit_box` checkpoint: the cube from -1 to 1.
const CUBE: (Vec3, Vec3) = (Vec3::splat(-1.0), Vec3::splat(1.0));

/// A `hit_box` case on `bounds`, for the ray `(origin, dir)` and
/// `t_min < t < t_max`, expecting the entry `t` or a miss.
fn box_case(
    name: &'static str,
    section: &'static str,
    says: &str,
    bounds: (Vec3, Vec3),
    ray: (Vec3, Vec3),
    range: (f32, f32),
    expect: Option<f64>,
) -> Case {
    Case::new(
        name,
        section,
        says,
        CaseKind::HitBox {
            min: bounds.0,
            max: bounds.1,
            origin: ray.0,
            dir: ray.1,
            t_min: range.0,
            t_max: range.1,
            expect,
        },
    )
}

/// The tree's shape is the student's choice, but the checkpoints ask for
/// one leaf per object, cut at the middle, so that a walk has several
/// leaves to choose between (the surface-area heuristic would keep three
/// spheres in one leaf, and hide a walk that stops too early).
const ONE_PER_LEAF: BvhOptions = BvhOptions {
    split: SplitRule::Midpoint,
    bins: 16,
    max_leaf: 1,
};

fn sphere(x: f32, y: f32, z: f32, radius: f32) -> Shape {
    Sphere::new(v(x, y, z), radius).into()
}

/// The middle cut, two objects per leaf: the `max_leaf` checkpoints.
const MIDDLE_TWO_PER_LEAF: BvhOptions = BvhOptions {
    split: SplitRule::Midpoint,
    bins: 16,
    max_leaf: 2,
};

/// The surface-area heuristic, one object per leaf allowed: the SAH
/// checkpoints, where the heuristic alone decides when to stop.
const SAH_ONE_PER_LEAF: BvhOptions = BvhOptions {
    split: SplitRule::Sah,
    bins: 16,
    max_leaf: 1,
};

/// A `build_bvh` case over the boxes of `shapes`: a valid tree of the
/// shape `expect`.
fn build_case(
    name: &'static str,
    section: &'static str,
    says: &str,
    shapes: Vec<Shape>,
    options: BvhOptions,
    expect: TreeShape,
) -> Case {
    Case::new(
        name,
        section,
        says,
        CaseKind::BvhBuild {
            shapes,
            options,
            expect,
        },
    )
}

/// A `nearest_hit_bvh` (or, `any`, `any_hit_bvh`) case over `shapes`.
#[allow(clippy::too_many_arguments)]
fn bvh_case(
    name: &'static str,
    section: &'static str,
    says: &str,
    shapes: Vec<Shape>,
    options: BvhOptions,
    rays: Vec<Ray>,
    range: (f32, f32),
    any: bool,
) -> Case {
    Case::new(
        name,
        section,
        says,
        CaseKind::BvhHits {
            shapes,
            options,
            rays,
            t_min: range.0,
            t_max: range.1,
            any,
        },
    )
}

/// Chapter 11's checkpoint cases.
pub fn chapter_11() -> Vec<Case> {
    let x = Vec3::X;
    let z = Vec3::Z;
    // Behind each other on the z axis, the first-hit one not the first-entered.
    let behind = || {
        vec![
            sphere(0.0, 4.0, 10.0, 5.0),
            sphere(0.0, 0.0, 7.0, 1.0),
            sphere(0.0, 0.0, 20.0, 1.0),
        ]
    };
    let plane_between = || {
        vec![
            sphere(0.0, 0.0, 10.0, 1.0),
            Plane::new(v(0.0, 0.0, 5.0), -z).into(),
            sphere(0.0, 0.0, 3.0, 1.0),
        ]
    };
    let blockers = || {
        vec![
            sphere(3.0, 0.0, 5.0, 1.0),
            sphere(0.0, 0.0, 5.0, 1.0),
            sphere(-3.0, 0.0, 5.0, 1.0),
        ]
    };
    let from_origin = |dir: Vec3| Ray::new(Vec3::ZERO, dir);
    vec![
        box_case(
            "box-from-outside",
            SLAB_11,
            "the box from (-1, -1, -1) to (1, 1, 1); a ray from (-5, -2.5, 0) along (2, 1, 0): \
             inside the x slab for t from 2 to 3, the y slab from 1.5 to 3.5, the z slab always \
             (dir.z = 0, origin inside it); inside all three from t = 2 to 3: expected 2",
            CUBE,
            (v(-5.0, -2.5, 0.0), v(2.0, 1.0, 0.0)),
            ALL,
            Some(2.0),
        ),
        box_case(
            "box-negative-direction",
            SLAB_11,
            "the same box; a ray from (5, 0, 0) along (-1, 0, 0) meets the plane x = 1 (max.x) \
             first, at t = 4, and x = -1 at t = 6: expected 4",
            CUBE,
            (v(5.0, 0.0, 0.0), -x),
            ALL,
            Some(4.0),
        ),
        box_case(
            "box-from-inside",
            SLAB_11,
            "the same box; a ray from its centre along (0.3, -0.2, 1) with t_min = 0.5: it starts \
             inside, so it is in the box from t_min on: expected 0.5",
            CUBE,
            (Vec3::ZERO, v(0.3, -0.2, 1.0)),
            (0.5, 10.0),
            Some(0.5),
        ),
        box_case(
            "box-behind",
            SLAB_11,
            "the same box; a ray from (-5, 0, 0) along (-1, 0, 0): the box is behind it (t from \
             -6 to -4): expected None",
            CUBE,
            (v(-5.0, 0.0, 0.0), -x),
            ALL,
            None,
        ),
        box_case(
            "box-beyond-t-max",
            SLAB_11,
            "the same box; a ray from (-5, 0, 0) along (1, 0, 0) with t_max = 3.9: the box starts \
             at t = 4, too far: expected None",
            CUBE,
            (v(-5.0, 0.0, 0.0), x),
            (0.0, 3.9),
            None,
        ),
        box_case(
            "box-missed",
            SLAB_11,
            "the same box; a ray from (-5, 0, 0) along (1, 1, 0): inside the x slab for t from 4 \
             to 6, the y slab from -1 to 1, never both: expected None",
            CUBE,
            (v(-5.0, 0.0, 0.0), v(1.0, 1.0, 0.0)),
            ALL,
            None,
        ),
        box_case(
            "box-parallel-inside-slab",
            NAN_11,
            "the same box; a ray from (0, 0.5, -5) along (0, 0, 1): dir.y = 0, so 1 / dir.y = inf \
             and the y slab gives (-1 - 0.5) x inf = -inf to (1 - 0.5) x inf = inf, always \
             inside; the z slab from 4 to 6: expected 4",
            CUBE,
            (v(0.0, 0.5, -5.0), z),
            ALL,
            Some(4.0),
        ),
        box_case(
            "box-parallel-outside-slab",
            NAN_11,
            "the same box; a ray from (0, 2, -5) along (0, 0, 1): the y slab gives \
             (-1 - 2) x inf = -inf to (1 - 2) x inf = -inf, never inside: expected None",
            CUBE,
            (v(0.0, 2.0, -5.0), z),
            ALL,
            None,
        ),
        box_case(
            "box-zero-direction-on-slab-plane",
            NAN_11,
            "the same box; a ray from (0, 1, -5) along (0, 0, 1): dir.y = 0 and the origin lies \
             on the plane y = 1 (max.y), so that plane's crossing is (1 - 1) x inf = 0 x inf = \
             NaN. The ray runs along the box's top face, on its closed boundary: the y axis must \
             not constrain it. The z slab from 4 to 6: expected 4",
            CUBE,
            (v(0.0, 1.0, -5.0), z),
            ALL,
            Some(4.0),
        ),
        box_case(
            "box-negative-zero-on-min-plane",
            NAN_11,
            "the same box; a ray from (0, -1, -5) along (0, -0, 1): 1 / -0 = -inf, and the origin \
             is on the plane y = -1 (min.y): (-1 - -1) x -inf = NaN again, on the bottom face: \
             expected 4",
            CUBE,
            (v(0.0, -1.0, -5.0), v(0.0, -0.0, 1.0)),
            ALL,
            Some(4.0),
        ),
        Case::new(
            "bvh-build-holds-every-sphere",
            BUILD_11,
            "five unit spheres at x = 0, 3, 6, 9, 12 (listed out of order), one per leaf: every \
             sphere exactly once in a leaf whose box holds the sphere's box (x - 1 to x + 1), \
             every inner node's box holding its two children's, nothing in unbounded",
            CaseKind::BvhBuild {
                shapes: vec![
                    sphere(6.0, 0.0, 0.0, 1.0),
                    sphere(0.0, 0.0, 0.0, 1.0),
                    sphere(12.0, 0.0, 0.0, 1.0),
                    sphere(3.0, 0.0, 0.0, 1.0),
                    sphere(9.0, 0.0, 0.0, 1.0),
                ],
                options: ONE_PER_LEAF,
                expect: TreeShape::Any,
            },
        ),
        bvh_case(
            "bvh-nearest-behind-a-nearer-box",
            WALK_11,
            "a ray from the origin along +z; object 0, centre (0, 4, 10) radius 5: its box starts \
             at z = 5, and the ray passes 4 from its centre, so it is hit at z = 10 - sqrt(25 - \
             16) = 7; object 1, centre (0, 0, 7) radius 1: box from z = 6, hit at 6; object 2 at \
             (0, 0, 20), radius 1. Object 0's box is entered first but object 1 is hit nearer: \
             expected object 1 at t = 6 (a walk that stops at the first leaf with a hit says \
             object 0 at t = 7)",
            behind(),
            ONE_PER_LEAF,
            vec![from_origin(z)],
            ALL,
            false,
        ),
        Case::new(
            "bvh-plane-stays-out",
            PLANES_11,
            "a unit sphere at (0, 0, 10) (object 0), the plane z = 5 (object 1, no box: \
             Shape::bounds is None) and a unit sphere at (0, 0, 3) (object 2): expected \
             unbounded = [1], and objects 0 and 2 in the tree",
            CaseKind::BvhBuild {
                shapes: plane_between(),
                options: ONE_PER_LEAF,
                expect: TreeShape::Any,
            },
        ),
        bvh_case(
            "bvh-plane-still-hit",
            PLANES_11,
            "the same three objects; a ray from the origin along +z hits object 2 at t = 2 first; \
             one along (0.6, 0, 0.8) passes 1.8 from the sphere at z = 3 and 6 from the one at \
             z = 10, and meets only the plane, at t = 5 / 0.8 = 6.25: expected object 2 at t = 2, \
             then object 1 at t = 6.25",
            plane_between(),
            ONE_PER_LEAF,
            vec![from_origin(z), from_origin(v(0.6, 0.0, 0.8))],
            ALL,
            false,
        ),
        bvh_case(
            "bvh-any-hit-finds-the-blocker",
            ANY_11,
            "unit spheres at (3, 0, 5), (0, 0, 5) and (-3, 0, 5); a shadow ray from the origin \
             along +z with t_max = 10 is blocked by object 1 at t = 4: expected a hit; one along \
             +y meets nothing: expected none",
            blockers(),
            ONE_PER_LEAF,
            vec![from_origin(z), from_origin(Vec3::Y)],
            (0.0, 10.0),
            true,
        ),
        bvh_case(
            "bvh-nearest-tie-goes-to-the-first-listed",
            WALK_11,
            "a unit sphere at (0, 0, 5) (object 0) and the plane z = 4 (object 1); a ray from \
             the origin along +z meets both at exactly t = 4 (5 - 1, and 4 / 1). Chapter 3 keeps \
             the first listed of equal hits: expected object 0 at t = 4, although the plane, \
             outside the tree, is asked first",
            vec![
                sphere(0.0, 0.0, 5.0, 1.0),
                Plane::new(v(0.0, 0.0, 4.0), -z).into(),
            ],
            ONE_PER_LEAF,
            vec![from_origin(z)],
            ALL,
            false,
        ),
        bvh_case(
            "bvh-any-hit-beyond-the-light",
            ANY_11,
            "the same spheres; the ray along +z with t_max = 3.5 (a light between the origin and \
             the spheres): the blocker at t = 4 is beyond it: expected no hit",
            blockers(),
            ONE_PER_LEAF,
            vec![from_origin(z)],
            (0.0, 3.5),
            true,
        ),
        bvh_case(
            "bvh-any-hit-only-planes",
            ANY_11,
            "the planes z = 8 and z = 3 and nothing with a box, so the tree has no nodes at all; \
             a shadow ray from the origin along +z with t_max = 10 is blocked by the plane z = 3 \
             at t = 3: expected a hit; one along +x runs parallel to both and must get past an \
             empty tree without asking for its root: expected none",
            vec![
                Plane::new(v(0.0, 0.0, 8.0), -z).into(),
                Plane::new(v(0.0, 0.0, 3.0), -z).into(),
            ],
            ONE_PER_LEAF,
            vec![from_origin(z), from_origin(x)],
            (0.0, 10.0),
            true,
        ),
        // The build's own rules, which the walks above cannot see (any
        // valid tree gives their answers). Which child is left is the
        // student's choice: a cut is compared as a partition.
        build_case(
            "bvh-max-leaf-objects-stay-a-leaf",
            BUILD_11,
            "two spheres of radius 1/128 at x = 0 and x = 1/32, max_leaf 2 (cut at the middle): \
             a node of max_leaf objects or fewer stays a leaf: expected the root a leaf holding \
             both, its box their boxes' union (x from -1/128 to 5/128, y and z from -1/128 to \
             1/128) grown by BOX_PADDING_EPSILONS (4) epsilons of its largest coordinate, 5/128: \
             about 2e-8",
            vec![
                sphere(0.0, 0.0, 0.0, 1.0 / 128.0),
                sphere(1.0 / 32.0, 0.0, 0.0, 1.0 / 128.0),
            ],
            MIDDLE_TWO_PER_LEAF,
            TreeShape::RootLeaf,
        ),
        build_case(
            "bvh-one-more-than-max-leaf-is-cut",
            BUILD_11,
            "unit spheres at x = 0, 2 and 6, max_leaf 2, cut at the middle: three objects are one \
             more than max_leaf, so the root is cut; the centroids (the centres) spread along x \
             from 0 to 6, the middle is 3: expected the root cut into objects [0, 1] (x = 0, 2) \
             and [2] (x = 6)",
            vec![
                sphere(0.0, 0.0, 0.0, 1.0),
                sphere(2.0, 0.0, 0.0, 1.0),
                sphere(6.0, 0.0, 0.0, 1.0),
            ],
            MIDDLE_TWO_PER_LEAF,
            TreeShape::RootCut(vec![vec![0, 1]]),
        ),
        build_case(
            "bvh-middle-of-the-centroids",
            BUILD_11,
            "spheres at x = 3, 4, 5, 6 with radii 1, 3, 3, 1, one per leaf, cut at the middle: \
             the centroids are the centres (the middle of each box), spread 3 along x and 0 along \
             y and z; the middle of that spread is 4.5: expected the root cut into objects [0, 1] \
             and [2, 3]",
            vec![
                sphere(3.0, 0.0, 0.0, 1.0),
                sphere(4.0, 0.0, 0.0, 3.0),
                sphere(5.0, 0.0, 0.0, 3.0),
                sphere(6.0, 0.0, 0.0, 1.0),
            ],
            ONE_PER_LEAF,
            TreeShape::RootCut(vec![vec![0, 1]]),
        ),
        build_case(
            "bvh-sah-cut-not-the-middle",
            SAH_11,
            "unit spheres at x = 100, 101, 105, 106, 111 (objects 0 to 4), the surface-area \
             heuristic with 16 bins, TRAVERSAL_COST 1, max_leaf 1. Each box is 2 by 2 in y and z \
             and L long in x: half its area is 2 L + 2 L + 4 = 4 L + 4. The root's is 56 (L = \
             13), so the leaf costs 56 x 5 = 280; multiplied through by 56, a cut costs 56 + \
             (half area x count) of each side: [0] | [1, 2, 3, 4]: 56 + 12 x 1 + 52 x 4 = 276; \
             [0, 1] | [2, 3, 4]: 56 + 16 x 2 + 36 x 3 = 196; [0, 1, 2] | [3, 4]: 56 + 32 x 3 + 32 \
             x 2 = 216; [0, 1, 2, 3] | [4]: 56 + 36 x 4 + 12 x 1 = 212. Expected the root cut \
             into objects [0, 1] and [2, 3, 4]; or, from a build that always cuts at the middle \
             (the split rule is the student's choice), [0, 1, 2] and [3, 4] (the middle of the \
             centroids is 105.5). Not a leaf, and not [0] alone",
            vec![
                sphere(100.0, 0.0, 0.0, 1.0),
                sphere(101.0, 0.0, 0.0, 1.0),
                sphere(105.0, 0.0, 0.0, 1.0),
                sphere(106.0, 0.0, 0.0, 1.0),
                sphere(111.0, 0.0, 0.0, 1.0),
            ],
            SAH_ONE_PER_LEAF,
            TreeShape::RootCut(vec![vec![0, 1], vec![0, 1, 2]]),
        ),
        // The example above has boxes of one height and depth, so any half
        // area of the form a L + b with a, b > 0 ranks some cuts alike; these
        // have boxes of several sizes, each of whose sides counts.
        build_case(
            "bvh-sah-the-big-box-alone",
            SAH_11,
            "spheres on the x axis at x = 4, 7.5, 10 and 10.5, radii 2, 1, 2 and 4 (objects 0 \
             to 3), the SAH, 16 bins, max_leaf 1. A sphere's box is a cube of side 2 r, half \
             area 3 (2 r)^2: 48, 12, 48, 192. The root, from (2, -4, -4) to (14.5, 4, 4), has \
             12.5 x 8 + 8 x 8 + 8 x 12.5 = 264 (the leaf: 264 x 4 = 1056). Object 3's box holds \
             every box right of any cut, so each cut costs 264 + (left half area) x (left \
             count) + 192 x (right count): [0] | [1, 2, 3]: 264 + 48 + 576 = 888; [0, 1] | \
             [2, 3]: left 6.5 by 4 by 4, 68: 264 + 136 + 384 = 784; [0, 1, 2] | [3]: left 10 \
             by 4 by 4, 96: 264 + 288 + 192 = 744. Expected the root cut into [0, 1, 2] and \
             [3] (or, cut at the middle of the centroids, 7.25: [0] and [1, 2, 3])",
            vec![
                sphere(4.0, 0.0, 0.0, 2.0),
                sphere(7.5, 0.0, 0.0, 1.0),
                sphere(10.0, 0.0, 0.0, 2.0),
                sphere(10.5, 0.0, 0.0, 4.0),
            ],
            SAH_ONE_PER_LEAF,
            TreeShape::RootCut(vec![vec![0, 1, 2], vec![0]]),
        ),
        build_case(
            "bvh-sah-three-sides-count",
            SAH_11,
            "spheres at (1, 0, -1), (2, 0, 1), (5, 0, 0) and (11.5, 0, 0), radii 4, 2, 1 and 2 \
             (objects 0 to 3; half areas 192, 48, 12, 48), the SAH, 16 bins, max_leaf 1. The \
             root from (-3, -4, -5) to (13.5, 4, 3): 16.5 x 8 + 8 x 8 + 8 x 16.5 = 328. [0] | \
             [1, 2, 3]: the right box from (0, -2, -2) to (13.5, 2, 3), 13.5 x 4 + 4 x 5 + 5 x \
             13.5 = 141.5: 328 + 192 + 141.5 x 3 = 944.5; [0, 1] | [2, 3]: object 0's box holds \
             object 1's, 192 x 2, and the right box from (4, -2, -2) to (13.5, 2, 2), 92 x 2: \
             328 + 384 + 184 = 896; [0, 1, 2] | [3]: the left box 9 by 8 by 8, 208 x 3, and \
             48: 328 + 624 + 48 = 1000. Expected the root cut into [0, 1] and [2, 3] (or, cut \
             at the middle of the centroids, 6.25: [0, 1, 2] and [3])",
            vec![
                sphere(1.0, 0.0, -1.0, 4.0),
                sphere(2.0, 0.0, 1.0, 2.0),
                sphere(5.0, 0.0, 0.0, 1.0),
                sphere(11.5, 0.0, 0.0, 2.0),
            ],
            SAH_ONE_PER_LEAF,
            TreeShape::RootCut(vec![vec![0, 1], vec![0, 1, 2]]),
        ),
        build_case(
            "bvh-sah-the-first-alone",
            SAH_11,
            "spheres at (15, 0, 0), (35, 0, -1), (36, 0, 0) and (56, 0, 1), radii 3, 2, 1 and 2 \
             (objects 0 to 3; half areas 108, 48, 12, 48), the SAH, 16 bins, max_leaf 1. The \
             root from (12, -3, -3) to (58, 3, 3): 46 x 6 + 6 x 6 + 6 x 46 = 588. [0] | [1, 2, \
             3]: the right box from (33, -2, -3) to (58, 2, 3), 25 x 4 + 4 x 6 + 6 x 25 = 274: \
             588 + 108 + 274 x 3 = 1518; [0, 1] | [2, 3]: the left box 25 by 6 by 6, 336 x 2, \
             the right from (35, -2, -1) to (58, 2, 3), 200 x 2: 588 + 672 + 400 = 1660; \
             [0, 1, 2] | [3]: 588 + 336 x 3 + 48 = 1644. Expected the root cut into [0] and \
             [1, 2, 3] (or, cut at the middle of the centroids, 35.5: [0, 1] and [2, 3])",
            vec![
                sphere(15.0, 0.0, 0.0, 3.0),
                sphere(35.0, 0.0, -1.0, 2.0),
                sphere(36.0, 0.0, 0.0, 1.0),
                sphere(56.0, 0.0, 1.0, 2.0),
            ],
            SAH_ONE_PER_LEAF,
            TreeShape::RootCut(vec![vec![0], vec![0, 1]]),
        ),
        build_case(
            "bvh-sah-leaf-cheaper-than-any-cut",
            SAH_11,
            "spheres at x = 3, 4.5 and 5.5 on the x axis, radii 3, 3 and 2.5 (objects 0 to 2; \
             half areas 108, 108, 75), the SAH, 16 bins, max_leaf 1. The root from (0, -3, -3) \
             to (8, 3, 3): 8 x 6 + 6 x 6 + 6 x 8 = 132, the leaf 132 x 3 = 396. [0] | [1, 2]: \
             the right box 6.5 by 6 by 6, 114: 132 + 108 + 114 x 2 = 468; [0, 1] | [2]: the \
             left box 7.5 by 6 by 6, 126: 132 + 126 x 2 + 75 = 459. Both cost more than the \
             leaf (the boxes overlap: a ray into one is likely in the other), so the SAH keeps \
             it: expected the root a leaf holding all three (or, cut at the middle of the \
             centroids, 4.25: [0] and [1, 2]). The cost of visiting the node, TRAVERSAL_COST x 132, is what makes \
             the cut [0, 1] | [2] dearer",
            vec![
                sphere(3.0, 0.0, 0.0, 3.0),
                sphere(4.5, 0.0, 0.0, 3.0),
                sphere(5.5, 0.0, 0.0, 2.5),
            ],
            SAH_ONE_PER_LEAF,
            TreeShape::RootLeafOrCut(vec![vec![0]]),
        ),
        build_case(
            "bvh-cut-along-z",
            BUILD_11,
            "unit spheres at z = 0, 3 and 7 on the z axis, one per leaf, cut at the middle: the \
             centroids spread 0 along x and y and 7 along z, so z is the axis to cut, at 3.5: \
             expected the root cut into [0, 1] and [2] (a widest-axis search that stays on x \
             or y finds no spread there and makes a leaf)",
            vec![
                sphere(0.0, 0.0, 0.0, 1.0),
                sphere(0.0, 0.0, 3.0, 1.0),
                sphere(0.0, 0.0, 7.0, 1.0),
            ],
            ONE_PER_LEAF,
            TreeShape::RootCut(vec![vec![0, 1]]),
        ),
        build_case(
            "bvh-nan-and-infinite-boxes-stay-out",
            PLANES_11,
            "unit spheres at (0, 0, 0) (object 0) and (3, 0, 0) (object 3); object 1 a sphere \
             with a NaN centre (its box is NaN); object 2 centred at x = 3e38 with radius 1e38, \
             whose box reaches x = 4e38, past f32::MAX (3.4e38): max.x = inf. Neither box is \
             finite: expected unbounded = [1, 2], objects 0 and 3 in the tree",
            vec![
                sphere(0.0, 0.0, 0.0, 1.0),
                sphere(f32::NAN, 0.0, 0.0, 1.0),
                sphere(3e38, 0.0, 0.0, 1e38),
                sphere(3.0, 0.0, 0.0, 1.0),
            ],
            ONE_PER_LEAF,
            TreeShape::Any,
        ),
        box_case(
            "box-entry-close-to-the-origin",
            ROUNDING_11,
            "the cube; a ray from (-5, 0, 0) along (4096, 0, 0): the x slab from t = 4/4096 to \
             6/4096, the others always: expected 4/4096 = 0.0009765625. The widening moves it by \
             2 gamma_3 of itself (about 4e-10): a slack that grew as t shrank would not",
            CUBE,
            (v(-5.0, 0.0, 0.0), v(4096.0, 0.0, 0.0)),
            ALL,
            Some(4.0 / 4096.0),
        ),
    ]
}

/// `count` spheres with centres in `[-extent, extent]^3` and radii in
/// `radii`, from `seed`, and `rays` rays from `eye` toward random points of
/// the same cube: the same every run.
fn random_spheres(
    seed: u64,
    count: usize,
    extent: f32,
    radii: (f32, f32),
    eye: Vec3,
    rays: usize,
) -> (Vec<Shape>, Vec<Ray>) {
    let mut numbers = exact::Xorshift::new(seed);
    let point = |numbers: &mut exact::Xorshift| {
        v(
            numbers.between(-extent, extent),
            numbers.between(-extent, extent),
            numbers.between(-extent, extent),
        )
    };
    let shapes = (0..count)
        .map(|_| {
            let center = point(&mut numbers);
            Sphere::new(center, numbers.between(radii.0, radii.1)).into()
        })
        .collect();
    let rays = (0..rays)
        .map(|_| Ray::new(eye, point(&mut numbers) - eye))
        .collect();
    (shapes, rays)
}

/// Chapter 11's hard cases.
pub fn chapter_11_robustness() -> Vec<Case> {
    let default = BvhOptions::default();
    let (thousand, thousand_rays) =
        random_spheres(11, 1000, 20.0, (0.1, 0.6), v(0.0, 0.0, -40.0), 200);
    let (huge, huge_rays) = random_spheres(1100, 300, 1e5, (1e3, 5e3), v(0.0, 0.0, -3e5), 200);
    // Two pairs of copies, and a big sphere touching a small one from
    // inside at z = 4, where the ray along +z meets both: ties everywhere.
    let ties = vec![
        sphere(0.0, 0.0, 20.0, 1.0),
        sphere(0.0, 0.0, 6.0, 2.0),
        sphere(0.0, 0.0, 5.0, 1.0),
        sphere(0.0, 0.0, 20.0, 1.0),
        sphere(0.0, 0.0, 5.0, 1.0),
        sphere(0.0, 0.0, 6.0, 2.0),
        sphere(2.0, 0.0, 5.0, 1.0),
        sphere(2.0, 0.0, 5.0, 1.0),
        Plane::new(v(0.0, 0.0, 4.0), -Vec3::Z).into(),
    ];
    let tie_rays: Vec<Ray> = [
        Vec3::Z,
        v(0.1, 0.0, 1.0),
        v(-0.1, 0.05, 1.0),
        v(0.4, 0.0, 1.0),
        v(0.0, 0.0, -1.0),
    ]
    .into_iter()
    .map(|dir| Ray::new(Vec3::ZERO, dir))
    .collect();
    // 200 spheres around one centre: every centroid the same point.
    let center = v(0.0, 0.0, 10.0);
    let concentric: Vec<Shape> = (0..200)
        .map(|index| Sphere::new(center, 0.5 + 0.0225 * index as f32).into())
        .collect();
    let concentric_rays = vec![
        Ray::new(Vec3::ZERO, Vec3::Z),
        Ray::new(Vec3::ZERO, v(0.2, 0.1, 1.0)),
        Ray::new(center, v(1.0, 0.5, -0.25)),
        Ray::new(center + v(0.0, 0.0, 1.0), Vec3::Z),
    ];
    robust(vec![
        bvh_case(
            "bvh-thousand-spheres",
            WALK_11,
            "1000 spheres of radius 0.1 to 0.6 scattered in the cube from -20 to 20 (the same \
             every run), the default options (SAH, 16 bins, max_leaf 4); 200 rays from \
             (0, 0, -40) into the cube: each must find chapter 3's hit, same object, same t",
            thousand.clone(),
            default,
            thousand_rays.clone(),
            ALL,
            false,
        ),
        bvh_case(
            "bvh-thousand-spheres-any-hit",
            ANY_11,
            "the same 1000 spheres and 200 rays, through any_hit_bvh: a real hit exactly when \
             chapter 3 finds one",
            thousand,
            default,
            thousand_rays,
            ALL,
            true,
        ),
        bvh_case(
            "bvh-huge-coordinates",
            WALK_11,
            "300 spheres of radius 1e3 to 5e3 with centres up to 1e5 from the origin, 200 rays \
             from (0, 0, -3e5): box areas near 1e11 (an f32 product of two sides is fine, a sum \
             of many costs needs care), and still chapter 3's hit on every ray",
            huge,
            default,
            huge_rays,
            ALL,
            false,
        ),
        bvh_case(
            "bvh-ties-lower-index-wins",
            WALK_11,
            "copies of the same spheres (objects 2 and 4, 1 and 5, 6 and 7, 0 and 3), the \
             radius 2 sphere at z = 6 touching the unit one at z = 5 from inside at z = 4, and \
             the plane z = 4 (object 8), one sphere per leaf where they can be cut apart: along \
             +z objects 1, 2, 4, 5 and 8 are all hit at t = 4. Chapter 3 keeps the first listed \
             of equal hits: expected its answer (object 1 at t = 4) on each of 5 rays",
            ties,
            ONE_PER_LEAF,
            tie_rays,
            ALL,
            false,
        ),
        bvh_case(
            "bvh-coincident-centroids",
            BUILD_11,
            "200 spheres around the same centre (0, 0, 10), radii 0.5 to 4.98: every centroid is \
             the same point, so no cut can separate them, even with max_leaf 1 (the build must \
             stop, not loop or recurse forever); from outside the largest is hit first, from the \
             centre the smallest: chapter 3's answer on each ray",
            concentric,
            ONE_PER_LEAF,
            concentric_rays,
            ALL,
            false,
        ),
        bvh_case(
            "bvh-only-planes",
            PLANES_11,
            "two planes and nothing with a box (an empty tree): a ray from the origin along +z \
             meets the plane z = 3 at t = 3: expected object 1 at t = 3",
            vec![
                Plane::new(v(0.0, 0.0, 8.0), -Vec3::Z).into(),
                Plane::new(v(0.0, 0.0, 3.0), -Vec3::Z).into(),
            ],
            default,
            vec![Ray::new(Vec3::ZERO, Vec3::Z)],
            ALL,
            false,
        ),
        bvh_case(
            "bvh-nan-ray",
            NAN_11,
            "a ray whose direction is NaN through the 1000 spheres' first ten: no box can \
             reject it (every crossing is NaN), the objects' own tests do: expected no hit",
            random_spheres(11, 10, 20.0, (0.1, 0.6), Vec3::ZERO, 0).0,
            default,
            vec![Ray::new(Vec3::ZERO, Vec3::NAN)],
            ALL,
            false,
        ),
        box_case(
            "box-through-a-corner",
            ROUNDING_11,
            "the cube from -1 to 1; a ray from (2, 2, 0) along (-1, -1, 1) touches it only at \
             the corner (1, 1, 1), at t = 1, where it enters (x and y planes) and leaves (the \
             z plane) at once: expected 1",
            CUBE,
            (v(2.0, 2.0, 0.0), v(-1.0, -1.0, 1.0)),
            ALL,
            Some(1.0),
        ),
        Case::new(
            "box-rays-along-edges",
            ROUNDING_11,
            "20000 rays from random origins aimed at random points of the edges of the box \
             from (-1.3, 0.2, 2.7) to (0.9, 1.7, 3.1): where the exact ray (in f64) meets the \
             box, even along a sliver, hit_box must say so; the rounded crossings can put \
             the entry a hair past the exit, which the widening by 2 gamma_3 absorbs",
            CaseKind::BoxEdges {
                min: v(-1.3, 0.2, 2.7),
                max: v(0.9, 1.7, 3.1),
                rays: 20_000,
                seed: 0x2545_f491_4f6c_dd1d,
            },
        ),
        bvh_case(
            "bvh-deeper-than-the-stack",
            WALK_11,
            "70 unit spheres on the x axis at x = 3^k, k = 0 to 69 (object k), one per leaf, \
             cut at the middle: the middle of 1 to 3^n is (1 + 3^n) / 2, above every centroid \
             but the last, so each cut peels off one sphere and the tree is 69 levels deep, more \
             than the 64 waiting nodes the walk keeps in a fixed array. A ray from (-10, 0, 0) \
             along +x meets every box and sets each peeled sphere aside on its way down: \
             expected object 0 at t = 10",
            (0..70)
                .map(|k| sphere(3.0f32.powi(k), 0.0, 0.0, 1.0))
                .collect(),
            ONE_PER_LEAF,
            vec![Ray::new(v(-10.0, 0.0, 0.0), Vec3::X)],
            ALL,
            false,
        ),
        bvh_case(
            "bvh-tie-far-from-the-origin",
            WALK_11,
            "a unit sphere at (0, 0, 5) (object 0, in the tree) and the plane z = 4 (object 1, \
             asked first); a ray from (0, 0, -100) along +z meets both at exactly t = 104. The \
             sphere's padded box is entered at 104 in f32 too: only the widening, which moves \
             the entry down by 2 gamma_3 of 104 (4e-5, five ulps there), lets the walk open it \
             at a best of 104. Chapter 3 keeps the first listed: expected object 0 at t = 104",
            vec![
                sphere(0.0, 0.0, 5.0, 1.0),
                Plane::new(v(0.0, 0.0, 4.0), -Vec3::Z).into(),
            ],
            ONE_PER_LEAF,
            vec![Ray::new(v(0.0, 0.0, -100.0), Vec3::Z)],
            ALL,
            false,
        ),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_expected_hit_has_an_exact_value() {
        for case in chapter_1()
            .into_iter()
            .chain(chapter_1_robustness())
            .chain(chapter_2())
            .chain(chapter_2_robustness())
        {
            if let CaseKind::Plane { expect, .. } | CaseKind::Sphere { expect, .. } = case.kind {
                if let ExpectT::Hit(t) = expect {
                    assert!(t.is_finite(), "{}: the exact reference misses", case.name);
                }
            }
        }
    }

    /// The skimming rays miss in exact arithmetic, and clearly for f64: their
    /// lines pass 5e-4 and 1.1e-5 above the sphere, where `exact::sphere`'s
    /// own rounding is about 1e-16 of the radius.
    #[test]
    fn skim_cases_miss_in_exact_arithmetic() {
        for name in ["sphere-skim-over-ground", "sphere-skim-over-hill"] {
            let case = chapter_2_robustness()
                .into_iter()
                .find(|case| case.name == name)
                .unwrap();
            let CaseKind::Sphere {
                center,
                radius,
                ray,
                ..
            } = case.kind
            else {
                panic!("{name} is not a sphere case")
            };
            let (c, o, d) = (wide(center), wide(ray.origin), wide(ray.dir));
            let oc = o - c;
            let foot = oc - d * (oc.dot(d) / d.dot(d));
            let above = foot.length() - f64::from(radius);
            assert!(
                above > 1e-5 && above < 1e-3,
                "{name}: the line passes {above:e} above"
            );
            let hit = exact::sphere(c, f64::from(radius), o, d, 0.0, f64::INFINITY);
            assert_eq!(hit, None, "{name}");
        }
    }
}

// ---------------------------------------------------------------------------
// Chapter 10: triangle meshes.

const HIT_10: &str = "Where a ray meets a triangle";
const LEAK_10: &str = "Why it leaks";
const WATERTIGHT_10: &str = "A watertight test";
const BARYCENTRIC_10: &str = "Barycentric coordinates of a hit";
const SMOOTH_10: &str = "Smooth shading";
const TERMINATOR_10: &str = "The shadow terminator";

/// The lesson's triangle: the right triangle (0, 0), (1, 0), (0, 1) in the
/// plane z = 2. By the winding its normal is +z.
const LESSON_TRIANGLE: [Vec3; 3] = [
    Vec3::new(0.0, 0.0, 2.0),
    Vec3::new(1.0, 0.0, 2.0),
    Vec3::new(0.0, 1.0, 2.0),
];

/// The same right triangle in the plane z = 0, for the shading cases.
const FLOOR_TRIANGLE: [Vec3; 3] = [Vec3::ZERO, Vec3::X, Vec3::Y];

/// Vertex normals of a bulge over [`FLOOR_TRIANGLE`], like a cylinder
/// along y seen from +z: tilted away from the middle at x = 0 and x = 1.
/// Unit (0.6^2 + 0.8^2 = 1), so every lift is a few products by hand.
const CONVEX_NORMALS: [Vec3; 3] = [
    Vec3::new(-0.6, 0.0, 0.8),
    Vec3::new(0.6, 0.0, 0.8),
    Vec3::new(-0.6, 0.0, 0.8),
];

/// The same tilts the other way: a hollow.
const CONCAVE_NORMALS: [Vec3; 3] = [
    Vec3::new(0.6, 0.0, 0.8),
    Vec3::new(-0.6, 0.0, 0.8),
    Vec3::new(0.6, 0.0, 0.8),
];

/// One normal per axis: their blend shows each weight on its own axis.
const AXIS_NORMALS: [Vec3; 3] = [Vec3::X, Vec3::Y, Vec3::Z];

/// The four faces of the tetrahedron on `corners` (each shares every edge
/// with another face: a closed mesh).
fn tetrahedron(corners: [Vec3; 4]) -> Vec<[Vec3; 3]> {
    [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]
        .into_iter()
        .map(|face| face.map(|corner| corners[corner]))
        .collect()
}

/// A case of `intersect_triangle` on each of `triangles`; a hit's `t` is
/// the nearest exact one among them.
fn triangles_case(
    name: &'static str,
    section: &'static str,
    says: &str,
    triangles: Vec<[Vec3; 3]>,
    ray: (Vec3, Vec3),
    range: (f32, f32),
    expect: E,
) -> Case {
    let expect = match expect {
        E::Hit => ExpectT::Hit(
            triangles
                .iter()
                .filter_map(|corners| {
                    exact::triangle(
                        corners.map(wide),
                        wide(ray.0),
                        wide(ray.1),
                        f64::from(range.0),
                        f64::from(range.1),
                    )
                })
                .reduce(f64::min)
                .unwrap_or(f64::NAN),
        ),
        E::Miss => ExpectT::Miss,
        E::Either => ExpectT::Either,
    };
    Case::new(
        name,
        section,
        says,
        CaseKind::Triangles {
            triangles,
            ray: Ray::new(ray.0, ray.1),
            t_min: range.0,
            t_max: range.1,
            expect,
        },
    )
}

/// The lesson's triangle alone.
fn lesson_triangle_case(
    name: &'static str,
    says: &str,
    ray: (Vec3, Vec3),
    range: (f32, f32),
    expect: E,
) -> Case {
    triangles_case(
        name,
        HIT_10,
        says,
        vec![LESSON_TRIANGLE],
        ray,
        range,
        expect,
    )
}

/// The unit square at z = 2 as two triangles sharing its diagonal
/// (1, 0, 2)-(0, 1, 2): the first takes the square's corners `first` (indices
/// into (0, 0), (1, 0), (1, 1), (0, 1)), the second the same turned half a
/// turn about the square's centre, which keeps the winding and puts the
/// diagonal (reversed) in the same place of both. A ray from
/// (0.5, 0.5, `from_z`) toward z = 2 goes through the middle of the diagonal.
fn shared_diagonal_case(name: &'static str, says: &str, first: [usize; 3], from_z: f32) -> Case {
    let square = [
        v(0.0, 0.0, 2.0),
        v(1.0, 0.0, 2.0),
        v(1.0, 1.0, 2.0),
        v(0.0, 1.0, 2.0),
    ];
    let turned = |i: usize| square[(i + 2) % 4];
    let direction = if from_z > 2.0 { -Vec3::Z } else { Vec3::Z };
    triangles_case(
        name,
        WATERTIGHT_10,
        says,
        vec![first.map(|i| square[i]), first.map(turned)],
        (v(0.5, 0.5, from_z), direction),
        ALL,
        E::Hit,
    )
}

fn barycentric_case(name: &'static str, says: &str, corners: [Vec3; 3], point: Vec3) -> Case {
    Case::new(
        name,
        BARYCENTRIC_10,
        says,
        CaseKind::Barycentric { corners, point },
    )
}

fn smooth_normal_case(name: &'static str, says: &str, point: Vec3) -> Case {
    Case::new(
        name,
        SMOOTH_10,
        says,
        CaseKind::SmoothNormal {
            corners: LESSON_TRIANGLE,
            normals: AXIS_NORMALS,
            point,
        },
    )
}

fn terminator_case(name: &'static str, says: &str, normals: [Vec3; 3]) -> Case {
    Case::new(
        name,
        TERMINATOR_10,
        says,
        CaseKind::Terminator {
            corners: FLOOR_TRIANGLE,
            normals,
            point: v(0.25, 0.25, 0.0),
        },
    )
}

fn smooth_hit_case(name: &'static str, says: &str, from_z: f32, transparent: bool) -> Case {
    Case::new(
        name,
        TERMINATOR_10,
        says,
        CaseKind::SmoothHit {
            corners: FLOOR_TRIANGLE,
            normals: CONVEX_NORMALS,
            ray: Ray::new(v(0.25, 0.25, from_z), v(0.0, 0.0, -from_z.signum())),
            transparent,
        },
    )
}

/// Chapter 10's checkpoint cases. The first two are the ones the lesson's
/// "Your turn" paragraph promises.
pub fn chapter_10() -> Vec<Case> {
    let up = (v(0.25, 0.25, 0.0), Vec3::Z);
    vec![
        lesson_triangle_case(
            "triangle-hit-from-behind",
            "the lesson's triangle (0, 0, 2), (1, 0, 2), (0, 1, 2) and a ray from \
             (0.25, 0.25, 0) along +z: it meets the plane z = 2 at (0.25, 0.25, 2), inside \
             (beta = gamma = 0.25): expected t = 2. By the winding a -> b -> c the normal is +z, \
             away from the ray: the ray meets the triangle's back, and a triangle is two-sided",
            up,
            ALL,
            E::Hit,
        ),
        barycentric_case(
            "barycentric-lesson-point",
            "the lesson's triangle and that hit point (0.25, 0.25, 2): p - a = 0.25 e1 + 0.25 e2, \
             so beta = gamma = 0.25 and alpha = 1 - 0.25 - 0.25: expected (0.5, 0.25, 0.25)",
            LESSON_TRIANGLE,
            v(0.25, 0.25, 2.0),
        ),
        lesson_triangle_case(
            "triangle-hit-from-the-front",
            "the lesson's triangle and a ray from (0.25, 0.25, 5) along -z, on the side its \
             normal points to: expected t = 5 - 2 = 3",
            (v(0.25, 0.25, 5.0), -Vec3::Z),
            ALL,
            E::Hit,
        ),
        lesson_triangle_case(
            "triangle-miss-beyond-bc",
            "a ray from (0.75, 0.75, 0) along +z meets the plane z = 2 past the long edge \
             (beta + gamma = 1.5 > 1): expected no hit",
            (v(0.75, 0.75, 0.0), Vec3::Z),
            ALL,
            E::Miss,
        ),
        lesson_triangle_case(
            "triangle-miss-beyond-ca",
            "a ray from (-0.25, 0.5, 0) along +z meets the plane left of the edge x = 0 \
             (beta = -0.25): expected no hit",
            (v(-0.25, 0.5, 0.0), Vec3::Z),
            ALL,
            E::Miss,
        ),
        lesson_triangle_case(
            "triangle-miss-beyond-ab",
            "a ray from (0.5, -0.25, 0) along +z meets the plane below the edge y = 0 \
             (gamma = -0.25): expected no hit",
            (v(0.5, -0.25, 0.0), Vec3::Z),
            ALL,
            E::Miss,
        ),
        lesson_triangle_case(
            "triangle-direction-not-unit",
            "a ray from the origin along (0.5, 0.5, 4), not unit: z reaches 2 at t = 2 / 4, \
             at the point (0.25, 0.25, 2), inside: expected t = 0.5 (in units of the direction)",
            (Vec3::ZERO, v(0.5, 0.5, 4.0)),
            ALL,
            E::Hit,
        ),
        triangles_case(
            "triangle-along-x",
            HIT_10,
            "the triangle (2, 0, 0), (2, 1, 0), (2, 0, 1) in the plane x = 2 and a ray from \
             (0, 0.25, 0.25) along +x (the ray's largest component is x, not z): expected t = 2",
            vec![[v(2.0, 0.0, 0.0), v(2.0, 1.0, 0.0), v(2.0, 0.0, 1.0)]],
            (v(0.0, 0.25, 0.25), Vec3::X),
            ALL,
            E::Hit,
        ),
        triangles_case(
            "triangle-along-minus-y",
            HIT_10,
            "the triangle (0, -3, 0), (1, -3, 0), (0, -3, 1) in the plane y = -3 and a ray from \
             (0.25, 0, 0.25) along (0, -2, 0): 3 units away at 2 per unit of t: expected t = 1.5",
            vec![[v(0.0, -3.0, 0.0), v(1.0, -3.0, 0.0), v(0.0, -3.0, 1.0)]],
            (v(0.25, 0.0, 0.25), v(0.0, -2.0, 0.0)),
            ALL,
            E::Hit,
        ),
        lesson_triangle_case(
            "triangle-before-t-min",
            "the first case's ray with t_min = 2.5: the only hit, t = 2, is before it: expected \
             no hit",
            up,
            (2.5, INF),
            E::Miss,
        ),
        lesson_triangle_case(
            "triangle-beyond-t-max",
            "the first case's ray with t_max = 1.5 (a shadow ray that stops at its light): the \
             hit at t = 2 is beyond it: expected no hit",
            up,
            (0.0, 1.5),
            E::Miss,
        ),
        lesson_triangle_case(
            "triangle-parallel-ray",
            "a ray from (0.25, 0.25, 0) along +x, parallel to the plane z = 2: it never \
             reaches it: expected no hit (and no division by zero)",
            (v(0.25, 0.25, 0.0), Vec3::X),
            ALL,
            E::Miss,
        ),
        triangles_case(
            "triangle-shared-edge",
            LEAK_10,
            "the lesson's triangle and its neighbour (1, 0, 2), (1, 1, 2), (0, 1, 2) make the \
             unit square at z = 2; a ray from (0.5, 0.5, 0) along +z goes through the middle \
             of the diagonal they share: at least one of them must claim it: expected t = 2",
            vec![
                LESSON_TRIANGLE,
                [v(1.0, 0.0, 2.0), v(1.0, 1.0, 2.0), v(0.0, 1.0, 2.0)],
            ],
            (v(0.5, 0.5, 0.0), Vec3::Z),
            ALL,
            E::Hit,
        ),
        triangles_case(
            "triangle-shared-vertex",
            LEAK_10,
            "four triangles around the corner (0, 0, 2), one per quadrant of the plane z = 2 \
             (their far corners are (1, 0, 2), (0, 1, 2), (-1, 0, 2), (0, -1, 2)); a ray from \
             the origin along +z goes through that corner: at least one must claim it: \
             expected t = 2",
            {
                let centre = v(0.0, 0.0, 2.0);
                let rim = [
                    v(1.0, 0.0, 2.0),
                    v(0.0, 1.0, 2.0),
                    v(-1.0, 0.0, 2.0),
                    v(0.0, -1.0, 2.0),
                ];
                (0..4).map(|i| [centre, rim[i], rim[(i + 1) % 4]]).collect()
            },
            (Vec3::ZERO, Vec3::Z),
            ALL,
            E::Hit,
        ),
        // The unit square at z = 2 cut along its diagonal (1, 0, 2)-(0, 1, 2)
        // into two triangles wound the same way (normal +z), listed so that
        // the diagonal is the same edge of both: b -> c, c -> a or a -> b.
        // A ray exactly through it makes that edge's test exactly 0 in both
        // (the coordinates are exact in f32): only a test that counts 0 as
        // inside on every edge, from either side, claims it. (In
        // triangle-shared-edge above the diagonal is a different edge of each
        // triangle, which hides a test that is strict on one edge only.)
        shared_diagonal_case(
            "triangle-shared-diagonal-bc",
            "the unit square at z = 2 as the triangles (0, 0, 2), (1, 0, 2), (0, 1, 2) and \
             (1, 1, 2), (0, 1, 2), (1, 0, 2), the diagonal their edge b -> c in both; a ray \
             from (0.5, 0.5, 5) along -z, from the side the normals face, through the middle \
             of the diagonal: at least one must claim it: expected t = 3",
            [0, 1, 3],
            5.0,
        ),
        shared_diagonal_case(
            "triangle-shared-diagonal-bc-from-behind",
            "the same two triangles and the ray from (0.5, 0.5, 0) along +z, from behind: \
             expected t = 2",
            [0, 1, 3],
            0.0,
        ),
        shared_diagonal_case(
            "triangle-shared-diagonal-ca",
            "the same square as the triangles (0, 1, 2), (0, 0, 2), (1, 0, 2) and \
             (1, 0, 2), (1, 1, 2), (0, 1, 2), the diagonal their edge c -> a in both, and the ray \
             from (0.5, 0.5, 5) along -z: expected t = 3",
            [3, 0, 1],
            5.0,
        ),
        shared_diagonal_case(
            "triangle-shared-diagonal-ab",
            "the same square as the triangles (1, 0, 2), (0, 1, 2), (0, 0, 2) and \
             (0, 1, 2), (1, 0, 2), (1, 1, 2), the diagonal their edge a -> b in both, and the ray \
             from (0.5, 0.5, 5) along -z: expected t = 3",
            [1, 3, 0],
            5.0,
        ),
        lesson_triangle_case(
            "triangle-at-t-min",
            "the first case's ray with t_min = 2: the hit, at exactly t = 2, is not beyond \
             t_min: expected no hit (as for planes and spheres)",
            up,
            (2.0, INF),
            E::Miss,
        ),
        lesson_triangle_case(
            "triangle-at-t-max",
            "the first case's ray with t_max = 2: the hit, at exactly t = 2, is not before \
             t_max: expected no hit",
            up,
            (0.0, 2.0),
            E::Miss,
        ),
        barycentric_case(
            "barycentric-corner-b",
            "the lesson's triangle at its corner b = (1, 0, 2): all of the weight on b: \
             expected (0, 1, 0)",
            LESSON_TRIANGLE,
            LESSON_TRIANGLE[1],
        ),
        barycentric_case(
            "barycentric-corner-c",
            "the lesson's triangle at its corner c = (0, 1, 2): expected (0, 0, 1)",
            LESSON_TRIANGLE,
            LESSON_TRIANGLE[2],
        ),
        barycentric_case(
            "barycentric-centroid",
            "the lesson's triangle at its centroid (1/3, 1/3, 2), the mean of the corners: \
             expected (1/3, 1/3, 1/3)",
            LESSON_TRIANGLE,
            v(1.0 / 3.0, 1.0 / 3.0, 2.0),
        ),
        barycentric_case(
            "barycentric-skewed-triangle",
            "the triangle (0, 0, 0), (2, 0, 0), (1, 2, 0), whose edges are not perpendicular \
             (e1.e2 = 2), at (1, 1, 0) = 0.25 a + 0.25 b + 0.5 c: expected (0.25, 0.25, 0.5)",
            [Vec3::ZERO, v(2.0, 0.0, 0.0), v(1.0, 2.0, 0.0)],
            v(1.0, 1.0, 0.0),
        ),
        smooth_normal_case(
            "smooth-normal-at-corner",
            "the lesson's triangle with vertex normals (1, 0, 0), (0, 1, 0), (0, 0, 1), at \
             its corner b = (1, 0, 2): the weights are (0, 1, 0): expected b's normal (0, 1, 0)",
            LESSON_TRIANGLE[1],
        ),
        smooth_normal_case(
            "smooth-normal-centroid",
            "the same normals at the centroid (1/3, 1/3, 2): the blend is (1/3, 1/3, 1/3), of \
             length 0.577, made unit again: expected (0.57735, 0.57735, 0.57735)",
            v(1.0 / 3.0, 1.0 / 3.0, 2.0),
        ),
        smooth_normal_case(
            "smooth-normal-lesson-point",
            "the same normals at (0.25, 0.25, 2), weights (0.5, 0.25, 0.25): the blend \
             (0.5, 0.25, 0.25) has length sqrt(0.375) = 0.61237: expected \
             (0.8165, 0.40825, 0.40825)",
            v(0.25, 0.25, 2.0),
        ),
        terminator_case(
            "terminator-flat-unchanged",
            "the triangle (0, 0, 0), (1, 0, 0), (0, 1, 0) with every vertex normal (0, 0, 1), \
             at (0.25, 0.25, 0): the point is on every corner's tangent plane (height 0): \
             expected the point itself",
            [Vec3::Z; 3],
        ),
        terminator_case(
            "terminator-convex-lifted",
            "the same triangle and point with the normals of a bulge, (-0.6, 0, 0.8) at a and c, \
             (0.6, 0, 0.8) at b; weights (0.5, 0.25, 0.25). Heights above the corners' tangent \
             planes: a: (0.25, 0.25, 0).n_a = -0.15, b: (-0.75, 0.25, 0).n_b = -0.45, \
             c: (0.25, -0.75, 0).n_c = -0.15, all below: the point rises by \
             0.5 x 0.15 n_a + 0.25 x 0.45 n_b + 0.25 x 0.15 n_c = (0, 0, 0.18): expected \
             (0.25, 0.25, 0.18)",
            CONVEX_NORMALS,
        ),
        terminator_case(
            "terminator-concave-unchanged",
            "the same with the tilts reversed, a hollow: heights +0.15, +0.45, +0.15, the point \
             is above every tangent plane already: expected the point itself",
            CONCAVE_NORMALS,
        ),
        smooth_hit_case(
            "smooth-hit-convex",
            "the bulge of terminator-convex-lifted, opaque, hit by a ray from (0.25, 0.25, 5) \
             along -z at (0.25, 0.25, 0): expected the normal normalize(0.5 n_a + 0.25 n_b + \
             0.25 n_c) = (-0.3, 0, 0.8) / 0.8544 = (-0.35112, 0, 0.93633), and the point lifted \
             to (0.25, 0.25, 0.18)",
            5.0,
            false,
        ),
        smooth_hit_case(
            "smooth-hit-from-below",
            "the same bulge hit from below, by a ray from (0.25, 0.25, -5) along +z: the vertex \
             normals face away from the ray, so they are turned first; from that side the bulge \
             is a hollow: expected the normal (0.35112, 0, -0.93633) and the point unchanged, \
             (0.25, 0.25, 0)",
            -5.0,
            false,
        ),
        smooth_hit_case(
            "smooth-hit-transparent",
            "the bulge of smooth-hit-convex, fully transparent: the smooth normal \
             (-0.35112, 0, 0.93633), but the point stays on the triangle, (0.25, 0.25, 0): the \
             refracted ray must start below the surface, not above it",
            5.0,
            true,
        ),
        Case::new(
            "smooth-hit-steep-normals-b",
            TERMINATOR_10,
            "the lesson's floor triangle with the vertex normals (0.96, 0, 0.28), (0, 0, 1), \
             (0, 0.96, 0.28) (two of them 74 degrees from the face's, a coarse and strongly \
             curved mesh), transparent, hit at (0.25, 0.25, 0) by a ray from (0.25, 0.25, 5) \
             along -z: their sum (0.96, 0.96, 1.56) is on the ray's side, so they are kept; \
             blended with the weights (0.5, 0.25, 0.25): (0.48, 0.24, 0.46) / 0.70682 = \
             (0.67909, 0.33955, 0.6508) (the side is the sum's: with n_a - n_b + n_c, \
             z = -0.44, they would be turned)",
            CaseKind::SmoothHit {
                corners: FLOOR_TRIANGLE,
                normals: [v(0.96, 0.0, 0.28), Vec3::Z, v(0.0, 0.96, 0.28)],
                ray: Ray::new(v(0.25, 0.25, 5.0), -Vec3::Z),
                transparent: true,
            },
        ),
        Case::new(
            "smooth-hit-steep-normals-c",
            TERMINATOR_10,
            "the same with the vertex normals (0.96, 0, 0.28), (0, 0.96, 0.28), (0, 0, 1): the \
             same sum, kept, the same blend (0.67909, 0.33955, 0.6508) (with n_a + n_b - n_c, \
             z = -0.44, they would be turned)",
            CaseKind::SmoothHit {
                corners: FLOOR_TRIANGLE,
                normals: [v(0.96, 0.0, 0.28), v(0.0, 0.96, 0.28), Vec3::Z],
                ray: Ray::new(v(0.25, 0.25, 5.0), -Vec3::Z),
                transparent: true,
            },
        ),
    ]
}

/// Chapter 10's hard cases: rays through the shared edges and corners of
/// closed meshes (where Moller-Trumbore leaks), huge and tiny triangles,
/// degenerate triangles and non-finite input.
pub fn chapter_10_robustness() -> Vec<Case> {
    // Found by trying edge midpoints of tetrahedra with coordinates in
    // tenths around the origin: along these, Moller-Trumbore in f32 misses
    // every face, the watertight test does not.
    let leaky_edge = [
        v(1.8, 1.0, 0.4),
        v(0.0, -0.4, -0.8),
        v(-0.4, -1.4, 1.7),
        v(0.0, 1.4, 1.2),
    ];
    let leaky_vertex = [
        v(0.5, -1.2, 0.6),
        v(0.7, -0.6, -1.9),
        v(-0.2, 1.8, 0.0),
        v(-1.8, -0.6, -0.8),
    ];
    let far = Vec3::splat(1e5);
    let tiny = [v(0.0, 0.0, 1.0), v(1e-5, 0.0, 1.0), v(0.0, 1e-5, 1.0)];
    let up = (v(0.25, 0.25, 0.0), Vec3::Z);
    robust(vec![
        triangles_case(
            "triangle-closed-mesh-edge",
            WATERTIGHT_10,
            "a closed tetrahedron (1.8, 1, 0.4), (0, -0.4, -0.8), (-0.4, -1.4, 1.7), \
             (0, 1.4, 1.2) around the origin, and a ray from the origin along (0.9, 0.3, -0.2), \
             to the middle of the edge the first two corners share: from inside a closed mesh \
             every ray hits something: expected t = 1 (Moller-Trumbore in f32 lets this one \
             through both triangles of the edge)",
            tetrahedron(leaky_edge),
            (Vec3::ZERO, 0.5 * (leaky_edge[0] + leaky_edge[1])),
            ALL,
            E::Hit,
        ),
        triangles_case(
            "triangle-closed-mesh-vertex",
            WATERTIGHT_10,
            "a closed tetrahedron (0.5, -1.2, 0.6), (0.7, -0.6, -1.9), (-0.2, 1.8, 0), \
             (-1.8, -0.6, -0.8) around the origin, and a ray from the origin straight at its \
             first corner: one of the three faces there must claim it: expected t = 1",
            tetrahedron(leaky_vertex),
            (Vec3::ZERO, leaky_vertex[0]),
            ALL,
            E::Hit,
        ),
        triangles_case(
            "triangle-huge-coordinates-edge",
            WATERTIGHT_10,
            "the first tetrahedron moved by (1e5, 1e5, 1e5) (its corners rounded to f32, 1/128 \
             apart there, shared exactly), and the same ray from (1e5, 1e5, 1e5): still closed, \
             still hit, near t = 1",
            tetrahedron(leaky_edge.map(|corner| corner + far)),
            (far, 0.5 * (leaky_edge[0] + leaky_edge[1])),
            ALL,
            E::Hit,
        ),
        triangles_case(
            "triangle-far-and-huge",
            HIT_10,
            "the triangle (1e5, 0, 1e5), (0, 1e5, 1e5), (0, 0, 1e5) and a ray from the origin \
             along (0.25, 0.25, 1): expected t = 1e5",
            vec![[v(1e5, 0.0, 1e5), v(0.0, 1e5, 1e5), v(0.0, 0.0, 1e5)]],
            (Vec3::ZERO, v(0.25, 0.25, 1.0)),
            ALL,
            E::Hit,
        ),
        triangles_case(
            "triangle-tiny-hit",
            HIT_10,
            "a triangle of side 1e-5, (0, 0, 1), (1e-5, 0, 1), (0, 1e-5, 1), and a ray from \
             (2.5e-6, 2.5e-6, 0) along +z (its area is 5e-11: no absolute epsilon may swallow \
             it): expected t = 1",
            vec![tiny],
            (v(2.5e-6, 2.5e-6, 0.0), Vec3::Z),
            ALL,
            E::Hit,
        ),
        triangles_case(
            "triangle-tiny-miss",
            HIT_10,
            "the same tiny triangle and a ray from (7.5e-6, 7.5e-6, 0) along +z, past its long \
             edge: expected no hit",
            vec![tiny],
            (v(7.5e-6, 7.5e-6, 0.0), Vec3::Z),
            ALL,
            E::Miss,
        ),
        triangles_case(
            "triangle-degenerate-line",
            WATERTIGHT_10,
            "a zero-area triangle (0, 0, 2), (1, 0, 2), (2, 0, 2), its corners on a line, and a \
             ray from (0.5, 0, 0) along +z straight through that line: expected no hit (and no \
             NaN)",
            vec![[v(0.0, 0.0, 2.0), v(1.0, 0.0, 2.0), v(2.0, 0.0, 2.0)]],
            (v(0.5, 0.0, 0.0), Vec3::Z),
            ALL,
            E::Miss,
        ),
        triangles_case(
            "triangle-degenerate-point",
            WATERTIGHT_10,
            "a triangle whose three corners are the point (1, 1, 2), and a ray from (1, 1, 0) \
             along +z through it: expected no hit (and no NaN)",
            vec![[v(1.0, 1.0, 2.0); 3]],
            (v(1.0, 1.0, 0.0), Vec3::Z),
            ALL,
            E::Miss,
        ),
        lesson_triangle_case(
            "triangle-edge-on",
            "a ray from (-1, 0.25, 2) along +x, inside the lesson triangle's own plane: the \
             triangle is seen edge-on; either no hit or a hit on the triangle's plane",
            (v(-1.0, 0.25, 2.0), Vec3::X),
            ALL,
            E::Either,
        ),
        lesson_triangle_case(
            "triangle-nan-origin",
            "the first case with a NaN origin: expected no hit",
            (Vec3::NAN, Vec3::Z),
            ALL,
            E::Miss,
        ),
        lesson_triangle_case(
            "triangle-nan-direction",
            "the first case with a NaN direction: expected no hit",
            (v(0.25, 0.25, 0.0), Vec3::NAN),
            ALL,
            E::Miss,
        ),
        lesson_triangle_case(
            "triangle-zero-direction",
            "the first case with the direction (0, 0, 0), a ray that goes nowhere: expected no \
             hit",
            (v(0.25, 0.25, 0.0), Vec3::ZERO),
            ALL,
            E::Miss,
        ),
        lesson_triangle_case(
            "triangle-nan-t-max",
            "the first case with t_max = NaN: no t is below it: expected no hit",
            up,
            (0.0, f32::NAN),
            E::Miss,
        ),
    ])
}

#[cfg(test)]
mod chapter_10_tests {
    use super::*;

    #[test]
    fn every_expected_triangle_hit_has_an_exact_value() {
        for case in chapter_10().into_iter().chain(chapter_10_robustness()) {
            if let CaseKind::Triangles {
                expect: ExpectT::Hit(t),
                ..
            } = case.kind
            {
                assert!(t.is_finite(), "{}: the exact reference misses", case.name);
            }
        }
    }

    #[test]
    fn the_hand_computed_numbers_are_the_exact_ones() {
        let lifted = exact::terminator_point(
            FLOOR_TRIANGLE.map(wide),
            CONVEX_NORMALS.map(wide),
            wide(v(0.25, 0.25, 0.0)),
        );
        assert!((lifted - glam::DVec3::new(0.25, 0.25, 0.18)).length() < 1e-7);
        let weights = exact::barycentric(LESSON_TRIANGLE.map(wide), wide(v(0.25, 0.25, 2.0)));
        assert!((weights - glam::DVec3::new(0.5, 0.25, 0.25)).length() < 1e-12);
        let skewed = [Vec3::ZERO, v(2.0, 0.0, 0.0), v(1.0, 2.0, 0.0)].map(wide);
        let weights = exact::barycentric(skewed, glam::DVec3::new(1.0, 1.0, 0.0));
        assert!((weights - glam::DVec3::new(0.25, 0.25, 0.5)).length() < 1e-12);
    }
}
