//! Sampling cases: where a pixel's samples go, and the mean they make.

use super::*;

/// `sample_offset(sampling, count, index, pixel, seed)` for every index
/// and each pixel.
#[derive(Debug, Clone)]
pub struct SampleOffsetsCase {
    pub sampling: Sampling,
    pub count: u32,
    pub pixels: Vec<(u32, u32)>,
    pub seed: u64,
    pub rule: SampleRule,
}

/// `sample_offset`'s inputs: every index of `count` in each pixel, for
/// each seed.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct SampleCall {
    pub sampling: Sampling,
    pub count: u32,
    pub pixels: Vec<(u32, u32)>,
    pub seeds: Vec<u64>,
}

/// The most offsets one case may ask for: a million pairs.
const MOST_OFFSETS: usize = 1 << 20;

impl SampleOffsetsCase {
    /// The seeds the rule needs answers for, the case's own first.
    fn seeds(&self) -> Vec<u64> {
        match self.rule {
            SampleRule::DistinctSeeds => std::iter::once(0)
                .chain((0..64).map(|bit| 1u64 << bit))
                .collect(),
            SampleRule::UnlikeSeed(other) => vec![self.seed, other],
            _ => vec![self.seed],
        }
    }
}

impl Kind for SampleOffsetsCase {
    type Call = SampleCall;
    /// The offsets by seed, then pixel, then index.
    type Answer = Vec<Vec<Vec<(f32, f32)>>>;

    fn statistical(&self) -> bool {
        self.rule == SampleRule::Spread
    }

    fn function(&self) -> &'static str {
        "sample_offset"
    }

    fn inputs(&self) -> String {
        let SampleOffsetsCase {
            sampling,
            count,
            pixels,
            seed,
            ..
        } = self;
        let seeds = if self.rule == SampleRule::DistinctSeeds {
            "seed 0 and each seed 2^k, k from 0 to 63".to_string()
        } else {
            format!("seed {seed}")
        };
        format!(
            "sample_offset({sampling:?}, count {count}, index 0..{count}, {} pixel{} from {:?}, {seeds})",
            pixels.len(),
            if pixels.len() > 1 { "s" } else { "" },
            pixels.first().copied().unwrap_or_default()
        )
    }

    fn call(&self) -> SampleCall {
        SampleCall {
            sampling: self.sampling,
            count: self.count,
            pixels: self.pixels.clone(),
            seeds: self.seeds(),
        }
    }

    fn ask<C: Chapters>(call: &SampleCall) -> Result<Self::Answer, String> {
        let asked = call.seeds.len() * call.pixels.len() * call.count as usize;
        if asked > MOST_OFFSETS {
            return Err(format!("{asked} offsets asked, more than {MOST_OFFSETS}"));
        }
        Ok(call
            .seeds
            .iter()
            .map(|&seed| {
                call.pixels
                    .iter()
                    .map(|&pixel| {
                        (0..call.count)
                            .map(|index| {
                                C::sample_offset(call.sampling, call.count, index, pixel, seed)
                            })
                            .collect()
                    })
                    .collect()
            })
            .collect())
    }

    /// The same rule at both levels.
    fn judge(&self, offsets: Self::Answer, _robust: bool) -> Outcome {
        let SampleOffsetsCase {
            sampling,
            count,
            pixels,
            rule,
            ..
        } = self;
        let seeds = self.seeds();
        let shaped = offsets.len() == seeds.len()
            && offsets.iter().all(|by_pixel| {
                by_pixel.len() == pixels.len()
                    && by_pixel.iter().all(|one| one.len() == *count as usize)
            });
        if !shaped {
            return super::intersections::wrong_length(
                seeds.len() * pixels.len() * *count as usize,
                offsets.iter().flatten().map(Vec::len).sum(),
            );
        }
        match rule {
            SampleRule::Spread => match spread(*sampling, *count, &offsets[0]) {
                Ok(()) => Outcome::Pass,
                Err(problem) => Outcome::Fail {
                    expected: rule_text(*rule, *count),
                    got: problem,
                },
            },
            SampleRule::DistinctSeeds => distinct_seeds(self, &seeds, &offsets),
            _ => {
                for (index, pixel) in pixels.iter().enumerate() {
                    let own = &offsets[0][index];
                    let mut verdict = sample_rule(*rule, *count, own);
                    if let (Ok(()), SampleRule::UnlikeSeed(other)) = (&verdict, rule)
                        && offsets[1][index] == *own
                    {
                        verdict = Err(format!("the same offsets as with seed {other}"));
                    }
                    if let Err(problem) = verdict {
                        return Outcome::Fail {
                            expected: rule_text(*rule, *count),
                            got: format!(
                                "pixel {pixel:?}: {problem}; offsets {}",
                                shown_offsets(own)
                            ),
                        };
                    }
                }
                Outcome::Pass
            }
        }
    }

    /// Every pixel moved by one shift (neighbours stay neighbours), and a
    /// new seed (and a new other seed) where the rule takes one.
    fn fresh(&self, draw: &mut Draw) -> Option<SampleOffsetsCase> {
        let (dx, dy) = (draw.below(4096) as u32, draw.below(4096) as u32);
        let rule = match self.rule {
            SampleRule::UnlikeSeed(_) => SampleRule::UnlikeSeed(draw.word()),
            rule => rule,
        };
        Some(SampleOffsetsCase {
            pixels: self
                .pixels
                .iter()
                .map(|&(x, y)| (x.saturating_add(dx), y.saturating_add(dy)))
                .collect(),
            seed: if self.rule == SampleRule::DistinctSeeds {
                self.seed
            } else {
                draw.word()
            },
            rule,
            ..self.clone()
        })
    }
}

/// `pixel_color` of each pixel of `scene` (TOML, chapter 7's stage):
/// expected the mean, in linear light, of the pixel's own samples (at
/// the offsets `sample_offset` gives).
#[derive(Debug, Clone)]
pub struct PixelColorCase {
    pub scene: String,
    pub pixels: Vec<(u32, u32)>,
}

/// `pixel_color`'s call: the scene (TOML) and the pixels.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct PixelColorCall {
    pub scene: String,
    pub pixels: Vec<(u32, u32)>,
}

impl Kind for PixelColorCase {
    type Call = PixelColorCall;
    /// For each pixel, its samples' colours (at the offsets the chapters'
    /// `sample_offset` gives) and `pixel_color`'s answer.
    type Answer = Vec<(Vec<Vec3>, Vec3)>;

    fn function(&self) -> &'static str {
        "pixel_color"
    }

    fn inputs(&self) -> String {
        let PixelColorCase { pixels, .. } = self;
        format!(
            "pixel_color of {} pixel{} from {:?}",
            pixels.len(),
            if pixels.len() > 1 { "s" } else { "" },
            pixels.first().copied().unwrap_or_default()
        )
    }

    fn call(&self) -> PixelColorCall {
        PixelColorCall {
            scene: self.scene.clone(),
            pixels: self.pixels.clone(),
        }
    }

    fn ask<C: Chapters>(call: &PixelColorCall) -> Result<Self::Answer, String> {
        let scene = parse(&call.scene)?;
        let stage =
            Stage::<C>::with_chapters(&scene, 7, scene.render).map_err(|e| e.to_string())?;
        let mut tracer = stage.tracer(None);
        let mut answers = Vec::with_capacity(call.pixels.len());
        for &(x, y) in &call.pixels {
            let colours: Vec<Vec3> = (0..tracer.samples())
                .map(|index| {
                    let (dx, dy) = tracer.sample_offset(index, (x, y));
                    tracer.sample(x as f32 + dx, y as f32 + dy)
                })
                .collect();
            answers.push((colours, C::pixel_color(&mut tracer, x, y)));
        }
        Ok(answers)
    }

    /// The same tolerance at both levels: each pixel the mean, in linear
    /// light, of its own samples, as many as the scene asks.
    fn judge(&self, answers: Self::Answer, _robust: bool) -> Outcome {
        if answers.len() != self.pixels.len() {
            return super::intersections::wrong_length(self.pixels.len(), answers.len());
        }
        // As many samples as raylab's own stage of the scene takes.
        let samples = parse(&self.scene).ok().and_then(|scene| {
            crate::answer_key::raylab_own(|| {
                Stage::<Reference>::with_chapters(&scene, 7, scene.render)
                    .ok()
                    .map(|stage| stage.samples())
            })
        });
        let Some(samples) = samples else {
            return Outcome::Error("the case's scene has no stage at chapter 7".into());
        };
        for (&(x, y), (colours, got)) in self.pixels.iter().zip(&answers) {
            if colours.len() != samples as usize {
                return super::intersections::wrong_length(samples as usize, colours.len());
            }
            let mean = colours.iter().copied().sum::<Vec3>() / samples.max(1) as f32;
            if !colour_close(*got, mean) {
                return Outcome::Fail {
                    expected: format!(
                        "pixel ({x}, {y}): {} = the mean of its samples {}",
                        vec(mean),
                        colours
                            .iter()
                            .map(|c| vec(*c))
                            .collect::<Vec<_>>()
                            .join(" ")
                    ),
                    got: vec(*got),
                };
            }
        }
        Outcome::Pass
    }

    /// As many pixels, drawn anywhere in the scene's image.
    fn fresh(&self, draw: &mut Draw) -> Option<PixelColorCase> {
        let scene = parse(&self.scene).ok()?;
        let (width, height) = (scene.render.width, scene.render.height);
        Some(PixelColorCase {
            pixels: self
                .pixels
                .iter()
                .map(|_| {
                    (
                        draw.below(u64::from(width)) as u32,
                        draw.below(u64::from(height)) as u32,
                    )
                })
                .collect(),
            ..self.clone()
        })
    }
}

/// [`SampleRule::DistinctSeeds`]: seed 0 and every seed of one bit give
/// offsets inside the pixel, and no two of them the same offsets in one
/// pixel (a hash that drops a bit of the seed gives that bit's seed the
/// offsets of seed 0).
fn distinct_seeds(
    case: &SampleOffsetsCase,
    seeds: &[u64],
    offsets: &[Vec<Vec<(f32, f32)>>],
) -> Outcome {
    let SampleOffsetsCase {
        count,
        pixels,
        rule,
        ..
    } = case;
    for (index, pixel) in pixels.iter().enumerate() {
        let mut seen: std::collections::HashMap<Vec<(u32, u32)>, u64> =
            std::collections::HashMap::new();
        for (&seed, by_pixel) in seeds.iter().zip(offsets) {
            let offsets = &by_pixel[index];
            let problem = match sample_rule(*rule, *count, offsets) {
                Err(problem) => Some(problem),
                Ok(()) => {
                    let bits = offsets.iter().map(|(x, y)| (x.to_bits(), y.to_bits()));
                    seen.insert(bits.collect(), seed)
                        .map(|earlier| format!("seeds {earlier} and {seed} give the same offsets"))
                }
            };
            if let Some(problem) = problem {
                return Outcome::Fail {
                    expected: rule_text(*rule, *count),
                    got: format!(
                        "pixel {pixel:?}, seed {seed}: {problem}; offsets {}",
                        shown_offsets(offsets)
                    ),
                };
            }
        }
    }
    Outcome::Pass
}

/// The first 16 offsets, as a failure quotes them.
fn shown_offsets(offsets: &[(f32, f32)]) -> String {
    offsets
        .iter()
        .take(16)
        .map(|(x, y)| format!("({}, {})", num(*x), num(*y)))
        .collect::<Vec<_>>()
        .join(" ")
}

fn sample_rule(rule: SampleRule, count: u32, offsets: &[(f32, f32)]) -> Result<(), String> {
    let inside = |v: f32| (0.0..1.0).contains(&v);
    if let Some((x, y)) = offsets.iter().find(|(x, y)| !inside(*x) || !inside(*y)) {
        return Err(format!(
            "({}, {}) is outside [0, 1)^2 (1.0 is the next pixel's edge)",
            num(*x),
            num(*y)
        ));
    }
    let k = count.isqrt().max(1);
    let cell_of = |(x, y): (f32, f32)| {
        let column = ((x * k as f32) as u32).min(k - 1);
        let row = ((y * k as f32) as u32).min(k - 1);
        row * k + column
    };
    match rule {
        SampleRule::GridCentres => {
            for &(x, y) in offsets {
                let centre = |v: f32| ((v * k as f32).floor() + 0.5) / k as f32;
                if (x - centre(x)).abs() > 1e-5 || (y - centre(y)).abs() > 1e-5 {
                    return Err(format!(
                        "({}, {}) is not the centre of a cell",
                        num(x),
                        num(y)
                    ));
                }
            }
            one_per_cell(k, offsets, cell_of)
        }
        SampleRule::OnePerCell => one_per_cell(k, offsets, cell_of),
        SampleRule::InsidePixel
        | SampleRule::UnlikeSeed(_)
        | SampleRule::DistinctSeeds
        | SampleRule::Spread => {
            if offsets.len() > 1 && offsets.iter().all(|o| *o == offsets[0]) {
                Err("every sample is at the same point".into())
            } else {
                Ok(())
            }
        }
    }
}

fn one_per_cell(
    k: u32,
    offsets: &[(f32, f32)],
    cell_of: impl Fn((f32, f32)) -> u32,
) -> Result<(), String> {
    let mut seen = vec![0u32; (k * k) as usize];
    for &offset in offsets {
        seen[cell_of(offset) as usize] += 1;
    }
    match seen.iter().position(|&n| n != 1) {
        None => Ok(()),
        Some(cell) => Err(format!(
            "cell (column {}, row {}) of the {k} x {k} grid has {} samples",
            cell as u32 % k,
            cell as u32 / k,
            seen[cell]
        )),
    }
}

fn rule_text(rule: SampleRule, count: u32) -> String {
    let k = count.isqrt().max(1);
    match rule {
        SampleRule::GridCentres => {
            format!("the {count} centres of a {k} x {k} grid of cells, one each")
        }
        SampleRule::OnePerCell => {
            format!("one sample in each cell of a {k} x {k} grid, inside [0, 1)^2")
        }
        SampleRule::InsidePixel => "samples inside [0, 1)^2, not all at one point".into(),
        SampleRule::UnlikeSeed(other) => {
            format!("samples inside [0, 1)^2, not all at one point, not those of seed {other}")
        }
        SampleRule::DistinctSeeds => "samples inside [0, 1)^2, not all at one point, and \
                                       other samples for each seed"
            .into(),
        SampleRule::Spread => format!(
            "samples spread like independent uniform ones{}: chi-square at most {} on 8 x 8 bins \
             for (x, y), for two cells of a pixel, and for two neighbouring pixels",
            if count > 1 { " within their cells" } else { "" },
            SPREAD_CHI_SQUARE
        ),
    }
}

/// Bins per axis of the spread tests.
const SPREAD_BINS: usize = 8;

/// The largest chi-square of a spread test that passes: the 1 - 1e-4
/// quantile of the chi-square law with 63 degrees of freedom (8 x 8 bins,
/// Wilson and Hilferty's approximation gives 113.7), so that a correct
/// sampler, whose statistic follows that law, fails one of the three tests
/// about once in 3,000 seeds; a sampler that reuses an offset puts every
/// point on a diagonal and scores in the tens of thousands.
pub const SPREAD_CHI_SQUARE: f64 = 114.0;

/// The three spread tests of [`SampleRule::Spread`] over `offsets` (one
/// list per pixel, neighbours next to each other): the first that fails,
/// in words. Jittered samples are judged by their place within their cell
/// (the grid is `sqrt(count)` cells a side), random ones by their place in
/// the pixel.
pub(super) fn spread(
    sampling: Sampling,
    count: u32,
    offsets: &[Vec<(f32, f32)>],
) -> Result<(), String> {
    let k = if sampling == Sampling::Random {
        1.0
    } else {
        count.isqrt().max(1) as f32
    };
    let within = |v: f32| (v * k).fract();
    let mut joint = Vec::new();
    for pixel in offsets {
        joint.extend(pixel.iter().map(|&(x, y)| (within(x), within(y))));
    }
    let mut cells = Vec::new();
    for pixel in offsets {
        if let [first, second, ..] = pixel[..] {
            cells.push((within(first.0), within(second.0)));
        }
    }
    let mut neighbours = Vec::new();
    for pair in offsets.windows(2) {
        if let (Some(this), Some(next)) = (pair[0].first(), pair[1].first()) {
            neighbours.push((within(this.0), within(next.0)));
        }
    }
    for (what, points) in [
        ("(x, y) of every sample", &joint),
        ("x of the first two samples of each pixel", &cells),
        ("x of the first sample of neighbouring pixels", &neighbours),
    ] {
        let statistic = chi_square(points);
        if !(statistic <= SPREAD_CHI_SQUARE) {
            return Err(format!(
                "{what}: chi-square {statistic:.1} over {} points (a correct sampler stays \
                 below {SPREAD_CHI_SQUARE}: are offsets reused, or correlated?)",
                points.len()
            ));
        }
    }
    Ok(())
}

/// Pearson's statistic of `points` in `[0, 1)^2` against the uniform law
/// on [`SPREAD_BINS`] x [`SPREAD_BINS`] bins.
fn chi_square(points: &[(f32, f32)]) -> f64 {
    let mut bins = vec![0u64; SPREAD_BINS * SPREAD_BINS];
    let bin = |v: f32| ((v * SPREAD_BINS as f32) as usize).min(SPREAD_BINS - 1);
    for &(a, b) in points {
        bins[bin(a) * SPREAD_BINS + bin(b)] += 1;
    }
    let expected = points.len() as f64 / bins.len() as f64;
    if expected == 0.0 {
        return 0.0;
    }
    bins.iter()
        .map(|&n| (n as f64 - expected).powi(2) / expected)
        .sum()
}
