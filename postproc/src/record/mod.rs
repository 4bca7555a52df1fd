//! Measured records as labs store them: one reader for every command that reads a decay
//! record (`coil-tune diagnose`, `damping`, `calibrate`, `paper`) and for the Python
//! package.
//!
//! # Formats (recognised by content, not by name)
//! - **UFF dataset 58 / 58b** ([`uff`]): a file whose first non-blank line is `-1`.
//!   Function type 1 (time response), real ordinate, even or uneven abscissa; units from
//!   the dataset's unit labels and data types, scaled by dataset 164 when present.
//! - **MATLAB level 5** ([`mat`]): v6 and v7 (compressed) numeric arrays. v7.3 files
//!   (HDF5) are refused with a message saying to save them with `-v7`.
//! - **CSV dialects** ([`dialect`]): delimiter (`,` `;` tab `|` blanks) and decimal comma
//!   detected, comment lines (`#`, `%`, `//`) skipped, units read from the header
//!   (`Time [s]`, `a (g)`) or from coil's column names (`time_s`, `accel_m_s2`).
//!   [`Record::format`] states what was detected.
//!
//! # What the case says
//! A [`RecordSpec`] is the case's record entry: the file, and optionally the `channel` (a
//! UFF dataset's index, counted from 1 among the file's datasets 58, or its
//! `node:direction`; a `.mat` variable; a CSV column), the `time` variable of a `.mat`
//! file, the `quantity` and the `unit`. The file's own units are used where it states
//! them; a case that states another unit for the same channel is an error (which one is
//! right cannot be guessed), and so is a channel whose unit neither states.
//!
//! # Units
//! Every value leaves here in SI: m, m/s, m/s^2, s ([`units`]). A record in g is scaled by
//! g_n = 9.80665 m/s^2; a record in mm by 1e-3.

pub mod dialect;
pub mod mat;
pub mod uff;
pub mod units;

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::error::{PostError, Result};

/// What a decay record measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// Acceleration (`accel_m_s2` in coil's CSV).
    Acceleration,
    /// Velocity (`velocity_m_s`).
    Velocity,
    /// Displacement (`displacement_mm`).
    Displacement,
}

impl Quantity {
    /// Every quantity, in the order of the measured-case table.
    pub const ALL: [Quantity; 3] = [
        Quantity::Acceleration,
        Quantity::Velocity,
        Quantity::Displacement,
    ];

    /// coil's CSV column of the quantity.
    pub fn column(self) -> &'static str {
        match self {
            Quantity::Acceleration => "accel_m_s2",
            Quantity::Velocity => "velocity_m_s",
            Quantity::Displacement => "displacement_mm",
        }
    }

    /// Factor from coil's column unit to SI (mm -> m).
    pub fn to_si(self) -> f64 {
        match self {
            Quantity::Displacement => 1e-3,
            _ => 1.0,
        }
    }

    /// The SI unit.
    pub fn si_unit(self) -> &'static str {
        match self {
            Quantity::Acceleration => "m/s^2",
            Quantity::Velocity => "m/s",
            Quantity::Displacement => "m",
        }
    }

    /// How many times the record must be differentiated to give the acceleration.
    pub fn derivatives_to_acceleration(self) -> usize {
        match self {
            Quantity::Acceleration => 0,
            Quantity::Velocity => 1,
            Quantity::Displacement => 2,
        }
    }

    /// The name a case uses (`acceleration`, `velocity`, `displacement`).
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Acceleration => "acceleration",
            Quantity::Velocity => "velocity",
            Quantity::Displacement => "displacement",
        }
    }

    /// The quantity a case names, `None` for any other word.
    pub fn from_name(name: &str) -> Option<Quantity> {
        Quantity::ALL.into_iter().find(|q| q.name() == name)
    }
}

/// A record entry of a case: the file and what the case says about it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RecordSpec {
    /// The file (resolved by the caller).
    pub file: PathBuf,
    /// The channel: a UFF dataset's index (from 1) or `node:direction`, a `.mat`
    /// variable, a CSV column.
    pub channel: Option<String>,
    /// The `.mat` variable holding the time (s).
    pub time: Option<String>,
    /// What the channel measures.
    pub quantity: Option<Quantity>,
    /// Its unit label (`m/s^2`, `g`, `mm`, ...).
    pub unit: Option<String>,
}

impl RecordSpec {
    /// A plain file name: the file states its channel and units.
    pub fn file(path: impl Into<PathBuf>) -> RecordSpec {
        RecordSpec {
            file: path.into(),
            ..RecordSpec::default()
        }
    }
}

/// A record read: one channel in SI on its time stamps as read.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// The file.
    pub file: PathBuf,
    /// The format as detected, in words (e.g. `CSV: delimiter ';', decimal comma`).
    pub format: String,
    /// The channel read (column, variable, or `dataset 2 (node 10, direction 3)`).
    pub channel: String,
    /// What it measures.
    pub quantity: Quantity,
    /// The unit the values were stated in (the file's or the case's label).
    pub unit: String,
    /// Time stamps, s (increasing).
    pub time_s: Vec<f64>,
    /// The values in SI (m/s^2, m/s or m).
    pub values: Vec<f64>,
    /// Where each sample sits, for messages: its line in a text file, else its number
    /// (from 1).
    pub lines: Vec<u64>,
    /// The decimal grid the time stamps were printed on (0 when stored exactly).
    pub time_resolution_s: f64,
}

/// Which format a file holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// UFF (datasets 58, 58b, 164).
    Uff,
    /// MATLAB level 5 MAT-file.
    Mat,
    /// MATLAB v7.3 MAT-file (HDF5).
    MatHdf5,
    /// Text with columns.
    Csv,
}

/// The format of a file's bytes.
pub fn detect(bytes: &[u8]) -> Format {
    const HDF5: &[u8] = b"\x89HDF\r\n\x1a\n";
    if bytes.starts_with(HDF5) || bytes.get(512..520) == Some(HDF5) {
        return Format::MatHdf5;
    }
    if bytes.starts_with(b"MATLAB") {
        let text = String::from_utf8_lossy(&bytes[..bytes.len().min(116)]);
        if text.contains("MAT-file, Platform") && text.contains("7.3") {
            return Format::MatHdf5;
        }
        return Format::Mat;
    }
    // A UTF-8 byte order mark (as Windows editors save) is not part of the first line.
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let first = bytes
        .split(|&b| b == b'\n')
        .map(|l| String::from_utf8_lossy(l).trim().to_string())
        .find(|l| !l.is_empty());
    if first.as_deref() == Some("-1") {
        return Format::Uff;
    }
    Format::Csv
}

/// Reads the record `spec` names, in SI.
pub fn read_record(spec: &RecordSpec) -> Result<Record> {
    let path = &spec.file;
    let bytes = coil_io::confine::read_bounded_bytes(path, coil_io::MAX_RECORD_BYTES, "a record")?;
    match detect(&bytes) {
        Format::Uff => uff::read(spec, &bytes),
        Format::Mat => mat::read(spec, &bytes),
        Format::MatHdf5 => Err(fail(
            path,
            "1",
            "a MATLAB v7.3 MAT-file (HDF5), which coil does not read".to_string(),
            "a level 5 MAT-file: in MATLAB, save it again with `save(name, '-v7')`",
        )),
        Format::Csv => dialect::read(spec, bytes),
    }
}

/// A record of acceleration as a checked [`crate::signal::Signal`] named by its file and
/// channel (its time stamps uniform within the tolerance and their print rounding); a
/// velocity or displacement record is an error naming the file.
pub fn acceleration_signal(record: Record) -> Result<crate::signal::Signal> {
    if record.quantity != Quantity::Acceleration {
        return Err(fail(
            &record.file,
            "1",
            format!(
                "a {} record (channel `{}`)",
                record.quantity.name(),
                coil_io::excerpt(&record.channel)
            ),
            "an acceleration record (`accel_m_s2`) for this command",
        ));
    }
    let signal =
        crate::signal::Signal::printed(record.time_s, record.values, record.time_resolution_s)
            .map_err(|e| PostError::Analysis {
                path: record.file.clone(),
                column: record.channel.clone(),
                error: Box::new(e),
            })?;
    Ok(signal.named(record.file, record.channel))
}

/// The error for a `time` entry on a file that carries its own abscissa.
pub(crate) fn no_time_variable(spec: &RecordSpec) -> Result<()> {
    match spec.time {
        None => Ok(()),
        Some(_) => Err(fail(
            &spec.file,
            "1",
            "the case names a `time` variable, but the file carries its own abscissa".into(),
            "`time` only for a `.mat` file (remove it from the record entry)",
        )),
    }
}

/// A [`PostError::Record`].
pub(crate) fn fail(path: &Path, at: &str, problem: String, expected: &str) -> PostError {
    PostError::Record {
        path: path.to_path_buf(),
        at: at.to_string(),
        problem,
        expected: expected.to_string(),
    }
}

/// The unit a file's own label states (`None` without a label): a label coil does not
/// know is an error naming it and the labels known, unless the case states the
/// channel's unit itself (then the case's unit is used). Never read as SI.
pub(crate) fn stated_unit(
    spec: &RecordSpec,
    at: &str,
    label: Option<&str>,
) -> Result<Option<units::Unit>> {
    let Some(label) = label.map(str::trim).filter(|l| !l.is_empty()) else {
        return Ok(None);
    };
    match units::parse(label) {
        Some(unit) => Ok(Some(unit)),
        None if spec.unit.is_some() => Ok(None),
        None => Err(fail(
            &spec.file,
            at,
            format!(
                "the file's unit `{}` is not a unit coil knows",
                coil_io::excerpt(label)
            ),
            &format!(
                "one of {} (or the record entry's `unit` for this channel)",
                units::known_labels()
            ),
        )),
    }
}

/// The unit of a channel from what the file states and what the case states (module
/// docs): an error when they disagree or when neither states one.
pub(crate) fn resolve_unit(
    spec: &RecordSpec,
    at: &str,
    file_unit: Option<units::Unit>,
) -> Result<units::Unit> {
    let path = &spec.file;
    let stated = match &spec.unit {
        None => None,
        Some(label) => Some(units::parse(label).ok_or_else(|| {
            fail(
                path,
                at,
                format!(
                    "the case's unit `{}` is not a unit coil knows",
                    coil_io::excerpt(label)
                ),
                &format!("one of {}", units::known_labels()),
            )
        })?),
    };
    let unit = match (file_unit, stated) {
        (Some(file), Some(case)) => {
            if file.quantity != case.quantity || file.to_si != case.to_si {
                return Err(fail(
                    path,
                    at,
                    format!(
                        "mismatched units: the file states `{}` ({}), the case states `{}` ({})",
                        file.label,
                        file.quantity.name(),
                        case.label,
                        case.quantity.name()
                    ),
                    "the case's `unit` equal to the file's, or no `unit` in the case (the file's is used)",
                ));
            }
            file
        }
        (Some(one), None) | (None, Some(one)) => one,
        (None, None) => {
            return Err(fail(
                path,
                at,
                "the file states no unit for this channel and the case gives none".into(),
                "`unit` (and `quantity`) in the case's record entry, e.g. {\"file\": ..., \"quantity\": \"acceleration\", \"unit\": \"m/s^2\"}",
            ))
        }
    };
    if let Some(q) = spec.quantity {
        if q != unit.quantity {
            return Err(fail(
                path,
                at,
                format!(
                    "mismatched units: the case's quantity is {} but the unit `{}` measures {}",
                    q.name(),
                    unit.label,
                    unit.quantity.name()
                ),
                "a unit of the stated quantity",
            ));
        }
    }
    Ok(unit)
}

/// Checks that stamps increase; the error names the sample.
pub(crate) fn check_increasing(path: &Path, at: &str, time_s: &[f64]) -> Result<()> {
    for i in 1..time_s.len() {
        // NaN stamps fail too.
        if time_s[i].partial_cmp(&time_s[i - 1]) != Some(std::cmp::Ordering::Greater) {
            return Err(fail(
                path,
                at,
                format!(
                    "non-uniform abscissa: sample {} at {} s does not follow {} s",
                    i + 1,
                    time_s[i],
                    time_s[i - 1]
                ),
                "increasing, uniformly spaced time stamps",
            ));
        }
    }
    Ok(())
}

/// Checks that stamps are uniform to [`crate::signal::STEP_TOLERANCE`] of the median step
/// (a stored, not printed, abscissa has no rounding to allow for).
pub(crate) fn check_uniform(path: &Path, at: &str, time_s: &[f64]) -> Result<()> {
    check_increasing(path, at, time_s)?;
    let steps: Vec<f64> = time_s.windows(2).map(|w| w[1] - w[0]).collect();
    let median = crate::stats::median(&steps).unwrap_or(0.0);
    if let Some(i) = steps
        .iter()
        .position(|s| (s - median).abs() > crate::signal::STEP_TOLERANCE * median)
    {
        return Err(fail(
            path,
            at,
            format!(
                "non-uniform abscissa: step {:e} s after sample {} against the median step {median:e} s",
                steps[i],
                i + 1
            ),
            "uniformly sampled data (steps within 5 % of the median)",
        ));
    }
    Ok(())
}

/// A record's checks once read: at least [`crate::signal::MIN_SAMPLES`] samples, finite.
pub(crate) fn finish(record: Record, at: &str) -> Result<Record> {
    let path = &record.file;
    if record.values.len() < crate::signal::MIN_SAMPLES {
        return Err(fail(
            path,
            at,
            format!("{} samples", record.values.len()),
            "a free-decay record of many samples",
        ));
    }
    if let Some(i) = record
        .values
        .iter()
        .zip(&record.time_s)
        .position(|(v, t)| !(v.is_finite() && t.is_finite()))
    {
        return Err(fail(
            path,
            at,
            format!("sample {} is not a finite number", i + 1),
            "finite numbers",
        ));
    }
    Ok(record)
}
