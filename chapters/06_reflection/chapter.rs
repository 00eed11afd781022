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
/// small to see (`min_contribution`). The mirror direction is about the
/// shading normal `point.normal`, as the Phong terms are, unless that image
/// points into the surface (the lesson's "Which normal").
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
        let dir = mirror_direction::<C>(point);
        let reflected = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
        color += k_r * tracer.trace(RayKind::Reflection, &reflected, depth + 1, weight * k_r);
    }
    color
}

/// The direction a mirror at `point` sends the ray `point.ray` on: its
/// mirror image about the shading normal `point.normal`, the normal the
/// point is lit with. On a plane or a sphere that is the geometric normal
/// (turned toward the ray), so nothing changes there; on a smooth mesh
/// (chapter 10) it is the blended vertex normal, and the mirror shows a
/// curved surface's image instead of the facets' (pbrt-v4, section 9.1:
/// every reflection is computed in the shading frame).
///
/// A shading normal can tilt so far from the facet that this mirror image
/// points *into* the surface (a grazing ray near a silhouette): the ray
/// would start below the triangle and see the inside of the mesh. There,
/// and only there, the direction is the mirror image about the geometric
/// normal, which always leaves on the side the ray came from. Which side is
/// which is the geometric normal's to say, as for chapter 4's offset.
fn mirror_direction<C: Chapters>(point: &HitPoint) -> Vec3 {
    let incoming = point.ray.dir;
    let geometric = point.surface.normal;
    // +1 when the ray came from the side the geometric normal points to.
    let eye_side = if incoming.dot(geometric) < 0.0 {
        1.0
    } else {
        -1.0
    };
    let shaded = C::reflect(incoming, point.normal);
    if eye_side * shaded.dot(geometric) > 0.0 {
        shaded
    } else {
        C::reflect(incoming, geometric)
    }
}

#[cfg(test)]
mod tests;
