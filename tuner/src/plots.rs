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

use crate::error::{Result, TuneError};
use crate::grid::GridResult;
use crate::loops::LoopReport;
use coil_postproc::plot::{self, Draw, Figure, FONT, SIZE};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// The axes of the tuner's figures (names 18 pt, ticks 16 pt).
const TUNER_AXES: plot::AxisText = plot::AxisText {
    names: 18,
    ticks: 16,
};

const BLUE: RGBColor = RGBColor(31, 119, 180);
const RED: RGBColor = RGBColor(214, 39, 40);
const GREEN: RGBColor = RGBColor(44, 160, 44);

/// Draws `figure` into `path` (PNG or SVG) with the post-processor's renderer: same
/// font, same size, same atomic output.
fn render<F: Figure>(path: &Path, figure: &F) -> Result<()> {
    plot::render(path, figure).map_err(|source| TuneError::Plot {
        path: path.to_path_buf(),
        message: source.to_string(),
    })
}

fn e<T: std::fmt::Display>(x: T) -> String {
    x.to_string()
}

/// Viridis-like colour for t in [0, 1].
fn colour(t: f64) -> RGBColor {
    const STOPS: [(f64, [f64; 3]); 5] = [
        (0.0, [68.0, 1.0, 84.0]),
        (0.25, [59.0, 82.0, 139.0]),
        (0.5, [33.0, 145.0, 140.0]),
        (0.75, [94.0, 201.0, 98.0]),
        (1.0, [253.0, 231.0, 37.0]),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let k = STOPS
        .windows(2)
        .position(|w| t <= w[1].0)
        .unwrap_or(STOPS.len() - 2);
    let (t0, c0) = STOPS[k];
    let (t1, c1) = STOPS[k + 1];
    let s = (t - t0) / (t1 - t0);
    let mix = |i: usize| (c0[i] + s * (c1[i] - c0[i])).round() as u8;
    RGBColor(mix(0), mix(1), mix(2))
}

/// Short number for ticks: up to 4 decimals or 3 significant digits.
pub fn short(x: &f64) -> String {
    let x = *x;
    if x.abs() < 1e-15 {
        return "0".into();
    }
    let a = x.abs();
    if (1e-2..1e5).contains(&a) {
        let s = format!("{x:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{x:.2e}")
    }
}

/// Integer tick labels only (iterations).
fn whole(x: &f64) -> String {
    if (x - x.round()).abs() < 1e-6 {
        format!("{}", x.round())
    } else {
        String::new()
    }
}

/// The range of the finite `values`, padded on both sides (axis limits).
pub fn range_of(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.5 * lo.abs().max(1e-12)
    };
    (lo - pad, hi + pad)
}

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

/// One decay record to compare (acceleration of the weight, m/s^2).
#[derive(Debug, Clone, Copy)]
pub struct DecayTrace<'a> {
    /// Label in legends and messages.
    pub label: &'a str,
    /// Time, s.
    pub time_s: &'a [f64],
    /// Acceleration, m/s^2.
    pub accel_m_s2: &'a [f64],
}

/// How the simulation was laid over the reference for the residual.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alignment {
    /// The simulation is read at `t + shift_s`.
    pub shift_s: f64,
    /// And scaled by `gain` (least squares).
    pub gain: f64,
    /// RMS of the residual over RMS of the reference.
    pub relative_rms: f64,
}

/// Linear interpolation of `(time, values)` at `t` (None outside the record).
fn sample(time: &[f64], values: &[f64], t: f64) -> Option<f64> {
    let (first, last) = (*time.first()?, *time.last()?);
    if !(first..=last).contains(&t) {
        return None;
    }
    let i = time.partition_point(|&x| x <= t).clamp(1, time.len() - 1);
    let (t0, t1) = (time[i - 1], time[i]);
    let s = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
    Some(values[i - 1] + s * (values[i] - values[i - 1]))
}

/// Lays `model` over `reference`: a measured record starts some unknown time after the
/// impulse (its phase is unknown) and its amplitude depends on the impulse, so the
/// simulation is shifted by the `shift` in `[0, period)` (steps of the reference's
/// sampling) and scaled by the `gain` that minimise the residual. A reference built on
/// the simulation's own time base needs neither (shift 0, gain 1 to rounding).
/// Returns the alignment and the residual `reference - gain * model(t + shift)` at the
/// reference's times that the shifted simulation covers.
pub fn align(
    reference: &DecayTrace<'_>,
    model: &DecayTrace<'_>,
    period_s: f64,
) -> (Alignment, Vec<(f64, f64)>) {
    let step = if reference.time_s.len() > 1 {
        (reference.time_s[reference.time_s.len() - 1] - reference.time_s[0])
            / (reference.time_s.len() - 1) as f64
    } else {
        period_s
    };
    let shifts = if step > 0.0 && period_s.is_finite() && period_s > 0.0 {
        (period_s / step).ceil().min(10_000.0) as usize
    } else {
        1
    };
    let fit = |shift: f64| {
        let (mut rm, mut mm) = (0.0, 0.0);
        for (&t, &r) in reference.time_s.iter().zip(reference.accel_m_s2) {
            if let Some(m) = sample(model.time_s, model.accel_m_s2, t + shift) {
                rm += r * m;
                mm += m * m;
            }
        }
        let gain = if mm > 0.0 { rm / mm } else { 0.0 };
        // The residual's energy is sum r^2 - gain * rm; a larger gain * rm is better.
        (gain * rm, gain)
    };
    let (mut best_shift, mut best) = (0.0, fit(0.0));
    // A reference on the simulation's own time base (shift 0) is kept unless another
    // shift is clearly better.
    for k in 1..shifts {
        let shift = k as f64 * step;
        let candidate = fit(shift);
        if candidate.0 > best.0 * (1.0 + 1e-9) {
            best = candidate;
            best_shift = shift;
        }
    }
    let gain = best.1;
    let mut residual = Vec::with_capacity(reference.time_s.len());
    let (mut rr, mut ee) = (0.0, 0.0);
    for (&t, &r) in reference.time_s.iter().zip(reference.accel_m_s2) {
        if let Some(m) = sample(model.time_s, model.accel_m_s2, t + best_shift) {
            let d = r - gain * m;
            residual.push((t, d));
            rr += r * r;
            ee += d * d;
        }
    }
    let relative_rms = if rr > 0.0 { (ee / rr).sqrt() } else { f64::NAN };
    (
        Alignment {
            shift_s: best_shift,
            gain,
            relative_rms,
        },
        residual,
    )
}

struct DecayFigure<'a> {
    reference: DecayTrace<'a>,
    model: DecayTrace<'a>,
    alignment: Alignment,
    residual: &'a [(f64, f64)],
}

/// At most this many points per drawn line (min and max per bucket keep the envelope).
const MAX_DRAWN: usize = 4000;

fn thin(points: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    if points.len() <= MAX_DRAWN {
        return points;
    }
    let bucket = points.len().div_ceil(MAX_DRAWN / 2);
    let mut out = Vec::with_capacity(MAX_DRAWN + 2);
    for chunk in points.chunks(bucket) {
        let lo = chunk.iter().min_by(|a, b| a.1.total_cmp(&b.1));
        let hi = chunk.iter().max_by(|a, b| a.1.total_cmp(&b.1));
        if let (Some(&lo), Some(&hi)) = (lo, hi) {
            if lo.0 <= hi.0 {
                out.extend([lo, hi]);
            } else {
                out.extend([hi, lo]);
            }
        }
    }
    out
}

impl Figure for DecayFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        root.fill(&WHITE).map_err(e)?;
        let root = root
            .titled(
                "Free decay of the weight: reference, simulation and residual",
                (FONT, 26),
            )
            .map_err(e)?;
        let (top, bottom) = root.split_vertically((SIZE.1 as f64 * 0.6) as u32);
        let (r, m, a) = (&self.reference, &self.model, &self.alignment);
        let (t0, t1) = range_of(r.time_s.iter().copied());
        let model_points: Vec<(f64, f64)> = m
            .time_s
            .iter()
            .zip(m.accel_m_s2)
            .map(|(&t, &v)| (t - a.shift_s, a.gain * v))
            .filter(|p| (t0..=t1).contains(&p.0))
            .collect();
        let (y0, y1) = range_of(
            r.accel_m_s2
                .iter()
                .copied()
                .chain(model_points.iter().map(|p| p.1)),
        );
        let mut chart = ChartBuilder::on(&top)
            .margin(12)
            .margin_right(36)
            .x_label_area_size(45)
            .y_label_area_size(90)
            .build_cartesian_2d(t0..t1, y0..y1)
            .map_err(e)?;
        plot::axes(
            &mut chart.configure_mesh(),
            "time [s]",
            "acceleration [m/s^2]",
            TUNER_AXES,
        )
        .y_label_formatter(&short)
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(e)?;
        let grey = RGBColor(90, 90, 90);
        let reference: Vec<(f64, f64)> = r
            .time_s
            .iter()
            .zip(r.accel_m_s2)
            .map(|(&t, &v)| (t, v))
            .collect();
        chart
            .draw_series(LineSeries::new(thin(reference), grey.stroke_width(4)))
            .map_err(e)?
            .label(r.label)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], grey.stroke_width(4)));
        let shifted = if a.shift_s != 0.0 || (a.gain - 1.0).abs() > 1e-6 {
            format!(
                " (read at t + {} s, times {})",
                short(&a.shift_s),
                short(&a.gain)
            )
        } else {
            String::new()
        };
        chart
            .draw_series(LineSeries::new(thin(model_points), RED.stroke_width(1)))
            .map_err(e)?
            .label(format!("{}{shifted}", m.label))
            .legend(|(x, y)| PathElement::new([(x, y), (x + 24, y)], RED.stroke_width(2)));
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font((FONT, 16))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(e)?;

        let (z0, z1) = range_of(self.residual.iter().map(|p| p.1));
        let span = z0.abs().max(z1.abs()).max(1e-12);
        let mut lower = ChartBuilder::on(&bottom)
            .margin(12)
            .margin_right(36)
            .x_label_area_size(50)
            .y_label_area_size(90)
            .build_cartesian_2d(t0..t1, -span..span)
            .map_err(e)?;
        plot::axes(
            &mut lower.configure_mesh(),
            "time [s]",
            "residual [m/s^2]",
            TUNER_AXES,
        )
        .y_label_formatter(&short)
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(e)?;
        lower
            .draw_series(LineSeries::new(
                thin(self.residual.to_vec()),
                BLUE.stroke_width(1),
            ))
            .map_err(e)?
            .label(format!(
                "reference - simulation: RMS {:.2} % of the reference's RMS",
                100.0 * a.relative_rms
            ))
            .legend(|(x, y)| PathElement::new([(x, y), (x + 24, y)], BLUE.stroke_width(2)));
        lower
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font((FONT, 16))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(e)?;
        Ok(())
    }
}

/// Fig. 10 analogue: the reference record (measured, or the experiment's figures),
/// the simulation laid over it ([`align`]) in m/s^2, and the residual below.
pub fn decay_figure(
    reference: &DecayTrace<'_>,
    model: &DecayTrace<'_>,
    period_s: f64,
    path: &Path,
) -> Result<Alignment> {
    let (alignment, residual) = align(reference, model, period_s);
    render(
        path,
        &DecayFigure {
            reference: *reference,
            model: *model,
            alignment,
            residual: &residual,
        },
    )?;
    Ok(alignment)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decay::DecayMeasure;
    use crate::grid::{Axis, GridPoint, GridSpec};
    use crate::loops::Iteration;

    #[test]
    fn figures_are_written_and_bad_extensions_leave_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let report = LoopReport {
            parameter: "youngs_modulus_mpa".into(),
            quantity: "stiffness_n_mm".into(),
            target: 3.9275,
            tolerance: 1e-5,
            iterations: vec![
                Iteration {
                    iteration: 1,
                    parameter: 206000.0,
                    result: 4.2,
                    relative_error: 0.07,
                    deck: None,
                },
                Iteration {
                    iteration: 2,
                    parameter: 193000.0,
                    result: 3.9275,
                    relative_error: 0.0,
                    deck: None,
                },
            ],
            value: 193000.0,
            result: 3.9275,
            relative_error: 0.0,
        };
        loops_figure(&[&report, &report], &dir.path().join("fig7.png")).unwrap();
        let spec = GridSpec {
            name: "g".into(),
            alpha: Axis::parse("0:1:2").unwrap(),
            beta: Axis::parse("0:1:1").unwrap(),
        };
        let points = (0..3)
            .flat_map(|i| (0..2).map(move |j| (i, j)))
            .map(|(i, j)| GridPoint {
                i,
                j,
                alpha: i as f64,
                beta: j as f64,
                measure: (i + j > 0).then_some(DecayMeasure {
                    zeta_mean: 0.1 * i as f64 + j as f64,
                    zeta_fit: 0.0,
                    period_s: 0.23,
                    crests: 20,
                }),
                error: (i + j == 0).then(|| "x".to_string()),
            })
            .collect();
        let grid = GridResult {
            spec,
            points,
            computed: 6,
            resumed: 0,
            elapsed_s: 0.0,
        };
        let marks = HeatMapMarks {
            target_zeta: 0.5,
            paper: Some((1.0, 0.5)),
            valley: Some((0.0, 0.1, 1.0)),
        };
        heat_map(&grid, &marks, &dir.path().join("fig8.png")).unwrap();
        heat_map(&grid, &marks, &dir.path().join("fig8.svg")).unwrap();
        let valley = ValleyPlot {
            target_zeta: 0.5,
            plane: (0.0, 0.1, 1.0),
            points: &[(0.0, 0.5, 0.5), (2.0, 0.3, 0.5)],
            alpha_max: 5.0,
        };
        valley_figure(&valley, &dir.path().join("valley.png")).unwrap();
        assert!(heat_map(&grid, &marks, &dir.path().join("fig8.txt")).is_err());
        let mut names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|f| f.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, ["fig7.png", "fig8.png", "fig8.svg", "valley.png"]);
    }

    #[test]
    fn a_shifted_scaled_record_is_aligned_and_leaves_no_residual() {
        // Model: a decaying cosine sampled at 1 ms; reference: the same read 0.05 s later
        // at half the amplitude, on a 2 ms grid (a measured record cut after the impulse).
        let period = 0.23;
        let w = std::f64::consts::TAU / period;
        let wave = |t: f64| (-0.05 * t).exp() * (w * t).cos();
        let model_t: Vec<f64> = (0..6000).map(|k| k as f64 * 1e-3).collect();
        let model_a: Vec<f64> = model_t.iter().map(|&t| wave(t)).collect();
        let ref_t: Vec<f64> = (0..2000).map(|k| k as f64 * 2e-3).collect();
        let ref_a: Vec<f64> = ref_t.iter().map(|&t| 0.5 * wave(t + 0.05)).collect();
        let reference = DecayTrace {
            label: "measured",
            time_s: &ref_t,
            accel_m_s2: &ref_a,
        };
        let model = DecayTrace {
            label: "coil",
            time_s: &model_t,
            accel_m_s2: &model_a,
        };
        let (a, residual) = align(&reference, &model, period);
        assert!((a.shift_s - 0.05).abs() < 1e-9, "{a:?}");
        assert!((a.gain - 0.5).abs() < 1e-4, "{a:?}");
        // Linear interpolation of a 1 ms model: error ~ (w dt)^2 / 8 = 9e-5 relative.
        assert!(a.relative_rms < 3e-4, "{a:?}");
        assert_eq!(residual.len(), ref_t.len());
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("fig10.png");
        decay_figure(&reference, &model, period, &path).unwrap();
        assert!(path.is_file());
    }
}
