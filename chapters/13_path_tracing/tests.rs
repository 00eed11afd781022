//! Chapter 13's estimators against the values closed scenes converge to,
//! its samplers against their densities, and the whole image against a
//! converged one, each with a stated false-alarm rate.

use super::*;
use crate::Scene;
use crate::bsdf::{phong_exponent, to_world};
use crate::chapters::Reference;
use crate::check::cases::{cosine_fit, mean_and_error, pearson, welch_rejections, z_threshold};
use crate::check::catalog::{ConvergesCase, inside_sphere};
use crate::render::Stage;
use raylab::check::planted::{self, Plant, Planted, plant};

/// The furnace of albedo `albedo` and emission `emission` with `without`
/// left out: its mean and standard error over `samples` camera samples.
fn furnace(albedo: f32, emission: f32, without: &'static [&'static str]) -> (f64, f64) {
    ConvergesCase {
        function: "shade_path",
        scene: inside_sphere(albedo, emission, ""),
        without,
        samples: 40_000,
        expected: 0.0,
        seed: 0,
    }
    .estimate::<Reference>()
    .expect("the furnace renders")
}

#[test]
fn the_white_furnace_converges_to_e_over_one_minus_a_with_every_switch() {
    // Every combination of light samples, MIS and roulette; MIS needs the
    // light samples, so "next-event" off leaves it off too.
    let switches: [&'static [&'static str]; 6] = [
        &[],
        &["mis"],
        &["russian-roulette"],
        &["mis", "russian-roulette"],
        &["next-event"],
        &["next-event", "russian-roulette"],
    ];
    for (albedo, emission) in [(0.5f32, 1.0f32), (0.8, 0.5)] {
        let expected = f64::from(emission) / (1.0 - f64::from(albedo));
        for without in switches {
            let (mean, error) = furnace(albedo, emission, without);
            assert!(
                (mean - expected).abs() <= z_threshold() * error + 1e-3 * expected,
                "albedo {albedo}, emission {emission}, without {without:?}: {mean} +- {error}, \
                 expected {expected}"
            );
        }
    }
}

#[test]
fn pbrts_analytic_scene_gives_radiance_one_and_no_light_without_light_samples() {
    let scene = inside_sphere(
        0.5,
        0.0,
        "[[lights]]\nposition = [0.0, 0.0, 0.0]\nintensity = 3.14159265",
    );
    let case = |without| ConvergesCase {
        function: "next_event",
        scene: scene.clone(),
        without,
        samples: 40_000,
        expected: 1.0,
        seed: 0,
    };
    let (mean, error) = case(&[]).estimate::<Reference>().expect("renders");
    assert!(
        (mean - 1.0).abs() <= z_threshold() * error + 1e-3,
        "{mean} +- {error}"
    );
    // A point light has no area: no scattered ray can ever meet it.
    let (dark, _) = case(&["next-event"])
        .estimate::<Reference>()
        .expect("renders");
    assert_eq!(dark, 0.0);
}

#[test]
fn cosine_directions_fit_their_density_and_a_uniform_hemisphere_does_not() {
    let draw = |sampler: fn(f32, f32) -> Vec3| -> Vec<Vec3> {
        (0..200_000)
            .map(|i| {
                sampler(
                    crate::check::cases::stream(i, 7),
                    crate::check::cases::stream(i, 8),
                )
            })
            .collect()
    };
    let (_, p_value) = cosine_fit(&draw(cosine_hemisphere)).expect("valid directions");
    assert!(p_value > 1e-3, "p = {p_value}");
    let uniform = |u: f32, v: f32| {
        let ring = (1.0 - u * u).max(0.0).sqrt();
        let (sin, cos) = (2.0 * PI * v).sin_cos();
        Vec3::new(ring * cos, ring * sin, u)
    };
    let (_, p_value) = cosine_fit(&draw(uniform)).expect("valid directions");
    assert!(p_value < 1e-12, "p = {p_value}");
}

/// A floor with the material `material` (TOML), seen from above at an angle.
fn floor_point(material: &str) -> Scene {
    floor_and(material, "")
}

/// [`floor_point`] with the objects `more` (TOML) after the floor.
fn floor_and(material: &str, more: &str) -> Scene {
    Scene::parse(
        &format!(
            r#"
[camera]
position = [0.0, 1.0, -1.0]
look_at = [0.0, 0.0, 0.0]
[render]
width = 4
height = 4
[[objects]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }}
material = {material}
{more}
"#
        ),
        "a test",
    )
    .expect("the floor parses")
}

/// The chi-square p-value of `samples` draws of a direction (`None`: the
/// light is absorbed, or nothing is drawn) against the density `pdf`, per
/// unit solid angle: bins of `cos` (about +y, the floor's normal) and
/// `phi`, each bin's probability by the midpoint rule on a 24 x 24 grid of
/// its cell (`dw = d(cos) d(phi)`), and one more cell for `None`, expected
/// to hold what the density leaves out. So a density off by a constant
/// factor fails too, as MIS would weigh it wrongly.
fn direction_fit(
    samples: u32,
    mut draw: impl FnMut() -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
) -> f64 {
    let (rows, columns, fine) = (16usize, 16usize, 24usize);
    let bin_of = |direction: Vec3| {
        let cosine = ((direction.y + 1.0) / 2.0 * rows as f32) as usize;
        let phi = (direction.z.atan2(direction.x).rem_euclid(2.0 * PI) / (2.0 * PI)
            * columns as f32) as usize;
        cosine.min(rows - 1) * columns + phi.min(columns - 1)
    };
    let none = rows * columns;
    let mut observed = vec![0f64; none + 1];
    for _ in 0..samples {
        match draw() {
            Some(direction) => observed[bin_of(direction)] += 1.0,
            None => observed[none] += 1.0,
        }
    }
    let mut expected = vec![0f64; none + 1];
    let cell = 2.0 / (rows * fine) as f64 * std::f64::consts::TAU / (columns * fine) as f64;
    for row in 0..rows * fine {
        let cosine = (row as f64 + 0.5) / (rows * fine) as f64 * 2.0 - 1.0;
        for column in 0..columns * fine {
            let phi = (column as f64 + 0.5) / (columns * fine) as f64 * std::f64::consts::TAU;
            let ring = (1.0 - cosine * cosine).sqrt();
            let direction = Vec3::new(
                (ring * phi.cos()) as f32,
                cosine as f32,
                (ring * phi.sin()) as f32,
            );
            expected[bin_of(direction)] += pdf(direction) * cell * f64::from(samples);
        }
    }
    let drawn: f64 = expected[..none].iter().sum();
    expected[none] = (f64::from(samples) - drawn).max(0.0);
    pearson(&observed, &expected).1
}

/// The p-value of the directions `lobe` scatters at the floor's point hit
/// from 45 degrees against the lobe's own pdf; draws below the floor are
/// absorbed (the `None` cell).
fn lobe_fit(material: &str) -> f64 {
    let scene = floor_point(material);
    let stage = Stage::<Reference>::with_chapters(&scene, 13, scene.render).expect("stage");
    let mut tracer = stage.tracer(None);
    let ray = Ray::new(Vec3::new(0.0, 1.0, -1.0), Vec3::new(0.0, -1.0, 1.0));
    let point = tracer.hit_point(0, &ray, 1.0);
    let lobe = Lobe::choose(&point, 0.999);
    let pdf = |direction: Vec3| {
        if direction.y > 0.0 {
            f64::from(lobe.pdf::<Reference>(&point, direction))
        } else {
            0.0
        }
    };
    direction_fit(
        100_000,
        || {
            lobe.scatter::<Reference>(&mut tracer, &point)
                .map(|scattered| scattered.direction)
        },
        pdf,
    )
}

#[test]
fn light_samples_are_spread_as_the_light_pdf_says() {
    // A 2 x 2 light one unit above the floor's point: it fills a large
    // share of the sky, over many bins.
    let scene = floor_and(
        "{ color = [0.5, 0.5, 0.5] }",
        r#"[[objects]]
quad = { corner = [-1.0, 1.0, -0.5], u = [2.0, 0.0, 0.0], v = [0.0, 0.0, 2.0] }
material = { color = [0.0, 0.0, 0.0], emission = [1.0, 1.0, 1.0] }"#,
    );
    let stage = Stage::<Reference>::with_chapters(&scene, 13, scene.render).expect("stage");
    let mut tracer = stage.tracer(None);
    let ray = Ray::new(Vec3::new(0.0, 1.0, -1.0), Vec3::new(0.0, -1.0, 1.0));
    let point = tracer.hit_point(0, &ray, 1.0);
    let probe = stage.tracer(None);
    let pdf = |direction: Vec3| {
        let ray = Ray::new(point.surface.point + 1e-4 * Vec3::Y, direction);
        match stage.nearest_hit(&ray, 0.0, f32::INFINITY) {
            Some(hit) => f64::from(probe.light_pdf(&probe.hit_point(hit.object, &ray, hit.t))),
            None => 0.0,
        }
    };
    let p_value = direction_fit(
        100_000,
        || tracer.sample_light(&point).map(|light| light.direction),
        pdf,
    );
    assert!(p_value > 1e-3, "p = {p_value}");
}

#[test]
fn a_lamp_shines_from_its_front_only_unless_it_is_two_sided() {
    // A 2 x 2 lamp one unit above the floor, whose normal `u x v` faces
    // down at it, then up, away from it.
    let down = "corner = [-1.0, 1.0, -1.0], u = [2.0, 0.0, 0.0], v = [0.0, 0.0, 2.0]";
    let up = "corner = [-1.0, 1.0, -1.0], u = [0.0, 0.0, 2.0], v = [2.0, 0.0, 0.0]";
    for (quad, two_sided, lit) in [(down, false, true), (up, false, false), (up, true, true)] {
        let scene = floor_and(
            "{ color = [0.5, 0.5, 0.5] }",
            &format!(
                "[[objects]]\nquad = {{ {quad} }}\n\
                 material = {{ color = [0.0, 0.0, 0.0], emission = [1.0, 1.0, 1.0], two_sided = {two_sided} }}"
            ),
        );
        let stage = Stage::<Reference>::with_chapters(&scene, 13, scene.render).expect("stage");
        let mut tracer = stage.tracer(None);
        let floor = tracer.hit_point(0, &Ray::new(Vec3::Y * 0.5, -Vec3::Y), 0.5);
        let samples = (0..64)
            .filter(|_| tracer.sample_light(&floor).is_some())
            .count();
        // Seen from the floor: the lamp's light is there or not, and the
        // density MIS weighs with follows it.
        let from_floor = Ray::new(Vec3::new(0.1, 0.0, 0.2), Vec3::Y);
        let lamp = stage
            .nearest_hit(&from_floor, 1e-3, f32::INFINITY)
            .map(|hit| tracer.hit_point(hit.object, &from_floor, hit.t))
            .expect("the ray up meets the lamp");
        let label = format!("{quad}, two_sided {two_sided}");
        assert_eq!(
            samples == 64,
            lit,
            "light samples: {samples} of 64, {label}"
        );
        assert_eq!(lamp.emitted() == Vec3::ONE, lit, "{label}");
        assert_eq!(tracer.light_pdf(&lamp) > 0.0, lit, "{label}");
        assert!(
            lit || (samples == 0 && lamp.emitted() == Vec3::ZERO),
            "{label}"
        );
    }
}

#[test]
fn roulette_never_ends_a_path_where_it_crosses_glass() {
    // A path that carries almost nothing, deep, at a glass ball: the
    // crossing's weight holds (n1 / n2)^2, a change of units, and roulette
    // there would end nearly every path into glass. It plays only where a
    // path scatters at random, so each visit casts its specular ray.
    let scene = floor_and(
        "{ color = [0.5, 0.5, 0.5] }",
        "[[objects]]\nsphere = { center = [0.0, 1.0, 0.0], radius = 0.5 }\n\
         material = { color = [1.0, 1.0, 1.0], transparency = 1.0, ior = 1.5, fresnel = \"exact\" }",
    );
    let stage = Stage::<Reference>::with_chapters(&scene, 13, scene.render).expect("stage");
    assert!(stage.effects.roulette);
    let mut tracer = stage.tracer(None);
    let ray = Ray::new(Vec3::new(0.0, 3.0, 0.0), -Vec3::Y);
    let glass = tracer.hit_point(1, &ray, 1.5);
    let visits = 200;
    for _ in 0..visits {
        shade_path::<Reference>(&mut tracer, &glass, ROULETTE_FROM_DEPTH, 1e-6);
    }
    let counts = tracer.counts();
    assert!(
        counts.of(crate::RayKind::Reflection) + counts.of(crate::RayKind::Refraction) >= visits,
        "{} reflection and {} refraction rays from {visits} visits",
        counts.of(crate::RayKind::Reflection),
        counts.of(crate::RayKind::Refraction)
    );
}

#[test]
fn the_glossy_and_diffuse_lobes_scatter_as_their_pdfs_say() {
    for material in [
        "{ color = [0.8, 0.8, 0.8] }",
        "{ color = [0.9, 0.9, 0.9], reflectivity = 1.0, roughness = 0.3 }",
        "{ color = [0.9, 0.9, 0.9], reflectivity = 1.0, roughness = 0.8 }",
    ] {
        let p_value = lobe_fit(material);
        assert!(p_value > 1e-3, "{material}: p = {p_value}");
    }
}

#[test]
fn the_glossy_lobe_never_returns_more_light_than_arrives() {
    // The directional albedo, the integral of f cos over the hemisphere,
    // by the lobe's own importance sampling: at most the colour, 0.9.
    for roughness in [0.05f32, 0.3, 1.0] {
        let scene = floor_point(&format!(
            "{{ color = [0.9, 0.9, 0.9], reflectivity = 1.0, roughness = {roughness} }}"
        ));
        let stage = Stage::<Reference>::with_chapters(&scene, 13, scene.render).expect("stage");
        let mut tracer = stage.tracer(None);
        for angle in [0.0f32, 45.0, 80.0] {
            let (sin, cos) = angle.to_radians().sin_cos();
            let ray = Ray::new(Vec3::new(0.0, cos, -sin), Vec3::new(0.0, -cos, sin));
            let point = tracer.hit_point(0, &ray, 1.0);
            let lobe = Lobe::choose(&point, 0.5);
            let draws: Vec<f64> = (0..20_000)
                .map(|_| {
                    lobe.scatter::<Reference>(&mut tracer, &point)
                        .map_or(0.0, |s| f64::from(s.weight.x))
                })
                .collect();
            let (albedo, error) = mean_and_error(&draws);
            assert!(
                albedo <= 0.9 + 4.0 * error,
                "roughness {roughness}, {angle} degrees: {albedo}"
            );
        }
    }
}

/// The mean and variance of each pixel's first channel over `samples`
/// samples of chapter 13's scene at `size` x `size`, with seed `seed`.
fn pixel_statistics<C: Plant>(size: u32, samples: u32, seed: u64) -> Vec<(f64, f64, f64)> {
    planted::with::<C, _>(|| {
        let mut scene = crate::builtin::scene(13).expect("the built-in scene");
        scene.render.width = size;
        scene.render.height = size;
        scene.render.seed = seed;
        scene.render.samples = samples;
        let stage = Stage::<Planted>::with_chapters(&scene, 13, scene.render).expect("stage");
        let mut tracer = stage.tracer(None);
        let mut statistics = Vec::new();
        for y in 0..size {
            for x in 0..size {
                let values: Vec<f64> = (0..samples)
                    .map(|index| {
                        let (dx, dy) = tracer.sample_offset(index, (x, y));
                        f64::from(tracer.sample(x as f32 + dx, y as f32 + dy).x)
                    })
                    .collect();
                let (mean, error) = mean_and_error(&values);
                statistics.push((mean, error * error, f64::from(samples)));
            }
        }
        statistics
    })
}

/// A variant that counts what a light emits again when a scattered ray
/// finds it, though next-event estimation counted it already.
struct EmissionTwice;
plant! {
    EmissionTwice;
    fn shade_path(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        let twice =
            matches!(tracer.arrival(), Arrival::Scattered { .. }) && tracer.effects().next_event;
        shade_path(tracer, point, depth, weight) + if twice { point.emitted() } else { Vec3::ZERO }
    }
}

#[test]
fn the_whole_image_is_unbiased_by_welchs_test_and_a_double_count_is_not() {
    // 144 pixels at level 0.01: a correct estimator rejects 1.4 on
    // average, and 7 or more with probability below 1e-3 (binomial).
    let (size, alpha) = (12, 0.01);
    let reference = pixel_statistics::<Reference>(size, 4096, 1);
    let own = pixel_statistics::<Reference>(size, 1024, 2);
    let rejected = welch_rejections(&own, &reference, alpha);
    assert!(rejected < 7, "{rejected} of 144 pixels differ");
    let biased = pixel_statistics::<EmissionTwice>(size, 1024, 2);
    let rejected = welch_rejections(&biased, &reference, alpha);
    assert!(rejected > 30, "only {rejected} of 144 pixels differ");
}

#[test]
fn phong_exponents_follow_the_roughness() {
    assert_eq!(phong_exponent(1.0), 0.0);
    assert!((phong_exponent(0.1) - 198.0).abs() < 1e-3);
}

#[test]
fn the_frame_is_orthonormal_for_any_normal() {
    for normal in [
        Vec3::Z,
        -Vec3::Z,
        Vec3::X,
        Vec3::new(0.0, 0.6, -0.8),
        Vec3::new(1e-8, 0.0, -1.0),
    ] {
        let x = to_world(normal, Vec3::X);
        let y = to_world(normal, Vec3::Y);
        assert!((x.length() - 1.0).abs() < 1e-5 && (y.length() - 1.0).abs() < 1e-5);
        assert!(x.dot(y).abs() < 1e-5 && x.dot(normal).abs() < 1e-5 && y.dot(normal).abs() < 1e-5);
        assert_eq!(to_world(normal, Vec3::Z), normal);
    }
}

// The bug gallery and the accepted alternatives of this chapter.
#[path = "gallery.rs"]
mod gallery;

#[test]
fn the_false_alarm_rate_is_corrected_for_at_least_every_statistical_case() {
    use crate::check::catalog::CaseKind;
    let statistical = crate::check::by_chapter::checkpoints(13)
        .into_iter()
        .chain(crate::check::by_chapter::robustness(13))
        .filter(|case| {
            matches!(
                case.kind,
                CaseKind::CosineSample(_) | CaseKind::Converges(_)
            )
        })
        .count();
    assert!((1..=crate::check::cases::STATISTICAL_CASES).contains(&statistical));
}

/// `grade --code --fresh` runs every checkpoint on other numbers (the
/// closed scenes on other streams): the reference must pass each draw, or
/// a correct student would fail one.
#[test]
fn the_reference_passes_fresh_draws_of_the_checkpoints() {
    use crate::check::Outcome;
    for seed in 1..=2 {
        for case in crate::check::by_chapter::checkpoints(13) {
            if let Some(fresh) = case.fresh(seed) {
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
}
