//! `check`: the verdict on a student's chapters, chapter by chapter.
//!
//! For each chapter, three things, in this order:
//!
//! 1. **checkpoint cases** ([`question::Case`], listed per chapter in the
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

// The judge's cases with their expectations, the f64 oracle, the judge
// itself: out of a student workspace's reach, as the reference chapters
// are, so that no chapter can read an expected value (a workspace's build
// names only `assert_chapter`).

#[cfg(not(feature = "student"))]
pub mod asker;
#[cfg(feature = "student")]
pub(crate) mod asker;
#[cfg(not(feature = "student"))]
pub mod cases;
#[cfg(feature = "student")]
pub(crate) mod cases;
#[cfg(not(feature = "student"))]
pub mod catalog;
#[cfg(feature = "student")]
pub(crate) mod catalog;
mod decoded_budget;
#[cfg(not(feature = "student"))]
pub mod exact;
#[cfg(feature = "student")]
pub(crate) mod exact;
#[cfg(not(feature = "student"))]
pub mod judge;
#[cfg(feature = "student")]
pub(crate) mod judge;
// Only the command line's `serve` calls it, and the page has no command line.
#[cfg(not(target_arch = "wasm32"))]
pub(crate) mod no_programs;
pub mod own_binary;
mod panics;
#[cfg(not(feature = "student"))]
#[doc(hidden)]
pub mod planted;
#[cfg(not(feature = "student"))]
pub mod protocol;
#[cfg(feature = "student")]
pub(crate) mod protocol;
#[cfg(not(feature = "student"))]
pub mod question;
#[cfg(feature = "student")]
pub(crate) mod question;
#[cfg(not(feature = "student"))]
pub mod remote;
#[cfg(feature = "student")]
pub(crate) mod remote;
#[cfg(not(feature = "student"))]
pub mod sampled;
#[cfg(feature = "student")]
pub(crate) mod sampled;
#[cfg(not(target_arch = "wasm32"))]
pub(crate) mod seccomp;
#[cfg(not(feature = "student"))]
pub mod serve;
#[cfg(feature = "student")]
pub(crate) mod serve;

/// Declares each chapter's cases, its folder's `checks.rs`, as a module of
/// the judge: they live beside the chapter's code so that a chapter is its
/// folder, but they are a tool (they use the judge's builders and oracle),
/// and the engine's chapter modules must not reach up to them.
macro_rules! declare_by_chapter {
    (($($visibility:tt)*) $($number:literal $module:ident $folder:literal $title:literal $adds:literal
       |$effects:ident| $switch_on:block [$($function:ident),*] $(kept { $($kept:path),* })?
       $(asks { $($asked:ident($asked_kind:ident)),* $(,)? })?
       $(shades |$when:ident| $condition:expr => $shade:expr)?;)*) => {
        /// The kinds of question a chapter's registry line names in its
        /// `asks` clause, its folder's `kinds.rs`: below the builders and
        /// the enum of kinds ([`question`]), so that the enum can name
        /// them and the chapter's `checks.rs` build cases of them.
        #[path = "../../chapters"]
        $($visibility)* mod chapter_kinds {
            $($(
                #[path = $folder]
                #[doc(hidden)]
                pub mod $module {
                    $(#[doc = concat!("Asks `", stringify!($asked_kind), "`.")])*
                    pub mod kinds;
                    pub use kinds::*;
                }
            )?)*
        }

        /// Each chapter's two lists of cases, its folder's `checks.rs`, and
        /// the table of them by chapter number, from the registry.
        #[path = "../../chapters"]
        $($visibility)* mod by_chapter {
            use super::Case;

            $(
                #[path = $folder]
                #[doc(hidden)]
                pub mod $module {
                    pub mod checks;
                }
            )*

            /// Chapter `number`'s checkpoints (level 1); none for an unknown chapter.
            /// Building them may use raylab's answers (a point on a sphere, by
            /// its intersection): that is raylab's own use, not the student's.
            pub fn checkpoints(number: u8) -> Vec<Case> {
                crate::answer_key::raylab_own(|| match number {
                    $($number => $module::checks::checkpoints(),)*
                    _ => Vec::new(),
                })
            }

            /// Chapter `number`'s hint for an image that fails when every
            /// checkpoint passes (each chapter's `IMAGE_HINT`).
            pub fn image_hint(number: u8) -> &'static str {
                match number {
                    $($number => $module::checks::IMAGE_HINT,)*
                    _ => "",
                }
            }

            /// Chapter `number`'s hard cases (level 2); none for an unknown
            /// chapter. Whatever level a chapter's file gave them, these are
            /// hard cases: judged and reported as robustness.
            pub fn robustness(number: u8) -> Vec<Case> {
                super::catalog::robust(crate::answer_key::raylab_own(|| match number {
                    $($number => $module::checks::robustness(),)*
                    _ => Vec::new(),
                }))
            }
        }
    };
}

// Public where the judge's modules are: a student workspace's build names
// none of the cases (see below).
#[cfg(not(feature = "student"))]
macro_rules! chapter_checks {
    ($($line:tt)*) => { declare_by_chapter! { (pub) $($line)* } };
}
#[cfg(feature = "student")]
macro_rules! chapter_checks {
    ($($line:tt)*) => { declare_by_chapter! { (pub(crate)) $($line)* } };
}

crate::for_each_chapter!(chapter_checks);

use std::fmt::Write as _;
use std::path::PathBuf;

pub use cases::{Level, Outcome, TreeShape};
pub use judge::{REQUIRE_ROBUST_VAR, assert_chapter};
#[cfg(not(feature = "student"))]
pub use judge::{check_all, check_chapter};
#[cfg(feature = "student")]
pub(crate) use judge::{check_all, check_chapter};
pub use panics::Panic;
pub use question::{Case, CaseKind};

use crate::diff::{Criteria, Metrics};

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
    /// Fresh inputs drawn from this seed for every parametrised case and
    /// for each chapter's camera (`grade --code --fresh SEED`); `None`:
    /// the lessons' own inputs.
    pub fresh: Option<u64>,
    /// Stop asking a chapter's checkpoints at the first that fails (not
    /// one left unwritten: a `todo!()` is still told apart from a wrong
    /// answer): the verdict names the same case, but counts as passed only
    /// the checkpoints before it. For raylab's bug galleries, which assert
    /// which case catches each bug; a student is told how many pass.
    pub first_failure_only: bool,
    /// Chapters 1 to this one, before the chapter checked alone
    /// ([`judge::Which::One`]), are taken as passing without being asked:
    /// set by [`planted::check_chapter`] for a variant that changes
    /// nothing in them. 0: every earlier chapter is asked.
    pub earlier_known_to_pass: u8,
}

impl Default for CheckOptions {
    fn default() -> CheckOptions {
        CheckOptions {
            failures_dir: PathBuf::from("check-failures"),
            write_images: true,
            forbid_answer_key: false,
            fresh: None,
            first_failure_only: false,
            earlier_known_to_pass: 0,
        }
    }
}

/// Why the judge stopped asking before the end.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Stopped {
    /// The time limit passed.
    TimedOut,
    /// The binary does not answer raylab's questions (or another
    /// version's), as the message says.
    Refused(String),
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
    /// Whether its inputs were drawn afresh (`grade --code --fresh`).
    pub drawn: bool,
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
    /// The camera it was seen from under `--fresh` (the reference then
    /// raylab's own render of that view); `None`: the scene's own.
    pub view: Option<protocol::View>,
}

/// The robustness level's result.
#[derive(Debug, Clone, PartialEq)]
pub struct Robustness {
    pub passed: usize,
    pub total: usize,
    pub first_failure: Option<CaseFailure>,
    /// The other hard cases that failed, by number (from 1) and name:
    /// a student fixing one at a time sees what is left.
    pub also_failing: Vec<(usize, &'static str)>,
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
    pub answers_used: Vec<String>,
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
                    by_chapter::image_hint(self.chapter),
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
    let mut out = image_comparison_text(image);
    // Where the camera went is not printed: a grading round that used the
    // same seed again would then have a view known in advance.
    if image.view.is_some() {
        let _ = writeln!(
            out,
            "    (--fresh: the scene seen from a camera turned a few degrees; the reference is \
             raylab's own render of that view)"
        );
    }
    out
}

/// The image's comparison lines.
fn image_comparison_text(image: &ImageCheck) -> String {
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
        if !robustness.also_failing.is_empty() {
            let names: Vec<String> = robustness
                .also_failing
                .iter()
                .map(|(number, name)| format!("{number} ({name})"))
                .collect();
            let _ = writeln!(
                out,
                "  also failing: hard case{} {}",
                if names.len() == 1 { "" } else { "s" },
                names.join(", ")
            );
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
    if failure.drawn {
        let _ = writeln!(
            out,
            "    (with fresh inputs, in the call below; the lesson's case: {})",
            failure.says
        );
    } else {
        let _ = writeln!(out, "    {}", failure.says);
    }
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
                crate::text::one_line(panic.location.as_deref().unwrap_or("an unknown place"))
            );
        }
        Outcome::Panicked(panic) => {
            let _ = writeln!(
                out,
                "    got:      a panic: {}{}",
                crate::text::one_line(&panic.message),
                panic
                    .location
                    .as_deref()
                    .map(|l| format!(" (at {})", crate::text::one_line(l)))
                    .unwrap_or_default()
            );
        }
        Outcome::Error(error) => {
            let _ = writeln!(
                out,
                "    the check could not run: {}",
                crate::text::one_line(error)
            );
        }
        Outcome::Ended(how) => {
            let _ = writeln!(
                out,
                "    got:      no answer: the process {} while working it out \
                 (std::process::exit, abort or a stack overflow in a chapter's function \
                 end the process; each function must return its answer)",
                crate::text::terminal_safe(how)
            );
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
    /// Why the judge stopped asking before the end, if it did.
    pub stopped: Option<Stopped>,
}

impl CheckReport {
    /// Whether every checked chapter passes, one fails (or is not
    /// started), or the check could not run.
    pub fn overall(&self) -> Overall {
        if self.stopped.is_some()
            || self
                .verdicts
                .iter()
                .any(|v| v.status == Status::Error || !v.errors.is_empty())
        {
            Overall::Error
        } else if !self.verdicts.is_empty() && self.verdicts.iter().all(ChapterVerdict::passes) {
            // A run that judged nothing has shown nothing.
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

    /// Every verdict, then the table, then why the check stopped. A binary
    /// that answers no question gets the reason alone, once.
    pub fn text(&self) -> String {
        let mut out = String::new();
        if let Some(Stopped::Refused(why)) = &self.stopped {
            let _ = writeln!(out, "no verdict: {}", crate::text::terminal_safe(why));
            return out;
        }
        for verdict in &self.verdicts {
            out.push_str(&verdict.text());
            out.push('\n');
        }
        out.push_str(&self.summary_table());
        match &self.stopped {
            Some(Stopped::TimedOut) => {
                out.push_str("(no verdict: the time limit passed before the check ended)\n");
            }
            Some(Stopped::Refused(why)) => {
                let _ = writeln!(out, "(no verdict: {})", crate::text::terminal_safe(why));
            }
            None => {}
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chapters::CHAPTERS;
    use judge::case_failure;

    #[test]
    fn the_reference_passes_every_checkpoint_and_hard_case() {
        for info in CHAPTERS {
            for case in by_chapter::checkpoints(info.number)
                .iter()
                .chain(&by_chapter::robustness(info.number))
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
    fn a_verdict_names_every_failing_hard_case() {
        let robustness = Robustness {
            passed: 25,
            total: 28,
            first_failure: None,
            also_failing: vec![(7, "grazing"), (12, "far-tiny")],
        };
        let text = robustness_text(&robustness);
        assert!(
            text.contains("also failing: hard cases 7 (grazing), 12 (far-tiny)"),
            "{text}"
        );
        let one = Robustness {
            also_failing: vec![(7, "grazing")],
            ..robustness
        };
        assert!(
            robustness_text(&one).contains("also failing: hard case 7 (grazing)\n"),
            "{}",
            robustness_text(&one)
        );
    }

    #[test]
    fn hard_cases_are_reported_as_robustness() {
        for info in CHAPTERS {
            let hard = by_chapter::robustness(info.number);
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
                by_chapter::checkpoints(info.number)
                    .into_iter()
                    .chain(by_chapter::robustness(info.number))
                    .map(|case| case.name)
            })
            .collect();
        let count = names.len();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), count);
    }
}
