//! The judge: raylab's own code deciding every verdict.
//!
//! Autograders that count for marks keep the harness trusted and the
//! submission an untrusted subprocess (Gradescope, Autolab, PrairieLearn);
//! so does this. The judge holds the cases, draws their inputs, works out
//! the expected answers ([`crate::check::exact`], raylab's reference
//! chapters) and compares; the chapters under check only answer questions
//! through an [`Asker`]. For a student's chapters that is [`Remote`]: their
//! own binary started as `serve` ([`super::serve`]), one process per
//! chapter, spoken to over a pipe ([`super::protocol`]). Nothing that
//! process prints, writes or exits with is read, and it never sees an
//! expected value. A process that ends while answering fails the case it
//! was answering, and the next question starts a new one. raylab's own
//! checks of its reference and of its variants ask in this process
//! ([`InProcess`]), through the same two halves of every case.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Vec3;

// The judge's interface: whoever drives it names these from here.
pub use super::asker::{Asker, Ended, Step};
use super::cases::Draw;
use super::cases::{Level, Outcome};
use super::panics::Panic;
use super::protocol::{Answered, Hello, Reply, Request, View};
use super::question::Case;
use super::remote::{Remote, Spawn};
use super::{
    CaseFailure, ChapterVerdict, CheckOptions, CheckReport, ImageCheck, Robustness, Status,
    Stopped, by_chapter, sampled,
};
use crate::Chapters;
use crate::chapters::{CHAPTERS, ChapterInfo, REFERENCE_HEIGHT, REFERENCE_WIDTH};
use crate::diff::{Criteria, Image, compare};

/// Makes an [`Asker`]: one per chapter checked at once.
pub type MakeAsker<'a> = dyn Fn() -> Box<dyn Asker + Send> + Sync + 'a;

/// The chapters `C`, asked in this process: raylab's own checks of its
/// reference and of its variants.
pub struct InProcess<C>(std::marker::PhantomData<C>);

impl<C> Default for InProcess<C> {
    fn default() -> Self {
        InProcess(std::marker::PhantomData)
    }
}

impl<C: Chapters> Asker for InProcess<C> {
    fn ask(&mut self, request: &Request, _step: &Step) -> Result<Reply, Ended> {
        Ok(super::serve::answer::<C>(request))
    }
}

/// What the answers of one chapter's check brought beside them.
#[derive(Default)]
struct Collected {
    /// raylab's answers that ran on the answering thread.
    used: Vec<String>,
    /// Those that ran on threads of the chapters' own.
    escaped: Vec<String>,
    /// Why the judge stopped asking, if it did.
    stopped: Option<Stopped>,
    /// Whether the chapters are a comparison wrapper of raylab's.
    comparison: bool,
}

impl Collected {
    fn take(&mut self, used: Vec<String>, escaped: Vec<String>) {
        for answer in used {
            if !self.used.contains(&answer) {
                self.used.push(answer);
            }
        }
        for answer in escaped {
            if !self.escaped.contains(&answer) {
                self.escaped.push(answer);
            }
        }
    }

    /// The outcome of asking a case: the judge's, or why there is none.
    fn case(&mut self, asked: Result<Reply, Ended>, case: &Case) -> Outcome {
        match asked {
            Ok(Reply::Answer {
                answer,
                used,
                escaped,
            }) => {
                self.take(used, escaped);
                match answer {
                    Answered::Case(answer) => case.judge(answer),
                    Answered::Panicked(panic) if panic.is_todo() => Outcome::Todo(panic),
                    Answered::Panicked(panic) => Outcome::Panicked(panic),
                    Answered::Error(error) => Outcome::Error(error),
                    Answered::Pixels(_) | Answered::Rgb { .. } => not_an_answer(),
                }
            }
            Ok(Reply::Hello { .. }) => not_an_answer(),
            Err(ended) => self.ended(ended),
        }
    }

    fn ended(&mut self, ended: Ended) -> Outcome {
        match ended {
            Ended::Died(how) => Outcome::Ended(how),
            Ended::TimedOut => {
                self.stopped = Some(Stopped::TimedOut);
                Outcome::Error("the time limit passed".into())
            }
            Ended::Refused(why) => {
                self.stopped = Some(Stopped::Refused(why.clone()));
                Outcome::Error(why)
            }
        }
    }
}

fn not_an_answer() -> Outcome {
    Outcome::Fail {
        expected: "the answer to the question asked".into(),
        got: "a reply to another question".into(),
    }
}

/// Which chapter a panic belongs to: the chapter file it happened in, or
/// else the chapter a skeleton's `todo!("chapter N: name")` names.
fn owner(panic: &Panic) -> Option<u8> {
    let by_file = panic.file.as_deref().and_then(|file| {
        CHAPTERS
            .iter()
            .find(|info| {
                file.contains(&info.module()) || file.contains(&format!("{}/", info.folder))
            })
            .map(|info| info.number)
    });
    by_file.or_else(|| {
        let said = panic
            .message
            .strip_prefix("not yet implemented: chapter ")?;
        let number: u8 = said.split(':').next()?.trim().parse().ok()?;
        crate::chapters::chapter(number).map(|info| info.number)
    })
}

/// Chapter `number`'s checkpoints; under `fresh`, each parametrised one
/// followed by its copy with fresh inputs, so that the lesson's exact
/// numbers keep their bite and no table of answers to them passes. A
/// statistical case is replaced by its copy instead: its stream has no
/// bite of its own, and asking twice would double its false alarms.
fn checkpoints(number: u8, fresh: Option<u64>) -> Vec<Case> {
    let cases = by_chapter::checkpoints(number);
    let Some(seed) = fresh else {
        return cases;
    };
    crate::answer_key::raylab_own(|| {
        let mut asked = Vec::with_capacity(2 * cases.len());
        for case in cases {
            match case.fresh(seed) {
                Some(drawn) if case.kind.statistical() => asked.push(drawn),
                Some(drawn) => asked.extend([case, drawn]),
                None => asked.push(case),
            }
        }
        asked
    })
}

/// Asks each of `cases`: how many pass, and those that do not.
fn run_cases(
    info: &ChapterInfo,
    cases: &[Case],
    first_failure_only: bool,
    asker: &mut dyn Asker,
    collected: &mut Collected,
) -> (usize, Vec<(usize, Outcome)>) {
    let mut passed = 0;
    let mut failures = Vec::new();
    for (index, case) in cases.iter().enumerate() {
        if first_failure_only
            && failures
                .iter()
                .any(|(_, outcome)| !matches!(outcome, Outcome::Todo(_)))
        {
            break;
        }
        let outcome = if collected.stopped.is_some() {
            Outcome::Error("not asked: the check stopped".into())
        } else {
            let step = Step {
                chapter: info.number,
                function: case.function().to_string(),
                case: case.name.to_string(),
            };
            let asked = asker.ask(&Request::Case(case.kind.call()), &step);
            collected.case(asked, case)
        };
        match outcome {
            Outcome::Pass => passed += 1,
            outcome => failures.push((index, outcome)),
        }
    }
    (passed, failures)
}

pub(super) fn case_failure(
    info: &ChapterInfo,
    cases: &[Case],
    index: usize,
    outcome: Outcome,
) -> CaseFailure {
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
        drawn: case.drawn,
    }
}

/// The chapter's lesson where this raylab's checkout has it (a student
/// runs the check in their own workspace, where a path relative to raylab
/// would name nothing).
pub(super) fn lesson(info: &ChapterInfo) -> String {
    let checkout = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = checkout.join(info.lesson_path());
    if path.is_file() {
        path.display().to_string()
    } else {
        info.lesson_path()
    }
}

/// Chapter `info`'s own verdict (not yet looking at earlier chapters),
/// asking `asker`. `full`: also the image and the robustness cases. With
/// [`CheckOptions::forbid_answer_key`], a chapter whose code ran raylab's
/// own answers fails, whatever its cases said.
fn own_verdict(
    info: &ChapterInfo,
    options: &CheckOptions,
    full: bool,
    asker: &mut dyn Asker,
) -> (ChapterVerdict, Collected) {
    let mut collected = Collected::default();
    let hello = Step {
        chapter: info.number,
        function: "hello".into(),
        case: "the chapters starting".into(),
    };
    match asker.ask(&Request::Hello(Hello::ours()), &hello) {
        Ok(Reply::Hello { comparison, .. }) => collected.comparison = comparison,
        Ok(_) => {}
        Err(ended) => {
            collected.ended(ended);
        }
    }
    let mut verdict = cases_image_robustness(info, options, full, asker, &mut collected);
    if let Some(Stopped::Refused(why)) = &collected.stopped {
        verdict.status = Status::Error;
        verdict.first_failure = None;
        if !verdict.errors.contains(why) {
            verdict.errors = vec![why.clone()];
        }
        return (verdict, collected);
    }
    if !options.forbid_answer_key {
        return (verdict, collected);
    }
    let mut answers = std::mem::take(&mut collected.used);
    if collected.comparison {
        answers.insert(0, "a comparison wrapper of raylab's (Textbook)".into());
    }
    if !answers.is_empty() && verdict.status != Status::Error {
        verdict.status = Status::Fail;
        verdict.answers_used = answers;
    }
    (verdict, collected)
}

/// [`own_verdict`] but for the answer key.
fn cases_image_robustness(
    info: &ChapterInfo,
    options: &CheckOptions,
    full: bool,
    asker: &mut dyn Asker,
    collected: &mut Collected,
) -> ChapterVerdict {
    let chapter = info.number;
    let cases = checkpoints(info.number, options.fresh);
    let (passed, failures) = run_cases(info, &cases, options.first_failure_only, asker, collected);
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
    if !full || collected.stopped.is_some() {
        return verdict;
    }
    judge_image(info, options, cases.len(), &mut verdict, asker, collected);
    if verdict.status == Status::Pass && collected.stopped.is_none() {
        verdict.robustness = Some(run_robustness(info, asker, collected));
    }
    verdict
}

/// Asks for the chapter's image and judges it into `verdict`, once its
/// `cases` checkpoints pass.
fn judge_image(
    info: &ChapterInfo,
    options: &CheckOptions,
    cases: usize,
    verdict: &mut ChapterVerdict,
    asker: &mut dyn Asker,
    collected: &mut Collected,
) {
    let step = Step {
        chapter: info.number,
        function: "the whole stage".into(),
        case: "the chapter's image".into(),
    };
    let view = match options.fresh.map(|seed| fresh_view(info.number, seed)) {
        Some(Err(error)) => {
            verdict.status = Status::Error;
            verdict.errors.push(error);
            return;
        }
        Some(Ok(view)) => Some(view),
        None => None,
    };
    let asked = asker.ask(
        &Request::Image {
            chapter: info.number,
            view,
        },
        &step,
    );
    let linear = match asked {
        Ok(Reply::Answer {
            answer,
            used,
            escaped,
        }) => {
            collected.take(used, escaped);
            match answer {
                Answered::Pixels(linear) => linear,
                Answered::Panicked(panic) => {
                    let (status, failure) = image_panic(info, cases, Outcome::from_panic(panic));
                    verdict.status = status;
                    verdict.first_failure = Some(failure);
                    return;
                }
                Answered::Error(error) => {
                    verdict.status = Status::Error;
                    verdict.errors.push(error);
                    return;
                }
                Answered::Case(_) | Answered::Rgb { .. } => {
                    let (status, failure) = image_panic(info, cases, not_an_answer());
                    verdict.status = status;
                    verdict.first_failure = Some(failure);
                    return;
                }
            }
        }
        Ok(Reply::Hello { .. }) => {
            let (status, failure) = image_panic(info, cases, not_an_answer());
            verdict.status = status;
            verdict.first_failure = Some(failure);
            return;
        }
        Err(ended) => {
            let outcome = collected.ended(ended);
            if let Outcome::Error(error) = outcome {
                verdict.status = Status::Error;
                verdict.errors.push(error);
            } else {
                let (status, failure) = image_panic(info, cases, outcome);
                verdict.status = status;
                verdict.first_failure = Some(failure);
            }
            return;
        }
    };
    match compare_image(info, options, view.as_ref(), &linear) {
        Ok(image) => {
            if !image.passed {
                verdict.status = Status::Fail;
            }
            verdict.image = Some(image);
        }
        Err(error) => {
            verdict.status = Status::Error;
            verdict.errors.push(error);
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

/// The chapter's hard cases, asked once its checkpoints and image pass.
fn run_robustness(
    info: &ChapterInfo,
    asker: &mut dyn Asker,
    collected: &mut Collected,
) -> Robustness {
    let hard = by_chapter::robustness(info.number);
    let (passed, failures) = run_cases(info, &hard, false, asker, collected);
    let also_failing = failures
        .iter()
        .skip(1)
        .map(|(index, _)| (index + 1, hard[*index].name))
        .collect();
    Robustness {
        passed,
        total: hard.len(),
        first_failure: failures
            .into_iter()
            .next()
            .map(|(index, outcome)| case_failure(info, &hard, index, outcome)),
        also_failing,
    }
}

/// The status and the failure of a chapter whose `cases` checkpoints
/// passed but whose image could not be had: `outcome` says why (a panic,
/// a process that ended).
fn image_panic(info: &ChapterInfo, cases: usize, outcome: Outcome) -> (Status, CaseFailure) {
    let chapter = info.number;
    // The chapter's own cases passed, so a todo!() met while
    // rendering is in an earlier chapter: by its file when the
    // panic says, else (0) the first earlier chapter not passing.
    let status = match &outcome {
        Outcome::Todo(panic) => match owner(panic) {
            Some(earlier) if earlier < chapter => Status::Blocked { by: earlier },
            None => Status::Blocked { by: 0 },
            _ => Status::Fail,
        },
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
        outcome,
        lesson: lesson(info),
        section: "What the picture shows",
        drawn: false,
    };
    (status, failure)
}

fn srgb(linear: &[Vec3]) -> Vec<u8> {
    linear
        .iter()
        .flat_map(|color| color.to_array().map(crate::output::linear_to_srgb8))
        .collect()
}

/// Chapter `chapter`'s image's camera under `--fresh SEED`: the built-in
/// scene's, turned about what it looks at ([`Draw::view`]).
fn fresh_view(chapter: u8, seed: u64) -> Result<View, String> {
    let camera = crate::builtin::scene(chapter)
        .map_err(|error| error.to_string())?
        .camera;
    Ok(turned_view(
        &camera,
        seed,
        &format!("chapter {chapter}'s image"),
    ))
}

/// `camera` turned about what it looks at, as `--fresh SEED` turns it,
/// drawn for the case called `name`.
pub fn turned_view(camera: &crate::scene::CameraSpec, seed: u64, name: &str) -> View {
    let mut draw = Draw::for_case(seed, name);
    View {
        position: draw
            .view(camera.position, camera.look_at, camera.up)
            .to_array(),
        look_at: camera.look_at.to_array(),
    }
}

/// Compares the student's `linear` image with the reference (or, for a
/// sampled stage, judges it within the noise of the converged one), and
/// writes the failure images. Seen from `view` (`--fresh`), the reference
/// is raylab's own render of that view, not the shipped image.
fn compare_image(
    info: &ChapterInfo,
    options: &CheckOptions,
    view: Option<&View>,
    linear: &[Vec3],
) -> Result<ImageCheck, String> {
    if linear.len() != (REFERENCE_WIDTH * REFERENCE_HEIGHT) as usize {
        return Err(format!(
            "the image came with {} pixels, not {REFERENCE_WIDTH}x{REFERENCE_HEIGHT}",
            linear.len()
        ));
    }
    let scene = super::serve::viewed_scene(info.number, view)?;
    let settings = super::serve::image_settings(&scene);
    // raylab's own stage of the scene: what it simulates and how many
    // samples it takes depend on the scene and the chapter alone.
    let stage = crate::answer_key::raylab_own(|| {
        crate::Stage::<crate::Reference>::with_chapters(&scene, info.number, settings)
    })
    .map_err(|error| error.to_string())?;
    let noise = if sampled::is_sampled(&stage, &settings) {
        let converged = sampled::converged(info, view, &scene, settings)?;
        if stage.effects.path_tracing {
            let side = sampled::PATH_BLOCK;
            let blocks = sampled::block_means(linear, REFERENCE_WIDTH, side);
            let mut noise = sampled::judge(&blocks, stage.samples(), &converged.blocks(side));
            noise.block = side;
            noise.allowed =
                sampled::allowed_block_outliers(blocks.len(), stage.effects.light_tracing);
            // The first block's top-left pixel.
            noise.first = noise.first.map(|(x, y)| (x * side, y * side));
            Some(noise)
        } else {
            Some(sampled::judge(linear, stage.samples(), &converged))
        }
    } else {
        None
    };
    let student = Image {
        width: REFERENCE_WIDTH,
        height: REFERENCE_HEIGHT,
        rgb: srgb(linear),
    };
    let reference = match view {
        None => Image::decode_png(info.reference_png)
            .map_err(|error| format!("the shipped reference image: {error:#}"))?,
        Some(view) => Image {
            width: REFERENCE_WIDTH,
            height: REFERENCE_HEIGHT,
            rgb: srgb(&crate::answer_key::raylab_own(|| {
                super::serve::image::<crate::Reference>(info.number, Some(view))
            })?),
        },
    };
    let comparison = compare(
        &student,
        &reference,
        Criteria::default(),
        ("your image", "the reference"),
    )
    .map_err(|error| format!("{error:#}"))?;
    let passed = match &noise {
        Some(noise) => noise.passes(),
        None => comparison.passes(),
    };
    let mut written = Vec::new();
    if !passed && options.write_images {
        written = write_failure_images(info.number, &options.failures_dir, &student, &comparison)?;
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
    Ok(ImageCheck {
        metrics: comparison.metrics,
        noise,
        passed,
        written,
        view: view.copied(),
    })
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

/// Fails the verdicts whose checks ran raylab's answers on threads the
/// code under check started, out of reach of the recording of the thread
/// that answered: each answer fails the chapter it belongs to where that
/// chapter is among `verdicts`, or else every verdict, since any of their
/// checks may have run it.
fn fail_for_escaped_answers(
    verdicts: &mut [ChapterVerdict],
    escaped: &[String],
    options: &CheckOptions,
) {
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
                if !verdict.answers_used.contains(answer) {
                    verdict.answers_used.push(answer.clone());
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

pub(crate) fn unknown_chapter(chapter: u8) -> ChapterVerdict {
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

/// The refusal of the judge's entry points inside a student's process
/// answering questions ([`super::serve`]).
fn refuse_inside_the_student_process() -> Option<CheckReport> {
    super::serve::serving().then(|| CheckReport {
        verdicts: Vec::new(),
        stopped: Some(Stopped::Refused(
            "the check does not run inside a chapter's code".into(),
        )),
    })
}

/// Which chapters a check judges.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Which {
    /// Every chapter.
    All,
    /// This one, with the cases of those it builds on (to say whether it
    /// waits for one of them); only its verdict is reported.
    One(u8),
    /// Every chapter from 1 to this one, each in full.
    UpTo(u8),
}

impl Which {
    /// Chapter `chapter` alone, or every chapter.
    pub fn one_or_all(chapter: Option<u8>) -> Which {
        chapter.map_or(Which::All, Which::One)
    }
}

/// Judges the chapters `which` says, asking each chapter's questions of an
/// asker `make` makes: chapters are checked at once, one thread and one
/// asker each.
pub fn judge(make: &MakeAsker, which: Which, options: &CheckOptions) -> CheckReport {
    if let Some(refused) = refuse_inside_the_student_process() {
        return refused;
    }
    let (last, reported) = match which {
        Which::All => (crate::chapters::LAST_CHAPTER, None),
        Which::One(chapter) => (chapter, Some(chapter)),
        Which::UpTo(chapter) => (chapter, None),
    };
    if crate::chapters::chapter(last).is_none() {
        return CheckReport {
            verdicts: vec![unknown_chapter(last)],
            stopped: None,
        };
    }
    // Chapters taken as passing are left out: only their passing matters
    // to the chapter reported, and that is given.
    let known_to_pass = |number: u8| {
        reported.is_some_and(|chapter| number < chapter && number <= options.earlier_known_to_pass)
    };
    let numbers: Vec<u8> = CHAPTERS
        .iter()
        .map(|info| info.number)
        .filter(|&number| number <= last && !known_to_pass(number))
        .collect();
    let asked: Vec<(ChapterVerdict, Collected)> = std::thread::scope(|scope| {
        let handles: Vec<_> = numbers
            .iter()
            .map(|&number| {
                scope.spawn(move || {
                    let info = crate::chapters::chapter(number)?;
                    // The chapters before the one asked for: their cases
                    // only, to say whether it waits for them.
                    let full = reported.is_none_or(|chapter| chapter == number);
                    let mut asker = make();
                    Some(own_verdict(info, options, full, asker.as_mut()))
                })
            })
            .collect();
        handles
            .into_iter()
            .zip(&numbers)
            .map(|(handle, &number)| {
                // Student panics are caught where they happen; a panic here
                // would be raylab's own bug, reported as an error.
                handle.join().ok().flatten().unwrap_or_else(|| {
                    let mut verdict = unknown_chapter(number);
                    verdict.errors = vec!["the check itself panicked".into()];
                    (verdict, Collected::default())
                })
            })
            .collect()
    });
    let mut escaped = Vec::new();
    let mut stopped = None;
    let mut verdicts = Vec::new();
    for (verdict, collected) in asked {
        for answer in collected.escaped {
            if !escaped.contains(&answer) {
                escaped.push(answer);
            }
        }
        stopped = stopped.or(collected.stopped);
        verdicts.push(verdict);
    }
    // Before the prerequisites, so that the chapters after one that ran
    // raylab's answer on a thread of its own wait for it, as for any fail.
    fail_for_escaped_answers(&mut verdicts, &escaped, options);
    let statuses: Vec<(u8, Status)> = verdicts.iter().map(|v| (v.chapter, v.status)).collect();
    for verdict in &mut verdicts {
        let earlier: Vec<(u8, Status)> = statuses
            .iter()
            .copied()
            .filter(|(chapter, _)| *chapter < verdict.chapter)
            .collect();
        apply_prerequisites(verdict, &earlier);
    }
    if let Some(chapter) = reported {
        verdicts.retain(|verdict| verdict.chapter == chapter);
    }
    CheckReport { verdicts, stopped }
}

/// The verdict on chapter `chapter` of the chapters `C`, asked in this
/// process (raylab's own checks of its reference and its variants): its
/// cases, its image, its robustness, and whether the chapters before it
/// pass their cases. An unknown chapter is an error verdict.
pub fn check_chapter<C: Chapters>(chapter: u8, options: &CheckOptions) -> ChapterVerdict {
    let make = || Box::new(InProcess::<C>::default()) as Box<dyn Asker + Send>;
    judge(&make, Which::One(chapter), options)
        .verdicts
        .pop()
        .unwrap_or_else(|| unknown_chapter(chapter))
}

/// [`check_chapter`] for chapter `chapters`, or for every chapter.
pub fn check_all<C: Chapters>(chapters: Option<u8>, options: &CheckOptions) -> CheckReport {
    let make = || Box::new(InProcess::<C>::default()) as Box<dyn Asker + Send>;
    judge(&make, Which::one_or_all(chapters), options)
}

/// Set to `1`, [`assert_chapter`] also demands the robustness level: what
/// `scripts/mutation-score.sh` sets, so that a mutant only the hard cases
/// notice counts as caught.
pub const REQUIRE_ROBUST_VAR: &str = "RAYLAB_CHECK_ROBUST";

/// Panics with the verdict's text unless chapter `chapter` (and every
/// chapter it builds on) passes, the chapters answering in `binary`, a
/// student workspace's own, started as `serve`: a workspace's `cargo
/// test` has one test per chapter that calls this with
/// `env!("CARGO_BIN_EXE_...")`. Robustness is reported apart, as by
/// `check`, unless [`REQUIRE_ROBUST_VAR`] is `1`.
///
/// In a student's build, raylab's own binary judges (see
/// [`super::own_binary`]): this runs its `check`, which asks `binary`.
#[cfg(feature = "student")]
pub fn assert_chapter(binary: &str, chapter: u8) {
    // A test cannot print: cargo's own progress, on standard error, says
    // that raylab is being built.
    let judge = match super::own_binary::judge_binary(&|| ()) {
        Ok(judge) => judge,
        Err(error) => panic!("\n{error}"),
    };
    let mut command = std::process::Command::new(&judge);
    command
        .arg("check")
        .arg("--answers-from")
        .arg(binary)
        .arg("--chapter")
        .arg(chapter.to_string())
        .stdin(std::process::Stdio::null());
    if std::env::var_os(REQUIRE_ROBUST_VAR).is_some_and(|v| v == "1") {
        command.arg("--require-robust");
    }
    let output = match command.output() {
        Ok(output) => output,
        Err(error) => panic!("\ncannot run raylab's judge {}: {error}", judge.display()),
    };
    if !output.status.success() {
        panic!(
            "\n{}{}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
    }
}

/// [`assert_chapter`] in raylab's own build: this process judges.
#[cfg(not(feature = "student"))]
pub fn assert_chapter(binary: &str, chapter: u8) {
    let binary = PathBuf::from(binary);
    let spawn: Arc<Spawn> = Arc::new(move || {
        let mut command = std::process::Command::new(&binary);
        command.arg("serve");
        Ok((command, Box::new(()) as Box<dyn std::any::Any + Send>))
    });
    let make =
        || Box::new(Remote::new(Arc::clone(&spawn)).inheriting_stderr()) as Box<dyn Asker + Send>;
    let options = CheckOptions {
        forbid_answer_key: true,
        ..CheckOptions::default()
    };
    let report = judge(&make, Which::One(chapter), &options);
    let require_robust = std::env::var_os(REQUIRE_ROBUST_VAR).is_some_and(|v| v == "1");
    let verdict = report.verdicts.first();
    let passes = verdict.is_some_and(|verdict| {
        verdict.passes() && (!require_robust || verdict.robust()) && report.stopped.is_none()
    });
    if !passes {
        panic!("\n{}", report.text());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Reference;

    /// Under `--fresh`, every parametrised checkpoint is drawn anew and the
    /// reference still passes it, for every seed tried: a draw keeps the
    /// case's meaning. Every function of every chapter has at least one
    /// such checkpoint, so that no function's answers can be tabulated in
    /// advance. A statistical case costs a second or more: fewer seeds.
    #[test]
    fn fresh_checkpoints_keep_their_meaning_and_cover_every_function() {
        let mut wrong = Vec::new();
        for info in CHAPTERS {
            let cases = by_chapter::checkpoints(info.number);
            for function in info.functions {
                let drawn = cases
                    .iter()
                    .any(|case| case.function() == *function && case.fresh(1).is_some());
                // A function every case reaches only through another (the
                // shading a scene case asks) is drawn through that one.
                let reached = cases.iter().any(|case| case.function() == *function);
                if reached && !drawn {
                    wrong.push(format!(
                        "chapter {}: no checkpoint of {function} has fresh inputs",
                        info.number
                    ));
                }
            }
            for case in &cases {
                let statistical = matches!(
                    case.kind,
                    super::super::CaseKind::Converges(_)
                        | super::super::CaseKind::LightConverges(_)
                        | super::super::CaseKind::Lens(_)
                        | super::super::CaseKind::CosineSample(_)
                        | super::super::CaseKind::Dispersion(_)
                );
                let seeds: &[u64] = if statistical {
                    &[1]
                } else {
                    &[1, 2, 3, 4, 5, 6, 7, 8]
                };
                for &seed in seeds {
                    let Some(fresh) = case.fresh(seed) else {
                        continue;
                    };
                    if format!("{:?}", fresh.kind.call()) == format!("{:?}", case.kind.call()) {
                        wrong.push(format!(
                            "chapter {}: {} drew the same inputs",
                            info.number, case.name
                        ));
                    }
                    let outcome = fresh.run::<Reference>();
                    if outcome != Outcome::Pass {
                        wrong.push(format!(
                            "chapter {}: {} with seed {seed}: {outcome:?}\n    {}",
                            info.number,
                            case.name,
                            fresh.inputs()
                        ));
                        break;
                    }
                }
            }
        }
        assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    }

    /// A chapter's checkpoints call no function of a later chapter: with
    /// every later chapter's functions `todo!()`, each chapter still passes
    /// its own. What lets `planted::check_chapter` take the chapters before
    /// a variant's first planted function as passing, unasked.
    #[test]
    fn a_chapters_checkpoints_call_no_later_chapters_function() {
        use super::super::planted::{Planted, Plants, with_table};
        let options = CheckOptions {
            write_images: false,
            ..CheckOptions::default()
        };
        let mut wrong = Vec::new();
        for info in CHAPTERS {
            let later = Plants::nothing_written().after(info.number);
            let (verdict, _) = with_table(later, || {
                own_verdict(info, &options, false, &mut InProcess::<Planted>::default())
            });
            if verdict.first_failure.is_some() || !verdict.not_written.is_empty() {
                wrong.push(verdict.text());
            }
        }
        assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    }

    /// Every case of every chapter asked over the wire as a student's
    /// process would be: its call encoded and decoded, the answer too. The
    /// reference passes each, so every call and answer survives the trip.
    #[test]
    fn every_case_crosses_the_wire_and_the_reference_passes_it() {
        use super::super::protocol::{read_frame, write_frame};
        for info in CHAPTERS {
            for case in by_chapter::checkpoints(info.number)
                .iter()
                .chain(&by_chapter::robustness(info.number))
            {
                let mut wire = Vec::new();
                write_frame(&mut wire, &Request::Case(case.kind.call())).unwrap();
                let request: Request = read_frame(&mut wire.as_slice()).unwrap();
                let reply = super::super::serve::answer::<Reference>(&request);
                let mut wire = Vec::new();
                write_frame(&mut wire, &reply).unwrap();
                let reply: Reply = read_frame(&mut wire.as_slice()).unwrap();
                let mut collected = Collected::default();
                assert_eq!(
                    collected.case(Ok(reply), case),
                    Outcome::Pass,
                    "chapter {}: {}",
                    info.number,
                    case.name
                );
            }
        }
    }

    /// A process that answers every checkpoint as raylab does but sends,
    /// for the image, the shipped reference's pixels instead of a render
    /// (the references are public): it passes with the lesson's camera and
    /// fails under `--fresh`, whose camera no image made beforehand saw.
    #[test]
    fn a_pasted_reference_image_fails_under_fresh() {
        struct Pasting;
        impl Asker for Pasting {
            fn ask(&mut self, request: &Request, _step: &Step) -> Result<Reply, Ended> {
                let Request::Image { chapter, .. } = request else {
                    return Ok(super::super::serve::answer::<Reference>(request));
                };
                let info = CHAPTERS
                    .iter()
                    .find(|info| info.number == *chapter)
                    .unwrap();
                let shipped = Image::decode_png(info.reference_png).unwrap();
                // Each code's middle, decoded: it encodes back to that code.
                let linear = |code: u8| {
                    let encoded = (f32::from(code) / 255.0 + 0.055) / 1.055;
                    if code < 11 {
                        f32::from(code) / 255.0 / 12.92
                    } else {
                        encoded.powf(2.4)
                    }
                };
                let pixels = shipped
                    .rgb
                    .chunks(3)
                    .map(|rgb| Vec3::new(linear(rgb[0]), linear(rgb[1]), linear(rgb[2])))
                    .collect();
                Ok(Reply::Answer {
                    answer: Answered::Pixels(pixels),
                    used: Vec::new(),
                    escaped: Vec::new(),
                })
            }
        }
        for chapter in [3, 7] {
            let info = CHAPTERS.iter().find(|info| info.number == chapter).unwrap();
            let lesson = CheckOptions {
                write_images: false,
                ..CheckOptions::default()
            };
            let (verdict, _) = own_verdict(info, &lesson, true, &mut Pasting);
            assert!(verdict.passes(), "{}", verdict.text());
            let fresh = CheckOptions {
                fresh: Some(2027),
                ..lesson
            };
            let (verdict, _) = own_verdict(info, &fresh, true, &mut Pasting);
            assert_eq!(verdict.status, Status::Fail, "{}", verdict.text());
            assert!(
                verdict.image.as_ref().is_some_and(|image| !image.passed),
                "{}",
                verdict.text()
            );
            assert!(verdict.text().contains("--fresh: the scene seen from"));
            // raylab's own answers, asked the same, pass the moved view.
            let (verdict, _) =
                own_verdict(info, &fresh, true, &mut InProcess::<Reference>::default());
            assert!(verdict.passes(), "{}", verdict.text());
        }
    }
}
