//! `raylab cost`: the sweep, its files, and its errors. No test reads the
//! times (machines are noisy); they check what the sweep rendered and how
//! far each setting is from the reference.

mod common;
use common::{raylab, stderr};

use raylab::cost::{CostConfig, Knob};

#[test]
fn error_falls_as_samples_rise() {
    let scene = raylab::builtin::scene(7).expect("built-in scene");
    let config = CostConfig {
        chapter: 7,
        base: raylab::RenderSettings {
            width: 32,
            height: 24,
            ..scene.render
        },
        scene,
        scene_name: "built-in scene".into(),
        knobs: vec![Knob::Samples],
        repeats: 1,
    };
    // The reference, one 1 spp row (a lone sample is the pixel centre, so
    // the three placements would be three identical rows), then 4, 16 and 64
    // spp for each placement.
    assert_eq!(raylab::cost::render_count(&config), 1 + 1 + 9);
    let report = raylab::cost::run::<raylab::Reference>(&config, None).expect("sweep");
    assert_eq!(report.rows.len(), 1 + 1 + 9);
    let centre = report
        .rows
        .iter()
        .find(|row| row.label == "1 spp (pixel centre)")
        .expect("a 1 spp row");
    assert!(report.rows[0].knob.is_none());
    assert_eq!(report.rows[0].error.rmse, 0.0);
    for sampling in ["grid", "jittered", "random"] {
        let errors: Vec<f64> = std::iter::once(centre)
            .chain(
                report
                    .rows
                    .iter()
                    .filter(|row| row.label.starts_with(sampling)),
            )
            .map(|row| row.error.rmse)
            .collect();
        assert_eq!(errors.len(), 4, "{sampling}");
        assert!(errors[0] > errors[3] * 2.0, "{sampling}: {errors:?}");
        if sampling != "random" {
            assert!(
                errors.windows(2).all(|w| w[0] > w[1]),
                "{sampling}: {errors:?}"
            );
        }
    }
    // The rays cast grow with the samples: 32 x 24 primary rays per sample.
    let jittered_64 = report
        .rows
        .iter()
        .find(|row| row.label == "jittered 64 spp")
        .expect("a jittered 64 spp row");
    assert_eq!(jittered_64.rays.primary, 32 * 24 * 64);
    let front = report.rows.iter().filter(|row| row.pareto).count();
    assert!(front >= 2, "a Pareto front of {front}");
}

#[test]
fn cost_command_writes_a_table_a_csv_and_a_plot() {
    let dir = tempfile::tempdir().expect("temp dir");
    let args = [
        "cost",
        "--chapter",
        "8",
        "--width",
        "24",
        "--height",
        "18",
        "--repeats",
        "1",
        "--out",
        "sweep",
    ];
    let out = raylab(&args, dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("| knob | setting | time (ms) |"),
        "{stdout}"
    );
    assert!(stdout.contains(
        "Reproduce with `raylab cost --chapter 8 --width 24 --height 18 --repeats 1 --out sweep`"
    ));

    let folder = dir.path().join("sweep");
    let csv = std::fs::read_to_string(folder.join("cost.csv")).expect("cost.csv");
    let lines: Vec<&str> = csv.lines().collect();
    assert!(lines[0].starts_with("chapter,scene,knob,setting,"));
    let count = |knob: &str| {
        lines[1..]
            .iter()
            .filter(|line| line.split(',').nth(2) == Some(knob))
            .count()
    };
    assert_eq!(count("reference"), 2, "main scene and far sphere");
    assert_eq!(count("samples"), 10);
    assert_eq!(count("depth"), 9);
    assert_eq!(count("offset"), 6);
    assert_eq!(count("sphere-formula"), 2);
    assert_eq!(lines.len(), 1 + 29);
    // Without an offset, shadow rays find their own surface: acne.
    let acne = |setting: &str| -> u64 {
        let line = lines
            .iter()
            .find(|line| line.split(',').nth(3) == Some(setting))
            .unwrap_or_else(|| panic!("no row {setting}"));
        let column = lines[0]
            .split(',')
            .position(|name| name == "self_shadowed_pixels")
            .expect("an acne column");
        line.split(',')
            .nth(column)
            .expect("a value")
            .parse()
            .expect("a count")
    };
    assert!(acne("no offset (epsilon 0)") > 0);
    assert_eq!(acne("scaled offset"), 0);

    let markdown = std::fs::read_to_string(folder.join("cost.md")).expect("cost.md");
    assert_eq!(
        markdown.lines().filter(|l| l.starts_with("| ")).count(),
        1 + 29
    );
    let svg = std::fs::read_to_string(folder.join("cost.svg")).expect("cost.svg");
    assert!(svg.starts_with("<svg"));
    assert!(svg.contains("<text") && svg.contains("Pareto front"));
    assert!(svg.trim_end().ends_with("</svg>"));
}

#[test]
fn bad_output_folder_is_a_clean_error() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(dir.path().join("taken"), "a file").expect("write file");
    for out in ["taken", "taken/below"] {
        let output = raylab(
            &[
                "cost", "-c", "2", "--width", "8", "--height", "6", "--out", out,
            ],
            dir.path(),
        );
        assert_eq!(output.status.code(), Some(2), "--out {out}");
        let message = stderr(&output);
        assert!(message.starts_with("error: "), "{message}");
        assert!(message.contains("taken"), "{message}");
        assert!(!message.contains("panicked"), "{message}");
    }
    assert_eq!(
        std::fs::read_to_string(dir.path().join("taken")).expect("still there"),
        "a file"
    );
}

#[test]
fn knobs_a_chapter_does_not_have_are_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let output = raylab(&["cost", "-c", "6", "--knob", "samples"], dir.path());
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("chapter 6 has no samples knob"));
    let output = raylab(&["cost", "-c", "1"], dir.path());
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("no accuracy knob"));
    let output = raylab(&["cost", "-c", "4", "--repeats", "0"], dir.path());
    assert_eq!(output.status.code(), Some(2));
    // Nothing was rendered or written.
    assert_eq!(std::fs::read_dir(dir.path()).expect("dir").count(), 0);
}
