//! Tests of chapter 11's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

use super::*;
use crate::chapters::Reference;
use crate::{Plane, Shape, Sphere};

fn unit_box() -> Aabb {
    Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0))
}

fn enter(origin: Vec3, dir: Vec3) -> Option<f32> {
    hit_box(&unit_box(), origin, dir.recip(), 0.0, f32::INFINITY)
}

/// `t` within the widening of `expected` (entries move down by 2 γ3).
fn about(t: Option<f32>, expected: f32) -> bool {
    t.is_some_and(|t| t <= expected && t >= expected * (1.0 - 3.0 * GAMMA_3))
}

#[test]
fn from_outside_the_entry_is_the_nearest_face() {
    // Along +x from x = -5: enters the face x = -1 at t = 4.
    assert!(about(enter(Vec3::new(-5.0, 0.0, 0.0), Vec3::X), 4.0));
    // Away from the box, and beyond t_max: no hit.
    assert_eq!(enter(Vec3::new(-5.0, 0.0, 0.0), -Vec3::X), None);
    let origin = Vec3::new(-5.0, 0.0, 0.0);
    assert_eq!(
        hit_box(&unit_box(), origin, Vec3::X.recip(), 0.0, 3.9),
        None
    );
}

#[test]
fn from_inside_the_entry_is_t_min() {
    assert_eq!(enter(Vec3::ZERO, Vec3::new(0.3, -0.2, 1.0)), Some(0.0));
    let inside = hit_box(&unit_box(), Vec3::ZERO, Vec3::X.recip(), 0.5, 10.0);
    assert_eq!(inside, Some(0.5));
}

#[test]
fn parallel_to_a_slab_inside_it_or_outside_it() {
    // dir.y = 0: the y slab holds the line (y = 0.5) or never does (y = 2).
    assert!(about(enter(Vec3::new(0.0, 0.5, -5.0), Vec3::Z), 4.0));
    assert_eq!(enter(Vec3::new(0.0, 2.0, -5.0), Vec3::Z), None);
    // Same with the zero's sign flipped: 1 / -0 = -inf.
    let dir = Vec3::new(0.0, -0.0, 1.0);
    assert!(about(enter(Vec3::new(0.0, 0.5, -5.0), dir), 4.0));
    assert_eq!(enter(Vec3::new(0.0, 2.0, -5.0), dir), None);
}

#[test]
fn zero_direction_component_with_the_origin_on_the_slab_plane() {
    // y = 1 and y = -1 are the box's planes; (plane - origin) * inf is
    // 0 * inf = NaN there. Both signs of zero, both planes: a hit.
    for y in [1.0, -1.0] {
        for zero in [0.0, -0.0] {
            let origin = Vec3::new(0.0, y, -5.0);
            let dir = Vec3::new(0.0, zero, 1.0);
            assert!(about(enter(origin, dir), 4.0), "y = {y}, dir.y = {zero}");
        }
    }
    // A flat box (min.y = max.y = 0) and a ray in its plane: both
    // distances of the y axis are NaN.
    let flat = Aabb::new(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, 1.0));
    let hit = hit_box(&flat, Vec3::new(0.0, 0.0, -5.0), Vec3::Z.recip(), 0.0, 9.0);
    assert!(about(hit, 4.0));
}

#[test]
fn a_ray_along_an_edge_hits() {
    // The line y = 1, z = 1 is an edge of the box: entry = exit on two
    // axes, which rounding must not turn into a miss.
    assert!(about(enter(Vec3::new(-5.0, 1.0, 1.0), Vec3::X), 4.0));
    // Touching the box at one point, the corner (1, 1, 1), at t = 1:
    // entry (x, y planes) and exit (z plane) are both exactly 1.
    let corner = enter(Vec3::new(2.0, 2.0, 0.0), Vec3::new(-1.0, -1.0, 1.0));
    assert!(about(corner, 1.0));
}

fn bounds(shapes: &[Shape]) -> Vec<Option<Aabb>> {
    shapes.iter().map(Shape::bounds).collect()
}

#[test]
fn planes_stay_out_of_the_tree() {
    let shapes: Vec<Shape> = vec![
        Sphere::new(Vec3::new(-3.0, 0.0, 0.0), 1.0).into(),
        Plane::new(Vec3::ZERO, Vec3::Y).into(),
        Sphere::new(Vec3::new(3.0, 0.0, 0.0), 1.0).into(),
    ];
    let options = BvhOptions {
        max_leaf: 1,
        ..BvhOptions::default()
    };
    let bvh = build_bvh(&bounds(&shapes), &options);
    assert_eq!(bvh.unbounded, vec![1]);
    // Two spheres, one per leaf, under one root.
    assert_eq!(bvh.node_count(), 3);
    assert_eq!(bvh.depth(), 2);
    let mut in_tree = bvh.primitives.clone();
    in_tree.sort();
    assert_eq!(in_tree, vec![0, 2]);
}

#[test]
fn non_finite_boxes_are_looped_over_not_built_into_the_tree() {
    let nan = Aabb::new(Vec3::NAN, Vec3::ONE);
    let infinite = Aabb::new(Vec3::NEG_INFINITY, Vec3::ONE);
    let bvh = build_bvh(
        &[
            Some(unit_box()),
            Some(nan),
            Some(infinite),
            Some(Aabb::EMPTY),
        ],
        &BvhOptions::default(),
    );
    assert_eq!(bvh.unbounded, vec![1, 2, 3]);
    assert_eq!(bvh.primitives, vec![0]);
}

#[test]
fn a_tie_goes_to_the_lower_index_as_in_chapter_3() {
    // The same sphere twice, far apart in the tree's leaves if need be.
    let ball: Shape = Sphere::new(Vec3::new(0.0, 0.0, 5.0), 1.0).into();
    let other: Shape = Sphere::new(Vec3::new(10.0, 0.0, 5.0), 1.0).into();
    let shapes = vec![other.clone(), ball.clone(), other, ball];
    let options = BvhOptions {
        max_leaf: 1,
        ..BvhOptions::default()
    };
    let bvh = build_bvh(&bounds(&shapes), &options);
    let ray = Ray::new(Vec3::ZERO, Vec3::Z);
    let objects = Objects::<Reference>::new(&shapes);
    let hit = nearest_hit_bvh(&bvh, &objects, &ray, 0.0, f32::INFINITY);
    assert_eq!(hit, Some(Hit { object: 1, t: 4.0 }));
    assert!(any_hit_bvh(&bvh, &objects, &ray, 0.0, f32::INFINITY).is_some());
    assert_eq!(any_hit_bvh(&bvh, &objects, &ray, 0.0, 3.0), None);
}

// The bug gallery and the accepted alternatives of this chapter.
#[path = "gallery.rs"]
mod gallery;
