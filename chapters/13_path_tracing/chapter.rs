use std::f32::consts::PI;

pub use raylab::bsdf::{Lobe, Scattered};
use raylab::course::{Chapters, HitPoint};
use raylab::render::{Arrival, Tracer};
use raylab::{Ray, Vec3};

/// From this depth on a path may end by Russian roulette: the first bounces
/// carry most of the light, and ending them would only add noise.
pub const ROULETTE_FROM_DEPTH: u32 = 3;

/// A cosine-distributed direction about the z axis, for `u, v` uniform in
/// `[0, 1)`: Malley's method. A point uniform on the unit disk (radius
/// `sqrt(u)`, angle `2 pi v`) lifted straight up onto the hemisphere has the
/// density `cos(theta) / pi` per unit solid angle.
pub fn cosine_hemisphere(u: f32, v: f32) -> Vec3 {
    let radius = u.sqrt();
    // `libm`'s sine and cosine, not the platform's: the same bits on every
    // machine and in the browser page's WebAssembly.
    let (sin, cos) = libm::sincosf(2.0 * PI * v);
    let (x, y) = (radius * cos, radius * sin);
    Vec3::new(x, y, (1.0 - u).max(0.0).sqrt())
}

/// The density per unit solid angle of [`cosine_hemisphere`]'s direction
/// at angle `theta` from the normal: `cos(theta) / pi`, and 0 below the
/// surface. It integrates to 1 over the hemisphere.
pub fn cosine_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) / PI
}

/// Veach's power heuristic (beta = 2): the weight of a sample drawn with
/// density `pdf` when another strategy could have drawn it with `other`.
/// The two weights of one direction add up to 1; a strategy that cannot
/// draw it (`pdf = 0`) gets 0, and a delta one (infinite) all of it.
pub fn power_heuristic(pdf: f32, other: f32) -> f32 {
    // Divided by the larger density first, so that no square overflows
    // (a light seen edge-on has a density of 1e30) nor both underflow.
    let larger = pdf.max(other);
    if !(larger > 0.0) {
        return 0.0;
    }
    if larger.is_infinite() {
        return if pdf.is_infinite() { 1.0 } else { 0.0 };
    }
    let (mine, theirs) = (pdf / larger, other / larger);
    mine * mine / (mine * mine + theirs * theirs)
}

/// Russian roulette for a path whose share of the pixel is `weight`, `u`
/// uniform in `[0, 1)`: it goes on with probability `q = min(1, weight)`,
/// and a survivor carries `1 / q` times more, so the expected light is
/// unchanged. `Some(1 / q)` when the path survives.
pub fn russian_roulette(weight: f32, u: f32) -> Option<f32> {
    // `f32::min` would take a NaN weight for 1: a NaN path must end.
    if !(weight > 0.0) {
        return None;
    }
    let survival = weight.min(1.0);
    (u < survival).then(|| 1.0 / survival)
}

/// Next-event estimation: the light that reaches `point` straight from a
/// point chosen on a light, and that `lobe` scatters toward the eye.
///
/// One sample of `f(to_light) L cos(theta) / pdf`, where `pdf` is the
/// density of the chosen direction (light choice included). With multiple
/// importance sampling on, an area light's sample is weighed against the
/// chance that the lobe's own scattered ray finds the same direction; a
/// point light can only be found this way, and keeps weight 1.
pub fn next_event<C: Chapters>(tracer: &mut Tracer<C>, point: &HitPoint, lobe: &Lobe) -> Vec3 {
    let Some(light) = tracer.sample_light(point) else {
        return Vec3::ZERO;
    };
    let cosine = point.normal.dot(light.direction);
    // A light behind the lit side shines on nothing here: no ray needed.
    if cosine <= 0.0 || !point.faces(light.position) {
        return Vec3::ZERO;
    }
    let scattered = lobe.value::<C>(point, light.direction);
    if scattered == Vec3::ZERO || C::in_shadow(tracer, point, light.position) {
        return Vec3::ZERO;
    }
    let weight = if light.delta || !tracer.effects().mis {
        1.0
    } else {
        C::power_heuristic(light.pdf, lobe.pdf::<C>(point, light.direction))
    };
    scattered * light.light * (cosine * weight / light.pdf)
}

/// The light leaving `point` toward the eye, by one random path: what the
/// point emits, what a light sample brings (next-event estimation), and
/// what one scattered ray sees, weighted by `f cos / pdf`.
///
/// Each is an unbiased estimate of a term of the rendering equation
///
/// ```text
/// L(x, wo) = Le(x, wo) + integral over wi of f(x, wo, wi) L(x', -wi) cos(theta_i) dwi
/// ```
///
/// `depth` counts the bounces so far and `weight` is the path's share of
/// the pixel, which Russian roulette reads.
pub fn shade_path<C: Chapters>(
    tracer: &mut Tracer<C>,
    point: &HitPoint,
    depth: u32,
    weight: f32,
) -> Vec3 {
    let effects = tracer.effects();
    let mut color = Vec3::ZERO;
    let emission = point.emitted();
    if emission != Vec3::ZERO {
        // With next-event estimation, a light found by a scattered ray was
        // also found by the light sample at the point before: count it once.
        let counted = match tracer.arrival() {
            Arrival::Camera | Arrival::Specular => 1.0,
            Arrival::Scattered { .. } if !effects.next_event => 1.0,
            Arrival::Scattered { pdf } if effects.mis => {
                C::power_heuristic(pdf, tracer.light_pdf(point))
            }
            Arrival::Scattered { .. } => 0.0,
            // A caustic seen on the camera's first point: chapter 14's
            // light paths bring it.
            Arrival::Caustic => 0.0,
        };
        color += counted * emission;
    }
    if depth >= tracer.max_depth() {
        return color;
    }
    let lobe = Lobe::choose(point, tracer.random());
    if effects.next_event && lobe.has_density() {
        color += C::next_event(tracer, point, &lobe);
    }
    let Some(scattered) = lobe.scatter::<C>(tracer, point) else {
        return color;
    };
    let mut throughput = scattered.weight;
    let mut share = weight * throughput.max_element();
    // A black surface (the light's own) sends nothing on: no ray to cast.
    if !(share > 0.0) {
        return color;
    }
    if effects.roulette && depth + 1 >= ROULETTE_FROM_DEPTH && lobe.has_density() {
        match C::russian_roulette(share, tracer.random()) {
            Some(boost) => {
                throughput *= boost;
                share *= boost;
            }
            None => return color,
        }
    }
    let dir = scattered.direction;
    let ray = Ray::new(tracer.offset_origin(&point.surface, dir), dir);
    let seen = tracer.trace_path(
        &scattered.media,
        scattered.kind,
        &ray,
        depth + 1,
        share,
        scattered.arrival,
    );
    // Light crossing an absorbing medium on its way here (chapter 9).
    let absorption = scattered.media.current().absorption;
    let kept = if absorption == Vec3::ZERO {
        Vec3::ONE
    } else {
        C::transmittance(absorption, seen.distance)
    };
    color + throughput * kept * seen.color
}

#[cfg(test)]
mod tests;
