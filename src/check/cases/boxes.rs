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

impl HitBoxCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "hit_box"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
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

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let HitBoxCase {
            min,
            max,
            origin,
            dir,
            t_min,
            t_max,
            expect,
        } = self;
        let got = C::hit_box(&Aabb::new(*min, *max), *origin, dir.recip(), *t_min, *t_max);
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
}

/// `hit_box` on `rays` rays from random origins aimed at random points
/// of the box's twelve edges (drawn from `seed`): whenever the exact
/// ray (the `f32` origin and direction, in `f64`) meets the box, the
/// answer must be a hit.
#[derive(Debug, Clone)]
pub struct BoxEdgesCase {
    pub min: Vec3,
    pub max: Vec3,
    pub rays: u32,
    pub seed: u64,
    /// Asks `hit_boxes`, the box in a lane that changes from ray to ray,
    /// rather than `hit_box`.
    pub four_at_once: bool,
}

impl BoxEdgesCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        if self.four_at_once {
            "hit_boxes"
        } else {
            "hit_box"
        }
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
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

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let BoxEdgesCase {
            min,
            max,
            rays,
            seed,
            four_at_once,
        } = self;
        box_edges::<C>(&Aabb::new(*min, *max), *rays, *seed, *four_at_once)
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

impl BvhBuildCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "build_bvh"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        let BvhBuildCase {
            shapes, options, ..
        } = self;
        format!(
            "build_bvh(the boxes of [{}], {})",
            shapes_text(shapes),
            options_text(options)
        )
    }

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let BvhBuildCase {
            shapes,
            options,
            expect,
        } = self;
        let bounds: Vec<Option<Aabb>> = shapes.iter().map(Shape::bounds).collect();
        let bvh = C::build_bvh(&bounds, options);
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
}

impl BvhHitsCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        match (self.wide, self.any) {
            (false, false) => "nearest_hit_bvh",
            (false, true) => "any_hit_bvh",
            (true, false) => "nearest_hit_wide",
            (true, true) => "any_hit_wide",
        }
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
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

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let BvhHitsCase {
            shapes,
            options,
            rays,
            t_min,
            t_max,
            any,
            wide,
        } = self;
        let (t_min, t_max, any) = (*t_min, *t_max, *any);
        let bounds: Vec<Option<Aabb>> = shapes.iter().map(Shape::bounds).collect();
        let bvh = C::build_bvh(&bounds, options);
        if *wide {
            let wide = C::collapse_bvh(&bvh, shapes);
            return bvh_hits::<C>(shapes, rays, t_min, t_max, any, |objects, ray| {
                if any {
                    C::any_hit_wide(&wide, objects, ray, t_min, t_max)
                } else {
                    C::nearest_hit_wide(&wide, objects, ray, t_min, t_max)
                }
            });
        }
        bvh_hits::<C>(shapes, rays, t_min, t_max, any, |objects, ray| {
            if any {
                C::any_hit_bvh(&bvh, objects, ray, t_min, t_max)
            } else {
                C::nearest_hit_bvh(&bvh, objects, ray, t_min, t_max)
            }
        })
    }
}
