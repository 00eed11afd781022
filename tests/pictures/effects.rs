//! Effects on demand: a render simulates only what its scene can show, and
//! what it leaves out changes no pixel.

use raylab::{Ray, RayCounts, RayKind, RayLog, RenderSettings, Scene, Stage, Vec3, nearest_hit};

fn small(scene: &Scene, samples: u32) -> RenderSettings {
    RenderSettings {
        width: 80,
        height: 60,
        samples,
        ..scene.render
    }
}

fn names(rendered: &raylab::Rendered) -> Vec<&'static str> {
    rendered.effects.names()
}

#[test]
fn no_mirror_no_glass_at_chapter_8_is_chapter_5_pixel_for_pixel() {
    // Chapter 5's scene: shiny and matte balls, lights, no reflectivity or
    // transparency anywhere.
    let scene = raylab::builtin::scene(5).expect("built-in scene");
    let settings = small(&scene, 1);
    let at_5 = raylab::render(&scene, 5, &settings, None).expect("renders");
    // Chapter 9 too: no media, Fresnel or absorption without glass.
    let at_9 = raylab::render(&scene, 9, &settings, None).expect("renders");
    assert!(at_5.rgb == at_9.rgb, "the images of stages 5 and 9 differ");
    assert_eq!(at_5.rays, at_9.rays);
    assert_eq!(names(&at_5), names(&at_9));
    let at_8 = raylab::render(&scene, 8, &settings, None).expect("renders");
    assert_eq!(at_8.rays.of(RayKind::Reflection), 0);
    assert_eq!(at_8.rays.of(RayKind::Refraction), 0);
    assert!(at_5.rgb == at_8.rgb, "the images differ");
    assert_eq!(at_5.rays, at_8.rays);
    assert_eq!(names(&at_5), names(&at_8));
    assert!(!names(&at_8).contains(&"reflection"));
    assert!(!names(&at_8).contains(&"refraction"));
    assert!(!names(&at_8).contains(&"antialiasing"));

    // With several samples, chapter 8 is chapter 7 for the same reason.
    let settings = small(&scene, 4);
    let at_7 = raylab::render(&scene, 7, &settings, None).expect("renders");
    let at_8 = raylab::render(&scene, 8, &settings, None).expect("renders");
    assert!(at_7.rgb == at_8.rgb, "the supersampled images differ");
    assert_eq!(at_8.rays.of(RayKind::Primary), 80 * 60 * 4);
    assert_eq!(
        at_8.rays.of(RayKind::Reflection) + at_8.rays.of(RayKind::Refraction),
        0
    );
}

#[test]
fn no_lights_no_shadow_rays_and_no_specular() {
    let mut scene = raylab::builtin::scene(8).expect("built-in scene");
    scene.lights.clear();
    let rendered = raylab::render(&scene, 8, &small(&scene, 1), None).expect("renders");
    assert_eq!(rendered.rays.of(RayKind::Shadow), 0);
    assert!(!names(&rendered).contains(&"shadows"));
    assert!(!names(&rendered).contains(&"phong-specular"));
    // The mirror and the glass still work without lights.
    assert!(rendered.rays.of(RayKind::Reflection) > 0);
    assert!(rendered.rays.of(RayKind::Refraction) > 0);

    // The same scene with its lights casts shadow rays: the count above is
    // zero because there is no light, not because shadows are broken.
    let lit = raylab::builtin::scene(8).expect("built-in scene");
    assert!(
        raylab::render(&lit, 8, &small(&lit, 1), None)
            .expect("renders")
            .rays
            .of(RayKind::Shadow)
            > 0
    );
}

const ONE_MIRROR: &str = r#"
background = [0.5, 0.7, 0.9]
[camera]
position = [0.0, 1.5, -6.0]
look_at = [0.0, 1.0, 0.0]
[render]
width = 80
height = 60
[[lights]]
position = [-4.0, 6.0, -3.0]
[[objects]]
name = "mirror"
sphere = { center = [0.5, 1.0, 1.0], radius = 1.0 }
material = { reflectivity = 0.8, specular = 0.5 }
[[objects]]
name = "matte ball"
sphere = { center = [-1.8, 0.6, 0.0], radius = 0.6 }
material = { color = [0.8, 0.2, 0.1] }
[[objects]]
name = "floor"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
"#;

/// Records the reflection rays cast while one pixel is traced.
#[derive(Default)]
struct ReflectionOrigins(Vec<Vec3>);

impl RayLog for ReflectionOrigins {
    fn cast(&mut self, kind: RayKind, ray: &Ray, _: f32, _: f32) {
        if kind == RayKind::Reflection {
            self.0.push(ray.origin);
        }
    }
}

#[test]
fn reflection_rays_start_only_from_pixels_that_see_the_mirror() {
    let scene = Scene::parse(ONE_MIRROR, "one mirror").expect("valid scene");
    let settings = scene.render;
    let tracer = Stage::new(&scene, 6, settings).expect("valid settings");
    let raylab::Shape::Sphere(mirror) = scene.shapes[0] else {
        panic!("the mirror is a sphere");
    };
    let mut mirror_pixels = 0u64;
    for y in 0..settings.height {
        for x in 0..settings.width {
            let primary = tracer.camera().ray_through(x as f32 + 0.5, y as f32 + 0.5);
            let sees_mirror = nearest_hit(tracer.shapes(), &primary, 0.0, f32::INFINITY)
                .is_some_and(|hit| hit.object == 0);
            let mut log = ReflectionOrigins::default();
            tracer.tracer(Some(&mut log)).pixel(x, y);
            // A ray leaving a convex mirror cannot come back to it, and
            // nothing else reflects: one reflection ray per mirror pixel.
            let expected = usize::from(sees_mirror);
            assert_eq!(log.0.len(), expected, "pixel ({x}, {y})");
            for origin in &log.0 {
                let off_surface = ((*origin - mirror.center()).length() - mirror.radius()).abs();
                assert!(off_surface < 1e-4, "pixel ({x}, {y}): {origin}");
            }
            mirror_pixels += expected as u64;
        }
    }
    assert!(
        mirror_pixels > 200,
        "the mirror covers {mirror_pixels} pixels"
    );
    assert!(mirror_pixels < u64::from(settings.width * settings.height) / 2);
    let rendered = raylab::render(&scene, 6, &settings, None).expect("renders");
    assert_eq!(rendered.rays.of(RayKind::Reflection), mirror_pixels);
    assert_eq!(rendered.rays.of(RayKind::Refraction), 0);
}

/// A camera under a glass surface (a pool seen from below): rays that meet
/// the surface steeper than the critical angle (48.8 degrees for water)
/// cross it, shallower ones are totally reflected. (A glass *ball* never
/// shows this: a ray leaves a sphere at the angle it entered.)
const UNDER_WATER: &str = r#"
background = [0.5, 0.7, 0.9]
[camera]
position = [0.0, -1.0, 0.0]
look_at = [0.0, 1.0, 3.0]
[render]
width = 80
height = 60
[[lights]]
position = [0.0, 6.0, 3.0]
[[objects]]
name = "water surface"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { color = [0.9, 1.0, 1.0], transparency = 0.9, ior = 1.33 }
[[objects]]
name = "pool floor"
plane = { point = [0.0, -3.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = { checker = { color = [0.1, 0.1, 0.3], size = 1.0 } }
"#;

#[test]
fn glass_that_does_not_reflect_still_casts_total_internal_reflection_rays() {
    let scene = Scene::parse(UNDER_WATER, "under water").expect("valid scene");
    assert!(scene.materials().all(|m| m.reflectivity == 0.0));
    let rendered = raylab::render(&scene, 8, &scene.render, None).expect("renders");
    assert!(rendered.rays.of(RayKind::Refraction) > 0);
    assert!(rendered.rays.of(RayKind::Reflection) > 0);
    assert!(names(&rendered).contains(&"reflection"));
    assert!(names(&rendered).contains(&"refraction"));
    assert!(!names(&rendered).contains(&"phong-specular"));
}

#[test]
fn a_glass_ball_alone_never_reflects_totally() {
    let glass_only = ONE_MIRROR.replace(
        "reflectivity = 0.8, specular = 0.5",
        "transparency = 0.9, ior = 1.5",
    );
    let scene = Scene::parse(&glass_only, "glass ball").expect("valid scene");
    let rendered = raylab::render(&scene, 8, &scene.render, None).expect("renders");
    assert!(rendered.rays.of(RayKind::Refraction) > 0);
    assert_eq!(rendered.rays.of(RayKind::Reflection), 0);
}

#[test]
fn recursion_stops_below_the_minimum_contribution() {
    let scene = Scene::parse(ONE_MIRROR, "one mirror").expect("valid scene");
    let with = |min_contribution: f32| {
        let settings = RenderSettings {
            min_contribution,
            ..scene.render
        };
        raylab::render(&scene, 6, &settings, None)
            .expect("renders")
            .rays
    };
    let counts: [RayCounts; 3] = [with(0.0), with(0.8), with(0.81)];
    // The mirror's reflection rays weigh 0.8: cast at thresholds up to 0.8.
    assert!(counts[0].of(RayKind::Reflection) > 0);
    assert_eq!(
        counts[0].of(RayKind::Reflection),
        counts[1].of(RayKind::Reflection)
    );
    assert_eq!(counts[2].of(RayKind::Reflection), 0);
}

#[test]
fn acne_is_counted_where_the_offset_fails_and_only_there() {
    // Chapter 8's glass ball lights its own inside: those shadow rays truly
    // meet the ball again and are not acne. The textbook sphere test, which
    // has no error bound of its own (the stable one rejects most acne by
    // itself, lesson 4), leaves the offset alone to keep the balls clean.
    let scene = raylab::builtin::scene(8).expect("built-in scene");
    let settings = RenderSettings {
        sphere_formula: raylab::scene::SphereFormula::Textbook,
        ..small(&scene, 1)
    };
    let scaled = raylab::render(&scene, 8, &settings, None)
        .expect("renders")
        .rays;
    assert_eq!(scaled.self_shadow_hits, 0);
    assert_eq!(scaled.self_shadowed_pixels, 0);
    let no_offset = RenderSettings {
        ray_offset: raylab::scene::OffsetRule::Fixed,
        fixed_epsilon: 0.0,
        ..settings
    };
    let acne = raylab::render(&scene, 8, &no_offset, None)
        .expect("renders")
        .rays;
    assert!(acne.self_shadowed_pixels > 100, "{acne:?}");
    assert!(acne.self_shadow_hits >= acne.self_shadowed_pixels);
}

/// Each chapter's stage without what the chapter adds is the chapter
/// before, pixel for pixel and ray for ray, on the chapter's own scene.
#[test]
fn a_stage_without_its_chapter_s_effects_is_the_chapter_before() {
    use raylab::effects::Effects;
    for chapter in 2..=raylab::chapters::LAST_CHAPTER {
        let scene = raylab::builtin::scene(chapter).expect("built-in scene");
        let added: Vec<&str> = Effects::for_chapter(chapter)
            .switchable()
            .into_iter()
            .filter(|name| {
                !Effects::for_chapter(chapter - 1)
                    .switchable()
                    .contains(name)
            })
            .collect();
        assert!(
            !added.is_empty(),
            "chapter {chapter} adds nothing to switch off"
        );
        let without = RenderSettings {
            without: raylab::scene::SwitchedOff::parse(added.iter().copied()).expect("names"),
            ..small(&scene, 4)
        };
        let off = raylab::render(&scene, chapter, &without, None).expect("renders");
        let before = raylab::render(&scene, chapter - 1, &small(&scene, 4), None).expect("renders");
        assert!(off.rgb == before.rgb, "chapter {chapter} without {added:?}");
        assert_eq!(off.rays, before.rays, "chapter {chapter} without {added:?}");
        assert_eq!(
            names(&off),
            names(&before),
            "chapter {chapter} without {added:?}"
        );
    }
}

#[test]
fn each_switch_is_off_exactly_when_its_name_is_given() {
    use raylab::scene::{Switch, SwitchedOff};
    for switch in Switch::ALL {
        let off = SwitchedOff::parse([switch.name()]).expect("its own name parses");
        for other in Switch::ALL {
            assert_eq!(
                off.contains(other),
                other == switch,
                "{switch:?} off, {other:?}"
            );
        }
        assert_eq!(off.names(), [switch.name()]);
    }
}

#[test]
fn an_unknown_effect_is_refused_with_the_names_that_exist() {
    let error = raylab::scene::SwitchedOff::parse(["reflections"]).expect_err("no such effect");
    assert!(
        error.contains("`reflections`") && error.contains("nested-media"),
        "{error}"
    );
    let scene = Scene::parse(
        "[camera]\nposition = [0, 1, -5]\nlook_at = [0, 1, 0]\n[render]\nwithout = [\"shadow\"]\n",
        "test",
    );
    assert!(scene.is_err_and(|error| error.to_string().contains("`shadow`")));
}

/// Every effect a stage offers to leave out is left out: the stats no
/// longer name it, and it casts none of its rays, at every chapter (the
/// layers built on it go too: chapter 8's glass casts reflection rays, so
/// without reflection it is gone).
#[test]
fn a_switched_off_effect_casts_none_of_its_rays_at_any_chapter() {
    use raylab::effects::Effects;
    for chapter in 1..=raylab::chapters::LAST_CHAPTER {
        let scene = raylab::builtin::scene(chapter).expect("built-in scene");
        for name in Effects::for_chapter(chapter).switchable() {
            let settings = RenderSettings {
                without: raylab::scene::SwitchedOff::parse([name]).expect("a name"),
                ..small(&scene, 4)
            };
            let off = raylab::render(&scene, chapter, &settings, None).expect("renders");
            let simulated = names(&off);
            let gone: &[&str] = match name {
                "lighting" => &["flat-lighting", "phong-diffuse", "shadows"],
                "phong" => &["phong-diffuse", "phong-specular"],
                other => &[other][..],
            };
            for effect in gone {
                assert!(
                    !simulated.contains(effect),
                    "chapter {chapter} without {name}: {simulated:?}"
                );
            }
            let rays = off.rays;
            let none = match name {
                "lighting" => rays.of(RayKind::Shadow),
                "reflection" => rays.of(RayKind::Reflection),
                "refraction" => rays.of(RayKind::Refraction),
                "antialiasing" => {
                    rays.of(RayKind::Primary) - u64::from(settings.width * settings.height)
                }
                _ => 0,
            };
            assert_eq!(none, 0, "chapter {chapter} without {name}: {rays:?}");
        }
    }
}
