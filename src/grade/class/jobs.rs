//! A class spread over machines: each job grades one student and stores
//! the result with the options it was graded with, and [`merge`] puts the
//! class together from those files, refusing results of another grading.
//! Apart from grading a class in one run, which needs none of this.

use std::path::{Path, PathBuf};

use super::report::{student_section_html, write_section};
use super::similar::similar_code;
use super::{Class, Outcome, Student, grade_renders_of, run_code_of, students_in};
use crate::course::Chapters;
use crate::diff::Criteria;
use crate::grade::code::CodeJob;
use crate::grade::{GradeError, Graded, References};

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
    /// Whether the workspaces' `target/` folders were built on as they
    /// were (`--trust-targets`, with `--code`).
    #[serde(default)]
    pub trusted_targets: Option<bool>,
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
            trusted_targets: None,
            scenes: Vec::new(),
            scene_chapter: None,
        })
    }

    /// The options of a grading of code by `job`, its hidden scenes read
    /// from `scene_files` (as [`crate::grade::hidden::texts`] gives them).
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
            trusted_targets: Some(job.sandbox.is_some_and(|sandbox| sandbox.trusts_targets())),
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
        check(
            self.trusted_targets == other.trusted_targets,
            "--trust-targets",
        );
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
pub const RESULT_VERSION: u32 = 3;

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
    let mut student = named(students, name).ok_or_else(|| GradeError::NoSuchStudent {
        name: crate::text::visible_name(name),
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

/// The student of `students` that `name` (a `--student` argument) names:
/// the one whose folder is named so, as the documented jobs give names
/// (read from the class folder), else the one the report shows by that
/// name, or as it would show `name`. A folder literally named like
/// another's shown name (`a\xff` beside a folder whose name has the byte
/// 0xff) is found by its own name; each result names the student it
/// graded, so a merge given two results for one student refuses them.
fn named(students: Vec<Student>, name: &std::ffi::OsStr) -> Option<Student> {
    let shown = crate::text::visible_name(name);
    let position = (students.iter())
        .position(|student| student.folder.file_name() == Some(name))
        .or_else(|| {
            (students.iter()).position(|student| name.to_str() == Some(student.name.as_str()))
        })
        .or_else(|| students.iter().position(|student| student.name == shown))?;
    students.into_iter().nth(position)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `--student` finds a folder by its own name first (the documented
    /// jobs read names from the class folder), else by the name the report
    /// shows: `ali ce`, spelled out beside `ali` NBSP `ce`, by its spelling
    /// where no folder is literally named so.
    #[test]
    fn a_student_is_found_by_their_folder_s_name_then_by_the_name_shown() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        for folder in ["ali ce", "ali\u{a0}ce", "bob"] {
            std::fs::create_dir(dir.path().join(folder)).expect("a student");
        }
        let found = |name: &str| {
            let (students, _) = students_in(dir.path(), &[]).expect("read");
            let shown: Vec<String> = students
                .iter()
                .map(|student| student.name.clone())
                .collect();
            let folder = named(students, std::ffi::OsStr::new(name)).and_then(|student| {
                let name = student.folder.file_name()?.to_str()?;
                Some(name.to_string())
            });
            (folder, shown)
        };
        let (folder, shown) = found(r"ali\u{20}ce");
        assert_eq!(folder.as_deref(), Some("ali ce"), "{shown:?}");
        assert_eq!(found(r"ali\u{a0}ce").0.as_deref(), Some("ali\u{a0}ce"));
        assert_eq!(found("ali ce").0.as_deref(), Some("ali ce"));
        // A folder literally named like the spelling: its own name wins.
        let literal = r"ali\u{20}ce";
        std::fs::create_dir(dir.path().join(literal)).expect("a student");
        assert_eq!(found(literal).0.as_deref(), Some(literal));
        assert_eq!(found("bob").0.as_deref(), Some("bob"));
        assert_eq!(found("carol").0, None);
    }
}
