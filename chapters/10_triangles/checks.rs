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

/// An `intersect_triangle` question on each of `triangles`, the ray from
/// `ray.0` along `ray.1`, hits wanted for `range.0 < t < range.1`; a hit's
/// `t` is the nearest exact one among them.
struct TrianglesQuestion {
    name: &'static str,
    section: &'static str,
    says: &'static str,
    triangles: Vec<[Vec3; 3]>,
    /// `(origin, dir)`.
    ray: (Vec3, Vec3),
    /// `(t_min, t_max)`.
    range: (f32, f32),
    expect: Expect,
}

impl From<TrianglesQuestion> for Case {
    fn from(question: TrianglesQuestion) -> Case {
        let (origin, dir) = question.ray;
        let (t_min, t_max) = question.range;
        let expect = question.expect.with_exact_t(|| {
            question
                .triangles
                .iter()
                .filter_map(|corners| {
                    exact::triangle(
                        corners.map(wide),
                        wide(origin),
                        wide(dir),
                        f64::from(t_min),
                        f64::from(t_max),
                    )
                })
                .reduce(f64::min)
        });
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::Triangles(TrianglesCase {
                triangles: question.triangles,
                ray: Ray::new(origin, dir),
                t_min,
                t_max,
                expect,
            }),
        )
    }
}

/// The unit square at z = 2 as two triangles sharing its diagonal
/// (1, 0, 2)-(0, 1, 2): the first takes the square's corners
/// `first_triangle` (indices into (0, 0), (1, 0), (1, 1), (0, 1)), the
/// second the same turned half a turn about the square's centre, which
/// keeps the winding and puts the diagonal (reversed) in the same place of
/// both. A ray from (0.5, 0.5, `ray_from_z`) toward z = 2 goes through the
/// middle of the diagonal: expected a hit.
struct SharedDiagonalQuestion {
    name: &'static str,
    says: &'static str,
    first_triangle: [usize; 3],
    ray_from_z: f32,
}

impl From<SharedDiagonalQuestion> for Case {
    fn from(question: SharedDiagonalQuestion) -> Case {
        let square = [
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::new(1.0, 0.0, 2.0),
            Vec3::new(1.0, 1.0, 2.0),
            Vec3::new(0.0, 1.0, 2.0),
        ];
        let turned = |i: usize| square[(i + 2) % 4];
        let direction = if question.ray_from_z > 2.0 {
            -Vec3::Z
        } else {
            Vec3::Z
        };
        Case::from(TrianglesQuestion {
            name: question.name,
            section: WATERTIGHT_10,
            says: question.says,
            triangles: vec![
                question.first_triangle.map(|i| square[i]),
                question.first_triangle.map(turned),
            ],
            ray: (Vec3::new(0.5, 0.5, question.ray_from_z), direction),
            range: IN_FRONT,
            expect: Expect::Hit,
        })
    }
}

/// Vertex normals all tilted toward +x, 37 degrees from the face's
/// (0, 0, 1): wherever it is hit, the blended normal is (0.6, 0, 0.8).
const TILTED_NORMALS: [Vec3; 3] = [Vec3::new(0.6, 0.0, 0.8); 3];

/// The lesson's floor triangle (object 0, given the vertex normals of each
/// case: `material` is its TOML material), hit at (0.25, 0.25, 0).
/// Around it, a ball in each direction its mirror or glass sends a ray
/// when it follows the blended normal (0.6, 0, 0.8), and none where the
/// facet's normal would send it: a red one toward (0.96, 0, 0.28) (the
/// mirror image of a ray straight down, and of a grazing one about the
/// facet), a blue one toward (-0.96, 0, -0.28) (that of a ray straight up
/// from below) and a small green one toward (-0.22991, 0, -0.97321) (a ray
/// straight down into glass of index 1.5, bent about the blended normal),
/// and a yellow one toward (0.98, 0, -0.2) (the mirror image about the
/// facet of a ray leaving it from below along (0.98, 0, 0.2)).
/// Ambient light only: every colour is a sum of shares of the balls' own.
fn smooth_facet_scene(material: &str) -> String {
    format!(
        r#"
background = [0.55, 0.7, 0.9]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
[render]
max_depth = 5
min_contribution = 0.0
[[objects]]
name = "smooth facet"
triangle = {{ a = [0.0, 0.0, 0.0], b = [1.0, 0.0, 0.0], c = [0.0, 1.0, 0.0] }}
material = {material}
[[objects]]
name = "red ball"
sphere = {{ center = [9.85, 0.25, 2.8], radius = 2.0 }}
material = {{ color = [0.9, 0.1, 0.1], ambient = 1.0, diffuse = 0.0 }}
[[objects]]
name = "blue ball"
sphere = {{ center = [-9.35, 0.25, -2.8], radius = 2.0 }}
material = {{ color = [0.1, 0.1, 0.9], ambient = 1.0, diffuse = 0.0 }}
[[objects]]
name = "green ball"
sphere = {{ center = [-0.43973, 0.25, -2.91964], radius = 0.3 }}
material = {{ color = [0.1, 0.9, 0.1], ambient = 1.0, diffuse = 0.0 }}
[[objects]]
name = "yellow ball"
sphere = {{ center = [9.86, 0.25, -1.96], radius = 1.5 }}
material = {{ color = [0.9, 0.9, 0.1], ambient = 1.0, diffuse = 0.0 }}
"#
    )
}

/// The smooth facet as a half-silvered mirror: k_r = 0.5, its own grey 0.4
/// lit by ambient light.
const SMOOTH_MIRROR: &str =
    "{ color = [0.4, 0.4, 0.4], ambient = 1.0, diffuse = 0.0, reflectivity = 0.5 }";

/// The smooth facet as clear glass of index 1.5, exact Fresnel.
const SMOOTH_GLASS: &str = "{ color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, \
                            transparency = 1.0, ior = 1.5, fresnel = \"exact\" }";

/// The smooth facet as glass of index 1.02, barely denser than air: a ray
/// leaving it at 74 degrees from the facet's normal is not totally
/// reflected (the critical angle is 78.6 degrees).
const THIN_SMOOTH_GLASS: &str = "{ color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, \
                                 transparency = 1.0, ior = 1.02, fresnel = \"exact\" }";

/// A grazing ray toward +x that meets the smooth facet at (0.25, 0.25, 0):
/// its blended normal (0.6, 0, 0.8) faces away from it.
const GRAZING_DIR: Vec3 = Vec3::new(1.0, 0.0, -0.2);

/// A `shade_mirror` or `shade_dielectric` question on the smooth facet at
/// chapter 10's stage.
fn smooth_shade(
    name: &'static str,
    says: &'static str,
    shading: Shading,
    material: &str,
    ray: Ray,
) -> Case {
    Case::new(
        name,
        SMOOTH_10,
        says,
        CaseKind::Shade(ShadeCase {
            shading,
            scene: smooth_facet_scene(material),
            ray,
            depth: 0,
            vertex_normals: Some(TILTED_NORMALS),
        }),
    )
}

/// Where the image differs when every checkpoint passes: what to look at
/// in the heatmap.
pub const IMAGE_HINT: &str = "on the meshes: a ray through a shared edge must hit one of its triangles, and the smooth normal is the vertex normals weighted by the barycentric coordinates";

/// Chapter 10's checkpoint cases. The first two are the ones the lesson's
/// "Your turn" paragraph promises.
///
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn checkpoints() -> Vec<Case> {
    let up = (Vec3::new(0.25, 0.25, 0.0), Vec3::Z);
    vec![
        Case::from(TrianglesQuestion {
            name: "triangle-hit-from-behind",
            section: HIT_10,
            says: "the lesson's triangle (0, 0, 2), (1, 0, 2), (0, 1, 2) and a ray from \
                   (0.25, 0.25, 0) along +z: it meets the plane z = 2 at (0.25, 0.25, 2), inside \
                   (beta = gamma = 0.25): expected t = 2. By the winding a -> b -> c the normal is \
                   +z, away from the ray: the ray meets the triangle's back, and a triangle is \
                   two-sided",
            triangles: vec![LESSON_TRIANGLE],
            ray: up,
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::new(
            "barycentric-lesson-point",
            BARYCENTRIC_10,
            "the lesson's triangle and that hit point (0.25, 0.25, 2): p - a = 0.25 e1 + 0.25 e2, \
             so beta = gamma = 0.25 and alpha = 1 - 0.25 - 0.25: expected (0.5, 0.25, 0.25)",
            CaseKind::Barycentric(BarycentricCase {
                corners: LESSON_TRIANGLE,
                point: Vec3::new(0.25, 0.25, 2.0),
            }),
        ),
        Case::from(TrianglesQuestion {
            name: "triangle-hit-from-the-front",
            section: HIT_10,
            says: "the lesson's triangle and a ray from (0.25, 0.25, 5) along -z, on the side its \
                   normal points to: expected t = 5 - 2 = 3",
            triangles: vec![LESSON_TRIANGLE],
            ray: (Vec3::new(0.25, 0.25, 5.0), -Vec3::Z),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-miss-beyond-bc",
            section: HIT_10,
            says: "a ray from (0.75, 0.75, 0) along +z meets the plane z = 2 past the long edge \
                   (beta + gamma = 1.5 > 1): expected no hit",
            triangles: vec![LESSON_TRIANGLE],
            ray: (Vec3::new(0.75, 0.75, 0.0), Vec3::Z),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-miss-beyond-ca",
            section: HIT_10,
            says: "a ray from (-0.25, 0.5, 0) along +z meets the plane left of the edge x = 0 \
                   (beta = -0.25): expected no hit",
            triangles: vec![LESSON_TRIANGLE],
            ray: (Vec3::new(-0.25, 0.5, 0.0), Vec3::Z),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-miss-beyond-ab",
            section: HIT_10,
            says: "a ray from (0.5, -0.25, 0) along +z meets the plane below the edge y = 0 \
                   (gamma = -0.25): expected no hit",
            triangles: vec![LESSON_TRIANGLE],
            ray: (Vec3::new(0.5, -0.25, 0.0), Vec3::Z),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-direction-not-unit",
            section: HIT_10,
            says: "a ray from the origin along (0.5, 0.5, 4), not unit: z reaches 2 at t = 2 / 4, \
                   at the point (0.25, 0.25, 2), inside: expected t = 0.5 \
                   (in units of the direction)",
            triangles: vec![LESSON_TRIANGLE],
            ray: (Vec3::ZERO, Vec3::new(0.5, 0.5, 4.0)),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-along-x",
            section: HIT_10,
            says: "the triangle (2, 0, 0), (2, 1, 0), (2, 0, 1) in the plane x = 2 and a ray from \
                   (0, 0.25, 0.25) along +x (the ray's largest component is x, not z): expected t \
                   = 2",
            triangles: vec![[
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(2.0, 1.0, 0.0),
                Vec3::new(2.0, 0.0, 1.0),
            ]],
            ray: (Vec3::new(0.0, 0.25, 0.25), Vec3::X),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-along-minus-y",
            section: HIT_10,
            says: "the triangle (0, -3, 0), (1, -3, 0), (0, -3, 1) in the plane y = -3 and a ray \
                   from (0.25, 0, 0.25) along (0, -2, 0): 3 units away at 2 per unit of t: \
                   expected t = 1.5",
            triangles: vec![[
                Vec3::new(0.0, -3.0, 0.0),
                Vec3::new(1.0, -3.0, 0.0),
                Vec3::new(0.0, -3.0, 1.0),
            ]],
            ray: (Vec3::new(0.25, 0.0, 0.25), Vec3::new(0.0, -2.0, 0.0)),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-before-t-min",
            section: HIT_10,
            says: "the first case's ray with t_min = 2.5: the only hit, t = 2, is before it: \
                   expected no hit",
            triangles: vec![LESSON_TRIANGLE],
            ray: up,
            range: (2.5, INF),
            expect: Expect::Miss,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-beyond-t-max",
            section: HIT_10,
            says: "the first case's ray with t_max = 1.5 (a shadow ray that stops at its light): \
                   the hit at t = 2 is beyond it: expected no hit",
            triangles: vec![LESSON_TRIANGLE],
            ray: up,
            range: (0.0, 1.5),
            expect: Expect::Miss,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-parallel-ray",
            section: HIT_10,
            says: "a ray from (0.25, 0.25, 0) along +x, parallel to the plane z = 2: it never \
                   reaches it: expected no hit (and no division by zero)",
            triangles: vec![LESSON_TRIANGLE],
            ray: (Vec3::new(0.25, 0.25, 0.0), Vec3::X),
            range: IN_FRONT,
            expect: Expect::Miss,
        })
        .fixed("a ray exactly in the triangle's plane"),
        Case::from(TrianglesQuestion {
            name: "triangle-shared-edge",
            section: LEAK_10,
            says: "the lesson's triangle and its neighbour (1, 0, 2), (1, 1, 2), (0, 1, 2) make \
                   the unit square at z = 2; a ray from (0.5, 0.5, 0) along +z goes through the \
                   middle of the diagonal they share: at least one of them must claim it: expected \
                   t = 2",
            triangles: vec![
                LESSON_TRIANGLE,
                [
                    Vec3::new(1.0, 0.0, 2.0),
                    Vec3::new(1.0, 1.0, 2.0),
                    Vec3::new(0.0, 1.0, 2.0),
                ],
            ],
            ray: (Vec3::new(0.5, 0.5, 0.0), Vec3::Z),
            range: IN_FRONT,
            expect: Expect::Hit,
        })
        .fixed("a ray exactly through a shared edge: moved, it passes within rounding of it, where only a watertight test is sure to hit (a hard case)"),
        Case::from(TrianglesQuestion {
            name: "triangle-shared-vertex",
            section: LEAK_10,
            says: "four triangles around the corner (0, 0, 2), one per quadrant of the plane z = 2 \
                   (their far corners are (1, 0, 2), (0, 1, 2), (-1, 0, 2), (0, -1, 2)); a ray \
                   from the origin along +z goes through that corner: at least one must claim it: \
                   expected t = 2",
            triangles: {
                let centre = Vec3::new(0.0, 0.0, 2.0);
                let rim = [
                    Vec3::new(1.0, 0.0, 2.0),
                    Vec3::new(0.0, 1.0, 2.0),
                    Vec3::new(-1.0, 0.0, 2.0),
                    Vec3::new(0.0, -1.0, 2.0),
                ];
                (0..4).map(|i| [centre, rim[i], rim[(i + 1) % 4]]).collect()
            },
            ray: (Vec3::ZERO, Vec3::Z),
            range: IN_FRONT,
            expect: Expect::Hit,
        })
        .fixed("a ray exactly through a shared corner"),
        // The unit square at z = 2 cut along its diagonal (1, 0, 2)-(0, 1, 2)
        // into two triangles wound the same way (normal +z), listed so that
        // the diagonal is the same edge of both: b -> c, c -> a or a -> b.
        // A ray exactly through it makes that edge's test exactly 0 in both
        // (the coordinates are exact in f32): only a test that counts 0 as
        // inside on every edge, from either side, claims it. (In
        // triangle-shared-edge above the diagonal is a different edge of each
        // triangle, which hides a test that is strict on one edge only.)
        Case::from(SharedDiagonalQuestion {
            name: "triangle-shared-diagonal-bc",
            says: "the unit square at z = 2 as the triangles (0, 0, 2), (1, 0, 2), (0, 1, 2) and \
                   (1, 1, 2), (0, 1, 2), (1, 0, 2), the diagonal their edge b -> c in both; a ray \
                   from (0.5, 0.5, 5) along -z, from the side the normals face, through the middle \
                   of the diagonal: at least one must claim it: expected t = 3",
            first_triangle: [0, 1, 3],
            ray_from_z: 5.0,
        })
        .fixed("a ray exactly through a shared edge"),
        Case::from(SharedDiagonalQuestion {
            name: "triangle-shared-diagonal-bc-from-behind",
            says: "the same two triangles and the ray from (0.5, 0.5, 0) along +z, from behind: \
                   expected t = 2",
            first_triangle: [0, 1, 3],
            ray_from_z: 0.0,
        })
        .fixed("a ray exactly through a shared edge"),
        Case::from(SharedDiagonalQuestion {
            name: "triangle-shared-diagonal-ca",
            says: "the same square as the triangles (0, 1, 2), (0, 0, 2), (1, 0, 2) and (1, 0, 2), \
                   (1, 1, 2), (0, 1, 2), the diagonal their edge c -> a in both, and the ray from \
                   (0.5, 0.5, 5) along -z: expected t = 3",
            first_triangle: [3, 0, 1],
            ray_from_z: 5.0,
        })
        .fixed("a ray exactly through a shared edge"),
        Case::from(SharedDiagonalQuestion {
            name: "triangle-shared-diagonal-ab",
            says: "the same square as the triangles (1, 0, 2), (0, 1, 2), (0, 0, 2) and (0, 1, 2), \
                   (1, 0, 2), (1, 1, 2), the diagonal their edge a -> b in both, and the ray from \
                   (0.5, 0.5, 5) along -z: expected t = 3",
            first_triangle: [1, 3, 0],
            ray_from_z: 5.0,
        })
        .fixed("a ray exactly through a shared edge"),
        Case::from(TrianglesQuestion {
            name: "triangle-at-t-min",
            section: HIT_10,
            says: "the first case's ray with t_min = 2: the hit, at exactly t = 2, is not beyond \
                   t_min: expected no hit (as for planes and spheres)",
            triangles: vec![LESSON_TRIANGLE],
            ray: up,
            range: (2.0, INF),
            expect: Expect::Miss,
        })
        .fixed("the hit exactly at t_min"),
        Case::from(TrianglesQuestion {
            name: "triangle-at-t-max",
            section: HIT_10,
            says: "the first case's ray with t_max = 2: the hit, at exactly t = 2, is not before \
                   t_max: expected no hit",
            triangles: vec![LESSON_TRIANGLE],
            ray: up,
            range: (0.0, 2.0),
            expect: Expect::Miss,
        })
        .fixed("the hit exactly at t_max"),
        Case::new(
            "barycentric-corner-b",
            BARYCENTRIC_10,
            "the lesson's triangle at its corner b = (1, 0, 2): all of the weight on b: expected \
             (0, 1, 0)",
            CaseKind::Barycentric(BarycentricCase {
                corners: LESSON_TRIANGLE,
                point: LESSON_TRIANGLE[1],
            }),
        ),
        Case::new(
            "barycentric-corner-c",
            BARYCENTRIC_10,
            "the lesson's triangle at its corner c = (0, 1, 2): expected (0, 0, 1)",
            CaseKind::Barycentric(BarycentricCase {
                corners: LESSON_TRIANGLE,
                point: LESSON_TRIANGLE[2],
            }),
        ),
        Case::new(
            "barycentric-centroid",
            BARYCENTRIC_10,
            "the lesson's triangle at its centroid (1/3, 1/3, 2), the mean of the corners: \
             expected (1/3, 1/3, 1/3)",
            CaseKind::Barycentric(BarycentricCase {
                corners: LESSON_TRIANGLE,
                point: Vec3::new(1.0 / 3.0, 1.0 / 3.0, 2.0),
            }),
        ),
        Case::new(
            "barycentric-skewed-triangle",
            BARYCENTRIC_10,
            "the triangle (0, 0, 0), (2, 0, 0), (1, 2, 0), whose edges are not perpendicular \
             (e1.e2 = 2), at (1, 1, 0) = 0.25 a + 0.25 b + 0.5 c: expected (0.25, 0.25, 0.5)",
            CaseKind::Barycentric(BarycentricCase {
                corners: [
                    Vec3::ZERO,
                    Vec3::new(2.0, 0.0, 0.0),
                    Vec3::new(1.0, 2.0, 0.0),
                ],
                point: Vec3::new(1.0, 1.0, 0.0),
            }),
        ),
        Case::new(
            "smooth-normal-at-corner",
            SMOOTH_10,
            "the lesson's triangle with vertex normals (1, 0, 0), (0, 1, 0), (0, 0, 1), at its \
             corner b = (1, 0, 2): the weights are (0, 1, 0): expected b's normal (0, 1, 0)",
            CaseKind::SmoothNormal(SmoothNormalCase {
                corners: LESSON_TRIANGLE,
                normals: AXIS_NORMALS,
                point: LESSON_TRIANGLE[1],
            }),
        ),
        Case::new(
            "smooth-normal-centroid",
            SMOOTH_10,
            "the same normals at the centroid (1/3, 1/3, 2): the blend is (1/3, 1/3, 1/3), of \
             length 0.577, made unit again: expected (0.57735, 0.57735, 0.57735)",
            CaseKind::SmoothNormal(SmoothNormalCase {
                corners: LESSON_TRIANGLE,
                normals: AXIS_NORMALS,
                point: Vec3::new(1.0 / 3.0, 1.0 / 3.0, 2.0),
            }),
        ),
        Case::new(
            "smooth-normal-lesson-point",
            SMOOTH_10,
            "the same normals at (0.25, 0.25, 2), weights (0.5, 0.25, 0.25): the blend \
             (0.5, 0.25, 0.25) has length sqrt(0.375) = 0.61237: expected \
             (0.8165, 0.40825, 0.40825)",
            CaseKind::SmoothNormal(SmoothNormalCase {
                corners: LESSON_TRIANGLE,
                normals: AXIS_NORMALS,
                point: Vec3::new(0.25, 0.25, 2.0),
            }),
        ),
        Case::new(
            "terminator-flat-unchanged",
            TERMINATOR_10,
            "the triangle (0, 0, 0), (1, 0, 0), (0, 1, 0) with every vertex normal (0, 0, 1), at \
             (0.25, 0.25, 0): the point is on every corner's tangent plane (height 0): expected \
             the point itself",
            CaseKind::Terminator(TerminatorCase {
                corners: FLOOR_TRIANGLE,
                normals: [Vec3::Z; 3],
                point: Vec3::new(0.25, 0.25, 0.0),
            }),
        ),
        Case::new(
            "terminator-convex-lifted",
            TERMINATOR_10,
            "the same triangle and point with the normals of a bulge, (-0.6, 0, 0.8) at a and c, \
             (0.6, 0, 0.8) at b; weights (0.5, 0.25, 0.25). Heights above the corners' tangent \
             planes: a: (0.25, 0.25, 0).n_a = -0.15, b: (-0.75, 0.25, 0).n_b = -0.45, c: \
             (0.25, -0.75, 0).n_c = -0.15, all below: the point rises by 0.5 x 0.15 n_a + 0.25 x \
             0.45 n_b + 0.25 x 0.15 n_c = (0, 0, 0.18): expected (0.25, 0.25, 0.18)",
            CaseKind::Terminator(TerminatorCase {
                corners: FLOOR_TRIANGLE,
                normals: CONVEX_NORMALS,
                point: Vec3::new(0.25, 0.25, 0.0),
            }),
        ),
        Case::new(
            "terminator-concave-unchanged",
            TERMINATOR_10,
            "the same with the tilts reversed, a hollow: heights +0.15, +0.45, +0.15, the point is \
             above every tangent plane already: expected the point itself",
            CaseKind::Terminator(TerminatorCase {
                corners: FLOOR_TRIANGLE,
                normals: CONCAVE_NORMALS,
                point: Vec3::new(0.25, 0.25, 0.0),
            }),
        ),
        Case::new(
            "smooth-hit-convex",
            TERMINATOR_10,
            "the bulge of terminator-convex-lifted, opaque, hit by a ray from (0.25, 0.25, 5) \
             along -z at (0.25, 0.25, 0): expected the normal \
             normalize(0.5 n_a + 0.25 n_b + 0.25 n_c) = (-0.3, 0, 0.8) / 0.8544 = \
             (-0.35112, 0, 0.93633), and the point lifted to (0.25, 0.25, 0.18)",
            CaseKind::SmoothHit(SmoothHitCase {
                corners: FLOOR_TRIANGLE,
                normals: CONVEX_NORMALS,
                ray: Ray::new(Vec3::new(0.25, 0.25, 5.0), Vec3::new(0.0, 0.0, -1.0)),
                transparent: false,
            }),
        ),
        Case::new(
            "smooth-hit-from-below",
            TERMINATOR_10,
            "the same bulge hit from below, by a ray from (0.25, 0.25, -5) along +z: the vertex \
             normals face away from the ray, so they are turned first; from that side the bulge is \
             a hollow: expected the normal (0.35112, 0, -0.93633) and the point unchanged, \
             (0.25, 0.25, 0)",
            CaseKind::SmoothHit(SmoothHitCase {
                corners: FLOOR_TRIANGLE,
                normals: CONVEX_NORMALS,
                ray: Ray::new(Vec3::new(0.25, 0.25, -5.0), Vec3::new(0.0, 0.0, 1.0)),
                transparent: false,
            }),
        ),
        Case::new(
            "smooth-hit-transparent",
            TERMINATOR_10,
            "the bulge of smooth-hit-convex, fully transparent: the smooth normal \
             (-0.35112, 0, 0.93633), but the point stays on the triangle, (0.25, 0.25, 0): the \
             refracted ray must start below the surface, not above it",
            CaseKind::SmoothHit(SmoothHitCase {
                corners: FLOOR_TRIANGLE,
                normals: CONVEX_NORMALS,
                ray: Ray::new(Vec3::new(0.25, 0.25, 5.0), Vec3::new(0.0, 0.0, -1.0)),
                transparent: true,
            }),
        ),
        Case::new(
            "smooth-hit-steep-normals-b",
            TERMINATOR_10,
            "the lesson's floor triangle with the vertex normals (0.96, 0, 0.28), (0, 0, 1), \
             (0, 0.96, 0.28) \
             (two of them 74 degrees from the face's, a coarse and strongly curved mesh), \
             transparent, hit at (0.25, 0.25, 0) by a ray from (0.25, 0.25, 5) along -z: their sum \
             (0.96, 0.96, 1.56) is on the ray's side, so they are kept; blended with the weights \
             (0.5, 0.25, 0.25): (0.48, 0.24, 0.46) / 0.70682 = (0.67909, 0.33955, 0.6508) \
             (the side is the sum's: with n_a - n_b + n_c, z = -0.44, they would be turned)",
            CaseKind::SmoothHit(SmoothHitCase {
                corners: FLOOR_TRIANGLE,
                normals: [
                    Vec3::new(0.96, 0.0, 0.28),
                    Vec3::Z,
                    Vec3::new(0.0, 0.96, 0.28),
                ],
                ray: Ray::new(Vec3::new(0.25, 0.25, 5.0), -Vec3::Z),
                transparent: true,
            }),
        ),
        Case::new(
            "smooth-hit-steep-normals-c",
            TERMINATOR_10,
            "the same with the vertex normals (0.96, 0, 0.28), (0, 0.96, 0.28), (0, 0, 1): the \
             same sum, kept, the same blend (0.67909, 0.33955, 0.6508) \
             (with n_a + n_b - n_c, z = -0.44, they would be turned)",
            CaseKind::SmoothHit(SmoothHitCase {
                corners: FLOOR_TRIANGLE,
                normals: [
                    Vec3::new(0.96, 0.0, 0.28),
                    Vec3::new(0.0, 0.96, 0.28),
                    Vec3::Z,
                ],
                ray: Ray::new(Vec3::new(0.25, 0.25, 5.0), -Vec3::Z),
                transparent: true,
            }),
        ),
        smooth_shade(
            "smooth-mirror-shading-normal",
            "a ray from (0.25, 0.25, 5) straight down onto the smooth facet, a mirror with \
             k_r = 0.5 and its own grey 0.4: about the blended normal (0.6, 0, 0.8) it leaves \
             along (0, 0, -1) + 1.6 (0.6, 0, 0.8) = (0.96, 0, 0.28) (from the point lifted off \
             the terminator, (0.3175, 0.25, 0.09)) and sees the red ball, \
             not the sky straight up as about the facet's normal: expected \
             0.5 x 0.4 + 0.5 x (0.9, 0.1, 0.1) = (0.65, 0.25, 0.25)",
            Shading::Mirror,
            SMOOTH_MIRROR,
            Ray::new(Vec3::new(0.25, 0.25, 5.0), -Vec3::Z),
        ),
        smooth_shade(
            "smooth-mirror-from-below",
            "the same mirror hit from below, by a ray from (0.25, 0.25, -5) straight up: the \
             blended normal is turned toward the ray, (-0.6, 0, -0.8), and the ray leaves \
             along (-0.96, 0, -0.28), below the facet, toward the blue ball: expected \
             0.5 x 0.4 + 0.5 x (0.1, 0.1, 0.9) = (0.25, 0.25, 0.65)",
            Shading::Mirror,
            SMOOTH_MIRROR,
            Ray::new(Vec3::new(0.25, 0.25, -5.0), Vec3::Z),
        ),
        smooth_shade(
            "smooth-mirror-grazing-falls-back",
            "a grazing ray along (1, 0, -0.2) meets the same mirror at (0.25, 0.25, 0): its \
             mirror image about the blended normal, (0.472, 0, -0.904), would go below the \
             facet, so the facet's normal (0, 0, 1) is used: it leaves along (1, 0, 0.2) and \
             sees the red ball: expected (0.65, 0.25, 0.25)",
            Shading::Mirror,
            SMOOTH_MIRROR,
            Ray::new(Vec3::new(0.25, 0.25, 0.0) - 5.0 * GRAZING_DIR, GRAZING_DIR),
        ),
        smooth_shade(
            "smooth-glass-shading-normal",
            "a ray from (0.25, 0.25, 5) straight down into the smooth facet, clear glass of \
             index 1.5: about the blended normal (cos i = 0.8) it bends to \
             (0, 0, -1) / 1.5 + (0.8 / 1.5 - sqrt(0.84)) (0.6, 0, 0.8) = \
             (-0.22991, 0, -0.97321), toward the green ball, and the exact Fresnel share at \
             that cosine is reflected toward the red ball",
            Shading::Dielectric,
            SMOOTH_GLASS,
            Ray::new(Vec3::new(0.25, 0.25, 5.0), -Vec3::Z),
        ),
        smooth_shade(
            "smooth-glass-grazing-falls-back",
            "a grazing ray along (1, 0, -0.2) into the same glass: the blended normal faces away \
             from it, so the facet's normal is used for both directions and for Fresnel's \
             cosine: the reflected share leaves along (1, 0, 0.2) toward the red ball",
            Shading::Dielectric,
            SMOOTH_GLASS,
            Ray::new(Vec3::new(0.25, 0.25, 0.0) - 5.0 * GRAZING_DIR, GRAZING_DIR),
        ),
        smooth_shade(
            "smooth-glass-from-below",
            "the same glass hit from below, by a ray from (0.25, 0.25, -5) straight up: the \
             blended normal is turned toward the ray, (-0.6, 0, -0.8), the ray came from the \
             facet's back, and the reflected share leaves along (-0.96, 0, -0.28), below the \
             facet, toward the blue ball, while the rest bends into the glass above it",
            Shading::Dielectric,
            SMOOTH_GLASS,
            Ray::new(Vec3::new(0.25, 0.25, -5.0), Vec3::Z),
        ),
        smooth_shade(
            "smooth-glass-grazing-from-below-falls-back",
            "a ray along (-0.96, 0, 0.28) from below into the facet made of glass of index \
             1.02 (leaving it, so no total reflection at this angle): about the blended normal \
             its mirror image would go above the facet while the refracted ray goes above \
             too, so the facet's normal is used, turned toward the ray, (0, 0, -1), for both \
             directions and for Fresnel's cosine (0.28): the reflected share leaves along \
             (-0.96, 0, -0.28) toward the blue ball, the rest goes on above",
            Shading::Dielectric,
            THIN_SMOOTH_GLASS,
            Ray::new(
                Vec3::new(0.25, 0.25, 0.0) - 5.0 * Vec3::new(-0.96, 0.0, 0.28),
                Vec3::new(-0.96, 0.0, 0.28),
            ),
        ),
        smooth_shade(
            "smooth-glass-leaving-refracts-back-falls-back",
            "a ray along (0.98, 0, 0.2) from below, leaving the glass of index 1.5: about the \
             blended normal, turned toward it, (-0.6, 0, -0.8), its mirror image goes back \
             down, but the refracted ray bends back below the facet too, (0.857, 0, -0.518): \
             it would not leave, so the facet's normal is used, (0, 0, -1); at cos 0.2 the ray \
             is totally reflected, along (0.98, 0, -0.2), toward the yellow ball",
            Shading::Dielectric,
            SMOOTH_GLASS,
            Ray::new(
                Vec3::new(0.25, 0.25, 0.0) - 5.0 * Vec3::new(0.98, 0.0, 0.2),
                Vec3::new(0.98, 0.0, 0.2),
            ),
        ),
    ]
}

/// Chapter 10's hard cases: rays through the shared edges and corners of
/// closed meshes (where Moller-Trumbore leaks), huge and tiny triangles,
/// degenerate triangles and non-finite input.
///
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn robustness() -> Vec<Case> {
    // Found by trying edge midpoints of tetrahedra with coordinates in
    // tenths around the origin: along these, Moller-Trumbore in f32 misses
    // every face, the watertight test does not.
    let leaky_edge = [
        Vec3::new(1.8, 1.0, 0.4),
        Vec3::new(0.0, -0.4, -0.8),
        Vec3::new(-0.4, -1.4, 1.7),
        Vec3::new(0.0, 1.4, 1.2),
    ];
    let leaky_vertex = [
        Vec3::new(0.5, -1.2, 0.6),
        Vec3::new(0.7, -0.6, -1.9),
        Vec3::new(-0.2, 1.8, 0.0),
        Vec3::new(-1.8, -0.6, -0.8),
    ];
    let far = Vec3::splat(1e5);
    let tiny = [
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(1e-5, 0.0, 1.0),
        Vec3::new(0.0, 1e-5, 1.0),
    ];
    let up = (Vec3::new(0.25, 0.25, 0.0), Vec3::Z);
    robust(vec![
        // The property itself, not one formula's failures: whatever the
        // test, no ray from inside a closed mesh gets out. Moller-Trumbore
        // lets 85 of these 2,016 through (`raylab cost --chapter 10 --knob
        // triangle-test` counts them), and so does a Cramer's-rule test
        // (gallery.rs).
        Case::new(
            "triangle-closed-mesh-nothing-escapes",
            WATERTIGHT_10,
            "raylab's generated closed model (a lumpy torus, 1,008 triangles) and 2,016 rays \
             from its core circle, each at a vertex or the midpoint of an edge, where two or \
             more triangles meet and rounding decides which one claims the ray: from inside a \
             closed mesh every ray hits a triangle",
            CaseKind::ClosedMesh(ClosedMeshCase {
                triangles: 1008,
                motion: None,
            }),
        ),
        Case::from(TrianglesQuestion {
            name: "triangle-closed-mesh-edge",
            section: WATERTIGHT_10,
            says: "a closed tetrahedron (1.8, 1, 0.4), (0, -0.4, -0.8), (-0.4, -1.4, 1.7), \
                   (0, 1.4, 1.2) around the origin, and a ray from the origin along \
                   (0.9, 0.3, -0.2), to the middle of the edge the first two corners share: from \
                   inside a closed mesh every ray hits something: expected t = 1 \
                   (Moller-Trumbore in f32 lets this one through both triangles of the edge)",
            triangles: tetrahedron(leaky_edge),
            ray: (Vec3::ZERO, 0.5 * (leaky_edge[0] + leaky_edge[1])),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-closed-mesh-vertex",
            section: WATERTIGHT_10,
            says: "a closed tetrahedron (0.5, -1.2, 0.6), (0.7, -0.6, -1.9), (-0.2, 1.8, 0), \
                   (-1.8, -0.6, -0.8) around the origin, and a ray from the origin straight at its \
                   first corner: one of the three faces there must claim it: expected t = 1",
            triangles: tetrahedron(leaky_vertex),
            ray: (Vec3::ZERO, leaky_vertex[0]),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-huge-coordinates-edge",
            section: WATERTIGHT_10,
            says: "the first tetrahedron moved by (1e5, 1e5, 1e5) \
                   (its corners rounded to f32, 1/128 apart there, shared exactly), and the same \
                   ray from (1e5, 1e5, 1e5): still closed, still hit, near t = 1",
            triangles: tetrahedron(leaky_edge.map(|corner| corner + far)),
            ray: (far, 0.5 * (leaky_edge[0] + leaky_edge[1])),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-far-and-huge",
            section: HIT_10,
            says: "the triangle (1e5, 0, 1e5), (0, 1e5, 1e5), (0, 0, 1e5) and a ray from the \
                   origin along (0.25, 0.25, 1): expected t = 1e5",
            triangles: vec![[
                Vec3::new(1e5, 0.0, 1e5),
                Vec3::new(0.0, 1e5, 1e5),
                Vec3::new(0.0, 0.0, 1e5),
            ]],
            ray: (Vec3::ZERO, Vec3::new(0.25, 0.25, 1.0)),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-tiny-hit",
            section: HIT_10,
            says: "a triangle of side 1e-5, (0, 0, 1), (1e-5, 0, 1), (0, 1e-5, 1), and a ray from \
                   (2.5e-6, 2.5e-6, 0) along +z \
                   (its area is 5e-11: no absolute epsilon may swallow it): expected t = 1",
            triangles: vec![tiny],
            ray: (Vec3::new(2.5e-6, 2.5e-6, 0.0), Vec3::Z),
            range: IN_FRONT,
            expect: Expect::Hit,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-tiny-miss",
            section: HIT_10,
            says: "the same tiny triangle and a ray from (7.5e-6, 7.5e-6, 0) along +z, past its \
                   long edge: expected no hit",
            triangles: vec![tiny],
            ray: (Vec3::new(7.5e-6, 7.5e-6, 0.0), Vec3::Z),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-degenerate-line",
            section: WATERTIGHT_10,
            says: "a zero-area triangle (0, 0, 2), (1, 0, 2), (2, 0, 2), its corners on a line, \
                   and a ray from (0.5, 0, 0) along +z straight through that line: expected no hit \
                   (and no NaN)",
            triangles: vec![[
                Vec3::new(0.0, 0.0, 2.0),
                Vec3::new(1.0, 0.0, 2.0),
                Vec3::new(2.0, 0.0, 2.0),
            ]],
            ray: (Vec3::new(0.5, 0.0, 0.0), Vec3::Z),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-degenerate-point",
            section: WATERTIGHT_10,
            says: "a triangle whose three corners are the point (1, 1, 2), and a ray from \
                   (1, 1, 0) along +z through it: expected no hit (and no NaN)",
            triangles: vec![[Vec3::new(1.0, 1.0, 2.0); 3]],
            ray: (Vec3::new(1.0, 1.0, 0.0), Vec3::Z),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-edge-on",
            section: HIT_10,
            says: "a ray from (-1, 0.25, 2) along +x, inside the lesson triangle's own plane: the \
                   triangle is seen edge-on; either no hit or a hit on the triangle's plane",
            triangles: vec![LESSON_TRIANGLE],
            ray: (Vec3::new(-1.0, 0.25, 2.0), Vec3::X),
            range: IN_FRONT,
            expect: Expect::Either,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-nan-origin",
            section: HIT_10,
            says: "the first case with a NaN origin: expected no hit",
            triangles: vec![LESSON_TRIANGLE],
            ray: (Vec3::NAN, Vec3::Z),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-nan-direction",
            section: HIT_10,
            says: "the first case with a NaN direction: expected no hit",
            triangles: vec![LESSON_TRIANGLE],
            ray: (Vec3::new(0.25, 0.25, 0.0), Vec3::NAN),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-zero-direction",
            section: HIT_10,
            says: "the first case with the direction (0, 0, 0), a ray that goes nowhere: expected \
                   no hit",
            triangles: vec![LESSON_TRIANGLE],
            ray: (Vec3::new(0.25, 0.25, 0.0), Vec3::ZERO),
            range: IN_FRONT,
            expect: Expect::Miss,
        }),
        Case::from(TrianglesQuestion {
            name: "triangle-nan-t-max",
            section: HIT_10,
            says: "the first case with t_max = NaN: no t is below it: expected no hit",
            triangles: vec![LESSON_TRIANGLE],
            ray: up,
            range: (0.0, f32::NAN),
            expect: Expect::Miss,
        }),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_expected_triangle_hit_has_an_exact_value() {
        for case in checkpoints().into_iter().chain(robustness()) {
            if let CaseKind::Triangles(TrianglesCase {
                expect: ExpectT::Hit(t),
                ..
            }) = case.kind
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
            wide(Vec3::new(0.25, 0.25, 0.0)),
        );
        assert!((lifted - glam::DVec3::new(0.25, 0.25, 0.18)).length() < 1e-7);
        let weights =
            exact::barycentric(LESSON_TRIANGLE.map(wide), wide(Vec3::new(0.25, 0.25, 2.0)));
        assert!((weights - glam::DVec3::new(0.5, 0.25, 0.25)).length() < 1e-12);
        let skewed = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
        ]
        .map(wide);
        let weights = exact::barycentric(skewed, glam::DVec3::new(1.0, 1.0, 0.0));
        assert!((weights - glam::DVec3::new(0.25, 0.25, 0.5)).length() < 1e-12);
    }
}
