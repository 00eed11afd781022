//! The pinhole camera: which ray goes through which point of the image.

use crate::scene::CameraSpec;
use crate::{Ray, Vec3};

/// A pinhole camera fitted to an image of `width x height` pixels.
#[derive(Debug, Clone, Copy)]
pub struct Camera {
    origin: Vec3,
    /// Direction to the image plane's centre, at distance 1.
    forward: Vec3,
    /// Image-plane vectors from the centre to the right and top edges.
    right_edge: Vec3,
    top_edge: Vec3,
    width: f32,
    height: f32,
}

impl Camera {
    pub fn new(spec: &CameraSpec, width: u32, height: u32) -> Camera {
        let forward = (spec.look_at - spec.position).normalize();
        let right = forward.cross(spec.up).normalize();
        let up = right.cross(forward);
        // `libm::tanf` rather than `f32::tan`: the same bits on every platform.
        let half_height = libm::tanf(spec.fov_degrees.to_radians() * 0.5);
        let half_width = half_height * width as f32 / height as f32;
        Camera {
            origin: spec.position,
            forward,
            right_edge: right * half_width,
            top_edge: up * half_height,
            width: width as f32,
            height: height as f32,
        }
    }

    /// The ray through the image point `(x, y)`, in pixels from the top-left
    /// corner: pixel `(i, j)` covers `[i, i+1) x [j, j+1)`, its centre is
    /// `(i + 0.5, j + 0.5)`.
    pub fn ray_through(&self, x: f32, y: f32) -> Ray {
        let horizontal = 2.0 * x / self.width - 1.0;
        let vertical = 1.0 - 2.0 * y / self.height;
        let dir = self.forward + horizontal * self.right_edge + vertical * self.top_edge;
        Ray::new(self.origin, dir.normalize())
    }
}
