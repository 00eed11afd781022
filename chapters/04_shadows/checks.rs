//! Chapter 4's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 4`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const SHADOW_RAYS_4: &str = "Shadow rays";
const WHERE_4: &str = "Where a shadow ray starts";
const OFFSET_4: &str = "The error-scaled offset";

/// One tilted floor, its point not representable in binary: the plane
/// where a shadow ray without an offset shows acne.
const TILTED_FLOOR: &str = "[camera]\nposition = [0.0, 2.0, -6.0]\nlook_at = [0.0, 0.0, 0.0]\n\
                            [[lights]]\nposition = [-4.0, 6.0, -3.0]\n\
                            [[objects]]\nplane = { point = [0.3, 0.1, 0.7], normal = [0.01, 1.0, 0.02] }\n";

/// Rays from `light` to a grid of 64 points of the ball (`center`,
/// `radius`) that face it: every point they reach sees the light.
fn rays_from_light(light: Vec3, center: Vec3, radius: f32) -> Vec<Ray> {
    let toward = (center - light).normalize();
    let side = toward.cross(Vec3::Y).normalize();
    let up = side.cross(toward);
    let mut rays = Vec::new();
    for i in 0..8 {
        for j in 0..8 {
            let (a, b) = ((i as f32 - 3.5) / 5.0, (j as f32 - 3.5) / 5.0);
            let target = center + radius * (a * side + b * up);
            rays.push(Ray::new(light, target - light));
        }
    }
    rays
}

fn surface(shape: Shape, origin: Vec3, toward: Vec3) -> crate::SurfacePoint {
    let ray = Ray::new(origin, toward - origin);
    let t = shape.intersect(&ray, 0.0, INF).unwrap_or(1.0);
    shape.surface_point(&ray, t)
}

pub fn checkpoints() -> Vec<Case> {
    let floor: Shape = Plane::new(Vec3::ZERO, Vec3::Y).into();
    let ball: Shape = Sphere::new(v(0.0, 1.0, 0.0), 1.0).into();
    let floor_point = surface(floor, v(0.5, 4.0, 0.0), v(0.5, 0.0, 2.0));
    let ball_top = surface(ball, v(0.3, 5.0, 0.2), v(0.0, 1.0, 0.0));
    let offset = |name, section, says, surface, dir| {
        Case::new(
            name,
            section,
            says,
            CaseKind::Offset {
                surface,
                dir,
                at_most: 1e-2,
            },
        )
    };
    let shadow = |name, says, rays: Vec<Ray>, light, expect, lights: &str| {
        Case::new(
            name,
            SHADOW_RAYS_4,
            says,
            CaseKind::Shadow {
                scene: floor_and_ball(lights),
                object: if rays.len() > 1 { 1 } else { 0 },
                rays,
                light,
                expect,
            },
        )
    };
    let flat = |name, says, ray: (Vec3, Vec3), lights: &str| {
        Case::new(
            name,
            SHADOW_RAYS_4,
            says,
            CaseKind::Shade {
                shading: Shading::Flat,
                scene: floor_and_ball(lights),
                ray: Ray::new(ray.0, ray.1),
                depth: 0,
            },
        )
    };
    // A slanted ray that reaches the floor point (0.2, 0, 0), next to where
    // the ball touches the floor, without touching the ball.
    let under_ball = (v(5.0, 0.5, 0.0), v(-4.8, -0.5, 0.0));
    let beside_ball = (v(3.0, 5.0, 0.0), -Vec3::Y);
    let light_above = v(0.0, 10.0, 0.0);
    vec![
        offset(
            "offset-floor-up",
            WHERE_4,
            format!(
                "a shadow ray leaving the floor point {} upward, along (0.3, 1, 0.2), must start \
                 above the floor by at least the point's error bound dot(|n|, error), and by \
                 less than 0.01",
                vec(floor_point.point)
            ),
            floor_point,
            v(0.3, 1.0, 0.2),
        ),
        offset(
            "offset-floor-down",
            WHERE_4,
            "the same floor point, a ray leaving downward along (0.3, -1, 0) (through the \
             surface, as a refracted ray does): it must start below the floor"
                .to_string(),
            floor_point,
            v(0.3, -1.0, 0.0),
        ),
        offset(
            "offset-ball-out",
            WHERE_4,
            format!(
                "a ray leaving the top of the unit ball at {} upward must start outside the ball",
                vec(ball_top.point)
            ),
            ball_top,
            v(0.2, 1.0, 0.0),
        ),
        offset(
            "offset-ball-in",
            WHERE_4,
            "the same point of the ball, a ray going into it: it must start inside".to_string(),
            ball_top,
            v(0.1, -1.0, 0.3),
        ),
        shadow(
            "shadow-under-ball",
            "the floor point (0.2, 0, 0), next to where the unit ball at (0, 1, 0) touches the \
             floor, with a light straight above at (0, 10, 0): the ball is between them, \
             expected in shadow",
            vec![Ray::new(under_ball.0, under_ball.1)],
            light_above,
            true,
            LIGHT_ABOVE,
        ),
        shadow(
            "shadow-beside-ball",
            "the floor point (3, 0, 0), light at (0, 10, 0): nothing between them, expected lit",
            vec![Ray::new(beside_ball.0, beside_ball.1)],
            light_above,
            false,
            LIGHT_ABOVE,
        ),
        shadow(
            "shadow-blocker-beyond-light",
            "the floor point (3, 0, 0), light at (2, 0.5, 0): the ball lies on the same line but \
             beyond the light (t > 1 on a shadow ray from the point to the light), expected lit",
            vec![Ray::new(beside_ball.0, beside_ball.1)],
            v(2.0, 0.5, 0.0),
            false,
            LIGHT_ABOVE,
        ),
        shadow(
            "shadow-no-acne",
            "64 rays from the light at (-4, 6, -3) to the unit ball at (0, 1, 0): every point they \
             reach sees the light, so none may be in shadow (a shadow ray must not hit the \
             surface it leaves: shadow acne)",
            rays_from_light(v(-4.0, 6.0, -3.0), v(0.0, 1.0, 0.0), 1.0),
            v(-4.0, 6.0, -3.0),
            false,
            LIGHT_ABOVE,
        ),
        Case::new(
            "shadow-no-acne-plane",
            SHADOW_RAYS_4,
            "64 rays from the light at (-4, 6, -3) to a floor through (0.3, 0.1, 0.7), tilted to \
             the normal (0.01, 1, 0.02): every point they reach sees the light, so none may be in \
             shadow. A tilted plane's points are rounded in every coordinate, so a shadow ray \
             started exactly on it meets it again just past its origin (chapter 2's stable \
             sphere test hides this on balls; the offset is what keeps planes clean)",
            CaseKind::Shadow {
                scene: TILTED_FLOOR.to_string(),
                object: 0,
                rays: rays_from_light(v(-4.0, 6.0, -3.0), v(0.3, 0.1, 0.7), 2.0),
                light: v(-4.0, 6.0, -3.0),
                expect: false,
            },
        ),
        flat(
            "flat-lit",
            "the floor point (3, 0, 0) (albedo 0.5, k_a = 0.2, k_d = 0.6, white ambient light), \
             lit by the light at (0, 10, 0): expected 0.2 * 0.5 + 0.6 * 0.5 = 0.4 in each channel",
            beside_ball,
            LIGHT_ABOVE,
        ),
        flat(
            "flat-shadowed",
            "the floor point (0.2, 0, 0) under the ball, light at (0, 10, 0): only ambient, \
             expected 0.2 * 0.5 = 0.1",
            under_ball,
            LIGHT_ABOVE,
        ),
        flat(
            "flat-two-lights",
            "the floor point (0.2, 0, 0), the light above hidden by the ball, a second light of \
             intensity 0.5 low on the right at (10, 0.5, 0) reaching it: expected \
             0.1 + 0.6 * 0.5 * 0.5 = 0.25",
            under_ball,
            TWO_LIGHTS,
        ),
        flat(
            "flat-light-below",
            "the floor point (3, 0, 0) seen from above, light below the floor at (0, -5, 0): it \
             lights the other side only, expected 0.1",
            beside_ball,
            "[[lights]]\nposition = [0.0, -5.0, 0.0]\n",
        ),
        Case::new(
            "flat-dim-ambient",
            SHADOW_RAYS_4,
            "the floor point (3, 0, 0) lit from (0, 10, 0) as in flat-lit, under a dim, coloured \
             ambient light (0.5, 0.25, 1): the ambient term is albedo * k_a * ambient light, \
             0.1 * (0.5, 0.25, 1), and the light's share 0.3 is not scaled by it: expected \
             (0.35, 0.325, 0.4)",
            CaseKind::Shade {
                shading: Shading::Flat,
                scene: floor_and_ball_in(DIM_AMBIENT, LIGHT_ABOVE),
                ray: Ray::new(beside_ball.0, beside_ball.1),
                depth: 0,
            },
        ),
    ]
}

pub fn robustness() -> Vec<Case> {
    let far_ball: Shape = Sphere::new(v(1e4, 1.0, 1e4), 1.0).into();
    let side = surface(
        far_ball,
        v(1e4 - 5.0, 1.0, 1e4 + 0.3),
        v(1e4, 1.0, 1e4 + 0.3),
    );
    let small: Shape = Sphere::new(v(0.1, 0.1, 0.1), 0.01).into();
    let small_point = surface(small, v(0.1, 0.5, 0.1), v(0.1, 0.1, 0.1));
    let ball: Shape = Sphere::new(v(0.0, 1.0, 0.0), 1.0).into();
    let ball_side = surface(ball, v(-5.0, 1.0, 0.0), v(0.0, 1.0, 0.0));
    let offset = |name, says: &str, surface, dir| {
        Case::new(
            name,
            OFFSET_4,
            says,
            CaseKind::Offset {
                surface,
                dir,
                at_most: 0.0,
            },
        )
    };
    let far_scene = r#"
[camera]
position = [9990.0, 5.0, 9990.0]
look_at = [10000.0, 1.0, 10000.0]
[[lights]]
position = [9996.0, 6.0, 9997.0]
[[objects]]
sphere = { center = [10000.0, 1.0, 10000.0], radius = 1.0 }
"#;
    robust(vec![
        offset(
            "offset-far-ball",
            "the side of a unit ball at (1e4, 1, 1e4): its point's error bound is about 5e-3, \
             so a fixed push of 1e-4 leaves the origin where rounding can put it inside",
            side,
            v(-1.0, 0.5, 0.0),
        ),
        offset(
            "offset-grazing",
            "a ray leaving the side of the unit ball at (0, 1, 0) almost along the surface \
             (dot(dir, n) = 1e-3): pushing along dir barely moves it off the surface",
            ball_side,
            v(-1e-3, 1.0, 0.0),
        ),
        offset(
            "offset-small-ball",
            "a ball of radius 0.01 at (0.1, 0.1, 0.1): its error bound is 5e-8, and a push of \
             more than 16 error bounds detaches shadows from small objects",
            small_point,
            v(0.0, 1.0, 0.0),
        ),
        Case::new(
            "shadow-no-acne-far",
            SHADOW_RAYS_4,
            "64 rays from the light at (9996, 6, 9997) to a unit ball at (1e4, 1, 1e4): every \
             point they reach sees the light, none may be in shadow",
            CaseKind::Shadow {
                scene: far_scene.to_string(),
                object: 0,
                rays: rays_from_light(v(9996.0, 6.0, 9997.0), v(1e4, 1.0, 1e4), 1.0),
                light: v(9996.0, 6.0, 9997.0),
                expect: false,
            },
        ),
    ])
}
