//! The pinhole camera: which ray goes through which point of the image.

use serde::Deserialize;

use crate::number;
use crate::{Ray, Vec3, unit_vector};

/// Where the camera stands and what it looks at.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSpec {
    #[serde(deserialize_with = "number::vec3")]
    pub position: Vec3,
    #[serde(deserialize_with = "number::vec3")]
    pub look_at: Vec3,
    #[serde(default = "up")]
    #[serde(deserialize_with = "number::vec3")]
    pub up: Vec3,
    /// Vertical field of view, in degrees.
    #[serde(default = "default_fov")]
    #[serde(deserialize_with = "number::f32")]
    pub fov_degrees: f32,
}

fn up() -> Vec3 {
    Vec3::Y
}
fn default_fov() -> f32 {
    45.0
}

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
    /// The camera for `spec`. A spec that [`Camera::try_new`] refuses (one
    /// that `Scene::parse` never lets through) gives a camera whose rays are
    /// NaN: every pixel is then counted as a non-finite sample, not a panic.
    pub fn new(spec: &CameraSpec, width: u32, height: u32) -> Camera {
        Camera::try_new(spec, width, height).unwrap_or(Camera {
            origin: Vec3::NAN,
            forward: Vec3::NAN,
            right_edge: Vec3::NAN,
            top_edge: Vec3::NAN,
            width: width as f32,
            height: height as f32,
        })
    }

    /// The camera for `spec`, or why it has no viewing direction or no
    /// sideways axis: the scene loader's check, so that what it accepts is
    /// exactly what can be built.
    pub fn try_new(spec: &CameraSpec, width: u32, height: u32) -> Result<Camera, CameraError> {
        let view = spec.look_at - spec.position;
        if view == Vec3::ZERO {
            return Err(CameraError::LooksAtItself {
                look_at: spec.look_at,
            });
        }
        let forward = direction(view).ok_or(CameraError::ViewOverflows { view })?;
        let up_unit = unit_vector(spec.up).ok_or(CameraError::NoUp { up: spec.up })?;
        // An `up` within a millionth of a radian of the viewing direction
        // leaves the sideways axis to rounding.
        if !(forward.cross(up_unit).length_squared() > 1e-12) {
            return Err(CameraError::UpAlongView { up: spec.up, view });
        }
        // `up` as given where its square is a normal `f32`: the pinned
        // images were made so.
        let up_hint = if in_normal_range(spec.up) {
            spec.up
        } else {
            up_unit
        };
        let right =
            direction(forward.cross(up_hint)).ok_or(CameraError::NoSideways { up: spec.up })?;
        let up = right.cross(forward);
        // `libm::tanf` rather than `f32::tan`: the same bits on every platform.
        let half_height = libm::tanf(spec.fov_degrees.to_radians() * 0.5);
        let half_width = half_height * width as f32 / height as f32;
        Ok(Camera {
            origin: spec.position,
            forward,
            right_edge: right * half_width,
            top_edge: up * half_height,
            width: width as f32,
            height: height as f32,
        })
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

    /// Where `point` appears in the image, in pixels from the top-left
    /// corner (the inverse of [`Camera::ray_through`]); `None` for a point
    /// behind the camera or in its plane.
    pub fn project(&self, point: Vec3) -> Option<(f32, f32)> {
        let offset = point - self.origin;
        let depth = offset.dot(self.forward);
        if !(depth > 0.0) {
            return None;
        }
        let horizontal = offset.dot(self.right_edge) / (self.right_edge.length_squared() * depth);
        let vertical = offset.dot(self.top_edge) / (self.top_edge.length_squared() * depth);
        let x = (horizontal + 1.0) * self.width / 2.0;
        let y = (1.0 - vertical) * self.height / 2.0;
        (x.is_finite() && y.is_finite()).then_some((x, y))
    }

    /// Where the camera stands: every camera ray starts here.
    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    /// The unit viewing direction, square to the image plane.
    pub fn forward(&self) -> Vec3 {
        self.forward
    }

    /// The area one pixel covers on the image plane at distance 1 from the
    /// camera (chapter 14's splats): the plane is `2 |right_edge|` by
    /// `2 |top_edge|`, cut into `width x height` pixels.
    pub fn pixel_area(&self) -> f32 {
        (2.0 * self.right_edge.length() / self.width) * (2.0 * self.top_edge.length() / self.height)
    }

    /// The size of the image in pixels, `(width, height)`.
    pub fn size(&self) -> (f32, f32) {
        (self.width, self.height)
    }

    /// The depth of `point` along the viewing direction.
    pub fn depth(&self, point: Vec3) -> f32 {
        (point - self.origin).dot(self.forward)
    }
}

/// Why [`Camera::try_new`] can build no camera for a spec, in the words of
/// the scene file's `[camera]` keys.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CameraError {
    #[error(
        "camera.look_at = {look_at}: the same point as camera.position; the camera must look \
         at another point"
    )]
    LooksAtItself { look_at: Vec3 },
    #[error(
        "camera.look_at - camera.position = {view}: not a finite direction (f32 \
         overflows)"
    )]
    ViewOverflows { view: Vec3 },
    #[error("camera.up = {up}: must be a finite, non-zero direction")]
    NoUp { up: Vec3 },
    #[error("camera.up = {up}: must not be parallel to the viewing direction {view}")]
    UpAlongView { up: Vec3, view: Vec3 },
    #[error("camera.up = {up}: no sideways axis")]
    NoSideways { up: Vec3 },
}

/// `v` scaled to unit length, or `None` when it is zero or not finite.
///
/// `normalize` where `|v|^2` is a normal `f32`: the images the snapshots pin
/// were made with it, bit for bit. Where `|v|^2` underflows (an `up` of
/// `[0, 1e-23, 0]` has `|v|^2 = 1e-46`, below the smallest `f32`) or
/// overflows, [`unit_vector`] rescales first, where `normalize` would give
/// NaN or infinity and distort the image.
fn direction(v: Vec3) -> Option<Vec3> {
    if in_normal_range(v) {
        Some(v.normalize())
    } else {
        unit_vector(v)
    }
}

/// Whether `|v|^2` is a normal `f32` (neither underflowed nor overflowed).
fn in_normal_range(v: Vec3) -> bool {
    let squared = v.length_squared();
    squared >= f32::MIN_POSITIVE && squared.is_finite()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_on_a_pixel_s_ray_projects_to_that_pixel() {
        let spec = CameraSpec {
            position: Vec3::new(0.5, 1.6, -6.0),
            look_at: Vec3::new(0.0, 1.0, 0.0),
            up: Vec3::Y,
            fov_degrees: 50.0,
        };
        let camera = Camera::new(&spec, 64, 48);
        for (x, y) in [(0.5, 0.5), (31.5, 20.25), (63.5, 47.5)] {
            let ray = camera.ray_through(x, y);
            let (px, py) = camera.project(ray.at(7.0)).expect("in front");
            assert!(
                (px - x).abs() < 1e-3 && (py - y).abs() < 1e-3,
                "{px},{py} for {x},{y}"
            );
        }
        assert_eq!(
            camera.project(spec.position - Vec3::new(0.0, 0.0, 1.0)),
            None
        );
    }
}
