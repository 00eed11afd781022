//! `raylab new`: a student workspace, generated from the reference chapters.
//!
//! A workspace is a small crate that depends on this raylab checkout: one
//! file per chapter of [`crate::chapters::CHAPTERS`] where the student writes
//! that chapter's functions, a type `Mine` that implements
//! [`crate::course::Chapters`] with them, a three-line `main` that runs
//! raylab's command line with `Mine`, and a test per chapter that runs
//! raylab's checks.
//!
//! The skeletons are cut from the reference chapter files themselves (one
//! source of truth): each function the registry lists keeps its doc comment
//! and signature, and its body becomes `todo!("chapter N: name")`, the text
//! [`crate::cli`] recognises to report "chapter N not started". The
//! lesson's helpers (constants, helper functions) are left out for the
//! student to write as they like; the answer key (`--solutions`) keeps the
//! whole reference file but its tests and its lesson include.

pub mod scan;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::chapters::{CHAPTERS, ChapterInfo};
use scan::{ItemKind, ScanError};

/// Why a workspace was not made. The folder's problems name it, the I/O
/// errors name the path; each message is whole (the system's reason
/// included, no `source`), as [`crate::output::OutputError`]'s are.
#[derive(Debug, thiserror::Error)]
pub enum WorkspaceError {
    #[error("the raylab folder's path is not valid UTF-8")]
    RaylabPathNotUtf8,
    /// The checkout a workspace depends on is gone (the binary names where
    /// it was built).
    #[error(
        "this raylab was built from {}, which is no longer there; a workspace depends on \
         that checkout: rebuild raylab where it now is",
        dir.display()
    )]
    RaylabMissing { dir: PathBuf },
    /// `action` is what was tried on `path`: "read", "resolve", "create",
    /// "write in" or "write".
    #[error("cannot {action} {}: {error}", path.display())]
    Io {
        action: &'static str,
        path: PathBuf,
        error: std::io::Error,
    },
    #[error("{} exists and is not empty: choose a new folder", dir.display())]
    NotEmpty { dir: PathBuf },
    #[error("{} exists and is not a folder", dir.display())]
    NotAFolder { dir: PathBuf },
    #[error("the folder needs a name in UTF-8")]
    NoName,
    #[error("cannot make a workspace at the root of the file system")]
    AtRoot,
    /// `src/chapters/mod.rs` could not be written from the trait.
    #[error(transparent)]
    Bridge(#[from] SkeletonError),
    /// The chapter file at `path` could not be cut into a skeleton.
    #[error("cannot cut {path} into a skeleton: {error}")]
    Skeleton { path: String, error: SkeletonError },
}

/// Why raylab's own sources (a chapter file, `src/course.rs`) could not be
/// cut into a workspace's files: each names the function or file at fault.
#[derive(Debug, thiserror::Error)]
pub enum SkeletonError {
    /// `file` names the text that was scanned: a path or "trait Chapters".
    #[error("{file}: {error}")]
    Scan { file: String, error: ScanError },
    /// A chapter file that does not scan; the caller names the file.
    #[error("{0}")]
    Items(ScanError),
    #[error("chapter {chapter} lists `{function}`, which is not a method of Chapters")]
    NotAMethod { chapter: u8, function: String },
    #[error("`{function}`'s signature: {error}")]
    Signature { function: String, error: ScanError },
    #[error("`{function}`'s generics: {error}")]
    Generics { function: String, error: ScanError },
    #[error("{path} has no function `{function}`")]
    NoFunctionIn { path: String, function: String },
    /// The chapter file being cut lacks a function the registry lists for it.
    #[error("it has no function `{function}`")]
    NoFunction { function: String },
    #[error(
        "`{function}`'s type parameter `{parameter}` is not the chapters (`Chapters`), and a \
         workspace cannot name it"
    )]
    ForeignTypeParameter { function: String, parameter: String },
    #[error("src/course.rs has no trait Chapters")]
    NoChaptersTrait,
    #[error("a method without a name")]
    UnnamedMethod,
}

/// The error for `action` on `path`, for `map_err`.
fn io_error<'a>(
    action: &'static str,
    path: &'a Path,
) -> impl FnOnce(std::io::Error) -> WorkspaceError + 'a {
    move |error| WorkspaceError::Io {
        action,
        path: path.to_path_buf(),
        error,
    }
}

/// The student workspace that `dir` is in, if any: the first `Cargo.toml`
/// found from `dir` upwards, when it is a package that depends on raylab
/// (what `raylab new` makes). raylab's own checkout is not one.
pub fn enclosing_workspace(dir: &Path) -> Option<PathBuf> {
    let manifest = dir
        .ancestors()
        .map(|folder| folder.join("Cargo.toml"))
        .find(|path| path.is_file())?;
    let bytes =
        crate::input::read_bounded(&manifest, 1 << 20, "manifest", crate::input::Links::Follow)
            .ok()?;
    let value: toml::Table = String::from_utf8(bytes).ok()?.parse().ok()?;
    let package = value.get("package")?.get("name")?.as_str()?;
    let depends_on_raylab = value
        .get("dependencies")
        .and_then(|dependencies| dependencies.get("raylab"))
        .is_some();
    (package != "raylab" && depends_on_raylab).then(|| manifest.parent().map(Path::to_path_buf))?
}

/// The raylab checkout this binary was built from: the workspace's path
/// dependency.
pub const RAYLAB_DIR: &str = env!("CARGO_MANIFEST_DIR");

/// raylab's lock file: a workspace starts from it so that it resolves to the
/// same versions, offline.
const RAYLAB_LOCK: &str = include_str!("../../Cargo.lock");

/// The trait a workspace implements, read for its signatures.
const COURSE_SOURCE: &str = include_str!("../course.rs");

/// The student's type, in the workspace's `src/lib.rs`.
pub const STUDENT_TYPE: &str = "Mine";

/// Names cargo or the workspace itself cannot use as a package name.
const RESERVED: &[&str] = &[
    "raylab",
    "test",
    "std",
    "core",
    "alloc",
    "proc_macro",
    "as",
    "async",
    "await",
    "box",
    "break",
    "const",
    "continue",
    "crate",
    "dyn",
    "else",
    "enum",
    "extern",
    "false",
    "fn",
    "for",
    "gen",
    "if",
    "impl",
    "in",
    "let",
    "loop",
    "match",
    "mod",
    "move",
    "mut",
    "pub",
    "ref",
    "return",
    "self",
    "static",
    "struct",
    "super",
    "trait",
    "true",
    "try",
    "type",
    "unsafe",
    "use",
    "where",
    "while",
    "yield",
];

/// The package name for a workspace in folder `folder`: its letters and
/// digits, lowercase, other characters as `-`, and a prefix or suffix when
/// that alone is not a valid name (empty, leading digit, a keyword, or
/// `raylab`, which the workspace depends on).
pub fn package_name(folder: &str) -> String {
    let mut name = String::new();
    for c in folder.chars() {
        if c.is_ascii_alphanumeric() {
            name.push(c.to_ascii_lowercase());
        } else if c == '_' || !name.ends_with(['-', '_']) && !name.is_empty() {
            name.push(if c == '_' { '_' } else { '-' });
        }
    }
    let name = name.trim_end_matches(['-', '_']).to_string();
    if name.is_empty() || name.starts_with(|c: char| c.is_ascii_digit()) {
        format!("raytracer-{name}")
            .trim_end_matches('-')
            .to_string()
    } else if RESERVED.contains(&name.replace('-', "_").as_str()) {
        format!("{name}-course")
    } else {
        name
    }
}

/// The workspace's files, as (path relative to the workspace, contents).
#[derive(Debug, Clone)]
pub struct Files(pub Vec<(String, String)>);

impl Files {
    /// The contents of `path`, if the workspace has it.
    pub fn get(&self, path: &str) -> Option<&str> {
        self.0
            .iter()
            .find(|(name, _)| name == path)
            .map(|(_, text)| text.as_str())
    }
}

/// The chapter and function a skeleton's `todo!("chapter N: name")` names,
/// from what its panic message says after "not yet implemented".
pub fn todo_names(rest: &str) -> Option<(&'static ChapterInfo, String)> {
    let (number, function) = rest
        .trim_start_matches(':')
        .trim()
        .strip_prefix("chapter ")?
        .split_once(": ")?;
    let info = crate::chapters::chapter(number.parse().ok()?)?;
    Some((info, function.to_string()))
}

/// What a student is told of a chapter not started: the function to write
/// (or "the function"), and where.
pub fn not_started_message(info: &ChapterInfo, function: Option<&str>) -> String {
    format!(
        "chapter {} not started: {} in src/chapters/{}.rs\n\
         (a chapter's stage runs your functions of every chapter up to it)",
        info.number,
        function.map_or_else(
            || "write the function".to_string(),
            |function| format!("write {function}")
        ),
        info.module()
    )
}

/// The crate that builds a workspace's chapters for the browser page: a
/// `cdylib` depending on the workspace's package `package` at `workspace`
/// and on the raylab at `raylab_dir` (its `student` feature on), exporting
/// the page's functions for `chapters_type` (the workspace's chapters, as
/// `my_course::Mine`). `raylab web` writes it in the workspace's `target/`
/// and builds it with raylab's scripts/build-web.sh.
pub fn web_crate(
    workspace: &Path,
    package: &str,
    chapters_type: &str,
    raylab_dir: &Path,
) -> Result<Files, WorkspaceError> {
    let text = |path: &Path| {
        path.to_str()
            .map(|text| toml::Value::String(text.to_string()).to_string())
            .ok_or(WorkspaceError::RaylabPathNotUtf8)
    };
    let (raylab, student) = (text(raylab_dir)?, text(workspace)?);
    let key = toml::Value::String(package.to_string());
    let cargo_toml = format!(
        r#"[package]
name = "raylab-web-page"
version = "0.1.0"
edition = "2024"
publish = false

[lib]
crate-type = ["cdylib"]
path = "lib.rs"

[dependencies]
raylab = {{ path = {raylab}, features = ["student"] }}
{key} = {{ path = {student} }}

[workspace]

[profile.release]
panic = "abort"
opt-level = 3
"#
    );
    let lib_rs = format!(
        "//! Your chapters for raylab's browser page (written by `raylab web`).\n\n\
         raylab::web_exports!({chapters_type});\n"
    );
    Ok(Files(vec![
        ("Cargo.toml".to_string(), cargo_toml),
        ("lib.rs".to_string(), lib_rs),
    ]))
}

/// The files of a workspace whose package is `package`, depending on the
/// raylab at `raylab_dir`: with `todo!()` bodies, or the reference bodies
/// when `solutions` is set.
pub fn files(package: &str, raylab_dir: &Path, solutions: bool) -> Result<Files, WorkspaceError> {
    let lib = package.replace('-', "_");
    let raylab_dir_text = raylab_dir
        .to_str()
        .ok_or(WorkspaceError::RaylabPathNotUtf8)?;
    let mut files = vec![
        (
            "Cargo.toml".to_string(),
            cargo_toml(package, raylab_dir_text),
        ),
        ("Cargo.lock".to_string(), RAYLAB_LOCK.to_string()),
        // `web/` is the page `raylab web` builds: 25 MB, made again at will.
        (".gitignore".to_string(), "/target\n/web\n".to_string()),
        (
            "README.md".to_string(),
            readme(package, raylab_dir_text, solutions),
        ),
        (
            "src/main.rs".to_string(),
            format!(
                "fn main() {{\n    std::process::exit(raylab::cli::main_with::<{lib}::{STUDENT_TYPE}>())\n}}\n"
            ),
        ),
        ("src/lib.rs".to_string(), lib_rs(solutions)),
        ("src/chapters/mod.rs".to_string(), chapters_mod_rs()?),
        ("tests/check.rs".to_string(), check_tests(package)),
    ];
    for info in CHAPTERS {
        let text = chapter_file(info, raylab_dir_text, solutions).map_err(|error| {
            WorkspaceError::Skeleton {
                path: info.code_path(),
                error,
            }
        })?;
        files.push((format!("src/chapters/{}.rs", info.module()), text));
    }
    Ok(Files(files))
}

fn cargo_toml(package: &str, raylab_dir: &str) -> String {
    // A TOML string, escaped: a path may hold quotes or backslashes.
    let path = toml::Value::String(raylab_dir.to_string());
    format!(
        r#"[package]
name = "{package}"
version = "0.1.0"
edition = "2024"
publish = false

[dependencies]
# The raylab this workspace was made from, as a student's dependency (its
# `student` feature keeps raylab's own answers out of reach; the check
# refuses a build without it). A class can share one copy
# instead (path = "/opt/raylab"), or use a tagged release
# (git = "https://example.org/raylab.git", tag = "v0.1.0"): see raylab's
# README, "Take the course".
raylab = {{ path = {path}, features = ["student"] }}
# The reference solutions of chapters 2 and 8 use it (exact ldexp, asin).
libm = "0.2"

# This crate is its own workspace, even inside another project's folder.
[workspace]

# Renders in debug builds take seconds rather than minutes, and the images
# are the same bit for bit (Rust never reorders float arithmetic).
[profile.dev]
opt-level = 1

[profile.dev.package."*"]
opt-level = 2

# raylab's renderer is generic over your chapters, so it is compiled again
# in this crate at each change: incremental builds recompile only what the
# change touched, which brings a chapter's verdict within a second or two
# of saving it instead of ten. The images are the same, but renders run
# slower (about 1.4 times): for a long render, turn it off for that run,
# `CARGO_PROFILE_RELEASE_INCREMENTAL=false cargo run --release -- render ...`.
# (raylab's scripts/edit-to-verdict.sh measures both.)
[profile.release]
incremental = true
"#
    )
}

fn readme(package: &str, raylab_dir: &str, solutions: bool) -> String {
    let mut chapters = String::new();
    for info in CHAPTERS {
        let _ = writeln!(
            chapters,
            "| {} | {} | `src/chapters/{}.rs` | {} |",
            info.number,
            info.title,
            info.module(),
            info.functions
                .iter()
                .map(|f| format!("`{f}`"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let state = if solutions {
        "This copy holds raylab's reference solutions: it is the answer key, \
         for instructors. A student's copy comes from `raylab new DIR` without \
         `--solutions`."
    } else {
        "Every function starts as `todo!()`: a chapter you have not started \
         is reported as \"not started\", never as a crash."
    };
    format!(
        r#"# {package}: your ray tracer

Made by `raylab new`. You write each chapter of the raylab course here, and
raylab renders and checks your code. {state}

## The loop

```sh
cargo run --release -- render --chapter 1      # writes chapter-1.png with your code
cargo run --release -- check --chapter 1       # the verdict: cases, image, robustness
cargo test                                     # the same checks, one test per chapter
cargo test chapter_01                          # chapter 1's alone
cargo run --release -- trace --chapter 1 --pixel 320,240   # every ray of one pixel, with your code
cargo run --release -- web                     # the browser page of your chapters, in web/
```

Chapter N's image needs your chapters 1 to N. The binary has every
subcommand of `raylab` (`render`, `diff`, `bench`, `probe`, ...), all
running your code: `cargo run --release -- --help`.

## The chapters

| chapter | title | your file | functions |
|---|---|---|---|
{chapters}
Each lesson is `chapters/NN_name/lesson.md` in raylab ({raylab_dir}), and in
`cargo doc --open` under `raylab::chapters`. Start each file by reading its
lesson's "Your turn".

`src/chapters/mod.rs` connects raylab to your functions; you should not need
to edit it, `src/main.rs` or `tests/check.rs`. Helpers of your own (constants,
small functions) go in your chapter files.
"#
    )
}

fn lib_rs(solutions: bool) -> String {
    let whose = if solutions {
        "raylab's reference solutions (the answer key)"
    } else {
        "your code"
    };
    format!(
        r#"//! Your ray tracer: the chapters of the raylab course, as you write them.
//!
//! `src/chapters/` holds one file per chapter ({whose}). raylab's renderer,
//! command line and checks reach them through [`{STUDENT_TYPE}`].

// raylab writes `!(x > y)` for "not greater, or NaN" on purpose (the lessons
// explain it); clippy would ask for `partial_cmp` instead.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// No chapter needs unsafe code, and `raylab grade --code` does not count a
// workspace that has some.
#![forbid(unsafe_code)]

pub mod chapters;

/// Your chapters: the type raylab runs (`raylab::cli::main_with::<{STUDENT_TYPE}>()` in
/// `src/main.rs`, which `tests/check.rs` asks).
#[derive(Debug, Clone, Copy, Default)]
pub struct {STUDENT_TYPE};
"#
    )
}

fn check_tests(package: &str) -> String {
    let mut out = String::from(
        "//! `cargo test` runs raylab's checks on your chapters, one test per\n\
         //! chapter: the same verdict as `cargo run --release -- check --chapter N`.\n\
         //! This test judges; your chapters answer in this workspace's own\n\
         //! program, which cargo builds for the tests.\n",
    );
    for info in CHAPTERS {
        let name = info
            .folder
            .split_once('_')
            .map_or(info.folder, |(_, name)| name);
        let _ = write!(
            out,
            // Two digits, so that `cargo test chapter_01` is chapter 1
            // alone (`chapter_1` would name chapters 10 to 19 too).
            "\n#[test]\nfn chapter_{:02}_{name}() {{\n    raylab::check::assert_chapter(env!(\"CARGO_BIN_EXE_{package}\"), {});\n}}\n",
            info.number, info.number
        );
    }
    out
}

/// `src/chapters/mod.rs`: the chapter modules, and `Chapters` for the
/// student's type, each method sending its arguments to the function of the
/// same name in the chapter that the registry says writes it. The
/// signatures are the trait's own, read from `src/course.rs`.
fn chapters_mod_rs() -> Result<String, SkeletonError> {
    let methods = trait_methods()?;
    let mut out = String::from(
        "//! Connects raylab to your chapters (made by `raylab new`; you should not\n\
         //! need to edit it). raylab calls the methods of `raylab::course::Chapters`;\n\
         //! each one here calls the function of the same name in your chapter file.\n\n",
    );
    for info in CHAPTERS {
        let _ = writeln!(out, "pub mod {};", info.module());
    }
    out.push('\n');
    // The trait's own imports, so that its signatures read the same here.
    // Not every one is used by the methods below.
    // rustfmt keeps the order of groups apart: the types of src/course.rs
    // itself, then its imports.
    let (own, imports) = course_imports()?;
    let _ = writeln!(out, "#[allow(unused_imports)]\n{own}\n");
    for line in imports {
        let _ = writeln!(out, "#[allow(unused_imports)]\n{line}");
    }
    let _ = writeln!(
        out,
        "\nimpl raylab::course::Chapters for crate::{STUDENT_TYPE} {{"
    );
    let mut first = true;
    for info in CHAPTERS {
        for &function in info.functions {
            let Some((_, signature)) = methods.iter().find(|(name, _)| name == function) else {
                return Err(SkeletonError::NotAMethod {
                    chapter: info.number,
                    function: function.to_string(),
                });
            };
            let arguments =
                scan::parameter_names(signature).map_err(|error| SkeletonError::Signature {
                    function: function.to_string(),
                    error,
                })?;
            if !first {
                out.push('\n');
            }
            first = false;
            let type_arguments = forwarded_type_arguments(info, function)?;
            let _ = writeln!(
                out,
                "    {signature} {{\n        {}::{function}{type_arguments}({})\n    }}",
                info.module(),
                arguments.join(", ")
            );
        }
    }
    out.push_str("}\n");
    Ok(out)
}

/// The turbofish a forwarding call to chapter function `function` needs:
/// none when the arguments tell its type parameters (`in_shadow<C:
/// Chapters>(tracer: &mut Tracer<C>, ..)`), else `::<Self>`, the student's
/// type, for each (`smooth_hit_point<'a, C: Chapters>` calls `C`'s other
/// functions but takes no argument of `C`'s).
fn forwarded_type_arguments(info: &ChapterInfo, function: &str) -> Result<String, SkeletonError> {
    let src = info.source;
    let items = scan::items(src).map_err(|error| SkeletonError::Scan {
        file: info.code_path(),
        error,
    })?;
    let item = items
        .iter()
        .find(|item| item.kind == ItemKind::Fn && item.name.as_deref() == Some(function))
        .ok_or_else(|| SkeletonError::NoFunctionIn {
            path: info.code_path(),
            function: function.to_string(),
        })?;
    let signature_end = item.body.as_ref().map_or(item.range.end, |body| body.start);
    let parameters = scan::type_parameters(&src[item.header..signature_end]).map_err(|error| {
        SkeletonError::Generics {
            function: function.to_string(),
            error,
        }
    })?;
    if parameters.iter().all(|parameter| parameter.in_parameters) {
        return Ok(String::new());
    }
    let mut arguments = Vec::new();
    for parameter in &parameters {
        if !parameter
            .bounds
            .split(['+', ' '])
            .any(|bound| bound == "Chapters" || bound.ends_with("::Chapters"))
        {
            return Err(SkeletonError::ForeignTypeParameter {
                function: function.to_string(),
                parameter: parameter.name.clone(),
            });
        }
        arguments.push("Self");
    }
    Ok(format!("::<{}>", arguments.join(", ")))
}

/// Every method of `Chapters` in `src/course.rs`, as (name, signature from
/// `fn` to just before its body).
fn trait_methods() -> Result<Vec<(String, String)>, SkeletonError> {
    let src = COURSE_SOURCE;
    let items = scan::items(src).map_err(|error| SkeletonError::Scan {
        file: "src/course.rs".to_string(),
        error,
    })?;
    let body = items
        .iter()
        .find(|item| item.kind == ItemKind::Trait && item.name.as_deref() == Some("Chapters"))
        .and_then(|item| {
            // A trait's block is its last `{ ... }`: the item ends there.
            src[item.header..item.range.end]
                .find('{')
                .map(|open| item.header + open + 1..item.range.end - 1)
        })
        .ok_or(SkeletonError::NoChaptersTrait)?;
    let inner = &src[body];
    let methods = scan::items(inner).map_err(|error| SkeletonError::Scan {
        file: "trait Chapters".to_string(),
        error,
    })?;
    let mut out = Vec::new();
    for method in methods.iter().filter(|item| item.kind == ItemKind::Fn) {
        let signature_end = method
            .body
            .as_ref()
            .map_or(method.range.end, |body| body.start);
        let signature = inner[method.header..signature_end].trim_end();
        let name = method.name.clone().ok_or(SkeletonError::UnnamedMethod)?;
        out.push((name, signature.to_string()));
    }
    Ok(out)
}

/// An import of the public types `src/course.rs` defines itself, and its
/// `use` lines as a workspace writes them.
fn course_imports() -> Result<(String, Vec<String>), SkeletonError> {
    let src = COURSE_SOURCE;
    let items = scan::items(src).map_err(|error| SkeletonError::Scan {
        file: "src/course.rs".to_string(),
        error,
    })?;
    let mut lines = Vec::new();
    for item in items.iter().filter(|item| item.kind == ItemKind::Use) {
        let line = &src[item.header..item.range.end];
        // The chapter modules it names are raylab's; the workspace has its own.
        if !line.contains("crate::chapters") {
            lines.push(scan::crate_paths_to_raylab(line));
        }
    }
    let mut own: Vec<&str> = items
        .iter()
        .filter(|item| {
            matches!(
                item.kind,
                ItemKind::Struct | ItemKind::Enum | ItemKind::Trait
            ) && item.is_pub(src)
        })
        .filter_map(|item| item.name.as_deref())
        .collect();
    own.sort_unstable();
    Ok((
        format!("use raylab::course::{{{}}};", own.join(", ")),
        lines,
    ))
}

/// One chapter's file in the workspace, cut from the reference.
pub fn chapter_file(
    info: &ChapterInfo,
    raylab_dir: &str,
    solutions: bool,
) -> Result<String, SkeletonError> {
    let src = info.source;
    let items = scan::items(src).map_err(SkeletonError::Items)?;
    for &function in info.functions {
        if !items
            .iter()
            .any(|item| item.kind == ItemKind::Fn && item.name.as_deref() == Some(function))
        {
            return Err(SkeletonError::NoFunction {
                function: function.to_string(),
            });
        }
    }
    let lesson = Path::new(raylab_dir).join(info.lesson_path());
    let mut out = chapter_file_header(info, &lesson, solutions);
    let parts = ChapterParts::sort(info, &items, &lesson, solutions);
    out.push('\n');
    // Separate groups, which rustfmt leaves in this order.
    for group in [parts.uses, parts.reexports] {
        if !group.is_empty() && !out.ends_with("\n\n") {
            out.push('\n');
        }
        for line in group {
            out.push_str(&line);
            out.push('\n');
        }
    }
    for block in parts.code {
        out.push('\n');
        out.push_str(&block);
        out.push('\n');
    }
    if !solutions {
        out = unlink_missing(&out);
    }
    Ok(out)
}

/// `text` with each doc link to a bare name the file neither defines nor
/// imports (a helper the skeleton leaves out) turned into plain code, so
/// that the student's docs have no broken link. The links to raylab's
/// items the file imports (`greater_of`, `WIDTH`) stay links: the student
/// has those. No reference doc comment copied into a skeleton names a
/// helper (`no_skeleton_or_lesson_sends_the_student_to_a_helper_of_the_answer_key`):
/// this is the fallback that keeps the docs building if one does.
fn unlink_missing(text: &str) -> String {
    let imported = imported_names(text);
    let defines = |name: &str| {
        imported.contains(&name)
            || [
                "fn ", "struct ", "enum ", "const ", "type ", "trait ", "static ",
            ]
            .iter()
            .any(|keyword| text.contains(&format!("{keyword}{name}")))
    };
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find("[`") {
        out.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        let name_end = after.find("`]").filter(|&end| {
            let name = &after[..end];
            !name.is_empty() && name.chars().all(|c| c.is_alphanumeric() || c == '_')
        });
        match name_end {
            Some(end) if !defines(&after[..end]) => {
                out.push_str(&format!("`{}`", &after[..end]));
                rest = &after[end + 2..];
            }
            _ => {
                out.push_str("[`");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// Every name the `use` items at the start of a line of `text` mention,
/// paths and all: a module's name among them is harmless, as a link to it
/// resolves too.
fn imported_names(text: &str) -> Vec<&str> {
    let mut names = Vec::new();
    for (at, _) in text.match_indices("use ") {
        let line_start = text[..at].rfind('\n').map_or(0, |newline| newline + 1);
        if !matches!(text[line_start..at].trim(), "" | "pub") {
            continue;
        }
        let end = text[at..].find(';').map_or(text.len(), |end| at + end);
        names.extend(
            text[at + 4..end]
                .split(|c: char| !(c.is_alphanumeric() || c == '_'))
                .filter(|name| !name.is_empty()),
        );
    }
    names
}

/// A chapter file's module doc: what to write (or that this is the answer
/// key), where the lesson is and how to check; and, in a student's file,
/// the `allow` that keeps the unwritten bodies quiet.
fn chapter_file_header(info: &ChapterInfo, lesson: &Path, solutions: bool) -> String {
    let module = info.module();
    let functions = info
        .functions
        .iter()
        .map(|f| format!("`{f}`"))
        .collect::<Vec<_>>()
        .join(", ");
    let mut out = format!("//! Chapter {}: {}.\n//!\n", info.number, info.title);
    if solutions {
        let _ = writeln!(
            out,
            "//! raylab's reference solution of {functions} (the answer key)."
        );
    } else {
        let _ = writeln!(
            out,
            "//! Your turn: write {functions} below, replacing each `todo!()`."
        );
    }
    let _ = write!(
        out,
        "//!\n\
         //! The lesson: {}\n\
         //! (also in `cargo doc --open`: [`raylab::chapters::{module}`]).\n\
         //! Check your work: `cargo run --release -- check --chapter {}`.\n",
        lesson.display(),
        info.number
    );
    if !solutions {
        out.push_str(
            "\n// The imports are the ones the reference solution uses. Until the\n\
             // bodies are written, some of them and the arguments are unused: this\n\
             // keeps the compiler quiet about it. Delete it once you are done.\n\
             #![allow(unused_imports, unused_variables)]\n",
        );
    }
    out
}

/// The reference chapter's items as a workspace's chapter file holds them.
struct ChapterParts {
    /// The `use` lines that still resolve in a workspace.
    uses: Vec<String>,
    /// `pub use` lines of the public types the chapter defines.
    reexports: Vec<String>,
    /// The functions (a `todo!()` body or the solution) and, in the answer
    /// key, the helpers.
    code: Vec<String>,
}

impl ChapterParts {
    fn sort(
        info: &ChapterInfo,
        items: &[scan::Item],
        lesson: &Path,
        solutions: bool,
    ) -> ChapterParts {
        let src = info.source;
        let module = info.module();
        let mut parts = ChapterParts {
            uses: Vec::new(),
            reexports: Vec::new(),
            code: Vec::new(),
        };
        // The chapter's private types (chapter 11's node stack, say) are
        // helpers like its private functions: no one outside can name them,
        // so they cannot be re-exported; the answer key copies them with
        // their methods, and a student writes their own, or none.
        let private_types: Vec<&str> = items
            .iter()
            .filter(|item| is_type(item.kind) && !item.is_pub(src))
            .filter_map(|item| item.name.as_deref())
            .collect();
        for item in items {
            let text = &src[item.range.clone()];
            let name = item.name.as_deref().unwrap_or_default();
            match item.kind {
                // The lesson include and the tests stay in raylab.
                ItemKind::InnerAttribute | ItemKind::Mod => {}
                ItemKind::Use => parts.uses.extend(workspace_use(text)),
                kind if is_type(kind) && private_types.contains(&name) => {
                    parts
                        .code
                        .extend(solutions.then(|| scan::crate_paths_to_raylab(text)));
                }
                // A public type the chapter defines is raylab's, and the
                // trait's signatures name raylab's: the workspace uses that
                // one.
                kind if is_type(kind) => {
                    parts
                        .reexports
                        .push(format!("pub use raylab::chapters::{module}::{name};"));
                }
                // Methods of a private type go with it; those of a public
                // type are raylab's too.
                ItemKind::Impl => {
                    let own_type = impl_self_type(&src[item.header..item.range.end]);
                    if solutions && own_type.is_some_and(|own| private_types.contains(&own)) {
                        parts.code.push(scan::crate_paths_to_raylab(text));
                    }
                }
                ItemKind::Fn if info.functions.contains(&name) => {
                    let function = student_function(info, src, item, lesson, solutions);
                    parts.code.push(function);
                }
                _ if solutions => parts.code.push(scan::crate_paths_to_raylab(text)),
                // The lesson's helpers are the student's to write, or not.
                _ => {}
            }
        }
        parts
    }
}

/// A `use` item of the reference, with its `crate::` paths made raylab's;
/// `None` when it imports another crate: a workspace depends on raylab (and
/// libm) only, and imports of other crates served the types re-exported.
fn workspace_use(text: &str) -> Option<String> {
    let line = scan::crate_paths_to_raylab(text);
    let root = line
        .trim_start_matches("pub ")
        .trim_start_matches("use ")
        .split("::")
        .next()
        .unwrap_or_default()
        .trim_start_matches("::");
    matches!(root, "raylab" | "std" | "core" | "alloc" | "libm").then_some(line)
}

fn is_type(kind: ItemKind) -> bool {
    matches!(
        kind,
        ItemKind::Struct | ItemKind::Enum | ItemKind::Union | ItemKind::Trait | ItemKind::TypeAlias
    )
}

/// The name of the type an `impl` block (the text from `impl` on) is for:
/// `Nearest` in `impl Nearest {` and in `impl<T> Trait for Nearest<T> {`.
fn impl_self_type(text: &str) -> Option<&str> {
    let header = &text[..text.find('{')?];
    let header = header.strip_prefix("impl")?;
    // Past the impl's own generics, `<...>` right after the keyword.
    let header = match header.trim_start().strip_prefix('<') {
        Some(rest) => {
            let mut depth = 1;
            let close = rest.char_indices().find_map(|(at, c)| {
                match c {
                    '<' => depth += 1,
                    '>' => depth -= 1,
                    _ => {}
                }
                (depth == 0).then_some(at)
            })?;
            &rest[close + 1..]
        }
        None => header,
    };
    let self_type = header
        .rsplit_once(" for ")
        .map_or(header, |(_, after)| after);
    let self_type = self_type.trim_start().trim_start_matches(['&', '(']);
    let end = self_type
        .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
        .unwrap_or(self_type.len());
    self_type[..end]
        .rsplit("::")
        .next()
        .filter(|name| !name.is_empty())
}

/// A function the student writes: its doc comment, a pointer to the lesson,
/// its signature, and `todo!()` or the reference body.
fn student_function(
    info: &ChapterInfo,
    src: &str,
    item: &scan::Item,
    lesson: &Path,
    solutions: bool,
) -> String {
    let name = item.name.as_deref().unwrap_or_default();
    let see = format!(
        "///\n/// Lesson: {} ([`raylab::chapters::{}`]).",
        lesson.display(),
        info.module()
    );
    // The lesson line goes after the doc comment (before any attribute).
    let split = item.doc_end.unwrap_or(item.range.start);
    let docs = &src[item.range.start..split];
    let rest = match (&item.body, solutions) {
        (Some(body), false) => format!(
            "{} {{\n    todo!(\"chapter {}: {name}\")\n}}",
            src[split..body.start].trim_end(),
            info.number
        ),
        _ => src[split..item.range.end].to_string(),
    };
    let text = if docs.is_empty() {
        format!("{}\n{}", see.trim_start_matches("///\n"), rest.trim_start())
    } else {
        format!("{docs}\n{see}{rest}")
    };
    scan::crate_paths_to_raylab(&text)
}

/// Creates the workspace in `dir`, which must not exist or be an empty
/// folder, all or nothing: the files are written in a temporary folder
/// beside it, then moved in place. Returns the package name.
pub fn create(dir: &Path, solutions: bool) -> Result<String, WorkspaceError> {
    let raylab_dir = Path::new(RAYLAB_DIR);
    if !raylab_dir.join("Cargo.toml").is_file() {
        return Err(WorkspaceError::RaylabMissing {
            dir: raylab_dir.to_path_buf(),
        });
    }
    let dir = std::path::absolute(dir).map_err(io_error("resolve", dir))?;
    let existing_empty = match std::fs::read_dir(&dir) {
        Ok(mut entries) => {
            if entries.next().is_some() {
                return Err(WorkspaceError::NotEmpty { dir });
            }
            true
        }
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => false,
        Err(_) if dir.exists() && !dir.is_dir() => {
            return Err(WorkspaceError::NotAFolder { dir });
        }
        Err(error) => return Err(io_error("read", &dir)(error)),
    };
    // The folder's own name (for `.`, the current folder's).
    let resolved = if existing_empty {
        dir.canonicalize().map_err(io_error("resolve", &dir))?
    } else {
        dir.clone()
    };
    let folder = resolved
        .file_name()
        .and_then(|name| name.to_str())
        .ok_or(WorkspaceError::NoName)?;
    let package = package_name(folder);
    let files = files(&package, raylab_dir, solutions)?;
    let parent = resolved.parent().ok_or(WorkspaceError::AtRoot)?;
    std::fs::create_dir_all(parent).map_err(io_error("create", parent))?;
    let staging = tempfile::Builder::new()
        .prefix(".raylab-new-")
        .tempdir_in(parent)
        .map_err(io_error("write in", parent))?;
    for (path, text) in &files.0 {
        let path = staging.path().join(path);
        if let Some(folder) = path.parent() {
            std::fs::create_dir_all(folder).map_err(io_error("create", folder))?;
        }
        std::fs::write(&path, text).map_err(io_error("write", &path))?;
    }
    if existing_empty {
        move_into(staging.path(), &resolved)?;
    } else {
        std::fs::rename(staging.path(), &resolved).map_err(io_error("create", &resolved))?;
        // Renamed: nothing left for the guard to remove.
        let _ = staging.keep();
    }
    Ok(package)
}

/// Moves the entries of `staging` into the empty folder `dir` (which may be
/// the current folder, so it is not replaced), undoing the moves if one fails.
fn move_into(staging: &Path, dir: &Path) -> Result<(), WorkspaceError> {
    let entries: Vec<PathBuf> = std::fs::read_dir(staging)
        .map_err(io_error("read", staging))?
        .map(|entry| entry.map(|entry| entry.path()))
        .collect::<std::io::Result<_>>()
        .map_err(io_error("read", staging))?;
    let mut moved = Vec::new();
    for from in entries {
        let Some(name) = from.file_name() else {
            continue;
        };
        let to = dir.join(name);
        if let Err(error) = std::fs::rename(&from, &to) {
            for (from, to) in moved.iter().rev() {
                let _ = std::fs::rename(to, from);
            }
            return Err(io_error("write", &to)(error));
        }
        moved.push((from, to));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn impl_blocks_name_their_type() {
        assert_eq!(impl_self_type("impl Nearest {}"), Some("Nearest"));
        assert_eq!(
            impl_self_type("impl<T: X<u8>> Show for Stack<T> {}"),
            Some("Stack")
        );
        assert_eq!(
            impl_self_type("impl std::fmt::Debug for a::Bins {}"),
            Some("Bins")
        );
        assert_eq!(impl_self_type("impl Sampling {}"), Some("Sampling"));
    }

    #[test]
    fn doc_links_to_what_the_skeleton_leaves_out_become_plain_code() {
        let text = "/// Within [`root_error`] of [`intersect_sphere`], see [`a::b`].\n\
                    pub fn intersect_sphere() {}\n";
        assert_eq!(
            unlink_missing(text),
            "/// Within `root_error` of [`intersect_sphere`], see [`a::b`].\n\
             pub fn intersect_sphere() {}\n"
        );
        let imports = "use raylab::bvh::{\n    WIDTH, greater_of,\n};\n\
                       /// Up to [`WIDTH`], by [`greater_of`], not [`leaf4`].\n\
                       pub fn hit_boxes() {}\n";
        assert_eq!(
            unlink_missing(imports),
            "use raylab::bvh::{\n    WIDTH, greater_of,\n};\n\
             /// Up to [`WIDTH`], by [`greater_of`], not `leaf4`.\n\
             pub fn hit_boxes() {}\n"
        );
    }

    /// The names the answer key of `info` defines and its skeleton does
    /// not: the helpers `raylab new` leaves out, which a student has
    /// nowhere (raylab's own are private to a workspace's build).
    fn dropped_helpers(info: &ChapterInfo) -> Vec<String> {
        let defined = |text: &str| -> Vec<String> {
            scan::items(text)
                .expect("a cut file scans")
                .into_iter()
                .filter(|item| {
                    !matches!(
                        item.kind,
                        ItemKind::Use | ItemKind::Impl | ItemKind::Mod | ItemKind::InnerAttribute
                    )
                })
                .filter_map(|item| item.name)
                .collect()
        };
        let skeleton = defined(&chapter_file(info, "/r", false).expect("cuts"));
        defined(&chapter_file(info, "/r", true).expect("cuts"))
            .into_iter()
            .filter(|name| !skeleton.contains(name))
            .collect()
    }

    /// Whether `text` names `name` as an identifier: not inside a longer
    /// one nor a case's name (`normal-central-with-a-wide-step`), and not
    /// after a `.`, where it is a field or method of a value the student
    /// has (`material.ambient`).
    fn names(text: &str, name: &str) -> bool {
        let joined = |c: char| c.is_alphanumeric() || c == '_' || c == '-';
        text.match_indices(name).any(|(at, _)| {
            let before = text[..at].chars().next_back();
            let after = text[at + name.len()..].chars().next();
            !before.is_some_and(|c| joined(c) || c == '.') && !after.is_some_and(joined)
        })
    }

    /// The code of a lesson or of a skeleton (fenced blocks and inline
    /// spans) and the rest, its prose and the skeleton's signatures.
    fn code_and_prose(markdown: &str) -> (String, String) {
        let (mut code, mut prose) = (String::new(), String::new());
        let mut fenced = false;
        for line in markdown.lines() {
            if line.trim_start().starts_with("```") {
                fenced = !fenced;
            } else if fenced {
                code.push_str(line);
                code.push('\n');
            } else {
                prose.push_str(line);
                prose.push('\n');
            }
        }
        let mut plain = String::new();
        for (index, part) in prose.split('`').enumerate() {
            if index % 2 == 1 {
                code.push_str(part);
                code.push('\n');
            } else {
                plain.push_str(part);
            }
        }
        (code, plain)
    }

    #[test]
    fn no_skeleton_or_lesson_sends_the_student_to_a_helper_of_the_answer_key() {
        let helpers: Vec<(u8, String)> = CHAPTERS
            .iter()
            .flat_map(|info| {
                dropped_helpers(info)
                    .into_iter()
                    .map(|name| (info.number, name))
            })
            .collect();
        // Each chapter drops at least its constants or helper functions:
        // an empty list would mean the derivation broke, not that all is well.
        assert!(
            helpers.iter().any(|(_, name)| name == "root_error"),
            "{helpers:?}"
        );
        let mut found = Vec::new();
        for info in CHAPTERS {
            let skeleton = chapter_file(info, "/r", false).expect("cuts");
            let lesson_path = Path::new(RAYLAB_DIR).join(info.lesson_path());
            let lesson = std::fs::read_to_string(&lesson_path).expect("the lesson reads");
            let (code, prose) = code_and_prose(&lesson);
            let (skeleton_code, skeleton_rest) = code_and_prose(&skeleton);
            for (chapter, name) in &helpers {
                // Another chapter's `wide` or `Nearest` is more likely a
                // name of this one (a parameter, a word); `root_error` is
                // no one else's.
                if *chapter != info.number && !name.contains('_') {
                    continue;
                }
                // A lowercase word (`ambient`, `boundary`) in prose is the
                // word; a name with `_`, a capital or a digit is code.
                let word = name.chars().all(|c| c.is_ascii_lowercase());
                if names(&skeleton_code, name) || (!word && names(&skeleton_rest, name)) {
                    found.push(format!("the skeleton of chapter {} names `{name}` (chapter {chapter}'s answer key)", info.number));
                }
                if names(&code, name) || (!word && names(&prose, name)) {
                    found.push(format!(
                        "{} names `{name}` (chapter {chapter}'s answer key)",
                        info.lesson_path()
                    ));
                }
            }
        }
        assert!(found.is_empty(), "{}", found.join("\n"));
    }

    #[test]
    fn the_web_crate_names_the_workspace_s_chapters() {
        let files = web_crate(
            Path::new("/home/ada/my \"course\""),
            "my-course",
            "my_course::Mine",
            Path::new("/opt/raylab"),
        )
        .expect("UTF-8 paths");
        let manifest: toml::Table = files
            .get("Cargo.toml")
            .expect("a manifest")
            .parse()
            .expect("valid TOML, quotes and all");
        assert_eq!(
            manifest["dependencies"]["my-course"]["path"].as_str(),
            Some("/home/ada/my \"course\"")
        );
        assert_eq!(
            manifest["dependencies"]["raylab"]["features"][0].as_str(),
            Some("student")
        );
        assert_eq!(manifest["lib"]["crate-type"][0].as_str(), Some("cdylib"));
        assert!(
            files
                .get("lib.rs")
                .is_some_and(|lib| lib.contains("raylab::web_exports!(my_course::Mine);"))
        );
    }

    #[test]
    fn package_names_are_valid() {
        assert_eq!(package_name("s"), "s");
        assert_eq!(package_name("My Tracer"), "my-tracer");
        assert_eq!(package_name("alice_2024"), "alice_2024");
        assert_eq!(package_name("2024"), "raytracer-2024");
        assert_eq!(package_name("élève"), "l-ve");
        assert_eq!(package_name("..."), "raytracer");
        assert_eq!(package_name("raylab"), "raylab-course");
        assert_eq!(package_name("test"), "test-course");
    }

    #[test]
    fn every_registry_function_has_a_method_and_a_plain_signature() {
        let methods = trait_methods().expect("the trait scans");
        for info in CHAPTERS {
            for function in info.functions {
                let (_, signature) = methods
                    .iter()
                    .find(|(name, _)| name == function)
                    .unwrap_or_else(|| panic!("no method {function}"));
                assert!(
                    signature.starts_with(&format!("fn {function}")),
                    "{signature}"
                );
                scan::parameter_names(signature).expect("plain parameters");
            }
        }
    }

    #[test]
    fn skeletons_keep_signatures_and_drop_bodies_helpers_and_tests() {
        for info in CHAPTERS {
            let todo = chapter_file(info, "/r", false).expect("cuts");
            let answer = chapter_file(info, "/r", true).expect("cuts");
            for text in [&todo, &answer] {
                assert!(!text.contains("#![doc"), "{}", info.folder);
                assert!(!text.contains("#[cfg(test)]"), "{}", info.folder);
                assert!(!text.contains("crate::"), "{}", info.folder);
                assert!(text.contains(&format!("/r/{}", info.lesson_path())));
            }
            for function in info.functions {
                assert!(todo.contains(&format!("todo!(\"chapter {}: {function}\")", info.number)));
                assert!(todo.contains(&format!("pub fn {function}")));
                assert!(answer.contains(&format!("pub fn {function}")));
            }
            assert!(!answer.contains("todo!("));
        }
        // Chapter 11's private helpers: the answer key carries them and
        // their methods (raylab's cannot be named from outside); the
        // skeleton leaves them to the student.
        let bvh = CHAPTERS.iter().find(|info| info.number == 11).expect("11");
        let bvh_todo = chapter_file(bvh, "/r", false).expect("cuts");
        let bvh_answer = chapter_file(bvh, "/r", true).expect("cuts");
        for helper in [
            "struct NodeStack",
            "> NodeStack<T> {",
            "struct Nearest",
            "impl Nearest",
            "fn leaf4(",
        ] {
            assert!(bvh_answer.contains(helper), "{helper}");
            assert!(!bvh_todo.contains(helper), "{helper}");
        }
        assert!(!bvh_answer.contains(&format!(
            "pub use raylab::chapters::{}::",
            CHAPTERS[10].module()
        )));
        assert!(
            bvh_todo.contains("use raylab::bvh::{\n    Aabb, Boxes4, Bvh, BvhNode, BvhOptions,")
        );
        let plane = chapter_file(&CHAPTERS[0], "/r", false).expect("cuts");
        assert!(!plane.contains("PARALLEL_TOLERANCE"));
        let plane_answer = chapter_file(&CHAPTERS[0], "/r", true).expect("cuts");
        assert!(plane_answer.contains("pub const PARALLEL_TOLERANCE"));
    }
}
