//! Chapter 9's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 9`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const FRESNEL_9: &str = "Fresnel, from the boundary conditions";
const SCHLICK_9: &str = "Schlick's approximation";
const STACK_9: &str = "Which media meet: the medium stack";
const ABSORPTION_9: &str = "Absorption: Beer-Lambert";

/// The exact unpolarised reflectance, written from the Fresnel equations in
/// `f64` (independently of the chapter's code).
fn exact_fresnel(cos_i: f64, n1: f64, n2: f64) -> f64 {
    let sin2_t = (n1 / n2).powi(2) * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_s = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    let r_p = (n1 * cos_t - n2 * cos_i) / (n1 * cos_t + n2 * cos_i);
    (r_s * r_s + r_p * r_p) / 2.0
}

/// A `fresnel(cos_i, n1, n2)` question, or `schlick` when `schlick` is set.
struct ReflectanceQuestion {
    name: &'static str,
    section: &'static str,
    says: &'static str,
    schlick: bool,
    cos_i: f32,
    n1: f32,
    n2: f32,
    expect: f64,
}

impl From<ReflectanceQuestion> for Case {
    fn from(question: ReflectanceQuestion) -> Case {
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::Reflectance(ReflectanceCase {
                schlick: question.schlick,
                cos_i: question.cos_i,
                n1: question.n1,
                n2: question.n2,
                expect: question.expect,
            }),
        )
    }
}

/// A glass ball (ior 1.5, Fresnel exact) holding a water ball (1.33) over a
/// floor: the ray from the camera meets the glass first.
const NESTED_SCENE: &str = r#"
background = [0.55, 0.7, 0.9]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, -6.0]
look_at = [0.0, 1.0, 0.0]
[render]
max_depth = 6
min_contribution = 0.0
[[lights]]
position = [-4.0, 6.0, -3.0]
[[objects]]
name = "glass"
sphere = { center = [0.0, 1.0, 0.0], radius = 1.0 }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.5, fresnel = "exact", absorption = [0.2, 0.05, 0.0] }
[[objects]]
name = "water"
sphere = { center = [0.0, 1.0, 0.0], radius = 0.6 }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.33, fresnel = "schlick" }
[[objects]]
name = "floor"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
[objects.material]
color = [0.9, 0.9, 0.85]
checker = { color = [0.15, 0.15, 0.2], size = 1.0 }
"#;

/// A clear glass ball of radius 1 at the origin (object 0: k_t = 1, index
/// 1.5, exact Fresnel, no light of its own), nothing else, no lights.
const INSIDE_SCENE: &str = r#"
background = [0.55, 0.7, 0.9]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 0.0, -6.0]
look_at = [0.0, 0.0, 0.0]
[render]
max_depth = 5
[[objects]]
name = "glass"
sphere = { center = [0.0, 0.0, 0.0], radius = 1.0 }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.5, fresnel = "exact" }
"#;

/// Where the image differs when every checkpoint passes: what to look at
/// in the heatmap.
pub const IMAGE_HINT: &str = "on the glass: the reflected share R and the transmitted 1 - R, the pair of media at each crossing, and absorption along the path inside only";

/// Chapter 9's checkpoints (level 1), in the order they run: the first
/// that fails is the one reported.
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn checkpoints() -> Vec<Case> {
    let cos45 = std::f32::consts::FRAC_1_SQRT_2;
    vec![
        Case::from(ReflectanceQuestion {
            name: "fresnel-normal-incidence",
            section: FRESNEL_9,
            says: "air to glass head-on: cos_i = 1, n1 = 1, n2 = 1.5: R = \
                   ((1 - 1.5) / (1 + 1.5))^2 = 0.04",
            schlick: false,
            cos_i: 1.0,
            n1: 1.0,
            n2: 1.5,
            expect: 0.04,
        }),
        Case::from(ReflectanceQuestion {
            name: "schlick-normal-incidence",
            section: SCHLICK_9,
            says: "the same with Schlick: R0 = 0.04, and (1 - cos_i)^5 = 0 head-on: 0.04",
            schlick: true,
            cos_i: 1.0,
            n1: 1.0,
            n2: 1.5,
            expect: 0.04,
        }),
        Case::from(ReflectanceQuestion {
            name: "fresnel-45-degrees",
            section: FRESNEL_9,
            says: "air to glass at 45 degrees: sin t = 0.7071 / 1.5 = 0.4714, cos t = 0.8819; r_s \
                   = (0.7071 - 1.5 x 0.8819) / (0.7071 + 1.5 x 0.8819) = -0.3034, r_p = \
                   (1.5 x 0.7071 - 0.8819) / (1.5 x 0.7071 + 0.8819) = 0.0920 (the lesson's \
                   sign; only its square counts): R = (r_s^2 + r_p^2) / 2 = 0.0502",
            schlick: false,
            cos_i: cos45,
            n1: 1.0,
            n2: 1.5,
            expect: exact_fresnel(f64::from(cos45), 1.0, 1.5),
        }),
        Case::from(ReflectanceQuestion {
            name: "fresnel-total-internal-reflection",
            section: FRESNEL_9,
            says: "glass to air at 60 degrees (cos_i = 0.5): sin t = 1.5 x 0.866 = 1.3 > 1, no \
                   transmitted ray: R = 1 exactly",
            schlick: false,
            cos_i: 0.5,
            n1: 1.5,
            n2: 1.0,
            expect: 1.0,
        }),
        Case::from(ReflectanceQuestion {
            name: "fresnel-grazing",
            section: FRESNEL_9,
            says: "air to glass at grazing incidence (cos_i = 0): everything is reflected, R = 1",
            schlick: false,
            cos_i: 0.0,
            n1: 1.0,
            n2: 1.5,
            expect: 1.0,
        }),
        Case::from(ReflectanceQuestion {
            name: "schlick-leaving-glass",
            section: SCHLICK_9,
            says: "glass to air with cos_i = 0.9: Schlick takes the cosine in the less dense \
                   medium, here the transmitted one: sin t = 1.5 x 0.4359 = 0.6538, cos t = \
                   0.7566, R = 0.04 + 0.96 x (1 - 0.7566)^5 = 0.04081 \
                   (with cos_i it would be 0.04001)",
            schlick: true,
            cos_i: 0.9,
            n1: 1.5,
            n2: 1.0,
            expect: {
                let cos_t = (1.0 - 2.25 * (1.0 - 0.81f64)).sqrt();
                0.04 + 0.96 * (1.0 - cos_t).powi(5)
            },
        }),
        Case::from(ReflectanceQuestion {
            name: "schlick-past-the-critical-angle",
            section: SCHLICK_9,
            says: "glass to air at 60 degrees (cos_i = 0.5), past the critical angle of 41.8 \
                   degrees: no transmitted ray, so R = 1, with Schlick too",
            schlick: true,
            cos_i: 0.5,
            n1: 1.5,
            n2: 1.0,
            expect: 1.0,
        }),
        Case::from(ReflectanceQuestion {
            name: "fresnel-water-in-glass",
            section: FRESNEL_9,
            says: "from glass (1.5) into water (1.33) head-on: R = ((1.5 - 1.33) / (1.5 + 1.33))^2 \
                   = 0.00361, ten times less than into air: the pair of media matters",
            schlick: false,
            cos_i: 1.0,
            n1: 1.5,
            n2: 1.33,
            expect: ((1.5f64 - 1.33) / (1.5 + 1.33)).powi(2),
        }),
        Case::new(
            "transmittance-slab",
            ABSORPTION_9,
            "through 2 units of glass absorbing (0.5, 0.1, 0) per unit: exp(-1) = 0.3679, \
             exp(-0.2) = 0.8187 and 1",
            CaseKind::Transmittance(TransmittanceCase {
                absorption: Vec3::new(0.5, 0.1, 0.0),
                distance: 2.0,
            }),
        ),
        Case::from(ShadeQuestion {
            name: "dielectric-highlight-in-full",
            section: STACK_9,
            says: "a ray from (0, 1, 0) straight down meets the lit glass pane (k_r = 0.25, \
                   k_t = 0.5, white, k_a = 0.4, k_s = 0.5, shininess 1, index 1.5, exact Fresnel) \
                   under a light at (0, 10, 0): its own diffuse light (1 - 0.75) * 0.4 = 0.1, the \
                   highlight 0.5 in full (not scaled by 1 - k_r - k_t), and both rays see the sky \
                   (0.2, 0.4, 0.6), with the shares 0.25 + 0.5 * 0.04 reflected and 0.5 * 0.96 \
                   refracted: expected 0.1 + 0.5 + 0.75 * sky = (0.75, 0.9, 1.05)",
            shading: Shading::Dielectric,
            scene: lit_pane(", fresnel = \"exact\""),
            ray: (Vec3::new(0.0, 1.0, 0.0), -Vec3::Y),
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "dielectric-depth-limit",
            section: STACK_9,
            says: "the same ray at depth 5 = max_depth: no more rays, only the pane's own light, \
                   0.1 diffuse and the highlight 0.5: expected (0.6, 0.6, 0.6)",
            shading: Shading::Dielectric,
            scene: lit_pane(", fresnel = \"exact\""),
            ray: (Vec3::new(0.0, 1.0, 0.0), -Vec3::Y),
            depth: 5,
        }),
        Case::from(ShadeQuestion {
            name: "dielectric-nested-balls",
            section: STACK_9,
            says: "a ray from (0, 1, -6) along +z meets a glass ball \
                   (ior 1.5, exact Fresnel, absorbing) holding a water ball (ior 1.33, Schlick) \
                   and crosses four surfaces, each between its own pair of media: (n1, n2) = \
                   (1, 1.5) into the glass, (1.5, 1.33) into the water, (1.33, 1.5) out of it, \
                   (1.5, 1) out of the glass; the glass absorbs along the path inside it only. \
                   A wrong pair at one crossing (the outer medium taken as air, the stack not \
                   popped) changes that crossing's Fresnel share and bend: print the pair your \
                   `crossing` gives at each",
            shading: Shading::Dielectric,
            scene: NESTED_SCENE.to_string(),
            ray: (Vec3::new(0.0, 1.0, -6.0), Vec3::Z),
            depth: 0,
        }),
        Case::new(
            "dielectric-fractional-shares",
            STACK_9,
            "chapter 8's glass-fractional-shares scene, no Fresnel (fresnel = \"none\": R = 0): a \
             pane with k_r = k_t = 0.5, tinted (1, 0.5, 0.25), of its own light 1 - 0.5 - 0.5 = 0; \
             the transmitted ray (weight 0.5) sees the floor's own light 0.2, the reflected one \
             (weight 0.5) the ceiling's, 0.1, neither casting further \
             (0.5 x 0.75 < min_contribution 0.5): expected (0.15, 0.1, 0.075)",
            CaseKind::Shade(ShadeCase {
                shading: Shading::Dielectric,
                scene: PANES_SCENE.to_string(),
                ray: Ray::new(PANES_RAY.0, PANES_RAY.1),
                depth: 0,
                vertex_normals: None,
            }),
        ),
        Case::from(ShadeQuestion {
            name: "dielectric-off-centre",
            section: STACK_9,
            says: "the same balls, the ray from (0.3, 1.2, -6) along +z: it crosses glass and \
                   water at an angle, where Fresnel's share and the bending both depend on the \
                   pair of media",
            shading: Shading::Dielectric,
            scene: NESTED_SCENE.to_string(),
            ray: (Vec3::new(0.3, 1.2, -6.0), Vec3::Z),
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "dielectric-inside-all-along",
            section: STACK_9,
            says: "a ray from (0, 0.8, 0), inside a clear glass ball of radius 1 at the origin \
                   (index 1.5, k_t = 1, no light of its own) but never seen entering it (a camera \
                   inside), along +z: it meets the ball at (0, 0.8, 0.6), leaving it, so (n1, \
                   n2) = (1.5, 1), not (1, 1); at cos i = 0.6 it is past the critical angle (sin \
                   i = 0.8 > 1 / 1.5) and totally reflected, and so at every bounce after, along \
                   chords of the same angle, until max_depth: expected black, (0, 0, 0), where \
                   the pair (1, 1) would let it out to the sky",
            shading: Shading::Dielectric,
            scene: INSIDE_SCENE.to_string(),
            ray: (Vec3::new(0.0, 0.8, 0.0), Vec3::Z),
            depth: 0,
        }),
    ]
}

/// Chapter 9's hard cases.
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn robustness() -> Vec<Case> {
    let critical = (1.0f64 / 1.5).asin();
    let just_below = (critical - 1e-4).cos() as f32;
    let just_above = (critical + 1e-4).cos() as f32;
    vec![
        Case::from(ReflectanceQuestion {
            name: "fresnel-just-below-the-critical-angle",
            section: FRESNEL_9,
            says: "glass to air 1e-4 rad before the critical angle: R is continuous and rises \
                   steeply to 1 (a square-root singularity): no NaN, no value above 1",
            schlick: false,
            cos_i: just_below,
            n1: 1.5,
            n2: 1.0,
            expect: exact_fresnel(f64::from(just_below), 1.5, 1.0),
        }),
        Case::from(ReflectanceQuestion {
            name: "fresnel-just-past-the-critical-angle",
            section: FRESNEL_9,
            says: "glass to air 1e-4 rad past the critical angle: total internal reflection, R = 1",
            schlick: false,
            cos_i: just_above,
            n1: 1.5,
            n2: 1.0,
            expect: 1.0,
        }),
        Case::from(ReflectanceQuestion {
            name: "fresnel-equal-media",
            section: FRESNEL_9,
            says: "water to water (1.33 to 1.33): no boundary, nothing reflected, R = 0 (not 0/0)",
            schlick: false,
            cos_i: 0.3,
            n1: 1.33,
            n2: 1.33,
            expect: 0.0,
        }),
        Case::from(ReflectanceQuestion {
            name: "fresnel-zero-index",
            section: FRESNEL_9,
            says: "n1 = 0, not an index (no medium has one below 1, and 0 makes n1 / n2 = 0): \
                   expected NaN, a loud answer, not a plausible R",
            schlick: false,
            cos_i: 0.8,
            n1: 0.0,
            n2: 1.5,
            expect: f64::NAN,
        }),
        Case::from(ReflectanceQuestion {
            name: "schlick-negative-index",
            section: SCHLICK_9,
            says: "n2 = -1.5, not an index: expected NaN \
                   (Schlick's R0 = ((1 + 1.5) / (1 - 1.5))^2 = 25 would be no reflectance at all)",
            schlick: true,
            cos_i: 0.8,
            n1: 1.0,
            n2: -1.5,
            expect: f64::NAN,
        }),
        Case::from(ReflectanceQuestion {
            name: "schlick-nearly-grazing",
            section: SCHLICK_9,
            says: "air to glass with cos_i = 1e-7: R = 0.04 + 0.96 (1 - 1e-7)^5, just below 1",
            schlick: true,
            cos_i: 1e-7,
            n1: 1.0,
            n2: 1.5,
            expect: 0.04 + 0.96 * (1.0 - f64::from(1e-7f32)).powi(5),
        }),
        Case::new(
            "transmittance-no-absorption-forever",
            ABSORPTION_9,
            "a channel that absorbs nothing keeps everything even over an infinite distance \
             (0 x inf would be NaN): (0, 0, 0) over inf gives (1, 1, 1)",
            CaseKind::Transmittance(TransmittanceCase {
                absorption: Vec3::ZERO,
                distance: f32::INFINITY,
            }),
        ),
        Case::new(
            "transmittance-absorbing-forever",
            ABSORPTION_9,
            "and a channel that absorbs keeps nothing of a ray that goes on for ever: \
             (0.2, 0.05, 0) over inf gives (0, 0, 1)",
            CaseKind::Transmittance(TransmittanceCase {
                absorption: Vec3::new(0.2, 0.05, 0.0),
                distance: f32::INFINITY,
            }),
        ),
    ]
}
