//! Tests of chapter 12's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

use super::*;
use crate::chapters::Reference;
use crate::check::exact::{self, wide};
use crate::shapes::{March, Sdf};
use proptest::prelude::*;

fn surface(tree: Sdf) -> Implicit {
    Implicit::new(tree).expect("a valid tree")
}

/// The closed form of a lone sphere or torus, where the tree is one.
fn closed_form(tree: &Sdf, ray: &Ray, t_min: f32, t_max: f32, grow: f64) -> Option<Option<f64>> {
    let (o, d) = (wide(ray.origin), wide(ray.dir));
    let (low, high) = (f64::from(t_min), f64::from(t_max));
    match tree {
        Sdf::Sphere { center, radius } => Some(exact::sphere(
            wide(*center),
            f64::from(*radius) + grow,
            o,
            d,
            low,
            high,
        )),
        Sdf::Torus {
            center,
            major,
            minor,
        } => Some(exact::torus(
            wide(*center),
            f64::from(*major),
            f64::from(*minor) + grow,
            o,
            d,
            low,
            high,
        )),
        _ => None,
    }
}

/// Every ray the built-in scene's render casts, at each lone torus and
/// sphere of the scene: the reference (march, then Newton) agrees with the
/// closed forms (the torus's quartic solved in `f64`, chapter 2's sphere in
/// `f64`). Hit against hit: `t` within `1e-5` of itself, or a ray that
/// only skims the surface (the surface shrunk by the march's cone, twice
/// `tolerance t |d|`, is missed), where the march may stop anywhere along
/// the stretch within the cone. Hit against miss: only where the surface
/// grown and shrunk by the cone disagree. The skims must stay rare.
#[test]
fn every_ray_of_the_scene_meets_the_torus_and_sphere_where_the_closed_forms_do() {
    let scene = crate::builtin::scene(12).expect("the built-in scene");
    let stage = crate::Stage::new(&scene, 12, scene.render).expect("valid settings");
    let rays = crate::record_rays(&stage);
    let lone: Vec<&Implicit> = stage
        .shapes()
        .iter()
        .filter_map(|shape| shape.as_implicit())
        .filter(|surface| matches!(surface.tree(), Sdf::Sphere { .. } | Sdf::Torus { .. }))
        .collect();
    assert_eq!(lone.len(), 2, "the scene's torus and mirror sphere");
    let (mut compared, mut skims, mut worst) = (0u64, 0u64, 0.0f64);
    for cast in &rays {
        for surface in &lone {
            let ray = &cast.ray;
            let ours = intersect_implicit::<Reference>(surface, ray, cast.t_min, cast.t_max);
            let tree = surface.tree();
            let exact = closed_form(tree, ray, cast.t_min, cast.t_max, 0.0).flatten();
            compared += 1;
            match (ours, exact) {
                (Some(t), Some(e)) => {
                    let error = (f64::from(t) - e).abs() / e.max(1.0);
                    if error <= 1e-5 {
                        worst = worst.max(error);
                        continue;
                    }
                    // A ray that skims the surface without crossing it
                    // there is within the cone for a stretch, where the
                    // march may stop: its point is within the cone of the
                    // surface, and the surface shrunk by the cone is not
                    // crossed before it.
                    let t = f64::from(t);
                    let cone =
                        2.0 * f64::from(surface.march().tolerance) * t * wide(ray.dir).length();
                    let at = exact::sdf_distance(tree, wide(ray.origin) + t * wide(ray.dir));
                    let shrunk = closed_form(tree, ray, cast.t_min, cast.t_max, -cone).flatten();
                    assert!(
                        at.abs() <= cone && shrunk.is_none_or(|root| root > t),
                        "{cast:?}: ours {t}, exact {e}, f there {at}, cone {cone}"
                    );
                    skims += 1;
                }
                (None, None) => {}
                (ours, exact) => {
                    let t = ours.map_or_else(|| exact.unwrap_or(0.0), f64::from);
                    let cone =
                        2.0 * f64::from(surface.march().tolerance) * t * wide(ray.dir).length();
                    let grown = closed_form(tree, ray, cast.t_min, cast.t_max, cone).flatten();
                    let shrunk = closed_form(tree, ray, cast.t_min, cast.t_max, -cone).flatten();
                    assert!(
                        grown.is_some() != shrunk.is_some(),
                        "{cast:?}: ours {ours:?}, exact {exact:?}, not within the cone {cone}"
                    );
                    skims += 1;
                }
            }
        }
    }
    println!(
        "{compared} ray-surface pairs, {skims} within the cone, worst relative t error {worst:e}"
    );
    assert!(
        skims * 1000 < compared,
        "{skims} of {compared} skim the surface"
    );
}

/// Where a render's steps go: the marches that spend the most evaluations
/// (128 or more, half the default budget) are the camera rays that pass
/// close to a silhouette. Each surface of the built-in scene, alone, at
/// every pixel's centre: a costly march is "at a silhouette" when a pixel
/// within 2 of it sees that surface at a depth 10% or more away, or does
/// not see it at all: the edge of the surface or a fold of it, where it
/// hides a part of itself (the inner rim of the torus, a bump). The
/// others hit it at a slant.
#[test]
fn the_costliest_marches_are_at_silhouettes() {
    let scene = crate::builtin::scene(12).expect("the built-in scene");
    let stage = crate::Stage::new(&scene, 12, scene.render).expect("valid settings");
    let (width, height) = (scene.render.width as usize, scene.render.height as usize);
    let (mut costly, mut at_silhouette, mut marches) = (0usize, 0usize, 0usize);
    let (mut slanted, mut steepest) = (0usize, 0.0f32);
    let mut costly_evaluations = 0u64;
    let mut all_evaluations = 0u64;
    for surface in stage
        .shapes()
        .iter()
        .filter_map(|shape| shape.as_implicit())
    {
        let mut depths = vec![f32::INFINITY; width * height];
        let mut spent = vec![0u64; width * height];
        for y in 0..height {
            for x in 0..width {
                let ray = stage.camera().ray_through(x as f32 + 0.5, y as f32 + 0.5);
                let before = crate::shapes::evaluations();
                let hit = intersect_implicit::<Reference>(surface, &ray, 0.0, f32::INFINITY);
                depths[y * width + x] = hit.unwrap_or(f32::INFINITY);
                spent[y * width + x] = crate::shapes::evaluations() - before;
            }
        }
        for y in 0..height {
            for x in 0..width {
                let evaluations = spent[y * width + x];
                marches += usize::from(evaluations > 0);
                all_evaluations += evaluations;
                if evaluations < 128 {
                    continue;
                }
                costly += 1;
                costly_evaluations += evaluations;
                let depth = depths[y * width + x];
                let edge = (y.saturating_sub(2)..(y + 3).min(height)).any(|near_y| {
                    (x.saturating_sub(2)..(x + 3).min(width)).any(|near_x| {
                        let near = depths[near_y * width + near_x];
                        !((near - depth).abs() < 0.1 * depth.min(near))
                    })
                });
                at_silhouette += usize::from(edge);
                if !edge {
                    // Not at an edge: then the ray meets the surface at a
                    // slant, more than 60 degrees from its normal, after
                    // running close to it.
                    let ray = stage.camera().ray_through(x as f32 + 0.5, y as f32 + 0.5);
                    let normal = surface.gradient(ray.at(depth)).normalize_or_zero();
                    let cosine = normal.dot(ray.dir.normalize()).abs();
                    slanted += usize::from(cosine < 0.5);
                    steepest = steepest.max(cosine);
                }
            }
        }
    }
    println!(
        "{costly} of {marches} camera-ray marches made 128 evaluations or more \
         ({costly_evaluations} of the {all_evaluations} evaluations): {at_silhouette} within \
         2 pixels of a silhouette, {slanted} hits at a slant (cosine at most {steepest})"
    );
    assert!(costly > 0, "no march spent 128 evaluations");
    assert!(
        at_silhouette * 4 >= costly * 3 && at_silhouette + slanted == costly,
        "{at_silhouette} of {costly} costly marches at a silhouette, {slanted} at a slant"
    );
}

/// Random exact primitives, moved about.
fn primitive() -> impl Strategy<Value = Sdf> {
    let point =
        || (-2.0f32..2.0, -2.0f32..2.0, -2.0f32..2.0).prop_map(|(x, y, z)| Vec3::new(x, y, z));
    let size = || 0.1f32..1.5;
    prop_oneof![
        (point(), size()).prop_map(|(center, radius)| Sdf::Sphere { center, radius }),
        (point(), size(), size(), size()).prop_map(|(center, x, y, z)| Sdf::Box {
            center,
            half_size: Vec3::new(x, y, z)
        }),
        (point(), size(), 0.05f32..1.0).prop_map(|(center, major, share)| Sdf::Torus {
            center,
            major,
            minor: major * share,
        }),
        (point(), point(), size()).prop_map(|(a, b, radius)| Sdf::Capsule {
            a,
            b: b + Vec3::splat(0.01),
            radius,
        }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 512,
        rng_seed: proptest::test_runner::RngSeed::Fixed(12),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Sphere tracing never reports a hit past the first root of an exact
    /// surface: each step stays inside a ball free of the surface. The
    /// root is the `f64` safe march's (`exact::first_crossing`); a hit
    /// where it finds none is a ray within the cone of the surface.
    #[test]
    fn sphere_tracing_never_steps_past_the_first_root(
        tree in primitive(),
        from in (-6.0f32..6.0, -6.0f32..6.0, -6.0f32..6.0),
        toward in (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
    ) {
        let surface = surface(tree);
        let origin = Vec3::new(from.0, from.1, from.2);
        let target = Vec3::new(toward.0, toward.1, toward.2);
        prop_assume!(origin.distance(target) > 0.1);
        let ray = Ray::new(origin, target - origin);
        let ours = sphere_trace(&surface, &ray, 0.0, f32::INFINITY);
        let root = exact::first_crossing(surface.tree(), 1.0, wide(ray.origin), wide(ray.dir), 0.0, 1e9);
        if let Some(t) = ours {
            match root {
                Some(root) => prop_assert!(
                    f64::from(t) <= root * (1.0 + 1e-5) + 1e-5,
                    "ours {t}, first root {root}"
                ),
                None => {
                    let at = exact::sdf_distance(surface.tree(), wide(ray.at(t)));
                    let cone = 2.0 * f64::from(surface.march().tolerance) * f64::from(t)
                        * wide(ray.dir).length();
                    prop_assert!(at.abs() <= cone + 1e-5, "ours {t} where f = {at}, no root");
                }
            }
        }
    }
}

#[test]
fn newton_keeps_the_converged_digits() {
    let g = |t: f32| (t * t - 2.0, 2.0 * t);
    let bracket = Bracket {
        low: 1.0,
        high: 2.0,
    };
    let settled = newton_bracketed(&g, bracket, 0.0, 4);
    for iterations in 5..=12 {
        assert_eq!(newton_bracketed(&g, bracket, 0.0, iterations), settled);
    }
    assert!((f64::from(settled) - std::f64::consts::SQRT_2).abs() < 2e-7);
}

#[test]
fn the_normal_methods_agree_on_a_smooth_surface() {
    let point = Vec3::new(0.6, 0.8, 0.0);
    let unit = Sdf::Sphere {
        center: Vec3::ZERO,
        radius: 1.0,
    };
    for normal in [
        NormalMethod::Analytic,
        NormalMethod::Central,
        NormalMethod::Tetrahedron,
    ] {
        let march = March {
            normal,
            ..March::default()
        };
        let found = implicit_normal(&surface(unit.clone()).with_march(march), point);
        assert!((found - point).length() < 1e-3, "{normal:?}: {found}");
    }
}

/// `grade --code --fresh` scales each march, Newton and normal checkpoint
/// by a power of two: the reference must pass every draw, or a correct
/// student would fail one.
#[test]
fn the_reference_passes_every_fresh_draw_of_the_checkpoints() {
    use crate::check::Outcome;
    for seed in 1..=10 {
        for case in crate::check::by_chapter::checkpoints(12) {
            if let Some(fresh) = case.fresh(seed) {
                assert_eq!(
                    fresh.run::<Reference>(),
                    Outcome::Pass,
                    "{} under seed {seed}: {}",
                    case.name,
                    fresh.kind.inputs()
                );
            }
        }
    }
}

// The bug gallery and the accepted alternatives of this chapter.
#[path = "gallery.rs"]
mod gallery;
