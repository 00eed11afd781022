#![doc = include_str!(concat!(env!("OUT_DIR"), "/lessons/README.md"))]

#[path = "01_plane.rs"]
pub mod ch01_plane;
#[path = "02_sphere.rs"]
pub mod ch02_sphere;
#[path = "03_nearest.rs"]
pub mod ch03_nearest;
#[path = "04_shadows.rs"]
pub mod ch04_shadows;
#[path = "05_phong.rs"]
pub mod ch05_phong;
#[path = "06_reflection.rs"]
pub mod ch06_reflection;
#[path = "07_antialiasing.rs"]
pub mod ch07_antialiasing;
#[path = "08_refraction.rs"]
pub mod ch08_refraction;
#[path = "09_glass.rs"]
pub mod ch09_glass;
#[path = "10_triangles.rs"]
pub mod ch10_triangles;
#[path = "11_bvh.rs"]
pub mod ch11_bvh;

/// raylab's own answer to every chapter: the functions of the modules
/// above, which are the [`crate::course::Chapters`] trait's defaults.
#[derive(Debug, Clone, Copy, Default)]
pub struct Reference;

impl crate::course::Chapters for Reference {}
