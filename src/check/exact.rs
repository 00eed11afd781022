//! The expected answers of the checks, computed in `f64` from the same
//! `f32` inputs (widened exactly) with formulas written apart from the
//! reference chapters': the point of the line nearest the centre for the
//! sphere, Heckbert's tangential form for refraction. `f64` carries 29 more
//! bits than `f32`, so its own rounding is far below every tolerance.

use glam::{DVec3, Vec3};

/// Unit roundoff of `f32`.
pub const U: f64 = f32::EPSILON as f64 / 2.0;

pub fn wide(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

/// Both parameters where the line `o + t d` meets the sphere, smaller first.
pub fn sphere_roots(center: DVec3, r: f64, o: DVec3, d: DVec3) -> Option<(f64, f64)> {
    let oc = o - center;
    let a = d.dot(d);
    let mid = -d.dot(oc) / a;
    let closest = oc + mid * d;
    let half_squared = (r * r - closest.length_squared()) / a;
    if !(half_squared >= 0.0) || !half_squared.is_finite() || !(r > 0.0) {
        return None;
    }
    let half = half_squared.sqrt();
    Some((mid - half, mid + half))
}

/// The outward normal (unit, up to rounding) where the line meets the
/// sphere at `t`, one of its roots: from the point of the line nearest the
/// centre and the half chord, `closest -/+ half d`, rather than as
/// `o + t d - center`. That difference cancels to nothing once the
/// coordinates are 2^53 times the radius (a unit ball at 2^100: both roots,
/// and so the hit point, round to the centre itself in `f64`).
pub fn sphere_normal(center: DVec3, r: f64, o: DVec3, d: DVec3, t: f64) -> DVec3 {
    let oc = o - center;
    let a = d.dot(d);
    let mid = -d.dot(oc) / a;
    let closest = oc + mid * d;
    let half = ((r * r - closest.length_squared()) / a).max(0.0).sqrt();
    // The near root is `mid - half`; a root that rounds to `mid` itself is
    // taken as the near one, the hit from outside.
    let along = if t <= mid { -half } else { half };
    (closest + along * d) / r
}

/// The first root in `(t_min, t_max)`.
pub fn sphere(center: DVec3, r: f64, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<f64> {
    let (near, far) = sphere_roots(center, r, o, d)?;
    [near, far].into_iter().find(|&t| t > t_min && t < t_max)
}

/// The plane's `t` in `(t_min, t_max)`; `None` for parallel or degenerate input.
pub fn plane(
    point: DVec3,
    normal: DVec3,
    o: DVec3,
    d: DVec3,
    t_min: f64,
    t_max: f64,
) -> Option<f64> {
    let denominator = d.dot(normal);
    if denominator == 0.0 || !denominator.is_finite() {
        return None;
    }
    let t = (point - o).dot(normal) / denominator;
    (t > t_min && t < t_max).then_some(t)
}

pub fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - 2.0 * (d.dot(n) / n.dot(n)) * n
}

/// Unit refracted direction, or `None` under total internal reflection.
pub fn refract(d: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
    let d = d / d.length();
    let mut n = n / n.length();
    if d.dot(n) > 0.0 {
        n = -n;
    }
    let tangential = eta * (d - d.dot(n) * n);
    let sin2 = tangential.length_squared();
    if sin2 > 1.0 {
        return None;
    }
    Some(tangential - (1.0 - sin2).sqrt() * n)
}

/// The angle between two directions, accurate for tiny angles.
pub fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}
