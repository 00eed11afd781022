use raylab::course::{Chapters, HitPoint};
use raylab::medium::{Crossing, Medium, MediumStack};
use raylab::render::{RayKind, Tracer};
use raylab::scene::FresnelModel;
use raylab::{Ray, Vec3};

/// The indices, or `None` when one is not a finite number > 0 (then the
/// reflectance is NaN: a loud answer, never a plausible one).
fn indices(n1: f32, n2: f32) -> Option<(f64, f64)> {
    let valid = |n: f32| n > 0.0 && n.is_finite();
    (valid(n1) && valid(n2)).then(|| (f64::from(n1), f64::from(n2)))
}

/// `cos^2` of the transmitted angle by Snell-Descartes, for a ray meeting
/// the surface at cosine `c` from index `n1` into `n2`: negative past the
/// critical angle (total internal reflection).
fn cos2_transmitted(c: f64, n1: f64, n2: f64) -> f64 {
    let eta = n1 / n2;
    // c is an f32, so c * c is exact in f64 (24 + 24 bits < 53): the only
    // roundings are three of f64's, far below the f32 answer's own.
    1.0 - eta * eta * (1.0 - c * c)
}

/// The exact unpolarised Fresnel reflectance: the share of light a smooth
/// boundary between two dielectrics reflects.
///
/// - `cos_i`: cosine of the angle between the incident ray and the normal,
///   in `[0, 1]` (values outside are clamped: 1 is head-on, 0 grazing);
/// - `n1`: index of the medium the ray comes from; `n2`: of the one beyond.
///
/// With `cos t` from Snell-Descartes, the amplitude ratios of the two
/// polarisations are
/// `r_s = (n1 cos i - n2 cos t) / (n1 cos i + n2 cos t)` and
/// `r_p = (n2 cos i - n1 cos t) / (n2 cos i + n1 cos t)`, and unpolarised
/// light reflects `R = (r_s^2 + r_p^2) / 2`. Past the critical angle, and at
/// it, `R = 1` (total internal reflection); at grazing incidence `R = 1`; at
/// normal incidence `R = ((n1 - n2) / (n1 + n2))^2` (0.04 for air and glass).
/// Equal indices are no boundary at all: `R = 0` at every angle. A NaN
/// argument, or an index that is not a finite number > 0, gives NaN.
///
/// Computed in `f64`: near the critical angle `cos t = sqrt(1 - sin^2 t)`
/// subtracts nearly equal numbers, and `R` has a square-root singularity
/// there; in `f64` the answer is the correctly rounded `f32` of the exact
/// value for every input but a few, with no case analysis.
pub fn fresnel(cos_i: f32, n1: f32, n2: f32) -> f32 {
    if cos_i.is_nan() {
        return f32::NAN;
    }
    let Some((n1, n2)) = indices(n1, n2) else {
        return f32::NAN;
    };
    if n1 == n2 {
        return 0.0;
    }
    let c = f64::from(cos_i.clamp(0.0, 1.0));
    let cos2_t = cos2_transmitted(c, n1, n2);
    if cos2_t <= 0.0 {
        return 1.0;
    }
    // Both denominators are > 0: cos t > 0 here, and n1 != n2.
    let cos_t = cos2_t.sqrt();
    let r_s = (n1 * c - n2 * cos_t) / (n1 * c + n2 * cos_t);
    let r_p = (n2 * c - n1 * cos_t) / (n2 * c + n1 * cos_t);
    (0.5 * (r_s * r_s + r_p * r_p)) as f32
}

/// Schlick's approximation of [`fresnel`], same arguments and edge cases:
/// `R = R0 + (1 - R0) (1 - cos)^5` with `R0 = ((n1 - n2) / (n1 + n2))^2`.
///
/// The cosine is that of the angle in the *less dense* medium: `cos_i` when
/// the ray enters a denser one (`n1 < n2`), the transmitted angle's `cos t`
/// when it leaves one, and `R = 1` when there is no transmitted ray (total
/// internal reflection). Using `cos_i` on the way out would miss total
/// internal reflection entirely.
pub fn schlick(cos_i: f32, n1: f32, n2: f32) -> f32 {
    if cos_i.is_nan() {
        return f32::NAN;
    }
    let Some((n1, n2)) = indices(n1, n2) else {
        return f32::NAN;
    };
    if n1 == n2 {
        // (1 - cos)^5 would reflect light at a boundary that is not there.
        return 0.0;
    }
    let c = f64::from(cos_i.clamp(0.0, 1.0));
    let c = if n1 < n2 {
        c
    } else {
        let cos2_t = cos2_transmitted(c, n1, n2);
        if cos2_t <= 0.0 {
            return 1.0;
        }
        cos2_t.sqrt()
    };
    let r0 = ((n1 - n2) / (n1 + n2)).powi(2);
    // Written out: the same multiplications on every platform.
    let m = 1.0 - c;
    let m2 = m * m;
    (r0 + (1.0 - r0) * (m2 * m2 * m)) as f32
}

/// The share of light, per channel, that crosses `distance` of a medium
/// that absorbs `absorption` per unit length: `exp(-absorption distance)`
/// (Beer-Lambert). A channel that does not absorb keeps everything at any
/// distance, even an infinite one (where `0 x inf` would be NaN); one that
/// does keeps nothing of a ray that goes on for ever.
///
/// `libm`'s `expf`, not the platform's: the same bits on every machine, so
/// the reference image is the same everywhere.
pub fn transmittance(absorption: Vec3, distance: f32) -> Vec3 {
    Vec3::from_array(absorption.to_array().map(|a| {
        if a == 0.0 {
            1.0
        } else {
            libm::expf(-a * distance)
        }
    }))
}

/// The media on both sides of the surface at `point`, for a ray that
/// travelled through `media` to reach it.
///
/// Geometry says which side the ray is on: it is entering the solid when it
/// travels against the outward normal (as in chapter 8). The stack says
/// what lies around: entering, the ray comes from the current medium and
/// goes into the solid, which becomes current; leaving, it goes into
/// whatever is current once the solid is removed. So water inside glass is
/// crossed with `n1 / n2 = 1.33 / 1.5`, not `1.33 / 1`. A ray leaving a
/// solid it was never seen entering (a camera under water) was inside it
/// all along. The solid is `point.solid`, not `point.object`: a glass mesh
/// is entered through one triangle and left through another.
pub fn crossing(media: &MediumStack, point: &HitPoint) -> Crossing {
    let solid = Medium {
        object: point.solid,
        ior: point.material.ior,
        absorption: point.material.absorption,
    };
    let entering = point.ray.dir.dot(point.surface.normal) < 0.0;
    let outside = media.leaving(point.solid);
    let (before, beyond) = if entering {
        (outside, outside.entering(solid))
    } else if media.contains(point.solid) {
        (*media, outside)
    } else {
        (media.entering(solid), *media)
    };
    Crossing {
        entering,
        n1: before.current().ior,
        n2: beyond.current().ior,
        before,
        beyond,
    }
}

/// A glass surface done right: its own light, plus the reflected and the
/// transmitted rays, weighted by Fresnel, between the right pair of media,
/// each darkened by what its medium absorbs along the way.
///
/// Of the light arriving, `k_t` (the material's `transparency`) meets the
/// dielectric boundary, which reflects `R` of it and lets `1 - R` through;
/// `k_r` is a mirror coating, reflected at any angle:
///
/// ```text
/// colour = (1 - k_r - k_t) diffuse + specular
///          + (k_r + k_t R)      colour(reflected)   exp(-a_before d_r)
///          + k_t (1 - R) tint   colour(refracted)   exp(-a_beyond d_t)
/// ```
///
/// `R` is [`fresnel`], [`schlick`] or, with `fresnel = "none"`, 0: chapter
/// 8's constants. Under total internal reflection no ray goes through and
/// `R = 1`. The two weights of the boundary, `R` and `1 - R`, add to 1: the
/// boundary moves light, it makes and loses none.
pub fn shade_dielectric<C: Chapters>(
    tracer: &mut Tracer<C>,
    point: &HitPoint,
    depth: u32,
    weight: f32,
) -> Vec3 {
    let local = C::shade_phong(tracer, point);
    let material = point.material;
    let (k_r, k_t) = (material.reflectivity, material.transparency);
    let mut color = (1.0 - k_r - k_t) * local.diffuse + local.specular;
    if depth >= tracer.max_depth() {
        return color;
    }
    let crossing = C::crossing(tracer.media(), point);
    let mut reflected_share = k_r;
    // An opaque surface has no transmitted share to weigh: no Fresnel work.
    let transmits = tracer.worth_casting(weight, k_t);
    let boundary = boundary::<C>(point, transmits.then_some(crossing.n1 / crossing.n2));
    if transmits {
        match boundary.refracted {
            Some(dir) => {
                let cos_i = point.to_eye.dot(boundary.normal);
                let reflectance = match material.fresnel {
                    FresnelModel::None => 0.0,
                    FresnelModel::Schlick => C::schlick(cos_i, crossing.n1, crossing.n2),
                    FresnelModel::Exact => C::fresnel(cos_i, crossing.n1, crossing.n2),
                };
                reflected_share += k_t * reflectance;
                let transmitted_share = k_t * (1.0 - reflectance);
                if tracer.worth_casting(weight, transmitted_share) {
                    let refracted = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
                    let through = seen_through::<C>(
                        tracer,
                        &crossing.beyond,
                        RayKind::Refraction,
                        &refracted,
                        depth + 1,
                        weight * transmitted_share,
                    );
                    color += transmitted_share * material.color * through;
                }
            }
            // Total internal reflection: the glass's share joins the mirror's.
            None => reflected_share += k_t,
        }
    }
    if tracer.worth_casting(weight, reflected_share) {
        let dir = boundary.reflected;
        let reflected = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
        let seen = seen_through::<C>(
            tracer,
            &crossing.before,
            RayKind::Reflection,
            &reflected,
            depth + 1,
            weight * reflected_share,
        );
        color += reflected_share * seen;
    }
    color
}

/// The normal a boundary bends and mirrors light about at one point, and
/// the directions it gives.
struct Boundary {
    /// Unit, on the side the ray came from: the Fresnel cosine is
    /// `to_eye . normal`.
    normal: Vec3,
    reflected: Vec3,
    /// `None` under total internal reflection, or when not asked for.
    refracted: Option<Vec3>,
}

/// The reflected and, when `eta = n1 / n2` is given, the refracted
/// direction of the ray arriving at `point`, both about one normal, the
/// one the Fresnel cosine uses too.
///
/// That normal is the shading normal `point.normal`, as in chapter 6 and
/// as pbrt-v4 computes specular reflection and transmission (sections 9.1
/// and 9.5: in the shading frame): on a smooth mesh (chapter 10) glass then
/// bends light as the curved surface would, not facet by facet. On a plane
/// or a sphere it is the geometric normal turned toward the ray, as before.
///
/// Whether the ray enters or leaves is still the geometric normal's to say
/// (`crossing`, which gave `eta`), and so is which side each new ray must
/// leave on: the reflected one toward the side it came from, the refracted
/// one through to the other. A shading normal tilted far from the facet can
/// face away from the ray, or send one of the two to the wrong side, where
/// it would start on the wrong face of the triangle. Then this point uses
/// the geometric normal for all three (both directions and the cosine),
/// which always gives consistent answers.
fn boundary<C: Chapters>(point: &HitPoint, eta: Option<f32>) -> Boundary {
    let incoming = point.ray.dir;
    let geometric = point.surface.normal;
    // +1 when the ray came from the side the geometric normal points to.
    let eye_side = if incoming.dot(geometric) < 0.0 {
        1.0
    } else {
        -1.0
    };
    let about = |normal: Vec3| Boundary {
        normal,
        reflected: C::reflect(incoming, normal),
        refracted: eta.and_then(|eta| C::refract(incoming, normal, eta)),
    };
    if point.to_eye.dot(point.normal) > 0.0 {
        let shaded = about(point.normal);
        let reflects_back = eye_side * shaded.reflected.dot(geometric) > 0.0;
        let crosses = shaded
            .refracted
            .is_none_or(|dir| eye_side * dir.dot(geometric) < 0.0);
        if reflects_back && crosses {
            return shaded;
        }
    }
    // The geometric normal on the ray's side, by HitPoint's own rule.
    about(if point.to_eye.dot(geometric) >= 0.0 {
        geometric
    } else {
        -geometric
    })
}

/// What `ray` sees, travelling inside `media`, dimmed by the absorption of
/// the medium it crosses over the distance it goes (none where that medium
/// absorbs nothing): the same for the refracted ray and the reflected one.
fn seen_through<C: Chapters>(
    tracer: &mut Tracer<C>,
    media: &MediumStack,
    kind: RayKind,
    ray: &Ray,
    depth: u32,
    weight: f32,
) -> Vec3 {
    let seen = tracer.trace_in(media, kind, ray, depth, weight);
    let absorption = media.current().absorption;
    if absorption == Vec3::ZERO {
        seen.color
    } else {
        seen.color * C::transmittance(absorption, seen.distance)
    }
}

#[cfg(test)]
mod tests;
