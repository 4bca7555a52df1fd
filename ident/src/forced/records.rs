//! Forced records: the `records.forced` entries of a case (docs/measured-case.md) and the
//! input and output histories they name, read by the record readers of `coil-postproc`
//! (CSV dialects: delimiter, decimal comma, comment lines) in the units the case states.
//!
//! A forced record is uniformly sampled (steps within 1 % of their median, beyond the time
//! stamps' print rounding), every input sample finite, its output as long as its input.
//! Errors name the file, the line or the case's field, and what was expected; nothing is
//! computed before every record of the case is read and checked.

use super::model::{InputQuantity, OutputQuantity};
use crate::error::{Result, TuneError};
use coil_tuner::case::{case_file, read_json, CaseError};
use coil_tuner::fields::{root, Field, FieldError, Object, Range};
use std::path::{Path, PathBuf};

/// A forced record entry of a case.
#[derive(Debug, Clone, PartialEq)]
pub struct ForcedEntry {
    /// The file, resolved inside the case folder.
    pub file: PathBuf,
    /// The time column (s).
    pub time: String,
    /// The input column.
    pub input: String,
    /// The output column.
    pub output: String,
    /// What the input is.
    pub input_quantity: InputQuantity,
    /// What the output is.
    pub output_quantity: OutputQuantity,
    /// The input's unit label.
    pub input_unit: String,
    /// The output's unit label.
    pub output_unit: String,
}

/// A forced record read and checked.
#[derive(Debug, Clone)]
pub struct ForcedRecord {
    /// Its entry.
    pub entry: ForcedEntry,
    /// The format, in words.
    pub format: String,
    /// The sample interval, s.
    pub dt: f64,
    /// The first time stamp, s.
    pub t0: f64,
    /// The time stamps as read, s.
    pub time_s: Vec<f64>,
    /// Input samples.
    pub input: Vec<f64>,
    /// Output samples (as many as the input's).
    pub output: Vec<f64>,
}

/// A case with forced records.
#[derive(Debug, Clone)]
pub struct ForcedCase {
    /// The case file.
    pub file: PathBuf,
    /// The case's name.
    pub name: String,
    /// Whether the case gives a spring (the lumped model then stands for its first mode).
    pub has_spring: bool,
    /// The weight's nominal mass, kg, when given.
    pub mass_kg: Option<f64>,
    /// The records.
    pub records: Vec<ForcedRecord>,
}

/// Whether the case at `path` lists forced records (a non-empty `records.forced`).
pub fn lists_forced(path: &Path) -> Result<bool> {
    let file = case_file(path);
    let (_, node) = read_json(&file)?;
    let top = root(&file, &node);
    let doc = top
        .object("a measured case (see docs/measured-case.md)")
        .map_err(CaseError::from)?;
    let Some(records) = doc.get("records") else {
        return Ok(false);
    };
    let records = records
        .object("the record files")
        .map_err(CaseError::from)?;
    Ok(match records.get("forced") {
        None => false,
        Some(f) => f.node.value != coil_tuner::json::Value::Null,
    })
}

fn field_error(e: FieldError) -> TuneError {
    TuneError::Case(CaseError::Field(e))
}

/// Reads a case's forced records, checked (module docs).
pub fn read_forced_case(path: &Path) -> Result<ForcedCase> {
    let file = case_file(path);
    let (_, node) = read_json(&file)?;
    let top = root(&file, &node);
    let doc = top
        .object("a measured case (see docs/measured-case.md)")
        .map_err(field_error)?;
    let folder = file.parent().map(Path::to_path_buf).unwrap_or_default();
    let name = doc
        .string("name", "the case's name (a non-empty string)")
        .map_err(field_error)?;
    let mass_kg = doc
        .opt_number(
            "mass_kg",
            Range::Positive,
            "the weight's nominal mass in kg",
        )
        .map_err(field_error)?;
    let records = doc
        .require("records", "the record files (an object)")
        .and_then(|r| r.object("the record files"))
        .map_err(field_error)?;
    let forced = records
        .require("forced", "a list of forced record entries")
        .map_err(field_error)?;
    let list = forced
        .array("a list of forced record entries")
        .map_err(field_error)?;
    if list.is_empty() {
        return Err(field_error(forced.error(
            "the list is empty",
            "at least one forced record entry {file, time, input, output, ...}",
        )));
    }
    let mut out = Vec::new();
    for item in &list {
        let entry = entry(&folder, item).map_err(field_error)?;
        out.push(read_record(&entry, None)?.0);
    }
    Ok(ForcedCase {
        name,
        has_spring: doc.get("spring").is_some(),
        mass_kg,
        records: out,
        file,
    })
}

fn entry(folder: &Path, item: &Field<'_>) -> std::result::Result<ForcedEntry, FieldError> {
    let o: Object<'_> = item.object(
        "a forced record entry {file, time, input, output, input_quantity, output_quantity, \
         input_unit, output_unit}",
    )?;
    let rel = o.string("file", "the record's file, relative to the case folder")?;
    let file = coil_io::resolve_inside(folder, &rel).map_err(|e| {
        o.require("file", "")
            .map(|f| {
                f.error(
                    e.to_string(),
                    "a record file inside the case folder (relative, no `..`)",
                )
            })
            .unwrap_or_else(|e| e)
    })?;
    let input_quantity = quantity(
        &o,
        "input_quantity",
        "\"force\" or \"base_acceleration\"",
        InputQuantity::from_name,
    )?;
    let output_quantity = quantity(
        &o,
        "output_quantity",
        "\"displacement\", \"velocity\" or \"acceleration\"",
        OutputQuantity::from_name,
    )?;
    Ok(ForcedEntry {
        file,
        time: o
            .opt_string("time", "the time column (s)")?
            .unwrap_or_else(|| "time_s".into()),
        input: o.string(
            "input",
            "the input column (the force or the base's acceleration)",
        )?,
        output: o.string("output", "the output column (the weight's motion)")?,
        input_quantity,
        output_quantity,
        input_unit: o.string("input_unit", "the input's unit label, e.g. \"N\" or \"V\"")?,
        output_unit: o.string(
            "output_unit",
            "the output's unit label, e.g. \"m\" or \"V\"",
        )?,
    })
}

fn quantity<T>(
    o: &Object<'_>,
    key: &str,
    expected: &str,
    parse: impl Fn(&str) -> Option<T>,
) -> std::result::Result<T, FieldError> {
    let field = o.require(key, expected)?;
    let name = field.string(expected)?;
    parse(name).ok_or_else(|| field.error(format!("found the string \"{name}\""), expected))
}

/// Reads the record `entry` names. With `head = Some(n)`, only the first `n` output cells
/// are read (they must be numbers) and the rest of the output column is ignored (it may be
/// empty); the record's `output` then holds those `n` values. Returns the record and the
/// number of output values read.
pub fn read_record(entry: &ForcedEntry, head: Option<usize>) -> Result<(ForcedRecord, usize)> {
    let path = &entry.file;
    let post = |e: coil_postproc::PostError| TuneError::Post {
        context: "reading a forced record".into(),
        source: e,
    };
    let names = [
        entry.time.as_str(),
        entry.input.as_str(),
        entry.output.as_str(),
    ];
    let (fields, format) =
        coil_postproc::record::dialect::read_columns(path, &names).map_err(post)?;
    let fail = |line: u64, problem: String, expected: &str| {
        TuneError::Invalid(format!(
            "{}:{line}: {problem}; expected {expected}",
            path.display()
        ))
    };
    let rows = fields.lines.len();
    if rows < 8 {
        return Err(fail(
            fields.header_line,
            format!("{rows} data rows"),
            "a forced record of many samples (8 at least)",
        ));
    }
    let mut columns = fields.values.into_iter();
    let (time, input, output) = (
        columns.next().unwrap_or_default(),
        columns.next().unwrap_or_default(),
        columns.next().unwrap_or_default(),
    );
    let mut t = Vec::with_capacity(rows);
    let mut u = Vec::with_capacity(rows);
    for (i, (ti, ui)) in time.iter().zip(&input).enumerate() {
        let line = fields.lines[i];
        let ti = ti.ok_or_else(|| {
            fail(
                line,
                format!("an empty `{}` cell", entry.time),
                "a time stamp in s",
            )
        })?;
        let ui = ui.ok_or_else(|| {
            fail(
                line,
                format!(
                    "an empty `{}` cell: the input column is shorter than the time column",
                    entry.input
                ),
                "an input sample on every row (input and output of equal length)",
            )
        })?;
        t.push(ti);
        u.push(ui);
    }
    let wanted = head.unwrap_or(rows);
    if wanted > rows {
        return Err(fail(
            fields.header_line,
            format!("{wanted} initial output samples asked for, but the record has {rows} rows"),
            "--init no longer than the record",
        ));
    }
    let mut y = Vec::with_capacity(wanted);
    for (i, yi) in output.iter().take(wanted).enumerate() {
        let line = fields.lines[i];
        let yi = yi.ok_or_else(|| {
            fail(
                line,
                format!(
                    "an empty `{}` cell at row {} of {rows}: the output column is shorter than \
                     the input column",
                    entry.output,
                    i + 1
                ),
                if head.is_some() {
                    "the first --init output samples given"
                } else {
                    "input and output of the same length (an output sample on every row)"
                },
            )
        })?;
        y.push(yi);
    }
    let dt = check_uniform(&t, &fields.lines, &fields.first_resolution)
        .map_err(|(line, problem)| fail(line, problem, "uniformly sampled time stamps"))?;
    Ok((
        ForcedRecord {
            entry: entry.clone(),
            format,
            dt,
            t0: t[0],
            time_s: t,
            input: u,
            output: y,
        },
        wanted,
    ))
}

/// The step of uniformly sampled time stamps, or the line and what is wrong.
fn check_uniform(
    t: &[f64],
    lines: &[u64],
    resolution: &[f64],
) -> std::result::Result<f64, (u64, String)> {
    let n = t.len();
    let dt = (t[n - 1] - t[0]) / (n - 1) as f64;
    let rounding = coil_postproc::stats::median(resolution).unwrap_or(0.0);
    for (i, w) in t.windows(2).enumerate() {
        let step = w[1] - w[0];
        if step <= 0.0 {
            return Err((
                lines[i + 1],
                format!(
                    "time {} does not increase (the previous row has {})",
                    w[1], w[0]
                ),
            ));
        }
        if (step - dt).abs() > 0.01 * dt + rounding {
            return Err((
                lines[i + 1],
                format!("a time step of {step:.6e} s against the record's {dt:.6e} s"),
            ));
        }
    }
    Ok(dt)
}
