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

use raylab::check::planted::{self, Plant, Planted, plant};
use std::f32::consts::PI;

use raylab::bsdf::Lobe;
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
        ..Default::default()
    }
}

/// Checks chapter 13 with `C` and asserts that it fails on checkpoint
/// `case`, with nothing earlier to blame.
fn assert_caught<C: Plant>(case: &str) -> ChapterVerdict {
    planted::assert_caught::<C>(13, case, &options())
}

fn assert_passes<C: Plant>() {
    planted::with::<C, _>(|| {
        let verdict = check_chapter::<Planted>(13, &options());
        assert_eq!(verdict.status, Status::Pass, "{}", verdict.text());
    })
}

#[test]
fn the_reference_passes_chapter_13_at_both_levels() {
    let verdict = check_chapter::<Reference>(13, &options());
    assert!(verdict.robust(), "{}", verdict.text());
}

struct PdfWithoutCosine;
plant! {
    PdfWithoutCosine;
    fn cosine_pdf(cos_theta: f32) -> f32 {
        if cos_theta > 0.0 { 1.0 / PI } else { 0.0 }
    }
}

#[test]
fn a_pdf_without_its_cosine_is_caught() {
    assert_caught::<PdfWithoutCosine>("cosine-pdf-60");
}

struct UniformDirections;
plant! {
    UniformDirections;
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
plant! {
    RouletteUndivided;
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
plant! {
    RouletteHalfDivided;
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
plant! {
    EmissionTwice;
    fn shade_path(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
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
plant! {
    EmissionFromBehind;
    fn shade_path(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        let behind = point.material.emission - point.emitted();
        raylab::chapters::ch13_path_tracing::shade_path(tracer, point, depth, weight) + behind
    }
}

#[test]
fn emission_seen_from_behind_a_one_sided_light_is_caught() {
    assert_caught::<EmissionFromBehind>("furnace-one-sided");
}

struct MisWeightOne;
plant! {
    MisWeightOne;
    fn power_heuristic(_pdf: f32, _other: f32) -> f32 {
        1.0
    }
}

#[test]
fn an_mis_weight_of_one_is_caught() {
    assert_caught::<MisWeightOne>("mis-equal");
}

struct LightSampleTooBright;
plant! {
    LightSampleTooBright;
    fn next_event(tracer: &mut Tracer<Planted>, point: &HitPoint, lobe: &Lobe) -> Vec3 {
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
plant! {
    ConcentricDisk;
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
plant! {
    InverseAngles;
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
plant! {
    MalleyFlipped;
    fn cosine_hemisphere(u: f32, v: f32) -> Vec3 {
        let radius = (1.0 - u).max(0.0).sqrt();
        let phi = 2.0 * PI * v;
        Vec3::new(radius * phi.cos(), radius * phi.sin(), u.sqrt())
    }
}

/// raylab's sampler with its two numbers swapped.
struct Swapped;
plant! {
    Swapped;
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
plant! {
    AveragedAfterToneMapping;
    fn pixel_color(tracer: &mut Tracer<Planted>, x: u32, y: u32) -> Vec3 {
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
    let verdict = planted::check_chapter::<AveragedAfterToneMapping>(13, &options());
    let text = verdict.text();
    assert_eq!(verdict.status, Status::Fail, "{text}");
    assert_eq!(verdict.failing_case(), None, "{text}");
    assert!(verdict.image.is_some_and(|image| !image.passed), "{text}");
}

// ---------------------------------------------------------------------------
// Contract clauses: one variant of the reference for each clause of the six
// functions (docs/course.md, chapter 13), failing on the case that asks it.

/// Checks chapter 13 with `C` and asserts that it passes every checkpoint
/// and its image but fails the hard case `case` first.
fn assert_caught_by_hard_case<C: Plant>(case: &str) {
    planted::assert_caught_by_hard_case::<C>(13, case, &options());
}

/// A direction below the surface now and then (one draw in 64, the
/// height's sign flipped): the density there is 0.
struct SometimesBelow;
plant! {
    SometimesBelow;
    fn cosine_hemisphere(u: f32, v: f32) -> Vec3 {
        let direction = Reference::cosine_hemisphere(u, v);
        if v < 1.0 / 64.0 {
            Vec3::new(direction.x, direction.y, -direction.z)
        } else {
            direction
        }
    }
}

/// Directions spread right but 1% too long.
struct NotUnit;
plant! {
    NotUnit;
    fn cosine_hemisphere(u: f32, v: f32) -> Vec3 {
        1.01 * Reference::cosine_hemisphere(u, v)
    }
}

#[test]
fn directions_below_the_surface_or_not_unit_are_caught() {
    assert_caught::<SometimesBelow>("cosine-directions-spread");
    assert_caught::<NotUnit>("cosine-directions-spread");
}

/// `cos / pi` without its floor: below the surface, a negative density.
struct NegativeDensityBelow;
plant! {
    NegativeDensityBelow;
    fn cosine_pdf(cos_theta: f32) -> f32 {
        cos_theta / PI
    }
}

#[test]
fn a_negative_density_below_the_surface_is_caught() {
    assert_caught::<NegativeDensityBelow>("cosine-pdf-below");
}

/// The power heuristic for the larger density, the balance heuristic
/// `a / (a + b)` for the smaller: the two weights of one direction no
/// longer add to 1.
struct BalanceForTheSmaller;
plant! {
    BalanceForTheSmaller;
    fn power_heuristic(pdf: f32, other: f32) -> f32 {
        if pdf < other {
            pdf / (pdf + other)
        } else {
            Reference::power_heuristic(pdf, other)
        }
    }
}

/// A strategy that cannot draw the direction taken for a delta one.
struct ZeroDensityTakesAll;
plant! {
    ZeroDensityTakesAll;
    fn power_heuristic(pdf: f32, other: f32) -> f32 {
        if pdf == 0.0 && other > 0.0 {
            1.0
        } else {
            Reference::power_heuristic(pdf, other)
        }
    }
}

/// The reference without its delta branch: an infinite density divided
/// by itself is NaN.
struct NoDeltaBranch;
plant! {
    NoDeltaBranch;
    fn power_heuristic(pdf: f32, other: f32) -> f32 {
        let larger = pdf.max(other);
        if !(larger > 0.0) {
            return 0.0;
        }
        let (mine, theirs) = (pdf / larger, other / larger);
        mine * mine / (mine * mine + theirs * theirs)
    }
}

/// A delta strategy of its own takes the sample, but another's delta is
/// not seen: `2 / inf` and `inf / inf` give NaN.
struct OnlyItsOwnDelta;
plant! {
    OnlyItsOwnDelta;
    fn power_heuristic(pdf: f32, other: f32) -> f32 {
        if pdf.is_infinite() {
            return 1.0;
        }
        NoDeltaBranch::power_heuristic(pdf, other)
    }
}

/// The reference without its guard for two zero densities: `0 / 0`.
struct NoZeroGuard;
plant! {
    NoZeroGuard;
    fn power_heuristic(pdf: f32, other: f32) -> f32 {
        let larger = pdf.max(other);
        if larger.is_infinite() {
            return if pdf.is_infinite() { 1.0 } else { 0.0 };
        }
        let (mine, theirs) = (pdf / larger, other / larger);
        mine * mine / (mine * mine + theirs * theirs)
    }
}

/// Zeros and deltas handled, the squares not scaled: `1e30^2` is
/// infinite.
struct SquaresUnscaled;
plant! {
    SquaresUnscaled;
    fn power_heuristic(pdf: f32, other: f32) -> f32 {
        let larger = pdf.max(other);
        if !(larger > 0.0) {
            return 0.0;
        }
        if larger.is_infinite() {
            return if pdf.is_infinite() { 1.0 } else { 0.0 };
        }
        pdf * pdf / (pdf * pdf + other * other)
    }
}

#[test]
fn each_clause_of_the_power_heuristic_is_caught() {
    assert_caught::<BalanceForTheSmaller>("mis-one-to-two");
    assert_caught::<ZeroDensityTakesAll>("mis-cannot-draw");
    assert_caught::<NoDeltaBranch>("mis-a-delta-takes-all");
    assert_caught::<OnlyItsOwnDelta>("mis-against-a-delta");
    assert_caught_by_hard_case::<NoZeroGuard>("mis-both-zero");
    assert_caught_by_hard_case::<SquaresUnscaled>("mis-huge-densities");
}

/// Every path survives, divided by its chance all the same.
struct RouletteNeverEnds;
plant! {
    RouletteNeverEnds;
    fn russian_roulette(weight: f32, _u: f32) -> Option<f32> {
        Reference::russian_roulette(weight, 0.0)
    }
}

/// The chance `weight`, not `min(1, weight)`: a bright path is dimmed.
struct RouletteWithoutMin;
plant! {
    RouletteWithoutMin;
    fn russian_roulette(weight: f32, u: f32) -> Option<f32> {
        if !(weight > 0.0) {
            return None;
        }
        (u < weight).then(|| 1.0 / weight)
    }
}

/// `u <= q` and no test of the weight: a path of weight 0 survives
/// `u = 0` with the infinite factor `1 / 0`.
struct RouletteAtTheEdge;
plant! {
    RouletteAtTheEdge;
    fn russian_roulette(weight: f32, u: f32) -> Option<f32> {
        let survival = weight.min(1.0);
        (u <= survival).then(|| 1.0 / survival)
    }
}

/// A weight of 0 ends the path, but `f32::min` takes a NaN weight for 1.
struct RouletteNanSurvives;
plant! {
    RouletteNanSurvives;
    fn russian_roulette(weight: f32, u: f32) -> Option<f32> {
        if weight == 0.0 {
            return None;
        }
        let survival = weight.min(1.0);
        (u < survival).then(|| 1.0 / survival)
    }
}

#[test]
fn each_clause_of_russian_roulette_is_caught() {
    assert_caught::<RouletteNeverEnds>("roulette-ends");
    assert_caught::<RouletteWithoutMin>("roulette-bright");
    assert_caught_by_hard_case::<RouletteAtTheEdge>("roulette-zero-weight");
    assert_caught_by_hard_case::<RouletteNanSurvives>("roulette-nan-weight");
}

/// One mistake in the reference's `next_event`, or none.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum LightSlip {
    NoSlip,
    /// Lambert's `albedo / pi` for `f`, whatever the lobe.
    LambertsF,
    /// The cosine density in MIS, whatever the lobe.
    CosineDensityInMis,
    /// A point light weighed by MIS as if a scattered ray could find it.
    PointLightWeighed,
    /// A point light's sample not divided by the chance of choosing it.
    PointLightUndivided,
    /// No shadow ray.
    NoShadowRay,
    /// Without the cosine at the lit point.
    NoCosine,
    /// Weight 1 with MIS on.
    NoMisWeight,
    /// Only the cosine asked, not whether the point faces the light: the
    /// sphere a point is inside no longer hides a light outside it, and the
    /// shadow ray alone must, where rounding decides.
    FacesUntested,
}

/// The reference's `next_event` with `slip` made.
fn light_sample<C: Chapters>(
    tracer: &mut Tracer<C>,
    point: &HitPoint,
    lobe: &Lobe,
    slip: LightSlip,
) -> Vec3 {
    use LightSlip::*;
    let Some(light) = tracer.sample_light(point) else {
        return Vec3::ZERO;
    };
    let cosine = point.normal.dot(light.direction);
    if cosine <= 0.0 || (slip != FacesUntested && !point.faces(light.position)) {
        return Vec3::ZERO;
    }
    let value = lobe.value::<C>(point, light.direction);
    let scattered = if slip == LambertsF && value != Vec3::ZERO {
        point.albedo / PI
    } else {
        value
    };
    if scattered == Vec3::ZERO
        || (slip != NoShadowRay && C::in_shadow(tracer, point, light.position))
    {
        return Vec3::ZERO;
    }
    let lobe_pdf = if slip == CosineDensityInMis {
        C::cosine_pdf(cosine)
    } else {
        lobe.pdf::<C>(point, light.direction)
    };
    let weighed = (!light.delta || slip == PointLightWeighed) && slip != NoMisWeight;
    let weight = if !weighed || !tracer.effects().mis {
        1.0
    } else {
        C::power_heuristic(light.pdf, lobe_pdf)
    };
    let pdf = if light.delta && slip == PointLightUndivided {
        1.0
    } else {
        light.pdf
    };
    let cosine = if slip == NoCosine { 1.0 } else { cosine };
    scattered * light.light * (cosine * weight / pdf)
}

/// A `Chapters` whose `next_event` is the reference with one slip.
macro_rules! light_variant {
    ($name:ident, $slip:ident) => {
        struct $name;
        plant! {
            $name;
            fn next_event(tracer: &mut Tracer<Planted>, point: &HitPoint, lobe: &Lobe) -> Vec3 {
                light_sample(tracer, point, lobe, LightSlip::$slip)
            }
        }
    };
}

light_variant!(LightSampleCopy, NoSlip);
light_variant!(LambertsF, LambertsF);
light_variant!(CosineDensityInMis, CosineDensityInMis);
light_variant!(PointLightWeighed, PointLightWeighed);
light_variant!(PointLightUndivided, PointLightUndivided);
light_variant!(NoShadowRay, NoShadowRay);
light_variant!(NoCosine, NoCosine);
light_variant!(NoMisWeight, NoMisWeight);
light_variant!(FacesUntested, FacesUntested);

#[test]
fn a_copy_of_next_event_passes() {
    assert_passes::<LightSampleCopy>();
}

#[test]
fn next_event_without_its_cosine_is_caught() {
    assert_caught::<NoCosine>("furnace-next-event");
}

#[test]
fn next_event_without_its_mis_weight_is_caught() {
    assert_caught::<NoMisWeight>("furnace-mis");
}

#[test]
fn a_point_light_weighed_by_mis_is_caught() {
    assert_caught::<PointLightWeighed>("point-light-in-a-glowing-sphere");
}

#[test]
fn a_point_light_not_divided_by_its_chance_is_caught() {
    // The glowing sphere is a second light: the point light is chosen
    // with chance 1/2, and undivided it gives 0.25, not 0.5 (radiance 2.5).
    assert_caught::<PointLightUndivided>("point-light-in-a-glowing-sphere");
}

#[test]
fn next_event_that_only_asks_the_cosine_is_caught() {
    assert_caught_by_hard_case::<FacesUntested>("lamp-on-the-wall-seen-from-inside");
}

#[test]
fn next_event_without_its_shadow_ray_is_caught() {
    assert_caught::<NoShadowRay>("light-over-a-roof");
}

#[test]
fn next_event_with_lamberts_f_is_caught() {
    assert_caught::<LambertsF>("glossy-plate-under-a-sky");
}

#[test]
fn next_event_with_the_cosine_density_in_mis_is_caught() {
    assert_caught::<CosineDensityInMis>("glossy-plate-under-a-sky");
}

/// One mistake in the reference's `shade_path`, or none.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PathSlip {
    NoSlip,
    /// The camera's own point's emission left out.
    CameraEmissionDropped,
    /// A light that a mirror's or glass's ray finds left out with light
    /// samples on, as if a light sample had found it.
    SpecularEmissionDropped,
    /// A light that a scattered ray finds counted fully with MIS on.
    ScatteredEmissionUnweighted,
    /// A roulette survivor's light not multiplied by the factor returned.
    SurvivorNotBoosted,
    /// No stop at `max_depth`.
    DepthUnbounded,
    /// What the scattered ray sees not dimmed by the medium it crossed.
    NoAbsorption,
    /// The scattered ray cast from the point itself, not offset.
    NoOffset,
}

/// The reference's `shade_path` with `slip` made.
fn path<C: Chapters>(
    tracer: &mut Tracer<C>,
    point: &HitPoint,
    depth: u32,
    weight: f32,
    slip: PathSlip,
) -> Vec3 {
    use PathSlip::*;
    use raylab::chapters::ch13_path_tracing::ROULETTE_FROM_DEPTH;
    let effects = tracer.effects();
    let mut color = Vec3::ZERO;
    let emission = point.emitted();
    if emission != Vec3::ZERO {
        let counted = match tracer.arrival() {
            Arrival::Camera if slip == CameraEmissionDropped => 0.0,
            Arrival::Specular if slip == SpecularEmissionDropped && effects.next_event => 0.0,
            Arrival::Camera | Arrival::Specular => 1.0,
            Arrival::Scattered { .. } if !effects.next_event => 1.0,
            Arrival::Scattered { .. } if effects.mis && slip == ScatteredEmissionUnweighted => 1.0,
            Arrival::Scattered { pdf } if effects.mis => {
                C::power_heuristic(pdf, tracer.light_pdf(point))
            }
            Arrival::Scattered { .. } => 0.0,
            Arrival::Caustic => 0.0,
        };
        color += counted * emission;
    }
    if depth >= tracer.max_depth() && slip != DepthUnbounded {
        return color;
    }
    let lobe = Lobe::choose(point, tracer.random());
    if effects.next_event && lobe.has_density() {
        color += C::next_event(tracer, point, &lobe);
    }
    let Some(scattered) = lobe.scatter::<C>(tracer, point) else {
        return color;
    };
    let mut throughput = scattered.weight;
    let mut share = weight * throughput.max_element();
    if !(share > 0.0) {
        return color;
    }
    if effects.roulette && depth + 1 >= ROULETTE_FROM_DEPTH && lobe.has_density() {
        match C::russian_roulette(share, tracer.random()) {
            Some(boost) => {
                if slip != SurvivorNotBoosted {
                    throughput *= boost;
                }
                share *= boost;
            }
            None => return color,
        }
    }
    let dir = scattered.direction;
    let origin = if slip == NoOffset {
        point.surface.point
    } else {
        tracer.offset_origin(&point.surface, dir)
    };
    let seen = tracer.trace_path(
        &scattered.media,
        scattered.kind,
        &raylab::Ray::new(origin, dir),
        depth + 1,
        share,
        scattered.arrival,
    );
    let absorption = scattered.media.current().absorption;
    let kept = if absorption == Vec3::ZERO || slip == NoAbsorption {
        Vec3::ONE
    } else {
        C::transmittance(absorption, seen.distance)
    };
    color + throughput * kept * seen.color
}

/// A `Chapters` whose `shade_path` is the reference with one slip.
macro_rules! path_variant {
    ($name:ident, $slip:ident) => {
        struct $name;
        plant! {
            $name;
            fn shade_path(
                tracer: &mut Tracer<Planted>,
                point: &HitPoint,
                depth: u32,
                weight: f32,
            ) -> Vec3 {
                path(tracer, point, depth, weight, PathSlip::$slip)
            }
        }
    };
}

path_variant!(PathCopy, NoSlip);
path_variant!(CameraEmissionDropped, CameraEmissionDropped);
path_variant!(SpecularEmissionDropped, SpecularEmissionDropped);
path_variant!(ScatteredEmissionUnweighted, ScatteredEmissionUnweighted);
path_variant!(SurvivorNotBoosted, SurvivorNotBoosted);
path_variant!(DepthUnbounded, DepthUnbounded);
path_variant!(NoAbsorption, NoAbsorption);
path_variant!(NoOffset, NoOffset);

#[test]
fn a_copy_of_shade_path_passes() {
    assert_passes::<PathCopy>();
}

#[test]
fn each_clause_of_shade_path_is_caught() {
    assert_caught::<CameraEmissionDropped>("furnace-scattered-only");
    assert_caught::<SurvivorNotBoosted>("furnace-roulette");
    assert_caught::<ScatteredEmissionUnweighted>("furnace-mis");
}

#[test]
fn a_specular_rays_light_left_out_is_caught() {
    assert_caught::<SpecularEmissionDropped>("furnace-mirror-and-glass");
}

#[test]
fn a_path_that_crosses_an_absorbing_solid_undimmed_is_caught() {
    assert_caught::<NoAbsorption>("absorbing-ball");
}

#[test]
fn a_path_past_max_depth_is_caught() {
    assert_caught::<DepthUnbounded>("furnace-max-depth");
}

/// A scattered ray cast from the point itself, without chapter 4's offset,
/// meets the surface it leaves where rounding put the point behind it, and
/// from behind: it sees no emission there (a light glows from its front),
/// so the furnace is darker than 2.
#[test]
fn a_ray_without_its_offset_fails() {
    assert_caught::<NoOffset>("furnace-scattered-only");
}
