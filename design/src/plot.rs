//! The design figure (`design.png`): rate against wire mass, the feasible set, the short
//! list by handbook and by FE, the target band. It implements
//! `coil_postproc::plot::Figure` and is written by its renderer (the same embedded font,
//! size and atomic output as every other figure of coil).

use crate::error::{Result, TuneError};
use coil_postproc::plot::{self, Figure, FONT};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// The axes' text (names 18 pt, ticks 16 pt), as the tuner's figures.
const AXES: plot::AxisText = plot::AxisText {
    names: 18,
    ticks: 16,
};

const BLUE: RGBColor = RGBColor(31, 119, 180);
const RED: RGBColor = RGBColor(214, 39, 40);
const GREEN: RGBColor = RGBColor(44, 160, 44);

fn e<T: std::fmt::Display>(x: T) -> String {
    x.to_string()
}

/// What the design figure shows (`design.png`).
#[derive(Debug, Clone, Copy)]
pub struct DesignPlot<'a> {
    /// (mass kg, handbook rate N/mm) of every feasible spring.
    pub feasible: &'a [(f64, f64)],
    /// (mass kg, handbook rate, FE rate, FE-verified) of the short list.
    pub short_list: &'a [(f64, f64, f64, bool)],
    /// The target rate of one spring (N/mm).
    pub rate_n_mm: f64,
    /// Its relative tolerance.
    pub tolerance: f64,
}

impl Figure for DesignPlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> plot::Draw {
        root.fill(&WHITE).map_err(e)?;
        let masses = self
            .feasible
            .iter()
            .map(|p| p.0)
            .chain(self.short_list.iter().map(|p| p.0));
        let (lo, hi) = masses.fold((f64::INFINITY, 0.0f64), |(a, b), m| (a.min(m), b.max(m)));
        let (lo, hi) = if lo.is_finite() && hi > lo {
            (lo * 1e3 * 0.95, hi * 1e3 * 1.05)
        } else {
            (0.0, 1.0)
        };
        let (k0, k1) = (
            self.rate_n_mm * (1.0 - 1.5 * self.tolerance),
            self.rate_n_mm * (1.0 + 1.5 * self.tolerance),
        );
        let mut chart = ChartBuilder::on(root)
            .caption("Design: rate against wire mass", (FONT, 26))
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(90)
            .build_cartesian_2d(lo..hi, k0..k1)
            .map_err(e)?;
        plot::axes(
            &mut chart.configure_mesh(),
            "wire mass (g)",
            "rate (N/mm)",
            AXES,
        )
        .y_label_formatter(&|y| format!("{y:.3}"))
        .draw()
        .map_err(e)?;
        for bound in [1.0 - self.tolerance, 1.0, 1.0 + self.tolerance] {
            let k = self.rate_n_mm * bound;
            let style = if bound == 1.0 {
                BLACK.stroke_width(2)
            } else {
                BLACK.mix(0.5).stroke_width(1)
            };
            chart
                .draw_series(LineSeries::new([(lo, k), (hi, k)], style))
                .map_err(e)?;
        }
        chart
            .draw_series(
                self.feasible
                    .iter()
                    .map(|&(m, k)| Circle::new((m * 1e3, k), 3, BLUE.mix(0.6).filled())),
            )
            .map_err(e)?
            .label("feasible (handbook)")
            .legend(|(x, y)| Circle::new((x + 10, y), 4, BLUE.filled()));
        chart
            .draw_series(
                self.short_list
                    .iter()
                    .map(|&(m, k, _, _)| Circle::new((m * 1e3, k), 6, GREEN.stroke_width(2))),
            )
            .map_err(e)?
            .label("short list (handbook)")
            .legend(|(x, y)| Circle::new((x + 10, y), 5, GREEN.stroke_width(2)));
        chart
            .draw_series(self.short_list.iter().map(|&(m, _, k, ok)| {
                Cross::new(
                    (m * 1e3, k),
                    7,
                    if ok { RED } else { BLACK }.stroke_width(2),
                )
            }))
            .map_err(e)?
            .label("short list (FE; black: rejected)")
            .legend(|(x, y)| Cross::new((x + 10, y), 5, RED.stroke_width(2)));
        chart
            .configure_series_labels()
            .label_font((FONT, 16))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(e)?;
        Ok(())
    }
}

/// The design figure (`design.png`): the target band, the feasible set, the short list.
pub fn design_figure(figure: &DesignPlot<'_>, path: &Path) -> Result<()> {
    plot::render(path, figure).map_err(|source| TuneError::Plot {
        path: path.to_path_buf(),
        message: source.to_string(),
    })
}
