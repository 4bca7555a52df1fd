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
    let units = [entry.input_unit.as_str(), entry.output_unit.as_str()];
    let (fields, format) =
        coil_postproc::record::read_columns(path, &names, &units).map_err(post)?;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A short forced record: a sine force and a lagging displacement, 200 samples at 100 Hz.
    fn histories() -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..200).map(|i| i as f64 * 0.01).collect();
        let u = t
            .iter()
            .map(|t| (2.0 * std::f64::consts::PI * 5.0 * t).sin())
            .collect();
        let y = t
            .iter()
            .map(|t| 1e-3 * (2.0 * std::f64::consts::PI * 5.0 * t - 0.3).sin())
            .collect();
        (t, u, y)
    }

    fn entry(
        file: PathBuf,
        time: &str,
        input: &str,
        output: &str,
        output_unit: &str,
    ) -> ForcedEntry {
        ForcedEntry {
            file,
            time: time.into(),
            input: input.into(),
            output: output.into(),
            input_quantity: InputQuantity::Force,
            output_quantity: OutputQuantity::Displacement,
            input_unit: "N".into(),
            output_unit: output_unit.into(),
        }
    }

    fn uff(u: &[f64], y: &[f64], output_unit: &str) -> Vec<u8> {
        let dataset = |node, label: &str, unit: &str, values: &[f64]| coil_io::uff::Uff58 {
            description: "forced record".into(),
            name: label.into(),
            node,
            direction: 3,
            ordinate_type: 1,
            length_exponent: 0,
            ordinate_label: label.into(),
            ordinate_unit: unit.into(),
            start_s: 0.0,
            step_s: 0.01,
            values: values.to_vec(),
        };
        coil_io::uff::uff58_bytes(
            &[
                dataset(1, "force", "N", u),
                dataset(2, "displacement", output_unit, y),
            ],
            false,
        )
    }

    /// The same histories as CSV, as a MAT-file (v7, compressed) and as UFF 58 read alike;
    /// a UFF dataset in another unit than the case's, or MAT variables of different
    /// lengths, are refused naming the dataset or variable.
    #[test]
    fn forced_records_read_alike_from_csv_mat_and_uff() {
        let dir = tempfile::tempdir().unwrap();
        let (t, u, y) = histories();
        let mut csv = String::from("time_s,force_n,disp_m\n");
        for i in 0..t.len() {
            csv.push_str(&format!("{},{:e},{:e}\n", t[i], u[i], y[i]));
        }
        std::fs::write(dir.path().join("r.csv"), csv).unwrap();
        let doubles = |v: &[f64]| coil_postproc::record::mat::doubles(v);
        let (bt, bu, by) = (doubles(&t), doubles(&u), doubles(&y));
        let mat = coil_postproc::record::mat::level5_bytes(
            &[
                ("t", 9, &bt, t.len()),
                ("f", 9, &bu, u.len()),
                ("x", 9, &by, y.len()),
            ],
            true,
        );
        std::fs::write(dir.path().join("r.mat"), mat).unwrap();
        std::fs::write(dir.path().join("r.uff"), uff(&u, &y, "m")).unwrap();
        let read = |e: ForcedEntry| read_record(&e, None).map(|(r, _)| r);
        let csv = read(entry(
            dir.path().join("r.csv"),
            "time_s",
            "force_n",
            "disp_m",
            "m",
        ))
        .unwrap();
        let mat = read(entry(dir.path().join("r.mat"), "t", "f", "x", "m")).unwrap();
        let uff_record = read(entry(
            dir.path().join("r.uff"),
            "time_s",
            "1:3",
            "2:+3",
            "m",
        ))
        .unwrap();
        assert!(mat.format.starts_with("MAT-file"), "{}", mat.format);
        assert!(
            uff_record.format.starts_with("UFF"),
            "{}",
            uff_record.format
        );
        for r in [&mat, &uff_record] {
            assert_eq!(r.input.len(), csv.input.len());
            assert!((r.dt - csv.dt).abs() < 1e-12, "{} {}", r.dt, csv.dt);
            for (a, b) in r
                .input
                .iter()
                .zip(&csv.input)
                .chain(r.output.iter().zip(&csv.output))
            {
                // The CSV and the ASCII UFF carry 12 to 13 significant digits.
                assert!((a - b).abs() <= 1e-11 * b.abs().max(1e-3), "{a} {b}");
            }
        }
        // --init reads only the first outputs, whatever the format.
        let (head, n) = read_record(
            &entry(dir.path().join("r.uff"), "t", "1:3", "2:3", "m"),
            Some(20),
        )
        .unwrap();
        assert_eq!((head.output.len(), n), (20, 20));
        // The UFF states mm where the case says m: refused, nothing converted silently.
        std::fs::write(dir.path().join("mm.uff"), uff(&u, &y, "mm")).unwrap();
        let e = read(entry(dir.path().join("mm.uff"), "t", "1:3", "2:3", "m")).unwrap_err();
        assert!(e.to_string().contains("mismatched units"), "{e}");
        // A channel that is not in the file names the ones that are.
        let e = read(entry(dir.path().join("r.uff"), "t", "1:3", "9:3", "m")).unwrap_err();
        assert!(e.to_string().contains("node 2"), "{e}");
        // MAT variables of different lengths, or a missing one.
        let short = coil_postproc::record::mat::level5_bytes(
            &[
                ("t", 9, &bt, t.len()),
                ("f", 9, &bu, u.len()),
                ("x", 9, &by[..80], 10),
            ],
            false,
        );
        std::fs::write(dir.path().join("short.mat"), short).unwrap();
        let e = read(entry(dir.path().join("short.mat"), "t", "f", "x", "m")).unwrap_err();
        assert!(e.to_string().contains("10 samples against 200"), "{e}");
        let e = read(entry(dir.path().join("r.mat"), "time", "f", "x", "m")).unwrap_err();
        assert!(e.to_string().contains("no such variable"), "{e}");
    }
}
