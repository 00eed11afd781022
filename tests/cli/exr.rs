//! OpenEXR output and `raylab diff` in linear light: the file holds the
//! renderer's radiance bit for bit, and the comparison sees differences
//! that a screen's clamp and 8-bit rounding would hide.

use crate::common;
use common::{raylab, stderr, stdout};

use std::path::Path;

const WIDTH: u32 = 32;
const HEIGHT: u32 = 24;
/// A chapter with lights and shading: the radiance varies over the image.
const CHAPTER: u8 = 4;

fn write_exr(path: &Path, width: u32, height: u32, linear: &[f32]) {
    let bytes = raylab::output::encode_exr(width, height, linear).expect("encodes");
    std::fs::write(path, bytes).expect("write");
}

fn flat(value: f32) -> Vec<f32> {
    vec![value; (3 * WIDTH * HEIGHT) as usize]
}

#[test]
fn an_exr_render_holds_the_linear_buffer_bit_for_bit() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (width, height) = (WIDTH.to_string(), HEIGHT.to_string());
    let chapter = CHAPTER.to_string();
    let args = [
        "render",
        "--chapter",
        &chapter,
        "--width",
        &width,
        "--height",
        &height,
        "-o",
        "linear.exr",
    ];
    let out = raylab(&args, dir.path());
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));

    let scene = raylab::builtin::scene(CHAPTER).expect("built-in scene");
    let settings = raylab::RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        ..scene.render
    };
    let expected =
        raylab::render_linear_with::<raylab::Reference>(&scene, CHAPTER, &settings, None)
            .expect("renders");
    // The buffer is the one the PNG's codes come from.
    let encoded: Vec<u8> = expected
        .linear
        .iter()
        .map(|&v| raylab::output::linear_to_srgb8(v))
        .collect();
    assert_eq!(encoded, expected.rgb);
    assert!(
        expected.linear.iter().any(|&v| v > 0.0),
        "the scene is not all black"
    );

    let read = raylab::diff::LinearImage::load_exr(&dir.path().join("linear.exr")).expect("reads");
    assert_eq!((read.width, read.height), (WIDTH, HEIGHT));
    let bits = |values: &[f32]| values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&read.rgb), bits(&expected.linear));

    // raylab's own EXR is replaced without --force; someone else's is not.
    let again = raylab(&args, dir.path());
    assert_eq!(again.status.code(), Some(0), "{}", stderr(&again));
    write_exr(&dir.path().join("theirs.exr"), 1, 1, &[0.0; 3]);
    let mut theirs = std::fs::read(dir.path().join("theirs.exr")).expect("read");
    let marker = theirs
        .windows(6)
        .position(|window| window == b"raylab")
        .expect("the marker is in the header");
    theirs[marker..marker + 6].copy_from_slice(b"mitsub");
    std::fs::write(dir.path().join("theirs.exr"), &theirs).expect("write");
    let mut over_theirs = args.to_vec();
    over_theirs[8] = "theirs.exr";
    let refused = raylab(&over_theirs, dir.path());
    assert_eq!(refused.status.code(), Some(2), "{}", stdout(&refused));
    assert!(
        stderr(&refused).contains("raylab did not write it"),
        "{}",
        stderr(&refused)
    );
    assert_eq!(
        std::fs::read(dir.path().join("theirs.exr")).expect("read"),
        theirs
    );

    let jpeg = raylab(&["render", "--chapter", "1", "-o", "x.jpg"], dir.path());
    assert_eq!(jpeg.status.code(), Some(2));
    assert!(
        stderr(&jpeg).contains("give a name ending in .png or .exr"),
        "{}",
        stderr(&jpeg)
    );
}

#[test]
fn diff_of_exr_images_measures_linear_light() {
    let dir = tempfile::tempdir().expect("temp dir");
    // 2 and 4 are both white on a screen (sRGB code 255): a comparison
    // through the tone curve would call these images identical.
    write_exr(&dir.path().join("a.exr"), WIDTH, HEIGHT, &flat(2.0));
    write_exr(&dir.path().join("b.exr"), WIDTH, HEIGHT, &flat(4.0));
    let out = raylab(&["diff", "a.exr", "b.exr", "--json", "m.json"], dir.path());
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}{}",
        stdout(&out),
        stderr(&out)
    );
    let text = stdout(&out);
    assert!(text.contains("linear light"), "{text}");
    assert!(text.contains("mean abs difference: 2.000000e0"), "{text}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("m.json")).expect("json"))
            .expect("JSON");
    assert_eq!(json["light"], "linear");
    assert_eq!(json["rmse"], 2.0);
    assert_eq!(json["mean_abs_difference"], 2.0);
    let relative_mse = json["relative_mse"].as_f64().expect("a number");
    assert!((relative_mse - 4.0 / 16.01).abs() < 1e-12, "{relative_mse}");
    assert_eq!(json["pixels_over_tolerance"], WIDTH * HEIGHT);

    // Under 1% relative error everywhere passes; the same image passes.
    write_exr(&dir.path().join("near.exr"), WIDTH, HEIGHT, &flat(4.02));
    let near = raylab(&["diff", "near.exr", "b.exr"], dir.path());
    assert_eq!(near.status.code(), Some(0), "{}", stdout(&near));
    let strict = raylab(
        &["diff", "near.exr", "b.exr", "--tolerance", "0.001"],
        dir.path(),
    );
    assert_eq!(strict.status.code(), Some(1), "{}", stdout(&strict));
}

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
    assert!(!dir.join("m.json").exists(), "no output after an error");
}

#[test]
fn broken_exr_images_give_clean_errors() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = |name: &str| dir.path().join(name);
    write_exr(&path("good.exr"), WIDTH, HEIGHT, &flat(0.5));
    let bytes = std::fs::read(path("good.exr")).expect("read");
    std::fs::write(path("cut.exr"), &bytes[..bytes.len() / 2]).expect("write");
    std::fs::write(path("header-only.exr"), &bytes[..40]).expect("write");
    let mut not_a_number = flat(0.5);
    not_a_number[3 * (WIDTH as usize + 2) + 1] = f32::NAN;
    write_exr(&path("nan.exr"), WIDTH, HEIGHT, &not_a_number);
    let mut infinite = flat(0.5);
    infinite[0] = f32::INFINITY;
    write_exr(&path("inf.exr"), WIDTH, HEIGHT, &infinite);
    // A header declaring a data window 100,000,000 pixels wide.
    let mut huge = bytes.clone();
    for name in [&b"dataWindow\0box2i\0"[..], &b"displayWindow\0box2i\0"[..]] {
        let at = huge
            .windows(name.len())
            .position(|window| window == name)
            .expect("the attribute is in the header")
            + name.len()
            + 4; // the attribute's size
        huge[at + 8..at + 12].copy_from_slice(&99_999_999i32.to_le_bytes());
    }
    std::fs::write(path("huge.exr"), &huge).expect("write");
    raylab::output::write_png(&path("good.png"), WIDTH, HEIGHT, &vec![128; 3 * 32 * 24])
        .expect("write");

    let json = ["--json", "m.json"];
    let with = |a: &'static str, b: &'static str| -> Vec<&'static str> {
        let mut args = vec!["diff", a, b];
        args.extend(json);
        args
    };
    assert_clean_error(
        dir.path(),
        &with("cut.exr", "good.exr"),
        "cut.exr: corrupted OpenEXR",
    );
    assert_clean_error(
        dir.path(),
        &with("good.exr", "header-only.exr"),
        "header-only.exr: corrupted OpenEXR",
    );
    assert_clean_error(
        dir.path(),
        &with("nan.exr", "good.exr"),
        "nan.exr: pixel x=2, y=1 has G = NaN",
    );
    assert_clean_error(
        dir.path(),
        &with("good.exr", "inf.exr"),
        "inf.exr: pixel x=0, y=0 has R = inf",
    );
    assert_clean_error(
        dir.path(),
        &with("huge.exr", "good.exr"),
        "huge.exr: 100000000x24 pixels is over raylab's image size limit",
    );
    assert_clean_error(
        dir.path(),
        &with("good.png", "good.exr"),
        "good.png is a PNG (8-bit sRGB) but good.exr is an OpenEXR image (linear light)",
    );
    assert_clean_error(
        dir.path(),
        &["diff", "good.exr", "good.exr", "--threshold", "3"],
        "use --tolerance",
    );
    assert_clean_error(
        dir.path(),
        &["diff", "good.png", "good.png", "--tolerance", "0.1"],
        "--tolerance is a relative error in linear light",
    );
    assert_clean_error(
        dir.path(),
        &["diff", "good.exr", "good.exr", "--heatmap", "heat.png"],
        "--heatmap draws differences in 8-bit levels",
    );
}
