//! TEMPORARY STUB (not committed): replaced by the mesh branch.
use crate::Vec3;
use std::path::Path;
pub struct Mesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    pub triangle_normals: Option<Vec<[u32; 3]>>,
}
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct MeshError(String);
pub struct MeshTransform {
    pub translate: Vec3,
    pub scale: f32,
    pub rotate_degrees: Vec3,
}
impl MeshTransform {
    pub fn apply(&self, mesh: &mut Mesh) {
        for p in &mut mesh.positions {
            *p = *p * self.scale + self.translate;
        }
    }
}
pub fn load_obj(_path: &Path, _t: &MeshTransform) -> Result<Mesh, MeshError> {
    Err(MeshError("stub".into()))
}
pub fn generate_closed_mesh(_n: usize) -> Result<Mesh, MeshError> {
    let p = vec![Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let t = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    Ok(Mesh {
        normals: p.clone(),
        positions: p,
        triangle_normals: Some(t.clone()),
        triangles: t,
    })
}
