//! Meshes in a scene file (`mesh = { obj = "model.obj" }` or `mesh = {
//! generated = N }`): the model [`crate::mesh`] loads or makes, placed,
//! checked and cut into the scene's triangles.

use std::path::Path;

use serde::Deserialize;

use super::one;
use super::validate::{check_coordinates, check_finite, check_point};
use crate::Vec3;
use crate::limits::MAX_SHAPE_COORDINATE;
use crate::number;
use crate::shapes::{Shape, Triangle};

/// `mesh = { obj = "model.obj", ... }` or `mesh = { generated = N, ... }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MeshSpec {
    /// A Wavefront OBJ file, relative to the scene file.
    obj: Option<String>,
    /// Or raylab's procedural closed model of about this many triangles
    /// (`raylab mesh`), so that a scene needs no file.
    generated: Option<u64>,
    #[serde(default, deserialize_with = "number::vec3")]
    translate: Vec3,
    #[serde(default = "one", deserialize_with = "number::f32")]
    scale: f32,
    #[serde(default, deserialize_with = "number::vec3")]
    rotate_degrees: Vec3,
    /// Shade with the model's vertex normals where it has them (`false`
    /// shows the facets).
    #[serde(default = "yes")]
    smooth: bool,
}

fn yes() -> bool {
    true
}

impl MeshSpec {
    /// The mesh's triangles, placed in the scene; their vertex normals (when
    /// the model has them and `smooth` is on) are appended to `normals`.
    pub(super) fn load(
        &self,
        label: &str,
        folder: Option<&Path>,
        normals: &mut Vec<[Vec3; 3]>,
    ) -> Result<Vec<Shape>, String> {
        check_point(&format!("{label}: mesh.translate"), self.translate)?;
        check_finite(
            &format!("{label}: mesh.rotate_degrees"),
            self.rotate_degrees,
        )?;
        if !(self.scale > 0.0 && self.scale <= MAX_SHAPE_COORDINATE) {
            return Err(format!(
                "{label}: mesh.scale = {}: must be a number > 0 and at most {MAX_SHAPE_COORDINATE:e}",
                self.scale
            ));
        }
        let transform = crate::mesh::MeshTransform {
            translate: self.translate,
            scale: self.scale,
            rotate_degrees: self.rotate_degrees,
        };
        let mesh = match (&self.obj, self.generated) {
            (Some(obj), None) => obj_model(label, obj, folder, &transform)?,
            (None, Some(count)) => generated_model(label, count, &transform)?,
            _ => {
                return Err(format!(
                    "{label}: a mesh needs exactly one of `obj = \"file.obj\"` and \
                     `generated = N`"
                ));
            }
        };
        self.triangles(label, &mesh, normals)
    }

    /// The placed model's triangles as shapes, checked; smooth ones get
    /// their vertex normals appended to `normals`.
    fn triangles(
        &self,
        label: &str,
        mesh: &crate::mesh::Mesh,
        normals: &mut Vec<[Vec3; 3]>,
    ) -> Result<Vec<Shape>, String> {
        let mut shapes = Vec::with_capacity(mesh.triangles.len());
        for (index, triangle) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = triangle.map(|vertex| mesh.positions[vertex as usize]);
            for corner in [a, b, c] {
                check_coordinates(&format!("{label}: a vertex of the mesh"), corner)?;
            }
            let smooth = match &mesh.triangle_normals {
                Some(indices) if self.smooth => Some(indices[index]),
                _ => None,
            };
            let shape = match smooth {
                Some(indices) => {
                    let entry = u32::try_from(normals.len()).unwrap_or(Triangle::FLAT);
                    normals.push(indices.map(|n| mesh.normals[n as usize]));
                    Triangle::with_normals(a, b, c, entry)
                }
                None => Triangle::new(a, b, c),
            };
            shapes.push(shape.into());
        }
        Ok(shapes)
    }
}

/// The model of `mesh.obj = "obj"`, loaded from next to the scene file (in
/// `folder`) and placed by `transform`.
fn obj_model(
    label: &str,
    obj: &str,
    folder: Option<&Path>,
    transform: &crate::mesh::MeshTransform,
) -> Result<crate::mesh::Mesh, String> {
    if obj.trim().is_empty() {
        return Err(format!(
            "{label}: mesh.obj is empty: name an OBJ file, relative to the scene file"
        ));
    }
    let Some(folder) = folder else {
        return Err(format!(
            "{label}: mesh.obj = \"{obj}\": OBJ files are found next to the scene \
             file, and this scene has none (a built-in scene can use \
             `generated = N` instead)"
        ));
    };
    crate::mesh::load_obj(&folder.join(obj), transform).map_err(|error| format!("{label}: {error}"))
}

/// The model of `mesh.generated = count`, placed by `transform`.
fn generated_model(
    label: &str,
    count: u64,
    transform: &crate::mesh::MeshTransform,
) -> Result<crate::mesh::Mesh, String> {
    // A scene holds no bigger model than it could load from a file:
    // `raylab mesh` writes larger ones, for other tools.
    let max = crate::mesh::MAX_MESH_TRIANGLES;
    if !(1..=max as u64).contains(&count) {
        return Err(format!(
            "{label}: mesh.generated = {count}: a scene's model has 1 to {max} \
             triangles, as a loaded OBJ model does"
        ));
    }
    let count = usize::try_from(count).unwrap_or(usize::MAX);
    let mut mesh = crate::mesh::generate_closed_mesh(count)
        .map_err(|error| format!("{label}: mesh.generated = {count}: {error}"))?;
    let placed = transform.compile();
    for position in &mut mesh.positions {
        *position = placed.point(*position);
    }
    for normal in &mut mesh.normals {
        *normal = placed.normal(*normal);
    }
    Ok(mesh)
}
