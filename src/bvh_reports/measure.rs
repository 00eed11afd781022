//! What chapter 11's tree costs and saves, measured: build time and trace
//! time of brute force (chapter 3's loop) against BVHs built with each split
//! rule and several leaf sizes, on the same shapes and rays.
//!
//! Each figure is the median of several runs, single-threaded, so that it
//! measures the algorithm rather than the scheduler, and timed by the
//! thread's CPU clock ([`CpuInstant`]), so that time spent waiting for a
//! core on a busy machine is not counted. Nothing here prints:
//! [`measure`] returns the numbers, and formatting them is the caller's
//! business (`raylab cost --chapter 11`).

use std::hint::black_box;
use std::time::Duration;

use crate::bvh::{Aabb, Bvh, BvhOptions, SplitRule};
use crate::course::Chapters;
use crate::course::{Hit, Objects};
use crate::{Ray, Reference, Shape};

/// What to measure.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasureOptions {
    /// Runs per figure; the median is kept (0 counts as 1).
    pub runs: u32,
    /// The `max_leaf` of each tree built, for each split rule.
    pub leaf_sizes: Vec<u32>,
    pub split_rules: Vec<SplitRule>,
    /// The SAH's bin count.
    pub bins: u32,
    /// Every ray is traced for its nearest hit with `t_min < t < infinity`.
    pub t_min: f32,
    /// Brute force is measured only for this many objects or fewer: its
    /// time grows with objects x rays, and at a million triangles one pass
    /// would take minutes. Above it the trees are timed but not checked.
    pub brute_force_max_objects: usize,
}

impl Default for MeasureOptions {
    fn default() -> Self {
        MeasureOptions {
            runs: 5,
            leaf_sizes: vec![1, 2, 4, 8],
            split_rules: vec![SplitRule::Sah, SplitRule::Midpoint],
            bins: BvhOptions::default().bins,
            t_min: 0.0,
            brute_force_max_objects: usize::MAX,
        }
    }
}

/// How the nearest hits were found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Chapter 3's loop over every object.
    BruteForce,
    /// Chapter 11's traversal of a tree built with these options.
    Bvh(BvhOptions),
}

/// The shape of a tree ([`Bvh`]'s statistics).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TreeStats {
    pub nodes: usize,
    pub leaves: usize,
    pub depth: usize,
    pub memory_bytes: usize,
    /// Objects outside the tree, tested by a loop on every ray.
    pub unbounded: usize,
}

impl TreeStats {
    pub fn of(bvh: &Bvh) -> TreeStats {
        TreeStats {
            nodes: bvh.node_count(),
            leaves: bvh.leaf_count(),
            depth: bvh.depth(),
            memory_bytes: bvh.memory_bytes(),
            unbounded: bvh.unbounded.len(),
        }
    }
}

/// The figures of one method.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurement {
    pub method: Method,
    /// Median build time (zero for brute force, which builds nothing).
    pub build: Duration,
    /// Median time to trace every ray.
    pub trace: Duration,
    /// The tree's shape (`None` for brute force).
    pub tree: Option<TreeStats>,
    /// How many rays hit something.
    pub hits: usize,
    /// How many rays' nearest hit (object or `t`) differs from brute
    /// force's: 0 unless chapter 11 is wrong; `None` when brute force was
    /// not measured (more objects than `brute_force_max_objects`).
    pub mismatches: Option<usize>,
}

/// Every method's figures on one set of shapes and rays; brute force first
/// when it was measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurements {
    pub objects: usize,
    pub rays: usize,
    pub runs: u32,
    pub results: Vec<Measurement>,
}

/// Measures brute force, then a BVH for each split rule and leaf size of
/// `options`, tracing every ray of `rays` among `shapes` (the reference
/// chapters' intersection tests).
pub fn measure(shapes: &[Shape], rays: &[Ray], options: &MeasureOptions) -> Measurements {
    let trial = Trial {
        objects: Objects::<Reference>::new(shapes),
        rays,
        runs: options.runs.max(1),
        t_min: options.t_min,
    };

    let mut results = Vec::new();
    let brute_hits = (shapes.len() <= options.brute_force_max_objects).then(|| {
        let (measurement, brute_hits) = measure_brute_force(&trial);
        results.push(measurement);
        brute_hits
    });

    let bounds: Vec<_> = shapes.iter().map(Shape::bounds).collect();
    for &split in &options.split_rules {
        for &max_leaf in &options.leaf_sizes {
            let bvh_options = BvhOptions {
                split,
                bins: options.bins,
                max_leaf,
            };
            results.push(measure_tree(
                &trial,
                &bounds,
                bvh_options,
                brute_hits.as_deref(),
            ));
        }
    }
    Measurements {
        objects: shapes.len(),
        rays: rays.len(),
        runs: trial.runs,
        results,
    }
}

/// What every method is timed on: the same objects and rays, as many runs
/// (at least 1), the same `t_min`.
struct Trial<'a> {
    objects: Objects<'a, Reference>,
    rays: &'a [Ray],
    runs: u32,
    t_min: f32,
}

/// Brute force's figures, and its nearest hits, which the trees are
/// checked against.
fn measure_brute_force(trial: &Trial) -> (Measurement, Vec<Option<Hit>>) {
    let mut brute_hits = Vec::new();
    let trace = median(trial.runs, || {
        let start = CpuInstant::now();
        brute_hits = trial
            .rays
            .iter()
            .map(|ray| {
                black_box(Reference::nearest_hit(
                    &trial.objects,
                    ray,
                    trial.t_min,
                    f32::INFINITY,
                ))
            })
            .collect();
        start.elapsed()
    });
    let measurement = Measurement {
        method: Method::BruteForce,
        build: Duration::ZERO,
        trace,
        tree: None,
        hits: count_hits(&brute_hits),
        mismatches: Some(0),
    };
    (measurement, brute_hits)
}

/// One tree's figures: built with `bvh_options` over `bounds`, then every
/// ray traced through it; its mismatches counted against `brute_hits`
/// when brute force was measured.
fn measure_tree(
    trial: &Trial,
    bounds: &[Option<Aabb>],
    bvh_options: BvhOptions,
    brute_hits: Option<&[Option<Hit>]>,
) -> Measurement {
    let mut bvh = Bvh::default();
    let build = median(trial.runs, || {
        let start = CpuInstant::now();
        bvh = black_box(Reference::build_bvh(bounds, &bvh_options));
        start.elapsed()
    });
    let mut hits = Vec::new();
    let trace = median(trial.runs, || {
        let start = CpuInstant::now();
        hits = trial
            .rays
            .iter()
            .map(|ray| {
                black_box(Reference::nearest_hit_bvh(
                    &bvh,
                    &trial.objects,
                    ray,
                    trial.t_min,
                    f32::INFINITY,
                ))
            })
            .collect();
        start.elapsed()
    });
    let mismatches = brute_hits.map(|brute_hits| {
        hits.iter()
            .zip(brute_hits)
            .filter(|(bvh_hit, brute_hit)| bvh_hit != brute_hit)
            .count()
    });
    Measurement {
        method: Method::Bvh(bvh_options),
        build,
        trace,
        tree: Some(TreeStats::of(&bvh)),
        hits: count_hits(&hits),
        mismatches,
    }
}

pub fn count_hits(hits: &[Option<Hit>]) -> usize {
    hits.iter().filter(|hit| hit.is_some()).count()
}

/// A reading of the CPU time the calling thread has used, for timing
/// single-threaded work. Wall time on a shared machine counts every
/// moment another process held the core: with a load of 8 on 2 cores a run
/// of half a millisecond is often stretched ten times, and medians of a few
/// runs follow the load rather than the algorithm. Outside Unix, where
/// there is no thread clock to read through `libc`, it falls back to wall
/// time.
#[derive(Debug, Clone, Copy)]
pub struct CpuInstant(Duration);

impl CpuInstant {
    pub fn now() -> CpuInstant {
        CpuInstant(thread_cpu_time())
    }

    pub fn elapsed(&self) -> Duration {
        thread_cpu_time().saturating_sub(self.0)
    }
}

#[cfg(unix)]
fn thread_cpu_time() -> Duration {
    let mut now = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `now` is a valid, writable timespec; the call writes only it.
    let status = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut now) };
    if status != 0 {
        // Linux and macOS always have this clock; a zero reading would
        // turn every figure into 0 rather than a wrong number.
        return Duration::ZERO;
    }
    Duration::new(now.tv_sec as u64, now.tv_nsec as u32)
}

#[cfg(not(unix))]
fn thread_cpu_time() -> Duration {
    use std::sync::OnceLock;
    use std::time::Instant;
    static START: OnceLock<Instant> = OnceLock::new();
    START.get_or_init(Instant::now).elapsed()
}

/// The median of `runs` calls of `time` (the mean of the middle two for an
/// even count).
pub fn median(runs: u32, mut time: impl FnMut() -> Duration) -> Duration {
    let mut times: Vec<Duration> = (0..runs.max(1)).map(|_| time()).collect();
    times.sort();
    let middle = times.len() / 2;
    if times.len() % 2 == 1 {
        times[middle]
    } else {
        (times[middle - 1] + times[middle]) / 2
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Plane, Sphere, Vec3};

    #[test]
    fn every_method_agrees_with_brute_force_on_a_small_scene() {
        let mut shapes: Vec<Shape> = vec![Plane::new(Vec3::new(0.0, -1.0, 0.0), Vec3::Y).into()];
        for i in 0..40 {
            let x = (i % 8) as f32 * 2.0 - 7.0;
            let z = (i / 8) as f32 * 2.0 + 5.0;
            shapes.push(Sphere::new(Vec3::new(x, 0.0, z), 0.8).into());
        }
        let rays: Vec<Ray> = (0..200)
            .map(|i| {
                let x = (i % 20) as f32 / 10.0 - 1.0;
                let y = (i / 20) as f32 / 10.0 - 0.5;
                Ray::new(Vec3::new(0.0, 1.0, 0.0), Vec3::new(x, y, 1.0))
            })
            .collect();
        let options = MeasureOptions {
            runs: 2,
            ..MeasureOptions::default()
        };
        let measured = measure(&shapes, &rays, &options);
        assert_eq!(measured.results.len(), 1 + 2 * 4);
        assert_eq!(measured.results[0].method, Method::BruteForce);
        let hits = measured.results[0].hits;
        assert!(hits > 50, "{hits}");
        for result in &measured.results {
            assert_eq!(result.mismatches, Some(0), "{:?}", result.method);
            assert_eq!(result.hits, hits);
        }
    }

    #[test]
    fn brute_force_is_left_out_above_its_limit() {
        let shapes: Vec<Shape> = (0..3)
            .map(|i| Sphere::new(Vec3::new(i as f32 * 3.0, 0.0, 5.0), 1.0).into())
            .collect();
        let rays = [Ray::new(Vec3::ZERO, Vec3::Z)];
        let options = MeasureOptions {
            runs: 1,
            leaf_sizes: vec![1],
            split_rules: vec![SplitRule::Sah],
            brute_force_max_objects: 2,
            ..MeasureOptions::default()
        };
        let measured = measure(&shapes, &rays, &options);
        assert_eq!(measured.results.len(), 1);
        assert_eq!(measured.results[0].mismatches, None);
        assert_eq!(measured.results[0].hits, 1);
        let options = MeasureOptions {
            brute_force_max_objects: 3,
            ..options
        };
        let measured = measure(&shapes, &rays, &options);
        assert_eq!(measured.results[0].method, Method::BruteForce);
        assert_eq!(measured.results[1].mismatches, Some(0));
    }
}
