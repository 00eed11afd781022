//! Triangles against Embree (feature `embree`, like tests/embree/embree.rs;
//! `scripts/test.sh` sets Embree up and runs both): a closed mesh is one
//! Embree geometry whose hits map back to our object indices, random rays
//! agree, and rays aimed exactly at shared edges and corners from inside
//! the mesh are hit by our watertight test every time, while the textbook
//! Moller-Trumbore test lets some through, which the cross-check reports as
//! edge misses.
//!
//! A speed race against Embree is here too, ignored by default
//! (it takes a minute in release):
//! `cargo test --release --features embree --test embree embree_triangles::race -- --ignored --nocapture`.
#![cfg(feature = "embree")]

use std::collections::HashMap;

use raylab::course::{Chapters, Objects, Textbook};
use raylab::crosscheck::{
    self, Answer, Boundary, PlaneQuad, Primitive, Reference, Verdict, cross_check_with,
};
use raylab::embree::EmbreeScene;
use raylab::shapes::Triangle;
use raylab::{CastRay, Ray, RayKind, Reference as ReferenceChapters, Shape, Sphere, Vec3};

/// The chapters with Moller-Trumbore in place of the watertight test.
type MollerTrumbore = Textbook<ReferenceChapters, false, true>;

/// A closed mesh: an octahedron (corners on the axes) subdivided `level`
/// times, every new corner pushed out onto the sphere of `radius` around
/// the origin. Every corner is computed once and every triangle takes its
/// corners from the one table, so neighbours share their edges bit for
/// bit. An octahedron rather than the usual icosahedron: its edges lie in
/// the coordinate planes, and stay there when subdivided (a midpoint of two
/// corners with x = 0 has x = 0), so a ray from the centre in such a plane
/// crosses an edge *exactly*, and the watertight test's edge function there
/// is exactly 0 (a planted `<=` for `<` makes it miss).
fn octasphere(level: u32, radius: f32) -> Vec<[Vec3; 3]> {
    let mut corners = vec![Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let (px, nx, py, ny, pz, nz) = (0, 1, 2, 3, 4, 5);
    // Wound counter-clockwise seen from outside.
    let mut faces: Vec<[u32; 3]> = vec![
        [px, py, pz],
        [py, nx, pz],
        [nx, ny, pz],
        [ny, px, pz],
        [py, px, nz],
        [nx, py, nz],
        [ny, nx, nz],
        [px, ny, nz],
    ];
    for _ in 0..level {
        let mut middles: HashMap<(u32, u32), u32> = HashMap::new();
        let mut middle = |a: u32, b: u32, corners: &mut Vec<Vec3>| {
            *middles.entry((a.min(b), a.max(b))).or_insert_with(|| {
                corners.push(((corners[a as usize] + corners[b as usize]) / 2.0).normalize());
                corners.len() as u32 - 1
            })
        };
        let mut finer = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let (ab, bc, ca) = (
                middle(a, b, &mut corners),
                middle(b, c, &mut corners),
                middle(c, a, &mut corners),
            );
            finer.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        faces = finer;
    }
    faces
        .iter()
        .map(|face| face.map(|index| radius * corners[index as usize]))
        .collect()
}

/// A closed torus around the z axis of `rings` x `segments` quads, two
/// triangles each (`2 rings segments` triangles), corners from one grid.
fn torus(rings: u32, segments: u32) -> Vec<[Vec3; 3]> {
    let (major, minor) = (1.0f32, 0.35f32);
    let corner = |ring: u32, segment: u32| {
        let phi = std::f32::consts::TAU * (ring % rings) as f32 / rings as f32;
        let theta = std::f32::consts::TAU * (segment % segments) as f32 / segments as f32;
        let reach = major + minor * theta.cos();
        Vec3::new(reach * phi.cos(), reach * phi.sin(), minor * theta.sin())
    };
    let grid: Vec<Vec3> = (0..rings)
        .flat_map(|ring| (0..segments).map(move |segment| corner(ring, segment)))
        .collect();
    let at =
        |ring: u32, segment: u32| grid[((ring % rings) * segments + segment % segments) as usize];
    let mut triangles = Vec::with_capacity(2 * (rings * segments) as usize);
    for ring in 0..rings {
        for segment in 0..segments {
            let (a, b) = (at(ring, segment), at(ring + 1, segment));
            let (c, d) = (at(ring + 1, segment + 1), at(ring, segment + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    triangles
}

fn shapes_of(triangles: &[[Vec3; 3]], offset: Vec3) -> Vec<Shape> {
    triangles
        .iter()
        .map(|&[a, b, c]| Shape::Triangle(Triangle::new(a + offset, b + offset, c + offset)))
        .collect()
}

fn primitives_of(shapes: &[Shape]) -> Vec<Primitive> {
    shapes
        .iter()
        .map(|shape| match shape {
            Shape::Triangle(triangle) => Primitive::Triangle(triangle.corners()),
            Shape::Sphere(sphere) => Primitive::Sphere {
                center: sphere.center(),
                radius: sphere.radius(),
            },
            Shape::Plane(_) => panic!("no planes in these tests"),
            Shape::Implicit(_) => panic!("no implicit surfaces in these tests"),
        })
        .collect()
}

/// A small deterministic generator (xorshift64*), so failures replay.
struct Random(u64);

impl Random {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 40;
        bits as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [-1, 1).
    fn signed(&mut self) -> f32 {
        2.0 * self.next() - 1.0
    }

    fn vector(&mut self) -> Vec3 {
        Vec3::new(self.signed(), self.signed(), self.signed())
    }
}

fn cast(ray: Ray) -> CastRay {
    CastRay {
        kind: RayKind::Primary,
        ray,
        t_min: 0.0,
        t_max: f32::INFINITY,
    }
}

fn embree_answer(embree: &EmbreeScene, cast: &CastRay) -> Option<Answer> {
    embree
        .intersect(&cast.ray, cast.t_min, cast.t_max)
        .map(|hit| Answer {
            object: hit.object,
            t: hit.t,
        })
}

fn watertight(shapes: &[Shape], cast: &CastRay) -> Option<Answer> {
    crosscheck::ours(shapes, cast).map(Answer::from)
}

fn moller_trumbore(shapes: &[Shape], cast: &CastRay) -> Option<Answer> {
    MollerTrumbore::nearest_hit(
        &Objects::<MollerTrumbore>::new(shapes),
        &cast.ray,
        cast.t_min,
        cast.t_max,
    )
    .map(Answer::from)
}

#[test]
fn a_mesh_is_one_geometry_and_hits_name_our_objects() {
    // sphere, 512 triangles, sphere, 512 triangles: four geometries.
    let mesh = octasphere(3, 1.0);
    let mut shapes = vec![Shape::Sphere(Sphere::new(Vec3::new(-5.0, 0.0, 0.0), 0.5))];
    shapes.extend(shapes_of(&mesh, Vec3::new(0.0, 0.0, 0.0)));
    shapes.push(Shape::Sphere(Sphere::new(Vec3::new(5.0, 0.0, 0.0), 0.5)));
    shapes.extend(shapes_of(&mesh, Vec3::new(0.0, 5.0, 0.0)));
    let embree = EmbreeScene::new(&primitives_of(&shapes)).expect("Embree scene");
    assert_eq!(embree.geometry_count(), 4);
    let build = embree.build_stats();
    assert!(build.peak_bytes >= build.bytes_after_commit && build.peak_bytes > 0);
    let quads = vec![None; shapes.len()];
    let reference = Reference {
        shapes: &shapes,
        quads: &quads,
    };
    let mut random = Random(7);
    let mut checked = [0; 4];
    for _ in 0..2000 {
        // From far away toward a random point of one of the four objects.
        let target = [
            Vec3::new(-5.0, 0.0, 0.0),
            Vec3::ZERO,
            Vec3::new(5.0, 0.0, 0.0),
            Vec3::new(0.0, 5.0, 0.0),
        ][(random.next() * 4.0) as usize % 4]
            + 0.25 * random.vector();
        let origin = target + Vec3::new(0.0, 0.0, -20.0) + 0.1 * random.vector();
        let cast = cast(Ray::new(origin, target - origin));
        let ours = watertight(&shapes, &cast);
        let theirs = embree_answer(&embree, &cast);
        let (Some(ours), Some(theirs)) = (ours, theirs) else {
            panic!("both must hit: ours {ours:?}, Embree {theirs:?}");
        };
        let verdict = reference
            .compare_answers(&cast, Some(ours), Some(theirs))
            .verdict;
        assert!(
            ours.object == theirs.object || matches!(verdict, Verdict::Boundary(_)),
            "ours {ours:?}, Embree {theirs:?}, {verdict:?}"
        );
        let group = match ours.object {
            0 => 0,
            513 => 2,
            object if object < 513 => 1,
            _ => 3,
        };
        checked[group] += 1;
    }
    assert!(checked.iter().all(|&count| count > 100), "{checked:?}");
}

/// Random rays from outside and inside a closed mesh: the same triangle
/// (our object index) or both a miss, `t` within the tolerance, apart from
/// a few edge cases, and never a crack.
#[test]
fn random_rays_at_a_closed_mesh_agree_with_embree() {
    let center = Vec3::new(0.3, -0.2, 5.0);
    let shapes = shapes_of(&octasphere(3, 2.0), center);
    let quads: Vec<Option<PlaneQuad>> = vec![None; shapes.len()];
    let embree = EmbreeScene::new(&primitives_of(&shapes)).expect("Embree scene");
    assert_eq!(embree.geometry_count(), 1);
    let reference = Reference {
        shapes: &shapes,
        quads: &quads,
    };
    let mut random = Random(42);
    let rays: Vec<CastRay> = (0..20_000)
        .map(|index| {
            let origin = if index % 4 == 0 {
                center + 1.5 * random.vector()
            } else {
                center + 6.0 * random.vector()
            };
            let aim = center + 2.2 * random.vector();
            cast(Ray::new(
                origin,
                (aim - origin) * (0.1 + 3.0 * random.next()),
            ))
        })
        .collect();
    let tally = cross_check_with(
        &reference,
        &rays,
        |cast| watertight(&shapes, cast),
        |cast| embree_answer(&embree, cast),
    );
    let boundary: u64 = tally.boundary.iter().sum();
    println!(
        "same {}, both miss {}, boundary {:?}, disagreements {}, worst {:#?}",
        tally.same_hit,
        tally.both_miss,
        tally.boundary,
        tally.disagreements,
        tally.worst.first()
    );
    assert!(tally.clean(), "{} disagreements", tally.disagreements);
    assert_eq!(tally.edge_misses, 0);
    assert!(tally.same_hit > 10_000, "{}", tally.same_hit);
    assert!(boundary * 100 < tally.total(), "{boundary} boundary cases");
    let (median, max) = tally.median_and_max().expect("shared hits");
    println!(
        "relative difference of t: median {:.2} eps, max {:.1} eps",
        median / f32::EPSILON,
        max / f32::EPSILON
    );
    assert!(median <= 2.0 * f32::EPSILON, "median {median}");

    // The tolerance is not a blanket: the same mesh one part in ten
    // thousand larger for Embree disagrees on most hits.
    let grown: Vec<Primitive> = primitives_of(&shapes)
        .into_iter()
        .map(|primitive| match primitive {
            Primitive::Triangle(corners) => {
                Primitive::Triangle(corners.map(|corner| center + (corner - center) * 1.0001))
            }
            other => other,
        })
        .collect();
    let grown = EmbreeScene::new(&grown).expect("Embree scene");
    let off = cross_check_with(
        &reference,
        &rays,
        |cast| watertight(&shapes, cast),
        |cast| embree_answer(&grown, cast),
    );
    println!("grown by 1e-4: {} disagreements", off.disagreements);
    assert!(
        off.disagreements > tally.same_hit / 2,
        "{}",
        off.disagreements
    );
}

/// Rays aimed exactly at the corners of the closed mesh and at points of
/// its edges (exactly on the edges in the coordinate planes, within a
/// rounding of the others), mostly from inside, some from outside.
fn edge_rays(triangles: &[[Vec3; 3]]) -> Vec<CastRay> {
    let mut edges: Vec<(Vec3, Vec3)> = Vec::new();
    let mut corners: Vec<Vec3> = Vec::new();
    let key = |v: Vec3| v.to_array().map(f32::to_bits);
    let mut seen_edges = std::collections::HashSet::new();
    let mut seen_corners = std::collections::HashSet::new();
    for triangle in triangles {
        for i in 0..3 {
            let (a, b) = (triangle[i], triangle[(i + 1) % 3]);
            let (ka, kb) = (key(a), key(b));
            if seen_edges.insert(if ka < kb { (ka, kb) } else { (kb, ka) }) {
                edges.push((a, b));
            }
            if seen_corners.insert(ka) {
                corners.push(a);
            }
        }
    }
    let mut random = Random(3);
    let mut rays = Vec::new();
    // From the centre, through every corner: the corner is exactly on the
    // ray, at t = 1. And from outside, back toward the centre.
    for &corner in &corners {
        rays.push(cast(Ray::new(Vec3::ZERO, corner)));
        rays.push(cast(Ray::new(3.0 * corner, -corner)));
    }
    for &(a, b) in &edges {
        for s in [0.5, 0.25, 1.0 / 3.0, 0.9] {
            let point = a + s * (b - a);
            rays.push(cast(Ray::new(Vec3::ZERO, point)));
            // From elsewhere inside, toward the same point.
            let origin = 0.5 * random.vector();
            rays.push(cast(Ray::new(origin, point - origin)));
        }
        // In a coordinate plane an edge lies exactly in it: a ray from the
        // centre toward its middle, with that coordinate exactly 0,
        // crosses the edge exactly.
        let middle = (a + b) / 2.0;
        for axis in 0..3 {
            if a[axis] == 0.0 && b[axis] == 0.0 {
                let mut dir = middle;
                dir[axis] = 0.0;
                rays.push(cast(Ray::new(Vec3::ZERO, dir)));
                // The same from outside: the triangles face the ray (the
                // test's other sign), and the line stays in the plane.
                rays.push(cast(Ray::new(3.0 * dir, -dir)));
            }
        }
    }
    rays
}

/// Planting a crack in ours makes this fail (checked by hand): `>=` for
/// `>` in the inside test of chapter 10's code (rays from inside,
/// which meet the triangles from behind: all edge functions negative) or
/// `<=` for `<` (rays from outside).
#[test]
fn rays_through_shared_edges_are_never_lost_by_ours_but_are_by_moller_trumbore() {
    let triangles = octasphere(4, 1.0);
    let shapes = shapes_of(&triangles, Vec3::ZERO);
    let quads: Vec<Option<PlaneQuad>> = vec![None; shapes.len()];
    let embree = EmbreeScene::new(&primitives_of(&shapes)).expect("Embree scene");
    let rays = edge_rays(&triangles);
    let reference = Reference {
        shapes: &shapes,
        quads: &quads,
    };
    let mut on_an_edge = 0;
    let (mut ours_missed, mut textbook_missed) = (0, 0);
    for cast in &rays {
        // Every one of these rays crosses the closed mesh.
        let theirs = embree_answer(&embree, cast)
            .unwrap_or_else(|| panic!("Embree (robust) missed {cast:?}"));
        if let Shape::Triangle(triangle) = shapes[theirs.object] {
            on_an_edge += usize::from(crosscheck::on_edge(&triangle, &cast.ray));
        }
        // Lost: no hit, or a hit farther along (through a crack in the
        // near side to the far side), beyond any rounding.
        let lost = |ours: Option<Answer>| {
            ours.is_none_or(|ours| ours.t > theirs.t + 1e-3 * theirs.t.abs())
        };
        ours_missed += usize::from(lost(watertight(&shapes, cast)));
        textbook_missed += usize::from(lost(moller_trumbore(&shapes, cast)));
    }
    println!(
        "{} rays at edges and corners ({on_an_edge} within the edge band of Embree's \
         triangle): ours missed {ours_missed}, Moller-Trumbore missed {textbook_missed}",
        rays.len()
    );
    assert_eq!(
        ours_missed, 0,
        "the watertight test lost rays at shared edges"
    );
    assert!(
        textbook_missed >= 1,
        "Moller-Trumbore lost no ray: the set does not probe the edges"
    );
    // The edge band is what the cross-check's rule hangs on: these rays
    // must be in it.
    assert!(
        on_an_edge * 10 >= rays.len() * 9,
        "{on_an_edge} of {}",
        rays.len()
    );

    // The cross-check itself: ours is clean; Moller-Trumbore as "ours" is
    // reported as edge misses, which are failures, not boundary cases.
    let tally = cross_check_with(
        &reference,
        &rays,
        |cast| watertight(&shapes, cast),
        |cast| embree_answer(&embree, cast),
    );
    println!(
        "watertight: same {}, boundary {:?}, disagreements {}",
        tally.same_hit, tally.boundary, tally.disagreements
    );
    assert!(tally.clean(), "{:#?}", tally.worst.first());
    let cracked = cross_check_with(
        &reference,
        &rays,
        |cast| moller_trumbore(&shapes, cast),
        |cast| embree_answer(&embree, cast),
    );
    println!(
        "Moller-Trumbore: edge misses {}, disagreements {}",
        cracked.edge_misses, cracked.disagreements
    );
    assert!(!cracked.clean());
    assert_eq!(cracked.edge_misses as usize, textbook_missed);
    assert_eq!(cracked.worst[0].verdict, Verdict::EdgeMissed);
}

/// The border of an open mesh is not a shared edge: a ray Embree hits
/// there and ours misses is an edge case, not a crack.
#[test]
fn an_open_border_is_a_boundary_case_and_a_shared_edge_is_not() {
    let a = Vec3::new(0.0, 0.0, 2.0);
    let b = Vec3::new(1.0, 0.0, 2.0);
    let c = Vec3::new(0.0, 1.0, 2.0);
    let d = Vec3::new(1.0, 1.0, 2.0);
    let shapes = vec![
        Shape::Triangle(Triangle::new(a, b, c)),
        Shape::Triangle(Triangle::new(b, d, c)),
    ];
    let quads = vec![None; 2];
    let reference = Reference {
        shapes: &shapes,
        quads: &quads,
    };
    let theirs = |t: f32| Some(Answer { object: 0, t });
    // Along x = 0, the border of triangle 0 only.
    let border = cast(Ray::new(Vec3::new(0.0, 0.5, 0.0), Vec3::Z));
    assert_eq!(
        reference
            .compare_answers(&border, None, theirs(2.0))
            .verdict,
        Verdict::Boundary(Boundary::Edge)
    );
    // Through the diagonal b-c, shared by both.
    let shared = cast(Ray::new(Vec3::new(0.5, 0.5, 0.0), Vec3::Z));
    assert_eq!(
        reference
            .compare_answers(&shared, None, theirs(2.0))
            .verdict,
        Verdict::EdgeMissed
    );
    // Both hit, each its own triangle of the shared edge: an edge case.
    let other = Some(Answer { object: 1, t: 2.0 });
    assert_eq!(
        reference
            .compare_answers(&shared, other, theirs(2.0))
            .verdict,
        Verdict::Boundary(Boundary::Edge)
    );
    // In the middle of a triangle, a miss is a plain disagreement.
    let inside = cast(Ray::new(Vec3::new(0.2, 0.2, 0.0), Vec3::Z));
    assert_eq!(
        reference
            .compare_answers(&inside, None, theirs(2.0))
            .verdict,
        Verdict::Disagree
    );
    // Parallel to the triangles: grazing.
    let grazing = cast(Ray::new(Vec3::new(-1.0, 0.5, 2.0), Vec3::X));
    assert_eq!(
        reference
            .compare_answers(&grazing, None, theirs(1.5))
            .verdict,
        Verdict::Boundary(Boundary::Grazing)
    );
}

/// The race: ours (brute force until chapter 11's BVH) against
/// Embree, one thread, median of 5, on closed tori of 1 k to 1 M triangles.
/// Run alone, in release (see the top of this file); it prints a table.
#[test]
#[ignore = "a minute of timing; run by hand for the README's figures"]
fn race() {
    let sizes = [(20, 25), (50, 100), (200, 250), (500, 1000)];
    println!(
        "| triangles | rays | ours rays/s | Embree rays/s | ratio ours/Embree | ours build | \
         Embree build (fill + BVH) | Embree peak (monitor) | peak RSS growth ours / Embree |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for (rings, segments) in sizes {
        let triangles = torus(rings, segments);
        let shapes = shapes_of(&triangles, Vec3::ZERO);
        let primitives = primitives_of(&shapes);
        // Brute force costs one test per triangle per ray: about 1e8
        // tests a run, at least 200 rays.
        let count = (100_000_000 / shapes.len()).clamp(200, 100_000);
        let mut random = Random(11);
        let rays: Vec<CastRay> = (0..count)
            .map(|_| {
                let origin = Vec3::new(0.0, -4.0, 1.5) + 0.5 * random.vector();
                let aim = Vec3::new(
                    1.4 * random.signed(),
                    1.4 * random.signed(),
                    0.4 * random.signed(),
                );
                cast(Ray::new(origin, aim - origin))
            })
            .collect();
        let race = raylab::bvh_reports::race::race(
            &primitives,
            &rays,
            || |cast: &CastRay| watertight(&shapes, cast),
            || |cast: &CastRay| watertight(&shapes, cast),
            raylab::bvh_reports::race::RACE_RUNS,
        )
        .expect("race");
        let mb = |bytes: Option<u64>| {
            bytes.map_or("?".to_string(), |b| format!("{:.1} MB", b as f64 / 1e6))
        };
        let build = race.embree_build;
        println!(
            "| {} | {} | {:.0} | {:.0} | {:.2e} | {:.1} ms | {:.1} ms ({:.1} + {:.1}) | {:.1} MB | {} / {} |",
            shapes.len(),
            race.rays,
            race.ours.rays_per_second,
            race.embree.rays_per_second,
            race.ratio(),
            race.ours.build.as_secs_f64() * 1e3,
            race.embree.build.as_secs_f64() * 1e3,
            build.fill.as_secs_f64() * 1e3,
            build.commit.as_secs_f64() * 1e3,
            build.peak_bytes as f64 / 1e6,
            mb(race.ours.peak_rss_growth),
            mb(race.embree.peak_rss_growth),
        );
    }
}

/// `raylab race`'s first table: the rays of a render of chapter 11's scene
/// with its model resized, traced by the stage's tree and by Embree, who
/// must agree on every one (no shared edge is met exactly by a camera ray
/// here).
#[test]
fn the_race_on_a_render_s_rays_resizes_the_model_and_both_sides_agree() {
    let measured = raylab::bvh_reports::race::race_on_rendered_scene(1000, 1).expect("race");
    // `raylab mesh --triangles 1000` makes 1008; the scene's balls are not
    // triangles.
    assert_eq!(measured.triangles, 1008);
    // Every pixel's camera ray, and shadow rays besides.
    assert!(
        measured.race.rays > 640 * 480,
        "{} rays",
        measured.race.rays
    );
    assert_eq!(measured.different_objects, 0);
    let ratio = measured.race.ratio();
    assert!(ratio.is_finite() && ratio > 0.0, "ratio {ratio}");
    assert!(measured.ours_bytes > 1008 * std::mem::size_of::<raylab::Shape>());
    // Brute force on the first rays, as many as its test budget allows:
    // 1008 triangles, 48 balls and the floor.
    let shapes = 1008 + 48 + 1;
    assert_eq!(
        measured.brute_force.rays,
        raylab::bvh_reports::race::BRUTE_FORCE_TESTS / shapes
    );
    assert!(measured.brute_force.rays_per_second > 0.0);
    // The stage walks a tree: every ray tests at least the root's box, and
    // the rays that enter it test more.
    let walk = measured
        .walk
        .expect("the stage of 1,057 objects builds a tree");
    assert!(walk.boxes_per_ray > 1.0, "{walk:?}");
    assert!(walk.objects_per_ray > 0.0, "{walk:?}");
    // The wide walk opens a node of four boxes where the binary one tests
    // two, and a leaf test asks up to four triangles: fewer of each.
    let wide = measured.wide_walk.expect("and folds it");
    assert!(wide.nodes_per_ray >= 1.0, "{wide:?}");
    assert!(wide.nodes_per_ray < walk.boxes_per_ray, "{wide:?} {walk:?}");
    assert!(wide.leaf_tests_per_ray > 0.0, "{wide:?}");
    assert!(
        wide.leaf_tests_per_ray < walk.objects_per_ray,
        "{wide:?} {walk:?}"
    );
    let binary = measured.race.second.rays_per_second;
    assert!(binary.is_finite() && binary > 0.0, "{binary}");
}
