//! What a case says about a record ([`RecordSpec`]), a record as read ([`Record`]), and
//! the checks every format's reader shares: the unit a channel is in (the file's label
//! against the case's), increasing and uniform time stamps, enough finite samples.
//! Errors are [`PostError::Record`] naming the file, where in it, and what was expected.

use std::path::{Path, PathBuf};

use super::units::{self, Quantity};
use crate::error::{PostError, Result};

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
