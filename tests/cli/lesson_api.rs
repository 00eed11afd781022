//! The API each lesson names, compiled as a student's crate compiles it.
//!
//! Every lesson has a `## What you call` section: the types a student's
//! functions are given (with their fields) and the methods they call, as
//! ```` ```rust ```` blocks. The lessons are raylab's docs, so `cargo test
//! --doc` compiles those blocks, but against raylab without its `student`
//! feature, where the reference chapters are public: a lesson that names
//! raylab's own answer (`raylab::reflect`) would pass there and fail in
//! every workspace. So this test puts every
//! ```` ```rust ```` block of every lesson into a fresh workspace (`raylab
//! new`) and builds it offline, against raylab with `student`. Each lesson
//! becomes one file whose lines are the lesson's own (the block's lines in
//! place, every other line blank), so the compiler's `file:line` is the
//! lesson's line.
//!
//! The convention, checked here: a lesson's Rust examples are fenced as
//! ```` ```rust ```` exactly (no `ignore`, `no_run` or other attribute:
//! each must compile in both places), and hold only items (`use`, `fn`),
//! which mean the same at a module's top level and in a doc test's `main`.

use crate::common;

use std::path::Path;

use crate::workspace::target_dir;
use common::{raylab, stderr};
use raylab::chapters::{CHAPTERS, ChapterInfo};

const SECTION: &str = "## What you call";

fn lesson(info: &ChapterInfo) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(info.lesson_path());
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The lesson as a Rust file for a workspace: each ```` ```rust ```` block
/// a module of its own (`mod block_N {` on the opening fence's line, `}`
/// on the closing one), the block's lines where the lesson has them, and
/// every other line blank. Also the line of each block's opening fence.
fn as_rust(lesson: &str) -> (String, Vec<usize>) {
    let mut out = Vec::new();
    let mut starts = Vec::new();
    let mut inside = false;
    for (index, line) in lesson.lines().enumerate() {
        let fence = line.trim_start();
        if !inside && fence == "```rust" {
            inside = true;
            starts.push(index + 1);
            out.push(format!("mod block_{} {{", index + 1));
        } else if inside && fence.starts_with("```") {
            inside = false;
            out.push("}".to_string());
        } else if inside {
            out.push(line.to_string());
        } else {
            out.push(String::new());
        }
    }
    out.push(String::new());
    (out.join("\n"), starts)
}

/// Every lesson has its API section, with a ```` ```rust ```` block in
/// it, and fences no Rust another way (which one of the two builds would
/// skip).
#[test]
fn every_lesson_names_its_api_in_rust_blocks() {
    let mut problems = Vec::new();
    for info in CHAPTERS {
        let text = lesson(info);
        let path = info.lesson_path();
        let lines: Vec<&str> = text.lines().collect();
        // 1-based: the section's heading, and the line before the next one.
        let Some(heading) = lines.iter().position(|line| *line == SECTION) else {
            problems.push(format!("{path}: no `{SECTION}` section"));
            continue;
        };
        let end = lines[heading + 1..]
            .iter()
            .position(|line| line.starts_with("## "))
            .map_or(lines.len(), |next| heading + 1 + next);
        let (_, starts) = as_rust(&text);
        if !starts.iter().any(|&line| line > heading + 1 && line <= end) {
            problems.push(format!("{path}: no ```rust block in `{SECTION}`"));
        }
        for (index, line) in text.lines().enumerate() {
            let fence = line.trim_start();
            let other_rust = ["```rust", "```rs"]
                .iter()
                .any(|tag| fence.starts_with(tag))
                && fence != "```rust";
            if other_rust {
                problems.push(format!(
                    "{path}:{}: `{fence}`: a lesson's Rust is fenced ```rust, which \
                     both the doc tests and a workspace's build compile",
                    index + 1
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_name_a_lesson_calls_resolves_in_a_student_workspace() {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("lesson-api-test");
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).expect("create the test folder");
    let workspace = root.join("lessons");
    let output = raylab(&["new", workspace.to_str().expect("UTF-8 path")], &root);
    assert!(output.status.success(), "raylab new: {}", stderr(&output));
    let folder = workspace.join("src/lesson_api");
    std::fs::create_dir_all(&folder).expect("create src/lesson_api");
    let mut modules = String::from("\n// The lessons' API sections (tests/cli/lesson_api.rs).\n");
    let mut blocks = 0;
    for info in CHAPTERS {
        let (rust, starts) = as_rust(&lesson(info));
        blocks += starts.len();
        // The file is named after the lesson's folder, so that the
        // compiler's messages point at the lesson.
        let file = format!("{}.rs", info.folder);
        std::fs::write(folder.join(&file), rust).expect("write a lesson's file");
        modules.push_str(&format!(
            "#[allow(unused, dead_code)]\n#[path = \"lesson_api/{file}\"]\nmod lesson_{};\n",
            info.module()
        ));
    }
    assert!(blocks >= CHAPTERS.len(), "{blocks} blocks");
    let lib = workspace.join("src/lib.rs");
    let mut text = std::fs::read_to_string(&lib).expect("read src/lib.rs");
    text.push_str(&modules);
    std::fs::write(&lib, text).expect("write src/lib.rs");
    let output = common::cargo()
        .args(["build", "--offline", "--quiet", "--lib"])
        .current_dir(&workspace)
        .env("CARGO_TARGET_DIR", target_dir())
        .output()
        .expect("run cargo");
    assert!(
        output.status.success(),
        "a lesson names what a student's crate cannot reach (or what does not \
         compile). In src/lesson_api/NN_name.rs below, the line is the line of \
         chapters/NN_name/lesson.md:\n{}",
        stderr(&output)
    );
}
