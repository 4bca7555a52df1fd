//! The tuner's figures (PNG or SVG by extension), the analogues of the paper's:
//! - Fig. 7: the calibration loops, the quantity (K, T) against its target, the parameter
//!   (E, m) and the relative error per iteration ([`loops_figure`]);
//! - Figs. 8 and 9: zeta over an (alpha, beta) grid as a heat map with the best point,
//!   the paper's point and the target valley ([`heat_map`]);
//! - the valley of (alpha, beta) pairs that give the target zeta ([`valley_figure`]);
//! - Fig. 10: the reference decay (a measured record, or the experiment's T and zeta),
//!   the simulation laid over it and the residual, in m/s^2 ([`decay_figure`]).
//!
//! The figures implement `coil_postproc::plot::Figure` and are written by its renderer:
//! the same embedded font (DejaVu Sans), size and atomic output as the post-processor's
//! plots.

mod decay;
mod style;
#[cfg(test)]
mod tests;

pub use decay::{align, decay_figure, Alignment, DecayTrace};
pub use style::{range_of, short};

use crate::error::Result;
use crate::grid::GridResult;
use crate::loops::LoopReport;
use coil_postproc::plot::{self, Draw, Figure, FONT, SIZE};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use style::{colour, e, render, whole, BLUE, GREEN, RED, TUNER_AXES};

struct LoopsFigure<'a> {
    loops: &'a [&'a LoopReport],
}

/// The floor of |relative error| on the log axis (an exact hit would be log(0)).
const ERROR_FLOOR: f64 = 1e-16;

/// Plain name and unit of a quantity or parameter name as coil writes them.
pub(crate) fn plain_name(name: &str) -> (&str, &str) {
    match name {
        "stiffness_n_mm" => ("stiffness K", "N/mm"),
        "period_s" => ("period T", "s"),
        "damping_ratio" => ("damping ratio zeta", "-"),
        "youngs_modulus_mpa" => ("Young's modulus E", "MPa"),
        "mass_kg" => ("mass of the weight m", "kg"),
        "alpha" | "rayleigh_alpha" => ("Rayleigh alpha", "1/s"),
        "beta" | "rayleigh_beta" => ("Rayleigh beta", "s"),
        other => (other, "-"),
    }
}

/// A panel of values against iteration 1..=n.
fn iteration_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: String,
    y_desc: String,
    n: f64,
    (lo, hi): (f64, f64),
) -> std::result::Result<
    ChartContext<
        'a,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    String,
> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, (FONT, 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(100)
        .build_cartesian_2d(0.5..n + 0.5, lo..hi)
        .map_err(e)?;
    plot::axes(
        &mut chart.configure_mesh(),
        "iteration",
        &y_desc,
        TUNER_AXES,
    )
    .x_label_formatter(&whole)
    .y_label_formatter(&short)
    .draw()
    .map_err(e)?;
    Ok(chart)
}

impl Figure for LoopsFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        root.fill(&WHITE).map_err(e)?;
        let root = root
            .titled(
                "Calibration loops (the paper's Fig. 6): each run of the model, in order",
                (FONT, 26),
            )
            .map_err(e)?;
        let rows = root.split_evenly((self.loops.len().max(1), 3));
        for (k, report) in self.loops.iter().enumerate() {
            let n = report.iterations.len() as f64;
            let (quantity, quantity_unit) = plain_name(&report.quantity);
            let (parameter, parameter_unit) = plain_name(&report.parameter);
            let symbol = |name: &str| name.rsplit(' ').next().unwrap_or(name).to_string();

            // The quantity the loop drives to its target (K, T), with the target.
            let results: Vec<(f64, f64)> = report
                .iterations
                .iter()
                .map(|i| (i.iteration as f64, i.result))
                .collect();
            let (lo, hi) = range_of(
                results
                    .iter()
                    .map(|p| p.1)
                    .chain(std::iter::once(report.target)),
            );
            let mut first = iteration_chart(
                &rows[3 * k],
                format!("Loop {}: {quantity} against its target", k + 1),
                format!("{} [{quantity_unit}]", symbol(quantity)),
                n,
                (lo, hi),
            )?;
            first
                .draw_series(LineSeries::new(
                    [(0.5, report.target), (n + 0.5, report.target)],
                    RED.stroke_width(2),
                ))
                .map_err(e)?
                .label(format!("target {} {quantity_unit}", short(&report.target)))
                .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], RED.stroke_width(2)));
            first
                .draw_series(LineSeries::new(results.clone(), BLUE.stroke_width(2)))
                .map_err(e)?
                .label(format!("{} of the run", symbol(quantity)))
                .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLUE.stroke_width(2)));
            first
                .draw_series(results.iter().map(|&p| Circle::new(p, 6, BLUE.filled())))
                .map_err(e)?;
            first
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .label_font((FONT, 16))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()
                .map_err(e)?;

            // The parameter the loop adjusts (E, m).
            let points: Vec<(f64, f64)> = report
                .iterations
                .iter()
                .map(|i| (i.iteration as f64, i.parameter))
                .collect();
            let (lo, hi) = range_of(points.iter().map(|p| p.1));
            let mut second = iteration_chart(
                &rows[3 * k + 1],
                format!("{parameter} of each run"),
                format!("{} [{parameter_unit}]", symbol(parameter)),
                n,
                (lo, hi),
            )?;
            second
                .draw_series(LineSeries::new(points.clone(), GREEN.stroke_width(2)))
                .map_err(e)?;
            second
                .draw_series(points.iter().map(|&p| Circle::new(p, 6, GREEN.filled())))
                .map_err(e)?;

            // How far from the target, on a log scale, against the tolerance.
            let errors: Vec<(f64, f64)> = report
                .iterations
                .iter()
                .map(|i| (i.iteration as f64, i.relative_error.abs().max(ERROR_FLOOR)))
                .collect();
            let top = errors.iter().fold(report.tolerance, |m, p| m.max(p.1)) * 10.0;
            let bottom = errors
                .iter()
                .fold(report.tolerance, |m, p| m.min(p.1))
                .max(ERROR_FLOOR)
                / 10.0;
            let mut third = ChartBuilder::on(&rows[3 * k + 2])
                .caption(
                    format!("Relative error of {}", symbol(quantity)),
                    (FONT, 22),
                )
                .margin(15)
                .x_label_area_size(45)
                .y_label_area_size(90)
                .build_cartesian_2d(0.5..n + 0.5, (bottom..top).log_scale())
                .map_err(e)?;
            plot::axes(
                &mut third.configure_mesh(),
                "iteration",
                "|relative error| [-]",
                TUNER_AXES,
            )
            .x_label_formatter(&whole)
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .draw()
            .map_err(e)?;
            third
                .draw_series(LineSeries::new(
                    [(0.5, report.tolerance), (n + 0.5, report.tolerance)],
                    RED.stroke_width(1),
                ))
                .map_err(e)?
                .label(format!("tolerance {:.0e}", report.tolerance))
                .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], RED));
            third
                .draw_series(LineSeries::new(errors.clone(), BLUE.stroke_width(2)))
                .map_err(e)?;
            third
                .draw_series(errors.iter().map(|&p| Circle::new(p, 6, BLUE.filled())))
                .map_err(e)?;
            third
                .configure_series_labels()
                .label_font((FONT, 16))
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(e)?;
        }
        Ok(())
    }
}

/// Fig. 7 analogue: each loop's quantity (K, T) against its target, its parameter (E,
/// m) and |relative error| per iteration.
pub fn loops_figure(loops: &[&LoopReport], path: &Path) -> Result<()> {
    render(path, &LoopsFigure { loops })
}

/// What to mark on a heat map besides the cells.
#[derive(Debug, Clone, Default)]
pub struct HeatMapMarks {
    /// The damping ratio aimed at (-).
    pub target_zeta: f64,
    /// The paper's (alpha, beta), drawn when inside the grid.
    pub paper: Option<(f64, f64)>,
    /// The valley `zeta = z0 + a alpha + b beta = target` as (z0, a, b).
    pub valley: Option<(f64, f64, f64)>,
}

struct HeatMap<'a> {
    grid: &'a GridResult,
    marks: &'a HeatMapMarks,
}

impl Figure for HeatMap<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        root.fill(&WHITE).map_err(e)?;
        let (main, bar) = root.split_horizontally(SIZE.0 - 220);
        let spec = &self.grid.spec;
        let half = |axis: &crate::grid::Axis| {
            if axis.count > 1 {
                0.5 * axis.step
            } else {
                0.5 * axis.start.abs().max(1e-6)
            }
        };
        let (ha, hb) = (half(&spec.alpha), half(&spec.beta));
        let (a0, a1) = (spec.alpha.value(0) - ha, spec.alpha.end() + ha);
        let (b0, b1) = (spec.beta.value(0) - hb, spec.beta.end() + hb);
        let zetas: Vec<f64> = self.grid.points.iter().filter_map(|p| p.zeta()).collect();
        let (zmin, zmax) = zetas
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &z| {
                (lo.min(z), hi.max(z))
            });
        let span = if zmax > zmin { zmax - zmin } else { 1.0 };
        let mut chart = ChartBuilder::on(&main)
            .caption(
                format!(
                    "{}: damping ratio over (alpha, beta), {} runs; target zeta = {}",
                    spec.name,
                    self.grid.points.len(),
                    short(&self.marks.target_zeta)
                ),
                (FONT, 26),
            )
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(110)
            .build_cartesian_2d(a0..a1, b0..b1)
            .map_err(e)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("alpha (1/s)")
            .y_desc("beta (s)")
            .x_label_formatter(&short)
            .y_label_formatter(&short)
            .label_style((FONT, 18))
            .draw()
            .map_err(e)?;
        chart
            .draw_series(self.grid.points.iter().map(|p| {
                let fill = match p.zeta() {
                    Some(z) => colour((z - zmin) / span).filled(),
                    None => RGBColor(200, 200, 200).filled(),
                };
                Rectangle::new(
                    [(p.alpha - ha, p.beta - hb), (p.alpha + ha, p.beta + hb)],
                    fill,
                )
            }))
            .map_err(e)?;
        if let Some((z0, a, b)) = self.marks.valley {
            if b > 0.0 {
                let line: Vec<(f64, f64)> = (0..=200)
                    .map(|k| a0 + (a1 - a0) * k as f64 / 200.0)
                    .map(|alpha| (alpha, (self.marks.target_zeta - z0 - a * alpha) / b))
                    .filter(|&(_, beta)| beta >= b0 && beta <= b1)
                    .collect();
                chart
                    .draw_series(LineSeries::new(line, WHITE.stroke_width(3)))
                    .map_err(e)?
                    .label("target valley (transient-fitted plane)")
                    .legend(|(x, y)| {
                        PathElement::new([(x, y), (x + 20, y)], WHITE.stroke_width(3))
                    });
            }
        }
        if let Some(best) = self.grid.best(self.marks.target_zeta) {
            chart
                .draw_series([Circle::new(
                    (best.alpha, best.beta),
                    10,
                    RED.stroke_width(3),
                )])
                .map_err(e)?
                .label(format!(
                    "best: alpha {}, beta {}, zeta {}",
                    short(&best.alpha),
                    short(&best.beta),
                    best.zeta().map_or("-".into(), |z| format!("{z:.6}"))
                ))
                .legend(|(x, y)| Circle::new((x + 10, y), 6, RED.stroke_width(3)));
        }
        if let Some((pa, pb)) = self.marks.paper {
            if pa >= a0 && pa <= a1 && pb >= b0 && pb <= b1 {
                chart
                    .draw_series([Cross::new((pa, pb), 10, BLACK.stroke_width(3))])
                    .map_err(e)?
                    .label(format!("paper: alpha {}, beta {}", short(&pa), short(&pb)))
                    .legend(|(x, y)| Cross::new((x + 10, y), 6, BLACK.stroke_width(3)));
            }
        }
        chart
            .configure_series_labels()
            .label_font((FONT, 18))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(e)?;

        let mut scale = ChartBuilder::on(&bar)
            .margin_top(80)
            .margin_bottom(75)
            .margin_right(20)
            .y_label_area_size(120)
            .caption("zeta", (FONT, 20))
            .build_cartesian_2d(0.0..1.0, zmin..zmin + span)
            .map_err(e)?;
        scale
            .configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_label_formatter(&|z| format!("{z:.2e}"))
            .label_style((FONT, 16))
            .draw()
            .map_err(e)?;
        scale
            .draw_series((0..100).map(|k| {
                let z0 = zmin + span * k as f64 / 100.0;
                let z1 = zmin + span * (k + 1) as f64 / 100.0;
                Rectangle::new([(0.0, z0), (1.0, z1)], colour(k as f64 / 99.0).filled())
            }))
            .map_err(e)?;
        Ok(())
    }
}

/// Figs. 8/9 analogue: zeta over a grid.
pub fn heat_map(grid: &GridResult, marks: &HeatMapMarks, path: &Path) -> Result<()> {
    render(path, &HeatMap { grid, marks })
}

/// The valley to draw: the line, the measured points and the zeta shares.
#[derive(Debug, Clone)]
pub struct ValleyPlot<'a> {
    /// The damping ratio aimed at (-).
    pub target_zeta: f64,
    /// (z0, a, b) of the fitted plane `zeta = z0 + a alpha + b beta`.
    pub plane: (f64, f64, f64),
    /// Measured valley points (alpha, beta, zeta).
    pub points: &'a [(f64, f64, f64)],
    /// Largest alpha drawn, 1/s.
    pub alpha_max: f64,
}

impl Figure for ValleyPlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        root.fill(&WHITE).map_err(e)?;
        let (top, bottom) = root.split_vertically(SIZE.1 / 2);
        let (z0, a, b) = self.plane;
        let amax = self.alpha_max.max(1e-9);
        let line: Vec<(f64, f64)> = (0..=200)
            .map(|k| amax * k as f64 / 200.0)
            .map(|alpha| (alpha, (self.target_zeta - z0 - a * alpha) / b))
            .collect();
        let (blo, bhi) = range_of(
            line.iter()
                .map(|p| p.1)
                .chain(self.points.iter().map(|p| p.1)),
        );
        let mut chart = ChartBuilder::on(&top)
            .caption(
                format!(
                    "pairs (alpha, beta) with zeta = {} from one decay: a one-parameter family",
                    short(&self.target_zeta)
                ),
                (FONT, 24),
            )
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(110)
            .build_cartesian_2d(0.0..amax * 1.02, blo.min(0.0)..bhi)
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("alpha (1/s)")
            .y_desc("beta (s)")
            .x_label_formatter(&short)
            .y_label_formatter(&short)
            .label_style((FONT, 16))
            .draw()
            .map_err(e)?;
        chart
            .draw_series(LineSeries::new(line, BLUE.stroke_width(2)))
            .map_err(e)?
            .label("plane fitted to the grid's transients")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLUE));
        chart
            .draw_series(
                self.points
                    .iter()
                    .map(|&(al, be, _)| Circle::new((al, be), 7, RED.filled())),
            )
            .map_err(e)?
            .label("beta solved by transient runs")
            .legend(|(x, y)| Circle::new((x + 10, y), 5, RED.filled()));
        chart
            .configure_series_labels()
            .label_font((FONT, 16))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(e)?;

        let mut shares = ChartBuilder::on(&bottom)
            .caption(
                "share of zeta from alpha (the wire's mass) and from beta (stiffness)",
                (FONT, 24),
            )
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(110)
            .build_cartesian_2d(0.0..amax * 1.02, 0.0..1.0)
            .map_err(e)?;
        shares
            .configure_mesh()
            .x_desc("alpha (1/s)")
            .y_desc("share of target zeta")
            .x_label_formatter(&short)
            .y_label_formatter(&|y| format!("{:.0}%", 100.0 * y))
            .label_style((FONT, 16))
            .draw()
            .map_err(e)?;
        let t = self.target_zeta;
        shares
            .draw_series(LineSeries::new(
                (0..=100).map(|k| {
                    let al = amax * k as f64 / 100.0;
                    (al, a * al / t)
                }),
                GREEN.stroke_width(2),
            ))
            .map_err(e)?
            .label("alpha: a alpha / zeta")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], GREEN));
        shares
            .draw_series(LineSeries::new(
                (0..=100).map(|k| {
                    let al = amax * k as f64 / 100.0;
                    (al, (t - z0 - a * al) / t)
                }),
                RED.stroke_width(2),
            ))
            .map_err(e)?
            .label("beta: b beta / zeta")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], RED));
        shares
            .configure_series_labels()
            .label_font((FONT, 16))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(e)?;
        Ok(())
    }
}

/// The valley figure.
pub fn valley_figure(valley: &ValleyPlot<'_>, path: &Path) -> Result<()> {
    render(path, valley)
}

/// Table 4's variants' zeta under each damping law calibrated to the same decay.
struct BandPlot<'a>(&'a crate::band::Band);

impl Figure for BandPlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> plot::Draw {
        let b = self.0;
        root.fill(&WHITE).map_err(e)?;
        let n = b.variants.len();
        let hi = b
            .variants
            .iter()
            .flat_map(|v| v.zeta.iter().copied().chain(v.paper_damping_ratio))
            .fold(0.0, f64::max)
            * 1.15;
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Table 4: zeta under each law calibrated to the same decay",
                (FONT, 26),
            )
            .margin(20)
            .x_label_area_size(45)
            .y_label_area_size(90)
            .build_cartesian_2d(-0.5..(n as f64 - 0.5), 0.0..hi)
            .map_err(e)?;
        let names: Vec<String> = b.variants.iter().map(|v| v.name.clone()).collect();
        chart
            .configure_mesh()
            .x_labels(n.max(1))
            .x_label_formatter(&|x| {
                let i = x.round();
                if (x - i).abs() < 1e-6 && i >= 0.0 {
                    names.get(i as usize).cloned().unwrap_or_default()
                } else {
                    String::new()
                }
            })
            .y_desc("zeta")
            .y_label_formatter(&|y| format!("{y:.4}"))
            .label_style((FONT, 16))
            .draw()
            .map_err(e)?;
        let colours = [RED, GREEN, BLUE, RGBColor(148, 103, 189)];
        for (k, (law, colour)) in b.laws.iter().zip(colours).enumerate() {
            let offset = (k as f64 - 1.5) * 0.12;
            chart
                .draw_series(
                    b.variants.iter().enumerate().map(|(i, v)| {
                        Circle::new((i as f64 + offset, v.zeta[k]), 6, colour.filled())
                    }),
                )
                .map_err(e)?
                .label(law.as_str())
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, colour.filled()));
        }
        chart
            .draw_series(b.variants.iter().enumerate().filter_map(|(i, v)| {
                v.paper_damping_ratio
                    .map(|p| Cross::new((i as f64, p), 8, BLACK.stroke_width(2)))
            }))
            .map_err(e)?
            .label("the paper's Table 4")
            .legend(|(x, y)| Cross::new((x + 10, y), 5, BLACK.stroke_width(2)));
        chart
            .configure_series_labels()
            .label_font((FONT, 16))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::LowerRight)
            .draw()
            .map_err(e)?;
        Ok(())
    }
}

/// The damping band figure (`damping_band.png`).
pub fn band_figure(band: &crate::band::Band, path: &Path) -> Result<()> {
    render(path, &BandPlot(band))
}
