//! Tests of chapter 5's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

use super::*;

const WHITE: Vec3 = Vec3::ONE;

fn material(diffuse: f32, specular: f32, shininess: u32) -> Material {
    Material {
        diffuse,
        specular,
        shininess,
        ..Material::default()
    }
}

#[test]
fn ambient_term_is_albedo_times_coefficient_times_ambient_light() {
    let a = ambient_term(Vec3::new(1.0, 0.5, 0.0), 0.1, Vec3::new(1.0, 1.0, 0.5));
    assert_eq!(a, Vec3::new(0.1, 0.05, 0.0));
}

#[test]
fn diffuse_follows_the_cosine_law() {
    let albedo = Vec3::new(1.0, 0.5, 0.25);
    // Light at 60 degrees from the normal: cos = 1/2.
    let to_light = Vec3::new(3f32.sqrt() / 2.0, 0.5, 0.0);
    let terms = phong_terms(
        &material(0.8, 0.0, 1),
        albedo,
        Vec3::Y,
        to_light,
        Vec3::Y,
        WHITE,
    );
    let expected = albedo * 0.8 * to_light.y;
    assert!((terms.diffuse - expected).abs().max_element() < 1e-6);
    assert_eq!(terms.specular, Vec3::ZERO);
}

#[test]
fn specular_peaks_in_the_mirror_direction() {
    let to_light = Vec3::new(-1.0, 1.0, 0.0).normalize();
    let mirror = Vec3::new(1.0, 1.0, 0.0).normalize();
    let terms = phong_terms(
        &material(0.0, 0.5, 10),
        Vec3::ONE,
        Vec3::Y,
        to_light,
        mirror,
        WHITE,
    );
    assert!((terms.specular - Vec3::splat(0.5)).abs().max_element() < 1e-6);
    // 30 degrees off the mirror direction: 0.5 * cos(30)^10.
    let off = Vec3::new(0.5, 3f32.sqrt() / 2.0, 0.0);
    let reflected = Vec3::new(1.0, 1.0, 0.0).normalize();
    let cos = off.dot(reflected) as f64;
    let terms = phong_terms(
        &material(0.0, 0.5, 10),
        Vec3::ONE,
        Vec3::Y,
        to_light,
        off,
        WHITE,
    );
    let expected = 0.5 * cos.powi(10);
    assert!((terms.specular.x as f64 - expected).abs() < 1e-6);
}

#[test]
fn light_behind_the_surface_adds_nothing() {
    let terms = phong_terms(
        &material(1.0, 1.0, 8),
        Vec3::ONE,
        Vec3::Y,
        -Vec3::Y,
        Vec3::Y,
        WHITE,
    );
    assert_eq!(terms.diffuse, Vec3::ZERO);
    assert_eq!(terms.specular, Vec3::ZERO);
}

#[test]
fn whole_powers() {
    assert_eq!(pow_whole(2.0, 0), 1.0);
    assert_eq!(pow_whole(2.0, 10), 1024.0);
    assert_eq!(pow_whole(0.5, 3), 0.125);
    assert_eq!(pow_whole(0.0, 5), 0.0);
}

#[test]
fn non_finite_colours_give_non_finite_ambient_and_powers_follow_powf() {
    for value in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        for axis in 0..3 {
            let mut colour = [0.5, 0.6, 0.7];
            colour[axis] = value;
            let spoilt = Vec3::from(colour);
            assert!(
                !ambient_term(spoilt, 0.1, WHITE).is_finite(),
                "albedo {spoilt}"
            );
            assert!(
                !ambient_term(WHITE, 0.1, spoilt).is_finite(),
                "light {spoilt}"
            );
        }
    }
    assert!(pow_whole(f32::NAN, 3).is_nan());
    assert_eq!(pow_whole(f32::INFINITY, 3), f32::INFINITY);
    assert_eq!(pow_whole(f32::NAN, 0), 1.0, "x^0 = 1 for every x, as powf");
}
