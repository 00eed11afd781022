//! How much work chapter 11's walks do per ray: the boxes the binary walk
//! tests and the objects it asks, the nodes the wide walk opens and the
//! leaf tests it makes, counted by a variant of the reference chapters
//! that tallies each call and then answers as the reference does.
//!
//! Speed figures say how long a walk takes; these say why. Two walks that
//! test as many boxes and objects but differ in time differ in the price
//! of a test (arithmetic, cache misses, mispredicted branches), not in the
//! tree (`raylab race` prints both).

use std::cell::Cell;

use crate::bvh::{Aabb, Boxes4, Bvh, Triangles4, WideBvh};
use crate::course::{Chapters, Objects};
use crate::render::CastRay;
use crate::shapes::{Plane, Sphere, Triangle};
use crate::{Ray, Shape, Vec3, Vec4};

/// Box and object tests per ray, averaged over a set of rays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkWork {
    /// Slab tests (chapter 11's `hit_box`), the root's included.
    pub boxes_per_ray: f64,
    /// Ray-object tests (planes outside the tree included).
    pub objects_per_ray: f64,
}

/// The wide walk's work per ray, averaged over a set of rays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WideWork {
    /// Nodes opened: four boxes tested at once (`hit_boxes`).
    pub nodes_per_ray: f64,
    /// Leaf tests: four triangles at once (`intersect_triangles`), or one
    /// object of another kind (planes outside the tree included).
    pub leaf_tests_per_ray: f64,
}

thread_local! {
    static BOX_TESTS: Cell<u64> = const { Cell::new(0) };
    static OBJECT_TESTS: Cell<u64> = const { Cell::new(0) };
}

fn tally(counter: &'static std::thread::LocalKey<Cell<u64>>) {
    counter.with(|count| count.set(count.get() + 1));
}

/// The reference chapters, counting their box and object tests.
struct Counting;

impl Chapters for Counting {
    fn intersect_plane(plane: &Plane, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        tally(&OBJECT_TESTS);
        crate::Reference::intersect_plane(plane, ray, t_min, t_max)
    }

    fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        tally(&OBJECT_TESTS);
        crate::Reference::intersect_sphere(sphere, ray, t_min, t_max)
    }

    fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        tally(&OBJECT_TESTS);
        crate::Reference::intersect_triangle(triangle, ray, t_min, t_max)
    }

    fn hit_box(
        bounds: &Aabb,
        origin: Vec3,
        inverse_direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<f32> {
        tally(&BOX_TESTS);
        crate::Reference::hit_box(bounds, origin, inverse_direction, t_min, t_max)
    }

    fn hit_boxes(
        boxes: &Boxes4,
        origin: Vec3,
        inverse_direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Vec4 {
        tally(&BOX_TESTS);
        crate::Reference::hit_boxes(boxes, origin, inverse_direction, t_min, t_max)
    }

    fn intersect_triangles(triangles: &Triangles4, ray: &Ray, t_min: f32, t_max: f32) -> Vec4 {
        tally(&OBJECT_TESTS);
        crate::Reference::intersect_triangles(triangles, ray, t_min, t_max)
    }
}

/// The work of chapter 11's binary nearest-hit walk through `bvh` (built
/// over `shapes`) for each of `rays`, averaged; zero for no rays.
pub fn walk_work(bvh: &Bvh, shapes: &[Shape], rays: &[CastRay]) -> WalkWork {
    let (boxes, objects) = per_ray(
        rays,
        |objects, cast| {
            Counting::nearest_hit_bvh(bvh, objects, &cast.ray, cast.t_min, cast.t_max);
        },
        shapes,
    );
    WalkWork {
        boxes_per_ray: boxes,
        objects_per_ray: objects,
    }
}

/// The work of chapter 11's wide nearest-hit walk through `wide` (built
/// over `shapes`) for each of `rays`, averaged; zero for no rays.
pub fn wide_walk_work(wide: &WideBvh, shapes: &[Shape], rays: &[CastRay]) -> WideWork {
    let (nodes, leaf_tests) = per_ray(
        rays,
        |objects, cast| {
            Counting::nearest_hit_wide(wide, objects, &cast.ray, cast.t_min, cast.t_max);
        },
        shapes,
    );
    WideWork {
        nodes_per_ray: nodes,
        leaf_tests_per_ray: leaf_tests,
    }
}

/// The box tests and object tests `walk` makes per ray, over `rays`.
fn per_ray(
    rays: &[CastRay],
    walk: impl Fn(&Objects<Counting>, &CastRay),
    shapes: &[Shape],
) -> (f64, f64) {
    let objects = Objects::<Counting>::new(shapes);
    let before = (BOX_TESTS.get(), OBJECT_TESTS.get());
    for cast in rays {
        walk(&objects, cast);
    }
    let per_ray = |count: u64| count as f64 / rays.len().max(1) as f64;
    (
        per_ray(BOX_TESTS.get() - before.0),
        per_ray(OBJECT_TESTS.get() - before.1),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RayKind;
    use crate::bvh::BvhNode;

    /// A root over two leaves of one triangle each: a unit triangle in the
    /// plane z = 0 at x in [0, 1], and another at x in [2, 3].
    fn two_leaves() -> (Bvh, Vec<Shape>) {
        let triangle = |x: f32| {
            Shape::Triangle(Triangle::new(
                Vec3::new(x, 0.0, 0.0),
                Vec3::new(x + 1.0, 0.0, 0.0),
                Vec3::new(x, 1.0, 0.0),
            ))
        };
        let shapes = vec![triangle(0.0), triangle(2.0)];
        let leaf = |object: u32, x: f32| BvhNode {
            bounds: Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 0.0)),
            first: object,
            count: 1,
        };
        let root = BvhNode {
            bounds: Aabb::new(Vec3::ZERO, Vec3::new(3.0, 1.0, 0.0)),
            first: 1,
            count: 0,
        };
        let bvh = Bvh {
            nodes: vec![root, leaf(0, 0.0), leaf(1, 2.0)],
            primitives: vec![0, 1],
            unbounded: vec![],
        };
        (bvh, shapes)
    }

    fn down_from(x: f32, y: f32) -> CastRay {
        CastRay {
            kind: RayKind::Primary,
            ray: Ray::new(Vec3::new(x, y, 1.0), -Vec3::Z),
            t_min: 0.0,
            t_max: f32::INFINITY,
        }
    }

    #[test]
    fn counts_the_root_both_children_and_the_one_leaf_entered() {
        let (bvh, shapes) = two_leaves();
        // The root, then both children's boxes; only the first is entered.
        let work = walk_work(&bvh, &shapes, &[down_from(0.25, 0.25)]);
        assert_eq!(work.boxes_per_ray, 3.0);
        assert_eq!(work.objects_per_ray, 1.0);
        // Missing the root ends the walk at one box; averaged with the hit.
        let work = walk_work(&bvh, &shapes, &[down_from(0.25, 0.25), down_from(9.0, 9.0)]);
        assert_eq!(work.boxes_per_ray, 2.0);
        assert_eq!(work.objects_per_ray, 0.5);
    }

    #[test]
    fn the_wide_walk_opens_one_node_and_tests_the_one_leaf_entered() {
        let (bvh, shapes) = two_leaves();
        let wide = crate::Reference::collapse_bvh(&bvh, &shapes);
        // One node holds both leaves; only the first is entered.
        let work = wide_walk_work(&wide, &shapes, &[down_from(0.25, 0.25)]);
        assert_eq!((work.nodes_per_ray, work.leaf_tests_per_ray), (1.0, 1.0));
        let missed = wide_walk_work(&wide, &shapes, &[down_from(9.0, 9.0)]);
        assert_eq!(
            (missed.nodes_per_ray, missed.leaf_tests_per_ray),
            (1.0, 0.0)
        );
    }

    #[test]
    fn no_rays_is_no_work() {
        let (bvh, shapes) = two_leaves();
        let work = walk_work(&bvh, &shapes, &[]);
        assert_eq!((work.boxes_per_ray, work.objects_per_ray), (0.0, 0.0));
    }
}
