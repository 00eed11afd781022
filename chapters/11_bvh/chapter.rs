use raylab::bvh::{
    Aabb, Boxes4, Bvh, BvhNode, BvhOptions, Leaf4, SplitRule, Triangles4, WIDTH, WideBvh, WideNode,
    greater_of, lesser_of, prefetch, vec_on_huge_pages,
};
use raylab::course::{Chapters, Hit, Objects};
use raylab::shapes::Shape;
use raylab::{Ray, Vec3, Vec4};

/// `γ3 = 3u / (1 - 3u)`, `u = 2^-24`: the relative error bound of a value
/// that went through three roundings. A slab distance `(plane - origin) *
/// inverse` is exactly that: a subtraction, the reciprocal of the direction
/// and a product.
pub const GAMMA_3: f32 = 3.0 * (f32::EPSILON / 2.0) / (1.0 - 3.0 * (f32::EPSILON / 2.0));

/// The distance at which `ray` enters `bounds`, if it meets the box at
/// some `t` with `t_min <= t <= t_max`; `t_min` when it starts inside.
///
/// `inverse_direction` is `ray.dir.recip()`, computed once per ray: each
/// axis' two planes are met at `(plane - origin) * inverse`, the box is the
/// intersection of the three slabs, so the ray is inside from the largest
/// entry to the smallest exit.
///
/// A direction component of 0 has an infinite inverse (of the zero's sign),
/// so that axis' distances are `±inf`: the whole line is inside that slab
/// (`-inf` to `+inf`) or outside it (both infinities of one sign, empty).
/// Only an origin exactly on one of the planes gives `0 * inf = NaN`, and
/// then the line lies in the plane, on the box's closed boundary: that axis
/// must not constrain anything. Two choices make it so. Which plane is the
/// entry is read off the sign *bit* of the inverse (`-0.0` gives `-inf`,
/// whose sign bit is set), never by comparing the two distances, which
/// would pick the NaN's partner, an infinity of either sign. And the
/// entries and exits are combined by comparisons (`if near > entry`) that
/// a NaN fails, as `f32::max` and `f32::min` would: a NaN distance leaves
/// the running entry and exit as they were.
///
/// The distances carry up to `γ3` of relative error, so the entry is moved
/// down and the exit up by `2 γ3` of themselves (pbrt's widening of
/// `t_far`, made symmetric). Without it a ray along a box's edge or
/// through its corner, where entry and exit are equal, can come out with
/// entry a hair beyond exit and miss; and an object touching its box (a
/// sphere touches each face at one point) can be hit at exactly the entry
/// distance, which rounded up would make the traversal skip the box as
/// farther than a hit it already has. Infinite distances are exact and
/// stay as they are (`inf - inf` would be NaN).
#[inline(always)]
pub fn hit_box(
    bounds: &Aabb,
    origin: Vec3,
    inverse_direction: Vec3,
    t_min: f32,
    t_max: f32,
) -> Option<f32> {
    // Plain arrays: indexing a `Vec3` by a run-time axis is a three-way
    // branch per access, in the hottest loop of the renderer.
    let (origin, inverse) = (origin.to_array(), inverse_direction.to_array());
    let (low, high) = (bounds.min.to_array(), bounds.max.to_array());
    let mut entry = f32::NEG_INFINITY;
    let mut exit = f32::INFINITY;
    for axis in 0..3 {
        let (near_plane, far_plane) = if inverse[axis].is_sign_negative() {
            (high[axis], low[axis])
        } else {
            (low[axis], high[axis])
        };
        let near = (near_plane - origin[axis]) * inverse[axis];
        let far = (far_plane - origin[axis]) * inverse[axis];
        // `entry.max(near)`, written as a comparison: a NaN compares false,
        // so it leaves `entry` as it was, exactly as `f32::max` would, and
        // the comparison is one instruction where `f32::max`, which must
        // also sort out which operand is the NaN, takes several.
        entry = if near > entry { near } else { entry };
        exit = if far < exit { far } else { exit };
    }
    // `2 γ3 |t|`, capped at `f32::MAX` so that an infinite distance moves
    // by a finite amount and stays infinite (`inf - inf` would be NaN).
    let slack = |t: f32| {
        let slack = 2.0 * GAMMA_3 * t.abs();
        if slack < f32::MAX { slack } else { f32::MAX }
    };
    let (entry, exit) = (entry - slack(entry), exit + slack(exit));
    // A NaN `t_min` or `t_max` is ignored, as `f32::max` would.
    let entry = if t_min > entry { t_min } else { entry };
    let exit = if t_max < exit { t_max } else { exit };
    (entry <= exit).then_some(entry)
}

/// The estimated cost of visiting an inner node (testing its two child
/// boxes), in units of the cost of testing one object. A box test is a few
/// subtractions, products and comparisons, about the price of the first
/// half of a sphere test; we estimate two of them, plus the stack, at about
/// one whole object test. Only the ratio matters, and
/// `raylab cost --chapter 11` measures what the choice buys.
pub const TRAVERSAL_COST: f64 = 1.0;

/// How many `f32::EPSILON`s of its largest coordinate each object's box is
/// grown by before it goes into the tree. A box computed from a shape
/// (`center ± radius`) is rounded, and so is the shape's own hit point: a
/// sphere test may report a hit a few roundings outside the exact sphere,
/// where the exact box would refuse the ray. The same allowance as the
/// error of a surface point ([`raylab::shapes::SURFACE_ERROR_EPSILONS`]).
///
/// It covers errors that scale with the shape's coordinates. Part of a
/// sphere test's error scales with the ray's distance to the sphere
/// instead, so a ray from far away grazing a sphere exactly where it
/// touches its box could in principle be reported by chapter 3 and refused
/// by the padded box; the random comparisons in `tests/course/bvh.rs` have not
/// met one.
pub const BOX_PADDING_EPSILONS: f32 = 4.0;

/// The most bins the SAH build sorts centroids into: the bins are allocated
/// per node, and a cap keeps a careless `bins = 4e9` from asking for
/// gigabytes.
pub const MAX_BINS: u32 = 1024;

/// Builds a BVH over the objects whose boxes are `bounds` (object `i` has
/// box `bounds[i]`, `None` when no box holds it).
///
/// Objects go into `Bvh::unbounded`, outside the tree, when they have no
/// box (planes), or when their box is not finite or is empty (NaN, or `min`
/// above `max`). Refusing them would drop objects from the picture; in the
/// loop, each is asked by its own test exactly as chapter 3 asks it, so the
/// answer cannot change, and a NaN or infinite box never reaches the
/// surface-area arithmetic, where `inf - inf` would poison every cost.
///
/// Each node's objects are cut in two by the position of their boxes'
/// centroids along the axis where the centroids spread the most. The cut is
/// chosen by `options.split`: the surface-area heuristic over
/// `options.bins` bins, or the middle. A node becomes a leaf when it holds
/// `options.max_leaf` objects or fewer, when no cut is possible (every
/// centroid in the same place, as for a thousand copies of one sphere), or,
/// with SAH, when no cut is estimated cheaper than the leaf.
///
/// Single-threaded and iterative (a stack of nodes to build, not
/// recursion): the same input gives the same tree, and a degenerate input
/// whose tree is as deep as it has objects cannot overflow the call stack.
///
/// # Panics
///
/// With more than `2^31` objects, which the tree's `u32` indices cannot
/// number (nor would that many fit in memory).
pub fn build_bvh(bounds: &[Option<Aabb>], options: &BvhOptions) -> Bvh {
    assert!(
        bounds.len() <= 1 << 31,
        "a BVH numbers at most 2^31 objects"
    );
    let mut bvh = Bvh::default();
    // Indexed by object: its padded box and centroid (unused for the
    // unbounded ones).
    let mut boxes = Vec::with_capacity(bounds.len());
    let mut centroids = Vec::with_capacity(bounds.len());
    for (object, bound) in bounds.iter().enumerate() {
        let padded = bound.map(padded).filter(is_finite_box);
        if padded.is_some() {
            bvh.primitives.push(object as u32);
        } else {
            bvh.unbounded.push(object as u32);
        }
        let padded = padded.unwrap_or(Aabb::EMPTY);
        boxes.push(padded);
        // Half of each, then the sum: `min + max` could overflow.
        centroids.push(0.5 * padded.min + 0.5 * padded.max);
    }
    if bvh.primitives.is_empty() {
        return bvh;
    }

    let placeholder = BvhNode {
        bounds: Aabb::EMPTY,
        first: 0,
        count: 0,
    };
    bvh.nodes.push(placeholder);
    // Nodes still to build: (node index, range of `bvh.primitives`).
    let mut to_build = vec![(0usize, 0..bvh.primitives.len())];
    while let Some((node, range)) = to_build.pop() {
        let objects = &mut bvh.primitives[range.clone()];
        let node_box = objects.iter().fold(Aabb::EMPTY, |sum, &object| {
            sum.union(boxes[object as usize])
        });
        let cut = if objects.len() <= options.max_leaf.max(1) as usize {
            None
        } else {
            choose_cut(objects, &boxes, &centroids, &node_box, options)
        };
        let Some(cut) = cut else {
            bvh.nodes[node] = BvhNode {
                bounds: node_box,
                first: range.start as u32,
                count: objects.len() as u32,
            };
            continue;
        };
        let left_count = partition(objects, |object| cut.goes_left(centroids[object as usize]));
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

/// `bounds` grown by [`BOX_PADDING_EPSILONS`] of its largest coordinate.
fn padded(bounds: Aabb) -> Aabb {
    let magnitude = bounds
        .min
        .abs()
        .max_element()
        .max(bounds.max.abs().max_element());
    let pad = Vec3::splat(BOX_PADDING_EPSILONS * f32::EPSILON * magnitude);
    Aabb::new(bounds.min - pad, bounds.max + pad)
}

/// Finite and not empty (NaN fails both tests).
fn is_finite_box(bounds: &Aabb) -> bool {
    bounds.min.is_finite() && bounds.max.is_finite() && bounds.min.cmple(bounds.max).all()
}

/// Half the surface area, in `f64`: the `f32` product of two sides of a box
/// 1e20 wide would overflow, and the SAH sums many of them.
fn half_area(bounds: &Aabb) -> f64 {
    if bounds.is_empty() {
        return 0.0;
    }
    let size = bounds.max.as_dvec3() - bounds.min.as_dvec3();
    size.x * size.y + size.y * size.z + size.z * size.x
}

/// Where centroids fall along one axis: `bins` equal bins spanning
/// `[low, low + bins / scale]`, in `f64`, where the difference of two `f32`
/// coordinates has room to be exact and `bins / extent` cannot overflow.
#[derive(Clone, Copy)]
struct Bins {
    axis: usize,
    low: f64,
    scale: f64,
    count: usize,
}

impl Bins {
    /// The bin of a centroid; the largest lands in the last bin, not past it.
    fn of(&self, centroid: Vec3) -> usize {
        let offset = (f64::from(centroid[self.axis]) - self.low) * self.scale;
        (offset as usize).min(self.count - 1)
    }
}

/// How a node's objects are cut in two.
#[derive(Clone, Copy)]
enum Cut {
    /// Centroids below `position` along `axis` go left.
    Below { axis: usize, position: f64 },
    /// Centroids in the bins before `boundary` go left.
    BinsBefore { bins: Bins, boundary: usize },
}

impl Cut {
    fn goes_left(&self, centroid: Vec3) -> bool {
        match *self {
            Cut::Below { axis, position } => f64::from(centroid[axis]) < position,
            Cut::BinsBefore { bins, boundary } => bins.of(centroid) < boundary,
        }
    }
}

/// The cut for a node holding `objects`, or `None` when it should stay a
/// leaf. Either side of a returned cut holds at least one object.
fn choose_cut(
    objects: &[u32],
    boxes: &[Aabb],
    centroids: &[Vec3],
    node_box: &Aabb,
    options: &BvhOptions,
) -> Option<Cut> {
    let spread = objects.iter().fold(Aabb::EMPTY, |sum, &object| {
        sum.grow(centroids[object as usize])
    });
    let extent = spread.max.as_dvec3() - spread.min.as_dvec3();
    // The first widest axis, so that ties are decided the same way each time.
    let axis = (0..3).fold(0, |widest, axis| {
        if extent[axis] > extent[widest] {
            axis
        } else {
            widest
        }
    });
    // Every centroid in one place: no plane can separate them.
    if !(extent[axis] > 0.0) {
        return None;
    }
    let low = f64::from(spread.min[axis]);
    if options.split == SplitRule::Midpoint {
        // In f64 the middle of two distinct f32 values lies strictly between
        // them, so the lowest centroid goes left and the highest right.
        return Some(Cut::Below {
            axis,
            position: low + 0.5 * extent[axis],
        });
    }

    let count = options.bins.clamp(2, MAX_BINS) as usize;
    let bins = Bins {
        axis,
        low,
        scale: count as f64 / extent[axis],
        count,
    };
    let mut bin_count = vec![0usize; count];
    let mut bin_box = vec![Aabb::EMPTY; count];
    for &object in objects {
        let bin = bins.of(centroids[object as usize]);
        bin_count[bin] += 1;
        bin_box[bin] = bin_box[bin].union(boxes[object as usize]);
    }
    // The SAH: a ray that meets the node meets a child with probability
    // (child's area) / (node's area), and then tests its objects. Costs are
    // multiplied through by the node's area so that a node of no area (a
    // point: a box flat along one axis still has positive area) needs no
    // division.
    //
    // right_cost[b] = area(bins b..) * objects(b..), swept from the right.
    let mut right_cost = vec![0.0f64; count];
    let (mut right_box, mut right_count) = (Aabb::EMPTY, 0usize);
    for bin in (1..count).rev() {
        right_box = right_box.union(bin_box[bin]);
        right_count += bin_count[bin];
        right_cost[bin] = half_area(&right_box) * right_count as f64;
    }
    let node_area = half_area(node_box);
    let leaf_cost = node_area * objects.len() as f64;
    let mut best: Option<(usize, f64)> = None;
    let (mut left_box, mut left_count) = (Aabb::EMPTY, 0usize);
    for boundary in 1..count {
        left_box = left_box.union(bin_box[boundary - 1]);
        left_count += bin_count[boundary - 1];
        if left_count == 0 || left_count == objects.len() {
            continue;
        }
        let cost = TRAVERSAL_COST * node_area
            + half_area(&left_box) * left_count as f64
            + right_cost[boundary];
        // Strictly lower: of equal costs, the first boundary wins.
        if best.is_none_or(|(_, best_cost)| cost < best_cost) {
            best = Some((boundary, cost));
        }
    }
    let (boundary, cost) = best?;
    (cost < leaf_cost).then_some(Cut::BinsBefore { bins, boundary })
}

/// Reorders `objects` so that those for which `goes_left` holds come
/// first, and returns how many they are.
fn partition(objects: &mut [u32], goes_left: impl Fn(u32) -> bool) -> usize {
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

/// How many nodes the traversal keeps waiting on the stack without
/// allocating. The traversal descends into one child and leaves at most
/// its sibling waiting, so the stack never holds more entries than the tree
/// is deep, and a balanced tree over `n` objects is about
/// `log2(n / max_leaf)` deep (20 for a million objects, one per leaf). A
/// degenerate tree can be deeper; the excess goes to a `Vec`, allocated
/// only then.
pub const TRAVERSAL_STACK: usize = 64;

/// The nodes waiting to be visited, each with the distance at which the
/// ray enters its box: a fixed array, and a `Vec` when that is full.
///
/// The binary walk's entries are a node index as `u32`, as the tree itself
/// numbers them ([`BvhNode::first`]), and the entry distance: 8 bytes an
/// entry rather than 16 for a `usize`, so each ray clears 512 bytes instead
/// of a kilobyte when its walk begins, and moves half as much on each push.
/// A render's walks are short, so that weighs: `raylab race` put ours at
/// 0.50 to 0.58 of Embree's speed on a render's rays before, 0.60 to 0.68
/// after (100 k and 1 M triangles).
struct NodeStack<T> {
    fixed: [T; TRAVERSAL_STACK],
    len: usize,
    spilled: Vec<T>,
}

impl<T: Copy + Default> NodeStack<T> {
    fn new() -> NodeStack<T> {
        NodeStack {
            fixed: [T::default(); TRAVERSAL_STACK],
            len: 0,
            spilled: Vec::new(),
        }
    }

    #[inline(always)]
    fn push(&mut self, waiting: T) {
        if self.len < TRAVERSAL_STACK {
            self.fixed[self.len] = waiting;
            self.len += 1;
        } else {
            self.spilled.push(waiting);
        }
    }

    /// The last pushed: entries only spill while the array is full, so the
    /// spilled ones are always the most recent.
    #[inline(always)]
    fn pop(&mut self) -> Option<T> {
        if let Some(top) = self.spilled.pop() {
            return Some(top);
        }
        self.len = self.len.checked_sub(1)?;
        Some(self.fixed[self.len])
    }
}

/// The best hit so far, compared as chapter 3 compares them.
struct Nearest {
    hit: Option<Hit>,
    t_max: f32,
}

impl Nearest {
    /// The farthest a box may be entered and still hold a better hit.
    #[inline(always)]
    fn closest(&self) -> f32 {
        self.hit.map_or(self.t_max, |hit| hit.t)
    }

    /// Asks object `object` and keeps its hit if it beats the best so far.
    ///
    /// Chapter 3 walks the objects in list order and only takes a hit
    /// strictly nearer than the best, so of two hits at exactly the same
    /// `t` the lower index wins. The tree visits objects in another order,
    /// so it asks up to and including the best `t` (`next_up` is the next
    /// `f32` above it: `t < next_up(best)` is `t <= best`) and breaks the
    /// tie by index itself. An object's answer does not depend on the
    /// interval it is asked in, only whether it is reported, so the winner
    /// is chapter 3's: same object, same `t`.
    #[inline(always)]
    fn consider<C: Chapters>(&mut self, objects: &Objects<C>, object: u32, ray: &Ray, t_min: f32) {
        if let Some(t) = objects.intersect(object as usize, ray, t_min, self.limit()) {
            self.offer(object as usize, t);
        }
    }

    /// How far an object is asked for a hit: up to and including the best
    /// so far ([`Nearest::consider`]).
    #[inline(always)]
    fn limit(&self) -> f32 {
        self.hit.map_or(self.t_max, |hit| hit.t.next_up())
    }

    /// Keeps `object`'s hit at `t` if it beats the best so far: nearer, or
    /// as near and listed first.
    #[inline(always)]
    fn offer(&mut self, object: usize, t: f32) {
        let better = self
            .hit
            .is_none_or(|best| t < best.t || (t == best.t && object < best.object));
        if better {
            self.hit = Some(Hit { object, t });
        }
    }
}

/// The closest hit with `t_min < t < t_max` among `objects`, found through
/// `bvh` (built from the same objects' boxes): chapter 3's answer, the
/// same object at the same `t`.
///
/// The unbounded objects (planes) are asked first, by a loop; a plane's
/// hit then shortens the interval every box is tested against. The tree is
/// walked depth first with an explicit stack, nearer child first, so that
/// a near hit is found early, and every box entered beyond the best hit so
/// far is skipped, with everything under it. A box entered exactly at the
/// best hit is still opened: an object in it could tie, and win by index.
pub fn nearest_hit_bvh<C: Chapters>(
    bvh: &Bvh,
    objects: &Objects<C>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    let mut nearest = Nearest { hit: None, t_max };
    for &object in &bvh.unbounded {
        nearest.consider(objects, object, ray, t_min);
    }
    let Some(root) = bvh.nodes.first() else {
        return nearest.hit;
    };
    let inverse = ray.dir.recip();
    if C::hit_box(&root.bounds, ray.origin, inverse, t_min, nearest.closest()).is_none() {
        return nearest.hit;
    }
    let mut stack = NodeStack::new();
    let mut visiting = 0;
    loop {
        let node = &bvh.nodes[visiting];
        if let Some((left, right)) = node.children() {
            let closest = nearest.closest();
            let (left_box, right_box) = (&bvh.nodes[left].bounds, &bvh.nodes[right].bounds);
            let left_entry = C::hit_box(left_box, ray.origin, inverse, t_min, closest);
            let right_entry = C::hit_box(right_box, ray.origin, inverse, t_min, closest);
            // Go on into the nearer child at once; the farther one waits.
            match (left_entry, right_entry) {
                (Some(left_entry), Some(right_entry)) if right_entry < left_entry => {
                    stack.push((left as u32, left_entry));
                    visiting = right;
                    continue;
                }
                (Some(_), Some(right_entry)) => {
                    stack.push((right as u32, right_entry));
                    visiting = left;
                    continue;
                }
                (Some(_), None) => {
                    visiting = left;
                    continue;
                }
                (None, Some(_)) => {
                    visiting = right;
                    continue;
                }
                (None, None) => {}
            }
        } else {
            for &object in &bvh.primitives[node.primitive_range()] {
                nearest.consider(objects, object, ray, t_min);
            }
        }
        // The next waiting node, unless a hit found since it was pushed is
        // nearer than its box.
        loop {
            let Some((waiting, entry)) = stack.pop() else {
                return nearest.hit;
            };
            if entry <= nearest.closest() {
                visiting = waiting as usize;
                break;
            }
        }
    }
}

/// Some hit with `t_min < t < t_max` among `objects`, the first the walk
/// through `bvh` finds: for shadow rays, where any blocker will do.
///
/// No order helps here, so children are visited as they come and the
/// first hit ends the walk. Which object it reports may differ from
/// [`raylab::course::Objects::first_hit`]; whether there is one does not.
pub fn any_hit_bvh<C: Chapters>(
    bvh: &Bvh,
    objects: &Objects<C>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    let hit = |object: u32| {
        let object = object as usize;
        objects
            .intersect(object, ray, t_min, t_max)
            .map(|t| Hit { object, t })
    };
    if let Some(found) = bvh.unbounded.iter().find_map(|&object| hit(object)) {
        return Some(found);
    }
    let inverse = ray.dir.recip();
    let enters = |node: usize| {
        C::hit_box(&bvh.nodes[node].bounds, ray.origin, inverse, t_min, t_max).is_some()
    };
    let mut stack = NodeStack::new();
    if !bvh.nodes.is_empty() && enters(0) {
        stack.push(0u32);
    }
    while let Some(index) = stack.pop() {
        let node = &bvh.nodes[index as usize];
        let Some((left, right)) = node.children() else {
            let leaf = &bvh.primitives[node.primitive_range()];
            if let Some(found) = leaf.iter().find_map(|&object| hit(object)) {
                return Some(found);
            }
            continue;
        };
        for child in [right, left] {
            if enters(child) {
                stack.push(child as u32);
            }
        }
    }
    None
}

// ---------------------------------------------------------------------------
// A wider tree for incoherent rays.

/// [`hit_box`] on four boxes at once: where the ray enters each, `NaN`
/// where it misses it.
///
/// The same operations in the same order, each on four lanes, so each
/// lane's answer is `hit_box`'s, bit for bit. The direction's sign picks
/// the near plane of an axis for all four boxes alike; the folds keep the
/// running entry and exit where a crossing is NaN ([`greater_of`],
/// [`lesser_of`]); a miss is a NaN entry, which fails every comparison a
/// walk makes with it.
#[inline(always)]
pub fn hit_boxes(
    boxes: &Boxes4,
    origin: Vec3,
    inverse_direction: Vec3,
    t_min: f32,
    t_max: f32,
) -> Vec4 {
    let mut entry = Vec4::NEG_INFINITY;
    let mut exit = Vec4::INFINITY;
    for axis in 0..3 {
        let (near_planes, far_planes) = if inverse_direction[axis].is_sign_negative() {
            (boxes.max[axis], boxes.min[axis])
        } else {
            (boxes.min[axis], boxes.max[axis])
        };
        let origin = Vec4::splat(origin[axis]);
        let inverse = Vec4::splat(inverse_direction[axis]);
        let near = (near_planes - origin) * inverse;
        let far = (far_planes - origin) * inverse;
        entry = greater_of(near, entry);
        exit = lesser_of(far, exit);
    }
    let slack = |t: Vec4| lesser_of(2.0 * GAMMA_3 * t.abs(), Vec4::splat(f32::MAX));
    let (entry, exit) = (entry - slack(entry), exit + slack(exit));
    let entry = greater_of(Vec4::splat(t_min), entry);
    let exit = lesser_of(Vec4::splat(t_max), exit);
    Vec4::select(entry.cmple(exit), entry, Vec4::NAN)
}

/// Chapter 10's watertight test on four triangles at once: where the ray
/// meets each with `t_min < t < t_max`, `NaN` where it does not.
///
/// The ray's half of the test (the axis it moves fastest along, the shear)
/// is the same for the four; the rest is chapter 10's arithmetic in the
/// same order on four lanes, so each lane's `t` is
/// [`Chapters::intersect_triangle`]'s, bit for bit. A lane whose edge
/// functions include a zero is recomputed in `f64` on its own, as chapter
/// 10 does: rare, and the other lanes keep their values. Testing four
/// triangles costs about what one did, and no lane's miss is a branch to
/// mispredict.
#[inline(always)]
pub fn intersect_triangles(triangles: &Triangles4, ray: &Ray, t_min: f32, t_max: f32) -> Vec4 {
    let dir = ray.dir.to_array();
    let z = ray.dir.abs().max_position();
    let (mut x, mut y) = ((z + 1) % 3, (z + 2) % 3);
    if dir[z] < 0.0 {
        std::mem::swap(&mut x, &mut y);
    }
    let shear_x = dir[x] / dir[z];
    let shear_y = dir[y] / dir[z];
    let scale_z = 1.0 / dir[z];

    let origin = ray.origin.to_array();
    // Written out rather than with `array::map`, which the compiler left
    // as a call that copies the corners through memory (a sixth of a
    // path-traced render's time, by perf).
    let relative = |corner: &[Vec4; 3]| {
        [
            corner[0] - Vec4::splat(origin[0]),
            corner[1] - Vec4::splat(origin[1]),
            corner[2] - Vec4::splat(origin[2]),
        ]
    };
    let [a, b, c] = [
        relative(&triangles.corners[0]),
        relative(&triangles.corners[1]),
        relative(&triangles.corners[2]),
    ];
    let sheared = |p: [Vec4; 3]| (p[x] - shear_x * p[z], p[y] - shear_y * p[z]);
    let (ax, ay) = sheared(a);
    let (bx, by) = sheared(b);
    let (cx, cy) = sheared(c);

    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    let zero = u.cmpeq(Vec4::ZERO) | v.cmpeq(Vec4::ZERO) | w.cmpeq(Vec4::ZERO);
    if zero.any() {
        let cross = |px: f32, py: f32, qx: f32, qy: f32| {
            (f64::from(px) * f64::from(qy) - f64::from(py) * f64::from(qx)) as f32
        };
        for lane in (0..WIDTH).filter(|&lane| zero.test(lane)) {
            u[lane] = cross(cx[lane], cy[lane], bx[lane], by[lane]);
            v[lane] = cross(ax[lane], ay[lane], cx[lane], cy[lane]);
            w[lane] = cross(bx[lane], by[lane], ax[lane], ay[lane]);
        }
    }
    let negative = u.cmplt(Vec4::ZERO) | v.cmplt(Vec4::ZERO) | w.cmplt(Vec4::ZERO);
    let positive = u.cmpgt(Vec4::ZERO) | v.cmpgt(Vec4::ZERO) | w.cmpgt(Vec4::ZERO);
    let determinant = u + v + w;
    let (az, bz, cz) = (scale_z * a[z], scale_z * b[z], scale_z * c[z]);
    let t = (u * az + v * bz + w * cz) / determinant;
    // A NaN determinant passes `!= 0`, as chapter 10's `!(d != 0)` lets it
    // through, and makes `t` NaN, which fails the range.
    let hit = !(negative & positive)
        & determinant.cmpne(Vec4::ZERO)
        & t.cmpgt(Vec4::splat(t_min))
        & t.cmplt(Vec4::splat(t_max));
    Vec4::select(hit, t, Vec4::NAN)
}

/// The binary tree `bvh` over `shapes` folded into a tree whose nodes have
/// up to [`WIDTH`] children, and whose leaves hold their triangles four to
/// a [`Leaf4`].
///
/// Each wide node starts from a binary node's two children and, while it
/// has room, replaces the inner child with the largest surface (the one a
/// ray is likeliest to enter) by that child's own two children: about two
/// binary levels become one. A binary leaf becomes a wide leaf, its objects
/// in groups of four. Every box is a box of the binary tree, so a ray
/// meets the same boxes, fewer of them at a time.
pub fn collapse_bvh(bvh: &Bvh, shapes: &[Shape]) -> WideBvh {
    // Room for the most the fold can make: a wide node per binary inner
    // node, a `Leaf4` per four objects of a binary leaf. On huge pages: an
    // incoherent ray's walk jumps across the whole tree ([`vec_on_huge_pages`]).
    let inner_nodes = bvh.nodes.iter().filter(|node| !node.is_leaf()).count();
    let leaf_groups = bvh
        .nodes
        .iter()
        .filter(|node| node.is_leaf())
        .map(|node| node.primitive_range().len().div_ceil(WIDTH))
        .sum();
    let mut wide = WideBvh {
        nodes: vec_on_huge_pages(inner_nodes.max(1)),
        leaves: vec_on_huge_pages(leaf_groups),
        unbounded: bvh.unbounded.clone(),
    };
    if bvh.nodes.is_empty() {
        return wide;
    }
    wide.nodes.push(WideNode::UNUSED);
    // Wide nodes still to fill: (index in `wide.nodes`, binary node).
    let mut to_fill = vec![(0usize, 0usize)];
    while let Some((slot, binary)) = to_fill.pop() {
        let mut children = match bvh.nodes[binary].children() {
            Some((left, right)) => vec![left, right],
            // A root that is a leaf: a wide root with one lane.
            None => vec![binary],
        };
        while children.len() < WIDTH {
            let mut largest: Option<(usize, f64)> = None;
            for (place, &child) in children.iter().enumerate() {
                let area = half_area(&bvh.nodes[child].bounds);
                if !bvh.nodes[child].is_leaf() && largest.is_none_or(|(_, most)| area > most) {
                    largest = Some((place, area));
                }
            }
            let Some((place, _)) = largest else {
                break;
            };
            let Some((left, right)) = bvh.nodes[children[place]].children() else {
                break;
            };
            children[place] = left;
            children.push(right);
        }
        let mut node = WideNode::UNUSED;
        for (lane, &index) in children.iter().enumerate() {
            let child = &bvh.nodes[index];
            node.boxes.set(lane, child.bounds);
            if child.is_leaf() {
                node.first[lane] = wide.leaves.len() as u32;
                for group in bvh.primitives[child.primitive_range()].chunks(WIDTH) {
                    wide.leaves.push(leaf4(group, shapes));
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

/// The objects `group` (at most four) as a [`Leaf4`]: each triangle's
/// corners copied into its lane, any other shape marked to be asked on its
/// own.
fn leaf4(group: &[u32], shapes: &[Shape]) -> Leaf4 {
    let mut leaf = Leaf4 {
        triangles: Triangles4::NAN,
        objects: [u32::MAX; WIDTH],
        one_by_one: 0,
    };
    for (lane, &object) in group.iter().enumerate() {
        leaf.objects[lane] = object;
        match shapes.get(object as usize).and_then(Shape::as_triangle) {
            Some(triangle) => leaf.triangles.set(lane, triangle),
            None => leaf.one_by_one |= 1 << lane,
        }
    }
    leaf
}

impl Nearest {
    /// Asks every object of `leaves` and keeps the best hit, as
    /// [`Nearest::consider`] would one by one: a lane that hits within the
    /// limit of the best so far is offered, and offers are compared as
    /// chapter 3 compares hits, so the four answering together changes
    /// nothing.
    #[inline(always)]
    fn consider_leaves<C: Chapters>(
        &mut self,
        leaves: &[Leaf4],
        objects: &Objects<C>,
        ray: &Ray,
        t_min: f32,
    ) {
        for leaf in leaves {
            let t = C::intersect_triangles(&leaf.triangles, ray, t_min, self.limit());
            for lane in lanes_of((!t.is_nan_mask()).bitmask()) {
                self.offer(leaf.objects[lane] as usize, t[lane]);
            }
            for lane in lanes_of(leaf.one_by_one) {
                self.consider(objects, leaf.objects[lane], ray, t_min);
            }
        }
    }
}

/// The [`Leaf4`]s of a leaf lane `first`, `count` (in `usize`, where a
/// sum past `u32::MAX` cannot wrap around).
fn leaf_range(first: u32, count: u32) -> std::ops::Range<usize> {
    first as usize..first as usize + count as usize
}

/// The lanes whose bit is set in `bits`, in order.
#[inline(always)]
fn lanes_of(mut bits: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (bits != 0).then(|| {
            let lane = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            lane
        })
    })
}

/// Starts loading the child a node's lane points to (`first`, `count`):
/// the inner node, or the first of its leaves.
#[inline(always)]
fn prefetch_child(wide: &WideBvh, first: u32, count: u32) {
    if count == 0 {
        prefetch(wide.nodes.as_ptr().wrapping_add(first as usize));
    } else {
        prefetch(wide.leaves.as_ptr().wrapping_add(first as usize));
    }
}

/// [`nearest_hit_bvh`] through the wide tree `wide`: chapter 3's answer,
/// the same object at the same `t`.
///
/// At each node the four boxes are tested at once ([`hit_boxes`]), while
/// the children are already being loaded ([`prefetch`]). The
/// walk goes on into the child entered nearest; the others wait on the
/// stack, farther first so that the nearer come off first, each with its
/// entry, and are skipped when they come off beyond the best hit found
/// since. A leaf's triangles are tested four at a time
/// ([`intersect_triangles`]).
pub fn nearest_hit_wide<C: Chapters>(
    wide: &WideBvh,
    objects: &Objects<C>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    let mut nearest = Nearest { hit: None, t_max };
    for &object in &wide.unbounded {
        nearest.consider(objects, object, ray, t_min);
    }
    if wide.nodes.is_empty() {
        return nearest.hit;
    }
    let inverse = ray.dir.recip();
    // Waiting children: (first, count) as the node's lane says, and entry.
    let mut stack = NodeStack::<(u32, u32, f32)>::new();
    let mut visiting = 0usize;
    loop {
        let node = &wide.nodes[visiting];
        // Every child's load starts before the box test, not after it: the
        // next node opened is one of them, and which one is only known
        // once the boxes are tested, a wait the load can overlap. Loading
        // the children the ray misses too costs bandwidth, not waiting.
        for lane in lanes_of(node.used_lanes().bitmask()) {
            prefetch_child(wide, node.first[lane], node.count[lane]);
        }
        let entries = C::hit_boxes(&node.boxes, ray.origin, inverse, t_min, nearest.closest());
        let entered = !entries.is_nan_mask() & node.used_lanes();
        if entered.any() {
            // The nearest entered lane. The others count as infinitely far,
            // and must not be taken for it when an entry is infinite too (a
            // ray of direction zero enters a box ahead of it at infinity).
            let keyed = Vec4::select(entered, entries, Vec4::INFINITY);
            let nearest_lane = (keyed.cmpeq(Vec4::splat(keyed.min_element())) & entered)
                .bitmask()
                .trailing_zeros() as usize;
            let mut waiting = [0usize; WIDTH];
            let mut count = 0;
            for lane in lanes_of(entered.bitmask() & !(1 << nearest_lane)) {
                // Sorted in place, farthest first.
                let mut place = count;
                while place > 0 && entries[waiting[place - 1]] < entries[lane] {
                    waiting[place] = waiting[place - 1];
                    place -= 1;
                }
                waiting[place] = lane;
                count += 1;
            }
            for &lane in &waiting[..count] {
                stack.push((node.first[lane], node.count[lane], entries[lane]));
            }
            let (first, count) = (node.first[nearest_lane], node.count[nearest_lane]);
            if count == 0 {
                visiting = first as usize;
                continue;
            }
            nearest.consider_leaves(&wide.leaves[leaf_range(first, count)], objects, ray, t_min);
        }
        // The next waiting child, unless a hit found since it was pushed is
        // nearer than its box; leaves are tested as they come off.
        loop {
            let Some((first, count, entry)) = stack.pop() else {
                return nearest.hit;
            };
            if !(entry <= nearest.closest()) {
                continue;
            }
            if count == 0 {
                visiting = first as usize;
                break;
            }
            nearest.consider_leaves(&wide.leaves[leaf_range(first, count)], objects, ray, t_min);
        }
    }
}

/// [`any_hit_bvh`] through the wide tree `wide`: some hit with
/// `t_min < t < t_max`, the first found, for shadow rays.
pub fn any_hit_wide<C: Chapters>(
    wide: &WideBvh,
    objects: &Objects<C>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    let hit = |object: u32| {
        let object = object as usize;
        objects
            .intersect(object, ray, t_min, t_max)
            .map(|t| Hit { object, t })
    };
    if let Some(found) = wide.unbounded.iter().find_map(|&object| hit(object)) {
        return Some(found);
    }
    if wide.nodes.is_empty() {
        return None;
    }
    let inverse = ray.dir.recip();
    // Waiting children: (first, count) as a node's lane says; the root is
    // the inner node 0.
    let mut stack = NodeStack::<(u32, u32)>::new();
    stack.push((0, 0));
    while let Some((first, count)) = stack.pop() {
        if count > 0 {
            for leaf in &wide.leaves[leaf_range(first, count)] {
                let t = C::intersect_triangles(&leaf.triangles, ray, t_min, t_max);
                if let Some(lane) = lanes_of((!t.is_nan_mask()).bitmask()).next() {
                    let object = leaf.objects[lane] as usize;
                    return Some(Hit { object, t: t[lane] });
                }
                if let Some(found) = lanes_of(leaf.one_by_one).find_map(|l| hit(leaf.objects[l])) {
                    return Some(found);
                }
            }
            continue;
        }
        let node = &wide.nodes[first as usize];
        let entries = C::hit_boxes(&node.boxes, ray.origin, inverse, t_min, t_max);
        for lane in lanes_of((!entries.is_nan_mask() & node.used_lanes()).bitmask()) {
            stack.push((node.first[lane], node.count[lane]));
        }
    }
    None
}

#[cfg(test)]
mod tests;
