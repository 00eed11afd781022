//! The wide tree's cases: four boxes and four triangles at once, the
//! binary tree folded into nodes of four, and (in `boxes`) the walks.

use super::*;
use crate::bvh::{Boxes4, Leaf4, Triangles4, WIDTH, WideBvh};

/// `hit_boxes` on four boxes (`boxes[lane]` as `(min, max)`) and one ray:
/// expected, lane by lane, the entry `t` (exact), or a miss (`NaN`).
#[derive(Debug, Clone)]
pub struct HitBoxesCase {
    pub boxes: [(Vec3, Vec3); WIDTH],
    pub origin: Vec3,
    pub dir: Vec3,
    pub t_min: f32,
    pub t_max: f32,
    pub expect: [Option<f64>; WIDTH],
}

/// `hit_boxes`' inputs: four boxes `(min, max)`, the ray's origin and
/// direction (the call takes its inverse), the interval.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct HitBoxesCall {
    pub boxes: [(Vec3, Vec3); WIDTH],
    pub origin: Vec3,
    pub dir: Vec3,
    pub t_min: f32,
    pub t_max: f32,
}

impl Kind for HitBoxesCase {
    type Call = HitBoxesCall;
    type Answer = [f32; WIDTH];

    fn function(&self) -> &'static str {
        "hit_boxes"
    }

    fn inputs(&self) -> String {
        let boxes: Vec<String> = self
            .boxes
            .iter()
            .map(|(min, max)| box_text(*min, *max))
            .collect();
        format!(
            "hit_boxes(lanes [{}], origin {}, inverse_direction 1 / {}, {})",
            boxes.join(", "),
            vec(self.origin),
            vec(self.dir),
            range(self.t_min, self.t_max)
        )
    }

    fn call(&self) -> HitBoxesCall {
        HitBoxesCall {
            boxes: self.boxes,
            origin: self.origin,
            dir: self.dir,
            t_min: self.t_min,
            t_max: self.t_max,
        }
    }

    fn ask<C: Chapters>(call: &HitBoxesCall) -> Result<[f32; WIDTH], String> {
        let mut boxes = Boxes4::EMPTY;
        for (lane, &(min, max)) in call.boxes.iter().enumerate() {
            boxes.set(lane, Aabb::new(min, max));
        }
        Ok(C::hit_boxes(
            &boxes,
            call.origin,
            call.dir.recip(),
            call.t_min,
            call.t_max,
        )
        .to_array())
    }

    /// The same tolerance at both levels.
    fn judge(&self, got: [f32; WIDTH], _robust: bool) -> Outcome {
        let pass = (0..WIDTH).all(|lane| match self.expect[lane] {
            None => got[lane].is_nan(),
            Some(want) => {
                got[lane].is_finite() && close(f64::from(got[lane]), want, CHECKPOINT_TOLERANCE)
            }
        });
        let expected: Vec<String> = self
            .expect
            .iter()
            .map(|entry| entry.map_or_else(|| "NaN (misses)".into(), num64))
            .collect();
        let got: Vec<String> = got.iter().map(|&t| num(t)).collect();
        verdict(
            pass,
            format!("[{}]", expected.join(", ")),
            format!("[{}]", got.join(", ")),
        )
    }

    /// The boxes and the ray moved by a motion that keeps the axes; each
    /// lane's entry worked out again by the exact slab test.
    fn fresh(&self, draw: &mut Draw) -> Option<HitBoxesCase> {
        let motion = draw.axis_motion();
        let boxes = self.boxes.map(|(min, max)| {
            if Aabb::new(min, max) == Aabb::EMPTY {
                (min, max)
            } else {
                motion.aligned_box(min, max)
            }
        });
        let (origin, dir) = (motion.point(self.origin), motion.direction(self.dir));
        let (t_min, t_max) = (motion.t(self.t_min), motion.t(self.t_max));
        let mut expect = [None; WIDTH];
        for lane in 0..WIDTH {
            if self.expect[lane].is_none() {
                continue;
            }
            let (min, max) = boxes[lane];
            let (entry, exit) = exact::slab_interval(&Aabb::new(min, max), origin, dir);
            let entry = entry.max(f64::from(t_min));
            if !(entry <= exit.min(f64::from(t_max))) {
                return None;
            }
            expect[lane] = Some(entry);
        }
        Some(HitBoxesCase {
            boxes,
            origin,
            dir,
            t_min,
            t_max,
            expect,
        })
    }
}

/// The box from `min` to `max` as a student writes it; "empty" for
/// [`Aabb::EMPTY`].
fn box_text(min: Vec3, max: Vec3) -> String {
    if Aabb::new(min, max) == Aabb::EMPTY {
        "the empty box".into()
    } else {
        format!("{} to {}", vec(min), vec(max))
    }
}

/// `intersect_triangles` on four triangles (corners `NaN` for a lane that
/// holds none) and one ray: expected, lane by lane, what the chapters'
/// own `intersect_triangle` answers for that triangle, bit for bit (`NaN`
/// where it finds no hit), since a wide walk must find the hit chapter 3
/// finds with it.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct FourTrianglesCase {
    pub triangles: [[Vec3; 3]; WIDTH],
    pub ray: Ray,
    pub t_min: f32,
    pub t_max: f32,
}

/// One call of `intersect_triangles` as judged: its four answers and the
/// chapters' own `intersect_triangle` on each lane's triangle.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Lanes {
    pub four: [f32; WIDTH],
    pub one_by_one: [Option<f32>; WIDTH],
}

impl Kind for FourTrianglesCase {
    type Call = FourTrianglesCase;
    type Answer = Lanes;

    fn function(&self) -> &'static str {
        "intersect_triangles"
    }

    fn inputs(&self) -> String {
        let lanes: Vec<String> = self.triangles.iter().map(|c| corners_text(*c)).collect();
        format!(
            "intersect_triangles(lanes [{}], {}, {})",
            lanes.join(", "),
            ray_text(&self.ray),
            range(self.t_min, self.t_max)
        )
    }

    fn call(&self) -> FourTrianglesCase {
        self.clone()
    }

    fn ask<C: Chapters>(call: &FourTrianglesCase) -> Result<Lanes, String> {
        let mut triangles = Triangles4::NAN;
        for (lane, &[a, b, c]) in call.triangles.iter().enumerate() {
            triangles.set(lane, &Triangle::new(a, b, c));
        }
        Ok(lanes::<C>(&triangles, &call.ray, call.t_min, call.t_max))
    }

    /// The same rule at both levels.
    fn judge(&self, lanes: Lanes, _robust: bool) -> Outcome {
        match lanes_problem(&lanes) {
            None => Outcome::Pass,
            Some((expected, got)) => Outcome::Fail { expected, got },
        }
    }

    /// The four triangles and the ray moved whole.
    fn fresh(&self, draw: &mut Draw) -> Option<FourTrianglesCase> {
        let motion = draw.motion();
        let (ray, t_min, t_max) =
            super::intersections::moved_ray(&motion, &self.ray, self.t_min, self.t_max);
        Some(FourTrianglesCase {
            triangles: self
                .triangles
                .map(|corners| corners.map(|corner| motion.point(corner))),
            ray,
            t_min,
            t_max,
        })
    }
}

/// `intersect_triangles` on `triangles`, and the chapters' own
/// `intersect_triangle` on each lane's triangle beside it.
fn lanes<C: Chapters>(triangles: &Triangles4, ray: &Ray, t_min: f32, t_max: f32) -> Lanes {
    let four = C::intersect_triangles(triangles, ray, t_min, t_max).to_array();
    // The chapters' own test, reported as it always is: run as raylab's
    // own, it could run raylab's answers unseen.
    let one_by_one =
        std::array::from_fn(|lane| C::intersect_triangle(&triangles.get(lane), ray, t_min, t_max));
    Lanes { four, one_by_one }
}

/// Where the four answers differ from the one-by-one ones, bit for bit
/// (`NaN` where a lane has no hit): (expected, got).
fn lanes_problem(lanes: &Lanes) -> Option<(String, String)> {
    let Lanes { four, one_by_one } = lanes;
    let same = |lane: usize| match one_by_one[lane] {
        None => four[lane].is_nan(),
        Some(t) => four[lane].to_bits() == t.to_bits(),
    };
    if (0..WIDTH).all(same) {
        return None;
    }
    let expected: Vec<String> = one_by_one
        .iter()
        .map(|t| t.map_or_else(|| "NaN (no hit)".into(), num))
        .collect();
    let got: Vec<String> = four.iter().map(|&t| num(t)).collect();
    Some((
        format!(
            "[{}] (your intersect_triangle on each lane's triangle, bit for bit)",
            expected.join(", ")
        ),
        format!("[{}]", got.join(", ")),
    ))
}

/// `intersect_triangles` on raylab's closed model of `triangles`
/// triangles, four consecutive ones to a call, for a ray from inside the
/// model toward each vertex and edge midpoint: every lane must answer as
/// the chapters' `intersect_triangle` does, there where edge functions are
/// zero or nearly so.
#[derive(Debug, Clone)]
pub struct MeshInFoursCase {
    pub triangles: usize,
    /// Where the model is moved to (`grade --fresh`); `None` where it is.
    pub motion: Option<super::Motion>,
}

impl Kind for MeshInFoursCase {
    type Call = super::intersections::MeshCall;
    /// The first call whose lanes differ, with its first triangle and its
    /// ray; and how many calls were made.
    type Answer = (Option<(usize, Ray, Lanes)>, usize);

    fn function(&self) -> &'static str {
        "intersect_triangles"
    }

    fn inputs(&self) -> String {
        format!(
            "intersect_triangles(four consecutive triangles of raylab's closed model of {} \
             triangles at a time, a ray from inside toward each vertex and edge midpoint, \
             t_min = 0, t_max = inf)",
            self.triangles
        )
    }

    fn call(&self) -> Self::Call {
        super::intersections::MeshCall {
            triangles: self.triangles,
            motion: self.motion.map(super::intersections::WireMotion::from),
        }
    }

    fn ask<C: Chapters>(call: &Self::Call) -> Result<Self::Answer, String> {
        let (triangles, rays) = super::intersections::closed_mesh_rays(call)?;
        let groups: Vec<Triangles4> = triangles
            .chunks(WIDTH)
            .map(|group| {
                let mut four = Triangles4::NAN;
                for (lane, triangle) in group.iter().enumerate() {
                    four.set(lane, triangle);
                }
                four
            })
            .collect();
        let mut calls = 0;
        for ray in &rays {
            for (group, four) in groups.iter().enumerate() {
                calls += 1;
                let lanes = lanes::<C>(four, ray, 0.0, f32::INFINITY);
                if lanes_problem(&lanes).is_some() {
                    return Ok((Some((WIDTH * group, *ray, lanes)), calls));
                }
            }
        }
        Ok((None, calls))
    }

    /// The same rule at both levels: every call's lanes as the
    /// one-by-one test's.
    fn judge(&self, (differs, calls): Self::Answer, _robust: bool) -> Outcome {
        let Some((first, ray, lanes)) = differs else {
            let expected = super::intersections::closed_mesh_rays(&self.call())
                .map_or(0, |(t, r)| r.len() * t.len().div_ceil(WIDTH));
            return if calls == expected {
                Outcome::Pass
            } else {
                super::intersections::wrong_length(expected, calls)
            };
        };
        match lanes_problem(&lanes) {
            Some((expected, got)) => Outcome::Fail {
                expected,
                got: format!(
                    "{got} for triangles {} to {} and the {}",
                    first,
                    first + WIDTH - 1,
                    ray_text(&ray)
                ),
            },
            None => Outcome::Fail {
                expected: "every lane as the one-by-one test".into(),
                got: "a difference that is not one".into(),
            },
        }
    }

    /// The model and its rays moved whole.
    fn fresh(&self, draw: &mut Draw) -> Option<MeshInFoursCase> {
        Some(MeshInFoursCase {
            triangles: self.triangles,
            motion: Some(draw.motion()),
        })
    }
}

/// What a `Collapse` case asks of the wide tree's shape, beyond its being
/// a valid tree over the same objects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WideShape {
    /// Any valid wide tree.
    Any,
    /// The root uses this many lanes.
    RootLanes(usize),
}

/// `build_bvh` over the boxes of `shapes`, then `collapse_bvh`: every boxed
/// object once in a leaf's lanes, each lane's box holding what is under
/// it, the triangles' corners copied into their lanes and every other
/// shape marked to be asked on its own; `unbounded` as the binary tree's;
/// no more nodes than the binary tree has inner nodes.
#[derive(Debug, Clone)]
pub struct CollapseCase {
    pub shapes: Vec<Shape>,
    pub options: BvhOptions,
    pub expect: WideShape,
}

impl Kind for CollapseCase {
    type Call = super::boxes::TreeCall;
    /// The binary tree and the wide tree it was folded into.
    type Answer = (Bvh, WideBvh);

    fn function(&self) -> &'static str {
        "collapse_bvh"
    }

    fn inputs(&self) -> String {
        format!(
            "collapse_bvh(build_bvh(the boxes of [{}], {}), the shapes)",
            shapes_text(&self.shapes),
            options_text(&self.options)
        )
    }

    fn call(&self) -> Self::Call {
        super::boxes::TreeCall {
            shapes: self.shapes.clone(),
            options: self.options,
        }
    }

    fn ask<C: Chapters>(call: &Self::Call) -> Result<(Bvh, WideBvh), String> {
        let bounds: Vec<Option<Aabb>> = call.shapes.iter().map(Shape::bounds).collect();
        let bvh = C::build_bvh(&bounds, &call.options);
        let wide = C::collapse_bvh(&bvh, &call.shapes);
        Ok((bvh, wide))
    }

    /// The same rule at both levels.
    fn judge(&self, (bvh, wide): (Bvh, WideBvh), _robust: bool) -> Outcome {
        if let Some(problem) = wide_problem(&wide, &bvh, &self.shapes) {
            return Outcome::Fail {
                expected: "every boxed object once in a leaf's lanes, under boxes that hold \
                           it; triangles copied into their lanes, other shapes marked \
                           one_by_one; unbounded as the binary tree's"
                    .into(),
                got: problem,
            };
        }
        match self.expect {
            WideShape::Any => Outcome::Pass,
            WideShape::RootLanes(lanes) => {
                let used = wide
                    .nodes
                    .first()
                    .map_or(0, |root| root.used_lanes().bitmask().count_ones() as usize);
                verdict(
                    used == lanes,
                    format!("the root using {lanes} lanes"),
                    format!("the root using {used}"),
                )
            }
        }
    }

    /// The objects moved by a motion that keeps the axes.
    fn fresh(&self, draw: &mut Draw) -> Option<CollapseCase> {
        let motion = draw.axis_motion();
        Some(CollapseCase {
            shapes: self
                .shapes
                .iter()
                .map(|shape| super::intersections::moved_shape(&motion, shape))
                .collect::<Option<_>>()?,
            ..self.clone()
        })
    }
}

/// What is wrong with `wide` as the collapse of `bvh` over `shapes`, if
/// anything. Walks from the root with a visited mark per node, so that a
/// cycle or an index out of range is reported, not followed.
pub(super) fn wide_problem(wide: &WideBvh, bvh: &Bvh, shapes: &[Shape]) -> Option<String> {
    let mut unbounded = wide.unbounded.clone();
    let mut expected = bvh.unbounded.clone();
    unbounded.sort_unstable();
    expected.sort_unstable();
    if unbounded != expected {
        return Some(format!(
            "unbounded {:?}, where the binary tree's is {:?}",
            wide.unbounded, bvh.unbounded
        ));
    }
    let inner = bvh.nodes.iter().filter(|node| !node.is_leaf()).count();
    if wide.nodes.len() > inner.max(1) {
        return Some(format!(
            "{} wide nodes, more than the binary tree's {} inner nodes",
            wide.nodes.len(),
            inner
        ));
    }
    if wide.nodes.is_empty() {
        return (!bvh.nodes.is_empty()).then(|| "no nodes, but the binary tree has some".into());
    }
    let holds = |outer: &Aabb, inner: &Aabb| {
        outer.min.cmple(inner.min).all() && inner.max.cmple(outer.max).all()
    };
    let mut placed = vec![0usize; shapes.len()];
    let mut visited = vec![false; wide.nodes.len()];
    let mut to_visit = vec![0usize];
    while let Some(index) = to_visit.pop() {
        if std::mem::replace(&mut visited[index], true) {
            return Some(format!("node {index} is reached twice: not a tree"));
        }
        let node = &wide.nodes[index];
        for lane in (0..WIDTH).filter(|&lane| node.used_lanes().test(lane)) {
            let (first, count) = (node.first[lane] as usize, node.count[lane] as usize);
            let lane_box = node.boxes.get(lane);
            if count == 0 {
                let Some(child) = wide.nodes.get(first) else {
                    return Some(format!(
                        "node {index}, lane {lane}: child node {first}, but there are {} nodes",
                        wide.nodes.len()
                    ));
                };
                for child_lane in (0..WIDTH).filter(|&l| child.used_lanes().test(l)) {
                    if !holds(&lane_box, &child.boxes.get(child_lane)) {
                        return Some(format!(
                            "node {index}, lane {lane}: its box does not hold node {first}'s \
                             lane {child_lane}"
                        ));
                    }
                }
                to_visit.push(first);
                continue;
            }
            let Some(leaves) = wide.leaves.get(first..first + count) else {
                return Some(format!(
                    "node {index}, lane {lane}: leaves {first} to {}, but there are {}",
                    first + count - 1,
                    wide.leaves.len()
                ));
            };
            for (place, leaf) in leaves.iter().enumerate() {
                if let Some(problem) = leaf_problem(leaf, &lane_box, shapes, &mut placed) {
                    return Some(format!("node {index}, lane {lane}: {problem}"));
                }
                let held = leaf.objects.iter().filter(|&&o| o != u32::MAX).count();
                if place + 1 < count && held < WIDTH {
                    return Some(format!(
                        "node {index}, lane {lane}: Leaf4 {} of {count} holds {held} objects \
                         (a leaf's objects go four to each Leaf4, only the last one short)",
                        place + 1
                    ));
                }
            }
        }
    }
    let boxed = |object: usize| !bvh.unbounded.contains(&(object as u32));
    if let Some(problem) = (0..shapes.len())
        .find(|&object| placed[object] != usize::from(boxed(object)))
        .map(|object| {
            format!(
                "object {object} is in {} leaf lanes reached from the root{}",
                placed[object],
                if boxed(object) {
                    ""
                } else {
                    ", but it has no box"
                }
            )
        })
    {
        return Some(problem);
    }
    let bounds: Vec<Option<Aabb>> = shapes.iter().map(Shape::bounds).collect();
    if super::tree::tree_problem(bvh, &bounds).is_some() {
        return None;
    }
    lane_box_problem(wide, bvh)
}

/// A lane of `wide` whose box is not the box of the node of `bvh` that
/// holds exactly the objects under it: the fold keeps the binary tree's
/// nodes, four at a time, and their boxes with them (both trees valid).
fn lane_box_problem(wide: &WideBvh, bvh: &Bvh) -> Option<String> {
    let mut binary = std::collections::HashMap::new();
    let mut reached = if bvh.nodes.is_empty() {
        vec![]
    } else {
        vec![0]
    };
    while let Some(node) = reached.pop() {
        binary.insert(
            super::tree::objects_under(bvh, node),
            bvh.nodes[node].bounds,
        );
        reached.extend(
            bvh.nodes[node]
                .children()
                .map(|(left, right)| [left, right])
                .into_iter()
                .flatten(),
        );
    }
    let mut to_visit = vec![0usize];
    while let Some(index) = to_visit.pop() {
        let node = &wide.nodes[index];
        for lane in (0..WIDTH).filter(|&lane| node.used_lanes().test(lane)) {
            let lane_box = node.boxes.get(lane);
            let under = objects_under_lane(wide, node.first[lane], node.count[lane]);
            if node.count[lane] == 0 {
                to_visit.push(node.first[lane] as usize);
            }
            match binary.get(&under) {
                Some(folded) if *folded == lane_box => {}
                Some(folded) => {
                    return Some(format!(
                        "node {index}, lane {lane}: its box {} to {} is not the box of the binary \
                         node holding its objects {under:?}, {} to {} (the fold keeps the binary \
                         tree's boxes)",
                        vec(lane_box.min),
                        vec(lane_box.max),
                        vec(folded.min),
                        vec(folded.max)
                    ));
                }
                None => {
                    return Some(format!(
                        "node {index}, lane {lane}: its objects {under:?} are no node's of the \
                         binary tree (the fold keeps the binary tree's nodes, four at a time)"
                    ));
                }
            }
        }
    }
    None
}

/// The objects under a lane `first`, `count` of a valid wide tree, sorted.
fn objects_under_lane(wide: &WideBvh, first: u32, count: u32) -> Vec<u32> {
    let mut found = Vec::new();
    let mut to_visit = vec![(first, count)];
    while let Some((first, count)) = to_visit.pop() {
        let (first, count) = (first as usize, count as usize);
        if count > 0 {
            for leaf in &wide.leaves[first..first + count] {
                found.extend(leaf.objects.iter().filter(|&&object| object != u32::MAX));
            }
            continue;
        }
        let node = &wide.nodes[first];
        for lane in (0..WIDTH).filter(|&lane| node.used_lanes().test(lane)) {
            to_visit.push((node.first[lane], node.count[lane]));
        }
    }
    found.sort_unstable();
    found
}

/// What is wrong with one [`Leaf4`] under a lane whose box is `lane_box`;
/// counts each object it holds in `placed`.
fn leaf_problem(
    leaf: &Leaf4,
    lane_box: &Aabb,
    shapes: &[Shape],
    placed: &mut [usize],
) -> Option<String> {
    for lane in 0..WIDTH {
        let object = leaf.objects[lane];
        let asked_alone = leaf.one_by_one & (1 << lane) != 0;
        let corners = leaf.triangles.corners.map(|c| c.map(|axis| axis[lane]));
        if object == u32::MAX {
            if asked_alone || corners.iter().flatten().any(|x| !x.is_nan()) {
                return Some(format!(
                    "lane {lane} holds no object, yet is marked one_by_one or has corners"
                ));
            }
            continue;
        }
        let Some(shape) = shapes.get(object as usize) else {
            return Some(format!(
                "object {object}, but there are {} objects",
                shapes.len()
            ));
        };
        placed[object as usize] += 1;
        if let Some(bounds) = shape.bounds()
            && !(lane_box.min.cmple(bounds.min).all() && bounds.max.cmple(lane_box.max).all())
        {
            return Some(format!(
                "object {object}'s box is not inside the lane's box"
            ));
        }
        match shape.as_triangle() {
            Some(triangle) => {
                let copied = corners
                    .iter()
                    .zip(triangle.corners())
                    .all(|(got, want)| got.iter().zip(want.to_array()).all(|(g, w)| g == &w));
                if asked_alone || !copied {
                    return Some(format!(
                        "object {object}, a triangle, not copied into lane {lane}'s corners \
                         (or marked one_by_one)"
                    ));
                }
            }
            None if !asked_alone => {
                return Some(format!(
                    "object {object} is not a triangle, but lane {lane} is not marked one_by_one"
                ));
            }
            None if corners.iter().flatten().any(|x| !x.is_nan()) => {
                return Some(format!(
                    "object {object} is not a triangle, but lane {lane}'s corners are not NaN"
                ));
            }
            None => {}
        }
    }
    None
}
