//! Chapter 11's report ([`super::cost`]) as Markdown tables and a
//! log-log SVG plot. Formatting only: every figure comes from the report.

use std::fmt::Write as _;
use std::time::Duration;

use super::cost::{BRUTE_FORCE_MAX_TRIANGLES, BvhCostReport, Crossover, RAY_COUNT, SplitTable};
use super::measure::{Measurement, Method};
use crate::bvh::SplitRule;

fn ms(duration: Duration) -> String {
    format!("{:.3}", duration.as_secs_f64() * 1e3)
}

fn mismatches(measurement: &Measurement) -> String {
    measurement
        .mismatches
        .map_or_else(|| "—".to_string(), |count| count.to_string())
}

fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// The three tables as Markdown, each with a line saying what it measured.
pub fn markdown(report: &BvhCostReport) -> String {
    let mut text = String::new();
    write_scaling_table(&mut text, report);
    if let Some(split) = &report.split {
        write_split_table(&mut text, split);
    }
    write_crossover_table(&mut text, &report.crossover);
    text
}

/// The scaling table: the SAH tree and brute force at each torus size.
fn write_scaling_table(text: &mut String, report: &BvhCostReport) {
    let repeats = report.options.repeats.max(1);
    let _ = writeln!(
        text,
        "\n### The tree (chapter 11)\n\n\
         One thread; times are the thread's CPU time (waits for a core on a busy machine left out), median of {repeats} runs; {RAY_COUNT} fixed rays (3072 from \
         a camera, about half of them missing, 1024 from inside the tube). Brute force is \
         chapter 3's loop over every triangle, timed up to {} triangles (above, \"—\": \
         it tests every triangle for every ray). Mismatches: rays whose nearest hit differs \
         from brute force's.\n",
        thousands(BRUTE_FORCE_MAX_TRIANGLES)
    );
    text.push_str(
        "| triangles | build (ms) | trace (ms) | brute force trace (ms) | nodes | depth | memory (bytes) | hits | mismatches |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for row in &report.scaling {
        let tree = row.tree.tree.unwrap_or_default();
        let _ = writeln!(
            text,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            thousands(row.triangles),
            ms(row.tree.build),
            ms(row.tree.trace),
            row.brute_force
                .as_ref()
                .map_or_else(|| "—".to_string(), |brute| ms(brute.trace)),
            thousands(tree.nodes),
            tree.depth,
            thousands(tree.memory_bytes),
            row.tree.hits,
            mismatches(&row.tree),
        );
    }
}

/// The split rule and leaf size table, at one size.
fn write_split_table(text: &mut String, split: &SplitTable) {
    let _ = writeln!(
        text,
        "\nSplit rule and leaf size at {} triangles (16 bins; same rays){}:\n",
        thousands(split.triangles),
        if split.checked {
            ""
        } else {
            "; too many triangles for brute force, so mismatches are not counted"
        }
    );
    text.push_str(
        "| split | max leaf | build (ms) | trace (ms) | nodes | leaves | depth | mismatches |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for tree in &split.trees {
        let Method::Bvh(options) = tree.method else {
            continue;
        };
        let stats = tree.tree.unwrap_or_default();
        let _ = writeln!(
            text,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            split_rule_name(options.split),
            options.max_leaf,
            ms(tree.build),
            ms(tree.trace),
            thousands(stats.nodes),
            thousands(stats.leaves),
            stats.depth,
            mismatches(tree),
        );
    }
}

fn split_rule_name(split: SplitRule) -> &'static str {
    match split {
        SplitRule::Sah => "SAH",
        SplitRule::Midpoint => "midpoint",
    }
}

/// The loop-or-tree table, with the sphere count from which the tree wins.
fn write_crossover_table(text: &mut String, crossover: &Crossover) {
    let _ = writeln!(
        text,
        "\nLoop or tree: scenes of k spheres and a floor plane, the same rays; the tree's time \
         is its build plus its trace (what a render pays); median of {} (passes over every k), loop \
         and tree taking turns. {}\n",
        crate::text::count(u64::from(crossover.runs), "run"),
        match crossover.from {
            Some(k) => format!("The tree is faster from k = {k} on."),
            None => "The tree is not faster at the largest k swept.".to_string(),
        }
    );
    text.push_str(
        "| spheres | loop (ms) | tree (ms) | faster | mismatches |\n|---:|---:|---:|---|---:|\n",
    );
    for row in &crossover.rows {
        let _ = writeln!(
            text,
            "| {} | {} | {} | {} | {} |",
            row.spheres,
            ms(row.loop_time),
            ms(row.tree_time),
            if row.tree_time < row.loop_time {
                "tree"
            } else {
                "loop"
            },
            row.mismatches,
        );
    }
}

/// Build and trace time against triangles, both axes logarithmic, with
/// brute force's trace where it was measured, as SVG.
pub fn scaling_svg(report: &BvhCostReport) -> Result<String, crate::plots::PlotError> {
    draw_scaling(report).map_err(crate::plots::PlotError::drawing)
}

/// A curve: its legend, its colour, its (triangles, seconds) points.
type Series = (&'static str, plotters::style::RGBColor, Vec<(f64, f64)>);

fn draw_scaling(report: &BvhCostReport) -> Result<String, Box<dyn std::error::Error>> {
    use plotters::prelude::*;

    let series = scaling_series(report);
    let (x_range, y_range) = plot_ranges(&series);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (800, 520)).into_drawing_area();
        root.fill(&WHITE)?;
        let (plot_area, note_area) = root.split_vertically(490);
        draw_chart(&plot_area, report.rays, x_range, y_range, series)?;
        note_area.draw(&Text::new(
            format!(
                "Thread CPU time, median of {}. Brute force (chapter 3's loop) is timed up to {} triangles.",
                crate::text::count(u64::from(report.options.repeats.max(1)), "run"),
                BRUTE_FORCE_MAX_TRIANGLES
            ),
            (16, 8),
            ("sans-serif", 12),
        ))?;
        root.present()?;
    }
    Ok(svg)
}

/// The tree's build and trace times and brute force's trace (where it was
/// measured), against triangles.
fn scaling_series(report: &BvhCostReport) -> [Series; 3] {
    use plotters::style::RGBColor;

    let seconds = |d: Duration| d.as_secs_f64().max(1e-7);
    [
        (
            "SAH tree: build",
            RGBColor(31, 119, 180),
            report
                .scaling
                .iter()
                .map(|r| (r.triangles as f64, seconds(r.tree.build)))
                .collect(),
        ),
        (
            "SAH tree: trace",
            RGBColor(44, 160, 44),
            report
                .scaling
                .iter()
                .map(|r| (r.triangles as f64, seconds(r.tree.trace)))
                .collect(),
        ),
        (
            "brute force: trace",
            RGBColor(214, 39, 40),
            report
                .scaling
                .iter()
                .filter_map(|r| {
                    r.brute_force
                        .as_ref()
                        .map(|b| (r.triangles as f64, seconds(b.trace)))
                })
                .collect(),
        ),
    ]
}

/// The x and y ranges that hold every point of `series`, widened to whole
/// decades (so the ticks are powers of ten), at least one decade each; a
/// fixed frame when there is no point.
fn plot_ranges(series: &[Series]) -> ((f64, f64), (f64, f64)) {
    let all = series.iter().flat_map(|(_, _, points)| points.iter());
    let (mut x_low, mut x_high, mut y_low, mut y_high) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in all {
        x_low = x_low.min(x);
        x_high = x_high.max(x);
        y_low = y_low.min(y);
        y_high = y_high.max(y);
    }
    if x_low > x_high {
        (x_low, x_high, y_low, y_high) = (10.0, 1e6, 1e-6, 1.0);
    }
    (whole_decades(x_low, x_high), whole_decades(y_low, y_high))
}

/// `low..high` widened to powers of ten, at least one decade apart.
fn whole_decades(low: f64, high: f64) -> (f64, f64) {
    let decade = |v: f64, up: bool| {
        let power = if up {
            v.log10().ceil()
        } else {
            v.log10().floor()
        };
        10f64.powf(power)
    };
    (
        decade(low, false),
        decade(high * 1.01, true).max(low * 10.0),
    )
}

/// The axes' ticks: each power of ten from `low` to `high` (themselves
/// powers of ten).
fn decades(low: f64, high: f64) -> Vec<f64> {
    let (first, last) = (low.log10().round() as i32, high.log10().round() as i32);
    (first..=last).map(|p| 10f64.powi(p)).collect::<Vec<_>>()
}

/// The log-log chart: caption, axes, each non-empty curve with its points,
/// and the legend.
fn draw_chart(
    area: &plotters::drawing::DrawingArea<
        plotters::backend::SVGBackend<'_>,
        plotters::coord::Shift,
    >,
    rays: usize,
    (x_low, x_high): (f64, f64),
    (y_low, y_high): (f64, f64),
    series: [Series; 3],
) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;

    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("raylab cost, chapter 11: time against triangles ({rays} rays, one thread)"),
            ("sans-serif", 20),
        )
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d(
            (x_low..x_high)
                .log_scale()
                .with_key_points(decades(x_low, x_high)),
            (y_low..y_high)
                .log_scale()
                .with_key_points(decades(y_low, y_high)),
        )?;
    chart
        .configure_mesh()
        .x_desc("triangles (generated torus)")
        .y_desc("thread CPU seconds (median)")
        .x_label_formatter(&|x| format!("{x:e}"))
        .y_label_formatter(&|y| format!("{y:e}"))
        .draw()?;
    for (label, colour, points) in series {
        if points.is_empty() {
            continue;
        }
        chart
            .draw_series(LineSeries::new(points.clone(), colour.stroke_width(2)))?
            .label(label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 16, y)], colour.stroke_width(2))
            });
        chart.draw_series(
            points
                .into_iter()
                .map(move |point| Circle::new(point, 4, colour.filled())),
        )?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}
