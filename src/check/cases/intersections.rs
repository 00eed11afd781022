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

impl PlaneCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "intersect_plane"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
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

    /// Asks the question of the chapters `C`; `robust`: at the robustness
    /// level's tolerance.
    pub(super) fn evaluate<C: Chapters>(&self, robust: bool) -> Outcome {
        let PlaneCase {
            point,
            normal,
            ray,
            t_min,
            t_max,
            expect,
        } = self;
        let plane = Plane::new(*point, *normal);
        let got = C::intersect_plane(&plane, ray, *t_min, *t_max);
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

impl SphereCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "intersect_sphere"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
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

    /// Asks the question of the chapters `C`; `robust`: at the robustness
    /// level's tolerance.
    pub(super) fn evaluate<C: Chapters>(&self, robust: bool) -> Outcome {
        let SphereCase {
            center,
            radius,
            ray,
            t_min,
            t_max,
            expect,
        } = self;
        let sphere = Sphere::new(*center, *radius);
        let got = C::intersect_sphere(&sphere, ray, *t_min, *t_max);
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

impl NearestCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "nearest_hit"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
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

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let NearestCase {
            shapes,
            ray,
            t_min,
            t_max,
            expect,
        } = self;
        let got = C::nearest_hit(&crate::Objects::<C>::new(shapes), ray, *t_min, *t_max);
        let show = |hit: Option<(usize, f64)>| match hit {
            Some((object, t)) => format!("object {object} at t = {}", num64(t)),
            None => "no hit".into(),
        };
        let got_pair = got.map(|hit| (hit.object, f64::from(hit.t)));
        let pass = match (got_pair, *expect) {
            (None, None) => true,
            (Some((object, t)), Some((want, t_ref))) => {
                object == want && close(t, t_ref, CHECKPOINT_TOLERANCE)
            }
            _ => false,
        };
        verdict(pass, show(*expect), show(got_pair))
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

impl TrianglesCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "intersect_triangle"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
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

    /// Asks the question of the chapters `C`; `robust`: at the robustness
    /// level's tolerance.
    pub(super) fn evaluate<C: Chapters>(&self, robust: bool) -> Outcome {
        let TrianglesCase {
            triangles,
            ray,
            t_min,
            t_max,
            expect,
        } = self;
        let hits: Vec<(usize, f32)> = triangles
            .iter()
            .enumerate()
            .filter_map(|(index, &[a, b, c])| {
                C::intersect_triangle(&Triangle::new(a, b, c), ray, *t_min, *t_max)
                    .map(|t| (index, t))
            })
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
}

impl ClosedMeshCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "intersect_triangle"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        format!(
            "intersect_triangle(each triangle of raylab's closed model of {} triangles, a ray \
             from inside toward each vertex and edge midpoint, t_min = 0, t_max = inf)",
            self.triangles
        )
    }

    /// Asks the question of the chapters `C`, with the same rule at both
    /// levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let mesh = match crate::mesh::generate_closed_mesh(self.triangles) {
            Ok(mesh) => mesh,
            Err(error) => return Outcome::Error(error.to_string()),
        };
        let triangles: Vec<Triangle> = mesh
            .triangles
            .iter()
            .map(|corners| {
                let [a, b, c] = corners.map(|index| mesh.positions[index as usize]);
                Triangle::new(a, b, c)
            })
            .collect();
        let targets = crate::bvh_reports::leaks::leak_targets(&mesh);
        let mut escaped = Vec::new();
        for &target in &targets {
            let origin = crate::bvh_reports::leaks::core_point(target);
            let ray = Ray::new(origin, target - origin);
            let hit = triangles.iter().any(|triangle| {
                C::intersect_triangle(triangle, &ray, 0.0, f32::INFINITY).is_some()
            });
            if !hit {
                escaped.push(ray);
            }
        }
        match escaped.first() {
            None => Outcome::Pass,
            Some(first) => Outcome::Fail {
                expected: format!("every one of the {} rays hits a triangle", targets.len()),
                got: format!(
                    "{} of {} rays hit no triangle and escape the closed mesh, the first the {}",
                    escaped.len(),
                    targets.len(),
                    ray_text(first)
                ),
            },
        }
    }
}
