//! Tests of chapter 8's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

use super::*;

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-6
}

#[test]
fn normal_incidence_goes_straight_through() {
    let t = refract(Vec3::new(0.0, -2.0, 0.0), Vec3::Y, 1.0 / 1.5);
    assert_eq!(t, Some(-Vec3::Y));
}

#[test]
fn air_to_glass_at_45_degrees() {
    // sin t = sin(45) / 1.5 = 0.471405, cos t = sqrt(1 - 0.222222) = 0.881917.
    let d = Vec3::new(1.0, -1.0, 0.0);
    let t = refract(d, Vec3::Y, 1.0 / 1.5).expect("refracts");
    assert!(close(t, Vec3::new(0.471_404_5, -0.881_917_1, 0.0)), "{t}");
    // The normal's length and orientation do not matter.
    assert_eq!(refract(d, -3.0 * Vec3::Y, 1.0 / 1.5), Some(t));
}

#[test]
fn glass_to_air_bends_away_from_the_normal() {
    // sin i = 0.4, sin t = 0.6, cos t = 0.8.
    let d = Vec3::new(0.4, (1.0f32 - 0.16).sqrt(), 0.0);
    let t = refract(d, Vec3::Y, 1.5).expect("below the critical angle");
    assert!(close(t, Vec3::new(0.6, 0.8, 0.0)), "{t}");
}

#[test]
fn critical_angle_of_glass_and_total_internal_reflection() {
    let critical = critical_angle(1.5, 1.0).expect("glass to air has one");
    assert!((critical - (1.0f32 / 1.5).asin()).abs() < 1e-6);
    assert_eq!(critical_angle(1.0, 1.5), None);
    let at = |angle: f32| Vec3::new(angle.sin(), angle.cos(), 0.0);
    assert!(refract(at(critical - 1e-3), Vec3::Y, 1.5).is_some());
    assert_eq!(refract(at(critical + 1e-3), Vec3::Y, 1.5), None);
}

#[test]
fn same_medium_is_an_exact_no_op() {
    // A unit direction comes back bit for bit, whatever its last bits.
    for d in [
        Vec3::new(0.6, -0.8, 0.0),
        Vec3::new(0.3, -0.5, 0.8).normalize(),
        Vec3::new(-1e-3, -1.0, 2e-4).normalize(),
    ] {
        assert_eq!(refract(d, Vec3::Y, 1.0), Some(d));
    }
    // A longer one comes back unit: (0, -2, 0) -> (0, -1, 0) exactly.
    assert_eq!(
        refract(Vec3::new(0.0, -2.0, 0.0), Vec3::X, 1.0),
        Some(-Vec3::Y)
    );
}

#[test]
fn degenerate_input_gives_none() {
    let d = Vec3::new(1.0, -1.0, 0.0);
    assert_eq!(refract(d, Vec3::ZERO, 0.7), None);
    assert_eq!(refract(d, Vec3::new(f32::NAN, 1.0, 0.0), 0.7), None);
    assert_eq!(refract(Vec3::ZERO, Vec3::Y, 0.7), None);
    assert_eq!(refract(d, Vec3::Y, 0.0), None);
    assert_eq!(refract(d, Vec3::Y, f32::INFINITY), None);
    assert_eq!(refract(d, Vec3::Y, f32::NAN), None);
}

#[test]
fn no_critical_angle_for_a_non_finite_index() {
    for value in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(critical_angle(value, 1.0), None, "n1 = {value}");
        assert_eq!(critical_angle(1.5, value), None, "n2 = {value}");
    }
}
