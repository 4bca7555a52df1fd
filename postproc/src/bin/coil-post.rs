//! `coil-post`: free-decay signals to period, logarithmic decrement, damping ratio, spectra,
//! envelopes and plots. Parses arguments, calls `coil_postproc`, maps errors to exit codes
//! (0 success, 1 an error in the data or options, 2 a usage error reported by clap).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};

use coil_postproc::decrement::{DecrementOptions, Lowpass};
use coil_postproc::envelope::EnvelopeOptions;
use coil_postproc::filter::DEFAULT_ORDER;
use coil_postproc::offset::Detrend;
use coil_postproc::peaks::{PeakFit, Polarity};
use coil_postproc::record::{self, Quantity, RecordSpec};
use coil_postproc::report::{self, PlotKind, PlotOptions};
use coil_postproc::signal::Signal;
use coil_postproc::signature::{self, CycleOptions};
use coil_postproc::spectrum::{SpectrumOptions, Window};
use coil_postproc::{PostError, Result};

#[derive(Parser)]
#[command(
    name = "coil-post",
    version,
    about = "Period, logarithmic decrement, damping ratio, spectra, envelopes and plots of \
             free-decay records (CSV, UFF 58 or MAT-file)",
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
    /// The record: CSV (coil's, with a `time_s` column, or a logger's dialect), UFF
    /// dataset 58/58b or a MATLAB level 5 MAT-file, recognised by its content.
    file: PathBuf,
    /// Signal column of a CSV file; a UFF dataset's index (from 1) or `node:direction`;
    /// a MAT-file variable (the record entry's `channel`). May be omitted when the file
    /// holds only one.
    #[arg(long, short, visible_alias = "channel")]
    column: Option<String>,
    #[command(flatten)]
    entry: Entry,
}

/// The other keys of a record entry (docs/measured-case.md): with any of them, or for a
/// file that is not coil's CSV, the channel is read in SI as `diagnose` reads it.
#[derive(Args)]
struct Entry {
    /// The MAT-file variable holding the time stamps, s (`time_s`, `time` or `t` are
    /// found without it).
    #[arg(long, value_name = "VARIABLE")]
    time: Option<String>,
    /// What the channel measures.
    #[arg(long, value_enum)]
    quantity: Option<QuantityArg>,
    /// The channel's unit (`m/s^2`, `g`, `mm/s`, `mm`, ...) when the file states none.
    #[arg(long)]
    unit: Option<String>,
}

#[derive(Clone, Copy, ValueEnum)]
enum QuantityArg {
    Acceleration,
    Velocity,
    Displacement,
}

impl From<QuantityArg> for Quantity {
    fn from(value: QuantityArg) -> Self {
        match value {
            QuantityArg::Acceleration => Quantity::Acceleration,
            QuantityArg::Velocity => Quantity::Velocity,
            QuantityArg::Displacement => Quantity::Displacement,
        }
    }
}

impl Entry {
    /// The record entry of `file` and its `channel` with these keys.
    fn spec(&self, file: &Path, channel: Option<&str>) -> RecordSpec {
        RecordSpec {
            file: file.to_path_buf(),
            channel: channel.map(str::to_string),
            time: self.time.clone(),
            quantity: self.quantity.map(Quantity::from),
            unit: self.unit.clone(),
        }
    }
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

impl From<Kind> for PlotKind {
    fn from(value: Kind) -> Self {
        match value {
            Kind::Time => PlotKind::Time,
            Kind::Spectrum => PlotKind::Spectrum,
            Kind::Envelope => PlotKind::Envelope,
        }
    }
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
            eprintln!("error: {}", coil_io::clean_message(&error.to_string()));
            ExitCode::from(1)
        }
    }
}

fn read(input: &Input) -> Result<Signal> {
    record::read_signal(&input.entry.spec(&input.file, input.column.as_deref()))
}

/// Writes the JSON where `--out` says and prints what is to be printed.
fn emit(args: &Report, report: Result<report::Report>) -> Result<()> {
    match report?.emit(args.json, args.out.as_deref())? {
        Some(text) => print_stdout(&text),
        None => Ok(()),
    }
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

fn run_decrement(args: &DecrementArgs) -> Result<()> {
    let signal = read(&args.input)?;
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
    emit(
        &args.report,
        report::decrement(&signal, &options, args.troughs),
    )
}

fn run_spectrum(args: &SpectrumArgs) -> Result<()> {
    let signal = read(&args.input)?;
    let options = SpectrumOptions {
        window: match args.window {
            WindowArg::Hann => Window::Hann,
            WindowArg::Rectangular => Window::Rectangular,
        },
        zero_pad: args.zero_pad,
        detrend: args.detrend.into(),
    };
    let report = report::spectrum(&signal, &options, args.peaks, args.threshold);
    emit(&args.report, report)
}

fn run_envelope(args: &EnvelopeArgs) -> Result<()> {
    let signal = read(&args.input)?;
    emit(
        &args.report,
        report::envelope(&signal, &args.envelope.options()),
    )
}

fn run_plot(args: &PlotArgs) -> Result<()> {
    let mut signals = vec![read(&args.input)?];
    if let Some(other) = &args.compare {
        let spec = RecordSpec {
            channel: args.compare_column.clone(),
            ..RecordSpec::file(other)
        };
        signals.push(record::read_signal(&spec)?);
    } else if args.compare_column.is_some() {
        return Err(PostError::InvalidOption(
            "--compare-column needs --compare FILE".to_string(),
        ));
    }
    let options = PlotOptions {
        overlay: args.overlay,
        physical: args.physical,
        detrend: args.detrend.into(),
        fmax: args.fmax,
        envelope: args.envelope.options(),
    };
    report::plot(&signals, args.kind.into(), &options, &args.out)
}

fn run_signature(args: &SignatureArgs) -> Result<()> {
    let signal = read(&args.input)?;
    let options = CycleOptions {
        band: (!args.no_band).then_some(args.band),
        ..CycleOptions::default()
    };
    emit(&args.report, report::signature(&signal, &options))
}

fn run_static(args: &StaticArgs) -> Result<()> {
    emit(&args.report, report::static_fit(&args.file))
}
