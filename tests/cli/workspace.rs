//! `raylab new`: a student workspace is generated from the registry, builds
//! offline against this checkout, reports unwritten chapters as "not
//! started" (never a backtrace), and its answer key renders exactly what
//! raylab renders.
//!
//! Building a workspace is slow (it compiles raylab as a dependency), so the
//! two workspaces, `todo` and `answer`, are built once, by two cargo
//! invocations into this test's own target folder (raylab's dependencies
//! are already there), and shared by the tests below.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

use common::{raylab, stderr, stdout};
use raylab::chapters::CHAPTERS;

pub(crate) struct Workspaces {
    pub(crate) root: PathBuf,
    pub(crate) todo: PathBuf,
    pub(crate) answer: PathBuf,
    /// The target folder the workspaces were built into.
    pub(crate) target: PathBuf,
}

/// This test's target folder: the raylab binary is `<target>/<profile>/raylab`.
pub(crate) fn target_dir() -> PathBuf {
    let binary = Path::new(env!("CARGO_BIN_EXE_raylab"));
    binary
        .parent()
        .and_then(Path::parent)
        .expect("the raylab binary is in <target>/<profile>/")
        .to_path_buf()
}

pub(crate) fn workspaces() -> &'static Workspaces {
    static BUILT: OnceLock<Workspaces> = OnceLock::new();
    BUILT.get_or_init(|| {
        let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("workspace-test");
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(&root).expect("create the test folder");
        let todo = root.join("student-todo");
        let answer = root.join("student-answer");
        let cheat = root.join("student-cheat");
        let main_cheat = root.join("student-main");
        for (dir, extra) in [
            (&todo, None),
            (&answer, Some("--solutions")),
            (&cheat, Some("--solutions")),
            (&main_cheat, None),
        ] {
            let mut args = vec!["new", dir.to_str().expect("UTF-8 path")];
            args.extend(extra);
            let output = raylab(&args, &root);
            assert!(output.status.success(), "raylab new: {}", stderr(&output));
        }
        let glue = cheat.join("src/chapters/mod.rs");
        let mut text = read(&glue);
        for (honest, cheating) in CHEATS {
            assert!(text.contains(honest), "{honest} not in {text}");
            text = text.replace(honest, cheating);
        }
        // Chapter 5 forges replies where `forged.frames` is (see FORGER).
        let phong = format!(
            "        {}::phong_terms(material, albedo, normal, to_light, to_eye, light)",
            module_of(5)
        );
        assert!(text.contains(&phong), "{phong} not in {text}");
        text = text.replace(
            &phong,
            &format!(
                "        if let Ok(frames) = std::fs::read(\"forged.frames\") {{\n            \
                 forge_replies(&frames);\n            \
                 return PhongTerms {{ diffuse: Vec3::splat(9.0), specular: Vec3::splat(9.0) }};\n        \
                 }}\n{phong}"
            ),
        );
        text.push_str(TABLE_LOOKUP);
        text.push_str(FORGER);
        std::fs::write(&glue, text).expect("write the glue");
        // The answer key's chapter 2 tells each new radius it meets on
        // stderr (which never counts): a hidden scene's, if anything the
        // process writes while rendering it came back to the student. On
        // meeting the hidden scene's radius it starts threads until the
        // run's process limit refuses one: the limits the report states
        // must not tell of it.
        let answer_glue = answer.join("src/chapters/mod.rs");
        let sphere = "        ch02_sphere::intersect_sphere(sphere, ray, t_min, t_max)";
        let text = read(&answer_glue);
        assert!(text.contains(sphere), "{sphere} not in {text}");
        let told = "        static TOLD: std::sync::Mutex<Vec<u32>> = std::sync::Mutex::new(Vec::new());\n        \
             if let Ok(mut told) = TOLD.lock()\n            && !told.contains(&sphere.radius().to_bits())\n        {\n            \
             told.push(sphere.radius().to_bits());\n            \
             eprintln!(\"a sphere of radius {}\", sphere.radius());\n            \
             if (sphere.radius() * 1e4).round() == 6171.0 {\n                \
             for _ in 0..2000 {\n                    \
             let sleeper = std::thread::Builder::new().stack_size(64 << 10);\n                    \
             if sleeper.spawn(|| std::thread::sleep(std::time::Duration::from_secs(1))).is_err() {\n                        \
             break;\n                    }\n                }\n            }\n        }\n";
        std::fs::write(&answer_glue, text.replace(sphere, &format!("{told}{sphere}")))
            .expect("write the answer's glue");
        // raylab's own chapters run by the workspace's own main, from
        // outside the workspace.
        std::fs::write(
            main_cheat.join("src/main.rs"),
            "fn main() {\n    let _ = std::env::set_current_dir(\"/\");\n    \
             std::process::exit(raylab::cli::main_with::<raylab::Reference>())\n}\n",
        )
        .expect("write main.rs");
        let target = target_dir();
        for dir in [&todo, &answer, &cheat, &main_cheat] {
            let output = common::cargo()
                .args(["build", "--offline", "--quiet"])
                .current_dir(dir)
                .env("CARGO_TARGET_DIR", &target)
                .output()
                .expect("run cargo");
            assert!(
                output.status.success(),
                "building {} offline failed:\n{}",
                dir.display(),
                stderr(&output)
            );
        }
        Workspaces {
            root,
            todo,
            answer,
            target,
        }
    })
}

/// The cheating workspace's glue: each honest call to the student's
/// function, and what replaces it. Chapter 1 never returns when
/// `CHEAT_LOOP` is set, and ends the process (printing a passing table
/// first) when `CHEAT_EXIT` is; chapter 2 calls the
/// shape's own method; chapter 3 keeps the trait's default (raylab's
/// answer); chapter 6 calls `Reference`'s; chapter 8 calls `Reference`'s,
/// the first thousand times on a thread of its own; chapter 10 calls the comparison wrapper's
/// Moller-Trumbore; chapter 14 calls the scene's own Cauchy formula.
const CHEATS: &[(&str, &str)] = &[
    (
        "        ch01_plane::intersect_plane(plane, ray, t_min, t_max)",
        "        if std::env::var_os(\"CHEAT_LOOP\").is_some() {\n            \
         loop {\n                std::thread::sleep(std::time::Duration::from_secs(1));\n            }\n        }\n        \
         if std::env::var_os(\"CHEAT_EXIT\").is_some() {\n            \
         println!(\"chapter  status       cases   robustness     image\\n1        pass\");\n            \
         std::process::exit(0);\n        }\n        \
         if let Some(answer) = table_answer(plane, ray, t_min, t_max) {\n            \
         return answer;\n        }\n        \
         ch01_plane::intersect_plane(plane, ray, t_min, t_max)",
    ),
    (
        "        ch02_sphere::intersect_sphere(sphere, ray, t_min, t_max)",
        "        sphere.intersect(ray, t_min, t_max)",
    ),
    (
        "    fn nearest_hit(objects: &Objects<Self>, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {\n        ch03_nearest::nearest_hit(objects, ray, t_min, t_max)\n    }\n",
        "",
    ),
    (
        "        ch06_reflection::reflect(d, n)",
        "        <raylab::Reference as Chapters>::reflect(d, n)",
    ),
    (
        "        ch08_refraction::refract(d, n, eta)",
        "        // The checkpoints' calls, on a thread of their own; a render's\n        \
         // millions, where a thread each would take the check minutes, on this one.\n        \
         static CALLS: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);\n        \
         if CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed) < 1000 {\n            \
         return std::thread::spawn(move || <raylab::Reference as Chapters>::refract(d, n, eta))\n                \
         .join()\n                .ok()\n                .flatten();\n        }\n        \
         <raylab::Reference as Chapters>::refract(d, n, eta)",
    ),
    (
        "        ch10_triangles::intersect_triangle(triangle, ray, t_min, t_max)",
        "        <Textbook<crate::Mine, false, true> as Chapters>::intersect_triangle(triangle, ray, t_min, t_max)",
    ),
    (
        "        ch14_caustics::cauchy_ior(cauchy, nanometres)",
        "        cauchy.index_at(nanometres)",
    ),
];

/// The cheating workspace's forger: the bytes of a file `forged.frames`
/// (replies of the judge's protocol, made by the test) written to every
/// file descriptor this process can reach by a path, in the hope of
/// reaching the pipe the judge reads its answers from.
const FORGER: &str = r#"
fn forge_replies(frames: &[u8]) {
    use std::io::Write as _;
    for folder in ["/proc/self/fd", "/dev/fd"] {
        for fd in 0..64 {
            let path = format!("{folder}/{fd}");
            if let Ok(mut file) = std::fs::OpenOptions::new().write(true).open(&path) {
                let _ = file.write_all(frames);
            }
        }
    }
}
"#;

/// The cheating workspace's table of answers: where a file `answers.table`
/// is in the folder it runs in, chapter 1 answers from it, every call it
/// does not list with no hit. Where a file `answers.program` is, the table
/// is what that program (its first word, with the others as arguments)
/// prints instead: answers computed by another program, which the
/// answering process may not start. Each line is a call's inputs (the plane's
/// point and normal, the ray's origin and direction, `t_min`, `t_max`, as
/// the bits of each `f32` in hex) and its answer (`none`, or the bits of
/// `t`).
const TABLE_LOOKUP: &str = r#"
fn table_answer(
    plane: &raylab::Plane,
    ray: &raylab::Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Option<f32>> {
    use std::collections::HashMap;
    static TABLE: std::sync::OnceLock<Option<HashMap<Vec<u32>, Option<f32>>>> =
        std::sync::OnceLock::new();
    let table = TABLE.get_or_init(|| {
        let text = match std::fs::read_to_string("answers.program") {
            // A program that cannot run prints an empty table: no hit
            // anywhere, rather than the workspace's own answers.
            Ok(program) => {
                let mut words = program.split_whitespace();
                std::process::Command::new(words.next()?)
                    .args(words)
                    .output()
                    .map(|printed| String::from_utf8_lossy(&printed.stdout).into_owned())
                    .unwrap_or_default()
            }
            Err(_) => std::fs::read_to_string("answers.table").ok()?,
        };
        let mut table = HashMap::new();
        for line in text.lines() {
            let mut words = line.split(' ');
            let key: Vec<u32> = words
                .by_ref()
                .take(14)
                .map(|word| u32::from_str_radix(word, 16).unwrap_or(0))
                .collect();
            let answer = match words.next() {
                Some("none") | None => None,
                Some(bits) => Some(f32::from_bits(u32::from_str_radix(bits, 16).unwrap_or(0))),
            };
            table.insert(key, answer);
        }
        Some(table)
    });
    let table = table.as_ref()?;
    let mut key = Vec::new();
    for v in [plane.point(), plane.normal(), ray.origin, ray.dir] {
        key.extend(v.to_array().map(f32::to_bits));
    }
    key.extend([t_min.to_bits(), t_max.to_bits()]);
    Some(table.get(&key).copied().flatten())
}
"#;

/// Runs a workspace's binary (named after its package) in `dir`, with no
/// RUST_BACKTRACE so that what a student sees by default is tested.
fn run_student(binary: &str, args: &[&str], dir: &Path) -> Output {
    run_student_with(binary, args, dir, None)
}

/// [`run_student`] with `RUST_BACKTRACE` set to `backtrace`, or unset.
fn run_student_with(binary: &str, args: &[&str], dir: &Path, backtrace: Option<&str>) -> Output {
    let path = workspaces().target.join("debug").join(binary);
    let mut command = Command::new(&path);
    command.args(args).current_dir(dir);
    common::judged_by_this_raylab(&mut command);
    match backtrace {
        Some(value) => command.env("RUST_BACKTRACE", value),
        None => command.env_remove("RUST_BACKTRACE"),
    };
    command
        .output()
        .unwrap_or_else(|error| panic!("run {}: {error}", path.display()))
}

/// A student's binary holds none of raylab's answers: not the reference
/// chapters, nor the judge's oracles and expectations, nor the tools that
/// compute with them (the cost sweeps, the figures, grading). Its code
/// could otherwise run them by any trick that reaches the process's
/// memory (a soundness hole of the compiler, say), out of sight of the
/// answer key's reports. Read from the symbols of a workspace's binary,
/// the answer key's, whose chapters are all written.
#[test]
fn a_student_binary_holds_none_of_raylabs_answers() {
    let ws = workspaces();
    let binary = ws.target.join("debug").join("student-answer");
    let output = Command::new("nm")
        .args(["--demangle", "--defined-only"])
        .arg(&binary)
        .output()
        .expect("run nm (binutils)");
    assert!(output.status.success(), "{}", stderr(&output));
    let symbols = stdout(&output);
    // raylab's own code the binary must have, so that an empty listing
    // (a stripped binary) does not pass.
    assert!(symbols.contains("raylab::check::serve::"), "no serve");
    // Random draws of the cases' inputs live beside the oracles.
    let allowed = ["raylab::check::exact::Xorshift::"];
    let left_out = [
        "raylab::chapters::Reference as ",
        "raylab::course::Textbook<raylab::chapters::Reference",
        "raylab::check::exact::",
        "raylab::check::judge::",
        "raylab::check::sampled::",
        "raylab::check::catalog::",
        "raylab::check::by_chapter::",
        "raylab::cost::",
        "raylab::figure::",
        "raylab::crosscheck::",
        "raylab::implicit_probe::",
        "raylab::plots::",
        "raylab::grade::code::",
        "raylab::grade::class::",
        "raylab::bvh_reports::race::",
        "raylab::bvh_reports::measure::",
    ];
    // A symbol's name is its item's path (or `<Type as Trait>::method`);
    // raylab's types may appear inside other names (a command-line
    // option's enum), which is no code of theirs.
    let mut found: Vec<&str> = symbols
        .lines()
        .filter_map(|line| line.splitn(3, ' ').nth(2))
        .filter(|name| !allowed.iter().any(|ok| name.starts_with(ok)))
        .filter(|name| {
            left_out
                .iter()
                .any(|item| name.starts_with(item) || name.starts_with(&format!("<{item}")))
                || chapter_answer(name).is_some()
        })
        .collect();
    found.sort_unstable();
    found.dedup();
    assert!(
        found.is_empty(),
        "{} symbols of raylab's answers in a student's binary, among them:\n{}",
        found.len(),
        found
            .iter()
            .take(20)
            .copied()
            .collect::<Vec<_>>()
            .join("\n")
    );
    // Nor the reference images a chapter's render is compared with: a
    // process that held them could send them back as its render.
    let bytes = std::fs::read(&binary).expect("read the binary");
    for info in CHAPTERS {
        let png = info.reference_png;
        let middle = &png[png.len() / 2..png.len() / 2 + 64];
        assert!(
            !bytes.windows(middle.len()).any(|window| window == middle),
            "chapter {}'s reference image is in a student's binary",
            info.number
        );
    }
}

/// A workspace's `check` is judged by raylab's own binary of the same
/// source, never by another program: a judge named in `RAYLAB_JUDGE` that
/// is not one is refused, with what to do.
#[test]
fn a_workspace_check_is_judged_only_by_raylab_of_the_same_source() {
    let ws = workspaces();
    let binary = ws.target.join("debug").join("student-answer");
    for (judge, why) in [
        (
            "/bin/echo",
            "which is not raylab built from this workspace's raylab",
        ),
        ("/nonexistent/raylab", "cannot run it"),
    ] {
        let out = Command::new(&binary)
            .args(["check", "--chapter", "1"])
            .current_dir(&ws.answer)
            .env("RAYLAB_JUDGE", judge)
            .output()
            .expect("run the workspace");
        let message = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{judge}: {message}");
        assert!(message.contains(why), "{judge}: {message}");
        assert!(
            stdout(&out).is_empty(),
            "{judge}: a verdict without a judge"
        );
    }
}

/// The function of a reference chapter's module a symbol names (its own
/// code: `raylab::chapters::ch02_sphere::intersect_sphere`), if it does;
/// the chapters' question kinds (`kinds`), which a student's process
/// answers, are not answers.
fn chapter_answer(symbol: &str) -> Option<&str> {
    let rest = symbol
        .strip_prefix("raylab::chapters::ch")
        .or_else(|| symbol.strip_prefix("<raylab::chapters::ch"))?;
    let mut parts = rest.split("::");
    let _module = parts.next()?;
    let item = parts.next()?;
    (item != "kinds").then_some(item)
}

/// A workspace builds raylab without the optional `embree` feature (its
/// manifest asks only for `student`) nor raylab's answers: `crosscheck`,
/// which compares with them, says to run raylab's own, and `probe` traces
/// its ray with the workspace's chapters only.
#[test]
fn a_student_build_leaves_the_comparisons_to_raylab() {
    let ws = workspaces();
    let crosscheck = run_student(
        "student-answer",
        &["crosscheck", "--chapter", "1"],
        &ws.answer,
    );
    assert_eq!(crosscheck.status.code(), Some(2));
    let message = stderr(&crosscheck);
    assert!(
        message.contains("`crosscheck` measures chapters against raylab's own answers"),
        "{message}"
    );
    let probe = run_student(
        "student-answer",
        &["probe", "--ray", "0,1,-5,0,0,1"],
        &ws.answer,
    );
    assert!(probe.status.success(), "{}", stderr(&probe));
    let shown = stdout(&probe);
    assert!(shown.contains("ours:"), "{shown}");
    assert!(shown.contains("embree: not built in"), "{shown}");
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|error| panic!("{}: {error}", path.display()))
}

#[test]
fn the_workspace_has_a_file_per_chapter_and_a_todo_per_function() {
    let ws = workspaces();
    let main = read(&ws.todo.join("src/main.rs"));
    assert_eq!(main.lines().count(), 3, "{main}");
    assert!(main.contains("raylab::cli::main_with::<student_todo::Mine>()"));
    let manifest = read(&ws.todo.join("Cargo.toml"));
    assert!(
        manifest.contains(&format!(
            "raylab = {{ path = \"{}\", features = [\"student\"] }}",
            env!("CARGO_MANIFEST_DIR")
        )),
        "{manifest}"
    );
    let lock = read(&ws.todo.join("Cargo.lock"));
    assert!(lock.contains("name = \"raylab\""));
    let chapter_files: Vec<_> = std::fs::read_dir(ws.todo.join("src/chapters"))
        .expect("list")
        .map(|entry| {
            entry
                .expect("entry")
                .file_name()
                .into_string()
                .expect("UTF-8")
        })
        .filter(|name| name != "mod.rs")
        .collect();
    assert_eq!(chapter_files.len(), CHAPTERS.len(), "{chapter_files:?}");
    let checks = read(&ws.todo.join("tests/check.rs"));
    for info in CHAPTERS {
        let file = format!("src/chapters/{}.rs", info.module());
        let todo = read(&ws.todo.join(&file));
        let answer = read(&ws.answer.join(&file));
        for function in info.functions {
            assert!(
                todo.contains(&format!("pub fn {function}")),
                "{file}: {function}"
            );
            assert!(
                todo.contains(&format!("todo!(\"chapter {}: {function}\")", info.number)),
                "{file}: {function}"
            );
            assert!(
                answer.contains(&format!("pub fn {function}")),
                "{file}: {function}"
            );
        }
        assert!(!answer.contains("todo!("), "{file}");
        assert!(todo.contains(&info.lesson_path()), "{file}");
        assert!(
            checks.contains(&format!(
                "assert_chapter(env!(\"CARGO_BIN_EXE_student-todo\"), {})",
                info.number
            )),
            "{checks}"
        );
    }
}

#[test]
fn an_unwritten_chapter_is_not_started_not_a_backtrace() {
    let ws = workspaces();
    let out = ws.root.join("todo-out");
    std::fs::create_dir_all(&out).expect("create");
    for args in [
        &["render", "--chapter", "1"][..],
        &[
            "bench",
            "--chapter",
            "1",
            "--width",
            "8",
            "--height",
            "8",
            "--runs",
            "1",
        ],
    ] {
        // Many students have RUST_BACKTRACE=1 set: a todo!() still reads as
        // a sentence, not a trace.
        for backtrace in [None, Some("1")] {
            let output = run_student_with("student-todo", args, &out, backtrace);
            let text = stderr(&output);
            assert_eq!(output.status.code(), Some(1), "{args:?}: {text}");
            assert!(
                text.contains(&format!(
                    "chapter 1 not started: write intersect_plane in {}",
                    student_file(1)
                )),
                "{args:?}: {text}"
            );
            assert!(!text.contains("panicked at"), "{args:?}: {text}");
            assert!(!text.contains("backtrace"), "{args:?}: {text}");
        }
    }
    // Nothing half-written.
    assert!(!out.join("chapter-1.png").exists());
}

/// A student's binary is a command-line tool like raylab's own: piped into
/// a reader that has gone (`| head`), it stops quietly, killed by SIGPIPE,
/// rather than panicking on the failed write.
#[cfg(unix)]
#[test]
fn a_student_binary_stops_quietly_on_a_closed_pipe() {
    use std::os::unix::process::ExitStatusExt;
    let ws = workspaces();
    let binary = ws.target.join("debug").join("student-answer");
    let mut command = Command::new(&binary);
    command
        .args(["scene", "--chapter", "8"])
        .current_dir(&ws.root)
        .env_remove("RUST_BACKTRACE");
    let out = common::output_into_closed_pipe(command);
    let message = stderr(&out);
    assert!(!message.contains("panicked"), "{message}");
    assert_eq!(out.status.signal(), Some(libc::SIGPIPE), "{message}");
}

/// Chapter 11's functions share raylab's tree types and their answer key
/// keeps private helper types (a node stack, the best hit so far): the
/// skeleton must still read as not started, and the answer key must pass
/// both levels, image included.
#[test]
fn chapter_11_is_not_started_in_the_skeleton_and_robust_in_the_answer_key() {
    let ws = workspaces();
    let skeleton = read(&ws.todo.join(student_file(11)));
    assert!(!skeleton.contains("struct NodeStack"), "{skeleton}");
    let answer = read(&ws.answer.join(student_file(11)));
    assert!(answer.contains("> NodeStack<T> {"), "{answer}");

    let todo = run_student("student-todo", &["check", "--chapter", "11"], &ws.todo);
    let text = stdout(&todo);
    assert_eq!(todo.status.code(), Some(1), "{text}{}", stderr(&todo));
    assert!(
        text.contains("chapter 11: Bounding volume hierarchy - not started"),
        "{text}"
    );
    assert!(
        text.contains(
            "hit_box, build_bvh, nearest_hit_bvh, any_hit_bvh, hit_boxes, intersect_triangles, \
             collapse_bvh, nearest_hit_wide, any_hit_wide still todo!()"
        ),
        "{text}"
    );

    let key = run_student("student-answer", &["check", "--chapter", "11"], &ws.answer);
    let text = stdout(&key);
    assert!(key.status.success(), "{text}{}", stderr(&key));
    assert!(
        text.contains("chapter 11: Bounding volume hierarchy - pass (robust)"),
        "{text}"
    );
}

/// Chapters 13 and 14's checks build raylab's own converged image, on a
/// stage with a tree (and chapter 14's, light images): none of that is the
/// student's use of an answer, and the answer key passes both levels.
#[test]
fn chapters_13_and_14_are_not_started_in_the_skeleton_and_robust_in_the_answer_key() {
    let ws = workspaces();
    for (chapter, title) in [("13", "Path tracing"), ("14", "Caustics and dispersion")] {
        let todo = run_student("student-todo", &["check", "--chapter", chapter], &ws.todo);
        let text = stdout(&todo);
        assert_eq!(todo.status.code(), Some(1), "{text}{}", stderr(&todo));
        assert!(
            text.contains(&format!("chapter {chapter}: {title} - not started")),
            "{text}"
        );

        let key = run_student(
            "student-answer",
            &["check", "--chapter", chapter],
            &ws.answer,
        );
        let text = stdout(&key);
        assert!(key.status.success(), "{text}{}", stderr(&key));
        assert!(
            text.contains(&format!("chapter {chapter}: {title} - pass (robust)")),
            "{text}"
        );
    }
}

#[test]
fn the_answer_key_renders_what_raylab_renders_bit_for_bit() {
    let ws = workspaces();
    let out = ws.root.join("answer-out");
    std::fs::create_dir_all(&out).expect("create");
    let args = |output: &'static str| {
        [
            "render",
            "--chapter",
            "8",
            "--width",
            "160",
            "--height",
            "120",
            "--output",
            output,
        ]
    };
    let student = run_student("student-answer", &args("student.png"), &out);
    assert!(student.status.success(), "{}", stderr(&student));
    let reference = raylab(&args("raylab.png"), &out);
    assert!(reference.status.success(), "{}", stderr(&reference));
    let student = std::fs::read(out.join("student.png")).expect("read");
    let reference = std::fs::read(out.join("raylab.png")).expect("read");
    assert!(
        student == reference,
        "the answer key's chapter 8 differs from raylab's"
    );
}

/// Chapter 10 is the first whose functions take a generic parameter no
/// argument names (`smooth_hit_point<'a, C: Chapters>`) and whose file
/// keeps a helper beside them (`intersect_triangle_moller_trumbore`): the
/// skeleton and the answer key must still build and check as any chapter.
#[test]
fn chapter_10_is_not_started_in_the_skeleton_and_robust_in_the_answer_key() {
    let ws = workspaces();
    let file = student_file(10);
    let todo = read(&ws.todo.join(&file));
    assert!(
        todo.contains("pub fn smooth_hit_point<'a, C: Chapters>("),
        "{todo}"
    );
    assert!(
        !todo.contains("intersect_triangle_moller_trumbore"),
        "{todo}"
    );
    let answer = read(&ws.answer.join(&file));
    assert!(
        answer.contains("pub fn intersect_triangle_moller_trumbore("),
        "{answer}"
    );
    let forwarding = read(&ws.todo.join("src/chapters/mod.rs"));
    assert!(
        forwarding.contains(&format!(
            "{}::smooth_hit_point::<Self>(point, triangle, normals)",
            module_of(10)
        )),
        "{forwarding}"
    );

    let out = ws.root.join("check-10");
    std::fs::create_dir_all(&out).expect("create");
    let args = ["check", "--chapter", "10"];
    let output = run_student("student-todo", &args, &out);
    let text = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{text}{}", stderr(&output));
    assert!(
        text.contains("chapter 10: Triangle meshes - not started"),
        "{text}"
    );
    assert!(
        text.contains(
            "not started: intersect_triangle, barycentric, smooth_normal, terminator_point, \
             smooth_hit_point still todo!()"
        ),
        "{text}"
    );
    assert!(
        !stderr(&output).contains("panicked at"),
        "{}",
        stderr(&output)
    );

    let output = run_student("student-answer", &args, &out);
    let text = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{text}{}", stderr(&output));
    assert!(
        text.contains("chapter 10: Triangle meshes - pass (robust)"),
        "{text}"
    );
}

#[test]
fn new_refuses_a_folder_that_is_not_empty_and_fills_an_empty_one() {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("workspace-new");
    let _ = std::fs::remove_dir_all(&root);
    let taken = root.join("taken");
    std::fs::create_dir_all(&taken).expect("create");
    std::fs::write(taken.join("notes.txt"), "mine").expect("write");
    let output = raylab(&["new", "taken"], &root);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("is not empty"),
        "{}",
        stderr(&output)
    );
    let left: Vec<_> = std::fs::read_dir(&taken).expect("list").collect();
    assert_eq!(left.len(), 1, "the folder was changed");

    let empty = root.join("empty");
    std::fs::create_dir_all(&empty).expect("create");
    let output = raylab(&["new", "."], &empty);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(empty.join(student_file(1)).is_file());
    assert!(read(&empty.join("Cargo.toml")).contains("name = \"empty\""));
    // No staging folder is left beside.
    let staging: Vec<_> = std::fs::read_dir(&root)
        .expect("list")
        .filter_map(|entry| entry.ok())
        .filter(|entry| {
            entry
                .file_name()
                .to_string_lossy()
                .starts_with(".raylab-new-")
        })
        .collect();
    assert!(staging.is_empty());
}

/// The module of chapter `number` in the registry (a workspace names its
/// files after it).
fn module_of(number: u8) -> String {
    raylab::chapters::chapter(number)
        .expect("a chapter of the registry")
        .module()
}

/// Chapter `number`'s file in a student workspace.
fn student_file(number: u8) -> String {
    format!("src/chapters/{}.rs", module_of(number))
}

/// No pass for code the student did not write: a chapter that runs
/// raylab's own answer, by whichever route, fails `check` and `render`
/// writes nothing; a process that ends itself in the middle of the check
/// (after printing a passing table) fails; the chapters written honestly
/// still pass.
#[test]
fn a_chapter_that_runs_raylabs_answer_fails_and_an_early_exit_is_no_pass() {
    let ws = workspaces();
    let glue = read(&ws.root.join("student-cheat/src/chapters/mod.rs"));
    assert!(
        glue.contains("sphere.intersect(ray, t_min, t_max)"),
        "{glue}"
    );
    let dir = ws.root.join("cheat-out");
    std::fs::create_dir_all(&dir).expect("create");
    let honest = run_student("student-cheat", &["check", "--chapter", "1"], &dir);
    assert_eq!(honest.status.code(), Some(0), "{}", stdout(&honest));
    for (chapter, answer) in [
        ("2", "Sphere::intersect"),
        ("3", "nearest_hit"),
        ("6", "reflect"),
        ("8", "Chapters::refract"),
        ("10", "Textbook::intersect_triangle"),
    ] {
        let out = run_student("student-cheat", &["check", "--chapter", chapter], &dir);
        let text = stdout(&out);
        assert_eq!(out.status.code(), Some(1), "chapter {chapter}: {text}");
        let line = text
            .lines()
            .find(|line| line.contains("runs raylab's own answer instead of yours"))
            .unwrap_or_else(|| panic!("chapter {chapter}: {text}"));
        assert!(line.contains(answer), "chapter {chapter}: {line}");
        assert!(
            text.contains(&format!("chapter {chapter}: ")) && text.contains("- FAIL"),
            "{text}"
        );
    }
    // A public method of raylab's that computes a chapter's answer
    // reports like the trait's defaults: chapter 14's `cauchy_ior` as the
    // scene's `Cauchy::index_at`.
    let out = run_student("student-cheat", &["check", "--chapter", "14"], &dir);
    let text = stdout(&out);
    assert_eq!(out.status.code(), Some(1), "chapter 14: {text}");
    assert!(
        text.lines().any(
            |line| line.contains("runs raylab's own answer instead of yours")
                && line.contains("Cauchy::index_at")
        ),
        "chapter 14: {text}"
    );
    let render = run_student("student-cheat", &["render", "--chapter", "2"], &dir);
    assert_eq!(render.status.code(), Some(2), "{}", stderr(&render));
    // A student's build holds no answer of raylab's to run: in its
    // place, a panic that says so.
    assert!(
        stderr(&render).contains(
            "Sphere::intersect is raylab's answer, which a student's build of raylab leaves out"
        ),
        "{}",
        stderr(&render)
    );
    assert!(!dir.join("chapter-2.png").exists());

    let mut command = Command::new(ws.target.join("debug").join("student-cheat"));
    common::judged_by_this_raylab(&mut command);
    command
        .args(["check", "--chapter", "1"])
        .current_dir(&dir)
        .env("CHEAT_EXIT", "1");
    let out = command.output().expect("run the cheat");
    let text = stdout(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    // The table the chapter printed is no verdict: the judge's says the
    // case it was answering got no answer, and the chapter fails.
    assert!(
        text.contains("got:      no answer: the process exited with status 0 while working it out"),
        "{text}"
    );
    assert!(text.contains("1        FAIL"), "{text}");
    assert!(!text.contains("1        pass"), "{text}");
}

/// A chapter that never returns: the check says where it is once a step
/// has gone without an answer for a while (here 2 s), and goes on.
#[cfg(unix)]
#[test]
fn a_check_that_stalls_says_where_it_is() {
    use std::io::Read;
    use std::os::unix::process::CommandExt;
    let ws = workspaces();
    let dir = ws.root.join("loop-out");
    std::fs::create_dir_all(&dir).expect("create");
    let mut command = Command::new(ws.target.join("debug").join("student-cheat"));
    common::judged_by_this_raylab(&mut command);
    command
        .args(["check", "--chapter", "1"])
        .current_dir(&dir)
        .env("CHEAT_LOOP", "1")
        .env("RAYLAB_STALL_NOTICE_SECONDS", "2")
        .stderr(std::process::Stdio::piped())
        .stdout(std::process::Stdio::null())
        .process_group(0);
    // SAFETY: signal is async-signal-safe; nothing else runs here. A SIGINT
    // ignored by whatever started the tests would stay ignored in raylab.
    unsafe {
        command.pre_exec(|| {
            libc::signal(libc::SIGINT, libc::SIG_DFL);
            Ok(())
        });
    }
    let mut child = command.spawn().expect("run the student's check");
    let mut stderr = child.stderr.take().expect("stderr");
    let (sender, receiver) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut seen = Vec::new();
        let mut chunk = [0u8; 512];
        while let Ok(read @ 1..) = stderr.read(&mut chunk) {
            seen.extend_from_slice(&chunk[..read]);
            if seen.contains(&b'\n') {
                break;
            }
        }
        let _ = sender.send(String::from_utf8_lossy(&seen).into_owned());
    });
    let notice = receiver.recv_timeout(std::time::Duration::from_secs(120));
    // Ctrl-C, to the check and its worker (a process group of their own);
    // a kill if it does not end within a minute.
    // SAFETY: plain system calls on the group just made.
    unsafe {
        libc::kill(-(child.id() as i32), libc::SIGINT);
    }
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while child.try_wait().expect("wait").is_none() && std::time::Instant::now() < deadline {
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    unsafe {
        libc::kill(-(child.id() as i32), libc::SIGKILL);
    }
    let _ = child.wait();
    let notice = notice.expect("a notice within two minutes");
    assert!(
        notice.contains(
            "still running after 2 s without an answer: chapter 1's check ran intersect_plane \
             (plane-straight-down)"
        ),
        "{notice}"
    );
}

/// A workspace whose main runs raylab's own chapters (`main_with::<raylab::
/// Reference>()`, from outside the workspace) is refused before any check.
#[test]
fn a_workspace_main_that_runs_raylabs_chapters_is_refused() {
    let ws = workspaces();
    let dir = ws.root.join("main-out");
    std::fs::create_dir_all(&dir).expect("create");
    for args in [&["check"][..], &["render", "--chapter", "1"]] {
        let out = run_student("student-main", args, &dir);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stdout(&out));
        assert!(
            stderr(&out).contains("runs raylab's own chapters, `raylab::Reference`"),
            "{}",
            stderr(&out)
        );
    }
    assert!(!Path::new("/chapter-1.png").exists());
}

/// raylab's own binary, run inside a student's workspace, would check,
/// render or trace raylab's answers: it refuses, naming the command to use.
#[test]
fn raylabs_own_check_refuses_to_run_inside_a_workspace() {
    let ws = workspaces();
    let inside = ws.todo.join("src");
    for args in [
        &["check", "--chapter", "3"][..],
        &["render", "--chapter", "3"],
        &["trace", "--chapter", "3", "--pixel", "1,1"],
    ] {
        let out = raylab(args, &inside);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stdout(&out));
        let message = stderr(&out);
        assert!(
            message.contains("is a student workspace: this `raylab` runs raylab's own chapters"),
            "{message}"
        );
        assert!(
            message.contains(&format!("cargo run --release -- {}`", args.join(" "))),
            "{message}"
        );
    }
    assert!(!inside.join("chapter-3.png").exists());
}

/// The reference chapters' modules are out of a workspace's reach, and so
/// are the judge's cases and its checks: a chapter that calls
/// `raylab::chapters::ch02_sphere::intersect_sphere`, reads
/// `raylab::check::by_chapter::checkpoints` (where the expected answers are)
/// or runs `raylab::check::check_chapter` in its own process does not
/// compile (raylab's `student` feature makes them private).
#[test]
fn a_workspace_cannot_name_the_reference_chapters_nor_the_judges_cases() {
    let ws = workspaces();
    let copy = ws.root.join("student-module");
    let output = raylab(
        &["new", copy.to_str().expect("UTF-8 path"), "--solutions"],
        &ws.root,
    );
    assert!(output.status.success(), "raylab new: {}", stderr(&output));
    let glue = copy.join("src/chapters/mod.rs");
    let text = read(&glue)
        .replace(
            "        ch02_sphere::intersect_sphere(sphere, ray, t_min, t_max)",
            "        raylab::chapters::ch02_sphere::intersect_sphere(sphere, ray, t_min, t_max)",
        )
        .replace(
            "        ch06_reflection::reflect(d, n)",
            "        { let _ = raylab::check::by_chapter::checkpoints(6); \
             use raylab::crosscheck as _; use raylab::implicit_probe as _; \
             use raylab::plots as _; use raylab::cost as _; use raylab::figure as _; \
             ch06_reflection::reflect(d, n) }",
        )
        .replace(
            "        ch08_refraction::refract(d, n, eta)",
            "        { let _ = raylab::check::check_chapter::<crate::Mine>(8, &Default::default()); \
             ch08_refraction::refract(d, n, eta) }",
        );
    std::fs::write(&glue, text).expect("write the glue");
    // `build`, not `check`: it fails at the same errors, and reuses the
    // dependencies the workspaces above were built with, where `check`
    // would check every one of them again.
    let output = common::cargo()
        .args(["build", "--offline", "--quiet"])
        .current_dir(&copy)
        .env("CARGO_TARGET_DIR", &ws.target)
        .output()
        .expect("run cargo");
    let message = stderr(&output);
    assert!(!output.status.success(), "it compiled");
    assert!(
        message.contains("intersect_sphere") && message.contains("ch02_sphere"),
        "{message}"
    );
    assert!(
        message.contains("module `by_chapter` is private"),
        "{message}"
    );
    assert!(
        message.contains("function `check_chapter` is private"),
        "{message}"
    );
    // raylab's tools compute with its answers: none is a student's to call.
    for tool in ["crosscheck", "implicit_probe", "plots", "cost", "figure"] {
        assert!(
            message.contains(&format!("module `{tool}` is private")),
            "{tool}: {message}"
        );
    }
}

/// Every call of `intersect_plane` that raylab's check of chapter 1 makes
/// (its cases, its image, its hard cases), with the reference's answers,
/// as `answers.table` lines (see [`TABLE_LOOKUP`]): the table a student
/// could prepare by running the reference once.
pub(crate) fn harvested_table() -> String {
    use std::sync::Mutex;
    static CALLS: Mutex<Vec<String>> = Mutex::new(Vec::new());
    struct Recorder;
    impl raylab::Chapters for Recorder {
        fn intersect_plane(
            plane: &raylab::Plane,
            ray: &raylab::Ray,
            t_min: f32,
            t_max: f32,
        ) -> Option<f32> {
            let answer =
                <raylab::Reference as raylab::Chapters>::intersect_plane(plane, ray, t_min, t_max);
            let mut words: Vec<String> = Vec::new();
            for v in [plane.point(), plane.normal(), ray.origin, ray.dir] {
                words.extend(v.to_array().map(|x| format!("{:x}", x.to_bits())));
            }
            words.extend([t_min, t_max].map(|x| format!("{:x}", x.to_bits())));
            words.push(answer.map_or("none".into(), |t| format!("{:x}", t.to_bits())));
            CALLS.lock().expect("the calls").push(words.join(" "));
            answer
        }
    }
    let options = raylab::check::CheckOptions {
        write_images: false,
        ..Default::default()
    };
    let verdict = raylab::check::check_chapter::<Recorder>(1, &options);
    assert!(verdict.robust(), "{}", verdict.text());
    let calls = CALLS.lock().expect("the calls");
    assert!(calls.len() > 1000, "{} calls", calls.len());
    calls.join("\n")
}

/// A chapter that answers from a table prepared in advance (every call the
/// check makes, answered by raylab's reference) passes the lesson's
/// inputs, and fails with fresh ones (`check --fresh`, as `grade --code
/// --fresh` asks), where the honest chapters still pass.
#[test]
fn a_prepared_table_of_answers_passes_the_lessons_inputs_only() {
    let ws = workspaces();
    let dir = ws.root.join("table-out");
    std::fs::create_dir_all(&dir).expect("create");
    std::fs::write(dir.join("answers.table"), harvested_table()).expect("write the table");
    let plain = run_student("student-cheat", &["check", "--chapter", "1"], &dir);
    assert_eq!(plain.status.code(), Some(0), "{}", stdout(&plain));
    assert!(
        stdout(&plain).contains("pass (robust)"),
        "{}",
        stdout(&plain)
    );
    let fresh = run_student(
        "student-cheat",
        &["check", "--chapter", "1", "--fresh", "7"],
        &dir,
    );
    let text = stdout(&fresh);
    assert_eq!(fresh.status.code(), Some(1), "{text}");
    assert!(text.contains("with fresh inputs"), "{text}");
    // Without the table, the same chapter (the answer key's) passes the
    // same fresh inputs.
    let honest = ws.root.join("table-honest-out");
    std::fs::create_dir_all(&honest).expect("create");
    let fresh = run_student(
        "student-cheat",
        &["check", "--chapter", "1", "--fresh", "7"],
        &honest,
    );
    assert_eq!(fresh.status.code(), Some(0), "{}", stdout(&fresh));
}
