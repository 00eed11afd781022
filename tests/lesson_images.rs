//! The lessons' images show in `cargo doc`: the build script copies each
//! `chapters/*.md` into `$OUT_DIR/lessons/` with its local images inlined
//! as `data:` URIs, and the chapter modules take their docs from there.
//! Before, the docs linked `../snapshots/chapter-2.png`, which is broken
//! under target/doc.

use std::path::{Path, PathBuf};

use base64::Engine as _;

fn chapters_folder() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("chapters")
}

fn generated_folder() -> PathBuf {
    PathBuf::from(env!("OUT_DIR")).join("lessons")
}

/// The targets of the Markdown images (`![alt](target)`) in `text`.
fn image_targets(text: &str) -> Vec<String> {
    let mut targets = Vec::new();
    for line in text.lines() {
        let mut rest = line;
        while let Some(start) = rest.find("![") {
            let after = &rest[start + 2..];
            let Some(close) = after.find("](") else {
                break;
            };
            let target = &after[close + 2..];
            let end = target.find(')').unwrap_or(target.len());
            targets.push(target[..end].to_string());
            rest = &target[end..];
        }
        // Raw HTML images too, should a lesson ever use one.
        for part in line.split("<img").skip(1) {
            if let Some(src) = part.split("src=\"").nth(1) {
                targets.push(src.split('"').next().unwrap_or("").to_string());
            }
        }
    }
    targets
}

fn lessons() -> Vec<PathBuf> {
    let mut lessons: Vec<PathBuf> = std::fs::read_dir(chapters_folder())
        .expect("chapters/")
        .map(|entry| entry.expect("entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "md"))
        .collect();
    lessons.sort();
    lessons
}

#[test]
fn every_lesson_image_is_inlined_in_the_generated_docs() {
    let lessons = lessons();
    assert!(lessons.len() >= 9, "8 lessons and the README: {lessons:?}");
    let mut images = 0;
    for lesson in &lessons {
        let name = lesson.file_name().expect("a name");
        let source = std::fs::read_to_string(lesson).expect("read the lesson");
        let generated = std::fs::read_to_string(generated_folder().join(name))
            .unwrap_or_else(|e| panic!("no generated {}: {e}", Path::new(name).display()));
        let wanted = image_targets(&source);
        let got = image_targets(&generated);
        assert_eq!(got.len(), wanted.len(), "{}", lesson.display());
        for (original, inlined) in wanted.iter().zip(&got) {
            // A PNG or an SVG (plots), as a data: URI of its own type.
            let encoded = inlined
                .strip_prefix("data:image/")
                .and_then(|rest| rest.split_once(";base64,"))
                .map(|(_, encoded)| encoded);
            let Some(encoded) = encoded else {
                panic!(
                    "{}: the image {original} is not inlined (a missing file?)",
                    lesson.display()
                );
            };
            // The inlined bytes are the file's, so the docs show the same
            // picture as GitHub.
            let bytes = base64::engine::general_purpose::STANDARD
                .decode(encoded)
                .expect("valid base64");
            let file = std::fs::read(chapters_folder().join(original))
                .unwrap_or_else(|e| panic!("{}: {original}: {e}", lesson.display()));
            assert!(bytes == file, "{}: {original}", lesson.display());
            images += 1;
        }
    }
    assert!(images >= 20, "only {images} images in the lessons");
}

/// Each lesson's module takes its docs from the generated copy: the first
/// line of every chapter file (one line, which `raylab new` strips when it
/// copies the file into a workspace) and of chapters/mod.rs.
#[test]
fn the_chapter_modules_include_the_generated_lessons() {
    for info in raylab::stage::CHAPTERS {
        let file = chapters_folder().join(format!("{}.rs", info.file));
        let text = std::fs::read_to_string(&file).expect("read");
        let first = text.lines().next().unwrap_or("");
        assert_eq!(
            first,
            format!(
                "#![doc = include_str!(concat!(env!(\"OUT_DIR\"), \"/lessons/{}.md\"))]",
                info.file
            ),
            "{}",
            file.display()
        );
    }
    let module = std::fs::read_to_string(chapters_folder().join("mod.rs")).expect("read");
    assert!(
        module.starts_with(
            "#![doc = include_str!(concat!(env!(\"OUT_DIR\"), \"/lessons/README.md\"))]"
        )
    );
}
