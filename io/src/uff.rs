//! Writing time histories as Universal File Format dataset 58, the function-at-nodal-DOF
//! record that vibration labs exchange (LMS Test.Lab / Simcenter, m+p, Brüel & Kjær, pyuff).
//!
//! # Why here
//! Two crates write histories: `coil-solver` (`coil-solve`'s transient histories) and
//! the tuner (`coil-tune diagnose`'s fits). The solver may depend only on `coil-io`, and
//! `coil-postproc` (where the UFF *reader* lives, beside every other record reader) stands
//! alone on signals; so the writer sits below both, in the file-boundary crate, and needs
//! nothing but `std`. The reader and the writer share one set of layout rules, documented
//! here and in `postproc::record::uff`.
//!
//! # Layout written (one dataset)
//! ```text
//!     -1
//!     58                                   (ASCII; 58b: "    58b     1     2          11    NBYTES     0     0           0           0")
//! ID lines 1..5 (80 characters each: description, name, date, two free lines)
//! record 6:  (2(I5,I10),2(1X,10A1,I10,I4))  function type 1 (time response), ids, response node and direction
//! record 7:  (3I10,3E13.5)                  ordinate type 4 (real double), points, 1 (even), start, step, 0
//! record 8:  (I10,3I5,2(1X,20A1))           abscissa: data type 17 (time), unit exponents, label, unit ("s")
//! record 9:                                 ordinate: data type (8 displacement, 11 velocity, 12 acceleration), exponents, label, unit
//! records 10, 11:                           denominator and z axis: none
//! record 12: ASCII 4E20.12 per line, or 58b: NBYTES of little-endian IEEE f64
//!     -1
//! ```
//! Reals in ASCII records are written Fortran style (`-1.234567890123E+02`): the data
//! keep 13 significant digits (relative rounding at most 5e-13), the binary form keeps
//! every bit. The start and step (record 7) carry 7 significant digits when positive
//! (`E13.6` fills the 13 columns) and 6 otherwise; a time grid in seconds at any rate whose
//! step has at most 7 significant digits (0.01 s, 1e-4 s, 1/1024 s is not) reads back
//! exactly. Units follow SI: lengths in m (length exponent 1), time in s.
//! Source: the UFF dataset 58 and 58b descriptions (SDRC I-DEAS Universal File Format,
//! as reproduced in pyuff's `dataset_58` documentation).

use std::fmt::Write as _;

/// Which form of dataset 58 to write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UffForm {
    /// ASCII dataset 58 (13 significant digits).
    Ascii,
    /// Binary dataset 58b (every bit).
    Binary,
}

/// One dataset 58: a real, evenly sampled time response at one node and direction.
#[derive(Debug, Clone, PartialEq)]
pub struct Uff58 {
    /// ID line 1: what the function is (e.g. `measured acceleration`).
    pub description: String,
    /// ID line 2: a name (e.g. the record's column name).
    pub name: String,
    /// The response node (0 when not a node of a model).
    pub node: i64,
    /// The response direction: 1, 2, 3 translations x, y, z; 4, 5, 6 rotations; 0 none.
    pub direction: i32,
    /// UFF specific data type of the ordinate: 8 displacement, 11 velocity, 12
    /// acceleration, 1 general.
    pub ordinate_type: i32,
    /// The ordinate's length unit exponent (1 for m, m/s, m/s^2; 0 for a rotation).
    pub length_exponent: i32,
    /// The ordinate's axis label (e.g. `acceleration`).
    pub ordinate_label: String,
    /// The ordinate's unit label (e.g. `m/s^2`).
    pub ordinate_unit: String,
    /// Time of the first sample, s.
    pub start_s: f64,
    /// Sampling step, s.
    pub step_s: f64,
    /// The samples, in `ordinate_unit`.
    pub values: Vec<f64>,
}

impl Uff58 {
    /// The UFF type and length exponent of a quantity named the way coil names history
    /// columns and record columns (`disp`, `displacement`, `vel`, `velocity`, `accel`,
    /// `acceleration`, `rot`): `(ordinate_type, length_exponent)`.
    pub fn ordinate_kind(quantity: &str) -> (i32, i32) {
        match quantity {
            "disp" | "displacement" => (8, 1),
            "vel" | "velocity" => (11, 1),
            "accel" | "acceleration" => (12, 1),
            _ => (1, 0),
        }
    }
}

/// A file of datasets 58: ASCII (`binary` false) or 58b (true). Non-finite numbers are
/// written as they print (`NaN`, `inf`); callers check their data first.
pub fn uff58_bytes(datasets: &[Uff58], binary: bool) -> Vec<u8> {
    let mut out: Vec<u8> = Vec::new();
    for d in datasets {
        let n = d.values.len();
        let mut head = String::new();
        head.push_str("    -1\n");
        if binary {
            let _ = writeln!(
                head,
                "    58b{:6}{:6}{:12}{:12}{:6}{:6}{:12}{:12}",
                1,
                2,
                11,
                8 * n,
                0,
                0,
                0,
                0
            );
        } else {
            head.push_str("    58\n");
        }
        for line in [
            d.description.as_str(),
            d.name.as_str(),
            "NONE",
            "NONE",
            "NONE",
        ] {
            let _ = writeln!(head, "{:<80}", clip(line, 80));
        }
        let _ = writeln!(
            head,
            "{:5}{:10}{:5}{:10} {:<10}{:10}{:4} {:<10}{:10}{:4}",
            1, 0, 0, 0, "NONE", d.node, d.direction, "NONE", 0, 0
        );
        let _ = writeln!(
            head,
            "{:10}{:10}{:10}{}{}{}",
            4,
            n,
            1,
            e13(d.start_s),
            e13(d.step_s),
            e13(0.0)
        );
        axis(&mut head, 17, 0, "time", "s");
        axis(
            &mut head,
            d.ordinate_type,
            d.length_exponent,
            &d.ordinate_label,
            &d.ordinate_unit,
        );
        axis(&mut head, 0, 0, "NONE", "NONE");
        axis(&mut head, 0, 0, "NONE", "NONE");
        out.extend_from_slice(head.as_bytes());
        if binary {
            for v in &d.values {
                out.extend_from_slice(&v.to_le_bytes());
            }
        } else {
            let mut data = String::with_capacity(21 * n + n / 4 + 2);
            for row in d.values.chunks(4) {
                for v in row {
                    data.push_str(&fortran_e(*v, 12, 20));
                }
                data.push('\n');
            }
            out.extend_from_slice(data.as_bytes());
        }
        out.extend_from_slice(b"    -1\n");
    }
    out
}

/// Records 8 to 11: `(I10,3I5,2(1X,20A1))`.
fn axis(out: &mut String, kind: i32, length_exponent: i32, label: &str, unit: &str) {
    let _ = writeln!(
        out,
        "{:10}{:5}{:5}{:5} {:<20} {:<20}",
        kind,
        length_exponent,
        0,
        0,
        clip(label, 20),
        clip(unit, 20)
    );
}

fn clip(text: &str, width: usize) -> String {
    text.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .take(width)
        .collect()
}

/// A 13-column real of record 7: `E13.6` when it fits (a non-negative value), else `E13.5`.
fn e13(x: f64) -> String {
    if x >= 0.0 {
        fortran_e(x, 6, 13)
    } else {
        fortran_e(x, 5, 13)
    }
}

/// `x` as Fortran's `Ew.d`: `d` digits after the point, a signed two- or three-digit
/// exponent, right-aligned in `width` columns with at least one blank before it (a
/// three-digit exponent takes one decimal less, so that fields never touch).
pub fn fortran_e(x: f64, decimals: usize, width: usize) -> String {
    if !x.is_finite() {
        return format!("{:>width$}", x);
    }
    let mut decimals = decimals;
    loop {
        let text = format!("{:.*e}", decimals, x);
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        let exponent: i32 = exponent.parse().unwrap_or(0);
        let sign = if exponent < 0 { '-' } else { '+' };
        let field = format!("{mantissa}E{sign}{:02}", exponent.unsigned_abs());
        if field.len() < width || decimals == 0 {
            return format!("{field:>width$}");
        }
        decimals -= 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fortran_reals_have_fixed_width() {
        assert_eq!(fortran_e(405.2, 12, 20), "  4.052000000000E+02");
        assert_eq!(fortran_e(-1.5e-300, 12, 20), " -1.50000000000E-300");
        assert_eq!(fortran_e(0.01, 6, 13), " 1.000000E-02");
        assert_eq!(fortran_e(-0.01, 5, 13), " -1.00000E-02");
    }

    #[test]
    fn ascii_and_binary_layouts() {
        let d = Uff58 {
            description: "measured".into(),
            name: "accel_m_s2".into(),
            node: 10,
            direction: 3,
            ordinate_type: 12,
            length_exponent: 1,
            ordinate_label: "acceleration".into(),
            ordinate_unit: "m/s^2".into(),
            start_s: 0.0,
            step_s: 0.01,
            values: vec![1.0, -2.0, 3.5, 4.0, 5.0],
        };
        let text = String::from_utf8(uff58_bytes(std::slice::from_ref(&d), false)).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "    -1");
        assert_eq!(lines[1], "    58");
        assert_eq!(lines.len(), 2 + 5 + 6 + 2 + 1);
        assert_eq!(&lines[8][..30], "         4         5         1");
        assert_eq!(lines[13].len(), 80);
        assert_eq!(lines[14].len(), 20);
        let binary = uff58_bytes(&[d], true);
        assert!(binary.starts_with(b"    -1\n    58b     1     2          11          40"));
        assert!(binary.ends_with(b"    -1\n"));
    }
}
