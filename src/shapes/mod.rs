//! The primitives a scene is made of.
//!
//! Each shape has its own file with its data; this file is the one place
//! that lists them. Adding a shape is a new file and one variant here, with
//! its arm in each `match` below; the compiler then names the few other
//! places that must learn it, all outside the renderer: the Embree
//! cross-check (`crosscheck`, which hands each shape to Embree and knows its
//! rounding error), `raylab probe`, and the checker's descriptions.
//! How a ray meets each shape is a chapter's lesson, which is why
//! [`Shape::intersect_with`] asks the running course (the `Chapters`
//! trait) rather than the shape itself.

mod bounds;
mod implicit;
mod plane;
mod sphere;
mod triangle;

pub use bounds::Aabb;
/// The deepest tree an implicit surface may have.
pub use implicit::MAX_DEPTH as MAX_IMPLICIT_DEPTH;
pub use implicit::{
    Bracket, CHECK_EVALUATION_LIMIT, Counted, Exactness, Implicit, ImplicitError, LipschitzRule,
    MAX_MARCH_STEPS, March, MarchHistogram, NormalMethod, Sdf, evaluations, limit_evaluations,
    march_ended, march_histogram,
};
pub use plane::Plane;
pub use sphere::Sphere;
pub use triangle::Triangle;

use crate::{Ray, Vec3, unit_vector};

/// A primitive the tracer can intersect.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Shape {
    Plane(Plane),
    Sphere(Sphere),
    Triangle(Triangle),
    /// Boxed: a surface's tree and march settings would make every shape
    /// (a mesh's millions of triangles) as large as itself.
    Implicit(Box<Implicit>),
}

/// How many `f32::EPSILON`s (each `2u`, `u = 2^-24`) of the coordinates
/// involved we allow as error in a hit point after it is projected back onto
/// its surface. The projection takes a handful of roundings (a difference, a
/// normalisation, a product, a sum), each adding at most `u` of the
/// magnitudes it touches; `4 * EPSILON = 8u` bounds them with margin.
pub const SURFACE_ERROR_EPSILONS: f32 = 4.0;

/// A point on a surface, known well enough to start a new ray from.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SurfacePoint {
    /// The hit point, projected back onto the surface.
    pub point: Vec3,
    /// The geometric unit normal: outward for spheres, as given for planes,
    /// by the winding for triangles.
    pub normal: Vec3,
    /// A bound on the absolute error of each coordinate of `point`.
    pub error: Vec3,
}

impl Shape {
    /// The smallest axis-aligned box around the shape, `None` for a shape
    /// no box holds (a plane): chapter 11 keeps those outside its tree.
    pub fn bounds(&self) -> Option<Aabb> {
        match self {
            Shape::Plane(_) => None,
            Shape::Sphere(sphere) => {
                let reach = Vec3::splat(sphere.radius());
                Some(Aabb::new(sphere.center() - reach, sphere.center() + reach))
            }
            Shape::Triangle(triangle) => {
                let [a, b, c] = triangle.corners();
                Some(Aabb::new(a.min(b).min(c), a.max(b).max(c)))
            }
            Shape::Implicit(surface) => surface.bounds(),
        }
    }

    pub fn is_sphere(&self) -> bool {
        matches!(self, Shape::Sphere(_))
    }

    pub fn is_triangle(&self) -> bool {
        matches!(self, Shape::Triangle(_))
    }

    /// The triangle, when this shape is one.
    pub fn as_triangle(&self) -> Option<&Triangle> {
        match self {
            Shape::Triangle(triangle) => Some(triangle),
            Shape::Plane(_) | Shape::Sphere(_) | Shape::Implicit(_) => None,
        }
    }

    /// The sphere, when this shape is one.
    pub fn as_sphere(&self) -> Option<&Sphere> {
        match self {
            Shape::Sphere(sphere) => Some(sphere),
            Shape::Plane(_) | Shape::Triangle(_) | Shape::Implicit(_) => None,
        }
    }

    /// The implicit surface, when this shape is one.
    pub fn as_implicit(&self) -> Option<&Implicit> {
        match self {
            Shape::Implicit(surface) => Some(surface),
            Shape::Plane(_) | Shape::Sphere(_) | Shape::Triangle(_) => None,
        }
    }

    /// Coordinates in which a checker pattern is laid out: the plane's own 2D
    /// coordinates, the 3D offset from a sphere's centre, or the point itself
    /// on a triangle.
    pub fn pattern_coordinates(&self, point: Vec3) -> Vec3 {
        match self {
            Shape::Plane(plane) => {
                let (u, v) = plane.axes();
                let local = point - plane.point();
                Vec3::new(local.dot(u), local.dot(v), 0.0)
            }
            Shape::Sphere(sphere) => point - sphere.center(),
            // A mesh is laid out in the scene's own coordinates, so that the
            // squares run on across its triangles.
            Shape::Triangle(_) | Shape::Implicit(_) => point,
        }
    }

    /// The surface point where `ray` meets this shape at parameter `t`.
    ///
    /// `ray.at(t)` carries the error of `t`, which grows with the length of
    /// the ray: a hit 1000 units away can be off the surface by a visible
    /// fraction of a unit. Projecting it back onto the exact surface leaves an
    /// error that only depends on the size of the surface's own coordinates,
    /// and that we can bound (chapter 4 starts new rays from it).
    pub fn surface_point(&self, ray: &Ray, t: f32) -> SurfacePoint {
        let on_ray = ray.at(t);
        let scale = SURFACE_ERROR_EPSILONS * f32::EPSILON;
        match self {
            Shape::Sphere(sphere) => {
                let center = sphere.center();
                let radius = sphere.radius();
                // A ray that hits a sphere exactly at its centre cannot exist
                // (the centre is inside), so this is only non-finite input:
                // it stays NaN rather than becoming a plausible point.
                let normal = unit_vector(on_ray - center).unwrap_or(Vec3::NAN);
                let point = center + radius * normal;
                SurfacePoint {
                    point,
                    normal,
                    error: scale * (center.abs() + Vec3::splat(radius)),
                }
            }
            Shape::Plane(plane) => {
                let normal = plane.normal();
                let point = on_ray - normal * (on_ray - plane.point()).dot(normal);
                // The projection's dot product mixes all three coordinates, so
                // the bound uses the largest of them for every axis.
                let magnitude = point.abs().max_element() + plane.point().abs().max_element();
                SurfacePoint {
                    point,
                    normal,
                    error: Vec3::splat(scale * magnitude),
                }
            }
            Shape::Triangle(triangle) => {
                // As for a plane: the triangle's plane, through corner `a`.
                let normal = triangle.geometric_normal();
                let a = triangle.a();
                let point = on_ray - normal * (on_ray - a).dot(normal);
                let magnitude = point.abs().max_element() + a.abs().max_element();
                SurfacePoint {
                    point,
                    normal,
                    error: Vec3::splat(scale * magnitude),
                }
            }
            Shape::Implicit(surface) => implicit_surface_point(surface, on_ray, scale),
        }
    }
}

/// The point of an implicit surface near `on_ray`: one Newton step in
/// space, `p - f(p) grad f / |grad f|^2`, moves it onto the surface to
/// first order. What is left is bounded by the function there: `|f| / L`
/// is at most the distance to the surface only for an exact distance, so
/// the bound takes `|f|` itself times a margin of 2 for the bounds' slack,
/// plus the rounding of the coordinates. The normal is the tree's
/// gradient; chapter 12 replaces it with the chosen method's.
fn implicit_surface_point(surface: &Implicit, on_ray: Vec3, scale: f32) -> SurfacePoint {
    let gradient = surface.gradient(on_ray);
    let value = surface.tree().distance(on_ray);
    let length_squared = gradient.length_squared();
    let point = if length_squared > 0.0 && value.is_finite() {
        on_ray - gradient * (value / length_squared)
    } else {
        on_ray
    };
    let residual = surface.tree().distance(point).abs();
    let residual = if residual.is_finite() {
        residual
    } else {
        f32::INFINITY
    };
    SurfacePoint {
        point,
        normal: unit_vector(gradient).unwrap_or(Vec3::NAN),
        error: Vec3::splat(2.0 * residual + scale * (point.abs().max_element() + 1.0)),
    }
}

/// The surface point where `ray` meets `shape` at parameter `t`
/// ([`Shape::surface_point`]).
pub fn surface_point(shape: &Shape, ray: &Ray, t: f32) -> SurfacePoint {
    shape.surface_point(ray, t)
}

impl From<Plane> for Shape {
    fn from(plane: Plane) -> Self {
        Shape::Plane(plane)
    }
}

impl From<Triangle> for Shape {
    fn from(triangle: Triangle) -> Self {
        Shape::Triangle(triangle)
    }
}

impl From<Implicit> for Shape {
    fn from(surface: Implicit) -> Self {
        Shape::Implicit(Box::new(surface))
    }
}

impl From<Sphere> for Shape {
    fn from(sphere: Sphere) -> Self {
        Shape::Sphere(sphere)
    }
}
