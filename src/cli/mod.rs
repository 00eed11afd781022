//! The `raylab` command line. Each subcommand lives in its own file.

use clap::{Parser, Subcommand};

use check::CheckArgs;

mod bench;
mod check;
mod cost;
mod crosscheck;
mod diff;
mod figure;
mod grade;
mod guard;
mod mesh;
mod new;
mod race;
mod render;
mod trace;
mod values;
mod web;

/// raylab: learn ray tracing one chapter at a time.
///
/// Start with `raylab chapters` to see the course, then
/// `raylab render --chapter 1` and open chapter-1.png. Each chapter's lesson
/// is in the chapters/ folder of the repository (and in `cargo doc --open`).
#[derive(Debug, Parser)]
#[command(name = "raylab", version, about, long_about)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a chapter's stage, with its built-in scene or your own.
    Render(render::RenderArgs),
    /// List the chapters, each with the effects it switches on.
    Chapters,
    /// Print a chapter's built-in scene as TOML, ready to copy and edit.
    Scene(render::SceneArgs),
    /// Time a render several times (no image written) and print the median.
    Bench(bench::BenchArgs),
    /// Sweep a chapter's quality knobs: time, rays and error against a
    /// high-quality reference, as a table, a CSV and an SVG plot.
    Cost(cost::CostArgs),
    // The help of these two is the doc of their argument structs.
    Diff(diff::DiffArgs),
    Grade(grade::GradeArgs),
    /// Trace every ray of a render with our code and with Embree, and compare
    /// (needs the `embree` feature).
    Crosscheck(crosscheck::CrosscheckArgs),
    /// Show what one ray hits: each shape, our nearest hit, and Embree's.
    Probe(crosscheck::ProbeArgs),
    Trace(trace::TraceArgs),
    Figure(figure::FigureArgs),
    Check(check::CheckArgs),
    /// Create a student workspace: a crate where you write each chapter,
    /// with `render`, `check` and every other command running your code.
    New(new::NewArgs),
    Mesh(mesh::MeshArgs),
    Web(web::WebArgs),
    /// Race chapter 11's tree against Embree on generated models of 1,000
    /// to 1,000,000 triangles (needs the `embree` feature).
    Race(race::RaceArgs),
    /// Answer the judge's questions on standard input and output: how
    /// `check` and `raylab grade --code` ask a student's chapters.
    #[command(hide = true)]
    Serve,
    /// Print the fingerprint of the source this binary was built from: how
    /// a student's build finds raylab's own binary of the same source.
    #[command(hide = true)]
    Fingerprint,
}

/// Exit status for "the command ran, and the answer is no" (a diff over its
/// threshold, a failed cross-check).
pub const EXIT_FAILED_CHECK: i32 = 1;
/// Exit status for an error: bad input, unreadable or unwritable files.
pub const EXIT_ERROR: i32 = 2;

/// The most worker threads `--threads` accepts, in every command. Starting
/// threads costs more than linearly in their number (10,000 took 78 s), and
/// no machine raylab teaches on has anywhere near 1024 cores.
pub const MAX_THREADS: usize = 1024;

/// Parses `--threads` (every command's, so the bound is the same
/// everywhere): a whole number from 1 to [`MAX_THREADS`].
pub fn parse_threads(text: &str) -> Result<usize, String> {
    whole_number(
        text,
        MAX_THREADS as u64,
        "the number of worker threads must be",
    )
    .map(|threads| threads as usize)
}

/// A count option's value: a whole number from 1 to `max`, or the message
/// `"{what} a whole number from 1 to {max}"` (`what` ends in "must be").
pub(crate) fn whole_number(text: &str, max: u64, what: &str) -> Result<u64, String> {
    match text.trim().parse::<u64>() {
        Ok(n @ 1..) if n <= max => Ok(n),
        _ => Err(format!("{what} a whole number from 1 to {max}")),
    }
}

/// Runs the command line with raylab's own chapters and returns the process
/// exit status.
pub fn main() -> i32 {
    main_with::<crate::Reference>()
}

/// Runs the command line with the chapters `C` (a student workspace's
/// `main` calls this with its own) and returns the process exit status.
pub fn main_with<C: crate::Chapters>() -> i32 {
    prepare_process();
    if cfg!(feature = "student") || !is_reference::<C>() {
        // A student's binary: raylab's answers must not stand in for theirs.
        crate::answer_key::seal();
    }
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(error) => {
            let _ = error.print();
            return if error.use_stderr() { EXIT_ERROR } else { 0 };
        }
    };
    // A chapter still `todo!()`, or a panic in a student's code, becomes a
    // verdict or an error message, never a backtrace.
    guard::run(|| run::<C>(cli))
}

fn is_reference<C: crate::Chapters>() -> bool {
    std::any::TypeId::of::<C>() == std::any::TypeId::of::<crate::Reference>()
}

/// Why `command` must not run with the chapters `C`, if it must not: a
/// student's chapters built without raylab's `student` feature (their code
/// could call raylab's answers), or raylab's own `check` or `render` run
/// inside a student's workspace (they would judge raylab's answers).
fn refusal<C: crate::Chapters>(command: &Command) -> Option<String> {
    // A check that names the binary whose chapters answer judges those,
    // wherever it runs.
    let judges_chapters = matches!(
        command,
        Command::Check(CheckArgs {
            answers_from: None,
            ..
        }) | Command::Serve
            | Command::Render(_)
            | Command::Trace(_)
            | Command::Web(_)
    );
    if cfg!(feature = "student") && is_reference::<C>() {
        return Some(
            "this program was built for a student workspace (raylab's `student` feature) but \
             runs raylab's own chapters, `raylab::Reference`: src/main.rs must run the \
             workspace's chapters, as `raylab new` writes it"
                .to_string(),
        );
    }
    if !is_reference::<C>() {
        return (!cfg!(feature = "student")).then(|| {
            "this workspace builds raylab without its `student` feature, so its chapters \
             could call raylab's own answers: in Cargo.toml, make the raylab line \
             `raylab = { path = \"...\", features = [\"student\"] }` (as `raylab new` \
             writes it)"
                .to_string()
        });
    }
    let here = std::env::current_dir().ok()?;
    let workspace = crate::workspace::enclosing_workspace(&here).filter(|_| judges_chapters)?;
    Some(format!(
        "{} is a student workspace: this `raylab` runs raylab's own chapters, not the ones \
         written there. Run your chapters with `cargo run --release -- {}` in {}",
        workspace.display(),
        typed_arguments(),
        workspace.display()
    ))
}

/// The arguments this program was given, as a shell would need them typed
/// again: each one that holds anything but letters, digits and `_./=:,-`
/// in single quotes.
fn typed_arguments() -> String {
    std::env::args_os()
        .skip(1)
        .map(|argument| {
            let text = crate::text::visible_name(&argument);
            let plain = !text.is_empty()
                && text
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || "_./=:,-".contains(c));
            if plain {
                text
            } else {
                format!("'{}'", text.replace('\'', "'\\''"))
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs this command line with raylab's own binary (see
/// [`crate::check::own_binary`]), in this process's place on Unix.
#[cfg(feature = "student")]
fn hand_to_raylab() -> anyhow::Result<i32> {
    let raylab = crate::check::own_binary::judge_binary(&check::announce_build)?;
    let mut command = std::process::Command::new(&raylab);
    command.args(std::env::args_os().skip(1));
    run_in_place(command)
}

/// Runs `command`, raylab's own binary, in this process's place on Unix
/// (elsewhere as a child, whose exit status this one returns).
#[cfg(feature = "student")]
fn run_in_place(mut command: std::process::Command) -> anyhow::Result<i32> {
    use anyhow::Context;
    let program = command.get_program().to_string_lossy().into_owned();
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        let error = command.exec();
        Err(error).with_context(|| format!("cannot run raylab's own {program}"))
    }
    #[cfg(not(unix))]
    {
        let status = command
            .status()
            .with_context(|| format!("cannot run raylab's own {program}"))?;
        Ok(status.code().unwrap_or(EXIT_ERROR))
    }
}

/// The error for a command that measures chapters against raylab's
/// answers, in a student's build, which leaves them out.
#[cfg(feature = "student")]
fn compares_with_answers(command: &str) -> anyhow::Result<i32> {
    Err(anyhow::anyhow!(
        "`{command}` measures chapters against raylab's own answers, which a student's build \
         of raylab leaves out (so that no code in it can run them): run `raylab {command}` in \
         raylab's folder, on raylab's chapters"
    ))
}

/// What every raylab binary (raylab's own, and a student workspace's,
/// which calls [`main_with`] from its `main`) sets up first, before any
/// other thread exists.
fn prepare_process() {
    // Rust programs ignore SIGPIPE, so once a reader such as `head` closes
    // the pipe, the next `println!` panics. Command-line tools are expected
    // to stop quietly instead: restore the default action of the signal.
    #[cfg(unix)]
    // SAFETY: called first thing in `main`, before any other thread exists;
    // setting a signal's action to its default installs no handler code.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // Ctrl-C or a kill while an output is being written must not leave its
    // temporary file behind (see crate::cleanup).
    crate::cleanup::install_signal_handlers();
}

fn run<C: crate::Chapters>(cli: Cli) -> i32 {
    if let Some(refusal) = refusal::<C>(&cli.command) {
        eprintln!("error: {}", crate::text::terminal_safe(&refusal));
        return EXIT_ERROR;
    }
    // A student's build leaves out the commands that compute with raylab's
    // answers (their oracles, reference images, the judge): those that do
    // not run the student's chapters are raylab's own binary's to run,
    // and those that would compare them with raylab's answers say so.
    let result = match cli.command {
        Command::Render(args) => render::render::<C>(&args),
        Command::Chapters => render::chapters(),
        Command::Scene(args) => render::scene(&args),
        Command::Bench(args) => bench::bench::<C>(&args),
        #[cfg(not(feature = "student"))]
        Command::Cost(args) => cost::cost::<C>(&args),
        #[cfg(not(feature = "student"))]
        Command::Diff(args) => diff::diff(&args),
        #[cfg(not(feature = "student"))]
        Command::Grade(args) => grade::grade(&args),
        #[cfg(not(feature = "student"))]
        Command::Crosscheck(args) => crosscheck::crosscheck::<C>(&args),
        Command::Probe(args) => crosscheck::probe::<C>(&args),
        Command::Trace(args) => trace::trace::<C>(&args),
        #[cfg(not(feature = "student"))]
        Command::Figure(args) => figure::figure::<C>(&args),
        Command::Check(args) => check::check::<C>(&args),
        #[cfg(not(feature = "student"))]
        Command::New(args) => new::new(&args),
        #[cfg(not(feature = "student"))]
        Command::Mesh(args) => mesh::mesh(&args),
        #[cfg(not(feature = "student"))]
        Command::Race(args) => race::race(&args),
        #[cfg(feature = "student")]
        Command::Diff(_)
        | Command::Grade(_)
        | Command::New(_)
        | Command::Mesh(_)
        | Command::Race(_) => hand_to_raylab(),
        #[cfg(feature = "student")]
        Command::Cost(_) => compares_with_answers("cost"),
        #[cfg(feature = "student")]
        Command::Crosscheck(_) => compares_with_answers("crosscheck"),
        #[cfg(feature = "student")]
        Command::Figure(_) => compares_with_answers("figure"),
        Command::Web(args) => web::web::<C>(&args),
        Command::Serve => check::serve::<C>(),
        Command::Fingerprint => {
            println!("{}", crate::check::protocol::SOURCE);
            Ok(0)
        }
    };
    match result {
        Ok(status) => status,
        Err(error) => {
            // Messages quote file and object names, which may hold
            // terminal control characters.
            eprintln!(
                "error: {}",
                crate::text::terminal_safe(&format!("{error:#}"))
            );
            EXIT_ERROR
        }
    }
}
