//! Tests of chapter 6's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

use super::*;

#[test]
fn bounce_off_the_floor() {
    let r = reflect(Vec3::new(1.0, -1.0, 0.0), Vec3::Y);
    assert_eq!(r, Vec3::new(1.0, 1.0, 0.0));
}

#[test]
fn normal_length_and_orientation_do_not_matter() {
    let d = Vec3::new(1.0, -2.0, 3.0);
    let expected = Vec3::new(1.0, 2.0, 3.0);
    assert_eq!(reflect(d, Vec3::new(0.0, 7.0, 0.0)), expected);
    assert_eq!(reflect(d, Vec3::new(0.0, -0.25, 0.0)), expected);
}

#[test]
fn huge_directions_do_not_overflow() {
    // 2 (d.n) = -6e38 is beyond f32::MAX, the answer is not.
    let r = reflect(Vec3::new(3e38, -3e38, 0.0), Vec3::Y);
    assert_eq!(r, Vec3::new(3e38, 3e38, 0.0));
    // d parallel to n, with |d| itself beyond f32::MAX: d comes back.
    let d = Vec3::splat(3e38);
    assert_eq!(reflect(d, Vec3::ONE), -d);
}

#[test]
fn normal_incidence_sends_the_ray_back() {
    assert_eq!(
        reflect(Vec3::new(0.0, 0.0, -2.0), Vec3::Z),
        Vec3::new(0.0, 0.0, 2.0)
    );
}

#[test]
fn slanted_mirror() {
    // A mirror at 45 degrees turns +x into +y.
    let r = reflect(Vec3::X, Vec3::new(-1.0, 1.0, 0.0));
    assert!((r - Vec3::Y).abs().max_element() < 1e-6);
}

#[test]
fn degenerate_normal_gives_nan() {
    assert!(reflect(Vec3::X, Vec3::ZERO).is_nan());
    assert!(reflect(Vec3::X, Vec3::new(f32::INFINITY, 0.0, 0.0)).is_nan());
}

#[test]
fn non_finite_direction_gives_nan() {
    // An infinite component once sent the rescaling into endless
    // recursion: inf / 2^64 is still inf.
    assert!(reflect(Vec3::new(f32::INFINITY, -1.0, 0.0), Vec3::Y).is_nan());
    assert!(reflect(Vec3::new(0.0, f32::NEG_INFINITY, 0.0), Vec3::Y).is_nan());
    assert!(reflect(Vec3::new(f32::NAN, -1.0, 0.0), Vec3::Y).is_nan());
}
