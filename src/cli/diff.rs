//! `raylab diff`: compare two PNGs, or two OpenEXR images in linear light.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;

use crate::cli::EXIT_FAILED_CHECK;
use crate::diff::{AnyImage, Criteria, DiffError, LinearCriteria, LinearImage, compare};

/// When two images count as the same (shared by `diff` and `grade`).
#[derive(Debug, Clone, Args)]
pub struct CriteriaArgs {
    /// A pixel is "over" when any of its R, G, B values differs by more than
    /// T levels (0-255, 8-bit sRGB units; a difference of exactly T is
    /// within) [default: 2]. PNGs only.
    #[arg(long, value_name = "T")]
    pub threshold: Option<u8>,
    /// The percentage of pixels that may be over the threshold while the
    /// images still pass (0 to 100).
    #[arg(long, value_name = "PERCENT", default_value_t = Criteria::default().allowed_percent,
          value_parser = parse_percent)]
    pub allow: f64,
}

fn parse_tolerance(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(r) if r.is_finite() && r >= 0.0 => Ok(r),
        _ => Err(format!(
            "{text:?} is not a relative error (a number from 0 up)"
        )),
    }
}

fn parse_percent(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(p) if (0.0..=100.0).contains(&p) => Ok(p),
        _ => Err(format!("{text:?} is not a percentage from 0 to 100")),
    }
}

impl CriteriaArgs {
    pub fn criteria(&self) -> Criteria {
        Criteria {
            threshold: self.threshold.unwrap_or(Criteria::default().threshold),
            allowed_percent: self.allow,
        }
    }
}

/// Compare two PNGs (8-bit sRGB) or two OpenEXR images (linear light):
/// metrics, pass/fail, and a heatmap of differences.
///
/// Prints the maximum and mean absolute difference, RMSE, PSNR and the
/// share of pixels over the threshold, and optionally draws a heatmap.
/// Whether a file is a PNG or an OpenEXR image is read from its first
/// bytes; one of each is an error.
///
/// Differences are in 8-bit levels (0-255) per R, G, B value. Mean and RMSE
/// are over all 3 x width x height values; PSNR = 20 log10(255 / RMSE) dB,
/// printed as `inf` for identical images. A pixel is over the threshold when
/// its largest channel difference exceeds T. The images pass when at most
/// --allow percent of the pixels are over (by default: none over 2 levels).
///
/// OpenEXR images (`raylab render -o NAME.exr`) are compared in linear
/// light, with B as the reference: max and mean absolute difference and
/// RMSE in linear units, relative MSE = mean of (a-b)^2 / (b^2 + 0.01) and
/// mean relative error = mean of |a-b| / (|b| + 0.01), the measures of a
/// Monte Carlo render's noise. A pixel is over when a channel's relative
/// error |a-b| / (|b| + 0.01) exceeds --tolerance (default 0.01). A NaN or
/// an infinity in either image is an error naming the pixel. No heatmap
/// is drawn for them.
///
/// Exit status: 0 pass, 1 fail, 2 error (missing file, not a regular file,
/// not a PNG or OpenEXR file, a corrupted one, a PNG and an OpenEXR image,
/// a NaN or infinite value, over the size limit, different sizes,
/// unwritable output; the verdict is printed before the outputs are
/// written, and they are written all or none).
///
/// Images are read up to 16384 pixels a side and 40,000,000 pixels in all
/// (320 MB decoded); larger ones are refused before decoding.
#[derive(Debug, Args)]
#[command(long_about)]
pub struct DiffArgs {
    /// The first image (e.g. the student's); the heatmap shows it dimmed where nothing differs.
    #[arg(value_name = "A.png|A.exr")]
    pub a: PathBuf,
    /// The second image (e.g. the reference).
    #[arg(value_name = "B.png|B.exr")]
    pub b: PathBuf,
    /// Write a false-colour heatmap: pixels that differ coloured from dark
    /// blue (1 level) to red (the largest difference), identical pixels in
    /// dim grey, and a legend strip below the image: the colour bar labelled
    /// 0 and the largest difference, a white tick at the threshold.
    #[arg(long, value_name = "OUT.png")]
    pub heatmap: Option<PathBuf>,
    #[command(flatten)]
    pub criteria: CriteriaArgs,
    /// OpenEXR images only: a pixel is "over" when one of its channels'
    /// relative error |a-b| / (|b| + 0.01) exceeds R (strictly) [default: 0.01].
    #[arg(long, value_name = "R", value_parser = parse_tolerance)]
    pub tolerance: Option<f64>,
    /// Also write the metrics as JSON to FILE (`psnr_db` is null when the
    /// images are identical: JSON has no infinity).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Replace a --heatmap or --json file that raylab did not write, or a
    /// read-only one.
    #[arg(long)]
    pub force: bool,
}

pub fn diff(args: &DiffArgs) -> Result<i32> {
    let outputs: Vec<(&str, &std::path::Path)> =
        [("--heatmap", &args.heatmap), ("--json", &args.json)]
            .into_iter()
            .filter_map(|(option, path)| Some((option, path.as_deref()?)))
            .collect();
    if let Some(path) = &args.heatmap {
        crate::output::check_png_name("--heatmap", path)?;
    }
    crate::output::check_outputs(&[&args.a, &args.b], &outputs, args.force)?;
    if let Some(path) = &args.heatmap {
        crate::output::check_replaceable_png("--heatmap", path, args.force)?;
    }
    if let Some(path) = &args.json {
        crate::output::check_replaceable_text(
            "--json",
            path,
            args.force,
            crate::output::markers::DIFF_JSON,
        )?;
    }
    let names = (args.a.display().to_string(), args.b.display().to_string());
    let (a, b) = match (AnyImage::load(&args.a)?, AnyImage::load(&args.b)?) {
        (AnyImage::Srgb(a), AnyImage::Srgb(b)) => (a, b),
        (AnyImage::Linear(a), AnyImage::Linear(b)) => return diff_linear(args, &a, &b, &names),
        (a, b) => {
            return Err(DiffError::MixedKinds {
                names,
                kinds: (a.kind(), b.kind()),
            }
            .into());
        }
    };
    if args.tolerance.is_some() {
        bail!(
            "--tolerance is a relative error in linear light, for OpenEXR images; \
             PNGs are compared in 8-bit levels (--threshold)"
        );
    }
    let comparison = compare(&a, &b, args.criteria.criteria(), (&names.0, &names.1))?;
    // The verdict first: an output that fails to be written (a full disk)
    // is an error, but must not hide the answer the comparison gave.
    let safe = crate::text::terminal_safe;
    println!("{} vs {}", safe(&names.0), safe(&names.1));
    print!("{}", comparison.report_text());
    let mut files: Vec<(&std::path::Path, Vec<u8>)> = Vec::new();
    if let Some(path) = &args.heatmap {
        files.push((path, comparison.heatmap(&a)?.encode_png()?));
    }
    if let Some(path) = &args.json {
        let mut json = comparison.json();
        json["a"] = names.0.clone().into();
        json["b"] = names.1.clone().into();
        files.push((path, format!("{json:#}\n").into_bytes()));
    }
    // All or nothing: never a heatmap without its JSON or the other way.
    let files: Vec<(&std::path::Path, &[u8])> = files
        .iter()
        .map(|(path, bytes)| (*path, bytes.as_slice()))
        .collect();
    crate::output::write_files(&files)?;
    if let Some(path) = &args.heatmap {
        println!(
            "heatmap: {} (dim grey: identical; dark blue 1 level .. red {} levels; white tick: threshold {})",
            safe(&path.display().to_string()),
            comparison.metrics.max.max(1),
            comparison.criteria.threshold
        );
    }
    Ok(if comparison.passes() {
        0
    } else {
        EXIT_FAILED_CHECK
    })
}

/// `raylab diff` of two OpenEXR images, in linear light.
fn diff_linear(
    args: &DiffArgs,
    a: &LinearImage,
    b: &LinearImage,
    names: &(String, String),
) -> Result<i32> {
    if args.heatmap.is_some() {
        bail!(
            "--heatmap draws differences in 8-bit levels, for PNGs; OpenEXR images are \
             compared in linear light without one (render .png images for a heatmap)"
        );
    }
    if args.criteria.threshold.is_some() {
        bail!(
            "--threshold counts 8-bit levels, for PNGs; OpenEXR images are compared in \
             linear light: use --tolerance (a relative error)"
        );
    }
    let criteria = LinearCriteria {
        tolerance: args
            .tolerance
            .unwrap_or(LinearCriteria::default().tolerance),
        allowed_percent: args.criteria.allow,
    };
    let comparison = crate::diff::compare_linear(a, b, criteria, (&names.0, &names.1))?;
    let safe = crate::text::terminal_safe;
    println!("{} vs {}", safe(&names.0), safe(&names.1));
    print!("{}", comparison.report_text());
    if let Some(path) = &args.json {
        let mut json = comparison.json();
        json["a"] = names.0.clone().into();
        json["b"] = names.1.clone().into();
        crate::output::write_files(&[(path, format!("{json:#}\n").as_bytes())])?;
    }
    Ok(if comparison.passes() {
        0
    } else {
        EXIT_FAILED_CHECK
    })
}
