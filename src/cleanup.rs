//! Removing raylab's temporary files when the process is interrupted.
//!
//! Outputs are written to a temporary file (`.raylab-XXXXXX.tmp`) that is
//! renamed over the output once complete (see [`crate::output`]), so an
//! interrupted write never damages the old file. Without this module, a
//! Ctrl-C or a `kill` in the middle of a write left the temporary file
//! behind. [`install_signal_handlers`] (called by the `raylab` binary)
//! makes the signals that end a process (SIGINT, SIGTERM, SIGHUP, SIGQUIT,
//! SIGPIPE, SIGXFSZ, ...) remove every live temporary file, then exit with
//! the conventional status 128 + the signal (130, 143, 129, ...).
//!
//! A signal handler may only call async-signal-safe functions: no lock, no
//! allocation. So the live paths sit in a fixed table of atomic pointers to
//! C strings; the handler reads them and calls `unlink`, then `_exit`.
//! Between the creation of a temporary file and its registration there are
//! a few instructions where a signal would still leave it behind.

use std::ffi::CString;
use std::path::Path;
use std::sync::atomic::{AtomicPtr, Ordering};

/// How many temporary files can be registered at once (a command writes at
/// most three outputs together).
const SLOTS: usize = 32;

static LIVE: [AtomicPtr<std::ffi::c_char>; SLOTS] =
    [const { AtomicPtr::new(std::ptr::null_mut()) }; SLOTS];

/// A registered temporary path; dropping it unregisters the path (drop it
/// once the file has been renamed or removed).
#[derive(Debug)]
pub struct Registered {
    slot: Option<usize>,
}

/// Registers a temporary file to be removed on SIGINT, SIGTERM or SIGHUP.
pub fn register(path: &Path) -> Registered {
    let Some(name) = c_path(path) else {
        return Registered { slot: None };
    };
    let pointer = name.into_raw();
    for (index, slot) in LIVE.iter().enumerate() {
        if slot
            .compare_exchange(
                std::ptr::null_mut(),
                pointer,
                Ordering::AcqRel,
                Ordering::Acquire,
            )
            .is_ok()
        {
            return Registered { slot: Some(index) };
        }
    }
    // Every slot taken: the file is still removed on success or error, only
    // not on a signal.
    // SAFETY: `pointer` came from `into_raw` above and was never shared.
    drop(unsafe { CString::from_raw(pointer) });
    Registered { slot: None }
}

impl Drop for Registered {
    fn drop(&mut self) {
        if let Some(index) = self.slot {
            // The string is leaked, not freed: a handler running on another
            // thread may be reading it right now. A few bytes per output.
            LIVE[index].store(std::ptr::null_mut(), Ordering::Release);
        }
    }
}

/// The paths registered now (for tests).
pub fn live_paths() -> Vec<std::path::PathBuf> {
    LIVE.iter()
        .filter_map(|slot| {
            let pointer = slot.load(Ordering::Acquire);
            // SAFETY: a non-null pointer in the table is a leaked, never
            // freed, NUL-terminated string.
            (!pointer.is_null()).then(|| {
                let bytes = unsafe { std::ffi::CStr::from_ptr(pointer) }.to_bytes();
                path_from_bytes(bytes)
            })
        })
        .collect()
}

/// Removes every registered temporary file (what the signal handler does).
#[cfg(unix)]
fn remove_live_files() {
    for slot in &LIVE {
        let pointer = slot.load(Ordering::Acquire);
        if !pointer.is_null() {
            // SAFETY: a NUL-terminated string that is never freed; `unlink`
            // is async-signal-safe.
            unsafe {
                libc::unlink(pointer);
            }
        }
    }
}

#[cfg(unix)]
fn c_path(path: &Path) -> Option<CString> {
    use std::os::unix::ffi::OsStrExt;
    CString::new(path.as_os_str().as_bytes()).ok()
}

#[cfg(not(unix))]
fn c_path(path: &Path) -> Option<CString> {
    CString::new(path.to_str()?).ok()
}

#[cfg(unix)]
fn path_from_bytes(bytes: &[u8]) -> std::path::PathBuf {
    use std::os::unix::ffi::OsStrExt;
    std::ffi::OsStr::from_bytes(bytes).into()
}

#[cfg(not(unix))]
fn path_from_bytes(bytes: &[u8]) -> std::path::PathBuf {
    String::from_utf8_lossy(bytes).into_owned().into()
}

#[cfg(unix)]
extern "C" fn on_signal(signal: libc::c_int) {
    remove_live_files();
    if signal == libc::SIGPIPE {
        // A closed pipe ends a command-line tool quietly, by the signal
        // itself (as `cat` or `ls`): the shell sees no error message.
        // SAFETY: `signal`, `sigprocmask` and `raise` are async-signal-safe;
        // the signal is blocked while its handler runs, so it is unblocked
        // first, and its default action then ends the process.
        unsafe {
            libc::signal(libc::SIGPIPE, libc::SIG_DFL);
            let mut set: libc::sigset_t = std::mem::zeroed();
            libc::sigemptyset(&mut set);
            libc::sigaddset(&mut set, libc::SIGPIPE);
            libc::sigprocmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut());
            libc::raise(libc::SIGPIPE);
        }
    }
    // SAFETY: `_exit` is async-signal-safe; it skips destructors and
    // buffered output on purpose (the work is abandoned).
    unsafe { libc::_exit(128 + signal) }
}

/// Makes every signal whose default action ends the process and that a
/// user, a shell or the kernel sends to a command (SIGINT, SIGTERM, SIGHUP,
/// SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGPIPE, SIGXFSZ and SIGXCPU: a
/// closed pipe, a file-size or CPU limit) remove the live temporary files
/// and exit with status 128 + the signal (SIGPIPE: end by the signal, as
/// a closed pipe ends any tool). A signal the parent set to be
/// ignored (`nohup`) stays ignored. Call once, before any thread starts.
pub fn install_signal_handlers() {
    #[cfg(unix)]
    for signal in [
        libc::SIGINT,
        libc::SIGTERM,
        libc::SIGHUP,
        libc::SIGQUIT,
        libc::SIGUSR1,
        libc::SIGUSR2,
        libc::SIGALRM,
        libc::SIGPIPE,
        libc::SIGXFSZ,
        libc::SIGXCPU,
    ] {
        // SAFETY: sigaction with a zeroed, then filled, struct; the handler
        // only touches atomics and async-signal-safe functions.
        unsafe {
            let mut old: libc::sigaction = std::mem::zeroed();
            if libc::sigaction(signal, std::ptr::null(), &mut old) != 0
                || old.sa_sigaction == libc::SIG_IGN
            {
                continue;
            }
            let mut action: libc::sigaction = std::mem::zeroed();
            action.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as usize;
            libc::sigemptyset(&mut action.sa_mask);
            libc::sigaction(signal, &action, std::ptr::null_mut());
        }
    }
}

/// Test hook, for the CLI tests only: with `RAYLAB_TEST_PAUSE_BEFORE_RENAME`
/// set, a command stops once its temporary files are written, says so on
/// stderr and waits (at most a minute) so that a test can send it a signal
/// at exactly that moment. Not a user feature.
pub fn test_pause_before_rename() {
    if std::env::var_os("RAYLAB_TEST_PAUSE_BEFORE_RENAME").is_none() {
        return;
    }
    eprintln!("raylab test hook: temporary files written, pausing");
    std::thread::sleep(std::time::Duration::from_secs(60));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn registration_lasts_until_dropped() {
        // Removal itself is tested on the binary (tests/cli/cli.rs): calling it
        // here would remove the temporary files of tests running alongside.
        let path = std::env::temp_dir().join(".raylab-registry-test.tmp");
        let registration = register(&path);
        assert!(registration.slot.is_some());
        assert!(live_paths().contains(&path));
        drop(registration);
        assert!(!live_paths().contains(&path));
    }
}
