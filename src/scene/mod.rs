//! Scenes: what is in the world, read from TOML files and checked before any
//! ray is cast.
//!
//! A scene file has a `[camera]`, optional `[render]` settings, a
//! `background` colour, an `ambient_light` colour, `[[lights]]` and
//! `[[objects]]`. `raylab scene --chapter N` prints a complete, commented
//! example. Every number is checked: the loader names the object and the
//! value it refuses, and a syntax error comes with the line, the column and
//! the field.

mod implicit;
mod lights;
mod materials;
mod mesh;
mod settings;
mod shapes;
mod switches;
mod validate;

use std::path::Path;

use serde::Deserialize;

use crate::Vec3;
use crate::number;
use implicit::SdfSpec;
use materials::check_material;
use mesh::MeshSpec;
use shapes::{CuboidSpec, PlaneSpec, PrismSpec, QuadSpec, SphereSpec, TriangleSpec};
use validate::{check_finite, check_light_color, check_point};

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
                object.material.ior = cauchy.index(crate::spectrum::D_LINE_NM);
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
