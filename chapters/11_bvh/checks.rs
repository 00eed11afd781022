//! Chapter 11's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 11`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const SLAB_11: &str = "The slab test";
const NAN_11: &str = "Why NaN cannot sneak in";
const ROUNDING_11: &str = "Rounding: widening the interval";
const BUILD_11: &str = "Building the tree";
const SAH_11: &str = "Where to cut: the surface-area heuristic";
const WALK_11: &str = "Walking the tree: the nearest hit";
const ANY_11: &str = "Any hit, for shadows";
const PLANES_11: &str = "Why planes stay out";
const BOXES4_11: &str = "Four boxes at once";
const TRIANGLES4_11: &str = "Four triangles at once";
const COLLAPSE_11: &str = "Folding the binary tree";
const WIDE_WALK_11: &str = "Walking the wide tree";

/// The box of every `hit_box` checkpoint: the cube from -1 to 1.
const CUBE: (Vec3, Vec3) = (Vec3::splat(-1.0), Vec3::splat(1.0));

/// A `hit_box` question: the box from `bounds.0` to `bounds.1`, the ray
/// from `ray.0` along `ray.1`, `range.0 < t < range.1`; expected the entry
/// `t`, or a miss.
struct BoxQuestion {
    name: &'static str,
    section: &'static str,
    says: &'static str,
    /// `(min, max)`.
    bounds: (Vec3, Vec3),
    /// `(origin, dir)`.
    ray: (Vec3, Vec3),
    /// `(t_min, t_max)`.
    range: (f32, f32),
    expect: Option<f64>,
}

impl From<BoxQuestion> for Case {
    fn from(question: BoxQuestion) -> Case {
        let (min, max) = question.bounds;
        let (origin, dir) = question.ray;
        let (t_min, t_max) = question.range;
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::HitBox(HitBoxCase {
                min,
                max,
                origin,
                dir,
                t_min,
                t_max,
                expect: question.expect,
            }),
        )
    }
}

/// A `nearest_hit_bvh` question over a tree of `shapes` (or `any_hit_bvh`,
/// when `any_hit`), for each of `rays`, `range.0 < t < range.1`.
struct BvhHitsQuestion {
    name: &'static str,
    section: &'static str,
    says: &'static str,
    shapes: Vec<Shape>,
    options: BvhOptions,
    rays: Vec<Ray>,
    /// `(t_min, t_max)`.
    range: (f32, f32),
    any_hit: bool,
    /// Through the wide tree (`collapse_bvh`, then `nearest_hit_wide` or
    /// `any_hit_wide`).
    wide: bool,
}

impl From<BvhHitsQuestion> for Case {
    fn from(question: BvhHitsQuestion) -> Case {
        let (t_min, t_max) = question.range;
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::BvhHits(BvhHitsCase {
                shapes: question.shapes,
                options: question.options,
                rays: question.rays,
                t_min,
                t_max,
                any: question.any_hit,
                wide: question.wide,
                steps: false,
            }),
        )
    }
}

/// The question's case, judging also the walk's steps as the lesson gives
/// them, seen through the objects it asks: planes first, a box entered
/// beyond the best hit so far skipped, each object asked up to and
/// including the best hit so far, and for any hit, nothing asked after
/// the first.
fn steps_judged(question: BvhHitsQuestion) -> Case {
    let mut case = Case::from(question);
    if let CaseKind::BvhHits(walk) = &mut case.kind {
        walk.steps = true;
    }
    case
}

/// A `hit_boxes` question: four boxes (`(min, max)`, lane by lane), the
/// ray from `ray.0` along `ray.1`, `range.0 < t < range.1`; expected each
/// lane's entry `t`, or a miss.
struct BoxesQuestion {
    name: &'static str,
    section: &'static str,
    says: &'static str,
    boxes: [(Vec3, Vec3); 4],
    /// `(origin, dir)`.
    ray: (Vec3, Vec3),
    /// `(t_min, t_max)`.
    range: (f32, f32),
    expect: [Option<f64>; 4],
}

impl From<BoxesQuestion> for Case {
    fn from(question: BoxesQuestion) -> Case {
        let (origin, dir) = question.ray;
        let (t_min, t_max) = question.range;
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::HitBoxes(HitBoxesCase {
                boxes: question.boxes,
                origin,
                dir,
                t_min,
                t_max,
                expect: question.expect,
            }),
        )
    }
}

/// The box from `min` to `max`.
fn cuboid(min: [f32; 3], max: [f32; 3]) -> (Vec3, Vec3) {
    (Vec3::from(min), Vec3::from(max))
}

/// No box at all in a lane: `min` above `max` everywhere.
const EMPTY_LANE: (Vec3, Vec3) = (Vec3::INFINITY, Vec3::NEG_INFINITY);

/// A triangle's corners.
fn corners(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> [Vec3; 3] {
    [Vec3::from(a), Vec3::from(b), Vec3::from(c)]
}

/// A lane that holds no triangle: NaN corners, which no ray hits.
const NO_TRIANGLE: [Vec3; 3] = [Vec3::NAN; 3];

fn triangle(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Shape {
    let [a, b, c] = corners(a, b, c);
    Triangle::new(a, b, c).into()
}

fn sphere(center: Vec3, radius: f32) -> Shape {
    Sphere::new(center, radius).into()
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

/// Where the image differs when every checkpoint passes: what to look at
/// in the heatmap.
pub const IMAGE_HINT: &str = "where the tree answers differently from chapter 3's loop: the slab test's range, both children visited when their boxes overlap, and the nearest hit kept from leaf to leaf";

/// Chapter 11's checkpoint cases.
///
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn checkpoints() -> Vec<Case> {
    // Behind each other on the z axis, the first-hit one not the first-entered.
    let behind = || {
        vec![
            sphere(Vec3::new(0.0, 4.0, 10.0), 5.0),
            sphere(Vec3::new(0.0, 0.0, 7.0), 1.0),
            sphere(Vec3::new(0.0, 0.0, 20.0), 1.0),
        ]
    };
    let plane_between = || {
        vec![
            sphere(Vec3::new(0.0, 0.0, 10.0), 1.0),
            Plane::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z).into(),
            sphere(Vec3::new(0.0, 0.0, 3.0), 1.0),
        ]
    };
    let blockers = || {
        vec![
            sphere(Vec3::new(3.0, 0.0, 5.0), 1.0),
            sphere(Vec3::new(0.0, 0.0, 5.0), 1.0),
            sphere(Vec3::new(-3.0, 0.0, 5.0), 1.0),
        ]
    };
    let from_origin = |dir: Vec3| Ray::new(Vec3::ZERO, dir);
    // Unit spheres one behind the other on the z axis.
    let in_a_row = || {
        vec![
            sphere(Vec3::new(0.0, 0.0, 5.0), 1.0),
            sphere(Vec3::new(0.0, 0.0, 10.0), 1.0),
            sphere(Vec3::new(0.0, 0.0, 15.0), 1.0),
        ]
    };
    // The plane z = 3 in front of two of them, listed last.
    let plane_in_front = || {
        vec![
            sphere(Vec3::new(0.0, 0.0, 5.0), 1.0),
            sphere(Vec3::new(0.0, 0.0, 10.0), 1.0),
            Plane::new(Vec3::new(0.0, 0.0, 3.0), -Vec3::Z).into(),
        ]
    };
    // Two blockers on the z axis, three spheres beside it and a plane
    // parallel to it.
    let shadow_row = || {
        vec![
            sphere(Vec3::new(0.0, 0.0, 15.0), 1.0),
            sphere(Vec3::new(3.0, 0.0, 5.0), 1.0),
            sphere(Vec3::new(0.0, 0.0, 10.0), 1.0),
            sphere(Vec3::new(-3.0, 0.0, 5.0), 1.0),
            sphere(Vec3::new(0.0, 3.0, 5.0), 1.0),
            Plane::new(Vec3::new(5.0, 0.0, 0.0), Vec3::X).into(),
        ]
    };
    vec![
        Case::from(BoxQuestion {
            name: "box-from-outside",
            section: SLAB_11,
            says: "the box from (-1, -1, -1) to (1, 1, 1); a ray from (-5, -2.5, 0) along \
                   (2, 1, 0): inside the x slab for t from 2 to 3, the y slab from 1.5 to 3.5, the \
                   z slab always (dir.z = 0, origin inside it); inside all three from t = 2 to 3: \
                   expected 2",
            bounds: CUBE,
            ray: (Vec3::new(-5.0, -2.5, 0.0), Vec3::new(2.0, 1.0, 0.0)),
            range: IN_FRONT,
            expect: Some(2.0),
        }),
        Case::from(BoxQuestion {
            name: "box-negative-direction",
            section: SLAB_11,
            says: "the same box; a ray from (5, 0, 0) along (-1, 0, 0) meets the plane x = 1 \
                   (max.x) first, at t = 4, and x = -1 at t = 6: expected 4",
            bounds: CUBE,
            ray: (Vec3::new(5.0, 0.0, 0.0), -Vec3::X),
            range: IN_FRONT,
            expect: Some(4.0),
        }),
        Case::from(BoxQuestion {
            name: "box-from-inside",
            section: SLAB_11,
            says: "the same box; a ray from its centre along (0.3, -0.2, 1) with t_min = 0.5: it \
                   starts inside, so it is in the box from t_min on: expected 0.5",
            bounds: CUBE,
            ray: (Vec3::ZERO, Vec3::new(0.3, -0.2, 1.0)),
            range: (0.5, 10.0),
            expect: Some(0.5),
        }),
        Case::from(BoxQuestion {
            name: "box-behind",
            section: SLAB_11,
            says: "the same box; a ray from (-5, 0, 0) along (-1, 0, 0): the box is behind it \
                   (t from -6 to -4): expected None",
            bounds: CUBE,
            ray: (Vec3::new(-5.0, 0.0, 0.0), -Vec3::X),
            range: IN_FRONT,
            expect: None,
        }),
        Case::from(BoxQuestion {
            name: "box-beyond-t-max",
            section: SLAB_11,
            says: "the same box; a ray from (-5, 0, 0) along (1, 0, 0) with t_max = 3.9: the box \
                   starts at t = 4, too far: expected None",
            bounds: CUBE,
            ray: (Vec3::new(-5.0, 0.0, 0.0), Vec3::X),
            range: (0.0, 3.9),
            expect: None,
        }),
        Case::from(BoxQuestion {
            name: "box-missed",
            section: SLAB_11,
            says: "the same box; a ray from (-5, 0, 0) along (1, 1, 0): inside the x slab for t \
                   from 4 to 6, the y slab from -1 to 1, never both: expected None",
            bounds: CUBE,
            ray: (Vec3::new(-5.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0)),
            range: IN_FRONT,
            expect: None,
        }),
        Case::from(BoxQuestion {
            name: "box-parallel-inside-slab",
            section: NAN_11,
            says: "the same box; a ray from (0, 0.5, -5) along (0, 0, 1): dir.y = 0, so 1 / dir.y \
                   = inf and the y slab gives (-1 - 0.5) x inf = -inf to (1 - 0.5) x inf = inf, \
                   always inside; the z slab from 4 to 6: expected 4",
            bounds: CUBE,
            ray: (Vec3::new(0.0, 0.5, -5.0), Vec3::Z),
            range: IN_FRONT,
            expect: Some(4.0),
        }),
        Case::from(BoxQuestion {
            name: "box-parallel-outside-slab",
            section: NAN_11,
            says: "the same box; a ray from (0, 2, -5) along (0, 0, 1): the y slab gives (-1 - 2) \
                   x inf = -inf to (1 - 2) x inf = -inf, never inside: expected None",
            bounds: CUBE,
            ray: (Vec3::new(0.0, 2.0, -5.0), Vec3::Z),
            range: IN_FRONT,
            expect: None,
        }),
        Case::from(BoxQuestion {
            name: "box-zero-direction-on-slab-plane",
            section: NAN_11,
            says: "the same box; a ray from (0, 1, -5) along (0, 0, 1): dir.y = 0 and the origin \
                   lies on the plane y = 1 (max.y), so that plane's crossing is (1 - 1) x inf = 0 \
                   x inf = NaN. The ray runs along the box's top face, on its closed boundary: the \
                   y axis must not constrain it. The z slab from 4 to 6: expected 4",
            bounds: CUBE,
            ray: (Vec3::new(0.0, 1.0, -5.0), Vec3::Z),
            range: IN_FRONT,
            expect: Some(4.0),
        }),
        Case::from(BoxQuestion {
            name: "box-negative-zero-on-min-plane",
            section: NAN_11,
            says: "the same box; a ray from (0, -1, -5) along (0, -0, 1): 1 / -0 = -inf, and the \
                   origin is on the plane y = -1 (min.y): (-1 - -1) x -inf = NaN again, on the \
                   bottom face: expected 4",
            bounds: CUBE,
            ray: (Vec3::new(0.0, -1.0, -5.0), Vec3::new(0.0, -0.0, 1.0)),
            range: IN_FRONT,
            expect: Some(4.0),
        })
        .fixed("a direction of exactly -0 on the box's plane"),
        Case::from(BoxQuestion {
            name: "box-flat-touched-at-t-min",
            section: SLAB_11,
            says: "a flat box, from (-1, -1, 0) to (1, 1, 0) (a triangle's box in the plane z = 0); \
                   a ray from the origin along +z: entry and exit are both t = 0, and the interval \
                   t_min <= t <= t_max is closed: expected 0",
            bounds: (Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)),
            ray: (Vec3::ZERO, Vec3::Z),
            range: IN_FRONT,
            expect: Some(0.0),
        })
        .fixed("a box touched exactly at t = t_min"),
        Case::new(
            "bvh-build-holds-every-sphere",
            BUILD_11,
            "five unit spheres at x = 0, 3, 6, 9, 12 (listed out of order), one per leaf: every \
             sphere exactly once in a leaf whose box holds the sphere's box (x - 1 to x + 1), \
             every inner node's box holding its two children's, nothing in unbounded",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    sphere(Vec3::new(6.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(0.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(12.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(3.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(9.0, 0.0, 0.0), 1.0),
                ],
                options: ONE_PER_LEAF,
                expect: TreeShape::Any,
            }),
        ),
        Case::from(BvhHitsQuestion {
            name: "bvh-nearest-behind-a-nearer-box",
            section: WALK_11,
            says: "a ray from the origin along +z; object 0, centre (0, 4, 10) radius 5: its box \
                   starts at z = 5, and the ray passes 4 from its centre, so it is hit at z = 10 - \
                   sqrt(25 - 16) = 7; object 1, centre (0, 0, 7) radius 1: box from z = 6, hit at \
                   6; object 2 at (0, 0, 20), radius 1. Object 0's box is entered first but object \
                   1 is hit nearer: expected object 1 at t = 6 \
                   (a walk that stops at the first leaf with a hit says object 0 at t = 7)",
            shapes: behind(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-nearest-in-a-leaf-of-three",
            section: WALK_11,
            says: "unit spheres at (0, 0, 10) (object 0), (0, 0, 5) (object 1) and (3, 0, 5) \
                   (object 2), the default options (a leaf holds up to four objects: these three \
                   make one); a ray from the origin along +z meets object 0 at t = 9 and object 1 \
                   at t = 4: expected object 1 at t = 4 \
                   (a leaf that ends at its first hit says object 0 at t = 9)",
            shapes: vec![
                sphere(Vec3::new(0.0, 0.0, 10.0), 1.0),
                sphere(Vec3::new(0.0, 0.0, 5.0), 1.0),
                sphere(Vec3::new(3.0, 0.0, 5.0), 1.0),
            ],
            options: BvhOptions::default(),
            rays: vec![from_origin(Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        steps_judged(BvhHitsQuestion {
            name: "bvh-nearest-skips-boxes-beyond-the-best",
            section: WALK_11,
            says: "unit spheres on the z axis at z = 5, 10 and 15 (objects 0 to 2), one per leaf; a \
                   ray from the origin along +z hits object 0 at t = 4, and the boxes of objects 1 \
                   and 2 start at z = 9 and 14, beyond that hit. A box entered beyond the best hit \
                   so far is skipped, with everything in it: expected object 0 at t = 4, and \
                   objects 1 and 2 never asked",
            shapes: in_a_row(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        steps_judged(BvhHitsQuestion {
            name: "bvh-nearest-asks-up-to-the-best",
            section: WALK_11,
            says: "the spheres of bvh-nearest-behind-a-nearer-box: object 0's box is entered at \
                   t = 5 and it is hit at 7, object 1's at 6 and hit at 6, object 2's at 19. Both \
                   boxes are entered before either hit, so both objects are asked, the second one \
                   for hits up to and including the first one's t (7, or 6), not to infinity; \
                   object 2's box is skipped: expected object 1 at t = 6",
            shapes: behind(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        Case::new(
            "bvh-plane-stays-out",
            PLANES_11,
            "a unit sphere at (0, 0, 10) (object 0), the plane z = 5 \
             (object 1, no box: Shape::bounds is None) and a unit sphere at (0, 0, 3) (object 2): \
             expected unbounded = [1], and objects 0 and 2 in the tree",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: plane_between(),
                options: ONE_PER_LEAF,
                expect: TreeShape::Any,
            }),
        ),
        Case::new(
            "bvh-build-mixed-shapes",
            BUILD_11,
            "the triangle (0, 0, 5), (2, 0, 5), (0, 2, 5) (object 0), a unit sphere at (0, 0, 10) \
             (object 1), the plane z = 0 (object 2) and the triangle (4, 0, 0), (4, 2, 0), \
             (4, 0, 2) (object 3), one per leaf: the triangles' boxes are flat (z from 5 to 5, x \
             from 4 to 4), finite and not empty, so they go in the tree like the sphere's: \
             expected unbounded = [2] and objects 0, 1 and 3 each in a leaf whose box holds its \
             box grown by 4 epsilons",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    triangle([0.0, 0.0, 5.0], [2.0, 0.0, 5.0], [0.0, 2.0, 5.0]),
                    sphere(Vec3::new(0.0, 0.0, 10.0), 1.0),
                    Plane::new(Vec3::ZERO, Vec3::Z).into(),
                    triangle([4.0, 0.0, 0.0], [4.0, 2.0, 0.0], [4.0, 0.0, 2.0]),
                ],
                options: ONE_PER_LEAF,
                expect: TreeShape::Any,
            }),
        ),
        Case::from(BvhHitsQuestion {
            name: "bvh-plane-still-hit",
            section: PLANES_11,
            says: "the same three objects; a ray from the origin along +z hits object 2 at t = 2 \
                   first; one along (0.6, 0, 0.8) passes 1.8 from the sphere at z = 3 and 6 from \
                   the one at z = 10, and meets only the plane, at t = 5 / 0.8 = 6.25: expected \
                   object 2 at t = 2, then object 1 at t = 6.25",
            shapes: plane_between(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z), from_origin(Vec3::new(0.6, 0.0, 0.8))],
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        steps_judged(BvhHitsQuestion {
            name: "bvh-planes-first-their-hit-shortens-the-walk",
            section: PLANES_11,
            says: "unit spheres at z = 5 and 10 (objects 0 and 1) and the plane z = 3 (object 2, \
                   outside the tree); a ray from the origin along +z. The plane is asked first, by \
                   the loop before the tree, and hit at t = 3; every box of the tree is entered \
                   beyond it (the nearest at z = 4): expected object 2 at t = 3, and neither \
                   sphere asked",
            shapes: plane_in_front(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-any-hit-finds-the-blocker",
            section: ANY_11,
            says: "unit spheres at (3, 0, 5), (0, 0, 5) and (-3, 0, 5); a shadow ray from the \
                   origin along +z with t_max = 10 is blocked by object 1 at t = 4: expected a \
                   hit; one along +y meets nothing: expected none",
            shapes: blockers(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z), from_origin(Vec3::Y)],
            range: (0.0, 10.0),
            any_hit: true,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-nearest-tie-goes-to-the-first-listed",
            section: WALK_11,
            says: "a unit sphere at (0, 0, 5) (object 0) and the plane z = 4 (object 1); a ray \
                   from the origin along +z meets both at exactly t = 4 (5 - 1, and 4 / 1). \
                   Chapter 3 keeps the first listed of equal hits: expected object 0 at t = 4, \
                   although the plane, outside the tree, is asked first",
            shapes: vec![
                sphere(Vec3::new(0.0, 0.0, 5.0), 1.0),
                Plane::new(Vec3::new(0.0, 0.0, 4.0), -Vec3::Z).into(),
            ],
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-any-hit-beyond-the-light",
            section: ANY_11,
            says: "the same spheres; the ray along +z with t_max = 3.5 \
                   (a light between the origin and the spheres): the blocker at t = 4 is beyond \
                   it: expected no hit",
            shapes: blockers(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: (0.0, 3.5),
            any_hit: true,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-any-hit-only-planes",
            section: ANY_11,
            says: "the planes z = 8 and z = 3 and nothing with a box, so the tree has no nodes at \
                   all; a shadow ray from the origin along +z with t_max = 10 is blocked by the \
                   plane z = 3 at t = 3: expected a hit; one along +x runs parallel to both and \
                   must get past an empty tree without asking for its root: expected none",
            shapes: vec![
                Plane::new(Vec3::new(0.0, 0.0, 8.0), -Vec3::Z).into(),
                Plane::new(Vec3::new(0.0, 0.0, 3.0), -Vec3::Z).into(),
            ],
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z), from_origin(Vec3::X)],
            range: (0.0, 10.0),
            any_hit: true,
            wide: false,
        }),
        steps_judged(BvhHitsQuestion {
            name: "bvh-any-hit-stops-at-its-first-hit",
            section: ANY_11,
            says: "unit spheres on the z axis at z = 15 and 10 (objects 0 and 2) and beside it at \
                   (3, 0, 5), (-3, 0, 5) and (0, 3, 5) (objects 1, 3 and 4, whose boxes the ray \
                   misses), and the plane x = 5 (object 5, outside the tree, parallel to the ray); \
                   a shadow ray from the origin along +z with t_max = 20. The plane is asked first \
                   (no hit), then the boxes the ray enters, and the first blocker ends the walk: \
                   expected a hit, nothing asked after it, and objects 1, 3 and 4 never asked",
            shapes: shadow_row(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: (0.0, 20.0),
            any_hit: true,
            wide: false,
        }),
        // The build's own rules, which the walks above cannot see (any
        // valid tree gives their answers). Which child is left is the
        // student's choice: a cut is compared as a partition.
        Case::new(
            "bvh-max-leaf-objects-stay-a-leaf",
            BUILD_11,
            "two spheres of radius 1/128 at x = 0 and x = 1/32, max_leaf 2 (cut at the middle): a \
             node of max_leaf objects or fewer stays a leaf: expected the root a leaf holding \
             both, its box their boxes' union \
             (x from -1/128 to 5/128, y and z from -1/128 to 1/128) grown by BOX_PADDING_EPSILONS \
             (4) epsilons of its largest coordinate, 5/128: about 2e-8",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    sphere(Vec3::new(0.0, 0.0, 0.0), 1.0 / 128.0),
                    sphere(Vec3::new(1.0 / 32.0, 0.0, 0.0), 1.0 / 128.0),
                ],
                options: MIDDLE_TWO_PER_LEAF,
                expect: TreeShape::RootLeaf,
            }),
        ),
        Case::new(
            "bvh-one-more-than-max-leaf-is-cut",
            BUILD_11,
            "unit spheres at x = 0, 2 and 6, max_leaf 2, cut at the middle: three objects are one \
             more than max_leaf, so the root is cut; the centroids (the centres) spread along x \
             from 0 to 6, the middle is 3: expected the root cut into objects [0, 1] (x = 0, 2) \
             and [2] (x = 6)",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    sphere(Vec3::new(0.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(2.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(6.0, 0.0, 0.0), 1.0),
                ],
                options: MIDDLE_TWO_PER_LEAF,
                expect: TreeShape::RootCut(vec![vec![0, 1]]),
            }),
        ),
        Case::new(
            "bvh-middle-of-the-centroids",
            BUILD_11,
            "spheres at x = 3, 4, 5, 6 with radii 1, 3, 3, 1, one per leaf, cut at the middle: the \
             centroids are the centres (the middle of each box), spread 3 along x and 0 along y \
             and z; the middle of that spread is 4.5: expected the root cut into objects [0, 1] \
             and [2, 3]",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    sphere(Vec3::new(3.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(4.0, 0.0, 0.0), 3.0),
                    sphere(Vec3::new(5.0, 0.0, 0.0), 3.0),
                    sphere(Vec3::new(6.0, 0.0, 0.0), 1.0),
                ],
                options: ONE_PER_LEAF,
                expect: TreeShape::RootCut(vec![vec![0, 1]]),
            }),
        ),
        Case::new(
            "bvh-middle-not-the-mean",
            BUILD_11,
            "unit spheres at x = 0, 1, 5 and 12 (objects 0 to 3), one per leaf, cut at the middle: \
             the centroids spread from 0 to 12, whose middle is 6: expected the root cut into \
             objects [0, 1, 2] and [3] \
             (their mean, 4.5, or their median would cut [0, 1] from [2, 3])",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    sphere(Vec3::new(0.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(1.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(5.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(12.0, 0.0, 0.0), 1.0),
                ],
                options: ONE_PER_LEAF,
                expect: TreeShape::RootCut(vec![vec![0, 1, 2]]),
            }),
        ),
        Case::new(
            "bvh-sah-cut-not-the-middle",
            SAH_11,
            "unit spheres at x = 100, 101, 105, 106, 111 (objects 0 to 4), the surface-area \
             heuristic with 16 bins, TRAVERSAL_COST 1, max_leaf 1. Each box is 2 by 2 in y and z \
             and L long in x: half its area is 2 L + 2 L + 4 = 4 L + 4. The root's is 56 (L = 13), \
             so the leaf costs 56 x 5 = 280; multiplied through by 56, a cut costs 56 + \
             (half area x count) of each side: [0] | [1, 2, 3, 4]: 56 + 12 x 1 + 52 x 4 = 276; \
             [0, 1] | [2, 3, 4]: 56 + 16 x 2 + 36 x 3 = 196; [0, 1, 2] | [3, 4]: 56 + 32 x 3 + 32 \
             x 2 = 216; [0, 1, 2, 3] | [4]: 56 + 36 x 4 + 12 x 1 = 212. Expected the root cut into \
             objects [0, 1] and [2, 3, 4]; or, from a build that always cuts at the middle \
             (the split rule is the student's choice), [0, 1, 2] and [3, 4] \
             (the middle of the centroids is 105.5). Not a leaf, and not [0] alone",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    sphere(Vec3::new(100.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(101.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(105.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(106.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(111.0, 0.0, 0.0), 1.0),
                ],
                options: SAH_ONE_PER_LEAF,
                expect: TreeShape::RootCut(vec![vec![0, 1], vec![0, 1, 2]]),
            }),
        ),
        // The example above has boxes of one height and depth, so any half
        // area of the form a L + b with a, b > 0 ranks some cuts alike; these
        // have boxes of several sizes, each of whose sides counts.
        Case::new(
            "bvh-sah-the-big-box-alone",
            SAH_11,
            "spheres on the x axis at x = 4, 7.5, 10 and 10.5, radii 2, 1, 2 and 4 \
             (objects 0 to 3), the SAH, 16 bins, max_leaf 1. A sphere's box is a cube of side 2 r, \
             half area 3 (2 r)^2: 48, 12, 48, 192. The root, from (2, -4, -4) to (14.5, 4, 4), has \
             12.5 x 8 + 8 x 8 + 8 x 12.5 = 264 (the leaf: 264 x 4 = 1056). Object 3's box holds \
             every box right of any cut, so each cut costs 264 + (left half area) x (left count) + \
             192 x (right count): [0] | [1, 2, 3]: 264 + 48 + 576 = 888; [0, 1] | [2, 3]: left 6.5 \
             by 4 by 4, 68: 264 + 136 + 384 = 784; [0, 1, 2] | [3]: left 10 by 4 by 4, 96: 264 + \
             288 + 192 = 744. Expected the root cut into [0, 1, 2] and [3] \
             (or, cut at the middle of the centroids, 7.25: [0] and [1, 2, 3])",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    sphere(Vec3::new(4.0, 0.0, 0.0), 2.0),
                    sphere(Vec3::new(7.5, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(10.0, 0.0, 0.0), 2.0),
                    sphere(Vec3::new(10.5, 0.0, 0.0), 4.0),
                ],
                options: SAH_ONE_PER_LEAF,
                expect: TreeShape::RootCut(vec![vec![0, 1, 2], vec![0]]),
            }),
        ),
        Case::new(
            "bvh-sah-three-sides-count",
            SAH_11,
            "spheres at (1, 0, -1), (2, 0, 1), (5, 0, 0) and (11.5, 0, 0), radii 4, 2, 1 and 2 \
             (objects 0 to 3; half areas 192, 48, 12, 48), the SAH, 16 bins, max_leaf 1. The root \
             from (-3, -4, -5) to (13.5, 4, 3): 16.5 x 8 + 8 x 8 + 8 x 16.5 = 328. [0] | \
             [1, 2, 3]: the right box from (0, -2, -2) to (13.5, 2, 3), 13.5 x 4 + 4 x 5 + 5 x \
             13.5 = 141.5: 328 + 192 + 141.5 x 3 = 944.5; [0, 1] | [2, 3]: object 0's box holds \
             object 1's, 192 x 2, and the right box from (4, -2, -2) to (13.5, 2, 2), 92 x 2: 328 \
             + 384 + 184 = 896; [0, 1, 2] | [3]: the left box 9 by 8 by 8, 208 x 3, and 48: 328 + \
             624 + 48 = 1000. Expected the root cut into [0, 1] and [2, 3] \
             (or, cut at the middle of the centroids, 6.25: [0, 1, 2] and [3])",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    sphere(Vec3::new(1.0, 0.0, -1.0), 4.0),
                    sphere(Vec3::new(2.0, 0.0, 1.0), 2.0),
                    sphere(Vec3::new(5.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(11.5, 0.0, 0.0), 2.0),
                ],
                options: SAH_ONE_PER_LEAF,
                expect: TreeShape::RootCut(vec![vec![0, 1], vec![0, 1, 2]]),
            }),
        ),
        Case::new(
            "bvh-sah-the-first-alone",
            SAH_11,
            "spheres at (15, 0, 0), (35, 0, -1), (36, 0, 0) and (56, 0, 1), radii 3, 2, 1 and 2 \
             (objects 0 to 3; half areas 108, 48, 12, 48), the SAH, 16 bins, max_leaf 1. The root \
             from (12, -3, -3) to (58, 3, 3): 46 x 6 + 6 x 6 + 6 x 46 = 588. [0] | [1, 2, 3]: the \
             right box from (33, -2, -3) to (58, 2, 3), 25 x 4 + 4 x 6 + 6 x 25 = 274: 588 + 108 + \
             274 x 3 = 1518; [0, 1] | [2, 3]: the left box 25 by 6 by 6, 336 x 2, the right from \
             (35, -2, -1) to (58, 2, 3), 200 x 2: 588 + 672 + 400 = 1660; [0, 1, 2] | [3]: 588 + \
             336 x 3 + 48 = 1644. Expected the root cut into [0] and [1, 2, 3] \
             (or, cut at the middle of the centroids, 35.5: [0, 1] and [2, 3])",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    sphere(Vec3::new(15.0, 0.0, 0.0), 3.0),
                    sphere(Vec3::new(35.0, 0.0, -1.0), 2.0),
                    sphere(Vec3::new(36.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(56.0, 0.0, 1.0), 2.0),
                ],
                options: SAH_ONE_PER_LEAF,
                expect: TreeShape::RootCut(vec![vec![0], vec![0, 1]]),
            }),
        ),
        Case::new(
            "bvh-sah-leaf-cheaper-than-any-cut",
            SAH_11,
            "spheres at x = 3, 4.5 and 5.5 on the x axis, radii 3, 3 and 2.5 \
             (objects 0 to 2; half areas 108, 108, 75), the SAH, 16 bins, max_leaf 1. The root \
             from (0, -3, -3) to (8, 3, 3): 8 x 6 + 6 x 6 + 6 x 8 = 132, the leaf 132 x 3 = 396. \
             [0] | [1, 2]: the right box 6.5 by 6 by 6, 114: 132 + 108 + 114 x 2 = 468; [0, 1] | \
             [2]: the left box 7.5 by 6 by 6, 126: 132 + 126 x 2 + 75 = 459. Both cost more than \
             the leaf (the boxes overlap: a ray into one is likely in the other), so the SAH keeps \
             it: expected the root a leaf holding all three \
             (or, cut at the middle of the centroids, 4.25: [0] and [1, 2]). The cost of visiting \
             the node, TRAVERSAL_COST x 132, is what makes the cut [0, 1] | [2] dearer",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    sphere(Vec3::new(3.0, 0.0, 0.0), 3.0),
                    sphere(Vec3::new(4.5, 0.0, 0.0), 3.0),
                    sphere(Vec3::new(5.5, 0.0, 0.0), 2.5),
                ],
                options: SAH_ONE_PER_LEAF,
                expect: TreeShape::RootLeafOrCut(vec![vec![0]]),
            }),
        ),
        Case::new(
            "bvh-sah-tie-goes-to-the-first-boundary",
            SAH_11,
            "unit spheres at x = -5, 0 and 5 (objects 0 to 2; half areas 12), the SAH, 16 bins, \
             max_leaf 1. The root from (-6, -1, -1) to (6, 1, 1): 12 x 2 + 2 x 2 + 2 x 12 = 52. \
             [0] | [1, 2]: the right box 7 by 2 by 2, 32: 52 + 12 + 32 x 2 = 128; [0, 1] | [2]: \
             the mirror image, 128 too. Of equal costs the first boundary wins: expected the root \
             cut into [0] and [1, 2] (the middle of the centroids, 0, cuts the same)",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    sphere(Vec3::new(-5.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(0.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(5.0, 0.0, 0.0), 1.0),
                ],
                options: SAH_ONE_PER_LEAF,
                expect: TreeShape::RootCut(vec![vec![0]]),
            }),
        )
        .fixed("two cuts of exactly equal cost, mirror images: a fresh draw would not keep the tie"),
        Case::new(
            "bvh-cut-along-z",
            BUILD_11,
            "unit spheres at z = 0, 3 and 7 on the z axis, one per leaf, cut at the middle: the \
             centroids spread 0 along x and y and 7 along z, so z is the axis to cut, at 3.5: \
             expected the root cut into [0, 1] and [2] \
             (a widest-axis search that stays on x or y finds no spread there and makes a leaf)",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    sphere(Vec3::new(0.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(0.0, 0.0, 3.0), 1.0),
                    sphere(Vec3::new(0.0, 0.0, 7.0), 1.0),
                ],
                options: ONE_PER_LEAF,
                expect: TreeShape::RootCut(vec![vec![0, 1]]),
            }),
        ),
        Case::new(
            "bvh-cut-where-the-centroids-spread",
            BUILD_11,
            "the triangle (-10, 0, 0), (10, 0, 0), (0, 0.5, 0) (object 0, its box's centre \
             (0, 0.25, 0)) and unit spheres at z = 3 and 7 (objects 1 and 2), one per leaf, cut at \
             the middle: the node's box is widest along x (20 against 2 and 9), but the centroids \
             do not spread along x at all, 0.25 along y and 7 along z: the cut is along z, at \
             3.5: expected the root cut into [0, 1] and [2] \
             (along the box's widest axis every centroid is at x = 0, and no cut separates them)",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    triangle([-10.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 0.5, 0.0]),
                    sphere(Vec3::new(0.0, 0.0, 3.0), 1.0),
                    sphere(Vec3::new(0.0, 0.0, 7.0), 1.0),
                ],
                options: ONE_PER_LEAF,
                expect: TreeShape::RootCut(vec![vec![0, 1]]),
            }),
        ),
        Case::new(
            "bvh-coincident-centroids-stay-a-leaf",
            BUILD_11,
            "spheres of radius 1, 2 and 3 around the same centre (0, 0, 10) (objects 0 to 2), one \
             per leaf: every centroid is the same point, so no plane separates them, and halves of \
             the list would be two children with the same box, both visited by every ray that \
             meets either: expected the root a leaf holding all three, max_leaf 1 or not",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: (1..=3)
                    .map(|radius| sphere(Vec3::new(0.0, 0.0, 10.0), radius as f32))
                    .collect(),
                options: ONE_PER_LEAF,
                expect: TreeShape::RootLeaf,
            }),
        )
        .fixed("centroids that coincide exactly: a fresh draw's radii round them apart"),
        Case::new(
            "bvh-nan-and-infinite-boxes-stay-out",
            PLANES_11,
            "unit spheres at (0, 0, 0) (object 0) and (3, 0, 0) (object 3); object 1 a sphere with \
             a NaN centre (its box is NaN); object 2 centred at x = 3e38 with radius 1e38, whose \
             box reaches x = 4e38, past f32::MAX (3.4e38): max.x = inf. Neither box is finite: \
             expected unbounded = [1, 2], objects 0 and 3 in the tree",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: vec![
                    sphere(Vec3::new(0.0, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(f32::NAN, 0.0, 0.0), 1.0),
                    sphere(Vec3::new(3e38, 0.0, 0.0), 1e38),
                    sphere(Vec3::new(3.0, 0.0, 0.0), 1.0),
                ],
                options: ONE_PER_LEAF,
                expect: TreeShape::Any,
            }),
        ),
        Case::from(BoxQuestion {
            name: "box-entry-close-to-the-origin",
            section: ROUNDING_11,
            says: "the cube; a ray from (-5, 0, 0) along (4096, 0, 0): the x slab from t = 4/4096 \
                   to 6/4096, the others always: expected 4/4096 = 0.0009765625. The widening \
                   moves it by 2 gamma_3 of itself (about 4e-10): a slack that grew as t shrank \
                   would not",
            bounds: CUBE,
            ray: (Vec3::new(-5.0, 0.0, 0.0), Vec3::new(4096.0, 0.0, 0.0)),
            range: IN_FRONT,
            expect: Some(4.0 / 4096.0),
        }),
        Case::from(BoxesQuestion {
            name: "boxes-four-at-once",
            section: BOXES4_11,
            says: "a ray from (-5, 0, 0) along (1, 0, 0), 0 < t < 10, and four boxes: lane 0 the \
                   cube from -1 to 1, entered at x = -1, t = 4; lane 1 from (2, -1, -1) to (3, 1, \
                   1), entered at t = 7; lane 2 from (-1, 2, -1) to (1, 3, 1), whose y slab the ray \
                   (y = 0, dir.y = 0) is never inside: a miss; lane 3 from (-6, -1, -1) to (-4, 1, \
                   1), around the origin: t_min. Expected [4, 7, NaN, 0] \
                   (a lane left out of the arithmetic answers NaN or garbage)",
            boxes: [
                CUBE,
                cuboid([2.0, -1.0, -1.0], [3.0, 1.0, 1.0]),
                cuboid([-1.0, 2.0, -1.0], [1.0, 3.0, 1.0]),
                cuboid([-6.0, -1.0, -1.0], [-4.0, 1.0, 1.0]),
            ],
            ray: (Vec3::new(-5.0, 0.0, 0.0), Vec3::X),
            range: (0.0, 10.0),
            expect: [Some(4.0), Some(7.0), None, Some(0.0)],
        }),
        Case::from(BoxesQuestion {
            name: "boxes-negative-direction-and-t-max",
            section: BOXES4_11,
            says: "a ray from (5, 0.5, 0) along (-1, 0, 0), 0 < t < 6.5: lane 0 the cube, whose \
                   plane x = 1 (max.x) comes first, at t = 4; lane 1 from (-3, -1, -1) to (-2, 1, \
                   1), entered at t = 7, beyond t_max: a miss; lane 2 from (6, -1, -1) to (7, 1, \
                   1), behind the ray: a miss; lane 3 the flat box x = 0 from (0, -1, -1) to (0, 1, \
                   1), entered and left at t = 5. Expected [4, NaN, NaN, 5]",
            boxes: [
                CUBE,
                cuboid([-3.0, -1.0, -1.0], [-2.0, 1.0, 1.0]),
                cuboid([6.0, -1.0, -1.0], [7.0, 1.0, 1.0]),
                cuboid([0.0, -1.0, -1.0], [0.0, 1.0, 1.0]),
            ],
            ray: (Vec3::new(5.0, 0.5, 0.0), -Vec3::X),
            range: (0.0, 6.5),
            expect: [Some(4.0), None, None, Some(5.0)],
        }),
        Case::from(BoxesQuestion {
            name: "boxes-nan-lanes",
            section: BOXES4_11,
            says: "a ray from (0, 1, -5) along (0, 0, 1): dir.y = 0, and the origin is on the \
                   plane y = 1, the cube's max.y (lane 0) and the min.y of the box from (-1, 1, -1) \
                   to (1, 2, 1) (lane 1): in both, (1 - 1) x inf = NaN must constrain nothing, and \
                   the z slab gives t = 4. Lane 2, from (-1, 2, -1) to (1, 3, 1), is above the ray: \
                   a miss; lane 3 holds the empty box (min inf, max -inf): a miss. Expected [4, 4, \
                   NaN, NaN]",
            boxes: [
                CUBE,
                cuboid([-1.0, 1.0, -1.0], [1.0, 2.0, 1.0]),
                cuboid([-1.0, 2.0, -1.0], [1.0, 3.0, 1.0]),
                EMPTY_LANE,
            ],
            ray: (Vec3::new(0.0, 1.0, -5.0), Vec3::Z),
            range: IN_FRONT,
            expect: [Some(4.0), Some(4.0), None, None],
        }),
        Case::from(BoxesQuestion {
            name: "boxes-entry-close-to-the-origin",
            section: BOXES4_11,
            says: "the four boxes of boxes-four-at-once and a ray from (-5, 0, 0) along (4096, 0, \
                   0), 0 < t < 10: the entries of boxes-four-at-once divided by 4096. Expected \
                   [4/4096, 7/4096, NaN, 0] = [0.0009765625, 0.0017089844, NaN, 0]. The widening \
                   moves each by 2 gamma_3 of itself (about 4e-10): a slack that grew as t shrank \
                   would not",
            boxes: [
                CUBE,
                cuboid([2.0, -1.0, -1.0], [3.0, 1.0, 1.0]),
                cuboid([-1.0, 2.0, -1.0], [1.0, 3.0, 1.0]),
                cuboid([-6.0, -1.0, -1.0], [-4.0, 1.0, 1.0]),
            ],
            ray: (Vec3::new(-5.0, 0.0, 0.0), Vec3::new(4096.0, 0.0, 0.0)),
            range: (0.0, 10.0),
            expect: [Some(4.0 / 4096.0), Some(7.0 / 4096.0), None, Some(0.0)],
        }),
        Case::from(BoxesQuestion {
            name: "boxes-flat-touched-at-t-min",
            section: BOXES4_11,
            says: "a ray from the origin along (0, 0, 1), 0 <= t <= 10, and four boxes: lane 0 the \
                   flat box from (-1, -1, 0) to (1, 1, 0), entered and left at t = 0 = t_min (the \
                   interval is closed); lane 1 from (-1, -1, 2) to (1, 1, 4), entered at 2; lane 2 \
                   the flat box at z = 3, entered at 3; lane 3 the flat box at z = -1, behind the \
                   ray: a miss. Expected [0, 2, 3, NaN]",
            boxes: [
                cuboid([-1.0, -1.0, 0.0], [1.0, 1.0, 0.0]),
                cuboid([-1.0, -1.0, 2.0], [1.0, 1.0, 4.0]),
                cuboid([-1.0, -1.0, 3.0], [1.0, 1.0, 3.0]),
                cuboid([-1.0, -1.0, -1.0], [1.0, 1.0, -1.0]),
            ],
            ray: (Vec3::ZERO, Vec3::Z),
            range: (0.0, 10.0),
            expect: [Some(0.0), Some(2.0), Some(3.0), None],
        })
        .fixed("lane 0 is touched exactly at t_min, which a fresh draw would move"),
        Case::new(
            "triangles-four-at-once",
            TRIANGLES4_11,
            "a ray from the origin along +z, 0 < t < inf, and four triangles: lane 0 from (-1, -1, \
             2), (1, -1, 2), (0, 1, 2), met at t = 2; lane 1 the same shape moved to x = 2 to 4, \
             z = 5, beside the ray: no hit; lane 2 the first moved to z = -3, behind the ray: no \
             hit; lane 3 tilted, from (-1, -1, 3.5), (1, -1, 4.5), (0, 1, 4), met at t = 4. \
             Expected, lane by lane, what your intersect_triangle answers for each triangle, bit \
             for bit: [2, NaN, NaN, 4]",
            CaseKind::FourTriangles(FourTrianglesCase {
                triangles: [
                    corners([-1.0, -1.0, 2.0], [1.0, -1.0, 2.0], [0.0, 1.0, 2.0]),
                    corners([2.0, -1.0, 5.0], [4.0, -1.0, 5.0], [3.0, 1.0, 5.0]),
                    corners([-1.0, -1.0, -3.0], [1.0, -1.0, -3.0], [0.0, 1.0, -3.0]),
                    corners([-1.0, -1.0, 3.5], [1.0, -1.0, 4.5], [0.0, 1.0, 4.0]),
                ],
                ray: Ray::new(Vec3::ZERO, Vec3::Z),
                t_min: 0.0,
                t_max: INF,
            }),
        ),
        Case::new(
            "triangles-a-zero-in-two-lanes",
            TRIANGLES4_11,
            "a ray from the origin along +z through the edge from (0, -1, 2) to (0, 1, 2) that \
             lanes 0 and 1 share (triangles (-1, 0, 2), (0, -1, 2), (0, 1, 2) and (0, -1, 2), (1, \
             0, 2), (0, 1, 2)): an edge function is exactly 0 in each, which chapter 10 \
             recomputes in f64; lane 2 holds (-1.1, -0.3, 3.7), (0.7, -0.9, 4.1), (0.3, 0.7, 4.9), \
             whose edge functions are not zero: recomputed in f64 they would round its t one ulp \
             lower; lane 3 is empty (NaN corners). Expected, lane by lane, your \
             intersect_triangle's answers bit for bit: 2, 2, about 4.348485, NaN \
             (recomputing every lane when one has a zero changes lane 2)",
            CaseKind::FourTriangles(FourTrianglesCase {
                triangles: [
                    corners([-1.0, 0.0, 2.0], [0.0, -1.0, 2.0], [0.0, 1.0, 2.0]),
                    corners([0.0, -1.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]),
                    corners([-1.1, -0.3, 3.7], [0.7, -0.9, 4.1], [0.3, 0.7, 4.9]),
                    NO_TRIANGLE,
                ],
                ray: Ray::new(Vec3::ZERO, Vec3::Z),
                t_min: 0.0,
                t_max: INF,
            }),
        )
        .fixed("edge functions exactly zero in two lanes"),
        Case::new(
            "triangles-at-the-ends-of-the-interval",
            TRIANGLES4_11,
            "a ray from the origin along +z, 1 < t < 4, and four copies of the triangle \
             (-1, -1, z), (1, -1, z), (0, 1, z): lane 0 at z = 2, met at t = 2, inside; lane 1 at \
             z = 8, beyond t_max; lane 2 at z = 4, exactly at t_max; lane 3 at z = 1, exactly at \
             t_min. The interval is open at both ends, in every lane as in intersect_triangle: \
             expected your intersect_triangle's answers bit for bit, [2, NaN, NaN, NaN]",
            CaseKind::FourTriangles(FourTrianglesCase {
                triangles: [2.0, 8.0, 4.0, 1.0]
                    .map(|z| corners([-1.0, -1.0, z], [1.0, -1.0, z], [0.0, 1.0, z])),
                ray: Ray::new(Vec3::ZERO, Vec3::Z),
                t_min: 1.0,
                t_max: 4.0,
            }),
        )
        .fixed("two lanes met exactly at t_min and t_max, which a fresh draw would move"),
        Case::new(
            "collapse-triangles-copied-a-sphere-alone",
            COLLAPSE_11,
            "three triangles (objects 0, 1 and 3) and a unit sphere (object 2) in one leaf (the \
             default options keep four objects together): expected the root using one lane, a \
             leaf of one Leaf4 whose lanes hold the four objects, each triangle's corners copied \
             into its lane and the sphere's lane marked one_by_one, its corners NaN",
            CaseKind::Collapse(CollapseCase {
                shapes: vec![
                    triangle([0.0, 0.0, 5.0], [1.0, 0.0, 5.0], [0.0, 1.0, 5.0]),
                    triangle([2.0, 0.0, 5.0], [3.0, 0.0, 6.0], [2.0, 1.0, 5.0]),
                    sphere(Vec3::new(1.0, 2.0, 6.0), 1.0),
                    triangle([-1.0, 1.0, 4.0], [0.0, 2.0, 4.0], [-1.0, 2.0, 5.0]),
                ],
                options: BvhOptions::default(),
                expect: WideShape::RootLanes(1),
            }),
        ),
        Case::new(
            "collapse-four-lanes",
            COLLAPSE_11,
            "eight unit spheres at x = 0, 3, ..., 21 (objects 0 to 7), one per leaf, cut at the \
             middle: the binary root's children hold spheres 0 to 3 and 4 to 7, theirs two spheres \
             each. The root takes its two children, opens the first of the two largest (equal \
             areas), then the largest inner child left, spheres 4 to 7: expected the root using \
             four lanes, each an inner node of two leaves, every sphere once under boxes that hold \
             it (a fold that opens no child keeps two lanes; one that drops a child loses its \
             spheres)",
            CaseKind::Collapse(CollapseCase {
                shapes: (0..8)
                    .map(|k| sphere(Vec3::new(3.0 * k as f32, 0.0, 0.0), 1.0))
                    .collect(),
                options: ONE_PER_LEAF,
                expect: WideShape::RootLanes(4),
            }),
        ),
        Case::new(
            "collapse-planes-stay-out",
            COLLAPSE_11,
            "a unit sphere at (0, 0, 10) (object 0), the plane z = 5 (object 1) and a unit sphere \
             at (0, 0, 3) (object 2), one per leaf: expected unbounded = [1], as the binary tree's, \
             and the two spheres in the wide tree's leaves",
            CaseKind::Collapse(CollapseCase {
                shapes: plane_between(),
                options: ONE_PER_LEAF,
                expect: WideShape::RootLanes(2),
            }),
        ),
        Case::from(BvhHitsQuestion {
            name: "wide-nearest-behind-a-nearer-box",
            section: WIDE_WALK_11,
            says: "the spheres of bvh-nearest-behind-a-nearer-box through the wide tree: object 0's \
                   box is entered first (z = 5), object 1 is hit nearer (t = 6 against 7): expected \
                   object 1 at t = 6 (a walk that stops at the first leaf with a hit says object 0)",
            shapes: behind(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-triangle-behind-a-nearer-box",
            section: WIDE_WALK_11,
            says: "a ray from the origin along +z; object 0 the triangle (-2, -2, 3), (2, -2, 3), \
                   (0, 2, 9), whose box starts at z = 3 but which the ray meets at z = 6 (halfway up \
                   its slope); object 1 the triangle (-1, -1, 5), (1, -1, 5), (0, 1, 5), met at t = \
                   5; one per leaf: expected object 1 at t = 5",
            shapes: vec![
                triangle([-2.0, -2.0, 3.0], [2.0, -2.0, 3.0], [0.0, 2.0, 9.0]),
                triangle([-1.0, -1.0, 5.0], [1.0, -1.0, 5.0], [0.0, 1.0, 5.0]),
            ],
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-plane-still-hit",
            section: WIDE_WALK_11,
            says: "the objects of bvh-plane-still-hit through the wide tree: expected object 2 at \
                   t = 2 along +z, then object 1 (the plane) at t = 6.25 along (0.6, 0, 0.8)",
            shapes: plane_between(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z), from_origin(Vec3::new(0.6, 0.0, 0.8))],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-nearest-tie-goes-to-the-first-listed",
            section: WIDE_WALK_11,
            says: "the sphere and plane of bvh-nearest-tie-goes-to-the-first-listed, both met at t = \
                   4, through the wide tree: expected object 0 at t = 4",
            shapes: vec![
                sphere(Vec3::new(0.0, 0.0, 5.0), 1.0),
                Plane::new(Vec3::new(0.0, 0.0, 4.0), -Vec3::Z).into(),
            ],
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-lane-tie-goes-to-the-first-listed",
            section: WIDE_WALK_11,
            says: "the triangle (-1, -1, 4), (1, -1, 4), (0, 1, 4) (object 0, in a Leaf4's lane) and \
                   the plane z = 4 (object 1, asked first): along +z from the origin both meet the \
                   ray at exactly t = 4, the lane after the plane. Chapter 3 keeps the first \
                   listed: expected object 0 at t = 4",
            shapes: vec![
                triangle([-1.0, -1.0, 4.0], [1.0, -1.0, 4.0], [0.0, 1.0, 4.0]),
                Plane::new(Vec3::new(0.0, 0.0, 4.0), -Vec3::Z).into(),
            ],
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        })
        .fixed("an exact tie between a triangle and a plane, which a fresh draw would break"),
        Case::from(BvhHitsQuestion {
            name: "wide-any-hit-finds-the-blocker",
            section: WIDE_WALK_11,
            says: "the spheres of bvh-any-hit-finds-the-blocker through any_hit_wide: a shadow ray \
                   along +z with t_max = 10 is blocked by object 1 at t = 4: expected a hit; one \
                   along +y: expected none",
            shapes: blockers(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z), from_origin(Vec3::Y)],
            range: (0.0, 10.0),
            any_hit: true,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-any-hit-beyond-the-light",
            section: WIDE_WALK_11,
            says: "the same spheres, the ray along +z with t_max = 3.5: the blocker at t = 4 is \
                   beyond the light: expected no hit",
            shapes: blockers(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: (0.0, 3.5),
            any_hit: true,
            wide: true,
        }),
        steps_judged(BvhHitsQuestion {
            name: "wide-skips-waiting-children-beyond-the-best",
            section: WIDE_WALK_11,
            says: "the spheres of bvh-nearest-skips-boxes-beyond-the-best through the wide tree, \
                   one lane each: the root's boxes are entered at t = 4, 9 and 14, object 0 is hit \
                   at 4, and the two lanes left waiting are skipped when they come off the stack: \
                   expected object 0 at t = 4, and objects 1 and 2 never asked",
            shapes: in_a_row(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        steps_judged(BvhHitsQuestion {
            name: "wide-asks-up-to-the-best",
            section: WIDE_WALK_11,
            says: "the spheres of bvh-nearest-asks-up-to-the-best through the wide tree: objects 0 \
                   and 1 are both asked, the second for hits up to and including the first one's \
                   t, and object 2 is skipped: expected object 1 at t = 6",
            shapes: behind(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        steps_judged(BvhHitsQuestion {
            name: "wide-planes-first",
            section: WIDE_WALK_11,
            says: "the objects of bvh-planes-first-their-hit-shortens-the-walk through the wide \
                   tree: the plane z = 3, outside the tree, is asked first and hit at t = 3, \
                   before every box: expected object 2 at t = 3, and neither sphere asked",
            shapes: plane_in_front(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        steps_judged(BvhHitsQuestion {
            name: "wide-any-hit-stops-at-its-first-hit",
            section: WIDE_WALK_11,
            says: "the objects and the shadow ray of bvh-any-hit-stops-at-its-first-hit through \
                   any_hit_wide: the plane first, then only the lanes the ray enters, and nothing \
                   after the first blocker: expected a hit, and objects 1, 3 and 4 never asked",
            shapes: shadow_row(),
            options: ONE_PER_LEAF,
            rays: vec![from_origin(Vec3::Z)],
            range: (0.0, 20.0),
            any_hit: true,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-mixed-leaf",
            section: WIDE_WALK_11,
            says: "one leaf of four, the default options: the triangle (-1, -1, 6), (1, -1, 6), \
                   (0, 1, 6) (object 0), a unit sphere at (0, 0, 5) (object 1), the triangle \
                   (2, -1, 3), (4, -1, 3), (3, 1, 3) (object 2) and a unit sphere at (3, 0, 5) \
                   (object 3); the plane z = 8 (object 4) outside the tree. Along +z from the \
                   origin the sphere, asked on its own, is nearer (t = 4) than the triangle in its \
                   lane (6); from (3, 0, 0) the triangle (t = 3) is nearer than the sphere (4): \
                   expected object 1 at t = 4, then object 2 at t = 3",
            shapes: vec![
                triangle([-1.0, -1.0, 6.0], [1.0, -1.0, 6.0], [0.0, 1.0, 6.0]),
                sphere(Vec3::new(0.0, 0.0, 5.0), 1.0),
                triangle([2.0, -1.0, 3.0], [4.0, -1.0, 3.0], [3.0, 1.0, 3.0]),
                sphere(Vec3::new(3.0, 0.0, 5.0), 1.0),
                Plane::new(Vec3::new(0.0, 0.0, 8.0), -Vec3::Z).into(),
            ],
            options: BvhOptions::default(),
            rays: vec![
                from_origin(Vec3::Z),
                Ray::new(Vec3::new(3.0, 0.0, 0.0), Vec3::Z),
            ],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-mixed-leaf-tie",
            section: WIDE_WALK_11,
            says: "one leaf of four: the triangle (-1, -1, 4), (1, -1, 4), (0, 1, 4) (object 0), \
                   unit spheres at (0, 0, 5) and (3, 0, 5) (objects 1 and 2) and the triangle \
                   (2, -1, 4), (4, -1, 4), (3, 1, 4) (object 3). Along +z from the origin the \
                   triangle in its lane and the sphere asked on its own both meet the ray at \
                   exactly t = 4, and so do the other two from (3, 0, 0). Chapter 3 keeps the first \
                   listed: expected object 0 at t = 4, then object 2 at t = 4, whichever of the \
                   two the walk asks first",
            shapes: vec![
                triangle([-1.0, -1.0, 4.0], [1.0, -1.0, 4.0], [0.0, 1.0, 4.0]),
                sphere(Vec3::new(0.0, 0.0, 5.0), 1.0),
                sphere(Vec3::new(3.0, 0.0, 5.0), 1.0),
                triangle([2.0, -1.0, 4.0], [4.0, -1.0, 4.0], [3.0, 1.0, 4.0]),
            ],
            options: BvhOptions::default(),
            rays: vec![
                from_origin(Vec3::Z),
                Ray::new(Vec3::new(3.0, 0.0, 0.0), Vec3::Z),
            ],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        })
        .fixed("exact ties between a triangle and a sphere, which a fresh draw would break"),
        Case::from(BvhHitsQuestion {
            name: "wide-any-hit-mixed-leaf",
            section: WIDE_WALK_11,
            says: "one leaf of four: the triangles (2, -1, 6), (4, -1, 6), (3, 1, 6) and \
                   (-4, -1, 6), (-2, -1, 6), (-3, 1, 6) (objects 0 and 2) and a unit sphere at \
                   (0, 3, 5) (object 3) beside the ray, a unit sphere at (0, 0, 5) (object 1) on \
                   it; a shadow ray from the origin along +z with t_max = 10: no triangle lane \
                   hits, the sphere asked on its own does, at t = 4: expected a hit",
            shapes: vec![
                triangle([2.0, -1.0, 6.0], [4.0, -1.0, 6.0], [3.0, 1.0, 6.0]),
                sphere(Vec3::new(0.0, 0.0, 5.0), 1.0),
                triangle([-4.0, -1.0, 6.0], [-2.0, -1.0, 6.0], [-3.0, 1.0, 6.0]),
                sphere(Vec3::new(0.0, 3.0, 5.0), 1.0),
            ],
            options: BvhOptions::default(),
            rays: vec![from_origin(Vec3::Z)],
            range: (0.0, 10.0),
            any_hit: true,
            wide: true,
        }),
    ]
}

/// `count` spheres with centres in `[-extent, extent]^3` and radii in
/// `radii.0..radii.1`, from `seed`, and `rays` rays from `eye` toward
/// random points of the same cube: the same every run.
struct RandomSpheres {
    seed: u64,
    count: usize,
    extent: f32,
    radii: (f32, f32),
    eye: Vec3,
    rays: usize,
}

impl RandomSpheres {
    fn generate(self) -> (Vec<Shape>, Vec<Ray>) {
        let RandomSpheres {
            seed,
            count,
            extent,
            radii,
            eye,
            rays,
        } = self;
        let mut numbers = exact::Xorshift::new(seed);
        let point = |numbers: &mut exact::Xorshift| {
            Vec3::new(
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
}

/// Raylab's closed model of about `triangles` triangles (a torus around the
/// y axis, radius about 1.5), and `rays` rays from points 4 from its centre
/// toward random points of its box, from `seed`: some through the hole,
/// some beside it, many through shared edges' neighbourhoods.
fn closed_mesh(triangles: usize, rays: usize, seed: u64) -> (Vec<Shape>, Vec<Ray>) {
    let shapes = crate::mesh::generate_closed_mesh(triangles)
        .map(|mesh| crate::bvh_reports::leaks::triangles(&mesh))
        .unwrap_or_default();
    let mut numbers = exact::Xorshift::new(seed);
    let rays = (0..rays)
        .map(|_| {
            let eye = Vec3::new(
                numbers.between(-1.0, 1.0),
                numbers.between(-1.0, 1.0),
                numbers.between(-1.0, 1.0),
            )
            .normalize_or(Vec3::X)
                * 4.0;
            let aim = Vec3::new(
                numbers.between(-1.5, 1.5),
                numbers.between(-0.5, 0.5),
                numbers.between(-1.5, 1.5),
            );
            Ray::new(eye, aim - eye)
        })
        .collect();
    (shapes, rays)
}

/// Chapter 11's hard cases.
///
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn robustness() -> Vec<Case> {
    let default = BvhOptions::default();
    let (thousand, thousand_rays) = RandomSpheres {
        seed: 11,
        count: 1000,
        extent: 20.0,
        radii: (0.1, 0.6),
        eye: Vec3::new(0.0, 0.0, -40.0),
        rays: 200,
    }
    .generate();
    let (huge, huge_rays) = RandomSpheres {
        seed: 1100,
        count: 300,
        extent: 1e5,
        radii: (1e3, 5e3),
        eye: Vec3::new(0.0, 0.0, -3e5),
        rays: 200,
    }
    .generate();
    // Two pairs of copies, and a big sphere touching a small one from
    // inside at z = 4, where the ray along +z meets both: ties everywhere.
    let ties = vec![
        sphere(Vec3::new(0.0, 0.0, 20.0), 1.0),
        sphere(Vec3::new(0.0, 0.0, 6.0), 2.0),
        sphere(Vec3::new(0.0, 0.0, 5.0), 1.0),
        sphere(Vec3::new(0.0, 0.0, 20.0), 1.0),
        sphere(Vec3::new(0.0, 0.0, 5.0), 1.0),
        sphere(Vec3::new(0.0, 0.0, 6.0), 2.0),
        sphere(Vec3::new(2.0, 0.0, 5.0), 1.0),
        sphere(Vec3::new(2.0, 0.0, 5.0), 1.0),
        Plane::new(Vec3::new(0.0, 0.0, 4.0), -Vec3::Z).into(),
    ];
    let tie_rays: Vec<Ray> = [
        Vec3::Z,
        Vec3::new(0.1, 0.0, 1.0),
        Vec3::new(-0.1, 0.05, 1.0),
        Vec3::new(0.4, 0.0, 1.0),
        Vec3::new(0.0, 0.0, -1.0),
    ]
    .into_iter()
    .map(|dir| Ray::new(Vec3::ZERO, dir))
    .collect();
    // 200 spheres around one centre: every centroid the same point.
    let center = Vec3::new(0.0, 0.0, 10.0);
    let concentric: Vec<Shape> = (0..200)
        .map(|index| Sphere::new(center, 0.5 + 0.0225 * index as f32).into())
        .collect();
    let concentric_rays = vec![
        Ray::new(Vec3::ZERO, Vec3::Z),
        Ray::new(Vec3::ZERO, Vec3::new(0.2, 0.1, 1.0)),
        Ray::new(center, Vec3::new(1.0, 0.5, -0.25)),
        Ray::new(center + Vec3::new(0.0, 0.0, 1.0), Vec3::Z),
    ];
    let (thousand_wide, thousand_wide_rays) = (thousand.clone(), thousand_rays.clone());
    let (ties_wide, tie_rays_wide) = (ties.clone(), tie_rays.clone());
    let (concentric_wide, concentric_rays_wide) = (concentric.clone(), concentric_rays.clone());
    let (mesh, mesh_rays) = closed_mesh(1000, 300, 1111);
    // The 70 spheres at x = 3^k of bvh-deeper-than-the-stack, object 3 of
    // radius 2, and a ray 0.9 off the axis in y and z, 1.27 from every
    // centre: it enters every box and misses every unit sphere, so its
    // one hit, object 3, is one of the last spheres set aside.
    let spilled: Vec<Shape> = (0..70)
        .map(|k| {
            let radius = if k == 3 { 2.0 } else { 1.0 };
            sphere(Vec3::new(3.0f32.powi(k), 0.0, 0.0), radius)
        })
        .collect();
    let past_the_stack = Ray::new(Vec3::new(-10.0, 0.9, 0.9), Vec3::X);
    // In the wide tree the rest of a chain lands in a node's last lane, and
    // an any-hit walk pushes lanes in order: mirrored, the chain is walked
    // first and the peeled spheres wait.
    let mirrored: Vec<Shape> = (0..70)
        .map(|k| {
            let radius = if k == 3 { 2.0 } else { 1.0 };
            sphere(Vec3::new(-(3.0f32.powi(k)), 0.0, 0.0), radius)
        })
        .collect();
    robust(vec![
        Case::from(BvhHitsQuestion {
            name: "bvh-thousand-spheres",
            section: WALK_11,
            says: "1000 spheres of radius 0.1 to 0.6 scattered in the cube from -20 to 20 \
                   (the same every run), the default options (SAH, 16 bins, max_leaf 4); 200 rays \
                   from (0, 0, -40) into the cube: each must find chapter 3's hit, same object, \
                   same t",
            shapes: thousand.clone(),
            options: default,
            rays: thousand_rays.clone(),
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-thousand-spheres-any-hit",
            section: ANY_11,
            says: "the same 1000 spheres and 200 rays, through any_hit_bvh: a real hit exactly \
                   when chapter 3 finds one",
            shapes: thousand,
            options: default,
            rays: thousand_rays,
            range: IN_FRONT,
            any_hit: true,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-huge-coordinates",
            section: WALK_11,
            says: "300 spheres of radius 1e3 to 5e3 with centres up to 1e5 from the origin, 200 \
                   rays from (0, 0, -3e5): box areas near 1e11 \
                   (an f32 product of two sides is fine, a sum of many costs needs care), and \
                   still chapter 3's hit on every ray",
            shapes: huge,
            options: default,
            rays: huge_rays,
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-ties-lower-index-wins",
            section: WALK_11,
            says: "copies of the same spheres (objects 2 and 4, 1 and 5, 6 and 7, 0 and 3), the \
                   radius 2 sphere at z = 6 touching the unit one at z = 5 from inside at z = 4, \
                   and the plane z = 4 (object 8), one sphere per leaf where they can be cut \
                   apart: along +z objects 1, 2, 4, 5 and 8 are all hit at t = 4. Chapter 3 keeps \
                   the first listed of equal hits: expected its answer (object 1 at t = 4) on each \
                   of 5 rays",
            shapes: ties,
            options: ONE_PER_LEAF,
            rays: tie_rays,
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-coincident-centroids",
            section: BUILD_11,
            says: "200 spheres around the same centre (0, 0, 10), radii 0.5 to 4.98: every \
                   centroid is the same point, so no cut can separate them, even with max_leaf 1 \
                   (the build must stop, not loop or recurse forever); from outside the largest is \
                   hit first, from the centre the smallest: chapter 3's answer on each ray",
            shapes: concentric,
            options: ONE_PER_LEAF,
            rays: concentric_rays,
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-only-planes",
            section: PLANES_11,
            says: "two planes and nothing with a box (an empty tree): a ray from the origin along \
                   +z meets the plane z = 3 at t = 3: expected object 1 at t = 3",
            shapes: vec![
                Plane::new(Vec3::new(0.0, 0.0, 8.0), -Vec3::Z).into(),
                Plane::new(Vec3::new(0.0, 0.0, 3.0), -Vec3::Z).into(),
            ],
            options: default,
            rays: vec![Ray::new(Vec3::ZERO, Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-nan-ray",
            section: NAN_11,
            says: "a ray whose direction is NaN through the 1000 spheres' first ten: no box can \
                   reject it (every crossing is NaN), the objects' own tests do: expected no hit",
            shapes: RandomSpheres {
                seed: 11,
                count: 10,
                extent: 20.0,
                radii: (0.1, 0.6),
                eye: Vec3::ZERO,
                rays: 0,
            }
            .generate()
            .0,
            options: default,
            rays: vec![Ray::new(Vec3::ZERO, Vec3::NAN)],
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        Case::from(BoxQuestion {
            name: "box-through-a-corner",
            section: ROUNDING_11,
            says: "the cube from -1 to 1; a ray from (2, 2, 0) along (-1, -1, 1) touches it only \
                   at the corner (1, 1, 1), at t = 1, where it enters (x and y planes) and leaves \
                   (the z plane) at once: expected 1",
            bounds: CUBE,
            ray: (Vec3::new(2.0, 2.0, 0.0), Vec3::new(-1.0, -1.0, 1.0)),
            range: IN_FRONT,
            expect: Some(1.0),
        }),
        Case::new(
            "box-rays-along-edges",
            ROUNDING_11,
            "20000 rays from random origins aimed at random points of the edges of the box from \
             (-1.3, 0.2, 2.7) to (0.9, 1.7, 3.1): where the exact ray (in f64) meets the box, even \
             along a sliver, hit_box must say so; the rounded crossings can put the entry a hair \
             past the exit, which the widening by 2 gamma_3 absorbs",
            CaseKind::BoxEdges(BoxEdgesCase {
                min: Vec3::new(-1.3, 0.2, 2.7),
                max: Vec3::new(0.9, 1.7, 3.1),
                rays: 20_000,
                seed: 0x2545_f491_4f6c_dd1d,
                four_at_once: false,
            }),
        ),
        Case::from(BvhHitsQuestion {
            name: "bvh-deeper-than-the-stack",
            section: WALK_11,
            says: "70 unit spheres on the x axis at x = 3^k, k = 0 to 69 (object k), one per leaf, \
                   cut at the middle: the middle of 1 to 3^n is (1 + 3^n) / 2, above every \
                   centroid but the last, so each cut peels off one sphere and the tree is 69 \
                   levels deep, more than the 64 waiting nodes the walk keeps in a fixed array. A \
                   ray from (-10, 0, 0) along +x meets every box and sets each peeled sphere aside \
                   on its way down: expected object 0 at t = 10",
            shapes: (0..70)
                .map(|k| sphere(Vec3::new(3.0f32.powi(k), 0.0, 0.0), 1.0))
                .collect(),
            options: ONE_PER_LEAF,
            rays: vec![Ray::new(Vec3::new(-10.0, 0.0, 0.0), Vec3::X)],
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-tie-far-from-the-origin",
            section: WALK_11,
            says: "a unit sphere at (0, 0, 5) (object 0, in the tree) and the plane z = 4 \
                   (object 1, asked first); a ray from (0, 0, -100) along +z meets both at exactly \
                   t = 104. The sphere's padded box is entered at 104 in f32 too: only the \
                   widening, which moves the entry down by 2 gamma_3 of 104 \
                   (4e-5, five ulps there), lets the walk open it at a best of 104. Chapter 3 \
                   keeps the first listed: expected object 0 at t = 104",
            shapes: vec![
                sphere(Vec3::new(0.0, 0.0, 5.0), 1.0),
                Plane::new(Vec3::new(0.0, 0.0, 4.0), -Vec3::Z).into(),
            ],
            options: ONE_PER_LEAF,
            rays: vec![Ray::new(Vec3::new(0.0, 0.0, -100.0), Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-coplanar-tie-far-from-the-origin",
            section: ROUNDING_11,
            says: "the triangle (-10, -10, 4), (10, -10, 4), (0, 10, 4) (object 0, in the tree, \
                   its box flat) and the plane z = 4 (object 1, asked first), met by a ray from \
                   (-14, -4, -1000) along (0.042, 0.012, 3). Both lie in one plane, and the \
                   roundings of three formulas decide: the plane at t = 334.66666, the triangle \
                   one ulp nearer at 334.66663, the box's entry, as rounded, one ulp past the \
                   plane at 334.6667. Only the entry's widening lets the walk open the box at a \
                   best of 334.66666: expected object 0 at t = 334.66663",
            shapes: vec![
                triangle([-10.0, -10.0, 4.0], [10.0, -10.0, 4.0], [0.0, 10.0, 4.0]),
                Plane::new(Vec3::new(0.0, 0.0, 4.0), -Vec3::Z).into(),
            ],
            options: ONE_PER_LEAF,
            rays: vec![Ray::new(
                Vec3::new(-14.0, -4.0, -1000.0),
                Vec3::new(0.042, 0.012, 3.0),
            )],
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        })
        .fixed("a hit decided by the roundings of three formulas, which a fresh draw would change"),
        Case::new(
            "boxes-rays-along-edges",
            BOXES4_11,
            "the rays of box-rays-along-edges through hit_boxes, the box in lane i % 4 for ray i \
             and the other lanes empty: every lane must enter the box where the exact ray meets \
             it, as hit_box does",
            CaseKind::BoxEdges(BoxEdgesCase {
                min: Vec3::new(-1.3, 0.2, 2.7),
                max: Vec3::new(0.9, 1.7, 3.1),
                rays: 20_000,
                seed: 0x2545_f491_4f6c_dd1d,
                four_at_once: true,
            }),
        ),
        Case::from(BvhHitsQuestion {
            name: "wide-coplanar-tie-far-from-the-origin",
            section: WIDE_WALK_11,
            says: "the triangle, plane and ray of bvh-coplanar-tie-far-from-the-origin through the \
                   wide tree: the four-box test's entry also rounds one ulp past the plane's hit, \
                   and only its widening opens the box: expected object 0 at t = 334.66663",
            shapes: vec![
                triangle([-10.0, -10.0, 4.0], [10.0, -10.0, 4.0], [0.0, 10.0, 4.0]),
                Plane::new(Vec3::new(0.0, 0.0, 4.0), -Vec3::Z).into(),
            ],
            options: ONE_PER_LEAF,
            rays: vec![Ray::new(
                Vec3::new(-14.0, -4.0, -1000.0),
                Vec3::new(0.042, 0.012, 3.0),
            )],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        })
        .fixed("a hit decided by the roundings of three formulas, which a fresh draw would change"),
        Case::new(
            "triangles-closed-mesh-in-fours",
            TRIANGLES4_11,
            "raylab's closed model of 200 triangles, four consecutive ones to a call, and a ray \
             from inside toward each vertex and edge midpoint: where edge functions are zero or \
             nearly so, every lane must still be your intersect_triangle's answer, bit for bit",
            CaseKind::MeshInFours(MeshInFoursCase {
                triangles: 200,
                motion: None,
            }),
        ),
        Case::new(
            "collapse-a-big-leaf-in-fours",
            COLLAPSE_11,
            "ten spheres around the same centre (0, 0, 10), radii 0.5 to 2.75: no cut separates \
             them, so the binary tree is one leaf of ten; expected the root using one lane, its \
             leaf three Leaf4s holding the ten spheres once each, every lane marked one_by_one",
            CaseKind::Collapse(CollapseCase {
                shapes: (0..10)
                    .map(|index| sphere(center, 0.5 + 0.25 * index as f32))
                    .collect(),
                options: default,
                expect: WideShape::RootLanes(1),
            }),
        ),
        Case::from(BvhHitsQuestion {
            name: "wide-thousand-spheres",
            section: WIDE_WALK_11,
            says: "the 1000 spheres and 200 rays of bvh-thousand-spheres through the wide tree: \
                   chapter 3's hit on every ray, same object, same t",
            shapes: thousand_wide.clone(),
            options: default,
            rays: thousand_wide_rays.clone(),
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-thousand-spheres-any-hit",
            section: WIDE_WALK_11,
            says: "the same through any_hit_wide: a real hit exactly when chapter 3 finds one",
            shapes: thousand_wide,
            options: default,
            rays: thousand_wide_rays,
            range: IN_FRONT,
            any_hit: true,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-closed-mesh",
            section: WIDE_WALK_11,
            says: "raylab's closed model of 1,008 triangles (the same every run) and 300 rays from \
                   4 units around it toward its box, the default options: the leaves' triangles \
                   tested four at a time, and chapter 3's hit on every ray, same object, same t",
            shapes: mesh.clone(),
            options: default,
            rays: mesh_rays.clone(),
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-closed-mesh-any-hit",
            section: WIDE_WALK_11,
            says: "the same model and rays through any_hit_wide: a real hit exactly when chapter 3 \
                   finds one",
            shapes: mesh,
            options: default,
            rays: mesh_rays,
            range: IN_FRONT,
            any_hit: true,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-ties-lower-index-wins",
            section: WIDE_WALK_11,
            says: "the copies and the plane of bvh-ties-lower-index-wins through the wide tree: \
                   expected chapter 3's answer (object 1 at t = 4 along +z) on each of 5 rays",
            shapes: ties_wide,
            options: ONE_PER_LEAF,
            rays: tie_rays_wide,
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-triangle-ties-lower-index-wins",
            section: WIDE_WALK_11,
            says: "objects 1 to 4 the same triangle (-1, -1, 4), (1, -1, 4), (0, 1, 4), object 0 \
                   the triangle (5, -1, 4), (7, -1, 4), (6, 1, 4) beside the ray; cut at the middle \
                   of the centroids (x = 3) with max_leaf 4, objects 1 to 4 make one leaf, one \
                   Leaf4 whose four lanes answer together, all at t = 4 along +z (in the reference's \
                   build, object 4 in the first lane). Chapter 3 keeps the first listed: expected \
                   object 1 at t = 4",
            shapes: vec![
                triangle([5.0, -1.0, 4.0], [7.0, -1.0, 4.0], [6.0, 1.0, 4.0]),
                triangle([-1.0, -1.0, 4.0], [1.0, -1.0, 4.0], [0.0, 1.0, 4.0]),
                triangle([-1.0, -1.0, 4.0], [1.0, -1.0, 4.0], [0.0, 1.0, 4.0]),
                triangle([-1.0, -1.0, 4.0], [1.0, -1.0, 4.0], [0.0, 1.0, 4.0]),
                triangle([-1.0, -1.0, 4.0], [1.0, -1.0, 4.0], [0.0, 1.0, 4.0]),
            ],
            options: BvhOptions {
                split: SplitRule::Midpoint,
                bins: 16,
                max_leaf: 4,
            },
            rays: vec![Ray::new(Vec3::ZERO, Vec3::Z)],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-coincident-centroids",
            section: WIDE_WALK_11,
            says: "the 200 spheres around one centre of bvh-coincident-centroids, one leaf of 50 \
                   Leaf4s in the wide tree, every lane asked on its own: chapter 3's answer on each \
                   of its 4 rays",
            shapes: concentric_wide,
            options: ONE_PER_LEAF,
            rays: concentric_rays_wide,
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-nan-ray",
            section: WIDE_WALK_11,
            says: "a ray whose direction is NaN through the wide tree of 10 spheres: every box is \
                   entered (no comparison can reject it), the lanes that hold nothing must not be: \
                   expected no hit",
            shapes: RandomSpheres {
                seed: 11,
                count: 10,
                extent: 20.0,
                radii: (0.1, 0.6),
                eye: Vec3::ZERO,
                rays: 0,
            }
            .generate()
            .0,
            options: default,
            rays: vec![Ray::new(Vec3::ZERO, Vec3::NAN)],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-zero-direction-ray",
            section: WIDE_WALK_11,
            says: "a ray of direction (0, 0, 0) from (0, 0, -40) through the wide tree of the 1000 \
                   spheres: 1 / 0 = inf on every axis, so a box ahead of the origin on some axis and \
                   around it on the others is entered at t = inf, as hit_box says; the walk must \
                   still go only where the ray enters, and end: expected chapter 3's answer (no \
                   hit: a ray that does not move meets nothing)",
            shapes: RandomSpheres {
                seed: 11,
                count: 1000,
                extent: 20.0,
                radii: (0.1, 0.6),
                eye: Vec3::ZERO,
                rays: 0,
            }
            .generate()
            .0,
            options: default,
            rays: vec![Ray::new(Vec3::new(0.0, 0.0, -40.0), Vec3::ZERO)],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-deeper-than-the-stack",
            section: WIDE_WALK_11,
            says: "the 70 spheres at x = 3^k of bvh-deeper-than-the-stack, a binary tree 69 levels \
                   deep folded into a wide one about half as deep, each node leaving up to three \
                   children waiting: expected object 0 at t = 10 along +x from (-10, 0, 0)",
            shapes: (0..70)
                .map(|k| sphere(Vec3::new(3.0f32.powi(k), 0.0, 0.0), 1.0))
                .collect(),
            options: ONE_PER_LEAF,
            rays: vec![Ray::new(Vec3::new(-10.0, 0.0, 0.0), Vec3::X)],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-stack-spills-over",
            section: WALK_11,
            says: "the 70 spheres of bvh-deeper-than-the-stack with object 3 (x = 27) of radius \
                   2, and a ray from (-10, 0.9, 0.9) along +x: it enters every box and passes 1.27 \
                   from every centre, missing every unit sphere. Each sphere peeled off on the way \
                   down waits on the stack, object 3 among the last five, past the fixed array's \
                   64 entries: they spill into a Vec, and none is lost: expected object 3 at \
                   t = 37 - sqrt(4 - 1.62) = 35.4573",
            shapes: spilled.clone(),
            options: ONE_PER_LEAF,
            rays: vec![past_the_stack],
            range: IN_FRONT,
            any_hit: false,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "bvh-any-hit-stack-spills-over",
            section: ANY_11,
            says: "the same spheres and ray through any_hit_bvh: its one blocker, object 3, waits \
                   past the fixed array's 64 entries: expected a hit",
            shapes: spilled.clone(),
            options: ONE_PER_LEAF,
            rays: vec![past_the_stack],
            range: IN_FRONT,
            any_hit: true,
            wide: false,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-stack-spills-over",
            section: WIDE_WALK_11,
            says: "the same spheres and ray through the wide tree, each node leaving up to three \
                   children waiting: expected object 3 at t = 35.4573",
            shapes: spilled,
            options: ONE_PER_LEAF,
            rays: vec![past_the_stack],
            range: IN_FRONT,
            any_hit: false,
            wide: true,
        }),
        Case::from(BvhHitsQuestion {
            name: "wide-any-hit-stack-spills-over",
            section: WIDE_WALK_11,
            says: "the same spheres mirrored (centres at x = -3^k) and the ray mirrored, from \
                   (10, 0.9, 0.9) along -x, through any_hit_wide. Each cut peels the sphere \
                   farthest out into the first lane and the rest of the chain lands in the last, \
                   pushed last and so walked first: three peeled spheres wait at each of the wide \
                   tree's levels, object 3 past the fixed array's 64 entries: expected a hit",
            shapes: mirrored,
            options: ONE_PER_LEAF,
            rays: vec![Ray::new(Vec3::new(10.0, 0.9, 0.9), -Vec3::X)],
            range: IN_FRONT,
            any_hit: true,
            wide: true,
        }),
        Case::new(
            "bvh-sah-boxes-1e20-wide",
            SAH_11,
            "the spheres of bvh-sah-cut-not-the-middle scaled by 1e19: radius 1e19, centres at \
             x = 1e21, 1.01e21, 1.05e21, 1.06e21 and 1.11e21. Every half area is 1e38 times the \
             small case's (the root's 5.6e39), past f32::MAX (3.4e38): summed in f64 the costs \
             are the same ratios: expected the same cut, [0, 1] and [2, 3, 4] (or the middle's, \
             [0, 1, 2] and [3, 4])",
            CaseKind::BvhBuild(BvhBuildCase {
                shapes: [1.0e21, 1.01e21, 1.05e21, 1.06e21, 1.11e21]
                    .into_iter()
                    .map(|x| sphere(Vec3::new(x, 0.0, 0.0), 1e19))
                    .collect(),
                options: SAH_ONE_PER_LEAF,
                expect: TreeShape::RootCut(vec![vec![0, 1], vec![0, 1, 2]]),
            }),
        ),
    ])
}
