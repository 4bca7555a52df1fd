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

impl DesignPlot<'_> {
    /// The x range (g) and y range (N/mm) of the chart.
    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let masses = self
            .feasible
            .iter()
            .map(|p| p.0)
            .chain(self.short_list.iter().map(|p| p.0));
        let (lo, hi) = masses.fold((f64::INFINITY, 0.0f64), |(a, b), m| (a.min(m), b.max(m)));
        let x = if lo.is_finite() && hi > lo {
            (lo * 1e3 * 0.95, hi * 1e3 * 1.05)
        } else if lo.is_finite() {
            (lo * 1e3 * 0.9, lo * 1e3 * 1.1 + 1e-9)
        } else {
            (0.0, 1.0)
        };
        let rates = self
            .short_list
            .iter()
            .flat_map(|p| [p.1, p.2])
            .chain(self.feasible.iter().map(|p| p.1));
        let (k_lo, k_hi) = rates.fold(
            (
                self.rate_n_mm * (1.0 - 1.5 * self.tolerance),
                self.rate_n_mm * (1.0 + 1.5 * self.tolerance),
            ),
            |(a, b), k| (a.min(k), b.max(k)),
        );
        let pad = 0.05 * (k_hi - k_lo);
        (x, (k_lo - pad, k_hi + pad))
    }
}

impl Figure for DesignPlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> plot::Draw {
        root.fill(&WHITE).map_err(e)?;
        // The legend has its own strip below the chart: it never covers a point.
        let (chart_area, legend_area) = root.split_vertically(root.dim_in_pixel().1 as i32 - 80);
        let ((lo, hi), (k0, k1)) = self.ranges();
        let mut chart = ChartBuilder::on(&chart_area)
            .caption("Design: rate against wire mass", (FONT, 26))
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(90)
            .build_cartesian_2d(lo..hi, k0..k1)
            .map_err(e)?;
        plot::axes(
            &mut chart.configure_mesh(),
            "wire mass (g)",
            "rate of one spring (N/mm)",
            AXES,
        )
        .y_label_formatter(&|y| format!("{y:.3}"))
        .draw()
        .map_err(e)?;
        let (band_lo, band_hi) = (
            self.rate_n_mm * (1.0 - self.tolerance),
            self.rate_n_mm * (1.0 + self.tolerance),
        );
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(lo, band_lo), (hi, band_hi)],
                GREEN.mix(0.12).filled(),
            )))
            .map_err(e)?;
        chart
            .draw_series(LineSeries::new(
                [(lo, self.rate_n_mm), (hi, self.rate_n_mm)],
                BLACK.stroke_width(2),
            ))
            .map_err(e)?;
        chart
            .draw_series(
                self.feasible
                    .iter()
                    .map(|&(m, k)| Circle::new((m * 1e3, k), 3, BLUE.mix(0.5).filled())),
            )
            .map_err(e)?;
        // Each short-listed spring: its handbook point, its FE point, a line between.
        for &(m, k, k_fe, ok) in self.short_list {
            let colour = if ok { RED } else { BLACK };
            chart
                .draw_series(LineSeries::new(
                    [(m * 1e3, k), (m * 1e3, k_fe)],
                    colour.mix(0.8).stroke_width(2),
                ))
                .map_err(e)?;
            chart
                .draw_series([Circle::new((m * 1e3, k), 6, GREEN.stroke_width(2))])
                .map_err(e)?;
            chart
                .draw_series([Cross::new((m * 1e3, k_fe), 7, colour.stroke_width(2))])
                .map_err(e)?;
        }
        legend(&legend_area)
    }
}

/// The legend strip: what each mark means.
fn legend<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>) -> plot::Draw {
    let font = (FONT, 18).into_font().color(&BLACK);
    let y = 30;
    let mut x = 110i32;
    let text = |x: i32, s: &str| {
        area.draw(&Text::new(s.to_string(), (x, y - 9), font.clone()))
            .map_err(e)
    };
    area.draw(&Circle::new((x, y), 4, BLUE.mix(0.5).filled()))
        .map_err(e)?;
    text(x + 12, "feasible (handbook rate)")?;
    x += 290;
    area.draw(&Circle::new((x, y), 6, GREEN.stroke_width(2)))
        .map_err(e)?;
    text(x + 12, "short list, handbook")?;
    x += 250;
    area.draw(&Cross::new((x, y), 7, RED.stroke_width(2)))
        .map_err(e)?;
    text(x + 12, "FE (black: rejected); line joins one spring")?;
    x += 470;
    area.draw(&Rectangle::new(
        [(x - 8, y - 8), (x + 8, y + 8)],
        GREEN.mix(0.25).filled(),
    ))
    .map_err(e)?;
    text(x + 14, "target +- tolerance")?;
    Ok(())
}

/// The design figure (`design.png`): the target band, the feasible set, the short list.
pub fn design_figure(figure: &DesignPlot<'_>, path: &Path) -> Result<()> {
    plot::render(path, figure).map_err(|source| TuneError::Plot {
        path: path.to_path_buf(),
        message: source.to_string(),
    })
}
