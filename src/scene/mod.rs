//! Scenes: what is in the world, read from TOML files and checked before any
//! ray is cast.
//!
//! A scene file has a `[camera]`, optional `[render]` settings, a
//! `background` colour, an `ambient_light` colour, `[[lights]]` and
//! `[[objects]]`. `raylab scene --chapter N` prints a complete, commented
//! example. Every number is checked: the loader names the object and the
//! value it refuses, and a syntax error comes with the line, the column and
//! the field.

mod lights;
mod materials;
mod settings;
mod switches;
mod validate;

use std::path::Path;

use serde::Deserialize;

use crate::number;
use crate::shapes::{Implicit, ImplicitError, MAX_IMPLICIT_DEPTH, Sdf, Triangle};
use crate::{Plane, Sphere, Vec3};
use materials::check_material;
use validate::{check_coordinates, check_finite, check_light_color, check_point, readable};

pub use crate::camera::CameraSpec;
pub use crate::limits::{
    MAX_ABSORPTION, MAX_CAUCHY_A, MAX_CAUCHY_B, MAX_COORDINATE, MAX_DEPTH, MAX_IMAGE_SAMPLES,
    MAX_LIGHT, MAX_LIGHTS, MAX_OBJECTS, MAX_PIXELS, MAX_PRIMITIVES, MAX_SAMPLES,
    MAX_SHAPE_COORDINATE, MAX_SHININESS, MAX_SIDE,
};
pub use crate::shapes::Shape;
pub use lights::{Beam, Light};
pub use materials::{Cauchy, Checker, FresnelModel, Material};
pub use settings::{
    OffsetRule, RayOffset, RenderSettings, Sampling, SettingsError, SphereFormula, TerminatorRule,
    TriangleTest,
};
pub use switches::{Switch, SwitchedOff};

fn white() -> Vec3 {
    Vec3::ONE
}
fn one() -> f32 {
    1.0
}
fn default_background() -> Vec3 {
    Vec3::new(0.05, 0.05, 0.08)
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    camera: CameraSpec,
    #[serde(default)]
    render: RenderSettings,
    #[serde(default = "default_background", alias = "background_colour")]
    #[serde(deserialize_with = "number::vec3")]
    background: Vec3,
    #[serde(default = "white")]
    #[serde(deserialize_with = "number::vec3")]
    ambient_light: Vec3,
    #[serde(default)]
    lights: Vec<Light>,
    #[serde(default)]
    beams: Vec<Beam>,
    #[serde(default)]
    objects: Vec<ObjectSpec>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ObjectSpec {
    name: Option<String>,
    plane: Option<PlaneSpec>,
    sphere: Option<SphereSpec>,
    triangle: Option<TriangleSpec>,
    mesh: Option<MeshSpec>,
    implicit: Option<SdfSpec>,
    quad: Option<QuadSpec>,
    cuboid: Option<CuboidSpec>,
    prism: Option<PrismSpec>,
    #[serde(default)]
    material: Material,
}

/// `prism = { base = [[..], [..], [..]], extrude = [..] }`: the triangle
/// `base` swept along `extrude` (a glass prism): two triangles at the ends
/// and three sides of two triangles each, wound so that every normal
/// points out of the solid.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PrismSpec {
    base: [[f32; 3]; 3],
    #[serde(deserialize_with = "number::vec3")]
    extrude: Vec3,
}

impl PrismSpec {
    fn triangles(&self, label: &str) -> Result<Vec<Shape>, String> {
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
struct QuadSpec {
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
struct CuboidSpec {
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
    fn triangles(&self, label: &str) -> Result<Vec<Shape>, String> {
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
    fn triangles(&self, label: &str) -> Result<Vec<Shape>, String> {
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

/// `implicit = { torus = { center = [..], major = .., minor = .. } }`: a
/// node of an implicit surface's tree, by name (chapter 12).
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
enum SdfSpec {
    Sphere {
        #[serde(deserialize_with = "number::vec3")]
        center: Vec3,
        #[serde(deserialize_with = "number::f32")]
        radius: f32,
    },
    Box {
        #[serde(deserialize_with = "number::vec3")]
        center: Vec3,
        #[serde(deserialize_with = "number::vec3")]
        half_size: Vec3,
    },
    RoundBox {
        #[serde(deserialize_with = "number::vec3")]
        center: Vec3,
        #[serde(deserialize_with = "number::vec3")]
        half_size: Vec3,
        #[serde(deserialize_with = "number::f32")]
        radius: f32,
    },
    Torus {
        #[serde(deserialize_with = "number::vec3")]
        center: Vec3,
        #[serde(deserialize_with = "number::f32")]
        major: f32,
        #[serde(deserialize_with = "number::f32")]
        minor: f32,
    },
    Capsule {
        #[serde(deserialize_with = "number::vec3")]
        a: Vec3,
        #[serde(deserialize_with = "number::vec3")]
        b: Vec3,
        #[serde(deserialize_with = "number::f32")]
        radius: f32,
    },
    Plane {
        #[serde(deserialize_with = "number::vec3")]
        point: Vec3,
        #[serde(deserialize_with = "number::vec3")]
        normal: Vec3,
    },
    Union(Vec<SdfSpec>),
    Intersection(Vec<SdfSpec>),
    Difference {
        shape: Box<SdfSpec>,
        minus: Box<SdfSpec>,
    },
    SmoothUnion {
        #[serde(deserialize_with = "number::f32")]
        blend: f32,
        shapes: Vec<SdfSpec>,
    },
    Translate {
        #[serde(deserialize_with = "number::vec3")]
        offset: Vec3,
        shape: Box<SdfSpec>,
    },
    Rotate {
        #[serde(deserialize_with = "number::vec3")]
        degrees: Vec3,
        shape: Box<SdfSpec>,
    },
    Displace {
        #[serde(deserialize_with = "number::f32")]
        amplitude: f32,
        #[serde(deserialize_with = "number::f32")]
        frequency: f32,
        shape: Box<SdfSpec>,
    },
}

impl SdfSpec {
    /// The tree, or why not. A smooth union of more than two shapes blends
    /// them in order, pairwise.
    fn tree(&self) -> Result<Sdf, String> {
        let boxed = |spec: &SdfSpec| spec.tree().map(Box::new);
        Ok(match self {
            SdfSpec::Sphere { center, radius } => Sdf::Sphere {
                center: *center,
                radius: *radius,
            },
            SdfSpec::Box { center, half_size } => Sdf::Box {
                center: *center,
                half_size: *half_size,
            },
            SdfSpec::RoundBox {
                center,
                half_size,
                radius,
            } => Sdf::RoundBox {
                center: *center,
                half_size: *half_size,
                radius: *radius,
            },
            SdfSpec::Torus {
                center,
                major,
                minor,
            } => Sdf::Torus {
                center: *center,
                major: *major,
                minor: *minor,
            },
            SdfSpec::Capsule { a, b, radius } => Sdf::Capsule {
                a: *a,
                b: *b,
                radius: *radius,
            },
            SdfSpec::Plane { point, normal } => Sdf::Plane {
                point: *point,
                normal: crate::unit_vector(*normal).ok_or_else(|| {
                    format!("plane.normal = {normal}: a plane's normal must be finite and not zero")
                })?,
            },
            SdfSpec::Union(shapes) => {
                Sdf::Union(shapes.iter().map(SdfSpec::tree).collect::<Result<_, _>>()?)
            }
            SdfSpec::Intersection(shapes) => {
                Sdf::Intersection(shapes.iter().map(SdfSpec::tree).collect::<Result<_, _>>()?)
            }
            SdfSpec::Difference { shape, minus } => Sdf::Difference(boxed(shape)?, boxed(minus)?),
            SdfSpec::SmoothUnion { blend, shapes } => {
                let mut trees = shapes.iter().map(SdfSpec::tree);
                let (Some(first), Some(second)) = (trees.next(), trees.next()) else {
                    return Err(format!(
                        "smooth_union has {} shapes: it blends at least two",
                        shapes.len()
                    ));
                };
                let mut blended = Sdf::SmoothUnion {
                    shapes: (Box::new(first?), Box::new(second?)),
                    blend: *blend,
                };
                for next in trees {
                    blended = Sdf::SmoothUnion {
                        shapes: (Box::new(blended), Box::new(next?)),
                        blend: *blend,
                    };
                }
                blended
            }
            SdfSpec::Translate { offset, shape } => Sdf::Translate {
                offset: *offset,
                shape: boxed(shape)?,
            },
            SdfSpec::Rotate { degrees, shape } => {
                let radians = *degrees * (std::f32::consts::PI / 180.0);
                Sdf::Rotate {
                    rotation: glam::Quat::from_euler(
                        glam::EulerRot::XYZ,
                        radians.x,
                        radians.y,
                        radians.z,
                    ),
                    shape: boxed(shape)?,
                }
            }
            SdfSpec::Displace {
                amplitude,
                frequency,
                shape,
            } => Sdf::Displace {
                amplitude: *amplitude,
                frequency: *frequency,
                shape: boxed(shape)?,
            },
        })
    }

    /// How many levels the spec has, counted without recursing deeper
    /// than the tree may be (a hostile file's depth costs nothing).
    fn depth_within(&self, limit: usize) -> Option<usize> {
        if limit == 0 {
            return None;
        }
        let children: Vec<&SdfSpec> = match self {
            SdfSpec::Sphere { .. }
            | SdfSpec::Box { .. }
            | SdfSpec::RoundBox { .. }
            | SdfSpec::Torus { .. }
            | SdfSpec::Capsule { .. }
            | SdfSpec::Plane { .. } => vec![],
            SdfSpec::Union(shapes) | SdfSpec::Intersection(shapes) => shapes.iter().collect(),
            SdfSpec::SmoothUnion { shapes, .. } => shapes.iter().collect(),
            SdfSpec::Difference { shape, minus } => vec![shape, minus],
            SdfSpec::Translate { shape, .. }
            | SdfSpec::Rotate { shape, .. }
            | SdfSpec::Displace { shape, .. } => vec![shape],
        };
        let mut deepest = 0;
        for child in children {
            deepest = deepest.max(child.depth_within(limit - 1)?);
        }
        Some(deepest + 1)
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TriangleSpec {
    #[serde(deserialize_with = "number::vec3")]
    a: Vec3,
    #[serde(deserialize_with = "number::vec3")]
    b: Vec3,
    #[serde(deserialize_with = "number::vec3")]
    c: Vec3,
}

/// `mesh = { obj = "model.obj", ... }` or `mesh = { generated = N, ... }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshSpec {
    /// A Wavefront OBJ file, relative to the scene file.
    obj: Option<String>,
    /// Or raylab's procedural closed model of about this many triangles
    /// (`raylab mesh`), so that a scene needs no file.
    generated: Option<u64>,
    #[serde(default, deserialize_with = "number::vec3")]
    translate: Vec3,
    #[serde(default = "one", deserialize_with = "number::f32")]
    scale: f32,
    #[serde(default, deserialize_with = "number::vec3")]
    rotate_degrees: Vec3,
    /// Shade with the model's vertex normals where it has them (`false`
    /// shows the facets).
    #[serde(default = "yes")]
    smooth: bool,
}

fn yes() -> bool {
    true
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PlaneSpec {
    #[serde(deserialize_with = "number::vec3")]
    point: Vec3,
    #[serde(deserialize_with = "number::vec3")]
    normal: Vec3,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SphereSpec {
    #[serde(deserialize_with = "number::vec3")]
    center: Vec3,
    #[serde(deserialize_with = "number::f32")]
    radius: f32,
}

/// A scene that passed every check: what the renderer draws.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub camera: CameraSpec,
    pub render: RenderSettings,
    pub background: Vec3,
    pub ambient_light: Vec3,
    pub lights: Vec<Light>,
    /// Beams of parallel light (chapter 14), `direction` unit.
    pub beams: Vec<Beam>,
    /// Every primitive the renderer intersects: each plane and sphere, and
    /// each triangle of each mesh.
    pub shapes: Vec<Shape>,
    /// The objects the scene lists, with their names and materials: a mesh
    /// is one object of many triangles.
    pub objects: Vec<SceneObject>,
    /// For each of `shapes`, the index of its object in `objects`.
    pub owners: Vec<u32>,
    /// The vertex normals of smooth triangles, three per triangle
    /// ([`crate::shapes::Triangle::normals`] is an index into this).
    pub vertex_normals: Vec<[Vec3; 3]>,
}

/// One object of a scene: its name and its material, shared by all its
/// primitives.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneObject {
    pub name: String,
    pub material: Material,
}

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read: missing, not a regular file, too large,
    /// not UTF-8 (the error says which, and names the file).
    #[error(transparent)]
    Read(#[from] crate::input::InputError),
    #[error("{origin}: {message}")]
    Syntax { origin: String, message: String },
    #[error("{origin}: {message}")]
    Invalid { origin: String, message: String },
}

impl Scene {
    /// Reads and checks a scene file: a regular file of at most
    /// [`crate::input::MAX_SCENE_BYTES`], so a FIFO or `/dev/zero` given as
    /// a scene is refused instead of blocking or filling memory.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = crate::input::read_scene_text(path)?;
        let folder = path.parent().unwrap_or(Path::new(""));
        Scene::parse_in(
            &text,
            &format!("scene file {}", path.display()),
            Some(folder),
        )
    }

    /// Parses and checks scene text; `origin` names it in error messages.
    /// Text with no file can name no OBJ file (`mesh = { generated = N }`
    /// needs none).
    pub fn parse(text: &str, origin: &str) -> Result<Scene, SceneError> {
        Scene::parse_in(text, origin, None)
    }

    /// The OBJ files the scene text `text` names (`mesh = { obj = ... }`),
    /// relative to `folder`: inputs an output must not replace. Text that
    /// does not parse names none.
    pub fn obj_files(text: &str, folder: &Path) -> Vec<std::path::PathBuf> {
        let Ok(value) = text.parse::<toml::Table>() else {
            return Vec::new();
        };
        let Some(objects) = value.get("objects").and_then(toml::Value::as_array) else {
            return Vec::new();
        };
        objects
            .iter()
            .filter_map(|object| object.get("mesh")?.get("obj")?.as_str())
            .map(|obj| folder.join(obj))
            .collect()
    }

    /// [`Scene::parse`] for the text of a file in `folder`, where the OBJ
    /// files it names are looked for.
    pub fn parse_in(text: &str, origin: &str, folder: Option<&Path>) -> Result<Scene, SceneError> {
        // Before the parser: its tables cost about 2 KB each.
        for (header, most, what) in [
            ("[[lights]]", MAX_LIGHTS, "lights"),
            ("[[objects]]", MAX_OBJECTS, "objects"),
        ] {
            let count = text
                .lines()
                .filter(|line| line.trim_start().starts_with(header))
                .take(most + 1)
                .count();
            if count > most {
                return Err(SceneError::Syntax {
                    origin: origin.to_string(),
                    message: format!(
                        "more than {most} {header} tables: a scene may have at most {most} {what}"
                    ),
                });
            }
        }
        let deserializer = toml::Deserializer::new(text);
        let file: SceneFile = serde_path_to_error::deserialize(deserializer).map_err(|error| {
            let field = error.path().to_string();
            let inner = error.into_inner();
            let location = inner
                .span()
                .map(|span| line_and_column(text, span.start))
                .map(|(line, column)| format!("line {line}, column {column}: "))
                .unwrap_or_default();
            let field = if field == "." || field.is_empty() {
                String::new()
            } else {
                format!("in `{field}`: ")
            };
            SceneError::Syntax {
                origin: origin.to_string(),
                message: format!("{location}{field}{}", inner.message().trim_end()),
            }
        })?;
        file.into_scene(folder)
            .map_err(|message| SceneError::Invalid {
                origin: origin.to_string(),
                message,
            })
    }

    /// Number of primitives (every triangle of a mesh counts).
    pub fn len(&self) -> usize {
        self.shapes.len()
    }

    /// The material of primitive `shape`.
    pub fn material(&self, shape: usize) -> &Material {
        &self.objects[self.owners[shape] as usize].material
    }

    /// The name of the object primitive `shape` belongs to, if there is
    /// such a primitive.
    pub fn name(&self, shape: usize) -> Option<&str> {
        let owner = *self.owners.get(shape)? as usize;
        self.objects.get(owner).map(|object| object.name.as_str())
    }

    /// The objects' materials, one per object.
    pub fn materials(&self) -> impl Iterator<Item = &Material> {
        self.objects.iter().map(|object| &object.material)
    }

    /// The objects' materials, to change them all (the cost sweeps do).
    pub fn materials_mut(&mut self) -> impl Iterator<Item = &mut Material> {
        self.objects.iter_mut().map(|object| &mut object.material)
    }

    /// Adds an object made of `shapes`.
    pub fn add_object(
        &mut self,
        name: String,
        material: Material,
        shapes: impl IntoIterator<Item = Shape>,
    ) {
        let owner = self.objects.len() as u32;
        self.objects.push(SceneObject { name, material });
        for shape in shapes {
            self.shapes.push(shape);
            self.owners.push(owner);
        }
    }

    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }
}

fn line_and_column(text: &str, byte: usize) -> (usize, usize) {
    let before = &text[..byte.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

impl SceneFile {
    /// `folder` is where the scene file is, for the OBJ files it names
    /// (`None` for a built-in scene or text with no file).
    fn into_scene(self, folder: Option<&Path>) -> Result<Scene, String> {
        self.render
            .validate()
            .map_err(|e| format!("[render] {e}"))?;
        let camera = self.camera;
        check_point("camera.position", camera.position)?;
        check_point("camera.look_at", camera.look_at)?;
        check_finite("camera.up", camera.up)?;
        crate::camera::Camera::try_new(&camera, self.render.width, self.render.height)
            .map_err(|error| error.to_string())?;
        if !(camera.fov_degrees > 0.0 && camera.fov_degrees < 180.0) {
            return Err(format!(
                "camera.fov_degrees = {}: must be between 0 and 180 (exclusive)",
                camera.fov_degrees
            ));
        }
        check_light_color("background", self.background)?;
        check_light_color("ambient_light", self.ambient_light)?;
        for (index, light) in self.lights.iter().enumerate() {
            let name = format!("light {}", index + 1);
            check_point(&format!("{name}: position"), light.position)?;
            check_light_color(&format!("{name}: color"), light.color)?;
            if !(light.intensity >= 0.0 && light.intensity <= MAX_LIGHT) {
                return Err(format!(
                    "{name}: intensity = {}: must be a number between 0 and {MAX_LIGHT:e}",
                    light.intensity
                ));
            }
        }
        let mut beams = self.beams;
        for (index, beam) in beams.iter_mut().enumerate() {
            let name = format!("beam {}", index + 1);
            check_point(&format!("{name}: position"), beam.position)?;
            check_light_color(&format!("{name}: color"), beam.color)?;
            if !(beam.intensity >= 0.0 && beam.intensity <= MAX_LIGHT) {
                return Err(format!(
                    "{name}: intensity = {}: must be a number between 0 and {MAX_LIGHT:e}",
                    beam.intensity
                ));
            }
            beam.direction = crate::unit_vector(beam.direction).ok_or_else(|| {
                format!(
                    "{name}: direction = {}: must be a finite direction, not zero",
                    beam.direction
                )
            })?;
            if !(beam.radius > 0.0 && beam.radius.is_finite()) {
                return Err(format!(
                    "{name}: radius = {}: must be a finite number > 0",
                    beam.radius
                ));
            }
        }
        if self.lights.len() + beams.len() > MAX_LIGHTS {
            return Err(format!(
                "{} lights and beams: a scene may have at most {MAX_LIGHTS}",
                self.lights.len() + beams.len()
            ));
        }
        if self.objects.len() > MAX_OBJECTS {
            return Err(format!(
                "{} objects: a scene may have at most {MAX_OBJECTS}",
                self.objects.len()
            ));
        }
        let mut scene = Scene {
            camera,
            render: self.render,
            background: self.background,
            ambient_light: self.ambient_light,
            lights: self.lights,
            beams,
            shapes: Vec::new(),
            objects: Vec::new(),
            owners: Vec::new(),
            vertex_normals: Vec::new(),
        };
        for (index, mut object) in self.objects.into_iter().enumerate() {
            let name = object
                .name
                .clone()
                .unwrap_or_else(|| format!("object {}", index + 1));
            let label = match &object.name {
                Some(given) => format!("object {} (\"{given}\")", index + 1),
                None => format!("object {}", index + 1),
            };
            let ior_given = !object.material.ior.is_nan();
            if !ior_given {
                object.material.ior = Material::default().ior;
            }
            check_material(&label, &object.material)?;
            if let Some(cauchy) = object.material.cauchy {
                if ior_given {
                    return Err(format!(
                        "{label}: material has both `ior` and `cauchy`; give one: `cauchy` \
                         sets the index at every wavelength"
                    ));
                }
                object.material.ior = cauchy.index_at(crate::spectrum::D_LINE_NM);
            }
            let flat = match (&object.quad, &object.cuboid, &object.prism) {
                (Some(quad), None, None) => Some(quad.triangles(&label)?),
                (None, Some(cuboid), None) => Some(cuboid.triangles(&label)?),
                (None, None, Some(prism)) => Some(prism.triangles(&label)?),
                (None, None, None) => None,
                _ => {
                    return Err(format!(
                        "{label}: has more than one of `quad`, `cuboid` and `prism`; give \
                         exactly one shape per object"
                    ));
                }
            };
            if let Some(triangles) = flat {
                if object.plane.is_some()
                    || object.sphere.is_some()
                    || object.triangle.is_some()
                    || object.implicit.is_some()
                    || object.mesh.is_some()
                {
                    return Err(format!(
                        "{label}: has a `quad`, `cuboid` or `prism` and another shape; give \
                         exactly one shape per object"
                    ));
                }
                if scene.shapes.len() + triangles.len() > MAX_PRIMITIVES {
                    return Err(format!(
                        "{label}: would make more than {MAX_PRIMITIVES} primitives in the scene"
                    ));
                }
                scene.add_object(name, object.material, triangles);
                continue;
            }
            if let Some(mesh) = &object.mesh {
                if object.plane.is_some()
                    || object.sphere.is_some()
                    || object.triangle.is_some()
                    || object.implicit.is_some()
                {
                    return Err(format!(
                        "{label}: has a `mesh` and another shape; give exactly one shape per object"
                    ));
                }
                let triangles = mesh.load(&label, folder, &mut scene.vertex_normals)?;
                if scene.shapes.len() + triangles.len() > MAX_PRIMITIVES {
                    return Err(format!(
                        "{label}: {} triangles would make more than {MAX_PRIMITIVES} primitives \
                         in the scene",
                        triangles.len()
                    ));
                }
                scene.add_object(name, object.material, triangles);
                continue;
            }
            let shape = object.shape(&label)?;
            scene.add_object(name, object.material, [shape]);
        }
        Ok(scene)
    }
}

impl MeshSpec {
    /// The mesh's triangles, placed in the scene; their vertex normals (when
    /// the model has them and `smooth` is on) are appended to `normals`.
    fn load(
        &self,
        label: &str,
        folder: Option<&Path>,
        normals: &mut Vec<[Vec3; 3]>,
    ) -> Result<Vec<Shape>, String> {
        check_point(&format!("{label}: mesh.translate"), self.translate)?;
        check_finite(
            &format!("{label}: mesh.rotate_degrees"),
            self.rotate_degrees,
        )?;
        if !(self.scale > 0.0 && self.scale <= MAX_SHAPE_COORDINATE) {
            return Err(format!(
                "{label}: mesh.scale = {}: must be a number > 0 and at most {MAX_SHAPE_COORDINATE:e}",
                self.scale
            ));
        }
        let transform = crate::mesh::MeshTransform {
            translate: self.translate,
            scale: self.scale,
            rotate_degrees: self.rotate_degrees,
        };
        let mesh = match (&self.obj, self.generated) {
            (Some(obj), None) => obj_model(label, obj, folder, &transform)?,
            (None, Some(count)) => generated_model(label, count, &transform)?,
            _ => {
                return Err(format!(
                    "{label}: a mesh needs exactly one of `obj = \"file.obj\"` and \
                     `generated = N`"
                ));
            }
        };
        self.triangles(label, &mesh, normals)
    }

    /// The placed model's triangles as shapes, checked; smooth ones get
    /// their vertex normals appended to `normals`.
    fn triangles(
        &self,
        label: &str,
        mesh: &crate::mesh::Mesh,
        normals: &mut Vec<[Vec3; 3]>,
    ) -> Result<Vec<Shape>, String> {
        let mut shapes = Vec::with_capacity(mesh.triangles.len());
        for (index, triangle) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = triangle.map(|vertex| mesh.positions[vertex as usize]);
            for corner in [a, b, c] {
                check_coordinates(&format!("{label}: a vertex of the mesh"), corner)?;
            }
            let smooth = match &mesh.triangle_normals {
                Some(indices) if self.smooth => Some(indices[index]),
                _ => None,
            };
            let shape = match smooth {
                Some(indices) => {
                    let entry = u32::try_from(normals.len()).unwrap_or(Triangle::FLAT);
                    normals.push(indices.map(|n| mesh.normals[n as usize]));
                    Triangle::with_normals(a, b, c, entry)
                }
                None => Triangle::new(a, b, c),
            };
            shapes.push(shape.into());
        }
        Ok(shapes)
    }
}

/// The model of `mesh.obj = "obj"`, loaded from next to the scene file (in
/// `folder`) and placed by `transform`.
fn obj_model(
    label: &str,
    obj: &str,
    folder: Option<&Path>,
    transform: &crate::mesh::MeshTransform,
) -> Result<crate::mesh::Mesh, String> {
    if obj.trim().is_empty() {
        return Err(format!(
            "{label}: mesh.obj is empty: name an OBJ file, relative to the scene file"
        ));
    }
    let Some(folder) = folder else {
        return Err(format!(
            "{label}: mesh.obj = \"{obj}\": OBJ files are found next to the scene \
             file, and this scene has none (a built-in scene can use \
             `generated = N` instead)"
        ));
    };
    crate::mesh::load_obj(&folder.join(obj), transform).map_err(|error| format!("{label}: {error}"))
}

/// The model of `mesh.generated = count`, placed by `transform`.
fn generated_model(
    label: &str,
    count: u64,
    transform: &crate::mesh::MeshTransform,
) -> Result<crate::mesh::Mesh, String> {
    // A scene holds no bigger model than it could load from a file:
    // `raylab mesh` writes larger ones, for other tools.
    let max = crate::mesh::MAX_MESH_TRIANGLES;
    if !(1..=max as u64).contains(&count) {
        return Err(format!(
            "{label}: mesh.generated = {count}: a scene's model has 1 to {max} \
             triangles, as a loaded OBJ model does"
        ));
    }
    let count = usize::try_from(count).unwrap_or(usize::MAX);
    let mut mesh = crate::mesh::generate_closed_mesh(count)
        .map_err(|error| format!("{label}: mesh.generated = {count}: {error}"))?;
    let placed = transform.compile();
    for position in &mut mesh.positions {
        *position = placed.point(*position);
    }
    for normal in &mut mesh.normals {
        *normal = placed.normal(*normal);
    }
    Ok(mesh)
}

impl ObjectSpec {
    fn shape(&self, label: &str) -> Result<Shape, String> {
        if let Some(spec) = &self.implicit {
            if self.plane.is_some() || self.sphere.is_some() || self.triangle.is_some() {
                return Err(format!(
                    "{label}: has an `implicit` surface and another shape; give exactly one \
                     shape per object"
                ));
            }
            // Smooth unions of n shapes become n - 1 nodes, so the spec's
            // own depth is checked before the tree is built.
            if spec.depth_within(MAX_IMPLICIT_DEPTH).is_none() {
                return Err(format!("{label}: implicit: {}", ImplicitError::TooDeep));
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
