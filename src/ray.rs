//! The ray: the one object every chapter shares.

use glam::Vec3;

/// A half-line `origin + t * dir` for `t >= 0`.
///
/// `dir` need not be unit length: every distance `t` in raylab is measured in
/// units of `dir`, so `ray.at(t)` is the point whatever the length. Only the
/// places that need an angle (shading) normalise.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
}

impl Ray {
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray { origin, dir }
    }

    /// The point at parameter `t` along the ray.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}

/// Returns `v / |v|`, or `None` when `v` is zero or not finite.
///
/// Scaling by the largest component first keeps `|v|^2` from underflowing
/// (a normal like `(1e-30, 0, 0)` is a perfectly good direction) or
/// overflowing (`(1e30, 1e30, 0)`), which a plain `v.normalize()` would turn
/// into NaN or zero.
pub fn unit_vector(v: Vec3) -> Option<Vec3> {
    let largest = v.abs().max_element();
    if !(largest > 0.0) || !largest.is_finite() {
        return None;
    }
    let scaled = v / largest;
    let unit = scaled / scaled.length();
    unit.is_finite().then_some(unit)
}
