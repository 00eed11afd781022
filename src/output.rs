//! Turning linear light into an 8-bit sRGB PNG or keeping it as OpenEXR,
//! hashing it, writing it safely.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Encodes a linear light value as an 8-bit sRGB code.
///
/// Screens and PNG viewers expect sRGB, whose codes are spaced roughly
/// evenly for the eye rather than for physics: a linear 0.5 (half the
/// light) is code 188, not 128. The transfer function is linear near black,
/// then a 1/2.4 power. `libm::powf` gives the same bits on every platform,
/// which keeps the snapshot hashes portable.
///
/// A power per channel per pixel is a noticeable share of a render, so the
/// codes come from a table instead: the 255 linear values where the code
/// steps up, found once by bisection on [`linear_to_srgb8_by_formula`].
/// The formula never decreases (a test checks every `f32` on the power
/// segment), so the code of `v` is the number of steps at or below `v`:
/// exactly the formula's answer, bit for bit, at a few comparisons' cost.
pub fn linear_to_srgb8(linear: f32) -> u8 {
    let v = displayable(linear);
    srgb_steps().partition_point(|&step| step <= v) as u8
}

/// A linear value a screen can show: clamped to `[0, 1]`, NaN as black.
fn displayable(linear: f32) -> f32 {
    if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    }
}

/// The sRGB formula itself, one power per call (see [`linear_to_srgb8`]).
pub fn linear_to_srgb8_by_formula(linear: f32) -> u8 {
    let v = displayable(linear);
    let encoded = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * libm::powf(v, 1.0 / 2.4) - 0.055
    };
    (encoded * 255.0 + 0.5) as u8
}

/// `steps[k]`: the smallest `f32` in `[0, 1]` whose code is above `k`.
fn srgb_steps() -> &'static [f32; 255] {
    static STEPS: std::sync::OnceLock<[f32; 255]> = std::sync::OnceLock::new();
    STEPS.get_or_init(|| {
        // Non-negative floats are ordered like their bit patterns, so a
        // bisection on the bits finds each step exactly.
        std::array::from_fn(|k| {
            let above = |bits: u32| linear_to_srgb8_by_formula(f32::from_bits(bits)) > k as u8;
            let (mut low, mut high) = (0u32, 1.0f32.to_bits()); // !above(low), above(high)
            while high - low > 1 {
                let middle = low + (high - low) / 2;
                if above(middle) {
                    high = middle;
                } else {
                    low = middle;
                }
            }
            f32::from_bits(high)
        })
    })
}

/// FNV-1a (64-bit) of the width, height (little-endian `u32`s) and the raw
/// RGB8 bytes: a stable fingerprint of an image, the same on every machine
/// and Rust version (unlike `std`'s `DefaultHasher`).
pub fn image_hash(width: u32, height: u32, rgb: &[u8]) -> u64 {
    let size = width.to_le_bytes().into_iter().chain(height.to_le_bytes());
    fnv1a64(size.chain(rgb.iter().copied()))
}

/// The 64-bit FNV-1a hash of a byte sequence.
pub fn fnv1a64(bytes: impl IntoIterator<Item = u8>) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in bytes {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    hash
}

/// Why an image was not encoded or a file not written, or why an output
/// path is refused before any work. `option` is the command-line option
/// that names the path (`-o`, `--heatmap`). Each message is whole, the
/// underlying reason included, and no variant has a `source`: callers print
/// it with `{}` or `{:#}` alike and a chain never repeats it.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("a {width}x{height} image has no pixels to encode")]
    NoPixels { width: u32, height: u32 },
    /// `bytes` of RGB where the size needs `needed`.
    #[error("{bytes} bytes of RGB for a {width}x{height} image, which needs {needed}")]
    WrongSize {
        width: u32,
        height: u32,
        bytes: usize,
        needed: u64,
    },
    /// The pixels do not fit the size ([`OutputError::NoPixels`] or
    /// [`OutputError::WrongSize`]).
    #[error("cannot encode a PNG: {0}")]
    Pixels(Box<OutputError>),
    #[error("cannot encode a PNG: {0}")]
    Png(png::EncodingError),
    /// The image for `path` could not be encoded.
    #[error("cannot write {}: {error}", path.display())]
    Encode {
        path: PathBuf,
        error: Box<OutputError>,
    },
    #[error("cannot write {}: {error}", path.display())]
    Io {
        path: PathBuf,
        error: std::io::Error,
    },
    #[error("cannot write {}: it is a folder", path.display())]
    WriteFolder { path: PathBuf },
    #[error(
        "cannot write {}: cannot create a file in {}: {error}",
        path.display(),
        folder.display()
    )]
    Temporary {
        path: PathBuf,
        folder: PathBuf,
        error: std::io::Error,
    },
    #[error(
        "{option} {}: the file exists and raylab did not write it; \
         use --force to replace it, or another name",
        path.display()
    )]
    NotRaylabs { option: String, path: PathBuf },
    #[error("{option} {}: it is a folder", path.display())]
    IsFolder { option: String, path: PathBuf },
    #[error("{option} {}: names a folder, not a file (remove the trailing /)", path.display())]
    NamesFolder { option: String, path: PathBuf },
    #[error("{option} {}: the folder {} does not exist", path.display(), folder.display())]
    NoFolder {
        option: String,
        path: PathBuf,
        folder: PathBuf,
    },
    #[error(
        "{option} {}: exists and is not a regular file; raylab writes a new \
         file and renames it into place, which would replace it",
        path.display()
    )]
    NotRegular { option: String, path: PathBuf },
    #[error(
        "{option} {}: the file exists and is read-only; raylab does not replace \
         it without --force (or make it writable, or choose another name)",
        path.display()
    )]
    ReadOnly { option: String, path: PathBuf },
    /// The probe file in `folder` could not be created.
    #[error(
        "{option} {}: cannot create a file in {}: {error}",
        path.display(),
        folder.display()
    )]
    NotWritable {
        option: String,
        path: PathBuf,
        folder: PathBuf,
        error: std::io::Error,
    },
    #[error(
        "{option} {}: that is an input ({}); writing it would destroy it",
        path.display(),
        input.display()
    )]
    IsInput {
        option: String,
        path: PathBuf,
        input: PathBuf,
    },
    /// `other` is the option of the earlier output naming the same file.
    #[error(
        "{option} {} and {other} name the same file: one would overwrite the other",
        path.display()
    )]
    SameFile {
        option: String,
        path: PathBuf,
        other: String,
    },
    #[error("{option} {}: raylab writes PNG images; give a name ending in .png", path.display())]
    NotPngName { option: String, path: PathBuf },
    #[error(
        "{option} {}: raylab writes PNG (8-bit sRGB) or OpenEXR (linear light) images; \
         give a name ending in .png or .exr",
        path.display()
    )]
    NotImageName { option: String, path: PathBuf },
    /// `values` floats of linear RGB where the size needs `needed`.
    #[error(
        "cannot encode an OpenEXR image: {values} linear values for a {width}x{height} image, \
         which needs {needed}"
    )]
    LinearWrongSize {
        width: u32,
        height: u32,
        values: usize,
        needed: u64,
    },
    #[error("cannot encode an OpenEXR image: {0}")]
    Exr(exr::error::Error),
}

/// The error for writing `path`, for `map_err`.
fn write_error(path: &Path) -> impl FnOnce(std::io::Error) -> OutputError + '_ {
    move |error| OutputError::Io {
        path: path.to_path_buf(),
        error,
    }
}

/// Checks that `rgb` holds exactly the pixels of a `width` x `height` RGB8
/// image, so that encoding reports a mismatch instead of panicking.
pub fn check_rgb_size(width: u32, height: u32, rgb: &[u8]) -> Result<(), OutputError> {
    if width == 0 || height == 0 {
        return Err(OutputError::NoPixels { width, height });
    }
    let needed = 3 * u64::from(width) * u64::from(height);
    if rgb.len() as u64 != needed {
        return Err(OutputError::WrongSize {
            width,
            height,
            bytes: rgb.len(),
            needed,
        });
    }
    Ok(())
}

/// The tEXt chunk every PNG raylab writes carries (`Software: raylab`):
/// how `raylab render` tells its own earlier image, which it may replace,
/// from a file someone made otherwise, which it keeps without `--force`.
const MARKER_KEYWORD: &str = "Software";
const MARKER_TEXT: &str = "raylab";

/// Encodes an RGB8 image as PNG bytes, marked as raylab's (see
/// [`is_raylab_png`]). A buffer of the wrong size is an error.
pub fn encode_png(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, OutputError> {
    check_rgb_size(width, height, rgb).map_err(|error| OutputError::Pixels(Box::new(error)))?;
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Balanced);
    encoder.set_filter(png::Filter::Adaptive);
    let encoded = encoder
        .add_text_chunk(MARKER_KEYWORD.into(), MARKER_TEXT.into())
        .and_then(|()| encoder.write_header())
        .and_then(|mut writer| {
            writer.write_image_data(rgb)?;
            writer.finish()
        });
    encoded.map_err(OutputError::Png)?;
    Ok(bytes)
}

/// Writes an RGB8 image as PNG at `path`, atomically (see
/// [`write_atomically`]); a buffer of the wrong size is an error.
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), OutputError> {
    let bytes = encode_png(width, height, rgb).map_err(|error| OutputError::Encode {
        path: path.to_path_buf(),
        error: Box::new(error),
    })?;
    write_files(&[(path, &bytes)])
}

/// Whether `path` is a PNG that raylab wrote (its chunks before the image
/// data hold raylab's tEXt marker). Only the file's first 64 KiB are read,
/// and only if it is a regular file.
pub fn is_raylab_png(path: &Path) -> bool {
    use std::io::Read;
    let Ok(file) = crate::input::open_regular(path, crate::input::Links::Follow) else {
        return false;
    };
    let mut head = Vec::new();
    if file.take(64 << 10).read_to_end(&mut head).is_err() {
        return false;
    }
    let Some(mut rest) = head.strip_prefix(b"\x89PNG\r\n\x1a\n".as_slice()) else {
        return false;
    };
    let marker = [MARKER_KEYWORD.as_bytes(), b"\0", MARKER_TEXT.as_bytes()].concat();
    while rest.len() >= 8 {
        let length = u32::from_be_bytes([rest[0], rest[1], rest[2], rest[3]]) as usize;
        let kind = &rest[4..8];
        let Some(data) = rest.get(8..8 + length) else {
            return false;
        };
        if kind == b"tEXt" && data == marker.as_slice() {
            return true;
        }
        if kind == b"IDAT" {
            return false;
        }
        rest = rest.get(8 + length + 4..).unwrap_or_default();
    }
    false
}

/// The two kinds of image raylab writes, told by the output's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageKind {
    /// 8-bit sRGB: what a screen shows, clamped to `[0, 1]`.
    Png,
    /// 32-bit float linear RGB: the radiance itself, for other tools.
    Exr,
}

/// The kind of image a name asks for: `.png` or `.exr` (any case). Any
/// other name is refused: PNG bytes under `render.jpg` would mislead every
/// viewer, and silently writing 8-bit under `render.hdr` would lose the
/// very range asked for.
pub fn image_kind(option: &str, path: &Path) -> Result<ImageKind, OutputError> {
    let extension = path.extension().unwrap_or_default();
    if extension.eq_ignore_ascii_case("png") {
        Ok(ImageKind::Png)
    } else if extension.eq_ignore_ascii_case("exr") {
        Ok(ImageKind::Exr)
    } else {
        Err(OutputError::NotImageName {
            option: option.to_string(),
            path: path.to_path_buf(),
        })
    }
}

/// Encodes linear RGB (3 `f32`s a pixel, row by row from the top) as an
/// OpenEXR file's bytes: one layer of 32-bit float R, G, B channels, ZIP
/// compressed (lossless: every value reads back bit for bit, NaN and
/// infinities included), marked as raylab's like its PNGs (see
/// [`is_raylab_exr`]). A buffer of the wrong size is an error.
pub fn encode_exr(width: u32, height: u32, linear: &[f32]) -> Result<Vec<u8>, OutputError> {
    use exr::prelude::WritableImage;
    use exr::prelude::{Encoding, Image, Layer, LayerAttributes, SpecificChannels, Text, Vec2};
    if width == 0 || height == 0 {
        return Err(OutputError::NoPixels { width, height });
    }
    let needed = 3 * u64::from(width) * u64::from(height);
    if linear.len() as u64 != needed {
        return Err(OutputError::LinearWrongSize {
            width,
            height,
            values: linear.len(),
            needed,
        });
    }
    let row = width as usize;
    let attributes = LayerAttributes {
        software_name: Some(Text::from(MARKER_TEXT)),
        ..LayerAttributes::default()
    };
    let layer = Layer::new(
        (width as usize, height as usize),
        attributes,
        Encoding::SMALL_LOSSLESS,
        SpecificChannels::rgb(|position: Vec2<usize>| {
            let at = 3 * (position.y() * row + position.x());
            (linear[at], linear[at + 1], linear[at + 2])
        }),
    );
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .non_parallel()
        .to_buffered(&mut bytes)
        .map_err(OutputError::Exr)?;
    Ok(bytes.into_inner())
}

/// The 4 bytes every OpenEXR file starts with.
pub const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// Whether `path` is an OpenEXR file that raylab wrote (its header's
/// `software` attribute is raylab's marker). Only the file's first 64 KiB
/// are read, and only if it is a regular file.
pub fn is_raylab_exr(path: &Path) -> bool {
    use std::io::Read;
    let Ok(file) = crate::input::open_regular(path, crate::input::Links::Follow) else {
        return false;
    };
    let mut head = Vec::new();
    if file.take(64 << 10).read_to_end(&mut head).is_err() || !head.starts_with(&EXR_MAGIC) {
        return false;
    }
    let Ok(meta) = exr::meta::MetaData::read_from_buffered(head.as_slice(), false) else {
        return false;
    };
    let marker = exr::prelude::Text::from(MARKER_TEXT);
    meta.headers
        .iter()
        .any(|header| header.own_attributes.software_name.as_ref() == Some(&marker))
}

/// [`check_replaceable_png`] for either kind of image.
pub fn check_replaceable_image(
    option: &str,
    path: &Path,
    force: bool,
    kind: ImageKind,
) -> Result<(), OutputError> {
    match kind {
        ImageKind::Png => check_replaceable_png(option, path, force),
        ImageKind::Exr => {
            if force || std::fs::symlink_metadata(path).is_err() || is_raylab_exr(path) {
                return Ok(());
            }
            Err(OutputError::NotRaylabs {
                option: option.to_string(),
                path: path.to_path_buf(),
            })
        }
    }
}

/// Refuses to replace an existing image raylab did not write, unless
/// `force`: `raylab render -o` must not destroy a student's own picture
/// (or any other file) by accident. A missing file is fine.
pub fn check_replaceable_png(option: &str, path: &Path, force: bool) -> Result<(), OutputError> {
    if force || std::fs::symlink_metadata(path).is_err() || is_raylab_png(path) {
        return Ok(());
    }
    Err(OutputError::NotRaylabs {
        option: option.to_string(),
        path: path.to_path_buf(),
    })
}

/// Refuses to replace an existing text output raylab did not write, unless
/// `force`: raylab's own has `marker` in its first 64 KiB (a key of its
/// JSON, the title of its report, the header of its CSV). `--stats-json
/// model.obj` or `--json notes.txt` must not destroy someone's file. A
/// missing file is fine.
pub fn check_replaceable_text(
    option: &str,
    path: &Path,
    force: bool,
    marker: &str,
) -> Result<(), OutputError> {
    use std::io::Read;
    if force || std::fs::symlink_metadata(path).is_err() {
        return Ok(());
    }
    let mut head = Vec::new();
    let ours = crate::input::open_regular(path, crate::input::Links::Follow).is_ok_and(|file| {
        file.take(64 << 10).read_to_end(&mut head).is_ok()
            && head
                .windows(marker.len())
                .any(|window| window == marker.as_bytes())
    });
    if ours {
        return Ok(());
    }
    Err(OutputError::NotRaylabs {
        option: option.to_string(),
        path: path.to_path_buf(),
    })
}

/// What raylab's text outputs carry, for [`check_replaceable_text`].
pub mod markers {
    /// `render --stats-json`.
    pub const STATS_JSON: &str = "\"image_fnv1a64\"";
    /// `diff --json`.
    pub const DIFF_JSON: &str = "\"max_abs_difference\"";
    /// `grade`'s HTML report.
    pub const GRADE_REPORT: &str = "<title>raylab grade";
    /// `grade`'s CSV.
    pub const GRADE_CSV: &str = "student,chapter,status,max,mean";
    /// `grade --student`'s result file.
    pub const GRADE_RESULT: &str = "\"raylab_grade_result\"";
    /// `grade --gradescope`'s results.json.
    pub const GRADESCOPE_RESULTS: &str = "\"raylab_gradescope\"";
    /// `grade --gradebook`'s CSV.
    pub const GRADEBOOK_CSV: &str = "Student,ID,SIS User ID,SIS Login ID,Section";
}

/// Checks, before any work is done, that every output can be written and
/// none would overwrite an input or another output.
///
/// A render or a comparison can take minutes; finding out only at the end
/// that `--stats-json` points into a missing folder wastes them, and
/// writing the image first would leave half the results behind. Each
/// output's folder must exist and accept a new file (a temporary file is
/// created there and removed), the output must name a file (not a folder,
/// not a path ending in `/`), an existing output must be a regular file
/// (never a device or a FIFO: outputs are renamed into place) and, unless
/// `force`, not read-only, and no two paths may name the same file (`-o`
/// equal to the scene file, a heatmap written over the image it came from,
/// a report over a student's PNG). `outputs` pairs each path with the
/// option that names it, for the message.
pub fn check_outputs(
    inputs: &[&Path],
    outputs: &[(&str, &Path)],
    force: bool,
) -> Result<(), OutputError> {
    for (index, &(option, path)) in outputs.iter().enumerate() {
        let option_text = option.to_string();
        let path_buf = path.to_path_buf();
        if path.is_dir() {
            return Err(OutputError::IsFolder {
                option: option_text,
                path: path_buf,
            });
        }
        if ends_in_separator(path) || path.file_name().is_none() {
            return Err(OutputError::NamesFolder {
                option: option_text,
                path: path_buf,
            });
        }
        let folder = folder_of(path);
        if !folder.is_dir() {
            return Err(OutputError::NoFolder {
                option: option_text,
                path: path_buf,
                folder: folder.to_path_buf(),
            });
        }
        if let Ok(existing) = std::fs::metadata(path) {
            if !existing.is_file() {
                return Err(OutputError::NotRegular {
                    option: option_text,
                    path: path_buf,
                });
            }
            if existing.permissions().readonly() && !force {
                return Err(OutputError::ReadOnly {
                    option: option_text,
                    path: path_buf,
                });
            }
        }
        let probe = temporary_file_builder()
            .tempfile_in(folder)
            .map_err(|error| OutputError::NotWritable {
                option: option.to_string(),
                path: path.to_path_buf(),
                folder: folder.to_path_buf(),
                error,
            })?;
        // Registered like any temporary file: a signal now must not leave it.
        let registration = crate::cleanup::register(probe.path());
        drop(probe);
        drop(registration);
        let identity = file_identity(path);
        if let Some(input) = inputs.iter().find(|input| file_identity(input) == identity) {
            return Err(OutputError::IsInput {
                option: option_text,
                path: path_buf,
                input: input.to_path_buf(),
            });
        }
        if let Some((other, _)) = outputs[..index]
            .iter()
            .find(|(_, other)| file_identity(other) == identity)
        {
            return Err(OutputError::SameFile {
                option: option_text,
                path: path_buf,
                other: other.to_string(),
            });
        }
    }
    Ok(())
}

/// `out.png/`: a trailing separator, which the file-name functions of
/// `Path` silently drop.
fn ends_in_separator(path: &Path) -> bool {
    let bytes = path.as_os_str().as_encoded_bytes();
    bytes
        .last()
        .is_some_and(|&last| std::path::is_separator(char::from(last)))
}

/// Refuses an image name that does not end in `.png`: raylab writes PNG
/// only, and PNG bytes under `render.jpg` would mislead every viewer.
pub fn check_png_name(option: &str, path: &Path) -> Result<(), OutputError> {
    let is_png = path
        .extension()
        .is_some_and(|extension| extension.eq_ignore_ascii_case("png"));
    if !is_png {
        return Err(OutputError::NotPngName {
            option: option.to_string(),
            path: path.to_path_buf(),
        });
    }
    Ok(())
}

/// The folder a file is (or would be) written in.
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    }
}

/// A path with its folder resolved (symbolic links, `..`), so that two
/// spellings of one file compare equal, whether or not the file exists yet.
fn file_identity(path: &Path) -> Option<std::path::PathBuf> {
    path.canonicalize().ok().or_else(|| {
        let folder = folder_of(path).canonicalize().ok()?;
        Some(folder.join(path.file_name()?))
    })
}

/// How raylab names and creates its temporary files (`.raylab-*.tmp`).
fn temporary_file_builder() -> tempfile::Builder<'static, 'static> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(".raylab-").suffix(".tmp");
    // A temporary file is private (0600) by default; the image it becomes is
    // an ordinary output, readable like any file the user creates (0666 less
    // the umask), e.g. by a web server showing a class's renders.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder
}

/// Writes a file atomically: `write` fills a temporary file in the same
/// folder, which is renamed over `path` only once complete. A failed or
/// interrupted write never leaves a partial file at `path`, nor (see
/// [`crate::cleanup`]) the temporary file. A file replaced keeps its
/// permissions. An error of `write` is one writing `path`.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), OutputError> {
    let staged = stage(path, write)?;
    crate::cleanup::test_pause_before_rename();
    staged.commit()
}

/// Writes several files all or nothing: every one goes to a temporary file
/// first, and only when all are complete are they renamed into place. A
/// failure while writing (a full disk) removes the temporary files and
/// leaves every old file as it was. (A rename failing after another one
/// succeeded cannot be undone; renames within a folder fail only if the
/// folder changes under us.)
pub fn write_files(files: &[(&Path, &[u8])]) -> Result<(), OutputError> {
    let mut staged = Vec::with_capacity(files.len());
    for &(path, bytes) in files {
        staged.push(stage(path, |file| file.write_all(bytes))?);
    }
    crate::cleanup::test_pause_before_rename();
    commit_all(staged)
}

/// A file's contents, written by a function (for [`write_streams`]).
pub type Writer<'a> = Box<dyn FnOnce(&mut dyn Write) -> std::io::Result<()> + 'a>;

/// [`write_files`] for contents too large to hold in memory: each `Writer`
/// streams its file into the temporary one.
pub fn write_streams(files: Vec<(&Path, Writer<'_>)>) -> Result<(), OutputError> {
    let mut staged = Vec::with_capacity(files.len());
    for (path, write) in files {
        staged.push(stage(path, write)?);
    }
    crate::cleanup::test_pause_before_rename();
    commit_all(staged)
}

/// Renames every staged file over its output, holding the signals that
/// would end the process until all are done (see
/// [`crate::cleanup::while_committing`]).
fn commit_all(staged: Vec<Staged>) -> Result<(), OutputError> {
    crate::cleanup::while_committing(|| {
        for (index, file) in staged.into_iter().enumerate() {
            if index == 1 {
                crate::cleanup::test_pause_between_renames();
            }
            file.commit()?;
        }
        Ok(())
    })
}

/// A complete temporary file waiting to be renamed over `path`. Dropping it
/// removes the file, then unregisters it (fields drop in this order).
struct Staged {
    temporary: tempfile::NamedTempFile,
    _registration: crate::cleanup::Registered,
    path: std::path::PathBuf,
}

fn stage(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<Staged, OutputError> {
    let folder = folder_of(path);
    if path.is_dir() {
        return Err(OutputError::WriteFolder {
            path: path.to_path_buf(),
        });
    }
    let temporary = temporary_file_builder()
        .tempfile_in(folder)
        .map_err(|error| OutputError::Temporary {
            path: path.to_path_buf(),
            folder: folder.to_path_buf(),
            error,
        })?;
    let registration = crate::cleanup::register(temporary.path());
    let mut staged = Staged {
        temporary,
        _registration: registration,
        path: path.to_path_buf(),
    };
    {
        let mut buffered = std::io::BufWriter::new(staged.temporary.as_file_mut());
        write(&mut buffered).map_err(write_error(path))?;
        buffered.flush().map_err(write_error(path))?;
    }
    // A file replaced keeps its mode: a read-only image replaced with
    // --force stays read-only, a private one private.
    if let Ok(existing) = std::fs::metadata(path)
        && existing.is_file()
    {
        staged
            .temporary
            .as_file()
            .set_permissions(existing.permissions())
            .map_err(write_error(path))?;
    }
    Ok(staged)
}

impl Staged {
    fn commit(self) -> Result<(), OutputError> {
        let Staged {
            temporary,
            _registration,
            path,
        } = self;
        temporary
            .persist(&path)
            .map_err(|error| error.error)
            .map_err(write_error(&path))?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_are_checked_before_any_work() {
        let folder = tempfile::tempdir().expect("temporary folder");
        let input = folder.path().join("scene.toml");
        std::fs::write(&input, "x").expect("write input");
        let image = folder.path().join("image.png");
        let ok = check_outputs(&[&input], &[("-o", &image)], false);
        assert!(ok.is_ok(), "{ok:?}");
        let message = |result: Result<(), OutputError>| result.expect_err("refused").to_string();
        // Another spelling of the input is still the input.
        let respelled = folder.path().join(".").join("scene.toml");
        assert!(message(check_outputs(&[&input], &[("-o", &respelled)], false)).contains("input"));
        assert!(
            message(check_outputs(
                &[],
                &[("-o", &image), ("--json", &image)],
                false
            ))
            .contains("same file")
        );
        let missing = folder.path().join("no-such-folder").join("x.png");
        assert!(message(check_outputs(&[], &[("-o", &missing)], false)).contains("does not exist"));
        assert!(message(check_outputs(&[], &[("-o", folder.path())], false)).contains("folder"));
        // The probe file is gone again.
        let left: Vec<_> = std::fs::read_dir(folder.path())
            .expect("list")
            .filter_map(|entry| entry.ok())
            .map(|entry| entry.file_name())
            .collect();
        assert_eq!(left, vec![std::ffi::OsString::from("scene.toml")]);
    }

    #[test]
    fn srgb_end_points_and_midpoint() {
        assert_eq!(linear_to_srgb8(0.0), 0);
        assert_eq!(linear_to_srgb8(1.0), 255);
        assert_eq!(linear_to_srgb8(2.0), 255);
        assert_eq!(linear_to_srgb8(-1.0), 0);
        assert_eq!(linear_to_srgb8(f32::NAN), 0);
        // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354 -> 187.5 -> 188.
        assert_eq!(linear_to_srgb8(0.5), 188);
        // Linear segment: 12.92 * 0.001 * 255 = 3.29 -> 3.
        assert_eq!(linear_to_srgb8(0.001), 3);
    }

    #[test]
    fn the_table_gives_the_formula_bit_for_bit() {
        // The table is exact if the formula never decreases. The linear
        // segment cannot (a product, a sum and a truncation of a growing
        // value); the power segment is checked at every f32, 70 million.
        let first = 0.003_130_8f32.next_up().to_bits();
        let mut previous = linear_to_srgb8_by_formula(0.003_130_8);
        for bits in first..=1.0f32.to_bits() {
            let code = linear_to_srgb8_by_formula(f32::from_bits(bits));
            assert!(
                code >= previous,
                "the formula decreases at {}",
                f32::from_bits(bits)
            );
            previous = code;
        }
        // And the two agree around every step and at the edges.
        for &step in srgb_steps() {
            for v in [step.next_down(), step, step.next_up()] {
                assert_eq!(linear_to_srgb8(v), linear_to_srgb8_by_formula(v), "at {v}");
            }
        }
        for v in [
            -1.0,
            -0.0,
            0.0,
            1e-40,
            0.003_130_8,
            0.5,
            1.0,
            7.0,
            f32::INFINITY,
            f32::NAN,
        ] {
            assert_eq!(linear_to_srgb8(v), linear_to_srgb8_by_formula(v), "at {v}");
        }
    }

    #[test]
    fn fnv1a_matches_the_published_test_vectors() {
        assert_eq!(fnv1a64(*b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(*b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a64(*b"foobar"), 0x8594_4171_f739_67e8);
        assert_ne!(image_hash(1, 1, &[0, 0, 0]), image_hash(1, 1, &[0, 0, 1]));
    }
}
