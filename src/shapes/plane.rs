//! The infinite plane: its data, and where a hit on it lies. How a ray meets
//! it is chapter 1's lesson.

use crate::{Vec3, unit_vector};

/// An infinite plane through `point` with unit normal `normal`. Two-sided: a
/// ray hits it from either side.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Plane {
    point: Vec3,
    normal: Vec3,
}

impl Plane {
    /// A plane through `point`, perpendicular to `normal` (any non-zero length).
    ///
    /// A zero or non-finite normal, or a non-finite point, makes a plane that
    /// no ray hits: its fields become NaN, and every comparison with NaN is
    /// false, so an intersection test returns `None` without a special case.
    pub fn new(point: Vec3, normal: Vec3) -> Self {
        match unit_vector(normal) {
            Some(normal) if point.is_finite() => Plane { point, normal },
            _ => Plane {
                point: Vec3::NAN,
                normal: Vec3::NAN,
            },
        }
    }

    pub fn point(&self) -> Vec3 {
        self.point
    }

    /// The unit normal (NaN for a degenerate plane).
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// Two axes lying in the plane, perpendicular to each other and to its
    /// normal: where a checker pattern is laid out, and how a plane becomes a
    /// quad for Embree. The helper axis is any one not close to the normal.
    pub fn axes(&self) -> (Vec3, Vec3) {
        let normal = self.normal;
        let helper = if normal.x.abs() > 0.9 {
            Vec3::Y
        } else {
            Vec3::X
        };
        let u = normal.cross(helper).normalize();
        (u, normal.cross(u))
    }
}
