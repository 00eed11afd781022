//! Chapter 11's report for `raylab cost --chapter 11`: what the tree costs
//! and saves, measured. Nothing here prints; [`super::format`] formats.
//!
//! Three tables, all single-threaded (so that they measure the algorithm,
//! not the scheduler), each time the median of `repeats` runs of the
//! thread's CPU time ([`CpuInstant`]: a busy machine's waits left out):
//!
//! - scaling: build and trace time of the SAH tree on raylab's generated
//!   torus at each size of [`SCALING_SIZES`], beside brute force (chapter
//!   3's loop) up to [`BRUTE_FORCE_MAX_TRIANGLES`];
//! - split rule and leaf size, at one size;
//! - the crossover: from how many spheres a tree (built and traced, what a
//!   render pays) beats the loop, the measurement behind
//!   [`crate::effects::BVH_MIN_OBJECTS`].

use std::hint::black_box;
use std::time::Duration;

use super::measure::{self, CpuInstant, MeasureOptions, Measurement, Method};
use crate::bvh::{BvhOptions, SplitRule};
use crate::course::Chapters;
use crate::course::Objects;
use crate::mesh::MeshError;
use crate::{Plane, Ray, Reference, Shape, Sphere, Vec3};

/// The torus sizes of the scaling table (requested triangles; the
/// generator rounds up to a closed grid, 10 to 18).
pub const SCALING_SIZES: [usize; 6] = [10, 100, 1_000, 10_000, 100_000, 1_000_000];
/// Brute force is timed up to this many triangles: it tests every triangle
/// for every ray, so at 1 M it would take minutes per run.
pub const BRUTE_FORCE_MAX_TRIANGLES: usize = 10_000;
/// The size of the split-rule and leaf-size table (or the largest size
/// measured, if smaller).
pub const SPLIT_TABLE_TRIANGLES: usize = 100_000;
/// The leaf sizes of the split table.
pub const LEAF_SIZES: [u32; 4] = [1, 2, 4, 8];
/// Rays traced per measurement: [`CAMERA_RAYS`] from a camera, the rest
/// from inside the torus's tube.
pub const RAY_COUNT: usize = 4096;
/// Rays of [`RAY_COUNT`] from the camera (about half of them hit).
pub const CAMERA_RAYS: usize = 3072;
/// The crossover sweep: scenes of 1 to this many spheres (and a floor).
pub const CROSSOVER_MAX_SPHERES: usize = 64;
/// Runs per crossover figure, at least: each takes well under the
/// scheduler's time slice, so on a busy machine one preempted run can be
/// ten times the others, and the crossover rule (the tree wins at every
/// count from there on) would take that one spike as a loss. Nine runs
/// let the median drop four.
pub const CROSSOVER_MIN_RUNS: u32 = 9;

/// What to measure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BvhCostOptions {
    /// Runs per figure; the median is kept (0 counts as 1).
    pub repeats: u32,
    /// Sizes of [`SCALING_SIZES`] above this are left out (for quick runs).
    pub max_triangles: usize,
}

impl Default for BvhCostOptions {
    fn default() -> Self {
        BvhCostOptions {
            repeats: 5,
            max_triangles: usize::MAX,
        }
    }
}

/// The shapes and rays of one measurement. This is the seam for other
/// tracers (Embree's race against ours): anything that takes
/// `workload.shapes` and `workload.rays` and finds each ray's nearest hit
/// with `t > 0` can be timed on exactly what chapter 11 was.
#[derive(Debug, Clone)]
pub struct Workload {
    /// The triangle count asked of the generator.
    pub requested: usize,
    pub shapes: Vec<Shape>,
    pub rays: Vec<Ray>,
}

/// Raylab's generated closed torus of about `triangles` triangles (radius
/// about 1.5 around the y axis), as shapes, with [`torus_rays`].
pub fn torus_workload(triangles: usize) -> Result<Workload, MeshError> {
    let mesh = crate::mesh::generate_closed_mesh(triangles)?;
    Ok(Workload {
        requested: triangles,
        shapes: super::leaks::triangles(&mesh),
        rays: torus_rays(),
    })
}

/// A fixed, deterministic set of [`RAY_COUNT`] rays for the torus:
/// [`CAMERA_RAYS`] on a grid from a camera above and in front, through a
/// window a little wider than the torus (so that about half miss: a miss
/// costs a tree only its root box, the loop every object), then rays from
/// the tube's core circle (radius 1, y = 0) in scattered directions, which
/// all hit from inside.
pub fn torus_rays() -> Vec<Ray> {
    let eye = Vec3::new(0.0, 3.0, -5.0);
    let forward = (Vec3::ZERO - eye).normalize();
    let right = Vec3::Y.cross(forward).normalize();
    let up = forward.cross(right);
    let (columns, rows) = (64, CAMERA_RAYS / 64);
    // Half the window's width at the origin's distance (about 5.8): the
    // torus (1.5 wide each way) fills about half of it.
    let half = 1.6;
    let distance = eye.length();
    let mut rays = Vec::with_capacity(RAY_COUNT);
    for row in 0..rows {
        for column in 0..columns {
            let x = ((column as f32 + 0.5) / columns as f32 * 2.0 - 1.0) * half;
            let y = ((row as f32 + 0.5) / rows as f32 * 2.0 - 1.0) * half;
            let target = eye + distance * forward + x * right + y * up;
            rays.push(Ray::new(eye, (target - eye).normalize()));
        }
    }
    let mut random = SplitMix(0x5eed_0011);
    while rays.len() < RAY_COUNT {
        let angle = random.unit() * std::f32::consts::TAU;
        let origin = Vec3::new(angle.cos(), 0.0, angle.sin());
        rays.push(Ray::new(origin, random.direction()));
    }
    rays
}

/// One size of the scaling table.
#[derive(Debug, Clone, PartialEq)]
pub struct ScalingRow {
    pub requested: usize,
    pub triangles: usize,
    /// The SAH tree with the default options (what a render builds).
    pub tree: Measurement,
    /// `None` above [`BRUTE_FORCE_MAX_TRIANGLES`].
    pub brute_force: Option<Measurement>,
}

/// The split rule and leaf size table, at one size.
#[derive(Debug, Clone, PartialEq)]
pub struct SplitTable {
    pub triangles: usize,
    /// Each split rule with each leaf of [`LEAF_SIZES`].
    pub trees: Vec<Measurement>,
    /// Whether brute force checked these trees (only at small sizes).
    pub checked: bool,
}

/// One scene of the crossover sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrossoverRow {
    /// Spheres (the floor plane comes on top).
    pub spheres: usize,
    /// Median time of the loop over every object, for every ray.
    pub loop_time: Duration,
    /// Median time to build the tree and trace every ray through it.
    pub tree_time: Duration,
    /// Rays whose nearest hit differs between the two: 0 unless chapter 11
    /// is wrong.
    pub mismatches: usize,
}

/// The crossover sweep and what it decides.
#[derive(Debug, Clone, PartialEq)]
pub struct Crossover {
    pub rows: Vec<CrossoverRow>,
    /// Runs per figure (the median is kept).
    pub runs: u32,
    /// The smallest sphere count from which the tree is faster at every
    /// count up to the end of the sweep; `None` if it is not faster at the
    /// last one.
    pub from: Option<usize>,
}

/// Everything `raylab cost --chapter 11` measures about the tree.
#[derive(Debug, Clone, PartialEq)]
pub struct BvhCostReport {
    pub options: BvhCostOptions,
    pub rays: usize,
    pub scaling: Vec<ScalingRow>,
    pub split: Option<SplitTable>,
    pub crossover: Crossover,
}

impl BvhCostReport {
    /// Whether every tree measured found brute force's hits (where brute
    /// force was measured).
    pub fn mismatches(&self) -> usize {
        let scaling = self.scaling.iter().map(|row| &row.tree);
        let split = self.split.iter().flat_map(|table| &table.trees);
        scaling
            .chain(split)
            .filter_map(|measurement| measurement.mismatches)
            .sum::<usize>()
            + self
                .crossover
                .rows
                .iter()
                .map(|row| row.mismatches)
                .sum::<usize>()
    }
}

/// Runs the three measurements; an error only if the mesh generator
/// refuses a size.
pub fn run(options: &BvhCostOptions) -> Result<BvhCostReport, MeshError> {
    let sizes: Vec<usize> = SCALING_SIZES
        .into_iter()
        .filter(|&n| n <= options.max_triangles)
        .collect();
    let mut scaling = Vec::with_capacity(sizes.len());
    let mut split = None;
    let split_size = sizes
        .iter()
        .copied()
        .filter(|&n| n <= SPLIT_TABLE_TRIANGLES)
        .max();
    for &size in &sizes {
        let workload = torus_workload(size)?;
        scaling.push(measure_scaling(&workload, options.repeats));
        if Some(size) == split_size {
            split = Some(measure_splits(&workload, options.repeats));
        }
    }
    Ok(BvhCostReport {
        options: *options,
        rays: RAY_COUNT,
        scaling,
        split,
        crossover: measure_crossover(CROSSOVER_MAX_SPHERES, options.repeats),
    })
}

/// One row of the scaling table: the default SAH tree, and brute force up
/// to [`BRUTE_FORCE_MAX_TRIANGLES`].
pub fn measure_scaling(workload: &Workload, repeats: u32) -> ScalingRow {
    let defaults = BvhOptions::default();
    let options = MeasureOptions {
        runs: repeats,
        leaf_sizes: vec![defaults.max_leaf],
        split_rules: vec![defaults.split],
        bins: defaults.bins,
        t_min: 0.0,
        brute_force_max_objects: brute_force_limit(workload),
    };
    let measured = measure::measure(&workload.shapes, &workload.rays, &options);
    let mut brute_force = None;
    let mut tree = None;
    for result in measured.results {
        match result.method {
            Method::BruteForce => brute_force = Some(result),
            Method::Bvh(_) => tree = Some(result),
        }
    }
    ScalingRow {
        requested: workload.requested,
        triangles: workload.shapes.len(),
        tree: tree.expect("measure builds one tree per split rule and leaf size"),
        brute_force,
    }
}

/// Brute force's limit for `measure`, decided on the size asked for
/// rather than the generator's rounded count (10,000 gives 10,032).
fn brute_force_limit(workload: &Workload) -> usize {
    if workload.requested <= BRUTE_FORCE_MAX_TRIANGLES {
        usize::MAX
    } else {
        0
    }
}

/// SAH and midpoint, each with every leaf size of [`LEAF_SIZES`].
pub fn measure_splits(workload: &Workload, repeats: u32) -> SplitTable {
    let options = MeasureOptions {
        runs: repeats,
        leaf_sizes: LEAF_SIZES.to_vec(),
        split_rules: vec![SplitRule::Sah, SplitRule::Midpoint],
        brute_force_max_objects: brute_force_limit(workload),
        ..MeasureOptions::default()
    };
    let measured = measure::measure(&workload.shapes, &workload.rays, &options);
    let checked = measured
        .results
        .iter()
        .any(|result| result.method == Method::BruteForce);
    SplitTable {
        triangles: workload.shapes.len(),
        trees: measured
            .results
            .into_iter()
            .filter(|result| result.method != Method::BruteForce)
            .collect(),
        checked,
    }
}

/// `spheres` scattered spheres (deterministic: the first `k` are the same
/// for every larger count) around the torus's place, on a floor plane.
pub fn sphere_scene(spheres: usize) -> Vec<Shape> {
    let mut random = SplitMix(0x5eed_0c05);
    let mut shapes: Vec<Shape> = vec![Plane::new(Vec3::new(0.0, -1.0, 0.0), Vec3::Y).into()];
    for _ in 0..spheres {
        let centre = Vec3::new(
            random.unit() * 4.0 - 2.0,
            random.unit() * 1.5 - 0.5,
            random.unit() * 4.0 - 2.0,
        );
        let radius = 0.15 + 0.2 * random.unit();
        shapes.push(Sphere::new(centre, radius).into());
    }
    shapes
}

/// Loop against tree on scenes of 1 to `max_spheres` spheres and a floor,
/// with [`torus_rays`]. The tree's time includes its build: a render
/// builds one tree per frame, so that is what the loop competes with.
///
/// Each run is one pass over every scene, loop and tree taking turns, and
/// the runs are passes one after the other: a busy spell of the machine
/// (a stall of tens of milliseconds is common under load) then spoils one
/// run of a few neighbouring scenes, which the median drops, rather than
/// every run of one scene, which it cannot.
pub fn measure_crossover(max_spheres: usize, repeats: u32) -> Crossover {
    let rays = torus_rays();
    let runs = repeats.max(CROSSOVER_MIN_RUNS);
    let scenes: Vec<Vec<Shape>> = (1..=max_spheres).map(sphere_scene).collect();
    let mut loop_times = vec![Vec::new(); scenes.len()];
    let mut tree_times = vec![Vec::new(); scenes.len()];
    let mut mismatches = vec![0; scenes.len()];
    for run in 0..runs {
        for (index, shapes) in scenes.iter().enumerate() {
            let objects = Objects::<Reference>::new(shapes);
            let start = CpuInstant::now();
            let loop_hits: Vec<_> = rays
                .iter()
                .map(|ray| black_box(Reference::nearest_hit(&objects, ray, 0.0, f32::INFINITY)))
                .collect();
            loop_times[index].push(start.elapsed());
            let start = CpuInstant::now();
            let bounds: Vec<_> = shapes.iter().map(Shape::bounds).collect();
            let bvh = Reference::build_bvh(&bounds, &BvhOptions::default());
            let tree_hits: Vec<_> = rays
                .iter()
                .map(|ray| {
                    black_box(Reference::nearest_hit_bvh(
                        &bvh,
                        &objects,
                        ray,
                        0.0,
                        f32::INFINITY,
                    ))
                })
                .collect();
            tree_times[index].push(start.elapsed());
            if run == 0 {
                mismatches[index] = loop_hits
                    .iter()
                    .zip(&tree_hits)
                    .filter(|(a, b)| a != b)
                    .count();
            }
        }
    }
    let rows: Vec<CrossoverRow> = (0..scenes.len())
        .map(|index| CrossoverRow {
            spheres: index + 1,
            loop_time: median_of(std::mem::take(&mut loop_times[index])),
            tree_time: median_of(std::mem::take(&mut tree_times[index])),
            mismatches: mismatches[index],
        })
        .collect();
    let from = crossover(&rows);
    Crossover { rows, runs, from }
}

/// The median of measured times (the mean of the middle two for an even
/// count), as `measure`'s median computes it.
fn median_of(mut times: Vec<Duration>) -> Duration {
    times.sort();
    let middle = times.len() / 2;
    match times.len() {
        0 => Duration::ZERO,
        n if n % 2 == 1 => times[middle],
        _ => (times[middle - 1] + times[middle]) / 2,
    }
}

/// The smallest sphere count from which the tree is faster than the loop
/// at every count that follows in `rows` (sorted by count): one lucky win
/// among losses is noise, not a crossover. `None` if the tree loses the
/// last row.
pub fn crossover(rows: &[CrossoverRow]) -> Option<usize> {
    let losses = rows.iter().rposition(|row| row.tree_time >= row.loop_time);
    match losses {
        None => rows.first().map(|row| row.spheres),
        Some(last_loss) => rows.get(last_loss + 1).map(|row| row.spheres),
    }
}

/// SplitMix64: a tiny deterministic generator, so that the scenes and
/// rays are the same on every machine and run without a dependency.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`, from the top 24 bits (exact in `f32`).
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// A direction uniform on the sphere (z uniform in [-1, 1], angle
    /// uniform: Archimedes).
    fn direction(&mut self) -> Vec3 {
        let z = self.unit() * 2.0 - 1.0;
        let angle = self.unit() * std::f32::consts::TAU;
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * angle.cos(), r * angle.sin(), z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(spheres: usize, loop_us: u64, tree_us: u64) -> CrossoverRow {
        CrossoverRow {
            spheres,
            loop_time: Duration::from_micros(loop_us),
            tree_time: Duration::from_micros(tree_us),
            mismatches: 0,
        }
    }

    #[test]
    fn the_crossover_is_where_the_tree_stops_losing() {
        let rows = [
            row(1, 10, 20),
            row(2, 20, 25),
            row(3, 30, 29),
            row(4, 40, 45), // a loss after a win: the win was noise
            row(5, 50, 40),
            row(6, 60, 41),
        ];
        assert_eq!(crossover(&rows), Some(5));
        assert_eq!(crossover(&rows[..4]), None);
        assert_eq!(crossover(&rows[4..]), Some(5));
        assert_eq!(crossover(&[]), None);
    }

    #[test]
    fn rays_are_fixed_and_about_half_hit_the_torus() {
        assert_eq!(torus_rays(), torus_rays());
        let workload = torus_workload(1_000).unwrap();
        assert_eq!(workload.rays.len(), RAY_COUNT);
        let objects = Objects::<Reference>::new(&workload.shapes);
        let camera_hits = workload.rays[..CAMERA_RAYS]
            .iter()
            .filter(|ray| Reference::nearest_hit(&objects, ray, 0.0, f32::INFINITY).is_some())
            .count();
        let share = camera_hits as f64 / CAMERA_RAYS as f64;
        assert!((0.3..0.7).contains(&share), "{share}");
        let inside_hits = workload.rays[CAMERA_RAYS..]
            .iter()
            .filter(|ray| Reference::nearest_hit(&objects, ray, 0.0, f32::INFINITY).is_some())
            .count();
        assert_eq!(inside_hits, RAY_COUNT - CAMERA_RAYS);
    }

    #[test]
    fn sphere_scenes_grow_by_one_sphere() {
        let small = sphere_scene(3);
        let large = sphere_scene(5);
        assert_eq!(small.len(), 4);
        assert_eq!(large.len(), 6);
        assert_eq!(small[..], large[..4]);
    }
}
