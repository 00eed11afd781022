//! What a case asks, written out as the call would receive it: the
//! "inputs" line of a failing case.

use super::*;

impl Case {
    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        let range =
            |t_min: f32, t_max: f32| format!("t_min = {}, t_max = {}", num(t_min), num(t_max));
        match &self.kind {
            CaseKind::Plane {
                point,
                normal,
                ray,
                t_min,
                t_max,
                ..
            } => format!(
                "intersect_plane(plane through {} with normal {}, {}, {})",
                vec(*point),
                vec(*normal),
                ray_text(ray),
                range(*t_min, *t_max)
            ),
            CaseKind::Sphere {
                center,
                radius,
                ray,
                t_min,
                t_max,
                ..
            } => format!(
                "intersect_sphere(sphere centre {} radius {}, {}, {})",
                vec(*center),
                num(*radius),
                ray_text(ray),
                range(*t_min, *t_max)
            ),
            CaseKind::Nearest {
                shapes,
                ray,
                t_min,
                t_max,
                ..
            } => format!(
                "nearest_hit([{}], {}, {})",
                shapes.iter().map(shape_text).collect::<Vec<_>>().join(", "),
                ray_text(ray),
                range(*t_min, *t_max)
            ),
            CaseKind::Offset { surface, dir, .. } => format!(
                "offset_origin(point {}, normal {}, error {}; dir {})",
                vec(surface.point),
                vec(surface.normal),
                vec(surface.error),
                vec(*dir)
            ),
            CaseKind::Shadow {
                rays,
                light,
                object,
                ..
            } => format!(
                "in_shadow at the point{} where {} meet{} object {object}, light at {}",
                if rays.len() > 1 { "s" } else { "" },
                if rays.len() > 1 {
                    format!("{} rays", rays.len())
                } else {
                    rays.first().map(ray_text).unwrap_or_default()
                },
                if rays.len() > 1 { "" } else { "s" },
                vec(*light)
            ),
            CaseKind::Shade {
                shading,
                ray,
                depth,
                ..
            } => format!(
                "{}(the point where {} meets the case's scene{})",
                self.function(),
                ray_text(ray),
                match shading {
                    Shading::Mirror | Shading::Glass | Shading::Dielectric => {
                        format!(", depth {depth}, weight 1")
                    }
                    _ => String::new(),
                }
            ),
            CaseKind::PhongTerms {
                material,
                albedo,
                normal,
                to_light,
                to_eye,
                light,
                ..
            } => format!(
                "phong_terms(k_d = {}, k_s = {}, shininess {}; albedo {}, normal {}, to_light {}, to_eye {}, light {})",
                num(material.diffuse),
                num(material.specular),
                material.shininess,
                vec(*albedo),
                vec(*normal),
                vec(*to_light),
                vec(*to_eye),
                vec(*light)
            ),
            CaseKind::Reflect { d, n } => format!("reflect({}, {})", vec(*d), vec(*n)),
            CaseKind::SampleOffsets {
                sampling,
                count,
                pixels,
                seed,
                ..
            } => format!(
                "sample_offset({sampling:?}, count {count}, index 0..{count}, {} pixel{} from {:?}, seed {seed})",
                pixels.len(),
                if pixels.len() > 1 { "s" } else { "" },
                pixels.first().copied().unwrap_or_default()
            ),
            CaseKind::PixelColor { pixels, .. } => format!(
                "pixel_color of {} pixel{} from {:?}",
                pixels.len(),
                if pixels.len() > 1 { "s" } else { "" },
                pixels.first().copied().unwrap_or_default()
            ),
            CaseKind::Refract { d, n, eta } => {
                format!("refract({}, {}, eta = {})", vec(*d), vec(*n), num(*eta))
            }
            CaseKind::Reflectance {
                schlick,
                cos_i,
                n1,
                n2,
                ..
            } => format!(
                "{}(cos_i = {}, n1 = {}, n2 = {})",
                if *schlick { "schlick" } else { "fresnel" },
                num(*cos_i),
                num(*n1),
                num(*n2)
            ),
            CaseKind::Transmittance {
                absorption,
                distance,
            } => format!(
                "transmittance(absorption {}, distance {})",
                vec(*absorption),
                num(*distance)
            ),
            CaseKind::Triangles {
                triangles,
                ray,
                t_min,
                t_max,
                ..
            } => {
                let listed: Vec<String> = triangles.iter().map(|c| corners_text(*c)).collect();
                if let [one] = listed.as_slice() {
                    format!(
                        "intersect_triangle({one}, {}, {})",
                        ray_text(ray),
                        range(*t_min, *t_max)
                    )
                } else {
                    format!(
                        "intersect_triangle on each of [{}], {}, {}; the nearest hit",
                        listed.join(", "),
                        ray_text(ray),
                        range(*t_min, *t_max)
                    )
                }
            }
            CaseKind::Barycentric { corners, point } => {
                format!("barycentric({}, {})", corners_text(*corners), vec(*point))
            }
            CaseKind::SmoothNormal {
                corners,
                normals,
                point,
            }
            | CaseKind::Terminator {
                corners,
                normals,
                point,
            } => format!(
                "{}({}, normals {}, {})",
                self.function(),
                corners_text(*corners),
                normals_text(normals),
                vec(*point)
            ),
            CaseKind::SmoothHit {
                corners,
                normals,
                ray,
                transparent,
            } => format!(
                "smooth_hit_point(the point where {} meets {}, {}, normals {})",
                ray_text(ray),
                corners_text(*corners),
                if *transparent {
                    "transparent material"
                } else {
                    "opaque material"
                },
                normals_text(normals)
            ),
            CaseKind::HitBox {
                min,
                max,
                origin,
                dir,
                t_min,
                t_max,
                ..
            } => format!(
                "hit_box(box {} to {}, origin {}, inverse_direction 1 / {}, {})",
                vec(*min),
                vec(*max),
                vec(*origin),
                vec(*dir),
                range(*t_min, *t_max)
            ),
            CaseKind::BoxEdges {
                min,
                max,
                rays,
                seed,
            } => format!(
                "hit_box(box {} to {}, ...) on {rays} rays aimed at its edges (seed {seed}), \
                 t_min = 0, t_max = inf",
                vec(*min),
                vec(*max)
            ),
            CaseKind::BvhBuild {
                shapes, options, ..
            } => format!(
                "build_bvh(the boxes of [{}], {})",
                shapes_text(shapes),
                options_text(options)
            ),
            CaseKind::BvhHits {
                shapes,
                options,
                rays,
                t_min,
                t_max,
                ..
            } => format!(
                "{}(build_bvh(the boxes of [{}], {}), the objects, {}, {})",
                self.function(),
                shapes_text(shapes),
                options_text(options),
                if rays.len() == 1 {
                    ray_text(&rays[0])
                } else {
                    format!(
                        "each of {} rays from {}",
                        rays.len(),
                        rays.first().map(ray_text).unwrap_or_default()
                    )
                },
                range(*t_min, *t_max)
            ),
        }
    }
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
