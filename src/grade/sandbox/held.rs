//! The disk a run's processes hold in files they deleted but keep open.
//!
//! A file removed while a process has it open (or mapped) leaves its
//! folder but not the disk: its blocks stay taken until the last process
//! lets go. A walk of the run's folder ([`super::workdir`]) cannot see it,
//! so the run's processes are asked instead: each entry of
//! `/proc/PID/fd` and `/proc/PID/map_files` that names a deleted file is
//! measured through that entry (which reaches the file itself), each file
//! once. A file can also be held where `/proc` does not show it (a
//! message in flight on a Unix socket): what the run's processes have
//! written ([`written`]) counts those too.

use std::collections::{BTreeMap, BTreeSet};
use std::os::unix::fs::MetadataExt;
use std::path::Path;

/// The processes of the run: those of its cgroups where it has any (every
/// process it starts joins them), else `root` and its descendants.
pub fn processes(cgroups: &[&Path], root: Option<u32>) -> Vec<u32> {
    let mut pids: BTreeSet<u32> = cgroups
        .iter()
        .filter_map(|folder| std::fs::read_to_string(folder.join("cgroup.procs")).ok())
        .flat_map(|text| {
            text.lines()
                .filter_map(|line| line.trim().parse().ok())
                .collect::<Vec<u32>>()
        })
        .collect();
    if pids.is_empty() {
        if let Some(root) = root {
            pids = descendants(root);
        }
    }
    pids.into_iter().collect()
}

/// `root` and every process below it, from each process's parent in
/// `/proc/PID/stat`. (A process that leaves the tree by a double fork is
/// adopted by the run's own first process, bubblewrap's, inside its pid
/// namespace: still below `root`.)
fn descendants(root: u32) -> BTreeSet<u32> {
    let mut parents: Vec<(u32, u32)> = Vec::new();
    if let Ok(entries) = std::fs::read_dir("/proc") {
        for entry in entries.flatten() {
            let Some(pid) = entry
                .file_name()
                .to_str()
                .and_then(|name| name.parse().ok())
            else {
                continue;
            };
            let Ok(stat) = std::fs::read_to_string(entry.path().join("stat")) else {
                continue;
            };
            // The name in brackets may hold spaces and brackets: the
            // fields after the last ')' are the state, then the parent.
            let parent = stat
                .rsplit_once(')')
                .and_then(|(_, rest)| rest.split_whitespace().nth(1))
                .and_then(|field| field.parse().ok());
            if let Some(parent) = parent {
                parents.push((pid, parent));
            }
        }
    }
    let mut found = BTreeSet::from([root]);
    loop {
        let before = found.len();
        for (pid, parent) in &parents {
            if found.contains(parent) {
                found.insert(*pid);
            }
        }
        if found.len() == before {
            return found;
        }
    }
}

/// The most open files and mappings one measure of a run looks at: a
/// build holds some hundreds; a run that holds more (a deleted file's
/// descriptor copied 20,000 times into each of 400 processes made each
/// measure take minutes, the time limit waiting behind it) counts as over
/// every limit.
const MOST_HANDLES: usize = 100_000;

/// The bytes on disk of the deleted files `pids` hold open or mapped,
/// each file counted once; `u64::MAX` past [`MOST_HANDLES`].
pub fn deleted_but_held(pids: &[u32]) -> u64 {
    match held_files(pids, MOST_HANDLES) {
        Some(held) => held
            .values()
            .fold(0u64, |total, bytes| total.saturating_add(*bytes)),
        None => u64::MAX,
    }
}

/// The deleted files `pids` hold, by device and inode, with their bytes
/// on disk; `None` past `most` handles.
fn held_files(pids: &[u32], most: usize) -> Option<BTreeMap<(u64, u64), u64>> {
    let mut held = BTreeMap::new();
    let mut handles = 0;
    for pid in pids {
        for table in ["fd", "map_files"] {
            let folder = Path::new("/proc").join(pid.to_string()).join(table);
            let Ok(entries) = std::fs::read_dir(&folder) else {
                continue;
            };
            for entry in entries.flatten() {
                handles += 1;
                if handles > most {
                    return None;
                }
                let path = entry.path();
                let deleted = std::fs::read_link(&path)
                    .is_ok_and(|target| target.to_string_lossy().ends_with(" (deleted)"));
                if !deleted {
                    continue;
                }
                let Ok(file) = std::fs::metadata(&path) else {
                    continue;
                };
                if file.is_file() {
                    held.insert((file.dev(), file.ino()), file.blocks().saturating_mul(512));
                }
            }
        }
    }
    Some(held)
}

/// The bytes `pids` have written to the storage of files, each process
/// with the processes it has waited for (`write_bytes` of
/// `/proc/PID/io`, counted as pages are first dirtied).
///
/// Every file the run fills is in it, wherever the file ends up: in the
/// run's folder, deleted but open, or deleted and held by no process at
/// all but by a message in flight on a Unix socket (`SCM_RIGHTS`), whose
/// blocks stay taken while the socket lives and which `/proc` does not
/// show. Pages written again after they reached the disk count again, and
/// a file deleted before it reached the disk still counts
/// (`cancelled_write_bytes` is not taken off: a run could earn that credit
/// by deleting its copy of the workspace, which it did not write).
pub fn written(pids: &[u32]) -> u64 {
    pids.iter()
        .filter_map(|pid| std::fs::read_to_string(format!("/proc/{pid}/io")).ok())
        .filter_map(|io| {
            io.lines()
                .find_map(|line| line.strip_prefix("write_bytes:"))
                .and_then(|bytes| bytes.trim().parse::<u64>().ok())
        })
        .fold(0u64, u64::saturating_add)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    /// A file this process deleted but keeps open is counted, once, by
    /// its blocks on disk; once closed it is not.
    #[test]
    fn a_deleted_file_kept_open_still_counts() {
        let folder = tempfile::tempdir().expect("temp dir");
        let path = folder.path().join("big");
        let mut file = std::fs::File::create(&path).expect("create");
        file.write_all(&vec![7u8; 4 << 20]).expect("write");
        file.sync_all().expect("sync");
        let again = std::fs::File::open(&path).expect("open again");
        let id = {
            let meta = file.metadata().expect("stat");
            (meta.dev(), meta.ino())
        };
        let me = std::process::id();
        let held = |most| held_files(&[me], most);
        assert!(
            !held(1000).expect("few").contains_key(&id),
            "not deleted yet"
        );
        std::fs::remove_file(&path).expect("remove");
        // Open twice, listed once.
        let bytes = held(1000).expect("few").get(&id).copied();
        assert!(bytes.is_some_and(|bytes| bytes >= 4 << 20), "{bytes:?}");
        assert!(deleted_but_held(&[me]) >= 4 << 20);
        // Past the most handles looked at, nothing is measured.
        assert_eq!(held(1), None);
        drop((file, again));
        assert!(!held(1000).expect("few").contains_key(&id), "closed");
    }

    /// What a child wrote counts for the process that waited for it: a
    /// file it keeps, and one it deleted before the disk saw it.
    #[test]
    fn what_a_child_wrote_counts_whether_kept_or_deleted() {
        // Not in /tmp, which may be a tmpfs: memory, with no storage to
        // write to and nothing counted.
        let folder = tempfile::tempdir_in(env!("CARGO_MANIFEST_DIR")).expect("temp dir");
        let me = std::process::id();
        let before = written(&[me]);
        let script = "dd if=/dev/zero of=kept bs=1M count=8 conv=fsync status=none \
                      && dd if=/dev/zero of=gone bs=1M count=8 status=none && rm gone";
        let status = std::process::Command::new("sh")
            .args(["-c", script])
            .current_dir(folder.path())
            .status()
            .expect("sh runs");
        assert!(status.success());
        let after = written(&[me]);
        assert!(after >= before + (16 << 20), "{before} then {after}");
    }

    #[test]
    fn a_process_is_among_the_descendants_of_its_parent() {
        let mut child = std::process::Command::new("sleep")
            .arg("30")
            .spawn()
            .expect("sleep");
        let found = processes(&[], Some(std::process::id()));
        let _ = child.kill();
        let _ = child.wait();
        assert!(found.contains(&child.id()), "{found:?}");
        assert!(found.contains(&std::process::id()));
    }
}
