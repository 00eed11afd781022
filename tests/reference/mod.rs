//! The `f64` reference shared by the hard-case and property tests: the
//! checker's own ([`raylab::check::exact`]: every problem solved from the
//! same `f32` inputs, widened exactly, with formulas written separately from
//! the library's), plus the normal at each hit.
#![allow(dead_code)]

use glam::DVec3;
#[allow(unused_imports)] // not every test file uses every function
pub use raylab::check::exact::{angle, reflect, refract, sphere_roots};

#[derive(Debug, Clone, Copy)]
pub struct Hit {
    pub t: f64,
    /// Unit normal at the hit.
    pub normal: DVec3,
}

pub fn sphere(center: DVec3, r: f64, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<Hit> {
    let t = raylab::check::exact::sphere(center, r, o, d, t_min, t_max)?;
    Some(Hit {
        t,
        normal: (o + t * d - center) / r,
    })
}

pub fn plane(
    point: DVec3,
    normal: DVec3,
    o: DVec3,
    d: DVec3,
    t_min: f64,
    t_max: f64,
) -> Option<Hit> {
    let t = raylab::check::exact::plane(point, normal, o, d, t_min, t_max)?;
    Some(Hit {
        t,
        normal: normal / normal.length(),
    })
}
