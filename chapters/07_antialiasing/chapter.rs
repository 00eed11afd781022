use raylab::course::Chapters;
use raylab::render::Tracer;
use raylab::{Sampling, Vec3};

/// Position of sample `index` (of `count`) inside pixel `(x, y)`, as an
/// offset in `[0, 1)^2` from the pixel's top-left corner.
///
/// The random numbers come from a hash of `(seed, x, y, index)` rather than
/// from a generator shared across pixels: every pixel gets the same samples
/// whichever thread renders it, in whatever order, so images are identical
/// on 1 or 64 threads.
///
/// `index` runs from 0 to `count - 1`; grid and jittered sampling need a
/// square `count` (the scene loader checks). Every such input, whatever the
/// pixel and seed, gives an offset inside the pixel.
pub fn sample_offset(
    sampling: Sampling,
    count: u32,
    index: u32,
    pixel: (u32, u32),
    seed: u64,
) -> (f32, f32) {
    let cells_per_side = count.isqrt().max(1);
    let cell = 1.0 / cells_per_side as f32;
    let column = (index % cells_per_side) as f32;
    let row = (index / cells_per_side) as f32;
    let random = |dimension: u32| unit_random(seed, pixel, index, dimension);
    match sampling {
        Sampling::Grid => ((column + 0.5) * cell, (row + 0.5) * cell),
        Sampling::Jittered => {
            // (column + r) can round up to the next cell: with two cells,
            // 1 + (1 - 2^-24) is not an f32 and rounds to 2, which would put
            // the sample at 1.0, on the next pixel's edge. Clamping to the
            // largest f32 below 1 keeps every sample inside its own pixel.
            let inside = |x: f32| x.min(1.0f32.next_down());
            (
                inside((column + random(0)) * cell),
                inside((row + random(1)) * cell),
            )
        }
        Sampling::Random => (random(0), random(1)),
    }
}

/// The colour of pixel `(x, y)`: the mean of its samples, each a camera ray
/// through the sample's position, in linear light.
///
/// The mean must be taken in linear light, before the sRGB encoding of the
/// PNG: light adds linearly, and a pixel half covered by a white edge sends
/// half the light of a white one. Averaging encoded values instead darkens
/// every edge. The samples are summed in index order, so the pixel is the
/// same on any thread.
pub fn pixel_color<C: Chapters>(tracer: &mut Tracer<C>, x: u32, y: u32) -> Vec3 {
    let samples = tracer.samples();
    let mut sum = Vec3::ZERO;
    for index in 0..samples {
        let (dx, dy) = tracer.sample_offset(index, (x, y));
        sum += tracer.sample(x as f32 + dx, y as f32 + dy);
    }
    sum / samples as f32
}

/// A number in `[0, 1)` that depends only on its arguments.
///
/// The arguments are packed into one 64-bit word and mixed by SplitMix64's
/// finaliser, whose every output bit depends on every input bit. The top 24
/// bits become the float: exactly the precision of an `f32` mantissa, so the
/// result is a multiple of `2^-24` and never rounds up to 1.
pub fn unit_random(seed: u64, pixel: (u32, u32), index: u32, dimension: u32) -> f32 {
    let mut word = seed ^ 0x9E37_79B9_7F4A_7C15;
    for part in [pixel.0, pixel.1, index, dimension] {
        word = mix(word ^ u64::from(part));
    }
    (word >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests;
