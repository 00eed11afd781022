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
//! size (the outputs) and, for a grader that is not root, the number of
//! processes. The kernel does not count processes for root; there a fork
//! loop still ends with the time limit, when the pid namespace is killed.

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
    /// Processes of the grader's user (not applied by the kernel to root).
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
    /// `workspace`.
    pub fn command(
        &self,
        workspace: &Path,
        writable: Option<&Path>,
        program: OsString,
        args: &[OsString],
    ) -> Command {
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
        command.args(["--unshare-all", "--die-with-parent", "--new-session"]);
        command.arg("--chdir").arg(workspace);
        command.arg("--").arg(program).args(args);
        let limits = self.limits;
        #[cfg(unix)]
        {
            use std::os::unix::process::CommandExt;
            // SAFETY: setrlimit is async-signal-safe, touches no memory of
            // the parent's, and is all this runs between fork and exec.
            unsafe {
                command.pre_exec(move || {
                    set_limit(libc::RLIMIT_AS, limits.memory_bytes)?;
                    set_limit(libc::RLIMIT_CPU, limits.cpu_seconds)?;
                    set_limit(libc::RLIMIT_FSIZE, limits.file_bytes)?;
                    set_limit(libc::RLIMIT_NPROC, limits.processes)?;
                    Ok(())
                });
            }
        }
        command
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
