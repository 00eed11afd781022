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

/// Writes an RGB8 image as PNG at `path`, atomically (see [`write_atomically`]).
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<()> {
    write_atomically(path, |file| {
        image::codecs::png::PngEncoder::new(file)
            .write_image(rgb, width, height, image::ExtendedColorType::Rgb8)
            .with_context(|| format!("cannot encode {}", path.display()))
    })
}

/// Checks, before any work is done, that every output can be written and
/// none would overwrite an input or another output.
///
/// A render or a comparison can take minutes; finding out only at the end
/// that `--stats-json` points into a missing folder wastes them, and
/// writing the image first would leave half the results behind. Each
/// output's folder must exist and accept a new file (a temporary file is
/// created there and removed), the output must not be a folder, and no two
/// paths may name the same file (`-o` equal to the scene file, a heatmap
/// written over the image it came from, a report over a student's PNG).
/// `outputs` pairs each path with the option that names it, for the message.
pub fn check_outputs(inputs: &[&Path], outputs: &[(&str, &Path)]) -> Result<()> {
    for (index, &(option, path)) in outputs.iter().enumerate() {
        if path.is_dir() {
            anyhow::bail!("{option} {}: it is a folder", path.display());
        }
        let folder = folder_of(path);
        if !folder.is_dir() {
            anyhow::bail!(
                "{option} {}: the folder {} does not exist",
                path.display(),
                folder.display()
            );
        }
        temporary_file_builder()
            .tempfile_in(folder)
            .with_context(|| {
                format!(
                    "{option} {}: cannot create a file in {}",
                    path.display(),
                    folder.display()
                )
            })?;
        let identity = file_identity(path);
        if let Some(input) = inputs.iter().find(|input| file_identity(input) == identity) {
            anyhow::bail!(
                "{option} {}: that is an input ({}); writing it would destroy it",
                path.display(),
                input.display()
            );
        }
        if let Some((other, _)) = outputs[..index]
            .iter()
            .find(|(_, other)| file_identity(other) == identity)
        {
            anyhow::bail!(
                "{option} {} and {other} name the same file: one would overwrite the other",
                path.display()
            );
        }
    }
    Ok(())
}

/// Refuses an image name that does not end in `.png`: raylab writes PNG
/// only, and PNG bytes under `render.jpg` would mislead every viewer.
pub fn check_png_name(option: &str, path: &Path) -> Result<()> {
    let is_png = path
        .extension()
        .is_some_and(|extension| extension.eq_ignore_ascii_case("png"));
    if !is_png {
        anyhow::bail!(
            "{option} {}: raylab writes PNG images; give a name ending in .png",
            path.display()
        );
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
/// interrupted write never leaves a partial file at `path`.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<()>,
) -> Result<()> {
    let folder = folder_of(path);
    if path.is_dir() {
        anyhow::bail!("cannot write {}: it is a folder", path.display());
    }
    let mut temporary = temporary_file_builder()
        .tempfile_in(folder)
        .with_context(|| {
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
    fn outputs_are_checked_before_any_work() {
        let folder = tempfile::tempdir().expect("temporary folder");
        let input = folder.path().join("scene.toml");
        std::fs::write(&input, "x").expect("write input");
        let image = folder.path().join("image.png");
        let ok = check_outputs(&[&input], &[("-o", &image)]);
        assert!(ok.is_ok(), "{ok:?}");
        let message = |result: Result<()>| format!("{:#}", result.expect_err("refused"));
        // Another spelling of the input is still the input.
        let respelled = folder.path().join(".").join("scene.toml");
        assert!(message(check_outputs(&[&input], &[("-o", &respelled)])).contains("input"));
        assert!(
            message(check_outputs(&[], &[("-o", &image), ("--json", &image)]))
                .contains("same file")
        );
        let missing = folder.path().join("no-such-folder").join("x.png");
        assert!(message(check_outputs(&[], &[("-o", &missing)])).contains("does not exist"));
        assert!(message(check_outputs(&[], &[("-o", folder.path())])).contains("folder"));
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
