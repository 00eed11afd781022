//! What accuracy costs: each quality knob of a chapter, swept and measured
//! against one high-quality reference render of the same scene.
//!
//! For every setting, [`run`] renders the scene `repeats` times and records
//! the median wall time, the rays cast and the error of the image against the
//! reference. Errors are measured on the 8-bit sRGB pixels, the numbers a
//! student's PNG holds, in code values (0 to 255):
//!
//! - RMSE: the root mean square of the channel differences;
//! - PSNR: `20 log10(255 / RMSE)` decibels (infinite for identical images);
//! - the share of pixels with a channel off by more than one code (1/255).
//!
//! The reference is the same chapter's stage at the same size with every
//! knob at its most accurate setting (see [`reference_settings`]). A chapter
//! before 7 takes one sample at each pixel centre, so its reference does too:
//! aliasing is not a knob that chapter has.

use std::fmt::Write as _;

use crate::effects::Effects;
use crate::render::Rendered;
use crate::scene::{FresnelModel, OffsetRule, SphereFormula, TriangleTest};
use crate::{RenderSettings, Sampling, Scene};

/// A quality knob the sweep can turn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Knob {
    /// Samples per pixel, 1 to 64, for grid, jittered and random sampling (chapter 7).
    Samples,
    /// Reflection and refraction depth, 0 to 8 (chapter 6).
    Depth,
    /// Where secondary rays start: global epsilons against the scaled offset (chapter 4).
    Offset,
    /// The textbook against the stable ray-sphere formula, on a far small sphere (chapter 2).
    SphereFormula,
    /// Fresnel on every transparent material: none (chapter 8's constants), Schlick, exact (chapter 9).
    Fresnel,
    /// Moller-Trumbore against the watertight triangle test (chapter 10).
    TriangleTest,
    /// Not an image knob (the tree changes no pixel): the BVH report, build
    /// and trace time against triangles, split rule, leaf size, and from
    /// how many objects a tree pays (chapter 11).
    Bvh,
    /// The march of implicit surfaces: hit tolerance, step budget,
    /// over-relaxation, the Lipschitz factor and Newton's refinement
    /// (chapter 12).
    March,
    /// How implicit surfaces' normals are found: analytic, central
    /// differences and the tetrahedron, at several steps (chapter 12).
    Normals,
    /// Path tracing's samples per pixel, with each of its switches on and
    /// off: MIS, next-event estimation, Russian roulette (chapter 13).
    Paths,
    /// Paths traced from the lights: camera paths alone against camera and
    /// light paths together, at each count per pixel (chapter 14).
    Caustics,
}

impl Knob {
    pub const ALL: [Knob; 11] = [
        Knob::Samples,
        Knob::Depth,
        Knob::Offset,
        Knob::SphereFormula,
        Knob::Fresnel,
        Knob::TriangleTest,
        Knob::Bvh,
        Knob::March,
        Knob::Normals,
        Knob::Paths,
        Knob::Caustics,
    ];

    /// The chapter that introduces this knob.
    pub fn chapter(self) -> u8 {
        match self {
            Knob::SphereFormula => 2,
            Knob::Offset => 4,
            Knob::Depth => 6,
            Knob::Samples => 7,
            Knob::Fresnel => 9,
            Knob::TriangleTest => 10,
            Knob::Bvh => 11,
            Knob::March | Knob::Normals => 12,
            Knob::Paths => 13,
            Knob::Caustics => 14,
        }
    }

    /// The name used in tables, files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Knob::Samples => "samples",
            Knob::Depth => "depth",
            Knob::Offset => "offset",
            Knob::SphereFormula => "sphere-formula",
            Knob::Fresnel => "fresnel",
            Knob::TriangleTest => "triangle-test",
            Knob::Bvh => "bvh",
            Knob::March => "march",
            Knob::Normals => "normals",
            Knob::Paths => "paths",
            Knob::Caustics => "caustics",
        }
    }

    /// The knobs chapter `chapter` has, in sweep order.
    pub fn of_chapter(chapter: u8) -> Vec<Knob> {
        Knob::ALL
            .into_iter()
            .filter(|knob| knob.chapter() <= chapter)
            .collect()
    }
}

/// Sample counts swept by [`Knob::Samples`] for each placement, after one
/// row at 1 sample (the pixel centre, whatever the placement): squares, so
/// grid and jittered sampling can use them too.
pub const SAMPLE_COUNTS: [u32; 3] = [4, 16, 64];
/// Depths swept by [`Knob::Depth`].
pub const DEPTHS: std::ops::RangeInclusive<u32> = 0..=8;
/// Global epsilons swept by [`Knob::Offset`], beside the scaled offset. Zero
/// is no offset at all; 1e-4 is the common textbook value.
pub const EPSILONS: [f32; 5] = [0.0, 1e-6, 1e-4, 1e-2, 1e-1];
/// Samples per pixel of the reference, for stages that supersample.
pub const REFERENCE_SAMPLES: u32 = 256;
/// Bounces of the reference.
pub const REFERENCE_DEPTH: u32 = 16;

/// The Fresnel models swept by [`Knob::Fresnel`], least accurate first.
pub const FRESNEL_MODELS: [FresnelModel; 3] = [
    FresnelModel::None,
    FresnelModel::Schlick,
    FresnelModel::Exact,
];

/// `scene` with `model` on every transparent material (the others have no
/// transmitted share for Fresnel to split).
pub fn with_fresnel(scene: &Scene, model: FresnelModel) -> Scene {
    let mut scene = scene.clone();
    for material in scene.materials_mut() {
        if material.transparency > 0.0 {
            material.fresnel = model;
        }
    }
    scene
}

/// The reference's `min_contribution` from chapter 9 on. Fresnel splits
/// every crossing of glass in two, so casting every ray to depth 16 is up
/// to 2^16 rays per sample in the glass (the chapter 9 sweep did not finish
/// in 15 minutes). Rays below 1e-5 of the pixel are skipped instead: each
/// is at most 1e-5 of the pixel's light, far below the half code (2e-3)
/// that changes an 8-bit value, unless thousands of them add up in one
/// pixel.
pub const GLASS_REFERENCE_MIN_CONTRIBUTION: f32 = 1e-5;

/// The reference: `base` with every knob at its most accurate setting.
/// `256` jittered samples per pixel (ignored before chapter 7), depth 16, no
/// minimum contribution, the scaled offset and the stable sphere formula.
pub fn reference_settings(base: &RenderSettings) -> RenderSettings {
    RenderSettings {
        samples: REFERENCE_SAMPLES,
        sampling: Sampling::Jittered,
        max_depth: REFERENCE_DEPTH,
        min_contribution: 0.0,
        ray_offset: OffsetRule::Scaled,
        sphere_formula: SphereFormula::Stable,
        triangle_test: TriangleTest::Watertight,
        march_tolerance: REFERENCE_MARCH_TOLERANCE,
        march_steps: REFERENCE_MARCH_STEPS,
        march_relaxation: 1.0,
        lipschitz: crate::shapes::LipschitzRule::Bound,
        newton: true,
        normals: crate::shapes::NormalMethod::Analytic,
        ..*base
    }
}

/// The scene of the [`Knob::SphereFormula`] sweep: a ball of radius 1 seen
/// from 1000 units away through a narrow lens, in front of a wall that
/// catches its shadow. With the camera that far, `b^2` and `4ac` in the
/// textbook formula are about `4e6` and differ by at most 4: the rounding of
/// either (a few tenths) is a visible share of the difference.
pub const FAR_SPHERE_SCENE: &str = r#"# The far small sphere of `raylab cost`: a ball of radius 1, 1000 units
# from the camera, in front of a wall 1.5 units behind it.
background = [0.55, 0.7, 0.9]
ambient_light = [1.0, 1.0, 1.0]

[camera]
position = [0.0, 0.0, -1000.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov_degrees = 0.2

[render]
width = 160
height = 120

[[lights]]
position = [-600.0, 800.0, -1000.0]
intensity = 1.0

[[objects]]
name = "far ball"
sphere = { center = [0.0, 0.0, 0.0], radius = 1.0 }
material = { color = [0.8, 0.2, 0.1], ambient = 0.1, diffuse = 0.8, specular = 0.5, shininess = 32 }

[[objects]]
name = "wall"
plane = { point = [0.0, 0.0, 1.5], normal = [0.0, 0.0, -1.0] }
material = { color = [0.9, 0.9, 0.85], ambient = 0.1, diffuse = 0.8, checker = { color = [0.5, 0.5, 0.55], size = 0.5 } }
"#;

/// The far-sphere scene, parsed.
pub fn far_sphere_scene() -> Scene {
    Scene::parse(FAR_SPHERE_SCENE, "the far-sphere scene of raylab cost")
        .expect("the built-in far-sphere scene is valid")
}

/// What to sweep.
#[derive(Debug, Clone)]
pub struct CostConfig {
    pub chapter: u8,
    /// The scene every knob but the sphere formula is swept on.
    pub scene: Scene,
    /// How the scene is named in the report (a path, or "built-in scene").
    pub scene_name: String,
    /// The settings each sweep starts from (the scene's, at the sweep's size).
    pub base: RenderSettings,
    pub knobs: Vec<Knob>,
    /// Renders per setting; the report gives the median time.
    pub repeats: u32,
}

/// One measured setting.
#[derive(Debug, Clone)]
pub struct Measurement {
    /// `None` for the reference itself.
    pub knob: Option<Knob>,
    /// The setting, as a student would type it ("jittered 16 spp", "depth 3").
    pub label: String,
    pub settings: RenderSettings,
    /// Whether it rendered the far-sphere scene rather than the main one.
    pub far_sphere: bool,
    /// Median wall time of the repeats, in seconds.
    pub seconds: f64,
    /// How many renders the median is of.
    pub runs: u32,
    pub rays: crate::RayCounts,
    pub error: ImageError,
    /// On the Pareto front of the main scene: no other setting is both
    /// faster and more accurate.
    pub pareto: bool,
}

/// How far an image is from the reference, in 8-bit sRGB codes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ImageError {
    pub rmse: f64,
    /// `f64::INFINITY` for identical images.
    pub psnr_db: f64,
    /// Share (0 to 1) of pixels with a channel more than 1 code off.
    pub share_off: f64,
}

/// Why a sweep stopped: a render refused, or an image that cannot be
/// measured against its reference.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CostError {
    #[error(transparent)]
    Render(#[from] crate::RenderError),
    /// The two buffers' lengths, in bytes of RGB.
    #[error(
        "cannot measure the error of an image of {image} bytes of RGB against a \
         reference of {reference}: only images of the same size can be compared"
    )]
    SizeMismatch { image: usize, reference: usize },
}

impl ImageError {
    /// The error of `image` against `reference` (same size, RGB8), with the
    /// metrics of `raylab diff` at a threshold of 1 code. Buffers of
    /// different sizes are an error naming both.
    pub fn between(image: &[u8], reference: &[u8]) -> Result<ImageError, CostError> {
        if image.len() != reference.len() || image.len() % 3 != 0 {
            return Err(CostError::SizeMismatch {
                image: image.len(),
                reference: reference.len(),
            });
        }
        let one_code = crate::diff::Criteria {
            threshold: 1,
            allowed_percent: 0.0,
        };
        let width = (image.len() / 3) as u32;
        let metrics = crate::diff::compare_pixels(image, reference, width, one_code).metrics;
        Ok(ImageError {
            rmse: metrics.rmse,
            psnr_db: metrics.psnr_db,
            share_off: metrics.pixels_over as f64 / metrics.pixels.max(1) as f64,
        })
    }
}

/// A finished sweep.
#[derive(Debug, Clone)]
pub struct CostReport {
    pub chapter: u8,
    pub scene_name: String,
    pub width: u32,
    pub height: u32,
    pub repeats: u32,
    /// The references first (main scene, then far sphere if swept), then
    /// every setting, knob by knob.
    pub rows: Vec<Measurement>,
}

/// One render to make.
struct Job {
    knob: Option<Knob>,
    label: String,
    settings: RenderSettings,
    far_sphere: bool,
    /// The Fresnel model every transparent material is given, or `None`
    /// for the scene's own.
    fresnel: Option<FresnelModel>,
}

impl Job {
    /// A render of the main scene with its own Fresnel models.
    fn new(knob: Knob, label: String, settings: RenderSettings) -> Job {
        Job {
            knob: Some(knob),
            label,
            settings,
            far_sphere: false,
            fresnel: None,
        }
    }
}

fn jobs(config: &CostConfig) -> Vec<Job> {
    let base = config.base;
    let mut jobs = Vec::new();
    for knob in &config.knobs {
        match knob {
            Knob::Samples => jobs.extend(sample_jobs(base)),
            Knob::Depth => {
                for max_depth in DEPTHS {
                    let settings = RenderSettings { max_depth, ..base };
                    jobs.push(Job::new(*knob, format!("depth {max_depth}"), settings));
                }
            }
            Knob::Offset => jobs.extend(offset_jobs(base)),
            Knob::SphereFormula => {
                for (formula, name) in [
                    (SphereFormula::Textbook, "textbook"),
                    (SphereFormula::Stable, "stable"),
                ] {
                    let settings = RenderSettings {
                        sphere_formula: formula,
                        ..base
                    };
                    jobs.push(Job {
                        far_sphere: true,
                        ..Job::new(*knob, format!("{name} formula, far sphere"), settings)
                    });
                }
            }
            Knob::Fresnel => {
                for model in FRESNEL_MODELS {
                    let label = match model {
                        FresnelModel::None => "fresnel none (chapter 8's constants)",
                        FresnelModel::Schlick => "fresnel schlick",
                        FresnelModel::Exact => "fresnel exact",
                    };
                    jobs.push(Job {
                        fresnel: Some(model),
                        ..Job::new(*knob, label.into(), base)
                    });
                }
            }
            Knob::TriangleTest => {
                for (test, label) in [
                    (TriangleTest::MollerTrumbore, "moller-trumbore"),
                    (TriangleTest::Watertight, "watertight"),
                ] {
                    let settings = RenderSettings {
                        triangle_test: test,
                        ..base
                    };
                    jobs.push(Job::new(*knob, label.into(), settings));
                }
            }
            // Measured by `crate::bvh_reports::cost`, not by rendering.
            Knob::Bvh => {}
            Knob::March => jobs.extend(march_jobs(base)),
            Knob::Normals => jobs.extend(normal_jobs(base)),
            Knob::Paths => jobs.extend(path_jobs(base)),
            Knob::Caustics => jobs.extend(caustic_jobs(base)),
        }
    }
    jobs
}

/// Hit tolerances swept by [`Knob::March`], coarsest first.
pub const MARCH_TOLERANCES: [f32; 4] = [1e-2, 1e-3, 1e-4, 1e-5];
/// Step budgets swept by [`Knob::March`].
pub const MARCH_STEPS: [u32; 4] = [16, 64, 256, 1024];
/// Over-relaxation factors swept by [`Knob::March`] (Keinert et al. 2014).
pub const RELAXATIONS: [f32; 4] = [1.0, 1.3, 1.6, 1.9];
/// Finite-difference steps swept by [`Knob::Normals`].
pub const NORMAL_STEPS: [f32; 4] = [1e-1, 1e-3, 1e-5, 1e-7];
/// The reference's march: a tolerance and a budget far beyond the sweep's,
/// safe steps, Newton, the analytic normal.
pub const REFERENCE_MARCH_TOLERANCE: f32 = 1e-6;
pub const REFERENCE_MARCH_STEPS: u32 = 4096;

/// The march knob's renders: each tolerance (Newton off, to show the
/// march's own error), each step budget, each relaxation, the step without
/// the Lipschitz factor, and Newton on against off.
fn march_jobs(base: RenderSettings) -> Vec<Job> {
    let mut jobs = Vec::new();
    for march_tolerance in MARCH_TOLERANCES {
        let settings = RenderSettings {
            march_tolerance,
            newton: false,
            ..base
        };
        let label = format!("tolerance {march_tolerance:e}, no newton");
        jobs.push(Job::new(Knob::March, label, settings));
    }
    for march_steps in MARCH_STEPS {
        let settings = RenderSettings {
            march_steps,
            ..base
        };
        jobs.push(Job::new(
            Knob::March,
            format!("{march_steps} steps"),
            settings,
        ));
    }
    for march_relaxation in RELAXATIONS {
        let settings = RenderSettings {
            march_relaxation,
            ..base
        };
        let label = format!("relaxation {march_relaxation}");
        jobs.push(Job::new(Knob::March, label, settings));
    }
    let settings = RenderSettings {
        lipschitz: crate::shapes::LipschitzRule::One,
        ..base
    };
    jobs.push(Job::new(
        Knob::March,
        "lipschitz one (unsafe)".into(),
        settings,
    ));
    for newton in [false, true] {
        let settings = RenderSettings { newton, ..base };
        let label = if newton { "newton" } else { "no newton" };
        jobs.push(Job::new(Knob::March, label.into(), settings));
    }
    jobs
}

/// Samples per pixel swept by [`Knob::Paths`]: squares (jittered cells),
/// each four times the last, so each should halve the noise.
pub const PATH_SAMPLE_COUNTS: [u32; 5] = [1, 4, 16, 64, 256];

/// Samples per pixel of the reference of a path-traced sweep: sixteen
/// times the most the sweep takes, so the reference's own noise is a
/// quarter of the best row's.
pub const PATH_REFERENCE_SAMPLES: u32 = 4096;

/// The switches [`Knob::Paths`] turns off, one at a time, and how each
/// row names it.
pub const PATH_SWITCHES: [(&str, &[&str]); 4] = [
    ("every switch", &[]),
    ("without mis", &["mis"]),
    ("without next-event", &["next-event"]),
    ("without russian-roulette", &["russian-roulette"]),
];

/// The paths knob's renders: each switch left out in turn, at each count.
fn path_jobs(base: RenderSettings) -> Vec<Job> {
    let mut jobs = Vec::new();
    for (name, off) in PATH_SWITCHES {
        let without = crate::scene::SwitchedOff::parse(off.iter().copied())
            .unwrap_or_default()
            .union(base.without);
        for samples in PATH_SAMPLE_COUNTS {
            let settings = RenderSettings {
                samples,
                sampling: Sampling::Jittered,
                without,
                ..base
            };
            jobs.push(Job::new(
                Knob::Paths,
                format!("{name}, {samples} spp"),
                settings,
            ));
        }
    }
    jobs
}

/// The caustics knob's renders: at each count of [`PATH_SAMPLE_COUNTS`],
/// camera paths alone (chapter 13's estimator), then camera paths with as
/// many light paths per pixel.
fn caustic_jobs(base: RenderSettings) -> Vec<Job> {
    let alone = crate::scene::SwitchedOff::parse(["light-tracing"])
        .unwrap_or_default()
        .union(base.without);
    let mut jobs = Vec::new();
    for (name, without) in [
        ("camera paths alone", alone),
        ("with light paths", base.without),
    ] {
        for count in PATH_SAMPLE_COUNTS {
            let settings = RenderSettings {
                samples: count,
                sampling: Sampling::Jittered,
                light_paths: count,
                without,
                ..base
            };
            let label = if without == alone {
                format!("{name}, {count} spp")
            } else {
                let paths = crate::text::count(u64::from(count), "light path");
                format!("{name}, {count} spp and {paths}")
            };
            jobs.push(Job::new(Knob::Caustics, label, settings));
        }
    }
    jobs
}

/// The normals knob's renders: the analytic gradient, then each difference
/// at each step.
fn normal_jobs(base: RenderSettings) -> Vec<Job> {
    use crate::shapes::NormalMethod;
    let analytic = RenderSettings {
        normals: NormalMethod::Analytic,
        ..base
    };
    let mut jobs = vec![Job::new(Knob::Normals, "analytic".into(), analytic)];
    for (normals, name) in [
        (NormalMethod::Central, "central"),
        (NormalMethod::Tetrahedron, "tetrahedron"),
    ] {
        for normal_step in NORMAL_STEPS {
            let settings = RenderSettings {
                normals,
                normal_step,
                ..base
            };
            let label = format!("{name}, h = {normal_step:e}");
            jobs.push(Job::new(Knob::Normals, label, settings));
        }
    }
    jobs
}

/// The samples knob's renders: the pixel centre, then each placement at
/// each sample count.
fn sample_jobs(base: RenderSettings) -> Vec<Job> {
    // One sample is the pixel's centre whatever the placement (a lone
    // sample is not anti-aliasing), so 1 spp is one row, not three
    // identical ones.
    let centre = RenderSettings {
        samples: 1,
        sampling: Sampling::Grid,
        ..base
    };
    let mut jobs = vec![Job::new(
        Knob::Samples,
        "1 spp (pixel centre)".to_string(),
        centre,
    )];
    for sampling in [Sampling::Grid, Sampling::Jittered, Sampling::Random] {
        for samples in SAMPLE_COUNTS {
            let name = format!("{sampling:?}").to_lowercase();
            let settings = RenderSettings {
                samples,
                sampling,
                ..base
            };
            jobs.push(Job::new(
                Knob::Samples,
                format!("{name} {samples} spp"),
                settings,
            ));
        }
    }
    jobs
}

/// The offset knob's renders: each fixed epsilon, then the scaled offset.
fn offset_jobs(base: RenderSettings) -> Vec<Job> {
    // With the textbook sphere test: the stable one rejects a root within
    // its own error bound of the origin, which hides most acne by itself
    // (lesson 4), and would leave this sweep nothing to show about the
    // offset.
    let base = RenderSettings {
        sphere_formula: SphereFormula::Textbook,
        ..base
    };
    let mut jobs = Vec::new();
    for epsilon in EPSILONS {
        let settings = RenderSettings {
            ray_offset: OffsetRule::Fixed,
            fixed_epsilon: epsilon,
            ..base
        };
        let label = if epsilon == 0.0 {
            "no offset (epsilon 0)".to_string()
        } else {
            format!("fixed epsilon {epsilon:e}")
        };
        jobs.push(Job::new(Knob::Offset, label, settings));
    }
    let settings = RenderSettings {
        ray_offset: OffsetRule::Scaled,
        ..base
    };
    jobs.push(Job::new(Knob::Offset, "scaled offset".into(), settings));
    jobs
}

/// How many renders [`run`] makes: for a progress bar.
pub fn render_count(config: &CostConfig) -> u64 {
    let implicit_knobs = config
        .knobs
        .iter()
        .any(|knob| matches!(knob, Knob::March | Knob::Normals));
    let references =
        1 + u64::from(config.knobs.contains(&Knob::SphereFormula)) + u64::from(implicit_knobs);
    references + jobs(config).len() as u64 * u64::from(config.repeats.max(1))
}

/// Runs the sweep on the current rayon pool; `progress` advances by one per
/// render.
pub fn run<C: crate::Chapters>(
    config: &CostConfig,
    progress: Option<&indicatif::ProgressBar>,
) -> Result<CostReport, CostError> {
    let scenes = SweepScenes::new(config);
    let chapter = config.chapter;
    let repeats = config.repeats.max(1);
    let render = |scene: &Scene, settings: &RenderSettings| {
        let rendered = crate::render_with::<C>(scene, chapter, settings, None)?;
        if let Some(bar) = progress {
            bar.inc(1);
        }
        Ok::<_, crate::RenderError>(rendered)
    };
    let reference_settings = sweep_reference_settings(config);
    // The references are rendered once: they are the slow part, and their
    // time is context, not a result.
    let mut references = vec![(false, render(&scenes.reference, &reference_settings)?)];
    if config.knobs.contains(&Knob::SphereFormula) {
        references.push((true, render(&scenes.far_sphere, &reference_settings)?));
    }
    let mut rows = reference_rows(&references, reference_settings)?;
    // The march's and the normals' error is their own, not the
    // anti-aliasing's: their reference is the scene's own samples and
    // depth with the reference's march.
    let implicit_knobs = config
        .knobs
        .iter()
        .any(|knob| matches!(knob, Knob::March | Knob::Normals));
    let march_reference = if implicit_knobs {
        let settings = RenderSettings {
            march_tolerance: REFERENCE_MARCH_TOLERANCE,
            march_steps: REFERENCE_MARCH_STEPS,
            ..reference_settings
        };
        let settings = RenderSettings {
            samples: config.base.samples,
            sampling: config.base.sampling,
            max_depth: config.base.max_depth,
            min_contribution: config.base.min_contribution,
            ..settings
        };
        let rendered = render(&scenes.reference, &settings)?;
        let mut row = measured(
            None,
            "reference, march (the scene's samples)".into(),
            settings,
            false,
            vec![rendered.clone()],
        );
        row.error = ImageError::between(&rendered.rgb, &rendered.rgb)?;
        rows.push(row);
        Some(rendered)
    } else {
        None
    };
    let jobs = jobs(config);
    let runs = render_repeats(&jobs, repeats, |job| {
        render(scenes.of(job, config), &job.settings)
    })?;
    for (job, job_runs) in jobs.into_iter().zip(runs) {
        let reference = match (&march_reference, job.knob) {
            (Some(march), Some(Knob::March | Knob::Normals)) => march,
            _ => reference_of(&references, job.far_sphere),
        };
        let error = ImageError::between(&job_runs[0].rgb, &reference.rgb)?;
        let mut row = measured(job.knob, job.label, job.settings, job.far_sphere, job_runs);
        row.error = error;
        rows.push(row);
    }
    mark_pareto_front(&mut rows);
    Ok(CostReport {
        chapter,
        scene_name: config.scene_name.clone(),
        width: config.base.width,
        height: config.base.height,
        repeats,
        rows,
    })
}

/// The scenes a sweep renders besides the one swept: the reference's, one
/// per Fresnel model when that knob is swept, and the far-sphere scene.
struct SweepScenes {
    reference: Scene,
    fresnel: Vec<(FresnelModel, Scene)>,
    far_sphere: Scene,
}

impl SweepScenes {
    fn new(config: &CostConfig) -> SweepScenes {
        let far_sphere = far_sphere_scene();
        // From chapter 9 on, the reference reflects by exact Fresnel wherever
        // light crosses a surface; the Fresnel knob's rows give every
        // transparent material one model.
        let reference = if Effects::for_chapter(config.chapter).fresnel {
            with_fresnel(&config.scene, FresnelModel::Exact)
        } else {
            config.scene.clone()
        };
        let fresnel = if config.knobs.contains(&Knob::Fresnel) {
            FRESNEL_MODELS
                .into_iter()
                .map(|model| (model, with_fresnel(&config.scene, model)))
                .collect()
        } else {
            Vec::new()
        };
        SweepScenes {
            reference,
            fresnel,
            far_sphere,
        }
    }

    /// The scene `job` renders: the far sphere, the swept scene with the
    /// job's Fresnel model, or the swept scene as it is.
    fn of<'a>(&'a self, job: &Job, config: &'a CostConfig) -> &'a Scene {
        match (job.far_sphere, job.fresnel) {
            (true, _) => &self.far_sphere,
            (false, Some(model)) => self
                .fresnel
                .iter()
                .find(|(m, _)| *m == model)
                .map_or(&config.scene, |(_, scene)| scene),
            (false, None) => &config.scene,
        }
    }
}

/// The settings of this sweep's reference: [`reference_settings`], with a
/// smaller cut-off of secondary rays once exact Fresnel is on.
fn sweep_reference_settings(config: &CostConfig) -> RenderSettings {
    let mut settings = reference_settings(&config.base);
    if Effects::for_chapter(config.chapter).fresnel {
        settings.min_contribution = GLASS_REFERENCE_MIN_CONTRIBUTION;
    }
    // A path's depth is its own knob (the scene's, 50 in the Cornell box)
    // and its noise needs many more samples to fall below the rows'.
    if Effects::for_chapter(config.chapter).path_tracing {
        settings.samples = PATH_REFERENCE_SAMPLES;
        settings.max_depth = config.base.max_depth.max(REFERENCE_DEPTH);
        settings.light_paths = PATH_REFERENCE_SAMPLES;
    }
    settings
}

/// The row of a setting rendered `runs` times: their median time, the last
/// run's rays, and no error yet.
fn measured(
    knob: Option<Knob>,
    label: String,
    settings: RenderSettings,
    far_sphere: bool,
    runs: Vec<Rendered>,
) -> Measurement {
    let mut seconds: Vec<f64> = runs.iter().map(|r| r.seconds).collect();
    let last = runs.into_iter().last().expect("at least one run");
    Measurement {
        knob,
        label,
        settings,
        far_sphere,
        seconds: median(&mut seconds),
        runs: seconds.len() as u32,
        rays: last.rays,
        error: ImageError::default(),
        pareto: false,
    }
}

/// The rows of the references (`far_sphere`, image), each at error zero.
fn reference_rows(
    references: &[(bool, Rendered)],
    settings: RenderSettings,
) -> Result<Vec<Measurement>, CostError> {
    references
        .iter()
        .map(|(far_sphere, rendered)| -> Result<Measurement, CostError> {
            let label = if *far_sphere {
                "reference, far sphere"
            } else {
                "reference"
            };
            let mut row = measured(
                None,
                label.into(),
                settings,
                *far_sphere,
                vec![rendered.clone()],
            );
            row.error = ImageError::between(&rendered.rgb, &rendered.rgb)?;
            Ok(row)
        })
        .collect()
}

/// The reference of the main scene, or of the far-sphere scene.
fn reference_of(references: &[(bool, Rendered)], far_sphere: bool) -> &Rendered {
    &references
        .iter()
        .find(|(far, _)| *far == far_sphere)
        .expect("a reference for each scene swept")
        .1
}

/// Every job's `repeats` renders, in the order of `jobs`; only the first
/// render of each keeps its image (the one compared).
fn render_repeats(
    jobs: &[Job],
    repeats: u32,
    render: impl Fn(&Job) -> Result<Rendered, crate::RenderError>,
) -> Result<Vec<Vec<Rendered>>, crate::RenderError> {
    let mut runs: Vec<Vec<Rendered>> = jobs.iter().map(|_| Vec::new()).collect();
    // Repeats go round the whole sweep rather than one setting at a time:
    // when the machine gets busier or quieter mid-sweep, every setting's
    // median sees the same mix of conditions.
    for _ in 0..repeats {
        for (job, job_runs) in jobs.iter().zip(&mut runs) {
            let mut rendered = render(job)?;
            if !job_runs.is_empty() {
                rendered.rgb = Vec::new(); // only the first image is compared
            }
            job_runs.push(rendered);
        }
    }
    Ok(runs)
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    match values.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => values[n / 2],
        n => 0.5 * (values[n / 2 - 1] + values[n / 2]),
    }
}

/// Marks the settings of the main scene that no other one beats on both
/// time and error (the reference is not a candidate: its error is zero by
/// definition).
fn mark_pareto_front(rows: &mut [Measurement]) {
    let candidates: Vec<usize> = (0..rows.len())
        .filter(|&i| rows[i].knob.is_some() && !rows[i].far_sphere)
        .collect();
    for &i in &candidates {
        let dominated = candidates.iter().any(|&j| {
            let (a, b) = (&rows[j], &rows[i]);
            a.seconds <= b.seconds
                && a.error.rmse <= b.error.rmse
                && (a.seconds < b.seconds || a.error.rmse < b.error.rmse)
        });
        rows[i].pareto = !dominated;
    }
}

impl Measurement {
    /// Samples per pixel actually taken at `chapter`'s stage.
    fn samples_at(&self, chapter: u8) -> u32 {
        if Effects::for_chapter(chapter).antialiasing {
            self.settings.samples
        } else {
            1
        }
    }

    fn knob_name(&self) -> &'static str {
        self.knob.map_or("reference", Knob::name)
    }
}

fn format_psnr(psnr: f64) -> String {
    if psnr.is_finite() {
        format!("{psnr:.1}")
    } else {
        "inf".into()
    }
}

impl CostReport {
    /// The command line that reproduces this report.
    pub fn command(&self, knobs: &[Knob], out: Option<&str>) -> String {
        let mut command = format!("raylab cost --chapter {}", self.chapter);
        if self.scene_name != "built-in scene" {
            let _ = write!(command, " --scene {}", self.scene_name);
        }
        let _ = write!(command, " --width {} --height {}", self.width, self.height);
        let _ = write!(command, " --repeats {}", self.repeats);
        if knobs != Knob::of_chapter(self.chapter).as_slice() {
            for knob in knobs {
                let _ = write!(command, " --knob {}", knob.name());
            }
        }
        if let Some(out) = out {
            let _ = write!(command, " --out {out}");
        }
        command
    }

    /// The report as a Markdown table with a short header.
    pub fn markdown(&self) -> String {
        let mut text = String::new();
        let reference = self.rows.first().map(|r| r.settings);
        let _ = writeln!(
            text,
            "Chapter {} stage, {} ({}x{}); time: median of {}; error against the reference in 8-bit sRGB codes.",
            self.chapter,
            self.scene_name,
            self.width,
            self.height,
            crate::text::count(u64::from(self.repeats), "run")
        );
        if let Some(reference) = reference {
            let samples = if Effects::for_chapter(self.chapter).antialiasing {
                format!("{} jittered spp", reference.samples)
            } else {
                "1 spp (this stage does not supersample)".into()
            };
            let fresnel = if Effects::for_chapter(self.chapter).fresnel {
                ", exact Fresnel on every transparent material"
            } else {
                ""
            };
            let stage = Effects::for_chapter(self.chapter);
            // Paths never skip a ray by its share: roulette ends them.
            let cut_off = if stage.path_tracing {
                String::new()
            } else {
                format!(", min_contribution {}", reference.min_contribution)
            };
            let light_paths = if stage.light_tracing {
                format!(", {} light paths per pixel", reference.light_paths)
            } else {
                String::new()
            };
            let _ = writeln!(
                text,
                "Reference: {samples}{light_paths}, depth {}{cut_off}, scaled offset, stable sphere formula{fresnel} (1 run).",
                reference.max_depth
            );
        }
        text.push('\n');
        text.push_str(
            "| knob | setting | time (ms) | rays | RMSE | PSNR (dB) | pixels off > 1/255 | acne pixels | Pareto |\n",
        );
        text.push_str("|---|---|---:|---:|---:|---:|---:|---:|:-:|\n");
        for row in &self.rows {
            let _ = writeln!(
                text,
                "| {} | {} | {:.1} | {} | {:.3} | {} | {:.2}% | {} | {} |",
                row.knob_name(),
                row.label,
                row.seconds * 1e3,
                row.rays.total(),
                row.error.rmse,
                format_psnr(row.error.psnr_db),
                row.error.share_off * 100.0,
                row.rays.self_shadowed_pixels,
                if row.pareto { "yes" } else { "" },
            );
        }
        text
    }

    /// The report as CSV, one row per setting.
    pub fn csv(&self) -> String {
        let mut text = String::from(
            "chapter,scene,knob,setting,samples,sampling,max_depth,min_contribution,ray_offset,fixed_epsilon,sphere_formula,\
             runs,seconds_median,rays_total,rays_primary,rays_shadow,rays_reflection,rays_refraction,\
             rays_bounce,rays_light,rays_to_camera,rmse_srgb8,psnr_db,share_pixels_off,self_shadowed_pixels,pareto\n",
        );
        for row in &self.rows {
            let s = &row.settings;
            let scene = if row.far_sphere {
                "far sphere"
            } else {
                &self.scene_name
            };
            let _ = writeln!(
                text,
                "{},{},{},{},{},{},{},{},{},{},{},{},{:.6},{},{},{},{},{},{},{},{},{:.6},{},{:.6},{},{}",
                self.chapter,
                csv_field(scene),
                row.knob_name(),
                csv_field(&row.label),
                row.samples_at(self.chapter),
                format!("{:?}", s.sampling).to_lowercase(),
                s.max_depth,
                s.min_contribution,
                format!("{:?}", s.ray_offset).to_lowercase(),
                s.fixed_epsilon,
                format!("{:?}", s.sphere_formula).to_lowercase(),
                row.runs,
                row.seconds,
                row.rays.total(),
                row.rays.primary,
                row.rays.shadow,
                row.rays.reflection,
                row.rays.refraction,
                row.rays.bounce,
                row.rays.light,
                row.rays.to_camera,
                row.error.rmse,
                if row.error.psnr_db.is_finite() {
                    format!("{:.3}", row.error.psnr_db)
                } else {
                    "inf".into()
                },
                row.error.share_off,
                row.rays.self_shadowed_pixels,
                row.pareto,
            );
        }
        text
    }

    /// Error against time, both on log scales, one colour per knob, the
    /// Pareto front of the main scene joined by a line, as SVG. Settings
    /// identical to the reference (RMSE 0) sit on the bottom edge.
    pub fn svg(&self) -> Result<String, crate::plots::PlotError> {
        plot_svg(self).map_err(crate::plots::PlotError::drawing)
    }
}

fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// Round axis ticks between `low` and `high`: 1, 2 and 5 times powers of ten.
/// Parsed from text so that they print as written ("0.005", not
/// "0.005000000000000001").
fn ticks(low: f64, high: f64) -> Vec<f64> {
    let (first, last) = (low.log10().floor() as i32, high.log10().ceil() as i32);
    (first..=last)
        .flat_map(|power| [1, 2, 5].map(|m| format!("{m}e{power}").parse::<f64>()))
        .filter_map(Result::ok)
        .filter(|tick| (low..=high).contains(tick))
        .collect()
}

/// The ranges the plot shows, on log scales: errors from `floor` (where the
/// settings identical to the reference sit) to `largest_error`, times from
/// `fastest` to `slowest`.
struct PlotRanges {
    floor: f64,
    largest_error: f64,
    fastest: f64,
    slowest: f64,
}

impl PlotRanges {
    fn of(rows: &[&Measurement]) -> PlotRanges {
        let smallest_error = rows
            .iter()
            .map(|r| r.error.rmse)
            .filter(|e| *e > 0.0)
            .fold(f64::INFINITY, f64::min);
        let floor = if smallest_error.is_finite() {
            smallest_error / 2.0
        } else {
            0.01
        };
        let largest_error = rows
            .iter()
            .map(|r| r.error.rmse)
            .fold(floor * 4.0, f64::max);
        let positive_seconds = rows.iter().map(|r| r.seconds).filter(|s| *s > 0.0);
        let fastest = positive_seconds.clone().fold(f64::INFINITY, f64::min);
        let slowest = positive_seconds.fold(0.0, f64::max);
        let (fastest, slowest) = if fastest.is_finite() && slowest > 0.0 {
            (fastest, slowest)
        } else {
            (1e-4, 1.0)
        };
        PlotRanges {
            floor,
            largest_error,
            fastest,
            slowest,
        }
    }

    /// Where `row` is drawn: its time and error, moved onto the plot's
    /// edges when they are zero.
    fn point(&self, row: &Measurement) -> (f64, f64) {
        (
            row.seconds.max(self.fastest),
            row.error.rmse.max(self.floor),
        )
    }
}

/// The cost plot's chart: log-scaled time across, log-scaled error up.
type CostChart<'a, 'b> = plotters::chart::ChartContext<
    'a,
    plotters::backend::SVGBackend<'b>,
    plotters::coord::cartesian::Cartesian2d<
        plotters::coord::combinators::WithKeyPoints<plotters::coord::combinators::LogCoord<f64>>,
        plotters::coord::combinators::WithKeyPoints<plotters::coord::combinators::LogCoord<f64>>,
    >,
>;

fn plot_svg(report: &CostReport) -> Result<String, Box<dyn std::error::Error>> {
    use plotters::prelude::*;

    let rows: Vec<&Measurement> = report.rows.iter().filter(|r| r.knob.is_some()).collect();
    let ranges = PlotRanges::of(&rows);
    let PlotRanges {
        floor,
        largest_error,
        fastest,
        slowest,
    } = ranges;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (800, 580)).into_drawing_area();
        root.fill(&WHITE)?;
        let (plot_area, note_area) = root.split_vertically(550);
        let title = format!(
            "raylab cost, chapter {}: error vs time ({}x{})",
            report.chapter, report.width, report.height
        );
        let mut chart = ChartBuilder::on(&plot_area)
            .caption(title, ("sans-serif", 20))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(64)
            .build_cartesian_2d(
                (fastest / 1.5..slowest * 1.5)
                    .log_scale()
                    .with_key_points(ticks(fastest / 1.5, slowest * 1.5)),
                // Headroom above the points for the legend.
                (floor / 1.5..largest_error * 8.0)
                    .log_scale()
                    .with_key_points(ticks(floor / 1.5, largest_error * 8.0)),
            )?;
        chart
            .configure_mesh()
            .x_desc("wall time, seconds (median)")
            .y_desc("RMSE against the reference (sRGB8 codes)")
            .x_label_formatter(&|s| format!("{s}"))
            .y_label_formatter(&|e| format!("{e}"))
            .draw()?;
        let mut front: Vec<&Measurement> = rows.iter().copied().filter(|r| r.pareto).collect();
        front.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
        draw_front(&mut chart, &ranges, &front)?;
        draw_knobs(&mut chart, &ranges, &rows)?;
        draw_root_n(&mut chart, &ranges, &rows)?;
        draw_front_labels(&mut chart, &ranges, &front)?;
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
        note_area.draw(&Text::new(
            format!(
                "Pareto front: the main scene's settings that no other beats on both time and error. \
                 Bottom edge: identical to the reference. Time: median of {}.",
                crate::text::count(u64::from(report.repeats), "run")
            ),
            (16, 8),
            ("sans-serif", 12),
        ))?;
        root.present()?;
    }
    Ok(svg)
}

/// For a path-traced sweep, the error Monte Carlo promises: from the
/// 1-sample row with every switch, `1 / sqrt(N)` of it at `N` times its
/// time (time grows with the samples, so that is `1 / sqrt(time)`).
fn draw_root_n(
    chart: &mut CostChart,
    ranges: &PlotRanges,
    rows: &[&Measurement],
) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    let series: Vec<&&Measurement> = rows
        .iter()
        .filter(|row| row.knob == Some(Knob::Paths) && row.settings.without == rows_base(rows))
        .collect();
    let (Some(first), Some(last)) = (
        series
            .iter()
            .min_by(|a, b| a.settings.samples.cmp(&b.settings.samples)),
        series.iter().max_by(|a, b| a.seconds.total_cmp(&b.seconds)),
    ) else {
        return Ok(());
    };
    let (start, error) = ranges.point(first);
    let end = last.seconds.max(start);
    let steps = 16;
    let line = (0..=steps).map(|step| {
        let time = start * (end / start).powf(f64::from(step) / f64::from(steps));
        (time, (error * (start / time).sqrt()).max(ranges.floor))
    });
    chart
        .draw_series(LineSeries::new(
            line,
            RGBColor(120, 120, 120).stroke_width(1),
        ))?
        .label("1 / sqrt(N) from 1 spp")
        .legend(|(x, y)| {
            PathElement::new(
                vec![(x, y), (x + 16, y)],
                RGBColor(120, 120, 120).stroke_width(1),
            )
        });
    Ok(())
}

/// What the paths knob's "every switch" rows leave out: the smallest set
/// among its rows (the scene's own `without`).
fn rows_base(rows: &[&Measurement]) -> crate::scene::SwitchedOff {
    rows.iter()
        .filter(|row| row.knob == Some(Knob::Paths) && row.label.starts_with(PATH_SWITCHES[0].0))
        .map(|row| row.settings.without)
        .next()
        .unwrap_or_default()
}

/// The Pareto front (sorted by time), as a line through ringed points.
fn draw_front(
    chart: &mut CostChart,
    ranges: &PlotRanges,
    front: &[&Measurement],
) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    chart
        .draw_series(LineSeries::new(
            front.iter().map(|r| ranges.point(r)),
            BLACK.stroke_width(2),
        ))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK.stroke_width(2)));
    chart.draw_series(
        front
            .iter()
            .map(|r| Circle::new(ranges.point(r), 7, BLACK.stroke_width(1))),
    )?;
    Ok(())
}

/// Every setting as a dot, one colour (and legend entry) per knob swept.
fn draw_knobs(
    chart: &mut CostChart,
    ranges: &PlotRanges,
    rows: &[&Measurement],
) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    // One colour a knob (a shorter list would leave the last knobs undrawn).
    let colours: [RGBColor; Knob::ALL.len()] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
        RGBColor(188, 189, 34),
        RGBColor(23, 190, 207),
        RGBColor(0, 0, 128),
    ];
    for (knob, colour) in Knob::ALL.into_iter().zip(colours) {
        let points: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.knob == Some(knob))
            .map(|r| ranges.point(r))
            .collect();
        if points.is_empty() {
            continue;
        }
        let label = if knob == Knob::SphereFormula {
            "sphere formula (far-sphere scene)"
        } else {
            knob.name()
        };
        chart
            .draw_series(
                points
                    .into_iter()
                    .map(|point| Circle::new(point, 4, colour.filled())),
            )?
            .label(label)
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, colour.filled()));
    }
    Ok(())
}

/// The front's points labelled with their settings, skipping any that
/// would print over a label already placed (points with the same error
/// cluster).
fn draw_front_labels(
    chart: &mut CostChart,
    ranges: &PlotRanges,
    front: &[&Measurement],
) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    let mut labelled: Vec<(f64, f64)> = Vec::new();
    let mut labels: Vec<&Measurement> = Vec::new();
    for r in front {
        let (seconds, error) = ranges.point(r);
        let at = (seconds.log10(), error.log10());
        let crowded = labelled
            .iter()
            .any(|(x, y)| (x - at.0).abs() < 0.25 && (y - at.1).abs() < 0.06);
        if !crowded {
            labelled.push(at);
            labels.push(r);
        }
    }
    chart.draw_series(labels.iter().map(|r| {
        let (seconds, error) = ranges.point(r);
        Text::new(
            r.label.clone(),
            (seconds * 1.06, error * 1.06),
            ("sans-serif", 11),
        )
    }))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_csv_counts_every_kind_of_ray_and_the_kinds_add_up_to_the_total() {
        let rays = crate::RayCounts {
            primary: 1,
            shadow: 20,
            reflection: 300,
            refraction: 4_000,
            bounce: 50_000,
            light: 600_000,
            to_camera: 7_000_000,
            ..Default::default()
        };
        let report = CostReport {
            chapter: 14,
            scene_name: "box".into(),
            width: 2,
            height: 2,
            repeats: 1,
            rows: vec![Measurement {
                knob: None,
                label: "reference".into(),
                settings: RenderSettings::default(),
                far_sphere: false,
                seconds: 1.0,
                runs: 1,
                rays,
                error: ImageError::default(),
                pareto: false,
            }],
        };
        let csv = report.csv();
        let mut lines = csv.lines();
        let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
        let row: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
        assert_eq!(header.len(), row.len());
        let column = |name: &str| -> u64 {
            let index = header.iter().position(|column| *column == name);
            index.and_then(|index| row[index].parse().ok()).unwrap_or(0)
        };
        let kinds: u64 = header
            .iter()
            .filter(|name| name.starts_with("rays_") && **name != "rays_total")
            .map(|name| column(name))
            .sum();
        assert_eq!(column("rays_total"), rays.total());
        assert_eq!(kinds, rays.total(), "{csv}");
    }

    #[test]
    fn identical_images_have_no_error() {
        let image = [10u8, 20, 30, 40, 50, 60];
        let error = ImageError::between(&image, &image).unwrap();
        assert_eq!(error.rmse, 0.0);
        assert_eq!(error.psnr_db, f64::INFINITY);
        assert_eq!(error.share_off, 0.0);
    }

    #[test]
    fn one_code_off_is_not_counted_but_two_are() {
        let reference = [100u8; 6];
        let one_off = [101u8, 100, 100, 100, 100, 100];
        assert_eq!(
            ImageError::between(&one_off, &reference).unwrap().share_off,
            0.0
        );
        let two_off = [100u8, 100, 100, 100, 98, 100];
        let error = ImageError::between(&two_off, &reference).unwrap();
        assert_eq!(error.share_off, 0.5);
        // One channel of six off by 2: RMSE = sqrt(4 / 6).
        assert!((error.rmse - (4.0f64 / 6.0).sqrt()).abs() < 1e-12);
        assert!((error.psnr_db - 20.0 * (255.0 / error.rmse).log10()).abs() < 1e-9);
    }

    #[test]
    fn images_of_different_sizes_are_an_error_not_a_panic() {
        let message = ImageError::between(&[0; 6], &[0; 9])
            .unwrap_err()
            .to_string();
        assert!(message.contains("6 bytes"), "{message}");
        assert!(message.contains("same size"), "{message}");
    }

    /// The march's knobs against their own reference (the scene's samples,
    /// a tight march): a finer tolerance and a larger budget are never
    /// worse, and the step without the Lipschitz factor is worse than the
    /// safe one. Errors are deterministic; times are not compared.
    #[test]
    fn the_march_knobs_trade_error_as_the_lesson_says() {
        let scene = crate::builtin::scene(12).expect("the built-in scene");
        let base = RenderSettings {
            width: 80,
            height: 60,
            ..scene.render
        };
        let config = CostConfig {
            chapter: 12,
            scene,
            scene_name: "built-in scene".into(),
            base,
            knobs: vec![Knob::March],
            repeats: 1,
        };
        let report = run::<crate::Reference>(&config, None).expect("the sweep runs");
        let rmse = |label: &str| {
            report
                .rows
                .iter()
                .find(|row| row.label == label)
                .map(|row| row.error.rmse)
                .unwrap_or_else(|| panic!("no row {label}"))
        };
        let tolerances: Vec<f64> = MARCH_TOLERANCES
            .iter()
            .map(|tolerance| rmse(&format!("tolerance {tolerance:e}, no newton")))
            .collect();
        assert!(
            tolerances.windows(2).all(|pair| pair[1] <= pair[0]),
            "{tolerances:?}"
        );
        let budgets: Vec<f64> = MARCH_STEPS
            .iter()
            .map(|steps| rmse(&format!("{steps} steps")))
            .collect();
        assert!(
            budgets.windows(2).all(|pair| pair[1] <= pair[0]),
            "{budgets:?}"
        );
        assert!(rmse("lipschitz one (unsafe)") > 2.0 * rmse("relaxation 1"));
        assert!(rmse("newton") <= rmse("no newton"));
    }

    #[test]
    fn medians() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
    }

    #[test]
    fn chapters_have_the_knobs_they_teach() {
        assert!(Knob::of_chapter(1).is_empty());
        assert_eq!(Knob::of_chapter(2), vec![Knob::SphereFormula]);
        assert_eq!(
            Knob::of_chapter(6),
            vec![Knob::Depth, Knob::Offset, Knob::SphereFormula]
        );
        assert_eq!(Knob::of_chapter(8), Knob::ALL[..4].to_vec());
        assert_eq!(Knob::of_chapter(9), Knob::ALL[..5].to_vec());
        assert_eq!(Knob::of_chapter(10), Knob::ALL[..6].to_vec());
        assert_eq!(Knob::of_chapter(11), Knob::ALL[..7].to_vec());
        assert_eq!(Knob::of_chapter(12), Knob::ALL[..9].to_vec());
        assert_eq!(Knob::of_chapter(13), Knob::ALL[..10].to_vec());
        assert_eq!(Knob::of_chapter(14), Knob::ALL.to_vec());
    }

    #[test]
    fn far_sphere_scene_is_valid() {
        assert_eq!(far_sphere_scene().shapes.len(), 2);
    }
}
