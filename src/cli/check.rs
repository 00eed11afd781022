//! `raylab check`: the verdict on your chapters (see [`crate::check`]),
//! and `serve`, how a student's binary answers the judge.

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{Context, Result};
use clap::Args;

use crate::check::judge::{Asker, Which};
use crate::check::remote::{Remote, Spawn, StallNotice};
use crate::check::{CheckOptions, CheckReport, Overall, check_all};

/// Check your chapters: checkpoint cases, the image, and robustness.
///
/// For each chapter: questions to each of its functions with numbers you
/// can work out by hand (the first failing one is printed with the lesson
/// section to read), then its built-in scene rendered with your code at
/// 160x120 and compared with the reference image shipped in raylab (on
/// failure your image and a heatmap are written to --failures-dir), then,
/// once the cases and the image pass, the hard cases, reported apart
/// ("correct, not yet robust"; "-" while something before them fails).
///
/// A chapter whose functions are still todo!() is "not started". Chapter N
/// builds on chapters 1 to N-1, and says so when one of them fails. Your
/// chapters answer in child processes and this one judges: what your code
/// prints, writes or exits with is never a verdict, and a function that
/// ends the process (std::process::exit) fails the case it was answering.
///
/// Exit status: 0 every checked chapter passes, 1 one fails or is not
/// started, 2 the check could not run (e.g. unwritable --failures-dir).
#[derive(Debug, Args)]
#[command(long_about)]
pub struct CheckArgs {
    /// Check only this chapter; all by default. The chapters it builds on
    /// are run too, and it fails when one of them does ("needs ch. K"):
    /// `check --chapter K` then shows that one's failure.
    #[arg(long, value_name = "N", value_parser = crate::chapters::parse_chapter)]
    pub chapter: Option<u8>,
    /// Where your image and the heatmap go when a chapter's image fails.
    #[arg(long, value_name = "DIR", default_value = "check-failures")]
    pub failures_dir: PathBuf,
    /// Ask the checkpoints with inputs drawn anew from SEED (as `raylab
    /// grade --code --fresh` does): code that works for the lesson's
    /// numbers only fails. Each chapter's image is then its built-in scene
    /// seen from a camera turned a few degrees (drawn from SEED), judged
    /// against raylab's own render of that view: an image made beforehand
    /// fails.
    #[arg(long, value_name = "SEED")]
    pub fresh: Option<u64>,
    /// The student's binary whose chapters answer (started as `serve`):
    /// how a workspace's `check`, in a build that holds none of raylab's
    /// answers, hands the judging to raylab's own binary.
    #[arg(long, value_name = "BINARY", hide = true)]
    pub answers_from: Option<PathBuf>,
    /// Fail (exit 1) unless every checked chapter is robust too: a
    /// workspace's `cargo test` under `RAYLAB_CHECK_ROBUST=1`.
    #[arg(long, hide = true)]
    pub require_robust: bool,
}

/// Runs the checks with the chapters `C` and prints the verdicts and the
/// summary table; returns the exit status. raylab's own chapters are
/// asked in this process; a student's answer in children of this binary
/// started as `serve`, and this process judges.
// A student's build judges with raylab's own binary, not with `C`.
#[cfg_attr(feature = "student", allow(clippy::extra_unused_type_parameters))]
pub fn check<C: crate::Chapters>(args: &CheckArgs) -> Result<i32> {
    #[cfg(feature = "student")]
    return hand_to_own_binary(args);
    #[cfg(not(feature = "student"))]
    judge_here::<C>(args)
}

/// [`check`] in raylab's own build, which judges in this process.
#[cfg(not(feature = "student"))]
fn judge_here<C: crate::Chapters>(args: &CheckArgs) -> Result<i32> {
    let answering = match &args.answers_from {
        Some(binary) => Some(binary.clone()),
        None if crate::answer_key::sealed() => {
            Some(std::env::current_exe().context("cannot find this program to run the check")?)
        }
        None => None,
    };
    let options = CheckOptions {
        failures_dir: args.failures_dir.clone(),
        forbid_answer_key: answering.is_some(),
        fresh: args.fresh,
        ..CheckOptions::default()
    };
    let report = if let Some(binary) = answering {
        let spawn: Arc<Spawn> = Arc::new(move || {
            let mut command = std::process::Command::new(&binary);
            command.arg("serve");
            Ok((command, Box::new(()) as Box<dyn std::any::Any + Send>))
        });
        let notice: Arc<StallNotice> = Arc::new(
            |step: &crate::check::judge::Step, waited: std::time::Duration| {
                eprintln!(
                    "still running after {} s without an answer: {step}. A loop that never ends? \
                 Ctrl-C stops the check.",
                    waited.as_secs()
                );
            },
        );
        let make = || {
            Box::new(
                Remote::new(Arc::clone(&spawn))
                    .inheriting_stderr()
                    .with_stall_notice(stall_notice(), Arc::clone(&notice)),
            ) as Box<dyn Asker + Send>
        };
        crate::check::judge::judge(&make, Which::one_or_all(args.chapter), &options)
    } else {
        // No comparison is asked for in a check: raylab's comparison
        // wrappers are answers like the others there.
        crate::answer_key::set_strict(true);
        check_all::<C>(args.chapter, &options)
    };
    print!("{}", report.text());
    let status = exit_status(&report);
    if status == 0 && args.require_robust && !report.verdicts.iter().all(|v| v.robust()) {
        return Ok(super::EXIT_FAILED_CHECK);
    }
    Ok(status)
}

/// What a student sees before raylab's own binary is built for the check.
#[cfg(feature = "student")]
pub(super) fn announce_build() {
    eprintln!(
        "building raylab's own binary, which judges your chapters and runs raylab's own \
         commands (once: minutes the first time)"
    );
}

/// A student's build holds none of raylab's answers, which judging
/// needs: raylab's own binary judges, asking this one (see
/// [`crate::check::own_binary`]). On Unix it takes this process's place.
#[cfg(feature = "student")]
fn hand_to_own_binary(args: &CheckArgs) -> Result<i32> {
    let judge = crate::check::own_binary::judge_binary(&announce_build)?;
    let this = std::env::current_exe().context("cannot find this program to run the check")?;
    let mut command = std::process::Command::new(&judge);
    command
        .arg("check")
        .arg("--answers-from")
        .arg(this)
        .arg("--failures-dir")
        .arg(&args.failures_dir);
    if let Some(chapter) = args.chapter {
        command.arg("--chapter").arg(chapter.to_string());
    }
    if let Some(seed) = args.fresh {
        command.arg("--fresh").arg(seed.to_string());
    }
    if args.require_robust {
        command.arg("--require-robust");
    }
    super::run_in_place(command)
}

fn exit_status(report: &CheckReport) -> i32 {
    match report.overall() {
        Overall::Pass => 0,
        Overall::Fail => super::EXIT_FAILED_CHECK,
        Overall::Error => super::EXIT_ERROR,
    }
}

/// How long a step may go without an answer before the student is told
/// where the check is: every case takes well under a second, a chapter's
/// image a few seconds. `RAYLAB_STALL_NOTICE_SECONDS` sets it (the tests
/// make it short).
fn stall_notice() -> std::time::Duration {
    let seconds = std::env::var("RAYLAB_STALL_NOTICE_SECONDS")
        .ok()
        .and_then(|text| text.parse().ok())
        .unwrap_or(30);
    std::time::Duration::from_secs(seconds)
}

/// Answers the judge's questions on this process's standard input and
/// output with the chapters `C` (see [`crate::check::serve`]); what the
/// chapters print goes to standard error.
pub fn serve<C: crate::Chapters>() -> Result<i32> {
    let (questions, answers) = private_pipes().context("cannot take the judge's pipes")?;
    // A program started from a chapter would answer outside the count of
    // raylab's answers that this process keeps.
    crate::check::no_programs::forbid_starting_programs()?;
    // No comparison is asked for: raylab's comparison wrappers are answers
    // like the others.
    crate::answer_key::set_strict(true);
    crate::check::serve::serve::<C>(
        std::io::BufReader::new(questions),
        std::io::BufWriter::new(answers),
    )
    .context("the judge's pipe")?;
    Ok(0)
}

/// The judge's two pipes, moved off standard input and output before any
/// chapter runs: standard output then goes to standard error and
/// standard input reads nothing, so that nothing a chapter prints or
/// reads touches them. The new descriptors close on `exec`, so no process
/// a chapter starts inherits them.
#[cfg(unix)]
fn private_pipes() -> std::io::Result<(std::fs::File, std::fs::File)> {
    use std::os::fd::FromRawFd;
    let moved = |fd: libc::c_int| {
        // SAFETY: plain system calls on this process's own descriptors.
        let copy = unsafe { libc::fcntl(fd, libc::F_DUPFD_CLOEXEC, 3) };
        if copy < 0 {
            Err(std::io::Error::last_os_error())
        } else {
            Ok(copy)
        }
    };
    let questions = moved(0)?;
    let answers = moved(1)?;
    // Not dumpable: no process of the same user may attach to this one
    // (ptrace) or read its memory, where the pipes are.
    #[cfg(target_os = "linux")]
    // SAFETY: a plain system call on this process.
    unsafe {
        libc::prctl(libc::PR_SET_DUMPABLE, 0);
    }
    let null = std::fs::File::open("/dev/null")?;
    // SAFETY: dup2 onto 0 and 1, which this process owns; `null` stays
    // open until both are made.
    unsafe {
        use std::os::fd::AsRawFd;
        if libc::dup2(null.as_raw_fd(), 0) < 0 || libc::dup2(2, 1) < 0 {
            return Err(std::io::Error::last_os_error());
        }
    }
    // SAFETY: both descriptors were just made by fcntl, and nothing else
    // owns them.
    Ok(unsafe {
        (
            std::fs::File::from_raw_fd(questions),
            std::fs::File::from_raw_fd(answers),
        )
    })
}

#[cfg(not(unix))]
fn private_pipes() -> std::io::Result<(std::fs::File, std::fs::File)> {
    Err(std::io::Error::other(
        "answering the judge needs a Unix system",
    ))
}
