//! Containing a student's build and check (`raylab grade --code`) with
//! bubblewrap (`bwrap`), the sandbox Flatpak runs applications in.
//!
//! Why bubblewrap: it is one small packaged binary (Debian's and Ubuntu's
//! `bubblewrap`), needs no daemon and no root on systems that allow user
//! namespaces, and builds exactly the view a build needs from command-line
//! arguments. Containers (Docker, Podman) would need a daemon or images;
//! `firejail` is setuid and configured by profiles; `systemd-run` needs
//! systemd.
//!
//! Each student's run ([`Run`]) sees only what a build needs (`view`):
//! the system's programs and libraries, the toolchain, cargo's cache of
//! crates, raylab's checkout without its builds (`target/`,
//! `web/target/`) or its history (`.git/`), and a copy of the workspace with the workspace's
//! `target/` (`workdir`); not the
//! grader's binary, home, environment or outputs, the instructor's hidden
//! scenes, other workspaces, `/etc/shadow`, `/run` or `/tmp`. It has no
//! network (a new network namespace has only its own loopback, which also
//! keeps the host's abstract Unix sockets out of reach) and a new pid
//! namespace, whose processes the kernel kills together when its first
//! process ends: a `setsid` child cannot outlive the run, and the
//! grader's processes cannot be seen. When the grader is root, the run's
//! processes are the unprivileged user `nobody`, with no capability
//! (`RunAs`).
//!
//! Limits: the memory and the processes of the whole run (its build, then
//! all its answering processes at once) are capped by cgroups of the run
//! where raylab may make them (`cgroups`); where it may not, each
//! process's address space is capped instead (a resource limit). What the
//! run writes to disk is measured while it runs, and a run past its disk
//! limit is stopped and its `target/` removed. CPU time and the size of
//! each file are resource limits of each process.

mod cgroups;
mod descriptors;
mod held;
mod syscalls;
mod view;
mod workdir;

pub use cgroups::RunCgroups;

use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};

use view::{Mount, View};
use workdir::RunFolder;

/// The resource limits of a sandboxed run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Memory of the whole run, where a memory cgroup can be made (root,
    /// or a delegated cgroup); else the address space of each process (a
    /// 50 GB `Vec` aborts at once).
    pub memory_bytes: u64,
    /// CPU time of each process, in seconds.
    pub cpu_seconds: u64,
    /// The largest file a process may write (`target/` holds the largest:
    /// raylab's libraries are a few tens of megabytes).
    pub file_bytes: u64,
    /// What the run may add on disk, all its files together: the build's
    /// output in `target/`, its copy of the workspace, its temporary
    /// files; or what its processes write to files, if more (which holds
    /// deleted files no process lists). A workspace's own files (outside
    /// `target/` and `.git/`) may not be more than this either.
    pub disk_bytes: u64,
    /// Processes (and threads) of the run at once, where a `pids` cgroup
    /// can be made; else of the user the run's processes are (a resource
    /// limit, which the kernel does not apply to root).
    pub processes: u64,
}

impl Limits {
    /// Enough for a release build of raylab and its check on 2 cores.
    pub const DEFAULT: Limits = Limits {
        memory_bytes: 8 << 30,
        cpu_seconds: 1800,
        file_bytes: 2 << 30,
        disk_bytes: 4 << 30,
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
    #[error(
        "raylab runs as root, so the students' code must run as an unprivileged user, which \
         needs util-linux's `setpriv` (not found on the PATH nor in /usr/bin): install \
         util-linux, or grade as an ordinary user"
    )]
    NoSetpriv,
    #[error("cannot find the Rust toolchain the students' workspaces build with: {why}")]
    Toolchain { why: String },
    #[error("cannot {action} {} for the run: {error}", path.display())]
    RunFolder {
        action: &'static str,
        path: PathBuf,
        error: std::io::Error,
    },
    #[error(
        "{} is not a folder: the build writes its output there; remove it",
        .0.display()
    )]
    TargetNotAFolder(PathBuf),
    #[error(
        "the workspace's files (but target/ and .git/) are more than {} or {entries} files: \
         over the run's disk limit",
        bytes_text(*budget)
    )]
    WorkspaceTooLarge { budget: u64, entries: u64 },
}

/// A limit of its run that a run reached, for the report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum LimitReached {
    /// The run's processes together held `bytes`, and the kernel killed one.
    Memory { bytes: u64 },
    /// The run wrote more than `bytes`, and was stopped.
    Disk { bytes: u64 },
    /// The run had `count` processes (and threads) at once, and one more
    /// could not start.
    Processes { count: u64 },
}

impl LimitReached {
    /// The limit in a few words: "the memory limit".
    pub fn name(&self) -> &'static str {
        match self {
            LimitReached::Memory { .. } => "the memory limit",
            LimitReached::Disk { .. } => "the disk limit",
            LimitReached::Processes { .. } => "the process limit",
        }
    }
}

impl std::fmt::Display for LimitReached {
    fn fmt(&self, out: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LimitReached::Memory { bytes } => write!(
                out,
                "the memory limit: the run's processes together reached {}, and the kernel \
                 killed one of them",
                bytes_text(*bytes)
            ),
            LimitReached::Disk { bytes } => write!(
                out,
                "the disk limit: the run wrote more than {} (its target/, its copy of the \
                 workspace, its temporary files and the files it deleted but kept open, \
                 together, or all its processes wrote to files), or more than a million \
                 files; it was stopped, and its target/ removed",
                bytes_text(*bytes)
            ),
            LimitReached::Processes { count } => write!(
                out,
                "the process limit: the run had {count} processes and threads at once, and \
                 one more could not start"
            ),
        }
    }
}

/// `bytes` in words: "8 GiB", "768 MiB", "1000 bytes".
pub fn bytes_text(bytes: u64) -> String {
    if bytes >= 1 << 30 && bytes % (1 << 30) == 0 {
        format!("{} GiB", bytes >> 30)
    } else if bytes >= 1 << 20 && bytes % (1 << 20) == 0 {
        format!("{} MiB", bytes >> 20)
    } else {
        format!("{bytes} bytes")
    }
}

/// When the grader is root, the user its runs' processes become.
///
/// bubblewrap's own `--uid` needs a user namespace, and one made by root
/// maps the sandbox's user to root outside: its processes would still own
/// root's files (`/etc/shadow` is readable by its owner), and a file
/// shown writable would be root's to change. So bubblewrap runs as root
/// with every capability dropped but the three `setpriv` needs to switch
/// users, and util-linux's `setpriv`, started first inside, becomes
/// `nobody` (uid and gid 65534), clears the supplementary groups, empties
/// the capability sets (bounding set included) and sets `no_new_privs`,
/// so that no setuid program can give them back, before it starts the
/// build or the student's binary. As `nobody` the run can write only what
/// raylab gives it ([`workdir`]), and cannot remount anything nor touch a
/// cgroup.
#[derive(Debug, Clone)]
struct RunAs {
    setpriv: PathBuf,
    uid: u32,
    gid: u32,
}

/// `nobody`, on Debian, Ubuntu, Fedora and Arch.
const NOBODY: u32 = 65534;

impl RunAs {
    /// The words that start `program` as the run's user.
    fn words(&self) -> Vec<OsString> {
        let mut words: Vec<OsString> = vec![self.setpriv.clone().into()];
        words.extend(
            [
                format!("--reuid={}", self.uid),
                format!("--regid={}", self.gid),
                "--clear-groups".into(),
                "--bounding-set=-all".into(),
                "--inh-caps=-all".into(),
                "--no-new-privs".into(),
                "--".into(),
            ]
            .map(OsString::from),
        );
        words
    }
}

/// The toolchain the runs build with, as found outside the sandbox.
#[derive(Debug, Clone)]
struct Toolchain {
    /// rustc's sysroot: its `bin/` has `rustc` and, from rustup, `cargo`.
    sysroot: PathBuf,
    /// The cargo binary itself (never rustup's proxy, which would need
    /// rustup's settings and the grader's home).
    cargo: PathBuf,
    /// cargo's folder, where it is not in the sysroot.
    cargo_folder: Option<PathBuf>,
    /// cargo's home, of which the runs see the cache of crates only.
    cargo_home: Option<PathBuf>,
}

impl Toolchain {
    /// The cargo of `$CARGO` (else of the PATH) and the sysroot of the
    /// `rustc` beside it (else of the PATH), asked from `/`, so that no
    /// workspace's `rust-toolchain` file picks another.
    fn find() -> Result<Toolchain, SandboxError> {
        let given = std::env::var_os("CARGO")
            .map(PathBuf::from)
            .or_else(|| on_path("cargo"))
            .ok_or_else(|| SandboxError::Toolchain {
                why: "no cargo: neither $CARGO nor a cargo on the PATH".into(),
            })?;
        let beside = given.with_file_name("rustc");
        let rustc = if beside.is_file() {
            beside
        } else {
            on_path("rustc").ok_or_else(|| SandboxError::Toolchain {
                why: "no rustc beside cargo nor on the PATH".into(),
            })?
        };
        let asked = Command::new(&rustc)
            .args(["--print", "sysroot"])
            .current_dir("/")
            .output()
            .map_err(|error| SandboxError::Toolchain {
                why: format!("{} --print sysroot: {error}", rustc.display()),
            })?;
        let printed = String::from_utf8_lossy(&asked.stdout).trim().to_string();
        let sysroot =
            Path::new(&printed)
                .canonicalize()
                .map_err(|error| SandboxError::Toolchain {
                    why: format!(
                        "{} --print sysroot said {printed:?}: {error}",
                        rustc.display()
                    ),
                })?;
        let given = given.canonicalize().unwrap_or(given);
        let inside = sysroot.join("bin/cargo");
        let cargo = if given.starts_with(&sysroot) || !inside.is_file() {
            given
        } else {
            inside
        };
        let cargo_folder = cargo
            .parent()
            .filter(|folder| !folder.starts_with(&sysroot))
            .map(Path::to_path_buf);
        let cargo_home = std::env::var_os("CARGO_HOME")
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|home| Path::new(&home).join(".cargo")))
            .and_then(|home| home.canonicalize().ok());
        Ok(Toolchain {
            sysroot,
            cargo,
            cargo_folder,
            cargo_home,
        })
    }

    /// The PATH inside: the toolchain, then the system's programs (the
    /// linker `cc` among them).
    fn path(&self) -> OsString {
        let mut folders = vec![self.sysroot.join("bin")];
        folders.extend(self.cargo_folder.clone());
        folders.extend(["/usr/bin", "/bin"].map(PathBuf::from));
        std::env::join_paths(folders).unwrap_or_else(|_| "/usr/bin:/bin".into())
    }
}

/// A working bubblewrap, the limits to run under, and what to hide.
#[derive(Debug, Clone)]
pub struct Sandbox {
    bwrap: PathBuf,
    pub limits: Limits,
    run_as: Option<RunAs>,
    toolchain: Toolchain,
    /// raylab's checkout (the workspaces' path dependency), where it is.
    raylab: Option<PathBuf>,
    /// Paths the runs must not see even inside what they see: the
    /// grader's binary, the instructor's files.
    hidden: Vec<PathBuf>,
    /// Where raylab notes, for each workspace, the state its `target/`
    /// was in when a run of raylab's left it (see [`Run::vouch_for_build`]);
    /// `None` where there is no cache folder: every `target/` is emptied.
    records: Option<PathBuf>,
    /// Use every workspace's `target/` as it is (`--trust-targets`).
    trust_targets: bool,
}

/// Whether raylab runs as root (never, where there are no users: the
/// browser page's WebAssembly build).
fn running_as_root() -> bool {
    #[cfg(unix)]
    {
        // SAFETY: geteuid has no preconditions.
        unsafe { libc::geteuid() == 0 }
    }
    #[cfg(not(unix))]
    {
        false
    }
}

impl Sandbox {
    /// The `bwrap` on the PATH, once it has run a program in a sandbox
    /// like those of the runs (as `nobody`, when raylab is root).
    pub fn find(limits: Limits) -> Result<Sandbox, SandboxError> {
        let bwrap = on_path("bwrap").ok_or(SandboxError::Missing)?;
        let run_as = if running_as_root() {
            let setpriv = on_path("setpriv")
                .or_else(|| Some(PathBuf::from("/usr/bin/setpriv")).filter(|path| path.is_file()))
                .ok_or(SandboxError::NoSetpriv)?;
            Some(RunAs {
                setpriv: setpriv.canonicalize().unwrap_or(setpriv),
                uid: NOBODY,
                gid: NOBODY,
            })
        } else {
            None
        };
        let raylab = Path::new(crate::workspace::RAYLAB_DIR)
            .canonicalize()
            .ok()
            .filter(|folder| folder.join("Cargo.toml").is_file());
        let grader = std::env::current_exe().and_then(|exe| exe.canonicalize());
        let sandbox = Sandbox {
            bwrap,
            limits,
            run_as,
            toolchain: Toolchain::find()?,
            raylab,
            hidden: grader.into_iter().collect(),
            records: records_folder(),
            trust_targets: false,
        };
        let env = [("PATH".into(), sandbox.toolchain.path())];
        let probe = sandbox
            .command(
                &sandbox.view(None),
                Path::new("/"),
                "true".as_ref(),
                &[],
                &env,
                None,
            )
            .and_then(|sandboxed| {
                let mut command = sandboxed.command;
                command.output().map_err(|error| SandboxError::Unusable {
                    bwrap: sandbox.bwrap.clone(),
                    why: error.to_string(),
                })
            })?;
        if probe.status.success() {
            Ok(sandbox)
        } else {
            Err(SandboxError::Unusable {
                bwrap: sandbox.bwrap,
                why: String::from_utf8_lossy(&probe.stderr).trim().to_string(),
            })
        }
    }

    /// The same sandbox, hiding `paths` too wherever they would show (the
    /// instructor's scenes, references and outputs).
    pub fn hiding(mut self, paths: impl IntoIterator<Item = PathBuf>) -> Sandbox {
        self.hidden.extend(
            paths
                .into_iter()
                .filter_map(|path| path.canonicalize().ok()),
        );
        self
    }

    /// The same sandbox, using each workspace's `target/` as it is, even
    /// where no run of raylab's left it so (`--trust-targets`: for builds
    /// the instructor made).
    pub fn trusting_targets(mut self, trust: bool) -> Sandbox {
        self.trust_targets = trust;
        self
    }

    /// Whether the runs build on each workspace's `target/` as it is
    /// ([`Sandbox::trusting_targets`]).
    pub fn trusts_targets(&self) -> bool {
        self.trust_targets
    }

    /// The cargo the runs build with.
    pub fn cargo(&self) -> &Path {
        &self.toolchain.cargo
    }

    /// A run of the workspace `workspace`: its folder, its copy of the
    /// workspace and its cgroups, ready for [`Run::build_command`] and
    /// [`Run::serve_command`].
    pub fn start(&self, workspace: &Path) -> Result<Run, SandboxError> {
        let workspace = workspace
            .canonicalize()
            .map_err(|error| SandboxError::RunFolder {
                action: "resolve",
                path: workspace.to_path_buf(),
                error,
            })?;
        let owner = self.run_as.as_ref().map(|user| (user.uid, user.gid));
        // A `target/` is built on only as a run of raylab's left it, and
        // only for the sources that run built: one the student made or
        // changed since, or one built from sources changed since (dated
        // back, cargo would take its binary for up to date), could hold a
        // binary built from other sources.
        let sources = workdir::sources_state(&workspace);
        let record = self
            .records
            .as_ref()
            .map(|folder| folder.join(record_name(&workspace)));
        let recorded = record
            .as_ref()
            .and_then(|record| std::fs::read_to_string(record).ok())
            .and_then(|text| {
                let mut states = text
                    .split_whitespace()
                    .map(|state| state.parse::<u64>().ok());
                Some((states.next()??, states.next()??))
            });
        let keep_target = self.trust_targets
            || recorded.is_some_and(|(target, built_from)| {
                workdir::tree_state(&workspace.join("target")) == Some(target)
                    && sources == Some(built_from)
            });
        // Used once: only this run, if it is vouched for, notes it again.
        if let Some(record) = &record {
            let _ = std::fs::remove_file(record);
        }
        let folder = RunFolder::new(&workspace, self.limits.disk_bytes, owner, keep_target)?;
        let baseline = folder.on_disk();
        Ok(Run {
            sandbox: self.clone(),
            workspace,
            record,
            sources,
            folder,
            cgroups: RunCgroups::create(&self.limits),
            baseline,
            over_disk: AtomicBool::new(false),
        })
    }

    /// The view every sandbox starts from: the system, the toolchain,
    /// cargo's cache of crates, raylab's checkout without its builds
    /// (`target/`, `web/target/`) or its history (`.git/`);
    /// then `then`'s mounts, and the hidden paths covered, the workspace's
    /// neighbours too (the other workspaces of a class).
    fn view(&self, then: Option<(&Path, Vec<Mount>)>) -> View {
        let mut view = View::system();
        view.show(&self.toolchain.sysroot);
        if let Some(folder) = &self.toolchain.cargo_folder {
            view.show(folder);
        }
        if let Some(home) = &self.toolchain.cargo_home {
            for name in ["registry", "git", "config.toml", "config"] {
                view.show(&home.join(name));
            }
        }
        if let Some(raylab) = &self.raylab {
            view.show(raylab);
            // Its builds: raylab's reference chapters compiled without
            // `student` (the browser page's WebAssembly among them), which
            // report nothing when they run. And its history, which a build
            // does not need: a hidden scene committed there, or a remote's
            // credentials in its config, would be read through `git`.
            for built in ["target", "web/target", ".git"] {
                view.hide(&raylab.join(built));
            }
        }
        let mut hidden = self.hidden.clone();
        if let Some(home) = &self.toolchain.cargo_home {
            hidden.extend(["credentials.toml", "credentials"].map(|name| home.join(name)));
        }
        if let Some((workspace, mounts)) = then {
            for mount in mounts {
                view.push(mount);
            }
            hidden.extend(workspace.parent().map(Path::to_path_buf));
        }
        for path in &hidden {
            view.hide(path);
        }
        view
    }

    /// bubblewrap running `program args` in `view`, from `folder`, with
    /// only the environment `env`, in `cgroups`, under the limits.
    fn command(
        &self,
        view: &View,
        folder: &Path,
        program: &OsStr,
        args: &[OsString],
        env: &[(OsString, OsString)],
        cgroups: Option<&RunCgroups>,
    ) -> Result<Sandboxed, SandboxError> {
        let mut options = view.options();
        // bubblewrap's root, on which the view is made, and its `/dev`
        // are folders in memory that a sandbox's user with a user
        // namespace of its own owns: writable, they would hold what the
        // disk limit does not count (up to half the machine's memory), and
        // the answering processes could write. Read-only once made (the
        // devices still work); the mounts in them keep their own rights.
        options.extend(["--remount-ro", "/", "--remount-ro", "/dev"].map(OsString::from));
        options.extend(
            [
                "--unshare-ipc",
                "--unshare-pid",
                "--unshare-net",
                "--unshare-uts",
                "--unshare-cgroup-try",
                "--die-with-parent",
                "--new-session",
                "--cap-drop",
                "ALL",
            ]
            .map(OsString::from),
        );
        if self.run_as.is_some() {
            for capability in ["CAP_SETUID", "CAP_SETGID", "CAP_SETPCAP"] {
                options.extend(["--cap-add", capability].map(OsString::from));
            }
        } else {
            // An ordinary user's sandbox needs a user namespace.
            options.push("--unshare-user".into());
        }
        options.push("--clearenv".into());
        for (name, value) in env {
            options.extend([OsString::from("--setenv"), name.clone(), value.clone()]);
        }
        options.extend([OsString::from("--chdir"), folder.into()]);
        let filters = syscalls::filter_files().map_err(|why| SandboxError::Unusable {
            bwrap: self.bwrap.clone(),
            why: format!("cannot make its seccomp programs: {why}"),
        })?;
        #[cfg(unix)]
        let filter_fds: Vec<i32> = filters
            .iter()
            .map(|file| {
                use std::os::fd::AsRawFd;
                file.as_raw_fd()
            })
            .collect();
        #[cfg(not(unix))]
        let filter_fds: Vec<i32> = Vec::new();
        for fd in &filter_fds {
            options.extend([OsString::from("--add-seccomp-fd"), fd.to_string().into()]);
        }
        let file = descriptors::options_file(&options).map_err(|error| SandboxError::Unusable {
            bwrap: self.bwrap.clone(),
            why: format!("cannot write its options to a temporary file: {error}"),
        })?;
        let mut command = Command::new(&self.bwrap);
        // Nothing of the grader's environment, not even in bubblewrap's
        // own process (its /proc/1/environ, inside).
        command.env_clear();
        // Its options from a file, so that its command line (/proc/1/cmdline
        // inside) does not spell out the view.
        #[cfg(unix)]
        let fd = {
            use std::os::fd::AsRawFd;
            file.as_raw_fd()
        };
        #[cfg(not(unix))]
        let fd = 0;
        command.arg("--args").arg(fd.to_string()).arg("--");
        if let Some(user) = &self.run_as {
            command.args(user.words());
        }
        command.arg(program).args(args);
        let kept: Vec<i32> = std::iter::once(fd).chain(filter_fds).collect();
        self.limit(&mut command, kept, cgroups);
        Ok(Sandboxed {
            command,
            _options: file,
            _filters: filters,
        })
    }

    /// Has `command`, between fork and exec, keep the files `kept` (the
    /// options', the seccomp program's) open, join `cgroups` and set the
    /// limits the cgroups do not hold.
    #[cfg_attr(not(unix), allow(unused_variables))]
    fn limit(&self, command: &mut Command, kept: Vec<i32>, cgroups: Option<&RunCgroups>) {
        #[cfg(unix)]
        {
            use std::os::unix::process::CommandExt;
            let limits = self.limits;
            let joins = cgroups.map(RunCgroups::joins).unwrap_or_default();
            let memory_capped = cgroups.is_some_and(RunCgroups::caps_memory);
            let processes_capped = cgroups.is_some_and(RunCgroups::caps_processes);
            // SAFETY: fcntl, write and setrlimit are async-signal-safe,
            // touch no memory of the parent's, and are all this runs
            // between fork and exec; the files stay open until the
            // Sandboxed and the Run that own them are dropped, after the
            // spawn.
            unsafe {
                command.pre_exec(move || {
                    // Whatever the grader was started with stays out of
                    // the run: a shell's `exec 7< secret`, a harness's
                    // log. Every descriptor closes at exec, but those kept.
                    descriptors::close_on_exec_from_3()?;
                    for &fd in &kept {
                        if libc::fcntl(fd, libc::F_SETFD, 0) != 0 {
                            return Err(std::io::Error::last_os_error());
                        }
                    }
                    for &procs in &joins {
                        // "0" moves the writing process: bwrap, and so
                        // everything it starts, into the run's cgroup.
                        if libc::write(procs, c"0".as_ptr().cast(), 1) != 1 {
                            return Err(std::io::Error::last_os_error());
                        }
                    }
                    // An address-space limit breaks programs that reserve
                    // more than they use (rustc does): only where no
                    // cgroup holds the memory of the run.
                    if !memory_capped {
                        set_limit(libc::RLIMIT_AS, limits.memory_bytes)?;
                    }
                    // SIGXCPU at the limit ends the process by a signal
                    // that names the limit (at a hard limit the kernel
                    // sends SIGKILL, which names nothing); SIGKILL a
                    // second later if it catches that.
                    set_limits(
                        libc::RLIMIT_CPU,
                        limits.cpu_seconds,
                        limits.cpu_seconds.saturating_add(1),
                    )?;
                    set_limit(libc::RLIMIT_FSIZE, limits.file_bytes)?;
                    if !processes_capped {
                        set_limit(libc::RLIMIT_NPROC, limits.processes)?;
                    }
                    Ok(())
                });
            }
        }
    }
}

/// One student's run: its folder (the copy of the workspace, the
/// temporary folder) and its cgroups, which every process of the run
/// joins. Its cgroups and its folder go when it is dropped, and the
/// workspace's `target/` too after a run that went over its disk limit.
#[derive(Debug)]
pub struct Run {
    sandbox: Sandbox,
    workspace: PathBuf,
    /// Where to note the state of its `target/` (see [`Run::vouch_for_build`]).
    record: Option<PathBuf>,
    /// The state of the workspace's sources when the run started: what
    /// its build compiled.
    sources: Option<u64>,
    folder: RunFolder,
    cgroups: RunCgroups,
    /// What the run's folders held on disk before it started.
    baseline: u64,
    over_disk: AtomicBool,
}

impl Run {
    /// The workspace, as the run sees it (absolute, without links).
    pub fn workspace(&self) -> &Path {
        &self.workspace
    }

    /// The copy of the workspace the build reads, where the grader sees it
    /// (the run sees it at [`Run::workspace`]).
    pub fn copy(&self) -> &Path {
        &self.folder.copy
    }

    /// The run's cgroups.
    pub fn cgroups(&self) -> &RunCgroups {
        &self.cgroups
    }

    /// `program args` run from the workspace, which (its copy, its
    /// `target/`) and `/tmp` it may write, with the toolchain's PATH, a
    /// HOME of its own, cargo's home, and `env`.
    pub fn build_command(
        &self,
        program: &OsStr,
        args: &[OsString],
        env: &[(&str, OsString)],
    ) -> Result<Sandboxed, SandboxError> {
        let sandbox = &self.sandbox;
        let mounts = vec![
            Mount::Proc {
                dest: "/proc".into(),
            },
            Mount::Bind {
                source: self.folder.tmp.clone(),
                dest: "/tmp".into(),
                writable: true,
            },
            Mount::Bind {
                source: self.folder.copy.clone(),
                dest: self.workspace.clone(),
                writable: true,
            },
            Mount::Bind {
                source: self.folder.target.clone(),
                dest: self.workspace.join("target"),
                writable: true,
            },
        ];
        let view = sandbox.view(Some((&self.workspace, mounts)));
        let mut all: Vec<(OsString, OsString)> = vec![
            ("PATH".into(), sandbox.toolchain.path()),
            ("HOME".into(), "/tmp".into()),
            ("TMPDIR".into(), "/tmp".into()),
            ("LANG".into(), "C.UTF-8".into()),
        ];
        if let Some(home) = &sandbox.toolchain.cargo_home {
            all.push(("CARGO_HOME".into(), home.into()));
        }
        all.extend(env.iter().map(|(name, value)| (name.into(), value.clone())));
        sandbox.command(
            &view,
            &self.workspace,
            program,
            args,
            &all,
            Some(&self.cgroups),
        )
    }

    /// `binary serve` run from the workspace, where nothing can be written
    /// and no process is visible: `/proc` is an empty folder (no
    /// `/proc/self/fd` to reach the judge's pipes by, no `/proc/self/mem`
    /// to read them from).
    pub fn serve_command(&self, binary: &Path) -> Result<Sandboxed, SandboxError> {
        let mounts = vec![
            Mount::Tmpfs {
                dest: "/proc".into(),
                size: Some(0),
                mode: None,
            },
            Mount::Bind {
                source: self.folder.copy.clone(),
                dest: self.workspace.clone(),
                writable: false,
            },
            Mount::Bind {
                source: self.folder.target.clone(),
                dest: self.workspace.join("target"),
                writable: false,
            },
        ];
        let view = self.sandbox.view(Some((&self.workspace, mounts)));
        let env = [("LANG".into(), "C.UTF-8".into())];
        self.sandbox.command(
            &view,
            &self.workspace,
            binary.as_os_str(),
            &["serve".into()],
            &env,
            Some(&self.cgroups),
        )
    }

    /// Notes the state the run leaves the workspace's `target/` in, so
    /// that the next run builds on it: only for a run in which none of
    /// the student's code ran at build time (no build script, procedural
    /// macro or dependency of its own), which wrote nothing there but
    /// cargo's and the compiler's output. A run not vouched for leaves no
    /// note, and the next run starts from an empty `target/`.
    pub fn vouch_for_build(&self) {
        let Some(record) = &self.record else {
            return;
        };
        if self.over_disk.load(Ordering::Relaxed) {
            return;
        }
        if let (Some(state), Some(sources)) =
            (workdir::tree_state(&self.folder.target), self.sources)
        {
            let written = record
                .parent()
                .map_or(Ok(()), std::fs::create_dir_all)
                .and_then(|()| std::fs::write(record, format!("{state} {sources}")));
            if written.is_err() {
                let _ = std::fs::remove_file(record);
            }
        }
    }

    /// Whether the run has written more than its disk limit (measured now):
    /// in its folder, and, while `root` (the run's first process) runs, in
    /// files its processes deleted but hold open, or all its living
    /// processes have written, whichever is more (a deleted file held by a
    /// message in flight on a Unix socket is only in the last).
    pub fn over_disk_limit(&self, root: Option<u32>) -> bool {
        let (held, written_by_processes) = root.map_or((0, 0), |root| {
            let processes = held::processes(&self.cgroups.folders(), Some(root));
            (
                held::deleted_but_held(&processes),
                held::written(&processes),
            )
        });
        let written = self
            .folder
            .on_disk()
            .saturating_sub(self.baseline)
            .saturating_add(held)
            .max(written_by_processes);
        if written > self.sandbox.limits.disk_bytes {
            self.over_disk.store(true, Ordering::Relaxed);
        }
        self.over_disk.load(Ordering::Relaxed)
    }

    /// The limits the run reached, so far.
    pub fn limits_reached(&self) -> Vec<LimitReached> {
        let limits = self.sandbox.limits;
        let mut reached = Vec::new();
        if self.cgroups.memory_ran_out() {
            reached.push(LimitReached::Memory {
                bytes: limits.memory_bytes,
            });
        }
        if self.over_disk_limit(None) {
            reached.push(LimitReached::Disk {
                bytes: limits.disk_bytes,
            });
        }
        if self.cgroups.processes_refused() {
            reached.push(LimitReached::Processes {
                count: limits.processes,
            });
        }
        reached
    }
}

impl Drop for Run {
    fn drop(&mut self) {
        if self.over_disk.load(Ordering::Relaxed) {
            self.folder.remove_target();
        }
    }
}

/// A sandboxed command, and the files of its options and of its seccomp
/// program, which must stay open until it is spawned.
#[derive(Debug)]
pub struct Sandboxed {
    pub command: Command,
    _options: std::fs::File,
    _filters: Vec<std::fs::File>,
}

impl Sandboxed {
    /// The command, and what must live until it is spawned.
    pub fn into_parts(self) -> (Command, Box<dyn std::any::Any + Send>) {
        (self.command, Box::new((self._options, self._filters)))
    }
}

/// The type of `setrlimit`'s first argument, which glibc names.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
type Resource = libc::__rlimit_resource_t;
#[cfg(all(unix, not(all(target_os = "linux", target_env = "gnu"))))]
type Resource = libc::c_int;

#[cfg(unix)]
fn set_limit(resource: Resource, value: u64) -> std::io::Result<()> {
    set_limits(resource, value, value)
}

/// Sets the soft and the hard limit of `resource` (see [`set_limit`]).
#[cfg(unix)]
fn set_limits(resource: Resource, soft: u64, hard: u64) -> std::io::Result<()> {
    let limit = libc::rlimit {
        rlim_cur: soft as libc::rlim_t,
        rlim_max: hard as libc::rlim_t,
    };
    // SAFETY: a plain system call on a value on the stack.
    if unsafe { libc::setrlimit(resource, &limit) } == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

/// The grader's folder of notes on the workspaces' `target/` folders:
/// `$XDG_CACHE_HOME/raylab/built-targets`, else `~/.cache/...`, out of
/// every run's sight.
fn records_folder() -> Option<PathBuf> {
    let cache = std::env::var_os("XDG_CACHE_HOME")
        .filter(|folder| Path::new(folder).is_absolute())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|home| Path::new(&home).join(".cache")))?;
    Some(cache.join("raylab/built-targets"))
}

/// The name of the note on the workspace at `workspace` (absolute,
/// without links): a 64-bit FNV-1a hash of its path, in hexadecimal.
fn record_name(workspace: &Path) -> String {
    let hash = workspace
        .as_os_str()
        .as_encoded_bytes()
        .iter()
        .fold(0xcbf2_9ce4_8422_2325u64, |hash, &byte| {
            (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3)
        });
    format!("{hash:016x}")
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

/// The entries of `parent` named `PREFIX` + a pid + `-...` whose grader
/// is no longer running (ended by a signal before it could remove them):
/// the cgroups and run folders a later run tidies up.
fn abandoned_entries(parent: &Path, prefix: &str) -> Vec<std::fs::DirEntry> {
    let Ok(entries) = std::fs::read_dir(parent) else {
        return Vec::new();
    };
    entries
        .flatten()
        .filter(|entry| {
            let name = entry.file_name();
            let pid = name
                .to_str()
                .and_then(|name| name.strip_prefix(prefix))
                .and_then(|rest| rest.split('-').next())
                .filter(|pid| !pid.is_empty() && pid.bytes().all(|byte| byte.is_ascii_digit()));
            pid.is_some_and(|pid| {
                pid != std::process::id().to_string() && !Path::new("/proc").join(pid).exists()
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run of a fresh workspace in a sandbox of `limits`, if bubblewrap
    /// works here.
    fn run_of(limits: Limits) -> Option<(tempfile::TempDir, Run)> {
        let Ok(sandbox) = Sandbox::find(limits) else {
            eprintln!("skipped: no working bubblewrap here");
            return None;
        };
        let folder = tempfile::tempdir().expect("a folder");
        let workspace = folder.path().join("ann");
        std::fs::create_dir(&workspace).expect("mkdir");
        let run = sandbox.start(&workspace).expect("a run");
        Some((folder, run))
    }

    /// Where the machine lets raylab make a `pids` cgroup (root, as in CI),
    /// a run that starts 64 processes is stopped at its cap of 8, says
    /// so, and the cgroup is gone once the run is over.
    #[test]
    fn a_run_cannot_start_more_processes_than_its_cap() {
        let limits = Limits {
            processes: 8,
            ..Limits::DEFAULT
        };
        let Some((_folder, run)) = run_of(limits) else {
            return;
        };
        if !run.cgroups().caps_processes() {
            eprintln!("skipped: no pids cgroup can be made here (the resource limit applies)");
            return;
        }
        let folders: Vec<PathBuf> = run
            .cgroups()
            .folders()
            .into_iter()
            .map(Path::to_path_buf)
            .collect();
        let script = "i=0; while [ $i -lt 64 ]; do sleep 1 & i=$((i+1)); done; wait";
        let sandboxed = run
            .build_command("sh".as_ref(), &["-c".into(), script.into()], &[])
            .expect("a command");
        let ran = sandboxed
            .into_parts()
            .0
            .output()
            .expect("the sandbox starts");
        assert_eq!(
            run.limits_reached(),
            vec![LimitReached::Processes { count: 8 }],
            "{}",
            String::from_utf8_lossy(&ran.stderr)
        );
        drop(run);
        assert!(
            folders.iter().all(|folder| !folder.exists()),
            "{folders:?} left"
        );
    }

    /// bubblewrap builds the view on a folder in memory (its root), which
    /// the sandbox's user owns where it has a user namespace of its own
    /// (an ordinary user's grading): there a build could write up to half
    /// the machine's memory outside the folders the disk limit counts, and
    /// the answering processes, to have nothing writable, could write
    /// too. Only the run's folders are writable, and `/tmp` for the build.
    #[test]
    fn a_run_writes_only_to_its_own_folders() {
        let Ok(mut sandbox) = Sandbox::find(Limits::DEFAULT) else {
            eprintln!("skipped: no working bubblewrap here");
            return;
        };
        // As for an ordinary user: a user namespace, no switch to nobody.
        sandbox.run_as = None;
        let folder = tempfile::tempdir().expect("a folder");
        let workspace = folder.path().join("ann");
        std::fs::create_dir(&workspace).expect("mkdir");
        // What both run: the build as `sh serve`, the answers as
        // `/bin/sh serve` (the binary's one argument).
        let script = "for f in /x /etc/x /usr/x /dev/x /dev/shm/x /tmp/x; do \
                      (echo 1 > $f) 2>/dev/null && echo wrote $f; done; true";
        std::fs::write(workspace.join("serve"), script).expect("write");
        let run = sandbox.start(&workspace).expect("a run");
        let ran = |sandboxed: Sandboxed| {
            let out = sandboxed
                .into_parts()
                .0
                .output()
                .expect("the sandbox starts");
            String::from_utf8_lossy(&out.stdout).into_owned()
        };
        let built = ran(run
            .build_command("sh".as_ref(), &["serve".into()], &[])
            .expect("a command"));
        assert_eq!(built, "wrote /tmp/x\n");
        let answered = ran(run.serve_command(Path::new("/bin/sh")).expect("a command"));
        assert_eq!(answered, "");
    }

    /// A `target/` a vouched run left is built on only while the sources
    /// are the ones it built: sources changed since, even dated back to
    /// before that build, empty it (cargo would run the old binary).
    #[test]
    fn a_target_is_built_on_only_for_the_sources_it_was_built_from() {
        let Ok(mut sandbox) = Sandbox::find(Limits::DEFAULT) else {
            eprintln!("skipped: no working bubblewrap here");
            return;
        };
        let folder = tempfile::tempdir().expect("a folder");
        sandbox.records = Some(folder.path().join("records"));
        sandbox.trust_targets = false;
        let workspace = folder.path().join("ann");
        std::fs::create_dir_all(workspace.join("src")).expect("mkdir");
        let lib = workspace.join("src/lib.rs");
        std::fs::write(&lib, "pub fn answer() {}\n").expect("write");
        let built = workspace.join("target/built");
        let vouched_run = |make: bool| {
            let run = sandbox.start(&workspace).expect("a run");
            let kept = built.exists();
            if make {
                std::fs::write(&built, "a binary").expect("write");
            }
            run.vouch_for_build();
            kept
        };
        assert!(!vouched_run(true), "no note yet: an empty target/");
        assert!(vouched_run(false), "the same sources: built on");
        assert!(vouched_run(false), "still the same sources");
        let dated = std::fs::metadata(&lib)
            .and_then(|meta| meta.modified())
            .expect("a time");
        std::fs::write(&lib, "pub fn answer() { todo!() }\n").expect("write");
        std::fs::File::options()
            .write(true)
            .open(&lib)
            .and_then(|file| file.set_modified(dated))
            .expect("date");
        assert!(!vouched_run(false), "other sources: an empty target/");
    }

    /// A process that reaches the CPU time limit is said to have: the
    /// kernel's SIGKILL at a hard limit named nothing ("exited with status
    /// 137", as a process killed for any reason).
    #[test]
    fn a_process_ended_by_the_cpu_time_limit_is_said_to_be() {
        let limits = Limits {
            cpu_seconds: 1,
            ..Limits::DEFAULT
        };
        let Some((_folder, run)) = run_of(limits) else {
            return;
        };
        let sandboxed = run
            .build_command(
                "sh".as_ref(),
                &["-c".into(), "while :; do :; done".into()],
                &[],
            )
            .expect("a command");
        let status = sandboxed
            .into_parts()
            .0
            .status()
            .expect("the sandbox starts");
        let said = crate::check::remote::process_end(status);
        assert!(said.contains("the CPU time limit"), "{said}");
    }

    #[test]
    fn sizes_are_written_in_the_largest_whole_unit() {
        assert_eq!(bytes_text(8 << 30), "8 GiB");
        assert_eq!(bytes_text(768 << 20), "768 MiB");
        assert_eq!(bytes_text(1000), "1000 bytes");
    }
}
