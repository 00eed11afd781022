//! The reference a sweep measures every row against, and the far-sphere
//! scene the sphere formula is swept on. What "most accurate" means for
//! each knob is decided here and nowhere else: the rows turn one knob away
//! from it, so tightening the reference never touches the sweep's values.

use crate::scene::{FresnelModel, OffsetRule, SphereFormula, TriangleTest};
use crate::{RenderSettings, Sampling, Scene};

/// Samples per pixel of the reference, for stages that supersample.
pub const REFERENCE_SAMPLES: u32 = 256;
/// Bounces of the reference.
pub const REFERENCE_DEPTH: u32 = 16;

/// `scene` with `model` on every transparent material (the others have no
/// transmitted share for Fresnel to split).
pub fn with_fresnel(scene: &Scene, model: FresnelModel) -> Scene {
    let mut scene = scene.clone();
    for material in scene.materials_mut() {
        if material.transparency > 0.0 {
            material.fresnel = model;
        }
    }
    scene
}

/// The reference's `min_contribution` from chapter 9 on. Fresnel splits
/// every crossing of glass in two, so casting every ray to depth 16 is up
/// to 2^16 rays per sample in the glass (the chapter 9 sweep did not finish
/// in 15 minutes). Rays below 1e-5 of the pixel are skipped instead: each
/// is at most 1e-5 of the pixel's light, far below the half code (2e-3)
/// that changes an 8-bit value, unless thousands of them add up in one
/// pixel.
pub const GLASS_REFERENCE_MIN_CONTRIBUTION: f32 = 1e-5;

/// The reference: `base` with every knob at its most accurate setting.
/// `256` jittered samples per pixel (ignored before chapter 7), depth 16, no
/// minimum contribution, the scaled offset and the stable sphere formula.
pub fn reference_settings(base: &RenderSettings) -> RenderSettings {
    RenderSettings {
        samples: REFERENCE_SAMPLES,
        sampling: Sampling::Jittered,
        max_depth: REFERENCE_DEPTH,
        min_contribution: 0.0,
        ray_offset: OffsetRule::Scaled,
        sphere_formula: SphereFormula::Stable,
        triangle_test: TriangleTest::Watertight,
        march_tolerance: REFERENCE_MARCH_TOLERANCE,
        march_steps: REFERENCE_MARCH_STEPS,
        march_relaxation: 1.0,
        lipschitz: crate::shapes::LipschitzRule::Bound,
        newton: true,
        normals: crate::shapes::NormalMethod::Analytic,
        ..*base
    }
}

/// The reference's march: a tolerance and a budget far beyond the sweep's,
/// safe steps, Newton, the analytic normal.
pub const REFERENCE_MARCH_TOLERANCE: f32 = 1e-6;
pub const REFERENCE_MARCH_STEPS: u32 = 4096;

/// Samples per pixel of the reference of a path-traced sweep: sixteen
/// times the most the sweep takes, so the reference's own noise is a
/// quarter of the best row's.
pub const PATH_REFERENCE_SAMPLES: u32 = 4096;

/// The scene of the [`Knob::SphereFormula`](super::Knob::SphereFormula)
/// sweep: a ball of radius 1 seen
/// from 1000 units away through a narrow lens, in front of a wall that
/// catches its shadow. With the camera that far, `b^2` and `4ac` in the
/// textbook formula are about `4e6` and differ by at most 4: the rounding of
/// either (a few tenths) is a visible share of the difference.
pub const FAR_SPHERE_SCENE: &str = r#"# The far small sphere of `raylab cost`: a ball of radius 1, 1000 units
# from the camera, in front of a wall 1.5 units behind it.
background = [0.55, 0.7, 0.9]
ambient_light = [1.0, 1.0, 1.0]

[camera]
position = [0.0, 0.0, -1000.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov_degrees = 0.2

[render]
width = 160
height = 120

[[lights]]
position = [-600.0, 800.0, -1000.0]
intensity = 1.0

[[objects]]
name = "far ball"
sphere = { center = [0.0, 0.0, 0.0], radius = 1.0 }
material = { color = [0.8, 0.2, 0.1], ambient = 0.1, diffuse = 0.8, specular = 0.5, shininess = 32 }

[[objects]]
name = "wall"
plane = { point = [0.0, 0.0, 1.5], normal = [0.0, 0.0, -1.0] }
material = { color = [0.9, 0.9, 0.85], ambient = 0.1, diffuse = 0.8, checker = { color = [0.5, 0.5, 0.55], size = 0.5 } }
"#;

/// The far-sphere scene, parsed.
pub fn far_sphere_scene() -> Scene {
    Scene::parse(FAR_SPHERE_SCENE, "the far-sphere scene of raylab cost")
        .expect("the built-in far-sphere scene is valid")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn far_sphere_scene_is_valid() {
        assert_eq!(far_sphere_scene().shapes.len(), 2);
    }
}
