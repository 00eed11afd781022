//! Loading a Wavefront OBJ model.
//!
//! Two passes over the text. The first, here, checks every line the model
//! is built from (`v`, `vn`, `vt`, `f`) and counts vertices and triangles,
//! so that each problem is reported with its line number (the `tobj`
//! crate's errors carry none), limits are enforced before any model is
//! built, and the second pass, `tobj`, only ever sees text it accepts. That
//! pass triangulates polygons (as a fan from the first corner) and splits
//! the model into objects, which are joined back into one [`Mesh`].
//!
//! The first pass also blanks a few lines before `tobj` reads them:
//! `l` (polyline) lines, which `tobj` would otherwise read as faces, and
//! `mtllib`/`usemtl` lines, since raylab gives a model one material and
//! never reads the `.mtl` files an OBJ file names.

use std::path::Path;

use super::{MAX_MESH_TRIANGLES, MAX_MESH_VERTICES, MAX_OBJ_BYTES, Mesh, MeshError, MeshTransform};
use crate::Vec3;
use crate::input::{Links, read_bounded};
use crate::limits::MAX_SHAPE_COORDINATE;

/// Loads the OBJ model at `path`, placed by `transform`.
///
/// The file is read through [`crate::input`]: a regular file (a symbolic
/// link to one is followed), at most [`super::MAX_OBJ_BYTES`]. It must be
/// UTF-8 text. Refused, with the file and line named: a number that does
/// not parse or is not finite, a vertex farther than
/// [`crate::limits::MAX_SHAPE_COORDINATE`] from the origin after the
/// transform, a face of fewer than three corners, an index of 0 or out of
/// range (indices refer to elements defined on earlier lines; negative ones
/// count back from the latest), more than [`super::MAX_MESH_TRIANGLES`]
/// triangles or [`super::MAX_MESH_VERTICES`] vertices. A file without
/// faces is refused too. Triangles without area are kept (see
/// [`Mesh::degenerate_triangle_count`]).
///
/// Vertex normals are kept when every face gives one at every corner;
/// otherwise the mesh is flat-shaded (`triangle_normals` is `None`). A
/// corner whose normal is zero gets its triangle's own normal instead.
pub fn load_obj(path: &Path, transform: &MeshTransform) -> Result<Mesh, MeshError> {
    transform.validate().map_err(MeshError::Transform)?;
    let mut bytes = read_bounded(path, MAX_OBJ_BYTES, "Wavefront OBJ file", Links::Follow)
        .map_err(MeshError::Read)?;
    if bytes.is_empty() {
        return Err(MeshError::Empty {
            path: path.to_path_buf(),
        });
    }
    let parse_error = |line: usize, message: String| MeshError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    let compiled = transform.compile();
    let scan = scan(&mut bytes, &|p| compiled.point(p))
        .map_err(|(line, message)| parse_error(line, message))?;
    // Every face has at least three corners (the scan checked), so no
    // triangles means no faces.
    if scan.triangles == 0 {
        return Err(MeshError::NoTriangles {
            path: path.to_path_buf(),
            detail: format!(
                "it has {} vertices and no faces (f lines); points and lines are not drawn",
                scan.positions
            ),
        });
    }
    let invalid = |message: String| MeshError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    // The rest is behind tobj features raylab does not enable, but another
    // crate in a build could.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        triangulate: true,
        // Positions and normals keep separate indices, so a vertex shared by
        // faces with different normals is stored once.
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let (models, _materials) = tobj::load_obj_buf(&mut bytes.as_slice(), &options, |_| {
        // Never read: raylab gives the model its scene material.
        Err(tobj::LoadError::GenericFailure)
    })
    .map_err(|error| invalid(format!("not a valid OBJ model: {error}")))?;
    drop(bytes);
    assemble(&models, &compiled, scan).map_err(invalid)
}

/// What the first pass found.
#[derive(Debug, Clone, Copy)]
struct Scan {
    positions: usize,
    faces: usize,
    triangles: usize,
    /// Whether every corner of every face names a normal.
    all_corners_have_normals: bool,
}

/// Checks the text line by line (see the module documentation) and blanks
/// the lines `tobj` must not act on. `place` is the model's transform,
/// applied to each vertex to check where it lands. The error is a line
/// number (1-based) and what is wrong there.
fn scan(bytes: &mut [u8], place: &dyn Fn(Vec3) -> Vec3) -> Result<Scan, (usize, String)> {
    // A byte-order mark would glue itself to the first keyword.
    if let Some(bom) = bytes.get_mut(..3)
        && bom == b"\xef\xbb\xbf"
    {
        bom.fill(b' ');
    }
    let mut counts = Counts::default();
    let mut scan = Scan {
        positions: 0,
        faces: 0,
        triangles: 0,
        all_corners_have_normals: true,
    };
    let mut start = 0;
    let mut number = 0;
    while start < bytes.len() {
        number += 1;
        let end = bytes[start..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |offset| start + offset);
        let raw = &mut bytes[start..end];
        if raw.contains(&0) {
            return Err((
                number,
                "a NUL byte: this is a binary file (or UTF-16 text), not OBJ text".into(),
            ));
        }
        if std::str::from_utf8(raw).is_err() {
            // Exporters write names (groups, materials, comments) in
            // Latin-1 and the like: harmless where raylab ignores the text,
            // so such bytes become '?'. A number is never anything but ASCII.
            let keyword = raw
                .split(|b| b.is_ascii_whitespace())
                .find(|word| !word.is_empty());
            if matches!(keyword, Some(b"v" | b"vn" | b"vt" | b"f")) {
                return Err((number, "not UTF-8 text".into()));
            }
            replace_invalid_utf8(raw);
        }
        let line = std::str::from_utf8(raw).map_err(|_| (number, "not UTF-8 text".to_string()))?;
        let indent = line.len() - line.trim_start().len();
        match check_line(line, place, &mut counts, &mut scan) {
            // '#' makes the line a comment; the keyword's first byte is ASCII.
            Ok(true) => raw[indent] = b'#',
            Ok(false) => {}
            Err(message) => return Err((number, message)),
        }
        start = end + 1;
    }
    Ok(scan)
}

/// Checks one line, counting what it declares; `Ok(true)` when the line
/// must be blanked before the second pass.
fn check_line(
    line: &str,
    place: &dyn Fn(Vec3) -> Vec3,
    counts: &mut Counts,
    scan: &mut Scan,
) -> Result<bool, String> {
    let mut words = line.split_whitespace();
    match words.next() {
        Some("v") => {
            let p = vertex(&mut words)?;
            let placed = place(p);
            if !placed.is_finite() || placed.abs().max_element() > MAX_SHAPE_COORDINATE {
                return Err(format!(
                    "vertex [{}, {}, {}] lands at [{}, {}, {}] after the transform; a \
                     model's vertices must stay within {MAX_SHAPE_COORDINATE:e} of the origin",
                    p.x, p.y, p.z, placed.x, placed.y, placed.z
                ));
            }
            counts.v = count_one(counts.v, "vertices (v lines)")?;
            scan.positions = counts.v;
        }
        Some("vn") => {
            let [x, y, z] = numbers::<3>(&mut words, "vn", "x y z")?;
            if ![x, y, z].iter().all(|c| c.is_finite()) {
                return Err(format!("normal [{x}, {y}, {z}] is not finite"));
            }
            counts.vn = count_one(counts.vn, "normals (vn lines)")?;
        }
        Some("vt") => {
            // Only checked so that the second pass cannot fail on it.
            numbers::<2>(&mut words, "vt", "u v")?;
            counts.vt = count_one(counts.vt, "texture coordinates (vt lines)")?;
        }
        Some("f") => {
            let mut corners = 0usize;
            for word in words {
                let has_normal = corner(word, counts)?;
                scan.all_corners_have_normals &= has_normal;
                corners += 1;
                // A face of n corners is n - 2 triangles; counted as we go
                // so that one huge face cannot pass the limit.
                if corners > 2 {
                    scan.triangles += 1;
                    if scan.triangles > MAX_MESH_TRIANGLES {
                        return Err(format!(
                            "more than {MAX_MESH_TRIANGLES} triangles; raylab loads models of \
                             at most {MAX_MESH_TRIANGLES}"
                        ));
                    }
                }
            }
            if corners < 3 {
                return Err(format!(
                    "a face (f) needs at least 3 corners, this one has {corners}"
                ));
            }
            scan.faces += 1;
        }
        Some("l" | "mtllib" | "usemtl") => return Ok(true),
        _ => {}
    }
    Ok(false)
}

/// How many of each element the lines so far declared.
#[derive(Debug, Default, Clone, Copy)]
struct Counts {
    v: usize,
    vt: usize,
    vn: usize,
}

fn count_one(count: usize, what: &str) -> Result<usize, String> {
    if count >= MAX_MESH_VERTICES {
        return Err(format!(
            "more than {MAX_MESH_VERTICES} {what}; raylab loads at most {MAX_MESH_VERTICES}"
        ));
    }
    Ok(count + 1)
}

/// Replaces each byte that is not part of valid UTF-8 with '?', in place.
fn replace_invalid_utf8(mut bytes: &mut [u8]) {
    while let Err(error) = std::str::from_utf8(bytes) {
        let bad = error.valid_up_to();
        // None: a sequence cut short by the end of the line.
        let length = error.error_len().unwrap_or(bytes.len() - bad);
        bytes[bad..bad + length].fill(b'?');
        bytes = &mut bytes[bad + length..];
    }
}

/// `N` numbers from `words` (more are ignored, as `tobj` does).
fn numbers<const N: usize>(
    words: &mut std::str::SplitWhitespace,
    keyword: &str,
    names: &str,
) -> Result<[f32; N], String> {
    let mut values = [0.0; N];
    for value in &mut values {
        let Some(word) = words.next() else {
            return Err(format!("{keyword} needs {N} numbers ({names})"));
        };
        *value = word
            .parse::<f32>()
            .map_err(|_| format!("{keyword}: {word:?} is not a number"))?;
        // `1e39` parses to infinity: say what was written, not `inf`.
        let spelled_infinite = word
            .trim_start_matches(['+', '-'])
            .to_ascii_lowercase()
            .starts_with("inf");
        if value.is_infinite() && !spelled_infinite {
            return Err(format!(
                "{keyword}: {word} is too large for a 32-bit float (at most about 3.4e38)"
            ));
        }
    }
    Ok(values)
}

/// A `v` line's position: `x y z`, optionally a weight `w` that divides
/// them (as `tobj` applies it) or a colour `r g b` (ignored).
fn vertex(words: &mut std::str::SplitWhitespace) -> Result<Vec3, String> {
    let [x, y, z] = numbers::<3>(words, "v", "x y z")?;
    let mut p = Vec3::new(x, y, z);
    let rest: Vec<&str> = words.take(4).collect();
    match rest.len() {
        0 | 3 => {}
        1 => {
            let w: f32 = rest[0]
                .parse()
                .map_err(|_| format!("v: the weight {:?} is not a number", rest[0]))?;
            if w == 0.0 {
                return Err("v: a weight of 0".into());
            }
            // Element by element, as tobj divides.
            p = Vec3::new(p.x / w, p.y / w, p.z / w);
        }
        count => {
            return Err(format!(
                "v takes x y z, then a weight w or a colour r g b; this one has {count} more numbers"
            ));
        }
    }
    if !p.is_finite() {
        return Err(format!("vertex [{}, {}, {}] is not finite", p.x, p.y, p.z));
    }
    Ok(p)
}

/// Checks one face corner (`v`, `v/vt`, `v//vn`, `v/vt/vn`) against the
/// elements declared so far; returns whether it names a normal.
fn corner(word: &str, counts: &Counts) -> Result<bool, String> {
    if word.split('/').count() > 3 {
        return Err(format!(
            "face corner {word:?}: at most three indices (v/vt/vn)"
        ));
    }
    let mut parts = word.split('/');
    let kinds = [
        ("vertex", counts.v),
        ("texture coordinate", counts.vt),
        ("normal", counts.vn),
    ];
    let mut has_normal = false;
    for (slot, (what, declared)) in kinds.into_iter().enumerate() {
        let Some(part) = parts.next() else { break };
        if part.is_empty() {
            if slot == 0 {
                return Err(format!("face corner {word:?} has no vertex index"));
            }
            continue;
        }
        let declared = declared as i64;
        let index: i64 = part.parse().map_err(|error: std::num::ParseIntError| {
            use std::num::IntErrorKind::{NegOverflow, PosOverflow};
            match error.kind() {
                PosOverflow | NegOverflow => format!(
                    "face corner {word:?}: {what} {part} does not exist ({declared} declared \
                     before this line)"
                ),
                _ => format!("face corner {word:?}: {part:?} is not a whole number"),
            }
        })?;
        let valid = match index {
            0 => return Err(format!("face corner {word:?}: index 0 (OBJ counts from 1)")),
            1.. => index <= declared,
            // -1 is the latest one declared; i64::MIN has no negation.
            _ => index.checked_neg().is_some_and(|back| back <= declared),
        };
        if !valid {
            return Err(format!(
                "face corner {word:?}: {what} {index} does not exist ({declared} declared \
                 before this line)"
            ));
        }
        has_normal = slot == 2;
    }
    Ok(has_normal)
}

/// Joins `tobj`'s objects into one mesh, placed by `transform`.
fn assemble(
    models: &[tobj::Model],
    transform: &super::CompiledTransform,
    scan: Scan,
) -> Result<Mesh, String> {
    let mut mesh = Mesh::default();
    let mut corner_normals = Vec::new();
    let mut smooth = scan.all_corners_have_normals;
    for model in models {
        let source = &model.mesh;
        let base =
            u32::try_from(mesh.positions.len()).map_err(|_| "too many vertices".to_string())?;
        let normal_base =
            u32::try_from(mesh.normals.len()).map_err(|_| "too many normals".to_string())?;
        for p in source.positions.chunks_exact(3) {
            let placed = transform.point(Vec3::new(p[0], p[1], p[2]));
            // The first pass checked every vertex; this is the same check on
            // what tobj built, should the two ever disagree.
            if !placed.is_finite() || placed.abs().max_element() > MAX_SHAPE_COORDINATE {
                return Err(format!(
                    "a vertex lands at {placed}, outside the scene's limits"
                ));
            }
            mesh.positions.push(placed);
        }
        let count = source.positions.len() / 3;
        if source.indices.len() % 3 != 0 {
            return Err("a face was not split into triangles".into());
        }
        for triangle in source.indices.chunks_exact(3) {
            let mut indices = [0u32; 3];
            for (slot, &index) in indices.iter_mut().zip(triangle) {
                if index as usize >= count {
                    return Err(format!("vertex index {index} out of range"));
                }
                *slot = base + index;
            }
            mesh.triangles.push(indices);
        }
        if smooth {
            for n in source.normals.chunks_exact(3) {
                // Zero if it cannot be normalised; replaced below.
                mesh.normals
                    .push(transform.normal(Vec3::new(n[0], n[1], n[2])));
            }
            let count = source.normals.len() / 3;
            if source.normal_indices.len() != source.indices.len() {
                smooth = false;
            }
            for triangle in source.normal_indices.chunks_exact(3) {
                let mut indices = [0u32; 3];
                for (slot, &index) in indices.iter_mut().zip(triangle) {
                    if index as usize >= count {
                        smooth = false;
                    }
                    *slot = normal_base + index;
                }
                corner_normals.push(indices);
            }
        }
    }
    if mesh.triangles.len() != scan.triangles {
        return Err(format!(
            "{} triangles were built, {} expected from the faces",
            mesh.triangles.len(),
            scan.triangles
        ));
    }
    if smooth && corner_normals.len() == mesh.triangles.len() {
        replace_zero_normals(&mut mesh, &mut corner_normals)?;
        mesh.triangle_normals = Some(corner_normals);
    } else {
        mesh.normals = Vec::new();
    }
    Ok(mesh)
}

/// Points each corner whose normal is zero (some exporters write
/// `vn 0 0 0`, e.g. spider.obj once in 747) at a new normal: its
/// triangle's own, so that the rest of the model stays smooth. A triangle
/// without area has no normal either; it is never hit, so any unit vector
/// serves. The zero normals stay in the list, unused.
fn replace_zero_normals(mesh: &mut Mesh, corner_normals: &mut [[u32; 3]]) -> Result<(), String> {
    for (t, corners) in corner_normals.iter_mut().enumerate() {
        let mut own = None;
        for corner in corners.iter_mut() {
            if mesh.normals[*corner as usize] != Vec3::ZERO {
                continue;
            }
            let index = match own {
                Some(index) => index,
                None => {
                    let [a, b, c] = mesh.corners(t);
                    let normal = (b - a).cross(c - a).try_normalize().unwrap_or(Vec3::Y);
                    let index = u32::try_from(mesh.normals.len())
                        .map_err(|_| "too many normals".to_string())?;
                    mesh.normals.push(normal);
                    *own.insert(index)
                }
            };
            *corner = index;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scanned(text: &str) -> Result<Scan, (usize, String)> {
        let mut bytes = text.as_bytes().to_vec();
        scan(&mut bytes, &|p| p)
    }

    #[test]
    fn the_scan_counts_fan_triangles_and_checks_indices_as_declared_so_far() {
        let scan =
            scanned("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf -4 -3 -2\n").expect("valid");
        assert_eq!((scan.positions, scan.faces, scan.triangles), (4, 2, 3));
        assert!(!scan.all_corners_have_normals);
        // A forward reference is refused, even though the vertex follows.
        let (line, message) = scanned("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 1 1 0\n").expect_err("refused");
        assert_eq!(line, 3, "{message}");
        assert!(message.contains("vertex 3 does not exist"), "{message}");
        let (line, message) =
            scanned("v 0 0 0\nv 1 0 0\nv 1 1 0\nf -4 1 2\n").expect_err("refused");
        assert_eq!(line, 4, "{message}");
    }

    #[test]
    fn vertices_normals_and_texture_coordinates_are_counted_up_to_the_limit() {
        assert_eq!(count_one(MAX_MESH_VERTICES - 1, "v"), Ok(MAX_MESH_VERTICES));
        let message = count_one(MAX_MESH_VERTICES, "vertices (v lines)").expect_err("over");
        assert!(message.contains("more than 12000000 vertices"), "{message}");
    }

    #[test]
    fn lines_and_material_lines_are_blanked_for_the_second_pass() {
        let mut bytes = b"v 0 0 0\n  l 1 1\nusemtl x\nmtllib a b.mtl\n".to_vec();
        scan(&mut bytes, &|p| p).expect("valid");
        assert_eq!(bytes, b"v 0 0 0\n  # 1 1\n#semtl x\n#tllib a b.mtl\n");
    }
}
