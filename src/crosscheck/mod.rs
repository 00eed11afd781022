//! Cross-checking our intersections against a second, independent
//! intersector (Embree 4: the `embree` module, built with the feature of that
//! name, and docs/embree.md).
//!
//! Every ray a render casts is traced twice: by [`nearest_hit`] over the
//! tracer's shapes, and by the other backend. The two answers are compared:
//! the same object (or both a miss) and the same `t` up to rounding is
//! agreement. Rounding makes some rays legitimately differ; these are
//! *boundary cases*, counted but not failures:
//!
//! - **silhouette**: the ray passes within a few ulps of a sphere's
//!   outline, where hit or miss (and `t`, whose error grows without bound at
//!   tangency) depends on rounding;
//! - **grazing**: the ray is within a few ulps of parallel to a plane or a
//!   triangle;
//! - **edge**: the ray passes within a few ulps of a triangle's edge or
//!   corner ([`on_edge`]), where which of two neighbours is hit, or whether
//!   the border of an open mesh is, depends on rounding. With one
//!   exception, which is a failure and not a boundary case: where Embree
//!   hits a triangle on an edge or corner it *shares* with another, ours
//!   must hit something there too (a watertight test on a closed mesh always
//!   does; Moller-Trumbore may not). A miss, or a hit farther along, is
//!   [`Verdict::EdgeMissed`];
//! - **beyond the quad**: Embree has no infinite planes, so each plane is
//!   a large quad ([`plane_quad`]); our hits at or past its edge have no
//!   counterpart;
//! - **tie**: two surfaces meet along the ray (a ball resting on the floor),
//!   so either may be the nearest;
//! - **at the ray's end**: one backend's hit lies within the tolerance of
//!   the ray's `t_min` or `t_max`, where our open interval and Embree's
//!   closed one, or a quad a rounding away from its plane, decide.
//!
//! Anything else beyond the tolerance ([`TOLERANCE_EPSILONS`]) is a
//! disagreement, and `raylab crosscheck` exits with status 1.

mod geometry;
mod rounding;

pub use geometry::{PlaneQuad, Primitive, QUAD_SCALE, plane_quad, primitives, scene_size};
pub use rounding::{
    EDGE_EPSILONS, EdgeCrossing, GRAZING_EPSILONS, SILHOUETTE_EPSILONS, edge_crossing, error_scale,
    grazes, grazes_triangle, on_edge, on_silhouette,
};

use std::time::Instant;

use rayon::prelude::*;

use crate::render::CastRay;
use crate::{Hit, Ray, RayKind, Shape, Vec3, nearest_hit};

/// How far two answers for `t` may differ, in units of `f32::EPSILON` times
/// the hit's error scale ([`error_scale`]). Each backend's `t` is off by a
/// few roundings of the quantities in the scale; 16 leaves room for both
/// backends' errors, which add, and for Embree's different formulas.
pub const TOLERANCE_EPSILONS: f32 = 16.0;

/// Hits of ours within this fraction of the quad's half-side from its edge,
/// or past it, are "beyond the quad".
pub const QUAD_EDGE_MARGIN: f32 = 1.0 / 1024.0;

/// One backend's answer for one ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Answer {
    pub object: usize,
    pub t: f32,
}

impl From<Hit> for Answer {
    fn from(hit: Hit) -> Self {
        Answer {
            object: hit.object,
            t: hit.t,
        }
    }
}

/// Why a difference is not counted as a disagreement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Boundary {
    Silhouette,
    Grazing,
    /// Within a few ulps of a triangle's edge or corner ([`on_edge`]).
    Edge,
    BeyondQuad,
    Tie,
    RayEnd,
}

impl Boundary {
    /// Every reason, in the order of [`Tally::boundary`].
    pub const ALL: [Boundary; 6] = [
        Boundary::Silhouette,
        Boundary::Grazing,
        Boundary::Edge,
        Boundary::BeyondQuad,
        Boundary::Tie,
        Boundary::RayEnd,
    ];

    pub fn describe(self) -> &'static str {
        match self {
            Boundary::Silhouette => "silhouette (within a few ulps of a sphere's outline)",
            Boundary::Grazing => "grazing (within a few ulps of parallel to a plane or a triangle)",
            Boundary::Edge => "edge (within a few ulps of a triangle's edge or corner)",
            Boundary::BeyondQuad => "beyond the quad (our plane hit is outside Embree's quad)",
            Boundary::Tie => "tie (two surfaces at the same t)",
            Boundary::RayEnd => "at the ray's end (a hit within the tolerance of t_min or t_max)",
        }
    }
}

/// The verdict on one ray.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    Agree,
    Boundary(Boundary),
    Disagree,
    /// Embree hit a triangle on an edge or corner it shares with another
    /// triangle, and ours hit nothing there (a miss, or a hit farther
    /// along): a crack in our test. Counted as a disagreement too.
    EdgeMissed,
}

/// One ray with both answers and the verdict.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Compared {
    pub cast: CastRay,
    pub ours: Option<Answer>,
    pub theirs: Option<Answer>,
    pub verdict: Verdict,
    /// `|t_theirs - t_ours| / t_ours` when both hit the same object.
    pub relative_difference: Option<f32>,
    /// The difference over its tolerance (above 1 is out of tolerance);
    /// infinite when the answers name different objects.
    pub severity: f32,
}

/// The geometry both backends are compared on.
pub struct Reference<'a> {
    pub shapes: &'a [Shape],
    /// The quad standing in for each plane, index for index with `shapes`.
    pub quads: &'a [Option<PlaneQuad>],
}

impl Reference<'_> {
    /// Compares our answer on `cast` (by [`nearest_hit`], every shape
    /// tested) with `theirs`.
    pub fn compare(&self, cast: &CastRay, theirs: Option<Answer>) -> Compared {
        let ours = nearest_hit(self.shapes, &cast.ray, cast.t_min, cast.t_max).map(Answer::from);
        self.compare_answers(cast, ours, theirs)
    }

    /// Compares two answers on `cast`: `ours` from any intersector over
    /// `self.shapes` (a BVH, or a variant of the chapters), `theirs` from
    /// the other backend. Objects are indices into `self.shapes`.
    pub fn compare_answers(
        &self,
        cast: &CastRay,
        ours: Option<Answer>,
        theirs: Option<Answer>,
    ) -> Compared {
        let ray = &cast.ray;
        let mut relative_difference = None;
        let mut severity = f32::INFINITY;
        let verdict = match (ours, theirs) {
            (None, None) => {
                severity = 0.0;
                Verdict::Agree
            }
            (Some(a), Some(b)) if a.object == b.object => {
                relative_difference = Some((b.t - a.t).abs() / a.t.abs());
                severity = (b.t - a.t).abs() / self.tolerance(a.object, ray, a.t);
                if severity <= 1.0 {
                    Verdict::Agree
                } else {
                    self.boundary_of(a.object, ray, a.t)
                        .map_or(Verdict::Disagree, Verdict::Boundary)
                }
            }
            // One backend saw a surface first that the other missed: is that
            // surface at a boundary?
            (Some(a), None) => self.disputed(a, cast),
            (None, Some(b)) => self.theirs_first(b, cast),
            (Some(a), Some(b)) => {
                let (first, second) = if a.t <= b.t { (a, b) } else { (b, a) };
                if (second.t - first.t).abs() <= self.tolerance(first.object, ray, first.t) {
                    // Two triangles meeting where the ray passes are an edge
                    // (or corner) of a mesh; anything else meeting there, a
                    // tie of two surfaces.
                    let edge = [first, second].iter().all(|hit| {
                        matches!(self.shapes[hit.object], Shape::Triangle(triangle)
                            if on_edge(&triangle, ray))
                    });
                    Verdict::Boundary(if edge { Boundary::Edge } else { Boundary::Tie })
                } else if b.t < a.t {
                    self.theirs_first(b, cast)
                } else {
                    self.disputed(a, cast)
                }
            }
        };
        Compared {
            cast: *cast,
            ours,
            theirs,
            verdict,
            relative_difference,
            severity,
        }
    }

    /// The verdict on a hit of Embree's that ours did not report: we missed,
    /// or hit something farther along. The shared-edge rule comes first: on
    /// an edge or corner that the triangle shares with another, a
    /// watertight test cannot miss, so unless the ray grazes the triangle
    /// or the hit is at the ray's end, that is [`Verdict::EdgeMissed`].
    fn theirs_first(&self, hit: Answer, cast: &CastRay) -> Verdict {
        let ray = &cast.ray;
        let Shape::Triangle(triangle) = self.shapes[hit.object] else {
            return self.disputed(hit, cast);
        };
        if grazes_triangle(&triangle, ray) {
            return Verdict::Boundary(Boundary::Grazing);
        }
        if self.at_ray_end(hit, cast) {
            return Verdict::Boundary(Boundary::RayEnd);
        }
        match edge_crossing(&triangle, ray) {
            Some(crossing) if crossing.on_edge() => {
                if self.shares_where_crossed(hit.object, &crossing) {
                    Verdict::EdgeMissed
                } else {
                    // The border of an open mesh: rounding decides.
                    Verdict::Boundary(Boundary::Edge)
                }
            }
            _ => Verdict::Disagree,
        }
    }

    /// Whether another triangle of the shapes has the same edge (both
    /// corners, bit for bit) or, near a corner, the same corner, as
    /// `object` has where `crossing` passes. A linear search: it runs only
    /// for the rare rays Embree hits on an edge and ours does not.
    fn shares_where_crossed(&self, object: usize, crossing: &EdgeCrossing) -> bool {
        let Shape::Triangle(triangle) = self.shapes[object] else {
            return false;
        };
        let corners = triangle.corners();
        let near = crossing.near_zero();
        // The corners at the end of the edge (two near-zero coordinates:
        // the one corner whose coordinate is not).
        let wanted: Vec<Vec3> = (0..3).filter(|&i| !near[i]).map(|i| corners[i]).collect();
        if wanted.is_empty() {
            return false;
        }
        let same =
            |p: Vec3, q: Vec3| p.to_array().map(f32::to_bits) == q.to_array().map(f32::to_bits);
        self.shapes.iter().enumerate().any(|(index, shape)| {
            index != object
                && matches!(shape, Shape::Triangle(other)
                    if wanted.iter().all(|&w| other.corners().iter().any(|&c| same(c, w))))
        })
    }

    fn at_ray_end(&self, hit: Answer, cast: &CastRay) -> bool {
        let tolerance = self.tolerance(hit.object, &cast.ray, hit.t);
        hit.t - cast.t_min <= tolerance || cast.t_max - hit.t <= tolerance
    }

    /// The verdict on a hit that only one backend reported (first).
    fn disputed(&self, hit: Answer, cast: &CastRay) -> Verdict {
        let ray = &cast.ray;
        if let Some(boundary) = self.boundary_of(hit.object, ray, hit.t) {
            return Verdict::Boundary(boundary);
        }
        if self.at_ray_end(hit, cast) {
            Verdict::Boundary(Boundary::RayEnd)
        } else {
            Verdict::Disagree
        }
    }

    /// How far `t` on `object` may differ between the backends.
    pub fn tolerance(&self, object: usize, ray: &Ray, t: f32) -> f32 {
        let rounding =
            TOLERANCE_EPSILONS * f32::EPSILON * error_scale(&self.shapes[object], ray, t);
        let quad = self.quads.get(object).copied().flatten();
        let quad_error = match (quad, &self.shapes[object]) {
            (Some(quad), Shape::Plane(plane)) if !quad.axis_aligned => {
                let reach = quad
                    .corners
                    .iter()
                    .map(|&corner| (corner - ray.origin).length())
                    .fold(0.0, f32::max);
                let distance = quad.corner_offset + TOLERANCE_EPSILONS * f32::EPSILON * reach;
                distance / plane.normal().dot(ray.dir).abs()
            }
            _ => 0.0,
        };
        rounding + quad_error
    }

    /// The boundary case the ray is at on `object`, if any (`t` is the hit
    /// one backend reported there).
    pub fn boundary_of(&self, object: usize, ray: &Ray, t: f32) -> Option<Boundary> {
        match &self.shapes[object] {
            Shape::Sphere(sphere) => on_silhouette(sphere, ray).then_some(Boundary::Silhouette),
            Shape::Plane(plane) => {
                if grazes(plane, ray) {
                    return Some(Boundary::Grazing);
                }
                let quad = self.quads.get(object).copied().flatten()?;
                let local = ray.at(t) - quad.center;
                let reach = local.dot(quad.u).abs().max(local.dot(quad.v).abs());
                (reach >= quad.half_side * (1.0 - QUAD_EDGE_MARGIN) || !reach.is_finite())
                    .then_some(Boundary::BeyondQuad)
            }
            Shape::Triangle(triangle) => {
                if grazes_triangle(triangle, ray) {
                    Some(Boundary::Grazing)
                } else {
                    on_edge(triangle, ray).then_some(Boundary::Edge)
                }
            }
            Shape::Implicit(_) => None,
        }
    }
}

/// The summary of a cross-check.
#[derive(Debug, Clone, Default)]
pub struct Tally {
    /// Rays compared, by kind, in the order of [`RayKind::ALL`].
    pub by_kind: [u64; RayKind::COUNT],
    pub both_miss: u64,
    /// Same object, `t` within tolerance.
    pub same_hit: u64,
    /// Boundary cases, by [`Boundary::ALL`].
    pub boundary: [u64; Boundary::ALL.len()],
    /// Every disagreement, edge misses included.
    pub disagreements: u64,
    /// Rays Embree hit on a shared edge or corner and ours missed
    /// ([`Verdict::EdgeMissed`]); also counted in `disagreements`.
    pub edge_misses: u64,
    /// Relative differences of `t` where both hit the same object, outside
    /// the boundary cases.
    pub relative_differences: Vec<f32>,
    /// The largest relative difference of `t` in a boundary case where both
    /// hit the same object.
    pub boundary_max_relative_difference: f32,
    /// The ray behind the largest of `relative_differences` (the first, of
    /// equal ones). Ranked by difference alone it need not be among the
    /// `worst`, which are ranked against each ray's tolerance, an absolute
    /// one: a tiny `t` (a shadow ray blocked just off its start) or a
    /// grazing ray's ill-conditioned one differs a lot relatively and little
    /// against it.
    pub largest_difference: Option<Compared>,
    /// The worst rays, worst first (at most [`WORST_KEPT`]).
    pub worst: Vec<Compared>,
}

/// How many of the worst rays a [`Tally`] keeps.
pub const WORST_KEPT: usize = 10;

impl Tally {
    pub fn total(&self) -> u64 {
        self.by_kind.iter().sum()
    }

    fn add(&mut self, compared: Compared) {
        self.by_kind[compared.cast.kind.index()] += 1;
        match compared.verdict {
            Verdict::Agree if compared.ours.is_none() => self.both_miss += 1,
            Verdict::Agree => self.same_hit += 1,
            Verdict::Boundary(reason) => self.boundary[reason as usize] += 1,
            Verdict::Disagree => self.disagreements += 1,
            Verdict::EdgeMissed => {
                self.disagreements += 1;
                self.edge_misses += 1;
            }
        }
        if let Some(difference) = compared.relative_difference {
            if let Verdict::Boundary(_) = compared.verdict {
                self.boundary_max_relative_difference =
                    self.boundary_max_relative_difference.max(difference);
            } else {
                self.relative_differences.push(difference);
                let larger = self
                    .largest_difference
                    .and_then(|largest| largest.relative_difference)
                    .is_none_or(|largest| difference > largest);
                if larger {
                    self.largest_difference = Some(compared);
                }
            }
        }
        if compared.severity > 0.0 {
            self.worst.push(compared);
            if self.worst.len() > 4 * WORST_KEPT {
                self.keep_worst();
            }
        }
    }

    fn keep_worst(&mut self) {
        // Stable: among equals, the earlier ray stays first.
        self.worst.sort_by(|a, b| rank(b).total_cmp(&rank(a)));
        self.worst.truncate(WORST_KEPT);
    }

    fn merge(mut self, other: Tally) -> Tally {
        for (mine, theirs) in self.by_kind.iter_mut().zip(other.by_kind) {
            *mine += theirs;
        }
        for (mine, theirs) in self.boundary.iter_mut().zip(other.boundary) {
            *mine += theirs;
        }
        self.both_miss += other.both_miss;
        self.same_hit += other.same_hit;
        self.disagreements += other.disagreements;
        self.edge_misses += other.edge_misses;
        self.relative_differences.extend(other.relative_differences);
        let difference = |tally: Option<Compared>| {
            tally
                .and_then(|compared| compared.relative_difference)
                .unwrap_or(f32::NEG_INFINITY)
        };
        if difference(other.largest_difference) > difference(self.largest_difference) {
            self.largest_difference = other.largest_difference;
        }
        self.boundary_max_relative_difference = self
            .boundary_max_relative_difference
            .max(other.boundary_max_relative_difference);
        self.worst.extend(other.worst);
        self.keep_worst();
        self
    }

    /// The median and the largest relative difference of `t` outside the
    /// boundary cases, if any hit was shared.
    pub fn median_and_max(&self) -> Option<(f32, f32)> {
        let mut sorted = self.relative_differences.clone();
        if sorted.is_empty() {
            return None;
        }
        sorted.sort_by(f32::total_cmp);
        let middle = sorted.len() / 2;
        let median = if sorted.len() % 2 == 1 {
            sorted[middle]
        } else {
            (sorted[middle - 1] + sorted[middle]) / 2.0
        };
        Some((median, sorted[sorted.len() - 1]))
    }

    pub fn clean(&self) -> bool {
        self.disagreements == 0
    }
}

/// Worst first: disagreements, then boundary cases of rounding, then
/// agreements, each by severity. Hits beyond the quad come last: they are
/// where our set-up cannot compare, not a sign of rounding trouble.
fn rank(compared: &Compared) -> f64 {
    let class = match compared.verdict {
        Verdict::Disagree | Verdict::EdgeMissed => 3.0,
        Verdict::Boundary(Boundary::BeyondQuad) => 0.0,
        Verdict::Boundary(_) => 2.0,
        Verdict::Agree => 1.0,
    };
    // Severity in [0, inf] maps into [0, 1) inside its class (written out
    // for infinity: inf / inf would be NaN).
    let severity = f64::from(compared.severity);
    let within = if severity.is_finite() {
        severity / (1.0 + severity)
    } else {
        1.0
    };
    class + within * 0.999
}

/// The most rays a cross-check records: every one is kept in memory (about
/// 600 MB at 36 bytes a ray). Counting primary samples is not enough: each
/// brings 1 ray or 130 (two facing mirrors at depth 64), so the bound is on
/// the rays actually cast, counted while they are recorded.
pub const MAX_RECORDED_RAYS: u64 = 1 << 24;

/// Compares every ray in `rays` with `theirs`, in parallel; the result does
/// not depend on the number of threads.
pub fn cross_check(
    reference: &Reference,
    rays: &[CastRay],
    theirs: impl Fn(&CastRay) -> Option<Answer> + Sync,
) -> Tally {
    cross_check_with(
        reference,
        rays,
        |cast| ours(reference.shapes, cast).map(Answer::from),
        theirs,
    )
}

/// [`cross_check`] with our answers from `ours` instead of testing every
/// shape: a BVH over `reference.shapes`, or a variant of the chapters (the
/// textbook triangle test, to show its cracks).
pub fn cross_check_with(
    reference: &Reference,
    rays: &[CastRay],
    ours: impl Fn(&CastRay) -> Option<Answer> + Sync,
    theirs: impl Fn(&CastRay) -> Option<Answer> + Sync,
) -> Tally {
    rays.par_chunks(4096)
        .map(|chunk| {
            let mut tally = Tally::default();
            for cast in chunk {
                tally.add(reference.compare_answers(cast, ours(cast), theirs(cast)));
            }
            tally.keep_worst();
            tally
        })
        .collect::<Vec<_>>()
        .into_iter()
        .fold(Tally::default(), Tally::merge)
}

/// Traces every ray with `trace` on this thread, in order, and returns the
/// rays per second.
pub fn rays_per_second<T>(rays: &[CastRay], trace: impl Fn(&CastRay) -> T) -> f64 {
    let start = Instant::now();
    for cast in rays {
        std::hint::black_box(trace(std::hint::black_box(cast)));
    }
    rays.len() as f64 / start.elapsed().as_secs_f64().max(1e-9)
}

/// Our side of the comparison, as [`rays_per_second`] times it.
pub fn ours(shapes: &[Shape], cast: &CastRay) -> Option<Hit> {
    nearest_hit(shapes, &cast.ray, cast.t_min, cast.t_max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::{TooManyRays, record_rays_within};
    use crate::shapes::Triangle;
    use crate::{Plane, Scene, Sphere, Stage};

    fn cast(origin: Vec3, dir: Vec3) -> CastRay {
        CastRay {
            kind: RayKind::Primary,
            ray: Ray::new(origin, dir),
            t_min: 0.0,
            t_max: f32::INFINITY,
        }
    }

    fn sphere_reference() -> (Vec<Shape>, Vec<Option<PlaneQuad>>) {
        (
            vec![Sphere::new(Vec3::new(0.0, 0.0, 5.0), 1.0).into()],
            vec![None],
        )
    }

    #[test]
    fn equal_answers_agree_and_far_ones_disagree() {
        let (shapes, quads) = sphere_reference();
        let reference = Reference {
            shapes: &shapes,
            quads: &quads,
        };
        let ray = cast(Vec3::ZERO, Vec3::Z);
        let same = reference.compare(&ray, Some(Answer { object: 0, t: 4.0 }));
        assert_eq!(same.verdict, Verdict::Agree);
        assert_eq!(same.relative_difference, Some(0.0));
        let off = reference.compare(&ray, Some(Answer { object: 0, t: 4.01 }));
        assert_eq!(off.verdict, Verdict::Disagree);
        let missed = reference.compare(&ray, None);
        assert_eq!(missed.verdict, Verdict::Disagree);
    }

    #[test]
    fn a_grazing_miss_is_a_silhouette_case() {
        let (shapes, quads) = sphere_reference();
        let reference = Reference {
            shapes: &shapes,
            quads: &quads,
        };
        let tangent = cast(Vec3::new(1.0, 0.0, 0.0), Vec3::Z);
        let compared = reference.compare(&tangent, None);
        assert_eq!(compared.verdict, Verdict::Boundary(Boundary::Silhouette));
        let clear_miss = cast(Vec3::new(1.01, 0.0, 0.0), Vec3::Z);
        let compared = reference.compare(&clear_miss, Some(Answer { object: 0, t: 5.0 }));
        assert_eq!(compared.verdict, Verdict::Disagree);
    }

    #[test]
    fn plane_hits_past_the_quad_are_boundary_cases() {
        let floor = Plane::new(Vec3::ZERO, Vec3::Y);
        let quad = plane_quad(&floor, Vec3::new(0.0, 1.0, 0.0), 16.0);
        let shapes = vec![Shape::Plane(floor)];
        let quads = vec![Some(quad)];
        let reference = Reference {
            shapes: &shapes,
            quads: &quads,
        };
        // Down at a shallow slope: hits the floor at x = 100, past the quad.
        let far = cast(Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, -0.01, 0.0));
        let compared = reference.compare(&far, None);
        assert_eq!(compared.verdict, Verdict::Boundary(Boundary::BeyondQuad));
        let near = cast(Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, -1.0, 0.0));
        assert_eq!(reference.compare(&near, None).verdict, Verdict::Disagree);
    }

    fn two_triangles() -> Vec<Shape> {
        // A unit square at z = 2 cut along the diagonal from (1,0) to (0,1).
        let (a, b) = (Vec3::new(0.0, 0.0, 2.0), Vec3::new(1.0, 0.0, 2.0));
        let (c, d) = (Vec3::new(0.0, 1.0, 2.0), Vec3::new(1.0, 1.0, 2.0));
        vec![
            Shape::Triangle(Triangle::new(a, b, c)),
            Shape::Triangle(Triangle::new(b, d, c)),
        ]
    }

    #[test]
    fn the_edge_band_is_a_few_ulps_around_the_edges() {
        let shapes = two_triangles();
        let Shape::Triangle(first) = shapes[0] else {
            unreachable!()
        };
        let through = |x: f32, y: f32| Ray::new(Vec3::new(x, y, 0.0), Vec3::Z);
        assert!(on_edge(&first, &through(0.5, 0.5)));
        assert!(on_edge(&first, &through(0.0, 0.0)));
        assert!(!on_edge(&first, &through(0.25, 0.25)));
        // A thousandth inside the diagonal: far more than rounding.
        assert!(!on_edge(&first, &through(0.499, 0.5)));
        let crossing = edge_crossing(&first, &through(0.5, 0.5)).expect("crosses");
        assert_eq!(crossing.near_zero(), [true, false, false]);
        assert!(crossing.band > 0.0 && crossing.band < 1e-4, "{crossing:?}");
        // The ray in the triangles' plane crosses nothing.
        assert!(edge_crossing(&first, &Ray::new(Vec3::new(0.0, 0.5, 2.0), Vec3::X)).is_none());
    }

    #[test]
    fn a_triangle_s_error_scale_grows_as_the_ray_grazes_it() {
        let shapes = two_triangles();
        let origin = Vec3::new(0.25, 0.25, 0.0);
        let head_on = error_scale(&shapes[0], &Ray::new(origin, Vec3::Z), 2.0);
        let slanted = Ray::new(origin, Vec3::new(0.0, 1.0, 0.01));
        let grazing = error_scale(&shapes[0], &slanted, 200.0);
        assert!(head_on > 0.0 && head_on < 10.0, "{head_on}");
        assert!(grazing > 100.0 * head_on, "{grazing} vs {head_on}");
        assert!(grazing.is_finite());
    }

    #[test]
    fn embree_hitting_a_shared_edge_that_ours_misses_is_a_failure() {
        let shapes = two_triangles();
        let quads = vec![None; 2];
        let reference = Reference {
            shapes: &shapes,
            quads: &quads,
        };
        let theirs = Some(Answer { object: 1, t: 2.0 });
        let diagonal = cast(Vec3::new(0.5, 0.5, 0.0), Vec3::Z);
        let missed = reference.compare_answers(&diagonal, None, theirs);
        assert_eq!(missed.verdict, Verdict::EdgeMissed);
        // Ours hits something farther: the same failure.
        let far = reference.compare_answers(&diagonal, Some(Answer { object: 0, t: 9.0 }), theirs);
        assert_eq!(far.verdict, Verdict::EdgeMissed);
        // The other way round (ours hits the edge, Embree misses): rounding.
        let ours_only = reference.compare_answers(&diagonal, theirs, None);
        assert_eq!(ours_only.verdict, Verdict::Boundary(Boundary::Edge));
        // On the open border x = 1 of triangle 1 only: rounding too.
        let border = cast(Vec3::new(1.0, 0.5, 0.0), Vec3::Z);
        let open = reference.compare_answers(&border, None, theirs);
        assert_eq!(open.verdict, Verdict::Boundary(Boundary::Edge));
        let tally = cross_check_with(&reference, &[diagonal, border], |_| None, |_| theirs);
        assert_eq!((tally.disagreements, tally.edge_misses), (1, 1));
        assert!(!tally.clean());
    }

    /// Two mirrors facing each other, the camera between them looking at
    /// one: every primary ray bounces `max_depth` times.
    const FACING_MIRRORS: &str = r#"
[camera]
position = [0.0, 0.0, -1.0]
look_at = [0.0, 0.0, 1.0]
fov_degrees = 10.0

[render]
max_depth = 64
min_contribution = 0.0

[[objects]]
plane = { point = [0.0, 0.0, 2.0], normal = [0.0, 0.0, 1.0] }
material = { reflectivity = 1.0 }

[[objects]]
plane = { point = [0.0, 0.0, -2.0], normal = [0.0, 0.0, 1.0] }
material = { reflectivity = 1.0 }
"#;

    fn mirrors_stage(scene: &Scene, width: u32, height: u32) -> Stage<'_> {
        let settings = crate::RenderSettings {
            width,
            height,
            ..scene.render
        };
        Stage::new(scene, 8, settings).expect("valid settings")
    }

    #[test]
    fn recording_stops_at_the_ray_budget_not_at_a_guess_per_sample() {
        let scene = Scene::parse(FACING_MIRRORS, "facing mirrors").expect("valid scene");
        let tracer = mirrors_stage(&scene, 16, 16);
        // 256 primary samples, far under any per-sample guess of 3.6 rays
        // each; but each casts 65 rays.
        // On one thread the rows run one after another, so the recording
        // stops within a row or two of passing the budget, whatever the
        // machine.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("one thread");
        let error = pool
            .install(|| record_rays_within(&tracer, 5_000))
            .expect_err("over budget");
        let TooManyRays::Cast {
            budget,
            pixels_done,
            pixels,
            estimate,
        } = error.clone()
        else {
            panic!("not refused while casting: {error:?}");
        };
        assert_eq!((budget, pixels), (5_000, 256));
        assert!(pixels_done < 128, "{error:?}");
        // Each pixel casts 65 rays.
        assert!(estimate > 5_000 && estimate <= 256 * 65 * 2, "{error:?}");
        let message = error.to_string();
        assert!(message.contains("at most 5000 rays"), "{message}");
        assert!(message.contains("--depth"), "{message}");
        // The count is exact: one ray over the budget is refused.
        let whole = crate::record_rays(&tracer);
        assert_eq!(whole.len(), 256 * 65);
        assert!(record_rays_within(&tracer, whole.len() as u64 - 1).is_err());
    }

    #[test]
    fn within_the_budget_the_recording_is_every_ray_in_order() {
        let scene = Scene::parse(FACING_MIRRORS, "facing mirrors").expect("valid scene");
        let tracer = mirrors_stage(&scene, 7, 5);
        let whole = crate::record_rays(&tracer);
        let budgeted = record_rays_within(&tracer, whole.len() as u64).expect("within budget");
        assert_eq!(budgeted, whole);
    }

    #[test]
    fn more_primary_samples_than_the_budget_are_refused_before_tracing() {
        let scene = Scene::parse(FACING_MIRRORS, "facing mirrors").expect("valid scene");
        let tracer = mirrors_stage(&scene, 100, 100);
        let error = record_rays_within(&tracer, 9_999).expect_err("over budget");
        assert_eq!(
            error,
            TooManyRays::Primary {
                width: 100,
                height: 100,
                samples: 1,
                primary: 10_000,
                budget: 9_999
            }
        );
        assert!(error.to_string().contains("100x100 at 1 samples per pixel"));
    }

    #[test]
    fn tally_counts_and_ranks() {
        let (shapes, quads) = sphere_reference();
        let reference = Reference {
            shapes: &shapes,
            quads: &quads,
        };
        let rays = [
            cast(Vec3::ZERO, Vec3::Z),
            cast(Vec3::new(3.0, 0.0, 0.0), Vec3::Z),
            cast(Vec3::new(0.5, 0.0, 0.0), Vec3::Z),
        ];
        // A fake backend that misses everything: the first and last rays
        // disagree, the middle one agrees (both miss).
        let tally = cross_check(&reference, &rays, |_| None);
        assert_eq!(tally.total(), 3);
        assert_eq!(tally.both_miss, 1);
        assert_eq!(tally.disagreements, 2);
        assert!(!tally.clean());
        assert_eq!(tally.worst.len(), 2);
        assert_eq!(tally.worst[0].verdict, Verdict::Disagree);
    }

    #[test]
    fn the_largest_relative_difference_names_its_ray() {
        let (shapes, quads) = sphere_reference();
        let reference = Reference {
            shapes: &shapes,
            quads: &quads,
        };
        // All hit the sphere, at t = 4 for the ray from the origin; a fake
        // backend answers 1, 3 and 2 ulps later: all within tolerance.
        let origins = [0.0, 0.25, 0.5].map(|x| Vec3::new(x, 0.0, 0.0));
        let rays: Vec<CastRay> = origins.iter().map(|&o| cast(o, Vec3::Z)).collect();
        let ulps = |cast: &CastRay| match cast.ray.origin.x {
            0.0 => 1,
            0.25 => 3,
            _ => 2,
        };
        let tally = cross_check(&reference, &rays, |cast| {
            let ours = ours(reference.shapes, cast)?;
            let t = (0..ulps(cast)).fold(ours.t, |t, _| t.next_up());
            Some(Answer { object: 0, t })
        });
        assert!(tally.clean());
        let largest = tally.largest_difference.expect("three shared hits");
        assert_eq!(largest.cast.ray.origin.x, 0.25);
        let (_, max) = tally.median_and_max().expect("three shared hits");
        assert_eq!(largest.relative_difference, Some(max));
    }
}
