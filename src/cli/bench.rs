//! `raylab bench`: time a render several times and print the median.

use crate::Chapters;
use anyhow::Result;
use clap::Args;

use super::render::{SettingsOverrides, select_scene};

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Chapter whose stage to time (see `raylab chapters`) [default: 8, or 8 with --scene].
    #[arg(short, long, value_parser = crate::chapters::parse_chapter)]
    pub chapter: Option<u8>,
    /// A TOML scene file instead of the chapter's built-in scene.
    #[arg(short, long, value_name = "FILE")]
    pub scene: Option<std::path::PathBuf>,
    #[command(flatten)]
    pub overrides: SettingsOverrides,
    /// How many timed renders (after one untimed warm-up).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub runs: u32,
}

/// Renders without writing an image, `runs` times after a warm-up, and
/// prints every time, the median and the rays per second. Times are wall
/// clock on whatever else the machine is doing: quote medians, and compare
/// figures taken on the same machine.
pub fn bench<C: Chapters>(args: &BenchArgs) -> Result<i32> {
    let chapter = args.chapter.or(args.scene.is_none().then_some(8));
    let (scene, chapter) = select_scene(chapter, args.scene.as_deref())?;
    let settings = args.overrides.settings_for(&scene, chapter)?;
    let threads = args
        .overrides
        .threads
        .unwrap_or_else(rayon::current_num_threads);
    let (times, rays) = args.overrides.in_pool(|| {
        let warm_up = crate::render_with::<C>(&scene, chapter, &settings, None)?;
        let times = (0..args.runs)
            .map(|_| Ok(crate::render_with::<C>(&scene, chapter, &settings, None)?.seconds))
            .collect::<Result<Vec<f64>, crate::RenderError>>()?;
        Ok::<_, crate::RenderError>((times, warm_up.rays))
    })??;
    let median = median(&times);
    let samples = if crate::effects::Effects::for_chapter(chapter).antialiasing {
        settings.samples
    } else {
        1
    };
    println!(
        "chapter {chapter}: {}x{}, {samples} spp, {threads} threads, {}",
        settings.width,
        settings.height,
        crate::text::count(u64::from(args.runs), "run")
    );
    let listed: Vec<String> = times.iter().map(|t| format!("{t:.3}")).collect();
    println!("times (s): {}", listed.join(" "));
    println!(
        "median: {median:.3} s, {:.1} M rays/s ({} rays per render)",
        rays.total() as f64 / median / 1e6,
        rays.total()
    );
    Ok(0)
}

/// The median of a non-empty list (the mean of the middle two for an even count).
pub fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let middle = sorted.len() / 2;
    if sorted.len() % 2 == 1 {
        sorted[middle]
    } else {
        (sorted[middle - 1] + sorted[middle]) / 2.0
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(super::median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(super::median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
    }
}
