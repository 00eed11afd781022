//! `raylab grade`: compare a folder of student renders with the references.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;

use crate::cli::diff::CriteriaArgs;
use crate::cli::{EXIT_FAILED_CHECK, render::write_text_atomic};

/// Grade a folder of student renders (chapter-N.png) into an HTML report.
///
/// The folder holds one PNG per chapter, named `chapter-N.png` (N from 1 to
/// 8, lower case, no leading zero), each rendered from the chapter's
/// built-in scene with default settings (`raylab render --chapter N`, any
/// --width/--height). Each is compared with a reference of its size, never
/// rendered by code that can be the student's: the `chapter-N.png` of the
/// --against folder when its size matches; at 160x120, the reference image
/// shipped inside raylab; at any other size, the built-in scene rendered by
/// raylab's reference chapters, only once they have reproduced the shipped
/// 160x120 image bit for bit (if not, the hand-in is not graded: "this
/// raylab's chapters differ from the shipped references").
///
/// Writes one self-contained HTML report (images inlined) with, per chapter,
/// the student image, the reference, a heatmap, the metrics and pass/fail,
/// and prints a Markdown summary. Missing chapters, unreadable files and
/// other entries of the folder are listed, not fatal. A hand-in must be a
/// regular file in the folder: a symbolic link is refused (never followed,
/// read or shown), and so is a FIFO or a device. Images are read up to
/// 16384 pixels a side and 40,000,000 pixels in all. See `raylab diff
/// --help` for the metrics and the threshold.
///
/// Exit status: 0 when all 8 chapters are present and pass; 1 when any
/// fails, is missing or unreadable; 2 on an error (the folder cannot be
/// read, the report cannot be written, --against is not a folder).
#[derive(Debug, Args)]
#[command(long_about)]
pub struct GradeArgs {
    /// The folder of student PNGs.
    #[arg(value_name = "DIR")]
    pub folder: PathBuf,
    /// A folder of your own reference PNGs named chapter-N.png, used where
    /// their size is the hand-in's [default: the references shipped inside
    /// raylab].
    #[arg(long, value_name = "FOLDER")]
    pub against: Option<PathBuf>,
    /// Where to write the HTML report [default: DIR/report.html].
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,
    #[command(flatten)]
    pub criteria: CriteriaArgs,
}

pub fn grade(args: &GradeArgs) -> Result<i32> {
    if !args.folder.is_dir() {
        bail!("{}: not a folder", args.folder.display());
    }
    let references: Option<&Path> = match &args.against {
        Some(folder) if !folder.is_dir() => {
            bail!("--against {}: not a folder", folder.display())
        }
        Some(folder) => Some(folder),
        None => None,
    };
    let report = args
        .report
        .clone()
        .unwrap_or_else(|| args.folder.join("report.html"));
    // The report must not replace a hand-in (or a reference): anything in
    // the folders but an earlier HTML report counts as an input.
    let mut inputs = files_in(&args.folder)?;
    inputs.retain(|path| {
        !path
            .extension()
            .is_some_and(|extension| extension.eq_ignore_ascii_case("html"))
    });
    if let Some(folder) = references {
        inputs.extend(files_in(folder)?);
    }
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    crate::output::check_outputs(&inputs, &[("--report", &report)], false)?;
    let grade = crate::grade::grade(
        &args.folder,
        references,
        args.criteria.criteria(),
        Some(&report),
    )?;
    write_text_atomic(&report, &grade.html()?)?;
    print!("{}", crate::text::terminal_safe(&grade.markdown(&report)));
    Ok(if grade.all_pass() {
        0
    } else {
        EXIT_FAILED_CHECK
    })
}

/// The files (not folders) directly in `folder`.
fn files_in(folder: &Path) -> Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(folder)
        .with_context(|| format!("cannot read the folder {}", folder.display()))?;
    let mut files = Vec::new();
    for entry in entries {
        let path = entry
            .with_context(|| format!("cannot read the folder {}", folder.display()))?
            .path();
        if path.is_file() {
            files.push(path);
        }
    }
    Ok(files)
}
