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
use crate::chapters::{
    ch01_plane, ch02_sphere, ch03_nearest, ch04_shadows, ch05_phong, ch06_reflection,
    ch07_antialiasing, ch08_refraction, ch09_glass, ch10_triangles, ch11_bvh, ch12_implicit,
    ch13_path_tracing, ch14_caustics,
};
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

    /// Chapter 1: the nearest `t` with `t_min < t < t_max` where `ray` meets `plane`.
    #[inline(always)]
    fn intersect_plane(plane: &Plane, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::intersect_plane");
        ch01_plane::intersect_plane(plane, ray, t_min, t_max)
    }

    /// Chapter 2: the nearest `t` with `t_min < t < t_max` where `ray` meets `sphere`.
    #[inline(always)]
    fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::intersect_sphere");
        ch02_sphere::intersect_sphere(sphere, ray, t_min, t_max)
    }

    /// Chapter 3: the closest hit with `t_min < t < t_max` among `objects`.
    #[inline(always)]
    fn nearest_hit(objects: &Objects<Self>, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::nearest_hit");
        ch03_nearest::nearest_hit(objects, ray, t_min, t_max)
    }

    /// Chapter 4: where a secondary ray leaving `surface` in direction `dir` starts.
    #[inline(always)]
    fn offset_origin(surface: &SurfacePoint, dir: Vec3) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::offset_origin");
        ch04_shadows::offset_origin(surface, dir)
    }

    /// Chapter 4: whether something lies between `point` and a light at `light`.
    #[inline(always)]
    fn in_shadow(tracer: &mut Tracer<Self>, point: &HitPoint, light: Vec3) -> bool {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::in_shadow");
        ch04_shadows::in_shadow(tracer, point, light)
    }

    /// Chapter 4: ambient light plus a constant share of each visible light.
    #[inline(always)]
    fn shade_flat(tracer: &mut Tracer<Self>, point: &HitPoint) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::shade_flat");
        ch04_shadows::shade_flat(tracer, point)
    }

    /// Chapter 5: diffuse and specular light that one light sends to the eye.
    #[inline(always)]
    fn phong_terms(
        material: &Material,
        albedo: Vec3,
        normal: Vec3,
        to_light: Vec3,
        to_eye: Vec3,
        light: Vec3,
    ) -> PhongTerms {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::phong_terms");
        ch05_phong::phong_terms(material, albedo, normal, to_light, to_eye, light)
    }

    /// Chapter 5: ambient, and the Phong terms of every visible light, summed.
    #[inline(always)]
    fn shade_phong(tracer: &mut Tracer<Self>, point: &HitPoint) -> PhongTerms {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::shade_phong");
        ch05_phong::shade_phong(tracer, point)
    }

    /// Chapter 6: the mirror image of direction `d` about the normal `n`.
    #[inline(always)]
    fn reflect(d: Vec3, n: Vec3) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::reflect");
        ch06_reflection::reflect(d, n)
    }

    /// Chapter 6: the local light mixed with what the mirror direction sees.
    #[inline(always)]
    fn shade_mirror(tracer: &mut Tracer<Self>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::shade_mirror");
        ch06_reflection::shade_mirror(tracer, point, depth, weight)
    }

    /// Chapter 7: where sample `index` of `count` falls inside pixel `pixel`.
    #[inline(always)]
    fn sample_offset(
        sampling: Sampling,
        count: u32,
        index: u32,
        pixel: (u32, u32),
        seed: u64,
    ) -> (f32, f32) {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::sample_offset");
        ch07_antialiasing::sample_offset(sampling, count, index, pixel, seed)
    }

    /// Chapter 7: the colour of pixel `(x, y)`, in linear light, from its samples.
    #[inline(always)]
    fn pixel_color(tracer: &mut Tracer<Self>, x: u32, y: u32) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::pixel_color");
        ch07_antialiasing::pixel_color(tracer, x, y)
    }

    /// Chapter 8: the direction of a ray crossing a surface, or `None` under
    /// total internal reflection.
    #[inline(always)]
    fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::refract");
        ch08_refraction::refract(d, n, eta)
    }

    /// Chapter 8: local light, reflection and refraction mixed.
    #[inline(always)]
    fn shade_glass(tracer: &mut Tracer<Self>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::shade_glass");
        ch08_refraction::shade_glass(tracer, point, depth, weight)
    }

    /// Chapter 9: the exact unpolarised Fresnel reflectance of a ray
    /// meeting, at an angle of cosine `cos_i`, the surface from a medium of
    /// index `n1` into one of index `n2`.
    #[inline(always)]
    fn fresnel(cos_i: f32, n1: f32, n2: f32) -> f32 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::fresnel");
        ch09_glass::fresnel(cos_i, n1, n2)
    }

    /// Chapter 9: Schlick's approximation of [`Chapters::fresnel`].
    #[inline(always)]
    fn schlick(cos_i: f32, n1: f32, n2: f32) -> f32 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::schlick");
        ch09_glass::schlick(cos_i, n1, n2)
    }

    /// Chapter 9: the share of light, per channel, that crosses `distance`
    /// of a medium with `absorption` (Beer-Lambert).
    #[inline(always)]
    fn transmittance(absorption: Vec3, distance: f32) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::transmittance");
        ch09_glass::transmittance(absorption, distance)
    }

    /// Chapter 9: the media on both sides of the surface at `point`, for a
    /// ray that travelled through `media`.
    #[inline(always)]
    fn crossing(media: &MediumStack, point: &HitPoint) -> Crossing {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::crossing");
        ch09_glass::crossing(media, point)
    }

    /// Chapter 9: local light, reflection and transmission weighted by
    /// Fresnel, between the right pair of media, with absorption.
    #[inline(always)]
    fn shade_dielectric(
        tracer: &mut Tracer<Self>,
        point: &HitPoint,
        depth: u32,
        weight: f32,
    ) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::shade_dielectric");
        ch09_glass::shade_dielectric(tracer, point, depth, weight)
    }

    /// Chapter 10: the nearest `t` with `t_min < t < t_max` where `ray` meets
    /// `triangle`, with no ray lost between two triangles sharing an edge.
    #[inline(always)]
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::intersect_triangle");
        ch10_triangles::intersect_triangle(triangle, ray, t_min, t_max)
    }

    /// Chapter 10: the barycentric coordinates of `point` in `triangle`.
    #[inline(always)]
    fn barycentric(triangle: &Triangle, point: Vec3) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::barycentric");
        ch10_triangles::barycentric(triangle, point)
    }

    /// Chapter 10: the vertex normals blended at `point`, unit length.
    #[inline(always)]
    fn smooth_normal(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::smooth_normal");
        ch10_triangles::smooth_normal(triangle, normals, point)
    }

    /// Chapter 10: where shadow rays leave a smooth triangle at `point`.
    #[inline(always)]
    fn terminator_point(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::terminator_point");
        ch10_triangles::terminator_point(triangle, normals, point)
    }

    /// Chapter 10: `point`, on a triangle with vertex normals `normals`, as
    /// smooth shading sees it.
    #[inline(always)]
    fn smooth_hit_point<'a>(
        point: HitPoint<'a>,
        triangle: &Triangle,
        normals: &[Vec3; 3],
    ) -> HitPoint<'a> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::smooth_hit_point");
        ch10_triangles::smooth_hit_point::<Self>(point, triangle, normals)
    }

    /// Chapter 11: where a ray enters `bounds` with `t_min <= t <= t_max`
    /// (the slab test), `inverse_direction` being `1 / dir` per axis.
    #[inline(always)]
    fn hit_box(
        bounds: &Aabb,
        origin: Vec3,
        inverse_direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<f32> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::hit_box");
        ch11_bvh::hit_box(bounds, origin, inverse_direction, t_min, t_max)
    }

    /// Chapter 11: a tree over the objects whose boxes are `bounds` (`None`
    /// for a plane).
    #[inline(always)]
    fn build_bvh(bounds: &[Option<Aabb>], options: &BvhOptions) -> Bvh {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::build_bvh");
        ch11_bvh::build_bvh(bounds, options)
    }

    /// Chapter 11: chapter 3's nearest hit, found through the tree.
    #[inline(always)]
    fn nearest_hit_bvh(
        bvh: &Bvh,
        objects: &Objects<Self>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::nearest_hit_bvh");
        ch11_bvh::nearest_hit_bvh(bvh, objects, ray, t_min, t_max)
    }

    /// Chapter 11: any hit, for shadow rays, found through the tree.
    #[inline(always)]
    fn any_hit_bvh(
        bvh: &Bvh,
        objects: &Objects<Self>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::any_hit_bvh");
        ch11_bvh::any_hit_bvh(bvh, objects, ray, t_min, t_max)
    }

    /// Chapter 11: [`Chapters::hit_box`] on four boxes at once: where the
    /// ray enters each, `NaN` where it misses.
    #[inline(always)]
    fn hit_boxes(
        boxes: &Boxes4,
        origin: Vec3,
        inverse_direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Vec4 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::hit_boxes");
        ch11_bvh::hit_boxes(boxes, origin, inverse_direction, t_min, t_max)
    }

    /// Chapter 11: [`Chapters::intersect_triangle`] on four triangles at
    /// once: where the ray meets each, `NaN` where it does not.
    #[inline(always)]
    fn intersect_triangles(triangles: &Triangles4, ray: &Ray, t_min: f32, t_max: f32) -> Vec4 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::intersect_triangles");
        ch11_bvh::intersect_triangles(triangles, ray, t_min, t_max)
    }

    /// Chapter 11: the binary tree over `shapes` folded into nodes of up to
    /// four children, the leaves' triangles four to a [`crate::bvh::Leaf4`].
    #[inline(always)]
    fn collapse_bvh(bvh: &Bvh, shapes: &[Shape]) -> WideBvh {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::collapse_bvh");
        ch11_bvh::collapse_bvh(bvh, shapes)
    }

    /// Chapter 11: chapter 3's nearest hit, found through the wide tree.
    #[inline(always)]
    fn nearest_hit_wide(
        wide: &WideBvh,
        objects: &Objects<Self>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::nearest_hit_wide");
        ch11_bvh::nearest_hit_wide(wide, objects, ray, t_min, t_max)
    }

    /// Chapter 11: any hit, for shadow rays, found through the wide tree.
    #[inline(always)]
    fn any_hit_wide(
        wide: &WideBvh,
        objects: &Objects<Self>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::any_hit_wide");
        ch11_bvh::any_hit_wide(wide, objects, ray, t_min, t_max)
    }

    /// Chapter 12: the nearest `t` with `t_min < t < t_max` where `ray`
    /// comes within the march's tolerance of `surface` (sphere tracing).
    #[inline(always)]
    fn sphere_trace(surface: &Implicit, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::sphere_trace");
        ch12_implicit::sphere_trace(surface, ray, t_min, t_max)
    }

    /// Chapter 12: a root of `g` (value and slope) inside `bracket`, by
    /// Newton's method kept inside the bracket by bisection.
    #[inline(always)]
    fn newton_bracketed(
        g: &dyn Fn(f32) -> (f32, f32),
        bracket: Bracket,
        tolerance: f32,
        max_iterations: u32,
    ) -> f32 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::newton_bracketed");
        ch12_implicit::newton_bracketed(g, bracket, tolerance, max_iterations)
    }

    /// Chapter 12: the unit normal of `surface` at `point`, by the
    /// march's method.
    #[inline(always)]
    fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::implicit_normal");
        ch12_implicit::implicit_normal(surface, point)
    }

    /// Chapter 12: the nearest `t` with `t_min < t < t_max` where `ray`
    /// meets `surface`: sphere tracing, then Newton inside a bracket.
    #[inline(always)]
    fn intersect_implicit(surface: &Implicit, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::intersect_implicit");
        ch12_implicit::intersect_implicit::<Self>(surface, ray, t_min, t_max)
    }

    /// Chapter 13: a direction about the z axis with density `cos(theta) / pi`,
    /// for `u, v` uniform in `[0, 1)`.
    #[inline(always)]
    fn cosine_hemisphere(u: f32, v: f32) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::cosine_hemisphere");
        ch13_path_tracing::cosine_hemisphere(u, v)
    }

    /// Chapter 13: the density of [`Chapters::cosine_hemisphere`]'s direction
    /// at angle `theta` from the normal.
    #[inline(always)]
    fn cosine_pdf(cos_theta: f32) -> f32 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::cosine_pdf");
        ch13_path_tracing::cosine_pdf(cos_theta)
    }

    /// Chapter 13: the power heuristic's weight of a sample of density
    /// `pdf` that another strategy draws with density `other`.
    #[inline(always)]
    fn power_heuristic(pdf: f32, other: f32) -> f32 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::power_heuristic");
        ch13_path_tracing::power_heuristic(pdf, other)
    }

    /// Chapter 13: whether a path of share `weight` survives Russian
    /// roulette for `u` uniform in `[0, 1)`, and then by what its weight is
    /// multiplied.
    #[inline(always)]
    fn russian_roulette(weight: f32, u: f32) -> Option<f32> {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::russian_roulette");
        ch13_path_tracing::russian_roulette(weight, u)
    }

    /// Chapter 13: the light a point chosen on a light sends to `point`
    /// and `lobe` scatters toward the eye (next-event estimation).
    #[inline(always)]
    fn next_event(tracer: &mut Tracer<Self>, point: &HitPoint, lobe: &Lobe) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::next_event");
        ch13_path_tracing::next_event(tracer, point, lobe)
    }

    /// Chapter 13: the light leaving `point` toward the eye, by one random
    /// path.
    #[inline(always)]
    fn shade_path(tracer: &mut Tracer<Self>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::shade_path");
        ch13_path_tracing::shade_path(tracer, point, depth, weight)
    }

    /// Chapter 14: what a unit of radiance leaving a point toward the
    /// camera adds to the pixel that sees it, per unit of the point's area.
    #[inline(always)]
    fn splat_weight(cos_surface: f32, cos_camera: f32, distance: f32, pixel_area: f32) -> f32 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::splat_weight");
        ch14_caustics::splat_weight(cos_surface, cos_camera, distance, pixel_area)
    }

    /// Chapter 14: the light a light path brings to `point`, scattered by
    /// `lobe` toward the camera, onto the pixel that sees it.
    #[inline(always)]
    fn connect_to_camera(tracer: &mut Tracer<Self>, point: &HitPoint, lobe: &Lobe, power: Vec3) {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::connect_to_camera");
        ch14_caustics::connect_to_camera(tracer, point, lobe, power)
    }

    /// Chapter 14: one path of light from a light through mirrors and
    /// glass, each diffuse point it lights after them joined to the camera.
    #[inline(always)]
    fn trace_light_path(tracer: &mut Tracer<Self>) {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::trace_light_path");
        ch14_caustics::trace_light_path(tracer)
    }

    /// Chapter 14: Cauchy's index of refraction at `nanometres`.
    #[inline(always)]
    fn cauchy_ior(cauchy: &Cauchy, nanometres: f32) -> f32 {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::cauchy_ior");
        ch14_caustics::cauchy_ior(cauchy, nanometres)
    }

    /// Chapter 14: the index a path sees in a dispersive glass, for its
    /// wavelength, and the colour its light takes there.
    #[inline(always)]
    fn dispersive_ior(tracer: &mut Tracer<Self>, cauchy: &Cauchy) -> Dispersed {
        crate::answer_key::answered_by(Self::COMPARISON, "Chapters::dispersive_ior");
        ch14_caustics::dispersive_ior(tracer, cauchy)
    }
}

/// The reference's answer to each of [`Chapters`]' functions, by the
/// function's name: what a variant that does not override one falls back
/// on (src/check/planted.rs).
#[cfg(not(feature = "student"))]
pub(crate) mod reference {
    pub(crate) use crate::chapters::ch01_plane::intersect_plane;
    pub(crate) use crate::chapters::ch02_sphere::intersect_sphere;
    pub(crate) use crate::chapters::ch03_nearest::nearest_hit;
    pub(crate) use crate::chapters::ch04_shadows::{in_shadow, offset_origin, shade_flat};
    pub(crate) use crate::chapters::ch05_phong::{phong_terms, shade_phong};
    pub(crate) use crate::chapters::ch06_reflection::{reflect, shade_mirror};
    pub(crate) use crate::chapters::ch07_antialiasing::{pixel_color, sample_offset};
    pub(crate) use crate::chapters::ch08_refraction::{refract, shade_glass};
    pub(crate) use crate::chapters::ch09_glass::{
        crossing, fresnel, schlick, shade_dielectric, transmittance,
    };
    pub(crate) use crate::chapters::ch10_triangles::{
        barycentric, intersect_triangle, smooth_hit_point, smooth_normal, terminator_point,
    };
    pub(crate) use crate::chapters::ch11_bvh::{
        any_hit_bvh, any_hit_wide, build_bvh, collapse_bvh, hit_box, hit_boxes,
        intersect_triangles, nearest_hit_bvh, nearest_hit_wide,
    };
    pub(crate) use crate::chapters::ch12_implicit::{
        implicit_normal, intersect_implicit, newton_bracketed, sphere_trace,
    };
    pub(crate) use crate::chapters::ch13_path_tracing::{
        cosine_hemisphere, cosine_pdf, next_event, power_heuristic, russian_roulette, shade_path,
    };
    pub(crate) use crate::chapters::ch14_caustics::{
        cauchy_ior, connect_to_camera, dispersive_ior, splat_weight, trace_light_path,
    };
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

    fn intersect_plane(plane: &Plane, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        C::intersect_plane(plane, ray, t_min, t_max)
    }
    fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        if SPHERE {
            crate::answer_key::answered_by(true, "Textbook::intersect_sphere");
            ch02_sphere::intersect_sphere_textbook(sphere, ray, t_min, t_max)
        } else {
            C::intersect_sphere(sphere, ray, t_min, t_max)
        }
    }
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        if TRIANGLE {
            crate::answer_key::answered_by(true, "Textbook::intersect_triangle");
            ch10_triangles::intersect_triangle_moller_trumbore(triangle, ray, t_min, t_max)
        } else {
            C::intersect_triangle(triangle, ray, t_min, t_max)
        }
    }
    fn barycentric(triangle: &Triangle, point: Vec3) -> Vec3 {
        C::barycentric(triangle, point)
    }
    fn smooth_normal(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3) -> Vec3 {
        C::smooth_normal(triangle, normals, point)
    }
    fn terminator_point(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3) -> Vec3 {
        C::terminator_point(triangle, normals, point)
    }
    fn smooth_hit_point<'a>(
        point: HitPoint<'a>,
        triangle: &Triangle,
        normals: &[Vec3; 3],
    ) -> HitPoint<'a> {
        C::smooth_hit_point(point, triangle, normals)
    }
    fn hit_box(
        bounds: &Aabb,
        origin: Vec3,
        inverse_direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<f32> {
        C::hit_box(bounds, origin, inverse_direction, t_min, t_max)
    }
    fn build_bvh(bounds: &[Option<Aabb>], options: &BvhOptions) -> Bvh {
        C::build_bvh(bounds, options)
    }
    fn hit_boxes(
        boxes: &Boxes4,
        origin: Vec3,
        inverse_direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Vec4 {
        C::hit_boxes(boxes, origin, inverse_direction, t_min, t_max)
    }
    fn intersect_triangles(triangles: &Triangles4, ray: &Ray, t_min: f32, t_max: f32) -> Vec4 {
        if TRIANGLE {
            // The comparison's own test, lane by lane, so that a tree's
            // leaves show Moller-Trumbore's cracks as chapter 10's loop does.
            crate::answer_key::answered_by(true, "Textbook::intersect_triangles");
            Vec4::from_array(std::array::from_fn(|lane| {
                ch10_triangles::intersect_triangle_moller_trumbore(
                    &triangles.get(lane),
                    ray,
                    t_min,
                    t_max,
                )
                .unwrap_or(f32::NAN)
            }))
        } else {
            C::intersect_triangles(triangles, ray, t_min, t_max)
        }
    }
    fn collapse_bvh(bvh: &Bvh, shapes: &[Shape]) -> WideBvh {
        C::collapse_bvh(bvh, shapes)
    }
    fn sphere_trace(surface: &Implicit, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        C::sphere_trace(surface, ray, t_min, t_max)
    }
    fn newton_bracketed(
        g: &dyn Fn(f32) -> (f32, f32),
        bracket: Bracket,
        tolerance: f32,
        max_iterations: u32,
    ) -> f32 {
        C::newton_bracketed(g, bracket, tolerance, max_iterations)
    }
    fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3 {
        C::implicit_normal(surface, point)
    }
    fn intersect_implicit(surface: &Implicit, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        C::intersect_implicit(surface, ray, t_min, t_max)
    }
    fn cosine_hemisphere(u: f32, v: f32) -> Vec3 {
        C::cosine_hemisphere(u, v)
    }
    fn cosine_pdf(cos_theta: f32) -> f32 {
        C::cosine_pdf(cos_theta)
    }
    fn power_heuristic(pdf: f32, other: f32) -> f32 {
        C::power_heuristic(pdf, other)
    }
    fn russian_roulette(weight: f32, u: f32) -> Option<f32> {
        C::russian_roulette(weight, u)
    }
    fn splat_weight(cos_surface: f32, cos_camera: f32, distance: f32, pixel_area: f32) -> f32 {
        C::splat_weight(cos_surface, cos_camera, distance, pixel_area)
    }
    fn cauchy_ior(cauchy: &Cauchy, nanometres: f32) -> f32 {
        C::cauchy_ior(cauchy, nanometres)
    }
    // The functions below take `Self`'s tracer, which `C`'s cannot accept:
    // each runs the reference code with this type, so a student's textbook
    // render uses the reference from chapter 3 on. Only the comparisons of
    // the formulas (raylab cost, the lessons of chapters 2 and 10) use it.
    fn offset_origin(surface: &SurfacePoint, dir: Vec3) -> Vec3 {
        C::offset_origin(surface, dir)
    }
    fn phong_terms(
        material: &Material,
        albedo: Vec3,
        normal: Vec3,
        to_light: Vec3,
        to_eye: Vec3,
        light: Vec3,
    ) -> PhongTerms {
        C::phong_terms(material, albedo, normal, to_light, to_eye, light)
    }
    fn reflect(d: Vec3, n: Vec3) -> Vec3 {
        C::reflect(d, n)
    }
    fn sample_offset(
        sampling: Sampling,
        count: u32,
        index: u32,
        pixel: (u32, u32),
        seed: u64,
    ) -> (f32, f32) {
        C::sample_offset(sampling, count, index, pixel, seed)
    }
    fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
        C::refract(d, n, eta)
    }
    fn fresnel(cos_i: f32, n1: f32, n2: f32) -> f32 {
        C::fresnel(cos_i, n1, n2)
    }
    fn schlick(cos_i: f32, n1: f32, n2: f32) -> f32 {
        C::schlick(cos_i, n1, n2)
    }
    fn transmittance(absorption: Vec3, distance: f32) -> Vec3 {
        C::transmittance(absorption, distance)
    }
    fn crossing(media: &MediumStack, point: &HitPoint) -> Crossing {
        C::crossing(media, point)
    }
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
        crate::answer_key::answered("Objects::nearest_hit_by_loop");
        ch03_nearest::nearest_hit(self, ray, t_min, t_max)
    }
}

/// The closest hit among `shapes` by raylab's reference chapters (chapter
/// 3's [`ch03_nearest::nearest_hit`] over chapter 1 and 2's tests).
pub fn nearest_hit(shapes: &[Shape], ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
    crate::answer_key::answered("raylab::nearest_hit");
    ch03_nearest::nearest_hit(
        &Objects::<crate::chapters::Reference>::new(shapes),
        ray,
        t_min,
        t_max,
    )
}

/// The first hit in list order among `shapes`, by the reference tests.
pub fn first_hit(shapes: &[Shape], ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
    crate::answer_key::answered("raylab::first_hit");
    Objects::<crate::chapters::Reference>::new(shapes).first_hit(ray, t_min, t_max)
}

// The shapes' intersections, answered by chapters: inherent methods of the
// shapes (any module of the crate may add some), written here because the
// shapes know nothing of the chapters.
impl Shape {
    /// The nearest hit with `t_min < t < t_max`, by the reference chapters.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        crate::answer_key::answered("Shape::intersect");
        self.intersect_with::<crate::chapters::Reference>(ray, t_min, t_max)
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

impl Plane {
    /// The nearest `t` with `t_min < t < t_max` where `ray` meets the plane,
    /// by the reference solution of chapter 1.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        crate::answer_key::answered("Plane::intersect");
        ch01_plane::intersect_plane(self, ray, t_min, t_max)
    }
}

impl Sphere {
    /// Both parameters where the ray's line meets the sphere, smaller first
    /// (chapter 2's reference solution).
    pub fn roots(&self, ray: &Ray) -> Option<(f32, f32)> {
        crate::answer_key::answered("Sphere::roots");
        ch02_sphere::sphere_roots(self, ray)
    }

    /// The nearest `t` with `t_min < t < t_max` where `ray` meets the sphere
    /// (chapter 2's reference solution).
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        crate::answer_key::answered("Sphere::intersect");
        ch02_sphere::intersect_sphere(self, ray, t_min, t_max)
    }

    /// The same with the textbook quadratic formula, kept for comparison.
    pub fn intersect_textbook(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        crate::answer_key::answered("Sphere::intersect_textbook");
        ch02_sphere::intersect_sphere_textbook(self, ray, t_min, t_max)
    }
}
