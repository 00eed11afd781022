//! The image loop, and the tracer the chapters drive.
//!
//! This file walks the pixels and hands each to the chapters; the chapters
//! decide everything else. For each ray, [`Tracer::trace`] finds what it
//! hits (chapter 3's nearest hit, or list order before it) and asks the
//! highest chapter of the stage to colour the point:
//!
//! ```text
//! stage 1-3   the material's colour
//! stage 4     chapter 4's flat light and shadows       (shade_flat)
//! stage 5     chapter 5's Phong sum                     (shade_phong)
//! stage 6-7   chapter 6's mirror mix, recursive         (shade_mirror)
//! stage 8     chapter 8's glass mix, recursive          (shade_glass)
//! stage 9     chapter 9's Fresnel glass, nested media   (shade_dielectric)
//! ```
//!
//! From chapter 9 on, the tracer also knows the media the current ray
//! travels through ([`crate::medium::MediumStack`]): chapter 9 traces a ray
//! inside other media with [`Tracer::trace_in`].
//!
//! A pixel is one ray through its centre, or from chapter 7 on chapter 7's
//! own sample loop ([`Chapters::pixel_color`]).

use std::marker::PhantomData;
use std::time::Instant;

use rayon::prelude::*;

use crate::bvh::{Bvh, BvhOptions, WideBvh};
use crate::camera::Camera;
use crate::chapters::LAST_CHAPTER;
use crate::chapters::Reference;
use crate::course::{Chapters, Hit, HitPoint, Objects};
use crate::effects::{Effects, Lighting};
use crate::medium::MediumStack;
use crate::output::linear_to_srgb8;
use crate::scene::{Light, MAX_DEPTH, RenderSettings, SphereFormula, TerminatorRule, TriangleTest};
use crate::shapes::SurfacePoint;
use crate::{Ray, Scene, Shape, Vec3};

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
    /// [`Tracer::trace`] for a bounce (a mirror's reflectivity, glass's
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
    pub primary: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
    /// Rays scattered at random off diffuse and glossy surfaces (chapter 13).
    pub bounce: u64,
    /// Rays of the paths traced from the lights (chapter 14).
    pub light: u64,
    /// Rays from the points light paths lit toward the camera (chapter 14).
    pub to_camera: u64,
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
    /// Only [`render`] fills it in (a tracer sees rays, not pixels).
    pub self_shadowed_pixels: u64,
    /// Samples whose colour was NaN or infinite (written as black).
    pub non_finite_samples: u64,
    /// Path-traced samples brighter than [`FIREFLY_FACTOR`] times the
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
    pub fn total(&self) -> u64 {
        self.primary
            + self.shadow
            + self.reflection
            + self.refraction
            + self.bounce
            + self.light
            + self.to_camera
    }

    /// Rays marched against an implicit surface, once per ray and surface.
    pub fn implicit_marches(&self) -> u64 {
        self.march_histogram.marches()
    }

    fn add(mut self, other: RayCounts) -> RayCounts {
        self.primary += other.primary;
        self.shadow += other.shadow;
        self.reflection += other.reflection;
        self.refraction += other.refraction;
        self.bounce += other.bounce;
        self.light += other.light;
        self.to_camera += other.to_camera;
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

    fn count(&mut self, kind: RayKind) {
        match kind {
            RayKind::Primary => self.primary += 1,
            RayKind::Shadow => self.shadow += 1,
            RayKind::Reflection => self.reflection += 1,
            RayKind::Refraction => self.refraction += 1,
            RayKind::Bounce => self.bounce += 1,
            RayKind::Light => self.light += 1,
            RayKind::ToCamera => self.to_camera += 1,
        }
    }
}

/// One ray as the tracer cast it: what [`RayRecorder`] keeps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CastRay {
    pub kind: RayKind,
    pub ray: Ray,
    /// The tracer looked for hits with `t_min < t < t_max`.
    pub t_min: f32,
    pub t_max: f32,
}

/// A [`RayLog`] that keeps every ray cast, in order (for `raylab crosscheck`).
#[derive(Debug, Clone, Default)]
pub struct RayRecorder {
    pub rays: Vec<CastRay>,
}

impl RayLog for RayRecorder {
    fn cast(&mut self, kind: RayKind, ray: &Ray, t_min: f32, t_max: f32) {
        self.rays.push(CastRay {
            kind,
            ray: *ray,
            t_min,
            t_max,
        });
    }
}

pub use crate::scene::RayOffset;

impl RayOffset {
    /// Where a secondary ray leaving `surface` in direction `dir` starts,
    /// with the chapters `C`'s offset when the rule is [`RayOffset::Scaled`].
    pub fn origin_with<C: Chapters>(self, surface: &SurfacePoint, dir: Vec3) -> Vec3 {
        match self {
            RayOffset::Scaled => C::offset_origin(surface, dir),
            RayOffset::Fixed(epsilon) => surface.point + epsilon * dir.normalize_or_zero(),
        }
    }

    /// [`RayOffset::origin_with`] the reference chapters.
    pub fn origin(self, surface: &SurfacePoint, dir: Vec3) -> Vec3 {
        self.origin_with::<Reference>(surface, dir)
    }
}

/// Why a render cannot start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RenderError {
    #[error("invalid render settings: {0}")]
    Settings(crate::scene::SettingsError),
    #[error("there is no chapter {0}; chapters are 1 to {LAST_CHAPTER}")]
    NoSuchChapter(u8),
    #[error("rows {start} to {end} are not rows of an image {height} pixels high")]
    Rows { start: u32, end: u32, height: u32 },
}

/// A scene prepared for one chapter's stage: what every thread shares.
pub struct Stage<'a, C: Chapters = Reference> {
    scene: &'a Scene,
    /// The shapes this stage can intersect (chapter 1 knows no spheres).
    shapes: Vec<Shape>,
    /// For each of `shapes`, its object in the scene (for its material and
    /// name).
    owners: Vec<u32>,
    /// Chapter 11's tree over `shapes`, when the stage uses one.
    bvh: Option<Bvh>,
    /// The same tree folded into nodes of four children, which the rays walk.
    wide: Option<WideBvh>,
    offset: RayOffset,
    camera: Camera,
    /// The primitives of `shapes` whose material emits, which next-event
    /// estimation aims at with the point lights (chapter 13).
    emitters: Vec<u32>,
    /// A path-traced sample above this is counted as a firefly.
    firefly_bound: f32,
    /// Chapter 14's light paths, traced on first use.
    light_image: std::sync::OnceLock<LightImage>,
    pub effects: Effects,
    pub settings: RenderSettings,
    chapters: PhantomData<C>,
}

impl<'a> Stage<'a, Reference> {
    /// `scene` at `chapter`'s stage with `settings`, rendered by raylab's
    /// own chapters ([`Stage::with_chapters`]).
    pub fn new(
        scene: &'a Scene,
        chapter: u8,
        settings: RenderSettings,
    ) -> Result<Stage<'a, Reference>, RenderError> {
        Stage::with_chapters(scene, chapter, settings)
    }
}

impl<'a, C: Chapters> Stage<'a, C> {
    /// `scene` at `chapter`'s stage with `settings`, rendered by the
    /// chapters `C`, simulating only the effects the scene can show. The
    /// settings are checked here, so no caller can ask for an empty image or
    /// unbounded recursion.
    pub fn with_chapters(
        scene: &'a Scene,
        chapter: u8,
        settings: RenderSettings,
    ) -> Result<Stage<'a, C>, RenderError> {
        if !(1..=LAST_CHAPTER).contains(&chapter) {
            return Err(RenderError::NoSuchChapter(chapter));
        }
        settings.validate().map_err(RenderError::Settings)?;
        let stage = Effects::for_chapter(chapter).without(settings.without);
        let samples = if stage.antialiasing {
            settings.samples
        } else {
            1
        };
        let effects = stage.needed_by(scene, samples);
        let (shapes, owners): (Vec<Shape>, Vec<u32>) = scene
            .shapes
            .iter()
            .zip(&scene.owners)
            .filter(|(shape, _)| match shape {
                Shape::Plane(_) => effects.planes,
                Shape::Sphere(_) => effects.spheres,
                Shape::Triangle(_) => effects.triangles,
                Shape::Implicit(_) => effects.implicit,
            })
            .map(|(shape, owner)| match shape {
                Shape::Implicit(surface) => (surface.with_march(settings.march()).into(), *owner),
                Shape::Plane(_) | Shape::Sphere(_) | Shape::Triangle(_) => (shape.clone(), *owner),
            })
            .unzip();
        let bvh = effects.bvh.then(|| {
            let bounds: Vec<_> = shapes.iter().map(Shape::bounds).collect();
            C::build_bvh(&bounds, &BvhOptions::default())
        });
        let wide = bvh.as_ref().map(|bvh| C::collapse_bvh(bvh, &shapes));
        let emitters: Vec<u32> = owners
            .iter()
            .enumerate()
            .filter(|(index, owner)| {
                scene.objects[**owner as usize].material.emission != Vec3::ZERO
                    && area_of(&shapes[*index]).is_some()
            })
            .map(|(index, _)| index as u32)
            .collect();
        let brightest = scene
            .materials()
            .map(|material| material.emission.max_element())
            .fold(scene.background.max_element().max(1.0), f32::max);
        Ok(Stage {
            scene,
            shapes,
            owners,
            bvh,
            wide,
            emitters,
            firefly_bound: FIREFLY_FACTOR * brightest,
            light_image: std::sync::OnceLock::new(),
            offset: settings.offset(),
            camera: Camera::new(&scene.camera, settings.width, settings.height),
            effects,
            settings,
            chapters: PhantomData,
        })
    }

    /// Samples per pixel actually taken (1 before chapter 7).
    pub fn samples(&self) -> u32 {
        if self.effects.antialiasing {
            self.settings.samples
        } else {
            1
        }
    }

    /// The shapes this stage intersects.
    pub fn shapes(&self) -> &[Shape] {
        &self.shapes
    }

    /// The objects this stage intersects, as the chapters `C` intersect them.
    pub fn objects(&self) -> Objects<'_, C> {
        Objects::new(&self.shapes)
    }

    /// Chapter 11's tree over [`Stage::shapes`], when this stage uses one.
    pub fn bvh(&self) -> Option<&Bvh> {
        self.bvh.as_ref()
    }

    /// Chapter 11's tree folded into nodes of four children, which this
    /// stage's rays walk, when it uses a tree.
    pub fn wide_bvh(&self) -> Option<&WideBvh> {
        self.wide.as_ref()
    }

    /// The nearest hit among [`Stage::shapes`] with `t_min < t < t_max`, as
    /// this stage finds it: through chapter 11's wide tree when it has one, else
    /// by chapter 3's loop. (The cross-check races this against Embree.)
    pub fn nearest_hit(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        let objects = self.objects();
        match &self.wide {
            Some(wide) => C::nearest_hit_wide(wide, &objects, ray, t_min, t_max),
            None => C::nearest_hit(&objects, ray, t_min, t_max),
        }
    }

    /// The name of `object` (an index into [`Stage::shapes`]) in the scene,
    /// or `None` when there is no such object.
    pub fn name(&self, object: usize) -> Option<&str> {
        let owner = *self.owners.get(object)? as usize;
        self.scene.objects.get(owner).map(|o| o.name.as_str())
    }

    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// What chapter 14's light paths bring to each pixel, traced on first
    /// use (once per stage, by whichever thread asks first); `None` when the
    /// stage traces no light paths.
    pub fn light_image(&self) -> Option<&LightImage> {
        self.effects
            .light_tracing
            .then(|| self.light_image.get_or_init(|| self.trace_light_paths()))
    }

    /// How many light paths the image traces (chapter 14): `light_paths`
    /// per pixel, none where the stage traces none.
    pub fn light_path_count(&self) -> u64 {
        if !self.effects.light_tracing {
            return 0;
        }
        let (width, height) = (self.settings.width, self.settings.height);
        u64::from(width) * u64::from(height) * u64::from(self.settings.light_paths)
    }

    /// Traces light paths `paths` of the image, showing each ray to
    /// `recorder` in the order it is cast (for `raylab crosscheck`); what
    /// they splat is not kept.
    pub fn record_light_paths(&self, paths: std::ops::Range<u64>, recorder: &mut dyn RayLog) {
        let mut tracer = self.tracer(Some(recorder));
        for index in paths {
            tracer.light_path(index);
            tracer.splats.clear();
        }
    }

    /// Traces `light_paths` paths per pixel of the image from the lights,
    /// by the chapters' `trace_light_path`, and adds up what they splat,
    /// each path's light divided by the number of paths. Path `i` draws
    /// from its own random stream and the sums are made in path order, so
    /// the image is the same on any number of threads.
    fn trace_light_paths(&self) -> LightImage {
        let (width, height) = (self.settings.width, self.settings.height);
        let total = self.light_path_count();
        let chunks = total.div_ceil(LIGHT_CHUNK);
        // raylab's own stage (a check's converged reference) stays its own
        // on rayon's threads, where no student's code started the work.
        let own = crate::answer_key::inside_own();
        let chunk = |number: u64| {
            crate::answer_key::own_if(own, || {
                let mut tracer = self.tracer(None);
                for index in number * LIGHT_CHUNK..((number + 1) * LIGHT_CHUNK).min(total) {
                    tracer.light_path(index);
                }
                (std::mem::take(&mut tracer.splats), tracer.counts())
            })
        };
        let mut sums = vec![glam::DVec3::ZERO; width as usize * height as usize];
        let mut counts = RayCounts::default();
        let scale = 1.0 / total as f64;
        let mut first = 0;
        while first < chunks {
            let last = (first + LIGHT_BATCH).min(chunks);
            // The browser page's workers are threads of their own.
            #[cfg(not(target_arch = "wasm32"))]
            let traced: Vec<_> = (first..last).into_par_iter().map(chunk).collect();
            #[cfg(target_arch = "wasm32")]
            let traced: Vec<_> = (first..last).map(chunk).collect();
            for (splats, chunk_counts) in traced {
                for (index, light) in splats {
                    sums[index as usize] += light.as_dvec3() * scale;
                }
                counts = counts.add(chunk_counts);
            }
            first = last;
        }
        LightImage {
            pixels: sums.iter().map(|sum| sum.as_vec3()).collect(),
            counts,
        }
    }

    /// A tracer for one thread's share of the work, counting its rays and
    /// showing each to `recorder` if there is one.
    pub fn tracer<'s>(&'s self, recorder: Option<&'s mut dyn RayLog>) -> Tracer<'s, C> {
        Tracer {
            stage: self,
            objects: self.objects(),
            counts: RayCounts::default(),
            recorder,
            media: MediumStack::EMPTY,
            arrival: Arrival::Camera,
            first_point_scatters: false,
            wavelength: None,
            from_light: false,
            splats: Vec::new(),
            random_key: 0,
            random_index: 0,
            sample_bound: f32::INFINITY,
            normal_evaluations: std::cell::Cell::new(0),
        }
    }
}

/// A path-traced sample brighter than this many times the brightest light
/// or background a camera ray could see is counted as a firefly: no
/// surface lit by those lights returns that much without an estimate that
/// divided by a tiny density.
pub const FIREFLY_FACTOR: f32 = 10.0;

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

/// A point chosen on a light, as seen from a point being shaded (chapter
/// 13's next-event estimation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightSample {
    /// Where a shadow ray aims: the point on the light, moved toward the
    /// shaded point by [`SHADOW_EPSILON`] of the way, so that the light's
    /// own surface is not taken for a blocker.
    pub position: Vec3,
    /// Unit direction from the shaded point toward the light.
    pub direction: Vec3,
    /// The light arriving along `direction`: an emitter's radiance, or a
    /// point light's intensity over the squared distance.
    pub light: Vec3,
    /// The density of having chosen this direction, per unit solid angle
    /// and with the choice of light in it; for a point light, only the
    /// chance of choosing it.
    pub pdf: f32,
    /// A point light: a direction no scattered ray can find.
    pub delta: bool,
}

/// The share of a shadow ray's segment left out at the light's end (pbrt-v4's
/// `ShadowEpsilon`): enough that the light's own surface, where the segment
/// ends, is never found as a blocker after rounding, and small enough
/// (0.09 units over the 900-unit diagonal of the Cornell box) that no real
/// blocker hides in it.
pub const SHADOW_EPSILON: f32 = 1e-4;

/// Past this many bounces [`Tracer::trace`] stops whatever the chapters ask,
/// so that no chapter (a student's without its depth test, say) can recurse
/// until the stack overflows. Chapters 6 and 8 stop at `max_depth`, which is
/// at most this.
pub const DEPTH_LIMIT: u32 = MAX_DEPTH;

/// The renderer's handle, given to the chapters that drive others: through
/// it they cast rays, read the scene and the settings, and reach the other
/// chapters. One per thread; it counts the rays it casts.
pub struct Tracer<'a, C: Chapters = Reference> {
    stage: &'a Stage<'a, C>,
    objects: Objects<'a, C>,
    counts: RayCounts,
    recorder: Option<&'a mut dyn RayLog>,
    /// The media the ray being traced travels through (chapter 9): empty
    /// (air) for camera rays, set by [`Tracer::trace_in`] for the others.
    media: MediumStack,
    /// How the ray being traced was cast (chapter 13).
    arrival: Arrival,
    /// Whether the current camera path scattered at random off its first
    /// point (chapter 14: its caustics are the light paths').
    first_point_scatters: bool,
    /// The wavelength of the current path, in nanometres, once it has met
    /// a dispersive surface (chapter 14).
    wavelength: Option<f32>,
    /// Whether the current path started at a light (chapter 14) rather
    /// than at the camera.
    from_light: bool,
    /// What the current light paths brought to which pixel (chapter 14):
    /// the pixel's index and the light, before dividing by the number of
    /// paths.
    splats: Vec<(u32, Vec3)>,
    /// The current sample's stream of random numbers (chapter 13): a key
    /// from the seed and the sample's position, and how many were drawn.
    random_key: u64,
    random_index: u32,
    /// Each sample's channels are cut to this (infinite but for the
    /// check's comparison of path-traced images, [`Tracer::with_sample_bound`]).
    sample_bound: f32,
    /// Evaluations spent on implicit normals (a cell: hit points are
    /// made through a shared reference).
    normal_evaluations: std::cell::Cell<u64>,
}

/// What [`Tracer::trace_in`] saw along a ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Traced {
    pub color: Vec3,
    /// How far the ray went before it met something, in the scene's units
    /// (not in units of the direction); infinite when it met nothing.
    pub distance: f32,
}

impl<'a, C: Chapters> Tracer<'a, C> {
    /// The rays cast so far, by kind.
    pub fn counts(&self) -> RayCounts {
        RayCounts {
            normal_evaluations: self.normal_evaluations.get(),
            ..self.counts
        }
    }

    /// The objects this stage intersects.
    pub fn objects(&self) -> Objects<'a, C> {
        self.objects
    }

    /// The point where `ray` meets object `object` at parameter `t`, as the
    /// shading chapters receive it.
    #[inline]
    pub fn hit_point(&self, object: usize, ray: &Ray, t: f32) -> HitPoint<'a> {
        let shape = &self.stage.shapes[object];
        let owner = self.stage.owners[object] as usize;
        let material = &self.stage.scene.objects[owner].material;
        let point = HitPoint::new(object, shape, material, ray, t).with_solid(owner);
        if self.stage.effects.smooth_shading && shape.is_triangle() {
            self.smoothed(point, shape)
        } else if self.stage.effects.implicit {
            self.implicit_normal(point, shape)
        } else {
            point
        }
    }

    /// `point` with chapter 12's normal, when `shape` is an implicit
    /// surface; its evaluations are counted apart from the march's.
    #[inline(never)]
    fn implicit_normal(&self, point: HitPoint<'a>, shape: &Shape) -> HitPoint<'a> {
        let Some(surface) = shape.as_implicit() else {
            return point;
        };
        let before = crate::shapes::evaluations();
        let normal = C::implicit_normal(surface, point.surface.point);
        self.normal_evaluations
            .set(self.normal_evaluations.get() + crate::shapes::evaluations() - before);
        point.with_normal(normal)
    }

    /// `point` on `shape` as chapter 10's smooth shading sees it, when the
    /// shape is a triangle with vertex normals. Apart from
    /// [`Tracer::hit_point`] so that stages without smooth meshes do not
    /// carry its code in their hot path.
    #[inline(never)]
    fn smoothed(&self, point: HitPoint<'a>, shape: &Shape) -> HitPoint<'a> {
        let smooth = shape.as_triangle().and_then(|triangle| {
            let normals = self.stage.scene.vertex_normals.get(triangle.normals()?)?;
            Some((triangle, normals))
        });
        match smooth {
            Some((triangle, normals)) => {
                let mut smooth = C::smooth_hit_point(point, triangle, normals);
                // `--terminator flat`: chapter 10's shading without its lift,
                // to show what the lift fixes.
                if self.stage.settings.terminator == TerminatorRule::Flat {
                    smooth.surface.point = point.surface.point;
                }
                smooth
            }
            None => point,
        }
    }

    /// This tracer with every sample's channels cut to at most `bound`:
    /// what `raylab check` compares path-traced images by (fireflies are
    /// rare and huge, so two correct images differ most in them), never
    /// what a render shows.
    pub fn with_sample_bound(mut self, bound: f32) -> Self {
        self.sample_bound = bound;
        self
    }

    /// The effects this stage simulates (chapter 13 reads its switches).
    #[inline]
    pub fn effects(&self) -> Effects {
        self.stage.effects
    }

    /// The next number of the current sample's random stream, uniform in
    /// `[0, 1)` (chapter 13). The stream depends only on the seed and the
    /// sample's position in the image, so a pixel is the same on any
    /// number of threads.
    #[inline]
    pub fn random(&mut self) -> f32 {
        self.random_index += 1;
        let word = mix64(self.random_key ^ u64::from(self.random_index));
        // The top 24 bits: an f32's precision, never rounded up to 1.
        (word >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    /// How the ray being shaded was cast (chapter 13).
    #[inline]
    pub fn arrival(&self) -> Arrival {
        self.arrival
    }

    /// How many lights next-event estimation and chapter 14's light paths
    /// choose among: the point lights, the beams and every primitive that
    /// emits.
    pub fn light_count(&self) -> usize {
        self.stage.scene.lights.len() + self.stage.scene.beams.len() + self.stage.emitters.len()
    }

    /// A light, and a point on it, chosen at random for the surface point
    /// `from` (chapter 13): each light with the same chance, a point light
    /// as it is, a beam where its light comes from, a point uniformly over
    /// an emitter's area. `None` when the scene has no light, the point
    /// chosen is where `from` is, or a beam chosen does not reach `from`.
    pub fn sample_light(&mut self, from: &HitPoint) -> Option<LightSample> {
        let count = self.light_count();
        if count == 0 {
            return None;
        }
        let choice = ((self.random() * count as f32) as usize).min(count - 1);
        let chosen = 1.0 / count as f32;
        let (u, v) = (self.random(), self.random());
        let origin = from.surface.point;
        let lights = &self.stage.scene.lights;
        if let Some(light) = lights.get(choice) {
            let to_light = light.position - origin;
            let squared = to_light.length_squared();
            if !(squared > 0.0) {
                return None;
            }
            return Some(LightSample {
                position: light.position,
                direction: to_light / squared.sqrt(),
                light: light.radiance() / squared,
                pdf: chosen,
                delta: true,
            });
        }
        let beams = &self.stage.scene.beams;
        if let Some(beam) = beams.get(choice - lights.len()) {
            // The beam's light arrives along its direction, from the point
            // of its disk straight upstream of `origin`.
            let upstream = (origin - beam.position).dot(beam.direction);
            let source = origin - upstream * beam.direction;
            if !(upstream > 0.0)
                || (source - beam.position).length_squared() > beam.radius * beam.radius
            {
                return None;
            }
            return Some(LightSample {
                position: origin - (1.0 - SHADOW_EPSILON) * upstream * beam.direction,
                direction: -beam.direction,
                light: beam.irradiance(),
                pdf: chosen,
                delta: true,
            });
        }
        let object = self.stage.emitters[choice - lights.len() - beams.len()] as usize;
        let shape = &self.stage.shapes[object];
        let (point, normal, area) = point_on(shape, u, v)?;
        let to_light = point - origin;
        let squared = to_light.length_squared();
        let direction = to_light / squared.sqrt();
        let material = &self.stage.scene.objects[self.stage.owners[object] as usize].material;
        let cosine = facing_cosine(material, normal, direction);
        if !(squared > 0.0 && cosine > 0.0) {
            return None;
        }
        Some(LightSample {
            position: point - SHADOW_EPSILON * to_light,
            direction,
            light: material.emission,
            pdf: chosen * squared / (cosine * area),
            delta: false,
        })
    }

    /// The density, per unit solid angle, with which [`Tracer::sample_light`]
    /// would have chosen the direction of `point.ray` toward `point` from
    /// where that ray started: what multiple importance sampling weighs a
    /// scattered ray that found an emitter against. 0 where `point` emits
    /// nothing.
    pub fn light_pdf(&self, point: &HitPoint) -> f32 {
        if point.emitted() == Vec3::ZERO {
            return 0.0;
        }
        let shape = &self.stage.shapes[point.object];
        let Some(area) = area_of(shape) else {
            return 0.0;
        };
        let to_point = point.surface.point - point.ray.origin;
        let squared = to_point.length_squared();
        let cosine = facing_cosine(
            point.material,
            point.surface.normal,
            to_point / squared.sqrt(),
        );
        if !(cosine > 0.0 && area > 0.0) {
            return 0.0;
        }
        squared / (cosine * area * self.light_count() as f32)
    }

    /// [`Tracer::trace_in`] for a ray a path scatters (chapter 13): it
    /// travels inside `media`, and the point it meets knows how it was
    /// cast (`arrival`).
    pub fn trace_path(
        &mut self,
        media: &MediumStack,
        kind: RayKind,
        ray: &Ray,
        depth: u32,
        weight: f32,
        arrival: Arrival,
    ) -> Traced {
        let arrival = match (self.arrival, arrival) {
            // The ray leaves the camera's first point: whether it scattered
            // there decides who counts the caustics beyond (chapter 14).
            (Arrival::Camera, _) => {
                self.first_point_scatters = matches!(arrival, Arrival::Scattered { .. });
                arrival
            }
            (_, Arrival::Specular)
                if self.first_point_scatters && self.stage.effects.light_tracing =>
            {
                Arrival::Caustic
            }
            _ => arrival,
        };
        let outer = std::mem::replace(&mut self.arrival, arrival);
        let traced = self.trace_in(media, kind, ray, depth, weight);
        self.arrival = outer;
        traced
    }

    /// The camera (chapter 14 joins lit points to it).
    pub fn camera(&self) -> &Camera {
        &self.stage.camera
    }

    /// Whether the current path started at a light (chapter 14's light
    /// paths carry power, not radiance: see `bsdf`'s refraction).
    pub fn from_light(&self) -> bool {
        self.from_light
    }

    /// The wavelength of the current path in nanometres, once it has met a
    /// dispersive surface (chapter 14).
    pub fn wavelength(&self) -> Option<f32> {
        self.wavelength
    }

    /// Fixes the wavelength of the current path (chapter 14): it keeps it
    /// until the path ends.
    pub fn set_wavelength(&mut self, nanometres: f32) {
        self.wavelength = Some(nanometres);
    }

    /// A light chosen at random and a ray of light leaving it (chapter
    /// 14): each light with the same chance; from a point light in a
    /// direction uniform over the sphere, from a beam at a point uniform
    /// over its disk along its direction, from an emitter at a point
    /// uniform over its area, on either face, cosine-distributed about
    /// that face's normal (chapter 13's `cosine_hemisphere`). `power` is
    /// the light it carries: what the light gives off divided by the
    /// density of having chosen this ray, so that the mean over many rays
    /// is the lights' total power. `None` when the scene has no light.
    pub fn emit(&mut self) -> Option<Emitted> {
        use std::f32::consts::PI;
        let count = self.light_count();
        if count == 0 {
            return None;
        }
        let choice = ((self.random() * count as f32) as usize).min(count - 1);
        let count = count as f32;
        let (u, v) = (self.random(), self.random());
        let scene = self.stage.scene;
        // `libm`'s sines: the same bits on every machine and in the browser.
        if let Some(light) = scene.lights.get(choice) {
            let z = 1.0 - 2.0 * u;
            let ring = (1.0 - z * z).max(0.0).sqrt();
            let (sin, cos) = libm::sincosf(2.0 * PI * v);
            return Some(Emitted {
                ray: Ray::new(light.position, Vec3::new(ring * cos, ring * sin, z)),
                power: light.radiance() * (4.0 * PI * count),
            });
        }
        if let Some(beam) = scene.beams.get(choice - scene.lights.len()) {
            let radius = beam.radius * u.sqrt();
            let (sin, cos) = libm::sincosf(2.0 * PI * v);
            let across =
                crate::bsdf::to_world(beam.direction, Vec3::new(radius * cos, radius * sin, 0.0));
            return Some(Emitted {
                ray: Ray::new(beam.position + across, beam.direction),
                power: beam.irradiance() * (PI * beam.radius * beam.radius * count),
            });
        }
        let object = self.stage.emitters[choice - scene.lights.len() - scene.beams.len()] as usize;
        let (point, normal, area) = point_on(&self.stage.shapes[object], u, v)?;
        let material = &scene.objects[self.stage.owners[object] as usize].material;
        // A two-sided emitter sends half its paths from each face.
        let (face, faces) = match material.two_sided {
            true if self.random() < 0.5 => (-normal, 2.0),
            true => (normal, 2.0),
            false => (normal, 1.0),
        };
        let local = C::cosine_hemisphere(self.random(), self.random());
        let direction = crate::bsdf::to_world(face, local);
        let surface = SurfacePoint {
            point,
            normal,
            error: point.abs() * (crate::shapes::SURFACE_ERROR_EPSILONS * f32::EPSILON),
        };
        Some(Emitted {
            ray: Ray::new(self.offset_origin(&surface, direction), direction),
            // Le cos / (cos / pi * 1 / area * 1 / faces * 1 / count).
            power: material.emission * (faces * PI * area * count),
        })
    }

    /// Traces a ray of a light path travelling inside `media` (chapter
    /// 14): the point it meets, as a camera path would see it, and how far
    /// it went. The tracer then knows the media of that ray, for the
    /// surface's scattering (`Lobe::scatter`).
    pub fn trace_light(&mut self, media: &MediumStack, ray: &Ray) -> Option<LightHit<'a>> {
        self.media = *media;
        let Hit { object, t } = self.find(RayKind::Light, ray)?;
        Some(LightHit {
            point: self.hit_point(object, ray, t),
            distance: t * ray.dir.length(),
        })
    }

    /// Whether something lies between `point` and the camera (chapter 14):
    /// a ray toward the camera from chapter 4's offset origin, stopped
    /// short of the camera by [`SHADOW_EPSILON`] of the way.
    pub fn blocked_from_camera(&mut self, point: &HitPoint) -> bool {
        let to_camera = self.stage.camera.origin() - point.surface.point;
        let origin = self.offset_origin(&point.surface, to_camera);
        let ray = Ray::new(origin, self.stage.camera.origin() - origin);
        self.any_blocker(RayKind::ToCamera, &ray, 0.0, 1.0 - SHADOW_EPSILON)
            .is_some()
    }

    /// Adds `light` to the pixel at image point `(x, y)` (in pixels from
    /// the top-left corner, as [`Camera::project`] gives it), for chapter
    /// 14's light paths: the renderer divides it by the number of paths.
    /// A point outside the image, or light that is not finite, adds
    /// nothing (the latter counted as a non-finite sample).
    pub fn splat(&mut self, x: f32, y: f32, light: Vec3) {
        let (width, height) = (self.stage.settings.width, self.stage.settings.height);
        if !(x >= 0.0 && y >= 0.0 && x < width as f32 && y < height as f32) {
            return;
        }
        if !light.is_finite() {
            self.counts.non_finite_samples += 1;
            return;
        }
        let index = (y as u32).min(height - 1) * width + (x as u32).min(width - 1);
        self.counts.splats += 1;
        self.splats.push((index, light));
    }

    /// Starts path number `stream` of a check's own (`raylab check` asks
    /// chapter 14's `dispersive_ior` at the first surface of many paths):
    /// its own stream of random numbers, and no wavelength yet.
    pub fn begin_path(&mut self, stream: u64) {
        self.random_key = mix64(self.stage.settings.seed ^ mix64(stream ^ CHECK_PATH_STREAM));
        self.random_index = 0;
        self.wavelength = None;
    }

    /// Traces light path number `index` of the image (chapter 14), with
    /// its own stream of random numbers, and hands back what it splatted.
    fn light_path(&mut self, index: u64) {
        self.random_key = mix64(self.stage.settings.seed ^ mix64(index ^ LIGHT_PATH_STREAM));
        self.random_index = 0;
        self.arrival = Arrival::Camera;
        self.wavelength = None;
        self.from_light = true;
        self.media = MediumStack::EMPTY;
        self.counts.light_paths += 1;
        C::trace_light_path(self);
    }

    /// The scene's point lights.
    #[inline]
    pub fn lights(&self) -> &'a [Light] {
        &self.stage.scene.lights
    }

    /// The scene's ambient light (chapters 4 and 5).
    #[inline]
    pub fn ambient_light(&self) -> Vec3 {
        self.stage.scene.ambient_light
    }

    /// How many bounces chapters 6 and 8 may follow.
    #[inline]
    pub fn max_depth(&self) -> u32 {
        self.stage.settings.max_depth
    }

    /// Samples per pixel (chapter 7).
    pub fn samples(&self) -> u32 {
        self.stage.samples()
    }

    /// Whether a secondary ray that brings `share` of a point whose own
    /// share of the pixel is `weight` is worth casting: the share must be
    /// positive, and the ray's weight in the pixel at least the scene's
    /// `min_contribution`. Skipping the others costs at most that much of
    /// the pixel, and saves every ray they would have spawned.
    #[inline]
    pub fn worth_casting(&self, weight: f32, share: f32) -> bool {
        share > 0.0 && weight * share >= self.stage.settings.min_contribution
    }

    /// Where a secondary ray leaving `surface` in direction `dir` starts:
    /// chapter 4's [`Chapters::offset_origin`], or the fixed epsilon of the
    /// comparison setting `ray_offset = "fixed"`.
    #[inline]
    pub fn offset_origin(&self, surface: &SurfacePoint, dir: Vec3) -> Vec3 {
        self.stage.offset.origin_with::<C>(surface, dir)
    }

    /// Whether shadow rays from `object` leave from a point lifted off its
    /// surface: a triangle with vertex normals, under the lifted terminator
    /// rule.
    fn starts_off_its_surface(&self, object: usize) -> bool {
        self.stage.settings.terminator == TerminatorRule::Lifted
            && self
                .stage
                .shapes
                .get(object)
                .and_then(Shape::as_triangle)
                .is_some_and(|triangle| triangle.normals().is_some())
    }

    /// Casts a shadow ray: whether any object lies on `ray` with
    /// `t_min < t < t_max`. Any blocker will do, so the search stops at the
    /// first in list order. `from` is the point the ray leaves, for the acne
    /// counter of `--stats`.
    #[inline]
    pub fn blocked(&mut self, ray: &Ray, t_min: f32, t_max: f32, from: &HitPoint) -> bool {
        match self.any_blocker(RayKind::Shadow, ray, t_min, t_max) {
            Some(blocker) => {
                // Planes and flat triangles are flat and spheres convex, and
                // lights outside a sphere seen from inside it are skipped
                // before any ray: a shadow ray that leaves a surface and
                // meets it again is acne. Not so from a point lifted off its
                // flat triangle (chapter 10's terminator fix): there the
                // triangle itself may rightly stand between the point and
                // a light, the faceted shadow the lift trades for.
                // An implicit surface may be anything but convex (a torus
                // shadows its own hole), so its self-shadowing is not
                // counted as acne either.
                let own_shadow_possible = self.starts_off_its_surface(from.object)
                    || self.stage.shapes[from.object].as_implicit().is_some();
                if blocker.object == from.object && !own_shadow_possible {
                    self.counts.self_shadow_hits += 1;
                }
                true
            }
            None => false,
        }
    }

    /// The colour seen along `ray`, a ray of `kind` (a reflection or
    /// refraction when chapters 6 and 8 call it). `depth` counts the bounces
    /// so far and `weight` is the ray's share of the pixel.
    pub fn trace(&mut self, kind: RayKind, ray: &Ray, depth: u32, weight: f32) -> Vec3 {
        self.trace_hit(kind, ray, depth, weight).0
    }

    /// The media the ray being shaded travelled through to reach its point
    /// (chapter 9): the solids it is inside, the last entered current.
    #[inline]
    pub fn media(&self) -> &MediumStack {
        &self.media
    }

    /// [`Tracer::trace`] for a ray that travels inside `media` (chapter 9):
    /// the point it meets is shaded knowing them, and the answer says how
    /// far the ray went, for absorption. The tracer's own media are the
    /// same afterwards: each ray carries its own, nothing leaks to the next.
    pub fn trace_in(
        &mut self,
        media: &MediumStack,
        kind: RayKind,
        ray: &Ray,
        depth: u32,
        weight: f32,
    ) -> Traced {
        let outer = std::mem::replace(&mut self.media, *media);
        let (color, t) = self.trace_hit(kind, ray, depth, weight);
        self.media = outer;
        Traced {
            color,
            // t counts lengths of the direction; a miss went on for ever.
            distance: t.map_or(f32::INFINITY, |t| t * ray.dir.length()),
        }
    }

    /// The colour seen along `ray`, and the `t` of what it met.
    fn trace_hit(
        &mut self,
        kind: RayKind,
        ray: &Ray,
        depth: u32,
        weight: f32,
    ) -> (Vec3, Option<f32>) {
        if depth > DEPTH_LIMIT {
            return (Vec3::ZERO, None);
        }
        let Some(Hit { object, t }) = self.find_weighted(kind, ray, Some(weight)) else {
            self.returned(self.stage.scene.background);
            return (self.stage.scene.background, None);
        };
        let point = self.hit_point(object, ray, t);
        let effects = self.stage.effects;
        let color = if effects.path_tracing {
            C::shade_path(self, &point, depth, weight)
        } else if effects.nested_media {
            C::shade_dielectric(self, &point, depth, weight)
        } else if effects.refraction {
            C::shade_glass(self, &point, depth, weight)
        } else if effects.reflection {
            C::shade_mirror(self, &point, depth, weight)
        } else {
            match effects.lighting {
                Lighting::Unlit => point.albedo,
                Lighting::Flat => C::shade_flat(self, &point),
                Lighting::Phong => {
                    let light = C::shade_phong(self, &point);
                    light.diffuse + light.specular
                }
            }
        };
        self.returned(color);
        (color, Some(t))
    }

    /// Any object on `ray`, a ray of `kind`, with `t_min < t < t_max`: the
    /// first the tree or the list order gives, since any blocker will do.
    #[inline]
    fn any_blocker(&mut self, kind: RayKind, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        self.log(kind, ray, t_min, t_max);
        let blocker = match &self.stage.wide {
            Some(wide) => C::any_hit_wide(wide, &self.objects, ray, t_min, t_max),
            None => self.objects.first_hit(ray, t_min, t_max),
        };
        if let Some(recorder) = self.recorder.as_deref_mut() {
            recorder.met(blocker);
        }
        blocker
    }

    /// What `ray`, a ray of `kind`, meets first: through chapter 11's tree,
    /// chapter 3's nearest hit, or (before chapter 3) the first in list
    /// order.
    #[inline]
    fn find(&mut self, kind: RayKind, ray: &Ray) -> Option<Hit> {
        self.find_weighted(kind, ray, None)
    }

    /// [`Tracer::find`], telling the recorder the ray's share of the pixel.
    #[inline]
    fn find_weighted(&mut self, kind: RayKind, ray: &Ray, weight: Option<f32>) -> Option<Hit> {
        self.log(kind, ray, 0.0, f32::INFINITY);
        if let (Some(recorder), Some(weight)) = (self.recorder.as_deref_mut(), weight) {
            recorder.weighted(weight);
        }
        let hit = if let Some(wide) = &self.stage.wide {
            C::nearest_hit_wide(wide, &self.objects, ray, 0.0, f32::INFINITY)
        } else if self.stage.effects.nearest_hit {
            C::nearest_hit(&self.objects, ray, 0.0, f32::INFINITY)
        } else {
            self.objects.first_hit(ray, 0.0, f32::INFINITY)
        };
        if let Some(recorder) = self.recorder.as_deref_mut() {
            recorder.met(hit);
        }
        hit
    }

    #[inline]
    fn returned(&mut self, color: Vec3) {
        if let Some(recorder) = self.recorder.as_deref_mut() {
            recorder.returned(color);
        }
    }

    /// The colour of one camera ray through the image point `(x, y)` (in
    /// pixels from the top-left corner), in linear light. A NaN or infinite
    /// colour is counted and becomes black.
    pub fn sample(&mut self, x: f32, y: f32) -> Vec3 {
        let ray = self.stage.camera.ray_through(x, y);
        self.random_key = mix64(
            self.stage.settings.seed
                ^ mix64((u64::from(x.to_bits()) << 32) | u64::from(y.to_bits())),
        );
        self.random_index = 0;
        self.arrival = Arrival::Camera;
        self.first_point_scatters = false;
        self.wavelength = None;
        self.from_light = false;
        let color = self.trace(RayKind::Primary, &ray, 0, 1.0);
        if color.is_finite() {
            if self.stage.effects.path_tracing && color.max_element() > self.stage.firefly_bound {
                self.counts.bright_samples += 1;
            }
            color.min(Vec3::splat(self.sample_bound))
        } else {
            self.counts.non_finite_samples += 1;
            Vec3::ZERO
        }
    }

    /// Where sample `index` of this stage's count falls inside `pixel`, by
    /// chapter 7's [`Chapters::sample_offset`] with the scene's settings.
    #[inline]
    pub fn sample_offset(&self, index: u32, pixel: (u32, u32)) -> (f32, f32) {
        let settings = &self.stage.settings;
        C::sample_offset(
            settings.sampling,
            self.samples(),
            index,
            pixel,
            settings.seed,
        )
    }

    /// The colour of pixel `(x, y)`: one ray through its centre, or chapter
    /// 7's samples when the stage takes more than one.
    pub fn pixel(&mut self, x: u32, y: u32) -> Vec3 {
        if self.samples() == 1 {
            self.sample(x as f32 + 0.5, y as f32 + 0.5)
        } else {
            C::pixel_color(self, x, y)
        }
    }

    #[inline]
    fn log(&mut self, kind: RayKind, ray: &Ray, t_min: f32, t_max: f32) {
        self.counts.count(kind);
        if let Some(recorder) = self.recorder.as_deref_mut() {
            recorder.cast(kind, ray, t_min, t_max);
        }
    }
}

/// Mixed into a light path's number to key its random stream, so that no
/// light path shares its numbers with a camera sample.
const LIGHT_PATH_STREAM: u64 = 0x4C49_4748_545F_5041;

/// Mixed into the seeds of [`Tracer::begin_path`]'s streams: a check's
/// paths draw numbers of their own, not a light path's.
const CHECK_PATH_STREAM: u64 = 0x4348_4543_4B5F_5041;

/// A ray of light leaving a light (chapter 14), and the power it carries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Emitted {
    pub ray: Ray,
    /// The light's power divided by the density of having chosen this
    /// ray: what the path carries until it meets something.
    pub power: Vec3,
}

/// The point a ray of a light path met (chapter 14), and how far it went
/// in the scene's units (for absorption).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightHit<'a> {
    pub point: HitPoint<'a>,
    pub distance: f32,
}

/// What chapter 14's light paths bring to the image: per pixel, row by row,
/// linear light to add to the camera's estimate; and the rays they cast.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LightImage {
    pub pixels: Vec<Vec3>,
    pub counts: RayCounts,
}

/// Light paths traced by one tracer before its splats are handed back.
pub const LIGHT_CHUNK: u64 = 1024;

/// Chunks traced together (in parallel) before their splats are added to
/// the image in chunk order: the memory a batch holds stays bounded, and
/// the sum is the same on any number of threads.
const LIGHT_BATCH: u64 = 64;

/// SplitMix64's finaliser: every output bit depends on every input bit.
fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The cosine between an emitter's normal and the direction toward it,
/// `direction`, from a point it lights: positive when the point is in
/// front of it; for a two-sided emitter, on either side.
fn facing_cosine(material: &crate::Material, normal: Vec3, direction: Vec3) -> f32 {
    let cosine = -normal.dot(direction);
    if material.two_sided {
        cosine.abs()
    } else {
        cosine
    }
}

/// The area of `shape`, for the shapes a light can be: `None` for a plane
/// (no finite area) and an implicit surface (none known in closed form).
fn area_of(shape: &Shape) -> Option<f32> {
    match shape {
        Shape::Triangle(triangle) => {
            let [a, b, c] = triangle.corners();
            Some(0.5 * (b - a).cross(c - a).length())
        }
        Shape::Sphere(sphere) => {
            Some(4.0 * std::f32::consts::PI * sphere.radius() * sphere.radius())
        }
        Shape::Plane(_) | Shape::Implicit(_) => None,
    }
}

/// A point uniformly distributed over `shape`'s area for `u, v` uniform in
/// `[0, 1)`, its unit normal, and the area; `None` for a shape with no
/// finite area or a degenerate one.
fn point_on(shape: &Shape, u: f32, v: f32) -> Option<(Vec3, Vec3, f32)> {
    let area = area_of(shape)?;
    match shape {
        Shape::Triangle(triangle) => {
            let [a, b, c] = triangle.corners();
            // Folding the square onto the triangle with the square root
            // keeps the density uniform (pbrt-v4's SampleUniformTriangle
            // gives the same distribution).
            let root = u.sqrt();
            let (first, second) = (1.0 - root, v * root);
            let point = first * a + second * b + (1.0 - first - second) * c;
            let normal = (b - a).cross(c - a).normalize_or_zero();
            (normal != Vec3::ZERO).then_some((point, normal, area))
        }
        Shape::Sphere(sphere) => {
            let z = 1.0 - 2.0 * u;
            let ring = (1.0 - z * z).max(0.0).sqrt();
            let (sin, cos) = libm::sincosf(2.0 * std::f32::consts::PI * v);
            let normal = Vec3::new(ring * cos, ring * sin, z);
            Some((sphere.center() + sphere.radius() * normal, normal, area))
        }
        Shape::Plane(_) | Shape::Implicit(_) => None,
    }
}

/// Every ray that rendering the whole image at `stage` casts, in a fixed
/// order: row by row from the top, pixel by pixel, and within a pixel in the
/// order the chapters cast them, whatever the number of threads. Unbounded:
/// `raylab crosscheck` uses [`crate::record::record_rays_within`].
pub fn record_rays<C: Chapters>(stage: &Stage<'_, C>) -> Vec<CastRay> {
    // No scene can cast u64::MAX rays, so the budget is never reached.
    crate::record::record_rays_within(stage, u64::MAX).unwrap_or_default()
}

/// What a render tells of each row it finishes: a terminal's progress bar.
#[cfg(not(target_arch = "wasm32"))]
pub type Progress = indicatif::ProgressBar;

/// In the browser page the workers report their rows themselves: no render
/// is given a progress bar there.
#[cfg(target_arch = "wasm32")]
pub enum Progress {}

#[cfg(target_arch = "wasm32")]
impl Progress {
    fn inc(&self, _rows: u64) {
        match *self {}
    }
}

/// A finished render.
#[derive(Debug, Clone)]
pub struct Rendered {
    pub width: u32,
    pub height: u32,
    /// sRGB-encoded pixels, row by row from the top, 3 bytes each.
    pub rgb: Vec<u8>,
    /// The effects that were simulated.
    pub effects: Effects,
    pub rays: RayCounts,
    pub seconds: f64,
}

impl Rendered {
    /// The stable fingerprint of the image (see [`crate::output::image_hash`]).
    pub fn hash(&self) -> u64 {
        crate::output::image_hash(self.width, self.height, &self.rgb)
    }
}

/// Renders `scene` at `chapter`'s stage with `settings` and raylab's own
/// chapters, on the current rayon thread pool. Each pixel depends only on
/// the scene, the settings and its position, so the image is the same on
/// any number of threads.
pub fn render(
    scene: &Scene,
    chapter: u8,
    settings: &RenderSettings,
    progress: Option<&Progress>,
) -> Result<Rendered, RenderError> {
    render_with::<Reference>(scene, chapter, settings, progress)
}

/// [`render`] with the chapters `C` (a student's, say). The comparison
/// settings `sphere_formula = "textbook"` and `triangle_test =
/// "moller-trumbore"` swap in the textbook tests.
pub fn render_with<C: Chapters>(
    scene: &Scene,
    chapter: u8,
    settings: &RenderSettings,
    progress: Option<&Progress>,
) -> Result<Rendered, RenderError> {
    use crate::course::Textbook;
    fn run<C: Chapters>(
        scene: &Scene,
        chapter: u8,
        settings: &RenderSettings,
        progress: Option<&Progress>,
    ) -> Result<Rendered, RenderError> {
        render_stage(
            &Stage::<C>::with_chapters(scene, chapter, *settings)?,
            progress,
        )
    }
    let textbook_triangle = settings.triangle_test == TriangleTest::MollerTrumbore;
    match (settings.sphere_formula, textbook_triangle) {
        (SphereFormula::Stable, false) => run::<C>(scene, chapter, settings, progress),
        (SphereFormula::Textbook, false) => {
            run::<Textbook<C, true, false>>(scene, chapter, settings, progress)
        }
        (SphereFormula::Stable, true) => {
            run::<Textbook<C, false, true>>(scene, chapter, settings, progress)
        }
        (SphereFormula::Textbook, true) => {
            run::<Textbook<C, true, true>>(scene, chapter, settings, progress)
        }
    }
}

/// Renders a prepared stage.
pub fn render_stage<C: Chapters>(
    stage: &Stage<'_, C>,
    progress: Option<&Progress>,
) -> Result<Rendered, RenderError> {
    let start = Instant::now();
    let (width, height) = (stage.settings.width, stage.settings.height);
    // Before the rows, which all read it.
    let light_counts = stage.light_image().map(|light| light.counts);
    let mut rgb = vec![0u8; width as usize * height as usize * 3];
    let rays = rgb
        .par_chunks_mut(width as usize * 3)
        .enumerate()
        .map(|(y, row)| {
            let counts = render_row(stage, y as u32, row);
            if let Some(bar) = progress {
                bar.inc(1);
            }
            counts
        })
        .reduce(RayCounts::default, RayCounts::add)
        .add(light_counts.unwrap_or_default());
    Ok(Rendered {
        width,
        height,
        rgb,
        effects: stage.effects,
        rays,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// Rows `rows` of the image of `scene` at `chapter`'s stage, as
/// [`render_with`] renders them (sRGB, 3 bytes a pixel), and the rays they
/// cast: the same bytes whichever rows are asked for and in what order, so
/// that any split of an image (the browser's workers) puts the same image
/// back together. Rows past the image are refused.
pub fn render_rows<C: Chapters>(
    scene: &Scene,
    chapter: u8,
    settings: &RenderSettings,
    rows: std::ops::Range<u32>,
) -> Result<(Vec<u8>, RayCounts), RenderError> {
    row_renderer::<C>(scene, chapter, settings)?.render_rows(rows)
}

/// A stage prepared once (its tree built) to render rows again and again.
pub trait RowRenderer {
    /// As [`render_rows`].
    fn render_rows(&self, rows: std::ops::Range<u32>) -> Result<(Vec<u8>, RayCounts), RenderError>;
}

impl<C: Chapters> RowRenderer for Stage<'_, C> {
    fn render_rows(&self, rows: std::ops::Range<u32>) -> Result<(Vec<u8>, RayCounts), RenderError> {
        let (width, height) = (self.settings.width, self.settings.height);
        if rows.end > height || rows.start > rows.end {
            return Err(RenderError::Rows {
                start: rows.start,
                end: rows.end,
                height,
            });
        }
        let row_bytes = width as usize * 3;
        let mut rgb = vec![0u8; row_bytes * rows.len()];
        // The light paths' rays are counted once, with the first row.
        let mut counts = match self.light_image() {
            Some(light) if rows.start == 0 => light.counts,
            _ => RayCounts::default(),
        };
        for (row, y) in rgb.chunks_exact_mut(row_bytes).zip(rows) {
            counts = counts.add(render_row(self, y, row));
        }
        Ok((rgb, counts))
    }
}

/// The stage [`render_with`] renders, as a [`RowRenderer`]: the chapters
/// `C`, or the textbook tests the settings ask for in their place.
pub fn row_renderer<'a, C: Chapters>(
    scene: &'a Scene,
    chapter: u8,
    settings: &RenderSettings,
) -> Result<Box<dyn RowRenderer + 'a>, RenderError> {
    use crate::course::Textbook;
    fn boxed<'a, C: Chapters>(
        scene: &'a Scene,
        chapter: u8,
        settings: &RenderSettings,
    ) -> Result<Box<dyn RowRenderer + 'a>, RenderError> {
        Ok(Box::new(Stage::<C>::with_chapters(
            scene, chapter, *settings,
        )?))
    }
    let textbook_triangle = settings.triangle_test == TriangleTest::MollerTrumbore;
    match (settings.sphere_formula, textbook_triangle) {
        (SphereFormula::Stable, false) => boxed::<C>(scene, chapter, settings),
        (SphereFormula::Textbook, false) => {
            boxed::<Textbook<C, true, false>>(scene, chapter, settings)
        }
        (SphereFormula::Stable, true) => {
            boxed::<Textbook<C, false, true>>(scene, chapter, settings)
        }
        (SphereFormula::Textbook, true) => {
            boxed::<Textbook<C, true, true>>(scene, chapter, settings)
        }
    }
}

/// Row `y` of `stage`'s image into `row` (sRGB, 3 bytes a pixel), and the
/// rays it cast.
fn render_row<C: Chapters>(stage: &Stage<'_, C>, y: u32, row: &mut [u8]) -> RayCounts {
    let mut tracer = stage.tracer(None);
    let light = stage.light_image();
    let (evaluations, marches) = (
        crate::shapes::evaluations(),
        crate::shapes::march_histogram(),
    );
    let mut self_shadowed_pixels = 0;
    for (x, pixel) in row.chunks_exact_mut(3).enumerate() {
        let self_shadowed_before = tracer.counts.self_shadow_hits;
        let mut color = tracer.pixel(x as u32, y);
        if let Some(light) = light {
            color += light.pixels[(y * stage.settings.width) as usize + x];
        }
        if tracer.counts.self_shadow_hits > self_shadowed_before {
            self_shadowed_pixels += 1;
        }
        pixel.copy_from_slice(&color.to_array().map(linear_to_srgb8));
    }
    let mut counts = tracer.counts();
    counts.self_shadowed_pixels = self_shadowed_pixels;
    counts.implicit_evaluations = crate::shapes::evaluations() - evaluations;
    counts.march_histogram = crate::shapes::march_histogram().since(&marches);
    counts
}
