//! Chapter 5's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 5`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const TERMS_5: &str = "The three terms";

#[allow(clippy::too_many_arguments)]
fn phong(
    name: &'static str,
    says: &str,
    material: (f32, f32, u32),
    albedo: Vec3,
    normal: Vec3,
    to_light: Vec3,
    to_eye: Vec3,
    light: Vec3,
    expect: (Vec3, Vec3),
) -> Case {
    Case::new(
        name,
        TERMS_5,
        says,
        CaseKind::PhongTerms {
            material: Material {
                diffuse: material.0,
                specular: material.1,
                shininess: material.2,
                ..Material::default()
            },
            albedo,
            normal,
            to_light,
            to_eye,
            light,
            expect: PhongTerms {
                diffuse: expect.0,
                specular: expect.1,
            },
        },
    )
}

pub fn checkpoints() -> Vec<Case> {
    let half_sqrt3 = 3f32.sqrt() / 2.0;
    let mirror = v(1.0, 1.0, 0.0).normalize();
    let off_mirror = v(0.5, half_sqrt3, 0.0);
    let cos15 = f64::from(mirror.dot(off_mirror));
    let shade = |name, says, ray: (Vec3, Vec3), lights: &str| {
        Case::new(
            name,
            TERMS_5,
            says,
            CaseKind::Shade {
                shading: Shading::Phong,
                scene: floor_and_ball(lights),
                ray: Ray::new(ray.0, ray.1),
                depth: 0,
            },
        )
    };
    vec![
        phong(
            "phong-diffuse-cosine",
            "a light 60 degrees from the normal (0, 1, 0), to_light = (0.866, 0.5, 0), white, \
             albedo (1, 0.5, 0.25), k_d = 0.8: diffuse = albedo * k_d * cos 60 = (0.4, 0.2, 0.1), \
             no specular (k_s = 0)",
            (0.8, 0.0, 1),
            v(1.0, 0.5, 0.25),
            Vec3::Y,
            v(half_sqrt3, 0.5, 0.0),
            Vec3::Y,
            Vec3::ONE,
            (v(0.4, 0.2, 0.1), Vec3::ZERO),
        ),
        phong(
            "phong-specular-peak",
            "light from (-1, 1, 0)/sqrt 2, eye exactly in the mirror direction (1, 1, 0)/sqrt 2, \
             k_s = 0.5, shininess 10: specular = 0.5 * 1^10 = 0.5 (k_d = 0: no diffuse)",
            (0.0, 0.5, 10),
            Vec3::ONE,
            Vec3::Y,
            v(-1.0, 1.0, 0.0).normalize(),
            mirror,
            Vec3::ONE,
            (Vec3::ZERO, Vec3::splat(0.5)),
        ),
        phong(
            "phong-specular-off-peak",
            "the same light, eye 15 degrees off the mirror direction at (0.5, 0.866, 0): \
             specular = 0.5 * cos(15)^10 = 0.3535",
            (0.0, 0.5, 10),
            Vec3::ONE,
            Vec3::Y,
            v(-1.0, 1.0, 0.0).normalize(),
            off_mirror,
            Vec3::ONE,
            (Vec3::ZERO, Vec3::splat((0.5 * cos15.powi(10)) as f32)),
        ),
        phong(
            "phong-light-behind",
            "a light behind the surface (to_light = (0, -1, 0), normal (0, 1, 0)): both terms 0",
            (1.0, 1.0, 8),
            Vec3::ONE,
            Vec3::Y,
            -Vec3::Y,
            Vec3::Y,
            Vec3::ONE,
            (Vec3::ZERO, Vec3::ZERO),
        ),
        phong(
            "phong-highlight-untinted",
            "a red surface (albedo (1, 0, 0), k_d = 0.5, k_s = 0.5, shininess 1) lit and seen \
             along its normal by a light (1, 0.9, 0.7): diffuse (0.5, 0, 0); the highlight has \
             the light's colour, not the albedo's: specular (0.5, 0.45, 0.35)",
            (0.5, 0.5, 1),
            v(1.0, 0.0, 0.0),
            Vec3::Y,
            Vec3::Y,
            Vec3::Y,
            v(1.0, 0.9, 0.7),
            (v(0.5, 0.0, 0.0), v(0.5, 0.45, 0.35)),
        ),
        shade(
            "phong-sum-lit",
            "the floor point (3, 0, 0) (albedo 0.5, k_a = 0.2, k_d = 0.6, k_s = 0.5, shininess 8) \
             lit from (0, 10, 0), seen from straight above: cos i = 10 / sqrt(109) = 0.958, so \
             diffuse 0.1 + 0.6 * 0.5 * 0.958 = 0.3873, and the mirrored light makes the same \
             angle with the eye: specular 0.5 * 0.958^8 = 0.354",
            (v(3.0, 5.0, 0.0), -Vec3::Y),
            LIGHT_ABOVE,
        ),
        shade(
            "phong-sum-one-hidden",
            "the floor point (0.2, 0, 0) under the ball: the light above is hidden, the light of \
             intensity 0.5 at (10, 0.5, 0) is not: diffuse 0.1 + 0.6 * 0.5 * 0.5 * 0.05095 = 0.1076",
            (v(5.0, 0.5, 0.0), v(-4.8, -0.5, 0.0)),
            TWO_LIGHTS,
        ),
        Case::new(
            "phong-sum-dim-ambient",
            TERMS_5,
            "phong-sum-lit under a dim, coloured ambient light (0.5, 0.25, 1): the ambient term \
             is albedo * k_a * ambient light = 0.1 * (0.5, 0.25, 1), the light's terms are as \
             before: diffuse (0.3373, 0.3123, 0.3873), specular 0.354",
            CaseKind::Shade {
                shading: Shading::Phong,
                scene: floor_and_ball_in(DIM_AMBIENT, LIGHT_ABOVE),
                ray: Ray::new(v(3.0, 5.0, 0.0), -Vec3::Y),
                depth: 0,
            },
        ),
    ]
}

pub fn robustness() -> Vec<Case> {
    robust(vec![phong(
        "phong-grazing-light",
        "a light grazing the surface, cos i = 1e-7: tiny but not negative, never NaN",
        (1.0, 0.0, 8),
        Vec3::ONE,
        Vec3::Y,
        v(1.0, 1e-7, 0.0),
        Vec3::Y,
        Vec3::ONE,
        (Vec3::splat(1e-7), Vec3::ZERO),
    )])
}
