//! Writing a mesh as an OBJ file.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use super::Mesh;
use crate::output::OutputError;

/// Why [`check_obj_output`] refuses a path for a model.
#[derive(Debug, thiserror::Error)]
pub enum ObjOutputError {
    #[error("{option} {}: raylab writes OBJ models; give a name ending in .obj", path.display())]
    NotObjName { option: String, path: PathBuf },
    /// Refused as any output is, or as a file raylab did not write.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// The first line of every OBJ file raylab writes: how `raylab mesh` tells
/// its own earlier output, which it may replace, from a model someone
/// made, which it keeps without `--force`.
const MARKER: &str = "# Written by raylab";

/// Writes `mesh` as OBJ text: a comment line marking it as raylab's, the
/// positions (`v`), the normals (`vn`) if the mesh has vertex normals, and
/// one `f` line per triangle (1-based, `a//n` corners when there are
/// normals). Numbers are written in the shortest form that reads back to
/// the same `f32`, so a model written and loaded again is the same.
pub fn write_obj<W: Write + ?Sized>(mesh: &Mesh, out: &mut W) -> std::io::Result<()> {
    writeln!(
        out,
        "{MARKER}: {} triangles, {} vertices, {} normals",
        mesh.triangles.len(),
        mesh.positions.len(),
        if mesh.triangle_normals.is_some() {
            mesh.normals.len()
        } else {
            0
        }
    )?;
    for p in &mesh.positions {
        writeln!(out, "v {} {} {}", p.x, p.y, p.z)?;
    }
    match &mesh.triangle_normals {
        Some(corner_normals) => {
            for n in &mesh.normals {
                writeln!(out, "vn {} {} {}", n.x, n.y, n.z)?;
            }
            for (t, n) in mesh.triangles.iter().zip(corner_normals) {
                writeln!(
                    out,
                    "f {}//{} {}//{} {}//{}",
                    t[0] + 1,
                    n[0] + 1,
                    t[1] + 1,
                    n[1] + 1,
                    t[2] + 1,
                    n[2] + 1
                )?;
            }
        }
        None => {
            for t in &mesh.triangles {
                writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
            }
        }
    }
    Ok(())
}

/// Whether `path` is an OBJ file raylab wrote (its first line is raylab's
/// marker). Only the first bytes are read, and only of a regular file.
pub fn is_raylab_obj(path: &Path) -> bool {
    let Ok(file) = crate::input::open_regular(path, crate::input::Links::Follow) else {
        return false;
    };
    let mut head = Vec::new();
    if file
        .take(MARKER.len() as u64)
        .read_to_end(&mut head)
        .is_err()
    {
        return false;
    }
    head == MARKER.as_bytes()
}

/// Checks, before a model is generated, that `path` can be written:
/// [`crate::output::check_outputs`]'s rules (an existing folder that
/// accepts files, not a folder itself, not read-only unless `force`), a
/// name ending in `.obj`, and no existing file replaced unless raylab wrote
/// it or `force`. `option` names the path in messages (`-o`).
pub fn check_obj_output(option: &str, path: &Path, force: bool) -> Result<(), ObjOutputError> {
    let is_obj = path
        .extension()
        .is_some_and(|extension| extension.eq_ignore_ascii_case("obj"));
    if !is_obj {
        return Err(ObjOutputError::NotObjName {
            option: option.to_string(),
            path: path.to_path_buf(),
        });
    }
    crate::output::check_outputs(&[], &[(option, path)], force)?;
    if force || std::fs::symlink_metadata(path).is_err() || is_raylab_obj(path) {
        return Ok(());
    }
    Err(OutputError::NotRaylabs {
        option: option.to_string(),
        path: path.to_path_buf(),
    }
    .into())
}

/// Writes `mesh` to `path` all or nothing: into a temporary file renamed
/// over `path` only once complete ([`crate::output::write_atomically`]).
/// Call [`check_obj_output`] first.
pub fn write_obj_file(path: &Path, mesh: &Mesh) -> Result<(), OutputError> {
    crate::output::write_atomically(path, |out| write_obj(mesh, out))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshTransform, generate_closed_mesh, load_obj};

    #[test]
    fn the_same_model_gives_the_same_bytes_and_reads_back_the_same() {
        let mesh = generate_closed_mesh(3_000).expect("in range");
        let mut first = Vec::new();
        let mut second = Vec::new();
        write_obj(&mesh, &mut first).expect("write");
        write_obj(&generate_closed_mesh(3_000).expect("in range"), &mut second).expect("write");
        assert_eq!(first, second);
        let header = format!("# Written by raylab: {} triangles", mesh.triangles.len());
        assert!(first.starts_with(header.as_bytes()));

        let folder = tempfile::tempdir().expect("temporary folder");
        let path = folder.path().join("torus.obj");
        check_obj_output("-o", &path, false).expect("writable");
        write_obj_file(&path, &mesh).expect("write");
        assert!(is_raylab_obj(&path));
        let loaded = load_obj(&path, &MeshTransform::default()).expect("load");
        // tobj numbers vertices in the order faces use them: compare corners.
        assert_eq!(loaded.triangles.len(), mesh.triangles.len());
        for t in 0..mesh.triangles.len() {
            assert_eq!(loaded.corners(t), mesh.corners(t), "triangle {t}");
        }
        let normals = |m: &Mesh, t: usize| {
            m.triangle_normals.as_ref().expect("smooth")[t].map(|k| m.normals[k as usize])
        };
        // Normals are renormalised on loading, which may move the last bit.
        for t in 0..mesh.triangles.len() {
            let (a, b) = (normals(&loaded, t), normals(&mesh, t));
            for (a, b) in a.iter().zip(b) {
                assert!((*a - b).abs().max_element() < 1e-6, "triangle {t}: {a} {b}");
            }
        }
        // Without vertex normals: plain `f a b c` lines.
        let flat = Mesh {
            normals: Vec::new(),
            triangle_normals: None,
            ..mesh.clone()
        };
        write_obj_file(&path, &flat).expect("write");
        let loaded = load_obj(&path, &MeshTransform::default()).expect("load");
        assert!(loaded.triangle_normals.is_none());
        assert_eq!(loaded.triangles.len(), flat.triangles.len());
        for t in 0..flat.triangles.len() {
            assert_eq!(loaded.corners(t), flat.corners(t), "triangle {t}");
        }
        // A second run may replace raylab's own file, not someone else's.
        check_obj_output("-o", &path, false).expect("raylab's own file");
        std::fs::write(&path, "v 0 0 0\n").expect("write");
        let message = check_obj_output("-o", &path, false)
            .unwrap_err()
            .to_string();
        assert!(message.contains("--force"), "{message}");
        check_obj_output("-o", &path, true).expect("forced");
    }
}
