//! The workspace's files that are templates, not cuts of raylab's source:
//! its manifest, README, `src/lib.rs`, the test per chapter, and the crate
//! `raylab web` builds. They change with how a workspace is set up, never
//! with a chapter's code.

use std::fmt::Write as _;
use std::path::Path;

use super::{Files, STUDENT_TYPE, WorkspaceError};
use crate::chapters::CHAPTERS;

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

pub(super) fn cargo_toml(package: &str, raylab_dir: &str) -> String {
    // A TOML string, escaped: a path may hold quotes or backslashes.
    let path = toml::Value::String(raylab_dir.to_string());
    let edition = super::EDITION;
    format!(
        r#"[package]
name = "{package}"
version = "0.1.0"
edition = "{edition}"
publish = false

[dependencies]
# The raylab this workspace was made from, as a student's dependency (its
# `student` feature keeps raylab's own answers out of reach; the check
# refuses a build without it). A class can share one copy
# instead (path = "/opt/raylab"), or use a tagged release
# (git = "https://example.org/raylab.git", tag = "v0.1.0"): see raylab's
# README, "For instructors: one raylab for a class".
raylab = {{ path = {path}, features = ["student"] }}
# The reference solutions of chapters 2 and 8 use it (exact ldexp, asin).
libm = "0.2"

# This crate is its own workspace, even inside another project's folder.
[workspace]

# Renders in debug builds take seconds rather than minutes, and the images
# are the same bit for bit (Rust never reorders float arithmetic). Line
# tables are all a backtrace needs; full debug info only makes each binary
# larger and slower to link.
[profile.dev]
opt-level = 1
debug = "line-tables-only"

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

pub(super) fn readme(package: &str, raylab_dir: &str, solutions: bool) -> String {
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
cargo test --release                           # the same checks, one test per chapter
cargo test --release chapter_01                # chapter 1's alone
cargo run --release -- trace --chapter 1 --pixel 320,240   # every ray of one pixel, with your code
cargo run --release -- web                     # the browser page of your chapters, in web/
```

Every command above but `web` shares one build of raylab and your
chapters, in `target/release/`: the first compiles raylab (minutes, about
500 MB), and after it a change to a chapter recompiles your crate alone,
in seconds, whichever of them runs next. Keep `--release` on `cargo test`:
plain `cargo test` compiles a second raylab, in debug, in `target/debug/`
(minutes again, and about 1.5 GB more on disk) for the same verdicts.
`web` builds the page for the browser, a build of its own: the first
time it fetches Debian's `rustc-web` toolchain (into raylab's folder,
`.wasm-toolchain/`) and compiles raylab for WebAssembly, which took 14
minutes and about 850 MB there, and 500 MB more in `target/`, on a loaded
2-core machine (`time cargo run --release -- web` measures yours); after
it, an edit rebuilds the page in seconds.

Chapter N's image needs your chapters 1 to N. Where a lesson says
`raylab render ...`, type `cargo run --release -- render ...` here: the
binary runs raylab's commands with your code (`render`, `trace`, `scene`,
`bench`, `probe`, ...: `cargo run --release -- --help`).

It holds none of raylab's answers, so that nothing in it can stand in for
your code. The verdict comes from raylab's own binary, built from the same
raylab ({raylab_dir}): `check` and `cargo test` run the `raylab` on your
`PATH` if it was built from that source, else the release build in that
folder (which `cargo run --release` there made), and build it the first
time if neither is there. `diff`, `grade` and `mesh` run there too; `cost`,
`figure` and `crosscheck`, which measure against raylab's answers, are
raylab's commands, in its folder.

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

pub(super) fn lib_rs(solutions: bool) -> String {
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

pub(super) fn check_tests(package: &str) -> String {
    let mut out = String::from(
        "//! `cargo test --release` runs raylab's checks on your chapters, one test\n\
         //! per chapter: the same verdict as `cargo run --release -- check --chapter N`,\n\
         //! from the same build (plain `cargo test` builds raylab again, in debug).\n\
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
