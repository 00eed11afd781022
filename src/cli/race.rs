//! `raylab race`: chapter 11's wide tree, and its binary tree beside it,
//! against Embree, on generated models of growing size, on the rays of a
//! render and on incoherent rays (the figures of docs/speed.md and lesson 11).

use anyhow::Result;
use clap::Args;

/// The model sizes raced by default, in triangles.
const DEFAULT_SIZES: [u64; 4] = [1_000, 10_000, 100_000, 1_000_000];

#[derive(Debug, Args)]
pub struct RaceArgs {
    /// Model sizes to race, in triangles (raylab's generated closed model,
    /// `raylab mesh`), comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = DEFAULT_SIZES,
          value_parser = parse_size, allow_hyphen_values = true)]
    pub triangles: Vec<u64>,
    /// Incoherent rays traced per run, the same for both sides (the render's
    /// rays are as many as the render casts, about 543,000).
    #[arg(long, default_value_t = 100_000, value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    pub rays: u64,
    /// Timed runs per side; the figure is their median.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u64).range(1..=100))]
    pub runs: u64,
}

/// A model size: what a scene can load ([`crate::mesh::MAX_MESH_TRIANGLES`]),
/// since one of the races renders the model in a scene.
fn parse_size(text: &str) -> Result<u64, String> {
    super::whole_number(
        text,
        crate::mesh::MAX_MESH_TRIANGLES as u64,
        "each model size in triangles must be",
    )
}

pub fn race(args: &RaceArgs) -> Result<i32> {
    #[cfg(feature = "embree")]
    {
        println!(
            "chapter 11's tree (SAH, 16 bins, leaves of at most 4) folded into nodes of four \
             children (ours), the same binary tree unfolded (binary), Embree (robust scene, \
             default build quality), and chapter 3's loop over every shape (brute force, on the \
             first of the same rays: as many as {} ray-shape tests allow), one thread each, \
             median of {}, the sides taking turns.\n",
            crate::bvh_reports::race::BRUTE_FORCE_TESTS,
            crate::text::count(args.runs, "run")
        );
        println!(
            "1. The rays of a render: chapter 11's built-in scene (`raylab render --chapter \
             11`) with its model resized, 640x480, one sample; every camera and shadow \
             ray it casts (it has no mirrors), in order (what `raylab crosscheck` compares). Ours is \
             the renderer's own search; build is the whole stage's.\n"
        );
        print_header();
        for &size in &args.triangles {
            let measured = crate::bvh_reports::race::race_on_rendered_scene(
                size as usize,
                args.runs as usize,
            )?;
            print_row(&measured);
        }
        println!(
            "\n2. Incoherent rays: {} rays at the lone model from all around, each \
             unrelated to the one before (a stress test: no two rays share a path \
             through the tree).\n",
            args.rays
        );
        print_header();
        for &size in &args.triangles {
            let measured = crate::bvh_reports::race::race_on_generated_mesh(
                size as usize,
                args.rays as usize,
                args.runs as usize,
            )?;
            print_row(&measured);
        }
        println!(
            "\nMemory: ours is the shapes as the renderer stores them plus the tree; \
             Embree's is its own count of its peak (its memory monitor). Embree's first \
             build also creates its device. Rays answered differently: the nearest object \
             differs (a ray through a shared edge may rightly go to either triangle; \
             `raylab crosscheck` tells such boundary cases from disagreements). Work per ray, \
             counted in an untimed pass (the work, where rays/s is its price): the nodes our \
             wide walk opens (four boxes tested at once) and its leaf tests (four triangles at \
             once, or one object of another kind: the floor plane, a sphere); the binary \
             walk's slab tests (the root's included) and ray-object tests (the floor plane \
             included)."
        );
        Ok(0)
    }
    #[cfg(not(feature = "embree"))]
    {
        let _ = args;
        anyhow::bail!(
            "`raylab race` needs Embree: {}",
            super::crosscheck::ENABLE_EMBREE
        )
    }
}

#[cfg(feature = "embree")]
fn print_header() {
    println!(
        "| triangles | rays | ours build | Embree build | ours rays/s | Embree rays/s | \
         ours / Embree | binary rays/s | binary / Embree | ours memory | Embree memory | \
         rays answered differently | brute force rays/s | ours / brute force | \
         ours nodes / ray | ours leaf tests / ray | binary boxes / ray | binary objects / ray |"
    );
    println!(
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
}

#[cfg(feature = "embree")]
fn print_row(measured: &crate::bvh_reports::race::MeshRace) {
    let race = &measured.race;
    println!(
        "| {} | {} | {:.1} ms | {:.1} ms | {:.3} M | {:.3} M | {:.2} | {:.3} M | {:.2} | {:.1} MB | \
         {:.1} MB | {} | {:.0} ({} rays) | {:.0} | {} | {} | {} | {} |",
        measured.triangles,
        race.rays,
        race.ours.build.as_secs_f64() * 1e3,
        race.embree.build.as_secs_f64() * 1e3,
        race.ours.rays_per_second / 1e6,
        race.embree.rays_per_second / 1e6,
        race.ratio(),
        race.second.rays_per_second / 1e6,
        race.second.rays_per_second / race.embree.rays_per_second,
        measured.ours_bytes as f64 / 1e6,
        race.embree_build.peak_bytes as f64 / 1e6,
        measured.different_objects,
        measured.brute_force.rays_per_second,
        measured.brute_force.rays,
        race.ours.rays_per_second / measured.brute_force.rays_per_second,
        per_ray(measured.wide_walk.map(|walk| walk.nodes_per_ray)),
        per_ray(measured.wide_walk.map(|walk| walk.leaf_tests_per_ray)),
        per_ray(measured.walk.map(|walk| walk.boxes_per_ray)),
        per_ray(measured.walk.map(|walk| walk.objects_per_ray)),
    );
}

/// A count per ray, or a dash where our side walks no tree.
#[cfg(feature = "embree")]
fn per_ray(count: Option<f64>) -> String {
    count.map_or("-".to_string(), |count| format!("{count:.1}"))
}
