//! # raylab: Whitted-style ray tracing, one runnable chapter at a time
//!
//! Each chapter is a module of [`chapters`] whose documentation is the
//! lesson and whose code is the idea it teaches, nothing else:
//!
//! | chapter | module | adds |
//! |---|---|---|
//! | 1 | [`chapters::ch01_plane`] | ray-plane intersection |
//! | 2 | [`chapters::ch02_sphere`] | ray-sphere intersection |
//! | 3 | [`chapters::ch03_nearest`] | the nearest hit among all primitives |
//! | 4 | [`chapters::ch04_shadows`] | hard shadows, and where a secondary ray starts |
//! | 5 | [`chapters::ch05_phong`] | Phong illumination |
//! | 6 | [`chapters::ch06_reflection`] | recursive mirror reflection |
//! | 7 | [`chapters::ch07_antialiasing`] | anti-aliasing by supersampling |
//! | 8 | [`chapters::ch08_refraction`] | refraction and total internal reflection |
//! | 9 | [`chapters::ch09_glass`] | Fresnel reflectance, nested media, absorption |
//! | 10 | [`chapters::ch10_triangles`] | triangle meshes, watertight intersection, smooth shading |
//! | 11 | [`chapters::ch11_bvh`] | a bounding volume hierarchy: the same hits, found sooner |
//!
//! Render any stage with `raylab render --chapter N`. The seam between the
//! lessons and the rest is one trait, [`course::Chapters`]: every function a
//! student writes, chapter by chapter, with raylab's answers as
//! [`Reference`]. The renderer is generic over it, so it runs raylab's
//! chapters or a student's (`raylab new` makes a workspace, [`check`] gives
//! the verdict per chapter). The scaffolding that is not a lesson lives
//! beside: [`scene`] (TOML scene files), [`shapes`] (the primitives' data),
//! [`camera`], [`mod@render`] (the image loop and the tracer the chapters
//! drive), [`output`] (sRGB, PNG, hashes), [`stage`] (the chapter registry
//! and which chapter enables what). For instructors, [`diff`] and [`grade`] compare student
//! renders with the references (`raylab diff`, `raylab grade`). With the
//! `embree` feature, [`crosscheck`] compares our
//! intersections with Embree's on every ray a render casts (docs/embree.md).
//! Files a user names are read through [`input`] (regular files only, with
//! stated size limits), names are printed through [`text`] (no terminal
//! control characters), and [`cleanup`] removes temporary files on signals.

// `!(x > y)` is how this crate writes "not greater, or NaN": rejecting NaN
// without a separate test is deliberate, and the lessons explain it.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

// The chapter files name raylab's items as `raylab::...`, as a student
// workspace does, so that the same text compiles in both places.
extern crate self as raylab;

#[path = "../chapters/mod.rs"]
pub mod chapters;

pub mod builtin;
pub mod bvh;
pub mod bvh_cost;
pub mod bvh_measure;
pub mod bvh_report;
pub mod camera;
pub mod check;
pub mod cleanup;
pub mod cli;
pub mod cost;
pub mod course;
pub mod crosscheck;
pub mod diff;
#[cfg(feature = "embree")]
pub mod embree;
pub mod grade;
pub mod input;
pub mod leaks;
pub mod medium;
pub mod mesh;
pub mod output;
pub mod plots;
#[cfg(feature = "embree")]
pub mod race;
pub mod ray;
pub mod render;
pub mod scene;
pub mod shapes;
pub mod stage;
pub mod text;
pub mod walk_work;
pub mod workspace;

/// The 3-vector used everywhere: points, directions and linear RGB colours.
pub use glam::Vec3;

pub use chapters::Reference;
pub use chapters::ch06_reflection::reflect;
pub use chapters::ch07_antialiasing::Sampling;
pub use chapters::ch08_refraction::refract;
pub use chapters::ch09_glass::{fresnel, schlick};
pub use course::{Chapters, Hit, HitPoint, Objects, first_hit, nearest_hit};
pub use ray::{Ray, unit_vector};
pub use render::{
    CastRay, RayCounts, RayKind, RayLog, RayRecorder, RenderError, Rendered, Stage, Tracer,
    record_rays, render, render_with,
};
pub use scene::{Material, RenderSettings, Scene, SceneError};
pub use shapes::{Plane, Shape, Sphere, SurfacePoint};
