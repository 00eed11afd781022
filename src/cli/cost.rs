//! `raylab cost`: what accuracy costs in time, knob by knob.

use crate::Chapters;
use std::io::IsTerminal;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;

use super::render::select_scene;
use crate::cost::{CostConfig, Knob};

/// The BVH report's plot, beside cost.md.
pub const BVH_PLOT: &str = "bvh-scaling.svg";

/// The default size: small enough that a sweep takes seconds in release.
const DEFAULT_WIDTH: u32 = 160;
const DEFAULT_HEIGHT: u32 = 120;

#[derive(Debug, Args)]
pub struct CostArgs {
    /// Chapter whose knobs to sweep (2 on): 2 adds the sphere formula, 4
    /// the secondary-ray offset, 6 the reflection depth, 7 the samples
    /// and the lab report's neighbour average, 9
    /// the Fresnel model, 10 the triangle test (and counts the rays that
    /// leak through a closed mesh), 11 the BVH report (build and trace
    /// time against triangles, split rule, leaf size, loop or tree), 12
    /// the march of implicit surfaces and their normals, 13 path tracing's
    /// samples and switches, 14 the light paths.
    #[arg(short, long, value_parser = crate::chapters::parse_chapter)]
    pub chapter: u8,
    /// A TOML scene to sweep instead of the chapter's built-in one.
    #[arg(short, long, value_name = "FILE")]
    pub scene: Option<PathBuf>,
    /// Image width in pixels.
    #[arg(long, default_value_t = DEFAULT_WIDTH)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = DEFAULT_HEIGHT)]
    pub height: u32,
    /// Renders per setting; the time reported is their median.
    #[arg(long, default_value_t = 3)]
    pub repeats: u32,
    /// Sweep only this knob (repeat for several) [default: all the chapter has].
    #[arg(long, value_enum)]
    pub knob: Vec<Knob>,
    /// Folder for cost.csv, cost.md and cost.svg [default: cost-chapter-N].
    #[arg(short, long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Worker threads, 1 to 1024 [default: one per core].
    #[arg(long, value_parser = crate::cli::parse_threads)]
    pub threads: Option<usize>,
    /// The BVH report's largest torus, in triangles: its sizes (10 to 1 M)
    /// above this are skipped, for a quick run [default: all].
    #[arg(long, value_name = "N")]
    pub max_triangles: Option<usize>,
}

pub fn cost<C: Chapters>(args: &CostArgs) -> Result<i32> {
    let chapter = args.chapter;
    let knobs = chosen_knobs(args)?;
    let bvh = knobs.contains(&Knob::Bvh);
    let neighbours = knobs.contains(&Knob::Neighbours);
    // The BVH report renders nothing, and the neighbours' measurement makes
    // its own images: the sweep's knobs are the others.
    let image_knobs: Vec<Knob> = knobs
        .iter()
        .copied()
        .filter(|k| !matches!(k, Knob::Bvh | Knob::Neighbours))
        .collect();
    check_options(args, bvh, &image_knobs, neighbours)?;
    let (scene, _) = select_scene(Some(chapter), args.scene.as_deref())?;
    let overrides = super::render::SettingsOverrides {
        width: Some(args.width),
        height: Some(args.height),
        threads: args.threads,
        ..Default::default()
    };
    let base = overrides.apply(scene.render)?;
    // The reference supersamples: check that its settings are valid too.
    crate::cost::reference_settings(&base)
        .validate()
        .map_err(|message| anyhow::anyhow!("invalid render settings: {message}"))?;
    let outputs = Outputs::prepare(args, !image_knobs.is_empty(), bvh)?;

    let mut markdown = String::new();
    let mut sweep_files = None;
    let mut command = command_line(args, &knobs, neighbours);
    let scene_name = match &args.scene {
        Some(path) => path.display().to_string(),
        None => "built-in scene".to_string(),
    };
    if !image_knobs.is_empty() {
        let config = CostConfig {
            chapter,
            scene: scene.clone(),
            scene_name: scene_name.clone(),
            base,
            knobs: image_knobs,
            repeats: args.repeats,
        };
        let (report, leaks) = sweep::<C>(args, &config, &overrides)?;
        command = report.command(&knobs, None);
        markdown = format!("{}{leaks}", report.markdown());
        sweep_files = Some((report.csv(), report.svg()?));
    }
    if neighbours {
        if std::io::stderr().is_terminal() {
            eprintln!("measuring the report's neighbour average against supersampling...");
        }
        let report = overrides.in_pool(|| {
            crate::cost::neighbours::run::<C>(&scene, &scene_name, chapter, &base, args.repeats)
        })??;
        markdown.push_str(&report.markdown());
    }
    let mut plot = None;
    if bvh {
        let (bvh_markdown, bvh_plot) = bvh_report(args)?;
        markdown.push_str(&bvh_markdown);
        plot = Some(bvh_plot);
        if let Some(max) = args.max_triangles {
            command.push_str(&format!(" --max-triangles {max}"));
        }
    }
    if let Some(out) = args.out.as_ref().and_then(|p| p.to_str()) {
        command.push_str(&format!(" --out {out}"));
    }
    let markdown = format!("{markdown}\nReproduce with `{command}`.\n");
    // All or nothing: a full disk must not leave a table without its plot.
    let mut contents: Vec<&[u8]> = Vec::new();
    if let Some((csv, svg)) = &sweep_files {
        contents.extend([csv.as_bytes(), markdown.as_bytes(), svg.as_bytes()]);
    } else {
        contents.push(markdown.as_bytes());
    }
    if let Some(plot) = &plot {
        contents.push(plot.as_bytes());
    }
    outputs.write(&contents)?;
    print!("{}", crate::text::terminal_safe(&markdown));
    outputs.print_written();
    Ok(0)
}

/// The knobs to sweep: those asked for (sorted, without repeats), or all
/// the chapter has. An error when one asked for comes with a later
/// chapter, or when the chapter has none.
fn chosen_knobs(args: &CostArgs) -> Result<Vec<Knob>> {
    let chapter = args.chapter;
    let available = Knob::of_chapter(chapter);
    let knobs = if args.knob.is_empty() {
        available.clone()
    } else {
        let mut knobs = args.knob.clone();
        knobs.sort();
        knobs.dedup();
        if let Some(knob) = knobs.iter().find(|k| !available.contains(k)) {
            bail!(
                "chapter {chapter} has no {} knob: it comes with chapter {}",
                knob.name(),
                knob.chapter()
            );
        }
        knobs
    };
    if knobs.is_empty() {
        bail!(
            "chapter {chapter} has no accuracy knob to sweep: the sphere formula comes with \
             chapter 2, the ray offset with 4, depth with 6, samples with 7, fresnel with 9, \
             the triangle test with 10, the BVH report with 11"
        );
    }
    Ok(knobs)
}

/// The command that makes this run's table again, for runs without a
/// sweep (whose report writes its own): the knobs unless they are all
/// the chapter's, and the scene and size when the neighbours' measurement
/// renders them.
fn command_line(args: &CostArgs, knobs: &[Knob], neighbours: bool) -> String {
    let mut command = format!("raylab cost --chapter {}", args.chapter);
    if neighbours {
        if let Some(scene) = &args.scene {
            command.push_str(&format!(" --scene {}", scene.display()));
        }
        command.push_str(&format!(" --width {} --height {}", args.width, args.height));
    }
    command.push_str(&format!(" --repeats {}", args.repeats));
    if knobs != Knob::of_chapter(args.chapter).as_slice() {
        for knob in knobs {
            command.push_str(&format!(" --knob {}", knob.name()));
        }
    }
    command
}

/// Refuses the options this run cannot use: a scene with only the BVH
/// report, --max-triangles without it or below its smallest torus, and
/// out-of-range --threads and --repeats.
fn check_options(args: &CostArgs, bvh: bool, image_knobs: &[Knob], neighbours: bool) -> Result<()> {
    if image_knobs.is_empty() && !neighbours && args.scene.is_some() {
        bail!(
            "--scene: the BVH report measures its own generated torus and spheres; \
             add an image knob to sweep a scene"
        );
    }
    if let Some(max) = args.max_triangles {
        if !bvh {
            bail!(
                "--max-triangles sizes the BVH report, which this run does not make (--knob bvh)"
            );
        }
        let smallest = crate::bvh_reports::cost::SCALING_SIZES[0];
        if max < smallest {
            bail!(
                "--max-triangles {max}: the BVH report's smallest torus has {smallest} triangles"
            );
        }
    }
    if args.threads == Some(0) {
        bail!("--threads must be at least 1");
    }
    if !(1..=100).contains(&args.repeats) {
        bail!("--repeats {}: must be between 1 and 100", args.repeats);
    }
    Ok(())
}

/// The files a run writes, in its output folder.
struct Outputs {
    folder: PathBuf,
    names: Vec<&'static str>,
    files: Vec<PathBuf>,
}

impl Outputs {
    /// Creates the folder and checks that the files can be written there
    /// (and would not replace the scene), before the sweep rather than after
    /// minutes of rendering. `sweep`: the image knobs' CSV, table and plot;
    /// `bvh`: the BVH report's plot; the table is always written.
    fn prepare(args: &CostArgs, sweep: bool, bvh: bool) -> Result<Outputs> {
        let folder = args
            .out
            .clone()
            .unwrap_or_else(|| PathBuf::from(format!("cost-chapter-{}", args.chapter)));
        std::fs::create_dir_all(&folder)
            .with_context(|| format!("cannot create the output folder {}", folder.display()))?;
        if !folder.is_dir() {
            bail!("--out {}: not a folder", folder.display());
        }
        let mut names = Vec::new();
        if sweep {
            names.extend(["cost.csv", "cost.md", "cost.svg"]);
        } else {
            names.push("cost.md");
        }
        if bvh {
            names.push(BVH_PLOT);
        }
        let files: Vec<PathBuf> = names.iter().map(|name| folder.join(name)).collect();
        let inputs: Vec<&std::path::Path> = args.scene.as_deref().into_iter().collect();
        let outputs: Vec<_> = files.iter().map(|file| ("--out", file.as_path())).collect();
        crate::output::check_outputs(&inputs, &outputs, false)?;
        Ok(Outputs {
            folder,
            names,
            files,
        })
    }

    /// Writes `contents`, one for each file in order, all or nothing.
    fn write(&self, contents: &[&[u8]]) -> Result<()> {
        let writes: Vec<(&std::path::Path, &[u8])> = self
            .files
            .iter()
            .map(PathBuf::as_path)
            .zip(contents.iter().copied())
            .collect();
        crate::output::write_files(&writes)?;
        Ok(())
    }

    /// The `wrote ...` line.
    fn print_written(&self) {
        let folder = crate::text::terminal_safe(&self.folder.display().to_string());
        let written: Vec<String> = self
            .names
            .iter()
            .map(|name| format!("{folder}/{name}"))
            .collect();
        println!("wrote {}", written.join(", "));
    }
}

/// Sweeps the image knobs of `config` on the --threads pool, with a progress
/// bar on a terminal; with the triangle test, the leak counts of chapter 10
/// as a Markdown section (else an empty one).
fn sweep<C: Chapters>(
    args: &CostArgs,
    config: &CostConfig,
    overrides: &super::render::SettingsOverrides,
) -> Result<(crate::cost::CostReport, String)> {
    let progress = std::io::stderr().is_terminal().then(|| {
        let bar = indicatif::ProgressBar::new(crate::cost::render_count(config));
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} sweeping [{bar:40}] {pos}/{len} renders, {eta} left",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    });
    let report = overrides.in_pool(|| crate::cost::run::<C>(config, progress.as_ref()))??;
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }
    let leaks = if config.knobs.contains(&Knob::TriangleTest) {
        let counts = overrides.in_pool(|| {
            crate::bvh_reports::leaks::LEAK_MESH_SIZES
                .iter()
                .map(|&size| {
                    crate::bvh_reports::leaks::leaks_of_both_tests::<C>(size, args.repeats)
                })
                .collect::<Result<Vec<_>, crate::mesh::MeshError>>()
        })??;
        leak_table(&counts)
    } else {
        String::new()
    };
    Ok((report, leaks))
}

/// The BVH report, as Markdown and its SVG plot.
fn bvh_report(args: &CostArgs) -> Result<(String, String)> {
    if std::io::stderr().is_terminal() {
        eprintln!("measuring the tree (one thread; the largest torus takes the longest)...");
    }
    let options = crate::bvh_reports::cost::BvhCostOptions {
        repeats: args.repeats,
        max_triangles: args.max_triangles.unwrap_or(usize::MAX),
    };
    // One thread by design (see crate::bvh_reports::cost): no pool needed.
    let report = crate::bvh_reports::cost::run(&options)?;
    Ok((
        crate::bvh_reports::format::markdown(&report),
        crate::bvh_reports::format::scaling_svg(&report)?,
    ))
}

/// The leak counts of chapter 10, as a Markdown section.
fn leak_table(counts: &[[crate::bvh_reports::leaks::LeakCount; 2]]) -> String {
    let mut table = String::from(
        "\nRays from inside raylab's generated closed model (a lumpy torus; each ray starts on \
         the tube's core circle) toward every vertex and every edge midpoint, which must all \
         hit it (one thread, median of the repeats, each ray tested against every \
         triangle):\n\n\
         | triangles | rays | test | escaped | time (s) |\n|---:|---:|---|---:|---:|\n",
    );
    for count in counts.iter().flatten() {
        let test = match count.test {
            crate::scene::TriangleTest::MollerTrumbore => "moller-trumbore",
            crate::scene::TriangleTest::Watertight => "watertight",
        };
        table.push_str(&format!(
            "| {} | {} | {test} | {} | {:.3} |\n",
            count.triangles, count.rays, count.escaped, count.seconds
        ));
    }
    table
}
