//! Reading Universal File Format datasets 58 and 58b (function at nodal DOF) and 164
//! (units), the layout `coil_io::uff` writes and documents.
//!
//! # What is read
//! - Datasets are delimited by `-1` lines; any dataset other than 58, 58b and 164 is
//!   skipped. 58b's ID line gives the byte order (1 little, 2 big endian) and the byte
//!   count of its binary record 12, which follows the 11 ASCII header lines directly
//!   (4 bytes a value for ordinate type 2, 8 for type 4; an uneven dataset's byte count
//!   may be announced for its points rather than its (x, y) pairs, as pyuff writes it).
//! - Record 6: function type (1, time response, is the only one accepted), the response
//!   node and direction. Record 7: ordinate type (2 real single, 4 real double; complex
//!   types are refused), number of points, abscissa spacing (1 even: `x_i = start + i
//!   step`, computed the way pyuff does; 0 uneven: (x, y) pairs), start, step. Records 8
//!   and 9: the abscissa's and the ordinate's specific data type (17 time; 8 displacement,
//!   11 velocity, 12 acceleration), length unit exponent, label and unit label.
//! - ASCII record 12 in fixed columns: `6E13.5` (single), `4E20.12` (double, even),
//!   `2(E13.5,E20.12)` (double, uneven); Fortran `D` exponents are accepted.
//!
//! # Units
//! The ordinate's unit label is used when it states one (not blank, not `NONE`): a label
//! coil does not know ([`super::units`]) is an error naming record 9's line and the
//! labels known, unless the case states the channel's unit. Without a label, a data type
//! of 8, 11 or 12 gives the quantity in the file's unit system: SI without a dataset 164,
//! else SI = value / (length factor)^(length exponent) (dataset 164's factors convert the
//! file's units to SI by division). The abscissa must be time: its data type 17 or a time
//! unit label (`s`, `ms`), or neither stated (then seconds); another label is an error
//! at record 8's line. A UTF-8 byte order mark before the first `-1` is skipped.

use std::path::Path;

use super::spec::{fail, Record, RecordSpec};
use super::units::{self, Quantity};
use crate::error::Result;

/// One axis description (records 8 to 11).
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// Specific data type.
    pub kind: i32,
    /// Length unit exponent.
    pub length_exponent: i32,
    /// Axis label.
    pub label: String,
    /// Unit label.
    pub unit: String,
}

/// One dataset 58 as stored.
#[derive(Debug, Clone, PartialEq)]
pub struct Dataset58 {
    /// Its index among the file's datasets 58, from 1.
    pub index: usize,
    /// The line of its `58` header.
    pub line: u64,
    /// Binary (58b).
    pub binary: bool,
    /// ID line 1.
    pub description: String,
    /// ID line 2.
    pub name: String,
    /// Function type (1: time response).
    pub function_type: i32,
    /// Response node.
    pub node: i64,
    /// Response direction.
    pub direction: i32,
    /// Ordinate data type (2, 4 real; 5, 6 complex).
    pub ordinate_type: i32,
    /// Even abscissa.
    pub even: bool,
    /// Abscissa start.
    pub start: f64,
    /// Abscissa step.
    pub step: f64,
    /// The abscissa.
    pub abscissa: Axis,
    /// The ordinate.
    pub ordinate: Axis,
    /// Abscissa values.
    pub x: Vec<f64>,
    /// Ordinate values, in the file's unit.
    pub y: Vec<f64>,
}

impl Dataset58 {
    /// `dataset 2 (line 14)` for messages.
    pub fn at(&self) -> String {
        format!("dataset {} (line {})", self.index, self.line)
    }

    /// `dataset 2 (node 10, direction 3)`.
    pub fn channel(&self) -> String {
        format!(
            "dataset {} (node {}, direction {})",
            self.index, self.node, self.direction
        )
    }
}

/// A file's datasets 58 and its dataset 164 length factor, if any.
#[derive(Debug, Clone, PartialEq)]
pub struct UffFile {
    /// Datasets 58 and 58b, in file order.
    pub datasets: Vec<Dataset58>,
    /// Dataset 164's length factor (file unit to SI by division).
    pub length_factor: Option<f64>,
}

struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: u64,
}

impl<'a> Cursor<'a> {
    fn next_line(&mut self) -> Option<(String, u64)> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.pos..];
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        let raw = &rest[..end];
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        self.pos += (end + 1).min(rest.len());
        self.line += 1;
        Some((String::from_utf8_lossy(raw).into_owned(), self.line))
    }
}

fn is_delimiter(line: &str) -> bool {
    line.trim() == "-1"
}

/// Characters `from..to` of a fixed-column line (blank past its end).
fn cols(line: &str, from: usize, to: usize) -> &str {
    let n = line.len();
    if from >= n || !line.is_char_boundary(from.min(n)) || !line.is_char_boundary(to.min(n)) {
        return "";
    }
    line[from..to.min(n)].trim()
}

fn real(text: &str) -> Option<f64> {
    text.trim().replace(['D', 'd'], "E").parse().ok()
}

/// Reads every dataset 58 / 58b and the dataset 164 of a UFF file.
pub fn read_file(path: &Path, bytes: &[u8]) -> Result<UffFile> {
    // A UTF-8 byte order mark before the first `-1` (Windows editors).
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let mut c = Cursor {
        bytes,
        pos: 0,
        line: 0,
    };
    let mut datasets = Vec::new();
    let mut length_factor = None;
    let bad = |line: u64, problem: String, expected: &str| {
        fail(path, &line.to_string(), problem, expected)
    };
    while let Some((line, number)) = c.next_line() {
        if line.trim().is_empty() {
            continue;
        }
        if !is_delimiter(&line) {
            return Err(bad(
                number,
                format!("`{}` where a dataset starts", coil_io::excerpt(&line)),
                "`    -1` opening each dataset (Universal File Format)",
            ));
        }
        // Two delimiters in a row (an empty dataset, as pyuff writes before a 58b) are one.
        let mut head = c.next_line();
        while head.as_ref().is_some_and(|(l, _)| is_delimiter(l)) {
            head = c.next_line();
        }
        let Some((head, head_line)) = head else {
            break;
        };
        let kind = cols(&head, 0, 6);
        let binary = head
            .as_bytes()
            .get(6)
            .is_some_and(|b| b.eq_ignore_ascii_case(&b'b'));
        match kind {
            "58" => {
                let d = read_58(path, &mut c, &head, head_line, binary, datasets.len() + 1)?;
                datasets.push(d);
            }
            "164" => {
                length_factor = Some(read_164(path, &mut c)?);
            }
            _ => loop {
                match c.next_line() {
                    Some((l, _)) if is_delimiter(&l) => break,
                    Some(_) => {}
                    None => {
                        return Err(bad(
                            head_line,
                            format!("dataset {} has no closing `-1`", coil_io::excerpt(kind)),
                            "each dataset closed by a `    -1` line",
                        ))
                    }
                }
            },
        }
    }
    Ok(UffFile {
        datasets,
        length_factor,
    })
}

fn read_164(path: &Path, c: &mut Cursor<'_>) -> Result<f64> {
    let (_, first) = c.next_line().unwrap_or_default();
    let (factors, line) = c.next_line().unwrap_or_default();
    let length = factors.split_whitespace().next().and_then(real);
    loop {
        match c.next_line() {
            Some((l, _)) if is_delimiter(&l) => break,
            Some(_) => {}
            None => break,
        }
    }
    match length {
        Some(f) if f.is_finite() && f > 0.0 => Ok(f),
        _ => Err(fail(
            path,
            &line.max(first + 1).to_string(),
            format!(
                "dataset 164's unit factors `{}` do not start with a length factor",
                coil_io::excerpt(&factors)
            ),
            "three positive reals (length, force, temperature factors, D25.17)",
        )),
    }
}

fn axis(line: &str) -> Axis {
    Axis {
        kind: cols(line, 0, 10).parse().unwrap_or(0),
        length_exponent: cols(line, 10, 15).parse().unwrap_or(0),
        label: cols(line, 26, 46).to_string(),
        unit: cols(line, 47, 67).to_string(),
    }
}

fn read_58(
    path: &Path,
    c: &mut Cursor<'_>,
    head: &str,
    head_line: u64,
    binary: bool,
    index: usize,
) -> Result<Dataset58> {
    let at = format!("dataset {index} (line {head_line})");
    let bad = |problem: String, expected: &str| fail(path, &at, problem, expected);
    let mut header = Vec::with_capacity(11);
    for _ in 0..11 {
        match c.next_line() {
            Some((l, _)) => header.push(l),
            None => {
                return Err(bad(
                    format!("{} of the 11 header lines", header.len()),
                    "a complete dataset 58 (5 ID lines, records 6 to 11)",
                ))
            }
        }
    }
    let r6 = &header[5];
    let r7 = &header[6];
    let int = |text: &str, what: &str| -> Result<i64> {
        text.parse().map_err(|_| {
            bad(
                format!("{what} `{}` is not an integer", coil_io::excerpt(text)),
                "records 6 and 7 in their fixed columns (I5, I10 ...)",
            )
        })
    };
    let function_type = int(cols(r6, 0, 5), "the function type")? as i32;
    let node = int(cols(r6, 41, 51), "the response node").unwrap_or(0);
    let direction = int(cols(r6, 51, 55), "the response direction").unwrap_or(0) as i32;
    let ordinate_type = int(cols(r7, 0, 10), "the ordinate data type")? as i32;
    let n = int(cols(r7, 10, 20), "the number of points")?;
    let even = int(cols(r7, 20, 30), "the abscissa spacing")? == 1;
    let start = real(cols(r7, 30, 43)).unwrap_or(0.0);
    let step = real(cols(r7, 43, 56)).unwrap_or(0.0);
    let n = usize::try_from(n)
        .ok()
        .filter(|&n| n > 0 && n <= coil_io::MAX_RECORD_BYTES as usize)
        .ok_or_else(|| bad(format!("{n} points"), "a positive number of points"))?;
    if !matches!(ordinate_type, 2 | 4) {
        return Err(bad(
            format!(
                "ordinate data type {ordinate_type} ({})",
                if matches!(ordinate_type, 5 | 6) {
                    "complex"
                } else {
                    "unknown"
                }
            ),
            "a real time response: ordinate type 2 (single) or 4 (double)",
        ));
    }
    let count = if even { n } else { 2 * n };
    let values = if binary {
        read_binary(path, &at, c, head, ordinate_type, count)?
    } else {
        read_ascii(path, &at, c, ordinate_type, even, count)?
    };
    let (x, y) = if even {
        let x = (0..n).map(|i| start + i as f64 * step).collect();
        (x, values)
    } else {
        let x = values.iter().step_by(2).copied().collect();
        let y = values.iter().skip(1).step_by(2).copied().collect();
        (x, y)
    };
    Ok(Dataset58 {
        index,
        line: head_line,
        binary,
        description: header[0].trim().to_string(),
        name: header[1].trim().to_string(),
        function_type,
        node,
        direction,
        ordinate_type,
        even,
        start,
        step,
        abscissa: axis(&header[7]),
        ordinate: axis(&header[8]),
        x,
        y,
    })
}

fn read_ascii(
    path: &Path,
    at: &str,
    c: &mut Cursor<'_>,
    ordinate_type: i32,
    even: bool,
    count: usize,
) -> Result<Vec<f64>> {
    let widths: &[usize] = match (ordinate_type, even) {
        (2, _) => &[13],
        (_, true) => &[20],
        (_, false) => &[13, 20],
    };
    // Reserved for what the rest of the file can hold (13 bytes a value at least), not
    // for what record 7 announces.
    let mut values =
        Vec::with_capacity(count.min((c.bytes.len() - c.pos.min(c.bytes.len())) / 13 + 1));
    loop {
        let Some((line, number)) = c.next_line() else {
            return Err(fail(
                path,
                at,
                format!("{} of {count} values and no closing `-1`", values.len()),
                "the data record closed by a `    -1` line",
            ));
        };
        if is_delimiter(&line) {
            break;
        }
        let mut from = 0;
        let mut k = 0;
        while from < line.len() {
            let w = widths[k % widths.len()];
            let text = cols(&line, from, from + w);
            if text.is_empty() {
                break;
            }
            let v = real(text).ok_or_else(|| {
                fail(
                    path,
                    &number.to_string(),
                    format!("`{}` is not a number", coil_io::excerpt(text)),
                    "reals in the fixed columns of record 12 (E13.5 or E20.12)",
                )
            })?;
            values.push(v);
            from += w;
            k += 1;
        }
    }
    if values.len() != count {
        return Err(fail(
            path,
            at,
            format!(
                "{} values in record 12, record 7 announces {count}",
                values.len()
            ),
            "as many values as record 7 says",
        ));
    }
    Ok(values)
}

fn read_binary(
    path: &Path,
    at: &str,
    c: &mut Cursor<'_>,
    head: &str,
    ordinate_type: i32,
    count: usize,
) -> Result<Vec<f64>> {
    let little = cols(head, 7, 13) != "2";
    let announced: usize = cols(head, 31, 43).parse().unwrap_or(0);
    let size = if ordinate_type == 4 { 8 } else { 4 };
    // An uneven dataset holds (x, y) pairs: `count` is twice the points. Some writers
    // (pyuff) announce the bytes of the points only; the data are the pairs all the same.
    if announced != size * count && announced != size * count / 2 {
        return Err(fail(
            path,
            at,
            format!("58b announces {announced} bytes for {count} values of {size} bytes"),
            "the byte count of record 12 in the 58b ID line",
        ));
    }
    let n_bytes = size * count;
    let end = c.pos + n_bytes;
    let Some(data) = c.bytes.get(c.pos..end) else {
        return Err(fail(
            path,
            at,
            format!(
                "the file ends {} bytes into the {n_bytes} of binary data",
                c.bytes.len() - c.pos
            ),
            "the complete binary record",
        ));
    };
    let values = data
        .chunks_exact(size)
        .map(|b| match (size, little) {
            (8, true) => f64::from_le_bytes(b.try_into().unwrap_or([0; 8])),
            (8, false) => f64::from_be_bytes(b.try_into().unwrap_or([0; 8])),
            (_, true) => f64::from(f32::from_le_bytes(b.try_into().unwrap_or([0; 4]))),
            (_, false) => f64::from(f32::from_be_bytes(b.try_into().unwrap_or([0; 4]))),
        })
        .collect();
    c.line += data.iter().filter(|&&b| b == b'\n').count() as u64;
    c.pos = end;
    // The closing `-1` follows, on the same line as the data's last byte or on the next.
    loop {
        match c.next_line() {
            Some((l, _)) if is_delimiter(&l) => break,
            Some((l, _)) if l.trim().is_empty() => {}
            _ => {
                return Err(fail(
                    path,
                    at,
                    "no `-1` after the binary data".into(),
                    "`    -1` right after the announced bytes",
                ))
            }
        }
    }
    Ok(values)
}

/// Which dataset a channel names: its index (from 1) or `node:direction`.
fn choose<'a>(path: &Path, file: &'a UffFile, channel: Option<&str>) -> Result<&'a Dataset58> {
    let listing = || {
        file.datasets
            .iter()
            .map(|d| format!("{} `{}`", d.channel(), coil_io::excerpt(&d.name)))
            .collect::<Vec<_>>()
            .join("; ")
    };
    let Some(channel) = channel else {
        return match file.datasets.as_slice() {
            [one] => Ok(one),
            several => Err(fail(
                path,
                "1",
                format!(
                    "{} datasets 58 ({}) and no channel",
                    several.len(),
                    listing()
                ),
                "the record entry's `channel`: a dataset index (from 1) or `node:direction`",
            )),
        };
    };
    let found = if let Some((node, dir)) = channel.split_once(':') {
        let node: Option<i64> = node.trim().parse().ok();
        let dir: Option<i32> = dir.trim().trim_start_matches('+').parse().ok();
        file.datasets
            .iter()
            .find(|d| Some(d.node) == node && Some(d.direction) == dir)
    } else {
        channel
            .trim()
            .parse::<usize>()
            .ok()
            .and_then(|i| file.datasets.iter().find(|d| d.index == i))
    };
    found.ok_or_else(|| {
        fail(
            path,
            "1",
            format!(
                "no dataset 58 matches the channel `{}` (the file holds: {})",
                coil_io::excerpt(channel),
                listing()
            ),
            "a dataset index (from 1) or `node:direction` of one of them",
        )
    })
}

/// A unit label that states a unit: not blank and not `NONE` (what writers put in an
/// unused label).
fn label(unit: &str) -> Option<&str> {
    let u = unit.trim();
    (!u.is_empty() && !u.eq_ignore_ascii_case("none")).then_some(u)
}

/// The ordinate's unit as the dataset states it (module docs), if it states one. A
/// label coil does not know is an error at record 9's line (unless the case states the
/// unit), never the data type's SI.
fn file_unit(
    spec: &RecordSpec,
    d: &Dataset58,
    length_factor: Option<f64>,
) -> Result<Option<units::Unit>> {
    let record_9 = (d.line + 9).to_string();
    if let Some(l) = label(&d.ordinate.unit) {
        return super::spec::stated_unit(spec, &record_9, Some(l));
    }
    let quantity = match d.ordinate.kind {
        8 => Quantity::Displacement,
        11 => Quantity::Velocity,
        12 => Quantity::Acceleration,
        _ => return Ok(None),
    };
    let factor = length_factor.unwrap_or(1.0);
    Ok(Some(units::Unit {
        label: if length_factor.is_some() {
            format!("the file's unit system (length factor {factor})")
        } else {
            quantity.si_unit().to_string()
        },
        quantity,
        to_si: 1.0 / factor.powi(d.ordinate.length_exponent),
    }))
}

/// A time response's abscissa in s, checked: function type 1, a time abscissa (a stated
/// unit must be a time unit; none stated is seconds), uniform when uneven.
fn time_axis(path: &Path, d: &Dataset58) -> Result<Vec<f64>> {
    let at = d.at();
    if d.function_type != 1 {
        return Err(fail(
            path,
            &at,
            format!("function type {} (not a time response)", d.function_type),
            "function type 1, a time response",
        ));
    }
    let time_factor = match label(&d.abscissa.unit) {
        Some(l) => units::time_factor(l),
        None => Some(1.0),
    };
    let (Some(time_factor), true) = (time_factor, matches!(d.abscissa.kind, 0 | 1 | 17)) else {
        return Err(fail(
            path,
            &(d.line + 8).to_string(),
            format!(
                "an abscissa of data type {} in `{}`",
                d.abscissa.kind,
                coil_io::excerpt(&d.abscissa.unit)
            ),
            "time as the abscissa (data type 17, unit `s`)",
        ));
    };
    let time_s: Vec<f64> = if time_factor == 1.0 {
        d.x.clone()
    } else {
        d.x.iter().map(|t| t * time_factor).collect()
    };
    if !d.even {
        super::spec::check_uniform(path, &at, &time_s)?;
    }
    Ok(time_s)
}

/// The datasets `channels` (each a dataset index from 1 or `node:direction`) of a UFF
/// file's bytes as written (the file's own units, no conversion) and their common time
/// axis in s: a forced record's input and output ([`super::read_columns`]). Each must be
/// a time response on the same abscissa; a dataset that states its ordinate's unit must
/// state the one the case gives for it (`units`, one per channel), compared without
/// case, blanks and `^`: the values are not converted, so another unit is an error.
pub fn read_columns(
    path: &Path,
    bytes: &[u8],
    channels: &[&str],
    units: &[&str],
) -> Result<(Vec<f64>, Vec<Vec<f64>>)> {
    let file = read_file(path, bytes)?;
    let mut time: Option<(Vec<f64>, String)> = None;
    let mut values = Vec::with_capacity(channels.len());
    let plain = |u: &str| -> String {
        u.chars()
            .filter(|c| !c.is_whitespace() && *c != '^')
            .flat_map(char::to_lowercase)
            .collect()
    };
    for (channel, unit) in channels.iter().zip(units) {
        let d = choose(path, &file, Some(channel))?;
        if let Some(stated) = label(&d.ordinate.unit) {
            if plain(stated) != plain(unit) {
                return Err(fail(
                    path,
                    &d.at(),
                    format!(
                        "the unit `{}` where the case gives `{}` (mismatched units)",
                        coil_io::excerpt(stated),
                        coil_io::excerpt(unit)
                    ),
                    "the unit the dataset states, in the case's forced record",
                ));
            }
        }
        let time_s = time_axis(path, d)?;
        match &time {
            None => time = Some((time_s, d.at())),
            Some((t, first)) => {
                let step = if t.len() > 1 {
                    (t[1] - t[0]).abs()
                } else {
                    1.0
                };
                let same = t.len() == time_s.len()
                    && t.iter()
                        .zip(&time_s)
                        .all(|(a, b)| (a - b).abs() <= 1e-6 * step);
                if !same {
                    return Err(fail(
                        path,
                        &d.at(),
                        format!(
                            "{} samples from {} s every {} s, another time axis than {first}'s",
                            time_s.len(),
                            time_s.first().copied().unwrap_or(0.0),
                            d.step
                        ),
                        "input and output sampled together (one abscissa)",
                    ));
                }
            }
        }
        values.push(d.y.clone());
    }
    let (time_s, _) = time.ok_or_else(|| {
        fail(
            path,
            "1",
            "no channel named".into(),
            "the input and output channels",
        )
    })?;
    Ok((time_s, values))
}

/// Reads the channel `spec` names from a UFF file's bytes, in SI.
pub fn read(spec: &RecordSpec, bytes: &[u8]) -> Result<Record> {
    super::spec::no_time_variable(spec)?;
    let path = &spec.file;
    let file = read_file(path, bytes)?;
    if file.datasets.is_empty() {
        return Err(fail(
            path,
            "1",
            "no dataset 58 in the file".into(),
            "a time response as UFF dataset 58 or 58b",
        ));
    }
    let d = choose(path, &file, spec.channel.as_deref())?;
    let at = d.at();
    let time_s = time_axis(path, d)?;
    let unit = super::spec::resolve_unit(spec, &at, file_unit(spec, d, file.length_factor)?)?;
    let values = if unit.to_si == 1.0 {
        d.y.clone()
    } else {
        d.y.iter().map(|v| v * unit.to_si).collect()
    };
    let record = Record {
        file: path.clone(),
        format: format!(
            "UFF dataset 58{} ({}, {})",
            if d.binary { "b" } else { "" },
            if d.ordinate_type == 4 {
                "double"
            } else {
                "single"
            },
            if d.even {
                "even abscissa"
            } else {
                "uneven abscissa"
            }
        ),
        channel: d.channel(),
        quantity: unit.quantity,
        unit: unit.label,
        lines: (1..=time_s.len() as u64).collect(),
        time_s,
        values,
        time_resolution_s: 0.0,
    };
    super::spec::finish(record, &at)
}

#[cfg(test)]
mod tests {
    use super::*;
    use coil_io::uff::{uff58_bytes, Uff58};

    fn dataset(node: i64, unit: &str, values: Vec<f64>) -> Uff58 {
        Uff58 {
            description: "measured".into(),
            name: "a".into(),
            node,
            direction: 3,
            ordinate_type: 12,
            length_exponent: 1,
            ordinate_label: "acceleration".into(),
            ordinate_unit: unit.into(),
            start_s: 0.5,
            step_s: 1e-3,
            values,
        }
    }

    fn read_bytes(bytes: &[u8], channel: Option<&str>, unit: Option<&str>) -> Result<Record> {
        let spec = RecordSpec {
            file: "r.uff".into(),
            channel: channel.map(str::to_string),
            unit: unit.map(str::to_string),
            ..RecordSpec::default()
        };
        read(&spec, bytes)
    }

    /// What coil writes it reads back: bit for bit in 58b, to 13 digits in ASCII; the
    /// channel by index or node:direction; g scaled by g_n.
    #[test]
    fn written_datasets_read_back() {
        let y: Vec<f64> = (0..11).map(|i| (0.7 * i as f64).sin() / 3.0).collect();
        let two = [dataset(10, "m/s^2", y.clone()), dataset(11, "g", y.clone())];
        for binary in [false, true] {
            let bytes = uff58_bytes(&two, binary);
            let r = read_bytes(&bytes, Some("1"), None).unwrap();
            assert_eq!(r.time_s[3], 0.5 + 3.0 * 1e-3);
            for (a, b) in r.values.iter().zip(&y) {
                if binary {
                    assert_eq!(a, b);
                } else {
                    assert!((a - b).abs() <= 5e-13 * b.abs(), "{a} {b}");
                }
            }
            let g = read_bytes(&bytes, Some("11:3"), None).unwrap();
            assert_eq!(g.values[1], r.values[1] * units::STANDARD_GRAVITY);
            let e = read_bytes(&bytes, None, None).unwrap_err().to_string();
            assert!(e.contains("2 datasets 58") && e.contains("node 11"), "{e}");
            let e = read_bytes(&bytes, Some("1"), Some("g"))
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("mismatched units") && e.contains("dataset 1"),
                "{e}"
            );
        }
    }

    /// An ordinate label coil does not know is refused at record 9's line with the
    /// labels known (never read as the data type's SI); the case's own unit overrides
    /// it. A byte order mark does not hide the format.
    #[test]
    fn unknown_units_are_refused_and_a_bom_is_skipped() {
        let bytes = uff58_bytes(&[dataset(1, "ft/s^2", vec![1.0; 16])], false);
        let e = read_bytes(&bytes, None, None).unwrap_err().to_string();
        assert!(
            e.starts_with("r.uff:11:")
                && e.contains("`ft/s^2` is not a unit coil knows")
                && e.contains("m/s^2, mm/s^2"),
            "{e}"
        );
        let r = read_bytes(&bytes, None, Some("g")).unwrap();
        assert_eq!(r.values[0], units::STANDARD_GRAVITY);
        let mut bom = b"\xef\xbb\xbf".to_vec();
        bom.extend(uff58_bytes(&[dataset(1, "m/s^2", vec![2.0; 16])], false));
        assert_eq!(super::super::detect(&bom), super::super::Format::Uff);
        assert_eq!(read_bytes(&bom, None, None).unwrap().values[3], 2.0);
    }

    #[test]
    fn bad_files_are_named() {
        let e = read_bytes(b"    -1\n   151\nx\n    -1\n", None, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("no dataset 58"), "{e}");
        let mut d = dataset(1, "NONE", vec![1.0, 2.0, 3.0]);
        d.ordinate_type = 0;
        let e = read_bytes(&uff58_bytes(&[d], false), None, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("states no unit"), "{e}");
    }
}
