use raylab::course::{Chapters, HitPoint};
use raylab::shapes::Triangle;
use raylab::{Ray, Vec3};

/// The nearest `t` with `t_min < t < t_max` where `ray` meets `triangle`:
/// the watertight test of Woop, Benthin and Wald (2013).
///
/// Move and shear space so that the ray starts at the origin and runs along
/// +z. Then the question is two-dimensional: does the origin of the (x, y)
/// plane lie inside the triangle's shadow on it? Each edge answers with the
/// sign of a 2D cross product (an *edge function*). Two triangles that share
/// an edge compute that edge's function from the same two sheared corners,
/// in the opposite order, so they get exactly opposite values: one of them
/// always claims a ray through the edge (both do when it is exactly zero),
/// and no ray slips between them. That is the whole point of the order of
/// the operations below.
pub fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
    // Coordinates are picked by an axis chosen at run time; indexing a
    // plain array is one load, while indexing a `Vec3` (`dir[z]`) is a
    // three-way `match` each time, and this test is run for every
    // triangle a ray reaches. The arithmetic below is the same either way.
    let dir = ray.dir.to_array();
    // z is the axis the ray moves fastest along, so dividing by it is safe;
    // x and y follow cyclically, swapped when dir.z < 0 to keep the winding.
    let z = ray.dir.abs().max_position();
    let (mut x, mut y) = ((z + 1) % 3, (z + 2) % 3);
    if dir[z] < 0.0 {
        std::mem::swap(&mut x, &mut y);
    }
    let shear_x = dir[x] / dir[z];
    let shear_y = dir[y] / dir[z];
    let scale_z = 1.0 / dir[z];

    // The corners relative to the ray's origin, sheared so the ray is +z.
    let [a, b, c] = triangle
        .corners()
        .map(|corner| (corner - ray.origin).to_array());
    let sheared = |p: [f32; 3]| (p[x] - shear_x * p[z], p[y] - shear_y * p[z]);
    let (ax, ay) = sheared(a);
    let (bx, by) = sheared(b);
    let (cx, cy) = sheared(c);

    // Twice the signed areas of the three sub-triangles the ray's point
    // makes with each edge: the unnormalised barycentric coordinates.
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    // A zero may be a rounded tiny value of either sign: recompute all three
    // in f64 (exact for products of f32s) so the sign is the true one.
    if u == 0.0 || v == 0.0 || w == 0.0 {
        let cross = |px: f32, py: f32, qx: f32, qy: f32| {
            (f64::from(px) * f64::from(qy) - f64::from(py) * f64::from(qx)) as f32
        };
        u = cross(cx, cy, bx, by);
        v = cross(ax, ay, cx, cy);
        w = cross(bx, by, ax, ay);
    }
    // Inside means all three on the same side; a triangle hit from behind
    // has all three negative. Mixed signs: outside. (NaN fails both tests
    // below only by reaching `determinant`, which is then NaN.)
    let outside = (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0);
    if outside {
        return None;
    }
    let determinant = u + v + w;
    if !(determinant != 0.0) {
        // Edge-on triangle (or degenerate, or NaN): nothing to hit.
        return None;
    }
    // The heights of the corners along the ray, interpolated with the same
    // weights, give t times the determinant.
    let (az, bz, cz) = (scale_z * a[z], scale_z * b[z], scale_z * c[z]);
    let t = (u * az + v * bz + w * cz) / determinant;
    (t > t_min && t < t_max).then_some(t)
}

/// The same question by Moller and Trumbore (1997), the test most courses
/// teach: solve `origin + t dir = a + beta (b - a) + gamma (c - a)` by
/// Cramer's rule. Fast and short, but each triangle tests its edges with
/// its own rounding (`beta >= 0` on one side, `beta + gamma <= 1` on the
/// other), so a ray through a shared edge can fail both. Kept to show the
/// cracks (`raylab cost --chapter 10` counts them).
pub fn intersect_triangle_moller_trumbore(
    triangle: &Triangle,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<f32> {
    let [a, b, c] = triangle.corners();
    let edge_1 = b - a;
    let edge_2 = c - a;
    let p = ray.dir.cross(edge_2);
    let determinant = edge_1.dot(p);
    if !(determinant != 0.0) {
        return None;
    }
    let inverse = 1.0 / determinant;
    let s = ray.origin - a;
    let beta = s.dot(p) * inverse;
    if !(0.0..=1.0).contains(&beta) {
        return None;
    }
    let q = s.cross(edge_1);
    let gamma = ray.dir.dot(q) * inverse;
    if !(gamma >= 0.0 && beta + gamma <= 1.0) {
        return None;
    }
    let t = edge_2.dot(q) * inverse;
    (t > t_min && t < t_max).then_some(t)
}

/// The barycentric coordinates `(alpha, beta, gamma)` of `point` (on the
/// triangle's plane): the weights with `point = alpha a + beta b + gamma c`
/// and `alpha + beta + gamma = 1`.
///
/// Write `point - a = beta (b - a) + gamma (c - a)` and dot it with both
/// edges: two equations in two unknowns, solved by Cramer's rule. The
/// denominator is `|e1|^2 |e2|^2 - (e1.e2)^2 = |e1 x e2|^2`, zero only for
/// a degenerate triangle, which no ray hits.
pub fn barycentric(triangle: &Triangle, point: Vec3) -> Vec3 {
    let [a, b, c] = triangle.corners();
    let (edge_1, edge_2, to_point) = (b - a, c - a, point - a);
    let (d11, d12, d22) = (edge_1.dot(edge_1), edge_1.dot(edge_2), edge_2.dot(edge_2));
    let (p1, p2) = (to_point.dot(edge_1), to_point.dot(edge_2));
    let denominator = d11 * d22 - d12 * d12;
    let beta = (d22 * p1 - d12 * p2) / denominator;
    let gamma = (d11 * p2 - d12 * p1) / denominator;
    Vec3::new(1.0 - beta - gamma, beta, gamma)
}

/// The shading normal of a smooth mesh at `point`: the vertex normals
/// `normals` blended with the point's barycentric weights, made unit again
/// (a blend of unit vectors is shorter than 1 between them). Light then
/// varies smoothly across the edges where the flat normals jump.
pub fn smooth_normal(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3) -> Vec3 {
    let weights = barycentric(triangle, point);
    let blended = weights.x * normals[0] + weights.y * normals[1] + weights.z * normals[2];
    blended.normalize_or(triangle.geometric_normal())
}

/// Where the shadow rays of a smooth triangle start, so that the shadow
/// terminator does not show the mesh's facets (Hanika, 2021).
///
/// A smooth normal pretends the surface is curved, but the shadow ray still
/// leaves from the flat triangle, which near the terminator lies *below*
/// the curved surface it stands for: its neighbours block the light and a
/// staircase of facet-shaped shadows appears where the smooth shading says
/// "lit". The fix lifts the point onto the curved surface the normals
/// describe: for each corner, the plane through it perpendicular to its
/// normal; where the point lies below that plane, project it up onto it;
/// blend the three results with the barycentric weights. On a convex part
/// this moves the point out; where the point is already above every
/// tangent plane (a concave part) it stays where it is. `normals` must face
/// the side the ray arrived on.
pub fn terminator_point(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3) -> Vec3 {
    let weights = barycentric(triangle, point);
    let corners = triangle.corners();
    let mut lifted = point;
    for ((corner, normal), weight) in corners.iter().zip(normals).zip(weights.to_array()) {
        let height = (point - *corner).dot(*normal);
        if height < 0.0 {
            lifted -= weight * height * *normal;
        }
    }
    if lifted.is_finite() { lifted } else { point }
}

/// The hit point `point` on a smooth triangle, as it is shaded: the
/// blended normal in place of the flat one, and the point lifted off the
/// terminator for the rays that leave it.
///
/// The vertex normals say where "out" is for the mesh; they are turned to
/// the side the ray arrived on, as [`HitPoint::normal`] is. A transparent
/// surface keeps its point: its refracted ray goes *into* the mesh, and
/// starting it above the surface would make it hit the same triangle again.
pub fn smooth_hit_point<'a, C: Chapters>(
    point: HitPoint<'a>,
    triangle: &Triangle,
    normals: &[Vec3; 3],
) -> HitPoint<'a> {
    let outward = normals[0] + normals[1] + normals[2];
    let side = if outward.dot(point.normal) < 0.0 {
        -1.0
    } else {
        1.0
    };
    let oriented = normals.map(|normal| side * normal);
    let mut smooth = point;
    smooth.normal = C::smooth_normal(triangle, &oriented, point.surface.point);
    if point.material.transparency == 0.0 {
        smooth.surface.point = C::terminator_point(triangle, &oriented, point.surface.point);
    }
    smooth
}

#[cfg(test)]
mod tests;
