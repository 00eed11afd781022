//! Chapter 6's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 6`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const FORMULA_6: &str = "The reflection formula";
const RECURSION_6: &str = "The recursion";

/// A `reflect(dir, normal)` question.
struct ReflectQuestion {
    name: &'static str,
    section: &'static str,
    says: &'static str,
    dir: Vec3,
    normal: Vec3,
}

impl From<ReflectQuestion> for Case {
    fn from(question: ReflectQuestion) -> Case {
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::Reflect(ReflectCase {
                d: question.dir,
                n: question.normal,
            }),
        )
    }
}

/// A mirror floor (object 0, k_r = 0.5, grey 0.4 lit by ambient light only)
/// and a red ball above it; no lights.
const MIRROR_SCENE: &str = r#"
background = [0.55, 0.7, 0.9]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, -5.0]
look_at = [0.0, 0.0, 0.0]
[render]
max_depth = 5
[[objects]]
name = "mirror floor"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [0.4, 0.4, 0.4], ambient = 1.0, diffuse = 0.0, reflectivity = 0.5 }
[[objects]]
name = "red ball"
sphere = { center = [0.0, 1.0, 4.0], radius = 1.0 }
material = { color = [0.9, 0.1, 0.1], ambient = 1.0, diffuse = 0.0 }
"#;

/// A mirror floor (object 0, k_r = 0.5, grey 0.4 lit by ambient light,
/// with a highlight k_s = 0.5 of shininess 1) under a light at (0, 10, 0).
const LIT_MIRROR_SCENE: &str = r#"
background = [0.55, 0.7, 0.9]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, -5.0]
look_at = [0.0, 0.0, 0.0]
[render]
max_depth = 5
[[lights]]
position = [0.0, 10.0, 0.0]
[[objects]]
name = "lit mirror floor"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [0.4, 0.4, 0.4], ambient = 1.0, diffuse = 0.0, specular = 0.5, shininess = 1, reflectivity = 0.5 }
"#;

/// Two facing mirrors, a floor (object 0) and a ceiling at height 2, each
/// k_r = 0.5 and grey 0.4 lit by ambient light only (its own share
/// (1 - 0.5) * 0.4 = 0.2); no lights. A slanted ray bounces between them
/// for ever: only `max_depth` and `min_contribution` (`render`, a TOML
/// table body) end the recursion, and the colour tells how many bounces
/// were traced: 0.2 * (1 + 0.5 + 0.25 + ...), one term per point shaded.
fn two_mirrors(render: &str) -> String {
    format!(
        r#"
background = [0.55, 0.7, 0.9]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, -5.0]
look_at = [0.0, 1.0, 0.0]
[render]
{render}
[[objects]]
name = "mirror floor"
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }}
material = {{ color = [0.4, 0.4, 0.4], ambient = 1.0, diffuse = 0.0, reflectivity = 0.5 }}
[[objects]]
name = "mirror ceiling"
plane = {{ point = [0.0, 2.0, 0.0], normal = [0.0, -1.0, 0.0] }}
material = {{ color = [0.4, 0.4, 0.4], ambient = 1.0, diffuse = 0.0, reflectivity = 0.5 }}
"#
    )
}

/// Where the image differs when every checkpoint passes: what to look at
/// in the heatmap.
pub const IMAGE_HINT: &str = "on the mirrors: the reflected light counts with the share k and the local light with 1 - k, the depth limit stops the recursion, and the reflected ray starts off the surface";

/// Chapter 6's checkpoints (level 1), in the order they run: the first
/// that fails is the one reported.
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn checkpoints() -> Vec<Case> {
    vec![
        Case::from(ReflectQuestion {
            name: "reflect-floor",
            section: FORMULA_6,
            says: "(1, -1, 0) bouncing off a floor with normal (0, 1, 0) leaves along (1, 1, 0)",
            dir: Vec3::new(1.0, -1.0, 0.0),
            normal: Vec3::Y,
        }),
        Case::from(ReflectQuestion {
            name: "reflect-normal-length",
            section: FORMULA_6,
            says: "the normal's length does not matter: (1, -2, 3) off a normal (0, 7, 0) gives \
                   (1, 2, 3)",
            dir: Vec3::new(1.0, -2.0, 3.0),
            normal: Vec3::new(0.0, 7.0, 0.0),
        }),
        Case::from(ReflectQuestion {
            name: "reflect-normal-flipped",
            section: FORMULA_6,
            says: "nor its orientation: (1, -2, 3) off a normal (0, -0.25, 0) gives (1, 2, 3)",
            dir: Vec3::new(1.0, -2.0, 3.0),
            normal: Vec3::new(0.0, -0.25, 0.0),
        }),
        Case::from(ReflectQuestion {
            name: "reflect-normal-incidence",
            section: FORMULA_6,
            says: "straight at a wall: (0, 0, -2) off a normal (0, 0, 1) comes back as (0, 0, 2), \
                   the same length",
            dir: Vec3::new(0.0, 0.0, -2.0),
            normal: Vec3::Z,
        }),
        Case::from(ReflectQuestion {
            name: "reflect-45-mirror",
            section: FORMULA_6,
            says: "a mirror at 45 degrees (normal (-1, 1, 0)) turns +x into +y",
            dir: Vec3::X,
            normal: Vec3::new(-1.0, 1.0, 0.0),
        }),
        Case::from(ShadeQuestion {
            name: "mirror-sees-sky",
            section: RECURSION_6,
            says: "a ray from (0, 1, -5) along (0, -1, 1) meets the mirror floor \
                   (k_r = 0.5, own colour 0.4) at (0, 0, -4) and is reflected to the sky \
                   (0.55, 0.7, 0.9): expected (1 - 0.5) * 0.4 + 0.5 * sky = (0.475, 0.55, 0.65)",
            shading: Shading::Mirror,
            scene: MIRROR_SCENE.to_string(),
            ray: (Vec3::new(0.0, 1.0, -5.0), Vec3::new(0.0, -1.0, 1.0)),
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "mirror-sees-ball",
            section: RECURSION_6,
            says: "a ray from (0, 1, 1) along (0, -1, 1.5) meets the mirror floor at (0, 0, 2.5) \
                   and is reflected into the red ball (0.9, 0.1, 0.1): expected 0.2 + 0.5 * ball = \
                   (0.65, 0.25, 0.25)",
            shading: Shading::Mirror,
            scene: MIRROR_SCENE.to_string(),
            ray: (Vec3::new(0.0, 1.0, 1.0), Vec3::new(0.0, -1.0, 1.5)),
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "mirror-depth-limit",
            section: RECURSION_6,
            says: "the sky case at depth 5 = max_depth: no more bounces, only the local share \
                   (1 - 0.5) * 0.4 = 0.2",
            shading: Shading::Mirror,
            scene: MIRROR_SCENE.to_string(),
            ray: (Vec3::new(0.0, 1.0, -5.0), Vec3::new(0.0, -1.0, 1.0)),
            depth: 5,
        }),
        Case::from(ShadeQuestion {
            name: "mirror-depth-counts-bounces",
            section: RECURSION_6,
            says: "a ray from (0, 1, 0) along (0, -1, 1) between two facing mirrors \
                   (k_r = 0.5, own share 0.2 each), max_depth = 2: the floor at depth 0, the \
                   ceiling at depth 1, the floor again at depth 2 = max_depth, where the recursion \
                   stops. Expected 0.2 + 0.5 * (0.2 + 0.5 * 0.2) = 0.35 (each reflected ray one \
                   deeper; without the limit the weights alone stop it after 10 points, 0.3996)",
            shading: Shading::Mirror,
            scene: two_mirrors("max_depth = 2"),
            ray: (Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, -1.0, 1.0)),
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "mirror-min-contribution",
            section: RECURSION_6,
            says: "the same ray between the two mirrors with max_depth = 5 but min_contribution = \
                   0.2: the reflected rays weigh 0.5 and 0.25 in the pixel, the next would weigh \
                   0.125 < 0.2 and is not cast. Expected 0.2 + 0.5 * (0.2 + 0.5 * 0.2) = 0.35 \
                   (each reflected ray's weight is its parent's times k_r; traced to max_depth, \
                   0.39375)",
            shading: Shading::Mirror,
            scene: two_mirrors("max_depth = 5\nmin_contribution = 0.2"),
            ray: (Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, -1.0, 1.0)),
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "mirror-highlight-in-full",
            section: RECURSION_6,
            says: "a ray from (0, 1, 0) straight down meets a lit mirror floor (k_r = 0.5, own \
                   colour 0.4, k_s = 0.5, shininess 1) at the origin, under a light at (0, 10, 0): \
                   the highlight is 0.5 * 1^1 = 0.5 and is not scaled by 1 - k_r, the reflected \
                   ray sees the sky: expected 0.5 * 0.4 + 0.5 + 0.5 * (0.55, 0.7, 0.9) = (0.975, \
                   1.05, 1.15)",
            shading: Shading::Mirror,
            scene: LIT_MIRROR_SCENE.to_string(),
            ray: (Vec3::new(0.0, 1.0, 0.0), -Vec3::Y),
            depth: 0,
        }),
    ]
}

/// Chapter 6's hard cases (level 2).
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn robustness() -> Vec<Case> {
    robust(vec![
        Case::from(ReflectQuestion {
            name: "reflect-huge-direction",
            section: FORMULA_6,
            says: "a direction (3e38, -3e38, 0) near f32::MAX: 2 (d.n) overflows, the answer \
                   (3e38, 3e38, 0) does not",
            dir: Vec3::new(3e38, -3e38, 0.0),
            normal: Vec3::Y,
        }),
        Case::from(ReflectQuestion {
            name: "reflect-tiny-normal",
            section: FORMULA_6,
            says: "a normal of length 1e-30: n.n underflows to 0",
            dir: Vec3::new(1.0, -1.0, 0.5),
            normal: Vec3::new(0.0, 1e-30, 1e-30),
        }),
        Case::from(ReflectQuestion {
            name: "reflect-huge-normal",
            section: FORMULA_6,
            says: "a normal of length 1e30: n.n overflows",
            dir: Vec3::new(1.0, -1.0, 0.5),
            normal: Vec3::new(1e30, 1e30, 0.0),
        }),
        Case::from(ReflectQuestion {
            name: "reflect-tiny-direction",
            section: FORMULA_6,
            says: "a direction of length 1e-20 keeps its length",
            dir: Vec3::new(1e-20, -2e-20, 3e-20),
            normal: Vec3::new(0.2, 0.9, -0.4),
        }),
        Case::from(ReflectQuestion {
            name: "reflect-awkward-normal",
            section: FORMULA_6,
            says: "a slanted normal with awkward components",
            dir: Vec3::new(0.1, 0.7, -0.3),
            normal: Vec3::new(0.577, -0.123, 0.808),
        }),
        Case::from(ReflectQuestion {
            name: "reflect-zero-normal",
            section: FORMULA_6,
            says: "a zero normal: NaN, not a plausible direction",
            dir: Vec3::X,
            normal: Vec3::ZERO,
        }),
    ])
}
