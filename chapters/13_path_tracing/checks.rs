//! Chapter 13's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 13`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

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
             spread as cos(theta) / pi: a chi-square test on 20 x 20 bins of cos(theta) and phi",
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
    ]
}

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
