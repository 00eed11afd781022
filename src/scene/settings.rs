//! A scene's `[render]` settings: the image's size and samples, and the
//! choices the chapters compare (which formula, which offset, which test),
//! each checked against [`crate::limits`] whether it came from the file or
//! the command line.

use serde::{Deserialize, Serialize};

use super::switches::SwitchedOff;
use crate::limits::{MAX_DEPTH, MAX_IMAGE_SAMPLES, MAX_PIXELS, MAX_SAMPLES, MAX_SIDE};
use crate::number;
use crate::shapes::{LipschitzRule, MAX_MARCH_STEPS, March, NormalMethod};

/// Image size and quality settings; the command line can override each.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel (used from chapter 7 on).
    pub samples: u32,
    /// Where the samples go inside a pixel (chapter 7).
    pub sampling: Sampling,
    /// Maximum number of bounces for reflection and refraction (chapters 6, 8).
    pub max_depth: u32,
    /// A secondary ray whose weight in the pixel falls below this is not
    /// cast (0 casts every ray up to `max_depth`).
    #[serde(deserialize_with = "number::f32")]
    pub min_contribution: f32,
    /// Seed of the per-pixel random sample positions.
    pub seed: u64,
    /// How ray-sphere hits are solved: `"stable"` (chapter 2's
    /// cancellation-free roots) or `"textbook"` (for comparison).
    pub sphere_formula: SphereFormula,
    /// Where secondary rays start: `"scaled"` (chapter 4's error-scaled
    /// push) or `"fixed"` (`fixed_epsilon` along the ray, for comparison).
    pub ray_offset: OffsetRule,
    /// The distance used by `ray_offset = "fixed"`.
    #[serde(deserialize_with = "number::f32")]
    pub fixed_epsilon: f32,
    /// How ray-triangle hits are found: `"watertight"` (chapter 10's test,
    /// no ray lost on a shared edge) or `"moller-trumbore"` (for comparison).
    pub triangle_test: TriangleTest,
    /// Where rays leave a smooth-shaded triangle: `"lifted"` (chapter 10's
    /// fix for the shadow terminator) or `"flat"` (from the flat triangle,
    /// to show the problem it fixes).
    pub terminator: TerminatorRule,
    /// Chapter 12: a march stops within this fraction of the distance
    /// travelled from an implicit surface.
    #[serde(deserialize_with = "number::f32")]
    pub march_tolerance: f32,
    /// Chapter 12: evaluations a march may spend before it gives up.
    pub march_steps: u32,
    /// Chapter 12: over-relaxation of the march's steps, 1 to 2 (1: safe
    /// steps only).
    #[serde(deserialize_with = "number::f32")]
    pub march_relaxation: f32,
    /// Chapter 12: `"bound"` (the tree's Lipschitz bound) or `"one"`
    /// (trust every function as a distance, to show the holes).
    pub lipschitz: LipschitzRule,
    /// Chapter 12: refine each march's hit by Newton's method in a bracket.
    pub newton: bool,
    /// Chapter 12: `"analytic"`, `"central"` or `"tetrahedron"`.
    pub normals: NormalMethod,
    /// Chapter 12: the step of the finite-difference normals.
    #[serde(deserialize_with = "number::f32")]
    pub normal_step: f32,
    /// Effects of the chapter's stage not to simulate (`without =
    /// ["reflection"]`): what the image is without them.
    pub without: SwitchedOff,
    /// Chapter 14: paths traced from the lights, per pixel of the image.
    pub light_paths: u32,
}

/// Where the rays that leave a smooth-shaded triangle start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TerminatorRule {
    /// Lifted towards the curved surface the vertex normals describe
    /// (`terminator_point`).
    #[default]
    Lifted,
    /// On the flat triangle, where the hit is: the shadow terminator shows
    /// as facet-shaped shadows.
    Flat,
}

/// How ray-triangle intersections are found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TriangleTest {
    #[default]
    Watertight,
    MollerTrumbore,
}

/// How ray-sphere intersections are solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SphereFormula {
    #[default]
    Stable,
    Textbook,
}

/// Where secondary rays start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OffsetRule {
    #[default]
    Scaled,
    Fixed,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 320,
            height: 240,
            samples: 1,
            sampling: Sampling::Jittered,
            max_depth: 5,
            min_contribution: 1e-3,
            seed: 0,
            sphere_formula: SphereFormula::Stable,
            ray_offset: OffsetRule::Scaled,
            fixed_epsilon: 1e-4,
            triangle_test: TriangleTest::Watertight,
            terminator: TerminatorRule::Lifted,
            march_tolerance: March::default().tolerance,
            march_steps: March::default().max_steps,
            march_relaxation: March::default().relaxation,
            lipschitz: LipschitzRule::Bound,
            newton: March::default().newton,
            normals: NormalMethod::Analytic,
            normal_step: March::default().normal_step,
            without: SwitchedOff::default(),
            light_paths: 16,
        }
    }
}

/// Why [`RenderSettings::validate`] refuses settings: the value refused and
/// the limit it breaks, in the words of the scene file's `[render]` keys.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SettingsError {
    #[error("resolution {width}x{height}: width and height must be between 1 and {MAX_SIDE}")]
    Side { width: u32, height: u32 },
    #[error("resolution {width}x{height} has more than {MAX_PIXELS} pixels")]
    Pixels { width: u32, height: u32 },
    #[error("samples = {samples}: samples per pixel must be between 1 and {MAX_SAMPLES}")]
    Samples { samples: u32 },
    #[error(
        "{width}x{height} at {samples} samples per pixel is {total} samples: at most \
         {MAX_IMAGE_SAMPLES} per image; lower the resolution or the samples"
    )]
    ImageSamples {
        width: u32,
        height: u32,
        samples: u32,
        total: u64,
    },
    #[error(
        "light_paths = {light_paths}: light paths per pixel must be between 1 and {MAX_SAMPLES}"
    )]
    LightPaths { light_paths: u32 },
    #[error(
        "{width}x{height} at {light_paths} light paths per pixel is {total} paths: at most \
         {MAX_IMAGE_SAMPLES} per image; lower the resolution or the light paths"
    )]
    ImageLightPaths {
        width: u32,
        height: u32,
        light_paths: u32,
        total: u64,
    },
    #[error(
        "samples = {samples}: {sampling:?} sampling needs a square count (1, 4, 9, 16, ...); \
         use sampling = \"random\" for other counts"
    )]
    NotSquare { samples: u32, sampling: Sampling },
    #[error("max_depth = {max_depth}: at most {MAX_DEPTH}")]
    Depth { max_depth: u32 },
    #[error("min_contribution = {min_contribution}: must be a finite number >= 0")]
    MinContribution { min_contribution: f32 },
    #[error("fixed_epsilon = {fixed_epsilon}: must be a finite number >= 0")]
    FixedEpsilon { fixed_epsilon: f32 },
    #[error("march_tolerance = {0}: must be a number > 0 and at most 0.1")]
    MarchTolerance(f32),
    #[error("march_steps = {0}: must be between 1 and {MAX_MARCH_STEPS}")]
    MarchSteps(u32),
    #[error("march_relaxation = {0}: must be at least 1 and below 2")]
    MarchRelaxation(f32),
    #[error("normal_step = {0}: must be a number > 0 and at most 1")]
    NormalStep(f32),
}

impl RenderSettings {
    /// Checks the settings, whether they came from a file or the command line.
    pub fn validate(&self) -> Result<(), SettingsError> {
        let RenderSettings {
            width,
            height,
            samples,
            sampling,
            max_depth,
            min_contribution,
            seed: _,
            sphere_formula: _,
            ray_offset: _,
            triangle_test: _,
            terminator: _,
            fixed_epsilon,
            march_tolerance,
            march_steps,
            march_relaxation,
            lipschitz: _,
            newton: _,
            normals: _,
            normal_step,
            // Any set of effects may be left out.
            without: _,
            light_paths,
        } = *self;
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(SettingsError::Side { width, height });
        }
        if u64::from(width) * u64::from(height) > MAX_PIXELS {
            return Err(SettingsError::Pixels { width, height });
        }
        if samples == 0 || samples > MAX_SAMPLES {
            return Err(SettingsError::Samples { samples });
        }
        let total = u64::from(width) * u64::from(height) * u64::from(samples);
        if total > MAX_IMAGE_SAMPLES {
            return Err(SettingsError::ImageSamples {
                width,
                height,
                samples,
                total,
            });
        }
        if light_paths == 0 || light_paths > MAX_SAMPLES {
            return Err(SettingsError::LightPaths { light_paths });
        }
        let light_total = u64::from(width) * u64::from(height) * u64::from(light_paths);
        if light_total > MAX_IMAGE_SAMPLES {
            return Err(SettingsError::ImageLightPaths {
                width,
                height,
                light_paths,
                total: light_total,
            });
        }
        if sampling.needs_square_count() {
            let side = samples.isqrt();
            if side * side != samples {
                return Err(SettingsError::NotSquare { samples, sampling });
            }
        }
        if max_depth > MAX_DEPTH {
            return Err(SettingsError::Depth { max_depth });
        }
        if !(min_contribution >= 0.0 && min_contribution.is_finite()) {
            return Err(SettingsError::MinContribution { min_contribution });
        }
        if !(fixed_epsilon >= 0.0 && fixed_epsilon.is_finite()) {
            return Err(SettingsError::FixedEpsilon { fixed_epsilon });
        }
        if !(march_tolerance > 0.0 && march_tolerance <= 0.1) {
            return Err(SettingsError::MarchTolerance(march_tolerance));
        }
        if !(1..=MAX_MARCH_STEPS).contains(&march_steps) {
            return Err(SettingsError::MarchSteps(march_steps));
        }
        if !(1.0..2.0).contains(&march_relaxation) {
            return Err(SettingsError::MarchRelaxation(march_relaxation));
        }
        if !(normal_step > 0.0 && normal_step <= 1.0) {
            return Err(SettingsError::NormalStep(normal_step));
        }
        Ok(())
    }

    /// How chapter 12 marches implicit surfaces under these settings.
    pub fn march(&self) -> March {
        March {
            tolerance: self.march_tolerance,
            max_steps: self.march_steps,
            relaxation: self.march_relaxation,
            lipschitz: self.lipschitz,
            newton: self.newton,
            normal: self.normals,
            normal_step: self.normal_step,
        }
    }

    /// The secondary-ray offset these settings ask for.
    pub fn offset(&self) -> RayOffset {
        match self.ray_offset {
            OffsetRule::Scaled => RayOffset::Scaled,
            OffsetRule::Fixed => RayOffset::Fixed(self.fixed_epsilon),
        }
    }
}

/// Where inside a pixel the samples go.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Sampling {
    /// A regular `k x k` grid of cell centres (supersampling).
    Grid,
    /// One random point in each cell of a `k x k` grid (stratified).
    #[default]
    Jittered,
    /// Independent random points anywhere in the pixel.
    Random,
}

impl Sampling {
    /// Grid and jittered sampling split the pixel into `k x k` cells, so they
    /// need a square sample count.
    pub fn needs_square_count(self) -> bool {
        matches!(self, Sampling::Grid | Sampling::Jittered)
    }
}

/// How secondary rays leave a surface.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum RayOffset {
    /// Chapter 4's `Chapters::offset_origin`: a push scaled to the point's
    /// rounding error.
    #[default]
    Scaled,
    /// The textbook fix: start `epsilon` along the new ray, whatever the
    /// scene's size (the same as ignoring hits with `t < epsilon`). Too small
    /// and far surfaces shadow themselves (acne); too large and shadows
    /// detach from the objects that cast them. Kept for comparison.
    Fixed(f32),
}
