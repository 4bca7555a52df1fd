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
//! with the advice to save with `-v7`. Decompression is bounded by
//! `coil_io::MAX_RECORD_BYTES` per element.

use std::path::Path;

use super::spec::{fail, Record, RecordSpec};
use super::units;
use crate::error::Result;

/// One array of the file.
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
    /// Real part as f64 (empty for non-numeric classes).
    pub real: Vec<f64>,
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
            dims.join("x"),
            if self.complex { ", complex" } else { "" }
        )
    }

    fn is_numeric_vector(&self) -> bool {
        (6..=15).contains(&self.class)
            && !self.complex
            && !self.logical
            && self.dims.iter().filter(|&&d| d != 1).count() <= 1
            && self.real.len() == self.dims.iter().product::<usize>()
    }
}

struct Reader {
    little: bool,
}

impl Reader {
    fn u32(&self, b: &[u8]) -> u32 {
        let a = [b[0], b[1], b[2], b[3]];
        if self.little {
            u32::from_le_bytes(a)
        } else {
            u32::from_be_bytes(a)
        }
    }

    /// The elements in `bytes`: `(type, data)`.
    fn elements<'a>(
        &self,
        mut bytes: &'a [u8],
    ) -> std::result::Result<Vec<(u32, &'a [u8])>, String> {
        let mut out = Vec::new();
        while bytes.len() >= 8 {
            let first = self.u32(&bytes[0..4]);
            if first >> 16 != 0 {
                let n = (first >> 16) as usize;
                if n > 4 {
                    return Err(format!("a small element of {n} bytes (at most 4)"));
                }
                out.push((first & 0xffff, &bytes[4..4 + n]));
                bytes = &bytes[8..];
                continue;
            }
            let n = self.u32(&bytes[4..8]) as usize;
            let data = bytes
                .get(8..8 + n)
                .ok_or_else(|| format!("an element of {n} bytes past the end of the file"))?;
            out.push((first, data));
            let padded = if first == 15 { n } else { n.div_ceil(8) * 8 };
            bytes = bytes.get(8 + padded..).unwrap_or(&[]);
        }
        Ok(out)
    }

    fn numbers(&self, kind: u32, b: &[u8]) -> std::result::Result<Vec<f64>, String> {
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
        Ok(match kind {
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
            other => return Err(format!("numeric data of element type {other}")),
        })
    }

    fn matrix(&self, data: &[u8]) -> std::result::Result<Variable, String> {
        let parts = self.elements(data)?;
        let (Some(flags), Some(dims), Some(name)) = (parts.first(), parts.get(1), parts.get(2))
        else {
            return Err("an array without flags, dimensions and name".into());
        };
        if flags.1.len() < 8 {
            return Err("array flags of fewer than 8 bytes".into());
        }
        let f = self.u32(&flags.1[0..4]);
        let class = (f & 0xff) as u8;
        let dims: Vec<usize> = dims
            .1
            .chunks_exact(4)
            .map(|c| self.u32(c) as usize)
            .collect();
        let name = String::from_utf8_lossy(name.1).into_owned();
        let numeric = (6..=15).contains(&class);
        let real = match parts.get(3) {
            Some((kind, bytes)) if numeric => self.numbers(*kind, bytes)?,
            _ => Vec::new(),
        };
        Ok(Variable {
            name,
            class,
            complex: f & 0x800 != 0,
            logical: f & 0x200 != 0,
            dims,
            real,
        })
    }
}

/// Every array of a level 5 MAT-file.
pub fn variables(path: &Path, bytes: &[u8]) -> Result<Vec<Variable>> {
    let broken = |problem: String| {
        fail(
            path,
            "1",
            problem,
            "a MATLAB level 5 MAT-file (save -v6 or -v7, SciPy savemat)",
        )
    };
    if bytes.len() < 128 {
        return Err(broken(format!(
            "{} bytes, shorter than the 128-byte header",
            bytes.len()
        )));
    }
    let little = match &bytes[126..128] {
        b"IM" => true,
        b"MI" => false,
        _ => {
            return Err(broken(
                "no level 5 endian indicator (`IM` or `MI`) in the header".into(),
            ))
        }
    };
    let r = Reader { little };
    let mut out = Vec::new();
    for (kind, data) in r.elements(&bytes[128..]).map_err(broken)? {
        let (kind, data) = match kind {
            15 => {
                let inflated = miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(
                    data,
                    coil_io::MAX_RECORD_BYTES as usize,
                )
                .map_err(|e| broken(format!("a compressed element does not inflate ({e:?})")))?;
                let inner = r.elements(&inflated).map_err(broken)?;
                match inner.first() {
                    Some(&(14, d)) => (14, d.to_vec()),
                    _ => continue,
                }
            }
            14 => (14, data.to_vec()),
            _ => continue,
        };
        debug_assert_eq!(kind, 14);
        out.push(r.matrix(&data).map_err(broken)?);
    }
    Ok(out)
}

/// Names of time variables looked for when the case names none.
const TIME_NAMES: [&str; 3] = ["time_s", "time", "t"];

/// Reads the channel `spec` names (the variable `channel`, the time `time`) from a
/// MAT-file's bytes.
pub fn read(spec: &RecordSpec, bytes: &[u8]) -> Result<Record> {
    let path = &spec.file;
    let vars = variables(path, bytes)?;
    let listing = || {
        vars.iter()
            .map(Variable::describe)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let find = |name: &str, role: &str| -> Result<&Variable> {
        let v = vars.iter().find(|v| v.name == name).ok_or_else(|| {
            fail(
                path,
                &format!("variable `{}`", coil_io::excerpt(name)),
                format!("no such variable (the file holds {})", listing()),
                &format!("the {role} variable named in the case"),
            )
        })?;
        if !v.is_numeric_vector() {
            return Err(fail(
                path,
                &format!("variable `{}`", coil_io::excerpt(name)),
                format!("{} is not a numeric vector", v.describe()),
                "a real numeric row or column vector",
            ));
        }
        Ok(v)
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
                            listing()
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
                            listing()
                        ),
                        "the record entry's `channel`: the variable holding the measured signal",
                    )),
                }
            }
        };
    let time = find(&time_name, "time")?;
    let signal = find(&channel, "channel")?;
    let at = format!("variable `{}`", coil_io::excerpt(&channel));
    if time.real.len() != signal.real.len() {
        return Err(fail(
            path,
            &at,
            format!(
                "{} samples against {} in the time variable `{}`",
                signal.real.len(),
                time.real.len(),
                coil_io::excerpt(&time_name)
            ),
            "a time stamp for every sample",
        ));
    }
    super::spec::check_increasing(
        path,
        &format!("variable `{}`", coil_io::excerpt(&time_name)),
        &time.real,
    )?;
    let file_unit = units::split_name(&channel).1.and_then(|u| units::parse(&u));
    let unit = super::spec::resolve_unit(spec, &at, file_unit)?;
    let values = signal.real.iter().map(|v| v * unit.to_si).collect();
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
        lines: (1..=time.real.len() as u64).collect(),
        time_s: time.real.clone(),
        values,
        time_resolution_s: 0.0,
    };
    super::spec::finish(record, &at)
}
