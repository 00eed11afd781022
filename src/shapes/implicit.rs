//! Surfaces given only by a function: a small tree of primitives and
//! operations whose function `f(p)` is zero on the surface, positive
//! outside and negative inside. How a ray meets one (sphere tracing,
//! Newton's method) is chapter 12's lesson; this file holds the functions
//! and the facts a tracer needs about them: a Lipschitz constant (how fast
//! `f` can change), whether `f` is the exact distance, and a box around the
//! surface.
//!
//! The formulas of the primitives are the exact signed distances of Inigo
//! Quilez's "distance functions" article; the operations are his too (the
//! smooth union is his quadratic `smin`). Hart's "Sphere tracing" (1996) is
//! where the Lipschitz constants come from: a function with
//! `|f(p) - f(q)| <= L |p - q|` is at most `L` times the distance to its
//! zero set, so a step of `f(p) / L` never crosses the surface.

use super::bounds::Aabb;
use crate::{Ray, Vec3};

/// The deepest tree a scene may give: deeper trees cost a call per level at
/// every step of every ray, and nothing a scene shows needs more.
pub const MAX_DEPTH: usize = 16;

/// The most nodes a tree may have: every step of a ray evaluates them all.
pub const MAX_NODES: usize = 256;

/// A node of a surface's tree.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Sdf {
    /// Every point at `radius` from `center`.
    Sphere { center: Vec3, radius: f32 },
    /// The axis-aligned box of `center` and half sizes `half_size`.
    Box { center: Vec3, half_size: Vec3 },
    /// The same box with its edges and corners rounded by `radius`
    /// (`radius` at most the smallest half size: the box keeps its size).
    RoundBox {
        center: Vec3,
        half_size: Vec3,
        radius: f32,
    },
    /// The ring around the vertical (y) axis through `center`: points at
    /// `minor` from the circle of radius `major` in the plane `y = center.y`.
    Torus {
        center: Vec3,
        major: f32,
        minor: f32,
    },
    /// Points within `radius` of the segment from `a` to `b`.
    Capsule { a: Vec3, b: Vec3, radius: f32 },
    /// The half space below the plane through `point` with unit `normal`.
    Plane { point: Vec3, normal: Vec3 },
    /// Inside any of the shapes: the smallest of their functions.
    Union(Vec<Sdf>),
    /// Inside all of the shapes: the largest of their functions.
    Intersection(Vec<Sdf>),
    /// Inside the first shape and outside the second.
    Difference(Box<Sdf>, Box<Sdf>),
    /// A union whose seams are rounded over a width of about `blend`.
    SmoothUnion {
        shapes: (Box<Sdf>, Box<Sdf>),
        blend: f32,
    },
    /// The shape moved by `offset`.
    Translate { offset: Vec3, shape: Box<Sdf> },
    /// The shape turned by `rotation` about the origin.
    Rotate {
        rotation: glam::Quat,
        shape: Box<Sdf>,
    },
    /// The shape's function plus `amplitude sin(fx) sin(fy) sin(fz)` with
    /// `f = frequency`: a bumpy surface with no distance formula.
    Displace {
        amplitude: f32,
        frequency: f32,
        shape: Box<Sdf>,
    },
}

/// What a tree's function says about the distance to its surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Exactness {
    /// `f(p)` is the signed distance to the surface.
    Exact,
    /// The signed distance outside the surface, a bound inside (a union).
    ExactOutside,
    /// Only `|f(p)| / L <= distance`, with `L` the Lipschitz constant.
    Bound,
}

/// Why a tree cannot be a surface.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ImplicitError {
    #[error("{what} must be a positive finite number (got {value})")]
    NotPositive { what: &'static str, value: f32 },
    #[error("{what} must be finite (got {value})")]
    NotFinite { what: &'static str, value: String },
    #[error("{what} must be at most {most} (got {value})")]
    TooLarge {
        what: &'static str,
        most: f32,
        value: f32,
    },
    #[error("{what} must not be zero")]
    Zero { what: &'static str },
    #[error("{operation} needs at least one shape")]
    Empty { operation: &'static str },
    #[error("the tree is deeper than {MAX_DEPTH} levels")]
    TooDeep,
    #[error("the tree has more than {MAX_NODES} nodes")]
    TooManyNodes,
}

impl Sdf {
    /// The same shape scaled by `factor` about the origin: every length
    /// of the tree (centres, sizes, radii, offsets, the blend and the
    /// bumps' amplitude) times `factor`, the bumps' frequency divided by
    /// it. With a power of two, every operation of [`Sdf::distance`]
    /// scales exactly, so the function at `factor p` is exactly `factor`
    /// times the original's at `p`: the same surface, to the last bit,
    /// at another size (the checker's fresh inputs use this).
    pub fn scaled(&self, factor: f32) -> Sdf {
        let boxed = |shape: &Sdf| Box::new(shape.scaled(factor));
        match self {
            Sdf::Sphere { center, radius } => Sdf::Sphere {
                center: *center * factor,
                radius: radius * factor,
            },
            Sdf::Box { center, half_size } => Sdf::Box {
                center: *center * factor,
                half_size: *half_size * factor,
            },
            Sdf::RoundBox {
                center,
                half_size,
                radius,
            } => Sdf::RoundBox {
                center: *center * factor,
                half_size: *half_size * factor,
                radius: radius * factor,
            },
            Sdf::Torus {
                center,
                major,
                minor,
            } => Sdf::Torus {
                center: *center * factor,
                major: major * factor,
                minor: minor * factor,
            },
            Sdf::Capsule { a, b, radius } => Sdf::Capsule {
                a: *a * factor,
                b: *b * factor,
                radius: radius * factor,
            },
            Sdf::Plane { point, normal } => Sdf::Plane {
                point: *point * factor,
                normal: *normal,
            },
            Sdf::Union(shapes) => Sdf::Union(shapes.iter().map(|s| s.scaled(factor)).collect()),
            Sdf::Intersection(shapes) => {
                Sdf::Intersection(shapes.iter().map(|s| s.scaled(factor)).collect())
            }
            Sdf::Difference(kept, removed) => Sdf::Difference(boxed(kept), boxed(removed)),
            Sdf::SmoothUnion {
                shapes: (first, second),
                blend,
            } => Sdf::SmoothUnion {
                shapes: (boxed(first), boxed(second)),
                blend: blend * factor,
            },
            Sdf::Translate { offset, shape } => Sdf::Translate {
                offset: *offset * factor,
                shape: boxed(shape),
            },
            Sdf::Rotate { rotation, shape } => Sdf::Rotate {
                rotation: *rotation,
                shape: boxed(shape),
            },
            Sdf::Displace {
                amplitude,
                frequency,
                shape,
            } => Sdf::Displace {
                amplitude: amplitude * factor,
                frequency: frequency / factor,
                shape: boxed(shape),
            },
        }
    }

    /// The tree's function at `point`.
    pub fn distance(&self, point: Vec3) -> f32 {
        match self {
            Sdf::Sphere { center, radius } => (point - *center).length() - radius,
            Sdf::Box { center, half_size } => box_distance(point - *center, *half_size),
            Sdf::RoundBox {
                center,
                half_size,
                radius,
            } => box_distance(point - *center, *half_size - Vec3::splat(*radius)) - radius,
            Sdf::Torus {
                center,
                major,
                minor,
            } => {
                let local = point - *center;
                let from_ring = glam::Vec2::new(local.x, local.z).length() - major;
                glam::Vec2::new(from_ring, local.y).length() - minor
            }
            Sdf::Capsule { a, b, radius } => {
                let along = *b - *a;
                let share = ((point - *a).dot(along) / along.length_squared()).clamp(0.0, 1.0);
                (point - (*a + along * share)).length() - radius
            }
            Sdf::Plane {
                point: on_plane,
                normal,
            } => (point - *on_plane).dot(*normal),
            Sdf::Union(shapes) => shapes
                .iter()
                .map(|shape| shape.distance(point))
                .fold(f32::INFINITY, f32::min),
            Sdf::Intersection(shapes) => shapes
                .iter()
                .map(|shape| shape.distance(point))
                .fold(f32::NEG_INFINITY, f32::max),
            Sdf::Difference(kept, removed) => kept.distance(point).max(-removed.distance(point)),
            Sdf::SmoothUnion {
                shapes: (first, second),
                blend,
            } => {
                let (a, b) = (first.distance(point), second.distance(point));
                let share = smooth_share(a, b, *blend);
                b + (a - b) * share - blend * share * (1.0 - share)
            }
            Sdf::Translate { offset, shape } => shape.distance(point - *offset),
            Sdf::Rotate { rotation, shape } => shape.distance(rotation.inverse() * point),
            Sdf::Displace {
                amplitude,
                frequency,
                shape,
            } => shape.distance(point) + amplitude * bumps(point * *frequency),
        }
    }

    /// The gradient of [`Sdf::distance`] at `point`, from the formulas
    /// (where a function has a kink, such as a box's edge or where two
    /// shapes of a union meet, the gradient of the side `point` is on).
    pub fn gradient(&self, point: Vec3) -> Vec3 {
        match self {
            Sdf::Sphere { center, .. } => (point - *center).normalize_or_zero(),
            Sdf::Box { center, half_size } => box_gradient(point - *center, *half_size),
            Sdf::RoundBox {
                center,
                half_size,
                radius,
            } => box_gradient(point - *center, *half_size - Vec3::splat(*radius)),
            Sdf::Torus { center, major, .. } => {
                let local = point - *center;
                let flat = glam::Vec2::new(local.x, local.z);
                let ring = flat.normalize_or_zero() * *major;
                (local - Vec3::new(ring.x, 0.0, ring.y)).normalize_or_zero()
            }
            Sdf::Capsule { a, b, .. } => {
                let along = *b - *a;
                let share = ((point - *a).dot(along) / along.length_squared()).clamp(0.0, 1.0);
                (point - (*a + along * share)).normalize_or_zero()
            }
            Sdf::Plane { normal, .. } => *normal,
            Sdf::Union(shapes) => {
                nearest_by(shapes, point, f32::lt).map_or(Vec3::NAN, |shape| shape.gradient(point))
            }
            Sdf::Intersection(shapes) => {
                nearest_by(shapes, point, f32::gt).map_or(Vec3::NAN, |shape| shape.gradient(point))
            }
            Sdf::Difference(kept, removed) => {
                if kept.distance(point) >= -removed.distance(point) {
                    kept.gradient(point)
                } else {
                    -removed.gradient(point)
                }
            }
            Sdf::SmoothUnion {
                shapes: (first, second),
                blend,
            } => {
                // d/dp of b + (a - b) h - k h (1 - h): the terms in dh
                // cancel, since a - b = k (1 - 2h) where 0 < h < 1, which
                // leaves the blend of the two gradients.
                let share = smooth_share(first.distance(point), second.distance(point), *blend);
                first.gradient(point) * share + second.gradient(point) * (1.0 - share)
            }
            Sdf::Translate { offset, shape } => shape.gradient(point - *offset),
            Sdf::Rotate { rotation, shape } => {
                *rotation * shape.gradient(rotation.inverse() * point)
            }
            Sdf::Displace {
                amplitude,
                frequency,
                shape,
            } => {
                let scaled = point * *frequency;
                let (sin, cos) = (
                    Vec3::new(scaled.x.sin(), scaled.y.sin(), scaled.z.sin()),
                    Vec3::new(scaled.x.cos(), scaled.y.cos(), scaled.z.cos()),
                );
                let bumps = Vec3::new(
                    cos.x * sin.y * sin.z,
                    sin.x * cos.y * sin.z,
                    sin.x * sin.y * cos.z,
                );
                shape.gradient(point) + bumps * (amplitude * frequency)
            }
        }
    }

    /// A bound `L` on how fast the function changes, `|f(p) - f(q)| <= L
    /// |p - q|`: a ray may step `f(p) / L` without crossing the surface.
    pub fn lipschitz(&self) -> f32 {
        match self {
            // Exact distances change by at most the distance moved.
            Sdf::Sphere { .. }
            | Sdf::Box { .. }
            | Sdf::RoundBox { .. }
            | Sdf::Torus { .. }
            | Sdf::Capsule { .. }
            | Sdf::Plane { .. } => 1.0,
            // The smallest or largest of functions changes no faster than
            // the fastest of them.
            Sdf::Union(shapes) | Sdf::Intersection(shapes) => {
                shapes.iter().map(Sdf::lipschitz).fold(0.0, f32::max)
            }
            Sdf::Difference(kept, removed) => kept.lipschitz().max(removed.lipschitz()),
            // Its gradient is h grad a + (1 - h) grad b (see `gradient`), a
            // weighted mean of the two: no longer than the longer.
            Sdf::SmoothUnion {
                shapes: (first, second),
                ..
            } => first.lipschitz().max(second.lipschitz()),
            // Moving and turning keep distances.
            Sdf::Translate { shape, .. } | Sdf::Rotate { shape, .. } => shape.lipschitz(),
            // The bumps' gradient is A w (cos x sin y sin z, ...), whose
            // squared length over A w is at most 1 (its largest value,
            // ab + bc + ca - 3abc for squared sines a, b, c in [0, 1], is
            // reached at a = b = 1, c = 0): L grows by A w.
            Sdf::Displace {
                amplitude,
                frequency,
                shape,
            } => shape.lipschitz() + amplitude * frequency,
        }
    }

    /// Whether the function is the distance to the surface, or only a
    /// bound of it.
    pub fn exactness(&self) -> Exactness {
        match self {
            Sdf::Sphere { .. }
            | Sdf::Box { .. }
            | Sdf::RoundBox { .. }
            | Sdf::Torus { .. }
            | Sdf::Capsule { .. }
            | Sdf::Plane { .. } => Exactness::Exact,
            Sdf::Translate { shape, .. } | Sdf::Rotate { shape, .. } => shape.exactness(),
            // Outside, the nearest point of the union is the nearest point
            // of the nearest shape; inside, the surface may be farther than
            // the nearest shape's own (inside the overlap of two).
            Sdf::Union(shapes) => {
                if shapes
                    .iter()
                    .all(|shape| shape.exactness() != Exactness::Bound)
                {
                    Exactness::ExactOutside
                } else {
                    Exactness::Bound
                }
            }
            Sdf::Intersection(_)
            | Sdf::Difference(..)
            | Sdf::SmoothUnion { .. }
            | Sdf::Displace { .. } => Exactness::Bound,
        }
    }

    /// A box the surface and its inside lie in, `None` for a surface no
    /// box holds (one with a plane in a union). Outside the box the
    /// function is at least the distance to the box, which is what lets a
    /// smooth union and a displacement grow their children's boxes by
    /// their own reach (see the arms).
    pub fn bounds(&self) -> Option<Aabb> {
        match self {
            Sdf::Sphere { center, radius } => Some(around(*center, Vec3::splat(*radius))),
            Sdf::Box { center, half_size }
            | Sdf::RoundBox {
                center, half_size, ..
            } => Some(around(*center, *half_size)),
            Sdf::Torus {
                center,
                major,
                minor,
            } => Some(around(
                *center,
                Vec3::new(major + minor, *minor, major + minor),
            )),
            Sdf::Capsule { a, b, radius } => {
                let reach = Vec3::splat(*radius);
                Some(Aabb::new(a.min(*b) - reach, a.max(*b) + reach))
            }
            Sdf::Plane { .. } => None,
            Sdf::Union(shapes) => shapes.iter().try_fold(Aabb::EMPTY, |hull, shape| {
                shape.bounds().map(|bounds| hull.union(bounds))
            }),
            // max(f_a, f_b) is at least each of them, hence at least the
            // distance to either box: the smaller box will do.
            Sdf::Intersection(shapes) => shapes
                .iter()
                .filter_map(Sdf::bounds)
                .min_by(|one, other| volume(one).total_cmp(&volume(other))),
            Sdf::Difference(kept, _) => kept.bounds(),
            // smin(a, b) >= min(a, b) - k/4 (h (1 - h) <= 1/4).
            Sdf::SmoothUnion {
                shapes: (first, second),
                blend,
            } => Some(grown(first.bounds()?.union(second.bounds()?), blend / 4.0)),
            Sdf::Translate { offset, shape } => shape
                .bounds()
                .map(|bounds| Aabb::new(bounds.min + *offset, bounds.max + *offset)),
            Sdf::Rotate { rotation, shape } => shape.bounds().map(|bounds| {
                corners(&bounds)
                    .into_iter()
                    .map(|corner| *rotation * corner)
                    .fold(Aabb::EMPTY, Aabb::grow)
            }),
            // The bumps lower the function by at most the amplitude.
            Sdf::Displace {
                amplitude, shape, ..
            } => shape.bounds().map(|bounds| grown(bounds, *amplitude)),
        }
    }

    /// Checks what a scene could get wrong: sizes that are not positive
    /// and finite, a rounding larger than its box, an empty operation, a
    /// zero normal or axis, a tree too deep or too large.
    pub fn check(&self) -> Result<(), ImplicitError> {
        let mut nodes = 0;
        self.check_node(1, &mut nodes)
    }

    fn check_node(&self, depth: usize, nodes: &mut usize) -> Result<(), ImplicitError> {
        *nodes += 1;
        if depth > MAX_DEPTH {
            return Err(ImplicitError::TooDeep);
        }
        if *nodes > MAX_NODES {
            return Err(ImplicitError::TooManyNodes);
        }
        let positive = |what: &'static str, value: f32| {
            if value > 0.0 && value.is_finite() {
                Ok(())
            } else {
                Err(ImplicitError::NotPositive { what, value })
            }
        };
        let finite = |what: &'static str, value: Vec3| {
            if value.is_finite() {
                Ok(())
            } else {
                Err(ImplicitError::NotFinite {
                    what,
                    value: format!("{value}"),
                })
            }
        };
        let children: Vec<&Sdf> = match self {
            Sdf::Sphere { center, radius } => {
                finite("a sphere's center", *center)?;
                positive("a sphere's radius", *radius)?;
                vec![]
            }
            Sdf::Box { center, half_size } => {
                finite("a box's center", *center)?;
                for size in half_size.to_array() {
                    positive("a box's half size", size)?;
                }
                vec![]
            }
            Sdf::RoundBox {
                center,
                half_size,
                radius,
            } => {
                finite("a rounded box's center", *center)?;
                for size in half_size.to_array() {
                    positive("a rounded box's half size", size)?;
                }
                positive("a rounded box's radius", *radius)?;
                let most = half_size.min_element();
                if *radius > most {
                    return Err(ImplicitError::TooLarge {
                        what: "a rounded box's radius (its smallest half size)",
                        most,
                        value: *radius,
                    });
                }
                vec![]
            }
            Sdf::Torus {
                center,
                major,
                minor,
            } => {
                finite("a torus's center", *center)?;
                positive("a torus's major radius", *major)?;
                positive("a torus's minor radius", *minor)?;
                vec![]
            }
            Sdf::Capsule { a, b, radius } => {
                finite("a capsule's end a", *a)?;
                finite("a capsule's end b", *b)?;
                positive("a capsule's radius", *radius)?;
                if !((*b - *a).length_squared() > 0.0) {
                    return Err(ImplicitError::Zero {
                        what: "a capsule's length (a and b are the same point)",
                    });
                }
                vec![]
            }
            Sdf::Plane { point, normal } => {
                finite("a plane's point", *point)?;
                finite("a plane's normal", *normal)?;
                if !((normal.length() - 1.0).abs() < 1e-3) {
                    return Err(ImplicitError::Zero {
                        what: "a plane's normal's length minus 1 (give a unit normal)",
                    });
                }
                vec![]
            }
            Sdf::Union(shapes) | Sdf::Intersection(shapes) => {
                if shapes.is_empty() {
                    return Err(ImplicitError::Empty {
                        operation: if matches!(self, Sdf::Union(_)) {
                            "a union"
                        } else {
                            "an intersection"
                        },
                    });
                }
                shapes.iter().collect()
            }
            Sdf::Difference(kept, removed) => vec![kept, removed],
            Sdf::SmoothUnion {
                shapes: (first, second),
                blend,
            } => {
                positive("a smooth union's blend", *blend)?;
                vec![first, second]
            }
            Sdf::Translate { offset, shape } => {
                finite("a translation's offset", *offset)?;
                vec![shape]
            }
            Sdf::Rotate { rotation, shape } => {
                if !rotation.is_finite() {
                    return Err(ImplicitError::NotFinite {
                        what: "a rotation",
                        value: format!("{rotation}"),
                    });
                }
                vec![shape]
            }
            Sdf::Displace {
                amplitude,
                frequency,
                shape,
            } => {
                positive("a displacement's amplitude", *amplitude)?;
                positive("a displacement's frequency", *frequency)?;
                vec![shape]
            }
        };
        for child in children {
            child.check_node(depth + 1, nodes)?;
        }
        Ok(())
    }
}

/// How a ray marches against an implicit surface: the knobs of chapter
/// 12, set from the render settings ([`crate::scene::RenderSettings`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct March {
    /// A point counts as on the surface when its function is below this
    /// fraction of its distance along the ray (a cone of that half angle:
    /// far points need no more precision than a pixel shows).
    pub tolerance: f32,
    /// Evaluations of the function a march may spend before it gives up.
    pub max_steps: u32,
    /// Each step is `relaxation` times the safe one (over-relaxation,
    /// 1 to 2), with a fall back to safe steps once two spheres fail to
    /// overlap.
    pub relaxation: f32,
    /// Whether the march divides by the tree's Lipschitz constant, or
    /// trusts the function as a distance (`lipschitz = "one"`, to show the
    /// holes that makes).
    pub lipschitz: LipschitzRule,
    /// Whether a hit is refined by Newton's method inside a bracket.
    pub newton: bool,
    /// How the normal is found.
    pub normal: NormalMethod,
    /// The step `h` of the finite differences, in the scene's units.
    pub normal_step: f32,
}

impl Default for March {
    fn default() -> March {
        March {
            tolerance: 1e-4,
            max_steps: 256,
            relaxation: 1.0,
            lipschitz: LipschitzRule::Bound,
            newton: true,
            normal: NormalMethod::Analytic,
            normal_step: 1e-3,
        }
    }
}

/// Which constant a march divides its steps by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LipschitzRule {
    /// The tree's own bound ([`Sdf::lipschitz`]): no step crosses the surface.
    #[default]
    Bound,
    /// 1, as if every function were a distance: wrong for a displacement.
    One,
}

/// How an implicit surface's normal is found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum NormalMethod {
    /// The gradient from the tree's formulas ([`Sdf::gradient`]).
    #[default]
    Analytic,
    /// Central differences along each axis: 6 evaluations.
    Central,
    /// Differences along the four corners of a tetrahedron: 4 evaluations.
    Tetrahedron,
}

/// An implicit surface as a scene holds it: its tree (shared, since every
/// stage copies the scene's shapes), the facts a march needs about it, and
/// the march's settings.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(into = "WireImplicit", try_from = "WireImplicit")]
pub struct Implicit {
    tree: std::sync::Arc<Sdf>,
    lipschitz: f32,
    bounds: Option<Aabb>,
    exactness: Exactness,
    march: March,
}

/// An [`Implicit`] as it is written down: its tree and its march's
/// settings (the rest is worked out from the tree again when it is read).
#[derive(serde::Serialize, serde::Deserialize)]
struct WireImplicit {
    tree: Sdf,
    march: March,
}

impl From<Implicit> for WireImplicit {
    fn from(surface: Implicit) -> WireImplicit {
        WireImplicit {
            tree: (*surface.tree).clone(),
            march: surface.march,
        }
    }
}

impl TryFrom<WireImplicit> for Implicit {
    type Error = ImplicitError;
    fn try_from(wire: WireImplicit) -> Result<Implicit, ImplicitError> {
        Implicit::new(wire.tree).map(|surface| surface.with_march(wire.march))
    }
}

impl Implicit {
    /// The surface of `tree`, once [`Sdf::check`] accepts it.
    pub fn new(tree: Sdf) -> Result<Implicit, ImplicitError> {
        tree.check()?;
        Ok(Implicit {
            lipschitz: tree.lipschitz(),
            bounds: tree.bounds(),
            exactness: tree.exactness(),
            tree: std::sync::Arc::new(tree),
            march: March::default(),
        })
    }

    /// The same surface marched with `march`.
    pub fn with_march(&self, march: March) -> Implicit {
        Implicit {
            march,
            ..self.clone()
        }
    }

    pub fn tree(&self) -> &Sdf {
        &self.tree
    }

    /// The nodes of its tree: what one evaluation of the function costs.
    pub fn nodes(&self) -> usize {
        let mut nodes = 0;
        // A surface's tree passed this check when it was made, so it
        // counts every node.
        let _ = self.tree.check_node(1, &mut nodes);
        nodes
    }

    pub fn march(&self) -> &March {
        &self.march
    }

    /// The function at `point`. Each call is one evaluation in the stats
    /// ([`evaluations`]).
    #[inline]
    pub fn distance(&self, point: Vec3) -> f32 {
        counters::evaluated();
        self.tree.distance(point)
    }

    /// The gradient from the tree's formulas (not counted: no evaluation
    /// of the function).
    pub fn gradient(&self, point: Vec3) -> Vec3 {
        self.tree.gradient(point)
    }

    /// The constant a march divides by: the tree's bound, or 1 under
    /// [`LipschitzRule::One`].
    pub fn lipschitz(&self) -> f32 {
        match self.march.lipschitz {
            LipschitzRule::Bound => self.lipschitz,
            LipschitzRule::One => 1.0,
        }
    }

    /// The tree's own bound, whatever the march uses.
    pub fn lipschitz_bound(&self) -> f32 {
        self.lipschitz
    }

    pub fn exactness(&self) -> Exactness {
        self.exactness
    }

    /// A box the surface lies in; `None` when no box holds it.
    pub fn bounds(&self) -> Option<Aabb> {
        self.bounds
    }

    /// The part of `t_min < t < t_max` where `ray` is inside the
    /// surface's box (all of it when there is no box), or `None` when the
    /// ray misses the box: outside it the function is at least the
    /// distance to the box, so a march needs only this span. The box is
    /// padded by `8 epsilon` of its largest coordinate and the span
    /// widened by as much of its ends, far more than the rounding of the
    /// slab test, so no surface point is cut off.
    pub fn span(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, f32)> {
        let Some(bounds) = self.bounds else {
            return Some((t_min, t_max));
        };
        let margin = 8.0 * f32::EPSILON;
        let pad = margin * bounds.min.abs().max(bounds.max.abs()).max_element();
        let (low, high) = (bounds.min - Vec3::splat(pad), bounds.max + Vec3::splat(pad));
        let (mut enter, mut leave) = (t_min, t_max);
        for axis in 0..3 {
            let inverse = 1.0 / ray.dir[axis];
            let near = (low[axis] - ray.origin[axis]) * inverse;
            let far = (high[axis] - ray.origin[axis]) * inverse;
            // A NaN slab (a zero direction on a slab's plane) is skipped by
            // `max` and `min`, as chapter 11's test does.
            enter = enter.max(near.min(far));
            leave = leave.min(near.max(far));
        }
        // A ray parallel to a slab and outside it has an infinite end,
        // which the widening below would turn into NaN (inf - inf), and
        // NaN into the whole ray.
        if !(enter <= leave) || !enter.is_finite() {
            return None;
        }
        let enter = (enter - margin * enter.abs()).max(t_min);
        let leave = (leave + margin * leave.abs()).min(t_max);
        (enter <= leave).then_some((enter, leave))
    }
}

/// An interval of a ray's parameter known to hold a root of a function
/// along it: the function's values at `low` and `high` differ in sign (or
/// one of them is zero). Chapter 12's Newton iteration never leaves it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bracket {
    pub low: f32,
    pub high: f32,
}

pub use counters::{
    Counted, MarchHistogram, evaluations, limit_evaluations, march_ended, march_histogram,
};

/// How many times this thread evaluated an implicit function: the stats'
/// figure, read before and after a piece of work (a row of pixels is one
/// thread's, so the counts never mix between threads).
mod counters {
    use std::cell::Cell;

    thread_local! {
        static EVALUATIONS: Cell<u64> = const { Cell::new(0) };
        static LIMIT: Cell<u64> = const { Cell::new(u64::MAX) };
        static MARCHES: Cell<MarchHistogram> = const { Cell::new(MarchHistogram::EMPTY) };
    }

    /// Marches counted by how many evaluations each made, in powers of
    /// two: bucket 0 is the marches that made none (the ray missed the
    /// surface's box), bucket `k` those with `2^(k-1)` to `2^k - 1`, and
    /// the last one everything from `2^(BUCKETS - 2)` on. Where a render's
    /// steps go: the grazing rays of a silhouette are its tail.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub struct MarchHistogram {
        pub counts: [u64; MarchHistogram::BUCKETS],
    }

    impl MarchHistogram {
        /// Up to 512 and more: past the default budget of 256 steps.
        pub const BUCKETS: usize = 11;
        const EMPTY: MarchHistogram = MarchHistogram {
            counts: [0; MarchHistogram::BUCKETS],
        };

        /// The bucket of a march that made `evaluations` evaluations.
        pub fn bucket(evaluations: u64) -> usize {
            let bits = (u64::BITS - evaluations.leading_zeros()) as usize;
            bits.min(Self::BUCKETS - 1)
        }

        /// The evaluations bucket `bucket` holds: from, and up to
        /// (inclusive; `None` for the last, open bucket).
        pub fn range(bucket: usize) -> (u64, Option<u64>) {
            match bucket {
                0 => (0, Some(0)),
                last if last >= Self::BUCKETS - 1 => (1 << (last - 1), None),
                _ => (1 << (bucket - 1), Some((1 << bucket) - 1)),
            }
        }

        /// All the marches counted.
        pub fn marches(&self) -> u64 {
            self.counts.iter().sum()
        }

        /// The marches counted here and not in `earlier`.
        pub fn since(&self, earlier: &MarchHistogram) -> MarchHistogram {
            MarchHistogram {
                counts: std::array::from_fn(|bucket| {
                    self.counts[bucket].saturating_sub(earlier.counts[bucket])
                }),
            }
        }

        /// Both histograms' marches.
        pub fn add(&self, other: &MarchHistogram) -> MarchHistogram {
            MarchHistogram {
                counts: std::array::from_fn(|bucket| self.counts[bucket] + other.counts[bucket]),
            }
        }
    }

    /// The marches this thread made so far, by their evaluations.
    pub fn march_histogram() -> MarchHistogram {
        MARCHES.with(Cell::get)
    }

    /// One more ray marched, with the evaluations it made (the shapes'
    /// intersection calls it, once per ray and surface).
    #[inline]
    pub fn march_ended(evaluations: u64) {
        MARCHES.with(|histogram| {
            let mut counts = histogram.get();
            counts.counts[MarchHistogram::bucket(evaluations)] += 1;
            histogram.set(counts);
        });
    }

    /// Evaluations made on this thread so far.
    pub fn evaluations() -> u64 {
        EVALUATIONS.with(Cell::get)
    }

    #[inline]
    pub(super) fn evaluated() {
        let count = EVALUATIONS.with(|count| {
            let next = count.get() + 1;
            count.set(next);
            next
        });
        if count > LIMIT.with(Cell::get) {
            // A check's budget: a march that never stops must end, and the
            // check's panic guard turns this into a verdict.
            LIMIT.with(|limit| limit.set(u64::MAX));
            panic!(
                "the march did not stop: more than {} evaluations of the function in one call \
                 (a loop needs a step budget and must stop past t_max)",
                super::CHECK_EVALUATION_LIMIT
            );
        }
    }

    /// Until the guard is dropped, more than `limit` evaluations on this
    /// thread panic (a check runs a student's march under it).
    pub fn limit_evaluations(limit: u64) -> Counted {
        let start = evaluations();
        LIMIT.with(|cell| cell.set(start.saturating_add(limit)));
        Counted { start }
    }

    /// The evaluations made since it was made; lifts the limit when dropped.
    pub struct Counted {
        start: u64,
    }

    impl Counted {
        pub fn count(&self) -> u64 {
            evaluations() - self.start
        }
    }

    impl Drop for Counted {
        fn drop(&mut self) {
            LIMIT.with(|limit| limit.set(u64::MAX));
        }
    }
}

/// The evaluations a check lets one call make: far more than any budget
/// a scene may set ([`MAX_MARCH_STEPS`]) times the few a normal takes.
pub const CHECK_EVALUATION_LIMIT: u64 = 1_000_000;

/// The largest step budget a scene may set.
pub const MAX_MARCH_STEPS: u32 = 100_000;

/// Quilez's exact box distance for a point `local` to the box's centre.
fn box_distance(local: Vec3, half_size: Vec3) -> f32 {
    let beyond = local.abs() - half_size;
    beyond.max(Vec3::ZERO).length() + beyond.max_element().min(0.0)
}

/// The gradient of [`box_distance`]: outside, towards the nearest point of
/// the box; inside, the normal of the nearest face.
fn box_gradient(local: Vec3, half_size: Vec3) -> Vec3 {
    let beyond = local.abs() - half_size;
    let sign = local.signum();
    if beyond.max_element() > 0.0 {
        (beyond.max(Vec3::ZERO) * sign).normalize_or_zero()
    } else {
        let axis = beyond.max_position();
        let mut face = Vec3::ZERO;
        face[axis] = sign[axis];
        face
    }
}

/// The weight `h` of the first shape in a smooth union of functions `a`
/// and `b`: 1 where `a` is below `b` by `blend` or more, 0 where above by
/// as much, linear between.
fn smooth_share(a: f32, b: f32, blend: f32) -> f32 {
    (0.5 + 0.5 * (b - a) / blend).clamp(0.0, 1.0)
}

/// `sin x sin y sin z`, in `[-1, 1]`.
fn bumps(point: Vec3) -> f32 {
    point.x.sin() * point.y.sin() * point.z.sin()
}

/// The shape whose function at `point` wins by `better` (the smallest for
/// a union, the largest for an intersection); `None` for no shapes.
fn nearest_by(shapes: &[Sdf], point: Vec3, better: fn(&f32, &f32) -> bool) -> Option<&Sdf> {
    let (first, rest) = shapes.split_first()?;
    let mut best = (first, first.distance(point));
    for shape in rest {
        let value = shape.distance(point);
        if better(&value, &best.1) {
            best = (shape, value);
        }
    }
    Some(best.0)
}

fn volume(bounds: &Aabb) -> f32 {
    (bounds.max - bounds.min).max(Vec3::ZERO).element_product()
}

fn around(center: Vec3, reach: Vec3) -> Aabb {
    Aabb::new(center - reach, center + reach)
}

fn grown(bounds: Aabb, by: f32) -> Aabb {
    Aabb::new(bounds.min - Vec3::splat(by), bounds.max + Vec3::splat(by))
}

fn corners(bounds: &Aabb) -> [Vec3; 8] {
    let (low, high) = (bounds.min, bounds.max);
    std::array::from_fn(|index| {
        Vec3::new(
            if index & 1 == 0 { low.x } else { high.x },
            if index & 2 == 0 { low.y } else { high.y },
            if index & 4 == 0 { low.z } else { high.z },
        )
    })
}

#[cfg(test)]
mod tests;
