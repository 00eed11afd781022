//! Running the `raylab` binary from the integration tests, as a user would.
//! Each test file that needs it says `mod common;`; not every file uses every
//! helper, hence the `dead_code` allowance.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Runs `raylab args...` in `dir` and waits for it.
pub fn raylab(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run raylab")
}

pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}
