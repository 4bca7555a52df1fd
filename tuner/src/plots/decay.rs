//! Fig. 10's analogue: the reference decay (a measured record, or the experiment's T and
//! zeta), the simulation laid over it by a time shift and a gain ([`align`]) and the
//! residual below, in m/s^2.

use super::style::{e, range_of, render, short, BLUE, RED, TUNER_AXES};
use crate::error::Result;
use coil_postproc::plot::{self, Draw, Figure, FONT, SIZE};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

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
