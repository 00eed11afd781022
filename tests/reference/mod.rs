//! The `f64` reference shared by the hard-case and property tests: every
//! problem solved from the same `f32` inputs, widened exactly, with formulas
//! written separately from the library's (see `hard_cases.rs` for the list).
#![allow(dead_code)]

use glam::DVec3;

#[derive(Debug, Clone, Copy)]
pub struct Hit {
    pub t: f64,
    /// Unit normal at the hit.
    pub normal: DVec3,
}

/// Both roots of the line against a sphere, smaller first.
pub fn sphere_roots(center: DVec3, r: f64, o: DVec3, d: DVec3) -> Option<(f64, f64)> {
    let oc = o - center;
    let a = d.dot(d);
    // Parameter of the point of the line closest to the centre.
    let mid = -d.dot(oc) / a;
    let closest = oc + mid * d;
    let half_squared = (r * r - closest.length_squared()) / a;
    if half_squared.is_nan() || half_squared < 0.0 {
        return None;
    }
    let half = half_squared.sqrt();
    Some((mid - half, mid + half))
}

pub fn sphere(center: DVec3, r: f64, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<Hit> {
    let (near, far) = sphere_roots(center, r, o, d)?;
    [near, far]
        .into_iter()
        .find(|&t| t > t_min && t < t_max)
        .map(|t| Hit {
            t,
            normal: (o + t * d - center) / r,
        })
}

pub fn plane(
    point: DVec3,
    normal: DVec3,
    o: DVec3,
    d: DVec3,
    t_min: f64,
    t_max: f64,
) -> Option<Hit> {
    let denominator = d.dot(normal);
    if denominator == 0.0 || !denominator.is_finite() {
        return None;
    }
    let t = (point - o).dot(normal) / denominator;
    (t > t_min && t < t_max).then(|| Hit {
        t,
        normal: normal / normal.length(),
    })
}

pub fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - 2.0 * (d.dot(n) / n.dot(n)) * n
}

/// Unit refracted direction, or `None` under total internal reflection.
pub fn refract(d: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
    let d = d / d.length();
    let mut n = n / n.length();
    if d.dot(n) > 0.0 {
        n = -n; // face the incoming ray
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
