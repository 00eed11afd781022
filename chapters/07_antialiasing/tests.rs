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

/// The strict avalanche criterion on the inputs that sit side by side in an
/// image: for 2^16 pixels, the pixel beside it, the pixel below, the next
/// sample and the other dimension flip each of the 24 bits of the number
/// with probability 1/2. A bit's count of flips is binomial, standard error
/// 128; 5 of them bounds the largest of the 96 counts for a good hash
/// (a false alarm about once in 10^4), while a finalizer that leaves the
/// top bits unmixed flips some of them every time or never.
/// The inputs of one random number: pixel, sample index, dimension.
type Inputs = ((u32, u32), u32, u32);

/// The inputs next to some inputs, in one direction.
type Neighbour = fn(Inputs) -> Inputs;

#[test]
fn neighbouring_inputs_flip_every_bit_half_the_time() {
    let bits = |value: f32| (value * (1u32 << 24) as f32) as u32;
    let pairs: Vec<Inputs> = (0..1u32 << 16)
        .map(|i| ((i % 256, i / 256), i % 3, 0))
        .collect();
    let neighbours: [(&str, Neighbour); 4] = [
        ("the pixel beside", |((x, y), i, d)| ((x + 1, y), i, d)),
        ("the pixel below", |((x, y), i, d)| ((x, y + 1), i, d)),
        ("the next sample", |(p, i, d)| (p, i + 1, d)),
        ("the other dimension", |(p, i, d)| (p, i, d + 1)),
    ];
    let trials = pairs.len() as f64;
    for (what, neighbour) in neighbours {
        let mut flips = [0u32; 24];
        for &(pixel, index, dimension) in &pairs {
            let (other_pixel, other_index, other_dimension) = neighbour((pixel, index, dimension));
            let changed = bits(unit_random(11, pixel, index, dimension))
                ^ bits(unit_random(11, other_pixel, other_index, other_dimension));
            for (bit, count) in flips.iter_mut().enumerate() {
                *count += (changed >> bit) & 1;
            }
        }
        for (bit, &count) in flips.iter().enumerate() {
            let standard_errors = (f64::from(count) - trials / 2.0) / (trials / 4.0).sqrt();
            assert!(
                standard_errors.abs() < 5.0,
                "{what}: bit {bit} flips {count} times in {trials} ({standard_errors:.1} standard errors)"
            );
        }
    }
}

#[test]
fn the_largest_inputs_stay_in_range() {
    assert!((0.0..1.0).contains(&unit_random(u64::MAX, (u32::MAX, u32::MAX), u32::MAX, 9)));
}
