//! Cases on chapter 14's light paths and dispersion: the splat weight and
//! Cauchy's index by hand, the prism's minimum deviation against Snell's
//! law in closed form, closed scenes whose every pixel converges to a
//! known value, and a ball lens whose caustic is as bright as geometry
//! says.
//!
//! Light paths add to every pixel at once, so a scene's estimate is not a
//! mean of independent samples of one pixel: each repetition renders the
//! whole image with a seed of its own, and the repetitions' means are the
//! independent samples whose spread the z-test reads.

use super::*;
use crate::scene::{Cauchy, SwitchedOff};

/// A function of chapter 14 of plain numbers: its inputs and the answer.
#[derive(Debug, Clone, PartialEq)]
pub enum LightFormula {
    /// `splat_weight(cos_surface, cos_camera, distance, pixel_area)`.
    SplatWeight {
        cos_surface: f32,
        cos_camera: f32,
        distance: f32,
        pixel_area: f32,
    },
    /// `cauchy_ior(cauchy, nanometres)`.
    CauchyIor { cauchy: Cauchy, nanometres: f32 },
}

/// One call of a [`LightFormula`].
#[derive(Debug, Clone)]
pub struct LightFormulaCase {
    pub formula: LightFormula,
}

impl LightFormulaCase {
    pub fn function(&self) -> &'static str {
        match self.formula {
            LightFormula::SplatWeight { .. } => "splat_weight",
            LightFormula::CauchyIor { .. } => "cauchy_ior",
        }
    }

    pub fn inputs(&self) -> String {
        match &self.formula {
            LightFormula::SplatWeight {
                cos_surface,
                cos_camera,
                distance,
                pixel_area,
            } => format!(
                "splat_weight(cos_surface = {}, cos_camera = {}, distance = {}, pixel_area = {})",
                num(*cos_surface),
                num(*cos_camera),
                num(*distance),
                num(*pixel_area)
            ),
            LightFormula::CauchyIor { cauchy, nanometres } => format!(
                "cauchy_ior(Cauchy {{ a: {}, b: {} }}, {} nm)",
                num(cauchy.a),
                num(cauchy.b),
                num(*nanometres)
            ),
        }
    }

    /// The exact answer, from `check::exact`.
    fn expected(&self) -> f64 {
        match &self.formula {
            LightFormula::SplatWeight {
                cos_surface,
                cos_camera,
                distance,
                pixel_area,
            } => exact::splat_weight(
                f64::from(*cos_surface),
                f64::from(*cos_camera),
                f64::from(*distance),
                f64::from(*pixel_area),
            ),
            LightFormula::CauchyIor { cauchy, nanometres } => exact::cauchy(
                f64::from(cauchy.a),
                f64::from(cauchy.b),
                f64::from(*nanometres),
            ),
        }
    }

    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let got = match &self.formula {
            LightFormula::SplatWeight {
                cos_surface,
                cos_camera,
                distance,
                pixel_area,
            } => C::splat_weight(*cos_surface, *cos_camera, *distance, *pixel_area),
            LightFormula::CauchyIor { cauchy, nanometres } => C::cauchy_ior(cauchy, *nanometres),
        };
        let expected = self.expected();
        verdict(
            got.is_finite() && close(f64::from(got), expected, CHECKPOINT_TOLERANCE),
            num64(expected),
            num(got),
        )
    }
}

/// The prism's smallest deviation at one wavelength, found by turning a
/// ray through a prism of apex angle `apex_degrees` with the chapters'
/// `refract` and `cauchy_ior`, against Snell's law in closed form.
#[derive(Debug, Clone)]
pub struct PrismCase {
    pub cauchy: Cauchy,
    pub apex_degrees: f32,
    pub nanometres: f32,
}

/// How far the deviation found may be from the closed form: a thousandth
/// of a degree, far above `f32`'s rounding of the two refractions (a few
/// `1e-7` radians, `1e-5` degrees) and far below what a wrong index or a
/// wrong refraction moves it by (a tenth of a degree and more).
pub const PRISM_TOLERANCE_DEGREES: f64 = 1e-3;

impl PrismCase {
    pub fn function(&self) -> &'static str {
        "cauchy_ior"
    }

    pub fn inputs(&self) -> String {
        format!(
            "a prism of apex {} degrees, Cauchy a = {}, b = {}, at {} nm: the smallest \
             deviation over every angle of incidence, with refract and cauchy_ior",
            num(self.apex_degrees),
            num(self.cauchy.a),
            num(self.cauchy.b),
            num(self.nanometres)
        )
    }

    /// The ray's deviation in degrees for the incidence `incidence` (radians)
    /// on the first face, `None` when it cannot leave by the second (total
    /// internal reflection). The prism's apex points up (+y), its faces'
    /// outward normals turned by `apex / 2` left and right of -x and +x.
    fn deviation<C: Chapters>(&self, index: f32, incidence: f32) -> Option<f32> {
        let half = self.apex_degrees.to_radians() / 2.0;
        let first = Vec3::new(-half.cos(), half.sin(), 0.0);
        let second = Vec3::new(half.cos(), half.sin(), 0.0);
        // The incoming ray meets the first face at `incidence` from its
        // inward normal, turned toward the apex (counter-clockwise), so
        // that it crosses to the second face and bends toward the base.
        let inward = -first;
        let (sin, cos) = incidence.sin_cos();
        let along = Vec3::new(-inward.y, inward.x, 0.0);
        let incoming = inward * cos + along * sin;
        let inside = C::refract(incoming, first, 1.0 / index)?;
        let outgoing = C::refract(inside, second, index)?;
        let turned = incoming.dot(outgoing).clamp(-1.0, 1.0).acos();
        Some(turned.to_degrees())
    }

    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let index = C::cauchy_ior(&self.cauchy, self.nanometres);
        let expected = exact::prism_minimum_deviation(
            exact::cauchy(
                f64::from(self.cauchy.a),
                f64::from(self.cauchy.b),
                f64::from(self.nanometres),
            ),
            f64::from(self.apex_degrees).to_radians(),
        )
        .to_degrees();
        // Every tenth of a degree of incidence, then a golden-section
        // search about the smallest: the deviation is flat at its minimum,
        // so its value is found far more precisely than the angle.
        let angles = (1..900).map(|tenth| (tenth as f32 / 10.0).to_radians());
        let Some((best, _)) = angles
            .filter_map(|angle| Some((angle, self.deviation::<C>(index, angle)?)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
        else {
            return verdict(
                false,
                format!("a smallest deviation of {expected:.4} degrees"),
                "no ray got through the prism (refract gave None at every angle)".into(),
            );
        };
        let step = 0.1f32.to_radians();
        let (mut low, mut high) = (best - step, best + step);
        let ratio = (5f32.sqrt() - 1.0) / 2.0;
        let value = |angle: f32| self.deviation::<C>(index, angle).unwrap_or(f32::INFINITY);
        for _ in 0..40 {
            let (left, right) = (high - ratio * (high - low), low + ratio * (high - low));
            if value(left) < value(right) {
                high = right;
            } else {
                low = left;
            }
        }
        let found = f64::from(value((low + high) / 2.0));
        verdict(
            (found - expected).abs() <= PRISM_TOLERANCE_DEGREES,
            format!("{expected:.4} degrees (2 asin(n sin(A / 2)) - A)"),
            format!("{found:.4} degrees"),
        )
    }
}

/// A closed scene rendered by chapter 14's stage with `without` left out,
/// whose every pixel converges to `expected` in each channel:
/// `repetitions` whole images, each with a seed of its own, each reduced
/// to the mean of its pixels; the mean of those within [`FALSE_ALARM`] of
/// `expected` by a z-test on their spread, plus `1e-3` of the value for
/// the paths `max_depth` cuts off.
#[derive(Debug, Clone)]
pub struct LightConvergesCase {
    pub function: &'static str,
    pub scene: String,
    pub without: &'static [&'static str],
    pub repetitions: u32,
    pub expected: [f64; 3],
}

impl LightConvergesCase {
    pub fn function(&self) -> &'static str {
        self.function
    }

    pub fn inputs(&self) -> String {
        format!(
            "{} renders of a closed scene, each with its own seed{}",
            self.repetitions,
            super::paths::without_text(self.without)
        )
    }

    /// Per channel, the mean of the repetitions' image means and its
    /// standard error, with the chapters `C`.
    pub fn estimate<C: Chapters>(&self) -> Result<(DVec3, DVec3), String> {
        let mut scene = parse(&self.scene)?;
        scene.render.without = SwitchedOff::parse(self.without.iter().copied())?;
        let means: Vec<DVec3> = (0..self.repetitions)
            .map(|repetition| {
                scene.render.seed = u64::from(repetition) + 1;
                image_mean::<C>(&scene, 14).map(|mean| mean.as_dvec3())
            })
            .collect::<Result<_, _>>()?;
        let channel = |pick: fn(DVec3) -> f64| {
            mean_and_error(&means.iter().map(|mean| pick(*mean)).collect::<Vec<_>>())
        };
        let (x, y, z) = (channel(|v| v.x), channel(|v| v.y), channel(|v| v.z));
        Ok((DVec3::new(x.0, y.0, z.0), DVec3::new(x.1, y.1, z.1)))
    }

    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        // The chapter's own formulas first: in a workspace where nothing is
        // written yet, their `todo!()` says chapter 14 is not started.
        let _ = (
            C::splat_weight(1.0, 1.0, 1.0, 1.0),
            C::cauchy_ior(&Cauchy { a: 1.5, b: 0.0 }, 550.0),
        );
        let (mean, error) = match self.estimate::<C>() {
            Ok(found) => found,
            Err(why) => return Outcome::Error(why),
        };
        let expected = DVec3::from_array(self.expected);
        let allowed = z_threshold() * error + 1e-3 * expected.abs();
        verdict(
            mean.is_finite() && (mean - expected).abs().cmple(allowed).all(),
            format!(
                "({}, {}, {}) (within {:.2e})",
                num64(expected.x),
                num64(expected.y),
                num64(expected.z),
                allowed.max_element()
            ),
            format!(
                "a mean of ({}, {}, {}) (standard error {:.2e})",
                num64(mean.x),
                num64(mean.y),
                num64(mean.z),
                error.max_element()
            ),
        )
    }
}

/// The mean of every pixel of `scene` at `chapter`'s stage, camera paths
/// and light paths together, rendered with the chapters `C` on this thread
/// (the light paths on rayon's).
fn image_mean<C: Chapters>(scene: &Scene, chapter: u8) -> Result<Vec3, String> {
    let stage =
        Stage::<C>::with_chapters(scene, chapter, scene.render).map_err(|e| e.to_string())?;
    let pixels = linear_image(&stage);
    Ok(pixels.iter().copied().sum::<Vec3>() / pixels.len() as f32)
}

/// Every pixel of `stage`'s image in linear light, row by row, as `raylab
/// render` computes it before encoding: the camera's estimate plus what
/// the light paths brought.
pub fn linear_image<C: Chapters>(stage: &Stage<C>) -> Vec<Vec3> {
    let (width, height) = (stage.settings.width, stage.settings.height);
    let light = stage.light_image();
    let mut tracer = stage.tracer(None);
    let mut pixels = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let index = pixels.len();
            let camera = tracer.pixel(x, y);
            pixels.push(camera + light.map_or(Vec3::ZERO, |light| light.pixels[index]));
        }
    }
    pixels
}

/// A glass ball of radius 1 at the origin lit by a parallel beam along +z,
/// and a matte screen square to the axis behind it, seen from the side
/// (the ball hides the screen's middle from any camera within 56 degrees
/// of the axis). The ball's caustic on the screen is brighter than the beam
/// by what [`exact::ball_lens_irradiance`] says.
#[derive(Debug, Clone)]
pub struct LensCase {
    /// The ball's index of refraction.
    pub ior: f32,
    /// The beam's radius: a third of the ball's keeps the marginal rays,
    /// which the ball focuses far short of the paraxial focus, off the
    /// screen's middle.
    pub beam: f32,
    /// Where the screen is along the axis, past the ball's centre.
    pub screen: f32,
    /// The disk about the axis whose pixels are compared.
    pub disk: f32,
    pub repetitions: u32,
}

impl LensCase {
    pub fn function(&self) -> &'static str {
        "connect_to_camera"
    }

    pub fn inputs(&self) -> String {
        format!(
            "a parallel beam of radius {} through a glass ball of radius 1 and index {}, onto \
             a matte screen {} past its centre; the pixels within {} of the axis, with the \
             ball and without",
            num(self.beam),
            num(self.ior),
            num(self.screen),
            num(self.disk)
        )
    }

    /// The scene, with the ball or without it.
    pub fn scene(&self, ball: bool) -> String {
        let ball = if ball {
            format!(
                "[[objects]]\nname = \"lens\"\nsphere = {{ center = [0.0, 0.0, 0.0], radius = 1.0 }}\n\
                 material = {{ color = [1.0, 1.0, 1.0], transparency = 1.0, ior = {}, fresnel = \"exact\" }}\n",
                self.ior
            )
        } else {
            String::new()
        };
        let screen = self.screen;
        format!(
            r#"
background = [0.0, 0.0, 0.0]
ambient_light = [0.0, 0.0, 0.0]
[camera]
position = [3.0, 0.0, {camera_z}]
look_at = [0.0, 0.0, {screen}]
fov_degrees = 3.0
[render]
width = 48
height = 48
samples = 1
light_paths = 64
max_depth = 3
[[beams]]
position = [0.0, 0.0, -3.0]
direction = [0.0, 0.0, 1.0]
radius = {beam}
intensity = 1.0
{ball}
[[objects]]
name = "screen"
quad = {{ corner = [-0.5, -0.5, {screen}], u = [0.0, 1.0, 0.0], v = [1.0, 0.0, 0.0] }}
material = {{ color = [0.8, 0.8, 0.8] }}
"#,
            camera_z = screen - 1.4,
            beam = self.beam,
        )
    }

    /// The image points of the pixels whose centres see the screen within
    /// `disk` of the axis, and the distance from the axis of each.
    fn compared_pixels(&self, stage: &Stage<Reference>) -> Vec<(usize, f64)> {
        let camera = stage.camera();
        let (width, height) = (stage.settings.width, stage.settings.height);
        let mut pixels = Vec::new();
        for y in 0..height {
            for x in 0..width {
                let ray = camera.ray_through(x as f32 + 0.5, y as f32 + 0.5);
                let t = (self.screen - ray.origin.z) / ray.dir.z;
                let point = wide(ray.at(t));
                let rho = (point.x * point.x + point.y * point.y).sqrt();
                if rho < f64::from(self.disk) {
                    pixels.push(((y * width + x) as usize, rho));
                }
            }
        }
        pixels
    }

    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        // The chapter's own formula first, as for the closed scenes.
        let _ = C::splat_weight(1.0, 1.0, 1.0, 1.0);
        let (with, without) = match (parse(&self.scene(true)), parse(&self.scene(false))) {
            (Ok(with), Ok(without)) => (with, without),
            (Err(why), _) | (_, Err(why)) => return Outcome::Error(why),
        };
        // raylab's own stage: only its camera's geometry is read.
        let geometry = match crate::answer_key::raylab_own(|| {
            Stage::<Reference>::with_chapters(&without, 14, without.render)
                .map(|stage| self.compared_pixels(&stage))
        }) {
            Ok(pixels) => pixels,
            Err(error) => return Outcome::Error(error.to_string()),
        };
        let expected = geometry
            .iter()
            .map(|(_, rho)| {
                exact::ball_lens_irradiance(
                    f64::from(self.ior),
                    1.0,
                    f64::from(self.beam),
                    f64::from(self.screen),
                    *rho,
                )
            })
            .sum::<f64>()
            / geometry.len().max(1) as f64;
        let mean_over = |pixels: &[Vec3]| {
            geometry
                .iter()
                .map(|(index, _)| f64::from(pixels[*index].x))
                .sum::<f64>()
                / geometry.len().max(1) as f64
        };
        let mut ratios = Vec::new();
        for repetition in 0..self.repetitions {
            let seed = u64::from(repetition) + 1;
            let mut images = Vec::new();
            for scene in [&with, &without] {
                let mut scene = scene.clone();
                scene.render.seed = seed;
                match Stage::<C>::with_chapters(&scene, 14, scene.render) {
                    Ok(stage) => images.push(mean_over(&linear_image(&stage))),
                    Err(error) => return Outcome::Error(error.to_string()),
                }
            }
            ratios.push(images[0] / images[1]);
        }
        let (mean, error) = mean_and_error(&ratios);
        let allowed = z_threshold() * error + LENS_ALLOWANCE * expected;
        verdict(
            mean.is_finite() && (mean - expected).abs() <= allowed,
            format!(
                "the caustic {} times as bright as the beam alone (within {:.2})",
                num64(expected),
                allowed
            ),
            format!(
                "{} times (standard error {:.2e}, over {} pixels)",
                num64(mean),
                error,
                geometry.len()
            ),
        )
    }
}

/// The share of the lens's expected ratio allowed beyond the noise: the
/// irradiance is compared at each pixel's centre, while a pixel averages
/// it over its footprint on the screen, and it grows by 4% from the axis
/// to the disk's edge; half a per cent covers that.
pub const LENS_ALLOWANCE: f64 = 5e-3;
