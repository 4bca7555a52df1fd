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

use crate::fields::{root, Field, FieldError, Object, Range};
use crate::json;
use coil_postproc::record::RecordSpec;
use coil_postproc::signal::Signal;
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

/// Everything that can be wrong with a case, a variants file or a record.
#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    #[error("{}: cannot read the file: {source}", path.display())]
    /// Reading or writing failed.
    Io {
        /// The file.
        path: PathBuf,
        /// Where the values come from (a citation), if given.
        source: std::io::Error,
    },
    #[error("{}:{line}:{column}: invalid JSON: {message}", path.display())]
    /// A file that is not valid JSON.
    Syntax {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: usize,
        /// Its column (1-based).
        column: usize,
        /// What is wrong and what was expected.
        message: String,
    },
    #[error(transparent)]
    /// A field missing or out of range.
    Field(#[from] FieldError),
    /// An input outside its limits or its folder (docs/files.md).
    #[error(transparent)]
    Input(#[from] coil_io::ConfineError),
    /// A record file (decay) that the post-processor cannot read.
    #[error(transparent)]
    Record(#[from] coil_postproc::PostError),
    /// A decay record whose columns or time stamps are wrong.
    #[error("{}:{line}: {problem}; expected {expected}", path.display())]
    DecayRecord {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: usize,
        /// What is wrong.
        problem: String,
        /// What was expected.
        expected: String,
    },
    /// A static record that cannot be read.
    #[error("{}:{line}: {problem}; expected {expected}", path.display())]
    StaticRecord {
        /// The file.
        path: PathBuf,
        /// Its line (1-based).
        line: usize,
        /// What is wrong.
        problem: String,
        /// What was expected.
        expected: String,
    },
}

/// A bounded read's error: an unreadable file stays [`CaseError::Io`].
fn input(e: coil_io::ConfineError) -> CaseError {
    match e {
        coil_io::ConfineError::Io { path, source } => CaseError::Io { path, source },
        other => CaseError::Input(other),
    }
}

/// Reads a JSON input (bounded in size) into a located tree; errors name the file,
/// line and column.
pub fn read_json(path: &Path) -> Result<(String, json::Node), CaseError> {
    let text =
        coil_io::read_bounded(path, coil_io::MAX_JSON_BYTES, "a JSON input").map_err(input)?;
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

/// The format note of a record for the report: `None` for coil's own CSV (comma, decimal
/// point), else the dialect or format detected (`coil_postproc::record`).
pub fn format_note(file: &Path, format: &str) -> Option<String> {
    (!format.starts_with("CSV: delimiter ',', decimal point"))
        .then(|| format!("{}: read as {format}", file.display()))
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
            "the decay's displacement amplitude {:.4e} m (peak {peak:.4e} m/s^2 at {frequency_hz:.3} Hz) is              {ratio:.3e} times the weight's static deflection {static_m:.4e} m (k from {source}), {what};              check the record's unit (a record in g read as m/s^2 is 9.81 times too small, one in mm/s^2              read as m/s^2 1000 times too large): state it as the record entry's `unit`",
            amplitude_m
        ))
    }
}

/// The least-squares slope of a static record's force against its compression, N/m
/// (`None` when it is not positive).
fn static_slope_n_m(r: &StaticRecord) -> Option<f64> {
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
    let text =
        coil_io::read_bounded(path, coil_io::MAX_RECORD_BYTES, "a record (CSV)").map_err(input)?;
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
        if let Err(e) = crate::study::check_name(&name) {
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

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"{
  "name": "spring 3, rig B",
  "spring": {
    "active_coils": 14.0,
    "mean_diameter_mm": 24.0,
    "wire_diameter_mm": 3.0,
    "pitch_mm": 6.2
  },
  "material": {
    "youngs_modulus_mpa": 206000.0,
    "poisson_ratio": 0.3,
    "density_kg_m3": 7850.0
  },
  "mass_kg": 5.3,
  "gravity_m_s2": 9.81,
  "records": { "static": ["static.csv"], "decay": ["decay.csv"] },
  "future_field": {"anything": [1, 2]}
}"#;

    fn folder_with(case: &str) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("case.json"), case).unwrap();
        std::fs::write(
            dir.path().join("static.csv"),
            "displacement_mm,force_n\n0,0\n1,3.9\n2,7.9\n",
        )
        .unwrap();
        let mut decay = String::from("time_s,accel_m_s2\n");
        for i in 0..100 {
            let t = i as f64 * 1e-3;
            decay.push_str(&format!("{t},{}\n", (27.3 * t).sin()));
        }
        std::fs::write(dir.path().join("decay.csv"), decay).unwrap();
        dir
    }

    /// The spec's example, verbatim plus an unknown member, is read from the folder.
    #[test]
    fn the_spec_example_is_read() {
        let dir = folder_with(GOOD);
        let case = read_case(dir.path()).unwrap();
        assert_eq!(case.name, "spring 3, rig B");
        assert_eq!(case.spring.pitch_mm, 6.2);
        assert_eq!(case.material.poisson_ratio, 0.3);
        assert_eq!(case.mass_kg, 5.3);
        assert_eq!(case.static_files, vec![dir.path().join("static.csv")]);
        assert_eq!(case.targets, Targets::default());
        let statics = case.static_records().unwrap();
        assert_eq!(statics[0].force_n, vec![0.0, 3.9, 7.9]);
        let decays = case.decay_records().unwrap();
        assert_eq!(decays[0].values().len(), 100);
    }

    /// Each broken field is named with its line and what was expected.
    #[test]
    fn broken_fields_are_located() {
        for (from, to, field, line) in [
            ("\"mass_kg\": 5.3,", "\"mass_kg\": -5.3,", "mass_kg", 14),
            ("\"mass_kg\": 5.3,", "", "mass_kg", 1),
            (
                "\"pitch_mm\": 6.2",
                "\"pitch_mm\": \"6.2\"",
                "spring.pitch_mm",
                7,
            ),
            (
                "\"wire_diameter_mm\": 3.0",
                "\"wire_diameter_mm\": 30.0",
                "spring.wire_diameter_mm",
                6,
            ),
            (
                "\"poisson_ratio\": 0.3",
                "\"poisson_ratio\": 0.5",
                "material.poisson_ratio",
                11,
            ),
            ("\"decay.csv\"", "\"nope.csv\"", "records.decay[0]", 16),
            ("\"active_coils\": 14.0,", "", "spring.active_coils", 3),
        ] {
            let dir = folder_with(&GOOD.replacen(from, to, 1));
            match read_case(dir.path()) {
                Err(CaseError::Field(e)) => {
                    assert_eq!(e.field, field, "{e}");
                    assert_eq!(e.line, line, "{e}");
                    let shown = e.to_string();
                    assert!(
                        shown.contains("case.json:") && shown.contains("expected"),
                        "{shown}"
                    );
                }
                other => panic!("{field}: {other:?}"),
            }
        }
    }

    #[test]
    fn syntax_errors_and_missing_files() {
        let dir = folder_with("{\"name\": \"x\",\n \"spring\": }");
        match read_case(dir.path()) {
            Err(CaseError::Syntax { line, .. }) => assert_eq!(line, 2),
            other => panic!("{other:?}"),
        }
        let empty = tempfile::tempdir().unwrap();
        assert!(matches!(read_case(empty.path()), Err(CaseError::Io { .. })));
    }

    #[test]
    fn static_record_errors_name_the_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("static.csv");
        for (text, line, needle) in [
            ("displacement_mm,force\n0,1\n", 1, "force_n"),
            ("displacement_mm,force_n\n0,1\n1,NaN\n", 3, "not finite"),
            ("# rig B\ndisplacement_mm,force_n\n0,1\n\n1\n", 5, "fields"),
            ("displacement_mm,force_n\n0,x\n", 2, "not a number"),
            ("displacement_mm,force_n\n0,1\n", 1, "at least 2 rows"),
        ] {
            std::fs::write(&path, text).unwrap();
            match read_static_record(&path) {
                Err(CaseError::StaticRecord {
                    line: l, problem, ..
                }) => {
                    assert_eq!(l, line, "{text}");
                    let all = format!("{problem} {}", read_static_record(&path).unwrap_err());
                    assert!(all.contains(needle), "{all}");
                }
                other => panic!("{text}: {other:?}"),
            }
        }
    }

    /// Decay records: one of the three columns (SI once read), two at once refused
    /// with both names and the header line, none refused with the header listed, time
    /// stamps that go back refused with their line.
    #[test]
    fn decay_record_columns() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("decay.csv");
        let rows = |header: &str| {
            let mut s = format!("# rig B\n{header}\n");
            for i in 0..10 {
                s.push_str(&format!("{},{}\n", i as f64 * 0.01, 1.5 + i as f64));
            }
            s
        };
        for (column, quantity, first) in [
            ("accel_m_s2", Quantity::Acceleration, 1.5),
            ("velocity_m_s", Quantity::Velocity, 1.5),
            ("displacement_mm", Quantity::Displacement, 1.5e-3),
        ] {
            std::fs::write(&path, rows(&format!("time_s,{column}"))).unwrap();
            let r = read_decay_record(&path).unwrap();
            assert_eq!(r.quantity, quantity);
            assert_eq!(r.values[0], first);
            assert_eq!(r.lines[0], 3);
        }
        std::fs::write(
            &path,
            rows("time_s,displacement_mm,accel_m_s2").replace(",1", ",1,2"),
        )
        .unwrap();
        let e = read_decay_record(&path).unwrap_err().to_string();
        assert!(
            e.contains("decay.csv:2:") && e.contains("`accel_m_s2` and `displacement_mm`"),
            "{e}"
        );
        std::fs::write(&path, rows("time_s,accel")).unwrap();
        let e = read_decay_record(&path).unwrap_err().to_string();
        assert!(
            e.contains("decay.csv:2:") && e.contains("columns: time_s, accel"),
            "{e}"
        );
        std::fs::write(&path, "time_s,accel_m_s2\n0,1\n0.01,2\n0.005,3\n0.02,1\n").unwrap();
        let e = read_decay_record(&path).unwrap_err().to_string();
        assert!(e.contains("decay.csv:4:") && e.contains("increase"), "{e}");
    }

    /// The paper's case and Table 4 as shipped under `cases/160ect`.
    #[test]
    fn the_paper_case_and_table4_are_read() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect");
        let case = read_case(&root).unwrap();
        assert_eq!(case.targets.stiffness_n_mm, Some(3.9275));
        assert_eq!(case.targets.period_s, Some(0.23));
        assert_eq!(case.tested_springs.len(), 4);
        let mean: f64 = case
            .tested_springs
            .iter()
            .map(|s| s.stiffness_n_mm)
            .sum::<f64>()
            / 4.0;
        assert!(
            (mean - 3.9275).abs() < 1e-12,
            "Table 1's mean is the target"
        );
        let paper = case.paper.unwrap();
        assert_eq!(paper.youngs_modulus_mpa, Some(190708.0));
        assert_eq!(paper.rayleigh_beta, Some(0.00012));
        let table4 = read_variants(&root.join("table4.json")).unwrap();
        assert_eq!(table4.variants.len(), 6);
        assert_eq!(table4.variants[5].spring.active_coils, 16.0);
        assert_eq!(table4.variants[1].paper_damping_ratio, Some(0.00246));
    }

    #[test]
    fn variants_need_unique_names() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("v.json");
        let one = r##"{"name": "#1", "active_coils": 14, "mean_diameter_mm": 28, "wire_diameter_mm": 3, "pitch_mm": 6.2}"##;
        std::fs::write(&path, format!("{{\"variants\": [{one},\n{one}]}}")).unwrap();
        match read_variants(&path) {
            Err(CaseError::Field(e)) => {
                assert_eq!((e.field.as_str(), e.line), ("variants[1].name", 2))
            }
            other => panic!("{other:?}"),
        }
        std::fs::write(&path, format!("{{\"variants\": [{one}]}}")).unwrap();
        let v = read_variants(&path).unwrap();
        assert_eq!(v.variants[0].spring.mean_diameter_mm, 28.0);
        assert_eq!(v.variants[0].paper_stiffness_n_mm, None);
    }
}
