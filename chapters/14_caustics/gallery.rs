//! Chapter 14, light paths and dispersion, as `raylab check` judges it:
//! the reference passes both levels; its bug gallery fails chapter 14 on
//! the case that names the mistake: a splat weight without the surface's
//! cosine or with the camera's only once, a light path that stops at its
//! first diffuse point or joins every diffuse point to the camera even
//! when no glass came first, a camera path that counts the caustics light
//! paths bring, an index in nanometres, a light joined to the camera from
//! the side it does not see; a wavelength drawn without its colour fails
//! the image.

use raylab::bsdf::{Dispersed, Lobe};
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
    }
}

/// Checks chapter 14 with `C` and asserts that it fails on case `case`,
/// with nothing earlier to blame.
fn assert_caught<C: Chapters>(case: &str) -> ChapterVerdict {
    let verdict = check_chapter::<C>(14, &options());
    let text = verdict.text();
    assert_eq!(verdict.status, Status::Fail, "{text}");
    assert_eq!(verdict.failing_case(), Some(case), "{text}");
    assert_eq!(verdict.needs, None, "{text}");
    verdict
}

#[test]
fn the_reference_passes_chapter_14_at_both_levels() {
    let verdict = check_chapter::<Reference>(14, &options());
    assert!(verdict.robust(), "{}", verdict.text());
}

struct NoSurfaceCosine;
impl Chapters for NoSurfaceCosine {
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
impl Chapters for CameraCosineOnce {
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
impl Chapters for Nanometres {
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
impl Chapters for EveryDiffusePoint {
    fn connect_to_camera(tracer: &mut Tracer<Self>, point: &HitPoint, lobe: &Lobe, power: Vec3) {
        super::connect_to_camera(tracer, point, lobe, power)
    }
    fn trace_light_path(tracer: &mut Tracer<Self>) {
        let Some(emitted) = tracer.emit() else {
            return;
        };
        let media = raylab::medium::MediumStack::EMPTY;
        let Some(hit) = tracer.trace_light(&media, &emitted.ray) else {
            return;
        };
        let lobe = Lobe::choose(&hit.point, tracer.random());
        if lobe.has_density() {
            Self::connect_to_camera(tracer, &hit.point, &lobe, emitted.power);
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
impl Chapters for FirstPointOnly {
    fn trace_light_path(tracer: &mut Tracer<Self>) {
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
                Self::connect_to_camera(tracer, &hit.point, &lobe, power);
                return;
            }
            let Some(scattered) = lobe.scatter::<Self>(tracer, &hit.point) else {
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
impl Chapters for CausticsTwice {
    fn shade_path(tracer: &mut Tracer<Self>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
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
impl Chapters for BothSides {
    fn connect_to_camera(tracer: &mut Tracer<Self>, point: &HitPoint, lobe: &Lobe, power: Vec3) {
        let camera = *tracer.camera();
        let Some((x, y)) = camera.project(point.surface.point) else {
            return;
        };
        let to_camera = camera.origin() - point.surface.point;
        let distance = to_camera.length();
        let direction = to_camera / distance;
        // The lobe's value on the lit side, wherever the camera is.
        let lit_side = direction - 2.0 * direction.dot(point.normal).min(0.0) * point.normal;
        let scattered = lobe.value(point, lit_side);
        if scattered == Vec3::ZERO || tracer.blocked_from_camera(point) {
            return;
        }
        let weight = Self::splat_weight(
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
    let verdict = check_chapter::<BothSides>(14, &options());
    let text = verdict.text();
    assert_eq!(verdict.status, Status::Pass, "{text}");
    assert!(!verdict.robust(), "{text}");
    let robustness = verdict.robustness.as_ref().expect("level 2 ran");
    let first = robustness.first_failure.as_ref().map(|f| f.name);
    assert_eq!(first, Some("lit-under-the-floor"), "{text}");
}

/// The wavelength drawn, but its colour forgotten: every path through the
/// prism carries white, and the spectrum on the wall is a white smear.
/// The furnace cannot see it (white stays white); the image can.
struct TintForgotten;
impl Chapters for TintForgotten {
    fn dispersive_ior(tracer: &mut Tracer<Self>, cauchy: &Cauchy) -> Dispersed {
        Dispersed {
            tint: Vec3::ONE,
            ..raylab::chapters::ch14_caustics::dispersive_ior(tracer, cauchy)
        }
    }
}

#[test]
fn a_wavelength_without_its_colour_fails_the_image() {
    let verdict = check_chapter::<TintForgotten>(14, &options());
    let text = verdict.text();
    assert_eq!(verdict.status, Status::Fail, "{text}");
    assert_eq!(verdict.failing_case(), None, "{text}");
    assert!(verdict.image.is_some_and(|image| !image.passed), "{text}");
}
