//! Turning linear light into an 8-bit sRGB PNG, hashing it, writing it safely.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};
use image::ImageEncoder;

/// Encodes a linear light value as an 8-bit sRGB code.
///
/// Screens and PNG viewers expect sRGB, whose codes are spaced roughly
/// evenly for the eye rather than for physics: a linear 0.5 (half the
/// light) is code 188, not 128. The transfer function is linear near black,
/// then a 1/2.4 power. `libm::powf` gives the same bits on every platform,
/// which keeps the snapshot hashes portable.
pub fn linear_to_srgb8(linear: f32) -> u8 {
    let v = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    let encoded = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * libm::powf(v, 1.0 / 2.4) - 0.055
    };
    (encoded * 255.0 + 0.5) as u8
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

/// Writes an RGB8 image as PNG at `path`, atomically (see [`write_atomically`]).
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<()> {
    write_atomically(path, |file| {
        image::codecs::png::PngEncoder::new(file)
            .write_image(rgb, width, height, image::ExtendedColorType::Rgb8)
            .with_context(|| format!("cannot encode {}", path.display()))
    })
}

/// Writes a file atomically: `write` fills a temporary file in the same
/// folder, which is renamed over `path` only once complete. A failed or
/// interrupted write never leaves a partial file at `path`.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<()>,
) -> Result<()> {
    let folder = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    if path.is_dir() {
        anyhow::bail!("cannot write {}: it is a folder", path.display());
    }
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
    let mut temporary = builder.tempfile_in(folder).with_context(|| {
        format!(
            "cannot write {}: cannot create a file in {}",
            path.display(),
            folder.display()
        )
    })?;
    {
        let mut buffered = std::io::BufWriter::new(temporary.as_file_mut());
        write(&mut buffered)?;
        buffered
            .flush()
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    temporary
        .persist(path)
        .map_err(|error| error.error)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn fnv1a_matches_the_published_test_vectors() {
        assert_eq!(fnv1a64(*b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(*b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a64(*b"foobar"), 0x8594_4171_f739_67e8);
        assert_ne!(image_hash(1, 1, &[0, 0, 0]), image_hash(1, 1, &[0, 0, 1]));
    }
}
