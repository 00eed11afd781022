//! Containing a student's build and check (`raylab grade --code`) with
//! bubblewrap (`bwrap`), the sandbox Flatpak runs applications in.
//!
//! Why bubblewrap: it is one small packaged binary (Debian's and Ubuntu's
//! `bubblewrap`), needs no daemon and no root on systems that allow user
//! namespaces, and builds exactly the view a build needs from command-line
//! arguments: the whole file system read-only, the student's workspace (and
//! so its `target/`) and one folder for the verdict file (and `TMPDIR`)
//! writable, no network (a new network namespace has only its own loopback)
//! and a new pid namespace, whose processes the kernel kills together when
//! its first process ends: a `setsid` child cannot outlive the run.
//! Containers (Docker, Podman) would need a daemon or images; `firejail`
//! is setuid and configured by profiles; `systemd-run` needs systemd.
//!
//! Limits are resource limits set on the sandbox before it starts, which
//! every process in it inherits: address space (memory), CPU time, file
//! size (the outputs) and the number of processes. The kernel does not
//! apply the process limit to root, so where raylab may make a cgroup of
//! the `pids` controller (root, or a delegated cgroup), each run also
//! goes into a cgroup of its own whose `pids.max` caps the processes of
//! the run itself, for root too ([`ProcessCap`]).

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The resource limits of a sandboxed run, per process (as the kernel
/// applies them).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Address space: an allocation past it fails (a 50 GB `Vec` aborts).
    pub memory_bytes: u64,
    /// CPU time, in seconds.
    pub cpu_seconds: u64,
    /// The largest file a process may write (`target/` holds the largest:
    /// raylab's libraries are a few tens of megabytes).
    pub file_bytes: u64,
    /// Processes: of the grader's user (a resource limit, which the
    /// kernel does not apply to root), and of the run (a `pids` cgroup,
    /// where one can be made).
    pub processes: u64,
}

impl Limits {
    /// Enough for a release build of raylab and its check on 2 cores.
    pub const DEFAULT: Limits = Limits {
        memory_bytes: 8 << 30,
        cpu_seconds: 1800,
        file_bytes: 2 << 30,
        processes: 512,
    };
}

/// Why student code cannot be sandboxed here.
#[derive(Debug, thiserror::Error)]
pub enum SandboxError {
    #[error(
        "grade --code runs each student's build and check inside bubblewrap (bwrap), which is \
         not installed: install it (`sudo apt-get install bubblewrap` on Debian or Ubuntu, \
         `sudo dnf install bubblewrap` on Fedora), or pass --no-sandbox to run the students' \
         code with your own rights"
    )]
    Missing,
    #[error(
        "bubblewrap ({}) cannot make a sandbox on this machine ({why}); user namespaces may be \
         disabled (`sysctl kernel.unprivileged_userns_clone=1`, or AppArmor's \
         `kernel.apparmor_restrict_unprivileged_userns=0` on Ubuntu 24.04), or pass \
         --no-sandbox to run the students' code with your own rights",
        bwrap.display()
    )]
    Unusable { bwrap: PathBuf, why: String },
}

/// A working bubblewrap and the limits to run under.
#[derive(Debug, Clone)]
pub struct Sandbox {
    bwrap: PathBuf,
    pub limits: Limits,
}

impl Sandbox {
    /// The `bwrap` on the PATH, once it has made a sandbox like the ones
    /// [`Sandbox::command`] makes.
    pub fn find(limits: Limits) -> Result<Sandbox, SandboxError> {
        let bwrap = on_path("bwrap").ok_or(SandboxError::Missing)?;
        let sandbox = Sandbox { bwrap, limits };
        let probe = sandbox
            .command(Path::new("/"), None, OsString::from("true"), &[])
            .command
            .output();
        match probe {
            Ok(out) if out.status.success() => Ok(sandbox),
            Ok(out) => Err(SandboxError::Unusable {
                bwrap: sandbox.bwrap,
                why: String::from_utf8_lossy(&out.stderr).trim().to_string(),
            }),
            Err(error) => Err(SandboxError::Unusable {
                bwrap: sandbox.bwrap,
                why: error.to_string(),
            }),
        }
    }

    /// `program args` inside a sandbox where only `workspace` and
    /// `writable` (the verdict file's folder) can be written, run from
    /// `workspace`, with the cgroup that caps its processes where there is
    /// one: keep it until the run has ended.
    pub fn command(
        &self,
        workspace: &Path,
        writable: Option<&Path>,
        program: OsString,
        args: &[OsString],
    ) -> Sandboxed {
        let mut command = Command::new(&self.bwrap);
        // /tmp stays as it is, read-only like the rest: a raylab checkout
        // or a workspace there must stay visible (a fresh /tmp would hide
        // the path dependency). Temporary files go to the writable folder.
        command.args(["--ro-bind", "/", "/", "--dev", "/dev", "--proc", "/proc"]);
        if workspace != Path::new("/") {
            command.arg("--bind").arg(workspace).arg(workspace);
        }
        if let Some(folder) = writable {
            command.arg("--bind").arg(folder).arg(folder);
            command.env("TMPDIR", folder);
        }
        self.finish(command, workspace, program, args)
    }

    /// `binary serve` inside a sandbox where nothing can be written and
    /// no process is visible: `/proc` is an empty folder (no
    /// `/proc/self/fd` to reach the judge's pipes by, no `/proc/self/mem`
    /// to read them from), every capability is dropped, and the run is
    /// capped and limited as [`Sandbox::command`]'s.
    pub fn serve_command(&self, workspace: &Path, binary: &Path) -> Sandboxed {
        let mut command = Command::new(&self.bwrap);
        command.args([
            "--ro-bind",
            "/",
            "/",
            "--dev",
            "/dev",
            "--tmpfs",
            "/proc",
            "--cap-drop",
            "ALL",
        ]);
        self.finish(command, workspace, binary.into(), &["serve".into()])
    }

    fn finish(
        &self,
        mut command: Command,
        workspace: &Path,
        program: OsString,
        args: &[OsString],
    ) -> Sandboxed {
        command.args(["--unshare-all", "--die-with-parent", "--new-session"]);
        command.arg("--chdir").arg(workspace);
        command.arg("--").arg(program).args(args);
        let limits = self.limits;
        let cap = ProcessCap::create(limits.processes);
        #[cfg(unix)]
        {
            use std::os::fd::AsRawFd;
            use std::os::unix::process::CommandExt;
            let joins = cap.as_ref().map(|cap| cap.procs.as_raw_fd());
            // SAFETY: setrlimit and write are async-signal-safe, touch no
            // memory of the parent's, and are all this runs between fork
            // and exec; the cgroup file stays open until the Sandboxed
            // that owns it is dropped, after the run.
            unsafe {
                command.pre_exec(move || {
                    if let Some(procs) = joins {
                        // "0" moves the writing process: bwrap, and so
                        // everything it starts, into the run's cgroup.
                        if libc::write(procs, c"0".as_ptr().cast(), 1) != 1 {
                            return Err(std::io::Error::last_os_error());
                        }
                    }
                    set_limit(libc::RLIMIT_AS, limits.memory_bytes)?;
                    set_limit(libc::RLIMIT_CPU, limits.cpu_seconds)?;
                    set_limit(libc::RLIMIT_FSIZE, limits.file_bytes)?;
                    set_limit(libc::RLIMIT_NPROC, limits.processes)?;
                    Ok(())
                });
            }
        }
        Sandboxed { command, cap }
    }
}

/// A sandboxed command and the cgroup that caps its processes, if one
/// could be made.
#[derive(Debug)]
pub struct Sandboxed {
    pub command: Command,
    pub cap: Option<ProcessCap>,
}

/// A `pids` cgroup of one run, whose `pids.max` the run cannot raise (the
/// sandbox mounts nothing of `/sys` writable): a fork loop stops at the
/// cap, for root too. Removed when dropped; one left by a grader that was
/// killed is removed by the next one (its name holds the grader's pid).
#[derive(Debug)]
pub struct ProcessCap {
    folder: PathBuf,
    // Written only where there are processes to cap (Unix).
    #[cfg_attr(not(unix), allow(dead_code))]
    procs: std::fs::File,
}

/// The prefix of the cgroups raylab makes, followed by the grader's pid
/// and a counter.
const CAP_PREFIX: &str = "raylab-grade-";

impl ProcessCap {
    /// A new cgroup allowing `processes` processes in all, under this
    /// process's own cgroup of the `pids` controller (cgroup v1), or of the
    /// unified hierarchy when that cgroup delegates `pids` to its children
    /// (v2); `None` where neither can be made (an ordinary user without a
    /// delegated cgroup: the resource limit applies to them).
    pub fn create(processes: u64) -> Option<ProcessCap> {
        let parent = pids_parent()?;
        remove_abandoned(&parent);
        static COUNT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        let number = COUNT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let folder = parent.join(format!("{CAP_PREFIX}{}-{number}", std::process::id()));
        std::fs::create_dir(&folder).ok()?;
        let made = std::fs::write(folder.join("pids.max"), processes.to_string()).and_then(|()| {
            std::fs::OpenOptions::new()
                .write(true)
                .open(folder.join("cgroup.procs"))
        });
        match made {
            Ok(procs) => Some(ProcessCap { folder, procs }),
            Err(_) => {
                let _ = std::fs::remove_dir(&folder);
                None
            }
        }
    }

    /// The cgroup's folder.
    pub fn folder(&self) -> &Path {
        &self.folder
    }
}

impl Drop for ProcessCap {
    fn drop(&mut self) {
        // The kernel frees the cgroup's last processes just after they are
        // reaped; until then the folder cannot be removed.
        for _ in 0..100 {
            if std::fs::remove_dir(&self.folder).is_ok() {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
    }
}

/// Where this process may make a `pids` cgroup: its own cgroup in the v1
/// `pids` hierarchy, or in the v2 one if `pids` is in that cgroup's
/// `cgroup.subtree_control`.
fn pids_parent() -> Option<PathBuf> {
    let own = std::fs::read_to_string("/proc/self/cgroup").ok()?;
    let root = Path::new("/sys/fs/cgroup");
    let inside = |path: &str| root.join(path.trim_start_matches('/'));
    for line in own.lines() {
        let mut fields = line.splitn(3, ':');
        let (Some(_), Some(controllers), Some(path)) =
            (fields.next(), fields.next(), fields.next())
        else {
            continue;
        };
        if controllers.split(',').any(|name| name == "pids") {
            let folder = root.join("pids").join(path.trim_start_matches('/'));
            if folder.join("cgroup.procs").is_file() {
                return Some(folder);
            }
        }
    }
    for line in own.lines() {
        if let Some(path) = line.strip_prefix("0::") {
            let folder = inside(path);
            let delegated = std::fs::read_to_string(folder.join("cgroup.subtree_control"))
                .is_ok_and(|control| control.split_whitespace().any(|name| name == "pids"));
            if delegated {
                return Some(folder);
            }
        }
    }
    None
}

/// Removes the empty cgroups of graders that are no longer running.
fn remove_abandoned(parent: &Path) {
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name
            .to_str()
            .and_then(|name| name.strip_prefix(CAP_PREFIX))
            .and_then(|rest| rest.split('-').next())
        else {
            continue;
        };
        if pid != std::process::id().to_string() && !Path::new("/proc").join(pid).exists() {
            let _ = std::fs::remove_dir(entry.path());
        }
    }
}

/// The type of `setrlimit`'s first argument, which glibc names.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
type Resource = libc::__rlimit_resource_t;
#[cfg(all(unix, not(all(target_os = "linux", target_env = "gnu"))))]
type Resource = libc::c_int;

#[cfg(unix)]
fn set_limit(resource: Resource, value: u64) -> std::io::Result<()> {
    let limit = libc::rlimit {
        rlim_cur: value as libc::rlim_t,
        rlim_max: value as libc::rlim_t,
    };
    // SAFETY: a plain system call on a value on the stack.
    if unsafe { libc::setrlimit(resource, &limit) } == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

/// The first executable file named `name` in the folders of `$PATH`.
fn on_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|folder| folder.join(name))
        .find(|candidate| {
            #[cfg(unix)]
            {
                use std::os::unix::fs::PermissionsExt;
                std::fs::metadata(candidate)
                    .is_ok_and(|meta| meta.is_file() && meta.permissions().mode() & 0o111 != 0)
            }
            #[cfg(not(unix))]
            {
                candidate.is_file()
            }
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where the machine lets raylab make a `pids` cgroup (root, as in CI),
    /// a run that starts 64 processes is stopped at its cap of 8, and the
    /// cgroup is gone once the run is over.
    #[test]
    fn a_run_cannot_start_more_processes_than_its_cap() {
        let limits = Limits {
            processes: 8,
            ..Limits::DEFAULT
        };
        let Ok(sandbox) = Sandbox::find(limits) else {
            eprintln!("skipped: no working bubblewrap here");
            return;
        };
        let script = "i=0; while [ $i -lt 64 ]; do sleep 1 & i=$((i+1)); done; wait";
        let mut sandboxed = sandbox.command(
            Path::new("/"),
            None,
            "sh".into(),
            &["-c".into(), script.into()],
        );
        let Some(folder) = sandboxed.cap.as_ref().map(|cap| cap.folder().to_path_buf()) else {
            eprintln!("skipped: no pids cgroup can be made here (the resource limit applies)");
            return;
        };
        let ran = sandboxed.command.output().expect("the sandbox starts");
        let events = std::fs::read_to_string(folder.join("pids.events")).expect("pids.events");
        let refused: u64 = events
            .lines()
            .find_map(|line| line.strip_prefix("max "))
            .and_then(|count| count.trim().parse().ok())
            .expect("a max count in pids.events");
        assert!(
            refused > 0,
            "no fork refused: {events}; {}",
            String::from_utf8_lossy(&ran.stderr)
        );
        drop(sandboxed);
        assert!(!folder.exists(), "{} left behind", folder.display());
    }

    #[test]
    fn abandoned_caps_of_dead_graders_are_removed() {
        let Some(parent) = pids_parent() else {
            eprintln!("skipped: no pids cgroup can be made here");
            return;
        };
        // No process has a pid above the kernel's pid_max (at most 2^22).
        let abandoned = parent.join(format!("{CAP_PREFIX}4294967295-0"));
        if std::fs::create_dir(&abandoned).is_err() {
            eprintln!("skipped: {} cannot be made", abandoned.display());
            return;
        }
        let cap = ProcessCap::create(8).expect("a cap where one was just made");
        assert!(!abandoned.exists());
        assert!(cap.folder().exists());
    }
}
