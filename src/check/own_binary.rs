//! Where a student's build finds raylab's own binary, which judges.
//!
//! A student's build of raylab (the `student` feature) leaves raylab's
//! answers out (see [`crate::answer_key::left_out`]): nothing inside the
//! process a student's code runs in can reach them, whatever that code
//! does to the process's memory. The judge needs them, so a workspace's
//! `check` and its `cargo test` hand the judging to raylab's own binary,
//! built from the same source without the feature, which asks the
//! student's binary its questions (`serve`) and decides.
//!
//! The binary is, in this order: `$RAYLAB_JUDGE` when set; the `raylab`
//! on the `PATH` (`cargo install --path` of the class's copy); the release
//! build in the raylab folder the workspace names (where `cargo run
//! --release -- new` left it); else that build, made now with cargo. Each
//! must have been built from the very source the workspace's raylab was
//! ([`crate::check::protocol::SOURCE`]), or it is passed over.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use super::protocol::SOURCE;

/// The environment variable naming the judge's binary.
pub const JUDGE_VAR: &str = "RAYLAB_JUDGE";

/// The folder of the raylab source this build was made from.
const RAYLAB_DIR: &str = env!("CARGO_MANIFEST_DIR");

/// Why no judge could be found.
#[derive(Debug, thiserror::Error)]
pub enum NoJudge {
    #[error(
        "{JUDGE_VAR} names {path}, which is not raylab built from this workspace's raylab \
         ({why}): unset it, or build raylab in {RAYLAB_DIR} (`cargo build --release`)"
    )]
    Named { path: PathBuf, why: String },
    #[error(
        "cannot build raylab's own binary, which judges your chapters: `cargo build --release` \
         in {RAYLAB_DIR} {why}. Build it there yourself, or ask your instructor for the \
         class's `raylab`"
    )]
    Build { why: String },
}

/// raylab's own binary, built from this source: found, or built (after
/// `building()`, which the command line has say so: the first build takes
/// minutes).
pub fn judge_binary(building: &dyn Fn()) -> Result<PathBuf, NoJudge> {
    if let Some(named) = std::env::var_os(JUDGE_VAR).filter(|named| !named.is_empty()) {
        let path = PathBuf::from(named);
        return match source_of(&path) {
            Ok(source) if source == SOURCE => Ok(path),
            Ok(_) => Err(NoJudge::Named {
                path,
                why: "it was built from another source".into(),
            }),
            Err(why) => Err(NoJudge::Named { path, why }),
        };
    }
    let candidates = on_path("raylab")
        .into_iter()
        .chain([Path::new(RAYLAB_DIR).join("target/release/raylab")]);
    for candidate in candidates {
        if source_of(&candidate).is_ok_and(|source| source == SOURCE) {
            return Ok(candidate);
        }
    }
    building();
    let built = build()?;
    match source_of(&built) {
        Ok(source) if source == SOURCE => Ok(built),
        Ok(_) => Err(NoJudge::Build {
            why: "made a binary of another source (did the folder change since the workspace \
                  was built?)"
                .into(),
        }),
        Err(why) => Err(NoJudge::Build { why }),
    }
}

/// The source fingerprint `binary` was built from (its hidden
/// `fingerprint` command), or why it cannot tell.
fn source_of(binary: &Path) -> Result<String, String> {
    let output = Command::new(binary)
        .arg("fingerprint")
        .stdin(Stdio::null())
        .stderr(Stdio::null())
        .output()
        .map_err(|error| format!("cannot run it: {error}"))?;
    if !output.status.success() {
        return Err("it has no `fingerprint` command".into());
    }
    Ok(String::from_utf8_lossy(&output.stdout).trim().to_string())
}

/// The first file called `name` in the `PATH`'s folders.
fn on_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|folder| folder.join(name))
        .find(|candidate| candidate.is_file())
}

/// Builds raylab's binary in its own folder (its own `target/`, unless
/// the caller's `CARGO_TARGET_DIR` says otherwise), cargo's progress on
/// standard error, and returns where cargo put it.
fn build() -> Result<PathBuf, NoJudge> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| OsString::from("cargo"));
    let manifest = Path::new(RAYLAB_DIR).join("Cargo.toml");
    let output = Command::new(cargo)
        .args([
            "build",
            "--release",
            "--bin",
            "raylab",
            "--message-format=json",
        ])
        .arg("--manifest-path")
        .arg(&manifest)
        .stdin(Stdio::null())
        .stderr(Stdio::inherit())
        .output()
        .map_err(|error| NoJudge::Build {
            why: format!("could not start cargo: {error}"),
        })?;
    if !output.status.success() {
        return Err(NoJudge::Build {
            why: "failed (its messages are above)".into(),
        });
    }
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter_map(|line| serde_json::from_str::<serde_json::Value>(line).ok())
        .filter(|message| message["reason"] == "compiler-artifact")
        .filter(|message| message["target"]["name"] == "raylab")
        .find_map(|message| message["executable"].as_str().map(PathBuf::from))
        .ok_or_else(|| NoJudge::Build {
            why: "reported no binary".into(),
        })
}
