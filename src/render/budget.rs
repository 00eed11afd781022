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
//! A ray that meets implicit surfaces (chapter 12) costs more than one
//! that meets spheres: it may evaluate each surface's tree up to
//! `march_steps` times, and a tree's evaluation costs one visit of each of
//! its nodes. So the budgets are of time, counted in plain rays: a ray
//! that may make `N` node visits counts as `1 + N /`
//! [`NODE_VISITS_PER_RAY`] rays ([`RayEstimate::ray_cost`]). Before a
//! stage has its tree of boxes (chapter 11), every ray tests every
//! primitive: past [`TESTS_IN_A_PLAIN_RAY`] of them, a ray counts as that
//! many more rays (a million triangles out of view made one pixel of a
//! thousand lights cost hours).
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

/// Visits of a node of an implicit surface's tree counted as one plain
/// ray. `cargo bench --bench ray_cost` measures the ratio, renders side by
/// side: a plain ray took as long as 11 to 18 visits in three runs here
/// (about 400 ns a ray, 28 ns a visit, beside another build). 8 is below
/// them, so that the budget errs on the side of refusing a long march.
pub const NODE_VISITS_PER_RAY: f64 = 8.0;

/// Ray-primitive tests that one plain ray's time covers. `cargo bench
/// --bench ray_cost` measures the ratio beside the one above: a plain ray
/// took as long as 32 to 50 sphere tests in the same runs (9 ns a test).
/// 16 is below them, so that the budget errs on the side of refusing.
pub const TESTS_IN_A_PLAIN_RAY: f64 = 16.0;

/// The evaluations one ray's meeting with one implicit surface makes
/// beside its march, at most: the bracket's 33, Newton's 17 values and
/// gradients, a normal's 7, rounded up.
const EVALUATIONS_BESIDE_THE_MARCH: f64 = 128.0;

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
    /// The implicit surfaces the stage marches.
    pub implicit_surfaces: usize,
    /// The most node visits one ray may make marching them all (each
    /// surface's nodes times its `march_steps` and the evaluations beside).
    pub march_visits: f64,
    /// The primitives each ray tests, where the stage has no tree of
    /// boxes (0 where it has one).
    pub tests_per_ray: f64,
    /// The time one ray may take, in plain rays:
    /// `max(1, tests_per_ray / TESTS_IN_A_PLAIN_RAY) + march_visits /
    /// NODE_VISITS_PER_RAY`.
    pub ray_cost: f64,
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
                "up to {:.1e} rays for one pixel{}, more than the {PIXEL_RAY_BUDGET:.1e} raylab \
                 casts for one: {} of up to {:.1e} rays each ({}{}); {}",
                estimate.per_pixel * estimate.ray_cost,
                estimate.counted_as(),
                crate::text::count(u64::from(estimate.samples), "sample"),
                estimate.per_sample,
                estimate.why(),
                estimate.ray_work(),
                estimate.remedy()
            ),
            BudgetError::Image {
                estimate,
                width,
                height,
            } => {
                write!(
                    f,
                    "up to {:.1e} rays for the {width}x{height} image{}, more than the \
                     {IMAGE_RAY_BUDGET:.1e} raylab casts for one render: {:.1e} a pixel ({}{})",
                    estimate.image * estimate.ray_cost,
                    estimate.counted_as(),
                    estimate.per_pixel,
                    estimate.why(),
                    estimate.ray_work()
                )?;
                if estimate.light_paths > 0.0 {
                    write!(f, ", and {:.1e} for the light paths", estimate.light_paths)?;
                }
                write!(f, "; {}, or lower the resolution", estimate.remedy())
            }
            BudgetError::LightPaths(estimate) => write!(
                f,
                "up to {:.1e} rays for the light paths{}, more than the {IMAGE_RAY_BUDGET:.1e} \
                 raylab casts for one render (the light paths are all traced for any part of \
                 the image{}): lower light_paths, max_depth or the resolution",
                estimate.light_paths * estimate.ray_cost,
                estimate.counted_as(),
                estimate.ray_work()
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

    /// How the rays are counted, where marching makes one cost more.
    fn counted_as(&self) -> String {
        if self.ray_cost > 1.0 {
            " (counted in the time of plain rays)".to_string()
        } else {
            String::new()
        }
    }

    /// What testing every primitive and marching add to each ray, where
    /// they add anything.
    fn ray_work(&self) -> String {
        let mut text = String::new();
        if self.tests_per_ray > TESTS_IN_A_PLAIN_RAY {
            text += &format!(
                "; and with no tree of boxes each ray tests all {:.0} primitives",
                self.tests_per_ray
            );
        }
        if self.implicit_surfaces > 0 {
            text += &format!(
                "; and each ray may march {}, up to {:.1e} visits of their trees' nodes",
                crate::text::count(self.implicit_surfaces as u64, "implicit surface"),
                self.march_visits
            );
        }
        if !text.is_empty() {
            text += &format!(": each ray as long as {:.1e} plain rays", self.ray_cost);
        }
        text
    }

    /// What lowers the estimate.
    fn remedy(&self) -> &'static str {
        if self.tests_per_ray > TESTS_IN_A_PLAIN_RAY && self.implicit_surfaces == 0 {
            return "use a chapter with a tree of boxes, fewer objects, or lower max_depth or \
                    the samples";
        }
        match (self.branching > 1, self.implicit_surfaces > 0) {
            (true, false) => {
                "raise min_contribution (no bounce then holds more than 1 / min_contribution \
                 rays), or lower max_depth or the samples"
            }
            (true, true) => {
                "raise min_contribution (no bounce then holds more than 1 / min_contribution \
                 rays), or lower march_steps, max_depth or the samples"
            }
            (false, true) => "lower march_steps, max_depth or the samples",
            (false, false) => "lower max_depth or the samples",
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
        let mut implicit_surfaces = 0;
        let mut march_visits = 0.0;
        for shape in &self.shapes {
            if let crate::shapes::Shape::Implicit(surface) = shape {
                implicit_surfaces += 1;
                let evaluations =
                    f64::from(surface.march().max_steps) + EVALUATIONS_BESIDE_THE_MARCH;
                march_visits += surface.nodes() as f64 * evaluations;
            }
        }
        let tests_per_ray = if self.bvh.is_some() {
            0.0
        } else {
            self.shapes.len() as f64
        };
        let testing = (tests_per_ray / TESTS_IN_A_PLAIN_RAY).max(1.0);
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
            implicit_surfaces,
            march_visits,
            tests_per_ray,
            ray_cost: testing + march_visits / NODE_VISITS_PER_RAY,
        }
    }

    /// Refuses a stage whose one pixel, or whose light paths (traced
    /// whole for any pixel), could cast more than the budgets allow.
    pub(super) fn check_pixel_budget(&self) -> Result<(), BudgetError> {
        let estimate = self.ray_estimate();
        if estimate.per_pixel * estimate.ray_cost > PIXEL_RAY_BUDGET {
            return Err(BudgetError::Pixel(estimate));
        }
        if estimate.light_paths * estimate.ray_cost > IMAGE_RAY_BUDGET {
            return Err(BudgetError::LightPaths(estimate));
        }
        Ok(())
    }

    /// Refuses a render of the whole image that could cast more than
    /// [`IMAGE_RAY_BUDGET`] rays.
    pub fn check_image_budget(&self) -> Result<(), BudgetError> {
        let estimate = self.ray_estimate();
        if estimate.image * estimate.ray_cost > IMAGE_RAY_BUDGET {
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

    /// Many rough implicit surfaces at the largest step budget: few rays,
    /// each marching for long. Counted in rays alone, a trace of 256
    /// samples passed the budget and ran for most of a minute.
    #[test]
    fn marching_counts_in_the_budget() {
        let mut text = String::from(
            "[camera]\nposition = [0.0, 0.0, -10.0]\nlook_at = [0.0, 0.0, 0.0]\n\
             [render]\nwidth = 160\nheight = 120\nsamples = 256\nmarch_steps = 100000\n",
        );
        for index in 0..250 {
            text += &format!(
                "[[objects]]\nimplicit = {{ displace = {{ amplitude = 0.01, frequency = 1e9, \
                 shape = {{ sphere = {{ center = [{}, 0.0, 0.0], radius = 0.2 }} }} }} }}\n",
                f64::from(index) * 0.01
            );
        }
        let scene = crate::Scene::parse(&text, "marching").expect("parses");
        // The first stage that marches: one ray a sample, as nothing in
        // the scene reflects or is lit.
        let chapter = (1..=crate::chapters::LAST_CHAPTER)
            .find(|&chapter| crate::effects::Effects::for_chapter(chapter).implicit)
            .expect("a chapter marches");
        let Err(error) = Stage::new(&scene, chapter, scene.render) else {
            panic!("256 samples of such marches are beyond the pixel budget");
        };
        let message = error.to_string();
        assert!(message.contains("250 implicit surfaces"), "{message}");
        assert!(message.contains("lower march_steps"), "{message}");
        // 36 samples: a pixel within the budget, the image beyond it.
        let fewer = crate::RenderSettings {
            samples: 36,
            ..scene.render
        };
        let stage = Stage::new(&scene, chapter, fewer).expect("one pixel is within the budget");
        let estimate = stage.ray_estimate();
        // Two nodes a tree, and the evaluations beside the march.
        assert_eq!(estimate.march_visits, 250.0 * 2.0 * (100_000.0 + 128.0));
        assert_eq!(
            estimate.ray_cost,
            1.0 + estimate.march_visits / NODE_VISITS_PER_RAY
        );
        let error = stage
            .check_image_budget()
            .expect_err("the image is too much");
        assert!(
            error
                .to_string()
                .contains("counted in the time of plain rays"),
            "{error}"
        );
        // Without marching a ray costs one ray.
        let plain = crate::builtin::scene(2).expect("a built-in scene");
        let stage = Stage::new(&plain, 2, plain.render).expect("within budget");
        assert_eq!(stage.ray_estimate().ray_cost, 1.0);
    }

    /// Before a stage has its tree of boxes every ray tests every
    /// primitive: thousands of them under a thousand lights made a single
    /// pixel of 4096 samples cost hours within a budget of rays alone.
    #[test]
    fn testing_every_primitive_counts_in_the_budget() {
        let mut text = String::from(
            "[camera]\nposition = [0.0, 0.0, -10.0]\nlook_at = [0.0, 0.0, 0.0]\n\
             [render]\nwidth = 1\nheight = 1\nsamples = 4096\n",
        );
        for index in 0..1024 {
            text += &format!("[[lights]]\nposition = [{}, 50.0, 0.0]\n", f64::from(index));
        }
        for index in 0..3200 {
            text += &format!(
                "[[objects]]\nsphere = {{ center = [{}, 100.0, 0.0], radius = 0.1 }}\n",
                f64::from(index)
            );
        }
        let scene = crate::Scene::parse(&text, "primitives").expect("parses");
        // A stage that samples and casts shadow rays, with no tree yet.
        let chapter = (1..=crate::chapters::LAST_CHAPTER)
            .find(|&chapter| {
                let effects = crate::effects::Effects::for_chapter(chapter);
                effects.antialiasing && effects.shadows && !effects.bvh
            })
            .expect("such a chapter");
        let Err(error) = Stage::new(&scene, chapter, scene.render) else {
            panic!("4096 samples of 1025 rays testing 3200 spheres are beyond the budget");
        };
        let message = error.to_string();
        assert!(message.contains("tests all 3200 primitives"), "{message}");
        assert!(message.contains("a tree of boxes"), "{message}");
        let one = crate::RenderSettings {
            samples: 1,
            ..scene.render
        };
        let stage = Stage::new(&scene, chapter, one).expect("one sample is within the budget");
        assert_eq!(stage.ray_estimate().ray_cost, 3200.0 / TESTS_IN_A_PLAIN_RAY);
        // With its tree, a stage counts a ray as one.
        let with_tree = (1..=crate::chapters::LAST_CHAPTER)
            .find(|&chapter| crate::effects::Effects::for_chapter(chapter).bvh)
            .expect("a chapter builds a tree");
        let stage = Stage::new(&scene, with_tree, one).expect("within the budget");
        assert_eq!(stage.ray_estimate().ray_cost, 1.0);
    }
}
