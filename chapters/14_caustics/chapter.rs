use raylab::bsdf::{Dispersed, Lobe};
use raylab::course::{Chapters, HitPoint};
use raylab::medium::MediumStack;
use raylab::render::Tracer;
use raylab::scene::Cauchy;
use raylab::spectrum::{rgb_weight, wavelength_of};
use raylab::{Ray, Vec3};

/// From this bounce on a light path may end by Russian roulette, as a
/// camera path does from chapter 13's third.
pub const LIGHT_ROULETTE_FROM_DEPTH: u32 = 3;

/// What one unit of radiance leaving a surface point toward a pinhole
/// camera adds to the pixel that sees it, per unit of the point's area:
/// `cos_surface / (distance^2 pixel_area cos_camera^3)`.
///
/// A pixel is the mean of the radiance over its square of the image. The
/// image plane is at distance 1, where a pixel covers `pixel_area`; seen
/// from the camera, an element `dA` of that plane at angle `theta_c` from
/// the view covers the solid angle `dA cos^3(theta_c)` (distance
/// `1 / cos`, tilted by `cos`), so a pixel's square is the solid angle
/// `pixel_area cos^3`. A surface element `dA_x` at `distance`, turned by
/// `theta_x` from the direction of the camera, covers `dA_x cos(theta_x) /
/// distance^2` of it. The ratio of the two is this weight.
pub fn splat_weight(cos_surface: f32, cos_camera: f32, distance: f32, pixel_area: f32) -> f32 {
    let seen = distance * distance * pixel_area * cos_camera * cos_camera * cos_camera;
    // Behind the camera or 90 degrees off its axis, at its pinhole, or
    // seen edge-on or from behind the surface: no pixel sees it.
    if !(seen > 0.0 && cos_surface > 0.0) {
        return 0.0;
    }
    cos_surface / seen
}

/// Joins `point`, lit by a light path that carries `power` and arrived
/// along `point.ray`, to the camera: the light `lobe` scatters toward the
/// camera lands on the pixel where the camera sees the point, weighted by
/// [`splat_weight`], unless something stands between them.
pub fn connect_to_camera<C: Chapters>(
    tracer: &mut Tracer<C>,
    point: &HitPoint,
    lobe: &Lobe,
    power: Vec3,
) {
    let camera = *tracer.camera();
    let Some((x, y)) = camera.project(point.surface.point) else {
        return;
    };
    // The camera must see the lit side of the surface.
    if !point.faces(camera.origin()) {
        return;
    }
    let to_camera = camera.origin() - point.surface.point;
    let distance = to_camera.length();
    let direction = to_camera / distance;
    let scattered = lobe.value::<C>(point, direction);
    if scattered == Vec3::ZERO || tracer.blocked_from_camera(point) {
        return;
    }
    let weight = C::splat_weight(
        point.normal.dot(direction),
        camera.forward().dot(-direction),
        distance,
        camera.pixel_area(),
    );
    tracer.splat(x, y, power * scattered * weight);
}

/// One path of light from a light (`tracer.emit`), through the mirrors and
/// glass it meets, to every diffuse or glossy point it lights after them:
/// each is joined to the camera ([`connect_to_camera`]), and the path
/// bounces on as a camera path would, its power multiplied by each
/// bounce's `f cos / pdf`, dimmed by absorption, ended by roulette.
///
/// A path whose first point is diffuse or glossy ends there: a camera
/// path finds that light by itself (chapter 13's light samples), and the
/// image must count every path of light once. The renderer keeps the other
/// half of that bargain: a camera path whose first point scatters at
/// random does not count a light it then finds through mirrors and glass
/// only (`Arrival::Caustic`), since light paths bring it.
pub fn trace_light_path<C: Chapters>(tracer: &mut Tracer<C>) {
    let Some(emitted) = tracer.emit() else {
        return;
    };
    let start = emitted.power.max_element();
    let (mut ray, mut power) = (emitted.ray, emitted.power);
    let mut media = MediumStack::EMPTY;
    let mut through_specular = false;
    for depth in 0..tracer.max_depth() {
        let Some(hit) = tracer.trace_light(&media, &ray) else {
            return;
        };
        let point = hit.point;
        let absorption = media.current().absorption;
        if absorption != Vec3::ZERO {
            power *= C::transmittance(absorption, hit.distance);
        }
        let lobe = Lobe::choose(&point, tracer.random());
        if lobe.has_density() {
            if !through_specular {
                return;
            }
            C::connect_to_camera(tracer, &point, &lobe, power);
        } else {
            through_specular = true;
        }
        let Some(scattered) = lobe.scatter::<C>(tracer, &point) else {
            return;
        };
        power *= scattered.weight;
        if depth + 1 >= LIGHT_ROULETTE_FROM_DEPTH {
            match C::russian_roulette(power.max_element() / start, tracer.random()) {
                Some(boost) => power *= boost,
                None => return,
            }
        }
        let direction = scattered.direction;
        ray = Ray::new(tracer.offset_origin(&point.surface, direction), direction);
        media = scattered.media;
    }
}

/// The index of refraction of a glass of Cauchy coefficients `cauchy` at
/// `nanometres`: `a + b / lambda^2`, with `lambda` in micrometres (the
/// unit glass tables quote `b` in).
pub fn cauchy_ior(cauchy: &Cauchy, nanometres: f32) -> f32 {
    let micrometres = nanometres / 1000.0;
    cauchy.a + cauchy.b / (micrometres * micrometres)
}

/// The index a path sees in a dispersive glass, and the colour its light
/// is multiplied by there.
///
/// White light is every wavelength at once, and each bends by its own
/// index. A path follows one direction, so it follows one wavelength: on
/// the first dispersive surface it meets, it draws one, uniform over the
/// visible range, and carries from then on only the light of that
/// wavelength: its colour, [`rgb_weight`], whose mean over the range is
/// white (so the mean over many paths is the light the glass lets
/// through). The wavelength stays the path's until it ends: the same index
/// at every later surface, and no colour again.
pub fn dispersive_ior<C: Chapters>(tracer: &mut Tracer<C>, cauchy: &Cauchy) -> Dispersed {
    if let Some(nanometres) = tracer.wavelength() {
        return Dispersed {
            ior: C::cauchy_ior(cauchy, nanometres),
            tint: Vec3::ONE,
        };
    }
    let nanometres = wavelength_of(tracer.random());
    tracer.set_wavelength(nanometres);
    Dispersed {
        ior: C::cauchy_ior(cauchy, nanometres),
        tint: rgb_weight(nanometres),
    }
}

#[cfg(test)]
mod tests;
