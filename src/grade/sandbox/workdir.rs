//! The folder of one run, outside the student's workspace: a copy of the
//! workspace (all but `target/` and `.git/`), which the build sees at the
//! workspace's own path and may write (cargo writes `Cargo.lock`), and
//! the build's temporary folder. The workspace's `target/` is shown over
//! the copy, so that a workspace built before builds again in seconds.
//!
//! When the grader is root, the run's processes are an unprivileged user
//! (see [`super::RunAs`]), who must own what the build writes: the copy,
//! the temporary folder and the workspace's `target/` are given to it
//! (`target/` is raylab's build output; the student's own files are never
//! changed, their copy is given instead).
//!
//! What a run writes is measured here too: the disk limit holds for the
//! run's writable folders together.

use std::path::{Path, PathBuf};

use super::SandboxError;

/// The most files (and folders) a workspace's copy may hold.
const MAX_ENTRIES: u64 = crate::grade::snapshot::MAX_ENTRIES as u64;

/// The least a file or folder counts for on disk: its inode and block.
const LEAST_ON_DISK: u64 = 4096;

/// How the name of a run's folder starts, before its grader's pid.
const RUN_PREFIX: &str = "raylab-run-";

/// Removes the run folders in `parent` of graders that are no longer
/// running (ended by a signal before they could remove them): only real
/// folders of this user, never a link someone else put there.
fn remove_abandoned(parent: &Path) {
    for entry in super::abandoned_entries(parent, RUN_PREFIX) {
        let Ok(meta) = std::fs::symlink_metadata(entry.path()) else {
            continue;
        };
        #[cfg(unix)]
        let ours = {
            use std::os::unix::fs::MetadataExt;
            // SAFETY: geteuid has no preconditions.
            meta.uid() == unsafe { libc::geteuid() }
        };
        #[cfg(not(unix))]
        let ours = true;
        if meta.is_dir() && ours {
            remove_tree(&entry.path());
        }
    }
}

/// A run's folder, removed when dropped.
#[derive(Debug)]
pub(super) struct RunFolder {
    folder: PathBuf,
    /// The copy of the workspace.
    pub(super) copy: PathBuf,
    /// The build's temporary folder (its `/tmp`).
    pub(super) tmp: PathBuf,
    /// The workspace's own `target/`.
    pub(super) target: PathBuf,
}

/// The error for `action` on `path`, for `map_err`.
fn failed(action: &'static str, path: &Path) -> impl FnOnce(std::io::Error) -> SandboxError {
    let path = path.to_path_buf();
    move |error| SandboxError::RunFolder {
        action,
        path,
        error,
    }
}

impl RunFolder {
    /// A new run folder for `workspace` (absolute, without links): its
    /// copy, of at most `budget` bytes, and its `target/` (made if
    /// missing, emptied first unless `keep_target`), both given to
    /// `owner` where there is one.
    pub(super) fn new(
        workspace: &Path,
        budget: u64,
        owner: Option<(u32, u32)>,
        keep_target: bool,
    ) -> Result<RunFolder, SandboxError> {
        let target = workspace.join("target");
        match std::fs::symlink_metadata(&target) {
            Ok(meta) if meta.is_dir() && keep_target => {}
            Ok(meta) if meta.is_dir() => {
                // Cargo takes a build output whose times are newer than
                // the sources for up to date, whoever made it: a binary
                // the student built from other sources would be run.
                remove_tree(&target);
                std::fs::create_dir(&target).map_err(failed("make", &target))?;
            }
            Ok(_) => return Err(SandboxError::TargetNotAFolder(target)),
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => {
                std::fs::create_dir(&target).map_err(failed("make", &target))?;
            }
            Err(error) => return Err(failed("read", &target)(error)),
        }
        remove_abandoned(&std::env::temp_dir());
        // The grader's pid in the name: a grader ended by a signal (its
        // handler can only unlink files) leaves its run's folder, a copy
        // of a student's workspace, which the next run removes.
        let folder = tempfile::Builder::new()
            .prefix(&format!("{RUN_PREFIX}{}-", std::process::id()))
            .tempdir()
            .map_err(failed("make", &std::env::temp_dir()))?
            .keep();
        let run = RunFolder {
            copy: folder.join("workspace"),
            tmp: folder.join("tmp"),
            folder,
            target,
        };
        std::fs::create_dir(&run.tmp).map_err(failed("make", &run.tmp))?;
        let mut counted = Counted::default();
        copy_tree(workspace, &run.copy, true, budget, &mut counted)?;
        // The folder the target is shown on.
        let mount_point = run.copy.join("target");
        std::fs::create_dir(&mount_point).map_err(failed("make", &mount_point))?;
        if let Some((uid, gid)) = owner {
            for tree in [&run.copy, &run.tmp, &run.target] {
                give(tree, uid, gid)?;
            }
        }
        Ok(run)
    }

    /// What the run's writable folders hold on disk, in bytes.
    pub(super) fn on_disk(&self) -> u64 {
        on_disk(&[&self.copy, &self.tmp, &self.target])
    }

    /// Removes the workspace's `target/`: after a run that went over its
    /// disk limit, what it wrote must not stay.
    pub(super) fn remove_target(&self) {
        remove_tree(&self.target);
    }
}

impl Drop for RunFolder {
    fn drop(&mut self) {
        remove_tree(&self.folder);
    }
}

/// What a copy holds so far.
#[derive(Default)]
struct Counted {
    bytes: u64,
    entries: u64,
}

/// Copies the folder `from` to `to` (which must not exist): folders,
/// files (with their permissions and times) and symbolic links (as
/// links), not sockets, FIFOs or devices; at the top, not `target/` nor
/// `.git/`. Refused past `budget` bytes or [`MAX_ENTRIES`] entries.
fn copy_tree(
    from: &Path,
    to: &Path,
    top: bool,
    budget: u64,
    counted: &mut Counted,
) -> Result<(), SandboxError> {
    std::fs::create_dir(to).map_err(failed("make", to))?;
    let entries = std::fs::read_dir(from).map_err(failed("read", from))?;
    for entry in entries {
        let entry = entry.map_err(failed("read", from))?;
        let name = entry.file_name();
        if top && (name == "target" || name == ".git") {
            continue;
        }
        let (source, dest) = (entry.path(), to.join(&name));
        let meta = std::fs::symlink_metadata(&source).map_err(failed("read", &source))?;
        counted.entries += 1;
        counted.bytes += meta.len();
        if counted.bytes > budget || counted.entries > MAX_ENTRIES {
            return Err(SandboxError::WorkspaceTooLarge {
                budget,
                entries: MAX_ENTRIES,
            });
        }
        let kind = meta.file_type();
        if kind.is_dir() {
            copy_tree(&source, &dest, false, budget, counted)?;
        } else if kind.is_file() {
            let room = budget.saturating_sub(counted.bytes - meta.len());
            if !copy_file(&source, &dest, room).map_err(failed("copy", &source))? {
                continue;
            }
            // Cargo takes a source newer than its last build for a change:
            // the copy keeps the times, so that an unchanged workspace is
            // not built again.
            if let Ok(modified) = meta.modified() {
                let file = std::fs::File::open(&dest).map_err(failed("open", &dest))?;
                file.set_modified(modified).map_err(failed("date", &dest))?;
            }
        } else if kind.is_symlink() {
            #[cfg(unix)]
            {
                let target = std::fs::read_link(&source).map_err(failed("read", &source))?;
                std::os::unix::fs::symlink(target, &dest).map_err(failed("link", &dest))?;
            }
        }
    }
    Ok(())
}

/// Copies the regular file `source` to `dest` (new), with its
/// permissions, at most `most` bytes of it: `false`, copying nothing, when
/// `source` is no longer a regular file. The entry was a file when its
/// folder was read, but a student who can write the hand-in while it is
/// graded could have put a link there since (to `/etc/shadow`, which root
/// would copy and give to the run's user) or a FIFO (whose open would
/// wait for ever): it is opened without following a link nor waiting,
/// and what was opened is what is checked.
fn copy_file(source: &Path, dest: &Path, most: u64) -> std::io::Result<bool> {
    use std::io::Read;
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK);
    }
    let mut file = match options.open(source) {
        Ok(file) => file,
        // A link now (ELOOP), or gone: not copied.
        Err(error) if is_a_link(&error) || error.kind() == std::io::ErrorKind::NotFound => {
            return Ok(false);
        }
        Err(error) => return Err(error),
    };
    let opened = file.metadata()?;
    if !opened.is_file() {
        return Ok(false);
    }
    let mut copy = std::fs::File::create_new(dest)?;
    std::io::copy(&mut (&mut file).take(most), &mut copy)?;
    copy.set_permissions(opened.permissions())?;
    Ok(true)
}

/// Whether opening failed because the path is a link (`O_NOFOLLOW`).
fn is_a_link(error: &std::io::Error) -> bool {
    #[cfg(unix)]
    return error.raw_os_error() == Some(libc::ELOOP);
    #[cfg(not(unix))]
    return {
        let _ = error;
        false
    };
}

/// Gives `tree` and all it holds to `uid`:`gid`, links themselves and
/// never what they point to (`lchown`), and never through a link.
fn give(tree: &Path, uid: u32, gid: u32) -> Result<(), SandboxError> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let mut stack = vec![tree.to_path_buf()];
        while let Some(path) = stack.pop() {
            let meta = std::fs::symlink_metadata(&path).map_err(failed("read", &path))?;
            if meta.uid() != uid || meta.gid() != gid {
                std::os::unix::fs::lchown(&path, Some(uid), Some(gid))
                    .map_err(failed("give to the sandbox's user", &path))?;
            }
            if meta.is_dir() {
                let entries = std::fs::read_dir(&path).map_err(failed("read", &path))?;
                for entry in entries {
                    stack.push(entry.map_err(failed("read", &path))?.path());
                }
            }
        }
    }
    #[cfg(not(unix))]
    let _ = (tree, uid, gid);
    Ok(())
}

/// A fingerprint of the tree `tree` as it is now: every entry's path,
/// kind, size, inode and times, the change time included, which no one
/// but the kernel sets (a file rewritten and dated back has a new one).
/// `None` when `tree` cannot be read.
pub(super) fn tree_state(tree: &Path) -> Option<u64> {
    state_of(tree, None, MOST_ENTRIES_WALKED)
}

/// [`tree_state`] of a workspace's sources: all of it but its `target/`;
/// `None` past the entries a workspace may hold.
pub(super) fn sources_state(workspace: &Path) -> Option<u64> {
    state_of(workspace, Some("target"), MAX_ENTRIES)
}

/// [`tree_state`], leaving out the top-level entry named `skipped`;
/// `None` past `most` entries.
fn state_of(tree: &Path, skipped: Option<&str>, most: u64) -> Option<u64> {
    use std::hash::{Hash, Hasher};
    #[cfg(unix)]
    use std::os::unix::fs::MetadataExt;
    let top = std::fs::symlink_metadata(tree).ok()?;
    if !top.is_dir() {
        return None;
    }
    let mut entries: Vec<(PathBuf, std::fs::Metadata)> = Vec::new();
    let mut stack = vec![tree.to_path_buf()];
    while let Some(folder) = stack.pop() {
        for entry in std::fs::read_dir(&folder).ok()? {
            let entry = entry.ok()?;
            if folder == tree && skipped.is_some_and(|name| entry.file_name() == name) {
                continue;
            }
            let meta = std::fs::symlink_metadata(entry.path()).ok()?;
            if meta.is_dir() {
                stack.push(entry.path());
            }
            let relative = entry.path().strip_prefix(tree).ok()?.to_path_buf();
            entries.push((relative, meta));
            if entries.len() as u64 > most {
                return None;
            }
        }
    }
    entries.sort_by(|a, b| a.0.cmp(&b.0));
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    for (path, meta) in &entries {
        path.hash(&mut hasher);
        meta.len().hash(&mut hasher);
        #[cfg(unix)]
        (
            meta.mode(),
            meta.ino(),
            meta.dev(),
            meta.mtime(),
            meta.mtime_nsec(),
            meta.ctime(),
            meta.ctime_nsec(),
        )
            .hash(&mut hasher);
        #[cfg(not(unix))]
        meta.modified().ok().hash(&mut hasher);
    }
    Some(hasher.finish())
}

/// The most entries a measure of a run's trees walks: a run that makes
/// more (a million hard links to one file take a few megabytes of disk)
/// counts as over every limit, so that the walk's memory and time stay
/// bounded. A workspace's build makes some thousands.
const MOST_ENTRIES_WALKED: u64 = 1_000_000;

/// What the trees `roots` hold on disk, in bytes: each file and folder
/// counted once (hard links too), at least [`LEAST_ON_DISK`] each, links
/// not followed. What cannot be read counts nothing, but for a path longer
/// than the system takes (folders nested past it hide what they hold from
/// any walk by path) and for more than [`MOST_ENTRIES_WALKED`] entries:
/// such trees count as more than any limit.
pub(super) fn on_disk(roots: &[&Path]) -> u64 {
    on_disk_within(roots, MOST_ENTRIES_WALKED)
}

fn on_disk_within(roots: &[&Path], most_entries: u64) -> u64 {
    // Only files with more than one name can be met twice: only theirs
    // are remembered, and only folders wait in the stack.
    let mut seen: std::collections::HashSet<(u64, u64)> = std::collections::HashSet::new();
    let mut total = 0u64;
    let mut entries = 0u64;
    let mut folders: Vec<PathBuf> = Vec::new();
    let too_long = |error: &std::io::Error| error.raw_os_error() == Some(libc::ENAMETOOLONG);
    let mut count = |meta: &std::fs::Metadata| -> u64 {
        #[cfg(unix)]
        let bytes = {
            use std::os::unix::fs::MetadataExt;
            if meta.nlink() > 1 && !meta.is_dir() && !seen.insert((meta.dev(), meta.ino())) {
                return 0;
            }
            meta.blocks().saturating_mul(512)
        };
        #[cfg(not(unix))]
        let bytes = {
            let _ = &mut seen;
            meta.len()
        };
        bytes.max(LEAST_ON_DISK)
    };
    for root in roots {
        match std::fs::symlink_metadata(root) {
            Ok(meta) => {
                total = total.saturating_add(count(&meta));
                if meta.is_dir() {
                    folders.push(root.to_path_buf());
                }
            }
            Err(error) if too_long(&error) => return u64::MAX,
            Err(_) => {}
        }
    }
    while let Some(folder) = folders.pop() {
        let listing = match std::fs::read_dir(&folder) {
            Ok(listing) => listing,
            Err(error) if too_long(&error) => return u64::MAX,
            Err(_) => continue,
        };
        for entry in listing.flatten() {
            entries += 1;
            if entries > most_entries {
                return u64::MAX;
            }
            // The entry itself: a link is not followed.
            let meta = match entry.metadata() {
                Ok(meta) => meta,
                Err(error) if too_long(&error) => return u64::MAX,
                Err(_) => continue,
            };
            total = total.saturating_add(count(&meta));
            if meta.is_dir() {
                folders.push(entry.path());
            }
        }
    }
    total
}

/// Removes `tree`, first making each of its folders writable by its owner
/// (a build may leave one read-only, which would keep its files).
fn remove_tree(tree: &Path) {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mut stack = vec![tree.to_path_buf()];
        while let Some(path) = stack.pop() {
            let Ok(meta) = std::fs::symlink_metadata(&path) else {
                continue;
            };
            if meta.is_dir() {
                let mode = meta.permissions().mode();
                if mode & 0o700 != 0o700 {
                    let _ = std::fs::set_permissions(
                        &path,
                        std::fs::Permissions::from_mode(mode | 0o700),
                    );
                }
                for entry in std::fs::read_dir(&path).into_iter().flatten().flatten() {
                    stack.push(entry.path());
                }
            }
        }
    }
    let _ = std::fs::remove_dir_all(tree);
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    /// An entry that became a link or a FIFO after its folder was read is
    /// not followed nor waited on; a file is copied, capped.
    #[cfg(unix)]
    #[test]
    fn a_file_swapped_for_a_link_or_a_fifo_is_not_copied() {
        let folder = tempfile::tempdir().expect("temp dir");
        let (file, link, fifo) = (
            folder.path().join("file"),
            folder.path().join("link"),
            folder.path().join("fifo"),
        );
        std::fs::write(&file, "0123456789").expect("write");
        std::os::unix::fs::symlink(&file, &link).expect("link");
        let status = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .expect("mkfifo");
        assert!(status.success());
        let dest = |name: &str| folder.path().join(format!("copy-of-{name}"));
        assert!(!copy_file(&link, &dest("link"), 100).expect("no error"));
        assert!(!dest("link").exists());
        assert!(!copy_file(&fifo, &dest("fifo"), 100).expect("no error"));
        assert!(!dest("fifo").exists());
        assert!(copy_file(&file, &dest("file"), 4).expect("copied"));
        assert_eq!(std::fs::read(dest("file")).expect("read"), b"0123");
    }

    /// Folders nested past the longest path the system takes, made one
    /// inside the other by file descriptor, as a build script can: a walk
    /// by path cannot see what they hold, so the tree counts as over any
    /// disk limit rather than as nearly empty.
    /// Hard links count once, and past the most entries a walk takes
    /// the tree counts as over every limit (4 million links to one file
    /// held 664 MB of paths in the grader's walk).
    #[test]
    fn many_names_for_one_file_count_once_and_too_many_count_as_over() {
        let root = tempfile::tempdir().expect("a folder");
        std::fs::write(root.path().join("file"), vec![1u8; 1 << 20]).expect("write");
        let one = on_disk_within(&[root.path()], 100);
        for link in 0..50 {
            std::fs::hard_link(
                root.path().join("file"),
                root.path().join(format!("link-{link}")),
            )
            .expect("link");
        }
        let linked = on_disk_within(&[root.path()], 100);
        assert!(linked < one + (64 << 10), "{one} then {linked}");
        assert_eq!(on_disk_within(&[root.path()], 50), u64::MAX);
    }

    #[test]
    fn a_tree_deeper_than_the_longest_path_counts_as_over_every_limit() {
        use std::ffi::CString;
        let root = tempfile::tempdir().expect("a folder");
        let plain = on_disk(&[root.path()]);
        assert!(plain < 1 << 20, "{plain}");
        let name = CString::new("d".repeat(250)).expect("no NUL");
        let start = CString::new(root.path().as_os_str().as_encoded_bytes()).expect("no NUL");
        // SAFETY: plain system calls on descriptors this test opened and
        // closes, with NUL-terminated names.
        unsafe {
            let mut folder = libc::open(start.as_ptr(), libc::O_RDONLY | libc::O_DIRECTORY);
            assert!(folder >= 0);
            for _ in 0..20 {
                assert_eq!(libc::mkdirat(folder, name.as_ptr(), 0o755), 0);
                let inner = libc::openat(folder, name.as_ptr(), libc::O_RDONLY | libc::O_DIRECTORY);
                libc::close(folder);
                assert!(inner >= 0);
                folder = inner;
            }
            libc::close(folder);
        }
        assert_eq!(on_disk(&[root.path()]), u64::MAX);
        // The removal works by descriptor, whatever the depth.
        remove_tree(root.path());
        assert!(!root.path().exists());
    }

    /// The state of a tree is the same while nothing changes, and not
    /// once a file is rewritten, even to its old size and dated back.
    #[test]
    fn a_tree_rewritten_and_dated_back_is_told_apart() {
        let folder = tempfile::tempdir().expect("a folder");
        let target = folder.path().join("target");
        std::fs::create_dir_all(target.join("debug")).expect("mkdir");
        let binary = target.join("debug/ann");
        std::fs::write(&binary, "built from ann's sources.").expect("write");
        let state = tree_state(&target);
        assert!(state.is_some());
        assert_eq!(tree_state(&target), state);
        let dated = std::fs::metadata(&binary)
            .and_then(|meta| meta.modified())
            .expect("a time");
        // A second passes, so that the change time differs on any file
        // system's clock.
        std::thread::sleep(std::time::Duration::from_millis(1100));
        std::fs::write(&binary, "built from the answer key").expect("write");
        std::fs::File::options()
            .write(true)
            .open(&binary)
            .and_then(|file| file.set_modified(dated))
            .expect("date");
        assert_ne!(tree_state(&target), state);
        assert_eq!(tree_state(&folder.path().join("none")), None);
    }

    /// A run folder that a grader ended by a signal left (its pid is of
    /// no process) is removed when the next run starts; a link of that
    /// name is not followed, and a live grader's folder stays.
    #[test]
    fn run_folders_of_graders_ended_by_a_signal_are_removed() {
        let temp = std::env::temp_dir();
        // No process has a pid above the kernel's pid_max (at most 2^22).
        let abandoned = temp.join(format!("{RUN_PREFIX}4294967295-adv3"));
        let link = temp.join(format!("{RUN_PREFIX}4294967294-adv3"));
        let live = temp.join(format!("{RUN_PREFIX}1-adv3"));
        let kept = tempfile::tempdir().expect("a folder");
        std::fs::write(kept.path().join("file"), "kept").expect("write");
        for folder in [&abandoned, &live] {
            std::fs::create_dir_all(folder.join("workspace/src")).expect("mkdir");
            std::fs::write(folder.join("workspace/src/lib.rs"), "pub struct Ann;").expect("write");
        }
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink(kept.path(), &link).expect("ln");
        let folder = tempfile::tempdir().expect("a folder");
        let workspace = folder.path().join("ann");
        std::fs::create_dir_all(workspace.join("src")).expect("mkdir");
        let run = RunFolder::new(&workspace, 1 << 20, None, false).expect("a run folder");
        assert!(!abandoned.exists());
        assert!(live.join("workspace/src/lib.rs").exists());
        assert!(kept.path().join("file").exists());
        drop(run);
        let _ = std::fs::remove_file(&link);
        remove_tree(&live);
    }

    /// The copy holds the workspace but `target/` and `.git/`, with its
    /// times and links (not followed); the run folder goes when dropped,
    /// a read-only folder the build left included; a workspace over the
    /// budget is refused; what is on disk counts hard links once.
    #[test]
    fn a_run_folder_copies_the_workspace_and_goes_when_dropped() {
        let folder = tempfile::tempdir().expect("a folder");
        let workspace = folder.path().join("ann");
        for path in ["src", "target/debug", ".git"] {
            std::fs::create_dir_all(workspace.join(path)).expect("mkdir");
        }
        std::fs::write(workspace.join("src/lib.rs"), "pub struct Mine;\n").expect("write");
        std::fs::write(workspace.join("target/debug/big"), vec![0u8; 1 << 16]).expect("write");
        std::fs::write(workspace.join(".git/HEAD"), "ref").expect("write");
        std::os::unix::fs::symlink("/etc/hostname", workspace.join("src/link.rs")).expect("ln");
        let old = std::time::SystemTime::UNIX_EPOCH + std::time::Duration::from_secs(1 << 30);
        std::fs::File::open(workspace.join("src/lib.rs"))
            .and_then(|file| file.set_modified(old))
            .expect("date");
        let run = RunFolder::new(&workspace, 1 << 20, None, true).expect("a run folder");
        let copied = run.copy.join("src/lib.rs");
        assert_eq!(
            std::fs::read_to_string(&copied).expect("read"),
            "pub struct Mine;\n"
        );
        assert_eq!(
            std::fs::metadata(&copied)
                .and_then(|meta| meta.modified())
                .expect("time"),
            old
        );
        assert_eq!(
            std::fs::read_link(run.copy.join("src/link.rs")).expect("a link"),
            Path::new("/etc/hostname")
        );
        assert!(!run.copy.join(".git").exists());
        assert_eq!(
            std::fs::read_dir(run.copy.join("target"))
                .expect("read")
                .count(),
            0
        );
        assert_eq!(run.target, workspace.join("target"));
        let before = run.on_disk();
        std::fs::hard_link(
            workspace.join("target/debug/big"),
            workspace.join("target/debug/same"),
        )
        .expect("link");
        assert_eq!(run.on_disk(), before, "a hard link counts once");
        let stuck = run.tmp.join("stuck");
        std::fs::create_dir(&stuck).expect("mkdir");
        std::fs::write(stuck.join("file"), "x").expect("write");
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&stuck, std::fs::Permissions::from_mode(0o500)).expect("chmod");
        let top = run.folder.clone();
        drop(run);
        assert!(!top.exists());
        assert!(workspace.join("target/debug/big").exists());
        std::fs::write(workspace.join("src/big.rs"), vec![b' '; 2 << 20]).expect("write");
        assert!(matches!(
            RunFolder::new(&workspace, 1 << 20, None, true),
            Err(SandboxError::WorkspaceTooLarge { .. })
        ));
    }
}
