//! Tests of chapter 3's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

use super::*;
use crate::chapters::Reference;
use crate::{Plane, Shape, Sphere, Vec3};

fn nearest(shapes: &[Shape], ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
    nearest_hit(&Objects::<Reference>::new(shapes), ray, t_min, t_max)
}

/// Three shapes on the +z axis, listed far to near: a wall at z = 10,
/// a sphere spanning z in [5, 7] and a sphere spanning z in [2, 4].
fn three_in_a_row() -> Vec<Shape> {
    vec![
        Plane::new(Vec3::new(0.0, 0.0, 10.0), Vec3::Z).into(),
        Sphere::new(Vec3::new(0.0, 0.0, 6.0), 1.0).into(),
        Sphere::new(Vec3::new(0.0, 0.0, 3.0), 1.0).into(),
    ]
}

#[test]
fn nearest_of_three_is_the_last_listed() {
    let ray = Ray::new(Vec3::ZERO, Vec3::Z);
    let hit = nearest(&three_in_a_row(), &ray, 0.0, f32::INFINITY);
    assert_eq!(hit, Some(Hit { object: 2, t: 2.0 }));
}

#[test]
fn first_hit_takes_list_order_instead() {
    let ray = Ray::new(Vec3::ZERO, Vec3::Z);
    let shapes = three_in_a_row();
    let hit = Objects::<Reference>::new(&shapes).first_hit(&ray, 0.0, f32::INFINITY);
    assert_eq!(hit, Some(Hit { object: 0, t: 10.0 }));
}

#[test]
fn t_max_excludes_everything_beyond() {
    let ray = Ray::new(Vec3::ZERO, Vec3::Z);
    assert_eq!(nearest(&three_in_a_row(), &ray, 0.0, 1.5), None);
    let hit = nearest(&three_in_a_row(), &ray, 4.5, f32::INFINITY);
    assert_eq!(hit, Some(Hit { object: 1, t: 5.0 }));
}

#[test]
fn empty_scene_has_no_hit() {
    let ray = Ray::new(Vec3::ZERO, Vec3::Z);
    assert_eq!(nearest(&[], &ray, 0.0, f32::INFINITY), None);
}
