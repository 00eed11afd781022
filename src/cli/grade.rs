//! `raylab grade`: compare student renders with the references, one
//! student or a class, or run a class's workspaces' checks.

use std::io::{Seek as _, Write};
use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{Context, Result, bail};
use clap::Args;

use crate::cli::diff::CriteriaArgs;
use crate::cli::{EXIT_FAILED_CHECK, render::write_text_atomic};
use crate::grade::References;
use crate::grade::code::MAX_TIMEOUT_SECONDS;

/// Grade student renders (chapter-N.png), one student or a whole class,
/// into an HTML report; or, with --code, students' workspaces.
///
/// One student: DIR holds one PNG per chapter, named `chapter-N.png` (N
/// a chapter's number as `raylab chapters` lists them, lower case, no
/// leading zero), each rendered from the
/// chapter's built-in scene with default settings (`raylab render
/// --chapter N`, at its size, or at a small --width/--height: from 16 a
/// side up to 160x120 pixels in all, a reference is rendered at the
/// hand-in's size; an --against image's size is graded too). A class: DIR holds one
/// folder per student, each like the above (DIR is a class when none of its
/// entries is named chapter-N.png and one is a folder).
///
/// Each image is compared with a reference of its size, never rendered by
/// code that can be the student's: the `chapter-N.png` of the --against
/// folder when its size matches; at 160x120, the reference image shipped
/// inside raylab; at any other size, the built-in scene rendered by
/// raylab's reference chapters, only once they have reproduced the shipped
/// 160x120 image bit for bit (if they do not, the hand-in is not graded:
/// "this raylab's chapters differ from the shipped references").
///
/// Writes one self-contained HTML report (images inlined; for a class, only
/// the failing chapters', written as each student is graded, so memory
/// does not grow with the class) and prints a
/// Markdown summary; a class also gets a CSV (student, chapter, status,
/// metrics). Missing chapters, unreadable files and other entries are
/// listed, not fatal. A hand-in must be a regular file in the folder and a
/// student's folder a real folder: symbolic links are refused (never
/// followed, read or shown), and so are FIFOs and devices. Images are read
/// up to 16384 pixels a side and 40,000,000 pixels in all. See `raylab diff
/// --help` for the metrics and the threshold.
///
/// With --code, each folder of DIR is a student workspace (made by `raylab
/// new`): raylab builds it (`cargo build --release --offline`), one student
/// at a time, then judges its chapters itself, the student's binary only
/// answering raylab's questions; the build and the answers run within
/// --timeout seconds (then every process of the run is killed), inside a
/// bubblewrap sandbox: the file system read-only but the workspace for the
/// build, nothing writable and no /proc for the answers, no network, its
/// own pid namespace, and limits on memory, CPU time and file size.
/// Without bubblewrap (`bwrap`), --code refuses to run unless --no-sandbox
/// is given. --fresh SEED draws every parametrised case's inputs and each
/// chapter image's camera anew. Each
/// student is reported as pass, fail, not started, timed out, build error
/// or error, with the check's summary table. See docs/instructors.md.
///
/// Exit status: 0 when every chapter (of every student) is present and
/// passes; 1 when any fails, is missing, unreadable or refused; 2 on an
/// error (the folder cannot be read, the report cannot be written,
/// --against is not a folder).
#[derive(Debug, Args)]
#[command(long_about)]
pub struct GradeArgs {
    /// One student's folder of PNGs, or a class's folder of students.
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
    /// Where to write the CSV of a class [default: DIR/grades.csv; one
    /// student's folder gets one only when asked].
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Each folder of DIR is a student workspace: run its `check`.
    #[arg(long)]
    pub code: bool,
    /// With --code, the time limit of each student's build and check, in
    /// seconds.
    #[arg(long, value_name = "SECONDS", default_value_t = 600, value_parser = parse_timeout)]
    pub timeout: u64,
    /// With --code, run the students' code without bubblewrap's sandbox,
    /// with your own rights (only for code you trust, or inside a VM).
    #[arg(long, requires = "code")]
    pub no_sandbox: bool,
    /// With --code, build on each workspace's target/ as it is. By
    /// default one that no run of raylab's left as it is now is emptied
    /// first: cargo would take a binary the student built from other
    /// sources for up to date. Only for builds you made yourself.
    #[arg(long, requires = "code")]
    pub trust_targets: bool,
    /// With --code, draw every parametrised case's inputs (rays, spheres,
    /// triangles, seeds) and each chapter's camera anew from SEED, within
    /// each case's stated ranges, so that no answers prepared in advance
    /// pass; the hard cases keep theirs. Give the same SEED to every job of
    /// a class and to --merge.
    #[arg(long, value_name = "SEED", requires = "code")]
    pub fresh: Option<u64>,
    /// With --code, the cargo profile each workspace is built with:
    /// `release`, or `dev`, which builds in about half the time and
    /// answers a few times slower (the verdicts are the same).
    #[arg(long, value_name = "PROFILE", default_value = "release", value_parser = parse_profile, requires = "code")]
    pub build_profile: crate::grade::code::BuildProfile,
    /// With --code, check chapters 1 to N only (those assigned so far);
    /// every chapter by default.
    #[arg(long, value_name = "N", requires = "code", value_parser = crate::chapters::parse_chapter)]
    pub chapter: Option<u8>,
    /// Write a gradebook CSV that Canvas and Moodle import: one row per
    /// student (their folder's name as `SIS Login ID`), 1 or 0 per
    /// chapter, and the total. See docs/instructors.md.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["student", "gradescope"])]
    pub gradebook: Option<PathBuf>,
    /// With --code, DIR is ONE submission (a workspace): grade it and write
    /// Gradescope's autograder results (results.json) to FILE, a test per
    /// chapter worth a point. What docs/instructors.md's `run_autograder`
    /// runs.
    #[arg(
        long,
        value_name = "FILE",
        requires = "code",
        conflicts_with_all = ["student", "merge", "report", "csv"]
    )]
    pub gradescope: Option<PathBuf>,
    /// Grade only this student of the class DIR (the name of their folder),
    /// into the result file --result: one job of a class graded on several
    /// machines (see --merge).
    #[arg(
        long,
        value_name = "NAME",
        requires = "result",
        conflicts_with = "merge"
    )]
    pub student: Option<std::ffi::OsString>,
    /// With --student, where to write the student's result (JSON).
    #[arg(long, value_name = "FILE", requires = "student")]
    pub result: Option<PathBuf>,
    /// With --code, a scene of your own (a TOML file, or a folder of them;
    /// repeat for more) that each student's chapters render and that is
    /// compared with raylab's reference chapters on the same scene: a
    /// copied reference image proves nothing. No OBJ files (generated
    /// meshes are fine).
    #[arg(long = "scene", value_name = "FILE", requires = "code")]
    pub scenes: Vec<PathBuf>,
    /// The chapter whose stage renders the --scene files [default: the
    /// --chapter graded up to, else the last chapter].
    #[arg(long, value_name = "N", value_parser = crate::chapters::parse_chapter)]
    pub scene_chapter: Option<u8>,
    /// Replace a --report, --csv or --result file that raylab did not write,
    /// or a read-only one.
    #[arg(long)]
    pub force: bool,
    /// Build the class DIR's report and CSV from the result files (*.json)
    /// in FOLDER that `--student` jobs wrote, as one run of the class would.
    #[arg(long, value_name = "FOLDER")]
    pub merge: Option<PathBuf>,
    #[command(flatten)]
    pub criteria: CriteriaArgs,
}

impl GradeArgs {
    /// The chapter whose stage renders the hidden scenes: `--scene-chapter`,
    /// else the chapter graded up to, because a class graded on chapters 1
    /// to 6 has written no chapter past them (the last chapter's stage
    /// would fail every student's scenes).
    fn scene_chapter(&self) -> u8 {
        (self.scene_chapter)
            .or(self.chapter)
            .unwrap_or(crate::chapters::LAST_CHAPTER)
    }
}

fn parse_profile(text: &str) -> Result<crate::grade::code::BuildProfile, String> {
    match text {
        "release" => Ok(crate::grade::code::BuildProfile::Release),
        "dev" => Ok(crate::grade::code::BuildProfile::Dev),
        _ => Err("the build profile must be release or dev".into()),
    }
}

fn parse_timeout(text: &str) -> Result<u64, String> {
    super::whole_number(
        text,
        MAX_TIMEOUT_SECONDS,
        "the time limit in seconds must be",
    )
}

/// A reference image of `against` that is one of the hand-ins in
/// `graded` (a student's folder, or a class of them) as the file system
/// identifies files (device and inode): a bind mount of a student's
/// folder, or a hard link to a hand-in, has a path of its own.
fn hand_in_among_references(against: &Path, graded: &Path) -> Option<PathBuf> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        // A reference is read through a symbolic link (`Links::Follow`):
        // it is the file the link leads to. A hand-in that is a link is
        // refused when graded: the file itself.
        let identity = |path: &Path, links: crate::input::Links| {
            let meta = match links {
                crate::input::Links::Follow => std::fs::metadata(path),
                crate::input::Links::Refuse => std::fs::symlink_metadata(path),
            };
            meta.ok()
                .filter(std::fs::Metadata::is_file)
                .map(|meta| (meta.dev(), meta.ino()))
        };
        let pngs = |folder: &Path| -> Vec<PathBuf> {
            std::fs::read_dir(folder)
                .into_iter()
                .flatten()
                .flatten()
                .map(|entry| entry.path())
                .filter(|path| path.extension().is_some_and(|ext| ext == "png"))
                .collect()
        };
        let references: Vec<((u64, u64), PathBuf)> = pngs(against)
            .into_iter()
            .filter_map(|path| identity(&path, crate::input::Links::Follow).map(|id| (id, path)))
            .collect();
        if references.is_empty() {
            return None;
        }
        // The hand-ins: the folder's own PNGs, and its students' (never
        // through a link: those are refused when graded).
        let mut folders = vec![graded.to_path_buf()];
        for entry in std::fs::read_dir(graded).into_iter().flatten().flatten() {
            if entry.file_type().is_ok_and(|kind| kind.is_dir()) {
                folders.push(entry.path());
            }
        }
        for folder in folders {
            for hand_in in pngs(&folder) {
                if let Some(id) = identity(&hand_in, crate::input::Links::Refuse)
                    && let Some((_, reference)) = references.iter().find(|(r, _)| *r == id)
                {
                    return Some(reference.clone());
                }
            }
        }
        None
    }
    #[cfg(not(unix))]
    {
        let _ = (against, graded);
        None
    }
}

pub fn grade(args: &GradeArgs) -> Result<i32> {
    if !args.folder.is_dir() {
        bail!("{}: not a folder", args.folder.display());
    }
    let against: Option<&Path> = match &args.against {
        Some(folder) if !folder.is_dir() => {
            bail!("--against {}: not a folder", folder.display())
        }
        // The hand-ins compared with themselves would all pass.
        Some(folder)
            if folder.canonicalize().ok().is_some_and(|against| {
                args.folder
                    .canonicalize()
                    .is_ok_and(|graded| against.starts_with(&graded))
            }) =>
        {
            bail!(
                "--against {}: that is the folder being graded (or inside it): each hand-in \
                 would be compared with itself; give a folder of your own references",
                folder.display()
            )
        }
        Some(folder) => {
            if let Some(shared) = hand_in_among_references(folder, &args.folder) {
                bail!(
                    "--against {}: {} is a hand-in of the folder being graded (the same file, \
                     through a bind mount or a hard link): it would be compared with itself; \
                     give a folder of your own references",
                    folder.display(),
                    shared.display()
                )
            }
            Some(folder)
        }
        None => None,
    };
    if let Some(results) = &args.gradescope {
        return grade_for_gradescope(args, results);
    }
    let class = args.code
        || args.student.is_some()
        || args.merge.is_some()
        || crate::grade::class::is_class(&args.folder)?;
    if !class && args.gradebook.is_some() {
        bail!(
            "--gradebook: {} is one student's folder; a gradebook is written for a class \
             (a folder of students' folders)",
            args.folder.display()
        );
    }
    if let (Some(name), Some(result)) = (&args.student, &args.result) {
        return grade_one_of_class(args, against, name, result);
    }
    let report = args
        .report
        .clone()
        .unwrap_or_else(|| args.folder.join("report.html"));
    let csv = args
        .csv
        .clone()
        .or_else(|| class.then(|| args.folder.join("grades.csv")));
    let mut outputs: Vec<(&str, &Path)> = vec![("--report", &report)];
    if let Some(csv) = &csv {
        outputs.push(("--csv", csv));
    }
    if let Some(gradebook) = &args.gradebook {
        outputs.push(("--gradebook", gradebook));
    }
    check_outputs_spare_hand_ins(args, class, against, &outputs)?;
    if args.code {
        check_outputs_spare_code(args, &folders_in(&args.folder)?, &outputs)?;
    }
    if class {
        let skip: Vec<&Path> = outputs.iter().map(|(_, path)| *path).collect();
        let csv = csv
            .clone()
            .unwrap_or_else(|| args.folder.join("grades.csv"));
        return grade_class(args, against, &skip, &report, &csv);
    }
    grade_one_student(args, against, &report, csv.as_deref())
}

/// Refuses, `--force` or not, an output that would replace an input of
/// the code's grading: a `--scene` file (or one in a `--scene` folder), or
/// anything inside a workspace graded (a chapter's source, its
/// `Cargo.toml`). `workspaces` are the folders graded with `--code`.
fn check_outputs_spare_code(
    args: &GradeArgs,
    workspaces: &[PathBuf],
    outputs: &[(&str, &Path)],
) -> Result<()> {
    let mut scenes = Vec::new();
    for scene in &args.scenes {
        if scene.is_dir() {
            scenes.extend(files_in(scene)?);
        } else {
            scenes.push(scene.clone());
        }
    }
    let scenes: Vec<&Path> = scenes.iter().map(PathBuf::as_path).collect();
    crate::output::check_outputs(&scenes, outputs, args.force)?;
    for &(option, path) in outputs {
        let folder = match path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        let Ok(folder) = folder.canonicalize() else {
            continue;
        };
        for workspace in workspaces {
            if workspace
                .canonicalize()
                .is_ok_and(|workspace| folder.starts_with(workspace))
            {
                bail!(
                    "{option} {}: that is inside the workspace {}, which is graded: an \
                     output there could replace the student's code; write it elsewhere",
                    path.display(),
                    workspace.display()
                );
            }
        }
    }
    Ok(())
}

/// Refuses outputs that would replace a hand-in (or a reference): anything
/// in the folders but an earlier report or CSV counts as an input.
fn check_outputs_spare_hand_ins(
    args: &GradeArgs,
    class: bool,
    against: Option<&Path>,
    outputs: &[(&str, &Path)],
) -> Result<()> {
    let mut inputs = files_in(&args.folder)?;
    if class {
        for student in folders_in(&args.folder)? {
            // A student's folder that cannot be read holds nothing an
            // output could replace here; grading refuses that student alone.
            if let Ok(files) = files_in(&student) {
                inputs.extend(files);
            }
        }
    }
    let outputs_of_before = |path: &PathBuf| {
        path.extension().is_some_and(|extension| {
            extension.eq_ignore_ascii_case("html") || extension.eq_ignore_ascii_case("csv")
        })
    };
    inputs.retain(|path| !outputs_of_before(path));
    if let Some(folder) = against {
        inputs.extend(files_in(folder)?);
    }
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    crate::output::check_outputs(&inputs, outputs, args.force)?;
    for &(option, path) in outputs {
        let marker = match option {
            "--csv" => crate::output::markers::GRADE_CSV,
            "--gradebook" => crate::output::markers::GRADEBOOK_CSV,
            _ => crate::output::markers::GRADE_REPORT,
        };
        crate::output::check_replaceable_text(option, path, args.force, marker)?;
    }
    Ok(())
}

/// Grades a class folder (renders, or with --code workspaces), skipping the
/// outputs `skip`, and writes its report and CSV.
fn grade_class(
    args: &GradeArgs,
    against: Option<&Path>,
    skip: &[&Path],
    report: &Path,
    csv: &Path,
) -> Result<i32> {
    let sandbox = if args.code && !args.no_sandbox && args.merge.is_none() {
        Some(code_sandbox(args, &[report, csv])?)
    } else {
        None
    };
    // The students' sections of the report, written as each is graded: an
    // unnamed file (gone however raylab ends) beside the report, so that
    // the report's size never has to fit in memory.
    let folder = match report.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let mut sections = tempfile::tempfile_in(folder).with_context(|| {
        format!(
            "cannot make a temporary file in {} for the report",
            folder.display()
        )
    })?;
    let graded = {
        let mut buffered = std::io::BufWriter::new(&mut sections);
        let graded = if let Some(results) = &args.merge {
            crate::grade::class::merge(
                &args.folder,
                read_results(results)?,
                &grade_options(args, against)?,
                skip,
                &mut buffered,
            )?
        } else if args.code {
            crate::grade::class::grade_class_code(
                &args.folder,
                &code_job(
                    args,
                    sandbox.as_ref(),
                    &crate::grade::hidden::load(&args.scenes, args.scene_chapter(), args.fresh)?,
                ),
                skip,
                &mut |student| {
                    eprintln!(
                        "checking {}",
                        crate::text::terminal_safe(
                            &args.folder.join(student).display().to_string()
                        )
                    )
                },
                &mut buffered,
            )?
        } else {
            crate::grade::class::grade_class(
                &args.folder,
                &mut References::<crate::Reference>::new(against),
                args.criteria.criteria(),
                skip,
                &mut buffered,
            )?
        };
        buffered
            .flush()
            .context("cannot write the report's temporary file")?;
        graded
    };
    sections
        .seek(std::io::SeekFrom::Start(0))
        .context("cannot read back the report's temporary file")?;
    let table = graded.csv();
    let assigned = args.chapter.unwrap_or(crate::chapters::LAST_CHAPTER);
    let gradebook = crate::grade::lms::gradebook_csv(&graded, assigned);
    let mut streams: Vec<(&Path, crate::output::Writer)> = vec![
        (
            report,
            Box::new(|out: &mut dyn Write| graded.write_html(out, &mut sections)),
        ),
        (
            csv,
            Box::new(|out: &mut dyn Write| out.write_all(table.as_bytes())),
        ),
    ];
    if let Some(path) = &args.gradebook {
        streams.push((
            path,
            Box::new(|out: &mut dyn Write| out.write_all(gradebook.as_bytes())),
        ));
    }
    crate::output::write_streams(streams)?;
    print!(
        "{}",
        crate::text::terminal_safe(&graded.markdown(report, csv))
    );
    Ok(if graded.all_pass() {
        0
    } else {
        EXIT_FAILED_CHECK
    })
}

/// Grades the one submission DIR (a workspace) and writes Gradescope's
/// results file `results`.
fn grade_for_gradescope(args: &GradeArgs, results: &Path) -> Result<i32> {
    let manifest = args.folder.join("Cargo.toml");
    if !std::fs::symlink_metadata(&manifest).is_ok_and(|metadata| metadata.is_file()) {
        bail!(
            "{}: not a workspace (no Cargo.toml): --gradescope grades one submission, a \
             folder made by raylab new",
            args.folder.display()
        );
    }
    check_outputs_spare_code(
        args,
        std::slice::from_ref(&args.folder),
        &[("--gradescope", results)],
    )?;
    crate::output::check_replaceable_text(
        "--gradescope",
        results,
        args.force,
        crate::output::markers::GRADESCOPE_RESULTS,
    )?;
    let sandbox = if args.no_sandbox {
        None
    } else {
        Some(code_sandbox(args, &[results])?)
    };
    let scenes = crate::grade::hidden::load(&args.scenes, args.scene_chapter(), args.fresh)?;
    let run =
        crate::grade::code::run_check(&args.folder, &code_job(args, sandbox.as_ref(), &scenes))?;
    let up_to = args.chapter.unwrap_or(crate::chapters::LAST_CHAPTER);
    let graded = crate::grade::lms::gradescope_results(&run, up_to);
    let json = serde_json::to_vec_pretty(&graded).context("cannot write the results as JSON")?;
    crate::output::write_files(&[(results, &json)])?;
    println!(
        "{}: {} of {} points -> {}",
        crate::text::terminal_safe(&args.folder.display().to_string()),
        graded.score,
        graded.tests.len(),
        crate::text::terminal_safe(&results.display().to_string())
    );
    Ok(if run.status == crate::grade::code::CodeStatus::Pass {
        0
    } else {
        EXIT_FAILED_CHECK
    })
}

/// Grades the student `name` of the class and writes their result file.
fn grade_one_of_class(
    args: &GradeArgs,
    against: Option<&Path>,
    name: &std::ffi::OsStr,
    result: &Path,
) -> Result<i32> {
    if args.code {
        check_outputs_spare_code(args, &folders_in(&args.folder)?, &[("--result", result)])?;
    } else {
        crate::output::check_outputs(&[], &[("--result", result)], args.force)?;
    }
    crate::output::check_replaceable_text(
        "--result",
        result,
        args.force,
        crate::output::markers::GRADE_RESULT,
    )?;
    let mut references = References::<crate::Reference>::new(against);
    let sandbox;
    let scenes;
    let job = if args.code {
        sandbox = if args.no_sandbox {
            None
        } else {
            Some(code_sandbox(args, &[result])?)
        };
        scenes = crate::grade::hidden::load(&args.scenes, args.scene_chapter(), args.fresh)?;
        crate::grade::class::Job::Code(code_job(args, sandbox.as_ref(), &scenes))
    } else {
        crate::grade::class::Job::Renders(&mut references)
    };
    let options = grade_options(args, against)?;
    let graded = crate::grade::class::grade_student(&args.folder, name, job, &options, &[result])?;
    let json = serde_json::to_vec(&graded).context("cannot write the result as JSON")?;
    crate::output::write_files(&[(result, &json)])?;
    println!(
        "{}: {} -> {}",
        graded.student.name,
        graded.student.verdict(),
        crate::text::terminal_safe(&result.display().to_string())
    );
    Ok(if graded.student.passes() {
        0
    } else {
        EXIT_FAILED_CHECK
    })
}

/// The sandbox of `grade --code`, hiding from the students' code the
/// files of the instructor's that `args` name (the hidden scenes, the
/// references) and `outputs`, wherever they would show in it.
fn code_sandbox(args: &GradeArgs, outputs: &[&Path]) -> Result<crate::grade::sandbox::Sandbox> {
    let mut hidden = args.scenes.clone();
    hidden.extend(args.against.clone());
    // What a folder's entries lead to, too: a scene in a --scene folder
    // may be a link to a file elsewhere, which the sandbox hides where it
    // is (the sandbox resolves each path it hides).
    for folder in args.scenes.iter().chain(&args.against) {
        if let Ok(entries) = std::fs::read_dir(folder) {
            hidden.extend(entries.flatten().map(|entry| entry.path()));
        }
    }
    hidden.extend(outputs.iter().map(|path| path.to_path_buf()));
    // And the folders they go in: the other jobs of a class write their
    // results beside this job's (each holding its student's sources), some
    // after this run has started.
    hidden.extend(
        outputs
            .iter()
            .filter_map(|path| path.parent())
            .map(|folder| {
                if folder.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    folder
                }
            })
            .filter(|folder| folder.parent().is_some() || folder.is_relative())
            .map(Path::to_path_buf),
    );
    Ok(
        crate::grade::sandbox::Sandbox::find(crate::grade::sandbox::Limits::DEFAULT)?
            .hiding(hidden)
            .trusting_targets(args.trust_targets),
    )
}

/// The job of `grade --code` that `args` describe, with its hidden
/// `scenes` loaded.
fn code_job<'a>(
    args: &GradeArgs,
    sandbox: Option<&'a crate::grade::sandbox::Sandbox>,
    scenes: &'a [crate::grade::hidden::HiddenScene],
) -> crate::grade::code::CodeJob<'a> {
    crate::grade::code::CodeJob {
        timeout: Duration::from_secs(args.timeout),
        sandbox,
        fresh: args.fresh,
        chapter: args.chapter,
        profile: args.build_profile,
        scenes,
    }
}

/// How `args` grade: what each `--student` job stores in its result and
/// `--merge` compares. The sandbox is named, not found: a merge runs no
/// code.
fn grade_options(
    args: &GradeArgs,
    against: Option<&Path>,
) -> Result<crate::grade::class::GradeOptions> {
    if !args.code {
        return Ok(crate::grade::class::GradeOptions::renders(
            args.criteria.criteria(),
            against,
        )?);
    }
    let job = code_job(args, None, &[]);
    let mut options = crate::grade::class::GradeOptions::code(
        &job,
        &crate::grade::hidden::texts(&args.scenes)?,
        args.scene_chapter(),
    );
    options.sandboxed = Some(!args.no_sandbox);
    options.trusted_targets = Some(args.trust_targets && !args.no_sandbox);
    Ok(options)
}

/// The result files (`*.json`) in `folder`, each read within a bound.
fn read_results(folder: &Path) -> Result<Vec<crate::grade::class::StudentResult>> {
    let entries = std::fs::read_dir(folder)
        .with_context(|| format!("--merge {}: cannot read the folder", folder.display()))?;
    let mut results = Vec::new();
    for entry in entries {
        let path = entry
            .with_context(|| format!("--merge {}: cannot read the folder", folder.display()))?
            .path();
        if path.extension().is_none_or(|extension| extension != "json") {
            continue;
        }
        let bytes = crate::input::read_bounded(
            &path,
            MAX_RESULT_BYTES,
            "result file",
            crate::input::Links::Refuse,
        )?;
        let result = serde_json::from_slice(&bytes).with_context(|| {
            format!(
                "{}: not a result file of raylab grade --student",
                path.display()
            )
        })?;
        results.push(result);
    }
    Ok(results)
}

/// The largest result file --merge reads: a student's section holds the
/// figures of their failing chapters (a few megabytes at 640x480).
const MAX_RESULT_BYTES: u64 = 256 << 20;

/// Grades one student's folder of renders and writes its report, and its
/// CSV when one is asked for.
fn grade_one_student(
    args: &GradeArgs,
    against: Option<&Path>,
    report: &Path,
    csv: Option<&Path>,
) -> Result<i32> {
    let grade = crate::grade::grade(
        &args.folder,
        against,
        args.criteria.criteria(),
        Some(report),
    )?;
    let html = grade.html()?;
    match csv {
        Some(csv) => {
            let single = crate::grade::class::Class::of_one(grade.clone());
            crate::output::write_files(&[
                (report, html.as_bytes()),
                (csv, single.csv().as_bytes()),
            ])?;
        }
        None => write_text_atomic(report, &html)?,
    }
    print!("{}", crate::text::terminal_safe(&grade.markdown(report)));
    Ok(if grade.all_pass() {
        0
    } else {
        EXIT_FAILED_CHECK
    })
}

/// The real folders (not links) directly in `folder`.
fn folders_in(folder: &Path) -> Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(folder)
        .with_context(|| format!("cannot read the folder {}", folder.display()))?;
    let mut folders = Vec::new();
    for entry in entries {
        let entry =
            entry.with_context(|| format!("cannot read the folder {}", folder.display()))?;
        if entry.file_type().is_ok_and(|kind| kind.is_dir()) {
            folders.push(entry.path());
        }
    }
    Ok(folders)
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

#[cfg(test)]
mod tests {
    use clap::Parser;

    fn scene_chapter(args: &[&str]) -> u8 {
        let cli = super::super::Cli::try_parse_from(args).expect("parses");
        match cli.command {
            super::super::Command::Grade(grade) => grade.scene_chapter(),
            _ => unreachable!("a grade command"),
        }
    }

    /// Pass 17 of issue 41: with `--chapter 6` the hidden scenes rendered
    /// at the last chapter's stage, which a class graded on chapters 1 to
    /// 6 has not written: every student failed them.
    #[test]
    fn hidden_scenes_render_at_the_chapter_graded_up_to() {
        let base = ["raylab", "grade", "class", "--code", "--scene", "s.toml"];
        let with = |extra: &[&'static str]| scene_chapter(&[&base[..], extra].concat());
        assert_eq!(with(&["--chapter", "6"]), 6);
        assert_eq!(with(&["--chapter", "6", "--scene-chapter", "4"]), 4);
        assert_eq!(with(&[]), crate::chapters::LAST_CHAPTER);
    }
}
