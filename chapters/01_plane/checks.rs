//! Chapter 1's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 1`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const EQUATION_1: &str = "The equation";
const CODE_1: &str = "The code: `intersect_plane`";

pub fn checkpoints() -> Vec<Case> {
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

pub fn robustness() -> Vec<Case> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_expected_hit_has_an_exact_value() {
        for case in checkpoints().into_iter().chain(robustness()) {
            if let CaseKind::Plane {
                expect: ExpectT::Hit(t),
                ..
            } = case.kind
            {
                assert!(t.is_finite(), "{}: the exact reference misses", case.name);
            }
        }
    }
}
