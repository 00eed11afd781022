//! The seam between the chapters and the engine: the types both sides
//! speak, in a module that uses nothing of either, so that the tools that
//! read rays (`crosscheck`, `trace`, the page) and the chapters that shade
//! points need only this and not the tracer.
//!
//! What a ray met ([`Hit`]) and the point a shading function colours
//! ([`HitPoint`]); the kinds of ray, their counts and the log that sees
//! them ([`RayKind`], [`RayCounts`], [`RayLog`], [`CastRay`]); how a ray
//! came to be cast ([`Arrival`]); and the lobes of chapter 13's scattering
//! and chapter 14's dispersed index ([`Lobe`], [`Dispersed`]).

use crate::shapes::{Shape, Sphere, SurfacePoint};
use crate::{Material, Ray, Vec3};

/// Which object a ray met, and where along the ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Index of the object in the list that was searched.
    pub object: usize,
    /// Ray parameter of the hit, in units of the ray's direction.
    pub t: f32,
}

/// What a shading function knows about the point it colours.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HitPoint<'a> {
    /// The object hit (an index into the tracer's objects).
    pub object: usize,
    /// The solid the object is part of, for chapter 9's media: the scene's
    /// object it belongs to, so that every triangle of a glass mesh is one
    /// solid, entered by one triangle and left by another.
    pub solid: usize,
    /// The ray that arrived here.
    pub ray: Ray,
    /// Where, exactly, with its error bound and the geometric normal.
    pub surface: SurfacePoint,
    pub material: &'a Material,
    /// The material's colour at this point (its checker applied).
    pub albedo: Vec3,
    /// Unit vector from the point toward where the ray came from.
    pub to_eye: Vec3,
    /// The unit normal turned toward the side the ray arrived on: the side
    /// that is lit.
    pub normal: Vec3,
    /// The sphere this point is on, when the ray arrived from inside it.
    inside_sphere: Option<Sphere>,
}

impl<'a> HitPoint<'a> {
    /// The light the point's material gives off toward the eye: its
    /// emission seen from the front, or from either side when it is two
    /// sided; nothing from behind a one-sided emitter.
    #[inline]
    pub fn emitted(&self) -> Vec3 {
        let seen_from_front = self.surface.normal.dot(self.to_eye) > 0.0;
        if self.material.two_sided || seen_from_front {
            self.material.emission
        } else {
            Vec3::ZERO
        }
    }

    /// The point where `ray` met `shape` (object number `object`) at `t`.
    #[inline]
    pub fn new(
        object: usize,
        shape: &Shape,
        material: &'a Material,
        ray: &Ray,
        t: f32,
    ) -> HitPoint<'a> {
        let surface = shape.surface_point(ray, t);
        let to_eye = -ray.dir.normalize();
        let from_outside = surface.normal.dot(to_eye) >= 0.0;
        HitPoint {
            object,
            solid: object,
            ray: *ray,
            surface,
            material,
            albedo: material.albedo_at(shape, surface.point),
            to_eye,
            normal: if from_outside {
                surface.normal
            } else {
                -surface.normal
            },
            inside_sphere: if from_outside {
                None
            } else {
                shape.as_sphere().copied()
            },
        }
    }

    /// The point with `normal` as its surface's geometric normal (chapter
    /// 12's, for an implicit surface), turned toward the eye as
    /// [`HitPoint::new`] turns it.
    pub fn with_normal(mut self, normal: Vec3) -> HitPoint<'a> {
        self.surface.normal = normal;
        self.normal = if normal.dot(self.to_eye) >= 0.0 {
            normal
        } else {
            -normal
        };
        self
    }

    /// The point as part of the solid `solid` (a triangle of a mesh is part
    /// of the mesh: see [`HitPoint::solid`]).
    pub fn with_solid(mut self, solid: usize) -> HitPoint<'a> {
        self.solid = solid;
        self
    }

    /// The point with another `material` (chapter 14: a dispersive glass
    /// with the index of the path's wavelength).
    pub fn with_material<'b>(&self, material: &'b Material) -> HitPoint<'b>
    where
        'a: 'b,
    {
        HitPoint { material, ..*self }
    }

    /// Whether a light at `light` can shine on the side of the surface the
    /// ray arrived on, before any shadow test: it must be in front of that
    /// side, and, seen from inside a sphere, inside the same sphere (the
    /// sphere itself hides every light outside it, no ray needed).
    #[inline]
    pub fn faces(&self, light: Vec3) -> bool {
        self.normal.dot(light - self.surface.point) > 0.0
            && self
                .inside_sphere
                .is_none_or(|sphere| sphere.contains(light))
    }
}

/// The kinds of ray a render casts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RayKind {
    Primary,
    Shadow,
    Reflection,
    Refraction,
    /// A ray scattered at random off a diffuse or glossy surface (chapter 13).
    Bounce,
    /// A ray of a path traced from a light (chapter 14).
    Light,
    /// A ray from a point a light path lit toward the camera (chapter 14):
    /// unless something blocks it, the point's light reaches the image.
    ToCamera,
}

impl RayKind {
    /// Every kind, in the order declared: the order of [`RayCounts::cast`],
    /// of the `"rays"` JSON objects and of `cost.csv`'s ray columns. A new
    /// kind is a variant, its place here and its [`RayKind::name`]; the
    /// counts, the JSON and the CSV follow.
    pub const ALL: [RayKind; 7] = [
        RayKind::Primary,
        RayKind::Shadow,
        RayKind::Reflection,
        RayKind::Refraction,
        RayKind::Bounce,
        RayKind::Light,
        RayKind::ToCamera,
    ];

    /// How many kinds there are.
    pub const COUNT: usize = RayKind::ALL.len();

    /// The kind's one name, wherever raylab writes it: the keys of the
    /// `"rays"` JSON objects (`raylab render --json`, the page), `cost.csv`'s
    /// `rays_<name>` columns, `raylab trace` and `raylab crosscheck`.
    pub const fn name(self) -> &'static str {
        match self {
            RayKind::Primary => "primary",
            RayKind::Shadow => "shadow",
            RayKind::Reflection => "reflection",
            RayKind::Refraction => "refraction",
            RayKind::Bounce => "bounce",
            RayKind::Light => "light",
            RayKind::ToCamera => "to_camera",
        }
    }

    /// The kind's place in [`RayKind::ALL`] (and in [`RayCounts::cast`]).
    pub const fn index(self) -> usize {
        self as usize
    }
}

// `ALL` lists the kinds in their declared order, so that `index` is a
// kind's place in it.
const _: () = {
    let mut place = 0;
    while place < RayKind::COUNT {
        assert!(RayKind::ALL[place].index() == place);
        place += 1;
    }
};

/// Something that wants to see every ray the tracer casts (for
/// `raylab crosscheck` and `raylab trace`); counting is built into the
/// tracer. For each ray, in the order the tracer computes them: `cast`,
/// then `met` with what it found, then (for every kind but shadow rays,
/// once the point is shaded, after the rays its shading cast) `returned`
/// with the colour it brings back.
pub trait RayLog {
    /// A ray of `kind` is about to be traced, looking for hits in `(t_min, t_max)`.
    fn cast(&mut self, kind: RayKind, ray: &Ray, t_min: f32, t_max: f32);
    /// The share of the pixel the ray just cast carries (every kind but
    /// shadow rays): 1 for a camera ray, and what the chapters passed to
    /// [`crate::render::Tracer::trace`] for a bounce (a mirror's reflectivity, glass's
    /// Fresnel split, times the parent's share).
    fn weighted(&mut self, _weight: f32) {}
    /// What the ray just cast met: the nearest hit, or for a shadow ray
    /// the blocker found; `None` when nothing is in its range.
    fn met(&mut self, _hit: Option<Hit>) {}
    /// The colour the innermost ray still being shaded brings back.
    fn returned(&mut self, _color: Vec3) {}
}

/// How many rays of each kind a render cast, and how many went wrong.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Rays cast, by kind: `cast[kind.index()]`, in the order of
    /// [`RayKind::ALL`] (read one with [`RayCounts::of`]).
    pub cast: [u64; RayKind::COUNT],
    /// Paths traced from the lights (chapter 14).
    pub light_paths: u64,
    /// Of the points light paths joined to the camera, those whose light
    /// landed on a pixel (chapter 14).
    pub splats: u64,
    /// Shadow rays that hit the primitive they started on, where the exact
    /// segment does not (acne). Only the first blocker in scene order is
    /// examined, so this may undercount.
    pub self_shadow_hits: u64,
    /// Pixels with at least one such shadow ray: the acne a student sees.
    /// Only [`crate::render::render`] fills it in (a tracer sees rays, not pixels).
    pub self_shadowed_pixels: u64,
    /// Samples whose colour was NaN or infinite (written as black).
    pub non_finite_samples: u64,
    /// Path-traced samples brighter than [`crate::render::FIREFLY_FACTOR`] times the
    /// brightest thing a camera ray can see (chapter 13's fireflies): kept
    /// in the image as they are, counted here.
    pub bright_samples: u64,
    /// Rays marched against an implicit surface (chapter 12), once per
    /// ray and surface, by the evaluations each march made.
    pub march_histogram: crate::shapes::MarchHistogram,
    /// Evaluations of implicit functions, for marching and normals.
    pub implicit_evaluations: u64,
    /// Of those, the ones spent on normals (chapter 12's differences).
    pub normal_evaluations: u64,
}

impl RayCounts {
    /// The rays of `kind` cast.
    pub fn of(&self, kind: RayKind) -> u64 {
        self.cast[kind.index()]
    }

    /// Every kind with its count, in the order of [`RayKind::ALL`]: what
    /// every listing of the counts by kind is written from.
    pub fn by_kind(&self) -> impl Iterator<Item = (RayKind, u64)> + '_ {
        RayKind::ALL.into_iter().map(|kind| (kind, self.of(kind)))
    }

    /// The counts by kind as a JSON object, `{name: count}` by
    /// [`RayKind::name`], in the order of [`RayKind::ALL`]: the `"rays"` of
    /// `raylab render --json` and of the page's answers, which each add
    /// their own keys.
    pub fn by_kind_json(&self) -> serde_json::Map<String, serde_json::Value> {
        self.by_kind()
            .map(|(kind, count)| (kind.name().to_string(), count.into()))
            .collect()
    }

    /// Rays of every kind.
    pub fn total(&self) -> u64 {
        self.cast.iter().sum()
    }

    /// Rays marched against an implicit surface, once per ray and surface.
    pub fn implicit_marches(&self) -> u64 {
        self.march_histogram.marches()
    }

    pub(crate) fn add(mut self, other: RayCounts) -> RayCounts {
        for (mine, theirs) in self.cast.iter_mut().zip(other.cast) {
            *mine += theirs;
        }
        self.light_paths += other.light_paths;
        self.splats += other.splats;
        self.bright_samples += other.bright_samples;
        self.self_shadow_hits += other.self_shadow_hits;
        self.self_shadowed_pixels += other.self_shadowed_pixels;
        self.non_finite_samples += other.non_finite_samples;
        self.march_histogram = self.march_histogram.add(&other.march_histogram);
        self.implicit_evaluations += other.implicit_evaluations;
        self.normal_evaluations += other.normal_evaluations;
        self
    }

    /// One more ray of `kind`.
    pub(crate) fn count(&mut self, kind: RayKind) {
        self.cast[kind.index()] += 1;
    }
}

/// One ray as the tracer cast it: what [`crate::record::RayRecorder`] keeps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CastRay {
    pub kind: RayKind,
    pub ray: Ray,
    /// The tracer looked for hits with `t_min < t < t_max`.
    pub t_min: f32,
    pub t_max: f32,
}

/// How the ray being shaded came to be cast (chapter 13), which decides how
/// much of the light it finds on an emitter counts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Arrival {
    /// A camera ray.
    Camera,
    /// A mirror's or glass's one direction: no light sample could have
    /// found the same light.
    Specular,
    /// Scattered at random from a diffuse or glossy surface with this
    /// density, per unit solid angle.
    Scattered { pdf: f32 },
    /// A mirror's or glass's ray on a path whose point nearest the camera
    /// is diffuse or glossy, while chapter 14's light paths run: a light
    /// this ray finds is a caustic seen by the camera, which the light
    /// paths bring to the image. Counted by both, it would count twice.
    Caustic,
}

/// One way a surface scatters light, chosen at random among its material's
/// at each visit: glass with probability `transparency`, a mirror (glossy
/// when it has a roughness) with `reflectivity`, Lambert's diffuse
/// reflection otherwise. Choosing a lobe with the probability that is its
/// share of the material, and then following it alone, estimates the whole
/// material's scattering without bias.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Lobe {
    /// Lambert: `albedo / pi` in every direction above the surface.
    Diffuse { albedo: Vec3 },
    /// Glossy metal: the normalised Phong lobe about the mirror direction,
    /// `albedo (n + 2) / (2 pi) cos^n(alpha)` (Lafortune and Willems 1994),
    /// which never returns more light than arrives.
    Glossy { albedo: Vec3, exponent: f32 },
    /// A perfect mirror tinted by `albedo`: one direction.
    Mirror { albedo: Vec3 },
    /// Chapter 9's glass: reflected or refracted by Fresnel's odds.
    Glass,
}

/// The index of refraction a path sees in a dispersive glass, for its
/// wavelength, and the colour its light is multiplied by there (chapter
/// 14's `dispersive_ior`): the colour of the wavelength on the surface
/// where the path drew it, white on the later ones.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dispersed {
    pub ior: f32,
    pub tint: Vec3,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_has_its_own_name_and_its_own_place() {
        let mut names: Vec<&str> = RayKind::ALL.iter().map(|kind| kind.name()).collect();
        assert_eq!(
            names,
            [
                "primary",
                "shadow",
                "reflection",
                "refraction",
                "bounce",
                "light",
                "to_camera"
            ]
        );
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), RayKind::COUNT, "two kinds share a name");
        for (place, kind) in RayKind::ALL.into_iter().enumerate() {
            assert_eq!(kind.index(), place, "{kind:?}");
            // A name is a JSON key, a CSV column's tail and a word of text.
            assert!(
                kind.name()
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c == '_'),
                "{kind:?}"
            );
        }
    }

    #[test]
    fn counting_reading_and_adding_agree() {
        let mut counts = RayCounts::default();
        for (place, kind) in RayKind::ALL.into_iter().enumerate() {
            for _ in 0..=place {
                counts.count(kind);
            }
        }
        for (place, (kind, count)) in counts.by_kind().enumerate() {
            assert_eq!(kind, RayKind::ALL[place]);
            assert_eq!(count, place as u64 + 1);
            assert_eq!(counts.of(kind), count);
        }
        let n = RayKind::COUNT as u64;
        assert_eq!(counts.total(), n * (n + 1) / 2);
        let twice = counts.add(counts);
        assert!(
            RayKind::ALL
                .into_iter()
                .all(|kind| twice.of(kind) == 2 * counts.of(kind))
        );
        assert_eq!(twice.total(), 2 * counts.total());
    }

    #[test]
    fn the_json_has_one_key_a_kind_with_its_count() {
        let mut counts = RayCounts::default();
        counts.count(RayKind::Shadow);
        counts.count(RayKind::ToCamera);
        counts.count(RayKind::ToCamera);
        let json = counts.by_kind_json();
        let keys: Vec<&str> = json.keys().map(String::as_str).collect();
        let mut names: Vec<&str> = RayKind::ALL.iter().map(|kind| kind.name()).collect();
        names.sort_unstable();
        let mut sorted = keys.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, names);
        for kind in RayKind::ALL {
            assert_eq!(json[kind.name()], counts.of(kind), "{kind:?}");
        }
        assert_eq!(json["to_camera"], 2);
    }
}
