//! Cases on a triangle's inside: barycentric weights, the blended normal
//! and the point lifted off the shadow terminator.

use super::*;

/// `barycentric(triangle, point)`: expected the exact weights (ratios
/// of areas, in `f64`).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct BarycentricCase {
    pub corners: [Vec3; 3],
    pub point: Vec3,
}

impl Kind for BarycentricCase {
    type Call = BarycentricCase;
    type Answer = Vec3;

    fn function(&self) -> &'static str {
        "barycentric"
    }

    fn inputs(&self) -> String {
        let BarycentricCase { corners, point } = self;
        format!("barycentric({}, {})", corners_text(*corners), vec(*point))
    }

    fn call(&self) -> BarycentricCase {
        self.clone()
    }

    fn ask<C: Chapters>(call: &BarycentricCase) -> Result<Vec3, String> {
        let [a, b, c] = call.corners;
        Ok(C::barycentric(&Triangle::new(a, b, c), call.point))
    }

    /// The same tolerance at both levels.
    fn judge(&self, got: Vec3, _robust: bool) -> Outcome {
        let BarycentricCase { corners, point } = self;
        let want = exact::barycentric(corners.map(wide), wide(*point));
        // Weights of a point inside are at most 1: an absolute
        // tolerance is a relative one.
        let pass = got.is_finite()
            && (wide(got) - want).abs().max_element()
                <= CHECKPOINT_TOLERANCE * max_abs(want).max(1.0);
        verdict(pass, vec64(want), vec(got))
    }

    /// The triangle and the point moved whole: the weights are the same,
    /// the numbers are not.
    fn fresh(&self, draw: &mut Draw) -> Option<BarycentricCase> {
        let motion = draw.motion();
        Some(BarycentricCase {
            corners: self.corners.map(|corner| motion.point(corner)),
            point: motion.point(self.point),
        })
    }
}

/// `smooth_normal(triangle, normals, point)`: expected the exact unit
/// blend.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct SmoothNormalCase {
    pub corners: [Vec3; 3],
    pub normals: [Vec3; 3],
    pub point: Vec3,
}

impl Kind for SmoothNormalCase {
    type Call = SmoothNormalCase;
    type Answer = Vec3;

    fn function(&self) -> &'static str {
        "smooth_normal"
    }

    fn inputs(&self) -> String {
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

    fn call(&self) -> SmoothNormalCase {
        self.clone()
    }

    fn ask<C: Chapters>(call: &SmoothNormalCase) -> Result<Vec3, String> {
        let [a, b, c] = call.corners;
        Ok(C::smooth_normal(
            &Triangle::new(a, b, c),
            &call.normals,
            call.point,
        ))
    }

    /// The same tolerance at both levels.
    fn judge(&self, got: Vec3, _robust: bool) -> Outcome {
        let SmoothNormalCase {
            corners,
            normals,
            point,
        } = self;
        let want = exact::smooth_normal(corners.map(wide), normals.map(wide), wide(*point));
        verdict(
            unit_toward(got, want),
            format!("{} (unit length)", vec64(want)),
            format!("{} (length {})", vec(got), num64(wide(got).length())),
        )
    }

    /// The triangle and the point moved whole, the normals turned with
    /// them.
    fn fresh(&self, draw: &mut Draw) -> Option<SmoothNormalCase> {
        let motion = draw.motion();
        Some(SmoothNormalCase {
            corners: self.corners.map(|corner| motion.point(corner)),
            normals: self.normals.map(|normal| motion.direction(normal)),
            point: motion.point(self.point),
        })
    }
}

/// `terminator_point(triangle, normals, point)`: expected the exact
/// lifted point.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct TerminatorCase {
    pub corners: [Vec3; 3],
    pub normals: [Vec3; 3],
    pub point: Vec3,
}

impl Kind for TerminatorCase {
    type Call = TerminatorCase;
    type Answer = Vec3;

    fn function(&self) -> &'static str {
        "terminator_point"
    }

    fn inputs(&self) -> String {
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

    fn call(&self) -> TerminatorCase {
        self.clone()
    }

    fn ask<C: Chapters>(call: &TerminatorCase) -> Result<Vec3, String> {
        let [a, b, c] = call.corners;
        Ok(C::terminator_point(
            &Triangle::new(a, b, c),
            &call.normals,
            call.point,
        ))
    }

    /// The same tolerance at both levels.
    fn judge(&self, got: Vec3, _robust: bool) -> Outcome {
        let TerminatorCase {
            corners,
            normals,
            point,
        } = self;
        let want = exact::terminator_point(corners.map(wide), normals.map(wide), wide(*point));
        verdict(point_close(got, want), vec64(want), vec(got))
    }

    /// The triangle and the point moved whole, the normals turned with
    /// them.
    fn fresh(&self, draw: &mut Draw) -> Option<TerminatorCase> {
        let motion = draw.motion();
        Some(TerminatorCase {
            corners: self.corners.map(|corner| motion.point(corner)),
            normals: self.normals.map(|normal| motion.direction(normal)),
            point: motion.point(self.point),
        })
    }
}

/// `smooth_hit_point` at the point where `ray` meets the triangle (by
/// the reference test), on a material of the given transparency:
/// expected the blended normal turned toward the ray, and the lifted
/// point (the point itself when the material lets any light through).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct SmoothHitCase {
    pub corners: [Vec3; 3],
    pub normals: [Vec3; 3],
    pub ray: Ray,
    /// The material's `transparency`, from 0 (opaque) to 1.
    pub transparency: f32,
}

/// A `smooth_hit_point` call: the case, and where its ray meets the
/// triangle by the reference test, worked out by the judge (none of
/// raylab's answers runs in the student's process).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct SmoothHitCall {
    pub case: SmoothHitCase,
    pub t: Option<f32>,
}

impl SmoothHitCase {
    /// Where the case's ray meets its triangle, by the reference test.
    fn reference_t(&self) -> Option<f32> {
        let [a, b, c] = self.corners;
        let shape = Shape::Triangle(Triangle::new(a, b, c));
        crate::answer_key::raylab_own(|| shape.intersect(&self.ray, 0.0, f32::INFINITY))
    }
}

impl Kind for SmoothHitCase {
    type Call = SmoothHitCall;
    /// The point as given (where the reference test found it), and the
    /// student's normal and point.
    type Answer = (Vec3, Vec3, Vec3);

    fn function(&self) -> &'static str {
        "smooth_hit_point"
    }

    fn inputs(&self) -> String {
        let SmoothHitCase {
            corners,
            normals,
            ray,
            transparency,
        } = self;
        format!(
            "smooth_hit_point(the point where {} meets {}, {}, normals {})",
            ray_text(ray),
            corners_text(*corners),
            if *transparency == 0.0 {
                "opaque material".to_string()
            } else {
                format!("material of transparency {}", num(*transparency))
            },
            normals_text(normals)
        )
    }

    fn call(&self) -> SmoothHitCall {
        SmoothHitCall {
            case: self.clone(),
            t: self.reference_t(),
        }
    }

    fn ask<C: Chapters>(call: &SmoothHitCall) -> Result<(Vec3, Vec3, Vec3), String> {
        let SmoothHitCase {
            corners,
            normals,
            ray,
            transparency,
        } = &call.case;
        let [a, b, c] = *corners;
        let triangle = Triangle::new(a, b, c);
        let shape = Shape::Triangle(triangle);
        // The point comes from the reference test: the case's input
        // does not depend on the code under check.
        let Some(t) = call.t else {
            return Err(format!(
                "the case's ray {} misses its triangle",
                ray_text(ray)
            ));
        };
        let material = Material {
            transparency: *transparency,
            ..Material::default()
        };
        let point = HitPoint::new(0, &shape, &material, ray, t);
        let got = C::smooth_hit_point(point, &triangle, normals);
        Ok((point.surface.point, got.normal, got.surface.point))
    }

    /// The same tolerance at both levels.
    fn judge(&self, (at, normal, point): (Vec3, Vec3, Vec3), _robust: bool) -> Outcome {
        let SmoothHitCase {
            corners,
            normals,
            ray,
            transparency,
        } = self;
        // The point where the ray meets the triangle, as the reference
        // test finds it: the student's process must have been given it.
        let shape = Shape::Triangle(Triangle::new(corners[0], corners[1], corners[2]));
        let given = self
            .reference_t()
            .map(|t| shape.surface_point(ray, t).point);
        if given != Some(at) {
            return Outcome::Fail {
                expected: "the answer at the point the case gives".into(),
                got: format!("an answer at {}", vec(at)),
            };
        }
        // The vertex normals turned to the side the ray came from.
        let outward: DVec3 = normals.iter().map(|n| wide(*n)).sum();
        let side = if outward.dot(-wide(ray.dir)) < 0.0 {
            -1.0
        } else {
            1.0
        };
        let facing = normals.map(|n| side * wide(n));
        let at = wide(at);
        let want_normal = exact::smooth_normal(corners.map(wide), facing, at);
        // Any light let through is refracted into the mesh, and must start
        // below the surface: only an opaque point is lifted.
        let want_point = if *transparency > 0.0 {
            at
        } else {
            exact::terminator_point(corners.map(wide), facing, at)
        };
        let pass = unit_toward(normal, want_normal) && point_close(point, want_point);
        verdict(
            pass,
            format!(
                "normal {} (unit length), point {}",
                vec64(want_normal),
                vec64(want_point)
            ),
            format!(
                "normal {} (length {}), point {}",
                vec(normal),
                num64(wide(normal).length()),
                vec(point)
            ),
        )
    }

    /// The triangle and the ray moved whole, the normals turned with them.
    fn fresh(&self, draw: &mut Draw) -> Option<SmoothHitCase> {
        let motion = draw.motion();
        Some(SmoothHitCase {
            corners: self.corners.map(|corner| motion.point(corner)),
            normals: self.normals.map(|normal| motion.direction(normal)),
            ray: motion.ray(&self.ray),
            transparency: self.transparency,
        })
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
