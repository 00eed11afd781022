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

impl OffsetCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "offset_origin"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        let OffsetCase { surface, dir, .. } = self;
        format!(
            "offset_origin(point {}, normal {}, error {}; dir {})",
            vec(surface.point),
            vec(surface.normal),
            vec(surface.error),
            vec(*dir)
        )
    }

    /// Asks the question of the chapters `C`; `robust`: at the robustness
    /// level's tolerance.
    pub(super) fn evaluate<C: Chapters>(&self, robust: bool) -> Outcome {
        let OffsetCase {
            surface,
            dir,
            at_most,
        } = self;
        let got = C::offset_origin(surface, *dir);
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

impl ShadowCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "in_shadow"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
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

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let ShadowCase {
            scene,
            object,
            rays,
            light,
            expect,
        } = self;
        let scene = match parse(scene) {
            Ok(scene) => scene,
            Err(error) => return Outcome::Error(error),
        };
        let stage = match Stage::<C>::with_chapters(&scene, 4, scene.render) {
            Ok(stage) => stage,
            Err(error) => return Outcome::Error(error.to_string()),
        };
        let mut tracer = stage.tracer(None);
        for (index, ray) in rays.iter().enumerate() {
            let point = match point_on(&scene, &tracer, *object, ray) {
                Ok(point) => point,
                Err(error) => return Outcome::Error(error),
            };
            let got = C::in_shadow(&mut tracer, &point, *light);
            if got != *expect {
                let word = |shadow: bool| if shadow { "in shadow" } else { "lit" };
                return Outcome::Fail {
                    expected: format!("{} at every point", word(*expect)),
                    got: format!(
                        "{} at {} (ray {} of {}: {})",
                        word(got),
                        vec(point.surface.point),
                        index + 1,
                        rays.len(),
                        ray_text(ray)
                    ),
                };
            }
        }
        Outcome::Pass
    }
}

/// A shading function at the point where `ray` meets `scene` (TOML):
/// expected, the reference chapters' answer on the same point.
#[derive(Debug, Clone)]
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

impl ShadeCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        match self.shading {
            Shading::Flat => "shade_flat",
            Shading::Phong => "shade_phong",
            Shading::Mirror => "shade_mirror",
            Shading::Glass => "shade_glass",
            Shading::Dielectric => "shade_dielectric",
        }
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
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

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let ShadeCase {
            shading,
            scene,
            ray,
            depth,
            vertex_normals,
        } = self;
        shade::<C>(*shading, scene, *vertex_normals, ray, *depth)
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

impl PhongTermsCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "phong_terms"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
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

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let PhongTermsCase {
            material,
            albedo,
            normal,
            to_light,
            to_eye,
            light,
            expect,
        } = self;
        let got = C::phong_terms(material, *albedo, *normal, *to_light, *to_eye, *light);
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
}

/// The point where `ray` meets object `object`, by the reference tests (the
/// case's inputs do not depend on the code under check).
fn point_on<'a, C: Chapters>(
    scene: &Scene,
    tracer: &Tracer<'a, C>,
    object: usize,
    ray: &Ray,
) -> Result<HitPoint<'a>, String> {
    match raylab_own(|| crate::nearest_hit(&scene.shapes, ray, 0.0, f32::INFINITY)) {
        Some(hit) if hit.object == object => Ok(tracer.hit_point(object, ray, hit.t)),
        other => Err(format!(
            "the case's ray {} should meet object {object} first, but meets {other:?}",
            ray_text(ray)
        )),
    }
}

fn shade<C: Chapters>(
    shading: Shading,
    scene: &str,
    vertex_normals: Option<[Vec3; 3]>,
    ray: &Ray,
    depth: u32,
) -> Outcome {
    let mut scene = match parse(scene) {
        Ok(scene) => scene,
        Err(error) => return Outcome::Error(error),
    };
    let mut chapter = shading.stage();
    if let Some(normals) = vertex_normals {
        let Some(Shape::Triangle(triangle)) = scene.shapes.first() else {
            return Outcome::Error("the case's object 0 should be a triangle".to_string());
        };
        let [a, b, c] = triangle.corners();
        scene.shapes[0] = Shape::Triangle(Triangle::with_normals(
            a,
            b,
            c,
            scene.vertex_normals.len() as u32,
        ));
        scene.vertex_normals.push(normals);
        chapter = 10;
    }
    let (stage, reference) = match (
        Stage::<C>::with_chapters(&scene, chapter, scene.render),
        Stage::<Reference>::with_chapters(&scene, chapter, scene.render),
    ) {
        (Ok(stage), Ok(reference)) => (stage, reference),
        (Err(error), _) | (_, Err(error)) => return Outcome::Error(error.to_string()),
    };
    let mut tracer = stage.tracer(None);
    let mut reference_tracer = reference.tracer(None);
    let point = match point_on(&scene, &tracer, 0, ray) {
        Ok(point) => point,
        Err(error) => return Outcome::Error(error),
    };
    // The expected colour: raylab's own chapters on the same point. The
    // case's sentence gives the same number by hand.
    let (got, expected) = match shading {
        Shading::Flat => (
            vec![C::shade_flat(&mut tracer, &point)],
            vec![raylab_own(|| {
                Reference::shade_flat(&mut reference_tracer, &point)
            })],
        ),
        Shading::Phong => {
            let got = C::shade_phong(&mut tracer, &point);
            let want = raylab_own(|| Reference::shade_phong(&mut reference_tracer, &point));
            (
                vec![got.diffuse, got.specular],
                vec![want.diffuse, want.specular],
            )
        }
        Shading::Mirror => (
            vec![C::shade_mirror(&mut tracer, &point, depth, 1.0)],
            vec![raylab_own(|| {
                Reference::shade_mirror(&mut reference_tracer, &point, depth, 1.0)
            })],
        ),
        Shading::Glass => (
            vec![C::shade_glass(&mut tracer, &point, depth, 1.0)],
            vec![raylab_own(|| {
                Reference::shade_glass(&mut reference_tracer, &point, depth, 1.0)
            })],
        ),
        Shading::Dielectric => (
            vec![C::shade_dielectric(&mut tracer, &point, depth, 1.0)],
            vec![raylab_own(|| {
                Reference::shade_dielectric(&mut reference_tracer, &point, depth, 1.0)
            })],
        ),
    };
    let pass = got.iter().zip(&expected).all(|(g, w)| colour_close(*g, *w));
    let show = |colours: &[Vec3]| {
        if shading == Shading::Phong {
            format!("diffuse {}, specular {}", vec(colours[0]), vec(colours[1]))
        } else {
            vec(colours[0])
        }
    };
    verdict(pass, show(&expected), show(&got))
}

fn terms_text(terms: &PhongTerms) -> String {
    format!(
        "diffuse {}, specular {}",
        vec(terms.diffuse),
        vec(terms.specular)
    )
}
