use raylab::{Plane, Ray};

/// How close to zero `dot(dir, normal)` may be before we call a ray parallel,
/// as a multiple of `sum |dir_i| |normal_i|`.
///
/// A three-term dot product computed in `f32` is off by at most
/// `gamma_3 = 3u / (1 - 3u)` times that sum (`u = 2^-24`), and the normal we
/// store was rounded when it was normalised (about `2u` more). A computed
/// denominator smaller than this bound could have either sign: the ray is
/// parallel as far as `f32` can tell, and dividing by it would give a
/// meaningless, huge `t`. `4 * f32::EPSILON = 8u` covers both with margin.
pub const PARALLEL_TOLERANCE: f32 = 4.0 * f32::EPSILON;

/// The nearest `t` with `t_min < t < t_max` where `ray` meets `plane`.
///
/// From `dot(origin + t dir - point, normal) = 0`:
/// `t = dot(point - origin, normal) / dot(dir, normal)`.
pub fn intersect_plane(plane: &Plane, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
    let denominator = ray.dir.dot(plane.normal());
    let rounding_bound = PARALLEL_TOLERANCE * ray.dir.abs().dot(plane.normal().abs());
    // Written as `!(a > b)` so that NaN (from a NaN ray or plane) also
    // lands here: a parallel ray, or one lying in the plane, never hits.
    if !(denominator.abs() > rounding_bound) {
        return None;
    }
    let t = (plane.point() - ray.origin).dot(plane.normal()) / denominator;
    // NaN and infinities fail one of these comparisons.
    (t > t_min && t < t_max).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use raylab::Vec3;

    #[test]
    fn floor_seen_from_above_is_hit_at_the_height() {
        let floor = Plane::new(Vec3::ZERO, Vec3::Y);
        let ray = Ray::new(Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
        assert_eq!(floor.intersect(&ray, 0.0, f32::INFINITY), Some(2.0));
    }

    #[test]
    fn slanted_ray_and_unnormalised_normal() {
        // From (0, 3, 0) toward (4, -3, 0): reaches y = 0 at t = 1, the point (4, 0, 0).
        let floor = Plane::new(Vec3::new(10.0, 0.0, -7.0), Vec3::new(0.0, 5.0, 0.0));
        let ray = Ray::new(Vec3::new(0.0, 3.0, 0.0), Vec3::new(4.0, -3.0, 0.0));
        assert_eq!(floor.intersect(&ray, 0.0, f32::INFINITY), Some(1.0));
    }

    #[test]
    fn hit_from_behind_counts() {
        let wall = Plane::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, 1.0));
        let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 0.5));
        assert_eq!(wall.intersect(&ray, 0.0, f32::INFINITY), Some(10.0));
    }

    #[test]
    fn parallel_and_behind_and_out_of_range_miss() {
        let floor = Plane::new(Vec3::ZERO, Vec3::Y);
        let above = Vec3::new(0.0, 1.0, 0.0);
        assert_eq!(floor.intersect(&Ray::new(above, Vec3::X), 0.0, 1e30), None);
        assert_eq!(
            floor.intersect(&Ray::new(Vec3::ZERO, Vec3::Z), -1.0, 1.0),
            None
        );
        assert_eq!(floor.intersect(&Ray::new(above, Vec3::Y), 0.0, 1e30), None);
        assert_eq!(floor.intersect(&Ray::new(above, -Vec3::Y), 0.0, 0.5), None);
    }

    #[test]
    fn degenerate_input_never_hits() {
        let down = Ray::new(Vec3::Y, -Vec3::Y);
        assert_eq!(
            Plane::new(Vec3::ZERO, Vec3::ZERO).intersect(&down, 0.0, 10.0),
            None
        );
        let nan_normal = Plane::new(Vec3::ZERO, Vec3::new(f32::NAN, 1.0, 0.0));
        assert_eq!(nan_normal.intersect(&down, 0.0, 10.0), None);
        let floor = Plane::new(Vec3::ZERO, Vec3::Y);
        assert_eq!(
            floor.intersect(&Ray::new(Vec3::Y, Vec3::ZERO), 0.0, 10.0),
            None
        );
        let nan_origin = Ray::new(Vec3::new(f32::NAN, 1.0, 0.0), -Vec3::Y);
        assert_eq!(floor.intersect(&nan_origin, 0.0, 10.0), None);
        let inf_origin = Ray::new(Vec3::new(0.0, f32::INFINITY, 0.0), -Vec3::Y);
        assert_eq!(floor.intersect(&inf_origin, 0.0, f32::INFINITY), None);
    }
}
