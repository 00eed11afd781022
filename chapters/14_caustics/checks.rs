//! Chapter 14's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 14`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const SPLAT_14: &str = "What a pixel sees of a point";
const LIGHT_PATHS_14: &str = "Light paths";
const ONCE_14: &str = "Every path counted once";
const DISPERSION_14: &str = "Dispersion";
const LENS_14: &str = "The lens";
const HARD_14: &str = "The hard cases";

/// Where the image differs when every checkpoint passes: what to look at
/// in the heatmap.
pub const IMAGE_HINT: &str = "on the sunlit floor, the ball's caustic and the prism's spectrum: a light path's power, its stop at the first diffuse point, the splat weight's cosines, the wavelength's colour";

/// Dense flint glass, Schott's SF10: Cauchy's coefficients of the
/// lesson's table.
const SF10: Cauchy = Cauchy {
    a: 1.728,
    b: 0.01342,
};

fn formula(name: &'static str, section: &'static str, says: &str, formula: LightFormula) -> Case {
    Case::new(
        name,
        section,
        says,
        CaseKind::LightFormula(LightFormulaCase { formula }),
    )
}

fn splat(
    name: &'static str,
    says: &str,
    (cos_surface, cos_camera, distance, pixel_area): (f32, f32, f32, f32),
) -> Case {
    formula(
        name,
        SPLAT_14,
        says,
        LightFormula::SplatWeight {
            cos_surface,
            cos_camera,
            distance,
            pixel_area,
        },
    )
}

/// A matte sphere of radius 1 and albedo 0.5 about the origin with `inside`
/// (TOML) in it and `wall` added to its material (`", emission = ..."`),
/// seen from `(0, 0, -0.5)` looking at `(0, 0, looking)`.
pub fn closed_sphere(inside: &str, looking: f32, wall: &str) -> String {
    format!(
        r#"
background = [0.0, 0.0, 0.0]
[camera]
position = [0.0, 0.0, -0.5]
look_at = [0.0, 0.0, {looking}]
fov_degrees = 60.0
[render]
width = 8
height = 8
samples = 4
light_paths = 256
max_depth = 64
[[objects]]
name = "wall"
sphere = {{ center = [0.0, 0.0, 0.0], radius = 1.0 }}
material = {{ color = [0.5, 0.5, 0.5]{wall} }}
{inside}
"#
    )
}

/// A glass ball of radius 0.25 about the origin.
pub const GLASS_BALL: &str = r#"
[[objects]]
name = "glass ball"
sphere = { center = [0.0, 0.0, 0.0], radius = 0.25 }
material = { color = [1.0, 1.0, 1.0], transparency = 1.0, ior = 1.5, fresnel = "exact" }
"#;

fn converges(
    name: &'static str,
    section: &'static str,
    function: &'static str,
    says: &str,
    scene: String,
    expected: f64,
) -> Case {
    Case::new(
        name,
        section,
        says,
        CaseKind::LightConverges(LightConvergesCase {
            function,
            scene,
            without: &[],
            repetitions: 24,
            expected: [expected; 3],
            first_seed: 1,
        }),
    )
}

/// Chapter 14's checkpoints (level 1), in the order they run: the first
/// that fails is the one reported.
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn checkpoints() -> Vec<Case> {
    vec![
        splat(
            "splat-face-on",
            "a point 2 ahead of the camera, facing it, with pixels of 1e-4 at distance 1: a \
             unit of its area covers 1 / 2^2 = 0.25 sr, a pixel 1e-4 sr: 2500",
            (1.0, 1.0, 2.0, 1e-4),
        ),
        splat(
            "splat-turned-surface",
            "the same point turned 60 degrees from the camera (cos = 0.5): its area looks half \
             as large, 1250",
            (0.5, 1.0, 2.0, 1e-4),
        ),
        splat(
            "splat-off-axis",
            "the same point, face on, seen 36.87 degrees off the view (cos = 0.8): the pixel's \
             square covers 1e-4 x 0.8^3 sr there, so 1 / (4 x 1e-4 x 0.512) = 4882.8125",
            (1.0, 0.8, 2.0, 1e-4),
        ),
        formula(
            "cauchy-bk7-d-line",
            DISPERSION_14,
            "BK7 (a = 1.5046, b = 0.0042) at the helium d line, 587.56 nm: 1.5046 + 0.0042 / \
             0.58756^2 = 1.516766 (Schott's catalogue says 1.5168)",
            LightFormula::CauchyIor {
                cauchy: Cauchy {
                    a: 1.5046,
                    b: 0.0042,
                },
                nanometres: 587.56,
            },
        ),
        formula(
            "cauchy-sf10-blue",
            DISPERSION_14,
            "SF10 (a = 1.728, b = 0.01342) at 450 nm: 1.728 + 0.01342 / 0.45^2 = 1.794272",
            LightFormula::CauchyIor {
                cauchy: SF10,
                nanometres: 450.0,
            },
        ),
        Case::new(
            "dispersion-draws-a-wavelength",
            DISPERSION_14,
            "20,000 paths each meet a dispersive glass (a = 1.6, b = 0.05) twice: at the first \
             surface each draws a wavelength uniform over 380..780 nm (a chi-square test on 20 \
             bins), keeps it (tracer.set_wavelength) and returns its index a + b / lambda^2 and \
             its colour rgb_weight(lambda); at the second, the same index and no colour, (1, 1, 1)",
            CaseKind::Dispersion(DispersionCase {
                cauchy: Cauchy { a: 1.6, b: 0.05 },
                paths: 20_000,
                seed: 0,
            }),
        ),
        Case::new(
            "prism-minimum-deviation-red",
            DISPERSION_14,
            "a 60-degree prism of SF10 at 650 nm (n = 1.76); turned through every angle of \
             incidence with your refract, the ray deviates least by 2 asin(n sin 30) - 60 = \
             63.3 degrees",
            CaseKind::Prism(PrismCase {
                cauchy: SF10,
                apex_degrees: 60.0,
                nanometres: 650.0,
            }),
        ),
        Case::new(
            "prism-minimum-deviation-blue",
            DISPERSION_14,
            "the same prism at 450 nm (n = 1.79): 2 asin(n sin 30) - 60 = 67.6 degrees, 4 more \
             than red: blue bends more",
            CaseKind::Prism(PrismCase {
                cauchy: SF10,
                apex_degrees: 60.0,
                nanometres: 450.0,
            }),
        ),
        converges(
            "point-light-in-glass",
            LIGHT_PATHS_14,
            "trace_light_path",
            "pbrt-v4's analytic scene (a point light of intensity pi at the centre of a sphere \
             of albedo 0.5: radiance 1) with the light inside a glass ball of radius 0.25: the \
             ball loses nothing, the wall's radiance is still 1, and only light paths find \
             the light",
            closed_sphere(
                &format!(
                    "[[lights]]\nposition = [0.0, 0.0, 0.0]\nintensity = 3.14159265\n{GLASS_BALL}"
                ),
                -1.0,
                "",
            ),
            1.0,
        ),
        converges(
            "point-light-in-the-open",
            ONCE_14,
            "trace_light_path",
            "pbrt-v4's analytic scene itself, the light in the open (a glass ball outside \
             the sphere, where no light reaches, makes the stage trace light paths): radiance \
             1, all of it found by camera paths' light samples; a light path whose first \
             point is diffuse must end there, or the wall gets its light twice",
            closed_sphere(
                "[[lights]]\nposition = [0.0, 0.0, 0.0]\nintensity = 3.14159265\n\
                 [[objects]]\nname = \"glass outside\"\n\
                 sphere = { center = [3.0, 0.0, 0.0], radius = 0.5 }\n\
                 material = { transparency = 1.0, ior = 1.5, fresnel = \"exact\" }\n",
                -1.0,
                "",
            ),
            1.0,
        ),
        converges(
            "lamp-in-glass",
            ONCE_14,
            "shade_path",
            "a white lamp of radius 0.1 and radiance 100 inside the glass ball: it gives off \
             pi per unit area of the wall, so the wall's radiance is 0.5 (pi + pi L) / pi: L = \
             1, counted once by camera paths and light paths together (a camera path that \
             finds the lamp through the glass from its first, diffuse point must not count it: \
             Arrival::Caustic)",
            closed_sphere(
                &format!(
                    "[[objects]]\nname = \"lamp\"\nsphere = {{ center = [0.0, 0.0, 0.0], radius = 0.1 }}\n\
                     material = {{ color = [1.0, 1.0, 1.0], emission = [100.0, 100.0, 100.0] }}\n{GLASS_BALL}"
                ),
                -1.0,
                "",
            ),
            1.0,
        ),
        converges(
            "spectral-white-furnace",
            DISPERSION_14,
            "dispersive_ior",
            "a ball of glass that disperses (Cauchy a = 1.6, b = 0.05) in the white furnace (a \
             sphere of albedo 0.5 that emits 1: radiance 2), seen through the ball: each \
             wavelength bends its own way, and the wall is still white, 2 in every channel",
            closed_sphere(
                r#"
[[objects]]
name = "prism glass"
sphere = { center = [0.0, 0.0, 0.0], radius = 0.25 }
material = { color = [1.0, 1.0, 1.0], transparency = 1.0, cauchy = { a = 1.6, b = 0.05 }, fresnel = "exact" }
"#,
                1.0,
                ", emission = [1.0, 1.0, 1.0], two_sided = true",
            ),
            2.0,
        ),
        Case::new(
            "ball-lens",
            LENS_14,
            "a parallel beam of radius 0.3 through a glass ball of radius 1 and index 1.5 onto a \
             matte screen 1.2 past its centre: near the axis the light is about 23.5 times as \
             bright as the beam's, as Snell's law and Fresnel's transmission at both surfaces \
             say, ring by ring of the beam (the screen without the ball is the measure)",
            CaseKind::Lens(LensCase {
                ior: 1.5,
                beam: 0.3,
                screen: 1.2,
                disk: 0.02,
                repetitions: 8,
                first_seed: 1,
            }),
        ),
        converges(
            "box-lit-inside-seen-from-outside",
            SPLAT_14,
            "connect_to_camera",
            "a closed box lit inside by a point light in a glass ball, seen from outside: the \
             outside of the box is black (exactly 0). The near wall's lit inside faces away \
             from the camera (the camera must see the lit side), and the far walls' lit \
             insides face it with the near wall between (the shadow ray to the camera must be \
             cast)",
            BOX_LIT_INSIDE.to_string(),
            0.0,
        ),
        converges(
            "glossy-floor-under-a-beam-through-glass",
            SPLAT_14,
            "connect_to_camera",
            "a beam of irradiance pi through a ball of index 1 (no bending, no reflection) onto \
             a glossy floor of colour 0.5 and Phong exponent 2 (roughness 1 / sqrt 2), 60 \
             degrees from its normal, seen from the mirror direction: the lobe's peak, \
             0.5 (2 + 2) / (2 pi), times the irradiance pi cos 60: radiance 0.5 (Lambert's \
             0.5 / pi would give 0.25). The light sent to the camera is the lobe's f toward it",
            GLOSSY_FLOOR_UNDER_A_BEAM.to_string(),
            0.5,
        ),
        converges(
            "beam-through-absorbing-glass",
            LIGHT_PATHS_14,
            "trace_light_path",
            "a beam of irradiance pi down through a ball of radius 0.25 that absorbs 2 per unit \
             (index 1: no bending, no reflection) onto a matte floor of albedo 0.5, seen near \
             the beam's axis (max_depth = 3: no light bounced back): the light crosses 0.5 \
             units of the ball, so the floor's radiance is 0.5 exp(-2 x 0.5) = 0.18394. A light \
             path's power is dimmed by the medium it crosses",
            BEAM_THROUGH_ABSORBING_GLASS.to_string(),
            0.5 * (-1.0f64).exp(),
        ),
    ]
}

/// A closed box of six matte quads (each a little wider than the box, so
/// that no ray slips out along an edge) with a point light inside a glass
/// ball at its centre, and the camera outside it.
const BOX_LIT_INSIDE: &str = r#"
background = [0.0, 0.0, 0.0]
[camera]
position = [0.3, 0.4, -3.0]
look_at = [0.0, 0.0, 0.0]
fov_degrees = 60.0
[render]
width = 8
height = 8
samples = 4
light_paths = 64
max_depth = 16
[[lights]]
position = [0.0, 0.0, 0.0]
intensity = 10.0
[[objects]]
name = "glass ball"
sphere = { center = [0.0, 0.0, 0.0], radius = 0.25 }
material = { color = [1.0, 1.0, 1.0], transparency = 1.0, ior = 1.5, fresnel = "exact" }
[[objects]]
name = "near wall"
quad = { corner = [-1.1, -1.1, -1.0], u = [2.2, 0.0, 0.0], v = [0.0, 2.2, 0.0] }
material = { color = [0.5, 0.5, 0.5] }
[[objects]]
name = "far wall"
quad = { corner = [-1.1, -1.1, 1.0], u = [2.2, 0.0, 0.0], v = [0.0, 2.2, 0.0] }
material = { color = [0.5, 0.5, 0.5] }
[[objects]]
name = "left wall"
quad = { corner = [-1.0, -1.1, -1.1], u = [0.0, 2.2, 0.0], v = [0.0, 0.0, 2.2] }
material = { color = [0.5, 0.5, 0.5] }
[[objects]]
name = "right wall"
quad = { corner = [1.0, -1.1, -1.1], u = [0.0, 2.2, 0.0], v = [0.0, 0.0, 2.2] }
material = { color = [0.5, 0.5, 0.5] }
[[objects]]
name = "floor"
quad = { corner = [-1.1, -1.0, -1.1], u = [2.2, 0.0, 0.0], v = [0.0, 0.0, 2.2] }
material = { color = [0.5, 0.5, 0.5] }
[[objects]]
name = "ceiling"
quad = { corner = [-1.1, 1.0, -1.1], u = [2.2, 0.0, 0.0], v = [0.0, 0.0, 2.2] }
material = { color = [0.5, 0.5, 0.5] }
"#;

/// A beam 60 degrees from the vertical through a ball of index 1 onto a
/// glossy floor, the camera on the mirror direction of the beam, 0.5 from
/// the lit spot, with a 2-degree view: every pixel sees the lobe's peak
/// within 0.1%.
const GLOSSY_FLOOR_UNDER_A_BEAM: &str = r#"
background = [0.0, 0.0, 0.0]
[camera]
position = [0.4330127, 0.25, 0.0]
look_at = [0.0, 0.0, 0.0]
fov_degrees = 2.0
[render]
width = 8
height = 8
samples = 4
light_paths = 256
max_depth = 3
[[beams]]
position = [-1.7320508, 1.0, 0.0]
direction = [0.8660254, -0.5, 0.0]
radius = 0.05
intensity = 3.14159265
[[objects]]
name = "glossy floor"
quad = { corner = [-2.0, 0.0, -2.0], u = [0.0, 0.0, 4.0], v = [4.0, 0.0, 0.0] }
material = { color = [0.5, 0.5, 0.5], reflectivity = 1.0, roughness = 0.70710678 }
[[objects]]
name = "clear ball"
sphere = { center = [-0.8660254, 0.5, 0.0], radius = 0.2 }
material = { color = [1.0, 1.0, 1.0], transparency = 1.0, ior = 1.0, fresnel = "exact" }
"#;

/// A beam of radius 0.05 straight down through an absorbing ball of index
/// 1 onto a floor, the camera looking steeply at the middle of the lit
/// spot through a 2-degree view that stays within 0.02 of the axis.
const BEAM_THROUGH_ABSORBING_GLASS: &str = r#"
background = [0.0, 0.0, 0.0]
[camera]
position = [0.0, 0.2, -0.4]
look_at = [0.0, 0.0, 0.0]
fov_degrees = 2.0
[render]
width = 8
height = 8
samples = 4
light_paths = 256
max_depth = 3
[[beams]]
position = [0.0, 1.0, 0.0]
direction = [0.0, -1.0, 0.0]
radius = 0.05
intensity = 3.14159265
[[objects]]
name = "floor"
quad = { corner = [-2.0, 0.0, -2.0], u = [0.0, 0.0, 4.0], v = [4.0, 0.0, 0.0] }
material = { color = [0.5, 0.5, 0.5] }
[[objects]]
name = "absorbing ball"
sphere = { center = [0.0, 0.5, 0.0], radius = 0.25 }
material = { color = [1.0, 1.0, 1.0], transparency = 1.0, ior = 1.0, fresnel = "exact", absorption = [2.0, 2.0, 2.0] }
"#;

/// A glass ball above a floor, lit from below the floor by a point light:
/// the light's paths reach the floor's underside only.
const LIGHT_UNDER_THE_FLOOR: &str = r#"
background = [0.0, 0.0, 0.0]
[camera]
position = [0.0, 2.0, -2.0]
look_at = [0.0, 0.0, 0.0]
[render]
width = 8
height = 8
samples = 4
light_paths = 64
max_depth = 16
[[lights]]
position = [0.0, -1.0, 0.0]
intensity = 10.0
[[objects]]
name = "floor"
quad = { corner = [-4.0, 0.0, -4.0], u = [8.0, 0.0, 0.0], v = [0.0, 0.0, 8.0] }
material = { color = [0.8, 0.8, 0.8] }
[[objects]]
name = "glass ball under the floor"
sphere = { center = [0.0, -0.5, 0.0], radius = 0.3 }
material = { color = [1.0, 1.0, 1.0], transparency = 1.0, ior = 1.5, fresnel = "exact" }
"#;

/// Chapter 14's hard cases (level 2).
pub fn robustness() -> Vec<Case> {
    robust(vec![
        splat(
            "splat-edge-on-camera",
            "a point at 90 degrees from the view (cos_camera = 0) is on no pixel: weight 0, \
             not the infinity of 1 / 0",
            (1.0, 0.0, 2.0, 1e-4),
        ),
        splat(
            "splat-behind-camera",
            "a point behind the camera (cos_camera = -0.5) is on no pixel: 0, not a negative \
             weight",
            (1.0, -0.5, 2.0, 1e-4),
        ),
        splat(
            "splat-at-the-pinhole",
            "a point at the camera itself (distance 0): 0, not the infinity of 1 / 0",
            (1.0, 1.0, 0.0, 1e-4),
        ),
        splat(
            "splat-back-face",
            "the camera behind the lit side (cos_surface = -0.5) sees none of its light: 0",
            (-0.5, 1.0, 2.0, 1e-4),
        ),
        splat(
            "splat-nan",
            "a NaN cosine (a degenerate point) adds nothing rather than a NaN: 0",
            (f32::NAN, 1.0, 2.0, 1e-4),
        ),
        Case::new(
            "lit-under-the-floor",
            HARD_14,
            "a point light under a floor, with a glass ball between: its light paths reach the \
             floor's underside only, and the camera above sees the top: exactly 0 (a point \
             joined to the camera from its unlit side is a bright ghost on the other)",
            CaseKind::LightConverges(LightConvergesCase {
                function: "connect_to_camera",
                scene: LIGHT_UNDER_THE_FLOOR.to_string(),
                without: &[],
                repetitions: 4,
                expected: [0.0; 3],
                first_seed: 1,
            }),
        ),
    ])
}
