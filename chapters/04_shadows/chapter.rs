use raylab::course::{Chapters, HitPoint};
use raylab::render::Tracer;
use raylab::shapes::SurfacePoint;
use raylab::{Ray, Vec3};

/// Where to start a secondary ray leaving `surface` in direction `dir`.
///
/// The origin is pushed off the surface along the normal, toward the side
/// the new ray travels to, by the largest distance the rounding error of the
/// point could span in that direction: `|n| . error`. Then each coordinate
/// moves one more float away, because the addition `point + offset` rounds
/// too. The push is a few ulps of the coordinates: invisible, and no bigger
/// far from the origin than it must be, unlike one global epsilon.
///
/// A non-finite point gives NaN (no ray from it hits anything): stepping
/// away from an infinite coordinate would otherwise land on `f32::MAX`, a
/// finite point. A NaN `dir` has no side; the push then goes against the
/// normal, and a ray with that direction hits nothing anyway.
pub fn offset_origin(surface: &SurfacePoint, dir: Vec3) -> Vec3 {
    if !surface.point.is_finite() {
        return Vec3::NAN;
    }
    let distance = surface.normal.abs().dot(surface.error);
    let side = if dir.dot(surface.normal) >= 0.0 {
        1.0
    } else {
        -1.0
    };
    let offset = side * distance * surface.normal;
    let moved = surface.point + offset;
    let away = |coordinate: f32, push: f32| {
        if push > 0.0 {
            coordinate.next_up()
        } else if push < 0.0 {
            coordinate.next_down()
        } else {
            coordinate
        }
    };
    Vec3::new(
        away(moved.x, offset.x),
        away(moved.y, offset.y),
        away(moved.z, offset.z),
    )
}

/// Whether an object lies between `point` and a point light at `light`.
///
/// The shadow ray starts just off the surface, on the light's side (chapter
/// 4's offset, through the tracer so that the comparison setting
/// `ray_offset = "fixed"` can swap it), and runs to the light itself: with
/// `dir = light - origin`, `t` goes from 0 (the origin) to 1 (the light), so
/// any hit with `0 < t < 1` blocks the light and one beyond it does not.
pub fn in_shadow<C: Chapters>(tracer: &mut Tracer<C>, point: &HitPoint, light: Vec3) -> bool {
    let origin = tracer.offset_origin(&point.surface, light - point.surface.point);
    let shadow_ray = Ray::new(origin, light - origin);
    tracer.blocked(&shadow_ray, 0.0, 1.0, point)
}

/// Flat lighting with shadows: the ambient term, plus for every light that
/// reaches the point a constant share `albedo * k_d * light`, whatever the
/// angle (chapter 5 brings the angle in).
pub fn shade_flat<C: Chapters>(tracer: &mut Tracer<C>, point: &HitPoint) -> Vec3 {
    let material = &point.material;
    let mut color = point.albedo * material.ambient * tracer.ambient_light();
    for light in tracer.lights() {
        // A light behind the lit side of the surface shines on nothing here.
        if !point.faces(light.position) || C::in_shadow(tracer, point, light.position) {
            continue;
        }
        color += point.albedo * material.diffuse * light.radiance();
    }
    color
}

#[cfg(test)]
mod tests;
