//! Chapter 14's light paths and dispersion against the values closed scenes
//! converge to, the lens against geometry, the prism against Snell's law,
//! and the whole image against chapter 13's, each with a stated
//! false-alarm rate.

use super::*;
use crate::chapters::Reference;
use crate::check::cases::{
    LensCase, LightConvergesCase, PrismCase, linear_image, welch_rejections, z_threshold,
};
use crate::check::catalog::Case;
use crate::render::Stage;
use raylab::check::planted::{self, Plant, Planted, plant};

use crate::check::by_chapter::ch14_caustics::checks::{GLASS_BALL, closed_sphere};

/// pbrt-v4's analytic scene (a point light of intensity pi at the centre
/// of a sphere of albedo 0.5: radiance 1 everywhere) with the light inside
/// a glass ball. The ball loses nothing and is centred on the light, so
/// the wall still receives the same light everywhere: radiance 1. But every
/// path of that light crosses glass first, so only light paths find it.
fn point_light_in_glass() -> String {
    closed_sphere(
        &format!("[[lights]]\nposition = [0.0, 0.0, 0.0]\nintensity = 3.14159265\n{GLASS_BALL}"),
        -1.0,
        "",
    )
}

/// A white emitting ball of radius 0.1 and radiance 100 inside the glass
/// ball: it gives off `100 pi 4 pi 0.1^2` in all, `pi` per unit area of
/// the wall, and the ball and emitter together lose nothing, so the wall's
/// radiance is `0.5 (pi + pi L) / pi`: `L = 1`.
fn area_light_in_glass() -> String {
    closed_sphere(
        &format!(
            "[[objects]]\nname = \"lamp\"\nsphere = {{ center = [0.0, 0.0, 0.0], radius = 0.1 }}\n\
             material = {{ color = [1.0, 1.0, 1.0], emission = [100.0, 100.0, 100.0] }}\n{GLASS_BALL}"
        ),
        -1.0,
        "",
    )
}

fn converges(scene: String, without: &'static [&'static str], expected: f64) -> (DVec3, DVec3) {
    converges_with::<Reference>(scene, without, expected)
}

fn converges_with<C: Plant>(
    scene: String,
    without: &'static [&'static str],
    expected: f64,
) -> (DVec3, DVec3) {
    planted::with::<C, _>(|| {
        LightConvergesCase {
            function: "trace_light_path",
            scene,
            without,
            repetitions: 24,
            expected: [expected; 3],
            first_seed: 1,
        }
        .estimate::<Planted>()
        .expect("the scene renders")
    })
}

fn assert_converges_to(found: (DVec3, DVec3), expected: f64, what: &str) {
    let (mean, error) = found;
    let allowed = z_threshold() * error + DVec3::splat(1e-3 * expected);
    assert!(
        (mean - DVec3::splat(expected)).abs().cmple(allowed).all(),
        "{what}: {mean} +- {error}, expected {expected}"
    );
}

use glam::DVec3;

#[test]
fn a_point_light_in_glass_lights_the_wall_through_light_paths_alone() {
    let with = converges(point_light_in_glass(), &[], 1.0);
    assert_converges_to(with, 1.0, "with light paths");
    // Camera paths cannot find a point light behind glass: no light at all.
    let (without, _) = converges(point_light_in_glass(), &["light-tracing"], 0.0);
    assert_eq!(without, DVec3::ZERO);
}

#[test]
fn an_area_light_in_glass_gives_the_same_light_with_and_without_light_paths() {
    assert_converges_to(
        converges(area_light_in_glass(), &[], 1.0),
        1.0,
        "light paths",
    );
    // Chapter 13's camera paths find the lamp through the glass by chance:
    // the same mean, with far more noise. (It was 2.25 times too bright
    // before refraction scaled radiance by (n1 / n2)^2: the lamp shines
    // into glass, and its light leaves it once.)
    assert_converges_to(
        converges(area_light_in_glass(), &["light-tracing"], 1.0),
        1.0,
        "camera paths alone",
    );
    // Counted by both, the lamp's light through the glass is counted twice.
    let (twice, _) = converges_with::<gallery::CausticsTwice>(area_light_in_glass(), &[], 1.0);
    assert!(twice.x > 1.5, "{twice}");
}

/// A dispersive glass ball in the white furnace (a sphere of albedo 0.5
/// that emits 1: radiance 2 everywhere), seen through the ball: every
/// wavelength is bent its own way, and the wall is still white, 2 in each
/// channel.
#[test]
fn a_spectral_white_furnace_stays_white() {
    let scene = closed_sphere(
        r#"
[[objects]]
name = "prism glass"
sphere = { center = [0.0, 0.0, 0.0], radius = 0.25 }
material = { color = [1.0, 1.0, 1.0], transparency = 1.0, cauchy = { a = 1.6, b = 0.05 }, fresnel = "exact" }
"#,
        1.0,
        ", emission = [1.0, 1.0, 1.0], two_sided = true",
    );
    assert_converges_to(converges(scene, &[], 2.0), 2.0, "dispersive furnace");
}

#[test]
fn the_lens_brightens_its_caustic_as_geometry_says() {
    let lens = LensCase {
        ior: 1.5,
        beam: 0.3,
        screen: 1.2,
        disk: 0.02,
        repetitions: 8,
        first_seed: 1,
    };
    let outcome =
        Case::new("lens", "", "", crate::check::catalog::CaseKind::Lens(lens)).run::<Reference>();
    assert_eq!(outcome, crate::check::cases::Outcome::Pass);
}

#[test]
fn the_prism_deviates_least_where_snell_says() {
    for nanometres in [420.0, 550.0, 680.0] {
        let prism = PrismCase {
            cauchy: Cauchy {
                a: 1.728,
                b: 0.01342,
            },
            apex_degrees: 60.0,
            nanometres,
        };
        let outcome = Case::new(
            "prism",
            "",
            "",
            crate::check::catalog::CaseKind::Prism(prism),
        )
        .run::<Reference>();
        assert_eq!(
            outcome,
            crate::check::cases::Outcome::Pass,
            "{nanometres} nm"
        );
    }
}

/// The mean and variance of the mean of each pixel's first channel over
/// `repetitions` renders of `scene` by chapter `chapter`'s stage, each with
/// its own seed from `first_seed` on: a pixel's value is the sum of camera
/// samples and light paths, so its spread is read across renders.
fn render_statistics<C: Plant>(
    scene: &crate::Scene,
    chapter: u8,
    repetitions: u32,
    first_seed: u64,
) -> Vec<(f64, f64, f64)> {
    planted::with::<C, _>(|| {
        let mut scene = scene.clone();
        let images: Vec<Vec<f64>> = (0..u64::from(repetitions))
            .map(|repetition| {
                scene.render.seed = first_seed + repetition;
                let stage =
                    Stage::<Planted>::with_chapters(&scene, chapter, scene.render).expect("stage");
                linear_image(&stage)
                    .iter()
                    .map(|pixel| f64::from(pixel.x))
                    .collect()
            })
            .collect();
        let count = f64::from(repetitions);
        (0..images[0].len())
            .map(|pixel| {
                let values: Vec<f64> = images.iter().map(|image| image[pixel]).collect();
                let (mean, error) = crate::check::cases::mean_and_error(&values);
                (mean, error * error, count)
            })
            .collect()
    })
}

/// The lens's screen lit through the ball by a lamp, a ball of radius 0.4
/// far up the axis, instead of the beam: chapter 13's camera paths find
/// the lamp through the glass often enough to converge.
fn lens_lit_by_a_lamp(samples: u32) -> crate::Scene {
    let lens = LensCase {
        ior: 1.5,
        beam: 0.3,
        screen: 1.2,
        disk: 0.02,
        repetitions: 1,
        first_seed: 1,
    };
    let text = lens.scene(true);
    let (start, end) = (
        text.find("[[beams]]").unwrap_or(0),
        text.find("[[objects]]").unwrap_or(0),
    );
    let beam = &text[start..end];
    let text = text
        .replace(
            beam,
            "[[objects]]\nname = \"lamp\"\nsphere = { center = [0.0, 0.0, -4.0], radius = 0.4 }\n\
             material = { color = [0.0, 0.0, 0.0], emission = [20.0, 20.0, 20.0] }\n",
        )
        .replace("width = 48\nheight = 48", "width = 12\nheight = 12")
        .replace("fov_degrees = 3.0", "fov_degrees = 6.0")
        .replace("max_depth = 3", "max_depth = 8")
        .replace("samples = 1", &format!("samples = {samples}"))
        .replace(
            "light_paths = 64",
            &format!("light_paths = {}", samples * 16),
        );
    crate::Scene::parse(&text, "a test").expect("the scene parses")
}

#[test]
fn a_caustic_from_light_paths_is_the_caustic_camera_paths_find() {
    // 144 pixels at level 0.01: a correct estimator rejects 1.4 on
    // average, and 7 or more with probability below 1e-3 (binomial).
    let alpha = 0.01;
    let reference = render_statistics::<Reference>(&lens_lit_by_a_lamp(256), 13, 32, 1000);
    let scene = lens_lit_by_a_lamp(16);
    let own = render_statistics::<Reference>(&scene, 14, 32, 1);
    let rejected = welch_rejections(&own, &reference, alpha);
    assert!(rejected < 7, "{rejected} of 144 pixels differ");
    let biased = render_statistics::<NoSurfaceCosine>(&scene, 14, 32, 1);
    let rejected = welch_rejections(&biased, &reference, alpha);
    assert!(rejected >= 7, "only {rejected} of 144 pixels differ");
}

/// A variant whose splat weight forgets the surface's cosine: the screen,
/// seen at 65 degrees from its normal, comes out 2.4 times too bright.
struct NoSurfaceCosine;
plant! {
    NoSurfaceCosine;
    fn splat_weight(cos_surface: f32, cos_camera: f32, distance: f32, pixel_area: f32) -> f32 {
        splat_weight(cos_surface, cos_camera, distance, pixel_area) / cos_surface
    }
}

#[test]
fn a_glass_of_constant_index_gives_the_image_of_its_index_wavelengths_and_all() {
    let constant = lens_lit_by_a_lamp(16);
    let mut dispersive = constant.clone();
    for material in dispersive.materials_mut() {
        if material.transparency > 0.0 {
            material.cauchy = Some(Cauchy { a: 1.5, b: 1e-7 });
        }
    }
    let stage =
        Stage::<Reference>::with_chapters(&dispersive, 14, dispersive.render).expect("stage");
    assert!(stage.effects.dispersion, "the stage draws wavelengths");
    // 144 pixels at level 0.01: 7 or more rejections has a chance below
    // 1e-3 for a correct estimator.
    let reference = render_statistics::<Reference>(&constant, 14, 32, 1000);
    let own = render_statistics::<Reference>(&dispersive, 14, 32, 1);
    let rejected = welch_rejections(&own, &reference, 0.01);
    assert!(rejected < 7, "{rejected} of 144 pixels differ");
    let tinted_twice = render_statistics::<TintAtEverySurface>(&dispersive, 14, 32, 1);
    let rejected = welch_rejections(&tinted_twice, &reference, 0.01);
    assert!(rejected >= 7, "only {rejected} of 144 pixels differ");
}

/// A variant that gives the path its wavelength's colour at every
/// dispersive surface, not the first only: through a ball, the colour
/// squared, whose mean is not white.
struct TintAtEverySurface;
plant! {
    TintAtEverySurface;
    fn dispersive_ior(tracer: &mut Tracer<Planted>, cauchy: &Cauchy) -> Dispersed {
        let dispersed = dispersive_ior(tracer, cauchy);
        let nanometres = tracer.wavelength().unwrap_or(550.0);
        Dispersed {
            tint: rgb_weight(nanometres),
            ..dispersed
        }
    }
}

#[test]
fn splat_weights_are_the_solid_angle_ratio() {
    // Straight ahead at distance 2, face on, a pixel of 1e-4 at distance 1:
    // the pixel covers 1e-4 sr, a unit area 1 / 4 sr.
    assert!((splat_weight(1.0, 1.0, 2.0, 1e-4) - 2500.0).abs() < 1e-2);
    assert_eq!(splat_weight(1.0, 0.0, 2.0, 1e-4), 0.0);
    assert_eq!(splat_weight(0.0, 1.0, 2.0, 1e-4), 0.0);
    assert_eq!(splat_weight(1.0, 1.0, 0.0, 1e-4), 0.0);
    assert_eq!(splat_weight(f32::NAN, 1.0, 1.0, 1.0), 0.0);
}

#[test]
fn cauchy_gives_bk7_its_catalogue_index() {
    let bk7 = Cauchy {
        a: 1.5046,
        b: 0.0042,
    };
    // Schott's n_d for N-BK7 is 1.5168.
    assert!((cauchy_ior(&bk7, 587.56) - 1.5168).abs() < 2e-4);
    assert!(cauchy_ior(&bk7, 450.0) > cauchy_ior(&bk7, 650.0));
}

// The bug gallery of this chapter.
#[path = "gallery.rs"]
mod gallery;

/// `grade --code --fresh` runs the checkpoints on other seeds: the
/// reference must pass the dispersion case and the two closed scenes that
/// check the shadow ray to the camera and absorption on other seeds too.
#[test]
fn the_reference_passes_fresh_draws_of_the_new_checkpoints() {
    use crate::check::Outcome;
    let new = [
        "dispersion-draws-a-wavelength",
        "box-lit-inside-seen-from-outside",
        "glossy-floor-under-a-beam-through-glass",
        "beam-through-absorbing-glass",
    ];
    for seed in 1..=2 {
        for case in crate::check::by_chapter::checkpoints(14) {
            if !new.contains(&case.name) {
                continue;
            }
            let fresh = case.fresh(seed).expect("a statistical case draws anew");
            assert_eq!(
                fresh.run::<Reference>(),
                Outcome::Pass,
                "{} under seed {seed}: {}",
                case.name,
                fresh.kind.inputs()
            );
        }
    }
}
