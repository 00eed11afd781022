//! Reading the files a user names: only regular files, never more than a
//! stated size, and images never larger than a stated decoded size.
//!
//! Every command that reads a scene or a PNG goes through here, so the
//! limits below are the whole story (docs/instructors.md states them too):
//!
//! - a scene file is at most [`MAX_SCENE_BYTES`] (16 MiB);
//! - an image is at most [`MAX_IMAGE_SIDE`] pixels a side and
//!   [`MAX_IMAGE_PIXELS`] pixels in all, the same limits as a render, so
//!   every image raylab can write it can read back; decoding it takes at
//!   most [`MAX_DECODED_BYTES`] (8 bytes a pixel: 16-bit RGBA, the widest
//!   PNG format);
//! - a PNG file is at most [`MAX_PNG_FILE_BYTES`]: the decoded size and a
//!   sixteenth more for the PNG's own overhead (an uncompressed PNG is a
//!   little larger than its pixels).
//!
//! A FIFO, a device (`/dev/zero`), a socket or a folder is refused before a
//! byte is read: reading one could block forever or never end. A FIFO is
//! opened without waiting for a writer (`O_NONBLOCK`), then refused.

use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The largest scene file read, in bytes (16 MiB: about 300,000 objects of
/// TOML, three times [`crate::limits::MAX_OBJECTS`]).
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// The widest or tallest image read, in pixels (the largest side a render
/// may have).
pub const MAX_IMAGE_SIDE: u32 = crate::limits::MAX_SIDE;

/// The most pixels an image read may have (the most a render may have).
pub const MAX_IMAGE_PIXELS: u64 = crate::limits::MAX_PIXELS;

/// The most bytes decoding one image may take: 8 a pixel.
pub const MAX_DECODED_BYTES: u64 = 8 * MAX_IMAGE_PIXELS;

/// The largest PNG file read, in bytes.
pub const MAX_PNG_FILE_BYTES: u64 = MAX_DECODED_BYTES + MAX_DECODED_BYTES / 16;

/// Whether a symbolic link may stand for the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Links {
    /// Follow links: the user named the path, wherever it leads.
    Follow,
    /// Refuse a link (a student's hand-in must be a file in the folder, not
    /// a pointer to someone else's).
    Refuse,
}

/// Why a file or an image is not read. Every message about a file names it.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    #[error("{}: no such file", path.display())]
    NotFound { path: PathBuf },
    /// An open, a read or a look at the file's metadata failed. The
    /// system's reason is part of the message, not a `source`, so the words
    /// are the same however the error is printed.
    #[error("cannot read {}: {error}", path.display())]
    Io {
        path: PathBuf,
        error: std::io::Error,
    },
    /// A link where [`Links::Refuse`] asks for the file itself.
    #[error("{}: {SYMBOLIC_LINK}", path.display())]
    SymbolicLink { path: PathBuf },
    /// `kind` says what it is instead: "a folder", "a FIFO (named pipe)".
    #[error("{}: is {kind}, not a regular file", path.display())]
    NotRegular { path: PathBuf, kind: &'static str },
    /// `size` is the file's length in bytes, or "more than that" when the
    /// file grew past `max` while it was read.
    #[error("{}: {size} bytes; raylab reads a {what} of at most {max} bytes", path.display())]
    TooLarge {
        path: PathBuf,
        size: String,
        what: String,
        max: u64,
    },
    /// `offset` is the byte where the text stops being UTF-8.
    #[error(
        "scene file {}: not UTF-8 text (invalid byte at offset {offset})",
        path.display()
    )]
    NotUtf8 { path: PathBuf, offset: usize },
    #[error(
        "{width}x{height} pixels is over raylab's image size limit: at most \
         {MAX_IMAGE_SIDE} pixels a side and {MAX_IMAGE_PIXELS} pixels in all \
         ({MAX_DECODED_BYTES} bytes decoded)"
    )]
    ImageTooLarge { width: u32, height: u32 },
}

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> InputError + '_ {
    move |error| InputError::Io {
        path: path.to_path_buf(),
        error,
    }
}

/// Opens `path` for reading if it is a regular file, without blocking on a
/// FIFO. The error names the file and what it is instead.
pub fn open_regular(path: &Path, links: Links) -> Result<File, InputError> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        let mut flags = libc::O_NONBLOCK;
        if links == Links::Refuse {
            flags |= libc::O_NOFOLLOW;
        }
        options.custom_flags(flags);
    }
    #[cfg(not(unix))]
    if links == Links::Refuse
        && std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink())
    {
        return Err(InputError::SymbolicLink {
            path: path.to_path_buf(),
        });
    }
    let file = options
        .open(path)
        .map_err(|error| open_error(path, error, links))?;
    // The handle's own metadata: the path may have been replaced since.
    let metadata = file.metadata().map_err(io_error(path))?;
    if !metadata.is_file() {
        return Err(InputError::NotRegular {
            path: path.to_path_buf(),
            kind: kind_of(&metadata),
        });
    }
    #[cfg(unix)]
    {
        use std::os::fd::AsRawFd;
        // Back to ordinary blocking reads (for a regular file the flag does
        // nothing on Linux, but other systems may differ).
        // SAFETY: plain fcntl calls on a descriptor we own.
        unsafe {
            let fd = file.as_raw_fd();
            let flags = libc::fcntl(fd, libc::F_GETFL);
            if flags >= 0 {
                libc::fcntl(fd, libc::F_SETFL, flags & !libc::O_NONBLOCK);
            }
        }
    }
    Ok(file)
}

const SYMBOLIC_LINK: &str = "is a symbolic link; only a regular file is read here";

fn open_error(path: &Path, error: std::io::Error, links: Links) -> InputError {
    let path = path.to_path_buf();
    #[cfg(unix)]
    if links == Links::Refuse && error.raw_os_error() == Some(libc::ELOOP) {
        return InputError::SymbolicLink { path };
    }
    let _ = links;
    match error.kind() {
        std::io::ErrorKind::NotFound => InputError::NotFound { path },
        _ => InputError::Io { path, error },
    }
}

/// What a file that is not a regular file is, for messages.
fn kind_of(metadata: &std::fs::Metadata) -> &'static str {
    let kind = metadata.file_type();
    if kind.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if kind.is_char_device() {
            return "a character device";
        }
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    "not a file"
}

/// Reads the regular file `path`, refusing one over `max` bytes before
/// reading it (and never reading more than `max` should it grow meanwhile).
/// `what` names the kind of file in the message ("scene file", "PNG").
pub fn read_bounded(
    path: &Path,
    max: u64,
    what: &str,
    links: Links,
) -> Result<Vec<u8>, InputError> {
    let file = open_regular(path, links)?;
    let too_big = |size: &str| InputError::TooLarge {
        path: path.to_path_buf(),
        size: size.to_string(),
        what: what.to_string(),
        max,
    };
    let length = file.metadata().map_err(io_error(path))?.len();
    if length > max {
        return Err(too_big(&length.to_string()));
    }
    let mut bytes = Vec::with_capacity(length as usize);
    file.take(max + 1)
        .read_to_end(&mut bytes)
        .map_err(io_error(path))?;
    if bytes.len() as u64 > max {
        return Err(too_big("more than that"));
    }
    Ok(bytes)
}

/// Reads a scene file's text (at most [`MAX_SCENE_BYTES`]).
pub fn read_scene_text(path: &Path) -> Result<String, InputError> {
    let bytes = read_bounded(path, MAX_SCENE_BYTES, "scene file", Links::Follow)?;
    String::from_utf8(bytes).map_err(|error| InputError::NotUtf8 {
        path: path.to_path_buf(),
        offset: error.utf8_error().valid_up_to(),
    })
}

/// Refuses an image over the size limits, naming them: called with the
/// dimensions a PNG declares, before any pixel is decoded.
pub fn check_image_size(width: u32, height: u32) -> Result<(), InputError> {
    let pixels = u64::from(width) * u64::from(height);
    if width > MAX_IMAGE_SIDE || height > MAX_IMAGE_SIDE || pixels > MAX_IMAGE_PIXELS {
        return Err(InputError::ImageTooLarge { width, height });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_decode_limit_bounds_memory() {
        // The largest image accepted decodes into at most MAX_DECODED_BYTES
        // (16-bit RGBA), and its RGB8 copy into less.
        assert_eq!(MAX_DECODED_BYTES, 320_000_000);
        assert!(check_image_size(MAX_IMAGE_SIDE, (MAX_IMAGE_PIXELS / 16_384) as u32).is_ok());
        for (width, height) in [(100_000_000, 1), (16_384, 16_384), (16_385, 1), (1, 16_385)] {
            let message = check_image_size(width, height).unwrap_err().to_string();
            assert!(message.contains("image size limit"), "{message}");
        }
        // The legend strip of a heatmap of the widest image: 68 rows.
        let legend =
            u64::from(MAX_IMAGE_SIDE) * u64::from(crate::diff::legend_height(MAX_IMAGE_SIDE)) * 3;
        assert!(legend <= 4 << 20, "{legend}");
    }

    #[test]
    fn only_regular_files_are_read_and_never_past_the_limit() {
        let folder = tempfile::tempdir().expect("temporary folder");
        let file = folder.path().join("a.toml");
        std::fs::write(&file, "12345").expect("write");
        assert_eq!(
            read_bounded(&file, 5, "test", Links::Follow).expect("read"),
            b"12345"
        );
        let message = format!(
            "{:#}",
            read_bounded(&file, 4, "test", Links::Follow).unwrap_err()
        );
        assert!(message.contains("at most 4 bytes"), "{message}");
        let message = format!(
            "{:#}",
            open_regular(folder.path(), Links::Follow).unwrap_err()
        );
        assert!(message.contains("is a folder"), "{message}");
        #[cfg(unix)]
        {
            let zero = format!(
                "{:#}",
                open_regular(Path::new("/dev/zero"), Links::Follow).unwrap_err()
            );
            assert!(zero.contains("character device"), "{zero}");
            let link = folder.path().join("link");
            std::os::unix::fs::symlink(&file, &link).expect("symlink");
            assert!(open_regular(&link, Links::Follow).is_ok());
            let refused = format!("{:#}", open_regular(&link, Links::Refuse).unwrap_err());
            assert!(refused.contains("symbolic link"), "{refused}");
        }
    }
}
