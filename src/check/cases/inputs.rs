//! How the inputs line of a failing case writes numbers, vectors, rays
//! and shapes: as a student would type them.

use super::*;

/// The interval of `t` a call asks about.
pub fn range(t_min: f32, t_max: f32) -> String {
    format!("t_min = {}, t_max = {}", num(t_min), num(t_max))
}

/// A number as a student would write it: short, exponent for the very
/// large and very small, and every digit the `f32` needs to be told from
/// its neighbours (Rust's shortest round-trip form): an input printed as
/// `-0.33333334` is not mistaken for the `-0.333333333` of an answer.
pub fn num(x: f32) -> String {
    if let Some(special) = special(f64::from(x)) {
        return special;
    }
    if exponent_form(f64::from(x)) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// An exact (`f64`) answer, to 9 significant digits: one more than an
/// `f32` carries, so that an answer and the `f32` it is compared with
/// never print alike when they differ by more than rounding.
pub fn num64(x: f64) -> String {
    if let Some(special) = special(x) {
        return special;
    }
    if exponent_form(x) {
        let text = format!("{x:.8e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        return format!("{mantissa}e{exponent}");
    }
    let whole_digits = x.abs().log10().floor() as i32 + 1;
    let decimals = (9 - whole_digits).max(0) as usize;
    let text = format!("{x:.decimals$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.')
    } else {
        &text
    };
    text.to_string()
}

fn special(x: f64) -> Option<String> {
    if x.is_nan() {
        Some("NaN".into())
    } else if x.is_infinite() {
        Some(if x > 0.0 { "inf".into() } else { "-inf".into() })
    } else if x == 0.0 {
        Some("0".into())
    } else {
        None
    }
}

fn exponent_form(x: f64) -> bool {
    !(1e-4..1e7).contains(&x.abs())
}

pub fn vec(v: Vec3) -> String {
    format!("({}, {}, {})", num(v.x), num(v.y), num(v.z))
}

pub fn vec64(v: DVec3) -> String {
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
        Shape::Implicit(surface) => format!("implicit {}", sdf_text(surface.tree())),
    }
}

/// An implicit surface's tree as a student would write it in a scene.
pub fn sdf_text(tree: &crate::shapes::Sdf) -> String {
    use crate::shapes::Sdf;
    let list = |shapes: &[Sdf]| shapes.iter().map(sdf_text).collect::<Vec<_>>().join(", ");
    match tree {
        Sdf::Sphere { center, radius } => format!("sphere {} r {}", vec(*center), num(*radius)),
        Sdf::Box { center, half_size } => {
            format!("box {} half size {}", vec(*center), vec(*half_size))
        }
        Sdf::RoundBox {
            center,
            half_size,
            radius,
        } => format!(
            "rounded box {} half size {} r {}",
            vec(*center),
            vec(*half_size),
            num(*radius)
        ),
        Sdf::Torus {
            center,
            major,
            minor,
        } => format!(
            "torus {} major {} minor {}",
            vec(*center),
            num(*major),
            num(*minor)
        ),
        Sdf::Capsule { a, b, radius } => {
            format!("capsule {} to {} r {}", vec(*a), vec(*b), num(*radius))
        }
        Sdf::Plane { point, normal } => {
            format!("half space below {} normal {}", vec(*point), vec(*normal))
        }
        Sdf::Union(shapes) => format!("union [{}]", list(shapes)),
        Sdf::Intersection(shapes) => format!("intersection [{}]", list(shapes)),
        Sdf::Difference(kept, removed) => {
            format!("({}) minus ({})", sdf_text(kept), sdf_text(removed))
        }
        Sdf::SmoothUnion {
            shapes: (first, second),
            blend,
        } => format!(
            "smooth union blend {} [{}, {}]",
            num(*blend),
            sdf_text(first),
            sdf_text(second)
        ),
        Sdf::Translate { offset, shape } => {
            format!("({}) moved by {}", sdf_text(shape), vec(*offset))
        }
        Sdf::Rotate { rotation, shape } => format!("({}) turned by {rotation}", sdf_text(shape)),
        Sdf::Displace {
            amplitude,
            frequency,
            shape,
        } => format!(
            "({}) displaced by {} sin({} x) sin({} y) sin({} z)",
            sdf_text(shape),
            num(*amplitude),
            num(*frequency),
            num(*frequency),
            num(*frequency)
        ),
    }
}
