//! Checkpoint cases as data, and how each is run against some chapters.
//!
//! A [`Case`] is one question to one function of the course, in the spirit
//! of The Ray Tracer Challenge's scenarios: its inputs, what is expected,
//! how close is close enough, and a sentence a student can check by hand.
//! [`Case::run`] asks the question of the chapters `C` and says whether the
//! answer is right, without ever letting a panic out.

mod inputs;
mod tree;

pub use inputs::{num, num64, vec};

use glam::{DVec3, Vec3};

use super::panics::{Panic, guarded};
use crate::bvh::{Aabb, Bvh, BvhOptions};
use crate::check::exact::{self, U, wide};
use crate::course::{Chapters, Hit, HitPoint, Objects, PhongTerms};
use crate::render::{Stage, Tracer};
use crate::shapes::{SurfacePoint, Triangle};
use crate::{Material, Plane, Ray, Reference, Sampling, Scene, Shape, Sphere};
use inputs::*;
use tree::*;

/// Which level a case belongs to: a checkpoint every correct formula meets,
/// or a hard case that only a numerically robust one does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Level {
    Checkpoint,
    Robustness,
}

/// Roundings allowed per formula in the robustness cases (the same bound as
/// tests/course/hard_cases.rs, where the largest ratio the reference reaches is
/// printed): `16 u` times the scale of the problem.
pub const ROUNDINGS: f64 = 16.0;

/// How far a checkpoint answer may be from the exact one, relative to
/// `max(1, |expected|)`. Checkpoints are well-conditioned: any correct `f32`
/// formula lands within a few `u = 6e-8` of the exact answer, in any order
/// of operations, so `1e-4` accepts them all and still rejects every wrong
/// formula (whose error is a visible fraction).
pub const CHECKPOINT_TOLERANCE: f64 = 1e-4;

/// What an intersection case expects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ExpectT {
    /// A hit at this `t` (exact).
    Hit(f64),
    Miss,
    /// Rounding decides (a tangent ray, an origin rounded onto the surface):
    /// either answer is right, but a hit must lie on the surface.
    Either,
}

/// Which shading function a scene case calls.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shading {
    /// Chapter 4's `shade_flat`.
    Flat,
    /// Chapter 5's `shade_phong`.
    Phong,
    /// Chapter 6's `shade_mirror`.
    Mirror,
    /// Chapter 8's `shade_glass`.
    Glass,
    /// Chapter 9's `shade_dielectric`.
    Dielectric,
}

impl Shading {
    fn stage(self) -> u8 {
        match self {
            Shading::Flat => 4,
            Shading::Phong => 5,
            Shading::Mirror => 6,
            Shading::Glass => 8,
            Shading::Dielectric => 9,
        }
    }
}

/// What a set of sample offsets must look like.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleRule {
    /// The centres of the `k x k` cells, in any order.
    GridCentres,
    /// Exactly one sample in each of the `k x k` cells, all inside `[0, 1)^2`.
    OnePerCell,
    /// Every sample inside `[0, 1)^2`, and not all at one point.
    InsidePixel,
    /// As `InsidePixel`, and not the same offsets as with this other seed:
    /// the seed changes the samples.
    UnlikeSeed(u64),
}

/// The question a case asks, one variant per kind of function.
#[derive(Debug, Clone)]
pub enum CaseKind {
    /// `intersect_plane(Plane::new(point, normal), ray, t_min, t_max)`.
    Plane {
        point: Vec3,
        normal: Vec3,
        ray: Ray,
        t_min: f32,
        t_max: f32,
        expect: ExpectT,
    },
    /// `intersect_sphere(Sphere::new(center, radius), ray, t_min, t_max)`.
    Sphere {
        center: Vec3,
        radius: f32,
        ray: Ray,
        t_min: f32,
        t_max: f32,
        expect: ExpectT,
    },
    /// `nearest_hit(shapes, ray, t_min, t_max)`: the object index and `t`.
    Nearest {
        shapes: Vec<Shape>,
        ray: Ray,
        t_min: f32,
        t_max: f32,
        expect: Option<(usize, f64)>,
    },
    /// `offset_origin(surface, dir)`: off the surface on `dir`'s side by at
    /// least the point's error bound `|n| . error`, and by at most
    /// `at_most` (scene units) at the checkpoint level or
    /// `ROUNDINGS` error bounds at the robustness level.
    Offset {
        surface: SurfacePoint,
        dir: Vec3,
        at_most: f64,
    },
    /// `in_shadow` at the points where each of `rays` meets object
    /// `object` of `scene` (TOML), for a light at `light`.
    Shadow {
        scene: String,
        object: usize,
        rays: Vec<Ray>,
        light: Vec3,
        expect: bool,
    },
    /// A shading function at the point where `ray` meets `scene` (TOML):
    /// expected, the reference chapters' answer on the same point.
    Shade {
        shading: Shading,
        scene: String,
        ray: Ray,
        /// Bounces so far (chapters 6 and 8).
        depth: u32,
    },
    /// `phong_terms(material, albedo, normal, to_light, to_eye, light)`.
    PhongTerms {
        material: Material,
        albedo: Vec3,
        normal: Vec3,
        to_light: Vec3,
        to_eye: Vec3,
        light: Vec3,
        expect: PhongTerms,
    },
    /// `reflect(d, n)`: expected the exact mirror image.
    Reflect { d: Vec3, n: Vec3 },
    /// `sample_offset(sampling, count, index, pixel, seed)` for every index
    /// and each pixel.
    SampleOffsets {
        sampling: Sampling,
        count: u32,
        pixels: Vec<(u32, u32)>,
        seed: u64,
        rule: SampleRule,
    },
    /// `pixel_color` of each pixel of `scene` (TOML, chapter 7's stage):
    /// expected the mean, in linear light, of the pixel's own samples (at
    /// the offsets `sample_offset` gives).
    PixelColor {
        scene: String,
        pixels: Vec<(u32, u32)>,
    },
    /// `refract(d, n, eta)`: expected the exact unit direction, or `None`.
    Refract { d: Vec3, n: Vec3, eta: f32 },
    /// `fresnel(cos_i, n1, n2)` (or `schlick`, when `schlick` is set):
    /// expected the `f64` value of the formula, within `1e-6` absolute, or
    /// NaN (for an index that is not a finite number > 0) when `expect` is.
    Reflectance {
        schlick: bool,
        cos_i: f32,
        n1: f32,
        n2: f32,
        expect: f64,
    },
    /// `transmittance(absorption, distance)`: expected `exp(-a d)` per
    /// channel, within `1e-6` relative.
    Transmittance { absorption: Vec3, distance: f32 },
    /// `intersect_triangle` on each of `triangles` (one, or a few sharing
    /// edges and corners): the nearest of their hits is judged, so a ray
    /// through a shared edge passes when at least one triangle claims it.
    Triangles {
        triangles: Vec<[Vec3; 3]>,
        ray: Ray,
        t_min: f32,
        t_max: f32,
        expect: ExpectT,
    },
    /// `barycentric(triangle, point)`: expected the exact weights (ratios
    /// of areas, in `f64`).
    Barycentric { corners: [Vec3; 3], point: Vec3 },
    /// `smooth_normal(triangle, normals, point)`: expected the exact unit
    /// blend.
    SmoothNormal {
        corners: [Vec3; 3],
        normals: [Vec3; 3],
        point: Vec3,
    },
    /// `terminator_point(triangle, normals, point)`: expected the exact
    /// lifted point.
    Terminator {
        corners: [Vec3; 3],
        normals: [Vec3; 3],
        point: Vec3,
    },
    /// `smooth_hit_point` at the point where `ray` meets the triangle (by
    /// the reference test), on a material that is opaque or fully
    /// transparent: expected the blended normal turned toward the ray, and
    /// the lifted point (the point itself when transparent).
    SmoothHit {
        corners: [Vec3; 3],
        normals: [Vec3; 3],
        ray: Ray,
        transparent: bool,
    },
    /// `hit_box(Aabb::new(min, max), origin, dir.recip(), t_min, t_max)`:
    /// expected the entry `t` (exact, `t_min` from inside), or no hit.
    HitBox {
        min: Vec3,
        max: Vec3,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
        expect: Option<f64>,
    },
    /// `hit_box` on `rays` rays from random origins aimed at random points
    /// of the box's twelve edges (drawn from `seed`): whenever the exact
    /// ray (the `f32` origin and direction, in `f64`) meets the box, the
    /// answer must be a hit.
    BoxEdges {
        min: Vec3,
        max: Vec3,
        rays: u32,
        seed: u64,
    },
    /// `build_bvh` over the boxes of `shapes` (`Shape::bounds`): the tree
    /// must hold every boxed object exactly once, under a leaf whose box
    /// holds it, each inner node's box holding its children's; objects
    /// without a box (planes) in `unbounded`, not in the tree.
    BvhBuild {
        shapes: Vec<Shape>,
        options: BvhOptions,
        /// What the lesson fixes about this tree's shape, beyond its being
        /// a valid tree.
        expect: TreeShape,
    },
    /// `build_bvh` over the boxes of `shapes`, then for each of `rays`
    /// `nearest_hit_bvh` (or `any_hit_bvh` when `any`) through that tree.
    /// Expected: chapter 3's nearest hit over the same objects, the same
    /// object at the same `t`, bit for bit; for any-hit, a hit exactly
    /// when there is one, and a real one (the object's own test gives
    /// that `t` in the interval).
    BvhHits {
        shapes: Vec<Shape>,
        options: BvhOptions,
        rays: Vec<Ray>,
        t_min: f32,
        t_max: f32,
        any: bool,
    },
}

/// What a `BvhBuild` case asks of the tree's shape, beyond its being valid.
/// Which child is called left is the student's choice, so a cut is
/// compared as a partition.
#[derive(Debug, Clone, PartialEq)]
pub enum TreeShape {
    /// Any valid tree.
    Any,
    /// The root is a leaf (it holds every boxed object), and its box is
    /// theirs, padded by a few epsilons.
    RootLeaf,
    /// The root is cut in two, one child holding exactly the objects of
    /// one of these lists (each a cut the lesson's rules may give) and the
    /// other the rest of the boxed ones; its box is theirs, padded by a few
    /// epsilons.
    RootCut(Vec<Vec<u32>>),
    /// Either the root is a leaf, as for `RootLeaf`, or it is cut as one of
    /// these lists says, as for `RootCut`: the SAH's leaf, or the cut of a
    /// build that always cuts at the middle.
    RootLeafOrCut(Vec<Vec<u32>>),
}

/// One checkpoint: a question, its expected answer and its tolerance, with
/// the sentence that says it and the lesson section that teaches it.
#[derive(Debug, Clone)]
pub struct Case {
    /// A short stable name (`sphere-direction-not-unit`), for tests and logs.
    pub name: &'static str,
    /// The case in words, with its numbers: what a student reproduces by hand.
    pub says: String,
    /// The heading of the lesson section that teaches it.
    pub section: &'static str,
    pub level: Level,
    pub kind: CaseKind,
}

/// How a case went.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    Pass,
    Fail {
        expected: String,
        got: String,
    },
    /// The code panicked with `todo!()`: a function not written yet.
    Todo(Panic),
    /// The code panicked otherwise.
    Panicked(Panic),
    /// The check itself could not run (a bug in raylab, not the student's).
    Error(String),
}

impl Case {
    pub fn new(
        name: &'static str,
        section: &'static str,
        says: impl Into<String>,
        kind: CaseKind,
    ) -> Case {
        Case {
            name,
            says: says.into(),
            section,
            level: Level::Checkpoint,
            kind,
        }
    }

    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        match &self.kind {
            CaseKind::Plane { .. } => "intersect_plane",
            CaseKind::Sphere { .. } => "intersect_sphere",
            CaseKind::Nearest { .. } => "nearest_hit",
            CaseKind::Offset { .. } => "offset_origin",
            CaseKind::Shadow { .. } => "in_shadow",
            CaseKind::Shade { shading, .. } => match shading {
                Shading::Flat => "shade_flat",
                Shading::Phong => "shade_phong",
                Shading::Mirror => "shade_mirror",
                Shading::Glass => "shade_glass",
                Shading::Dielectric => "shade_dielectric",
            },
            CaseKind::PhongTerms { .. } => "phong_terms",
            CaseKind::Reflect { .. } => "reflect",
            CaseKind::SampleOffsets { .. } => "sample_offset",
            CaseKind::PixelColor { .. } => "pixel_color",
            CaseKind::Refract { .. } => "refract",
            CaseKind::Reflectance { schlick: false, .. } => "fresnel",
            CaseKind::Reflectance { schlick: true, .. } => "schlick",
            CaseKind::Transmittance { .. } => "transmittance",
            CaseKind::Triangles { .. } => "intersect_triangle",
            CaseKind::Barycentric { .. } => "barycentric",
            CaseKind::SmoothNormal { .. } => "smooth_normal",
            CaseKind::Terminator { .. } => "terminator_point",
            CaseKind::SmoothHit { .. } => "smooth_hit_point",
            CaseKind::HitBox { .. } | CaseKind::BoxEdges { .. } => "hit_box",
            CaseKind::BvhBuild { .. } => "build_bvh",
            CaseKind::BvhHits { any: false, .. } => "nearest_hit_bvh",
            CaseKind::BvhHits { any: true, .. } => "any_hit_bvh",
        }
    }

    /// Asks the question of the chapters `C`.
    pub fn run<C: Chapters>(&self) -> Outcome {
        match guarded(|| self.evaluate::<C>()) {
            Ok(outcome) => outcome,
            Err(panic) if panic.is_todo() => Outcome::Todo(panic),
            Err(panic) => Outcome::Panicked(panic),
        }
    }

    fn evaluate<C: Chapters>(&self) -> Outcome {
        let robust = self.level == Level::Robustness;
        match &self.kind {
            CaseKind::Plane {
                point,
                normal,
                ray,
                t_min,
                t_max,
                expect,
            } => {
                let plane = Plane::new(*point, *normal);
                let got = C::intersect_plane(&plane, ray, *t_min, *t_max);
                let scale = max_abs(wide(*point));
                let on_surface =
                    |p: DVec3| (p - wide(plane.point())).dot(wide(plane.normal())).abs();
                judge_t(
                    got,
                    *expect,
                    ray,
                    robust,
                    scale,
                    wide(plane.normal()),
                    on_surface,
                )
            }
            CaseKind::Sphere {
                center,
                radius,
                ray,
                t_min,
                t_max,
                expect,
            } => {
                let sphere = Sphere::new(*center, *radius);
                let got = C::intersect_sphere(&sphere, ray, *t_min, *t_max);
                let c = wide(*center);
                let r = f64::from(*radius);
                let scale = max_abs(c) + r;
                let normal_at = match expect {
                    ExpectT::Hit(t) => {
                        exact::sphere_normal(c, r, wide(ray.origin), wide(ray.dir), *t)
                    }
                    _ => DVec3::Y,
                };
                let on_surface = |p: DVec3| ((p - c).length() - r).abs();
                judge_t(got, *expect, ray, robust, scale, normal_at, on_surface)
            }
            CaseKind::Nearest {
                shapes,
                ray,
                t_min,
                t_max,
                expect,
            } => {
                let got = C::nearest_hit(&crate::Objects::<C>::new(shapes), ray, *t_min, *t_max);
                let show = |hit: Option<(usize, f64)>| match hit {
                    Some((object, t)) => format!("object {object} at t = {}", num64(t)),
                    None => "no hit".into(),
                };
                let got_pair = got.map(|hit| (hit.object, f64::from(hit.t)));
                let pass = match (got_pair, *expect) {
                    (None, None) => true,
                    (Some((object, t)), Some((want, t_ref))) => {
                        object == want && close(t, t_ref, CHECKPOINT_TOLERANCE)
                    }
                    _ => false,
                };
                verdict(pass, show(*expect), show(got_pair))
            }
            CaseKind::Offset {
                surface,
                dir,
                at_most,
            } => {
                let got = C::offset_origin(surface, *dir);
                let n = wide(surface.normal);
                let bound = n.abs().dot(wide(surface.error));
                let side = if wide(*dir).dot(n) >= 0.0 { 1.0 } else { -1.0 };
                let push = side * (wide(got) - wide(surface.point)).dot(n);
                let limit = if robust {
                    ROUNDINGS * bound + 4.0 * 2.0 * U * max_abs(wide(surface.point))
                } else {
                    *at_most
                };
                // 0.99: the bound itself is computed in f32 by the reference,
                // a few u below its exact value.
                let pass = got.is_finite() && push > 0.0 && push >= 0.99 * bound && push <= limit;
                verdict(
                    pass,
                    format!(
                        "an origin {} the surface (dir side) by at least {} and at most {}",
                        if side > 0.0 { "above" } else { "below" },
                        num64(bound),
                        num64(limit)
                    ),
                    format!(
                        "{}, {} the surface by {}",
                        vec(got),
                        if push >= 0.0 {
                            "on the dir side of"
                        } else {
                            "on the WRONG side of"
                        },
                        num64(push.abs())
                    ),
                )
            }
            CaseKind::Shadow {
                scene,
                object,
                rays,
                light,
                expect,
            } => {
                let scene = match parse(scene) {
                    Ok(scene) => scene,
                    Err(error) => return Outcome::Error(error),
                };
                let stage = match Stage::<C>::with_chapters(&scene, 4, scene.render) {
                    Ok(stage) => stage,
                    Err(error) => return Outcome::Error(error.to_string()),
                };
                let mut tracer = stage.tracer(None);
                for (index, ray) in rays.iter().enumerate() {
                    let point = match point_on(&scene, &tracer, *object, ray) {
                        Ok(point) => point,
                        Err(error) => return Outcome::Error(error),
                    };
                    let got = C::in_shadow(&mut tracer, &point, *light);
                    if got != *expect {
                        let word = |shadow: bool| if shadow { "in shadow" } else { "lit" };
                        return Outcome::Fail {
                            expected: format!("{} at every point", word(*expect)),
                            got: format!(
                                "{} at {} (ray {} of {}: {})",
                                word(got),
                                vec(point.surface.point),
                                index + 1,
                                rays.len(),
                                ray_text(ray)
                            ),
                        };
                    }
                }
                Outcome::Pass
            }
            CaseKind::Shade {
                shading,
                scene,
                ray,
                depth,
            } => shade::<C>(*shading, scene, ray, *depth),
            CaseKind::PhongTerms {
                material,
                albedo,
                normal,
                to_light,
                to_eye,
                light,
                expect,
            } => {
                let got = C::phong_terms(material, *albedo, *normal, *to_light, *to_eye, *light);
                let pass = colour_close(got.diffuse, expect.diffuse)
                    && colour_close(got.specular, expect.specular);
                verdict(pass, terms_text(expect), terms_text(&got))
            }
            CaseKind::Reflect { d, n } => {
                let got = C::reflect(*d, *n);
                let expected = exact::reflect(wide(*d), wide(*n));
                if !expected.is_finite() {
                    // A zero or non-finite normal has no mirror: the answer
                    // must not look like a direction.
                    return verdict(
                        got.is_nan(),
                        "a NaN component (no mirror without a normal)".into(),
                        vec(got),
                    );
                }
                let g = wide(got);
                let pass = got.is_finite()
                    && if robust {
                        // Direction and length apart, as tests/course/hard_cases.rs.
                        let length = expected.length();
                        exact::angle(g, expected) <= ROUNDINGS * U
                            && (g.length() - length).abs() <= ROUNDINGS * U * length
                    } else {
                        (g - expected).length() <= CHECKPOINT_TOLERANCE * expected.length()
                    };
                verdict(pass, vec64(expected), vec(got))
            }
            CaseKind::SampleOffsets {
                sampling,
                count,
                pixels,
                seed,
                rule,
            } => {
                for pixel in pixels {
                    let offsets_with = |seed: u64| -> Vec<(f32, f32)> {
                        (0..*count)
                            .map(|index| C::sample_offset(*sampling, *count, index, *pixel, seed))
                            .collect()
                    };
                    let offsets = offsets_with(*seed);
                    let mut verdict = sample_rule(*rule, *count, &offsets);
                    if let (Ok(()), SampleRule::UnlikeSeed(other)) = (&verdict, rule) {
                        if offsets_with(*other) == offsets {
                            verdict = Err(format!("the same offsets as with seed {other}"));
                        }
                    }
                    if let Err(problem) = verdict {
                        return Outcome::Fail {
                            expected: rule_text(*rule, *count),
                            got: format!(
                                "pixel {pixel:?}: {problem}; offsets {}",
                                offsets
                                    .iter()
                                    .take(16)
                                    .map(|(x, y)| format!("({}, {})", num(*x), num(*y)))
                                    .collect::<Vec<_>>()
                                    .join(" ")
                            ),
                        };
                    }
                }
                Outcome::Pass
            }
            CaseKind::PixelColor { scene, pixels } => {
                let scene = match parse(scene) {
                    Ok(scene) => scene,
                    Err(error) => return Outcome::Error(error),
                };
                let stage = match Stage::<C>::with_chapters(&scene, 7, scene.render) {
                    Ok(stage) => stage,
                    Err(error) => return Outcome::Error(error.to_string()),
                };
                let mut tracer = stage.tracer(None);
                for &(x, y) in pixels {
                    let samples = tracer.samples();
                    let mut colours = Vec::new();
                    for index in 0..samples {
                        let (dx, dy) = tracer.sample_offset(index, (x, y));
                        colours.push(tracer.sample(x as f32 + dx, y as f32 + dy));
                    }
                    let mean = colours.iter().copied().sum::<Vec3>() / samples.max(1) as f32;
                    let got = C::pixel_color(&mut tracer, x, y);
                    if !colour_close(got, mean) {
                        return Outcome::Fail {
                            expected: format!(
                                "pixel ({x}, {y}): {} = the mean of its samples {}",
                                vec(mean),
                                colours
                                    .iter()
                                    .map(|c| vec(*c))
                                    .collect::<Vec<_>>()
                                    .join(" ")
                            ),
                            got: vec(got),
                        };
                    }
                }
                Outcome::Pass
            }
            CaseKind::Refract { d, n, eta } => {
                let got = C::refract(*d, *n, *eta);
                let expected = if eta.is_finite() && *eta > 0.0 {
                    exact::refract(wide(*d), wide(*n), f64::from(*eta)).filter(|t| t.is_finite())
                } else {
                    None
                };
                let show =
                    |t: Option<String>| t.unwrap_or_else(|| "None (no refracted ray)".into());
                match (expected, got) {
                    (None, None) => Outcome::Pass,
                    (Some(want), Some(t)) => {
                        let d64 = wide(*d).normalize();
                        let n64 = wide(*n).normalize();
                        let cos_i = d64.dot(n64).abs();
                        let cos_t = want.dot(n64).abs();
                        let tolerance = if robust {
                            ROUNDINGS * U * (1.0 + f64::from(*eta) * cos_i / cos_t.max(1e-300))
                        } else {
                            CHECKPOINT_TOLERANCE
                        };
                        let t64 = wide(t);
                        let unit = (t64.length() - 1.0).abs() <= tolerance.max(ROUNDINGS * U);
                        let pass = t.is_finite() && unit && exact::angle(t64, want) <= tolerance;
                        verdict(
                            pass,
                            format!("Some({}) (unit length)", vec64(want)),
                            format!("Some({}) (length {})", vec(t), num64(t64.length())),
                        )
                    }
                    (want, t) => Outcome::Fail {
                        expected: show(want.map(|w| format!("Some({})", vec64(w)))),
                        got: show(t.map(|t| format!("Some({})", vec(t)))),
                    },
                }
            }
            CaseKind::Reflectance {
                schlick,
                cos_i,
                n1,
                n2,
                expect,
            } => {
                let got = if *schlick {
                    C::schlick(*cos_i, *n1, *n2)
                } else {
                    C::fresnel(*cos_i, *n1, *n2)
                };
                // A reflectance is a share in [0, 1]: 1e-6 absolute is a few
                // f32 roundings of it, far below what any image shows.
                // An expected NaN is the answer to an invalid index: only NaN
                // passes.
                let pass = if expect.is_nan() {
                    got.is_nan()
                } else {
                    (f64::from(got) - expect).abs() <= 1e-6
                };
                verdict(pass, num64(*expect), num(got))
            }
            CaseKind::Transmittance {
                absorption,
                distance,
            } => {
                let got = C::transmittance(*absorption, *distance);
                let want = wide(*absorption).map(|a| {
                    if a == 0.0 {
                        1.0
                    } else {
                        (-a * f64::from(*distance)).exp()
                    }
                });
                let pass = got.is_finite()
                    && (wide(got) - want)
                        .abs()
                        .cmple(want.abs() * 1e-6 + DVec3::splat(1e-30))
                        .all();
                verdict(pass, vec64(want), vec(got))
            }
            CaseKind::Triangles {
                triangles,
                ray,
                t_min,
                t_max,
                expect,
            } => {
                let hits: Vec<(usize, f32)> = triangles
                    .iter()
                    .enumerate()
                    .filter_map(|(index, &[a, b, c])| {
                        C::intersect_triangle(&Triangle::new(a, b, c), ray, *t_min, *t_max)
                            .map(|t| (index, t))
                    })
                    .collect();
                // A NaN or infinite t is wrong however it compares: it is
                // the one judged, never hidden behind a finite hit.
                let nearest = hits
                    .iter()
                    .copied()
                    .find(|(_, t)| !t.is_finite())
                    .or_else(|| hits.iter().copied().min_by(|x, y| x.1.total_cmp(&y.1)));
                let judged = triangles[nearest.map_or(0, |(index, _)| index)].map(wide);
                let normal = (judged[1] - judged[0])
                    .cross(judged[2] - judged[0])
                    .normalize();
                let on_surface = |p: DVec3| (p - judged[0]).dot(normal).abs();
                let scale = triangles
                    .iter()
                    .flatten()
                    .map(|corner| max_abs(wide(*corner)))
                    .fold(0.0, f64::max);
                judge_t(
                    nearest.map(|(_, t)| t),
                    *expect,
                    ray,
                    robust,
                    scale,
                    normal,
                    on_surface,
                )
            }
            CaseKind::Barycentric { corners, point } => {
                let [a, b, c] = *corners;
                let got = C::barycentric(&Triangle::new(a, b, c), *point);
                let want = exact::barycentric(corners.map(wide), wide(*point));
                // Weights of a point inside are at most 1: an absolute
                // tolerance is a relative one.
                let pass = got.is_finite()
                    && (wide(got) - want).abs().max_element()
                        <= CHECKPOINT_TOLERANCE * max_abs(want).max(1.0);
                verdict(pass, vec64(want), vec(got))
            }
            CaseKind::SmoothNormal {
                corners,
                normals,
                point,
            } => {
                let [a, b, c] = *corners;
                let got = C::smooth_normal(&Triangle::new(a, b, c), normals, *point);
                let want = exact::smooth_normal(corners.map(wide), normals.map(wide), wide(*point));
                verdict(
                    unit_toward(got, want),
                    format!("{} (unit length)", vec64(want)),
                    format!("{} (length {})", vec(got), num64(wide(got).length())),
                )
            }
            CaseKind::Terminator {
                corners,
                normals,
                point,
            } => {
                let [a, b, c] = *corners;
                let got = C::terminator_point(&Triangle::new(a, b, c), normals, *point);
                let want =
                    exact::terminator_point(corners.map(wide), normals.map(wide), wide(*point));
                verdict(point_close(got, want), vec64(want), vec(got))
            }
            CaseKind::SmoothHit {
                corners,
                normals,
                ray,
                transparent,
            } => {
                let [a, b, c] = *corners;
                let triangle = Triangle::new(a, b, c);
                let shape = Shape::Triangle(triangle);
                // The point comes from the reference test: the case's input
                // does not depend on the code under check.
                let Some(t) = shape.intersect(ray, 0.0, f32::INFINITY) else {
                    return Outcome::Error(format!(
                        "the case's ray {} misses its triangle",
                        ray_text(ray)
                    ));
                };
                let material = Material {
                    transparency: if *transparent { 1.0 } else { 0.0 },
                    ..Material::default()
                };
                let point = HitPoint::new(0, &shape, &material, ray, t);
                let got = C::smooth_hit_point(point, &triangle, normals);
                // The vertex normals turned to the side the ray came from.
                let outward: DVec3 = normals.iter().map(|n| wide(*n)).sum();
                let side = if outward.dot(-wide(ray.dir)) < 0.0 {
                    -1.0
                } else {
                    1.0
                };
                let facing = normals.map(|n| side * wide(n));
                let at = wide(point.surface.point);
                let want_normal = exact::smooth_normal(corners.map(wide), facing, at);
                let want_point = if *transparent {
                    at
                } else {
                    exact::terminator_point(corners.map(wide), facing, at)
                };
                let pass = unit_toward(got.normal, want_normal)
                    && point_close(got.surface.point, want_point);
                verdict(
                    pass,
                    format!(
                        "normal {} (unit length), point {}",
                        vec64(want_normal),
                        vec64(want_point)
                    ),
                    format!(
                        "normal {} (length {}), point {}",
                        vec(got.normal),
                        num64(wide(got.normal).length()),
                        vec(got.surface.point)
                    ),
                )
            }
            CaseKind::HitBox {
                min,
                max,
                origin,
                dir,
                t_min,
                t_max,
                expect,
            } => {
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
            CaseKind::BoxEdges {
                min,
                max,
                rays,
                seed,
            } => box_edges::<C>(&Aabb::new(*min, *max), *rays, *seed),
            CaseKind::BvhBuild {
                shapes,
                options,
                expect,
            } => {
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
            CaseKind::BvhHits {
                shapes,
                options,
                rays,
                t_min,
                t_max,
                any,
            } => {
                let bounds: Vec<Option<Aabb>> = shapes.iter().map(Shape::bounds).collect();
                let bvh = C::build_bvh(&bounds, options);
                bvh_hits::<C>(shapes, &bvh, rays, *t_min, *t_max, *any)
            }
        }
    }
}

/// Whether `got` is a unit vector along `want` (unit), within the
/// checkpoint tolerance in length and in angle.
fn unit_toward(got: Vec3, want: DVec3) -> bool {
    let g = wide(got);
    got.is_finite()
        && (g.length() - 1.0).abs() <= CHECKPOINT_TOLERANCE
        && exact::angle(g, want) <= CHECKPOINT_TOLERANCE
}

/// Whether the point `got` is `want` within the checkpoint tolerance,
/// relative to the size of its coordinates.
fn point_close(got: Vec3, want: DVec3) -> bool {
    got.is_finite()
        && (wide(got) - want).abs().max_element() <= CHECKPOINT_TOLERANCE * max_abs(want).max(1.0)
}

fn verdict(pass: bool, expected: String, got: String) -> Outcome {
    if pass {
        Outcome::Pass
    } else {
        Outcome::Fail { expected, got }
    }
}

/// Judges an intersection answer `got` against `expect` (see the module
/// docs of tests/course/hard_cases.rs for the robustness bound).
fn judge_t(
    got: Option<f32>,
    expect: ExpectT,
    ray: &Ray,
    robust: bool,
    shape_scale: f64,
    normal: DVec3,
    distance_to_surface: impl Fn(DVec3) -> f64,
) -> Outcome {
    let (o, d) = (wide(ray.origin), wide(ray.dir));
    let show_expected = match expect {
        ExpectT::Hit(t) => format!("t = {}", num64(t)),
        ExpectT::Miss => "no hit (None)".into(),
        ExpectT::Either => "either no hit or a hit on the surface".into(),
    };
    let show_got = match got {
        Some(t) => format!("t = {}", num(t)),
        None => "no hit (None)".into(),
    };
    let scale_at = |t: f64| max_abs(o) + shape_scale + max_abs(o + t * d);
    let pass = match (expect, got) {
        (_, Some(t)) if !t.is_finite() => false,
        (ExpectT::Miss | ExpectT::Either, None) => true,
        (ExpectT::Miss, Some(_)) | (ExpectT::Hit(_), None) => false,
        (ExpectT::Either, Some(t)) => {
            let t = f64::from(t);
            distance_to_surface(o + t * d) <= ROUNDINGS * U * scale_at(t)
        }
        (ExpectT::Hit(t_ref), Some(t)) => {
            let t = f64::from(t);
            if robust {
                let cos = (d.dot(normal) / (d.length() * normal.length())).abs();
                let unit = U * (t_ref.abs() + scale_at(t_ref) / (d.length() * cos));
                (t - t_ref).abs() <= ROUNDINGS * unit
            } else {
                close(t, t_ref, CHECKPOINT_TOLERANCE)
            }
        }
    };
    verdict(pass, show_expected, show_got)
}

fn close(got: f64, want: f64, tolerance: f64) -> bool {
    (got - want).abs() <= tolerance * want.abs().max(1.0)
}

/// Colours agree within `1e-4` (about a third of an 8-bit level in the
/// darkest sRGB codes): far above any rounding, far below any wrong term.
fn colour_close(got: Vec3, want: Vec3) -> bool {
    got.is_finite()
        && (wide(got) - wide(want))
            .abs()
            .cmple(DVec3::splat(CHECKPOINT_TOLERANCE) * wide(want).abs().max(DVec3::ONE))
            .all()
}

fn parse(text: &str) -> Result<Scene, String> {
    Scene::parse(text, "a checkpoint's scene").map_err(|error| error.to_string())
}

/// The point where `ray` meets object `object`, by the reference tests (the
/// case's inputs do not depend on the code under check).
fn point_on<'a, C: Chapters>(
    scene: &Scene,
    tracer: &Tracer<'a, C>,
    object: usize,
    ray: &Ray,
) -> Result<HitPoint<'a>, String> {
    match crate::nearest_hit(&scene.shapes, ray, 0.0, f32::INFINITY) {
        Some(hit) if hit.object == object => Ok(tracer.hit_point(object, ray, hit.t)),
        other => Err(format!(
            "the case's ray {} should meet object {object} first, but meets {other:?}",
            ray_text(ray)
        )),
    }
}

fn shade<C: Chapters>(shading: Shading, scene: &str, ray: &Ray, depth: u32) -> Outcome {
    let scene = match parse(scene) {
        Ok(scene) => scene,
        Err(error) => return Outcome::Error(error),
    };
    let chapter = shading.stage();
    let (stage, reference) = match (
        Stage::<C>::with_chapters(&scene, chapter, scene.render),
        Stage::<Reference>::with_chapters(&scene, chapter, scene.render),
    ) {
        (Ok(stage), Ok(reference)) => (stage, reference),
        (Err(error), _) | (_, Err(error)) => return Outcome::Error(error.to_string()),
    };
    let mut tracer = stage.tracer(None);
    let mut reference_tracer = reference.tracer(None);
    let point = match point_on(&scene, &tracer, 0, ray) {
        Ok(point) => point,
        Err(error) => return Outcome::Error(error),
    };
    // The expected colour: raylab's own chapters on the same point. The
    // case's sentence gives the same number by hand.
    let (got, expected) = match shading {
        Shading::Flat => (
            vec![C::shade_flat(&mut tracer, &point)],
            vec![Reference::shade_flat(&mut reference_tracer, &point)],
        ),
        Shading::Phong => {
            let got = C::shade_phong(&mut tracer, &point);
            let want = Reference::shade_phong(&mut reference_tracer, &point);
            (
                vec![got.diffuse, got.specular],
                vec![want.diffuse, want.specular],
            )
        }
        Shading::Mirror => (
            vec![C::shade_mirror(&mut tracer, &point, depth, 1.0)],
            vec![Reference::shade_mirror(
                &mut reference_tracer,
                &point,
                depth,
                1.0,
            )],
        ),
        Shading::Glass => (
            vec![C::shade_glass(&mut tracer, &point, depth, 1.0)],
            vec![Reference::shade_glass(
                &mut reference_tracer,
                &point,
                depth,
                1.0,
            )],
        ),
        Shading::Dielectric => (
            vec![C::shade_dielectric(&mut tracer, &point, depth, 1.0)],
            vec![Reference::shade_dielectric(
                &mut reference_tracer,
                &point,
                depth,
                1.0,
            )],
        ),
    };
    let pass = got.iter().zip(&expected).all(|(g, w)| colour_close(*g, *w));
    let show = |colours: &[Vec3]| {
        if shading == Shading::Phong {
            format!("diffuse {}, specular {}", vec(colours[0]), vec(colours[1]))
        } else {
            vec(colours[0])
        }
    };
    verdict(pass, show(&expected), show(&got))
}

fn sample_rule(rule: SampleRule, count: u32, offsets: &[(f32, f32)]) -> Result<(), String> {
    let inside = |v: f32| (0.0..1.0).contains(&v);
    if let Some((x, y)) = offsets.iter().find(|(x, y)| !inside(*x) || !inside(*y)) {
        return Err(format!(
            "({}, {}) is outside [0, 1)^2 (1.0 is the next pixel's edge)",
            num(*x),
            num(*y)
        ));
    }
    let k = count.isqrt().max(1);
    let cell_of = |(x, y): (f32, f32)| {
        let column = ((x * k as f32) as u32).min(k - 1);
        let row = ((y * k as f32) as u32).min(k - 1);
        row * k + column
    };
    match rule {
        SampleRule::GridCentres => {
            for &(x, y) in offsets {
                let centre = |v: f32| ((v * k as f32).floor() + 0.5) / k as f32;
                if (x - centre(x)).abs() > 1e-5 || (y - centre(y)).abs() > 1e-5 {
                    return Err(format!(
                        "({}, {}) is not the centre of a cell",
                        num(x),
                        num(y)
                    ));
                }
            }
            one_per_cell(k, offsets, cell_of)
        }
        SampleRule::OnePerCell => one_per_cell(k, offsets, cell_of),
        SampleRule::InsidePixel | SampleRule::UnlikeSeed(_) => {
            if offsets.len() > 1 && offsets.iter().all(|o| *o == offsets[0]) {
                Err("every sample is at the same point".into())
            } else {
                Ok(())
            }
        }
    }
}

fn one_per_cell(
    k: u32,
    offsets: &[(f32, f32)],
    cell_of: impl Fn((f32, f32)) -> u32,
) -> Result<(), String> {
    let mut seen = vec![0u32; (k * k) as usize];
    for &offset in offsets {
        seen[cell_of(offset) as usize] += 1;
    }
    match seen.iter().position(|&n| n != 1) {
        None => Ok(()),
        Some(cell) => Err(format!(
            "cell (column {}, row {}) of the {k} x {k} grid has {} samples",
            cell as u32 % k,
            cell as u32 / k,
            seen[cell]
        )),
    }
}

fn rule_text(rule: SampleRule, count: u32) -> String {
    let k = count.isqrt().max(1);
    match rule {
        SampleRule::GridCentres => {
            format!("the {count} centres of a {k} x {k} grid of cells, one each")
        }
        SampleRule::OnePerCell => {
            format!("one sample in each cell of a {k} x {k} grid, inside [0, 1)^2")
        }
        SampleRule::InsidePixel => "samples inside [0, 1)^2, not all at one point".into(),
        SampleRule::UnlikeSeed(other) => {
            format!("samples inside [0, 1)^2, not all at one point, not those of seed {other}")
        }
    }
}

fn terms_text(terms: &PhongTerms) -> String {
    format!(
        "diffuse {}, specular {}",
        vec(terms.diffuse),
        vec(terms.specular)
    )
}

fn max_abs(v: DVec3) -> f64 {
    v.abs().max_element()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_like_a_student_writes_them() {
        assert_eq!(num(0.0), "0");
        assert_eq!(num(-5.0), "-5");
        assert_eq!(num(0.5), "0.5");
        assert_eq!(num(1e20), "1e20");
        assert_eq!(num(f32::INFINITY), "inf");
        assert_eq!(vec(Vec3::new(0.0, 1.0, -5.0)), "(0, 1, -5)");
    }
}
