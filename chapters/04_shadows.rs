#![doc = include_str!("04_shadows.md")]

use crate::chapters::ch03_nearest::{Hit, first_hit};
use crate::{Ray, Shape, Vec3, unit_vector};

/// How many `f32::EPSILON`s (each `2u`, `u = 2^-24`) of the coordinates
/// involved we allow as error in a hit point after it is projected back onto
/// its surface. The projection takes a handful of roundings (a difference, a
/// normalisation, a product, a sum), each adding at most `u` of the
/// magnitudes it touches; `4 * EPSILON = 8u` bounds them with margin.
pub const SURFACE_ERROR_EPSILONS: f32 = 4.0;

/// A point on a surface, known well enough to start a new ray from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// The hit point, projected back onto the surface.
    pub point: Vec3,
    /// The geometric unit normal: outward for spheres, as given for planes.
    pub normal: Vec3,
    /// A bound on the absolute error of each coordinate of `point`.
    pub error: Vec3,
}

/// The surface point where `ray` meets `shape` at parameter `t`.
///
/// `ray.at(t)` carries the error of `t`, which grows with the length of the
/// ray: a hit 1000 units away can be off the surface by a visible fraction of
/// a unit. Projecting it back onto the exact surface leaves an error that
/// only depends on the size of the surface's own coordinates, and that we
/// can bound.
pub fn surface_point(shape: &Shape, ray: &Ray, t: f32) -> SurfacePoint {
    let on_ray = ray.at(t);
    let scale = SURFACE_ERROR_EPSILONS * f32::EPSILON;
    match shape {
        Shape::Sphere(sphere) | Shape::TextbookSphere(sphere) => {
            let center = sphere.center();
            let radius = sphere.radius();
            // A ray that hits a sphere exactly at its centre cannot exist
            // (the centre is inside), so this fallback is only for NaN input.
            let normal = unit_vector(on_ray - center).unwrap_or(Vec3::Y);
            let point = center + radius * normal;
            SurfacePoint {
                point,
                normal,
                error: scale * (center.abs() + Vec3::splat(radius)),
            }
        }
        Shape::Plane(plane) => {
            let normal = plane.normal();
            let point = on_ray - normal * (on_ray - plane.point()).dot(normal);
            // The projection's dot product mixes all three coordinates, so
            // the bound uses the largest of them for every axis.
            let magnitude = point.abs().max_element() + plane.point().abs().max_element();
            SurfacePoint {
                point,
                normal,
                error: Vec3::splat(scale * magnitude),
            }
        }
    }
}

/// Where to start a secondary ray leaving `surface` in direction `dir`.
///
/// The origin is pushed off the surface along the normal, toward the side
/// the new ray travels to, by the largest distance the rounding error of the
/// point could span in that direction: `|n| . error`. Then each coordinate
/// moves one more float away, because the addition `point + offset` rounds
/// too. The push is a few ulps of the coordinates: invisible, and no bigger
/// far from the origin than it must be, unlike one global epsilon.
pub fn offset_origin(surface: &SurfacePoint, dir: Vec3) -> Vec3 {
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

/// How secondary rays leave a surface.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum RayOffset {
    /// [`offset_origin`]: a push scaled to the point's rounding error.
    #[default]
    Scaled,
    /// The textbook fix: start `epsilon` along the new ray, whatever the
    /// scene's size (the same as ignoring hits with `t < epsilon`). Too small
    /// and far surfaces shadow themselves (acne); too large and shadows
    /// detach from the objects that cast them. Kept for comparison.
    Fixed(f32),
}

impl RayOffset {
    /// Where a secondary ray leaving `surface` in direction `dir` starts.
    pub fn origin(self, surface: &SurfacePoint, dir: Vec3) -> Vec3 {
        match self {
            RayOffset::Scaled => offset_origin(surface, dir),
            RayOffset::Fixed(epsilon) => surface.point + epsilon * dir.normalize_or_zero(),
        }
    }
}

/// The shadow ray from `surface` to a point light at `light`: it starts just
/// off the surface, on the light's side, and `t` runs from 0 (the surface)
/// to 1 (the light), so any hit with `0 < t < 1` blocks the light.
pub fn shadow_ray_from(surface: &SurfacePoint, light: Vec3, offset: RayOffset) -> Ray {
    let origin = offset.origin(surface, light - surface.point);
    Ray::new(origin, light - origin)
}

/// The first shape between `surface` and the light, if any.
///
/// Any blocker will do, so `first_hit` stops at the first it finds: the
/// nearest is not needed. Returns `None` when the light is visible.
pub fn shadow_blocker(shapes: &[Shape], surface: &SurfacePoint, light: Vec3) -> Option<Hit> {
    first_hit(
        shapes,
        &shadow_ray_from(surface, light, RayOffset::Scaled),
        0.0,
        1.0,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Plane, Sphere};

    fn floor_and_ball() -> Vec<Shape> {
        vec![
            Plane::new(Vec3::ZERO, Vec3::Y).into(),
            Sphere::new(Vec3::new(0.0, 1.0, 0.0), 1.0).into(),
        ]
    }

    fn floor_point(x: f32, z: f32) -> SurfacePoint {
        let shapes = floor_and_ball();
        let ray = Ray::new(Vec3::new(x, 5.0, z), -Vec3::Y);
        surface_point(&shapes[0], &ray, 5.0)
    }

    #[test]
    fn point_under_the_ball_is_in_shadow() {
        let light = Vec3::new(0.0, 10.0, 0.0);
        let blocker = shadow_blocker(&floor_and_ball(), &floor_point(0.2, 0.0), light);
        assert_eq!(blocker.map(|hit| hit.object), Some(1));
    }

    #[test]
    fn point_beside_the_ball_is_lit() {
        let light = Vec3::new(0.0, 10.0, 0.0);
        assert_eq!(
            shadow_blocker(&floor_and_ball(), &floor_point(3.0, 0.0), light),
            None
        );
    }

    #[test]
    fn blockers_beyond_the_light_do_not_count() {
        // A ball hangs at height 5, above a light at height 2: the floor
        // under the light sees the light, and the ball only past it (t > 1).
        let shapes: Vec<Shape> = vec![
            Plane::new(Vec3::ZERO, Vec3::Y).into(),
            Sphere::new(Vec3::new(0.0, 5.0, 0.0), 1.0).into(),
        ];
        let light = Vec3::new(0.0, 2.0, 0.0);
        assert_eq!(shadow_blocker(&shapes, &floor_point(0.0, 0.0), light), None);
    }

    #[test]
    fn offset_leaves_the_surface_on_the_requested_side() {
        let point = floor_point(1000.0, -1000.0);
        assert_eq!(point.point.y, 0.0);
        let up = offset_origin(&point, Vec3::new(0.3, 1.0, 0.0));
        let down = offset_origin(&point, Vec3::new(0.3, -1.0, 0.0));
        assert!(up.y > 0.0 && down.y < 0.0);
        // A few ulps of 1000 (one ulp is 6.1e-5), not a global epsilon.
        assert!(up.y < 1e-2, "offset {}", up.y);
    }

    #[test]
    fn sphere_point_is_projected_onto_the_surface() {
        let ball = Sphere::new(Vec3::new(0.0, 1.0, 0.0), 1.0);
        let ray = Ray::new(Vec3::new(0.0, 1.0, -5.0), Vec3::Z);
        let hit = surface_point(&Shape::Sphere(ball), &ray, 4.0);
        assert_eq!(hit.point, Vec3::new(0.0, 1.0, -1.0));
        assert_eq!(hit.normal, -Vec3::Z);
    }
}
