//! The sphere: its data, and a few facts about it. How a ray meets it is
//! chapter 2's lesson ([`crate::chapters::ch02_sphere`]).

use crate::{Ray, Vec3};

/// A sphere: every point at distance `radius` from `center`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    center: Vec3,
    radius: f32,
}

impl Sphere {
    /// A sphere of the given centre and radius. A radius that is not `> 0`,
    /// or anything non-finite, makes a sphere that no ray hits (its fields
    /// become NaN, which fails every comparison of an intersection test).
    pub fn new(center: Vec3, radius: f32) -> Self {
        if radius > 0.0 && radius.is_finite() && center.is_finite() {
            Sphere { center, radius }
        } else {
            Sphere {
                center: Vec3::NAN,
                radius: f32::NAN,
            }
        }
    }

    pub fn center(&self) -> Vec3 {
        self.center
    }

    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// Both parameters where the ray's line meets the sphere, smaller first
    /// (chapter 2's reference solution).
    pub fn roots(&self, ray: &Ray) -> Option<(f32, f32)> {
        crate::chapters::ch02_sphere::sphere_roots(self, ray)
    }

    /// The nearest `t` with `t_min < t < t_max` where `ray` meets the sphere
    /// (chapter 2's reference solution).
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        crate::chapters::ch02_sphere::intersect_sphere(self, ray, t_min, t_max)
    }

    /// The same with the textbook quadratic formula, kept for comparison.
    pub fn intersect_textbook(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        crate::chapters::ch02_sphere::intersect_sphere_textbook(self, ray, t_min, t_max)
    }

    /// Whether `point` is strictly inside the sphere.
    pub fn contains(&self, point: Vec3) -> bool {
        (point - self.center).length_squared() < self.radius * self.radius
    }

    /// The outward unit normal at a point on the sphere.
    pub fn normal_at(&self, point: Vec3) -> Vec3 {
        (point - self.center) / self.radius
    }
}
