//! Where rounding decides: the error scale of a hit's `t`, and the bands
//! around a sphere's outline, a plane's or a triangle's grazing angle and
//! a triangle's edges inside which two correct backends may differ. The
//! numerical analysis lives here, apart from the verdicts that use it.

use crate::shapes::Triangle;
use crate::{Plane, Ray, Shape, Sphere};

/// A ray is on a sphere's silhouette when its distance to the centre is
/// within this many `f32::EPSILON` of `|origin - centre| + radius` from the
/// radius: both backends compute that distance with an error of a few
/// roundings of `|origin - centre|`, so hit or miss there is up to rounding.
pub const SILHOUETTE_EPSILONS: f32 = 8.0;

/// A ray grazes a plane when the cosine between its direction and the plane
/// is at most this many `f32::EPSILON` (chapter 1 refuses hits below 4).
pub const GRAZING_EPSILONS: f32 = 16.0;

/// A ray is on a triangle's edge when the smallest of its barycentric
/// coordinates (computed in `f64`, [`edge_crossing`]) is within this many
/// `f32::EPSILON` of 0, in units of how much rounding moves them.
///
/// Why 32: our watertight test computes each edge function from corners
/// moved to the ray's origin (1 rounding, relative to the corner's distance
/// `D`) and sheared (2 more, by a factor of at most 1 each way), so each
/// sheared coordinate is off by about 3 eps `D`, and the edge function, a
/// difference of two products of coordinates no larger than the corners'
/// distance `H` from the ray's line, by about 2 × 3 eps `D H` plus its own
/// two roundings: some 8 eps `D H`, times up to √3 for the shear's
/// stretch, about 14 eps `D H`. A barycentric coordinate is an edge
/// function over their sum (twice the triangle's area seen along the ray),
/// so it moves by 14 eps `D H / |det|`. Embree's Plücker test has errors of
/// the same size and the two add: 32 covers both with a little room, and
/// is still a band of a few ulps of the corners' distance around each edge.
pub const EDGE_EPSILONS: f32 = 32.0;

/// The length scale of the rounding error of `t` on `shape` (divided by
/// `|dir|`, so in units of `t`): to first order each backend's `t` is off by
/// a few `f32::EPSILON` times this.
///
/// - Sphere: the distance along the ray is `projection ∓ half_chord`. The
///   projection is off by roundings of `|o - c|`; the half-chord
///   `sqrt(r² - l²)` amplifies the error of the closest-approach distance
///   `l` (itself roundings of `|o - c|`) by `r / half_chord`, which grows
///   without bound at tangency (see [`SILHOUETTE_EPSILONS`]).
/// - Plane: `t = ((p - o)·n) / (d·n)`: roundings of `|p - o|` and of the
///   distance itself, both divided by the cosine of the angle of incidence.
pub fn error_scale(shape: &Shape, ray: &Ray, t: f32) -> f32 {
    let length = ray.dir.as_dvec3().length();
    let scale = match shape {
        Shape::Sphere(sphere) => {
            let (to_center, closest) = closest_approach(sphere, ray);
            let radius = f64::from(sphere.radius());
            // Inside the silhouette band the ray is a boundary case anyway;
            // the half-chord at the band's inner edge caps the amplification
            // (and keeps it finite for a line that misses).
            let band = silhouette_band(to_center, radius);
            let inner = (radius - band).max(0.0);
            let smallest = (radius * radius - inner * inner).sqrt();
            let half_chord = (radius * radius - closest * closest).max(0.0).sqrt();
            to_center * (1.0 + radius / half_chord.max(smallest)) + radius
        }
        Shape::Plane(plane) => {
            let to_point = (plane.point() - ray.origin).as_dvec3().length();
            let distance = f64::from(t) * length;
            let cosine = cosine_to_normal(plane, ray);
            (to_point + distance) / cosine
        }
        Shape::Triangle(triangle) => {
            let Some(crossing) = edge_crossing(triangle, ray) else {
                // Edge-on or degenerate: no backend computes a `t` worth
                // comparing (and the ray grazes it anyway).
                return f32::INFINITY;
            };
            // Both backends' `t` is a plane's: the corners' distances along
            // the ray, weighted by the barycentric coordinates (ours:
            // `(u az + v bz + w cz) / det`, Embree's the plane through a
            // corner). As for a plane, the corners' roundings (relative to
            // their distance `D`) and the distance `t|d|` itself, divided by
            // the cosine. And ours has one more: errors `δb` in the weights
            // (`EDGE_EPSILONS`: about eps `D H / |det|` each, summing to
            // 0) move `t` by `Σ δb_i (z_i - t)`, where `z_i - t` is how far
            // along the ray corner `i` lies from the hit, which grows as
            // the ray grazes the plane (and `det` shrinks): `D H Z / |det|`
            // with `Z` the largest `|z_i - t|`.
            let distance = f64::from(t) * length;
            let spread = crossing
                .heights
                .iter()
                .map(|height| (height - distance).abs())
                .fold(0.0, f64::max);
            let weights = crossing.reach * crossing.offset * spread / crossing.capped_det();
            (crossing.reach + distance) / crossing.capped_cosine() + weights
        }
        // A march stops at its tolerance, not at a rounding: no rounding
        // scale applies (and `raylab crosscheck` refuses implicit surfaces).
        Shape::Implicit(_) => return f32::INFINITY,
    };
    (scale / length) as f32
}

/// `|o - c|` and the distance from the centre to the ray's line, in double
/// precision.
fn closest_approach(sphere: &Sphere, ray: &Ray) -> (f64, f64) {
    let oc = (ray.origin - sphere.center()).as_dvec3();
    let dir = ray.dir.as_dvec3();
    let foot = oc - (oc.dot(dir) / dir.dot(dir)) * dir;
    (oc.length(), foot.length())
}

fn cosine_to_normal(plane: &Plane, ray: &Ray) -> f64 {
    let dir = ray.dir.as_dvec3();
    (dir.dot(plane.normal().as_dvec3()) / dir.length()).abs()
}

/// Whether the ray passes within [`SILHOUETTE_EPSILONS`] of the sphere's outline.
pub fn on_silhouette(sphere: &Sphere, ray: &Ray) -> bool {
    let (to_center, closest) = closest_approach(sphere, ray);
    let radius = f64::from(sphere.radius());
    (closest - radius).abs() <= silhouette_band(to_center, radius)
}

/// The half-width of the silhouette band, as a distance from the centre.
fn silhouette_band(to_center: f64, radius: f64) -> f64 {
    f64::from(SILHOUETTE_EPSILONS * f32::EPSILON) * (to_center + radius)
}

/// Whether the ray is within [`GRAZING_EPSILONS`] of parallel to the plane.
pub fn grazes(plane: &Plane, ray: &Ray) -> bool {
    cosine_to_normal(plane, ray) <= f64::from(GRAZING_EPSILONS * f32::EPSILON)
}

/// Where a ray crosses a triangle's plane, in `f64`, with the size of the
/// rounding errors the backends make there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeCrossing {
    /// The barycentric coordinates of the crossing, weights of corners
    /// `a`, `b`, `c` (summing to 1; all positive inside).
    pub barycentric: [f64; 3],
    /// How far a barycentric coordinate may be from 0 for the ray to be on
    /// an edge: `EDGE_EPSILONS` eps `D H / |det|` ([`EDGE_EPSILONS`]).
    pub band: f64,
    /// `D`: the largest distance from the ray's origin to a corner.
    pub reach: f64,
    /// `H`: the largest distance from the ray's line to a corner.
    pub offset: f64,
    /// The corners' distances along the ray (projections on its unit
    /// direction).
    pub heights: [f64; 3],
    /// `d̂ · ((b - a) × (c - a))`: twice the triangle's area seen along the
    /// ray, signed (negative from behind).
    pub det: f64,
    /// Twice the triangle's area.
    pub double_area: f64,
}

impl EdgeCrossing {
    /// Whether the ray passes within the band of an edge or a corner: the
    /// smallest coordinate is that close to 0 (from either side).
    pub fn on_edge(&self) -> bool {
        let smallest = self
            .barycentric
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        smallest.abs() <= self.band
    }

    /// Which coordinates are within the band of 0: one for an edge (the
    /// one of the corner across from it), two near a corner.
    pub fn near_zero(&self) -> [bool; 3] {
        self.barycentric.map(|weight| weight.abs() <= self.band)
    }

    /// The cosine between the ray and the triangle's normal, no smaller
    /// than the grazing limit: inside it the ray is a boundary case, and
    /// this keeps error scales finite.
    fn capped_cosine(&self) -> f64 {
        (self.det.abs() / self.double_area).max(f64::from(GRAZING_EPSILONS * f32::EPSILON))
    }

    fn capped_det(&self) -> f64 {
        self.double_area * self.capped_cosine()
    }
}

/// The barycentric coordinates of the point where `ray` crosses the plane
/// of `triangle`, computed in `f64` from corners relative to the origin
/// (each the triple product `d̂ · (p_j × p_k)`, the edge functions the
/// watertight test computes in `f32`), and the band of rounding around the
/// edges. `None` for a degenerate triangle or a ray in its plane.
pub fn edge_crossing(triangle: &Triangle, ray: &Ray) -> Option<EdgeCrossing> {
    let dir = ray.dir.as_dvec3().normalize();
    let origin = ray.origin.as_dvec3();
    let [a, b, c] = triangle.corners().map(|corner| corner.as_dvec3() - origin);
    let weights = [
        dir.dot(b.cross(c)),
        dir.dot(c.cross(a)),
        dir.dot(a.cross(b)),
    ];
    let det: f64 = weights.iter().sum();
    let double_area = (b - a).cross(c - a).length();
    if !(det != 0.0 && double_area > 0.0 && det.is_finite()) {
        return None;
    }
    let reach = [a, b, c].iter().map(|p| p.length()).fold(0.0, f64::max);
    let offset = [a, b, c]
        .iter()
        .map(|p| p.cross(dir).length())
        .fold(0.0, f64::max);
    let band = f64::from(EDGE_EPSILONS * f32::EPSILON) * reach * offset / det.abs();
    Some(EdgeCrossing {
        barycentric: weights.map(|weight| weight / det),
        band,
        reach,
        offset,
        heights: [a.dot(dir), b.dot(dir), c.dot(dir)],
        det,
        double_area,
    })
}

/// Whether the ray passes within [`EDGE_EPSILONS`] of an edge or a corner
/// of `triangle`.
pub fn on_edge(triangle: &Triangle, ray: &Ray) -> bool {
    edge_crossing(triangle, ray).is_some_and(|crossing| crossing.on_edge())
}

/// Whether the ray is within [`GRAZING_EPSILONS`] of parallel to the
/// triangle (or the triangle is degenerate).
pub fn grazes_triangle(triangle: &Triangle, ray: &Ray) -> bool {
    let [a, b, c] = triangle.corners().map(|corner| corner.as_dvec3());
    let normal = (b - a).cross(c - a);
    let dir = ray.dir.as_dvec3();
    let cosine = (normal.dot(dir) / (normal.length() * dir.length())).abs();
    !(cosine > f64::from(GRAZING_EPSILONS * f32::EPSILON))
}
