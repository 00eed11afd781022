//! Tests of chapter 10's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

use super::*;

fn unit_right_triangle() -> Triangle {
    // In the plane z = 2, corners (0,0), (1,0), (0,1).
    Triangle::new(
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::new(1.0, 0.0, 2.0),
        Vec3::new(0.0, 1.0, 2.0),
    )
}

#[test]
fn hits_inside_from_both_sides() {
    let triangle = unit_right_triangle();
    let front = Ray::new(Vec3::new(0.25, 0.25, 0.0), Vec3::Z);
    assert_eq!(
        intersect_triangle(&triangle, &front, 0.0, f32::INFINITY),
        Some(2.0)
    );
    let back = Ray::new(Vec3::new(0.25, 0.25, 5.0), -Vec3::Z);
    assert_eq!(
        intersect_triangle(&triangle, &back, 0.0, f32::INFINITY),
        Some(3.0)
    );
}

#[test]
fn misses_outside_and_respects_the_interval() {
    let triangle = unit_right_triangle();
    let outside = Ray::new(Vec3::new(0.75, 0.75, 0.0), Vec3::Z);
    assert_eq!(
        intersect_triangle(&triangle, &outside, 0.0, f32::INFINITY),
        None
    );
    let inside = Ray::new(Vec3::new(0.25, 0.25, 0.0), Vec3::Z);
    assert_eq!(intersect_triangle(&triangle, &inside, 0.0, 2.0), None);
    assert_eq!(intersect_triangle(&triangle, &inside, 2.0, 9.0), None);
}

#[test]
fn a_ray_along_a_shared_edge_is_claimed_by_a_triangle() {
    // Two triangles share the diagonal from (1,0) to (0,1); a ray through
    // its midpoint must hit at least one of them.
    let first = unit_right_triangle();
    let second = Triangle::new(
        Vec3::new(1.0, 0.0, 2.0),
        Vec3::new(1.0, 1.0, 2.0),
        Vec3::new(0.0, 1.0, 2.0),
    );
    let ray = Ray::new(Vec3::new(0.5, 0.5, 0.0), Vec3::Z);
    let hits = [first, second]
        .iter()
        .filter(|t| intersect_triangle(t, &ray, 0.0, f32::INFINITY).is_some())
        .count();
    assert!(hits >= 1);
}

#[test]
fn barycentric_of_the_corners_and_centroid() {
    let triangle = unit_right_triangle();
    assert_eq!(
        barycentric(&triangle, triangle.b()),
        Vec3::new(0.0, 1.0, 0.0)
    );
    let centroid = (triangle.a() + triangle.b() + triangle.c()) / 3.0;
    assert!(barycentric(&triangle, centroid).abs_diff_eq(Vec3::splat(1.0 / 3.0), 1e-6));
}

#[test]
fn terminator_point_moves_out_on_a_convex_patch_only() {
    let triangle = unit_right_triangle();
    let point = Vec3::new(0.25, 0.25, 2.0);
    // Normals tilted outward as on a sphere seen from +z... toward -z.
    let bulging = [
        Vec3::new(-0.3, -0.3, -1.0).normalize(),
        Vec3::new(0.3, -0.3, -1.0).normalize(),
        Vec3::new(-0.3, 0.3, -1.0).normalize(),
    ];
    let lifted = terminator_point(&triangle, &bulging, point);
    assert!(lifted.z < point.z, "{lifted}");
    let flat = [-Vec3::Z; 3];
    assert_eq!(terminator_point(&triangle, &flat, point), point);
}

/// The unit right triangle in the plane z = 0 (geometric normal +z by its
/// winding) with the same vertex normal at every corner, tilted toward +x
/// (0.6^2 + 0.8^2 = 1): a smooth surface whose shading normal is
/// (0.6, 0, 0.8) everywhere, 37 degrees off the facet's.
const TILTED: Vec3 = Vec3::new(0.6, 0.0, 0.8);

/// A scene of that one smooth triangle, with `material`, seen from above.
fn tilted_triangle_scene(material: raylab::Material) -> raylab::Scene {
    let mut scene = raylab::Scene::parse(
        "background = [0.5, 0.5, 0.5]\n[camera]\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n",
        "the tilted-normal test",
    )
    .expect("the test scene parses");
    scene.vertex_normals.push([TILTED; 3]);
    let triangle = Triangle::with_normals(Vec3::ZERO, Vec3::X, Vec3::Y, 0);
    scene.add_object(
        "smooth triangle".to_string(),
        material,
        [raylab::Shape::Triangle(triangle)],
    );
    scene
}

/// The directions of the secondary rays of `kind` that shading the point
/// where `ray` meets the scene's triangle casts, at chapter 10's stage.
fn secondary_rays(
    scene: &raylab::Scene,
    ray: &Ray,
    shade: fn(&mut raylab::render::Tracer, &HitPoint) -> Vec3,
    kind: raylab::render::RayKind,
) -> Vec<Vec3> {
    let stage = raylab::render::Stage::new(scene, 10, scene.render).expect("stage 10");
    assert!(stage.effects.smooth_shading);
    let mut recorder = raylab::RayRecorder::default();
    {
        let mut tracer = stage.tracer(Some(&mut recorder));
        let hit = raylab::nearest_hit(stage.shapes(), ray, 0.0, f32::INFINITY).expect("a hit");
        let point = tracer.hit_point(hit.object, ray, hit.t);
        assert_eq!(point.normal, TILTED, "the shading normal");
        assert_eq!(point.surface.normal, Vec3::Z, "the geometric normal");
        shade(&mut tracer, &point);
    }
    recorder
        .rays
        .iter()
        .filter(|cast| cast.kind == kind)
        .map(|cast| cast.ray.dir.normalize())
        .collect()
}

fn close(got: Vec3, want: Vec3) -> bool {
    (got - want).abs().max_element() < 1e-6
}

fn mirror() -> raylab::Material {
    raylab::Material {
        reflectivity: 1.0,
        ..raylab::Material::default()
    }
}

fn shade_mirror(tracer: &mut raylab::render::Tracer, point: &HitPoint) -> Vec3 {
    raylab::chapters::Reference::shade_mirror(tracer, point, 0, 1.0)
}

fn shade_dielectric(tracer: &mut raylab::render::Tracer, point: &HitPoint) -> Vec3 {
    raylab::chapters::Reference::shade_dielectric(tracer, point, 0, 1.0)
}

#[test]
fn a_smooth_mirror_reflects_about_the_shading_normal() {
    // Straight down onto the triangle: about the facet's normal the ray
    // would come straight back up, (0, 0, 1); about the shading normal it
    // leaves along d - 2 (d.n) n = (0, 0, -1) + 1.6 (0.6, 0, 0.8).
    let scene = tilted_triangle_scene(mirror());
    let ray = Ray::new(Vec3::new(0.25, 0.25, 5.0), -Vec3::Z);
    let reflected = secondary_rays(
        &scene,
        &ray,
        shade_mirror,
        raylab::render::RayKind::Reflection,
    );
    assert_eq!(reflected.len(), 1, "{reflected:?}");
    assert!(
        close(reflected[0], Vec3::new(0.96, 0.0, 0.28)),
        "{}",
        reflected[0]
    );
}

#[test]
fn a_mirror_image_below_the_facet_falls_back_to_the_geometric_normal() {
    // A grazing ray travelling toward +x: the shading normal faces away
    // from it (to_eye . n = (-0.6 + 0.16) / |d| < 0), and its mirror image
    // about that normal would go below the triangle (z < 0). The mirror
    // uses the facet's normal there: (1, 0, 0.2), normalised.
    let scene = tilted_triangle_scene(mirror());
    let dir = Vec3::new(1.0, 0.0, -0.2);
    let ray = Ray::new(Vec3::new(0.25, 0.25, 0.0) - 5.0 * dir, dir);
    let reflected = secondary_rays(
        &scene,
        &ray,
        shade_mirror,
        raylab::render::RayKind::Reflection,
    );
    assert_eq!(reflected.len(), 1, "{reflected:?}");
    assert!(reflected[0].z > 0.0, "{}", reflected[0]);
    assert!(
        close(reflected[0], Vec3::new(1.0, 0.0, 0.2).normalize()),
        "{}",
        reflected[0]
    );
}

#[test]
fn smooth_glass_bends_and_reflects_about_the_shading_normal() {
    // Straight down into glass (n1 / n2 = 1 / 1.5) through the shading
    // normal: cos i = 0.8, sin^2 t = 0.36 / 2.25 = 0.16, and the ray goes
    // on along (0, 0, -1) / 1.5 + (0.8 / 1.5 - sqrt(0.84)) (0.6, 0, 0.8),
    // not straight down as through the facet. The reflected share (exact
    // Fresnel at that same cosine) leaves as from the mirror above.
    let glass = raylab::Material {
        transparency: 1.0,
        ior: 1.5,
        fresnel: raylab::scene::FresnelModel::Exact,
        ..raylab::Material::default()
    };
    let scene = tilted_triangle_scene(glass);
    let ray = Ray::new(Vec3::new(0.25, 0.25, 5.0), -Vec3::Z);
    let refracted = secondary_rays(
        &scene,
        &ray,
        shade_dielectric,
        raylab::render::RayKind::Refraction,
    );
    let eta = 1.0 / 1.5;
    let k = eta * 0.8 - 0.84f32.sqrt();
    let want = Vec3::new(0.0, 0.0, -eta) + k * TILTED;
    assert_eq!(refracted.len(), 1, "{refracted:?}");
    assert!(close(refracted[0], want), "{} against {want}", refracted[0]);
    let reflected = secondary_rays(
        &scene,
        &ray,
        shade_dielectric,
        raylab::render::RayKind::Reflection,
    );
    assert_eq!(reflected.len(), 1, "{reflected:?}");
    assert!(
        close(reflected[0], Vec3::new(0.96, 0.0, 0.28)),
        "{}",
        reflected[0]
    );
}

/// The checkpoints added for the contract's clauses get fresh inputs
/// under `grade --code --fresh`: the reference must pass every draw.
#[test]
fn the_contracts_checkpoints_pass_with_fresh_inputs() {
    let names = [
        "triangle-tilted",
        "terminator-mixed-heights",
        "smooth-hit-one-normal-below-the-facet",
        "smooth-hit-winding-against-the-normals",
        "smooth-hit-half-transparent",
    ];
    let cases = crate::check::by_chapter::checkpoints(10);
    for name in names {
        let case = cases
            .iter()
            .find(|case| case.name == name)
            .expect("the case exists");
        for seed in 1..=20 {
            let fresh = case.fresh(seed).expect("drawn afresh");
            let outcome = fresh.run::<crate::Reference>();
            assert_eq!(
                outcome,
                crate::check::Outcome::Pass,
                "{name}, seed {seed}: {}",
                fresh.kind.inputs()
            );
        }
    }
}

// The bug gallery and the accepted alternatives of this chapter.
#[path = "gallery.rs"]
mod gallery;
