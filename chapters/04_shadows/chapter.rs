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
mod tests {
    use super::*;
    use crate::Scene;
    use crate::render::Stage;

    /// A floor at y = 0 and a unit ball resting on it at the origin.
    fn floor_and_ball() -> Scene {
        let text = r#"
            [camera]
            position = [0.0, 2.0, -6.0]
            look_at = [0.0, 0.0, 0.0]
            [[lights]]
            position = [0.0, 10.0, 0.0]
            [[objects]]
            plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
            [[objects]]
            sphere = { center = [0.0, 1.0, 0.0], radius = 1.0 }
        "#;
        Scene::parse(text, "test").expect("valid scene")
    }

    /// Whether the floor point `(x, 0, z)` is in shadow from a light at `light`.
    fn floor_in_shadow(x: f32, z: f32, light: Vec3) -> bool {
        let scene = floor_and_ball();
        let stage = Stage::new(&scene, 4, scene.render).unwrap();
        let mut tracer = stage.tracer(None);
        let down = Ray::new(Vec3::new(x, 5.0, z), -Vec3::Y);
        let point = tracer.hit_point(0, &down, 5.0);
        in_shadow(&mut tracer, &point, light)
    }

    #[test]
    fn point_under_the_ball_is_in_shadow() {
        assert!(floor_in_shadow(0.2, 0.0, Vec3::new(0.0, 10.0, 0.0)));
    }

    #[test]
    fn point_beside_the_ball_is_lit() {
        assert!(!floor_in_shadow(3.0, 0.0, Vec3::new(0.0, 10.0, 0.0)));
    }

    #[test]
    fn blockers_beyond_the_light_do_not_count() {
        // The ball spans heights 0 to 2; a light at height 0.5 beside it
        // lights the floor point on the far side of the light (t > 1 for the ball).
        assert!(!floor_in_shadow(3.0, 0.0, Vec3::new(2.0, 0.5, 0.0)));
    }

    #[test]
    fn offset_leaves_the_surface_on_the_requested_side() {
        let point = SurfacePoint {
            point: Vec3::new(1000.0, 0.0, -1000.0),
            normal: Vec3::Y,
            error: Vec3::splat(4.0 * f32::EPSILON * 1000.0),
        };
        let up = offset_origin(&point, Vec3::new(0.3, 1.0, 0.0));
        let down = offset_origin(&point, Vec3::new(0.3, -1.0, 0.0));
        assert!(up.y > 0.0 && down.y < 0.0);
        // A few ulps of 1000 (one ulp is 6.1e-5), not a global epsilon.
        assert!(up.y < 1e-2, "offset {}", up.y);
    }

    #[test]
    fn sphere_point_is_projected_onto_the_surface() {
        let ball = crate::Shape::Sphere(crate::Sphere::new(Vec3::new(0.0, 1.0, 0.0), 1.0));
        let ray = Ray::new(Vec3::new(0.0, 1.0, -5.0), Vec3::Z);
        let hit = ball.surface_point(&ray, 4.0);
        assert_eq!(hit.point, Vec3::new(0.0, 1.0, -1.0));
        assert_eq!(hit.normal, -Vec3::Z);
    }
}
