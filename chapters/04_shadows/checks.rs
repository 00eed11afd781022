//! Chapter 4's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 4`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const SHADOW_RAYS_4: &str = "Shadow rays";
const WHERE_4: &str = "Where a shadow ray starts";
const OFFSET_4: &str = "The error-scaled offset";

/// One tilted floor, its point not representable in binary: the plane
/// where a shadow ray without an offset shows acne.
const TILTED_FLOOR: &str = "[camera]\nposition = [0.0, 2.0, -6.0]\nlook_at = \
                            [0.0, 0.0, 0.0]\n[[lights]]\nposition = \
                            [-4.0, 6.0, -3.0]\n[[objects]]\nplane = { point = [0.3, 0.1, 0.7], \
                            normal = [0.01, 1.0, 0.02] }\n";

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

/// An `offset_origin` question: a ray leaving `surface` along `dir` must
/// start off it on `dir`'s side, by at most `at_most` (0 for the robustness
/// level, whose bound is in error bounds: see [`CaseKind::Offset`]).
struct OffsetQuestion {
    name: &'static str,
    section: &'static str,
    says: String,
    surface: crate::SurfacePoint,
    dir: Vec3,
    at_most: f64,
}

impl From<OffsetQuestion> for Case {
    fn from(question: OffsetQuestion) -> Case {
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::Offset(OffsetCase {
                surface: question.surface,
                dir: question.dir,
                at_most: question.at_most,
            }),
        )
    }
}

/// An `in_shadow` question on [`floor_and_ball`] lit by `scene_lights`
/// (TOML), at the points where `rays` meet it, for a light at `light`: a
/// single ray asks about the floor (object 0), a fan of rays about the ball
/// (object 1).
struct ShadowQuestion {
    name: &'static str,
    says: &'static str,
    scene_lights: &'static str,
    rays: Vec<Ray>,
    light: Vec3,
    expect: bool,
}

impl From<ShadowQuestion> for Case {
    fn from(question: ShadowQuestion) -> Case {
        Case::new(
            question.name,
            SHADOW_RAYS_4,
            question.says,
            CaseKind::Shadow(ShadowCase {
                scene: floor_and_ball(question.scene_lights),
                object: if question.rays.len() > 1 { 1 } else { 0 },
                rays: question.rays,
                light: question.light,
                expect: question.expect,
            }),
        )
    }
}

/// The light of [`LIGHT_ABOVE`], coloured.
const COLOURED_LIGHT_ABOVE: &str =
    "[[lights]]\nposition = [0.0, 10.0, 0.0]\ncolor = [1.0, 0.5, 0.25]\n";

/// Where the image differs when every checkpoint passes: what to look at
/// in the heatmap.
pub const IMAGE_HINT: &str = "in the shadows: a shadow ray must stop at the light (its t range), and start off the surface (the offset), or the surface shadows itself in speckles";

/// Chapter 4's checkpoints (level 1), in the order they run: the first
/// that fails is the one reported.
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn checkpoints() -> Vec<Case> {
    let floor: Shape = Plane::new(Vec3::ZERO, Vec3::Y).into();
    let ball: Shape = Sphere::new(Vec3::new(0.0, 1.0, 0.0), 1.0).into();
    let floor_point = surface(floor, Vec3::new(0.5, 4.0, 0.0), Vec3::new(0.5, 0.0, 2.0));
    let ball_top = surface(ball, Vec3::new(0.3, 5.0, 0.2), Vec3::new(0.0, 1.0, 0.0));
    // A slanted ray that reaches the floor point (0.2, 0, 0), next to where
    // the ball touches the floor, without touching the ball.
    let under_ball = (Vec3::new(5.0, 0.5, 0.0), Vec3::new(-4.8, -0.5, 0.0));
    let beside_ball = (Vec3::new(3.0, 5.0, 0.0), -Vec3::Y);
    let light_above = Vec3::new(0.0, 10.0, 0.0);
    vec![
        Case::from(OffsetQuestion {
            name: "offset-floor-up",
            section: WHERE_4,
            says: format!(
                "a shadow ray leaving the floor point {} upward, along (0.3, 1, 0.2), must start \
                 above the floor by at least the point's error bound dot(|n|, error), and by less \
                 than 0.01",
                vec(floor_point.point)
            ),
            surface: floor_point,
            dir: Vec3::new(0.3, 1.0, 0.2),
            at_most: 1e-2,
        }),
        Case::from(OffsetQuestion {
            name: "offset-floor-down",
            section: WHERE_4,
            says: "the same floor point, a ray leaving downward along (0.3, -1, 0) (through the \
                   surface, as a refracted ray does): it must start below the floor"
                .to_string(),
            surface: floor_point,
            dir: Vec3::new(0.3, -1.0, 0.0),
            at_most: 1e-2,
        }),
        Case::from(OffsetQuestion {
            name: "offset-ball-out",
            section: WHERE_4,
            says: format!(
                "a ray leaving the top of the unit ball at {} upward must start outside the ball",
                vec(ball_top.point)
            ),
            surface: ball_top,
            dir: Vec3::new(0.2, 1.0, 0.0),
            at_most: 1e-2,
        }),
        Case::from(OffsetQuestion {
            name: "offset-ball-in",
            section: WHERE_4,
            says: "the same point of the ball, a ray going into it: it must start inside"
                .to_string(),
            surface: ball_top,
            dir: Vec3::new(0.1, -1.0, 0.3),
            at_most: 1e-2,
        }),
        Case::from(ShadowQuestion {
            name: "shadow-under-ball",
            says: "the floor point (0.2, 0, 0), next to where the unit ball at (0, 1, 0) touches \
                   the floor, with a light straight above at (0, 10, 0): the ball is between them, \
                   expected in shadow",
            scene_lights: LIGHT_ABOVE,
            rays: vec![Ray::new(under_ball.0, under_ball.1)],
            light: light_above,
            expect: true,
        }),
        Case::from(ShadowQuestion {
            name: "shadow-beside-ball",
            says: "the floor point (3, 0, 0), light at (0, 10, 0): nothing between them, expected \
                   lit",
            scene_lights: LIGHT_ABOVE,
            rays: vec![Ray::new(beside_ball.0, beside_ball.1)],
            light: light_above,
            expect: false,
        }),
        Case::from(ShadowQuestion {
            name: "shadow-blocker-beyond-light",
            says: "the floor point (3, 0, 0), light at (2, 0.5, 0): the ball lies on the same line \
                   but beyond the light (t > 1 on a shadow ray from the point to the light), \
                   expected lit",
            scene_lights: LIGHT_ABOVE,
            rays: vec![Ray::new(beside_ball.0, beside_ball.1)],
            light: Vec3::new(2.0, 0.5, 0.0),
            expect: false,
        }),
        Case::from(ShadowQuestion {
            name: "shadow-no-acne",
            says: "64 rays from the light at (-4, 6, -3) to the unit ball at (0, 1, 0): every \
                   point they reach sees the light, so none may be in shadow \
                   (a shadow ray must not hit the surface it leaves: shadow acne)",
            scene_lights: LIGHT_ABOVE,
            rays: rays_from_light(Vec3::new(-4.0, 6.0, -3.0), Vec3::new(0.0, 1.0, 0.0), 1.0),
            light: Vec3::new(-4.0, 6.0, -3.0),
            expect: false,
        }),
        Case::new(
            "shadow-no-acne-plane",
            SHADOW_RAYS_4,
            "64 rays from the light at (-4, 6, -3) to a floor through (0.3, 0.1, 0.7), tilted to \
             the normal (0.01, 1, 0.02): every point they reach sees the light, so none may be in \
             shadow. A tilted plane's points are rounded in every coordinate, so a shadow ray \
             started exactly on it meets it again just past its origin (chapter 2's stable sphere \
             test hides this on balls; the offset is what keeps planes clean)",
            CaseKind::Shadow(ShadowCase {
                scene: TILTED_FLOOR.to_string(),
                object: 0,
                rays: rays_from_light(Vec3::new(-4.0, 6.0, -3.0), Vec3::new(0.3, 0.1, 0.7), 2.0),
                light: Vec3::new(-4.0, 6.0, -3.0),
                expect: false,
            }),
        ),
        Case::from(ShadeQuestion {
            name: "flat-lit",
            section: SHADOW_RAYS_4,
            says: "the floor point (3, 0, 0) \
                   (albedo 0.5, k_a = 0.2, k_d = 0.6, white ambient light), lit by the light at \
                   (0, 10, 0): expected 0.2 * 0.5 + 0.6 * 0.5 = 0.4 in each channel",
            shading: Shading::Flat,
            scene: floor_and_ball(LIGHT_ABOVE),
            ray: beside_ball,
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "flat-shadowed",
            section: SHADOW_RAYS_4,
            says: "the floor point (0.2, 0, 0) under the ball, light at (0, 10, 0): only ambient, \
                   expected 0.2 * 0.5 = 0.1",
            shading: Shading::Flat,
            scene: floor_and_ball(LIGHT_ABOVE),
            ray: under_ball,
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "flat-two-lights",
            section: SHADOW_RAYS_4,
            says: "the floor point (0.2, 0, 0), the light above hidden by the ball, a second light \
                   of intensity 0.5 low on the right at (10, 0.5, 0) reaching it: expected 0.1 + \
                   0.6 * 0.5 * 0.5 = 0.25",
            shading: Shading::Flat,
            scene: floor_and_ball(TWO_LIGHTS),
            ray: under_ball,
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "flat-light-below",
            section: SHADOW_RAYS_4,
            says: "the floor point (3, 0, 0) seen from above, light below the floor at (0, -5, 0): \
                   it lights the other side only, expected 0.1",
            shading: Shading::Flat,
            scene: floor_and_ball("[[lights]]\nposition = [0.0, -5.0, 0.0]\n"),
            ray: beside_ball,
            depth: 0,
        }),
        Case::new(
            "flat-dim-ambient",
            SHADOW_RAYS_4,
            "the floor point (3, 0, 0) lit from (0, 10, 0) as in flat-lit, under a dim, coloured \
             ambient light (0.5, 0.25, 1): the ambient term is albedo * k_a * ambient light, 0.1 * \
             (0.5, 0.25, 1), and the light's share 0.3 is not scaled by it: expected \
             (0.35, 0.325, 0.4)",
            CaseKind::Shade(ShadeCase {
                shading: Shading::Flat,
                scene: floor_and_ball_in(DIM_AMBIENT, LIGHT_ABOVE),
                ray: Ray::new(beside_ball.0, beside_ball.1),
                depth: 0,
                vertex_normals: None,
            }),
        ),
        Case::from(ShadowQuestion {
            name: "shadow-blocker-far-from-the-point",
            says: "the floor point (3, 0, 0), light at (-3, 2, 0): the line between them passes \
                   through the ball's centre (0, 1, 0), entering the ball 2.16 units from the \
                   point, well past the first unit: expected in shadow (t = 1 is the light only \
                   when the direction is light - point, not a unit vector)",
            scene_lights: LIGHT_ABOVE,
            rays: vec![Ray::new(beside_ball.0, beside_ball.1)],
            light: Vec3::new(-3.0, 2.0, 0.0),
            expect: true,
        }),
        Case::from(ShadowQuestion {
            name: "shadow-blocker-just-beyond-light",
            says: "the floor point (3, 0, 0), light at (1.5, 0.75, 0), 1.68 units away: the ball \
                   lies on the same line from t = 4/3 (at (1, 1, 0)) on, beyond the light at t = \
                   1 but within the light's distance: expected lit (t counts lengths of light - \
                   point, so t_max is 1, not the distance)",
            scene_lights: LIGHT_ABOVE,
            rays: vec![Ray::new(beside_ball.0, beside_ball.1)],
            light: Vec3::new(1.5, 0.75, 0.0),
            expect: false,
        }),
        Case::from(ShadeQuestion {
            name: "flat-lit-from-below",
            section: SHADOW_RAYS_4,
            says: "the floor point (3, 0, 0) seen from below, along +y from (3, -5, 0), light \
                   below the floor at (0, -5, 0): the side the eye sees faces the light (the \
                   normal turned toward the eye, not the plane's own (0, 1, 0)): expected 0.1 + \
                   0.3 = 0.4",
            shading: Shading::Flat,
            scene: floor_and_ball("[[lights]]\nposition = [0.0, -5.0, 0.0]\n"),
            ray: (Vec3::new(3.0, -5.0, 0.0), Vec3::Y),
            depth: 0,
        }),
        Case::from(ShadeQuestion {
            name: "flat-coloured-light",
            section: SHADOW_RAYS_4,
            says: "flat-lit with the light coloured (1, 0.5, 0.25): I_light is the light's colour \
                   times its intensity, so the light's share is 0.3 * (1, 0.5, 0.25): expected \
                   (0.4, 0.25, 0.175)",
            shading: Shading::Flat,
            scene: floor_and_ball(COLOURED_LIGHT_ABOVE),
            ray: beside_ball,
            depth: 0,
        }),
    ]
}

/// Chapter 4's hard cases (level 2).
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn robustness() -> Vec<Case> {
    let far_ball: Shape = Sphere::new(Vec3::new(1e4, 1.0, 1e4), 1.0).into();
    let side = surface(
        far_ball,
        Vec3::new(1e4 - 5.0, 1.0, 1e4 + 0.3),
        Vec3::new(1e4, 1.0, 1e4 + 0.3),
    );
    let small: Shape = Sphere::new(Vec3::new(0.1, 0.1, 0.1), 0.01).into();
    let small_point = surface(small, Vec3::new(0.1, 0.5, 0.1), Vec3::new(0.1, 0.1, 0.1));
    let ball: Shape = Sphere::new(Vec3::new(0.0, 1.0, 0.0), 1.0).into();
    let ball_side = surface(ball, Vec3::new(-5.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
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
        Case::from(OffsetQuestion {
            name: "offset-far-ball",
            section: OFFSET_4,
            says: "the side of a unit ball at (1e4, 1, 1e4): its point's error bound is about \
                   5e-3, so a fixed push of 1e-4 leaves the origin where rounding can put it inside"
                .to_string(),
            surface: side,
            dir: Vec3::new(-1.0, 0.5, 0.0),
            at_most: 0.0,
        }),
        Case::from(OffsetQuestion {
            name: "offset-grazing",
            section: OFFSET_4,
            says: "a ray leaving the side of the unit ball at (0, 1, 0) almost along the surface \
                   (dot(dir, n) = 1e-3): pushing along dir barely moves it off the surface"
                .to_string(),
            surface: ball_side,
            dir: Vec3::new(-1e-3, 1.0, 0.0),
            at_most: 0.0,
        }),
        Case::from(OffsetQuestion {
            name: "offset-infinite-point",
            section: OFFSET_4,
            says: "a point at x = inf (a hit on a plane far beyond f32's range): one float \
                   beyond inf is f32::MAX, a finite origin nowhere near the surface: expected NaN, \
                   an origin no ray starts from"
                .to_string(),
            surface: crate::SurfacePoint {
                point: Vec3::new(f32::INFINITY, 0.0, 0.0),
                normal: Vec3::Y,
                error: Vec3::ZERO,
            },
            dir: Vec3::Y,
            at_most: 0.0,
        }),
        Case::from(OffsetQuestion {
            name: "offset-small-ball",
            section: OFFSET_4,
            says: "a ball of radius 0.01 at (0.1, 0.1, 0.1): its error bound is 5e-8, and a push \
                   of more than 16 error bounds detaches shadows from small objects"
                .to_string(),
            surface: small_point,
            dir: Vec3::new(0.0, 1.0, 0.0),
            at_most: 0.0,
        }),
        Case::new(
            "shadow-no-acne-far",
            SHADOW_RAYS_4,
            "64 rays from the light at (9996, 6, 9997) to a unit ball at (1e4, 1, 1e4): every \
             point they reach sees the light, none may be in shadow",
            CaseKind::Shadow(ShadowCase {
                scene: far_scene.to_string(),
                object: 0,
                rays: rays_from_light(
                    Vec3::new(9996.0, 6.0, 9997.0),
                    Vec3::new(1e4, 1.0, 1e4),
                    1.0,
                ),
                light: Vec3::new(9996.0, 6.0, 9997.0),
                expect: false,
            }),
        ),
    ])
}
