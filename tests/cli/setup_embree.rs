//! `scripts/setup-embree.sh --check` as a user without root: it reports what
//! is missing and asks for root only for a system package it would install
//! (set-up without root). `--check` changes nothing, so these
//! tests can run anywhere; they skip where the script cannot (no bash or no
//! apt, as on a non-Debian system).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A copy of the script in a fresh folder that any user can read: the
/// checkout may sit in a home folder that `nobody` cannot enter. (`--check`
/// only looks at the copy's `.embree`, which does not exist.)
fn script_copy() -> (tempfile::TempDir, PathBuf) {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().expect("temp dir");
    let scripts = dir.path().join("scripts");
    std::fs::create_dir(&scripts).expect("mkdir");
    let copy = scripts.join("setup-embree.sh");
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/setup-embree.sh"),
        &copy,
    )
    .expect("copy the script");
    for path in [dir.path(), scripts.as_path(), copy.as_path()] {
        std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    }
    (dir, copy)
}

fn found(tool: &str) -> Option<PathBuf> {
    std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|dir| dir.join(tool))
            .find(|path| path.is_file())
    })
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|out| String::from_utf8_lossy(&out.stdout).trim() == "0")
}

/// Runs `--check` as a user without root: as `nobody` through `setpriv`
/// when the tests run as root, else as the current (non-root) user. `None`
/// where neither is possible, or the script's tools are missing.
fn check_without_root(path: Option<&str>) -> Option<Output> {
    if found("bash").is_none() || found("apt-get").is_none() || found("dpkg-query").is_none() {
        return None;
    }
    let mut command = if is_root() {
        let mut command = Command::new(found("setpriv")?);
        command.args(["--reuid=65534", "--regid=65534", "--clear-groups", "bash"]);
        command
    } else {
        Command::new("bash")
    };
    let (_dir, script) = script_copy();
    command.arg(&script).arg("--check");
    if let Some(path) = path {
        command.env("PATH", path);
    }
    command.env_remove("LIBCLANG_PATH");
    let output = command.output().expect("run setup-embree.sh");
    Some(output)
}

fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

fn libclang_installed() -> bool {
    Command::new("dpkg-query")
        .args(["-W", "-f=${Status}", "libclang-dev"])
        .output()
        .is_ok_and(|out| String::from_utf8_lossy(&out.stdout).contains("install ok installed"))
}

#[test]
fn with_libclang_installed_no_root_is_needed() {
    if !libclang_installed() {
        eprintln!("skipped: libclang-dev is not installed here");
        return;
    }
    let Some(output) = check_without_root(None) else {
        eprintln!("skipped: cannot run the script as a user without root here");
        return;
    };
    let report = text(&output);
    // Without root the script still finds what it can use, rather than
    // stopping at "not root and no sudo: install packages by hand".
    assert!(!report.contains("ERROR"), "{report}");
    assert!(report.contains("libclang: found"), "{report}");
    if report.contains("embreex") {
        assert!(report.contains("root needed: no"), "{report}");
        assert_eq!(output.status.code(), Some(0), "{report}");
    }
}

#[test]
fn a_missing_package_is_named_as_what_needs_root() {
    // A PATH with the script's tools but no sudo, and a dpkg-query that
    // knows no installed package: libclang is missing, and only root can
    // install it.
    let dir = tempfile::tempdir().expect("temp dir");
    let tools = [
        "bash",
        "id",
        "uname",
        "dirname",
        "apt-get",
        "apt-cache",
        "awk",
        "grep",
        "cut",
        "sha256sum",
        "cat",
        "python3",
        "curl",
    ];
    for tool in tools {
        if let Some(path) = found(tool) {
            std::os::unix::fs::symlink(path, dir.path().join(tool)).expect("symlink");
        }
    }
    let stub = dir.path().join("dpkg-query");
    std::fs::write(&stub, "#!/bin/sh\nexit 1\n").expect("write stub");
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&stub, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    // `nobody` must be able to enter the folder.
    std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o755)).expect("chmod");
    let path = dir.path().to_string_lossy().into_owned();
    let Some(output) = check_without_root(Some(&path)) else {
        eprintln!("skipped: cannot run the script as a user without root here");
        return;
    };
    let report = text(&output);
    assert!(report.contains("libclang: MISSING"), "{report}");
    assert!(
        report.contains("root needed: yes, to apt-get install libclang-dev"),
        "{report}"
    );
    assert!(
        report.contains("you are not root and have no sudo"),
        "{report}"
    );
    assert_eq!(output.status.code(), Some(1), "{report}");
}
