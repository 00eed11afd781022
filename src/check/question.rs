//! A question as the judge holds it: [`Case`], one question with its
//! expectation, and the enums over every kind of question ([`CaseKind`],
//! the wire's [`Call`] and [`Answer`]).
//!
//! The kinds are those of [`super::cases`], shared by several chapters,
//! and those a chapter's registry line names in its `asks { ... }` clause,
//! defined in its folder's `kinds.rs` ([`super::chapter_kinds`]). Both sit
//! below this module, so a chapter's kinds live in its folder and no list
//! here grows with a chapter.

use super::cases::*;
use super::panics::guarded;
use crate::course::Chapters;

/// The list of kinds, once: it makes [`CaseKind`] (a case), [`Call`] (what
/// the student's process is sent) and [`Answer`] (what it sends back),
/// and the one dispatch of each over them.
macro_rules! kinds {
    ($($variant:ident($case:ty),)*) => {
        /// The question a case asks, one variant per kind of function
        /// (see [`Kind`]).
        #[derive(Debug, Clone)]
        pub enum CaseKind {
            $($variant($case),)*
        }

        /// A case's call as the student's process receives it.
        #[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
        pub enum Call {
            $($variant(<$case as Kind>::Call),)*
        }

        /// The raw answer of the student's process to a [`Call`].
        #[derive(Debug, serde::Serialize, serde::Deserialize)]
        pub enum Answer {
            $($variant(<$case as Kind>::Answer),)*
        }

        impl CaseKind {
            /// The course function this case calls.
            pub fn function(&self) -> &'static str {
                match self {
                    $(CaseKind::$variant(case) => case.function(),)*
                }
            }

            /// The inputs, as the call would receive them.
            pub fn inputs(&self) -> String {
                match self {
                    $(CaseKind::$variant(case) => case.inputs(),)*
                }
            }

            /// What the student's process is sent.
            pub fn call(&self) -> Call {
                match self {
                    $(CaseKind::$variant(case) => Call::$variant(case.call()),)*
                }
            }

            /// Judges `answer` (see [`Kind::judge`]); an answer to another
            /// kind of question fails.
            pub fn judge(&self, answer: Answer, robust: bool) -> Outcome {
                match (self, answer) {
                    $((CaseKind::$variant(case), Answer::$variant(answer)) => {
                        case.judge(answer, robust)
                    })*
                    (_, other) => Outcome::Fail {
                        expected: format!("an answer to {}", self.function()),
                        got: format!("an answer to another question ({})", other.function()),
                    },
                }
            }

            /// The case with fresh inputs (see [`Kind::fresh`]).
            pub fn fresh(&self, draw: &mut Draw) -> Option<CaseKind> {
                match self {
                    $(CaseKind::$variant(case) => case.fresh(draw).map(CaseKind::$variant),)*
                }
            }

            /// Whether the case is statistical (see [`Kind::statistical`]).
            pub fn statistical(&self) -> bool {
                match self {
                    $(CaseKind::$variant(case) => case.statistical(),)*
                }
            }
        }

        impl Call {
            /// Asks the call of the chapters `C` (see [`Kind::ask`]).
            pub fn ask<C: Chapters>(&self) -> Result<Answer, String> {
                match self {
                    $(Call::$variant(call) => <$case as Kind>::ask::<C>(call).map(Answer::$variant),)*
                }
            }
        }

        impl Answer {
            /// The name of the kind of question this answers.
            fn function(&self) -> &'static str {
                match self {
                    $(Answer::$variant(_) => stringify!($variant),)*
                }
            }
        }
    };
}

/// The kinds: [`super::cases`]'s, then those of each chapter's `asks`
/// clause (`chapters/mod.rs`).
macro_rules! declare_questions {
    ($($number:literal $module:ident $folder:literal $title:literal $adds:literal
       |$effects:ident| $switch_on:block [$($function:ident),*] $(kept { $($kept:path),* })?
       $(asks { $($asked:ident($asked_kind:ident)),* $(,)? })?
       $(shades |$when:ident| $condition:expr => $shade:expr)?;)*) => {
        kinds! {
            Plane(PlaneCase),
            Sphere(SphereCase),
            Nearest(NearestCase),
            Offset(OffsetCase),
            Shadow(ShadowCase),
            Shade(ShadeCase),
            PhongTerms(PhongTermsCase),
            Reflect(ReflectCase),
            SampleOffsets(SampleOffsetsCase),
            PixelColor(PixelColorCase),
            Refract(RefractCase),
            Reflectance(ReflectanceCase),
            Transmittance(TransmittanceCase),
            Triangles(TrianglesCase),
            ClosedMesh(ClosedMeshCase),
            Barycentric(BarycentricCase),
            SmoothNormal(SmoothNormalCase),
            Terminator(TerminatorCase),
            SmoothHit(SmoothHitCase),
            HitBox(HitBoxCase),
            BoxEdges(BoxEdgesCase),
            BvhBuild(BvhBuildCase),
            BvhHits(BvhHitsCase),
            HitBoxes(HitBoxesCase),
            FourTriangles(FourTrianglesCase),
            MeshInFours(MeshInFoursCase),
            Collapse(CollapseCase),
            CosineSample(CosineSampleCase),
            PathFormula(PathFormulaCase),
            Converges(ConvergesCase),
            LightFormula(LightFormulaCase),
            LightConverges(LightConvergesCase),
            Lens(LensCase),
            Prism(PrismCase),
            Dispersion(DispersionCase),
            $($($($asked(super::chapter_kinds::$module::$asked_kind),)*)?)*
        }
    };
}

crate::for_each_chapter!(declare_questions);

/// One checkpoint: a question, its expected answer and its tolerance, with
/// the sentence that says it and the lesson section that teaches it.
#[derive(Debug, Clone)]
pub struct Case {
    /// A short stable name (`sphere-direction-not-unit`), for tests and logs.
    pub name: &'static str,
    /// The case in words, with its numbers: what a student reproduces by hand.
    pub says: String,
    /// The heading of the lesson section that teaches it.
    pub section: &'static str,
    pub level: Level,
    pub kind: CaseKind,
    /// Why this checkpoint keeps its inputs under `grade --code --fresh`
    /// (an exact tie, a root exactly at `t_max`: a relation a fresh draw
    /// would not keep), when it does.
    pub fixed: Option<&'static str>,
    /// Whether its inputs were drawn afresh ([`Case::fresh`]): its `says`
    /// is then the lesson's case, and its inputs line the call made.
    pub drawn: bool,
}

impl Case {
    pub fn new(
        name: &'static str,
        section: &'static str,
        says: impl Into<String>,
        kind: CaseKind,
    ) -> Case {
        Case {
            name,
            says: says.into(),
            section,
            level: Level::Checkpoint,
            kind,
            fixed: None,
            drawn: false,
        }
    }

    /// The case, keeping its inputs under `grade --code --fresh` for
    /// `reason`.
    pub fn fixed(self, reason: &'static str) -> Case {
        Case {
            fixed: Some(reason),
            ..self
        }
    }

    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        self.kind.function()
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        self.kind.inputs()
    }

    /// Asks the question of the chapters `C` in this process and judges
    /// the answer: raylab's own checks of its reference and of its
    /// variants (a student's chapters are asked in a process of their own,
    /// see [`crate::check::judge`]).
    pub fn run<C: Chapters>(&self) -> Outcome {
        match guarded(|| self.kind.call().ask::<C>()) {
            Ok(Ok(answer)) => self.judge(answer),
            Ok(Err(error)) => Outcome::Error(error),
            Err(panic) if panic.is_todo() => Outcome::Todo(panic),
            Err(panic) => Outcome::Panicked(panic),
        }
    }

    /// Judges a raw answer to this case's call. A panic of the judge
    /// itself is raylab's bug, reported as an error of the check.
    pub fn judge(&self, answer: Answer) -> Outcome {
        let robust = self.level == Level::Robustness;
        match guarded(|| self.kind.judge(answer, robust)) {
            Ok(outcome) => outcome,
            Err(panic) => Outcome::Error(format!(
                "the judge of case {} panicked: {}",
                self.name, panic.message
            )),
        }
    }

    /// This case with fresh inputs drawn from `seed` (see [`Kind::fresh`]),
    /// or `None` when it keeps its own: every hard case (their inputs are
    /// the hard part), a checkpoint marked [`Case::fixed`], and a kind
    /// with nothing to draw. The draw depends on the seed and the case's
    /// name alone, so it is the same for every student, in any order.
    pub fn fresh(&self, seed: u64) -> Option<Case> {
        if self.level == Level::Robustness || self.fixed.is_some() {
            return None;
        }
        let mut draw = Draw::for_case(seed, self.name);
        self.kind.fresh(&mut draw).map(|kind| Case {
            kind,
            drawn: true,
            ..self.clone()
        })
    }
}
