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
    // All of src/ is fingerprinted file by file (each spelled one way
    // alone: two files together are not one Rust file), in one sequence.
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
        .chain(std::iter::once((ALL_OF_SRC, skeleton_src.fingerprints())))
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
                .collect();
            let mut submission = Submission::new(name, files, &skeleton_of);
            submission.files.push((
                ALL_OF_SRC,
                src.text.clone(),
                src.fingerprints().without(&skeleton_of(ALL_OF_SRC)),
            ));
            submission
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

    /// The fingerprints of all the files, one after the other, each at
    /// its line of `text`.
    fn fingerprints(&self) -> crate::grade::similarity::Fingerprints {
        let files: Vec<(usize, &str)> = self
            .files
            .iter()
            .zip(&self.starts)
            .map(|((_, body), (_, start))| (*start, body.as_str()))
            .collect();
        crate::grade::similarity::fingerprints_of_files(&files)
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

#[cfg(test)]
mod tests {
    use super::chapter_path;
    use crate::grade::similarity::{REPORTED, compare, fingerprints};
    use proc_macro2::{Delimiter, Group, Ident, Punct, Spacing, Span, TokenStream, TokenTree};
    use std::str::FromStr;

    /// `stream` reworded a token at a time, its meaning kept: every float
    /// literal in brackets, every `let x =` typed `let x: _ =`, `Some` as
    /// `Option::Some`, `Vec3::` as `<Vec3>::`.
    fn reworded(stream: TokenStream) -> TokenStream {
        let trees: Vec<TokenTree> = stream.into_iter().collect();
        let mut out: Vec<TokenTree> = Vec::new();
        let punct = |c: char, spacing| TokenTree::Punct(Punct::new(c, spacing));
        let ident = |name: &str| TokenTree::Ident(Ident::new(name, Span::call_site()));
        for (index, tree) in trees.iter().enumerate() {
            let next = trees.get(index + 1);
            let after = trees.get(index + 2);
            let previous_is_path =
                index > 0 && matches!(&trees[index - 1], TokenTree::Punct(p) if p.as_char() == ':');
            match tree {
                TokenTree::Group(group) => {
                    let mut inner = Group::new(group.delimiter(), reworded(group.stream()));
                    inner.set_span(group.span());
                    out.push(TokenTree::Group(inner));
                }
                TokenTree::Literal(literal)
                    if literal
                        .to_string()
                        .starts_with(|c: char| c.is_ascii_digit())
                        && literal.to_string().contains('.') =>
                {
                    out.push(TokenTree::Group(Group::new(
                        Delimiter::Parenthesis,
                        TokenStream::from(tree.clone()),
                    )));
                }
                TokenTree::Ident(name) if name == "let" => {
                    out.push(tree.clone());
                    if let (Some(TokenTree::Ident(binding)), Some(TokenTree::Punct(equals))) =
                        (next, after)
                    {
                        if binding != "mut"
                            && equals.as_char() == '='
                            && equals.spacing() == Spacing::Alone
                        {
                            out.push(TokenTree::Ident(binding.clone()));
                            out.push(punct(':', Spacing::Alone));
                            out.push(ident("_"));
                            out.push(TokenTree::Punct(equals.clone()));
                            // The binding and `=` are written: skip them.
                            return reworded_from(out, &trees[index + 3..]);
                        }
                    }
                }
                TokenTree::Ident(name) if name == "Some" && !previous_is_path => {
                    out.extend([
                        ident("Option"),
                        punct(':', Spacing::Joint),
                        punct(':', Spacing::Alone),
                    ]);
                    out.push(tree.clone());
                }
                TokenTree::Ident(name)
                    if name == "Vec3"
                        && !previous_is_path
                        && matches!(next, Some(TokenTree::Punct(p)) if p.as_char() == ':') =>
                {
                    out.extend([
                        punct('<', Spacing::Alone),
                        tree.clone(),
                        punct('>', Spacing::Alone),
                    ]);
                }
                _ => out.push(tree.clone()),
            }
        }
        out.into_iter().collect()
    }

    fn reworded_from(mut done: Vec<TokenTree>, rest: &[TokenTree]) -> TokenStream {
        done.extend(reworded(rest.iter().cloned().collect()));
        done.into_iter().collect()
    }

    /// The answer key reworded a token at a time shares too little of any
    /// 20-token run to be seen by the tokens alone; spelled one way first,
    /// every chapter of it is reported against the key.
    #[test]
    fn the_answer_key_reworded_token_by_token_is_still_found() {
        let raylab = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let skeleton = crate::workspace::files("student", raylab, false).expect("the skeleton");
        let answers = crate::workspace::files("student", raylab, true).expect("the answer key");
        let mut compared = 0;
        for info in crate::chapters::CHAPTERS {
            let path = chapter_path(info);
            let (Some(base), Some(key)) = (skeleton.get(&path), answers.get(&path)) else {
                continue;
            };
            let base = fingerprints(base).expect("Rust");
            let copy = reworded(TokenStream::from_str(key).expect("Rust tokens")).to_string();
            assert_ne!(
                copy,
                TokenStream::from_str(key).expect("Rust tokens").to_string()
            );
            let key = fingerprints(key).expect("Rust").without(&base);
            let copy = fingerprints(&copy).expect("Rust").without(&base);
            let Some(found) = compare(&key, &copy) else {
                continue;
            };
            compared += 1;
            assert!(
                found.similarity >= REPORTED,
                "chapter {}: {:.2} alike",
                info.number,
                found.similarity
            );
        }
        assert!(compared >= 10, "only {compared} chapters compared");
        // All of src/, each file reworded, against all of the key's.
        let reworded_all: Vec<(String, String)> = answers
            .0
            .iter()
            .map(|(path, text)| {
                let copy = match (path.ends_with(".rs"), TokenStream::from_str(text)) {
                    (true, Ok(stream)) => reworded(stream).to_string(),
                    _ => text.clone(),
                };
                (path.clone(), copy)
            })
            .collect();
        let base = super::Src::of(&skeleton.0).fingerprints();
        let key = super::Src::of(&answers.0).fingerprints().without(&base);
        let copy = super::Src::of(&reworded_all).fingerprints().without(&base);
        let found = compare(&key, &copy).expect("enough to compare");
        assert!(
            found.similarity >= REPORTED,
            "all of src/: {:.2} alike",
            found.similarity
        );
    }
}
