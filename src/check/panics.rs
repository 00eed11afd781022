//! Running student code that may panic, without a backtrace on the screen.
//!
//! A chapter still written as `todo!()` panics with "not yet implemented":
//! that is "not started", not a crash, and the student must not see a
//! backtrace for it. [`guarded`] runs code under `catch_unwind` with the
//! panic hook silenced for the calling thread only, and records where the
//! panic happened: the file tells which chapter's function it was.
//!
//! The hook is process-wide, and several checks may run at once (the test
//! harness runs tests in parallel threads). So one hook is installed while
//! at least one [`guarded`] call is running, it stays quiet only on threads
//! that are inside [`guarded`], it hands every other panic to the hook that
//! was there before, and the last call out puts that hook back.

use std::cell::RefCell;
use std::panic::{AssertUnwindSafe, PanicHookInfo, catch_unwind};
use std::sync::Mutex;

type Hook = Box<dyn Fn(&PanicHookInfo<'_>) + Sync + Send + 'static>;

/// How many threads are inside [`guarded`], and the hook to restore.
struct Installed {
    users: usize,
    previous: Option<Hook>,
}

static INSTALLED: Mutex<Installed> = Mutex::new(Installed {
    users: 0,
    previous: None,
});

thread_local! {
    /// `Some` while this thread runs guarded code: the last panic seen.
    static CAPTURE: RefCell<Option<Option<Panic>>> = const { RefCell::new(None) };
}

/// The last panic of a thread outside [`guarded`] (a worker of rayon's,
/// whose panic rayon hands to the thread that started the loop): what a
/// guarded call reports when the panic it caught came from such a thread.
static FOREIGN: Mutex<Option<Panic>> = Mutex::new(None);

/// A panic caught in code under check.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Panic {
    pub message: String,
    /// `file:line`, when the panic said where it happened.
    pub location: Option<String>,
    /// The file alone, to attribute the panic to a chapter.
    pub file: Option<String>,
}

impl Panic {
    /// Whether this is `todo!()`: a function not written yet.
    pub fn is_todo(&self) -> bool {
        self.message.starts_with("not yet implemented")
    }
}

fn lock() -> std::sync::MutexGuard<'static, Installed> {
    // A panic while holding the lock cannot leave the counter half-updated
    // (every update is one statement), so a poisoned lock is still usable.
    INSTALLED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// The panic `info` describes.
fn panic_of(info: &PanicHookInfo<'_>) -> Panic {
    let payload = info.payload();
    let message = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "panic with a non-text payload".to_string());
    Panic {
        message,
        location: info
            .location()
            .map(|l| format!("{}:{}", l.file(), l.line())),
        file: info.location().map(|l| l.file().to_string()),
    }
}

fn quiet_hook(info: &PanicHookInfo<'_>) {
    let captured = CAPTURE.with(|capture| {
        let mut capture = capture.borrow_mut();
        match capture.as_mut() {
            Some(slot) => {
                *slot = Some(panic_of(info));
                true
            }
            None => false,
        }
    });
    if !captured {
        if let Ok(mut foreign) = FOREIGN.lock() {
            *foreign = Some(panic_of(info));
        }
        // Another thread's panic: it deserves the usual report.
        if let Some(previous) = lock().previous.as_ref() {
            previous(info);
        }
    }
}

/// Runs `f`, returning its result or the panic it raised (with its
/// message and location), printing nothing.
pub fn guarded<R>(f: impl FnOnce() -> R) -> Result<R, Panic> {
    {
        let mut installed = lock();
        if installed.users == 0 {
            installed.previous = Some(std::panic::take_hook());
            std::panic::set_hook(Box::new(quiet_hook));
        }
        installed.users += 1;
    }
    let outer = CAPTURE.with(|capture| capture.borrow_mut().replace(None));
    let result = catch_unwind(AssertUnwindSafe(f));
    let caught = CAPTURE.with(|capture| {
        let mut capture = capture.borrow_mut();
        let caught = capture.take().flatten();
        *capture = outer;
        caught
    });
    {
        let mut installed = lock();
        installed.users -= 1;
        if installed.users == 0
            && let Some(previous) = installed.previous.take()
        {
            std::panic::set_hook(previous);
        }
    }
    result.map_err(|_| {
        caught
            .or_else(|| FOREIGN.lock().ok().and_then(|mut foreign| foreign.take()))
            .unwrap_or_else(|| Panic {
                message: "panicked".into(),
                location: None,
                file: None,
            })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn todo_is_caught_with_its_location() {
        let caught = guarded(|| -> u32 { todo!() }).unwrap_err();
        assert!(caught.is_todo());
        assert!(caught.file.as_deref().unwrap_or("").ends_with("panics.rs"));
        assert_eq!(guarded(|| 7), Ok(7));
        let other = guarded(|| -> u32 { panic!("boom {}", 3) }).unwrap_err();
        assert_eq!(other.message, "boom 3");
        assert!(!other.is_todo());
    }
}
