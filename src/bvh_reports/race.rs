//! The speed race: our intersector against Embree on the same
//! rays, for the figures of docs/speed.md and lesson 11 (rays per second on one
//! thread, median of 5; build times; peak memory). Computing only: the
//! caller prints.
//!
//! "Ours" is whatever the caller builds: a closure that builds an
//! intersector and returns the function that traces one ray with it
//! (chapter 11's tree here; [`crate::crosscheck::ours`], the brute-force
//! loop, would do as well).
//!
//! Two sets of rays are raced ([`race_on_generated_mesh`] and
//! [`race_on_rendered_scene`]): rays from all around a lone model, each
//! unrelated to the one before, and the rays a render casts, camera rays
//! pixel after pixel with their shadow rays (and mirror rays in a scene with
//! mirrors), which is what a
//! ray tracer spends its time on and what `raylab crosscheck` compares.
//!
//! Memory is measured two ways, and the race reports both:
//!
//! - **Embree's own count**: Embree 4 calls a memory monitor on every
//!   allocation and free of a device (`rtcSetDeviceMemoryMonitorFunction`,
//!   present in the 4.2 headers `embree4-sys` was generated from and in the
//!   4.4 library we load). That is exact for Embree and independent of what
//!   the process's allocator does, so it is the Embree figure to quote
//!   ([`crate::embree::BuildStats::peak_bytes`]).
//! - **The process's peak resident memory** while a side builds: the
//!   kernel's high-water mark is reset (`5` written to
//!   `/proc/self/clear_refs`), the build runs, and `VmHWM` minus the `VmRSS`
//!   before is the peak growth. This is the only measure for ours, whose
//!   structure is opaque here. It counts everything the process does
//!   meanwhile (run the race alone, not among other tests), and memory the
//!   allocator reuses instead of asking the kernel for is not counted; it is
//!   `None` where `/proc` or `clear_refs` is missing (not Linux, or a
//!   kernel without it).

use std::time::{Duration, Instant};

use crate::CastRay;
use crate::Chapters;
use crate::crosscheck::{Answer, Primitive, rays_per_second};
use crate::embree::{BuildStats, EmbreeError, EmbreeScene};

/// How many times each side traces all the rays; the median is the figure.
pub const RACE_RUNS: usize = 5;

/// One side of the race.
#[derive(Debug, Clone, PartialEq)]
pub struct Side {
    /// Wall-clock time to build the side's structure.
    pub build: Duration,
    /// Rays per second of each run, in the order run.
    pub runs: Vec<f64>,
    /// The median of `runs`.
    pub rays_per_second: f64,
    /// The growth of the process's peak resident memory while building, in
    /// bytes (see the module documentation), if it could be measured.
    pub peak_rss_growth: Option<u64>,
}

/// The outcome of [`race`].
#[derive(Debug, Clone, PartialEq)]
pub struct Race {
    /// How many rays each run traced.
    pub rays: usize,
    pub ours: Side,
    /// A second structure of ours, raced in the same turns on the same rays
    /// (chapter 11's binary tree, beside its wide one): what one changed
    /// gains, measured in one run.
    pub second: Side,
    pub embree: Side,
    /// Embree's build split into filling and BVH build, and its own count
    /// of its memory.
    pub embree_build: BuildStats,
}

impl Race {
    /// Ours over Embree, in rays per second (above 1: ours is faster).
    pub fn ratio(&self) -> f64 {
        self.ours.rays_per_second / self.embree.rays_per_second
    }
}

/// Races ours against Embree over `rays`, on this thread.
///
/// `build_ours` builds our structure (timed, with the peak memory it
/// takes) and returns the function that answers one ray with it;
/// `build_second` likewise another of ours, to compare with it.
/// `primitives` is the same geometry for Embree
/// ([`crate::crosscheck::primitives`] makes it from the shapes); Embree
/// builds on one thread too. Then each side traces every ray `runs` times,
/// the sides taking turns so that a busy moment of a shared machine falls
/// on all; the figure is the median.
pub fn race<O, F, S, G>(
    primitives: &[Primitive],
    rays: &[CastRay],
    build_ours: O,
    build_second: S,
    runs: usize,
) -> Result<Race, EmbreeError>
where
    O: FnOnce() -> F,
    F: Fn(&CastRay) -> Option<Answer>,
    S: FnOnce() -> G,
    G: Fn(&CastRay) -> Option<Answer>,
{
    let runs = runs.max(1);
    let (ours, ours_build, ours_memory) = measure_build(build_ours);
    let (second, second_build, second_memory) = measure_build(build_second);
    let (embree, embree_build_wall, embree_memory) =
        measure_build(|| EmbreeScene::with_threads(primitives, Some(1)));
    let embree = embree?;
    let theirs = |cast: &CastRay| {
        embree
            .intersect(&cast.ray, cast.t_min, cast.t_max)
            .map(|hit| Answer {
                object: hit.object,
                t: hit.t,
            })
    };
    let mut ours_runs = Vec::with_capacity(runs);
    let mut second_runs = Vec::with_capacity(runs);
    let mut embree_runs = Vec::with_capacity(runs);
    for _ in 0..runs {
        ours_runs.push(rays_per_second(rays, &ours));
        second_runs.push(rays_per_second(rays, &second));
        embree_runs.push(rays_per_second(rays, theirs));
    }
    Ok(Race {
        rays: rays.len(),
        ours: Side {
            build: ours_build,
            rays_per_second: median(&ours_runs),
            runs: ours_runs,
            peak_rss_growth: ours_memory,
        },
        second: Side {
            build: second_build,
            rays_per_second: median(&second_runs),
            runs: second_runs,
            peak_rss_growth: second_memory,
        },
        embree: Side {
            build: embree_build_wall,
            rays_per_second: median(&embree_runs),
            runs: embree_runs,
            peak_rss_growth: embree_memory,
        },
        embree_build: embree.build_stats(),
    })
}

/// Runs `build`, timing it and measuring the growth of the peak resident
/// memory it causes.
fn measure_build<T>(build: impl FnOnce() -> T) -> (T, Duration, Option<u64>) {
    let before = reset_peak_rss();
    let start = Instant::now();
    let built = build();
    let elapsed = start.elapsed();
    let growth = before.and_then(|before| Some(status_kb("VmHWM")?.saturating_sub(before) * 1024));
    (built, elapsed, growth)
}

/// Resets the kernel's high-water mark of this process's resident memory
/// to the current resident size, and returns that size in kB; `None` if
/// the kernel does not let us.
fn reset_peak_rss() -> Option<u64> {
    std::fs::write("/proc/self/clear_refs", "5").ok()?;
    status_kb("VmRSS")
}

/// A `kB` field of `/proc/self/status`.
fn status_kb(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status.lines().find_map(|line| {
        let rest = line.strip_prefix(field)?.strip_prefix(':')?;
        rest.trim().strip_suffix("kB")?.trim().parse().ok()
    })
}

/// The median (the mean of the middle two for an even count); NaN for none.
pub fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let middle = sorted.len() / 2;
    match sorted.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => sorted[middle],
        _ => (sorted[middle - 1] + sorted[middle]) / 2.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(median(&[]).is_nan());
    }

    #[test]
    fn status_fields_parse_on_linux() {
        if cfg!(target_os = "linux") {
            assert!(status_kb("VmRSS").is_some_and(|kb| kb > 0));
        }
    }
}

/// The race at one model size: chapter 11's tree against Embree on
/// raylab's generated closed model of about `triangles` triangles.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshRace {
    pub triangles: usize,
    pub race: Race,
    /// The bytes our side keeps: the triangles (as the renderer stores
    /// them) and the tree, counted from their lengths, as Embree's monitor
    /// counts its own.
    pub ours_bytes: usize,
    /// Rays whose nearest object or hit/miss differs between the two sides
    /// (boundary cases such as shared edges can differ legitimately;
    /// `raylab crosscheck` tells them apart).
    pub different_objects: usize,
    /// Chapter 3's loop over every shape, on the first of the same rays.
    pub brute_force: BruteForce,
    /// The nodes our wide walk opens and the leaf tests it makes per ray
    /// (counted in an untimed pass); `None` when our side uses no tree.
    pub wide_walk: Option<super::walk_work::WideWork>,
    /// The boxes and objects the binary walk tests per ray, likewise.
    pub walk: Option<super::walk_work::WalkWork>,
}

/// Brute force (chapter 3: every ray against every shape) on the first
/// `rays` of a race's rays, as many as [`BRUTE_FORCE_TESTS`] allows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BruteForce {
    pub rays: usize,
    /// The median of [`RACE_RUNS`] runs over those rays.
    pub rays_per_second: f64,
}

/// About how many ray-shape tests a brute-force run may make: at a
/// million triangles that is 20 rays, at a thousand 20,000.
pub const BRUTE_FORCE_TESTS: usize = 20_000_000;

/// Times chapter 3's loop over every one of `shapes`, on this thread, on
/// the first of `rays` (at least 10, at most all of them).
pub fn brute_force(shapes: &[crate::Shape], rays: &[CastRay], runs: usize) -> BruteForce {
    let count = (BRUTE_FORCE_TESTS / shapes.len().max(1)).clamp(10, rays.len());
    let rays = &rays[..count.min(rays.len())];
    let rates: Vec<f64> = (0..runs.max(1))
        .map(|_| rays_per_second(rays, |cast| crate::crosscheck::ours(shapes, cast)))
        .collect();
    BruteForce {
        rays: rays.len(),
        rays_per_second: median(&rates),
    }
}

/// `count` rays at the generated model (a torus of radius about 1.5 around
/// the y axis): from points on a sphere of radius 4 around it toward points
/// of its bounding box, so that some hit and some pass through the hole or
/// beside it. Deterministic: ray `i` depends only on `i`.
pub fn rays_at_the_model(count: usize) -> Vec<CastRay> {
    // SplitMix64: a fixed, well-mixed sequence, no dependency.
    fn mix(mut z: u64) -> u64 {
        z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    let unit = |seed: u64| (mix(seed) >> 40) as f32 / (1u64 << 24) as f32;
    (0..count as u64)
        .map(|i| {
            let u = |k: u64| unit(i * 8 + k);
            let theta = std::f32::consts::TAU * u(0);
            let height = 2.0 * u(1) - 1.0;
            let ring = (1.0 - height * height).sqrt();
            let origin = 4.0 * crate::Vec3::new(ring * theta.cos(), height, ring * theta.sin());
            let aim = crate::Vec3::new(3.0 * u(2) - 1.5, u(3) - 0.5, 3.0 * u(4) - 1.5);
            CastRay {
                kind: crate::RayKind::Primary,
                ray: crate::Ray::new(origin, aim - origin),
                t_min: 0.0,
                t_max: f32::INFINITY,
            }
        })
        .collect()
}

/// Why a race on a model did not run. Each message is whole.
#[derive(Debug, thiserror::Error)]
pub enum RaceError {
    #[error(transparent)]
    Mesh(#[from] crate::mesh::MeshError),
    #[error(transparent)]
    Embree(#[from] EmbreeError),
    #[error(transparent)]
    Scene(#[from] crate::SceneError),
    #[error(transparent)]
    Render(#[from] crate::RenderError),
    #[error(transparent)]
    TooManyRays(#[from] crate::record::TooManyRays),
    #[error("chapter 11 has no built-in scene")]
    NoScene,
    /// The built-in scene's model is not written `model`, so it cannot be
    /// resized by replacing that text.
    #[error("chapter 11's built-in scene no longer has a model of `{model}` triangles to resize")]
    NoModel { model: &'static str },
}

/// [`race`] of chapter 11's wide tree (the SAH tree with the default
/// options, collapsed; its build timed), and its binary tree beside it,
/// against Embree over [`rays_at_the_model`], on the generated model of
/// about `triangles` triangles.
pub fn race_on_generated_mesh(
    triangles: usize,
    rays: usize,
    runs: usize,
) -> Result<MeshRace, RaceError> {
    use crate::course::Objects;
    let mesh = crate::mesh::generate_closed_mesh(triangles)?;
    let shapes = super::leaks::triangles(&mesh);
    let primitives: Vec<Primitive> = mesh
        .triangles
        .iter()
        .map(|corners| Primitive::Triangle(corners.map(|index| mesh.positions[index as usize])))
        .collect();
    let rays = rays_at_the_model(rays);
    let bounds: Vec<_> = shapes.iter().map(crate::Shape::bounds).collect();
    let objects = Objects::<crate::Reference>::new(&shapes);
    let build = || crate::Reference::build_bvh(&bounds, &crate::bvh::BvhOptions::default());
    let mut tree_bytes = 0;
    let race = race(
        &primitives,
        &rays,
        || {
            let wide = crate::Reference::collapse_bvh(&build(), &shapes);
            tree_bytes = wide.memory_bytes();
            move |cast: &CastRay| {
                crate::Reference::nearest_hit_wide(
                    &wide, &objects, &cast.ray, cast.t_min, cast.t_max,
                )
                .map(Answer::from)
            }
        },
        || {
            let bvh = build();
            move |cast: &CastRay| {
                crate::Reference::nearest_hit_bvh(&bvh, &objects, &cast.ray, cast.t_min, cast.t_max)
                    .map(Answer::from)
            }
        },
        runs,
    )?;
    // A second pass, untimed, to count the rays the two sides answer
    // differently.
    let bvh = build();
    let wide = crate::Reference::collapse_bvh(&bvh, &shapes);
    let embree = EmbreeScene::with_threads(&primitives, Some(1))?;
    let different_objects = rays
        .iter()
        .filter(|cast| {
            let ours = crate::Reference::nearest_hit_wide(
                &wide, &objects, &cast.ray, cast.t_min, cast.t_max,
            )
            .map(|hit| hit.object);
            let theirs = embree
                .intersect(&cast.ray, cast.t_min, cast.t_max)
                .map(|hit| hit.object);
            ours != theirs
        })
        .count();
    Ok(MeshRace {
        triangles: shapes.len(),
        race,
        ours_bytes: shapes.len() * std::mem::size_of::<crate::Shape>() + tree_bytes,
        different_objects,
        brute_force: brute_force(&shapes, &rays, runs),
        wide_walk: Some(super::walk_work::wide_walk_work(&wide, &shapes, &rays)),
        walk: Some(super::walk_work::walk_work(&bvh, &shapes, &rays)),
    })
}

/// The race on the rays a render casts: chapter 11's built-in scene with
/// its model made of about `triangles` triangles, rendered at the scene's
/// own size (640x480, one sample), every camera and shadow ray (it has no
/// mirrors) recorded in order, then traced by both sides, one thread each. Ours is
/// the stage's own search (the tree, the floor plane outside it, as
/// rendering uses it); Embree gets the same shapes as in
/// `raylab crosscheck` (the plane as a large quad). The build times are
/// ours for the whole stage, Embree's for its scene; memory is not
/// measured here ([`race_on_generated_mesh`] does, on the model alone).
pub fn race_on_rendered_scene(triangles: usize, runs: usize) -> Result<MeshRace, RaceError> {
    const MODEL: &str = "generated = 20000";
    let text = crate::builtin::scene_text(11).ok_or(RaceError::NoScene)?;
    if !text.contains(MODEL) {
        return Err(RaceError::NoModel { model: MODEL });
    }
    let text = text.replacen(MODEL, &format!("generated = {triangles}"), 1);
    let scene = crate::Scene::parse(&text, "chapter 11's built-in scene, resized")?;
    let started = Instant::now();
    let stage = crate::Stage::<crate::Reference>::with_chapters(&scene, 11, scene.render)?;
    let stage_build = started.elapsed();
    let rays = crate::record::record_rays_within(&stage, crate::crosscheck::MAX_RECORDED_RAYS)?;
    let (primitives, _) = crate::crosscheck::primitives(stage.shapes(), &scene);
    let ours = |cast: &CastRay| {
        stage
            .nearest_hit(&cast.ray, cast.t_min, cast.t_max)
            .map(Answer::from)
    };
    let objects = stage.objects();
    let binary = |cast: &CastRay| {
        let hit = match stage.bvh() {
            Some(bvh) => {
                crate::Reference::nearest_hit_bvh(bvh, &objects, &cast.ray, cast.t_min, cast.t_max)
            }
            None => crate::Reference::nearest_hit(&objects, &cast.ray, cast.t_min, cast.t_max),
        };
        hit.map(Answer::from)
    };
    let mut race = race(&primitives, &rays, || ours, || binary, runs)?;
    // The stage was built above, to record the rays; its build is that.
    race.ours.build = stage_build;
    race.ours.peak_rss_growth = None;
    race.second.build = stage_build;
    race.second.peak_rss_growth = None;
    let embree = EmbreeScene::with_threads(&primitives, Some(1))?;
    let different_objects = rays
        .iter()
        .filter(|cast| {
            let theirs = embree.intersect(&cast.ray, cast.t_min, cast.t_max);
            ours(cast).map(|hit| hit.object) != theirs.map(|hit| hit.object)
        })
        .count();
    let triangles = stage
        .shapes()
        .iter()
        .filter(|shape| matches!(shape, crate::Shape::Triangle(_)))
        .count();
    Ok(MeshRace {
        triangles,
        race,
        ours_bytes: std::mem::size_of_val(stage.shapes())
            + stage
                .wide_bvh()
                .map_or(0, crate::bvh::WideBvh::memory_bytes),
        different_objects,
        brute_force: brute_force(stage.shapes(), &rays, runs),
        wide_walk: stage
            .wide_bvh()
            .map(|wide| super::walk_work::wide_walk_work(wide, stage.shapes(), &rays)),
        walk: stage
            .bvh()
            .map(|bvh| super::walk_work::walk_work(bvh, stage.shapes(), &rays)),
    })
}
