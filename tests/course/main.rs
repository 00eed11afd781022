//! The course: the checker and its bug gallery, the chapters' galleries,
//! the seams between chapters, the registry against the docs, and the hard
//! cases and properties of the intersections (one test binary; each module
//! was a file of its own under `tests/`).

#[path = "../common/rays.rs"]
mod rays;

mod bvh;
mod chapter_seam;
mod check;
mod docs_registry;
mod hard_cases;
mod properties;
mod scene_fuzz;
