//! The similarity section of a class graded with `--code`: every
//! workspace's chapter files (and raylab's answer key) against each other,
//! the skeleton left out. Reading the students' files is this part's
//! alone; the fingerprints are `grade::similarity`'s.

use std::path::Path;

use super::{Outcome, Student};
use crate::grade::GradeError;

/// The name raylab's answer key goes by in the similarity report.
pub const ANSWER_KEY: &str = "raylab's answer key";

/// The largest chapter file read for the similarity report.
const MAX_CHAPTER_FILE_BYTES: u64 = 1 << 20;

/// The pairs of workspaces (and raylab's answer key) whose chapter files
/// are alike, skeleton aside (see [`crate::grade::similarity`]).
pub(super) fn similar_code(
    students: &[Student],
) -> Result<Vec<crate::grade::similarity::SimilarPair>, GradeError> {
    use crate::grade::similarity::{Fingerprints, Submission, fingerprints};
    let raylab = Path::new(env!("CARGO_MANIFEST_DIR"));
    let skeleton = crate::workspace::files("student", raylab, false);
    let answers = crate::workspace::files("student", raylab, true);
    let (Ok(skeleton), Ok(answers)) = (skeleton, answers) else {
        return Ok(Vec::new());
    };
    let path = |info: &crate::chapters::ChapterInfo| format!("src/chapters/{}.rs", info.module());
    let base: Vec<(u8, Fingerprints)> = crate::chapters::CHAPTERS
        .iter()
        .map(|info| {
            let prints = skeleton
                .get(&path(info))
                .and_then(|text| fingerprints(text).ok())
                .unwrap_or_default();
            (info.number, prints)
        })
        .collect();
    let skeleton_of = |chapter: u8| {
        base.iter()
            .find(|(c, _)| *c == chapter)
            .map(|(_, prints)| prints.clone())
            .unwrap_or_default()
    };
    let mut submissions = vec![Submission::new(
        ANSWER_KEY,
        crate::chapters::CHAPTERS
            .iter()
            .filter_map(|info| Some((info.number, answers.get(&path(info))?.to_string())))
            .collect(),
        &skeleton_of,
    )];
    for student in students {
        if !matches!(student.outcome, Outcome::Code(_)) {
            continue;
        }
        let files = crate::chapters::CHAPTERS
            .iter()
            .filter_map(|info| {
                let bytes = crate::input::read_bounded(
                    &student.folder.join(path(info)),
                    MAX_CHAPTER_FILE_BYTES,
                    "chapter file",
                    crate::input::Links::Refuse,
                )
                .ok()?;
                Some((info.number, String::from_utf8(bytes).ok()?))
            })
            .collect();
        submissions.push(Submission::new(&student.name, files, &skeleton_of));
    }
    Ok(crate::grade::similarity::similar_pairs(&submissions))
}
