//! Measuring the acceleration: what chapter 11's tree costs and saves, and
//! what chapter 10's watertight triangle test buys. [`cost`] times the tree
//! against chapter 3's loop (build and trace time as triangles grow, split
//! rule and leaf size, the sphere count from which a tree pays), on top of
//! [`measure`]'s medians of thread CPU time, and [`mod@format`] turns its
//! report into Markdown tables and an SVG plot (`raylab cost --chapter 11`).
//! [`walk_work`] counts the boxes and objects a walk tests per ray, [`leaks`]
//! the rays that slip through a closed mesh (`raylab cost --chapter 10`),
//! and, with the `embree` feature, `race` sets the tree against Embree
//! (`raylab race`).
//!
//! These are tools, in the tools layer of docs/architecture.md: they use the
//! engine and the reference chapters, and the engine never imports them, so
//! a render runs the same whether or not anyone measures it.

pub mod cost;
#[cfg(not(target_arch = "wasm32"))]
pub mod format;
pub mod leaks;
pub mod measure;
#[cfg(feature = "embree")]
pub mod race;
pub mod walk_work;
