//! Tests of chapter 11's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

use super::*;
use crate::chapters::Reference;
use crate::shapes::Triangle;
use crate::{Plane, Sphere};

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

/// A small deterministic source of numbers for the comparisons below.
struct Numbers(u64);

impl Numbers {
    fn between(&mut self, low: f32, high: f32) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        low + (self.0 >> 40) as f32 / (1u64 << 24) as f32 * (high - low)
    }

    fn point(&mut self, extent: f32) -> Vec3 {
        Vec3::new(
            self.between(-extent, extent),
            self.between(-extent, extent),
            self.between(-extent, extent),
        )
    }
}

#[test]
fn hit_boxes_is_hit_box_on_every_lane_bit_for_bit() {
    let mut numbers = Numbers(0x5eed);
    let unit = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
    for round in 0..5_000 {
        let mut boxes = Boxes4::EMPTY;
        let mut lanes = [Aabb::EMPTY; WIDTH];
        for (lane, bounds) in lanes.iter_mut().enumerate().skip(round % 2) {
            let (a, b) = (numbers.point(3.0), numbers.point(3.0));
            *bounds = Aabb::new(a.min(b), a.max(b));
            boxes.set(lane, *bounds);
        }
        // Every few rounds the unit cube, and a ray along its face with
        // zero components: the NaN crossings.
        let (origin, dir) = if round % 7 == 0 {
            lanes[WIDTH - 1] = unit;
            boxes.set(WIDTH - 1, unit);
            (Vec3::new(0.0, 1.0, -5.0), Vec3::new(0.0, -0.0, 1.0))
        } else {
            (numbers.point(6.0), numbers.point(1.0))
        };
        let (t_min, t_max) = (numbers.between(-1.0, 1.0), numbers.between(0.0, 20.0));
        let inverse = dir.recip();
        let four = hit_boxes(&boxes, origin, inverse, t_min, t_max);
        for (lane, bounds) in lanes.iter().enumerate() {
            let one = hit_box(bounds, origin, inverse, t_min, t_max);
            assert_eq!(
                one.map(f32::to_bits),
                (!four[lane].is_nan()).then(|| four[lane].to_bits()),
                "round {round}, lane {lane}"
            );
        }
    }
}

#[test]
fn intersect_triangles_is_intersect_triangle_on_every_lane_bit_for_bit() {
    let mesh = raylab::mesh::generate_closed_mesh(200).expect("the generator makes a model");
    let triangles: Vec<Triangle> = mesh
        .triangles
        .iter()
        .map(|corners| {
            let [a, b, c] = corners.map(|index| mesh.positions[index as usize]);
            Triangle::new(a, b, c)
        })
        .collect();
    let mut numbers = Numbers(0xface);
    // Rays toward the model's vertices (edge functions of zero) and
    // toward random points.
    let targets = mesh
        .positions
        .iter()
        .copied()
        .chain((0..200).map(|_| numbers.point(1.5)));
    for target in targets.collect::<Vec<_>>() {
        let origin = numbers.point(4.0);
        let ray = Ray::new(origin, target - origin);
        for group in triangles.chunks(WIDTH) {
            let mut four = Triangles4::NAN;
            for (lane, triangle) in group.iter().enumerate() {
                four.set(lane, triangle);
            }
            let t = intersect_triangles(&four, &ray, 0.0, f32::INFINITY);
            for (lane, triangle) in group.iter().enumerate() {
                let one = Reference::intersect_triangle(triangle, &ray, 0.0, f32::INFINITY);
                assert_eq!(
                    one.map(f32::to_bits),
                    (!t[lane].is_nan()).then(|| t[lane].to_bits()),
                    "{ray:?}, lane {lane}"
                );
            }
        }
    }
}

#[test]
fn collapse_folds_two_levels_into_one_and_keeps_every_object() {
    // Eight spheres one per leaf: a binary tree of 15 nodes, 4 levels;
    // the wide root holds the four pairs, each a node of two leaves.
    let shapes: Vec<Shape> = (0..8)
        .map(|k| Sphere::new(Vec3::new(3.0 * k as f32, 0.0, 0.0), 1.0).into())
        .collect();
    let options = BvhOptions {
        split: SplitRule::Midpoint,
        max_leaf: 1,
        ..BvhOptions::default()
    };
    let bvh = build_bvh(&bounds(&shapes), &options);
    assert_eq!(bvh.node_count(), 15);
    let wide = collapse_bvh(&bvh, &shapes);
    assert_eq!(wide.nodes.len(), 5);
    assert_eq!(wide.nodes[0].used_lanes().bitmask(), 0b1111);
    let mut objects: Vec<u32> = wide
        .leaves
        .iter()
        .flat_map(|leaf| leaf.objects)
        .filter(|&object| object != u32::MAX)
        .collect();
    objects.sort_unstable();
    assert_eq!(objects, (0..8).collect::<Vec<_>>());
    // Spheres are asked one by one: each leaf's single lane is marked.
    assert!(wide.leaves.iter().all(|leaf| leaf.one_by_one == 0b1));
}

#[test]
fn the_wide_walks_answer_as_the_binary_walks_do() {
    let mesh = raylab::mesh::generate_closed_mesh(2000).expect("the generator makes a model");
    let mut shapes: Vec<Shape> = mesh
        .triangles
        .iter()
        .map(|corners| {
            let [a, b, c] = corners.map(|index| mesh.positions[index as usize]);
            Triangle::new(a, b, c).into()
        })
        .collect();
    let mut numbers = Numbers(0xbead);
    // Spheres among the triangles, and a floor outside the tree.
    shapes.extend((0..50).map(|_| Shape::from(Sphere::new(numbers.point(2.0), 0.2))));
    shapes.push(Plane::new(Vec3::new(0.0, -1.0, 0.0), Vec3::Y).into());
    let bvh = build_bvh(&bounds(&shapes), &BvhOptions::default());
    let wide = collapse_bvh(&bvh, &shapes);
    let objects = Objects::<Reference>::new(&shapes);
    for _ in 0..3_000 {
        let origin = numbers.point(4.0);
        let ray = Ray::new(origin, numbers.point(1.5) - origin);
        let t_max = numbers.between(0.5, 10.0);
        assert_eq!(
            nearest_hit_wide(&wide, &objects, &ray, 0.0, t_max),
            nearest_hit_bvh(&bvh, &objects, &ray, 0.0, t_max),
            "{ray:?}"
        );
        let any = any_hit_wide(&wide, &objects, &ray, 0.0, t_max);
        assert_eq!(
            any.is_some(),
            any_hit_bvh(&bvh, &objects, &ray, 0.0, t_max).is_some()
        );
        if let Some(hit) = any {
            assert_eq!(objects.intersect(hit.object, &ray, 0.0, t_max), Some(hit.t));
        }
    }
}

/// The checkpoints added for the contract's clauses get fresh inputs
/// under `grade --code --fresh`: the reference must pass every draw.
#[test]
fn the_contracts_checkpoints_pass_with_fresh_inputs() {
    let names = [
        "bvh-build-mixed-shapes",
        "bvh-nearest-skips-boxes-beyond-the-best",
        "bvh-nearest-asks-up-to-the-best",
        "bvh-planes-first-their-hit-shortens-the-walk",
        "bvh-any-hit-stops-at-its-first-hit",
        "bvh-middle-not-the-mean",
        "bvh-cut-where-the-centroids-spread",
        "wide-skips-waiting-children-beyond-the-best",
        "wide-asks-up-to-the-best",
        "wide-planes-first",
        "wide-any-hit-stops-at-its-first-hit",
        "wide-mixed-leaf",
        "wide-any-hit-mixed-leaf",
    ];
    let cases = crate::check::by_chapter::checkpoints(11);
    for name in names {
        let case = cases
            .iter()
            .find(|case| case.name == name)
            .expect("the case exists");
        for seed in 1..=20 {
            let fresh = case.fresh(seed).expect("drawn afresh");
            let outcome = fresh.run::<Reference>();
            assert_eq!(
                outcome,
                crate::check::Outcome::Pass,
                "{name}, seed {seed}: {}",
                fresh.kind.inputs()
            );
        }
    }
}

// The bug gallery and the accepted alternatives of this chapter.
#[path = "gallery.rs"]
mod gallery;
