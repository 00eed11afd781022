//! Grading a whole class (`raylab grade CLASS/`): one subfolder per student,
//! each graded like a single student's folder, or with `--code` each a
//! student workspace whose `check` is run. One HTML report and one CSV for
//! the class.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::code::{CodeJob, CodeRun, CodeStatus, last_lines, run_check};
use super::{
    Grade, GradeError, Graded, Ignored, References, STYLE, chapter_of, folder_error, grade_with,
    html_escape, markdown_escape,
};
use crate::chapters::LAST_CHAPTER;
use crate::course::Chapters;
use crate::diff::{Criteria, psnr_text};

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
    let mut ignored = Vec::new();
    for entry in read_folder(folder)? {
        let entry = entry.map_err(folder_error(folder))?;
        let path = entry.path();
        let name = crate::text::visible_name(&entry.file_name());
        if path.canonicalize().is_ok_and(|p| skip.contains(&p)) {
            continue;
        }
        let kind = entry.file_type().map_err(folder_error(folder))?;
        if kind.is_symlink() {
            // A link could lead to another student's folder, or anywhere:
            // it is never followed.
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
            ignored.push(Ignored {
                name,
                reason: "not a student's folder".into(),
            });
        }
    }
    students.sort_by(|a, b| a.name.cmp(&b.name));
    ignored.sort_by(|a, b| a.name.cmp(&b.name));
    Ok((students, ignored))
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

/// Everything that decides how a class's students are graded. Each job of
/// a class spread over machines stores it in its result file, and
/// [`merge`] refuses a result whose options differ from its own: a class is
/// merged from one grading, whatever option the jobs were run with.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GradeOptions {
    /// `--code`: the workspaces' checks, not their renders.
    pub code: bool,
    /// When two images count as the same (renders; the default with
    /// `--code`, whose hidden scenes use it).
    pub criteria: Criteria,
    /// `--against`: each reference PNG by name, with the CRC-32 of its
    /// bytes.
    pub against: Option<Vec<(String, u32)>>,
    /// The seed of `--fresh`, when the code was checked with fresh inputs.
    pub fresh: Option<u64>,
    /// The last chapter checked (`--chapter`), when not every one was.
    pub chapter: Option<u8>,
    /// `--timeout`, in seconds (with `--code`).
    pub timeout_seconds: Option<u64>,
    /// Whether the students' code ran in the sandbox (with `--code`).
    pub sandboxed: Option<bool>,
    /// The cargo profile the workspaces were built with (with `--code`).
    pub profile: Option<String>,
    /// The hidden scenes (`--scene`), each by name with the CRC-32 of its
    /// text, and the chapter that renders them.
    pub scenes: Vec<(String, u32)>,
    pub scene_chapter: Option<u8>,
}

impl GradeOptions {
    /// The options of a grading of renders.
    pub fn renders(criteria: Criteria, against: Option<&Path>) -> Result<GradeOptions, GradeError> {
        let against = match against {
            Some(folder) => {
                let mut files = Vec::new();
                for chapter in crate::chapters::CHAPTERS {
                    let name = format!("chapter-{}.png", chapter.number);
                    let path = folder.join(&name);
                    if path.is_file() {
                        let bytes = crate::input::read_bounded(
                            &path,
                            crate::input::MAX_PNG_FILE_BYTES,
                            "reference image",
                            crate::input::Links::Refuse,
                        )?;
                        files.push((name, crc32fast::hash(&bytes)));
                    }
                }
                Some(files)
            }
            None => None,
        };
        Ok(GradeOptions {
            code: false,
            criteria,
            against,
            fresh: None,
            chapter: None,
            timeout_seconds: None,
            sandboxed: None,
            profile: None,
            scenes: Vec::new(),
            scene_chapter: None,
        })
    }

    /// The options of a grading of code by `job`, its hidden scenes read
    /// from `scene_files` (as [`super::hidden::texts`] gives them).
    pub fn code(
        job: &CodeJob,
        scene_files: &[(PathBuf, String, String)],
        scene_chapter: u8,
    ) -> GradeOptions {
        GradeOptions {
            code: true,
            criteria: Criteria::default(),
            against: None,
            fresh: job.fresh,
            chapter: job.chapter,
            timeout_seconds: Some(job.timeout.as_secs()),
            sandboxed: Some(job.sandbox.is_some()),
            profile: Some(job.profile.name().to_string()),
            scenes: scene_files
                .iter()
                .map(|(_, name, text)| (name.clone(), crc32fast::hash(text.as_bytes())))
                .collect(),
            scene_chapter: (!scene_files.is_empty()).then_some(scene_chapter),
        }
    }

    /// The options on which `self` and `other` differ, by name, as the
    /// command line spells them.
    pub fn differences(&self, other: &GradeOptions) -> Vec<&'static str> {
        let mut differ = Vec::new();
        let mut check = |same: bool, name| {
            if !same {
                differ.push(name)
            }
        };
        check(self.code == other.code, "--code");
        check(self.criteria == other.criteria, "--threshold/--allow");
        check(self.against == other.against, "--against");
        check(self.fresh == other.fresh, "--fresh");
        check(self.chapter == other.chapter, "--chapter");
        check(self.timeout_seconds == other.timeout_seconds, "--timeout");
        check(self.sandboxed == other.sandboxed, "--no-sandbox");
        check(self.profile == other.profile, "--build-profile");
        check(self.scenes == other.scenes, "--scene");
        check(self.scene_chapter == other.scene_chapter, "--scene-chapter");
        differ
    }
}

/// What grading one student of a class gives, as one job of a class
/// spread over machines (`raylab grade CLASS --student NAME --result
/// FILE`): the student, their images dropped, and their section of the
/// report, figures included. [`merge`] builds the class's report from
/// these, the same as one `grade` run of the whole class.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct StudentResult {
    /// The version of this file's layout.
    pub raylab_grade_result: u32,
    /// How the student was graded.
    pub options: GradeOptions,
    pub student: Student,
    pub section: String,
}

/// The layout of [`StudentResult`] this raylab writes and reads.
pub const RESULT_VERSION: u32 = 2;

/// How a job grades its student: their renders against `references`, or
/// their workspace's check.
pub enum Job<'a, R: Chapters> {
    Renders(&'a mut References<R>),
    Code(CodeJob<'a>),
}

/// Grades the student of the class in `folder` whose folder is `name`
/// (as the file system has it, or as the report shows it, escaped) alone.
pub fn grade_student<R: Chapters>(
    folder: &Path,
    name: &std::ffi::OsStr,
    job: Job<'_, R>,
    options: &GradeOptions,
    skip: &[&Path],
) -> Result<StudentResult, GradeError> {
    let (students, _) = students_in(folder, skip)?;
    let shown = crate::text::visible_name(name);
    let mut student = students
        .into_iter()
        .find(|student| student.name == shown || name.to_str() == Some(student.name.as_str()))
        .ok_or_else(|| GradeError::NoSuchStudent {
            name: shown,
            folder: folder.to_path_buf(),
        })?;
    match job {
        Job::Renders(references) => grade_renders_of(&mut student, references, options.criteria),
        Job::Code(job) => run_code_of(&mut student, &job, &mut |_| {})?,
    }
    let mut section = String::new();
    student_section_html(&mut section, &student)?;
    if let Outcome::Renders(grade) = &mut student.outcome {
        grade.graded.iter_mut().for_each(Graded::drop_images);
    }
    Ok(StudentResult {
        raylab_grade_result: RESULT_VERSION,
        options: options.clone(),
        student,
        section,
    })
}

/// The class in `folder` from its jobs' `results`: every student of the
/// folder, in the order of their names, each with their result (a student
/// with none is refused: "no result"), and their sections written to
/// `sections`. Results of students not in the folder, twice the same
/// student, or graded with other [`GradeOptions`] than `options` are
/// errors: a class is merged from one grading.
pub fn merge(
    folder: &Path,
    results: Vec<StudentResult>,
    options: &GradeOptions,
    skip: &[&Path],
    sections: &mut dyn std::io::Write,
) -> Result<Class, GradeError> {
    let (mut students, ignored) = students_in(folder, skip)?;
    let code = options.code;
    let criteria = options.criteria;
    let mut by_name = std::collections::BTreeMap::new();
    for result in results {
        let name = result.student.name.clone();
        if result.raylab_grade_result != RESULT_VERSION {
            return Err(GradeError::MergeMismatch {
                name,
                why: format!(
                    "its result file's layout is version {}, this raylab's {RESULT_VERSION}",
                    result.raylab_grade_result
                ),
            });
        }
        let differ = result.options.differences(options);
        if !differ.is_empty() {
            return Err(GradeError::MergeMismatch {
                name,
                why: format!("it was graded with other {}", differ.join(", ")),
            });
        }
        if !students.iter().any(|student| student.name == name) {
            return Err(GradeError::NoSuchStudent {
                name,
                folder: folder.to_path_buf(),
            });
        }
        if by_name.insert(name.clone(), result).is_some() {
            return Err(GradeError::MergeTwice { name });
        }
    }
    for student in &mut students {
        match by_name.remove(&student.name) {
            Some(result) => {
                *student = result.student;
                sections
                    .write_all(result.section.as_bytes())
                    .map_err(GradeError::Staging)?;
            }
            None => {
                student.outcome = Outcome::Refused(
                    "no result: this student's grading job wrote no result file".into(),
                );
                write_section(sections, student)?;
            }
        }
    }
    let similar = if code {
        similar_code(&students)?
    } else {
        Vec::new()
    };
    Ok(Class {
        folder: folder.to_path_buf(),
        criteria,
        students,
        ignored,
        similar,
    })
}

/// The HTML anchor of a student's section: from their name alone, so that
/// a job grading one student writes the same section as a run of the class.
fn anchor(name: &str) -> String {
    format!("student-{:016x}", crate::output::fnv1a64(name.bytes()))
}

/// The name raylab's answer key goes by in the similarity report.
pub const ANSWER_KEY: &str = "raylab's answer key";

/// The largest chapter file read for the similarity report.
const MAX_CHAPTER_FILE_BYTES: u64 = 1 << 20;

/// The pairs of workspaces (and raylab's answer key) whose chapter files
/// are alike, skeleton aside (see [`super::similarity`]).
fn similar_code(students: &[Student]) -> Result<Vec<super::similarity::SimilarPair>, GradeError> {
    use super::similarity::{Fingerprints, Submission, fingerprints};
    let raylab = Path::new(env!("CARGO_MANIFEST_DIR"));
    let skeleton = crate::workspace::files("student", raylab, false);
    let answers = crate::workspace::files("student", raylab, true);
    let (Ok(skeleton), Ok(answers)) = (skeleton, answers) else {
        return Ok(Vec::new());
    };
    let path = |info: &crate::chapters::ChapterInfo| format!("src/chapters/{}.rs", info.module());
    let base: Vec<(u8, Fingerprints)> = crate::chapters::CHAPTERS
        .iter()
        .map(|info| {
            let prints = skeleton
                .get(&path(info))
                .and_then(|text| fingerprints(text).ok())
                .unwrap_or_default();
            (info.number, prints)
        })
        .collect();
    let skeleton_of = |chapter: u8| {
        base.iter()
            .find(|(c, _)| *c == chapter)
            .map(|(_, prints)| prints.clone())
            .unwrap_or_default()
    };
    let mut submissions = vec![Submission::new(
        ANSWER_KEY,
        crate::chapters::CHAPTERS
            .iter()
            .filter_map(|info| Some((info.number, answers.get(&path(info))?.to_string())))
            .collect(),
        &skeleton_of,
    )];
    for student in students {
        if !matches!(student.outcome, Outcome::Code(_)) {
            continue;
        }
        let files = crate::chapters::CHAPTERS
            .iter()
            .filter_map(|info| {
                let bytes = crate::input::read_bounded(
                    &student.folder.join(path(info)),
                    MAX_CHAPTER_FILE_BYTES,
                    "chapter file",
                    crate::input::Links::Refuse,
                )
                .ok()?;
                Some((info.number, String::from_utf8(bytes).ok()?))
            })
            .collect();
        submissions.push(Submission::new(&student.name, files, &skeleton_of));
    }
    Ok(super::similarity::similar_pairs(&submissions))
}

/// Writes `student`'s section of the class report to `sections`.
fn write_section(sections: &mut dyn std::io::Write, student: &Student) -> Result<(), GradeError> {
    let mut section = String::new();
    student_section_html(&mut section, student)?;
    sections
        .write_all(section.as_bytes())
        .map_err(GradeError::Staging)
}

/// A chapter's status in a student's grade: `pass`, `fail`, `missing` or
/// `unreadable`, with the grading if there is one, or the reason.
enum ChapterStatus<'a> {
    Graded(&'a Graded),
    Missing,
    Unreadable(&'a str),
}

fn chapter_status(grade: &Grade, chapter: u8) -> ChapterStatus<'_> {
    if let Some(graded) = grade.graded.iter().find(|g| g.chapter == chapter) {
        ChapterStatus::Graded(graded)
    } else if let Some(unreadable) = grade.unreadable.iter().find(|u| u.chapter == chapter) {
        ChapterStatus::Unreadable(&unreadable.reason)
    } else {
        ChapterStatus::Missing
    }
}

impl ChapterStatus<'_> {
    fn name(&self) -> &'static str {
        match self {
            ChapterStatus::Graded(g) if g.passes() => "pass",
            ChapterStatus::Graded(_) => "fail",
            ChapterStatus::Missing => "missing",
            ChapterStatus::Unreadable(_) => "unreadable",
        }
    }
}

/// How many lines of a `check`'s output the report and the CSV keep.
const SUMMARY_LINES: usize = 40;

/// The last [`SUMMARY_LINES`] lines of a check's verdicts `text`, its
/// chapters not started left out first: the table at its end lists them
/// anyway, and thirteen of them would push a failing chapter's call,
/// expected and got out of the lines kept.
fn verdict_summary(text: &str) -> String {
    let blocks: Vec<&str> = text
        .split("\n\n")
        .filter(|block| {
            !block
                .lines()
                .nth(1)
                .is_some_and(|line| line.starts_with("  not started:"))
        })
        .collect();
    last_lines(&blocks.join("\n\n"), SUMMARY_LINES)
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
            Outcome::Code(run) if !run.scenes.is_empty() => format!(
                "{}; hidden scenes: {} of {} pass",
                run.status.name(),
                run.scenes.iter().filter(|scene| scene.passed).count(),
                run.scenes.len()
            ),
            Outcome::Code(run) => run.status.name().to_string(),
            Outcome::Refused(_) => "refused".to_string(),
        }
    }

    /// What a `--code` run printed that the report shows: the check's
    /// summary table (the end of its output), or the compiler's errors.
    fn code_summary(run: &CodeRun) -> String {
        let summary = Student::code_lines(run);
        match run.fresh {
            Some(seed) => format!("(checkpoints with fresh inputs too, seed {seed})\n{summary}"),
            None => summary,
        }
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
            CodeStatus::BuildError | CodeStatus::Error if run.stdout.trim().is_empty() => {
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

    /// One row per student and chapter (per student with `--code`, chapter
    /// `all`): student, chapter, status, then the metrics of a comparison.
    pub fn csv(&self) -> String {
        let mut csv = String::from(
            "student,chapter,status,max,mean,rmse,psnr_db,pixels_over,percent_over,size,detail\n",
        );
        let mut row = |fields: &[String]| {
            let cells: Vec<String> = fields.iter().map(|f| csv_field(f)).collect();
            csv.push_str(&cells.join(","));
            csv.push('\n');
        };
        for student in &self.students {
            let name = student.name.clone();
            let blank = || vec![String::new(); 7];
            match &student.outcome {
                Outcome::Refused(why) => {
                    let mut fields = vec![name, "all".into(), "refused".into()];
                    fields.extend(blank());
                    fields.push(why.clone());
                    row(&fields);
                }
                Outcome::Code(run) => {
                    let mut fields = vec![name.clone(), "all".into(), run.status.name().into()];
                    fields.extend(blank());
                    fields.push(Student::code_summary(run));
                    row(&fields);
                    for scene in &run.scenes {
                        let mut fields = vec![
                            name.clone(),
                            format!("scene:{}", scene.name),
                            if scene.passed { "pass" } else { "fail" }.into(),
                        ];
                        match &scene.metrics {
                            Some(m) => fields.extend([
                                m.max.to_string(),
                                format!("{:.6}", m.mean),
                                format!("{:.6}", m.rmse),
                                psnr_text(m.psnr_db),
                                m.pixels_over.to_string(),
                                format!("{:.4}", m.percent_over()),
                                format!("{}x{}", m.width, m.height),
                            ]),
                            None => fields.extend(blank()),
                        }
                        fields.push(scene.detail.clone());
                        row(&fields);
                    }
                }
                Outcome::Renders(grade) => {
                    for chapter in 1..=LAST_CHAPTER {
                        let status = chapter_status(grade, chapter);
                        let mut fields =
                            vec![name.clone(), chapter.to_string(), status.name().into()];
                        match &status {
                            ChapterStatus::Graded(g) => {
                                let m = &g.comparison.metrics;
                                fields.extend([
                                    m.max.to_string(),
                                    format!("{:.6}", m.mean),
                                    format!("{:.6}", m.rmse),
                                    psnr_text(m.psnr_db),
                                    m.pixels_over.to_string(),
                                    format!("{:.4}", m.percent_over()),
                                    format!("{}x{}", m.width, m.height),
                                    g.reference_source.clone(),
                                ]);
                            }
                            ChapterStatus::Missing => {
                                fields.extend(blank());
                                fields.push(grade.missing_detail(chapter));
                            }
                            ChapterStatus::Unreadable(why) => {
                                fields.extend(blank());
                                fields.push((*why).to_string());
                            }
                        }
                        row(&fields);
                    }
                }
            }
        }
        csv
    }

    /// The Markdown summary printed by `raylab grade CLASS/`.
    pub fn markdown(&self, report: &Path, csv: &Path) -> String {
        let mut md = String::new();
        let _ = writeln!(
            md,
            "# raylab grade: {} (a class)\n",
            markdown_escape(&self.folder.display().to_string())
        );
        let code = self
            .students
            .iter()
            .any(|s| matches!(s.outcome, Outcome::Code(_)));
        if code {
            md.push_str("| student | result |\n|---|---|\n");
        } else {
            md.push_str("| student |");
            for chapter in 1..=LAST_CHAPTER {
                let _ = write!(md, " {chapter} |");
            }
            md.push_str(" result |\n|---|");
            for _ in 1..=LAST_CHAPTER {
                md.push_str("---|");
            }
            md.push_str("---|\n");
        }
        for student in &self.students {
            let _ = write!(md, "| {} |", markdown_escape(&student.name));
            if let Outcome::Renders(grade) = &student.outcome {
                for chapter in 1..=LAST_CHAPTER {
                    let status = chapter_status(grade, chapter).name();
                    let _ = write!(
                        md,
                        " {} |",
                        if status == "fail" { "**fail**" } else { status }
                    );
                }
            } else if !code {
                for _ in 1..=LAST_CHAPTER {
                    md.push_str(" |");
                }
            }
            let verdict = match &student.outcome {
                Outcome::Refused(why) => format!("refused: {}", markdown_escape(why)),
                _ => student.verdict(),
            };
            let _ = writeln!(md, " {verdict} |");
        }
        md.push('\n');
        if !self.ignored.is_empty() {
            md.push_str("Ignored:\n");
            for i in &self.ignored {
                let _ = writeln!(
                    md,
                    "- {}: {}",
                    markdown_escape(&i.name),
                    markdown_escape(&i.reason)
                );
            }
            md.push('\n');
        }
        if !self.similar.is_empty() {
            md.push_str("Similar code (token k-grams, winnowed; skeleton excluded):\n");
            for pair in &self.similar {
                let _ = writeln!(
                    md,
                    "- chapter {}: {} and {}, {:.0}% alike",
                    pair.chapter,
                    markdown_escape(&pair.first),
                    markdown_escape(&pair.second),
                    100.0 * pair.similarity
                );
            }
            md.push('\n');
        }
        let _ = writeln!(
            md,
            "**{} of {} students pass everything.** Report: {}; CSV: {}",
            self.passed(),
            self.students.len(),
            markdown_escape(&report.display().to_string()),
            markdown_escape(&csv.display().to_string())
        );
        md
    }

    /// The self-contained HTML report: an overview, then one section per
    /// student. Images are inlined only for the chapters that fail (the
    /// student's, the reference, the heatmap); a passing chapter is one row
    /// of figures, so that the report of a class of 30 at 640x480 stays a
    /// few megabytes instead of a few hundred.
    pub fn html(&self) -> Result<String, GradeError> {
        let mut h = self.html_head();
        for student in &self.students {
            student_section_html(&mut h, student)?;
        }
        h.push_str(HTML_TAIL);
        Ok(h)
    }

    /// The report of a class graded by [`grade_class`] or
    /// [`grade_class_code`], whose students' sections are in `sections`
    /// (what they wrote there, from its start), streamed into `out`.
    pub fn write_html(
        &self,
        out: &mut dyn std::io::Write,
        sections: &mut dyn std::io::Read,
    ) -> std::io::Result<()> {
        out.write_all(self.html_head().as_bytes())?;
        std::io::copy(sections, out)?;
        out.write_all(HTML_TAIL.as_bytes())
    }

    /// The report up to the students' sections: the overview.
    fn html_head(&self) -> String {
        let mut h = String::new();
        let title = format!("raylab grade: {} (a class)", self.folder.display());
        let _ = write!(
            h,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n<h1>{}</h1>\n",
            html_escape(&title),
            html_escape(&title)
        );
        let _ = writeln!(
            h,
            "<p class=\"verdict {}\"><strong>{} of {} students pass everything.</strong></p>",
            if self.all_pass() { "pass" } else { "fail" },
            self.passed(),
            self.students.len()
        );
        let code = self
            .students
            .iter()
            .any(|s| matches!(s.outcome, Outcome::Code(_)));
        if !code {
            let c = &self.criteria;
            let _ = writeln!(
                h,
                "<p>A pixel is <em>over</em> when one of its R, G, B values differs from the reference by more than {} levels (of 255); a chapter passes when {}.</p>",
                c.threshold,
                super::allowance_text(c)
            );
        }
        self.html_summary_table(&mut h, code);
        self.html_ignored(&mut h);
        self.html_similar(&mut h);
        h
    }

    /// The pairs of similar chapter files, their shared passages side by
    /// side.
    fn html_similar(&self, h: &mut String) {
        if self.similar.is_empty() {
            return;
        }
        let _ = writeln!(
            h,
            "<section class=\"problems\">\n<h2>Similar code</h2>\n<p>Pairs whose chapter file shares at least {:.0}% of its fingerprints with the other's (token {}-grams winnowed over windows of {}, names and literals ignored, the workspace skeleton excluded): read them before concluding anything.</p>",
            100.0 * super::similarity::REPORTED,
            super::similarity::K,
            super::similarity::WINDOW
        );
        for pair in &self.similar {
            let _ = writeln!(
                h,
                "<h3>Chapter {}: {} and {}, {:.0}% alike</h3>\n<table>\n<tr><th>{}</th><th>{}</th></tr>",
                pair.chapter,
                html_escape(&pair.first),
                html_escape(&pair.second),
                100.0 * pair.similarity,
                html_escape(&pair.first),
                html_escape(&pair.second)
            );
            for (first, second) in &pair.passages {
                let _ = writeln!(
                    h,
                    "<tr><td><pre>line {}\n{}</pre></td><td><pre>line {}\n{}</pre></td></tr>",
                    first.line,
                    html_escape(&first.text),
                    second.line,
                    html_escape(&second.text)
                );
            }
            h.push_str("</table>\n");
        }
        h.push_str("</section>\n");
    }

    /// The overview: one row per student, with a column per chapter unless
    /// the class handed in code (`code`), linked to their sections.
    fn html_summary_table(&self, h: &mut String, code: bool) {
        h.push_str("<table class=\"summary\">\n<tr><th>student</th>");
        if !code {
            for chapter in 1..=LAST_CHAPTER {
                let _ = write!(h, "<th>{chapter}</th>");
            }
        }
        h.push_str("<th>result</th></tr>\n");
        for student in &self.students {
            let _ = write!(
                h,
                "<tr><td><a href=\"#{}\">{}</a></td>",
                anchor(&student.name),
                html_escape(&student.name)
            );
            if !code {
                for chapter in 1..=LAST_CHAPTER {
                    match &student.outcome {
                        Outcome::Renders(grade) => {
                            let status = chapter_status(grade, chapter).name();
                            let class = if status == "pass" { "pass" } else { "fail" };
                            let _ = write!(h, "<td class=\"{class}\">{status}</td>");
                        }
                        _ => h.push_str("<td></td>"),
                    }
                }
            }
            let _ = writeln!(
                h,
                "<td class=\"{}\">{}</td></tr>",
                if student.passes() { "pass" } else { "fail" },
                html_escape(&student.verdict())
            );
        }
        h.push_str("</table>\n");
    }

    /// The entries of the class folder that are not students, if any.
    fn html_ignored(&self, h: &mut String) {
        if !self.ignored.is_empty() {
            h.push_str("<section class=\"problems\">\n<p><strong>Ignored:</strong></p>\n<ul>\n");
            for i in &self.ignored {
                let _ = writeln!(
                    h,
                    "<li><code>{}</code>: {}</li>",
                    html_escape(&i.name),
                    html_escape(&i.reason)
                );
            }
            h.push_str("</ul>\n</section>\n");
        }
    }
}

const HTML_TAIL: &str = "</body>\n</html>\n";

/// One student's section of the class report: why they were refused, their
/// code's check run, or their chapters.
fn student_section_html(h: &mut String, student: &Student) -> Result<(), GradeError> {
    let _ = writeln!(
        h,
        "<section class=\"chapter {}\" id=\"{}\">\n<h2>{} <span class=\"badge\">{}</span></h2>",
        if student.passes() { "pass" } else { "fail" },
        anchor(&student.name),
        html_escape(&student.name),
        html_escape(&student.verdict())
    );
    match &student.outcome {
        Outcome::Refused(why) => {
            let _ = writeln!(h, "<p>{}</p>", html_escape(why));
        }
        Outcome::Code(run) => {
            let exit = run
                .exit_code
                .map(|code| format!("exit status {code}"))
                .unwrap_or_else(|| "no exit status".into());
            let _ = writeln!(
                h,
                "<p><code>cargo run --release --offline -- check</code>: {}, {}</p>\n<pre>{}</pre>",
                html_escape(run.status.name()),
                html_escape(&exit),
                html_escape(&Student::code_summary(run))
            );
            if !run.scenes.is_empty() {
                h.push_str("<table>\n<tr><th>hidden scene</th><th>result</th><th>max</th><th>PSNR (dB)</th><th>pixels over</th><th>detail</th></tr>\n");
                for scene in &run.scenes {
                    let (max, psnr, over) = match &scene.metrics {
                        Some(m) => (
                            m.max.to_string(),
                            psnr_text(m.psnr_db),
                            format!("{} ({:.3}%)", m.pixels_over, m.percent_over()),
                        ),
                        None => Default::default(),
                    };
                    let result = if scene.passed { "pass" } else { "fail" };
                    let _ = writeln!(
                        h,
                        "<tr><td>{}</td><td class=\"{result}\">{result}</td><td>{max}</td><td>{psnr}</td><td>{over}</td><td>{}</td></tr>",
                        html_escape(&scene.name),
                        html_escape(&scene.detail)
                    );
                }
                h.push_str("</table>\n");
            }
        }
        Outcome::Renders(grade) => student_renders_html(h, grade)?,
    }
    h.push_str("</section>\n");
    Ok(())
}

/// One student's chapters in the class report.
fn student_renders_html(h: &mut String, grade: &Grade) -> Result<(), GradeError> {
    h.push_str("<table>\n<tr><th>chapter</th><th>result</th><th>size</th><th>max</th><th>PSNR (dB)</th><th>pixels over</th><th>detail</th></tr>\n");
    for chapter in 1..=LAST_CHAPTER {
        let status = chapter_status(grade, chapter);
        let name = status.name();
        let class = if name == "pass" { "pass" } else { "fail" };
        match &status {
            ChapterStatus::Graded(g) => {
                let m = &g.comparison.metrics;
                let _ = writeln!(
                    h,
                    "<tr><td>{chapter}</td><td class=\"{class}\">{name}</td><td>{}x{}</td><td>{}</td><td>{}</td><td>{} ({:.3}%)</td><td>{}</td></tr>",
                    m.width,
                    m.height,
                    m.max,
                    psnr_text(m.psnr_db),
                    m.pixels_over,
                    m.percent_over(),
                    html_escape(&format!("reference: {}", g.reference_source))
                );
            }
            ChapterStatus::Missing => {
                let _ = writeln!(
                    h,
                    "<tr><td>{chapter}</td><td class=\"{class}\">{name}</td><td colspan=\"5\">{}</td></tr>",
                    html_escape(&grade.missing_detail(chapter))
                );
            }
            ChapterStatus::Unreadable(why) => {
                let _ = writeln!(
                    h,
                    "<tr><td>{chapter}</td><td class=\"{class}\">{name}</td><td colspan=\"5\">{}</td></tr>",
                    html_escape(why)
                );
            }
        }
    }
    h.push_str("</table>\n");
    if !grade.ignored.is_empty() {
        h.push_str("<p>Ignored:</p>\n<ul>\n");
        for i in &grade.ignored {
            let _ = writeln!(
                h,
                "<li><code>{}</code>: {}</li>",
                html_escape(&i.name),
                html_escape(&i.reason)
            );
        }
        h.push_str("</ul>\n");
    }
    for g in grade
        .graded
        .iter()
        .filter(|g| !g.passes() && g.images.is_some())
    {
        let _ = writeln!(
            h,
            "<h3>Chapter {} <span class=\"badge\">FAIL</span></h3>",
            g.chapter
        );
        super::figures_html(h, g, "student")?;
    }
    Ok(())
}

/// One CSV field (RFC 4180): quoted when it holds a comma, a quote or a
/// line break. A field a spreadsheet would run as a formula (a student's
/// folder named `=HYPERLINK(...)`) is prefixed with `'`. Control
/// characters (an escape sequence in a student's output would drive the
/// terminal of whoever runs `cat grades.csv`) and bidirectional overrides
/// are written as escapes, line breaks kept.
fn csv_field(text: &str) -> String {
    let text = crate::text::terminal_safe(text);
    let text = if text.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        format!("'{text}")
    } else {
        text
    };
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn csv_fields_are_quoted_and_formulas_defused() {
        assert_eq!(csv_field("alice"), "alice");
        assert_eq!(csv_field("a,b"), "\"a,b\"");
        assert_eq!(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
        assert_eq!(csv_field("two\nlines"), "\"two\nlines\"");
        assert_eq!(csv_field("=1+1"), "'=1+1");
        assert_eq!(csv_field("-2"), "'-2");
        assert_eq!(csv_field("a\u{1b}]0;owned\u{7}"), "a\\u{1b}]0;owned\\u{7}");
        assert_eq!(csv_field("\u{202e}gnp"), "\\u{202e}gnp");
    }
}
