//! How much of two students' code is the same, in the manner of MOSS:
//! token k-grams, winnowed (Schleimer, Wilkerson and Aiken, "Winnowing:
//! local algorithms for document fingerprinting", SIGMOD 2003).
//!
//! A file is cut into Rust tokens by `proc-macro2` (Rust's own tokeniser,
//! usable outside a macro); comments fall away, and every identifier that
//! is not a keyword becomes the same token, as does every literal, so that
//! renaming variables changes nothing. Each run of [`K`] tokens is hashed;
//! of every [`WINDOW`] consecutive hashes the smallest is kept (the
//! rightmost on a tie), which guarantees that any shared run of at least
//! `K + WINDOW - 1` tokens leaves a shared fingerprint, wherever it is in
//! the file: reordering functions changes nothing either. Fingerprints of
//! the skeleton a workspace starts from (the signatures and docs everyone
//! has) are removed before comparing, as MOSS removes a base file.
//!
//! Two files' similarity is the share of the smaller one's fingerprints
//! that the other has too.

use std::collections::{BTreeMap, BTreeSet};
use std::str::FromStr;

use proc_macro2::{Delimiter, TokenStream, TokenTree};

/// Tokens per k-gram. Short enough that a copied function of a few lines
/// is seen, long enough that the idioms every solution shares (`let x =
/// a.dot(b);`, 8 tokens) are not.
pub const K: usize = 20;

/// Hashes per winnowing window: every shared run of `K + WINDOW - 1 = 27`
/// tokens is found.
pub const WINDOW: usize = 8;

/// The similarity from which a pair of chapter files is reported.
pub const REPORTED: f64 = 0.6;

/// A chapter file needs this many fingerprints of its own (not the
/// skeleton's) to be compared: a handful of lines is the same in every
/// correct solution.
pub const MIN_FINGERPRINTS: usize = 12;

/// A file's fingerprints: each hash kept, with the first line of the
/// tokens it stands for.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Fingerprints {
    pub lines: BTreeMap<u64, usize>,
}

/// A file that is not Rust tokens (an unclosed string, a stray bracket).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("not Rust tokens: {0}")]
pub struct NotRust(String);

/// The deepest brackets raylab reads a Rust file with: the tokeniser's
/// groups, and the walks over them, nest one level per bracket, and a
/// file of thousands would overflow the grader's stack. No course code
/// comes near it.
pub const MAX_NESTING: usize = 256;

/// How deep `stream`'s groups nest, counted without recursion (the
/// tokeniser and a stream's drop do not recurse either): what the walks
/// over the tokens, which do, are asked to go through.
pub fn nesting(stream: &TokenStream) -> usize {
    let mut deepest = 0;
    let mut pending = vec![(stream.clone(), 0usize)];
    while let Some((stream, depth)) = pending.pop() {
        deepest = deepest.max(depth);
        for tree in stream {
            if let TokenTree::Group(group) = tree {
                pending.push((group.stream(), depth + 1));
            }
        }
    }
    deepest
}

/// The normalised tokens of `source`, each with its line.
pub fn tokens(source: &str) -> Result<Vec<(u64, usize)>, NotRust> {
    let stream = TokenStream::from_str(source).map_err(|error| NotRust(error.to_string()))?;
    if nesting(&stream) > MAX_NESTING {
        return Err(NotRust(format!(
            "brackets nested more than {MAX_NESTING} deep"
        )));
    }
    let mut out = super::canonical::in_one_spelling(source, &stream, |stream| {
        let mut out = Vec::new();
        flatten(stream, &mut out);
        out
    })
    .unwrap_or_else(|| {
        let mut out = Vec::new();
        flatten(stream, &mut out);
        out
    });
    // A token the canonical form made (the `.` of a method call written
    // as a path's) has no line of its own: it takes its neighbour's.
    let mut last = 1;
    for (_, line) in &mut out {
        if *line == 0 {
            *line = last;
        }
        last = *line;
    }
    Ok(out)
}

fn flatten(stream: TokenStream, out: &mut Vec<(u64, usize)>) {
    let mut trees = stream.into_iter().peekable();
    while let Some(tree) = trees.next() {
        // A doc comment reaches the tokeniser as `#[doc = "..."]` (or
        // `#![doc = ...]`): a comment, dropped like the others.
        if let TokenTree::Punct(punct) = &tree {
            if punct.as_char() == '#' {
                if matches!(trees.peek(), Some(TokenTree::Punct(bang)) if bang.as_char() == '!') {
                    let mut ahead = trees.clone();
                    ahead.next();
                    if ahead.peek().is_some_and(is_doc_attribute) {
                        trees.next();
                        trees.next();
                        continue;
                    }
                } else if trees.peek().is_some_and(is_doc_attribute) {
                    trees.next();
                    continue;
                }
            }
        }
        let line = tree.span().start().line;
        match tree {
            TokenTree::Group(group) => {
                let (open, close) = match group.delimiter() {
                    Delimiter::Parenthesis => ("(", ")"),
                    Delimiter::Brace => ("{", "}"),
                    Delimiter::Bracket => ("[", "]"),
                    Delimiter::None => ("", ""),
                };
                if !open.is_empty() {
                    out.push((hash(open.as_bytes()), line));
                }
                flatten(group.stream(), out);
                if !close.is_empty() {
                    out.push((hash(close.as_bytes()), group.span_close().start().line));
                }
            }
            TokenTree::Ident(ident) => {
                let text = ident.to_string();
                let kept = if KEYWORDS.contains(&text.as_str()) {
                    text
                } else {
                    "identifier".to_string()
                };
                out.push((hash(kept.as_bytes()), line));
            }
            TokenTree::Punct(punct) => {
                out.push((hash(punct.as_char().to_string().as_bytes()), line));
            }
            TokenTree::Literal(_) => out.push((hash(b"literal"), line)),
        }
    }
}

/// Whether `tree` is the bracket of a `#[doc = ...]` attribute.
fn is_doc_attribute(tree: &TokenTree) -> bool {
    match tree {
        TokenTree::Group(group) if group.delimiter() == Delimiter::Bracket => group
            .stream()
            .into_iter()
            .next()
            .is_some_and(|first| matches!(first, TokenTree::Ident(ident) if ident == "doc")),
        _ => false,
    }
}

/// Rust's keywords, kept as themselves: they are the structure of the code.
const KEYWORDS: &[&str] = &[
    "as", "break", "const", "continue", "crate", "else", "enum", "fn", "for", "if", "impl", "in",
    "let", "loop", "match", "mod", "move", "mut", "pub", "ref", "return", "self", "Self", "static",
    "struct", "super", "trait", "type", "unsafe", "use", "where", "while",
];

/// FNV-1a, 64 bits: stable across runs and machines.
fn hash(bytes: &[u8]) -> u64 {
    crate::output::fnv1a64(bytes.iter().copied())
}

/// The winnowed fingerprints of `source`.
pub fn fingerprints(source: &str) -> Result<Fingerprints, NotRust> {
    Ok(winnowed(&tokens(source)?))
}

/// The winnowed fingerprints of several files read one after the other,
/// each given with the line its first line is counted as; each file is
/// cut (and spelled one way) alone, and one that is not Rust is left out.
pub fn fingerprints_of_files(files: &[(usize, &str)]) -> Fingerprints {
    let mut all = Vec::new();
    for (first_line, text) in files {
        if let Ok(tokens) = tokens(text) {
            all.extend(
                tokens
                    .into_iter()
                    .map(|(token, line)| (token, line + first_line - 1)),
            );
        }
    }
    winnowed(&all)
}

fn winnowed(tokens: &[(u64, usize)]) -> Fingerprints {
    let grams: Vec<(u64, usize)> = tokens
        .windows(K)
        .map(|gram| {
            let bytes = gram.iter().flat_map(|(token, _)| token.to_le_bytes());
            (crate::output::fnv1a64(bytes), gram[0].1)
        })
        .collect();
    let mut lines = BTreeMap::new();
    if grams.is_empty() {
        return Fingerprints { lines };
    }
    let window = WINDOW.min(grams.len());
    for start in 0..=grams.len() - window {
        // The rightmost smallest hash of the window.
        let chosen = grams[start..start + window]
            .iter()
            .rev()
            .min_by_key(|(hash, _)| *hash)
            .copied();
        if let Some((hash, line)) = chosen {
            lines.entry(hash).or_insert(line);
        }
    }
    Fingerprints { lines }
}

impl Fingerprints {
    /// These fingerprints less those of `base` (the skeleton).
    pub fn without(&self, base: &Fingerprints) -> Fingerprints {
        Fingerprints {
            lines: self
                .lines
                .iter()
                .filter(|(hash, _)| !base.lines.contains_key(hash))
                .map(|(hash, line)| (*hash, *line))
                .collect(),
        }
    }

    pub fn len(&self) -> usize {
        self.lines.len()
    }

    pub fn is_empty(&self) -> bool {
        self.lines.is_empty()
    }
}

/// How two files compare: the share of the smaller's fingerprints the
/// other has, and the lines of each where shared runs start.
#[derive(Debug, Clone, PartialEq)]
pub struct Match {
    pub similarity: f64,
    pub shared: usize,
    /// The lines of the first file and of the second where a shared run
    /// starts, in order of the first.
    pub lines: Vec<(usize, usize)>,
}

/// `a` against `b`, or `None` when either has fewer than
/// [`MIN_FINGERPRINTS`] to compare.
pub fn compare(a: &Fingerprints, b: &Fingerprints) -> Option<Match> {
    let smaller = a.len().min(b.len());
    if smaller < MIN_FINGERPRINTS {
        return None;
    }
    let mut lines: Vec<(usize, usize)> = a
        .lines
        .iter()
        .filter_map(|(hash, line)| b.lines.get(hash).map(|other| (*line, *other)))
        .collect();
    let shared = lines.len();
    lines.sort_unstable();
    let lines: Vec<(usize, usize)> = lines
        .into_iter()
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    Some(Match {
        similarity: shared as f64 / smaller as f64,
        shared,
        lines,
    })
}

/// The number [`Submission`]'s files give all of a workspace's `src/`
/// (every Rust file of it, one after the other), beside its chapter files
/// (1 to 14): code moved out of the chapter files (the answer key in
/// `src/answers/`, each chapter file a `pub use` of it) is compared there.
pub const ALL_OF_SRC: u8 = 0;

/// A pair of students whose chapter file, or whose whole `src/`
/// ([`ALL_OF_SRC`]), is at least [`REPORTED`] alike.
#[derive(Debug, Clone, PartialEq)]
pub struct SimilarPair {
    /// The chapter whose files are alike, or [`ALL_OF_SRC`].
    pub chapter: u8,
    pub first: String,
    pub second: String,
    pub similarity: f64,
    /// Shared passages: each student's lines, from where a shared run
    /// starts (at most [`PASSAGES`], each of at most [`PASSAGE_LINES`]).
    pub passages: Vec<(Passage, Passage)>,
}

impl SimilarPair {
    /// What is alike, in words: `chapter 2`, or `all of src/`.
    pub fn what(&self) -> String {
        if self.chapter == ALL_OF_SRC {
            "all of src/".to_string()
        } else {
            format!("chapter {}", self.chapter)
        }
    }
}

/// Lines of one file, from `line` (1-based).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Passage {
    pub line: usize,
    pub text: String,
    /// The file the lines are from, where that is not the chapter's file
    /// (a passage of all of `src/`).
    pub file: Option<String>,
}

/// How many shared passages a pair shows, and how long each is.
pub const PASSAGES: usize = 4;
pub const PASSAGE_LINES: usize = 8;

/// One student's chapter files: their text and fingerprints (the
/// skeleton's removed), by chapter.
#[derive(Debug, Clone, Default)]
pub struct Submission {
    pub name: String,
    pub files: Vec<(u8, String, Fingerprints)>,
}

impl Submission {
    /// `files` (chapter, text), fingerprinted less `skeleton`'s chapter
    /// file; a file that is not Rust tokens is left out.
    pub fn new(
        name: &str,
        files: Vec<(u8, String)>,
        skeleton: &dyn Fn(u8) -> Fingerprints,
    ) -> Submission {
        let files = files
            .into_iter()
            .filter_map(|(chapter, text)| {
                let prints = fingerprints(&text).ok()?.without(&skeleton(chapter));
                Some((chapter, text, prints))
            })
            .collect();
        Submission {
            name: name.to_string(),
            files,
        }
    }
}

/// Every pair of `submissions` with a chapter file at least [`REPORTED`]
/// alike, most alike first, then by chapter and names: the same for any
/// order of the class.
pub fn similar_pairs(submissions: &[Submission]) -> Vec<SimilarPair> {
    let mut pairs = Vec::new();
    for (index, first) in submissions.iter().enumerate() {
        for second in &submissions[index + 1..] {
            // In the order of their names: the passages then do not depend
            // on the order of the class.
            let (first, second) = if first.name <= second.name {
                (first, second)
            } else {
                (second, first)
            };
            for (chapter, text, prints) in &first.files {
                let Some((_, other_text, other_prints)) =
                    second.files.iter().find(|(c, _, _)| c == chapter)
                else {
                    continue;
                };
                let Some(found) = compare(prints, other_prints) else {
                    continue;
                };
                if found.similarity < REPORTED {
                    continue;
                }
                pairs.push(SimilarPair {
                    chapter: *chapter,
                    first: first.name.clone(),
                    second: second.name.clone(),
                    similarity: found.similarity,
                    passages: passages(text, other_text, &found.lines),
                });
            }
        }
    }
    // All of src/ is compared to find what the chapter files do not show:
    // a pair already alike in a chapter is not listed again for it.
    let alike_in_a_chapter: BTreeSet<(String, String)> = pairs
        .iter()
        .filter(|pair: &&SimilarPair| pair.chapter != ALL_OF_SRC)
        .map(|pair| (pair.first.clone(), pair.second.clone()))
        .collect();
    pairs.retain(|pair| {
        pair.chapter != ALL_OF_SRC
            || !alike_in_a_chapter.contains(&(pair.first.clone(), pair.second.clone()))
    });
    pairs.sort_by(|x, y| {
        y.similarity
            .total_cmp(&x.similarity)
            .then(x.chapter.cmp(&y.chapter))
            .then(x.first.cmp(&y.first))
            .then(x.second.cmp(&y.second))
    });
    pairs
}

/// The shared passages of two texts, from the lines where shared runs
/// start: one passage per run of nearby starts.
fn passages(first: &str, second: &str, lines: &[(usize, usize)]) -> Vec<(Passage, Passage)> {
    let excerpt = |text: &str, line: usize| Passage {
        line,
        file: None,
        text: text
            .lines()
            .skip(line.saturating_sub(1))
            .take(PASSAGE_LINES)
            .collect::<Vec<_>>()
            .join("\n"),
    };
    let mut out = Vec::new();
    let mut last: Option<usize> = None;
    for &(a, b) in lines {
        if last.is_some_and(|previous| a < previous + PASSAGE_LINES) {
            continue;
        }
        last = Some(a);
        out.push((excerpt(first, a), excerpt(second, b)));
        if out.len() == PASSAGES {
            break;
        }
    }
    out
}

#[cfg(test)]
mod tests {

    /// Brackets nested past what the grader's stack holds are refused
    /// before they are read, whatever their depth (a crash would end the
    /// whole class's grading).
    #[test]
    fn brackets_nested_too_deep_are_refused_not_walked() {
        let deep = "(".repeat(100_000) + &")".repeat(100_000);
        assert!(tokens(&format!("const _: () = {deep};")).is_err());
        let shallow = "(".repeat(MAX_NESTING) + &")".repeat(MAX_NESTING);
        assert!(tokens(&format!("const _: () = {shallow};")).is_ok());
        let stream = |text: &str| TokenStream::from_str(text).expect("Rust tokens");
        assert_eq!(nesting(&stream("fn f() { [1, (2)] }")), 3);
        // A closing bracket in a string closes nothing.
        let hidden = "(\")\", ".repeat(100_000) + &")".repeat(100_000);
        assert!(tokens(&format!("const _: () = {hidden};")).is_err());
        assert_eq!(nesting(&stream("(\")\", (\")\", ()))")), 3);
    }

    use super::*;

    /// A chapter 2 in the textbook's manner: the quadratic, `b` halved.
    const QUADRATIC: &str = r#"
use raylab::{Ray, Sphere};
pub fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
    let oc = ray.origin - sphere.center();
    let a = ray.dir.dot(ray.dir);
    let half_b = oc.dot(ray.dir);
    let c = oc.dot(oc) - sphere.radius() * sphere.radius();
    let discriminant = half_b * half_b - a * c;
    if discriminant < 0.0 {
        return None;
    }
    let root = discriminant.sqrt();
    let near = (-half_b - root) / a;
    if near > t_min && near < t_max {
        return Some(near);
    }
    let far = (-half_b + root) / a;
    if far > t_min && far < t_max {
        return Some(far);
    }
    None
}
pub fn reflect(d: raylab::Vec3, n: raylab::Vec3) -> raylab::Vec3 {
    let n = n.normalize();
    d - 2.0 * d.dot(n) * n
}
pub fn describe(sphere: &Sphere) -> String {
    let mut text = String::new();
    for (index, value) in [sphere.center().x, sphere.center().y, sphere.center().z].iter().enumerate() {
        if index > 0 {
            text.push_str(", ");
        }
        text.push_str(&format!("{value:.3}"));
    }
    format!("sphere at ({text}) of radius {}", sphere.radius())
}
"#;

    /// The same code, its names changed and its functions reordered.
    const RENAMED: &str = r#"
use raylab::{Ray, Sphere};
pub fn describe(ball: &Sphere) -> String {
    let mut out = String::new();
    for (i, v) in [ball.center().x, ball.center().y, ball.center().z].iter().enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        out.push_str(&format!("{v:.3}"));
    }
    format!("sphere at ({out}) of radius {}", ball.radius())
}
pub fn reflect(incoming: raylab::Vec3, normal: raylab::Vec3) -> raylab::Vec3 {
    let normal = normal.normalize();
    incoming - 2.0 * incoming.dot(normal) * normal
}
// Copied? Never.
pub fn intersect_sphere(s: &Sphere, r: &Ray, lo: f32, hi: f32) -> Option<f32> {
    let w = r.origin - s.center();
    let aa = r.dir.dot(r.dir);
    let bb = w.dot(r.dir);
    let cc = w.dot(w) - s.radius() * s.radius();
    let disc = bb * bb - aa * cc;
    if disc < 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    let t1 = (-bb - sq) / aa;
    if t1 > lo && t1 < hi {
        return Some(t1);
    }
    let t2 = (-bb + sq) / aa;
    if t2 > lo && t2 < hi {
        return Some(t2);
    }
    None
}
"#;

    /// An independent correct chapter: the geometric method (the foot of
    /// the perpendicular), written by someone else.
    const GEOMETRIC: &str = r#"
use raylab::{Ray, Sphere, Vec3};

fn in_range(t: f32, t_min: f32, t_max: f32) -> Option<f32> {
    (t > t_min && t < t_max).then_some(t)
}

pub fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
    let speed = ray.dir.length();
    let unit = ray.dir / speed;
    let to_center = sphere.center() - ray.origin;
    let along = to_center.dot(unit);
    let foot = to_center - along * unit;
    let gap = sphere.radius() * sphere.radius() - foot.length_squared();
    if gap < 0.0 {
        return None;
    }
    let half_chord = gap.sqrt();
    in_range((along - half_chord) / speed, t_min, t_max)
        .or_else(|| in_range((along + half_chord) / speed, t_min, t_max))
}

pub fn reflect(direction: Vec3, normal: Vec3) -> Vec3 {
    match normal.try_normalize() {
        Some(unit) => direction - unit * (2.0 * unit.dot(direction)),
        None => Vec3::NAN,
    }
}

pub fn describe(sphere: &Sphere) -> String {
    let c = sphere.center();
    format!("a sphere of radius {} centred on {:?}", sphere.radius(), c)
}
"#;

    fn similarity(a: &str, b: &str) -> f64 {
        let (a, b) = (
            fingerprints(a).expect("Rust"),
            fingerprints(b).expect("Rust"),
        );
        compare(&a, &b).map_or(0.0, |m| m.similarity)
    }

    #[test]
    fn renaming_and_reordering_do_not_hide_a_copy() {
        let copied = similarity(QUADRATIC, RENAMED);
        assert!(copied >= REPORTED, "{copied}");
        assert!(copied > 0.8, "{copied}");
        // The figure docs/instructors.md quotes.
        assert_eq!((copied * 100.0).round(), 88.0, "{copied}");
    }

    #[test]
    fn independent_solutions_are_not_reported() {
        let independent = similarity(QUADRATIC, GEOMETRIC);
        assert!(independent < REPORTED, "{independent}");
        // The figure docs/instructors.md quotes.
        assert_eq!((independent * 100.0).round(), 7.0, "{independent}");
        let independent = similarity(RENAMED, GEOMETRIC);
        assert!(independent < REPORTED, "{independent}");
    }

    #[test]
    fn the_skeleton_shared_by_all_is_not_evidence() {
        // Two students who wrote nothing but the same signatures.
        let skeleton = fingerprints(QUADRATIC).expect("Rust");
        let mine = fingerprints(QUADRATIC).expect("Rust").without(&skeleton);
        assert!(mine.is_empty());
        assert_eq!(compare(&mine, &mine), None, "too little left to compare");
    }

    #[test]
    fn comments_and_literals_change_nothing() {
        let commented = QUADRATIC
            .replace("let a =", "// a note\n    let a =")
            .replace(
                "pub fn reflect",
                "/// Doc comments too.\n/// Two lines.\npub fn reflect",
            )
            .replace("0.0", "1e-9");
        let hashes = |source: &str| -> BTreeSet<u64> {
            fingerprints(source)
                .expect("Rust")
                .lines
                .into_keys()
                .collect()
        };
        assert_eq!(hashes(QUADRATIC), hashes(&commented));
    }

    #[test]
    fn a_class_reports_the_copied_pair_only() {
        let none = |_| Fingerprints::default();
        let class = [
            Submission::new("zoe", vec![(2, RENAMED.to_string())], &none),
            Submission::new("ann", vec![(2, QUADRATIC.to_string())], &none),
            Submission::new("bob", vec![(2, GEOMETRIC.to_string())], &none),
        ];
        let pairs = similar_pairs(&class);
        assert_eq!(pairs.len(), 1, "{pairs:?}");
        assert_eq!(
            (pairs[0].first.as_str(), pairs[0].second.as_str()),
            ("ann", "zoe")
        );
        assert!(!pairs[0].passages.is_empty());
        // The order of the class changes nothing.
        let mut reversed = class.to_vec();
        reversed.reverse();
        assert_eq!(similar_pairs(&reversed), pairs);
    }

    #[test]
    fn not_rust_is_an_error_not_a_panic() {
        assert!(fingerprints("fn f() { let s = \"unclosed; }").is_err());
        assert!(fingerprints("fn f() { ( }").is_err());
    }
}
