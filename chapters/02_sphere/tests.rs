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

#[test]
fn no_roots_for_a_ray_with_a_non_finite_coordinate() {
    let ball = Sphere::new(Vec3::ZERO, 1.0);
    let (origin, dir) = (Vec3::new(0.1, 0.2, -5.0), Vec3::new(0.01, 0.02, 1.0));
    for value in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        for axis in 0..3 {
            let mut spoilt_origin = origin.to_array();
            spoilt_origin[axis] = value;
            let mut spoilt_dir = dir.to_array();
            spoilt_dir[axis] = value;
            for ray in [
                Ray::new(Vec3::from(spoilt_origin), dir),
                Ray::new(origin, Vec3::from(spoilt_dir)),
            ] {
                assert_eq!(sphere_roots(&ball, &ray), None, "{ray:?}");
            }
        }
    }
}

/// `root_error` is conservative: on random rays against spheres from 1e-3
/// to 1e6 in radius, at coordinates up to 1e6, from origins near and far,
/// with directions of lengths 1e-3 to 1e3, every root `sphere_roots`
/// returns lies within the bound of the exact roots'.
#[test]
fn the_sphere_root_error_bound_is_conservative() {
    use crate::check::exact;
    use glam::DVec3;
    let wide = |p: Vec3| p.as_dvec3();
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let log_uniform = |low: f64, high: f64, r: f64| 10f64.powf(low + (high - low) * r);
    let (mut checked, mut worst) = (0, 0.0f64);
    for _ in 0..200_000 {
        let mut r = || uniform();
        let radius = log_uniform(-3.0, 6.0, r()) as f32;
        let spread = log_uniform(-1.0, 6.0, r());
        let center = Vec3::new(
            ((r() - 0.5) * spread) as f32,
            ((r() - 0.5) * spread) as f32,
            ((r() - 0.5) * spread) as f32,
        );
        // Origins from just off the surface to far away, in any direction.
        let unit = DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize();
        let away = radius as f64 * (1.0 + (r() - 0.5) * log_uniform(-6.0, 2.0, r()));
        let origin = (wide(center) + unit * away).as_vec3();
        // Aimed at a random point of the ball, with a random length.
        let target =
            wide(center) + radius as f64 * 1.2 * DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5);
        let length = log_uniform(-3.0, 3.0, r());
        let dir = ((target - wide(origin)).normalize() * length).as_vec3();
        let (sphere, ray) = (Sphere::new(center, radius), Ray::new(origin, dir));
        let (Some(roots), Some(exact)) = (
            sphere_roots(&sphere, &ray),
            exact::sphere_roots(wide(center), radius as f64, wide(origin), wide(dir)),
        ) else {
            continue;
        };
        for (t, t_ref) in [(roots.0, exact.0), (roots.1, exact.1)] {
            let bound = root_error(&sphere, &ray, roots, t) as f64;
            let off = (t as f64 - t_ref).abs();
            worst = worst.max(off / bound);
            assert!(
                off <= bound,
                "{sphere:?} {ray:?}: t = {t}, exact {t_ref}, off by {off:e} > bound {bound:e}"
            );
            checked += 1;
        }
    }
    println!("{checked} roots, worst error {worst:.3} of the bound");
    assert!(checked > 100_000, "{checked}");
}
