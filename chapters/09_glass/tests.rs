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

// The bug gallery and the accepted alternatives of this chapter.
#[path = "gallery.rs"]
mod gallery;
