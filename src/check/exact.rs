//! The `f64` oracle: the expected answers of the checks, and of the hard-case
//! and property tests, computed in `f64` from the same
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

/// A hit of the oracle: its parameter and the unit normal there.
#[derive(Debug, Clone, Copy)]
pub struct Hit {
    pub t: f64,
    pub normal: DVec3,
}

/// The sphere's first hit in `(t_min, t_max)`, with its normal.
pub fn sphere_hit(
    center: DVec3,
    r: f64,
    o: DVec3,
    d: DVec3,
    t_min: f64,
    t_max: f64,
) -> Option<Hit> {
    let t = sphere(center, r, o, d, t_min, t_max)?;
    Some(Hit {
        t,
        normal: sphere_normal(center, r, o, d, t),
    })
}

/// The plane's hit in `(t_min, t_max)`, with its unit normal.
pub fn plane_hit(
    point: DVec3,
    normal: DVec3,
    o: DVec3,
    d: DVec3,
    t_min: f64,
    t_max: f64,
) -> Option<Hit> {
    let t = plane(point, normal, o, d, t_min, t_max)?;
    Some(Hit {
        t,
        normal: normal / normal.length(),
    })
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

/// Twice the signed area of `(p, q, r)` seen along `normal`: positive when
/// they turn counter-clockwise about it.
fn signed_area(p: DVec3, q: DVec3, r: DVec3, normal: DVec3) -> f64 {
    (q - p).cross(r - p).dot(normal)
}

/// The barycentric coordinates of `point` (on the plane of `corners`) as
/// ratios of areas: each corner's weight is the area of the triangle the
/// point makes with the opposite edge, over the whole area. Not the
/// reference's two-equation solve, so that a shared mistake cannot hide.
pub fn barycentric(corners: [DVec3; 3], point: DVec3) -> DVec3 {
    let [a, b, c] = corners;
    let normal = (b - a).cross(c - a);
    let whole = signed_area(a, b, c, normal);
    DVec3::new(
        signed_area(point, b, c, normal),
        signed_area(a, point, c, normal),
        signed_area(a, b, point, normal),
    ) / whole
}

/// Where the line `o + t d` meets the triangle `corners`, with `t` in
/// `(t_min, t_max)`: the plane's `t`, kept when the point's weights are all
/// at least `-1e-9` (a point on an edge, rounded in `f64`, is on it).
/// `None` for a degenerate triangle or a line in its plane.
pub fn triangle(corners: [DVec3; 3], o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<f64> {
    let [a, b, c] = corners;
    let normal = (b - a).cross(c - a);
    if normal == DVec3::ZERO || !normal.is_finite() {
        return None;
    }
    let t = plane(a, normal, o, d, t_min, t_max)?;
    let weights = barycentric(corners, o + t * d);
    (weights.min_element() >= -1e-9).then_some(t)
}

/// The vertex normals blended with the weights of `point`, unit length.
pub fn smooth_normal(corners: [DVec3; 3], normals: [DVec3; 3], point: DVec3) -> DVec3 {
    let w = barycentric(corners, point);
    (w.x * normals[0] + w.y * normals[1] + w.z * normals[2]).normalize()
}

/// Hanika's lifted point: `point` pushed up onto each corner's tangent
/// plane it lies below, the three pushes weighted by the point's
/// barycentric coordinates.
pub fn terminator_point(corners: [DVec3; 3], normals: [DVec3; 3], point: DVec3) -> DVec3 {
    let w = barycentric(corners, point).to_array();
    let mut lifted = point;
    for i in 0..3 {
        let unit = normals[i].normalize();
        let below = (corners[i] - point).dot(unit).max(0.0);
        lifted += w[i] * below * unit;
    }
    lifted
}

/// The torus's polynomial at `p`, relative to its centre, around the y
/// axis: `(|p|^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + z^2)`, zero on the surface
/// and negative inside. Evaluated as written, not expanded in `t`, so its
/// rounding is that of a few products of the point's own size.
pub fn torus_polynomial(major: f64, minor: f64, p: DVec3) -> f64 {
    let ring = p.length_squared() + major * major - minor * minor;
    ring * ring - 4.0 * major * major * (p.x * p.x + p.z * p.z)
}

/// The first `t` in `(t_min, t_max)` where the line `o + t d` crosses the
/// torus of centre `center` (around the y axis), radii `major` and
/// `minor`: the roots of a quartic, found without sphere tracing or
/// Newton's method. The line is first moved to start at its point nearest
/// the centre (so the quartic's coefficients are of the torus's size, not
/// of the origin's); the quartic's real roots are isolated between the
/// roots of its derivatives (a polynomial is monotone between two
/// neighbouring critical points) and each is bisected to the last bit on
/// the polynomial evaluated as written. Only crossings count: a line that
/// touches the surface without entering it (a double root) is a hit only
/// where the polynomial rounds to exactly 0 at the touching point.
pub fn torus(
    center: DVec3,
    major: f64,
    minor: f64,
    o: DVec3,
    d: DVec3,
    t_min: f64,
    t_max: f64,
) -> Option<f64> {
    let oc = o - center;
    let a = d.length_squared();
    if !(a > 0.0) || !a.is_finite() || !oc.is_finite() || !(major > 0.0) || !(minor > 0.0) {
        return None;
    }
    let nearest = -oc.dot(d) / a;
    let q = oc + nearest * d;
    let reach = major + minor;
    if q.length_squared() > reach * reach {
        return None;
    }
    // (|q + s d|^2 + R^2 - r^2)^2 - 4 R^2 ((q + s d).x^2 + (q + s d).z^2)
    // in powers of s: the square of a s^2 + b s + c, less 4 R^2 (e s^2 +
    // f s + g).
    let (b, c) = (
        2.0 * q.dot(d),
        q.length_squared() + major * major - minor * minor,
    );
    let four_r2 = 4.0 * major * major;
    let (e, f, g) = (
        d.x * d.x + d.z * d.z,
        2.0 * (q.x * d.x + q.z * d.z),
        q.x * q.x + q.z * q.z,
    );
    let quartic = [
        c * c - four_r2 * g,
        2.0 * b * c - four_r2 * f,
        b * b + 2.0 * a * c - four_r2 * e,
        2.0 * a * b,
        a * a,
    ];
    // Every root of the line is within the torus's reach of q.
    let bound = 2.0 * reach / a.sqrt();
    let on_line = |s: f64| torus_polynomial(major, minor, q + s * d);
    let mut critical = polynomial_roots(&derivative(&quartic), -bound, bound);
    critical.insert(0, -bound);
    critical.push(bound);
    critical
        .windows(2)
        .filter_map(|pair| bisect(on_line, pair[0], pair[1]))
        .map(|s| nearest + s)
        .find(|&t| t > t_min && t < t_max)
}

/// The first root in `[low, high]` of the polynomial (constant first).
pub fn polynomial_root_in(coefficients: &[f64], low: f64, high: f64) -> Option<f64> {
    polynomial_roots(coefficients, low, high).first().copied()
}

/// The polynomial (constant first) at `x`, in `f64`.
pub fn polynomial(coefficients: &[f64], x: f64) -> f64 {
    evaluate(coefficients, x)
}

/// An implicit surface's function at `p`, in `f64`: the formulas of
/// `shapes::implicit` written again, each evaluated in double precision.
pub fn sdf_distance(tree: &crate::shapes::Sdf, p: DVec3) -> f64 {
    use crate::shapes::Sdf;
    let box_distance = |local: DVec3, half: DVec3| {
        let beyond = local.abs() - half;
        beyond.max(DVec3::ZERO).length() + beyond.max_element().min(0.0)
    };
    match tree {
        Sdf::Sphere { center, radius } => (p - wide(*center)).length() - f64::from(*radius),
        Sdf::Box { center, half_size } => box_distance(p - wide(*center), wide(*half_size)),
        Sdf::RoundBox {
            center,
            half_size,
            radius,
        } => {
            let radius = f64::from(*radius);
            box_distance(p - wide(*center), wide(*half_size) - DVec3::splat(radius)) - radius
        }
        Sdf::Torus {
            center,
            major,
            minor,
        } => {
            let local = p - wide(*center);
            let from_ring = (local.x * local.x + local.z * local.z).sqrt() - f64::from(*major);
            (from_ring * from_ring + local.y * local.y).sqrt() - f64::from(*minor)
        }
        Sdf::Capsule { a, b, radius } => {
            let (a, b) = (wide(*a), wide(*b));
            let along = b - a;
            let share = ((p - a).dot(along) / along.length_squared()).clamp(0.0, 1.0);
            (p - (a + along * share)).length() - f64::from(*radius)
        }
        Sdf::Plane { point, normal } => (p - wide(*point)).dot(wide(*normal)),
        Sdf::Union(shapes) => shapes
            .iter()
            .map(|shape| sdf_distance(shape, p))
            .fold(f64::INFINITY, f64::min),
        Sdf::Intersection(shapes) => shapes
            .iter()
            .map(|shape| sdf_distance(shape, p))
            .fold(f64::NEG_INFINITY, f64::max),
        Sdf::Difference(kept, removed) => sdf_distance(kept, p).max(-sdf_distance(removed, p)),
        Sdf::SmoothUnion {
            shapes: (first, second),
            blend,
        } => {
            let (a, b, k) = (
                sdf_distance(first, p),
                sdf_distance(second, p),
                f64::from(*blend),
            );
            let h = (0.5 + 0.5 * (b - a) / k).clamp(0.0, 1.0);
            b + (a - b) * h - k * h * (1.0 - h)
        }
        Sdf::Translate { offset, shape } => sdf_distance(shape, p - wide(*offset)),
        Sdf::Rotate { rotation, shape } => sdf_distance(shape, rotation.as_dquat().inverse() * p),
        Sdf::Displace {
            amplitude,
            frequency,
            shape,
        } => {
            let w = f64::from(*frequency);
            sdf_distance(shape, p)
                + f64::from(*amplitude) * (w * p.x).sin() * (w * p.y).sin() * (w * p.z).sin()
        }
    }
}

/// The first `t` in `(t_min, t_max)` where the line `o + t d` reaches the
/// surface of `tree`, whose function changes by at most `lipschitz` per
/// unit: safe steps of `|f| / L` in `f64`, which cannot cross the surface,
/// until `|f|` is below `1e-10` of the scene's scale (then the point is
/// within that of the surface, before it). `None` when the line leaves
/// `(t_min, t_max)` first, or after ten million steps (a line that runs
/// along the surface without meeting it).
pub fn first_crossing(
    tree: &crate::shapes::Sdf,
    lipschitz: f64,
    o: DVec3,
    d: DVec3,
    t_min: f64,
    t_max: f64,
) -> Option<f64> {
    let speed = d.length();
    if !(speed > 0.0) || !speed.is_finite() || !o.is_finite() || !(lipschitz > 0.0) {
        return None;
    }
    let scale = 1e-10 * (o.abs().max_element() + 1.0);
    let mut t = t_min;
    for _ in 0..10_000_000 {
        if !(t < t_max) {
            return None;
        }
        let value = sdf_distance(tree, o + t * d).abs();
        if value < scale && t > t_min {
            return Some(t);
        }
        t += (value / lipschitz).max(0.25 * scale) / speed;
    }
    None
}

/// The unit normal of `tree` at `p` as `method` finds it, every
/// evaluation in `f64`: for the analytic gradient, central differences
/// with a step far below any feature and far above `f64`'s rounding (the
/// gradient's direction to about 1e-9); for the differences, the same
/// formula with the same step `h` (what a correct `f32` version
/// approximates, blur included).
pub fn difference_normal(
    tree: &crate::shapes::Sdf,
    p: DVec3,
    method: crate::shapes::NormalMethod,
    h: f64,
) -> DVec3 {
    use crate::shapes::NormalMethod;
    let f = |q: DVec3| sdf_distance(tree, q);
    let central = |h: f64| {
        DVec3::new(
            f(p + h * DVec3::X) - f(p - h * DVec3::X),
            f(p + h * DVec3::Y) - f(p - h * DVec3::Y),
            f(p + h * DVec3::Z) - f(p - h * DVec3::Z),
        )
    };
    let gradient = match method {
        NormalMethod::Analytic => central(1e-6 * (p.abs().max_element() + 1.0)),
        NormalMethod::Central => central(h),
        NormalMethod::Tetrahedron => [
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(-1.0, -1.0, 1.0),
            DVec3::new(-1.0, 1.0, -1.0),
            DVec3::new(1.0, 1.0, 1.0),
        ]
        .into_iter()
        .map(|corner| corner * f(p + h * corner))
        .sum(),
    };
    gradient.normalize_or_zero()
}

/// The coefficients (constant first) of a polynomial's derivative.
fn derivative(coefficients: &[f64]) -> Vec<f64> {
    coefficients
        .iter()
        .enumerate()
        .skip(1)
        .map(|(power, coefficient)| power as f64 * coefficient)
        .collect()
}

fn evaluate(coefficients: &[f64], x: f64) -> f64 {
    coefficients.iter().rev().fold(0.0, |sum, c| sum * x + c)
}

/// The real roots in `[low, high]` of the polynomial (constant first),
/// sorted: those of its derivative split the interval into monotone
/// pieces, each with at most one root.
fn polynomial_roots(coefficients: &[f64], low: f64, high: f64) -> Vec<f64> {
    let degree = coefficients.iter().rposition(|&c| c != 0.0).unwrap_or(0);
    let coefficients = &coefficients[..=degree];
    if degree == 0 {
        return Vec::new();
    }
    if degree == 1 {
        let root = -coefficients[0] / coefficients[1];
        return if (low..=high).contains(&root) {
            vec![root]
        } else {
            Vec::new()
        };
    }
    let mut ends = polynomial_roots(&derivative(coefficients), low, high);
    ends.insert(0, low);
    ends.push(high);
    ends.windows(2)
        .filter_map(|pair| bisect(|x| evaluate(coefficients, x), pair[0], pair[1]))
        .collect()
}

/// The point where `function` changes sign in `[low, high]`, bisected
/// until the interval cannot shrink; `None` without a sign change.
fn bisect(function: impl Fn(f64) -> f64, mut low: f64, mut high: f64) -> Option<f64> {
    let (at_low, at_high) = (function(low), function(high));
    if at_low == 0.0 {
        return Some(low);
    }
    if !(at_low * at_high < 0.0) {
        return None;
    }
    let rising = at_high > 0.0;
    loop {
        let middle = 0.5 * (low + high);
        if middle <= low || middle >= high {
            return Some(middle);
        }
        if (function(middle) > 0.0) == rising {
            high = middle;
        } else {
            low = middle;
        }
    }
}

/// Where the line `origin + t dir` is inside `bounds`: the slab test in
/// `f64`, where `plane - origin` is exact and the division nearly so (the
/// exact answer, to judge the `f32` one by). Empty when `entry > exit`; a
/// zero direction component with the origin on a plane gives NaN, which
/// `f64::max` and `f64::min` skip.
pub fn slab_interval(bounds: &crate::bvh::Aabb, origin: Vec3, dir: Vec3) -> (f64, f64) {
    let (mut entry, mut exit) = (f64::NEG_INFINITY, f64::INFINITY);
    for axis in 0..3 {
        let (o, d) = (f64::from(origin[axis]), f64::from(dir[axis]));
        let a = (f64::from(bounds.min[axis]) - o) / d;
        let b = (f64::from(bounds.max[axis]) - o) / d;
        entry = entry.max(a.min(b));
        exit = exit.min(a.max(b));
    }
    (entry, exit)
}

/// A small deterministic generator (xorshift64), so that a case's many
/// inputs are the same on every run and every machine.
#[derive(Debug, Clone)]
pub struct Xorshift(u64);

impl Xorshift {
    /// Any seed; 0 (which xorshift would never leave) is replaced.
    pub fn new(seed: u64) -> Xorshift {
        Xorshift(if seed == 0 {
            0x9e37_79b9_7f4a_7c15
        } else {
            seed
        })
    }

    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// Uniform in `[low, high)` (24 random bits, as many as an `f32` holds).
    pub fn between(&mut self, low: f32, high: f32) -> f32 {
        let unit = (self.next() >> 40) as f32 / (1u64 << 24) as f32;
        low + unit * (high - low)
    }

    /// Uniform in `0..n`.
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

#[cfg(test)]
mod tests;

/// Chapter 14: what a unit of radiance leaving a point toward a pinhole
/// camera adds to its pixel, per unit of the point's area: the solid angle
/// the area covers, `cos_surface / distance^2`, over the solid angle of the
/// pixel's square, `pixel_area cos_camera^3` (0 where no pixel sees it).
pub fn splat_weight(cos_surface: f64, cos_camera: f64, distance: f64, pixel_area: f64) -> f64 {
    let pixel = pixel_area * cos_camera.powi(3);
    if !(pixel > 0.0 && distance > 0.0 && cos_surface > 0.0) {
        return 0.0;
    }
    (cos_surface / (distance * distance)) / pixel
}

/// Chapter 14: Cauchy's index `a + b / lambda^2`, `lambda` in micrometres.
pub fn cauchy(a: f64, b: f64, nanometres: f64) -> f64 {
    let micrometres = nanometres * 1e-3;
    a + b / (micrometres * micrometres)
}

/// Chapter 14: the smallest deviation, in radians, of a ray through a
/// prism of apex angle `apex` (radians) and index `n` in air, in closed
/// form: at the minimum the ray crosses the prism symmetrically, meeting
/// both faces at `apex / 2` from their normals inside, so Snell's law at
/// the first face gives `sin((deviation + apex) / 2) = n sin(apex / 2)`.
pub fn prism_minimum_deviation(n: f64, apex: f64) -> f64 {
    2.0 * (n * (apex / 2.0).sin()).asin() - apex
}

/// The unpolarised Fresnel reflectance of a dielectric boundary for light
/// meeting it at `cos_i` from index `n1` into `n2`: the mean of the s and
/// p amplitudes squared (Born and Wolf); 1 under total internal
/// reflection.
pub fn fresnel(cos_i: f64, n1: f64, n2: f64) -> f64 {
    let sin_t = n1 / n2 * (1.0 - cos_i * cos_i).max(0.0).sqrt();
    if sin_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t * sin_t).sqrt();
    let s = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    let p = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
    (s * s + p * p) / 2.0
}

/// Chapter 13's density of a cosine-weighted direction at angle `theta`
/// from the normal: `cos(theta) / pi` above the surface, 0 below.
pub fn cosine_pdf(cos_theta: f64) -> f64 {
    cos_theta.max(0.0) / std::f64::consts::PI
}

/// Veach's power heuristic (beta = 2), `a^2 / (a^2 + b^2)`: 0 where
/// neither strategy can draw the direction. In `f64`, no square of an
/// `f32` density overflows.
pub fn power_heuristic(pdf: f64, other: f64) -> f64 {
    if !(pdf.max(other) > 0.0) {
        return 0.0;
    }
    pdf * pdf / (pdf * pdf + other * other)
}

/// Russian roulette: a path of share `weight` goes on when `u <
/// min(1, weight)`, carrying `1 / min(1, weight)` more.
pub fn russian_roulette(weight: f64, u: f64) -> Option<f64> {
    if !(weight > 0.0) {
        return None;
    }
    let survival = weight.min(1.0);
    (u < survival).then(|| 1.0 / survival)
}

/// Chapter 5's Phong terms of one light, `(diffuse, specular)`: `albedo
/// k_d (n.l) light` and `k_s max(r.v, 0)^shininess light`, `r` the light's
/// mirror direction `2 (n.l) n - l`; nothing from a light behind (`n.l <=
/// 0`). `[n, l, v]`: the normal and the directions to the light and to
/// the eye, unit vectors.
pub fn phong_terms(
    k_d: f64,
    k_s: f64,
    shininess: u32,
    albedo: DVec3,
    [n, l, v]: [DVec3; 3],
    light: DVec3,
) -> (DVec3, DVec3) {
    let cos_incidence = n.dot(l);
    if cos_incidence <= 0.0 {
        return (DVec3::ZERO, DVec3::ZERO);
    }
    let mirrored = 2.0 * cos_incidence * n - l;
    let highlight = mirrored.dot(v).max(0.0).powi(shininess as i32);
    (
        albedo * k_d * cos_incidence * light,
        k_s * highlight * light,
    )
}

/// Schlick's approximation of [`fresnel`], `R0 + (1 - R0) (1 - c)^5`,
/// with `c` the cosine on the less dense side: the transmitted ray's when
/// light leaves the denser medium (1 past the critical angle), and no
/// reflection where the two indices are equal.
pub fn schlick(cos_i: f64, n1: f64, n2: f64) -> f64 {
    if n1 == n2 {
        return 0.0;
    }
    let c = if n1 < n2 {
        cos_i
    } else {
        let sin2_t = (n1 / n2).powi(2) * (1.0 - cos_i * cos_i).max(0.0);
        if sin2_t >= 1.0 {
            return 1.0;
        }
        (1.0 - sin2_t).sqrt()
    };
    let r0 = ((n1 - n2) / (n1 + n2)).powi(2);
    r0 + (1.0 - r0) * (1.0 - c).powi(5)
}

/// Chapter 14's lens: a ray parallel to the axis at height `height` through
/// a glass ball of index `n` and radius `radius` centred on the axis, in
/// the plane that holds them both: where it crosses the screen square to
/// the axis at `screen` past the centre (its signed height there), and the
/// share of its light that came through both surfaces (Fresnel, the ray
/// refracted twice). Snell's law in closed form: the ray meets the ball at
/// `sin(i) = height / radius`, bends to `sin(r) = sin(i) / n`, crosses a
/// chord `2 radius cos(r)` and leaves turned by `2 (i - r)` in all.
pub fn ball_lens_ray(n: f64, radius: f64, height: f64, screen: f64) -> (f64, f64) {
    let incidence = (height / radius).asin();
    let refracted = (incidence.sin() / n).asin();
    let turn = incidence - refracted;
    let entry = (height, -(radius * radius - height * height).sqrt());
    let chord = 2.0 * radius * refracted.cos();
    let exit = (entry.0 - chord * turn.sin(), entry.1 + chord * turn.cos());
    let (across, along) = (-(2.0 * turn).sin(), (2.0 * turn).cos());
    let crossed = exit.0 + (screen - exit.1) / along * across;
    let through =
        (1.0 - fresnel(incidence.cos(), 1.0, n)) * (1.0 - fresnel(refracted.cos(), n, 1.0));
    (crossed, through)
}

/// Chapter 14's lens: the irradiance at distance `rho` from the axis on the
/// screen at `screen`, as a multiple of the irradiance of the parallel beam
/// of radius `beam` that enters the ball of [`ball_lens_ray`], counting the
/// light refracted twice. The ring of heights `h .. h + dh` of the beam
/// (area `2 pi h dh`) lands on the ring `rho .. rho + drho` of the screen
/// (area `2 pi rho drho`): the ratio is `through(h) h / (rho |drho / dh|)`,
/// summed over every height that lands at `rho` (found on a fine grid, then
/// by bisection).
pub fn ball_lens_irradiance(n: f64, radius: f64, beam: f64, screen: f64, rho: f64) -> f64 {
    let landing = |height: f64| ball_lens_ray(n, radius, height, screen).0.abs() - rho;
    let steps = 4096;
    let mut total = 0.0;
    for step in 0..steps {
        let (mut low, mut high) = (
            beam * step as f64 / steps as f64,
            beam * (step + 1) as f64 / steps as f64,
        );
        if landing(low).signum() == landing(high).signum() {
            continue;
        }
        for _ in 0..60 {
            let middle = (low + high) / 2.0;
            if landing(middle).signum() == landing(low).signum() {
                low = middle;
            } else {
                high = middle;
            }
        }
        let height = (low + high) / 2.0;
        let delta = 1e-6 * beam;
        let slope = (ball_lens_ray(n, radius, height + delta, screen).0
            - ball_lens_ray(n, radius, height - delta, screen).0)
            / (2.0 * delta);
        let through = ball_lens_ray(n, radius, height, screen).1;
        total += through * height / (rho * slope.abs());
    }
    total
}
