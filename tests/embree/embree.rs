//! The Embree backend (feature `embree`; `scripts/test.sh` sets it up):
//! every chapter's render cross-checks clean, random rays on random spheres
//! and planes agree, and the command-line tools print both answers.
#![cfg(feature = "embree")]

use std::path::Path;
use std::process::Command;

use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;
use raylab::crosscheck::{
    self, Answer, Boundary, PlaneQuad, Primitive, Reference, Verdict, cross_check, plane_quad,
};
use raylab::embree::EmbreeScene;
use raylab::{CastRay, Plane, Ray, RayKind, Shape, Sphere, Stage, Vec3, builtin, record_rays};

/// The `f64` oracle of the checks and the hard-case tests.
use raylab::check::exact;

fn embree_answer(embree: &EmbreeScene, cast: &CastRay) -> Option<Answer> {
    embree
        .intersect(&cast.ray, cast.t_min, cast.t_max)
        .map(|hit| Answer {
            object: hit.object,
            t: hit.t,
        })
}

#[test]
fn the_library_is_embree_4() {
    let embree = EmbreeScene::new(&[]).expect("Embree device");
    let version = embree.version();
    assert!((40000..50000).contains(&version), "version {version}");
}

/// Embree's answer for `ray`: the object and t, with t within a few ulps of
/// `expected_t`. Embree picks its kernels for the CPU it runs on (SSE, AVX2,
/// AVX-512), and they round differently: the sphere hit at t = 2 is exactly
/// 2 on one machine and 1.9999998 (one ulp below) on another.
fn assert_hit(answer: Option<(usize, f32)>, object: usize, expected_t: f32) {
    let (hit_object, t) = answer.unwrap_or_else(|| panic!("expected a hit on object {object}"));
    assert_eq!(hit_object, object, "object hit");
    let ulps = 4.0 * f32::EPSILON * expected_t;
    assert!(
        (t - expected_t).abs() <= ulps,
        "t = {t}, expected {expected_t} within {ulps}"
    );
}

#[test]
fn spheres_and_quads_answer_in_units_of_the_direction() {
    let embree = EmbreeScene::new(&[
        Primitive::Sphere {
            center: Vec3::new(0.0, 0.0, 5.0),
            radius: 1.0,
        },
        Primitive::Quad([
            Vec3::new(-2.0, -2.0, 10.0),
            Vec3::new(2.0, -2.0, 10.0),
            Vec3::new(2.0, 2.0, 10.0),
            Vec3::new(-2.0, 2.0, 10.0),
        ]),
    ])
    .expect("scene");
    let answer = |ray: &Ray, t_min: f32, t_max: f32| {
        embree
            .intersect(ray, t_min, t_max)
            .map(|hit| (hit.object, hit.t))
    };
    // The direction has length 2, so the front at distance 4 is t = 2.
    let twice = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0));
    assert_hit(answer(&twice, 0.0, f32::INFINITY), 0, 2.0);
    // Past the sphere's front, its back; past the sphere, the quad.
    assert_hit(
        answer(&Ray::new(Vec3::ZERO, Vec3::Z), 4.5, f32::INFINITY),
        0,
        6.0,
    );
    let beside = Ray::new(Vec3::new(1.5, 1.5, 0.0), Vec3::Z);
    assert_hit(answer(&beside, 0.0, f32::INFINITY), 1, 10.0);
    assert_eq!(embree.intersect(&beside, 0.0, 9.0), None);
    let outside = Ray::new(Vec3::new(3.0, 0.0, 0.0), Vec3::Z);
    assert_eq!(embree.intersect(&outside, 0.0, f32::INFINITY), None);
}

/// Records chapter `chapter`'s render, at half its width and height, and
/// cross-checks it (`shift` grows every sphere's radius, to show that real
/// errors are caught). A quarter of the pixels casts about a quarter of
/// the 0.3 to 12 million rays of the full render (`raylab render
/// --stats-json`), of every kind it casts, in a quarter of the time;
/// `raylab crosscheck` checks the full size.
fn cross_check_chapter(chapter: u8, shift: f32) -> crosscheck::Tally {
    let scene = builtin::scene(chapter).expect("built-in scene");
    let settings = raylab::RenderSettings {
        width: scene.render.width / 2,
        height: scene.render.height / 2,
        ..scene.render
    };
    let tracer = Stage::new(&scene, chapter, settings).expect("valid settings");
    let rays = record_rays(&tracer);
    let (mut primitives, quads) = crosscheck::primitives(tracer.shapes(), &scene);
    for primitive in &mut primitives {
        if let Primitive::Sphere { radius, .. } = primitive {
            *radius *= 1.0 + shift;
        }
    }
    let embree = EmbreeScene::new(&primitives).expect("Embree scene");
    let reference = Reference {
        shapes: tracer.shapes(),
        quads: &quads,
    };
    let tally = cross_check(&reference, &rays, |cast| embree_answer(&embree, cast));
    assert_eq!(tally.total(), rays.len() as u64);
    tally
}

fn cross_check_scene(scene: &raylab::Scene, chapter: u8) -> crosscheck::Tally {
    let stage = Stage::new(scene, chapter, scene.render).expect("valid settings");
    let rays = record_rays(&stage);
    let (primitives, quads) = crosscheck::primitives(stage.shapes(), scene);
    let embree = EmbreeScene::new(&primitives).expect("Embree scene");
    let reference = Reference {
        shapes: stage.shapes(),
        quads: &quads,
    };
    let tally = cross_check(&reference, &rays, |cast| embree_answer(&embree, cast));
    assert_eq!(tally.total(), rays.len() as u64);
    tally
}

/// Glass balls resting a few thousandths above a ground sphere of radius
/// 1e5, seen from above: rays refracted out of their bottoms start just above
/// the ground, heading down. A near root that rounds below 0 turns into the
/// far root (t = 1.9e5, the other side of the ground): 43 DISAGREE.
/// Embree makes the same mistake on some of these rays (in f32 the origin's
/// 0.004 above the ground is half an ulp of 1e5), so the check is against
/// the f64 reference: in every disagreement left, ours is the exact answer.
#[test]
fn glass_balls_on_a_huge_ground_sphere_agree_with_f64_where_embree_does_not() {
    let text = r#"
background = [0.55, 0.7, 0.9]
[render]
width = 160
height = 120
[camera]
position = [-0.8, 6.0, -0.8]
look_at = [-0.8, 1.003, 0.0]
fov_degrees = 25.0
[[lights]]
position = [-4.0, 6.0, -3.0]
[[objects]]
name = "ground"
sphere = { center = [0.0, -100000.0, 0.0], radius = 100000.0 }
material = { color = [0.9, 0.9, 0.85], checker = { color = [0.2, 0.2, 0.25], size = 1.0 } }
[[objects]]
name = "glass ball 3e-3 up"
sphere = { center = [-0.8, 1.003, 0.0], radius = 1.0 }
material = { color = [0.95, 0.95, 0.95], transparency = 0.9, ior = 1.5, specular = 0.5 }
[[objects]]
name = "glass ball 1e-3 up"
sphere = { center = [1.3, 0.601, 0.5], radius = 0.6 }
material = { color = [0.95, 0.95, 0.95], transparency = 0.9, ior = 1.5, specular = 0.5 }
"#;
    let scene = raylab::Scene::parse(text, "glass on ground").expect("valid scene");
    let tally = cross_check_scene(&scene, 8);
    println!(
        "rays by kind {:?}, boundary {:?}, disagreements {}",
        tally.by_kind, tally.boundary, tally.disagreements
    );
    assert!(
        tally.by_kind[raylab::RayKind::Refraction.index()] > 10_000,
        "refraction rays: {:?}",
        tally.by_kind
    );
    assert!(tally.disagreements < 40, "{}", tally.disagreements);
    let ground = (glam::DVec3::new(0.0, -1e5, 0.0), 1e5);
    for compared in &tally.worst {
        let ray = compared.cast.ray;
        let exact = exact::sphere_hit(
            ground.0,
            ground.1,
            ray.origin.as_dvec3(),
            ray.dir.as_dvec3(),
            0.0,
            f64::INFINITY,
        )
        .map(|hit| hit.t);
        let ours = compared.ours.map(|answer| (answer.object, answer.t as f64));
        let agrees = match (ours, exact) {
            (Some((0, t)), Some(e)) => (t - e).abs() <= 1e-3 * e.max(1.0),
            _ => false,
        };
        assert!(agrees, "ours {ours:?}, exact {exact:?}: {compared:#?}");
    }
}

#[test]
fn every_chapter_cross_checks_clean() {
    // Chapter 12's built-in scene is implicit surfaces, which Embree has
    // no primitive for: embree_implicit.rs tessellates them instead.
    for chapter in 1..=11 {
        let tally = cross_check_chapter(chapter, 0.0);
        let boundary: u64 = tally.boundary.iter().sum();
        assert!(
            tally.clean(),
            "chapter {chapter}: {} disagreements, worst {:#?}",
            tally.disagreements,
            tally.worst.first()
        );
        // The boundary cases are the rare exception, not a blanket excuse.
        assert!(
            boundary * 10_000 < tally.total(),
            "chapter {chapter}: {boundary} boundary cases of {}",
            tally.total()
        );
        assert!(tally.same_hit > tally.total() / 4, "chapter {chapter}");
        let (median, _) = tally.median_and_max().expect("shared hits");
        assert!(median <= f32::EPSILON, "chapter {chapter}: median {median}");
    }
}

#[test]
fn a_sphere_one_part_in_ten_thousand_too_big_is_caught() {
    let tally = cross_check_chapter(2, 1e-4);
    assert!(!tally.clean());
    assert!(tally.disagreements > 100, "{}", tally.disagreements);
    assert_eq!(tally.worst[0].verdict, Verdict::Disagree);
}

#[test]
fn recorded_rays_do_not_depend_on_the_thread_count() {
    let scene = builtin::scene(8).expect("scene");
    let mut settings = scene.render;
    settings.width = 40;
    settings.height = 30;
    let tracer = Stage::new(&scene, 8, settings).expect("valid settings");
    let record = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| record_rays(&tracer))
    };
    let one = record(1);
    assert_eq!(one, record(3));
    let counts = raylab::render(&scene, 8, &settings, None)
        .expect("renders")
        .rays;
    assert_eq!(one.len() as u64, counts.total());
    assert_eq!(one[0].kind, RayKind::Primary);
}

/// A random scene: a few spheres and planes around the origin.
fn shapes() -> impl Strategy<Value = Vec<Shape>> {
    let coordinate = -4.0f32..4.0;
    let point = (coordinate.clone(), coordinate.clone(), coordinate);
    let sphere = (point.clone(), 0.05f32..2.0)
        .prop_map(|((x, y, z), radius)| Shape::Sphere(Sphere::new(Vec3::new(x, y, z), radius)));
    let normal = (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0)
        .prop_filter("a direction", |(x, y, z)| x.abs() + y.abs() + z.abs() > 0.1);
    let plane = (point, normal).prop_map(|((x, y, z), (a, b, c))| {
        Shape::Plane(Plane::new(Vec3::new(x, y, z), Vec3::new(a, b, c)))
    });
    (
        prop::collection::vec(sphere, 1..5),
        prop::collection::vec(plane, 0..3),
    )
        .prop_map(|(mut spheres, planes)| {
            spheres.extend(planes);
            spheres
        })
}

fn rays() -> impl Strategy<Value = Vec<Ray>> {
    let origin = (-10.0f32..10.0, -10.0f32..10.0, -10.0f32..10.0);
    let dir = (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_filter("a direction", |(x, y, z)| {
        x.abs() + y.abs() + z.abs() > 0.01
    });
    prop::collection::vec(
        (origin, dir, 0.1f32..10.0).prop_map(|((x, y, z), (a, b, c), length)| {
            Ray::new(Vec3::new(x, y, z), Vec3::new(a, b, c) * length)
        }),
        64,
    )
}

proptest! {
    // Failing cases are kept in the .proptest-regressions file beside this
    // one, as before the tests were grouped (proptest's default would use
    // tests/proptest-regressions/, since this folder has a main.rs).
    #![proptest_config(ProptestConfig {
        cases: 256,
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("proptest-regressions"))),
        // The same cases on every run: a test must not pass or fail by the
        // draw (proptest's f32 sampler has a debug assertion that a rare
        // draw trips, as a CI run met).
        rng_seed: proptest::test_runner::RngSeed::Fixed(11),
        ..ProptestConfig::default()
    })]

    /// Random rays against random spheres and planes: the same object (or
    /// both a miss) with `t` within the tolerance, except on a silhouette or
    /// a grazing plane, whose rays must then really be at the boundary.
    #[test]
    fn random_rays_agree_with_embree(shapes in shapes(), rays in rays()) {
        let quads: Vec<Option<PlaneQuad>> = shapes
            .iter()
            .map(|shape| match shape {
                Shape::Plane(plane) => Some(plane_quad(plane, Vec3::ZERO, 1024.0)),
                _ => None,
            })
            .collect();
        let primitives: Vec<Primitive> = shapes
            .iter()
            .zip(&quads)
            .map(|(shape, quad)| match (shape, quad) {
                (Shape::Sphere(sphere), _) => Primitive::Sphere {
                    center: sphere.center(),
                    radius: sphere.radius(),
                },
                (_, Some(quad)) => Primitive::Quad(quad.corners),
                _ => unreachable!("planes have quads"),
            })
            .collect();
        let embree = EmbreeScene::new(&primitives).expect("Embree scene");
        let reference = Reference { shapes: &shapes, quads: &quads };
        for ray in rays {
            let cast = CastRay { kind: RayKind::Primary, ray, t_min: 0.0, t_max: f32::INFINITY };
            let compared = reference.compare(&cast, embree_answer(&embree, &cast));
            prop_assert_ne!(compared.verdict, Verdict::Disagree, "{:?} in {:?}", compared, shapes);
            if let (Some(ours), Some(theirs)) = (compared.ours, compared.theirs) {
                if ours.object == theirs.object && compared.verdict == Verdict::Agree {
                    let tolerance = reference.tolerance(ours.object, &ray, ours.t);
                    prop_assert!((ours.t - theirs.t).abs() <= tolerance);
                }
            }
            if let Verdict::Boundary(Boundary::Silhouette) = compared.verdict {
                let object = compared.ours.or(compared.theirs).map(|hit| hit.object);
                let on_one = shapes.iter().any(|shape| match shape {
                    Shape::Sphere(sphere) => crosscheck::on_silhouette(sphere, &ray),
                    _ => false,
                });
                prop_assert!(object.is_some() && on_one);
            }
        }
    }
}

#[test]
fn crosscheck_command_reports_every_section() {
    let out = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args([
            "crosscheck",
            "--chapter",
            "8",
            "--width",
            "64",
            "--height",
            "48",
        ])
        .args(["--timing-runs", "1"])
        .current_dir(Path::new("."))
        .output()
        .expect("run raylab");
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    for expected in [
        "ours against Embree 4.",
        "rays compared: ",
        " primary, ",
        " refraction)",
        "hit/miss: ",
        "relative difference of t",
        "the largest, against its tolerance",
        "worst rays",
        "ratio ours/Embree ",
        "result: agree",
    ] {
        assert!(text.contains(expected), "missing {expected:?} in\n{text}");
    }
}

#[test]
fn probe_shows_both_answers_and_the_verdict() {
    let out = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(["probe", "--chapter", "8", "--ray", "0,1.5,-6,-0.1,-0.13,1"])
        .output()
        .expect("run raylab");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("ours:   \"glass ball\" (object 1) at t = 4.83"),
        "{text}"
    );
    assert!(
        text.contains("embree: \"glass ball\" (object 1) at t = 4.83"),
        "{text}"
    );
    assert!(text.contains("cross-check: agree"), "{text}");
    // Chapter 1's floor, hit far beyond the quad that stands in for it.
    let out = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(["probe", "--chapter", "1", "--ray", "0,1,0,1,-0.00001,0"])
        .output()
        .expect("run raylab");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("embree: no hit"), "{text}");
    assert!(text.contains("boundary case: beyond the quad"), "{text}");
}

#[test]
fn crosscheck_refuses_more_rays_than_memory_holds() {
    let out = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args([
            "crosscheck",
            "--chapter",
            "8",
            "--width",
            "4000",
            "--height",
            "3000",
        ])
        .output()
        .expect("run raylab");
    let message = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{message}");
    assert!(
        message.contains("4000x3000 at 4 samples per pixel") && message.contains("--samples"),
        "{message}"
    );
}
