//! Chapter 1's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 1`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const EQUATION_1: &str = "The equation";
const CODE_1: &str = "The code: `intersect_plane`";

/// Where the image differs when every checkpoint passes: what to look at
/// in the heatmap.
pub const IMAGE_HINT: &str = "near the horizon, where rays run almost parallel to the plane (the parallel test), or everywhere when a hit outside t_min < t < t_max is kept";

/// Chapter 1's checkpoints (level 1), in the order they run: the first
/// that fails is the one reported.
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn checkpoints() -> Vec<Case> {
    let floor = (Vec3::ZERO, Vec3::Y);
    vec![
        Case::from(PlaneQuestion {
            name: "plane-straight-down",
            section: EQUATION_1,
            says: "a ray from (0, 2, 0) straight down, along (0, -1, 0), meets the floor y = 0 at \
                   t = 2: t = dot(point - origin, n) / dot(dir, n) = (0 - 2) / -1",
            plane: floor,
            ray: (Vec3::new(0.0, 2.0, 0.0), -Vec3::Y),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(PlaneQuestion {
            name: "plane-parallel",
            section: EQUATION_1,
            says: "a ray from (0, 1, -5) along +z runs parallel to the floor y = 0 \
                   (dot(dir, n) = 0): expected no hit",
            plane: floor,
            ray: (Vec3::new(0.0, 1.0, -5.0), Vec3::Z),
            range: IN_FRONT,
            expect: Expect::Miss,
        })
        .fixed("a ray exactly parallel to the plane: a turn would make it parallel within rounding only, a hard case"),
        Case::from(PlaneQuestion {
            name: "plane-direction-not-unit",
            section: EQUATION_1,
            says: "a ray from (0, 3, 0) along (4, -3, 0) meets the floor y = 0 at the point \
                   (4, 0, 0), that is at t = 1: t counts lengths of the direction, not scene units",
            plane: floor,
            ray: (Vec3::new(0.0, 3.0, 0.0), Vec3::new(4.0, -3.0, 0.0)),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(PlaneQuestion {
            name: "plane-behind",
            section: EQUATION_1,
            says: "a ray from (0, 1, 0) going up, along (0, 1, 0), has the floor y = 0 behind it \
                   (t = -1): expected no hit",
            plane: floor,
            ray: (Vec3::new(0.0, 1.0, 0.0), Vec3::Y),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(PlaneQuestion {
            name: "plane-from-behind",
            section: EQUATION_1,
            says: "planes are two-sided: a ray from the origin along (0, 0, 0.5) meets the wall z \
                   = 5 (normal +z, facing the other way) at t = 10",
            plane: (Vec3::new(0.0, 0.0, 5.0), Vec3::Z),
            ray: (Vec3::ZERO, Vec3::new(0.0, 0.0, 0.5)),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(PlaneQuestion {
            name: "plane-beyond-t-max",
            section: EQUATION_1,
            says: "a ray from (0, 1, 0) straight down meets the floor at t = 1, beyond t_max = \
                   0.5: expected no hit",
            plane: floor,
            ray: (Vec3::new(0.0, 1.0, 0.0), -Vec3::Y),
            range: (0.0, 0.5),
            expect: Expect::Miss,
        }),
        Case::from(PlaneQuestion {
            name: "plane-at-t-max",
            section: EQUATION_1,
            says: "a ray from (0, 1, 0) straight down meets the floor at t = 1 exactly, and t must \
                   be strictly less than t_max = 1: expected no hit",
            plane: floor,
            ray: (Vec3::new(0.0, 1.0, 0.0), -Vec3::Y),
            range: (0.0, 1.0),
            expect: Expect::Miss,
        })
        .fixed("the hit exactly at t_max"),
        Case::from(PlaneQuestion {
            name: "plane-before-t-min",
            section: EQUATION_1,
            says: "a ray from (0, 1, 0) straight down meets the floor at t = 1, before t_min = 2 \
                   (the caller wants hits beyond 2 only): expected no hit",
            plane: floor,
            ray: (Vec3::new(0.0, 1.0, 0.0), -Vec3::Y),
            range: (2.0, INF),
            expect: Expect::Miss,
        }),
        Case::from(PlaneQuestion {
            name: "plane-behind-negative-t-min",
            section: EQUATION_1,
            says: "a ray from (0, 1, 0) going up has the floor y = 0 behind it at t = -1, and \
                   the caller asks for t_min = -10 < t: expected a hit at t = -1 (\"behind\" \
                   means below t_min, which is the caller's to choose, not below 0)",
            plane: floor,
            ray: (Vec3::new(0.0, 1.0, 0.0), Vec3::Y),
            range: (-10.0, INF),
            expect: Expect::Hit,
        }),
        Case::from(PlaneQuestion {
            name: "plane-close-ahead",
            section: EQUATION_1,
            says: "a ray from (0, 0.001, 0) straight down meets the floor at t = 0.001 > t_min = \
                   0: a hit however near (a distance of your own below which hits are dropped \
                   loses it; t_min is the caller's)",
            plane: floor,
            ray: (Vec3::new(0.0, 0.001, 0.0), -Vec3::Y),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(PlaneQuestion {
            name: "plane-origin-on-it",
            section: EQUATION_1,
            says: "a ray starting on the floor, from (0, 0, 0) along (0, -1, 0), meets it at t = \
                   0, and t must be strictly greater than t_min = 0: expected no hit",
            plane: floor,
            ray: (Vec3::ZERO, -Vec3::Y),
            range: IN_FRONT,
            expect: Expect::Miss,
        })
        .fixed("the origin exactly on the plane, t exactly t_min"),
        Case::from(PlaneQuestion {
            name: "plane-slanted",
            section: EQUATION_1,
            says: "a ray from the origin along (1, 1, 1) meets the plane through (1, 2, 3) with \
                   normal (1, 1, 1) at t = 6 / 3 = 2 (the normal's length does not matter)",
            plane: (Vec3::new(1.0, 2.0, 3.0), Vec3::ONE),
            ray: (Vec3::ZERO, Vec3::ONE),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
    ]
}

/// Chapter 1's hard cases (level 2).
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn robustness() -> Vec<Case> {
    let floor = (Vec3::ZERO, Vec3::Y);
    robust(vec![
        Case::from(PlaneQuestion {
            name: "plane-nearly-parallel",
            section: CODE_1,
            says: "nearly parallel, slope 1e-6, from (0, 1, 0): a genuine hit at t = 1e6",
            plane: floor,
            ray: (Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, -1e-6, 0.0)),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(PlaneQuestion {
            name: "plane-parallel-within-rounding",
            section: CODE_1,
            says: "slope 1e-8: parallel as far as f32 can tell; either answer, but a hit must lie \
                   on the plane",
            plane: floor,
            ray: (Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, -1e-8, 0.0)),
            range: IN_FRONT,
            expect: Expect::Either,
        }),
        // The stored normal's x and z are exactly twice its y, so the ray is
        // parallel to the plane as stored, not only on paper: only the
        // rounding of `3 * 0.6666667` makes the f32 dot product nonzero.
        Case::from(PlaneQuestion {
            name: "plane-parallel-denominator-rounded",
            section: CODE_1,
            says: "a ray from (0, 3, 0) along (3, -2, -2) runs parallel to the plane through the \
                   origin with normal (2, 1, 2), 1 away from it: dot(dir, n) = (6 - 2 - 4) / 3 = \
                   0. In f32 the unit normal is (0.6666667, 0.33333334, 0.6666667) and the dot \
                   product rounds to 2.0 - 0.6666667 - 1.3333334 = -1.2e-7, not 0; dividing -1 by \
                   it gives t = 8388608, a point still 1 away from the plane. That denominator is \
                   below the rounding bound 4 * f32::EPSILON * sum |dir_i| |n_i| = 4 * 1.19e-7 * \
                   4 = 1.9e-6: expected no hit, which a test `dot(dir, n) == 0` lets through",
            plane: (Vec3::ZERO, Vec3::new(2.0, 1.0, 2.0)),
            ray: (Vec3::new(0.0, 3.0, 0.0), Vec3::new(3.0, -2.0, -2.0)),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(PlaneQuestion {
            name: "plane-tiny-direction",
            section: CODE_1,
            says: "a direction of length 1e-20 straight down from (0, 1, 0): a hit at t = 1e20 \
                   (a fixed 'parallel' threshold such as 1e-6 on dot(dir, n) wrongly misses)",
            plane: floor,
            ray: (Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, -1e-20, 0.0)),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(PlaneQuestion {
            name: "plane-grazing-far",
            section: CODE_1,
            says: "grazing ray 1e4 along and 1 above the floor: hit at t = 1",
            plane: floor,
            ray: (Vec3::new(-1e4, 1.0, 0.0), Vec3::new(1e4, -1.0, 0.0)),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(PlaneQuestion {
            name: "plane-far-away",
            section: CODE_1,
            says: "a wall 1e6 away: t = 1e6",
            plane: (Vec3::new(0.0, 0.0, 1e6), -Vec3::Z),
            ray: (Vec3::ZERO, Vec3::Z),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(PlaneQuestion {
            name: "plane-large-coordinates",
            section: CODE_1,
            says: "slanted plane through (1e5, 1e5, 1e5) with normal (1, 2, 3), seen from close by",
            plane: (Vec3::new(1e5, 1e5, 1e5), Vec3::new(1.0, 2.0, 3.0)),
            ray: (
                Vec3::new(1e5 - 10.0, 1e5 + 3.0, 1e5 - 7.0),
                Vec3::new(0.3, 0.1, 0.9),
            ),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(PlaneQuestion {
            name: "plane-in-the-plane",
            section: CODE_1,
            says: "a ray lying in the floor (0 / 0): no hit",
            plane: floor,
            ray: (Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0)),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(PlaneQuestion {
            name: "plane-zero-normal",
            section: CODE_1,
            says: "a plane made with a zero normal (its fields are NaN): no hit",
            plane: (Vec3::ZERO, Vec3::ZERO),
            ray: (Vec3::new(0.0, 1.0, 0.0), -Vec3::Y),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(PlaneQuestion {
            name: "plane-nan-origin",
            section: CODE_1,
            says: "a NaN in the origin: no hit",
            plane: floor,
            ray: (Vec3::new(0.0, f32::NAN, 0.0), -Vec3::Y),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(PlaneQuestion {
            name: "plane-infinite-direction",
            section: CODE_1,
            says: "an infinite direction (inf / inf): no hit",
            plane: floor,
            ray: (Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, -INF, 0.0)),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(PlaneQuestion {
            name: "plane-infinite-origin",
            section: CODE_1,
            says: "an infinite origin: no hit",
            plane: floor,
            ray: (Vec3::new(0.0, INF, 0.0), -Vec3::Y),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_expected_hit_has_an_exact_value() {
        for case in checkpoints().into_iter().chain(robustness()) {
            if let CaseKind::Plane(PlaneCase {
                expect: ExpectT::Hit(t),
                ..
            }) = case.kind
            {
                assert!(t.is_finite(), "{}: the exact reference misses", case.name);
            }
        }
    }

    /// The numbers `plane-parallel-denominator-rounded` tells the student:
    /// parallel exactly for the normal as stored, yet a nonzero f32
    /// denominator and a "hit" 1 away from the plane.
    #[test]
    fn the_rounded_denominator_is_what_the_case_says() {
        let plane = Plane::new(Vec3::ZERO, Vec3::new(2.0, 1.0, 2.0));
        let (origin, dir) = (Vec3::new(0.0, 3.0, 0.0), Vec3::new(3.0, -2.0, -2.0));
        let n = plane.normal();
        assert_eq!(n.to_array(), [0.6666667, 0.33333334, 0.6666667]);
        assert_eq!(wide(dir).dot(wide(n)), 0.0, "parallel as stored");
        let denominator = dir.dot(n);
        assert_eq!(denominator, -(2.0_f32.powi(-23)));
        assert_eq!(dir.abs().dot(n.abs()), 4.0);
        let t = (plane.point() - origin).dot(n) / denominator;
        assert_eq!(t, 8388608.0);
        let off = (wide(origin) + f64::from(t) * wide(dir)).dot(wide(n));
        assert!((off - 1.0).abs() < 1e-6, "{off}");
        let bound = 4.0 * f32::EPSILON * 4.0;
        assert!(denominator.abs() < bound && (bound - 1.9e-6).abs() < 1e-8);
    }
}
