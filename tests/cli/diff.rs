//! `raylab diff` on real renders: the metrics it prints are checked against
//! values computed here independently, from the two images' bytes.

use crate::common;
use common::{raylab, stderr, stdout};

use std::path::{Path, PathBuf};

const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;

/// Renders a chapter's built-in scene at the test size with `tweak` applied.
fn render(chapter: u8, tweak: impl FnOnce(&mut raylab::RenderSettings)) -> raylab::Rendered {
    let scene = raylab::builtin::scene(chapter).expect("built-in scene");
    let mut settings = raylab::RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        ..scene.render
    };
    tweak(&mut settings);
    raylab::render(&scene, chapter, &settings, None).expect("renders")
}

fn save(dir: &Path, name: &str, rgb: &[u8]) -> PathBuf {
    let path = dir.join(name);
    raylab::output::write_png(&path, WIDTH, HEIGHT, rgb).expect("write PNG");
    path
}

fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("JSON written")).expect("JSON")
}

/// The metrics of the module docs, computed the plain way.
struct Expected {
    max: u8,
    mean: f64,
    rmse: f64,
    pixels_over: u64,
}

fn expected(a: &[u8], b: &[u8], threshold: u8) -> Expected {
    let diffs: Vec<f64> = a
        .iter()
        .zip(b)
        .map(|(&x, &y)| (f64::from(x) - f64::from(y)).abs())
        .collect();
    let n = diffs.len() as f64;
    let pixels_over = diffs
        .chunks(3)
        .filter(|p| p.iter().any(|&d| d > f64::from(threshold)))
        .count() as u64;
    Expected {
        max: diffs.iter().fold(0.0f64, |m, &d| m.max(d)) as u8,
        mean: diffs.iter().sum::<f64>() / n,
        rmse: (diffs.iter().map(|d| d * d).sum::<f64>() / n).sqrt(),
        pixels_over,
    }
}

fn assert_close(actual: &serde_json::Value, expected: f64, what: &str) {
    let actual = actual
        .as_f64()
        .unwrap_or_else(|| panic!("{what} is a number"));
    assert!(
        (actual - expected).abs() <= 1e-9 * expected.abs().max(1.0),
        "{what}: {actual} != {expected}"
    );
}

fn check_against(json: &serde_json::Value, e: &Expected) {
    assert_eq!(json["max_abs_difference"], u64::from(e.max));
    assert_close(&json["mean_abs_difference"], e.mean, "mean");
    assert_close(&json["rmse"], e.rmse, "rmse");
    assert_close(&json["psnr_db"], 20.0 * (255.0 / e.rmse).log10(), "psnr_db");
    assert_eq!(json["pixels_over_threshold"], e.pixels_over);
    assert_eq!(json["pixels"], u64::from(WIDTH * HEIGHT));
}

#[test]
fn identical_renders_pass_with_zero_difference() {
    let dir = tempfile::tempdir().expect("temp dir");
    let image = render(6, |_| {});
    save(dir.path(), "a.png", &image.rgb);
    save(dir.path(), "b.png", &render(6, |_| {}).rgb);
    let out = raylab(
        &[
            "diff",
            "a.png",
            "b.png",
            "--heatmap",
            "heat.png",
            "--json",
            "m.json",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    for line in [
        "max abs difference: 0\n",
        "mean abs difference: 0.000000\n",
        "RMSE: 0.000000\n",
        "PSNR: inf dB\n",
        "pixels over threshold 2: 0 of 3072",
        "result: PASS\n",
    ] {
        assert!(text.contains(line), "{line:?} not in:\n{text}");
    }
    let json = read_json(&dir.path().join("m.json"));
    assert_eq!(json["max_abs_difference"], 0);
    assert_eq!(json["mean_abs_difference"], 0.0);
    assert_eq!(json["rmse"], 0.0);
    assert!(json["psnr_db"].is_null(), "infinite PSNR is null in JSON");
    assert_eq!(json["max_at"], serde_json::Value::Null);
    assert_eq!(json["pass"], true);
    // Nothing differs: the picture part of the heatmap is all grey.
    let heat = image::open(dir.path().join("heat.png"))
        .expect("heatmap")
        .to_rgb8();
    assert_eq!(heat.width(), WIDTH);
    assert!(heat.height() > HEIGHT, "a legend strip below the image");
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let [r, g, b] = heat.get_pixel(x, y).0;
            assert!(r == g && g == b, "pixel ({x}, {y}) is coloured");
        }
    }
}

#[test]
fn one_changed_pixel_is_measured_and_located() {
    let dir = tempfile::tempdir().expect("temp dir");
    let original = render(5, |_| {});
    let (x, y) = (41u32, 17u32);
    let mut changed = original.rgb.clone();
    let green = 3 * (y * WIDTH + x) as usize + 1;
    // Move the green value 10 levels, away from whichever end is nearer.
    changed[green] = if changed[green] >= 128 {
        changed[green] - 10
    } else {
        changed[green] + 10
    };
    save(dir.path(), "student.png", &changed);
    save(dir.path(), "reference.png", &original.rgb);
    let out = raylab(
        &[
            "diff",
            "student.png",
            "reference.png",
            "--heatmap",
            "heat.png",
            "--json",
            "m.json",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    // Derived by hand: one value of 3 W H differs, by 10.
    let values = f64::from(3 * WIDTH * HEIGHT);
    let json = read_json(&dir.path().join("m.json"));
    assert_eq!(json["max_abs_difference"], 10);
    assert_close(&json["mean_abs_difference"], 10.0 / values, "mean");
    assert_close(&json["rmse"], (100.0 / values).sqrt(), "rmse");
    assert_close(
        &json["psnr_db"],
        20.0 * (255.0 / (100.0 / values).sqrt()).log10(),
        "psnr_db",
    );
    assert_eq!(json["max_at"], serde_json::json!({"x": x, "y": y}));
    assert_eq!(json["pixels_over_threshold"], 1);
    assert_eq!(json["pass"], false);
    let text = stdout(&out);
    assert!(
        text.contains("max abs difference: 10 (first at x=41, y=17)"),
        "{text}"
    );
    assert!(text.contains("result: FAIL"), "{text}");

    // The heatmap's one hot pixel is the changed one; all others are grey.
    let heat = image::open(dir.path().join("heat.png"))
        .expect("heatmap")
        .to_rgb8();
    let coloured: Vec<(u32, u32, [u8; 3])> = (0..HEIGHT)
        .flat_map(|py| (0..WIDTH).map(move |px| (px, py)))
        .map(|(px, py)| (px, py, heat.get_pixel(px, py).0))
        .filter(|(_, _, [r, g, b])| !(r == g && g == b))
        .collect();
    assert_eq!(coloured, vec![(x, y, raylab::diff::HOTTEST)]);

    // A difference of exactly the threshold is within it.
    let at_threshold = raylab(
        &["diff", "student.png", "reference.png", "--threshold", "10"],
        dir.path(),
    );
    assert_eq!(
        at_threshold.status.code(),
        Some(0),
        "{}",
        stdout(&at_threshold)
    );
    // So is one pixel of 3072 when 0.05% may be over.
    let allowed = raylab(
        &["diff", "student.png", "reference.png", "--allow", "0.05"],
        dir.path(),
    );
    assert_eq!(allowed.status.code(), Some(0), "{}", stdout(&allowed));
}

#[test]
fn another_depth_fails_with_the_expected_metrics() {
    let dir = tempfile::tempdir().expect("temp dir");
    let reference = render(6, |_| {});
    let shallow = render(6, |s| s.max_depth = 1);
    save(dir.path(), "shallow.png", &shallow.rgb);
    save(dir.path(), "reference.png", &reference.rgb);
    let out = raylab(
        &["diff", "shallow.png", "reference.png", "--json", "m.json"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let e = expected(&shallow.rgb, &reference.rgb, 2);
    assert!(
        e.pixels_over > 0,
        "depth 1 must change the mirror reflections"
    );
    let json = read_json(&dir.path().join("m.json"));
    check_against(&json, &e);
    assert_eq!(json["pass"], false);
}

#[test]
fn another_sample_count_fails_with_the_expected_metrics() {
    let dir = tempfile::tempdir().expect("temp dir");
    let reference = render(7, |_| {});
    let aliased = render(7, |s| s.samples = 1);
    save(dir.path(), "aliased.png", &aliased.rgb);
    save(dir.path(), "reference.png", &reference.rgb);
    let out = raylab(
        &[
            "diff",
            "aliased.png",
            "reference.png",
            "--threshold",
            "5",
            "--json",
            "m.json",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let e = expected(&aliased.rgb, &reference.rgb, 5);
    assert!(e.pixels_over > 0, "1 sample per pixel must alias the edges");
    let json = read_json(&dir.path().join("m.json"));
    check_against(&json, &e);
    // And the printed figures agree with the JSON.
    let text = stdout(&out);
    assert!(text.contains(&format!("RMSE: {:.6}\n", e.rmse)), "{text}");
    assert!(
        text.contains(&format!(
            "PSNR: {:.2} dB\n",
            20.0 * (255.0 / e.rmse).log10()
        )),
        "{text}"
    );
    assert!(
        text.contains(&format!(
            "pixels over threshold 5: {} of 3072",
            e.pixels_over
        )),
        "{text}"
    );
}

/// Bad input: exit 2, an `error:` naming the file, and no heatmap written.
fn assert_clean_error(dir: &Path, args: &[&str], expected_message: &str) {
    let out = raylab(args, dir);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stdout(&out));
    let message = stderr(&out);
    assert!(message.starts_with("error: "), "{message}");
    assert!(
        message.contains(expected_message),
        "{expected_message:?} not in {message:?}"
    );
    assert!(!message.contains("panicked"), "{message}");
    assert!(!dir.join("heat.png").exists(), "no heatmap after an error");
}

#[test]
fn bad_inputs_give_clean_errors() {
    let dir = tempfile::tempdir().expect("temp dir");
    let image = render(2, |_| {});
    let good = save(dir.path(), "good.png", &image.rgb);
    // A real render cut in half: the signature is right, the data is not.
    let bytes = std::fs::read(&good).expect("read");
    std::fs::write(dir.path().join("cut.png"), &bytes[..bytes.len() / 2]).expect("write");
    // A real render with a damaged byte inside its image data (CRC fails).
    let mut flipped = bytes.clone();
    let middle = flipped.len() / 2;
    flipped[middle] ^= 0xff;
    std::fs::write(dir.path().join("flipped.png"), &flipped).expect("write");
    std::fs::write(dir.path().join("notes.png"), "not an image").expect("write");
    let small = render(2, |s| {
        s.width = 32;
        s.height = 24;
    });
    raylab::output::write_png(&dir.path().join("small.png"), 32, 24, &small.rgb).expect("write");
    std::fs::create_dir(dir.path().join("folder.png")).expect("mkdir");

    let heat = ["--heatmap", "heat.png"];
    let with_json = |json: &'static str| -> Vec<&'static str> {
        let mut args = vec!["diff", "good.png", "good.png", "--json", json];
        args.extend(heat);
        args
    };
    let with = |a: &'static str, b: &'static str| -> Vec<&'static str> {
        let mut args = vec!["diff", a, b];
        args.extend(heat);
        args
    };
    assert_clean_error(
        dir.path(),
        &with("good.png", "gone.png"),
        "gone.png: no such file",
    );
    assert_clean_error(
        dir.path(),
        &with("cut.png", "good.png"),
        "cut.png: corrupted PNG",
    );
    assert_clean_error(
        dir.path(),
        &with("good.png", "flipped.png"),
        "flipped.png: corrupted PNG",
    );
    assert_clean_error(
        dir.path(),
        &with("notes.png", "good.png"),
        "notes.png: not a PNG file",
    );
    assert_clean_error(
        dir.path(),
        &with("folder.png", "good.png"),
        "folder.png: is a folder",
    );
    assert_clean_error(
        dir.path(),
        &with("good.png", "small.png"),
        "good.png is 64x48 but small.png is 32x24",
    );
    assert_clean_error(
        dir.path(),
        &[
            "diff",
            "good.png",
            "good.png",
            "--heatmap",
            "no/such/folder/heat.png",
        ],
        "--heatmap no/such/folder/heat.png: the folder no/such/folder does not exist",
    );
    // A heatmap over one of its own inputs would destroy it: refused, and
    // good.png is still the same image.
    assert_clean_error(
        dir.path(),
        &["diff", "good.png", "small.png", "--heatmap", "./good.png"],
        "that is an input",
    );
    assert_eq!(std::fs::read(&good).expect("read"), bytes);
    // An unwritable JSON file is found before the heatmap is written.
    assert_clean_error(
        dir.path(),
        &with_json("no/such/folder/m.json"),
        "--json no/such/folder/m.json",
    );
    assert_clean_error(
        dir.path(),
        &["diff", "good.png", "good.png", "--allow", "150"],
        "not a percentage",
    );
}

/// A PNG can declare any size in a few bytes: 100,000,000 x 1 would make
/// `diff --heatmap` allocate 20.7 GB and abort, and the decoder's own limit
/// calls a valid 16384x16384 PNG "corrupted PNG: Memory limit exceeded". Both are refused
/// with the limit named, before any pixel is decoded (the limit's own
/// arithmetic is checked in src/input.rs), and nothing is written.
#[test]
fn a_png_over_the_size_limit_is_refused_before_decoding() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(
        dir.path().join("wide.png"),
        common::png_declaring(100_000_000, 1),
    )
    .expect("write");
    // A real, complete 16384x16384 PNG, written a row at a time (black
    // rows compress to under a megabyte).
    let big = std::fs::File::create(dir.path().join("big.png")).expect("create");
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(big), 16_384, 16_384);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_compression(png::Compression::Fast);
    let mut writer = encoder.write_header().expect("header");
    let mut stream = writer.stream_writer().expect("stream");
    let row = vec![0u8; 16_384];
    for _ in 0..16_384 {
        std::io::Write::write_all(&mut stream, &row).expect("row");
    }
    stream.finish().expect("finish");
    for (name, size) in [("wide.png", "100000000x1"), ("big.png", "16384x16384")] {
        let out = raylab(&["diff", name, name, "--heatmap", "heat.png"], dir.path());
        assert_eq!(out.status.code(), Some(2), "{}", stdout(&out));
        let message = stderr(&out);
        assert!(
            message.contains(&format!(
                "{name}: {size} pixels is over raylab's image size limit"
            )),
            "{message}"
        );
        assert!(message.contains("16384 pixels a side"), "{message}");
        assert!(!message.contains("corrupted"), "{message}");
        assert!(!message.contains("Memory limit"), "{message}");
        assert!(!dir.path().join("heat.png").exists());
    }
}

/// Pass 13 of issue 41, finding 10: a colour profile (iCCP) of 5 MB that
/// inflates to 700 MB made `diff` hold 0.6 GB while decoding a 64x48 PNG.
/// raylab reads no profile: under an address-space limit of 512 MiB, far
/// below what inflating it takes, the PNG is diffed like any other.
#[cfg(target_os = "linux")]
#[test]
fn a_colour_profile_that_inflates_to_hundreds_of_megabytes_is_not_read() {
    use std::os::unix::process::CommandExt;
    let dir = tempfile::tempdir().expect("temp dir");
    let rgb = render(2, |_| {});
    let plain = save(dir.path(), "plain.png", &rgb.rgb);
    let mut profile = b"bomb\0\0".to_vec();
    profile.extend(common::zeros_deflated(1 + 258 * 2_713_000));
    let png = std::fs::read(&plain).expect("read");
    std::fs::write(
        dir.path().join("profiled.png"),
        common::with_chunk(&png, *b"iCCP", &profile),
    )
    .expect("write");
    let mut command = common::command(&["diff", "plain.png", "profiled.png"], dir.path());
    // SAFETY: setrlimit only, which is async-signal-safe, in the child
    // before it runs raylab.
    unsafe {
        command.pre_exec(|| {
            let limit = libc::rlimit {
                rlim_cur: 512 << 20,
                rlim_max: 512 << 20,
            };
            if libc::setrlimit(libc::RLIMIT_AS, &limit) == 0 {
                Ok(())
            } else {
                Err(std::io::Error::last_os_error())
            }
        });
    }
    let out = command.output().expect("runs");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains("PASS"), "{}", stdout(&out));
}

/// A FIFO would block `diff` forever, `/dev/zero` (or a link to it) would be
/// read until memory ran out: only regular files are read.
#[cfg(unix)]
#[test]
fn fifos_and_devices_are_refused_without_blocking() {
    let dir = tempfile::tempdir().expect("temp dir");
    let image = render(2, |_| {});
    save(dir.path(), "good.png", &image.rgb);
    common::make_fifo(&dir.path().join("pipe.png"));
    std::os::unix::fs::symlink("/dev/zero", dir.path().join("zero.png")).expect("symlink");
    for (args, message) in [
        (
            ["diff", "pipe.png", "good.png"],
            "pipe.png: is a FIFO (named pipe), not a regular file",
        ),
        (
            ["diff", "good.png", "pipe.png"],
            "pipe.png: is a FIFO (named pipe), not a regular file",
        ),
        (
            ["diff", "/dev/zero", "good.png"],
            "/dev/zero: is a character device, not a regular file",
        ),
        (
            ["diff", "good.png", "zero.png"],
            "zero.png: is a character device, not a regular file",
        ),
    ] {
        let out = common::raylab_unblocked(&args, dir.path());
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).contains(message), "{args:?}: {}", stderr(&out));
    }
}

/// On a full disk `diff` must not leave the heatmap without the JSON, nor
/// die before printing its verdict: the verdict comes first and the
/// outputs are written all or none (here the JSON, the larger file, cannot
/// be written: RLIMIT_FSIZE stands in for the full disk).
#[cfg(unix)]
#[test]
fn a_failed_write_leaves_no_output_and_the_verdict_is_printed() {
    let dir = tempfile::tempdir().expect("temp dir");
    raylab::output::write_png(&dir.path().join("dot.png"), 1, 1, &[9, 9, 9]).expect("write");
    let args = [
        "diff",
        "dot.png",
        "dot.png",
        "--heatmap",
        "heat.png",
        "--json",
        "m.json",
    ];
    // Unlimited first, to learn the two sizes.
    let out = raylab(&args, dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let size = |name: &str| {
        std::fs::metadata(dir.path().join(name))
            .expect("written")
            .len()
    };
    let (heat, json) = (size("heat.png"), size("m.json"));
    assert!(heat < json, "heatmap {heat} bytes, JSON {json}");
    std::fs::remove_file(dir.path().join("heat.png")).expect("remove");
    std::fs::remove_file(dir.path().join("m.json")).expect("remove");

    let out = common::raylab_with_file_size_limit(&args, dir.path(), (heat + json) / 2);
    assert_eq!(out.status.code(), Some(2), "{}", stdout(&out));
    assert!(stdout(&out).contains("result: PASS"), "{}", stdout(&out));
    assert!(
        stderr(&out).contains("cannot write m.json"),
        "{}",
        stderr(&out)
    );
    assert!(
        !dir.path().join("heat.png").exists(),
        "a heatmap without its JSON"
    );
    assert!(!dir.path().join("m.json").exists());
    assert_eq!(common::temporary_files(dir.path()), Vec::<String>::new());
}

/// Sizes that do not match are errors from the library, never panics.
#[test]
fn mismatched_buffers_are_errors_not_panics() {
    let dir = tempfile::tempdir().expect("temp dir");
    let short = raylab::output::write_png(&dir.path().join("x.png"), 4, 4, &[0; 10]);
    let message = format!("{:#}", short.expect_err("a short buffer"));
    assert!(
        message.contains("10 bytes of RGB for a 4x4 image, which needs 48"),
        "{message}"
    );
    assert!(!dir.path().join("x.png").exists());
    assert!(raylab::output::encode_png(4, 4, &[0; 49]).is_err());
    assert!(raylab::output::encode_png(0, 4, &[]).is_err());
    let image = raylab::diff::Image {
        width: 4,
        height: 4,
        rgb: vec![0; 47],
    };
    assert!(image.encode_png().is_err());

    let a = raylab::diff::Image {
        width: 4,
        height: 4,
        rgb: vec![0; 48],
    };
    let comparison = raylab::diff::compare(&a, &a, raylab::diff::Criteria::default(), ("a", "b"))
        .expect("same size");
    let wrong_base = raylab::diff::Image {
        width: 2,
        height: 2,
        rgb: vec![0; 12],
    };
    let message = format!(
        "{:#}",
        comparison.heatmap(&wrong_base).expect_err("wrong base")
    );
    assert!(
        message.contains("the comparison is of 4x4 pixels"),
        "{message}"
    );
    assert!(message.contains("the base image is 2x2"), "{message}");
    assert!(comparison.heatmap(&a).is_ok());
}
