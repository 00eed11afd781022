//! The layers of docs/architecture.md, kept by reading the code: every
//! `crate::` (or, in a chapter file, `raylab::`) path in a file of `src/`
//! or `chapters/` must name a module of its own layer or of one below, and
//! only the command line prints or names clap.
//!
//! Tests (`#[cfg(test)]` modules, a chapter folder's `tests.rs` and the
//! `gallery.rs` it includes) may use anything, as may `src/lib.rs`, which
//! only declares and re-exports.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The layers, lowest first: a file may use its own layer and those below.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Layer {
    /// Rays, shapes, scenes, meshes, the camera, image files, input limits:
    /// nothing of chapters, the course, tools or the command line.
    Foundation,
    /// The course trait, the render loop, the registry and the chapters'
    /// code: no tool, no command line.
    Engine,
    /// check, grade, workspace, cost, crosscheck, the BVH reports (the race
    /// among them), the implicit probe, the ray trees, and each chapter's
    /// cases: never the command line.
    Tool,
    /// The command line: clap, exit codes, printing.
    Cli,
}

/// The layer of a source file, by its path; `None` for `src/lib.rs` and
/// for tests, which the rules do not bind.
fn layer_of(path: &str) -> Result<Option<Layer>, String> {
    // A chapter's tests and its bug gallery (a child of its tests) are test
    // code, which may use any layer.
    let chapter_gallery = path.starts_with("chapters/") && path.ends_with("/gallery.rs");
    if path == "src/lib.rs" || path.ends_with("/tests.rs") || chapter_gallery {
        return Ok(None);
    }
    if let Some(rest) = path.strip_prefix("chapters/") {
        return match rest {
            "mod.rs" => Ok(Some(Layer::Engine)),
            _ if rest.ends_with("/chapter.rs") => Ok(Some(Layer::Engine)),
            _ if rest.ends_with("/checks.rs") || rest.ends_with("/kinds.rs") => {
                Ok(Some(Layer::Tool))
            }
            _ => Err(format!(
                "{path}: a chapter folder holds chapter.rs, checks.rs, kinds.rs, tests.rs and \
                 gallery.rs"
            )),
        };
    }
    let module = path
        .strip_prefix("src/")
        .and_then(|rest| rest.split('/').next())
        .map(|first| first.trim_end_matches(".rs"))
        .ok_or_else(|| format!("{path} is not in src/ or chapters/"))?;
    module_layer(module)
        .map(Some)
        .ok_or_else(|| format!("{path}: module `{module}` has no layer; add it to docs/architecture.md and to tests/architecture.rs"))
}

/// The layer of a top-level module of the crate.
fn module_layer(module: &str) -> Option<Layer> {
    Some(match module {
        "ray" | "shapes" | "scene" | "mesh" | "camera" | "output" | "input" | "text" | "medium"
        | "bvh" | "cleanup" | "spectrum" | "limits" | "number" => Layer::Foundation,
        "course" | "seam" | "answer_key" | "render" | "record" | "effects" | "builtin"
        | "chapters" => Layer::Engine,
        "check" | "grade" | "workspace" | "cost" | "crosscheck" | "bvh_reports" | "diff"
        | "embree" | "plots" | "implicit_probe" | "ray_tree" | "figure" | "web" => Layer::Tool,
        "cli" | "main" => Layer::Cli,
        _ => return None,
    })
}

/// What the crate root re-exports, by name: `Vec3` is glam's (a
/// foundation), `Reference` the registry's, `Tracer` the render loop's.
fn root_names() -> BTreeMap<String, String> {
    let lib = read("src/lib.rs");
    let mut names = BTreeMap::new();
    for statement in lib.split(';') {
        let statement = statement.trim();
        let Some(path) = statement.strip_prefix("pub use ") else {
            continue;
        };
        let (module, items) = path.split_once("::").unwrap_or((path, path));
        for item in items.trim_matches(|c| c == '{' || c == '}').split(',') {
            let name = item.rsplit("::").next().unwrap_or(item).trim();
            let module = if module == "glam" { "ray" } else { module };
            names.insert(name.to_string(), module.to_string());
        }
    }
    names
}

fn read(path: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(path))
        .unwrap_or_else(|error| panic!("{path}: {error}"))
}

/// `text` without comments, string and character literals and its
/// `#[cfg(test)]` modules (each replaced by spaces, so line numbers stay):
/// the production code of the whole file, before and after its tests.
fn code_only(text: &str) -> String {
    without_test_modules(&without_literals(text))
}

/// `text` with comments, strings and raw strings blanked.
fn without_literals(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut at = 0;
    while at < bytes.len() {
        let rest = &text[at..];
        let end = if rest.starts_with("//") {
            rest.find('\n').unwrap_or(rest.len())
        } else if rest.starts_with("/*") {
            rest.find("*/").map_or(rest.len(), |end| end + 2)
        } else if let Some(hashes) = raw_string_hashes(rest) {
            let close = format!("\"{}", "#".repeat(hashes));
            let open = 2 + hashes;
            rest[open..]
                .find(&close)
                .map_or(rest.len(), |end| open + end + close.len())
        } else if rest.starts_with('"') {
            let mut end = 1;
            while end < rest.len() && rest.as_bytes()[end] != b'"' {
                end += if rest.as_bytes()[end] == b'\\' { 2 } else { 1 };
            }
            (end + 1).min(rest.len())
        } else {
            let c = rest.chars().next().map_or(1, char::len_utf8);
            out.push_str(&rest[..c]);
            at += c;
            continue;
        };
        out.push_str(&blank(&rest[..end]));
        at += end;
    }
    out
}

/// Spaces for every character of `slice` but its line breaks.
fn blank(slice: &str) -> String {
    slice
        .chars()
        .map(|c| if c == '\n' { '\n' } else { ' ' })
        .collect()
}

/// `code` (literals already blanked, so every brace is code) with each
/// inline `#[cfg(test)] mod name { ... }` blanked to its matching brace.
fn without_test_modules(code: &str) -> String {
    let mut out = code.to_string();
    let mut from = 0;
    while let Some(found) = out[from..].find("#[cfg(test)]") {
        let start = from + found;
        let after = &out[start + "#[cfg(test)]".len()..];
        let item = after.trim_start();
        let item = item.strip_prefix("pub(crate)").unwrap_or(item).trim_start();
        let is_inline_module = item.strip_prefix("mod ").is_some_and(|rest| {
            let name_end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                .unwrap_or(rest.len());
            rest[name_end..].trim_start().starts_with('{')
        });
        if !is_inline_module {
            from = start + 1;
            continue;
        }
        let open = start
            + out[start..]
                .find('{')
                .expect("an inline module has a brace");
        let mut depth = 0usize;
        let mut end = out.len();
        for (offset, c) in out[open..].char_indices() {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = open + offset + 1;
                        break;
                    }
                }
                _ => {}
            }
        }
        let blanked = blank(&out[start..end]);
        out.replace_range(start..end, &blanked);
        from = end;
    }
    out
}

/// The number of `#` of a raw string starting `text` (`r"`, `r#"`, ...).
fn raw_string_hashes(text: &str) -> Option<usize> {
    let rest = text.strip_prefix('r')?;
    let hashes = rest.len() - rest.trim_start_matches('#').len();
    rest[hashes..].starts_with('"').then_some(hashes)
}

/// The rule broken by each `crate::` path of `text` (the file `path`,
/// of `layer`), one message a violation.
fn violations(
    path: &str,
    layer: Layer,
    text: &str,
    roots: &BTreeMap<String, String>,
) -> Vec<String> {
    let code = code_only(text);
    let line_of = |at: usize| code[..at].matches('\n').count() + 1;
    let mut found = Vec::new();
    for prefix in ["crate::", "raylab::"] {
        for (at, _) in code.match_indices(prefix) {
            let before = code[..at].chars().next_back();
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            let after = &code[at + prefix.len()..];
            // `crate::{a, b::c}`: each name of the group.
            let names: Vec<String> = match after.strip_prefix('{') {
                Some(group) => group[..group.find('}').unwrap_or(group.len())]
                    .split(',')
                    .map(|item| item.trim().split("::").next().unwrap_or("").to_string())
                    .collect(),
                None => vec![
                    after
                        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
                        .next()
                        .unwrap_or("")
                        .to_string(),
                ],
            };
            for name in names.into_iter().filter(|name| !name.is_empty()) {
                let module = roots.get(&name).cloned().unwrap_or(name.clone());
                let Some(target) = module_layer(&module) else {
                    continue;
                };
                if target > layer {
                    found.push(format!(
                        "{path}:{}: {layer:?} code uses {prefix}{name} ({module}, {target:?} layer)",
                        line_of(at)
                    ));
                }
            }
        }
    }
    if layer != Layer::Cli {
        for (number, line) in code.lines().enumerate() {
            if line.contains("clap::") || line.split_whitespace().any(|word| word == "clap") {
                found.push(format!(
                    "{path}:{}: only the command line names clap",
                    number + 1
                ));
            }
            let prints = ["println!", "eprintln!", "print!(", "eprint!("]
                .iter()
                .any(|mac| line.contains(mac));
            if prints && !PRINTS_ALLOWED.contains(&path) {
                found.push(format!(
                    "{path}:{}: only the command line prints",
                    number + 1
                ));
            }
        }
    }
    found
}

/// Files outside the command line allowed to print, each with its reason:
/// cleanup's pause exists only for the command line's signal tests, which
/// wait for its line on stderr.
const PRINTS_ALLOWED: &[&str] = &["src/cleanup.rs"];

fn source_files(folder: &Path, out: &mut Vec<PathBuf>) {
    files_ending(folder, &["rs"], out);
}

/// The files under `folder` whose extension is one of `extensions`, sorted.
fn files_ending(folder: &Path, extensions: &[&str], out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(folder)
        .unwrap_or_else(|error| panic!("{}: {error}", folder.display()))
        .map(|entry| entry.expect("a folder entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            files_ending(&path, extensions, out);
        } else if path
            .extension()
            .is_some_and(|extension| extensions.iter().any(|wanted| extension == *wanted))
        {
            out.push(path);
        }
    }
}

#[test]
fn every_file_keeps_to_its_layer() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let roots = root_names();
    let mut files = Vec::new();
    source_files(&root.join("src"), &mut files);
    source_files(&root.join("chapters"), &mut files);
    assert!(files.len() > 50, "only {} files", files.len());
    let mut broken = Vec::new();
    for file in files {
        let path = file
            .strip_prefix(root)
            .expect("inside the crate")
            .to_string_lossy()
            .replace('\\', "/");
        match layer_of(&path) {
            Ok(Some(layer)) => broken.extend(violations(&path, layer, &read(&path), &roots)),
            Ok(None) => {}
            Err(problem) => broken.push(problem),
        }
    }
    assert!(
        broken.is_empty(),
        "layer rules broken (docs/architecture.md):\n{}",
        broken.join("\n")
    );
}

/// The rule can fail: an upward import planted in a foundation, a tool
/// that reaches for the command line, a chapter's cases that print, a
/// scene that derives clap's trait.
#[test]
fn planted_upward_imports_are_named() {
    let roots = root_names();
    let cases = [
        (
            "src/scene.rs",
            Layer::Foundation,
            "use crate::render::Tracer;\n",
            "crate::render",
        ),
        (
            "src/shapes/plane.rs",
            Layer::Foundation,
            "fn f() { crate::Reference::default(); }\n",
            "crate::Reference",
        ),
        (
            "src/render.rs",
            Layer::Engine,
            "use crate::crosscheck::MAX_RECORDED_RAYS;\n",
            "crate::crosscheck",
        ),
        (
            "src/check/mod.rs",
            Layer::Tool,
            "const X: i32 = crate::cli::EXIT_ERROR;\n",
            "crate::cli",
        ),
        (
            "chapters/99_planted/chapter.rs",
            Layer::Engine,
            "use raylab::check::Case;\n",
            "raylab::check",
        ),
        (
            "chapters/99_planted/checks.rs",
            Layer::Tool,
            "fn f() { println!(\"x\"); }\n",
            "prints",
        ),
        (
            "src/cost.rs",
            Layer::Tool,
            "#[derive(clap::ValueEnum)]\nenum K { A }\n",
            "clap",
        ),
    ];
    for (path, layer, text, named) in cases {
        let found = violations(path, layer, text, &roots);
        assert!(
            found.len() == 1 && found[0].contains(named),
            "{path}: {found:?}"
        );
    }
    // Code after a test module is code.
    let after_tests = "#[cfg(test)]\nmod tests {\n    fn f() { {} }\n}\nuse crate::cli::Cli;\n";
    let found = violations("src/scene.rs", Layer::Foundation, after_tests, &roots);
    assert!(
        found.len() == 1 && found[0].contains("src/scene.rs:5"),
        "{found:?}"
    );
    // Comments, strings and tests are not code.
    let quiet = "// crate::cli\nconst S: &str = \"crate::cli::X\";\nconst R: &str = r#\"raylab::cli\"#;\n\
                 #[cfg(test)]\nmod tests { use crate::cli; }\n";
    assert_eq!(
        violations("src/scene.rs", Layer::Foundation, quiet, &roots),
        Vec::<String>::new()
    );
    assert!(layer_of("src/new_module.rs").is_err());
    // A folder module's files take the folder's layer.
    assert_eq!(layer_of("src/bvh_reports/race.rs"), Ok(Some(Layer::Tool)));
}

/// The trait, `Textbook`'s forwards and the planted variants' table are
/// made from one list (`raylab::course::FUNCTIONS`'s): it must name every
/// function of the registry, in its chapter, and mark `drives` exactly the
/// functions that take the chapters' own tracer or objects, which
/// `Textbook<C>` cannot hand to `C` (a pure function marked so would
/// silently run the reference under `--sphere-formula textbook`).
#[test]
fn the_course_list_is_the_registry_s_functions() {
    use raylab::chapters::CHAPTERS;
    use raylab::course::FUNCTIONS;
    let listed: Vec<(String, &str)> = FUNCTIONS
        .iter()
        .map(|function| (function.module.to_string(), function.name))
        .collect();
    let registered: Vec<(String, &str)> = CHAPTERS
        .iter()
        .flat_map(|info| info.functions.iter().map(|name| (info.module(), *name)))
        .collect();
    assert_eq!(listed, registered);
    for function in FUNCTIONS {
        let own = ["Tracer <", "Objects <"]
            .iter()
            .any(|own| function.arguments.contains(own));
        assert_eq!(
            function
                .markers
                .split_whitespace()
                .any(|marker| marker == "drives"),
            own,
            "{}: ({}) [{}]",
            function.name,
            function.arguments,
            function.markers
        );
    }
}

/// Whether `text` names a chapter by its folder's stem (`42_lens`) or its
/// module (`ch42_lens`) as a whole word.
fn names_chapter(text: &str, stem: &str) -> bool {
    let is_word = |c: char| c.is_ascii_alphanumeric() || c == '_';
    text.match_indices(stem).any(|(at, _)| {
        let before = text[..at].strip_suffix("ch").unwrap_or(&text[..at]);
        let after = &text[at + stem.len()..];
        !before.chars().next_back().is_some_and(is_word)
            && !after.chars().next().is_some_and(is_word)
    })
}

/// The files outside `chapters/<folder>/` (code, manifests and scripts;
/// docs aside) that name the chapter.
fn files_naming(folder: &str, files: &[(String, String)]) -> Vec<String> {
    let inside = format!("chapters/{folder}/");
    files
        .iter()
        .filter(|(path, text)| !path.starts_with(&inside) && names_chapter(text, folder))
        .map(|(path, _)| path.clone())
        .collect()
}

/// Adding a chapter is its folder, its registry line and its methods in the
/// course trait: besides the registry and the trait, at most one more file
/// may name a chapter.
#[test]
fn at_most_three_files_outside_a_chapter_folder_name_the_chapter() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut paths = vec![root.join("build.rs"), root.join("Cargo.toml")];
    for folder in ["src", "chapters", "tests", "benches", "scripts"] {
        files_ending(&root.join(folder), &["rs", "toml", "sh"], &mut paths);
    }
    let files: Vec<(String, String)> = paths
        .iter()
        .map(|path| {
            let relative = path.strip_prefix(root).expect("inside the crate");
            let relative = relative.to_string_lossy().replace('\\', "/");
            (relative.clone(), read(&relative))
        })
        .collect();
    assert!(files.len() > 80, "only {} files", files.len());
    let mut crowded = Vec::new();
    for info in raylab::chapters::CHAPTERS {
        let naming = files_naming(info.folder, &files);
        if naming.len() > 3 {
            crowded.push(format!("{}: {}", info.folder, naming.join(", ")));
        }
    }
    assert!(
        crowded.is_empty(),
        "more than three files outside a chapter's folder name it:\n{}",
        crowded.join("\n")
    );
    // The count can fail: four files naming a chapter are found, by stem or
    // by module, in code or in comments.
    let planted: Vec<(String, String)> = [
        ("src/a.rs", "use crate::chapters::ch42_lens::focus;"),
        ("tests/b.rs", "// chapters/42_lens/lesson.md"),
        ("scripts/c.sh", "cat chapters/42_lens/scene.toml"),
        ("Cargo.toml", "# ch42_lens"),
        ("chapters/42_lens/chapter.rs", "//! ch42_lens"),
    ]
    .into_iter()
    .map(|(path, text)| (path.to_string(), text.to_string()))
    .collect();
    assert_eq!(files_naming("42_lens", &planted).len(), 4);
    assert!(!names_chapter("ch142_lens 42_lenses x42_lens", "42_lens"));
}

/// Runs `git` in `repo`, failing the test with its stderr.
fn git(repo: &Path, args: &[&str]) {
    let output = std::process::Command::new("git")
        .args([
            "-c",
            "user.name=t",
            "-c",
            "user.email=t@t",
            "-c",
            "commit.gpgsign=false",
        ])
        .args(args)
        .current_dir(repo)
        .output()
        .expect("git runs");
    assert!(
        output.status.success(),
        "git {args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// Writes `files` (path, text) into `repo` and commits them as `message`.
fn commit(repo: &Path, files: &[&str], message: &str) {
    for file in files {
        let path = repo.join(file);
        std::fs::create_dir_all(path.parent().expect("a file has a folder")).expect("mkdir");
        let before = std::fs::read_to_string(&path).unwrap_or_default();
        std::fs::write(&path, format!("{before}{message}\n")).expect("write");
    }
    git(repo, &["add", "-A"]);
    git(repo, &["commit", "-q", "-m", message]);
}

#[test]
fn the_footprint_script_counts_what_a_chapters_commits_touched_outside_its_folder() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let repo = dir.path();
    git(repo, &["init", "-q"]);
    commit(
        repo,
        &["chapters/01_first/chapter.rs", "src/lib.rs"],
        "chapter 1",
    );
    commit(
        repo,
        &[
            "chapters/02_second/chapter.rs",
            "chapters/mod.rs",
            "docs/course.md",
        ],
        "chapter 2",
    );
    commit(
        repo,
        &["src/render.rs", "snapshots/chapter-2.png", "README.md"],
        "its tool",
    );
    commit(
        repo,
        &["chapters/03_third/chapter.rs", "src/course.rs"],
        "chapter 3",
    );
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/chapter-footprint.sh");
    let run = |args: &[&str]| {
        let output = std::process::Command::new("bash")
            .arg(&script)
            .args(args)
            .current_dir(repo)
            .output()
            .expect("bash runs");
        (
            output.status.success(),
            String::from_utf8_lossy(&output.stdout).into_owned(),
            String::from_utf8_lossy(&output.stderr).into_owned(),
        )
    };
    // Chapter 2's commits end where chapter 3's begin; its folder, docs,
    // snapshots and READMEs aside.
    let (ok, out, err) = run(&["2"]);
    assert!(ok, "{err}");
    assert_eq!(
        out,
        "chapters/mod.rs\nsrc/render.rs\n2 files outside chapters/02_*/ in 2 commits\n"
    );
    // The last chapter's run to HEAD; `--until` ends the range earlier.
    let (ok, out, err) = run(&["3"]);
    assert!(ok, "{err}");
    assert_eq!(
        out,
        "src/course.rs\n1 files outside chapters/03_*/ in 1 commits\n"
    );
    let (ok, out, err) = run(&["2", "--until", "HEAD~2"]);
    assert!(ok, "{err}");
    assert_eq!(
        out,
        "chapters/mod.rs\n1 files outside chapters/02_*/ in 1 commits\n"
    );
    // A chapter no commit adds is an error, not an empty footprint.
    let (ok, _, err) = run(&["9"]);
    assert!(!ok);
    assert!(err.contains("no commit adds a file of chapter 9"), "{err}");
}

/// The modules that may import each other in a circle, and why: the
/// `Chapters` trait (`course`) has the chapters' code (`chapters`) as its
/// defaults, that code casts its rays through the tracer (`render`), and the
/// tracer is generic over the trait (`Tracer<Self>`). It is the seam
/// between the course and the engine, and the one deliberate circle.
const SEAM: &[&str] = &["chapters", "course", "render"];

/// Where a file sits in the module tree: its top-level module and, below
/// that, the child module it is part of (`src/check/judge.rs` is `check`'s
/// child `judge`; a chapter's `chapter.rs` is `chapters`' child
/// `chNN_name`; its `checks.rs` and `kinds.rs` are the judge's,
/// `check::by_chapter` and `check::chapter_kinds`).
/// `None` for test code and for the crate root, which only re-exports.
fn module_of(path: &str) -> Option<(String, Option<String>)> {
    // Test code and the crate root have no layer: no module to place.
    layer_of(path).ok()??;
    if let Some(rest) = path.strip_prefix("chapters/") {
        return match rest.split_once('/') {
            None => Some(("chapters".into(), None)),
            Some((_, "checks.rs")) => Some(("check".into(), Some("by_chapter".into()))),
            Some((_, "kinds.rs")) => Some(("check".into(), Some("chapter_kinds".into()))),
            Some((folder, _)) => Some(("chapters".into(), Some(format!("ch{folder}")))),
        };
    }
    let rest = path.strip_prefix("src/")?;
    let mut parts = rest.split('/');
    let top = parts.next()?.trim_end_matches(".rs").to_string();
    let child = parts
        .next()
        .map(|child| child.trim_end_matches(".rs").to_string())
        .filter(|child| child != "mod");
    Some((top, child))
}

/// One import: the file and line that names another module.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct Import {
    from: String,
    to: String,
    at: String,
}

/// The first two names of each path of `code` that starts with one of
/// `prefixes` (`crate::a::b`, `crate::a::{b, c}`, `crate::{a, b::c}`), with
/// the byte offset of the path.
fn named_paths(code: &str, prefixes: &[&str]) -> Vec<(usize, String, Option<String>)> {
    let word = |text: &str| -> String {
        text.split(|c: char| !(c.is_alphanumeric() || c == '_'))
            .next()
            .unwrap_or("")
            .to_string()
    };
    let group = |text: &str| -> Vec<String> {
        let inner = &text[..text.find('}').unwrap_or(text.len())];
        inner
            .split(',')
            .map(|item| item.trim().to_string())
            .collect()
    };
    let mut found = Vec::new();
    for prefix in prefixes {
        for (at, _) in code.match_indices(prefix) {
            let before = code[..at].chars().next_back();
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            let after = &code[at + prefix.len()..];
            let items = match after.strip_prefix('{') {
                Some(inner) => group(inner),
                None => vec![after.to_string()],
            };
            for item in items {
                let first = word(&item);
                if first.is_empty() {
                    continue;
                }
                let rest = item[first.len()..].trim_start();
                let Some(rest) = rest.strip_prefix("::") else {
                    found.push((at, first, None));
                    continue;
                };
                match rest.strip_prefix('{') {
                    Some(inner) => {
                        for second in group(inner) {
                            found.push((at, first.clone(), Some(word(&second))));
                        }
                    }
                    None => found.push((at, first, Some(word(rest)))),
                }
            }
        }
    }
    found
}

/// Every import between two top-level modules, and between two children
/// of one top-level module (siblings), in `files` (path and text).
fn imports(
    files: &[(String, String)],
    roots: &BTreeMap<String, String>,
) -> (Vec<Import>, Vec<Import>) {
    let mut children: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for (path, _) in files {
        if let Some((top, Some(child))) = module_of(path) {
            children.entry(top).or_default().push(child);
        }
    }
    let (mut between, mut siblings) = (Vec::new(), Vec::new());
    for (path, text) in files {
        let Some((top, child)) = module_of(path) else {
            continue;
        };
        let code = code_only(text);
        let line_of = |at: usize| code[..at].matches('\n').count() + 1;
        for (at, first, second) in named_paths(&code, &["crate::", "raylab::"]) {
            let target = roots.get(&first).cloned().unwrap_or(first.clone());
            if module_layer(&target).is_none() {
                continue;
            }
            let at = format!("{path}:{}", line_of(at));
            if target != top {
                between.push(Import {
                    from: top.clone(),
                    to: target,
                    at,
                });
            } else if let (Some(child), Some(second)) = (&child, second) {
                let known = children.get(&top).is_some_and(|all| all.contains(&second));
                if known && &second != child {
                    siblings.push(Import {
                        from: format!("{top}::{child}"),
                        to: format!("{top}::{second}"),
                        at,
                    });
                }
            }
        }
        // `super::sibling` from a direct child of a folder module.
        let direct_child = path.starts_with("src/") && path.matches('/').count() == 2;
        if let (Some(child), true) = (&child, direct_child) {
            for (at, first, _) in named_paths(&code, &["super::"]) {
                let known = children.get(&top).is_some_and(|all| all.contains(&first));
                if known && &first != child {
                    siblings.push(Import {
                        from: format!("{top}::{child}"),
                        to: format!("{top}::{first}"),
                        at: format!("{path}:{}", line_of(at)),
                    });
                }
            }
        }
    }
    (between, siblings)
}

/// The circles among `imports`: each strongly connected set of two or more
/// modules (Tarjan's algorithm), sorted, with the imports inside it.
fn circles(imports: &[Import]) -> Vec<(Vec<String>, Vec<Import>)> {
    let mut next: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for import in imports {
        next.entry(&import.from).or_default().push(&import.to);
        next.entry(&import.to).or_default();
    }
    struct Walk<'a> {
        next: &'a BTreeMap<&'a str, Vec<&'a str>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'a>(walk: &mut Walk<'a>, node: &'a str) {
        let index = walk.index.len();
        walk.index.insert(node, index);
        walk.low.insert(node, index);
        walk.stack.push(node);
        for &target in &walk.next[node] {
            if !walk.index.contains_key(target) {
                visit(walk, target);
                let low = walk.low[node].min(walk.low[target]);
                walk.low.insert(node, low);
            } else if walk.stack.contains(&target) {
                let low = walk.low[node].min(walk.index[target]);
                walk.low.insert(node, low);
            }
        }
        if walk.low[node] == walk.index[node] {
            let mut set = Vec::new();
            while let Some(top) = walk.stack.pop() {
                set.push(top.to_string());
                if top == node {
                    break;
                }
            }
            if set.len() > 1 {
                set.sort();
                walk.found.push(set);
            }
        }
    }
    let mut walk = Walk {
        next: &next,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        found: Vec::new(),
    };
    for &node in next.keys() {
        if !walk.index.contains_key(node) {
            visit(&mut walk, node);
        }
    }
    let mut found: Vec<_> = walk
        .found
        .into_iter()
        .map(|set| {
            let mut inside: Vec<Import> = imports
                .iter()
                .filter(|import| set.contains(&import.from) && set.contains(&import.to))
                .cloned()
                .collect();
            inside.sort();
            inside.dedup_by(|a, b| a.from == b.from && a.to == b.to);
            (set, inside)
        })
        .collect();
    found.sort();
    found
}

/// Each circle but the seam's, as a message naming its modules and one
/// import of each pair that closes it.
fn circles_broken(files: &[(String, String)], roots: &BTreeMap<String, String>) -> Vec<String> {
    let (between, siblings) = imports(files, roots);
    let mut broken = Vec::new();
    for (set, inside) in circles(&between).into_iter().chain(circles(&siblings)) {
        if set.iter().map(String::as_str).eq(SEAM.iter().copied()) {
            continue;
        }
        let edges: Vec<String> = inside
            .iter()
            .map(|import| format!("  {} -> {} ({})", import.from, import.to, import.at))
            .collect();
        broken.push(format!(
            "modules {} import each other in a circle:\n{}",
            set.join(", "),
            edges.join("\n")
        ));
    }
    broken
}

/// Every file of `src/` and `chapters/`, by its path in the crate, with its text.
fn crate_files() -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    source_files(&root.join("src"), &mut files);
    source_files(&root.join("chapters"), &mut files);
    files
        .into_iter()
        .map(|file| {
            let path = file
                .strip_prefix(root)
                .expect("inside the crate")
                .to_string_lossy()
                .replace('\\', "/");
            let text = read(&path);
            (path, text)
        })
        .collect()
}

/// No two modules import each other, directly or around a circle, but the
/// seam's (`SEAM`): a circle means neither can be understood, tested or
/// moved without the other, and a new chapter's code would have to touch
/// both.
#[test]
fn no_circle_but_the_seams() {
    let broken = circles_broken(&crate_files(), &root_names());
    assert!(
        broken.is_empty(),
        "import circles (docs/architecture.md, Invariants):\n{}",
        broken.join("\n")
    );
    // The seam is still a circle: were it gone, `SEAM` would excuse nothing.
    let (between, _) = imports(&crate_files(), &root_names());
    let seam: Vec<String> = SEAM.iter().map(|name| name.to_string()).collect();
    assert!(
        circles(&between).iter().any(|(set, _)| *set == seam),
        "the seam {SEAM:?} is no longer a circle: shrink SEAM and its paragraph in docs/architecture.md"
    );
}

/// The circle test can fail: a foundation that names a module naming it
/// back, two children of one module that use each other, one of them
/// through `super::`, and a circle closed by code after a test module.
#[test]
fn planted_circles_are_named() {
    let roots = root_names();
    let file = |path: &str, text: &str| (path.to_string(), text.to_string());
    let between = [
        file("src/ray.rs", "use crate::shapes::Shape;\n"),
        file(
            "src/shapes/mod.rs",
            "pub fn f() -> crate::ray::Ray { todo!() }\n",
        ),
    ];
    let found = circles_broken(&between, &roots);
    assert!(
        found.len() == 1 && found[0].contains("ray, shapes") && found[0].contains("src/ray.rs:1"),
        "{found:?}"
    );
    let siblings = [
        file(
            "src/check/judge.rs",
            "use crate::check::{remote::Asked, protocol};\n",
        ),
        file("src/check/remote.rs", "use super::judge::Asker;\n"),
        file("src/check/protocol.rs", "pub struct Wire;\n"),
    ];
    let found = circles_broken(&siblings, &roots);
    assert!(
        found.len() == 1 && found[0].contains("check::judge, check::remote"),
        "{found:?}"
    );
    let after_tests = [
        file(
            "src/camera.rs",
            "#[cfg(test)]\nmod tests {\n    fn f() { if true { } }\n}\n\nuse crate::scene::Scene;\n",
        ),
        file("src/scene.rs", "use crate::camera::Camera;\n"),
    ];
    let found = circles_broken(&after_tests, &roots);
    assert!(
        found.len() == 1 && found[0].contains("src/camera.rs:6"),
        "{found:?}"
    );
    // An import inside a test module is a test's, not the module's.
    let only_tests = [
        file(
            "src/camera.rs",
            "#[cfg(test)]\nmod tests {\n    use crate::scene::Scene;\n}\n",
        ),
        file("src/scene.rs", "use crate::camera::Camera;\n"),
    ];
    assert_eq!(circles_broken(&only_tests, &roots), Vec::<String>::new());
    // The seam's circle is allowed; a fourth module joining it is not.
    let seam = [
        file("src/course.rs", "use crate::chapters::Reference;\n"),
        file(
            "chapters/99_planted/chapter.rs",
            "use raylab::render::Tracer;\n",
        ),
        file("src/render/mod.rs", "use crate::course::Chapters;\n"),
    ];
    assert_eq!(circles_broken(&seam, &roots), Vec::<String>::new());
    let mut joined = seam.to_vec();
    joined.push(file("src/effects.rs", "use crate::chapters::CHAPTERS;\n"));
    joined.push(file("chapters/mod.rs", "use crate::effects::Effects;\n"));
    let found = circles_broken(&joined, &roots);
    assert!(
        found.len() == 1 && found[0].contains("effects"),
        "{found:?}"
    );
}

/// The longest a file of `src/` may be, tests included: past it a file
/// holds more than one concern, and a reader cannot keep it in mind.
const MAX_LINES: usize = 1_200;

/// Each file of `src/` longer than [`MAX_LINES`], with its length.
fn too_long(files: &[(String, String)]) -> Vec<String> {
    files
        .iter()
        .filter(|(path, _)| path.starts_with("src/"))
        .map(|(path, text)| (path, text.lines().count()))
        .filter(|&(_, lines)| lines > MAX_LINES)
        .map(|(path, lines)| format!("{path}: {lines} lines"))
        .collect()
}

#[test]
fn no_source_file_is_over_1200_lines() {
    let long = too_long(&crate_files());
    assert!(
        long.is_empty(),
        "split these by concern (docs/architecture.md):\n{}",
        long.join("\n")
    );
    let planted = [("src/scene.rs".to_string(), "\n".repeat(MAX_LINES + 1))];
    assert_eq!(too_long(&planted), ["src/scene.rs: 1201 lines"]);
}
