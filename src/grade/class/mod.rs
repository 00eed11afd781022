//! Grading a whole class (`raylab grade CLASS/`): one subfolder per student,
//! each graded like a single student's folder, or with `--code` each a
//! student workspace whose `check` is run. One HTML report and one CSV for
//! the class.

mod jobs;
mod report;
mod similar;

pub use jobs::{GradeOptions, Job, RESULT_VERSION, StudentResult, grade_student, merge};
pub(crate) use report::csv_field;
pub use similar::ANSWER_KEY;

use std::path::{Path, PathBuf};

use super::code::{CodeJob, CodeRun, CodeStatus, last_lines, run_check};
use super::{Grade, GradeError, Graded, Ignored, References, chapter_of, folder_error, grade_with};
use crate::chapters::LAST_CHAPTER;
use crate::course::Chapters;
use crate::diff::Criteria;
use report::write_section;
use similar::similar_code;

/// What grading one student gave.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub enum Outcome {
    /// Their renders, graded.
    Renders(Box<Grade>),
    /// Their workspace's `check`, run.
    Code(Box<CodeRun>),
    /// Not graded at all, and why (a symbolic link, no Cargo.toml, ...).
    Refused(String),
}

/// One student of the class.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Student {
    /// The subfolder's name.
    pub name: String,
    #[serde(with = "super::raw_path")]
    pub folder: PathBuf,
    pub outcome: Outcome,
}

/// A graded class.
#[derive(Debug, Clone)]
pub struct Class {
    pub folder: PathBuf,
    pub criteria: Criteria,
    pub students: Vec<Student>,
    /// Entries of the class folder that are not a student's folder.
    pub ignored: Vec<Ignored>,
    /// With `--code`: pairs of students (raylab's answer key among them)
    /// whose chapter files are alike.
    pub similar: Vec<super::similarity::SimilarPair>,
}

/// Why a file of the class folder is not graded.
const NOT_A_STUDENT: &str = "not a student's folder";

/// Why a symbolic link in the class folder is not graded.
pub const LINKED_STUDENT_REFUSED: &str = "a symbolic link; a student's folder must be \
     a real folder inside the class folder (links are never followed)";

/// Whether `folder` holds a class (students' subfolders) rather than one
/// student's renders: no entry is named like a chapter's PNG, and at least
/// one is a folder (or a link to one, which is then refused).
pub fn is_class(folder: &Path) -> Result<bool, GradeError> {
    let mut has_folder = false;
    for entry in read_folder(folder)? {
        let entry = entry.map_err(folder_error(folder))?;
        if chapter_of(&entry.file_name().to_string_lossy()).is_ok() {
            return Ok(false);
        }
        // `path.is_dir()` follows a link: a linked student's folder still
        // makes this a class, and is refused there.
        has_folder |= entry.path().is_dir();
    }
    Ok(has_folder)
}

fn read_folder(folder: &Path) -> Result<std::fs::ReadDir, GradeError> {
    std::fs::read_dir(folder).map_err(folder_error(folder))
}

/// The students' subfolders of `folder`, sorted by name, with links
/// refused, and the other entries (files) listed as ignored. `skip` lists
/// files not to list at all (the report and the CSV).
fn students_in(folder: &Path, skip: &[&Path]) -> Result<(Vec<Student>, Vec<Ignored>), GradeError> {
    let skip: Vec<PathBuf> = skip.iter().filter_map(|p| p.canonicalize().ok()).collect();
    let mut students = Vec::new();
    // Listed by name up to a point, then counted: a class folder of
    // 300,000 other files made a report of 17 MB naming each.
    let mut ignored = super::IgnoredList::default();
    let mut entries = Vec::new();
    for entry in read_folder(folder)? {
        let entry = entry.map_err(folder_error(folder))?;
        if entry.path().canonicalize().is_ok_and(|p| skip.contains(&p)) {
            continue;
        }
        entries.push(entry);
    }
    // In the order of their names, so that which links are listed as
    // students (the first) is the same on any file system.
    entries.sort_by_key(|entry| entry.file_name());
    // Names that would look alike in the report are spelled out, so that
    // an instructor never reads two students' rows as one student's.
    let raw_names: Vec<std::ffi::OsString> = entries.iter().map(|e| e.file_name()).collect();
    let raw_names: Vec<&std::ffi::OsStr> = raw_names.iter().map(|n| n.as_os_str()).collect();
    let shown_names = crate::text::told_apart(&raw_names);
    let mut links = 0;
    for (entry, name) in entries.into_iter().zip(shown_names) {
        let path = entry.path();
        let kind = entry.file_type().map_err(folder_error(folder))?;
        if kind.is_symlink() && links >= super::MOST_IGNORED_LISTED {
            // Past the first, links are listed as other files are: a class
            // folder of 100,000 links made a report of 46 MB.
            ignored.add(Ignored {
                name,
                reason: LINKED_STUDENT_REFUSED.into(),
            });
        } else if kind.is_symlink() {
            // A link could lead to another student's folder, or anywhere:
            // it is never followed.
            links += 1;
            students.push(Student {
                name,
                folder: path,
                outcome: Outcome::Refused(LINKED_STUDENT_REFUSED.into()),
            });
        } else if kind.is_dir() {
            students.push(Student {
                name,
                folder: path,
                outcome: Outcome::Refused(String::new()),
            });
        } else {
            ignored.add(Ignored {
                name,
                reason: NOT_A_STUDENT.into(),
            });
        }
    }
    students.sort_by(|a, b| a.name.cmp(&b.name));
    Ok((
        students,
        ignored.into_list("entries that are not a student's folder"),
    ))
}

/// Grades every student's renders in `folder` (see [`super::grade_with`]),
/// one student at a time: each student's section of the HTML report goes
/// to `sections` as soon as they are graded, with the figures of their
/// failing chapters, and their images are then dropped. What the class
/// keeps is a few numbers a chapter: its memory does not grow with the
/// images. [`Class::write_html`] puts the report together.
pub fn grade_class<R: Chapters>(
    folder: &Path,
    references: &mut References<R>,
    criteria: Criteria,
    skip: &[&Path],
    sections: &mut dyn std::io::Write,
) -> Result<Class, GradeError> {
    let (mut students, ignored) = students_in(folder, skip)?;
    for student in &mut students {
        grade_renders_of(student, references, criteria);
        write_section(sections, student)?;
        if let Outcome::Renders(grade) = &mut student.outcome {
            grade.graded.iter_mut().for_each(Graded::drop_images);
        }
    }
    Ok(Class {
        folder: folder.to_path_buf(),
        criteria,
        students,
        ignored,
        similar: Vec::new(),
    })
}

/// Runs every student workspace's `check` in `folder`, one at a time, each
/// within `timeout`. `progress` hears of each student before their run
/// (runs can be long: the first build of a workspace compiles raylab).
pub fn grade_class_code(
    folder: &Path,
    job: &CodeJob,
    skip: &[&Path],
    progress: &mut dyn FnMut(&str),
    sections: &mut dyn std::io::Write,
) -> Result<Class, GradeError> {
    let (mut students, ignored) = students_in(folder, skip)?;
    for student in &mut students {
        run_code_of(student, job, progress)?;
        write_section(sections, student)?;
        // The full output is in the section now; the class keeps only the
        // lines its summary shows, so that its memory does not grow with
        // every student's failures.
        if let Outcome::Code(run) = &mut student.outcome {
            run.stdout = verdict_summary(&run.stdout);
            run.stderr = last_lines(&run.stderr, SUMMARY_LINES);
        }
    }
    let similar = similar_code(&students)?;
    Ok(Class {
        folder: folder.to_path_buf(),
        criteria: Criteria::default(),
        students,
        ignored,
        similar,
    })
}

/// Grades `student`'s renders, unless the student is refused already.
fn grade_renders_of<R: Chapters>(
    student: &mut Student,
    references: &mut References<R>,
    criteria: Criteria,
) {
    if matches!(&student.outcome, Outcome::Refused(why) if why.is_empty()) {
        student.outcome = match grade_with(&student.folder, references, criteria, None) {
            Ok(grade) => Outcome::Renders(Box::new(grade)),
            Err(error) => Outcome::Refused(format!("{error:#}")),
        };
    }
}

/// Runs `student`'s workspace's check, unless the student is refused
/// already.
fn run_code_of(
    student: &mut Student,
    job: &CodeJob,
    progress: &mut dyn FnMut(&str),
) -> Result<(), GradeError> {
    if !matches!(&student.outcome, Outcome::Refused(why) if why.is_empty()) {
        return Ok(());
    }
    let manifest = student.folder.join("Cargo.toml");
    let is_file = std::fs::symlink_metadata(&manifest).is_ok_and(|m| m.is_file());
    student.outcome = if !is_file {
        Outcome::Refused("not a workspace: no Cargo.toml (make one with raylab new)".into())
    } else {
        progress(&student.name);
        match run_check(&student.folder, job) {
            Ok(run) => Outcome::Code(Box::new(run)),
            Err(error) => Outcome::Refused(format!("{error:#}")),
        }
    };
    Ok(())
}

/// How many lines of a `check`'s output the report and the CSV keep.
const SUMMARY_LINES: usize = 40;

/// The longest reason the overview shows beside a status; the student's
/// section has the rest.
const REASON_CHARACTERS: usize = 160;

/// `reason` cut to [`REASON_CHARACTERS`], marked where it was cut.
fn shortened(reason: &str) -> String {
    let line = reason.lines().next().unwrap_or_default();
    if line.chars().count() <= REASON_CHARACTERS && !reason.contains('\n') {
        return line.to_string();
    }
    let kept: String = line.chars().take(REASON_CHARACTERS).collect();
    format!("{kept} ...")
}

/// The end of a check's verdicts `text` in about [`SUMMARY_LINES`] lines,
/// cut between chapters, never inside one: the summary table at its end
/// and the last chapter's block before it in full, then the blocks before
/// those that fit. The chapters not started are left out first: the table
/// lists them anyway, and thirteen of them would push a failing chapter's
/// call, expected and got out of the lines kept.
fn verdict_summary(text: &str) -> String {
    let blocks: Vec<&str> = text
        .trim_end()
        .split("\n\n")
        .filter(|block| {
            !block
                .lines()
                .nth(1)
                .is_some_and(|line| line.starts_with("  not started:"))
        })
        .collect();
    // The first chapter that failed a case of its own: the later ones
    // that build on it say only that, and would push its details out.
    let first_failure = blocks.iter().position(|block| block.contains("\n    got:"));
    let reserved = first_failure.map_or(0, |at| blocks[at].lines().count() + 1);
    let mut kept = 0;
    let mut lines = reserved;
    for block in blocks.iter().rev() {
        let block_lines = block.lines().count() + 1;
        if kept >= 2 && lines + block_lines > SUMMARY_LINES {
            break;
        }
        kept += 1;
        lines += block_lines;
    }
    let tail = blocks.len() - kept;
    match first_failure {
        Some(at) if at < tail => format!("{}\n\n{}", blocks[at], blocks[tail..].join("\n\n")),
        _ => blocks[tail..].join("\n\n"),
    }
}

impl Student {
    /// Everything graded passes.
    pub fn passes(&self) -> bool {
        match &self.outcome {
            Outcome::Renders(grade) => grade.all_pass(),
            Outcome::Code(run) => {
                run.status == CodeStatus::Pass && run.scenes.iter().all(|scene| scene.passed)
            }
            Outcome::Refused(_) => false,
        }
    }

    /// The student's verdict in a word or two.
    pub fn verdict(&self) -> String {
        match &self.outcome {
            Outcome::Renders(grade) => format!("{} of {LAST_CHAPTER} pass", grade.passed()),
            Outcome::Code(run)
                if run.status == CodeStatus::NotStarted && run.chapters_passed > 0 =>
            {
                format!(
                    "in progress: {} of {LAST_CHAPTER} pass, the rest not started",
                    run.chapters_passed
                )
            }
            // How far a failing student got, beside the word.
            Outcome::Code(run) if run.status == CodeStatus::Fail && run.scenes.is_empty() => {
                format!(
                    "fail: {} of {} pass",
                    run.chapters_passed,
                    if run.chapters.is_empty() {
                        usize::from(LAST_CHAPTER)
                    } else {
                        run.chapters.len()
                    }
                )
            }
            Outcome::Code(run) if !run.scenes.is_empty() => format!(
                "{}; hidden scenes: {} of {} pass",
                Student::status_with_reason(run),
                run.scenes.iter().filter(|scene| scene.passed).count(),
                run.scenes.len()
            ),
            Outcome::Code(run) => Student::status_with_reason(run),
            Outcome::Refused(_) => "refused".to_string(),
        }
    }

    /// A run's status and, where the status alone leaves the instructor
    /// asking why, the reason in a line: "error: stopped by the memory
    /// limit", "timed out after 600 s".
    pub(crate) fn status_with_reason(run: &CodeRun) -> String {
        let reason = match run.status {
            CodeStatus::TimedOut => Some(format!("after {} s", run.timeout.as_secs())),
            CodeStatus::Pass | CodeStatus::Fail | CodeStatus::NotStarted => None,
            CodeStatus::BuildError | CodeStatus::Error => run.reason.clone(),
        };
        match reason {
            Some(reason) => format!("{}: {}", run.status.name(), shortened(&reason)),
            None => run.status.name().to_string(),
        }
    }

    /// What a `--code` run printed that the report shows: the check's
    /// summary table (the end of its output), or the compiler's errors.
    pub(crate) fn code_summary(run: &CodeRun) -> String {
        let mut summary = Student::code_lines(run);
        if let Some(seed) = run.fresh {
            summary = format!("(checkpoints with fresh inputs too, seed {seed})\n{summary}");
        }
        if run.trusted_target {
            summary = format!(
                "(built on the workspace's target/ as it was, --trust-targets: a binary built \
                 from other sources would pass)\n{summary}"
            );
        }
        summary
    }

    /// [`Student::code_summary`] but for the seed's line.
    fn code_lines(run: &CodeRun) -> String {
        match run.status {
            CodeStatus::TimedOut => {
                let mut text = format!(
                    "timed out after {} s; every process of the run was killed",
                    run.timeout.as_secs()
                );
                let out = verdict_summary(&run.stdout);
                if !out.is_empty() {
                    text.push_str("\noutput so far:\n");
                    text.push_str(&out);
                }
                text
            }
            // A build error's why is on stderr (the compiler's errors, a
            // build script's output), whatever note its stdout holds: a
            // note that the code is not counted also ends stderr.
            CodeStatus::BuildError => last_lines(&run.stderr, SUMMARY_LINES),
            CodeStatus::Error if run.stdout.trim().is_empty() => {
                last_lines(&run.stderr, SUMMARY_LINES)
            }
            CodeStatus::Error => format!(
                "{}\n{}",
                verdict_summary(&run.stdout),
                last_lines(&run.stderr, 10)
            ),
            _ => verdict_summary(&run.stdout),
        }
    }
}

impl Class {
    /// One student's grade as a class of one (for the CSV of `raylab grade
    /// DIR --csv FILE`), named after the folder.
    pub fn of_one(grade: Grade) -> Class {
        let name = grade
            .folder
            .file_name()
            .map(|name| name.to_string_lossy().into_owned())
            .unwrap_or_else(|| grade.folder.display().to_string());
        Class {
            folder: grade.folder.clone(),
            criteria: grade.criteria,
            students: vec![Student {
                name,
                folder: grade.folder.clone(),
                outcome: Outcome::Renders(Box::new(grade)),
            }],
            ignored: Vec::new(),
            similar: Vec::new(),
        }
    }

    pub fn all_pass(&self) -> bool {
        !self.students.is_empty() && self.students.iter().all(Student::passes)
    }

    pub fn passed(&self) -> usize {
        self.students.iter().filter(|s| s.passes()).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pass 16 of issue 41: 300,000 files beside the students made a
    /// report of 17 MB naming each. The first are named, the rest counted.
    #[test]
    fn a_class_folder_of_many_other_files_names_the_first_and_counts_the_rest() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        std::fs::create_dir(dir.path().join("amy")).expect("a student");
        for index in 0..120 {
            std::fs::write(dir.path().join(format!("junk-{index:03}")), "").expect("a file");
        }
        let (students, ignored) = students_in(dir.path(), &[]).expect("read");
        assert_eq!(students.len(), 1);
        assert_eq!(ignored.len(), 51, "{ignored:?}");
        assert_eq!(ignored[0].name, "junk-000");
        assert_eq!(ignored[0].reason, NOT_A_STUDENT);
        assert_eq!(ignored[50].name, "70 more");
        // Symbolic links: the first 50 are refused students, the rest are
        // counted with the other files.
        for index in 0..80 {
            std::os::unix::fs::symlink("amy", dir.path().join(format!("link-{index:03}")))
                .expect("a link");
        }
        let (students, ignored) = students_in(dir.path(), &[]).expect("read");
        assert_eq!(students.len(), 51);
        assert_eq!(ignored.len(), 51, "{ignored:?}");
        assert_eq!(ignored[50].name, "100 more");
    }

    /// A run of `status` that printed `stdout` and `stderr`, nothing else.
    fn code_run(status: CodeStatus, stdout: &str, stderr: &str) -> CodeRun {
        CodeRun {
            status,
            exit_code: Some(0),
            stdout: stdout.to_string(),
            stderr: stderr.to_string(),
            timeout: std::time::Duration::from_secs(600),
            chapters_passed: 0,
            scenes: Vec::new(),
            fresh: None,
            trusted_target: false,
            sources: Vec::new(),
            limits: Vec::new(),
            reason: None,
            chapters: Vec::new(),
        }
    }

    /// A failing chapter's details survive a class of not-started ones:
    /// the table lists those, and their blocks go first.
    #[test]
    fn the_summary_keeps_a_failing_chapters_details_over_not_started_ones() {
        let mut text = String::from(
            "chapter 1: Ray-plane intersection - FAIL\n  checkpoints: 12 of 17 pass\n  \
             checkpoint 10 of 17 failed (intersect_plane: plane-beyond-t-max):\n    \
             call:     intersect_plane(...)\n    expected: no hit (None)\n    got:      t = 1\n\n",
        );
        for chapter in 2..=14 {
            text.push_str(&format!(
                "chapter {chapter}: Title - not started\n  not started: f still todo!() (the \
                 lesson: l.md)\n\n"
            ));
        }
        text.push_str("chapter  status       cases   robustness     image\n");
        for chapter in 1..=14 {
            text.push_str(&format!(
                "{chapter:<8} not started  -       -              -\n"
            ));
        }
        assert!(!last_lines(&text, SUMMARY_LINES).contains("expected: no hit"));
        let summary = verdict_summary(&text);
        assert!(summary.contains("expected: no hit (None)"), "{summary}");
        assert!(summary.contains("got:      t = 1"), "{summary}");
        assert!(
            summary.ends_with("14       not started  -       -              -"),
            "{summary}"
        );
        assert!(!summary.contains("still todo!()"), "{summary}");
        assert_eq!(verdict_summary(&summary), summary);
    }

    /// The first chapter that failed a case of its own keeps its details
    /// ahead of the later chapters that only build on it (a Phong bug
    /// fails chapters 5 to 14, and only chapter 5 says why).
    #[test]
    fn the_summary_keeps_the_first_failing_chapters_details() {
        let mut text = String::from(
            "chapter 5: Phong - FAIL\n  checkpoints: 3 of 11 pass\n  checkpoint 4 of 11 \
             failed (phong_terms: spec):\n    call:     phong_terms(...)\n    expected: \
             specular 0.5\n    got:      specular 0.25\n\n",
        );
        for chapter in 6..=14 {
            text.push_str(&format!("chapter {chapter}: Title - FAIL\n"));
            for line in 1..=4 {
                text.push_str(&format!(
                    "  builds on chapter 5, which is failing ({line})\n"
                ));
            }
            text.push('\n');
        }
        text.push_str("chapter  status\n5        FAIL\n");
        let summary = verdict_summary(&text);
        assert!(summary.starts_with("chapter 5: Phong - FAIL"), "{summary}");
        assert!(summary.contains("got:      specular 0.25"), "{summary}");
        assert!(summary.ends_with("5        FAIL"), "{summary}");
        assert!(summary.lines().count() <= SUMMARY_LINES + 1, "{summary}");
        assert_eq!(verdict_summary(&summary), summary);
    }

    /// A run built on the workspace's `target/` as it was says so in the
    /// report, and jobs graded with and without `--trust-targets` do not
    /// merge: a binary built from other sources passes under it.
    #[test]
    fn trusting_the_workspaces_targets_is_said_and_never_merged_silently() {
        let trusted = CodeRun {
            trusted_target: true,
            ..code_run(CodeStatus::Pass, "chapter 1: Plane - pass\n", "")
        };
        assert!(
            Student::code_summary(&trusted)
                .starts_with("(built on the workspace's target/ as it was, --trust-targets"),
            "{}",
            Student::code_summary(&trusted)
        );
        let plain = code_run(CodeStatus::Pass, "chapter 1: Plane - pass\n", "");
        assert!(!Student::code_summary(&plain).contains("--trust-targets"));
        let job = super::super::code::CodeJob {
            timeout: std::time::Duration::from_secs(60),
            sandbox: None,
            fresh: None,
            chapter: None,
            profile: super::super::code::BuildProfile::Dev,
            scenes: &[],
        };
        let options = GradeOptions::code(&job, &[], 14);
        let trusting = GradeOptions {
            trusted_targets: Some(true),
            ..options.clone()
        };
        assert_eq!(options.differences(&trusting), ["--trust-targets"]);
        assert!(options.differences(&options).is_empty());
    }

    /// A failing student's verdict says how many chapters pass.
    #[test]
    fn a_failing_students_verdict_counts_the_chapters_that_pass() {
        let run = CodeRun {
            chapters_passed: 4,
            ..code_run(CodeStatus::Fail, "", "")
        };
        let student = Student {
            name: "carol".into(),
            folder: PathBuf::from("carol"),
            outcome: Outcome::Code(Box::new(run)),
        };
        assert_eq!(student.verdict(), format!("fail: 4 of {LAST_CHAPTER} pass"));
    }

    /// A build that failed in a build script, which is not counted: its
    /// summary shows what cargo wrote on stderr (the script's own
    /// output), not only the note that the code is not counted.
    #[test]
    fn a_build_error_shows_its_stderr_beside_a_note_on_stdout() {
        let note = "not counted: the workspace has a build script, build.rs.";
        let run = CodeRun {
            exit_code: Some(101),
            ..code_run(
                CodeStatus::BuildError,
                &format!("\n{note}"),
                &format!(
                    "error: failed to run custom build command for `ann`\n\nCaused by:\n  \
                     --- stderr\n  the build script says why\n\n{note}"
                ),
            )
        };
        let summary = Student::code_summary(&run);
        assert!(summary.contains("the build script says why"), "{summary}");
        assert!(summary.contains(note), "{summary}");
    }

    /// The summary starts at a chapter's first line: a chapter that does
    /// not fit is left out whole, not cut in the middle.
    #[test]
    fn the_summary_starts_at_a_chapter_boundary() {
        let mut text = String::new();
        for chapter in 1..=6 {
            text.push_str(&format!("chapter {chapter}: Title - FAIL\n"));
            for case in 1..=12 {
                text.push_str(&format!("  checkpoint {case} failed\n"));
            }
            text.push('\n');
        }
        text.push_str("chapter  status\n1        fail\n");
        let summary = verdict_summary(&text);
        assert!(summary.starts_with("chapter "), "{summary}");
        assert!(summary.contains("chapter 6: Title - FAIL"), "{summary}");
        assert!(summary.ends_with("1        fail"), "{summary}");
        assert!(summary.lines().count() <= SUMMARY_LINES, "{summary}");
        let alone = "chapter 1: Title - FAIL\n".to_string()
            + &"  line\n".repeat(2 * SUMMARY_LINES)
            + "\nchapter  status\n";
        assert!(
            verdict_summary(&alone).starts_with("chapter 1: Title - FAIL"),
            "a chapter longer than the summary is kept whole"
        );
    }
}
