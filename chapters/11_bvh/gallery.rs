//! Chapter 11, the bounding volume hierarchy, as `raylab check` judges it:
//! the reference passes both levels; its bug gallery (a slab
//! test poisoned by NaN, a walk that stops at the first leaf with a hit, a
//! build that puts planes in the tree; for the wide tree a lane left out, a
//! fallback taken by every lane, a fold that drops a child, a leaf that
//! forgets a sphere) fails chapter 11 on the case that names the mistake;
//! correct alternatives (another split rule, another visiting order, a
//! plainer wide walk) pass; and the tree changes no pixel.

use raylab::bvh::{
    Aabb, Boxes4, Bvh, BvhNode, BvhOptions, Leaf4, SplitRule, Triangles4, WIDTH, WideBvh, WideNode,
};
use raylab::chapters::{REFERENCE_HEIGHT, REFERENCE_WIDTH};
use raylab::check::planted::{self, Plant, Planted, plant};
use raylab::check::{ChapterVerdict, CheckOptions, Status, check_chapter};
use raylab::course::{Chapters, Hit, Objects};
use raylab::shapes::{Shape, Triangle};
use raylab::{Ray, Reference, RenderSettings, Vec3, Vec4};

fn options() -> CheckOptions {
    CheckOptions {
        failures_dir: std::env::temp_dir().join("raylab-chapter-11-tests"),
        write_images: false,
        forbid_answer_key: false,
        fresh: None,
        ..Default::default()
    }
}

/// Checks chapter 11 with `C` and asserts that it fails on case `case`,
/// with nothing earlier to blame.
fn assert_caught<C: Plant>(case: &str) -> ChapterVerdict {
    planted::assert_caught::<C>(11, case, &options())
}

/// Checks chapter 11 with `C` and asserts that it passes both levels.
fn assert_robust<C: Plant>() -> ChapterVerdict {
    planted::with::<C, _>(|| {
        let verdict = check_chapter::<Planted>(11, &options());
        assert!(verdict.robust(), "{}", verdict.text());
        verdict
    })
}

#[test]
fn the_reference_passes_chapter_11_at_both_levels() {
    let verdict = assert_robust::<Reference>();
    assert!(verdict.cases_total >= 10, "{}", verdict.text());
    let image = verdict.image.expect("the image was compared");
    assert!(image.passed);
}

// ---------------------------------------------------------------------------
// The bug gallery.

/// Bug: the slab test sorts each axis' two crossings and folds them into
/// the interval with `<` comparisons. A zero direction component with the
/// origin exactly on one of that axis' planes makes a crossing
/// `0 x inf = NaN`; every comparison with NaN is false, so `near < far`
/// picks the NaN's partner wrongly and the exit becomes `-inf`: the ray
/// running along the box's face misses it.
struct SlabNanPoisoned;
plant! {
    SlabNanPoisoned;
    fn hit_box(
        bounds: &Aabb,
        origin: Vec3,
        inverse_direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<f32> {
        let (mut entry, mut exit) = (t_min, t_max);
        for axis in 0..3 {
            let low = (bounds.min[axis] - origin[axis]) * inverse_direction[axis];
            let high = (bounds.max[axis] - origin[axis]) * inverse_direction[axis];
            let (near, far) = if low < high { (low, high) } else { (high, low) };
            entry = if near > entry { near } else { entry };
            exit = if far < exit { far } else { exit };
        }
        (entry <= exit).then_some(entry)
    }
}

#[test]
fn gallery_slab_test_poisoned_by_nan() {
    // By hand: the unit cube, origin (0, 1, -5) on the plane y = 1, dir
    // (0, 0, 1). The y crossings are (-1 - 1) x inf = -inf and
    // (1 - 1) x inf = NaN; `-inf < NaN` is false, so far = -inf.
    let cube = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
    let origin = Vec3::new(0.0, 1.0, -5.0);
    let inverse = Vec3::Z.recip();
    assert_eq!(
        SlabNanPoisoned::hit_box(&cube, origin, inverse, 0.0, f32::INFINITY),
        None
    );
    assert!(Reference::hit_box(&cube, origin, inverse, 0.0, f32::INFINITY).is_some());
    assert_caught::<SlabNanPoisoned>("box-zero-direction-on-slab-plane");
}

/// Bug: the walk visits the nearer child first, as it should, but returns
/// as soon as a leaf holds a hit. A leaf whose box is entered first can
/// hold an object hit farther than one in a box entered later.
struct StopsAtFirstLeafHit;
plant! {
    StopsAtFirstLeafHit;
    fn nearest_hit_bvh(
        bvh: &Bvh,
        objects: &Objects<Planted>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        let mut closest = t_max;
        let ask = |object: u32, best: &mut Option<Hit>, closest: &mut f32| {
            let object = object as usize;
            if let Some(t) = objects.intersect(object, ray, t_min, *closest) {
                *best = Some(Hit { object, t });
                *closest = t;
                return true;
            }
            false
        };
        for &object in &bvh.unbounded {
            ask(object, &mut best, &mut closest);
        }
        let inverse = ray.dir.recip();
        let enter = |node: usize, closest: f32| {
            Planted::hit_box(&bvh.nodes[node].bounds, ray.origin, inverse, t_min, closest)
        };
        let mut stack = Vec::new();
        if !bvh.nodes.is_empty() && enter(0, closest).is_some() {
            stack.push(0);
        }
        while let Some(index) = stack.pop() {
            let node = &bvh.nodes[index];
            let Some((left, right)) = node.children() else {
                let mut found = false;
                for &object in &bvh.primitives[node.primitive_range()] {
                    found |= ask(object, &mut best, &mut closest);
                }
                // The bug: the first leaf with a hit ends the walk.
                if found {
                    return best;
                }
                continue;
            };
            match (enter(left, closest), enter(right, closest)) {
                (Some(l), Some(r)) if r < l => stack.extend([left, right]),
                (Some(_), Some(_)) => stack.extend([right, left]),
                (Some(_), None) => stack.push(left),
                (None, Some(_)) => stack.push(right),
                (None, None) => {}
            }
        }
        best
    }
}

#[test]
fn gallery_walk_stops_at_the_first_leaf_with_a_hit() {
    assert_caught::<StopsAtFirstLeafHit>("bvh-nearest-behind-a-nearer-box");
}

/// Bug: planes go into the tree, each with an enormous (finite) box in
/// place of `None`, so that the build accepts them.
struct PlanesInTheTree;
plant! {
    PlanesInTheTree;
    fn build_bvh(bounds: &[Option<Aabb>], options: &BvhOptions) -> Bvh {
        let everywhere = Aabb::new(Vec3::splat(-1e30), Vec3::splat(1e30));
        let boxed: Vec<Option<Aabb>> = bounds
            .iter()
            .map(|bound| Some(bound.unwrap_or(everywhere)))
            .collect();
        Reference::build_bvh(&boxed, options)
    }
}

#[test]
fn gallery_build_puts_planes_in_the_tree() {
    assert_caught::<PlanesInTheTree>("bvh-plane-stays-out");
}

/// Bug: the walk keeps only strictly nearer hits, so of two hits at the
/// same `t` it keeps whichever it asked first. The planes are asked first,
/// outside the tree: a plane tied with a sphere listed before it wins,
/// where chapter 3 keeps the sphere.
struct TieToWhoeverIsAskedFirst;
plant! {
    TieToWhoeverIsAskedFirst;
    fn nearest_hit_bvh(
        bvh: &Bvh,
        objects: &Objects<Planted>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        // Asks up to the best t, exclusive, and keeps whatever it is told.
        left_first_walk(
            bvh,
            objects,
            ray,
            (t_min, t_max),
            |best| best.map_or(t_max, |hit| hit.t),
            |_, _, _| true,
            Leaf::AsksAll,
        )
    }
}

#[test]
fn gallery_tie_to_whoever_is_asked_first() {
    assert_caught::<TieToWhoeverIsAskedFirst>("bvh-nearest-tie-goes-to-the-first-listed");
}

/// Bug: in a leaf, the first object that hits ends the leaf, as if a leaf
/// were asked for any hit. A checkpoint puts three spheres in one leaf,
/// the farther first; so do the hard cases whose leaves hold many objects
/// (200 spheres around one centre make one leaf). The image cannot see it:
/// a render walks the wide tree.
struct FirstHitInALeaf;
plant! {
    FirstHitInALeaf;
    fn nearest_hit_bvh(
        bvh: &Bvh,
        objects: &Objects<Planted>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        left_first_walk(
            bvh,
            objects,
            ray,
            (t_min, t_max),
            |best| best.map_or(t_max, |hit| hit.t.next_up()),
            |object, t, best| best.is_none_or(|b| t < b.t || (t == b.t && object < b.object)),
            Leaf::StopsAtItsFirstHit,
        )
    }
}

#[test]
fn gallery_first_hit_in_a_leaf_ends_the_leaf() {
    assert_caught::<FirstHitInALeaf>("bvh-nearest-in-a-leaf-of-three");
    for name in [
        "bvh-thousand-spheres",
        "bvh-huge-coordinates",
        "bvh-coincident-centroids",
    ] {
        let case = raylab::check::by_chapter::robustness(11)
            .into_iter()
            .find(|case| case.name == name)
            .expect("the case exists");
        let outcome = planted::with::<FirstHitInALeaf, _>(|| case.run::<Planted>());
        assert!(
            matches!(outcome, raylab::check::Outcome::Fail { .. }),
            "{name}: {outcome:?}"
        );
    }
}

/// Correct, not yet robust: the slab test without the `2 gamma_3`
/// widening. Every checkpoint passes (their crossings are exact), but a
/// ray along a box's edge, whose exact entry equals its exact exit, can
/// come out with the entry rounded past the exit, and miss.
struct Unwidened;
plant! {
    Unwidened;
    fn hit_box(
        bounds: &Aabb,
        origin: Vec3,
        inverse_direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<f32> {
        let (mut entry, mut exit) = (t_min, t_max);
        for axis in 0..3 {
            let inverse = inverse_direction[axis];
            let (near, far) = if inverse.is_sign_negative() {
                (bounds.max[axis], bounds.min[axis])
            } else {
                (bounds.min[axis], bounds.max[axis])
            };
            entry = entry.max((near - origin[axis]) * inverse);
            exit = exit.min((far - origin[axis]) * inverse);
        }
        (entry <= exit).then_some(entry)
    }
}

#[test]
fn unwidened_slab_test_is_correct_but_not_robust() {
    let verdict = planted::check_chapter::<Unwidened>(11, &options());
    assert!(verdict.passes(), "{}", verdict.text());
    let robustness = verdict.robustness.as_ref().expect("level 2 ran");
    let first = robustness.first_failure.as_ref().map(|f| f.name);
    assert_eq!(first, Some("box-rays-along-edges"), "{}", verdict.text());
    assert!(verdict.text().contains("correct, not yet robust"));
}

// ---------------------------------------------------------------------------
// Correct alternatives: a tree's shape and a walk's order are the student's
// choice, and neither may fail the check.

/// Always the midpoint split, whatever the options ask.
struct MidpointBuild;
plant! {
    MidpointBuild;
    fn build_bvh(bounds: &[Option<Aabb>], options: &BvhOptions) -> Bvh {
        let midpoint = BvhOptions {
            split: SplitRule::Midpoint,
            ..*options
        };
        Reference::build_bvh(bounds, &midpoint)
    }
}

#[test]
fn alternative_midpoint_split_passes() {
    assert_robust::<MidpointBuild>();
}

/// Children visited left first, each box tested when it comes off the
/// stack against the best hit so far; ties broken by index as chapter 3
/// breaks them (asked up to and including the best `t`).
struct LeftFirstWalk;
plant! {
    LeftFirstWalk;
    fn nearest_hit_bvh(
        bvh: &Bvh,
        objects: &Objects<Planted>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        // Asks up to the best t, inclusive, and breaks ties by index.
        left_first_walk(
            bvh,
            objects,
            ray,
            (t_min, t_max),
            |best| best.map_or(t_max, |hit| hit.t.next_up()),
            |object, t, best| best.is_none_or(|b| t < b.t || (t == b.t && object < b.object)),
            Leaf::AsksAll,
        )
    }
}

#[test]
fn alternative_left_first_walk_passes() {
    assert_robust::<LeftFirstWalk>();
}

// ---------------------------------------------------------------------------
// The wide tree's bug gallery.

/// Bug: the four-lane slab test leaves its last lane out (a loop to
/// `WIDTH - 1`, say): that lane never enters, and the children it holds
/// are never visited.
struct LastLaneLeftOut;
plant! {
    LastLaneLeftOut;
    fn hit_boxes(boxes: &Boxes4, origin: Vec3, inverse: Vec3, t_min: f32, t_max: f32) -> Vec4 {
        let mut entries = Reference::hit_boxes(boxes, origin, inverse, t_min, t_max);
        entries[WIDTH - 1] = f32::NAN;
        entries
    }
}

#[test]
fn gallery_hit_boxes_leaves_a_lane_out() {
    assert_caught::<LastLaneLeftOut>("boxes-four-at-once");
}

/// Bug: the near plane of each axis is always the box's `min`, whatever
/// the direction's sign: a ray moving toward `-x` gets its exit as its
/// entry, and its entry as its exit.
struct NearPlaneAlwaysMin;
plant! {
    NearPlaneAlwaysMin;
    fn hit_boxes(boxes: &Boxes4, origin: Vec3, inverse: Vec3, t_min: f32, t_max: f32) -> Vec4 {
        let (mut entry, mut exit) = (Vec4::NEG_INFINITY, Vec4::INFINITY);
        for axis in 0..3 {
            let near = (boxes.min[axis] - Vec4::splat(origin[axis])) * inverse[axis];
            let far = (boxes.max[axis] - Vec4::splat(origin[axis])) * inverse[axis];
            entry = raylab::bvh::greater_of(near, entry);
            exit = raylab::bvh::lesser_of(far, exit);
        }
        let entry = raylab::bvh::greater_of(Vec4::splat(t_min), entry);
        let exit = raylab::bvh::lesser_of(Vec4::splat(t_max), exit);
        Vec4::select(entry.cmple(exit), entry, Vec4::NAN)
    }
}

#[test]
fn gallery_hit_boxes_near_plane_ignores_the_direction() {
    assert_caught::<NearPlaneAlwaysMin>("boxes-negative-direction-and-t-max");
}

/// Bug: the four-triangle test leaves its last lane out: a leaf's fourth
/// triangle is never hit.
struct LastTriangleLeftOut;
plant! {
    LastTriangleLeftOut;
    fn intersect_triangles(triangles: &Triangles4, ray: &Ray, t_min: f32, t_max: f32) -> Vec4 {
        let mut t = Reference::intersect_triangles(triangles, ray, t_min, t_max);
        t[WIDTH - 1] = f32::NAN;
        t
    }
}

#[test]
fn gallery_intersect_triangles_leaves_a_lane_out() {
    assert_caught::<LastTriangleLeftOut>("triangles-four-at-once");
}

/// Bug: each lane is chapter 11's NaN-poisoned slab test (the crossings
/// sorted by comparing them): a ray along a box's face misses it.
struct LanesNanPoisoned;
plant! {
    LanesNanPoisoned;
    fn hit_boxes(boxes: &Boxes4, origin: Vec3, inverse: Vec3, t_min: f32, t_max: f32) -> Vec4 {
        Vec4::from_array(std::array::from_fn(|lane| {
            SlabNanPoisoned::hit_box(&boxes.get(lane), origin, inverse, t_min, t_max)
                .unwrap_or(f32::NAN)
        }))
    }
}

#[test]
fn gallery_hit_boxes_poisoned_by_nan() {
    assert_caught::<LanesNanPoisoned>("boxes-nan-lanes");
}

/// Bug: when one lane's edge functions include a zero, all four lanes are
/// recomputed in `f64`: the others' `t` move by an ulp, and are no longer
/// chapter 10's.
struct FallbackForEveryLane;
plant! {
    FallbackForEveryLane;
    fn intersect_triangles(triangles: &Triangles4, ray: &Ray, t_min: f32, t_max: f32) -> Vec4 {
        let one = |lane: usize, fallback: Fallback| {
            f64_edges_triangle(&triangles.get(lane), ray, t_min, t_max, fallback)
        };
        let any_zero = (0..WIDTH).any(|lane| one(lane, Fallback::WhenZero).1);
        let fallback = if any_zero {
            Fallback::Always
        } else {
            Fallback::WhenZero
        };
        Vec4::from_array(std::array::from_fn(|lane| {
            one(lane, fallback).0.unwrap_or(f32::NAN)
        }))
    }
}

/// When [`f64_edges_triangle`] recomputes the edge functions in `f64`.
#[derive(Clone, Copy, PartialEq)]
enum Fallback {
    /// When one of them is zero, as chapter 10 does.
    WhenZero,
    Always,
    Never,
}

/// Chapter 10's watertight test, its edge functions recomputed in `f64`
/// as `fallback` says; and whether one was zero.
fn f64_edges_triangle(
    triangle: &Triangle,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    fallback: Fallback,
) -> (Option<f32>, bool) {
    let dir = ray.dir.to_array();
    let z = ray.dir.abs().max_position();
    let (mut x, mut y) = ((z + 1) % 3, (z + 2) % 3);
    if dir[z] < 0.0 {
        std::mem::swap(&mut x, &mut y);
    }
    let (shear_x, shear_y, scale_z) = (dir[x] / dir[z], dir[y] / dir[z], 1.0 / dir[z]);
    let [a, b, c] = triangle
        .corners()
        .map(|corner| (corner - ray.origin).to_array());
    let sheared = |p: [f32; 3]| (p[x] - shear_x * p[z], p[y] - shear_y * p[z]);
    let ((ax, ay), (bx, by), (cx, cy)) = (sheared(a), sheared(b), sheared(c));
    let (mut u, mut v, mut w) = (cx * by - cy * bx, ax * cy - ay * cx, bx * ay - by * ax);
    let zero = u == 0.0 || v == 0.0 || w == 0.0;
    if (zero && fallback == Fallback::WhenZero) || fallback == Fallback::Always {
        let cross = |px: f32, py: f32, qx: f32, qy: f32| {
            (f64::from(px) * f64::from(qy) - f64::from(py) * f64::from(qx)) as f32
        };
        (u, v, w) = (
            cross(cx, cy, bx, by),
            cross(ax, ay, cx, cy),
            cross(bx, by, ax, ay),
        );
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return (None, zero);
    }
    let determinant = u + v + w;
    if !(determinant != 0.0) {
        return (None, zero);
    }
    let (az, bz, cz) = (scale_z * a[z], scale_z * b[z], scale_z * c[z]);
    let t = (u * az + v * bz + w * cz) / determinant;
    ((t > t_min && t < t_max).then_some(t), zero)
}

#[test]
fn gallery_every_lane_recomputed_in_f64() {
    assert_caught::<FallbackForEveryLane>("triangles-a-zero-in-two-lanes");
}

/// Bug: the fold opens a child but keeps only its left child (the line
/// that adds the right one is missing): every object under the right one
/// is lost from the wide tree.
struct FoldDropsAChild;
plant! {
    FoldDropsAChild;
    fn collapse_bvh(bvh: &Bvh, shapes: &[Shape]) -> WideBvh {
        plain_fold(bvh, shapes, FoldRules::DROPS_THE_RIGHT_CHILD)
    }
}

#[test]
fn gallery_fold_drops_a_child() {
    assert_caught::<FoldDropsAChild>("collapse-four-lanes");
}

/// Bug: the fold takes each binary node's two children and opens none: a
/// binary tree in wide clothing, two of four lanes used.
struct FoldOpensNothing;
plant! {
    FoldOpensNothing;
    fn collapse_bvh(bvh: &Bvh, shapes: &[Shape]) -> WideBvh {
        plain_fold(bvh, shapes, FoldRules::OPENS_NOTHING)
    }
}

#[test]
fn gallery_fold_opens_no_child() {
    assert_caught::<FoldOpensNothing>("collapse-four-lanes");
}

/// Correct: the fold opens the first inner child it finds rather than the
/// largest. Another tree, as valid, and as full.
struct FoldOpensTheFirst;
plant! {
    FoldOpensTheFirst;
    fn collapse_bvh(bvh: &Bvh, shapes: &[Shape]) -> WideBvh {
        plain_fold(bvh, shapes, FoldRules::CORRECT)
    }
}

#[test]
fn alternative_fold_opening_the_first_inner_child_passes() {
    assert_robust::<FoldOpensTheFirst>();
}

/// What `plain_fold` gets right or wrong.
#[derive(Clone, Copy)]
struct FoldRules {
    /// Open inner children while there is room.
    opens: bool,
    /// An opened child is replaced by both of its children.
    keeps_the_right_child: bool,
    /// Each lane's box is its child's (else the binary node's it was
    /// folded from: the parent's).
    lanes_keep_their_boxes: bool,
    /// How many objects go to a `Leaf4` (four, or fewer).
    objects_per_leaf4: usize,
    /// A lane asked one by one keeps NaN corners (else the corners of a
    /// triangle listed before it, left over).
    alone_corners_nan: bool,
    /// `unbounded` copied from the binary tree (else left empty).
    keeps_unbounded: bool,
}

impl FoldRules {
    const CORRECT: FoldRules = FoldRules {
        opens: true,
        keeps_the_right_child: true,
        lanes_keep_their_boxes: true,
        objects_per_leaf4: WIDTH,
        alone_corners_nan: true,
        keeps_unbounded: true,
    };
    const DROPS_THE_RIGHT_CHILD: FoldRules = FoldRules {
        keeps_the_right_child: false,
        ..FoldRules::CORRECT
    };
    const OPENS_NOTHING: FoldRules = FoldRules {
        opens: false,
        ..FoldRules::CORRECT
    };
}

/// A fold that opens the first inner child it finds (not the largest),
/// with its leaves' objects four to a [`Leaf4`], as `rules` say.
fn plain_fold(bvh: &Bvh, shapes: &[Shape], rules: FoldRules) -> WideBvh {
    let mut wide = WideBvh {
        nodes: Vec::new(),
        leaves: Vec::new(),
        unbounded: if rules.keeps_unbounded {
            bvh.unbounded.clone()
        } else {
            Vec::new()
        },
    };
    if bvh.nodes.is_empty() {
        return wide;
    }
    wide.nodes.push(WideNode::UNUSED);
    let mut to_fill = vec![(0usize, 0usize)];
    while let Some((slot, binary)) = to_fill.pop() {
        let mut children = match bvh.nodes[binary].children() {
            Some((left, right)) => vec![left, right],
            None => vec![binary],
        };
        while rules.opens && children.len() < WIDTH {
            let Some(place) = children.iter().position(|&c| !bvh.nodes[c].is_leaf()) else {
                break;
            };
            let Some((left, right)) = bvh.nodes[children[place]].children() else {
                break;
            };
            children[place] = left;
            if rules.keeps_the_right_child {
                children.push(right);
            }
        }
        let mut node = WideNode::UNUSED;
        for (lane, &index) in children.iter().enumerate() {
            let child = &bvh.nodes[index];
            let lane_box = if rules.lanes_keep_their_boxes {
                child.bounds
            } else {
                bvh.nodes[binary].bounds
            };
            node.boxes.set(lane, lane_box);
            if child.is_leaf() {
                node.first[lane] = wide.leaves.len() as u32;
                for group in bvh.primitives[child.primitive_range()].chunks(rules.objects_per_leaf4)
                {
                    let mut leaf = Leaf4 {
                        triangles: Triangles4::NAN,
                        objects: [u32::MAX; WIDTH],
                        one_by_one: 0,
                    };
                    let mut last_triangle = None;
                    for (lane, &object) in group.iter().enumerate() {
                        leaf.objects[lane] = object;
                        match shapes[object as usize].as_triangle() {
                            Some(triangle) => {
                                leaf.triangles.set(lane, triangle);
                                last_triangle = Some(*triangle);
                            }
                            None => {
                                leaf.one_by_one |= 1 << lane;
                                if !rules.alone_corners_nan
                                    && let Some(triangle) = &last_triangle
                                {
                                    leaf.triangles.set(lane, triangle);
                                }
                            }
                        }
                    }
                    wide.leaves.push(leaf);
                }
                node.count[lane] = wide.leaves.len() as u32 - node.first[lane];
            } else {
                node.first[lane] = wide.nodes.len() as u32;
                to_fill.push((wide.nodes.len(), index));
                wide.nodes.push(WideNode::UNUSED);
            }
        }
        wide.nodes[slot] = node;
    }
    wide
}

/// Bug: every object of a leaf goes into a triangle lane; a sphere's
/// lane keeps NaN corners and is never asked.
struct SphereNotAskedAlone;
plant! {
    SphereNotAskedAlone;
    fn collapse_bvh(bvh: &Bvh, shapes: &[Shape]) -> WideBvh {
        let mut wide = Reference::collapse_bvh(bvh, shapes);
        for leaf in &mut wide.leaves {
            leaf.one_by_one = 0;
        }
        wide
    }
}

#[test]
fn gallery_fold_forgets_to_ask_a_sphere() {
    assert_caught::<SphereNotAskedAlone>("collapse-triangles-copied-a-sphere-alone");
}

/// Bug: the wide walk returns as soon as a leaf holds a hit, although a
/// box entered later can hold a nearer one.
struct WideStopsAtFirstLeafHit;
plant! {
    WideStopsAtFirstLeafHit;
    fn nearest_hit_wide(
        wide: &WideBvh,
        objects: &Objects<Planted>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        plain_wide_walk(
            wide,
            objects,
            ray,
            (t_min, t_max),
            WideRules::STOPS_AT_FIRST_LEAF_HIT,
        )
    }
}

#[test]
fn gallery_wide_walk_stops_at_the_first_leaf_with_a_hit() {
    assert_caught::<WideStopsAtFirstLeafHit>("wide-nearest-behind-a-nearer-box");
}

/// Bug: the wide walk keeps only strictly nearer hits, so of two hits at
/// the same `t` whichever was asked first: the plane, outside the tree,
/// beats the sphere listed before it.
struct WideTieToWhoeverIsAskedFirst;
plant! {
    WideTieToWhoeverIsAskedFirst;
    fn nearest_hit_wide(
        wide: &WideBvh,
        objects: &Objects<Planted>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        plain_wide_walk(
            wide,
            objects,
            ray,
            (t_min, t_max),
            WideRules::TIE_TO_THE_FIRST_ASKED,
        )
    }
}

#[test]
fn gallery_wide_tie_to_whoever_is_asked_first() {
    assert_caught::<WideTieToWhoeverIsAskedFirst>("wide-nearest-tie-goes-to-the-first-listed");
}

/// Bug: the wide any-hit walk tests the leaves' triangles and forgets the
/// lanes marked one by one: spheres cast no shadow.
struct AnyHitWideForgetsSpheres;
plant! {
    AnyHitWideForgetsSpheres;
    fn any_hit_wide(
        wide: &WideBvh,
        objects: &Objects<Planted>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        let mut forgetful = wide.clone();
        for leaf in &mut forgetful.leaves {
            leaf.one_by_one = 0;
        }
        super::any_hit_wide(&forgetful, objects, ray, t_min, t_max)
    }
}

#[test]
fn gallery_any_hit_wide_forgets_the_spheres() {
    assert_caught::<AnyHitWideForgetsSpheres>("wide-any-hit-finds-the-blocker");
}

/// Correct: a plainer wide walk, every entered lane pushed nearest on
/// top, each box tested once when its node is opened, ties broken by
/// index.
struct PlainWideWalk;
plant! {
    PlainWideWalk;
    fn nearest_hit_wide(
        wide: &WideBvh,
        objects: &Objects<Planted>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        plain_wide_walk(wide, objects, ray, (t_min, t_max), WideRules::CORRECT)
    }
}

#[test]
fn alternative_plain_wide_walk_passes() {
    assert_robust::<PlainWideWalk>();
}

/// What `plain_wide_walk` gets right or wrong.
#[derive(Clone, Copy)]
struct WideRules {
    /// Ask up to and including the best `t`, and break ties by index.
    ties_by_index: bool,
    /// Return as soon as a leaf holds a hit.
    stop_at_first_leaf_hit: bool,
    /// Skip a waiting child whose entry is beyond the best hit found since
    /// it was pushed.
    prunes_waiting: bool,
    /// The planes asked before the tree (else after it).
    planes_first: bool,
    /// Ask each object up to and including the best so far (else to
    /// `t_max`).
    asks_up_to_the_best: bool,
    /// A triangle lane's hit kept when it ties the best and is listed
    /// first (else only when nearer).
    lanes_tie_by_index: bool,
    /// The objects asked one by one asked only when no triangle lane of
    /// their `Leaf4` hits.
    spheres_only_without_triangle_hits: bool,
    /// How many waiting children the stack keeps; those pushed beyond are
    /// dropped.
    stack_cap: usize,
}

impl WideRules {
    const CORRECT: WideRules = WideRules {
        ties_by_index: true,
        stop_at_first_leaf_hit: false,
        prunes_waiting: true,
        planes_first: true,
        asks_up_to_the_best: true,
        lanes_tie_by_index: true,
        spheres_only_without_triangle_hits: false,
        stack_cap: usize::MAX,
    };
    const STOPS_AT_FIRST_LEAF_HIT: WideRules = WideRules {
        stop_at_first_leaf_hit: true,
        ..WideRules::CORRECT
    };
    const TIE_TO_THE_FIRST_ASKED: WideRules = WideRules {
        ties_by_index: false,
        ..WideRules::CORRECT
    };
}

/// A wide walk with a plain stack: the entered lanes of a node pushed
/// farthest first, each with its entry, skipped when it comes off beyond
/// the best hit so far; a leaf's triangle lanes tested together, then its
/// objects asked one by one; all as `rules` say.
fn plain_wide_walk<C: Chapters>(
    wide: &WideBvh,
    objects: &Objects<C>,
    ray: &Ray,
    (t_min, t_max): (f32, f32),
    rules: WideRules,
) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    let limit = |best: Option<Hit>| match best {
        Some(hit) if !rules.ties_by_index => hit.t,
        Some(hit) if rules.asks_up_to_the_best => hit.t.next_up(),
        _ => t_max,
    };
    let offer = |best: &mut Option<Hit>, object: usize, t: f32, by_index: bool| {
        let better = best.is_none_or(|b| {
            t < b.t || (rules.ties_by_index && by_index && t == b.t && object < b.object)
        });
        if better {
            *best = Some(Hit { object, t });
        }
    };
    let planes = |best: &mut Option<Hit>| {
        for &object in &wide.unbounded {
            if let Some(t) = objects.intersect(object as usize, ray, t_min, limit(*best)) {
                offer(best, object as usize, t, true);
            }
        }
    };
    if rules.planes_first {
        planes(&mut best);
    }
    let inverse = ray.dir.recip();
    let mut stack = if wide.nodes.is_empty() {
        Vec::new()
    } else {
        vec![(0u32, 0u32, f32::NEG_INFINITY)]
    };
    while let Some((first, count, entry)) = stack.pop() {
        let closest = best.map_or(t_max, |hit| hit.t);
        if rules.prunes_waiting && !(entry <= closest) {
            continue;
        }
        if count == 0 {
            let node = &wide.nodes[first as usize];
            let entries = C::hit_boxes(&node.boxes, ray.origin, inverse, t_min, closest);
            let mut entered: Vec<usize> = (0..WIDTH)
                .filter(|&lane| !entries[lane].is_nan() && node.used_lanes().test(lane))
                .collect();
            entered.sort_by(|&a, &b| entries[b].total_cmp(&entries[a]));
            for lane in entered {
                if stack.len() < rules.stack_cap {
                    stack.push((node.first[lane], node.count[lane], entries[lane]));
                }
            }
            continue;
        }
        let mut found = false;
        for leaf in &wide.leaves[first as usize..(first + count) as usize] {
            let t = C::intersect_triangles(&leaf.triangles, ray, t_min, limit(best));
            let lane_hit = (0..WIDTH).any(|lane| !t[lane].is_nan());
            for lane in (0..WIDTH).filter(|&lane| !t[lane].is_nan()) {
                offer(
                    &mut best,
                    leaf.objects[lane] as usize,
                    t[lane],
                    rules.lanes_tie_by_index,
                );
                found = true;
            }
            if rules.spheres_only_without_triangle_hits && lane_hit {
                continue;
            }
            for lane in (0..WIDTH).filter(|&lane| leaf.one_by_one & (1 << lane) != 0) {
                let object = leaf.objects[lane] as usize;
                if let Some(t) = objects.intersect(object, ray, t_min, limit(best)) {
                    offer(&mut best, object, t, true);
                    found = true;
                }
            }
        }
        if found && rules.stop_at_first_leaf_hit {
            return best;
        }
    }
    if !rules.planes_first {
        planes(&mut best);
    }
    best
}

// ---------------------------------------------------------------------------
// The contract, clause by clause: each variant breaks one sentence of the
// lesson or of a doc comment, and fails on the case that asks it.

/// Asserts that `C` passes chapter 11's checkpoints and fails its hard
/// case `case` first: a clause only rounding or a deep tree can show.
fn assert_caught_by_hard_case<C: Plant>(case: &str) {
    planted::assert_caught_by_hard_case::<C>(11, case, &options());
}

/// One sentence of the slab test broken, by [`slab`].
#[derive(Clone, Copy, PartialEq)]
enum SlabSlip {
    None,
    /// The entry is the smallest of the three slabs' entries.
    SmallestEntry,
    /// The near plane is always `min`, whatever the direction's sign.
    NearPlaneAlwaysMin,
    /// The entry returned as it is, not raised to `t_min` from inside.
    EntryNotRaisedToTMin,
    /// The interval never compared with `t_min`: a box behind the ray is
    /// met.
    BehindMet,
    /// No upper end.
    TMaxIgnored,
    /// An axis whose direction component is 0 skipped, as if its slab held
    /// every line.
    ZeroDirectionSkipsTheAxis,
    /// Each axis' crossings sorted by comparing them the other way round:
    /// with the origin on a plane and a negative zero, the exit is `-inf`.
    CrossingsSortedTheOtherWay,
    /// A slack of `1e-6 / |t|`, which grows as `t` shrinks.
    SlackGrowsAsTShrinks,
    /// Only the exit widened: the entry as rounded, which can land past a
    /// hit that ties the best so far.
    ExitOnlyWidened,
}

/// Chapter 11's `hit_box` as the reference writes it, with `slip`.
fn slab(
    bounds: &Aabb,
    origin: Vec3,
    inverse: Vec3,
    t_min: f32,
    t_max: f32,
    slip: SlabSlip,
) -> Option<f32> {
    let mut entry = if slip == SlabSlip::SmallestEntry {
        f32::INFINITY
    } else {
        f32::NEG_INFINITY
    };
    let mut exit = f32::INFINITY;
    for axis in 0..3 {
        if slip == SlabSlip::ZeroDirectionSkipsTheAxis && inverse[axis].is_infinite() {
            continue;
        }
        let (low, high) = (bounds.min[axis], bounds.max[axis]);
        let (near_plane, far_plane) =
            if inverse[axis].is_sign_negative() && slip != SlabSlip::NearPlaneAlwaysMin {
                (high, low)
            } else {
                (low, high)
            };
        let mut near = (near_plane - origin[axis]) * inverse[axis];
        let mut far = (far_plane - origin[axis]) * inverse[axis];
        if slip == SlabSlip::CrossingsSortedTheOtherWay {
            let from_low = (low - origin[axis]) * inverse[axis];
            let from_high = (high - origin[axis]) * inverse[axis];
            (near, far) = if from_high < from_low {
                (from_high, from_low)
            } else {
                (from_low, from_high)
            };
        }
        entry = match slip {
            SlabSlip::SmallestEntry => {
                if near < entry {
                    near
                } else {
                    entry
                }
            }
            _ => {
                if near > entry {
                    near
                } else {
                    entry
                }
            }
        };
        exit = if far < exit { far } else { exit };
    }
    let slack = |t: f32| {
        let slack = if slip == SlabSlip::SlackGrowsAsTShrinks {
            1e-6 / t.abs()
        } else {
            2.0 * super::GAMMA_3 * t.abs()
        };
        if slack < f32::MAX { slack } else { f32::MAX }
    };
    let entry = if slip == SlabSlip::ExitOnlyWidened {
        entry
    } else {
        entry - slack(entry)
    };
    let exit = exit + slack(exit);
    let raised = if t_min > entry { t_min } else { entry };
    let lowered = if t_max < exit && slip != SlabSlip::TMaxIgnored {
        t_max
    } else {
        exit
    };
    let meets = if slip == SlabSlip::BehindMet {
        entry <= exit && entry <= t_max
    } else {
        raised <= lowered
    };
    let answer = if slip == SlabSlip::EntryNotRaisedToTMin {
        entry
    } else {
        raised
    };
    meets.then_some(answer)
}

macro_rules! slabs {
    ($($(#[$doc:meta])* $name:ident = $slip:expr;)*) => {$(
        $(#[$doc])*
        struct $name;
        plant! {
            $name;
            fn hit_box(
                bounds: &Aabb,
                origin: Vec3,
                inverse_direction: Vec3,
                t_min: f32,
                t_max: f32,
            ) -> Option<f32> {
                slab(bounds, origin, inverse_direction, t_min, t_max, $slip)
            }
        }
    )*};
}

slabs! {
    /// No slip: it must pass.
    SlabAsTheLessonSays = SlabSlip::None;
    SmallestEntry = SlabSlip::SmallestEntry;
    SlabNearPlaneAlwaysMin = SlabSlip::NearPlaneAlwaysMin;
    EntryNotRaisedToTMin = SlabSlip::EntryNotRaisedToTMin;
    BoxBehindMet = SlabSlip::BehindMet;
    BoxTMaxIgnored = SlabSlip::TMaxIgnored;
    ZeroDirectionSkipsTheAxis = SlabSlip::ZeroDirectionSkipsTheAxis;
    CrossingsSortedTheOtherWay = SlabSlip::CrossingsSortedTheOtherWay;
    SlackGrowsAsTShrinks = SlabSlip::SlackGrowsAsTShrinks;
    ExitOnlyWidened = SlabSlip::ExitOnlyWidened;
}

#[test]
fn contract_the_slab_copy_passes() {
    assert_robust::<SlabAsTheLessonSays>();
}

#[test]
fn contract_the_entry_is_the_largest_and_its_plane_the_near_one() {
    assert_caught::<SmallestEntry>("box-from-outside");
    assert_caught::<SlabNearPlaneAlwaysMin>("box-negative-direction");
}

#[test]
fn contract_the_interval_is_t_min_to_t_max() {
    assert_caught::<EntryNotRaisedToTMin>("box-from-inside");
    assert_caught::<BoxBehindMet>("box-behind");
    assert_caught::<BoxTMaxIgnored>("box-beyond-t-max");
}

#[test]
fn contract_a_zero_direction_component_is_all_or_nothing() {
    assert_caught::<ZeroDirectionSkipsTheAxis>("box-parallel-outside-slab");
}

#[test]
fn contract_a_nan_crossing_constrains_nothing() {
    assert_caught::<CrossingsSortedTheOtherWay>("box-negative-zero-on-min-plane");
}

#[test]
fn contract_the_widening_is_2_gamma_3_of_each_end() {
    assert_caught::<SlackGrowsAsTShrinks>("box-entry-close-to-the-origin");
    assert_caught_by_hard_case::<ExitOnlyWidened>("bvh-coplanar-tie-far-from-the-origin");
}

/// How a variant of `build_bvh` chooses the axis of a cut.
#[derive(Clone, Copy, PartialEq)]
enum CutAxis {
    /// Where the centroids spread the most: the reference.
    CentroidSpread,
    /// Where the node's box is widest.
    WidestBox,
    /// The wider of x and y only.
    XOrY,
}

/// What a variant of `build_bvh` does, by [`build_with`].
#[derive(Clone, Copy)]
struct BuildRules {
    /// Each object's box grown by 4 epsilons of its largest coordinate.
    pads: bool,
    /// A flat box (`min == max` on an axis) counted finite and not empty.
    flat_boxes_kept: bool,
    /// A NaN or infinite box kept out of the tree.
    non_finite_boxes_out: bool,
    /// Added to `max_leaf` for the leaf test: 0, or a leaf one object too
    /// small (-1) or too large (+1).
    leaf_size_slip: isize,
    axis: CutAxis,
    /// The middle of the centroids' spread (else their mean).
    middle_of_the_spread: bool,
    /// Coincident centroids make a leaf (else the list cut in halves).
    coincident_leaf: bool,
    /// The SAH's `C_trav` term.
    sah_traversal_cost: bool,
    /// The SAH keeps a leaf when no cut is cheaper.
    sah_leaf_test: bool,
    /// Of equal costs the first boundary wins (else the last).
    sah_first_of_equals: bool,
    /// Half areas of all three pairs of sides (else `xy + yz` only).
    sah_three_sides: bool,
    /// Areas summed in `f64` (else in `f32`).
    sah_areas_in_f64: bool,
    /// An inner node's box holds both children (else the left one's only).
    inner_box_holds_both: bool,
}

impl BuildRules {
    const CORRECT: BuildRules = BuildRules {
        pads: true,
        flat_boxes_kept: true,
        non_finite_boxes_out: true,
        leaf_size_slip: 0,
        axis: CutAxis::CentroidSpread,
        middle_of_the_spread: true,
        coincident_leaf: true,
        sah_traversal_cost: true,
        sah_leaf_test: true,
        sah_first_of_equals: true,
        sah_three_sides: true,
        sah_areas_in_f64: true,
        inner_box_holds_both: true,
    };
}

/// How [`build_with`] cuts a node.
#[derive(Clone, Copy)]
enum Cutting {
    /// Centroids below `position` along `axis` go left.
    Below { axis: usize, position: f64 },
    /// Centroids in the bins before `boundary` go left.
    BinsBefore {
        axis: usize,
        low: f64,
        scale: f64,
        bins: usize,
        boundary: usize,
    },
    /// The first half of the list goes left.
    Halves,
}

/// The bin of `centroid` along `axis`, as the reference's SAH sorts them.
fn bin_of(centroid: Vec3, axis: usize, low: f64, scale: f64, bins: usize) -> usize {
    (((f64::from(centroid[axis]) - low) * scale) as usize).min(bins - 1)
}

/// Chapter 11's `build_bvh` as the reference writes it, as `rules` say.
fn build_with(bounds: &[Option<Aabb>], options: &BvhOptions, rules: BuildRules) -> Bvh {
    let pad = |bounds: Aabb| {
        let magnitude = bounds.min.abs().max(bounds.max.abs()).max_element();
        let pad = Vec3::splat(4.0 * f32::EPSILON * magnitude);
        Aabb::new(bounds.min - pad, bounds.max + pad)
    };
    let kept = |bounds: &Aabb| {
        let ordered = if rules.flat_boxes_kept {
            bounds.min.cmple(bounds.max).all()
        } else {
            bounds.min.cmplt(bounds.max).all()
        };
        !rules.non_finite_boxes_out || (bounds.min.is_finite() && bounds.max.is_finite() && ordered)
    };
    let mut bvh = Bvh::default();
    let mut boxes = Vec::new();
    for (object, bound) in bounds.iter().enumerate() {
        let boxed = bound.filter(kept);
        match boxed {
            Some(_) => bvh.primitives.push(object as u32),
            None => bvh.unbounded.push(object as u32),
        }
        let boxed = boxed.map_or(
            Aabb::EMPTY,
            |bounds| if rules.pads { pad(bounds) } else { bounds },
        );
        boxes.push(boxed);
    }
    let centroids: Vec<Vec3> = boxes.iter().map(|b| 0.5 * b.min + 0.5 * b.max).collect();
    if bvh.primitives.is_empty() {
        return bvh;
    }
    let placeholder = BvhNode {
        bounds: Aabb::EMPTY,
        first: 0,
        count: 0,
    };
    bvh.nodes.push(placeholder);
    let mut to_build = vec![(0usize, 0..bvh.primitives.len())];
    while let Some((node, range)) = to_build.pop() {
        let objects = &mut bvh.primitives[range.clone()];
        let union = |objects: &[u32]| {
            objects
                .iter()
                .fold(Aabb::EMPTY, |sum, &o| sum.union(boxes[o as usize]))
        };
        let node_box = union(objects);
        let leaf_size = (options.max_leaf.max(1) as isize + rules.leaf_size_slip).max(0) as usize;
        let cut = if objects.len() <= leaf_size {
            None
        } else {
            cut_with(objects, &boxes, &centroids, &node_box, options, rules)
        };
        let Some(cut) = cut else {
            bvh.nodes[node] = BvhNode {
                bounds: node_box,
                first: range.start as u32,
                count: objects.len() as u32,
            };
            continue;
        };
        let left_count = match cut {
            Cutting::Halves => objects.len() / 2,
            Cutting::Below { axis, position } => reorder(objects, |o| {
                f64::from(centroids[o as usize][axis]) < position
            }),
            Cutting::BinsBefore {
                axis,
                low,
                scale,
                bins,
                boundary,
            } => reorder(objects, |o| {
                bin_of(centroids[o as usize], axis, low, scale, bins) < boundary
            }),
        };
        let node_box = if rules.inner_box_holds_both {
            node_box
        } else {
            union(&objects[..left_count])
        };
        let first = bvh.nodes.len();
        bvh.nodes.push(placeholder);
        bvh.nodes.push(placeholder);
        bvh.nodes[node] = BvhNode {
            bounds: node_box,
            first: first as u32,
            count: 0,
        };
        let middle = range.start + left_count;
        to_build.push((first + 1, middle..range.end));
        to_build.push((first, range.start..middle));
    }
    bvh
}

/// Reorders `objects` so that those `goes_left` takes come first; how
/// many they are.
fn reorder(objects: &mut [u32], goes_left: impl Fn(u32) -> bool) -> usize {
    let (mut left, mut right) = (0, objects.len());
    while left < right {
        if goes_left(objects[left]) {
            left += 1;
        } else {
            right -= 1;
            objects.swap(left, right);
        }
    }
    left
}

/// Half the area of `bounds`, as `rules` say.
fn half_area_with(bounds: &Aabb, rules: BuildRules) -> f64 {
    if bounds.is_empty() {
        return 0.0;
    }
    if !rules.sah_areas_in_f64 {
        let size = bounds.max - bounds.min;
        return f64::from(size.x * size.y + size.y * size.z + size.z * size.x);
    }
    let size = bounds.max.as_dvec3() - bounds.min.as_dvec3();
    let two_sides = size.x * size.y + size.y * size.z;
    if rules.sah_three_sides {
        two_sides + size.z * size.x
    } else {
        two_sides
    }
}

/// The cut of a node holding `objects`, as `rules` say; `None` for a leaf.
fn cut_with(
    objects: &[u32],
    boxes: &[Aabb],
    centroids: &[Vec3],
    node_box: &Aabb,
    options: &BvhOptions,
    rules: BuildRules,
) -> Option<Cutting> {
    let spread = objects
        .iter()
        .fold(Aabb::EMPTY, |sum, &o| sum.grow(centroids[o as usize]));
    let extent = spread.max.as_dvec3() - spread.min.as_dvec3();
    let widest = |sizes: glam::DVec3, axes: usize| {
        (0..axes).fold(0, |widest, axis| {
            if sizes[axis] > sizes[widest] {
                axis
            } else {
                widest
            }
        })
    };
    let axis = match rules.axis {
        CutAxis::CentroidSpread => widest(extent, 3),
        CutAxis::WidestBox => widest(node_box.max.as_dvec3() - node_box.min.as_dvec3(), 3),
        CutAxis::XOrY => widest(extent, 2),
    };
    if !(extent[axis] > 0.0) {
        return (!rules.coincident_leaf).then_some(Cutting::Halves);
    }
    let low = f64::from(spread.min[axis]);
    if options.split == SplitRule::Midpoint {
        let position = if rules.middle_of_the_spread {
            low + 0.5 * extent[axis]
        } else {
            objects
                .iter()
                .map(|&o| f64::from(centroids[o as usize][axis]))
                .sum::<f64>()
                / objects.len() as f64
        };
        return Some(Cutting::Below { axis, position });
    }
    let bins = options.bins.clamp(2, 1024) as usize;
    let scale = bins as f64 / extent[axis];
    let mut bin_count = vec![0usize; bins];
    let mut bin_box = vec![Aabb::EMPTY; bins];
    for &o in objects {
        let bin = bin_of(centroids[o as usize], axis, low, scale, bins);
        bin_count[bin] += 1;
        bin_box[bin] = bin_box[bin].union(boxes[o as usize]);
    }
    let mut right_cost = vec![0.0f64; bins];
    let (mut right_box, mut right_count) = (Aabb::EMPTY, 0usize);
    for bin in (1..bins).rev() {
        right_box = right_box.union(bin_box[bin]);
        right_count += bin_count[bin];
        right_cost[bin] = half_area_with(&right_box, rules) * right_count as f64;
    }
    let node_area = half_area_with(node_box, rules);
    let leaf_cost = node_area * objects.len() as f64;
    let traversal = if rules.sah_traversal_cost {
        super::TRAVERSAL_COST * node_area
    } else {
        0.0
    };
    let mut best: Option<(usize, f64)> = None;
    let (mut left_box, mut left_count) = (Aabb::EMPTY, 0usize);
    for boundary in 1..bins {
        left_box = left_box.union(bin_box[boundary - 1]);
        left_count += bin_count[boundary - 1];
        if left_count == 0 || left_count == objects.len() {
            continue;
        }
        let cost =
            traversal + half_area_with(&left_box, rules) * left_count as f64 + right_cost[boundary];
        let better = best.is_none_or(|(_, best_cost)| {
            if rules.sah_first_of_equals {
                cost < best_cost
            } else {
                cost <= best_cost
            }
        });
        if better {
            best = Some((boundary, cost));
        }
    }
    let (boundary, cost) = best?;
    (!rules.sah_leaf_test || cost < leaf_cost).then_some(Cutting::BinsBefore {
        axis,
        low,
        scale,
        bins,
        boundary,
    })
}

macro_rules! builds {
    ($($(#[$doc:meta])* $name:ident = $rules:expr;)*) => {$(
        $(#[$doc])*
        struct $name;
        plant! {
            $name;
            fn build_bvh(bounds: &[Option<Aabb>], options: &BvhOptions) -> Bvh {
                build_with(bounds, options, $rules)
            }
        }
    )*};
}

builds! {
    /// Every rule kept: it must pass.
    BuildAsTheLessonSays = BuildRules::CORRECT;
    Unpadded = BuildRules { pads: false, ..BuildRules::CORRECT };
    /// Only boxes with `min < max` on every axis go in the tree: a
    /// triangle's flat box goes to `unbounded`, where the loop still finds
    /// it.
    FlatBoxesLeftOut = BuildRules { flat_boxes_kept: false, ..BuildRules::CORRECT };
    NonFiniteBoxesInTheTree = BuildRules { non_finite_boxes_out: false, ..BuildRules::CORRECT };
    LeafBelowMaxLeaf = BuildRules { leaf_size_slip: -1, ..BuildRules::CORRECT };
    LeafAtOneMoreThanMaxLeaf = BuildRules { leaf_size_slip: 1, ..BuildRules::CORRECT };
    CutAlongTheWidestBoxAxis = BuildRules { axis: CutAxis::WidestBox, ..BuildRules::CORRECT };
    NeverCutAlongZ = BuildRules { axis: CutAxis::XOrY, ..BuildRules::CORRECT };
    CutAtTheMeanCentroid = BuildRules { middle_of_the_spread: false, ..BuildRules::CORRECT };
    /// Coincident centroids cut by list position: a valid tree whose two
    /// children have the same box.
    CoincidentCutInHalves = BuildRules { coincident_leaf: false, ..BuildRules::CORRECT };
    SahWithoutTheTraversalCost = BuildRules { sah_traversal_cost: false, ..BuildRules::CORRECT };
    SahWithoutTheLeafTest = BuildRules { sah_leaf_test: false, ..BuildRules::CORRECT };
    SahTieToTheLastBoundary = BuildRules { sah_first_of_equals: false, ..BuildRules::CORRECT };
    SahTwoPairsOfSides = BuildRules { sah_three_sides: false, ..BuildRules::CORRECT };
    SahAreasInF32 = BuildRules { sah_areas_in_f64: false, ..BuildRules::CORRECT };
    /// An inner node's box is its left child's: every walk is still
    /// right where the right child's box lies inside it, and the tree's
    /// invariant is broken.
    InnerBoxOfTheLeftChild = BuildRules { inner_box_holds_both: false, ..BuildRules::CORRECT };
}

#[test]
fn contract_the_build_copy_passes() {
    assert_robust::<BuildAsTheLessonSays>();
}

#[test]
fn contract_every_boxed_object_once_in_boxes_that_hold_it_padded() {
    assert_caught::<Unpadded>("bvh-build-holds-every-sphere");
    assert_caught::<InnerBoxOfTheLeftChild>("bvh-build-holds-every-sphere");
    assert_caught::<FlatBoxesLeftOut>("bvh-build-mixed-shapes");
}

#[test]
fn contract_no_box_nan_or_infinite_in_the_tree() {
    assert_caught::<NonFiniteBoxesInTheTree>("bvh-nan-and-infinite-boxes-stay-out");
}

#[test]
fn contract_a_leaf_at_max_leaf_objects_a_cut_at_one_more() {
    assert_caught::<LeafBelowMaxLeaf>("bvh-max-leaf-objects-stay-a-leaf");
    assert_caught::<LeafAtOneMoreThanMaxLeaf>("bvh-one-more-than-max-leaf-is-cut");
}

#[test]
fn contract_the_cut_is_where_the_centroids_spread_at_their_middle() {
    assert_caught::<NeverCutAlongZ>("bvh-cut-along-z");
    assert_caught::<CutAlongTheWidestBoxAxis>("bvh-cut-where-the-centroids-spread");
    assert_caught::<CutAtTheMeanCentroid>("bvh-middle-not-the-mean");
    assert_caught::<CoincidentCutInHalves>("bvh-coincident-centroids-stay-a-leaf");
}

#[test]
fn contract_the_surface_area_heuristic() {
    assert_caught::<SahWithoutTheTraversalCost>("bvh-sah-leaf-cheaper-than-any-cut");
    assert_caught::<SahWithoutTheLeafTest>("bvh-sah-leaf-cheaper-than-any-cut");
    assert_caught::<SahTieToTheLastBoundary>("bvh-sah-tie-goes-to-the-first-boundary");
    assert_caught::<SahTwoPairsOfSides>("bvh-sah-three-sides-count");
    assert_caught_by_hard_case::<SahAreasInF32>("bvh-sah-boxes-1e20-wide");
}

/// What a variant of `nearest_hit_bvh` does, by [`nearest_walk`].
#[derive(Clone, Copy)]
struct WalkRules {
    /// The objects outside the tree asked at all.
    asks_planes: bool,
    /// Asked before the tree (else after it).
    planes_first: bool,
    /// Boxes tested against the best hit so far, and a waiting child
    /// skipped when it comes off beyond it (else `t_max` throughout).
    prunes: bool,
    /// Each object asked up to and including the best so far (else to
    /// `t_max`).
    asks_up_to_the_best: bool,
    /// How many waiting nodes the stack keeps; those pushed beyond are
    /// dropped.
    stack_cap: usize,
}

impl WalkRules {
    const CORRECT: WalkRules = WalkRules {
        asks_planes: true,
        planes_first: true,
        prunes: true,
        asks_up_to_the_best: true,
        stack_cap: usize::MAX,
    };
}

/// Chapter 11's nearest-hit walk, nearer child first, as `rules` say.
fn nearest_walk<C: Chapters>(
    bvh: &Bvh,
    objects: &Objects<C>,
    ray: &Ray,
    (t_min, t_max): (f32, f32),
    rules: WalkRules,
) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    let ask = |object: u32, best: &mut Option<Hit>| {
        let limit = match *best {
            Some(hit) if rules.asks_up_to_the_best => hit.t.next_up(),
            _ => t_max,
        };
        let object = object as usize;
        if let Some(t) = objects.intersect(object, ray, t_min, limit)
            && best.is_none_or(|b| t < b.t || (t == b.t && object < b.object))
        {
            *best = Some(Hit { object, t });
        }
    };
    let planes = |best: &mut Option<Hit>| {
        if rules.asks_planes {
            for &object in &bvh.unbounded {
                ask(object, best);
            }
        }
    };
    if rules.planes_first {
        planes(&mut best);
    }
    let inverse = ray.dir.recip();
    let closest = |best: Option<Hit>| match best {
        Some(hit) if rules.prunes => hit.t,
        _ => t_max,
    };
    let enter = |node: usize, best: Option<Hit>| {
        C::hit_box(
            &bvh.nodes[node].bounds,
            ray.origin,
            inverse,
            t_min,
            closest(best),
        )
        .map(|entry| (node, entry))
    };
    let mut stack: Vec<(usize, f32)> = Vec::new();
    if !bvh.nodes.is_empty() {
        stack.extend(enter(0, best));
    }
    while let Some((index, entry)) = stack.pop() {
        if !(entry <= closest(best)) {
            continue;
        }
        let node = &bvh.nodes[index];
        let Some((left, right)) = node.children() else {
            for &object in &bvh.primitives[node.primitive_range()] {
                ask(object, &mut best);
            }
            continue;
        };
        let mut entered: Vec<(usize, f32)> = [enter(left, best), enter(right, best)]
            .into_iter()
            .flatten()
            .collect();
        // The farther first, so that the nearer comes off the stack next.
        entered.sort_by(|a, b| b.1.total_cmp(&a.1));
        for child in entered {
            if stack.len() < rules.stack_cap {
                stack.push(child);
            }
        }
    }
    if !rules.planes_first {
        planes(&mut best);
    }
    best
}

macro_rules! walks {
    ($($(#[$doc:meta])* $name:ident = $rules:expr;)*) => {$(
        $(#[$doc])*
        struct $name;
        plant! {
            $name;
            fn nearest_hit_bvh(
                bvh: &Bvh,
                objects: &Objects<Planted>,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<Hit> {
                nearest_walk(bvh, objects, ray, (t_min, t_max), $rules)
            }
        }
    )*};
}

walks! {
    /// Every rule kept: it must pass.
    WalkAsTheLessonSays = WalkRules::CORRECT;
    PlanesForgotten = WalkRules { asks_planes: false, ..WalkRules::CORRECT };
    /// The planes asked after the tree: the same answers, and every box
    /// tested against `t_max` where a plane's hit would have shortened it.
    PlanesLast = WalkRules { planes_first: false, ..WalkRules::CORRECT };
    /// No box skipped for a hit already found: the same answers, every
    /// box the ray enters visited.
    NeverSkips = WalkRules { prunes: false, ..WalkRules::CORRECT };
    /// Every object asked up to `t_max`, its hit compared afterwards: the
    /// same answers.
    AsksToTMax = WalkRules { asks_up_to_the_best: false, ..WalkRules::CORRECT };
    /// A fixed stack of 64 that drops what does not fit.
    StackDropsWhatOverflows = WalkRules { stack_cap: 64, ..WalkRules::CORRECT };
}

#[test]
fn contract_the_walk_copy_passes() {
    assert_robust::<WalkAsTheLessonSays>();
}

#[test]
fn contract_planes_asked_first_and_their_hit_shortens_the_walk() {
    assert_caught::<PlanesForgotten>("bvh-plane-still-hit");
    assert_caught::<PlanesLast>("bvh-planes-first-their-hit-shortens-the-walk");
}

#[test]
fn contract_a_box_entered_beyond_the_best_is_skipped() {
    assert_caught::<NeverSkips>("bvh-nearest-skips-boxes-beyond-the-best");
}

#[test]
fn contract_each_object_asked_up_to_the_best() {
    assert_caught::<AsksToTMax>("bvh-nearest-asks-up-to-the-best");
}

#[test]
fn contract_the_stack_spills_and_loses_nothing() {
    assert_caught_by_hard_case::<StackDropsWhatOverflows>("bvh-deeper-than-the-stack");
}

/// What a variant of `any_hit_bvh` does, by [`any_walk`].
#[derive(Clone, Copy)]
struct AnyRules {
    asks_planes: bool,
    planes_first: bool,
    /// The first hit ends the walk (else every box the ray enters is
    /// walked, and the nearest hit kept).
    stops_at_the_first: bool,
    /// The tree's boxes tested (else every object of `primitives` asked
    /// in turn).
    tests_boxes: bool,
    /// Hits beyond `t_max` refused.
    keeps_t_max: bool,
    stack_cap: usize,
}

impl AnyRules {
    const CORRECT: AnyRules = AnyRules {
        asks_planes: true,
        planes_first: true,
        stops_at_the_first: true,
        tests_boxes: true,
        keeps_t_max: true,
        stack_cap: usize::MAX,
    };
}

/// Chapter 11's any-hit walk as `rules` say.
fn any_walk<C: Chapters>(
    bvh: &Bvh,
    objects: &Objects<C>,
    ray: &Ray,
    (t_min, t_max): (f32, f32),
    rules: AnyRules,
) -> Option<Hit> {
    let t_max = if rules.keeps_t_max {
        t_max
    } else {
        f32::INFINITY
    };
    let mut found: Option<Hit> = None;
    // Whether the walk ends here.
    let mut ask = |object: u32| {
        let object = object as usize;
        let Some(t) = objects.intersect(object, ray, t_min, t_max) else {
            return false;
        };
        if found.is_none_or(|f| t < f.t) {
            found = Some(Hit { object, t });
        }
        rules.stops_at_the_first
    };
    let planes_now = |first: bool| rules.asks_planes && rules.planes_first == first;
    if planes_now(true) && bvh.unbounded.iter().any(|&object| ask(object)) {
        return found;
    }
    if !rules.tests_boxes {
        if bvh.primitives.iter().any(|&object| ask(object)) {
            return found;
        }
    } else if !bvh.nodes.is_empty() {
        let inverse = ray.dir.recip();
        let enters = |node: usize| {
            C::hit_box(&bvh.nodes[node].bounds, ray.origin, inverse, t_min, t_max).is_some()
        };
        let mut stack = if enters(0) { vec![0] } else { vec![] };
        while let Some(index) = stack.pop() {
            let node = &bvh.nodes[index];
            let Some((left, right)) = node.children() else {
                if bvh.primitives[node.primitive_range()]
                    .iter()
                    .any(|&object| ask(object))
                {
                    return found;
                }
                continue;
            };
            for child in [right, left] {
                if enters(child) && stack.len() < rules.stack_cap {
                    stack.push(child);
                }
            }
        }
    }
    if planes_now(false) && bvh.unbounded.iter().any(|&object| ask(object)) {
        return found;
    }
    found
}

macro_rules! any_walks {
    ($($(#[$doc:meta])* $name:ident = $rules:expr;)*) => {$(
        $(#[$doc])*
        struct $name;
        plant! {
            $name;
            fn any_hit_bvh(
                bvh: &Bvh,
                objects: &Objects<Planted>,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<Hit> {
                any_walk(bvh, objects, ray, (t_min, t_max), $rules)
            }
        }
    )*};
}

any_walks! {
    /// Every rule kept: it must pass.
    AnyWalkAsTheLessonSays = AnyRules::CORRECT;
    AnyHitForgetsThePlanes = AnyRules { asks_planes: false, ..AnyRules::CORRECT };
    AnyHitPlanesLast = AnyRules { planes_first: false, ..AnyRules::CORRECT };
    /// Walks on past its first hit and keeps the nearest: the same yes or
    /// no, with work a shadow ray does not need.
    AnyHitWalksOn = AnyRules { stops_at_the_first: false, ..AnyRules::CORRECT };
    /// Asks the tree's objects in list order, no box tested.
    AnyHitAsksEveryObject = AnyRules { tests_boxes: false, ..AnyRules::CORRECT };
    AnyHitBeyondTheLight = AnyRules { keeps_t_max: false, ..AnyRules::CORRECT };
    AnyHitStackDropsWhatOverflows = AnyRules { stack_cap: 64, ..AnyRules::CORRECT };
}

#[test]
fn contract_the_any_hit_copy_passes() {
    assert_robust::<AnyWalkAsTheLessonSays>();
}

#[test]
fn contract_any_hit_finds_a_blocker_before_the_light() {
    assert_caught::<AnyHitForgetsThePlanes>("bvh-any-hit-only-planes");
    assert_caught::<AnyHitBeyondTheLight>("bvh-any-hit-beyond-the-light");
}

#[test]
fn contract_any_hit_asks_planes_first_only_entered_boxes_and_stops_at_its_first_hit() {
    assert_caught::<AnyHitPlanesLast>("bvh-any-hit-stops-at-its-first-hit");
    assert_caught::<AnyHitWalksOn>("bvh-any-hit-stops-at-its-first-hit");
    assert_caught::<AnyHitAsksEveryObject>("bvh-any-hit-stops-at-its-first-hit");
    assert_caught_by_hard_case::<AnyHitStackDropsWhatOverflows>("bvh-any-hit-stack-spills-over");
}

/// One sentence of `hit_boxes` broken.
#[derive(Clone, Copy, PartialEq)]
enum BoxesSlip {
    /// A lane the ray misses answers `inf`, not NaN.
    MissIsInfinity,
    /// `entry < exit`: a lane touched at a single `t` is missed.
    IntervalOpen,
    /// No widening.
    Unwidened,
    /// A slack of `2 gamma_3 / |t|`, which grows as `t` shrinks.
    SlackDividedByT,
    /// The entry moved up by its slack, as the exit is: narrowed, not
    /// widened.
    EntryRaised,
}

/// Chapter 11's `hit_boxes` as the reference writes it, with `slip`.
fn boxes_with(
    boxes: &Boxes4,
    origin: Vec3,
    inverse: Vec3,
    t_min: f32,
    t_max: f32,
    slip: BoxesSlip,
) -> Vec4 {
    if slip == BoxesSlip::MissIsInfinity {
        let entries = Reference::hit_boxes(boxes, origin, inverse, t_min, t_max);
        return Vec4::select(entries.is_nan_mask(), Vec4::INFINITY, entries);
    }
    let mut entry = Vec4::NEG_INFINITY;
    let mut exit = Vec4::INFINITY;
    for axis in 0..3 {
        let (near_planes, far_planes) = if inverse[axis].is_sign_negative() {
            (boxes.max[axis], boxes.min[axis])
        } else {
            (boxes.min[axis], boxes.max[axis])
        };
        let near = (near_planes - Vec4::splat(origin[axis])) * inverse[axis];
        let far = (far_planes - Vec4::splat(origin[axis])) * inverse[axis];
        entry = raylab::bvh::greater_of(near, entry);
        exit = raylab::bvh::lesser_of(far, exit);
    }
    if slip != BoxesSlip::Unwidened {
        let slack = |t: Vec4| {
            let slack = if slip == BoxesSlip::SlackDividedByT {
                2.0 * super::GAMMA_3 / t.abs()
            } else {
                2.0 * super::GAMMA_3 * t.abs()
            };
            raylab::bvh::lesser_of(slack, Vec4::splat(f32::MAX))
        };
        let entry_slack = if slip == BoxesSlip::EntryRaised {
            -slack(entry)
        } else {
            slack(entry)
        };
        (entry, exit) = (entry - entry_slack, exit + slack(exit));
    }
    let entry = raylab::bvh::greater_of(Vec4::splat(t_min), entry);
    let exit = raylab::bvh::lesser_of(Vec4::splat(t_max), exit);
    let meets = if slip == BoxesSlip::IntervalOpen {
        entry.cmplt(exit)
    } else {
        entry.cmple(exit)
    };
    Vec4::select(meets, entry, Vec4::NAN)
}

macro_rules! four_boxes {
    ($($(#[$doc:meta])* $name:ident = $slip:expr;)*) => {$(
        $(#[$doc])*
        struct $name;
        plant! {
            $name;
            fn hit_boxes(
                boxes: &Boxes4,
                origin: Vec3,
                inverse: Vec3,
                t_min: f32,
                t_max: f32,
            ) -> Vec4 {
                boxes_with(boxes, origin, inverse, t_min, t_max, $slip)
            }
        }
    )*};
}

four_boxes! {
    BoxMissIsInfinity = BoxesSlip::MissIsInfinity;
    LanesIntervalOpen = BoxesSlip::IntervalOpen;
    LanesUnwidened = BoxesSlip::Unwidened;
    LanesSlackDividedByT = BoxesSlip::SlackDividedByT;
    LanesEntryRaised = BoxesSlip::EntryRaised;
}

#[test]
fn contract_hit_boxes_lane_by_lane() {
    assert_caught::<BoxMissIsInfinity>("boxes-four-at-once");
    assert_caught::<LanesIntervalOpen>("boxes-flat-touched-at-t-min");
    assert_caught_by_hard_case::<LanesUnwidened>("boxes-rays-along-edges");
    assert_caught::<LanesSlackDividedByT>("boxes-entry-close-to-the-origin");
    assert_caught_by_hard_case::<LanesEntryRaised>("wide-coplanar-tie-far-from-the-origin");
}

/// A triangle lane the ray misses answers `inf`, not NaN.
struct TriangleMissIsInfinity;
plant! {
    TriangleMissIsInfinity;
    fn intersect_triangles(triangles: &Triangles4, ray: &Ray, t_min: f32, t_max: f32) -> Vec4 {
        let t = Reference::intersect_triangles(triangles, ray, t_min, t_max);
        Vec4::select(t.is_nan_mask(), Vec4::INFINITY, t)
    }
}

/// The four lanes answer beyond `t_max`: a walk that offers every lane's
/// hit and keeps the nearest finds the same hits.
struct LanesIgnoreTMax;
plant! {
    LanesIgnoreTMax;
    fn intersect_triangles(triangles: &Triangles4, ray: &Ray, t_min: f32, _t_max: f32) -> Vec4 {
        Reference::intersect_triangles(triangles, ray, t_min, f32::INFINITY)
    }
}

/// The lanes' interval closed at both ends, `t_min <= t <= t_max`.
struct LanesClosedInterval;
plant! {
    LanesClosedInterval;
    fn intersect_triangles(triangles: &Triangles4, ray: &Ray, t_min: f32, t_max: f32) -> Vec4 {
        Reference::intersect_triangles(triangles, ray, t_min.next_down(), t_max.next_up())
    }
}

/// No lane's edge functions recomputed in `f64`: a zero that rounding made
/// counts as inside.
struct LanesWithoutTheFallback;
plant! {
    LanesWithoutTheFallback;
    fn intersect_triangles(triangles: &Triangles4, ray: &Ray, t_min: f32, t_max: f32) -> Vec4 {
        Vec4::from_array(std::array::from_fn(|lane| {
            f64_edges_triangle(&triangles.get(lane), ray, t_min, t_max, Fallback::Never)
                .0
                .unwrap_or(f32::NAN)
        }))
    }
}

#[test]
fn contract_intersect_triangles_lane_by_lane() {
    assert_caught::<TriangleMissIsInfinity>("triangles-four-at-once");
    assert_caught::<LanesIgnoreTMax>("triangles-at-the-ends-of-the-interval");
    assert_caught::<LanesClosedInterval>("triangles-at-the-ends-of-the-interval");
    assert_caught_by_hard_case::<LanesWithoutTheFallback>("triangles-closed-mesh-in-fours");
}

macro_rules! folds {
    ($($(#[$doc:meta])* $name:ident = $rules:expr;)*) => {$(
        $(#[$doc])*
        struct $name;
        plant! {
            $name;
            fn collapse_bvh(bvh: &Bvh, shapes: &[Shape]) -> WideBvh {
                plain_fold(bvh, shapes, $rules)
            }
        }
    )*};
}

folds! {
    /// Every lane given the box of the binary node it was folded from:
    /// a valid tree whose boxes hold too much.
    LanesTakeTheParentsBox = FoldRules { lanes_keep_their_boxes: false, ..FoldRules::CORRECT };
    OneObjectPerLeaf4 = FoldRules { objects_per_leaf4: 1, ..FoldRules::CORRECT };
    /// A sphere's lane keeps the corners of the triangle before it.
    AloneLaneKeepsCorners = FoldRules { alone_corners_nan: false, ..FoldRules::CORRECT };
    FoldForgetsThePlanes = FoldRules { keeps_unbounded: false, ..FoldRules::CORRECT };
}

#[test]
fn contract_the_fold_keeps_the_binary_trees_boxes_and_fills_its_leaves() {
    assert_caught::<LanesTakeTheParentsBox>("collapse-four-lanes");
    assert_caught::<OneObjectPerLeaf4>("collapse-triangles-copied-a-sphere-alone");
    assert_caught::<AloneLaneKeepsCorners>("collapse-triangles-copied-a-sphere-alone");
    assert_caught::<FoldForgetsThePlanes>("collapse-planes-stay-out");
}

macro_rules! wide_walks {
    ($($(#[$doc:meta])* $name:ident = $rules:expr;)*) => {$(
        $(#[$doc])*
        struct $name;
        plant! {
            $name;
            fn nearest_hit_wide(
                wide: &WideBvh,
                objects: &Objects<Planted>,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<Hit> {
                plain_wide_walk(wide, objects, ray, (t_min, t_max), $rules)
            }
        }
    )*};
}

wide_walks! {
    /// Waiting children never skipped: every lane entered when its node
    /// was opened is walked, whatever was hit since.
    WideNeverSkipsAWaitingChild = WideRules { prunes_waiting: false, ..WideRules::CORRECT };
    WidePlanesLast = WideRules { planes_first: false, ..WideRules::CORRECT };
    WideAsksToTMax = WideRules { asks_up_to_the_best: false, ..WideRules::CORRECT };
    /// A leaf's objects asked one by one only when none of its triangle
    /// lanes hit.
    WideSpheresOnlyWithoutTriangleHits =
        WideRules { spheres_only_without_triangle_hits: true, ..WideRules::CORRECT };
    WideStackDropsWhatOverflows = WideRules { stack_cap: 64, ..WideRules::CORRECT };
    /// A triangle lane's hit kept only when strictly nearer than the best
    /// so far, so a tie goes to whoever was asked first.
    WideLaneTieToWhoeverIsAskedFirst =
        WideRules { lanes_tie_by_index: false, ..WideRules::CORRECT };
}

#[test]
fn contract_the_wide_walk_skips_asks_and_orders_as_the_binary_one() {
    assert_caught::<WideNeverSkipsAWaitingChild>("wide-skips-waiting-children-beyond-the-best");
    assert_caught::<WideAsksToTMax>("wide-asks-up-to-the-best");
    assert_caught::<WidePlanesLast>("wide-planes-first");
    assert_caught::<WideLaneTieToWhoeverIsAskedFirst>("wide-lane-tie-goes-to-the-first-listed");
}

#[test]
fn contract_a_wide_leaf_of_triangles_and_spheres() {
    assert_caught::<WideSpheresOnlyWithoutTriangleHits>("wide-mixed-leaf");
}

#[test]
fn contract_the_wide_stack_spills_and_loses_nothing() {
    assert_caught_by_hard_case::<WideStackDropsWhatOverflows>("wide-deeper-than-the-stack");
}

/// What a variant of `any_hit_wide` does, by [`wide_any_walk`].
#[derive(Clone, Copy)]
struct WideAnyRules {
    planes_first: bool,
    stops_at_the_first: bool,
    keeps_t_max: bool,
    /// A `Leaf4`'s objects asked one by one only when it holds no
    /// triangle.
    spheres_only_in_sphere_leaves: bool,
    stack_cap: usize,
}

impl WideAnyRules {
    const CORRECT: WideAnyRules = WideAnyRules {
        planes_first: true,
        stops_at_the_first: true,
        keeps_t_max: true,
        spheres_only_in_sphere_leaves: false,
        stack_cap: usize::MAX,
    };
}

/// Chapter 11's wide any-hit walk as `rules` say.
fn wide_any_walk<C: Chapters>(
    wide: &WideBvh,
    objects: &Objects<C>,
    ray: &Ray,
    (t_min, t_max): (f32, f32),
    rules: WideAnyRules,
) -> Option<Hit> {
    let t_max = if rules.keeps_t_max {
        t_max
    } else {
        f32::INFINITY
    };
    let found = std::cell::Cell::new(None::<Hit>);
    // Whether the walk ends here.
    let keep = |object: usize, t: f32| {
        if found.get().is_none_or(|f| t < f.t) {
            found.set(Some(Hit { object, t }));
        }
        rules.stops_at_the_first
    };
    let planes = || {
        wide.unbounded.iter().any(|&object| {
            objects
                .intersect(object as usize, ray, t_min, t_max)
                .is_some_and(|t| keep(object as usize, t))
        })
    };
    if rules.planes_first && planes() {
        return found.get();
    }
    let inverse = ray.dir.recip();
    let mut stack = if wide.nodes.is_empty() {
        vec![]
    } else {
        vec![(0u32, 0u32)]
    };
    'walk: while let Some((first, count)) = stack.pop() {
        if count > 0 {
            for leaf in &wide.leaves[first as usize..(first + count) as usize] {
                let t = C::intersect_triangles(&leaf.triangles, ray, t_min, t_max);
                for lane in (0..WIDTH).filter(|&lane| !t[lane].is_nan()) {
                    if keep(leaf.objects[lane] as usize, t[lane]) {
                        break 'walk;
                    }
                }
                let holds_a_triangle = (0..WIDTH).any(|lane| {
                    leaf.objects[lane] != u32::MAX && leaf.one_by_one & (1 << lane) == 0
                });
                if rules.spheres_only_in_sphere_leaves && holds_a_triangle {
                    continue;
                }
                for lane in (0..WIDTH).filter(|&lane| leaf.one_by_one & (1 << lane) != 0) {
                    let object = leaf.objects[lane] as usize;
                    if let Some(t) = objects.intersect(object, ray, t_min, t_max)
                        && keep(object, t)
                    {
                        break 'walk;
                    }
                }
            }
            continue;
        }
        let node = &wide.nodes[first as usize];
        let entries = C::hit_boxes(&node.boxes, ray.origin, inverse, t_min, t_max);
        for lane in
            (0..WIDTH).filter(|&lane| !entries[lane].is_nan() && node.used_lanes().test(lane))
        {
            if stack.len() < rules.stack_cap {
                stack.push((node.first[lane], node.count[lane]));
            }
        }
    }
    if found.get().is_none() && !rules.planes_first {
        planes();
    }
    found.get()
}

macro_rules! wide_any_walks {
    ($($(#[$doc:meta])* $name:ident = $rules:expr;)*) => {$(
        $(#[$doc])*
        struct $name;
        plant! {
            $name;
            fn any_hit_wide(
                wide: &WideBvh,
                objects: &Objects<Planted>,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<Hit> {
                wide_any_walk(wide, objects, ray, (t_min, t_max), $rules)
            }
        }
    )*};
}

wide_any_walks! {
    /// Every rule kept: it must pass.
    WideAnyWalkAsTheLessonSays = WideAnyRules::CORRECT;
    WideAnyHitPlanesLast = WideAnyRules { planes_first: false, ..WideAnyRules::CORRECT };
    WideAnyHitWalksOn = WideAnyRules { stops_at_the_first: false, ..WideAnyRules::CORRECT };
    WideAnyHitBeyondTheLight = WideAnyRules { keeps_t_max: false, ..WideAnyRules::CORRECT };
    /// A leaf's spheres asked only where it holds no triangle.
    WideAnyHitSpheresOnlyInSphereLeaves =
        WideAnyRules { spheres_only_in_sphere_leaves: true, ..WideAnyRules::CORRECT };
    WideAnyHitStackDropsWhatOverflows = WideAnyRules { stack_cap: 64, ..WideAnyRules::CORRECT };
}

#[test]
fn contract_the_wide_any_hit_copy_passes() {
    assert_robust::<WideAnyWalkAsTheLessonSays>();
}

#[test]
fn contract_wide_any_hit() {
    assert_caught::<WideAnyHitBeyondTheLight>("wide-any-hit-beyond-the-light");
    assert_caught::<WideAnyHitPlanesLast>("wide-any-hit-stops-at-its-first-hit");
    assert_caught::<WideAnyHitWalksOn>("wide-any-hit-stops-at-its-first-hit");
    assert_caught::<WideAnyHitSpheresOnlyInSphereLeaves>("wide-any-hit-mixed-leaf");
    assert_caught_by_hard_case::<WideAnyHitStackDropsWhatOverflows>(
        "wide-any-hit-stack-spills-over",
    );
}

// ---------------------------------------------------------------------------
// Not started, and the picture.

struct NotWritten;
plant! {
    NotWritten;
    fn hit_box(_bounds: &Aabb, _origin: Vec3, _inverse: Vec3, _t_min: f32, _t_max: f32) -> Option<f32> {
        todo!("chapter 11: hit_box")
    }
    fn build_bvh(_bounds: &[Option<Aabb>], _options: &BvhOptions) -> Bvh {
        todo!("chapter 11: build_bvh")
    }
    fn nearest_hit_bvh(_bvh: &Bvh, _objects: &Objects<Planted>, _ray: &Ray, _t_min: f32, _t_max: f32) -> Option<Hit> {
        todo!("chapter 11: nearest_hit_bvh")
    }
    fn any_hit_bvh(_bvh: &Bvh, _objects: &Objects<Planted>, _ray: &Ray, _t_min: f32, _t_max: f32) -> Option<Hit> {
        todo!("chapter 11: any_hit_bvh")
    }
    fn hit_boxes(_boxes: &Boxes4, _origin: Vec3, _inverse_direction: Vec3, _t_min: f32, _t_max: f32) -> Vec4 {
        todo!("chapter 11: hit_boxes")
    }
    fn intersect_triangles(_triangles: &Triangles4, _ray: &Ray, _t_min: f32, _t_max: f32) -> Vec4 {
        todo!("chapter 11: intersect_triangles")
    }
    fn collapse_bvh(_bvh: &Bvh, _shapes: &[Shape]) -> WideBvh {
        todo!("chapter 11: collapse_bvh")
    }
    fn nearest_hit_wide(_wide: &WideBvh, _objects: &Objects<Planted>, _ray: &Ray, _t_min: f32, _t_max: f32) -> Option<Hit> {
        todo!("chapter 11: nearest_hit_wide")
    }
    fn any_hit_wide(_wide: &WideBvh, _objects: &Objects<Planted>, _ray: &Ray, _t_min: f32, _t_max: f32) -> Option<Hit> {
        todo!("chapter 11: any_hit_wide")
    }
}

#[test]
fn unwritten_chapter_11_is_not_started() {
    let verdict = planted::check_chapter::<NotWritten>(11, &options());
    assert_eq!(verdict.status, Status::NotStarted, "{}", verdict.text());
    assert_eq!(
        verdict.not_written,
        [
            "hit_box",
            "build_bvh",
            "nearest_hit_bvh",
            "any_hit_bvh",
            "hit_boxes",
            "intersect_triangles",
            "collapse_bvh",
            "nearest_hit_wide",
            "any_hit_wide"
        ]
    );
}

fn image(chapter: u8) -> Vec<u8> {
    let scene = raylab::builtin::scene(11).expect("built-in scene");
    let settings = RenderSettings {
        width: REFERENCE_WIDTH,
        height: REFERENCE_HEIGHT,
        ..scene.render
    };
    raylab::render_with::<Reference>(&scene, chapter, &settings, None)
        .expect("valid settings")
        .rgb
}

#[test]
fn the_tree_changes_no_pixel_of_chapter_11s_scene() {
    assert!(image(11) == image(10), "stage 11 differs from stage 10");
}

/// How `left_first_walk` treats a leaf's objects.
#[derive(Clone, Copy, PartialEq)]
enum Leaf {
    AsksAll,
    /// The bug of a leaf asked for any hit: the first object that hits
    /// ends the leaf.
    StopsAtItsFirstHit,
}

/// A walk with a plain stack that opens left children first and skips a
/// box entered beyond the best hit so far: the skeleton shared by gallery
/// bugs and an alternative, which differ only in the interval each object
/// is asked in (`limit`, from the best hit so far), in which answers
/// replace the best (`better`, given the object, its `t` and the best) and
/// in `leaf`.
fn left_first_walk<C: Chapters>(
    bvh: &Bvh,
    objects: &Objects<C>,
    ray: &Ray,
    (t_min, t_max): (f32, f32),
    limit: impl Fn(Option<Hit>) -> f32,
    better: impl Fn(usize, f32, Option<Hit>) -> bool,
    leaf: Leaf,
) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    // Whether the object hits at all (kept or not).
    let ask = |object: u32, best: &mut Option<Hit>| {
        let object = object as usize;
        let Some(t) = objects.intersect(object, ray, t_min, limit(*best)) else {
            return false;
        };
        if better(object, t, *best) {
            *best = Some(Hit { object, t });
        }
        true
    };
    for &object in &bvh.unbounded {
        ask(object, &mut best);
    }
    let inverse = ray.dir.recip();
    let mut stack = if bvh.nodes.is_empty() {
        Vec::new()
    } else {
        vec![0]
    };
    while let Some(index) = stack.pop() {
        let node = &bvh.nodes[index];
        let closest = best.map_or(t_max, |hit| hit.t);
        if C::hit_box(&node.bounds, ray.origin, inverse, t_min, closest).is_none() {
            continue;
        }
        match node.children() {
            Some((left, right)) => stack.extend([right, left]),
            None => {
                for &object in &bvh.primitives[node.primitive_range()] {
                    if ask(object, &mut best) && leaf == Leaf::StopsAtItsFirstHit {
                        break;
                    }
                }
            }
        }
    }
    best
}

/// `--stats` counts a shadow ray that meets the surface it left as acne.
/// From a point chapter 10 lifted off its flat triangle, the triangle
/// itself can rightly stand in the way (at 640x480 the built-in scene has
/// five such rays): that is the faceted shadow, not acne, and the counter
/// must leave it out.
#[test]
fn lifted_terminator_points_are_not_counted_as_acne() {
    let scene = raylab::builtin::scene(11).expect("built-in scene");
    let settings = RenderSettings {
        width: 640,
        height: 480,
        samples: 1,
        ..scene.render
    };
    let rendered = raylab::render::render(&scene, 11, &settings, None).expect("renders");
    assert_eq!(rendered.rays.self_shadow_hits, 0);
}

/// The reference's tests, asserting that the judge never calls them as
/// raylab's own: there, a student's test could run raylab's answers (the
/// reference walks, say) without their being reported.
struct TestsNeverRaylabsOwn;
plant! {
    TestsNeverRaylabsOwn;
    fn intersect_plane(plane: &raylab::Plane, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        assert!(!raylab::answer_key::inside_own(), "intersect_plane run as raylab's own");
        <Reference as Chapters>::intersect_plane(plane, ray, t_min, t_max)
    }
    fn intersect_sphere(sphere: &raylab::Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        assert!(!raylab::answer_key::inside_own(), "intersect_sphere run as raylab's own");
        <Reference as Chapters>::intersect_sphere(sphere, ray, t_min, t_max)
    }
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        assert!(!raylab::answer_key::inside_own(), "intersect_triangle run as raylab's own");
        <Reference as Chapters>::intersect_triangle(triangle, ray, t_min, t_max)
    }
}

#[test]
fn the_judge_never_runs_the_chapters_tests_as_raylabs_own() {
    assert_robust::<TestsNeverRaylabsOwn>();
}
