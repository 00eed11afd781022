//! Running a student workspace's chapters for `raylab grade --code`.
//!
//! A workspace made by `raylab new` is a Cargo project whose binary is the
//! student's raylab. [`run_check`] builds it (`cargo build --release
//! --offline`, or `--profile dev`), then judges it: the grader's own raylab holds the cases
//! and the expected answers, and starts the student's binary as `serve`
//! to answer them (see [`crate::check::judge`]), one process per chapter.
//! Nothing that binary prints, writes or exits with can change a verdict:
//! the grader reads only its answers, and a case it did not answer fails.
//!
//! The build and the answers run inside a [`Sandbox`] unless the grader
//! asks for none (`--no-sandbox`): then with the grader's rights, see
//! docs/instructors.md.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::sandbox::{LimitReached, Run, Sandbox};
use super::snapshot::{Entry, Snapshot};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use crate::check::judge::Asker;
use crate::check::remote::{Remote, Spawn};
use crate::check::{CheckOptions, CheckReport, Overall, Stopped};

/// The outcome of one workspace's `check`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum CodeStatus {
    /// Every chapter passes.
    Pass,
    /// A chapter fails.
    Fail,
    /// No chapter fails: some are still `todo!()`.
    NotStarted,
    /// Still running when the time limit came; every process it started
    /// was killed.
    TimedOut,
    /// Cargo could not compile the workspace.
    BuildError,
    /// Anything else: the binary does not answer raylab's questions (or
    /// another version's), or the check itself could not run.
    Error,
}

impl CodeStatus {
    /// The status as the report and the CSV write it.
    pub fn name(self) -> &'static str {
        match self {
            CodeStatus::Pass => "pass",
            CodeStatus::Fail => "fail",
            CodeStatus::NotStarted => "not started",
            CodeStatus::TimedOut => "timed out",
            CodeStatus::BuildError => "build error",
            CodeStatus::Error => "error",
        }
    }
}

/// What running a workspace's `check` gave.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct CodeRun {
    pub status: CodeStatus,
    /// The exit status of the build, when it exited by itself.
    pub exit_code: Option<i32>,
    /// The verdicts as the judge wrote them (never the student's output).
    pub stdout: String,
    /// The end of what the build and the student's binary wrote on
    /// standard error (at most [`KEPT_OUTPUT`] bytes of each), for the
    /// instructor to read: none of it counts.
    pub stderr: String,
    /// The time limit, for the report of a run that hit it.
    pub timeout: Duration,
    /// How many chapters pass.
    pub chapters_passed: usize,
    /// The instructor's hidden scenes (`--scene`), rendered by the
    /// student's chapters and compared with raylab's.
    #[serde(default)]
    pub scenes: Vec<super::hidden::SceneOutcome>,
    /// The seed of the fresh inputs the check drew (`--fresh`).
    #[serde(default)]
    pub fresh: Option<u64>,
    /// The Rust files of the workspace's `src/` as they were before the
    /// build (path, text), at most [`MAX_COMPARED_BYTES`] of them: what
    /// the similarity report compares.
    #[serde(default)]
    pub sources: Vec<(String, String)>,
    /// The limits of its sandbox the run reached (memory, disk,
    /// processes), which ended it or a part of it.
    #[serde(default)]
    pub limits: Vec<LimitReached>,
    /// Why the run has its status when the status alone does not say
    /// (the limit that stopped it, why its verdicts do not count, why the
    /// judge got no answer, the compiler's first error), in a line: what
    /// the class's overview shows beside the status.
    #[serde(default)]
    pub reason: Option<String>,
    /// Each chapter the judge gave a verdict on, and whether it passes:
    /// what an LMS export scores chapter by chapter.
    #[serde(default)]
    pub chapters: Vec<ChapterScore>,
}

/// One chapter of a judged run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ChapterScore {
    pub chapter: u8,
    pub passes: bool,
}

/// The most bytes of a workspace's `src/` kept for the similarity report
/// (a course's is a few hundred kilobytes).
pub const MAX_COMPARED_BYTES: usize = 4 << 20;

/// How much of each output stream is kept: the end, where the compiler's
/// errors are. A student's code can print without end; the grader's
/// memory must not grow with it.
pub const KEPT_OUTPUT: usize = 64 * 1024;

/// The longest time limit `--timeout` accepts: a day.
pub const MAX_TIMEOUT_SECONDS: u64 = 24 * 60 * 60;

/// After the build ends (or is killed), how long to wait for the rest of
/// its output. A process that left the group (`setsid`) and kept the pipe
/// open would otherwise block the grading of the whole class.
const OUTPUT_GRACE: Duration = Duration::from_secs(5);

/// The cargo profile a workspace is built with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BuildProfile {
    #[default]
    Release,
    Dev,
}

impl BuildProfile {
    /// Its name as cargo's `--profile` takes it.
    pub fn name(self) -> &'static str {
        match self {
            BuildProfile::Release => "release",
            BuildProfile::Dev => "dev",
        }
    }
}

/// How a class's code is graded: the time limit of each student's build
/// and check, the sandbox, fresh inputs, and the hidden scenes.
#[derive(Clone, Copy)]
pub struct CodeJob<'a> {
    pub timeout: Duration,
    pub sandbox: Option<&'a Sandbox>,
    /// Draw each parametrised case's inputs anew from this seed
    /// (`--fresh`).
    pub fresh: Option<u64>,
    /// Check chapters 1 to this one only (`--chapter`); every chapter by
    /// default.
    pub chapter: Option<u8>,
    /// The cargo profile each workspace is built with: `release`, or
    /// `dev` (a build in about half the time, answers a few times slower).
    pub profile: BuildProfile,
    pub scenes: &'a [super::hidden::HiddenScene],
}

/// Builds the workspace and judges its chapters, then renders the hidden
/// scenes with them, all within `job.timeout` (the cargo of `$CARGO` if
/// set, else `cargo` from the PATH). An error only when the build cannot
/// be started at all.
pub fn run_check(workspace: &Path, job: &CodeJob) -> Result<CodeRun, super::GradeError> {
    let deadline = Instant::now() + job.timeout;
    let workspace = &std::path::absolute(workspace).unwrap_or_else(|_| workspace.to_path_buf());
    // Before the build: what is judged, checked for its origin and
    // compared is this, whatever the student's binary does to the files
    // later (see grade::snapshot).
    let snapshot = Snapshot::take(workspace);
    let mut not_counted: Vec<String> = outside_code(&snapshot, workspace).into_iter().collect();
    // The run's folder and cgroups, shared by the build and every
    // answering process: the limits hold for the run as a whole. Its copy
    // of the workspace is made after the snapshot, so it is what was
    // snapshotted.
    let sandboxed = job
        .sandbox
        .map(|sandbox| sandbox.start(workspace).map(Arc::new))
        .transpose()?;
    let workspace = sandboxed
        .as_ref()
        .map_or(workspace.as_path(), |run| run.workspace());
    let built = build(workspace, job, sandboxed.as_deref())?;
    let mut run = CodeRun {
        status: CodeStatus::BuildError,
        exit_code: built.exit.and_then(|status| status.code()),
        stdout: String::new(),
        stderr: built.stderr.clone(),
        timeout: job.timeout,
        chapters_passed: 0,
        scenes: Vec::new(),
        fresh: job.fresh,
        sources: compared_sources(&snapshot),
        limits: Vec::new(),
        reason: None,
        chapters: Vec::new(),
    };
    if built.timed_out {
        run.status = CodeStatus::TimedOut;
        run.exit_code = None;
    } else if built.over_disk {
        run.exit_code = None;
    } else if let Some(binary) = built
        .binary
        .filter(|_| built.exit.is_some_and(|s| s.success()))
    {
        let spawn = serve_spawn(workspace, &binary, sandboxed.clone());
        let students_stderr = Arc::new(std::sync::Mutex::new(Vec::new()));
        let remote = || {
            Remote::new(Arc::clone(&spawn))
                .with_deadline(Some(deadline))
                .with_stderr_buffer(Arc::clone(&students_stderr))
        };
        let make = || Box::new(remote()) as Box<dyn Asker + Send>;
        let options = CheckOptions {
            write_images: false,
            forbid_answer_key: true,
            fresh: job.fresh,
            ..CheckOptions::default()
        };
        let which = job.chapter.map_or(
            crate::check::judge::Which::All,
            crate::check::judge::Which::UpTo,
        );
        let report = crate::check::judge::judge(&make, which, &options);
        run.status = classify(&report);
        if let Some(crate::check::Stopped::Refused(why)) = &report.stopped {
            run.reason = Some(format!("no verdict: {why}"));
        }
        run.chapters_passed = report.verdicts.iter().filter(|v| v.passes()).count();
        run.chapters = report
            .verdicts
            .iter()
            .map(|verdict| ChapterScore {
                chapter: verdict.chapter,
                passes: verdict.passes(),
            })
            .collect();
        run.stdout = report.text();
        // Hidden scenes only for a binary that answered.
        if !job.scenes.is_empty() && !matches!(run.status, CodeStatus::TimedOut | CodeStatus::Error)
        {
            run.scenes = super::hidden::grade_scenes(job.scenes, &mut remote());
        }
        let students = remote().stderr();
        if !students.trim().is_empty() {
            run.stderr = format!(
                "{}\nwhat the student's binary wrote (none of it counts):\n{students}",
                run.stderr
            );
        }
    } else if built.exit.is_some_and(|status| status.success()) {
        run.status = CodeStatus::Error;
        run.stdout = "no verdict: the build made no binary to ask".into();
        run.reason = Some("the build made no binary to ask".into());
    } else if run.status == CodeStatus::BuildError {
        run.reason = first_compiler_error(&run.stderr);
    }
    if let Some(sandboxed) = &sandboxed {
        run.limits = sandboxed.limits_reached();
    }
    if !run.limits.is_empty() {
        let reached: Vec<String> = run.limits.iter().map(ToString::to_string).collect();
        let line = format!("stopped by {}", reached.join("; and by "));
        let names: Vec<&str> = run.limits.iter().map(LimitReached::name).collect();
        run.reason = Some(format!("stopped by {}", names.join(" and ")));
        run.stdout = format!("{}\n{line}", run.stdout).trim_start().to_string();
        run.stderr = format!("{}\n{line}", run.stderr);
    }
    if let Some(change) = snapshot.changed(workspace) {
        not_counted.push(format!(
            "{change} while the workspace was built and checked (the code compared is as it \
             was before the build)"
        ));
    }
    // Its build output is built on next time only where nothing of the
    // student's ran while it was made.
    if let Some(sandboxed) = sandboxed.as_ref().filter(|_| not_counted.is_empty()) {
        sandboxed.vouch_for_build();
    }
    // Run all the same (inside the sandbox), so that the report shows what
    // the code did; but no verdict of such code counts. A build that failed
    // or ran out of time has no verdict to discount, and says so itself.
    if !not_counted.is_empty() {
        if !matches!(run.status, CodeStatus::BuildError | CodeStatus::TimedOut) {
            run.status = CodeStatus::Error;
        }
        run.chapters_passed = 0;
        for chapter in &mut run.chapters {
            chapter.passes = false;
        }
        // Last in both outputs: the report keeps their ends, stderr's last.
        let reason = format!(
            "not counted: {}. A workspace's code is its own files, laid out as `raylab new` \
             lays them out, and all of its src/ is compared with other students' and with \
             raylab's answer key.",
            not_counted.join("; ")
        );
        run.stdout = format!("{}\n{reason}", run.stdout);
        run.stderr = format!("{}\n{reason}", run.stderr);
        if run.status == CodeStatus::Error {
            run.reason = Some(format!("not counted: {}", not_counted.join("; ")));
        }
    }
    Ok(run)
}

/// The snapshot's `src/` for the similarity report, in the order of the
/// paths, up to [`MAX_COMPARED_BYTES`].
fn compared_sources(snapshot: &Snapshot) -> Vec<(String, String)> {
    let mut total = 0;
    snapshot
        .src_texts()
        .into_iter()
        .take_while(|(_, text)| {
            total += text.len();
            total <= MAX_COMPARED_BYTES
        })
        .collect()
}

/// How the student's binary is started as `serve`: in the run's sandbox
/// for answering (nothing writable, no `/proc`), or plainly.
fn serve_spawn(workspace: &Path, binary: &Path, sandboxed: Option<Arc<Run>>) -> Arc<Spawn> {
    let (workspace, binary) = (workspace.to_path_buf(), binary.to_path_buf());
    Arc::new(move || {
        let (mut command, keep): (Command, Box<dyn std::any::Any + Send>) = match &sandboxed {
            Some(run) => run
                .serve_command(&binary)
                .map_err(std::io::Error::other)?
                .into_parts(),
            None => {
                let mut command = Command::new(&binary);
                command.arg("serve");
                (command, Box::new(()))
            }
        };
        command.current_dir(&workspace);
        Ok((command, keep))
    })
}

/// What a build gave.
struct Built {
    exit: Option<ExitStatus>,
    timed_out: bool,
    /// Stopped for writing more than the run's disk limit.
    over_disk: bool,
    stderr: String,
    /// The workspace's binary, as cargo names it.
    binary: Option<PathBuf>,
}

/// `cargo build --profile P --offline` in `workspace` (inside the run's
/// sandbox if there is one), killed with all it started past the job's
/// time limit, or past the run's disk limit.
fn build(
    workspace: &Path,
    job: &CodeJob,
    sandboxed: Option<&Run>,
) -> Result<Built, super::GradeError> {
    let args: Vec<std::ffi::OsString> = [
        "build",
        "--profile",
        job.profile.name(),
        "--offline",
        "--message-format=json-render-diagnostics",
    ]
    .into_iter()
    .map(Into::into)
    .collect();
    // A shared target folder would let cargo take one student's build for
    // another's (same crate name, older sources): each workspace builds in
    // its own target/. Set, not just unset: the variable overrides a
    // `build.target-dir` of the workspace's own .cargo/config.toml.
    let target = (
        "CARGO_TARGET_DIR",
        workspace.join("target").into_os_string(),
    );
    let (mut command, keep, cargo) = match (job.sandbox, sandboxed) {
        (Some(sandbox), Some(run)) => {
            let cargo = sandbox.cargo().as_os_str().to_os_string();
            let (command, keep) = run
                .build_command(&cargo, &args, &[target])
                .map_err(super::GradeError::from)?
                .into_parts();
            (command, keep, cargo)
        }
        _ => {
            let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
            let mut command = Command::new(&cargo);
            command.args(&args).env(target.0, target.1);
            (
                command,
                Box::new(()) as Box<dyn std::any::Any + Send>,
                cargo,
            )
        }
    };
    command
        .current_dir(workspace)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    // Its own process group, so that on a timeout the compiler and all it
    // started die together.
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        command.process_group(0);
    }
    let mut child = command.spawn().map_err(|error| super::GradeError::Run {
        cargo: cargo.clone().into(),
        workspace: workspace.to_path_buf(),
        error,
    })?;
    drop(keep);
    let receiver = read_outputs(&mut child);
    let waited = wait_within(&mut child, job.timeout, sandboxed);
    // Whatever the build left behind in its group goes too.
    kill_group(&mut child);
    let [stdout, stderr] = received_outputs(&receiver);
    Ok(Built {
        exit: waited.exit,
        timed_out: waited.timed_out,
        over_disk: waited.over_disk || sandboxed.is_some_and(Run::over_disk_limit),
        stderr,
        binary: built_binary(&stdout, workspace),
    })
}

/// The binary of the workspace's package in cargo's JSON messages: the
/// last compiler artifact with an executable, inside the workspace's
/// `target/`.
fn built_binary(messages: &str, workspace: &Path) -> Option<PathBuf> {
    messages
        .lines()
        .rev()
        .filter_map(|line| serde_json::from_str::<serde_json::Value>(line).ok())
        .filter(|message| message["reason"] == "compiler-artifact")
        .filter_map(|message| message["executable"].as_str().map(PathBuf::from))
        .find(|binary| binary.starts_with(workspace.join("target")) && binary.is_file())
}

/// The crates a workspace may depend on: those `raylab new` writes.
const ALLOWED_DEPENDENCIES: [&str; 2] = ["raylab", "libm"];

/// The top-level tables of the manifest `raylab new` writes.
const MANIFEST_TABLES: [&str; 4] = ["package", "dependencies", "workspace", "profile"];

/// [`outside_code`] of the workspace as it is now.
pub fn code_from_outside(workspace: &Path) -> Option<String> {
    outside_code(&Snapshot::take(workspace), workspace)
}

/// Where a workspace (`snapshot` of the folder `workspace`) takes code
/// from outside its own source files, which no copy detection would see,
/// or runs something other than its own chapters: a `#[path]` module or an
/// `include!` (of raylab's own chapter files, say) in any of its Rust
/// files, a symbolic link among them, a build script (which could write
/// them into `src/` while it builds), a dependency `raylab new` does not
/// write, a manifest of another shape than the one `raylab new` writes (a
/// `[lib]` path into a classmate's folder, a `[patch]`, a raylab that is
/// not the grader's: see `manifest_shape`), a `.cargo/config.toml` (a
/// `runner` could replace the binary), a `src/main.rs` that is not the one
/// `raylab new` writes, or unsafe code. `None` for a workspace as `raylab
/// new` makes it.
pub fn outside_code(snapshot: &Snapshot, workspace: &Path) -> Option<String> {
    if let Some(why) = &snapshot.incomplete {
        return Some(why.clone());
    }
    let has = |path: &str| {
        snapshot
            .entries
            .iter()
            .any(|(relative, _)| relative == Path::new(path))
    };
    if has("build.rs") {
        return Some("the workspace has a build script, build.rs".into());
    }
    for config in [".cargo/config.toml", ".cargo/config"] {
        if has(config) {
            return Some(format!("the workspace has a {config}"));
        }
    }
    let manifest = snapshot
        .source("Cargo.toml")
        .map(String::from_utf8_lossy)
        .unwrap_or_default();
    if let Ok(manifest) = manifest.parse::<toml::Table>() {
        if manifest
            .get("package")
            .and_then(|package| package.get("build"))
            .is_some()
        {
            return Some("Cargo.toml names a build script".into());
        }
        if let Some(other) = foreign_dependency(&manifest) {
            return Some(other);
        }
        if let Some(other) = manifest_shape(&manifest, workspace) {
            return Some(other);
        }
        let package = manifest
            .get("package")
            .and_then(|package| package.get("name"))
            .and_then(toml::Value::as_str)
            .unwrap_or_default()
            .replace('-', "_");
        let main = snapshot
            .source("src/main.rs")
            .map(String::from_utf8_lossy)
            .unwrap_or_default();
        let expected = format!(
            "fn main() {{\n    std::process::exit(raylab::cli::main_with::<{package}::{}>())\n}}\n",
            crate::workspace::STUDENT_TYPE
        );
        if main.trim() != expected.trim() {
            return Some("src/main.rs is not the one `raylab new` writes".into());
        }
    }
    for (path, entry) in &snapshot.entries {
        let shown = || crate::text::visible_name(path.as_os_str());
        let rust = path.extension().is_some_and(|ext| ext == "rs");
        let text = match entry {
            Entry::Link => return Some(format!("{} is a symbolic link", shown())),
            Entry::Source(Some(bytes)) if rust => String::from_utf8_lossy(bytes),
            // Too large (or unreadable) to be read, it would be neither
            // checked here nor compared, yet the compiler reads it whole.
            Entry::Source(None) if rust => {
                return Some(format!(
                    "{} could not be read (a Rust file is at most {} MiB), so it cannot be \
                     checked",
                    shown(),
                    super::snapshot::MAX_SOURCE_BYTES >> 20
                ));
            }
            _ => continue,
        };
        // Tokens the checks cannot read could hide anything from them.
        let readings: Vec<&str> = readings(&text)
            .into_iter()
            .filter(|reading| reading.parse::<proc_macro2::TokenStream>().is_ok())
            .collect();
        if readings.is_empty() {
            return Some(format!(
                "{} is not Rust whose tokens raylab can read, so it cannot be checked",
                shown()
            ));
        }
        for reading in readings {
            if let Some((line, what)) = outside_reference(reading) {
                return Some(format!(
                    "{}:{line} takes code from another file with {what}",
                    shown()
                ));
            }
            if let Some((line, what)) = unsafe_code(reading) {
                return Some(format!(
                    "{}:{line} uses {what}, which the course never needs and which could \
                     reach the pipes the grader reads the answers from",
                    shown()
                ));
            }
        }
    }
    None
}

/// The ways the compiler may read the Rust file `text`: without a leading
/// byte order mark, and, where its first line starts with `#!`, both with
/// and without that line. rustc skips such a line (a shebang) unless an
/// inner attribute's `[` follows; read whole, a quote on it opens a
/// string that would hide every token after it (`unsafe`, `#[path]`)
/// from the checks, so each reading is checked. The line is cut, not its
/// end: the line numbers stay the file's.
fn readings(text: &str) -> Vec<&str> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut readings = vec![text];
    if text.starts_with("#!") {
        readings.push(text.find('\n').map_or("", |end| &text[end..]));
    }
    readings
}

/// Where `manifest` (of the workspace in `workspace`) is not of the shape
/// `raylab new` writes, in words. Only the tables it writes
/// ([`MANIFEST_TABLES`]: a `[lib]` or `[[bin]]` with a path of its own, a
/// `[patch]` or a `[replace]` would build another crate's code as the
/// student's), no `package.workspace` (whose root's patches would apply),
/// an empty `[workspace]` (a member would be built too), and the two
/// dependencies exactly as written: `raylab` by a path to the raylab that
/// grades it, with the `student` feature and nothing else (a patched copy
/// of raylab, inside `.git/` say, would answer for the student), and
/// `libm` from the registry.
fn manifest_shape(manifest: &toml::Table, workspace: &Path) -> Option<String> {
    let safe = crate::text::terminal_safe;
    if let Some(other) = manifest
        .keys()
        .find(|key| !MANIFEST_TABLES.contains(&key.as_str()))
    {
        return Some(format!(
            "Cargo.toml has [{}], which `raylab new` does not write: a workspace's manifest \
             keeps the shape `raylab new` gives it",
            safe(other)
        ));
    }
    if manifest
        .get("package")
        .and_then(|package| package.get("workspace"))
        .is_some()
    {
        return Some("Cargo.toml's [package] names a workspace to belong to".into());
    }
    if manifest
        .get("workspace")
        .is_some_and(|table| table.as_table().is_none_or(|table| !table.is_empty()))
    {
        return Some("Cargo.toml's [workspace] is not the empty one `raylab new` writes".into());
    }
    let dependencies = manifest.get("dependencies").and_then(toml::Value::as_table);
    let raylab = dependencies.and_then(|table| table.get("raylab"));
    if !is_graders_raylab(raylab, workspace) {
        return Some(format!(
            "the raylab dependency is not the one `raylab new` writes: raylab = {{ path = {}, \
             features = [\"student\"] }}, the raylab grading it",
            toml::Value::String(crate::workspace::RAYLAB_DIR.to_string())
        ));
    }
    let libm = dependencies.and_then(|table| table.get("libm"));
    if libm.is_some_and(|libm| libm.as_str() != Some("0.2")) {
        return Some(
            "the libm dependency is not the one `raylab new` writes: libm = \"0.2\", from the \
             registry"
                .into(),
        );
    }
    None
}

/// Whether `raylab` (the dependency's value) is `{ path = P, features =
/// ["student"] }` with `P` (relative to `workspace`) the folder of the
/// raylab running now.
fn is_graders_raylab(raylab: Option<&toml::Value>, workspace: &Path) -> bool {
    let Some(table) = raylab.and_then(toml::Value::as_table) else {
        return false;
    };
    let mut keys: Vec<&str> = table.keys().map(String::as_str).collect();
    keys.sort_unstable();
    let student = table
        .get("features")
        .and_then(toml::Value::as_array)
        .is_some_and(|features| features.len() == 1 && features[0].as_str() == Some("student"));
    let Some(path) = table.get("path").and_then(toml::Value::as_str) else {
        return false;
    };
    let same_folder = match (
        workspace.join(path).canonicalize(),
        Path::new(crate::workspace::RAYLAB_DIR).canonicalize(),
    ) {
        (Ok(theirs), Ok(ours)) => theirs == ours,
        _ => false,
    };
    keys == ["features", "path"] && student && same_folder
}

/// The first dependency of any kind (normal, build, dev, and each of them
/// per target) that `raylab new` does not write, in words.
fn foreign_dependency(manifest: &toml::Table) -> Option<String> {
    let kinds = ["dependencies", "build-dependencies", "dev-dependencies"];
    let mut tables: Vec<(String, &toml::Table)> = kinds
        .iter()
        .filter_map(|kind| Some((format!("[{kind}]"), manifest.get(*kind)?.as_table()?)))
        .collect();
    if let Some(targets) = manifest.get("target").and_then(toml::Value::as_table) {
        for (target, table) in targets {
            for kind in kinds {
                if let Some(names) = table.get(kind).and_then(toml::Value::as_table) {
                    tables.push((format!("[target.{target}.{kind}]"), names));
                }
            }
        }
    }
    tables.into_iter().find_map(|(table, names)| {
        names
            .keys()
            .find(|name| !ALLOWED_DEPENDENCIES.contains(&name.as_str()))
            .map(|other| {
                format!(
                    "Cargo.toml's {} adds `{}`: a workspace depends on raylab and libm alone",
                    crate::text::terminal_safe(&table),
                    crate::text::terminal_safe(other)
                )
            })
    })
}

/// The line and the form of the first piece of unsafe code in Rust source
/// `text`, read as tokens: the `unsafe` keyword, or what runs code or
/// names a symbol without it in older editions (`#[no_mangle]`,
/// `#[export_name]`, `#[link_section]`, `global_asm!`).
fn unsafe_code(text: &str) -> Option<(usize, &'static str)> {
    use proc_macro2::{TokenStream, TokenTree};
    fn walk(stream: TokenStream) -> Option<(usize, &'static str)> {
        for token in stream {
            match token {
                TokenTree::Ident(ident) => {
                    let what = match resolved(&ident).as_str() {
                        "unsafe" => "unsafe code",
                        "no_mangle" => "#[no_mangle]",
                        "export_name" => "#[export_name]",
                        "link_section" => "#[link_section]",
                        "global_asm" => "global_asm!",
                        _ => continue,
                    };
                    return Some((ident.span().start().line, what));
                }
                TokenTree::Group(group) => {
                    if let Some(found) = walk(group.stream()) {
                        return Some(found);
                    }
                }
                _ => {}
            }
        }
        None
    }
    walk(text.parse().ok()?)
}

/// An identifier as the compiler resolves it: `r#path` is `path`,
/// `r#include!` the `include!` macro.
fn resolved(ident: &proc_macro2::Ident) -> String {
    let name = ident.to_string();
    match name.strip_prefix("r#") {
        Some(plain) => plain.to_string(),
        None => name,
    }
}

/// The line and the form of the first `#[path = ...]` attribute or
/// `include!`-family macro in Rust source `text`, read as tokens (so a
/// comment or a string that mentions one is not one).
///
/// A macro by example can put either together from its arguments, so
/// that no `#[path` or `include!` is ever written: the include-family
/// macros count wherever they are named (`use std::include as inc;`, an
/// argument `via!(include)` that the macro calls as `$m!`), and an
/// attribute counts wherever its `#`, its brackets or what is inside
/// them can come from a macro's arguments (`#[$($t)*]`, `# $b`,
/// `$h [...]`, or brackets handed to a macro whole, `[path = "..."]`).
/// No chapter needs a macro that makes attributes.
fn outside_reference(text: &str) -> Option<(usize, &'static str)> {
    use proc_macro2::{Delimiter, TokenStream, TokenTree};
    const MADE: &str = "an attribute made from a macro's arguments";
    fn walk(stream: TokenStream, in_attribute: bool) -> Option<(usize, &'static str)> {
        let tokens: Vec<TokenTree> = stream.into_iter().collect();
        let punct = |at: Option<usize>| match at.and_then(|at| tokens.get(at)) {
            Some(TokenTree::Punct(p)) => Some(p.as_char()),
            _ => None,
        };
        for (index, token) in tokens.iter().enumerate() {
            let back = |by: usize| index.checked_sub(by);
            match token {
                TokenTree::Ident(ident) => {
                    let name = resolved(ident);
                    if matches!(name.as_str(), "include" | "include_str" | "include_bytes") {
                        return Some((ident.span().start().line, "an include! macro"));
                    }
                    if in_attribute && name == "path" {
                        return Some((ident.span().start().line, "a #[path] attribute"));
                    }
                }
                TokenTree::Punct(p) if p.as_char() == '$' && in_attribute => {
                    return Some((p.span().start().line, MADE));
                }
                TokenTree::Punct(p) if p.as_char() == '#' => {
                    // `# $b` or `#! $b`: brackets from a macro's argument.
                    let next = if punct(Some(index + 1)) == Some('!') {
                        index + 2
                    } else {
                        index + 1
                    };
                    if punct(Some(next)) == Some('$') {
                        return Some((p.span().start().line, MADE));
                    }
                }
                TokenTree::Group(group) => {
                    let bracket = group.delimiter() == Delimiter::Bracket;
                    // `#[...]` or `#![...]`, not `vec![...]`.
                    let after_hash = punct(back(1)) == Some('#')
                        || (punct(back(1)) == Some('!') && punct(back(2)) == Some('#'));
                    // `$h [...]`: the `#` may be a macro's argument.
                    let after_argument =
                        matches!(back(1).map(|at| &tokens[at]), Some(TokenTree::Ident(_)))
                            && punct(back(2)) == Some('$');
                    // Brackets a macro may put a `#` before: `[path = ...]`,
                    // `[cfg_attr(...)]` or `[$...]`, but not a macro call's
                    // own (`vec![$($x),*]`).
                    let mut inside = group.stream().into_iter();
                    let looks_like = punct(back(1)) != Some('!')
                        && match (inside.next(), inside.next()) {
                            (Some(TokenTree::Ident(first)), second) => {
                                match resolved(&first).as_str() {
                                    "cfg_attr" => true,
                                    "path" => {
                                        matches!(second, Some(TokenTree::Punct(p)) if p.as_char() == '=')
                                    }
                                    _ => false,
                                }
                            }
                            (Some(TokenTree::Punct(p)), _) => p.as_char() == '$',
                            _ => false,
                        };
                    let attribute =
                        in_attribute || (bracket && (after_hash || after_argument || looks_like));
                    if let Some(found) = walk(group.stream(), attribute) {
                        return Some(found);
                    }
                }
                _ => {}
            }
        }
        None
    }
    // Text the tokeniser refuses cannot compile either: the build says why.
    walk(text.parse().ok()?, false)
}

/// Reads the child's stdout and stderr on threads of their own (one full
/// pipe must not block the other), each sending its kept tail with its
/// index, 0 for stdout and 1 for stderr.
fn read_outputs(child: &mut Child) -> mpsc::Receiver<(usize, String)> {
    let (sender, receiver) = mpsc::channel();
    let readers = [
        child
            .stdout
            .take()
            .map(|out| Box::new(out) as Box<dyn Read + Send>),
        child
            .stderr
            .take()
            .map(|err| Box::new(err) as Box<dyn Read + Send>),
    ];
    for (index, reader) in readers.into_iter().enumerate() {
        let sender = sender.clone();
        std::thread::spawn(move || {
            let tail = reader.map(read_tail).unwrap_or_default();
            let _ = sender.send((index, tail));
        });
    }
    receiver
}

/// How a wait for a child ended.
struct Waited {
    exit: Option<ExitStatus>,
    timed_out: bool,
    over_disk: bool,
}

/// The least time between two measures of what a run wrote to disk.
const DISK_EVERY: Duration = Duration::from_millis(250);

/// Waits for the child to end, killing its group once `timeout` passes or,
/// in a run's sandbox, once the run has written more than its disk limit
/// (measured at most every [`DISK_EVERY`], and no more than a tenth of
/// the time: a large `target/` takes a while to walk).
fn wait_within(child: &mut Child, timeout: Duration, sandboxed: Option<&Run>) -> Waited {
    let deadline = Instant::now() + timeout;
    let mut next_measure = Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(status)) => {
                return Waited {
                    exit: Some(status),
                    timed_out: false,
                    over_disk: false,
                };
            }
            Ok(None) => {}
            Err(_) => {
                return Waited {
                    exit: None,
                    timed_out: false,
                    over_disk: false,
                };
            }
        }
        if Instant::now() >= deadline {
            kill_group(child);
            return Waited {
                exit: child.wait().ok(),
                timed_out: true,
                over_disk: false,
            };
        }
        if let Some(run) = sandboxed
            && Instant::now() >= next_measure
        {
            let started = Instant::now();
            if run.over_disk_limit() {
                kill_group(child);
                return Waited {
                    exit: child.wait().ok(),
                    timed_out: false,
                    over_disk: true,
                };
            }
            next_measure = Instant::now() + DISK_EVERY.max(started.elapsed() * 10);
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The stdout and stderr the readers send, waiting at most
/// [`OUTPUT_GRACE`] for them; an empty string for one that did not come.
fn received_outputs(receiver: &mpsc::Receiver<(usize, String)>) -> [String; 2] {
    let mut outputs = [String::new(), String::new()];
    let grace_end = Instant::now() + OUTPUT_GRACE;
    for _ in 0..2 {
        let left = grace_end.saturating_duration_since(Instant::now());
        match receiver.recv_timeout(left) {
            Ok((index, text)) => outputs[index] = text,
            Err(_) => break,
        }
    }
    outputs
}

/// Sorts a judged run by its verdicts: a run the judge stopped is timed
/// out or an error; any failing chapter (or an error of the check) fails
/// it; otherwise a chapter not started, or waiting for one, makes it "not
/// started"; a correct but not yet robust chapter passes.
pub fn classify(report: &CheckReport) -> CodeStatus {
    match (&report.stopped, report.overall()) {
        (Some(Stopped::TimedOut), _) => CodeStatus::TimedOut,
        (Some(Stopped::Refused(_)), _) => CodeStatus::Error,
        (None, Overall::Pass) => CodeStatus::Pass,
        (None, Overall::Error) => CodeStatus::Error,
        (None, Overall::Fail) => {
            let failing = report.verdicts.iter().any(|v| {
                !v.passes()
                    && !matches!(
                        v.status,
                        crate::check::Status::NotStarted | crate::check::Status::Blocked { .. }
                    )
            });
            if failing || report.verdicts.is_empty() {
                CodeStatus::Fail
            } else {
                CodeStatus::NotStarted
            }
        }
    }
}

/// Everything `reader` gives until it closes, keeping the last
/// [`KEPT_OUTPUT`] bytes, as text.
fn read_tail(mut reader: Box<dyn Read + Send>) -> String {
    let mut kept: Vec<u8> = Vec::new();
    let mut dropped = false;
    let mut buffer = [0u8; 8192];
    loop {
        match reader.read(&mut buffer) {
            Ok(0) => break,
            Ok(n) => {
                kept.extend_from_slice(&buffer[..n]);
                if kept.len() > 2 * KEPT_OUTPUT {
                    kept.drain(..kept.len() - KEPT_OUTPUT);
                    dropped = true;
                }
            }
            Err(error) if error.kind() == std::io::ErrorKind::Interrupted => {}
            Err(_) => break,
        }
    }
    if kept.len() > KEPT_OUTPUT {
        kept.drain(..kept.len() - KEPT_OUTPUT);
        dropped = true;
    }
    let text = String::from_utf8_lossy(&kept).into_owned();
    if dropped {
        format!("[... earlier output dropped ...]\n{text}")
    } else {
        text
    }
}

/// The first error cargo's compiler reported in `stderr`, if any: what a
/// build error is, in a line.
fn first_compiler_error(stderr: &str) -> Option<String> {
    stderr
        .lines()
        .map(str::trim)
        .find(|line| line.starts_with("error"))
        .map(str::to_string)
}

/// Kills the child's whole process group (the child is its leader).
fn kill_group(child: &mut Child) {
    crate::check::remote::kill_group(child);
}

/// The last `lines` lines of `text`, trimmed: a run's summary for the
/// report and the CSV (the check prints its table last, cargo its errors).
pub fn last_lines(text: &str, lines: usize) -> String {
    let all: Vec<&str> = text.trim_end().lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn code_from_other_files_is_found_as_tokens() {
        let found = outside_reference;
        assert_eq!(
            found("fn a() {}\n#[path = \"/raylab/chapters/answer.rs\"]\nmod key;"),
            Some((2, "a #[path] attribute"))
        );
        assert_eq!(
            found("#![cfg_attr(all(), path = \"x.rs\")]"),
            Some((1, "a #[path] attribute"))
        );
        assert_eq!(
            found("fn f() -> &'static str { include_str!(\"/etc/passwd\") }"),
            Some((1, "an include! macro"))
        );
        assert_eq!(
            found("mod m { fn g() { include!(concat!(env!(\"OUT_DIR\"), \"/k.rs\")); } }"),
            Some((1, "an include! macro"))
        );
        assert_eq!(
            unsafe_code("fn f() {\n    let x = unsafe { std::mem::zeroed::<u8>() };\n}"),
            Some((2, "unsafe code"))
        );
        assert_eq!(
            unsafe_code("#[unsafe(link_section = \".init_array\")]\nstatic S: u8 = 0;"),
            Some((1, "unsafe code"))
        );
        assert_eq!(
            unsafe_code("#[no_mangle]\npub fn g() {}"),
            Some((1, "#[no_mangle]"))
        );
        assert_eq!(
            unsafe_code("// unsafe\nfn h() -> &'static str { \"unsafe\" }"),
            None
        );
        // Mentions in comments and strings, a variable named path, a
        // macro's brackets: none of them.
        assert_eq!(
            found(
                "// #[path = \"x\"] include!()\nfn h(path: u8) -> Vec<u8> { let _ = \"include!(\"; vec![path] }"
            ),
            None
        );
    }

    /// The compiler resolves a raw identifier as the plain one, and a
    /// macro by example can put together, from its arguments, an
    /// attribute or a macro call that its text never spells out: each of
    /// these compiled with rustc 1.95 and took code from `key.txt`.
    #[test]
    fn code_from_other_files_is_found_through_raw_names_and_macros() {
        let found = |text: &str| outside_reference(text).map(|(line, _)| line);
        // The line is the route's first token the checks see: the call or
        // the macro's definition.
        let routes = [
            "fn a() {}\n#[r#path = \"key.txt\"]\nmod k;",
            "fn a() {}\nmod k { r#include!(\"key.txt\"); }",
            "fn a() {}\nuse std::include as inc;\nmod k { super::inc!(\"key.txt\"); }",
            "macro_rules! via { ($m:ident) => { $m!(\"key.txt\"); } }\nmod k { via!(include); }",
            "fn a() {}\nmacro_rules! m { ($($t:tt)*) => { #[$($t)*] mod k; } }\nm!(path = \"key.txt\");",
            "fn a() {}\nmacro_rules! m { ($b:tt) => { # $b mod k; } }\nm!([path = \"key.txt\"]);",
            "fn a() {}\nmacro_rules! s { ($h:tt , $b:tt) => { $h $b mod k; } }\ns!(# , [path = \"key.txt\"]);",
            "fn a() {}\nmacro_rules! o { ($p:ident) => { s!(# , [$p = \"key.txt\"]); } }\no!(path);",
            "fn a() {}\nmacro_rules! s { ($h:tt $($t:tt)*) => { $h [$($t)*] mod k; } }\ns!(# path = \"key.txt\");",
        ];
        for route in routes {
            assert!(matches!(found(route), Some(2 | 3)), "{route}");
        }
        assert_eq!(
            unsafe_code("fn a() {}\n#[r#no_mangle]\npub extern \"C\" fn g() {}"),
            Some((2, "#[no_mangle]"))
        );
        // An array, a vec! of a macro's arguments, a variable named path:
        // none of them.
        assert_eq!(
            found(
                "macro_rules! v { ($($x:expr),*) => { vec![$($x),*] } }\nfn f(path: u8) -> [u8; 1] { [path] }"
            ),
            None
        );
    }

    /// Plants a route in a workspace (given it and one of its chapter files).
    type Plant = fn(&Path, &Path);

    /// A workspace as `raylab new` writes it takes nothing from outside;
    /// each route planted in a copy of it is found, one at a time.
    #[test]
    fn a_workspace_as_made_takes_no_code_from_outside_and_each_route_is_found() {
        let folder = tempfile::tempdir().expect("a folder");
        let raylab = Path::new(crate::workspace::RAYLAB_DIR);
        let made = crate::workspace::files("w", raylab, true).expect("the files");
        let write = |workspace: &Path| {
            for (name, text) in &made.0 {
                let path = workspace.join(name);
                std::fs::create_dir_all(path.parent().expect("a folder")).expect("mkdir");
                std::fs::write(path, text).expect("write");
            }
        };
        let fresh = |name: &str| {
            let workspace = folder.path().join(name);
            write(&workspace);
            workspace
        };
        let clean = fresh("clean");
        std::fs::create_dir_all(clean.join("target/release")).expect("mkdir");
        std::fs::write(clean.join("target/release/x.rs"), "include!(\"y\");").expect("write");
        assert_eq!(code_from_outside(&clean), None);
        let chapter = |workspace: &Path| {
            let name = made
                .0
                .iter()
                .map(|(name, _)| name)
                .find(|name| name.starts_with("src/chapters/ch"))
                .expect("a chapter file")
                .clone();
            workspace.join(name)
        };
        let planted: [(&str, Plant, &str); 12] = [
            (
                "include",
                |_, file| {
                    let text = std::fs::read_to_string(file).expect("read");
                    std::fs::write(file, format!("{text}\ninclude!(\"../../k.rs\");"))
                        .expect("write");
                },
                "takes code from another file with an include! macro",
            ),
            (
                "symlink",
                |workspace, _| {
                    std::os::unix::fs::symlink("/etc/hostname", workspace.join("src/key.rs"))
                        .expect("link");
                },
                "src/key.rs is a symbolic link",
            ),
            (
                "target-dependency",
                |workspace, _| {
                    let path = workspace.join("Cargo.toml");
                    let text = std::fs::read_to_string(&path).expect("read");
                    std::fs::write(&path, format!("{text}\n[target.'cfg(all())'.dependencies]\nkey = {{ path = \"/k\" }}\n"))
                        .expect("write");
                },
                "adds `key`",
            ),
            (
                "config",
                |workspace, _| {
                    std::fs::create_dir_all(workspace.join(".cargo")).expect("mkdir");
                    std::fs::write(workspace.join(".cargo/config.toml"), "").expect("write");
                },
                ".cargo/config.toml",
            ),
            (
                "build-script",
                |workspace, _| {
                    std::fs::write(workspace.join("build.rs"), "fn main() {}").expect("write")
                },
                "build.rs",
            ),
            (
                "main",
                |workspace, _| {
                    std::fs::write(workspace.join("src/main.rs"), "fn main() {}\n").expect("write")
                },
                "src/main.rs is not the one",
            ),
            (
                "path-in-tests",
                |workspace, _| {
                    std::fs::write(
                        workspace.join("tests/key.rs"),
                        "#[path = \"/k.rs\"]\nmod key;",
                    )
                    .expect("write")
                },
                "tests/key.rs:1 takes code from another file with a #[path] attribute",
            ),
            (
                "raylab-in-git",
                |workspace, _| {
                    let path = workspace.join("Cargo.toml");
                    let text = std::fs::read_to_string(&path).expect("read");
                    let line = text
                        .lines()
                        .find(|line| line.starts_with("raylab = "))
                        .expect("the raylab dependency");
                    let patched = text.replace(
                        line,
                        "raylab = { path = \".git/raylab\", features = [\"student\"] }",
                    );
                    std::fs::write(&path, patched).expect("write");
                },
                "the raylab dependency is not the one `raylab new` writes",
            ),
            (
                "raylab-without-student",
                |workspace, _| {
                    let path = workspace.join("Cargo.toml");
                    let text = std::fs::read_to_string(&path).expect("read");
                    std::fs::write(&path, text.replace(", features = [\"student\"]", ""))
                        .expect("write");
                },
                "the raylab dependency is not the one `raylab new` writes",
            ),
            (
                "lib-path",
                |workspace, _| {
                    let path = workspace.join("Cargo.toml");
                    let text = std::fs::read_to_string(&path).expect("read");
                    std::fs::write(
                        &path,
                        format!("{text}\n[lib]\npath = \"../classmate/src/lib.rs\"\n"),
                    )
                    .expect("write");
                },
                "Cargo.toml has [lib], which `raylab new` does not write",
            ),
            (
                "patch",
                |workspace, _| {
                    let path = workspace.join("Cargo.toml");
                    let text = std::fs::read_to_string(&path).expect("read");
                    std::fs::write(
                        &path,
                        format!("{text}\n[patch.crates-io]\nlibm = {{ path = \".git/libm\" }}\n"),
                    )
                    .expect("write");
                },
                "Cargo.toml has [patch], which `raylab new` does not write",
            ),
            (
                "libm-path",
                |workspace, _| {
                    let path = workspace.join("Cargo.toml");
                    let text = std::fs::read_to_string(&path).expect("read");
                    std::fs::write(
                        &path,
                        text.replace("libm = \"0.2\"", "libm = { path = \".git/libm\" }"),
                    )
                    .expect("write");
                },
                "the libm dependency is not the one `raylab new` writes",
            ),
        ];
        for (name, plant, expected) in planted {
            let workspace = fresh(name);
            plant(&workspace, &chapter(&workspace));
            let found = code_from_outside(&workspace).unwrap_or_default();
            assert!(found.contains(expected), "{name}: {found:?}");
        }
    }

    /// rustc skips a first line that starts with `#!` (a shebang): a quote
    /// on it must not hide the file's code from the checks as a string;
    /// and a Rust file too large for the snapshot to read is not passed
    /// over unchecked (the compiler reads it whole).
    #[test]
    fn a_shebang_line_or_a_source_too_large_to_read_hides_no_code() {
        let folder = tempfile::tempdir().expect("a folder");
        let raylab = Path::new(crate::workspace::RAYLAB_DIR);
        let made = crate::workspace::files("w", raylab, true).expect("the files");
        let chapter = made
            .0
            .iter()
            .map(|(name, _)| name.clone())
            .find(|name| name.starts_with("src/chapters/ch"))
            .expect("a chapter file");
        let planted: [(&str, String, &str); 4] = [
            (
                "shebang-path",
                "#!/bin/x \"\n#[path = \"../../notes/key.txt\"] mod key; // \"\n".into(),
                ":2 takes code from another file with a #[path] attribute",
            ),
            (
                "shebang-unsafe",
                "\u{feff}#!/bin/x \"\npub fn f() -> u8 { unsafe { *(&1u8 as *const u8) } } // \"\n"
                    .into(),
                ":2 uses unsafe code",
            ),
            (
                "too-large",
                format!(
                    "include!(\"../../notes/key.txt\");\n/*{}*/\n",
                    " ".repeat((super::super::snapshot::MAX_SOURCE_BYTES + 1) as usize)
                ),
                "could not be read",
            ),
            (
                "no-tokens",
                "pub fn f() -> &'static str { \"unterminated }\n".into(),
                "is not Rust whose tokens raylab can read",
            ),
        ];
        for (name, text, expected) in planted {
            let workspace = folder.path().join(name);
            for (file, made_text) in &made.0 {
                let path = workspace.join(file);
                std::fs::create_dir_all(path.parent().expect("a folder")).expect("mkdir");
                std::fs::write(path, made_text).expect("write");
            }
            std::fs::write(workspace.join(&chapter), text).expect("write");
            let found = code_from_outside(&workspace).unwrap_or_default();
            assert!(found.contains(expected), "{name}: {found:?}");
        }
        // An inner attribute on the first line is not a shebang, and is fine.
        let workspace = folder.path().join("attribute");
        for (file, made_text) in &made.0 {
            let path = workspace.join(file);
            std::fs::create_dir_all(path.parent().expect("a folder")).expect("mkdir");
            let text = if *file == chapter {
                format!("#![allow(\n    unused_imports,\n)]\n{made_text}")
            } else {
                made_text.clone()
            };
            std::fs::write(path, text).expect("write");
        }
        assert_eq!(code_from_outside(&workspace), None);
    }

    #[test]
    fn runs_are_sorted_by_their_verdicts() {
        use crate::check::{ChapterVerdict, Status};
        let verdict = |chapter, status| ChapterVerdict {
            status,
            errors: Vec::new(),
            ..crate::check::judge::unknown_chapter(chapter)
        };
        let report = |verdicts, stopped| CheckReport { verdicts, stopped };
        let pass = verdict(1, Status::Pass);
        let fail = verdict(2, Status::Fail);
        let todo = verdict(3, Status::NotStarted);
        assert_eq!(
            classify(&report(vec![pass.clone()], None)),
            CodeStatus::Pass
        );
        assert_eq!(
            classify(&report(vec![pass.clone(), fail, todo.clone()], None)),
            CodeStatus::Fail
        );
        assert_eq!(
            classify(&report(vec![pass.clone(), todo], None)),
            CodeStatus::NotStarted
        );
        // A run the judge stopped passes nothing.
        assert_eq!(
            classify(&report(vec![pass.clone()], Some(Stopped::TimedOut))),
            CodeStatus::TimedOut
        );
        assert_eq!(
            classify(&report(vec![pass], Some(Stopped::Refused("no".into())))),
            CodeStatus::Error
        );
        assert_eq!(classify(&report(Vec::new(), None)), CodeStatus::Fail);
    }

    #[test]
    fn only_the_end_of_a_long_output_is_kept() {
        let long = "x".repeat(5 * KEPT_OUTPUT) + "the table";
        let kept = read_tail(Box::new(std::io::Cursor::new(long.into_bytes())));
        assert!(kept.ends_with("the table"));
        assert!(kept.starts_with("[... earlier output dropped ...]"));
        assert!(kept.len() < KEPT_OUTPUT + 100);
        assert_eq!(last_lines("a\nb\nc\n", 2), "b\nc");
    }
}
