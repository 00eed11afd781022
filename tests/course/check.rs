//! The proof that `raylab check` is honest: a bug gallery of the classic
//! mistakes, each planted in the chapter it belongs to, must fail THAT
//! chapter and name the case that catches it; correct alternatives to the
//! reference (another formula, another offset rule, another sample order)
//! must pass. Each variant overrides one function of the reference and
//! keeps the rest, so the planted bug reaches everything that calls it.

use raylab::check::planted::{self, Plant, Planted, plant};
use raylab::check::{ChapterVerdict, CheckOptions, Status, check_all, check_chapter};
use raylab::course::{Chapters, HitPoint, PhongTerms, TextbookSphere};
use raylab::render::{RayKind, Tracer};
use raylab::shapes::SurfacePoint;
use raylab::{Material, Plane, Ray, Reference, Sampling, Sphere, Vec3};

fn options() -> CheckOptions {
    CheckOptions {
        failures_dir: std::env::temp_dir().join("raylab-check-tests"),
        write_images: false,
        forbid_answer_key: false,
        fresh: None,
        ..Default::default()
    }
}

/// Checks `chapter` with `C` and asserts that it fails on case `case`.
fn assert_caught<C: Plant>(chapter: u8, case: &str) -> ChapterVerdict {
    planted::assert_caught::<C>(chapter, case, &options())
}

/// Checks `chapter` with `C` and asserts that it passes, with the lesson's
/// inputs and with fresh ones (`--fresh`): a correct alternative passes
/// whatever numbers it is asked.
fn assert_passes<C: Plant>(chapter: u8) -> ChapterVerdict {
    planted::with::<C, _>(|| {
        for seed in [1, 2] {
            let fresh = CheckOptions {
                fresh: Some(seed),
                ..options()
            };
            let verdict = check_chapter::<Planted>(chapter, &fresh);
            assert!(verdict.passes(), "fresh seed {seed}: {}", verdict.text());
        }
        let verdict = check_chapter::<Planted>(chapter, &options());
        assert!(verdict.passes(), "{}", verdict.text());
        verdict
    })
}

// ---------------------------------------------------------------------------
// The bug gallery.

/// Chapter 4: the shadow test always says "lit".
struct AlwaysLit;
plant! {
    AlwaysLit;
    fn in_shadow(_tracer: &mut Tracer<Planted>, _point: &HitPoint, _light: Vec3) -> bool {
        false
    }
}

#[test]
fn gallery_shadow_test_always_lit() {
    assert_caught::<AlwaysLit>(4, "shadow-under-ball");
}

/// Chapter 2: the quadratic written for unit directions (`a = 1`).
struct DropsA;
plant! {
    DropsA;
    fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let oc = ray.origin - sphere.center();
        let b = 2.0 * ray.dir.dot(oc);
        let c = oc.dot(oc) - sphere.radius() * sphere.radius();
        let discriminant = b * b - 4.0 * c;
        if discriminant < 0.0 {
            return None;
        }
        let root = discriminant.sqrt();
        [(-b - root) / 2.0, (-b + root) / 2.0]
            .into_iter()
            .find(|&t| t > t_min && t < t_max)
    }
}

#[test]
fn gallery_quadratic_drops_a() {
    assert_caught::<DropsA>(2, "sphere-direction-not-unit");
}

/// Chapter 2: the sub-cases mixed up: from outside it takes the far root,
/// from inside the negative one.
struct RootMixUp;
plant! {
    RootMixUp;
    fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let oc = ray.origin - sphere.center();
        let a = ray.dir.dot(ray.dir);
        let b = 2.0 * ray.dir.dot(oc);
        let c = oc.dot(oc) - sphere.radius() * sphere.radius();
        let discriminant = b * b - 4.0 * a * c;
        if discriminant < 0.0 {
            return None;
        }
        let root = discriminant.sqrt();
        let t = if c > 0.0 {
            (-b + root) / (2.0 * a)
        } else {
            (-b - root) / (2.0 * a)
        };
        (t > t_min && t < t_max).then_some(t)
    }
}

#[test]
fn gallery_sphere_root_mix_up() {
    assert_caught::<RootMixUp>(2, "sphere-nearer-root");
}

/// Chapter 8: the refracted direction comes out with length n1 / n2.
struct RefractedNotUnit;
plant! {
    RefractedNotUnit;
    fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
        raylab::refract(d, n, eta).map(|t| t * eta)
    }
}

#[test]
fn gallery_refracted_direction_not_normalised() {
    assert_caught::<RefractedNotUnit>(8, "refract-normal-incidence");
}

/// Chapter 6: the mirror mix normalised by 1 / (1 + k) instead of
/// `(1 - k) local + k reflected`.
struct OnePlusK;
plant! {
    OnePlusK;
    fn shade_mirror(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        let local = Planted::shade_phong(tracer, point);
        let k = point.material.reflectivity;
        let mut seen = Vec3::ZERO;
        if depth < tracer.max_depth() && tracer.worth_casting(weight, k) {
            let dir = Planted::reflect(point.ray.dir, point.surface.normal);
            let ray = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
            seen = tracer.trace(RayKind::Reflection, &ray, depth + 1, weight * k);
        }
        (local.diffuse + local.specular + k * seen) / (1.0 + k)
    }
}

#[test]
fn gallery_reflection_weighted_one_over_one_plus_k() {
    assert_caught::<OnePlusK>(6, "mirror-sees-sky");
}

/// Chapter 7: "anti-aliasing" by blurring: the mean of the neighbouring
/// pixels' centres.
struct Blur;
plant! {
    Blur;
    fn pixel_color(tracer: &mut Tracer<Planted>, x: u32, y: u32) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for dy in -1..=1 {
            for dx in -1..=1 {
                sum += tracer.sample(x as f32 + 0.5 + dx as f32, y as f32 + 0.5 + dy as f32);
            }
        }
        sum / 9.0
    }
}

#[test]
fn gallery_blur_is_not_anti_aliasing() {
    let verdict = planted::check_chapter::<Blur>(7, &options());
    assert_eq!(verdict.status, Status::Fail, "{}", verdict.text());
    let case = verdict.failing_case().unwrap_or_default();
    assert!(
        case == "pixel-quarters" || case == "pixel-mean-of-own-samples",
        "{}",
        verdict.text()
    );
}

/// Chapter 4: shadow acne: the shadow ray starts on the surface itself,
/// with no offset, and counts hits from t = 0.
struct Acne;
plant! {
    Acne;
    fn in_shadow(tracer: &mut Tracer<Planted>, point: &HitPoint, light: Vec3) -> bool {
        let origin = point.surface.point;
        tracer.blocked(&Ray::new(origin, light - origin), 0.0, 1.0, point)
    }
}

#[test]
fn gallery_shadow_acne() {
    // On the ball, chapter 2's stable sphere test rejects the self-hits by
    // itself; the tilted floor shows the acne.
    assert_caught::<Acne>(4, "shadow-no-acne-plane");
}

/// Chapter 4: the ambient term without the ambient light, `albedo * k_a`:
/// right under white ambient light only.
struct AmbientLightLeftOut;
plant! {
    AmbientLightLeftOut;
    fn shade_flat(tracer: &mut Tracer<Planted>, point: &HitPoint) -> Vec3 {
        let material = &point.material;
        let mut color = point.albedo * material.ambient;
        for light in tracer.lights() {
            if !point.faces(light.position) || Planted::in_shadow(tracer, point, light.position) {
                continue;
            }
            color += point.albedo * material.diffuse * light.radiance();
        }
        color
    }
}

#[test]
fn gallery_ambient_light_left_out() {
    assert_caught::<AmbientLightLeftOut>(4, "flat-dim-ambient");
}

/// Chapter 6: the reflected ray traced at the mirror's own depth: only the
/// weights end the recursion, `max_depth` never does.
struct DepthNotCounted;
plant! {
    DepthNotCounted;
    fn shade_mirror(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        let local = Planted::shade_phong(tracer, point);
        let k = point.material.reflectivity;
        let mut color = (1.0 - k) * local.diffuse + local.specular;
        if depth < tracer.max_depth() && tracer.worth_casting(weight, k) {
            let dir = Planted::reflect(point.ray.dir, point.surface.normal);
            let ray = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
            color += k * tracer.trace(RayKind::Reflection, &ray, depth, weight * k);
        }
        color
    }
}

#[test]
fn gallery_reflection_depth_not_counted() {
    assert_caught::<DepthNotCounted>(6, "mirror-depth-counts-bounces");
}

/// Chapter 7: the random numbers hashed from the pixel and the sample only:
/// every seed gives the same samples.
struct SeedIgnored;
plant! {
    SeedIgnored;
    fn sample_offset(
        sampling: Sampling,
        count: u32,
        index: u32,
        pixel: (u32, u32),
        _seed: u64,
    ) -> (f32, f32) {
        Reference::sample_offset(sampling, count, index, pixel, 0)
    }
}

#[test]
fn gallery_seed_ignored() {
    assert_caught::<SeedIgnored>(7, "samples-seed-changes-them");
}

fn srgb_encode(linear: f32) -> f32 {
    let v = linear.clamp(0.0, 1.0);
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

fn srgb_decode(encoded: f32) -> f32 {
    if encoded <= 0.040_45 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// Chapter 7: the samples averaged as sRGB codes, not in linear light.
struct SrgbAverage;
plant! {
    SrgbAverage;
    fn pixel_color(tracer: &mut Tracer<Planted>, x: u32, y: u32) -> Vec3 {
        let samples = tracer.samples();
        let mut sum = Vec3::ZERO;
        for index in 0..samples {
            let (dx, dy) = tracer.sample_offset(index, (x, y));
            let c = tracer.sample(x as f32 + dx, y as f32 + dy);
            sum += Vec3::new(srgb_encode(c.x), srgb_encode(c.y), srgb_encode(c.z));
        }
        let mean = sum / samples as f32;
        Vec3::new(
            srgb_decode(mean.x),
            srgb_decode(mean.y),
            srgb_decode(mean.z),
        )
    }
}

#[test]
fn gallery_samples_averaged_in_srgb() {
    assert_caught::<SrgbAverage>(7, "pixel-quarters");
}

/// Chapter 5: the normal flipped in the Phong terms.
struct FlippedNormal;
plant! {
    FlippedNormal;
    fn phong_terms(
        material: &Material,
        albedo: Vec3,
        normal: Vec3,
        to_light: Vec3,
        to_eye: Vec3,
        light: Vec3,
    ) -> PhongTerms {
        Reference::phong_terms(material, albedo, -normal, to_light, to_eye, light)
    }
}

#[test]
fn gallery_flipped_normal() {
    assert_caught::<FlippedNormal>(5, "phong-diffuse-cosine");
}

/// Chapter 8's glass mix, with a switch for each planted bug.
fn glass<C: Chapters>(
    tracer: &mut Tracer<C>,
    point: &HitPoint,
    depth: u32,
    weight: f32,
    swap_eta: bool,
    tir_black: bool,
) -> Vec3 {
    let local = C::shade_phong(tracer, point);
    let material = &point.material;
    let (k_r, k_t) = (material.reflectivity, material.transparency);
    let mut color = (1.0 - k_r - k_t) * local.diffuse + local.specular;
    if depth >= tracer.max_depth() {
        return color;
    }
    let incoming = point.ray.dir;
    let normal = point.surface.normal;
    let mut reflected_share = k_r;
    if tracer.worth_casting(weight, k_t) {
        let entering = incoming.dot(normal) < 0.0;
        let eta = if entering != swap_eta {
            1.0 / material.ior
        } else {
            material.ior
        };
        match C::refract(incoming, normal, eta) {
            Some(dir) => {
                let ray = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
                let through = tracer.trace(RayKind::Refraction, &ray, depth + 1, weight * k_t);
                color += k_t * material.color * through;
            }
            None if tir_black => {}
            None => reflected_share += k_t,
        }
    }
    if tracer.worth_casting(weight, reflected_share) {
        let dir = C::reflect(incoming, normal);
        let ray = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
        let seen = tracer.trace(
            RayKind::Reflection,
            &ray,
            depth + 1,
            weight * reflected_share,
        );
        color += reflected_share * seen;
    }
    color
}

/// Chapter 8: eta = n2 / n1 instead of n1 / n2.
struct EtaSwapped;
plant! {
    EtaSwapped;
    fn shade_glass(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        glass(tracer, point, depth, weight, true, false)
    }
}

#[test]
fn gallery_eta_swapped() {
    assert_caught::<EtaSwapped>(8, "glass-entering");
}

/// Chapter 8: total internal reflection drawn black (the transmitted share
/// lost instead of joining the reflected one).
struct TirBlack;
plant! {
    TirBlack;
    fn shade_glass(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        glass(tracer, point, depth, weight, false, true)
    }
}

#[test]
fn gallery_total_internal_reflection_as_black() {
    assert_caught::<TirBlack>(8, "glass-total-internal-reflection");
}

/// The glass mix above with neither bug is the reference's: the gallery's
/// two chapter 8 bugs are caught for what they change, nothing else.
struct GlassRewritten;
plant! {
    GlassRewritten;
    fn shade_glass(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        glass(tracer, point, depth, weight, false, false)
    }
}

#[test]
fn the_glass_mix_without_the_bugs_passes() {
    assert_passes::<GlassRewritten>(8);
}

// ---------------------------------------------------------------------------
// Correct alternatives: they must pass.

#[test]
fn alternative_textbook_sphere_is_correct_but_not_robust() {
    // Not a planted variant: raylab's own comparison wrapper, checked as
    // it is.
    for seed in [1, 2] {
        let fresh = CheckOptions {
            fresh: Some(seed),
            ..options()
        };
        let verdict = check_chapter::<TextbookSphere<Reference>>(2, &fresh);
        assert!(verdict.passes(), "fresh seed {seed}: {}", verdict.text());
    }
    let verdict = check_chapter::<TextbookSphere<Reference>>(2, &options());
    assert!(verdict.passes(), "{}", verdict.text());
    assert!(!verdict.robust(), "{}", verdict.text());
    assert!(
        verdict.text().contains("correct, not yet robust"),
        "{}",
        verdict.text()
    );
}

/// Chapter 1 written with signed distances: the origin is `s0` from the
/// plane, each unit of `t` moves `s1` more, so the hit is at `-s0 / s1`.
struct PlaneBySignedDistance;
plant! {
    PlaneBySignedDistance;
    fn intersect_plane(plane: &Plane, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let start = (ray.origin - plane.point()).dot(plane.normal());
        let rate = ray.dir.dot(plane.normal());
        if rate == 0.0 || !rate.is_finite() {
            return None;
        }
        let t = -start / rate;
        (t > t_min && t < t_max).then_some(t)
    }
}

#[test]
fn alternative_plane_by_signed_distance() {
    assert_passes::<PlaneBySignedDistance>(1);
}

/// Chapter 4 with another offset rule: twice the length of the error
/// vector along the normal (at least twice the reference's push).
struct OffsetTwiceTheError;
plant! {
    OffsetTwiceTheError;
    fn offset_origin(surface: &SurfacePoint, dir: Vec3) -> Vec3 {
        let side = if dir.dot(surface.normal) >= 0.0 {
            1.0
        } else {
            -1.0
        };
        surface.point + side * 2.0 * surface.error.length() * surface.normal
    }
}

#[test]
fn alternative_offset_rule() {
    assert_passes::<OffsetTwiceTheError>(4);
}

/// Chapter 7 summing the samples last to first: another order, the same
/// mean up to rounding.
struct ReverseSum;
plant! {
    ReverseSum;
    fn pixel_color(tracer: &mut Tracer<Planted>, x: u32, y: u32) -> Vec3 {
        let samples = tracer.samples();
        let mut sum = Vec3::ZERO;
        for index in (0..samples).rev() {
            let (dx, dy) = tracer.sample_offset(index, (x, y));
            sum += tracer.sample(x as f32 + dx, y as f32 + dy);
        }
        sum / samples as f32
    }
}

#[test]
fn alternative_sample_sum_order() {
    assert_passes::<ReverseSum>(7);
}

/// Chapter 7's grid samples numbered column by column instead of row by
/// row (the lesson asks for the cell centres, in no particular order).
struct GridColumnMajor;
plant! {
    GridColumnMajor;
    fn sample_offset(
        sampling: Sampling,
        count: u32,
        index: u32,
        pixel: (u32, u32),
        seed: u64,
    ) -> (f32, f32) {
        if sampling == Sampling::Grid {
            let k = count.isqrt().max(1);
            let cell = 1.0 / k as f32;
            let (column, row) = ((index / k) as f32, (index % k) as f32);
            ((column + 0.5) * cell, (row + 0.5) * cell)
        } else {
            Reference::sample_offset(sampling, count, index, pixel, seed)
        }
    }
}

#[test]
fn alternative_grid_sample_order() {
    assert_passes::<GridColumnMajor>(7);
}

// ---------------------------------------------------------------------------
// Not started, other panics, and what a chapter builds on.

/// A student who wrote chapters 1 to 3 and 13 and left chapters 4 to 12 as
/// the skeleton has them, each function `todo!("chapter N: name")`.
mod skips_to_thirteen {
    use raylab::bvh::{Aabb, Boxes4, Bvh, BvhOptions, Triangles4, WideBvh};
    use raylab::check::planted::{Planted, plant};
    use raylab::course::{HitPoint, PhongTerms};
    use raylab::medium::{Crossing, MediumStack};
    use raylab::render::Tracer;
    use raylab::shapes::{Bracket, Implicit, Shape, SurfacePoint, Triangle};
    use raylab::{Hit, Material, Objects, Ray, Sampling, Vec3, Vec4};

    pub struct SkipsToThirteen;
    plant! {
        SkipsToThirteen;
        fn offset_origin(_surface: &SurfacePoint, _dir: Vec3) -> Vec3 {
            todo!("chapter 4: offset_origin")
        }
        fn in_shadow(_tracer: &mut Tracer<Planted>, _point: &HitPoint, _light: Vec3) -> bool {
            todo!("chapter 4: in_shadow")
        }
        fn shade_flat(_tracer: &mut Tracer<Planted>, _point: &HitPoint) -> Vec3 {
            todo!("chapter 4: shade_flat")
        }
        fn phong_terms(
            _material: &Material,
            _albedo: Vec3,
            _normal: Vec3,
            _to_light: Vec3,
            _to_eye: Vec3,
            _light: Vec3,
        ) -> PhongTerms {
            todo!("chapter 5: phong_terms")
        }
        fn shade_phong(_tracer: &mut Tracer<Planted>, _point: &HitPoint) -> PhongTerms {
            todo!("chapter 5: shade_phong")
        }
        fn reflect(_d: Vec3, _n: Vec3) -> Vec3 {
            todo!("chapter 6: reflect")
        }
        fn shade_mirror(
            _tracer: &mut Tracer<Planted>,
            _point: &HitPoint,
            _depth: u32,
            _weight: f32,
        ) -> Vec3 {
            todo!("chapter 6: shade_mirror")
        }
        fn sample_offset(
            _sampling: Sampling,
            _count: u32,
            _index: u32,
            _pixel: (u32, u32),
            _seed: u64,
        ) -> (f32, f32) {
            todo!("chapter 7: sample_offset")
        }
        fn pixel_color(_tracer: &mut Tracer<Planted>, _x: u32, _y: u32) -> Vec3 {
            todo!("chapter 7: pixel_color")
        }
        fn refract(_d: Vec3, _n: Vec3, _eta: f32) -> Option<Vec3> {
            todo!("chapter 8: refract")
        }
        fn shade_glass(
            _tracer: &mut Tracer<Planted>,
            _point: &HitPoint,
            _depth: u32,
            _weight: f32,
        ) -> Vec3 {
            todo!("chapter 8: shade_glass")
        }
        fn fresnel(_cos_i: f32, _n1: f32, _n2: f32) -> f32 {
            todo!("chapter 9: fresnel")
        }
        fn schlick(_cos_i: f32, _n1: f32, _n2: f32) -> f32 {
            todo!("chapter 9: schlick")
        }
        fn transmittance(_absorption: Vec3, _distance: f32) -> Vec3 {
            todo!("chapter 9: transmittance")
        }
        fn crossing(_media: &MediumStack, _point: &HitPoint) -> Crossing {
            todo!("chapter 9: crossing")
        }
        fn shade_dielectric(
            _tracer: &mut Tracer<Planted>,
            _point: &HitPoint,
            _depth: u32,
            _weight: f32,
        ) -> Vec3 {
            todo!("chapter 9: shade_dielectric")
        }
        fn intersect_triangle(
            _triangle: &Triangle,
            _ray: &Ray,
            _t_min: f32,
            _t_max: f32,
        ) -> Option<f32> {
            todo!("chapter 10: intersect_triangle")
        }
        fn barycentric(_triangle: &Triangle, _point: Vec3) -> Vec3 {
            todo!("chapter 10: barycentric")
        }
        fn smooth_normal(_triangle: &Triangle, _normals: &[Vec3; 3], _point: Vec3) -> Vec3 {
            todo!("chapter 10: smooth_normal")
        }
        fn terminator_point(_triangle: &Triangle, _normals: &[Vec3; 3], _point: Vec3) -> Vec3 {
            todo!("chapter 10: terminator_point")
        }
        fn smooth_hit_point<'a>(
            _point: HitPoint<'a>,
            _triangle: &Triangle,
            _normals: &[Vec3; 3],
        ) -> HitPoint<'a> {
            todo!("chapter 10: smooth_hit_point")
        }
        fn hit_box(
            _bounds: &Aabb,
            _origin: Vec3,
            _inverse_direction: Vec3,
            _t_min: f32,
            _t_max: f32,
        ) -> Option<f32> {
            todo!("chapter 11: hit_box")
        }
        fn build_bvh(_bounds: &[Option<Aabb>], _options: &BvhOptions) -> Bvh {
            todo!("chapter 11: build_bvh")
        }
        fn nearest_hit_bvh(
            _bvh: &Bvh,
            _objects: &Objects<Planted>,
            _ray: &Ray,
            _t_min: f32,
            _t_max: f32,
        ) -> Option<Hit> {
            todo!("chapter 11: nearest_hit_bvh")
        }
        fn any_hit_bvh(
            _bvh: &Bvh,
            _objects: &Objects<Planted>,
            _ray: &Ray,
            _t_min: f32,
            _t_max: f32,
        ) -> Option<Hit> {
            todo!("chapter 11: any_hit_bvh")
        }
        fn hit_boxes(
            _boxes: &Boxes4,
            _origin: Vec3,
            _inverse_direction: Vec3,
            _t_min: f32,
            _t_max: f32,
        ) -> Vec4 {
            todo!("chapter 11: hit_boxes")
        }
        fn intersect_triangles(
            _triangles: &Triangles4,
            _ray: &Ray,
            _t_min: f32,
            _t_max: f32,
        ) -> Vec4 {
            todo!("chapter 11: intersect_triangles")
        }
        fn collapse_bvh(_bvh: &Bvh, _shapes: &[Shape]) -> WideBvh {
            todo!("chapter 11: collapse_bvh")
        }
        fn nearest_hit_wide(
            _wide: &WideBvh,
            _objects: &Objects<Planted>,
            _ray: &Ray,
            _t_min: f32,
            _t_max: f32,
        ) -> Option<Hit> {
            todo!("chapter 11: nearest_hit_wide")
        }
        fn any_hit_wide(
            _wide: &WideBvh,
            _objects: &Objects<Planted>,
            _ray: &Ray,
            _t_min: f32,
            _t_max: f32,
        ) -> Option<Hit> {
            todo!("chapter 11: any_hit_wide")
        }
        fn sphere_trace(_surface: &Implicit, _ray: &Ray, _t_min: f32, _t_max: f32) -> Option<f32> {
            todo!("chapter 12: sphere_trace")
        }
        fn newton_bracketed(
            _g: &dyn Fn(f32) -> (f32, f32),
            _bracket: Bracket,
            _tolerance: f32,
            _max_iterations: u32,
        ) -> f32 {
            todo!("chapter 12: newton_bracketed")
        }
        fn implicit_normal(_surface: &Implicit, _point: Vec3) -> Vec3 {
            todo!("chapter 12: implicit_normal")
        }
        fn intersect_implicit(
            _surface: &Implicit,
            _ray: &Ray,
            _t_min: f32,
            _t_max: f32,
        ) -> Option<f32> {
            todo!("chapter 12: intersect_implicit")
        }
    }
}

/// Chapter 13 written over unwritten chapters 4 to 12: it waits for chapter
/// 4, as any chapter waits for a `todo!()` of an earlier one (its stage
/// calls them), with its own checkpoints counted; never a crash of the
/// check, whether asked alone or with every chapter.
#[test]
fn a_chapter_written_past_unwritten_ones_waits_for_the_first() {
    use skips_to_thirteen::SkipsToThirteen;
    let verdict = planted::check_chapter::<SkipsToThirteen>(13, &options());
    let text = verdict.text();
    assert_eq!(verdict.status, Status::Blocked { by: 4 }, "{text}");
    assert_eq!(verdict.needs, Some((4, Status::NotStarted)), "{text}");
    assert!(text.contains("needs ch. 4"), "{text}");
    assert!(
        text.contains(&format!(
            "checkpoints: {} of {} pass",
            verdict.cases_passed, verdict.cases_total
        )),
        "{text}"
    );
    assert!(verdict.cases_passed > 0, "{text}");
    assert!(
        !text.contains("ERROR") && !text.contains("panicked"),
        "{text}"
    );
    let report = planted::check_all::<SkipsToThirteen>(None, &options());
    let thirteen = report
        .verdicts
        .iter()
        .find(|verdict| verdict.chapter == 13)
        .expect("chapter 13");
    assert_eq!(
        thirteen.status,
        Status::Blocked { by: 4 },
        "{}",
        report.text()
    );
    assert_eq!(
        report.overall(),
        raylab::check::Overall::Fail,
        "{}",
        report.text()
    );
    for chapter in 4..=12 {
        let verdict = &report.verdicts[chapter - 1];
        assert_eq!(verdict.status, Status::NotStarted, "{}", verdict.text());
    }
}

/// Chapter 3 not written yet.
struct NearestNotStarted;
plant! {
    NearestNotStarted;
    fn nearest_hit(_objects: &raylab::Objects<Planted>, _ray: &Ray, _t_min: f32, _t_max: f32) -> Option<raylab::Hit> {
        todo!()
    }
}

#[test]
fn a_todo_chapter_is_not_started_and_blocks_the_next() {
    let verdict = planted::check_chapter::<NearestNotStarted>(3, &options());
    assert_eq!(verdict.status, Status::NotStarted, "{}", verdict.text());
    assert!(verdict.text().contains("nearest_hit"), "{}", verdict.text());
    // Chapter 4's own cases pass, but its image needs chapter 3.
    let next = planted::check_chapter::<NearestNotStarted>(4, &options());
    assert_eq!(next.status, Status::Blocked { by: 3 }, "{}", next.text());
    assert!(
        next.text().contains("builds on chapter 3"),
        "{}",
        next.text()
    );
}

/// A chapter 1 that panics for another reason.
struct PlanePanics;
plant! {
    PlanePanics;
    fn intersect_plane(_plane: &Plane, _ray: &Ray, _t_min: f32, _t_max: f32) -> Option<f32> {
        let empty: Vec<f32> = Vec::new();
        empty
            .first()
            .copied()
            .map(Some)
            .unwrap_or_else(|| panic!("no roots at all"))
    }
}

#[test]
fn another_panic_is_a_failure_with_its_message() {
    let verdict = planted::check_chapter::<PlanePanics>(1, &options());
    assert_eq!(verdict.status, Status::Fail);
    assert!(
        verdict.text().contains("a panic: no roots at all"),
        "{}",
        verdict.text()
    );
}

/// Every function still `todo!()`: a fresh student workspace.
struct NothingWritten;
impl planted::Plant for NothingWritten {
    fn plants() -> planted::Plants {
        planted::Plants::nothing_written()
    }
}

#[test]
fn a_fresh_workspace_is_every_chapter_not_started() {
    let report = planted::check_all::<NothingWritten>(None, &options());
    let statuses: Vec<Status> = report.verdicts.iter().map(|v| v.status).collect();
    let chapters = usize::from(raylab::chapters::LAST_CHAPTER);
    assert_eq!(
        statuses,
        vec![Status::NotStarted; chapters],
        "{}",
        report.text()
    );
    assert_eq!(report.overall(), raylab::check::Overall::Fail);
    assert!(!report.text().contains("panicked at"), "{}", report.text());
}

/// With fresh inputs, and each image seen from a moved camera: the moved
/// scenes stay ones the lessons' rules judge (the lessons' own images are
/// the snapshots, pinned in tests/pictures).
#[test]
fn the_reference_passes_every_chapter_at_both_levels() {
    let fresh = CheckOptions {
        fresh: Some(11),
        ..options()
    };
    let report = check_all::<Reference>(None, &fresh);
    for verdict in &report.verdicts {
        let view = verdict.image.as_ref().and_then(|image| image.view);
        let lesson = raylab::builtin::scene(verdict.chapter).expect("a built-in scene");
        assert!(
            view.is_some_and(|view| Vec3::from_array(view.position) != lesson.camera.position),
            "chapter {}: {view:?}",
            verdict.chapter
        );
    }
    assert_eq!(
        report.overall(),
        raylab::check::Overall::Pass,
        "{}",
        report.text()
    );
    assert!(
        report.verdicts.iter().all(ChapterVerdict::robust),
        "{}",
        report.text()
    );
}

#[test]
fn a_failing_image_is_written_with_its_heatmap() {
    let folder = std::env::temp_dir().join(format!("raylab-check-images-{}", std::process::id()));
    let options = CheckOptions {
        failures_dir: folder.clone(),
        write_images: true,
        forbid_answer_key: false,
        fresh: None,
        ..Default::default()
    };
    // A bug only the picture shows (no checkpoint of chapter 1 is further
    // than t = 10): the floor clipped beyond t = 100.
    let verdict = planted::check_chapter::<FarClip>(1, &options);
    assert_eq!(verdict.status, Status::Fail, "{}", verdict.text());
    assert_eq!(verdict.failing_case(), None, "{}", verdict.text());
    let written = verdict
        .image
        .as_ref()
        .map(|i| i.written.clone())
        .unwrap_or_default();
    assert_eq!(
        written,
        vec![
            folder.join("chapter-1.png"),
            folder.join("chapter-1-heatmap.png")
        ]
    );
    assert!(written.iter().all(|path| path.is_file()));
    assert!(
        verdict.text().contains("chapter-1-heatmap.png"),
        "{}",
        verdict.text()
    );
    // Every checkpoint passed: the hint says where to look.
    assert!(
        verdict
            .text()
            .contains("hint:     every checkpoint passes, so look at the heatmap near the horizon"),
        "{}",
        verdict.text()
    );
    // Fixed, the chapter passes and the old pictures go: they would mislead.
    let verdict = check_chapter::<Reference>(1, &options);
    assert_eq!(verdict.status, Status::Pass, "{}", verdict.text());
    assert!(written.iter().all(|path| !path.exists()));
    let _ = std::fs::remove_dir_all(&folder);
}

/// A file in the failures folder that raylab did not write (a student's
/// own `chapter-1.png`) is neither replaced by a failing check nor removed
/// by a passing one; a read-only one is not replaced either.
#[test]
fn foreign_files_in_the_failures_folder_are_kept() {
    let folder = tempfile::tempdir().expect("temp dir");
    let options = CheckOptions {
        failures_dir: folder.path().to_path_buf(),
        write_images: true,
        forbid_answer_key: false,
        fresh: None,
        ..Default::default()
    };
    let own = folder.path().join("chapter-1.png");
    std::fs::write(&own, "a student's own picture").expect("write");
    let verdict = planted::check_chapter::<FarClip>(1, &options);
    assert_eq!(verdict.status, Status::Error, "{}", verdict.text());
    assert!(
        verdict.text().contains("chapter-1.png"),
        "{}",
        verdict.text()
    );
    assert!(
        verdict
            .text()
            .contains("was not written by raylab, so it is kept"),
        "{}",
        verdict.text()
    );
    let verdict = check_chapter::<Reference>(1, &options);
    assert_eq!(verdict.status, Status::Pass, "{}", verdict.text());
    assert_eq!(
        std::fs::read(&own).expect("kept"),
        b"a student's own picture"
    );
}

/// Chapter 1 that drops hits beyond t = 100.
struct FarClip;
plant! {
    FarClip;
    fn intersect_plane(plane: &Plane, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        Reference::intersect_plane(plane, ray, t_min, t_max.min(100.0))
    }
}

/// Chapter 1: a plane test that ignores `t_min` (tests `t > 0` instead).
struct IgnoresTMin;
plant! {
    IgnoresTMin;
    fn intersect_plane(plane: &Plane, ray: &Ray, _t_min: f32, t_max: f32) -> Option<f32> {
        Reference::intersect_plane(plane, ray, 0.0, t_max)
    }
}

#[test]
fn gallery_plane_ignoring_t_min() {
    assert_caught::<IgnoresTMin>(1, "plane-before-t-min");
}

/// Chapter 1 with a minimum distance of its own: hits less than 0.5
/// ahead dropped whatever `t_min` says (every other checkpoint's hit
/// ahead is at `t >= 1`, and the image's camera is far from the floor).
struct DropsNearHits;
plant! {
    DropsNearHits;
    fn intersect_plane(plane: &Plane, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        Reference::intersect_plane(plane, ray, t_min, t_max).filter(|t| *t <= 0.0 || *t > 0.5)
    }
}

/// Chapter 1 that takes "behind the origin" for `t <= 0`, not `t <= t_min`.
struct BehindMeansNegative;
plant! {
    BehindMeansNegative;
    fn intersect_plane(plane: &Plane, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        Reference::intersect_plane(plane, ray, t_min, t_max).filter(|t| *t > 0.0)
    }
}

#[test]
fn gallery_plane_with_a_minimum_distance_or_a_fixed_behind() {
    assert_caught::<DropsNearHits>(1, "plane-close-ahead");
    assert_caught::<BehindMeansNegative>(1, "plane-behind-negative-t-min");
}

// Chapters 9 to 11 keep their bug galleries in their folders (gallery.rs),
// beside their hand-computed values: chapter 9's Schlick with n1 and n2
// swapped, chapter 10's one-sided triangle test and Moller-Trumbore,
// "correct, not yet robust", chapter 11's tree bugs.

// ---------------------------------------------------------------------------
// Samplers: any correct one passes the sampled chapters, whatever its hash
// and its order of cells; one that reuses its jitter does not.

/// A stateless hash of the student's own (murmur3's finaliser over the
/// arguments), not raylab's: another realisation of the same noise.
fn own_random(seed: u64, pixel: (u32, u32), index: u32, dimension: u32) -> f32 {
    let mut word = seed
        .wrapping_mul(0xff51_afd7_ed55_8ccd)
        .wrapping_add((u64::from(pixel.0) << 32) | u64::from(pixel.1))
        .wrapping_add(u64::from(index) << 8 | u64::from(dimension));
    word ^= word >> 33;
    word = word.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    word ^= word >> 29;
    word = word.wrapping_mul(0xff51_afd7_ed55_8ccd);
    word ^= word >> 32;
    (word >> 40) as f32 / (1u64 << 24) as f32
}

/// Jittered sample `index` of `count`, the cells numbered column by column
/// when `column_first`, `jitter(dimension)` its random numbers.
fn jittered(count: u32, index: u32, column_first: bool, jitter: impl Fn(u32) -> f32) -> (f32, f32) {
    let k = count.isqrt().max(1);
    let (column, row) = if column_first {
        (index / k, index % k)
    } else {
        (index % k, index / k)
    };
    let cell = 1.0 / k as f32;
    let inside = |x: f32| x.min(1.0 - f32::EPSILON / 2.0);
    (
        inside((column as f32 + jitter(0)) * cell),
        inside((row as f32 + jitter(1)) * cell),
    )
}

/// Another correct sampler: `salt` changes its hash's seed, and an odd one
/// numbers the cells column by column.
fn salted_offset(
    salt: u64,
    sampling: Sampling,
    count: u32,
    index: u32,
    pixel: (u32, u32),
    seed: u64,
) -> (f32, f32) {
    let random = |dimension| own_random(seed ^ salt, pixel, index, dimension);
    match sampling {
        Sampling::Jittered => jittered(count, index, salt % 2 == 1, random),
        Sampling::Random => (random(0), random(1)),
        Sampling::Grid => Reference::sample_offset(sampling, count, index, pixel, seed),
    }
}

struct OwnHash;
plant! {
    OwnHash;
    fn sample_offset(
        s: Sampling,
        count: u32,
        index: u32,
        pixel: (u32, u32),
        seed: u64,
    ) -> (f32, f32) {
        salted_offset(0, s, count, index, pixel, seed)
    }
}

struct ColumnFirst;
plant! {
    ColumnFirst;
    fn sample_offset(
        s: Sampling,
        count: u32,
        index: u32,
        pixel: (u32, u32),
        seed: u64,
    ) -> (f32, f32) {
        salted_offset(0x1235, s, count, index, pixel, seed)
    }
}

/// The classic slip: the jitter is drawn once per pixel (as if for sample
/// 0) and every cell reuses it, a shifted grid rather than a jittered one.
struct JitterReused;
plant! {
    JitterReused;
    fn sample_offset(
        s: Sampling,
        count: u32,
        index: u32,
        pixel: (u32, u32),
        seed: u64,
    ) -> (f32, f32) {
        match s {
            Sampling::Jittered => jittered(count, index, false, |dimension| {
                own_random(seed, pixel, 0, dimension)
            }),
            _ => Reference::sample_offset(s, count, index, pixel, seed),
        }
    }
}

#[test]
fn another_hash_and_another_order_of_cells_pass_every_sampled_chapter() {
    for chapter in [7, 8, 9] {
        for verdict in [
            assert_passes::<OwnHash>(chapter),
            assert_passes::<ColumnFirst>(chapter),
        ] {
            let image = verdict.image.as_ref().expect("an image");
            let noise = image
                .noise
                .as_ref()
                .unwrap_or_else(|| panic!("chapter {chapter} is judged by its noise"));
            // Not a pixel-for-pixel match: the shipped image would refuse it.
            assert!(image.metrics.pixels_over > 100, "{}", verdict.text());
            assert!(noise.passes(), "{}", verdict.text());
        }
    }
}

/// The seed mixed in by `&` instead of `^`: seeds that differ only where
/// the mask has a zero bit give the same samples (0, 2 and 8 among them),
/// although seeds 0 and 1 still differ.
struct SeedBitsLost;
plant! {
    SeedBitsLost;
    fn sample_offset(
        s: Sampling,
        count: u32,
        index: u32,
        pixel: (u32, u32),
        seed: u64,
    ) -> (f32, f32) {
        Reference::sample_offset(s, count, index, pixel, seed & 0x9E37_79B9_7F4A_7C15)
    }
}

#[test]
fn gallery_seed_bits_lost() {
    assert_caught::<SeedBitsLost>(7, "samples-every-seed-its-own");
}

/// A hash of 32-bit words fed `seed as u32`: seeds 2^32 and 0 render the
/// same noise.
struct SeedUpperHalfLost;
plant! {
    SeedUpperHalfLost;
    fn sample_offset(
        s: Sampling,
        count: u32,
        index: u32,
        pixel: (u32, u32),
        seed: u64,
    ) -> (f32, f32) {
        Reference::sample_offset(s, count, index, pixel, u64::from(seed as u32))
    }
}

#[test]
fn gallery_seed_upper_half_lost() {
    assert_caught::<SeedUpperHalfLost>(7, "samples-every-seed-its-own");
}

#[test]
fn gallery_jitter_reused_for_every_cell() {
    assert_caught::<JitterReused>(7, "samples-jittered-spread");
}

/// Two dozen more correct samplers (each hash seed salted, every other one
/// numbering its cells column by column) pass chapters 7 and 9: the
/// figures quoted at `check::sampled::allowed_outliers` come from here.
#[test]
fn two_dozen_correct_samplers_pass_the_sampled_chapters() {
    static SALT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    struct Salted;
    plant! {
        Salted;
        fn sample_offset(
            s: Sampling,
            count: u32,
            index: u32,
            pixel: (u32, u32),
            seed: u64,
        ) -> (f32, f32) {
            let salt = SALT.load(std::sync::atomic::Ordering::Relaxed);
            salted_offset(salt, s, count, index, pixel, seed)
        }
    }
    for chapter in [7, 9] {
        for salt in 0..24 {
            SALT.store(salt * 7919 + 1, std::sync::atomic::Ordering::Relaxed);
            let verdict = planted::check_chapter::<Salted>(chapter, &options());
            assert!(verdict.passes(), "salt {salt}: {}", verdict.text());
        }
    }
}

/// A student's off-by-one in `nearest_hit` (`0..=len`): the panic names the
/// student's line and the object that does not exist, not raylab's
/// `Objects` that was asked for it.
struct OneObjectTooMany;
plant! {
    OneObjectTooMany;
    fn nearest_hit(
        objects: &raylab::Objects<Planted>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<raylab::Hit> {
        let mut nearest: Option<raylab::Hit> = None;
        for object in 0..=objects.len() {
            let limit = nearest.map_or(t_max, |hit| hit.t);
            if let Some(t) = objects.intersect(object, ray, t_min, limit) {
                nearest = Some(raylab::Hit { object, t });
            }
        }
        nearest
    }
}

#[test]
fn a_panic_in_the_students_loop_names_the_students_line() {
    let verdict = planted::check_chapter::<OneObjectTooMany>(3, &options());
    let text = verdict.text();
    assert_eq!(verdict.status, Status::Fail, "{text}");
    assert!(text.contains("does not exist: there are"), "{text}");
    assert!(text.contains("tests/course/check.rs:"), "{text}");
    assert!(!text.contains("course.rs:"), "{text}");
}

// ---------------------------------------------------------------------------
// Contract clauses: docs/course.md lists each function's contract, clause by
// clause, with the case that a violation of that clause alone fails. Each
// variant below breaks one clause that no case caught before, and fails on
// exactly the case added for it.

/// Chapter 1 with `if denominator == 0.0` for the parallel test, the one
/// the lesson says not to write: right on paper, so every checkpoint
/// passes, but a denominator that is 0 only up to rounding divides into a
/// huge `t` off the plane.
struct PlaneParallelOnlyAtZero;
plant! {
    PlaneParallelOnlyAtZero;
    fn intersect_plane(plane: &Plane, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let denominator = ray.dir.dot(plane.normal());
        if denominator == 0.0 {
            return None;
        }
        let t = (plane.point() - ray.origin).dot(plane.normal()) / denominator;
        (t > t_min && t < t_max).then_some(t)
    }
}

/// Chapter 1 with the parallel test written as the lesson derives its
/// bound, `gamma_3` for the dot product and `2u` for the stored normal,
/// with no margin: tighter than the reference's `8u`, and still robust.
struct PlaneParallelTightBound;
plant! {
    PlaneParallelTightBound;
    // The lesson's `!(|D . N| > bound)`: "not greater, or NaN".
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    fn intersect_plane(plane: &Plane, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let u = f32::EPSILON / 2.0;
        let gamma_3 = 3.0 * u / (1.0 - 3.0 * u);
        let denominator = ray.dir.dot(plane.normal());
        let bound = (gamma_3 + 2.0 * u) * ray.dir.abs().dot(plane.normal().abs());
        if !(denominator.abs() > bound) {
            return None;
        }
        let t = (plane.point() - ray.origin).dot(plane.normal()) / denominator;
        (t > t_min && t < t_max).then_some(t)
    }
}

/// Chapter 1 with the bound scaled by `|D| |N|` instead of
/// `sum |D_i| |N_i|`: never smaller (Cauchy-Schwarz), so it calls at least
/// as many rays parallel, and still finds every hit the hard cases ask for.
struct PlaneParallelBoundByLengths;
plant! {
    PlaneParallelBoundByLengths;
    // The lesson's `!(|D . N| > bound)`: "not greater, or NaN".
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    fn intersect_plane(plane: &Plane, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let denominator = ray.dir.dot(plane.normal());
        let bound = 4.0 * f32::EPSILON * ray.dir.length() * plane.normal().length();
        if !(denominator.abs() > bound) {
            return None;
        }
        let t = (plane.point() - ray.origin).dot(plane.normal()) / denominator;
        (t > t_min && t < t_max).then_some(t)
    }
}

/// Chapter 2: `t_min` taken as a closed bound: a root exactly at `t_min`
/// is the hit.
struct SphereTMinClosed;
plant! {
    SphereTMinClosed;
    fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let (near, far) = sphere.roots(ray)?;
        [near, far].into_iter().find(|&t| t >= t_min && t < t_max)
    }
}

/// Chapter 3: the objects walked last to first: on a tie the last listed wins.
struct NearestTieLastWins;
plant! {
    NearestTieLastWins;
    fn nearest_hit(
        objects: &raylab::course::Objects<Planted>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<raylab::course::Hit> {
        let mut nearest = None;
        let mut closest = t_max;
        for object in (0..objects.len()).rev() {
            if let Some(t) = objects.intersect(object, ray, t_min, closest) {
                closest = t;
                nearest = Some(raylab::course::Hit { object, t });
            }
        }
        nearest
    }
}

/// Chapter 4: the shadow ray's direction made unit, but still stopped at
/// `t = 1`: one unit from the point, not at the light.
struct ShadowUnitDirection;
plant! {
    ShadowUnitDirection;
    fn in_shadow(tracer: &mut Tracer<Planted>, point: &HitPoint, light: Vec3) -> bool {
        let origin = tracer.offset_origin(&point.surface, light - point.surface.point);
        let ray = Ray::new(origin, (light - origin).normalize());
        tracer.blocked(&ray, 0.0, 1.0, point)
    }
}

/// Chapter 4: the unnormalised shadow ray stopped at the light's distance
/// (`t_max = |L - P|`), which is in lengths of the direction past the light.
struct ShadowDistanceAsTMax;
plant! {
    ShadowDistanceAsTMax;
    fn in_shadow(tracer: &mut Tracer<Planted>, point: &HitPoint, light: Vec3) -> bool {
        let origin = tracer.offset_origin(&point.surface, light - point.surface.point);
        let ray = Ray::new(origin, light - origin);
        tracer.blocked(&ray, 0.0, (light - origin).length(), point)
    }
}

/// Flat lighting with the light's side tested against the geometric normal
/// rather than the one turned to the eye; `colour_only` drops the light's
/// colour (intensity alone).
fn flat<C: Chapters>(
    tracer: &mut Tracer<C>,
    point: &HitPoint,
    geometric: bool,
    intensity_only: bool,
) -> Vec3 {
    let material = &point.material;
    let mut color = point.albedo * material.ambient * tracer.ambient_light();
    for light in tracer.lights() {
        let normal = if geometric {
            point.surface.normal
        } else {
            point.normal
        };
        if normal.dot(light.position - point.surface.point) <= 0.0
            || C::in_shadow(tracer, point, light.position)
        {
            continue;
        }
        let radiance = if intensity_only {
            Vec3::splat(light.intensity)
        } else {
            light.radiance()
        };
        color += point.albedo * material.diffuse * radiance;
    }
    color
}

/// Chapter 4: a light "in front" only of the geometric normal's side.
struct FlatGeometricNormal;
plant! {
    FlatGeometricNormal;
    fn shade_flat(tracer: &mut Tracer<Planted>, point: &HitPoint) -> Vec3 {
        flat(tracer, point, true, false)
    }
}

/// Chapter 4: a light's intensity without its colour.
struct FlatLightColourLost;
plant! {
    FlatLightColourLost;
    fn shade_flat(tracer: &mut Tracer<Planted>, point: &HitPoint) -> Vec3 {
        flat(tracer, point, false, true)
    }
}

/// Chapter 5: the textbook terms `max(0, n.l)` and `max(0, r.v)^s`, with
/// no test that the light is in front: a light behind still makes a
/// highlight where its mirror image points at the eye.
struct SpecularFromBehind;
plant! {
    SpecularFromBehind;
    fn phong_terms(
        material: &Material,
        albedo: Vec3,
        normal: Vec3,
        to_light: Vec3,
        to_eye: Vec3,
        light: Vec3,
    ) -> PhongTerms {
        let cos_i = normal.dot(to_light);
        let r = 2.0 * cos_i * normal - to_light;
        PhongTerms {
            diffuse: albedo * material.diffuse * cos_i.max(0.0) * light,
            specular: material.specular
                * r.dot(to_eye).max(0.0).powi(material.shininess as i32)
                * light,
        }
    }
}

/// Chapter 5: the Phong sum lit by each light's intensity, its colour lost.
struct PhongLightColourLost;
plant! {
    PhongLightColourLost;
    fn shade_phong(tracer: &mut Tracer<Planted>, point: &HitPoint) -> PhongTerms {
        let material = &point.material;
        let mut sum = PhongTerms {
            diffuse: point.albedo * material.ambient * tracer.ambient_light(),
            specular: Vec3::ZERO,
        };
        for light in tracer.lights() {
            if !point.faces(light.position) || Planted::in_shadow(tracer, point, light.position) {
                continue;
            }
            let to_light = (light.position - point.surface.point).normalize();
            let terms = Planted::phong_terms(
                material,
                point.albedo,
                point.normal,
                to_light,
                point.to_eye,
                Vec3::splat(light.intensity),
            );
            sum.diffuse += terms.diffuse;
            sum.specular += terms.specular;
        }
        sum
    }
}

/// Chapter 6: the highlight scaled by `1 - k_r` with the diffuse light.
struct MirrorHighlightScaled;
plant! {
    MirrorHighlightScaled;
    fn shade_mirror(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        let local = Planted::shade_phong(tracer, point);
        let k = point.material.reflectivity;
        let mut color = (1.0 - k) * (local.diffuse + local.specular);
        if depth < tracer.max_depth() && tracer.worth_casting(weight, k) {
            let dir = Planted::reflect(point.ray.dir, point.surface.normal);
            let ray = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
            color += k * tracer.trace(RayKind::Reflection, &ray, depth + 1, weight * k);
        }
        color
    }
}

/// Chapter 7: four samples a pixel, whatever the scene asks.
struct FourSamplesAlways;
plant! {
    FourSamplesAlways;
    fn pixel_color(tracer: &mut Tracer<Planted>, x: u32, y: u32) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for index in 0..4 {
            let (dx, dy) = tracer.sample_offset(index, (x, y));
            sum += tracer.sample(x as f32 + dx, y as f32 + dy);
        }
        sum / 4.0
    }
}

/// Chapter 8's glass mix with a switch for each clause broken here: the
/// highlight scaled with the diffuse light, the refracted ray traced at
/// the same depth as its parent.
fn glass_clauses<C: Chapters>(
    tracer: &mut Tracer<C>,
    point: &HitPoint,
    depth: u32,
    weight: f32,
    highlight_scaled: bool,
    refracted_same_depth: bool,
) -> Vec3 {
    let local = C::shade_phong(tracer, point);
    let material = &point.material;
    let (k_r, k_t) = (material.reflectivity, material.transparency);
    let own = 1.0 - k_r - k_t;
    let mut color = if highlight_scaled {
        own * (local.diffuse + local.specular)
    } else {
        own * local.diffuse + local.specular
    };
    if depth >= tracer.max_depth() {
        return color;
    }
    let incoming = point.ray.dir;
    let normal = point.surface.normal;
    let mut reflected_share = k_r;
    if tracer.worth_casting(weight, k_t) {
        let eta = if incoming.dot(normal) < 0.0 {
            1.0 / material.ior
        } else {
            material.ior
        };
        match C::refract(incoming, normal, eta) {
            Some(dir) => {
                let ray = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
                let next = if refracted_same_depth {
                    depth
                } else {
                    depth + 1
                };
                let through = tracer.trace(RayKind::Refraction, &ray, next, weight * k_t);
                color += k_t * material.color * through;
            }
            None => reflected_share += k_t,
        }
    }
    if tracer.worth_casting(weight, reflected_share) {
        let dir = C::reflect(incoming, normal);
        let ray = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
        let seen = tracer.trace(
            RayKind::Reflection,
            &ray,
            depth + 1,
            weight * reflected_share,
        );
        color += reflected_share * seen;
    }
    color
}

/// Chapter 8: the highlight scaled by `1 - k_r - k_t`.
struct GlassHighlightScaled;
plant! {
    GlassHighlightScaled;
    fn shade_glass(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        glass_clauses(tracer, point, depth, weight, true, false)
    }
}

/// Chapter 8: the refracted ray not one bounce deeper than its parent.
struct RefractedDepthNotCounted;
plant! {
    RefractedDepthNotCounted;
    fn shade_glass(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        glass_clauses(tracer, point, depth, weight, false, true)
    }
}

/// Chapter 9: a ray leaving a solid it was never seen entering (a camera
/// inside it) taken to cross nothing: the pair of media is (current,
/// current) instead of (the solid, outside).
struct UnseenSolidIgnored;
plant! {
    UnseenSolidIgnored;
    fn crossing(media: &raylab::medium::MediumStack, point: &HitPoint) -> raylab::medium::Crossing {
        let crossing = Reference::crossing(media, point);
        if !crossing.entering && !media.contains(point.object) {
            let outside = media.leaving(point.object);
            return raylab::medium::Crossing {
                entering: false,
                n1: media.current().ior,
                n2: outside.current().ior,
                before: *media,
                beyond: outside,
            };
        }
        crossing
    }
}

/// Chapter 11: the slab test's closed interval taken as open
/// (`entry < exit`): a box touched at a single `t` is missed.
struct BoxIntervalOpen;
plant! {
    BoxIntervalOpen;
    fn hit_box(
        bounds: &raylab::bvh::Aabb,
        origin: Vec3,
        inverse_direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<f32> {
        let entry = Reference::hit_box(bounds, origin, inverse_direction, t_min, t_max)?;
        let exit = (0..3)
            .map(|axis| {
                let inverse = inverse_direction[axis];
                let far = if inverse.is_sign_negative() {
                    bounds.min[axis]
                } else {
                    bounds.max[axis]
                };
                let far = (far - origin[axis]) * inverse;
                if far.is_nan() { f32::INFINITY } else { far }
            })
            .fold(t_max, f32::min);
        (entry < exit).then_some(entry)
    }
}

#[test]
fn contract_sphere_t_min_is_open() {
    assert_caught::<SphereTMinClosed>(2, "sphere-near-root-at-t-min");
}

#[test]
fn contract_nearest_tie_goes_to_the_first_listed() {
    assert_caught::<NearestTieLastWins>(3, "nearest-tie-first-listed");
}

#[test]
fn contract_shadow_ray_reaches_the_light() {
    assert_caught::<ShadowUnitDirection>(4, "shadow-blocker-far-from-the-point");
}

#[test]
fn contract_shadow_ray_stops_at_the_light() {
    assert_caught::<ShadowDistanceAsTMax>(4, "shadow-blocker-just-beyond-light");
}

#[test]
fn contract_flat_light_faces_the_side_seen() {
    assert_caught::<FlatGeometricNormal>(4, "flat-lit-from-below");
}

#[test]
fn contract_flat_light_has_a_colour() {
    assert_caught::<FlatLightColourLost>(4, "flat-coloured-light");
}

#[test]
fn contract_phong_light_behind_adds_no_highlight() {
    assert_caught::<SpecularFromBehind>(5, "phong-light-behind-eye-at-its-mirror");
}

#[test]
fn contract_phong_light_has_a_colour() {
    assert_caught::<PhongLightColourLost>(5, "phong-sum-coloured-light");
}

#[test]
fn contract_mirror_highlight_in_full() {
    assert_caught::<MirrorHighlightScaled>(6, "mirror-highlight-in-full");
}

/// Chapter 6 on a smooth mesh: the mirror image about the facet's normal,
/// as if the blended vertex normal were only for the Phong terms.
struct FacetMirror;
plant! {
    FacetMirror;
    fn shade_mirror(tracer: &mut Tracer<Planted>, point: &HitPoint, depth: u32, weight: f32) -> Vec3 {
        let local = Planted::shade_phong(tracer, point);
        let k = point.material.reflectivity;
        let mut color = (1.0 - k) * local.diffuse + local.specular;
        if depth < tracer.max_depth() && tracer.worth_casting(weight, k) {
            let dir = Planted::reflect(point.ray.dir, facet_normal(point).normal);
            let ray = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
            color += k * tracer.trace(RayKind::Reflection, &ray, depth + 1, weight * k);
        }
        color
    }
}

/// Chapter 9 on a smooth mesh: bent and reflected about the facet's normal.
struct FacetGlass;
plant! {
    FacetGlass;
    fn shade_dielectric(
        tracer: &mut Tracer<Planted>,
        point: &HitPoint,
        depth: u32,
        weight: f32,
    ) -> Vec3 {
        raylab::chapters::ch09_glass::shade_dielectric::<Planted>(
            tracer,
            &facet_normal(point),
            depth,
            weight,
        )
    }
}

/// `point` with its shading normal replaced by the facet's, turned toward
/// the eye.
fn facet_normal<'a>(point: &HitPoint<'a>) -> HitPoint<'a> {
    let mut facet = *point;
    let geometric = point.surface.normal;
    facet.normal = if point.to_eye.dot(geometric) >= 0.0 {
        geometric
    } else {
        -geometric
    };
    facet
}

#[test]
fn contract_smooth_mirror_follows_the_shading_normal() {
    assert_caught::<FacetMirror>(10, "smooth-mirror-shading-normal");
    // Planes and spheres have one normal: chapter 6 itself cannot tell.
    assert_passes::<FacetMirror>(6);
}

#[test]
fn contract_smooth_glass_follows_the_shading_normal() {
    assert_caught::<FacetGlass>(10, "smooth-glass-shading-normal");
    assert_passes::<FacetGlass>(9);
}

/// Chapter 5: the facing test on the plane's own normal, not the one
/// turned toward the eye: a floor seen and lit from below stays dark.
struct PhongGeometricNormal;
plant! {
    PhongGeometricNormal;
    fn shade_phong(tracer: &mut Tracer<Planted>, point: &HitPoint) -> PhongTerms {
        let mut unturned = *point;
        unturned.normal = point.surface.normal;
        raylab::chapters::ch05_phong::shade_phong::<Planted>(tracer, &unturned)
    }
}

/// Chapter 9: the highlight scaled by the local share `1 - k_r - k_t`.
struct DielectricHighlightScaled;
plant! {
    DielectricHighlightScaled;
    fn shade_dielectric(
        tracer: &mut Tracer<Planted>,
        point: &HitPoint,
        depth: u32,
        weight: f32,
    ) -> Vec3 {
        let full =
            raylab::chapters::ch09_glass::shade_dielectric::<Planted>(tracer, point, depth, weight);
        let passed_on = point.material.reflectivity + point.material.transparency;
        full - passed_on * Planted::shade_phong(tracer, point).specular
    }
}

/// Chapter 9: rays cast at the depth limit (`depth <= max_depth`): one
/// bounce too many, once (the bounce it adds is at the limit again, and
/// is not extended).
struct DielectricOneBounceTooMany;
thread_local! {
    static EXTENDING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}
plant! {
    DielectricOneBounceTooMany;
    fn shade_dielectric(
        tracer: &mut Tracer<Planted>,
        point: &HitPoint,
        depth: u32,
        weight: f32,
    ) -> Vec3 {
        let shade = raylab::chapters::ch09_glass::shade_dielectric::<Planted>;
        if depth == tracer.max_depth() && depth > 0 && !EXTENDING.get() {
            EXTENDING.set(true);
            let color = shade(tracer, point, depth - 1, weight);
            EXTENDING.set(false);
            color
        } else {
            shade(tracer, point, depth, weight)
        }
    }
}

/// Chapter 9: an infinite distance taken as no distance at all.
struct InfinityKeepsEverything;
plant! {
    InfinityKeepsEverything;
    fn transmittance(absorption: Vec3, distance: f32) -> Vec3 {
        if distance.is_infinite() {
            Vec3::ONE
        } else {
            Reference::transmittance(absorption, distance)
        }
    }
}

/// Chapter 4: an infinite point stepped off like a finite one, to
/// f32::MAX (the guard for non-finite points left out).
struct InfinityStepsToMax;
plant! {
    InfinityStepsToMax;
    fn offset_origin(surface: &SurfacePoint, dir: Vec3) -> Vec3 {
        if surface.point.is_finite() {
            Reference::offset_origin(surface, dir)
        } else {
            surface
                .point
                .map(|coordinate| coordinate.clamp(-f32::MAX, f32::MAX))
        }
    }
}

/// Chapter 5: the highlight's cosine clamped with `f32::max`, which turns
/// a NaN into 0.
struct PhongNanClamped;
plant! {
    PhongNanClamped;
    fn phong_terms(
        material: &Material,
        albedo: Vec3,
        normal: Vec3,
        to_light: Vec3,
        to_eye: Vec3,
        light: Vec3,
    ) -> PhongTerms {
        let terms = Reference::phong_terms(material, albedo, normal, to_light, to_eye, light);
        PhongTerms {
            diffuse: terms.diffuse,
            specular: terms.specular.map(|term| term.max(0.0)),
        }
    }
}

#[test]
fn contract_plane_parallel_up_to_rounding() {
    let verdict = planted::check_chapter::<PlaneParallelOnlyAtZero>(1, &options());
    let text = verdict.text();
    assert!(verdict.passes(), "{text}");
    assert!(!verdict.robust(), "{text}");
    let failure = verdict
        .robustness
        .as_ref()
        .and_then(|robustness| robustness.first_failure.as_ref())
        .expect("a hard case fails");
    assert_eq!(failure.name, "plane-parallel-denominator-rounded", "{text}");
}

#[test]
fn alternative_plane_parallel_bounds_are_robust() {
    let verdict = planted::check_chapter::<PlaneParallelTightBound>(1, &options());
    assert!(verdict.robust(), "{}", verdict.text());
    let verdict = planted::check_chapter::<PlaneParallelBoundByLengths>(1, &options());
    assert!(verdict.robust(), "{}", verdict.text());
}

/// A hard case catches `C` in `chapter`: correct, not robust.
fn assert_not_robust<C: Plant>(chapter: u8, case: &str) {
    planted::with::<C, _>(|| {
        let verdict = check_chapter::<Planted>(chapter, &options());
        let text = verdict.text();
        assert!(verdict.passes(), "{text}");
        assert!(!verdict.robust(), "{text}");
        assert!(text.contains(case), "{text}");
    })
}

#[test]
fn contract_offset_of_an_infinite_point() {
    assert_not_robust::<InfinityStepsToMax>(4, "offset-infinite-point");
}

#[test]
fn contract_phong_nan_is_not_hidden() {
    assert_not_robust::<PhongNanClamped>(5, "phong-nan-to-eye");
}

#[test]
fn contract_phong_light_faces_the_side_seen() {
    assert_caught::<PhongGeometricNormal>(5, "phong-sum-lit-from-below");
}

#[test]
fn contract_dielectric_highlight_in_full() {
    assert_caught::<DielectricHighlightScaled>(9, "dielectric-highlight-in-full");
}

#[test]
fn contract_dielectric_depth_limit() {
    assert_caught::<DielectricOneBounceTooMany>(9, "dielectric-depth-limit");
}

#[test]
fn contract_transmittance_of_an_infinite_ray() {
    assert_not_robust::<InfinityKeepsEverything>(9, "transmittance-absorbing-forever");
}

#[test]
fn contract_pixel_takes_the_scenes_sample_count() {
    assert_caught::<FourSamplesAlways>(7, "pixel-nine-samples");
}

#[test]
fn contract_glass_highlight_in_full() {
    assert_caught::<GlassHighlightScaled>(8, "glass-highlight-in-full");
}

#[test]
fn contract_glass_refracted_ray_one_deeper() {
    assert_caught::<RefractedDepthNotCounted>(8, "glass-depth-counts-refractions");
}

#[test]
fn contract_crossing_a_solid_never_entered() {
    assert_caught::<UnseenSolidIgnored>(9, "dielectric-inside-all-along");
}

#[test]
fn contract_box_interval_is_closed() {
    assert_caught::<BoxIntervalOpen>(11, "box-flat-touched-at-t-min");
}
