//! A student workspace's sources as they were before its build: what the
//! code-origin check reads (`grade::origin::code_from_outside`), what the
//! similarity report compares, and what those files must still be once
//! the run is over.
//!
//! The build runs none of the student's code (a build script, a
//! procedural macro or a dependency of its own is refused), so what is
//! built is what the snapshot holds. The student's binary runs afterwards,
//! and could rewrite its chapter files while it is checked (outside the
//! sandbox): read then, they would be compared as the binary left them,
//! not as they were built. So the snapshot is read once, first, and a
//! workspace whose sources differ from it at the end is not counted.

use std::path::{Path, PathBuf};

/// The most Rust files a workspace may hold.
pub const MAX_RUST_FILES: usize = 1000;

/// The most entries (files, folders, links; `target/` and `.git/` aside)
/// of a workspace that is graded: beyond, the snapshot is incomplete and
/// the workspace is not copied, and reading more would cost the grader
/// memory (1.2 million empty files held 494 MB).
pub const MAX_ENTRIES: usize = 100_000;

/// The largest source file read, in bytes.
pub const MAX_SOURCE_BYTES: u64 = crate::input::MAX_SCENE_BYTES;

/// The most bytes of sources read in all: a course's workspace is a few
/// hundred kilobytes, and the checks hold each file's tokens, tens of
/// times its text, for every student graded at once.
pub const MAX_SNAPSHOT_BYTES: u64 = 16 << 20;

/// One entry of the workspace, as the snapshot saw it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Entry {
    /// Code the build reads (a Rust file, `Cargo.toml`), with its bytes;
    /// `None` when it could not be read.
    Source(Option<Vec<u8>>),
    /// Any other regular file: the build does not read it.
    Other,
    /// A symbolic link, never followed.
    Link,
    /// A folder.
    Folder,
}

/// The workspace's entries, by path relative to it, sorted; its build
/// output (`target/`) and git's folder (`.git/`) left out.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Snapshot {
    pub entries: Vec<(PathBuf, Entry)>,
    /// Why the snapshot is not the whole workspace (too many files or
    /// bytes), in words; `None` when it is.
    pub incomplete: Option<String>,
}

impl Snapshot {
    /// Reads `workspace` (see [`Snapshot`]).
    pub fn take(workspace: &Path) -> Snapshot {
        Snapshot::take_within(workspace, MAX_ENTRIES)
    }

    /// [`Snapshot::take`], incomplete past `most_entries`.
    fn take_within(workspace: &Path, most_entries: usize) -> Snapshot {
        let mut snapshot = Snapshot::default();
        let mut folders = vec![PathBuf::new()];
        let (mut rust_files, mut bytes) = (0usize, 0u64);
        'walk: while let Some(folder) = folders.pop() {
            let Ok(entries) = std::fs::read_dir(workspace.join(&folder)) else {
                continue;
            };
            for entry in entries.flatten() {
                if snapshot.entries.len() >= most_entries {
                    snapshot.incomplete = Some(format!(
                        "the workspace holds more than {most_entries} files and folders"
                    ));
                    break 'walk;
                }
                let relative = folder.join(entry.file_name());
                let Ok(kind) = entry.file_type() else {
                    continue;
                };
                let found = if kind.is_symlink() {
                    Entry::Link
                } else if kind.is_dir() {
                    // The build's own output, and git's.
                    if folder.as_os_str().is_empty()
                        && (entry.file_name() == "target" || entry.file_name() == ".git")
                    {
                        continue;
                    }
                    folders.push(relative.clone());
                    Entry::Folder
                } else if kind.is_file() && read_by_the_build(&relative) {
                    if relative.extension().is_some_and(|ext| ext == "rs") {
                        rust_files += 1;
                    }
                    if rust_files > MAX_RUST_FILES {
                        snapshot.incomplete = Some(format!(
                            "the workspace holds more than {MAX_RUST_FILES} Rust files"
                        ));
                        break;
                    }
                    let text = crate::input::read_bounded(
                        &entry.path(),
                        MAX_SOURCE_BYTES,
                        "source file",
                        crate::input::Links::Refuse,
                    )
                    .ok();
                    bytes += text.as_ref().map_or(0, |text| text.len() as u64);
                    if bytes > MAX_SNAPSHOT_BYTES {
                        snapshot.incomplete = Some(format!(
                            "the workspace's sources are more than {} MiB",
                            MAX_SNAPSHOT_BYTES >> 20
                        ));
                        break;
                    }
                    Entry::Source(text)
                } else {
                    Entry::Other
                };
                snapshot.entries.push((relative, found));
            }
        }
        snapshot.entries.sort_by(|a, b| a.0.cmp(&b.0));
        snapshot
    }

    /// The bytes of source `path` (relative to the workspace), if the
    /// snapshot read it.
    pub fn source(&self, path: &str) -> Option<&[u8]> {
        self.entries
            .iter()
            .find(|(relative, _)| relative == Path::new(path))
            .and_then(|(_, entry)| match entry {
                Entry::Source(Some(bytes)) => Some(bytes.as_slice()),
                _ => None,
            })
    }

    /// The Rust files under `src/` that are UTF-8, as (path, text), in the
    /// order of their paths: what the similarity report compares.
    pub fn src_texts(&self) -> Vec<(String, String)> {
        self.entries
            .iter()
            .filter(|(path, _)| path.starts_with("src"))
            .filter(|(path, _)| path.extension().is_some_and(|ext| ext == "rs"))
            .filter_map(|(path, entry)| match entry {
                Entry::Source(Some(bytes)) => Some((
                    path.to_str()?.to_string(),
                    String::from_utf8(bytes.clone()).ok()?,
                )),
                _ => None,
            })
            .collect()
    }

    /// The first difference between the sources of this snapshot and
    /// those of `workspace` now, in words (a source changed, added or
    /// removed), or `None`. Other files (a render the binary wrote) are no
    /// sources.
    pub fn changed(&self, workspace: &Path) -> Option<String> {
        let now = Snapshot::take(workspace);
        let sources = |snapshot: &Snapshot| -> Vec<(PathBuf, Option<Vec<u8>>)> {
            snapshot
                .entries
                .iter()
                .filter_map(|(path, entry)| match entry {
                    Entry::Source(bytes) => Some((path.clone(), bytes.clone())),
                    _ => None,
                })
                .collect()
        };
        let (before, after) = (sources(self), sources(&now));
        let shown = |path: &Path| crate::text::visible_name(path.as_os_str());
        for (path, bytes) in &before {
            match after.iter().find(|(other, _)| other == path) {
                None => return Some(format!("{} was removed", shown(path))),
                Some((_, other)) if other != bytes => {
                    return Some(format!("{} changed", shown(path)));
                }
                Some(_) => {}
            }
        }
        after
            .iter()
            .find(|(path, _)| !before.iter().any(|(other, _)| other == path))
            .map(|(path, _)| format!("{} was added", shown(path)))
    }
}

/// Whether the file at `relative` is code the build reads: a Rust file
/// anywhere, the manifest, cargo's configuration. (`Cargo.lock` is left
/// out: cargo itself rewrites it when it is missing or stale, and with
/// only raylab by path and libm from the registry, it pins nothing that
/// could be another crate's code.)
fn read_by_the_build(relative: &Path) -> bool {
    relative.extension().is_some_and(|ext| ext == "rs")
        || relative == Path::new("Cargo.toml")
        || relative.starts_with(".cargo")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A workspace of more entries than are graded is read no further
    /// (its snapshot, and so its run, is incomplete), whatever it holds.
    #[test]
    fn a_workspace_of_too_many_files_is_read_no_further() {
        let workspace = tempfile::tempdir().expect("a folder");
        std::fs::create_dir(workspace.path().join("junk")).expect("mkdir");
        for index in 0..30 {
            std::fs::write(workspace.path().join(format!("junk/{index}")), "").expect("write");
        }
        let whole = Snapshot::take_within(workspace.path(), 100);
        assert_eq!(whole.incomplete, None);
        let cut = Snapshot::take_within(workspace.path(), 20);
        assert!(
            cut.incomplete
                .as_deref()
                .is_some_and(|why| why.contains("more than 20 files")),
            "{:?}",
            cut.incomplete
        );
        assert_eq!(cut.entries.len(), 20);
    }

    #[test]
    fn a_change_to_the_sources_is_found_and_others_are_not() {
        let folder = tempfile::tempdir().expect("a folder");
        let root = folder.path();
        std::fs::create_dir_all(root.join("src/chapters")).expect("mkdir");
        std::fs::create_dir_all(root.join("target")).expect("mkdir");
        std::fs::write(root.join("Cargo.toml"), "[package]\n").expect("write");
        std::fs::write(root.join("src/chapters/a.rs"), "fn a() {}\n").expect("write");
        let before = Snapshot::take(root);
        assert_eq!(before.changed(root), None);
        assert_eq!(
            before.src_texts(),
            vec![("src/chapters/a.rs".to_string(), "fn a() {}\n".to_string())]
        );
        // The build's output and a render are not sources.
        std::fs::write(root.join("target/x.rs"), "fn x() {}").expect("write");
        std::fs::write(root.join("chapter-1.png"), "png").expect("write");
        assert_eq!(before.changed(root), None);
        std::fs::write(root.join("src/chapters/a.rs"), "fn b() {}\n").expect("write");
        assert_eq!(
            before.changed(root).as_deref(),
            Some("src/chapters/a.rs changed")
        );
        std::fs::write(root.join("src/chapters/a.rs"), "fn a() {}\n").expect("write");
        std::fs::write(root.join("src/more.rs"), "").expect("write");
        assert_eq!(
            before.changed(root).as_deref(),
            Some("src/more.rs was added")
        );
    }
}
