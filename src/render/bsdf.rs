//! How a surface scatters light, for chapter 13's paths: the lobes of a
//! material (Lambert's diffuse reflection, a glossy or perfect mirror,
//! chapter 9's glass), each with its value `f`, its density and one random
//! direction drawn from it. The chapter's `shade_path` and `next_event`
//! use them; the directions of the diffuse lobe come from the chapter's
//! own `cosine_hemisphere` and `cosine_pdf`.

use std::f32::consts::PI;

use crate::Vec3;
use crate::course::{Chapters, HitPoint};
use crate::medium::MediumStack;
use crate::render::{Arrival, RayKind, Tracer};
use crate::scene::{FresnelModel, Material};

pub use crate::seam::{Dispersed, Lobe};

/// One direction a lobe scattered into, and what it is worth.
#[derive(Debug, Clone, Copy)]
pub struct Scattered {
    pub direction: Vec3,
    /// `f cos / pdf`: what the light seen along `direction` is multiplied by.
    pub weight: Vec3,
    pub kind: RayKind,
    pub arrival: Arrival,
    /// The media the scattered ray travels through.
    pub media: MediumStack,
}

/// The Phong exponent of a rough mirror: `2 / r^2 - 2`, so roughness 1 is
/// the widest lobe (exponent 0).
///
/// The formula is Walter et al.'s match (2007, section 5.2) between two
/// distributions of microfacet normals, a Phong one `cos^n` of a facet's
/// tilt from the normal and a Beckmann one of width `r`. The lobe here is a
/// power of the cosine of the angle to the mirror direction instead, and
/// that angle is about twice a facet's tilt: `cos^n(2 t)` falls as
/// `exp(-2 n t^2)`, `cos^n(t)` as `exp(-n t^2 / 2)`. So the lobe that
/// matches a Beckmann surface of roughness `r` has about a quarter of this
/// exponent, and this one is about half as wide: read `roughness` as a name
/// for the exponent, not as Beckmann's width (the Veach plates are about
/// twice as sharp as their roughness says).
pub fn phong_exponent(roughness: f32) -> f32 {
    (2.0 / (roughness * roughness) - 2.0).max(0.0)
}

impl Lobe {
    /// The lobe of `point`'s material for `u` uniform in `[0, 1)`.
    pub fn choose(point: &HitPoint, u: f32) -> Lobe {
        let material = point.material;
        let albedo = point.albedo;
        if u < material.transparency {
            Lobe::Glass
        } else if u < material.transparency + material.reflectivity {
            if material.roughness > 0.0 {
                Lobe::Glossy {
                    albedo,
                    exponent: phong_exponent(material.roughness),
                }
            } else {
                Lobe::Mirror { albedo }
            }
        } else {
            Lobe::Diffuse { albedo }
        }
    }

    /// Whether the lobe spreads light over a range of directions (a light
    /// sample can then land in it), rather than into one direction.
    pub fn has_density(&self) -> bool {
        matches!(self, Lobe::Diffuse { .. } | Lobe::Glossy { .. })
    }

    /// `f(wo, wi)`: the share of light arriving along `to_light` that
    /// leaves toward the eye, per unit solid angle and projected area. A
    /// glossy lobe is centred on the mirror direction of `C`'s chapter 6.
    pub fn value<C: Chapters>(&self, point: &HitPoint, to_light: Vec3) -> Vec3 {
        if point.normal.dot(to_light) <= 0.0 {
            return Vec3::ZERO;
        }
        match *self {
            Lobe::Diffuse { albedo } => albedo / PI,
            // `libm`'s powers and sines throughout, not the platform's: the
            // same bits on every machine and in the browser page.
            Lobe::Glossy { albedo, exponent } => {
                let cos_alpha = mirrored::<C>(point).dot(to_light).max(0.0);
                albedo * ((exponent + 2.0) / (2.0 * PI) * libm::powf(cos_alpha, exponent))
            }
            Lobe::Mirror { .. } | Lobe::Glass => Vec3::ZERO,
        }
    }

    /// The density per unit solid angle with which [`Lobe::scatter`]
    /// chooses `direction`: 0 for the lobes of one direction.
    pub fn pdf<C: Chapters>(&self, point: &HitPoint, direction: Vec3) -> f32 {
        match *self {
            Lobe::Diffuse { .. } => C::cosine_pdf(point.normal.dot(direction)),
            Lobe::Glossy { exponent, .. } => {
                let cos_alpha = mirrored::<C>(point).dot(direction).max(0.0);
                (exponent + 1.0) / (2.0 * PI) * libm::powf(cos_alpha, exponent)
            }
            Lobe::Mirror { .. } | Lobe::Glass => 0.0,
        }
    }

    /// One direction drawn from the lobe, with its weight `f cos / pdf`;
    /// `None` when the draw leaves below the surface (the light is
    /// absorbed).
    pub fn scatter<C: Chapters>(
        &self,
        tracer: &mut Tracer<C>,
        point: &HitPoint,
    ) -> Option<Scattered> {
        let media = *tracer.media();
        let bounce = |direction: Vec3, weight: Vec3, pdf: f32| Scattered {
            direction,
            weight,
            kind: RayKind::Bounce,
            arrival: Arrival::Scattered { pdf },
            media,
        };
        match *self {
            Lobe::Diffuse { albedo } => {
                let local = C::cosine_hemisphere(tracer.random(), tracer.random());
                let direction = to_world(point.normal, local);
                let pdf = C::cosine_pdf(point.normal.dot(direction));
                if !(pdf > 0.0) {
                    return None;
                }
                let cosine = point.normal.dot(direction);
                Some(bounce(direction, albedo / PI * (cosine / pdf), pdf))
            }
            Lobe::Glossy { exponent, .. } => {
                // cos(alpha) = u^(1 / (n + 1)) has the density of cos^n.
                let cos_alpha = libm::powf(tracer.random(), 1.0 / (exponent + 1.0));
                let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
                let (sin, cos) = libm::sincosf(2.0 * PI * tracer.random());
                let local = Vec3::new(sin_alpha * cos, sin_alpha * sin, cos_alpha);
                let direction = to_world(mirrored::<C>(point), local);
                let cosine = point.normal.dot(direction);
                let pdf = self.pdf::<C>(point, direction);
                if cosine <= 0.0 || !(pdf > 0.0) {
                    return None;
                }
                Some(bounce(
                    direction,
                    self.value::<C>(point, direction) * (cosine / pdf),
                    pdf,
                ))
            }
            Lobe::Mirror { albedo } => Some(Scattered {
                direction: mirrored::<C>(point),
                weight: albedo,
                kind: RayKind::Reflection,
                arrival: Arrival::Specular,
                media,
            }),
            Lobe::Glass => Some(through_glass::<C>(tracer, point)),
        }
    }
}

/// The mirror direction of the ray arriving at `point`, by `C`'s chapter
/// 6: never raylab's own, which would make these public methods a way to
/// its answer.
fn mirrored<C: Chapters>(point: &HitPoint) -> Vec3 {
    C::reflect(point.ray.dir.normalize(), point.normal)
}

/// Chapter 9's boundary as a choice: reflected with probability `R`
/// (Fresnel's reflectance), refracted otherwise, so each ray carries its
/// whole weight and the expected light is chapter 9's mix. A dispersive
/// glass (chapter 14) has the index of the path's wavelength, on both
/// sides of every crossing: the solids a ray is inside keep the index they
/// were entered with.
fn through_glass<C: Chapters>(tracer: &mut Tracer<C>, point: &HitPoint) -> Scattered {
    let dispersed = match point.material.cauchy {
        Some(cauchy) if tracer.effects().dispersion => Some(C::dispersive_ior(tracer, &cauchy)),
        _ => None,
    };
    let material;
    let point = match dispersed {
        Some(dispersed) => {
            material = Material {
                ior: dispersed.ior,
                ..*point.material
            };
            &point.with_material(&material)
        }
        None => point,
    };
    let tint = dispersed.map_or(Vec3::ONE, |dispersed| dispersed.tint);
    let crossing = C::crossing(tracer.media(), point);
    let incoming = point.ray.dir.normalize();
    let refracted = C::refract(incoming, point.normal, crossing.n1 / crossing.n2);
    let cos_i = point.to_eye.dot(point.normal);
    let reflectance = match (refracted, point.material.fresnel) {
        (None, _) => 1.0,
        (Some(_), FresnelModel::Schlick) => C::schlick(cos_i, crossing.n1, crossing.n2),
        (Some(_), FresnelModel::Exact | FresnelModel::None) => {
            C::fresnel(cos_i, crossing.n1, crossing.n2)
        }
    };
    // Radiance crossing into a denser medium is squeezed into a narrower
    // cone: `L / n^2` is what a lossless crossing keeps (the radiance
    // theorem), so the light a camera path sees through a crossing from
    // `n1` (its side) into `n2` is `(n1 / n2)^2` of what arrives. A light
    // path carries power, which a crossing keeps whole (Veach's thesis,
    // section 5.2; pbrt-v4's `TransportMode`). Through a closed solid the
    // two crossings cancel, but not for a light inside glass.
    let squeeze = if tracer.from_light() {
        1.0
    } else {
        let ratio = crossing.n1 / crossing.n2;
        ratio * ratio
    };
    match refracted {
        Some(direction) if tracer.random() >= reflectance => Scattered {
            direction,
            weight: point.material.color * tint * squeeze,
            kind: RayKind::Refraction,
            arrival: Arrival::Specular,
            media: crossing.beyond,
        },
        _ => Scattered {
            direction: C::reflect(incoming, point.normal),
            weight: tint,
            kind: RayKind::Reflection,
            arrival: Arrival::Specular,
            media: crossing.before,
        },
    }
}

/// `local` (z along `normal`) in world coordinates, by the branchless
/// orthonormal basis of Duff et al. (JCGT 2017), exact for any unit normal.
pub fn to_world(normal: Vec3, local: Vec3) -> Vec3 {
    let sign = 1.0_f32.copysign(normal.z);
    let a = -1.0 / (sign + normal.z);
    let b = normal.x * normal.y * a;
    let tangent = Vec3::new(
        1.0 + sign * normal.x * normal.x * a,
        sign * b,
        -sign * normal.x,
    );
    let bitangent = Vec3::new(b, sign + normal.y * normal.y * a, -normal.y);
    local.x * tangent + local.y * bitangent + local.z * normal
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::{Plane, Shape};
    use crate::{Ray, Reference};

    /// Chapters whose chapter 6 mirrors every ray straight up.
    struct StraightUp;
    impl Chapters for StraightUp {
        fn reflect(_d: Vec3, _n: Vec3) -> Vec3 {
            Vec3::Y
        }
    }

    /// A glossy lobe is centred on the mirror direction of the chapters
    /// asked, never on raylab's own: its public methods are then no way to
    /// raylab's chapter 6 answer.
    #[test]
    fn a_glossy_lobe_is_centred_on_the_chapters_own_mirror_direction() {
        let floor = Shape::Plane(Plane::new(Vec3::ZERO, Vec3::Y));
        let material = Material::default();
        let ray = Ray::new(Vec3::new(-1.0, 1.0, 0.0), Vec3::new(1.0, -1.0, 0.0));
        let point = HitPoint::new(0, &floor, &material, &ray, 1.0);
        let lobe = Lobe::Glossy {
            albedo: Vec3::ONE,
            exponent: 200.0,
        };
        let mirror = Vec3::new(1.0, 1.0, 0.0).normalize();
        let peak = |value: Vec3| value.x > 1.0;
        assert!(peak(lobe.value::<Reference>(&point, mirror)));
        assert!(!peak(lobe.value::<StraightUp>(&point, mirror)));
        assert!(peak(lobe.value::<StraightUp>(&point, Vec3::Y)));
        assert!(lobe.pdf::<StraightUp>(&point, mirror) < lobe.pdf::<StraightUp>(&point, Vec3::Y));
    }
}
