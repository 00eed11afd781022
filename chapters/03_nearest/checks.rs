//! Chapter 3's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 3`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const NEAREST_3: &str = "The fix: `nearest_hit`";

/// A `nearest_hit` question: the ray from `ray.0` along `ray.1` through
/// `shapes`, hits wanted for `range.0 < t < range.1`; expected the nearest
/// hit's object index and exact `t`, or no hit.
struct NearestQuestion {
    name: &'static str,
    section: &'static str,
    says: &'static str,
    shapes: Vec<Shape>,
    /// `(origin, dir)`.
    ray: (Vec3, Vec3),
    /// `(t_min, t_max)`.
    range: (f32, f32),
    expect: Option<(usize, f64)>,
}

impl From<NearestQuestion> for Case {
    fn from(question: NearestQuestion) -> Case {
        let (origin, dir) = question.ray;
        let (t_min, t_max) = question.range;
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::Nearest(NearestCase {
                shapes: question.shapes,
                ray: Ray::new(origin, dir),
                t_min,
                t_max,
                expect: question.expect,
            }),
        )
    }
}

/// Where the image differs when every checkpoint passes: what to look at
/// in the heatmap.
pub const IMAGE_HINT: &str = "where objects overlap on screen: the nearest hit must win whatever the order of the list (compare each t with the closest so far)";

/// Chapter 3's checkpoints (level 1), in the order they run: the first
/// that fails is the one reported.
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn checkpoints() -> Vec<Case> {
    let three = || -> Vec<Shape> {
        vec![
            Plane::new(Vec3::new(0.0, 0.0, 10.0), Vec3::Z).into(),
            Sphere::new(Vec3::new(0.0, 0.0, 6.0), 1.0).into(),
            Sphere::new(Vec3::new(0.0, 0.0, 3.0), 1.0).into(),
        ]
    };
    let axis = (Vec3::ZERO, Vec3::Z);
    vec![
        Case::from(NearestQuestion {
            name: "nearest-of-three",
            section: NEAREST_3,
            says: "a wall z = 10 (object 0), a unit sphere at z = 6 (object 1) and one at z = 3 \
                   (object 2), listed far to near; a ray from the origin along +z: expected object \
                   2 at t = 2",
            shapes: three(),
            ray: axis,
            range: IN_FRONT,
            expect: Some((2, 2.0)),
        }),
        Case::from(NearestQuestion {
            name: "nearest-listed-first",
            section: NEAREST_3,
            says: "a unit sphere at z = 3 (object 0) before a wall z = 10 (object 1): expected \
                   object 0 at t = 2",
            shapes: vec![
                Sphere::new(Vec3::new(0.0, 0.0, 3.0), 1.0).into(),
                Plane::new(Vec3::new(0.0, 0.0, 10.0), Vec3::Z).into(),
            ],
            ray: axis,
            range: IN_FRONT,
            expect: Some((0, 2.0)),
        }),
        Case::from(NearestQuestion {
            name: "nearest-t-min",
            section: NEAREST_3,
            says: "the three objects with t_min = 4.5: the sphere at z = 3 ends at t = 4, so the \
                   next hit is object 1 at t = 5",
            shapes: three(),
            ray: axis,
            range: (4.5, INF),
            expect: Some((1, 5.0)),
        }),
        Case::from(NearestQuestion {
            name: "nearest-t-max",
            section: NEAREST_3,
            says: "the three objects with t_max = 1.5: nothing that close: expected no hit",
            shapes: three(),
            ray: axis,
            range: (0.0, 1.5),
            expect: None,
        }),
        Case::from(NearestQuestion {
            name: "nearest-empty",
            section: NEAREST_3,
            says: "an empty list of objects: expected no hit",
            shapes: Vec::new(),
            ray: axis,
            range: IN_FRONT,
            expect: None,
        }),
        Case::from(NearestQuestion {
            name: "nearest-all-behind",
            section: NEAREST_3,
            says: "the three objects, ray along -z: all behind: expected no hit",
            shapes: three(),
            ray: (Vec3::ZERO, -Vec3::Z),
            range: IN_FRONT,
            expect: None,
        }),
        Case::from(NearestQuestion {
            name: "nearest-tie-first-listed",
            section: NEAREST_3,
            says: "a unit sphere at z = 3 (object 0) and the wall z = 2 (object 1) that touches it \
                   at (0, 0, 2): a ray from the origin along +z meets both at t = 2 exactly, and \
                   on a tie the first listed wins: expected object 0 at t = 2",
            shapes: vec![
                Sphere::new(Vec3::new(0.0, 0.0, 3.0), 1.0).into(),
                Plane::new(Vec3::new(0.0, 0.0, 2.0), Vec3::Z).into(),
            ],
            ray: axis,
            range: IN_FRONT,
            expect: Some((0, 2.0)),
        })
        .fixed("two hits at exactly the same t"),
    ]
}

/// Chapter 3's hard cases (level 2).
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn robustness() -> Vec<Case> {
    // 100 spheres of radius 0.25 along +z, listed far to near.
    let row: Vec<Shape> = (1..=100)
        .rev()
        .map(|z| Sphere::new(Vec3::new(0.0, 0.0, z as f32), 0.25).into())
        .collect();
    robust(vec![
        Case::from(NearestQuestion {
            name: "nearest-hundred-reversed",
            section: NEAREST_3,
            says: "100 spheres of radius 0.25 at z = 100, 99, ..., 1 (that order): expected the \
                   last listed, object 99, at t = 0.75",
            shapes: row,
            ray: (Vec3::ZERO, Vec3::Z),
            range: IN_FRONT,
            expect: Some((99, 0.75)),
        }),
        Case::from(NearestQuestion {
            name: "nearest-nested",
            section: NEAREST_3,
            says: "a sphere of radius 2 at (0, 0, 5) around one of radius 1 at (0, 0, 5.5), inner \
                   listed first: from the origin the outer is met first, object 1 at t = 3",
            shapes: vec![
                Sphere::new(Vec3::new(0.0, 0.0, 5.5), 1.0).into(),
                Sphere::new(Vec3::new(0.0, 0.0, 5.0), 2.0).into(),
            ],
            ray: (Vec3::ZERO, Vec3::Z),
            range: IN_FRONT,
            expect: Some((1, 3.0)),
        }),
        Case::from(NearestQuestion {
            name: "nearest-nan-t-max",
            section: NEAREST_3,
            says: "t_max = NaN: expected no hit",
            shapes: vec![Sphere::new(Vec3::new(0.0, 0.0, 3.0), 1.0).into()],
            ray: (Vec3::ZERO, Vec3::Z),
            range: (0.0, f32::NAN),
            expect: None,
        }),
    ])
}
