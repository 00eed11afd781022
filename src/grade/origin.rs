//! Whether a workspace's code is the student's: what `grade --code`
//! refuses to count before it judges anything. A workspace as `raylab new`
//! makes it takes no code from outside its own source files, which no
//! copy detection would see, and runs nothing but its own chapters; each
//! route around that (a `#[path]` module, an `include!`, a link, a build
//! script, a foreign dependency or manifest, a runner, unsafe code) is
//! found here, on a [`Snapshot`] taken before the build.

use std::path::Path;

use super::snapshot::{Entry, Snapshot};

/// The crates a workspace may depend on: those `raylab new` writes.
const ALLOWED_DEPENDENCIES: [&str; 2] = ["raylab", "libm"];

/// The top-level tables of the manifest `raylab new` writes.
const MANIFEST_TABLES: [&str; 4] = ["package", "dependencies", "workspace", "profile"];

/// [`outside_code`] of the workspace as it is now.
pub fn code_from_outside(workspace: &Path) -> Option<String> {
    outside_code(&Snapshot::take(workspace), workspace)
}

/// Where a workspace (`snapshot` of the folder `workspace`) takes code
/// from outside its own source files, which no copy detection would see,
/// or runs something other than its own chapters: a `#[path]` module or an
/// `include!` (of raylab's own chapter files, say) in any of its Rust
/// files, a symbolic link among them, a build script (which could write
/// them into `src/` while it builds), a dependency `raylab new` does not
/// write, a manifest of another shape than the one `raylab new` writes (a
/// `[lib]` path into a classmate's folder, a `[patch]`, a raylab that is
/// not the grader's: see `manifest_shape`), a `.cargo/config.toml` (a
/// `runner` could replace the binary), a `src/main.rs` that is not the one
/// `raylab new` writes, or unsafe code. `None` for a workspace as `raylab
/// new` makes it.
pub fn outside_code(snapshot: &Snapshot, workspace: &Path) -> Option<String> {
    if let Some(why) = &snapshot.incomplete {
        return Some(why.clone());
    }
    let has = |path: &str| {
        snapshot
            .entries
            .iter()
            .any(|(relative, _)| relative == Path::new(path))
    };
    if has("build.rs") {
        return Some("the workspace has a build script, build.rs".into());
    }
    for config in [".cargo/config.toml", ".cargo/config"] {
        if has(config) {
            return Some(format!("the workspace has a {config}"));
        }
    }
    let manifest = snapshot
        .source("Cargo.toml")
        .map(String::from_utf8_lossy)
        .unwrap_or_default();
    // Cargo's own parser may take what this one refuses (a newer TOML: a
    // trailing comma in an inline table); unread, the checks below would
    // not run at all.
    let manifest = match manifest.parse::<toml::Table>() {
        Ok(manifest) => Some(manifest),
        Err(error) => {
            let why = error
                .message()
                .lines()
                .next()
                .unwrap_or_default()
                .to_string();
            return Some(format!(
                "Cargo.toml is not TOML raylab can read ({}), so its shape cannot be checked: \
                 keep the manifest `raylab new` writes",
                crate::text::terminal_safe(&why)
            ));
        }
    };
    if let Some(manifest) = manifest {
        if manifest
            .get("package")
            .and_then(|package| package.get("build"))
            .is_some()
        {
            return Some("Cargo.toml names a build script".into());
        }
        if let Some(other) = foreign_dependency(&manifest) {
            return Some(other);
        }
        if let Some(other) = manifest_shape(&manifest, workspace) {
            return Some(other);
        }
        let package = manifest
            .get("package")
            .and_then(|package| package.get("name"))
            .and_then(toml::Value::as_str)
            .unwrap_or_default()
            .replace('-', "_");
        let main = snapshot
            .source("src/main.rs")
            .map(String::from_utf8_lossy)
            .unwrap_or_default();
        let expected = format!(
            "fn main() {{\n    std::process::exit(raylab::cli::main_with::<{package}::{}>())\n}}\n",
            crate::workspace::STUDENT_TYPE
        );
        if main.trim() != expected.trim() {
            return Some("src/main.rs is not the one `raylab new` writes".into());
        }
    }
    for (path, entry) in &snapshot.entries {
        let shown = || crate::text::visible_name(path.as_os_str());
        let rust = path.extension().is_some_and(|ext| ext == "rs");
        let text = match entry {
            Entry::Link => return Some(format!("{} is a symbolic link", shown())),
            Entry::Source(Some(bytes)) if rust => String::from_utf8_lossy(bytes),
            // Too large (or unreadable) to be read, it would be neither
            // checked here nor compared, yet the compiler reads it whole.
            Entry::Source(None) if rust => {
                return Some(format!(
                    "{} could not be read (a Rust file is at most {} MiB), so it cannot be \
                     checked",
                    shown(),
                    super::snapshot::MAX_SOURCE_BYTES >> 20
                ));
            }
            _ => continue,
        };
        // Tokens the checks cannot read could hide anything from them.
        let parsed: Vec<(&str, proc_macro2::TokenStream)> = readings(&text)
            .into_iter()
            .filter_map(|reading| Some((reading, reading.parse().ok()?)))
            .collect();
        // The walks below recurse once per bracket: a file nested deeper
        // than the grader's stack holds is refused before them.
        if parsed
            .iter()
            .any(|(_, stream)| super::similarity::nesting(stream) > super::similarity::MAX_NESTING)
        {
            return Some(format!(
                "{} nests brackets more than {} deep, so it cannot be checked",
                shown(),
                super::similarity::MAX_NESTING
            ));
        }
        let readings: Vec<&str> = parsed.into_iter().map(|(reading, _)| reading).collect();
        if readings.is_empty() {
            return Some(format!(
                "{} is not Rust whose tokens raylab can read, so it cannot be checked",
                shown()
            ));
        }
        for reading in readings {
            if let Some((line, what)) = outside_reference(reading) {
                return Some(format!(
                    "{}:{line} takes code from another file with {what}",
                    shown()
                ));
            }
            if let Some((line, what)) = unsafe_code(reading) {
                return Some(format!(
                    "{}:{line} uses {what}, which the course never needs and which could \
                     reach the pipes the grader reads the answers from",
                    shown()
                ));
            }
        }
    }
    None
}

/// The ways the compiler may read the Rust file `text`: without a leading
/// byte order mark, and, where its first line starts with `#!`, both with
/// and without that line. rustc skips such a line (a shebang) unless an
/// inner attribute's `[` follows; read whole, a quote on it opens a
/// string that would hide every token after it (`unsafe`, `#[path]`)
/// from the checks, so each reading is checked. The line is cut, not its
/// end: the line numbers stay the file's.
fn readings(text: &str) -> Vec<&str> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut readings = vec![text];
    if text.starts_with("#!") {
        readings.push(text.find('\n').map_or("", |end| &text[end..]));
    }
    readings
}

/// Where `manifest` (of the workspace in `workspace`) is not of the shape
/// `raylab new` writes, in words. Only the tables it writes
/// ([`MANIFEST_TABLES`]: a `[lib]` or `[[bin]]` with a path of its own, a
/// `[patch]` or a `[replace]` would build another crate's code as the
/// student's), no `package.workspace` (whose root's patches would apply),
/// an empty `[workspace]` (a member would be built too), and the two
/// dependencies exactly as written: `raylab` by a path to the raylab that
/// grades it, with the `student` feature and nothing else (a patched copy
/// of raylab, inside `.git/` say, would answer for the student), and
/// `libm` from the registry.
fn manifest_shape(manifest: &toml::Table, workspace: &Path) -> Option<String> {
    let safe = crate::text::terminal_safe;
    if let Some(other) = manifest
        .keys()
        .find(|key| !MANIFEST_TABLES.contains(&key.as_str()))
    {
        return Some(format!(
            "Cargo.toml has [{}], which `raylab new` does not write: a workspace's manifest \
             keeps the shape `raylab new` gives it",
            safe(other)
        ));
    }
    if manifest
        .get("package")
        .and_then(|package| package.get("workspace"))
        .is_some()
    {
        return Some("Cargo.toml's [package] names a workspace to belong to".into());
    }
    if manifest
        .get("workspace")
        .is_some_and(|table| table.as_table().is_none_or(|table| !table.is_empty()))
    {
        return Some("Cargo.toml's [workspace] is not the empty one `raylab new` writes".into());
    }
    let edition = manifest
        .get("package")
        .and_then(|package| package.get("edition"))
        .and_then(toml::Value::as_str);
    if edition != Some(crate::workspace::EDITION) {
        return Some(format!(
            "Cargo.toml's edition is not {}, the one `raylab new` writes (in it, code that links \
             other code in, an `unsafe extern` block, is unsafe code)",
            crate::workspace::EDITION
        ));
    }
    let dependencies = manifest.get("dependencies").and_then(toml::Value::as_table);
    let raylab = dependencies.and_then(|table| table.get("raylab"));
    if !is_graders_raylab(raylab, workspace) {
        return Some(format!(
            "the raylab dependency is not the one `raylab new` writes: raylab = {{ path = {}, \
             features = [\"student\"] }}, the raylab grading it",
            toml::Value::String(crate::workspace::RAYLAB_DIR.to_string())
        ));
    }
    let libm = dependencies.and_then(|table| table.get("libm"));
    if libm.is_some_and(|libm| libm.as_str() != Some("0.2")) {
        return Some(
            "the libm dependency is not the one `raylab new` writes: libm = \"0.2\", from the \
             registry"
                .into(),
        );
    }
    None
}

/// Whether `raylab` (the dependency's value) is `{ path = P, features =
/// ["student"] }` with `P` (relative to `workspace`) the folder of the
/// raylab running now.
fn is_graders_raylab(raylab: Option<&toml::Value>, workspace: &Path) -> bool {
    let Some(table) = raylab.and_then(toml::Value::as_table) else {
        return false;
    };
    let mut keys: Vec<&str> = table.keys().map(String::as_str).collect();
    keys.sort_unstable();
    let student = table
        .get("features")
        .and_then(toml::Value::as_array)
        .is_some_and(|features| features.len() == 1 && features[0].as_str() == Some("student"));
    let Some(path) = table.get("path").and_then(toml::Value::as_str) else {
        return false;
    };
    let same_folder = match (
        workspace.join(path).canonicalize(),
        Path::new(crate::workspace::RAYLAB_DIR).canonicalize(),
    ) {
        (Ok(theirs), Ok(ours)) => theirs == ours,
        _ => false,
    };
    keys == ["features", "path"] && student && same_folder
}

/// The first dependency of any kind (normal, build, dev, and each of them
/// per target) that `raylab new` does not write, in words.
fn foreign_dependency(manifest: &toml::Table) -> Option<String> {
    let kinds = ["dependencies", "build-dependencies", "dev-dependencies"];
    let mut tables: Vec<(String, &toml::Table)> = kinds
        .iter()
        .filter_map(|kind| Some((format!("[{kind}]"), manifest.get(*kind)?.as_table()?)))
        .collect();
    if let Some(targets) = manifest.get("target").and_then(toml::Value::as_table) {
        for (target, table) in targets {
            for kind in kinds {
                if let Some(names) = table.get(kind).and_then(toml::Value::as_table) {
                    tables.push((format!("[target.{target}.{kind}]"), names));
                }
            }
        }
    }
    tables.into_iter().find_map(|(table, names)| {
        names
            .keys()
            .find(|name| !ALLOWED_DEPENDENCIES.contains(&name.as_str()))
            .map(|other| {
                format!(
                    "Cargo.toml's {} adds `{}`: a workspace depends on raylab and libm alone",
                    crate::text::terminal_safe(&table),
                    crate::text::terminal_safe(other)
                )
            })
    })
}

/// The line and the form of the first piece of unsafe code in Rust source
/// `text`, read as tokens: the `unsafe` keyword, or what runs code or
/// names a symbol without it in older editions (`#[no_mangle]`,
/// `#[export_name]`, `#[link_section]`, `global_asm!`).
fn unsafe_code(text: &str) -> Option<(usize, &'static str)> {
    use proc_macro2::{TokenStream, TokenTree};
    fn walk(stream: TokenStream) -> Option<(usize, &'static str)> {
        for token in stream {
            match token {
                TokenTree::Ident(ident) => {
                    let what = match resolved(&ident).as_str() {
                        "unsafe" => "unsafe code",
                        "no_mangle" => "#[no_mangle]",
                        "export_name" => "#[export_name]",
                        "link_section" => "#[link_section]",
                        "global_asm" => "global_asm!",
                        _ => continue,
                    };
                    return Some((ident.span().start().line, what));
                }
                TokenTree::Group(group) => {
                    if let Some(found) = walk(group.stream()) {
                        return Some(found);
                    }
                }
                _ => {}
            }
        }
        None
    }
    walk(text.parse().ok()?)
}

/// An identifier as the compiler resolves it: `r#path` is `path`,
/// `r#include!` the `include!` macro.
fn resolved(ident: &proc_macro2::Ident) -> String {
    let name = ident.to_string();
    match name.strip_prefix("r#") {
        Some(plain) => plain.to_string(),
        None => name,
    }
}

/// The line and the form of the first `#[path = ...]` attribute or
/// `include!`-family macro in Rust source `text`, read as tokens (so a
/// comment or a string that mentions one is not one).
///
/// A macro by example can put either together from its arguments, so
/// that no `#[path` or `include!` is ever written: the include-family
/// macros count wherever they are named (`use std::include as inc;`, an
/// argument `via!(include)` that the macro calls as `$m!`), and an
/// attribute counts wherever its `#`, its brackets or what is inside
/// them can come from a macro's arguments (`#[$($t)*]`, `# $b`,
/// `$h [...]`, or brackets handed to a macro whole, `[path = "..."]`).
/// No chapter needs a macro that makes attributes.
fn outside_reference(text: &str) -> Option<(usize, &'static str)> {
    use proc_macro2::{Delimiter, TokenStream, TokenTree};
    const MADE: &str = "an attribute made from a macro's arguments";
    fn walk(stream: TokenStream, in_attribute: bool) -> Option<(usize, &'static str)> {
        let tokens: Vec<TokenTree> = stream.into_iter().collect();
        let punct = |at: Option<usize>| match at.and_then(|at| tokens.get(at)) {
            Some(TokenTree::Punct(p)) => Some(p.as_char()),
            _ => None,
        };
        for (index, token) in tokens.iter().enumerate() {
            let back = |by: usize| index.checked_sub(by);
            match token {
                TokenTree::Ident(ident) => {
                    let name = resolved(ident);
                    if matches!(name.as_str(), "include" | "include_str" | "include_bytes") {
                        return Some((ident.span().start().line, "an include! macro"));
                    }
                    if in_attribute && name == "path" {
                        return Some((ident.span().start().line, "a #[path] attribute"));
                    }
                    // A native library the linker takes in: code no Rust
                    // file holds, and that the compiler's list of the
                    // files it read does not name.
                    if in_attribute
                        && matches!(name.as_str(), "link" | "link_name" | "link_ordinal")
                    {
                        return Some((ident.span().start().line, "a #[link] attribute"));
                    }
                    let starts_block = |at: usize| matches!(tokens.get(at), Some(TokenTree::Group(group)) if group.delimiter() == Delimiter::Brace);
                    let abi = matches!(tokens.get(index + 1), Some(TokenTree::Literal(_)));
                    if name == "extern"
                        && (starts_block(index + 1) || (abi && starts_block(index + 2)))
                    {
                        return Some((ident.span().start().line, "an extern block"));
                    }
                }
                TokenTree::Punct(p) if p.as_char() == '$' && in_attribute => {
                    return Some((p.span().start().line, MADE));
                }
                TokenTree::Punct(p) if p.as_char() == '#' => {
                    // `# $b` or `#! $b`: brackets from a macro's argument.
                    let next = if punct(Some(index + 1)) == Some('!') {
                        index + 2
                    } else {
                        index + 1
                    };
                    if punct(Some(next)) == Some('$') {
                        return Some((p.span().start().line, MADE));
                    }
                }
                TokenTree::Group(group) => {
                    let bracket = group.delimiter() == Delimiter::Bracket;
                    // `#[...]` or `#![...]`, not `vec![...]`.
                    let after_hash = punct(back(1)) == Some('#')
                        || (punct(back(1)) == Some('!') && punct(back(2)) == Some('#'));
                    // `$h [...]`: the `#` may be a macro's argument.
                    let after_argument =
                        matches!(back(1).map(|at| &tokens[at]), Some(TokenTree::Ident(_)))
                            && punct(back(2)) == Some('$');
                    // Brackets a macro may put a `#` before: `[path = ...]`,
                    // `[cfg_attr(...)]` or `[$...]`, but not a macro call's
                    // own (`vec![$($x),*]`).
                    let mut inside = group.stream().into_iter();
                    let looks_like = punct(back(1)) != Some('!')
                        && match (inside.next(), inside.next()) {
                            (Some(TokenTree::Ident(first)), second) => {
                                match resolved(&first).as_str() {
                                    "cfg_attr" => true,
                                    "path" => {
                                        matches!(second, Some(TokenTree::Punct(p)) if p.as_char() == '=')
                                    }
                                    _ => false,
                                }
                            }
                            (Some(TokenTree::Punct(p)), _) => p.as_char() == '$',
                            _ => false,
                        };
                    let attribute =
                        in_attribute || (bracket && (after_hash || after_argument || looks_like));
                    if let Some(found) = walk(group.stream(), attribute) {
                        return Some(found);
                    }
                }
                _ => {}
            }
        }
        None
    }
    // Text the tokeniser refuses cannot compile either: the build says why.
    walk(text.parse().ok()?, false)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn code_from_other_files_is_found_as_tokens() {
        let found = outside_reference;
        assert_eq!(
            found("fn a() {}\n#[path = \"/raylab/chapters/answer.rs\"]\nmod key;"),
            Some((2, "a #[path] attribute"))
        );
        assert_eq!(
            found("#![cfg_attr(all(), path = \"x.rs\")]"),
            Some((1, "a #[path] attribute"))
        );
        assert_eq!(
            found("fn f() -> &'static str { include_str!(\"/etc/passwd\") }"),
            Some((1, "an include! macro"))
        );
        assert_eq!(
            found("mod m { fn g() { include!(concat!(env!(\"OUT_DIR\"), \"/k.rs\")); } }"),
            Some((1, "an include! macro"))
        );
        assert_eq!(
            unsafe_code("fn f() {\n    let x = unsafe { std::mem::zeroed::<u8>() };\n}"),
            Some((2, "unsafe code"))
        );
        assert_eq!(
            unsafe_code("#[unsafe(link_section = \".init_array\")]\nstatic S: u8 = 0;"),
            Some((1, "unsafe code"))
        );
        assert_eq!(
            unsafe_code("#[no_mangle]\npub fn g() {}"),
            Some((1, "#[no_mangle]"))
        );
        assert_eq!(
            unsafe_code("// unsafe\nfn h() -> &'static str { \"unsafe\" }"),
            None
        );
        // Mentions in comments and strings, a variable named path, a
        // macro's brackets: none of them.
        assert_eq!(
            found(
                "// #[path = \"x\"] include!()\nfn h(path: u8) -> Vec<u8> { let _ = \"include!(\"; vec![path] }"
            ),
            None
        );
    }

    /// The compiler resolves a raw identifier as the plain one, and a
    /// macro by example can put together, from its arguments, an
    /// attribute or a macro call that its text never spells out: each of
    /// these compiled with rustc 1.95 and took code from `key.txt`.
    #[test]
    fn code_from_other_files_is_found_through_raw_names_and_macros() {
        let found = |text: &str| outside_reference(text).map(|(line, _)| line);
        // The line is the route's first token the checks see: the call or
        // the macro's definition.
        let routes = [
            "fn a() {}\n#[r#path = \"key.txt\"]\nmod k;",
            "fn a() {}\nmod k { r#include!(\"key.txt\"); }",
            "fn a() {}\nuse std::include as inc;\nmod k { super::inc!(\"key.txt\"); }",
            "macro_rules! via { ($m:ident) => { $m!(\"key.txt\"); } }\nmod k { via!(include); }",
            "fn a() {}\nmacro_rules! m { ($($t:tt)*) => { #[$($t)*] mod k; } }\nm!(path = \"key.txt\");",
            "fn a() {}\nmacro_rules! m { ($b:tt) => { # $b mod k; } }\nm!([path = \"key.txt\"]);",
            "fn a() {}\nmacro_rules! s { ($h:tt , $b:tt) => { $h $b mod k; } }\ns!(# , [path = \"key.txt\"]);",
            "fn a() {}\nmacro_rules! o { ($p:ident) => { s!(# , [$p = \"key.txt\"]); } }\no!(path);",
            "fn a() {}\nmacro_rules! s { ($h:tt $($t:tt)*) => { $h [$($t)*] mod k; } }\ns!(# path = \"key.txt\");",
        ];
        for route in routes {
            assert!(matches!(found(route), Some(2 | 3)), "{route}");
        }
        assert_eq!(
            unsafe_code("fn a() {}\n#[r#no_mangle]\npub extern \"C\" fn g() {}"),
            Some((2, "#[no_mangle]"))
        );
        // An array, a vec! of a macro's arguments, a variable named path:
        // none of them.
        assert_eq!(
            found(
                "macro_rules! v { ($($x:expr),*) => { vec![$($x),*] } }\nfn f(path: u8) -> [u8; 1] { [path] }"
            ),
            None
        );
    }

    /// Rewrites the file at `path` with `change`.
    fn edit(path: &Path, change: impl FnOnce(String) -> String) {
        let text = std::fs::read_to_string(path).expect("read");
        std::fs::write(path, change(text)).expect("write");
    }

    /// Plants a route in a workspace (given it and one of its chapter files).
    type Plant = fn(&Path, &Path);
    /// Deep enough to overflow the grader's stack if walked.
    const DEEP: usize = 30_000;

    /// A workspace as `raylab new` writes it takes nothing from outside;
    /// each route planted in a copy of it is found, one at a time.
    #[test]
    fn a_workspace_as_made_takes_no_code_from_outside_and_each_route_is_found() {
        let folder = tempfile::tempdir().expect("a folder");
        let raylab = Path::new(crate::workspace::RAYLAB_DIR);
        let made = crate::workspace::files("w", raylab, true).expect("the files");
        let write = |workspace: &Path| {
            for (name, text) in &made.0 {
                let path = workspace.join(name);
                std::fs::create_dir_all(path.parent().expect("a folder")).expect("mkdir");
                std::fs::write(path, text).expect("write");
            }
        };
        let fresh = |name: &str| {
            let workspace = folder.path().join(name);
            write(&workspace);
            workspace
        };
        let clean = fresh("clean");
        std::fs::create_dir_all(clean.join("target/release")).expect("mkdir");
        std::fs::write(clean.join("target/release/x.rs"), "include!(\"y\");").expect("write");
        assert_eq!(code_from_outside(&clean), None);
        let chapter = |workspace: &Path| {
            let name = made
                .0
                .iter()
                .map(|(name, _)| name)
                .find(|name| name.starts_with("src/chapters/ch"))
                .expect("a chapter file")
                .clone();
            workspace.join(name)
        };
        let planted: [(&str, Plant, &str); 19] = [
            (
                // Deep enough to overflow the grader's stack if walked.
                "deep-brackets",
                |_, file| {
                    edit(file, |text| {
                        format!(
                            "{text}\nconst _: () = {}{};\n",
                            "(".repeat(DEEP),
                            ")".repeat(DEEP)
                        )
                    });
                },
                "nests brackets more than 256 deep, so it cannot be checked",
            ),
            (
                // As deep, each closing bracket in a string beside an
                // opening one: a count of characters sees no depth at all.
                "deep-brackets-beside-strings",
                |_, file| {
                    edit(file, |text| {
                        let deep = "(\")\", ".repeat(DEEP) + &")".repeat(DEEP);
                        format!("{text}\nconst _: () = {deep}();\n")
                    });
                },
                "nests brackets more than 256 deep, so it cannot be checked",
            ),
            (
                // TOML 1.1, which cargo reads and raylab's parser does not.
                "unreadable-manifest",
                |workspace, _| {
                    edit(&workspace.join("Cargo.toml"), |text| {
                        text.replace("features = [\"student\"] }", "features = [\"student\"], }")
                    });
                },
                "so its shape cannot be checked: keep the manifest `raylab new` writes",
            ),
            (
                "edition",
                |workspace, _| {
                    edit(&workspace.join("Cargo.toml"), |text| {
                        text.replace("edition = \"2024\"", "edition = \"2021\"")
                    });
                },
                "Cargo.toml's edition is not 2024",
            ),
            (
                "link",
                |_, file| {
                    edit(file, |text| {
                        format!(
                            "{text}\n#[link(name = \"answers\", kind = \"dylib\")]\nextern \"C\" {{}}\n"
                        )
                    });
                },
                "takes code from another file with a #[link] attribute",
            ),
            (
                "link-in-cfg-attr",
                |_, file| {
                    edit(file, |text| {
                        format!(
                            "{text}\n#[cfg_attr(all(), r#link(name = \"answers\"))]\nextern {{}}\n"
                        )
                    });
                },
                "takes code from another file with a #[link] attribute",
            ),
            (
                "extern-block",
                |_, file| {
                    edit(file, |text| {
                        format!(
                            "{text}\nextern \"C\" {{\n    fn hypot(x: f64, y: f64) -> f64;\n}}\n"
                        )
                    });
                },
                "takes code from another file with an extern block",
            ),
            (
                "include",
                |_, file| {
                    edit(file, |text| format!("{text}\ninclude!(\"../../k.rs\");"));
                },
                "takes code from another file with an include! macro",
            ),
            (
                "symlink",
                |workspace, _| {
                    std::os::unix::fs::symlink("/etc/hostname", workspace.join("src/key.rs"))
                        .expect("link");
                },
                "src/key.rs is a symbolic link",
            ),
            (
                "target-dependency",
                |workspace, _| {
                    edit(&workspace.join("Cargo.toml"), |text| {
                        format!(
                            "{text}\n[target.'cfg(all())'.dependencies]\nkey = {{ path = \"/k\" }}\n"
                        )
                    });
                },
                "adds `key`",
            ),
            (
                "config",
                |workspace, _| {
                    std::fs::create_dir_all(workspace.join(".cargo")).expect("mkdir");
                    std::fs::write(workspace.join(".cargo/config.toml"), "").expect("write");
                },
                ".cargo/config.toml",
            ),
            (
                "build-script",
                |workspace, _| {
                    std::fs::write(workspace.join("build.rs"), "fn main() {}").expect("write")
                },
                "build.rs",
            ),
            (
                "main",
                |workspace, _| {
                    std::fs::write(workspace.join("src/main.rs"), "fn main() {}\n").expect("write")
                },
                "src/main.rs is not the one",
            ),
            (
                "path-in-tests",
                |workspace, _| {
                    std::fs::write(
                        workspace.join("tests/key.rs"),
                        "#[path = \"/k.rs\"]\nmod key;",
                    )
                    .expect("write")
                },
                "tests/key.rs:1 takes code from another file with a #[path] attribute",
            ),
            (
                "raylab-in-git",
                |workspace, _| {
                    let path = workspace.join("Cargo.toml");
                    let text = std::fs::read_to_string(&path).expect("read");
                    let line = text
                        .lines()
                        .find(|line| line.starts_with("raylab = "))
                        .expect("the raylab dependency");
                    let patched = text.replace(
                        line,
                        "raylab = { path = \".git/raylab\", features = [\"student\"] }",
                    );
                    std::fs::write(&path, patched).expect("write");
                },
                "the raylab dependency is not the one `raylab new` writes",
            ),
            (
                "raylab-without-student",
                |workspace, _| {
                    edit(&workspace.join("Cargo.toml"), |text| {
                        text.replace(", features = [\"student\"]", "")
                    });
                },
                "the raylab dependency is not the one `raylab new` writes",
            ),
            (
                "lib-path",
                |workspace, _| {
                    edit(&workspace.join("Cargo.toml"), |text| {
                        format!("{text}\n[lib]\npath = \"../classmate/src/lib.rs\"\n")
                    });
                },
                "Cargo.toml has [lib], which `raylab new` does not write",
            ),
            (
                "patch",
                |workspace, _| {
                    edit(&workspace.join("Cargo.toml"), |text| {
                        format!("{text}\n[patch.crates-io]\nlibm = {{ path = \".git/libm\" }}\n")
                    });
                },
                "Cargo.toml has [patch], which `raylab new` does not write",
            ),
            (
                "libm-path",
                |workspace, _| {
                    edit(&workspace.join("Cargo.toml"), |text| {
                        text.replace("libm = \"0.2\"", "libm = { path = \".git/libm\" }")
                    });
                },
                "the libm dependency is not the one `raylab new` writes",
            ),
        ];
        for (name, plant, expected) in planted {
            let workspace = fresh(name);
            plant(&workspace, &chapter(&workspace));
            let found = code_from_outside(&workspace).unwrap_or_default();
            assert!(found.contains(expected), "{name}: {found:?}");
        }
    }

    /// rustc skips a first line that starts with `#!` (a shebang): a quote
    /// on it must not hide the file's code from the checks as a string;
    /// and a Rust file too large for the snapshot to read is not passed
    /// over unchecked (the compiler reads it whole).
    #[test]
    fn a_shebang_line_or_a_source_too_large_to_read_hides_no_code() {
        let folder = tempfile::tempdir().expect("a folder");
        let raylab = Path::new(crate::workspace::RAYLAB_DIR);
        let made = crate::workspace::files("w", raylab, true).expect("the files");
        let chapter = made
            .0
            .iter()
            .map(|(name, _)| name.clone())
            .find(|name| name.starts_with("src/chapters/ch"))
            .expect("a chapter file");
        let planted: [(&str, String, &str); 4] = [
            (
                "shebang-path",
                "#!/bin/x \"\n#[path = \"../../notes/key.txt\"] mod key; // \"\n".into(),
                ":2 takes code from another file with a #[path] attribute",
            ),
            (
                "shebang-unsafe",
                "\u{feff}#!/bin/x \"\npub fn f() -> u8 { unsafe { *(&1u8 as *const u8) } } // \"\n"
                    .into(),
                ":2 uses unsafe code",
            ),
            (
                "too-large",
                format!(
                    "include!(\"../../notes/key.txt\");\n/*{}*/\n",
                    " ".repeat((super::super::snapshot::MAX_SOURCE_BYTES + 1) as usize)
                ),
                "could not be read",
            ),
            (
                "no-tokens",
                "pub fn f() -> &'static str { \"unterminated }\n".into(),
                "is not Rust whose tokens raylab can read",
            ),
        ];
        for (name, text, expected) in planted {
            let workspace = folder.path().join(name);
            for (file, made_text) in &made.0 {
                let path = workspace.join(file);
                std::fs::create_dir_all(path.parent().expect("a folder")).expect("mkdir");
                std::fs::write(path, made_text).expect("write");
            }
            std::fs::write(workspace.join(&chapter), text).expect("write");
            let found = code_from_outside(&workspace).unwrap_or_default();
            assert!(found.contains(expected), "{name}: {found:?}");
        }
        // An inner attribute on the first line is not a shebang, and is fine.
        let workspace = folder.path().join("attribute");
        for (file, made_text) in &made.0 {
            let path = workspace.join(file);
            std::fs::create_dir_all(path.parent().expect("a folder")).expect("mkdir");
            let text = if *file == chapter {
                format!("#![allow(\n    unused_imports,\n)]\n{made_text}")
            } else {
                made_text.clone()
            };
            std::fs::write(path, text).expect("write");
        }
        assert_eq!(code_from_outside(&workspace), None);
    }
}
