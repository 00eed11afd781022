//! What a surface is made of, as a scene file gives it (`material = {
//! ... }`), and the checks its values pass before the renderer sees them.

use serde::Deserialize;

use super::validate::{check_albedo, check_coefficient, check_finite, check_light_color};
use crate::Vec3;
use crate::limits::{MAX_ABSORPTION, MAX_CAUCHY_A, MAX_CAUCHY_B, MAX_SHININESS};
use crate::number;
use crate::shapes::Shape;

/// How a surface responds to light. Coefficients follow the chapters: the
/// Phong terms (chapter 5), mirror reflection (6), transparency (8).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Material {
    /// Linear RGB albedo, each channel in `[0, 1]`.
    #[serde(alias = "colour")]
    #[serde(deserialize_with = "number::vec3")]
    pub color: Vec3,
    /// `k_a`: how much ambient light the surface returns.
    #[serde(deserialize_with = "number::f32")]
    pub ambient: f32,
    /// `k_d`: how much diffuse (matte) light the surface returns.
    #[serde(deserialize_with = "number::f32")]
    pub diffuse: f32,
    /// `k_s`: strength of the specular highlight.
    #[serde(deserialize_with = "number::f32")]
    pub specular: f32,
    /// Phong exponent: larger is a smaller, sharper highlight.
    pub shininess: u32,
    /// Share of the colour that comes from the mirror direction, in `[0, 1]`.
    #[serde(deserialize_with = "number::f32")]
    pub reflectivity: f32,
    /// Share of the colour that comes through the surface, in `[0, 1]`.
    #[serde(deserialize_with = "number::f32")]
    pub transparency: f32,
    /// Index of refraction of the solid (glass is about 1.5, water 1.33).
    /// A scene file that leaves it out reads NaN here, until its object is
    /// built: then 1.5, or `cauchy`'s index, which must not meet a given one.
    #[serde(default = "ior_not_given", deserialize_with = "number::f32")]
    pub ior: f32,
    /// An optional second colour laid out in squares.
    pub checker: Option<Checker>,
    /// How the transparent share splits between reflection and
    /// transmission at each crossing (chapter 9): `"none"` keeps chapter
    /// 8's constant `reflectivity` and `transparency`.
    pub fresnel: FresnelModel,
    /// Beer-Lambert absorption inside the solid, per unit length and per
    /// channel (chapter 9): light crossing a thickness `d` keeps
    /// `exp(-absorption d)`. Zero is clear.
    #[serde(deserialize_with = "number::vec3")]
    pub absorption: Vec3,
    /// Light the surface gives off as radiance (chapter 13: an area
    /// light), from its front: the side its normal faces (outward for a
    /// sphere, `u x v` for a quad, by the winding for a triangle). Zero for
    /// a surface that only reflects.
    #[serde(deserialize_with = "number::vec3")]
    pub emission: Vec3,
    /// Whether `emission` leaves both faces (pbrt-v4's `twosided`): a lamp
    /// in a ceiling shines down only, the inside of a glowing sphere needs
    /// both.
    pub two_sided: bool,
    /// How rough a mirror is (chapter 13): 0 is a perfect mirror, larger
    /// spreads the reflection into a glossy lobe, 1 the widest.
    #[serde(deserialize_with = "number::f32")]
    pub roughness: f32,
    /// An index of refraction that depends on the wavelength (chapter 14's
    /// dispersion), by Cauchy's equation; `ior` is then its value at the
    /// helium d line, what the stages before chapter 14 use.
    pub cauchy: Option<Cauchy>,
}

/// Cauchy's equation for the index of refraction of a glass at wavelength
/// `lambda`: `n = a + b / lambda^2`, with `lambda` in micrometres (the unit
/// of the coefficients glass tables quote: BK7 is `a = 1.5046`, `b =
/// 0.00420`).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cauchy {
    #[serde(deserialize_with = "number::f32")]
    pub a: f32,
    /// In square micrometres.
    #[serde(deserialize_with = "number::f32")]
    pub b: f32,
}

impl Cauchy {
    /// The index at `nanometres`, for raylab's own use: the scene's
    /// constant `ior` for the stages before chapter 14, worked out while
    /// the scene loads. It is chapter 14's `cauchy_ior`, the formula a
    /// student writes, so it is not public: the public
    /// [`Cauchy::index_at`] (src/course.rs) reports to the answer key.
    pub(crate) fn index(&self, nanometres: f32) -> f32 {
        let micrometres = nanometres / 1000.0;
        self.a + self.b / (micrometres * micrometres)
    }
}

/// How a transparent material reflects (chapter 9).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FresnelModel {
    /// Chapter 8's constants: `reflectivity` reflects, `transparency` goes
    /// through, whatever the angle (total internal reflection aside).
    #[default]
    None,
    /// Schlick's approximation of the Fresnel reflectance.
    Schlick,
    /// The exact unpolarised Fresnel reflectance of a dielectric.
    Exact,
}

/// `Material::ior` as serde reads a scene file without it: no index is
/// NaN, which the file cannot give (`number::f32` refuses it).
fn ior_not_given() -> f32 {
    f32::NAN
}

impl Default for Material {
    fn default() -> Self {
        Material {
            color: Vec3::splat(0.8),
            ambient: 0.1,
            diffuse: 0.9,
            specular: 0.0,
            shininess: 32,
            reflectivity: 0.0,
            transparency: 0.0,
            ior: 1.5,
            checker: None,
            fresnel: FresnelModel::None,
            absorption: Vec3::ZERO,
            emission: Vec3::ZERO,
            two_sided: false,
            roughness: 0.0,
            cauchy: None,
        }
    }
}

/// A checker pattern: squares of `size` alternate between the material's
/// colour and this `color`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Checker {
    #[serde(alias = "colour")]
    #[serde(deserialize_with = "number::vec3")]
    pub color: Vec3,
    #[serde(deserialize_with = "number::f32")]
    pub size: f32,
}

impl Material {
    /// The material's colour at `point` on `shape`, with the checker applied.
    pub fn albedo_at(&self, shape: &Shape, point: Vec3) -> Vec3 {
        let Some(checker) = self.checker else {
            return self.color;
        };
        let cells = (shape.pattern_coordinates(point) / checker.size).floor();
        // Parity of the sum = xor of the parities (no overflow for far cells).
        let odd = |cell: f32| (cell as i64) & 1 == 1;
        if odd(cells.x) ^ odd(cells.y) ^ odd(cells.z) {
            checker.color
        } else {
            self.color
        }
    }
}

pub(super) fn check_material(label: &str, material: &Material) -> Result<(), String> {
    let field = |name: &str| format!("{label}: material.{name}");
    check_albedo(&field("color"), material.color)?;
    check_coefficient(&field("ambient"), material.ambient, 1.0)?;
    check_coefficient(&field("diffuse"), material.diffuse, 1.0)?;
    check_coefficient(&field("specular"), material.specular, 1.0)?;
    check_coefficient(&field("reflectivity"), material.reflectivity, 1.0)?;
    check_coefficient(&field("transparency"), material.transparency, 1.0)?;
    if material.reflectivity + material.transparency > 1.0 {
        return Err(format!(
            "{label}: material.reflectivity + material.transparency = {}: must be at most 1",
            material.reflectivity + material.transparency
        ));
    }
    if material.shininess > MAX_SHININESS {
        return Err(format!(
            "{} = {}: at most {MAX_SHININESS}",
            field("shininess"),
            material.shininess
        ));
    }
    if !(material.ior > 0.0 && material.ior.is_finite()) {
        return Err(format!(
            "{} = {}: an index of refraction must be a finite number > 0",
            field("ior"),
            material.ior
        ));
    }
    check_light_color(&field("emission"), material.emission)?;
    check_coefficient(&field("roughness"), material.roughness, 1.0)?;
    if let Some(cauchy) = material.cauchy {
        check_cauchy(label, cauchy)?;
    }
    check_finite(&field("absorption"), material.absorption)?;
    if !(material.absorption.min_element() >= 0.0
        && material.absorption.max_element() <= MAX_ABSORPTION)
    {
        return Err(format!(
            "{} = {}: absorption is per unit length, each component between 0 and \
             {MAX_ABSORPTION:e} (0 is clear glass)",
            field("absorption"),
            material.absorption
        ));
    }
    if let Some(checker) = material.checker {
        check_albedo(&field("checker.color"), checker.color)?;
        if !(checker.size > 0.0 && checker.size.is_finite()) {
            return Err(format!(
                "{} = {}: must be a finite number > 0",
                field("checker.size"),
                checker.size
            ));
        }
    }
    Ok(())
}

/// Cauchy's coefficients of a real glass: `a` at least 1 (light is
/// slower in glass than in vacuum) and `b` between 0 (no dispersion) and
/// [`MAX_CAUCHY_B`].
fn check_cauchy(label: &str, cauchy: Cauchy) -> Result<(), String> {
    if !(cauchy.a >= 1.0 && cauchy.a <= MAX_CAUCHY_A) {
        return Err(format!(
            "{label}: material.cauchy.a = {}: Cauchy's constant term is an index of \
             refraction, between 1 and {MAX_CAUCHY_A}",
            cauchy.a
        ));
    }
    if !(cauchy.b >= 0.0 && cauchy.b <= MAX_CAUCHY_B) {
        return Err(format!(
            "{label}: material.cauchy.b = {}: in square micrometres, between 0 (no \
             dispersion) and {MAX_CAUCHY_B} (glass tables quote 0.0035 to 0.0134)",
            cauchy.b
        ));
    }
    Ok(())
}
