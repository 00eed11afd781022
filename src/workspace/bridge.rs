//! The workspace's `src/chapters/mod.rs`, written from the `Chapters`
//! trait as `src/course.rs` declares it: each method forwarded to the
//! chapter function of the same name. Read from the list the trait's
//! methods are made from, so a new method needs no edit here; kept apart
//! from the chapter files' cut, which reads the chapters instead.

use std::fmt::Write as _;

use super::scan::{self, ItemKind};
use super::{STUDENT_TYPE, SkeletonError};
use crate::chapters::{CHAPTERS, ChapterInfo};

/// The trait a workspace implements, read for its signatures.
const COURSE_SOURCE: &str = include_str!("../course.rs");

/// `src/chapters/mod.rs`: the chapter modules, and `Chapters` for the
/// student's type, each method sending its arguments to the function of the
/// same name in the chapter that the registry says writes it. The
/// signatures are the trait's own, read from its list in `src/course.rs`.
pub(super) fn chapters_mod_rs() -> Result<String, SkeletonError> {
    let methods = trait_methods()?;
    let mut out = String::from(
        "//! Connects raylab to your chapters (made by `raylab new`; you should not\n\
         //! need to edit it). raylab calls the methods of `raylab::course::Chapters`;\n\
         //! each one here calls the function of the same name in your chapter file.\n\n",
    );
    for info in CHAPTERS {
        let _ = writeln!(out, "pub mod {};", info.module());
    }
    out.push('\n');
    // The trait's own imports, so that its signatures read the same here.
    // Not every one is used by the methods below.
    // rustfmt keeps the order of groups apart: the types of src/course.rs
    // itself, then its imports.
    let (own, imports) = course_imports()?;
    let _ = writeln!(out, "#[allow(unused_imports)]\n{own}\n");
    for line in imports {
        let _ = writeln!(out, "#[allow(unused_imports)]\n{line}");
    }
    let _ = writeln!(
        out,
        "\nimpl raylab::course::Chapters for crate::{STUDENT_TYPE} {{"
    );
    let mut first = true;
    for info in CHAPTERS {
        for &function in info.functions {
            let Some((_, signature)) = methods.iter().find(|(name, _)| name == function) else {
                return Err(SkeletonError::NotAMethod {
                    chapter: info.number,
                    function: function.to_string(),
                });
            };
            let arguments =
                scan::parameter_names(signature).map_err(|error| SkeletonError::Signature {
                    function: function.to_string(),
                    error,
                })?;
            if !first {
                out.push('\n');
            }
            first = false;
            let type_arguments = forwarded_type_arguments(info, function)?;
            let _ = writeln!(
                out,
                "    {signature} {{\n        {}::{function}{type_arguments}({})\n    }}",
                info.module(),
                arguments.join(", ")
            );
        }
    }
    out.push_str("}\n");
    Ok(out)
}

/// The turbofish a forwarding call to chapter function `function` needs:
/// none when the arguments tell its type parameters (`in_shadow<C:
/// Chapters>(tracer: &mut Tracer<C>, ..)`), else `::<Self>`, the student's
/// type, for each (`smooth_hit_point<'a, C: Chapters>` calls `C`'s other
/// functions but takes no argument of `C`'s).
fn forwarded_type_arguments(info: &ChapterInfo, function: &str) -> Result<String, SkeletonError> {
    let src = info.source;
    let items = scan::items(src).map_err(|error| SkeletonError::Scan {
        file: info.code_path(),
        error,
    })?;
    let item = items
        .iter()
        .find(|item| item.kind == ItemKind::Fn && item.name.as_deref() == Some(function))
        .ok_or_else(|| SkeletonError::NoFunctionIn {
            path: info.code_path(),
            function: function.to_string(),
        })?;
    let signature_end = item.body.as_ref().map_or(item.range.end, |body| body.start);
    let parameters = scan::type_parameters(&src[item.header..signature_end]).map_err(|error| {
        SkeletonError::Generics {
            function: function.to_string(),
            error,
        }
    })?;
    if parameters.iter().all(|parameter| parameter.in_parameters) {
        return Ok(String::new());
    }
    let mut arguments = Vec::new();
    for parameter in &parameters {
        if !parameter
            .bounds
            .split(['+', ' '])
            .any(|bound| bound == "Chapters" || bound.ends_with("::Chapters"))
        {
            return Err(SkeletonError::ForeignTypeParameter {
                function: function.to_string(),
                parameter: parameter.name.clone(),
            });
        }
        arguments.push("Self");
    }
    Ok(format!("::<{}>", arguments.join(", ")))
}

/// Every method of `Chapters`, as (name, signature from `fn` to the end
/// of its answer, with `Self` for the chapters). The trait's methods are
/// made by a macro from one list in `src/course.rs`
/// (`for_each_course_function!`), so that list is what is read: each
/// entry is `module fn name(parameters) -> answer`, then optional
/// `[markers]` and `{ textbook ... }`, ended by `;`.
fn trait_methods() -> Result<Vec<(String, String)>, SkeletonError> {
    const LIST: &str = "macro_rules! for_each_course_function";
    const CHAPTERS: &str = "$chapters;";
    let src = COURSE_SOURCE;
    let list = src
        .find(LIST)
        .and_then(|at| {
            src[at..]
                .find(CHAPTERS)
                .map(|start| at + start + CHAPTERS.len())
        })
        .ok_or(SkeletonError::NoChaptersTrait)?;
    let text = &src[list..];
    let scan_error = |error| SkeletonError::Scan {
        file: "src/course.rs".to_string(),
        error,
    };
    let tokens = scan::lex(text).map_err(scan_error)?;
    let mut out = Vec::new();
    let mut entry: Vec<scan::Token> = Vec::new();
    let mut depth = 0usize;
    for token in tokens {
        match token.kind {
            scan::Tok::Comment { .. } => continue,
            scan::Tok::Open(_) => depth += 1,
            // The list ends where the block that holds it closes.
            scan::Tok::Close(_) if depth == 0 => break,
            scan::Tok::Close(_) => depth -= 1,
            scan::Tok::Semi if depth == 0 => {
                out.push(list_entry(text, &entry)?);
                entry.clear();
                continue;
            }
            _ => {}
        }
        entry.push(token);
    }
    if out.is_empty() {
        return Err(SkeletonError::NoChaptersTrait);
    }
    Ok(out)
}

/// One entry of the functions' list (its tokens, without comments and the
/// closing `;`): the function's name and its signature, on one line.
fn list_entry(text: &str, tokens: &[scan::Token]) -> Result<(String, String), SkeletonError> {
    let word = |token: &scan::Token| &text[token.start..token.end];
    let fn_at = tokens
        .iter()
        .position(|token| word(token) == "fn")
        .ok_or(SkeletonError::UnnamedMethod)?;
    let name = tokens
        .get(fn_at + 1)
        .filter(|token| token.kind == scan::Tok::Word)
        .map(|token| word(token).to_string())
        .ok_or(SkeletonError::UnnamedMethod)?;
    // The signature ends before the markers `[..]` or the textbook block
    // `{..}` at the entry's own level (the parameters' brackets are inside
    // their parentheses).
    let mut depth = 0usize;
    let mut end = tokens[fn_at].end;
    for token in &tokens[fn_at..] {
        match token.kind {
            scan::Tok::Open(b'[' | b'{') if depth == 0 => break,
            scan::Tok::Open(_) => depth += 1,
            scan::Tok::Close(_) => depth = depth.saturating_sub(1),
            _ => {}
        }
        end = token.end;
    }
    let signature = text[tokens[fn_at].start..end].replace("$chapters", "Self");
    Ok((name, one_line(&signature)))
}

/// `signature` on one line: each run of white space one space, none just
/// inside the parameters' parentheses, and no comma after the last one.
fn one_line(signature: &str) -> String {
    let spaced = signature.split_whitespace().collect::<Vec<_>>().join(" ");
    spaced
        .replace("( ", "(")
        .replace(", )", ")")
        .replace(",)", ")")
        .replace(" )", ")")
}

/// An import of the public types `src/course.rs` defines itself, and its
/// `use` lines as a workspace writes them.
fn course_imports() -> Result<(String, Vec<String>), SkeletonError> {
    let src = COURSE_SOURCE;
    let items = scan::items(src).map_err(|error| SkeletonError::Scan {
        file: "src/course.rs".to_string(),
        error,
    })?;
    let mut lines = Vec::new();
    for item in items.iter().filter(|item| item.kind == ItemKind::Use) {
        let line = &src[item.header..item.range.end];
        // The chapter modules it names are raylab's; the workspace has its
        // own. A `use` of a bare name (a macro of the file's own, made
        // visible to the rest of raylab) names nothing a workspace can reach.
        let path = line.trim_start_matches("pub ").trim_start_matches("use ");
        if !line.contains("crate::chapters") && path.starts_with("crate::") {
            lines.push(scan::crate_paths_to_raylab(line));
        }
    }
    let mut own: Vec<&str> = items
        .iter()
        .filter(|item| {
            matches!(
                item.kind,
                ItemKind::Struct | ItemKind::Enum | ItemKind::Trait
            ) && item.is_pub(src)
        })
        .filter_map(|item| item.name.as_deref())
        .collect();
    own.sort_unstable();
    Ok((
        format!("use raylab::course::{{{}}};", own.join(", ")),
        lines,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_registry_function_has_a_method_and_a_plain_signature() {
        let methods = trait_methods().expect("the trait scans");
        for info in CHAPTERS {
            for function in info.functions {
                let (_, signature) = methods
                    .iter()
                    .find(|(name, _)| name == function)
                    .unwrap_or_else(|| panic!("no method {function}"));
                assert!(
                    signature.starts_with(&format!("fn {function}")),
                    "{signature}"
                );
                scan::parameter_names(signature).expect("plain parameters");
            }
        }
    }

    #[test]
    fn a_list_entry_is_one_line_without_its_markers() {
        let text = "/// Chapter 4: docs.\n    ch04_shadows fn in_shadow(\n        \
                    tracer: &mut Tracer<$chapters>,\n        normals: &[Vec3; 3],\n    \
                    ) -> bool [drives] { textbook if SPHERE => a::b }";
        let tokens: Vec<scan::Token> = scan::lex(text)
            .expect("lexes")
            .into_iter()
            .filter(|token| !matches!(token.kind, scan::Tok::Comment { .. }))
            .collect();
        let (name, signature) = list_entry(text, &tokens).expect("an entry");
        assert_eq!(name, "in_shadow");
        assert_eq!(
            signature,
            "fn in_shadow(tracer: &mut Tracer<Self>, normals: &[Vec3; 3]) -> bool"
        );
    }
}
