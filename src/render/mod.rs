//! The image loop, and the tracer the chapters drive.
//!
//! This file walks the pixels and hands each to the chapters; the chapters
//! decide everything else. For each ray, [`Tracer::trace`] finds what it
//! hits (chapter 3's nearest hit, or list order before it) and asks the
//! highest chapter of the stage that has a shader (its registry line's
//! `shades` clause, in `chapters/mod.rs`) to colour the point:
//!
//! ```text
//! stage 1-3   the material's colour
//! stage 4     chapter 4's flat light and shadows       (shade_flat)
//! stage 5     chapter 5's Phong sum                     (shade_phong)
//! stage 6-7   chapter 6's mirror mix, recursive         (shade_mirror)
//! stage 8     chapter 8's glass mix, recursive          (shade_glass)
//! stage 9-12  chapter 9's Fresnel glass, nested media   (shade_dielectric)
//! stage 13-14 chapter 13's random paths                 (shade_path)
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

pub use crate::seam::{Arrival, CastRay, RayCounts, RayKind, RayLog};

pub mod bsdf;
mod budget;

pub use budget::{
    BudgetError, IMAGE_RAY_BUDGET, NODE_VISITS_PER_RAY, PIXEL_RAY_BUDGET, RayEstimate,
    TESTS_IN_A_PLAIN_RAY,
};

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
    /// The settings could cast more rays than a budget allows.
    #[error(transparent)]
    TooManyRays(#[from] BudgetError),
    /// A comparison setting in a student's build, which leaves raylab's
    /// textbook formulas out with its other answers.
    #[error(
        "{0} asks for raylab's textbook formula, which a student's build of raylab leaves \
         out: render the comparison with raylab itself, in its folder"
    )]
    TextbookLeftOut(&'static str),
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
        let stage = Stage {
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
        };
        // Before any ray, so that no caller (a trace, the page) can ask
        // for a tree of rays that would not end for hours.
        stage.check_pixel_budget()?;
        Ok(stage)
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

    pub fn scene(&self) -> &'a Scene {
        self.scene
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

    /// The first `most` of the image's light paths, in path order, that
    /// light pixel `pixel` (counted row by row from the top-left corner),
    /// found by tracing every path as the render does (chapter 14).
    pub fn light_paths_lighting(&self, pixel: u32, most: usize) -> Vec<u64> {
        let total = self.light_path_count();
        let own = crate::answer_key::inside_own();
        let chunk = |number: u64| {
            crate::answer_key::own_if(own, || {
                let mut tracer = self.tracer(None);
                let mut lighting = Vec::new();
                for index in number * LIGHT_CHUNK..((number + 1) * LIGHT_CHUNK).min(total) {
                    tracer.light_path(index);
                    if tracer.splats.iter().any(|(lit, _)| *lit == pixel) {
                        lighting.push(index);
                    }
                    tracer.splats.clear();
                }
                lighting
            })
        };
        let chunks = 0..total.div_ceil(LIGHT_CHUNK);
        #[cfg(not(target_arch = "wasm32"))]
        let found: Vec<Vec<u64>> = chunks.into_par_iter().map(chunk).collect();
        #[cfg(target_arch = "wasm32")]
        let found: Vec<Vec<u64>> = chunks.map(chunk).collect();
        found.into_iter().flatten().take(most).collect()
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
        Tracer::new(self, recorder)
    }
}

mod tracer;
pub use tracer::*;

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
    /// The linear radiance the sRGB codes were encoded from, 3 `f32`s a
    /// pixel in the same order: unclamped, before any encoding. Empty
    /// unless asked for ([`render_linear_with`]): it takes four times the
    /// memory of `rgb`.
    pub linear: Vec<f32>,
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
    render_keeping::<C>(scene, chapter, settings, progress, KeepLinear::No)
}

/// Whether a render keeps its linear radiance beside the sRGB codes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeepLinear {
    No,
    Yes,
}

/// [`render_with`], keeping the linear radiance in [`Rendered::linear`]
/// (for OpenEXR output and errors measured in linear light). The sRGB
/// codes are the same bytes [`render_with`] gives.
pub fn render_linear_with<C: Chapters>(
    scene: &Scene,
    chapter: u8,
    settings: &RenderSettings,
    progress: Option<&Progress>,
) -> Result<Rendered, RenderError> {
    render_keeping::<C>(scene, chapter, settings, progress, KeepLinear::Yes)
}

/// [`render_with`] or [`render_linear_with`], as `keep` says.
pub fn render_keeping<C: Chapters>(
    scene: &Scene,
    chapter: u8,
    settings: &RenderSettings,
    progress: Option<&Progress>,
    keep: KeepLinear,
) -> Result<Rendered, RenderError> {
    use crate::course::Textbook;
    fn run<C: Chapters>(
        scene: &Scene,
        chapter: u8,
        settings: &RenderSettings,
        progress: Option<&Progress>,
        keep: KeepLinear,
    ) -> Result<Rendered, RenderError> {
        render_stage_keeping(
            &Stage::<C>::with_chapters(scene, chapter, *settings)?,
            progress,
            keep,
        )
    }
    let textbook_triangle = settings.triangle_test == TriangleTest::MollerTrumbore;
    textbook_left_out(settings)?;
    match (settings.sphere_formula, textbook_triangle) {
        (SphereFormula::Stable, false) => run::<C>(scene, chapter, settings, progress, keep),
        (SphereFormula::Textbook, false) => {
            run::<Textbook<C, true, false>>(scene, chapter, settings, progress, keep)
        }
        (SphereFormula::Stable, true) => {
            run::<Textbook<C, false, true>>(scene, chapter, settings, progress, keep)
        }
        (SphereFormula::Textbook, true) => {
            run::<Textbook<C, true, true>>(scene, chapter, settings, progress, keep)
        }
    }
}

/// In a student's build, the error for settings that ask for a textbook
/// formula (see [`RenderError::TextbookLeftOut`]).
fn textbook_left_out(settings: &RenderSettings) -> Result<(), RenderError> {
    if !cfg!(feature = "student") {
        Ok(())
    } else if settings.sphere_formula == SphereFormula::Textbook {
        Err(RenderError::TextbookLeftOut(
            "sphere_formula = \"textbook\"",
        ))
    } else if settings.triangle_test == TriangleTest::MollerTrumbore {
        Err(RenderError::TextbookLeftOut(
            "triangle_test = \"moller-trumbore\"",
        ))
    } else {
        Ok(())
    }
}

/// Renders a prepared stage.
pub fn render_stage<C: Chapters>(
    stage: &Stage<'_, C>,
    progress: Option<&Progress>,
) -> Result<Rendered, RenderError> {
    render_stage_keeping(stage, progress, KeepLinear::No)
}

/// [`render_stage`], keeping the linear radiance if `keep` says so.
pub fn render_stage_keeping<C: Chapters>(
    stage: &Stage<'_, C>,
    progress: Option<&Progress>,
    keep: KeepLinear,
) -> Result<Rendered, RenderError> {
    stage.check_image_budget()?;
    let start = Instant::now();
    let (width, height) = (stage.settings.width, stage.settings.height);
    // Before the rows, which all read it.
    let light_counts = stage.light_image().map(|light| light.counts);
    let values = width as usize * height as usize * 3;
    let mut rgb = vec![0u8; values];
    let mut linear = vec![0f32; if keep == KeepLinear::Yes { values } else { 0 }];
    // Without a linear buffer each row gets an empty slice, and keeps none.
    let linear_rows: Vec<&mut [f32]> = if linear.is_empty() {
        (0..height).map(|_| <&mut [f32]>::default()).collect()
    } else {
        linear.chunks_mut(width as usize * 3).collect()
    };
    let rays = rgb
        .par_chunks_mut(width as usize * 3)
        .zip(linear_rows)
        .enumerate()
        .map(|(y, (row, linear_row))| {
            let counts = render_row(stage, y as u32, row, linear_row);
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
        linear,
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
        // Rows are parts of the image (the page's workers render all of
        // them), so the whole image's budget holds.
        self.check_image_budget()?;
        let row_bytes = width as usize * 3;
        let mut rgb = vec![0u8; row_bytes * rows.len()];
        // The light paths' rays are counted once, with the first row.
        let mut counts = match self.light_image() {
            Some(light) if rows.start == 0 => light.counts,
            _ => RayCounts::default(),
        };
        for (row, y) in rgb.chunks_exact_mut(row_bytes).zip(rows) {
            counts = counts.add(render_row(self, y, row, &mut []));
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
    textbook_left_out(settings)?;
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

/// Row `y` of `stage`'s image into `row` (sRGB, 3 bytes a pixel) and, if
/// `linear_row` is not empty, its linear radiance (3 `f32`s a pixel); and
/// the rays it cast.
fn render_row<C: Chapters>(
    stage: &Stage<'_, C>,
    y: u32,
    row: &mut [u8],
    linear_row: &mut [f32],
) -> RayCounts {
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
        if let Some(values) = linear_row.get_mut(3 * x..3 * x + 3) {
            values.copy_from_slice(&color.to_array());
        }
    }
    let mut counts = tracer.counts();
    counts.self_shadowed_pixels = self_shadowed_pixels;
    counts.implicit_evaluations = crate::shapes::evaluations() - evaluations;
    counts.march_histogram = crate::shapes::march_histogram().since(&marches);
    counts
}
