//! The lights of a scene file: point lights (`[[lights]]`) and chapter
//! 14's beams of parallel light (`[[beams]]`).

use serde::Deserialize;

use super::{one, white};
use crate::Vec3;
use crate::number;

/// A point light.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Light {
    #[serde(deserialize_with = "number::vec3")]
    pub position: Vec3,
    #[serde(alias = "colour", default = "white")]
    #[serde(deserialize_with = "number::vec3")]
    pub color: Vec3,
    #[serde(default = "one")]
    #[serde(deserialize_with = "number::f32")]
    pub intensity: f32,
}

impl Light {
    /// Colour times intensity: what the light adds at full exposure.
    pub fn radiance(&self) -> Vec3 {
        self.color * self.intensity
    }
}

/// A beam of parallel light (chapter 14: sunlight through a window, the
/// beam a lens focuses): light of irradiance `intensity` (times `color`)
/// across the disk of `radius` about `position`, all of it travelling
/// along `direction`. Only the stages that trace paths (chapter 13 on) see
/// beams: no camera ray or scattered ray can find a light that shines in
/// one direction only, and light samples or light paths must aim at it.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Beam {
    #[serde(deserialize_with = "number::vec3")]
    pub position: Vec3,
    /// The way the light travels; made unit when the scene is read.
    #[serde(deserialize_with = "number::vec3")]
    pub direction: Vec3,
    #[serde(deserialize_with = "number::f32")]
    pub radius: f32,
    #[serde(alias = "colour", default = "white")]
    #[serde(deserialize_with = "number::vec3")]
    pub color: Vec3,
    /// Irradiance: power per unit area across the beam.
    #[serde(default = "one")]
    #[serde(deserialize_with = "number::f32")]
    pub intensity: f32,
}

impl Beam {
    /// Colour times intensity: the irradiance the beam brings to a surface
    /// square to it.
    pub fn irradiance(&self) -> Vec3 {
        self.color * self.intensity
    }
}
