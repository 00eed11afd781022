//! What the build of a workspace compiled, from cargo's and rustc's own
//! records: the crates (cargo's JSON messages) and, for the student's
//! library, every file the compiler read (rustc's dep-info). No macro can
//! hide an include from these, where the token checks of
//! [`super::origin`] read only the sources.

use std::path::Path;

use super::snapshot::Snapshot;

/// What cargo's messages say one of the workspace's own crates was built
/// from: its kind (`lib`, `bin`), its root file, and, for a library, the
/// compiler's list of the files it read (rustc's dep-info, `deps/NAME-HASH.d`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Compiled {
    /// The manifest of its package.
    pub manifest: std::path::PathBuf,
    /// Whether its package is not a registry's (a folder on this machine,
    /// a git repository).
    pub local: bool,
    pub kinds: Vec<String>,
    pub root: std::path::PathBuf,
    pub dep_info: Option<std::path::PathBuf>,
}

/// The most bytes of a dep-info file read: a course's crate lists a few
/// dozen files.
const MAX_DEP_INFO_BYTES: u64 = 1 << 20;

/// Where the compiler, building the workspace's crates (`compiled`, from
/// cargo's messages), read anything but the snapshot's Rust files under
/// `src/`, in words; `None` when it read only those.
///
/// The token checks of [`super::origin::outside_code`] read the sources; this reads what
/// the build did, which no macro can hide (a macro that assembles
/// `include!` from pieces still makes the compiler list the file). The
/// list is trustworthy because nothing of the student's runs before or
/// during the build (no build script, no dependency of theirs), and their
/// binary later sees `target/` read-only. A program other than the one
/// `raylab new` writes is refused too: its code would be what answers.
pub fn compiled_from_outside(
    compiled: &[Compiled],
    snapshot: &Snapshot,
    workspace: &Path,
) -> Option<String> {
    // Relative to the workspace where it is inside, as the report names
    // the workspace's files.
    let shown = |path: &Path| {
        crate::text::visible_name(path.strip_prefix(workspace).unwrap_or(path).as_os_str())
    };
    let raylab = Path::new(crate::workspace::RAYLAB_DIR).join("Cargo.toml");
    let same = |a: &Path, b: &Path| {
        a == b || matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b)
    };
    // Every finding, not the first: a stand-in crate would hide an
    // include from the report.
    let mut found = Vec::new();
    // Its dep-info is what says which files the student's code came from:
    // a build cargo did not report is not one to take on trust.
    let library_reported = compiled.iter().any(|unit| {
        same(&unit.manifest, &workspace.join("Cargo.toml"))
            && unit.kinds.iter().any(|kind| kind == "lib")
    });
    if !library_reported {
        found.push(
            "cargo did not report building the workspace's library, so the files the compiler \
             read cannot be checked"
                .into(),
        );
    }
    for unit in compiled {
        if !same(&unit.manifest, &workspace.join("Cargo.toml")) {
            // Registry crates are the dependencies' own (libm, raylab's);
            // a folder other than the grader's raylab is code of the
            // student's choosing, whatever the manifest said.
            if unit.local && !same(&unit.manifest, &raylab) {
                found.push(format!(
                    "the build compiled a crate `raylab new` does not write, from {}",
                    shown(&unit.manifest)
                ));
            }
            continue;
        }
        let lib = unit.kinds.iter().any(|kind| kind == "lib");
        let bin = unit.kinds.iter().any(|kind| kind == "bin");
        if bin && !lib {
            // Its text is checked to be the one `raylab new` writes, which
            // reads no other file.
            if unit.root != workspace.join("src/main.rs") {
                found.push(format!(
                    "the workspace builds a program of its own, {}",
                    shown(&unit.root)
                ));
            }
            continue;
        }
        if !lib || unit.root != workspace.join("src/lib.rs") {
            found.push(format!(
                "the workspace builds a crate `raylab new` does not write, {}",
                shown(&unit.root)
            ));
            continue;
        }
        let Some(dep_info) = &unit.dep_info else {
            found.push("the compiler's list of the files it read is missing".into());
            continue;
        };
        let text = match read_bounded(dep_info) {
            Ok(text) => text,
            Err(why) => {
                found.push(format!(
                    "the compiler's list of the files it read, {}, {why}",
                    shown(dep_info)
                ));
                continue;
            }
        };
        let outside = dep_info_files(&text).into_iter().find_map(|read| {
            let inside = lexically_inside(&read, workspace);
            let counted = inside.as_deref().is_some_and(|relative| {
                relative.starts_with("src")
                    && relative.extension().is_some_and(|ext| ext == "rs")
                    && relative
                        .to_str()
                        .is_some_and(|path| snapshot.source(path).is_some())
            });
            (!counted).then(|| inside.unwrap_or(read))
        });
        if let Some(named) = outside {
            found.push(format!(
                "the compiler read {}, which is not one of the workspace's Rust files under src/",
                shown(&named)
            ));
        }
    }
    found.dedup();
    (!found.is_empty()).then(|| found.join("; "))
}

/// The file at `path`, as text, if it is a regular file of at most
/// [`MAX_DEP_INFO_BYTES`]; else why not, in words.
fn read_bounded(path: &Path) -> Result<String, String> {
    use std::io::Read;
    let meta =
        std::fs::symlink_metadata(path).map_err(|error| format!("cannot be read: {error}"))?;
    if !meta.is_file() {
        return Err("is not a file".into());
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|file| file.take(MAX_DEP_INFO_BYTES + 1).read_to_end(&mut bytes))
        .map_err(|error| format!("cannot be read: {error}"))?;
    if bytes.len() as u64 > MAX_DEP_INFO_BYTES {
        return Err(format!("is over {} KiB", MAX_DEP_INFO_BYTES >> 10));
    }
    String::from_utf8(bytes).map_err(|_| "is not UTF-8".into())
}

/// Every file a Makefile-style dep-info `text` lists as a prerequisite
/// (rustc escapes a space in a name as `\ `); `#` lines are comments
/// (rustc notes the environment variables it read there).
fn dep_info_files(text: &str) -> Vec<std::path::PathBuf> {
    let mut files = Vec::new();
    for line in text.lines().filter(|line| !line.starts_with('#')) {
        let mut words = Vec::new();
        let mut word = String::new();
        let mut chars = line.chars().peekable();
        while let Some(c) = chars.next() {
            match c {
                '\\' if chars.peek() == Some(&' ') => {
                    word.push(' ');
                    chars.next();
                }
                ' ' => {
                    if !word.is_empty() {
                        words.push(std::mem::take(&mut word));
                    }
                }
                _ => word.push(c),
            }
        }
        if !word.is_empty() {
            words.push(word);
        }
        // The first word is the rule's target, `NAME:`; the rest are what
        // it was made from.
        let Some(target) = words.first() else {
            continue;
        };
        if !target.ends_with(':') {
            continue;
        }
        files.extend(words[1..].iter().map(std::path::PathBuf::from));
    }
    files
}

/// `path` (absolute, or relative to `workspace`, where cargo runs the
/// compiler) relative to `workspace`, resolving `.` and `..` by their
/// names; `None` when it is outside.
fn lexically_inside(path: &Path, workspace: &Path) -> Option<std::path::PathBuf> {
    use std::path::Component;
    let relative = if path.is_absolute() {
        path.strip_prefix(workspace).ok()?
    } else {
        path
    };
    let mut inside = std::path::PathBuf::new();
    for component in relative.components() {
        match component {
            Component::Normal(name) => inside.push(name),
            Component::CurDir => {}
            Component::ParentDir => {
                if !inside.pop() {
                    return None;
                }
            }
            Component::RootDir | Component::Prefix(_) => return None,
        }
    }
    Some(inside)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A space in a name is escaped; comments (the environment variables
    /// rustc read) and the empty rules for each file are no files.
    #[test]
    fn a_dep_info_lists_each_file_once_per_rule_with_its_spaces() {
        let text = "/w/target/debug/deps/w-1.d: src/lib.rs src/my\\ chapter.rs\n\n\
                    src/lib.rs:\nsrc/my\\ chapter.rs:\n\n# env-dep:CARGO_PKG_NAME=w\n";
        let files = dep_info_files(text);
        assert_eq!(
            files,
            [Path::new("src/lib.rs"), Path::new("src/my chapter.rs")]
        );
    }

    /// What rustc itself lists, for a crate that reads only its own files
    /// and for each way of reading another: a file beside `src/`, a
    /// classmate's, one under `src/` that is not Rust. And a program or a
    /// crate `raylab new` does not write.
    #[test]
    fn the_compiler_reading_any_file_but_the_workspaces_rust_is_found() {
        let folder = tempfile::tempdir().expect("a folder");
        let workspace = folder.path().join("w");
        std::fs::create_dir_all(workspace.join("src")).expect("mkdir");
        std::fs::create_dir_all(folder.path().join("classmate")).expect("mkdir");
        std::fs::write(workspace.join("Cargo.toml"), "[package]\nname = \"w\"\n").expect("write");
        std::fs::write(workspace.join("key.txt"), "1").expect("write");
        std::fs::write(workspace.join("src/notes.txt"), "1").expect("write");
        std::fs::write(folder.path().join("classmate/key.rs"), "pub fn k() {}").expect("write");
        std::fs::write(workspace.join("src/chapter.rs"), "pub fn c() {}").expect("write");
        let lib = |extra: &str| format!("mod chapter;\n{extra}\n");
        let compile = |text: &str| -> Option<String> {
            std::fs::write(workspace.join("src/lib.rs"), text).expect("write");
            let deps = workspace.join("target/debug/deps");
            std::fs::create_dir_all(&deps).expect("mkdir");
            let status = std::process::Command::new("rustc")
                .args([
                    "--edition",
                    "2021",
                    "--crate-type",
                    "lib",
                    "--crate-name",
                    "w",
                ])
                .args([
                    "--emit",
                    "dep-info,metadata",
                    "-C",
                    "extra-filename=-1",
                    "-A",
                    "warnings",
                ])
                .arg("--out-dir")
                .arg(&deps)
                .arg("src/lib.rs")
                .current_dir(&workspace)
                .status()
                .expect("rustc");
            assert!(status.success(), "{text}");
            let unit = Compiled {
                manifest: workspace.join("Cargo.toml"),
                local: true,
                kinds: vec!["lib".into()],
                root: workspace.join("src/lib.rs"),
                dep_info: Some(deps.join("w-1.d")),
            };
            compiled_from_outside(&[unit], &Snapshot::take(&workspace), &workspace)
        };
        assert_eq!(compile(&lib("")), None);
        for (route, named) in [
            (
                "pub const K: &str = include_str!(\"../key.txt\");",
                "key.txt",
            ),
            (
                "pub const K: &str = include_str!(concat!(\"no\", \"tes.txt\"));",
                "src/notes.txt",
            ),
            (
                "#[path = \"../../classmate/key.rs\"]\nmod key;",
                "classmate/key.rs",
            ),
        ] {
            let found = compile(&lib(route)).unwrap_or_default();
            assert!(found.contains(named), "{route}: {found}");
            assert!(
                found.contains("which is not one of the workspace's Rust files"),
                "{found}"
            );
        }
        let unit = |kind: &str, root: &str, dep_info: Option<&str>| Compiled {
            manifest: workspace.join("Cargo.toml"),
            local: true,
            kinds: vec![kind.into()],
            root: workspace.join(root),
            dep_info: dep_info.map(|name| workspace.join(name)),
        };
        let snapshot = Snapshot::take(&workspace);
        for (units, expected) in [
            (
                vec![unit("bin", "src/bin/other.rs", None)],
                "builds a program of its own",
            ),
            (
                vec![unit("lib", "src/other.rs", None)],
                "a crate `raylab new` does not write",
            ),
            (
                vec![unit("lib", "src/lib.rs", None)],
                "list of the files it read is missing",
            ),
            (
                vec![unit("lib", "src/lib.rs", Some("target/none.d"))],
                "target/none.d, cannot be read",
            ),
        ] {
            let found = compiled_from_outside(&units, &snapshot, &workspace).unwrap_or_default();
            assert!(found.contains(expected), "{found}");
        }
        // The generated program is fine; a build that reported no library
        // is not.
        let found =
            compiled_from_outside(&[unit("bin", "src/main.rs", None)], &snapshot, &workspace)
                .unwrap_or_default();
        assert_eq!(
            found,
            "cargo did not report building the workspace's library, so the files the compiler \
             read cannot be checked"
        );
        // Another crate: the grader's raylab or a registry's is fine; any
        // other folder is not, whatever the manifest said.
        let other = |manifest: &Path, local: bool| Compiled {
            manifest: manifest.to_path_buf(),
            local,
            kinds: vec!["lib".into()],
            root: manifest.with_file_name("src/lib.rs"),
            dep_info: None,
        };
        let raylab = Path::new(crate::workspace::RAYLAB_DIR).join("Cargo.toml");
        let registry = Path::new("/cargo/registry/libm-0.2/Cargo.toml");
        let vendored = workspace.join("vendor/key/Cargo.toml");
        let found = compiled_from_outside(
            &[other(&raylab, true), other(registry, false)],
            &snapshot,
            &workspace,
        )
        .unwrap_or_default();
        assert!(
            !found.contains("a crate `raylab new` does not write"),
            "{found}"
        );
        let found = compiled_from_outside(&[other(&vendored, true)], &snapshot, &workspace)
            .unwrap_or_default();
        assert!(
            found.contains(
                "compiled a crate `raylab new` does not write, from vendor/key/Cargo.toml"
            ),
            "{found}"
        );
    }
}
