//! A finished sweep as an SVG plot of error against time, drawn with
//! plotters. Its ranges, ticks and chart type are the plot's alone: kept
//! out of the tables, which need none of them.

use super::jobs::PATH_SWITCHES;
use super::{CostReport, Knob, Measurement};

impl CostReport {
    /// Error against time, both on log scales, one colour per knob, the
    /// Pareto front of the main scene joined by a line, as SVG. Settings
    /// identical to the reference (RMSE 0) sit on the bottom edge.
    pub fn svg(&self) -> Result<String, crate::plots::PlotError> {
        plot_svg(self).map_err(crate::plots::PlotError::drawing)
    }
}

/// Round axis ticks between `low` and `high`: 1, 2 and 5 times powers of ten.
/// Parsed from text so that they print as written ("0.005", not
/// "0.005000000000000001").
fn ticks(low: f64, high: f64) -> Vec<f64> {
    let (first, last) = (low.log10().floor() as i32, high.log10().ceil() as i32);
    (first..=last)
        .flat_map(|power| [1, 2, 5].map(|m| format!("{m}e{power}").parse::<f64>()))
        .filter_map(Result::ok)
        .filter(|tick| (low..=high).contains(tick))
        .collect()
}

/// The ranges the plot shows, on log scales: errors from `floor` (where the
/// settings identical to the reference sit) to `largest_error`, times from
/// `fastest` to `slowest`.
struct PlotRanges {
    floor: f64,
    largest_error: f64,
    fastest: f64,
    slowest: f64,
}

impl PlotRanges {
    fn of(rows: &[&Measurement]) -> PlotRanges {
        let smallest_error = rows
            .iter()
            .map(|r| r.error.rmse)
            .filter(|e| *e > 0.0)
            .fold(f64::INFINITY, f64::min);
        let floor = if smallest_error.is_finite() {
            smallest_error / 2.0
        } else {
            0.01
        };
        let largest_error = rows
            .iter()
            .map(|r| r.error.rmse)
            .fold(floor * 4.0, f64::max);
        let positive_seconds = rows.iter().map(|r| r.seconds).filter(|s| *s > 0.0);
        let fastest = positive_seconds.clone().fold(f64::INFINITY, f64::min);
        let slowest = positive_seconds.fold(0.0, f64::max);
        let (fastest, slowest) = if fastest.is_finite() && slowest > 0.0 {
            (fastest, slowest)
        } else {
            (1e-4, 1.0)
        };
        PlotRanges {
            floor,
            largest_error,
            fastest,
            slowest,
        }
    }

    /// Where `row` is drawn: its time and error, moved onto the plot's
    /// edges when they are zero.
    fn point(&self, row: &Measurement) -> (f64, f64) {
        (
            row.seconds.max(self.fastest),
            row.error.rmse.max(self.floor),
        )
    }
}

/// The cost plot's chart: log-scaled time across, log-scaled error up.
type CostChart<'a, 'b> = plotters::chart::ChartContext<
    'a,
    plotters::backend::SVGBackend<'b>,
    plotters::coord::cartesian::Cartesian2d<
        plotters::coord::combinators::WithKeyPoints<plotters::coord::combinators::LogCoord<f64>>,
        plotters::coord::combinators::WithKeyPoints<plotters::coord::combinators::LogCoord<f64>>,
    >,
>;

fn plot_svg(report: &CostReport) -> Result<String, Box<dyn std::error::Error>> {
    use plotters::prelude::*;

    let rows: Vec<&Measurement> = report.rows.iter().filter(|r| r.knob.is_some()).collect();
    let ranges = PlotRanges::of(&rows);
    let PlotRanges {
        floor,
        largest_error,
        fastest,
        slowest,
    } = ranges;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (800, 580)).into_drawing_area();
        root.fill(&WHITE)?;
        let (plot_area, note_area) = root.split_vertically(550);
        let title = format!(
            "raylab cost, chapter {}: error vs time ({}x{})",
            report.chapter, report.width, report.height
        );
        let mut chart = ChartBuilder::on(&plot_area)
            .caption(title, ("sans-serif", 20))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(64)
            .build_cartesian_2d(
                (fastest / 1.5..slowest * 1.5)
                    .log_scale()
                    .with_key_points(ticks(fastest / 1.5, slowest * 1.5)),
                // Headroom above the points for the legend.
                (floor / 1.5..largest_error * 8.0)
                    .log_scale()
                    .with_key_points(ticks(floor / 1.5, largest_error * 8.0)),
            )?;
        chart
            .configure_mesh()
            .x_desc("wall time, seconds (median)")
            .y_desc("RMSE against the reference (sRGB8 codes)")
            .x_label_formatter(&|s| format!("{s}"))
            .y_label_formatter(&|e| format!("{e}"))
            .draw()?;
        let mut front: Vec<&Measurement> = rows.iter().copied().filter(|r| r.pareto).collect();
        front.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
        draw_front(&mut chart, &ranges, &front)?;
        draw_knobs(&mut chart, &ranges, &rows)?;
        draw_root_n(&mut chart, &ranges, &rows)?;
        draw_front_labels(&mut chart, &ranges, &front)?;
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
        note_area.draw(&Text::new(
            format!(
                "Pareto front: the main scene's settings that no other beats on both time and error. \
                 Bottom edge: identical to the reference. Time: median of {}.",
                crate::text::count(u64::from(report.repeats), "run")
            ),
            (16, 8),
            ("sans-serif", 12),
        ))?;
        root.present()?;
    }
    Ok(svg)
}

/// For a path-traced sweep, the error Monte Carlo promises: from the
/// 1-sample row with every switch, `1 / sqrt(N)` of it at `N` times its
/// time (time grows with the samples, so that is `1 / sqrt(time)`).
fn draw_root_n(
    chart: &mut CostChart,
    ranges: &PlotRanges,
    rows: &[&Measurement],
) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    let series: Vec<&&Measurement> = rows
        .iter()
        .filter(|row| row.knob == Some(Knob::Paths) && row.settings.without == rows_base(rows))
        .collect();
    let (Some(first), Some(last)) = (
        series
            .iter()
            .min_by(|a, b| a.settings.samples.cmp(&b.settings.samples)),
        series.iter().max_by(|a, b| a.seconds.total_cmp(&b.seconds)),
    ) else {
        return Ok(());
    };
    let (start, error) = ranges.point(first);
    let end = last.seconds.max(start);
    let steps = 16;
    let line = (0..=steps).map(|step| {
        let time = start * (end / start).powf(f64::from(step) / f64::from(steps));
        (time, (error * (start / time).sqrt()).max(ranges.floor))
    });
    chart
        .draw_series(LineSeries::new(
            line,
            RGBColor(120, 120, 120).stroke_width(1),
        ))?
        .label("1 / sqrt(N) from 1 spp")
        .legend(|(x, y)| {
            PathElement::new(
                vec![(x, y), (x + 16, y)],
                RGBColor(120, 120, 120).stroke_width(1),
            )
        });
    Ok(())
}

/// What the paths knob's "every switch" rows leave out: the smallest set
/// among its rows (the scene's own `without`).
fn rows_base(rows: &[&Measurement]) -> crate::scene::SwitchedOff {
    rows.iter()
        .filter(|row| row.knob == Some(Knob::Paths) && row.label.starts_with(PATH_SWITCHES[0].0))
        .map(|row| row.settings.without)
        .next()
        .unwrap_or_default()
}

/// The Pareto front (sorted by time), as a line through ringed points.
fn draw_front(
    chart: &mut CostChart,
    ranges: &PlotRanges,
    front: &[&Measurement],
) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    chart
        .draw_series(LineSeries::new(
            front.iter().map(|r| ranges.point(r)),
            BLACK.stroke_width(2),
        ))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK.stroke_width(2)));
    chart.draw_series(
        front
            .iter()
            .map(|r| Circle::new(ranges.point(r), 7, BLACK.stroke_width(1))),
    )?;
    Ok(())
}

/// Every setting as a dot, one colour (and legend entry) per knob swept.
fn draw_knobs(
    chart: &mut CostChart,
    ranges: &PlotRanges,
    rows: &[&Measurement],
) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    // One colour a knob (a shorter list would leave the last knobs undrawn).
    let colours: [RGBColor; Knob::ALL.len()] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
        RGBColor(188, 189, 34),
        RGBColor(23, 190, 207),
        RGBColor(0, 0, 128),
        RGBColor(128, 0, 0),
    ];
    for (knob, colour) in Knob::ALL.into_iter().zip(colours) {
        let points: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.knob == Some(knob))
            .map(|r| ranges.point(r))
            .collect();
        if points.is_empty() {
            continue;
        }
        let label = if knob == Knob::SphereFormula {
            "sphere formula (far-sphere scene)"
        } else {
            knob.name()
        };
        chart
            .draw_series(
                points
                    .into_iter()
                    .map(|point| Circle::new(point, 4, colour.filled())),
            )?
            .label(label)
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, colour.filled()));
    }
    Ok(())
}

/// The front's points labelled with their settings, skipping any that
/// would print over a label already placed (points with the same error
/// cluster).
fn draw_front_labels(
    chart: &mut CostChart,
    ranges: &PlotRanges,
    front: &[&Measurement],
) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    let mut labelled: Vec<(f64, f64)> = Vec::new();
    let mut labels: Vec<&Measurement> = Vec::new();
    for r in front {
        let (seconds, error) = ranges.point(r);
        let at = (seconds.log10(), error.log10());
        let crowded = labelled
            .iter()
            .any(|(x, y)| (x - at.0).abs() < 0.25 && (y - at.1).abs() < 0.06);
        if !crowded {
            labelled.push(at);
            labels.push(r);
        }
    }
    chart.draw_series(labels.iter().map(|r| {
        let (seconds, error) = ranges.point(r);
        Text::new(
            r.label.clone(),
            (seconds * 1.06, error * 1.06),
            ("sans-serif", 11),
        )
    }))?;
    Ok(())
}
