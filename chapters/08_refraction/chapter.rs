use raylab::course::{Chapters, HitPoint};
use raylab::render::{RayKind, Tracer};
use raylab::{Ray, Vec3, unit_vector};

/// The unit direction of a ray that crosses a surface, by Snell-Descartes'
/// law `n1 sin(i) = n2 sin(t)`, or `None` under total internal reflection.
///
/// - `d`: incident direction, toward the surface, any non-zero length;
/// - `n`: surface normal, any non-zero length, either orientation;
/// - `eta = n1 / n2`: index of the medium the ray comes from over the index
///   of the medium it enters.
///
/// With unit `d`, and `n` turned to face the incoming ray (`cos i = -d.n > 0`),
/// the refracted direction is `eta d + (eta cos i - cos t) n`, where
/// `sin^2 t = eta^2 sin^2 i` and `cos t = sqrt(1 - sin^2 t)`. When
/// `sin^2 t > 1` no refracted ray exists: that is total internal reflection,
/// which happens past the critical angle `asin(1 / eta)` when `eta > 1`.
/// Degenerate input (zero or non-finite vectors, `eta` not finite and > 0)
/// gives `None`.
pub fn refract(incident: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let d = unit_vector(incident)?;
    let mut n = unit_vector(n)?;
    if !(eta > 0.0 && eta.is_finite()) {
        return None;
    }
    if eta == 1.0 {
        // Same medium on both sides: the ray goes straight on, exactly. A
        // direction that is already unit (its squared length within a few
        // rounding errors of 1) comes back bit for bit: normalising it again
        // could move its last bits, and a no-op must not.
        let already_unit = (incident.length_squared() - 1.0).abs() <= 4.0 * f32::EPSILON;
        return Some(if already_unit { incident } else { d });
    }
    let mut cos_incidence = -d.dot(n);
    if cos_incidence < 0.0 {
        n = -n;
        cos_incidence = -cos_incidence;
    }
    // |d x n|^2 rather than 1 - cos^2: near normal incidence `1 - cos^2`
    // keeps only a few bits of sin^2 i, the cross product all of them. The
    // direction below is no more accurate for it (cos t only needs sin^2 t
    // to an ulp of 1); the lesson measures both.
    let sin2_incidence = d.cross(n).length_squared().min(1.0);
    let sin2_transmitted = eta * eta * sin2_incidence;
    if sin2_transmitted > 1.0 {
        return None;
    }
    let cos_transmitted = (1.0 - sin2_transmitted).sqrt();
    unit_vector(eta * d + (eta * cos_incidence - cos_transmitted) * n)
}

/// The critical angle, in radians, for light going from index `n1` into a
/// lower index `n2`: past it, every ray is totally reflected. `None` when
/// `n1 <= n2` (then every ray can cross) or when either is not a finite
/// positive number.
pub fn critical_angle(n1: f32, n2: f32) -> Option<f32> {
    (n1 > n2 && n2 > 0.0 && n1.is_finite()).then(|| libm::asinf(n2 / n1))
}

/// The colour of a surface that may reflect and let light through: its own
/// light where it is neither mirror nor glass, plus the reflected and the
/// refracted rays, each traced recursively.
///
/// `colour = (1 - k_r - k_t) diffuse + specular + k_r reflected + k_t tint refracted`,
/// where the refracted light is tinted by the material's colour. Every solid
/// is taken to be surrounded by air: the ray is entering when it travels
/// against the outward normal, and then `eta = 1 / ior`, else `eta = ior`.
/// Under total internal reflection no light crosses, so the glass's share
/// joins the mirror's.
pub fn shade_glass<C: Chapters>(
    tracer: &mut Tracer<C>,
    point: &HitPoint,
    depth: u32,
    weight: f32,
) -> Vec3 {
    let local = C::shade_phong(tracer, point);
    let material = &point.material;
    let (k_r, k_t) = (material.reflectivity, material.transparency);
    let mut color = (1.0 - k_r - k_t) * local.diffuse + local.specular;
    if depth >= tracer.max_depth() {
        return color;
    }
    let incoming = point.ray.dir;
    let normal = point.surface.normal;
    let mut reflected_share = k_r;
    if tracer.worth_casting(weight, k_t) {
        let entering = incoming.dot(normal) < 0.0;
        let eta = if entering {
            1.0 / material.ior
        } else {
            material.ior
        };
        match C::refract(incoming, normal, eta) {
            Some(dir) => {
                let refracted = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
                let through =
                    tracer.trace(RayKind::Refraction, &refracted, depth + 1, weight * k_t);
                color += k_t * material.color * through;
            }
            None => reflected_share += k_t,
        }
    }
    if tracer.worth_casting(weight, reflected_share) {
        let dir = C::reflect(incoming, normal);
        let reflected = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
        let seen = tracer.trace(
            RayKind::Reflection,
            &reflected,
            depth + 1,
            weight * reflected_share,
        );
        color += reflected_share * seen;
    }
    color
}

#[cfg(test)]
mod tests;
