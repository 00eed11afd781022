//! The docs list the chapters of the registry (`raylab::chapters::CHAPTERS`),
//! every one of them and in order: the README's table, the chapters
//! folder's table and the crate docs' table. Adding a chapter to the
//! registry without its row fails here.

use raylab::chapters::CHAPTERS;

fn read(path: &str) -> String {
    let full = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{}: {e}", full.display()))
}

/// Asserts that `text` has, in registry order, a table row per chapter
/// starting `| N |` and naming `needle(chapter)`.
fn assert_rows(doc: &str, text: &str, needle: impl Fn(&raylab::chapters::ChapterInfo) -> String) {
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
        format!("({})", info.lesson_path())
    });
}

#[test]
fn the_chapters_folder_lists_every_chapter() {
    assert_rows("chapters/README.md", &read("chapters/README.md"), |info| {
        format!("({}/lesson.md)", info.folder)
    });
}

#[test]
fn every_chapter_has_its_code_lesson_scene_and_reference() {
    for info in CHAPTERS {
        for path in [
            info.code_path(),
            info.lesson_path(),
            info.scene_path(),
            format!("chapters/{}/checks.rs", info.folder),
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
        let code = read(&info.code_path());
        for function in info.functions {
            assert!(
                code.contains(&format!("pub fn {function}")),
                "chapter {}: {function} is not in {}",
                info.number,
                info.code_path()
            );
        }
    }
}

#[test]
fn the_course_page_names_every_chapter_gallery() {
    let course = read("docs/course.md");
    for info in CHAPTERS {
        let gallery = format!("chapters/{}/gallery.rs", info.folder);
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
        let lesson = read(&info.lesson_path());
        for case in raylab::check::catalog::checkpoints(info.number)
            .into_iter()
            .chain(raylab::check::catalog::robustness(info.number))
        {
            assert!(
                lesson
                    .lines()
                    .any(|line| line.trim_start_matches('#').trim().eq(case.section)),
                "chapter {}: case {} names the section \"{}\", which {} does not have",
                info.number,
                case.name,
                case.section,
                info.lesson_path()
            );
        }
    }
}
