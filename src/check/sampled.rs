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

use crate::chapters::ChapterInfo;
use crate::output::linear_to_srgb8;
use crate::{Chapters, Reference, RenderSettings, Sampling, Scene, Stage};

/// Samples per pixel of the converged reference.
pub const REFERENCE_SAMPLES: u32 = 64;

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
    pub mean: Vec<Vec3>,
    pub sigma: Vec<Vec3>,
}

/// Whether the stage of `settings` averages samples placed by chapter 7's
/// `sample_offset` with randomness in them.
pub fn is_sampled<C: Chapters>(stage: &Stage<C>, settings: &RenderSettings) -> bool {
    stage.samples() > 1 && settings.sampling != Sampling::Grid
}

/// The converged reference of chapter `info`'s stage of `scene` at
/// `settings`' size, computed once per process and chapter.
pub fn converged(
    info: &ChapterInfo,
    scene: &Scene,
    settings: RenderSettings,
) -> Result<Arc<Converged>, String> {
    static CACHE: Mutex<Vec<(u8, Arc<Converged>)>> = Mutex::new(Vec::new());
    if let Some((_, found)) = CACHE
        .lock()
        .ok()
        .and_then(|cache| cache.iter().find(|(n, _)| *n == info.number).cloned())
    {
        return Ok(found);
    }
    let stage = Stage::<Reference>::with_chapters(scene, info.number, settings)
        .map_err(|error| error.to_string())?;
    let converged = Arc::new(crate::answer_key::raylab_own(|| {
        measure(&stage, settings.width, settings.height)
    }));
    if let Ok(mut cache) = CACHE.lock() {
        cache.push((info.number, Arc::clone(&converged)));
    }
    Ok(converged)
}

fn measure(stage: &Stage<Reference>, width: u32, height: u32) -> Converged {
    let mut tracer = stage.tracer(None);
    let pixels = (width * height) as usize;
    let mut mean = Vec::with_capacity(pixels);
    let mut sigma = Vec::with_capacity(pixels);
    let count = REFERENCE_SAMPLES as f32;
    for y in 0..height {
        for x in 0..width {
            let mut sum = glam::DVec3::ZERO;
            let mut squares = glam::DVec3::ZERO;
            for index in 0..REFERENCE_SAMPLES {
                let (dx, dy) = Reference::sample_offset(
                    Sampling::Jittered,
                    REFERENCE_SAMPLES,
                    index,
                    (x, y),
                    REFERENCE_SEED,
                );
                let sample = tracer.sample(x as f32 + dx, y as f32 + dy).as_dvec3();
                sum += sample;
                squares += sample * sample;
            }
            let average = sum / f64::from(count);
            let variance = (squares / f64::from(count) - average * average).max(glam::DVec3::ZERO)
                * (f64::from(count) / f64::from(count - 1.0));
            mean.push(average.as_vec3());
            sigma.push(variance.map(f64::sqrt).as_vec3());
        }
    }
    Converged {
        width,
        height,
        mean,
        sigma,
    }
}

/// How a student's sampled image compares with the converged reference.
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseCheck {
    /// Pixels beyond both 2 levels and [`SIGMAS`] of the noise.
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

/// Compares the student's linear pixels `image` (row by row, `samples`
/// each) with `converged`.
pub fn judge(image: &[Vec3], samples: u32, converged: &Converged) -> NoiseCheck {
    let scale = 1.0 / (samples as f32).sqrt() + 1.0 / (REFERENCE_SAMPLES as f32).sqrt();
    let mut outside = 0;
    let mut first = None;
    for (index, ((got, mean), sigma)) in image
        .iter()
        .zip(&converged.mean)
        .zip(&converged.sigma)
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
            .cmple(*sigma * (SIGMAS * scale))
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
        outside,
        allowed: allowed_outliers(image.len()),
        pixels: image.len(),
        first,
    }
}
