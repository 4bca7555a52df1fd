//! The one error type of the post-processor.
//!
//! Every variant that comes from a file names the file and, where a line is at fault, the
//! 1-based line number as a text editor shows it (the header is line 1). Variants that come
//! from in-memory signals name the 0-based sample index instead. Each message says what was
//! expected, so that the person reading it knows what to fix.

use coil_io::excerpt;
use std::path::PathBuf;

/// Column names of a user file for a message: each a short sanitised excerpt, at most 8.
fn names(available: &[String]) -> String {
    let mut shown: Vec<String> = available.iter().take(8).map(|n| excerpt(n)).collect();
    if available.len() > 8 {
        shown.push(format!("and {} more", available.len() - 8));
    }
    excerpt_n(&shown.join(", "), 300)
}

use coil_io::confine::excerpt_n;

/// Everything that can go wrong while reading, analysing or writing signals.
#[derive(Debug, thiserror::Error)]
pub enum PostError {
    /// An input outside its limits (size, not a regular file; docs/files.md).
    #[error(transparent)]
    Input(#[from] coil_io::ConfineError),

    /// An analysis produced a non-finite number (the data is outside its numeric range).
    #[error("the {what} holds a non-finite number (inf or NaN): the data is outside the range this analysis can represent (e.g. values near 1e308); expected finite results, nothing was printed")]
    NonFiniteResult {
        /// What was computed.
        what: String,
    },

    /// An output file cannot be written (or would replace a non-regular file).
    #[error(transparent)]
    Output(#[from] coil_io::WriteError),

    /// The input file could not be opened or read.
    #[error("{}: cannot read the file: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },

    /// The CSV syntax itself is broken (unequal field counts, bad quoting, invalid UTF-8).
    #[error("{}:{line}: malformed CSV: {message}", path.display())]
    Csv {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: u64,
        /// What is wrong and what was expected.
        message: String,
    },

    /// No header line at all.
    #[error("{}: the file is empty; expected a header line such as `time_s,accel_m_s2`", path.display())]
    Empty {
        /// The file.
        path: PathBuf,
    },

    /// A requested column (or `time_s`) is not in the header.
    #[error(
        "{}:{line}: no column named `{}` in the header; available columns: {}",
        path.display(),
        excerpt(column),
        names(available)
    )]
    MissingColumn {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: u64,
        /// The column's name.
        column: String,
        /// The names that are there.
        available: Vec<String>,
    },

    /// The same column name appears twice, so a lookup by name is ambiguous.
    #[error(
        "{}:{line}: column `{column}` appears more than once in the header (fields {first} and {second}); expected unique names",
        path.display()
    )]
    DuplicateColumn {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: u64,
        /// The column's name.
        column: String,
        /// The first (1-based).
        first: usize,
        /// The second (1-based).
        second: usize,
    },

    /// A cell does not parse as a number.
    #[error("{}:{line}: column `{}`: expected a number, found `{}`", path.display(), excerpt(column), excerpt(text))]
    NotANumber {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: u64,
        /// The column's name.
        column: String,
        /// The text as written.
        text: String,
    },

    /// A cell parses as NaN or an infinity.
    #[error("{}:{line}: column `{}`: `{}` is not a finite number; expected a finite value", path.display(), excerpt(column), excerpt(text))]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: u64,
        /// The column's name.
        column: String,
        /// The text as written.
        text: String,
    },

    /// `time_s` goes backwards or repeats.
    #[error(
        "{}:{line}: time_s = {time} s does not increase (previous sample: {previous} s); expected strictly increasing time",
        path.display()
    )]
    TimeNotIncreasing {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: u64,
        /// The time, s.
        time: f64,
        /// The time before it, s.
        previous: f64,
    },

    /// `time_s` steps are not uniform (a dropped sample, a change of rate).
    #[error(
        "{}:{line}: time step {step_s:e} s differs from the record's median step {median_step_s:e} s by more than {tolerance_percent}% (plus print rounding); expected uniformly sampled data; resample it first",
        path.display()
    )]
    NonUniformTime {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: u64,
        /// The step, s.
        step_s: f64,
        /// The record's median step, s.
        median_step_s: f64,
        /// The tolerance, percent.
        tolerance_percent: f64,
    },

    /// Fewer data rows than any analysis can use.
    #[error("{}: {found} data rows; need at least {needed}", path.display())]
    TooFewSamples {
        /// The file.
        path: PathBuf,
        /// How many were found.
        found: usize,
        /// How many are needed.
        needed: usize,
    },

    /// The user named no column and the file has more than one signal column.
    #[error(
        "{}:{line}: {} signal columns ({}); choose one with --column",
        path.display(),
        available.len(),
        names(available)
    )]
    AmbiguousColumn {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: u64,
        /// The names that are there.
        available: Vec<String>,
    },

    /// An analysis of one column of a file failed; says which.
    #[error("{}, column `{column}`: {error}", path.display())]
    Analysis {
        /// The file.
        path: PathBuf,
        /// The column's name.
        column: String,
        /// The analysis error.
        error: Box<PostError>,
    },

    /// A record (a UFF dataset, a MAT-file variable, a CSV column) that cannot be read as
    /// the file or the case describes it: `at` is the line, dataset or variable.
    #[error("{}:{at}: {problem}; expected {expected}", path.display())]
    Record {
        /// The file.
        path: PathBuf,
        /// Where in it: a line number, `dataset 2 (line 14)`, `variable `acc``.
        at: String,
        /// What is wrong.
        problem: String,
        /// What was expected.
        expected: String,
    },

    /// An in-memory signal is unusable (length mismatch, non-finite value, bad time axis).
    #[error("invalid signal at sample {index}: {what}")]
    InvalidSignal {
        /// Index of the first bad sample.
        index: usize,
        /// What was computed.
        what: String,
    },

    /// Not enough regular crests for the requested estimator.
    #[error("found {found} regular {kind}, need at least {needed}: {hint}")]
    TooFewPeaks {
        /// What was counted (crests, cycles, ...).
        kind: &'static str,
        /// How many were found.
        found: usize,
        /// How many are needed.
        needed: usize,
        /// What to do next.
        hint: String,
    },

    /// Fewer usable points than a fit needs (cycles for the loss fit, samples of a static
    /// record, ...).
    #[error("{what}: {found} usable points, need at least {needed}; {hint}")]
    TooFewPoints {
        /// What was computed.
        what: &'static str,
        /// How many were found.
        found: usize,
        /// How many are needed.
        needed: usize,
        /// What to do next.
        hint: String,
    },

    /// A static record without any point where the compression increases.
    #[error(
        "static record: no loading branch ({increasing} of {points} points have increasing \
         displacement, need at least {needed}); expected compression that grows, then (optionally) \
         shrinks"
    )]
    NoLoadingBranch {
        /// Points given.
        points: usize,
        /// Points on the increasing branch.
        increasing: usize,
        /// How many are needed.
        needed: usize,
    },

    /// The data do not determine a quantity (a singular fit, a value no model parameter can
    /// produce).
    #[error("{what} cannot be identified: {why}")]
    Unidentifiable {
        /// What was computed.
        what: &'static str,
        /// Why.
        why: String,
    },

    /// An option value is out of its valid range.
    #[error("invalid option: {0}")]
    InvalidOption(String),

    /// A history given beside a time axis has another length (EN 50318 statistics).
    #[error("{what}: {found} samples but the time axis has {expected}; expected one value per time sample")]
    LengthMismatch {
        /// Which history (`force_n`, `position_m`, `support 3 displacement_mm`).
        what: String,
        /// Its length.
        found: usize,
        /// The time axis's length.
        expected: usize,
    },

    /// A low-pass cutoff at or above the Nyquist frequency of the record.
    #[error("low-pass cutoff {cutoff_hz} Hz is at or above the Nyquist frequency {nyquist_hz} Hz of the record; expected a cutoff below it (sample the record more finely or lower the cutoff)")]
    CutoffAboveNyquist {
        /// The cutoff asked for (Hz).
        cutoff_hz: f64,
        /// Half the sampling rate (Hz).
        nyquist_hz: f64,
    },

    /// No sample of a record lies in the evaluation window (EN 50318 statistics).
    #[error("the evaluation window {start_m} to {end_m} m holds no sample: the pantograph covers {first_m} to {last_m} m; expected a window inside the covered track")]
    EmptyWindow {
        /// The window's start along the track (m).
        start_m: f64,
        /// Its end (m).
        end_m: f64,
        /// The pantograph's first position (m).
        first_m: f64,
        /// Its last position (m).
        last_m: f64,
    },

    /// No support (steady arm, messenger support) lies in the evaluation window.
    #[error("no support lies in the evaluation window {start_m} to {end_m} m ({supports} supports given); expected the displacement history of at least one support inside it")]
    NoSupportInWindow {
        /// The window's start along the track (m).
        start_m: f64,
        /// Its end (m).
        end_m: f64,
        /// How many supports were given.
        supports: usize,
    },

    /// Writing an output file failed; nothing was left at the destination.
    #[error("{}: cannot write: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },

    /// The plotting backend failed.
    #[error("{}: cannot draw the plot: {message}", path.display())]
    Plot {
        /// The file.
        path: PathBuf,
        /// What is wrong and what was expected.
        message: String,
    },
}

/// Result alias of the crate.
pub type Result<T, E = PostError> = std::result::Result<T, E>;

/// A number for a message: plain for ordinary magnitudes, with an exponent otherwise (Rust's
/// `Display` writes 1e-300 with 300 digits).
pub(crate) fn show(x: f64) -> String {
    if x == 0.0 || (1e-4..1e9).contains(&x.abs()) || !x.is_finite() {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}
