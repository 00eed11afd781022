//! Triangle meshes: OBJ models loaded (real ones from Debian's
//! `assimp-testmodels` when installed, and small ones written here always),
//! broken files refused with the file and line named and never a panic, and
//! `raylab mesh`.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common;
use common::raylab;

use raylab::Vec3;
use raylab::mesh::{MAX_MESH_TRIANGLES, MAX_OBJ_BYTES, Mesh, MeshError, MeshTransform, load_obj};

/// Where Debian's `assimp-testmodels` puts its models (scripts/test.sh
/// installs it where it can). `RAYLAB_ASSIMP_MODELS` names another folder
/// (a copy elsewhere, or a missing one to try the fallback).
const ASSIMP_MODELS: &str = "/usr/share/assimp/models";

fn assimp_folder(name: &str) -> Option<PathBuf> {
    let root = std::env::var_os("RAYLAB_ASSIMP_MODELS")
        .map_or_else(|| PathBuf::from(ASSIMP_MODELS), PathBuf::from);
    let folder = root.join(name);
    if folder.is_dir() {
        Some(folder)
    } else {
        eprintln!(
            "SKIPPED: {} is missing; install Debian's assimp-testmodels package \
             (scripts/test.sh does where it can) to test real models. The small \
             models written by the other tests still run.",
            folder.display()
        );
        None
    }
}

fn obj_files(folder: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(folder)
        .expect("list the folder")
        .map(|entry| entry.expect("folder entry").path())
        .filter(|path| {
            path.extension()
                .is_some_and(|extension| extension.eq_ignore_ascii_case("obj"))
        })
        .collect();
    files.sort();
    files
}

fn identity() -> MeshTransform {
    MeshTransform::default()
}

/// What a model's text says, counted independently of raylab: triangles
/// (a face of n corners is n - 2), whether every face corner names a
/// normal (`v//n`, `v/t/n`), and the box around every `v` line.
struct Expected {
    triangles: usize,
    every_corner_has_a_normal: bool,
    bounds: (Vec3, Vec3),
}

fn expected(path: &Path) -> Expected {
    let bytes = std::fs::read(path).expect("read the model");
    let text = String::from_utf8_lossy(&bytes);
    let mut expected = Expected {
        triangles: 0,
        every_corner_has_a_normal: true,
        bounds: (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
    };
    for line in text.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.first() {
            Some(&"f") => {
                let corners = &words[1..];
                expected.triangles += corners.len().saturating_sub(2);
                expected.every_corner_has_a_normal &= corners
                    .iter()
                    .all(|c| c.split('/').nth(2).is_some_and(|n| !n.is_empty()));
            }
            Some(&"v") => {
                let xyz: Vec<f32> = words[1..4]
                    .iter()
                    .map(|w| w.parse().expect("number"))
                    .collect();
                let p = Vec3::new(xyz[0], xyz[1], xyz[2]);
                expected.bounds = (expected.bounds.0.min(p), expected.bounds.1.max(p));
            }
            _ => {}
        }
    }
    expected
}

/// The checks every loaded mesh must pass, whatever the file.
fn assert_well_formed(mesh: &Mesh, what: &str) {
    assert!(!mesh.triangles.is_empty(), "{what}");
    for p in &mesh.positions {
        assert!(p.is_finite() && p.abs().max_element() <= 1e6, "{what}: {p}");
    }
    for t in &mesh.triangles {
        assert!(
            t.iter().all(|&i| (i as usize) < mesh.positions.len()),
            "{what}: {t:?}"
        );
    }
    match &mesh.triangle_normals {
        Some(corners) => {
            assert_eq!(corners.len(), mesh.triangles.len(), "{what}");
            for c in corners {
                assert!(
                    c.iter().all(|&i| (i as usize) < mesh.normals.len()),
                    "{what}: {c:?}"
                );
            }
            for &i in corners.iter().flatten() {
                let n = mesh.normals[i as usize];
                assert!((n.length() - 1.0).abs() < 1e-4, "{what}: normal {n}");
            }
        }
        None => assert!(mesh.normals.is_empty(), "{what}"),
    }
}

/// The message of a refused model, checked to name the file.
fn refused(path: &Path) -> String {
    let error =
        load_obj(path, &identity()).expect_err(&format!("{} must be refused", path.display()));
    let message = error.to_string();
    let name = path.file_name().expect("file name").to_string_lossy();
    assert!(
        message.contains(&*name),
        "the message names the file: {message}"
    );
    message
}

/// The models of assimp's OBJ folder raylab refuses, each for a stated
/// reason, with what the message must say.
const REFUSED_ASSIMP_MODELS: &[(&str, &str)] = &[
    // UTF-16: every other byte is NUL.
    ("box_UTF16BE.obj", "box_UTF16BE.obj:1: a NUL byte"),
    // `v 1e+2 2.e+1 3.1+e2`: "3.1+e2" is no number (assimp reads 3.1).
    (
        "number_formats.obj",
        "number_formats.obj:11: v: \"3.1+e2\" is not a number",
    ),
    // Points and lines only: nothing a ray can hit.
    ("point_cloud.obj", "no triangles in"),
    ("testline.obj", "no triangles in"),
    ("testpoints.obj", "no triangles in"),
];

#[test]
fn real_models_load_with_the_triangles_their_faces_declare() {
    let Some(folder) = assimp_folder("OBJ") else {
        return;
    };
    let files = obj_files(&folder);
    assert!(files.len() >= 20, "{} OBJ files", files.len());
    let mut loaded = 0;
    for path in &files {
        let name = path
            .file_name()
            .expect("name")
            .to_string_lossy()
            .into_owned();
        if let Some((_, says)) = REFUSED_ASSIMP_MODELS.iter().find(|(n, _)| *n == name) {
            let message = refused(path);
            assert!(message.contains(says), "{message}");
            continue;
        }
        let mesh = load_obj(path, &identity()).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_well_formed(&mesh, &name);
        let expected = expected(path);
        assert_eq!(mesh.triangles.len(), expected.triangles, "{name}");
        assert_eq!(
            mesh.triangle_normals.is_some(),
            expected.every_corner_has_a_normal,
            "{name}"
        );
        let (low, high) = mesh.bounds().expect("triangles");
        assert!(
            low.cmpge(expected.bounds.0).all()
                && high.cmple(expected.bounds.1).all()
                && low.cmple(high).all(),
            "{name}: {low} {high} outside {:?}",
            expected.bounds
        );
        loaded += 1;
    }
    assert_eq!(loaded + REFUSED_ASSIMP_MODELS.len(), files.len());
    // The large ones, by name, with their counts written out as well.
    for (name, triangles, smooth, degenerate) in [
        ("spider.obj", 1_368, true, 56),
        ("WusonOBJ.obj", 3_732, true, 0),
        ("regr01.obj", 2_710, false, 4),
    ] {
        let mesh = load_obj(&folder.join(name), &identity()).expect(name);
        assert_eq!(mesh.triangles.len(), triangles, "{name}");
        assert_eq!(mesh.triangle_normals.is_some(), smooth, "{name}");
        assert_eq!(mesh.degenerate_triangle_count(), degenerate, "{name}");
    }
    // The spider spans about 150 x 80 x 190 units, the Wuson 1 x 1.5 x 3.2.
    let spider = load_obj(&folder.join("spider.obj"), &identity()).expect("spider");
    let (low, high) = spider.bounds().expect("triangles");
    assert!(
        (high - low).cmpgt(Vec3::new(140.0, 70.0, 180.0)).all(),
        "{low} {high}"
    );
    assert!(
        (high - low).cmplt(Vec3::new(160.0, 90.0, 200.0)).all(),
        "{low} {high}"
    );
}

#[test]
fn a_real_model_is_placed_by_its_transform() {
    let Some(folder) = assimp_folder("OBJ") else {
        return;
    };
    let path = folder.join("WusonOBJ.obj");
    let plain = load_obj(&path, &identity()).expect("load");
    let transform = MeshTransform {
        translate: Vec3::new(5.0, -2.0, 3.0),
        scale: 2.0,
        rotate_degrees: Vec3::new(0.0, 90.0, 0.0),
    };
    let placed = load_obj(&path, &transform).expect("load");
    assert_eq!(placed.triangles.len(), plain.triangles.len());
    for t in 0..plain.triangles.len() {
        for (p, q) in plain.corners(t).into_iter().zip(placed.corners(t)) {
            let want = transform.apply(p);
            assert!((want - q).abs().max_element() < 1e-4, "{want} {q}");
        }
    }
}

#[test]
fn assimps_invalid_models_are_refused_cleanly() {
    let Some(folder) = assimp_folder("invalid") else {
        return;
    };
    let files = obj_files(&folder);
    assert_eq!(files.len(), 3, "{files:?}");
    for path in &files {
        let message = refused(path);
        let name = path.file_name().expect("name").to_string_lossy();
        match &*name {
            "empty.obj" => assert!(message.contains("empty"), "{message}"),
            "malformed.obj" => assert!(
                message.contains("malformed.obj:23: face corner \"12\": vertex 12 does not exist"),
                "{message}"
            ),
            "malformed2.obj" => assert!(
                message.contains("malformed2.obj:23: a face (f) needs at least 3"),
                "{message}"
            ),
            _ => panic!("unexpected {message}"),
        }
    }
    // Every other file there is not OBJ at all, and is refused too.
    for entry in std::fs::read_dir(&folder).expect("list") {
        let path = entry.expect("entry").path();
        if path.is_file() && !files.contains(&path) {
            refused(&path);
        }
    }
}

/// A folder of small models written by the tests themselves.
struct Models {
    folder: tempfile::TempDir,
}

impl Models {
    fn new() -> Models {
        Models {
            folder: tempfile::tempdir().expect("temporary folder"),
        }
    }

    fn write(&self, name: &str, text: impl AsRef<[u8]>) -> PathBuf {
        let path = self.folder.path().join(name);
        std::fs::write(&path, text).expect("write a model");
        path
    }
}

const CUBE: &str = "\
# a unit cube, six quads
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
";

/// Every edge of the mesh between exactly two triangles, in opposite
/// directions.
fn is_closed(mesh: &Mesh) -> bool {
    let mut edges = std::collections::HashMap::new();
    for &[a, b, c] in &mesh.triangles {
        for edge in [(a, b), (b, c), (c, a)] {
            *edges.entry(edge).or_insert(0) += 1;
        }
    }
    edges
        .iter()
        .all(|(&(a, b), &count)| count == 1 && edges.get(&(b, a)) == Some(&1))
}

#[test]
fn a_cube_of_quads_is_twelve_triangles_closed_and_flat() {
    let models = Models::new();
    let cube = load_obj(&models.write("cube.obj", CUBE), &identity()).expect("cube");
    assert_eq!(cube.triangles.len(), 12);
    assert_eq!(cube.positions.len(), 8);
    assert_eq!(cube.bounds(), Some((Vec3::splat(-1.0), Vec3::splat(1.0))));
    assert_eq!(cube.degenerate_triangle_count(), 0);
    assert!(cube.triangle_normals.is_none());
    assert!(is_closed(&cube));
    // The fan of "f 1 4 3 2": (1, 4, 3) and (1, 3, 2), wound as written.
    assert_eq!(
        cube.corners(0),
        [
            Vec3::splat(-1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(1.0, 1.0, -1.0)
        ]
    );
    // Outward: the normal of the first face (z = -1) points to -z.
    let [a, b, c] = cube.corners(0);
    assert!((b - a).cross(c - a).z < 0.0);
    // Windows line endings and a byte-order mark (before the first vertex)
    // change nothing.
    let without_comment = CUBE.split_once('\n').expect("lines").1;
    let crlf = format!("\u{feff}{}", without_comment.replace('\n', "\r\n"));
    let again = load_obj(&models.write("crlf.obj", crlf), &identity()).expect("crlf");
    assert_eq!(again, cube);
    // Neither do names in Latin-1, or material lines naming missing files.
    let latin = [
        b"g Terraind\xe6k\nmtllib /no/such.mtl\nusemtl \xe6\n".as_slice(),
        CUBE.as_bytes(),
    ]
    .concat();
    let again = load_obj(&models.write("latin.obj", latin), &identity()).expect("latin-1 names");
    assert_eq!(again, cube);
    // Polylines are not faces.
    let lines = format!("{CUBE}l 1 2 3 4\nl 5 6 7\np 1 2 3\n");
    let again = load_obj(&models.write("lines.obj", lines), &identity()).expect("lines");
    assert_eq!(again.triangles.len(), 12);
}

#[test]
fn negative_indices_count_back_from_the_latest_vertex() {
    let models = Models::new();
    let positive = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nv 0 0 5\nf 1 2 5\n";
    let negative = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\nv 0 0 5\nf -5 -4 -1\n";
    let a = load_obj(&models.write("positive.obj", positive), &identity()).expect("positive");
    let b = load_obj(&models.write("negative.obj", negative), &identity()).expect("negative");
    assert_eq!(a.triangles.len(), 3);
    for t in 0..3 {
        assert_eq!(a.corners(t), b.corners(t), "triangle {t}");
    }
    assert_eq!(
        b.corners(2),
        [Vec3::ZERO, Vec3::X, Vec3::new(0.0, 0.0, 5.0)]
    );
}

#[test]
fn vertex_normals_are_kept_only_when_every_corner_has_one() {
    let models = Models::new();
    let smooth = "vt 0 0\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 2\nvn 0 1 1\n\
                  f 1//1 2//1 3//2\nf 2/1/2 4/1/2 3/1/1\n";
    let mesh = load_obj(&models.write("smooth.obj", smooth), &identity()).expect("smooth");
    assert_well_formed(&mesh, "smooth");
    let corners = mesh.triangle_normals.as_ref().expect("vertex normals");
    let normal = |t: usize, k: usize| mesh.normals[corners[t][k] as usize];
    assert_eq!(normal(0, 0), Vec3::Z);
    assert!((normal(0, 2) - Vec3::new(0.0, 1.0, 1.0).normalize()).length() < 1e-6);
    assert_eq!(normal(1, 2), Vec3::Z);
    // Rotated with the model: +Z turns to +X about Y.
    let turned = MeshTransform {
        rotate_degrees: Vec3::new(0.0, 90.0, 0.0),
        ..identity()
    };
    let mesh = load_obj(&models.write("smooth.obj", smooth), &turned).expect("smooth");
    let corners = mesh.triangle_normals.as_ref().expect("vertex normals");
    assert!((mesh.normals[corners[0][0] as usize] - Vec3::X).length() < 1e-6);
    // One corner without a normal: flat shading for the whole model.
    let mixed = smooth.replace("3//2", "3");
    let mesh = load_obj(&models.write("mixed.obj", mixed), &identity()).expect("mixed");
    assert!(mesh.triangle_normals.is_none() && mesh.normals.is_empty());
    // A zero normal cannot shade: its corners get their triangle's normal.
    let zero = smooth.replace("vn 0 1 1", "vn 0 0 0");
    let mesh = load_obj(&models.write("zero.obj", zero), &identity()).expect("zero normal");
    assert_well_formed(&mesh, "zero normal");
    let corners = mesh.triangle_normals.as_ref().expect("vertex normals");
    assert_eq!(mesh.normals[corners[0][2] as usize], Vec3::Z);
    assert_eq!(mesh.normals[corners[1][0] as usize], Vec3::Z);
    assert_eq!(mesh.normals[corners[1][2] as usize], Vec3::Z);
}

#[test]
fn broken_models_are_refused_naming_the_file_and_line() {
    let models = Models::new();
    let triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let cases: &[(&str, String, &str)] = &[
        (
            "range.obj",
            format!("{triangle}f 1 2 4\n"),
            "range.obj:4: face corner \"4\": vertex 4 does not exist (3 declared",
        ),
        (
            "zero.obj",
            format!("{triangle}f 0 1 2\n"),
            "zero.obj:4: face corner \"0\": index 0",
        ),
        (
            "back.obj",
            format!("{triangle}f -1 -2 -4\n"),
            "back.obj:4: face corner \"-4\": vertex -4 does not exist",
        ),
        // i64::MIN: its negation overflows (a panic in a debug build).
        (
            "most-negative.obj",
            format!("{triangle}f 1 2 -9223372036854775808\n"),
            "most-negative.obj:4: face corner \"-9223372036854775808\": vertex \
             -9223372036854775808 does not exist",
        ),
        (
            "ahead.obj",
            format!("v 0 0 0\nf 1 2 3\n{triangle}"),
            "ahead.obj:2: face corner \"2\"",
        ),
        (
            "short.obj",
            format!("{triangle}f 1 2\n"),
            "short.obj:4: a face (f) needs at least 3 corners, this one has 2",
        ),
        (
            "bare.obj",
            format!("{triangle}f\n"),
            "bare.obj:4: a face (f) needs at least 3 corners, this one has 0",
        ),
        (
            "nan.obj",
            "v 0 0 0\nv 1 nan 2\nv 0 1 0\nf 1 2 3\n".into(),
            "nan.obj:2: vertex [1, NaN, 2] is not finite",
        ),
        (
            "inf.obj",
            "v 0 0 inf\n".into(),
            "inf.obj:1: vertex [0, 0, inf] is not finite",
        ),
        (
            "overflow.obj",
            "v 0 0 1e39\n".into(),
            "overflow.obj:1: v: 1e39 is too large for a 32-bit float",
        ),
        (
            "normal-overflow.obj",
            format!("{triangle}vn 0 -1e40 0\n"),
            "normal-overflow.obj:4: vn: -1e40 is too large for a 32-bit float",
        ),
        (
            "huge-index.obj",
            format!("{triangle}f 1 2 99999999999999999999\n"),
            "huge-index.obj:4: face corner \"99999999999999999999\": vertex \
             99999999999999999999 does not exist (3 declared",
        ),
        (
            "word.obj",
            "v 0 zero 0\n".into(),
            "word.obj:1: v: \"zero\" is not a number",
        ),
        ("two.obj", "v 0 0\n".into(), "two.obj:1: v needs 3 numbers"),
        (
            "weight.obj",
            "v 1 1 1 0\n".into(),
            "weight.obj:1: v: a weight of 0",
        ),
        (
            "far.obj",
            format!("{triangle}v 2e6 0 0\n"),
            "far.obj:4: vertex [2000000, 0, 0] lands at",
        ),
        (
            "normal.obj",
            format!("{triangle}vn 0 nan 1\n"),
            "normal.obj:4: normal [0, NaN, 1] is not finite",
        ),
        (
            "normal-index.obj",
            format!("{triangle}vn 0 0 1\nf 1//1 2//2 3//1\n"),
            "normal-index.obj:5: face corner \"2//2\": normal 2 does not exist",
        ),
        (
            "texture.obj",
            format!("{triangle}f 1/1 2/1 3/1\n"),
            "texture.obj:4: face corner \"1/1\": texture coordinate 1 does not exist",
        ),
        (
            "slashes.obj",
            format!("{triangle}f 1/1/1/1 2 3\n"),
            "slashes.obj:4: face corner \"1/1/1/1\": at most three",
        ),
        (
            "letters.obj",
            format!("{triangle}f 1 b 3\n"),
            "letters.obj:4: face corner \"b\": \"b\" is not a whole number",
        ),
        (
            "novertex.obj",
            format!("{triangle}f /1 2 3\n"),
            "novertex.obj:4: face corner \"/1\" has no vertex index",
        ),
        ("vt.obj", "vt 0\n".into(), "vt.obj:1: vt needs 2 numbers"),
        ("points.obj", triangle.into(), "no triangles in"),
        ("comments.obj", "# nothing\n\n".into(), "no triangles in"),
        (
            "latin.obj",
            "v 0 0 0\nv 1\u{0} 0 0\n".into(),
            "latin.obj:2: a NUL byte",
        ),
    ];
    for (name, text, says) in cases {
        let message = refused(&models.write(name, text));
        assert!(message.contains(says), "{name}: {message}");
    }
    // A number in Latin-1 is refused (never guessed at).
    let message = refused(&models.write("bytes.obj", b"v 0 0 0\nv 1 \xb2 0\n"));
    assert!(message.contains("bytes.obj:2: not UTF-8 text"), "{message}");
    let message = refused(&models.write("empty.obj", ""));
    assert!(
        message.contains("empty.obj: the file is empty"),
        "{message}"
    );
    // The transform itself.
    let good = models.write("good.obj", format!("{triangle}f 1 2 3\n"));
    let flat = MeshTransform {
        scale: 0.0,
        ..identity()
    };
    assert!(matches!(
        load_obj(&good, &flat),
        Err(MeshError::Transform(_))
    ));
    // A vertex within the limit that a scale takes past it.
    let far = models.write("scaled.obj", "v 0 0 0\nv 1 0 0\nv 0 6e5 0\nf 1 2 3\n");
    assert!(load_obj(&far, &identity()).is_ok());
    let twice = MeshTransform {
        scale: 2.0,
        ..identity()
    };
    let message = load_obj(&far, &twice).expect_err("too far").to_string();
    assert!(
        message.contains("scaled.obj:3: vertex [0, 600000, 0] lands at [0, 1200000, 0]"),
        "{message}"
    );
}

#[test]
fn degenerate_triangles_are_kept_and_counted() {
    let models = Models::new();
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\nf 1 2 4\n";
    let mesh = load_obj(&models.write("flat.obj", text), &identity()).expect("load");
    assert_eq!(mesh.triangles.len(), 3);
    assert_eq!(mesh.degenerate_triangle_count(), 2);
}

#[test]
fn only_regular_files_are_read_and_never_past_the_limits() {
    let models = Models::new();
    let message = refused(models.folder.path());
    assert!(message.contains("folder"), "{message}");
    let message = refused(&models.folder.path().join("missing.obj"));
    assert!(message.contains("no such file"), "{message}");
    // Over the size limit: refused from its size alone (a sparse file).
    let big = models.write("big.obj", "");
    std::fs::File::options()
        .write(true)
        .open(&big)
        .and_then(|file| file.set_len(MAX_OBJ_BYTES + 1))
        .expect("grow");
    let message = refused(&big);
    assert!(message.contains("at most 268435456 bytes"), "{message}");
    // One face of more than the triangle limit's corners: refused on that
    // line, before any model is built.
    let mut huge = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
    for _ in 0..MAX_MESH_TRIANGLES + 3 {
        huge.push_str(" 1");
    }
    let message = refused(&models.write("huge.obj", huge));
    assert!(
        message.contains("huge.obj:4: more than 4000000 triangles"),
        "{message}"
    );
    #[cfg(unix)]
    {
        let cube = models.write("cube.obj", CUBE);
        let link = models.folder.path().join("link.obj");
        std::os::unix::fs::symlink(&cube, &link).expect("symlink");
        assert_eq!(
            load_obj(&link, &identity())
                .expect("through the link")
                .triangles
                .len(),
            12
        );
        let fifo = models.folder.path().join("fifo.obj");
        let made = Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|status| status.success()) {
            // No writer: reading it would block forever, so it must be
            // refused before a byte is read.
            let message = refused(&fifo);
            assert!(message.contains("FIFO"), "{message}");
        }
        let message = load_obj(Path::new("/dev/zero"), &identity())
            .expect_err("a device")
            .to_string();
        assert!(message.contains("character device"), "{message}");
    }
}

/// A small deterministic generator (xorshift), so a failure can be replayed.
struct Random(u64);

impl Random {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

#[test]
fn random_text_and_bytes_never_panic() {
    let models = Models::new();
    let mut random = Random(0x9e37_79b9_7f4a_7c15);
    let words = [
        "v",
        "vn",
        "vt",
        "f",
        "l",
        "p",
        "o",
        "g",
        "s",
        "usemtl",
        "mtllib",
        "#",
        "1",
        "2",
        "3",
        "-1",
        "-2",
        "0",
        "4",
        "99999999999999999999",
        "1/1",
        "1//1",
        "2/2/2",
        "/",
        "//",
        "1.5",
        "-0.25",
        "nan",
        "inf",
        "-inf",
        "1e38",
        "1e39",
        "2e6",
        "x",
        "\u{feff}",
        "\t",
        "é",
        "\\",
    ];
    let mut loaded = 0;
    for case in 0..600 {
        let mut text = String::new();
        // Often a valid start, so that faces have vertices to refer to.
        if random.below(2) == 0 {
            text.push_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n");
        }
        let lines = [
            "f 1 2 3",
            "f -1 -2 -3",
            "f 1//1 2//1 3//1",
            "f 1/1/1 2/1/1 3/1/1",
            "f 3 2 1 -1",
            "v 0.5 0.5 2",
            "vn 1 0 0",
            "f 1 2 3 4 5 6",
        ];
        for _ in 0..random.below(12) {
            if random.below(3) == 0 {
                text.push_str(lines[random.below(lines.len() as u64) as usize]);
                text.push(' ');
            }
            for _ in 0..random.below(4) {
                text.push_str(words[random.below(words.len() as u64) as usize]);
                text.push(' ');
            }
            text.push(if random.below(8) == 0 { '\r' } else { '\n' });
        }
        let path = models.write(&format!("text-{case}.obj"), &text);
        match load_obj(&path, &identity()) {
            Ok(mesh) => {
                assert_well_formed(&mesh, &text);
                loaded += 1;
            }
            Err(error) => assert!(
                error.to_string().contains(&format!("text-{case}.obj")),
                "{error}"
            ),
        }
    }
    // Some of the soup must be valid, or the Ok branch is never checked.
    assert!(loaded > 10, "{loaded} loaded");
    for case in 0..200 {
        let length = random.below(4096) as usize;
        let bytes: Vec<u8> = (0..length).map(|_| random.next() as u8).collect();
        let path = models.write(&format!("bytes-{case}.obj"), &bytes);
        refused(&path);
    }
}

// ---- raylab mesh ----------------------------------------------------------

fn names_in(folder: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(folder)
        .expect("list")
        .map(|entry| {
            entry
                .expect("entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names
}

#[test]
fn raylab_mesh_writes_a_closed_model_that_loads_back() {
    let folder = tempfile::tempdir().expect("temporary folder");
    let out = raylab(
        &["mesh", "--triangles", "1000", "-o", "torus.obj"],
        folder.path(),
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("1008 triangles") && stdout.contains("torus.obj"),
        "{stdout}"
    );
    let path = folder.path().join("torus.obj");
    let first = std::fs::read(&path).expect("written");
    let mesh = load_obj(&path, &identity()).expect("loads");
    assert_eq!(mesh.triangles.len(), 1008);
    assert!(is_closed(&mesh));
    assert!(mesh.triangle_normals.is_some());
    assert_eq!(mesh.degenerate_triangle_count(), 0);
    // Again: raylab replaces its own file, with the same bytes.
    let out = raylab(
        &["mesh", "--triangles", "1000", "-o", "torus.obj"],
        folder.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(std::fs::read(&path).expect("written"), first);
    assert_eq!(names_in(folder.path()), ["torus.obj"]);
    // The smallest model.
    let out = raylab(
        &["mesh", "--triangles", "1", "-o", "tiny.obj"],
        folder.path(),
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("18 triangles"));
}

#[test]
fn raylab_mesh_refuses_bad_input_and_writes_nothing() {
    let folder = tempfile::tempdir().expect("temporary folder");
    std::fs::create_dir(folder.path().join("sub.obj")).expect("folder");
    std::fs::write(folder.path().join("mine.obj"), "my own model\n").expect("write");
    let cases: &[(&[&str], &str)] = &[
        (&["--triangles", "0", "-o", "a.obj"], "from 1 to 16000000"),
        (
            &["--triangles", "16000001", "-o", "a.obj"],
            "from 1 to 16000000",
        ),
        (
            &["--triangles", "99999999999999999999999", "-o", "a.obj"],
            "from 1 to 16000000",
        ),
        (&["--triangles", "-5", "-o", "a.obj"], "from 1 to 16000000"),
        (&["--triangles", "1e3", "-o", "a.obj"], "whole number"),
        (&["--triangles", "100", "-o", "a.txt"], "ending in .obj"),
        (
            &["--triangles", "100", "-o", "missing/a.obj"],
            "does not exist",
        ),
        (&["--triangles", "100", "-o", "sub.obj"], "folder"),
        (
            &["--triangles", "100", "-o", "mine.obj"],
            "raylab did not write it",
        ),
        (&["--triangles", "100"], "--output"),
    ];
    for (args, says) in cases {
        let out = raylab(&[&["mesh"], *args].concat(), folder.path());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
        assert_eq!(names_in(folder.path()), ["mine.obj", "sub.obj"], "{args:?}");
    }
    assert_eq!(
        std::fs::read_to_string(folder.path().join("mine.obj")).expect("kept"),
        "my own model\n"
    );
    // With --force it is replaced.
    let out = raylab(
        &["mesh", "--triangles", "100", "-o", "mine.obj", "--force"],
        folder.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mesh = load_obj(&folder.path().join("mine.obj"), &identity()).expect("loads");
    assert_eq!(mesh.triangles.len(), 104);
}

#[cfg(unix)]
#[test]
fn raylab_mesh_in_a_read_only_folder_fails_cleanly() {
    use std::os::unix::fs::PermissionsExt;
    let folder = tempfile::tempdir().expect("temporary folder");
    let locked = folder.path().join("locked");
    std::fs::create_dir(&locked).expect("folder");
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).expect("chmod");
    // Root may write anyway; then there is nothing to test.
    if std::fs::write(locked.join("probe"), "").is_ok() {
        eprintln!("SKIPPED: running as root, a read-only folder accepts files");
        return;
    }
    let out = raylab(
        &["mesh", "--triangles", "100", "-o", "locked/a.obj"],
        folder.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot create a file"));
    assert!(names_in(&locked).is_empty());
}

/// A scene file names its OBJ model relative to itself, wherever raylab is
/// run from; a missing or broken model is an error naming the file (and
/// the line), with exit status 2 and no image.
#[test]
fn a_scene_loads_its_obj_model_from_its_own_folder() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scenes = dir.path().join("scenes");
    std::fs::create_dir(&scenes).expect("mkdir");
    std::fs::write(
        scenes.join("tetra.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .expect("write obj");
    std::fs::write(scenes.join("broken.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 9\n").expect("write");
    let scene = |obj: &str| {
        format!(
            "[camera]\nposition = [0.3, 0.3, -3.0]\nlook_at = [0.3, 0.3, 0.0]\n\
             [[lights]]\nposition = [-2.0, 3.0, -3.0]\n\
             [[objects]]\nname = \"tetra\"\nmesh = {{ obj = \"{obj}\", scale = 1.5 }}\n"
        )
    };
    std::fs::write(scenes.join("good.toml"), scene("tetra.obj")).expect("write");
    std::fs::write(scenes.join("missing.toml"), scene("nowhere.obj")).expect("write");
    std::fs::write(scenes.join("bad.toml"), scene("broken.obj")).expect("write");
    let render = |name: &str| {
        raylab(
            &[
                "render",
                "--scene",
                &format!("scenes/{name}"),
                "--chapter",
                "10",
                "--width",
                "32",
                "--height",
                "24",
                "-o",
                "out.png",
                "--force",
            ],
            dir.path(),
        )
    };
    let good = render("good.toml");
    assert_eq!(
        good.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&good.stderr)
    );
    let image = image::open(dir.path().join("out.png"))
        .expect("a PNG")
        .to_rgb8();
    let background = *image.get_pixel(0, 0);
    assert!(
        image.pixels().any(|pixel| *pixel != background),
        "the model is drawn"
    );
    std::fs::remove_file(dir.path().join("out.png")).expect("rm");
    for (name, says) in [
        ("missing.toml", "nowhere.obj"),
        ("bad.toml", "broken.obj:3"),
    ] {
        let out = render(name);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
        assert!(stderr.contains(says), "{name}: {stderr}");
        assert!(!dir.path().join("out.png").exists(), "{name}: no image");
    }
}
