//! Bounding-volume cases: the slab test on one box, and the tree built
//! and walked over many.

use super::*;

/// `hit_box(Aabb::new(min, max), origin, dir.recip(), t_min, t_max)`:
/// expected the entry `t` (exact, `t_min` from inside), or no hit.
#[derive(Debug, Clone)]
pub struct HitBoxCase {
    pub min: Vec3,
    pub max: Vec3,
    pub origin: Vec3,
    pub dir: Vec3,
    pub t_min: f32,
    pub t_max: f32,
    pub expect: Option<f64>,
}

/// `hit_box`'s inputs: the box `(min, max)`, the ray's origin and
/// direction (the call takes its inverse), the interval.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct HitBoxCall {
    pub bounds: (Vec3, Vec3),
    pub origin: Vec3,
    pub dir: Vec3,
    pub t_min: f32,
    pub t_max: f32,
}

impl Kind for HitBoxCase {
    type Call = HitBoxCall;
    type Answer = Option<f32>;

    fn function(&self) -> &'static str {
        "hit_box"
    }

    fn inputs(&self) -> String {
        let HitBoxCase {
            min,
            max,
            origin,
            dir,
            t_min,
            t_max,
            ..
        } = self;
        format!(
            "hit_box(box {} to {}, origin {}, inverse_direction 1 / {}, {})",
            vec(*min),
            vec(*max),
            vec(*origin),
            vec(*dir),
            range(*t_min, *t_max)
        )
    }

    fn call(&self) -> HitBoxCall {
        HitBoxCall {
            bounds: (self.min, self.max),
            origin: self.origin,
            dir: self.dir,
            t_min: self.t_min,
            t_max: self.t_max,
        }
    }

    fn ask<C: Chapters>(call: &HitBoxCall) -> Result<Option<f32>, String> {
        let (min, max) = call.bounds;
        Ok(C::hit_box(
            &Aabb::new(min, max),
            call.origin,
            call.dir.recip(),
            call.t_min,
            call.t_max,
        ))
    }

    /// The same tolerance at both levels.
    fn judge(&self, got: Option<f32>, _robust: bool) -> Outcome {
        let expect = &self.expect;
        let show = |entry: Option<String>| {
            entry.map_or_else(|| "None (misses)".into(), |t| format!("Some({t})"))
        };
        let pass = match (got, *expect) {
            (None, None) => true,
            // The reference widens the entry by 2 gamma_3 of itself
            // (a few 1e-7): far inside the checkpoint tolerance.
            (Some(t), Some(want)) => {
                t.is_finite() && close(f64::from(t), want, CHECKPOINT_TOLERANCE)
            }
            _ => false,
        };
        verdict(pass, show(expect.map(num64)), show(got.map(num)))
    }

    /// The box and the ray moved by a motion that keeps the axes; the
    /// entry worked out again by the exact slab test (`t_min` from
    /// inside).
    fn fresh(&self, draw: &mut Draw) -> Option<HitBoxCase> {
        let motion = draw.axis_motion();
        let (min, max) = motion.aligned_box(self.min, self.max);
        let (origin, dir) = (motion.point(self.origin), motion.direction(self.dir));
        let (t_min, t_max) = (motion.t(self.t_min), motion.t(self.t_max));
        let expect = self.expect.and_then(|_| {
            let (entry, exit) = exact::slab_interval(&Aabb::new(min, max), origin, dir);
            let entry = entry.max(f64::from(t_min));
            (entry <= exit.min(f64::from(t_max))).then_some(entry)
        });
        if expect.is_none() && self.expect.is_some() {
            return None;
        }
        Some(HitBoxCase {
            min,
            max,
            origin,
            dir,
            t_min,
            t_max,
            expect,
        })
    }
}

/// `hit_box` on `rays` rays from random origins aimed at random points
/// of the box's twelve edges (drawn from `seed`): whenever the exact
/// ray (the `f32` origin and direction, in `f64`) meets the box, the
/// answer must be a hit.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct BoxEdgesCase {
    pub min: Vec3,
    pub max: Vec3,
    pub rays: u32,
    pub seed: u64,
    /// Asks `hit_boxes`, the box in a lane that changes from ray to ray,
    /// rather than `hit_box`.
    pub four_at_once: bool,
}

impl Kind for BoxEdgesCase {
    type Call = BoxEdgesCase;
    /// For each ray, in order, whether the chapters say it enters the box.
    type Answer = Vec<bool>;

    fn function(&self) -> &'static str {
        if self.four_at_once {
            "hit_boxes"
        } else {
            "hit_box"
        }
    }

    fn inputs(&self) -> String {
        let BoxEdgesCase {
            min,
            max,
            rays,
            seed,
            four_at_once,
        } = self;
        format!(
            "{}(box {} to {}{}, ...) on {rays} rays aimed at its edges (seed {seed}), \
             t_min = 0, t_max = inf",
            self.function(),
            vec(*min),
            vec(*max),
            if *four_at_once {
                " in lane i % 4 for ray i, the other lanes empty"
            } else {
                ""
            }
        )
    }

    fn call(&self) -> BoxEdgesCase {
        self.clone()
    }

    fn ask<C: Chapters>(call: &BoxEdgesCase) -> Result<Vec<bool>, String> {
        Ok(box_edges::<C>(
            &Aabb::new(call.min, call.max),
            call.rays,
            call.seed,
            call.four_at_once,
        ))
    }

    /// The same rule at both levels: every ray the exact slab test says
    /// meets the box is a hit. The judge draws the rays again and finds
    /// the first the chapters refused.
    fn judge(&self, enters: Vec<bool>, _robust: bool) -> Outcome {
        if enters.len() != self.rays as usize {
            return super::intersections::wrong_length(self.rays as usize, enters.len());
        }
        let bounds = Aabb::new(self.min, self.max);
        for (index, ((origin, dir), entered)) in edge_rays(&bounds, self.rays, self.seed)
            .zip(enters)
            .enumerate()
        {
            let (entry, exit) = exact::slab_interval(&bounds, origin, dir);
            // The exact ray meets the box for some t >= 0 (a NaN from a
            // zero direction component is not counted: no such ray is
            // drawn).
            if entered || !(exit >= entry.max(0.0)) {
                continue;
            }
            return Outcome::Fail {
                expected: format!(
                    "a hit: the exact ray meets the box from t = {} to t = {}",
                    num64(entry),
                    num64(exit)
                ),
                got: format!(
                    "None for ray {} of {}: from {} along {}",
                    index + 1,
                    self.rays,
                    vec(origin),
                    vec(dir)
                ),
            };
        }
        Outcome::Pass
    }

    /// Another seed, and the box moved by a motion that keeps the axes.
    fn fresh(&self, draw: &mut Draw) -> Option<BoxEdgesCase> {
        let motion = draw.axis_motion();
        let (min, max) = motion.aligned_box(self.min, self.max);
        Some(BoxEdgesCase {
            min,
            max,
            seed: draw.word() | 1,
            ..self.clone()
        })
    }
}

/// `build_bvh` over the boxes of `shapes` (`Shape::bounds`): the tree
/// must hold every boxed object exactly once, under a leaf whose box
/// holds it, each inner node's box holding its children's; objects
/// without a box (planes) in `unbounded`, not in the tree.
#[derive(Debug, Clone)]
pub struct BvhBuildCase {
    pub shapes: Vec<Shape>,
    pub options: BvhOptions,
    /// What the lesson fixes about this tree's shape, beyond its being
    /// a valid tree.
    pub expect: TreeShape,
}

/// A tree's call: the objects (their boxes are what the build gets) and
/// the build's options.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct TreeCall {
    pub shapes: Vec<Shape>,
    pub options: BvhOptions,
}

impl Kind for BvhBuildCase {
    type Call = TreeCall;
    type Answer = Bvh;

    fn function(&self) -> &'static str {
        "build_bvh"
    }

    fn inputs(&self) -> String {
        let BvhBuildCase {
            shapes, options, ..
        } = self;
        format!(
            "build_bvh(the boxes of [{}], {})",
            shapes_text(shapes),
            options_text(options)
        )
    }

    fn call(&self) -> TreeCall {
        TreeCall {
            shapes: self.shapes.clone(),
            options: self.options,
        }
    }

    fn ask<C: Chapters>(call: &TreeCall) -> Result<Bvh, String> {
        let bounds: Vec<Option<Aabb>> = call.shapes.iter().map(Shape::bounds).collect();
        Ok(C::build_bvh(&bounds, &call.options))
    }

    /// The same rule at both levels.
    fn judge(&self, bvh: Bvh, _robust: bool) -> Outcome {
        let expect = &self.expect;
        let bounds: Vec<Option<Aabb>> = self.shapes.iter().map(Shape::bounds).collect();
        match tree_problem(&bvh, &bounds) {
            None => match shape_problem(&bvh, &bounds, expect) {
                None => Outcome::Pass,
                Some((expected, got)) => Outcome::Fail { expected, got },
            },
            Some(problem) => Outcome::Fail {
                expected: "every boxed object once, under a leaf whose box holds it; \
                           each node's box holding its children; planes in unbounded"
                    .into(),
                got: problem,
            },
        }
    }

    /// The objects moved by a motion that keeps the axes: every cut the
    /// lesson's rules give is the same partition of the same objects.
    fn fresh(&self, draw: &mut Draw) -> Option<BvhBuildCase> {
        let motion = draw.axis_motion();
        Some(BvhBuildCase {
            shapes: moved_shapes(&motion, &self.shapes)?,
            ..self.clone()
        })
    }
}

/// Every shape of `shapes` moved by `motion`, if every one can be.
fn moved_shapes(motion: &Motion, shapes: &[Shape]) -> Option<Vec<Shape>> {
    shapes
        .iter()
        .map(|shape| super::intersections::moved_shape(motion, shape))
        .collect()
}

/// `build_bvh` over the boxes of `shapes`, then for each of `rays`
/// `nearest_hit_bvh` (or `any_hit_bvh` when `any`) through that tree;
/// when `wide`, the tree folded by `collapse_bvh` and walked by
/// `nearest_hit_wide` (or `any_hit_wide`).
/// Expected: chapter 3's nearest hit over the same objects, the same
/// object at the same `t`, bit for bit; for any-hit, a hit exactly
/// when there is one, and a real one (the object's own test gives
/// that `t` in the interval).
#[derive(Debug, Clone)]
pub struct BvhHitsCase {
    pub shapes: Vec<Shape>,
    pub options: BvhOptions,
    pub rays: Vec<Ray>,
    pub t_min: f32,
    pub t_max: f32,
    pub any: bool,
    pub wide: bool,
    /// Also judges the walk's steps as the lesson gives them, seen through
    /// the objects it asks (see `steps_problem`).
    pub steps: bool,
}

/// A walk's call: the tree's, the rays, the interval, which walk.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct WalkCall {
    pub tree: TreeCall,
    pub rays: Vec<Ray>,
    pub t_min: f32,
    pub t_max: f32,
    pub any: bool,
    pub wide: bool,
    /// Whether to write down every object test the walk makes, and send
    /// the trees back with the answers.
    pub steps: bool,
}

/// One ray's walk: the walk's hit; every object the same chapters' own
/// tests hit on the ray, with its `t` (what chapter 3's loop would choose
/// from: the judge finds the nearest, [`Walked::by_loop`], so that no loop
/// of raylab's runs in the student's process); for a hit the walk claims,
/// that object's own test on the ray; when its steps are judged, every
/// object test the walk made, in order.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Walked {
    pub walk: Option<(usize, f32)>,
    pub hits: Vec<(usize, f32)>,
    pub own_test: Option<f32>,
    pub asked: Vec<crate::course::Asked>,
}

impl Walked {
    /// The hit chapter 3's loop finds among [`Walked::hits`]: the nearest,
    /// and of equally near ones the first listed (the loop only takes a
    /// later object that is strictly nearer).
    pub fn by_loop(&self) -> Option<(usize, f32)> {
        let mut nearest: Option<(usize, f32)> = None;
        for &(object, t) in &self.hits {
            if nearest.is_none_or(|(_, best)| t < best) {
                nearest = Some((object, t));
            }
        }
        nearest
    }
}

/// The trees a walk went through, as the student's process built them.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct WalkedTrees {
    pub bvh: Bvh,
    /// The wide tree folded from it, for the wide walks.
    pub wide: Option<crate::bvh::WideBvh>,
}

impl Kind for BvhHitsCase {
    type Call = WalkCall;
    type Answer = (Vec<Walked>, Option<WalkedTrees>);

    fn function(&self) -> &'static str {
        match (self.wide, self.any) {
            (false, false) => "nearest_hit_bvh",
            (false, true) => "any_hit_bvh",
            (true, false) => "nearest_hit_wide",
            (true, true) => "any_hit_wide",
        }
    }

    fn inputs(&self) -> String {
        let BvhHitsCase {
            shapes,
            options,
            rays,
            t_min,
            t_max,
            ..
        } = self;
        let tree = format!(
            "build_bvh(the boxes of [{}], {})",
            shapes_text(shapes),
            options_text(options)
        );
        format!(
            "{}({}, the objects, {}, {})",
            self.function(),
            if self.wide {
                format!("collapse_bvh({tree}, the shapes)")
            } else {
                tree
            },
            if rays.len() == 1 {
                ray_text(&rays[0])
            } else {
                format!(
                    "each of {} rays from {}",
                    rays.len(),
                    rays.first().map(ray_text).unwrap_or_default()
                )
            },
            range(*t_min, *t_max)
        )
    }

    fn call(&self) -> WalkCall {
        WalkCall {
            tree: TreeCall {
                shapes: self.shapes.clone(),
                options: self.options,
            },
            rays: self.rays.clone(),
            t_min: self.t_min,
            t_max: self.t_max,
            any: self.any,
            wide: self.wide,
            steps: self.steps,
        }
    }

    fn ask<C: Chapters>(call: &WalkCall) -> Result<Self::Answer, String> {
        let (t_min, t_max, any, steps) = (call.t_min, call.t_max, call.any, call.steps);
        let shapes = &call.tree.shapes;
        let bounds: Vec<Option<Aabb>> = shapes.iter().map(Shape::bounds).collect();
        let bvh = C::build_bvh(&bounds, &call.tree.options);
        if call.wide {
            let wide = C::collapse_bvh(&bvh, shapes);
            let walked = bvh_hits::<C>(shapes, &call.rays, t_min, t_max, steps, |objects, ray| {
                if any {
                    C::any_hit_wide(&wide, objects, ray, t_min, t_max)
                } else {
                    C::nearest_hit_wide(&wide, objects, ray, t_min, t_max)
                }
            });
            let trees = steps.then_some(WalkedTrees {
                bvh,
                wide: Some(wide),
            });
            return Ok((walked, trees));
        }
        let walked = bvh_hits::<C>(shapes, &call.rays, t_min, t_max, steps, |objects, ray| {
            if any {
                C::any_hit_bvh(&bvh, objects, ray, t_min, t_max)
            } else {
                C::nearest_hit_bvh(&bvh, objects, ray, t_min, t_max)
            }
        });
        Ok((walked, steps.then_some(WalkedTrees { bvh, wide: None })))
    }

    /// The same rule at both levels (see `judge_walks`), and, for a case
    /// that judges them, the walk's steps (see `steps_problem`).
    fn judge(&self, (walked, trees): Self::Answer, _robust: bool) -> Outcome {
        let answers = judge_walks(&self.rays, self.any, &walked);
        if answers != Outcome::Pass || !self.steps {
            return answers;
        }
        let Some(trees) = trees else {
            return Outcome::Fail {
                expected: "the trees the walk went through".into(),
                got: "no trees".into(),
            };
        };
        match steps_problem(&self.shapes, &self.call(), &trees, &walked) {
            None => Outcome::Pass,
            Some((expected, got)) => Outcome::Fail { expected, got },
        }
    }

    /// The objects and the rays moved by a motion that keeps the axes
    /// (the loop's answer, which the walk must match, comes with them).
    fn fresh(&self, draw: &mut Draw) -> Option<BvhHitsCase> {
        let motion = draw.axis_motion();
        Some(BvhHitsCase {
            shapes: moved_shapes(&motion, &self.shapes)?,
            rays: self.rays.iter().map(|ray| motion.ray(ray)).collect(),
            t_min: motion.t(self.t_min),
            t_max: motion.t(self.t_max),
            ..self.clone()
        })
    }
}
