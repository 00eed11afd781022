//! The builders every chapter's cases share, and the table of each
//! chapter's cases (its folder's `checks.rs`), read from the registry.
//!
//! Checkpoints are well-conditioned questions whose answers a student can
//! work out by hand; robustness cases are the hard inputs of
//! tests/course/hard_cases.rs (grazing and tangent rays, far and huge spheres,
//! origins on surfaces, the critical angle, NaN and infinite input), where
//! only a numerically careful formula is right. Expected intersection
//! parameters and directions come from `exact` (f64, separate formulas);
//! shading cases compare with raylab's reference chapters on the same point.

pub use glam::Vec3;

pub use super::cases::{
    BarycentricCase, BoxEdgesCase, BvhBuildCase, BvhHitsCase, ClosedMeshCase, HitBoxCase,
    NearestCase, OffsetCase, PhongTermsCase, PixelColorCase, PlaneCase, ReflectCase,
    ReflectanceCase, RefractCase, SampleOffsetsCase, ShadeCase, ShadowCase, SmoothHitCase,
    SmoothNormalCase, SphereCase, TerminatorCase, TransmittanceCase, TrianglesCase,
};
pub use super::cases::{CollapseCase, FourTrianglesCase, HitBoxesCase, MeshInFoursCase, WideShape};
pub use super::cases::{
    ConvergesCase, CosineSampleCase, DIRECTION_SAMPLES, PathFormula, PathFormulaCase,
    inside_sphere, inside_sphere_glowing_outward,
};
pub use super::cases::{
    DispersionCase, LensCase, LightConvergesCase, LightFormula, LightFormulaCase, PrismCase,
};
pub use super::cases::{ExpectT, Level, SampleRule, Shading, TreeShape, vec};
#[cfg(not(feature = "student"))]
pub use super::exact::{self, wide};
#[cfg(feature = "student")]
pub(crate) use super::exact::{self, wide};
pub use super::question::{Case, CaseKind};
pub use crate::bvh::{BvhOptions, SplitRule};
pub use crate::course::PhongTerms;
pub use crate::scene::Cauchy;
pub use crate::shapes::{Implicit, LipschitzRule, March, NormalMethod, Sdf, Triangle};
pub use crate::{Material, Plane, Ray, Sampling, Shape, Sphere};

pub const INF: f32 = f32::INFINITY;

/// `cases` at the robustness level (level 2).
pub fn robust(cases: Vec<Case>) -> Vec<Case> {
    cases
        .into_iter()
        .map(|case| Case {
            level: Level::Robustness,
            ..case
        })
        .collect()
}

/// What an intersection question expects, before the exact `t` of a hit is
/// worked out (which makes it an [`ExpectT`]).
#[derive(Clone, Copy)]
pub enum Expect {
    Hit,
    Miss,
    /// Rounding decides: see [`ExpectT::Either`].
    Either,
}

impl Expect {
    /// The expectation with a hit's `t` from `exact_t`; NaN when the exact
    /// reference finds no hit, which each chapter's own test rejects.
    pub fn with_exact_t(self, exact_t: impl FnOnce() -> Option<f64>) -> ExpectT {
        match self {
            Expect::Hit => ExpectT::Hit(exact_t().unwrap_or(f64::NAN)),
            Expect::Miss => ExpectT::Miss,
            Expect::Either => ExpectT::Either,
        }
    }
}

/// An `intersect_plane` question: the plane through `plane.0` with normal
/// `plane.1`, the ray from `ray.0` along `ray.1`, hits wanted for
/// `range.0 < t < range.1`.
pub struct PlaneQuestion {
    pub name: &'static str,
    pub section: &'static str,
    pub says: &'static str,
    /// `(point, normal)`.
    pub plane: (Vec3, Vec3),
    /// `(origin, dir)`.
    pub ray: (Vec3, Vec3),
    /// `(t_min, t_max)`.
    pub range: (f32, f32),
    pub expect: Expect,
}

impl From<PlaneQuestion> for Case {
    fn from(question: PlaneQuestion) -> Case {
        let (point, normal) = question.plane;
        let (origin, dir) = question.ray;
        let (t_min, t_max) = question.range;
        // The exact `t` of the plane as built: its normal made unit, or NaN
        // when degenerate, as the code under check receives it.
        let plane = Plane::new(point, normal);
        let expect = question.expect.with_exact_t(|| {
            exact::plane(
                wide(plane.point()),
                wide(plane.normal()),
                wide(origin),
                wide(dir),
                f64::from(t_min),
                f64::from(t_max),
            )
        });
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::Plane(PlaneCase {
                point,
                normal,
                ray: Ray::new(origin, dir),
                t_min,
                t_max,
                expect,
            }),
        )
    }
}

/// An `intersect_sphere` question: the sphere of centre `sphere.0` and
/// radius `sphere.1`, the ray from `ray.0` along `ray.1`, hits wanted for
/// `range.0 < t < range.1`.
pub struct SphereQuestion {
    pub name: &'static str,
    pub section: &'static str,
    pub says: &'static str,
    /// `(center, radius)`.
    pub sphere: (Vec3, f32),
    /// `(origin, dir)`.
    pub ray: (Vec3, Vec3),
    /// `(t_min, t_max)`.
    pub range: (f32, f32),
    pub expect: Expect,
}

impl From<SphereQuestion> for Case {
    fn from(question: SphereQuestion) -> Case {
        let (center, radius) = question.sphere;
        let (origin, dir) = question.ray;
        let (t_min, t_max) = question.range;
        let expect = question.expect.with_exact_t(|| {
            exact::sphere(
                wide(center),
                f64::from(radius),
                wide(origin),
                wide(dir),
                f64::from(t_min),
                f64::from(t_max),
            )
        });
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::Sphere(SphereCase {
                center,
                radius,
                ray: Ray::new(origin, dir),
                t_min,
                t_max,
                expect,
            }),
        )
    }
}

/// A shading question: `shading`'s function at the point where the ray from
/// `ray.0` along `ray.1` first meets `scene` (TOML), `depth` bounces deep.
pub struct ShadeQuestion {
    pub name: &'static str,
    pub section: &'static str,
    pub says: &'static str,
    pub shading: Shading,
    pub scene: String,
    /// `(origin, dir)`.
    pub ray: (Vec3, Vec3),
    pub depth: u32,
}

impl From<ShadeQuestion> for Case {
    fn from(question: ShadeQuestion) -> Case {
        let (origin, dir) = question.ray;
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::Shade(ShadeCase {
                shading: question.shading,
                scene: question.scene,
                ray: Ray::new(origin, dir),
                depth: question.depth,
                vertex_normals: None,
            }),
        )
    }
}

/// A lit glass pane y = 0 (object 0: k_r = 0.25, k_t = 0.5, white,
/// k_a = 0.4, a highlight k_s = 0.5 of shininess 1, index 1.5, and
/// `material_extra`, more TOML of its material such as `, fresnel =
/// "exact"`) under a light at (0, 10, 0), the sky (0.2, 0.4, 0.6), nothing
/// else: chapter 8's and chapter 9's highlight and depth cases.
pub fn lit_pane(material_extra: &str) -> String {
    format!(
        r#"
background = [0.2, 0.4, 0.6]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, -5.0]
look_at = [0.0, 0.0, 0.0]
[render]
max_depth = 5
[[lights]]
position = [0.0, 10.0, 0.0]
[[objects]]
name = "lit pane"
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }}
material = {{ color = [1.0, 1.0, 1.0], ambient = 0.4, diffuse = 0.0, specular = 0.5, shininess = 1, reflectivity = 0.25, transparency = 0.5, ior = 1.5{material_extra} }}
"#
    )
}

/// `(t_min, t_max)` for every `t` in front of the ray's origin.
pub const IN_FRONT: (f32, f32) = (0.0, INF);

// Scenes that the cases of chapters 4 and 5, and of 8 and 9, share.
/// A glass pane y = 0 (object 0: k_r = k_t = 0.5, tinted (1, 0.5, 0.25),
/// index 1.5) between two fainter panes, a floor y = -2 (colour 0.8,
/// k_t = 0.75) and a ceiling y = 2 (colour 0.4, k_t = 0.75), index 1, all
/// lit by ambient light only (ambient = 1, no lights). With
/// `min_contribution = 0.5` the pane's two rays are cast (weight 0.5 each)
/// but the floor's and the ceiling's are not (0.5 x 0.75 < 0.5): every
/// share is a fraction, and the answer is a few products by hand.
pub const PANES_SCENE: &str = r#"
background = [0.2, 0.4, 0.6]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, -5.0]
look_at = [0.0, 0.0, 0.0]
[render]
max_depth = 5
min_contribution = 0.5
[[objects]]
name = "pane"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [1.0, 0.5, 0.25], ambient = 1.0, diffuse = 0.0, reflectivity = 0.5, transparency = 0.5, ior = 1.5 }
[[objects]]
name = "floor pane"
plane = { point = [0.0, -2.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [0.8, 0.8, 0.8], ambient = 1.0, diffuse = 0.0, transparency = 0.75, ior = 1.0 }
[[objects]]
name = "ceiling pane"
plane = { point = [0.0, 2.0, 0.0], normal = [0.0, -1.0, 0.0] }
material = { color = [0.4, 0.4, 0.4], ambient = 1.0, diffuse = 0.0, transparency = 0.75, ior = 1.0 }
"#;

/// The ray of the panes cases: from (0, 1, 0) down at 45 degrees, meeting
/// the pane at (1, 0, 0).
pub const PANES_RAY: (Vec3, Vec3) = (Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, -1.0, 0.0));

/// A floor (object 0) and a unit ball resting on it (object 1).
pub fn floor_and_ball(lights: &str) -> String {
    floor_and_ball_in([1.0, 1.0, 1.0], lights)
}

/// A dim, coloured ambient light for [`floor_and_ball_in`]: each channel a
/// power of two, so the expected ambient terms are exact.
pub const DIM_AMBIENT: [f32; 3] = [0.5, 0.25, 1.0];

/// [`floor_and_ball`] under the ambient light `ambient`.
pub fn floor_and_ball_in(ambient: [f32; 3], lights: &str) -> String {
    let [r, g, b] = ambient;
    format!(
        r#"
background = [0.55, 0.7, 0.9]
ambient_light = [{r:?}, {g:?}, {b:?}]
[camera]
position = [0.0, 2.0, -6.0]
look_at = [0.0, 0.0, 0.0]
{lights}
[[objects]]
name = "floor"
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }}
material = {{ color = [0.5, 0.5, 0.5], ambient = 0.2, diffuse = 0.6, specular = 0.5, shininess = 8 }}
[[objects]]
name = "ball"
sphere = {{ center = [0.0, 1.0, 0.0], radius = 1.0 }}
material = {{ color = [0.8, 0.2, 0.2], ambient = 0.2, diffuse = 0.6 }}
"#
    )
}

pub const LIGHT_ABOVE: &str = "[[lights]]\nposition = [0.0, 10.0, 0.0]\n";

pub const TWO_LIGHTS: &str = "[[lights]]\nposition = [0.0, 10.0, 0.0]\n\
                          [[lights]]\nposition = [10.0, 0.5, 0.0]\nintensity = 0.5\n";
