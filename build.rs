//! Build script. Without the `embree` feature it does nothing (and the
//! default build needs neither Embree nor libclang).
//!
//! With the feature, it tells the linker where `libembree4` is, because
//! `embree4-sys` only says `-lembree4` and reads no variable:
//! - the Embree folder is `$RAYLAB_EMBREE_DIR` if set and non-empty, else
//!   `<crate>/.embree`, which `scripts/setup-embree.sh` fills from the pinned
//!   `embreex` wheel on distributions without Embree 4;
//! - its library folder is `<dir>/lib` if that exists, else `<dir>`;
//! - if that folder holds `libembree4.so` (or `.dylib`), we add it to the
//!   link search path and as an rpath, so binaries, tests and doctests run
//!   without `LD_LIBRARY_PATH`;
//! - otherwise we rely on the system's linker path (`libembree-dev` on
//!   Debian 13 / Ubuntu 24.04, Homebrew's embree on macOS).
//!
//! See docs/embree.md.
use std::env;
use std::path::{Path, PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
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
