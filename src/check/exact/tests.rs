//! Tests of the `f64` oracle's torus, beside it: rays worked by hand, and
//! random rays against a scan of the polynomial along the ray.

use super::*;

fn first_hit(o: [f64; 3], d: [f64; 3], t_min: f64) -> Option<f64> {
    torus(
        DVec3::ZERO,
        1.0,
        0.25,
        DVec3::from(o),
        DVec3::from(d),
        t_min,
        f64::INFINITY,
    )
}

/// Within a few roundings of `expected`.
fn near(found: Option<f64>, expected: f64) -> bool {
    found.is_some_and(|t| (t - expected).abs() <= 4.0 * f64::EPSILON * (1.0 + expected.abs()))
}

#[test]
fn rays_worked_by_hand() {
    // Along the x axis through the centre: the tube's four walls, at
    // x = -1.25, -0.75, 0.75 and 1.25.
    for (t_min, expected) in [(0.0, 3.75), (3.8, 4.25), (4.3, 5.75), (6.0, 6.25)] {
        let found = first_hit([-5.0, 0.0, 0.0], [1.0, 0.0, 0.0], t_min);
        assert!(near(found, expected), "{found:?} for {expected}");
    }
    assert_eq!(first_hit([-5.0, 0.0, 0.0], [1.0, 0.0, 0.0], 6.3), None);
    // Down the axis, through the hole.
    assert_eq!(first_hit([0.0, 5.0, 0.0], [0.0, -1.0, 0.0], 0.0), None);
    // Down onto the top of the tube.
    assert!(near(
        first_hit([1.0, 5.0, 0.0], [0.0, -1.0, 0.0], 0.0),
        4.75
    ));
    // A long direction: t in its units.
    assert!(near(
        first_hit([-5.0, 0.0, 0.0], [1e3, 0.0, 0.0], 0.0),
        3.75e-3
    ));
    // A million units away: the line is moved to the centre first.
    let far = first_hit([-1e6, 0.0, 0.0], [1.0, 0.0, 0.0], 0.0).expect("a hit");
    assert!((far - (1e6 - 1.25)).abs() < 1e-9, "{far}");
    // Beside the torus, above it, and a zero direction.
    assert_eq!(first_hit([-5.0, 0.3, 0.0], [1.0, 0.0, 0.0], 0.0), None);
    assert_eq!(first_hit([-5.0, 0.0, 0.0], [0.0, 0.0, 0.0], 0.0), None);
}

/// For random lines near a torus, the oracle's first crossing is never
/// after the first sign change a fine scan of the polynomial finds, and
/// wherever it answers, the polynomial changes sign there.
#[test]
fn the_first_root_agrees_with_a_scan_of_the_polynomial() {
    let mut random = Xorshift::new(5);
    let (major, minor) = (1.0, 0.3);
    let mut hits = 0;
    for _ in 0..2000 {
        let o = DVec3::new(
            f64::from(random.between(-4.0, 4.0)),
            f64::from(random.between(-2.0, 2.0)),
            f64::from(random.between(-4.0, 4.0)),
        );
        let aim = DVec3::new(
            f64::from(random.between(-1.3, 1.3)),
            f64::from(random.between(-0.3, 0.3)),
            f64::from(random.between(-1.3, 1.3)),
        );
        let d = aim - o;
        let found = torus(DVec3::ZERO, major, minor, o, d, 0.0, 3.0);
        let on_line = |t: f64| torus_polynomial(major, minor, o + t * d);
        let steps = 30_000;
        let scanned = (0..steps).find_map(|step| {
            let (from, to) = (
                3.0 * step as f64 / steps as f64,
                3.0 * (step + 1) as f64 / steps as f64,
            );
            (on_line(from) * on_line(to) < 0.0)
                .then(|| bisect(on_line, from, to))
                .flatten()
        });
        match (found, scanned) {
            (Some(t), _) => {
                hits += 1;
                let step = 1e-9 * (1.0 + t);
                assert!(
                    on_line(t - step) * on_line(t + step) <= 0.0,
                    "no crossing at {t}"
                );
                if let Some(scan) = scanned {
                    assert!(t <= scan + 1e-12, "oracle {t} after the scan's {scan}");
                }
            }
            (None, Some(scan)) => panic!("the scan crosses at {scan}, the oracle finds nothing"),
            (None, None) => {}
        }
    }
    assert!(
        hits > 500,
        "{hits} hits of 2000: the rays should mostly hit"
    );
}
