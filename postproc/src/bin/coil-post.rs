//! `coil-post`: free-decay signals to period, logarithmic decrement, damping ratio, spectra,
//! envelopes and plots. Parses arguments, calls `coil_postproc`, maps errors to exit codes
//! (0 success, 1 an error in the data or options, 2 a usage error reported by clap).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};
use serde_json::{json, Value};

use coil_postproc::decrement::{self, DecrementOptions, DecrementReport, Lowpass};
use coil_postproc::envelope::{self, EnvelopeOptions, EnvelopeReport};
use coil_postproc::filter::DEFAULT_ORDER;
use coil_postproc::peaks::{PeakFit, Polarity};
use coil_postproc::signal::{self, Detrend, Signal};
use coil_postproc::signature::{self, CycleOptions, Estimate};
use coil_postproc::spectrum::{self, SpectralPeak, Spectrum, SpectrumOptions, Window};
use coil_postproc::static_curve::{self, StaticFit};
use coil_postproc::{output, plot, PostError, Result};

#[derive(Parser)]
#[command(
    name = "coil-post",
    version,
    about = "Period, logarithmic decrement, damping ratio, spectra, envelopes and plots of \
             free-decay records (CSV with a time_s column)",
    after_help = "Files (docs/files.md): records up to 64 MiB; a report with a non-finite number is \
an error; --out files are written as regular files (an existing symlink, device or FIFO is refused)."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Crests, the paper's logarithmic decrement (Eqs. 2-3) and an exponential envelope fit.
    Decrement(DecrementArgs),
    /// Amplitude spectrum with interpolated peak frequencies.
    Spectrum(SpectrumArgs),
    /// Hilbert envelope, instantaneous frequency, backbone and damping curves.
    Envelope(EnvelopeArgs),
    /// PNG or SVG plot of a time history, spectrum or envelope.
    Plot(PlotArgs),
    /// What a linear model misses in a free decay (acceleration in m/s^2): per-cycle
    /// amplitude and frequency, loss per cycle, backbone, envelope shape, side peak.
    Signature(SignatureArgs),
    /// Stiffness, cubic stiffness and friction of a static.csv (displacement_mm, force_n).
    Static(StaticArgs),
}

#[derive(Args)]
struct SignatureArgs {
    #[command(flatten)]
    input: Input,
    #[command(flatten)]
    report: Report,
    /// Band-pass around the dominant peak, from (1 - B) f0 to (1 + B) f0.
    #[arg(long, value_name = "B", default_value_t = signature::DEFAULT_BAND)]
    band: f64,
    /// No band-pass at all.
    #[arg(long, conflicts_with = "band")]
    no_band: bool,
}

#[derive(Args)]
struct StaticArgs {
    /// CSV file with `displacement_mm` and `force_n` columns.
    file: PathBuf,
    #[command(flatten)]
    report: Report,
}

#[derive(Args)]
struct Input {
    /// CSV file with a `time_s` column.
    file: PathBuf,
    /// Signal column (may be omitted when the file has only one besides `time_s`).
    #[arg(long, short)]
    column: Option<String>,
}

#[derive(Args)]
struct Report {
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
    /// Write the JSON to this file (through a temporary file and a rename).
    #[arg(long, short, value_name = "FILE")]
    out: Option<PathBuf>,
}

#[derive(Clone, Copy, ValueEnum)]
enum DetrendArg {
    /// Analyse the signal as given.
    None,
    /// Subtract the record's mean.
    Mean,
    /// Subtract the equilibrium line found from crest/trough triples.
    Midline,
}

impl From<DetrendArg> for Detrend {
    fn from(value: DetrendArg) -> Self {
        match value {
            DetrendArg::None => Detrend::None,
            DetrendArg::Mean => Detrend::Mean,
            DetrendArg::Midline => Detrend::Midline,
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum PeakFitArg {
    /// Least-squares quartic over +-1/8 period (default).
    Lsq,
    /// Parabola through three samples.
    Parabola3,
    /// The largest sample, not interpolated.
    Raw,
}

impl From<PeakFitArg> for PeakFit {
    fn from(value: PeakFitArg) -> Self {
        match value {
            PeakFitArg::Lsq => PeakFit::LeastSquares,
            PeakFitArg::Parabola3 => PeakFit::Parabola3,
            PeakFitArg::Raw => PeakFit::Raw,
        }
    }
}

#[derive(Args)]
struct DecrementArgs {
    #[command(flatten)]
    input: Input,
    #[command(flatten)]
    report: Report,
    /// Crest intervals per decrement span (the paper: every 10th peak).
    #[arg(long, default_value_t = 10)]
    every: usize,
    /// Zero-phase Butterworth low-pass cutoff before crest picking, Hz.
    #[arg(long, value_name = "HZ")]
    lowpass: Option<f64>,
    /// Order of the low-pass.
    #[arg(long, default_value_t = DEFAULT_ORDER)]
    lowpass_order: usize,
    /// Offset removed before analysis.
    #[arg(long, value_enum, default_value = "none")]
    detrend: DetrendArg,
    /// How crests are located between samples.
    #[arg(long, value_enum, default_value = "lsq")]
    peak_fit: PeakFitArg,
    /// Also analyse the troughs.
    #[arg(long)]
    troughs: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum WindowArg {
    Hann,
    Rectangular,
}

#[derive(Args)]
struct SpectrumArgs {
    #[command(flatten)]
    input: Input,
    #[command(flatten)]
    report: Report,
    /// Taper before the transform.
    #[arg(long, value_enum, default_value = "hann")]
    window: WindowArg,
    /// Zero padding: the transform length is the next power of two of this times the samples.
    #[arg(long, default_value_t = 4)]
    zero_pad: usize,
    /// Most peaks listed.
    #[arg(long, default_value_t = 5)]
    peaks: usize,
    /// Smallest peak listed, relative to the largest.
    #[arg(long, default_value_t = 0.05)]
    threshold: f64,
    /// Offset removed before the transform.
    #[arg(long, value_enum, default_value = "mean")]
    detrend: DetrendArg,
}

#[derive(Args)]
struct EnvelopeArgs {
    #[command(flatten)]
    input: Input,
    #[command(flatten)]
    report: Report,
    #[command(flatten)]
    envelope: EnvelopeFlags,
}

#[derive(Args)]
struct EnvelopeFlags {
    /// Band-pass around the dominant peak first: from (1 - B) f0 to (1 + B) f0.
    #[arg(long, value_name = "B")]
    bandpass: Option<f64>,
    /// Length of each fit window, periods.
    #[arg(long, default_value_t = 4.0)]
    window_periods: f64,
    /// Discarded at each end, periods.
    #[arg(long, default_value_t = 2.0)]
    trim_periods: f64,
    /// Linear-prediction continuation added at each end before the transform, periods.
    #[arg(long, default_value_t = 4.0)]
    extension_periods: f64,
    /// Offset removed first.
    #[arg(long = "envelope-detrend", value_enum, default_value = "mean")]
    envelope_detrend: DetrendArg,
}

impl EnvelopeFlags {
    fn options(&self) -> EnvelopeOptions {
        EnvelopeOptions {
            detrend: self.envelope_detrend.into(),
            bandpass: self.bandpass,
            window_periods: self.window_periods,
            trim_periods: self.trim_periods,
            extension_periods: self.extension_periods,
            ..EnvelopeOptions::default()
        }
    }
}

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
enum Kind {
    Time,
    Spectrum,
    Envelope,
}

#[derive(Args)]
struct PlotArgs {
    #[command(flatten)]
    input: Input,
    /// A second record to draw beside the first.
    #[arg(long, value_name = "FILE")]
    compare: Option<PathBuf>,
    /// Column of the second record (may be omitted when it has only one).
    #[arg(long, value_name = "NAME")]
    compare_column: Option<String>,
    /// What to draw.
    #[arg(long, value_enum, default_value = "time")]
    kind: Kind,
    /// Output picture, .png or .svg.
    #[arg(long, short, value_name = "FILE")]
    out: PathBuf,
    /// Time histories in one panel instead of one panel each.
    #[arg(long)]
    overlay: bool,
    /// Highest frequency of a spectrum plot, Hz.
    #[arg(long, value_name = "HZ")]
    fmax: Option<f64>,
    /// Time histories in the column's unit (m/s^2, mm, ...) instead of normalised to
    /// (-1, 1) by the largest magnitude.
    #[arg(long)]
    physical: bool,
    /// Offset removed from time histories before normalising.
    #[arg(long, value_enum, default_value = "none")]
    detrend: DetrendArg,
    #[command(flatten)]
    envelope: EnvelopeFlags,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Decrement(args) => run_decrement(&args),
        Command::Spectrum(args) => run_spectrum(&args),
        Command::Envelope(args) => run_envelope(&args),
        Command::Plot(args) => run_plot(&args),
        Command::Signature(args) => run_signature(&args),
        Command::Static(args) => run_static(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::from(1)
        }
    }
}

fn read(file: &Path, column: Option<&str>) -> Result<Signal> {
    signal::read_signal_or_only(file, column)
}

fn label(signal: &Signal) -> String {
    let name = signal.source.file_name().map_or_else(
        || signal.source.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    format!("{name}: {}", signal.column)
}

/// Prints or writes the JSON, or prints `table`.
fn emit(report: &Report, value: &Value, table: impl FnOnce() -> String) -> Result<()> {
    let json = serde_json::to_string_pretty(value)
        .map_err(|e| PostError::InvalidOption(format!("cannot serialise the report: {e}")))?;
    if let Some(path) = &report.out {
        output::write_atomic(path, format!("{json}\n").as_bytes())?;
    }
    let text = if report.json {
        format!("{json}\n")
    } else if report.out.is_none() {
        table()
    } else {
        return Ok(());
    };
    print_stdout(&text)
}

/// Writes to standard output; a reader that stopped early (`| head`) is not an error.
fn print_stdout(text: &str) -> Result<()> {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    match stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush())
    {
        Err(error) if error.kind() != std::io::ErrorKind::BrokenPipe => Err(PostError::Write {
            path: PathBuf::from("<standard output>"),
            source: error,
        }),
        _ => Ok(()),
    }
}

fn header(signal: &Signal) -> Value {
    json!({
        "file": signal.source.display().to_string(),
        "column": signal.column,
        "samples": signal.values.len(),
        "step_s": signal.step_s,
    })
}

fn merge(mut base: Value, extra: Value) -> Value {
    if let (Some(base), Value::Object(extra)) = (base.as_object_mut(), extra) {
        base.extend(extra);
    }
    base
}

/// A report piece as JSON; a non-finite number in it (which JSON would print as null and
/// a table as `inf`) is an error: the input is out of the analysis' range.
fn to_value<T: serde::Serialize + std::fmt::Debug>(value: &T) -> Result<Value> {
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

fn run_decrement(args: &DecrementArgs) -> Result<()> {
    let signal = read(&args.input.file, args.input.column.as_deref())?;
    let options = DecrementOptions {
        every: args.every,
        polarity: Polarity::Crests,
        peak_fit: args.peak_fit.into(),
        detrend: args.detrend.into(),
        lowpass: args.lowpass.map(|cutoff_hz| Lowpass {
            cutoff_hz,
            order: args.lowpass_order,
        }),
    };
    let analyze = |polarity| {
        let options = DecrementOptions {
            polarity,
            ..options
        };
        decrement::analyze(&signal.time_s, &signal.values, &options)
            .map_err(|error| signal.locate(error))
    };
    let crests = analyze(Polarity::Crests)?;
    let troughs = if args.troughs {
        Some(analyze(Polarity::Troughs)?)
    } else {
        None
    };
    let mut value = merge(header(&signal), to_value(&crests)?);
    if let (Some(object), Some(troughs)) = (value.as_object_mut(), &troughs) {
        object.insert("troughs".to_string(), to_value(troughs)?);
    }
    emit(&args.report, &value, || {
        let mut text = decrement_table(&signal, &crests);
        if let Some(troughs) = &troughs {
            text.push_str("\ntroughs:\n");
            text.push_str(&decrement_table(&signal, troughs));
        }
        text
    })
}

fn decrement_table(signal: &Signal, report: &DecrementReport) -> String {
    let mut text = format!(
        "{} ({} samples, step {:.6e} s)\n",
        label(signal),
        signal.values.len(),
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

fn spectrum_of(
    signal: &Signal,
    options: &SpectrumOptions,
    count: usize,
    threshold: f64,
) -> Result<(Spectrum, Vec<SpectralPeak>)> {
    let spectrum = spectrum::amplitude_spectrum(&signal.time_s, &signal.values, options)
        .map_err(|error| signal.locate(error))?;
    let peaks = spectrum.peaks(count, threshold);
    Ok((spectrum, peaks))
}

fn run_spectrum(args: &SpectrumArgs) -> Result<()> {
    let signal = read(&args.input.file, args.input.column.as_deref())?;
    let options = SpectrumOptions {
        window: match args.window {
            WindowArg::Hann => Window::Hann,
            WindowArg::Rectangular => Window::Rectangular,
        },
        zero_pad: args.zero_pad,
        detrend: args.detrend.into(),
    };
    let (spectrum, peaks) = spectrum_of(&signal, &options, args.peaks, args.threshold)?;
    let value = merge(
        header(&signal),
        merge(to_value(&spectrum)?, json!({ "peaks": to_value(&peaks)? })),
    );
    emit(&args.report, &value, || {
        let mut text = format!(
            "{}: {:?} window, {} samples padded to {}, native bin {:.5} Hz, grid {:.5} Hz\n\n",
            label(&signal),
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
    })
}

fn run_envelope(args: &EnvelopeArgs) -> Result<()> {
    let signal = read(&args.input.file, args.input.column.as_deref())?;
    let report = envelope::analyze(&signal.time_s, &signal.values, &args.envelope.options())
        .map_err(|error| signal.locate(error))?;
    let value = merge(header(&signal), to_value(&report)?);
    emit(&args.report, &value, || envelope_table(&signal, &report))
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

fn run_plot(args: &PlotArgs) -> Result<()> {
    let mut signals = vec![read(&args.input.file, args.input.column.as_deref())?];
    if let Some(other) = &args.compare {
        signals.push(read(other, args.compare_column.as_deref())?);
    } else if args.compare_column.is_some() {
        return Err(PostError::InvalidOption(
            "--compare-column needs --compare FILE".to_string(),
        ));
    }
    let labels: Vec<String> = signals.iter().map(label).collect();
    match args.kind {
        Kind::Time => {
            let detrended = signals
                .iter()
                .map(|s| {
                    signal::remove_offset(&s.time_s, &s.values, args.detrend.into())
                        .map(|(values, _)| values)
                        .map_err(|error| s.locate(error))
                })
                .collect::<Result<Vec<_>>>()?;
            let traces: Vec<plot::Trace<'_>> = signals
                .iter()
                .zip(&detrended)
                .zip(&labels)
                .map(|((s, values), label)| plot::Trace {
                    label,
                    unit: plot::unit_of(&s.column),
                    time_s: &s.time_s,
                    values,
                })
                .collect();
            let scale = if args.physical {
                plot::Scale::Physical
            } else {
                plot::Scale::Normalised
            };
            plot::time_histories_scaled(&traces, args.overlay, scale, &args.out)
        }
        Kind::Spectrum => {
            let computed = signals
                .iter()
                .map(|s| spectrum_of(s, &SpectrumOptions::default(), 5, 0.05))
                .collect::<Result<Vec<_>>>()?;
            let nyquist = 0.5 / signals[0].step_s;
            let fmax = args.fmax.unwrap_or_else(|| {
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
            plot::spectra(&traces, fmax, &args.out)
        }
        Kind::Envelope => {
            let options = args.envelope.options();
            let reports = signals
                .iter()
                .map(|s| {
                    envelope::analyze(&s.time_s, &s.values, &options)
                        .map_err(|error| s.locate(error))
                })
                .collect::<Result<Vec<_>>>()?;
            let traces: Vec<plot::EnvelopeTrace<'_>> = reports
                .iter()
                .zip(&labels)
                .zip(&signals)
                .map(|((report, label), s)| plot::EnvelopeTrace {
                    label,
                    unit: plot::unit_of(&s.column),
                    report,
                })
                .collect();
            plot::envelopes(&traces, &args.out)
        }
    }
}

/// A part of the signature, or the reason it could not be computed (the other parts still
/// print).
fn part<T: serde::Serialize + std::fmt::Debug>(result: &Result<T>) -> Result<Value> {
    match result {
        Ok(value) => to_value(value),
        Err(error) => Ok(json!({ "error": error.to_string() })),
    }
}

fn estimate(e: &Estimate) -> String {
    format!("{:.6e} +- {:.2e}", e.value, e.std_error)
}

fn run_signature(args: &SignatureArgs) -> Result<()> {
    let signal = read(&args.input.file, args.input.column.as_deref())?;
    let options = CycleOptions {
        band: (!args.no_band).then_some(args.band),
        ..CycleOptions::default()
    };
    // Without cycles nothing else can be measured: that is the command's error.
    let series = signature::cycles(&signal, &options)?;
    let locate = |error| signal.locate(error);
    let loss = signature::loss_per_cycle(&series.cycles).map_err(locate);
    let backbone = signature::backbone(&series.cycles).map_err(locate);
    let shape = signature::envelope_shape(&series.cycles).map_err(locate);
    let spectral = signature::spectral_peaks(&signal);
    let value = merge(
        header(&signal),
        json!({
            "cycles": to_value(&series)?,
            "loss": part(&loss)?,
            "backbone": part(&backbone)?,
            "envelope_shape": part(&shape)?,
            "spectral_peaks": part(&spectral)?,
        }),
    );
    emit(&args.report, &value, || {
        let band = series.band_hz.map_or("none".to_string(), |(low, high)| {
            format!("{low:.4} to {high:.4} Hz (order {})", series.filter_order)
        });
        let mut text = format!(
            "{}: dominant {:.6} Hz, band-pass {band}, {} cycles ({} rejected, {:.3} s guarded at each end)\n",
            label(&signal),
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
    })
}

fn run_static(args: &StaticArgs) -> Result<()> {
    let (displacement, force) = static_curve::read_static_csv(&args.file)?;
    let fit = static_curve::analyze_static(&displacement, &force).map_err(|error| {
        PostError::Analysis {
            path: args.file.clone(),
            column: "displacement_mm, force_n".to_string(),
            error: Box::new(error),
        }
    })?;
    let value = merge(
        json!({ "file": args.file.display().to_string() }),
        to_value(&fit)?,
    );
    emit(&args.report, &value, || static_table(&args.file, &fit))
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
