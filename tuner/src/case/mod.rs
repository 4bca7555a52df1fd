//! Reading a measured case (`docs/measured-case.md`) and a variants file.
//!
//! A case is a folder holding `case.json` and the record files it names; [`read_case`]
//! takes the folder or the `case.json` path. Field names and units are exactly the
//! spec's: `spring.{active_coils, mean_diameter_mm, wire_diameter_mm, pitch_mm}`,
//! `material.{youngs_modulus_mpa, poisson_ratio, density_kg_m3}`, `mass_kg`,
//! `gravity_m_s2`, `records.{static, decay}` (paths relative to the folder; either list
//! may be missing or empty) and the optional `targets.{stiffness_n_mm, damping_ratio,
//! period_s}`. Extras read when present: `tested_springs` (Table 1 of the paper) and
//! `paper` (the paper's reported figures, for side-by-side tables). Unknown members are
//! ignored, as the spec allows.
//!
//! Every problem is a [`CaseError`] naming the file, line and column, the field and what
//! was expected; nothing here panics on user data. Record files are checked to exist
//! when the case is read and parsed on demand ([`MeasuredCase::static_records`],
//! [`MeasuredCase::decay_records`]), so a case with targets only costs nothing more.

mod records;
#[cfg(test)]
mod tests;

pub use crate::error::CaseError;
pub use records::{
    format_note, read_decay, read_decay_record, read_static_record, MeasuredDecay, Quantity,
    StaticRecord,
};

use crate::fields::{root, Field, FieldError, Object, Range};
use crate::json;
use coil_postproc::record::RecordSpec;
use coil_postproc::signal::Signal;
use records::static_slope_n_m;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Helix geometry of the active coils (Table 4's n, D, d, h).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
pub struct SpringGeometry {
    /// Number of active coils n.
    pub active_coils: f64,
    /// Mean coil diameter D, mm.
    pub mean_diameter_mm: f64,
    /// Wire diameter d, mm.
    pub wire_diameter_mm: f64,
    /// Pitch h, mm.
    pub pitch_mm: f64,
}

/// Handbook material values: starting points of the calibration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NominalMaterial {
    /// Young's modulus E, MPa.
    pub youngs_modulus_mpa: f64,
    /// Poisson's ratio (-).
    pub poisson_ratio: f64,
    /// Wire density, kg/m^3.
    pub density_kg_m3: f64,
}

/// The paper's reduced figures, given instead of (or beside) raw records.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Targets {
    /// Axial stiffness K, N/mm, if given.
    pub stiffness_n_mm: Option<f64>,
    /// Damping ratio zeta (-), if given.
    pub damping_ratio: Option<f64>,
    /// Period of the axial mode, s, if given.
    pub period_s: Option<f64>,
}

/// One spring of the paper's Table 1.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TestedSpring {
    /// Its name.
    pub name: String,
    /// Axial stiffness K, N/mm.
    pub stiffness_n_mm: f64,
    /// Damping ratio zeta (-).
    pub damping_ratio: f64,
}

/// What the paper reports for its case (Tables 2 and 3, the loop counts).
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct PaperFigures {
    /// Where the values come from (a citation), if given.
    pub source: Option<String>,
    /// Young's modulus E, MPa, if given.
    pub youngs_modulus_mpa: Option<f64>,
    /// Axial stiffness K, N/mm, if given.
    pub stiffness_n_mm: Option<f64>,
    /// Damping ratio zeta (-), if given.
    pub damping_ratio: Option<f64>,
    /// The paper's alpha, 1/s.
    pub rayleigh_alpha: Option<f64>,
    /// The paper's beta, s.
    pub rayleigh_beta: Option<f64>,
    /// The paper's iterations of loop 1.
    pub stiffness_iterations: Option<f64>,
    /// The paper's iterations of loop 2.
    pub mass_iterations: Option<f64>,
}

/// A case folder, read and checked.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeasuredCase {
    /// The `case.json` that was read.
    pub file: PathBuf,
    /// Its name.
    pub name: String,
    /// The spring geometry.
    pub spring: SpringGeometry,
    /// The material and weight.
    pub material: NominalMaterial,
    /// The weight's mass, kg.
    pub mass_kg: f64,
    /// Gravity, m/s^2.
    pub gravity_m_s2: f64,
    /// Static records, resolved against the case folder (they exist).
    pub static_files: Vec<PathBuf>,
    /// Decay records, resolved against the case folder (they exist).
    pub decay_files: Vec<PathBuf>,
    /// What each decay record says about itself, in `decay_files` order (a plain file
    /// name: the case's mass, the axial mode, at the weight).
    pub decay_info: Vec<DecayInfo>,
    /// The targets.
    pub targets: Targets,
    /// Line and column of the `targets` object (for messages about a missing target).
    #[serde(skip)]
    pub targets_at: Option<(usize, usize)>,
    /// The tested springs (the paper's Table 1).
    pub tested_springs: Vec<TestedSpring>,
    /// The paper's values.
    pub paper: Option<PaperFigures>,
}

/// The mode a decay record shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DecayMode {
    /// The weight bouncing on the spring (the default).
    Axial,
    /// The spring's own first axial mode, with the weight held (fixed-fixed coil).
    Surge,
}

/// A `records.decay` entry's own description (docs/measured-case.md, "Several
/// decay records").
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DecayInfo {
    /// The attached mass of this record (kg); `None`: the case's `mass_kg`.
    pub mass_kg: Option<f64>,
    /// Which mode the record shows.
    pub mode: DecayMode,
    /// Where the sensor sat, in words (`"weight"` by default).
    pub location: String,
    /// How to read the file: `channel`, `time`, `quantity`, `unit` of the entry
    /// (`coil_postproc::record`); all `None` for a plain file name.
    #[serde(skip)]
    pub reading: Reading,
}

/// What a record entry says about reading its file (docs/measured-case.md, "Records as
/// labs store them").
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Reading {
    /// A UFF dataset (index from 1, or `node:direction`), a `.mat` variable, a CSV column.
    pub channel: Option<String>,
    /// The `.mat` variable holding the time stamps (s).
    pub time: Option<String>,
    /// What the channel measures.
    pub quantity: Option<Quantity>,
    /// Its unit label.
    pub unit: Option<String>,
}

impl Reading {
    /// The record spec of `file` read this way.
    pub fn spec(&self, file: &Path) -> RecordSpec {
        RecordSpec {
            file: file.to_path_buf(),
            channel: self.channel.clone(),
            time: self.time.clone(),
            quantity: self.quantity,
            unit: self.unit.clone(),
        }
    }
}

impl Default for DecayInfo {
    fn default() -> Self {
        DecayInfo {
            mass_kg: None,
            mode: DecayMode::Axial,
            location: "weight".to_string(),
            reading: Reading::default(),
        }
    }
}

/// The `channel`, `time`, `quantity` and `unit` of a record entry object.
fn reading(o: &Object<'_>) -> Result<Reading, FieldError> {
    let quantity = match o.get("quantity") {
        None => None,
        Some(q) => {
            const EXPECTED: &str =
                "the record's quantity: \"acceleration\", \"velocity\" or \"displacement\"";
            let name = q.string(EXPECTED)?;
            Some(
                Quantity::from_name(name)
                    .ok_or_else(|| q.error(format!("found the string \"{name}\""), EXPECTED))?,
            )
        }
    };
    let unit = o.opt_string("unit", "the channel's unit, e.g. \"m/s^2\", \"g\", \"mm\"")?;
    if let (Some(label), Some(u)) = (&unit, o.get("unit")) {
        if coil_postproc::record::units::parse(label).is_none() {
            return Err(u.error(
                format!("found the string \"{}\"", coil_io::excerpt(label)),
                format!(
                    "a unit of displacement, velocity or acceleration: one of {}",
                    coil_postproc::record::units::known_labels()
                ),
            ));
        }
    }
    const CHANNEL: &str =
        "a UFF dataset index (from 1) or `node:direction`, a `.mat` variable or a CSV column";
    let channel = match o.get("channel") {
        None => None,
        Some(c) => match &c.node.value {
            json::Value::Number(_) => Some(c.number(Range::Positive, CHANNEL)?.to_string()),
            _ => Some(c.string(CHANNEL)?.to_string()),
        },
    };
    Ok(Reading {
        channel,
        time: o.opt_string("time", "the `.mat` variable holding the time stamps in s")?,
        quantity,
        unit,
    })
}

/// Reads a `records.decay` entry: a file name, or `{file, channel?, time?, quantity?,
/// unit?, mass_kg?, mode?, location?}`.
/// Returns the field holding the file name and the entry's description.
fn decay_entry<'a>(item: &Field<'a>) -> Result<(Field<'a>, DecayInfo), FieldError> {
    if !matches!(item.node.value, json::Value::Object(_)) {
        return Ok((item.clone(), DecayInfo::default()));
    }
    let o = item.object(
        "a decay record: a file name or {file, channel, time, quantity, unit, mass_kg, mode, location}",
    )?;
    let file = o.require("file", "the record's file, relative to the case folder")?;
    // An explicit null is not an absent key: a mass left blank is an error, not the case's.
    if let Some(m) = o
        .get("mass_kg")
        .filter(|m| m.node.value == json::Value::Null)
    {
        return Err(m.error(
            "found null",
            "the attached mass of this record in kg (a number > 0); leave the key out for the \
             case's mass_kg",
        ));
    }
    let mass_kg = o.opt_number(
        "mass_kg",
        Range::Positive,
        "the attached mass of this record in kg",
    )?;
    let mode = match o.get("mode") {
        None => DecayMode::Axial,
        Some(m) => match m.string("the record's mode: \"axial\" or \"surge\"")? {
            "axial" => DecayMode::Axial,
            "surge" => DecayMode::Surge,
            other => {
                return Err(m.error(
                    format!("found the string \"{other}\""),
                    "the record's mode: \"axial\" or \"surge\"",
                ))
            }
        },
    };
    let location = o
        .opt_string("location", "where the sensor sat, in words")?
        .unwrap_or_else(|| "weight".to_string());
    let reading = reading(&o)?;
    Ok((
        file,
        DecayInfo {
            mass_kg,
            mode,
            location,
            reading,
        },
    ))
}

/// Reads a JSON input (bounded in size) into a located tree; errors name the file,
/// line and column.
pub fn read_json(path: &Path) -> Result<(String, json::Node), CaseError> {
    let text = coil_io::read_bounded(path, coil_io::MAX_JSON_BYTES, "a JSON input")
        .map_err(CaseError::input)?;
    let node = json::parse(&text).map_err(|e| CaseError::Syntax {
        path: path.to_path_buf(),
        line: e.line,
        column: e.column,
        message: e.message,
    })?;
    Ok((text, node))
}

/// A record entry of `case.json` resolved inside the case folder (docs/files.md): a
/// relative path without `..` naming a regular file that stays inside the folder after
/// symlinks are resolved. The error names the entry, never the target's content.
fn resolve_record(folder: &Path, entry: &str, item: &Field<'_>) -> Result<PathBuf, CaseError> {
    coil_io::resolve_inside(folder, entry).map_err(|e| {
        item.error(
            e.to_string(),
            "a record file inside the case folder (relative, no `..`, no symlink out of it)",
        )
        .into()
    })
}

/// The `case.json` of a case given as a folder or as the file itself.
pub fn case_file(path: &Path) -> PathBuf {
    if path.is_dir() {
        path.join("case.json")
    } else {
        path.to_path_buf()
    }
}

/// Reads and checks a case (a folder with `case.json`, or the `case.json` path).
pub fn read_case(path: &Path) -> Result<MeasuredCase, CaseError> {
    let file = case_file(path);
    let (_, node) = read_json(&file)?;
    let top = root(&file, &node);
    let doc = top.object("a measured case (see docs/measured-case.md)")?;
    let folder = file.parent().map(Path::to_path_buf).unwrap_or_default();

    let name = doc.string("name", "the case's name (a non-empty string)")?;
    let spring = read_geometry(
        &doc.require("spring", "the spring's geometry (an object)")?
            .object("the spring's geometry")?,
    )?;
    let material = read_material(
        &doc.require("material", "the nominal material (an object)")?
            .object("the nominal material")?,
    )?;
    let mass_kg = doc.number(
        "mass_kg",
        Range::Positive,
        "the weight's nominal mass in kg",
    )?;
    let gravity_m_s2 = doc.number(
        "gravity_m_s2",
        Range::NonNegative,
        "gravity along the spring axis in m/s^2 (0: no preload)",
    )?;

    let (mut static_files, mut decay_files) = (Vec::new(), Vec::new());
    let mut decay_info = Vec::new();
    if let Some(records) = doc.get("records") {
        let records = records.object("the record files")?;
        for (key, out) in [("static", &mut static_files), ("decay", &mut decay_files)] {
            let Some(list) = records.get(key) else {
                continue;
            };
            if list.node.value == json::Value::Null {
                continue;
            }
            for item in list.array(&format!("a list of {key} record files"))? {
                let item = if key == "decay" {
                    let (file, info) = decay_entry(&item)?;
                    decay_info.push(info);
                    file
                } else {
                    item
                };
                let rel = item.string("a path relative to the case folder")?;
                out.push(resolve_record(&folder, rel, &item)?);
            }
        }
    }

    let targets_at = doc.get("targets").map(|t| (t.node.line, t.node.column));
    let targets = match doc.get("targets") {
        None => Targets::default(),
        Some(t) => {
            let t = t.object("the reduced target figures")?;
            Targets {
                stiffness_n_mm: t.opt_number(
                    "stiffness_n_mm",
                    Range::Positive,
                    "the target stiffness in N/mm",
                )?,
                damping_ratio: t.opt_number(
                    "damping_ratio",
                    Range::Open(0.0, 1.0),
                    "the target damping ratio",
                )?,
                period_s: t.opt_number("period_s", Range::Positive, "the target period in s")?,
            }
        }
    };

    let mut tested_springs = Vec::new();
    if let Some(list) = doc.get("tested_springs") {
        for item in list.array("the tested springs")? {
            let o = item.object("a tested spring")?;
            tested_springs.push(TestedSpring {
                name: o.string("name", "the spring's name")?,
                stiffness_n_mm: o.number(
                    "stiffness_n_mm",
                    Range::Positive,
                    "the measured stiffness in N/mm",
                )?,
                damping_ratio: o.number(
                    "damping_ratio",
                    Range::Open(0.0, 1.0),
                    "the measured damping ratio",
                )?,
            });
        }
    }

    let paper = match doc.get("paper") {
        None => None,
        Some(p) => {
            let p = p.object("the paper's reported figures")?;
            let mut figures = PaperFigures {
                source: p.opt_string("source", "a citation")?,
                ..PaperFigures::default()
            };
            if let Some(t3) = p.get("table3") {
                let t = t3.object("the paper's Table 3 figures")?;
                figures.youngs_modulus_mpa =
                    t.opt_number("youngs_modulus_mpa", Range::Positive, "E in MPa")?;
                figures.stiffness_n_mm =
                    t.opt_number("stiffness_n_mm", Range::Positive, "K in N/mm")?;
                figures.damping_ratio =
                    t.opt_number("damping_ratio", Range::Open(0.0, 1.0), "zeta")?;
                figures.rayleigh_alpha =
                    t.opt_number("rayleigh_alpha", Range::NonNegative, "alpha in 1/s")?;
                figures.rayleigh_beta =
                    t.opt_number("rayleigh_beta", Range::NonNegative, "beta in s")?;
                figures.stiffness_iterations =
                    t.opt_number("stiffness_iterations", Range::Count, "an iteration count")?;
                figures.mass_iterations =
                    t.opt_number("mass_iterations", Range::Count, "an iteration count")?;
            }
            Some(figures)
        }
    };

    Ok(MeasuredCase {
        file,
        name,
        spring,
        material,
        mass_kg,
        gravity_m_s2,
        static_files,
        decay_files,
        decay_info,
        targets,
        targets_at,
        tested_springs,
        paper,
    })
}

fn read_geometry(o: &Object<'_>) -> Result<SpringGeometry, FieldError> {
    let active_coils = o.number(
        "active_coils",
        Range::Positive,
        "the number of active coils n",
    )?;
    let mean_diameter_mm = o.number(
        "mean_diameter_mm",
        Range::Positive,
        "the mean coil diameter D in mm",
    )?;
    let wire = o.require("wire_diameter_mm", "the wire diameter d in mm")?;
    let wire_diameter_mm = wire.number(Range::Positive, "the wire diameter d in mm")?;
    if wire_diameter_mm >= mean_diameter_mm {
        return Err(wire.error(
            format!("{wire_diameter_mm} is not below the mean diameter {mean_diameter_mm}"),
            "a wire diameter smaller than the mean coil diameter",
        ));
    }
    let pitch = o.require("pitch_mm", "the pitch h in mm")?;
    let pitch_mm = pitch.number(Range::Positive, "the pitch h in mm")?;
    if pitch_mm < wire_diameter_mm {
        return Err(pitch.error(
            format!(
                "{pitch_mm} is below the wire diameter {wire_diameter_mm}: the coils would overlap"
            ),
            "a pitch at least the wire diameter",
        ));
    }
    // The FE model's orientation vector is the spring axis; it must not be parallel to
    // the wire (pitch angle below 63 degrees), as coil_mesher checks.
    if pitch_mm >= 2.0 * std::f64::consts::PI * mean_diameter_mm {
        return Err(pitch.error(
            format!("{pitch_mm} gives a pitch angle above 63 degrees"),
            "a pitch below 2 pi D",
        ));
    }
    Ok(SpringGeometry {
        active_coils,
        mean_diameter_mm,
        wire_diameter_mm,
        pitch_mm,
    })
}

fn read_material(o: &Object<'_>) -> Result<NominalMaterial, FieldError> {
    Ok(NominalMaterial {
        youngs_modulus_mpa: o.number(
            "youngs_modulus_mpa",
            Range::Positive,
            "the nominal Young's modulus in MPa",
        )?,
        poisson_ratio: o.number("poisson_ratio", Range::Open(-1.0, 0.5), "Poisson's ratio")?,
        density_kg_m3: o.number(
            "density_kg_m3",
            Range::Positive,
            "the wire's density in kg/m^3",
        )?,
    })
}

impl MeasuredCase {
    /// The case folder (where the record paths are resolved).
    pub fn folder(&self) -> PathBuf {
        self.file
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default()
    }

    /// A target, or an error naming the missing `targets.<name>` field.
    pub fn target(&self, name: &'static str) -> Result<f64, CaseError> {
        let value = match name {
            "stiffness_n_mm" => self.targets.stiffness_n_mm,
            "damping_ratio" => self.targets.damping_ratio,
            _ => self.targets.period_s,
        };
        value.ok_or_else(|| {
            let (line, column) = self.targets_at.unwrap_or((1, 1));
            CaseError::Field(FieldError {
                file: self.file.clone(),
                line,
                column,
                field: format!("targets.{name}"),
                problem: if self.targets_at.is_some() {
                    "missing in this object".into()
                } else {
                    "missing: the case has no `targets`".into()
                },
                expected: "the target figure, or a number in place of `target` in a procedure"
                    .into(),
            })
        })
    }

    /// Reads every static record.
    pub fn static_records(&self) -> Result<Vec<StaticRecord>, CaseError> {
        self.static_files
            .iter()
            .map(|p| read_static_record(p))
            .collect()
    }

    /// Reads every decay record as written (any of the spec's columns, time stamps as
    /// read: [`read_decay`]).
    pub fn measured_decays(&self) -> Result<Vec<MeasuredDecay>, CaseError> {
        Ok(self
            .measured_decays_with_format()?
            .into_iter()
            .map(|(decay, _)| decay)
            .collect())
    }

    /// [`MeasuredCase::measured_decays`] with each file's format as detected, in words
    /// (`coil_postproc::record::Record::format`).
    pub fn measured_decays_with_format(&self) -> Result<Vec<(MeasuredDecay, String)>, CaseError> {
        (0..self.decay_files.len())
            .map(|k| read_decay(&self.decay_spec(k)))
            .collect()
    }

    /// The record spec of decay record `k` (its file and how its entry says to read it).
    pub fn decay_spec(&self, k: usize) -> RecordSpec {
        let file = &self.decay_files[k];
        self.decay_info
            .get(k)
            .map_or_else(|| RecordSpec::file(file), |i| i.reading.spec(file))
    }

    /// Reads every decay record as an acceleration signal (uniform time, finite values;
    /// a velocity or position record is an error: these commands fit accelerations).
    pub fn decay_records(&self) -> Result<Vec<Signal>, CaseError> {
        (0..self.decay_files.len())
            .map(|k| {
                let record = coil_postproc::record::read_record(&self.decay_spec(k))?;
                Ok(coil_postproc::record::acceleration_signal(record)?)
            })
            .collect()
    }
}

impl MeasuredCase {
    /// A warning when a decay's size is implausible for its stated unit (the classic
    /// silent error: a record in g read as m/s^2 is 9.81 times too small, one in mm/s^2
    /// read as m/s^2 1000 times too large).
    ///
    /// The record's displacement amplitude is `A = a_peak / w^2` (w = 2 pi f, f its
    /// crossing frequency); the weight's static deflection is `x_st = m g / k`, with k the
    /// slope of the static record when there is one, else `m w^2` (then `x_st = g / w^2`
    /// and the test reads `a_peak` against g). A free decay of a weight resting on its
    /// spring stays within its static deflection (beyond it the spring unloads every
    /// cycle) and a lab records it well above its sensor's floor: the warning is given
    /// when `A / x_st` is above 1 or below 1e-3. A factor 9.81 inside that band is not
    /// detectable from the record: the unit the file or the case states decides. Without
    /// gravity (no preload) nothing is checked here (`diagnose`'s travel check still is).
    pub fn unit_warning(&self, acceleration_m_s2: &[f64], frequency_hz: f64) -> Option<String> {
        if self.gravity_m_s2 <= 0.0
            || frequency_hz.is_nan()
            || frequency_hz <= 0.0
            || acceleration_m_s2.is_empty()
        {
            return None;
        }
        let n = acceleration_m_s2.len() as f64;
        let mean = acceleration_m_s2.iter().sum::<f64>() / n;
        let peak = acceleration_m_s2
            .iter()
            .fold(0.0_f64, |m, a| m.max((a - mean).abs()));
        let w2 = (std::f64::consts::TAU * frequency_hz).powi(2);
        let amplitude_m = peak / w2;
        let static_k = self
            .static_records()
            .ok()
            .and_then(|r| r.into_iter().next())
            .and_then(|r| static_slope_n_m(&r));
        let (k, source) = match static_k {
            Some(k) => (k, "the static record's slope"),
            None => (self.mass_kg * w2, "the record's own frequency"),
        };
        let static_m = self.mass_kg * self.gravity_m_s2 / k;
        let ratio = amplitude_m / static_m;
        let what = if ratio > 1.0 {
            "above the static deflection: the spring would unload every cycle"
        } else if ratio < 1e-3 {
            "below a thousandth of the static deflection"
        } else {
            return None;
        };
        Some(format!(
            "the decay's displacement amplitude {:.4e} m (peak {peak:.4e} m/s^2 at \
             {frequency_hz:.3} Hz) is {ratio:.3e} times the weight's static deflection \
             {static_m:.4e} m (k from {source}), {what}; check the record's unit (a record in \
             g read as m/s^2 is 9.81 times too small, one in mm/s^2 read as m/s^2 1000 times \
             too large): state it as the record entry's `unit`",
            amplitude_m
        ))
    }
}

/// The longest variant name, characters.
pub const MAX_NAME_CHARS: usize = 100;

/// A variant's name: one printable line of 1 to [`MAX_NAME_CHARS`] characters (it
/// reaches tables, reports, figure labels and deck titles; commas and quotes are fine,
/// tables quote them).
pub fn check_name(name: &str) -> std::result::Result<(), String> {
    let printable = !name.chars().any(|c| {
        c.is_control()
            || ('\u{202a}'..='\u{202e}').contains(&c)
            || ('\u{2066}'..='\u{2069}').contains(&c)
    });
    let count = name.chars().count();
    if printable && (1..=MAX_NAME_CHARS).contains(&count) && name.trim() == name {
        Ok(())
    } else {
        Err(format!(
            "variant name `{}`; expected one printable line of 1 to {MAX_NAME_CHARS} characters, without blanks at its ends",
            coil_io::excerpt(name)
        ))
    }
}

/// One alternative spring of a variants file (Table 4), with the paper's figures if given.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct Variant {
    /// Its name.
    pub name: String,
    /// The spring geometry.
    pub spring: SpringGeometry,
    /// The paper's K, N/mm.
    pub paper_stiffness_n_mm: Option<f64>,
    /// The paper's zeta (-).
    pub paper_damping_ratio: Option<f64>,
}

/// A variants file: `{"source": .., "variants": [{"name", "active_coils",
/// "mean_diameter_mm", "wire_diameter_mm", "pitch_mm", "paper_stiffness_n_mm"?,
/// "paper_damping_ratio"?}, ..]}`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VariantsFile {
    /// The file it was read from.
    pub file: PathBuf,
    /// Where the values come from (a citation), if given.
    pub source: Option<String>,
    /// The variants.
    pub variants: Vec<Variant>,
}

/// Reads and checks a variants file (at least one variant, unique names).
pub fn read_variants(path: &Path) -> Result<VariantsFile, CaseError> {
    let (_, node) = read_json(path)?;
    let top = root(path, &node);
    let doc = top.object("a variants file with a `variants` list")?;
    let source = doc.opt_string("source", "a description of the variants")?;
    let list = doc.require("variants", "a list of spring variants")?;
    let items = list.array("a list of spring variants")?;
    if items.is_empty() {
        return Err(list
            .error("the list is empty", "at least one spring variant")
            .into());
    }
    let mut variants: Vec<Variant> = Vec::with_capacity(items.len());
    for item in &items {
        let o = item.object("a spring variant")?;
        let name_field = o.require("name", "the variant's name")?;
        let name = name_field.string("the variant's name")?.to_string();
        if let Err(e) = check_name(&name) {
            return Err(name_field
                .error(
                    e,
                    "one printable line (it reaches tables, reports and deck titles)",
                )
                .into());
        }
        if variants.iter().any(|v| v.name == name) {
            return Err(name_field
                .error(
                    format!("the name {name} is used twice"),
                    "unique variant names",
                )
                .into());
        }
        variants.push(Variant {
            name,
            spring: read_geometry(&o)?,
            paper_stiffness_n_mm: o.opt_number(
                "paper_stiffness_n_mm",
                Range::Positive,
                "the paper's stiffness in N/mm",
            )?,
            paper_damping_ratio: o.opt_number(
                "paper_damping_ratio",
                Range::Open(0.0, 1.0),
                "the paper's damping ratio",
            )?,
        });
    }
    Ok(VariantsFile {
        file: path.to_path_buf(),
        source,
        variants,
    })
}
