//! `raylab check`: the verdict on your chapters (see [`crate::check`]).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;

use crate::check::verdict_file::{Record, SentReport, SentVerdict, VerdictWriter};
use crate::check::{CheckOptions, Overall, check_all};

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
/// chapters run in a child process, so that code which ends the process
/// (std::process::exit) or prints a table of its own cannot pass.
///
/// Exit status: 0 every checked chapter passes, 1 one fails or is not
/// started, 2 the check could not run (e.g. unwritable --failures-dir).
#[derive(Debug, Args)]
#[command(long_about)]
pub struct CheckArgs {
    /// Check only this chapter (and what it builds on); all by default.
    #[arg(long, value_name = "N", value_parser = crate::chapters::parse_chapter)]
    pub chapter: Option<u8>,
    /// Where your image and the heatmap go when a chapter's image fails.
    #[arg(long, value_name = "DIR", default_value = "check-failures")]
    pub failures_dir: PathBuf,
    /// Run the chapters here and write the verdict to FILE, printing
    /// nothing: what `check` and `raylab grade --code` start in a child.
    #[arg(long, value_name = "FILE", hide = true)]
    pub verdict_file: Option<PathBuf>,
}

/// Runs the checks with the chapters `C` and prints the verdicts and the
/// summary table; returns the exit status. raylab's own chapters are
/// checked here; a student's run in a child that writes a verdict file.
pub fn check<C: crate::Chapters>(args: &CheckArgs) -> Result<i32> {
    let options = CheckOptions {
        failures_dir: args.failures_dir.clone(),
        forbid_answer_key: crate::answer_key::sealed(),
        ..CheckOptions::default()
    };
    // No comparison is asked for in a check: raylab's comparison wrappers
    // are answers like the others there.
    crate::answer_key::set_strict(true);
    if let Some(path) = &args.verdict_file {
        return check_into::<C>(args.chapter, &options, path);
    }
    if !crate::answer_key::sealed() {
        let report = check_all::<C>(args.chapter, &options);
        print!("{}", report.text());
        return Ok(exit_status(report.overall()));
    }
    let path = std::env::temp_dir().join(format!(
        "raylab-check-{}-{}.jsonl",
        std::process::id(),
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|elapsed| elapsed.as_nanos())
            .unwrap_or_default()
    ));
    // Removed on Ctrl-C too (crate::cleanup), not only once the check ends.
    let registered = crate::cleanup::register(&path);
    let result = check_in_child(args, &path);
    let _ = std::fs::remove_file(&path);
    drop(registered);
    let (report, ended) = result?;
    print!("{}", report.text(&ended));
    Ok(exit_status(report.overall()))
}

fn exit_status(overall: Overall) -> i32 {
    match overall {
        Overall::Pass => 0,
        Overall::Fail => super::EXIT_FAILED_CHECK,
        Overall::Error => super::EXIT_ERROR,
    }
}

/// The worker: checks and writes every verdict, then the closing record.
fn check_into<C: crate::Chapters>(
    chapter: Option<u8>,
    options: &CheckOptions,
    path: &Path,
) -> Result<i32> {
    let writer = crate::check::verdict_file::install(VerdictWriter::create(path)?)
        .map_err(|_| anyhow::anyhow!("a verdict file is already open"))?;
    let report = check_all::<C>(chapter, options);
    for verdict in &report.verdicts {
        writer.write(&Record::Verdict(SentVerdict::of(verdict)))?;
    }
    writer.write(&Record::End)?;
    Ok(exit_status(report.overall()))
}

/// Runs this same binary as the worker and reads what it wrote, with how
/// its process ended.
fn check_in_child(args: &CheckArgs, path: &Path) -> Result<(SentReport, String)> {
    let binary = std::env::current_exe().context("cannot find this program to run the check")?;
    let mut command = std::process::Command::new(binary);
    command
        .arg("check")
        .arg("--failures-dir")
        .arg(&args.failures_dir)
        .arg("--verdict-file")
        .arg(path);
    if let Some(chapter) = args.chapter {
        command.arg("--chapter").arg(chapter.to_string());
    }
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::process::CommandExt;
        // SAFETY: prctl is async-signal-safe and is all that runs between
        // fork and exec. The worker dies with this process: a check killed
        // alone (SIGTERM, SIGKILL) leaves no chapter looping on.
        unsafe {
            command.pre_exec(|| {
                libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL);
                Ok(())
            });
        }
    }
    let mut child = command
        .spawn()
        .context("cannot start the check of your chapters")?;
    let status = wait_with_stall_notice(&mut child, path)?;
    let report = SentReport::read(path).unwrap_or_default();
    Ok((report, crate::check::verdict_file::process_end(status)))
}

/// How long the check may go without starting a new step before the
/// student is told where it is: every case takes well under a second, a
/// chapter's image a few seconds. `RAYLAB_STALL_NOTICE_SECONDS` sets it
/// (the tests make it short).
fn stall_notice() -> std::time::Duration {
    let seconds = std::env::var("RAYLAB_STALL_NOTICE_SECONDS")
        .ok()
        .and_then(|text| text.parse().ok())
        .unwrap_or(30);
    std::time::Duration::from_secs(seconds)
}

/// Waits for the check's child to end. A check that starts no new step for
/// [`stall_notice`] is usually a loop that never ends in a chapter: the
/// student is told once, on stderr, which step each running chapter is in,
/// and the check goes on (Ctrl-C ends it).
fn wait_with_stall_notice(
    child: &mut std::process::Child,
    path: &Path,
) -> Result<std::process::ExitStatus> {
    let mut size = 0;
    let mut since = std::time::Instant::now();
    let mut told = false;
    let notice = stall_notice();
    loop {
        if let Some(status) = child.try_wait().context("waiting for the check")? {
            return Ok(status);
        }
        std::thread::sleep(std::time::Duration::from_millis(200));
        let now = std::fs::metadata(path).map(|meta| meta.len()).unwrap_or(0);
        if now != size {
            (size, since, told) = (now, std::time::Instant::now(), false);
        } else if !told && since.elapsed() >= notice {
            told = true;
            let steps = SentReport::read(path).unwrap_or_default().running_text();
            if !steps.is_empty() {
                eprintln!(
                    "still running after {} s without a new step: {steps}. A loop that \
                     never ends? Ctrl-C stops the check.",
                    notice.as_secs()
                );
            }
        }
    }
}
