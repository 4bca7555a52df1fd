//! What each `coil-post` command reports, as a library: the JSON value and the terminal
//! table of a decrement, a spectrum, an envelope, a signature or a static fit, and the
//! plots. The binary only parses its arguments, reads the records, calls these and prints.
//!
//! A report's JSON opens with the record's file, column, sample count and step; a
//! non-finite number anywhere in it is an error ([`PostError::NonFiniteResult`]): the input
//! is out of the analysis' range.

use std::path::Path;

use serde_json::{json, Value};

use crate::decrement::{self, DecrementOptions, DecrementReport};
use crate::envelope::{self, EnvelopeOptions, EnvelopeReport};
use crate::error::{PostError, Result};
use crate::offset::{remove_offset, Detrend};
use crate::peaks::Polarity;
use crate::signal::Signal;
use crate::signature::{self, CycleOptions, Estimate};
use crate::spectrum::{self, SpectralPeak, Spectrum, SpectrumOptions};
use crate::static_curve::{self, StaticFit};
use crate::{output, plot};

/// A command's result: its JSON value and its table.
#[derive(Debug, Clone)]
pub struct Report {
    /// The JSON report.
    pub value: Value,
    /// The table printed on a terminal.
    pub table: String,
}

impl Report {
    /// Writes the JSON to `out` when given (temporary file and rename); returns what to
    /// print: the JSON when `json`, else the table unless the JSON went to a file.
    pub fn emit(&self, json: bool, out: Option<&Path>) -> Result<Option<String>> {
        let text = serde_json::to_string_pretty(&self.value)
            .map_err(|e| PostError::InvalidOption(format!("cannot serialise the report: {e}")))?;
        if let Some(path) = out {
            output::write_atomic(path, format!("{text}\n").as_bytes())?;
        }
        Ok(if json {
            Some(format!("{text}\n"))
        } else if out.is_none() {
            Some(self.table.clone())
        } else {
            None
        })
    }
}

/// `coil-post decrement`: the crests' decrement (and the troughs' when `troughs`).
pub fn decrement(signal: &Signal, options: &DecrementOptions, troughs: bool) -> Result<Report> {
    let analyze = |polarity| {
        let options = DecrementOptions {
            polarity,
            ..*options
        };
        decrement::analyze(signal, &options).map_err(|error| signal.locate(error))
    };
    let crests = analyze(Polarity::Crests)?;
    let troughs = if troughs {
        Some(analyze(Polarity::Troughs)?)
    } else {
        None
    };
    let mut value = merge(header(signal), to_value(&crests)?);
    if let (Some(object), Some(troughs)) = (value.as_object_mut(), &troughs) {
        object.insert("troughs".to_string(), to_value(troughs)?);
    }
    let mut table = decrement_table(signal, &crests);
    if let Some(troughs) = &troughs {
        table.push_str("\ntroughs:\n");
        table.push_str(&decrement_table(signal, troughs));
    }
    Ok(Report { value, table })
}

/// `coil-post spectrum`: the spectrum's figures and up to `count` peaks above `threshold`
/// times the largest.
pub fn spectrum(
    signal: &Signal,
    options: &SpectrumOptions,
    count: usize,
    threshold: f64,
) -> Result<Report> {
    let (spectrum, peaks) = spectrum_of(signal, options, count, threshold)?;
    let value = merge(
        header(signal),
        merge(to_value(&spectrum)?, json!({ "peaks": to_value(&peaks)? })),
    );
    let table = {
        let mut text = format!(
            "{}: {:?} window, {} samples padded to {}, native bin {:.5} Hz, grid {:.5} Hz\n\n",
            label(signal),
            spectrum.window,
            spectrum.samples,
            spectrum.fft_length,
            spectrum.native_bin_hz,
            spectrum.grid_bin_hz
        );
        text.push_str("peak   frequency [Hz]   amplitude\n");
        for (j, peak) in peaks.iter().enumerate() {
            text.push_str(&format!(
                "{:>4}   {:>14.6}   {:.6e}\n",
                j + 1,
                peak.frequency_hz,
                peak.amplitude
            ));
        }
        text
    };
    Ok(Report { value, table })
}

/// `coil-post envelope`: the Hilbert envelope's points and fit.
pub fn envelope(signal: &Signal, options: &EnvelopeOptions) -> Result<Report> {
    let report = envelope::analyze(signal, options).map_err(|error| signal.locate(error))?;
    let value = merge(header(signal), to_value(&report)?);
    let table = envelope_table(signal, &report);
    Ok(Report { value, table })
}

/// `coil-post signature`: the cycles (without them nothing else can be measured: that is
/// the error) and, each with the reason when it cannot be computed, the loss per cycle, the
/// backbone, the envelope shape and the spectral peaks.
pub fn signature(signal: &Signal, options: &CycleOptions) -> Result<Report> {
    // Without cycles nothing else can be measured: that is the command's error.
    let series = signature::cycles(signal, options)?;
    let locate = |error| signal.locate(error);
    let loss = signature::loss_per_cycle(&series.cycles).map_err(locate);
    let backbone = signature::backbone(&series.cycles).map_err(locate);
    let shape = signature::envelope_shape(&series.cycles).map_err(locate);
    let spectral = signature::spectral_peaks(signal);
    let value = merge(
        header(signal),
        json!({
            "cycles": to_value(&series)?,
            "loss": part(&loss)?,
            "backbone": part(&backbone)?,
            "envelope_shape": part(&shape)?,
            "spectral_peaks": part(&spectral)?,
        }),
    );
    let table = {
        let band = series.band_hz.map_or("none".to_string(), |(low, high)| {
            format!("{low:.4} to {high:.4} Hz (order {})", series.filter_order)
        });
        let mut text = format!(
            "{}: dominant {:.6} Hz, band-pass {band}, {} cycles ({} rejected, {:.3} s guarded at each end)\n",
            label(signal),
            series.dominant_frequency_hz,
            series.cycles.len(),
            series.rejected,
            series.edge_guard_s
        );
        if let (Some(first), Some(last)) = (series.cycles.first(), series.cycles.last()) {
            text.push_str(&format!(
                "first cycle t {:.3} s: A {:.4e} m, f {:.5} Hz; last cycle t {:.3} s: A {:.4e} m, f {:.5} Hz\n",
                first.time_s, first.amplitude_m, first.frequency_hz,
                last.time_s, last.amplitude_m, last.frequency_hz
            ));
        }
        text.push_str("\nloss per cycle dA = a0 + a1 A + a2 A^2 (A in m):\n");
        match &loss {
            Ok(loss) => {
                text.push_str(&format!(
                    "  a0 {} m   a1 {}   a2 {} 1/m   (reduced chi2 {:.3}, {} windows of {} cycles, A {:.3e} to {:.3e} m)\n",
                    estimate(&loss.a0_m), estimate(&loss.a1), estimate(&loss.a2_per_m),
                    loss.reduced_chi2, loss.points.len(), loss.cycles_per_window,
                    loss.amplitude_range_m.0, loss.amplitude_range_m.1
                ));
                let single = &loss.single;
                text.push_str(&format!(
                    "  alone: a0 {} (chi2 {:.3}), a1 {} (chi2 {:.3}), a2 {} (chi2 {:.3})\n",
                    estimate(&single.coulomb_a0_m.coefficient),
                    single.coulomb_a0_m.reduced_chi2,
                    estimate(&single.viscous_a1.coefficient),
                    single.viscous_a1.reduced_chi2,
                    estimate(&single.quadratic_a2_per_m.coefficient),
                    single.quadratic_a2_per_m.reduced_chi2
                ));
            }
            Err(error) => text.push_str(&format!("  not available: {error}\n")),
        }
        text.push_str("\nbackbone f^2 = f0^2 (1 + b A^2):\n");
        match &backbone {
            Ok(b) => text.push_str(&format!(
                "  f0 {} Hz   b {} 1/m^2   (b A_max^2 = {:.3e}, residual {:.3e} Hz)\n",
                estimate(&b.f0_hz),
                estimate(&b.b_per_m2),
                b.shift_at_largest,
                b.residual_rms_hz
            )),
            Err(error) => text.push_str(&format!("  not available: {error}\n")),
        }
        text.push_str("\nenvelope shape:\n");
        match &shape {
            Ok(s) => {
                text.push_str(&format!(
                    "  {:?}: R^2 exponential {:.6}, linear {:.6}, beating {}\n",
                    s.kind,
                    s.r2_exponential,
                    s.r2_linear,
                    s.r2_beating.map_or("-".to_string(), |r| format!("{r:.6}"))
                ));
                if let (Some(period), Some(ratio), Some(depth)) = (
                    s.beat_candidate_period_s,
                    s.beat_variance_ratio,
                    s.modulation_depth,
                ) {
                    text.push_str(&format!(
                        "  beat candidate {period:.4} s: residual ratio {ratio:.3}, depth {depth:.3}\n"
                    ));
                }
            }
            Err(error) => text.push_str(&format!("  not available: {error}\n")),
        }
        text.push_str("\nspectral peaks:\n");
        match &spectral {
            Ok(p) => {
                text.push_str(&format!(
                    "  axial {:.6} Hz, amplitude {:.4e} (bin {:.5} Hz)\n",
                    p.axial.frequency_hz, p.axial.amplitude, p.native_bin_hz
                ));
                match &p.side {
                    Some(side) => text.push_str(&format!(
                        "  side  {:.6} Hz, relative amplitude {:.4}, beat period {:.4} s\n",
                        side.frequency_hz, side.relative_amplitude, side.beat_period_s
                    )),
                    None => text.push_str("  no side peak within 0.7-1.3 f above 2%\n"),
                }
            }
            Err(error) => text.push_str(&format!("  not available: {error}\n")),
        }
        text
    };
    Ok(Report { value, table })
}

/// `coil-post static`: the fits of a `static.csv` (displacement_mm, force_n).
pub fn static_fit(file: &Path) -> Result<Report> {
    let (displacement, force) = static_curve::read_static_csv(file)?;
    let fit = static_curve::analyze_static(&displacement, &force).map_err(|error| {
        PostError::Analysis {
            path: file.to_path_buf(),
            column: "displacement_mm, force_n".to_string(),
            error: Box::new(error),
        }
    })?;
    let value = merge(
        json!({ "file": file.display().to_string() }),
        to_value(&fit)?,
    );
    let table = static_table(file, &fit);
    Ok(Report { value, table })
}

/// What `coil-post plot` draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlotKind {
    /// Time histories.
    Time,
    /// Amplitude spectra with their peaks.
    Spectrum,
    /// Envelopes and their damping curves.
    Envelope,
}

/// The options of `coil-post plot`.
#[derive(Debug, Clone)]
pub struct PlotOptions {
    /// Time histories in one panel instead of one panel each.
    pub overlay: bool,
    /// Time histories in the column's unit instead of normalised to (-1, 1).
    pub physical: bool,
    /// Offset removed from time histories.
    pub detrend: Detrend,
    /// Highest frequency of a spectrum plot, Hz (default: twice the highest peak).
    pub fmax: Option<f64>,
    /// The envelope analysis of an envelope plot.
    pub envelope: EnvelopeOptions,
}

/// `coil-post plot`: one or two signals drawn as `kind` into `out` (.png or .svg).
pub fn plot(signals: &[Signal], kind: PlotKind, options: &PlotOptions, out: &Path) -> Result<()> {
    if signals.is_empty() {
        return Err(PostError::InvalidOption(
            "nothing to plot; expected a record".to_string(),
        ));
    }
    let labels: Vec<String> = signals.iter().map(label).collect();
    match kind {
        PlotKind::Time => {
            let detrended = signals
                .iter()
                .map(|s| {
                    remove_offset(s, options.detrend)
                        .map(|(detrended, _)| detrended.into_parts().1)
                        .map_err(|error| s.locate(error))
                })
                .collect::<Result<Vec<_>>>()?;
            let traces: Vec<plot::Trace<'_>> = signals
                .iter()
                .zip(&detrended)
                .zip(&labels)
                .map(|((s, values), label)| plot::Trace {
                    label,
                    unit: plot::unit_of(s.column()),
                    time_s: s.time_s(),
                    values,
                })
                .collect();
            let scale = if options.physical {
                plot::Scale::Physical
            } else {
                plot::Scale::Normalised
            };
            plot::time_histories_scaled(&traces, options.overlay, scale, out)
        }
        PlotKind::Spectrum => {
            let computed = signals
                .iter()
                .map(|s| spectrum_of(s, &SpectrumOptions::default(), 5, 0.05))
                .collect::<Result<Vec<_>>>()?;
            let nyquist = 0.5 / signals[0].step_s();
            let fmax = options.fmax.unwrap_or_else(|| {
                let highest = computed
                    .iter()
                    .flat_map(|(_, peaks)| peaks.iter().map(|p| p.frequency_hz))
                    .fold(0.0, f64::max);
                (2.0 * highest).clamp(f64::MIN_POSITIVE, nyquist)
            });
            if !(fmax > 0.0 && fmax.is_finite()) {
                return Err(PostError::InvalidOption(format!(
                    "--fmax {fmax}; expected a positive frequency"
                )));
            }
            let traces: Vec<plot::SpectrumTrace<'_>> = computed
                .iter()
                .zip(&labels)
                .map(|((spectrum, peaks), label)| plot::SpectrumTrace {
                    label,
                    spectrum,
                    peaks,
                })
                .collect();
            plot::spectra(&traces, fmax, out)
        }
        PlotKind::Envelope => {
            let envelope_options = &options.envelope;
            let reports = signals
                .iter()
                .map(|s| envelope::analyze(s, envelope_options).map_err(|error| s.locate(error)))
                .collect::<Result<Vec<_>>>()?;
            let traces: Vec<plot::EnvelopeTrace<'_>> = reports
                .iter()
                .zip(&labels)
                .zip(signals)
                .map(|((report, label), s)| plot::EnvelopeTrace {
                    label,
                    unit: plot::unit_of(s.column()),
                    report,
                })
                .collect();
            plot::envelopes(&traces, out)
        }
    }
}

/// `file name: column`, the line that opens each table.
pub fn label(signal: &Signal) -> String {
    let name = signal.source().file_name().map_or_else(
        || signal.source().display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    format!("{name}: {}", signal.column())
}

/// The JSON fields that open each report: file, column, samples, step.
pub fn header(signal: &Signal) -> Value {
    json!({
        "file": signal.source().display().to_string(),
        "column": signal.column(),
        "samples": signal.len(),
        "step_s": signal.step_s(),
    })
}

/// `base` with the fields of `extra` added.
pub fn merge(mut base: Value, extra: Value) -> Value {
    if let (Some(base), Value::Object(extra)) = (base.as_object_mut(), extra) {
        base.extend(extra);
    }
    base
}

/// A report piece as JSON; a non-finite number in it (which JSON would print as null and
/// a table as `inf`) is an error: the input is out of the analysis' range.
pub fn to_value<T: serde::Serialize + std::fmt::Debug>(value: &T) -> Result<Value> {
    if coil_io::non_finite_token(&format!("{value:?}")).is_some() {
        return Err(PostError::NonFiniteResult {
            what: std::any::type_name::<T>()
                .rsplit("::")
                .next()
                .unwrap_or("result")
                .to_string(),
        });
    }
    serde_json::to_value(value)
        .map_err(|e| PostError::InvalidOption(format!("cannot serialise the report: {e}")))
}

fn decrement_table(signal: &Signal, report: &DecrementReport) -> String {
    let mut text = format!(
        "{} ({} samples, step {:.6e} s)\n",
        label(signal),
        signal.len(),
        report.step_s
    );
    let lowpass = report.lowpass.map_or("none".to_string(), |l| {
        format!("{} Hz, order {} (zero phase)", l.cutoff_hz, l.order)
    });
    text.push_str(&format!(
        "{}: {} used, {} rejected; fit {:?} (+-{} samples); detrend {:?} (offset {:.6e}); low-pass {}\n\n",
        report.polarity.noun(),
        report.peak_count,
        report.peaks_rejected,
        report.peak_fit,
        report.fit_half_width,
        report.detrend,
        report.offset_removed,
        lowpass
    ));
    text.push_str("span   crests      t_first [s]   delta         zeta\n");
    for (j, span) in report.spans.iter().enumerate() {
        text.push_str(&format!(
            "{:>4}   {:>4}-{:<4}   {:>11.5}   {:<12.6e}  {:.6e}\n",
            j + 1,
            span.first + 1,
            span.last + 1,
            report.peaks[span.first].time_s,
            span.delta,
            span.zeta
        ));
    }
    text.push_str(&format!(
        "\nzeta_mean  {:.6e}   paper's Eqs. 2-3 over every {}th crest, mean of {} spans (std {:.2e})\n",
        report.zeta_mean,
        report.every,
        report.spans.len(),
        report.zeta_span_std
    ));
    text.push_str(&format!(
        "zeta_fit   {:.6e}   exponential fit of {} crest amplitudes (standard error {:.2e})\n",
        report.zeta_fit, report.peak_count, report.zeta_fit_std_error
    ));
    text.push_str(&format!(
        "period_s   {:.8}     damped frequency {:.6} Hz, natural {:.6} Hz, decay rate {:.6e} 1/s\n",
        report.period_s, report.frequency_hz, report.natural_frequency_hz, report.decay_rate_per_s
    ));
    text
}

/// The spectrum of a signal and up to `count` of its peaks above `threshold` times the
/// largest.
pub fn spectrum_of(
    signal: &Signal,
    options: &SpectrumOptions,
    count: usize,
    threshold: f64,
) -> Result<(Spectrum, Vec<SpectralPeak>)> {
    let spectrum =
        spectrum::amplitude_spectrum(signal, options).map_err(|error| signal.locate(error))?;
    let peaks = spectrum.peaks(count, threshold);
    Ok((spectrum, peaks))
}

fn envelope_table(signal: &Signal, report: &EnvelopeReport) -> String {
    let band = report.band_hz.map_or("none".to_string(), |(low, high)| {
        format!("{low:.4} to {high:.4} Hz")
    });
    let mut text = format!(
        "{}: dominant {:.6} Hz, band-pass {}, {} samples trimmed at each end, windows of {} samples\n\n",
        label(signal),
        report.dominant_frequency_hz,
        band,
        report.trim_samples,
        report.window_samples
    );
    text.push_str("  time [s]    amplitude      frequency [Hz]   zeta\n");
    for p in &report.points {
        text.push_str(&format!(
            "{:>10.4}    {:<12.6e}   {:>12.6}     {:.6e}\n",
            p.time_s, p.amplitude, p.frequency_hz, p.zeta
        ));
    }
    text.push_str(&format!(
        "\nzeta_fit {:.6e}, decay rate {:.6e} 1/s, mean frequency {:.6} Hz\n",
        report.zeta_fit, report.decay_rate_per_s, report.frequency_hz
    ));
    text
}

/// A part of the signature, or the reason it could not be computed (the other parts still
/// print).
fn part<T: serde::Serialize + std::fmt::Debug>(result: &Result<T>) -> Result<Value> {
    match result {
        Ok(value) => to_value(value),
        Err(error) => Ok(json!({ "error": error.to_string() })),
    }
}

/// `value +- std_error`.
pub fn estimate(e: &Estimate) -> String {
    format!("{:.6e} +- {:.2e}", e.value, e.std_error)
}

fn static_table(file: &Path, fit: &StaticFit) -> String {
    let friction = |f: &Option<Estimate>| {
        f.as_ref()
            .map_or("- (no unloading branch)".to_string(), estimate)
    };
    let mut text = format!(
        "{}: {} points, {} loading, {} unloading, {} excluded\n\n",
        file.display(),
        fit.points,
        fit.loading_points,
        fit.unloading_points,
        fit.excluded_points
    );
    text.push_str(&format!(
        "F = k x + k3 x^3 + s Ff:  k {} N/mm   k3 {} N/mm^3 ({} N/m^3)   Ff {} N\n  residual {:.4e} N, R^2 {:.8}\n",
        estimate(&fit.stiffness_n_mm),
        estimate(&fit.cubic_n_mm3),
        estimate(&fit.cubic_n_m3),
        friction(&fit.friction_n),
        fit.cubic.residual_rms_n,
        fit.cubic.r2
    ));
    text.push_str(&format!(
        "F = k x + s Ff:           k {} N/mm   Ff {} N\n  residual {:.4e} N, R^2 {:.8}\n",
        estimate(&fit.linear.stiffness_n_mm),
        friction(&fit.linear.friction_n),
        fit.linear.quality.residual_rms_n,
        fit.linear.quality.r2
    ));
    let o = &fit.with_offset;
    text.push_str(&format!(
        "with offset F0:           F0 {} N   k {} N/mm   k3 {} N/mm^3   Ff {} N\n  residual {:.4e} N, R^2 {:.8}\n",
        estimate(&o.offset_n),
        estimate(&o.stiffness_n_mm),
        estimate(&o.cubic_n_mm3),
        friction(&o.friction_n),
        o.quality.residual_rms_n,
        o.quality.r2
    ));
    text
}
