//! The answer key's seal: in a student's run, raylab's own answers must not
//! stand in for the student's code.
//!
//! raylab carries the reference solution of every chapter: the defaults of
//! [`crate::course::Chapters`]' methods, the shapes' `intersect` methods,
//! chapter 3's loop behind [`crate::course::nearest_hit`] and the scene's
//! own Cauchy formula ([`crate::scene::Cauchy::index_at`], chapter 14's
//! `cauchy_ior`). Every public method that computes a chapter's answer
//! reports here. A student's
//! function that calls one of them (`sphere.intersect(...)`,
//! `Reference::intersect_sphere(...)`, an `impl Chapters` that keeps a
//! default) would otherwise pass every check without a line of its own.
//! The chapters' modules themselves are out of a workspace's reach at
//! compile time (the `student` feature, which `raylab new` turns on, makes
//! them private to raylab); what is left is reached through the trait and
//! those methods, and each of them reports here before it answers.
//!
//! In a student's build (the `student` feature) none of those answers is
//! there to run: each reports, then panics ([`left_out`]). The reports are
//! plain state of the student's own process, which safe code can rewrite
//! through a soundness hole of the compiler; what is not in the binary
//! cannot be run by any trick. raylab's own binary judges
//! ([`crate::check::own_binary`]); the reports still name, in its
//! verdict, the answer a chapter reached for.
//!
//! `seal` turns the reports on, once, in a student's binary. raylab's own
//! uses of its answers during a student's run (a tree compared with the
//! loop over every object, say) run inside `raylab_own` and are not
//! reported. Every report is kept: `recording` collects those made on its
//! thread while it runs (a chapter's check), `take_reported` the others
//! (a render's, from any thread).

use std::cell::{Cell, RefCell};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

static SEALED: AtomicBool = AtomicBool::new(false);

/// Answers reported outside any `recording` (a render's worker threads).
static REPORTED: Mutex<Vec<&'static str>> = Mutex::new(Vec::new());
/// How many times [`take_reported`] has emptied `REPORTED`.
static REPORTS_TAKEN: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

thread_local! {
    /// How deep this thread is inside `raylab_own`.
    static OWN_USE: Cell<u32> = const { Cell::new(0) };
    /// The answers this thread's `recording` has seen, when one runs.
    static RECORDING: RefCell<Option<Vec<&'static str>>> = const { RefCell::new(None) };
    /// The answers this thread has already put in `REPORTED`: an answer
    /// run in a render's inner loop (a dispersive index per wavelength)
    /// reports millions of times from every thread, and taking the lock
    /// each time kept the process in the kernel, fighting over it.
    /// (With the [`REPORTS_TAKEN`] count it was made under: a take empties
    /// `REPORTED`, and every thread's list with it.)
    static REPORTED_HERE: RefCell<(u64, Vec<&'static str>)> = const { RefCell::new((0, Vec::new())) };
}

/// From now on, in this process, every answer that runs outside
/// `raylab_own` is reported.
// Called by the command line, which the browser page's build leaves out.
#[cfg_attr(target_arch = "wasm32", allow(dead_code))]
pub(crate) fn seal() {
    SEALED.store(true, Ordering::SeqCst);
}

/// Whether `seal` was called.
pub fn sealed() -> bool {
    SEALED.load(Ordering::Relaxed)
}

/// What each of raylab's answers runs instead in a student's build:
/// the answer key is left out of the binary a student's code runs in, so
/// that no trick inside that process (a soundness hole of the compiler
/// that clears [`sealed`]'s flag, say) can reach it. `answer` names the
/// answer as a student would look for it. raylab's own binary, which
/// judges, has them all.
#[cold]
#[inline(never)]
#[track_caller]
pub fn left_out(answer: &'static str) -> ! {
    panic!(
        "{answer} is raylab's answer, which a student's build of raylab leaves out: \
         write your own (raylab judges with its own binary)"
    )
}

/// Whether comparison wrappers ([`crate::course::Textbook`]) report too:
/// set where no comparison was asked for (a check, a render with the
/// stable formulas), so that a student's code cannot reach raylab's
/// answers through them.
static STRICT: AtomicBool = AtomicBool::new(false);

/// Makes comparison wrappers report (`true`) or not.
#[cfg_attr(target_arch = "wasm32", allow(dead_code))]
pub(crate) fn set_strict(strict: bool) {
    STRICT.store(strict, Ordering::SeqCst);
}

/// Called first thing by each of raylab's answers; `answer` names it as a
/// student would look for it (`Chapters::intersect_sphere`,
/// `Sphere::intersect`). Unsealed, it costs one relaxed load.
///
/// Only a build with the `student` feature (a workspace's) can be sealed:
/// elsewhere this is empty, and raylab's own renders pay nothing per call.
#[inline(always)]
pub fn answered(answer: &'static str) {
    if cfg!(feature = "student") && SEALED.load(Ordering::Relaxed) {
        report(answer);
    }
}

/// [`answered`] for an answer that a comparison wrapper may run on purpose
/// (`comparison`): then it reports only in strict mode.
#[inline(always)]
pub fn answered_by(comparison: bool, answer: &'static str) {
    if cfg!(feature = "student")
        && SEALED.load(Ordering::Relaxed)
        && (!comparison || STRICT.load(Ordering::Relaxed))
    {
        report(answer);
    }
}

#[cold]
#[inline(never)]
fn report(answer: &'static str) {
    if OWN_USE.with(Cell::get) > 0 {
        return;
    }
    let recorded = RECORDING.with(|recording| match recording.borrow_mut().as_mut() {
        Some(answers) => {
            if !answers.contains(&answer) {
                answers.push(answer);
            }
            true
        }
        None => false,
    });
    if recorded {
        return;
    }
    let taken = REPORTS_TAKEN.load(Ordering::Acquire);
    let reported_here = REPORTED_HERE.with(|here| {
        let (since, answers) = &*here.borrow();
        *since == taken && answers.contains(&answer)
    });
    if !reported_here && let Ok(mut reported) = REPORTED.lock() {
        if !reported.contains(&answer) {
            reported.push(answer);
        }
        REPORTED_HERE.with(|here| {
            let (since, answers) = &mut *here.borrow_mut();
            if *since != taken {
                *since = taken;
                answers.clear();
            }
            answers.push(answer);
        });
    }
}

/// Runs `work`, raylab's own use of its answers, without reporting them.
pub(crate) fn raylab_own<T>(work: impl FnOnce() -> T) -> T {
    struct Leave;
    impl Drop for Leave {
        fn drop(&mut self) {
            OWN_USE.with(|depth| depth.set(depth.get().saturating_sub(1)));
        }
    }
    OWN_USE.with(|depth| depth.set(depth.get() + 1));
    let _leave = Leave;
    work()
}

/// Whether this thread is inside [`raylab_own`]: work it hands to other
/// threads (a stage's light paths, on rayon's) carries that with it
/// through [`own_if`].
pub(crate) fn inside_own() -> bool {
    OWN_USE.with(Cell::get) > 0
}

/// Runs `work` as raylab's own when `own` (what [`inside_own`] said on the
/// thread that handed the work over), as it is otherwise.
pub(crate) fn own_if<T>(own: bool, work: impl FnOnce() -> T) -> T {
    if own { raylab_own(work) } else { work() }
}

/// Runs `work` and returns the answers it reported on this thread, in the
/// order first met (nothing unless sealed).
pub(crate) fn recording<T>(work: impl FnOnce() -> T) -> (T, Vec<&'static str>) {
    struct Stop(Option<Vec<&'static str>>);
    impl Drop for Stop {
        fn drop(&mut self) {
            let outer = self.0.take();
            RECORDING.with(|recording| *recording.borrow_mut() = outer);
        }
    }
    let outer = RECORDING.with(|recording| recording.borrow_mut().replace(Vec::new()));
    let stop = Stop(outer);
    let result = work();
    let answers = RECORDING.with(|recording| recording.borrow_mut().take().unwrap_or_default());
    drop(stop);
    (result, answers)
}

/// The answers reported outside any recording since the last call.
pub(crate) fn take_reported() -> Vec<&'static str> {
    REPORTED
        .lock()
        .map(|mut reported| {
            REPORTS_TAKEN.fetch_add(1, Ordering::AcqRel);
            std::mem::take(&mut *reported)
        })
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reports_are_kept_by_the_recording_and_skipped_for_raylab_own() {
        seal();
        // `report` is what `answered` calls once sealed in a student build.
        let ((), answers) = recording(|| {
            report("intersect_sphere");
            raylab_own(|| report("nearest_hit"));
            report("intersect_sphere");
        });
        assert_eq!(answers, ["intersect_sphere"]);
    }

    #[test]
    fn an_answer_reported_again_after_a_take_is_reported_again() {
        // A serve process takes the reports after each question: the next
        // question's use of the same answer must be seen too, whatever
        // this thread remembers having reported.
        let answer = "answer_key::tests::reported_again";
        let present = || {
            REPORTED
                .lock()
                .map(|reported| reported.contains(&answer))
                .unwrap_or(false)
        };
        // Another test's take may fall between a report and the look: a
        // few tries tell that from a report that never lands.
        let lands = || {
            (0..3).any(|_| {
                report(answer);
                present()
            })
        };
        assert!(lands(), "the first report");
        let _ = take_reported();
        assert!(lands(), "the report after a take");
    }
}
