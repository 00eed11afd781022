//! The anti-aliasing of the lab report raylab grew from, measured against
//! supersampling (chapter 7's lesson quotes the table): each pixel, traced
//! once through its centre, replaced by the mean of itself and its four
//! neighbours.
//!
//! Two scenes show two faults. On the chapter's scene, the error at edges:
//! the mean spreads each edge over three pixels instead of measuring how
//! much of one pixel it covers. On a checker whose squares are exactly one
//! pixel, the detail lost: a pixel's four neighbours are all of the other
//! colour, so the mean keeps `(1 - 4) / 5 = -60%` of the contrast (the
//! checker comes back inverted and fainter), where supersampling keeps all
//! of it. Both are measured, not assumed, with the chapters being run.
//!
//! Everything is rendered at the chapter's stage by the chapters `C`
//! themselves (a scene's comparison settings, the textbook sphere formula
//! or triangle test, are not swapped in), without chapter 14's light
//! paths, which add the same light to every row whatever the camera's
//! samples (and would otherwise be left out of the camera paths).

use std::time::Instant;

use rayon::prelude::*;

use super::{CostError, ImageError, reference_settings};
use crate::output::linear_to_srgb8;
use crate::render::{Stage, Tracer};
use crate::scene::{Switch, SwitchedOff};
use crate::{Chapters, RenderSettings, Sampling, Scene, Vec3};

/// Samples per pixel of the supersampled rows (jittered): fewer rays than
/// the five a pixel the report's mean reads.
pub const SUPERSAMPLES: u32 = 4;

/// A pixel of the reference is on an edge when a channel of one of its
/// four neighbours differs from it by more than this many codes (a tenth
/// of the range).
pub const EDGE_CODES: u8 = 25;

/// One way to make a pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// One ray through the pixel's centre.
    Centre,
    /// The report's: the centres' image, each pixel the mean of itself and
    /// its four neighbours (those inside the image), their colours reused.
    Averaged,
    /// The same mean, each pixel casting its neighbours' rays again: five
    /// rays a pixel for the same image.
    AveragedTraced,
    /// Chapter 7's: [`SUPERSAMPLES`] jittered samples inside the pixel.
    Supersampled,
    /// Supersampling, then the report's mean: what the mean does at no
    /// cost in rays.
    SupersampledAveraged,
}

impl Method {
    pub const ALL: [Method; 5] = [
        Method::Centre,
        Method::Averaged,
        Method::AveragedTraced,
        Method::Supersampled,
        Method::SupersampledAveraged,
    ];

    pub fn label(self) -> String {
        match self {
            Method::Centre => "pixel centre".into(),
            Method::Averaged => "centre, neighbours averaged (the report's)".into(),
            Method::AveragedTraced => "centre, neighbours' rays cast again and averaged".into(),
            Method::Supersampled => format!("jittered {SUPERSAMPLES} spp"),
            Method::SupersampledAveraged => {
                format!("jittered {SUPERSAMPLES} spp, neighbours averaged")
            }
        }
    }

    /// Camera rays cast per pixel.
    pub fn rays_per_pixel(self) -> u32 {
        match self {
            Method::Centre | Method::Averaged => 1,
            Method::AveragedTraced => 5,
            Method::Supersampled | Method::SupersampledAveraged => SUPERSAMPLES,
        }
    }
}

/// One method, measured on both scenes.
#[derive(Debug, Clone)]
pub struct NeighbourRow {
    pub method: Method,
    /// Median wall time on the chapter's scene, in seconds.
    pub seconds: f64,
    /// Error on the chapter's scene, every pixel.
    pub error: ImageError,
    /// RMSE on the chapter's scene's edge pixels, in codes.
    pub edge_rmse: f64,
    /// Error on the one-pixel checker.
    pub checker: ImageError,
    /// The share of the checker's contrast kept, in linear light: 1 for
    /// all of it, negative when light and dark squares trade places.
    pub contrast: f64,
}

/// The measurement.
#[derive(Debug, Clone)]
pub struct NeighbourReport {
    pub chapter: u8,
    pub scene_name: String,
    pub width: u32,
    pub height: u32,
    pub repeats: u32,
    /// Samples per pixel of the references.
    pub reference_samples: u32,
    /// Pixels of the chapter's scene on an edge ([`EDGE_CODES`]).
    pub edge_pixels: usize,
    pub rows: Vec<NeighbourRow>,
}

impl NeighbourReport {
    /// The measurement as Markdown: what was rendered, then a row a method.
    pub fn markdown(&self) -> String {
        use std::fmt::Write as _;
        let pixels = (self.width * self.height) as f64;
        let mut text = format!(
            "\nThe lab report's anti-aliasing, each pixel averaged with its four neighbours, \
             against supersampling: chapter {} stage, {} and a checker of one-pixel squares \
             ({}x{}); time: median of {} on the scene; error against a {} jittered spp \
             reference in 8-bit sRGB codes, over every pixel and over the {} edge pixels \
             ({:.1}%: a channel more than {} codes from a neighbour's in the reference); \
             contrast: the checker's light squares minus its dark ones, in linear light, \
             as a share of the reference's.\n\n\
             | method | rays a pixel | time (ms) | RMSE | RMSE at edges | checker RMSE | checker contrast kept |\n\
             |---|---:|---:|---:|---:|---:|---:|\n",
            self.chapter,
            self.scene_name,
            self.width,
            self.height,
            crate::text::count(u64::from(self.repeats), "run"),
            self.reference_samples,
            self.edge_pixels,
            100.0 * self.edge_pixels as f64 / pixels.max(1.0),
            EDGE_CODES,
        );
        for row in &self.rows {
            let _ = writeln!(
                text,
                "| {} | {} | {:.1} | {:.2} | {:.2} | {:.2} | {:.0}% |",
                row.method.label(),
                row.method.rays_per_pixel(),
                row.seconds * 1e3,
                row.error.rmse,
                row.edge_rmse,
                row.checker.rmse,
                row.contrast * 100.0,
            );
        }
        text
    }
}

/// Measures every [`Method`] on `scene` (named `scene_name`) and on the
/// one-pixel checker, at `chapter`'s stage with `base`'s size and
/// settings, each against a [`reference_settings`] render of the same
/// scene; times are the median of `repeats` renders of `scene`.
pub fn run<C: Chapters>(
    scene: &Scene,
    scene_name: &str,
    chapter: u8,
    base: &RenderSettings,
    repeats: u32,
) -> Result<NeighbourReport, CostError> {
    let without = SwitchedOff::parse([Switch::LightTracing.name()])
        .unwrap_or_default()
        .union(base.without);
    let base = RenderSettings { without, ..*base };
    let (width, height) = (base.width, base.height);
    let checker = one_pixel_checker(width, height);
    let reference = reference_settings(&base);
    let scene_reference = render::<C>(scene, chapter, reference, Method::Supersampled)?;
    let checker_reference = render::<C>(&checker, chapter, reference, Method::Supersampled)?;
    let scene_reference_rgb = encode(&scene_reference);
    let edges = edge_pixels(&scene_reference_rgb, width, height);
    let mut rows = Vec::new();
    for method in Method::ALL {
        let settings = settings_for(method, &base);
        let mut times = Vec::new();
        let mut image = Vec::new();
        for _ in 0..repeats.max(1) {
            let start = Instant::now();
            image = encode(&render::<C>(scene, chapter, settings, method)?);
            times.push(start.elapsed().as_secs_f64());
        }
        times.sort_by(f64::total_cmp);
        let on_checker = render::<C>(&checker, chapter, settings, method)?;
        rows.push(NeighbourRow {
            method,
            seconds: times[times.len() / 2],
            error: ImageError::between(&image, &scene_reference_rgb)?,
            edge_rmse: masked_rmse(&image, &scene_reference_rgb, &edges),
            checker: ImageError::between(&encode(&on_checker), &encode(&checker_reference))?,
            contrast: contrast_kept(&on_checker, &checker_reference),
        });
    }
    Ok(NeighbourReport {
        chapter,
        scene_name: scene_name.to_string(),
        width,
        height,
        repeats: repeats.max(1),
        reference_samples: reference.samples,
        edge_pixels: edges.iter().filter(|&&edge| edge).count(),
        rows,
    })
}

/// `base` as `method` renders it: one sample a pixel, or
/// [`SUPERSAMPLES`] jittered ones.
pub fn settings_for(method: Method, base: &RenderSettings) -> RenderSettings {
    match method {
        Method::Supersampled | Method::SupersampledAveraged => RenderSettings {
            samples: SUPERSAMPLES,
            sampling: Sampling::Jittered,
            ..*base
        },
        Method::Centre | Method::Averaged | Method::AveragedTraced => RenderSettings {
            samples: 1,
            ..*base
        },
    }
}

/// `scene`'s image with `settings` as `method` makes its pixels (of the
/// settings' samples: see [`settings_for`]), in linear light, row by row;
/// the rows in parallel on the current thread pool, one tracer each.
pub fn render<C: Chapters>(
    scene: &Scene,
    chapter: u8,
    settings: RenderSettings,
    method: Method,
) -> Result<Vec<Vec3>, CostError> {
    let stage = Stage::<C>::with_chapters(scene, chapter, settings)?;
    let (width, height) = (settings.width, settings.height);
    let pixels = |pixel: &(dyn Fn(&mut Tracer<'_, C>, u32, u32) -> Vec3 + Sync)| {
        (0..height)
            .into_par_iter()
            .flat_map_iter(|y| {
                let mut tracer = stage.tracer(None);
                (0..width)
                    .map(|x| pixel(&mut tracer, x, y))
                    .collect::<Vec<_>>()
            })
            .collect::<Vec<Vec3>>()
    };
    Ok(match method {
        Method::Centre | Method::Supersampled => pixels(&|tracer, x, y| tracer.pixel(x, y)),
        Method::Averaged | Method::SupersampledAveraged => {
            let image = pixels(&|tracer, x, y| tracer.pixel(x, y));
            neighbour_mean(&image, width, height)
        }
        Method::AveragedTraced => pixels(&|tracer, x, y| {
            mean_around(x, y, width, height, |nx, ny| {
                tracer.sample(nx as f32 + 0.5, ny as f32 + 0.5)
            })
        }),
    })
}

/// Pixel `(x, y)` and those of its four neighbours inside a `width x
/// height` image, in the order the means add them: the first `count` of
/// the array.
fn neighbours(x: u32, y: u32, width: u32, height: u32) -> ([(u32, u32); 5], usize) {
    let mut around = [(x, y); 5];
    let mut count = 1;
    let mut add = |inside: bool, pixel: (u32, u32)| {
        if inside {
            around[count] = pixel;
            count += 1;
        }
    };
    add(x > 0, (x.wrapping_sub(1), y));
    add(x + 1 < width, (x + 1, y));
    add(y > 0, (x, y.wrapping_sub(1)));
    add(y + 1 < height, (x, y + 1));
    (around, count)
}

/// The mean of `value` over pixel `(x, y)` and its neighbours.
fn mean_around(
    x: u32,
    y: u32,
    width: u32,
    height: u32,
    mut value: impl FnMut(u32, u32) -> Vec3,
) -> Vec3 {
    let (around, count) = neighbours(x, y, width, height);
    let mut sum = Vec3::ZERO;
    for &(nx, ny) in &around[..count] {
        sum += value(nx, ny);
    }
    sum / count as f32
}

/// The report's filter: each pixel of `image` the mean of itself and its
/// neighbours inside the image (rows in parallel, as a render's).
pub fn neighbour_mean(image: &[Vec3], width: u32, height: u32) -> Vec<Vec3> {
    let at = |x: u32, y: u32| image[(y * width + x) as usize];
    (0..height)
        .into_par_iter()
        .flat_map_iter(|y| (0..width).map(move |x| mean_around(x, y, width, height, at)))
        .collect()
}

fn encode(image: &[Vec3]) -> Vec<u8> {
    image
        .iter()
        .flat_map(|pixel| pixel.to_array().map(linear_to_srgb8))
        .collect()
}

/// Which pixels of `rgb` are on an edge ([`EDGE_CODES`]).
fn edge_pixels(rgb: &[u8], width: u32, height: u32) -> Vec<bool> {
    let at = |x: u32, y: u32| {
        let start = 3 * (y * width + x) as usize;
        &rgb[start..start + 3]
    };
    (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (around, count) = neighbours(x, y, width, height);
            around[..count].iter().any(|&(nx, ny)| {
                at(x, y)
                    .iter()
                    .zip(at(nx, ny))
                    .any(|(a, b)| a.abs_diff(*b) > EDGE_CODES)
            })
        })
        .collect()
}

/// The RMSE in codes of `image` against `reference` over the pixels
/// `mask` marks (0 when it marks none).
fn masked_rmse(image: &[u8], reference: &[u8], mask: &[bool]) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for ((pixel, expected), &marked) in image
        .chunks_exact(3)
        .zip(reference.chunks_exact(3))
        .zip(mask)
    {
        if marked {
            for (a, b) in pixel.iter().zip(expected) {
                sum += (f64::from(*a) - f64::from(*b)).powi(2);
                count += 1;
            }
        }
    }
    if count == 0 {
        0.0
    } else {
        (sum / count as f64).sqrt()
    }
}

/// The share of the reference's contrast `image` keeps, in linear light:
/// the mean of its pixels where the reference is light minus the mean
/// where it is dark, over the same for the reference (light: above the
/// reference's middle grey).
fn contrast_kept(image: &[Vec3], reference: &[Vec3]) -> f64 {
    let grey = |pixel: &Vec3| f64::from(pixel.element_sum()) / 3.0;
    let middle = reference.iter().map(grey).fold(0.0, f64::max) / 2.0;
    let mean_where = |pixels: &[Vec3], light: bool| {
        let chosen: Vec<f64> = pixels
            .iter()
            .zip(reference)
            .filter(|(_, expected)| (grey(expected) > middle) == light)
            .map(|(pixel, _)| grey(pixel))
            .collect();
        chosen.iter().sum::<f64>() / chosen.len().max(1) as f64
    };
    let difference = |pixels: &[Vec3]| mean_where(pixels, true) - mean_where(pixels, false);
    difference(image) / difference(reference)
}

/// A white and black checker facing the camera, lit by ambient light
/// alone (and, for path tracing, by a white sky), whose squares are
/// exactly the pixels of a `width x height` image.
///
/// With a 90 degree field of view (vertical), a plane at distance
/// `height / 2` is seen `height` units high: one unit a pixel, the size of
/// the squares. The image's centre is a corner of four pixels when both
/// sizes are even; an odd size moves the squares by half of one, so that
/// no pixel's centre lies on the edge of a square.
pub fn one_pixel_checker(width: u32, height: u32) -> Scene {
    let half = |size: u32| if size % 2 == 1 { 0.5 } else { 0.0 };
    let text = format!(
        "background = [1.0, 1.0, 1.0]\n\
         ambient_light = [1.0, 1.0, 1.0]\n\
         [camera]\n\
         position = [0.0, 0.0, 0.0]\n\
         look_at = [0.0, 0.0, 1.0]\n\
         up = [0.0, 1.0, 0.0]\n\
         fov_degrees = 90.0\n\
         [[objects]]\n\
         name = \"one-pixel checker\"\n\
         plane = {{ point = [{}, {}, {}], normal = [0.0, 0.0, -1.0] }}\n\
         material = {{ color = [1.0, 1.0, 1.0], ambient = 1.0, diffuse = 0.0, \
         checker = {{ color = [0.0, 0.0, 0.0], size = 1.0 }} }}\n",
        half(width),
        half(height),
        f64::from(height) / 2.0,
    );
    // Only the plane's place depends on the size, and every finite place
    // is a valid plane.
    Scene::parse(&text, "the one-pixel checker of raylab cost")
        .expect("the one-pixel checker is a valid scene at any size")
}
