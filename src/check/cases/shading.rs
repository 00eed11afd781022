//! Shading cases: where a shadow ray starts, whether a point is lit, and
//! the colour of a point, judged against the reference chapters.

use super::*;
use crate::answer_key::raylab_own;

/// `offset_origin(surface, dir)`: off the surface on `dir`'s side by at
/// least the point's error bound `|n| . error`, and by at most
/// `at_most` (scene units) at the checkpoint level or
/// `ROUNDINGS` error bounds at the robustness level.
#[derive(Debug, Clone)]
pub struct OffsetCase {
    pub surface: SurfacePoint,
    pub dir: Vec3,
    pub at_most: f64,
}

impl Kind for OffsetCase {
    type Call = (SurfacePoint, Vec3);
    type Answer = Vec3;

    fn function(&self) -> &'static str {
        "offset_origin"
    }

    fn inputs(&self) -> String {
        let OffsetCase { surface, dir, .. } = self;
        format!(
            "offset_origin(point {}, normal {}, error {}; dir {})",
            vec(surface.point),
            vec(surface.normal),
            vec(surface.error),
            vec(*dir)
        )
    }

    fn call(&self) -> Self::Call {
        (self.surface, self.dir)
    }

    fn ask<C: Chapters>((surface, dir): &Self::Call) -> Result<Vec3, String> {
        Ok(C::offset_origin(surface, *dir))
    }

    fn judge(&self, got: Vec3, robust: bool) -> Outcome {
        let OffsetCase {
            surface,
            dir,
            at_most,
        } = self;
        if !surface.point.is_finite() {
            // No step from an infinite coordinate is a point: f32::MAX
            // would be a finite, wrong origin.
            return verdict(got.is_nan(), "NaN (no origin)".to_string(), vec(got));
        }
        let n = wide(surface.normal);
        let bound = n.abs().dot(wide(surface.error));
        let side = if wide(*dir).dot(n) >= 0.0 { 1.0 } else { -1.0 };
        let push = side * (wide(got) - wide(surface.point)).dot(n);
        let limit = if robust {
            ROUNDINGS * bound + 4.0 * 2.0 * U * max_abs(wide(surface.point))
        } else {
            *at_most
        };
        // 0.99: the bound itself is computed in f32 by the reference,
        // a few u below its exact value.
        let pass = got.is_finite() && push > 0.0 && push >= 0.99 * bound && push <= limit;
        verdict(
            pass,
            format!(
                "an origin {} the surface (dir side) by at least {} and at most {}",
                if side > 0.0 { "above" } else { "below" },
                num64(bound),
                num64(limit)
            ),
            format!(
                "{}, {} the surface by {}",
                vec(got),
                if push >= 0.0 {
                    "on the dir side of"
                } else {
                    "on the WRONG side of"
                },
                num64(push.abs())
            ),
        )
    }

    /// The point, its normal and `dir` moved whole; the point's error
    /// bound carried through the turn (each new coordinate mixes the old
    /// ones' errors) and grown by the rounding of the move itself.
    fn fresh(&self, draw: &mut Draw) -> Option<OffsetCase> {
        if !self.surface.point.is_finite() {
            return None;
        }
        let motion = draw.motion();
        let point = motion.point(self.surface.point);
        let turned_error = motion.scale * (abs_matrix(motion.turn) * wide(self.surface.error));
        let rounding = 4.0 * U * (wide(point).abs() + DVec3::splat(max_abs(wide(point))));
        Some(OffsetCase {
            surface: SurfacePoint {
                point,
                normal: motion.direction(self.surface.normal),
                error: (turned_error + rounding).as_vec3(),
            },
            dir: motion.direction(self.dir),
            at_most: self.at_most * motion.scale,
        })
    }
}

/// The matrix of the absolute values of `matrix`'s entries: what a bound
/// per coordinate becomes through it.
fn abs_matrix(matrix: glam::DMat3) -> glam::DMat3 {
    glam::DMat3::from_cols(
        matrix.x_axis.abs(),
        matrix.y_axis.abs(),
        matrix.z_axis.abs(),
    )
}

/// `in_shadow` at the points where each of `rays` meets object
/// `object` of `scene` (TOML), for a light at `light`.
#[derive(Debug, Clone)]
pub struct ShadowCase {
    pub scene: String,
    pub object: usize,
    pub rays: Vec<Ray>,
    pub light: Vec3,
    pub expect: bool,
}

/// An `in_shadow` call: the scene (TOML), the object, the rays that
/// find the points on it, where each meets it (see [`hit_on`]), and the
/// light.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct ShadowCall {
    pub scene: String,
    pub object: usize,
    pub rays: Vec<Ray>,
    pub hits: Vec<Result<f32, String>>,
    pub light: Vec3,
}

impl Kind for ShadowCase {
    type Call = ShadowCall;
    /// For each ray, the point it found and the answer there.
    type Answer = Vec<(Vec3, bool)>;

    fn function(&self) -> &'static str {
        "in_shadow"
    }

    fn inputs(&self) -> String {
        let ShadowCase {
            rays,
            light,
            object,
            ..
        } = self;
        format!(
            "in_shadow at the point{} where {} meet{} object {object}, light at {}",
            if rays.len() > 1 { "s" } else { "" },
            if rays.len() > 1 {
                format!("{} rays", rays.len())
            } else {
                rays.first().map(ray_text).unwrap_or_default()
            },
            if rays.len() > 1 { "" } else { "s" },
            vec(*light)
        )
    }

    fn call(&self) -> ShadowCall {
        let scene = parse(&self.scene);
        ShadowCall {
            scene: self.scene.clone(),
            object: self.object,
            rays: self.rays.clone(),
            hits: self
                .rays
                .iter()
                .map(|ray| {
                    let scene = scene.as_ref().map_err(Clone::clone)?;
                    hit_on(scene, self.object, ray)
                })
                .collect(),
            light: self.light,
        }
    }

    fn ask<C: Chapters>(call: &ShadowCall) -> Result<Self::Answer, String> {
        let scene = parse(&call.scene)?;
        let stage =
            Stage::<C>::with_chapters(&scene, 4, scene.render).map_err(|e| e.to_string())?;
        let mut tracer = stage.tracer(None);
        let mut answers = Vec::with_capacity(call.rays.len());
        for (index, ray) in call.rays.iter().enumerate() {
            let t = call
                .hits
                .get(index)
                .cloned()
                .unwrap_or_else(|| Err(format!("no hit sent for ray {index}")))?;
            let point = tracer.hit_point(call.object, ray, t);
            answers.push((
                point.surface.point,
                C::in_shadow(&mut tracer, &point, call.light),
            ));
        }
        Ok(answers)
    }

    /// The same rule at both levels.
    fn judge(&self, answers: Self::Answer, _robust: bool) -> Outcome {
        let ShadowCase { rays, expect, .. } = self;
        if answers.len() != rays.len() {
            return super::intersections::wrong_length(rays.len(), answers.len());
        }
        for (index, (ray, &(point, got))) in rays.iter().zip(&answers).enumerate() {
            if got != *expect {
                let word = |shadow: bool| if shadow { "in shadow" } else { "lit" };
                return Outcome::Fail {
                    expected: format!("{} at every point", word(*expect)),
                    got: format!(
                        "{} at {} (ray {} of {}: {})",
                        word(got),
                        vec(point),
                        index + 1,
                        rays.len(),
                        ray_text(ray)
                    ),
                };
            }
        }
        Outcome::Pass
    }

    /// Each ray turned by up to a degree and the light moved by up to 2%
    /// of its distance from the scene's centre, drawn again until every
    /// ray still finds the case's object and the exact segment to the
    /// light is blocked (or clear) as in the case.
    fn fresh(&self, draw: &mut Draw) -> Option<ShadowCase> {
        let scene = parse(&self.scene).ok()?;
        for _ in 0..FRESH_TRIES {
            let rays: Vec<Ray> = self
                .rays
                .iter()
                .map(|ray| Ray::new(ray.origin, draw.tilt(ray.dir, 1.0)))
                .collect();
            let reach = f64::from(self.light.length()).max(1.0);
            let light = (wide(self.light) + draw.shift(0.02 * reach)).as_vec3();
            let kept = rays.iter().all(|ray| {
                reference_point(&scene, self.object, ray).is_some_and(|point| {
                    exactly_blocked(&scene.shapes, point, light) == Some(self.expect)
                })
            });
            if kept {
                return Some(ShadowCase {
                    rays,
                    light,
                    ..self.clone()
                });
            }
        }
        None
    }
}

/// How many draws a fresh case may take to keep its meaning.
const FRESH_TRIES: usize = 16;

/// The point where `ray` first meets `scene`, by raylab's own geometry,
/// when that is object `object`.
fn reference_point(scene: &Scene, object: usize, ray: &Ray) -> Option<Vec3> {
    let hit = crate::nearest_hit(&scene.shapes, ray, 0.0, f32::INFINITY)?;
    (hit.object == object).then(|| scene.shapes[object].surface_point(ray, hit.t).point)
}

/// Whether the exact segment from `point` to `light` meets a shape (past a
/// thousandth of its length, so that the point's own surface does not
/// count), worked out in `f64`; `None` where a shape has no exact test.
fn exactly_blocked(shapes: &[Shape], point: Vec3, light: Vec3) -> Option<bool> {
    let segment = Ray::new(point, light - point);
    let mut blocked = false;
    for shape in shapes {
        if matches!(shape, Shape::Implicit(_)) {
            return None;
        }
        blocked |= super::intersections::exact_t(shape, &segment, 1e-3, 1.0).is_some();
    }
    Some(blocked)
}

/// A shading function at the point where `ray` meets `scene` (TOML):
/// expected, the reference chapters' answer on the same point.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct ShadeCase {
    pub shading: Shading,
    pub scene: String,
    pub ray: Ray,
    /// Bounces so far (chapters 6 and 8).
    pub depth: u32,
    /// When given, the scene's object 0 must be a triangle: it is shaded
    /// smooth with these vertex normals, at chapter 10's stage, where a
    /// mirror or glass follows the shading normal (TOML has no way to give
    /// a triangle its vertex normals).
    pub vertex_normals: Option<[Vec3; 3]>,
}

/// A shading call: the case itself, which holds no expectation (the
/// reference chapters give it, in the judge), and where its ray meets
/// object 0 (see [`hit_on`]).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct ShadeCall {
    pub case: ShadeCase,
    pub hit: Result<f32, String>,
}

impl Kind for ShadeCase {
    type Call = ShadeCall;
    /// The colour (for Phong, its diffuse and specular terms).
    type Answer = Vec<Vec3>;

    fn function(&self) -> &'static str {
        match self.shading {
            Shading::Flat => "shade_flat",
            Shading::Phong => "shade_phong",
            Shading::Mirror => "shade_mirror",
            Shading::Glass => "shade_glass",
            Shading::Dielectric => "shade_dielectric",
        }
    }

    fn inputs(&self) -> String {
        let ShadeCase {
            shading,
            ray,
            depth,
            vertex_normals,
            ..
        } = self;
        let smooth = match vertex_normals {
            Some(normals) => format!(
                " (object 0 smooth, vertex normals {})",
                normals_text(normals)
            ),
            None => String::new(),
        };
        format!(
            "{}(the point where {} meets the case's scene{smooth}{})",
            self.function(),
            ray_text(ray),
            match shading {
                Shading::Mirror | Shading::Glass | Shading::Dielectric => {
                    format!(", depth {depth}, weight 1")
                }
                _ => String::new(),
            }
        )
    }

    fn call(&self) -> ShadeCall {
        ShadeCall {
            case: self.clone(),
            hit: scene_of(self).and_then(|scene| hit_on(&scene, 0, &self.ray)),
        }
    }

    fn ask<C: Chapters>(call: &ShadeCall) -> Result<Vec<Vec3>, String> {
        shade::<C>(call)
    }

    /// Against the reference chapters on the same point, with the same
    /// tolerance at both levels.
    fn judge(&self, got: Vec<Vec3>, _robust: bool) -> Outcome {
        let expected = match crate::answer_key::raylab_own(|| shade::<Reference>(&self.call())) {
            Ok(expected) => expected,
            Err(error) => return Outcome::Error(error),
        };
        if got.len() != expected.len() {
            return super::intersections::wrong_length(expected.len(), got.len());
        }
        let pass = got.iter().zip(&expected).all(|(g, w)| colour_close(*g, *w));
        let show = |colours: &[Vec3]| {
            if self.shading == Shading::Phong {
                format!("diffuse {}, specular {}", vec(colours[0]), vec(colours[1]))
            } else {
                vec(colours[0])
            }
        };
        verdict(pass, show(&expected), show(&got))
    }

    /// The ray turned by up to a degree, drawn again until it still finds
    /// the case's object first; the expected colour is the reference's
    /// at the new point.
    fn fresh(&self, draw: &mut Draw) -> Option<ShadeCase> {
        let scene = scene_of(self).ok()?;
        for _ in 0..FRESH_TRIES {
            let ray = Ray::new(self.ray.origin, draw.tilt(self.ray.dir, 1.0));
            if reference_point(&scene, 0, &ray).is_some() {
                return Some(ShadeCase {
                    ray,
                    ..self.clone()
                });
            }
        }
        None
    }
}

/// `phong_terms(material, albedo, normal, to_light, to_eye, light)`.
#[derive(Debug, Clone)]
pub struct PhongTermsCase {
    pub material: Material,
    pub albedo: Vec3,
    pub normal: Vec3,
    pub to_light: Vec3,
    pub to_eye: Vec3,
    pub light: Vec3,
    pub expect: PhongTerms,
}

/// `phong_terms`' inputs: the material's Phong coefficients, then the
/// vectors and colours.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct PhongTermsCall {
    /// `(k_a, k_d, k_s, shininess)`; the rest of the material is the
    /// default one.
    pub coefficients: (f32, f32, f32, u32),
    pub albedo: Vec3,
    pub normal: Vec3,
    pub to_light: Vec3,
    pub to_eye: Vec3,
    pub light: Vec3,
}

impl Kind for PhongTermsCase {
    type Call = PhongTermsCall;
    type Answer = PhongTerms;

    fn function(&self) -> &'static str {
        "phong_terms"
    }

    fn inputs(&self) -> String {
        let PhongTermsCase {
            material,
            albedo,
            normal,
            to_light,
            to_eye,
            light,
            ..
        } = self;
        format!(
            "phong_terms(k_d = {}, k_s = {}, shininess {}; albedo {}, normal {}, to_light {}, to_eye {}, light {})",
            num(material.diffuse),
            num(material.specular),
            material.shininess,
            vec(*albedo),
            vec(*normal),
            vec(*to_light),
            vec(*to_eye),
            vec(*light)
        )
    }

    fn call(&self) -> PhongTermsCall {
        let material = &self.material;
        PhongTermsCall {
            coefficients: (
                material.ambient,
                material.diffuse,
                material.specular,
                material.shininess,
            ),
            albedo: self.albedo,
            normal: self.normal,
            to_light: self.to_light,
            to_eye: self.to_eye,
            light: self.light,
        }
    }

    fn ask<C: Chapters>(call: &PhongTermsCall) -> Result<PhongTerms, String> {
        let (ambient, diffuse, specular, shininess) = call.coefficients;
        let material = Material {
            ambient,
            diffuse,
            specular,
            shininess,
            ..Material::default()
        };
        Ok(C::phong_terms(
            &material,
            call.albedo,
            call.normal,
            call.to_light,
            call.to_eye,
            call.light,
        ))
    }

    /// The same tolerance at both levels.
    fn judge(&self, got: PhongTerms, _robust: bool) -> Outcome {
        let expect = &self.expect;
        let finite = |terms: &PhongTerms| terms.diffuse.is_finite() && terms.specular.is_finite();
        if !finite(expect) {
            // Non-finite input: any non-finite term is the answer, a
            // colour is not (it would hide the NaN from the render's count).
            return verdict(
                !finite(&got),
                "non-finite terms".to_string(),
                terms_text(&got),
            );
        }
        let pass = colour_close(got.diffuse, expect.diffuse)
            && colour_close(got.specular, expect.specular);
        verdict(pass, terms_text(expect), terms_text(&got))
    }

    /// The three unit vectors turned together (every cosine kept), the
    /// coefficients, the albedo and the light's colour nudged by up to
    /// 10%; the terms worked out again by the oracle.
    fn fresh(&self, draw: &mut Draw) -> Option<PhongTermsCase> {
        let finite = |v: Vec3| v.is_finite();
        if ![
            self.albedo,
            self.normal,
            self.to_light,
            self.to_eye,
            self.light,
        ]
        .into_iter()
        .all(finite)
        {
            return None;
        }
        let turn = draw.rotation();
        let turned = |v: Vec3| (turn * wide(v)).as_vec3();
        let mut nudged = |v: Vec3| Vec3::from_array(v.to_array().map(|x| draw.nudge(x, 0.1)));
        let (albedo, light) = (nudged(self.albedo), nudged(self.light));
        let material = Material {
            diffuse: draw.nudge(self.material.diffuse, 0.1),
            specular: draw.nudge(self.material.specular, 0.1),
            ..self.material
        };
        let (normal, to_light, to_eye) = (
            turned(self.normal),
            turned(self.to_light),
            turned(self.to_eye),
        );
        let (diffuse, specular) = exact::phong_terms(
            f64::from(material.diffuse),
            f64::from(material.specular),
            material.shininess,
            wide(albedo),
            [wide(normal), wide(to_light), wide(to_eye)],
            wide(light),
        );
        Some(PhongTermsCase {
            material,
            albedo,
            normal,
            to_light,
            to_eye,
            light,
            expect: PhongTerms {
                diffuse: diffuse.as_vec3(),
                specular: specular.as_vec3(),
            },
        })
    }
}

/// Where `ray` meets object `object` of `scene`, by raylab's own geometry,
/// when it meets that object first: the case's inputs do not depend on
/// the code under check. Worked out by the judge and sent with the call,
/// so that none of raylab's answers runs in the student's process.
fn hit_on(scene: &Scene, object: usize, ray: &Ray) -> Result<f32, String> {
    match raylab_own(|| crate::nearest_hit(&scene.shapes, ray, 0.0, f32::INFINITY)) {
        Some(hit) if hit.object == object => Ok(hit.t),
        other => Err(format!(
            "the case's ray {} should meet object {object} first, but meets {other:?}",
            ray_text(ray)
        )),
    }
}

/// The scene of a shading case, with object 0 made smooth where the case
/// gives it vertex normals; and the chapter whose stage shades it.
fn scene_of(case: &ShadeCase) -> Result<Scene, String> {
    let mut scene = parse(&case.scene)?;
    if let Some(normals) = case.vertex_normals {
        let Some(Shape::Triangle(triangle)) = scene.shapes.first() else {
            return Err("the case's object 0 should be a triangle".to_string());
        };
        let [a, b, c] = triangle.corners();
        scene.shapes[0] = Shape::Triangle(Triangle::with_normals(
            a,
            b,
            c,
            scene.vertex_normals.len() as u32,
        ));
        scene.vertex_normals.push(normals);
    }
    Ok(scene)
}

/// The shading function of `case` at its point, by the chapters `C`: the
/// colour, or for Phong its diffuse and specular terms.
fn shade<C: Chapters>(call: &ShadeCall) -> Result<Vec<Vec3>, String> {
    let case = &call.case;
    let scene = scene_of(case)?;
    let chapter = if case.vertex_normals.is_some() {
        10
    } else {
        case.shading.stage()
    };
    let stage =
        Stage::<C>::with_chapters(&scene, chapter, scene.render).map_err(|e| e.to_string())?;
    let mut tracer = stage.tracer(None);
    let point = tracer.hit_point(0, &case.ray, call.hit.clone()?);
    let depth = case.depth;
    Ok(match case.shading {
        Shading::Flat => vec![C::shade_flat(&mut tracer, &point)],
        Shading::Phong => {
            let terms = C::shade_phong(&mut tracer, &point);
            vec![terms.diffuse, terms.specular]
        }
        Shading::Mirror => vec![C::shade_mirror(&mut tracer, &point, depth, 1.0)],
        Shading::Glass => vec![C::shade_glass(&mut tracer, &point, depth, 1.0)],
        Shading::Dielectric => vec![C::shade_dielectric(&mut tracer, &point, depth, 1.0)],
    })
}

fn terms_text(terms: &PhongTerms) -> String {
    format!(
        "diffuse {}, specular {}",
        vec(terms.diffuse),
        vec(terms.specular)
    )
}
