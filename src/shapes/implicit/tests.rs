//! Tests of the implicit surfaces' functions, beside them: the facts a
//! tracer relies on (the Lipschitz bound, the box, the gradient) checked on
//! random trees, and each primitive's distance at points worked by hand.

use super::*;
use proptest::prelude::*;

fn sphere(center: [f32; 3], radius: f32) -> Sdf {
    Sdf::Sphere {
        center: Vec3::from(center),
        radius,
    }
}

fn torus() -> Sdf {
    Sdf::Torus {
        center: Vec3::new(0.0, 1.0, 0.0),
        major: 1.0,
        minor: 0.25,
    }
}

#[test]
fn primitives_are_their_distances_at_points_worked_by_hand() {
    let close =
        |got: f32, expected: f32| assert!((got - expected).abs() < 1e-6, "{got} {expected}");
    close(
        sphere([1.0, 0.0, 0.0], 2.0).distance(Vec3::new(1.0, 0.0, 5.0)),
        3.0,
    );
    close(
        sphere([1.0, 0.0, 0.0], 2.0).distance(Vec3::new(1.0, 0.0, 0.0)),
        -2.0,
    );
    let cube = Sdf::Box {
        center: Vec3::ZERO,
        half_size: Vec3::ONE,
    };
    // Beyond a corner: the distance to the corner.
    close(cube.distance(Vec3::new(2.0, 2.0, 2.0)), 3f32.sqrt());
    // Inside: minus the distance to the nearest face.
    close(cube.distance(Vec3::new(0.5, 0.0, 0.0)), -0.5);
    let rounded = Sdf::RoundBox {
        center: Vec3::ZERO,
        half_size: Vec3::ONE,
        radius: 0.5,
    };
    // A face stays where the box's was; a corner moves in by r (sqrt 3 - 1).
    close(rounded.distance(Vec3::new(3.0, 0.0, 0.0)), 2.0);
    close(
        rounded.distance(Vec3::new(2.0, 2.0, 2.0)),
        1.5 * 3f32.sqrt() - 0.5,
    );
    // On the ring inside the tube: minus the tube's radius; on the axis:
    // the distance to the ring's circle, sqrt(1 + 0) - r.
    close(torus().distance(Vec3::new(1.0, 1.0, 0.0)), -0.25);
    close(torus().distance(Vec3::new(0.0, 1.0, 0.0)), 0.75);
    let capsule = Sdf::Capsule {
        a: Vec3::ZERO,
        b: Vec3::new(0.0, 2.0, 0.0),
        radius: 0.5,
    };
    close(capsule.distance(Vec3::new(1.0, 1.0, 0.0)), 0.5);
    close(capsule.distance(Vec3::new(0.0, 4.0, 0.0)), 1.5);
    let floor = Sdf::Plane {
        point: Vec3::ZERO,
        normal: Vec3::Y,
    };
    close(floor.distance(Vec3::new(5.0, -2.0, 1.0)), -2.0);
}

#[test]
fn operations_combine_the_functions() {
    let a = sphere([0.0, 0.0, 0.0], 1.0);
    let b = sphere([1.5, 0.0, 0.0], 1.0);
    let at = Vec3::new(0.75, 0.0, 0.0);
    let union = Sdf::Union(vec![a.clone(), b.clone()]);
    let intersection = Sdf::Intersection(vec![a.clone(), b.clone()]);
    let difference = Sdf::Difference(Box::new(a.clone()), Box::new(b.clone()));
    assert_eq!(union.distance(at), -0.25);
    assert_eq!(intersection.distance(at), -0.25);
    assert_eq!(difference.distance(at), 0.25);
    // Halfway between two equal functions, h = 1/2: min - k/4.
    let smooth = Sdf::SmoothUnion {
        shapes: (Box::new(a), Box::new(b)),
        blend: 0.4,
    };
    assert!((smooth.distance(at) - (-0.25 - 0.1)).abs() < 1e-6);
}

/// Two overlapping spheres blended: the seam bulges above both, by up to
/// a quarter of the blend, and the box grows with it.
#[test]
fn a_smooth_union_reaches_beyond_its_shapes_and_its_box_follows() {
    let blended = Sdf::SmoothUnion {
        shapes: (
            Box::new(sphere([-0.1, 0.0, 0.0], 1.0)),
            Box::new(sphere([0.1, 0.0, 0.0], 1.0)),
        ),
        blend: 1.0,
    };
    let above = Vec3::new(0.0, 1.05, 0.0);
    assert!(blended.distance(above) < 0.0, "{}", blended.distance(above));
    let bounds = blended.bounds().expect("bounded");
    assert!(bounds.max.y >= 1.05, "{bounds:?}");
}

#[test]
fn a_ray_parallel_to_slabs_and_outside_them_misses_the_box() {
    // The torus's box: x and z in [-1.25, 1.25], y in [0.75, 1.25].
    let surface = Implicit::new(torus()).expect("a valid torus");
    let span = |origin: [f32; 3], dir: Vec3| {
        surface.span(&Ray::new(Vec3::from(origin), dir), 0.0, f32::INFINITY)
    };
    // Below the z slab and beyond the x slab, parallel to both: one slab
    // says "never in" (+inf) and the other "out before the start" (-inf).
    assert_eq!(span([3.0, 0.0, -4.0], Vec3::Y), None);
    assert_eq!(span([-3.0, 0.0, 4.0], Vec3::Y), None);
    assert_eq!(span([3.0, 0.0, 0.0], Vec3::Y), None);
    // Inside both, up through the hole: the box's height.
    let (enter, leave) = span([1.0, 0.0, 0.0], Vec3::Y).expect("the ray crosses the box");
    assert!(
        (enter - 0.75).abs() < 1e-5 && (leave - 1.25).abs() < 1e-5,
        "{enter} {leave}"
    );
}

#[test]
fn checks_name_what_is_wrong() {
    let radius = sphere([0.0; 3], -1.0).check();
    assert!(
        matches!(radius, Err(ImplicitError::NotPositive { .. })),
        "{radius:?}"
    );
    assert!(sphere([0.0; 3], f32::NAN).check().is_err());
    assert!(sphere([f32::INFINITY, 0.0, 0.0], 1.0).check().is_err());
    assert!(matches!(
        Sdf::Union(vec![]).check(),
        Err(ImplicitError::Empty { .. })
    ));
    let rounded = Sdf::RoundBox {
        center: Vec3::ZERO,
        half_size: Vec3::new(1.0, 0.2, 1.0),
        radius: 0.3,
    };
    assert!(matches!(
        rounded.check(),
        Err(ImplicitError::TooLarge { .. })
    ));
    let mut deep = sphere([0.0; 3], 1.0);
    for _ in 0..MAX_DEPTH {
        deep = Sdf::Translate {
            offset: Vec3::X,
            shape: Box::new(deep),
        };
    }
    assert_eq!(deep.check(), Err(ImplicitError::TooDeep));
    let wide = Sdf::Union(vec![sphere([0.0; 3], 1.0); MAX_NODES]);
    assert_eq!(wide.check(), Err(ImplicitError::TooManyNodes));
    let flat = Sdf::Capsule {
        a: Vec3::ONE,
        b: Vec3::ONE,
        radius: 1.0,
    };
    assert!(matches!(flat.check(), Err(ImplicitError::Zero { .. })));
    assert_eq!(torus().check(), Ok(()));
}

fn coordinate() -> impl Strategy<Value = f32> {
    -3.0f32..3.0
}

fn point() -> impl Strategy<Value = Vec3> {
    (coordinate(), coordinate(), coordinate()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn size() -> impl Strategy<Value = f32> {
    0.1f32..1.5
}

fn primitive() -> impl Strategy<Value = Sdf> {
    prop_oneof![
        (point(), size()).prop_map(|(center, radius)| Sdf::Sphere { center, radius }),
        (point(), size(), size(), size()).prop_map(|(center, x, y, z)| Sdf::Box {
            center,
            half_size: Vec3::new(x, y, z),
        }),
        (point(), size(), size(), 0.0f32..1.0).prop_map(|(center, x, y, share)| Sdf::RoundBox {
            center,
            half_size: Vec3::new(x, y, x.min(y)),
            radius: share * x.min(y),
        }),
        (point(), size(), size()).prop_map(|(center, major, minor)| Sdf::Torus {
            center,
            major,
            minor,
        }),
        (point(), point(), size()).prop_map(|(a, b, radius)| Sdf::Capsule {
            a,
            b: b + Vec3::splat(0.01),
            radius,
        }),
    ]
}

/// Random trees of up to three levels of operations over primitives.
fn tree() -> impl Strategy<Value = Sdf> {
    primitive().prop_recursive(3, 12, 2, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 1..3).prop_map(Sdf::Union),
            prop::collection::vec(inner.clone(), 1..3).prop_map(Sdf::Intersection),
            (inner.clone(), inner.clone())
                .prop_map(|(kept, removed)| Sdf::Difference(Box::new(kept), Box::new(removed))),
            (inner.clone(), inner.clone(), 0.05f32..1.0).prop_map(|(a, b, blend)| {
                Sdf::SmoothUnion {
                    shapes: (Box::new(a), Box::new(b)),
                    blend,
                }
            }),
            (inner.clone(), point()).prop_map(|(shape, offset)| Sdf::Translate {
                offset,
                shape: Box::new(shape),
            }),
            (inner.clone(), point(), -180.0f32..180.0).prop_map(|(shape, axis, degrees)| {
                Sdf::Rotate {
                    rotation: glam::Quat::from_axis_angle(
                        (axis + Vec3::splat(0.01)).normalize(),
                        degrees.to_radians(),
                    ),
                    shape: Box::new(shape),
                }
            }),
            (inner, 0.01f32..0.3, 1.0f32..20.0).prop_map(|(shape, amplitude, frequency)| {
                Sdf::Displace {
                    amplitude,
                    frequency,
                    shape: Box::new(shape),
                }
            }),
        ]
    })
}

/// The distance from `point` to the box, 0 inside.
fn to_box(bounds: &Aabb, point: Vec3) -> f32 {
    (bounds.min - point)
        .max(point - bounds.max)
        .max(Vec3::ZERO)
        .length()
}

proptest! {
    // A fixed seed: the same trees and points on every run.
    #![proptest_config(ProptestConfig {
        cases: 512,
        rng_seed: proptest::test_runner::RngSeed::Fixed(12),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Every tree the scene may build is L-Lipschitz with its own L: the
    /// fact that makes a step of f/L safe. Pairs of points a short step
    /// apart along the gradient, where the function changes fastest, and
    /// pairs anywhere; rounding adds a few ulps of the values involved.
    #[test]
    fn no_function_changes_faster_than_its_lipschitz_constant(
        shape in tree(), from in point(), to in point(), step in 1e-3f32..0.1
    ) {
        prop_assume!(shape.check().is_ok());
        let along = from + shape.gradient(from).normalize_or_zero() * step;
        for to in [to, along] {
            let change = (shape.distance(from) - shape.distance(to)).abs();
            let allowed = shape.lipschitz() * from.distance(to);
            prop_assert!(
                change <= allowed * (1.0 + 1e-3) + 1e-5,
                "change {change} over {} with L {}", from.distance(to), shape.lipschitz()
            );
        }
    }

    /// Outside its box, a tree's function is at least the distance to the
    /// box: no surface and no inside beyond it. Points up to half the box's
    /// size beyond it, where a box too small shows first.
    #[test]
    fn outside_its_box_a_function_is_at_least_the_distance_to_it(
        shape in tree(), at in point()
    ) {
        prop_assume!(shape.check().is_ok());
        let Some(bounds) = shape.bounds() else { return Ok(()) };
        let (centre, half) = ((bounds.min + bounds.max) / 2.0, (bounds.max - bounds.min) / 2.0);
        let near = centre + half * (at / 3.0) * 1.5;
        let outside = to_box(&bounds, near);
        prop_assume!(outside > 0.0);
        prop_assert!(
            shape.distance(near) >= outside * (1.0 - 1e-5) - 1e-5,
            "f = {} at {} from {bounds:?}", shape.distance(near), outside
        );
    }

    /// The exact primitives' functions are distances: never more than the
    /// distance to a point found on the surface, by walking the gradient.
    #[test]
    fn an_exact_function_is_never_more_than_the_distance_to_the_surface(
        shape in primitive(), at in point()
    ) {
        let value = shape.distance(at);
        // One step along the gradient lands on the surface of an exact
        // distance function, at exactly |f| away.
        let landed = at - shape.gradient(at) * value;
        prop_assert!(shape.distance(landed).abs() <= 1e-4 * (1.0 + value.abs()),
            "f = {} after a step of {value}", shape.distance(landed));
    }

    /// Where the function is smooth, the formula's gradient is the
    /// function's: central differences agree. Smoothness is told by the
    /// differences alone (two step sizes agree: no kink of a box, a union
    /// or a clamp lies between), never by the gradient under test.
    #[test]
    fn gradients_match_central_differences(shape in tree(), at in point()) {
        prop_assume!(shape.check().is_ok());
        let differences = |step: f32| Vec3::new(
            shape.distance(at + Vec3::X * step) - shape.distance(at - Vec3::X * step),
            shape.distance(at + Vec3::Y * step) - shape.distance(at - Vec3::Y * step),
            shape.distance(at + Vec3::Z * step) - shape.distance(at - Vec3::Z * step),
        ) / (2.0 * step);
        let (coarse, fine) = (differences(2e-3), differences(1e-3));
        let tolerance = 0.02 * (1.0 + shape.lipschitz());
        prop_assume!((coarse - fine).length() < tolerance / 4.0);
        let gradient = shape.gradient(at);
        prop_assert!(
            (fine - gradient).length() <= tolerance,
            "differences {fine}, formula {gradient}"
        );
    }
}
