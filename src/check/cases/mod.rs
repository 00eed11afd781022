//! Checkpoint cases as data, and how each is run against some chapters.
//!
//! A [`Case`] is one question to one function of the course, in the spirit
//! of The Ray Tracer Challenge's scenarios: its inputs, what is expected,
//! how close is close enough, and a sentence a student can check by hand.
//! [`Case::run`] asks the question of the chapters `C` and says whether the
//! answer is right, without ever letting a panic out.

mod boxes;
mod directions;
mod implicit;
mod inputs;
mod intersections;
mod light_paths;
mod paths;
mod sampling;
mod shading;
mod smooth;
mod tree;
mod wide;

pub use boxes::{BoxEdgesCase, BvhBuildCase, BvhHitsCase, HitBoxCase};
pub use directions::{ReflectCase, ReflectanceCase, RefractCase, TransmittanceCase};
pub use implicit::{
    ImplicitNormalCase, MarchCase, MarchExpect, Marcher, NewtonCase, NewtonFunction, method_name,
    surface_of,
};
pub use inputs::{num, num64, vec};
pub use intersections::{ClosedMeshCase, NearestCase, PlaneCase, SphereCase, TrianglesCase};
pub use light_paths::{
    LENS_ALLOWANCE, LensCase, LightConvergesCase, LightFormula, LightFormulaCase,
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

use super::panics::{Panic, guarded};
use crate::bvh::{Aabb, Bvh, BvhOptions};
use crate::check::exact::{self, U, wide};
use crate::course::{Chapters, Hit, HitPoint, Objects, PhongTerms};
use crate::render::{Stage, Tracer};
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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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

/// The question a case asks, one variant per kind of function. Each kind
/// writes its own inputs line and judges its own answer; the enum keeps the
/// list closed, so that a new kind is matched everywhere.
#[derive(Debug, Clone)]
pub enum CaseKind {
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
    March(MarchCase),
    Newton(NewtonCase),
    ImplicitNormal(ImplicitNormalCase),
    CosineSample(CosineSampleCase),
    PathFormula(PathFormulaCase),
    Converges(ConvergesCase),
    LightFormula(LightFormulaCase),
    LightConverges(LightConvergesCase),
    Lens(LensCase),
    Prism(PrismCase),
}

impl CaseKind {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        match self {
            CaseKind::Plane(case) => case.function(),
            CaseKind::Sphere(case) => case.function(),
            CaseKind::Nearest(case) => case.function(),
            CaseKind::Offset(case) => case.function(),
            CaseKind::Shadow(case) => case.function(),
            CaseKind::Shade(case) => case.function(),
            CaseKind::PhongTerms(case) => case.function(),
            CaseKind::Reflect(case) => case.function(),
            CaseKind::SampleOffsets(case) => case.function(),
            CaseKind::PixelColor(case) => case.function(),
            CaseKind::Refract(case) => case.function(),
            CaseKind::Reflectance(case) => case.function(),
            CaseKind::Transmittance(case) => case.function(),
            CaseKind::Triangles(case) => case.function(),
            CaseKind::ClosedMesh(case) => case.function(),
            CaseKind::Barycentric(case) => case.function(),
            CaseKind::SmoothNormal(case) => case.function(),
            CaseKind::Terminator(case) => case.function(),
            CaseKind::SmoothHit(case) => case.function(),
            CaseKind::HitBox(case) => case.function(),
            CaseKind::BoxEdges(case) => case.function(),
            CaseKind::BvhBuild(case) => case.function(),
            CaseKind::BvhHits(case) => case.function(),
            CaseKind::HitBoxes(case) => case.function(),
            CaseKind::FourTriangles(case) => case.function(),
            CaseKind::MeshInFours(case) => case.function(),
            CaseKind::Collapse(case) => case.function(),
            CaseKind::March(case) => case.function(),
            CaseKind::Newton(case) => case.function(),
            CaseKind::ImplicitNormal(case) => case.function(),
            CaseKind::CosineSample(case) => case.function(),
            CaseKind::PathFormula(case) => case.function(),
            CaseKind::Converges(case) => case.function(),
            CaseKind::LightFormula(case) => case.function(),
            CaseKind::LightConverges(case) => case.function(),
            CaseKind::Lens(case) => case.function(),
            CaseKind::Prism(case) => case.function(),
        }
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        match self {
            CaseKind::Plane(case) => case.inputs(),
            CaseKind::Sphere(case) => case.inputs(),
            CaseKind::Nearest(case) => case.inputs(),
            CaseKind::Offset(case) => case.inputs(),
            CaseKind::Shadow(case) => case.inputs(),
            CaseKind::Shade(case) => case.inputs(),
            CaseKind::PhongTerms(case) => case.inputs(),
            CaseKind::Reflect(case) => case.inputs(),
            CaseKind::SampleOffsets(case) => case.inputs(),
            CaseKind::PixelColor(case) => case.inputs(),
            CaseKind::Refract(case) => case.inputs(),
            CaseKind::Reflectance(case) => case.inputs(),
            CaseKind::Transmittance(case) => case.inputs(),
            CaseKind::Triangles(case) => case.inputs(),
            CaseKind::ClosedMesh(case) => case.inputs(),
            CaseKind::Barycentric(case) => case.inputs(),
            CaseKind::SmoothNormal(case) => case.inputs(),
            CaseKind::Terminator(case) => case.inputs(),
            CaseKind::SmoothHit(case) => case.inputs(),
            CaseKind::HitBox(case) => case.inputs(),
            CaseKind::BoxEdges(case) => case.inputs(),
            CaseKind::BvhBuild(case) => case.inputs(),
            CaseKind::BvhHits(case) => case.inputs(),
            CaseKind::HitBoxes(case) => case.inputs(),
            CaseKind::FourTriangles(case) => case.inputs(),
            CaseKind::MeshInFours(case) => case.inputs(),
            CaseKind::Collapse(case) => case.inputs(),
            CaseKind::March(case) => case.inputs(),
            CaseKind::Newton(case) => case.inputs(),
            CaseKind::ImplicitNormal(case) => case.inputs(),
            CaseKind::CosineSample(case) => case.inputs(),
            CaseKind::PathFormula(case) => case.inputs(),
            CaseKind::Converges(case) => case.inputs(),
            CaseKind::LightFormula(case) => case.inputs(),
            CaseKind::LightConverges(case) => case.inputs(),
            CaseKind::Lens(case) => case.inputs(),
            CaseKind::Prism(case) => case.inputs(),
        }
    }

    /// Asks the question of the chapters `C`; `robust`: at the robustness
    /// level's tolerance.
    fn evaluate<C: Chapters>(&self, robust: bool) -> Outcome {
        match self {
            CaseKind::Plane(case) => case.evaluate::<C>(robust),
            CaseKind::Sphere(case) => case.evaluate::<C>(robust),
            CaseKind::Nearest(case) => case.evaluate::<C>(robust),
            CaseKind::Offset(case) => case.evaluate::<C>(robust),
            CaseKind::Shadow(case) => case.evaluate::<C>(robust),
            CaseKind::Shade(case) => case.evaluate::<C>(robust),
            CaseKind::PhongTerms(case) => case.evaluate::<C>(robust),
            CaseKind::Reflect(case) => case.evaluate::<C>(robust),
            CaseKind::SampleOffsets(case) => case.evaluate::<C>(robust),
            CaseKind::PixelColor(case) => case.evaluate::<C>(robust),
            CaseKind::Refract(case) => case.evaluate::<C>(robust),
            CaseKind::Reflectance(case) => case.evaluate::<C>(robust),
            CaseKind::Transmittance(case) => case.evaluate::<C>(robust),
            CaseKind::Triangles(case) => case.evaluate::<C>(robust),
            CaseKind::ClosedMesh(case) => case.evaluate::<C>(robust),
            CaseKind::Barycentric(case) => case.evaluate::<C>(robust),
            CaseKind::SmoothNormal(case) => case.evaluate::<C>(robust),
            CaseKind::Terminator(case) => case.evaluate::<C>(robust),
            CaseKind::SmoothHit(case) => case.evaluate::<C>(robust),
            CaseKind::HitBox(case) => case.evaluate::<C>(robust),
            CaseKind::BoxEdges(case) => case.evaluate::<C>(robust),
            CaseKind::BvhBuild(case) => case.evaluate::<C>(robust),
            CaseKind::BvhHits(case) => case.evaluate::<C>(robust),
            CaseKind::HitBoxes(case) => case.evaluate::<C>(robust),
            CaseKind::FourTriangles(case) => case.evaluate::<C>(robust),
            CaseKind::MeshInFours(case) => case.evaluate::<C>(robust),
            CaseKind::Collapse(case) => case.evaluate::<C>(robust),
            CaseKind::March(case) => case.evaluate::<C>(robust),
            CaseKind::Newton(case) => case.evaluate::<C>(robust),
            CaseKind::ImplicitNormal(case) => case.evaluate::<C>(robust),
            CaseKind::CosineSample(case) => case.evaluate::<C>(robust),
            CaseKind::PathFormula(case) => case.evaluate::<C>(robust),
            CaseKind::Converges(case) => case.evaluate::<C>(robust),
            CaseKind::LightFormula(case) => case.evaluate::<C>(robust),
            CaseKind::LightConverges(case) => case.evaluate::<C>(robust),
            CaseKind::Lens(case) => case.evaluate::<C>(robust),
            CaseKind::Prism(case) => case.evaluate::<C>(robust),
        }
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
}

/// How a case went.
#[derive(Debug, Clone, PartialEq)]
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
        }
    }

    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        self.kind.function()
    }

    /// Asks the question of the chapters `C`.
    pub fn run<C: Chapters>(&self) -> Outcome {
        match guarded(|| self.evaluate::<C>()) {
            Ok(outcome) => outcome,
            Err(panic) if panic.is_todo() => Outcome::Todo(panic),
            Err(panic) => Outcome::Panicked(panic),
        }
    }

    fn evaluate<C: Chapters>(&self) -> Outcome {
        self.kind.evaluate::<C>(self.level == Level::Robustness)
    }
}

fn verdict(pass: bool, expected: String, got: String) -> Outcome {
    if pass {
        Outcome::Pass
    } else {
        Outcome::Fail { expected, got }
    }
}

fn close(got: f64, want: f64, tolerance: f64) -> bool {
    (got - want).abs() <= tolerance * want.abs().max(1.0)
}

/// Colours agree within `1e-4` (about a third of an 8-bit level in the
/// darkest sRGB codes): far above any rounding, far below any wrong term.
fn colour_close(got: Vec3, want: Vec3) -> bool {
    got.is_finite()
        && (wide(got) - wide(want))
            .abs()
            .cmple(DVec3::splat(CHECKPOINT_TOLERANCE) * wide(want).abs().max(DVec3::ONE))
            .all()
}

fn parse(text: &str) -> Result<Scene, String> {
    Scene::parse(text, "a checkpoint's scene").map_err(|error| error.to_string())
}

fn max_abs(v: DVec3) -> f64 {
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
