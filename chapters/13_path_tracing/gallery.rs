//! Chapter 13, path tracing, as `raylab check` judges it: the reference
//! passes both levels; its bug gallery (a pdf without its cosine, uniform
//! directions called cosine ones, roulette survivors not divided by their
//! chance, emission counted twice with light samples or from behind a
//! one-sided light, an MIS weight of 1,
//! a light sample that returns more than arrives) fails chapter 13 on the
//! case that names the mistake, and samples averaged after tone mapping
//! fail its image; correct alternatives (the concentric mapping, the
//! inverse of the cosine law in angles, Malley's with `1 - u`, the two
//! numbers swapped) pass.

use std::f32::consts::PI;

use raylab::check::{ChapterVerdict, CheckOptions, Status, check_chapter};
use raylab::course::{Chapters, HitPoint};
use raylab::render::{Arrival, Tracer};
use raylab::{Reference, Vec3};

fn options() -> CheckOptions {
    CheckOptions {
        failures_dir: std::env::temp_dir().join("raylab-chapter-13-tests"),
        write_images: false,
        forbid_answer_key: false,
        fresh: None,
    }
}

/// Checks chapter 13 with `C` and asserts that it fails on checkpoint
/// `case`, with nothing earlier to blame.
fn assert_caught<C: Chapters>(case: &str) -> ChapterVerdict {
    let verdict = check_chapter::<C>(13, &options());
    let text = verdict.text();
    assert_eq!(verdict.status, Status::Fail, "{text}");
    assert_eq!(verdict.failing_case(), Some(case), "{text}");
    assert_eq!(verdict.needs, None, "{text}");
    verdict
}

fn assert_passes<C: Chapters>() {
    let verdict = check_chapter::<C>(13, &options());
    assert_eq!(verdict.status, Status::Pass, "{}", verdict.text());
}

#[test]
fn the_reference_passes_chapter_13_at_both_levels() {
    let verdict = check_chapter::<Reference>(13, &options());
    assert!(verdict.robust(), "{}", verdict.text());
}

struct PdfWithoutCosine;
impl Chapters for PdfWithoutCosine {
    fn cosine_pdf(cos_theta: f32) -> f32 {
        if cos_theta > 0.0 { 1.0 / PI } else { 0.0 }
    }
}

#[test]
fn a_pdf_without_its_cosine_is_caught() {
    assert_caught::<PdfWithoutCosine>("cosine-pdf-60");
}

struct UniformDirections;
impl Chapters for UniformDirections {
    fn cosine_hemisphere(u: f32, v: f32) -> Vec3 {
        let ring = (1.0 - u * u).max(0.0).sqrt();
        let (sin, cos) = (2.0 * PI * v).sin_cos();
        Vec3::new(ring * cos, ring * sin, u)
    }
}

#[test]
fn uniform_directions_called_cosine_ones_are_caught() {
    assert_caught::<UniformDirections>("cosine-directions-spread");
}

struct RouletteUndivided;
impl Chapters for RouletteUndivided {
    fn russian_roulette(weight: f32, u: f32) -> Option<f32> {
        (u < weight.min(1.0)).then_some(1.0)
    }
}

#[test]
fn roulette_without_dividing_by_the_survival_chance_is_caught() {
    assert_caught::<RouletteUndivided>("roulette-survives");
}

/// Roulette whose factor is right on the checkpoints' numbers and wrong
/// everywhere else: only the furnace can see it.
struct RouletteHalfDivided;
impl Chapters for RouletteHalfDivided {
    fn russian_roulette(weight: f32, u: f32) -> Option<f32> {
        let survival = weight.min(1.0);
        if !(weight > 0.0) || u >= survival {
            return None;
        }
        Some(if weight == 0.25 || weight >= 1.0 {
            1.0 / survival
        } else {
            1.0
        })
    }
}

#[test]
fn roulette_that_only_passes_the_hand_cases_is_caught_by_the_furnace() {
    assert_caught::<RouletteHalfDivided>("furnace-roulette");
}

struct EmissionTwice;
impl Chapters for EmissionTwice {
    fn shade_path(tracer: &mut Tracer<Self>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        let twice =
            matches!(tracer.arrival(), Arrival::Scattered { .. }) && tracer.effects().next_event;
        let again = if twice { point.emitted() } else { Vec3::ZERO };
        raylab::chapters::ch13_path_tracing::shade_path(tracer, point, depth, weight) + again
    }
}

#[test]
fn emission_counted_twice_with_light_samples_is_caught() {
    assert_caught::<EmissionTwice>("furnace-next-event");
}

/// A variant that counts a light's emission seen from behind as well
/// (`point.material.emission` where `point.emitted()` belongs): a
/// one-sided lamp's back glows.
struct EmissionFromBehind;
impl Chapters for EmissionFromBehind {
    fn shade_path(tracer: &mut Tracer<Self>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        let behind = point.material.emission - point.emitted();
        raylab::chapters::ch13_path_tracing::shade_path(tracer, point, depth, weight) + behind
    }
}

#[test]
fn emission_seen_from_behind_a_one_sided_light_is_caught() {
    assert_caught::<EmissionFromBehind>("furnace-one-sided");
}

struct MisWeightOne;
impl Chapters for MisWeightOne {
    fn power_heuristic(_pdf: f32, _other: f32) -> f32 {
        1.0
    }
}

#[test]
fn an_mis_weight_of_one_is_caught() {
    assert_caught::<MisWeightOne>("mis-equal");
}

struct LightSampleTooBright;
impl Chapters for LightSampleTooBright {
    fn next_event(tracer: &mut Tracer<Self>, point: &HitPoint, lobe: &raylab::bsdf::Lobe) -> Vec3 {
        1.5 * raylab::chapters::ch13_path_tracing::next_event(tracer, point, lobe)
    }
}

#[test]
fn a_light_sample_that_returns_more_than_arrives_is_caught() {
    assert_caught::<LightSampleTooBright>("furnace-next-event");
}

/// Shirley and Chiu's concentric mapping of the square onto the disk,
/// lifted to the hemisphere: another correct cosine sampler.
struct ConcentricDisk;
impl Chapters for ConcentricDisk {
    fn cosine_hemisphere(u: f32, v: f32) -> Vec3 {
        let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
        let (radius, angle) = if a == 0.0 && b == 0.0 {
            (0.0, 0.0)
        } else if a.abs() > b.abs() {
            (a, PI / 4.0 * (b / a))
        } else {
            (b, PI / 2.0 - PI / 4.0 * (a / b))
        };
        let (x, y) = (radius * angle.cos(), radius * angle.sin());
        Vec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt())
    }
}

/// The cosine law inverted in angles: `theta = asin(sqrt(u))`.
struct InverseAngles;
impl Chapters for InverseAngles {
    fn cosine_hemisphere(u: f32, v: f32) -> Vec3 {
        let theta = u.sqrt().asin();
        let phi = 2.0 * PI * v;
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }
}

/// Malley's method with the other half of the square: the radius from
/// `1 - u`, the height from `u` (the same distribution, the directions of
/// other draws).
struct MalleyFlipped;
impl Chapters for MalleyFlipped {
    fn cosine_hemisphere(u: f32, v: f32) -> Vec3 {
        let radius = (1.0 - u).max(0.0).sqrt();
        let phi = 2.0 * PI * v;
        Vec3::new(radius * phi.cos(), radius * phi.sin(), u.sqrt())
    }
}

/// raylab's sampler with its two numbers swapped.
struct Swapped;
impl Chapters for Swapped {
    fn cosine_hemisphere(u: f32, v: f32) -> Vec3 {
        Reference::cosine_hemisphere(v, u)
    }
}

#[test]
fn other_correct_cosine_samplers_pass() {
    assert_passes::<ConcentricDisk>();
    assert_passes::<InverseAngles>();
    assert_passes::<MalleyFlipped>();
    assert_passes::<Swapped>();
}

/// The samples averaged after they are turned to the screen's sRGB (each
/// cut to white first, as a display does) and the mean turned back:
/// Jensen's inequality makes every noisy pixel darker, and a path-traced
/// pixel is noise.
struct AveragedAfterToneMapping;
impl Chapters for AveragedAfterToneMapping {
    fn pixel_color(tracer: &mut Tracer<Self>, x: u32, y: u32) -> Vec3 {
        let encode = |linear: f32| {
            let linear = linear.clamp(0.0, 1.0);
            if linear <= 0.003_130_8 {
                12.92 * linear
            } else {
                1.055 * linear.powf(1.0 / 2.4) - 0.055
            }
        };
        let decode = |code: f32| {
            if code <= 0.040_45 {
                code / 12.92
            } else {
                ((code + 0.055) / 1.055).powf(2.4)
            }
        };
        let samples = tracer.samples();
        let mut sum = Vec3::ZERO;
        for index in 0..samples {
            let (dx, dy) = tracer.sample_offset(index, (x, y));
            sum += tracer.sample(x as f32 + dx, y as f32 + dy).map(encode);
        }
        (sum / samples as f32).map(decode)
    }
}

#[test]
fn averaging_after_tone_mapping_fails_the_image() {
    let verdict = check_chapter::<AveragedAfterToneMapping>(13, &options());
    let text = verdict.text();
    assert_eq!(verdict.status, Status::Fail, "{text}");
    assert_eq!(verdict.failing_case(), None, "{text}");
    assert!(verdict.image.is_some_and(|image| !image.passed), "{text}");
}
