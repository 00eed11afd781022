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
use crate::course::{Chapters, Hit, HitPoint, Objects, PhongTerms, reference};
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
    let table: &'static mut Plants = Box::leak(Box::new(P::plants()));
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

/// [`crate::check::check_chapter`] of the variant `P`.
pub fn check_chapter<P: Plant>(chapter: u8, options: &CheckOptions) -> ChapterVerdict {
    with::<P, _>(|| crate::check::check_chapter::<Planted>(chapter, options))
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
    let verdict = check_chapter::<P>(chapter, options);
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

/// Declares the table's fields and `Planted`'s `Chapters`, one line per
/// function: its signature (with `Planted` for `Self`) and the reference.
macro_rules! plants {
    ($(
        fn $name:ident $(<$lifetime:lifetime>)? ($($argument:ident: $type:ty),* $(,)?)
            $(-> $answer:ty)? = $reference:path;
    )*) => {
        /// The functions a variant overrides, by name.
        #[derive(Clone, Copy, Default)]
        pub struct Plants {
            $(pub $name: Option<for<$($lifetime)?> fn($($type),*) $(-> $answer)?>,)*
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
                            $reference($($argument),*)
                        }
                    }
                }
            )*
        }
    };
}

plants! {
    fn intersect_plane(plane: &Plane, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32>
        = reference::intersect_plane;
    fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32>
        = reference::intersect_sphere;
    fn nearest_hit(objects: &Objects<Planted>, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit>
        = reference::nearest_hit;
    fn offset_origin(surface: &SurfacePoint, dir: Vec3) -> Vec3 = reference::offset_origin;
    fn in_shadow(tracer: &mut Tracer<Planted>, point: &HitPoint, light: Vec3) -> bool
        = reference::in_shadow;
    fn shade_flat(tracer: &mut Tracer<Planted>, point: &HitPoint) -> Vec3
        = reference::shade_flat;
    fn phong_terms(
        material: &Material,
        albedo: Vec3,
        normal: Vec3,
        to_light: Vec3,
        to_eye: Vec3,
        light: Vec3,
    ) -> PhongTerms = reference::phong_terms;
    fn shade_phong(tracer: &mut Tracer<Planted>, point: &HitPoint) -> PhongTerms
        = reference::shade_phong;
    fn reflect(d: Vec3, n: Vec3) -> Vec3 = reference::reflect;
    fn shade_mirror(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32)
        -> Vec3 = reference::shade_mirror;
    fn sample_offset(sampling: Sampling, count: u32, index: u32, pixel: (u32, u32), seed: u64)
        -> (f32, f32) = reference::sample_offset;
    fn pixel_color(tracer: &mut Tracer<Planted>, x: u32, y: u32) -> Vec3
        = reference::pixel_color;
    fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> = reference::refract;
    fn shade_glass(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32)
        -> Vec3 = reference::shade_glass;
    fn fresnel(cos_i: f32, n1: f32, n2: f32) -> f32 = reference::fresnel;
    fn schlick(cos_i: f32, n1: f32, n2: f32) -> f32 = reference::schlick;
    fn transmittance(absorption: Vec3, distance: f32) -> Vec3 = reference::transmittance;
    fn crossing(media: &MediumStack, point: &HitPoint) -> Crossing = reference::crossing;
    fn shade_dielectric(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32)
        -> Vec3 = reference::shade_dielectric;
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32>
        = reference::intersect_triangle;
    fn barycentric(triangle: &Triangle, point: Vec3) -> Vec3 = reference::barycentric;
    fn smooth_normal(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3) -> Vec3
        = reference::smooth_normal;
    fn terminator_point(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3) -> Vec3
        = reference::terminator_point;
    fn smooth_hit_point<'a>(point: HitPoint<'a>, triangle: &Triangle, normals: &[Vec3; 3])
        -> HitPoint<'a> = reference::smooth_hit_point::<Planted>;
    fn hit_box(bounds: &Aabb, origin: Vec3, inverse_direction: Vec3, t_min: f32, t_max: f32)
        -> Option<f32> = reference::hit_box;
    fn build_bvh(bounds: &[Option<Aabb>], options: &BvhOptions) -> Bvh = reference::build_bvh;
    fn nearest_hit_bvh(bvh: &Bvh, objects: &Objects<Planted>, ray: &Ray, t_min: f32, t_max: f32)
        -> Option<Hit> = reference::nearest_hit_bvh;
    fn any_hit_bvh(bvh: &Bvh, objects: &Objects<Planted>, ray: &Ray, t_min: f32, t_max: f32)
        -> Option<Hit> = reference::any_hit_bvh;
    fn hit_boxes(boxes: &Boxes4, origin: Vec3, inverse_direction: Vec3, t_min: f32, t_max: f32)
        -> Vec4 = reference::hit_boxes;
    fn intersect_triangles(triangles: &Triangles4, ray: &Ray, t_min: f32, t_max: f32) -> Vec4
        = reference::intersect_triangles;
    fn collapse_bvh(bvh: &Bvh, shapes: &[Shape]) -> WideBvh = reference::collapse_bvh;
    fn nearest_hit_wide(
        wide: &WideBvh,
        objects: &Objects<Planted>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> = reference::nearest_hit_wide;
    fn any_hit_wide(wide: &WideBvh, objects: &Objects<Planted>, ray: &Ray, t_min: f32, t_max: f32)
        -> Option<Hit> = reference::any_hit_wide;
    fn sphere_trace(surface: &Implicit, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32>
        = reference::sphere_trace;
    fn newton_bracketed(
        g: &dyn Fn(f32) -> (f32, f32),
        bracket: Bracket,
        tolerance: f32,
        max_iterations: u32,
    ) -> f32 = reference::newton_bracketed;
    fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3 = reference::implicit_normal;
    fn intersect_implicit(surface: &Implicit, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32>
        = reference::intersect_implicit::<Planted>;
    fn cosine_hemisphere(u: f32, v: f32) -> Vec3 = reference::cosine_hemisphere;
    fn cosine_pdf(cos_theta: f32) -> f32 = reference::cosine_pdf;
    fn power_heuristic(pdf: f32, other: f32) -> f32 = reference::power_heuristic;
    fn russian_roulette(weight: f32, u: f32) -> Option<f32> = reference::russian_roulette;
    fn next_event(tracer: &mut Tracer<Planted>, point: &HitPoint, lobe: &Lobe) -> Vec3
        = reference::next_event;
    fn shade_path(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3
        = reference::shade_path;
    fn splat_weight(cos_surface: f32, cos_camera: f32, distance: f32, pixel_area: f32) -> f32
        = reference::splat_weight;
    fn connect_to_camera(tracer: &mut Tracer<Planted>, point: &HitPoint, lobe: &Lobe, power: Vec3)
        = reference::connect_to_camera;
    fn trace_light_path(tracer: &mut Tracer<Planted>) = reference::trace_light_path;
    fn cauchy_ior(cauchy: &Cauchy, nanometres: f32) -> f32 = reference::cauchy_ior;
    fn dispersive_ior(tracer: &mut Tracer<Planted>, cauchy: &Cauchy) -> Dispersed
        = reference::dispersive_ior;
}

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

    /// The galleries' assertion can fail: the reference is caught by no
    /// case, so asserting that it is panics.
    #[test]
    #[should_panic(expected = "left: Pass")]
    fn the_reference_is_not_caught() {
        assert_caught::<Reference>(1, "plane-hit-head-on", &CheckOptions::default());
    }
}
