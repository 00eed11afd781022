//! Renders: the pinned images, their independence from threads, the
//! effects each scene switches on, robustness of the shading, scene values
//! at the edges of `f32`, and the images inlined in the lessons (one test
//! binary; each module was a file of its own under `tests/`).

mod determinism;
mod effects;
mod lesson_images;
mod ray_trees;
mod render_robustness;
mod scene_values;
mod snapshots;
