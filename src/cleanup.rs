//! Removing raylab's temporary files when the process is interrupted.
//!
//! Outputs are written to a temporary file (`.raylab-XXXXXX.tmp`) that is
//! renamed over the output once complete (see [`crate::output`]), so an
//! interrupted write never damages the old file. Without this module, a
//! Ctrl-C or a `kill` in the middle of a write left the temporary file
//! behind. [`install_signal_handlers`] (called by the `raylab` binary)
//! makes every signal whose default action ends a process (SIGINT,
//! SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGXFSZ, SIGVTALRM, SIGTRAP, the
//! real-time signals, ...) remove every live temporary file, then end the
//! process: with the conventional status 128 + the signal (130, 143, 129,
//! ...), or by the signal itself for a closed pipe and a fault.
//!
//! A signal handler may only call async-signal-safe functions: no lock, no
//! allocation. So the live paths sit in a fixed table of atomic pointers to
//! C strings; the handler reads them and calls `unlink`, then `_exit`.
//! Between the creation of a temporary file and its registration there are
//! a few instructions where a signal would still leave it behind.

use std::ffi::CString;
use std::path::Path;
#[cfg(unix)]
use std::sync::atomic::{AtomicI32, AtomicUsize};
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

/// Registers a temporary file to be removed on any signal that ends the
/// process (see [`install_signal_handlers`]).
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

/// The action each fault signal had before [`install_signal_handlers`]
/// (the handler's address and flags, by signal number), to hand a fault
/// back to: the standard library's stack-overflow report on SIGSEGV and
/// SIGBUS, the default action elsewhere.
#[cfg(unix)]
static PREVIOUS_HANDLER: [AtomicUsize; MAX_SIGNAL] = [const { AtomicUsize::new(0) }; MAX_SIGNAL];
#[cfg(unix)]
static PREVIOUS_FLAGS: [AtomicI32; MAX_SIGNAL] = [const { AtomicI32::new(0) }; MAX_SIGNAL];

/// Above every signal number of the systems raylab runs on (Linux's
/// real-time signals end at 64, or 127 on MIPS).
#[cfg(unix)]
const MAX_SIGNAL: usize = 129;

/// The signals whose default action also dumps core because the program
/// itself went wrong: a bad memory access, instruction or division, a
/// breakpoint, a refused system call, `abort`.
#[cfg(unix)]
fn is_fault(signal: libc::c_int) -> bool {
    [
        libc::SIGSEGV,
        libc::SIGBUS,
        libc::SIGILL,
        libc::SIGFPE,
        libc::SIGTRAP,
        libc::SIGSYS,
        libc::SIGABRT,
    ]
    .contains(&signal)
}

/// Gives `signal` its default action and delivers it again: the process
/// ends by the signal itself.
#[cfg(unix)]
fn end_by(signal: libc::c_int) {
    // SAFETY: `signal`, `sigprocmask` and `raise` are async-signal-safe;
    // the signal is blocked while its handler runs, so it is unblocked
    // first, and its default action then ends the process.
    unsafe {
        libc::signal(signal, libc::SIG_DFL);
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        libc::sigaddset(&mut set, signal);
        libc::sigprocmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut());
        libc::raise(signal);
    }
}

#[cfg(unix)]
extern "C" fn on_signal(
    signal: libc::c_int,
    info: *mut libc::siginfo_t,
    _context: *mut libc::c_void,
) {
    if !is_fault(signal) && COMMITTING.load(Ordering::SeqCst) {
        // Held until the set of outputs is renamed (`while_committing`).
        let _ = PENDING.compare_exchange(0, signal, Ordering::SeqCst, Ordering::SeqCst);
        return;
    }
    remove_live_files();
    if signal == libc::SIGPIPE {
        // A closed pipe ends a command-line tool quietly, by the signal
        // itself (as `cat` or `ls`): the shell sees no error message.
        end_by(signal);
    }
    if is_fault(signal) {
        // SAFETY: the kernel passes a valid `siginfo_t` to a handler
        // installed with SA_SIGINFO.
        let from_the_kernel = !info.is_null() && unsafe { (*info).si_code } > 0;
        let index = signal as usize;
        let previous = PREVIOUS_HANDLER
            .get(index)
            .map_or(libc::SIG_DFL, |handler| handler.load(Ordering::Acquire));
        if from_the_kernel && previous != libc::SIG_DFL && previous != libc::SIG_IGN {
            // A real fault: hand it back to the handler that was there
            // before (the standard library's, which reports a stack
            // overflow). Returning runs the faulting instruction again,
            // and it meets that handler.
            let flags = PREVIOUS_FLAGS
                .get(index)
                .map_or(0, |flags| flags.load(Ordering::Acquire));
            // SAFETY: sigaction is async-signal-safe; the struct is zeroed,
            // then filled with what the earlier sigaction call returned.
            unsafe {
                let mut action: libc::sigaction = std::mem::zeroed();
                action.sa_sigaction = previous;
                action.sa_flags = flags;
                libc::sigemptyset(&mut action.sa_mask);
                libc::sigaction(signal, &action, std::ptr::null_mut());
            }
            return;
        }
        // Sent by a process (`kill`, `abort`), or a fault with no handler
        // before: it ends the process as a crash, core file and all, as
        // it would have without raylab.
        end_by(signal);
    }
    // SAFETY: `_exit` is async-signal-safe; it skips destructors and
    // buffered output on purpose (the work is abandoned).
    unsafe { libc::_exit(128 + signal) }
}

/// Every signal whose default action ends the process: on Linux, every
/// signal from 1 to the last real-time one but those whose default is to
/// be ignored (SIGCHLD, SIGCONT, SIGURG, SIGWINCH) or to stop (SIGSTOP,
/// SIGTSTP, SIGTTIN, SIGTTOU), SIGKILL (which no handler can catch) and
/// the real-time signals the C library keeps for its threads (below
/// `SIGRTMIN()`); elsewhere, the ones POSIX defines.
#[cfg(unix)]
fn terminating_signals() -> Vec<libc::c_int> {
    #[cfg(any(target_os = "linux", target_os = "android"))]
    {
        let not_ending = [
            libc::SIGKILL,
            libc::SIGCHLD,
            libc::SIGCONT,
            libc::SIGURG,
            libc::SIGWINCH,
            libc::SIGSTOP,
            libc::SIGTSTP,
            libc::SIGTTIN,
            libc::SIGTTOU,
        ];
        // The signals below 32 are the classic ones; 32 and up are
        // real-time signals.
        (1..=libc::SIGRTMAX())
            .filter(|signal| !not_ending.contains(signal))
            .filter(|&signal| signal < 32 || signal >= libc::SIGRTMIN())
            .collect()
    }
    #[cfg(not(any(target_os = "linux", target_os = "android")))]
    {
        vec![
            libc::SIGHUP,
            libc::SIGINT,
            libc::SIGQUIT,
            libc::SIGILL,
            libc::SIGTRAP,
            libc::SIGABRT,
            libc::SIGBUS,
            libc::SIGFPE,
            libc::SIGUSR1,
            libc::SIGSEGV,
            libc::SIGUSR2,
            libc::SIGPIPE,
            libc::SIGALRM,
            libc::SIGTERM,
            libc::SIGXCPU,
            libc::SIGXFSZ,
            libc::SIGVTALRM,
            libc::SIGPROF,
            libc::SIGSYS,
        ]
    }
}

/// Makes every signal whose default action ends the process (see
/// `terminating_signals`: SIGINT, SIGTERM, SIGHUP, a closed pipe, a
/// file-size or CPU limit, the timers SIGALRM, SIGVTALRM and SIGPROF, a
/// fault sent by `kill`, the real-time signals, ...) remove the live
/// temporary files first. Then a fault (SIGSEGV, SIGBUS, SIGILL, SIGFPE,
/// SIGTRAP, SIGSYS, SIGABRT) ends the process as it would have without
/// raylab (a real fault goes on to the handler that was there, the
/// standard library's stack-overflow report; a sent one ends by the
/// signal), a closed pipe ends it by SIGPIPE quietly, and any other signal
/// exits with status 128 + the signal. A signal the parent set to be
/// ignored (`nohup`) stays ignored. Call once, before any thread starts.
pub fn install_signal_handlers() {
    #[cfg(unix)]
    for signal in terminating_signals() {
        // SAFETY: sigaction with a zeroed, then filled, struct; the handler
        // only touches atomics and async-signal-safe functions.
        unsafe {
            let mut old: libc::sigaction = std::mem::zeroed();
            if libc::sigaction(signal, std::ptr::null(), &mut old) != 0
                || old.sa_sigaction == libc::SIG_IGN
            {
                continue;
            }
            if let (Some(handler), Some(flags)) = (
                PREVIOUS_HANDLER.get(signal as usize),
                PREVIOUS_FLAGS.get(signal as usize),
            ) {
                handler.store(old.sa_sigaction, Ordering::Release);
                flags.store(old.sa_flags, Ordering::Release);
            }
            let mut action: libc::sigaction = std::mem::zeroed();
            action.sa_sigaction = on_signal
                as extern "C" fn(libc::c_int, *mut libc::siginfo_t, *mut libc::c_void)
                as usize;
            // SA_ONSTACK: a stack overflow's SIGSEGV can only be handled on
            // the thread's alternate stack (the standard library sets one).
            action.sa_flags = libc::SA_SIGINFO | libc::SA_ONSTACK;
            libc::sigemptyset(&mut action.sa_mask);
            libc::sigaction(signal, &action, std::ptr::null_mut());
        }
    }
}

/// Whether a set of outputs is being renamed into place now.
static COMMITTING: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// A signal that arrived while a set of outputs was renamed, handled once
/// the set is complete; 0 for none.
#[cfg(unix)]
static PENDING: AtomicI32 = AtomicI32::new(0);

/// Runs `renames` (the renames of a set of outputs written together) with
/// signals held: a signal that would end the process waits until every
/// rename is done, so that an interruption leaves all the old files or all
/// the new ones, never some of each. The renames take microseconds; a
/// fault is never held.
pub fn while_committing<T>(renames: impl FnOnce() -> T) -> T {
    COMMITTING.store(true, Ordering::SeqCst);
    let done = renames();
    COMMITTING.store(false, Ordering::SeqCst);
    #[cfg(unix)]
    {
        let signal = PENDING.swap(0, Ordering::SeqCst);
        if signal != 0 {
            remove_live_files();
            if signal == libc::SIGPIPE {
                end_by(signal);
            }
            // SAFETY: `_exit` ends the process at once, as the handler
            // would have.
            unsafe { libc::_exit(128 + signal) }
        }
    }
    done
}

/// Test hook, for the CLI tests only: with
/// `RAYLAB_TEST_PAUSE_BETWEEN_RENAMES` set, a command stops after the first
/// rename of a set of outputs, says so on stderr and waits (at most a
/// minute, or until a signal is held) so that a test can send it a signal
/// at exactly that moment. Not a user feature.
pub fn test_pause_between_renames() {
    if std::env::var_os("RAYLAB_TEST_PAUSE_BETWEEN_RENAMES").is_none() {
        return;
    }
    eprintln!("raylab test hook: first output renamed, pausing");
    let start = std::time::Instant::now();
    while start.elapsed() < std::time::Duration::from_secs(60) {
        #[cfg(unix)]
        if PENDING.load(Ordering::SeqCst) != 0 {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
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
