//! Tests of chapter 2's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

use super::*;

fn unit_sphere_at_z5() -> Sphere {
    Sphere::new(Vec3::new(0.0, 0.0, 5.0), 1.0)
}

#[test]
fn the_behind_shortcut_never_changes_an_answer() {
    // Rays from all around a ball, many heading away from it, some
    // starting on or inside it: intersect (with the shortcut) must give
    // exactly what choosing among the full roots gives.
    // Any fixed spread of numbers in [-1, 1) will do: a splitmix64 step.
    let random = |i: u32, d: u32| {
        let mut z = ((u64::from(i) << 32) | u64::from(d)).wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
    };
    let ball = Sphere::new(Vec3::new(0.5, -0.25, 2.0), 1.5);
    let mut shortcuts = 0;
    for i in 0..20_000 {
        let origin = ball.center() + 4.0 * Vec3::new(random(i, 0), random(i, 1), random(i, 2));
        let dir = Vec3::new(random(i, 3), random(i, 4), random(i, 5));
        let ray = Ray::new(origin, dir);
        for (t_min, t_max) in [(0.0, f32::INFINITY), (1e-3, 2.0), (-1.0, f32::INFINITY)] {
            let full = ball
                .roots(&ray)
                .and_then(|roots| choose_root(&ball, &ray, roots, t_min, t_max));
            assert_eq!(ball.intersect(&ray, t_min, t_max), full, "{ray:?}");
        }
        let oc = origin - ball.center();
        shortcuts += usize::from(oc.length() > 1.5 && dir.dot(oc) > 0.0);
    }
    assert!(
        shortcuts > 5_000,
        "the shortcut was taken {shortcuts} times"
    );
}

#[test]
fn both_roots_of_a_central_ray() {
    // From the origin along +z: the surface is at z = 4 and z = 6.
    let ray = Ray::new(Vec3::ZERO, Vec3::Z);
    assert_eq!(unit_sphere_at_z5().roots(&ray), Some((4.0, 6.0)));
    assert_eq!(
        unit_sphere_at_z5().intersect(&ray, 0.0, f32::INFINITY),
        Some(4.0)
    );
}

#[test]
fn t_is_in_units_of_the_direction() {
    let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0));
    assert_eq!(
        unit_sphere_at_z5().intersect(&ray, 0.0, f32::INFINITY),
        Some(2.0)
    );
}

#[test]
fn origin_inside_takes_the_far_root() {
    let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::Z);
    assert_eq!(unit_sphere_at_z5().roots(&ray), Some((-1.0, 1.0)));
    assert_eq!(
        unit_sphere_at_z5().intersect(&ray, 0.0, f32::INFINITY),
        Some(1.0)
    );
}

#[test]
fn sphere_behind_and_beside_is_missed() {
    let behind = Ray::new(Vec3::ZERO, -Vec3::Z);
    assert_eq!(
        unit_sphere_at_z5().intersect(&behind, 0.0, f32::INFINITY),
        None
    );
    let beside = Ray::new(Vec3::new(2.0, 0.0, 0.0), Vec3::Z);
    assert_eq!(unit_sphere_at_z5().roots(&beside), None);
}

#[test]
fn tangent_ray_has_a_double_root() {
    let ray = Ray::new(Vec3::new(1.0, 0.0, 0.0), Vec3::Z);
    assert_eq!(unit_sphere_at_z5().roots(&ray), Some((5.0, 5.0)));
}

#[test]
fn degenerate_spheres_and_rays_never_hit() {
    let ray = Ray::new(Vec3::ZERO, Vec3::Z);
    for radius in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        let sphere = Sphere::new(Vec3::new(0.0, 0.0, 5.0), radius);
        assert_eq!(
            sphere.intersect(&ray, 0.0, f32::INFINITY),
            None,
            "radius {radius}"
        );
    }
    let zero_dir = Ray::new(Vec3::ZERO, Vec3::ZERO);
    assert_eq!(
        unit_sphere_at_z5().intersect(&zero_dir, 0.0, f32::INFINITY),
        None
    );
    let nan_dir = Ray::new(Vec3::ZERO, Vec3::new(0.0, f32::NAN, 1.0));
    assert_eq!(
        unit_sphere_at_z5().intersect(&nan_dir, 0.0, f32::INFINITY),
        None
    );
}

#[test]
fn textbook_formula_agrees_on_an_easy_case() {
    let ray = Ray::new(Vec3::ZERO, Vec3::Z);
    assert_eq!(
        unit_sphere_at_z5().intersect_textbook(&ray, 0.0, f32::INFINITY),
        Some(4.0)
    );
}
