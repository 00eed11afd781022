//! Every chapter's default render, pinned: a hash of its pixels in an insta
//! snapshot, and the image itself as a reference PNG, both in `snapshots/`.
//!
//! When a render differs from its reference, the test writes the new
//! render and a heatmap of the difference under the target folder
//! (`target/snapshot-failures/chapter-N.png`, `chapter-N-heatmap.png`) and
//! names them. Look at both first: most differences are bugs. Only after an
//! intended change, regenerate the references with
//! `scripts/bless-snapshots.sh` and review the new PNGs before committing.

use std::path::{Path, PathBuf};

use raylab::chapters::{REFERENCE_HEIGHT as HEIGHT, REFERENCE_WIDTH as WIDTH};
use raylab::output::image_hash;

fn snapshot_folder() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("snapshots")
}

fn reference_render(chapter: u8) -> raylab::Rendered {
    let scene = raylab::builtin::scene(chapter).expect("built-in scenes parse");
    let settings = raylab::RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        ..scene.render
    };
    raylab::render(&scene, chapter, &settings, None).expect("renders")
}

/// Where a failing snapshot test writes the new render and its heatmap:
/// `snapshot-failures/` in the target folder (beside `tmp/`, whatever
/// CARGO_TARGET_DIR says), never in `snapshots/`.
fn failure_folder() -> PathBuf {
    let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    tmp.parent().unwrap_or(&tmp).join("snapshot-failures")
}

/// Compares `rendered` with the reference PNG `png`. On a difference,
/// writes the render and a heatmap into `failures` and returns the message
/// that names them.
fn compare_with_reference(
    chapter: u8,
    rendered: &raylab::Rendered,
    png: &Path,
    failures: &Path,
) -> Result<(), String> {
    let reference = match raylab::diff::Image::load_png(png) {
        Ok(reference) => reference,
        Err(error) => {
            return Err(format!(
                "{}: {error:#}; the reference image is missing or unreadable: restore it \
                 (git checkout snapshots/) or, for a new chapter, create it with \
                 scripts/bless-snapshots.sh and review it",
                png.display()
            ));
        }
    };
    if reference.width == rendered.width
        && reference.height == rendered.height
        && reference.rgb == rendered.rgb
    {
        return Ok(());
    }
    let new = raylab::diff::Image {
        width: rendered.width,
        height: rendered.height,
        rgb: rendered.rgb.clone(),
    };
    let written = failures.join(format!("chapter-{chapter}.png"));
    let heatmap_path = failures.join(format!("chapter-{chapter}-heatmap.png"));
    let mut notes = Vec::new();
    let mut wrote =
        |path: &Path, image: &raylab::diff::Image| match std::fs::create_dir_all(failures)
            .map_err(anyhow::Error::from)
            .and_then(|()| image.write_png(path).map_err(anyhow::Error::from))
        {
            Ok(()) => notes.push(format!("  {}", path.display())),
            Err(error) => notes.push(format!("  (could not write {}: {error:#})", path.display())),
        };
    wrote(&written, &new);
    let summary = match raylab::diff::compare(
        &new,
        &reference,
        raylab::diff::Criteria::default(),
        ("render", "reference"),
    ) {
        Ok(comparison) => {
            match comparison.heatmap(&new) {
                Ok(heatmap) => wrote(&heatmap_path, &heatmap),
                Err(error) => notes.push(format!("  (no heatmap: {error:#})")),
            }
            comparison.report_text()
        }
        // Different sizes: no pixel-by-pixel comparison.
        Err(error) => format!("{error:#}"),
    };
    Err(format!(
        "chapter {chapter}'s render differs from the reference {}.\n{summary}\n\
         The new render and a heatmap of where it differs are in:\n{}\n\
         Look at both, beside the reference, before anything else: a difference nobody \
         intended is a bug to fix, not a reference to replace. Only if the change is \
         intended and the new image is right, run scripts/bless-snapshots.sh and review \
         the new PNGs (git diff --stat snapshots/) before committing.",
        png.display(),
        notes.join("\n")
    ))
}

fn check_chapter(chapter: u8) {
    let rendered = reference_render(chapter);
    let summary = format!(
        "chapter: {chapter}\nsize: {}x{}\nfnv1a64: {:016x}\n",
        rendered.width,
        rendered.height,
        image_hash(rendered.width, rendered.height, &rendered.rgb)
    );
    let png = snapshot_folder().join(format!("chapter-{chapter}.png"));
    if std::env::var_os("RAYLAB_BLESS").is_some() {
        raylab::output::write_png(&png, rendered.width, rendered.height, &rendered.rgb)
            .expect("write the reference PNG");
    } else if let Err(message) = compare_with_reference(chapter, &rendered, &png, &failure_folder())
    {
        panic!("{message}");
    }
    insta::with_settings!({
        snapshot_path => snapshot_folder(),
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::assert_snapshot!(format!("chapter-{chapter}"), summary);
    });
}

/// One test per chapter of the registry, named after its module
/// (`snapshots::` and the module): scripts/bless-snapshots.sh blesses them all.
macro_rules! snapshot_tests {
    ($($number:literal $module:ident $folder:literal $title:literal $adds:literal
       |$effects:ident| $switch_on:block [$($function:ident),*] $(kept { $($kept:path),* })?
       $(asks { $($asked:ident($asked_kind:ident)),* $(,)? })?
       $(shades |$when:ident| $condition:expr => $shade:expr)?;)*) => {
        $(
            #[test]
            fn $module() {
                check_chapter($number);
            }
        )*
    };
}

raylab::for_each_chapter!(snapshot_tests);

/// Chapter 11 adds speed, not pixels: its scene drawn at chapter 10's stage
/// (every ray tests every object) is the same image, bit for bit. Small, so
/// that chapter 10's loop over 20,000 triangles stays quick in debug.
#[test]
fn the_tree_changes_no_pixel() {
    let scene = raylab::builtin::scene(11).expect("the built-in scene");
    let settings = raylab::RenderSettings {
        width: 40,
        height: 30,
        ..scene.render
    };
    let with_tree = raylab::render(&scene, 11, &settings, None).expect("renders");
    let without = raylab::render(&scene, 10, &settings, None).expect("renders");
    assert!(with_tree.effects.bvh && !without.effects.bvh);
    assert_eq!(with_tree.rgb, without.rgb);
}

#[test]
fn each_chapter_changes_the_picture() {
    // A stage that renders the same image as the one before teaches nothing.
    let hashes: Vec<u64> = (1..=raylab::chapters::LAST_CHAPTER)
        .map(|chapter| reference_render(chapter).hash())
        .collect();
    for pair in hashes.windows(2) {
        assert_ne!(pair[0], pair[1]);
    }
}

/// A render that differs from its reference is written out with a heatmap,
/// and the message names both and says to look before blessing.
#[test]
fn a_differing_render_is_written_with_a_heatmap() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut rendered = reference_render(2);
    // A few pixels off, as a small change to a chapter would do.
    for value in rendered
        .rgb
        .iter_mut()
        .skip(3 * WIDTH as usize * HEIGHT as usize / 2)
        .take(30)
    {
        *value = value.wrapping_add(40);
    }
    let png = snapshot_folder().join("chapter-2.png");
    let message =
        compare_with_reference(2, &rendered, &png, dir.path()).expect_err("the render differs");
    let written = dir.path().join("chapter-2.png");
    let heatmap = dir.path().join("chapter-2-heatmap.png");
    assert!(
        message.contains(&written.display().to_string()),
        "{message}"
    );
    assert!(
        message.contains(&heatmap.display().to_string()),
        "{message}"
    );
    assert!(
        message.contains(&format!(
            "pixels over threshold 2: 10 of {}",
            WIDTH * HEIGHT
        )),
        "{message}"
    );
    assert!(message.contains("Look at both"), "{message}");
    assert!(
        !message.contains("if the change is intended, run"),
        "{message}"
    );
    let new = image::open(&written).expect("the render").to_rgb8();
    assert_eq!(new.as_raw(), &rendered.rgb);
    let heat = image::open(&heatmap).expect("the heatmap").to_rgb8();
    assert_eq!(heat.width(), WIDTH);
    assert!(heat.height() > HEIGHT, "with its legend");
    // The same render passes against itself, and writes nothing.
    let same = dir.path().join("same");
    let clean = reference_render(2);
    assert_eq!(compare_with_reference(2, &clean, &png, &same), Ok(()));
    assert!(!same.exists());
}
