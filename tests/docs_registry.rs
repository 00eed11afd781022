//! The docs list the chapters of the registry (`raylab::stage::CHAPTERS`),
//! every one of them and in order: the README's table, the chapters
//! folder's table and the crate docs' table. Adding a chapter to the
//! registry without its row fails here.

use raylab::stage::CHAPTERS;

fn read(path: &str) -> String {
    let full = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{}: {e}", full.display()))
}

/// Asserts that `text` has, in registry order, a table row per chapter
/// starting `| N |` and naming `needle(chapter)`.
fn assert_rows(doc: &str, text: &str, needle: impl Fn(&raylab::stage::ChapterInfo) -> String) {
    let mut from = 0;
    for info in CHAPTERS {
        let row_start = format!("| {} |", info.number);
        let at = text[from..]
            .find(&row_start)
            .unwrap_or_else(|| panic!("{doc}: no row for chapter {}", info.number));
        let row_end = text[from + at..]
            .find('\n')
            .map_or(text.len(), |e| from + at + e);
        let row = &text[from + at..row_end];
        let wanted = needle(info);
        assert!(
            row.contains(&wanted),
            "{doc}: chapter {}'s row does not name {wanted}: {row}",
            info.number
        );
        from = row_end;
    }
}

#[test]
fn the_readme_lists_every_chapter() {
    assert_rows("README.md", &read("README.md"), |info| {
        format!("(chapters/{}.md)", info.file)
    });
}

#[test]
fn the_chapters_folder_lists_every_chapter() {
    assert_rows("chapters/README.md", &read("chapters/README.md"), |info| {
        format!("`{}.rs`", info.file)
    });
}

#[test]
fn the_crate_docs_list_every_chapter() {
    assert_rows(
        "src/lib.rs",
        &read("src/lib.rs").replace("//! ", ""),
        |info| format!("chapters::{}", info.module()),
    );
}

#[test]
fn every_chapter_has_its_code_lesson_scene_and_reference() {
    for info in CHAPTERS {
        for path in [
            format!("chapters/{}.rs", info.file),
            format!("chapters/{}.md", info.file),
            format!("chapters/scenes/chapter-{}.toml", info.number),
            format!("snapshots/chapter-{}.png", info.number),
        ] {
            assert!(
                std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join(&path)
                    .is_file(),
                "chapter {}: {path} is missing",
                info.number
            );
        }
        let code = read(&format!("chapters/{}.rs", info.file));
        for function in info.functions {
            assert!(
                code.contains(&format!("pub fn {function}")),
                "chapter {}: {function} is not in chapters/{}.rs",
                info.number,
                info.file
            );
        }
    }
}

#[test]
fn the_course_page_names_every_chapter_gallery() {
    let course = read("docs/course.md");
    for info in CHAPTERS {
        let gallery = format!("tests/chapter_{}.rs", info.number);
        let exists = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(&gallery)
            .is_file();
        assert!(
            !exists || course.contains(&format!("`{gallery}`")),
            "docs/course.md does not name {gallery}"
        );
    }
}

/// A failing case sends the student to a section of the lesson by its
/// heading: that heading must be there.
#[test]
fn every_case_names_a_section_of_its_lesson() {
    for info in CHAPTERS {
        let lesson = read(&format!("chapters/{}.md", info.file));
        for case in (info.checkpoints)().into_iter().chain((info.robustness)()) {
            assert!(
                lesson
                    .lines()
                    .any(|line| line.trim_start_matches('#').trim().eq(case.section)),
                "chapter {}: case {} names the section \"{}\", which chapters/{}.md does not have",
                info.number,
                case.name,
                case.section,
                info.file
            );
        }
    }
}
