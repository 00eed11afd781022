//! The `raylab` command as a student meets it: renders, listings, and clear
//! errors with a non-zero exit and no output file for every kind of bad input.

mod common;
use common::{raylab, stderr, stdout};

use std::path::Path;
use std::process::Command;

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

#[test]
fn chapters_lists_all_eight() {
    let out = raylab(&["chapters"], Path::new("."));
    assert!(out.status.success());
    let text = stdout(&out);
    assert_eq!(text.lines().count(), 8);
    assert!(
        text.lines()
            .nth(7)
            .expect("line 8")
            .starts_with("8  Refraction")
    );
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
        stdout(&out).starts_with("chapter 8:"),
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
    let out = raylab(&["render", "--chapter", "9"], Path::new("."));
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("9"));
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

#[test]
fn probe_refuses_a_malformed_ray() {
    for bad in ["1,2,3", "0,0,0,0,0,0", "0,0,0,1,nan,0", "a,b,c,d,e,f"] {
        let out = raylab(&["probe", "--ray", bad], Path::new("."));
        assert_eq!(out.status.code(), Some(2), "{bad}");
        assert!(stderr(&out).contains("--ray"), "{bad}: {}", stderr(&out));
    }
}

/// Without the `embree` feature, `crosscheck` explains how to get it
/// (scripts/test.sh runs this file once without the feature).
#[cfg(not(feature = "embree"))]
#[test]
fn crosscheck_without_embree_says_how_to_enable_it() {
    let out = raylab(&["crosscheck", "--chapter", "1"], Path::new("."));
    assert_eq!(out.status.code(), Some(2));
    let message = stderr(&out);
    assert!(message.contains("scripts/setup-embree.sh"), "{message}");
    assert!(message.contains("--features embree"), "{message}");
    assert!(message.contains("docs/embree.md"), "{message}");
    let probe = raylab(&["probe", "--ray", "0,1,-5,0,0,1"], Path::new("."));
    assert!(probe.status.success(), "{}", stderr(&probe));
    assert!(stdout(&probe).contains("embree: not built in"));
}

#[cfg(unix)]
#[test]
fn a_closed_pipe_stops_quietly_without_a_panic() {
    // `raylab scene --chapter 8 | head -0`: the reader has gone before
    // raylab writes. Close the pipe's read end before the child starts, so
    // its first write surely meets a closed pipe.
    use std::os::fd::{FromRawFd, OwnedFd};
    let mut ends = [0; 2];
    // SAFETY: `pipe` fills the two descriptors, which we then own.
    assert_eq!(unsafe { libc::pipe(ends.as_mut_ptr()) }, 0, "pipe");
    let (read_end, write_end) =
        unsafe { (OwnedFd::from_raw_fd(ends[0]), OwnedFd::from_raw_fd(ends[1])) };
    drop(read_end);
    let out = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(["scene", "--chapter", "8"])
        .stdout(std::process::Stdio::from(write_end))
        .output()
        .expect("run raylab");
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
