//! The `raylab` binary run as a user runs it, and the scripts around it
//! (one test binary; each module was a file of its own under `tests/`).

#[path = "../common/mod.rs"]
mod common;

mod cli;
mod cli_options;
mod cost;
mod diff;
mod exr;
mod figures;
mod grade;
mod lesson_api;
mod mesh;
mod sandbox;
mod setup_embree;
mod workspace;
