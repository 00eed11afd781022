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
/// empty): the first ray the exact slab test says meets the box and the
/// chapters refuse.
pub(super) fn box_edges<C: Chapters>(
    bounds: &Aabb,
    rays: u32,
    seed: u64,
    four_at_once: bool,
) -> Option<RefusedRay> {
    for (index, (origin, dir)) in edge_rays(bounds, rays, seed).enumerate() {
        let (entry, exit) = exact::slab_interval(bounds, origin, dir);
        // The exact ray meets the box for some t >= 0 (a NaN from a zero
        // direction component is not counted: no such ray is drawn).
        if !(exit >= entry.max(0.0)) {
            continue;
        }
        let enters = if four_at_once {
            let lane = index % crate::bvh::WIDTH;
            let mut boxes = crate::bvh::Boxes4::EMPTY;
            boxes.set(lane, *bounds);
            !C::hit_boxes(&boxes, origin, dir.recip(), 0.0, f32::INFINITY)[lane].is_nan()
        } else {
            C::hit_box(bounds, origin, dir.recip(), 0.0, f32::INFINITY).is_some()
        };
        if !enters {
            return Some(RefusedRay {
                index: index as u32,
                origin,
                dir,
            });
        }
    }
    None
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
            if let Some(object_box) = boxed(object)
                && !holds(&node.bounds, &object_box)
            {
                return Some(format!(
                    "leaf {index}'s box {} to {} does not hold object {object}'s, {} to {}",
                    vec(node.bounds.min),
                    vec(node.bounds.max),
                    vec(object_box.min),
                    vec(object_box.max)
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
/// walk) and beside it chapter 3's loop over the same objects (the
/// chapters `C`'s own object tests, so that only the tree is judged, bit
/// for bit), with the claimed object's own test.
pub(super) fn bvh_hits<C: Chapters>(
    shapes: &[Shape],
    rays: &[Ray],
    t_min: f32,
    t_max: f32,
    walk: impl Fn(&Objects<C>, &Ray) -> Option<Hit>,
) -> Vec<Walked> {
    let objects = Objects::<C>::new(shapes);
    rays.iter()
        .map(|ray| {
            let by_loop =
                crate::answer_key::raylab_own(|| objects.nearest_hit_by_loop(ray, t_min, t_max));
            let walk = walk(&objects, ray);
            let own_test = walk
                .filter(|hit| hit.object < objects.len())
                .and_then(|hit| objects.intersect(hit.object, ray, t_min, t_max));
            Walked {
                walk: walk.map(|hit| (hit.object, hit.t)),
                by_loop: by_loop.map(|hit| (hit.object, hit.t)),
                own_test,
            }
        })
        .collect()
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
        let Walked {
            walk: got,
            by_loop,
            own_test,
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
