//! The seam between the renderer and the chapters.
//!
//! [`Chapters`] lists every function a student writes, chapter by chapter.
//! The renderer is generic over it: [`crate::chapters::Reference`] is
//! raylab's own answer, a student workspace (`raylab new`) has its own type,
//! and the checker plants bugs in variants of the reference. Every call goes
//! through the trait with static dispatch, so the seam costs nothing at run
//! time.
//!
//! The functions that drive others (chapter 4's shadow test and light loop,
//! chapter 5's Phong sum, the recursion of 6 and 8, the sample loop of 7)
//! receive a [`Tracer`], the renderer's handle: through it they cast rays,
//! reach the scene, and call the other chapters' functions as the running
//! `Chapters` wrote them.

use crate::bvh::{Aabb, Boxes4, Bvh, BvhOptions, Triangles4, WideBvh};
use crate::chapters::{ch01_plane, ch02_sphere, ch03_nearest};
use crate::medium::{Crossing, MediumStack};
use crate::render::Tracer;
use crate::scene::Cauchy;
use crate::seam::{Dispersed, Lobe};
use crate::shapes::{Bracket, Implicit, Plane, Shape, Sphere, SurfacePoint, Triangle};
use crate::{Material, Ray, Sampling, Vec3, Vec4};

pub use crate::seam::{Hit, HitPoint};

/// The diffuse and specular light at one point (ambient counts as diffuse).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct PhongTerms {
    pub diffuse: Vec3,
    pub specular: Vec3,
}

/// Every function of the course, once, by chapter: calls `$then! {
/// $chapters; ... }` with one entry per function, `module fn name(arguments)
/// -> answer`, where `$chapters` stands for the chapters that run (`Self`
/// in the trait). After the answer, `[drives]` marks a function that takes
/// those chapters' own tracer or objects (`Tracer<$chapters>`,
/// `Objects<$chapters>`), `[generic]` one whose reference code needs the
/// chapters named (`name::<$chapters>(...)`), and `{ textbook if FLAG =>
/// path }` the textbook formula [`Textbook`] runs instead when asked.
///
/// It makes the trait's defaults, [`Textbook`]'s forwards and the planted
/// variants' table (src/check/planted.rs): a new function is one entry here.
macro_rules! for_each_course_function {
    ($then:ident, $chapters:ty) => {
        $then! {
            $chapters;
            /// Chapter 1: the nearest `t` with `t_min < t < t_max` where `ray` meets `plane`.
            ch01_plane fn intersect_plane(
                plane: &Plane,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<f32>;

            /// Chapter 2: the nearest `t` with `t_min < t < t_max` where `ray` meets `sphere`.
            ch02_sphere fn intersect_sphere(
                sphere: &Sphere,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<f32>
                { textbook if SPHERE => ch02_sphere::intersect_sphere_textbook };

            /// Chapter 3: the closest hit with `t_min < t < t_max` among `objects`.
            ch03_nearest fn nearest_hit(
                objects: &Objects<$chapters>,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<Hit> [drives];

            /// Chapter 4: where a secondary ray leaving `surface` in direction `dir` starts.
            ch04_shadows fn offset_origin(surface: &SurfacePoint, dir: Vec3) -> Vec3;
            /// Chapter 4: whether something lies between `point` and a light at `light`.
            ch04_shadows fn in_shadow(
                tracer: &mut Tracer<$chapters>,
                point: &HitPoint,
                light: Vec3,
            ) -> bool [drives];
            /// Chapter 4: ambient light plus a constant share of each visible light.
            ch04_shadows fn shade_flat(
                tracer: &mut Tracer<$chapters>,
                point: &HitPoint,
            ) -> Vec3 [drives];

            /// Chapter 5: diffuse and specular light that one light sends to the eye.
            ch05_phong fn phong_terms(
                material: &Material,
                albedo: Vec3,
                normal: Vec3,
                to_light: Vec3,
                to_eye: Vec3,
                light: Vec3,
            ) -> PhongTerms;
            /// Chapter 5: ambient, and the Phong terms of every visible light, summed.
            ch05_phong fn shade_phong(
                tracer: &mut Tracer<$chapters>,
                point: &HitPoint,
            ) -> PhongTerms [drives];

            /// Chapter 6: the mirror image of direction `d` about the normal `n`.
            ch06_reflection fn reflect(d: Vec3, n: Vec3) -> Vec3;
            /// Chapter 6: the local light mixed with what the mirror direction sees.
            ch06_reflection fn shade_mirror(
                tracer: &mut Tracer<$chapters>,
                point: &HitPoint,
                depth: u32,
                weight: f32,
            ) -> Vec3 [drives];

            /// Chapter 7: where sample `index` of `count` falls inside pixel `pixel`.
            ch07_antialiasing fn sample_offset(
                sampling: Sampling,
                count: u32,
                index: u32,
                pixel: (u32, u32),
                seed: u64,
            ) -> (f32, f32);
            /// Chapter 7: the colour of pixel `(x, y)`, in linear light, from its samples.
            ch07_antialiasing fn pixel_color(
                tracer: &mut Tracer<$chapters>,
                x: u32,
                y: u32,
            ) -> Vec3 [drives];

            /// Chapter 8: the direction of a ray crossing a surface, or `None` under
            /// total internal reflection.
            ch08_refraction fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3>;
            /// Chapter 8: local light, reflection and refraction mixed.
            ch08_refraction fn shade_glass(
                tracer: &mut Tracer<$chapters>,
                point: &HitPoint,
                depth: u32,
                weight: f32,
            ) -> Vec3 [drives];

            /// Chapter 9: the exact unpolarised Fresnel reflectance of a ray
            /// meeting, at an angle of cosine `cos_i`, the surface from a medium of
            /// index `n1` into one of index `n2`.
            ch09_glass fn fresnel(cos_i: f32, n1: f32, n2: f32) -> f32;
            /// Chapter 9: Schlick's approximation of [`Chapters::fresnel`].
            ch09_glass fn schlick(cos_i: f32, n1: f32, n2: f32) -> f32;
            /// Chapter 9: the share of light, per channel, that crosses `distance`
            /// of a medium with `absorption` (Beer-Lambert).
            ch09_glass fn transmittance(absorption: Vec3, distance: f32) -> Vec3;
            /// Chapter 9: the media on both sides of the surface at `point`, for a
            /// ray that travelled through `media`.
            ch09_glass fn crossing(media: &MediumStack, point: &HitPoint) -> Crossing;
            /// Chapter 9: local light, reflection and transmission weighted by
            /// Fresnel, between the right pair of media, with absorption.
            ch09_glass fn shade_dielectric(
                tracer: &mut Tracer<$chapters>,
                point: &HitPoint,
                depth: u32,
                weight: f32,
            ) -> Vec3 [drives];

            /// Chapter 10: the nearest `t` with `t_min < t < t_max` where `ray` meets
            /// `triangle`, with no ray lost between two triangles sharing an edge.
            ch10_triangles fn intersect_triangle(
                triangle: &Triangle,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<f32>
                { textbook if TRIANGLE => ch10_triangles::intersect_triangle_moller_trumbore };
            /// Chapter 10: the barycentric coordinates of `point` in `triangle`.
            ch10_triangles fn barycentric(triangle: &Triangle, point: Vec3) -> Vec3;
            /// Chapter 10: the vertex normals blended at `point`, unit length.
            ch10_triangles fn smooth_normal(
                triangle: &Triangle,
                normals: &[Vec3; 3],
                point: Vec3,
            ) -> Vec3;
            /// Chapter 10: where shadow rays leave a smooth triangle at `point`.
            ch10_triangles fn terminator_point(
                triangle: &Triangle,
                normals: &[Vec3; 3],
                point: Vec3,
            ) -> Vec3;
            /// Chapter 10: `point`, on a triangle with vertex normals `normals`, as
            /// smooth shading sees it.
            ch10_triangles fn smooth_hit_point<'a>(
                point: HitPoint<'a>,
                triangle: &Triangle,
                normals: &[Vec3; 3],
            ) -> HitPoint<'a> [generic];

            /// Chapter 11: where a ray enters `bounds` with `t_min <= t <= t_max`
            /// (the slab test), `inverse_direction` being `1 / dir` per axis.
            ch11_bvh fn hit_box(
                bounds: &Aabb,
                origin: Vec3,
                inverse_direction: Vec3,
                t_min: f32,
                t_max: f32,
            ) -> Option<f32>;
            /// Chapter 11: a tree over the objects whose boxes are `bounds` (`None`
            /// for a plane).
            ch11_bvh fn build_bvh(bounds: &[Option<Aabb>], options: &BvhOptions) -> Bvh;
            /// Chapter 11: chapter 3's nearest hit, found through the tree.
            ch11_bvh fn nearest_hit_bvh(
                bvh: &Bvh,
                objects: &Objects<$chapters>,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<Hit> [drives];
            /// Chapter 11: any hit, for shadow rays, found through the tree.
            ch11_bvh fn any_hit_bvh(
                bvh: &Bvh,
                objects: &Objects<$chapters>,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<Hit> [drives];
            /// Chapter 11: [`Chapters::hit_box`] on four boxes at once: where the
            /// ray enters each, `NaN` where it misses.
            ch11_bvh fn hit_boxes(
                boxes: &Boxes4,
                origin: Vec3,
                inverse_direction: Vec3,
                t_min: f32,
                t_max: f32,
            ) -> Vec4;
            /// Chapter 11: [`Chapters::intersect_triangle`] on four triangles at
            /// once: where the ray meets each, `NaN` where it does not.
            ch11_bvh fn intersect_triangles(
                triangles: &Triangles4,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Vec4;
            /// Chapter 11: the binary tree over `shapes` folded into nodes of up to
            /// four children, the leaves' triangles four to a [`crate::bvh::Leaf4`].
            ch11_bvh fn collapse_bvh(bvh: &Bvh, shapes: &[Shape]) -> WideBvh;
            /// Chapter 11: chapter 3's nearest hit, found through the wide tree.
            ch11_bvh fn nearest_hit_wide(
                wide: &WideBvh,
                objects: &Objects<$chapters>,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<Hit> [drives];
            /// Chapter 11: any hit, for shadow rays, found through the wide tree.
            ch11_bvh fn any_hit_wide(
                wide: &WideBvh,
                objects: &Objects<$chapters>,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<Hit> [drives];

            /// Chapter 12: the nearest `t` with `t_min < t < t_max` where `ray`
            /// comes within the march's tolerance of `surface` (sphere tracing).
            ch12_implicit fn sphere_trace(
                surface: &Implicit,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<f32>;
            /// Chapter 12: a root of `g` (value and slope) inside `bracket`, by
            /// Newton's method kept inside the bracket by bisection.
            ch12_implicit fn newton_bracketed(
                g: &dyn Fn(f32) -> (f32,
                f32), bracket: Bracket, tolerance: f32, max_iterations: u32,
            ) -> f32;
            /// Chapter 12: the unit normal of `surface` at `point`, by the
            /// march's method.
            ch12_implicit fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3;
            /// Chapter 12: the nearest `t` with `t_min < t < t_max` where `ray`
            /// meets `surface`: sphere tracing, then Newton inside a bracket.
            ch12_implicit fn intersect_implicit(
                surface: &Implicit,
                ray: &Ray,
                t_min: f32,
                t_max: f32,
            ) -> Option<f32> [generic];

            /// Chapter 13: a direction about the z axis with density `cos(theta) / pi`,
            /// for `u, v` uniform in `[0, 1)`.
            ch13_path_tracing fn cosine_hemisphere(u: f32, v: f32) -> Vec3;
            /// Chapter 13: the density of [`Chapters::cosine_hemisphere`]'s direction
            /// at angle `theta` from the normal.
            ch13_path_tracing fn cosine_pdf(cos_theta: f32) -> f32;
            /// Chapter 13: the power heuristic's weight of a sample of density
            /// `pdf` that another strategy draws with density `other`.
            ch13_path_tracing fn power_heuristic(pdf: f32, other: f32) -> f32;
            /// Chapter 13: whether a path of share `weight` survives Russian
            /// roulette for `u` uniform in `[0, 1)`, and then by what its weight is
            /// multiplied.
            ch13_path_tracing fn russian_roulette(weight: f32, u: f32) -> Option<f32>;
            /// Chapter 13: the light a point chosen on a light sends to `point`
            /// and `lobe` scatters toward the eye (next-event estimation).
            ch13_path_tracing fn next_event(
                tracer: &mut Tracer<$chapters>,
                point: &HitPoint,
                lobe: &Lobe,
            ) -> Vec3 [drives];
            /// Chapter 13: the light leaving `point` toward the eye, by one random
            /// path.
            ch13_path_tracing fn shade_path(
                tracer: &mut Tracer<$chapters>,
                point: &HitPoint,
                depth: u32,
                weight: f32,
            ) -> Vec3 [drives];

            /// Chapter 14: what a unit of radiance leaving a point toward the
            /// camera adds to the pixel that sees it, per unit of the point's area.
            ch14_caustics fn splat_weight(
                cos_surface: f32,
                cos_camera: f32,
                distance: f32,
                pixel_area: f32,
            ) -> f32;
            /// Chapter 14: the light a light path brings to `point`, scattered by
            /// `lobe` toward the camera, onto the pixel that sees it.
            ch14_caustics fn connect_to_camera(
                tracer: &mut Tracer<$chapters>,
                point: &HitPoint,
                lobe: &Lobe,
                power: Vec3,
            ) [drives];
            /// Chapter 14: one path of light from a light through mirrors and
            /// glass, each diffuse point it lights after them joined to the camera.
            ch14_caustics fn trace_light_path(tracer: &mut Tracer<$chapters>) [drives];
            /// Chapter 14: Cauchy's index of refraction at `nanometres`.
            ch14_caustics fn cauchy_ior(cauchy: &Cauchy, nanometres: f32) -> f32;
            /// Chapter 14: the index a path sees in a dispersive glass, for its
            /// wavelength, and the colour its light takes there.
            ch14_caustics fn dispersive_ior(
                tracer: &mut Tracer<$chapters>,
                cauchy: &Cauchy,
            ) -> Dispersed [drives];
        }
    };
}
pub(crate) use for_each_course_function;

/// The body of one of raylab's answers outside the trait (an inherent
/// method, a free function): reports `$name` to [`crate::answer_key`],
/// then returns `$answer`. A student's build leaves the answer out (see
/// [`crate::answer_key::left_out`]): the report names it in the verdict.
macro_rules! answer {
    ($name:expr => $answer:expr) => {{
        crate::answer_key::answered($name);
        #[cfg(feature = "student")]
        crate::answer_key::left_out($name);
        #[cfg(not(feature = "student"))]
        return $answer;
    }};
}

/// The call of a function's reference code, `chNN_name::function(...)`,
/// with the running chapters named where the entry says `[generic]`. A
/// student's build leaves the reference code out: the call is then
/// [`crate::answer_key::left_out`].
#[cfg(feature = "student")]
macro_rules! reference_call {
    ($chapters:ty, $module:ident :: $name:ident, [$($marker:ident)*], ($($argument:ident),*)) => {{
        $(let _ = $argument;)*
        crate::answer_key::left_out(concat!("Chapters::", stringify!($name)))
    }};
}
#[cfg(not(feature = "student"))]
macro_rules! reference_call {
    ($chapters:ty, $module:ident :: $name:ident, [generic], ($($argument:ident),*)) => {
        crate::chapters::$module::$name::<$chapters>($($argument),*)
    };
    ($chapters:ty, $module:ident :: $name:ident, [$($marker:ident)*], ($($argument:ident),*)) => {
        crate::chapters::$module::$name($($argument),*)
    };
}
pub(crate) use reference_call;

/// One entry of the course's list of functions, as text.
#[derive(Debug, Clone, Copy)]
pub struct CourseFunction {
    /// The chapter's module (`ch01_plane`).
    pub module: &'static str,
    pub name: &'static str,
    /// The arguments' types.
    pub arguments: &'static str,
    /// `drives`, `generic` (see `for_each_course_function!` in src/course.rs), or nothing.
    pub markers: &'static str,
}

/// [`FUNCTIONS`]: what tests compare with the registry's lists.
macro_rules! function_names {
    ($chapters:ty; $(
        $(#[$doc:meta])*
        $module:ident fn $name:ident $(<$lifetime:lifetime>)? ($($argument:ident: $type:ty),* $(,)?)
            $(-> $answer:ty)? $([$($marker:ident)*])?
            $({ textbook if $flag:ident => $text_module:ident :: $text_function:ident })?;
    )*) => {
        /// Every method of [`Chapters`], by chapter.
        pub const FUNCTIONS: &[CourseFunction] = &[$(CourseFunction {
            module: stringify!($module),
            name: stringify!($name),
            arguments: stringify!($($type),*),
            markers: stringify!($($($marker)*)?),
        }),*];
    };
}
for_each_course_function!(function_names, crate::chapters::Reference);

/// The trait's defaults: each reports to the answer key, then runs the
/// reference code.
macro_rules! trait_defaults {
    ($chapters:ty; $(
        $(#[$doc:meta])*
        $module:ident fn $name:ident $(<$lifetime:lifetime>)? ($($argument:ident: $type:ty),* $(,)?)
            $(-> $answer:ty)? $([$($marker:ident)*])?
            $({ textbook if $flag:ident => $text_module:ident :: $text_function:ident })?;
    )*) => {
        $(
            $(#[$doc])*
            #[inline(always)]
            fn $name $(<$lifetime>)? ($($argument: $type),*) $(-> $answer)? {
                crate::answer_key::answered_by(
                    Self::COMPARISON,
                    concat!("Chapters::", stringify!($name)),
                );
                reference_call!($chapters, $module::$name, [$($($marker)*)?], ($($argument),*))
            }
        )*
    };
}

/// [`Textbook`]'s methods: each function that does not drive the others
/// forwards to `C`, or runs its textbook formula when its flag is set.
macro_rules! textbook_forwards {
    ($chapters:ty; $(
        $(#[$doc:meta])*
        $module:ident fn $name:ident $(<$lifetime:lifetime>)? ($($argument:ident: $type:ty),* $(,)?)
            $(-> $answer:ty)? $([$($marker:ident)*])?
            $({ textbook if $flag:ident => $text_module:ident :: $text_function:ident })?;
    )*) => {
        $(
            textbook_forwards!(@ [$($($marker)*)?]
                fn $name $(<$lifetime>)? ($($argument: $type),*) $(-> $answer)? {
                    textbook_forwards!(
                        @call [$($flag $text_module $text_function)?] $name ($($argument),*)
                    )
                }
            );
        )*
    };
    (@call [$flag:ident $module:ident $function:ident] $name:ident ($($argument:ident),*)) => {
        if $flag {
            textbook_forwards!(@textbook $name $module::$function($($argument),*))
        } else {
            C::$name($($argument),*)
        }
    };
    (@textbook $name:ident $module:ident :: $function:ident ($($argument:ident),*)) => {{
        crate::answer_key::answered_by(true, concat!("Textbook::", stringify!($name)));
        #[cfg(feature = "student")]
        {
            $(let _ = $argument;)*
            crate::answer_key::left_out(concat!("Textbook::", stringify!($name)))
        }
        #[cfg(not(feature = "student"))]
        {
            crate::chapters::$module::$function($($argument),*)
        }
    }};
    (@call [] $name:ident ($($argument:ident),*)) => {
        C::$name($($argument),*)
    };
    (@ [drives $($marker:ident)*] $($method:tt)*) => {};
    (@ [$($marker:ident)*] $($method:tt)*) => { $($method)* };
}

/// Every function of the course, by chapter. A chapter's stage needs the
/// functions of every chapter up to it.
///
/// Each method's default is raylab's reference solution, so a variant of the
/// reference (a planted bug, an alternative formula) overrides one method
/// and keeps the rest. A student workspace implements every method with the
/// student's own functions.
pub trait Chapters: Sized + Send + Sync + 'static {
    /// Whether these chapters are one of raylab's comparison wrappers
    /// ([`Textbook`]), which run the reference's shading on purpose: their
    /// defaults are reported to [`crate::answer_key`] only where no
    /// comparison was asked for (a check; a render with the stable
    /// formulas). A student's chapters leave it `false`; `check` fails
    /// chapters that set it.
    #[doc(hidden)]
    const COMPARISON: bool = false;

    for_each_course_function!(trait_defaults, Self);
}

/// The chapters `C` with the textbook tests in place of `C`'s where asked:
/// chapter 2's quadratic formula when `SPHERE` (the comparison setting
/// `sphere_formula = "textbook"`), chapter 10's Moller-Trumbore test when
/// `TRIANGLE` (`triangle_test = "moller-trumbore"`).
///
/// It forwards to `C` every method it can (tests/architecture.rs keeps
/// that): the functions that take the chapters' own tracer or objects
/// (`Tracer<Self>`, `Objects<Self>`: the shading, the loops, the walks)
/// cannot be handed to `C`, and run the reference's, which call back into
/// `Textbook<C>`, so `C`'s own intersections and formulas still answer.
pub struct Textbook<C, const SPHERE: bool, const TRIANGLE: bool>(std::marker::PhantomData<C>);

/// The chapters `C` with chapter 2's textbook quadratic formula.
pub type TextbookSphere<C> = Textbook<C, true, false>;

impl<C: Chapters, const SPHERE: bool, const TRIANGLE: bool> Chapters
    for Textbook<C, SPHERE, TRIANGLE>
{
    const COMPARISON: bool = true;

    for_each_course_function!(textbook_forwards, Self);
}

/// The objects a ray can hit, as the running chapters intersect them.
pub struct Objects<'a, C> {
    shapes: &'a [Shape],
    /// Where each object test is written down while a check watches a
    /// walk's steps from outside it ([`Objects::recording`]).
    asked: Option<&'a std::sync::Mutex<Vec<Asked>>>,
    chapters: std::marker::PhantomData<C>,
}

/// One object test a walk made: which object, the interval it was asked
/// in, and its answer.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Asked {
    pub object: usize,
    pub t_min: f32,
    pub t_max: f32,
    pub answer: Option<f32>,
}

impl<C> Clone for Objects<'_, C> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<C> Copy for Objects<'_, C> {}

impl<'a, C: Chapters> Objects<'a, C> {
    pub fn new(shapes: &'a [Shape]) -> Self {
        Objects {
            shapes,
            asked: None,
            chapters: std::marker::PhantomData,
        }
    }

    /// The objects `shapes`, each test of which is appended to `asked`:
    /// how a check sees the order in which a walk asks them.
    pub(crate) fn recording(shapes: &'a [Shape], asked: &'a std::sync::Mutex<Vec<Asked>>) -> Self {
        Objects {
            shapes,
            asked: Some(asked),
            chapters: std::marker::PhantomData,
        }
    }

    /// How many objects there are; they are numbered `0..len()`.
    pub fn len(&self) -> usize {
        self.shapes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// Object `object`'s own test: its nearest hit with `t_min < t < t_max`,
    /// by the running chapters (chapter 1 for planes, 2 for spheres).
    ///
    /// An `object` out of `0..len()` panics, and the panic names the line
    /// of the caller (the chapter that asked), not this one.
    #[inline(always)]
    #[track_caller]
    pub fn intersect(&self, object: usize, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let answer = self.shape(object).intersect_with::<C>(ray, t_min, t_max);
        if let Some(asked) = self.asked {
            let test = Asked {
                object,
                t_min,
                t_max,
                answer,
            };
            asked
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .push(test);
        }
        answer
    }

    /// The shape of object `object`; out of `0..len()`, a panic that names
    /// the caller's line.
    #[inline(always)]
    #[track_caller]
    pub fn shape(&self, object: usize) -> &'a Shape {
        match self.shapes.get(object) {
            Some(shape) => shape,
            None => panic!(
                "object {object} does not exist: there are {} objects, numbered 0 to {}",
                self.shapes.len(),
                self.shapes.len() as i64 - 1
            ),
        }
    }

    /// The first object in list order that `ray` hits with
    /// `t_min < t < t_max`, wherever it is along the ray.
    ///
    /// Chapters 1 and 2 draw with this, and it is wrong for drawing: a far
    /// object listed early hides a near one listed late (chapter 3 fixes
    /// that). It is exactly right for shadow rays, where any blocker will do
    /// and stopping at the first saves work.
    #[inline(always)]
    pub fn first_hit(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        (0..self.len()).find_map(|object| {
            self.intersect(object, ray, t_min, t_max)
                .map(|t| Hit { object, t })
        })
    }

    /// The nearest hit by chapter 3's reference loop over every object,
    /// with `C`'s own intersections: what a tree must agree with.
    pub fn nearest_hit_by_loop(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        answer!("Objects::nearest_hit_by_loop" => ch03_nearest::nearest_hit(self, ray, t_min, t_max))
    }
}

/// The closest hit among `shapes` by raylab's reference chapters (chapter
/// 3's [`ch03_nearest::nearest_hit`] over chapter 1 and 2's tests).
pub fn nearest_hit(shapes: &[Shape], ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
    answer!("raylab::nearest_hit" => ch03_nearest::nearest_hit(
        &Objects::<crate::chapters::Reference>::new(shapes),
        ray,
        t_min,
        t_max,
    ))
}

/// The first hit in list order among `shapes`, by the reference tests.
pub fn first_hit(shapes: &[Shape], ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
    answer!("raylab::first_hit" => Objects::<crate::chapters::Reference>::new(shapes).first_hit(ray, t_min, t_max))
}

// The shapes' intersections and the glass's Cauchy index, answered by
// chapters: inherent methods of the scene's types (any module of the crate
// may add some), written here because the scene knows nothing of the
// chapters.
impl Shape {
    /// The nearest hit with `t_min < t < t_max`, by the reference chapters.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        answer!("Shape::intersect" => self.intersect_with::<crate::chapters::Reference>(ray, t_min, t_max))
    }

    /// The nearest hit with `t_min < t < t_max`, by the chapters `C`: the
    /// reference, a student's, or a variant under test.
    #[inline(always)]
    pub fn intersect_with<C: Chapters>(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        match self {
            Shape::Plane(plane) => C::intersect_plane(plane, ray, t_min, t_max),
            Shape::Sphere(sphere) => C::intersect_sphere(sphere, ray, t_min, t_max),
            Shape::Triangle(triangle) => C::intersect_triangle(triangle, ray, t_min, t_max),
            Shape::Implicit(surface) => {
                let before = crate::shapes::evaluations();
                let hit = C::intersect_implicit(surface, ray, t_min, t_max);
                crate::shapes::march_ended(crate::shapes::evaluations() - before);
                hit
            }
        }
    }
}

impl Cauchy {
    /// The index of refraction at `nanometres`, by the reference solution
    /// of chapter 14's `cauchy_ior`: in a student's run it reports to
    /// [`crate::answer_key`], as the trait's defaults do.
    pub fn index_at(&self, nanometres: f32) -> f32 {
        answer!("Cauchy::index_at" => crate::chapters::ch14_caustics::cauchy_ior(self, nanometres))
    }
}

impl Plane {
    /// The nearest `t` with `t_min < t < t_max` where `ray` meets the plane,
    /// by the reference solution of chapter 1.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        answer!("Plane::intersect" => ch01_plane::intersect_plane(self, ray, t_min, t_max))
    }
}

impl Sphere {
    /// Both parameters where the ray's line meets the sphere, smaller first
    /// (chapter 2's reference solution).
    pub fn roots(&self, ray: &Ray) -> Option<(f32, f32)> {
        answer!("Sphere::roots" => ch02_sphere::sphere_roots(self, ray))
    }

    /// The nearest `t` with `t_min < t < t_max` where `ray` meets the sphere
    /// (chapter 2's reference solution).
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        answer!("Sphere::intersect" => ch02_sphere::intersect_sphere(self, ray, t_min, t_max))
    }

    /// The same with the textbook quadratic formula, kept for comparison.
    pub fn intersect_textbook(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        answer!("Sphere::intersect_textbook" => ch02_sphere::intersect_sphere_textbook(self, ray, t_min, t_max))
    }
}
