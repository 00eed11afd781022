//! The similarity section of a class graded with `--code`: every
//! workspace's chapter files, and all of its `src/`, against each other's
//! and raylab's answer key's, the skeleton left out. The students' files
//! are those their runs read before the build; the fingerprints are
//! `grade::similarity`'s.

use std::path::Path;

use super::{Outcome, Student};
use crate::grade::GradeError;

/// The name raylab's answer key goes by in the similarity report.
pub const ANSWER_KEY: &str = "raylab's answer key";

/// The pairs of workspaces (and raylab's answer key) whose chapter files,
/// or whose whole `src/`, are alike, skeleton aside (see
/// [`crate::grade::similarity`]). A student's files are those of the run's
/// snapshot, taken before the build ([`crate::grade::code::CodeRun::sources`]),
/// never the folder as the student's binary may have left it.
pub(super) fn similar_code(
    students: &[Student],
) -> Result<Vec<crate::grade::similarity::SimilarPair>, GradeError> {
    use crate::grade::similarity::{ALL_OF_SRC, Fingerprints, Submission, fingerprints};
    let raylab = Path::new(env!("CARGO_MANIFEST_DIR"));
    let skeleton = crate::workspace::files("student", raylab, false);
    let answers = crate::workspace::files("student", raylab, true);
    let (Ok(skeleton), Ok(answers)) = (skeleton, answers) else {
        return Ok(Vec::new());
    };
    let skeleton_src = Src::of(&skeleton.0);
    let base: Vec<(u8, Fingerprints)> = crate::chapters::CHAPTERS
        .iter()
        .map(|info| {
            let prints = skeleton
                .get(&chapter_path(info))
                .and_then(|text| fingerprints(text).ok())
                .unwrap_or_default();
            (info.number, prints)
        })
        .chain(std::iter::once((
            ALL_OF_SRC,
            fingerprints(&skeleton_src.text).unwrap_or_default(),
        )))
        .collect();
    let skeleton_of = |chapter: u8| {
        base.iter()
            .find(|(c, _)| *c == chapter)
            .map(|(_, prints)| prints.clone())
            .unwrap_or_default()
    };
    let mut sources = vec![(ANSWER_KEY.to_string(), Src::of(&answers.0))];
    for student in students {
        if let Outcome::Code(run) = &student.outcome {
            sources.push((student.name.clone(), Src::of(&run.sources)));
        }
    }
    let submissions: Vec<Submission> = sources
        .iter()
        .map(|(name, src)| {
            let files = crate::chapters::CHAPTERS
                .iter()
                .filter_map(|info| Some((info.number, src.file(&chapter_path(info))?.to_string())))
                .chain(std::iter::once((ALL_OF_SRC, src.text.clone())))
                .collect();
            Submission::new(name, files, &skeleton_of)
        })
        .collect();
    let mut pairs = crate::grade::similarity::similar_pairs(&submissions);
    // A passage of all of src/ names its file and its line there.
    for pair in pairs.iter_mut().filter(|pair| pair.chapter == ALL_OF_SRC) {
        let src_of = |name: &str| sources.iter().find(|(n, _)| n == name).map(|(_, src)| src);
        let (Some(first), Some(second)) = (src_of(&pair.first), src_of(&pair.second)) else {
            continue;
        };
        for (a, b) in &mut pair.passages {
            (a.file, a.line) = first.place(a.line);
            (b.file, b.line) = second.place(b.line);
        }
    }
    Ok(pairs)
}

/// A chapter's file in a workspace.
fn chapter_path(info: &crate::chapters::ChapterInfo) -> String {
    format!("src/chapters/{}.rs", info.module())
}

/// All of a workspace's `src/`: its Rust files (path, text) and their
/// texts one after the other, with the line each starts at.
struct Src {
    files: Vec<(String, String)>,
    text: String,
    /// Each file's path and the line of `text` its first line is.
    starts: Vec<(String, usize)>,
}

impl Src {
    /// The Rust files under `src/` of `files` (path, text), in the order
    /// of their paths.
    fn of(files: &[(String, String)]) -> Src {
        let mut files: Vec<(String, String)> = files
            .iter()
            .filter(|(path, _)| path.starts_with("src/") && path.ends_with(".rs"))
            .cloned()
            .collect();
        files.sort();
        let mut text = String::new();
        let mut starts = Vec::new();
        let mut line = 1;
        for (path, body) in &files {
            starts.push((path.clone(), line));
            text.push_str(body);
            if !body.ends_with('\n') {
                text.push('\n');
            }
            line += body.lines().count().max(1);
        }
        Src {
            files,
            text,
            starts,
        }
    }

    fn file(&self, path: &str) -> Option<&str> {
        self.files
            .iter()
            .find(|(name, _)| name == path)
            .map(|(_, text)| text.as_str())
    }

    /// The file and the line in it of line `line` of `text`.
    fn place(&self, line: usize) -> (Option<String>, usize) {
        match self.starts.iter().rev().find(|(_, start)| *start <= line) {
            Some((path, start)) => (Some(path.clone()), line - start + 1),
            None => (None, line),
        }
    }
}
