//! The shapes of a scene file's objects as the file gives them (`plane`,
//! `sphere`, `triangle`, `quad`, `cuboid`, `prism`, and the `implicit`
//! surface of scene/implicit.rs), checked and turned into the primitives
//! the renderer intersects.

use serde::Deserialize;

use super::ObjectSpec;
use super::validate::{check_coordinates, check_finite, check_point, readable};
use crate::limits::MAX_SHAPE_COORDINATE;
use crate::number;
use crate::shapes::{Implicit, ImplicitError, MAX_IMPLICIT_DEPTH, Shape, Triangle};
use crate::{Plane, Sphere, Vec3};

/// `prism = { base = [[..], [..], [..]], extrude = [..] }`: the triangle
/// `base` swept along `extrude` (a glass prism): two triangles at the ends
/// and three sides of two triangles each, wound so that every normal
/// points out of the solid.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PrismSpec {
    base: [[f32; 3]; 3],
    #[serde(deserialize_with = "number::vec3")]
    extrude: Vec3,
}

impl PrismSpec {
    pub(super) fn triangles(&self, label: &str) -> Result<Vec<Shape>, String> {
        let base = self.base.map(Vec3::from_array);
        for (index, corner) in base.iter().enumerate() {
            check_point(&format!("{label}: prism.base[{index}]"), *corner)?;
        }
        check_point(&format!("{label}: prism.extrude"), self.extrude)?;
        let [a, b, c] = base;
        let normal = (b - a).cross(c - a);
        let height = normal.dot(self.extrude);
        if !(height.abs() > 0.0) {
            return Err(format!(
                "{label}: prism.base spans no area, or prism.extrude = {} lies in its plane: \
                 the prism has no volume",
                self.extrude
            ));
        }
        // Wind the base so that its normal points into the solid (toward
        // the extrusion): the bottom then faces out when turned around.
        let [a, b, c] = if height > 0.0 { [a, c, b] } else { [a, b, c] };
        let top = |p: Vec3| p + self.extrude;
        let mut shapes: Vec<Shape> = vec![
            Triangle::new(a, b, c).into(),
            Triangle::new(top(a), top(c), top(b)).into(),
        ];
        for (p, q) in [(a, b), (b, c), (c, a)] {
            shapes.push(Triangle::new(p, top(p), top(q)).into());
            shapes.push(Triangle::new(p, top(q), q).into());
        }
        check_corners(&format!("{label}: prism (a corner)"), &shapes)?;
        Ok(shapes)
    }
}

/// `quad = { corner = [..], u = [..], v = [..] }`: the parallelogram
/// `corner + s u + t v` for `s, t` in `[0, 1]`, as two triangles.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct QuadSpec {
    #[serde(deserialize_with = "number::vec3")]
    corner: Vec3,
    #[serde(deserialize_with = "number::vec3")]
    u: Vec3,
    #[serde(deserialize_with = "number::vec3")]
    v: Vec3,
}

/// `cuboid = { min = [..], max = [..], rotate_y_degrees = .., translate = [..] }`:
/// the box from `min` to `max`, turned about the y axis through the
/// origin, then moved: twelve triangles.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CuboidSpec {
    #[serde(deserialize_with = "number::vec3")]
    min: Vec3,
    #[serde(deserialize_with = "number::vec3")]
    max: Vec3,
    #[serde(default, deserialize_with = "number::f32")]
    rotate_y_degrees: f32,
    #[serde(default, deserialize_with = "number::vec3")]
    translate: Vec3,
}

/// The two triangles of the parallelogram `corner`, `corner + u`,
/// `corner + u + v`, `corner + v`.
fn quad_triangles(corner: Vec3, u: Vec3, v: Vec3) -> [Shape; 2] {
    [
        Triangle::new(corner, corner + u, corner + u + v).into(),
        Triangle::new(corner, corner + u + v, corner + v).into(),
    ]
}

impl QuadSpec {
    pub(super) fn triangles(&self, label: &str) -> Result<Vec<Shape>, String> {
        for (what, value) in [("corner", self.corner), ("u", self.u), ("v", self.v)] {
            check_point(&format!("{label}: quad.{what}"), value)?;
        }
        if self.u.cross(self.v).length_squared() == 0.0 {
            return Err(format!(
                "{label}: quad.u = {} and quad.v = {} span no area: give two edges \
                 that are not parallel",
                self.u, self.v
            ));
        }
        let far = self.corner + self.u + self.v;
        check_coordinates(&format!("{label}: quad (far corner)"), far)?;
        Ok(quad_triangles(self.corner, self.u, self.v).to_vec())
    }
}

/// Every corner of `shapes` within the coordinates a scene may use, named
/// `what` in the error.
fn check_corners(what: &str, shapes: &[Shape]) -> Result<(), String> {
    for bounds in shapes.iter().filter_map(Shape::bounds) {
        check_coordinates(what, bounds.max)?;
        check_coordinates(what, bounds.min)?;
    }
    Ok(())
}

impl CuboidSpec {
    pub(super) fn triangles(&self, label: &str) -> Result<Vec<Shape>, String> {
        check_point(&format!("{label}: cuboid.min"), self.min)?;
        check_point(&format!("{label}: cuboid.max"), self.max)?;
        check_point(&format!("{label}: cuboid.translate"), self.translate)?;
        if !self.rotate_y_degrees.is_finite() {
            return Err(format!(
                "{label}: cuboid.rotate_y_degrees = {}: must be a finite number",
                self.rotate_y_degrees
            ));
        }
        if !self.min.cmplt(self.max).all() {
            return Err(format!(
                "{label}: cuboid.min = {} must be below cuboid.max = {} on every axis",
                self.min, self.max
            ));
        }
        // `libm`'s sine and cosine: the same corners on every machine and
        // in the browser page's WebAssembly.
        let (sin, cos) = libm::sincosf(self.rotate_y_degrees.to_radians());
        let place = |p: Vec3| {
            Vec3::new(cos * p.x + sin * p.z, p.y, -sin * p.x + cos * p.z) + self.translate
        };
        let size = self.max - self.min;
        let (x, y, z) = (
            Vec3::new(size.x, 0.0, 0.0),
            Vec3::new(0.0, size.y, 0.0),
            Vec3::new(0.0, 0.0, size.z),
        );
        let (low, high) = (self.min, self.max);
        // Each face with its edges in an order whose cross product points
        // out of the box.
        let faces = [
            (low, z, y),
            (low, y, x),
            (low, x, z),
            (high, -y, -z),
            (high, -x, -y),
            (high, -z, -x),
        ];
        let mut shapes = Vec::with_capacity(12);
        for (corner, u, v) in faces {
            let [a, b, c, d] = [corner, corner + u, corner + u + v, corner + v].map(place);
            shapes.push(Triangle::new(a, b, c).into());
            shapes.push(Triangle::new(a, c, d).into());
        }
        check_corners(&format!("{label}: cuboid (a corner)"), &shapes)?;
        Ok(shapes)
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TriangleSpec {
    #[serde(deserialize_with = "number::vec3")]
    a: Vec3,
    #[serde(deserialize_with = "number::vec3")]
    b: Vec3,
    #[serde(deserialize_with = "number::vec3")]
    c: Vec3,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PlaneSpec {
    #[serde(deserialize_with = "number::vec3")]
    point: Vec3,
    #[serde(deserialize_with = "number::vec3")]
    normal: Vec3,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SphereSpec {
    #[serde(deserialize_with = "number::vec3")]
    center: Vec3,
    #[serde(deserialize_with = "number::f32")]
    radius: f32,
}

impl ObjectSpec {
    pub(super) fn shape(&self, label: &str) -> Result<Shape, String> {
        if let Some(spec) = &self.implicit {
            if self.plane.is_some() || self.sphere.is_some() || self.triangle.is_some() {
                return Err(format!(
                    "{label}: has an `implicit` surface and another shape; give exactly one \
                     shape per object"
                ));
            }
            // Smooth unions of n shapes become n - 1 levels, so the
            // spec's own depth is checked before the tree is built.
            if spec.depth_within(MAX_IMPLICIT_DEPTH).is_none() {
                return Err(format!(
                    "{label}: implicit: {} (a smooth_union of n shapes is n - 1 levels: it \
                     blends them pairwise, in order)",
                    ImplicitError::TooDeep
                ));
            }
            let tree = spec
                .tree()
                .map_err(|error| format!("{label}: implicit: {error}"))?;
            if let Some(bounds) = tree.bounds() {
                for (what, corner) in [("lowest", bounds.min), ("highest", bounds.max)] {
                    check_coordinates(&format!("{label}: implicit ({what} corner)"), corner)?;
                }
            }
            let surface =
                Implicit::new(tree).map_err(|error| format!("{label}: implicit: {error}"))?;
            return Ok(surface.into());
        }
        if let Some(triangle) = &self.triangle {
            if self.plane.is_some() || self.sphere.is_some() {
                return Err(format!(
                    "{label}: has a `triangle` and another shape; give exactly one shape per object"
                ));
            }
            for (corner, value) in [("a", triangle.a), ("b", triangle.b), ("c", triangle.c)] {
                let what = format!("{label}: triangle.{corner}");
                check_finite(&what, value)?;
                check_coordinates(&what, value)?;
            }
            return Ok(Triangle::new(triangle.a, triangle.b, triangle.c).into());
        }
        match (&self.plane, &self.sphere) {
            (Some(plane), None) => {
                check_finite(&format!("{label}: plane.point"), plane.point)?;
                check_finite(&format!("{label}: plane.normal"), plane.normal)?;
                check_coordinates(&format!("{label}: plane.point"), plane.point)?;
                if plane.normal.abs().max_element() == 0.0 {
                    return Err(format!(
                        "{label}: plane.normal = {}: a plane's normal must not be zero",
                        plane.normal
                    ));
                }
                Ok(Plane::new(plane.point, plane.normal).into())
            }
            (None, Some(sphere)) => {
                check_finite(&format!("{label}: sphere.center"), sphere.center)?;
                if !(sphere.radius > 0.0 && sphere.radius.is_finite()) {
                    return Err(format!(
                        "{label}: sphere.radius = {}: must be a finite number > 0",
                        sphere.radius
                    ));
                }
                check_coordinates(&format!("{label}: sphere.center"), sphere.center)?;
                if sphere.radius > MAX_SHAPE_COORDINATE {
                    return Err(format!(
                        "{label}: sphere.radius = {}: at most {MAX_SHAPE_COORDINATE:e}; f32 resolves \
                         the surface of a larger sphere to worse than 0.06 units (use a plane \
                         for a floor that should look infinite)",
                        readable(sphere.radius)
                    ));
                }
                Ok(Sphere::new(sphere.center, sphere.radius).into())
            }
            (Some(_), Some(_)) => Err(format!(
                "{label}: has both `plane` and `sphere`; give exactly one shape per object"
            )),
            (None, None) => Err(format!(
                "{label}: has no shape; give it `plane = {{ point = [..], normal = [..] }}`, \
                 `sphere = {{ center = [..], radius = .. }}`, `triangle = {{ a = [..], b = [..], \
                 c = [..] }}`, `mesh = {{ obj = \"file.obj\" }}` or `implicit = {{ sphere = {{ \
                 center = [..], radius = .. }} }}`"
            )),
        }
    }
}
