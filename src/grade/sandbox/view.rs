//! What a sandboxed process sees of the file system: a list of mounts
//! that bubblewrap makes in order on an empty root.
//!
//! Nothing is shown by default. The system's programs and libraries
//! (`/usr` and the folders merged into it), the few files of `/etc` a
//! compiler and a linker read, the Rust toolchain, cargo's cache of
//! crates, raylab's own checkout (the workspace's path dependency, but not
//! its `target/`, where the grader's binary is, nor its `.git/`) and the workspace: that is
//! all. Any of those that would show something the student must not see
//! (the grader's binary, the instructor's hidden scenes or reports, the
//! other workspaces of the class, cargo's credentials) has it covered by
//! an empty file or folder.

use std::ffi::OsString;
use std::path::{Component, Path, PathBuf};

/// The folders of the system's programs and libraries, as they are on the
/// host (a link into `/usr` where `/usr` is merged).
const SYSTEM: [&str; 7] = [
    "/usr", "/bin", "/sbin", "/lib", "/lib32", "/lib64", "/libx32",
];

/// What of `/etc` a build reads: the dynamic loader's cache and settings,
/// `cc`'s alternatives (Debian's `/usr/bin/cc` is a link through
/// `/etc/alternatives`), and the names of users and groups. Not
/// `/etc/shadow`, `/etc/ssh`, `/etc/sudoers` or anything else.
const ETC: [&str; 8] = [
    "/etc/ld.so.cache",
    "/etc/ld.so.conf",
    "/etc/ld.so.conf.d",
    "/etc/alternatives",
    "/etc/passwd",
    "/etc/group",
    "/etc/nsswitch.conf",
    "/etc/localtime",
];

/// One mount, or one thing made on the sandbox's root.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Mount {
    /// `source` shown at `dest`, read-only unless `writable`.
    Bind {
        source: PathBuf,
        dest: PathBuf,
        writable: bool,
    },
    /// An empty folder in memory, of `size` bytes at most, with
    /// permissions `mode`.
    Tmpfs {
        dest: PathBuf,
        size: Option<u64>,
        mode: Option<u32>,
    },
    /// The file at `dest` shown empty (`/dev/null` over it).
    Blank {
        dest: PathBuf,
    },
    Symlink {
        target: PathBuf,
        dest: PathBuf,
    },
    Dir {
        dest: PathBuf,
    },
    /// The processes of the sandbox's own pid namespace.
    Proc {
        dest: PathBuf,
    },
    /// A minimal `/dev`: null, zero, full, random, urandom, tty.
    Dev {
        dest: PathBuf,
    },
}

impl Mount {
    fn dest(&self) -> &Path {
        match self {
            Mount::Bind { dest, .. }
            | Mount::Tmpfs { dest, .. }
            | Mount::Blank { dest }
            | Mount::Symlink { dest, .. }
            | Mount::Dir { dest }
            | Mount::Proc { dest }
            | Mount::Dev { dest } => dest,
        }
    }

    fn ro(source: &Path, dest: &Path) -> Mount {
        Mount::Bind {
            source: source.to_path_buf(),
            dest: dest.to_path_buf(),
            writable: false,
        }
    }
}

/// The mounts of one sandbox.
#[derive(Debug, Clone, Default)]
pub(super) struct View {
    mounts: Vec<Mount>,
}

impl View {
    /// The system's programs and libraries, and the few files of `/etc` a
    /// build needs, with a `/dev` of its own.
    pub(super) fn system() -> View {
        let mut view = View::default();
        for folder in SYSTEM.map(Path::new) {
            match std::fs::symlink_metadata(folder) {
                Ok(meta) if meta.file_type().is_symlink() => {
                    if let Ok(target) = std::fs::read_link(folder) {
                        view.push(Mount::Symlink {
                            target,
                            dest: folder.to_path_buf(),
                        });
                    }
                }
                Ok(meta) if meta.is_dir() => view.push(Mount::ro(folder, folder)),
                _ => {}
            }
        }
        view.push(Mount::Dir {
            dest: "/etc".into(),
        });
        for file in ETC.map(Path::new) {
            if file.exists() {
                view.push(Mount::ro(file, file));
            }
        }
        view.push(Mount::Dev {
            dest: "/dev".into(),
        });
        view
    }

    pub(super) fn push(&mut self, mount: Mount) {
        self.mounts.push(mount);
    }

    /// `source` shown read-only at the same path, where it exists.
    pub(super) fn show(&mut self, source: &Path) {
        if source.exists() {
            self.push(Mount::ro(source, source));
        }
    }

    /// What shows at `path` (absolute, without links) in the view: the
    /// host's file or folder that the deepest mount at or above it shows
    /// there, if it is a bind mount and that file exists.
    pub(super) fn shows(&self, path: &Path) -> Option<PathBuf> {
        let mount = self
            .mounts
            .iter()
            .filter(|mount| path.starts_with(mount.dest()))
            .max_by_key(|mount| depth(mount.dest()))?;
        let Mount::Bind { source, dest, .. } = mount else {
            return None;
        };
        let shown = source.join(path.strip_prefix(dest).ok()?);
        shown.symlink_metadata().is_ok().then_some(shown)
    }

    /// Covers `path` (absolute, without links) where it shows: a folder by
    /// an empty one, a file by an empty file. Never a mount's own folder,
    /// which the sandbox needs; a folder above mounts is covered, and the
    /// mounts inside it still show (they come after it, see
    /// [`View::options`]).
    pub(super) fn hide(&mut self, path: &Path) {
        let needed = self.mounts.iter().any(|mount| mount.dest() == path);
        let Some(shown) = self.shows(path).filter(|_| !needed) else {
            return;
        };
        match std::fs::metadata(shown) {
            Ok(meta) if meta.is_dir() => self.push(Mount::Tmpfs {
                dest: path.to_path_buf(),
                size: Some(0),
                mode: Some(0o755),
            }),
            Ok(_) => self.push(Mount::Blank {
                dest: path.to_path_buf(),
            }),
            Err(_) => {}
        }
    }

    /// Whether `path`, not a mount's own folder, is there before the
    /// mounts below it are made: inside a bind mount whose source has it.
    /// bubblewrap makes the others itself, but as private as the host's
    /// folder of the same name (`/root` is `0700`), which would keep the
    /// sandbox's user from what is mounted inside: they are made first,
    /// open to all (see [`View::options`]).
    fn is_there(&self, path: &Path) -> bool {
        self.mounts
            .iter()
            .filter(|mount| path.starts_with(mount.dest()) && path != mount.dest())
            .max_by_key(|mount| depth(mount.dest()))
            .is_some_and(|mount| match mount {
                Mount::Bind { source, dest, .. } => path
                    .strip_prefix(dest)
                    .is_ok_and(|rest| source.join(rest).exists()),
                _ => false,
            })
    }

    /// bubblewrap's options making the view: the mounts ordered so that
    /// each comes after those above it (a folder mounted later would hide
    /// what was mounted inside it), keeping their order otherwise, and
    /// the folders on the way to each made first.
    pub(super) fn options(&self) -> Vec<OsString> {
        let mut mounts = self.mounts.clone();
        for mount in &self.mounts {
            for folder in mount.dest().ancestors().skip(1) {
                let made = mounts.iter().any(|made| made.dest() == folder);
                if depth(folder) > 0 && !made && !self.is_there(folder) {
                    mounts.push(Mount::Dir {
                        dest: folder.to_path_buf(),
                    });
                }
            }
        }
        mounts.sort_by_key(|mount| depth(mount.dest()));
        let mut options: Vec<OsString> = Vec::new();
        let mut add = |words: &[&std::ffi::OsStr]| {
            options.extend(words.iter().map(|word| word.to_os_string()));
        };
        for mount in &mounts {
            match mount {
                Mount::Bind {
                    source,
                    dest,
                    writable,
                } => {
                    let option = if *writable { "--bind" } else { "--ro-bind" };
                    add(&[option.as_ref(), source.as_os_str(), dest.as_os_str()]);
                }
                Mount::Tmpfs { dest, size, mode } => {
                    if let Some(mode) = mode {
                        add(&["--perms".as_ref(), format!("{mode:o}").as_ref()]);
                    }
                    if let Some(size) = size {
                        // bubblewrap takes no size of 0 as no limit; a
                        // folder that only hides needs a page at most.
                        let size = (*size).max(4096);
                        add(&["--size".as_ref(), size.to_string().as_ref()]);
                    }
                    add(&["--tmpfs".as_ref(), dest.as_os_str()]);
                }
                Mount::Blank { dest } => {
                    add(&["--ro-bind".as_ref(), "/dev/null".as_ref(), dest.as_os_str()]);
                }
                Mount::Symlink { target, dest } => {
                    add(&["--symlink".as_ref(), target.as_os_str(), dest.as_os_str()]);
                }
                Mount::Dir { dest } => {
                    add(&[
                        "--perms".as_ref(),
                        "755".as_ref(),
                        "--dir".as_ref(),
                        dest.as_os_str(),
                    ]);
                }
                Mount::Proc { dest } => add(&["--proc".as_ref(), dest.as_os_str()]),
                Mount::Dev { dest } => add(&["--dev".as_ref(), dest.as_os_str()]),
            }
        }
        options
    }
}

/// How many folders deep `path` is.
fn depth(path: &Path) -> usize {
    path.components()
        .filter(|part| matches!(part, Component::Normal(_)))
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Mounts come out parents first; what shows is what the deepest
    /// mount above a path shows; a hidden path is covered only where it
    /// shows and never where it would hide what the sandbox needs.
    #[test]
    fn mounts_are_ordered_and_hidden_paths_covered_where_they_show() {
        let folder = tempfile::tempdir().expect("a folder");
        let root = folder.path();
        let checkout = root.join("raylab");
        let class = checkout.join("class");
        let workspace = class.join("ann");
        let secret = checkout.join("scene.toml");
        std::fs::create_dir_all(&workspace).expect("mkdir");
        std::fs::write(&secret, "").expect("write");
        let mut view = View::default();
        view.push(Mount::Bind {
            source: root.join("copy"),
            dest: workspace.clone(),
            writable: true,
        });
        view.show(&checkout);
        view.push(Mount::Tmpfs {
            dest: "/run".into(),
            size: None,
            mode: None,
        });
        std::fs::create_dir(class.join("bob")).expect("mkdir");
        assert_eq!(view.shows(&secret), Some(secret.clone()));
        assert!(view.shows(&class.join("bob")).is_some());
        // The copy has no such file: nothing shows there.
        assert_eq!(view.shows(&workspace.join("src")), None);
        assert_eq!(view.shows(Path::new("/run/user")), None);
        assert_eq!(view.shows(Path::new("/root")), None);
        view.hide(&secret);
        view.hide(&class);
        // Mounts' own folders, and what does not show: left as they are.
        view.hide(&checkout);
        view.hide(&workspace);
        view.hide(Path::new("/root"));
        std::fs::create_dir_all(root.join("copy/src")).expect("mkdir");
        std::fs::create_dir(checkout.join("src")).expect("mkdir");
        assert_eq!(view.shows(&secret), None);
        assert_eq!(view.shows(&class.join("bob")), None);
        assert_eq!(
            view.shows(&workspace.join("src")),
            Some(root.join("copy/src"))
        );
        assert_eq!(
            view.shows(&checkout.join("src")),
            Some(checkout.join("src"))
        );
        let text: Vec<String> = view
            .options()
            .iter()
            .map(|word| word.to_string_lossy().into_owned())
            .collect();
        let at = |word: &Path| {
            text.iter()
                .position(|option| option == &word.display().to_string())
                .unwrap_or_else(|| panic!("{} not in {text:?}", word.display()))
        };
        assert!(at(Path::new("/run")) < at(&checkout));
        assert!(at(&checkout) < at(&class));
        assert!(at(&class) < at(&workspace));
        assert_eq!(
            text.iter().filter(|word| *word == "--tmpfs").count(),
            2,
            "{text:?}"
        );
        assert_eq!(
            text.iter().filter(|word| *word == "/dev/null").count(),
            1,
            "{text:?}"
        );
    }
}
