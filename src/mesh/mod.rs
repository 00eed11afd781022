//! Triangle meshes: loading Wavefront OBJ models, generating a closed test
//! model of any size, and writing OBJ files.
//!
//! A [`Mesh`] is plain data: positions, optional vertex normals, and
//! triangles as indices into them. A scene places a model with a
//! [`MeshTransform`] (uniform scale, then rotations about X, Y and Z, then
//! a translation) and gives it one material; the OBJ file's own materials
//! (`mtllib`, `usemtl`) are ignored and never read.
//!
//! What is read is bounded like every file raylab reads ([`crate::input`]):
//! an OBJ file is at most [`MAX_OBJ_BYTES`], a regular file (or a link to
//! one), UTF-8 text, and a model at most [`MAX_MESH_TRIANGLES`] triangles
//! and [`MAX_MESH_VERTICES`] vertices (or normals). Every problem is an
//! error naming the file, and the line when one line is at fault.

mod generate;
mod obj;
mod write;

use std::path::PathBuf;

use crate::Vec3;

pub use generate::{MAX_GENERATED_TRIANGLES, closed_mesh_triangle_count, generate_closed_mesh};
pub use obj::load_obj;
pub use write::{ObjOutputError, check_obj_output, is_raylab_obj, write_obj, write_obj_file};

/// The largest OBJ file read, in bytes (256 MiB: about 3.3 million triangles
/// as `raylab mesh` writes them, 82 bytes a triangle with its share of
/// vertices and normals).
pub const MAX_OBJ_BYTES: u64 = 256 << 20;

/// The most triangles a loaded model may have (after polygons are split
/// into triangles). Checked while the file is scanned, before the model is
/// built, so memory stays bounded.
pub const MAX_MESH_TRIANGLES: usize = 4_000_000;

/// The most vertex positions, and separately the most vertex normals, an
/// OBJ file may declare: three per triangle, the most a model of
/// [`MAX_MESH_TRIANGLES`] can use without sharing any.
pub const MAX_MESH_VERTICES: usize = 3 * MAX_MESH_TRIANGLES;

/// A triangle mesh.
///
/// `triangles[t]` holds three indices into `positions`, counter-clockwise
/// seen from outside (the side the geometric normal
/// `(b - a) x (c - a)` points to). When every triangle of the model has a
/// vertex normal at each corner, `triangle_normals[t]` holds three indices
/// into `normals` for smooth shading (every normal so used is unit
/// length); otherwise
/// `triangle_normals` is `None`, `normals` is empty, and the mesh is shaded
/// flat with each triangle's geometric normal. Every index is in range.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    pub triangle_normals: Option<Vec<[u32; 3]>>,
}

impl Mesh {
    /// The corners of triangle `t`.
    pub fn corners(&self, t: usize) -> [Vec3; 3] {
        self.triangles[t].map(|i| self.positions[i as usize])
    }

    /// How many triangles have no area (collinear or repeated corners): a
    /// ray never hits them, but they are kept, so that triangle numbers
    /// match the file's.
    pub fn degenerate_triangle_count(&self) -> usize {
        (0..self.triangles.len())
            .filter(|&t| {
                let [a, b, c] = self.corners(t);
                (b - a).cross(c - a) == Vec3::ZERO
            })
            .count()
    }

    /// The smallest box holding every vertex a triangle uses, as
    /// `(min, max)`; `None` for a mesh without triangles.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut corners = self
            .triangles
            .iter()
            .flatten()
            .map(|&i| self.positions[i as usize]);
        let first = corners.next()?;
        Some(corners.fold((first, first), |(low, high), p| (low.min(p), high.max(p))))
    }
}

/// Where a model is placed in a scene: `scale` first (uniform, about the
/// model's origin), then `rotate_degrees.x` degrees about the X axis, then
/// `.y` about Y, then `.z` about Z (each counter-clockwise looking from the
/// positive axis towards the origin, right-handed), then `translate`.
///
/// Normals are only rotated: a uniform positive scale does not change their
/// direction. The default is the identity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshTransform {
    pub translate: Vec3,
    pub scale: f32,
    pub rotate_degrees: Vec3,
}

impl Default for MeshTransform {
    fn default() -> Self {
        MeshTransform {
            translate: Vec3::ZERO,
            scale: 1.0,
            rotate_degrees: Vec3::ZERO,
        }
    }
}

impl MeshTransform {
    /// Checks the numbers themselves: all finite, the scale positive (zero
    /// would flatten the model to a point, a negative scale would turn it
    /// inside out), and the translation within the scene's shape limit.
    pub fn validate(&self) -> Result<(), TransformError> {
        let limit = crate::limits::MAX_SHAPE_COORDINATE;
        if !self.translate.is_finite() || self.translate.abs().max_element() > limit {
            return Err(TransformError::Translate {
                translate: self.translate,
            });
        }
        if !(self.scale > 0.0) || !self.scale.is_finite() {
            return Err(TransformError::Scale { scale: self.scale });
        }
        if !self.rotate_degrees.is_finite() {
            return Err(TransformError::Rotate {
                rotate_degrees: self.rotate_degrees,
            });
        }
        Ok(())
    }

    /// The rotation as one matrix: X first, so it is rightmost.
    fn rotation(&self) -> glam::Mat3 {
        let [x, y, z] = self.rotate_degrees.to_array().map(f32::to_radians);
        glam::Mat3::from_rotation_z(z)
            * glam::Mat3::from_rotation_y(y)
            * glam::Mat3::from_rotation_x(x)
    }

    /// The transform ready to apply to many points.
    pub fn compile(&self) -> CompiledTransform {
        CompiledTransform {
            rotation: self.rotation(),
            scale: self.scale,
            translate: self.translate,
        }
    }

    /// A point of the model placed in the scene.
    pub fn apply(&self, point: Vec3) -> Vec3 {
        self.compile().point(point)
    }

    /// A normal of the model in the scene (rotated and renormalised); zero
    /// if it cannot be normalised.
    pub fn apply_normal(&self, normal: Vec3) -> Vec3 {
        self.compile().normal(normal)
    }
}

/// Why [`MeshTransform::validate`] refuses a transform, naming the value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TransformError {
    #[error(
        "translate = {translate}: each coordinate must be a number within {:e} of the origin",
        crate::limits::MAX_SHAPE_COORDINATE
    )]
    Translate { translate: Vec3 },
    #[error("scale = {scale}: must be a positive number")]
    Scale { scale: f32 },
    #[error("rotate_degrees = {rotate_degrees}: must be numbers")]
    Rotate { rotate_degrees: Vec3 },
}

/// A [`MeshTransform`] with its rotation matrix computed once.
#[derive(Debug, Clone, Copy)]
pub struct CompiledTransform {
    rotation: glam::Mat3,
    scale: f32,
    translate: Vec3,
}

impl CompiledTransform {
    pub fn point(&self, point: Vec3) -> Vec3 {
        self.rotation * (point * self.scale) + self.translate
    }

    pub fn normal(&self, normal: Vec3) -> Vec3 {
        (self.rotation * normal).normalize_or_zero()
    }
}

/// Why a model could not be loaded or generated. Every message about a
/// file names it; `Parse` also names the line (`model.obj:12: ...`).
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The file could not be read: missing, not a regular file, too large.
    /// The message names the file.
    #[error(transparent)]
    Read(crate::input::InputError),
    #[error("{}: the file is empty; an OBJ model needs vertices (v lines) and faces (f lines)", path.display())]
    Empty { path: PathBuf },
    #[error("{}:{line}: {message}", path.display())]
    Parse {
        path: PathBuf,
        line: usize,
        message: String,
    },
    #[error("no triangles in {}: {detail}", path.display())]
    NoTriangles { path: PathBuf, detail: String },
    /// A problem found after parsing (no single line to blame).
    #[error("{}: {message}", path.display())]
    Invalid { path: PathBuf, message: String },
    #[error("mesh transform: {0}")]
    Transform(TransformError),
    #[error(
        "{requested} triangles: raylab generates a model of 1 to {MAX_GENERATED_TRIANGLES} triangles"
    )]
    TriangleCount { requested: usize },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_transform_scales_then_rotates_x_y_z_then_translates() {
        let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 1e-6;
        let identity = MeshTransform::default();
        assert_eq!(
            identity.apply(Vec3::new(1.0, 2.0, 3.0)),
            Vec3::new(1.0, 2.0, 3.0)
        );
        // X first: +Y turns to +Z about X, then +Z turns to +X about Y. Y
        // first would leave +Y alone, then X would take it to +Z.
        let xy = MeshTransform {
            rotate_degrees: Vec3::new(90.0, 90.0, 0.0),
            ..identity
        };
        assert!(close(xy.apply(Vec3::Y), Vec3::X), "{}", xy.apply(Vec3::Y));
        // Y before Z: +X about Y (90) is -Z, which Z leaves alone.
        let yz = MeshTransform {
            rotate_degrees: Vec3::new(0.0, 90.0, 90.0),
            ..identity
        };
        assert!(close(yz.apply(Vec3::X), -Vec3::Z), "{}", yz.apply(Vec3::X));
        // Scale before the translation: the offset is not scaled.
        let moved = MeshTransform {
            translate: Vec3::new(10.0, 0.0, 0.0),
            scale: 2.0,
            rotate_degrees: Vec3::new(0.0, 0.0, 90.0),
        };
        assert!(close(moved.apply(Vec3::X), Vec3::new(10.0, 2.0, 0.0)));
        // Normals are rotated and stay unit length.
        assert!(close(moved.apply_normal(Vec3::X * 5.0), Vec3::Y));
        for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert!(
                MeshTransform {
                    scale: bad,
                    ..identity
                }
                .validate()
                .is_err()
            );
        }
        let far = MeshTransform {
            translate: Vec3::new(0.0, 2e6, 0.0),
            ..identity
        };
        assert!(far.validate().is_err());
    }

    #[test]
    fn degenerate_triangles_are_counted_and_bounds_cover_the_used_vertices() {
        let mesh = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::splat(100.0)],
            normals: Vec::new(),
            triangles: vec![[0, 1, 2], [0, 1, 1], [0, 0, 0]],
            triangle_normals: None,
        };
        assert_eq!(mesh.degenerate_triangle_count(), 2);
        assert_eq!(mesh.bounds(), Some((Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0))));
        assert_eq!(Mesh::default().bounds(), None);
    }
}
