//! Checkpoint cases as data, and how each is run against some chapters.
//!
//! A [`Case`](super::question::Case) is one question to one function of
//! the course, in the spirit of The Ray Tracer Challenge's scenarios: its
//! inputs, what is expected, how close is close enough, and a sentence a
//! student can check by hand. [`Case::run`](super::question::Case::run)
//! asks the question of the chapters `C` and says whether the answer is
//! right, without ever letting a panic out. The kinds of question here are
//! those several chapters share (a chapter's own live in its folder).

mod boxes;
mod directions;
mod draw;
mod inputs;
mod intersections;
mod light_paths;
mod paths;
mod sampling;
mod shading;
mod smooth;
mod tree;
mod wide;

pub use boxes::{
    BoxEdgesCase, BvhBuildCase, BvhHitsCase, HitBoxCall, HitBoxCase, TreeCall, WalkCall, Walked,
    WalkedTrees,
};
pub use directions::{ReflectCase, ReflectanceCase, RefractCase, TransmittanceCase};
pub use inputs::{num, num64, range, sdf_text, vec, vec64};
pub use intersections::{ClosedMeshCase, NearestCase, PlaneCase, SphereCase, TrianglesCase};
pub use light_paths::{
    DispersionCase, LENS_ALLOWANCE, LensCase, LightConvergesCase, LightFormula, LightFormulaCase,
    PRISM_TOLERANCE_DEGREES, PrismCase, linear_image,
};
pub use paths::{
    ConvergesCase, CosineSampleCase, DIRECTION_SAMPLES, FALSE_ALARM, PathFormula, PathFormulaCase,
    STATISTICAL_CASES, cosine_fit, inside_sphere, inside_sphere_glowing_outward, mean_and_error,
    pearson, stream, welch_rejections, z_threshold,
};
pub use sampling::{PixelColorCase, SampleOffsetsCase};
pub use shading::{OffsetCase, PhongTermsCase, ShadeCase, ShadowCase};
pub use smooth::{BarycentricCase, SmoothHitCase, SmoothNormalCase, TerminatorCase};
pub use wide::{CollapseCase, FourTrianglesCase, HitBoxesCase, MeshInFoursCase, WideShape};

use glam::{DVec3, Vec3};

pub use draw::{Draw, Motion};

use super::panics::Panic;
use crate::bvh::{Aabb, Bvh, BvhOptions};
use crate::check::exact::{self, U, wide};
use crate::course::{Chapters, Hit, HitPoint, Objects, PhongTerms};
use crate::render::Stage;
use crate::shapes::{SurfacePoint, Triangle};
use crate::{Material, Plane, Ray, Reference, Sampling, Scene, Shape, Sphere};
use inputs::*;
use tree::*;

/// Which level a case belongs to: a checkpoint every correct formula meets,
/// or a hard case that only a numerically robust one does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Level {
    Checkpoint,
    Robustness,
}

/// Roundings allowed per formula in the robustness cases (the same bound as
/// tests/course/hard_cases.rs, where the largest ratio the reference reaches is
/// printed): `16 u` times the scale of the problem.
pub const ROUNDINGS: f64 = 16.0;

/// How far a checkpoint answer may be from the exact one, relative to
/// `max(1, |expected|)`. Checkpoints are well-conditioned: any correct `f32`
/// formula lands within a few `u = 6e-8` of the exact answer, in any order
/// of operations, so `1e-4` accepts them all and still rejects every wrong
/// formula (whose error is a visible fraction).
pub const CHECKPOINT_TOLERANCE: f64 = 1e-4;

/// What an intersection case expects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ExpectT {
    /// A hit at this `t` (exact).
    Hit(f64),
    Miss,
    /// Rounding decides (a tangent ray, an origin rounded onto the surface):
    /// either answer is right, but a hit must lie on the surface.
    Either,
}

/// Which shading function a scene case calls.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Shading {
    /// Chapter 4's `shade_flat`.
    Flat,
    /// Chapter 5's `shade_phong`.
    Phong,
    /// Chapter 6's `shade_mirror`.
    Mirror,
    /// Chapter 8's `shade_glass`.
    Glass,
    /// Chapter 9's `shade_dielectric`.
    Dielectric,
}

impl Shading {
    fn stage(self) -> u8 {
        match self {
            Shading::Flat => 4,
            Shading::Phong => 5,
            Shading::Mirror => 6,
            Shading::Glass => 8,
            Shading::Dielectric => 9,
        }
    }
}

/// What a set of sample offsets must look like.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleRule {
    /// The centres of the `k x k` cells, in any order.
    GridCentres,
    /// Exactly one sample in each of the `k x k` cells, all inside `[0, 1)^2`.
    OnePerCell,
    /// Every sample inside `[0, 1)^2`, and not all at one point.
    InsidePixel,
    /// As `InsidePixel`, and not the same offsets as with this other seed:
    /// the seed changes the samples.
    UnlikeSeed(u64),
    /// As `InsidePixel`, for seed 0 and each of the 64 seeds of one bit,
    /// and no two of those seeds give the same offsets in a pixel: every
    /// bit of the seed changes the samples.
    DistinctSeeds,
    /// Over all the case's pixels, the samples are spread as independent
    /// uniform ones would be (jittered: within their cells): uniform in x
    /// and y together, one cell's independent of another's in the same
    /// pixel, one pixel's independent of the next pixel's. Each is a
    /// chi-square test on 8 x 8 bins (see `sampling::spread`).
    Spread,
}

/// One kind of question to the course: what the student's process is
/// sent, what it sends back, and how the judge reads the answer.
///
/// The split is the judge's guarantee (see [`crate::check::judge`]):
/// [`Kind::ask`] runs in the student's process with nothing but
/// [`Kind::Call`], the inputs of the call, and returns the raw answer (a
/// `t`, a direction, hits, samples, pixels); [`Kind::judge`] runs in
/// raylab's own process, which alone holds the case's expectation, its
/// tolerance and its oracle. So no expected value ever reaches the
/// student's code, and nothing it prints, writes or exits with is read as
/// a verdict.
pub trait Kind: std::fmt::Debug + Clone {
    /// The inputs of the call, all the student's process is sent.
    type Call: serde::Serialize + serde::de::DeserializeOwned + std::fmt::Debug + Clone;
    /// What the student's process answers.
    type Answer: serde::Serialize + serde::de::DeserializeOwned + std::fmt::Debug;
    /// The course function this case calls.
    fn function(&self) -> &'static str;
    /// The inputs, as the call would receive them.
    fn inputs(&self) -> String;
    /// What the student's process is sent.
    fn call(&self) -> Self::Call;
    /// Asks the question of the chapters `C`: runs in the student's
    /// process. `Err` is a problem of the case itself (a scene that does
    /// not parse), reported as an error of the check.
    fn ask<C: Chapters>(call: &Self::Call) -> Result<Self::Answer, String>;
    /// Judges `answer`: runs in raylab's own process. `robust`: at the
    /// robustness level's tolerance.
    fn judge(&self, answer: Self::Answer, robust: bool) -> Outcome;
    /// The case with fresh inputs drawn by `draw` within the kind's stated
    /// ranges, its expectation worked out again (`grade --code --fresh`);
    /// `None` where the kind keeps its inputs.
    fn fresh(&self, _draw: &mut Draw) -> Option<Self> {
        None
    }
    /// Whether the case is a statistical test on a stream of numbers,
    /// whose verdict a correct answer misses with a small stated chance.
    fn statistical(&self) -> bool {
        false
    }
}

/// What a `BvhBuild` case asks of the tree's shape, beyond its being valid.
/// Which child is called left is the student's choice, so a cut is
/// compared as a partition.
#[derive(Debug, Clone, PartialEq)]
pub enum TreeShape {
    /// Any valid tree.
    Any,
    /// The root is a leaf (it holds every boxed object), and its box is
    /// theirs, padded by a few epsilons.
    RootLeaf,
    /// The root is cut in two, one child holding exactly the objects of
    /// one of these lists (each a cut the lesson's rules may give) and the
    /// other the rest of the boxed ones; its box is theirs, padded by a few
    /// epsilons.
    RootCut(Vec<Vec<u32>>),
    /// Either the root is a leaf, as for `RootLeaf`, or it is cut as one of
    /// these lists says, as for `RootCut`: the SAH's leaf, or the cut of a
    /// build that always cuts at the middle.
    RootLeafOrCut(Vec<Vec<u32>>),
}

/// How a case went.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Outcome {
    Pass,
    Fail {
        expected: String,
        got: String,
    },
    /// The code panicked with `todo!()`: a function not written yet.
    Todo(Panic),
    /// The code panicked otherwise.
    Panicked(Panic),
    /// The check itself could not run (a bug in raylab, not the student's).
    Error(String),
    /// The student's process ended while it worked the answer out: how
    /// ("exited with status 0").
    Ended(String),
}

impl Outcome {
    /// A panic's outcome: not written yet for `todo!()`, else a panic.
    pub fn from_panic(panic: Panic) -> Outcome {
        if panic.is_todo() {
            Outcome::Todo(panic)
        } else {
            Outcome::Panicked(panic)
        }
    }
}

pub fn verdict(pass: bool, expected: String, got: String) -> Outcome {
    if pass {
        Outcome::Pass
    } else {
        Outcome::Fail { expected, got }
    }
}

pub fn close(got: f64, want: f64, tolerance: f64) -> bool {
    (got - want).abs() <= tolerance * want.abs().max(1.0)
}

/// Colours agree within `1e-4` (about a third of an 8-bit level in the
/// darkest sRGB codes): far above any rounding, far below any wrong term.
pub fn colour_close(got: Vec3, want: Vec3) -> bool {
    got.is_finite()
        && (wide(got) - wide(want))
            .abs()
            .cmple(DVec3::splat(CHECKPOINT_TOLERANCE) * wide(want).abs().max(DVec3::ONE))
            .all()
}

pub fn parse(text: &str) -> Result<Scene, String> {
    Scene::parse(text, "a checkpoint's scene").map_err(|error| error.to_string())
}

pub fn max_abs(v: DVec3) -> f64 {
    v.abs().max_element()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_like_a_student_writes_them() {
        assert_eq!(num(0.0), "0");
        assert_eq!(num(-5.0), "-5");
        assert_eq!(num(0.5), "0.5");
        assert_eq!(num(1e20), "1e20");
        assert_eq!(num(f32::INFINITY), "inf");
        assert_eq!(vec(Vec3::new(0.0, 1.0, -5.0)), "(0, 1, -5)");
        // Every digit that tells an f32 from its neighbours, and an exact
        // answer with one digit more: the two never print alike.
        assert_eq!(num(-1.0 / 3.0), "-0.33333334");
        assert_eq!(num64(-1.0 / 3.0), "-0.333333333");
        assert_eq!(num(0.1), "0.1");
        assert_eq!(num64(0.1), "0.1");
        assert_eq!(num64(1234.5), "1234.5");
        assert_eq!(num64(2.5e-7), "2.5e-7");
        assert_eq!(num(1.5e-7), "1.5e-7");
    }
}
