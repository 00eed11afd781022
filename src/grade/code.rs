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
use super::snapshot::Snapshot;
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
    /// Whether the build went on from the workspace's `target/` as it was
    /// (`--trust-targets`), which a binary built from other sources
    /// passes: the report says so.
    #[serde(default)]
    pub trusted_target: bool,
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
    let mut not_counted: Vec<String> = super::origin::outside_code(&snapshot, workspace)
        .into_iter()
        .collect();
    // The run's folder and cgroups, shared by the build and every
    // answering process: the limits hold for the run as a whole. Its copy
    // of the workspace is made after the snapshot, so it is what was
    // snapshotted.
    let sandboxed = job
        .sandbox
        .map(|sandbox| sandbox.start(workspace).map(Arc::new))
        .transpose()?;
    // The copy is read after the snapshot: a student who can write the
    // hand-in while it is graded could swap other files in between (and
    // back once the build started). What is built must be what was
    // snapshotted.
    if let Some(change) = sandboxed
        .as_ref()
        .and_then(|run| copied_otherwise(&snapshot, run))
    {
        not_counted.push(change);
    }
    let workspace = sandboxed
        .as_ref()
        .map_or(workspace.as_path(), |run| run.workspace());
    let built = build(workspace, job, sandboxed.as_deref())?;
    // An incomplete snapshot is already not counted, and would make every
    // file it left out look foreign to the compiler's list.
    if built.exit.is_some_and(|status| status.success()) && snapshot.incomplete.is_none() {
        if built.messages_cut {
            not_counted.push(
                "cargo's report of the crates it compiled was too long to read whole, so what \
                 the compiler read cannot be checked"
                    .into(),
            );
        }
        not_counted.extend(super::compiled::compiled_from_outside(
            &built.compiled,
            &snapshot,
            workspace,
        ));
    }
    let mut run = CodeRun {
        status: CodeStatus::BuildError,
        exit_code: built.exit.and_then(|status| status.code()),
        stdout: String::new(),
        stderr: built.stderr.clone(),
        timeout: job.timeout,
        chapters_passed: 0,
        scenes: Vec::new(),
        fresh: job.fresh,
        trusted_target: job.sandbox.is_some_and(Sandbox::trusts_targets),
        sources: compared_sources(&snapshot),
        limits: Vec::new(),
        reason: None,
        chapters: Vec::new(),
    };
    let mut limits_before_scenes = None;
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
            // A limit reached while a hidden scene renders would tell of
            // the scene (code that starts 600 threads on meeting one
            // radius): the report says only the limits reached before,
            // and a scene is passed or failed, nothing more.
            limits_before_scenes = sandboxed.as_ref().map(|run| run.limits_reached());
            // What the process writes while it renders a hidden scene
            // could tell the scene: it goes to a buffer of its own, never
            // shown.
            let mut unshown = Remote::new(Arc::clone(&spawn))
                .with_deadline(Some(deadline))
                .with_stderr_buffer(Arc::new(std::sync::Mutex::new(Vec::new())));
            run.scenes = super::hidden::grade_scenes(job.scenes, &mut unshown, Some(deadline));
            // A student passes only when the check and every scene pass:
            // one status says so to everything that reads it (the exit
            // status, the report's and the CSV's overall row, Gradescope's).
            if run.status == CodeStatus::Pass && run.scenes.iter().any(|scene| !scene.passed) {
                run.status = CodeStatus::Fail;
            }
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
        run.limits = limits_before_scenes.unwrap_or_else(|| sandboxed.limits_reached());
    }
    if let Some((reason, line)) = limits_text(run.status, &run.limits) {
        run.reason = Some(reason);
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
        discount(&mut run, &not_counted);
    }
    Ok(run)
}

/// Takes back every point of `run`, whose code is not all the student's
/// (`not_counted` says why): its chapters and its hidden scenes. It ran
/// all the same (inside the sandbox), so that the report shows what the
/// code did.
fn discount(run: &mut CodeRun, not_counted: &[String]) {
    if !matches!(run.status, CodeStatus::BuildError | CodeStatus::TimedOut) {
        run.status = CodeStatus::Error;
    }
    run.chapters_passed = 0;
    for chapter in &mut run.chapters {
        chapter.passes = false;
    }
    // A hidden scene rendered by code that is not the student's (a chapter
    // file that includes raylab's own by `#[path]`) passes as readily.
    for scene in &mut run.scenes {
        scene.passed = false;
        scene.metrics = None;
        scene.detail = "not counted: the run is not counted (its reason says why)".into();
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
    /// The crates compiled from outside the registry, as cargo's messages
    /// name them.
    compiled: Vec<super::compiled::Compiled>,
    /// Some of those messages could not be kept whole: `compiled` may miss
    /// a crate.
    messages_cut: bool,
}

/// `cargo build --profile P --offline` in `workspace` (inside the run's
/// sandbox if there is one), killed with all it started past the job's
/// time limit, or past the run's disk limit.
/// How the sources of `run`'s copy of the workspace differ from
/// `snapshot`, in words, or `None`.
fn copied_otherwise(snapshot: &Snapshot, run: &Run) -> Option<String> {
    snapshot.changed(run.copy()).map(|change| {
        format!(
            "the workspace changed between the reading of its sources and their copy for the \
             build ({change}): what was built is not what was read"
        )
    })
}

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
    let [(stdout, messages_cut), (stderr, _)] = received_outputs(&receiver);
    Ok(Built {
        exit: waited.exit,
        timed_out: waited.timed_out,
        over_disk: waited.over_disk || sandboxed.is_some_and(|run| run.over_disk_limit(None)),
        stderr,
        binary: built_binary(&stdout, workspace),
        compiled: compiled_crates(&stdout, workspace),
        messages_cut,
    })
}

/// The crates of cargo's JSON messages, each with the compiler's dep-info
/// of a library: cargo names the library's metadata
/// `deps/libNAME-HASH.rmeta`, beside which rustc wrote `deps/NAME-HASH.d`.
fn compiled_crates(messages: &str, workspace: &Path) -> Vec<super::compiled::Compiled> {
    messages
        .lines()
        .filter_map(|line| serde_json::from_str::<serde_json::Value>(line).ok())
        .filter(|message| message["reason"] == "compiler-artifact")
        .map(|message| {
            let target = &message["target"];
            let kinds = target["kind"]
                .as_array()
                .map(|kinds| {
                    kinds
                        .iter()
                        .filter_map(|kind| kind.as_str().map(String::from))
                        .collect()
                })
                .unwrap_or_default();
            let dep_info = message["filenames"]
                .as_array()
                .into_iter()
                .flatten()
                .filter_map(|name| name.as_str().map(PathBuf::from))
                .find_map(|file| {
                    let stem = file.file_name()?.to_str()?.strip_suffix(".rmeta")?;
                    let crate_and_hash = stem.strip_prefix("lib")?;
                    Some(file.with_file_name(format!("{crate_and_hash}.d")))
                })
                .filter(|file| file.starts_with(workspace.join("target")));
            super::compiled::Compiled {
                manifest: PathBuf::from(message["manifest_path"].as_str().unwrap_or_default()),
                // Cargo's ids: `registry+URL#name@version` (or, before
                // cargo 1.77, `name version (registry+URL)`); anything
                // else (a path, a git repository) is not a registry's.
                local: !message["package_id"]
                    .as_str()
                    .is_some_and(|id| id.starts_with("registry+") || id.contains("(registry+")),
                kinds,
                root: PathBuf::from(target["src_path"].as_str().unwrap_or_default()),
                dep_info,
            }
        })
        .collect()
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

/// Reads the child's stdout and stderr on threads of their own (one full
/// pipe must not block the other), each sending what it kept with its
/// index, 0 for stdout (cargo's messages of the crates compiled from
/// outside the registry, and whether some were cut) and 1 for stderr (its
/// tail).
fn read_outputs(child: &mut Child) -> mpsc::Receiver<(usize, (String, bool))> {
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
            let kept = match (index, reader) {
                (0, Some(reader)) => read_artifacts(reader),
                (_, Some(reader)) => (read_tail(reader), false),
                (_, None) => (String::new(), false),
            };
            let _ = sender.send((index, kept));
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
            if run.over_disk_limit(Some(child.id())) {
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
fn received_outputs(receiver: &mpsc::Receiver<(usize, (String, bool))>) -> [(String, bool); 2] {
    let mut outputs = [(String::new(), false), (String::new(), false)];
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

/// The limits a run reached, as the overview's reason and as the line
/// its outputs end with. A limit reached by a run that went on to pass
/// (a thread that could not start, where the code made do with fewer)
/// did not stop it, and the words say so.
fn limits_text(status: CodeStatus, limits: &[LimitReached]) -> Option<(String, String)> {
    if limits.is_empty() {
        return None;
    }
    let names: Vec<&str> = limits.iter().map(LimitReached::name).collect();
    let details: Vec<String> = limits.iter().map(ToString::to_string).collect();
    Some(
        if matches!(status, CodeStatus::Pass | CodeStatus::NotStarted) {
            (
                format!("reached {}, and went on", names.join(" and ")),
                format!(
                    "reached {}; the run went on without it, and its verdicts stand",
                    details.join("; and ")
                ),
            )
        } else {
            (
                format!("stopped by {}", names.join(" and ")),
                format!("stopped by {}", details.join("; and by ")),
            )
        },
    )
}

/// The longest line of cargo's messages kept, and the most kept in all:
/// a build's messages about its own crates are a few kilobytes.
const MAX_MESSAGE_BYTES: usize = 1 << 20;
const MAX_MESSAGES_BYTES: usize = 16 << 20;

/// cargo's JSON messages on `reader` about the crates it compiled from
/// outside the registry (the workspace's, raylab's, any other folder's),
/// read line by line as they come, the others dropped: a tail of the whole
/// output could cut the one that matters (a long package version makes a
/// message tens of kilobytes). `true` with them if one was too long or
/// they were too many to keep.
fn read_artifacts(reader: Box<dyn Read + Send>) -> (String, bool) {
    use std::io::BufRead;
    let mut reader = std::io::BufReader::new(reader);
    let (mut kept, mut cut) = (String::new(), false);
    let mut line = Vec::new();
    loop {
        line.clear();
        // At most one byte past the bound, so that a longer line is seen
        // as such; its rest is then skipped to the line's end.
        match (&mut reader)
            .take(MAX_MESSAGE_BYTES as u64 + 1)
            .read_until(b'\n', &mut line)
        {
            Ok(0) => break,
            Ok(_) => {}
            Err(error) if error.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(_) => break,
        }
        if line.len() > MAX_MESSAGE_BYTES {
            cut = true;
            if !skip_line(&mut reader) {
                break;
            }
            continue;
        }
        let Ok(message) = serde_json::from_slice::<serde_json::Value>(&line) else {
            continue;
        };
        let registry = message["package_id"]
            .as_str()
            .is_some_and(|id| id.starts_with("registry+") || id.contains("(registry+"));
        if message["reason"] != "compiler-artifact" || registry {
            continue;
        }
        if kept.len() + line.len() > MAX_MESSAGES_BYTES {
            cut = true;
            continue;
        }
        kept.push_str(&String::from_utf8_lossy(&line));
    }
    (kept, cut)
}

/// Reads past the end of the current line; `false` at the end of input.
fn skip_line(reader: &mut impl std::io::BufRead) -> bool {
    loop {
        let (done, used) = match reader.fill_buf() {
            Ok([]) => return false,
            Ok(buffer) => match buffer.iter().position(|&byte| byte == b'\n') {
                Some(end) => (true, end + 1),
                None => (false, buffer.len()),
            },
            Err(error) if error.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(_) => return false,
        };
        reader.consume(used);
        if done {
            return true;
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

    /// Pass 13 of issue 41, finding 4: the answer key swapped into the
    /// hand-in after its sources were read and before they were copied
    /// (and swapped back once the build started) was built, judged and
    /// passed, while the snapshot compared and checked held the skeleton.
    /// A copy whose sources are not the snapshot's is named.
    #[test]
    fn sources_swapped_between_their_reading_and_their_copy_are_named() {
        let Ok(sandbox) = Sandbox::find(super::super::sandbox::Limits::DEFAULT) else {
            eprintln!("skipped: no working bubblewrap here");
            return;
        };
        let folder = tempfile::tempdir().expect("temp dir");
        let workspace = folder.path().join("ann");
        std::fs::create_dir_all(workspace.join("src")).expect("mkdir");
        std::fs::write(workspace.join("Cargo.toml"), "[package]\nname = \"ann\"\n").expect("write");
        let lib = workspace.join("src/lib.rs");
        std::fs::write(&lib, "pub fn answer() { todo!() }\n").expect("write");
        let snapshot = Snapshot::take(&workspace);
        std::fs::write(&lib, "pub fn answer() { the_key() }\n").expect("write");
        let run = sandbox.start(&workspace).expect("a run");
        // Swapped back: the hand-in is the snapshot again, its copy is not.
        std::fs::write(&lib, "pub fn answer() { todo!() }\n").expect("write");
        assert_eq!(snapshot.changed(&workspace), None);
        let change = copied_otherwise(&snapshot, &run);
        assert!(
            change
                .as_deref()
                .is_some_and(|change| change.contains("src/lib.rs changed")),
            "{change:?}"
        );
        drop(run);
        let run = sandbox.start(&workspace).expect("a run");
        assert_eq!(copied_otherwise(&Snapshot::take(&workspace), &run), None);
    }

    #[test]
    fn a_limit_reached_stops_only_a_run_that_did_not_pass() {
        let processes = [LimitReached::Processes { count: 512 }];
        assert_eq!(limits_text(CodeStatus::Pass, &[]), None);
        let (reason, line) = limits_text(CodeStatus::Pass, &processes).expect("a limit");
        assert_eq!(reason, "reached the process limit, and went on");
        assert!(
            line.starts_with("reached the process limit: the run had 512"),
            "{line}"
        );
        assert!(line.ends_with("its verdicts stand"), "{line}");
        for status in [CodeStatus::Fail, CodeStatus::TimedOut, CodeStatus::Error] {
            let (reason, line) = limits_text(status, &processes).expect("a limit");
            assert_eq!(reason, "stopped by the process limit");
            assert!(line.starts_with("stopped by the process limit: "), "{line}");
        }
        let both = [
            LimitReached::Memory { bytes: 1 << 30 },
            LimitReached::Processes { count: 8 },
        ];
        let (reason, line) = limits_text(CodeStatus::Fail, &both).expect("limits");
        assert_eq!(reason, "stopped by the memory limit and the process limit");
        assert!(line.contains("; and by the process limit"), "{line}");
    }

    /// A run whose code is not all the student's keeps no point: not a
    /// chapter's, and not a hidden scene's, which code including raylab's
    /// own chapters by `#[path]` renders as well as the answer key does.
    #[test]
    fn a_run_not_counted_keeps_no_point_of_a_hidden_scene() {
        let mut run = CodeRun {
            status: CodeStatus::Pass,
            exit_code: Some(0),
            stdout: String::new(),
            stderr: String::new(),
            timeout: Duration::from_secs(60),
            chapters_passed: 1,
            scenes: vec![super::super::hidden::SceneOutcome {
                name: "secret.toml".into(),
                passed: true,
                metrics: None,
                detail: "passes".into(),
            }],
            fresh: None,
            trusted_target: false,
            sources: Vec::new(),
            limits: Vec::new(),
            reason: None,
            chapters: vec![ChapterScore {
                chapter: 1,
                passes: true,
            }],
        };
        assert_eq!(crate::grade::lms::gradescope_results(&run, 1).score, 2.0);
        discount(
            &mut run,
            &["a chapter file includes a file by #[path]".into()],
        );
        let results = crate::grade::lms::gradescope_results(&run, 1);
        assert_eq!(results.score, 0.0);
        assert!(results.tests[1].output.starts_with("not counted"));
        assert_eq!(run.status, CodeStatus::Error);
        assert!(!run.scenes[0].passed);
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

    /// cargo's messages about the crates compiled from outside the
    /// registry are kept whole, however much else cargo says and however
    /// long each is; one too long to keep is said to be cut.
    #[test]
    fn the_messages_of_the_crates_compiled_are_kept_whole() {
        let message = |id: &str, version: &str| {
            format!(
                "{{\"reason\":\"compiler-artifact\",\"package_id\":\"{id}\",\"version\":\"{version}\"}}\n"
            )
        };
        let registry = message(
            "registry+https://github.com/rust-lang/crates.io-index#libm@0.2.1",
            "",
        );
        let student = message("path+file:///class/alice#alice@0.1.0", &"9".repeat(40_000));
        let noise = registry.repeat(2_000) + &"not json\n".repeat(10_000);
        let read = |text: String| read_artifacts(Box::new(std::io::Cursor::new(text.into_bytes())));
        let (kept, cut) = read(noise.clone() + &student + &noise);
        assert!(!cut);
        assert_eq!(kept, student);
        let huge = message("path+file:///class/alice#alice@0.1.0", &"9".repeat(2 << 20));
        let (kept, cut) = read(huge + &student);
        assert!(cut);
        assert_eq!(kept, student);
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
