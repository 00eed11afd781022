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

/// A [`LightFormula`]'s inputs as the wire carries them (Cauchy's
/// coefficients as numbers).
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub enum LightFormulaCall {
    SplatWeight {
        cos_surface: f32,
        cos_camera: f32,
        distance: f32,
        pixel_area: f32,
    },
    CauchyIor {
        a: f32,
        b: f32,
        nanometres: f32,
    },
}

impl LightFormulaCase {
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
}

impl Kind for LightFormulaCase {
    type Call = LightFormulaCall;
    type Answer = f32;

    fn function(&self) -> &'static str {
        match self.formula {
            LightFormula::SplatWeight { .. } => "splat_weight",
            LightFormula::CauchyIor { .. } => "cauchy_ior",
        }
    }

    fn inputs(&self) -> String {
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

    fn call(&self) -> LightFormulaCall {
        match self.formula {
            LightFormula::SplatWeight {
                cos_surface,
                cos_camera,
                distance,
                pixel_area,
            } => LightFormulaCall::SplatWeight {
                cos_surface,
                cos_camera,
                distance,
                pixel_area,
            },
            LightFormula::CauchyIor { cauchy, nanometres } => LightFormulaCall::CauchyIor {
                a: cauchy.a,
                b: cauchy.b,
                nanometres,
            },
        }
    }

    fn ask<C: Chapters>(call: &LightFormulaCall) -> Result<f32, String> {
        Ok(match *call {
            LightFormulaCall::SplatWeight {
                cos_surface,
                cos_camera,
                distance,
                pixel_area,
            } => C::splat_weight(cos_surface, cos_camera, distance, pixel_area),
            LightFormulaCall::CauchyIor { a, b, nanometres } => {
                C::cauchy_ior(&Cauchy { a, b }, nanometres)
            }
        })
    }

    fn judge(&self, got: f32, _robust: bool) -> Outcome {
        let expected = self.expected();
        verdict(
            got.is_finite() && close(f64::from(got), expected, CHECKPOINT_TOLERANCE),
            num64(expected),
            num(got),
        )
    }

    /// Every input nudged by up to 10% (a zero stays zero, a sign its
    /// sign), the wavelength anywhere in 400 to 700 nm; the answer worked
    /// out again by the oracle.
    fn fresh(&self, draw: &mut Draw) -> Option<LightFormulaCase> {
        let formula = match self.formula {
            LightFormula::SplatWeight {
                cos_surface,
                cos_camera,
                distance,
                pixel_area,
            } => {
                let cos_surface = draw.nudge(cos_surface, 0.1).clamp(-1.0, 1.0);
                let cos_camera = draw.nudge(cos_camera, 0.1).clamp(-1.0, 1.0);
                LightFormula::SplatWeight {
                    cos_surface,
                    cos_camera,
                    distance: draw.nudge(distance, 0.1),
                    pixel_area: draw.nudge(pixel_area, 0.1),
                }
            }
            LightFormula::CauchyIor { cauchy, .. } => LightFormula::CauchyIor {
                cauchy: Cauchy {
                    a: draw.nudge(cauchy.a, 0.02),
                    b: draw.nudge(cauchy.b, 0.1),
                },
                nanometres: draw.between(400.0, 700.0) as f32,
            },
        };
        Some(LightFormulaCase { formula })
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

/// A prism's call: Cauchy's `(a, b)`, the apex angle in degrees and the
/// wavelength.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub struct PrismCall {
    pub cauchy: (f32, f32),
    pub apex_degrees: f32,
    pub nanometres: f32,
}

impl Kind for PrismCase {
    type Call = PrismCall;
    /// The smallest deviation found, in degrees; `None` when no ray got
    /// through.
    type Answer = Option<f64>;

    fn function(&self) -> &'static str {
        "cauchy_ior"
    }

    fn inputs(&self) -> String {
        format!(
            "a prism of apex {} degrees, Cauchy a = {}, b = {}, at {} nm: the smallest \
             deviation over every angle of incidence, with refract and cauchy_ior",
            num(self.apex_degrees),
            num(self.cauchy.a),
            num(self.cauchy.b),
            num(self.nanometres)
        )
    }

    fn call(&self) -> PrismCall {
        PrismCall {
            cauchy: (self.cauchy.a, self.cauchy.b),
            apex_degrees: self.apex_degrees,
            nanometres: self.nanometres,
        }
    }

    fn ask<C: Chapters>(call: &PrismCall) -> Result<Option<f64>, String> {
        let (a, b) = call.cauchy;
        let index = C::cauchy_ior(&Cauchy { a, b }, call.nanometres);
        // Every tenth of a degree of incidence, then a golden-section
        // search about the smallest: the deviation is flat at its minimum,
        // so its value is found far more precisely than the angle.
        let angles = (1..900).map(|tenth| (tenth as f32 / 10.0).to_radians());
        let Some((best, _)) = angles
            .filter_map(|angle| Some((angle, deviation::<C>(call, index, angle)?)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
        else {
            return Ok(None);
        };
        let step = 0.1f32.to_radians();
        let (mut low, mut high) = (best - step, best + step);
        let ratio = (5f32.sqrt() - 1.0) / 2.0;
        let value = |angle: f32| deviation::<C>(call, index, angle).unwrap_or(f32::INFINITY);
        for _ in 0..40 {
            let (left, right) = (high - ratio * (high - low), low + ratio * (high - low));
            if value(left) < value(right) {
                high = right;
            } else {
                low = left;
            }
        }
        Ok(Some(f64::from(value((low + high) / 2.0))))
    }

    fn judge(&self, found: Option<f64>, _robust: bool) -> Outcome {
        let expected = exact::prism_minimum_deviation(
            exact::cauchy(
                f64::from(self.cauchy.a),
                f64::from(self.cauchy.b),
                f64::from(self.nanometres),
            ),
            f64::from(self.apex_degrees).to_radians(),
        )
        .to_degrees();
        let Some(found) = found else {
            return verdict(
                false,
                format!("a smallest deviation of {expected:.4} degrees"),
                "no ray got through the prism (refract gave None at every angle)".into(),
            );
        };
        verdict(
            (found - expected).abs() <= PRISM_TOLERANCE_DEGREES,
            format!("{expected:.4} degrees (2 asin(n sin(A / 2)) - A)"),
            format!("{found:.4} degrees"),
        )
    }

    /// The apex nudged by up to 5%, Cauchy's coefficients by 1% and 10%,
    /// the wavelength anywhere in 400 to 700 nm.
    fn fresh(&self, draw: &mut Draw) -> Option<PrismCase> {
        Some(PrismCase {
            cauchy: Cauchy {
                a: draw.nudge(self.cauchy.a, 0.01),
                b: draw.nudge(self.cauchy.b, 0.1),
            },
            apex_degrees: draw.nudge(self.apex_degrees, 0.05),
            nanometres: draw.between(400.0, 700.0) as f32,
        })
    }
}

/// The ray's deviation in degrees for the incidence `incidence` (radians)
/// on the first face, `None` when it cannot leave by the second (total
/// internal reflection). The prism's apex points up (+y), its faces'
/// outward normals turned by `apex / 2` left and right of -x and +x.
fn deviation<C: Chapters>(call: &PrismCall, index: f32, incidence: f32) -> Option<f32> {
    let half = call.apex_degrees.to_radians() / 2.0;
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
    /// The first render's seed (1 for the lesson's case).
    pub first_seed: u64,
}

/// A closed scene's renders: the scene (TOML), the effects left out, how
/// many renders, and the seed of the first (each next one's is one more).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct LightConvergesCall {
    pub scene: String,
    pub without: Vec<String>,
    pub repetitions: u32,
    pub first_seed: u64,
}

/// The most whole renders one case may ask for.
const MOST_RENDERS: u32 = 1024;

impl LightConvergesCase {
    /// Per channel, the mean of the repetitions' image means and its
    /// standard error, with the chapters `C`.
    pub fn estimate<C: Chapters>(&self) -> Result<(DVec3, DVec3), String> {
        Ok(channel_means(&light_means::<C>(&self.call())?))
    }
}

/// Per channel, the mean of `means` and its standard error.
fn channel_means(means: &[Vec3]) -> (DVec3, DVec3) {
    let channel = |pick: fn(Vec3) -> f32| {
        mean_and_error(
            &means
                .iter()
                .map(|mean| f64::from(pick(*mean)))
                .collect::<Vec<_>>(),
        )
    };
    let (x, y, z) = (channel(|v| v.x), channel(|v| v.y), channel(|v| v.z));
    (DVec3::new(x.0, y.0, z.0), DVec3::new(x.1, y.1, z.1))
}

/// Each render's image mean, with the chapters `C`.
fn light_means<C: Chapters>(call: &LightConvergesCall) -> Result<Vec<Vec3>, String> {
    if call.repetitions > MOST_RENDERS {
        return Err(format!(
            "{} renders asked, more than {MOST_RENDERS}",
            call.repetitions
        ));
    }
    let mut scene = parse(&call.scene)?;
    scene.render.without = SwitchedOff::parse(call.without.iter().map(String::as_str))?;
    (0..call.repetitions)
        .map(|repetition| {
            scene.render.seed = call.first_seed.wrapping_add(u64::from(repetition));
            image_mean::<C>(&scene, 14)
        })
        .collect()
}

impl Kind for LightConvergesCase {
    type Call = LightConvergesCall;
    /// Each render's image mean.
    type Answer = Vec<Vec3>;

    fn statistical(&self) -> bool {
        true
    }

    fn function(&self) -> &'static str {
        self.function
    }

    fn inputs(&self) -> String {
        format!(
            "{} renders of a closed scene, each with its own seed from {}{}",
            self.repetitions,
            self.first_seed,
            super::paths::without_text(self.without)
        )
    }

    fn call(&self) -> LightConvergesCall {
        LightConvergesCall {
            scene: self.scene.clone(),
            without: self.without.iter().map(|name| name.to_string()).collect(),
            repetitions: self.repetitions,
            first_seed: self.first_seed,
        }
    }

    fn ask<C: Chapters>(call: &LightConvergesCall) -> Result<Vec<Vec3>, String> {
        // The chapter's own formulas first: in a workspace where nothing is
        // written yet, their `todo!()` says chapter 14 is not started.
        let _ = (
            C::splat_weight(1.0, 1.0, 1.0, 1.0),
            C::cauchy_ior(&Cauchy { a: 1.5, b: 0.0 }, 550.0),
        );
        light_means::<C>(call)
    }

    fn judge(&self, means: Vec<Vec3>, _robust: bool) -> Outcome {
        if means.len() != self.repetitions as usize {
            return super::intersections::wrong_length(self.repetitions as usize, means.len());
        }
        let (mean, error) = channel_means(&means);
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

    /// Other seeds for the renders.
    fn fresh(&self, draw: &mut Draw) -> Option<LightConvergesCase> {
        Some(LightConvergesCase {
            first_seed: draw.word() >> 1,
            ..self.clone()
        })
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
    /// The first render's seed (1 for the lesson's case).
    pub first_seed: u64,
}

/// The lens's renders: the scene with the ball and without, each seed.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct LensCall {
    pub with: String,
    pub without: String,
    pub seeds: Vec<u64>,
}

impl LensCase {
    /// The renders' seeds, one per repetition.
    fn seeds(&self) -> Vec<u64> {
        (0..u64::from(self.repetitions))
            .map(|repetition| self.first_seed.wrapping_add(repetition))
            .collect()
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
}

impl Kind for LensCase {
    type Call = LensCall;
    /// For each seed, the first channel of every pixel with the ball and
    /// without it.
    type Answer = Vec<(Vec<f32>, Vec<f32>)>;

    fn statistical(&self) -> bool {
        true
    }

    fn function(&self) -> &'static str {
        "connect_to_camera"
    }

    fn inputs(&self) -> String {
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

    fn call(&self) -> LensCall {
        LensCall {
            with: self.scene(true),
            without: self.scene(false),
            seeds: self.seeds(),
        }
    }

    fn ask<C: Chapters>(call: &LensCall) -> Result<Self::Answer, String> {
        // The chapter's own formula first, as for the closed scenes.
        let _ = C::splat_weight(1.0, 1.0, 1.0, 1.0);
        if call.seeds.len() > MOST_RENDERS as usize {
            return Err(format!("{} renders asked", call.seeds.len()));
        }
        let (with, without) = (parse(&call.with)?, parse(&call.without)?);
        let image = |scene: &Scene, seed: u64| -> Result<Vec<f32>, String> {
            let mut scene = scene.clone();
            scene.render.seed = seed;
            let stage =
                Stage::<C>::with_chapters(&scene, 14, scene.render).map_err(|e| e.to_string())?;
            Ok(linear_image(&stage).iter().map(|pixel| pixel.x).collect())
        };
        call.seeds
            .iter()
            .map(|&seed| Ok((image(&with, seed)?, image(&without, seed)?)))
            .collect()
    }

    fn judge(&self, images: Self::Answer, _robust: bool) -> Outcome {
        let without = match parse(&self.scene(false)) {
            Ok(without) => without,
            Err(why) => return Outcome::Error(why),
        };
        let geometry = match Stage::<Reference>::with_chapters(&without, 14, without.render) {
            Ok(stage) => self.compared_pixels(&stage),
            Err(error) => return Outcome::Error(error.to_string()),
        };
        let seeds = self.seeds();
        if images.len() != seeds.len() {
            return super::intersections::wrong_length(seeds.len(), images.len());
        }
        let pixels = (without.render.width * without.render.height) as usize;
        if images
            .iter()
            .any(|(with, without)| with.len() != pixels || without.len() != pixels)
        {
            return super::intersections::wrong_length(pixels, 0);
        }
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
        let mean_over = |pixels: &[f32]| {
            geometry
                .iter()
                .map(|(index, _)| f64::from(pixels[*index]))
                .sum::<f64>()
                / geometry.len().max(1) as f64
        };
        let ratios: Vec<f64> = images
            .iter()
            .map(|(with, without)| mean_over(with) / mean_over(without))
            .collect();
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

    /// Other seeds for the renders.
    fn fresh(&self, draw: &mut Draw) -> Option<LensCase> {
        Some(LensCase {
            first_seed: draw.word() >> 1,
            ..self.clone()
        })
    }
}

/// The share of the lens's expected ratio allowed beyond the noise: the
/// irradiance is compared at each pixel's centre, while a pixel averages
/// it over its footprint on the screen, and it grows by 4% from the axis
/// to the disk's edge; half a per cent covers that.
pub const LENS_ALLOWANCE: f64 = 5e-3;

/// `dispersive_ior` at the first dispersive surface of `paths` paths and
/// again at a second one: on the first, each path draws a wavelength
/// uniform over the visible range, keeps it (`tracer.wavelength()`), and
/// returns the Cauchy index of that wavelength with its colour
/// (`rgb_weight`); on the second, the same index and no colour (white).
/// The wavelengths' spread is a chi-square test on 20 equal bins of
/// 380..780 nm, at [`FALSE_ALARM`]; the rest is exact for each path.
#[derive(Debug, Clone)]
pub struct DispersionCase {
    pub cauchy: Cauchy,
    pub paths: u32,
    /// The paths' streams' seed: 0 for the lesson's, `grade --fresh`'s
    /// otherwise.
    pub seed: u64,
}

/// A [`DispersionCase`]'s call: Cauchy's coefficients as numbers.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub struct DispersionCall {
    pub a: f32,
    pub b: f32,
    pub paths: u32,
    pub seed: u64,
}

/// What one path's two calls of `dispersive_ior` gave, and the wavelength
/// the path kept after the first.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub struct DispersedTwice {
    pub first: (f32, Vec3),
    pub kept: Option<f32>,
    pub second: (f32, Vec3),
}

/// Bins of the wavelength test.
const WAVELENGTH_BINS: usize = 20;

/// A scene for the stage the dispersion case's tracer comes from: the
/// stage's objects play no part.
const DISPERSION_STAGE: &str = r#"
[camera]
position = [0.0, 0.0, -2.0]
look_at = [0.0, 0.0, 0.0]
[render]
width = 4
height = 4
[[objects]]
sphere = { center = [0.0, 0.0, 0.0], radius = 1.0 }
material = { color = [1.0, 1.0, 1.0], transparency = 1.0, cauchy = { a = 1.6, b = 0.05 } }
"#;

impl Kind for DispersionCase {
    type Call = DispersionCall;
    type Answer = Vec<DispersedTwice>;

    fn statistical(&self) -> bool {
        true
    }

    fn function(&self) -> &'static str {
        "dispersive_ior"
    }

    fn inputs(&self) -> String {
        format!(
            "dispersive_ior(tracer, Cauchy {{ a: {}, b: {} }}) twice on each of {} new paths{}",
            num(self.cauchy.a),
            num(self.cauchy.b),
            self.paths,
            if self.seed == 0 {
                String::new()
            } else {
                format!(", stream seed {}", self.seed)
            }
        )
    }

    fn call(&self) -> DispersionCall {
        DispersionCall {
            a: self.cauchy.a,
            b: self.cauchy.b,
            paths: self.paths,
            seed: self.seed,
        }
    }

    fn ask<C: Chapters>(call: &DispersionCall) -> Result<Vec<DispersedTwice>, String> {
        if call.paths > MOST_DISPERSED_PATHS {
            return Err(format!(
                "{} paths asked, more than {MOST_DISPERSED_PATHS}",
                call.paths
            ));
        }
        let mut scene = parse(DISPERSION_STAGE)?;
        if call.seed != 0 {
            scene.render.seed = call.seed;
        }
        let stage = Stage::<C>::with_chapters(&scene, 14, scene.render)
            .map_err(|error| error.to_string())?;
        let mut tracer = stage.tracer(None);
        let cauchy = Cauchy {
            a: call.a,
            b: call.b,
        };
        Ok((0..call.paths)
            .map(|path| {
                tracer.begin_path(u64::from(path));
                let first = C::dispersive_ior(&mut tracer, &cauchy);
                let kept = tracer.wavelength();
                let second = C::dispersive_ior(&mut tracer, &cauchy);
                DispersedTwice {
                    first: (first.ior, first.tint),
                    kept,
                    second: (second.ior, second.tint),
                }
            })
            .collect())
    }

    fn judge(&self, draws: Vec<DispersedTwice>, _robust: bool) -> Outcome {
        if draws.len() != self.paths as usize {
            return super::intersections::wrong_length(self.paths as usize, draws.len());
        }
        let (low, high) = crate::spectrum::VISIBLE;
        let (a, b) = (f64::from(self.cauchy.a), f64::from(self.cauchy.b));
        // `max_element` skips a NaN (`f32::max` returns the other number):
        // a colour with a NaN channel must not pass on its other two.
        let close_to =
            |got: Vec3, want: Vec3| got.is_finite() && (got - want).abs().max_element() <= 1e-4;
        let mut observed = vec![0f64; WAVELENGTH_BINS];
        for (path, draw) in draws.iter().enumerate() {
            let Some(nanometres) = draw.kept.filter(|nm| (low..=high).contains(nm)) else {
                return verdict(
                    false,
                    format!(
                        "path {path}: a wavelength in {low}..{high} nm kept by the path \
                         (tracer.set_wavelength) after the first dispersive surface"
                    ),
                    match draw.kept {
                        Some(nm) => format!("the path kept {} nm", num(nm)),
                        None => "no wavelength kept".into(),
                    },
                );
            };
            let index = exact::cauchy(a, b, f64::from(nanometres));
            if !close(f64::from(draw.first.0), index, CHECKPOINT_TOLERANCE) {
                return verdict(
                    false,
                    format!(
                        "path {path}: the index of the wavelength it kept, {} nm: {}",
                        num(nanometres),
                        num64(index)
                    ),
                    format!("index {}", num(draw.first.0)),
                );
            }
            let colour = crate::spectrum::rgb_weight(nanometres);
            if !close_to(draw.first.1, colour) {
                return verdict(
                    false,
                    format!(
                        "path {path}: the colour of its wavelength, {} nm: {}",
                        num(nanometres),
                        vec(colour)
                    ),
                    format!("colour {}", vec(draw.first.1)),
                );
            }
            if draw.second.0 != draw.first.0 || !close_to(draw.second.1, Vec3::ONE) {
                return verdict(
                    false,
                    format!(
                        "path {path}: at its second dispersive surface the same index, {}, and \
                         no colour again, (1, 1, 1)",
                        num(draw.first.0)
                    ),
                    format!(
                        "index {} and colour {}",
                        num(draw.second.0),
                        vec(draw.second.1)
                    ),
                );
            }
            let share = f64::from((nanometres - low) / (high - low));
            let bin = ((share * WAVELENGTH_BINS as f64) as usize).min(WAVELENGTH_BINS - 1);
            observed[bin] += 1.0;
        }
        let expected = vec![f64::from(self.paths) / WAVELENGTH_BINS as f64; WAVELENGTH_BINS];
        let (statistic, p_value) = super::paths::pearson(&observed, &expected);
        verdict(
            p_value >= FALSE_ALARM,
            format!(
                "wavelengths uniform over {low}..{high} nm: a chi-square p-value above \
                 {FALSE_ALARM:.0e}"
            ),
            format!("chi-square {statistic:.1}, p-value {p_value:.2e}"),
        )
    }

    /// Other streams: the same test on other numbers.
    fn fresh(&self, draw: &mut Draw) -> Option<DispersionCase> {
        Some(DispersionCase {
            seed: draw.word() | 1,
            ..self.clone()
        })
    }
}

/// The most paths a dispersion case may ask for.
const MOST_DISPERSED_PATHS: u32 = 1 << 20;

#[cfg(test)]
mod tests {
    use super::*;

    /// Answers to a dispersion case, every path right but for the colour
    /// `second` gives it at its second dispersive surface.
    fn dispersed(case: &DispersionCase, second: Vec3) -> Vec<DispersedTwice> {
        let (low, high) = crate::spectrum::VISIBLE;
        (0..case.paths)
            .map(|path| {
                let nanometres = low + (high - low) * (path as f32 + 0.5) / case.paths as f32;
                let index = exact::cauchy(
                    f64::from(case.cauchy.a),
                    f64::from(case.cauchy.b),
                    f64::from(nanometres),
                ) as f32;
                DispersedTwice {
                    first: (index, crate::spectrum::rgb_weight(nanometres)),
                    kept: Some(nanometres),
                    second: (index, second),
                }
            })
            .collect()
    }

    /// A colour with a NaN channel is no colour, whatever its other two.
    #[test]
    fn a_nan_in_a_dispersed_colour_fails() {
        let case = DispersionCase {
            cauchy: Cauchy { a: 1.5, b: 0.004 },
            paths: 400,
            seed: 0,
        };
        assert!(matches!(
            case.judge(dispersed(&case, Vec3::ONE), false),
            Outcome::Pass
        ));
        let nan = Vec3::new(f32::NAN, 1.0, 1.0);
        assert!(matches!(
            case.judge(dispersed(&case, nan), false),
            Outcome::Fail { .. }
        ));
    }
}
