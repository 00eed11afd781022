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
mod tests;
