//! Reading numeric vectors from MATLAB level 5 MAT-files (`save -v6`, `save -v7`,
//! SciPy's `savemat`).
//!
//! # Layout (MathWorks, "MAT-File Format", level 5)
//! A 128-byte header (text, subsystem offset, version 0x0100, endian indicator `IM`
//! little-endian or `MI` big-endian), then data elements: an 8-byte tag (type, byte count)
//! or a 4-byte small-element tag (count in the upper 16 bits) and the data, padded to 8
//! bytes. A `miCOMPRESSED` (15) element is a zlib stream holding one element (v7); a
//! `miMATRIX` (14) element holds the array flags (class, complex), the dimensions, the
//! name and the real (and imaginary) part, stored in any numeric type (MATLAB stores a
//! double array of small integers as `miUINT8`, say): every value becomes an `f64`
//! exactly.
//!
//! A variable is read when it is a real numeric array with one non-singleton dimension
//! (a row or a column vector). v7.3 files are HDF5 and are refused by [`super::read_record`]
//! with the advice to save with `-v7`.
//!
//! # Work and memory (docs/files.md)
//! Reading is in two passes. The first reads every array's header only: for a compressed
//! one, the first [`HEADER_BYTES`] of its stream are inflated (flags, dimensions, name,
//! and the tag of its real part, which states its type and byte count). The second
//! inflates and converts only the variables the case names (or, when it names none, the
//! time and the one other numeric vector), after checking from their headers, before any
//! work: at most [`MAX_SAMPLES`] values each, and at most `coil_io::MAX_RECORD_BYTES`
//! inflated bytes for the file as a whole. A small file that inflates to gigabytes
//! (a zip bomb), or one with thousands of variables the case never names, costs what
//! its headers cost; at most [`MAX_VARIABLES`] arrays a file.

use std::path::Path;

use super::spec::{fail, Record, RecordSpec};
use super::units;
use crate::error::Result;

/// Bytes of a compressed array's stream inflated to read its header: flags (16),
/// dimensions (8 + 4 per dimension), name (8 + up to 63 in MATLAB) and the real part's
/// tag (8), with room for a few hundred dimensions.
pub const HEADER_BYTES: usize = 4096;
/// Most values of one variable converted to `f64` (32 MiB each; a 64 MiB CSV holds about
/// 2 million rows).
pub const MAX_SAMPLES: usize = 1 << 22;
/// Most arrays in one file.
pub const MAX_VARIABLES: usize = 100_000;

/// One array of the file, as its header describes it (its values are read on demand).
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    /// Its name.
    pub name: String,
    /// MATLAB class code (6 double, 7 single, 8 to 15 integers, 4 char, 1 cell, 2 struct, 5
    /// sparse).
    pub class: u8,
    /// Complex.
    pub complex: bool,
    /// Logical.
    pub logical: bool,
    /// Dimensions.
    pub dims: Vec<usize>,
    /// The real part's element type and byte count, as its tag states them.
    pub data: Option<(u32, usize)>,
    /// The byte of the file where its element starts (for messages).
    pub offset: usize,
    /// Its element: `(compressed, bytes)`, the zlib stream or the matrix's content.
    element: (bool, std::ops::Range<usize>),
}

/// Bytes per value of a numeric element type, `None` for another type.
fn type_size(kind: u32) -> Option<usize> {
    match kind {
        1 | 2 => Some(1),
        3 | 4 => Some(2),
        5..=7 => Some(4),
        9 | 12 | 13 => Some(8),
        _ => None,
    }
}

impl Variable {
    fn describe(&self) -> String {
        let dims: Vec<String> = self.dims.iter().map(|d| d.to_string()).collect();
        let class = match self.class {
            1 => "cell",
            2 => "struct",
            3 => "object",
            4 => "char",
            5 => "sparse",
            6 => "double",
            7 => "single",
            8..=15 if self.logical => "logical",
            8..=15 => "integer",
            _ => "unknown",
        };
        format!(
            "`{}` ({} {class}{})",
            coil_io::excerpt(&self.name),
            coil_io::confine::excerpt_n(&dims.join("x"), 40),
            if self.complex { ", complex" } else { "" }
        )
    }

    /// The number of values its dimensions announce (saturating).
    pub fn len(&self) -> usize {
        self.dims.iter().fold(1usize, |n, &d| n.saturating_mul(d))
    }

    /// No values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// A real numeric row or column vector whose real part holds as many values as its
    /// dimensions announce.
    pub fn is_numeric_vector(&self) -> bool {
        let stored = self
            .data
            .and_then(|(kind, bytes)| type_size(kind).map(|s| (bytes % s == 0, bytes / s)));
        (6..=15).contains(&self.class)
            && !self.complex
            && !self.logical
            && self.dims.iter().filter(|&&d| d != 1).count() <= 1
            && stored == Some((true, self.len()))
    }
}

/// A tag at the start of `b`: `(type, byte count, header bytes, whole element bytes)`,
/// or `None` when `b` is shorter than the tag. A small element (count in the upper 16
/// bits) has a 4-byte header and takes 8 bytes; a compressed one is not padded.
fn tag(little: bool, b: &[u8]) -> Option<std::result::Result<(u32, usize, usize, usize), String>> {
    let word = |at: usize| -> Option<u32> {
        let a: [u8; 4] = b.get(at..at + 4)?.try_into().ok()?;
        Some(if little {
            u32::from_le_bytes(a)
        } else {
            u32::from_be_bytes(a)
        })
    };
    let first = word(0)?;
    if first >> 16 != 0 {
        let n = (first >> 16) as usize;
        if n > 4 {
            return Some(Err(format!("a small element of {n} bytes (at most 4)")));
        }
        return Some(Ok((first & 0xffff, n, 4, 8)));
    }
    let n = word(4)? as usize;
    let whole = if first == 15 {
        8 + n
    } else {
        8 + n.div_ceil(8) * 8
    };
    Some(Ok((first, n, 8, whole)))
}

/// The header of a matrix's content (possibly only its first bytes): class, flags,
/// dimensions, name and the real part's tag, with the real part's place in `b`.
struct Header {
    class: u8,
    complex: bool,
    logical: bool,
    dims: Vec<usize>,
    name: String,
    data: Option<(u32, usize, usize)>,
}

fn header(little: bool, b: &[u8]) -> std::result::Result<Header, String> {
    let mut at = 0;
    let mut parts: Vec<&[u8]> = Vec::with_capacity(3);
    while parts.len() < 3 {
        let what = ["array flags", "dimensions", "name"][parts.len()];
        let (_, n, head, whole) = tag(little, &b[at.min(b.len())..])
            .ok_or_else(|| format!("an array without its {what}"))??;
        let data = b
            .get(at + head..at + head + n)
            .ok_or_else(|| format!("the array's {what} ({n} bytes) past the end of its element"))?;
        parts.push(data);
        at += whole;
    }
    let (flags, dims, name) = (parts[0], parts[1], parts[2]);
    if flags.len() < 8 {
        return Err("array flags of fewer than 8 bytes".into());
    }
    let word = |c: &[u8]| {
        let a = [c[0], c[1], c[2], c[3]];
        if little {
            u32::from_le_bytes(a)
        } else {
            u32::from_be_bytes(a)
        }
    };
    let f = word(flags);
    let data = match b.get(at..).and_then(|rest| tag(little, rest)) {
        Some(Ok((kind, n, head, _))) => Some((kind, n, at + head)),
        Some(Err(e)) => return Err(e),
        None => None,
    };
    Ok(Header {
        class: (f & 0xff) as u8,
        complex: f & 0x800 != 0,
        logical: f & 0x200 != 0,
        dims: dims.chunks_exact(4).map(|c| word(c) as usize).collect(),
        name: String::from_utf8_lossy(name).into_owned(),
        data,
    })
}

/// A MAT-file's bytes with its byte order, read lazily (module docs).
pub struct MatFile<'a> {
    path: &'a Path,
    bytes: &'a [u8],
    little: bool,
    /// Inflated bytes left of the file's budget.
    budget: usize,
}

impl<'a> MatFile<'a> {
    fn broken(&self, at: &str, problem: String) -> crate::error::PostError {
        fail(
            self.path,
            at,
            problem,
            "a MATLAB level 5 MAT-file (save -v6 or -v7, SciPy savemat)",
        )
    }

    /// Opens the bytes of a level 5 MAT-file (the header checked).
    pub fn open(path: &'a Path, bytes: &'a [u8]) -> Result<MatFile<'a>> {
        let mut file = MatFile {
            path,
            bytes,
            little: true,
            budget: coil_io::MAX_RECORD_BYTES as usize,
        };
        if bytes.len() < 128 {
            return Err(file.broken(
                "1",
                format!("{} bytes, shorter than the 128-byte header", bytes.len()),
            ));
        }
        file.little = match &bytes[126..128] {
            b"IM" => true,
            b"MI" => false,
            _ => {
                return Err(file.broken(
                    "1",
                    "no level 5 endian indicator (`IM` or `MI`) in the header".into(),
                ))
            }
        };
        Ok(file)
    }

    /// Every array of the file, from its header only (module docs).
    pub fn variables(&self) -> Result<Vec<Variable>> {
        let mut out = Vec::new();
        let mut at = 128;
        while self.bytes.len() >= at + 8 {
            let place = format!("byte {at}");
            let (kind, n, head, whole) = match tag(self.little, &self.bytes[at..]) {
                Some(Ok(t)) => t,
                Some(Err(e)) => return Err(self.broken(&place, e)),
                None => break,
            };
            let range = at + head..at + head + n;
            if range.end > self.bytes.len() {
                return Err(self.broken(
                    &place,
                    format!("an element of {n} bytes past the end of the file"),
                ));
            }
            let element = at;
            at = at.saturating_add(whole);
            let header = match kind {
                14 => header(self.little, &self.bytes[range.clone()]),
                15 => {
                    let prefix = self.inflate(&self.bytes[range.clone()], HEADER_BYTES, &place)?;
                    match tag(self.little, &prefix) {
                        Some(Ok((14, _, inner, _))) => header(self.little, &prefix[inner..]),
                        Some(Err(e)) => Err(e),
                        // A compressed element that is not an array (none is written).
                        _ => continue,
                    }
                }
                _ => continue,
            }
            .map_err(|e| self.broken(&place, e))?;
            if out.len() == MAX_VARIABLES {
                return Err(fail(
                    self.path,
                    &place,
                    format!("more than {MAX_VARIABLES} arrays"),
                    &format!("at most {MAX_VARIABLES} arrays in a record file (docs/files.md)"),
                ));
            }
            out.push(Variable {
                name: header.name,
                class: header.class,
                complex: header.complex,
                logical: header.logical,
                dims: header.dims,
                data: header.data.map(|(kind, n, _)| (kind, n)),
                offset: element,
                element: (kind == 15, range),
            });
        }
        Ok(out)
    }

    /// The first `limit` bytes of a zlib stream (all of it when shorter); an error when
    /// the stream is broken before that.
    fn inflate(&self, stream: &[u8], limit: usize, at: &str) -> Result<Vec<u8>> {
        use miniz_oxide::inflate::{decompress_to_vec_zlib_with_limit, TINFLStatus};
        match decompress_to_vec_zlib_with_limit(stream, limit) {
            Ok(v) => Ok(v),
            Err(e) if e.status == TINFLStatus::HasMoreOutput => Ok(e.output),
            Err(e) => Err(self.broken(
                at,
                format!("a compressed element does not inflate ({:?})", e.status),
            )),
        }
    }

    /// Checks from its header that `v` is a numeric vector of at most [`MAX_SAMPLES`]
    /// values.
    pub fn check_size(&self, v: &Variable) -> Result<()> {
        let at = format!("variable `{}`", coil_io::excerpt(&v.name));
        if !v.is_numeric_vector() {
            return Err(fail(
                self.path,
                &at,
                format!("{} is not a numeric vector", v.describe()),
                "a real numeric row or column vector",
            ));
        }
        if v.len() > MAX_SAMPLES {
            return Err(fail(
                self.path,
                &at,
                format!("{} values", v.len()),
                &format!("at most {MAX_SAMPLES} values a variable (docs/files.md)"),
            ));
        }
        Ok(())
    }

    /// The values of a numeric vector `v` of this file as `f64`, after checking its size
    /// ([`MatFile::check_size`]) and the file's inflated budget.
    pub fn values(&mut self, v: &Variable) -> Result<Vec<f64>> {
        self.check_size(v)?;
        let at = format!("variable `{}`", coil_io::excerpt(&v.name));
        let (compressed, range) = v.element.clone();
        let stored = &self.bytes[range];
        let inflated;
        let content: &[u8] = if compressed {
            let whole = match tag(self.little, &self.inflate(stored, 16, &at)?) {
                Some(Ok((14, _, _, whole))) => whole,
                _ => return Err(self.broken(&at, "its compressed element changed".into())),
            };
            if whole > self.budget {
                return Err(fail(
                    self.path,
                    &at,
                    format!(
                        "the variables read inflate to more than {} MiB",
                        coil_io::MAX_RECORD_BYTES >> 20
                    ),
                    &format!(
                        "at most {} MiB of inflated data a file (docs/files.md)",
                        coil_io::MAX_RECORD_BYTES >> 20
                    ),
                ));
            }
            inflated = self.inflate(stored, whole, &at)?;
            self.budget -= inflated.len();
            let head = tag(self.little, &inflated).map_or(8, |t| t.map_or(8, |t| t.2));
            &inflated[head.min(inflated.len())..]
        } else {
            stored
        };
        let h = header(self.little, content).map_err(|e| self.broken(&at, e))?;
        let (kind, n, start) = h
            .data
            .ok_or_else(|| self.broken(&at, "an array without its real part".into()))?;
        let bytes = content
            .get(start..start + n)
            .ok_or_else(|| self.broken(&at, format!("its {n} bytes of data past the end")))?;
        Ok(self.convert(kind, bytes))
    }

    fn convert(&self, kind: u32, b: &[u8]) -> Vec<f64> {
        macro_rules! conv {
            ($t:ty, $n:expr) => {
                b.chunks_exact($n)
                    .map(|c| {
                        let a: [u8; $n] = c.try_into().unwrap_or([0; $n]);
                        if self.little {
                            <$t>::from_le_bytes(a) as f64
                        } else {
                            <$t>::from_be_bytes(a) as f64
                        }
                    })
                    .collect()
            };
        }
        match kind {
            1 => conv!(i8, 1),
            2 => conv!(u8, 1),
            3 => conv!(i16, 2),
            4 => conv!(u16, 2),
            5 => conv!(i32, 4),
            6 => conv!(u32, 4),
            7 => conv!(f32, 4),
            9 => conv!(f64, 8),
            12 => conv!(i64, 8),
            13 => conv!(u64, 8),
            // `is_numeric_vector` admits the types above only.
            _ => Vec::new(),
        }
    }
}

/// Names of time variables looked for when the case names none.
const TIME_NAMES: [&str; 3] = ["time_s", "time", "t"];

/// The arrays of a file for a message: the first 8, then how many more.
fn listing(vars: &[Variable]) -> String {
    let mut shown: Vec<String> = vars.iter().take(8).map(Variable::describe).collect();
    if vars.len() > 8 {
        shown.push(format!("and {} more", vars.len() - 8));
    }
    if shown.is_empty() {
        return "no array".into();
    }
    shown.join(", ")
}

/// Reads the channel `spec` names (the variable `channel`, the time `time`) from a
/// MAT-file's bytes.
pub fn read(spec: &RecordSpec, bytes: &[u8]) -> Result<Record> {
    let path = &spec.file;
    let mut file = MatFile::open(path, bytes)?;
    let vars = file.variables()?;
    let find = |name: &str, role: &str| -> Result<&Variable> {
        vars.iter().find(|v| v.name == name).ok_or_else(|| {
            fail(
                path,
                &format!("variable `{}`", coil_io::excerpt(name)),
                format!("no such variable (the file holds {})", listing(&vars)),
                &format!("the {role} variable named in the case"),
            )
        })
    };
    let time_name = match &spec.time {
        Some(t) => t.clone(),
        None => {
            let found: Vec<&str> = TIME_NAMES
                .into_iter()
                .filter(|n| vars.iter().any(|v| v.name == *n))
                .collect();
            match found.as_slice() {
                [one] => one.to_string(),
                _ => {
                    return Err(fail(
                        path,
                        "1",
                        format!(
                            "no time variable named in the case (the file holds {})",
                            listing(&vars)
                        ),
                        "the record entry's `time`: the variable holding the time stamps in s",
                    ))
                }
            }
        }
    };
    let channel =
        match &spec.channel {
            Some(c) => c.clone(),
            None => {
                let others: Vec<&Variable> = vars
                    .iter()
                    .filter(|v| v.name != time_name && v.is_numeric_vector())
                    .collect();
                match others.as_slice() {
                    [one] => one.name.clone(),
                    _ => return Err(fail(
                        path,
                        "1",
                        format!(
                            "no channel named in the case (the file holds {})",
                            listing(&vars)
                        ),
                        "the record entry's `channel`: the variable holding the measured signal",
                    )),
                }
            }
        };
    let time = find(&time_name, "time")?;
    let signal = find(&channel, "channel")?;
    let at = format!("variable `{}`", coil_io::excerpt(&channel));
    file.check_size(time)?;
    file.check_size(signal)?;
    if time.len() != signal.len() {
        return Err(fail(
            path,
            &at,
            format!(
                "{} samples against {} in the time variable `{}`",
                signal.len(),
                time.len(),
                coil_io::excerpt(&time_name)
            ),
            "a time stamp for every sample",
        ));
    }
    let file_unit = super::spec::stated_unit(spec, &at, units::split_name(&channel).1.as_deref())?;
    let unit = super::spec::resolve_unit(spec, &at, file_unit)?;
    let time_s = file.values(time)?;
    super::spec::check_uniform(
        path,
        &format!("variable `{}`", coil_io::excerpt(&time_name)),
        &time_s,
    )?;
    let mut values = file.values(signal)?;
    for v in &mut values {
        *v *= unit.to_si;
    }
    let record = Record {
        file: path.clone(),
        format: format!(
            "MAT-file level 5 (variables `{}` and `{}`)",
            coil_io::excerpt(&time_name),
            coil_io::excerpt(&channel)
        ),
        channel,
        quantity: unit.quantity,
        unit: unit.label,
        lines: (1..=time_s.len() as u64).collect(),
        time_s,
        values,
        time_resolution_s: 0.0,
    };
    super::spec::finish(record, &at)
}

/// The variables `names` of a MAT-file's bytes as written (no unit conversion), each a
/// real numeric vector, all of one length: a forced record's time, input and output
/// ([`super::read_columns`]). Only the variables named are inflated.
pub fn read_columns(path: &Path, bytes: &[u8], names: &[&str]) -> Result<Vec<Vec<f64>>> {
    let mut file = MatFile::open(path, bytes)?;
    let vars = file.variables()?;
    let mut length = None;
    let mut named = Vec::with_capacity(names.len());
    for name in names {
        let at = format!("variable `{}`", coil_io::excerpt(name));
        let v = vars.iter().find(|v| v.name == *name).ok_or_else(|| {
            fail(
                path,
                &at,
                format!("no such variable (the file holds {})", listing(&vars)),
                "the variable the case's forced record names",
            )
        })?;
        if !v.is_numeric_vector() {
            return Err(fail(
                path,
                &at,
                format!("{}, not a real numeric vector", v.describe()),
                "a real numeric row or column vector",
            ));
        }
        file.check_size(v)?;
        match length {
            None => length = Some((v.len(), *name)),
            Some((n, first)) if n != v.len() => {
                return Err(fail(
                    path,
                    &at,
                    format!(
                        "{} samples against {n} in `{}`",
                        v.len(),
                        coil_io::excerpt(first)
                    ),
                    "time, input and output of one length",
                ))
            }
            Some(_) => {}
        }
        named.push(v.clone());
    }
    named.iter().map(|v| file.values(v)).collect()
}

/// The bytes of a level 5 MAT-file (little-endian) of real row vectors, each
/// `(name, element type, stored bytes, number of values)` (type 9 double, 2 uint8, ...),
/// each array compressed (v7) or not (v6): the reader's inverse, for tests and examples.
pub fn level5_bytes(vars: &[(&str, u32, &[u8], usize)], compressed: bool) -> Vec<u8> {
    let element = |kind: u32, data: &[u8]| {
        let mut e = kind.to_le_bytes().to_vec();
        e.extend_from_slice(&(data.len() as u32).to_le_bytes());
        e.extend_from_slice(data);
        while e.len() % 8 != 0 {
            e.push(0);
        }
        e
    };
    let mut out = b"MATLAB 5.0 MAT-file, written by coil".to_vec();
    out.resize(124, b' ');
    out.extend_from_slice(&0x0100u16.to_le_bytes());
    out.extend_from_slice(b"IM");
    for &(name, kind, data, n) in vars {
        let mut body = element(6, &[6, 0, 0, 0, 0, 0, 0, 0]);
        let mut dims = 1u32.to_le_bytes().to_vec();
        dims.extend_from_slice(&(n as u32).to_le_bytes());
        body.extend(element(5, &dims));
        body.extend(element(1, name.as_bytes()));
        body.extend(element(kind, data));
        let array = element(14, &body);
        if compressed {
            let z = miniz_oxide::deflate::compress_to_vec_zlib(&array, 6);
            out.extend_from_slice(&15u32.to_le_bytes());
            out.extend_from_slice(&(z.len() as u32).to_le_bytes());
            out.extend(z);
        } else {
            out.extend(array);
        }
    }
    out
}

/// Little-endian bytes of doubles (an array of element type 9).
pub fn doubles(values: &[f64]) -> Vec<u8> {
    values.iter().flat_map(|x| x.to_le_bytes()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(channel: &str) -> RecordSpec {
        RecordSpec {
            channel: Some(channel.into()),
            unit: Some("m/s^2".into()),
            ..RecordSpec::file("r.mat")
        }
    }

    #[test]
    fn vectors_read_back_compressed_or_not() {
        let t: Vec<f64> = (0..64).map(|i| i as f64 * 1e-3).collect();
        let a: Vec<f64> = (0..64).map(|i| (0.3 * i as f64).sin()).collect();
        let counts: Vec<u8> = (0..64).map(|i| i as u8).collect();
        for compressed in [false, true] {
            let bytes = level5_bytes(
                &[
                    ("time_s", 9, &doubles(&t), 64),
                    ("acc", 9, &doubles(&a), 64),
                    ("counts", 2, &counts, 64),
                ],
                compressed,
            );
            let r = read(&spec("acc"), &bytes).unwrap();
            assert_eq!((r.time_s, r.values), (t.clone(), a.clone()));
            let r = read(&spec("counts"), &bytes).unwrap();
            assert_eq!(r.values[63], 63.0);
        }
    }

    /// A file of a few hundred KB whose compressed arrays inflate to far more than the
    /// file's budget: the arrays the case does not name cost their headers only, and a
    /// named one is refused before it is inflated.
    #[test]
    fn a_zip_bomb_costs_its_headers() {
        let t: Vec<f64> = (0..64).map(|i| i as f64 * 1e-3).collect();
        let a: Vec<f64> = (0..64).map(|i| (0.3 * i as f64).sin()).collect();
        let big = vec![0u8; 60 << 20];
        let (t, a8) = (doubles(&t), doubles(&a));
        let mut vars: Vec<(&str, u32, &[u8], usize)> =
            vec![("time_s", 9, &t, 64), ("acc", 9, &a8, 64)];
        for name in ["z1", "z2", "z3"] {
            vars.push((name, 2, &big, big.len()));
        }
        let bytes = level5_bytes(&vars, true);
        assert!(bytes.len() < 1 << 20, "{} bytes", bytes.len());
        let r = read(&spec("acc"), &bytes).unwrap();
        assert_eq!(r.values, a);
        // Named: more values than a variable may hold, refused from its header.
        let e = read(&spec("z1"), &bytes).unwrap_err().to_string();
        assert!(
            e.contains("r.mat:variable `z1`") && e.contains("at most 4194304 values"),
            "{e}"
        );
        // The file's inflated budget: two named variables of 40 MiB of bytes each.
        let small = vec![1u8; 3 << 20];
        let vars: Vec<(&str, u32, &[u8], usize)> = vec![
            ("time_s", 2, &small, small.len()),
            ("acc", 2, &small, small.len()),
        ];
        let bytes = level5_bytes(&vars, true);
        let mut file = MatFile::open(Path::new("r.mat"), &bytes).unwrap();
        file.budget = 5 << 20;
        let vars = file.variables().unwrap();
        file.values(&vars[0]).unwrap();
        let e = file.values(&vars[1]).unwrap_err().to_string();
        assert!(e.contains("inflate to more than 64 MiB"), "{e}");
    }

    #[test]
    fn broken_files_are_located() {
        let t: Vec<f64> = (0..64).map(|i| i as f64).collect();
        let t = doubles(&t);
        let good = level5_bytes(&[("time_s", 9, &t, 64), ("a", 9, &t, 64)], true);
        // Every truncation is an error naming the file, never a panic.
        for cut in (0..good.len()).step_by(7) {
            if let Err(e) = read(&spec("a"), &good[..cut]) {
                assert!(e.to_string().starts_with("r.mat:"), "{e}");
            }
        }
        let e = read(&spec("b"), &good).unwrap_err().to_string();
        assert!(e.contains("no such variable") && e.contains("`a`"), "{e}");
        // A channel whose name states a unit coil does not know, and no case unit.
        let named = level5_bytes(&[("time_s", 9, &t, 64), ("a (ft/s^2)", 9, &t, 64)], false);
        let spec = RecordSpec {
            channel: Some("a (ft/s^2)".into()),
            ..RecordSpec::file("r.mat")
        };
        let e = read(&spec, &named).unwrap_err().to_string();
        assert!(e.contains("`ft/s^2` is not a unit coil knows"), "{e}");
    }
}
