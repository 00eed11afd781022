//! `raylab web`: the browser page, built from the chapters this binary runs.

use std::path::PathBuf;
use std::process::Command as Process;

use anyhow::{Context, Result, bail};
use clap::Args;

use crate::Chapters;
use crate::workspace::RAYLAB_DIR;

/// Build the browser page (WebAssembly, the page's files and the lessons)
/// into a folder any static web server can serve. In a workspace it
/// builds your chapters, so you can click on your own pixels; elsewhere,
/// raylab's. Needs rustup's wasm32-unknown-unknown target, or Debian's
/// rustc-web where rustup cannot add it (raylab's scripts/setup-wasm.sh
/// fetches it); says so and fails where neither is possible.
#[derive(Debug, Args)]
pub struct WebArgs {
    /// Where the page goes [default: web/ in a workspace, raylab-web/ elsewhere].
    #[arg(short, long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

pub fn web<C: Chapters>(args: &WebArgs) -> Result<i32> {
    let raylab_dir = PathBuf::from(RAYLAB_DIR);
    let script = raylab_dir.join("scripts/build-web.sh");
    if !script.is_file() {
        bail!(
            "{} is missing: this raylab was built from {}, which no longer holds raylab's scripts",
            script.display(),
            raylab_dir.display()
        );
    }
    let here = std::env::current_dir().context("cannot read the current folder")?;
    let reference = std::any::TypeId::of::<C>() == std::any::TypeId::of::<crate::Reference>();
    let (crate_dir, out, target) = if reference {
        let out = args.out.clone().unwrap_or_else(|| here.join("raylab-web"));
        (raylab_dir.join("web"), out, None)
    } else {
        let workspace = crate::workspace::enclosing_workspace(&here)
            .context("your chapters' page is built from inside your workspace")?;
        let manifest = std::fs::read_to_string(workspace.join("Cargo.toml"))
            .with_context(|| format!("cannot read {}/Cargo.toml", workspace.display()))?;
        let package = manifest
            .parse::<toml::Table>()
            .ok()
            .and_then(|table| {
                table
                    .get("package")?
                    .get("name")?
                    .as_str()
                    .map(str::to_string)
            })
            .with_context(|| format!("{}/Cargo.toml names no package", workspace.display()))?;
        let files = crate::workspace::web_crate(
            &workspace,
            &package,
            std::any::type_name::<C>(),
            &raylab_dir,
        )?;
        let crate_dir = workspace.join("target/raylab-web");
        std::fs::create_dir_all(&crate_dir)
            .with_context(|| format!("cannot create {}", crate_dir.display()))?;
        let mut written: Vec<(PathBuf, Vec<u8>)> = files
            .0
            .iter()
            .map(|(name, text)| (crate_dir.join(name), text.clone().into_bytes()))
            .collect();
        // The versions the workspace builds with, not newer ones.
        if let Ok(lock) = std::fs::read(workspace.join("Cargo.lock")) {
            written.push((crate_dir.join("Cargo.lock"), lock));
        }
        let borrowed: Vec<(&std::path::Path, &[u8])> = written
            .iter()
            .map(|(path, bytes)| (path.as_path(), bytes.as_slice()))
            .collect();
        crate::output::write_files(&borrowed)?;
        let out = args.out.clone().unwrap_or_else(|| workspace.join("web"));
        (crate_dir.clone(), out, Some(crate_dir.join("target")))
    };
    let mut build = Process::new("bash");
    build
        .arg(&script)
        .arg("--crate")
        .arg(&crate_dir)
        .arg("--out")
        .arg(&out);
    if let Some(target) = target {
        build.env("RAYLAB_WASM_TARGET_DIR", target);
    }
    let status = build
        .status()
        .with_context(|| format!("cannot run bash {}", script.display()))?;
    match status.code() {
        Some(0) => Ok(0),
        Some(3) => bail!("the page cannot be built on this machine (the reason is above)"),
        _ => bail!("building the page failed ({status})"),
    }
}
