use raylab::{Ray, Sphere, Vec3};

/// Both parameters where the ray's line meets the sphere, smaller first,
/// or `None` when it misses (or the input is degenerate).
///
/// With `oc = origin - center`, `|oc + t dir|^2 = r^2` is the quadratic
/// `a t^2 + 2 h t + c = 0` with `a = dir.dir`, `h = dir.oc`,
/// `c = oc.oc - r^2`. Its quarter-discriminant `h^2 - a c` is computed as
/// `a (r - l)(r + l)`, where `l` is the distance from the centre to the
/// line, and the roots as `q / a` and `c / q` with `q = -(h + sign(h) sqrt(h^2 - a c))`:
/// no subtraction of two large, nearly equal numbers anywhere (the lesson
/// derives both forms).
#[inline]
pub fn sphere_roots(sphere: &Sphere, ray: &Ray) -> Option<(f32, f32)> {
    roots_unless_behind(sphere, ray, false)
}

/// [`sphere_roots`], or `None` early when `skip_behind` is set and both
/// roots are certainly negative.
#[inline(always)]
fn roots_unless_behind(sphere: &Sphere, ray: &Ray, skip_behind: bool) -> Option<(f32, f32)> {
    let oc = ray.origin - sphere.center();
    let a = ray.dir.dot(ray.dir);
    let oc_squared = oc.dot(oc);
    let r_squared = sphere.radius() * sphere.radius();
    // `a`, `oc.oc` and `r^2` are squares of lengths, and the discriminant
    // is a product of two of them: while each lies in [2^-60, 2^60], no
    // intermediate comes near the limits of `f32` (2^-126, 2^128). That
    // is every ordinary scene; the rest (and NaN) takes the slow path.
    let safe = |x: f32| x > SAFE_SQUARE_MIN && x < SAFE_SQUARE_MAX;
    if safe(a) && oc_squared < SAFE_SQUARE_MAX && safe(r_squared) {
        let c = oc_squared - r_squared;
        let h = ray.dir.dot(oc);
        // Origin outside (c > 0) and heading away (h > 0): then
        // q = -(h + sqrt(..)) < 0, so both roots, q / a and c / q, are
        // negative. A caller that wants only t >= 0 learns "miss" without
        // a square root or a division, with exactly the answer `solve`
        // would give: most shadow rays pass most spheres this way.
        if skip_behind && c > 0.0 && h > 0.0 {
            return None;
        }
        solve(ray.dir, oc, a, h, c, sphere.radius())
    } else {
        rescaled_roots(ray.dir, oc, sphere.radius())
    }
}

/// `roots` for sizes outside the safe range: a direction of length 1e20
/// or an `|oc|` of 1e20 overflows (1e40), a direction of length 1e-21
/// underflows to a subnormal that keeps a few bits. Dividing the
/// direction, and `oc` and `r`, by powers of two that bring their largest
/// component near 1 is exact, so nothing else changes, and nothing
/// overflows.
#[cold]
fn rescaled_roots(dir: Vec3, oc: Vec3, radius: f32) -> Option<(f32, f32)> {
    let dir_exponent = binary_exponent(dir.abs().max_element())?;
    let dir = scale_by_power_of_two(dir, -dir_exponent);
    let oc_exponent = binary_exponent(oc.abs().max_element().max(radius))?;
    let oc = scale_by_power_of_two(oc, -oc_exponent);
    let radius = libm::ldexpf(radius, -oc_exponent);
    let (a, h, c) = (dir.dot(dir), dir.dot(oc), oc.dot(oc) - radius * radius);
    // Here the sizes are near 1, but the sphere may be tiny beside them: a
    // ball of radius 1 seen from 1e23 has radius 1e-23 now, and so may the
    // line's distance `l` from its centre. Squared, 1e-46 underflows to 0,
    // and `solve` would find l = 0 < r: a hit for a line that misses by
    // miles. Measure `l` by its largest component first (as `unit_vector`
    // does) and reject the misses here.
    let foot = oc - (h / a) * dir;
    let largest = foot.abs().max_element();
    let l = if largest > 0.0 {
        largest * (foot / largest).length()
    } else {
        0.0
    };
    if !(l <= radius) {
        return None;
    }
    let (t0, t1) = solve(dir, oc, a, h, c, radius)?;
    // Back to units of the caller's direction: t scales as |oc| / |dir|.
    let rescale = |t: f32| libm::ldexpf(t, oc_exponent - dir_exponent);
    Some((rescale(t0), rescale(t1)))
}

/// The roots from `a = dir.dir`, `h = dir.oc` and `c = oc.oc - r^2`,
/// sizes safe.
#[inline(always)]
fn solve(dir: Vec3, oc: Vec3, a: f32, h: f32, c: f32, radius: f32) -> Option<(f32, f32)> {
    // The foot of the perpendicular from the centre to the line is
    // `oc - (h / a) dir`; its length `l` is accurate even when `|oc|` is
    // huge compared with `r`.
    let foot = oc - (h / a) * dir;
    let l = foot.length();
    let quarter_discriminant = a * ((radius - l) * (radius + l));
    // `!(x >= 0)` also rejects NaN (zero direction, NaN input).
    if !(quarter_discriminant >= 0.0) {
        return None;
    }
    let q = -(h + quarter_discriminant.sqrt().copysign(h));
    let t0 = q / a;
    // q = 0 only when the origin is the tangent point itself: both roots are t0.
    let t1 = if q != 0.0 { c / q } else { t0 };
    Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
}

/// The nearest `t` with `t_min < t < t_max` where `ray` meets the sphere.
/// When the point at `t_min` is outside the sphere that is the near root;
/// inside, the far one.
///
/// Each root is only known to within its rounding error, so "beyond
/// `t_min`" must mean beyond it by more than that: a ray leaving the
/// sphere's own surface has a root within rounding of its origin, on either
/// side of it, and must not meet it again there (whatever `t_min` the
/// caller passes). The lesson's "Roots near `t_min`" gives bound and rule.
pub fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
    let roots = roots_unless_behind(sphere, ray, t_min >= 0.0)?;
    choose_root(sphere, ray, roots, t_min, t_max)
}

/// The root of `roots` (from [`sphere_roots`]) that [`intersect_sphere`]
/// reports, if any, given their error bounds:
///
/// 1. The near root certainly beyond `t_min`: the line enters the sphere
///    ahead, and that is the hit.
/// 2. The near root certainly not beyond `t_min`: the point at `t_min` is
///    inside (or past the sphere). The far root is the hit, if it is
///    certainly beyond `t_min`; if it is within rounding of `t_min`, the ray
///    is leaving the surface right there, and that is no hit.
/// 3. The near root within rounding of `t_min`: the ray starts where it
///    enters the sphere, and `f32` cannot tell on which side. A ray that
///    left this sphere inward was pushed inside by chapter 4, well past this
///    band, so it is one that starts just outside, from another surface (a
///    glass ball resting on a huge ground sphere), or just inside. Rejecting
///    the near root and taking the far one, as if the origin were inside,
///    would send it to the other side of the ground, 1e5 away. The roots
///    are solved again in `f64`, where the difference of two `f32`
///    coordinates is exact: near root beyond `t_min`, it is the hit; else,
///    on to the far root as in 2.
pub fn choose_root(
    sphere: &Sphere,
    ray: &Ray,
    roots: (f32, f32),
    t_min: f32,
    t_max: f32,
) -> Option<f32> {
    let (near, far) = roots;
    let near_error = root_error(sphere, ray, roots, near);
    if near - near_error > t_min {
        return (near < t_max).then_some(near);
    }
    if near + near_error > t_min {
        let (exact_near, _) = roots_f64(sphere, ray)?;
        if exact_near > f64::from(t_min) {
            // Rounded to f32 it may land on t_min itself; one step beyond.
            let t = (exact_near as f32).max(t_min.next_up());
            return (t < t_max).then_some(t);
        }
    }
    let far_error = root_error(sphere, ray, roots, far);
    (far - far_error > t_min && far < t_max).then_some(far)
}

/// How many `f32::EPSILON`s (each `2u`) of its error scale a root may be
/// off by: each root takes a dozen roundings in a row (`oc`, two dot
/// products, the foot, its length, `r - l`, `r + l`, a product, a square
/// root, `q`, a division), each at most `u` of what it touches.
/// `tests/course/hard_cases.rs` checks the bound on random rays and huge spheres.
pub const ROOT_ERROR_EPSILONS: f64 = 8.0;

/// A bound on the rounding error of the root `t`, one of `roots` from
/// [`sphere_roots`], in units of `t`.
///
/// The root is `projection ∓ half_chord` along the ray (in distance; in
/// `t`, divided by `|D|`). The projection carries a few roundings of
/// `|O - C|`; the half chord `W = sqrt(r^2 - l^2)` turns an error `δl` of
/// the line's distance `l <= r` into `l δl / W <= r δl / W`, large as the
/// ray nears tangency (`W -> 0`). The last division adds a few `u` of `t`
/// itself. So, with `W = (t1 - t0) |D| / 2` read off the roots:
///
/// `error = ROOT_ERROR_EPSILONS eps ((|O - C| (1 + r / W) + r) / |D| + |t|)`
///
/// For a ray leaving a sphere of radius 1e5 at 45 degrees that is about
/// 0.3 (`tests/course/hard_cases.rs` measures the actual error at under a tenth of
/// the bound): far more than the renderer's `t_min = 0` or any fixed
/// epsilon a caller might pass. Computed in `f64` so that the bound itself neither
/// overflows nor underflows where the roots do not.
pub fn root_error(sphere: &Sphere, ray: &Ray, roots: (f32, f32), t: f32) -> f32 {
    let length = |v: [f64; 3]| dot_f64(v, v).sqrt();
    let speed = length(wide(ray.dir));
    let distance = length(sub_f64(wide(ray.origin), wide(sphere.center())));
    let radius = f64::from(sphere.radius());
    let half_chord = (f64::from(roots.1) - f64::from(roots.0)) * speed / 2.0;
    let scale = (distance * (1.0 + radius / half_chord) + radius) / speed + f64::from(t).abs();
    (ROOT_ERROR_EPSILONS * f64::from(f32::EPSILON) * scale) as f32
}

/// Both roots in `f64`, or `None` when the line misses. `O - C` is exact
/// in `f64` (two `f32` coordinates whose exponents differ by at most 29),
/// so a point 0.003 above a sphere of radius 1e5 stays 0.003 above it, where
/// the `f32` difference rounds to a multiple of 0.0078.
fn roots_f64(sphere: &Sphere, ray: &Ray) -> Option<(f64, f64)> {
    let (d, oc) = (
        wide(ray.dir),
        sub_f64(wide(ray.origin), wide(sphere.center())),
    );
    let a = dot_f64(d, d);
    // The point of the line closest to the centre, at `t = mid`.
    let mid = -dot_f64(d, oc) / a;
    let foot = [oc[0] + mid * d[0], oc[1] + mid * d[1], oc[2] + mid * d[2]];
    let (r, l) = (f64::from(sphere.radius()), dot_f64(foot, foot).sqrt());
    let half = ((r - l) * (r + l) / a).sqrt();
    // NaN (no real root, or degenerate input) fails this test.
    (half >= 0.0).then_some((mid - half, mid + half))
}

fn wide(v: Vec3) -> [f64; 3] {
    [f64::from(v.x), f64::from(v.y), f64::from(v.z)]
}

fn sub_f64(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot_f64(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The textbook solution, `(-b ± sqrt(b^2 - 4ac)) / 2a`, kept for
/// comparison: `b^2 - 4ac` subtracts two huge, nearly equal numbers when
/// the sphere is small and far away, and `-b + sqrt(...)` cancels
/// whenever one root is much smaller than the other. The lesson shows the
/// picture this gives; `raylab cost` measures it.
pub fn intersect_sphere_textbook(
    sphere: &Sphere,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<f32> {
    let oc = ray.origin - sphere.center();
    let a = ray.dir.dot(ray.dir);
    let b = 2.0 * ray.dir.dot(oc);
    let c = oc.dot(oc) - sphere.radius() * sphere.radius();
    let discriminant = b * b - 4.0 * a * c;
    if !(discriminant >= 0.0) {
        return None;
    }
    let root = discriminant.sqrt();
    let near = (-b - root) / (2.0 * a);
    let far = (-b + root) / (2.0 * a);
    first_root_in(near, far, t_min, t_max)
}

/// The first of two roots, `near <= far`, inside `(t_min, t_max)`: from
/// outside the sphere the near one, from inside the far one.
#[inline(always)]
fn first_root_in(near: f32, far: f32, t_min: f32, t_max: f32) -> Option<f32> {
    if near > t_min && near < t_max {
        Some(near)
    } else if far > t_min && far < t_max {
        Some(far)
    } else {
        None
    }
}

/// Squared lengths for which `roots` needs no rescaling: 2^-60 to 2^60, so
/// lengths from about 1e-9 to 1e9.
const SAFE_SQUARE_MIN: f32 = 1.0 / (1u64 << 60) as f32;
const SAFE_SQUARE_MAX: f32 = (1u64 << 60) as f32;

/// The `e` with `2^(e-1) <= x < 2^e`, or `None` when `x` is not `> 0` and finite.
fn binary_exponent(x: f32) -> Option<i32> {
    (x > 0.0 && x.is_finite()).then(|| libm::frexpf(x).1)
}

/// `v * 2^exponent`: only the exponents change, so nothing is rounded
/// (unless a component leaves the range of `f32`).
fn scale_by_power_of_two(v: Vec3, exponent: i32) -> Vec3 {
    Vec3::new(
        libm::ldexpf(v.x, exponent),
        libm::ldexpf(v.y, exponent),
        libm::ldexpf(v.z, exponent),
    )
}

#[cfg(test)]
mod tests;
