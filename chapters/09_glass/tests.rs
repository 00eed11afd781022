//! Tests of chapter 9's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

use super::*;

#[test]
fn normal_incidence_air_to_glass_reflects_four_percent() {
    assert_eq!(fresnel(1.0, 1.0, 1.5), 0.04);
    assert_eq!(schlick(1.0, 1.0, 1.5), 0.04);
    // The same from the glass side.
    assert_eq!(fresnel(1.0, 1.5, 1.0), 0.04);
    assert_eq!(schlick(1.0, 1.5, 1.0), 0.04);
}

#[test]
fn grazing_incidence_reflects_everything() {
    assert_eq!(fresnel(0.0, 1.0, 1.5), 1.0);
    assert_eq!(schlick(0.0, 1.0, 1.5), 1.0);
    assert_eq!(fresnel(0.0, 1.5, 1.0), 1.0);
    assert_eq!(schlick(0.0, 1.5, 1.0), 1.0);
}

#[test]
fn equal_indices_are_no_boundary() {
    for c in [0.0, 0.3, 1.0] {
        assert_eq!(fresnel(c, 1.33, 1.33), 0.0);
        assert_eq!(schlick(c, 1.33, 1.33), 0.0);
    }
}

#[test]
fn nan_in_nan_out_and_bad_indices_are_nan() {
    for (c, n1, n2) in [
        (f32::NAN, 1.0, 1.5),
        (0.5, f32::NAN, 1.5),
        (0.5, 1.0, f32::NAN),
        (0.5, 0.0, 1.5),
        (0.5, 1.0, -1.5),
        (0.5, f32::INFINITY, 1.5),
    ] {
        assert!(fresnel(c, n1, n2).is_nan(), "fresnel({c}, {n1}, {n2})");
        assert!(schlick(c, n1, n2).is_nan(), "schlick({c}, {n1}, {n2})");
    }
}

#[test]
fn clear_channels_transmit_everything_even_for_ever() {
    let t = transmittance(Vec3::new(0.0, 0.5, 2.0), f32::INFINITY);
    assert_eq!(t, Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(transmittance(Vec3::splat(3.0), 0.0), Vec3::ONE);
}

/// A ray through a glass slab made of triangles (a cuboid: twelve of
/// them) enters through one triangle and leaves through another, and must
/// leave glass for air there: the solid is the mesh, not the triangle.
#[test]
fn a_glass_mesh_is_one_solid_entered_by_one_triangle_and_left_by_another() {
    use raylab::Reference;
    let scene = raylab::Scene::parse(
        r#"
[camera]
position = [0.0, 0.0, -5.0]
look_at = [0.0, 0.0, 0.0]
[[objects]]
name = "slab"
cuboid = { min = [-1.0, -1.0, -0.1], max = [1.0, 1.0, 0.1] }
material = { transparency = 1.0, ior = 1.5, fresnel = "exact" }
"#,
        "a test",
    )
    .expect("the scene parses");
    // Chapter 10 draws the triangles.
    let stage = raylab::Stage::<Reference>::with_chapters(&scene, 10, scene.render).expect("stage");
    let tracer = stage.tracer(None);
    let incoming = Ray::new(Vec3::new(0.3, 0.2, -2.0), Vec3::new(0.3, 0.1, 1.0));
    let hit = stage
        .nearest_hit(&incoming, 0.0, f32::INFINITY)
        .expect("the slab");
    let entry = tracer.hit_point(hit.object, &incoming, hit.t);
    let into = crossing(&MediumStack::EMPTY, &entry);
    assert_eq!((into.n1, into.n2), (1.0, 1.5));
    let inside = Ray::new(
        entry.surface.point + 1e-3 * incoming.dir,
        raylab::refract(incoming.dir, entry.normal, 1.0 / 1.5).expect("a refraction"),
    );
    let hit = stage
        .nearest_hit(&inside, 0.0, f32::INFINITY)
        .expect("the far face");
    let exit = tracer.hit_point(hit.object, &inside, hit.t);
    assert_ne!(exit.object, entry.object, "another triangle");
    let out = crossing(&into.beyond, &exit);
    assert_eq!((out.n1, out.n2), (1.5, 1.0));
}

// The bug gallery and the accepted alternatives of this chapter.
#[path = "gallery.rs"]
mod gallery;
