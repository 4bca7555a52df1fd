//! PNG and SVG plots: normalised time histories (the paper's Fig. 10), amplitude spectra,
//! and envelope/backbone/damping curves.
//!
//! The format follows the output file's extension (`.png` or `.svg`). Text uses DejaVu Sans,
//! embedded in the binary (`assets/DejaVuSans.ttf`, license in `assets/LICENSE-DejaVu.txt`)
//! and registered with plotters' `ab_glyph` font table, so plots look the same on any machine
//! without system fonts. Files are drawn into a temporary file and renamed (see
//! [`crate::output`]).
//!
//! Time histories are normalised to (-1, 1) by their largest magnitude, as in the paper's
//! Fig. 10 ("The acceleration courses were normalized to the range (-1, 1)"), or drawn in
//! their physical unit ([`Scale::Physical`], `coil-post plot --physical`). Long records are
//! reduced to the minimum and maximum of each of [`MAX_POINTS`]`/2` buckets before drawing:
//! the picture is the same and an SVG stays small.

use std::path::Path;
use std::sync::OnceLock;

use plotters::chart::MeshStyle;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle, RGBColor};

use crate::envelope::EnvelopeReport;
use crate::error::{PostError, Result};
use crate::output::produce_atomic;
use crate::spectrum::{SpectralPeak, Spectrum};

/// The embedded font.
const FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Family name the embedded font is registered under (use it in text styles).
pub const FONT: &str = "sans-serif";

/// Most points drawn per line.
pub const MAX_POINTS: usize = 4000;

/// Picture size in pixels (SVG units for SVG).
pub const SIZE: (u32, u32) = (1400, 900);

/// Text sizes of a chart's axes, in points: the axis names and the tick labels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AxisText {
    /// The axis names (`x_desc`, `y_desc`).
    pub names: u32,
    /// The tick labels.
    pub ticks: u32,
}

/// The axes of `coil-post`'s own figures.
pub const POST_AXES: AxisText = AxisText {
    names: 20,
    ticks: 17,
};

/// The axis styling every coil figure shares: both axes named and their text in the
/// embedded [`FONT`] at `text`'s sizes. Returns the mesh for the figure's own tick
/// formatters, label counts and grid lines; `.draw()` it.
pub fn axes<'m, 'a, 'b, X, Y, DB>(
    mesh: &'m mut MeshStyle<'a, 'b, X, Y, DB>,
    x_desc: &str,
    y_desc: &str,
    text: AxisText,
) -> &'m mut MeshStyle<'a, 'b, X, Y, DB>
where
    X: Ranged,
    Y: Ranged,
    DB: DrawingBackend,
{
    mesh.x_desc(x_desc)
        .y_desc(y_desc)
        .axis_desc_style((FONT, text.names))
        .label_style((FONT, text.ticks))
}

/// The figures' line colours, in order.
pub const PALETTE: [RGBColor; 4] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
];

/// One time history to draw.
#[derive(Debug, Clone, Copy)]
pub struct Trace<'a> {
    /// Legend text, e.g. `decay.csv: accel_m_s2`.
    pub label: &'a str,
    /// Unit of the values, e.g. `m/s^2` (see [`unit_of`]).
    pub unit: &'a str,
    /// Time, s.
    pub time_s: &'a [f64],
    /// The values.
    pub values: &'a [f64],
}

/// One spectrum and its listed peaks.
#[derive(Debug, Clone, Copy)]
pub struct SpectrumTrace<'a> {
    /// Label in legends and messages.
    pub label: &'a str,
    /// The spectrum.
    pub spectrum: &'a Spectrum,
    /// Its peaks.
    pub peaks: &'a [SpectralPeak],
}

/// One envelope analysis.
#[derive(Debug, Clone, Copy)]
pub struct EnvelopeTrace<'a> {
    /// Label in legends and messages.
    pub label: &'a str,
    /// Unit of the signal, for the amplitude axis (e.g. `m/s^2`).
    pub unit: &'a str,
    /// The report.
    pub report: &'a EnvelopeReport,
}

/// Unit of a column from its name's suffix (`accel_m_s2` -> `m/s^2`), as coil names them.
pub fn unit_of(column: &str) -> &'static str {
    const SUFFIXES: [(&str, &str); 9] = [
        ("_m_s2", "m/s^2"),
        ("_mm_s2", "mm/s^2"),
        ("_m_s", "m/s"),
        ("_mm_s", "mm/s"),
        ("_rad_s", "rad/s"),
        ("_mm", "mm"),
        ("_m", "m"),
        ("_rad", "rad"),
        ("_n", "N"),
    ];
    SUFFIXES
        .iter()
        .find(|(suffix, _)| column.ends_with(suffix))
        .map_or("signal unit", |(_, unit)| unit)
}

/// How a time history's values are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    /// Divided by the trace's largest magnitude, as the paper's Fig. 10.
    Normalised,
    /// In the unit of the column.
    Physical,
}

/// Normalised time histories: one panel per trace, or all in one panel when `overlay`.
pub fn time_histories(traces: &[Trace<'_>], overlay: bool, path: &Path) -> Result<()> {
    time_histories_scaled(traces, overlay, Scale::Normalised, path)
}

/// [`time_histories`], normalised or in physical units.
pub fn time_histories_scaled(
    traces: &[Trace<'_>],
    overlay: bool,
    scale: Scale,
    path: &Path,
) -> Result<()> {
    render(
        path,
        &TimeFigure {
            traces,
            overlay,
            scale,
        },
    )
}

/// Amplitude spectra (normalised to their largest peak, log scale) up to `max_frequency_hz`.
pub fn spectra(traces: &[SpectrumTrace<'_>], max_frequency_hz: f64, path: &Path) -> Result<()> {
    render(
        path,
        &SpectrumFigure {
            traces,
            max_frequency_hz,
        },
    )
}

/// Signal and envelope over time, the backbone and the damping curve.
pub fn envelopes(traces: &[EnvelopeTrace<'_>], path: &Path) -> Result<()> {
    render(path, &EnvelopeFigure { traces })
}

struct TimeFigure<'a> {
    traces: &'a [Trace<'a>],
    overlay: bool,
    scale: Scale,
}

struct SpectrumFigure<'a> {
    traces: &'a [SpectrumTrace<'a>],
    max_frequency_hz: f64,
}

struct EnvelopeFigure<'a> {
    traces: &'a [EnvelopeTrace<'a>],
}

/// What drawing a [`Figure`] returns: plotters errors as text.
pub type Draw = std::result::Result<(), String>;

/// A plotting error as text (the [`Draw`] error).
pub fn text<E: std::fmt::Display>(error: E) -> String {
    error.to_string()
}

fn ensure_font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok());
    if ok {
        Ok(())
    } else {
        Err(PostError::Plot {
            path: "assets/DejaVuSans.ttf".into(),
            message: "the embedded font cannot be loaded".to_string(),
        })
    }
}

/// A picture that can be drawn on any plotters backend; [`render`] writes it as PNG or
/// SVG. Other crates (the tuner's figures) implement it to share the font and output.
pub trait Figure {
    /// Draws the figure into `root`.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw;
}

/// Picks the backend from the extension (`.png`, `.svg`) and draws `figure` at [`SIZE`]
/// through a temporary file, with the embedded font registered.
pub fn render<F: Figure>(path: &Path, figure: &F) -> Result<()> {
    ensure_font()?;
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let plot_error = |message: String| PostError::Plot {
        path: path.to_path_buf(),
        message,
    };
    match extension.as_deref() {
        Some("png") => produce_atomic(path, |temporary| {
            let root = BitMapBackend::new(temporary, SIZE).into_drawing_area();
            figure.draw(&root).map_err(plot_error)?;
            root.present().map_err(|e| plot_error(e.to_string()))
        }),
        Some("svg") => produce_atomic(path, |temporary| {
            let root = SVGBackend::new(temporary, SIZE).into_drawing_area();
            figure.draw(&root).map_err(plot_error)?;
            root.present().map_err(|e| plot_error(e.to_string()))
        }),
        _ => Err(PostError::InvalidOption(format!(
            "plot file {}: expected a .png or .svg extension",
            path.display()
        ))),
    }
}

/// Min/max decimation to about [`MAX_POINTS`] points, keeping the visual envelope.
pub fn decimate(time_s: &[f64], values: &[f64]) -> Vec<(f64, f64)> {
    let n = time_s.len().min(values.len());
    if n <= MAX_POINTS {
        return time_s.iter().copied().zip(values.iter().copied()).collect();
    }
    let buckets = MAX_POINTS / 2;
    let mut points = Vec::with_capacity(MAX_POINTS);
    for b in 0..buckets {
        let (start, end) = (
            b * n / buckets,
            ((b + 1) * n / buckets).max(b * n / buckets + 1),
        );
        let slice = &values[start..end.min(n)];
        let (mut low, mut high) = (start, start);
        for (k, v) in slice.iter().enumerate() {
            if *v < values[low] {
                low = start + k;
            }
            if *v > values[high] {
                high = start + k;
            }
        }
        let (first, second) = if low < high { (low, high) } else { (high, low) };
        points.push((time_s[first], values[first]));
        if second != first {
            points.push((time_s[second], values[second]));
        }
    }
    points
}

/// Largest value of each of about one bucket per pixel column: the upper envelope of a
/// spectrum, which is what a log-scale plot of it shows (more points than pixels only draw
/// near-vertical segments over each other).
fn decimate_max(x: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    let n = x.len().min(y.len());
    let per_bucket = n.div_ceil(SIZE.0 as usize).max(1);
    (0..n)
        .step_by(per_bucket)
        .map(|start| {
            let end = (start + per_bucket).min(n);
            let best = (start..end).fold(start, |best, k| if y[k] > y[best] { k } else { best });
            (x[best], y[best])
        })
        .collect()
}

/// A finite, non-empty range that contains `values` with a margin.
pub fn padded_range(values: impl Iterator<Item = f64>, margin: f64) -> (f64, f64) {
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        low = low.min(v);
        high = high.max(v);
    }
    if !(low.is_finite() && high.is_finite()) {
        return (0.0, 1.0);
    }
    let span = high - low;
    let pad = if span > 0.0 {
        margin * span
    } else {
        0.5 * high.abs().max(1e-12)
    };
    (low - pad, high + pad)
}

/// A tick label with three significant digits (scientific below 0.01), no "-0".
pub fn tick_physical(value: &f64) -> String {
    let v = *value;
    if v.abs() < 1e-12 {
        "0".to_string()
    } else if v.abs() < 0.01 || v.abs() >= 1e5 {
        format!("{v:.1e}")
    } else {
        let digits = (2 - v.abs().log10().floor() as i32).max(0) as usize;
        let text = format!("{v:.digits$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    }
}

/// A tick label with one decimal and no "-0.0".
fn tick(value: &f64) -> String {
    if value.abs() < 1e-9 {
        "0".to_string()
    } else {
        format!("{value:.1}")
    }
}

fn largest_magnitude(values: &[f64]) -> f64 {
    let m = values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if m > 0.0 {
        m
    } else {
        1.0
    }
}

/// Draws the series' legend of `chart` at `position`.
pub fn legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Draw {
    chart
        .configure_series_labels()
        .position(position)
        .label_font((FONT, 18))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(text)
}

impl Figure for TimeFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let traces = self.traces;
        root.fill(&WHITE).map_err(text)?;
        let physical = self.scale == Scale::Physical;
        let root = root
            .titled(
                if physical {
                    "Time history"
                } else {
                    "Time history, normalised to (-1, 1) by its largest magnitude"
                },
                (FONT, 26),
            )
            .map_err(text)?;
        let (t0, t1) = padded_range(
            traces
                .iter()
                .flat_map(|t| [t.time_s.first(), t.time_s.last()])
                .flatten()
                .copied(),
            0.0,
        );
        // Which traces each panel holds: all in one, or one each.
        let groups: Vec<Vec<usize>> = if self.overlay {
            vec![(0..traces.len()).collect()]
        } else {
            (0..traces.len()).map(|index| vec![index]).collect()
        };
        let panels = root.split_evenly((groups.len().max(1), 1));
        for (area, group) in panels.iter().zip(&groups) {
            let (y0, y1) = if physical {
                padded_range(
                    group.iter().flat_map(|&i| traces[i].values.iter().copied()),
                    0.05,
                )
            } else {
                (-1.1, 1.1)
            };
            let y_desc = if physical {
                let units: Vec<&str> = group.iter().map(|&i| traces[i].unit).collect();
                format!("{} [{}]", quantity_of(units[0]), units[0])
            } else {
                "x / max|x| [-]".to_string()
            };
            let mut chart = ChartBuilder::on(area)
                .margin(12)
                .margin_right(36)
                .x_label_area_size(55)
                .y_label_area_size(90)
                .build_cartesian_2d(t0..t1, y0..y1)
                .map_err(text)?;
            axes(&mut chart.configure_mesh(), "time [s]", &y_desc, POST_AXES)
                .y_label_formatter(if physical { &tick_physical } else { &tick })
                .light_line_style(WHITE.mix(0.0))
                .draw()
                .map_err(text)?;
            for &index in group {
                let trace = &traces[index];
                let scale = if physical {
                    1.0
                } else {
                    largest_magnitude(trace.values)
                };
                let scaled: Vec<f64> = trace.values.iter().map(|v| v / scale).collect();
                let color = PALETTE[index % PALETTE.len()];
                let label = if physical {
                    trace.label.to_string()
                } else {
                    format!(
                        "{} (max |x| = {} {})",
                        trace.label,
                        tick_physical(&scale),
                        trace.unit
                    )
                };
                chart
                    .draw_series(LineSeries::new(
                        decimate(trace.time_s, &scaled),
                        color.stroke_width(1),
                    ))
                    .map_err(text)?
                    .label(label)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(3))
                    });
            }
            legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        }
        Ok(())
    }
}

/// The quantity a unit measures, for an axis label.
fn quantity_of(unit: &str) -> &'static str {
    match unit {
        "m/s^2" | "mm/s^2" | "rad/s^2" => "acceleration",
        "m/s" | "mm/s" | "rad/s" => "velocity",
        "m" | "mm" | "rad" => "displacement",
        "N" => "force",
        _ => "value",
    }
}

impl Figure for SpectrumFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let (traces, max_frequency_hz) = (self.traces, self.max_frequency_hz);
        root.fill(&WHITE).map_err(text)?;
        let root = root
            .titled(
                "Amplitude spectrum (Hann window), normalised to its largest peak",
                (FONT, 26),
            )
            .map_err(text)?;
        let floor = 1e-5;
        let mut chart = ChartBuilder::on(&root)
            .margin(12)
            .margin_right(36)
            .x_label_area_size(55)
            .y_label_area_size(90)
            .build_cartesian_2d(0.0..max_frequency_hz, (floor..2.0).log_scale())
            .map_err(text)?;
        axes(
            &mut chart.configure_mesh(),
            "frequency [Hz]",
            "amplitude / largest peak [-]",
            POST_AXES,
        )
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(text)?;
        for (index, trace) in traces.iter().enumerate() {
            let color = PALETTE[index % PALETTE.len()];
            let largest = trace
                .peaks
                .iter()
                .map(|p| p.amplitude)
                .fold(0.0, f64::max)
                .max(f64::MIN_POSITIVE);
            let (frequency, amplitude): (Vec<f64>, Vec<f64>) = trace
                .spectrum
                .frequency_hz
                .iter()
                .zip(&trace.spectrum.amplitude)
                .filter(|(f, _)| **f <= max_frequency_hz)
                // Just above the axis floor, so that clamped values stay inside the chart.
                .map(|(f, a)| (*f, (a / largest).max(1.01 * floor)))
                .unzip();
            let listed: Vec<String> = trace
                .peaks
                .iter()
                .take(3)
                .map(|p| format!("{:.4}", p.frequency_hz))
                .collect();
            chart
                .draw_series(LineSeries::new(
                    decimate_max(&frequency, &amplitude),
                    color.stroke_width(2),
                ))
                .map_err(text)?
                .label(format!(
                    "{}; peaks at {} Hz",
                    trace.label,
                    listed.join(", ")
                ))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(3))
                });
            let shown: Vec<&SpectralPeak> = trace
                .peaks
                .iter()
                .filter(|p| p.frequency_hz <= max_frequency_hz)
                .collect();
            chart
                .draw_series(shown.iter().map(|p| {
                    Circle::new((p.frequency_hz, p.amplitude / largest), 5, color.filled())
                }))
                .map_err(text)?;
            if traces.len() > 1 {
                // Labels of several spectra would overprint each other; the legend lists them.
                continue;
            }
            chart
                .draw_series(shown.iter().map(|p| {
                    Text::new(
                        format!("{:.4} Hz", p.frequency_hz),
                        (p.frequency_hz, (p.amplitude / largest * 1.6).min(1.9)),
                        (FONT, 17).into_font().color(&color),
                    )
                }))
                .map_err(text)?;
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

impl Figure for EnvelopeFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Draw {
        let traces = self.traces;
        root.fill(&WHITE).map_err(text)?;
        let root = root
            .titled("Hilbert envelope, backbone and damping curves", (FONT, 26))
            .map_err(text)?;
        let (upper, lower) = root.split_vertically(root.dim_in_pixel().1 / 2);
        let (left, right) = lower.split_horizontally(lower.dim_in_pixel().0 / 2);

        let (t0, t1) = padded_range(
            traces
                .iter()
                .flat_map(|t| [t.report.time_s.first(), t.report.time_s.last()])
                .flatten()
                .copied(),
            0.0,
        );
        let mut chart = ChartBuilder::on(&upper)
            .margin(12)
            .margin_right(36)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(t0..t1, -1.1..1.1)
            .map_err(text)?;
        axes(
            &mut chart.configure_mesh(),
            "time [s]",
            "x / max|z| [-]",
            POST_AXES,
        )
        .y_label_formatter(&tick)
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(text)?;
        for (index, trace) in traces.iter().enumerate() {
            let color = PALETTE[index % PALETTE.len()];
            let report = trace.report;
            let scale = largest_magnitude(&report.envelope);
            let signal: Vec<f64> = report.signal.iter().map(|v| v / scale).collect();
            // The envelope is drawn where it is used: the trimmed ends ring (see envelope.rs).
            let used =
                report.trim_samples..report.envelope.len().saturating_sub(report.trim_samples);
            let envelope: Vec<f64> = report.envelope[used.clone()]
                .iter()
                .map(|v| v / scale)
                .collect();
            chart
                .draw_series(LineSeries::new(
                    decimate(&report.time_s, &signal),
                    color.mix(0.35).stroke_width(1),
                ))
                .map_err(text)?;
            chart
                .draw_series(LineSeries::new(
                    decimate(&report.time_s[used], &envelope),
                    color.stroke_width(3),
                ))
                .map_err(text)?
                .label(format!("{}: envelope |z|", trace.label))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(3))
                });
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)?;

        let unit = traces.first().map_or("signal unit", |t| t.unit);
        let amplitude_range = padded_range(
            traces
                .iter()
                .flat_map(|t| t.report.points.iter().map(|p| p.amplitude)),
            0.05,
        );
        curve_panel(
            &left,
            traces,
            amplitude_range,
            &format!("amplitude [{unit}]"),
            "damped frequency [Hz]",
            |p| p.frequency_hz,
        )?;
        curve_panel(
            &right,
            traces,
            amplitude_range,
            &format!("amplitude [{unit}]"),
            "damping ratio zeta [-]",
            |p| p.zeta,
        )
    }
}

fn curve_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    traces: &[EnvelopeTrace<'_>],
    (a0, a1): (f64, f64),
    x_desc: &str,
    y_desc: &str,
    value: fn(&crate::envelope::EnvelopePoint) -> f64,
) -> Draw {
    let (y0, y1) = padded_range(
        traces
            .iter()
            .flat_map(|t| t.report.points.iter().map(value)),
        0.1,
    );
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .margin_right(36)
        .x_label_area_size(50)
        .y_label_area_size(100)
        .build_cartesian_2d(a0..a1, y0..y1)
        .map_err(text)?;
    axes(
        &mut chart.configure_mesh(),
        x_desc,
        y_desc,
        AxisText {
            names: 20,
            ticks: 16,
        },
    )
    .x_labels(6)
    .y_labels(6)
    .y_label_formatter(&|v| format!("{v:.5}"))
    .x_label_formatter(&|v| format!("{v:.3}"))
    .draw()
    .map_err(text)?;
    for (index, trace) in traces.iter().enumerate() {
        let color = PALETTE[index % PALETTE.len()];
        let points: Vec<(f64, f64)> = trace
            .report
            .points
            .iter()
            .map(|p| (p.amplitude, value(p)))
            .collect();
        // No legend here: the colours are those of the upper panel's legend.
        chart
            .draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))
            .map_err(text)?;
        chart
            .draw_series(points.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(text)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_follow_column_suffixes() {
        assert_eq!(unit_of("node12_uz_accel_m_s2"), "m/s^2");
        assert_eq!(unit_of("accel_m_s2"), "m/s^2");
        assert_eq!(unit_of("node3_uz_disp_mm"), "mm");
        assert_eq!(unit_of("force_n"), "N");
        assert_eq!(unit_of("whatever"), "signal unit");
    }

    #[test]
    fn decimation_keeps_extremes() {
        let time: Vec<f64> = (0..100_000).map(|i| i as f64).collect();
        let values: Vec<f64> = time.iter().map(|t| (t * 0.01).sin()).collect();
        let points = decimate(&time, &values);
        assert!(points.len() <= MAX_POINTS);
        let high = points.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        assert!((high - 1.0).abs() < 1e-6);
    }

    #[test]
    fn unknown_extension_is_an_error_and_writes_nothing() {
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("plot.jpg");
        let time = [0.0, 1.0, 2.0];
        let values = [0.0, 1.0, 0.0];
        let trace = Trace {
            label: "x",
            unit: "m",
            time_s: &time,
            values: &values,
        };
        assert!(time_histories(&[trace], false, &path).is_err());
        assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 0);
    }
}
