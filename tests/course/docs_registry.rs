//! The docs list the chapters of the registry (`raylab::chapters::CHAPTERS`),
//! every one of them and in order: the README's table, the chapters
//! folder's table and the crate docs' table. Adding a chapter to the
//! registry without its row fails here, and so does a count of every
//! chapter in the docs ("chapter-1.png .. chapter-11.png", "all 11") that
//! is not the registry's.

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

/// Phrases that mean "every chapter" and give its number: `#` stands for
/// a number, in digits or in words, which must be the registry's last
/// chapter. A range that does not mean the whole course ("chapters 1 to
/// 11" of a measurement, "chapter 11's tree") matches none of them.
fn every_chapter_phrases() -> Vec<String> {
    let first = CHAPTERS[0].module();
    vec![
        // The hand-ins of a whole course.
        "chapter-1.png .. chapter-#.png".into(),
        "chapter-1.png ... chapter-#.png".into(),
        "chapter-1.png to chapter-#.png".into(),
        // `chapter-N.png`'s naming rule.
        "n from 1 to #".into(),
        // What the chapter numbers are (the grade's and the CLI's errors).
        "chapters are 1 to #".into(),
        "every chapter (all #".into(),
        // A count of chapters is the course's size unless the allowlist
        // says otherwise ("the 14 chapters", "all eleven chapters").
        "# chapters".into(),
        // The stage of every effect, the default of `render --scene`.
        "every effect (stage #)".into(),
        // A workspace's chapter files, first to last.
        format!("{first}.rs to ch#_"),
    ]
}

/// Counts of chapters that are not the course's size, with the reason:
/// the file and the phrase as matched (one space between words, any case).
const NOT_EVERY_CHAPTER: &[(&str, &str, &str)] = &[(
    "docs/instructors.md",
    "five chapters",
    "a synthetic class's failing students fail five chapters each",
)];

/// The docs a reader meets a chapter count in: the README, every page
/// under docs/, the chapters folder's README, and the README a `raylab
/// new` workspace gets (its answer key's too).
fn docs_with_counts() -> Vec<(String, String)> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut docs = vec![
        ("README.md".to_string(), read("README.md")),
        ("chapters/README.md".to_string(), read("chapters/README.md")),
    ];
    let mut folders = vec![root.join("docs")];
    while let Some(folder) = folders.pop() {
        let mut entries: Vec<_> = std::fs::read_dir(&folder)
            .unwrap_or_else(|e| panic!("{}: {e}", folder.display()))
            .map(|entry| entry.expect("a docs entry").path())
            .collect();
        entries.sort();
        for path in entries {
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                let name = path
                    .strip_prefix(root)
                    .expect("under the crate")
                    .to_string_lossy()
                    .into_owned();
                let text = read(&name);
                docs.push((name, text));
            }
        }
    }
    for (solutions, name) in [
        (false, "a workspace's README.md"),
        (true, "the answer key's README.md"),
    ] {
        let files = raylab::workspace::files("my-tracer", root, solutions).expect("a workspace");
        let readme = files.get("README.md").expect("a workspace README");
        docs.push((name.to_string(), readme.to_string()));
    }
    docs
}

/// `text` as one line: Markdown's backticks and asterisks dropped (a
/// phrase may cross a code span), each run of white space one space (and
/// a line break), and a `¶`, which no phrase spans, at each blank line,
/// heading and code fence; with the line of each byte.
fn flatten(text: &str) -> (String, Vec<usize>) {
    fn apart(flat: &mut String, lines: &mut Vec<usize>, line: usize) {
        if flat.ends_with(' ') {
            flat.pop();
            lines.pop();
        }
        if !flat.is_empty() && !flat.ends_with('¶') {
            flat.push('¶');
            lines.extend(std::iter::repeat_n(line, '¶'.len_utf8()));
        }
    }
    let (mut flat, mut lines) = (String::new(), Vec::new());
    for (index, text_line) in text.lines().enumerate() {
        let line = index + 1;
        let trimmed = text_line.trim();
        let heading = trimmed.starts_with('#');
        if trimmed.is_empty() || trimmed.starts_with("```") || heading {
            apart(&mut flat, &mut lines, line);
            if !heading {
                continue;
            }
        }
        for c in text_line.chars().chain([' ']) {
            if c == '`' || c == '*' {
                continue;
            }
            let c = if c.is_whitespace() { ' ' } else { c };
            if c == ' ' && (flat.is_empty() || flat.ends_with([' ', '¶'])) {
                continue;
            }
            flat.push(c);
            lines.extend(std::iter::repeat_n(line, c.len_utf8()));
        }
        if heading {
            apart(&mut flat, &mut lines, line);
        }
    }
    (flat, lines)
}

const NUMBER_WORDS: [&str; 20] = [
    "one",
    "two",
    "three",
    "four",
    "five",
    "six",
    "seven",
    "eight",
    "nine",
    "ten",
    "eleven",
    "twelve",
    "thirteen",
    "fourteen",
    "fifteen",
    "sixteen",
    "seventeen",
    "eighteen",
    "nineteen",
    "twenty",
];

/// The number at the start of `text`, in digits or in words (any case),
/// and its length in bytes; a word must end there ("tenth" is no number).
fn number_at(text: &str) -> Option<(u32, usize)> {
    let digits = text.bytes().take_while(u8::is_ascii_digit).count();
    if digits > 0 {
        return Some((text[..digits].parse().ok()?, digits));
    }
    NUMBER_WORDS
        .iter()
        .enumerate()
        .filter(|(_, word)| {
            text.get(..word.len())
                .is_some_and(|start| start.eq_ignore_ascii_case(word))
                && !text[word.len()..]
                    .chars()
                    .next()
                    .is_some_and(|c| c.is_alphanumeric())
        })
        .map(|(index, word)| (index as u32 + 1, word.len()))
        .max_by_key(|&(_, len)| len)
}

/// `text` after `start`, which it begins with: as written, or with a
/// capital first letter, where a sentence starts with it (the rest in its
/// case: "one `Chapters`", a trait, is no count of chapters).
fn strip_phrase_start<'a>(text: &'a str, start: &str) -> Option<&'a str> {
    if let Some(rest) = text.strip_prefix(start) {
        return Some(rest);
    }
    let mut start = start.chars();
    let first = start.next()?;
    let mut text = text.chars();
    let capital = text.next()?;
    (capital != first && capital.to_ascii_lowercase() == first).then_some(())?;
    text.as_str().strip_prefix(start.as_str())
}

/// Every match of `phrase` (`#` its number) in `flat`: where it starts,
/// the phrase as written, and its number. The phrase starts a word, and
/// so does its number; a phrase ending in a letter ends a word that is not
/// a path ("chapters/*/*.rs" is no count).
fn find_phrase(flat: &str, phrase: &str) -> Vec<(usize, String, u32)> {
    let (before, after) = phrase.split_once('#').expect("a phrase has a #");
    // Whether the character before `at` ends a word ("main from 1 to 5"
    // is no "n from 1 to 5", nor "v0.11 chapters" a count).
    let word_starts = |at: usize| {
        !flat[..at]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_alphanumeric() || "-_.".contains(c))
    };
    let mut found = Vec::new();
    for (start, _) in flat.char_indices() {
        let Some(rest) = strip_phrase_start(&flat[start..], before) else {
            continue;
        };
        let number_start = start + before.len();
        if !word_starts(start) || (before.is_empty() && !word_starts(number_start)) {
            continue;
        }
        let Some((number, len)) = number_at(rest) else {
            continue;
        };
        let Some(tail) = rest[len..].strip_prefix(after) else {
            continue;
        };
        let ends_word = !after.ends_with(char::is_alphabetic)
            || !tail
                .chars()
                .next()
                .is_some_and(|c| c.is_alphanumeric() || "/_".contains(c));
        if ends_word {
            let end = number_start + len + after.len();
            found.push((start, flat[start..end].to_string(), number));
        }
    }
    found
}

/// Every phrase of the docs that means "every chapter" gives the
/// registry's last chapter: adding a chapter, or a doc written when there
/// were fewer, fails here until the count follows. The allowlist's entries
/// must each still be found, so that none outlives its text.
#[test]
fn every_chapter_count_in_the_docs_is_the_registry_s() {
    let last = u32::from(CHAPTERS.last().expect("chapters").number);
    assert_eq!(
        last as usize,
        CHAPTERS.len(),
        "the chapters are numbered 1 to {}",
        CHAPTERS.len()
    );
    let phrases = every_chapter_phrases();
    let (mut stale, mut right) = (Vec::new(), Vec::new());
    let mut allowed_seen = vec![false; NOT_EVERY_CHAPTER.len()];
    for (name, text) in docs_with_counts() {
        let (flat, lines) = flatten(&text);
        for phrase in &phrases {
            for (at, written, number) in find_phrase(&flat, phrase) {
                let allowed = NOT_EVERY_CHAPTER.iter().position(|&(file, allowed, _)| {
                    file == name && allowed.eq_ignore_ascii_case(&written)
                });
                if let Some(index) = allowed {
                    allowed_seen[index] = true;
                } else if number == last {
                    right.push(name.clone());
                } else {
                    stale.push(format!("{name}:{}: \"{written}\" says {number}", lines[at]));
                }
            }
        }
    }
    assert!(
        stale.is_empty(),
        "the registry's last chapter is {last}, but these say otherwise (fix them, \
         or add one that is no count of the whole course to NOT_EVERY_CHAPTER with \
         its reason):\n{}",
        stale.join("\n")
    );
    for ((file, phrase, _), seen) in NOT_EVERY_CHAPTER.iter().zip(allowed_seen) {
        assert!(
            seen,
            "NOT_EVERY_CHAPTER lists \"{phrase}\" in {file}, which is no longer there"
        );
    }
    // The rule sees the phrases it is for: the README's and the
    // instructors' page's counts are found, and right.
    for doc in ["README.md", "docs/instructors.md"] {
        assert!(
            right.iter().any(|name| name == doc),
            "no count of every chapter found in {doc}: {right:?}"
        );
    }
}
