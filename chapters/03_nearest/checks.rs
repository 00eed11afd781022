//! Chapter 3's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 3`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

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

pub fn checkpoints() -> Vec<Case> {
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

pub fn robustness() -> Vec<Case> {
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
