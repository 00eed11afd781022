//! Build script. It does two things.
//!
//! 1. The lessons (`chapters/NN_name/lesson.md`) link their images relatively
//!    (`../../snapshots/chapter-2.png`, `../../docs/images/...`), which is right
//!    on GitHub and in an editor but broken in `cargo doc`, whose pages live
//!    under target/doc. So each lesson is copied to `$OUT_DIR/lessons/` with
//!    every local image inlined as a `data:` URI, and the chapter modules
//!    take their docs from there (`#![doc = include_str!(concat!(env!(
//!    "OUT_DIR"), "/lessons/NN_name.md"))]`). An image that cannot be read is
//!    left as it was, with a warning; tests/pictures/lesson_images.rs fails on it.
//!
//! 2. The source's fingerprint, `RAYLAB_SOURCE`: a hash of every file
//!    under `src/` and `chapters/` and of `Cargo.lock`. The judge (raylab's
//!    own binary) and a student's binary speak one protocol only when both
//!    were built from the same source (src/check/protocol.rs), so that a
//!    workspace built against another raylab gets a clear message, never a
//!    wrong verdict.
//!
//! 3. Without the `embree` feature, nothing else (the default build needs
//!    neither Embree nor libclang). With the feature, it tells the linker
//!    where `libembree4` is, because `embree4-sys` only says `-lembree4`
//!    and reads no variable:
//!    - the Embree folder is `$RAYLAB_EMBREE_DIR` if set and non-empty,
//!      else `<crate>/.embree`, which `scripts/setup-embree.sh` fills from
//!      the pinned `embreex` wheel on distributions without Embree 4;
//!    - its library folder is `<dir>/lib` if that exists, else `<dir>`;
//!    - if that folder holds `libembree4.so` (or `.dylib`), we add it to
//!      the link search path and as an rpath, so binaries, tests and
//!      doctests run without `LD_LIBRARY_PATH`;
//!    - otherwise we rely on the system's linker path (`libembree-dev` on
//!      Debian 13 / Ubuntu 24.04, Homebrew's embree on macOS).
//!
//! See docs/embree.md.
use std::env;
use std::path::{Path, PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    inline_lesson_images();
    source_fingerprint();
    if env::var_os("CARGO_FEATURE_EMBREE").is_none() {
        return;
    }
    println!("cargo:rerun-if-env-changed=RAYLAB_EMBREE_DIR");
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    let default_dir = manifest.join(".embree");
    // The set-up script's stamp: running the script after a failed build
    // re-runs this script, with no `cargo clean`.
    println!(
        "cargo:rerun-if-changed={}",
        default_dir.join(".done").display()
    );
    let chosen = env::var("RAYLAB_EMBREE_DIR")
        .ok()
        .filter(|dir| !dir.is_empty());
    let dir = chosen.clone().map_or(default_dir, PathBuf::from);
    let lib = if dir.join("lib").is_dir() {
        dir.join("lib")
    } else {
        dir.clone()
    };
    let found = ["libembree4.so", "libembree4.dylib"]
        .iter()
        .map(|name| lib.join(name))
        .find(|path| path.exists());
    if let Some(path) = found {
        println!("cargo:rerun-if-changed={}", path.display());
        println!("cargo:rustc-link-search=native={}", lib.display());
        println!("cargo:rustc-link-arg=-Wl,-rpath,{}", lib.display());
        return;
    }
    if chosen.is_some() {
        println!(
            "cargo:warning=RAYLAB_EMBREE_DIR={} has no libembree4.so in {}",
            dir.display(),
            lib.display()
        );
    }
    let system_dirs = [
        "/usr/lib",
        "/usr/lib64",
        "/usr/local/lib",
        "/usr/lib/x86_64-linux-gnu",
        "/usr/lib/aarch64-linux-gnu",
        "/opt/homebrew/lib",
    ];
    let on_system = system_dirs.iter().any(|dir| {
        let dir = Path::new(dir);
        dir.join("libembree4.so").exists() || dir.join("libembree4.dylib").exists()
    });
    if !on_system {
        println!(
            "cargo:warning=feature `embree`: no libembree4 found; run scripts/setup-embree.sh \
             (or set RAYLAB_EMBREE_DIR), see docs/embree.md"
        );
    }
}

/// Hashes the files the judge and a student's binary must share (see the
/// top of this file) into `RAYLAB_SOURCE`: FNV-1a, 64 bits, over each
/// file's path relative to the crate and its bytes, in path order.
fn source_fingerprint() {
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    let mut files = vec![manifest.join("Cargo.lock")];
    for folder in ["src", "chapters"] {
        println!("cargo:rerun-if-changed={}", manifest.join(folder).display());
        collect_files(&manifest.join(folder), &mut files);
    }
    files.sort();
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut feed = |bytes: &[u8]| {
        for &byte in bytes {
            hash ^= u64::from(byte);
            hash = hash.wrapping_mul(0x0100_0000_01b3);
        }
    };
    for file in &files {
        let relative = file.strip_prefix(&manifest).unwrap_or(file);
        feed(relative.to_string_lossy().as_bytes());
        feed(&[0]);
        feed(&std::fs::read(file).unwrap_or_default());
        feed(&[0]);
    }
    println!("cargo:rustc-env=RAYLAB_SOURCE={hash:016x}");
}

/// Every file under `folder`, recursively (links are not followed).
fn collect_files(folder: &Path, files: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(folder) else {
        return;
    };
    for entry in entries.flatten() {
        let Ok(kind) = entry.file_type() else {
            continue;
        };
        if kind.is_dir() {
            collect_files(&entry.path(), files);
        } else if kind.is_file() {
            files.push(entry.path());
        }
    }
}

/// Writes every lesson (`chapters/README.md` and each chapter folder's
/// `lesson.md`, as `NN_name.md`) to `$OUT_DIR/lessons/` with its local
/// images inlined (see the top of this file).
fn inline_lesson_images() {
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    let chapters = manifest.join("chapters");
    let out = PathBuf::from(env::var_os("OUT_DIR").unwrap_or_default()).join("lessons");
    println!("cargo:rerun-if-changed={}", chapters.display());
    if let Err(error) = std::fs::create_dir_all(&out) {
        println!("cargo:warning=cannot create {}: {error}", out.display());
        return;
    }
    let Ok(entries) = std::fs::read_dir(&chapters) else {
        println!("cargo:warning=cannot read {}", chapters.display());
        return;
    };
    let mut lessons = vec![(chapters.join("README.md"), "README.md".to_string())];
    for entry in entries.flatten() {
        let lesson = entry.path().join("lesson.md");
        if lesson.is_file() {
            let name = entry.file_name().to_string_lossy().into_owned();
            lessons.push((lesson, format!("{name}.md")));
        }
    }
    for (path, name) in lessons {
        println!("cargo:rerun-if-changed={}", path.display());
        let Ok(text) = std::fs::read_to_string(&path) else {
            println!("cargo:warning=cannot read {}", path.display());
            continue;
        };
        let folder = path.parent().unwrap_or(&chapters);
        let inlined = inline_images(&text, folder);
        let target = out.join(name);
        if let Err(error) = std::fs::write(&target, inlined) {
            println!("cargo:warning=cannot write {}: {error}", target.display());
        }
    }
}

/// `markdown` with each `![alt](local/path)` image replaced by a `data:`
/// URI of the file, `local/path` taken relative to `folder`. Web addresses,
/// `data:` URIs and unreadable files are left as they are.
fn inline_images(markdown: &str, folder: &Path) -> String {
    let mut out = String::with_capacity(markdown.len());
    let mut rest = markdown;
    while let Some(start) = rest.find("![") {
        // The `(` right after the alt text's `]`, and the closing `)`.
        // On the same line: `#![allow(...)]` in a code block is no image.
        let line_end = rest[start..].find('\n').map_or(rest.len(), |at| start + at);
        let Some(close) = rest[start..line_end].find("](").map(|at| start + at) else {
            out.push_str(&rest[..start + 2]);
            rest = &rest[start + 2..];
            continue;
        };
        let target_start = close + 2;
        let Some(target_end) = rest[target_start..].find(')').map(|at| target_start + at) else {
            break;
        };
        out.push_str(&rest[..target_start]);
        let target = &rest[target_start..target_end];
        out.push_str(&inline_one(target, folder).unwrap_or_else(|| target.to_string()));
        rest = &rest[target_end..];
    }
    out.push_str(rest);
    out
}

/// The `data:` URI of the local image `target` (relative to `folder`), or
/// `None` to leave it alone.
fn inline_one(target: &str, folder: &Path) -> Option<String> {
    if target.contains(':') || target.contains(char::is_whitespace) || target.is_empty() {
        return None;
    }
    let path = folder.join(target);
    println!("cargo:rerun-if-changed={}", path.display());
    let mime = match path.extension()?.to_str()? {
        "png" => "image/png",
        "svg" => "image/svg+xml",
        "jpg" | "jpeg" => "image/jpeg",
        "gif" => "image/gif",
        _ => return None,
    };
    match std::fs::read(&path) {
        Ok(bytes) => Some(format!("data:{mime};base64,{}", base64(&bytes))),
        Err(error) => {
            println!(
                "cargo:warning=lesson image {} cannot be read: {error}",
                path.display()
            );
            None
        }
    }
}

/// Standard base64 with padding (RFC 4648), written here so the build
/// script needs no dependency.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for (index, shift) in [18, 12, 6, 0].into_iter().enumerate() {
            if index <= chunk.len() {
                out.push(char::from(ALPHABET[((n >> shift) & 63) as usize]));
            } else {
                out.push('=');
            }
        }
    }
    out
}
