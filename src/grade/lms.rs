//! What a learning management system imports from `raylab grade`:
//! Gradescope's autograder results (`results.json`, one submission) and a
//! gradebook CSV that Canvas and Moodle import (one row per student).
//!
//! Each chapter is worth one point: it passes or it does not. These only
//! read what grading gave; how it was graded is none of their business.

use std::fmt::Write as _;

use super::class::{Class, Outcome, Student, csv_field};
use super::code::CodeRun;
use crate::chapters::LAST_CHAPTER;

/// Gradescope's `results.json` (its autograder specification): the total
/// score, what the student reads at the top, and one test per chapter.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct GradescopeResults {
    /// The sum of the tests' scores.
    pub score: f64,
    /// Shown above the tests: the status, with its reason.
    pub output: String,
    /// What Gradescope shows of the tests: `visible` to the student.
    pub visibility: String,
    /// What the autograder printed is the instructor's alone.
    pub stdout_visibility: String,
    pub tests: Vec<GradescopeTest>,
    /// Marks the file as raylab's, so that a later run may replace it.
    pub extra_data: GradescopeExtra,
}

/// One test of [`GradescopeResults`].
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct GradescopeTest {
    pub name: String,
    /// The chapter's number (Gradescope sorts tests by it).
    pub number: String,
    pub score: f64,
    pub max_score: f64,
    /// `passed` or `failed`.
    pub status: String,
    pub visibility: String,
    pub output: String,
}

/// raylab's own field of [`GradescopeResults`].
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct GradescopeExtra {
    /// The version of the file's layout.
    pub raylab_gradescope: u32,
    /// The run's status in raylab's words (`pass`, `build error`, ...).
    pub status: String,
}

/// The layout of [`GradescopeResults`] that this raylab writes.
pub const GRADESCOPE_VERSION: u32 = 1;

/// The results of one submission's `run`, chapters 1 to `up_to` each a
/// test worth a point, then each hidden scene a test worth a point.
pub fn gradescope_results(run: &CodeRun, up_to: u8) -> GradescopeResults {
    let status = Student::status_with_reason(run);
    let mut tests = Vec::new();
    for chapter in 1..=up_to {
        let title = crate::chapters::chapter(chapter).map_or("", |info| info.title);
        let passes = run
            .chapters
            .iter()
            .any(|score| score.chapter == chapter && score.passes);
        let output = chapter_block(&run.stdout, chapter)
            .unwrap_or_else(|| format!("no verdict: the run ended with {status}"));
        tests.push(test(
            format!("Chapter {chapter}: {title}"),
            chapter.to_string(),
            passes,
            output,
        ));
    }
    for (index, scene) in run.scenes.iter().enumerate() {
        tests.push(test(
            format!("Hidden scene: {}", scene.name),
            format!("{}.{}", up_to.saturating_add(1), index + 1),
            scene.passed,
            scene.detail.clone(),
        ));
    }
    GradescopeResults {
        score: tests.iter().map(|test| test.score).sum(),
        output: crate::text::terminal_safe(&format!(
            "raylab grade --code: {status}\n\n{}",
            Student::code_summary(run)
        )),
        visibility: "visible".into(),
        stdout_visibility: "hidden".into(),
        tests,
        extra_data: GradescopeExtra {
            raylab_gradescope: GRADESCOPE_VERSION,
            status: run.status.name().into(),
        },
    }
}

/// A test of the results. Gradescope shows its name and output as they
/// are, and a build error's output is the student's text (the compiler
/// quotes a `compile_error!`, a build script prints what it likes): its
/// invisible characters, bidi controls and escape sequences are escaped,
/// as in the report and the CSV, so that it cannot pass for raylab's.
fn test(name: String, number: String, passes: bool, output: String) -> GradescopeTest {
    let output = crate::text::terminal_safe(&output);
    GradescopeTest {
        name: crate::text::terminal_safe(&name),
        number,
        score: if passes { 1.0 } else { 0.0 },
        max_score: 1.0,
        status: if passes { "passed" } else { "failed" }.into(),
        visibility: "visible".into(),
        output,
    }
}

/// The block of the check's verdicts `text` about `chapter`: from its
/// line `chapter N: ...` to the blank line after it.
fn chapter_block(text: &str, chapter: u8) -> Option<String> {
    let start = format!("chapter {chapter}: ");
    text.split("\n\n")
        .find(|block| block.starts_with(&start))
        .map(|block| block.trim_end().to_string())
}

/// The first columns of the gradebook CSV: those Canvas's gradebook import
/// reads a student by (`SIS Login ID` holds the student's folder name;
/// Moodle maps it to a user field on import).
pub const GRADEBOOK_HEADER: &str = crate::output::markers::GRADEBOOK_CSV;

/// The gradebook of a graded class: one row per student, named by their
/// folder, a column per chapter of 1 to `assigned` (`--chapter`; 1 when it
/// passes, else 0), then with `grade --code --scene` a column per hidden
/// scene (1 when it passes), and the total: a point each, as in
/// Gradescope's results.
pub fn gradebook_csv(class: &Class, assigned: u8) -> String {
    let assigned = assigned.min(LAST_CHAPTER);
    let scenes = hidden_scenes(class);
    let mut csv = String::from(GRADEBOOK_HEADER);
    for chapter in 1..=assigned {
        let _ = write!(csv, ",raylab chapter {chapter}");
    }
    for scene in &scenes {
        let _ = write!(
            csv,
            ",{}",
            csv_field(&format!("raylab hidden scene {scene}"))
        );
    }
    let most = usize::from(assigned) + scenes.len();
    let _ = writeln!(csv, ",raylab total ({most})");
    for student in &class.students {
        let name = csv_field(&student.name);
        let _ = write!(csv, "{name},,,{name},");
        let mut total = 0;
        let points = (1..=assigned)
            .map(|chapter| chapter_passes(student, chapter))
            .chain(scenes.iter().map(|scene| scene_passes(student, scene)));
        for passes in points {
            total += usize::from(passes);
            let _ = write!(csv, ",{}", u8::from(passes));
        }
        let _ = writeln!(csv, ",{total}");
    }
    csv
}

/// The names of the hidden scenes the class's code was graded on, in the
/// order they were rendered (every student whose code answered met the
/// same ones; one whose build failed met none).
fn hidden_scenes(class: &Class) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for student in &class.students {
        if let Outcome::Code(run) = &student.outcome {
            for scene in &run.scenes {
                if !names.contains(&scene.name) {
                    names.push(scene.name.clone());
                }
            }
        }
    }
    names
}

/// Whether `student`'s code rendered the hidden scene `name` as the
/// reference does: a student who never rendered it gets no point.
fn scene_passes(student: &Student, name: &str) -> bool {
    match &student.outcome {
        Outcome::Code(run) => run
            .scenes
            .iter()
            .any(|scene| scene.name == name && scene.passed),
        Outcome::Renders(_) | Outcome::Refused(_) => false,
    }
}

/// Whether `student`'s `chapter` passes: their render of it, or their
/// code's.
fn chapter_passes(student: &Student, chapter: u8) -> bool {
    match &student.outcome {
        Outcome::Renders(grade) => grade
            .graded
            .iter()
            .any(|graded| graded.chapter == chapter && graded.passes()),
        Outcome::Code(run) => run
            .chapters
            .iter()
            .any(|score| score.chapter == chapter && score.passes),
        Outcome::Refused(_) => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grade::code::{ChapterScore, CodeStatus};

    /// Each chapter that passes is a point, and so is each hidden scene;
    /// the total is their sum.
    #[test]
    fn a_passing_chapter_is_a_point_and_the_total_adds_up() {
        let run = CodeRun {
            status: CodeStatus::Fail,
            exit_code: Some(0),
            stdout: "chapter 1: Ray-plane intersection - pass\n  checkpoints: 17 of 17 pass\n\n\
                     chapter 2: Ray-sphere intersection - FAIL\n  checkpoints: 3 of 9 pass\n\n"
                .into(),
            stderr: String::new(),
            timeout: std::time::Duration::from_secs(60),
            chapters_passed: 1,
            scenes: Vec::new(),
            fresh: None,
            trusted_target: false,
            sources: Vec::new(),
            limits: Vec::new(),
            reason: None,
            chapters: vec![
                ChapterScore {
                    chapter: 1,
                    passes: true,
                },
                ChapterScore {
                    chapter: 2,
                    passes: false,
                },
            ],
        };
        let results = gradescope_results(&run, 3);
        assert_eq!(results.tests.len(), 3);
        assert_eq!(results.score, 1.0);
        assert_eq!(results.tests[0].status, "passed");
        assert_eq!(results.tests[1].score, 0.0);
        assert!(results.tests[1].output.contains("3 of 9 pass"));
        assert!(results.tests[2].output.starts_with("no verdict"));
    }

    /// With hidden scenes, the gradebook has a column per scene, a point
    /// each as in Gradescope's results: a student who fails them does not
    /// get the marks of one who passes them.
    #[test]
    fn each_hidden_scene_is_a_point_of_the_gradebook() {
        let scene = |name: &str, passed: bool| crate::grade::hidden::SceneOutcome {
            name: name.into(),
            passed,
            metrics: None,
            detail: String::new(),
        };
        let student = |name: &str, scenes| Student {
            name: name.into(),
            folder: std::path::PathBuf::from(name),
            outcome: Outcome::Code(Box::new(CodeRun {
                status: CodeStatus::Fail,
                exit_code: Some(0),
                stdout: String::new(),
                stderr: String::new(),
                timeout: std::time::Duration::from_secs(60),
                chapters_passed: 1,
                scenes,
                fresh: None,
                trusted_target: false,
                sources: Vec::new(),
                limits: Vec::new(),
                reason: None,
                chapters: vec![ChapterScore {
                    chapter: 1,
                    passes: true,
                }],
            })),
        };
        let class = Class {
            folder: std::path::PathBuf::from("class"),
            criteria: crate::diff::Criteria::default(),
            students: vec![
                student("ann", vec![scene("a.toml", true), scene("b.toml", true)]),
                student("bob", vec![scene("a.toml", true), scene("b.toml", false)]),
                student("cy", Vec::new()),
            ],
            ignored: Vec::new(),
            similar: Vec::new(),
        };
        // Graded on chapters 1 to 3 (`--chapter 3`): no column for the
        // chapters not assigned, which would post zeros.
        let csv = gradebook_csv(&class, 3);
        let rows: Vec<Vec<&str>> = csv.lines().map(|line| line.split(',').collect()).collect();
        let chapters = 3;
        assert_eq!(rows[0][5 + chapters - 1], "raylab chapter 3", "{csv}");
        let header = &rows[0][5 + chapters..];
        let total = format!("raylab total ({})", chapters + 2);
        assert_eq!(
            header,
            [
                "raylab hidden scene a.toml",
                "raylab hidden scene b.toml",
                &total
            ]
        );
        let points = |row: &Vec<&str>| row[5 + chapters..].join(",");
        assert_eq!(points(&rows[1]), "1,1,3", "{csv}");
        assert_eq!(points(&rows[2]), "1,0,2", "{csv}");
        assert_eq!(points(&rows[3]), "0,0,1", "{csv}");
    }

    /// What Gradescope shows is text the student's code wrote, for a build
    /// error (the compiler's errors quote a `compile_error!`'s message,
    /// a build script prints what it likes): its invisible characters, bidi
    /// overrides, line separators and escape sequences arrive escaped, as in
    /// the report and the CSV, so that it cannot pass for raylab's text.
    #[test]
    fn a_students_text_reaches_gradescope_escaped() {
        let forged = "error: \u{202e}41/41 ssap\u{202c} \u{200b}\u{2028}\u{1b}[2J ok";
        let run = CodeRun {
            status: CodeStatus::BuildError,
            exit_code: Some(101),
            stdout: String::new(),
            stderr: format!("   Compiling ann v0.1.0\n{forged}\n"),
            timeout: std::time::Duration::from_secs(60),
            chapters_passed: 0,
            scenes: Vec::new(),
            fresh: None,
            trusted_target: false,
            sources: Vec::new(),
            limits: Vec::new(),
            reason: Some(forged.into()),
            chapters: Vec::new(),
        };
        let results = gradescope_results(&run, 2);
        let texts =
            std::iter::once(&results.output).chain(results.tests.iter().map(|test| &test.output));
        for text in texts {
            assert!(text.contains("u{202e}"), "{text}");
            assert!(
                !text
                    .chars()
                    .any(|c| (c.is_control() && c != '\n') || crate::text::invisible(c)),
                "{text:?}"
            );
        }
    }
}
