//! The lessons' figures are `raylab figure`'s drawings of the chapters'
//! own rays: each figure's caption names the command that drew it, and
//! this test runs every such command and compares what it draws with the
//! file the lesson shows, so that a figure cannot drift from the code.
//! `RAYLAB_BLESS=1 cargo test --test cli figures` redraws them.

use std::path::{Path, PathBuf};

use crate::common;

/// The caption that names a figure's command, as a lesson writes it.
const DRAWN_BY: &str = "*Drawn by `raylab figure ";

/// Every `(lesson, arguments)` of a figure's caption in the lessons.
fn figure_commands() -> Vec<(PathBuf, Vec<String>)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut lessons: Vec<PathBuf> = std::fs::read_dir(root.join("chapters"))
        .expect("chapters/")
        .filter_map(|entry| entry.ok().map(|entry| entry.path().join("lesson.md")))
        .filter(|lesson| lesson.is_file())
        .collect();
    lessons.sort();
    let mut commands = Vec::new();
    for lesson in lessons {
        let text = std::fs::read_to_string(&lesson).expect("read the lesson");
        for line in text.lines().filter(|line| line.starts_with(DRAWN_BY)) {
            let command = line[DRAWN_BY.len() - "raylab figure ".len()..]
                .split('`')
                .next()
                .expect("a caption's command ends with a backquote");
            let words: Vec<String> = command
                .split_whitespace()
                .skip(1)
                .map(String::from)
                .collect();
            commands.push((lesson.clone(), words));
        }
    }
    commands
}

/// The file a figure command writes (its `-o`).
fn output_of(arguments: &[String]) -> &str {
    let at = arguments
        .iter()
        .position(|word| word == "-o")
        .expect("a figure's command names its file with -o");
    &arguments[at + 1]
}

#[test]
fn every_figure_of_the_lessons_is_what_its_command_draws() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let commands = figure_commands();
    // Lessons 4, 6, 8, 12 and 13 explain their geometry with one.
    assert!(commands.len() >= 5, "{commands:?}");
    let scratch = tempfile::tempdir().expect("temp dir");
    let bless = std::env::var_os("RAYLAB_BLESS").is_some();
    for (lesson, arguments) in &commands {
        let shown = output_of(arguments);
        let lesson_text = std::fs::read_to_string(lesson).expect("read the lesson");
        let image = format!("](../../{shown})");
        assert!(
            lesson_text.contains(&image),
            "{}: the caption draws {shown}, which the lesson does not show",
            lesson.display()
        );
        let drawn = scratch.path().join("figure.svg");
        let mut words: Vec<&str> = arguments.iter().map(String::as_str).collect();
        let at = words.iter().position(|word| *word == "-o").expect("-o");
        let drawn_text = drawn.to_str().expect("a UTF-8 temp path");
        words[at + 1] = drawn_text;
        let out = common::raylab_unblocked(&words, root);
        assert!(
            out.status.success(),
            "raylab {}: {}",
            arguments.join(" "),
            String::from_utf8_lossy(&out.stderr)
        );
        let svg = std::fs::read_to_string(&drawn).expect("the figure");
        let checked_in = root.join(shown);
        if bless {
            std::fs::write(&checked_in, &svg).expect("write the figure");
            continue;
        }
        let kept = std::fs::read_to_string(&checked_in).unwrap_or_else(|error| {
            panic!("{}: {error}; run with RAYLAB_BLESS=1", checked_in.display())
        });
        assert!(
            kept == svg,
            "{} is not what `raylab {}` draws now; if the change is intended, run \
             RAYLAB_BLESS=1 cargo test --test cli figures and look at it",
            checked_in.display(),
            arguments.join(" ")
        );
    }
}

#[test]
fn a_figure_of_a_pixel_outside_the_image_is_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = common::raylab_unblocked(
        &[
            "figure",
            "--chapter",
            "4",
            "--pixel",
            "640,0",
            "-o",
            "f.svg",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("pixel 640,0 is outside the 640x480 image"),
        "{stderr}"
    );
    assert!(!dir.path().join("f.svg").exists());
    let out = common::raylab_unblocked(
        &[
            "figure",
            "--chapter",
            "4",
            "--pixel",
            "1,1",
            "--zoom",
            "0.5",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("zoom"));
}
