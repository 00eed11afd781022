//! Cases on chapter 13's Monte Carlo code: the sampled directions against
//! their density (a chi-square test), the weights and the roulette by hand,
//! and whole estimators against the value a closed scene must converge to.
//!
//! A sampler or an estimator is random, so a correct one can fail a
//! statistical test by bad luck and a wrong one pass by good luck. Each
//! test here is run on one fixed stream of numbers, so its verdict is the
//! same every time, and its threshold makes a false alarm rare: a correct
//! answer of a student fails it with probability [`FALSE_ALARM`] or less,
//! whatever its own formula, while every wrong distribution of the bug
//! gallery misses it by orders of magnitude.

use super::*;
use crate::scene::SwitchedOff;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// The chance, per statistical case, that a correct answer fails: a 1%
/// budget split evenly over [`STATISTICAL_CASES`] tests (Bonferroni's
/// correction), so that a correct chapter fails any of them with a chance
/// of at most 1%, however the tests depend on each other. Mitsuba's and
/// pbrt-v4's sampling tests take Sidak's `1 - (1 - 0.01)^(1/n)` instead,
/// exact for independent tests and a hair looser (6.28e-4 against 6.25e-4
/// for 16).
pub const FALSE_ALARM: f64 = 1e-2 / STATISTICAL_CASES as f64;

/// How many statistical cases chapter 13 asks at most, for
/// [`FALSE_ALARM`]'s correction: a test counts them, and fewer only make
/// the 1% safer.
pub const STATISTICAL_CASES: usize = 16;

/// Bins of the direction tests: in `cos(theta)` over `[-1, 1]` (the lower
/// half must stay empty) and in `phi` over `[0, 2 pi)`.
const COSINE_BINS: usize = 20;
const PHI_BINS: usize = 20;

/// Samples of a direction test: enough that a pdf wrong by 5% in a band of
/// the hemisphere is far beyond the threshold.
pub const DIRECTION_SAMPLES: u32 = 200_000;

/// A number in `[0, 1)` from a fixed hash of `index` and `dimension`: the
/// stream every direction test draws from.
pub fn stream(index: u32, dimension: u32) -> f32 {
    seeded_stream(0, index, dimension)
}

/// [`stream`] under `seed` (0 is [`stream`] itself): `grade --fresh`'s
/// other draws of the same test.
pub fn seeded_stream(seed: u64, index: u32, dimension: u32) -> f32 {
    let mut word = (0x243F_6A88_85A3_08D3_u64 ^ seed.wrapping_mul(0xD1B5_4A32_D192_ED03))
        ^ (u64::from(index) << 32 | u64::from(dimension));
    word = word.wrapping_add(0x9E37_79B9_7F4A_7C15);
    word = (word ^ (word >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    word = (word ^ (word >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    word ^= word >> 31;
    (word >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

/// The chi-square goodness of fit of `directions` (unit vectors) to the
/// density `cos(theta) / pi` about +z: Pearson's statistic over bins of
/// the sphere, the bins expected to hold fewer than 5 pooled into one
/// (the rule of Cochran, as pbrt-v4's and Mitsuba's tests pool them), and
/// its p-value. With [`DIRECTION_SAMPLES`] the emptiest bin above the
/// surface expects 100, so nothing is pooled; the rule guards smaller
/// counts. `Err` names a direction that cannot come from the density
/// at all (below the surface, not unit, NaN).
pub fn cosine_fit(directions: &[Vec3]) -> Result<(f64, f64), String> {
    let mut observed = vec![0f64; COSINE_BINS * PHI_BINS];
    for direction in directions {
        let length = f64::from(direction.length());
        if !direction.is_finite() || (length - 1.0).abs() > 1e-4 {
            return Err(format!(
                "the direction {} is not unit length",
                vec(*direction)
            ));
        }
        if direction.z < 0.0 {
            return Err(format!(
                "the direction {} is below the surface (z < 0), where the density is 0",
                vec(*direction)
            ));
        }
        let cosine = (f64::from(direction.z) + 1.0) / 2.0;
        let phi = f64::from(direction.y)
            .atan2(f64::from(direction.x))
            .rem_euclid(std::f64::consts::TAU)
            / std::f64::consts::TAU;
        let row = ((cosine * COSINE_BINS as f64) as usize).min(COSINE_BINS - 1);
        let column = ((phi * PHI_BINS as f64) as usize).min(PHI_BINS - 1);
        observed[row * PHI_BINS + column] += 1.0;
    }
    let total = directions.len() as f64;
    // The probability of a bin cos in [c0, c1], phi in a 1/PHI_BINS share:
    // the integral of cos / pi dw = (c1^2 - c0^2) / 2 over the share of 2 pi.
    let expected: Vec<f64> = (0..COSINE_BINS * PHI_BINS)
        .map(|bin| {
            let row = bin / PHI_BINS;
            let c0 = (2.0 * row as f64 / COSINE_BINS as f64 - 1.0).max(0.0);
            let c1 = (2.0 * (row + 1) as f64 / COSINE_BINS as f64 - 1.0).max(0.0);
            total * (c1 * c1 - c0 * c0) / PHI_BINS as f64
        })
        .collect();
    Ok(pearson(&observed, &expected))
}

/// Pearson's chi-square of `observed` against `expected` counts, sparse
/// cells pooled, and its p-value. An observation in a cell expected empty
/// makes the statistic infinite (p = 0).
pub fn pearson(observed: &[f64], expected: &[f64]) -> (f64, f64) {
    let (mut statistic, mut cells) = (0.0, 0usize);
    let (mut pooled_observed, mut pooled_expected) = (0.0, 0.0);
    for (&got, &want) in observed.iter().zip(expected) {
        if want == 0.0 {
            if got > 0.0 {
                return (f64::INFINITY, 0.0);
            }
        } else if want < 5.0 {
            pooled_observed += got;
            pooled_expected += want;
        } else {
            statistic += (got - want).powi(2) / want;
            cells += 1;
        }
    }
    if pooled_expected > 0.0 {
        statistic += (pooled_observed - pooled_expected).powi(2) / pooled_expected;
        cells += 1;
    }
    let freedom = cells.saturating_sub(1).max(1) as f64;
    let p_value = ChiSquared::new(freedom).map_or(0.0, |law| 1.0 - law.cdf(statistic));
    (statistic, p_value)
}

/// `cosine_hemisphere(u, v)` over a fixed stream of `(u, v)`: every
/// direction unit and above the surface, spread with density `cos / pi`.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct CosineSampleCase {
    pub samples: u32,
    /// The stream's seed (`seeded_stream`): 0, or `grade --fresh`'s.
    pub seed: u64,
}

/// The most samples a statistical case may ask for.
const MOST_SAMPLES: u32 = 1 << 20;

impl Kind for CosineSampleCase {
    type Call = CosineSampleCase;
    type Answer = Vec<Vec3>;

    fn statistical(&self) -> bool {
        true
    }

    fn function(&self) -> &'static str {
        "cosine_hemisphere"
    }

    fn inputs(&self) -> String {
        format!(
            "cosine_hemisphere(u, v) for {} pairs (u, v) uniform in [0, 1)^2{}",
            self.samples,
            seed_text(self.seed)
        )
    }

    fn call(&self) -> CosineSampleCase {
        self.clone()
    }

    fn ask<C: Chapters>(call: &CosineSampleCase) -> Result<Vec<Vec3>, String> {
        if call.samples > MOST_SAMPLES {
            return Err(format!(
                "{} samples asked, more than {MOST_SAMPLES}",
                call.samples
            ));
        }
        Ok((0..call.samples)
            .map(|index| {
                C::cosine_hemisphere(
                    seeded_stream(call.seed, index, 0),
                    seeded_stream(call.seed, index, 1),
                )
            })
            .collect())
    }

    fn judge(&self, directions: Vec<Vec3>, _robust: bool) -> Outcome {
        if directions.len() != self.samples as usize {
            return super::intersections::wrong_length(self.samples as usize, directions.len());
        }
        let expected = format!(
            "directions spread as cos(theta) / pi: a chi-square p-value above {FALSE_ALARM:.0e}"
        );
        match cosine_fit(&directions) {
            Err(why) => verdict(false, expected, why),
            Ok((statistic, p_value)) => verdict(
                p_value >= FALSE_ALARM,
                expected,
                format!("chi-square {statistic:.1}, p-value {p_value:.2e}"),
            ),
        }
    }

    /// Another stream: the same test on other numbers.
    fn fresh(&self, draw: &mut Draw) -> Option<CosineSampleCase> {
        Some(CosineSampleCase {
            seed: draw.word() | 1,
            ..self.clone()
        })
    }
}

/// `", stream seed S"` for a stream other than the lessons' own.
fn seed_text(seed: u64) -> String {
    if seed == 0 {
        String::new()
    } else {
        format!(", stream seed {seed}")
    }
}

/// A function of chapter 13 of plain numbers: its inputs and the answer.
#[derive(Debug, Clone, PartialEq)]
pub enum PathFormula {
    /// `cosine_pdf(cos_theta)`.
    CosinePdf { cos_theta: f32, expected: f64 },
    /// `power_heuristic(pdf, other)`.
    PowerHeuristic { pdf: f32, other: f32, expected: f64 },
    /// `russian_roulette(weight, u)`: `None` when the path ends.
    Roulette {
        weight: f32,
        u: f32,
        expected: Option<f64>,
    },
}

/// One call of a [`PathFormula`].
#[derive(Debug, Clone)]
pub struct PathFormulaCase {
    pub formula: PathFormula,
}

/// A [`PathFormula`]'s inputs.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub enum PathFormulaCall {
    CosinePdf { cos_theta: f32 },
    PowerHeuristic { pdf: f32, other: f32 },
    Roulette { weight: f32, u: f32 },
}

impl Kind for PathFormulaCase {
    type Call = PathFormulaCall;
    /// The number (`Some` for the two densities), or the roulette's answer.
    type Answer = Option<f32>;

    fn function(&self) -> &'static str {
        match self.formula {
            PathFormula::CosinePdf { .. } => "cosine_pdf",
            PathFormula::PowerHeuristic { .. } => "power_heuristic",
            PathFormula::Roulette { .. } => "russian_roulette",
        }
    }

    fn inputs(&self) -> String {
        match self.formula {
            PathFormula::CosinePdf { cos_theta, .. } => format!("cosine_pdf({})", num(cos_theta)),
            PathFormula::PowerHeuristic { pdf, other, .. } => {
                format!("power_heuristic({}, {})", num(pdf), num(other))
            }
            PathFormula::Roulette { weight, u, .. } => {
                format!("russian_roulette(weight = {}, u = {})", num(weight), num(u))
            }
        }
    }

    fn call(&self) -> PathFormulaCall {
        match self.formula {
            PathFormula::CosinePdf { cos_theta, .. } => PathFormulaCall::CosinePdf { cos_theta },
            PathFormula::PowerHeuristic { pdf, other, .. } => {
                PathFormulaCall::PowerHeuristic { pdf, other }
            }
            PathFormula::Roulette { weight, u, .. } => PathFormulaCall::Roulette { weight, u },
        }
    }

    fn ask<C: Chapters>(call: &PathFormulaCall) -> Result<Option<f32>, String> {
        Ok(match *call {
            PathFormulaCall::CosinePdf { cos_theta } => Some(C::cosine_pdf(cos_theta)),
            PathFormulaCall::PowerHeuristic { pdf, other } => Some(C::power_heuristic(pdf, other)),
            PathFormulaCall::Roulette { weight, u } => C::russian_roulette(weight, u),
        })
    }

    fn judge(&self, got: Option<f32>, _robust: bool) -> Outcome {
        let number = |expected: f64| match got {
            Some(got) => verdict(
                got.is_finite() && close(f64::from(got), expected, CHECKPOINT_TOLERANCE),
                num64(expected),
                num(got),
            ),
            None => verdict(false, num64(expected), "no number".into()),
        };
        match self.formula {
            PathFormula::CosinePdf { expected, .. }
            | PathFormula::PowerHeuristic { expected, .. } => number(expected),
            PathFormula::Roulette { expected, .. } => {
                let show = |answer: Option<f64>| {
                    answer.map_or("None (the path ends)".to_string(), |boost| {
                        format!("Some({})", num64(boost))
                    })
                };
                let pass = match (got, expected) {
                    (None, None) => true,
                    (Some(got), Some(want)) => {
                        got.is_finite() && close(f64::from(got), want, CHECKPOINT_TOLERANCE)
                    }
                    _ => false,
                };
                verdict(pass, show(expected), show(got.map(f64::from)))
            }
        }
    }

    /// New numbers of the same kind: a cosine of the same sign, densities
    /// scaled together with their ratio nudged, a roulette weight and `u`
    /// on the same side of each other; the answer worked out again.
    fn fresh(&self, draw: &mut Draw) -> Option<PathFormulaCase> {
        let formula = match self.formula {
            PathFormula::CosinePdf { cos_theta, .. } => {
                let cos_theta = if cos_theta > 0.0 {
                    draw.between(0.05, 1.0) as f32
                } else if cos_theta < 0.0 {
                    -draw.between(0.05, 1.0) as f32
                } else {
                    return None;
                };
                PathFormula::CosinePdf {
                    cos_theta,
                    expected: exact::cosine_pdf(f64::from(cos_theta)),
                }
            }
            PathFormula::PowerHeuristic { pdf, other, .. } => {
                if !(pdf.is_finite() && other.is_finite()) || pdf < 0.0 || other < 0.0 {
                    return None;
                }
                let scale = draw.between(0.1, 10.0);
                let pdf = (f64::from(pdf) * scale) as f32;
                let other = (f64::from(other) * scale * draw.between(0.8, 1.25)) as f32;
                PathFormula::PowerHeuristic {
                    pdf,
                    other,
                    expected: exact::power_heuristic(f64::from(pdf), f64::from(other)),
                }
            }
            PathFormula::Roulette {
                weight, expected, ..
            } => {
                if !(weight > 0.0 && weight.is_finite()) {
                    return None;
                }
                let weight = if weight < 1.0 {
                    draw.between(0.1, 0.9) as f32
                } else {
                    draw.between(1.0, 4.0) as f32
                };
                let survival = f64::from(weight.min(1.0));
                let u = match expected {
                    Some(_) => draw.between(0.0, survival),
                    None => draw.between(survival, 1.0),
                } as f32;
                PathFormula::Roulette {
                    weight,
                    u,
                    expected: exact::russian_roulette(f64::from(weight), f64::from(u)),
                }
            }
        };
        Some(PathFormulaCase { formula })
    }
}

/// A whole estimator on a closed scene whose every pixel converges to
/// `expected`: `samples` camera samples through the stage of chapter 13
/// with `without` left out, their mean within [`FALSE_ALARM`] of it by a
/// z-test on the samples' own spread (the standard error of the mean),
/// plus `1e-3` of the value for the paths `max_depth` cuts off.
#[derive(Debug, Clone)]
pub struct ConvergesCase {
    pub function: &'static str,
    pub scene: String,
    pub without: &'static [&'static str],
    pub samples: u32,
    pub expected: f64,
    /// The stream's and the scene's seed: 0 for the lesson's own,
    /// `grade --fresh`'s otherwise.
    pub seed: u64,
}

/// The z-score past which a correct mean counts as wrong, two-sided, for
/// [`FALSE_ALARM`].
pub fn z_threshold() -> f64 {
    use statrs::distribution::Normal;
    Normal::new(0.0, 1.0).map_or(4.0, |law| law.inverse_cdf(1.0 - FALSE_ALARM / 2.0))
}

/// How many of the pixels `test` and `reference` describe (each pixel's
/// mean, the variance of that mean, and the count it is of) Welch's t-test
/// finds different at level `alpha` (Jung, Hanika and Dachsbacher, "Detecting
/// Bias in Monte Carlo Renderers using Welch's t-test", JCGT 2020). Pixels
/// of no spread on either side differ when their means do.
pub fn welch_rejections(
    test: &[(f64, f64, f64)],
    reference: &[(f64, f64, f64)],
    alpha: f64,
) -> usize {
    use statrs::distribution::StudentsT;
    test.iter()
        .zip(reference)
        .filter(|((m1, v1, n1), (m2, v2, n2))| {
            let spread = v1 + v2;
            if spread == 0.0 {
                return (m1 - m2).abs() > 1e-6;
            }
            let t = (m1 - m2) / spread.sqrt();
            let freedom = spread * spread / (v1 * v1 / (n1 - 1.0) + v2 * v2 / (n2 - 1.0));
            StudentsT::new(0.0, 1.0, freedom.max(1.0))
                .is_ok_and(|law| 2.0 * (1.0 - law.cdf(t.abs())) < alpha)
        })
        .count()
}

/// `", without a, b"` for the effects a closed-scene case leaves out, or
/// nothing.
pub(super) fn without_text(without: &[&str]) -> String {
    if without.is_empty() {
        String::new()
    } else {
        format!(", without {}", without.join(", "))
    }
}

/// The mean of `samples` and its standard error.
pub fn mean_and_error(samples: &[f64]) -> (f64, f64) {
    let count = samples.len() as f64;
    let mean = samples.iter().sum::<f64>() / count;
    let variance = samples.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (count - 1.0).max(1.0);
    (mean, (variance / count).sqrt())
}

/// A closed scene's call: the scene (TOML), the effects left out, how
/// many camera samples, and the stream and scene seed.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct ConvergesCall {
    pub scene: String,
    pub without: Vec<String>,
    pub samples: u32,
    /// 0: the lesson's stream and the scene's own seed.
    pub seed: u64,
}

impl ConvergesCase {
    /// The mean of the samples' first channel and its standard error, with
    /// the chapters `C`.
    pub fn estimate<C: Chapters>(&self) -> Result<(f64, f64), String> {
        Ok(mean_and_error(&converges_samples::<C>(&self.call())?))
    }
}

/// The first channel of each camera sample of a closed scene, with the
/// chapters `C`.
fn converges_samples<C: Chapters>(call: &ConvergesCall) -> Result<Vec<f64>, String> {
    if call.samples > MOST_SAMPLES {
        return Err(format!(
            "{} samples asked, more than {MOST_SAMPLES}",
            call.samples
        ));
    }
    let mut scene = parse(&call.scene)?;
    scene.render.without = SwitchedOff::parse(call.without.iter().map(String::as_str))?;
    if call.seed != 0 {
        scene.render.seed = call.seed;
    }
    let stage =
        Stage::<C>::with_chapters(&scene, 13, scene.render).map_err(|error| error.to_string())?;
    let mut tracer = stage.tracer(None);
    let (width, height) = (scene.render.width, scene.render.height);
    Ok((0..call.samples)
        .map(|index| {
            let (x, y) = (index % width, (index / width) % height);
            let jitter = (
                seeded_stream(call.seed, index, 2),
                seeded_stream(call.seed, index, 3),
            );
            f64::from(tracer.sample(x as f32 + jitter.0, y as f32 + jitter.1).x)
        })
        .collect())
}

impl Kind for ConvergesCase {
    type Call = ConvergesCall;
    /// Each sample's first channel.
    type Answer = Vec<f64>;

    fn statistical(&self) -> bool {
        true
    }

    fn function(&self) -> &'static str {
        self.function
    }

    fn inputs(&self) -> String {
        format!(
            "{} camera samples of a closed scene{}{}",
            self.samples,
            without_text(self.without),
            seed_text(self.seed)
        )
    }

    fn call(&self) -> ConvergesCall {
        ConvergesCall {
            scene: self.scene.clone(),
            without: self.without.iter().map(|name| name.to_string()).collect(),
            samples: self.samples,
            seed: self.seed,
        }
    }

    fn ask<C: Chapters>(call: &ConvergesCall) -> Result<Vec<f64>, String> {
        // The chapter's own formulas first: in a workspace where nothing is
        // written yet, their `todo!()` says chapter 13 is not started,
        // before the render stops at an earlier chapter's.
        let _ = (
            C::cosine_hemisphere(0.5, 0.5),
            C::cosine_pdf(1.0),
            C::power_heuristic(1.0, 1.0),
            C::russian_roulette(0.5, 0.5),
        );
        converges_samples::<C>(call)
    }

    fn judge(&self, samples: Vec<f64>, _robust: bool) -> Outcome {
        if samples.len() != self.samples as usize {
            return super::intersections::wrong_length(self.samples as usize, samples.len());
        }
        let (mean, error) = mean_and_error(&samples);
        let allowed = z_threshold() * error + 1e-3 * self.expected.abs();
        verdict(
            mean.is_finite() && (mean - self.expected).abs() <= allowed,
            format!("{} (within {:.2e})", num64(self.expected), allowed),
            format!("a mean of {} (standard error {:.2e})", num64(mean), error),
        )
    }

    /// Another stream and scene seed: the same scene on other numbers.
    fn fresh(&self, draw: &mut Draw) -> Option<ConvergesCase> {
        Some(ConvergesCase {
            seed: draw.word() | 1,
            ..self.clone()
        })
    }
}

/// A closed sphere of radius 1 at the origin, seen from its centre, of
/// albedo `albedo` (grey) and emission `emission` (on both faces: the
/// camera sees the inside), with `lights` (TOML).
pub fn inside_sphere(albedo: f32, emission: f32, lights: &str) -> String {
    closed_sphere(albedo, emission, true, lights)
}

/// [`inside_sphere`] glowing from its outside only: seen from the centre,
/// its emission is behind every point, and the radiance is 0.
pub fn inside_sphere_glowing_outward(albedo: f32, emission: f32) -> String {
    closed_sphere(albedo, emission, false, "")
}

fn closed_sphere(albedo: f32, emission: f32, two_sided: bool, lights: &str) -> String {
    format!(
        r#"
background = [0.0, 0.0, 0.0]
[camera]
position = [0.0, 0.0, 0.0]
look_at = [0.0, 0.0, 1.0]
fov_degrees = 90.0
[render]
width = 8
height = 8
samples = 1
max_depth = 64
{lights}
[[objects]]
sphere = {{ center = [0.0, 0.0, 0.0], radius = 1.0 }}
material = {{ color = [{albedo}, {albedo}, {albedo}], emission = [{emission}, {emission}, {emission}], two_sided = {two_sided} }}
"#
    )
}
