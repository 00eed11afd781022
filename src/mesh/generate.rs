//! A closed test model of any size: a lumpy torus.
//!
//! A torus is a grid of `ring` x `tube` quads that wraps around in both
//! directions, so it is closed (every edge is shared by exactly two
//! triangles, with opposite directions) for any grid of at least 3 x 3, and
//! its triangle count, `2 x ring x tube`, can be brought within a fraction
//! of a percent of any requested count. (A subdivided icosahedron only
//! comes in steps of 4x.) Its hole and the lumps make the model shadow and
//! reflect itself, as a real model does.

use std::f64::consts::TAU;

use super::{Mesh, MeshError};
use crate::Vec3;

/// The most triangles [`generate_closed_mesh`] is asked for (16 million:
/// about 580 MB of mesh in memory, and an OBJ file over 1 GB, far past
/// what [`super::load_obj`] reads back, [`super::MAX_MESH_TRIANGLES`]).
pub const MAX_GENERATED_TRIANGLES: usize = 16_000_000;

/// The distance from the torus's centre to the middle of its tube.
const RING_RADIUS: f64 = 1.0;
/// The tube's radius before the lumps, which change it by at most 20%:
/// the tube never reaches the centre (0.48 < 1), so the surface never
/// meets itself.
const TUBE_RADIUS: f64 = 0.4;

/// The grid for about `triangles` triangles: `(ring, tube)` quads around
/// the ring and around the tube.
///
/// The rule: `tube = max(3, floor(sqrt(N / 5)))` and
/// `ring = max(3, ceil(N / (2 tube)))`, so the ring has about 2.5 times as
/// many quads as the tube is around (the ring is 2.5 times as long), the
/// count `2 x ring x tube` is at least N, and over by less than `2 x tube`.
/// N = 1,000 gives 1,008 triangles; 10,000 gives 10,032; 100,000 gives
/// 100,110; 1,000,000 gives 1,000,386; anything up to 18 gives 18.
fn grid(triangles: usize) -> Result<(usize, usize), MeshError> {
    if triangles == 0 || triangles > MAX_GENERATED_TRIANGLES {
        return Err(MeshError::TriangleCount {
            requested: triangles,
        });
    }
    let tube = (triangles / 5).isqrt().max(3);
    let ring = triangles.div_ceil(2 * tube).max(3);
    Ok((ring, tube))
}

/// The number of triangles [`generate_closed_mesh`] gives for a request
/// of `triangles` (see the rule there), without building the mesh.
pub fn closed_mesh_triangle_count(triangles: usize) -> Result<usize, MeshError> {
    let (ring, tube) = grid(triangles)?;
    Ok(2 * ring * tube)
}

/// A closed, consistently wound model of about `triangles` triangles,
/// from 1 to [`MAX_GENERATED_TRIANGLES`]: a torus of radius 1 around the Y
/// axis, its tube (radius 0.4) made lumpy by a fixed sum of sines.
///
/// The count is `2 x ring x tube` for a grid chosen so that it is at least
/// `triangles` and close to it: 1,000 gives 1,008, 10,000 gives 10,032,
/// 100,000 gives 100,110, 1,000,000 gives 1,000,386 (at most 18 gives 18,
/// the smallest closed grid). Every edge is shared by exactly two
/// triangles, each wound counter-clockwise seen from outside. Vertex
/// normals are the area-weighted average of the triangles around each
/// vertex, for smooth shading.
///
/// The result depends on `triangles` only, bit for bit, on every machine:
/// the sines come from `libm`, not the platform's maths library.
pub fn generate_closed_mesh(triangles: usize) -> Result<Mesh, MeshError> {
    let (ring, tube) = grid(triangles)?;
    let vertex = |i: usize, j: usize| ((i % ring) * tube + (j % tube)) as u32;
    let mut positions = Vec::with_capacity(ring * tube);
    for i in 0..ring {
        let u = TAU * i as f64 / ring as f64;
        for j in 0..tube {
            let v = TAU * j as f64 / tube as f64;
            // Whole-number frequencies, so the lumps join up where the grid
            // wraps around.
            let lumps = 1.0
                + 0.15 * libm::sin(3.0 * u) * libm::sin(2.0 * v)
                + 0.05 * libm::sin(7.0 * u + 5.0 * v);
            let r = TUBE_RADIUS * lumps;
            let across = RING_RADIUS + r * libm::cos(v);
            positions.push(Vec3::new(
                (across * libm::cos(u)) as f32,
                (r * libm::sin(v)) as f32,
                (across * libm::sin(u)) as f32,
            ));
        }
    }
    let mut faces = Vec::with_capacity(2 * ring * tube);
    for i in 0..ring {
        for j in 0..tube {
            let (a, b, c, d) = (
                vertex(i, j),
                vertex(i + 1, j),
                vertex(i + 1, j + 1),
                vertex(i, j + 1),
            );
            // Going around the tube (j) then along the ring (i) turns
            // counter-clockwise seen from outside (checked by a test: the
            // enclosed volume is positive).
            faces.push([a, d, c]);
            faces.push([a, c, b]);
        }
    }
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for face in &faces {
        let [a, b, c] = face.map(|k| positions[k as usize]);
        // Unnormalised: its length is twice the area, so larger triangles
        // weigh more.
        let n = (b - a).cross(c - a);
        for &k in face {
            normals[k as usize] += n;
        }
    }
    for n in &mut normals {
        *n = n.normalize_or_zero();
    }
    Ok(Mesh {
        positions,
        normals,
        triangle_normals: Some(faces.clone()),
        triangles: faces,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    #[test]
    fn the_counts_are_the_documented_ones() {
        let counts: Vec<usize> = [
            1,
            18,
            19,
            1_000,
            10_000,
            100_000,
            1_000_000,
            MAX_GENERATED_TRIANGLES,
        ]
        .into_iter()
        .map(|n| closed_mesh_triangle_count(n).expect("in range"))
        .collect();
        assert_eq!(counts[..7], [18, 18, 24, 1_008, 10_032, 100_110, 1_000_386]);
        for n in [
            1,
            2,
            17,
            18,
            19,
            999,
            1_000,
            12_345,
            999_999,
            4_000_000,
            MAX_GENERATED_TRIANGLES,
        ] {
            let count = closed_mesh_triangle_count(n).expect("in range");
            assert!(
                count >= n && count < n + 2 * (n / 5).isqrt().max(3) + 18,
                "{n} -> {count}"
            );
        }
        assert!(closed_mesh_triangle_count(0).is_err());
        assert!(closed_mesh_triangle_count(MAX_GENERATED_TRIANGLES + 1).is_err());
        assert!(generate_closed_mesh(usize::MAX).is_err());
        let mesh = generate_closed_mesh(1_000).expect("in range");
        assert_eq!(mesh.triangles.len(), 1_008);
    }

    #[test]
    fn the_model_is_closed_and_wound_outwards() {
        for n in [1, 100, 5_000] {
            let mesh = generate_closed_mesh(n).expect("in range");
            // Every directed edge once, and its reverse once: closed, each
            // edge between exactly two triangles, wound consistently.
            let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
            for &[a, b, c] in &mesh.triangles {
                for edge in [(a, b), (b, c), (c, a)] {
                    *edges.entry(edge).or_default() += 1;
                }
            }
            for (&(a, b), &count) in &edges {
                assert_eq!(count, 1, "edge {a}-{b} of the {n} model");
                assert_eq!(
                    edges.get(&(b, a)),
                    Some(&1),
                    "edge {a}-{b} of the {n} model"
                );
            }
            assert_eq!(edges.len(), 3 * mesh.triangles.len());
            // Outwards: the signed volume (divergence theorem) is positive;
            // once the grid is fine, near that of the torus without lumps,
            // 2 pi^2 R r^2 = 3.16 (the 3 x 3 grid holds 0.54).
            let volume: f64 = (0..mesh.triangles.len())
                .map(|t| {
                    let [a, b, c] = mesh.corners(t);
                    f64::from(a.dot(b.cross(c))) / 6.0
                })
                .sum();
            assert!(volume > 0.5 && volume < 4.5, "{n}: volume {volume}");
            if n >= 5_000 {
                assert!((volume - 3.16).abs() < 0.3, "{n}: volume {volume}");
            }
            assert_eq!(mesh.degenerate_triangle_count(), 0);
            // Each vertex normal points away from the ring's middle line.
            let normals = mesh.triangle_normals.as_ref().expect("smooth");
            assert_eq!(normals, &mesh.triangles);
            for (p, normal) in mesh.positions.iter().zip(&mesh.normals) {
                let centre = Vec3::new(p.x, 0.0, p.z).normalize() * RING_RADIUS as f32;
                assert!((normal.length() - 1.0).abs() < 1e-5);
                assert!(normal.dot(*p - centre) > 0.0, "{n}: normal {normal} at {p}");
            }
        }
    }

    #[test]
    fn the_model_depends_on_the_count_only() {
        let a = generate_closed_mesh(2_000).expect("in range");
        let b = generate_closed_mesh(2_000).expect("in range");
        assert_eq!(a, b);
        let bounds = a.bounds().expect("triangles");
        assert!(
            bounds.1.max_element() < 1.5 && bounds.0.min_element() > -1.5,
            "{bounds:?}"
        );
    }
}
