//! Running a sweep: the references, then every job's repeats, each image
//! measured against its reference and the Pareto front marked. The one
//! part of `raylab cost` that renders (and takes time), apart from what
//! the jobs are and from how a finished report is shown.

use super::jobs::{FRESNEL_MODELS, Job, jobs};
use super::reference::{
    GLASS_REFERENCE_MIN_CONTRIBUTION, PATH_REFERENCE_SAMPLES, REFERENCE_DEPTH,
    REFERENCE_MARCH_STEPS, REFERENCE_MARCH_TOLERANCE, far_sphere_scene, reference_settings,
    with_fresnel,
};
use super::{CostConfig, CostError, CostReport, ImageError, Knob, Measurement};
use crate::effects::Effects;
use crate::render::Rendered;
use crate::scene::FresnelModel;
use crate::{RenderSettings, Scene};

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
        // Linear radiance too: the error in linear light (relative MSE).
        let rendered = crate::render_linear_with::<C>(scene, chapter, settings, None)?;
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
        row.error = ImageError::between_renders(&rendered, &rendered)?;
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
        let error = ImageError::between_renders(&job_runs[0], reference)?;
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
            row.error = ImageError::between_renders(rendered, rendered)?;
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
                // Only the first image is compared.
                rendered.rgb = Vec::new();
                rendered.linear = Vec::new();
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cost::{MARCH_STEPS, MARCH_TOLERANCES};

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
}
