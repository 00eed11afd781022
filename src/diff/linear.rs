//! Comparing two OpenEXR renders in linear light: the radiance itself,
//! before any clamp, tone curve or 8-bit rounding.
//!
//! Image B is the reference. Over all `3 * width * height` channel values:
//!
//! - *max* and *mean*: the largest and the mean absolute difference `|a - b|`,
//!   in the images' own linear units;
//! - *RMSE*: the root of the mean of `(a - b)^2`, in the same units;
//! - *relative MSE*: the mean of `(a - b)^2 / (b^2 + 0.01)`, the usual
//!   measure of a Monte Carlo render's error (its `0.01` keeps black
//!   pixels from dividing by zero);
//! - *mean relative error*: the mean of `|a - b| / (|b| + 0.01)`;
//! - a pixel is *over* the tolerance when one of its channels' relative
//!   error `|a - b| / (|b| + 0.01)` exceeds it (strictly).
//!
//! Two images pass when the share of pixels over the tolerance is at most
//! the allowed percentage, as for PNGs.

use std::path::Path;

use super::DiffError;

/// What keeps a black reference pixel from dividing by zero: added to `b^2`
/// in the relative MSE and to `|b|` in the relative error.
pub const RELATIVE_FLOOR: f64 = 0.01;

/// The largest OpenEXR file read, in bytes: 16 bytes a pixel (32-bit RGBA,
/// uncompressed) and a sixteenth more for the file's own tables.
pub const MAX_EXR_FILE_BYTES: u64 =
    16 * crate::input::MAX_IMAGE_PIXELS + 16 * crate::input::MAX_IMAGE_PIXELS / 16;

/// The most layers, and channels in a layer, of an OpenEXR file read:
/// raylab writes one layer of R, G and B; the decoder holds every channel
/// of a layer in memory (a 1 MB file of 1,000 channels took 2 GB).
pub const MAX_EXR_CHANNELS: usize = 16;

/// The most attributes, in all its headers, of an OpenEXR file read:
/// raylab writes about ten; the decoder holds every one in memory at a
/// hundred times its size (a 40 MB file of small attributes took 4.9 GB
/// and 46 s before its layers could be counted).
pub const MAX_EXR_ATTRIBUTES: usize = 1024;

/// The most bytes of headers an OpenEXR file read may have: a list of a
/// million empty strings (4 MB) took 137 MB to decode. Room for a
/// preview image of 1024x1024.
pub const MAX_EXR_HEADER_BYTES: usize = 4 << 20;

/// The most bytes one block of an OpenEXR file (a tile, or a run of scan
/// lines) may hold decoded: the decoder inflates a whole block, every
/// channel, at once, and a tile may be the whole image (a 2.5 MB file of
/// one tile took 6 GB). Tiles of 64 x 64 of 16 channels take 256 KB;
/// raylab's own files, runs of 16 lines of 3, 192 bytes a pixel of width.
pub const MAX_EXR_BLOCK_BYTES: u64 = 64 << 20;

/// What one block of `header`'s layer holds decoded, at most: a tile's
/// pixels, or a run of scan lines as long as its compression reads at
/// once, times the bytes of a pixel of every channel. Worked out in `u64`
/// without overflow, whatever sizes the file declares.
fn exr_block_bytes(header: &exr::meta::header::Header) -> u64 {
    let pixels = match header.blocks {
        exr::meta::BlockDescription::Tiles(tiles) => {
            (tiles.tile_size.width() as u64).saturating_mul(tiles.tile_size.height() as u64)
        }
        exr::meta::BlockDescription::ScanLines => (header.compression.scan_lines_per_block()
            as u64)
            .saturating_mul(header.layer_size.width() as u64),
    };
    pixels.saturating_mul(header.channels.bytes_per_pixel as u64)
}

/// Whether raylab decodes OpenEXR blocks compressed with `compression`.
/// Not RLE, whose decoder reads on while its runs have not landed exactly
/// on the block's size (a 50 MB file took 6.4 GB), nor DWAA and DWAB, whose
/// decoder sizes its buffers by counts the block itself declares (a file of
/// 431 bytes asked for 4 EiB). The others decode within the block's size.
fn exr_compression_read(compression: exr::compression::Compression) -> bool {
    use exr::compression::Compression;
    matches!(
        compression,
        Compression::Uncompressed
            | Compression::ZIP1
            | Compression::ZIP16
            | Compression::PIZ
            | Compression::PXR24
            | Compression::B44
            | Compression::B44A
    )
}

/// How far the headers of `bytes` (an OpenEXR file, magic number and
/// version first) reach, read without keeping any attribute: their
/// attributes counted up to `most + 1`, and the offset they end at (or
/// had reached past [`MAX_EXR_HEADER_BYTES`]); or, where the scan cannot
/// read them to their end as the decoder would, the offset and why.
///
/// Each attribute is a name and a type name, each ended by a zero byte, a
/// 4-byte little-endian size and that many bytes; a header ends with an
/// empty name, and a multi-part file's headers end with an empty header.
/// The decoder takes a text's first byte whatever it is and reads on to a
/// zero byte, up to 32 bytes (256 with the long-names flag): the scan
/// follows the same rules, and refuses what the decoder would read
/// differently from a well-formed file (an empty type name, whose zero the
/// decoder takes as its first byte) rather than stop early and leave the
/// rest to the decoder unbounded.
fn exr_headers_extent(bytes: &[u8], most: usize) -> Result<(usize, usize), (usize, &'static str)> {
    const LONG_NAMES: u32 = 0x400;
    const MULTIPART: u32 = 0x1000;
    let Some(version) = bytes.get(4..8).and_then(|word| word.try_into().ok()) else {
        return Err((bytes.len(), "the file ends before its version"));
    };
    let version = u32::from_le_bytes(version);
    let multipart = version & MULTIPART != 0;
    let longest = if version & LONG_NAMES != 0 { 256 } else { 32 };
    let mut at = 8;
    let mut count = 0;
    // A text starting at `from`: the offset just past its ending zero.
    let text = |from: usize, what: &'static str| -> Result<usize, (usize, &'static str)> {
        match bytes.get(from) {
            None => return Err((from, "the file ends inside its headers")),
            Some(0) => return Err((from, what)),
            Some(_) => {}
        }
        let rest = bytes.get(from + 1..).unwrap_or_default();
        match rest.iter().take(longest).position(|&byte| byte == 0) {
            Some(length) => Ok(from + 1 + length + 1),
            None if rest.len() < longest => Err((from, "the file ends inside its headers")),
            None => Err((
                from,
                "an attribute's name or type is longer than the decoder reads",
            )),
        }
    };
    loop {
        // An empty name ends a header; in a multi-part file, an empty
        // header (a second zero byte at once) ends them all.
        match bytes.get(at) {
            None => return Err((at, "the file ends inside its headers")),
            Some(0) => {
                at += 1;
                if !multipart || bytes.get(at) == Some(&0) {
                    return Ok((count, at));
                }
                continue;
            }
            Some(_) => {}
        }
        let type_at = text(at, "an attribute's name is empty")?;
        let size_at = text(type_at, "an attribute's type name is empty")?;
        let Some(size) = bytes
            .get(size_at..size_at + 4)
            .and_then(|word| word.try_into().ok())
            .map(i32::from_le_bytes)
        else {
            return Err((size_at, "the file ends inside its headers"));
        };
        let Ok(size) = usize::try_from(size) else {
            return Err((size_at, "an attribute's size is negative"));
        };
        count += 1;
        at = size_at + 4 + size;
        if count > most || at > MAX_EXR_HEADER_BYTES {
            return Ok((count, at));
        }
    }
}

/// A linear RGB image: 3 finite `f32`s a pixel, row by row from the top.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearImage {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<f32>,
}

impl LinearImage {
    /// Reads an OpenEXR file's R, G and B channels as 32-bit floats
    /// (half-float and integer channels are converted, an alpha channel is
    /// ignored). Errors name the file: missing, not a regular file, too
    /// large, not an OpenEXR file, damaged, without R, G and B, or holding
    /// a NaN or an infinity (no error can be measured against one).
    pub fn load_exr(path: &Path) -> Result<LinearImage, DiffError> {
        let bytes = crate::input::read_bounded(
            path,
            MAX_EXR_FILE_BYTES,
            "OpenEXR image",
            crate::input::Links::Follow,
        )?;
        LinearImage::decode_exr(&bytes).map_err(|error| DiffError::InFile {
            path: path.to_path_buf(),
            error: Box::new(error),
        })
    }

    /// Decodes OpenEXR bytes (see [`LinearImage::load_exr`]). Every layer's
    /// declared size is checked against [`crate::input::check_image_size`]
    /// before any pixel is decoded: a small file can declare a huge image.
    pub fn decode_exr(bytes: &[u8]) -> Result<LinearImage, DiffError> {
        use exr::prelude::ReadChannels;
        use exr::prelude::ReadLayers;
        if !bytes.starts_with(&crate::output::EXR_MAGIC) {
            return Err(DiffError::NotExr);
        }
        let (attributes, headers_end) = exr_headers_extent(bytes, MAX_EXR_ATTRIBUTES)
            .map_err(|(at, why)| DiffError::ExrHeaderUnreadable { at, why })?;
        if attributes > MAX_EXR_ATTRIBUTES {
            return Err(DiffError::ExrTooWide {
                what: "header attributes or more",
                count: attributes,
                most: MAX_EXR_ATTRIBUTES,
            });
        }
        if headers_end > MAX_EXR_HEADER_BYTES {
            return Err(DiffError::ExrHeaderTooLarge {
                most: MAX_EXR_HEADER_BYTES,
            });
        }
        let meta = exr::meta::MetaData::read_from_buffered(bytes, false)
            .map_err(DiffError::CorruptedExr)?;
        let too_wide = |what, count| DiffError::ExrTooWide {
            what,
            count,
            most: MAX_EXR_CHANNELS,
        };
        if meta.headers.len() > MAX_EXR_CHANNELS {
            return Err(too_wide("layers", meta.headers.len()));
        }
        for header in &meta.headers {
            if header.channels.list.len() > MAX_EXR_CHANNELS {
                return Err(too_wide("channels", header.channels.list.len()));
            }
            let side = |length: usize| u32::try_from(length).unwrap_or(u32::MAX);
            crate::input::check_image_size(
                side(header.layer_size.width()),
                side(header.layer_size.height()),
            )?;
            if !exr_compression_read(header.compression) {
                return Err(DiffError::ExrCompressionNotRead {
                    compression: header.compression.to_string(),
                });
            }
            let block_bytes = exr_block_bytes(header);
            if block_bytes > MAX_EXR_BLOCK_BYTES {
                return Err(DiffError::ExrBlockTooLarge {
                    bytes: block_bytes,
                    most: MAX_EXR_BLOCK_BYTES,
                });
            }
        }
        let read = exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .rgb_channels(
                |size, _channels| (size.width(), vec![0f32; 3 * size.area()]),
                |(width, values): &mut (usize, Vec<f32>),
                 position: exr::prelude::Vec2<usize>,
                 (r, g, b): (f32, f32, f32)| {
                    let at = 3 * (position.y() * *width + position.x());
                    if let Some(pixel) = values.get_mut(at..at + 3) {
                        pixel.copy_from_slice(&[r, g, b]);
                    }
                },
            )
            .first_valid_layer()
            .all_attributes()
            .from_buffered(std::io::Cursor::new(bytes))
            .map_err(DiffError::CorruptedExr)?;
        let size = read.layer_data.size;
        let (_, rgb) = read.layer_data.channel_data.pixels;
        let side = |length: usize| u32::try_from(length).unwrap_or(u32::MAX);
        let image = LinearImage {
            width: side(size.width()),
            height: side(size.height()),
            rgb,
        };
        if let Some(index) = image.rgb.iter().position(|value| !value.is_finite()) {
            let pixel = (index / 3) as u64;
            let row = u64::from(image.width.max(1));
            return Err(DiffError::NotFinite {
                x: (pixel % row) as u32,
                y: (pixel / row) as u32,
                channel: ["R", "G", "B"][index % 3],
                value: image.rgb[index],
            });
        }
        Ok(image)
    }

    pub(super) fn size(&self) -> String {
        format!("{}x{}", self.width, self.height)
    }
}

/// When two linear images count as the same.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearCriteria {
    /// A pixel is over when one of its channels' relative error
    /// `|a - b| / (|b| + 0.01)` exceeds this.
    pub tolerance: f64,
    /// The percentage (0 to 100) of pixels that may be over.
    pub allowed_percent: f64,
}

impl Default for LinearCriteria {
    /// One percent absorbs the last digits of float arithmetic done in
    /// another order (another renderer, another machine); no pixel may be
    /// over it.
    fn default() -> LinearCriteria {
        LinearCriteria {
            tolerance: 0.01,
            allowed_percent: 0.0,
        }
    }
}

/// The numbers that summarise how two linear images differ (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearMetrics {
    pub width: u32,
    pub height: u32,
    pub max: f64,
    /// The first pixel (in reading order) with the `max` difference, if any differs.
    pub max_at: Option<(u32, u32)>,
    pub mean: f64,
    pub rmse: f64,
    pub relative_mse: f64,
    pub mean_relative: f64,
    pub pixels_over: u64,
    pub pixels: u64,
}

/// Two linear images compared.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearComparison {
    pub metrics: LinearMetrics,
    pub criteria: LinearCriteria,
}

/// Compares two linear images of the same size, `b` the reference. The
/// error names both sizes; `names` says what to call the images in it.
pub fn compare_linear(
    a: &LinearImage,
    b: &LinearImage,
    criteria: LinearCriteria,
    names: (&str, &str),
) -> Result<LinearComparison, DiffError> {
    super::same_size(
        ((a.width, a.height), a.rgb.len()),
        ((b.width, b.height), b.rgb.len()),
        (a.size(), b.size()),
        names,
    )?;
    Ok(compare_linear_values(&a.rgb, &b.rgb, a.width, criteria))
}

/// Compares two linear RGB buffers of the same length, `width` pixels a row
/// (the caller checks the sizes), `b` the reference. Sums are in `f64`, so
/// a million small differences are not lost against a large one.
pub fn compare_linear_values(
    a: &[f32],
    b: &[f32],
    width: u32,
    criteria: LinearCriteria,
) -> LinearComparison {
    let pixels = (a.len().min(b.len()) / 3) as u64;
    let (mut sum, mut sum_squares, mut sum_relative_squares, mut sum_relative) =
        (0f64, 0f64, 0f64, 0f64);
    let (mut max, mut max_index, mut pixels_over) = (0f64, None, 0u64);
    for (index, (pa, pb)) in a.chunks_exact(3).zip(b.chunks_exact(3)).enumerate() {
        let (mut largest, mut over) = (0f64, false);
        for (&ca, &cb) in pa.iter().zip(pb) {
            let (ca, cb) = (f64::from(ca), f64::from(cb));
            let d = (ca - cb).abs();
            let relative = d / (cb.abs() + RELATIVE_FLOOR);
            sum += d;
            sum_squares += d * d;
            sum_relative_squares += d * d / (cb * cb + RELATIVE_FLOOR);
            sum_relative += relative;
            largest = largest.max(d);
            over |= relative > criteria.tolerance;
        }
        if largest > max {
            max = largest;
            max_index = Some(index as u64);
        }
        if over {
            pixels_over += 1;
        }
    }
    let values = (3 * pixels).max(1) as f64;
    let row = u64::from(width.max(1));
    LinearComparison {
        metrics: LinearMetrics {
            width,
            height: (pixels / row) as u32,
            max,
            max_at: max_index.map(|i| ((i % row) as u32, (i / row) as u32)),
            mean: sum / values,
            rmse: (sum_squares / values).sqrt(),
            relative_mse: sum_relative_squares / values,
            mean_relative: sum_relative / values,
            pixels_over,
            pixels,
        },
        criteria,
    }
}

impl LinearComparison {
    /// Whether the share of pixels over the tolerance is within the allowance.
    pub fn passes(&self) -> bool {
        self.metrics.pixels_over as f64
            <= self.criteria.allowed_percent / 100.0 * self.metrics.pixels as f64
    }

    /// The percentage of pixels over the tolerance.
    pub fn percent_over(&self) -> f64 {
        100.0 * self.metrics.pixels_over as f64 / self.metrics.pixels.max(1) as f64
    }

    /// The metrics as JSON (`"light": "linear"` tells them from a PNG
    /// comparison's 8-bit levels).
    pub fn json(&self) -> serde_json::Value {
        let m = &self.metrics;
        serde_json::json!({
            "light": "linear",
            "width": m.width,
            "height": m.height,
            "max_abs_difference": m.max,
            "max_at": m.max_at.map(|(x, y)| serde_json::json!({"x": x, "y": y})),
            "mean_abs_difference": m.mean,
            "rmse": m.rmse,
            "relative_mse": m.relative_mse,
            "mean_relative_error": m.mean_relative,
            "tolerance": self.criteria.tolerance,
            "allowed_percent": self.criteria.allowed_percent,
            "pixels_over_tolerance": m.pixels_over,
            "pixels": m.pixels,
            "percent_over_tolerance": self.percent_over(),
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
            "size: {}x{} (OpenEXR, linear light; B is the reference)\n\
             max abs difference: {:.6e}{at}\n\
             mean abs difference: {:.6e}\n\
             RMSE: {:.6e}\n\
             relative MSE: {:.6e}\n\
             mean relative error: {:.6e}\n\
             pixels over relative tolerance {}: {} of {} ({:.4}%, allowed {}%)\n\
             result: {}\n",
            m.width,
            m.height,
            m.max,
            m.mean,
            m.rmse,
            m.relative_mse,
            m.mean_relative,
            self.criteria.tolerance,
            m.pixels_over,
            m.pixels,
            self.percent_over(),
            self.criteria.allowed_percent,
            if self.passes() { "PASS" } else { "FAIL" },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(width: u32, height: u32, value: f32) -> LinearImage {
        LinearImage {
            width,
            height,
            rgb: vec![value; (width * height * 3) as usize],
        }
    }

    #[test]
    fn differences_above_white_count_in_linear_light() {
        // 5 and 10 are both white on a screen: the same sRGB code 255.
        let (a, b) = (flat(2, 2, 5.0), flat(2, 2, 10.0));
        let compared =
            compare_linear(&a, &b, LinearCriteria::default(), ("a", "b")).expect("same size");
        assert_eq!(compared.metrics.mean, 5.0);
        assert_eq!(compared.metrics.rmse, 5.0);
        assert!((compared.metrics.relative_mse - 25.0 / 100.01).abs() < 1e-12);
        assert_eq!(compared.metrics.pixels_over, 4);
        assert!(!compared.passes());
    }

    #[test]
    fn the_tolerance_is_relative_and_strict() {
        let b = flat(1, 1, 1.0);
        let mut a = b.clone();
        a.rgb[0] = 1.5;
        // Exactly at the tolerance is within it.
        let criteria = LinearCriteria {
            tolerance: 0.5 / (1.0 + RELATIVE_FLOOR),
            allowed_percent: 0.0,
        };
        let compared = compare_linear(&a, &b, criteria, ("a", "b")).expect("same size");
        assert_eq!(compared.metrics.pixels_over, 0, "{compared:?}");
        a.rgb[0] = 1.5f32.next_up();
        let compared = compare_linear(&a, &b, criteria, ("a", "b")).expect("same size");
        assert_eq!(compared.metrics.pixels_over, 1, "{compared:?}");
    }

    #[test]
    fn broken_exr_bytes_are_errors_not_panics() {
        let text = LinearImage::decode_exr(b"hello").unwrap_err().to_string();
        assert!(text.starts_with("not an OpenEXR file"), "{text}");
        let exr = crate::output::encode_exr(4, 3, &[0.25; 36]).expect("encodes");
        assert_eq!(
            LinearImage::decode_exr(&exr).expect("decodes"),
            flat(4, 3, 0.25)
        );
        for length in [4, 8, exr.len() / 2, exr.len() - 1] {
            let text = LinearImage::decode_exr(&exr[..length])
                .unwrap_err()
                .to_string();
            assert!(text.starts_with("corrupted OpenEXR"), "at {length}: {text}");
        }
    }

    /// Pass 13 of issue 41, finding 9: a 1 MB pair of files with 1,000
    /// extra channels each took 2 GB to compare. A layer of more channels
    /// than raylab reads is refused before a pixel is decoded.
    #[test]
    fn an_exr_of_many_channels_is_refused_before_it_is_decoded() {
        use exr::prelude::*;
        let exr_of = |count: usize| {
            let channels: Vec<AnyChannel<FlatSamples>> = (0..count)
                .map(|index| {
                    AnyChannel::new(
                        format!("channel{index:04}").as_str(),
                        FlatSamples::F32(vec![0.5; 4]),
                    )
                })
                .collect();
            let image = Image::from_channels((2, 2), AnyChannels::sort(channels.into()));
            let mut bytes = std::io::Cursor::new(Vec::new());
            image.write().to_buffered(&mut bytes).expect("writes");
            bytes.into_inner()
        };
        let text = LinearImage::decode_exr(&exr_of(MAX_EXR_CHANNELS + 1))
            .unwrap_err()
            .to_string();
        assert!(text.contains("17 channels"), "{text}");
        // At the most, the file is read (and found to have no R, G and B).
        let text = LinearImage::decode_exr(&exr_of(MAX_EXR_CHANNELS))
            .unwrap_err()
            .to_string();
        assert!(!text.contains("channels:"), "{text}");
    }

    /// Pass 15 of issue 41: a file of many small header attributes took
    /// 4.9 GB and 46 s to be found corrupted. Past the most raylab reads,
    /// it is refused before the decoder reads the header; the count reads
    /// raylab's own files right.
    #[test]
    fn an_exr_of_many_header_attributes_is_refused_before_it_is_decoded() {
        let exr = crate::output::encode_exr(2, 2, &[0.5; 12]).expect("encodes");
        let (own, _) = exr_headers_extent(&exr, MAX_EXR_ATTRIBUTES).expect("raylab's own file");
        assert!((5..=20).contains(&own), "{own} attributes");
        let with_extra = |extra: usize| {
            let mut bytes = exr[..8].to_vec();
            for index in 0..extra {
                bytes.extend(format!("a{index}\0int\0").as_bytes());
                bytes.extend(4u32.to_le_bytes());
                bytes.extend(7i32.to_le_bytes());
            }
            bytes.extend(&exr[8..]);
            bytes
        };
        let over = with_extra(MAX_EXR_ATTRIBUTES + 1 - own);
        assert_eq!(
            exr_headers_extent(&over, MAX_EXR_ATTRIBUTES).map(|(count, _)| count),
            Ok(MAX_EXR_ATTRIBUTES + 1)
        );
        let text = LinearImage::decode_exr(&over).unwrap_err().to_string();
        assert!(text.contains("header attributes"), "{text}");
        // At the most, the decoder reads it (and finds its offsets moved).
        let at_most = with_extra(MAX_EXR_ATTRIBUTES - own);
        assert_eq!(
            exr_headers_extent(&at_most, MAX_EXR_ATTRIBUTES).map(|(count, _)| count),
            Ok(MAX_EXR_ATTRIBUTES)
        );
        let text = LinearImage::decode_exr(&at_most).unwrap_err().to_string();
        assert!(!text.contains("header attributes"), "{text}");
        // A list of a million empty strings: one attribute of 4 MB.
        let mut long = exr[..8].to_vec();
        long.extend(b"names\0stringvector\0");
        long.extend((4u32 << 20).to_le_bytes());
        long.extend(vec![0u8; 4 << 20]);
        long.extend(&exr[8..]);
        let text = LinearImage::decode_exr(&long).unwrap_err().to_string();
        assert!(text.contains("headers of more than"), "{text}");
    }

    /// Pass 16 of issue 41: two ways to put the scan out of step with the
    /// decoder, so that it stopped early and the decoder read on through a
    /// million attributes (a 40 MB file took 4.9 GB). The scan now reads
    /// texts as the decoder does, and refuses what it cannot read to the end.
    #[test]
    fn headers_the_scan_would_read_apart_from_the_decoder_are_refused() {
        let exr = crate::output::encode_exr(2, 2, &[0.5; 12]).expect("encodes");
        let attributes = |bytes: &mut Vec<u8>, count: usize| {
            for index in 0..count {
                bytes.extend(format!("a{index}\0int\0").as_bytes());
                bytes.extend(4u32.to_le_bytes());
                bytes.extend(7i32.to_le_bytes());
            }
        };
        // A type name whose first byte is zero: the decoder takes that zero
        // as the name's first byte and reads on to the next.
        let mut empty_type = exr[..8].to_vec();
        empty_type.extend(b"x\0\0");
        empty_type.extend(16u32.to_le_bytes());
        attributes(&mut empty_type, 2 * MAX_EXR_ATTRIBUTES);
        empty_type.extend(&exr[8..]);
        let text = LinearImage::decode_exr(&empty_type)
            .unwrap_err()
            .to_string();
        assert!(text.contains("type name is empty"), "{text}");
        // Long names (version bit 10): a name of 256 bytes is the decoder's
        // longest, and counted like any other.
        let mut long_name = exr[..8].to_vec();
        long_name[5] |= 0x04;
        long_name.extend([b'n'; 256]);
        long_name.extend(b"\0int\0");
        long_name.extend(4u32.to_le_bytes());
        long_name.extend(7i32.to_le_bytes());
        attributes(&mut long_name, 2 * MAX_EXR_ATTRIBUTES);
        long_name.extend(&exr[8..]);
        let text = LinearImage::decode_exr(&long_name).unwrap_err().to_string();
        assert!(text.contains("header attributes"), "{text}");
        // One byte longer is past what the decoder reads: refused.
        let mut longer = exr[..8].to_vec();
        longer[5] |= 0x04;
        longer.extend([b'n'; 257]);
        longer.extend(b"\0int\0");
        longer.extend(&exr[8..]);
        let text = LinearImage::decode_exr(&longer).unwrap_err().to_string();
        assert!(text.contains("longer than the decoder reads"), "{text}");
        // Without the flag, the decoder reads names of 32 bytes at most.
        let mut short_names = exr[..8].to_vec();
        short_names.extend([b'n'; 33]);
        short_names.extend(b"\0int\0");
        short_names.extend(&exr[8..]);
        let text = LinearImage::decode_exr(&short_names)
            .unwrap_err()
            .to_string();
        assert!(text.contains("longer than the decoder reads"), "{text}");
        // A file that ends inside its headers, and a negative size.
        let text = LinearImage::decode_exr(&exr[..20]).unwrap_err().to_string();
        assert!(text.contains("ends inside its headers"), "{text}");
        let mut negative = exr[..8].to_vec();
        negative.extend(b"a\0int\0");
        negative.extend((-4i32).to_le_bytes());
        negative.extend(&exr[8..]);
        let text = LinearImage::decode_exr(&negative).unwrap_err().to_string();
        assert!(text.contains("size is negative"), "{text}");
    }

    /// Pass 17 of issue 41: a tiled file of one tile the size of the
    /// image, 16 channels of zeros compressed to 2.5 MB, took 6 GB to
    /// decode (and aborted under a cap). A block larger decoded than raylab
    /// reads at once is refused before any is decoded.
    #[test]
    fn an_exr_block_larger_than_raylab_decodes_at_once_is_refused() {
        use exr::prelude::*;
        let tiled = |width: usize, height: usize, tile: (usize, usize)| {
            let channels =
                SpecificChannels::rgba(|_: Vec2<usize>| (0.0f32, 0.0f32, 0.0f32, 0.0f32));
            let encoding = Encoding {
                compression: Compression::ZIP16,
                blocks: Blocks::Tiles(Vec2(tile.0, tile.1)),
                line_order: LineOrder::Increasing,
            };
            let layer = Layer::new(
                (width, height),
                LayerAttributes::named("tiles"),
                encoding,
                channels,
            );
            let mut bytes = std::io::Cursor::new(Vec::new());
            Image::from_layer(layer)
                .write()
                .to_buffered(&mut bytes)
                .expect("encodes");
            bytes.into_inner()
        };
        // RGBA in f32, 16 bytes a pixel: a tile of 2100 x 2048 is past 64 MiB.
        let one_tile = tiled(2100, 2048, (2100, 2048));
        let text = LinearImage::decode_exr(&one_tile).unwrap_err().to_string();
        assert!(
            text.contains("blocks (tiles or runs of scan lines)"),
            "{text}"
        );
        // The same image in tiles of 64 x 64 is read.
        let small_tiles = tiled(2100, 2048, (64, 64));
        assert!(LinearImage::decode_exr(&small_tiles).is_ok());
    }

    #[test]
    fn an_exr_compression_whose_decoder_runs_past_its_block_is_refused() {
        use exr::prelude::*;
        let encoded = |compression: Compression| {
            let channels = SpecificChannels::rgb(|_: Vec2<usize>| (0.25f32, 0.5f32, 1.0f32));
            let encoding = Encoding {
                compression,
                blocks: Blocks::ScanLines,
                line_order: LineOrder::Increasing,
            };
            let layer = Layer::new((64, 64), LayerAttributes::named("rgb"), encoding, channels);
            let mut bytes = std::io::Cursor::new(Vec::new());
            Image::from_layer(layer)
                .write()
                .to_buffered(&mut bytes)
                .expect("encodes");
            bytes.into_inner()
        };
        for compression in [
            Compression::RLE,
            Compression::DWAA(None),
            Compression::DWAB(None),
        ] {
            let text = match LinearImage::decode_exr(&encoded(compression)) {
                Ok(_) => panic!("{compression}: decoded"),
                Err(error) => error.to_string(),
            };
            assert!(text.contains("OpenEXR file of"), "{compression}: {text}");
        }
        for compression in [
            Compression::Uncompressed,
            Compression::ZIP1,
            Compression::ZIP16,
            Compression::PIZ,
            Compression::PXR24,
            Compression::B44,
        ] {
            if let Err(error) = LinearImage::decode_exr(&encoded(compression)) {
                panic!("{compression}: {error}");
            }
        }
    }

    #[test]
    fn nan_and_infinite_pixels_are_named() {
        let mut values = [0.5f32; 12];
        values[7] = f32::NAN;
        let exr = crate::output::encode_exr(2, 2, &values).expect("encodes");
        let text = LinearImage::decode_exr(&exr).unwrap_err().to_string();
        assert!(text.contains("x=0, y=1") && text.contains("G"), "{text}");
        values[7] = f32::INFINITY;
        let exr = crate::output::encode_exr(2, 2, &values).expect("encodes");
        let text = LinearImage::decode_exr(&exr).unwrap_err().to_string();
        assert!(text.contains("inf"), "{text}");
    }
}
