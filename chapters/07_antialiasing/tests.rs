//! Tests of chapter 7's reference code, beside it (they may use its
//! private helpers: this is a child module of `chapter.rs`).

use super::*;

#[test]
fn grid_of_four_hits_the_quarter_centres() {
    let positions: Vec<_> = (0..4)
        .map(|i| sample_offset(Sampling::Grid, 4, i, (3, 7), 1))
        .collect();
    assert_eq!(
        positions,
        vec![(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)]
    );
}

#[test]
fn jittered_samples_stay_in_their_cells() {
    for index in 0..16 {
        let (x, y) = sample_offset(Sampling::Jittered, 16, index, (10, 20), 42);
        let (column, row) = ((index % 4) as f32, (index / 4) as f32);
        assert!(x >= column / 4.0 && x < (column + 1.0) / 4.0, "x = {x}");
        assert!(y >= row / 4.0 && y < (row + 1.0) / 4.0, "y = {y}");
    }
}

#[test]
fn a_jittered_sample_never_reaches_the_next_pixel() {
    // Here 1 + r rounds to 2 in f32: without the clamp, dx would be 1.0.
    let (dx, _) = sample_offset(Sampling::Jittered, 4, 1, (109_417, 17), 0);
    assert_eq!(dx, 1.0 - f32::EPSILON / 2.0);
    for x in 0..20_000 {
        for index in 0..4 {
            let (dx, dy) = sample_offset(Sampling::Jittered, 4, index, (x, 3), 0);
            assert!((0.0..1.0).contains(&dx) && (0.0..1.0).contains(&dy));
        }
    }
}

#[test]
fn random_samples_depend_only_on_pixel_sample_and_seed() {
    let a = sample_offset(Sampling::Random, 4, 2, (5, 6), 9);
    assert_eq!(a, sample_offset(Sampling::Random, 4, 2, (5, 6), 9));
    assert_ne!(a, sample_offset(Sampling::Random, 4, 2, (6, 5), 9));
    assert_ne!(a, sample_offset(Sampling::Random, 4, 3, (5, 6), 9));
    assert_ne!(a, sample_offset(Sampling::Random, 4, 2, (5, 6), 10));
}

#[test]
fn unit_random_is_in_range_and_roughly_uniform() {
    let values: Vec<f32> = (0..10_000).map(|i| unit_random(7, (i, 0), 0, 0)).collect();
    assert!(values.iter().all(|v| (0.0..1.0).contains(v)));
    let mean = values.iter().sum::<f32>() / values.len() as f32;
    assert!((mean - 0.5).abs() < 0.02, "mean {mean}");
    let below_tenth = values.iter().filter(|v| **v < 0.1).count();
    assert!(
        (800..1200).contains(&below_tenth),
        "{below_tenth} below 0.1"
    );
}

/// The inputs of one random number: pixel, sample index, dimension.
type Inputs = ((u32, u32), u32, u32);

/// The inputs next to some inputs, in one direction.
type Neighbour = fn(Inputs) -> Inputs;

/// How far a random number from `random` is from the strict avalanche
/// criterion on the inputs that sit side by side in an image: for 2^16
/// inputs, the pixel beside, the pixel below, the next sample and the
/// other dimension should flip each of the 24 bits of the number with
/// probability 1/2. A bit's count of flips is then binomial, with a
/// standard error of 128 flips; the largest of the 96 deviations, in
/// standard errors, with what it was measured on and the bit.
fn avalanche_deviation(random: impl Fn(Inputs) -> f32) -> (f64, &'static str, usize) {
    let bits = |value: f32| (value * (1u32 << 24) as f32) as u32;
    let inputs: Vec<Inputs> = (0..1u32 << 16)
        .map(|i| ((i % 256, i / 256), i % 3, 0))
        .collect();
    let neighbours: [(&str, Neighbour); 4] = [
        ("the pixel beside", |((x, y), i, d)| ((x + 1, y), i, d)),
        ("the pixel below", |((x, y), i, d)| ((x, y + 1), i, d)),
        ("the next sample", |(p, i, d)| (p, i + 1, d)),
        ("the other dimension", |(p, i, d)| (p, i, d + 1)),
    ];
    let trials = inputs.len() as f64;
    let mut worst = (0.0, "", 0);
    for (what, neighbour) in neighbours {
        let mut flips = [0u32; 24];
        for &input in &inputs {
            let changed = bits(random(input)) ^ bits(random(neighbour(input)));
            for (bit, count) in flips.iter_mut().enumerate() {
                *count += (changed >> bit) & 1;
            }
        }
        for (bit, &count) in flips.iter().enumerate() {
            let deviation = ((f64::from(count) - trials / 2.0) / (trials / 4.0).sqrt()).abs();
            if deviation > worst.0 {
                worst = (deviation, what, bit);
            }
        }
    }
    worst
}

/// 5 standard errors bound the largest of 96 deviations of a good hash (a
/// false alarm about once in 10^4 inputs sets).
const AVALANCHE_LIMIT: f64 = 5.0;

#[test]
fn neighbouring_inputs_flip_every_bit_half_the_time() {
    let (deviation, what, bit) =
        avalanche_deviation(|(pixel, index, dimension)| unit_random(11, pixel, index, dimension));
    assert!(
        deviation < AVALANCHE_LIMIT,
        "{what}: bit {bit} is {deviation:.1} standard errors from flipping half the time"
    );
}

/// `unit_random` with another finalizer in place of `mix`.
fn unit_random_mixed_by(finalize: fn(u64) -> u64, (pixel, index, dimension): Inputs) -> f32 {
    let mut word = 11 ^ 0x9E37_79B9_7F4A_7C15;
    for part in [pixel.0, pixel.1, index, dimension] {
        word = finalize(word ^ u64::from(part));
    }
    (word >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

/// SplitMix64's finalizer with the operator of one of its xor-shifts
/// replaced (`step` 0, 1 or 2, each by `shift_left`, or by `|` or `&`
/// for `^`), as a mutation of `mix` does.
fn weakened_mix(z: u64, step: usize, weaken: fn(u64, u32) -> u64) -> u64 {
    let mut z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let shift = |z: u64, at: usize, by: u32| {
        if at == step {
            weaken(z, by)
        } else {
            z ^ (z >> by)
        }
    };
    z = shift(z, 0, 30).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = shift(z, 1, 27).wrapping_mul(0x94D0_49BB_1331_11EB);
    shift(z, 2, 31)
}

/// The six survivors of `mix` listed in `equivalent-mutants.txt` give
/// random numbers no neighbouring input tells from the reference's: the
/// same test as above passes them all. A finalizer without its xor-shifts
/// shows the test's power: it fails by far.
#[test]
fn weakened_finalizers_pass_the_avalanche_test_and_no_finalizer_fails_it() {
    let same = unit_random_mixed_by(mix, ((5, 6), 2, 1));
    assert_eq!(
        same,
        unit_random(11, (5, 6), 2, 1),
        "the copy follows unit_random"
    );
    let weakened: [fn(u64) -> u64; 6] = [
        |z| weakened_mix(z, 0, |z, by| z ^ (z << by)),
        |z| weakened_mix(z, 1, |z, by| z | (z >> by)),
        |z| weakened_mix(z, 1, |z, by| z & (z >> by)),
        |z| weakened_mix(z, 1, |z, by| z ^ (z << by)),
        |z| weakened_mix(z, 2, |z, by| z | (z >> by)),
        |z| weakened_mix(z, 2, |z, by| z ^ (z << by)),
    ];
    for (number, finalize) in weakened.into_iter().enumerate() {
        let (deviation, what, bit) =
            avalanche_deviation(|inputs| unit_random_mixed_by(finalize, inputs));
        assert!(
            deviation < AVALANCHE_LIMIT,
            "weakened finalizer {number}: {what}, bit {bit}: {deviation:.1} standard errors"
        );
    }
    let unmixed: fn(u64) -> u64 = |z| {
        z.wrapping_add(0x9E37_79B9_7F4A_7C15)
            .wrapping_mul(0xBF58_476D_1CE4_E5B9)
            .wrapping_mul(0x94D0_49BB_1331_11EB)
    };
    let (deviation, ..) = avalanche_deviation(|inputs| unit_random_mixed_by(unmixed, inputs));
    assert!(deviation > 3.0 * AVALANCHE_LIMIT, "{deviation:.1}");
}

#[test]
fn the_largest_inputs_stay_in_range() {
    assert!((0.0..1.0).contains(&unit_random(u64::MAX, (u32::MAX, u32::MAX), u32::MAX, 9)));
}
