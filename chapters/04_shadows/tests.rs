//! Tests of chapter 4's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

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
