//! A workspace's chapter file, cut from the reference chapter: the
//! functions a student writes keep their docs and signatures (with
//! `todo!()` bodies, or the solution in the answer key), the helpers are
//! left out, and doc links to what was left out become plain code. The
//! rules of what a student gets of raylab's answers live here alone.

use std::fmt::Write as _;
use std::path::Path;

use super::SkeletonError;
use super::scan::{self, ItemKind};
use crate::chapters::ChapterInfo;

/// One chapter's file in the workspace, cut from the reference.
pub fn chapter_file(
    info: &ChapterInfo,
    raylab_dir: &str,
    solutions: bool,
) -> Result<String, SkeletonError> {
    let src = info.source;
    let items = scan::items(src).map_err(SkeletonError::Items)?;
    for &function in info.functions {
        if !items
            .iter()
            .any(|item| item.kind == ItemKind::Fn && item.name.as_deref() == Some(function))
        {
            return Err(SkeletonError::NoFunction {
                function: function.to_string(),
            });
        }
    }
    let lesson = Path::new(raylab_dir).join(info.lesson_path());
    let mut out = chapter_file_header(info, &lesson, solutions);
    let parts = ChapterParts::sort(info, &items, &lesson, solutions);
    out.push('\n');
    // Separate groups, which rustfmt leaves in this order.
    for group in [parts.uses, parts.reexports] {
        if !group.is_empty() && !out.ends_with("\n\n") {
            out.push('\n');
        }
        for line in group {
            out.push_str(&line);
            out.push('\n');
        }
    }
    for block in parts.code {
        out.push('\n');
        out.push_str(&block);
        out.push('\n');
    }
    if !solutions {
        out = unlink_missing(&out);
    }
    Ok(out)
}

/// `text` with each doc link to a bare name the file neither defines nor
/// imports (a helper the skeleton leaves out) turned into plain code, so
/// that the student's docs have no broken link. The links to raylab's
/// items the file imports (`greater_of`, `WIDTH`) stay links: the student
/// has those. No reference doc comment copied into a skeleton names a
/// helper (`no_skeleton_or_lesson_sends_the_student_to_a_helper_of_the_answer_key`):
/// this is the fallback that keeps the docs building if one does.
fn unlink_missing(text: &str) -> String {
    let imported = imported_names(text);
    let defines = |name: &str| {
        imported.contains(&name)
            || [
                "fn ", "struct ", "enum ", "const ", "type ", "trait ", "static ",
            ]
            .iter()
            .any(|keyword| text.contains(&format!("{keyword}{name}")))
    };
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find("[`") {
        out.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        let name_end = after.find("`]").filter(|&end| {
            let name = &after[..end];
            !name.is_empty() && name.chars().all(|c| c.is_alphanumeric() || c == '_')
        });
        match name_end {
            Some(end) if !defines(&after[..end]) => {
                out.push_str(&format!("`{}`", &after[..end]));
                rest = &after[end + 2..];
            }
            _ => {
                out.push_str("[`");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// Every name the `use` items at the start of a line of `text` mention,
/// paths and all: a module's name among them is harmless, as a link to it
/// resolves too.
fn imported_names(text: &str) -> Vec<&str> {
    let mut names = Vec::new();
    for (at, _) in text.match_indices("use ") {
        let line_start = text[..at].rfind('\n').map_or(0, |newline| newline + 1);
        if !matches!(text[line_start..at].trim(), "" | "pub") {
            continue;
        }
        let end = text[at..].find(';').map_or(text.len(), |end| at + end);
        names.extend(
            text[at + 4..end]
                .split(|c: char| !(c.is_alphanumeric() || c == '_'))
                .filter(|name| !name.is_empty()),
        );
    }
    names
}

/// A chapter file's module doc: what to write (or that this is the answer
/// key), where the lesson is and how to check; and, in a student's file,
/// the `allow` that keeps the unwritten bodies quiet.
fn chapter_file_header(info: &ChapterInfo, lesson: &Path, solutions: bool) -> String {
    let module = info.module();
    let functions = info
        .functions
        .iter()
        .map(|f| format!("`{f}`"))
        .collect::<Vec<_>>()
        .join(", ");
    let mut out = format!("//! Chapter {}: {}.\n//!\n", info.number, info.title);
    if solutions {
        let _ = writeln!(
            out,
            "//! raylab's reference solution of {functions} (the answer key)."
        );
    } else {
        let _ = writeln!(
            out,
            "//! Your turn: write {functions} below, replacing each `todo!()`."
        );
    }
    let _ = write!(
        out,
        "//!\n\
         //! The lesson: {}\n\
         //! (also in `cargo doc --open`: [`raylab::chapters::{module}`]).\n\
         //! Check your work: `cargo run --release -- check --chapter {}`.\n",
        lesson.display(),
        info.number
    );
    if !solutions {
        out.push_str(
            "\n// The imports are the ones the reference solution uses. Until the\n\
             // bodies are written, some of them and the arguments are unused: this\n\
             // keeps the compiler quiet about it. Delete it once you are done.\n\
             #![allow(unused_imports, unused_variables)]\n",
        );
    }
    out
}

/// The reference chapter's items as a workspace's chapter file holds them.
struct ChapterParts {
    /// The `use` lines that still resolve in a workspace.
    uses: Vec<String>,
    /// `pub use` lines of the public types the chapter defines.
    reexports: Vec<String>,
    /// The functions (a `todo!()` body or the solution) and, in the answer
    /// key, the helpers.
    code: Vec<String>,
}

impl ChapterParts {
    fn sort(
        info: &ChapterInfo,
        items: &[scan::Item],
        lesson: &Path,
        solutions: bool,
    ) -> ChapterParts {
        let src = info.source;
        let module = info.module();
        let mut parts = ChapterParts {
            uses: Vec::new(),
            reexports: Vec::new(),
            code: Vec::new(),
        };
        // The chapter's private types (chapter 11's node stack, say) are
        // helpers like its private functions: no one outside can name them,
        // so they cannot be re-exported; the answer key copies them with
        // their methods, and a student writes their own, or none.
        let private_types: Vec<&str> = items
            .iter()
            .filter(|item| is_type(item.kind) && !item.is_pub(src))
            .filter_map(|item| item.name.as_deref())
            .collect();
        for item in items {
            let text = &src[item.range.clone()];
            let name = item.name.as_deref().unwrap_or_default();
            match item.kind {
                // The lesson include and the tests stay in raylab.
                ItemKind::InnerAttribute | ItemKind::Mod => {}
                ItemKind::Use => parts.uses.extend(workspace_use(text)),
                kind if is_type(kind) && private_types.contains(&name) => {
                    parts
                        .code
                        .extend(solutions.then(|| scan::crate_paths_to_raylab(text)));
                }
                // A public type the chapter defines is raylab's, and the
                // trait's signatures name raylab's: the workspace uses that
                // one.
                kind if is_type(kind) => {
                    parts
                        .reexports
                        .push(format!("pub use raylab::chapters::{module}::{name};"));
                }
                // Methods of a private type go with it; those of a public
                // type are raylab's too.
                ItemKind::Impl => {
                    let own_type = impl_self_type(&src[item.header..item.range.end]);
                    if solutions && own_type.is_some_and(|own| private_types.contains(&own)) {
                        parts.code.push(scan::crate_paths_to_raylab(text));
                    }
                }
                ItemKind::Fn if info.functions.contains(&name) => {
                    let function = student_function(info, src, item, lesson, solutions);
                    parts.code.push(function);
                }
                _ if solutions => parts.code.push(scan::crate_paths_to_raylab(text)),
                // The lesson's helpers are the student's to write, or not.
                _ => {}
            }
        }
        parts
    }
}

/// A `use` item of the reference, with its `crate::` paths made raylab's;
/// `None` when it imports another crate: a workspace depends on raylab (and
/// libm) only, and imports of other crates served the types re-exported.
fn workspace_use(text: &str) -> Option<String> {
    let line = scan::crate_paths_to_raylab(text);
    let root = line
        .trim_start_matches("pub ")
        .trim_start_matches("use ")
        .split("::")
        .next()
        .unwrap_or_default()
        .trim_start_matches("::");
    matches!(root, "raylab" | "std" | "core" | "alloc" | "libm").then_some(line)
}

fn is_type(kind: ItemKind) -> bool {
    matches!(
        kind,
        ItemKind::Struct | ItemKind::Enum | ItemKind::Union | ItemKind::Trait | ItemKind::TypeAlias
    )
}

/// The name of the type an `impl` block (the text from `impl` on) is for:
/// `Nearest` in `impl Nearest {` and in `impl<T> Trait for Nearest<T> {`.
fn impl_self_type(text: &str) -> Option<&str> {
    let header = &text[..text.find('{')?];
    let header = header.strip_prefix("impl")?;
    // Past the impl's own generics, `<...>` right after the keyword.
    let header = match header.trim_start().strip_prefix('<') {
        Some(rest) => {
            let mut depth = 1;
            let close = rest.char_indices().find_map(|(at, c)| {
                match c {
                    '<' => depth += 1,
                    '>' => depth -= 1,
                    _ => {}
                }
                (depth == 0).then_some(at)
            })?;
            &rest[close + 1..]
        }
        None => header,
    };
    let self_type = header
        .rsplit_once(" for ")
        .map_or(header, |(_, after)| after);
    let self_type = self_type.trim_start().trim_start_matches(['&', '(']);
    let end = self_type
        .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
        .unwrap_or(self_type.len());
    self_type[..end]
        .rsplit("::")
        .next()
        .filter(|name| !name.is_empty())
}

/// A function the student writes: its doc comment, a pointer to the lesson,
/// its signature, and `todo!()` or the reference body.
fn student_function(
    info: &ChapterInfo,
    src: &str,
    item: &scan::Item,
    lesson: &Path,
    solutions: bool,
) -> String {
    let name = item.name.as_deref().unwrap_or_default();
    let see = format!(
        "///\n/// Lesson: {} ([`raylab::chapters::{}`]).",
        lesson.display(),
        info.module()
    );
    // The lesson line goes after the doc comment (before any attribute).
    let split = item.doc_end.unwrap_or(item.range.start);
    let docs = &src[item.range.start..split];
    let rest = match (&item.body, solutions) {
        (Some(body), false) => format!(
            "{} {{\n    todo!(\"chapter {}: {name}\")\n}}",
            src[split..body.start].trim_end(),
            info.number
        ),
        _ => src[split..item.range.end].to_string(),
    };
    let text = if docs.is_empty() {
        format!("{}\n{}", see.trim_start_matches("///\n"), rest.trim_start())
    } else {
        format!("{docs}\n{see}{rest}")
    };
    scan::crate_paths_to_raylab(&text)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chapters::CHAPTERS;
    use crate::workspace::RAYLAB_DIR;

    #[test]
    fn impl_blocks_name_their_type() {
        assert_eq!(impl_self_type("impl Nearest {}"), Some("Nearest"));
        assert_eq!(
            impl_self_type("impl<T: X<u8>> Show for Stack<T> {}"),
            Some("Stack")
        );
        assert_eq!(
            impl_self_type("impl std::fmt::Debug for a::Bins {}"),
            Some("Bins")
        );
        assert_eq!(impl_self_type("impl Sampling {}"), Some("Sampling"));
    }

    #[test]
    fn doc_links_to_what_the_skeleton_leaves_out_become_plain_code() {
        let text = "/// Within [`root_error`] of [`intersect_sphere`], see [`a::b`].\n\
                    pub fn intersect_sphere() {}\n";
        assert_eq!(
            unlink_missing(text),
            "/// Within `root_error` of [`intersect_sphere`], see [`a::b`].\n\
             pub fn intersect_sphere() {}\n"
        );
        let imports = "use raylab::bvh::{\n    WIDTH, greater_of,\n};\n\
                       /// Up to [`WIDTH`], by [`greater_of`], not [`leaf4`].\n\
                       pub fn hit_boxes() {}\n";
        assert_eq!(
            unlink_missing(imports),
            "use raylab::bvh::{\n    WIDTH, greater_of,\n};\n\
             /// Up to [`WIDTH`], by [`greater_of`], not `leaf4`.\n\
             pub fn hit_boxes() {}\n"
        );
    }

    /// The names the answer key of `info` defines and its skeleton does
    /// not: the helpers `raylab new` leaves out, which a student has
    /// nowhere (raylab's own are private to a workspace's build).
    fn dropped_helpers(info: &ChapterInfo) -> Vec<String> {
        let defined = |text: &str| -> Vec<String> {
            scan::items(text)
                .expect("a cut file scans")
                .into_iter()
                .filter(|item| {
                    !matches!(
                        item.kind,
                        ItemKind::Use | ItemKind::Impl | ItemKind::Mod | ItemKind::InnerAttribute
                    )
                })
                .filter_map(|item| item.name)
                .collect()
        };
        let skeleton = defined(&chapter_file(info, "/r", false).expect("cuts"));
        defined(&chapter_file(info, "/r", true).expect("cuts"))
            .into_iter()
            .filter(|name| !skeleton.contains(name))
            .collect()
    }

    /// Whether `text` names `name` as an identifier: not inside a longer
    /// one nor a case's name (`normal-central-with-a-wide-step`), and not
    /// after a `.`, where it is a field or method of a value the student
    /// has (`material.ambient`).
    fn names(text: &str, name: &str) -> bool {
        let joined = |c: char| c.is_alphanumeric() || c == '_' || c == '-';
        text.match_indices(name).any(|(at, _)| {
            let before = text[..at].chars().next_back();
            let after = text[at + name.len()..].chars().next();
            !before.is_some_and(|c| joined(c) || c == '.') && !after.is_some_and(joined)
        })
    }

    /// The code of a lesson or of a skeleton (fenced blocks and inline
    /// spans) and the rest, its prose and the skeleton's signatures.
    fn code_and_prose(markdown: &str) -> (String, String) {
        let (mut code, mut prose) = (String::new(), String::new());
        let mut fenced = false;
        for line in markdown.lines() {
            if line.trim_start().starts_with("```") {
                fenced = !fenced;
            } else if fenced {
                code.push_str(line);
                code.push('\n');
            } else {
                prose.push_str(line);
                prose.push('\n');
            }
        }
        let mut plain = String::new();
        for (index, part) in prose.split('`').enumerate() {
            if index % 2 == 1 {
                code.push_str(part);
                code.push('\n');
            } else {
                plain.push_str(part);
            }
        }
        (code, plain)
    }

    #[test]
    fn no_skeleton_or_lesson_sends_the_student_to_a_helper_of_the_answer_key() {
        let helpers: Vec<(u8, String)> = CHAPTERS
            .iter()
            .flat_map(|info| {
                dropped_helpers(info)
                    .into_iter()
                    .map(|name| (info.number, name))
            })
            .collect();
        // Each chapter drops at least its constants or helper functions:
        // an empty list would mean the derivation broke, not that all is well.
        assert!(
            helpers.iter().any(|(_, name)| name == "root_error"),
            "{helpers:?}"
        );
        let mut found = Vec::new();
        for info in CHAPTERS {
            let skeleton = chapter_file(info, "/r", false).expect("cuts");
            let lesson_path = Path::new(RAYLAB_DIR).join(info.lesson_path());
            let lesson = std::fs::read_to_string(&lesson_path).expect("the lesson reads");
            let (code, prose) = code_and_prose(&lesson);
            let (skeleton_code, skeleton_rest) = code_and_prose(&skeleton);
            for (chapter, name) in &helpers {
                // Another chapter's `wide` or `Nearest` is more likely a
                // name of this one (a parameter, a word); `root_error` is
                // no one else's.
                if *chapter != info.number && !name.contains('_') {
                    continue;
                }
                // A lowercase word (`ambient`, `boundary`) in prose is the
                // word; a name with `_`, a capital or a digit is code.
                let word = name.chars().all(|c| c.is_ascii_lowercase());
                if names(&skeleton_code, name) || (!word && names(&skeleton_rest, name)) {
                    found.push(format!("the skeleton of chapter {} names `{name}` (chapter {chapter}'s answer key)", info.number));
                }
                if names(&code, name) || (!word && names(&prose, name)) {
                    found.push(format!(
                        "{} names `{name}` (chapter {chapter}'s answer key)",
                        info.lesson_path()
                    ));
                }
            }
        }
        assert!(found.is_empty(), "{}", found.join("\n"));
    }

    #[test]
    fn skeletons_keep_signatures_and_drop_bodies_helpers_and_tests() {
        for info in CHAPTERS {
            let todo = chapter_file(info, "/r", false).expect("cuts");
            let answer = chapter_file(info, "/r", true).expect("cuts");
            for text in [&todo, &answer] {
                assert!(!text.contains("#![doc"), "{}", info.folder);
                assert!(!text.contains("#[cfg(test)]"), "{}", info.folder);
                assert!(!text.contains("crate::"), "{}", info.folder);
                assert!(text.contains(&format!("/r/{}", info.lesson_path())));
            }
            for function in info.functions {
                assert!(todo.contains(&format!("todo!(\"chapter {}: {function}\")", info.number)));
                assert!(todo.contains(&format!("pub fn {function}")));
                assert!(answer.contains(&format!("pub fn {function}")));
            }
            assert!(!answer.contains("todo!("));
        }
        // Chapter 11's private helpers: the answer key carries them and
        // their methods (raylab's cannot be named from outside); the
        // skeleton leaves them to the student.
        let bvh = CHAPTERS.iter().find(|info| info.number == 11).expect("11");
        let bvh_todo = chapter_file(bvh, "/r", false).expect("cuts");
        let bvh_answer = chapter_file(bvh, "/r", true).expect("cuts");
        for helper in [
            "struct NodeStack",
            "> NodeStack<T> {",
            "struct Nearest",
            "impl Nearest",
            "fn leaf4(",
        ] {
            assert!(bvh_answer.contains(helper), "{helper}");
            assert!(!bvh_todo.contains(helper), "{helper}");
        }
        assert!(!bvh_answer.contains(&format!(
            "pub use raylab::chapters::{}::",
            CHAPTERS[10].module()
        )));
        assert!(
            bvh_todo.contains("use raylab::bvh::{\n    Aabb, Boxes4, Bvh, BvhNode, BvhOptions,")
        );
        let plane = chapter_file(&CHAPTERS[0], "/r", false).expect("cuts");
        assert!(!plane.contains("PARALLEL_TOLERANCE"));
        let plane_answer = chapter_file(&CHAPTERS[0], "/r", true).expect("cuts");
        assert!(plane_answer.contains("pub const PARALLEL_TOLERANCE"));
    }
}
