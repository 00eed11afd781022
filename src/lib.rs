//! # raylab: Whitted-style ray tracing, one runnable chapter at a time
//!
//! Each chapter is a module of [`chapters`] whose documentation is the
//! lesson and whose code is the idea it teaches, nothing else; the
//! [`chapters`] page lists them, and its registry is the one list of them.
//!
//! Render any stage with `raylab render --chapter N`. The seam between the
//! lessons and the rest is one trait, [`course::Chapters`]: every function a
//! student writes, chapter by chapter, with raylab's answers as
//! [`Reference`]. The renderer is generic over it, so it runs raylab's
//! chapters or a student's (`raylab new` makes a workspace, [`check`] gives
//! the verdict per chapter). The scaffolding that is not a lesson lives
//! beside: [`scene`] (TOML scene files), [`shapes`] (the primitives' data),
//! [`camera`], [`mod@render`] (the image loop and the tracer the chapters
//! drive), [`output`] (sRGB, PNG, hashes), [`effects`] (which chapter enables
//! what). For instructors, [`diff`] and [`grade`] compare student
//! renders with the references (`raylab diff`, `raylab grade`). With the
//! `embree` feature, [`crosscheck`] compares our
//! intersections with Embree's on every ray a render casts (docs/embree.md).
//! Files a user names are read through [`input`] (regular files only, with
//! stated size limits), names are printed through [`text`] (no terminal
//! control characters), and [`cleanup`] removes temporary files on signals.

// `!(x > y)` is how this crate writes "not greater, or NaN": rejecting NaN
// without a separate test is deliberate, and the lessons explain it.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Built for a student workspace, the reference chapters' code is private
// and raylab's answers are left out (see the `student` feature): what only
// a student could have called, and the arguments of an answer left out,
// are then unused, which is the point.
#![cfg_attr(
    feature = "student",
    allow(dead_code, unused_imports, unused_variables, unreachable_code)
)]
// The crate docs are the lessons, which students read (`cargo doc --open`,
// the browser page): a "Source" link would open the reference solutions,
// the answer key. scripts/check-docs-no-source.sh fails if one comes back.
#![doc(html_no_source)]

// The browser page (web/) builds this crate for WebAssembly without the
// command line, grading, the cost tables and their plots: see Cargo.toml.

// The chapter files name raylab's items as `raylab::...`, as a student
// workspace does, so that the same text compiles in both places.
extern crate self as raylab;

#[path = "../chapters/mod.rs"]
pub mod chapters;

pub mod answer_key;
pub mod builtin;
pub mod bvh;
pub mod bvh_reports;
pub mod camera;
pub mod check;
pub mod cleanup;
#[cfg(not(target_arch = "wasm32"))]
pub mod cli;
pub mod course;
pub mod diff;
pub mod effects;
#[cfg(feature = "embree")]
pub mod embree;
#[cfg(not(target_arch = "wasm32"))]
pub mod grade;
pub mod input;
pub mod limits;
pub mod medium;
pub mod mesh;
mod number;
pub mod output;
pub mod ray;
pub mod ray_tree;
pub mod record;
pub mod render;
pub mod scene;
pub mod seam;
pub mod shapes;
pub mod spectrum;
pub mod text;
pub mod web;
pub mod workspace;

/// raylab's tools over a student's chapters: the cost sweeps, the
/// cross-checks, the figures, the implicit surfaces' probe and the plots.
/// Each computes with raylab's own answers (its oracles, its reference
/// chapters) and reports none of it, so in a student's build (feature
/// `student`) they are raylab's alone: a chapter that called one would
/// pass with raylab's answer.
macro_rules! tools {
    ($($(#[$attribute:meta])* $module:ident;)*) => {$(
        $(#[$attribute])*
        #[cfg(not(feature = "student"))]
        pub mod $module;
        $(#[$attribute])*
        #[cfg(feature = "student")]
        pub(crate) mod $module;
    )*};
}
tools! {
    #[cfg(not(target_arch = "wasm32"))]
    cost;
    crosscheck;
    figure;
    implicit_probe;
    #[cfg(not(target_arch = "wasm32"))]
    plots;
}

/// The 3-vector used everywhere: points, directions and linear RGB colours.
pub use glam::Vec3;
/// Four `f32` lanes computed together: chapter 11's wide tree tests four
/// boxes, or four triangles, at once with them.
pub use glam::Vec4;

pub use chapters::Reference;
#[cfg(not(feature = "student"))]
pub use chapters::{fresnel, reflect, refract, schlick};
#[cfg(feature = "student")]
pub(crate) use chapters::{fresnel, reflect, refract, schlick};
pub use course::{Chapters, Hit, HitPoint, Objects, first_hit, nearest_hit};
pub use ray::{Ray, unit_vector};
pub use record::{RayRecorder, record_rays};
pub use render::bsdf;
pub use render::{
    CastRay, RayCounts, RayKind, RayLog, RenderError, Rendered, Stage, Tracer, render,
    render_linear_with, render_with,
};
pub use scene::{Material, RenderSettings, Sampling, Scene, SceneError};
pub use shapes::{Plane, Shape, Sphere, SurfacePoint};
