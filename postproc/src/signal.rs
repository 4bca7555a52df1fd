//! Uniformly sampled signals: reading them from CSV and checking their time axis once, into
//! a [`Signal`] that every analysis takes.
//!
//! # File format
//! Any comma-separated file whose first line is a header naming the columns, one of them
//! `time_s` (seconds), the others signals in whatever unit their name gives (for example
//! `node12_uz_accel_m_s2` from `coil-solve`, or `accel_m_s2` in a measured `decay.csv`, see
//! `docs/measured-case.md`). Cells may be padded with spaces; lines starting with `#`
//! are comments; blank lines are skipped. Every cell of `time_s` and of each requested column
//! must be a finite number.
//!
//! # Time axis
//! The estimators assume uniform sampling. A record passes when every step
//! `t[i] - t[i-1]` is positive and within [`STEP_TOLERANCE`] of the median step, widened by
//! the resolution to which the times were printed (the median over the cells of the decimal
//! grid each was written on: a file that writes 1024 Hz times with four decimals has steps
//! that jitter by up to 1e-4 s purely from rounding), at most by 45% of the step. The
//! analyses then use the ideal grid `t[0] + i * step` with the mean step
//! `(t[n-1] - t[0]) / (n - 1)`, so print rounding does not leak into peak times. A dropped
//! sample (a step of twice the median) or a change of sampling rate is reported with its line.
//!
//! # Offsets
//! [`crate::offset::Detrend`] says what constant is removed before analysis; see its
//! variants for what each choice does to a decaying oscillation.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::error::{PostError, Result};

/// Name of the mandatory time column.
pub const TIME_COLUMN: &str = "time_s";

/// Relative tolerance of each time step against the record's mean step (5%).
pub const STEP_TOLERANCE: f64 = 0.05;

/// The fewest rows a record may have: three samples define a step and check it once.
pub const MIN_SAMPLES: usize = 3;

/// Columns read from one CSV file, on a checked uniform time axis.
#[derive(Debug, Clone)]
pub struct Table {
    /// The file the table came from (for messages).
    pub path: PathBuf,
    /// Line of the header (1 unless comment lines precede it).
    pub header_line: u64,
    /// `time_s` as read, seconds.
    pub time_s: Vec<f64>,
    /// Mean sampling step, seconds.
    pub step_s: f64,
    /// Every header name in file order (including `time_s`).
    pub header: Vec<String>,
    /// The parsed columns, by name, in the order they were requested.
    pub columns: Vec<(String, Vec<f64>)>,
}

impl Table {
    /// The values of column `name`, or a [`PostError::MissingColumn`] listing the columns
    /// that were read.
    pub fn column(&self, name: &str) -> Result<&[f64]> {
        self.columns
            .iter()
            .find(|(column, _)| column == name)
            .map(|(_, values)| values.as_slice())
            .ok_or_else(|| PostError::MissingColumn {
                path: self.path.clone(),
                line: self.header_line,
                column: name.to_string(),
                available: self.header.clone(),
            })
    }

    /// One column as a [`Signal`] (the time axis was checked when the file was read).
    pub fn signal(&self, name: &str) -> Result<Signal> {
        Ok(Signal {
            source: self.path.clone(),
            column: name.to_string(),
            time_s: self.time_s.clone(),
            step_s: self.step_s,
            values: self.column(name)?.to_vec(),
        })
    }
}

/// One named column with its time axis, checked once when it is made: at least
/// [`MIN_SAMPLES`] samples, finite values, a finite time that increases uniformly (see the
/// module doc), and its sampling step computed then. The fields are private so that no
/// analysis re-derives or re-checks them: every analysis of the crate takes a `&Signal`.
#[derive(Debug, Clone)]
pub struct Signal {
    source: PathBuf,
    column: String,
    time_s: Vec<f64>,
    step_s: f64,
    values: Vec<f64>,
}

impl Signal {
    /// An in-memory signal: checks equal lengths, at least [`MIN_SAMPLES`] samples, finite
    /// numbers and a uniform increasing time (within [`STEP_TOLERANCE`]); the step is the
    /// mean step `(t[n-1] - t[0]) / (n - 1)`. Errors are [`PostError::InvalidSignal`] with
    /// the first bad index. It has no file or column name until [`Signal::named`].
    pub fn new(time_s: Vec<f64>, values: Vec<f64>) -> Result<Signal> {
        let step_s = uniform_step(&time_s, &values)?;
        Ok(Signal::unnamed(time_s, step_s, values))
    }

    /// [`Signal::new`] for time stamps printed on a decimal grid of `rounding_s` (their
    /// steps may jitter by that much, see the module doc).
    pub fn printed(time_s: Vec<f64>, values: Vec<f64>, rounding_s: f64) -> Result<Signal> {
        if rounding_s == 0.0 {
            return Signal::new(time_s, values);
        }
        let exact = Signal::new(time_s.clone(), values.clone());
        match exact {
            Ok(signal) => Ok(signal),
            Err(_) if time_s.len() == values.len() && time_s.len() >= MIN_SAMPLES => {
                check_finite(&time_s, &values)?;
                let step_s = check_time_axis(&time_s, rounding_s).map_err(|_| {
                    PostError::InvalidSignal {
                        index: 0,
                        what: format!(
                            "time steps beyond {}% of the median plus the print rounding {rounding_s:e} s; expected uniform sampling",
                            STEP_TOLERANCE * 100.0
                        ),
                    }
                })?;
                Ok(Signal::unnamed(time_s, step_s, values))
            }
            Err(e) => Err(e),
        }
    }

    /// A signal sampled at `start_s + i * step_s` (exactly that grid): checks a finite
    /// start, a finite positive step, at least [`MIN_SAMPLES`] finite values.
    pub fn uniform(start_s: f64, step_s: f64, values: Vec<f64>) -> Result<Signal> {
        if !(start_s.is_finite() && step_s.is_finite() && step_s > 0.0) {
            return Err(PostError::InvalidSignal {
                index: 0,
                what: format!(
                    "start {start_s} s, step {step_s} s: expected a finite start and a positive step"
                ),
            });
        }
        if values.len() < MIN_SAMPLES {
            return Err(PostError::InvalidSignal {
                index: values.len(),
                what: format!("{} samples; need at least {MIN_SAMPLES}", values.len()),
            });
        }
        let time_s: Vec<f64> = (0..values.len())
            .map(|i| start_s + i as f64 * step_s)
            .collect();
        check_finite(&time_s, &values)?;
        Ok(Signal::unnamed(time_s, step_s, values))
    }

    /// A checked axis and values without a file or column name.
    fn unnamed(time_s: Vec<f64>, step_s: f64, values: Vec<f64>) -> Signal {
        Signal {
            source: PathBuf::new(),
            column: String::new(),
            time_s,
            step_s,
            values,
        }
    }

    /// The same signal, named by the file and column it stands for (for messages).
    pub fn named(self, source: impl Into<PathBuf>, column: impl Into<String>) -> Signal {
        Signal {
            source: source.into(),
            column: column.into(),
            ..self
        }
    }

    /// Other values on the same (already checked) time axis: checks their count and that
    /// they are finite.
    pub fn with_values(&self, values: Vec<f64>) -> Result<Signal> {
        if values.len() != self.time_s.len() {
            return Err(PostError::InvalidSignal {
                index: self.time_s.len().min(values.len()),
                what: format!(
                    "time has {} samples but the signal has {}; expected equal lengths",
                    self.time_s.len(),
                    values.len()
                ),
            });
        }
        check_finite(&self.time_s, &values)?;
        Ok(Signal {
            source: self.source.clone(),
            column: self.column.clone(),
            time_s: self.time_s.clone(),
            step_s: self.step_s,
            values,
        })
    }

    /// The samples `range` (at least [`MIN_SAMPLES`] of them), with the same step.
    pub fn slice(&self, range: std::ops::Range<usize>) -> Result<Signal> {
        let n = self.time_s.len();
        if range.start > range.end || range.end > n || range.len() < MIN_SAMPLES {
            return Err(PostError::InvalidSignal {
                index: range.start.min(n),
                what: format!(
                    "samples {}..{} of {n}; expected a range of at least {MIN_SAMPLES} inside the record",
                    range.start, range.end
                ),
            });
        }
        Ok(Signal {
            source: self.source.clone(),
            column: self.column.clone(),
            time_s: self.time_s[range.clone()].to_vec(),
            step_s: self.step_s,
            values: self.values[range].to_vec(),
        })
    }

    /// The file it came from (empty for an in-memory signal).
    pub fn source(&self) -> &Path {
        &self.source
    }

    /// Its column name (empty for an in-memory signal).
    pub fn column(&self) -> &str {
        &self.column
    }

    /// Time, seconds (uniform within [`STEP_TOLERANCE`], increasing).
    pub fn time_s(&self) -> &[f64] {
        &self.time_s
    }

    /// Mean sampling step, seconds.
    pub fn step_s(&self) -> f64 {
        self.step_s
    }

    /// The values, in the unit the column name gives.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The number of samples (at least [`MIN_SAMPLES`]).
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Always false: a signal has at least [`MIN_SAMPLES`] samples.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The time and the values.
    pub fn into_parts(self) -> (Vec<f64>, Vec<f64>) {
        (self.time_s, self.values)
    }

    /// Wraps an analysis error with this signal's file and column (an unnamed, in-memory
    /// signal returns it as is).
    pub fn locate(&self, error: PostError) -> PostError {
        if self.source.as_os_str().is_empty() && self.column.is_empty() {
            return error;
        }
        match error {
            PostError::TooFewPeaks { .. }
            | PostError::TooFewPoints { .. }
            | PostError::Unidentifiable { .. }
            | PostError::InvalidSignal { .. }
            | PostError::InvalidOption(_) => PostError::Analysis {
                path: self.source.clone(),
                column: self.column.clone(),
                error: Box::new(error),
            },
            other => other,
        }
    }
}

/// Which columns to parse.
#[derive(Debug, Clone, Copy)]
pub enum Columns<'a> {
    /// Every column of the header must be numeric.
    All,
    /// Only these (plus `time_s`); other columns may hold anything.
    Named(&'a [&'a str]),
}

/// Reads every column of a CSV file (all must be numeric).
pub fn read_csv(path: &Path) -> Result<Table> {
    read_csv_columns(path, Columns::All)
}

/// Reads one column of a CSV file as a [`Signal`].
pub fn read_signal(path: &Path, column: &str) -> Result<Signal> {
    read_csv_columns(path, Columns::Named(&[column]))?.signal(column)
}

/// Reads `column`, or, when it is `None`, the only column besides `time_s`
/// ([`PostError::AmbiguousColumn`] when there are several).
pub fn read_signal_or_only(path: &Path, column: Option<&str>) -> Result<Signal> {
    if let Some(column) = column {
        return read_signal(path, column);
    }
    let (header, header_line) = read_header(path)?;
    if !header.iter().any(|name| name == TIME_COLUMN) {
        return Err(PostError::MissingColumn {
            path: path.to_path_buf(),
            line: header_line,
            column: TIME_COLUMN.to_string(),
            available: header,
        });
    }
    let signals: Vec<String> = header
        .into_iter()
        .filter(|name| name != TIME_COLUMN)
        .collect();
    match signals.as_slice() {
        [only] => read_signal(path, only),
        _ => Err(PostError::AmbiguousColumn {
            path: path.to_path_buf(),
            line: header_line,
            available: signals,
        }),
    }
}

/// A CSV file in memory with the physical line of each record. The csv crate's own line
/// counter skips blank lines, so records are mapped to lines here: the n-th line that is not
/// blank and does not start with `#` holds the n-th record (cells never span lines in a
/// numeric record).
struct Source {
    path: PathBuf,
    bytes: Vec<u8>,
    record_lines: Vec<u64>,
}

impl Source {
    fn open(path: &Path) -> Result<Self> {
        let bytes = coil_io::confine::read_bounded_bytes(
            path,
            coil_io::MAX_RECORD_BYTES,
            "a record (CSV)",
        )?;
        Ok(Source::in_memory(path, bytes))
    }

    /// A file's text already in memory (a CSV dialect rewritten to this syntax, line for
    /// line, by [`crate::record`]).
    fn in_memory(path: &Path, bytes: Vec<u8>) -> Self {
        let record_lines = bytes
            .split(|&b| b == b'\n')
            .enumerate()
            .filter(|(_, line)| {
                let line = line.strip_suffix(b"\r").unwrap_or(line);
                !line.is_empty() && !line.starts_with(b"#")
            })
            .map(|(index, _)| index as u64 + 1)
            .collect();
        Source {
            path: path.to_path_buf(),
            bytes,
            record_lines,
        }
    }

    fn reader(&self) -> csv::Reader<&[u8]> {
        csv::ReaderBuilder::new()
            .has_headers(true)
            .trim(csv::Trim::All)
            .comment(Some(b'#'))
            .from_reader(self.bytes.as_slice())
    }

    /// Line of record `index` (0 is the header).
    fn line(&self, index: u64) -> u64 {
        usize::try_from(index)
            .ok()
            .and_then(|i| self.record_lines.get(i))
            .copied()
            .unwrap_or(index + 1)
    }

    fn csv_error(&self, error: csv::Error) -> PostError {
        let path = self.path.clone();
        let line = error.position().map_or(0, |p| self.line(p.record()));
        match error.into_kind() {
            csv::ErrorKind::Io(source) => PostError::Read { path, source },
            csv::ErrorKind::UnequalLengths {
                expected_len, len, ..
            } => PostError::Csv {
                path,
                line,
                message: format!("expected {expected_len} fields as in the header, found {len}"),
            },
            csv::ErrorKind::Utf8 { err, .. } => PostError::Csv {
                path,
                line,
                message: format!("invalid UTF-8: {err}"),
            },
            other => PostError::Csv {
                path,
                line,
                message: format!("{other:?}"),
            },
        }
    }

    /// The header names (trimmed, without a byte-order mark) and the header's line.
    fn header(&self, reader: &mut csv::Reader<&[u8]>) -> Result<(Vec<String>, u64)> {
        let record = reader
            .headers()
            .map_err(|error| self.csv_error(error))?
            .clone();
        if record.is_empty() || (record.len() == 1 && record[0].is_empty()) {
            return Err(PostError::Empty {
                path: self.path.clone(),
            });
        }
        let header = record
            .iter()
            .enumerate()
            .map(|(i, name)| {
                // A spreadsheet may save a byte-order mark before the first name.
                let name = if i == 0 {
                    name.trim_start_matches('\u{feff}')
                } else {
                    name
                };
                name.trim().to_string()
            })
            .collect();
        Ok((header, self.line(0)))
    }
}

/// The header names of a CSV file and the line they are on (comment lines skipped).
pub fn read_header(path: &Path) -> Result<(Vec<String>, u64)> {
    let source = Source::open(path)?;
    let mut reader = source.reader();
    source.header(&mut reader)
}

/// Named columns of a CSV file, every cell checked, with the physical line of each row.
pub struct Fields {
    /// Every header name in file order.
    pub header: Vec<String>,
    /// Line of the header.
    pub header_line: u64,
    /// One vector per requested name, in the order requested.
    pub values: Vec<Vec<f64>>,
    /// Printed resolution of each cell of the first requested column (see
    /// `printed_resolution`).
    pub first_resolution: Vec<f64>,
    /// Line of each row.
    pub lines: Vec<u64>,
}

/// Reads the columns `names` (in that order) of a CSV file, with the same syntax and checks
/// as [`read_csv_columns`] but no time axis: for records such as `static.csv`
/// (`displacement_mm,force_n`). Errors name the file and line.
pub fn read_fields(path: &Path, names: &[&str]) -> Result<Fields> {
    read_fields_of(Source::open(path)?, names)
}

/// [`read_fields`] on the text of `path` already in memory, in this module's syntax
/// (comma-separated, decimal point, `#` comments), with the file's own line numbers.
pub(crate) fn read_fields_in(path: &Path, bytes: Vec<u8>, names: &[&str]) -> Result<Fields> {
    read_fields_of(Source::in_memory(path, bytes), names)
}

/// [`read_header`] on text in memory (see [`read_fields_in`]).
pub(crate) fn read_header_in(path: &Path, bytes: Vec<u8>) -> Result<(Vec<String>, u64)> {
    let source = Source::in_memory(path, bytes);
    let mut reader = source.reader();
    source.header(&mut reader)
}

fn read_fields_of(source: Source, names: &[&str]) -> Result<Fields> {
    let cells = read_cells_of(source, names, false)?;
    Ok(Fields {
        header: cells.header,
        header_line: cells.header_line,
        // Every cell was required, so every cell holds a number.
        values: cells
            .values
            .into_iter()
            .map(|column| column.into_iter().map(|v| v.unwrap_or(f64::NAN)).collect())
            .collect(),
        first_resolution: cells.first_resolution,
        lines: cells.lines,
    })
}

/// Columns read by name where a cell may be left empty (`None`): the measured output of a
/// forced record given only for its first samples.
#[derive(Debug, Clone)]
pub struct OptionalFields {
    /// Every header name in file order.
    pub header: Vec<String>,
    /// Line of the header.
    pub header_line: u64,
    /// One vector per requested name, in the order requested; `None` for an empty cell.
    pub values: Vec<Vec<Option<f64>>>,
    /// Printed resolution of each cell of the first requested column (0 for an empty one).
    pub first_resolution: Vec<f64>,
    /// Line of each row.
    pub lines: Vec<u64>,
}

/// [`read_fields_in`] with empty cells allowed (`None`); a cell that holds text must still be
/// a finite number.
pub(crate) fn read_optional_fields_in(
    path: &Path,
    bytes: Vec<u8>,
    names: &[&str],
) -> Result<OptionalFields> {
    read_cells_of(Source::in_memory(path, bytes), names, true)
}

fn read_cells_of(source: Source, names: &[&str], allow_empty: bool) -> Result<OptionalFields> {
    let path = source.path.clone();
    let path = path.as_path();
    let mut reader = source.reader();
    let (header, header_line) = source.header(&mut reader)?;

    let mut first_field: HashMap<&str, usize> = HashMap::new();
    for (field, name) in header.iter().enumerate() {
        if let Some(&first) = first_field.get(name.as_str()) {
            if names.contains(&name.as_str()) {
                return Err(PostError::DuplicateColumn {
                    path: path.to_path_buf(),
                    line: header_line,
                    column: name.clone(),
                    first: first + 1,
                    second: field + 1,
                });
            }
        } else {
            first_field.insert(name, field);
        }
    }
    let wanted_fields = names
        .iter()
        .map(|name| {
            first_field
                .get(name)
                .copied()
                .ok_or_else(|| PostError::MissingColumn {
                    path: path.to_path_buf(),
                    line: header_line,
                    column: name.to_string(),
                    available: header.clone(),
                })
        })
        .collect::<Result<Vec<_>>>()?;

    let mut first_resolution = Vec::new();
    let mut lines = Vec::new();
    let mut values: Vec<Vec<Option<f64>>> = vec![Vec::new(); names.len()];
    let mut record = csv::StringRecord::new();
    loop {
        match reader.read_record(&mut record) {
            Ok(true) => {}
            Ok(false) => break,
            Err(error) => return Err(source.csv_error(error)),
        }
        let line = source.line(record.position().map_or(0, csv::Position::record));
        lines.push(line);
        for (column, (&field, name)) in wanted_fields.iter().zip(names).enumerate() {
            let text = &record[field];
            if column == 0 {
                first_resolution.push(printed_resolution(text));
            }
            let cell = if allow_empty && text.is_empty() {
                None
            } else {
                Some(parse_cell(path, line, name, text)?)
            };
            values[column].push(cell);
        }
    }
    Ok(OptionalFields {
        header,
        header_line,
        values,
        first_resolution,
        lines,
    })
}

/// Reads `time_s` and the selected columns of a CSV file, checking every cell and the time
/// axis. Errors name the file and line.
pub fn read_csv_columns(path: &Path, columns: Columns<'_>) -> Result<Table> {
    let (header, _) = read_header(path)?;
    let wanted: Vec<String> = match columns {
        // Every header name is requested, so `read_fields` reports any repeated one.
        Columns::All => header
            .iter()
            .filter(|name| name.as_str() != TIME_COLUMN)
            .cloned()
            .collect(),
        Columns::Named(names) => names.iter().map(|name| name.to_string()).collect(),
    };
    let mut names: Vec<&str> = vec![TIME_COLUMN];
    names.extend(wanted.iter().map(String::as_str));
    let mut fields = read_fields(path, &names)?;
    let header_line = fields.header_line;
    let lines = std::mem::take(&mut fields.lines);
    let time_resolution = std::mem::take(&mut fields.first_resolution);
    let mut columns = fields.values.into_iter();
    let time_s = columns.next().unwrap_or_default();
    let values: Vec<Vec<f64>> = columns.collect();
    let header = fields.header;

    if time_s.len() < MIN_SAMPLES {
        return Err(PostError::TooFewSamples {
            path: path.to_path_buf(),
            found: time_s.len(),
            needed: MIN_SAMPLES,
        });
    }
    // The record's print resolution is the median over its cells: "%g" drops trailing zeros
    // ("0.1" among "0.1234"), a leading "0" has no decimals at all.
    let rounding = crate::stats::median(&time_resolution).unwrap_or(0.0);
    let step_s = located_time_axis(path, &lines, &time_s, rounding)?;

    Ok(Table {
        path: path.to_path_buf(),
        header_line,
        time_s,
        step_s,
        header,
        columns: wanted.into_iter().zip(values).collect(),
    })
}

fn parse_cell(path: &Path, line: u64, column: &str, text: &str) -> Result<f64> {
    let value: f64 = text.parse().map_err(|_| PostError::NotANumber {
        path: path.to_path_buf(),
        line,
        column: column.to_string(),
        text: text.to_string(),
    })?;
    if !value.is_finite() {
        return Err(PostError::NonFinite {
            path: path.to_path_buf(),
            line,
            column: column.to_string(),
            text: text.to_string(),
        });
    }
    Ok(value)
}

/// The spacing of the decimal grid a number was printed on: `0.0125` -> 1e-4,
/// `1.5e-3` -> 1e-4, `20` -> 1. Printed values are exact to half of it.
pub(crate) fn printed_resolution(text: &str) -> f64 {
    let text = text.trim_start_matches(['+', '-']);
    let (mantissa, exponent) = match text.find(['e', 'E']) {
        Some(at) => (&text[..at], text[at + 1..].parse::<i32>().unwrap_or(0)),
        None => (text, 0),
    };
    let decimals = mantissa.find('.').map_or(0, |dot| mantissa.len() - dot - 1) as i32;
    10f64.powi(exponent - decimals)
}

enum TimeFault {
    NotIncreasing {
        index: usize,
    },
    NonUniform {
        index: usize,
        step_s: f64,
        median_step_s: f64,
    },
}

/// [`check_time_axis`] for time stamps read from the lines `lines` of a text file
/// (`lines[i]` holds sample `i`): a fault is an error naming the file and the line.
pub(crate) fn located_time_axis(
    path: &Path,
    lines: &[u64],
    time_s: &[f64],
    rounding: f64,
) -> Result<f64> {
    let line = |index: usize| lines.get(index).copied().unwrap_or(index as u64 + 1);
    check_time_axis(time_s, rounding).map_err(|fault| match fault {
        TimeFault::NotIncreasing { index } => PostError::TimeNotIncreasing {
            path: path.to_path_buf(),
            line: line(index),
            time: time_s[index],
            previous: time_s[index - 1],
        },
        TimeFault::NonUniform {
            index,
            step_s,
            median_step_s,
        } => PostError::NonUniformTime {
            path: path.to_path_buf(),
            line: line(index),
            step_s,
            median_step_s,
            tolerance_percent: STEP_TOLERANCE * 100.0,
        },
    })
}

/// Checks a time axis; returns the mean step. `rounding` is the resolution to which the times
/// were printed (0 for exact values).
fn check_time_axis(time_s: &[f64], rounding: f64) -> std::result::Result<f64, TimeFault> {
    for index in 1..time_s.len() {
        if time_s[index] <= time_s[index - 1] {
            return Err(TimeFault::NotIncreasing { index });
        }
    }
    let n = time_s.len();
    let steps: Vec<f64> = time_s.windows(2).map(|w| w[1] - w[0]).collect();
    // The median step is the sampling step even when a few samples are missing.
    let median_step_s = crate::stats::median(&steps).unwrap_or(0.0);
    // Two printed times are each within half their resolution of the truth, so a step is
    // within one resolution; capped so that a dropped sample (an error of one whole step) is
    // always caught.
    let tolerance = STEP_TOLERANCE * median_step_s + rounding.min(0.45 * median_step_s);
    for (offset, step_s) in steps.iter().enumerate() {
        if (step_s - median_step_s).abs() > tolerance {
            return Err(TimeFault::NonUniform {
                index: offset + 1,
                step_s: *step_s,
                median_step_s,
            });
        }
    }
    Ok((time_s[n - 1] - time_s[0]) / (n - 1) as f64)
}

/// Checks an in-memory signal (equal lengths, finite values, at least [`MIN_SAMPLES`],
/// uniform increasing time) and returns its mean step, seconds.
fn uniform_step(time_s: &[f64], values: &[f64]) -> Result<f64> {
    if time_s.len() != values.len() {
        return Err(PostError::InvalidSignal {
            index: time_s.len().min(values.len()),
            what: format!(
                "time has {} samples but the signal has {}; expected equal lengths",
                time_s.len(),
                values.len()
            ),
        });
    }
    if time_s.len() < MIN_SAMPLES {
        return Err(PostError::InvalidSignal {
            index: time_s.len(),
            what: format!("{} samples; need at least {MIN_SAMPLES}", time_s.len()),
        });
    }
    check_finite(time_s, values)?;
    check_time_axis(time_s, 0.0).map_err(|fault| match fault {
        TimeFault::NotIncreasing { index } => PostError::InvalidSignal {
            index,
            what: format!(
                "time {} s does not increase (previous {} s)",
                time_s[index],
                time_s[index - 1]
            ),
        },
        TimeFault::NonUniform {
            index,
            step_s,
            median_step_s,
        } => PostError::InvalidSignal {
            index,
            what: format!(
                "time step {step_s:e} s differs from the median step {median_step_s:e} s by more than {}%; expected uniform sampling",
                STEP_TOLERANCE * 100.0
            ),
        },
    })
}

/// The first sample whose time or value is not finite, as an error.
fn check_finite(time_s: &[f64], values: &[f64]) -> Result<()> {
    for (index, (t, x)) in time_s.iter().zip(values).enumerate() {
        if !t.is_finite() || !x.is_finite() {
            return Err(PostError::InvalidSignal {
                index,
                what: format!("time {t} s, value {x}: expected finite numbers"),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(folder: &Path, name: &str, text: &str) -> PathBuf {
        let path = folder.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn printed_resolution_follows_the_text() {
        assert_eq!(printed_resolution("20"), 1.0);
        assert!((printed_resolution("0.0125") - 1e-4).abs() < 1e-18);
        assert!((printed_resolution("1.5e-3") - 1e-4).abs() < 1e-18);
        assert!((printed_resolution("-2.50E+1") - 0.1).abs() < 1e-15);
    }

    #[test]
    fn rounded_print_of_1024_hz_passes_but_a_dropped_sample_fails() {
        let n = 200;
        let texts: Vec<String> = (0..n)
            .map(|i| format!("{:.4}", i as f64 / 1024.0))
            .collect();
        let time: Vec<f64> = texts.iter().map(|t| t.parse().unwrap()).collect();
        assert!(check_time_axis(&time, 1e-4).is_ok());
        assert!(check_time_axis(&time, 0.0).is_err());

        let mut dropped = time.clone();
        dropped.remove(120);
        match check_time_axis(&dropped, 1e-4) {
            Err(TimeFault::NonUniform { index, .. }) => assert_eq!(index, 120),
            _ => panic!("a dropped sample must be reported at the gap"),
        }
    }

    #[test]
    fn uniform_step_rejects_bad_slices() {
        assert!(uniform_step(&[0.0, 1.0, 2.0], &[1.0, 2.0]).is_err());
        assert!(uniform_step(&[0.0, 1.0, 2.0], &[1.0, f64::NAN, 2.0]).is_err());
        assert!(uniform_step(&[0.0, 1.0, 1.0], &[1.0, 2.0, 3.0]).is_err());
        assert!(uniform_step(&[0.0, 1.0, 3.0, 4.0], &[1.0, 2.0, 3.0, 4.0]).is_err());
        let step = uniform_step(&[0.0, 0.5, 1.0, 1.5], &[1.0, 2.0, 3.0, 4.0]);
        assert!(matches!(step, Ok(s) if (s - 0.5).abs() < 1e-15));
    }

    #[test]
    fn reads_every_column_with_comments_spaces_and_a_byte_order_mark() {
        let folder = tempfile::tempdir().unwrap();
        let path = write(
            folder.path(),
            "history.csv",
            "# coil-solve history\n\u{feff}time_s, node12_uz_accel_m_s2 ,node12_uz_disp_mm\n\
             0.000, 1.0, -12.5\n0.001, 2.0, -12.4\n\n0.002, 3.0, -12.3\n",
        );
        let table = read_csv(&path).unwrap();
        assert_eq!(table.header_line, 2);
        assert_eq!(
            table.header,
            ["time_s", "node12_uz_accel_m_s2", "node12_uz_disp_mm"]
        );
        assert_eq!(
            table.column("node12_uz_accel_m_s2").unwrap(),
            [1.0, 2.0, 3.0]
        );
        assert!((table.step_s - 0.001).abs() < 1e-15);
        match table.column("accel") {
            Err(PostError::MissingColumn {
                line, available, ..
            }) => {
                assert_eq!(line, 2);
                assert_eq!(available.len(), 3);
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn named_columns_ignore_other_cells_but_duplicates_are_errors() {
        let folder = tempfile::tempdir().unwrap();
        let path = write(
            folder.path(),
            "mixed.csv",
            "time_s,accel_m_s2,note\n0,1,start\n0.5,2,\n1.0,3,end\n",
        );
        assert!(read_csv(&path).is_err());
        let signal = read_signal(&path, "accel_m_s2").unwrap();
        assert_eq!(signal.values, [1.0, 2.0, 3.0]);
        let only = read_signal_or_only(&path, None);
        assert!(matches!(only, Err(PostError::AmbiguousColumn { .. })));

        let twice = write(
            folder.path(),
            "twice.csv",
            "time_s,a,a\n0,1,1\n1,2,2\n2,3,3\n",
        );
        let error = read_signal(&twice, "a").unwrap_err();
        assert!(
            matches!(
                error,
                PostError::DuplicateColumn {
                    first: 2,
                    second: 3,
                    ..
                }
            ),
            "{error}"
        );
    }
}
