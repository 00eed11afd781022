//! Chapter 10's bug gallery: the classic mistakes of triangle meshes, each
//! planted in one function of the reference, each asserted to fail chapter
//! 10 on the case that names it; and the correct alternatives that must
//! pass, Moller-Trumbore first ("correct, not yet robust").

use glam::Vec2;
use raylab::chapters::CHAPTERS;
use raylab::check::planted::{self, Plant, Planted, plant};
use raylab::check::{ChapterVerdict, CheckOptions, Level, check_chapter};
use raylab::course::{Chapters, HitPoint, Textbook};
use raylab::render::{RayKind, Tracer};
use raylab::shapes::Triangle;
use raylab::{Ray, Reference, Vec3};

const CHAPTER: u8 = 10;

fn options() -> CheckOptions {
    CheckOptions {
        failures_dir: std::env::temp_dir().join("raylab-chapter-10-tests"),
        write_images: false,
        forbid_answer_key: false,
        fresh: None,
        ..Default::default()
    }
}

/// Checks chapter 10 with `C` and asserts that it fails on case `case`,
/// with the earlier chapters (the reference's) not to blame.
fn assert_caught<C: Plant>(case: &str) -> ChapterVerdict {
    planted::assert_caught::<C>(CHAPTER, case, &options())
}

/// The reference's Moller-Trumbore with the inside test written by the
/// caller: `inside(beta, gamma)`.
fn moller_trumbore(
    triangle: &Triangle,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    cull_back_faces: bool,
    inside: impl Fn(f32, f32) -> bool,
) -> Option<f32> {
    let [a, b, c] = triangle.corners();
    let (edge_1, edge_2) = (b - a, c - a);
    let p = ray.dir.cross(edge_2);
    let determinant = edge_1.dot(p);
    // The textbook's culling test: a negative determinant is a ray
    // travelling along the winding's normal, meeting the back.
    let rejected = if cull_back_faces {
        determinant.is_nan() || determinant <= 1e-8
    } else {
        !(determinant != 0.0)
    };
    if rejected {
        return None;
    }
    let s = ray.origin - a;
    let q = s.cross(edge_1);
    let beta = s.dot(p) / determinant;
    let gamma = ray.dir.dot(q) / determinant;
    if !inside(beta, gamma) {
        return None;
    }
    let t = edge_2.dot(q) / determinant;
    (t > t_min && t < t_max).then_some(t)
}

fn inclusive(beta: f32, gamma: f32) -> bool {
    beta >= 0.0 && gamma >= 0.0 && beta + gamma <= 1.0
}

// ---------------------------------------------------------------------------
// The bug gallery.

/// A one-sided test: Moller-Trumbore with back faces culled, as renderers
/// of closed opaque models do for speed. The lesson's first ray meets its
/// triangle's back.
struct BackFaceCulled;
plant! {
    BackFaceCulled;
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        moller_trumbore(triangle, ray, t_min, t_max, true, inclusive)
    }
}

#[test]
fn gallery_one_sided_triangle() {
    assert_caught::<BackFaceCulled>("triangle-hit-from-behind");
}

/// Edges excluded (`beta > 0`, `beta + gamma < 1`): each triangle leaves its
/// boundary to the neighbour, which leaves it too.
struct StrictEdges;
plant! {
    StrictEdges;
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        moller_trumbore(triangle, ray, t_min, t_max, false, |beta, gamma| {
            beta > 0.0 && gamma > 0.0 && beta + gamma < 1.0
        })
    }
}

#[test]
fn gallery_edges_belong_to_no_triangle() {
    assert_caught::<StrictEdges>("triangle-shared-edge");
}

/// The interval's lower end ignored (`t > 0` instead of `t > t_min`).
struct IgnoresTMin;
plant! {
    IgnoresTMin;
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, _t_min: f32, t_max: f32) -> Option<f32> {
        Reference::intersect_triangle(triangle, ray, 0.0, t_max)
    }
}

#[test]
fn gallery_triangle_ignoring_t_min() {
    assert_caught::<IgnoresTMin>("triangle-before-t-min");
}

/// Barycentric coordinates with beta and gamma swapped: symmetric points
/// (the lesson's, the centroid) cannot tell, a corner can.
struct BarycentricSwapped;
plant! {
    BarycentricSwapped;
    fn barycentric(triangle: &Triangle, point: Vec3) -> Vec3 {
        let weights = Reference::barycentric(triangle, point);
        Vec3::new(weights.x, weights.z, weights.y)
    }
}

#[test]
fn gallery_barycentric_beta_and_gamma_swapped() {
    assert_caught::<BarycentricSwapped>("barycentric-corner-b");
}

/// The blend of the vertex normals not made unit again: right at a corner,
/// too short everywhere between.
struct NormalNotRenormalised;
plant! {
    NormalNotRenormalised;
    fn smooth_normal(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3) -> Vec3 {
        let w = Planted::barycentric(triangle, point);
        w.x * normals[0] + w.y * normals[1] + w.z * normals[2]
    }
}

#[test]
fn gallery_smooth_normal_not_renormalised() {
    assert_caught::<NormalNotRenormalised>("smooth-normal-centroid");
}

/// Hanika's lift with its sign wrong: the point is pushed down, further
/// below the neighbours, instead of up onto the curved surface.
struct TerminatorSignError;
plant! {
    TerminatorSignError;
    fn terminator_point(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3) -> Vec3 {
        let weights = Planted::barycentric(triangle, point).to_array();
        let mut moved = point;
        for ((corner, normal), weight) in triangle.corners().iter().zip(normals).zip(weights) {
            let height = (point - *corner).dot(*normal);
            if height < 0.0 {
                moved += weight * height * *normal;
            }
        }
        moved
    }
}

#[test]
fn gallery_terminator_moves_points_down() {
    assert_caught::<TerminatorSignError>("terminator-convex-lifted");
}

/// `smooth_hit_point` that uses the vertex normals as given, without
/// turning them to the side the ray arrived on.
struct NormalsNotTurned;
plant! {
    NormalsNotTurned;
    fn smooth_hit_point<'a>(
        point: HitPoint<'a>,
        triangle: &Triangle,
        normals: &[Vec3; 3],
    ) -> HitPoint<'a> {
        let mut smooth = point;
        smooth.normal = Planted::smooth_normal(triangle, normals, point.surface.point);
        smooth.surface.point = Planted::terminator_point(triangle, normals, point.surface.point);
        smooth
    }
}

#[test]
fn gallery_vertex_normals_not_turned_toward_the_ray() {
    assert_caught::<NormalsNotTurned>("smooth-hit-from-below");
}

/// `smooth_hit_point` that lifts the point of a transparent surface too:
/// its refracted ray would start above the surface it has to cross.
struct LiftsGlass;
plant! {
    LiftsGlass;
    fn smooth_hit_point<'a>(
        point: HitPoint<'a>,
        triangle: &Triangle,
        normals: &[Vec3; 3],
    ) -> HitPoint<'a> {
        let outward = normals[0] + normals[1] + normals[2];
        let side = if outward.dot(point.normal) < 0.0 {
            -1.0
        } else {
            1.0
        };
        let facing = normals.map(|normal| side * normal);
        let mut smooth = point;
        smooth.normal = Planted::smooth_normal(triangle, &facing, point.surface.point);
        smooth.surface.point = Planted::terminator_point(triangle, &facing, point.surface.point);
        smooth
    }
}

#[test]
fn gallery_transparent_points_lifted() {
    assert_caught::<LiftsGlass>("smooth-hit-transparent");
}

// ---------------------------------------------------------------------------
// The contract, clause by clause: each variant breaks one sentence of the
// lesson or of a doc comment, and fails on the case that asks it.

/// Asserts that `C` passes chapter 10's checkpoints and fails its hard
/// case `case` first: a clause only rounding or degenerate input can show.
fn assert_caught_by_hard_case<C: Plant>(case: &str) {
    planted::assert_caught_by_hard_case::<C>(CHAPTER, case, &options());
}

/// One sentence of the watertight test broken, by [`watertight`].
#[derive(Clone, Copy, PartialEq, Debug)]
enum Slip {
    /// None: the reference's test, operation for operation.
    None,
    /// Edge `e` (0 for b c, 1 for c a, 2 for a b) left out of the inside
    /// test.
    EdgeUnchecked(usize),
    /// A zero on edge `e` counted outside: a ray exactly on that edge
    /// belongs to neither triangle that shares it.
    EdgeStrict(usize),
    /// A zero counted outside from behind (the other edge functions
    /// negative) only.
    StrictFromBehind,
    /// The shear always along z, whichever axis the ray moves fastest
    /// along.
    AlwaysAlongZ,
    /// `t` as corner a's height alone, not the heights blended by the
    /// edge functions.
    HeightOfTheFirstCorner,
    /// `t` in units of length: the direction made unit first.
    UnitDirection,
    /// `t >= t_min`.
    TMinIncluded,
    /// `t <= t_max`.
    TMaxIncluded,
    /// No upper end to the interval.
    TMaxIgnored,
    /// The interval tested as `!(t <= t_min || t >= t_max)`, which a NaN
    /// `t` passes.
    NanPassesTheRange,
    /// A determinant below an absolute `1e-9` taken for an edge-on
    /// triangle.
    AbsoluteEpsilon,
    /// Edge c a's line of the `f64` recomputation with its corners the
    /// other way round, `cross(c, a)`: `-v`. The `f32` line is right, so
    /// only a ray with an edge function exactly 0 takes this path.
    RecomputedCaBackwards,
}

/// Chapter 10's watertight test as the reference writes it, with `slip`.
fn watertight(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32, slip: Slip) -> Option<f32> {
    let ray = if slip == Slip::UnitDirection {
        Ray::new(ray.origin, ray.dir.normalize())
    } else {
        *ray
    };
    let dir = ray.dir.to_array();
    let z = if slip == Slip::AlwaysAlongZ {
        2
    } else {
        ray.dir.abs().max_position()
    };
    let (mut x, mut y) = ((z + 1) % 3, (z + 2) % 3);
    if dir[z] < 0.0 {
        std::mem::swap(&mut x, &mut y);
    }
    let (shear_x, shear_y, scale_z) = (dir[x] / dir[z], dir[y] / dir[z], 1.0 / dir[z]);
    let [a, b, c] = triangle
        .corners()
        .map(|corner| (corner - ray.origin).to_array());
    let sheared = |p: [f32; 3]| (p[x] - shear_x * p[z], p[y] - shear_y * p[z]);
    let ((ax, ay), (bx, by), (cx, cy)) = (sheared(a), sheared(b), sheared(c));
    let mut edges = [cx * by - cy * bx, ax * cy - ay * cx, bx * ay - by * ax];
    if edges.contains(&0.0) {
        let cross = |px: f32, py: f32, qx: f32, qy: f32| {
            (f64::from(px) * f64::from(qy) - f64::from(py) * f64::from(qx)) as f32
        };
        edges = [
            cross(cx, cy, bx, by),
            if slip == Slip::RecomputedCaBackwards {
                cross(cx, cy, ax, ay)
            } else {
                cross(ax, ay, cx, cy)
            },
            cross(bx, by, ax, ay),
        ];
    }
    let asked = |edge: usize| slip != Slip::EdgeUnchecked(edge);
    let negative = (0..3).any(|edge| asked(edge) && edges[edge] < 0.0);
    let positive = (0..3).any(|edge| asked(edge) && edges[edge] > 0.0);
    let on_an_edge = edges.contains(&0.0);
    let outside = (negative && positive)
        || matches!(slip, Slip::EdgeStrict(edge) if edges[edge] == 0.0)
        || (slip == Slip::StrictFromBehind && negative && on_an_edge);
    if outside {
        return None;
    }
    let [u, v, w] = edges;
    let determinant = u + v + w;
    let edge_on = if slip == Slip::AbsoluteEpsilon {
        !(determinant.abs() > 1e-9)
    } else {
        !(determinant != 0.0)
    };
    if edge_on {
        return None;
    }
    let (az, bz, cz) = (scale_z * a[z], scale_z * b[z], scale_z * c[z]);
    let t = if slip == Slip::HeightOfTheFirstCorner {
        az
    } else {
        (u * az + v * bz + w * cz) / determinant
    };
    let within = match slip {
        Slip::TMinIncluded => t >= t_min && t < t_max,
        Slip::TMaxIncluded => t > t_min && t <= t_max,
        Slip::TMaxIgnored => t > t_min,
        Slip::NanPassesTheRange => !(t <= t_min || t >= t_max),
        _ => t > t_min && t < t_max,
    };
    within.then_some(t)
}

/// Variants of the reference, each with one [`Slip`] planted in its
/// triangle test.
macro_rules! slipped {
    ($($(#[$doc:meta])* $name:ident = $slip:expr;)*) => {$(
        $(#[$doc])*
        struct $name;
        plant! {
            $name;
            fn intersect_triangle(
                triangle: &Triangle,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<f32> {
                watertight(triangle, ray, t_min, t_max, $slip)
            }
        }
    )*};
}

slipped! {
    EdgeBcUnchecked = Slip::EdgeUnchecked(0);
    EdgeCaUnchecked = Slip::EdgeUnchecked(1);
    EdgeAbUnchecked = Slip::EdgeUnchecked(2);
    /// Only edge b c leaves its boundary out: the lesson's square cut
    /// along its diagonal, which is edge b c of both halves, leaks.
    EdgeBcStrict = Slip::EdgeStrict(0);
    EdgeCaStrict = Slip::EdgeStrict(1);
    EdgeAbStrict = Slip::EdgeStrict(2);
    StrictFromBehind = Slip::StrictFromBehind;
    AlwaysAlongZ = Slip::AlwaysAlongZ;
    HeightOfTheFirstCorner = Slip::HeightOfTheFirstCorner;
    UnitDirection = Slip::UnitDirection;
    TMinIncluded = Slip::TMinIncluded;
    TMaxIncluded = Slip::TMaxIncluded;
    TMaxIgnored = Slip::TMaxIgnored;
    NanPassesTheRange = Slip::NanPassesTheRange;
    AbsoluteEpsilon = Slip::AbsoluteEpsilon;
    /// A typo in the rarely run `f64` recomputation: edge c a written in
    /// the order of its name, `c'x a'y - c'y a'x`, which is `-v`.
    RecomputedCaBackwards = Slip::RecomputedCaBackwards;
}

#[test]
fn the_slipless_copy_is_the_reference_bit_for_bit() {
    let triangles = [
        Triangle::new(
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::X + 2.0 * Vec3::Z,
            Vec3::Y + 2.0 * Vec3::Z,
        ),
        Triangle::new(
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(2.0, 0.0, 3.0),
            Vec3::new(0.0, 2.0, 2.0),
        ),
        Triangle::new(
            Vec3::new(1.8, 1.0, 0.4),
            Vec3::new(0.0, -0.4, -0.8),
            Vec3::new(-0.4, -1.4, 1.7),
        ),
    ];
    let mut numbers = raylab::check::exact::Xorshift::new(10);
    for _ in 0..2000 {
        let origin = Vec3::new(
            numbers.between(-3.0, 3.0),
            numbers.between(-3.0, 3.0),
            numbers.between(-3.0, 3.0),
        );
        let aim = Vec3::new(
            numbers.between(-1.0, 2.0),
            numbers.between(-1.0, 2.0),
            numbers.between(0.0, 3.0),
        );
        let ray = Ray::new(origin, aim - origin);
        for triangle in &triangles {
            let copy = watertight(triangle, &ray, 0.0, f32::INFINITY, Slip::None);
            let reference = Reference::intersect_triangle(triangle, &ray, 0.0, f32::INFINITY);
            assert_eq!(
                copy.map(f32::to_bits),
                reference.map(f32::to_bits),
                "{ray:?}"
            );
        }
    }
}

#[test]
fn contract_each_edge_is_asked() {
    assert_caught::<EdgeBcUnchecked>("triangle-miss-beyond-bc");
    assert_caught::<EdgeCaUnchecked>("triangle-miss-beyond-ca");
    assert_caught::<EdgeAbUnchecked>("triangle-miss-beyond-ab");
}

#[test]
fn contract_every_edge_belongs_to_its_triangles() {
    assert_caught::<EdgeBcStrict>("triangle-shared-diagonal-bc");
    assert_caught::<EdgeCaStrict>("triangle-shared-vertex");
    assert_caught::<EdgeAbStrict>("triangle-shared-vertex");
    assert_caught::<StrictFromBehind>("triangle-shared-edge");
}

#[test]
fn contract_the_shear_runs_along_the_fastest_axis() {
    assert_caught::<AlwaysAlongZ>("triangle-along-x");
}

#[test]
fn contract_t_blends_the_corners_heights() {
    assert_caught::<HeightOfTheFirstCorner>("triangle-tilted");
}

#[test]
fn contract_t_counts_lengths_of_the_direction() {
    assert_caught::<UnitDirection>("triangle-direction-not-unit");
}

#[test]
fn contract_the_interval_is_open_at_both_ends() {
    assert_caught::<TMinIncluded>("triangle-at-t-min");
    assert_caught::<TMaxIncluded>("triangle-at-t-max");
    assert_caught::<TMaxIgnored>("triangle-beyond-t-max");
}

/// A ray parallel to the triangle's plane never reaches it. The
/// reference rejects it by the edge functions alone: they sum to the
/// determinant, 0, so unless all three are 0 their signs are mixed (and
/// `t` would be infinite). The lesson's parallel ray runs along edge a b,
/// whose corners shear onto the same point: `w` is exactly 0, the `f64`
/// recomputation runs, and with its `v` negated the edge functions
/// (2, 2, 0) agree, the determinant is 4, and the ray hits at `t = 0.25`.
#[test]
fn contract_a_parallel_ray_misses() {
    assert_caught::<RecomputedCaBackwards>("triangle-parallel-ray");
}

#[test]
fn contract_nan_and_degenerate_input_is_no_hit() {
    assert_caught_by_hard_case::<NanPassesTheRange>("triangle-nan-origin");
}

#[test]
fn contract_no_absolute_epsilon_swallows_a_tiny_triangle() {
    assert_caught_by_hard_case::<AbsoluteEpsilon>("triangle-tiny-hit");
}

/// Barycentric coordinates whose alpha has a sign slip, `1 - beta +
/// gamma`: right at the corners, where beta or gamma is 0 or 1 alone.
struct AlphaSignSlip;
plant! {
    AlphaSignSlip;
    fn barycentric(triangle: &Triangle, point: Vec3) -> Vec3 {
        let weights = Reference::barycentric(triangle, point);
        Vec3::new(1.0 - weights.y + weights.z, weights.y, weights.z)
    }
}

#[test]
fn contract_the_weights_sum_to_one() {
    assert_caught::<AlphaSignSlip>("barycentric-lesson-point");
}

/// Barycentric coordinates that take the edges for perpendicular (each
/// weight a projection on its own edge): right on the lesson's right
/// triangle, wrong on any other.
struct EdgesAssumedPerpendicular;
plant! {
    EdgesAssumedPerpendicular;
    fn barycentric(triangle: &Triangle, point: Vec3) -> Vec3 {
        let [a, b, c] = triangle.corners();
        let (e1, e2, to_point) = (b - a, c - a, point - a);
        let beta = to_point.dot(e1) / e1.dot(e1);
        let gamma = to_point.dot(e2) / e2.dot(e2);
        Vec3::new(1.0 - beta - gamma, beta, gamma)
    }
}

#[test]
fn contract_barycentric_of_a_skewed_triangle() {
    assert_caught::<EdgesAssumedPerpendicular>("barycentric-skewed-triangle");
}

/// The lesson's two equations solved on x and y only: right wherever the
/// triangle's shadow on the xy plane is a triangle, NaN on a wall.
struct BarycentricInXyOnly;
plant! {
    BarycentricInXyOnly;
    fn barycentric(triangle: &Triangle, point: Vec3) -> Vec3 {
        let [a, b, c] = triangle.corners().map(|corner| corner.truncate());
        let (e1, e2, to_point) = (b - a, c - a, point.truncate() - a);
        let flat = |u: Vec2, v: Vec2| u.dot(v);
        let (d11, d12, d22) = (flat(e1, e1), flat(e1, e2), flat(e2, e2));
        let (p1, p2) = (flat(to_point, e1), flat(to_point, e2));
        let denominator = d11 * d22 - d12 * d12;
        let beta = (d22 * p1 - d12 * p2) / denominator;
        let gamma = (d11 * p2 - d12 * p1) / denominator;
        Vec3::new(1.0 - beta - gamma, beta, gamma)
    }
}

#[test]
fn contract_barycentric_in_any_plane() {
    assert_caught::<BarycentricInXyOnly>("barycentric-in-a-wall");
}

/// The three vertex normals averaged with equal weights, wherever the
/// point is.
struct NormalsBlendedEqually;
plant! {
    NormalsBlendedEqually;
    fn smooth_normal(_triangle: &Triangle, normals: &[Vec3; 3], _point: Vec3) -> Vec3 {
        (normals[0] + normals[1] + normals[2]).normalize()
    }
}

#[test]
fn contract_the_normals_are_blended_by_the_weights() {
    assert_caught::<NormalsBlendedEqually>("smooth-normal-at-corner");
}

/// One sentence of Hanika's lift broken, by [`lift`].
#[derive(Clone, Copy, PartialEq)]
enum LiftSlip {
    /// The point pushed out along the blended normal by a fixed 1e-3, as
    /// an offset would, rather than projected.
    NudgedOut,
    /// The three projections blended with equal weights.
    EqualWeights,
    /// Projected onto every tangent plane, above it or below: Phong
    /// tessellation's projection, not kept only where it lifts.
    EveryPlane,
    /// Decided once for the triangle: onto every plane when the point is
    /// below any of them.
    WholeTriangle,
    /// Decided once for the triangle: onto every plane when the heights,
    /// weighted, add up to below 0.
    WeightedHeights,
}

/// Chapter 10's `terminator_point` with `slip`.
fn lift(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3, slip: LiftSlip) -> Vec3 {
    let weights = Reference::barycentric(triangle, point).to_array();
    let weights = if slip == LiftSlip::EqualWeights {
        [1.0 / 3.0; 3]
    } else {
        weights
    };
    let heights = triangle
        .corners()
        .iter()
        .zip(normals)
        .map(|(corner, normal)| (point - *corner).dot(*normal))
        .collect::<Vec<f32>>();
    if slip == LiftSlip::NudgedOut {
        let blended = weights[0] * normals[0] + weights[1] * normals[1] + weights[2] * normals[2];
        return point + 1e-3 * blended.normalize();
    }
    let whole = match slip {
        LiftSlip::EveryPlane => true,
        LiftSlip::WholeTriangle => heights.iter().any(|&height| height < 0.0),
        LiftSlip::WeightedHeights => {
            heights.iter().zip(weights).map(|(h, w)| h * w).sum::<f32>() < 0.0
        }
        _ => false,
    };
    let mut lifted = point;
    for ((normal, height), weight) in normals.iter().zip(&heights).zip(weights) {
        let moves = match slip {
            LiftSlip::WholeTriangle | LiftSlip::WeightedHeights => whole,
            LiftSlip::EveryPlane => true,
            _ => *height < 0.0,
        };
        if moves {
            lifted -= weight * height * *normal;
        }
    }
    lifted
}

macro_rules! lifted {
    ($($(#[$doc:meta])* $name:ident = $slip:expr;)*) => {$(
        $(#[$doc])*
        struct $name;
        plant! {
            $name;
            fn terminator_point(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3) -> Vec3 {
                lift(triangle, normals, point, $slip)
            }
        }
    )*};
}

lifted! {
    NudgedOut = LiftSlip::NudgedOut;
    LiftedWithEqualWeights = LiftSlip::EqualWeights;
    ProjectedOntoEveryPlane = LiftSlip::EveryPlane;
    LiftDecidedForTheWholeTriangle = LiftSlip::WholeTriangle;
    LiftDecidedByTheWeightedHeights = LiftSlip::WeightedHeights;
}

#[test]
fn contract_a_flat_facet_stays_where_it_is() {
    assert_caught::<NudgedOut>("terminator-flat-unchanged");
}

#[test]
fn contract_the_lifts_are_blended_by_the_weights() {
    assert_caught::<LiftedWithEqualWeights>("terminator-convex-lifted");
}

#[test]
fn contract_only_lifts_never_lowers() {
    assert_caught::<ProjectedOntoEveryPlane>("terminator-concave-unchanged");
}

#[test]
fn contract_each_corner_decides_its_own_lift() {
    assert_caught::<LiftDecidedForTheWholeTriangle>("terminator-mixed-heights");
    assert_caught::<LiftDecidedByTheWeightedHeights>("terminator-mixed-heights");
}

/// How a variant of `smooth_hit_point` turns the vertex normals toward
/// the ray.
#[derive(Clone, Copy, PartialEq)]
enum Turn {
    /// All three by one sign, their sum's: the reference.
    BySum,
    /// Each turned on its own, by its own side.
    EachOnItsOwn,
    /// All three by the first normal's side.
    ByTheFirst,
    /// All three by the winding: turned when the hit point's normal was
    /// turned from the triangle's own.
    ByTheWinding,
}

/// What a variant of `smooth_hit_point` does.
#[derive(Clone, Copy)]
struct SmoothRules {
    turn: Turn,
    /// The shading normal set to the blend (else the flat normal kept).
    blends: bool,
    /// The point lifted where the material is opaque.
    lifts: bool,
    /// The point lifted with the normals as given, not the turned ones.
    lifts_unturned: bool,
    /// Lifted unless the material is fully transparent (not unless it
    /// lets any light through).
    lifts_half_transparent: bool,
}

impl SmoothRules {
    const CORRECT: SmoothRules = SmoothRules {
        turn: Turn::BySum,
        blends: true,
        lifts: true,
        lifts_unturned: false,
        lifts_half_transparent: false,
    };
}

/// Chapter 10's `smooth_hit_point` as `rules` say.
fn smooth_hit<'a, C: Chapters>(
    point: HitPoint<'a>,
    triangle: &Triangle,
    normals: &[Vec3; 3],
    rules: SmoothRules,
) -> HitPoint<'a> {
    let side = |toward: Vec3| {
        if toward.dot(point.normal) < 0.0 {
            -1.0
        } else {
            1.0
        }
    };
    let turned = match rules.turn {
        Turn::BySum => normals.map(|normal| side(normals[0] + normals[1] + normals[2]) * normal),
        Turn::EachOnItsOwn => normals.map(|normal| side(normal) * normal),
        Turn::ByTheFirst => normals.map(|normal| side(normals[0]) * normal),
        Turn::ByTheWinding => normals.map(|normal| side(triangle.geometric_normal()) * normal),
    };
    let mut smooth = point;
    if rules.blends {
        smooth.normal = C::smooth_normal(triangle, &turned, point.surface.point);
    }
    let transparency = point.material.transparency;
    let lifted = if rules.lifts_half_transparent {
        transparency < 1.0
    } else {
        transparency == 0.0
    };
    if rules.lifts && lifted {
        let lifted_with = if rules.lifts_unturned {
            normals
        } else {
            &turned
        };
        smooth.surface.point = C::terminator_point(triangle, lifted_with, point.surface.point);
    }
    smooth
}

macro_rules! smoothed {
    ($($(#[$doc:meta])* $name:ident = $rules:expr;)*) => {$(
        $(#[$doc])*
        struct $name;
        plant! {
            $name;
            fn smooth_hit_point<'a>(
                point: HitPoint<'a>,
                triangle: &Triangle,
                normals: &[Vec3; 3],
            ) -> HitPoint<'a> {
                smooth_hit::<Planted>(point, triangle, normals, $rules)
            }
        }
    )*};
}

smoothed! {
    KeepsTheFlatNormal = SmoothRules { blends: false, ..SmoothRules::CORRECT };
    PointNotLifted = SmoothRules { lifts: false, ..SmoothRules::CORRECT };
    /// The blend turned, the lift made with the normals as given: from
    /// below, a bulge seen as a hollow is lifted all the same.
    LiftsWithUnturnedNormals = SmoothRules { lifts_unturned: true, ..SmoothRules::CORRECT };
    EachNormalTurnedOnItsOwn = SmoothRules { turn: Turn::EachOnItsOwn, ..SmoothRules::CORRECT };
    TurnedByTheFirstNormal = SmoothRules { turn: Turn::ByTheFirst, ..SmoothRules::CORRECT };
    /// The side read off the triangle's winding: right wherever the
    /// winding and the vertex normals agree on which side is out.
    TurnedByTheWinding = SmoothRules { turn: Turn::ByTheWinding, ..SmoothRules::CORRECT };
    /// Lifted unless the material lets everything through: a half
    /// transparent point's refracted ray starts above the surface.
    LiftsHalfTransparent = SmoothRules { lifts_half_transparent: true, ..SmoothRules::CORRECT };
    /// All of the rules kept: it must pass.
    SmoothAsTheLessonSays = SmoothRules::CORRECT;
}

#[test]
fn contract_the_shading_normal_is_the_blend() {
    assert_caught::<KeepsTheFlatNormal>("smooth-hit-convex");
}

#[test]
fn contract_an_opaque_point_is_lifted() {
    assert_caught::<PointNotLifted>("smooth-hit-convex");
}

#[test]
fn contract_the_lift_uses_the_turned_normals() {
    assert_caught::<LiftsWithUnturnedNormals>("smooth-hit-from-below");
}

#[test]
fn contract_the_normals_are_turned_together_by_their_sum() {
    assert_caught::<EachNormalTurnedOnItsOwn>("smooth-hit-one-normal-below-the-facet");
    assert_caught::<TurnedByTheFirstNormal>("smooth-hit-one-normal-below-the-facet");
}

#[test]
fn contract_the_vertex_normals_say_where_out_is_not_the_winding() {
    assert_caught::<TurnedByTheWinding>("smooth-hit-winding-against-the-normals");
}

#[test]
fn contract_any_transparency_keeps_the_point() {
    assert_caught::<LiftsHalfTransparent>("smooth-hit-half-transparent");
}

#[test]
fn the_rules_copy_passes() {
    let verdict = planted::check_chapter::<SmoothAsTheLessonSays>(CHAPTER, &options());
    assert!(verdict.robust(), "{}", verdict.text());
}

/// Chapter 6's mirror on a smooth mesh that never falls back to the
/// facet's normal: a grazing ray's mirror image about the blended normal
/// goes into the surface, and sees the inside of the mesh.
struct MirrorNeverFallsBack;
plant! {
    MirrorNeverFallsBack;
    fn shade_mirror(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        let local = Planted::shade_phong(tracer, point);
        let k_r = point.material.reflectivity;
        let mut color = (1.0 - k_r) * local.diffuse + local.specular;
        if depth < tracer.max_depth() && tracer.worth_casting(weight, k_r) {
            let dir = Planted::reflect(point.ray.dir, point.normal);
            let reflected = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
            color += k_r * tracer.trace(RayKind::Reflection, &reflected, depth + 1, weight * k_r);
        }
        color
    }
}

#[test]
fn contract_a_smooth_mirror_falls_back_to_the_facet() {
    assert_caught::<MirrorNeverFallsBack>("smooth-mirror-grazing-falls-back");
}

// ---------------------------------------------------------------------------
// Correct alternatives: they must pass.

#[test]
fn alternative_moller_trumbore_is_correct_but_not_robust() {
    let verdict = check_chapter::<Textbook<Reference, false, true>>(CHAPTER, &options());
    let text = verdict.text();
    assert!(verdict.passes(), "{text}");
    assert!(!verdict.robust(), "{text}");
    assert!(text.contains("correct, not yet robust"), "{text}");
    let failure = verdict
        .robustness
        .as_ref()
        .and_then(|robustness| robustness.first_failure.as_ref())
        .expect("a hard case fails");
    assert_eq!(
        failure.name, "triangle-closed-mesh-nothing-escapes",
        "{text}"
    );
    assert_eq!(failure.level, Level::Robustness, "{text}");
}

/// Cramer's rule with three determinants of their own (not
/// Moller-Trumbore's shared cross products): right to rounding, and not
/// watertight, which the closed mesh, not one formula's known failures,
/// shows.
struct CramersRule;
plant! {
    CramersRule;
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let [a, b, c] = triangle.corners();
        let (e1, e2, s) = (b - a, c - a, ray.origin - a);
        let back = -ray.dir;
        let determinant = back.dot(e1.cross(e2));
        if determinant == 0.0 || !determinant.is_finite() {
            return None;
        }
        let t = s.dot(e1.cross(e2)) / determinant;
        let beta = back.dot(s.cross(e2)) / determinant;
        let gamma = back.dot(e1.cross(s)) / determinant;
        (beta >= 0.0 && gamma >= 0.0 && beta + gamma <= 1.0 && t > t_min && t < t_max).then_some(t)
    }
}

#[test]
fn alternative_cramers_rule_is_correct_but_lets_rays_out_of_a_closed_mesh() {
    let verdict = planted::check_chapter::<CramersRule>(CHAPTER, &options());
    let text = verdict.text();
    assert!(verdict.passes(), "{text}");
    let failure = verdict
        .robustness
        .as_ref()
        .and_then(|robustness| robustness.first_failure.as_ref())
        .expect("a hard case fails");
    assert_eq!(
        failure.name, "triangle-closed-mesh-nothing-escapes",
        "{text}"
    );
    assert!(
        text.contains("rays hit no triangle and escape the closed mesh"),
        "{text}"
    );
}

/// Moller-Trumbore as raylab keeps it, and as written here (division by
/// the determinant instead of a multiplication by its inverse): both the
/// same "correct, not yet robust" answer to every checkpoint.
struct MollerTrumboreByDivision;
plant! {
    MollerTrumboreByDivision;
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        moller_trumbore(triangle, ray, t_min, t_max, false, inclusive)
    }
}

#[test]
fn alternative_moller_trumbore_by_division_passes_the_checkpoints() {
    let verdict = planted::check_chapter::<MollerTrumboreByDivision>(CHAPTER, &options());
    assert!(verdict.passes(), "{}", verdict.text());
}

/// Barycentric coordinates as ratios of signed areas (cross products along
/// the normal) instead of the lesson's two-equation solve.
struct BarycentricByAreas;
plant! {
    BarycentricByAreas;
    fn barycentric(triangle: &Triangle, point: Vec3) -> Vec3 {
        let [a, b, c] = triangle.corners();
        let normal = (b - a).cross(c - a);
        let area = |p: Vec3, q: Vec3, r: Vec3| (q - p).cross(r - p).dot(normal);
        Vec3::new(area(point, b, c), area(a, point, c), area(a, b, point)) / normal.dot(normal)
    }
}

#[test]
fn alternative_barycentric_by_areas() {
    let verdict = planted::check_chapter::<BarycentricByAreas>(CHAPTER, &options());
    assert!(verdict.passes(), "{}", verdict.text());
}

#[test]
fn the_reference_passes_chapter_10_at_both_levels_image_included() {
    let verdict = check_chapter::<Reference>(CHAPTER, &options());
    let text = verdict.text();
    assert!(verdict.robust(), "{text}");
    let image = verdict.image.as_ref().expect("the image was compared");
    assert!(image.passed, "{text}");
}

// ---------------------------------------------------------------------------
// The cases and the lesson agree.

#[test]
fn the_lesson_promises_the_first_two_cases() {
    let info = CHAPTERS
        .iter()
        .find(|info| info.number == CHAPTER)
        .expect("chapter 10 is registered");
    let cases = raylab::check::by_chapter::checkpoints(info.number);
    let names: Vec<&str> = cases.iter().take(2).map(|case| case.name).collect();
    assert_eq!(
        names,
        ["triangle-hit-from-behind", "barycentric-lesson-point"]
    );
    assert!(
        cases[0].says.contains("expected t = 2"),
        "{}",
        cases[0].says
    );
    assert!(
        cases[1].says.contains("expected (0.5, 0.25, 0.25)"),
        "{}",
        cases[1].says
    );
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("chapters/10_triangles/lesson.md"),
    )
    .expect("the lesson reads");
    // Sentences are compared with their line breaks as spaces.
    let lesson = text.split_whitespace().collect::<Vec<_>>().join(" ");
    for promise in [
        "ray from (0.25, 0.25, 0) along +z at the triangle (0,0,2), (1,0,2), (0,1,2)",
        "hit at `t = 2`",
        "barycentric coordinates (0.5, 0.25, 0.25)",
    ] {
        assert!(
            lesson.contains(promise),
            "the lesson no longer says {promise}"
        );
    }
    // Every case points at a section the lesson has, heading for heading.
    let headings: Vec<&str> = text
        .lines()
        .filter(|line| line.starts_with('#'))
        .map(|line| line.trim_start_matches('#').trim())
        .collect();
    for case in cases
        .iter()
        .chain(&raylab::check::by_chapter::robustness(info.number))
    {
        assert!(
            headings.contains(&case.section),
            "{}: no section \"{}\" in the lesson",
            case.name,
            case.section
        );
    }
}

/// `--terminator flat` shows what chapter 10's lift fixes: on lesson 10's
/// coarse smooth model lit from the side, rays leaving the flat triangles
/// are shadowed by the neighbouring facets along the terminator, so the
/// picture darkens there; lifted, it is smooth. A renderer that ignored
/// the setting, or a lift that did nothing, would draw the two alike.
#[test]
fn the_flat_terminator_darkens_what_the_lift_lights() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scenes/terminator.toml");
    let scene = raylab::Scene::load(&path).expect("lesson 10's terminator scene");
    let render = |terminator| {
        let settings = raylab::RenderSettings {
            width: 160,
            height: 120,
            samples: 1,
            terminator,
            ..scene.render
        };
        raylab::render::render(&scene, CHAPTER, &settings, None).expect("renders")
    };
    let lifted = render(raylab::scene::TerminatorRule::Lifted);
    let flat = render(raylab::scene::TerminatorRule::Flat);
    let default = render(raylab::RenderSettings::default().terminator);
    assert_eq!(default.rgb, lifted.rgb, "lifted is the default");
    let brightness = |rgb: &[u8]| rgb.iter().map(|&v| u64::from(v)).sum::<u64>();
    let changed = flat
        .rgb
        .chunks(3)
        .zip(lifted.rgb.chunks(3))
        .filter(|(f, l)| f.iter().zip(l.iter()).any(|(f, l)| f.abs_diff(*l) > 2))
        .count();
    // About 3% of the pixels at 320x240 (lesson 10).
    assert!(changed > 400, "only {changed} pixels changed by the lift");
    assert!(
        brightness(&flat.rgb) < brightness(&lifted.rgb),
        "the flat origins should shadow more than they light"
    );
}
