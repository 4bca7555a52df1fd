//! Unit labels as labs write them, each mapped to the quantity it measures and its factor
//! to SI (m, m/s, m/s^2, s).
//!
//! A label is compared after trimming, lower-casing, removing blanks and writing the
//! usual variants one way (`²` and `**2` as `^2`, `s2` after a slash as `s^2`, `µ` as `u`,
//! `sec` as `s`). Standard gravity is g_n = 9.80665 m/s^2 exactly (CGPM 1901, the value
//! accelerometer calibrations use). coil's own column suffixes (`_m_s2`, `_m_s`, `_mm`)
//! are labels too, so `accel_m_s2` and `Accel [m/s^2]` mean the same.

use serde::Serialize;

/// What a decay record measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// Acceleration (`accel_m_s2` in coil's CSV).
    Acceleration,
    /// Velocity (`velocity_m_s`).
    Velocity,
    /// Displacement (`displacement_mm`).
    Displacement,
}

impl Quantity {
    /// Every quantity, in the order of the measured-case table.
    pub const ALL: [Quantity; 3] = [
        Quantity::Acceleration,
        Quantity::Velocity,
        Quantity::Displacement,
    ];

    /// coil's CSV column of the quantity.
    pub fn column(self) -> &'static str {
        match self {
            Quantity::Acceleration => "accel_m_s2",
            Quantity::Velocity => "velocity_m_s",
            Quantity::Displacement => "displacement_mm",
        }
    }

    /// Factor from coil's column unit to SI (mm -> m).
    pub fn to_si(self) -> f64 {
        match self {
            Quantity::Displacement => 1e-3,
            _ => 1.0,
        }
    }

    /// The SI unit.
    pub fn si_unit(self) -> &'static str {
        match self {
            Quantity::Acceleration => "m/s^2",
            Quantity::Velocity => "m/s",
            Quantity::Displacement => "m",
        }
    }

    /// How many times the record must be differentiated to give the acceleration.
    pub fn derivatives_to_acceleration(self) -> usize {
        match self {
            Quantity::Acceleration => 0,
            Quantity::Velocity => 1,
            Quantity::Displacement => 2,
        }
    }

    /// The name a case uses (`acceleration`, `velocity`, `displacement`).
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Acceleration => "acceleration",
            Quantity::Velocity => "velocity",
            Quantity::Displacement => "displacement",
        }
    }

    /// The quantity a case names, `None` for any other word.
    pub fn from_name(name: &str) -> Option<Quantity> {
        Quantity::ALL.into_iter().find(|q| q.name() == name)
    }
}

/// Standard gravity, m/s^2.
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// A unit label understood: what it measures and its factor to SI.
#[derive(Debug, Clone, PartialEq)]
pub struct Unit {
    /// The label as written.
    pub label: String,
    /// What it measures.
    pub quantity: Quantity,
    /// Multiply a value in this unit by it to get SI.
    pub to_si: f64,
}

/// Known labels of the three record quantities: `(normalised label, quantity, to SI)`.
const LABELS: &[(&str, Quantity, f64)] = &[
    ("m/s^2", Quantity::Acceleration, 1.0),
    ("m_s2", Quantity::Acceleration, 1.0),
    ("mm/s^2", Quantity::Acceleration, 1e-3),
    ("cm/s^2", Quantity::Acceleration, 1e-2),
    ("in/s^2", Quantity::Acceleration, 0.0254),
    ("g", Quantity::Acceleration, STANDARD_GRAVITY),
    ("gn", Quantity::Acceleration, STANDARD_GRAVITY),
    ("m/s", Quantity::Velocity, 1.0),
    ("m_s", Quantity::Velocity, 1.0),
    ("mm/s", Quantity::Velocity, 1e-3),
    ("cm/s", Quantity::Velocity, 1e-2),
    ("in/s", Quantity::Velocity, 0.0254),
    ("m", Quantity::Displacement, 1.0),
    ("mm", Quantity::Displacement, 1e-3),
    ("cm", Quantity::Displacement, 1e-2),
    ("um", Quantity::Displacement, 1e-6),
    ("in", Quantity::Displacement, 0.0254),
];

/// Every label [`parse`] understands, for messages.
pub fn known_labels() -> String {
    LABELS
        .iter()
        .filter(|(l, _, _)| !l.contains('_'))
        .map(|(l, _, _)| *l)
        .collect::<Vec<_>>()
        .join(", ")
}

fn normalise(label: &str) -> String {
    let mut s: String = label
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect();
    for (from, to) in [
        ("²", "^2"),
        ("**", "^"),
        ("µ", "u"),
        ("μ", "u"),
        ("sec", "s"),
    ] {
        s = s.replace(from, to);
    }
    if s.ends_with("/s2") {
        s = format!("{}^2", s.trim_end_matches('2'));
    }
    s
}

/// The unit a label names (`None` when it is not a unit of displacement, velocity or
/// acceleration).
pub fn parse(label: &str) -> Option<Unit> {
    let key = normalise(label);
    LABELS
        .iter()
        .find(|(l, _, _)| *l == key)
        .map(|&(_, quantity, to_si)| Unit {
            label: label.trim().to_string(),
            quantity,
            to_si,
        })
}

/// The factor to seconds of a time label (`s`, `ms`), `None` for anything else.
pub fn time_factor(label: &str) -> Option<f64> {
    match normalise(label).as_str() {
        "s" => Some(1.0),
        "ms" => Some(1e-3),
        _ => None,
    }
}

/// Splits a column name into its name and the unit it states: `Time [s]`, `a (g)`,
/// `accel_m_s2` (coil's suffixes), or no unit.
pub fn split_name(column: &str) -> (String, Option<String>) {
    let c = column.trim();
    for (open, close) in [('[', ']'), ('(', ')'), ('{', '}')] {
        if let (Some(start), true) = (c.rfind(open), c.ends_with(close)) {
            let unit = c[start + 1..c.len() - 1].trim();
            if !unit.is_empty() {
                return (c[..start].trim().to_string(), Some(unit.to_string()));
            }
        }
    }
    if let Some(q) = Quantity::ALL.iter().find(|q| q.column() == c) {
        let unit = match q {
            Quantity::Acceleration => "m/s^2",
            Quantity::Velocity => "m/s",
            Quantity::Displacement => "mm",
        };
        return (c.to_string(), Some(unit.to_string()));
    }
    if c == "time_s" {
        return (c.to_string(), Some("s".to_string()));
    }
    (c.to_string(), None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_as_labs_write_them() {
        for (label, q, f) in [
            ("m/s^2", Quantity::Acceleration, 1.0),
            ("m/s²", Quantity::Acceleration, 1.0),
            ("M/S**2", Quantity::Acceleration, 1.0),
            ("m/s2", Quantity::Acceleration, 1.0),
            (" g ", Quantity::Acceleration, STANDARD_GRAVITY),
            ("mm/sec", Quantity::Velocity, 1e-3),
            ("µm", Quantity::Displacement, 1e-6),
            ("mm", Quantity::Displacement, 1e-3),
        ] {
            let u = parse(label).unwrap_or_else(|| panic!("{label}"));
            assert_eq!((u.quantity, u.to_si), (q, f), "{label}");
        }
        assert!(parse("N").is_none());
        assert_eq!(time_factor("ms"), Some(1e-3));
        assert_eq!(split_name("Time [s]"), ("Time".into(), Some("s".into())));
        assert_eq!(split_name("a (g)"), ("a".into(), Some("g".into())));
        assert_eq!(
            split_name("displacement_mm"),
            ("displacement_mm".into(), Some("mm".into()))
        );
        assert_eq!(split_name("x"), ("x".into(), None));
    }
}
