use raylab::course::{Chapters, HitPoint};
use raylab::render::{RayKind, Tracer};
use raylab::{Ray, Vec3};

/// The mirror image of the incident direction `d` about the normal `n`.
///
/// `d` points toward the surface; the result points away from it and has
/// the same length as `d`. `n` may have any length and either orientation:
/// it is normalised first, and flipping `n` flips both factors of
/// `2 (d.n) n`, which leaves the product unchanged. Degenerate input gives
/// NaN components, never a plausible-looking direction: a zero or
/// non-finite `n` (it has no direction to mirror about) or a non-finite `d`.
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    // Normalising first keeps n.n from underflowing (n = 1e-30) or
    // overflowing (n = 1e30); the unit normal then needs no division.
    let Some(n) = raylab::unit_vector(n) else {
        return Vec3::NAN;
    };
    if !d.is_finite() {
        return Vec3::NAN;
    }
    // A huge d (components near f32::MAX = 2^128) would overflow 2 (d.n)
    // although the mirrored vector, as long as d, fits. Scaling by a power of
    // two is exact, so reflect d / 2^64 (now below 2^64) and scale back.
    const HUGE: f32 = (1u64 << 63) as f32 * 2.0; // 2^64
    if d.abs().max_element() > HUGE {
        let small = d / HUGE;
        return (small - 2.0 * small.dot(n) * n) * HUGE;
    }
    d - 2.0 * d.dot(n) * n
}

/// A mirror's colour: its own light (chapter 5) where it is not a mirror,
/// plus what the mirror direction sees, traced recursively.
///
/// `colour = (1 - k_r) diffuse + specular + k_r colour(reflected ray)`. The
/// specular highlight is not scaled by `1 - k_r`: it is the light source's
/// own mirror image, which a mirror shows in full. The recursion stops after
/// `max_depth` bounces, and skips rays whose weight in the pixel is too
/// small to see (`min_contribution`).
pub fn shade_mirror<C: Chapters>(
    tracer: &mut Tracer<C>,
    point: &HitPoint,
    depth: u32,
    weight: f32,
) -> Vec3 {
    let local = C::shade_phong(tracer, point);
    let k_r = point.material.reflectivity;
    let mut color = (1.0 - k_r) * local.diffuse + local.specular;
    if depth < tracer.max_depth() && tracer.worth_casting(weight, k_r) {
        let dir = C::reflect(point.ray.dir, point.surface.normal);
        let reflected = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
        color += k_r * tracer.trace(RayKind::Reflection, &reflected, depth + 1, weight * k_r);
    }
    color
}

#[cfg(test)]
mod tests;
