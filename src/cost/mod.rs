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

mod jobs;
pub mod neighbours;
mod plot;
mod reference;
mod sweep;
mod table;

pub use jobs::{
    DEPTHS, EPSILONS, FRESNEL_MODELS, MARCH_STEPS, MARCH_TOLERANCES, NORMAL_STEPS,
    PATH_SAMPLE_COUNTS, PATH_SWITCHES, RELAXATIONS, SAMPLE_COUNTS,
};
pub use reference::{
    FAR_SPHERE_SCENE, GLASS_REFERENCE_MIN_CONTRIBUTION, PATH_REFERENCE_SAMPLES, REFERENCE_DEPTH,
    REFERENCE_MARCH_STEPS, REFERENCE_MARCH_TOLERANCE, REFERENCE_SAMPLES, far_sphere_scene,
    reference_settings, with_fresnel,
};
pub use sweep::{render_count, run};

use crate::{RenderSettings, Scene};

/// A quality knob the sweep can turn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Knob {
    /// Samples per pixel, 1 to 64, for grid, jittered and random sampling (chapter 7).
    Samples,
    /// Not a sweep: the anti-aliasing of the report raylab grew from (each
    /// pixel averaged with its four neighbours) against supersampling, on
    /// the chapter's scene and a checker of one-pixel squares (chapter 7;
    /// see [`neighbours`]).
    Neighbours,
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
    pub const ALL: [Knob; 12] = [
        Knob::Samples,
        Knob::Neighbours,
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
            Knob::Samples | Knob::Neighbours => 7,
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
            Knob::Neighbours => "neighbours",
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

/// How far an image is from the reference: in 8-bit sRGB codes, and in
/// linear light where both renders kept their radiance.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ImageError {
    pub rmse: f64,
    /// `f64::INFINITY` for identical images.
    pub psnr_db: f64,
    /// Share (0 to 1) of pixels with a channel more than 1 code off.
    pub share_off: f64,
    /// The relative MSE of the linear radiance, as `raylab diff` measures
    /// two OpenEXR images ([`crate::diff::linear`]): the noise a clamp and
    /// 8-bit rounding hide above white and exaggerate in the dark. `None`
    /// when either render kept no radiance.
    pub relative_mse: Option<f64>,
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
            relative_mse: None,
        })
    }

    /// [`ImageError::between`] two renders' codes, and the relative MSE of
    /// their linear radiance when both kept it (the same length, or it is
    /// a size error like the codes').
    pub fn between_renders(
        image: &crate::Rendered,
        reference: &crate::Rendered,
    ) -> Result<ImageError, CostError> {
        let mut error = ImageError::between(&image.rgb, &reference.rgb)?;
        if image.linear.is_empty() || reference.linear.is_empty() {
            return Ok(error);
        }
        if image.linear.len() != reference.linear.len() {
            return Err(CostError::SizeMismatch {
                image: image.linear.len(),
                reference: reference.linear.len(),
            });
        }
        let compared = crate::diff::linear::compare_linear_values(
            &image.linear,
            &reference.linear,
            image.width,
            crate::diff::LinearCriteria::default(),
        );
        error.relative_mse = Some(compared.metrics.relative_mse);
        Ok(error)
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

#[cfg(test)]
mod tests {
    use super::*;

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

    /// A render of `value` everywhere in linear light, 2x1 pixels.
    fn flat_render(value: f32) -> crate::Rendered {
        let linear = vec![value; 6];
        crate::Rendered {
            width: 2,
            height: 1,
            rgb: linear
                .iter()
                .map(|&v| crate::output::linear_to_srgb8(v))
                .collect(),
            linear,
            effects: crate::effects::Effects::for_chapter(1),
            rays: crate::RayCounts::default(),
            seconds: 0.0,
        }
    }

    #[test]
    fn the_linear_error_sees_what_the_screen_clamps() {
        // 2 and 4 are both white on a screen: no error in sRGB codes.
        let error =
            ImageError::between_renders(&flat_render(2.0), &flat_render(4.0)).expect("same size");
        assert_eq!(error.rmse, 0.0);
        let relative_mse = error.relative_mse.expect("both kept their radiance");
        assert!((relative_mse - 4.0 / 16.01).abs() < 1e-12, "{relative_mse}");
        let mut without = flat_render(2.0);
        without.linear.clear();
        let error = ImageError::between_renders(&without, &flat_render(4.0)).expect("same size");
        assert_eq!(error.relative_mse, None);
    }

    #[test]
    fn images_of_different_sizes_are_an_error_not_a_panic() {
        let message = ImageError::between(&[0; 6], &[0; 9])
            .unwrap_err()
            .to_string();
        assert!(message.contains("6 bytes"), "{message}");
        assert!(message.contains("same size"), "{message}");
    }

    #[test]
    fn chapters_have_the_knobs_they_teach() {
        assert!(Knob::of_chapter(1).is_empty());
        assert_eq!(Knob::of_chapter(2), vec![Knob::SphereFormula]);
        assert_eq!(
            Knob::of_chapter(6),
            vec![Knob::Depth, Knob::Offset, Knob::SphereFormula]
        );
        assert_eq!(Knob::of_chapter(8), Knob::ALL[..5].to_vec());
        assert_eq!(Knob::of_chapter(9), Knob::ALL[..6].to_vec());
        assert_eq!(Knob::of_chapter(10), Knob::ALL[..7].to_vec());
        assert_eq!(Knob::of_chapter(11), Knob::ALL[..8].to_vec());
        assert_eq!(Knob::of_chapter(12), Knob::ALL[..10].to_vec());
        assert_eq!(Knob::of_chapter(13), Knob::ALL[..11].to_vec());
        assert_eq!(Knob::of_chapter(14), Knob::ALL.to_vec());
    }
}
