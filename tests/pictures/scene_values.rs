//! Scene values at the edges of `f32`: each one loads and renders right, or
//! is refused with a message that names the field and the real problem
//! (no wrong answer given as right).

use raylab::{RenderSettings, Scene};

/// A floor seen from above, lit by one light straight over it.
fn scene(camera: &str, light: &str) -> String {
    format!(
        r#"
[camera]
{camera}

[[lights]]
{light}

[[objects]]
name = "floor"
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }}
material = {{ ambient = 0.1, diffuse = 0.9 }}
"#
    )
}

const CAMERA: &str = "position = [0.0, 3.0, -5.0]\nlook_at = [0.0, 0.0, 0.0]";
const LIGHT: &str = "position = [0.0, 5.0, 0.0]";

fn refused(text: &str) -> String {
    match Scene::parse(text, "test scene") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(error) => error.to_string(),
    }
}

fn assert_names(message: &str, needles: &[&str]) {
    for needle in needles {
        assert!(message.contains(needle), "`{needle}` not in: {message}");
    }
}

fn pixels(text: &str) -> Vec<u8> {
    let scene = Scene::parse(text, "test scene").expect("valid scene");
    let settings = RenderSettings {
        width: 8,
        height: 6,
        samples: 1,
        ..scene.render
    };
    raylab::render(&scene, 5, &settings, None)
        .expect("renders")
        .rgb
}

#[test]
fn a_light_beyond_the_coordinate_limit_is_refused_and_one_within_it_shines() {
    // At y = 2e19 the squared distance to the floor (4e38) overflows f32 and
    // the light would add nothing, silently.
    let message = refused(&scene(CAMERA, "position = [0.0, 2e19, 0.0]"));
    assert_names(&message, &["light 1: position", "2e19", "at most 1e18"]);
    // At the limit, the light is far but lights the floor: brighter than no
    // light at all, everywhere the floor is seen.
    let lit = pixels(&scene(CAMERA, "position = [0.0, 1e18, 0.0]"));
    let dark = pixels(&scene(CAMERA, "position = [0.0, -5.0, 0.0]"));
    assert!(lit.iter().zip(&dark).any(|(l, d)| l > d));
    assert!(lit.iter().zip(&dark).all(|(l, d)| l >= d));
}

#[test]
fn shapes_beyond_the_coordinate_limit_are_refused() {
    let far_ball = format!(
        "{}\n[[objects]]\nname = \"moon\"\nsphere = {{ center = [0.0, 0.0, 3e18], radius = 1.0 }}\n",
        scene(CAMERA, LIGHT)
    );
    assert_names(
        &refused(&far_ball),
        &["object 2 (\"moon\"): sphere.center", "3e18", "within 1e6"],
    );
    let huge_ball = format!(
        "{}\n[[objects]]\nsphere = {{ center = [0.0, 0.0, 0.0], radius = 1e30 }}\n",
        scene(CAMERA, LIGHT)
    );
    assert_names(
        &refused(&huge_ball),
        &["object 2: sphere.radius", "1e30", "at most 1e6"],
    );
}

#[test]
fn a_tiny_up_vector_is_a_direction_like_any_other() {
    // |up|^2 = 1e-46 underflows to zero in f32: normalising it plainly gave
    // NaN or infinity, and a distorted image.
    let unit = pixels(&scene(&format!("{CAMERA}\nup = [0.0, 1.0, 0.0]"), LIGHT));
    let tiny = pixels(&scene(&format!("{CAMERA}\nup = [0.0, 1e-23, 0.0]"), LIGHT));
    assert_eq!(tiny, unit);
    let huge = pixels(&scene(&format!("{CAMERA}\nup = [0.0, 1e30, 0.0]"), LIGHT));
    assert_eq!(huge, unit);
}

#[test]
fn a_degenerate_up_or_view_names_the_problem() {
    let zero_up = refused(&scene(&format!("{CAMERA}\nup = [0.0, 0.0, 0.0]"), LIGHT));
    assert_names(&zero_up, &["camera.up", "non-zero"]);
    let parallel = refused(&scene(&format!("{CAMERA}\nup = [0.0, 3.0, -5.0]"), LIGHT));
    assert_names(&parallel, &["camera.up", "parallel"]);
    let same = refused(&scene(
        "position = [1.0, 2.0, 3.0]\nlook_at = [1.0, 2.0, 3.0]",
        LIGHT,
    ));
    assert_names(&same, &["camera.look_at", "same point as camera.position"]);
}

#[test]
fn a_far_camera_is_told_its_distance_not_that_look_at_equals_position() {
    // 3.4e38 apart: the difference overflows f32, and the old check called
    // that "look_at must differ from position".
    let message = refused(&scene(
        "position = [0.0, 0.0, -1.7e38]\nlook_at = [0.0, 0.0, 1.7e38]",
        LIGHT,
    ));
    assert_names(&message, &["camera.position", "1.7e38", "at most 1e18"]);
    assert!(!message.contains("must differ"), "{message}");
}

#[test]
fn vectors_need_exactly_three_numbers() {
    let junk = refused(&scene(
        "position = [0.0, 0.0, -5.0, \"junk\"]\nlook_at = [0.0, 0.0, 0.0]",
        LIGHT,
    ));
    assert_names(&junk, &["camera.position", "4 elements", "[x, y, z]"]);
    let four = refused(&scene(CAMERA, "position = [0.0, 5.0, 0.0, 1.0]"));
    assert_names(&four, &["lights[0].position", "4 elements"]);
    let two = refused(&scene(CAMERA, "position = [0.0, 5.0]"));
    assert_names(&two, &["lights[0].position", "2 numbers"]);
    let word = refused(&scene(CAMERA, "position = [0.0, \"up\", 0.0]"));
    assert_names(&word, &["lights[0].position", "invalid type"]);
    let colour = refused(&scene(
        CAMERA,
        "position = [0.0, 5.0, 0.0]\ncolor = [1, 1, 1, 1]",
    ));
    assert_names(&colour, &["lights[0].color", "4 elements"]);
    // Integers are numbers too.
    Scene::parse(&scene(CAMERA, "position = [0, 5, 0]"), "test scene").expect("integers");
}

#[test]
fn numbers_beyond_f32_are_refused_as_written_not_as_inf() {
    let far = refused(&scene(CAMERA, "position = [0.0, 1e39, 0.0]"));
    assert_names(&far, &["lights[0].position", "y: 1e39 is too large"]);
    assert!(!far.contains("inf"), "{far}");
    let bright = refused(&scene(
        CAMERA,
        "position = [0.0, 5.0, 0.0]\nintensity = -1e39",
    ));
    assert_names(&bright, &["lights[0].intensity", "-1e39 is too large"]);
    let radius = format!(
        "{}\n[[objects]]\nsphere = {{ center = [0.0, 0.0, 0.0], radius = 1e39 }}\n",
        scene(CAMERA, LIGHT)
    );
    assert_names(
        &refused(&radius),
        &["objects[1].sphere.radius", "1e39 is too large"],
    );
    // A number that f32 rounds to zero would make a zero radius out of a
    // positive one.
    let tiny = format!(
        "{}\n[[objects]]\nsphere = {{ center = [0.0, 0.0, 0.0], radius = 1e-50 }}\n",
        scene(CAMERA, LIGHT)
    );
    assert_names(
        &refused(&tiny),
        &["objects[1].sphere.radius", "1e-50 is too small"],
    );
    let epsilon = format!("{}\n[render]\nfixed_epsilon = 1e40\n", scene(CAMERA, LIGHT));
    assert_names(
        &refused(&epsilon),
        &["render.fixed_epsilon", "1e40 is too large"],
    );
    let infinite = refused(&scene(&format!("{CAMERA}\nfov_degrees = inf"), LIGHT));
    assert_names(
        &infinite,
        &["camera.fov_degrees", "inf is not a finite number"],
    );
}

/// `Scene::load`, the library's own reader, takes the same guard as the
/// command line: a device or a FIFO is refused at once, never read.
#[test]
fn scene_load_reads_only_regular_files() {
    let error = raylab::Scene::load(std::path::Path::new("/dev/zero")).expect_err("a device");
    assert!(error.to_string().contains("/dev/zero"), "{error}");
    let dir = tempfile::tempdir().expect("temp dir");
    let fifo = dir.path().join("scene.toml");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    let error = raylab::Scene::load(&fifo).expect_err("a FIFO");
    assert!(error.to_string().contains("scene.toml"), "{error}");
}

/// A generated model in a scene obeys the limit of a loaded one
/// (`raylab::mesh::MAX_MESH_TRIANGLES`), not the larger one of
/// `raylab mesh`, which writes files for other tools too.
#[test]
fn a_generated_model_has_the_triangle_limit_of_a_loaded_one() {
    let with_model = |count: &str| {
        format!(
            "{}\n[[objects]]\nname = \"model\"\nmesh = {{ generated = {count} }}\n\
             material = {{ diffuse = 0.5 }}\n",
            scene(CAMERA, LIGHT)
        )
    };
    let max = raylab::mesh::MAX_MESH_TRIANGLES;
    for count in [0, max as u64 + 1, 16_000_000, i64::MAX as u64] {
        let message = refused(&with_model(&count.to_string()));
        assert_names(
            &message,
            &[
                "object 2 (\"model\")",
                &format!("mesh.generated = {count}"),
                &format!("1 to {max} triangles"),
            ],
        );
    }
    let scene = Scene::parse(&with_model("100"), "test scene").expect("valid scene");
    assert!(scene.shapes.len() > 100);
}

#[test]
fn an_empty_obj_path_is_named_as_such() {
    let text = format!(
        "{}\n[[objects]]\nname = \"model\"\nmesh = {{ obj = \"\" }}\n\
         material = {{ diffuse = 0.5 }}\n",
        scene(CAMERA, LIGHT)
    );
    let message = refused(&text);
    assert_names(&message, &["object 2 (\"model\")", "mesh.obj is empty"]);
}

/// An implicit surface's tree (chapter 12): a misspelt node, a missing or
/// extra field, a negative radius, a smooth union of one shape, a tree too
/// deep and a march setting out of range are each refused, naming the
/// object, the field and the problem; a valid tree loads and renders.
#[test]
fn implicit_trees_are_refused_with_the_node_and_the_field_named() {
    let with = |object: &str| format!("{}\n[[objects]]\n{object}\n", scene(CAMERA, LIGHT));
    let sphere = "{ sphere = { center = [0, 1, 0], radius = 1 } }";
    for (object, needles) in [
        (
            "implicit = { sphre = { center = [0, 1, 0], radius = 1 } }".to_string(),
            &["objects[1].implicit", "unknown variant `sphre`", "`sphere`"][..],
        ),
        (
            "implicit = { sphere = { center = [0, 1, 0] } }".into(),
            &["objects[1].implicit.sphere", "missing field `radius`"],
        ),
        (
            "implicit = { torus = { center = [0, 1, 0], major = 1, minor = 0.2, tube = 3 } }"
                .into(),
            &["objects[1].implicit.torus", "tube"],
        ),
        (
            "implicit = { sphere = { center = [0, 1, 0], radius = -1 } }".into(),
            &["object 2", "a sphere's radius", "-1"],
        ),
        (
            format!("implicit = {{ smooth_union = {{ blend = 0.1, shapes = [ {sphere} ] }} }}"),
            &["object 2", "smooth_union has 1 shapes"],
        ),
        (
            format!(
                "implicit = {}{sphere}{}",
                "{ translate = { offset = [0, 0, 0], shape = ".repeat(20),
                " } }".repeat(20)
            ),
            &["object 2", "deeper than 16 levels"],
        ),
        // Blended pairwise in order: 20,000 shapes would be a chain 19,999
        // levels deep, which overflowed the stack when its box was found.
        (
            format!(
                "implicit = {{ smooth_union = {{ blend = 0.1, shapes = [ {} ] }} }}",
                vec![sphere; 20_000].join(", ")
            ),
            &["object 2", "deeper than 16 levels"],
        ),
    ] {
        assert_names(&refused(&with(&object)), needles);
    }
    let bad_march = with(&format!("implicit = {sphere}"))
        .replace("[camera]", "[render]\nmarch_relaxation = 2.5\n\n[camera]");
    assert_names(&refused(&bad_march), &["march_relaxation = 2.5", "below 2"]);
    let good = with(&format!("implicit = {sphere}"));
    let loaded = Scene::parse(&good, "test scene").expect("a valid tree");
    let settings = RenderSettings {
        width: 8,
        height: 6,
        ..loaded.render
    };
    let rendered = raylab::render(&loaded, 12, &settings, None).expect("renders");
    assert!(rendered.effects.implicit && rendered.rays.implicit_marches() > 0);
    let before = raylab::render(&loaded, 11, &settings, None).expect("renders");
    assert!(!before.effects.implicit && before.rays.implicit_marches() == 0);
    // Chapter 12 on a scene with no implicit surface marches nothing.
    let plain = Scene::parse(&scene(CAMERA, LIGHT), "test scene").expect("valid");
    let rendered = raylab::render(&plain, 12, &settings, None).expect("renders");
    assert!(!rendered.effects.implicit && rendered.rays.implicit_evaluations == 0);
}

/// `cauchy` sets the index at every wavelength, so a given `ior` beside it
/// is refused whatever its value, the default's 1.5 included; without
/// `cauchy`, a missing `ior` is 1.5 and a given one is kept.
#[test]
fn an_ior_beside_cauchy_is_refused_even_at_the_default() {
    let glass = |material: &str| {
        format!(
            "{}\n[[objects]]\nname = \"glass\"\nsphere = {{ center = [0.0, 1.0, 0.0], radius = 0.5 }}\n\
             material = {{ transparency = 1.0{material} }}\n",
            scene(CAMERA, LIGHT)
        )
    };
    let cauchy = ", cauchy = { a = 1.6, b = 0.05 }";
    for ior in ["1.5", "1.6"] {
        let message = refused(&glass(&format!(", ior = {ior}{cauchy}")));
        assert_names(&message, &["\"glass\"", "both `ior` and `cauchy`"]);
    }
    let index = |material: &str| {
        let scene = Scene::parse(&glass(material), "test scene").expect("valid scene");
        scene.objects[1].material.ior
    };
    assert_eq!(index(""), 1.5);
    assert_eq!(index(", ior = 1.33"), 1.33);
    assert!((index(cauchy) - (1.6 + 0.05 / (0.587_56 * 0.587_56))).abs() < 1e-5);
}
