//! The most rays a render may cast, checked before the first is cast.
//!
//! Every limit of [`crate::limits`] is sensible alone, but a ray tree grows
//! with the depth: each point of glass sends a reflected and a refracted
//! ray on, so with `min_contribution = 0` a single camera ray can become
//! `2^max_depth` rays (a glass box around a diamond ball at depth 64: some
//! 10^9 rays for a 1x1 image, where walls that reflect totally keep most
//! rays in). Waiting to count them while rendering would leave a render
//! or a page request running for hours first; cutting the tree where a
//! count runs out would give an image that depends on the cut. So a stage
//! works out the most rays its settings allow ([`RayEstimate`], a bound,
//! not a guess) and refuses, with that estimate, settings whose bound is
//! above a budget: [`PIXEL_RAY_BUDGET`] for one pixel (what `trace` and
//! the page's ray tree cost), [`IMAGE_RAY_BUDGET`] for a whole render.
//!
//! The bound holds for raylab's chapters: a point sends at most two rays
//! on (glass), each ray's weight in the pixel is its parent's times the
//! share of the light it carries, and the shares of one point add up to at
//! most 1 (a material's `reflectivity + transparency` is at most 1, and
//! Fresnel's `R` and `1 - R` split the transparent part). A ray below
//! `min_contribution` is not cast, so no bounce level can hold more than
//! `1 / min_contribution` of them. A student's chapters that ignore the
//! shares are bounded by `max_depth` alone (and by the check's time limit).

use super::Stage;
use crate::course::Chapters;

/// The most rays one pixel may cast, at worst: 2^28 (about 2.7e8, a minute
/// or so on one core). A 4096-sample pixel of chapter 13's paths casts
/// 4e5; chapter 9's glass at depth 16 with no contribution cut at `raylab
/// cost`'s 256 samples, 1e8.
pub const PIXEL_RAY_BUDGET: f64 = (1u64 << 28) as f64;

/// The most rays one render may cast, at worst: 2^41 (about 2.2e12, a day
/// or two on two cores). The largest image the sample limit allows
/// (2^30 samples) at chapter 13's 102 rays a sample is 1.1e11; `raylab
/// cost`'s reference for chapter 8 (depth 16, no contribution cut, 256
/// samples, 160x120) is 1.9e12.
pub const IMAGE_RAY_BUDGET: f64 = (1u64 << 41) as f64;

/// The most rays a stage's settings allow, worked out before any is cast.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayEstimate {
    /// Camera samples per pixel.
    pub samples: u32,
    /// Rays a point can send on: 2 through glass, 1 off a mirror or along
    /// a path, 0 where nothing reflects.
    pub branching: u32,
    pub max_depth: u32,
    pub min_contribution: f32,
    /// Shadow rays cast from each point the tree meets.
    pub shadow_rays: u32,
    /// The most rays one camera sample casts.
    pub per_sample: f64,
    /// The most rays one pixel casts: `samples` of `per_sample`.
    pub per_pixel: f64,
    /// The most rays chapter 14's light paths cast, all of them (they are
    /// traced for the whole image, whatever part of it is rendered).
    pub light_paths: f64,
    /// The most rays of the whole image, its light paths included.
    pub image: f64,
}

/// Settings whose rays could go beyond a budget.
#[derive(Debug, Clone, PartialEq)]
pub enum BudgetError {
    /// One pixel's rays.
    Pixel(RayEstimate),
    /// The whole image's rays.
    Image {
        estimate: RayEstimate,
        width: u32,
        height: u32,
    },
    /// Chapter 14's light paths, all traced for any pixel.
    LightPaths(RayEstimate),
}

impl std::fmt::Display for BudgetError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BudgetError::Pixel(estimate) => write!(
                f,
                "up to {:.1e} rays for one pixel, more than the {PIXEL_RAY_BUDGET:.1e} raylab \
                 casts for one: {} of up to {:.1e} rays each ({}); {}",
                estimate.per_pixel,
                crate::text::count(u64::from(estimate.samples), "sample"),
                estimate.per_sample,
                estimate.why(),
                estimate.remedy()
            ),
            BudgetError::Image {
                estimate,
                width,
                height,
            } => {
                write!(
                    f,
                    "up to {:.1e} rays for the {width}x{height} image, more than the \
                     {IMAGE_RAY_BUDGET:.1e} raylab casts for one render: {:.1e} a pixel ({})",
                    estimate.image,
                    estimate.per_pixel,
                    estimate.why()
                )?;
                if estimate.light_paths > 0.0 {
                    write!(f, ", and {:.1e} for the light paths", estimate.light_paths)?;
                }
                write!(f, "; {}, or lower the resolution", estimate.remedy())
            }
            BudgetError::LightPaths(estimate) => write!(
                f,
                "up to {:.1e} rays for the light paths, more than the {IMAGE_RAY_BUDGET:.1e} \
                 raylab casts for one render (chapter 14 traces all of them for any part of the \
                 image): lower light_paths, max_depth or the resolution",
                estimate.light_paths
            ),
        }
    }
}

impl std::error::Error for BudgetError {}

impl RayEstimate {
    /// Why one sample's tree is as large as it is, in the settings' words.
    fn why(&self) -> String {
        let sends = match self.branching {
            0 => "no point sends a ray on".to_string(),
            1 => "each point sends one ray on".to_string(),
            n => format!("each point of glass sends {n} rays on"),
        };
        format!(
            "{sends}, up to max_depth = {} bounces with min_contribution = {}, and {} from each \
             point",
            self.max_depth,
            self.min_contribution,
            crate::text::count(u64::from(self.shadow_rays), "shadow ray")
        )
    }

    /// What lowers the estimate.
    fn remedy(&self) -> &'static str {
        if self.branching > 1 {
            "raise min_contribution (no bounce then holds more than 1 / min_contribution rays), \
             or lower max_depth or the samples"
        } else {
            "lower max_depth or the samples"
        }
    }
}

impl<C: Chapters> Stage<'_, C> {
    /// The most rays this stage's settings allow (see the module's
    /// documentation for why it is a bound).
    pub fn ray_estimate(&self) -> RayEstimate {
        let settings = &self.settings;
        let effects = self.effects;
        let max_depth = settings.max_depth;
        let (branching, shadow_rays, per_sample) = if effects.path_tracing {
            // One ray a bounce, and one shadow ray toward a light at each.
            let shadow = u32::from(effects.next_event);
            let rays = f64::from(max_depth + 1) * f64::from(1 + shadow);
            (1, shadow, rays)
        } else {
            let branching = if effects.refraction {
                2
            } else {
                u32::from(effects.reflection)
            };
            let shadow = if effects.shadows {
                u32::try_from(self.scene.lights.len()).unwrap_or(u32::MAX)
            } else {
                0
            };
            let tree = tree_size(max_depth, branching, settings.min_contribution);
            (branching, shadow, tree * (1.0 + f64::from(shadow)))
        };
        let samples = self.samples();
        let per_pixel = f64::from(samples) * per_sample;
        // A light path is a ray a bounce, each point it lights joined to
        // the camera by one more.
        let light_paths = self.light_path_count() as f64 * f64::from(max_depth + 1) * 2.0;
        let pixels = f64::from(settings.width) * f64::from(settings.height);
        RayEstimate {
            samples,
            branching,
            max_depth,
            min_contribution: settings.min_contribution,
            shadow_rays,
            per_sample,
            per_pixel,
            light_paths,
            image: pixels * per_pixel + light_paths,
        }
    }

    /// Refuses a stage whose one pixel, or whose light paths (traced
    /// whole for any pixel), could cast more than the budgets allow.
    pub(super) fn check_pixel_budget(&self) -> Result<(), BudgetError> {
        let estimate = self.ray_estimate();
        if estimate.per_pixel > PIXEL_RAY_BUDGET {
            return Err(BudgetError::Pixel(estimate));
        }
        if estimate.light_paths > IMAGE_RAY_BUDGET {
            return Err(BudgetError::LightPaths(estimate));
        }
        Ok(())
    }

    /// Refuses a render of the whole image that could cast more than
    /// [`IMAGE_RAY_BUDGET`] rays.
    pub fn check_image_budget(&self) -> Result<(), BudgetError> {
        let estimate = self.ray_estimate();
        if estimate.image > IMAGE_RAY_BUDGET {
            return Err(BudgetError::Image {
                estimate,
                width: self.settings.width,
                height: self.settings.height,
            });
        }
        Ok(())
    }
}

/// The most rays in the tree of one camera ray: one level a bounce, each
/// level at most `branching` times the one before, and never more than
/// `1 / min_contribution` rays (their weights add up to at most 1, and
/// each is at least `min_contribution`).
fn tree_size(max_depth: u32, branching: u32, min_contribution: f32) -> f64 {
    let cap = if min_contribution > 0.0 {
        1.0 / f64::from(min_contribution)
    } else {
        f64::INFINITY
    };
    let mut level = 1.0_f64;
    let mut total = 1.0;
    for _ in 0..max_depth {
        level = (level * f64::from(branching)).min(cap);
        total += level;
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tree_doubles_a_level_until_the_contribution_cut_holds_it() {
        assert_eq!(tree_size(0, 2, 0.0), 1.0);
        assert_eq!(tree_size(3, 2, 0.0), 15.0);
        assert_eq!(tree_size(64, 2, 0.0), 2f64.powi(65) - 1.0);
        // 2, 4, then 8 a level (1 / 0.125).
        assert_eq!(tree_size(5, 2, 0.125), 1.0 + 2.0 + 4.0 + 8.0 + 8.0 + 8.0);
        assert_eq!(tree_size(50, 1, 0.0), 51.0);
        assert_eq!(tree_size(50, 0, 0.0), 1.0);
    }

    #[test]
    fn every_built_in_scene_is_within_both_budgets() {
        for info in crate::chapters::CHAPTERS {
            let scene = crate::builtin::scene(info.number).expect("a built-in scene");
            let stage = Stage::new(&scene, info.number, scene.render).expect("within budget");
            assert!(
                stage.check_image_budget().is_ok(),
                "chapter {}",
                info.number
            );
        }
    }
}
