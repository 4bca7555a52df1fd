//! Figures of EN 50318 evaluations (PNG or SVG by the extension, the embedded font and the
//! temp-file-and-rename writing of [`coil_postproc::plot`]):
//!
//! - [`contact_force`]: the raw and the filtered contact force along the track (the raw
//!   trace drawn over the filtered one, both visible), the evaluation window shaded, the
//!   supports as dashed orange verticals (the grid is a faint grey), the window's mean and
//!   mean +- 3 std, the legend in headroom above the traces.
//! - [`speeds`]: the statistics against speed for a speed sweep.
//! - [`uplift`]: each support's displacement from its static position against the
//!   pantograph's position (supports in the window in colour, the others grey), each
//!   support's own position marked.
//! - [`spring_study`]: standard deviation, minimum and loss of contact per head-stage spring,
//!   one colour per speed; the line joins the `mid` damping values, the vertical bar spans
//!   the damping band's values (low to high) of the same spring.

use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::study;
pub use super::study::SpringStudyRow;
use super::{speed_label, Evaluation, Record, Settings};
use coil_postproc::error::Result;
use coil_postproc::plot::{
    axes, decimate, legend, padded_range, render, text, tick_physical, Draw, Figure, FONT, PALETTE,
    POST_AXES,
};

const SHADE: RGBColor = RGBColor(225, 225, 225);
const GREY: RGBColor = RGBColor(150, 150, 150);
/// The supports' colour: not the grid's grey.
const SUPPORT: RGBColor = RGBColor(230, 120, 20);
/// The grid's colour.
const GRID: RGBColor = RGBColor(238, 238, 238);

/// A dashed vertical (or any straight) line from `a` to `b` as short segments.
fn dashed(a: (f64, f64), b: (f64, f64), style: ShapeStyle) -> Vec<PathElement<(f64, f64)>> {
    const PIECES: usize = 24;
    (0..PIECES)
        .step_by(2)
        .map(|k| {
            let at = |s: f64| (a.0 + (b.0 - a.0) * s, a.1 + (b.1 - a.1) * s);
            let s0 = k as f64 / PIECES as f64;
            let s1 = (k + 1) as f64 / PIECES as f64;
            PathElement::new(vec![at(s0), at(s1)], style)
        })
        .collect()
}

/// The statistics against speed (a speed sweep): the mean, mean +- 3 std and the actual
/// extremes in one panel, the standard deviation and the loss of contact in another.
pub fn speeds(path: &Path, runs: &[super::Statistics]) -> Result<()> {
    render(path, &SpeedFigure { runs })
}

struct SpeedFigure<'a> {
    runs: &'a [super::Statistics],
}

type Pick = fn(&super::Statistics) -> f64;

impl Figure for SpeedFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        root.fill(&WHITE).map_err(text)?;
        let root = root
            .titled("Contact force statistics against speed", (FONT, 26))
            .map_err(text)?;
        let mut runs = self.runs.to_vec();
        runs.sort_by(|a, b| a.speed_km_h.total_cmp(&b.speed_km_h));
        let (x0, x1) = padded_range(runs.iter().map(|r| r.speed_km_h), 0.05);
        let panels: [(&str, Vec<(&str, Pick)>); 2] = [
            (
                "contact force [N]",
                vec![
                    ("mean", |s| s.mean_n),
                    ("mean + 3 std", |s| s.stat_max_n),
                    ("mean - 3 std", |s| s.stat_min_n),
                    ("actual max", |s| s.max_n),
                    ("actual min", |s| s.min_n),
                ],
            ),
            (
                "std [N], loss of contact [%]",
                vec![
                    ("std", |s| s.std_n),
                    ("loss of contact", |s| s.loss_percent),
                ],
            ),
        ];
        let areas = root.split_evenly((2, 1));
        for (area, (y_desc, lines)) in areas.iter().zip(panels) {
            let (y0, y1) = padded_range(
                runs.iter()
                    .flat_map(|r| lines.iter().map(move |(_, f)| f(r)))
                    .chain([0.0]),
                0.1,
            );
            let mut chart = ChartBuilder::on(area)
                .margin(10)
                .margin_right(36)
                .x_label_area_size(50)
                .y_label_area_size(90)
                .build_cartesian_2d(x0..x1, y0..(y1 + 0.3 * (y1 - y0)))
                .map_err(text)?;
            axes(
                &mut chart.configure_mesh(),
                "speed [km/h]",
                y_desc,
                POST_AXES,
            )
            .x_label_formatter(&tick_physical)
            .y_label_formatter(&tick_physical)
            .bold_line_style(GRID)
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(text)?;
            for (k, (name, f)) in lines.iter().enumerate() {
                let colour =
                    PALETTE[k % PALETTE.len()].mix(if k < PALETTE.len() { 1.0 } else { 0.5 });
                let points: Vec<(f64, f64)> = runs.iter().map(|r| (r.speed_km_h, f(r))).collect();
                chart
                    .draw_series(points.iter().map(|&p| Circle::new(p, 4, colour.filled())))
                    .map_err(text)?;
                chart
                    .draw_series(LineSeries::new(points, colour.stroke_width(2)))
                    .map_err(text)?
                    .label(*name)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
                    });
            }
            legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        }
        Ok(())
    }
}

/// The contact force along the track (raw and filtered), window shaded, supports marked.
pub fn contact_force(
    path: &Path,
    record: &Record<'_>,
    settings: &Settings,
    evaluation: &Evaluation,
) -> Result<()> {
    render(
        path,
        &RunFigure::new(Along::Force, record, settings, evaluation),
    )
}

/// Each support's uplift from its static position against the pantograph's position.
pub fn uplift(
    path: &Path,
    record: &Record<'_>,
    settings: &Settings,
    evaluation: &Evaluation,
) -> Result<()> {
    render(
        path,
        &RunFigure::new(Along::Uplift, record, settings, evaluation),
    )
}

/// Standard deviation, minimum and loss of contact per spring and speed (module doc).
pub fn spring_study(path: &Path, rows: &[SpringStudyRow]) -> Result<()> {
    render(path, &StudyFigure { rows })
}

/// What a figure of one run shows along the track.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Along {
    Force,
    Uplift,
}

struct RunFigure<'a> {
    what: Along,
    record: &'a Record<'a>,
    settings: &'a Settings,
    evaluation: &'a Evaluation,
}

impl<'a> RunFigure<'a> {
    fn new(
        what: Along,
        record: &'a Record<'a>,
        settings: &'a Settings,
        evaluation: &'a Evaluation,
    ) -> Self {
        RunFigure {
            what,
            record,
            settings,
            evaluation,
        }
    }
}

impl Figure for RunFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        match self.what {
            Along::Force => self.force(root),
            Along::Uplift => self.uplift(root),
        }
    }
}

struct StudyFigure<'a> {
    rows: &'a [SpringStudyRow],
}

/// The track's extent of an evaluation.
fn track_range(evaluation: &Evaluation) -> (f64, f64) {
    padded_range(evaluation.position_m.iter().copied(), 0.0)
}

/// A chart over the track's extent with its axes, the window shaded and the supports as
/// thin vertical lines.
fn track_chart<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    y_desc: &str,
    record: &Record<'_>,
    settings: &Settings,
) -> std::result::Result<Chart<'a, DB>, String> {
    let mut chart = ChartBuilder::on(root)
        .margin(12)
        .margin_right(36)
        .x_label_area_size(55)
        .y_label_area_size(90)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(text)?;
    axes(
        &mut chart.configure_mesh(),
        "pantograph position along the track [m]",
        y_desc,
        POST_AXES,
    )
    .x_label_formatter(&tick_physical)
    .y_label_formatter(&tick_physical)
    .bold_line_style(GRID)
    .light_line_style(WHITE.mix(0.0))
    .draw()
    .map_err(text)?;
    window_and_supports(&mut chart, record, settings, (y0, y1))?;
    Ok(chart)
}

/// A chart of two `f64` axes.
type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// The window as a shaded band and the supports as dashed orange vertical lines.
fn window_and_supports<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    record: &Record<'_>,
    settings: &Settings,
    (y0, y1): (f64, f64),
) -> Draw {
    let w = settings.window;
    chart
        .draw_series([Rectangle::new(
            [(w.start_m, y0), (w.end_m, y1)],
            SHADE.filled(),
        )])
        .map_err(text)?
        .label(format!("evaluation window {} to {} m", w.start_m, w.end_m))
        .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 24, y + 6)], SHADE.filled()));
    if !record.supports.is_empty() {
        chart
            .draw_series(record.supports.iter().flat_map(|s| {
                dashed(
                    (s.position_m, y0),
                    (s.position_m, y1),
                    SUPPORT.stroke_width(1),
                )
            }))
            .map_err(text)?
            .label("supports (steady arms)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], SUPPORT.stroke_width(2)));
    }
    Ok(())
}

impl RunFigure<'_> {
    fn force<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let (record, e) = (self.record, self.evaluation);
        let s = &e.statistics;
        root.fill(&WHITE).map_err(text)?;
        let root = root
            .titled(
                &format!(
                    "Contact force at {}: mean {:.1} N, std {:.1} N in the window",
                    speed_label(s.speed_km_h),
                    s.mean_n,
                    s.std_n
                ),
                (FONT, 26),
            )
            .map_err(text)?;
        let (x0, x1) = track_range(e);
        let (y0, y1) = padded_range(
            record.force_n.iter().chain(&e.filtered_n).copied().chain([
                0.0,
                s.stat_min_n,
                s.stat_max_n,
            ]),
            0.05,
        );
        // Headroom above the traces for the legend, so that it covers no peak.
        let y1 = y1 + 0.45 * (y1 - y0);
        let mut chart = track_chart(
            &root,
            (x0, x1),
            (y0, y1),
            "contact force [N]",
            record,
            self.settings,
        )?;
        // The filtered line first, the raw one thin and translucent over it: both show.
        let filtered = PALETTE[1];
        chart
            .draw_series(LineSeries::new(
                decimate(&e.position_m, &e.filtered_n),
                filtered.stroke_width(2),
            ))
            .map_err(text)?
            .label(format!(
                "low-pass {} Hz (zero-phase Butterworth, order {} per pass)",
                self.settings.cutoff_hz, self.settings.order
            ))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], filtered.stroke_width(3))
            });
        let raw = PALETTE[0].mix(0.55);
        chart
            .draw_series(LineSeries::new(
                decimate(&e.position_m, record.force_n),
                raw.stroke_width(1),
            ))
            .map_err(text)?
            .label("raw")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], raw.stroke_width(3)));
        let w = self.settings.window;
        chart
            .draw_series(LineSeries::new(
                [(w.start_m, s.mean_n), (w.end_m, s.mean_n)],
                BLACK.stroke_width(2),
            ))
            .map_err(text)?
            .label(format!("mean in the window, {:.1} N", s.mean_n))
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], BLACK.stroke_width(2)));
        chart
            .draw_series(
                [s.stat_max_n, s.stat_min_n]
                    .into_iter()
                    .flat_map(|f| dashed((w.start_m, f), (w.end_m, f), BLACK.stroke_width(2))),
            )
            .map_err(text)?
            .label(format!(
                "mean +- 3 std: {:.1} / {:.1} N",
                s.stat_max_n, s.stat_min_n
            ))
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 10, y)], BLACK.stroke_width(2)));
        legend(&mut chart, SeriesLabelPosition::UpperRight)
    }

    fn uplift<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let (record, e) = (self.record, self.evaluation);
        root.fill(&WHITE).map_err(text)?;
        let root = root
            .titled(
                &format!(
                    "Uplift at the supports at {}: largest in the window {:.1} mm",
                    speed_label(e.statistics.speed_km_h),
                    e.statistics.uplift_support_mm
                ),
                (FONT, 26),
            )
            .map_err(text)?;
        let uplifts: Vec<Vec<f64>> = record
            .supports
            .iter()
            .map(|s| s.displacement_mm.iter().map(|d| d - s.static_mm).collect())
            .collect();
        let (x0, x1) = track_range(e);
        let (y0, y1) = padded_range(uplifts.iter().flatten().copied().chain([0.0]), 0.05);
        let y1 = y1 + 0.45 * (y1 - y0);
        let mut chart = track_chart(
            &root,
            (x0, x1),
            (y0, y1),
            "support displacement from its static position, up [mm]",
            record,
            self.settings,
        )?;
        let mut coloured = 0;
        for ((support, values), uplift) in record
            .supports
            .iter()
            .zip(&uplifts)
            .zip(&e.support_uplift_mm)
        {
            let series = decimate(&e.position_m, values);
            match uplift {
                Some(peak) => {
                    let colour = PALETTE[coloured % PALETTE.len()];
                    coloured += 1;
                    chart
                        .draw_series(LineSeries::new(series, colour.stroke_width(2)))
                        .map_err(text)?
                        .label(format!(
                            "support at {} m: {:.1} mm",
                            support.position_m, peak
                        ))
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
                        });
                }
                None => {
                    chart
                        .draw_series(LineSeries::new(series, GREY.mix(0.6).stroke_width(1)))
                        .map_err(text)?;
                }
            }
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// The loss-of-contact panel's index in [`study::COLUMNS`].
const LOSS_PANEL: usize = 2;

/// The loss panel's axis (%): 0 and the largest loss, padded by a tenth; 0 to 1 % when no
/// run loses contact (a zero-height axis would label every tick "0").
fn loss_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let high = values.filter(|v| v.is_finite()).fold(0.0_f64, f64::max);
    if high > 0.0 {
        padded_range([0.0, high].into_iter(), 0.1)
    } else {
        (0.0, 1.0)
    }
}

impl Figure for StudyFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let rows = self.rows;
        root.fill(&WHITE).map_err(text)?;
        let root = root
            .titled(
                "Head-stage springs: contact force scatter, minimum and loss of contact",
                (FONT, 26),
            )
            .map_err(text)?;
        let springs = study::springs(rows);
        let speeds = study::speeds(rows);
        let panels = study::COLUMNS;
        let areas = root.split_evenly((panels.len(), 1));
        let n = springs.len();
        for (panel, (area, (y_desc, _, value))) in areas.iter().zip(panels).enumerate() {
            let values = rows.iter().map(|r| value(&r.statistics));
            let (y0, y1) = if panel == LOSS_PANEL {
                loss_range(values)
            } else {
                padded_range(values, 0.1)
            };
            let mut chart = ChartBuilder::on(area)
                .margin(10)
                .margin_right(36)
                .x_label_area_size(40)
                .y_label_area_size(90)
                .build_cartesian_2d(-0.5..(n as f64 - 0.5), y0..y1)
                .map_err(text)?;
            axes(&mut chart.configure_mesh(), "", y_desc, POST_AXES)
                .x_labels(n.max(1))
                .x_label_formatter(&|x| {
                    let i = x.round();
                    if (x - i).abs() < 1e-6 && i >= 0.0 {
                        springs.get(i as usize).cloned().unwrap_or_default()
                    } else {
                        String::new()
                    }
                })
                .y_label_formatter(&tick_physical)
                .light_line_style(WHITE.mix(0.0))
                .draw()
                .map_err(text)?;
            for (k, speed) in speeds.iter().enumerate() {
                let colour = PALETTE[k % PALETTE.len()];
                // Side by side so that the bars of two speeds do not hide each other.
                let offset = (k as f64 - 0.5 * (speeds.len() as f64 - 1.0)) * 0.08;
                let mut mids = Vec::new();
                let mut bars = Vec::new();
                for (i, spring) in springs.iter().enumerate() {
                    let Some(b) = study::band(rows, spring, *speed, value) else {
                        continue;
                    };
                    let x = i as f64 + offset;
                    mids.push((x, b.mid));
                    bars.push(((x, b.low), (x, b.high)));
                }
                chart
                    .draw_series(
                        bars.iter()
                            .map(|&(a, b)| PathElement::new(vec![a, b], colour.stroke_width(3))),
                    )
                    .map_err(text)?;
                chart
                    .draw_series(mids.iter().map(|&p| Circle::new(p, 5, colour.filled())))
                    .map_err(text)?;
                chart
                    .draw_series(LineSeries::new(mids, colour.stroke_width(1)))
                    .map_err(text)?
                    .label(speed_label(*speed))
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
                    });
            }
            if panel == 0 {
                legend(&mut chart, SeriesLabelPosition::UpperRight)?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::{evaluate, Statistics, Support, Track, Window};
    use super::*;

    #[test]
    fn the_loss_axis_is_0_to_1_percent_without_loss() {
        assert_eq!(loss_range([0.0, 0.0, 0.0].into_iter()), (0.0, 1.0));
        assert_eq!(loss_range(std::iter::empty()), (0.0, 1.0));
        let (low, high) = loss_range([0.0, 2.0].into_iter());
        assert!(
            low < 0.0 && low > -0.25 && high > 2.0 && high < 2.25,
            "{low} {high}"
        );
        assert!(study::COLUMNS[LOSS_PANEL].1 == "loss");
    }

    /// The three figures are drawn (PNG and SVG) from a small synthetic run.
    #[test]
    fn figures_are_written() {
        let time: Vec<f64> = (0..4000).map(|i| i as f64 * 1e-3).collect();
        let force: Vec<f64> = time
            .iter()
            .map(|t| (100.0 + 30.0 * (2.0 * std::f64::consts::PI * 3.0 * t).sin()).max(0.0))
            .collect();
        let bumps: Vec<Vec<f64>> = [20.0, 40.0, 60.0]
            .iter()
            .map(|x| {
                time.iter()
                    .map(|t| 50.0 * (-((60.0 * t - x) / 5.0).powi(2)).exp())
                    .collect()
            })
            .collect();
        let supports: Vec<Support<'_>> = [20.0, 40.0, 60.0]
            .iter()
            .zip(&bumps)
            .map(|(x, d)| Support {
                position_m: *x,
                static_mm: 0.0,
                displacement_mm: d,
            })
            .collect();
        let record = Record {
            time_s: &time,
            force_n: &force,
            track: Track::Uniform { start_m: 0.0 },
            speed_m_s: 60.0,
            supports: &supports,
        };
        let settings = Settings::new(Window {
            start_m: 30.0,
            end_m: 200.0,
        });
        let e = evaluate(&record, &settings).unwrap();
        let folder = tempfile::tempdir().unwrap();
        for name in ["force.png", "force.svg"] {
            contact_force(&folder.path().join(name), &record, &settings, &e).unwrap();
        }
        uplift(&folder.path().join("uplift.png"), &record, &settings, &e).unwrap();
        let rows: Vec<SpringStudyRow> = ["160ECT", "#1", "#2"]
            .iter()
            .enumerate()
            .flat_map(|(i, spring)| {
                [250.0, 300.0].into_iter().flat_map(move |speed| {
                    ["low", "mid", "high"]
                        .iter()
                        .enumerate()
                        .map(move |(j, zeta)| SpringStudyRow {
                            spring: spring.to_string(),
                            zeta: zeta.to_string(),
                            statistics: Statistics {
                                speed_km_h: speed,
                                std_n: 30.0 + i as f64 + j as f64 * 0.5 + speed / 100.0,
                                min_n: 50.0 - i as f64,
                                loss_percent: i as f64 * 0.1,
                                ..e.statistics
                            },
                        })
                })
            })
            .collect();
        spring_study(&folder.path().join("springs.png"), &rows).unwrap();
        for name in ["force.png", "force.svg", "uplift.png", "springs.png"] {
            let size = std::fs::metadata(folder.path().join(name)).unwrap().len();
            assert!(size > 10_000, "{name}: {size} bytes");
        }
    }
}
