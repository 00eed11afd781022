//! Every ray a render casts, recorded in a fixed order under a budget:
//! what `raylab crosscheck` and `raylab race` compare, ray by ray.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use rayon::prelude::*;

use crate::Ray;
use crate::course::Chapters;
use crate::render::{CastRay, LIGHT_CHUNK, RayKind, RayLog, Stage};

/// Why a recording was refused or stopped at its ray budget.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TooManyRays {
    /// The primary rays alone pass the budget: refused before tracing.
    #[error(
        "{width}x{height} at {samples} samples per pixel is {primary} primary rays alone; \
         crosscheck keeps every ray in memory and records at most {budget}: use a smaller \
         --width, --height or --samples"
    )]
    Primary {
        width: u32,
        height: u32,
        samples: u32,
        primary: u64,
        budget: u64,
    },
    /// The rays cast passed the budget while recording.
    #[error(
        "crosscheck keeps every ray in memory and records at most {budget} rays: this render \
         passed that after {pixels_done} of {pixels} pixels (about {estimate} rays in all); \
         use a smaller --width, --height, --samples or --depth"
    )]
    Cast {
        budget: u64,
        pixels_done: u64,
        pixels: u64,
        /// The whole render's rays, extrapolated from the pixels done.
        estimate: u64,
    },
}

/// How many rays a row's recorder counts before adding them to the shared
/// count: few enough additions that the atomic counter is not contended,
/// and at most this many rays per thread kept past the budget before the
/// recording stops (150 KB).
const FLUSH_EVERY: u64 = 4096;

/// A [`RayLog`] that keeps every ray until the shared count passes the
/// budget, then keeps none and raises the shared `exhausted` flag.
struct BudgetedRecorder<'a> {
    rays: Vec<CastRay>,
    /// Rays cast and not yet added to `cast`.
    unflushed: u64,
    budget: u64,
    cast: &'a AtomicU64,
    exhausted: &'a AtomicBool,
}

impl<'a> BudgetedRecorder<'a> {
    /// A recorder with nothing kept yet, sharing the count `cast` and the
    /// flag `exhausted` with the others of one recording.
    fn new(budget: u64, cast: &'a AtomicU64, exhausted: &'a AtomicBool) -> BudgetedRecorder<'a> {
        BudgetedRecorder {
            rays: Vec::new(),
            unflushed: 0,
            budget,
            cast,
            exhausted,
        }
    }

    fn flush(&mut self) {
        let total = self.cast.fetch_add(self.unflushed, Ordering::Relaxed) + self.unflushed;
        self.unflushed = 0;
        if total > self.budget {
            self.exhausted.store(true, Ordering::Relaxed);
        }
    }

    fn stopped(&self) -> bool {
        self.exhausted.load(Ordering::Relaxed)
    }
}

impl RayLog for BudgetedRecorder<'_> {
    fn cast(&mut self, kind: RayKind, ray: &Ray, t_min: f32, t_max: f32) {
        self.unflushed += 1;
        if self.unflushed == FLUSH_EVERY {
            self.flush();
        }
        if !self.stopped() {
            self.rays.push(CastRay {
                kind,
                ray: *ray,
                t_min,
                t_max,
            });
        }
    }
}

/// A [`RayLog`] that keeps every ray cast, in order (for `raylab crosscheck`).
#[derive(Debug, Clone, Default)]
pub struct RayRecorder {
    pub rays: Vec<CastRay>,
}

impl RayLog for RayRecorder {
    fn cast(&mut self, kind: RayKind, ray: &Ray, t_min: f32, t_max: f32) {
        self.rays.push(CastRay {
            kind,
            ray: *ray,
            t_min,
            t_max,
        });
    }
}

/// Every ray that rendering the whole image at `stage` casts, in a fixed
/// order: row by row from the top, pixel by pixel, and within a pixel in the
/// order the chapters cast them, whatever the number of threads. Unbounded:
/// `raylab crosscheck` uses [`record_rays_within`].
pub fn record_rays<C: Chapters>(stage: &Stage<'_, C>) -> Vec<CastRay> {
    // No scene can cast u64::MAX rays, so the budget is never reached.
    record_rays_within(stage, u64::MAX).unwrap_or_default()
}

/// Every ray that rendering the whole image with `tracer` casts, in the
/// order of [`record_rays`] (row by row from the top, pixel by
/// pixel), or [`TooManyRays`] as soon as more than `budget` have been cast.
/// Memory stays at about `budget` rays whatever the scene: recorders stop
/// keeping rays, and rows stop at the next pixel, once the count passes it.
pub fn record_rays_within<C: Chapters>(
    stage: &Stage<'_, C>,
    budget: u64,
) -> Result<Vec<CastRay>, TooManyRays> {
    let tracer = stage;
    let (width, height) = (tracer.settings.width, tracer.settings.height);
    let pixels = u64::from(width) * u64::from(height);
    let primary = pixels * u64::from(tracer.samples());
    // Each sample casts at least its primary ray: no need to start.
    if primary > budget {
        return Err(TooManyRays::Primary {
            width,
            height,
            samples: tracer.samples(),
            primary,
            budget,
        });
    }
    let cast = AtomicU64::new(0);
    let exhausted = AtomicBool::new(false);
    let pixels_done = AtomicU64::new(0);
    let rows: Vec<Vec<CastRay>> = (0..height)
        .into_par_iter()
        .map(|y| {
            let mut recorder = BudgetedRecorder::new(budget, &cast, &exhausted);
            for x in 0..width {
                if recorder.stopped() {
                    break;
                }
                // A tracer per pixel (a copy of two references) leaves the
                // recorder free between pixels, to ask whether to stop.
                stage.tracer(Some(&mut recorder)).pixel(x, y);
                pixels_done.fetch_add(1, Ordering::Relaxed);
            }
            recorder.flush();
            recorder.rays
        })
        .collect();
    // Every row has added its count: the total is exact, and so is the
    // comparison with the budget.
    if exhausted.load(Ordering::Relaxed) {
        let done = pixels_done.into_inner();
        let estimate = u128::from(cast.into_inner()) * u128::from(pixels) / u128::from(done.max(1));
        return Err(TooManyRays::Cast {
            budget,
            pixels_done: done,
            pixels,
            estimate: u64::try_from(estimate).unwrap_or(u64::MAX),
        });
    }
    // Chapter 14's light paths after the pixels, chunk by chunk in path
    // order, as the render traces them.
    let paths = stage.light_path_count();
    let chunks: Vec<Vec<CastRay>> = (0..paths.div_ceil(LIGHT_CHUNK))
        .into_par_iter()
        .map(|chunk| {
            let mut recorder = BudgetedRecorder::new(budget, &cast, &exhausted);
            if !recorder.stopped() {
                let first = chunk * LIGHT_CHUNK;
                stage.record_light_paths(first..(first + LIGHT_CHUNK).min(paths), &mut recorder);
            }
            recorder.flush();
            recorder.rays
        })
        .collect();
    if exhausted.into_inner() {
        // Every pixel was traced: the light paths passed the budget, and
        // the rays counted so far are a floor of the whole.
        return Err(TooManyRays::Cast {
            budget,
            pixels_done: pixels,
            pixels,
            estimate: cast.into_inner(),
        });
    }
    // Row by row into one vector, each row freed once copied: the peak is
    // about one copy of the rays, not two.
    let mut rays = Vec::with_capacity(rows.iter().chain(&chunks).map(Vec::len).sum());
    for row in rows.into_iter().chain(chunks) {
        rays.extend_from_slice(&row);
    }
    Ok(rays)
}
