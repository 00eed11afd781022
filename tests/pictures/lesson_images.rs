//! The lessons' images show in `cargo doc`: the build script copies each
//! lesson (`chapters/NN_name/lesson.md`, and `chapters/README.md`) into
//! `$OUT_DIR/lessons/` with its local images inlined as `data:` URIs, and
//! the chapter modules take their docs from there: a relative link such as
//! `../../snapshots/chapter-2.png` is broken under target/doc.

use std::path::PathBuf;

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

/// Every lesson, with the name of its generated copy.
fn lessons() -> Vec<(PathBuf, String)> {
    let mut lessons = vec![(chapters_folder().join("README.md"), "README.md".to_string())];
    for info in raylab::chapters::CHAPTERS {
        let path = chapters_folder().join(info.folder).join("lesson.md");
        lessons.push((path, format!("{}.md", info.folder)));
    }
    lessons
}

#[test]
fn every_lesson_image_is_inlined_in_the_generated_docs() {
    let lessons = lessons();
    assert!(lessons.len() >= 9, "8 lessons and the README: {lessons:?}");
    let mut images = 0;
    for (lesson, name) in &lessons {
        let source = std::fs::read_to_string(lesson).expect("read the lesson");
        let generated = std::fs::read_to_string(generated_folder().join(name))
            .unwrap_or_else(|e| panic!("no generated {name}: {e}"));
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
            let folder = lesson.parent().expect("a folder");
            let file = std::fs::read(folder.join(original))
                .unwrap_or_else(|e| panic!("{}: {original}: {e}", lesson.display()));
            assert!(bytes == file, "{}: {original}", lesson.display());
            images += 1;
        }
    }
    assert!(images >= 20, "only {images} images in the lessons");
}

/// Each chapter's module takes its docs from the generated copy of its
/// lesson (the registry declares the modules), and so does chapters/mod.rs.
#[test]
fn the_chapter_modules_include_the_generated_lessons() {
    let registry = std::fs::read_to_string(chapters_folder().join("mod.rs")).expect("read");
    assert!(
        registry.starts_with(
            "#![doc = include_str!(concat!(env!(\"OUT_DIR\"), \"/lessons/README.md\"))]"
        )
    );
    assert!(registry.contains(
        "#[doc = include_str!(concat!(env!(\"OUT_DIR\"), \"/lessons/\", $folder, \".md\"))]"
    ));
    for info in raylab::chapters::CHAPTERS {
        assert!(
            chapters_folder()
                .join(info.folder)
                .join("lesson.md")
                .is_file(),
            "{} has no lesson",
            info.folder
        );
    }
}
