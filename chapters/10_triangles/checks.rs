//! Chapter 10's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 10`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

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
pub fn checkpoints() -> Vec<Case> {
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
pub fn robustness() -> Vec<Case> {
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
mod tests {
    use super::*;

    #[test]
    fn every_expected_triangle_hit_has_an_exact_value() {
        for case in checkpoints().into_iter().chain(robustness()) {
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
