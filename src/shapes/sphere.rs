//! The sphere: its data, and a few facts about it. How a ray meets it is
//! chapter 2's lesson.

use crate::Vec3;

/// A sphere: every point at distance `radius` from `center`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
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

    /// Whether `point` is strictly inside the sphere.
    pub fn contains(&self, point: Vec3) -> bool {
        (point - self.center).length_squared() < self.radius * self.radius
    }

    /// The outward unit normal at a point on the sphere.
    pub fn normal_at(&self, point: Vec3) -> Vec3 {
        (point - self.center) / self.radius
    }
}
