use raylab::course::Chapters;
use raylab::shapes::{Bracket, Implicit, NormalMethod};
use raylab::{Ray, Vec3};

/// The nearest `t` with `t_min < t < t_max` where `ray` comes within the
/// march's tolerance of `surface`, found by sphere tracing (Hart, 1996).
///
/// At a point `p`, `|f(p)| / L` is a radius no surface point is inside
/// (`L` bounds how fast `f` changes), so the ray may move that far and
/// still be on the same side. Step by it, `relaxation` times over
/// (Keinert et al., 2014), until the radius is below `tolerance` times the
/// distance travelled: a cone, since a far point needs no more precision
/// than its pixel shows, and since `f` itself is computed with an error
/// that grows with the point's size, an absolute tolerance would never be
/// met far away. When an over-relaxed step leaves a gap (this radius and
/// the last do not overlap: their sum is at most the step, since balls
/// that only touch leave out the point where they touch), a surface may be
/// in it: go back to the last point's safe step and relax no more. Stop after `max_steps`
/// evaluations (a grazing ray may need them all) or past `t_max`.
pub fn sphere_trace(surface: &Implicit, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
    let march = surface.march();
    let lipschitz = surface.lipschitz();
    // t counts lengths of the direction; radii are in the scene's units.
    let speed = ray.dir.length();
    let mut relaxation = march.relaxation;
    let mut t = t_min;
    let mut last: Option<(f32, f32)> = None;
    for _ in 0..march.max_steps {
        let radius = surface.distance(ray.at(t)).abs() / lipschitz;
        if let Some((last_t, last_radius)) = last
            && relaxation > 1.0
            && last_radius + radius <= (t - last_t) * speed
        {
            relaxation = 1.0;
            t = last_t + last_radius / speed;
            last = None;
            continue;
        }
        if !(t < t_max) {
            return None;
        }
        if radius < march.tolerance * t * speed && t > t_min {
            return Some(t);
        }
        // NaN (a broken ray, a degenerate direction) fails every test
        // above and would loop to the budget: stop at once.
        if !radius.is_finite() || !(speed > 0.0) {
            return None;
        }
        last = Some((t, radius));
        t += relaxation * radius / speed;
    }
    None
}

/// A root of `g` inside `bracket`, by Newton's method safeguarded by
/// bisection: `g(t)` returns the value and the slope at `t`.
///
/// Newton's step `t - g / g'` doubles the correct digits near a simple
/// root, but far from one it may jump anywhere (to another root, or off to
/// infinity where the slope is nearly flat). The bracket holds a sign
/// change, so a root: a step that would leave it is replaced by its
/// midpoint, and after every step the half without the sign change is
/// dropped, so the bracket only shrinks. Start at `bracket.low`; stop when
/// a step moves less than `tolerance`, when `g` is exactly zero, or after
/// `max_iterations` steps, and return the last point.
pub fn newton_bracketed(
    g: &dyn Fn(f32) -> (f32, f32),
    bracket: Bracket,
    tolerance: f32,
    max_iterations: u32,
) -> f32 {
    let (mut low, mut high) = (bracket.low, bracket.high);
    let mut t = low;
    let (mut value, mut slope) = g(t);
    let low_positive = value > 0.0;
    for _ in 0..max_iterations {
        if value == 0.0 {
            break;
        }
        let newton = t - value / slope;
        // The ends count as inside: near the root a step smaller than an
        // ulp rounds onto the end just moved there, and bisecting then
        // would throw the converged digits away. A NaN step (zero divided
        // by a flat slope) fails both comparisons, and bisects too.
        let next = if newton >= low && newton <= high {
            newton
        } else {
            0.5 * (low + high)
        };
        let step = next - t;
        t = next;
        (value, slope) = g(t);
        if (value > 0.0) == low_positive {
            low = t;
        } else {
            high = t;
        }
        if step.abs() <= tolerance {
            break;
        }
    }
    t
}

/// The unit normal of `surface` at `point` (on it, or nearly), by the
/// march's method: the analytic gradient, central differences (6
/// evaluations), or the four corners of a tetrahedron (4).
///
/// A central difference `(f(p + h x) - f(p - h x)) / 2h` has an error of
/// order `h^2` from the third derivatives, and a rounding error of order
/// `epsilon |p| / h` from subtracting two nearly equal values (each
/// computed to about `epsilon |p|`): too large an `h` blurs detail, too
/// small a one is noise. Only the direction matters, so the common factor
/// `1 / 2h` is left out. The tetrahedron's corners `k` sum to zero and
/// `sum k k^T = 4 I`, so `sum k f(p + h k)` is `4 h` times the gradient,
/// with 4 evaluations; their third moment does not vanish, so its error is
/// of order `h` times the curvature, one order worse.
pub fn implicit_normal(surface: &Implicit, point: Vec3) -> Vec3 {
    let h = surface.march().normal_step;
    let gradient = match surface.march().normal {
        NormalMethod::Analytic => surface.gradient(point),
        NormalMethod::Central => {
            let along = |axis: Vec3| {
                surface.distance(point + h * axis) - surface.distance(point - h * axis)
            };
            Vec3::new(along(Vec3::X), along(Vec3::Y), along(Vec3::Z))
        }
        NormalMethod::Tetrahedron => [
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(-1.0, -1.0, 1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(1.0, 1.0, 1.0),
        ]
        .into_iter()
        .map(|corner| corner * surface.distance(point + h * corner))
        .sum(),
    };
    // A flat difference (h below the rounding) has no direction: the
    // formulas' gradient is better than none.
    gradient
        .try_normalize()
        .unwrap_or_else(|| surface.gradient(point).normalize_or_zero())
}

/// The nearest `t` with `t_min < t < t_max` where `ray` meets `surface`:
/// sphere tracing to reach it, then Newton's method to pin it down.
///
/// The march need only run where the ray is inside the surface's box
/// ([`Implicit::span`]): a saving, not a rule, since outside it no surface
/// is near. It stops within its cone of the surface, a little before it:
/// where the safe step `|g| / (L |d|)` fell below the cone's width
/// `tolerance t`. Near the root `g` changes at the rate
/// `|grad f| |d| sin a` for a ray that crosses the surface at an angle `a`,
/// so the root is less than `L / (|grad f| sin a)` cone widths on
/// (`1 / sin a` for an exact distance): creep on by cone widths, up to 32
/// of them. The first step where `g(t) = f(o + t d)` changes sign closes
/// the bracket, and Newton (`newton_bracketed` with `g' = grad f . d`, a
/// tolerance of `2 f32::EPSILON high`, two to four ulps of the bracket's
/// high end, and 16 iterations) finds the root. If `|g|` stops shrinking
/// instead, the ray skims the surface without crossing it (a silhouette),
/// or has reached the end of the box: the march's answer stands, as it
/// does after the 32 steps (a crossing shallower than that many cone
/// widths reach).
pub fn intersect_implicit<C: Chapters>(
    surface: &Implicit,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<f32> {
    // Only the part of the ray inside the surface's box can meet it: a
    // ray that misses the box costs no step at all.
    let (enter, leave) = surface.span(ray, t_min, t_max)?;
    let near = C::sphere_trace(surface, ray, enter, leave)?;
    if !surface.march().newton {
        return Some(near);
    }
    let g = |t: f32| {
        let point = ray.at(t);
        (
            surface.distance(point),
            surface.gradient(point).dot(ray.dir),
        )
    };
    let cone = surface.march().tolerance * near;
    let (mut low, mut at_low) = (near, surface.distance(ray.at(near)));
    for _ in 0..BRACKET_STEPS {
        if at_low == 0.0 {
            return Some(low);
        }
        // At the end of the box this is `leave` again, where `|g|` is the
        // same: no longer shrinking, so the search ends below.
        let high = (low + cone).min(leave);
        let at_high = surface.distance(ray.at(high));
        if (at_low > 0.0) != (at_high > 0.0) {
            let bracket = Bracket { low, high };
            let t = C::newton_bracketed(&g, bracket, 2.0 * f32::EPSILON * high, NEWTON_ITERATIONS);
            // Newton stays in the bracket, after the march's point and so
            // after t_min; only t_max can be reached, by a root on it.
            return (t < t_max).then_some(t);
        }
        if !(at_high.abs() < at_low.abs()) {
            break;
        }
        (low, at_low) = (high, at_high);
    }
    Some(near)
}

/// How many cone widths the bracket's search creeps. A ray that crosses
/// the surface at an angle `a` reaches it within `L / (|grad f| sin a)` of
/// them: for an exact distance (`|grad f| = L = 1`) 32 bracket every
/// crossing steeper than 1.8 degrees; under bumps, where `|grad f|` can be
/// `1 - A w` and `L = 1 + A w` (0.28 and 1.72 on the built-in sphere), only
/// those steeper than 11. A shallower crossing keeps the march's answer,
/// within its cone: less precise, never wrong.
const BRACKET_STEPS: u32 = 32;

/// Enough for `f32`: each iteration near a simple root doubles the correct
/// digits, and a bracket of the cone's width needs a handful; bisection
/// steps, where Newton's leave the bracket, halve it 16 times.
const NEWTON_ITERATIONS: u32 = 16;

#[cfg(test)]
mod tests;
