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
        for case in raylab::check::by_chapter::checkpoints(info.number)
            .into_iter()
            .chain(raylab::check::by_chapter::robustness(info.number))
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

/// docs/course.md's section "Each function's contract, and the case for
/// each clause" covers every function of the registry, under its chapter's
/// heading, and every case it names exists in that chapter: a renamed or
/// removed case, or a new function without its clauses, fails here.
#[test]
fn the_contract_section_names_every_function_and_only_real_cases() {
    let course = read("docs/course.md");
    let start = course
        .find("## Each function's contract, and the case for each clause")
        .expect("docs/course.md has the contract section");
    let section = &course[start..];
    let section = &section[..section[3..].find("\n## ").map_or(section.len(), |e| e + 3)];
    let headings: Vec<(usize, &str)> = section.match_indices("\n### Chapter ").collect();
    assert_eq!(headings.len(), CHAPTERS.len(), "one heading per chapter");
    let all: Vec<(u8, &str)> = CHAPTERS
        .iter()
        .flat_map(|info| {
            raylab::check::by_chapter::checkpoints(info.number)
                .into_iter()
                .chain(raylab::check::by_chapter::robustness(info.number))
                .map(move |case| (info.number, case.name))
        })
        .collect();
    for (index, info) in CHAPTERS.iter().enumerate() {
        let from = headings[index].0;
        let to = headings.get(index + 1).map_or(section.len(), |h| h.0);
        let part = &section[from..to];
        assert!(
            part.starts_with(&format!("\n### Chapter {}:", info.number)),
            "chapter {}'s heading: {}",
            info.number,
            part.lines().nth(1).unwrap_or_default()
        );
        for function in info.functions {
            assert!(
                part.contains(&format!("`{function}`")),
                "chapter {}'s contracts do not list `{function}`",
                info.number
            );
        }
        let cases: Vec<&str> = all
            .iter()
            .filter(|&&(number, _)| number == info.number)
            .map(|&(_, name)| name)
            .collect();
        for quoted in part.split('`').skip(1).step_by(2) {
            let looks_like_a_case = quoted.contains('-')
                && quoted
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
                && !quoted.starts_with('-')
                && !quoted.ends_with('-');
            // A chapter may name an earlier chapter's case it relies on.
            let earlier = all
                .iter()
                .any(|&(number, name)| number < info.number && name == quoted);
            assert!(
                !looks_like_a_case || cases.contains(&quoted) || earlier,
                "chapter {}'s contracts name `{quoted}`, which is none of its cases",
                info.number
            );
        }
    }
}
