//! Cases on a triangle's inside: barycentric weights, the blended normal
//! and the point lifted off the shadow terminator.

use super::*;

/// `barycentric(triangle, point)`: expected the exact weights (ratios
/// of areas, in `f64`).
#[derive(Debug, Clone)]
pub struct BarycentricCase {
    pub corners: [Vec3; 3],
    pub point: Vec3,
}

impl BarycentricCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "barycentric"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        let BarycentricCase { corners, point } = self;
        format!("barycentric({}, {})", corners_text(*corners), vec(*point))
    }

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let BarycentricCase { corners, point } = self;
        let [a, b, c] = *corners;
        let got = C::barycentric(&Triangle::new(a, b, c), *point);
        let want = exact::barycentric(corners.map(wide), wide(*point));
        // Weights of a point inside are at most 1: an absolute
        // tolerance is a relative one.
        let pass = got.is_finite()
            && (wide(got) - want).abs().max_element()
                <= CHECKPOINT_TOLERANCE * max_abs(want).max(1.0);
        verdict(pass, vec64(want), vec(got))
    }
}

/// `smooth_normal(triangle, normals, point)`: expected the exact unit
/// blend.
#[derive(Debug, Clone)]
pub struct SmoothNormalCase {
    pub corners: [Vec3; 3],
    pub normals: [Vec3; 3],
    pub point: Vec3,
}

impl SmoothNormalCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "smooth_normal"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        let SmoothNormalCase {
            corners,
            normals,
            point,
        } = self;
        format!(
            "{}({}, normals {}, {})",
            self.function(),
            corners_text(*corners),
            normals_text(normals),
            vec(*point)
        )
    }

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let SmoothNormalCase {
            corners,
            normals,
            point,
        } = self;
        let [a, b, c] = *corners;
        let got = C::smooth_normal(&Triangle::new(a, b, c), normals, *point);
        let want = exact::smooth_normal(corners.map(wide), normals.map(wide), wide(*point));
        verdict(
            unit_toward(got, want),
            format!("{} (unit length)", vec64(want)),
            format!("{} (length {})", vec(got), num64(wide(got).length())),
        )
    }
}

/// `terminator_point(triangle, normals, point)`: expected the exact
/// lifted point.
#[derive(Debug, Clone)]
pub struct TerminatorCase {
    pub corners: [Vec3; 3],
    pub normals: [Vec3; 3],
    pub point: Vec3,
}

impl TerminatorCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "terminator_point"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        let TerminatorCase {
            corners,
            normals,
            point,
        } = self;
        format!(
            "{}({}, normals {}, {})",
            self.function(),
            corners_text(*corners),
            normals_text(normals),
            vec(*point)
        )
    }

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let TerminatorCase {
            corners,
            normals,
            point,
        } = self;
        let [a, b, c] = *corners;
        let got = C::terminator_point(&Triangle::new(a, b, c), normals, *point);
        let want = exact::terminator_point(corners.map(wide), normals.map(wide), wide(*point));
        verdict(point_close(got, want), vec64(want), vec(got))
    }
}

/// `smooth_hit_point` at the point where `ray` meets the triangle (by
/// the reference test), on a material that is opaque or fully
/// transparent: expected the blended normal turned toward the ray, and
/// the lifted point (the point itself when transparent).
#[derive(Debug, Clone)]
pub struct SmoothHitCase {
    pub corners: [Vec3; 3],
    pub normals: [Vec3; 3],
    pub ray: Ray,
    pub transparent: bool,
}

impl SmoothHitCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "smooth_hit_point"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        let SmoothHitCase {
            corners,
            normals,
            ray,
            transparent,
        } = self;
        format!(
            "smooth_hit_point(the point where {} meets {}, {}, normals {})",
            ray_text(ray),
            corners_text(*corners),
            if *transparent {
                "transparent material"
            } else {
                "opaque material"
            },
            normals_text(normals)
        )
    }

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let SmoothHitCase {
            corners,
            normals,
            ray,
            transparent,
        } = self;
        let [a, b, c] = *corners;
        let triangle = Triangle::new(a, b, c);
        let shape = Shape::Triangle(triangle);
        // The point comes from the reference test: the case's input
        // does not depend on the code under check.
        let Some(t) = crate::answer_key::raylab_own(|| shape.intersect(ray, 0.0, f32::INFINITY))
        else {
            return Outcome::Error(format!(
                "the case's ray {} misses its triangle",
                ray_text(ray)
            ));
        };
        let material = Material {
            transparency: if *transparent { 1.0 } else { 0.0 },
            ..Material::default()
        };
        let point = HitPoint::new(0, &shape, &material, ray, t);
        let got = C::smooth_hit_point(point, &triangle, normals);
        // The vertex normals turned to the side the ray came from.
        let outward: DVec3 = normals.iter().map(|n| wide(*n)).sum();
        let side = if outward.dot(-wide(ray.dir)) < 0.0 {
            -1.0
        } else {
            1.0
        };
        let facing = normals.map(|n| side * wide(n));
        let at = wide(point.surface.point);
        let want_normal = exact::smooth_normal(corners.map(wide), facing, at);
        let want_point = if *transparent {
            at
        } else {
            exact::terminator_point(corners.map(wide), facing, at)
        };
        let pass =
            unit_toward(got.normal, want_normal) && point_close(got.surface.point, want_point);
        verdict(
            pass,
            format!(
                "normal {} (unit length), point {}",
                vec64(want_normal),
                vec64(want_point)
            ),
            format!(
                "normal {} (length {}), point {}",
                vec(got.normal),
                num64(wide(got.normal).length()),
                vec(got.surface.point)
            ),
        )
    }
}

/// Whether `got` is a unit vector along `want` (unit), within the
/// checkpoint tolerance in length and in angle.
fn unit_toward(got: Vec3, want: DVec3) -> bool {
    let g = wide(got);
    got.is_finite()
        && (g.length() - 1.0).abs() <= CHECKPOINT_TOLERANCE
        && exact::angle(g, want) <= CHECKPOINT_TOLERANCE
}

/// Whether the point `got` is `want` within the checkpoint tolerance,
/// relative to the size of its coordinates.
fn point_close(got: Vec3, want: DVec3) -> bool {
    got.is_finite()
        && (wide(got) - want).abs().max_element() <= CHECKPOINT_TOLERANCE * max_abs(want).max(1.0)
}
