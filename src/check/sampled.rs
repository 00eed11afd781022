//! The image check of a sampled stage: any correct sampler passes.
//!
//! From chapter 7 on, a pixel is the mean of a few samples at positions the
//! student's `sample_offset` chooses: a random-number hash, an order of the
//! cells and a seed of the student's own. Two correct samplers give two
//! different realisations of the same noise, so the shipped image (one
//! realisation, raylab's) cannot be matched pixel for pixel. What every
//! correct sampler shares is the mean each pixel converges to, and how far
//! one pixel may stray from it: the spread of a single sample over the
//! pixel, divided by the square root of the count.
//!
//! So the reference here is raylab's own stage at [`REFERENCE_SAMPLES`]
//! stratified samples per pixel: per pixel and channel, the mean `mu` and
//! the standard deviation `sigma` of one sample. A student's pixel `x` of
//! `n` samples is within the noise when it is within 2 sRGB levels of
//! `mu`, or within `SIGMAS * sigma * (1/sqrt(n) + 1/sqrt(m))` (the second
//! term for the reference's own error). Independent samples stray beyond 4
//! sigma in well under one pixel in a thousand (Chebyshev bounds it by 1/16
//! for any distribution; a pixel's mean of bounded samples is far tighter),
//! and stratified samples stray less. A few such pixels are allowed
//! ([`allowed_outliers`]); a bug that changes a region changes pixels whose
//! `sigma` is 0 (every sample of them sees the same surface), where only
//! the 2 levels are allowed.
//!
//! A sampler that is wrong only in how it spreads its samples (one offset
//! reused for every cell) can stay within this noise: chapter 7's
//! checkpoints on the distribution of the offsets catch it.

use std::sync::{Arc, Mutex};

use glam::Vec3;

use super::protocol::View;
use crate::chapters::ChapterInfo;
use crate::output::linear_to_srgb8;
use crate::{Chapters, Reference, RenderSettings, Sampling, Scene, Stage};

/// Samples per pixel of the converged reference.
pub const REFERENCE_SAMPLES: u32 = 64;

/// Samples per pixel of the converged reference of a path-traced stage: a
/// path's light varies far more from one sample to the next, and the
/// reference's own noise must stay well below the student's.
pub const PATH_REFERENCE_SAMPLES: u32 = 256;

/// How many standard deviations of the mean a pixel may stray.
pub const SIGMAS: f32 = 4.0;

/// The seed of the reference's own samples: not the scene's, so that it is
/// no realisation the student's could share by accident.
const REFERENCE_SEED: u64 = 0x5_EED0_F0C0_u64;

/// Per pixel: the converged mean and one sample's standard deviation, in
/// linear light, row by row.
#[derive(Debug)]
pub struct Converged {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel it was measured with.
    pub samples: u32,
    pub mean: Vec<Vec3>,
    pub sigma: Vec<Vec3>,
    /// Chapter 14: the standard deviation of one light image at the
    /// settings' light paths per pixel (zero where the stage traces none),
    /// and how many such images the mean's share of it was averaged over.
    pub light_sigma: Vec<Vec3>,
    pub light_images: u32,
}

/// Chapter 14: light images averaged into the converged reference, each
/// with its own seed, whose spread is the noise of a student's one.
pub const LIGHT_REFERENCE_IMAGES: u32 = 16;

/// Whether the stage of `settings` averages samples placed by chapter 7's
/// `sample_offset` with randomness in them.
pub fn is_sampled<C: Chapters>(stage: &Stage<C>, settings: &RenderSettings) -> bool {
    (stage.samples() > 1 && settings.sampling != Sampling::Grid) || stage.effects.path_tracing
}

/// The side of the blocks a path-traced image is judged by (chapter 13).
///
/// A path's light has a long tail: most samples of a pixel under the glass
/// ball miss its caustic, and a few find it and are a hundred times
/// brighter. The mean of one pixel's 64 samples is then far from normal,
/// and a correct image strays beyond 4 sigma in a few per cent of its
/// pixels (2.4% in a trial of raylab's own code against itself). The mean
/// of a block of 4 x 4 pixels, 1,024 samples, is close to normal, and a
/// biased estimate (emission counted twice, a pdf without its cosine)
/// shifts whole regions, so whole blocks.
pub const PATH_BLOCK: u32 = 4;

/// The brightest a sample may be when a path-traced image is judged: 1,
/// the white of the screen. Both the student's image and the converged
/// one are cut alike, so a correct estimator matches; a firefly (a
/// caustic of the glass ball found by a matte bounce, a thousand times
/// brighter than its pixel) then weighs no more than a white sample.
pub const PATH_SAMPLE_BOUND: f32 = 1.0;

/// A tracer for judging `stage`: samples cut to [`PATH_SAMPLE_BOUND`]
/// when it traces paths.
pub fn judging_tracer<'s, C: Chapters>(stage: &'s Stage<'s, C>) -> crate::render::Tracer<'s, C> {
    let tracer = stage.tracer(None);
    if stage.effects.path_tracing {
        tracer.with_sample_bound(PATH_SAMPLE_BOUND)
    } else {
        tracer
    }
}

impl Converged {
    /// The means of blocks of `side` x `side` pixels, and the standard
    /// deviation of one sample of such a block (a sample of each pixel,
    /// averaged): `sqrt(sum sigma^2) / side^2`, the pixels being
    /// independent (and the same for the light images). Pixels past the
    /// last whole block are left out.
    pub fn blocks(&self, side: u32) -> Converged {
        let (width, height) = (self.width / side, self.height / side);
        let blocks = (width * height) as usize;
        let (mut mean, mut sigma, mut light_sigma) = (
            Vec::with_capacity(blocks),
            Vec::with_capacity(blocks),
            Vec::with_capacity(blocks),
        );
        for by in 0..height {
            for bx in 0..width {
                let (mut sum, mut variance, mut light_variance) =
                    (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
                for y in by * side..(by + 1) * side {
                    for x in bx * side..(bx + 1) * side {
                        let index = (y * self.width + x) as usize;
                        sum += self.mean[index];
                        variance += self.sigma[index] * self.sigma[index];
                        light_variance += self.light_sigma[index] * self.light_sigma[index];
                    }
                }
                let count = (side * side) as f32;
                mean.push(sum / count);
                sigma.push(variance.map(f32::sqrt) / count);
                light_sigma.push(light_variance.map(f32::sqrt) / count);
            }
        }
        Converged {
            width,
            height,
            samples: self.samples,
            mean,
            sigma,
            light_sigma,
            light_images: self.light_images,
        }
    }
}

/// `image` (`width` pixels a row) as the means of blocks of `side` x
/// `side` pixels, as [`Converged::blocks`] cuts them.
pub fn block_means(image: &[Vec3], width: u32, side: u32) -> Vec<Vec3> {
    let height = image.len() as u32 / width.max(1);
    let mut means = Vec::new();
    for by in 0..height / side {
        for bx in 0..width / side {
            let mut sum = Vec3::ZERO;
            for y in by * side..(by + 1) * side {
                for x in bx * side..(bx + 1) * side {
                    sum += image[(y * width + x) as usize];
                }
            }
            means.push(sum / (side * side) as f32);
        }
    }
    means
}

/// The converged reference of chapter `info`'s stage of `scene` (its
/// built-in scene seen from `view`) at `settings`' size, computed once per
/// process, chapter and view: a class graded in one run shares it.
pub fn converged(
    info: &ChapterInfo,
    view: Option<&View>,
    scene: &Scene,
    settings: RenderSettings,
) -> Result<Arc<Converged>, String> {
    type Key = (u8, Option<View>);
    static CACHE: Mutex<Vec<(Key, Arc<Converged>)>> = Mutex::new(Vec::new());
    let key = (info.number, view.copied());
    if let Some((_, found)) = CACHE
        .lock()
        .ok()
        .and_then(|cache| cache.iter().find(|(k, _)| *k == key).cloned())
    {
        return Ok(found);
    }
    // raylab's own stage: its tree is built by raylab's chapter 11, which
    // must not count as the student's use of an answer.
    let stage = crate::answer_key::raylab_own(|| {
        Stage::<Reference>::with_chapters(scene, info.number, settings)
    })
    .map_err(|error| error.to_string())?;
    let samples = if stage.effects.path_tracing {
        PATH_REFERENCE_SAMPLES
    } else {
        REFERENCE_SAMPLES
    };
    let mut converged =
        crate::answer_key::raylab_own(|| measure(&stage, settings.width, settings.height, samples));
    if stage.effects.light_tracing {
        crate::answer_key::raylab_own(|| add_light_images(&mut converged, scene, info, settings))?;
    }
    let converged = Arc::new(converged);
    if let Ok(mut cache) = CACHE.lock() {
        cache.push((key, Arc::clone(&converged)));
    }
    Ok(converged)
}

/// Per pixel, the mean and one sample's spread over `samples` jittered
/// samples, row by row on rayon's threads (each pixel depends only on its
/// position, so the answer is the same on any number of them).
fn measure(stage: &Stage<Reference>, width: u32, height: u32, samples: u32) -> Converged {
    use rayon::prelude::*;
    let count = f64::from(samples);
    let rows: Vec<Vec<(Vec3, Vec3)>> = (0..height)
        .into_par_iter()
        .map(|y| {
            crate::answer_key::raylab_own(|| {
                let mut tracer = judging_tracer(stage);
                (0..width)
                    .map(|x| {
                        let mut sum = glam::DVec3::ZERO;
                        let mut squares = glam::DVec3::ZERO;
                        for index in 0..samples {
                            let (dx, dy) = Reference::sample_offset(
                                Sampling::Jittered,
                                samples,
                                index,
                                (x, y),
                                REFERENCE_SEED,
                            );
                            let sample = tracer.sample(x as f32 + dx, y as f32 + dy).as_dvec3();
                            sum += sample;
                            squares += sample * sample;
                        }
                        let average = sum / count;
                        let variance = (squares / count - average * average).max(glam::DVec3::ZERO)
                            * (count / (count - 1.0));
                        (average.as_vec3(), variance.map(f64::sqrt).as_vec3())
                    })
                    .collect()
            })
        })
        .collect();
    let (mean, sigma): (Vec<Vec3>, Vec<Vec3>) = rows.into_iter().flatten().unzip();
    Converged {
        width,
        height,
        samples,
        light_sigma: vec![Vec3::ZERO; mean.len()],
        light_images: 1,
        mean,
        sigma,
    }
}

/// Chapter 14: adds to `converged` the mean of [`LIGHT_REFERENCE_IMAGES`]
/// light images of raylab's own stage, each with its own seed, and their
/// spread: a student's light image is one more such image.
fn add_light_images(
    converged: &mut Converged,
    scene: &Scene,
    info: &ChapterInfo,
    settings: RenderSettings,
) -> Result<(), String> {
    let count = LIGHT_REFERENCE_IMAGES;
    let pixels = converged.mean.len();
    let (mut sum, mut squares) = (
        vec![glam::DVec3::ZERO; pixels],
        vec![glam::DVec3::ZERO; pixels],
    );
    for image in 0..count {
        let settings = RenderSettings {
            seed: REFERENCE_SEED + u64::from(image),
            ..settings
        };
        let stage = Stage::<Reference>::with_chapters(scene, info.number, settings)
            .map_err(|error| error.to_string())?;
        let Some(light) = stage.light_image() else {
            return Ok(());
        };
        for ((sum, squares), pixel) in sum.iter_mut().zip(&mut squares).zip(&light.pixels) {
            let pixel = pixel.as_dvec3();
            *sum += pixel;
            *squares += pixel * pixel;
        }
    }
    let n = f64::from(count);
    for (index, (sum, squares)) in sum.iter().zip(&squares).enumerate() {
        let average = *sum / n;
        let variance = (*squares / n - average * average).max(glam::DVec3::ZERO) * (n / (n - 1.0));
        converged.mean[index] += average.as_vec3();
        converged.light_sigma[index] = variance.map(f64::sqrt).as_vec3();
    }
    converged.light_images = count;
    Ok(())
}

/// How a student's sampled image compares with the converged reference.
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseCheck {
    /// The side of the blocks judged: 1 (each pixel), or [`PATH_BLOCK`].
    pub block: u32,
    /// Pixels (blocks) beyond both 2 levels and [`SIGMAS`] of the noise.
    pub outside: usize,
    pub allowed: usize,
    pub pixels: usize,
    /// The first such pixel.
    pub first: Option<(u32, u32)>,
}

impl NoiseCheck {
    pub fn passes(&self) -> bool {
        self.outside <= self.allowed
    }
}

/// Outliers allowed among `pixels`: one in 400 (48 of the reference
/// size's 19,200), with room for every correct sampler of raylab's tests
/// (`two_dozen_correct_samplers_pass_the_sampled_chapters`: other hashes,
/// cells column by column); a bug of the shading changes whole regions.
pub fn allowed_outliers(pixels: usize) -> usize {
    (pixels / 400).max(2)
}

/// Blocks allowed beyond the noise among `blocks` of a path-traced image.
///
/// Clamping a sample at white bounds it, but a caustic that a matte
/// bounce finds one time in a thousand is still a long tail for a block of
/// 1,024 samples, so chapter 13's correct estimators stray more often than
/// the normal law says: raylab's own and ten other correct cosine samplers
/// (Malley's with `1 - u`, `u` and `v` swapped, eight Cranley-Patterson
/// rotations of raylab's) put 2 to 5 of its 1,200 blocks beyond 4 sigma,
/// so one block in 100 (12) is allowed; averaging after tone mapping puts
/// 354. Where light paths carry the caustics (`caustics_by_light_paths`,
/// chapter 14), camera paths leave them out, and the tail goes with them:
/// raylab's own and six rotations put 0 blocks beyond, so 3 are allowed,
/// and a forgotten wavelength tint (14 blocks) fails. Chapter 13's and
/// 14's galleries keep these figures.
pub fn allowed_block_outliers(blocks: usize, caustics_by_light_paths: bool) -> usize {
    if caustics_by_light_paths {
        3
    } else {
        (blocks / 100).max(3)
    }
}

/// Compares the student's linear pixels `image` (row by row, `samples`
/// each) with `converged`.
pub fn judge(image: &[Vec3], samples: u32, converged: &Converged) -> NoiseCheck {
    let scale = 1.0 / (samples as f32).sqrt() + 1.0 / (converged.samples as f32).sqrt();
    // The student's light image is one more of the reference's, whose mean
    // holds `light_images` of them.
    let light_scale = 1.0 + 1.0 / (converged.light_images as f32).sqrt();
    let mut outside = 0;
    let mut first = None;
    for (index, (((got, mean), sigma), light_sigma)) in image
        .iter()
        .zip(&converged.mean)
        .zip(&converged.sigma)
        .zip(&converged.light_sigma)
        .enumerate()
    {
        let levels = got
            .to_array()
            .iter()
            .zip(mean.to_array())
            .map(|(g, m)| linear_to_srgb8(*g).abs_diff(linear_to_srgb8(m)))
            .max()
            .unwrap_or(0);
        let within_noise = ((*got - *mean).abs())
            .cmple(SIGMAS * (*sigma * scale + *light_sigma * light_scale))
            .all();
        if !(levels <= 2 || within_noise) || !got.is_finite() {
            outside += 1;
            if first.is_none() {
                let width = converged.width as usize;
                first = Some(((index % width) as u32, (index / width) as u32));
            }
        }
    }
    NoiseCheck {
        block: 1,
        outside,
        allowed: allowed_outliers(image.len()),
        pixels: image.len(),
        first,
    }
}
