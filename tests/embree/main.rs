//! Our intersections against Embree 4 (feature `embree`; without it this
//! binary is empty, so the default build needs no Embree). One test binary;
//! each module was a file of its own under `tests/`.
#![cfg(feature = "embree")]

mod embree;
mod embree_implicit;
mod embree_triangles;
