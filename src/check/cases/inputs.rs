//! How the inputs line of a failing case writes numbers, vectors, rays
//! and shapes: as a student would type them.

use super::*;

impl Case {
    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        self.kind.inputs()
    }
}

/// The interval of `t` a call asks about.
pub(super) fn range(t_min: f32, t_max: f32) -> String {
    format!("t_min = {}, t_max = {}", num(t_min), num(t_max))
}

/// A number as a student would write it: short, exponent for the very
/// large and very small.
pub fn num(x: f32) -> String {
    num64(f64::from(x))
}

pub fn num64(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return if x.is_nan() {
            "NaN".into()
        } else if x.is_infinite() {
            if x > 0.0 { "inf".into() } else { "-inf".into() }
        } else {
            "0".into()
        };
    }
    let magnitude = x.abs();
    if !(1e-4..1e7).contains(&magnitude) {
        return format!("{x:.6e}")
            .replace("0000e", "e")
            .replace("000e", "e")
            .replace("00e", "e")
            .replace("0e", "e")
            .replace(".e", "e");
    }
    let text = format!("{x:.7}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    text.to_string()
}

pub fn vec(v: Vec3) -> String {
    format!("({}, {}, {})", num(v.x), num(v.y), num(v.z))
}

pub(super) fn vec64(v: DVec3) -> String {
    format!("({}, {}, {})", num64(v.x), num64(v.y), num64(v.z))
}

pub(super) fn ray_text(ray: &Ray) -> String {
    format!("ray from {} along {}", vec(ray.origin), vec(ray.dir))
}

pub(super) fn corners_text([a, b, c]: [Vec3; 3]) -> String {
    format!("triangle {} {} {}", vec(a), vec(b), vec(c))
}

pub(super) fn normals_text(normals: &[Vec3; 3]) -> String {
    normals.map(vec).join(" ")
}

/// A list of shapes, the first few spelled out.
pub(super) fn shapes_text(shapes: &[Shape]) -> String {
    const SPELLED: usize = 6;
    let mut text = shapes
        .iter()
        .take(SPELLED)
        .map(shape_text)
        .collect::<Vec<_>>()
        .join(", ");
    if shapes.len() > SPELLED {
        text.push_str(&format!(", ... {} objects in all", shapes.len()));
    }
    text
}

pub(super) fn options_text(options: &BvhOptions) -> String {
    format!(
        "{:?} split, {} bins, max_leaf {}",
        options.split, options.bins, options.max_leaf
    )
}

pub(super) fn shape_text(shape: &Shape) -> String {
    match shape {
        Shape::Plane(plane) => format!(
            "plane through {} normal {}",
            vec(plane.point()),
            vec(plane.normal())
        ),
        Shape::Sphere(sphere) => {
            format!("sphere {} r {}", vec(sphere.center()), num(sphere.radius()))
        }
        Shape::Triangle(triangle) => {
            let [a, b, c] = triangle.corners();
            format!("triangle {} {} {}", vec(a), vec(b), vec(c))
        }
    }
}
