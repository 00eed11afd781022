//! The cgroups of one run: every process of a student's run (the build,
//! then all the answering processes, which the judge starts at once, one
//! a chapter) joins them, so that their limits hold for the run as a
//! whole, where a resource limit holds for each process alone.
//!
//! `pids.max` caps the processes (and threads) of the run, for root too
//! (the kernel does not apply `RLIMIT_NPROC` to root); `memory.max` (v2)
//! or `memory.limit_in_bytes` (v1) caps the memory of all of them
//! together, the kernel killing one of them when they reach it.
//! raylab may make them as root (cgroup v1's hierarchies, or v2 where its
//! cgroup delegates the controller) or in a cgroup delegated to its user;
//! elsewhere none is made and the resource limits alone hold (see
//! [`super::Limits`]). The student's code cannot raise them: no part of
//! `/sys` is in the sandbox.

use std::path::{Path, PathBuf};

use super::Limits;

/// The prefix of the cgroups raylab makes, followed by the grader's pid
/// and a counter.
pub(super) const PREFIX: &str = "raylab-grade-";

/// Where cgroups are mounted.
const ROOT: &str = "/sys/fs/cgroup";

/// One cgroup of the run, and the file a process joins it by.
#[derive(Debug)]
struct Group {
    folder: PathBuf,
    // Written only where there are processes to move (Unix).
    #[cfg_attr(not(unix), allow(dead_code))]
    procs: std::fs::File,
    /// Its `pids.max` caps the run's processes.
    pids: bool,
    /// Its memory limit caps the run's memory: cgroup v1's files, or v2's.
    memory: Option<Version>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Version {
    V1,
    V2,
}

/// The cgroups a run's processes join: none, one (v2, or v1's `pids`
/// alone) or two (v1's `pids` and `memory`). Removed when dropped; those
/// left by a grader that was killed are removed by the next one (their
/// name holds the grader's pid).
#[derive(Debug, Default)]
pub struct RunCgroups {
    groups: Vec<Group>,
}

impl RunCgroups {
    /// New cgroups capping processes and memory at `limits`, under this
    /// process's own cgroups, where they can be made.
    pub(super) fn create(limits: &Limits) -> RunCgroups {
        static COUNT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        let number = COUNT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let name = format!("{PREFIX}{}-{number}", std::process::id());
        let mut groups = Vec::new();
        for (parent, pids, memory) in parents() {
            remove_abandoned(&parent);
            if let Some(group) = make(&parent.join(&name), pids, memory, limits) {
                groups.push(group);
            }
        }
        RunCgroups { groups }
    }

    /// The files that move a process into the run's cgroups.
    #[cfg(unix)]
    pub(super) fn joins(&self) -> Vec<std::os::fd::RawFd> {
        use std::os::fd::AsRawFd;
        self.groups
            .iter()
            .map(|group| group.procs.as_raw_fd())
            .collect()
    }

    /// Whether a cgroup caps the run's processes.
    pub fn caps_processes(&self) -> bool {
        self.groups.iter().any(|group| group.pids)
    }

    /// Whether a cgroup caps the run's memory.
    pub fn caps_memory(&self) -> bool {
        self.groups.iter().any(|group| group.memory.is_some())
    }

    /// The cgroups' folders.
    pub fn folders(&self) -> Vec<&Path> {
        self.groups
            .iter()
            .map(|group| group.folder.as_path())
            .collect()
    }

    /// Whether the kernel killed a process of the run for its memory.
    pub(super) fn memory_ran_out(&self) -> bool {
        self.groups.iter().any(|group| match group.memory {
            Some(Version::V2) => counter(&group.folder.join("memory.events"), "oom_kill") > 0,
            Some(Version::V1) => {
                let control = group.folder.join("memory.oom_control");
                let text = std::fs::read_to_string(&control).unwrap_or_default();
                if text.lines().any(|line| line.starts_with("oom_kill ")) {
                    counter(&control, "oom_kill") > 0
                } else {
                    // Kernels before 4.13 do not count kills: that the
                    // limit was reached is what they tell.
                    std::fs::read_to_string(group.folder.join("memory.failcnt"))
                        .ok()
                        .and_then(|count| count.trim().parse::<u64>().ok())
                        .is_some_and(|count| count > 0)
                }
            }
            None => false,
        })
    }

    /// Whether a process of the run could not start for the cap.
    pub(super) fn processes_refused(&self) -> bool {
        self.groups
            .iter()
            .any(|group| group.pids && counter(&group.folder.join("pids.events"), "max") > 0)
    }
}

impl Drop for RunCgroups {
    fn drop(&mut self) {
        for group in &self.groups {
            // The kernel frees the cgroup's last processes just after they
            // are reaped; until then the folder cannot be removed.
            for _ in 0..100 {
                if std::fs::remove_dir(&group.folder).is_ok() {
                    break;
                }
                std::thread::sleep(std::time::Duration::from_millis(10));
            }
        }
    }
}

/// The number after `name` on its line of the flat-keyed file `file`
/// (`pids.events`, `memory.events`, `memory.oom_control`); 0 if none.
fn counter(file: &Path, name: &str) -> u64 {
    std::fs::read_to_string(file)
        .unwrap_or_default()
        .lines()
        .find_map(|line| line.strip_prefix(name)?.strip_prefix(' '))
        .and_then(|count| count.trim().parse().ok())
        .unwrap_or(0)
}

/// Makes the cgroup `folder` with the limits it is for, and opens its
/// `cgroup.procs`; `None`, and nothing left, where that fails.
fn make(folder: &Path, pids: bool, memory: Option<Version>, limits: &Limits) -> Option<Group> {
    std::fs::create_dir(folder).ok()?;
    let write = |file: &str, value: String| std::fs::write(folder.join(file), value);
    let made = (|| {
        if pids {
            write("pids.max", limits.processes.to_string())?;
        }
        match memory {
            Some(Version::V2) => {
                write("memory.max", limits.memory_bytes.to_string())?;
                // Swapped-out pages would not count: none may be. A kernel
                // without swap has no such file.
                let _ = write("memory.swap.max", "0".into());
            }
            Some(Version::V1) => {
                write("memory.limit_in_bytes", limits.memory_bytes.to_string())?;
                let _ = write(
                    "memory.memsw.limit_in_bytes",
                    limits.memory_bytes.to_string(),
                );
            }
            None => {}
        }
        std::fs::OpenOptions::new()
            .write(true)
            .open(folder.join("cgroup.procs"))
    })();
    match made {
        Ok(procs) => Some(Group {
            folder: folder.to_path_buf(),
            procs,
            pids,
            memory,
        }),
        Err(_) => {
            let _ = std::fs::remove_dir(folder);
            None
        }
    }
}

/// Where this process may make its runs' cgroups, each with what it can
/// cap (processes, memory): its own cgroup in v1's `pids` and `memory`
/// hierarchies, or in the v2 hierarchy for the controllers its
/// `cgroup.subtree_control` delegates.
fn parents() -> Vec<(PathBuf, bool, Option<Version>)> {
    let Ok(own) = std::fs::read_to_string("/proc/self/cgroup") else {
        return Vec::new();
    };
    let root = Path::new(ROOT);
    let inside = |base: &Path, path: &str| base.join(path.trim_start_matches('/'));
    let mut found = Vec::new();
    for line in own.lines() {
        let mut fields = line.splitn(3, ':');
        let (Some(_), Some(controllers), Some(path)) =
            (fields.next(), fields.next(), fields.next())
        else {
            continue;
        };
        for controller in controllers.split(',') {
            let (pids, memory) = match controller {
                "pids" => (true, None),
                "memory" => (false, Some(Version::V1)),
                _ => continue,
            };
            let folder = inside(&root.join(controller), path);
            if folder.join("cgroup.procs").is_file() {
                found.push((folder, pids, memory));
            }
        }
    }
    if found.is_empty() {
        for line in own.lines() {
            if let Some(path) = line.strip_prefix("0::") {
                let folder = inside(root, path);
                let control = std::fs::read_to_string(folder.join("cgroup.subtree_control"))
                    .unwrap_or_default();
                let has = |name: &str| control.split_whitespace().any(|c| c == name);
                let (pids, memory) = (has("pids"), has("memory").then_some(Version::V2));
                if pids || memory.is_some() {
                    found.push((folder, pids, memory));
                }
            }
        }
    }
    found
}

/// Removes the empty cgroups of graders that are no longer running.
fn remove_abandoned(parent: &Path) {
    for entry in super::abandoned_entries(parent, PREFIX) {
        let _ = std::fs::remove_dir(entry.path());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn abandoned_cgroups_of_dead_graders_are_removed() {
        let Some((parent, _, _)) = parents().into_iter().next() else {
            eprintln!("skipped: no cgroup can be made here");
            return;
        };
        // No process has a pid above the kernel's pid_max (at most 2^22).
        let abandoned = parent.join(format!("{PREFIX}4294967295-0"));
        if std::fs::create_dir(&abandoned).is_err() {
            eprintln!("skipped: {} cannot be made", abandoned.display());
            return;
        }
        let made = RunCgroups::create(&Limits {
            processes: 8,
            ..Limits::DEFAULT
        });
        assert!(!abandoned.exists());
        assert!(made.folders().iter().all(|folder| folder.exists()));
    }

    #[test]
    fn counters_are_read_from_flat_keyed_files() {
        let folder = tempfile::tempdir().expect("a folder");
        let file = folder.path().join("memory.events");
        std::fs::write(&file, "low 0\nhigh 0\nmax 12\noom 1\noom_kill 1\n").expect("write");
        assert_eq!(counter(&file, "oom_kill"), 1);
        assert_eq!(counter(&file, "oom"), 1);
        assert_eq!(counter(&file, "max"), 12);
        assert_eq!(counter(&file, "absent"), 0);
    }
}
