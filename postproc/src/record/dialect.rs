//! CSV as loggers and spreadsheets write it: the dialect is detected, stated, and the text
//! is rewritten line for line into coil's own CSV syntax, so that every cell is then read
//! and checked by [`crate::signal`] with the file's own line numbers.
//!
//! # Detection
//! - **Comment lines** start with `#`, `%` or `//` (after blanks) and are skipped, as are
//!   blank lines. The first other line is the header.
//! - **Delimiter**: the first of tab, `;`, `,`, `|` that splits the header and the first
//!   data lines (up to 20) into the same number of at least two fields; else runs of
//!   blanks when they do.
//! - **Decimal comma**: when the delimiter is not `,` and a data cell holds a comma; a
//!   cell with both a point and a comma (a thousands separator) is then an error.
//! - **Units** from the header: `Time [s]`, `a (g)`, or coil's names (`time_s`,
//!   `accel_m_s2`, `velocity_m_s`, `displacement_mm`). The time column is `time_s`, else a
//!   column in `s` or `ms`, else one named `time` or `t` (then in seconds).
//!
//! # Which column
//! The case's `channel` (the header name, with or without its unit); else exactly one of
//! coil's quantity columns; else the only column whose unit is a displacement, velocity
//! or acceleration; else the only column besides time.

use super::spec::{fail, Record, RecordSpec};
use super::units;
use crate::error::Result;
use crate::signal::TIME_COLUMN;

/// A detected dialect.
#[derive(Debug, Clone, PartialEq)]
pub struct Dialect {
    /// The delimiter (`None`: runs of blanks).
    pub delimiter: Option<char>,
    /// Decimal comma.
    pub decimal_comma: bool,
}

impl Dialect {
    /// The dialect in words, for the report.
    pub fn describe(&self) -> String {
        let d = match self.delimiter {
            Some('\t') => "tab".to_string(),
            Some(c) => format!("'{c}'"),
            None => "blanks".to_string(),
        };
        format!(
            "CSV: delimiter {d}, decimal {}",
            if self.decimal_comma { "comma" } else { "point" }
        )
    }

    /// coil's own syntax.
    pub fn is_plain(&self) -> bool {
        self.delimiter == Some(',') && !self.decimal_comma
    }
}

fn is_comment(line: &str) -> bool {
    let t = line.trim_start();
    t.starts_with('#') || t.starts_with('%') || t.starts_with("//")
}

fn split(line: &str, delimiter: Option<char>) -> Vec<&str> {
    match delimiter {
        Some(c) => line.split(c).map(str::trim).collect(),
        None => line.split_whitespace().collect(),
    }
}

/// Detects the dialect of a text's header and first data lines.
pub fn detect(text: &str) -> Dialect {
    let lines: Vec<&str> = text
        .lines()
        .filter(|l| !l.trim().is_empty() && !is_comment(l))
        .take(21)
        .collect();
    let consistent = |d: Option<char>| {
        let counts: Vec<usize> = lines.iter().map(|l| split(l, d).len()).collect();
        counts
            .first()
            .is_some_and(|&n| n >= 2 && counts.iter().all(|&c| c == n))
    };
    let delimiter = ['\t', ';', ',', '|']
        .into_iter()
        .map(Some)
        .find(|&d| consistent(d))
        .or_else(|| consistent(None).then_some(None))
        .unwrap_or(Some(','));
    let decimal_comma = delimiter != Some(',')
        && lines
            .iter()
            .skip(1)
            .any(|l| split(l, delimiter).iter().any(|c| c.contains(',')));
    Dialect {
        delimiter,
        decimal_comma,
    }
}

/// The text rewritten into coil's syntax, line for line (comments as `#`).
fn rewrite(path: &std::path::Path, text: &str, dialect: &Dialect) -> Result<String> {
    let mut out = String::with_capacity(text.len() + 64);
    let mut header_done = false;
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            out.push('\n');
            continue;
        }
        if is_comment(line) {
            out.push_str("#\n");
            continue;
        }
        let cells = split(line, dialect.delimiter);
        let mut fields = Vec::with_capacity(cells.len());
        for cell in cells {
            let cell = cell.trim_matches('"');
            if !header_done {
                fields.push(format!("\"{}\"", cell.replace('"', "")));
                continue;
            }
            if dialect.decimal_comma {
                if cell.contains('.') && cell.contains(',') {
                    return Err(fail(
                        path,
                        &(i + 1).to_string(),
                        format!(
                            "`{}` holds both a point and a comma",
                            coil_io::excerpt(cell)
                        ),
                        "numbers with a decimal comma and no thousands separator",
                    ));
                }
                fields.push(cell.replace(',', "."));
            } else {
                fields.push(cell.to_string());
            }
        }
        header_done = true;
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    Ok(out)
}

/// A CSV file's bytes as coil's own CSV (comma, decimal point, `#` comments) and the dialect
/// they were written in.
fn normalise(path: &std::path::Path, bytes: Vec<u8>) -> Result<(String, Dialect)> {
    let raw = match String::from_utf8(bytes) {
        Ok(text) => text,
        // Latin-1 exports (a `°` or `µ` in a header) are read as such.
        Err(e) => e.into_bytes().iter().map(|&b| b as char).collect(),
    };
    let text = raw.strip_prefix('\u{feff}').unwrap_or(&raw);
    let dialect = detect(text);
    let other_comments = text.lines().any(|l| is_comment(l) && !l.starts_with('#'));
    let normalised = if dialect.is_plain() && !other_comments {
        text.to_string()
    } else {
        rewrite(path, text, &dialect)?
    };
    Ok((normalised, dialect))
}

/// Reads the channel `spec` names from a CSV file's bytes (any dialect).
pub fn read(spec: &RecordSpec, bytes: Vec<u8>) -> Result<Record> {
    super::spec::no_time_variable(spec)?;
    let path = spec.file.as_path();
    let (normalised, dialect) = normalise(path, bytes)?;
    let (header, header_line) =
        crate::signal::read_header_in(path, normalised.clone().into_bytes())?;
    let fail_at =
        |problem: String, expected: &str| fail(path, &header_line.to_string(), problem, expected);
    let parsed: Vec<(String, Option<String>)> =
        header.iter().map(|h| units::split_name(h)).collect();
    // The time column.
    let time_index = header
        .iter()
        .position(|h| h == TIME_COLUMN)
        .or_else(|| {
            parsed
                .iter()
                .position(|(_, u)| u.as_deref().and_then(units::time_factor).is_some())
        })
        .or_else(|| {
            parsed
                .iter()
                .position(|(n, u)| u.is_none() && matches!(n.to_lowercase().as_str(), "time" | "t"))
        })
        .ok_or_else(|| {
            fail_at(
                format!(
                    "no time column in the header (columns: {})",
                    header.join(", ")
                ),
                "`time_s`, or a column in s or ms such as `Time [s]`",
            )
        })?;
    let time_factor = parsed[time_index]
        .1
        .as_deref()
        .and_then(units::time_factor)
        .unwrap_or(1.0);
    let others: Vec<usize> = (0..header.len()).filter(|&i| i != time_index).collect();
    let column = match &spec.channel {
        Some(c) => others
            .iter()
            .copied()
            .find(|&i| header[i] == *c || parsed[i].0.eq_ignore_ascii_case(c.trim()))
            .ok_or_else(|| {
                fail_at(
                    format!(
                        "no column `{}` (columns: {})",
                        coil_io::excerpt(c),
                        header.join(", ")
                    ),
                    "the record entry's `channel` naming a column of the header",
                )
            })?,
        None => choose_column(&header, &parsed, &others, spec.unit.is_some())
            .map_err(|(problem, expected)| fail_at(problem, &expected))?,
    };
    let at = header_line.to_string();
    let file_unit = parsed[column].1.as_deref().and_then(units::parse);
    if let (None, Some(label)) = (&file_unit, &parsed[column].1) {
        if spec.unit.is_none() {
            return Err(fail_at(
                format!(
                    "the header's unit `{}` of `{}` is not a unit coil knows",
                    coil_io::excerpt(label),
                    coil_io::excerpt(&header[column])
                ),
                &format!("one of {}", units::known_labels()),
            ));
        }
    }
    let unit = super::spec::resolve_unit(spec, &at, file_unit)?;
    let names = [header[time_index].as_str(), header[column].as_str()];
    let fields = crate::signal::read_fields_in(path, normalised.into_bytes(), &names)?;
    let mut columns = fields.values.into_iter();
    let time_s: Vec<f64> = columns
        .next()
        .unwrap_or_default()
        .into_iter()
        .map(|t| t * time_factor)
        .collect();
    let values: Vec<f64> = columns
        .next()
        .unwrap_or_default()
        .into_iter()
        .map(|v| v * unit.to_si)
        .collect();
    if time_s.len() < crate::signal::MIN_SAMPLES {
        return Err(fail_at(
            format!("{} data rows", time_s.len()),
            "a free-decay record of many samples",
        ));
    }
    for i in 1..time_s.len() {
        if time_s[i] <= time_s[i - 1] {
            return Err(fail(
                path,
                &fields.lines[i].to_string(),
                format!(
                    "{} {} does not increase (the previous row has {})",
                    header[time_index],
                    time_s[i] / time_factor,
                    time_s[i - 1] / time_factor
                ),
                "increasing time stamps",
            ));
        }
    }
    let resolution = crate::stats::median(&fields.first_resolution).unwrap_or(0.0) * time_factor;
    let mut format = dialect.describe();
    format.push_str(&format!(
        ", header line {header_line}, time `{}`, channel `{}` in {}",
        coil_io::excerpt(&header[time_index]),
        coil_io::excerpt(&header[column]),
        unit.label
    ));
    Ok(Record {
        file: path.to_path_buf(),
        format,
        channel: header[column].clone(),
        quantity: unit.quantity,
        unit: unit.label,
        time_s,
        values,
        lines: fields.lines,
        time_resolution_s: resolution,
    })
}

/// Reads the columns `names` of a CSV file's bytes of any dialect as written (no unit
/// conversion), empty cells as `None`: the input and output histories of a forced record,
/// whose units (volts, newtons) the case states. Returns the cells and the dialect in
/// words.
pub fn read_columns(
    path: &std::path::Path,
    bytes: Vec<u8>,
    names: &[&str],
) -> Result<(crate::signal::OptionalFields, String)> {
    let (normalised, dialect) = normalise(path, bytes)?;
    let fields = crate::signal::read_optional_fields_in(path, normalised.into_bytes(), names)?;
    Ok((fields, dialect.describe()))
}

/// The measured column when the case names none (module docs, "Which column").
fn choose_column(
    header: &[String],
    parsed: &[(String, Option<String>)],
    others: &[usize],
    unit_given: bool,
) -> std::result::Result<usize, (String, String)> {
    let coil: Vec<usize> = others
        .iter()
        .copied()
        .filter(|&i| {
            super::units::Quantity::ALL
                .iter()
                .any(|q| q.column() == header[i])
        })
        .collect();
    match coil.as_slice() {
        [one] => return Ok(*one),
        [] => {}
        several => {
            let mut names: Vec<String> = several
                .iter()
                .map(|&i| format!("`{}`", header[i]))
                .collect();
            names.sort();
            return Err((
                format!(
                    "the header gives {} at once: which one to fit is ambiguous",
                    names.join(" and ")
                ),
                "exactly one of `accel_m_s2`, `velocity_m_s`, `displacement_mm` beside `time_s` (write the other records to their own files, or name one as the record's `channel`)".into(),
            ));
        }
    }
    let with_units: Vec<usize> = others
        .iter()
        .copied()
        .filter(|&i| parsed[i].1.as_deref().and_then(units::parse).is_some())
        .collect();
    match (with_units.as_slice(), others) {
        ([one], _) => Ok(*one),
        ([], [only]) if unit_given || parsed[*only].1.is_some() => Ok(*only),
        _ => Err((
            format!(
                "no measured column in the header (columns: {})",
                header.join(", ")
            ),
            "`time_s` and one of `accel_m_s2`, `velocity_m_s`, `displacement_mm`, or a column with its unit such as `Accel [g]`, or the record entry's `channel` and `unit`".into(),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::Quantity;

    fn read_text(text: &str, spec: RecordSpec) -> Result<Record> {
        read(&spec, text.as_bytes().to_vec())
    }

    #[test]
    fn dialects_are_detected_and_stated() {
        let plain = "# rig\ntime_s,accel_m_s2\n0,1.5\n0.01,2.5\n0.02,-1\n0.03,0\n";
        let semicolon =
            "% logger export\nZeit [s];Beschl. [g]\n0,000;1,5\n0,010;2,5\n0,020;-1\n0,030;0\n";
        let tabs = "Time (ms)\tDisp (mm)\n0\t1.5\n10\t2.5\n20\t-1\n30\t0\n";
        let a = read_text(plain, RecordSpec::file("a.csv")).unwrap();
        assert!(a.format.starts_with("CSV: delimiter ',', decimal point"));
        assert_eq!(a.lines[0], 3);
        let b = read_text(semicolon, RecordSpec::file("b.csv")).unwrap();
        assert!(
            b.format.starts_with("CSV: delimiter ';', decimal comma"),
            "{}",
            b.format
        );
        assert_eq!(b.quantity, Quantity::Acceleration);
        assert_eq!(b.values[1], 2.5 * units::STANDARD_GRAVITY);
        assert_eq!(b.time_s[2], 0.02);
        assert_eq!(b.lines[0], 3);
        let c = read_text(tabs, RecordSpec::file("c.csv")).unwrap();
        assert_eq!(c.quantity, Quantity::Displacement);
        assert_eq!(c.time_s[1], 10.0 * 1e-3);
        assert_eq!(c.values[0], 1.5e-3);
        assert!(c.format.starts_with("CSV: delimiter tab"));
    }

    #[test]
    fn units_and_columns_are_checked() {
        let text = "time_s;a;b\n0;1;2\n0,01;2;3\n0,02;3;4\n";
        let e = read_text(text, RecordSpec::file("x.csv"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("x.csv:1:") && e.contains("no measured column"),
            "{e}"
        );
        let spec = RecordSpec {
            channel: Some("b".into()),
            unit: Some("g".into()),
            ..RecordSpec::file("x.csv")
        };
        assert_eq!(
            read_text(text, spec).unwrap().values[0],
            2.0 * units::STANDARD_GRAVITY
        );
        let spec = RecordSpec {
            unit: Some("g".into()),
            ..RecordSpec::file("x.csv")
        };
        let e = read_text("time_s,accel_m_s2\n0,1\n1,2\n2,3\n", spec)
            .unwrap_err()
            .to_string();
        assert!(e.contains("mismatched units"), "{e}");
        let e = read_text("t;a [g]\n0;1,5.0\n1;2\n2;3\n", RecordSpec::file("y.csv"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("y.csv:2:") && e.contains("point and a comma"),
            "{e}"
        );
    }
}
