//! Plots the lessons show, drawn from raylab's own functions so they cannot
//! drift from the code. Each is checked in under `docs/images/` and a test
//! regenerates it (see the lesson that shows it).

use crate::{fresnel, schlick};

/// Why a plot could not be drawn: the plotting library's own reason, which
/// is text (its backends' errors share no type).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("cannot draw the plot: {0}")]
pub struct PlotError(pub String);

impl PlotError {
    /// The error of a drawing function of this crate, for `map_err`.
    pub fn drawing(error: Box<dyn std::error::Error>) -> PlotError {
        PlotError(error.to_string())
    }
}

/// The indices of the Schlick plot: water, glass, diamond.
pub const SCHLICK_INDICES: [f32; 3] = [1.33, 1.5, 2.4];

/// Schlick's error against exact Fresnel, `schlick - fresnel`, over the
/// angle of incidence (0 to 90 degrees, every 0.1), for each index of
/// [`SCHLICK_INDICES`], entering (from air) and leaving (into air), as SVG
/// (chapter 9, `docs/images/schlick-error.svg`).
pub fn schlick_error_svg() -> Result<String, PlotError> {
    draw_schlick_error().map_err(PlotError::drawing)
}

/// `(degrees, schlick - fresnel)` from `n1` into `n2`.
pub fn schlick_error_curve(n1: f32, n2: f32) -> Vec<(f64, f64)> {
    (0..=900)
        .map(|step| {
            let degrees = f64::from(step) / 10.0;
            let c = degrees.to_radians().cos() as f32;
            (
                degrees,
                f64::from(schlick(c, n1, n2)) - f64::from(fresnel(c, n1, n2)),
            )
        })
        .collect()
}

fn draw_schlick_error() -> Result<String, Box<dyn std::error::Error>> {
    use plotters::prelude::*;

    let colours = [
        RGBColor(31, 119, 180),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
    ];
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (800, 480)).into_drawing_area();
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "Schlick's approximation minus exact Fresnel reflectance",
                ("sans-serif", 20),
            )
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(0f64..90f64, -0.08f64..0.08f64)?;
        chart
            .configure_mesh()
            .x_desc("angle of incidence, degrees")
            .y_desc("R(Schlick) - R(exact)")
            .x_labels(10)
            .y_labels(9)
            .y_label_formatter(&|e| format!("{e:.2}"))
            .draw()?;
        for (n, colour) in SCHLICK_INDICES.into_iter().zip(colours) {
            chart
                .draw_series(LineSeries::new(
                    schlick_error_curve(1.0, n),
                    colour.stroke_width(2),
                ))?
                .label(format!("air -> n = {n}"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 16, y)], colour.stroke_width(2))
                });
            // Leaving: dashed, drawn as short segments up to the critical
            // angle (past it both are exactly 1 and the error is 0).
            let leaving = schlick_error_curve(n, 1.0);
            chart
                .draw_series(
                    leaving
                        .chunks(8)
                        .step_by(2)
                        .map(|dash| PathElement::new(dash.to_vec(), colour.stroke_width(1))),
                )?
                .label(format!("n = {n} -> air (dashed)"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 6, y)], colour.stroke_width(1))
                });
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
        root.present()?;
    }
    Ok(svg)
}
