//! Planted bugs that share one renderer.
//!
//! A variant of the reference (a bug in a gallery, an alternative the lesson
//! allows) overrides a few of [`Chapters`]' functions. Written as a type
//! implementing `Chapters`, each variant would be a new instantiation of the
//! whole renderer and judge: a few hundred of them cost the test build ten
//! times its time (docs/course.md). Here a variant is a table of the
//! functions it overrides ([`Plants`]); [`Planted`] is one `Chapters` that
//! answers every call from the table installed for the running check, and
//! from the reference where the table has no entry. So a variant costs the
//! compiler only its own functions.
//!
//! A variant's functions call the others through `Planted::` (what `Self::`
//! meant in a type of its own), so an override reaches every caller, as
//! one method of a `Chapters` impl does.
//!
//! One table is installed at a time, for the whole process: [`with`] holds
//! a lock while it runs, so checks of planted variants run one by one even
//! when the test harness runs tests on several threads (the judge's worker
//! threads see the same table).

use std::sync::Mutex;
use std::sync::atomic::{AtomicPtr, Ordering};

use crate::bsdf::{Dispersed, Lobe};
use crate::bvh::{Aabb, Boxes4, Bvh, BvhOptions, Triangles4, WideBvh};
use crate::check::{ChapterVerdict, CheckOptions, CheckReport};
use crate::course::{Chapters, Hit, HitPoint, Objects, PhongTerms};
use crate::medium::{Crossing, MediumStack};
use crate::render::Tracer;
use crate::scene::Cauchy;
use crate::shapes::{Bracket, Implicit, Plane, Shape, Sphere, SurfacePoint, Triangle};
use crate::{Material, Ray, Sampling, Vec3, Vec4};

/// A variant of the reference: the functions it plants.
pub trait Plant {
    /// The variant's table; every function it leaves `None` is the
    /// reference's.
    fn plants() -> Plants;
}

/// The reference is the variant that plants nothing.
impl Plant for crate::Reference {
    fn plants() -> Plants {
        Plants::default()
    }
}

/// The chapters that answer from the table [`with`] installed.
pub struct Planted;

static INSTALLED: AtomicPtr<Plants> = AtomicPtr::new(std::ptr::null_mut());
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

thread_local! {
    /// Whether this thread holds [`ONE_AT_A_TIME`]: a variant's function
    /// called inside another's [`with`] plants its own table for the call.
    static HOLDING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `body` with `P`'s functions planted in [`Planted`].
pub fn with<P: Plant, R>(body: impl FnOnce() -> R) -> R {
    with_table(P::plants(), body)
}

/// Runs `body` with the functions of `plants` planted in [`Planted`].
pub fn with_table<R>(plants: Plants, body: impl FnOnce() -> R) -> R {
    let turn = if HOLDING.get() {
        None
    } else {
        let turn = ONE_AT_A_TIME
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        HOLDING.set(true);
        Some(turn)
    };
    // Leaked, not freed: a worker thread the judge gave up on may still be
    // reading it after the check returns.
    let table: &'static mut Plants = Box::leak(Box::new(plants));
    let before = INSTALLED.swap(table, Ordering::AcqRel);
    struct Restore {
        before: *mut Plants,
        outermost: bool,
    }
    impl Drop for Restore {
        fn drop(&mut self) {
            INSTALLED.store(self.before, Ordering::Release);
            if self.outermost {
                HOLDING.set(false);
            }
        }
    }
    // Declared after `turn`, so dropped before the lock is released.
    let _restore = Restore {
        before,
        outermost: turn.is_some(),
    };
    body()
}

/// [`crate::check::check_chapter`] of the variant `P`. The chapters before
/// the first one whose function `P` plants are the reference's, whose
/// checkpoints pass and call no later chapter's function
/// (`a_chapters_checkpoints_call_no_later_chapters_function`, in
/// `check::judge`): they are
/// taken as passing, not asked again for every variant.
pub fn check_chapter<P: Plant>(chapter: u8, options: &CheckOptions) -> ChapterVerdict {
    let plants = P::plants();
    let unchanged = plants
        .first_planted_chapter()
        .unwrap_or(chapter)
        .min(chapter)
        .saturating_sub(1);
    let options = CheckOptions {
        earlier_known_to_pass: options.earlier_known_to_pass.max(unchanged),
        ..options.clone()
    };
    with_table(plants, || {
        crate::check::check_chapter::<Planted>(chapter, &options)
    })
}

/// The chapter whose student writes `function`; one no chapter lists
/// counts as chapter 1's, the earliest.
fn chapter_of(function: &str) -> u8 {
    crate::chapters::CHAPTERS
        .iter()
        .find(|info| info.functions.contains(&function))
        .map_or(1, |info| info.number)
}

/// [`crate::check::check_all`] of the variant `P`.
pub fn check_all<P: Plant>(chapters: Option<u8>, options: &CheckOptions) -> CheckReport {
    with::<P, _>(|| crate::check::check_all::<Planted>(chapters, options))
}

thread_local! {
    /// The table of the variant whose own function this thread is running
    /// (`SomeVariant::hit_box(...)`, called by a test or by another
    /// variant): authoritative while set, so the call is the variant's
    /// whatever another test's check has installed.
    static CALLING: std::cell::Cell<*const Plants> = const { std::cell::Cell::new(std::ptr::null()) };
}

/// Runs `body`, on this thread only, with `P`'s functions planted: what a
/// call of a variant's own function does. No lock: a variant's function
/// called by another's, on a worker thread of a check, must not wait for
/// the check to end.
pub fn calling<P: Plant, R>(body: impl FnOnce() -> R) -> R {
    // On the stack: only this thread reads it, and only until `body`
    // returns (a variant's function may be called once a ray).
    let table = P::plants();
    let before = CALLING.replace(&table);
    struct Restore(*const Plants);
    impl Drop for Restore {
        fn drop(&mut self) {
            CALLING.set(self.0);
        }
    }
    let _restore = Restore(before);
    body()
}

/// Checks chapter `chapter` with the variant `P` and panics unless it
/// fails on the checkpoint `case`, its hint naming the lesson, with no
/// earlier chapter to blame: how a gallery shows that a case catches the
/// bug it was written for.
pub fn assert_caught<P: Plant>(chapter: u8, case: &str, options: &CheckOptions) -> ChapterVerdict {
    // The first failing checkpoint is all this asserts: the ones after it
    // would cost the statistical cases' time for nothing.
    let options = CheckOptions {
        first_failure_only: true,
        ..options.clone()
    };
    let verdict = check_chapter::<P>(chapter, &options);
    let text = verdict.text();
    assert_eq!(verdict.status, crate::check::Status::Fail, "{text}");
    assert_eq!(verdict.failing_case(), Some(case), "{text}");
    assert!(text.contains("hint:     read "), "{text}");
    assert!(text.contains("lesson.md"), "{text}");
    assert_eq!(verdict.needs, None, "{text}");
    verdict
}

/// Checks chapter `chapter` with the variant `P` and panics unless it
/// passes every checkpoint and its image but fails the hard case `case`
/// first: correct, not yet robust.
pub fn assert_caught_by_hard_case<P: Plant>(chapter: u8, case: &str, options: &CheckOptions) {
    let verdict = check_chapter::<P>(chapter, options);
    let text = verdict.text();
    assert!(verdict.passes(), "{text}");
    let robustness = verdict.robustness.as_ref().expect("level 2 ran");
    let first = robustness
        .first_failure
        .as_ref()
        .map(|failure| failure.name);
    assert_eq!(first, Some(case), "{text}");
}

fn installed() -> Option<&'static Plants> {
    let calling = CALLING.get();
    let table = if calling.is_null() {
        INSTALLED.load(Ordering::Acquire).cast_const()
    } else {
        calling
    };
    // SAFETY: `with` installs only tables it leaked, never freed; `calling`
    // sets this thread's table only while the table lives, and every
    // caller copies a function pointer out at once.
    unsafe { table.as_ref() }
}

/// The table of planted functions and the `Chapters` that answers from
/// it, made from the course's list of functions
/// ([`crate::course::for_each_course_function`]).
macro_rules! plants {
    ($chapters:ty; $(
        $(#[$doc:meta])*
        $module:ident fn $name:ident $(<$lifetime:lifetime>)? ($($argument:ident: $type:ty),* $(,)?)
            $(-> $answer:ty)? $([$($marker:ident)*])?
            $({ textbook if $flag:ident => $text_module:ident :: $text_function:ident })?;
    )*) => {
        #[derive(Clone, Copy, Default)]
        pub struct Plants {
            $(pub $name: Option<for<$($lifetime)?> fn($($type),*) $(-> $answer)?>,)*
        }

        impl Plants {
            /// Every function `todo!()`: a workspace where nothing is
            /// written yet.
            pub fn nothing_written() -> Plants {
                Plants {
                    $($name: Some({
                        fn not_written $(<$lifetime>)? ($(_: $type),*) $(-> $answer)? {
                            todo!()
                        }
                        not_written
                    }),)*
                }
            }

            /// The earliest chapter one of whose functions is planted;
            /// `None` for the reference.
            pub fn first_planted_chapter(&self) -> Option<u8> {
                [$(self.$name.is_some().then(|| chapter_of(stringify!($name))),)*]
                    .into_iter()
                    .flatten()
                    .min()
            }

            /// This table with the functions of chapters 1 to `chapter`
            /// back to the reference's.
            pub fn after(mut self, chapter: u8) -> Plants {
                $(if chapter_of(stringify!($name)) <= chapter {
                    self.$name = None;
                })*
                self
            }
        }

        impl Chapters for Planted {
            $(
                #[inline]
                fn $name $(<$lifetime>)? ($($argument: $type),*) $(-> $answer)? {
                    match installed().and_then(|table| table.$name) {
                        Some(planted) => planted($($argument),*),
                        None => {
                            crate::answer_key::answered_by(
                                false,
                                concat!("Chapters::", stringify!($name)),
                            );
                            crate::course::reference_call!(
                                Planted,
                                $module::$name,
                                [$($($marker)*)?],
                                ($($argument),*)
                            )
                        }
                    }
                }
            )*
        }
    };
}

crate::course::for_each_course_function!(plants, Planted);

/// A variant, written as the methods of a `Chapters` impl would be (with
/// `Planted` where they said `Self`):
///
/// ```ignore
/// plant! {
///     NoRefraction;
///     fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> { None }
/// }
/// ```
///
/// Each function is also the variant's own, `NoRefraction::refract(...)`,
/// which runs with the variant planted on the calling thread ([`calling`]).
#[macro_export]
#[doc(hidden)]
macro_rules! plant {
    (
        $variant:ident;
        $(
            $(#[$meta:meta])*
            fn $name:ident $(<$lifetime:lifetime>)? ($($argument:ident: $type:ty),* $(,)?)
                $(-> $answer:ty)? $body:block
        )*
    ) => {
        impl $crate::check::planted::Plant for $variant {
            fn plants() -> $crate::check::planted::Plants {
                // Each function in a block of its own, so that its body
                // still reaches the reference's function of the same name.
                // A variant may plant every function (a workspace with
                // nothing written).
                #[allow(clippy::needless_update)]
                $crate::check::planted::Plants {
                    $($name: Some({
                        $(#[$meta])*
                        fn planted $(<$lifetime>)? ($($argument: $type),*) $(-> $answer)? $body
                        planted
                    }),)*
                    ..Default::default()
                }
            }
        }

        #[allow(dead_code)]
        impl $variant {
            $(
                fn $name $(<$lifetime>)? ($($argument: $type),*) $(-> $answer)? {
                    $crate::check::planted::calling::<$variant, _>(|| {
                        <$crate::check::planted::Planted as $crate::course::Chapters>::$name(
                            $($argument),*
                        )
                    })
                }
            )*
        }
    };
}

pub use crate::plant;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Reference;

    struct NoSphere;
    plant! {
        NoSphere;
        fn intersect_sphere(_sphere: &Sphere, _ray: &Ray, _t_min: f32, _t_max: f32) -> Option<f32> {
            None
        }
    }

    struct SphereAtOne;
    plant! {
        SphereAtOne;
        fn intersect_sphere(_sphere: &Sphere, _ray: &Ray, _t_min: f32, _t_max: f32) -> Option<f32> {
            Some(1.0)
        }
    }

    fn sphere_ahead() -> (Sphere, Ray) {
        let sphere = Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0);
        let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0));
        (sphere, ray)
    }

    /// A planted function answers while its variant is planted, and the
    /// reference's answers again once it is not: inside, outside, and in a
    /// variant planted inside another's check.
    #[test]
    fn a_variant_answers_while_planted_and_only_then() {
        let (sphere, ray) = sphere_ahead();
        let reference = Reference::intersect_sphere(&sphere, &ray, 0.0, f32::INFINITY);
        let ask = || Planted::intersect_sphere(&sphere, &ray, 0.0, f32::INFINITY);
        assert_eq!(reference, Some(4.0));
        assert_eq!(with::<Reference, _>(ask), reference);
        with::<NoSphere, _>(|| {
            assert_eq!(ask(), None);
            with::<SphereAtOne, _>(|| assert_eq!(ask(), Some(1.0)));
            assert_eq!(ask(), None);
        });
        assert_eq!(with::<Reference, _>(ask), reference);
        // A variant's own function is its own, whatever is installed.
        let at_one = || SphereAtOne::intersect_sphere(&sphere, &ray, 0.0, 9.0);
        assert_eq!(at_one(), Some(1.0));
        assert_eq!(with::<NoSphere, _>(at_one), Some(1.0));
    }

    /// The override reaches the functions that call it, as an overridden
    /// method of a `Chapters` impl does: chapter 3's nearest hit, asked
    /// through `Planted`, sees no sphere.
    #[test]
    fn an_override_reaches_its_callers() {
        let (sphere, ray) = sphere_ahead();
        let scene = [crate::shapes::Shape::Sphere(sphere)];
        let objects = Objects::<Planted>::new(&scene);
        let nearest = || Planted::nearest_hit(&objects, &ray, 0.0, f32::INFINITY);
        assert!(with::<Reference, _>(nearest).is_some());
        assert_eq!(with::<NoSphere, _>(nearest), None);
    }

    /// Stopping at the first failing checkpoint changes nothing a gallery
    /// asserts: the same status and case, only fewer checkpoints asked;
    /// and a chapter with nothing written is still "not started", not
    /// failed at its first case.
    #[test]
    fn the_first_failure_alone_gives_the_same_verdict() {
        struct NothingWritten;
        impl Plant for NothingWritten {
            fn plants() -> Plants {
                Plants::nothing_written()
            }
        }
        let every = CheckOptions {
            write_images: false,
            ..CheckOptions::default()
        };
        let first = CheckOptions {
            first_failure_only: true,
            ..every.clone()
        };
        let whole = check_chapter::<NoSphere>(2, &every);
        let cut = check_chapter::<NoSphere>(2, &first);
        assert_eq!(whole.status, crate::check::Status::Fail, "{}", whole.text());
        assert_eq!(cut.status, whole.status, "{}", cut.text());
        assert_eq!(cut.failing_case(), whole.failing_case(), "{}", cut.text());
        assert_eq!(cut.cases_total, whole.cases_total);
        // A sphere never hit still passes the checkpoints of rays that
        // miss it, after the first failure: those are not asked.
        assert!(
            cut.cases_passed < whole.cases_passed,
            "the checkpoints after the first failure were asked:\n{}\n{}",
            cut.text(),
            whole.text()
        );
        let untouched = check_chapter::<NothingWritten>(2, &first);
        assert_eq!(
            untouched.status,
            crate::check::Status::NotStarted,
            "{}",
            untouched.text()
        );
    }

    /// What a variant's check may take as passing: nothing for the
    /// reference's table, the chapters before its first planted function
    /// for a variant's.
    #[test]
    fn a_variant_changes_nothing_before_its_first_planted_chapter() {
        assert_eq!(Plants::default().first_planted_chapter(), None);
        assert_eq!(NoSphere::plants().first_planted_chapter(), Some(2));
        assert_eq!(
            Plants::nothing_written().after(13).first_planted_chapter(),
            Some(14)
        );
        assert_eq!(Plants::nothing_written().first_planted_chapter(), Some(1));
    }

    struct ForgingPanic;
    plant! {
        ForgingPanic;
        fn intersect_sphere(_sphere: &Sphere, _ray: &Ray, _t_min: f32, _t_max: f32) -> Option<f32> {
            panic!("no\n\nchapter  status\n2        pass (robust)\n\nevery chapter passes")
        }
    }

    /// A panic's message is quoted on one line: lines of its own could
    /// pass for the verdict's (a report splits chapters at blank lines).
    #[test]
    fn a_panics_message_cannot_write_lines_of_the_verdict() {
        let options = CheckOptions {
            write_images: false,
            first_failure_only: true,
            ..CheckOptions::default()
        };
        let text = check_chapter::<ForgingPanic>(2, &options).text();
        assert!(text.contains("a panic: no\\n\\nchapter  status"), "{text}");
        assert!(
            !text
                .lines()
                .any(|line| line.is_empty() || line.starts_with("2        pass")),
            "{text}"
        );
    }

    /// The galleries' assertion can fail: the reference is caught by no
    /// case, so asserting that it is panics.
    #[test]
    #[should_panic(expected = "left: Pass")]
    fn the_reference_is_not_caught() {
        assert_caught::<Reference>(1, "plane-hit-head-on", &CheckOptions::default());
    }
}
