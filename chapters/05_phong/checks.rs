//! Chapter 5's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 5`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const TERMS_5: &str = "The three terms";

/// A `phong_terms` question on a material of diffuse weight `k_d`,
/// specular weight `k_s` and exponent `shininess` (the rest default).
struct PhongTermsQuestion {
    name: &'static str,
    says: &'static str,
    k_d: f32,
    k_s: f32,
    shininess: u32,
    albedo: Vec3,
    normal: Vec3,
    to_light: Vec3,
    to_eye: Vec3,
    /// The light's colour.
    light: Vec3,
    expect: PhongTerms,
}

impl From<PhongTermsQuestion> for Case {
    fn from(question: PhongTermsQuestion) -> Case {
        Case::new(
            question.name,
            TERMS_5,
            question.says,
            CaseKind::PhongTerms(PhongTermsCase {
                material: Material {
                    diffuse: question.k_d,
                    specular: question.k_s,
                    shininess: question.shininess,
                    ..Material::default()
                },
                albedo: question.albedo,
                normal: question.normal,
                to_light: question.to_light,
                to_eye: question.to_eye,
                light: question.light,
                expect: question.expect,
            }),
        )
    }
}

/// Where the image differs when every checkpoint passes: what to look at
/// in the heatmap.
pub const IMAGE_HINT: &str = "in the highlights (the mirror direction of the light, the exponent) or in the diffuse shading (max(0, n.l) with the normal on the eye's side)";

/// Chapter 5's checkpoints (level 1), in the order they run: the first
/// that fails is the one reported.
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn checkpoints() -> Vec<Case> {
    let half_sqrt3 = 3f32.sqrt() / 2.0;
    let mirror = Vec3::new(1.0, 1.0, 0.0).normalize();
    let off_mirror = Vec3::new(0.5, half_sqrt3, 0.0);
    let cos15 = f64::from(mirror.dot(off_mirror));
    vec![
        Case::from(PhongTermsQuestion {
            name: "phong-diffuse-cosine",
            says: "a light 60 degrees from the normal (0, 1, 0), to_light = (0.866, 0.5, 0), \
                   white, albedo (1, 0.5, 0.25), k_d = 0.8: diffuse = albedo * k_d * cos 60 = \
                   (0.4, 0.2, 0.1), no specular (k_s = 0)",
            k_d: 0.8,
            k_s: 0.0,
            shininess: 1,
            albedo: Vec3::new(1.0, 0.5, 0.25),
            normal: Vec3::Y,
            to_light: Vec3::new(half_sqrt3, 0.5, 0.0),
            to_eye: Vec3::Y,
            light: Vec3::ONE,
            expect: PhongTerms {
                diffuse: Vec3::new(0.4, 0.2, 0.1),
                specular: Vec3::ZERO,
            },
        }),
        Case::from(PhongTermsQuestion {
            name: "phong-specular-peak",
            says: "light from (-1, 1, 0)/sqrt 2, eye exactly in the mirror direction \
                   (1, 1, 0)/sqrt 2, k_s = 0.5, shininess 10: specular = 0.5 * 1^10 = 0.5 \
                   (k_d = 0: no diffuse)",
            k_d: 0.0,
            k_s: 0.5,
            shininess: 10,
            albedo: Vec3::ONE,
            normal: Vec3::Y,
            to_light: Vec3::new(-1.0, 1.0, 0.0).normalize(),
            to_eye: mirror,
            light: Vec3::ONE,
            expect: PhongTerms {
                diffuse: Vec3::ZERO,
                specular: Vec3::splat(0.5),
            },
        }),
        Case::from(PhongTermsQuestion {
            name: "phong-specular-off-peak",
            says: "the same light, eye 15 degrees off the mirror direction at (0.5, 0.866, 0): \
                   specular = 0.5 * cos(15)^10 = 0.3535",
            k_d: 0.0,
            k_s: 0.5,
            shininess: 10,
            albedo: Vec3::ONE,
            normal: Vec3::Y,
            to_light: Vec3::new(-1.0, 1.0, 0.0).normalize(),
            to_eye: off_mirror,
            light: Vec3::ONE,
            expect: PhongTerms {
                diffuse: Vec3::ZERO,
                specular: Vec3::splat((0.5 * cos15.powi(10)) as f32),
            },
        }),
        Case::from(PhongTermsQuestion {
            name: "phong-light-behind",
            says: "a light behind the surface (to_light = (0, -1, 0), normal (0, 1, 0)): both \
                   terms 0",
            k_d: 1.0,
            k_s: 1.0,
            shininess: 8,
            albedo: Vec3::ONE,
            normal: Vec3::Y,
            to_light: -Vec3::Y,
            to_eye: Vec3::Y,
            light: Vec3::ONE,
            expect: PhongTerms {
                diffuse: Vec3::ZERO,
                specular: Vec3::ZERO,
            },
        }),
        Case::from(PhongTermsQuestion {
            name: "phong-highlight-untinted",
            says: "a red surface (albedo (1, 0, 0), k_d = 0.5, k_s = 0.5, shininess 1) lit and \
                   seen along its normal by a light (1, 0.9, 0.7): diffuse (0.5, 0, 0); the \
                   highlight has the light's colour, not the albedo's: specular (0.5, 0.45, 0.35)",
            k_d: 0.5,
            k_s: 0.5,
            shininess: 1,
            albedo: Vec3::new(1.0, 0.0, 0.0),
            normal: Vec3::Y,
            to_light: Vec3::Y,
            to_eye: Vec3::Y,
            light: Vec3::new(1.0, 0.9, 0.7),
            expect: PhongTerms {
                diffuse: Vec3::new(0.5, 0.0, 0.0),
                specular: Vec3::new(0.5, 0.45, 0.35),
            },
        }),
        Case::from(ShadeQuestion {
            name: "phong-sum-lit",
            section: TERMS_5,
            says: "the floor point (3, 0, 0) \
                   (albedo 0.5, k_a = 0.2, k_d = 0.6, k_s = 0.5, shininess 8) lit from (0, 10, 0), \
                   seen from straight above: cos i = 10 / sqrt(109) = 0.958, so diffuse 0.1 + 0.6 \
                   * 0.5 * 0.958 = 0.3873, and the mirrored light makes the same angle with the \
                   eye: specular 0.5 * 0.958^8 = 0.354",
            shading: Shading::Phong,
            scene: floor_and_ball(LIGHT_ABOVE),
            ray: (Vec3::new(3.0, 5.0, 0.0), -Vec3::Y),
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "phong-sum-lit-from-below",
            section: TERMS_5,
            says: "phong-sum-lit upside down: the floor point (3, 0, 0) seen from straight below, \
                   from (3, -5, 0), lit from (0, -10, 0): the side the eye sees faces the light \
                   (the normal turned toward the eye, not the plane's own (0, 1, 0)), so the same \
                   diffuse 0.3873 and specular 0.354",
            shading: Shading::Phong,
            scene: floor_and_ball("[[lights]]\nposition = [0.0, -10.0, 0.0]\n"),
            ray: (Vec3::new(3.0, -5.0, 0.0), Vec3::Y),
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "phong-sum-one-hidden",
            section: TERMS_5,
            says: "the floor point (0.2, 0, 0) under the ball: the light above is hidden, the \
                   light of intensity 0.5 at (10, 0.5, 0) is not: diffuse 0.1 + 0.6 * 0.5 * 0.5 * \
                   0.05095 = 0.1076",
            shading: Shading::Phong,
            scene: floor_and_ball(TWO_LIGHTS),
            ray: (Vec3::new(5.0, 0.5, 0.0), Vec3::new(-4.8, -0.5, 0.0)),
            depth: 0,
        }),
        Case::new(
            "phong-sum-dim-ambient",
            TERMS_5,
            "phong-sum-lit under a dim, coloured ambient light (0.5, 0.25, 1): the ambient term is \
             albedo * k_a * ambient light = 0.1 * (0.5, 0.25, 1), the light's terms are as before: \
             diffuse (0.3373, 0.3123, 0.3873), specular 0.354",
            CaseKind::Shade(ShadeCase {
                shading: Shading::Phong,
                scene: floor_and_ball_in(DIM_AMBIENT, LIGHT_ABOVE),
                ray: Ray::new(Vec3::new(3.0, 5.0, 0.0), -Vec3::Y),
                depth: 0,
                vertex_normals: None,
            }),
        ),
        Case::from(PhongTermsQuestion {
            name: "phong-light-behind-eye-at-its-mirror",
            says: "a light behind the surface, to_light = (-0.6, -0.8, 0) with normal (0, 1, 0), \
                   and the eye low at (0.96, 0.28, 0), where the light's mirror image r = (0.6, \
                   -0.8, 0) still gives r.v = 0.352 > 0: the light is behind, so both terms are 0 \
                   (k_d = k_s = 1, shininess 1; clamping n.l and r.v each at 0 is not enough)",
            k_d: 1.0,
            k_s: 1.0,
            shininess: 1,
            albedo: Vec3::ONE,
            normal: Vec3::Y,
            to_light: Vec3::new(-0.6, -0.8, 0.0),
            to_eye: Vec3::new(0.96, 0.28, 0.0),
            light: Vec3::ONE,
            expect: PhongTerms {
                diffuse: Vec3::ZERO,
                specular: Vec3::ZERO,
            },
        }),
        Case::from(ShadeQuestion {
            name: "phong-sum-coloured-light",
            section: TERMS_5,
            says: "phong-sum-lit with the light coloured (1, 0.5, 0.25): both of its terms are \
                   scaled by the colour, diffuse 0.1 + 0.2873 * (1, 0.5, 0.25) = (0.3873, 0.2437, \
                   0.1718), specular 0.354 * (1, 0.5, 0.25) = (0.354, 0.177, 0.0885)",
            shading: Shading::Phong,
            scene: floor_and_ball(
                "[[lights]]\nposition = [0.0, 10.0, 0.0]\ncolor = [1.0, 0.5, 0.25]\n",
            ),
            ray: (Vec3::new(3.0, 5.0, 0.0), -Vec3::Y),
            depth: 0,
        }),
    ]
}

/// Chapter 5's hard cases (level 2).
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn robustness() -> Vec<Case> {
    robust(vec![
        Case::from(PhongTermsQuestion {
            name: "phong-grazing-light",
            says: "a light grazing the surface, cos i = 1e-7: tiny but not negative, never NaN",
            k_d: 1.0,
            k_s: 0.0,
            shininess: 8,
            albedo: Vec3::ONE,
            normal: Vec3::Y,
            to_light: Vec3::new(1.0, 1e-7, 0.0),
            to_eye: Vec3::Y,
            light: Vec3::ONE,
            expect: PhongTerms {
                diffuse: Vec3::splat(1e-7),
                specular: Vec3::ZERO,
            },
        }),
        Case::from(PhongTermsQuestion {
            name: "phong-nan-to-eye",
            says: "a NaN direction to the eye (a ray that went wrong upstream): the highlight's \
               cosine is NaN, and clamping it with f32::max(NaN, 0) = 0 would hide it as a \
               plausible colour the render cannot count: expected a non-finite term",
            k_d: 1.0,
            k_s: 0.5,
            shininess: 8,
            albedo: Vec3::ONE,
            normal: Vec3::Y,
            to_light: Vec3::Y,
            to_eye: Vec3::NAN,
            light: Vec3::ONE,
            expect: PhongTerms {
                diffuse: Vec3::ONE,
                specular: Vec3::NAN,
            },
        }),
    ])
}
