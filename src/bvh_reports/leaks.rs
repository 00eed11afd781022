//! Rays that slip through a closed mesh: what chapter 10's watertight
//! triangle test buys, counted.
//!
//! From a point inside a closed mesh every ray must hit it. The rays most
//! likely not to are those through an edge or a vertex, where two or more
//! triangles each decide by their own rounding whether the ray is theirs:
//! [`leak_targets`] aims one ray at every vertex and at the midpoint of
//! every edge (rounded to `f32`, so within an ulp or so of the edge), and
//! [`count_leaks`] counts those that hit nothing.
//!
//! The model is raylab's generated lumpy torus (`raylab mesh`), a tube
//! around the circle of radius 1 in the plane y = 0: each ray starts on
//! that circle, inside the tube, at the angle of its target, so it leaves
//! the tube through its target.

use std::collections::BTreeSet;
use std::time::Instant;

use crate::course::Objects;
use crate::mesh::Mesh;
use crate::scene::TriangleTest;
use crate::shapes::{Shape, Triangle};
use crate::{Chapters, Ray, Vec3};

/// The model sizes `raylab cost --chapter 10` counts leaks on.
pub const LEAK_MESH_SIZES: [usize; 2] = [1_000, 10_000];

/// One test's count on one model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeakCount {
    pub test: TriangleTest,
    pub triangles: usize,
    pub rays: usize,
    /// Rays that hit no triangle.
    pub escaped: usize,
    /// Median wall time to find every ray's nearest hit by testing every
    /// triangle (one thread), in seconds.
    pub seconds: f64,
}

/// The mesh's triangles as shapes.
pub fn triangles(mesh: &Mesh) -> Vec<Shape> {
    mesh.triangles
        .iter()
        .map(|corners| {
            let [a, b, c] = corners.map(|index| mesh.positions[index as usize]);
            Triangle::new(a, b, c).into()
        })
        .collect()
}

/// Every vertex of `mesh`, and the midpoint of every edge, each once.
pub fn leak_targets(mesh: &Mesh) -> Vec<Vec3> {
    let mut edges = BTreeSet::new();
    for &[a, b, c] in &mesh.triangles {
        for (p, q) in [(a, b), (b, c), (c, a)] {
            edges.insert((p.min(q), p.max(q)));
        }
    }
    let midpoints = edges
        .into_iter()
        .map(|(p, q)| 0.5 * (mesh.positions[p as usize] + mesh.positions[q as usize]));
    mesh.positions.iter().copied().chain(midpoints).collect()
}

/// The point of the generated torus's core circle (radius 1, y = 0) at
/// the angle of `target` around the y axis: inside the tube, under it.
pub fn core_point(target: Vec3) -> Vec3 {
    Vec3::new(target.x, 0.0, target.z).normalize_or(Vec3::X)
}

/// Casts a ray from `inside(target)` toward each of `targets` against
/// `shapes` with the chapters `C`, and counts the rays that hit nothing;
/// times `repeats` passes and keeps the median.
pub fn count_leaks<C: Chapters>(
    shapes: &[Shape],
    inside: impl Fn(Vec3) -> Vec3,
    targets: &[Vec3],
    repeats: u32,
) -> (usize, f64) {
    let objects = Objects::<C>::new(shapes);
    let mut escaped = 0;
    let mut times = Vec::new();
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        escaped = targets
            .iter()
            .filter(|&&target| {
                let origin = inside(target);
                let ray = Ray::new(origin, target - origin);
                C::nearest_hit(&objects, &ray, 0.0, f32::INFINITY).is_none()
            })
            .count();
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    (escaped, times[times.len() / 2])
}

/// [`count_leaks`] for both triangle tests on raylab's generated closed
/// model of about `size` triangles, from its core circle.
pub fn leaks_of_both_tests<C: Chapters>(
    size: usize,
    repeats: u32,
) -> Result<[LeakCount; 2], crate::mesh::MeshError> {
    use crate::course::Textbook;
    let mesh = crate::mesh::generate_closed_mesh(size)?;
    let shapes = triangles(&mesh);
    let targets = leak_targets(&mesh);
    let count = |test, (escaped, seconds)| LeakCount {
        test,
        triangles: shapes.len(),
        rays: targets.len(),
        escaped,
        seconds,
    };
    Ok([
        count(
            TriangleTest::MollerTrumbore,
            count_leaks::<Textbook<C, false, true>>(&shapes, core_point, &targets, repeats),
        ),
        count(
            TriangleTest::Watertight,
            count_leaks::<C>(&shapes, core_point, &targets, repeats),
        ),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Reference;

    /// The watertight test loses no ray on the small model, and the count
    /// is not vacuous: every target is tested, and a ray aimed away from
    /// the model (from outside it) is counted as escaped.
    #[test]
    fn watertight_loses_nothing_and_escapes_are_counted() {
        let [moller_trumbore, watertight] =
            leaks_of_both_tests::<Reference>(1_000, 1).expect("the generated model");
        assert_eq!(watertight.escaped, 0);
        assert_eq!(watertight.rays, moller_trumbore.rays);
        assert!(watertight.rays > watertight.triangles, "{watertight:?}");
        let mesh = crate::mesh::generate_closed_mesh(1_000).expect("model");
        let shapes = triangles(&mesh);
        let outside = |_: Vec3| Vec3::new(0.0, 10.0, 0.0);
        let away = [Vec3::new(0.0, 20.0, 0.0)];
        assert_eq!(count_leaks::<Reference>(&shapes, outside, &away, 1).0, 1);
    }
}
