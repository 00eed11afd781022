//! Tests of chapter 10's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

use super::*;

fn unit_right_triangle() -> Triangle {
    // In the plane z = 2, corners (0,0), (1,0), (0,1).
    Triangle::new(
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::new(1.0, 0.0, 2.0),
        Vec3::new(0.0, 1.0, 2.0),
    )
}

#[test]
fn hits_inside_from_both_sides() {
    let triangle = unit_right_triangle();
    let front = Ray::new(Vec3::new(0.25, 0.25, 0.0), Vec3::Z);
    assert_eq!(
        intersect_triangle(&triangle, &front, 0.0, f32::INFINITY),
        Some(2.0)
    );
    let back = Ray::new(Vec3::new(0.25, 0.25, 5.0), -Vec3::Z);
    assert_eq!(
        intersect_triangle(&triangle, &back, 0.0, f32::INFINITY),
        Some(3.0)
    );
}

#[test]
fn misses_outside_and_respects_the_interval() {
    let triangle = unit_right_triangle();
    let outside = Ray::new(Vec3::new(0.75, 0.75, 0.0), Vec3::Z);
    assert_eq!(
        intersect_triangle(&triangle, &outside, 0.0, f32::INFINITY),
        None
    );
    let inside = Ray::new(Vec3::new(0.25, 0.25, 0.0), Vec3::Z);
    assert_eq!(intersect_triangle(&triangle, &inside, 0.0, 2.0), None);
    assert_eq!(intersect_triangle(&triangle, &inside, 2.0, 9.0), None);
}

#[test]
fn a_ray_along_a_shared_edge_is_claimed_by_a_triangle() {
    // Two triangles share the diagonal from (1,0) to (0,1); a ray through
    // its midpoint must hit at least one of them.
    let first = unit_right_triangle();
    let second = Triangle::new(
        Vec3::new(1.0, 0.0, 2.0),
        Vec3::new(1.0, 1.0, 2.0),
        Vec3::new(0.0, 1.0, 2.0),
    );
    let ray = Ray::new(Vec3::new(0.5, 0.5, 0.0), Vec3::Z);
    let hits = [first, second]
        .iter()
        .filter(|t| intersect_triangle(t, &ray, 0.0, f32::INFINITY).is_some())
        .count();
    assert!(hits >= 1);
}

#[test]
fn barycentric_of_the_corners_and_centroid() {
    let triangle = unit_right_triangle();
    assert_eq!(
        barycentric(&triangle, triangle.b()),
        Vec3::new(0.0, 1.0, 0.0)
    );
    let centroid = (triangle.a() + triangle.b() + triangle.c()) / 3.0;
    assert!(barycentric(&triangle, centroid).abs_diff_eq(Vec3::splat(1.0 / 3.0), 1e-6));
}

#[test]
fn terminator_point_moves_out_on_a_convex_patch_only() {
    let triangle = unit_right_triangle();
    let point = Vec3::new(0.25, 0.25, 2.0);
    // Normals tilted outward as on a sphere seen from +z... toward -z.
    let bulging = [
        Vec3::new(-0.3, -0.3, -1.0).normalize(),
        Vec3::new(0.3, -0.3, -1.0).normalize(),
        Vec3::new(-0.3, 0.3, -1.0).normalize(),
    ];
    let lifted = terminator_point(&triangle, &bulging, point);
    assert!(lifted.z < point.z, "{lifted}");
    let flat = [-Vec3::Z; 3];
    assert_eq!(terminator_point(&triangle, &flat, point), point);
}

// The bug gallery and the accepted alternatives of this chapter.
#[path = "gallery.rs"]
mod gallery;
