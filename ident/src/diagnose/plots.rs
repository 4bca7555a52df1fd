//! The diagnosis figures: one generic figure of panels with x-y series (lines or
//! points), drawn by the post-processor's renderer (embedded font, atomic output).

use crate::error::{Result, TuneError};
use crate::plots::{range_of as range, short};
use coil_postproc::plot::{self, Draw, Figure, FONT};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

const COLOURS: [RGBColor; 5] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
];

/// One series of a panel.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// The `(x, y)` points, in the panel's units.
    pub points: Vec<(f64, f64)>,
    /// Points (markers) instead of a line.
    pub markers: bool,
}

/// One panel.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Caption above the panel.
    pub title: String,
    /// The x axis label (with its unit).
    pub x: String,
    /// The y axis label (with its unit).
    pub y: String,
    /// The series drawn, in legend order.
    pub series: Vec<Series>,
}

/// Panels stacked vertically; three or more in two columns, so each keeps room for its
/// ticks.
pub struct Panels(pub Vec<Panel>);

fn e<T: std::fmt::Display>(x: T) -> String {
    x.to_string()
}

/// Min/max decimation of a long line to about 4000 points (keeps its envelope).
pub fn decimate(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    const KEEP: usize = 2000;
    if points.len() <= 2 * KEEP {
        return points.to_vec();
    }
    let chunk = points.len().div_ceil(KEEP);
    let mut out = Vec::with_capacity(2 * KEEP);
    for c in points.chunks(chunk) {
        let lo = c.iter().fold(c[0], |m, p| if p.1 < m.1 { *p } else { m });
        let hi = c.iter().fold(c[0], |m, p| if p.1 > m.1 { *p } else { m });
        if lo.0 <= hi.0 {
            out.extend([lo, hi]);
        } else {
            out.extend([hi, lo]);
        }
    }
    out
}

impl Figure for Panels {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        root.fill(&WHITE).map_err(e)?;
        let n = self.0.len().max(1);
        let areas = if n > 2 {
            root.split_evenly((n.div_ceil(2), 2))
        } else {
            root.split_evenly((n, 1))
        };
        for (panel, area) in self.0.iter().zip(&areas) {
            let (x0, x1) = range(
                panel
                    .series
                    .iter()
                    .flat_map(|s| s.points.iter().map(|p| p.0)),
            );
            let (y0, y1) = range(
                panel
                    .series
                    .iter()
                    .flat_map(|s| s.points.iter().map(|p| p.1)),
            );
            let mut chart = ChartBuilder::on(area)
                .caption(panel.title.as_str(), (FONT, 22))
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(90)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(e)?;
            plot::axes(
                &mut chart.configure_mesh(),
                panel.x.as_str(),
                panel.y.as_str(),
                plot::AxisText {
                    names: 17,
                    ticks: 15,
                },
            )
            .x_label_formatter(&short)
            .y_label_formatter(&short)
            .x_labels(8)
            .y_labels(6)
            .draw()
            .map_err(e)?;
            for (k, s) in panel.series.iter().enumerate() {
                let colour = COLOURS[k % COLOURS.len()];
                let legend = move |(x, y): (i32, i32)| {
                    PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(3))
                };
                if s.markers {
                    chart
                        .draw_series(
                            s.points.iter().map(|&p| {
                                Circle::new(p, if k == 0 { 3 } else { 5 }, colour.filled())
                            }),
                        )
                        .map_err(e)?
                        .label(s.label.as_str())
                        .legend(legend);
                } else {
                    chart
                        .draw_series(LineSeries::new(decimate(&s.points), colour.stroke_width(1)))
                        .map_err(e)?
                        .label(s.label.as_str())
                        .legend(legend);
                }
            }
            chart
                .configure_series_labels()
                .label_font((FONT, 15))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(e)?;
        }
        Ok(())
    }
}

/// Draws `panels` into `path` (PNG or SVG by extension).
pub fn draw(path: &Path, panels: Vec<Panel>) -> Result<()> {
    plot::render(path, &Panels(panels)).map_err(|source| TuneError::Plot {
        path: path.to_path_buf(),
        message: source.to_string(),
    })
}
