//! How the tree cases are judged: the shape of a built tree, and the
//! walks' answers against chapter 3's loop.

use super::*;

/// The rays of a box-edges case: `rays` rays from random origins aimed at
/// random points of the twelve edges of `bounds` (drawn from `seed`), as
/// `(origin, direction)`.
pub(super) fn edge_rays(bounds: &Aabb, rays: u32, seed: u64) -> impl Iterator<Item = (Vec3, Vec3)> {
    let mut numbers = exact::Xorshift::new(seed);
    let bounds = *bounds;
    (0..rays).map(move |_| {
        // A point on one of the twelve edges: one axis free, the other two
        // on a face each.
        let free_axis = numbers.below(3);
        let mut aim = Vec3::ZERO;
        for axis in 0..3 {
            aim[axis] = if axis == free_axis {
                numbers.between(bounds.min[axis], bounds.max[axis])
            } else if numbers.below(2) == 0 {
                bounds.min[axis]
            } else {
                bounds.max[axis]
            };
        }
        let origin = Vec3::new(
            numbers.between(-10.0, 10.0),
            numbers.between(-10.0, 10.0),
            numbers.between(-10.0, 10.0),
        );
        (origin, aim - origin)
    })
}

/// `hit_box` on the rays of [`edge_rays`] (`hit_boxes` when
/// `four_at_once`, the box in lane `i % 4` for ray `i`, the other lanes
/// empty): whether the chapters say each ray enters the box. Which of
/// them should is the judge's to work out.
pub(super) fn box_edges<C: Chapters>(
    bounds: &Aabb,
    rays: u32,
    seed: u64,
    four_at_once: bool,
) -> Vec<bool> {
    edge_rays(bounds, rays, seed)
        .enumerate()
        .map(|(index, (origin, dir))| {
            if four_at_once {
                let lane = index % crate::bvh::WIDTH;
                let mut boxes = crate::bvh::Boxes4::EMPTY;
                boxes.set(lane, *bounds);
                !C::hit_boxes(&boxes, origin, dir.recip(), 0.0, f32::INFINITY)[lane].is_nan()
            } else {
                C::hit_box(bounds, origin, dir.recip(), 0.0, f32::INFINITY).is_some()
            }
        })
        .collect()
}

/// What is wrong with `bvh` as a tree over objects with boxes `bounds`, if
/// anything. Walks from the root with a visited mark per node, so a
/// student's tree with a cycle or an index out of range is reported, not
/// followed forever.
/// The objects in the leaves under `node`, sorted (`bvh` a valid tree).
pub(super) fn objects_under(bvh: &Bvh, node: usize) -> Vec<u32> {
    let mut found = Vec::new();
    let mut to_visit = vec![node];
    while let Some(index) = to_visit.pop() {
        let node = &bvh.nodes[index];
        match node.children() {
            Some((left, right)) => to_visit.extend([left, right]),
            None => found.extend_from_slice(&bvh.primitives[node.primitive_range()]),
        }
    }
    found.sort_unstable();
    found
}

/// The cuts `sides` in words ("[0, 1] and [2], or ..."), and whether the
/// root of `bvh` (`root`: its children, if it has any) is one of them,
/// compared as partitions of the boxed objects `all`.
pub(super) fn cut_matches(
    bvh: &Bvh,
    root: Option<Option<(usize, usize)>>,
    all: &[u32],
    sides: &[Vec<u32>],
) -> (String, bool) {
    let sides: Vec<Vec<u32>> = sides
        .iter()
        .map(|side| {
            let mut side = side.clone();
            side.sort_unstable();
            side
        })
        .collect();
    let matches = root.flatten().is_some_and(|(left, right)| {
        let (left, right) = (objects_under(bvh, left), objects_under(bvh, right));
        sides.iter().any(|side| left == *side || right == *side)
    });
    let cuts: Vec<String> = sides
        .iter()
        .map(|side| {
            let rest: Vec<u32> = all.iter().copied().filter(|o| !side.contains(o)).collect();
            format!("{side:?} and {rest:?}")
        })
        .collect();
    (cuts.join(", or "), matches)
}

/// How a valid tree `bvh` differs from `expect`: (expected, got).
pub(super) fn shape_problem(
    bvh: &Bvh,
    bounds: &[Option<Aabb>],
    expect: &TreeShape,
) -> Option<(String, String)> {
    let finite = |b: &Aabb| b.min.is_finite() && b.max.is_finite() && !b.is_empty();
    let boxed: Vec<Aabb> = bounds.iter().flatten().copied().filter(finite).collect();
    let all: Vec<u32> = (0..bounds.len() as u32)
        .filter(|&o| bounds[o as usize].as_ref().is_some_and(finite))
        .collect();
    let root = bvh.nodes.first().map(|root| root.children());
    let got = match root {
        None => "no nodes".to_string(),
        Some(None) => format!(
            "the root a leaf holding objects {:?}",
            objects_under(bvh, 0)
        ),
        Some(Some((left, right))) => format!(
            "the root cut into objects {:?} and {:?}",
            objects_under(bvh, left),
            objects_under(bvh, right)
        ),
    };
    let (expected, matches) = match expect {
        TreeShape::Any => return None,
        TreeShape::RootLeaf => (
            format!("the root a leaf holding objects {all:?}"),
            root == Some(None),
        ),
        TreeShape::RootCut(sides) => {
            let (cuts, matches) = cut_matches(bvh, root, &all, sides);
            (format!("the root cut into objects {cuts}"), matches)
        }
        TreeShape::RootLeafOrCut(sides) => {
            let (cuts, matches) = cut_matches(bvh, root, &all, sides);
            (
                format!("the root a leaf holding objects {all:?}, or cut into objects {cuts}"),
                matches || root == Some(None),
            )
        }
    };
    if !matches {
        return Some((expected, got));
    }
    // The root's box: the objects' boxes, grown by BOX_PADDING_EPSILONS (4)
    // epsilons of their largest coordinate; allowed up to 1e-4 of it.
    let union = boxed.iter().fold(Aabb::EMPTY, |sum, b| sum.union(*b));
    let root_box = bvh.nodes[0].bounds;
    let magnitude = union.min.abs().max(union.max.abs()).max_element();
    let off = (root_box.min - union.min)
        .abs()
        .max((root_box.max - union.max).abs())
        .max_element();
    (!(off <= 1e-4 * magnitude)).then(|| {
        (
            format!(
                "the root's box {} to {} (the objects' boxes), grown by a few epsilons of its \
                 largest coordinate",
                vec(union.min),
                vec(union.max)
            ),
            format!(
                "the root's box {} to {}",
                vec(root_box.min),
                vec(root_box.max)
            ),
        )
    })
}

/// What is wrong with `bvh` as a tree over `bounds`, if anything: where
/// each object is (see [`placement_problem`]), then the nodes themselves.
pub(super) fn tree_problem(bvh: &Bvh, bounds: &[Option<Aabb>]) -> Option<String> {
    if let Some(problem) = placement_problem(bvh, bounds) {
        return Some(problem);
    }
    if bvh.nodes.is_empty() {
        return (!bvh.primitives.is_empty()).then(|| {
            format!(
                "no nodes, but {} objects in primitives",
                bvh.primitives.len()
            )
        });
    }
    nodes_problem(bvh, bounds)
}

/// Object `object`'s box, when it is one a tree can hold: finite and not
/// empty.
fn finite_box(bounds: &[Option<Aabb>], object: usize) -> Option<Aabb> {
    bounds[object].filter(|b| b.min.is_finite() && b.max.is_finite() && !b.is_empty())
}

/// Each object once, in `primitives` or `unbounded`; those with a finite
/// box in the tree, the others out of it.
fn placement_problem(bvh: &Bvh, bounds: &[Option<Aabb>]) -> Option<String> {
    let boxed = |object: usize| finite_box(bounds, object);
    let mut places = vec![0usize; bounds.len()];
    for &object in bvh.primitives.iter().chain(&bvh.unbounded) {
        let Some(count) = places.get_mut(object as usize) else {
            return Some(format!(
                "object {object} in the tree, but there are {} objects",
                bounds.len()
            ));
        };
        *count += 1;
    }
    if let Some(object) = places.iter().position(|&count| count != 1) {
        return Some(format!(
            "object {object} appears {} times (in primitives and unbounded together)",
            places[object]
        ));
    }
    if let Some(&object) = bvh.unbounded.iter().find(|&&o| boxed(o as usize).is_some()) {
        return Some(format!(
            "object {object} has a finite box but is in unbounded, outside the tree"
        ));
    }
    if let Some(&object) = bvh
        .primitives
        .iter()
        .find(|&&o| boxed(o as usize).is_none())
    {
        return Some(format!(
            "object {object} has no box (a plane) but is in the tree"
        ));
    }
    None
}

/// How many `f32::EPSILON`s of its largest coordinate a leaf's box must
/// at least grow each object's box by: half of the lesson's 4, so that
/// any way of writing the lesson's padding passes, rounding included, and
/// a box not grown at all does not.
const PADDING_JUDGED: f32 = 2.0;

/// `bounds` grown by `epsilons` of its largest coordinate.
fn grown(bounds: Aabb, epsilons: f32) -> Aabb {
    let magnitude = bounds.min.abs().max(bounds.max.abs()).max_element();
    let pad = Vec3::splat(epsilons * f32::EPSILON * magnitude);
    Aabb::new(bounds.min - pad, bounds.max + pad)
}

/// From the root, every node reached once, each box holding its children's
/// or its objects', and every slot of `primitives` under exactly one leaf.
fn nodes_problem(bvh: &Bvh, bounds: &[Option<Aabb>]) -> Option<String> {
    let boxed = |object: usize| finite_box(bounds, object);
    let holds = |outer: &Aabb, inner: &Aabb| {
        outer.min.cmple(inner.min).all() && inner.max.cmple(outer.max).all()
    };
    let mut visited = vec![false; bvh.nodes.len()];
    let mut covered = vec![0usize; bvh.primitives.len()];
    let mut to_visit = vec![0usize];
    while let Some(index) = to_visit.pop() {
        if std::mem::replace(&mut visited[index], true) {
            return Some(format!("node {index} is reached twice: not a tree"));
        }
        let node = &bvh.nodes[index];
        if let Some((left, right)) = node.children() {
            if right >= bvh.nodes.len() {
                return Some(format!(
                    "node {index} has children {left} and {right}, but there are {} nodes",
                    bvh.nodes.len()
                ));
            }
            for child in [left, right] {
                if !holds(&node.bounds, &bvh.nodes[child].bounds) {
                    return Some(format!(
                        "node {index}'s box {} to {} does not hold its child {child}'s, {} to {}",
                        vec(node.bounds.min),
                        vec(node.bounds.max),
                        vec(bvh.nodes[child].bounds.min),
                        vec(bvh.nodes[child].bounds.max)
                    ));
                }
                to_visit.push(child);
            }
            continue;
        }
        let range = node.primitive_range();
        if range.end > bvh.primitives.len() {
            return Some(format!(
                "leaf {index} holds primitives {range:?}, but there are {}",
                bvh.primitives.len()
            ));
        }
        for slot in range {
            covered[slot] += 1;
            let object = bvh.primitives[slot] as usize;
            let Some(object_box) = boxed(object) else {
                continue;
            };
            if !holds(&node.bounds, &object_box) {
                return Some(format!(
                    "leaf {index}'s box {} to {} does not hold object {object}'s, {} to {}",
                    vec(node.bounds.min),
                    vec(node.bounds.max),
                    vec(object_box.min),
                    vec(object_box.max)
                ));
            }
            let padded = grown(object_box, PADDING_JUDGED);
            if !holds(&node.bounds, &padded) {
                return Some(format!(
                    "leaf {index}'s box {} to {} does not hold object {object}'s box grown by 4 \
                     epsilons of its largest coordinate, {} to {} (so that a hit the object \
                     reports lies inside its box)",
                    vec(node.bounds.min),
                    vec(node.bounds.max),
                    vec(padded.min),
                    vec(padded.max)
                ));
            }
        }
    }
    if let Some(slot) = covered.iter().position(|&count| count != 1) {
        return Some(format!(
            "primitives[{slot}] (object {}) is under {} leaves reached from the root",
            bvh.primitives[slot], covered[slot]
        ));
    }
    None
}

/// Runs each ray through a tree over `shapes` (`walk`: the chapters `C`'s
/// walk) and beside it every object's own test by the chapters `C` (from
/// which the judge takes chapter 3's nearest, so that only the tree is
/// judged, bit for bit), with the claimed object's own test; when
/// `record`, with every object test the walk made, in order.
pub(super) fn bvh_hits<C: Chapters>(
    shapes: &[Shape],
    rays: &[Ray],
    t_min: f32,
    t_max: f32,
    record: bool,
    walk: impl Fn(&Objects<C>, &Ray) -> Option<Hit>,
) -> Vec<Walked> {
    let objects = Objects::<C>::new(shapes);
    rays.iter()
        .map(|ray| {
            let hits = (0..objects.len())
                .filter_map(|object| {
                    objects
                        .intersect(object, ray, t_min, t_max)
                        .map(|t| (object, t))
                })
                .collect();
            let log = std::sync::Mutex::new(Vec::new());
            let walk = if record {
                walk(&Objects::recording(shapes, &log), ray)
            } else {
                walk(&objects, ray)
            };
            let own_test = walk
                .filter(|hit| hit.object < objects.len())
                .and_then(|hit| objects.intersect(hit.object, ray, t_min, t_max));
            Walked {
                walk: walk.map(|hit| (hit.object, hit.t)),
                hits,
                own_test,
                asked: log
                    .into_inner()
                    .unwrap_or_else(std::sync::PoisonError::into_inner),
            }
        })
        .collect()
}

/// Where a walk broke one of the steps the lesson gives it, seen from
/// outside through the objects it asked (`walked`, ray by ray) and the
/// trees it walked: (expected, got).
///
/// The steps: the objects outside the tree (planes) are asked first; an
/// object in the tree is asked only if the ray enters its leaf's box
/// within `[t_min, limit]`, the limit being the best hit so far for the
/// nearest hit (a box entered beyond it is skipped, with everything in
/// it) and `t_max` for any hit; the nearest hit asks each object up to and
/// including the best hit so far; any hit asks nothing after its first
/// hit. Only what goes through the objects can be seen: a wide leaf's
/// triangles answer inside `intersect_triangles`, so a hit among them
/// leaves the best seen here larger than the walk's, which only makes
/// these rules more lenient.
pub(super) fn steps_problem(
    shapes: &[Shape],
    walk: &WalkCall,
    trees: &WalkedTrees,
    walked: &[Walked],
) -> Option<(String, String)> {
    let bounds: Vec<Option<Aabb>> = shapes.iter().map(Shape::bounds).collect();
    if let Some(problem) = tree_problem(&trees.bvh, &bounds) {
        return Some(("a valid tree to walk".into(), problem));
    }
    let (unbounded, leaf_boxes) = match &trees.wide {
        None => (
            trees.bvh.unbounded.clone(),
            binary_leaf_boxes(&trees.bvh, shapes.len()),
        ),
        Some(wide) => {
            if let Some(problem) = super::wide::wide_problem(wide, &trees.bvh, shapes) {
                return Some(("a valid wide tree to walk".into(), problem));
            }
            (wide.unbounded.clone(), wide_leaf_boxes(wide, shapes.len()))
        }
    };
    for (index, (ray, walked)) in walk.rays.iter().zip(walked).enumerate() {
        if let Some((expected, got)) =
            ray_steps_problem(walk, ray, &unbounded, &leaf_boxes, &walked.asked)
        {
            let which = if walk.rays.len() == 1 {
                String::new()
            } else {
                format!(" (ray {} of {})", index + 1, walk.rays.len())
            };
            return Some((expected, format!("{got}{which}")));
        }
    }
    None
}

/// The box of the leaf holding each object, in a valid binary tree.
fn binary_leaf_boxes(bvh: &Bvh, objects: usize) -> Vec<Option<Aabb>> {
    let mut boxes = vec![None; objects];
    let mut to_visit = if bvh.nodes.is_empty() {
        vec![]
    } else {
        vec![0]
    };
    while let Some(index) = to_visit.pop() {
        let node = &bvh.nodes[index];
        match node.children() {
            Some((left, right)) => to_visit.extend([left, right]),
            None => {
                for &object in &bvh.primitives[node.primitive_range()] {
                    boxes[object as usize] = Some(node.bounds);
                }
            }
        }
    }
    boxes
}

/// The box of the lane holding each object's leaf, in a valid wide tree.
fn wide_leaf_boxes(wide: &crate::bvh::WideBvh, objects: usize) -> Vec<Option<Aabb>> {
    let mut boxes = vec![None; objects];
    let mut to_visit = if wide.nodes.is_empty() {
        vec![]
    } else {
        vec![0]
    };
    while let Some(index) = to_visit.pop() {
        let node = &wide.nodes[index];
        for lane in (0..crate::bvh::WIDTH).filter(|&lane| node.used_lanes().test(lane)) {
            let (first, count) = (node.first[lane] as usize, node.count[lane] as usize);
            if count == 0 {
                to_visit.push(first);
                continue;
            }
            for leaf in &wide.leaves[first..first + count] {
                for &object in leaf.objects.iter().filter(|&&object| object != u32::MAX) {
                    boxes[object as usize] = Some(node.boxes.get(lane));
                }
            }
        }
    }
    boxes
}

/// [`steps_problem`] for one ray, whose walk asked `asked`.
fn ray_steps_problem(
    walk: &WalkCall,
    ray: &Ray,
    unbounded: &[u32],
    leaf_boxes: &[Option<Aabb>],
    asked: &[crate::course::Asked],
) -> Option<(String, String)> {
    let inverse = ray.dir.recip();
    let enters = |bounds: &Aabb, limit: f32| {
        crate::answer_key::raylab_own(|| {
            Reference::hit_box(bounds, ray.origin, inverse, walk.t_min, limit)
        })
    };
    let show =
        |t: Option<f32>| t.map_or_else(|| "never".to_string(), |t| format!("at t = {}", num(t)));
    let mut best: Option<f32> = None;
    for (step, test) in asked.iter().enumerate() {
        let object = test.object;
        if walk.any
            && let Some(hit) = best
        {
            return Some((
                "nothing asked after the first hit: any hit will do".into(),
                format!(
                    "object {object} asked after a hit at t = {} (test {} of the walk)",
                    num(hit),
                    step + 1
                ),
            ));
        }
        let in_tree = !unbounded.contains(&(object as u32));
        if in_tree
            && let Some(&plane) = unbounded
                .iter()
                .find(|&&plane| !asked[..step].iter().any(|t| t.object == plane as usize))
        {
            return Some((
                "the objects outside the tree (planes) asked first".into(),
                format!(
                    "object {object}, in the tree, asked before object {plane}, outside it \
                     (test {} of the walk)",
                    step + 1
                ),
            ));
        }
        let limit = if walk.any {
            walk.t_max
        } else {
            best.unwrap_or(walk.t_max)
        };
        if in_tree {
            let leaf = leaf_boxes.get(object).copied().flatten();
            // A student's slab test may widen a little more than raylab's.
            let allowed = limit + 1e-4 * limit.abs().max(1.0);
            if leaf.and_then(|bounds| enters(&bounds, allowed)).is_none() {
                let entry = leaf.and_then(|bounds| enters(&bounds, f32::INFINITY));
                return Some((
                    format!(
                        "only objects whose leaf's box the ray enters by t = {} asked ({})",
                        num(limit),
                        if walk.any {
                            "t_max"
                        } else {
                            "the best hit so far: a box entered beyond it is skipped"
                        }
                    ),
                    format!(
                        "object {object} asked (test {} of the walk), whose leaf's box the ray \
                         enters {}",
                        step + 1,
                        show(entry)
                    ),
                ));
            }
        }
        if !walk.any
            && let Some(hit) = best
            && !(test.t_max <= hit.next_up())
        {
            return Some((
                format!(
                    "object {object} asked for hits up to and including the best so far, t = {}",
                    num(hit)
                ),
                format!(
                    "object {object} asked for hits up to t = {} (test {} of the walk)",
                    num(test.t_max),
                    step + 1
                ),
            ));
        }
        if let Some(t) = test.answer {
            best = Some(best.map_or(t, |hit| hit.min(t)));
        }
    }
    None
}

/// Judges the walks of `rays`: a nearest-hit walk must find chapter 3's
/// loop's hit, the same object at the same `t`; an any-hit walk, a hit
/// exactly when the loop finds one, and a real one (the object's own test
/// gives that `t`).
pub(super) fn judge_walks(rays: &[Ray], any: bool, walked: &[Walked]) -> Outcome {
    if walked.len() != rays.len() {
        return super::intersections::wrong_length(rays.len(), walked.len());
    }
    let show = |hit: Option<(usize, f32)>| match hit {
        Some((object, t)) => format!("object {object} at t = {}", num(t)),
        None => "no hit".into(),
    };
    let which = |index: usize, ray: &Ray| {
        if rays.len() == 1 {
            String::new()
        } else {
            format!(" (ray {} of {}: {})", index + 1, rays.len(), ray_text(ray))
        }
    };
    let same = |a: Option<(usize, f32)>, b: Option<(usize, f32)>| match (a, b) {
        (None, None) => true,
        (Some((x, s)), Some((y, t))) => x == y && s == t,
        _ => false,
    };
    for (index, (ray, walked)) in rays.iter().zip(walked).enumerate() {
        let by_loop = walked.by_loop();
        let Walked {
            walk: got,
            own_test,
            ..
        } = *walked;
        if !any {
            if !same(got, by_loop) {
                return Outcome::Fail {
                    expected: format!("{} (chapter 3's loop)", show(by_loop)),
                    got: format!("{}{}", show(got), which(index, ray)),
                };
            }
            continue;
        }
        let real = got.is_some_and(|(_, t)| own_test == Some(t));
        if got.is_some() != by_loop.is_some() || (got.is_some() && !real) {
            return Outcome::Fail {
                expected: match by_loop {
                    Some(hit) => {
                        format!("a hit of an object there (chapter 3: {})", show(Some(hit)))
                    }
                    None => "no hit (chapter 3 finds none)".into(),
                },
                got: format!(
                    "{}{}{}",
                    show(got),
                    if got.is_some() && !real {
                        ", which is not where that object's own test hits"
                    } else {
                        ""
                    },
                    which(index, ray)
                ),
            };
        }
    }
    Outcome::Pass
}
