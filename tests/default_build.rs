//! What the default build, without the optional `embree` feature, does
//! differently: `crosscheck` explains how to get Embree, and `probe` traces
//! its ray on raylab's side only. scripts/test.sh runs this file in the
//! release build the pinned images use, which has no optional feature, so
//! that the suite needs no debug build of raylab without Embree.

#![cfg(not(feature = "embree"))]

use std::process::{Command, Output};

fn raylab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(args)
        .output()
        .expect("run raylab")
}

#[test]
fn crosscheck_without_embree_says_how_to_enable_it() {
    let out = raylab(&["crosscheck", "--chapter", "1"]);
    assert_eq!(out.status.code(), Some(2));
    let message = String::from_utf8_lossy(&out.stderr);
    assert!(message.contains("scripts/setup-embree.sh"), "{message}");
    assert!(message.contains("--features embree"), "{message}");
    assert!(message.contains("docs/embree.md"), "{message}");
    let probe = raylab(&["probe", "--ray", "0,1,-5,0,0,1"]);
    assert!(
        probe.status.success(),
        "{}",
        String::from_utf8_lossy(&probe.stderr)
    );
    assert!(String::from_utf8_lossy(&probe.stdout).contains("embree: not built in"));
}
