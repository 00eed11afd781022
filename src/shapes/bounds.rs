//! Axis-aligned boxes: the bounds a shape gives ([`super::Shape::bounds`])
//! and the boxes of chapter 11's tree ([`crate::bvh`]), here with the
//! shapes so that they need nothing of the tree.

use crate::Vec3;

/// An axis-aligned box: every point `p` with `min <= p <= max`, axis by axis.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    /// The box that contains nothing: `min` above `max` on every axis, so
    /// that growing it by any point or box gives that point or box.
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    pub fn new(min: Vec3, max: Vec3) -> Aabb {
        Aabb { min, max }
    }

    /// The smallest box holding both.
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// The smallest box holding this one and `point`.
    pub fn grow(self, point: Vec3) -> Aabb {
        Aabb {
            min: self.min.min(point),
            max: self.max.max(point),
        }
    }

    pub fn is_empty(&self) -> bool {
        !(self.min.cmple(self.max).all())
    }

    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Half the surface area (what the surface-area heuristic compares; the
    /// factor 2 cancels), 0 for the empty box.
    pub fn half_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let size = self.max - self.min;
        size.x * size.y + size.y * size.z + size.z * size.x
    }
}
