//! Chapter 8's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 8`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const SNELL_8: &str = "Snell-Descartes";
const TIR_8: &str = "Total internal reflection";
const ENTERING_8: &str = "Entering and leaving";

/// A `refract(dir, normal, eta)` question.
struct RefractQuestion {
    name: &'static str,
    section: &'static str,
    says: &'static str,
    dir: Vec3,
    normal: Vec3,
    eta: f32,
}

impl From<RefractQuestion> for Case {
    fn from(question: RefractQuestion) -> Case {
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::Refract(RefractCase {
                d: question.dir,
                n: question.normal,
                eta: question.eta,
            }),
        )
    }
}

/// Incident direction at `degrees` from the normal +y, travelling down.
fn at_angle(degrees: f64) -> Vec3 {
    let a = degrees.to_radians();
    Vec3::new(a.sin() as f32, -a.cos() as f32, 0.0)
}

/// A water surface y = 0 (object 0: k_t = 0.9, k_r = 0.1, no light of its
/// own, index 1.33) over a red and blue checkered floor y = -2 lit by
/// ambient light only; no lights.
const WATER_SCENE: &str = r#"
background = [0.55, 0.7, 0.9]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, -5.0]
look_at = [0.0, 0.0, 0.0]
[render]
max_depth = 5
[[objects]]
name = "water surface"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, reflectivity = 0.1, transparency = 0.9, ior = 1.33 }
[[objects]]
name = "floor"
plane = { point = [0.0, -2.0, 0.0], normal = [0.0, 1.0, 0.0] }
[objects.material]
color = [0.9, 0.1, 0.1]
ambient = 1.0
diffuse = 0.0
checker = { color = [0.1, 0.1, 0.9], size = 1.5 }
"#;

/// `count` clear panes y = 0, -1, ... (k_t = 0.5, index 1: rays go straight
/// through; white, k_a = 0.4, so each one's own light is 0.2), max_depth 2,
/// ambient light only: the colour tells how deep the refracted rays went.
fn stacked_panes(count: u32) -> String {
    let mut scene = String::from(
        "background = [0.55, 0.7, 0.9]\nambient_light = [1.0, 1.0, 1.0]\n[camera]\nposition = \
         [0.0, 1.0, -5.0]\nlook_at = [0.0, 0.0, 0.0]\n[render]\nmax_depth = 2\n",
    );
    for pane in 0..count {
        scene.push_str(&format!(
            "[[objects]]\nplane = {{ point = [0.0, -{pane}.0, 0.0], normal = [0.0, 1.0, 0.0] }}\n\
             material = {{ color = [1.0, 1.0, 1.0], ambient = 0.4, diffuse = 0.0, transparency = \
             0.5, ior = 1.0 }}\n"
        ));
    }
    scene
}

/// Where the image differs when every checkpoint passes: what to look at
/// in the heatmap.
pub const IMAGE_HINT: &str = "inside the glass: eta is n1/n2 on the way in and n2/n1 on the way out, total internal reflection sends the ray back, and the normal faces the side the ray comes from";

/// Chapter 8's checkpoints (level 1), in the order they run: the first
/// that fails is the one reported.
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn checkpoints() -> Vec<Case> {
    let glass = 1.5f32;
    vec![
        Case::from(RefractQuestion {
            name: "refract-normal-incidence",
            section: SNELL_8,
            says: "straight down into glass, (0, -2, 0) through a normal (0, 1, 0), eta = 1/1.5: \
                   straight on, as a unit vector (0, -1, 0)",
            dir: Vec3::new(0.0, -2.0, 0.0),
            normal: Vec3::Y,
            eta: 1.0 / glass,
        }),
        Case::from(RefractQuestion {
            name: "refract-air-to-glass-45",
            section: SNELL_8,
            says: "air to glass at 45 degrees, (1, -1, 0) through (0, 1, 0), eta = 1/1.5: sin t = \
                   sin 45 / 1.5 = 0.4714, so the unit direction (0.4714, -0.8819, 0)",
            dir: Vec3::new(1.0, -1.0, 0.0),
            normal: Vec3::Y,
            eta: 1.0 / glass,
        }),
        Case::from(RefractQuestion {
            name: "refract-glass-to-air",
            section: SNELL_8,
            says: "glass to air, (0.4, 0.9165, 0) through (0, 1, 0), eta = 1.5: sin i = 0.4, sin t \
                   = 0.6, so (0.6, 0.8, 0): away from the normal",
            dir: Vec3::new(0.4, (1.0f32 - 0.16).sqrt(), 0.0),
            normal: Vec3::Y,
            eta: glass,
        }),
        Case::from(RefractQuestion {
            name: "refract-normal-either-way",
            section: SNELL_8,
            says: "the 45 degree case with the normal given as (0, -3, 0): its length and side do \
                   not matter, expected (0.4714, -0.8819, 0)",
            dir: Vec3::new(1.0, -1.0, 0.0),
            normal: Vec3::new(0.0, -3.0, 0.0),
            eta: 1.0 / glass,
        }),
        Case::from(RefractQuestion {
            name: "refract-same-medium",
            section: SNELL_8,
            says: "eta = 1 (same medium on both sides): the ray goes straight on, as a unit vector",
            dir: Vec3::new(0.3, -0.5, 0.8),
            normal: Vec3::Y,
            eta: 1.0,
        }),
        Case::from(RefractQuestion {
            name: "refract-total-internal-reflection",
            section: TIR_8,
            says: "glass to air at 60 degrees, past the critical angle asin(1/1.5) = 41.8 degrees: \
                   sin t would be 1.5 * 0.866 = 1.3 > 1, expected None",
            dir: at_angle(60.0),
            normal: Vec3::Y,
            eta: glass,
        }),
        Case::from(ShadeQuestion {
            name: "glass-entering",
            section: ENTERING_8,
            says: "a ray from (0, 1, 0.7) along (1, -1, 0) enters water \
                   (index 1.33, k_t = 0.9, k_r = 0.1) at (1, 0, 0.7): entering, eta = 1/1.33, it \
                   bends toward the normal (sin t = 0.53) and meets the checkered floor y = -2 at \
                   x = 2.26; expected 0.9 * that floor colour + 0.1 * the sky",
            shading: Shading::Glass,
            scene: WATER_SCENE.to_string(),
            ray: (Vec3::new(0.0, 1.0, 0.7), Vec3::new(1.0, -1.0, 0.0)),
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "glass-total-internal-reflection",
            section: TIR_8,
            says: "an eye under water at (0, -1, 0.7) looking up along (1, 0.2, 0): leaving the \
                   water at 79 degrees from the normal, past the critical angle (48.8 degrees), \
                   nothing crosses; the transmitted share joins the reflected one: expected \
                   (0.1 + 0.9) * the floor colour at (15, -2, 0.7)",
            shading: Shading::Glass,
            scene: WATER_SCENE.to_string(),
            ray: (Vec3::new(0.0, -1.0, 0.7), Vec3::new(1.0, 0.2, 0.0)),
            depth: 0,
        }),
        Case::new(
            "glass-fractional-shares",
            ENTERING_8,
            "a glass pane (k_r = k_t = 0.5, tinted (1, 0.5, 0.25)) between a floor and a ceiling \
             pane (k_t = 0.75, own light 0.25 x 0.8 and 0.25 x 0.4), min_contribution 0.5, a ray \
             from (0, 1, 0) along (1, -1, 0): 0 x its own light + 0.5 x (1, 0.5, 0.25) x 0.2 \
             through + 0.5 x 0.1 reflected = (0.15, 0.1, 0.075); the rays it casts carry the \
             weights 0.5, so the floor's and ceiling's (0.5 x 0.75 < 0.5) are not cast",
            CaseKind::Shade(ShadeCase {
                shading: Shading::Glass,
                scene: PANES_SCENE.to_string(),
                ray: Ray::new(PANES_RAY.0, PANES_RAY.1),
                depth: 0,
                vertex_normals: None,
            }),
        ),
        Case::from(ShadeQuestion {
            name: "glass-depth-limit",
            section: ENTERING_8,
            says: "the entering ray at depth 5 = max_depth: no more rays, only the surface's own \
                   light, which is 0 here",
            shading: Shading::Glass,
            scene: WATER_SCENE.to_string(),
            ray: (Vec3::new(0.0, 1.0, 0.7), Vec3::new(1.0, -1.0, 0.0)),
            depth: 5,
        }),
        Case::from(ShadeQuestion {
            name: "glass-highlight-in-full",
            section: ENTERING_8,
            says: "a ray from (0, 1, 0) straight down meets a lit glass pane (k_r = 0.25, k_t = \
                   0.5, white, k_a = 0.4, k_s = 0.5, shininess 1, index 1.5) under a light at (0, \
                   10, 0): its own diffuse light (1 - 0.75) * 0.4 = 0.1, the highlight 0.5 in \
                   full (not scaled by 1 - k_r - k_t), and both rays see the sky (0.2, 0.4, 0.6): \
                   expected 0.1 + 0.5 + 0.75 * sky = (0.75, 0.9, 1.05)",
            shading: Shading::Glass,
            scene: lit_pane(""),
            ray: (Vec3::new(0.0, 1.0, 0.0), -Vec3::Y),
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "glass-depth-counts-refractions",
            section: ENTERING_8,
            says: "a ray from (0, 1, 0) straight down through a stack of five clear panes y = 0, \
                   -1, ..., -4 (k_t = 0.5, index 1, own light (1 - 0.5) * 0.4 = 0.2 each), \
                   max_depth = 2: the pane at depth 0, the next at depth 1, the third at depth 2 = \
                   max_depth, where the recursion stops; each refracted ray is one deeper than \
                   its parent: expected 0.2 + 0.5 * (0.2 + 0.5 * 0.2) = 0.35",
            shading: Shading::Glass,
            scene: stacked_panes(5),
            ray: (Vec3::new(0.0, 1.0, 0.0), -Vec3::Y),
            depth: 0,
        }),
    ]
}

/// Chapter 8's hard cases (level 2).
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn robustness() -> Vec<Case> {
    let glass = 1.5f32;
    let water = 1.33f32;
    let critical = (1.0 / 1.5f64).asin().to_degrees();
    robust(vec![
        Case::from(RefractQuestion {
            name: "refract-just-below-critical",
            section: TIR_8,
            says: "glass to air 0.01 degree below the critical angle: cos t = 0.0198, the refracted \
                   ray exists and skims the surface",
            dir: at_angle(critical - 0.01),
            normal: Vec3::Y,
            eta: glass,
        }),
        Case::from(RefractQuestion {
            name: "refract-just-above-critical",
            section: TIR_8,
            says: "glass to air 0.01 degree above the critical angle: None",
            dir: at_angle(critical + 0.01),
            normal: Vec3::Y,
            eta: glass,
        }),
        Case::from(RefractQuestion {
            name: "refract-grazing",
            section: SNELL_8,
            says: "air to glass at 89.99 degrees: cos i = 1.7e-4",
            dir: at_angle(89.99),
            normal: Vec3::Y,
            eta: 1.0 / glass,
        }),
        Case::from(RefractQuestion {
            name: "refract-near-normal",
            section: SNELL_8,
            says: "near-normal incidence, 1e-4 degree: sin^2 i from 1 - cos^2 i would be noise",
            dir: at_angle(1e-4),
            normal: Vec3::Y,
            eta: 1.0 / glass,
        }),
        Case::from(RefractQuestion {
            name: "refract-nested-media",
            section: SNELL_8,
            says: "glass into water at 40 degrees, eta = 1.5 / 1.33",
            dir: at_angle(40.0),
            normal: Vec3::Y,
            eta: glass / water,
        }),
        Case::from(RefractQuestion {
            name: "refract-unnormalised-input",
            section: SNELL_8,
            says: "air to glass at 45 degrees with d = (3, -3, 0) and n = (0, 0.25, 0)",
            dir: Vec3::new(3.0, -3.0, 0.0),
            normal: Vec3::new(0.0, 0.25, 0.0),
            eta: 1.0 / glass,
        }),
        Case::from(RefractQuestion {
            name: "refract-same-medium-short-direction",
            section: SNELL_8,
            says: "eta = 1 with the short direction (1e-4, -2e-4, 2e-4), length 3e-4: straight on, \
                   as a unit vector (1/3, -2/3, 2/3) (a shortcut for eta = 1 that keeps a \
                   direction already unit must not keep this one)",
            dir: Vec3::new(1e-4, -2e-4, 2e-4),
            normal: Vec3::Y,
            eta: 1.0,
        }),
        Case::from(RefractQuestion {
            name: "refract-zero-normal",
            section: SNELL_8,
            says: "a zero normal: None",
            dir: at_angle(30.0),
            normal: Vec3::ZERO,
            eta: 1.0 / glass,
        }),
        Case::from(RefractQuestion {
            name: "refract-nan-direction",
            section: SNELL_8,
            says: "a NaN direction: None",
            dir: Vec3::new(f32::NAN, -1.0, 0.0),
            normal: Vec3::Y,
            eta: 1.0 / glass,
        }),
        Case::from(RefractQuestion {
            name: "refract-nan-eta",
            section: SNELL_8,
            says: "eta = NaN: None",
            dir: at_angle(30.0),
            normal: Vec3::Y,
            eta: f32::NAN,
        }),
        Case::from(RefractQuestion {
            name: "refract-zero-eta",
            section: SNELL_8,
            says: "eta = 0: None",
            dir: at_angle(30.0),
            normal: Vec3::Y,
            eta: 0.0,
        }),
    ])
}
