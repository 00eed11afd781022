//! Every chapter's default render, pinned: a hash of its pixels in an insta
//! snapshot, and the image itself as a reference PNG, both in `snapshots/`.
//!
//! After an intended change to the images, regenerate both with
//! `scripts/bless-snapshots.sh` and review the new PNGs before committing.

use std::path::PathBuf;

use raylab::output::image_hash;

/// Size of the pinned renders: small enough for a quick debug-build test,
/// large enough to show every effect.
const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

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
    } else {
        let reference = image::open(&png)
            .unwrap_or_else(|e| panic!("{}: {e}; run scripts/bless-snapshots.sh", png.display()))
            .to_rgb8();
        assert_eq!(reference.dimensions(), (rendered.width, rendered.height));
        assert!(
            reference.as_raw() == &rendered.rgb,
            "{} differs from the render; if the change is intended, run scripts/bless-snapshots.sh",
            png.display()
        );
    }
    insta::with_settings!({
        snapshot_path => snapshot_folder(),
        prepend_module_to_snapshot => false,
        omit_expression => true,
    }, {
        insta::assert_snapshot!(format!("chapter-{chapter}"), summary);
    });
}

#[test]
fn chapter_1_plane() {
    check_chapter(1);
}
#[test]
fn chapter_2_sphere() {
    check_chapter(2);
}
#[test]
fn chapter_3_nearest_hit() {
    check_chapter(3);
}
#[test]
fn chapter_4_shadows() {
    check_chapter(4);
}
#[test]
fn chapter_5_phong() {
    check_chapter(5);
}
#[test]
fn chapter_6_reflection() {
    check_chapter(6);
}
#[test]
fn chapter_7_antialiasing() {
    check_chapter(7);
}
#[test]
fn chapter_8_refraction() {
    check_chapter(8);
}

#[test]
fn chapter_9_glass() {
    check_chapter(9);
}

#[test]
fn each_chapter_changes_the_picture() {
    // A stage that renders the same image as the one before teaches nothing.
    let hashes: Vec<u64> = (1..=raylab::stage::LAST_CHAPTER)
        .map(|chapter| reference_render(chapter).hash())
        .collect();
    for pair in hashes.windows(2) {
        assert_ne!(pair[0], pair[1]);
    }
}
