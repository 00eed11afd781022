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
            _ if rest.ends_with("/checks.rs") => Ok(Some(Layer::Tool)),
            _ => Err(format!(
                "{path}: a chapter folder holds chapter.rs, checks.rs, tests.rs and gallery.rs"
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
        "course" | "bsdf" | "answer_key" | "render" | "record" | "effects" | "builtin"
        | "chapters" => Layer::Engine,
        "check" | "grade" | "workspace" | "cost" | "crosscheck" | "bvh_reports" | "diff"
        | "embree" | "plots" | "implicit_probe" | "ray_tree" | "web" => Layer::Tool,
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

/// `text` without comments, string and character literals (replaced by
/// spaces, so line numbers stay), and without its `#[cfg(test)]` modules.
fn code_only(text: &str) -> String {
    let text = match text.find("#[cfg(test)]\nmod ") {
        Some(at) => &text[..at],
        None => text,
    };
    let bytes = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut at = 0;
    let blank = |slice: &str, out: &mut String| {
        out.extend(slice.chars().map(|c| if c == '\n' { '\n' } else { ' ' }))
    };
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
        blank(&rest[..end], &mut out);
        at += end;
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

/// `Textbook<C>` swaps in the textbook intersections and must otherwise be
/// `C`: every method of `Chapters` that does not take the chapters' own
/// tracer or objects (which `Textbook<C>` cannot hand to `C`) forwards to
/// `C`. A method added to the trait and not forwarded would silently run
/// the reference under `--sphere-formula textbook`.
#[test]
fn textbook_forwards_every_method_it_can() {
    use raylab::workspace::scan::{ItemKind, items};
    let course = read("src/course.rs");
    let top = items(&course).expect("src/course.rs scans");
    let block = |item: &raylab::workspace::scan::Item| {
        let text = &course[item.header..item.range.end];
        let open = text.find('{').expect("a block");
        text[open + 1..text.len() - 1].to_string()
    };
    let methods = |text: &str| -> Vec<(String, String)> {
        items(text)
            .expect("a block scans")
            .into_iter()
            .filter(|item| item.kind == ItemKind::Fn)
            .map(|item| {
                let end = item.body.clone().map_or(item.range.end, |body| body.start);
                (
                    item.name.clone().unwrap_or_default(),
                    text[item.header..end].to_string(),
                )
            })
            .collect()
    };
    let trait_block = top
        .iter()
        .find(|item| item.kind == ItemKind::Trait && item.name.as_deref() == Some("Chapters"))
        .map(block)
        .expect("trait Chapters");
    let textbook_block = top
        .iter()
        .find(|item| {
            item.kind == ItemKind::Impl
                && course[item.header..item.range.end].contains("for Textbook<")
        })
        .map(block)
        .expect("impl Chapters for Textbook");
    let forwarded: Vec<String> = methods(&textbook_block)
        .into_iter()
        .map(|(name, _)| name)
        .collect();
    let mut missing = Vec::new();
    for (name, signature) in methods(&trait_block) {
        let own_types = ["Tracer<Self>", "Objects<Self>"];
        let forwardable = !own_types.iter().any(|own| signature.contains(own));
        if forwardable && !forwarded.contains(&name) {
            missing.push(name);
        }
    }
    assert!(
        missing.is_empty(),
        "Textbook does not forward {missing:?} to its C"
    );
    assert!(forwarded.len() >= 15, "only {forwarded:?}");
}

/// Every default of the trait is raylab's answer, so each reports itself
/// to `answer_key` under its own name before it answers: a student's
/// `impl Chapters` that keeps one is caught (src/answer_key.rs).
#[test]
fn every_default_of_the_trait_reports_to_the_answer_key() {
    use raylab::workspace::scan::{ItemKind, items};
    let course = read("src/course.rs");
    let top = items(&course).expect("src/course.rs scans");
    let chapters = top
        .iter()
        .find(|item| item.kind == ItemKind::Trait && item.name.as_deref() == Some("Chapters"))
        .expect("trait Chapters");
    let text = &course[chapters.header..chapters.range.end];
    let open = text.find('{').expect("a block");
    let block = &text[open + 1..text.len() - 1];
    let mut silent = Vec::new();
    let mut defaults = 0;
    for item in items(block).expect("the trait scans") {
        let (Some(name), Some(body)) = (item.name.clone(), item.body.clone()) else {
            continue;
        };
        if item.kind != ItemKind::Fn {
            continue;
        }
        defaults += 1;
        let report =
            format!("crate::answer_key::answered_by(Self::COMPARISON, \"Chapters::{name}\")");
        if !block[body].contains(&report) {
            silent.push(name);
        }
    }
    assert!(
        silent.is_empty(),
        "these defaults do not report: {silent:?}"
    );
    assert!(defaults >= 28, "only {defaults} defaults");
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
