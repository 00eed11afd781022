//! Chapter 13's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 13`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const EQUATION_13: &str = "The rendering equation";
const COSINE_13: &str = "Cosine-weighted directions";
const ROULETTE_13: &str = "Russian roulette";
const NEE_13: &str = "Next-event estimation";
const MIS_13: &str = "Multiple importance sampling";
const FURNACE_13: &str = "The white furnace";
const HARD_13: &str = "The hard cases";

/// Where the image differs when every checkpoint passes: what to look at
/// in the heatmap.
pub const IMAGE_HINT: &str = "in whole regions when an estimate is biased: emission counted twice with next-event estimation, a pdf without its cosine, roulette survivors not divided by their chance";

fn formula(name: &'static str, section: &'static str, says: &str, formula: PathFormula) -> Case {
    Case::new(
        name,
        section,
        says,
        CaseKind::PathFormula(PathFormulaCase { formula }),
    )
}

/// A furnace question: the sphere of albedo `albedo` and emission
/// `emission` seen from inside with `without` left out converges to
/// `emission / (1 - albedo)`.
fn furnace(
    name: &'static str,
    function: &'static str,
    says: &str,
    albedo: f32,
    emission: f32,
    without: &'static [&'static str],
) -> Case {
    Case::new(
        name,
        FURNACE_13,
        says,
        CaseKind::Converges(ConvergesCase {
            function,
            scene: inside_sphere(albedo, emission, ""),
            without,
            samples: 20_000,
            expected: f64::from(emission) / (1.0 - f64::from(albedo)),
            seed: 0,
        }),
    )
}

/// Chapter 13's checkpoints (level 1), in the order they run: the first
/// that fails is the one reported.
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn checkpoints() -> Vec<Case> {
    use std::f64::consts::PI;
    vec![
        formula(
            "cosine-pdf-normal",
            COSINE_13,
            "the density of the direction along the normal: cos(0) / pi = 1 / pi",
            PathFormula::CosinePdf {
                cos_theta: 1.0,
                expected: 1.0 / PI,
            },
        ),
        formula(
            "cosine-pdf-60",
            COSINE_13,
            "the density of a direction 60 degrees from the normal: cos(60) / pi = 0.5 / pi",
            PathFormula::CosinePdf {
                cos_theta: 0.5,
                expected: 0.5 / PI,
            },
        ),
        formula(
            "cosine-pdf-below",
            COSINE_13,
            "a direction below the surface (cos = -0.5) is never drawn: density 0",
            PathFormula::CosinePdf {
                cos_theta: -0.5,
                expected: 0.0,
            },
        ),
        Case::new(
            "cosine-directions-spread",
            COSINE_13,
            "200,000 directions from cosine_hemisphere are unit, above the surface (z >= 0) and \
             spread as cos(theta) / pi: a chi-square test on 20 bins of cos(theta) over [-1, 1] \
             by 20 of phi",
            CaseKind::CosineSample(CosineSampleCase {
                samples: DIRECTION_SAMPLES,
                seed: 0,
            }),
        ),
        formula(
            "mis-equal",
            MIS_13,
            "two strategies with the same density share a direction equally: 1 / (1 + 1) = 0.5",
            PathFormula::PowerHeuristic {
                pdf: 1.0,
                other: 1.0,
                expected: 0.5,
            },
        ),
        formula(
            "mis-two-to-one",
            MIS_13,
            "densities 2 and 1: 2^2 / (2^2 + 1^2) = 0.8",
            PathFormula::PowerHeuristic {
                pdf: 2.0,
                other: 1.0,
                expected: 0.8,
            },
        ),
        formula(
            "mis-one-to-two",
            MIS_13,
            "densities 1 and 2: the other share, 1 / 5 = 0.2 (the two weights add to 1)",
            PathFormula::PowerHeuristic {
                pdf: 1.0,
                other: 2.0,
                expected: 0.2,
            },
        ),
        formula(
            "mis-cannot-draw",
            MIS_13,
            "a strategy that cannot draw the direction (density 0) gets none of it",
            PathFormula::PowerHeuristic {
                pdf: 0.0,
                other: 3.0,
                expected: 0.0,
            },
        ),
        formula(
            "mis-a-delta-takes-all",
            MIS_13,
            "a delta strategy (a point light: infinite density) against a density of 2: it takes \
             the whole sample, weight 1",
            PathFormula::PowerHeuristic {
                pdf: f32::INFINITY,
                other: 2.0,
                expected: 1.0,
            },
        ),
        formula(
            "mis-against-a-delta",
            MIS_13,
            "a density of 2 against a delta strategy: the delta takes the whole sample, so this \
             one gets 0 (the two weights add to 1)",
            PathFormula::PowerHeuristic {
                pdf: 2.0,
                other: f32::INFINITY,
                expected: 0.0,
            },
        ),
        formula(
            "roulette-survives",
            ROULETTE_13,
            "a path of weight 0.25 goes on with probability 0.25: for u = 0.1 it survives, and \
             carries 1 / 0.25 = 4 times more",
            PathFormula::Roulette {
                weight: 0.25,
                u: 0.1,
                expected: Some(4.0),
            },
        ),
        formula(
            "roulette-ends",
            ROULETTE_13,
            "a path of weight 0.25 with u = 0.3 (above 0.25) ends",
            PathFormula::Roulette {
                weight: 0.25,
                u: 0.3,
                expected: None,
            },
        ),
        formula(
            "roulette-bright",
            ROULETTE_13,
            "a path of weight 2 (above 1) always survives, and keeps its weight: Some(1)",
            PathFormula::Roulette {
                weight: 2.0,
                u: 0.99,
                expected: Some(1.0),
            },
        ),
        furnace(
            "furnace-scattered-only",
            "shade_path",
            "inside a closed sphere of albedo 0.5 that emits 1, without light samples nor \
             roulette, every path converges to 1 / (1 - 0.5) = 2",
            0.5,
            1.0,
            &["next-event", "russian-roulette"],
        ),
        furnace(
            "furnace-roulette",
            "russian_roulette",
            "the same sphere with Russian roulette: still 2 (the survivors carry the light of \
             the paths ended). A wrong answer is in russian_roulette or in shade_path (a \
             survivor's weight multiplied by the 1 / q it returns)",
            0.5,
            1.0,
            &["next-event"],
        ),
        furnace(
            "furnace-next-event",
            "next_event",
            "the same sphere with a light sample at each point and no MIS: still 2. A wrong \
             answer is in next_event (its f cos / pdf) or in shade_path (a light that a \
             scattered ray finds must not be counted again)",
            0.5,
            1.0,
            &["mis", "russian-roulette"],
        ),
        furnace(
            "furnace-mis",
            "shade_path",
            "a sphere of albedo 0.8 that emits 0.5, with light samples, MIS and roulette: \
             0.5 / (1 - 0.8) = 2.5. A wrong answer is in the MIS weights: next_event's of the \
             light sample and shade_path's of the light a scattered ray finds must add to 1",
            0.8,
            0.5,
            &[],
        ),
        Case::new(
            "furnace-one-sided",
            FURNACE_13,
            "a sphere of albedo 0.5 that glows from its outside only, seen from inside: every \
             point shows its back, which gives nothing: radiance 0. Count a point's emission as \
             point.emitted() does, not point.material.emission",
            CaseKind::Converges(ConvergesCase {
                function: "shade_path",
                scene: inside_sphere_glowing_outward(0.5, 1.0),
                without: &[],
                samples: 2_000,
                expected: 0.0,
                seed: 0,
            }),
        ),
        Case::new(
            "point-light-in-sphere",
            NEE_13,
            "a point light of intensity pi at the centre of a sphere of albedo 0.5 (pbrt-v4's \
             analytic scene): the light gives 0.5 / pi * pi / 1^2 = 0.5 at every point, the \
             bounces 0.5 more: radiance 1",
            CaseKind::Converges(ConvergesCase {
                function: "next_event",
                scene: inside_sphere(
                    0.5,
                    0.0,
                    "[[lights]]\nposition = [0.0, 0.0, 0.0]\nintensity = 3.14159265",
                ),
                without: &[],
                samples: 20_000,
                expected: 1.0,
                seed: 0,
            }),
        ),
        Case::new(
            "point-light-in-a-glowing-sphere",
            MIS_13,
            "pbrt-v4's analytic scene in a sphere that also glows with radiance 1: the point \
             light gives 0.5 at every point, so L = 1 + 0.5 + 0.5 L: radiance 3. MIS is on (the \
             sphere emits), but a point light's sample keeps weight 1: no scattered ray finds it",
            CaseKind::Converges(ConvergesCase {
                function: "next_event",
                scene: inside_sphere(
                    0.5,
                    1.0,
                    "[[lights]]\nposition = [0.0, 0.0, 0.0]\nintensity = 3.14159265",
                ),
                without: &[],
                samples: 20_000,
                expected: 3.0,
                seed: 0,
            }),
        ),
        Case::new(
            "two-point-lights-in-sphere",
            NEE_13,
            "pbrt-v4's analytic scene with its light split in two at the centre, of intensities \
             pi / 4 and 3 pi / 4: a light sample chooses one of them, each with chance 1 / 2, \
             and divides by that chance, so the two together still give radiance 1",
            CaseKind::Converges(ConvergesCase {
                function: "next_event",
                scene: inside_sphere(
                    0.5,
                    0.0,
                    "[[lights]]\nposition = [0.0, 0.0, 0.0]\nintensity = 0.78539816\n\
                     [[lights]]\nposition = [0.0, 0.0, 0.0]\nintensity = 2.35619449",
                ),
                without: &[],
                samples: 20_000,
                expected: 1.0,
                seed: 0,
            }),
        ),
        Case::new(
            "light-over-a-roof",
            NEE_13,
            "a point light above a black roof, a floor under the roof: every light sample's \
             shadow ray meets the roof, and the floor is black (exactly 0)",
            CaseKind::Converges(ConvergesCase {
                function: "next_event",
                scene: LIGHT_OVER_A_ROOF.to_string(),
                without: &[],
                samples: 2_000,
                expected: 0.0,
                seed: 0,
            }),
        ),
        Case::new(
            "glossy-plate-under-a-sky",
            MIS_13,
            "a glossy plate of colour 0.5 (roughness 0.5) seen head-on under a sky of radiance 1: \
             its normalised lobe about the normal returns all it reflects, radiance 0.5. The \
             light sample must weigh by the lobe's f and, with MIS, by the lobe's own density, \
             neither of which is Lambert's here",
            CaseKind::Converges(ConvergesCase {
                function: "next_event",
                scene: GLOSSY_PLATE_UNDER_A_SKY.to_string(),
                without: &[],
                samples: 20_000,
                expected: 0.5,
                seed: 0,
            }),
        ),
        Case::new(
            "furnace-mirror-and-glass",
            NEE_13,
            "the furnace of albedo 0.5 that emits 1, with a glass ball and a white mirror ball in \
             it: neither loses light, so every pixel is still 2. A light a mirror's or glass's \
             ray finds counts fully, as no light sample could aim along that ray",
            CaseKind::Converges(ConvergesCase {
                function: "shade_path",
                scene: inside_sphere(0.5, 1.0, MIRROR_AND_GLASS),
                without: &[],
                samples: 20_000,
                expected: 2.0,
                seed: 0,
            }),
        ),
        Case::new(
            "absorbing-ball",
            EQUATION_13,
            "a ball of radius 1 that absorbs 0.5 per unit (index 1: no bending, no reflection), \
             seen through its centre against a wall of radiance 1: the light crosses 2 units of \
             it, exp(-0.5 x 2) = exp(-1) = 0.367879. shade_path dims what a ray sees by the \
             medium it crossed",
            CaseKind::Converges(ConvergesCase {
                function: "shade_path",
                scene: ABSORBING_BALL.to_string(),
                without: &[],
                samples: 256,
                expected: (-1.0f64).exp(),
                seed: 0,
            }),
        ),
        Case::new(
            "furnace-max-depth",
            ROULETTE_13,
            "the furnace of albedo 0.5 that emits 1 with max_depth = 2, without light samples \
             nor roulette: the camera's point and two bounces, 1 + 0.5 + 0.25 = 1.75 (a path \
             bounces at most max_depth times)",
            CaseKind::Converges(ConvergesCase {
                function: "shade_path",
                scene: inside_sphere(0.5, 1.0, "").replace("max_depth = 64", "max_depth = 2"),
                without: &["next-event", "russian-roulette"],
                samples: 256,
                expected: 1.75,
                seed: 0,
            }),
        ),
    ]
}

/// A floor under a black roof, a point light above the roof.
const LIGHT_OVER_A_ROOF: &str = r#"
background = [0.0, 0.0, 0.0]
[camera]
position = [0.0, 0.5, -1.0]
look_at = [0.0, 0.0, 0.0]
[render]
width = 8
height = 8
samples = 1
max_depth = 8
[[lights]]
position = [0.0, 2.0, 0.0]
intensity = 10.0
[[objects]]
name = "floor"
quad = { corner = [-10.0, 0.0, -10.0], u = [0.0, 0.0, 20.0], v = [20.0, 0.0, 0.0] }
material = { color = [0.8, 0.8, 0.8] }
[[objects]]
name = "black roof"
quad = { corner = [-10.0, 1.0, -10.0], u = [20.0, 0.0, 0.0], v = [0.0, 0.0, 20.0] }
material = { color = [0.0, 0.0, 0.0] }
"#;

/// A glossy plate facing the camera inside a sphere that glows inward
/// with radiance 1 and reflects nothing: seen head-on (a 1-degree view),
/// the plate's normalised lobe lies about its normal, and the plate
/// returns its colour times the sky.
const GLOSSY_PLATE_UNDER_A_SKY: &str = r#"
background = [0.0, 0.0, 0.0]
[camera]
position = [0.0, 0.0, -0.5]
look_at = [0.0, 0.0, 0.0]
fov_degrees = 1.0
[render]
width = 8
height = 8
samples = 1
max_depth = 64
[[objects]]
name = "sky"
sphere = { center = [0.0, 0.0, 0.0], radius = 1.0 }
material = { color = [0.0, 0.0, 0.0], emission = [1.0, 1.0, 1.0], two_sided = true }
[[objects]]
name = "glossy plate"
quad = { corner = [-0.6, -0.6, 0.0], u = [0.0, 1.2, 0.0], v = [1.2, 0.0, 0.0] }
material = { color = [0.5, 0.5, 0.5], reflectivity = 1.0, roughness = 0.5 }
"#;

/// A glass ball and a white mirror ball inside the furnace, in the
/// camera's view.
const MIRROR_AND_GLASS: &str = r#"
[[objects]]
name = "glass ball"
sphere = { center = [-0.2, 0.0, 0.5], radius = 0.25 }
material = { color = [1.0, 1.0, 1.0], transparency = 1.0, ior = 1.5, fresnel = "exact" }
[[objects]]
name = "mirror ball"
sphere = { center = [0.3, 0.0, 0.5], radius = 0.2 }
material = { color = [1.0, 1.0, 1.0], reflectivity = 1.0 }
"#;

/// A ball that absorbs but neither bends nor reflects (index 1), seen
/// through its centre in a narrow view, against a black wall glowing
/// with radiance 1.
const ABSORBING_BALL: &str = r#"
background = [0.0, 0.0, 0.0]
[camera]
position = [0.0, 0.0, 0.0]
look_at = [0.0, 0.0, 3.0]
fov_degrees = 0.2
[render]
width = 8
height = 8
samples = 1
max_depth = 64
[[objects]]
name = "glowing wall"
sphere = { center = [0.0, 0.0, 0.0], radius = 10.0 }
material = { color = [0.0, 0.0, 0.0], emission = [1.0, 1.0, 1.0], two_sided = true }
[[objects]]
name = "absorbing ball"
sphere = { center = [0.0, 0.0, 3.0], radius = 1.0 }
material = { color = [1.0, 1.0, 1.0], transparency = 1.0, ior = 1.0, fresnel = "exact", absorption = [0.5, 0.5, 0.5] }
"#;

/// A floor lit only by a light under it, shining from both faces up at
/// the floor's underside: seen from above, black.
const LIGHT_UNDER_THE_FLOOR: &str = r#"
background = [0.0, 0.0, 0.0]
[camera]
position = [0.0, 2.0, -2.0]
look_at = [0.0, 0.0, 0.0]
[render]
width = 8
height = 8
max_depth = 8
[[objects]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [0.8, 0.8, 0.8] }
[[objects]]
quad = { corner = [-1.0, -0.5, -1.0], u = [2.0, 0.0, 0.0], v = [0.0, 0.0, 2.0] }
material = { color = [0.0, 0.0, 0.0], emission = [5.0, 5.0, 5.0], two_sided = true }
"#;

/// Chapter 13's hard cases (level 2).
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn robustness() -> Vec<Case> {
    robust(vec![
        formula(
            "cosine-pdf-grazing",
            HARD_13,
            "a grazing direction (cos = 0) has density 0, not a NaN",
            PathFormula::CosinePdf {
                cos_theta: 0.0,
                expected: 0.0,
            },
        ),
        formula(
            "mis-both-zero",
            HARD_13,
            "neither strategy can draw the direction (0 and 0): weight 0, not 0 / 0",
            PathFormula::PowerHeuristic {
                pdf: 0.0,
                other: 0.0,
                expected: 0.0,
            },
        ),
        formula(
            "mis-huge-densities",
            HARD_13,
            "densities of 1e30 and 1e30 (a light seen edge-on): 0.5, not inf / inf",
            PathFormula::PowerHeuristic {
                pdf: 1e30,
                other: 1e30,
                expected: 0.5,
            },
        ),
        formula(
            "roulette-zero-weight",
            HARD_13,
            "a path that carries nothing (weight 0) ends, even for u = 0",
            PathFormula::Roulette {
                weight: 0.0,
                u: 0.0,
                expected: None,
            },
        ),
        Case::new(
            "light-under-the-floor",
            HARD_13,
            "a light under the floor lights its underside only: every light sample from above \
             is behind the surface, and the floor is black (exactly 0)",
            CaseKind::Converges(ConvergesCase {
                function: "next_event",
                scene: LIGHT_UNDER_THE_FLOOR.to_string(),
                without: &[],
                samples: 4_000,
                expected: 0.0,
                seed: 0,
            }),
        ),
        Case::new(
            "lamp-on-the-wall-seen-from-inside",
            HARD_13,
            "a point light exactly on the wall of a closed sphere of albedo 0.5, seen from \
             inside: not strictly inside the sphere, it is hidden by it, as any light outside \
             is, whatever the shadow ray's rounding says about a wall met at t = 1 exactly: \
             the sphere is black (exactly 0)",
            CaseKind::Converges(ConvergesCase {
                function: "next_event",
                scene: inside_sphere(
                    0.5,
                    0.0,
                    "[[lights]]\nposition = [0.0, 0.0, 1.0]\nintensity = 3.14159265",
                ),
                without: &[],
                samples: 4_000,
                expected: 0.0,
                seed: 0,
            }),
        ),
        formula(
            "roulette-nan-weight",
            HARD_13,
            "a path whose weight is NaN ends rather than spread the NaN",
            PathFormula::Roulette {
                weight: f32::NAN,
                u: 0.0,
                expected: None,
            },
        ),
    ])
}
