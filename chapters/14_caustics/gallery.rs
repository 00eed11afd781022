//! Chapter 14, light paths and dispersion, as `raylab check` judges it:
//! the reference passes both levels; its bug gallery fails chapter 14 on
//! the case that names the mistake: a splat weight without the surface's
//! cosine or with the camera's only once, a light path that stops at its
//! first diffuse point or joins every diffuse point to the camera even
//! when no glass came first, a camera path that counts the caustics light
//! paths bring, an index in nanometres, a light joined to the camera from
//! the side it does not see, a wavelength drawn without its colour; and
//! one variant of the reference for each other clause of the five
//! functions' contract (docs/course.md lists them).

use raylab::bsdf::{Dispersed, Lobe};
use raylab::check::planted::{self, Plant, Planted, plant};
use raylab::check::{ChapterVerdict, CheckOptions, Status, check_chapter};
use raylab::course::{Chapters, HitPoint};
use raylab::render::{Arrival, Tracer};
use raylab::scene::Cauchy;
use raylab::{Reference, Vec3};

fn options() -> CheckOptions {
    CheckOptions {
        failures_dir: std::env::temp_dir().join("raylab-chapter-14-tests"),
        write_images: false,
        forbid_answer_key: false,
        fresh: None,
        ..Default::default()
    }
}

/// Checks chapter 14 with `C` and asserts that it fails on case `case`,
/// with nothing earlier to blame.
fn assert_caught<C: Plant>(case: &str) -> ChapterVerdict {
    planted::assert_caught::<C>(14, case, &options())
}

#[test]
fn the_reference_passes_chapter_14_at_both_levels() {
    let verdict = check_chapter::<Reference>(14, &options());
    assert!(verdict.robust(), "{}", verdict.text());
}

struct NoSurfaceCosine;
plant! {
    NoSurfaceCosine;
    fn splat_weight(cos_surface: f32, cos_camera: f32, distance: f32, pixel_area: f32) -> f32 {
        if cos_surface > 0.0 {
            super::splat_weight(1.0, cos_camera, distance, pixel_area)
        } else {
            0.0
        }
    }
}

#[test]
fn a_splat_weight_without_the_surface_cosine_is_caught() {
    assert_caught::<NoSurfaceCosine>("splat-turned-surface");
}

struct CameraCosineOnce;
plant! {
    CameraCosineOnce;
    fn splat_weight(cos_surface: f32, cos_camera: f32, distance: f32, pixel_area: f32) -> f32 {
        let seen = distance * distance * pixel_area * cos_camera;
        if seen > 0.0 && cos_surface > 0.0 {
            cos_surface / seen
        } else {
            0.0
        }
    }
}

#[test]
fn a_pixel_seen_without_its_cos_cubed_is_caught() {
    assert_caught::<CameraCosineOnce>("splat-off-axis");
}

struct Nanometres;
plant! {
    Nanometres;
    fn cauchy_ior(cauchy: &Cauchy, nanometres: f32) -> f32 {
        cauchy.a + cauchy.b / (nanometres * nanometres)
    }
}

#[test]
fn an_index_with_the_wavelength_in_nanometres_is_caught() {
    assert_caught::<Nanometres>("cauchy-bk7-d-line");
}

/// A light path that joins its first diffuse point to the camera even when
/// it came straight from the light: chapter 13's light samples bring that
/// light already.
struct EveryDiffusePoint;
plant! {
    EveryDiffusePoint;
    fn connect_to_camera(tracer: &mut Tracer<Planted>, point: &HitPoint, lobe: &Lobe, power: Vec3) {
        super::connect_to_camera(tracer, point, lobe, power)
    }
    fn trace_light_path(tracer: &mut Tracer<Planted>) {
        let Some(emitted) = tracer.emit() else {
            return;
        };
        let media = raylab::medium::MediumStack::EMPTY;
        let Some(hit) = tracer.trace_light(&media, &emitted.ray) else {
            return;
        };
        let lobe = Lobe::choose(&hit.point, tracer.random());
        if lobe.has_density() {
            Planted::connect_to_camera(tracer, &hit.point, &lobe, emitted.power);
        }
        super::trace_light_path(tracer);
    }
}

#[test]
fn light_paths_that_bring_direct_light_again_are_caught() {
    assert_caught::<EveryDiffusePoint>("point-light-in-the-open");
}

/// A light path that ends where it first lights a diffuse point: the light
/// that point sends on, the wall's light from the wall, is lost.
struct FirstPointOnly;
plant! {
    FirstPointOnly;
    fn trace_light_path(tracer: &mut Tracer<Planted>) {
        let Some(emitted) = tracer.emit() else {
            return;
        };
        let (mut ray, mut media) = (emitted.ray, raylab::medium::MediumStack::EMPTY);
        let mut power = emitted.power;
        for _ in 0..tracer.max_depth() {
            let Some(hit) = tracer.trace_light(&media, &ray) else {
                return;
            };
            let lobe = Lobe::choose(&hit.point, tracer.random());
            if lobe.has_density() {
                Planted::connect_to_camera(tracer, &hit.point, &lobe, power);
                return;
            }
            let Some(scattered) = lobe.scatter::<Planted>(tracer, &hit.point) else {
                return;
            };
            power *= scattered.weight;
            let direction = scattered.direction;
            ray = raylab::Ray::new(
                tracer.offset_origin(&hit.point.surface, direction),
                direction,
            );
            media = scattered.media;
        }
    }
}

#[test]
fn a_light_path_that_stops_at_its_first_diffuse_point_is_caught() {
    assert_caught::<FirstPointOnly>("point-light-in-glass");
}

/// A camera path that counts the light it finds through glass from its
/// first, diffuse point, as chapter 13 did, though light paths bring it.
pub(super) struct CausticsTwice;
plant! {
    CausticsTwice;
    fn shade_path(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        let twice = tracer.arrival() == Arrival::Caustic;
        raylab::chapters::ch13_path_tracing::shade_path(tracer, point, depth, weight)
            + if twice { point.emitted() } else { Vec3::ZERO }
    }
}

#[test]
fn a_caustic_counted_by_both_paths_is_caught() {
    assert_caught::<CausticsTwice>("lamp-in-glass");
}

/// A lit point joined to the camera whichever side the camera is on.
struct BothSides;
plant! {
    BothSides;
    fn connect_to_camera(tracer: &mut Tracer<Planted>, point: &HitPoint, lobe: &Lobe, power: Vec3) {
        let camera = *tracer.camera();
        let Some((x, y)) = camera.project(point.surface.point) else {
            return;
        };
        let to_camera = camera.origin() - point.surface.point;
        let distance = to_camera.length();
        let direction = to_camera / distance;
        // The lobe's value on the lit side, wherever the camera is.
        let lit_side = direction - 2.0 * direction.dot(point.normal).min(0.0) * point.normal;
        let scattered = lobe.value::<Planted>(point, lit_side);
        if scattered == Vec3::ZERO || tracer.blocked_from_camera(point) {
            return;
        }
        let weight = Planted::splat_weight(
            point.normal.dot(direction).abs(),
            camera.forward().dot(-direction),
            distance,
            camera.pixel_area(),
        );
        tracer.splat(x, y, power * scattered * weight);
    }
}

#[test]
fn a_point_joined_to_the_camera_from_its_unlit_side_is_caught() {
    // The box seen from outside shows it at the first level: the near
    // wall's inside is lit, and its outside, which the camera sees, is
    // not. Under the floor, the hard case, it was the only case before.
    assert_caught::<BothSides>("box-lit-inside-seen-from-outside");
}

/// The wavelength drawn, but its colour forgotten: every path through the
/// prism carries white, and the spectrum on the wall is a white smear.
/// The furnace cannot see it (white stays white); the image can.
struct TintForgotten;
plant! {
    TintForgotten;
    fn dispersive_ior(tracer: &mut Tracer<Planted>, cauchy: &Cauchy) -> Dispersed {
        Dispersed {
            tint: Vec3::ONE,
            ..raylab::chapters::ch14_caustics::dispersive_ior(tracer, cauchy)
        }
    }
}

#[test]
fn a_wavelength_without_its_colour_is_caught() {
    assert_caught::<TintForgotten>("dispersion-draws-a-wavelength");
}

// ---------------------------------------------------------------------------
// Contract clauses: one variant of the reference for each clause of the five
// functions (docs/course.md, chapter 14), failing on the case that asks it.

/// Checks chapter 14 with `C` and asserts that it passes every checkpoint
/// and its image but fails the hard case `case` first.
fn assert_caught_by_hard_case<C: Plant>(case: &str) {
    planted::assert_caught_by_hard_case::<C>(14, case, &options());
}

/// The distance not squared.
struct DistanceNotSquared;
plant! {
    DistanceNotSquared;
    fn splat_weight(cos_surface: f32, cos_camera: f32, distance: f32, pixel_area: f32) -> f32 {
        super::splat_weight(cos_surface, cos_camera, distance.sqrt(), pixel_area)
    }
}

/// The formula as written, with no test of what the pixel sees.
struct SplatAsWritten;
plant! {
    SplatAsWritten;
    fn splat_weight(cos_surface: f32, cos_camera: f32, distance: f32, pixel_area: f32) -> f32 {
        cos_surface / (distance * distance * pixel_area * cos_camera.powi(3))
    }
}

/// Zeros tested, signs not: behind the camera or the surface, a negative
/// weight.
struct SplatZerosOnly;
plant! {
    SplatZerosOnly;
    fn splat_weight(cos_surface: f32, cos_camera: f32, distance: f32, pixel_area: f32) -> f32 {
        if cos_camera == 0.0 || distance == 0.0 || cos_surface == 0.0 {
            return 0.0;
        }
        SplatAsWritten::splat_weight(cos_surface, cos_camera, distance, pixel_area)
    }
}

/// Both cosines' signs tested, the distance not: at the pinhole, `1 / 0`.
struct SplatAtThePinhole;
plant! {
    SplatAtThePinhole;
    fn splat_weight(cos_surface: f32, cos_camera: f32, distance: f32, pixel_area: f32) -> f32 {
        if cos_camera <= 0.0 || cos_surface <= 0.0 {
            return 0.0;
        }
        SplatAsWritten::splat_weight(cos_surface, cos_camera, distance, pixel_area)
    }
}

/// The camera's side tested, the surface's not.
struct SplatSurfaceSideUntested;
plant! {
    SplatSurfaceSideUntested;
    fn splat_weight(cos_surface: f32, cos_camera: f32, distance: f32, pixel_area: f32) -> f32 {
        let seen = distance * distance * pixel_area * cos_camera.powi(3);
        if !(seen > 0.0) {
            return 0.0;
        }
        cos_surface / seen
    }
}

/// Every sign tested as `<= 0`, which a NaN passes.
struct SplatNanPasses;
plant! {
    SplatNanPasses;
    fn splat_weight(cos_surface: f32, cos_camera: f32, distance: f32, pixel_area: f32) -> f32 {
        let seen = distance * distance * pixel_area * cos_camera.powi(3);
        if seen <= 0.0 || cos_surface <= 0.0 {
            return 0.0;
        }
        cos_surface / seen
    }
}

#[test]
fn each_clause_of_the_splat_weight_is_caught() {
    assert_caught::<DistanceNotSquared>("splat-face-on");
    assert_caught_by_hard_case::<SplatAsWritten>("splat-edge-on-camera");
    assert_caught_by_hard_case::<SplatZerosOnly>("splat-behind-camera");
    assert_caught_by_hard_case::<SplatAtThePinhole>("splat-at-the-pinhole");
    assert_caught_by_hard_case::<SplatSurfaceSideUntested>("splat-back-face");
    assert_caught_by_hard_case::<SplatNanPasses>("splat-nan");
}

/// `b / lambda`: the wavelength not squared.
struct WavelengthNotSquared;
plant! {
    WavelengthNotSquared;
    fn cauchy_ior(cauchy: &Cauchy, nanometres: f32) -> f32 {
        cauchy.a + cauchy.b / (nanometres / 1000.0)
    }
}

#[test]
fn an_index_with_the_wavelength_not_squared_is_caught() {
    assert_caught::<WavelengthNotSquared>("cauchy-bk7-d-line");
}

/// The reference's `connect_to_camera` without its shadow ray.
struct NoShadowToTheCamera;
plant! {
    NoShadowToTheCamera;
    fn connect_to_camera(tracer: &mut Tracer<Planted>, point: &HitPoint, lobe: &Lobe, power: Vec3) {
        let camera = *tracer.camera();
        let Some((x, y)) = camera.project(point.surface.point) else {
            return;
        };
        if !point.faces(camera.origin()) {
            return;
        }
        let to_camera = camera.origin() - point.surface.point;
        let distance = to_camera.length();
        let direction = to_camera / distance;
        let scattered = lobe.value::<Planted>(point, direction);
        if scattered == Vec3::ZERO {
            return;
        }
        let weight = Planted::splat_weight(
            point.normal.dot(direction),
            camera.forward().dot(-direction),
            distance,
            camera.pixel_area(),
        );
        tracer.splat(x, y, power * scattered * weight);
    }
}

/// The reference's `connect_to_camera` splatting at `(y, x)`: the row
/// taken for the column. The camera sees the screen at a slant, so the
/// spot's image is an ellipse, and turned a quarter it lights other pixels.
struct SplatAxesSwapped;
plant! {
    SplatAxesSwapped;
    fn connect_to_camera(tracer: &mut Tracer<Planted>, point: &HitPoint, lobe: &Lobe, power: Vec3) {
        let camera = *tracer.camera();
        let Some((x, y)) = camera.project(point.surface.point) else {
            return;
        };
        if !point.faces(camera.origin()) {
            return;
        }
        let to_camera = camera.origin() - point.surface.point;
        let distance = to_camera.length();
        let direction = to_camera / distance;
        let scattered = lobe.value::<Planted>(point, direction);
        if scattered == Vec3::ZERO || tracer.blocked_from_camera(point) {
            return;
        }
        let weight = Planted::splat_weight(
            point.normal.dot(direction),
            camera.forward().dot(-direction),
            distance,
            camera.pixel_area(),
        );
        tracer.splat(y, x, power * scattered * weight);
    }
}

#[test]
fn a_lit_point_splatted_on_another_pixel_is_caught() {
    assert_caught::<SplatAxesSwapped>("ball-lens");
}

/// The reference's `connect_to_camera` with Lambert's `albedo / pi` for
/// the lobe's `f`.
struct LambertsFToTheCamera;
plant! {
    LambertsFToTheCamera;
    fn connect_to_camera(tracer: &mut Tracer<Planted>, point: &HitPoint, lobe: &Lobe, power: Vec3) {
        let diffuse = Lobe::Diffuse {
            albedo: point.albedo,
        };
        let lobe = if lobe.has_density() { &diffuse } else { lobe };
        super::connect_to_camera(tracer, point, lobe, power)
    }
}

#[test]
fn a_lit_point_joined_to_the_camera_through_a_wall_or_with_lamberts_f_is_caught() {
    assert_caught::<NoShadowToTheCamera>("box-lit-inside-seen-from-outside");
    assert_caught::<LambertsFToTheCamera>("glossy-floor-under-a-beam-through-glass");
}

/// One mistake in the reference's `trace_light_path`, or none.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum LightPathSlip {
    NoSlip,
    /// The power not multiplied by a bounce's `f cos / pdf`.
    PowerNotScattered,
    /// The power not dimmed by the medium crossed.
    NoAbsorption,
    /// A roulette survivor's power not multiplied by the factor returned.
    SurvivorNotBoosted,
}

/// The reference's `trace_light_path` with `slip` made.
fn light_path<C: Chapters>(tracer: &mut Tracer<C>, slip: LightPathSlip) {
    use LightPathSlip::*;
    use raylab::chapters::ch14_caustics::LIGHT_ROULETTE_FROM_DEPTH;
    let Some(emitted) = tracer.emit() else {
        return;
    };
    let start = emitted.power.max_element();
    let (mut ray, mut power) = (emitted.ray, emitted.power);
    let mut media = raylab::medium::MediumStack::EMPTY;
    let mut through_specular = false;
    for depth in 0..tracer.max_depth() {
        let Some(hit) = tracer.trace_light(&media, &ray) else {
            return;
        };
        let point = hit.point;
        let absorption = media.current().absorption;
        if absorption != Vec3::ZERO && slip != NoAbsorption {
            power *= C::transmittance(absorption, hit.distance);
        }
        let lobe = Lobe::choose(&point, tracer.random());
        if lobe.has_density() {
            if !through_specular {
                return;
            }
            C::connect_to_camera(tracer, &point, &lobe, power);
        } else {
            through_specular = true;
        }
        let Some(scattered) = lobe.scatter::<C>(tracer, &point) else {
            return;
        };
        if slip != PowerNotScattered {
            power *= scattered.weight;
        }
        if depth + 1 >= LIGHT_ROULETTE_FROM_DEPTH {
            match C::russian_roulette(power.max_element() / start, tracer.random()) {
                Some(boost) if slip != SurvivorNotBoosted => power *= boost,
                Some(_) => {}
                None => return,
            }
        }
        let direction = scattered.direction;
        ray = raylab::Ray::new(tracer.offset_origin(&point.surface, direction), direction);
        media = scattered.media;
    }
}

/// A `Chapters` whose `trace_light_path` is the reference with one slip.
macro_rules! light_path_variant {
    ($name:ident, $slip:ident) => {
        struct $name;
        plant! {
            $name;
            fn trace_light_path(tracer: &mut Tracer<Planted>) {
                light_path(tracer, LightPathSlip::$slip)
            }
        }
    };
}

light_path_variant!(LightPathCopy, NoSlip);
light_path_variant!(PowerNotScattered, PowerNotScattered);
light_path_variant!(LightPathUnabsorbed, NoAbsorption);
light_path_variant!(LightSurvivorNotBoosted, SurvivorNotBoosted);

#[test]
fn each_clause_of_trace_light_path_is_caught() {
    let verdict = planted::check_chapter::<LightPathCopy>(14, &options());
    assert!(verdict.robust(), "{}", verdict.text());
    assert_caught::<PowerNotScattered>("point-light-in-glass");
    assert_caught::<LightSurvivorNotBoosted>("point-light-in-glass");
    assert_caught::<LightPathUnabsorbed>("beam-through-absorbing-glass");
}

/// One mistake in the reference's `dispersive_ior`, or none.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum DispersionSlip {
    NoSlip,
    /// The wavelength never kept: each surface draws one anew, with its
    /// colour.
    NotKept,
    /// The kept wavelength's colour applied again at every surface.
    TintEverySurface,
    /// Wavelengths drawn as `u^2` over the range: more of the blue.
    NotUniform,
    /// The index of the middle of the range, whatever was drawn.
    IndexOfAnotherWavelength,
}

/// The reference's `dispersive_ior` with `slip` made.
fn dispersed<C: Chapters>(
    tracer: &mut Tracer<C>,
    cauchy: &Cauchy,
    slip: DispersionSlip,
) -> Dispersed {
    use DispersionSlip::*;
    use raylab::spectrum::{rgb_weight, wavelength_of};
    let index = |nanometres: f32| {
        if slip == IndexOfAnotherWavelength {
            C::cauchy_ior(cauchy, 580.0)
        } else {
            C::cauchy_ior(cauchy, nanometres)
        }
    };
    if let Some(nanometres) = tracer.wavelength() {
        let tint = if slip == TintEverySurface {
            rgb_weight(nanometres)
        } else {
            Vec3::ONE
        };
        return Dispersed {
            ior: index(nanometres),
            tint,
        };
    }
    let u = tracer.random();
    let nanometres = wavelength_of(if slip == NotUniform { u * u } else { u });
    if slip != NotKept {
        tracer.set_wavelength(nanometres);
    }
    Dispersed {
        ior: index(nanometres),
        tint: rgb_weight(nanometres),
    }
}

/// A `Chapters` whose `dispersive_ior` is the reference with one slip.
macro_rules! dispersion_variant {
    ($name:ident, $slip:ident) => {
        struct $name;
        plant! {
            $name;
            fn dispersive_ior(tracer: &mut Tracer<Planted>, cauchy: &Cauchy) -> Dispersed {
                dispersed(tracer, cauchy, DispersionSlip::$slip)
            }
        }
    };
}

dispersion_variant!(DispersionCopy, NoSlip);
dispersion_variant!(WavelengthNotKept, NotKept);
dispersion_variant!(TintEverySurface, TintEverySurface);
dispersion_variant!(WavelengthNotUniform, NotUniform);
dispersion_variant!(IndexOfAnotherWavelength, IndexOfAnotherWavelength);

#[test]
fn wavelengths_drawn_unevenly_tint_the_white_furnace() {
    // `dispersion-draws-a-wavelength` comes first and fails it too; asked
    // alone, the furnace sees the colours' average tilted to the blue.
    let case = raylab::check::by_chapter::checkpoints(14)
        .into_iter()
        .find(|case| case.name == "spectral-white-furnace")
        .expect("the case exists");
    let outcome = planted::with::<WavelengthNotUniform, _>(|| case.run::<Planted>());
    assert!(
        matches!(outcome, raylab::check::Outcome::Fail { .. }),
        "{outcome:?}"
    );
}

#[test]
fn each_clause_of_dispersive_ior_is_caught() {
    let verdict = planted::check_chapter::<DispersionCopy>(14, &options());
    assert!(verdict.robust(), "{}", verdict.text());
    let variants: [fn(u8, &CheckOptions) -> ChapterVerdict; 4] = [
        planted::check_chapter::<WavelengthNotKept>,
        planted::check_chapter::<TintEverySurface>,
        planted::check_chapter::<WavelengthNotUniform>,
        planted::check_chapter::<IndexOfAnotherWavelength>,
    ];
    for check in variants {
        let verdict = check(14, &options());
        let text = verdict.text();
        assert_eq!(verdict.status, Status::Fail, "{text}");
        assert_eq!(
            verdict.failing_case(),
            Some("dispersion-draws-a-wavelength"),
            "{text}"
        );
    }
}
