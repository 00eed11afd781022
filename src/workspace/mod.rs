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

mod bridge;
pub mod scan;
mod skeleton;
mod templates;

pub use skeleton::chapter_file;
pub use templates::web_crate;

use std::path::{Path, PathBuf};

use crate::chapters::{CHAPTERS, ChapterInfo};
use bridge::chapters_mod_rs;
use scan::ScanError;
use templates::{cargo_toml, check_tests, lib_rs, readme};

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

/// The student's type, in the workspace's `src/lib.rs`.
pub const STUDENT_TYPE: &str = "Mine";

/// The Rust edition of a workspace's crate: `grade --code` counts no other
/// (in it an `extern` block, code linked in from elsewhere, is `unsafe`).
pub const EDITION: &str = "2024";

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
}
