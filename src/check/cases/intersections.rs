//! Intersection cases: a ray against a plane, a sphere, a list of objects or
//! a few triangles, judged on the `t` of the hit.

use super::*;

/// `intersect_plane(Plane::new(point, normal), ray, t_min, t_max)`.
#[derive(Debug, Clone)]
pub struct PlaneCase {
    pub point: Vec3,
    pub normal: Vec3,
    pub ray: Ray,
    pub t_min: f32,
    pub t_max: f32,
    pub expect: ExpectT,
}

/// The inputs of an intersection call: a shape, a ray and the interval of
/// `t`.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct HitCall<S> {
    pub shape: S,
    pub ray: Ray,
    pub t_min: f32,
    pub t_max: f32,
}

impl Kind for PlaneCase {
    type Call = HitCall<(Vec3, Vec3)>;
    type Answer = Option<f32>;

    fn function(&self) -> &'static str {
        "intersect_plane"
    }

    fn inputs(&self) -> String {
        let PlaneCase {
            point,
            normal,
            ray,
            t_min,
            t_max,
            ..
        } = self;
        format!(
            "intersect_plane(plane through {} with normal {}, {}, {})",
            vec(*point),
            vec(*normal),
            ray_text(ray),
            range(*t_min, *t_max)
        )
    }

    fn call(&self) -> Self::Call {
        HitCall {
            shape: (self.point, self.normal),
            ray: self.ray,
            t_min: self.t_min,
            t_max: self.t_max,
        }
    }

    fn ask<C: Chapters>(call: &Self::Call) -> Result<Option<f32>, String> {
        let (point, normal) = call.shape;
        let plane = Plane::new(point, normal);
        Ok(C::intersect_plane(
            &plane, &call.ray, call.t_min, call.t_max,
        ))
    }

    fn judge(&self, got: Option<f32>, robust: bool) -> Outcome {
        let PlaneCase {
            point,
            normal,
            ray,
            expect,
            ..
        } = self;
        let plane = Plane::new(*point, *normal);
        let scale = max_abs(wide(*point));
        let on_surface = |p: DVec3| (p - wide(plane.point())).dot(wide(plane.normal())).abs();
        judge_t(
            got,
            *expect,
            ray,
            robust,
            scale,
            wide(plane.normal()),
            on_surface,
        )
    }

    fn fresh(&self, draw: &mut Draw) -> Option<PlaneCase> {
        let motion = draw.motion();
        let (point, normal) = (motion.point(self.point), motion.direction(self.normal));
        let (ray, t_min, t_max) = moved_ray(&motion, &self.ray, self.t_min, self.t_max);
        let plane = Plane::new(point, normal);
        let expect = again(self.expect, || {
            exact::plane(
                wide(plane.point()),
                wide(plane.normal()),
                wide(ray.origin),
                wide(ray.dir),
                f64::from(t_min),
                f64::from(t_max),
            )
        });
        Some(PlaneCase {
            point,
            normal,
            ray,
            t_min,
            t_max,
            expect,
        })
    }
}

/// `ray` and its interval moved by `motion`.
pub(super) fn moved_ray(motion: &Motion, ray: &Ray, t_min: f32, t_max: f32) -> (Ray, f32, f32) {
    (motion.ray(ray), motion.t(t_min), motion.t(t_max))
}

/// `expect` for moved inputs: a hit's `t` worked out again by `exact_t`
/// (NaN if the oracle finds none, which fails the reference: the tests of
/// fresh draws catch it), a miss or either as they were.
pub(super) fn again(expect: ExpectT, exact_t: impl FnOnce() -> Option<f64>) -> ExpectT {
    match expect {
        ExpectT::Hit(_) => ExpectT::Hit(exact_t().unwrap_or(f64::NAN)),
        other => other,
    }
}

/// `intersect_sphere(Sphere::new(center, radius), ray, t_min, t_max)`.
#[derive(Debug, Clone)]
pub struct SphereCase {
    pub center: Vec3,
    pub radius: f32,
    pub ray: Ray,
    pub t_min: f32,
    pub t_max: f32,
    pub expect: ExpectT,
}

impl Kind for SphereCase {
    type Call = HitCall<(Vec3, f32)>;
    type Answer = Option<f32>;

    fn function(&self) -> &'static str {
        "intersect_sphere"
    }

    fn inputs(&self) -> String {
        let SphereCase {
            center,
            radius,
            ray,
            t_min,
            t_max,
            ..
        } = self;
        format!(
            "intersect_sphere(sphere centre {} radius {}, {}, {})",
            vec(*center),
            num(*radius),
            ray_text(ray),
            range(*t_min, *t_max)
        )
    }

    fn call(&self) -> Self::Call {
        HitCall {
            shape: (self.center, self.radius),
            ray: self.ray,
            t_min: self.t_min,
            t_max: self.t_max,
        }
    }

    fn ask<C: Chapters>(call: &Self::Call) -> Result<Option<f32>, String> {
        let (center, radius) = call.shape;
        let sphere = Sphere::new(center, radius);
        Ok(C::intersect_sphere(
            &sphere, &call.ray, call.t_min, call.t_max,
        ))
    }

    fn judge(&self, got: Option<f32>, robust: bool) -> Outcome {
        let SphereCase {
            center,
            radius,
            ray,
            expect,
            ..
        } = self;
        let c = wide(*center);
        let r = f64::from(*radius);
        let scale = max_abs(c) + r;
        let normal_at = match expect {
            ExpectT::Hit(t) => exact::sphere_normal(c, r, wide(ray.origin), wide(ray.dir), *t),
            _ => DVec3::Y,
        };
        let on_surface = |p: DVec3| ((p - c).length() - r).abs();
        judge_t(got, *expect, ray, robust, scale, normal_at, on_surface)
    }

    fn fresh(&self, draw: &mut Draw) -> Option<SphereCase> {
        let motion = draw.motion();
        let (center, radius) = (motion.point(self.center), motion.length(self.radius));
        let (ray, t_min, t_max) = moved_ray(&motion, &self.ray, self.t_min, self.t_max);
        let expect = again(self.expect, || {
            exact::sphere(
                wide(center),
                f64::from(radius),
                wide(ray.origin),
                wide(ray.dir),
                f64::from(t_min),
                f64::from(t_max),
            )
        });
        Some(SphereCase {
            center,
            radius,
            ray,
            t_min,
            t_max,
            expect,
        })
    }
}

/// `nearest_hit(shapes, ray, t_min, t_max)`: the object index and `t`.
#[derive(Debug, Clone)]
pub struct NearestCase {
    pub shapes: Vec<Shape>,
    pub ray: Ray,
    pub t_min: f32,
    pub t_max: f32,
    pub expect: Option<(usize, f64)>,
}

impl Kind for NearestCase {
    type Call = HitCall<Vec<Shape>>;
    type Answer = Option<(usize, f32)>;

    fn function(&self) -> &'static str {
        "nearest_hit"
    }

    fn inputs(&self) -> String {
        let NearestCase {
            shapes,
            ray,
            t_min,
            t_max,
            ..
        } = self;
        format!(
            "nearest_hit([{}], {}, {})",
            shapes.iter().map(shape_text).collect::<Vec<_>>().join(", "),
            ray_text(ray),
            range(*t_min, *t_max)
        )
    }

    fn call(&self) -> Self::Call {
        HitCall {
            shape: self.shapes.clone(),
            ray: self.ray,
            t_min: self.t_min,
            t_max: self.t_max,
        }
    }

    fn ask<C: Chapters>(call: &Self::Call) -> Result<Self::Answer, String> {
        let objects = crate::Objects::<C>::new(&call.shape);
        Ok(C::nearest_hit(&objects, &call.ray, call.t_min, call.t_max)
            .map(|hit| (hit.object, hit.t)))
    }

    /// The same tolerance at both levels.
    fn judge(&self, got: Self::Answer, _robust: bool) -> Outcome {
        let expect = &self.expect;
        let show = |hit: Option<(usize, f64)>| match hit {
            Some((object, t)) => format!("object {object} at t = {}", num64(t)),
            None => "no hit".into(),
        };
        let got_pair = got.map(|(object, t)| (object, f64::from(t)));
        let pass = match (got_pair, *expect) {
            (None, None) => true,
            (Some((object, t)), Some((want, t_ref))) => {
                object == want && close(t, t_ref, CHECKPOINT_TOLERANCE)
            }
            _ => false,
        };
        verdict(pass, show(*expect), show(got_pair))
    }

    fn fresh(&self, draw: &mut Draw) -> Option<NearestCase> {
        let motion = draw.motion();
        let shapes: Vec<Shape> = self
            .shapes
            .iter()
            .map(|shape| moved_shape(&motion, shape))
            .collect::<Option<_>>()?;
        let (ray, t_min, t_max) = moved_ray(&motion, &self.ray, self.t_min, self.t_max);
        let expect = match self.expect {
            None => None,
            Some((object, _)) => Some((
                object,
                exact_t(shapes.get(object)?, &ray, t_min, t_max).unwrap_or(f64::NAN),
            )),
        };
        Some(NearestCase {
            shapes,
            ray,
            t_min,
            t_max,
            expect,
        })
    }
}

/// `shape` moved by `motion` (`None` for an implicit surface, whose tree
/// a motion does not move).
pub(super) fn moved_shape(motion: &Motion, shape: &Shape) -> Option<Shape> {
    Some(match shape {
        Shape::Plane(plane) => Shape::Plane(Plane::new(
            motion.point(plane.point()),
            motion.direction(plane.normal()),
        )),
        Shape::Sphere(sphere) => Shape::Sphere(Sphere::new(
            motion.point(sphere.center()),
            motion.length(sphere.radius()),
        )),
        Shape::Triangle(triangle) => {
            let [a, b, c] = triangle.corners().map(|corner| motion.point(corner));
            let normals = triangle
                .normals()
                .map_or(Triangle::FLAT, |index| index as u32);
            Shape::Triangle(Triangle::with_normals(a, b, c, normals))
        }
        Shape::Implicit(_) => return None,
    })
}

/// The exact `t` of the nearest hit of `ray` on `shape` with `t_min < t <
/// t_max` (`None` for an implicit surface: no case moves one).
pub(super) fn exact_t(shape: &Shape, ray: &Ray, t_min: f32, t_max: f32) -> Option<f64> {
    let (o, d) = (wide(ray.origin), wide(ray.dir));
    let (low, high) = (f64::from(t_min), f64::from(t_max));
    match shape {
        Shape::Plane(plane) => {
            exact::plane(wide(plane.point()), wide(plane.normal()), o, d, low, high)
        }
        Shape::Sphere(sphere) => exact::sphere(
            wide(sphere.center()),
            f64::from(sphere.radius()),
            o,
            d,
            low,
            high,
        ),
        Shape::Triangle(triangle) => exact::triangle(triangle.corners().map(wide), o, d, low, high),
        Shape::Implicit(_) => None,
    }
}

/// `intersect_triangle` on each of `triangles` (one, or a few sharing
/// edges and corners): the nearest of their hits is judged, so a ray
/// through a shared edge passes when at least one triangle claims it.
#[derive(Debug, Clone)]
pub struct TrianglesCase {
    pub triangles: Vec<[Vec3; 3]>,
    pub ray: Ray,
    pub t_min: f32,
    pub t_max: f32,
    pub expect: ExpectT,
}

impl Kind for TrianglesCase {
    type Call = HitCall<Vec<[Vec3; 3]>>;
    /// Each triangle's answer, in order.
    type Answer = Vec<Option<f32>>;

    fn function(&self) -> &'static str {
        "intersect_triangle"
    }

    fn inputs(&self) -> String {
        let TrianglesCase {
            triangles,
            ray,
            t_min,
            t_max,
            ..
        } = self;
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

    fn call(&self) -> Self::Call {
        HitCall {
            shape: self.triangles.clone(),
            ray: self.ray,
            t_min: self.t_min,
            t_max: self.t_max,
        }
    }

    fn ask<C: Chapters>(call: &Self::Call) -> Result<Self::Answer, String> {
        Ok(call
            .shape
            .iter()
            .map(|&[a, b, c]| {
                C::intersect_triangle(&Triangle::new(a, b, c), &call.ray, call.t_min, call.t_max)
            })
            .collect())
    }

    fn judge(&self, answers: Self::Answer, robust: bool) -> Outcome {
        let TrianglesCase {
            triangles,
            ray,
            expect,
            ..
        } = self;
        if answers.len() != triangles.len() {
            return wrong_length(triangles.len(), answers.len());
        }
        let hits: Vec<(usize, f32)> = answers
            .iter()
            .enumerate()
            .filter_map(|(index, t)| t.map(|t| (index, t)))
            .collect();
        // A NaN or infinite t is wrong however it compares: it is
        // the one judged, never hidden behind a finite hit.
        let nearest = hits
            .iter()
            .copied()
            .find(|(_, t)| !t.is_finite())
            .or_else(|| hits.iter().copied().min_by(|x, y| x.1.total_cmp(&y.1)));
        let judged = triangles[nearest.map_or(0, |(index, _)| index)].map(wide);
        let normal = (judged[1] - judged[0])
            .cross(judged[2] - judged[0])
            .normalize();
        let on_surface = |p: DVec3| (p - judged[0]).dot(normal).abs();
        let scale = triangles
            .iter()
            .flatten()
            .map(|corner| max_abs(wide(*corner)))
            .fold(0.0, f64::max);
        judge_t(
            nearest.map(|(_, t)| t),
            *expect,
            ray,
            robust,
            scale,
            normal,
            on_surface,
        )
    }

    fn fresh(&self, draw: &mut Draw) -> Option<TrianglesCase> {
        let motion = draw.motion();
        let triangles: Vec<[Vec3; 3]> = self
            .triangles
            .iter()
            .map(|corners| corners.map(|corner| motion.point(corner)))
            .collect();
        let (ray, t_min, t_max) = moved_ray(&motion, &self.ray, self.t_min, self.t_max);
        let expect = again(self.expect, || {
            triangles
                .iter()
                .filter_map(|corners| {
                    exact::triangle(
                        corners.map(wide),
                        wide(ray.origin),
                        wide(ray.dir),
                        f64::from(t_min),
                        f64::from(t_max),
                    )
                })
                .min_by(f64::total_cmp)
        });
        Some(TrianglesCase {
            triangles,
            ray,
            t_min,
            t_max,
            expect,
        })
    }
}

/// The outcome of an answer with `got` entries where the call asked for
/// `asked`: only a process that is not raylab's own answering loop sends
/// one.
pub(super) fn wrong_length(asked: usize, got: usize) -> Outcome {
    Outcome::Fail {
        expected: format!("{asked} answers, one per input"),
        got: format!("{got} answers"),
    }
}

/// Judges an intersection answer `got` against `expect` (see the module
/// docs of tests/course/hard_cases.rs for the robustness bound).
fn judge_t(
    got: Option<f32>,
    expect: ExpectT,
    ray: &Ray,
    robust: bool,
    shape_scale: f64,
    normal: DVec3,
    distance_to_surface: impl Fn(DVec3) -> f64,
) -> Outcome {
    let (o, d) = (wide(ray.origin), wide(ray.dir));
    let show_expected = match expect {
        ExpectT::Hit(t) => format!("t = {}", num64(t)),
        ExpectT::Miss => "no hit (None)".into(),
        ExpectT::Either => "either no hit or a hit on the surface".into(),
    };
    let show_got = match got {
        Some(t) => format!("t = {}", num(t)),
        None => "no hit (None)".into(),
    };
    let scale_at = |t: f64| max_abs(o) + shape_scale + max_abs(o + t * d);
    let pass = match (expect, got) {
        (_, Some(t)) if !t.is_finite() => false,
        (ExpectT::Miss | ExpectT::Either, None) => true,
        (ExpectT::Miss, Some(_)) | (ExpectT::Hit(_), None) => false,
        (ExpectT::Either, Some(t)) => {
            let t = f64::from(t);
            distance_to_surface(o + t * d) <= ROUNDINGS * U * scale_at(t)
        }
        (ExpectT::Hit(t_ref), Some(t)) => {
            let t = f64::from(t);
            if robust {
                let cos = (d.dot(normal) / (d.length() * normal.length())).abs();
                let unit = U * (t_ref.abs() + scale_at(t_ref) / (d.length() * cos));
                (t - t_ref).abs() <= ROUNDINGS * unit
            } else {
                close(t, t_ref, CHECKPOINT_TOLERANCE)
            }
        }
    };
    verdict(pass, show_expected, show_got)
}

/// `intersect_triangle` on every triangle of raylab's generated closed
/// model (a lumpy torus of about `triangles` triangles), for a ray from
/// inside it (its core circle) toward each vertex and each edge midpoint,
/// where rounding decides which triangle claims the ray: the property a
/// watertight test keeps, whatever its formula, is that every such ray hits
/// some triangle. None may escape.
#[derive(Debug, Clone)]
pub struct ClosedMeshCase {
    pub triangles: usize,
    /// Where the model is moved to (`grade --fresh`); `None` where it is.
    pub motion: Option<Motion>,
}

/// A closed model's rays: what `intersect_triangle` on the model's
/// triangles found for them.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct MeshCall {
    pub triangles: usize,
    /// The motion the model and its rays are moved by (`grade --fresh`),
    /// as `(turn's columns, scale, shift)`.
    pub motion: Option<WireMotion>,
}

impl Kind for ClosedMeshCase {
    type Call = MeshCall;
    /// The rays that escaped, and how many were cast.
    type Answer = (Vec<Ray>, usize);

    fn function(&self) -> &'static str {
        "intersect_triangle"
    }

    fn inputs(&self) -> String {
        format!(
            "intersect_triangle(each triangle of raylab's closed model of {} triangles, a ray \
             from inside toward each vertex and edge midpoint, t_min = 0, t_max = inf)",
            self.triangles
        )
    }

    fn call(&self) -> MeshCall {
        MeshCall {
            triangles: self.triangles,
            motion: self.motion.map(WireMotion::from),
        }
    }

    fn ask<C: Chapters>(call: &MeshCall) -> Result<Self::Answer, String> {
        let (triangles, rays) = closed_mesh_rays(call)?;
        let escaped = rays
            .iter()
            .filter(|ray| {
                !triangles.iter().any(|triangle| {
                    C::intersect_triangle(triangle, ray, 0.0, f32::INFINITY).is_some()
                })
            })
            .copied()
            .collect();
        Ok((escaped, rays.len()))
    }

    /// The same rule at both levels.
    fn judge(&self, (escaped, cast): Self::Answer, _robust: bool) -> Outcome {
        let expected_rays = closed_mesh_rays(&self.call()).map_or(0, |(_, rays)| rays.len());
        if cast != expected_rays {
            return wrong_length(expected_rays, cast);
        }
        match escaped.first() {
            None => Outcome::Pass,
            Some(first) => Outcome::Fail {
                expected: format!("every one of the {cast} rays hits a triangle"),
                got: format!(
                    "{} of {cast} rays hit no triangle and escape the closed mesh, the first the {}",
                    escaped.len(),
                    ray_text(first)
                ),
            },
        }
    }

    fn fresh(&self, draw: &mut Draw) -> Option<ClosedMeshCase> {
        Some(ClosedMeshCase {
            triangles: self.triangles,
            motion: Some(draw.motion()),
        })
    }
}

/// A [`Motion`] as the wire carries it.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub struct WireMotion {
    pub turn: [f64; 9],
    pub scale: f64,
    pub shift: [f64; 3],
}

impl From<Motion> for WireMotion {
    fn from(motion: Motion) -> WireMotion {
        WireMotion {
            turn: motion.turn.to_cols_array(),
            scale: motion.scale,
            shift: motion.shift.to_array(),
        }
    }
}

impl From<WireMotion> for Motion {
    fn from(wire: WireMotion) -> Motion {
        Motion {
            turn: glam::DMat3::from_cols_array(&wire.turn),
            scale: wire.scale,
            shift: DVec3::from_array(wire.shift),
        }
    }
}

/// raylab's closed model of about `call.triangles` triangles and the rays
/// from inside it toward each vertex and edge midpoint, moved by the
/// call's motion where it has one.
pub(super) fn closed_mesh_rays(call: &MeshCall) -> Result<(Vec<Triangle>, Vec<Ray>), String> {
    let mesh = crate::mesh::generate_closed_mesh(call.triangles).map_err(|e| e.to_string())?;
    let motion = call.motion.map(Motion::from);
    let place = |point: Vec3| motion.map_or(point, |motion| motion.point(point));
    let triangles = mesh
        .triangles
        .iter()
        .map(|corners| {
            let [a, b, c] = corners.map(|index| place(mesh.positions[index as usize]));
            Triangle::new(a, b, c)
        })
        .collect();
    let rays = crate::bvh_reports::leaks::leak_targets(&mesh)
        .into_iter()
        .map(|target| {
            let (origin, target) = (
                place(crate::bvh_reports::leaks::core_point(target)),
                place(target),
            );
            Ray::new(origin, target - origin)
        })
        .collect();
    Ok((triangles, rays))
}
