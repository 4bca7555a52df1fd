//! Reading a case's record files: a decay record in any format `coil_postproc::record`
//! reads (UFF 58/58b, MAT-file, CSV dialects) converted to SI, and a static
//! force-compression record (`displacement_mm,force_n`). Errors name the file, the line
//! and what was expected.

use crate::error::CaseError;
use coil_postproc::record::RecordSpec;
use std::path::{Path, PathBuf};

/// A static force-compression record (`displacement_mm,force_n`).
#[derive(Debug, Clone, PartialEq)]
pub struct StaticRecord {
    /// The file it was read from.
    pub file: PathBuf,
    /// Compression from the free length (mm, positive = shorter).
    pub displacement_mm: Vec<f64>,
    /// Axial force (N).
    pub force_n: Vec<f64>,
}

/// The format note of a record for the report: `None` for coil's own CSV (comma, decimal
/// point), else the dialect or format detected (`coil_postproc::record`).
pub fn format_note(file: &Path, format: &str) -> Option<String> {
    (!format.starts_with("CSV: delimiter ',', decimal point"))
        .then(|| format!("{}: read as {format}", file.display()))
}

/// The least-squares slope of a static record's force against its compression, N/m
/// (`None` when it is not positive).
pub(crate) fn static_slope_n_m(r: &StaticRecord) -> Option<f64> {
    let n = r.displacement_mm.len().min(r.force_n.len()) as f64;
    if n < 2.0 {
        return None;
    }
    let mx = r.displacement_mm.iter().sum::<f64>() / n;
    let my = r.force_n.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (x, y) in r.displacement_mm.iter().zip(&r.force_n) {
        sxy += (x - mx) * (y - my);
        sxx += (x - mx) * (x - mx);
    }
    let k = 1e3 * sxy / sxx;
    (k.is_finite() && k > 0.0).then_some(k)
}

/// What a decay record measures (the spec's decay.csv columns), shared with the record
/// reader.
pub use coil_postproc::record::Quantity;

/// A decay record as written: its one measured column (converted to SI) and its time
/// stamps exactly as read (increasing, finite; whether they are uniform is for the
/// diagnosis to judge, `diagnose::data`).
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredDecay {
    /// The file it was read from.
    pub file: PathBuf,
    /// What the column measures.
    pub quantity: Quantity,
    /// Time stamps (s).
    pub time_s: Vec<f64>,
    /// The measured quantity in SI (m/s^2, m/s or m).
    pub values: Vec<f64>,
    /// The file's line of each sample (for messages).
    pub lines: Vec<u64>,
    /// The printed resolution of the time stamps (s): the decimal grid they were written
    /// on (median over the cells).
    pub time_resolution_s: f64,
}

/// Reads a decay record named by a plain file name: [`read_decay`] with the file's own
/// channel and units (coil's CSV: `time_s` and exactly one of `accel_m_s2`,
/// `velocity_m_s`, `displacement_mm`; two of them is an error naming both).
pub fn read_decay_record(path: &Path) -> Result<MeasuredDecay, CaseError> {
    Ok(read_decay(&RecordSpec::file(path))?.0)
}

/// Reads a decay record in any format `coil_postproc::record` reads (UFF 58/58b,
/// MAT-file, CSV dialects), converted to SI, with its format in words. Every cell is
/// checked (finite number) and the time stamps must increase; their uniformity is checked
/// by the diagnosis, which resamples small jitter.
pub fn read_decay(spec: &RecordSpec) -> Result<(MeasuredDecay, String), CaseError> {
    let r = coil_postproc::record::read_record(spec)?;
    Ok((
        MeasuredDecay {
            file: r.file,
            quantity: r.quantity,
            time_s: r.time_s,
            values: r.values,
            lines: r.lines,
            time_resolution_s: r.time_resolution_s,
        },
        r.format,
    ))
}

/// Reads a static record: header `displacement_mm,force_n` (in either order, padded cells
/// allowed, `#` comment lines and blank lines skipped), finite numbers, at least 2 rows.
pub fn read_static_record(path: &Path) -> Result<StaticRecord, CaseError> {
    let text = coil_io::read_bounded(path, coil_io::MAX_RECORD_BYTES, "a record (CSV)")
        .map_err(CaseError::input)?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let fail = |line: usize, problem: String, expected: &str| CaseError::StaticRecord {
        path: path.to_path_buf(),
        line,
        problem,
        expected: expected.to_string(),
    };
    let mut rows = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (header_line, header) = rows.next().ok_or_else(|| {
        fail(
            1,
            "the file is empty".into(),
            "a header `displacement_mm,force_n` and data rows",
        )
    })?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let find = |name: &str| -> Result<usize, CaseError> {
        let hits: Vec<usize> = (0..names.len()).filter(|&i| names[i] == name).collect();
        match hits.as_slice() {
            [one] => Ok(*one),
            [] => Err(fail(
                header_line,
                format!(
                    "no column `{name}` in the header (columns: {})",
                    coil_io::excerpt(&names.join(", "))
                ),
                "the header `displacement_mm,force_n`",
            )),
            _ => Err(fail(
                header_line,
                format!("column `{name}` appears more than once"),
                "unique column names",
            )),
        }
    };
    let (di, fi) = (find("displacement_mm")?, find("force_n")?);
    let (mut displacement_mm, mut force_n) = (Vec::new(), Vec::new());
    for (line, row) in rows {
        let cells: Vec<&str> = row.split(',').map(str::trim).collect();
        if cells.len() != names.len() {
            return Err(fail(
                line,
                format!("{} fields", cells.len()),
                &format!("{} fields as in the header", names.len()),
            ));
        }
        for (index, column, out) in [
            (di, "displacement_mm", &mut displacement_mm),
            (fi, "force_n", &mut force_n),
        ] {
            let cell = cells[index];
            match cell.parse::<f64>() {
                Ok(x) if x.is_finite() => out.push(x),
                Ok(_) => {
                    return Err(fail(
                        line,
                        format!(
                            "column `{column}`: `{}` is not finite",
                            coil_io::excerpt(cell)
                        ),
                        "a finite number",
                    ))
                }
                Err(_) => {
                    return Err(fail(
                        line,
                        format!(
                            "column `{column}`: `{}` is not a number",
                            coil_io::excerpt(cell)
                        ),
                        "a number",
                    ))
                }
            }
        }
    }
    if displacement_mm.len() < 2 {
        return Err(fail(
            header_line,
            format!("{} data rows", displacement_mm.len()),
            "at least 2 rows of displacement and force",
        ));
    }
    Ok(StaticRecord {
        file: path.to_path_buf(),
        displacement_mm,
        force_n,
    })
}
