//! Chapter 9, glass done right: Fresnel and Schlick by hand, the media of
//! nested solids with hand-computed directions, Beer-Lambert absorption on
//! a single ray, energy at every boundary, and the bugs the course's
//! checker will plant (each a `Chapters` variant that must show).

use raylab::chapters::{REFERENCE_HEIGHT, REFERENCE_WIDTH};
use raylab::check::planted::{self, Plant, Planted, plant};
use raylab::course::{Chapters, HitPoint};
use raylab::medium::{Crossing, MediumStack};
use raylab::render::Tracer;
use raylab::{CastRay, RayKind, RayRecorder, RenderSettings, Scene, Stage, Vec3, fresnel, schlick};

/// `cos` of the angle whose `sin` is `s`.
fn cos_of_sin(s: f64) -> f64 {
    (1.0 - s * s).sqrt()
}

/// The cosine, as `f32`, of an angle in degrees.
fn cos_deg(degrees: f64) -> f32 {
    degrees.to_radians().cos() as f32
}

// ---------------------------------------------------------------- values

#[test]
fn normal_incidence_air_to_glass_is_four_percent_for_both() {
    // ((1 - 1.5) / (1 + 1.5))^2 = 0.2^2 = 0.04.
    assert_eq!(fresnel(1.0, 1.0, 1.5), 0.04);
    assert_eq!(schlick(1.0, 1.0, 1.5), 0.04);
    // Water: (0.33 / 2.33)^2 = 0.020060.
    assert!((fresnel(1.0, 1.0, 1.33) - 0.020_060).abs() < 1e-6);
}

#[test]
fn past_the_critical_angle_it_is_exactly_one() {
    // Glass to air: critical angle asin(1 / 1.5) = 41.81 degrees.
    for degrees in [41.9, 45.0, 60.0, 89.0, 90.0] {
        let c = cos_deg(degrees);
        assert_eq!(fresnel(c, 1.5, 1.0), 1.0, "{degrees} degrees");
        assert_eq!(schlick(c, 1.5, 1.0), 1.0, "{degrees} degrees");
    }
    // Water to air (48.75 degrees), glass to water (62.46 degrees).
    assert_eq!(fresnel(cos_deg(50.0), 1.33, 1.0), 1.0);
    assert_eq!(fresnel(cos_deg(63.0), 1.5, 1.33), 1.0);
    assert!(fresnel(cos_deg(62.0), 1.5, 1.33) < 1.0);
}

#[test]
fn at_the_critical_angle_it_is_continuous() {
    // cos of the critical angle of glass and air: sqrt(1 - 1 / 2.25).
    let critical = cos_of_sin(1.0 / 1.5) as f32;
    // A few ulps on either side: R has a square-root singularity there, so
    // one ulp of cos_i (6e-8) moves R by about sqrt(6e-8) x a few = 1e-3.
    let mut c = critical;
    for _ in 0..4 {
        c = f32::from_bits(c.to_bits() - 1);
    }
    for _ in 0..9 {
        let r = fresnel(c, 1.5, 1.0);
        assert!((0.99..=1.0).contains(&r), "R({c}) = {r}");
        let s = schlick(c, 1.5, 1.0);
        assert!((0.99..=1.0).contains(&s), "Schlick({c}) = {s}");
        c = f32::from_bits(c.to_bits() + 1);
    }
    // A degree inside the critical angle, R is well below 1.
    assert!(fresnel(cos_deg(40.8), 1.5, 1.0) < 0.5);
}

#[test]
fn grazing_incidence_reflects_everything() {
    for (n1, n2) in [(1.0, 1.5), (1.0, 1.33), (1.33, 1.5), (2.4, 1.0)] {
        assert_eq!(fresnel(0.0, n1, n2), 1.0);
        assert_eq!(schlick(0.0, n1, n2), 1.0);
    }
    // And it gets there smoothly: 0.990 at 89.9 degrees air to glass
    // (by hand: R is about 1 - 4 cos(i) / sqrt(n^2 - 1) near grazing,
    // with cos i = 0.001745, 1 - 0.0062 x 1.6 for s and p averaged).
    let r = fresnel(cos_deg(89.9), 1.0, 1.5);
    assert!((r - 0.989_912).abs() < 1e-5, "{r}");
}

#[test]
fn nan_in_gives_nan_out() {
    assert!(fresnel(f32::NAN, 1.0, 1.5).is_nan());
    assert!(schlick(0.5, f32::NAN, 1.5).is_nan());
    assert!(fresnel(0.5, 1.0, f32::NAN).is_nan());
}

#[test]
fn reflectance_is_the_same_from_either_side_at_matching_angles() {
    // Stokes: light meeting the boundary from side 1 at angle i reflects
    // the same share as light from side 2 at the transmitted angle t.
    for (n1, n2) in [(1.0, 1.33), (1.0, 1.5), (1.0, 2.4), (1.33, 1.5)] {
        for step in 0..=89 {
            let i = f64::from(step).to_radians();
            let sin_t = i.sin() * f64::from(n1) / f64::from(n2);
            let (ci, ct) = (i.cos() as f32, cos_of_sin(sin_t) as f32);
            let from_1 = fresnel(ci, n1, n2);
            let from_2 = fresnel(ct, n2, n1);
            // The two cosines are rounded to f32 separately, and near
            // grazing R is steep in cos i (dR/dcos i reaches hundreds for
            // diamond at 87 degrees): one rounding of the cosine (3e-8)
            // moves R by up to about 1e-5.
            assert!(
                (from_1 - from_2).abs() < 5e-5,
                "n {n1} -> {n2}, {step} degrees: {from_1} vs {from_2}"
            );
        }
    }
}

#[test]
fn reflected_and_transmitted_energy_add_to_one() {
    // The transmitted share, from the transmission amplitudes of the
    // boundary conditions (not from 1 - R): t_s = 2 n1 ci / (n1 ci + n2 ct),
    // t_p = 2 n1 ci / (n2 ci + n1 ct), and T = (n2 ct) / (n1 ci) t^2, the
    // ratio of the beams' power through equal areas of the boundary.
    for (n1, n2) in [
        (1.0f32, 1.33f32),
        (1.0, 1.5),
        (1.0, 2.4),
        (1.5, 1.0),
        (1.5, 1.33),
    ] {
        // The indices fresnel sees: 1.33 as an f32 is 1.33000004, and near
        // the critical angle that difference shows.
        let (n1, n2) = (f64::from(n1), f64::from(n2));
        for step in 0..90 {
            let i = f64::from(step).to_radians();
            let sin_t = i.sin() * n1 / n2;
            if sin_t >= 1.0 {
                assert_eq!(fresnel(i.cos() as f32, n1 as f32, n2 as f32), 1.0);
                continue;
            }
            // The angle fresnel sees: its f32 cosine (near the critical
            // angle R is steep, and the f64 cosine is another angle).
            let ci = f64::from(i.cos() as f32);
            let sin_t = cos_of_sin(ci) * n1 / n2;
            let ct = cos_of_sin(sin_t);
            let t_s = 2.0 * n1 * ci / (n1 * ci + n2 * ct);
            let t_p = 2.0 * n1 * ci / (n2 * ci + n1 * ct);
            let transmitted = (n2 * ct) / (n1 * ci) * 0.5 * (t_s * t_s + t_p * t_p);
            let reflected = f64::from(fresnel(ci as f32, n1 as f32, n2 as f32));
            assert!(
                (reflected + transmitted - 1.0).abs() < 1e-6,
                "n {n1} -> {n2}, {step} degrees: R + T = {}",
                reflected + transmitted
            );
        }
    }
}

#[test]
fn schlick_is_within_its_known_error_of_exact() {
    // The largest gap over a sweep of 0 to 90 degrees in steps of 0.01,
    // measured in f64 (see the lesson's plot): about 0.060 for water, 0.036
    // for glass and 0.074 for diamond, near grazing entering the denser
    // medium and just inside the critical angle leaving it. Bounds: those,
    // rounded up.
    for (n, bound) in [(1.33f32, 0.061f32), (1.5, 0.037), (2.4, 0.075)] {
        for (n1, n2) in [(1.0, n), (n, 1.0)] {
            let mut worst = 0.0f32;
            for step in 0..=9000 {
                let c = cos_deg(f64::from(step) / 100.0);
                worst = worst.max((schlick(c, n1, n2) - fresnel(c, n1, n2)).abs());
            }
            assert!(worst < bound, "n {n1} -> {n2}: {worst}");
            assert!(
                worst > bound - 0.01,
                "n {n1} -> {n2}: {worst}, bound too loose"
            );
        }
        // Up to 40 degrees entering, Schlick is within 0.006 (0.0034 for
        // water, 0.0051 for glass, 0.0048 for diamond).
        for step in 0..=40 {
            let c = cos_deg(f64::from(step));
            assert!((schlick(c, 1.0, n) - fresnel(c, 1.0, n)).abs() < 6e-3);
        }
    }
}

// ---------------------------------------------------------- nested media

/// Three nested half-spaces under a camera looking down at 45 degrees:
/// glass (y < 0), water inside it (y < -1), air inside the water (y < -2).
/// No reflection (`fresnel = "none"`, no reflectivity): one refraction ray
/// per boundary.
const LAYERS: &str = r#"
background = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, 0.0]
look_at = [1.0, 0.0, 0.0]
[render]
width = 1
height = 1
max_depth = 8
min_contribution = 0.0
[[objects]]
name = "glass"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.5 }
[[objects]]
name = "water"
plane = { point = [0.0, -1.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.33 }
[[objects]]
name = "bubble"
plane = { point = [0.0, -2.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.0 }
"#;

/// Every ray the one pixel of `scene` casts at stage 9 with chapters `C`,
/// and the pixel's linear colour.
fn cast<C: Plant>(scene: &Scene) -> (Vec<CastRay>, Vec3) {
    planted::with::<C, _>(|| {
        let stage =
            Stage::<Planted>::with_chapters(scene, 9, scene.render).expect("valid settings");
        let mut recorder = RayRecorder::default();
        let color = stage.tracer(Some(&mut recorder)).pixel(0, 0);
        (recorder.rays, color)
    })
}

/// The `sin` of the angle between `dir` and the vertical.
fn sin_from_vertical(dir: Vec3) -> f32 {
    let d = dir.normalize();
    (d.x * d.x + d.z * d.z).sqrt()
}

#[test]
fn water_in_glass_and_a_bubble_in_water_bend_by_the_ratio_of_their_media() {
    let scene = Scene::parse(LAYERS, "layers").expect("valid scene");
    let (rays, _) = cast::<raylab::Reference>(&scene);
    let kinds: Vec<RayKind> = rays.iter().map(|r| r.kind).collect();
    assert_eq!(
        kinds,
        [
            RayKind::Primary,
            RayKind::Refraction,
            RayKind::Refraction,
            RayKind::Refraction
        ]
    );
    // The camera looks down at 45 degrees.
    assert!((sin_from_vertical(rays[0].ray.dir) - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6);
    // Air to glass: sin t = sin 45 / 1.5 = 0.471405.
    // Glass to water: sin t = 1.5 x 0.471405 / 1.33 = 0.531659 (with air
    // assumed outside, 0.471405 / 1.33 = 0.354440 instead).
    // Water to the bubble's air: sin t = 1.33 x 0.531659 / 1.0 = 0.707107,
    // back to 45 degrees (with air assumed outside, no bend at all).
    let expected = [0.471_404_5, 0.531_659_1, std::f32::consts::FRAC_1_SQRT_2];
    for (ray, sin) in rays[1..].iter().zip(expected) {
        let got = sin_from_vertical(ray.ray.dir);
        assert!((got - sin).abs() < 1e-5, "sin {got}, expected {sin}");
        assert!(ray.ray.dir.y < 0.0, "still going down: {}", ray.ray.dir);
    }
}

#[test]
fn leaving_the_inner_solid_returns_to_the_outer_one() {
    // The water ball inside the glass ball, concentric: a ray along a
    // diameter meets glass, water, water, glass, and the media on each
    // side of every crossing are the hand-written ones.
    let scene = Scene::parse(
        r#"
background = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 0.0, -5.0]
look_at = [0.0, 0.0, 0.0]
[render]
width = 1
height = 1
max_depth = 8
min_contribution = 0.0
[[objects]]
name = "glass"
sphere = { center = [0.0, 0.0, 0.0], radius = 2.0 }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.5 }
[[objects]]
name = "water"
sphere = { center = [0.0, 0.0, 0.0], radius = 1.0 }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.33 }
"#,
        "water in glass",
    )
    .expect("valid scene");
    let (rays, color) = cast::<RecordCrossings>(&scene);
    // Head-on, fresnel "none": four refraction rays along the axis, and the
    // background comes through untouched.
    assert_eq!(rays.len(), 5);
    assert_eq!(color, Vec3::ONE);
    let seen = CROSSINGS.with(|c| c.borrow().clone());
    assert_eq!(
        seen,
        [
            (true, 1.0, 1.5, 0, 1),
            (true, 1.5, 1.33, 1, 2),
            (false, 1.33, 1.5, 2, 1),
            (false, 1.5, 1.0, 1, 0),
        ]
    );
}

/// (entering, n1, n2, solids before, solids beyond) of one crossing.
type Seen = (bool, f32, f32, usize, usize);

thread_local! {
    /// (entering, n1, n2, solids before, solids beyond) of every crossing.
    static CROSSINGS: std::cell::RefCell<Vec<Seen>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// The reference, recording each crossing it computes.
struct RecordCrossings;
plant! {
    RecordCrossings;
    fn crossing(media: &MediumStack, point: &HitPoint) -> Crossing {
        let crossing = raylab::chapters::ch09_glass::crossing(media, point);
        CROSSINGS.with(|c| {
            c.borrow_mut().push((
                crossing.entering,
                crossing.n1,
                crossing.n2,
                crossing.before.len(),
                crossing.beyond.len(),
            ))
        });
        crossing
    }
}

// ------------------------------------------------------------ absorption

#[test]
fn a_slab_of_thickness_d_transmits_exp_minus_a_d() {
    // A slab 2 thick (between y = 0 and y = -2) absorbing a = (0.5, 0.1, 0)
    // per unit, all indices 1 so the ray goes straight down, under a white
    // sky: the pixel is exp(-a d) = (exp(-1), exp(-0.2), 1).
    let scene = Scene::parse(
        r#"
background = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 1.0, 0.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
[render]
width = 1
height = 1
min_contribution = 0.0
[[objects]]
name = "slab top: the absorbing half-space y < 0"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.0, absorption = [0.5, 0.1, 0.0] }
[[objects]]
name = "slab bottom: clear below y = -2"
plane = { point = [0.0, -2.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.0 }
"#,
        "slab",
    )
    .expect("valid scene");
    let (rays, color) = cast::<raylab::Reference>(&scene);
    assert_eq!(rays.len(), 3, "{rays:?}");
    // The ray inside starts a hair below y = 0 (chapter 4's offset: a few
    // ulps of the point), so it crosses 2 minus that hair.
    let inside = rays[1].ray;
    assert_eq!(inside.dir.normalize(), -Vec3::Y);
    let thickness = 2.0 + inside.origin.y;
    assert!((thickness - 2.0).abs() < 1e-6, "{thickness}");
    let a = Vec3::new(0.5, 0.1, 0.0);
    // Exact for the distance the ray crossed: the same expf, the same bits.
    let expected = Vec3::new(
        libm::expf(-a.x * thickness),
        libm::expf(-a.y * thickness),
        1.0,
    );
    assert_eq!(color, expected);
    // And exp(-a d) for d = 2 within that hair (relative 1e-6).
    let ideal = Vec3::new((-1.0f32).exp(), (-0.2f32).exp(), 1.0);
    assert!(
        (color - ideal).abs().max_element() < 1e-6,
        "{color} vs {ideal}"
    );
}

#[test]
fn thicker_glass_is_darker() {
    // Beer-Lambert per channel, multiplicative over distance.
    let a = Vec3::new(0.2, 0.5, 1.0);
    let one = raylab::chapters::ch09_glass::transmittance(a, 1.0);
    let two = raylab::chapters::ch09_glass::transmittance(a, 2.0);
    assert!(((one * one) - two).abs().max_element() < 1e-6);
    assert!(two.cmplt(one).all(), "{two} vs {one}");
}

// ---------------------------------------------------------------- energy

/// A white furnace: a clear glass ball holding a water ball holding an air
/// bubble, under a uniformly white sky, no lights, no local light. Every
/// boundary only moves light between reflection and transmission, so every
/// pixel must come out white.
///
/// The three are concentric: then `n r sin(angle)` is the same at every
/// surface a ray meets, so a ray that came in can always get out, and
/// after a few dozen crossings almost nothing is left inside. Off-centre,
/// total internal reflection can trap a ray in the glass shell for
/// hundreds of bounces (a whispering gallery), and a finite depth loses
/// what is still inside (5% in one pixel with the water moved by 0.1).
const FURNACE: &str = r#"
background = [1.0, 1.0, 1.0]
ambient_light = [0.0, 0.0, 0.0]
[camera]
position = [0.0, 0.0, -4.0]
look_at = [0.0, 0.0, 0.0]
[render]
width = 20
height = 15
max_depth = 64
# Every ray down to a millionth of the pixel: 0 would cast all 2^64 paths.
min_contribution = 1e-6
[[objects]]
name = "glass"
sphere = { center = [0.0, 0.0, 0.0], radius = 1.0 }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.5, fresnel = "exact" }
[[objects]]
name = "water"
sphere = { center = [0.0, 0.0, 0.0], radius = 0.6 }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.33, fresnel = "exact" }
[[objects]]
name = "bubble"
sphere = { center = [0.0, 0.0, 0.0], radius = 0.3 }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.0, fresnel = "exact" }
"#;

#[test]
fn a_white_furnace_stays_white_reflection_plus_transmission_is_one() {
    for model in ["exact", "schlick"] {
        let text = FURNACE.replace("\"exact\"", &format!("\"{model}\""));
        let scene = Scene::parse(&text, "furnace").expect("valid scene");
        let stage = Stage::new(&scene, 9, scene.render).expect("valid settings");
        let mut tracer = stage.tracer(None);
        let mut worst = 0.0f32;
        for y in 0..scene.render.height {
            for x in 0..scene.render.width {
                worst = worst.max((tracer.pixel(x, y) - Vec3::ONE).abs().max_element());
            }
        }
        // What is lost is the rays skipped below a millionth of the pixel
        // each (a pixel skips a few hundred: 1e-4 measured) and anything
        // still bouncing after 64 crossings: 1e-3 is a quarter of one
        // 8-bit code (1/255 = 4e-3).
        assert!(worst < 1e-3, "{model}: a pixel is {worst} away from white");
        assert!(
            tracer.counts().of(RayKind::Reflection) > 0
                && tracer.counts().of(RayKind::Refraction) > 0
        );
    }
}

// --------------------------------------------------- chapter 8 unchanged

#[test]
fn chapter_8_scene_at_stage_9_is_chapter_8_pixel_for_pixel() {
    // fresnel = "none" is chapter 8's constants, and with no solid inside
    // another, air is outside each: chapter 9 draws what chapter 8 drew.
    let scene = raylab::builtin::scene(8).expect("built-in scene");
    let settings = RenderSettings {
        width: REFERENCE_WIDTH,
        height: REFERENCE_HEIGHT,
        ..scene.render
    };
    let at_8 = raylab::render(&scene, 8, &settings, None).expect("renders");
    let at_9 = raylab::render(&scene, 9, &settings, None).expect("renders");
    assert!(at_8.rgb == at_9.rgb, "the images differ");
    assert_eq!(at_8.rays, at_9.rays);
    let names = at_9.effects.names();
    assert!(names.contains(&"nested-media"));
    assert!(!names.contains(&"fresnel"));
    assert!(!names.contains(&"absorption"));
}

#[test]
fn effects_name_fresnel_and_absorption_only_where_a_transparent_material_has_them() {
    let scene = raylab::builtin::scene(9).expect("built-in scene");
    let settings = RenderSettings {
        width: 16,
        height: 12,
        ..scene.render
    };
    let rendered = raylab::render(&scene, 9, &settings, None).expect("renders");
    let names = rendered.effects.names();
    for effect in ["refraction", "nested-media", "fresnel", "absorption"] {
        assert!(names.contains(&effect), "{effect} missing from {names:?}");
    }
    // Fresnel and absorption on an opaque material are no work at all.
    let mut opaque = scene.clone();
    for material in opaque.materials_mut() {
        material.transparency = 0.0;
    }
    let names = raylab::render(&opaque, 9, &settings, None)
        .expect("renders")
        .effects
        .names();
    for effect in ["refraction", "nested-media", "fresnel", "absorption"] {
        assert!(!names.contains(&effect), "{effect} in {names:?}");
    }
}

#[test]
fn scene_files_refuse_bad_fresnel_and_absorption_with_clear_errors() {
    let with = |material: &str| {
        Scene::parse(
            &format!(
                "[camera]\nposition = [0.0, 0.0, -5.0]\nlook_at = [0.0, 0.0, 0.0]\n\
                 [[objects]]\nsphere = {{ center = [0.0, 0.0, 0.0], radius = 1.0 }}\n\
                 material = {{ {material} }}\n"
            ),
            "test",
        )
        .map_err(|e| e.to_string())
    };
    assert!(with("fresnel = \"exact\", absorption = [0.1, 0.2, 0.3]").is_ok());
    let message = with("fresnel = \"fast\"").unwrap_err();
    assert!(
        message.contains("schlick") && message.contains("exact"),
        "{message}"
    );
    let message = with("absorption = [-0.1, 0.0, 0.0]").unwrap_err();
    assert!(message.contains("material.absorption"), "{message}");
    assert!(message.contains("between 0"), "{message}");
    let message = with("absorption = [1e7, 0.0, 0.0]").unwrap_err();
    assert!(message.contains("material.absorption"), "{message}");
    let message = with("absorption = [0.1, 0.2]").unwrap_err();
    assert!(message.contains("three"), "{message}");
}

// ------------------------------------------- the bug gallery of chapter 9

fn image<C: Plant>(scene: &Scene) -> Vec<u8> {
    planted::with::<C, _>(|| {
        let settings = RenderSettings {
            width: REFERENCE_WIDTH,
            height: REFERENCE_HEIGHT,
            ..scene.render
        };
        raylab::render_with::<Planted>(scene, 9, &settings, None)
            .expect("valid settings")
            .rgb
    })
}

fn changes_chapter_9<C: Plant>(what: &str) {
    let scene = raylab::builtin::scene(9).expect("built-in scene");
    assert!(
        image::<C>(&scene) != image::<raylab::Reference>(&scene),
        "{what} left chapter 9's image unchanged"
    );
}

/// Bug: Schlick with n1 and n2 swapped. R0 is symmetric, but the choice of
/// cosine is not: entering glass it takes the transmitted angle of a ray
/// *leaving* glass, and finds total internal reflection past 41.8 degrees.
struct SchlickSwapped;
plant! {
    SchlickSwapped;
    fn schlick(cos_i: f32, n1: f32, n2: f32) -> f32 {
        raylab::schlick(cos_i, n2, n1)
    }
}

/// Bug: Schlick leaving a denser medium with `cos t = sqrt(1 - sin^2 t)`
/// and no test for total internal reflection: NaN past the critical angle.
struct SchlickNoTir;
plant! {
    SchlickNoTir;
    fn schlick(cos_i: f32, n1: f32, n2: f32) -> f32 {
        let r0 = ((n1 - n2) / (n1 + n2)).powi(2);
        let c = if n1 <= n2 {
            cos_i
        } else {
            let sin2_t = (n1 / n2).powi(2) * (1.0 - cos_i * cos_i);
            (1.0 - sin2_t).sqrt()
        };
        r0 + (1.0 - r0) * (1.0 - c).powi(5)
    }
}

/// Bug: air assumed outside every solid (chapter 8's rule kept): water in
/// glass is crossed with 1 / 1.33 instead of 1.5 / 1.33.
struct AirOutside;
plant! {
    AirOutside;
    fn crossing(media: &MediumStack, point: &HitPoint) -> Crossing {
        let right = raylab::chapters::ch09_glass::crossing(media, point);
        let ior = point.material.ior;
        let (n1, n2) = if right.entering {
            (1.0, ior)
        } else {
            (ior, 1.0)
        };
        Crossing { n1, n2, ..right }
    }
}

#[test]
fn bug_schlick_with_n1_and_n2_swapped() {
    // By hand, air to glass at 60 degrees: 0.04 + 0.96 x 0.5^5 = 0.07.
    let c = 0.5;
    assert!((schlick(c, 1.0, 1.5) - 0.07).abs() < 1e-6);
    assert_eq!(SchlickSwapped::schlick(c, 1.0, 1.5), 1.0);
    changes_chapter_9::<SchlickSwapped>("Schlick with n1 and n2 swapped");
}

#[test]
fn bug_cos_of_the_transmitted_angle_used_under_total_internal_reflection() {
    // Glass to air at 60 degrees is past the critical angle: R = 1.
    assert_eq!(schlick(0.5, 1.5, 1.0), 1.0);
    let buggy = SchlickNoTir::schlick(0.5, 1.5, 1.0);
    assert!(buggy.is_nan(), "{buggy}");
    // Below the critical angle the bug is invisible: same formula.
    let c = cos_deg(30.0);
    assert!((SchlickNoTir::schlick(c, 1.5, 1.0) - schlick(c, 1.5, 1.0)).abs() < 1e-5);
}

#[test]
fn bug_air_assumed_outside_every_solid() {
    let scene = Scene::parse(LAYERS, "layers").expect("valid scene");
    let (rays, _) = cast::<AirOutside>(&scene);
    // Glass to water bends as if from air: sin t = 0.471405 / 1.33.
    let got = sin_from_vertical(rays[2].ray.dir);
    assert!((got - 0.354_439_5).abs() < 1e-5, "{got}");
    changes_chapter_9::<AirOutside>("air assumed outside every solid");
}

// --------------------------- every chapter 9 function draws in its image

struct NoFresnel;
plant! {
    NoFresnel;
    fn fresnel(_cos_i: f32, _n1: f32, _n2: f32) -> f32 {
        0.0
    }
}

struct NoSchlick;
plant! {
    NoSchlick;
    fn schlick(_cos_i: f32, _n1: f32, _n2: f32) -> f32 {
        0.0
    }
}

struct Clear;
plant! {
    Clear;
    fn transmittance(_absorption: Vec3, _distance: f32) -> Vec3 {
        Vec3::ONE
    }
}

struct Chapter8Glass;
plant! {
    Chapter8Glass;
    fn shade_dielectric(
        tracer: &mut Tracer<Planted>,
        point: &HitPoint,
        depth: u32,
        weight: f32,
    ) -> Vec3 {
        Planted::shade_glass(tracer, point, depth, weight)
    }
}

#[test]
fn chapter_9_draws_with_each_of_its_functions() {
    changes_chapter_9::<NoFresnel>("fresnel");
    changes_chapter_9::<NoSchlick>("schlick");
    changes_chapter_9::<Clear>("transmittance");
    changes_chapter_9::<AirOutside>("crossing");
    changes_chapter_9::<Chapter8Glass>("shade_dielectric");
}

// ------------------------------------------------------- the lesson's plot

#[test]
fn schlick_plot() {
    // `RAYLAB_BLESS=1 cargo test --lib schlick_plot` rewrites it.
    let svg = raylab::plots::schlick_error_svg().expect("plot");
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/images/schlick-error.svg");
    if std::env::var_os("RAYLAB_BLESS").is_some() {
        std::fs::write(&path, &svg).expect("write the plot");
    } else {
        let checked_in = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("{}: {e}; run with RAYLAB_BLESS=1", path.display()));
        assert!(
            checked_in == svg,
            "{} is stale; run with RAYLAB_BLESS=1",
            path.display()
        );
    }
    // The curves it draws: Schlick's largest gap for glass, entering.
    let worst = raylab::plots::schlick_error_curve(1.0, 1.5)
        .into_iter()
        .map(|(_, error)| error.abs())
        .fold(0.0, f64::max);
    assert!((0.03..0.037).contains(&worst), "{worst}");
}

/// The lesson's figures for Schlick's gap, entering water, glass and
/// diamond: within 0.002 of exact Fresnel up to 35 degrees (water) and 32
/// (glass, diamond), and 0.0034, 0.0051 and 0.0047 at 40 degrees.
#[test]
fn schlick_gaps() {
    let gap = |degrees: f32, n2: f32| {
        let cos = degrees.to_radians().cos();
        (raylab::Reference::fresnel(cos, 1.0, n2) - raylab::Reference::schlick(cos, 1.0, n2)).abs()
    };
    for (n2, within_to, at_40) in [
        (1.33, 35.0, 0.0034),
        (1.5, 32.0, 0.0051),
        (2.42, 32.0, 0.0047),
    ] {
        assert!(
            gap(within_to, n2) <= 0.002,
            "n2 = {n2}: {}",
            gap(within_to, n2)
        );
        assert!(gap(within_to + 3.0, n2) > 0.002, "n2 = {n2}");
        assert!(
            (gap(40.0, n2) - at_40).abs() < 0.00005,
            "n2 = {n2}: {}",
            gap(40.0, n2)
        );
    }
}

/// Asserts that `raylab check` fails chapter 9 of the chapters `C` on the
/// case named `case` (the bug gallery of the course, as for chapters 1-8 in
/// tests/course/check.rs).
fn caught_by_check<C: Plant>(case: &str) {
    planted::with::<C, _>(|| {
        let options = raylab::check::CheckOptions {
            failures_dir: std::env::temp_dir().join("raylab-chapter-9-tests"),
            write_images: false,
            forbid_answer_key: false,
            fresh: None,
            ..Default::default()
        };
        let verdict = raylab::check::check_chapter::<Planted>(9, &options);
        let text = verdict.text();
        assert_eq!(verdict.status, raylab::check::Status::Fail, "{text}");
        assert_eq!(verdict.failing_case(), Some(case), "{text}");
    })
}

#[test]
fn check_names_each_chapter_9_bug() {
    caught_by_check::<SchlickSwapped>("schlick-leaving-glass");
    caught_by_check::<SchlickNoTir>("schlick-past-the-critical-angle");
    caught_by_check::<AirOutside>("dielectric-nested-balls");
}
