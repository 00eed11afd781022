//! Tests of chapter 1's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

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
