use raylab::course::{Chapters, HitPoint, PhongTerms};
use raylab::render::Tracer;
use raylab::{Material, Vec3};

/// The ambient term: light that arrives "from everywhere", a stand-in for
/// all the light bounced between surfaces that a Whitted tracer does not
/// follow. `albedo * k_a * ambient_light`.
pub fn ambient_term(albedo: Vec3, k_ambient: f32, ambient_light: Vec3) -> Vec3 {
    albedo * k_ambient * ambient_light
}

/// Diffuse and specular light that one point light sends toward the eye.
///
/// `albedo` is the material's colour at this point (its checker pattern
/// applied). All vectors are unit length: `normal` faces the viewer, `to_light` and
/// `to_eye` point away from the surface.
/// - diffuse: `albedo * k_d * max(0, n.l) * light` (Lambert's cosine law)
/// - specular: `k_s * max(0, r.v)^shininess * light`, with `r` the mirror
///   image of `l` about `n`. It is not tinted by the albedo: highlights on
///   plastic are the colour of the light.
///
/// A light behind the surface (`n.l <= 0`) adds nothing, whatever else is
/// given; otherwise NaN or infinite input gives non-finite terms (the
/// renderer counts such samples), never a plausible colour.
pub fn phong_terms(
    material: &Material,
    albedo: Vec3,
    normal: Vec3,
    to_light: Vec3,
    to_eye: Vec3,
    light: Vec3,
) -> PhongTerms {
    let cos_incidence = normal.dot(to_light);
    if cos_incidence <= 0.0 {
        // The light is behind the surface: it lights nothing here.
        return PhongTerms {
            diffuse: Vec3::ZERO,
            specular: Vec3::ZERO,
        };
    }
    let diffuse = albedo * material.diffuse * cos_incidence * light;
    let mirrored_light = 2.0 * cos_incidence * normal - to_light;
    // Clamp negative cosines to 0, but let NaN through: `f32::max` would
    // turn a NaN `to_eye` into 0 and a plausible colour.
    let cos_highlight = mirrored_light.dot(to_eye);
    let cos_highlight = if cos_highlight < 0.0 {
        0.0
    } else {
        cos_highlight
    };
    let specular = material.specular * pow_whole(cos_highlight, material.shininess) * light;
    PhongTerms { diffuse, specular }
}

/// All the light a point sends toward the eye: the ambient term once, then
/// for every light that reaches it (chapter 4's test) the Phong terms of
/// that light, summed.
pub fn shade_phong<C: Chapters>(tracer: &mut Tracer<C>, point: &HitPoint) -> PhongTerms {
    let material = &point.material;
    let mut sum = PhongTerms {
        diffuse: ambient_term(point.albedo, material.ambient, tracer.ambient_light()),
        specular: Vec3::ZERO,
    };
    for light in tracer.lights() {
        if !point.faces(light.position) || C::in_shadow(tracer, point, light.position) {
            continue;
        }
        let to_light = (light.position - point.surface.point).normalize();
        let terms = C::phong_terms(
            material,
            point.albedo,
            point.normal,
            to_light,
            point.to_eye,
            light.radiance(),
        );
        sum.diffuse += terms.diffuse;
        sum.specular += terms.specular;
    }
    sum
}

/// `x^n` by repeated squaring: about `2 log2(n)` multiplications.
///
/// `f32::powf` calls the platform's maths library, whose last bit may
/// differ between machines; a whole exponent and plain multiplications give
/// the same bits everywhere, which keeps the snapshot hashes portable.
pub fn pow_whole(x: f32, n: u32) -> f32 {
    let mut result = 1.0;
    let mut base = x;
    let mut exponent = n;
    while exponent > 0 {
        if exponent & 1 == 1 {
            result *= base;
        }
        base *= base;
        exponent >>= 1;
    }
    result
}

#[cfg(test)]
mod tests;
