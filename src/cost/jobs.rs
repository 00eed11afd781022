//! The renders a sweep makes: for each knob, the values it is turned to
//! and one job per value. Adding a setting to a knob's sweep is an edit
//! here alone: running, measuring and reporting take whatever jobs this
//! lists.

use super::{CostConfig, Knob};
use crate::scene::{FresnelModel, OffsetRule, SphereFormula, TriangleTest};
use crate::{RenderSettings, Sampling};

/// Sample counts swept by [`Knob::Samples`] for each placement, after one
/// row at 1 sample (the pixel centre, whatever the placement): squares, so
/// grid and jittered sampling can use them too.
pub const SAMPLE_COUNTS: [u32; 3] = [4, 16, 64];
/// Depths swept by [`Knob::Depth`].
pub const DEPTHS: std::ops::RangeInclusive<u32> = 0..=8;
/// Global epsilons swept by [`Knob::Offset`], beside the scaled offset. Zero
/// is no offset at all; 1e-4 is the common textbook value.
pub const EPSILONS: [f32; 5] = [0.0, 1e-6, 1e-4, 1e-2, 1e-1];

/// The Fresnel models swept by [`Knob::Fresnel`], least accurate first.
pub const FRESNEL_MODELS: [FresnelModel; 3] = [
    FresnelModel::None,
    FresnelModel::Schlick,
    FresnelModel::Exact,
];

/// Hit tolerances swept by [`Knob::March`], coarsest first.
pub const MARCH_TOLERANCES: [f32; 4] = [1e-2, 1e-3, 1e-4, 1e-5];
/// Step budgets swept by [`Knob::March`].
pub const MARCH_STEPS: [u32; 4] = [16, 64, 256, 1024];
/// Over-relaxation factors swept by [`Knob::March`] (Keinert et al. 2014).
pub const RELAXATIONS: [f32; 4] = [1.0, 1.3, 1.6, 1.9];
/// Finite-difference steps swept by [`Knob::Normals`].
pub const NORMAL_STEPS: [f32; 4] = [1e-1, 1e-3, 1e-5, 1e-7];

/// Samples per pixel swept by [`Knob::Paths`]: squares (jittered cells),
/// each four times the last, so each should halve the noise.
pub const PATH_SAMPLE_COUNTS: [u32; 5] = [1, 4, 16, 64, 256];

/// The switches [`Knob::Paths`] turns off, one at a time, and how each
/// row names it.
pub const PATH_SWITCHES: [(&str, &[&str]); 4] = [
    ("every switch", &[]),
    ("without mis", &["mis"]),
    ("without next-event", &["next-event"]),
    ("without russian-roulette", &["russian-roulette"]),
];

/// One render to make.
pub(super) struct Job {
    pub(super) knob: Option<Knob>,
    pub(super) label: String,
    pub(super) settings: RenderSettings,
    pub(super) far_sphere: bool,
    /// The Fresnel model every transparent material is given, or `None`
    /// for the scene's own.
    pub(super) fresnel: Option<FresnelModel>,
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

pub(super) fn jobs(config: &CostConfig) -> Vec<Job> {
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
            // Measured by `super::neighbours`, which makes its own images.
            Knob::Neighbours => {}
            Knob::March => jobs.extend(march_jobs(base)),
            Knob::Normals => jobs.extend(normal_jobs(base)),
            Knob::Paths => jobs.extend(path_jobs(base)),
            Knob::Caustics => jobs.extend(caustic_jobs(base)),
        }
    }
    jobs
}

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
