//! `check`: the verdict on a student's chapters, chapter by chapter.
//!
//! For each chapter, three things, in this order:
//!
//! 1. **checkpoint cases** ([`cases::Case`], listed per chapter in the
//!    registry [`crate::chapters::CHAPTERS`]): questions to each function of the
//!    chapter with numbers a student can work out by hand; the first failing
//!    one is printed with its inputs, the expected and the actual answer, and
//!    the lesson section that teaches it;
//! 2. **the image**: the chapter's built-in scene rendered with the student's
//!    chapters at the reference size, compared with the reference image
//!    shipped inside raylab (never rendered by the code under check) by
//!    `raylab diff`'s default rule: no pixel may differ by more than 2
//!    levels. A student whose code is right differs from the reference only
//!    by rounding, which changes a pixel by at most a level; every bug of the
//!    gallery (tests/course/check.rs) changes hundreds. A sampled stage
//!    (chapters 7 to 9) is judged against its converged reference instead,
//!    pixel by pixel within its noise ([`sampled`]), so that any correct
//!    sampler passes. On failure the student's
//!    image and a heatmap are written to [`CheckOptions::failures_dir`];
//! 3. **robustness**, reported apart: the chapter's hard cases (grazing and
//!    tangent rays, far and huge spheres, origins on surfaces, the critical
//!    angle, NaN input). A correct textbook formula passes level 1 and is
//!    "correct, not yet robust"; the stable one earns level 2.
//!
//! A function still written as `todo!()` makes its chapter "not started",
//! never a backtrace; any other panic is a failure that quotes its message.
//! Chapter N builds on chapters 1 to N-1: when one of them does not pass,
//! the verdict says so.

pub mod cases;
pub mod catalog;
// The f64 oracle answers every question a chapter asks: out of a student
// workspace's reach, as the reference chapters are.
#[cfg(not(feature = "student"))]
pub mod exact;
#[cfg(feature = "student")]
pub(crate) mod exact;
mod panics;
pub mod sampled;
pub mod verdict_file;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

pub use cases::{Case, CaseKind, Level, Outcome, TreeShape};
pub use panics::Panic;

use crate::Chapters;
use crate::chapters::{CHAPTERS, ChapterInfo, REFERENCE_HEIGHT, REFERENCE_WIDTH};
use crate::diff::{Criteria, Image, Metrics, compare};

/// What a whole check came to: the command line turns it into an exit status.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Overall {
    /// Every checked chapter passes.
    Pass,
    /// A chapter fails or is not started.
    Fail,
    /// The check itself could not run.
    Error,
}

/// How to check.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CheckOptions {
    /// Where the student's image and the heatmap go when a chapter's image
    /// fails (created when needed).
    pub failures_dir: PathBuf,
    /// Whether to write those images at all (the tests of raylab itself
    /// turn it off).
    pub write_images: bool,
    /// Whether a chapter whose code runs raylab's own answers fails (see
    /// [`crate::answer_key`]): set for a student's chapters, not for the
    /// variants of the reference that raylab's tests check.
    pub forbid_answer_key: bool,
}

impl Default for CheckOptions {
    fn default() -> CheckOptions {
        CheckOptions {
            failures_dir: PathBuf::from("check-failures"),
            write_images: true,
            forbid_answer_key: false,
        }
    }
}

/// A chapter's verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Its cases and its image pass, and so do the chapters before it.
    Pass,
    /// Every function of the chapter is still `todo!()`.
    NotStarted,
    /// A case or the image fails (or a function is not written yet).
    Fail,
    /// The chapter's own cases pass, but chapter `by` (an earlier one it
    /// builds on) does not.
    Blocked { by: u8 },
    /// The check could not run, or its output could not be written.
    Error,
}

impl Status {
    pub fn word(self) -> String {
        match self {
            Status::Pass => "pass".into(),
            Status::NotStarted => "not started".into(),
            Status::Fail => "FAIL".into(),
            Status::Blocked { by } => format!("needs ch. {by}"),
            Status::Error => "ERROR".into(),
        }
    }
}

/// A case that did not pass, as the report prints it.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseFailure {
    pub name: &'static str,
    pub function: &'static str,
    pub level: Level,
    /// Its number in its list (from 1) and the length of the list.
    pub number: usize,
    pub of: usize,
    pub says: String,
    pub inputs: String,
    pub outcome: Outcome,
    /// The lesson file and section that teach it.
    pub lesson: String,
    pub section: &'static str,
}

/// How the chapter's image compared with the reference.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageCheck {
    /// The comparison with the shipped reference image, pixel for pixel.
    pub metrics: Metrics,
    /// For a sampled stage, the comparison with the converged reference
    /// that decides (see [`sampled`]); `None` where pixels must match.
    pub noise: Option<sampled::NoiseCheck>,
    pub passed: bool,
    /// The student's image and the heatmap, when written.
    pub written: Vec<PathBuf>,
}

/// The robustness level's result.
#[derive(Debug, Clone, PartialEq)]
pub struct Robustness {
    pub passed: usize,
    pub total: usize,
    pub first_failure: Option<CaseFailure>,
}

/// Everything the check found about one chapter.
#[derive(Debug, Clone, PartialEq)]
pub struct ChapterVerdict {
    pub chapter: u8,
    pub title: &'static str,
    pub status: Status,
    pub cases_passed: usize,
    pub cases_total: usize,
    pub first_failure: Option<CaseFailure>,
    /// The chapter's functions found still `todo!()`.
    pub not_written: Vec<&'static str>,
    pub image: Option<ImageCheck>,
    /// `None` until level 1 passes.
    pub robustness: Option<Robustness>,
    /// The first earlier chapter that does not pass, with its status.
    pub needs: Option<(u8, Status)>,
    /// Problems of the check itself (an unwritable folder, say).
    pub errors: Vec<String>,
    /// The lesson file (`chapters/NN_name/lesson.md`, where raylab's
    /// checkout has it).
    pub lesson: String,
    /// raylab's own answers that ran while the chapter was checked (see
    /// [`crate::answer_key`]), when the check forbids them: the chapter fails.
    pub answers_used: Vec<&'static str>,
}

impl ChapterVerdict {
    /// Whether the chapter passes level 1 (robustness is reported apart).
    pub fn passes(&self) -> bool {
        self.status == Status::Pass
    }

    /// Whether it also passes every robustness case.
    pub fn robust(&self) -> bool {
        self.passes()
            && self
                .robustness
                .as_ref()
                .is_some_and(|r| r.passed == r.total)
    }

    /// The name of the first failing checkpoint case, if any.
    pub fn failing_case(&self) -> Option<&'static str> {
        self.first_failure.as_ref().map(|f| f.name)
    }

    /// The verdict as the student reads it.
    pub fn text(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "chapter {}: {} - {}",
            self.chapter,
            self.title,
            match self.status {
                Status::Pass if self.robust() => "pass (robust)".to_string(),
                Status::Pass => "pass".to_string(),
                other => other.word(),
            }
        );
        match self.status {
            Status::NotStarted => {
                let _ = writeln!(
                    out,
                    "  not started: {} still todo!() (the lesson: {})",
                    self.not_written.join(", "),
                    self.lesson
                );
            }
            _ => {
                let _ = writeln!(
                    out,
                    "  checkpoints: {} of {} pass",
                    self.cases_passed, self.cases_total
                );
            }
        }
        if !self.answers_used.is_empty() {
            let _ = writeln!(
                out,
                "  your code runs raylab's own answer instead of yours: {}\n    \
                 hint:     each function of chapter {} computes its answer itself; \
                 an `impl Chapters` must define every function it checks (the \
                 trait's defaults are raylab's answers), and the shapes' methods \
                 and raylab's functions are not yours to call",
                self.answers_used.join(", "),
                self.chapter
            );
        }
        if let Some(failure) = &self.first_failure {
            out.push_str(&failure_text(failure));
        }
        if let Some((chapter, status)) = self.needs {
            let _ = writeln!(
                out,
                "  chapter {} builds on chapter {chapter}, which is {}: {}",
                self.chapter,
                match status {
                    Status::NotStarted => "not started".to_string(),
                    Status::Fail => "failing".to_string(),
                    other => other.word(),
                },
                "make it pass first (cargo run --release -- check --chapter {chapter})"
                    .replace("{chapter}", &chapter.to_string())
            );
        }
        if let Some(image) = &self.image {
            out.push_str(&image_text(image));
            if !image.passed {
                let _ = writeln!(
                    out,
                    "    hint:     every checkpoint passes, so look at the heatmap {}; the \
                     lesson: {}",
                    catalog::image_hint(self.chapter),
                    self.lesson
                );
            }
        }
        if let Some(robustness) = &self.robustness {
            out.push_str(&robustness_text(robustness));
        }
        for error in &self.errors {
            let _ = writeln!(out, "  error: {}", crate::text::terminal_safe(error));
        }
        out
    }
}

/// The image's lines of the verdict.
fn image_text(image: &ImageCheck) -> String {
    let mut out = String::new();
    let m = &image.metrics;
    if let Some(noise) = &image.noise {
        let _ = writeln!(
            out,
            "  image: {} of {} {} beyond the noise of the converged reference ({} sigma \
             and 2 levels; at most {} allowed{}): {}",
            noise.outside,
            noise.pixels,
            if noise.block > 1 {
                format!("blocks of {0} x {0} pixels", noise.block)
            } else {
                "pixels".to_string()
            },
            sampled::SIGMAS,
            noise.allowed,
            noise
                .first
                .map(|(x, y)| format!(", the first at x={x}, y={y}"))
                .unwrap_or_default(),
            if image.passed {
                "within the noise"
            } else {
                "outside it"
            }
        );
        if !image.passed {
            for path in &image.written {
                let _ = writeln!(
                    out,
                    "    wrote {}",
                    crate::text::terminal_safe(&path.display().to_string())
                );
            }
        }
        return out;
    }
    if image.passed {
        let _ = writeln!(
            out,
            "  image: matches the reference ({}, max difference {} levels)",
            if m.max == 0 {
                "identical"
            } else {
                "within rounding"
            },
            m.max
        );
    } else {
        let _ = writeln!(
            out,
            "  image: {} of {} pixels differ from the reference by more than {} levels \
             (max {}{}, PSNR {} dB)",
            m.pixels_over,
            m.pixels,
            Criteria::default().threshold,
            m.max,
            m.max_at
                .map(|(x, y)| format!(" at x={x}, y={y}"))
                .unwrap_or_default(),
            m.psnr_text()
        );
        for path in &image.written {
            let _ = writeln!(
                out,
                "    wrote {}",
                crate::text::terminal_safe(&path.display().to_string())
            );
        }
    }
    out
}

/// The robustness lines of the verdict.
fn robustness_text(robustness: &Robustness) -> String {
    let mut out = String::new();
    if robustness.passed == robustness.total {
        let _ = writeln!(
            out,
            "  robustness: all {} hard cases pass",
            robustness.total
        );
    } else {
        let _ = writeln!(
            out,
            "  robustness: {} of {} hard cases pass: correct, not yet robust",
            robustness.passed, robustness.total
        );
        if let Some(failure) = &robustness.first_failure {
            out.push_str(&failure_text(failure));
        }
    }
    out
}

fn failure_text(failure: &CaseFailure) -> String {
    let mut out = String::new();
    let level = match failure.level {
        Level::Checkpoint => "checkpoint",
        Level::Robustness => "hard case",
    };
    if failure.name == "image" {
        let _ = writeln!(out, "  the image could not be rendered:");
    } else {
        let _ = writeln!(
            out,
            "  {level} {} of {} failed ({}: {}):",
            failure.number, failure.of, failure.function, failure.name
        );
    }
    let _ = writeln!(out, "    {}", failure.says);
    let _ = writeln!(out, "    call:     {}", failure.inputs);
    match &failure.outcome {
        Outcome::Fail { expected, got } => {
            let _ = writeln!(out, "    expected: {expected}");
            let _ = writeln!(out, "    got:      {got}");
        }
        Outcome::Todo(panic) => {
            let _ = writeln!(
                out,
                "    got:      todo!() at {} (not written yet)",
                panic.location.as_deref().unwrap_or("an unknown place")
            );
        }
        Outcome::Panicked(panic) => {
            let _ = writeln!(
                out,
                "    got:      a panic: {}{}",
                crate::text::terminal_safe(&panic.message),
                panic
                    .location
                    .as_deref()
                    .map(|l| format!(" (at {l})"))
                    .unwrap_or_default()
            );
        }
        Outcome::Error(error) => {
            let _ = writeln!(out, "    the check could not run: {error}");
        }
        Outcome::Pass => {}
    }
    let _ = writeln!(
        out,
        "    hint:     read {}, section \"{}\"",
        failure.lesson, failure.section
    );
    out
}

/// The verdicts of the chapters checked.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckReport {
    pub verdicts: Vec<ChapterVerdict>,
}

impl CheckReport {
    /// Whether every checked chapter passes, one fails (or is not
    /// started), or the check could not run.
    pub fn overall(&self) -> Overall {
        if self
            .verdicts
            .iter()
            .any(|v| v.status == Status::Error || !v.errors.is_empty())
        {
            Overall::Error
        } else if self.verdicts.iter().all(ChapterVerdict::passes) {
            Overall::Pass
        } else {
            Overall::Fail
        }
    }

    /// The table printed at the end: chapter, status, cases, robustness,
    /// image metric.
    pub fn summary_table(&self) -> String {
        let mut out = CheckReport::summary_header();
        for verdict in &self.verdicts {
            out.push_str(&CheckReport::summary_row(verdict));
        }
        out
    }

    /// The table's header line.
    pub fn summary_header() -> String {
        format!(
            "{:<8} {:<12} {:<7} {:<14} image\n",
            "chapter", "status", "cases", "robustness"
        )
    }

    /// The table's line for `verdict`.
    pub fn summary_row(verdict: &ChapterVerdict) -> String {
        let robustness = match &verdict.robustness {
            Some(r) if r.passed == r.total => format!("{}/{} robust", r.passed, r.total),
            Some(r) => format!("{}/{}", r.passed, r.total),
            None => "-".into(),
        };
        let image = match &verdict.image {
            Some(ImageCheck {
                noise: Some(noise), ..
            }) if noise.block > 1 => format!("{} blocks beyond noise", noise.outside),
            Some(ImageCheck {
                noise: Some(noise), ..
            }) => format!("{} px beyond noise", noise.outside),
            Some(image) if image.metrics.max == 0 => "identical".to_string(),
            Some(image) => format!(
                "max {}, {} px over {}",
                image.metrics.max,
                image.metrics.pixels_over,
                Criteria::default().threshold
            ),
            None => "-".into(),
        };
        format!(
            "{:<8} {:<12} {:<7} {:<14} {image}\n",
            verdict.chapter,
            verdict.status.word(),
            format!("{}/{}", verdict.cases_passed, verdict.cases_total),
            robustness
        )
    }

    /// Every verdict, then the table.
    pub fn text(&self) -> String {
        let mut out = String::new();
        for verdict in &self.verdicts {
            out.push_str(&verdict.text());
            out.push('\n');
        }
        out.push_str(&self.summary_table());
        out
    }
}

/// Which chapter's file a panic happened in.
fn owner(panic: &Panic) -> Option<u8> {
    let file = panic.file.as_deref()?;
    CHAPTERS
        .iter()
        .find(|info| file.contains(&info.module()) || file.contains(&format!("{}/", info.folder)))
        .map(|info| info.number)
}

/// Runs `cases` with `C`: how many pass, and the first that does not.
fn run_cases<C: Chapters>(info: &ChapterInfo, cases: &[Case]) -> (usize, Vec<(usize, Outcome)>) {
    let mut passed = 0;
    let mut failures = Vec::new();
    for (index, case) in cases.iter().enumerate() {
        verdict_file::step(info.number, case.function(), case.name);
        match case.run::<C>() {
            Outcome::Pass => passed += 1,
            outcome => failures.push((index, outcome)),
        }
    }
    (passed, failures)
}

fn case_failure(info: &ChapterInfo, cases: &[Case], index: usize, outcome: Outcome) -> CaseFailure {
    let case = &cases[index];
    CaseFailure {
        name: case.name,
        function: case.function(),
        level: case.level,
        number: index + 1,
        of: cases.len(),
        says: case.says.clone(),
        inputs: case.inputs(),
        outcome,
        lesson: lesson(info),
        section: case.section,
    }
}

/// The chapter's lesson where this raylab's checkout has it (a student
/// runs the check in their own workspace, where a path relative to raylab
/// would name nothing).
fn lesson(info: &ChapterInfo) -> String {
    let checkout = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = checkout.join(info.lesson_path());
    if path.is_file() {
        path.display().to_string()
    } else {
        info.lesson_path()
    }
}

/// Chapter `info`'s own verdict (not yet looking at earlier chapters).
/// `full`: also the image and the robustness cases. With
/// [`CheckOptions::forbid_answer_key`], a chapter whose code ran raylab's
/// own answers fails, whatever its cases said.
fn own_verdict<C: Chapters>(
    info: &ChapterInfo,
    options: &CheckOptions,
    full: bool,
) -> ChapterVerdict {
    let (mut verdict, mut answers) =
        crate::answer_key::recording(|| cases_image_robustness::<C>(info, options, full));
    verdict_file::finished(info.number);
    if !options.forbid_answer_key {
        return verdict;
    }
    if C::COMPARISON {
        answers.insert(0, "a comparison wrapper of raylab's (Textbook)");
    }
    if !answers.is_empty() && verdict.status != Status::Error {
        verdict.status = Status::Fail;
        verdict.answers_used = answers;
    }
    verdict
}

/// [`own_verdict`] but for the answer key.
fn cases_image_robustness<C: Chapters>(
    info: &ChapterInfo,
    options: &CheckOptions,
    full: bool,
) -> ChapterVerdict {
    let chapter = info.number;
    let cases = catalog::checkpoints(info.number);
    let (passed, failures) = run_cases::<C>(info, &cases);
    let mut verdict = ChapterVerdict {
        chapter,
        title: info.title,
        status: Status::Pass,
        cases_passed: passed,
        cases_total: cases.len(),
        first_failure: None,
        not_written: Vec::new(),
        image: None,
        robustness: None,
        needs: None,
        errors: Vec::new(),
        lesson: lesson(info),
        answers_used: Vec::new(),
    };
    let own_todo = |outcome: &Outcome| match outcome {
        Outcome::Todo(panic) => owner(panic).is_none_or(|o| o >= chapter),
        _ => false,
    };
    for (index, outcome) in &failures {
        if own_todo(outcome) {
            let function = cases[*index].function();
            if !verdict.not_written.contains(&function) {
                verdict.not_written.push(function);
            }
        }
    }
    if !cases.is_empty()
        && failures.len() == cases.len()
        && failures.iter().all(|(_, o)| own_todo(o))
    {
        verdict.status = Status::NotStarted;
        verdict.not_written = info.functions.to_vec();
        return verdict;
    }
    if let Some((index, outcome)) = failures.into_iter().next() {
        verdict.status = match &outcome {
            Outcome::Error(error) => {
                verdict.errors.push(error.clone());
                Status::Error
            }
            Outcome::Todo(panic) => match owner(panic) {
                Some(earlier) if earlier < chapter => Status::Blocked { by: earlier },
                _ => Status::Fail,
            },
            _ => Status::Fail,
        };
        verdict.first_failure = Some(case_failure(info, &cases, index, outcome));
        return verdict;
    }
    if !full {
        return verdict;
    }
    judge_image::<C>(info, options, cases.len(), &mut verdict);
    if verdict.status == Status::Pass {
        verdict.robustness = Some(run_robustness::<C>(info));
    }
    verdict
}

/// Renders and compares the chapter's image into `verdict`, once its
/// `cases` checkpoints pass.
fn judge_image<C: Chapters>(
    info: &ChapterInfo,
    options: &CheckOptions,
    cases: usize,
    verdict: &mut ChapterVerdict,
) {
    verdict_file::step(info.number, "the whole stage", "the chapter's image");
    match check_image::<C>(info, options) {
        Ok(Ok(image)) => {
            if !image.passed {
                verdict.status = Status::Fail;
            }
            verdict.image = Some(image);
        }
        Ok(Err(error)) => {
            verdict.status = Status::Error;
            verdict.errors.push(error);
        }
        Err(panic) => {
            let (status, failure) = image_panic(info, cases, panic);
            verdict.status = status;
            verdict.errors.clear();
            verdict.first_failure = Some(failure);
        }
    }
    // A write error of the failure images is reported; the verdict stands.
    if let Some(image) = &verdict.image
        && !image.passed
        && options.write_images
        && image.written.is_empty()
    {
        verdict
            .errors
            .push("the failure images could not be written".into());
    }
}

/// The chapter's hard cases, run once its checkpoints and image pass.
fn run_robustness<C: Chapters>(info: &ChapterInfo) -> Robustness {
    let hard = catalog::robustness(info.number);
    let (passed, failures) = run_cases::<C>(info, &hard);
    Robustness {
        passed,
        total: hard.len(),
        first_failure: failures
            .into_iter()
            .next()
            .map(|(index, outcome)| case_failure(info, &hard, index, outcome)),
    }
}

/// The status and the failure of a chapter whose `cases` checkpoints
/// passed but whose image rendering panicked.
fn image_panic(info: &ChapterInfo, cases: usize, panic: Panic) -> (Status, CaseFailure) {
    let chapter = info.number;
    // The chapter's own cases passed, so a todo!() met while
    // rendering is in an earlier chapter: by its file when the
    // panic says, else (0) the first earlier chapter not passing.
    let status = match owner(&panic) {
        Some(earlier) if panic.is_todo() && earlier < chapter => Status::Blocked { by: earlier },
        None if panic.is_todo() => Status::Blocked { by: 0 },
        _ => Status::Fail,
    };
    let failure = CaseFailure {
        name: "image",
        function: "(the whole stage)",
        level: Level::Checkpoint,
        number: cases + 1,
        of: cases + 1,
        says: format!(
            "rendering the chapter's built-in scene at {REFERENCE_WIDTH}x{REFERENCE_HEIGHT}"
        ),
        inputs: format!("raylab render --chapter {chapter}"),
        outcome: if panic.is_todo() {
            Outcome::Todo(panic)
        } else {
            Outcome::Panicked(panic)
        },
        lesson: lesson(info),
        section: "What the picture shows",
    };
    (status, failure)
}

/// Renders the chapter's scene with `C` (on this thread, so that a panic
/// is caught here), compares it with the shipped reference, and writes the
/// failure images. `Err` is a panic in the code under check; `Ok(Err)` a
/// problem of the check itself.
fn check_image<C: Chapters>(
    info: &ChapterInfo,
    options: &CheckOptions,
) -> Result<Result<ImageCheck, String>, Panic> {
    let reference = match Image::decode_png(info.reference_png) {
        Ok(image) => image,
        Err(error) => return Ok(Err(format!("the shipped reference image: {error:#}"))),
    };
    let scene = match crate::builtin::scene(info.number) {
        Ok(scene) => scene,
        Err(error) => return Ok(Err(error.to_string())),
    };
    let settings = crate::RenderSettings {
        width: REFERENCE_WIDTH,
        height: REFERENCE_HEIGHT,
        ..scene.render
    };
    let stage = match crate::Stage::<C>::with_chapters(&scene, info.number, settings) {
        Ok(stage) => stage,
        Err(error) => return Ok(Err(error.to_string())),
    };
    let linear = panics::guarded(|| {
        // The same loop as render::render_stage, on one thread: each pixel
        // is computed exactly as `raylab render` does (path-traced samples
        // cut to the screen's white, as the converged image is).
        // Chapter 14's light paths first, as raylab render traces them.
        let light = stage.light_image();
        let mut tracer = sampled::judging_tracer(&stage);
        let mut linear = Vec::with_capacity((REFERENCE_WIDTH * REFERENCE_HEIGHT) as usize);
        for y in 0..REFERENCE_HEIGHT {
            for x in 0..REFERENCE_WIDTH {
                let index = linear.len();
                let camera = tracer.pixel(x, y);
                linear.push(camera + light.map_or(crate::Vec3::ZERO, |light| light.pixels[index]));
            }
        }
        linear
    })?;
    let rgb = linear
        .iter()
        .flat_map(|color| color.to_array().map(crate::output::linear_to_srgb8))
        .collect();
    let noise = if sampled::is_sampled(&stage, &settings) {
        match sampled::converged(info, &scene, settings) {
            Ok(converged) if stage.effects.path_tracing => {
                let side = sampled::PATH_BLOCK;
                let blocks = sampled::block_means(&linear, REFERENCE_WIDTH, side);
                let mut noise = sampled::judge(&blocks, stage.samples(), &converged.blocks(side));
                noise.block = side;
                noise.allowed =
                    sampled::allowed_block_outliers(blocks.len(), stage.effects.light_tracing);
                // The first block's top-left pixel.
                noise.first = noise.first.map(|(x, y)| (x * side, y * side));
                Some(noise)
            }
            Ok(converged) => Some(sampled::judge(&linear, stage.samples(), &converged)),
            Err(error) => return Ok(Err(error)),
        }
    } else {
        None
    };
    let student = Image {
        width: REFERENCE_WIDTH,
        height: REFERENCE_HEIGHT,
        rgb,
    };
    let comparison = match compare(
        &student,
        &reference,
        Criteria::default(),
        ("your image", "the reference"),
    ) {
        Ok(comparison) => comparison,
        Err(error) => return Ok(Err(format!("{error:#}"))),
    };
    let passed = match &noise {
        Some(noise) => noise.passes(),
        None => comparison.passes(),
    };
    let mut written = Vec::new();
    if !passed && options.write_images {
        match write_failure_images(info.number, &options.failures_dir, &student, &comparison) {
            Ok(paths) => written = paths,
            Err(error) => return Ok(Err(error)),
        }
    } else if passed && options.write_images {
        // The images of an earlier failure would now mislead: the chapter
        // draws right. Only raylab's own two names are removed, and only
        // files raylab wrote (a student's own chapter-3.png stays).
        for name in failure_image_names(info.number) {
            let path = options.failures_dir.join(name);
            if crate::output::is_raylab_png(&path) {
                let _ = std::fs::remove_file(path);
            }
        }
    }
    Ok(Ok(ImageCheck {
        metrics: comparison.metrics,
        noise,
        passed,
        written,
    }))
}

/// The names of the student's image and its heatmap in the failures folder.
fn failure_image_names(chapter: u8) -> [String; 2] {
    [
        format!("chapter-{chapter}.png"),
        format!("chapter-{chapter}-heatmap.png"),
    ]
}

fn write_failure_images(
    chapter: u8,
    folder: &Path,
    student: &Image,
    comparison: &crate::diff::Comparison,
) -> Result<Vec<PathBuf>, String> {
    let heatmap = comparison
        .heatmap(student)
        .map_err(|error| format!("{error:#}"))?;
    std::fs::create_dir_all(folder).map_err(|error| {
        format!(
            "cannot create the folder {}: {error}",
            crate::text::terminal_safe(&folder.display().to_string())
        )
    })?;
    let [image_name, heatmap_name] = failure_image_names(chapter);
    let image_path = folder.join(image_name);
    let heatmap_path = folder.join(heatmap_name);
    // Never over a file raylab did not write, nor a read-only one.
    let outputs = [
        ("--failures-dir", image_path.as_path()),
        ("--failures-dir", heatmap_path.as_path()),
    ];
    crate::output::check_outputs(&[], &outputs, false).map_err(|error| format!("{error:#}"))?;
    for (_, path) in outputs {
        if std::fs::symlink_metadata(path).is_ok() && !crate::output::is_raylab_png(path) {
            return Err(format!(
                "{} was not written by raylab, so it is kept: move it, or give --failures-dir \
                 another folder",
                crate::text::terminal_safe(&path.display().to_string())
            ));
        }
    }
    student
        .write_png(&image_path)
        .and_then(|()| heatmap.write_png(&heatmap_path))
        .map_err(|error| format!("{error:#}"))?;
    Ok(vec![image_path, heatmap_path])
}

/// Marks `verdict` with the first of `earlier` that does not pass.
fn apply_prerequisites(verdict: &mut ChapterVerdict, earlier: &[(u8, Status)]) {
    if verdict.status == (Status::Blocked { by: 0 })
        && !earlier.iter().any(|(_, status)| *status != Status::Pass)
    {
        // A todo!() nowhere to be found among the earlier chapters: this
        // chapter's own, in a function its cases do not reach.
        verdict.status = Status::Fail;
    }
    if let Some(&(chapter, status)) = earlier.iter().find(|(_, status)| *status != Status::Pass) {
        verdict.needs = Some((chapter, status));
        if matches!(verdict.status, Status::Pass | Status::Blocked { by: 0 }) {
            verdict.status = Status::Blocked { by: chapter };
        }
    }
}

/// The verdict on chapter `chapter` of the chapters `C`: its cases, its
/// image, its robustness, and whether the chapters before it pass their
/// cases. An unknown chapter is an error verdict.
pub fn check_chapter<C: Chapters>(chapter: u8, options: &CheckOptions) -> ChapterVerdict {
    let Some(info) = crate::chapters::chapter(chapter) else {
        return unknown_chapter(chapter);
    };
    crate::answer_key::take_reported();
    let mut verdict = own_verdict::<C>(info, options, true);
    // Before the prerequisites: an answer of an earlier chapter's, run on a
    // thread of the student's, makes that chapter fail and this one wait.
    let mut all: Vec<ChapterVerdict> = CHAPTERS
        .iter()
        .filter(|other| other.number < chapter)
        .map(|other| own_verdict::<C>(other, options, false))
        .collect();
    all.push(verdict);
    fail_for_escaped_answers(&mut all, options);
    verdict = all.pop().unwrap_or_else(|| unknown_chapter(chapter));
    let earlier: Vec<(u8, Status)> = all.iter().map(|v| (v.chapter, v.status)).collect();
    apply_prerequisites(&mut verdict, &earlier);
    verdict
}

/// Fails the verdicts whose checks ran raylab's answers on threads the
/// code under check started, out of reach of [`own_verdict`]'s recording
/// (which sees its own thread's): each answer fails the chapter it belongs
/// to where that chapter is among `verdicts`, or else every verdict, since
/// any of their checks may have run it.
fn fail_for_escaped_answers(verdicts: &mut [ChapterVerdict], options: &CheckOptions) {
    let escaped = crate::answer_key::take_reported();
    if !options.forbid_answer_key || escaped.is_empty() {
        return;
    }
    for answer in escaped {
        let owner = answer_chapter(answer);
        let owned = verdicts
            .iter()
            .any(|verdict| Some(verdict.chapter) == owner);
        for verdict in verdicts.iter_mut() {
            if (!owned || Some(verdict.chapter) == owner) && verdict.status != Status::Error {
                verdict.status = Status::Fail;
                if !verdict.answers_used.contains(&answer) {
                    verdict.answers_used.push(answer);
                }
            }
        }
    }
}

/// The chapter whose lesson an answer of raylab's (as
/// [`crate::answer_key::answered`] names it) answers, where one does.
fn answer_chapter(answer: &str) -> Option<u8> {
    if let Some(function) = answer.strip_prefix("Chapters::") {
        return CHAPTERS
            .iter()
            .find(|info| info.functions.contains(&function))
            .map(|info| info.number);
    }
    match answer {
        "Plane::intersect" => Some(1),
        "Sphere::intersect"
        | "Sphere::roots"
        | "Sphere::intersect_textbook"
        | "Textbook::intersect_sphere" => Some(2),
        "Objects::nearest_hit_by_loop" | "raylab::nearest_hit" | "raylab::first_hit" => Some(3),
        "Textbook::intersect_triangle" => Some(10),
        _ => None,
    }
}

fn unknown_chapter(chapter: u8) -> ChapterVerdict {
    ChapterVerdict {
        chapter,
        title: "",
        status: Status::Error,
        cases_passed: 0,
        cases_total: 0,
        first_failure: None,
        not_written: Vec::new(),
        image: None,
        robustness: None,
        needs: None,
        errors: vec![format!(
            "there is no chapter {chapter}; chapters are 1 to {}",
            crate::chapters::LAST_CHAPTER
        )],
        lesson: String::new(),
        answers_used: Vec::new(),
    }
}

/// Checks chapter `chapters` (with what it builds on), or every chapter.
/// Chapters are checked in parallel, one thread each: each checks its own
/// panics, so no panic of student code ever reaches the screen.
pub fn check_all<C: Chapters>(chapters: Option<u8>, options: &CheckOptions) -> CheckReport {
    crate::answer_key::take_reported();
    if let Some(chapter) = chapters {
        return CheckReport {
            verdicts: vec![check_chapter::<C>(chapter, options)],
        };
    }
    let mut verdicts: Vec<ChapterVerdict> = std::thread::scope(|scope| {
        let handles: Vec<_> = CHAPTERS
            .iter()
            .map(|info| scope.spawn(move || own_verdict::<C>(info, options, true)))
            .collect();
        handles
            .into_iter()
            .zip(CHAPTERS)
            .map(|(handle, info)| {
                // Student panics are caught inside; a panic here would be
                // raylab's own bug, reported as an error, not a crash.
                handle.join().unwrap_or_else(|_| {
                    let mut verdict = unknown_chapter(info.number);
                    verdict.errors = vec!["the check itself panicked".into()];
                    verdict.title = info.title;
                    verdict
                })
            })
            .collect()
    });
    // Before the prerequisites, so that the chapters after one that ran
    // raylab's answer on a thread of its own wait for it, as for any fail.
    fail_for_escaped_answers(&mut verdicts, options);
    let statuses: Vec<(u8, Status)> = verdicts.iter().map(|v| (v.chapter, v.status)).collect();
    for verdict in &mut verdicts {
        let earlier: Vec<(u8, Status)> = statuses
            .iter()
            .copied()
            .filter(|(chapter, _)| *chapter < verdict.chapter)
            .collect();
        apply_prerequisites(verdict, &earlier);
    }
    CheckReport { verdicts }
}

/// Set to `1`, [`assert_chapter`] also demands the robustness level: what
/// `scripts/mutation-score.sh` sets, so that a mutant only the hard cases
/// notice counts as caught.
pub const REQUIRE_ROBUST_VAR: &str = "RAYLAB_CHECK_ROBUST";

/// Panics with the verdict's text unless chapter `chapter` (and every
/// chapter it builds on) passes: a student workspace's `cargo test` has one
/// test per chapter that calls this. Robustness is reported apart, as by
/// `check`, unless [`REQUIRE_ROBUST_VAR`] is `1`.
pub fn assert_chapter<C: Chapters>(chapter: u8) {
    // A student's tests, like their binary, may not lean on raylab's answers
    // (nor, in a student's build, run raylab's own chapters as theirs).
    let student = cfg!(feature = "student")
        || std::any::TypeId::of::<C>() != std::any::TypeId::of::<crate::Reference>();
    if student {
        crate::answer_key::seal();
        crate::answer_key::set_strict(true);
    }
    let options = CheckOptions {
        forbid_answer_key: student,
        ..CheckOptions::default()
    };
    let verdict = check_chapter::<C>(chapter, &options);
    let require_robust = std::env::var_os(REQUIRE_ROBUST_VAR).is_some_and(|v| v == "1");
    if !verdict.passes() || (require_robust && !verdict.robust()) {
        panic!("\n{}", verdict.text());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_passes_every_checkpoint_and_hard_case() {
        for info in CHAPTERS {
            for case in catalog::checkpoints(info.number)
                .iter()
                .chain(&catalog::robustness(info.number))
            {
                assert_eq!(
                    case.run::<crate::Reference>(),
                    Outcome::Pass,
                    "chapter {}: {} ({})",
                    info.number,
                    case.name,
                    case.says
                );
            }
        }
    }

    #[test]
    fn hard_cases_are_reported_as_robustness() {
        for info in CHAPTERS {
            let hard = catalog::robustness(info.number);
            assert!(
                hard.iter().all(|case| case.level == Level::Robustness),
                "chapter {}",
                info.number
            );
            if let Some(case) = hard.first() {
                let failure = case_failure(
                    info,
                    &hard,
                    0,
                    Outcome::Fail {
                        expected: "1".into(),
                        got: "2".into(),
                    },
                );
                assert!(
                    failure_text(&failure).contains("  hard case 1 of"),
                    "{case:?}"
                );
            }
        }
    }

    #[test]
    fn case_names_are_unique() {
        let mut names: Vec<&str> = CHAPTERS
            .iter()
            .flat_map(|info| {
                catalog::checkpoints(info.number)
                    .into_iter()
                    .chain(catalog::robustness(info.number))
                    .map(|case| case.name)
            })
            .collect();
        let count = names.len();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), count);
    }
}
