//! Chapter 7's checkpoints (level 1) and hard cases (level 2) for
//! `raylab check --chapter 7`; the builders they share are in
//! `raylab::check::catalog`.

use crate::check::catalog::*;

const SAMPLES_7: &str = "Where the samples go";

/// A wall of white and black checkers of size 1 whose corner is on the
/// camera's axis, seen in 3 x 3 pixels: the middle pixel's four quarters see
/// white, black, black, white. Ambient light only, `k_a = 1`: each sample is
/// exactly 1 or 0.
const QUARTERS_SCENE: &str = r#"
background = [1.0, 1.0, 1.0]
ambient_light = [1.0, 1.0, 1.0]
[camera]
position = [0.0, 0.0, -5.0]
look_at = [0.0, 0.0, 0.0]
fov_degrees = 45.0
[render]
width = 3
height = 3
samples = 4
sampling = "grid"
[[objects]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, -1.0] }
[objects.material]
color = [1.0, 1.0, 1.0]
ambient = 1.0
diffuse = 0.0
checker = { color = [0.0, 0.0, 0.0], size = 1.0 }
"#;

/// A `sample_offset` question: `count` samples of `sampling` in each of
/// `pixels`, from `seed`, must follow `rule`.
struct SamplesQuestion {
    name: &'static str,
    section: &'static str,
    says: &'static str,
    sampling: Sampling,
    count: u32,
    pixels: Vec<(u32, u32)>,
    seed: u64,
    rule: SampleRule,
}

impl From<SamplesQuestion> for Case {
    fn from(question: SamplesQuestion) -> Case {
        Case::new(
            question.name,
            question.section,
            question.says,
            CaseKind::SampleOffsets(SampleOffsetsCase {
                sampling: question.sampling,
                count: question.count,
                pixels: question.pixels,
                seed: question.seed,
                rule: question.rule,
            }),
        )
    }
}

/// Chapter 7's own scene at the reference size: what `pixel_color` is
/// checked on, pixel by pixel, along three rows that cross edges.
fn chapter_7_scene() -> String {
    crate::chapters::chapter(7)
        .map(|info| {
            info.scene
                .replace(
                    "width = 640",
                    &format!("width = {}", crate::chapters::REFERENCE_WIDTH),
                )
                .replace(
                    "height = 480",
                    &format!("height = {}", crate::chapters::REFERENCE_HEIGHT),
                )
        })
        .unwrap_or_default()
}

/// The pixels of the spread cases: 64 x 64, row by row, so that each pixel's
/// neighbour in the list is its neighbour in the image.
fn spread_pixels() -> Vec<(u32, u32)> {
    (0..64).flat_map(|y| (0..64).map(move |x| (x, y))).collect()
}

/// Where the image differs when every checkpoint passes: what to look at
/// in the heatmap.
pub const IMAGE_HINT: &str = "along the edges only: the samples must cover the pixel (one in each cell, each cell with its own jitter), and the pixel is their average";

/// Chapter 7's checkpoints (level 1), in the order they run: the first
/// that fails is the one reported.
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn checkpoints() -> Vec<Case> {
    let rows: Vec<(u32, u32)> = [44u32, 60, 84]
        .iter()
        .flat_map(|&y| (0..crate::chapters::REFERENCE_WIDTH).map(move |x| (x, y)))
        .collect();
    vec![
        Case::from(SamplesQuestion {
            name: "samples-grid-4",
            section: SAMPLES_7,
            says: "4 grid samples in pixel (3, 7): the centres of its quarters, (0.25, 0.25), \
                   (0.75, 0.25), (0.25, 0.75) and (0.75, 0.75), in any order",
            sampling: Sampling::Grid,
            count: 4,
            pixels: vec![(3, 7)],
            seed: 1,
            rule: SampleRule::GridCentres,
        }),
        Case::from(SamplesQuestion {
            name: "samples-grid-9",
            section: SAMPLES_7,
            says: "9 grid samples: the centres of a 3 x 3 grid of cells, (1/6, 1/6) to (5/6, 5/6)",
            sampling: Sampling::Grid,
            count: 9,
            pixels: vec![(0, 0), (5, 2)],
            seed: 0,
            rule: SampleRule::GridCentres,
        }),
        Case::from(SamplesQuestion {
            name: "samples-jittered-16",
            section: SAMPLES_7,
            says: "16 jittered samples in pixels (10, 20), (0, 0) and (159, 119), seed 42: one in \
                   each cell of a 4 x 4 grid, all inside [0, 1)^2",
            sampling: Sampling::Jittered,
            count: 16,
            pixels: vec![(10, 20), (0, 0), (159, 119)],
            seed: 42,
            rule: SampleRule::OnePerCell,
        }),
        Case::from(SamplesQuestion {
            name: "samples-jittered-spread",
            section: SAMPLES_7,
            says: "4 jittered samples in each of 64 x 64 pixels, seed 7: within its cell, a \
                   sample is anywhere with equal chance, x and y independently, and the jitter \
                   of one cell tells nothing of another's, nor one pixel's of the next's (a \
                   jitter drawn once and reused for every cell puts the samples on a grid)",
            sampling: Sampling::Jittered,
            count: 4,
            pixels: spread_pixels(),
            seed: 7,
            rule: SampleRule::Spread,
        }),
        Case::from(SamplesQuestion {
            name: "samples-random-spread",
            section: SAMPLES_7,
            says: "4 random samples in each of 64 x 64 pixels, seed 11: uniform over the pixel, \
                   x and y independent, and independent from sample to sample and from pixel \
                   to pixel",
            sampling: Sampling::Random,
            count: 4,
            pixels: spread_pixels(),
            seed: 11,
            rule: SampleRule::Spread,
        }),
        Case::from(SamplesQuestion {
            name: "samples-random-4",
            section: SAMPLES_7,
            says: "4 random samples: inside [0, 1)^2, not all at the same point",
            sampling: Sampling::Random,
            count: 4,
            pixels: vec![(5, 6), (100, 50)],
            seed: 9,
            rule: SampleRule::InsidePixel,
        }),
        Case::from(SamplesQuestion {
            name: "samples-random-5",
            section: SAMPLES_7,
            says: "5 random samples: random sampling takes any count, not only squares \
                   (5 has no whole square root: floor(sqrt 5) = 2); inside [0, 1)^2, not all at \
                   the same point",
            sampling: Sampling::Random,
            count: 5,
            pixels: vec![(5, 6), (100, 50)],
            seed: 9,
            rule: SampleRule::InsidePixel,
        }),
        Case::from(SamplesQuestion {
            name: "samples-seed-changes-them",
            section: SAMPLES_7,
            says: "4 random samples in pixels (5, 6) and (100, 50) with seed 1, then with seed 0: \
                   the seed changes the samples (it is hashed with the pixel and the index), so \
                   the two sets must differ",
            sampling: Sampling::Random,
            count: 4,
            pixels: vec![(5, 6), (100, 50)],
            seed: 1,
            rule: SampleRule::UnlikeSeed(0),
        }),
        Case::from(SamplesQuestion {
            name: "samples-every-seed-its-own",
            section: SAMPLES_7,
            says: "4 random samples in pixels (5, 6) and (100, 50) with seed 0 and with each seed \
                   of one bit, 1, 2, 4, ... 2^63: every seed gives samples of its own; the whole \
                   64-bit seed goes into the hash, so no bit of it can be lost (two seeds that \
                   differ in a lost bit render the same noise)",
            sampling: Sampling::Random,
            count: 4,
            pixels: vec![(5, 6), (100, 50)],
            seed: 0,
            rule: SampleRule::DistinctSeeds,
        }),
        Case::new(
            "pixel-quarters",
            SAMPLES_7,
            "the middle pixel of a 3 x 3 view of a black and white checker whose corner is on the \
             axis: its four grid samples see 1, 0, 0, 1; expected their mean in linear light, 0.5 \
             (averaging sRGB codes instead gives 0.21)",
            CaseKind::PixelColor(PixelColorCase {
                scene: QUARTERS_SCENE.to_string(),
                pixels: vec![(1, 1)],
            }),
        ),
        Case::new(
            "pixel-mean-of-own-samples",
            SAMPLES_7,
            "every pixel of rows 44, 60 and 84 of the chapter 7 scene at 160 x 120 \
             (they cross the balls' edges): expected the mean, in linear light, of the pixel's own \
             4 samples, at the offsets sample_offset gives; nothing from neighbouring pixels",
            CaseKind::PixelColor(PixelColorCase {
                scene: chapter_7_scene(),
                pixels: rows,
            }),
        ),
        Case::new(
            "pixel-nine-samples",
            SAMPLES_7,
            "every pixel of row 60 of the chapter 7 scene at 160 x 120 with samples = 9 (3 x 3 \
             jittered): expected the mean, in linear light, of the pixel's own 9 samples; the \
             count is the scene's (tracer.samples()), not 4",
            CaseKind::PixelColor(PixelColorCase {
                scene: chapter_7_scene().replace("samples = 4", "samples = 9"),
                pixels: (0..crate::chapters::REFERENCE_WIDTH)
                    .map(|x| (x, 60))
                    .collect(),
            }),
        ),
    ]
}

/// Chapter 7's hard cases (level 2).
/// A list of cases that reads as data, one entry per case: kept whole,
/// however long.
pub fn robustness() -> Vec<Case> {
    let mut pixels: Vec<(u32, u32)> = (0..20_000).map(|x| (x, 3)).collect();
    pixels.push((109_417, 17));
    robust(vec![
        Case::from(SamplesQuestion {
            name: "samples-jittered-never-1",
            section: SAMPLES_7,
            says: "4 jittered samples in each of 20,000 pixels: (column + r) / 2 can round up to \
                   1.0 in f32 (pixel (109417, 17), sample 1 does); every offset must stay below 1",
            sampling: Sampling::Jittered,
            count: 4,
            pixels: pixels.clone(),
            seed: 0,
            rule: SampleRule::OnePerCell,
        }),
        Case::from(SamplesQuestion {
            name: "samples-random-never-1",
            section: SAMPLES_7,
            says: "4 random samples in each of 20,000 pixels: every offset inside [0, 1)^2",
            sampling: Sampling::Random,
            count: 4,
            pixels,
            seed: 0,
            rule: SampleRule::InsidePixel,
        }),
    ])
}
