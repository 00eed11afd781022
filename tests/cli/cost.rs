//! `raylab cost`: the sweep, its files, and its errors. No test reads the
//! times (machines are noisy); they check what the sweep rendered and how
//! far each setting is from the reference.

use crate::common;
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
    assert_eq!(jittered_64.rays.of(raylab::RayKind::Primary), 32 * 24 * 64);
    let front = report.rows.iter().filter(|row| row.pareto).count();
    assert!(front >= 2, "a Pareto front of {front}");
}

/// The lab report's anti-aliasing is a blur: on a checker of one-pixel
/// squares, which one ray a pixel draws exactly, its mean of five pixels
/// turns the squares over (each pixel's four neighbours are of the other
/// colour), where supersampling keeps them; it is the same image whether
/// the neighbours' colours are reused or their rays cast again.
#[test]
fn the_reports_neighbour_average_is_a_blur() {
    use raylab::Reference;
    use raylab::cost::neighbours::{self, Method};
    // An odd height: the squares move by half a pixel to stay on the grid.
    let (width, height) = (12u32, 9u32);
    let checker = neighbours::one_pixel_checker(width, height);
    let base = raylab::RenderSettings {
        width,
        height,
        ..checker.render
    };
    let image = |method| {
        let settings = neighbours::settings_for(method, &base);
        neighbours::render::<Reference>(&checker, 7, settings, method).expect("renders")
    };
    let centre = image(Method::Centre);
    let at = |image: &[raylab::Vec3], x: u32, y: u32| image[(y * width + x) as usize].x;
    for y in 0..height {
        for x in 0..width {
            let value = at(&centre, x, y);
            assert!(value == 0.0 || value == 1.0, "({x}, {y}): {value}");
            if x + 1 < width {
                assert_ne!(value, at(&centre, x + 1, y), "({x}, {y})");
            }
            if y + 1 < height {
                assert_ne!(value, at(&centre, x, y + 1), "({x}, {y})");
            }
        }
    }
    let averaged = image(Method::Averaged);
    let (x, y) = (5, 4);
    let turned = if at(&centre, x, y) == 1.0 { 0.2 } else { 0.8 };
    assert!((at(&averaged, x, y) - turned).abs() < 1e-6);
    assert_eq!(averaged, image(Method::AveragedTraced));
    // Every sample lies inside its pixel, so in its square: a pixel could
    // differ only by a sample within rounding of a square's edge (a quarter).
    let supersampled = image(Method::Supersampled);
    for (kept, drawn) in supersampled.iter().zip(&centre) {
        assert!((kept.x - drawn.x).abs() <= 0.25, "{kept} against {drawn}");
    }

    let scene = raylab::builtin::scene(7).expect("built-in scene");
    let base = raylab::RenderSettings {
        width: 32,
        height: 24,
        ..scene.render
    };
    let report =
        neighbours::run::<Reference>(&scene, "built-in scene", 7, &base, 1).expect("measures");
    let row = |method| {
        report
            .rows
            .iter()
            .find(|row| row.method == method)
            .expect("a row for each method")
    };
    assert!(row(Method::Centre).contrast > 0.99);
    assert!(row(Method::Supersampled).contrast > 0.99);
    assert!(row(Method::Averaged).contrast < -0.3);
    assert_eq!(
        row(Method::Averaged).error,
        row(Method::AveragedTraced).error
    );
    assert!(report.edge_pixels > 0);
    assert!(row(Method::Supersampled).edge_rmse < row(Method::Centre).edge_rmse);
    assert!(row(Method::Supersampled).error.rmse < row(Method::Averaged).error.rmse);
    let markdown = report.markdown();
    assert!(markdown.contains("| method | rays a pixel |"), "{markdown}");
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
    // The sweep's header and rows, then the neighbours' header and rows.
    let methods = raylab::cost::neighbours::Method::ALL.len();
    assert_eq!(
        markdown.lines().filter(|l| l.starts_with("| ")).count(),
        1 + 29 + 1 + methods
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

/// Chapter 11's report at tiny sizes: every tree finds brute force's hits,
/// the figures sit in the right columns, and the crossover is in range.
#[test]
fn bvh_report_matches_brute_force_at_small_sizes() {
    use raylab::bvh_reports::cost::{BvhCostOptions, CROSSOVER_MAX_SPHERES};
    let report = raylab::bvh_reports::cost::run(&BvhCostOptions {
        repeats: 3,
        max_triangles: 1_000,
    })
    .expect("report");
    let triangles: Vec<usize> = report.scaling.iter().map(|row| row.triangles).collect();
    assert_eq!(triangles, [18, 104, 1_008]);
    for row in &report.scaling {
        assert_eq!(row.tree.mismatches, Some(0), "{} triangles", row.triangles);
        let brute = row.brute_force.as_ref().expect("brute force up to 10k");
        assert_eq!(row.tree.hits, brute.hits);
        assert!(brute.hits > 0);
    }
    // Not timing assertions but column checks, each by a factor of 50 or
    // more: building a 5-node tree takes microseconds, tracing 4096 rays
    // hundreds of them; at a thousand triangles the loop tests every one
    // for every ray, the tree a few dozen.
    let smallest = &report.scaling[0].tree;
    assert!(smallest.trace > smallest.build * 10, "{smallest:?}");
    let largest = &report.scaling[2];
    let brute = largest.brute_force.as_ref().expect("brute force");
    assert!(brute.trace > largest.tree.trace * 5, "{largest:?}");

    let split = report.split.as_ref().expect("a split table");
    assert_eq!(split.triangles, 1_008);
    assert!(split.checked);
    assert_eq!(split.trees.len(), 8);
    for tree in &split.trees {
        assert_eq!(tree.mismatches, Some(0), "{:?}", tree.method);
    }

    let crossover = &report.crossover;
    assert_eq!(crossover.rows.len(), CROSSOVER_MAX_SPHERES);
    assert!(crossover.rows.iter().all(|row| row.mismatches == 0));
    let from = crossover.from.expect("the tree wins at 64 spheres");
    assert!((1..=CROSSOVER_MAX_SPHERES).contains(&from), "{from}");
    assert_eq!(report.mismatches(), 0);
}

#[test]
fn cost_command_writes_the_bvh_report_and_its_plot() {
    let dir = tempfile::tempdir().expect("temp dir");
    let args = [
        "cost",
        "--chapter",
        "11",
        "--knob",
        "bvh",
        "--max-triangles",
        "1000",
        "--repeats",
        "1",
        "--out",
        "bvh",
    ];
    let out = raylab(&args, dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let folder = dir.path().join("bvh");
    let mut written: Vec<String> = std::fs::read_dir(&folder)
        .expect("folder")
        .map(|entry| entry.expect("entry").file_name().to_string_lossy().into())
        .collect();
    written.sort();
    assert_eq!(written, ["bvh-scaling.svg", "cost.md"]);
    let markdown = std::fs::read_to_string(folder.join("cost.md")).expect("cost.md");
    assert!(markdown.contains("| triangles | build (ms) | trace (ms) |"));
    assert!(markdown.contains("| SAH | 4 |") && markdown.contains("| midpoint | 8 |"));
    assert!(
        markdown.contains("The tree is faster from k = "),
        "{markdown}"
    );
    assert!(markdown.contains(
        "Reproduce with `raylab cost --chapter 11 --repeats 1 --knob bvh --max-triangles 1000 --out bvh`"
    ));
    // Three sizes up to 1,000 (18, 104, 1,008 triangles), none above.
    assert!(markdown.contains("| 1,008 |") && !markdown.contains("| 10,032 |"));
    let svg = std::fs::read_to_string(folder.join("bvh-scaling.svg")).expect("svg");
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("SAH tree: build") && svg.contains("brute force: trace"));

    // The report's size cap without the report, and the report before
    // chapter 11, are refused before anything is written.
    let empty = tempfile::tempdir().expect("temp dir");
    let output = raylab(
        &["cost", "-c", "10", "--max-triangles", "1000"],
        empty.path(),
    );
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("--max-triangles"),
        "{}",
        stderr(&output)
    );
    let output = raylab(&["cost", "-c", "10", "--knob", "bvh"], empty.path());
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("chapter 10 has no bvh knob"));
    let output = raylab(
        &["cost", "-c", "11", "--knob", "bvh", "--max-triangles", "5"],
        empty.path(),
    );
    assert_eq!(output.status.code(), Some(2));
    std::fs::write(empty.path().join("scene.toml"), "").expect("write");
    let output = raylab(
        &["cost", "-c", "11", "--knob", "bvh", "--scene", "scene.toml"],
        empty.path(),
    );
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("--scene"), "{}", stderr(&output));
    std::fs::remove_file(empty.path().join("scene.toml")).expect("remove");
    assert_eq!(std::fs::read_dir(empty.path()).expect("dir").count(), 0);
}
