#![doc = include_str!(concat!(env!("OUT_DIR"), "/lessons/02_sphere.md"))]

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
/// From inside the sphere that is the far root; from outside, the near one.
pub fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
    let (near, far) = roots_unless_behind(sphere, ray, t_min >= 0.0)?;
    first_root_in(near, far, t_min, t_max)
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
mod tests {
    use super::*;

    fn unit_sphere_at_z5() -> Sphere {
        Sphere::new(Vec3::new(0.0, 0.0, 5.0), 1.0)
    }

    #[test]
    fn the_behind_shortcut_never_changes_an_answer() {
        // Rays from all around a ball, many heading away from it, some
        // starting on or inside it: intersect (with the shortcut) must give
        // exactly what the full roots give.
        let random = |i: u32, d: u32| {
            crate::chapters::ch07_antialiasing::unit_random(7, (i, 0), 0, d) * 2.0 - 1.0
        };
        let ball = Sphere::new(Vec3::new(0.5, -0.25, 2.0), 1.5);
        let mut shortcuts = 0;
        for i in 0..20_000 {
            let origin = ball.center() + 4.0 * Vec3::new(random(i, 0), random(i, 1), random(i, 2));
            let dir = Vec3::new(random(i, 3), random(i, 4), random(i, 5));
            let ray = Ray::new(origin, dir);
            for (t_min, t_max) in [(0.0, f32::INFINITY), (1e-3, 2.0), (-1.0, f32::INFINITY)] {
                let full = ball
                    .roots(&ray)
                    .and_then(|(near, far)| first_root_in(near, far, t_min, t_max));
                assert_eq!(ball.intersect(&ray, t_min, t_max), full, "{ray:?}");
            }
            let oc = origin - ball.center();
            shortcuts += usize::from(oc.length() > 1.5 && dir.dot(oc) > 0.0);
        }
        assert!(
            shortcuts > 5_000,
            "the shortcut was taken {shortcuts} times"
        );
    }

    #[test]
    fn both_roots_of_a_central_ray() {
        // From the origin along +z: the surface is at z = 4 and z = 6.
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(unit_sphere_at_z5().roots(&ray), Some((4.0, 6.0)));
        assert_eq!(
            unit_sphere_at_z5().intersect(&ray, 0.0, f32::INFINITY),
            Some(4.0)
        );
    }

    #[test]
    fn t_is_in_units_of_the_direction() {
        let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0));
        assert_eq!(
            unit_sphere_at_z5().intersect(&ray, 0.0, f32::INFINITY),
            Some(2.0)
        );
    }

    #[test]
    fn origin_inside_takes_the_far_root() {
        let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::Z);
        assert_eq!(unit_sphere_at_z5().roots(&ray), Some((-1.0, 1.0)));
        assert_eq!(
            unit_sphere_at_z5().intersect(&ray, 0.0, f32::INFINITY),
            Some(1.0)
        );
    }

    #[test]
    fn sphere_behind_and_beside_is_missed() {
        let behind = Ray::new(Vec3::ZERO, -Vec3::Z);
        assert_eq!(
            unit_sphere_at_z5().intersect(&behind, 0.0, f32::INFINITY),
            None
        );
        let beside = Ray::new(Vec3::new(2.0, 0.0, 0.0), Vec3::Z);
        assert_eq!(unit_sphere_at_z5().roots(&beside), None);
    }

    #[test]
    fn tangent_ray_has_a_double_root() {
        let ray = Ray::new(Vec3::new(1.0, 0.0, 0.0), Vec3::Z);
        assert_eq!(unit_sphere_at_z5().roots(&ray), Some((5.0, 5.0)));
    }

    #[test]
    fn degenerate_spheres_and_rays_never_hit() {
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        for radius in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let sphere = Sphere::new(Vec3::new(0.0, 0.0, 5.0), radius);
            assert_eq!(
                sphere.intersect(&ray, 0.0, f32::INFINITY),
                None,
                "radius {radius}"
            );
        }
        let zero_dir = Ray::new(Vec3::ZERO, Vec3::ZERO);
        assert_eq!(
            unit_sphere_at_z5().intersect(&zero_dir, 0.0, f32::INFINITY),
            None
        );
        let nan_dir = Ray::new(Vec3::ZERO, Vec3::new(0.0, f32::NAN, 1.0));
        assert_eq!(
            unit_sphere_at_z5().intersect(&nan_dir, 0.0, f32::INFINITY),
            None
        );
    }

    #[test]
    fn textbook_formula_agrees_on_an_easy_case() {
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(
            unit_sphere_at_z5().intersect_textbook(&ray, 0.0, f32::INFINITY),
            Some(4.0)
        );
    }
}
