//! `raylab check`: the verdict on your chapters (see [`crate::check`]).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use crate::check::{CheckOptions, Overall, check_all};

/// Check your chapters: checkpoint cases, the image, and robustness.
///
/// For each chapter: questions to each of its functions with numbers you
/// can work out by hand (the first failing one is printed with the lesson
/// section to read), then its built-in scene rendered with your code at
/// 160x120 and compared with the reference image shipped in raylab (on
/// failure your image and a heatmap are written to --failures-dir), then
/// the hard cases, reported apart ("correct, not yet robust").
///
/// A chapter whose functions are still todo!() is "not started". Chapter N
/// builds on chapters 1 to N-1, and says so when one of them fails.
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
}

/// Runs the checks with the chapters `C` and prints the verdicts and the
/// summary table; returns the exit status.
pub fn check<C: crate::Chapters>(args: &CheckArgs) -> Result<i32> {
    let options = CheckOptions {
        failures_dir: args.failures_dir.clone(),
        ..CheckOptions::default()
    };
    let report = check_all::<C>(args.chapter, &options);
    print!("{}", report.text());
    Ok(match report.overall() {
        Overall::Pass => 0,
        Overall::Fail => super::EXIT_FAILED_CHECK,
        Overall::Error => super::EXIT_ERROR,
    })
}
