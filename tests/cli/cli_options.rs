//! Options the chosen chapter ignores are never ignored without a word, and
//! `--help` shows every default, and no option is taken and ignored without a word.

use crate::common;
use common::{raylab, stderr, stdout};

use raylab::RenderSettings;

/// Renders in a fresh folder and returns (exit status, stderr, image hash).
fn render(args: &[&str], scene: Option<&str>) -> (Option<i32>, String, String) {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut all = vec![
        "render",
        "--width",
        "32",
        "--height",
        "24",
        "-o",
        "out.png",
        "--stats-json",
        "stats.json",
    ];
    if let Some(text) = scene {
        std::fs::write(dir.path().join("scene.toml"), text).expect("write scene");
        all.extend(["--scene", "scene.toml"]);
    }
    all.extend(args);
    let out = raylab(&all, dir.path());
    let hash = std::fs::read_to_string(dir.path().join("stats.json"))
        .ok()
        .and_then(|json| serde_json::from_str::<serde_json::Value>(&json).ok())
        .and_then(|json| json["image_fnv1a64"].as_str().map(str::to_string))
        .unwrap_or_default();
    (out.status.code(), stderr(&out), hash)
}

fn warnings(text: &str) -> Vec<&str> {
    text.lines()
        .filter(|line| line.starts_with("warning: "))
        .collect()
}

#[test]
fn epsilon_implies_a_fixed_ray_offset() {
    let (status, message, scaled) = render(&["--chapter", "4"], None);
    assert_eq!(status, Some(0), "{message}");
    // A push of two units skips blockers near the surface (the contact
    // shadows under the balls): an image unlike the scaled rule's. (No push
    // at all would not do: chapter 2's stable sphere test and the exact
    // floor of this scene show no acne.)
    let (status, message, implied) = render(&["--chapter", "4", "--epsilon", "2"], None);
    assert_eq!(status, Some(0), "{message}");
    assert!(warnings(&message).is_empty(), "{message}");
    let (_, _, explicit) = render(
        &["--chapter", "4", "--ray-offset", "fixed", "--epsilon", "2"],
        None,
    );
    // An --epsilon taken and dropped would give the scaled image.
    assert_eq!(implied, explicit);
    assert_ne!(implied, scaled);
    // Asked for both ways at once, the explicit rule wins, with a warning.
    let (status, message, both) = render(
        &[
            "--chapter",
            "4",
            "--ray-offset",
            "scaled",
            "--epsilon",
            "0.5",
        ],
        None,
    );
    assert_eq!(status, Some(0), "{message}");
    assert_eq!(both, scaled);
    assert_eq!(
        warnings(&message),
        [
            "warning: --epsilon has no effect with --ray-offset scaled: it is the distance of --ray-offset fixed"
        ]
    );
}

#[test]
fn options_the_chapter_does_not_use_draw_a_warning() {
    let cases: &[(&[&str], &str)] = &[
        (
            &["--chapter", "4", "--samples", "16"],
            "warning: --samples 16 has no effect at chapter 4",
        ),
        (
            &["--chapter", "6", "--sampling", "grid"],
            "warning: --sampling has no effect at chapter 6",
        ),
        (
            &["--chapter", "5", "--seed", "3"],
            "warning: --seed has no effect at chapter 5",
        ),
        (
            &["--chapter", "5", "--depth", "2"],
            "warning: --depth has no effect at chapter 5",
        ),
        (
            &["--chapter", "3", "--epsilon", "0.5"],
            "warning: --epsilon has no effect at chapter 3",
        ),
        (
            &["--chapter", "3", "--ray-offset", "fixed"],
            "warning: --ray-offset has no effect at chapter 3",
        ),
        (
            &["--chapter", "1", "--sphere-formula", "textbook"],
            "warning: --sphere-formula has no effect at chapter 1",
        ),
        (
            &["--chapter", "7", "--samples", "1", "--sampling", "grid"],
            "warning: --sampling has no effect with 1 sample per pixel",
        ),
        (
            &[
                "--chapter",
                "14",
                "--samples",
                "1",
                "--without",
                "light-tracing",
                "--light-paths",
                "4",
            ],
            "warning: --light-paths has no effect with --without light-tracing",
        ),
    ];
    for (args, expected) in cases {
        let (status, message, _) = render(args, None);
        assert_eq!(status, Some(0), "{args:?}: {message}");
        let found = warnings(&message);
        assert_eq!(found.len(), 1, "{args:?}: {message}");
        assert!(found[0].starts_with(expected), "{args:?}: {message}");
    }
    // Options the chapter uses draw none.
    for args in [
        &["--chapter", "7", "--samples", "16", "--sampling", "grid"][..],
        &["--chapter", "6", "--depth", "2", "--min-contribution", "0"],
        &[
            "--chapter",
            "4",
            "--ray-offset",
            "fixed",
            "--epsilon",
            "0.01",
        ],
        &["--chapter", "2", "--sphere-formula", "textbook"],
        &["--chapter", "4", "--samples", "1"],
    ] {
        let (status, message, _) = render(args, None);
        assert_eq!(status, Some(0), "{args:?}: {message}");
        assert!(warnings(&message).is_empty(), "{args:?}: {message}");
    }
}

#[test]
fn a_scene_without_lights_draws_a_warning_from_chapter_4_on() {
    let dark = r#"
[camera]
position = [0.0, 1.0, -5.0]
look_at = [0.0, 1.0, 0.0]

[[objects]]
sphere = { center = [0.0, 1.0, 0.0], radius = 1.0 }
"#;
    for chapter in ["4", "8"] {
        let (status, message, _) = render(&["--chapter", chapter], Some(dark));
        assert_eq!(status, Some(0), "{message}");
        let found = warnings(&message);
        assert_eq!(found.len(), 1, "{message}");
        assert!(found[0].contains("the scene has no lights"), "{message}");
        assert!(found[0].contains("[[lights]]"), "{message}");
    }
    // Before chapter 4 nothing is lit anyway.
    let (_, message, _) = render(&["--chapter", "3"], Some(dark));
    assert!(warnings(&message).is_empty(), "{message}");
}

/// `render --help`, cut into one block of text per option.
fn option_blocks() -> Vec<(String, String)> {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = raylab(&["render", "--help"], dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let help = stdout(&out);
    let mut blocks: Vec<(String, String)> = Vec::new();
    for line in help.lines() {
        let trimmed = line.trim_start();
        let is_option =
            line.starts_with("  ") && trimmed.starts_with('-') && !line.starts_with("          ");
        if is_option {
            let long = trimmed
                .split_whitespace()
                .find(|word| word.starts_with("--"))
                .unwrap_or(trimmed)
                .to_string();
            blocks.push((long, line.to_string()));
        } else if let Some((_, block)) = blocks.last_mut() {
            block.push('\n');
            block.push_str(line);
        }
    }
    blocks
}

#[test]
fn render_help_shows_every_default() {
    let blocks = option_blocks();
    let defaults = RenderSettings::default();
    let expected = [
        (
            "--chapter",
            "the last chapter when --scene is given".to_string(),
        ),
        ("--scene", "the chapter's built-in scene".into()),
        ("--width", format!("{}", defaults.width)),
        ("--height", format!("{}", defaults.height)),
        ("--samples", format!("else {}", defaults.samples)),
        (
            "--sampling",
            format!("{:?}", defaults.sampling).to_lowercase(),
        ),
        ("--depth", format!("else {}", defaults.max_depth)),
        (
            "--min-contribution",
            format!("else {}", defaults.min_contribution),
        ),
        ("--seed", format!("else {}", defaults.seed)),
        (
            "--sphere-formula",
            format!("else {:?}", defaults.sphere_formula).to_lowercase(),
        ),
        (
            "--ray-offset",
            format!("else {:?}", defaults.ray_offset).to_lowercase(),
        ),
        ("--triangle-test", "else watertight".into()),
        (
            "--terminator",
            format!("else {:?}", defaults.terminator).to_lowercase(),
        ),
        ("--epsilon", format!("else {}", defaults.fixed_epsilon)),
        ("--without", "the scene's `without`, else none".into()),
        ("--light-paths", format!("else {}", defaults.light_paths)),
        ("--threads", "one per core".into()),
        ("--output", "chapter-N.png".into()),
        ("--stats-json", "none written".into()),
    ];
    for (option, value) in &expected {
        let (_, block) = blocks
            .iter()
            .find(|(long, _)| long == option)
            .unwrap_or_else(|| panic!("{option} not in render --help"));
        let default = block
            .split("[default: ")
            .nth(1)
            .and_then(|rest| rest.split(']').next())
            .unwrap_or_else(|| panic!("{option} shows no default: {block}"));
        assert!(
            default.contains(value.as_str()),
            "{option}: [default: {default}] lacks {value}"
        );
    }
    // Every option that takes a value is listed above; flags (--stats,
    // --help) have nothing to show.
    for (long, block) in &blocks {
        let takes_value = block.lines().next().is_some_and(|line| line.contains('<'));
        if takes_value {
            assert!(
                expected.iter().any(|(option, _)| option == long),
                "{long} is new: give it a [default: ...] and list it here"
            );
        }
    }
}

/// `raylab race --triangles` takes the sizes a scene can load, and says so
/// for anything else (clap's own message said only "invalid digit").
#[test]
fn race_sizes_out_of_range_are_named_with_the_range() {
    for size in ["abc", "0", "4000001", "1e3", "-5", ""] {
        // As one word and as two (`--triangles -5` is no flag).
        let joined = format!("--triangles={size}");
        let out = raylab(&["race", &joined], std::path::Path::new("."));
        let text = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{size:?}: {text}");
        assert!(text.contains("from 1 to 4000000"), "{size:?}: {text}");
        let out = raylab(&["race", "--triangles", size], std::path::Path::new("."));
        let text = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{size:?}: {text}");
        assert!(
            text.contains("each model size in triangles must be a whole number from 1 to 4000000"),
            "{size:?}: {text}"
        );
    }
}
