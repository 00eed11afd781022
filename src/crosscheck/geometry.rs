//! What the other backend is given: one primitive per shape, each plane
//! a large quad. Embree has no infinite planes, so this is the one place
//! that decides how far a quad reaches and how it is placed; the comparison
//! only reads the quads it made.

use crate::{Plane, Scene, Shape, Vec3};

/// Each plane becomes a square quad whose half-side is at least this many
/// times the scene's size (rounded up to a power of two).
pub const QUAD_SCALE: f32 = 1024.0;

/// A primitive as the other backend receives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Primitive {
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// Four corners in order around the edge: triangles (0, 1, 2), (0, 2, 3).
    Quad([Vec3; 4]),
    /// Three corners, in the triangle's winding.
    Triangle([Vec3; 3]),
}

/// The quad standing in for one of our planes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneQuad {
    pub center: Vec3,
    /// Unit vectors along the quad's sides, in the plane.
    pub u: Vec3,
    pub v: Vec3,
    pub half_side: f32,
    pub corners: [Vec3; 4],
    /// The largest distance of a corner from our plane: corners are rounded
    /// to `f32`, so a quad that is not axis-aligned is a slightly different
    /// plane. Zero when the plane is axis-aligned.
    pub corner_offset: f32,
    /// Whether the normal is along an axis. Then the corners lie exactly in
    /// the plane, Embree's triangle normal is exact, and so are the
    /// products with it: the quad adds no error. Otherwise Embree's `t`
    /// comes from `(corner - origin) · normal`, rounded at the scale of the
    /// corners' distance, far larger than the scene.
    pub axis_aligned: bool,
}

/// The size of the scene: the largest side of the box holding the camera,
/// the lights, the spheres and the planes' points (at least 1).
pub fn scene_size(scene: &Scene) -> f32 {
    let mut low = scene.camera.position;
    let mut high = scene.camera.position;
    let mut include = |point: Vec3, reach: f32| {
        low = low.min(point - reach);
        high = high.max(point + reach);
    };
    for light in &scene.lights {
        include(light.position, 0.0);
    }
    for shape in &scene.shapes {
        match shape {
            Shape::Plane(plane) => include(plane.point(), 0.0),
            Shape::Sphere(sphere) => include(sphere.center(), sphere.radius()),
            Shape::Triangle(triangle) => {
                for corner in triangle.corners() {
                    include(corner, 0.0);
                }
            }
            Shape::Implicit(surface) => {
                if let Some(bounds) = surface.bounds() {
                    include(bounds.min, 0.0);
                    include(bounds.max, 0.0);
                }
            }
        }
    }
    (high - low).max_element().max(1.0)
}

/// The quad standing in for `plane`: a square of half-side `half_side`
/// centred where the camera at `eye` stands over the plane, so it covers
/// everything the camera sees except hits near the horizon.
///
/// The centre is the plane's point moved along the quad's sides only, so
/// for an axis-aligned plane the coordinate along the normal is copied, not
/// computed, and the quad lies exactly in the plane.
pub fn plane_quad(plane: &Plane, eye: Vec3, half_side: f32) -> PlaneQuad {
    let (u, v) = plane.axes();
    let v = v.normalize();
    let point = plane.point();
    let to_eye = eye - point;
    let center = point + to_eye.dot(u) * u + to_eye.dot(v) * v;
    let (a, b) = (half_side * u, half_side * v);
    let corners = [
        center - a - b,
        center + a - b,
        center + a + b,
        center - a + b,
    ];
    let corner_offset = corners
        .iter()
        .map(|&corner| distance_to_plane(plane, corner))
        .fold(0.0, f64::max) as f32;
    PlaneQuad {
        center,
        u,
        v,
        half_side,
        corners,
        corner_offset,
        axis_aligned: plane.normal().cmpeq(Vec3::ZERO).bitmask().count_ones() == 2,
    }
}

/// `|(point - plane point) . normal|`, in double precision.
fn distance_to_plane(plane: &Plane, point: Vec3) -> f64 {
    let offset = point.as_dvec3() - plane.point().as_dvec3();
    offset.dot(plane.normal().as_dvec3()).abs()
}

/// What the other backend is given for `shapes`: one primitive per shape,
/// index for index, and the quads that stand in for the planes.
pub fn primitives(shapes: &[Shape], scene: &Scene) -> (Vec<Primitive>, Vec<Option<PlaneQuad>>) {
    let half_side = (QUAD_SCALE * scene_size(scene)).next_power_of_two_f32();
    shapes
        .iter()
        .map(|shape| match shape {
            Shape::Sphere(sphere) => (
                Primitive::Sphere {
                    center: sphere.center(),
                    radius: sphere.radius(),
                },
                None,
            ),
            Shape::Plane(plane) => {
                let quad = plane_quad(plane, scene.camera.position, half_side);
                (Primitive::Quad(quad.corners), Some(quad))
            }
            Shape::Triangle(triangle) => (Primitive::Triangle(triangle.corners()), None),
            // Embree has no implicit surfaces: a triangle of NaN corners,
            // which it skips, keeps the others' indices (`raylab
            // crosscheck` refuses such scenes before it comes to this).
            Shape::Implicit(_) => (Primitive::Triangle([Vec3::NAN; 3]), None),
        })
        .unzip()
}

trait PowerOfTwo {
    fn next_power_of_two_f32(self) -> f32;
}

impl PowerOfTwo for f32 {
    /// The smallest power of two at least `self` (for positive finite input):
    /// corners at `center ± 2^k` round like `center` does, no worse.
    fn next_power_of_two_f32(self) -> f32 {
        2f32.powi(self.log2().ceil() as i32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_aligned_quad_lies_exactly_in_its_plane() {
        let floor = Plane::new(Vec3::new(0.0, -1.25, 0.0), Vec3::Y);
        let quad = plane_quad(&floor, Vec3::new(0.3, 1.7, -6.1), 8192.0);
        assert_eq!(quad.corner_offset, 0.0);
        assert!(quad.axis_aligned);
        assert!(quad.corners.iter().all(|corner| corner.y == -1.25));
        assert_eq!(quad.center.x, 0.3);
    }

    #[test]
    fn tilted_quad_reports_its_rounding() {
        let tilted = Plane::new(Vec3::new(0.1, 0.2, 0.3), Vec3::new(1.0, 2.0, 3.0));
        let quad = plane_quad(&tilted, Vec3::new(5.0, 5.0, 5.0), 4096.0);
        // Corners 4096 away are rounded to about 4096 * 2^-24.
        assert!(quad.corner_offset > 0.0 && quad.corner_offset < 4096.0 * 4.0 * f32::EPSILON);
        assert!(!quad.axis_aligned);
    }

    #[test]
    fn scene_size_is_a_power_of_two_quad() {
        assert_eq!(1000.0f32.next_power_of_two_f32(), 1024.0);
        assert_eq!(1024.0f32.next_power_of_two_f32(), 1024.0);
    }
}
