//! Comparing two renders: difference metrics, a pass/fail rule, and a
//! false-colour heatmap of where they differ (used by `raylab diff` and
//! `raylab grade`).
//!
//! Between PNGs, all differences are in 8-bit sRGB levels (0 to 255), the
//! units of the files themselves (OpenEXR images are compared in linear
//! light instead: see [`linear`]):
//!
//! - *max*: the largest absolute difference of any channel of any pixel;
//! - *mean*: the mean absolute difference over all `3 * width * height`
//!   channel values;
//! - *RMSE*: the root of the mean squared difference over the same values;
//! - *PSNR*: `20 log10(255 / RMSE)` in dB, infinite for identical images;
//! - a pixel's difference is the largest of its three channel differences,
//!   and the pixel is *over* the threshold `T` when that exceeds `T`
//!   (strictly: a difference of exactly `T` is within it).
//!
//! Two images *pass* when the share of pixels over `T` is at most the allowed
//! percentage ([`Criteria`]; by default no pixel may be over 2 levels).

use std::path::{Path, PathBuf};

use crate::input::InputError;
use crate::output::OutputError;

pub mod linear;
pub use linear::{LinearComparison, LinearCriteria, LinearImage, compare_linear};

/// Why an image was not read, two images not compared, or a heatmap not
/// drawn. Each message is whole, the decoder's reason included.
#[derive(Debug, thiserror::Error)]
pub enum DiffError {
    /// Missing, not a regular file, too large, or declaring a size over
    /// [`crate::input`]'s limits.
    #[error(transparent)]
    Input(#[from] InputError),
    #[error("not a PNG file (it does not start with the PNG signature)")]
    NotPng,
    #[error("corrupted PNG: {0}")]
    CorruptedHeader(png::DecodingError),
    #[error("corrupted PNG: {0}")]
    Corrupted(png::DecodingError),
    /// The decoder expanded the pixels to a layout it should not have: a
    /// PNG whose header and data disagree.
    #[error("corrupted PNG: its pixels do not decode to the colour type its header declares")]
    Undecodable,
    /// The decoder's own guard, worded as the limit it is.
    #[error(
        "{width}x{height} pixels: decoding needs more memory than raylab's image size \
         limit allows ({} bytes)",
        2 * crate::input::MAX_DECODED_BYTES
    )]
    DecodeLimit { width: u32, height: u32 },
    /// The PNG at `path` does not decode.
    #[error("{}: {error}", path.display())]
    InFile {
        path: PathBuf,
        error: Box<DiffError>,
    },
    /// `names` say what the images are ("student", "reference"); the sizes
    /// are written `WxH`.
    #[error(
        "{} is {} but {} is {}: only images of the same size can be compared",
        names.0,
        sizes.0,
        names.1,
        sizes.1
    )]
    SizeMismatch {
        names: (String, String),
        sizes: (String, String),
    },
    #[error("{} and {}: no pixels to compare", names.0, names.1)]
    NoPixels { names: (String, String) },
    /// The base image is not the one compared: `base_size` is written `WxH`.
    #[error(
        "cannot draw a heatmap: the comparison is of {width}x{height} pixels \
         ({differences} differences) but the base image is {base_size} ({base_bytes} bytes of RGB)"
    )]
    HeatmapMismatch {
        width: u32,
        height: u32,
        differences: usize,
        base_size: String,
        base_bytes: usize,
    },
    #[error("cannot draw a heatmap: {0}")]
    HeatmapTooLarge(InputError),
    #[error("not an OpenEXR file (it does not start with the OpenEXR magic number)")]
    NotExr,
    #[error("corrupted OpenEXR: {0}")]
    CorruptedExr(exr::error::Error),
    /// More layers or channels than raylab reads: every one is decoded in
    /// memory, at four bytes a pixel each.
    #[error(
        "an OpenEXR file of {count} {what}: raylab reads at most {most} (R, G, B and a few \
         more), as each is decoded in memory"
    )]
    ExrTooWide {
        what: &'static str,
        count: usize,
        most: usize,
    },
    /// Headers longer than raylab reads: every attribute is held in
    /// memory, many times its size.
    #[error(
        "an OpenEXR file with headers of more than {most} bytes: raylab reads smaller ones, \
         as every attribute is held in memory"
    )]
    ExrHeaderTooLarge { most: usize },
    /// An OpenEXR block (a tile, a run of scan lines) larger decoded than
    /// raylab decodes at once.
    #[error(
        "an OpenEXR file whose blocks (tiles or runs of scan lines) decode to {bytes} bytes \
         each: raylab reads blocks of at most {most} bytes, as each is decoded whole in memory"
    )]
    ExrBlockTooLarge { bytes: u64, most: u64 },
    /// An OpenEXR compression whose decoder may take memory far past the
    /// block's size.
    #[error(
        "an OpenEXR file of {compression}: raylab reads OpenEXR without \
         compression or with ZIP, PIZ, PXR24 or B44, as this one's decoder can take memory \
         far past the image's size; save it with one of those"
    )]
    ExrCompressionNotRead { compression: String },
    /// OpenEXR headers the scan cannot read to their end as the decoder
    /// would: refused before the decoder reads on past them.
    #[error(
        "corrupted OpenEXR headers: at byte {at}, {why}; raylab refuses them before decoding \
         (the decoder would read on unbounded)"
    )]
    ExrHeaderUnreadable { at: usize, why: &'static str },
    /// A channel's value that no error can be measured against.
    #[error(
        "pixel x={x}, y={y} has {channel} = {value}: raylab compares finite linear values only"
    )]
    NotFinite {
        x: u32,
        y: u32,
        channel: &'static str,
        value: f32,
    },
    /// Neither signature: `path` is the file.
    #[error(
        "{}: not a PNG file nor an OpenEXR file (it starts with neither's signature)",
        path.display()
    )]
    NotAnImage { path: PathBuf },
    /// One PNG, one OpenEXR: `kinds` say which is which.
    #[error(
        "{} is {} but {} is {}: 8-bit sRGB and linear light cannot be compared; \
         render both as .png, or both as .exr for errors in linear light",
        names.0,
        kinds.0,
        names.1,
        kinds.1
    )]
    MixedKinds {
        names: (String, String),
        kinds: (&'static str, &'static str),
    },
}

/// An image as `raylab diff` reads it: by its signature, not its name.
#[derive(Debug, Clone, PartialEq)]
pub enum AnyImage {
    Srgb(Image),
    Linear(LinearImage),
}

impl AnyImage {
    /// Reads a PNG or an OpenEXR file, whichever its first bytes say it is.
    pub fn load(path: &Path) -> Result<AnyImage, DiffError> {
        let bytes = crate::input::read_bounded(
            path,
            crate::input::MAX_PNG_FILE_BYTES.max(linear::MAX_EXR_FILE_BYTES),
            "PNG or OpenEXR image",
            crate::input::Links::Follow,
        )?;
        let in_file = |error| DiffError::InFile {
            path: path.to_path_buf(),
            error: Box::new(error),
        };
        if bytes.starts_with(&PNG_SIGNATURE) {
            if bytes.len() as u64 > crate::input::MAX_PNG_FILE_BYTES {
                return Err(crate::input::InputError::TooLarge {
                    path: path.to_path_buf(),
                    size: bytes.len().to_string(),
                    what: "PNG".into(),
                    max: crate::input::MAX_PNG_FILE_BYTES,
                }
                .into());
            }
            Image::decode_png(&bytes)
                .map(AnyImage::Srgb)
                .map_err(in_file)
        } else if bytes.starts_with(&crate::output::EXR_MAGIC) {
            LinearImage::decode_exr(&bytes)
                .map(AnyImage::Linear)
                .map_err(in_file)
        } else {
            Err(DiffError::NotAnImage {
                path: path.to_path_buf(),
            })
        }
    }

    /// What the image holds, for messages.
    pub fn kind(&self) -> &'static str {
        match self {
            AnyImage::Srgb(_) => "a PNG (8-bit sRGB)",
            AnyImage::Linear(_) => "an OpenEXR image (linear light)",
        }
    }
}

/// An 8-bit RGB image, row by row from the top.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

/// The 8 bytes every PNG file starts with.
pub(crate) const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];

impl Image {
    /// Reads a PNG file as 8-bit RGB. Grey, 16-bit and palette PNGs are
    /// converted; an alpha channel is dropped (renders have none).
    ///
    /// Errors name the file: missing or unreadable, not a regular file (a
    /// FIFO or a device is never read), over the size limits of
    /// [`crate::input`], not a PNG at all, or a PNG whose data is damaged.
    pub fn load_png(path: &Path) -> Result<Image, DiffError> {
        Image::read_png(path, crate::input::Links::Follow)
    }

    /// [`Image::load_png`], saying whether `path` may be a symbolic link.
    pub fn read_png(path: &Path, links: crate::input::Links) -> Result<Image, DiffError> {
        let bytes =
            crate::input::read_bounded(path, crate::input::MAX_PNG_FILE_BYTES, "PNG", links)?;
        Image::decode_png(&bytes).map_err(|error| DiffError::InFile {
            path: path.to_path_buf(),
            error: Box::new(error),
        })
    }

    /// Decodes PNG bytes (see [`Image::load_png`]). The size the PNG
    /// declares is checked against [`crate::input::check_image_size`]
    /// before any pixel is decoded: a small file can declare a huge image.
    pub fn decode_png(bytes: &[u8]) -> Result<Image, DiffError> {
        if !bytes.starts_with(&PNG_SIGNATURE) {
            return Err(DiffError::NotPng);
        }
        // A second guard inside the decoder; the size check below is the
        // one that speaks, so any limit hit here is worded as a limit too.
        let limits = png::Limits {
            bytes: usize::try_from(2 * crate::input::MAX_DECODED_BYTES).unwrap_or(usize::MAX),
        };
        let mut decoder = png::Decoder::new_with_limits(std::io::Cursor::new(bytes), limits);
        // raylab reads the pixels alone. A colour profile (iCCP) or a
        // compressed text (zTXt, iTXt) of a few kilobytes can inflate to
        // hundreds of megabytes: they are skipped unread.
        decoder.set_ignore_iccp_chunk(true);
        decoder.set_ignore_text_chunk(true);
        let info = decoder
            .read_header_info()
            .map_err(DiffError::CorruptedHeader)?;
        let (width, height) = (info.width, info.height);
        crate::input::check_image_size(width, height)?;
        let limit = |error| match error {
            png::DecodingError::LimitsExceeded => DiffError::DecodeLimit { width, height },
            other => DiffError::Corrupted(other),
        };
        // Palettes and low bit depths expanded: what is left is grey or
        // RGB, with or without alpha, in 8 or 16 bits.
        decoder.set_transformations(png::Transformations::EXPAND);
        let mut reader = decoder.read_info().map_err(limit)?;
        let too_large = DiffError::DecodeLimit { width, height };
        let size = reader.output_buffer_size().ok_or(too_large)?;
        let mut pixels = Vec::new();
        pixels
            .try_reserve_exact(size)
            .map_err(|_| DiffError::DecodeLimit { width, height })?;
        pixels.resize(size, 0);
        let frame = reader.next_frame(&mut pixels).map_err(limit)?;
        pixels.truncate(frame.buffer_size());
        // 16-bit samples become 8-bit ones as `image` converts them
        // (rounded to nearest), below.
        let wide = |bytes: Vec<u8>| -> Vec<u16> {
            bytes
                .chunks_exact(2)
                .map(|pair| u16::from_be_bytes([pair[0], pair[1]]))
                .collect()
        };
        // `None` where the samples' count is not the size's.
        macro_rules! image_of {
            ($pixel:ident, $samples:expr) => {
                image::ImageBuffer::<image::$pixel<_>, _>::from_raw(width, height, $samples)
                    .map(image::DynamicImage::from)
            };
        }
        use png::{BitDepth::Eight, BitDepth::Sixteen, ColorType};
        let decoded = match reader.output_color_type() {
            (ColorType::Grayscale, Eight) => image_of!(Luma, pixels),
            (ColorType::GrayscaleAlpha, Eight) => image_of!(LumaA, pixels),
            (ColorType::Rgb, Eight) => image_of!(Rgb, pixels),
            (ColorType::Rgba, Eight) => image_of!(Rgba, pixels),
            (ColorType::Grayscale, Sixteen) => image_of!(Luma, wide(pixels)),
            (ColorType::GrayscaleAlpha, Sixteen) => image_of!(LumaA, wide(pixels)),
            (ColorType::Rgb, Sixteen) => image_of!(Rgb, wide(pixels)),
            (ColorType::Rgba, Sixteen) => image_of!(Rgba, wide(pixels)),
            // EXPAND leaves no palette and no depth under 8 bits.
            _ => None,
        }
        .ok_or(DiffError::Undecodable)?;
        // `into_rgb8` keeps an RGB8 buffer as it is instead of copying it.
        let rgb = decoded.into_rgb8();
        Ok(Image {
            width: rgb.width(),
            height: rgb.height(),
            rgb: rgb.into_raw(),
        })
    }

    /// The image encoded as a PNG file's bytes; an error, not a panic, when
    /// the pixels do not match the size.
    pub fn encode_png(&self) -> Result<Vec<u8>, OutputError> {
        crate::output::encode_png(self.width, self.height, &self.rgb)
    }

    /// Writes the image as a PNG, atomically.
    pub fn write_png(&self, path: &Path) -> Result<(), OutputError> {
        crate::output::write_png(path, self.width, self.height, &self.rgb)
    }

    fn size(&self) -> String {
        format!("{}x{}", self.width, self.height)
    }
}

impl From<crate::Rendered> for Image {
    fn from(rendered: crate::Rendered) -> Image {
        Image {
            width: rendered.width,
            height: rendered.height,
            rgb: rendered.rgb,
        }
    }
}

/// When two images count as the same.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Criteria {
    /// A pixel is over the threshold when one of its channels differs by
    /// more than this many 8-bit levels.
    pub threshold: u8,
    /// The percentage (0 to 100) of pixels that may be over the threshold.
    pub allowed_percent: f64,
}

impl Default for Criteria {
    /// Two levels absorb last-digit rounding of the sRGB encoding; no pixel
    /// may be over them.
    fn default() -> Criteria {
        Criteria {
            threshold: 2,
            allowed_percent: 0.0,
        }
    }
}

/// The numbers that summarise how two images differ (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Metrics {
    pub width: u32,
    pub height: u32,
    pub max: u8,
    /// The first pixel (in reading order) with the `max` difference, if any differs.
    pub max_at: Option<(u32, u32)>,
    pub mean: f64,
    pub rmse: f64,
    /// Infinite when the images are identical (`null` in JSON, which has
    /// no infinity).
    #[serde(with = "infinite_as_null")]
    pub psnr_db: f64,
    pub pixels_over: u64,
    pub pixels: u64,
}

impl Metrics {
    /// The percentage of pixels over the threshold.
    pub fn percent_over(&self) -> f64 {
        100.0 * self.pixels_over as f64 / self.pixels as f64
    }

    /// PSNR as text: `inf` for identical images, else dB with two decimals.
    pub fn psnr_text(&self) -> String {
        psnr_text(self.psnr_db)
    }
}

/// PSNR as text: `inf` when infinite, else two decimals.
pub fn psnr_text(psnr_db: f64) -> String {
    if psnr_db.is_infinite() {
        "inf".into()
    } else {
        format!("{psnr_db:.2}")
    }
}

/// Two images compared: the metrics, and each pixel's difference.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Comparison {
    pub metrics: Metrics,
    pub criteria: Criteria,
    /// Each pixel's largest channel difference, row by row (not kept in a
    /// grading job's result file).
    #[serde(skip)]
    pub pixel_differences: Vec<u8>,
}

/// An `f64` that may be infinite, as JSON: `null` for infinity.
mod infinite_as_null {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(value: &f64, serializer: S) -> Result<S::Ok, S::Error> {
        if value.is_infinite() {
            serializer.serialize_none()
        } else {
            serializer.serialize_some(value)
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(deserializer)?.unwrap_or(f64::INFINITY))
    }
}

/// Compares two images of the same size. The error names both sizes;
/// `names` says what to call the two images in it.
pub fn compare(
    a: &Image,
    b: &Image,
    criteria: Criteria,
    names: (&str, &str),
) -> Result<Comparison, DiffError> {
    same_size(
        ((a.width, a.height), a.rgb.len()),
        ((b.width, b.height), b.rgb.len()),
        (a.size(), b.size()),
        names,
    )?;
    Ok(compare_pixels(&a.rgb, &b.rgb, a.width, criteria))
}

/// Whether two images, each `((width, height), values)` with 3 values a
/// pixel, have the same size and at least one pixel, whatever their
/// pixels' type; the error names both `sizes` as shown and the images by
/// `names`.
pub(crate) fn same_size(
    a: ((u32, u32), usize),
    b: ((u32, u32), usize),
    sizes: (String, String),
    names: (&str, &str),
) -> Result<(), DiffError> {
    let names = || (names.0.to_string(), names.1.to_string());
    if a.0 != b.0 {
        return Err(DiffError::SizeMismatch {
            names: names(),
            sizes,
        });
    }
    let pixels = u64::from(a.0.0) * u64::from(a.0.1);
    if pixels == 0 || a.1 as u64 != 3 * pixels || b.1 != a.1 {
        return Err(DiffError::NoPixels { names: names() });
    }
    Ok(())
}

/// Compares two RGB8 buffers of the same length, `width` pixels a row (the
/// caller checks the sizes). `raylab cost` measures its errors with this too.
pub fn compare_pixels(a: &[u8], b: &[u8], width: u32, criteria: Criteria) -> Comparison {
    let pixels = (a.len().min(b.len()) / 3) as u64;
    let mut pixel_differences = Vec::with_capacity(pixels as usize);
    let (mut sum, mut sum_squares) = (0u64, 0u64);
    let (mut max, mut max_index, mut pixels_over) = (0u8, None, 0u64);
    for (index, (pa, pb)) in a.chunks_exact(3).zip(b.chunks_exact(3)).enumerate() {
        let mut largest = 0u8;
        for (&ca, &cb) in pa.iter().zip(pb) {
            let d = ca.abs_diff(cb);
            sum += u64::from(d);
            sum_squares += u64::from(d) * u64::from(d);
            largest = largest.max(d);
        }
        if largest > max {
            max = largest;
            max_index = Some(index as u64);
        }
        if largest > criteria.threshold {
            pixels_over += 1;
        }
        pixel_differences.push(largest);
    }
    // Integer sums are exact; only the final divisions round.
    let values = (3 * pixels).max(1) as f64;
    let mean = sum as f64 / values;
    let rmse = (sum_squares as f64 / values).sqrt();
    let psnr_db = if sum_squares == 0 {
        f64::INFINITY
    } else {
        20.0 * (255.0 / rmse).log10()
    };
    let row = u64::from(width.max(1));
    Comparison {
        metrics: Metrics {
            width,
            height: (pixels / row) as u32,
            max,
            max_at: max_index.map(|i| ((i % row) as u32, (i / row) as u32)),
            mean,
            rmse,
            psnr_db,
            pixels_over,
            pixels,
        },
        criteria,
        pixel_differences,
    }
}

impl Comparison {
    /// Whether the share of pixels over the threshold is within the allowance.
    pub fn passes(&self) -> bool {
        self.metrics.pixels_over as f64
            <= self.criteria.allowed_percent / 100.0 * self.metrics.pixels as f64
    }

    /// The metrics as JSON. JSON has no infinity: `psnr_db` is `null` for
    /// identical images.
    pub fn json(&self) -> serde_json::Value {
        let m = &self.metrics;
        serde_json::json!({
            "width": m.width,
            "height": m.height,
            "max_abs_difference": m.max,
            "max_at": m.max_at.map(|(x, y)| serde_json::json!({"x": x, "y": y})),
            "mean_abs_difference": m.mean,
            "rmse": m.rmse,
            "psnr_db": m.psnr_db.is_finite().then_some(m.psnr_db),
            "threshold": self.criteria.threshold,
            "allowed_percent": self.criteria.allowed_percent,
            "pixels_over_threshold": m.pixels_over,
            "pixels": m.pixels,
            "percent_over_threshold": m.percent_over(),
            "pass": self.passes(),
        })
    }

    /// The metrics as the lines `raylab diff` prints.
    pub fn report_text(&self) -> String {
        let m = &self.metrics;
        let at = m
            .max_at
            .map(|(x, y)| format!(" (first at x={x}, y={y})"))
            .unwrap_or_default();
        format!(
            "size: {}x{}\n\
             max abs difference: {}{at}\n\
             mean abs difference: {:.6}\n\
             RMSE: {:.6}\n\
             PSNR: {} dB\n\
             pixels over threshold {}: {} of {} ({:.4}%, allowed {}%)\n\
             result: {}\n",
            m.width,
            m.height,
            m.max,
            m.mean,
            m.rmse,
            m.psnr_text(),
            self.criteria.threshold,
            m.pixels_over,
            m.pixels,
            m.percent_over(),
            self.criteria.allowed_percent,
            if self.passes() { "PASS" } else { "FAIL" },
        )
    }

    /// The false-colour heatmap (see [`heatmap`]).
    pub fn heatmap(&self, base: &Image) -> Result<Image, DiffError> {
        heatmap(self, base)
    }
}

/// Colour stops of the heatmap scale, from the smallest difference to the
/// largest. All are saturated, so none can be mistaken for the grey of
/// identical pixels.
const SCALE: [(f64, [u8; 3]); 5] = [
    (0.00, [40, 20, 170]),
    (0.25, [0, 110, 255]),
    (0.50, [0, 200, 110]),
    (0.75, [255, 210, 0]),
    (1.00, [255, 0, 0]),
];

/// The scale's colour at `t` in 0..=1 (0: smallest, 1: largest difference).
pub fn scale_colour(t: f64) -> [u8; 3] {
    let t = t.clamp(0.0, 1.0);
    for pair in SCALE.windows(2) {
        let ((t0, c0), (t1, c1)) = (pair[0], pair[1]);
        if t <= t1 {
            let f = (t - t0) / (t1 - t0);
            return std::array::from_fn(|i| {
                (f64::from(c0[i]) + f * (f64::from(c1[i]) - f64::from(c0[i]))).round() as u8
            });
        }
    }
    SCALE[SCALE.len() - 1].1
}

/// The colour of the largest difference in a heatmap.
pub const HOTTEST: [u8; 3] = SCALE[SCALE.len() - 1].1;

/// The legend strip's height for an image `width` pixels wide.
pub fn legend_height(width: u32) -> u32 {
    LEGEND_ROWS * legend_scale(width)
}

const LEGEND_ROWS: u32 = 17;

/// Legend text and bar grow with the image so they stay legible when a
/// large heatmap is viewed scaled down.
fn legend_scale(width: u32) -> u32 {
    (width / 120).clamp(1, 4)
}

/// Draws where two images differ. Identical pixels show the base image in
/// dim grey (so the scene stays recognisable); differing pixels take the
/// colour of their difference on a scale from 1 level (dark blue) to the
/// largest difference in the image (red, [`HOTTEST`]). Below the image, a
/// legend strip shows the scale as a bar labelled `0` and the largest
/// difference, with a white tick where the threshold falls.
///
/// `base` must be the size the comparison measured, and that size within
/// [`crate::input::check_image_size`]: the heatmap then takes the image's
/// memory plus a legend of at most 68 rows (3.3 MB at the widest), never
/// more. Anything else is an error naming the sizes.
pub fn heatmap(comparison: &Comparison, base: &Image) -> Result<Image, DiffError> {
    let m = &comparison.metrics;
    let (width, image_height) = (m.width, m.height);
    let pixels = u64::from(width) * u64::from(image_height);
    if (base.width, base.height) != (width, image_height)
        || base.rgb.len() as u64 != 3 * pixels
        || comparison.pixel_differences.len() as u64 != pixels
    {
        return Err(DiffError::HeatmapMismatch {
            width,
            height: image_height,
            differences: comparison.pixel_differences.len(),
            base_size: base.size(),
            base_bytes: base.rgb.len(),
        });
    }
    crate::input::check_image_size(width, image_height).map_err(DiffError::HeatmapTooLarge)?;
    let height = image_height + legend_height(width);
    let mut canvas = Canvas {
        width,
        height,
        rgb: vec![24; width as usize * height as usize * 3],
    };
    let top = f64::from(m.max.max(1));
    for (index, &d) in comparison.pixel_differences.iter().enumerate() {
        let colour = if d == 0 {
            let p = &base.rgb[3 * index..3 * index + 3];
            let luma =
                (299 * u32::from(p[0]) + 587 * u32::from(p[1]) + 114 * u32::from(p[2])) / 1000;
            [(luma / 4) as u8; 3]
        } else {
            scale_colour(f64::from(d) / top)
        };
        canvas.rgb[3 * index..3 * index + 3].copy_from_slice(&colour);
    }
    draw_legend(
        &mut canvas,
        image_height,
        m.max,
        comparison.criteria.threshold,
    );
    Ok(Image {
        width,
        height,
        rgb: canvas.rgb,
    })
}

struct Canvas {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Canvas {
    /// Sets a pixel; pixels outside the canvas are ignored (legends of very
    /// narrow images are clipped, never out of bounds).
    fn set(&mut self, x: i64, y: i64, colour: [u8; 3]) {
        if x >= 0 && y >= 0 && x < i64::from(self.width) && y < i64::from(self.height) {
            let i = 3 * (y as usize * self.width as usize + x as usize);
            self.rgb[i..i + 3].copy_from_slice(&colour);
        }
    }

    fn fill(&mut self, x: i64, y: i64, w: i64, h: i64, colour: [u8; 3]) {
        for yy in y..y + h {
            for xx in x..x + w {
                self.set(xx, yy, colour);
            }
        }
    }

    /// Draws decimal digits with the 3x5 font, each dot `scale` pixels wide.
    fn digits(&mut self, x: i64, y: i64, text: &str, scale: i64, colour: [u8; 3]) {
        for (n, c) in text.chars().enumerate() {
            let Some(glyph) = c.to_digit(10).map(|d| DIGITS[d as usize]) else {
                continue;
            };
            let left = x + n as i64 * 4 * scale;
            for row in 0..5 {
                for col in 0..3 {
                    if glyph >> (14 - (row * 3 + col)) & 1 == 1 {
                        self.fill(left + col * scale, y + row * scale, scale, scale, colour);
                    }
                }
            }
        }
    }
}

/// Width in pixels of `text` in the 3x5 font at `scale`.
fn text_width(text: &str, scale: i64) -> i64 {
    (text.chars().count() as i64 * 4 - 1) * scale
}

/// A 3x5 bitmap font for 0-9: five rows of three bits, top row first.
const DIGITS: [u16; 10] = [
    0b111_101_101_101_111,
    0b010_110_010_010_111,
    0b111_001_111_100_111,
    0b111_001_111_001_111,
    0b101_101_111_001_001,
    0b111_100_111_001_111,
    0b111_100_111_101_111,
    0b111_001_001_001_001,
    0b111_101_111_101_111,
    0b111_101_111_001_111,
];

fn draw_legend(canvas: &mut Canvas, top: u32, max: u8, threshold: u8) {
    let s = i64::from(legend_scale(canvas.width));
    let width = i64::from(canvas.width);
    let (bar_left, bar_right) = (2 * s, width - 2 * s - 1);
    let bar_top = i64::from(top) + 2 * s;
    let bar_width = (bar_right - bar_left).max(1);
    for x in bar_left..=bar_right {
        let t = (x - bar_left) as f64 / bar_width as f64;
        canvas.fill(x, bar_top, 1, 6 * s, scale_colour(t));
    }
    // The threshold's place on the bar: pixels left of the tick are within it.
    if threshold > 0 && threshold < max {
        let x =
            bar_left + (f64::from(threshold) / f64::from(max) * bar_width as f64).round() as i64;
        canvas.fill(x, bar_top - s, s, 8 * s, [255, 255, 255]);
    }
    let label_top = bar_top + 8 * s;
    let white = [230, 230, 230];
    canvas.digits(bar_left, label_top, "0", s, white);
    // The bar's right end is the largest difference (1 when none differ,
    // matching the colour scale of `heatmap`).
    let max_label = max.max(1).to_string();
    canvas.digits(
        bar_right + 1 - text_width(&max_label, s),
        label_top,
        &max_label,
        s,
        white,
    );
}

/// Writes `image` as a PNG at `path` atomically, with a clear error.
pub fn write_heatmap(image: &Image, path: &Path) -> Result<(), OutputError> {
    image.write_png(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every colour type and depth a PNG may have decodes to the RGB that
    /// `image`'s own PNG reader gives (palettes expanded, grey spread to
    /// three channels, alpha dropped, 16 bits rounded to 8).
    #[test]
    fn every_png_layout_decodes_as_image_decodes_it() {
        let (width, height) = (5u32, 3u32);
        let samples = |channels: usize, depth: usize| -> Vec<u8> {
            (0..width as usize * height as usize * channels * depth)
                .map(|i| (i * 37 % 251) as u8)
                .collect()
        };
        let layouts = [
            (png::ColorType::Grayscale, png::BitDepth::Eight, 1, 1),
            (png::ColorType::Grayscale, png::BitDepth::Sixteen, 1, 2),
            (png::ColorType::GrayscaleAlpha, png::BitDepth::Eight, 2, 1),
            (png::ColorType::Rgb, png::BitDepth::Eight, 3, 1),
            (png::ColorType::Rgb, png::BitDepth::Sixteen, 3, 2),
            (png::ColorType::Rgba, png::BitDepth::Sixteen, 4, 2),
            (png::ColorType::Indexed, png::BitDepth::Eight, 1, 1),
        ];
        for (color, depth, channels, bytes) in layouts {
            let mut file = Vec::new();
            let mut encoder = png::Encoder::new(&mut file, width, height);
            encoder.set_color(color);
            encoder.set_depth(depth);
            let mut data = samples(channels, bytes);
            if color == png::ColorType::Indexed {
                encoder.set_palette(
                    (0..=255u8)
                        .flat_map(|i| [i, 255 - i, i / 2])
                        .collect::<Vec<_>>(),
                );
                data.iter_mut().for_each(|index| *index %= 200);
            }
            let mut writer = encoder.write_header().expect("header");
            writer.write_image_data(&data).expect("pixels");
            writer.finish().expect("end");
            let ours = Image::decode_png(&file).expect("decodes");
            let theirs = image::load_from_memory(&file)
                .expect("image decodes")
                .into_rgb8();
            assert_eq!(ours.rgb, theirs.into_raw(), "{color:?} {depth:?}");
        }
    }

    fn flat(width: u32, height: u32, value: u8) -> Image {
        Image {
            width,
            height,
            rgb: vec![value; (width * height * 3) as usize],
        }
    }

    #[test]
    fn scale_runs_from_blue_to_red_through_its_stops() {
        assert_eq!(scale_colour(0.0), [40, 20, 170]);
        assert_eq!(scale_colour(0.5), [0, 200, 110]);
        assert_eq!(scale_colour(1.0), HOTTEST);
        assert_eq!(scale_colour(7.0), HOTTEST);
        // Half-way between the first two stops.
        assert_eq!(scale_colour(0.125), [20, 65, 213]);
    }

    #[test]
    fn threshold_is_strict_and_allowance_is_a_share_of_pixels() {
        let a = flat(10, 10, 100);
        let mut b = a.clone();
        b.rgb[0] = 103; // one pixel 3 levels off
        b.rgb[4] = 102; // another exactly at the threshold of 2
        let strict = compare(&a, &b, Criteria::default(), ("a", "b")).unwrap();
        assert_eq!(strict.metrics.pixels_over, 1);
        assert!(!strict.passes());
        let one_percent = Criteria {
            allowed_percent: 1.0,
            ..Criteria::default()
        };
        assert!(compare(&a, &b, one_percent, ("a", "b")).unwrap().passes());
        let loose = Criteria {
            threshold: 3,
            ..Criteria::default()
        };
        assert!(compare(&a, &b, loose, ("a", "b")).unwrap().passes());
    }

    #[test]
    fn digits_are_drawn_in_bounds_even_on_tiny_images() {
        let a = flat(3, 1, 0);
        let mut b = a.clone();
        b.rgb[8] = 255;
        let comparison = compare(&a, &b, Criteria::default(), ("a", "b")).unwrap();
        let map = heatmap(&comparison, &a).unwrap();
        assert_eq!((map.width, map.height), (3, 1 + legend_height(3)));
        assert_eq!(&map.rgb[6..9], &HOTTEST);
    }

    #[test]
    fn sizes_must_match() {
        let error = compare(
            &flat(2, 2, 0),
            &flat(2, 3, 0),
            Criteria::default(),
            ("a.png", "b.png"),
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            error,
            "a.png is 2x2 but b.png is 2x3: only images of the same size can be compared"
        );
    }

    #[test]
    fn not_a_png_and_a_truncated_png_are_told_apart() {
        let text = Image::decode_png(b"hello").unwrap_err().to_string();
        assert!(text.starts_with("not a PNG file"), "{text}");
        let png = flat(4, 4, 9).encode_png().unwrap();
        let truncated = Image::decode_png(&png[..png.len() / 2])
            .unwrap_err()
            .to_string();
        assert!(truncated.starts_with("corrupted PNG"), "{truncated}");
        assert_eq!(Image::decode_png(&png).unwrap(), flat(4, 4, 9));
    }
}
