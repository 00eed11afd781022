//! Every chapter's code runs in that chapter's image: for each function a
//! student writes (each method of `Chapters`), a variant of the reference
//! that breaks just that function renders the chapter that introduces it
//! differently. A function whose mutation left the image unchanged would be
//! lesson code that never runs, or runs somewhere else.

use raylab::chapters::{REFERENCE_HEIGHT, REFERENCE_WIDTH};
use raylab::check::planted::{self, Plant, Planted, plant};
use raylab::course::{Chapters, Hit, HitPoint, Objects, PhongTerms};
use raylab::render::Tracer;
use raylab::{Material, Plane, Ray, RenderSettings, Sampling, Sphere, SurfacePoint, Vec3};

fn image<C: Plant>(chapter: u8) -> Vec<u8> {
    planted::with::<C, _>(|| {
        let scene = raylab::builtin::scene(chapter).expect("built-in scene");
        let settings = RenderSettings {
            width: REFERENCE_WIDTH,
            height: REFERENCE_HEIGHT,
            ..scene.render
        };
        raylab::render_with::<Planted>(&scene, chapter, &settings, None)
            .expect("valid settings")
            .rgb
    })
}

/// Asserts that the variant `C` changes chapter `chapter`'s image.
fn changes<C: Plant>(chapter: u8, what: &str) {
    assert_ne!(
        image::<C>(chapter),
        image::<raylab::Reference>(chapter),
        "breaking {what} left chapter {chapter}'s image unchanged"
    );
}

struct NoPlane;
plant! {
    NoPlane;
    fn intersect_plane(_plane: &Plane, _ray: &Ray, _t_min: f32, _t_max: f32) -> Option<f32> {
        None
    }
}

struct NoSphere;
plant! {
    NoSphere;
    fn intersect_sphere(_sphere: &Sphere, _ray: &Ray, _t_min: f32, _t_max: f32) -> Option<f32> {
        None
    }
}

struct ListOrder;
plant! {
    ListOrder;
    fn nearest_hit(objects: &Objects<Planted>, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        objects.first_hit(ray, t_min, t_max)
    }
}

/// Pushes the origin to the wrong side of the surface: a shadow ray from
/// the floor then starts under it and the floor shadows itself everywhere.
/// (Leaving the origin on the surface would not do: chapter 2's stable
/// sphere test and an axis-aligned floor at y = 0, exact in `f32`, show no
/// acne in this scene; lesson 4 shows it with the textbook formula.)
struct WrongSide;
plant! {
    WrongSide;
    fn offset_origin(surface: &SurfacePoint, dir: Vec3) -> Vec3 {
        let right = raylab::Reference::offset_origin(surface, dir);
        surface.point - (right - surface.point)
    }
}

struct NeverInShadow;
plant! {
    NeverInShadow;
    fn in_shadow(_tracer: &mut Tracer<Planted>, _point: &HitPoint, _light: Vec3) -> bool {
        false
    }
}

struct Unlit;
plant! {
    Unlit;
    fn shade_flat(_tracer: &mut Tracer<Planted>, point: &HitPoint) -> Vec3 {
        point.albedo
    }
}

struct NoDiffuse;
plant! {
    NoDiffuse;
    fn phong_terms(
        material: &Material,
        albedo: Vec3,
        normal: Vec3,
        to_light: Vec3,
        to_eye: Vec3,
        light: Vec3,
    ) -> PhongTerms {
        let terms =
            raylab::Reference::phong_terms(material, albedo, normal, to_light, to_eye, light);
        PhongTerms {
            diffuse: Vec3::ZERO,
            ..terms
        }
    }
}

struct AmbientOnly;
plant! {
    AmbientOnly;
    fn shade_phong(tracer: &mut Tracer<Planted>, point: &HitPoint) -> PhongTerms {
        PhongTerms {
            diffuse: point.albedo * point.material.ambient * tracer.ambient_light(),
            specular: Vec3::ZERO,
        }
    }
}

struct StraightOn;
plant! {
    StraightOn;
    fn reflect(d: Vec3, _n: Vec3) -> Vec3 {
        d
    }
}

struct NoMirror;
plant! {
    NoMirror;
    fn shade_mirror(tracer: &mut Tracer<Planted>, point: &HitPoint, _depth: u32, _weight: f32) -> Vec3 {
        let local = Planted::shade_phong(tracer, point);
        local.diffuse + local.specular
    }
}

struct CentreSamples;
plant! {
    CentreSamples;
    fn sample_offset(_sampling: Sampling, _count: u32, _index: u32, _pixel: (u32, u32), _seed: u64) -> (f32, f32) {
        (0.5, 0.5)
    }
}

struct OneSample;
plant! {
    OneSample;
    fn pixel_color(tracer: &mut Tracer<Planted>, x: u32, y: u32) -> Vec3 {
        tracer.sample(x as f32 + 0.5, y as f32 + 0.5)
    }
}

struct AlwaysTotal;
plant! {
    AlwaysTotal;
    fn refract(_d: Vec3, _n: Vec3, _eta: f32) -> Option<Vec3> {
        None
    }
}

struct Opaque;
plant! {
    Opaque;
    fn shade_glass(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        Planted::shade_mirror(tracer, point, depth, weight)
    }
}

#[test]
fn chapter_1_draws_with_intersect_plane() {
    changes::<NoPlane>(1, "intersect_plane");
}

#[test]
fn chapter_2_draws_with_intersect_sphere() {
    changes::<NoSphere>(2, "intersect_sphere");
}

#[test]
fn chapter_3_draws_with_nearest_hit() {
    changes::<ListOrder>(3, "nearest_hit");
}

#[test]
fn chapter_4_draws_with_its_offset_shadow_test_and_light_sum() {
    changes::<WrongSide>(4, "offset_origin");
    changes::<NeverInShadow>(4, "in_shadow");
    changes::<Unlit>(4, "shade_flat");
}

#[test]
fn chapter_5_draws_with_its_terms_and_sum() {
    changes::<NoDiffuse>(5, "phong_terms");
    changes::<AmbientOnly>(5, "shade_phong");
}

#[test]
fn chapter_6_draws_with_reflect_and_its_mix() {
    changes::<StraightOn>(6, "reflect");
    changes::<NoMirror>(6, "shade_mirror");
}

#[test]
fn chapter_7_draws_with_its_samples_and_their_mean() {
    changes::<CentreSamples>(7, "sample_offset");
    changes::<OneSample>(7, "pixel_color");
}

#[test]
fn chapter_8_draws_with_refract_and_its_mix() {
    changes::<AlwaysTotal>(8, "refract");
    changes::<Opaque>(8, "shade_glass");
}
