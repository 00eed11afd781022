//! The `raylab` command as a student meets it: renders, listings, and clear
//! errors with a non-zero exit and no output file for every kind of bad input.

use crate::common;
use common::{raylab, stderr, stdout};

use std::path::Path;

fn only_files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("read dir")
        .map(|entry| {
            entry
                .expect("entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names
}

#[test]
fn render_a_chapter_with_the_default_output_name() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = raylab(
        &[
            "render",
            "--chapter",
            "5",
            "--width",
            "64",
            "--height",
            "48",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let line = stdout(&out);
    assert!(line.starts_with("chapter 5: 64x48, 1 spp"), "{line}");
    assert!(line.contains("3072 primary"), "{line}");
    let image = image::open(dir.path().join("chapter-5.png"))
        .expect("a PNG")
        .to_rgb8();
    assert_eq!(image.dimensions(), (64, 48));
}

#[test]
fn stats_name_effects_and_ray_kinds_and_json_agrees() {
    let dir = tempfile::tempdir().expect("temp dir");
    let args = [
        "render",
        "-c",
        "8",
        "--width",
        "40",
        "--height",
        "30",
        "--stats",
        "--stats-json",
        "s.json",
    ];
    let out = raylab(&args, dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("effects simulated: planes, spheres, nearest-hit, phong-diffuse, shadows, phong-specular, reflection, antialiasing, refraction"), "{text}");
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("s.json")).expect("json file"),
    )
    .expect("valid json");
    assert_eq!(json["rays"]["primary"], 40 * 30 * 4);
    assert!(json["rays"]["refraction"].as_u64().expect("a count") > 0);
}

/// Chapter 12's stats count the marches by their evaluations, in text and
/// in JSON, and the two agree with the total.
#[test]
fn stats_count_the_marches_by_their_evaluations() {
    let dir = tempfile::tempdir().expect("temp dir");
    let args = [
        "render",
        "-c",
        "12",
        "--width",
        "80",
        "--height",
        "60",
        "--stats",
        "--stats-json",
        "s.json",
    ];
    let out = raylab(&args, dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.contains("of the marches missed their surface's box and made no evaluation"),
        "{text}"
    );
    assert!(text.contains(", by their evaluations:"), "{text}");
    assert!(text.contains("      8-15 "), "{text}");
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("s.json")).expect("json file"),
    )
    .expect("valid json");
    let implicit = &json["implicit"];
    let buckets = implicit["evaluations_a_march"]
        .as_array()
        .expect("the histogram");
    let counted: u64 = buckets
        .iter()
        .map(|bucket| bucket["marches"].as_u64().expect("a count"))
        .sum();
    assert_eq!(Some(counted), implicit["marches"].as_u64());
    assert_eq!(buckets[0]["to"], 0);
    assert_eq!(buckets[3]["from"], 4);
    assert_eq!(buckets[3]["to"], 7);
    assert!(buckets.last().expect("a last bucket")["to"].is_null());
    // Several buckets are filled: a histogram, not one count.
    let filled = buckets
        .iter()
        .filter(|bucket| bucket["marches"] != 0)
        .count();
    assert!(filled >= 5, "{buckets:?}");
}

#[test]
fn chapters_lists_every_chapter() {
    let out = raylab(&["chapters"], Path::new("."));
    assert!(out.status.success());
    let text = stdout(&out);
    assert_eq!(text.lines().count(), raylab::chapters::CHAPTERS.len());
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[7].starts_with(" 8  Refraction"), "{}", lines[7]);
    assert!(lines[8].starts_with(" 9  Glass done right"), "{}", lines[8]);
    // Every row's columns start where the first row's do.
    let column = |line: &str, label: &str| line.find(label).expect("a column label");
    for line in &lines {
        assert_eq!(column(line, " adds "), column(lines[0], " adds "), "{line}");
        assert_eq!(
            column(line, "effects:"),
            column(lines[0], "effects:"),
            "{line}"
        );
    }
}

#[test]
fn printed_scene_renders_when_edited() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = raylab(&["scene", "--chapter", "4"], dir.path());
    assert!(out.status.success());
    let edited = stdout(&out).replace("intensity = 0.8", "intensity = 0.3");
    std::fs::write(dir.path().join("mine.toml"), edited).expect("write scene");
    let out = raylab(
        &[
            "render",
            "--scene",
            "mine.toml",
            "--width",
            "32",
            "--height",
            "24",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.path().join("mine.png").exists());
    assert!(
        stdout(&out).starts_with(&format!("chapter {}:", raylab::chapters::LAST_CHAPTER)),
        "a scene alone renders with every effect"
    );
}

/// Runs a render that must fail, and checks the message, the exit status
/// and that no file was left behind.
fn assert_refused(scene: Option<&str>, extra: &[&str], expected: &[&str]) {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut args = vec!["render"];
    if !extra.contains(&"-o") {
        args.extend(["-o", "out.png"]);
    }
    if !extra.contains(&"--width") {
        args.extend(["--width", "16"]);
    }
    if !extra.contains(&"--height") {
        args.extend(["--height", "12"]);
    }
    if let Some(text) = scene {
        std::fs::write(dir.path().join("bad.toml"), text).expect("write scene");
        args.extend(["--scene", "bad.toml"]);
    } else {
        args.extend(["--chapter", "3"]);
    }
    args.extend(extra);
    let out = raylab(&args, dir.path());
    let message = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{message}");
    for needle in expected {
        assert!(message.contains(needle), "`{needle}` not in: {message}");
    }
    assert!(!message.contains("panicked"), "{message}");
    let left: Vec<String> = only_files(dir.path())
        .into_iter()
        .filter(|n| n != "bad.toml")
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}

const GOOD: &str = r#"
[camera]
position = [0.0, 1.0, -5.0]
look_at = [0.0, 1.0, 0.0]

[[lights]]
position = [0.0, 5.0, 0.0]

[[objects]]
name = "ball"
sphere = { center = [0.0, 1.0, 0.0], radius = 1.0 }
"#;

#[test]
fn good_scene_is_accepted() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(dir.path().join("good.toml"), GOOD).expect("write");
    let out = raylab(
        &[
            "render",
            "--scene",
            "good.toml",
            "--width",
            "8",
            "--height",
            "8",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
}

#[test]
fn syntax_error_names_file_line_and_column() {
    let broken = GOOD.replace("radius = 1.0 }", "radius = 1.0");
    assert_refused(Some(&broken), &[], &["bad.toml", "line 11"]);
}

#[test]
fn wrong_type_names_the_field() {
    let broken = GOOD.replace("radius = 1.0", "radius = \"big\"");
    assert_refused(
        Some(&broken),
        &[],
        &["line 11", "objects[0].sphere.radius", "expected f32"],
    );
}

#[test]
fn unknown_field_is_a_typo_not_silence() {
    let broken = GOOD.replace("radius = 1.0", "radius = 1.0, colour = [1, 0, 0]");
    assert_refused(Some(&broken), &[], &["unknown field `colour`"]);
}

#[test]
fn zero_radius_names_the_object_and_value() {
    let broken = GOOD.replace("radius = 1.0", "radius = 0.0");
    assert_refused(
        Some(&broken),
        &[],
        &["object 1 (\"ball\")", "sphere.radius = 0"],
    );
}

#[test]
fn non_finite_numbers_are_refused() {
    let broken = GOOD.replace("center = [0.0, 1.0, 0.0]", "center = [nan, 1.0, 0.0]");
    assert_refused(Some(&broken), &[], &["sphere.center", "finite"]);
    let broken = GOOD.replace("position = [0.0, 5.0, 0.0]", "position = [0.0, inf, 0.0]");
    assert_refused(Some(&broken), &[], &["lights[0].position", "finite"]);
}

#[test]
fn zero_normal_and_bad_ior_are_refused() {
    let plane = format!(
        "{GOOD}\n[[objects]]\nplane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 0.0] }}\n"
    );
    assert_refused(Some(&plane), &[], &["object 2", "normal"]);
    let glass = GOOD.replace(
        "radius = 1.0 }",
        "radius = 1.0 }\nmaterial = { transparency = 0.5, ior = 0.0 }",
    );
    assert_refused(Some(&glass), &[], &["ball", "ior = 0"]);
}

#[test]
fn broken_lights_quads_and_boxes_are_refused() {
    let object = |text: &str| format!("{GOOD}\n[[objects]]\nname = \"extra\"\n{text}\n");
    let flat_quad =
        object("quad = { corner = [0.0, 0.0, 0.0], u = [1.0, 0.0, 0.0], v = [2.0, 0.0, 0.0] }");
    assert_refused(
        Some(&flat_quad),
        &[],
        &["object 2 (\"extra\")", "span no area"],
    );
    let inside_out = object("cuboid = { min = [1.0, 0.0, 0.0], max = [0.0, 1.0, 1.0] }");
    assert_refused(Some(&inside_out), &[], &["cuboid.min", "below cuboid.max"]);
    let two_shapes = object(
        "quad = { corner = [0.0, 0.0, 0.0], u = [1.0, 0.0, 0.0], v = [0.0, 1.0, 0.0] }\n\
         sphere = { center = [0.0, 0.0, 0.0], radius = 1.0 }",
    );
    assert_refused(Some(&two_shapes), &[], &["exactly one shape per object"]);
    let glowing = GOOD.replace(
        "radius = 1.0 }",
        "radius = 1.0 }\nmaterial = { emission = [1.0, nan, 1.0] }",
    );
    assert_refused(Some(&glowing), &[], &["material.emission", "finite"]);
    let rough = GOOD.replace(
        "radius = 1.0 }",
        "radius = 1.0 }\nmaterial = { roughness = 2.0 }",
    );
    assert_refused(
        Some(&rough),
        &[],
        &["material.roughness = 2", "between 0 and 1"],
    );
}

#[test]
fn absurd_settings_are_refused() {
    assert_refused(None, &["--width", "0"], &["resolution 0x12"]);
    assert_refused(None, &["--width", "100000"], &["resolution 100000x12"]);
    assert_refused(None, &["--samples", "0"], &["samples = 0"]);
    assert_refused(None, &["--samples", "3"], &["square"]);
    assert_refused(None, &["--depth", "1000"], &["max_depth = 1000"]);
    // Each number is allowed alone; together they are 1.5e11 samples.
    let huge = ["--width", "6000", "--height", "6000", "--samples", "4096"];
    assert_refused(None, &huge, &["147456000000 samples", "at most 1073741824"]);
}

#[test]
fn lights_too_bright_for_f32_and_colours_over_one_are_refused() {
    // 3e38 is finite, but times any colour it overflows to infinity.
    let blinding = GOOD.replace(
        "position = [0.0, 5.0, 0.0]",
        "position = [0.0, 5.0, 0.0]\nintensity = 3e38",
    );
    assert_refused(
        Some(&blinding),
        &[],
        &["light 1: intensity = 3", "between 0 and 1e6"],
    );
    let glowing = GOOD.replace(
        "radius = 1.0 }",
        "radius = 1.0 }\nmaterial = { color = [2.0, 0.5, 0.5] }",
    );
    assert_refused(
        Some(&glowing),
        &[],
        &["ball", "material.color", "between 0 and 1"],
    );
}

#[test]
fn outputs_are_checked_before_rendering_and_never_overwrite_an_input() {
    // Not a PNG name (here the scene file itself): refused.
    assert_refused(Some(GOOD), &["-o", "bad.toml"], &["-o bad.toml", ".png"]);
    // A scene file that happens to end in .png as the image: refused by the
    // input check, and the scene survives.
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(dir.path().join("scene.png"), GOOD).expect("write scene");
    let out = raylab(
        &["render", "--scene", "scene.png", "-o", "./scene.png"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("that is an input"),
        "{}",
        stderr(&out)
    );
    let kept = std::fs::read_to_string(dir.path().join("scene.png")).expect("read scene");
    assert_eq!(kept, GOOD);
    assert_refused(
        Some(GOOD),
        &["-o", "bad.png", "--stats-json", "bad.png"],
        &["same file"],
    );
    // A statistics file into a missing folder: nothing rendered, no image.
    assert_refused(
        None,
        &["--stats-json", "no/such/s.json"],
        &["--stats-json", "does not exist"],
    );
    assert_refused(None, &["-o", "render.jpg"], &["render.jpg", "PNG"]);
}

#[test]
fn missing_scene_file_is_named() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = raylab(&["render", "--scene", "nowhere.toml"], dir.path());
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("nowhere.toml"), "{}", stderr(&out));
}

#[test]
fn unwritable_output_is_a_clear_error() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = raylab(
        &[
            "render",
            "-c",
            "1",
            "--width",
            "8",
            "--height",
            "8",
            "-o",
            "no/such/dir/x.png",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("-o no/such/dir/x.png: the folder no/such/dir does not exist"),
        "{}",
        stderr(&out)
    );
    assert!(only_files(dir.path()).is_empty());
}

#[test]
fn nothing_to_render_says_what_to_give() {
    let out = raylab(&["render"], Path::new("."));
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--chapter N"));
}

#[test]
fn chapter_out_of_range_is_refused_by_the_parser() {
    let out = raylab(&["render", "--chapter", "99"], Path::new("."));
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("99"));
}

#[test]
fn bench_prints_every_run_and_the_median() {
    let out = raylab(
        &[
            "bench", "-c", "6", "--width", "16", "--height", "12", "--runs", "3",
        ],
        Path::new("."),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.starts_with("chapter 6: 16x12, 1 spp"), "{text}");
    let times = text.lines().nth(1).expect("times line");
    assert_eq!(times.split_whitespace().count(), 2 + 3, "{times}");
    assert!(text.contains("median: "), "{text}");
}

#[test]
fn probe_prints_each_shape_and_our_nearest_hit() {
    let out = raylab(
        &["probe", "--chapter", "8", "--ray", "0,1.5,-6,-0.1,-0.13,1"],
        Path::new("."),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.contains("glass ball       sphere, roots t = "),
        "{text}"
    );
    assert!(text.contains("floor            plane, t = "), "{text}");
    assert!(
        text.contains("ours:   \"glass ball\" (object 1) at t = 4.83"),
        "{text}"
    );
    assert!(text.contains("embree: "), "{text}");
}

/// Chapter 12's probe: the march, then Newton in its bracket and alone,
/// each iterate with the digits it has right; on the lesson's ray, Newton
/// alone settles on the tube's far side.
#[test]
fn probe_tells_the_march_and_newton_of_an_implicit_surface() {
    let out = raylab(
        &[
            "probe",
            "--chapter",
            "12",
            "--ray",
            "0,2.2,-5.5,-0.33,-0.3,1",
        ],
        Path::new("."),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    for expected in [
        "torus            implicit surface, t = 6.23165",
        "sphere tracing: stops at t = ",
        "the first root, in f64: t = 6.23165",
        "Newton in the bracket [5.3333",
        "bisection",
        "Newton alone from the same start, no bracket",
        "it ends at t = 6.7904",
        "intersect_implicit (march, bracket, Newton): t = 6.23165",
        "blend            implicit surface, no hit ahead",
        "the ray misses its box: no evaluation",
    ] {
        assert!(text.contains(expected), "{expected:?} in\n{text}");
    }
    // The last bracketed iterate has all the digits f32 holds.
    let bracketed = text
        .split("Newton alone")
        .next()
        .and_then(|part| part.lines().rev().find(|line| line.contains("Newton ")))
        .expect("a Newton step in the bracket");
    let digits: f64 = bracketed
        .split_whitespace()
        .last()
        .and_then(|word| word.parse().ok())
        .expect("digits at the end of the row");
    assert!(digits > 7.0, "{bracketed}");
}

/// `raylab trace`: the ray tree of one pixel, as text and as JSON, ending
/// in the pixel the render writes; a pixel outside the image, a sample
/// that does not exist and a malformed pixel are errors.
#[test]
fn trace_prints_a_pixels_ray_tree_ending_in_its_rendered_value() {
    let dir = tempfile::tempdir().expect("temp dir");
    let size = ["--width", "32", "--height", "24"];
    let render = raylab(
        &[&["render", "-c", "6", "-o", "six.png"][..], &size[..]].concat(),
        dir.path(),
    );
    assert!(render.status.success(), "{}", stderr(&render));
    let image = image::open(dir.path().join("six.png"))
        .expect("the render")
        .to_rgb8();
    let pixel = image.get_pixel(16, 12).0;
    let out = raylab(
        &[&["trace", "-c", "6", "--pixel", "16,12"][..], &size[..]].concat(),
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.starts_with("chapter 6, pixel 16,12: 1 camera ray"),
        "{text}"
    );
    assert!(text.contains("  primary ray from "), "{text}");
    assert!(text.contains("shadow ray from "), "{text}");
    assert!(text.contains("brings back ("), "{text}");
    let last = text.lines().last().expect("a last line");
    let srgb = format!(
        "-> sRGB ({}, {}, {}), as the render writes it",
        pixel[0], pixel[1], pixel[2]
    );
    assert!(last.ends_with(&srgb), "{last} vs {srgb}");

    let out = raylab(
        &[
            &["trace", "-c", "6", "--pixel", "16,12", "--json"][..],
            &size[..],
        ]
        .concat(),
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value = serde_json::from_str(&stdout(&out)).expect("valid json");
    assert_eq!(json["srgb"], serde_json::json!(pixel));
    assert_eq!(json["samples"][0]["ray"]["kind"], "primary");
    assert!(
        json["samples"][0]["ray"]["children"]
            .as_array()
            .is_some_and(|c| !c.is_empty())
    );

    for (args, message) in [
        (
            vec!["--pixel", "32,0"],
            "pixel 32,0 is outside the 32x24 image",
        ),
        (
            vec!["--pixel", "1,1", "--sample", "1"],
            "sample 1 does not exist",
        ),
        (vec!["--pixel", "1"], "expected `x,y`"),
        (vec!["--pixel", "-1,2"], "`-1` is not a pixel coordinate"),
        (
            vec!["--pixel", "99999999999,1"],
            "a whole number from 0 to 4294967295",
        ),
    ] {
        let out = raylab(
            &[&["trace", "-c", "6"][..], &size[..], &args[..]].concat(),
            dir.path(),
        );
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).contains(message), "{args:?}: {}", stderr(&out));
    }
}

#[test]
fn probe_refuses_a_malformed_ray() {
    for bad in ["1,2,3", "0,0,0,0,0,0", "0,0,0,1,nan,0", "a,b,c,d,e,f"] {
        let out = raylab(&["probe", "--ray", bad], Path::new("."));
        assert_eq!(out.status.code(), Some(2), "{bad}");
        assert!(stderr(&out).contains("--ray"), "{bad}: {}", stderr(&out));
    }
}

#[cfg(unix)]
#[test]
fn a_closed_pipe_stops_quietly_without_a_panic() {
    // `raylab scene --chapter 8 | head -0`: the reader has gone before
    // raylab writes.
    let out = common::output_into_closed_pipe(common::command(
        &["scene", "--chapter", "8"],
        Path::new("."),
    ));
    let message = stderr(&out);
    assert!(!message.contains("panicked"), "{message}");
    // Killed by SIGPIPE, as `cat` or `ls` would be: no exit code.
    use std::os::unix::process::ExitStatusExt;
    assert_eq!(out.status.signal(), Some(libc::SIGPIPE), "{message}");
}

#[cfg(unix)]
#[test]
fn images_get_the_permissions_of_any_new_file() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().expect("temp dir");
    let out = raylab(
        &["render", "--chapter", "1", "--width", "8", "--height", "6"],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let ordinary = dir.path().join("ordinary");
    std::fs::File::create(&ordinary).expect("create a file");
    let mode = |path: &Path| {
        std::fs::metadata(path)
            .expect("metadata")
            .permissions()
            .mode()
            & 0o777
    };
    assert_eq!(mode(&dir.path().join("chapter-1.png")), mode(&ordinary));
}

/// `--threads 100000` would hang starting threads: every command that
/// takes `--threads` refuses more than 1024 through the same parser, and
/// `--help` says so.
#[test]
fn thread_counts_above_the_bound_are_refused_in_every_command() {
    let dir = tempfile::tempdir().expect("temp dir");
    for command in ["render", "bench", "cost", "crosscheck"] {
        for threads in ["1025", "100000", "0"] {
            let out = raylab(
                &[
                    command,
                    "--chapter",
                    "2",
                    "--width",
                    "8",
                    "--height",
                    "6",
                    "--threads",
                    threads,
                ],
                dir.path(),
            );
            assert_eq!(out.status.code(), Some(2), "{command} {threads}");
            let message = stderr(&out);
            assert!(
                message.contains(&format!("invalid value '{threads}' for '--threads"))
                    && message.contains("from 1 to 1024"),
                "{command} {threads}: {message}"
            );
        }
        let help = stdout(&raylab(&[command, "--help"], dir.path()));
        assert!(help.contains("1 to 1024"), "{command} --help: {help}");
    }
    assert!(only_files(dir.path()).is_empty());
    let out = raylab(
        &[
            "render",
            "-c",
            "1",
            "--width",
            "8",
            "--height",
            "6",
            "--threads",
            "1024",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
}

/// A FIFO as `--scene` would block forever, `/dev/zero` would be read until
/// memory ran out: a scene file is read only if it is a regular file of at
/// most 16 MiB (a sparse file here: nothing of it is read).
#[cfg(unix)]
#[test]
fn a_scene_must_be_a_regular_file_of_bounded_size() {
    let dir = tempfile::tempdir().expect("temp dir");
    common::make_fifo(&dir.path().join("pipe.toml"));
    let huge = std::fs::File::create(dir.path().join("huge.toml")).expect("create");
    huge.set_len((16 << 20) + 1).expect("sparse file");
    for (scene, message) in [
        (
            "pipe.toml",
            "pipe.toml: is a FIFO (named pipe), not a regular file",
        ),
        (
            "/dev/zero",
            "/dev/zero: is a character device, not a regular file",
        ),
        (
            "huge.toml",
            "huge.toml: 16777217 bytes; raylab reads a scene file of at most 16777216 bytes",
        ),
    ] {
        for command in ["render", "probe", "cost", "bench"] {
            let mut args = vec![command, "--scene", scene, "--chapter", "6"];
            if command == "probe" {
                args.extend(["--ray", "0,1,-5,0,0,1"]);
            }
            let out = common::raylab_unblocked(&args, dir.path());
            assert_eq!(out.status.code(), Some(2), "{args:?}");
            assert!(stderr(&out).contains(message), "{args:?}: {}", stderr(&out));
        }
    }
}

/// The object count is bounded too (every ray tests every object).
#[test]
fn a_scene_with_too_many_objects_is_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut scene = String::from(GOOD);
    let sphere = "[[objects]]\nsphere = { center = [0, 1, 9], radius = 0.1 }\n";
    scene.push_str(&sphere.repeat(raylab::scene::MAX_OBJECTS));
    std::fs::write(dir.path().join("crowd.toml"), scene).expect("write");
    let out = raylab(
        &[
            "render",
            "--scene",
            "crowd.toml",
            "--width",
            "4",
            "--height",
            "3",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains(
            "more than 100000 [[objects]] tables: a scene may have at most 100000 objects"
        ),
        "{}",
        stderr(&out)
    );
    assert!(!dir.path().join("crowd.png").exists());
}

/// Lights are bounded like objects, before the file is parsed (500,000
/// light tables took 1.2 GB to parse), and after, for inline arrays.
#[test]
fn a_scene_with_too_many_lights_is_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let most = raylab::scene::MAX_LIGHTS;
    let mut tables = String::from(GOOD);
    tables.push_str(&"[[lights]]\nposition = [0, 5, 0]\n".repeat(500_000));
    let light = "{ position = [0, 5, 0] }, ";
    let inline = format!(
        "lights = [{}]\n[camera]\nposition = [0, 1, -5]\nlook_at = [0, 0, 0]\n",
        light.repeat(most + 1)
    );
    for (name, scene, message) in [
        (
            "tables.toml",
            tables,
            format!("more than {most} [[lights]] tables"),
        ),
        (
            "inline.toml",
            inline,
            format!(
                "{} lights and beams: a scene may have at most {most}",
                most + 1
            ),
        ),
    ] {
        std::fs::write(dir.path().join(name), scene).expect("write");
        let out = raylab(
            &["render", "--scene", name, "--width", "4", "--height", "3"],
            dir.path(),
        );
        assert_eq!(out.status.code(), Some(2), "{name}");
        assert!(stderr(&out).contains(&message), "{name}: {}", stderr(&out));
    }
}

/// Names with terminal control characters (here `ESC [2J`, which clears
/// the screen) are printed escaped: in errors, in the summary line, and in
/// `probe`'s listing.
#[test]
fn control_characters_in_names_are_printed_escaped() {
    let dir = tempfile::tempdir().expect("temp dir");
    let named = GOOD.replace("name = \"ball\"", "name = \"\\u001b[2Jball\\u0007\"");
    std::fs::write(dir.path().join("named.toml"), &named).expect("write");
    let broken = named.replace("radius = 1.0", "radius = 0.0");
    std::fs::write(dir.path().join("broken.toml"), &broken).expect("write");
    let clean = |text: &str| !text.contains('\u{1b}') && !text.contains('\u{7}');

    let out = raylab(&["render", "--scene", "broken.toml"], dir.path());
    assert_eq!(out.status.code(), Some(2));
    assert!(clean(&stderr(&out)), "{:?}", stderr(&out));
    assert!(
        stderr(&out).contains("(\"\\u{1b}[2Jball\\u{7}\"): sphere.radius"),
        "{}",
        stderr(&out)
    );

    let out = raylab(
        &["probe", "--scene", "named.toml", "--ray", "0,1,-5,0,0,1"],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(clean(&stdout(&out)), "{:?}", stdout(&out));
    assert!(
        stdout(&out).contains("\\u{1b}[2Jball\\u{7}"),
        "{}",
        stdout(&out)
    );

    let out = raylab(
        &[
            "render",
            "-c",
            "1",
            "--width",
            "8",
            "--height",
            "6",
            "-o",
            "\u{1b}[2J.png",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(clean(&stdout(&out)), "{:?}", stdout(&out));
    assert!(
        stdout(&out).contains("-> \\u{1b}[2J.png"),
        "{}",
        stdout(&out)
    );
}

/// Characters that show as nothing (a zero-width space, a soft hyphen, a
/// byte-order mark, directional marks) and the line and paragraph
/// separators are printed escaped too, in `trace`, in `probe` and in
/// errors: a name must not look like another, or break a line.
#[test]
fn invisible_characters_in_names_are_printed_escaped() {
    let dir = tempfile::tempdir().expect("temp dir");
    let invisible = [
        '\u{200b}', '\u{ad}', '\u{feff}', '\u{200f}', '\u{61c}', '\u{2028}', '\u{2029}',
    ];
    let name: String = std::iter::once("ball".to_string())
        .chain(invisible.iter().map(|c| c.to_string()))
        .collect();
    let shown: String = std::iter::once("ball".to_string())
        .chain(
            invisible
                .iter()
                .map(|c| format!("\\u{{{:x}}}", u32::from(*c))),
        )
        .collect();
    let named = GOOD.replace("name = \"ball\"", &format!("name = \"{name}\""));
    std::fs::write(dir.path().join("named.toml"), &named).expect("write");
    let broken = named.replace("radius = 1.0", "radius = 0.0");
    std::fs::write(dir.path().join("broken.toml"), &broken).expect("write");
    let clean = |text: &str| !text.contains(invisible);

    let out = raylab(&["render", "--scene", "broken.toml"], dir.path());
    assert_eq!(out.status.code(), Some(2));
    assert!(clean(&stderr(&out)), "{:?}", stderr(&out));

    let out = raylab(
        &["probe", "--scene", "named.toml", "--ray", "0,1,-5,0,0,1"],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(clean(&stdout(&out)), "{:?}", stdout(&out));
    assert!(stdout(&out).contains(&shown), "{}", stdout(&out));

    let out = raylab(
        &[
            "trace",
            "--scene",
            "named.toml",
            "--chapter",
            "5",
            "--width",
            "8",
            "--height",
            "8",
            "--pixel",
            "4,4",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(clean(&stdout(&out)), "{:?}", stdout(&out));
    assert!(stdout(&out).contains(&shown), "{}", stdout(&out));
}

/// `render --scene my-scene.toml --chapter 4` must not write chapter-4.png,
/// the hand-in name, over the student's render of the built-in scene.
#[test]
fn a_scene_render_is_named_after_the_scene() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(dir.path().join("my-scene.toml"), GOOD).expect("write");
    let small = ["--width", "8", "--height", "6"];
    let out = raylab(
        &[&["render", "--chapter", "4"][..], &small].concat(),
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let hand_in = std::fs::read(dir.path().join("chapter-4.png")).expect("hand-in");
    let out = raylab(
        &[
            &["render", "--scene", "my-scene.toml", "--chapter", "4"][..],
            &small,
        ]
        .concat(),
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stdout(&out).ends_with("-> my-scene-ch4.png\n"),
        "{}",
        stdout(&out)
    );
    assert_eq!(
        std::fs::read(dir.path().join("chapter-4.png")).expect("kept"),
        hand_in
    );
    assert!(dir.path().join("my-scene-ch4.png").exists());
    let out = raylab(
        &[&["render", "--scene", "my-scene.toml"][..], &small].concat(),
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.path().join("my-scene.png").exists());
}

/// `render` replaces its own earlier image, but not a file it did not write
/// nor a read-only one, unless --force; a file replaced keeps its mode.
#[cfg(unix)]
#[test]
fn render_replaces_only_its_own_writable_images_without_force() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().expect("temp dir");
    let render = |output: &str, force: bool| {
        let mut args = vec![
            "render", "-c", "2", "--width", "8", "--height", "6", "-o", output,
        ];
        if force {
            args.push("--force");
        }
        raylab(&args, dir.path())
    };
    // raylab's own image: replaced freely.
    assert!(render("mine.png", false).status.success());
    assert!(render("mine.png", false).status.success());
    // A PNG from elsewhere (no raylab marker), and a text file.
    let photo = dir.path().join("photo.png");
    image::RgbImage::from_pixel(3, 2, image::Rgb([1, 2, 3]))
        .save(&photo)
        .expect("save");
    let photo_bytes = std::fs::read(&photo).expect("read");
    std::fs::write(dir.path().join("notes.png"), "my notes").expect("write");
    for name in ["photo.png", "notes.png"] {
        let out = render(name, false);
        assert_eq!(out.status.code(), Some(2));
        assert!(
            stderr(&out).contains(&format!(
                "-o {name}: the file exists and raylab did not write it; use --force"
            )),
            "{}",
            stderr(&out)
        );
        assert!(stdout(&out).is_empty(), "nothing rendered");
    }
    assert_eq!(std::fs::read(&photo).expect("kept"), photo_bytes);
    assert!(render("photo.png", true).status.success());
    assert_ne!(std::fs::read(&photo).expect("replaced"), photo_bytes);
    // Read-only, even raylab's own: kept without --force, and replaced with
    // it stays read-only.
    let mine = dir.path().join("mine.png");
    std::fs::set_permissions(&mine, std::fs::Permissions::from_mode(0o444)).expect("chmod");
    let before = std::fs::read(&mine).expect("read");
    let out = render("mine.png", false);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("-o mine.png: the file exists and is read-only"),
        "{}",
        stderr(&out)
    );
    assert_eq!(std::fs::read(&mine).expect("kept"), before);
    let out = raylab(
        &[
            "render", "-c", "5", "--width", "8", "--height", "6", "-o", "mine.png", "--force",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert_ne!(std::fs::read(&mine).expect("replaced"), before);
    let mode = std::fs::metadata(&mine)
        .expect("metadata")
        .permissions()
        .mode()
        & 0o777;
    assert_eq!(mode, 0o444);
}

/// Outputs that cannot be written are found before the render, so that `-o
/// out.png/` or an unwritable `--stats-json` never costs a render, nor
/// prints success before it fails.
#[cfg(unix)]
#[test]
fn unwritable_outputs_fail_before_the_render() {
    let dir = tempfile::tempdir().expect("temp dir");
    common::make_fifo(&dir.path().join("pipe.json"));
    for (extra, message) in [
        (
            vec!["-o", "out.png/"],
            "-o out.png/: names a folder, not a file",
        ),
        (
            vec!["--stats-json", "s.json/"],
            "--stats-json s.json/: names a folder, not a file",
        ),
        (
            vec!["--stats-json", "pipe.json"],
            "--stats-json pipe.json: exists and is not a regular file",
        ),
    ] {
        let mut args = vec!["render", "-c", "8", "--width", "8", "--height", "6"];
        args.extend(&extra);
        let out = common::raylab_unblocked(&args, dir.path());
        assert_eq!(out.status.code(), Some(2), "{extra:?}");
        assert!(
            stderr(&out).contains(message),
            "{extra:?}: {}",
            stderr(&out)
        );
        assert!(stdout(&out).is_empty(), "{extra:?}: nothing rendered");
        assert!(!dir.path().join("chapter-8.png").exists(), "{extra:?}");
        assert!(!dir.path().join("out.png").exists(), "{extra:?}");
    }
}

/// On a full disk `cost` must not leave cost.csv and cost.md without
/// cost.svg: its three files are written all or none (RLIMIT_FSIZE stands
/// in for the full disk: the SVG is the largest).
#[cfg(unix)]
#[test]
fn cost_writes_its_files_all_or_none() {
    let dir = tempfile::tempdir().expect("temp dir");
    let args = [
        "cost",
        "--chapter",
        "6",
        "--knob",
        "depth",
        "--width",
        "8",
        "--height",
        "6",
        "--repeats",
        "1",
        "--out",
        "c",
    ];
    let out = raylab(&args, dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let size = |name: &str| {
        std::fs::metadata(dir.path().join("c").join(name))
            .expect("file")
            .len()
    };
    let largest_text = size("cost.csv").max(size("cost.md"));
    let svg = size("cost.svg");
    assert!(
        largest_text * 2 < svg,
        "text {largest_text} bytes, SVG {svg}"
    );
    std::fs::remove_dir_all(dir.path().join("c")).expect("clean");

    let out = common::raylab_with_file_size_limit(&args, dir.path(), largest_text * 2);
    assert_eq!(out.status.code(), Some(2), "{}", stdout(&out));
    assert!(
        stderr(&out).contains("cannot write c/cost.svg"),
        "{}",
        stderr(&out)
    );
    assert!(
        only_files(&dir.path().join("c")).is_empty(),
        "{:?}",
        only_files(&dir.path().join("c"))
    );
}

/// A signal that ends the process (SIGTERM, SIGINT, SIGQUIT, SIGPIPE,
/// SIGXFSZ, ...) while an output is being written must not leave a
/// `.raylab-XXXXXX.tmp` file: it is removed, the old image survives,
/// and the exit status is 128 + the signal. The test-only hook
/// RAYLAB_TEST_PAUSE_BEFORE_RENAME stops raylab with its temporary files
/// written, so the signal arrives at exactly that moment.
#[cfg(unix)]
#[test]
fn a_signal_during_a_write_removes_the_temporary_files() {
    use std::io::BufRead;
    let dir = tempfile::tempdir().expect("temp dir");
    let args = [
        "render",
        "-c",
        "2",
        "--width",
        "8",
        "--height",
        "6",
        "-o",
        "old.png",
        "--stats-json",
        "s.json",
    ];
    assert!(raylab(&args, dir.path()).status.success());
    let old = std::fs::read(dir.path().join("old.png")).expect("old image");
    for signal in [
        libc::SIGTERM,
        libc::SIGINT,
        libc::SIGHUP,
        libc::SIGQUIT,
        libc::SIGUSR1,
        libc::SIGUSR2,
        libc::SIGALRM,
        libc::SIGPIPE,
        libc::SIGXFSZ,
        libc::SIGXCPU,
    ] {
        let status = 128 + signal;
        let mut command = common::command(
            &[
                "render",
                "-c",
                "5",
                "--width",
                "8",
                "--height",
                "6",
                "-o",
                "old.png",
                "--stats-json",
                "s.json",
            ],
            dir.path(),
        );
        command
            .env("RAYLAB_TEST_PAUSE_BEFORE_RENAME", "1")
            .stderr(std::process::Stdio::piped());
        {
            use std::os::unix::process::CommandExt;
            // A signal ignored by whatever started the tests (`nohup`
            // ignores SIGHUP, a shell's background job SIGINT) stays
            // ignored in raylab, as it should: give it the default.
            // SAFETY: signal is async-signal-safe; nothing else runs here.
            unsafe {
                command.pre_exec(move || {
                    libc::signal(signal, libc::SIG_DFL);
                    Ok(())
                });
            }
        }
        let mut child = command.spawn().expect("spawn");
        let mut stderr_lines =
            std::io::BufReader::new(child.stderr.take().expect("stderr")).lines();
        let line = stderr_lines.next().expect("a line").expect("text");
        assert!(line.contains("temporary files written"), "{line}");
        assert_eq!(
            common::temporary_files(dir.path()).len(),
            2,
            "both outputs staged"
        );
        // SAFETY: signalling our own child.
        assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, signal) }, 0);
        let exit = child.wait().expect("wait");
        if signal == libc::SIGPIPE {
            // Ended by the signal itself, as a closed pipe ends `cat`.
            use std::os::unix::process::ExitStatusExt;
            assert_eq!(exit.signal(), Some(signal));
        } else {
            assert_eq!(exit.code(), Some(status), "signal {signal}");
        }
        assert_eq!(common::temporary_files(dir.path()), Vec::<String>::new());
        assert_eq!(
            std::fs::read(dir.path().join("old.png")).expect("old image"),
            old
        );
    }
}

/// Pass 13 of issue 41, finding 3: a signal between the renames of a set
/// of outputs left the new first file beside the old second one (a
/// report of this run beside the CSV of the last). The signal waits for
/// the set: both outputs are the new ones, no temporary file is left,
/// and the exit status is still 128 + the signal. The test-only hook
/// RAYLAB_TEST_PAUSE_BETWEEN_RENAMES stops raylab after the first rename.
#[cfg(unix)]
#[test]
fn a_signal_between_the_renames_of_a_set_waits_for_the_whole_set() {
    use std::io::BufRead;
    let dir = tempfile::tempdir().expect("temp dir");
    let render = |chapter: &str| {
        [
            "render",
            "-c",
            chapter,
            "--width",
            "8",
            "--height",
            "6",
            "-o",
            "out.png",
            "--stats-json",
            "stats.json",
        ]
        .map(String::from)
    };
    let old_args = render("2");
    let old_args: Vec<&str> = old_args.iter().map(String::as_str).collect();
    assert!(raylab(&old_args, dir.path()).status.success());
    let read = |name: &str| std::fs::read(dir.path().join(name)).expect("an output");
    let (old_image, old_stats) = (read("out.png"), read("stats.json"));
    let new_args = render("5");
    let new_args: Vec<&str> = new_args.iter().map(String::as_str).collect();
    let mut command = common::command(&new_args, dir.path());
    command
        .env("RAYLAB_TEST_PAUSE_BETWEEN_RENAMES", "1")
        .stderr(std::process::Stdio::piped());
    {
        use std::os::unix::process::CommandExt;
        // SAFETY: signal is async-signal-safe; nothing else runs here.
        unsafe {
            command.pre_exec(|| {
                libc::signal(libc::SIGTERM, libc::SIG_DFL);
                Ok(())
            });
        }
    }
    let mut child = command.spawn().expect("spawn");
    let mut lines = std::io::BufReader::new(child.stderr.take().expect("stderr")).lines();
    let line = lines.next().expect("a line").expect("text");
    assert!(line.contains("first output renamed"), "{line}");
    // SAFETY: signalling our own child.
    assert_eq!(
        unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGTERM) },
        0
    );
    let exit = child.wait().expect("wait");
    assert_eq!(exit.code(), Some(128 + libc::SIGTERM));
    assert_eq!(common::temporary_files(dir.path()), Vec::<String>::new());
    assert!(read("out.png") != old_image, "the image is the new one");
    assert!(read("stats.json") != old_stats, "and so are the stats");
}

/// Every signal whose default action ends the process, not only the ones
/// a shell sends: timers (SIGVTALRM, SIGPROF), a debugger's or a seccomp
/// filter's (SIGTRAP, SIGSYS), a fault sent by `kill` (SIGSEGV, SIGBUS,
/// SIGILL, SIGFPE, SIGABRT), and Linux's others (SIGSTKFLT, SIGIO, SIGPWR,
/// the real-time signals). Each, arriving while `render` or `diff` has its
/// two outputs staged, leaves no `.raylab-*.tmp` file and the old outputs
/// as they were; the process ends by the signal or with status 128 + it.
#[cfg(target_os = "linux")]
#[test]
fn every_terminating_signal_during_a_write_removes_the_temporary_files() {
    use std::io::BufRead;
    use std::os::unix::process::{CommandExt, ExitStatusExt};
    let dir = tempfile::tempdir().expect("temp dir");
    let render = [
        "render",
        "-c",
        "5",
        "--width",
        "8",
        "--height",
        "6",
        "-o",
        "old.png",
        "--stats-json",
        "s.json",
    ];
    assert!(raylab(&render, dir.path()).status.success());
    let other = [
        "render",
        "-c",
        "4",
        "--width",
        "8",
        "--height",
        "6",
        "-o",
        "other.png",
    ];
    assert!(raylab(&other, dir.path()).status.success());
    let diff = [
        "diff",
        "old.png",
        "other.png",
        "--heatmap",
        "heat.png",
        "--json",
        "d.json",
    ];
    assert!(raylab(&diff, dir.path()).status.code().is_some());
    let kept: Vec<(&str, Vec<u8>)> = ["old.png", "s.json", "heat.png", "d.json"]
        .into_iter()
        .map(|name| {
            (
                name,
                std::fs::read(dir.path().join(name)).expect("an output"),
            )
        })
        .collect();
    let mut signals = vec![
        libc::SIGVTALRM,
        libc::SIGPROF,
        libc::SIGTRAP,
        libc::SIGSYS,
        libc::SIGSEGV,
        libc::SIGBUS,
        libc::SIGILL,
        libc::SIGFPE,
        libc::SIGABRT,
        libc::SIGSTKFLT,
        libc::SIGIO,
        libc::SIGPWR,
    ];
    signals.extend([libc::SIGRTMIN(), libc::SIGRTMIN() + 5, libc::SIGRTMAX()]);
    for args in [&render[..], &diff[..]] {
        for &signal in &signals {
            let mut command = common::command(args, dir.path());
            command
                .env("RAYLAB_TEST_PAUSE_BEFORE_RENAME", "1")
                .stderr(std::process::Stdio::piped());
            // SAFETY: async-signal-safe calls only. The default action, in
            // case whatever started the tests ignores the signal; no core
            // file for the faults.
            unsafe {
                command.pre_exec(move || {
                    libc::signal(signal, libc::SIG_DFL);
                    let none = libc::rlimit {
                        rlim_cur: 0,
                        rlim_max: 0,
                    };
                    libc::setrlimit(libc::RLIMIT_CORE, &none);
                    Ok(())
                });
            }
            let mut child = command.spawn().expect("spawn");
            let mut stderr_lines =
                std::io::BufReader::new(child.stderr.take().expect("stderr")).lines();
            let line = stderr_lines.next().expect("a line").expect("text");
            assert!(line.contains("temporary files written"), "{line}");
            assert_eq!(
                common::temporary_files(dir.path()).len(),
                2,
                "{} stages both outputs",
                args[0]
            );
            // SAFETY: signalling our own child.
            assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, signal) }, 0);
            let exit = child.wait().expect("wait");
            assert!(
                exit.signal() == Some(signal) || exit.code() == Some(128 + signal),
                "{} and signal {signal}: {exit:?}",
                args[0]
            );
            assert_eq!(
                common::temporary_files(dir.path()),
                Vec::<String>::new(),
                "{} and signal {signal}",
                args[0]
            );
            for (name, bytes) in &kept {
                assert_eq!(
                    &std::fs::read(dir.path().join(name)).expect("an output"),
                    bytes,
                    "{name}"
                );
            }
        }
    }
}

/// A glass cuboid around a diamond ball: every ray that meets glass
/// splits in two, and the box's walls keep most of them in (total internal
/// reflection), so with `min_contribution = 0` the tree of one camera ray
/// grows by about 1.3 a level: some 10^9 rays at `max_depth = 64`. The
/// work is bounded before any ray is cast: `render` and `trace` of one
/// pixel refuse it at once, with the estimate and what lowers it.
const GLASS_BOX: &str = r#"
[camera]
position = [0.3, 1.4, -5.0]
look_at = [0.0, 1.0, 0.0]

[render]
width = 1
height = 1
max_depth = 64
min_contribution = 0

[[lights]]
position = [0.0, 5.0, -3.0]

[[objects]]
name = "glass box"
cuboid = { min = [-1.0, 0.0, -1.0], max = [1.0, 2.0, 1.0], rotate_y_degrees = 30.0 }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 1.5, fresnel = "exact" }

[[objects]]
name = "diamond ball"
sphere = { center = [0.2, 1.1, 0.1], radius = 0.6 }
material = { color = [1.0, 1.0, 1.0], ambient = 0.0, diffuse = 0.0, transparency = 1.0, ior = 2.4, fresnel = "exact" }
"#;

/// Runs raylab with `args` in `dir`, killed if it has not ended within
/// `seconds`: `None` then. Its output is read as it comes (a full pipe
/// would stall it).
#[cfg(unix)]
fn output_within(args: &[&str], dir: &Path, seconds: u64) -> Option<std::process::Output> {
    let child = common::command(args, dir)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("spawn");
    let pid = child.id();
    let (sender, receiver) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = sender.send(child.wait_with_output().expect("output"));
    });
    match receiver.recv_timeout(std::time::Duration::from_secs(seconds)) {
        Ok(output) => Some(output),
        Err(_) => {
            // SAFETY: signalling our own child, not yet waited for.
            unsafe {
                libc::kill(pid as libc::pid_t, libc::SIGKILL);
            }
            None
        }
    }
}

#[cfg(unix)]
#[test]
fn an_exponential_ray_tree_is_refused_up_front_with_its_estimate() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(dir.path().join("box.toml"), GLASS_BOX).expect("write");
    for chapter in ["10", "11", "12"] {
        for args in [
            &[
                "render", "--scene", "box.toml", "-c", chapter, "-o", "box.png",
            ][..],
            &[
                "trace", "--scene", "box.toml", "-c", chapter, "--pixel", "0,0",
            ][..],
        ] {
            let out = output_within(args, dir.path(), 60)
                .unwrap_or_else(|| panic!("{args:?} still ran after 60 s"));
            assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
            let text = stderr(&out);
            assert!(text.contains("rays for one pixel"), "{args:?}: {text}");
            assert!(text.contains("max_depth = 64"), "{args:?}: {text}");
            assert!(text.contains("min_contribution"), "{args:?}: {text}");
            assert!(!dir.path().join("box.png").exists());
        }
    }
    // The same scene with a contribution cut: each bounce level then holds
    // at most 1 / min_contribution rays, and the render goes ahead.
    let out = output_within(
        &[
            "render",
            "--scene",
            "box.toml",
            "-c",
            "10",
            "--min-contribution",
            "0.01",
            "-o",
            "box.png",
        ],
        dir.path(),
        60,
    )
    .expect("a bounded render ends");
    assert!(out.status.success(), "{}", stderr(&out));
    // Bounded for one pixel, but not for a 4096x4096 image of them: the
    // render is refused with the image's estimate, one pixel's trace is not.
    let deep = [
        "--scene",
        "box.toml",
        "-c",
        "10",
        "--depth",
        "30",
        "--min-contribution",
        "0.0001",
        "--width",
        "4096",
        "--height",
        "4096",
    ];
    let render: Vec<&str> = ["render"]
        .into_iter()
        .chain(deep)
        .chain(["-o", "big.png"])
        .collect();
    let out = output_within(&render, dir.path(), 60)
        .unwrap_or_else(|| panic!("{render:?} still ran after 60 s"));
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("rays for the 4096x4096 image"),
        "{}",
        stderr(&out)
    );
    assert!(!dir.path().join("big.png").exists());
    let trace: Vec<&str> = ["trace"]
        .into_iter()
        .chain(deep)
        .chain(["--pixel", "2048,2048"])
        .collect();
    let out = output_within(&trace, dir.path(), 120).expect("one pixel's trace ends");
    assert!(out.status.success(), "{}", stderr(&out));
}

/// A full standard output (`> /dev/full`) is an error that says so, exit
/// 2, not "a bug in raylab"; the image written before is kept.
#[cfg(target_os = "linux")]
#[test]
fn an_unwritable_standard_output_is_reported_not_a_panic() {
    let dir = tempfile::tempdir().expect("temp dir");
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full");
    let out = common::command(
        &[
            "render", "-c", "1", "--width", "8", "--height", "6", "-o", "a.png",
        ],
        dir.path(),
    )
    .stdout(full)
    .output()
    .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let text = stderr(&out);
    assert!(
        text.contains("cannot write to the standard output"),
        "{text}"
    );
    assert!(!text.contains("bug in raylab"), "{text}");
    assert!(dir.path().join("a.png").is_file());
}

/// A negative --epsilon is a value out of range, not an unknown option.
#[test]
fn a_negative_epsilon_gets_the_range_message() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = raylab(
        &["render", "-c", "4", "--epsilon", "-1", "-o", "a.png"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("must be a finite number >= 0"),
        "{}",
        stderr(&out)
    );
    assert!(!dir.path().join("a.png").exists());
}

/// A scene render never takes a hand-in's name (`--scene chapter-3.toml`
/// writes `chapter-3-scene.png`, not `chapter-3.png`), and the OBJ models a
/// scene names are inputs no output may replace.
#[test]
fn scene_renders_spare_hand_ins_and_models() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(
        dir.path().join("tri.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .expect("write");
    std::fs::write(
        dir.path().join("chapter-3.toml"),
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n[[objects]]\nmesh = { obj = \"tri.obj\" }\n",
    )
    .expect("write");
    std::fs::write(dir.path().join("chapter-3.png"), "a hand-in").expect("write");
    let small = ["--width", "8", "--height", "6"];
    let mut args = vec!["render", "--scene", "chapter-3.toml"];
    args.extend(small);
    let out = raylab(&args, dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.path().join("chapter-3-scene.png").is_file());
    assert_eq!(
        std::fs::read(dir.path().join("chapter-3.png")).expect("kept"),
        b"a hand-in"
    );
    args.extend(["--stats-json", "tri.obj", "--force"]);
    let out = raylab(&args, dir.path());
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("that is an input"),
        "{}",
        stderr(&out)
    );
    assert!(
        std::fs::read_to_string(dir.path().join("tri.obj"))
            .expect("kept")
            .starts_with("v 0 0 0")
    );
}

/// Text outputs (`render --stats-json`, `diff --json`, `diff --heatmap`,
/// `grade --report` and `--csv`) never replace a file raylab did not write
/// without --force; raylab's own earlier outputs are replaced.
#[test]
fn outputs_spare_files_raylab_did_not_write() {
    let dir = tempfile::tempdir().expect("temp dir");
    let small = ["--width", "16", "--height", "12"];
    let mut render = vec!["render", "-c", "1", "-o", "a.png"];
    render.extend(small);
    assert!(raylab(&render, dir.path()).status.success());
    let foreign = dir.path().join("notes.txt");
    let student = dir.path().join("alice");
    std::fs::create_dir(&student).expect("mkdir");
    std::fs::copy(dir.path().join("a.png"), student.join("chapter-1.png")).expect("copy");
    let cases: Vec<Vec<&str>> = vec![
        [render.clone(), vec!["--stats-json", "notes.txt"]].concat(),
        vec!["diff", "a.png", "a.png", "--json", "notes.txt"],
        vec!["diff", "a.png", "a.png", "--heatmap", "notes.png"],
        vec!["grade", "alice", "--report", "notes.txt"],
        vec!["grade", "alice", "--csv", "notes.txt"],
    ];
    for args in cases {
        std::fs::write(&foreign, "someone's notes").expect("write");
        std::fs::write(dir.path().join("notes.png"), "someone's picture").expect("write");
        let out = raylab(&args, dir.path());
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(
            stderr(&out).contains("raylab did not write it"),
            "{args:?}: {}",
            stderr(&out)
        );
        assert_eq!(
            std::fs::read_to_string(&foreign).expect("kept"),
            "someone's notes"
        );
        assert_eq!(
            std::fs::read_to_string(dir.path().join("notes.png")).expect("kept"),
            "someone's picture"
        );
        let forced = [args.clone(), vec!["--force"]].concat();
        let out = raylab(&forced, dir.path());
        assert!(
            out.status.code().is_some_and(|code| code < 2),
            "{forced:?}: {}",
            stderr(&out)
        );
        // raylab's own output is replaced without --force.
        let out = raylab(&args, dir.path());
        assert!(
            out.status.code().is_some_and(|code| code < 2),
            "{args:?} again: {}",
            stderr(&out)
        );
    }
}

/// `--without` leaves effects out, says so in the stats, warns about an
/// effect the chapter does not have, and refuses a name that is no effect.
#[test]
fn without_leaves_effects_out_and_names_the_ones_it_knows() {
    let dir = tempfile::tempdir().expect("temp dir");
    let small = ["--width", "40", "--height", "30", "--stats"];
    let out = raylab(
        &[
            &["render", "-c", "8", "--without", "refraction,reflection"],
            &small[..],
        ]
        .concat(),
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("effects simulated: planes, spheres, nearest-hit, phong-diffuse, shadows, phong-specular, antialiasing\n"), "{text}");
    let out = raylab(
        &[&["render", "-c", "3", "--without", "bvh"], &small[..]].concat(),
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("warning: --without bvh has no effect at chapter 3"),
        "{}",
        stderr(&out)
    );
    let out = raylab(
        &[&["render", "-c", "3", "--without", "shadow"], &small[..]].concat(),
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("`shadow` is not an effect that can be switched off"),
        "{}",
        stderr(&out)
    );
}
