//! The triangle: its data, and a few facts about it. How a ray meets it is
//! chapter 10's lesson.

use crate::{Vec3, unit_vector};

/// A triangle with corners `a`, `b`, `c`. Two-sided: a ray hits it from
/// either side. The winding `a -> b -> c` only fixes which way the
/// geometric normal points (right-hand rule), which a mesh file uses to say
/// "outside".
///
/// A triangle of a smooth mesh also knows where its three vertex normals
/// are kept ([`Triangle::normals`]): an index into the scene's table rather
/// than three more vectors here, so that the data a ray test reads stays
/// small (a million triangles are 40 MB, not 76).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Triangle {
    corners: [Vec3; 3],
    normals: u32,
}

impl Triangle {
    /// Marks a triangle shaded flat (its geometric normal everywhere).
    pub const FLAT: u32 = u32::MAX;

    /// A flat triangle. A corner that is not finite makes a triangle no ray
    /// hits (all corners NaN), as with spheres and planes. A degenerate
    /// triangle (three corners on a line) is kept: no ray hits it either,
    /// because its area, the denominator of every test, is zero.
    pub fn new(a: Vec3, b: Vec3, c: Vec3) -> Self {
        Triangle::with_normals(a, b, c, Triangle::FLAT)
    }

    /// A triangle whose vertex normals are entry `normals` of the scene's
    /// table ([`crate::Scene::vertex_normals`]).
    pub fn with_normals(a: Vec3, b: Vec3, c: Vec3, normals: u32) -> Self {
        if a.is_finite() && b.is_finite() && c.is_finite() {
            Triangle {
                corners: [a, b, c],
                normals,
            }
        } else {
            Triangle {
                corners: [Vec3::NAN; 3],
                normals: Triangle::FLAT,
            }
        }
    }

    pub fn corners(&self) -> [Vec3; 3] {
        self.corners
    }

    pub fn a(&self) -> Vec3 {
        self.corners[0]
    }

    pub fn b(&self) -> Vec3 {
        self.corners[1]
    }

    pub fn c(&self) -> Vec3 {
        self.corners[2]
    }

    /// Where this triangle's vertex normals are in the scene's table, or
    /// `None` for a flat triangle.
    pub fn normals(&self) -> Option<usize> {
        (self.normals != Triangle::FLAT).then_some(self.normals as usize)
    }

    /// The unit normal by the right-hand rule on `a -> b -> c`, NaN for a
    /// degenerate triangle.
    pub fn geometric_normal(&self) -> Vec3 {
        let [a, b, c] = self.corners;
        unit_vector((b - a).cross(c - a)).unwrap_or(Vec3::NAN)
    }
}
