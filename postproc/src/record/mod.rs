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
pub mod spec;
pub mod uff;
pub mod units;

pub use spec::{Record, RecordSpec};
pub use units::Quantity;

use crate::error::{PostError, Result};
use crate::signal::Signal;
use spec::fail;

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
        Format::MatHdf5 => Err(hdf5(path)),
        Format::Csv => dialect::read(spec, bytes),
    }
}

/// The histories of a forced record in any of the formats above, as written (no unit
/// conversion: the case states the units, which may be volts or newtons): `names` is the
/// time column or variable, then the channels (CSV columns, `.mat` variables, UFF datasets
/// by index or `node:direction`, whose abscissa is the time: the time name is not read);
/// `units` the case's unit of each channel (checked against a UFF dataset's own label).
/// Returns the cells (`None` for an empty CSV cell; rows of a binary format numbered from
/// 1 as its "lines") and the format in words.
pub fn read_columns(
    path: &std::path::Path,
    names: &[&str],
    units: &[&str],
) -> Result<(crate::signal::OptionalFields, String)> {
    let bytes = coil_io::confine::read_bounded_bytes(path, coil_io::MAX_RECORD_BYTES, "a record")?;
    let (time_s, channels, format) = match detect(&bytes) {
        Format::Csv => return dialect::read_columns(path, bytes, names),
        Format::MatHdf5 => return Err(hdf5(path)),
        Format::Mat => {
            let mut columns = mat::read_columns(path, &bytes, names)?.into_iter();
            let time_s = columns.next().unwrap_or_default();
            let listed: Vec<String> = names
                .iter()
                .map(|n| format!("`{}`", coil_io::excerpt(n)))
                .collect();
            let format = format!("MAT-file level 5 (variables {})", listed.join(", "));
            (time_s, columns.collect::<Vec<_>>(), format)
        }
        Format::Uff => {
            let channels = names.get(1..).unwrap_or_default();
            let (time_s, columns) = uff::read_columns(path, &bytes, channels, units)?;
            let listed: Vec<String> = channels
                .iter()
                .map(|n| format!("`{}`", coil_io::excerpt(n)))
                .collect();
            let format = format!(
                "UFF dataset 58 (channels {}; time from the abscissa)",
                listed.join(", ")
            );
            (time_s, columns, format)
        }
    };
    let n = time_s.len();
    let values = std::iter::once(time_s)
        .chain(channels)
        .map(|c| c.into_iter().map(Some).collect())
        .collect();
    Ok((
        crate::signal::OptionalFields {
            header: names.iter().map(|n| n.to_string()).collect(),
            header_line: 1,
            values,
            first_resolution: Vec::new(),
            lines: (1..=n as u64).collect(),
        },
        format,
    ))
}

/// The refusal of a MATLAB v7.3 file.
fn hdf5(path: &std::path::Path) -> PostError {
    fail(
        path,
        "1",
        "a MATLAB v7.3 MAT-file (HDF5), which coil does not read".to_string(),
        "a level 5 MAT-file: in MATLAB, save it again with `save(name, '-v7')`",
    )
}

/// A record of acceleration as a checked [`Signal`] ([`signal_of`]); a velocity or
/// displacement record is an error naming the file.
pub fn acceleration_signal(record: Record) -> Result<Signal> {
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
    signal_of(record)
}

/// A record as a checked [`Signal`] named by its file and channel (its time stamps
/// uniform within the tolerance and their print rounding), values in SI.
pub fn signal_of(record: Record) -> Result<Signal> {
    // Stamps printed in a text file (a CSV dialect) are checked here, where the line of
    // each sample is known, so that a fault names its line.
    if record.time_resolution_s > 0.0 && record.time_s.len() >= crate::signal::MIN_SAMPLES {
        crate::signal::located_time_axis(
            &record.file,
            &record.lines,
            &record.time_s,
            record.time_resolution_s,
        )?;
    }
    let signal =
        Signal::printed(record.time_s, record.values, record.time_resolution_s).map_err(|e| {
            PostError::Analysis {
                path: record.file.clone(),
                column: record.channel.clone(),
                error: Box::new(e),
            }
        })?;
    Ok(signal.named(record.file, record.channel))
}

/// The signal of the channel `spec` names, for `coil-post`: the file is recognised by its
/// content and read through [`read_record`] like every record (a UFF or MAT-file channel,
/// a CSV file in any dialect; values in SI), except a CSV file in coil's own syntax (a
/// `time_s` column) whose entry states no `time`, `quantity` or `unit`: that one is read
/// as written ([`crate::signal::read_signal_or_only`]), any column, in its own unit (a
/// `coil-solve` history's `node12_uz_disp_mm` stays in mm).
pub fn read_signal(spec: &RecordSpec) -> Result<Signal> {
    let path = &spec.file;
    let bytes = coil_io::confine::read_bounded_bytes(path, coil_io::MAX_RECORD_BYTES, "a record")?;
    let as_written = spec.time.is_none()
        && spec.quantity.is_none()
        && spec.unit.is_none()
        && detect(&bytes) == Format::Csv
        && crate::signal::read_header_in(path, bytes)
            .is_ok_and(|(header, _)| header.iter().any(|h| h == crate::signal::TIME_COLUMN));
    if as_written {
        return crate::signal::read_signal_or_only(path, spec.channel.as_deref());
    }
    signal_of(read_record(spec)?)
}
