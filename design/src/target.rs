//! Reading `TARGET.json`, the design target of `coil-tune design` (docs/spring-design.md),
//! and resolving its material (a wire grade, or a `calibration.json` of
//! `coil-tune calibrate`).
//!
//! Keys: `rate_n_mm`, `rate_tolerance_percent`, optional `weight_kg` and `damping_ratio`,
//! `force_1_n` and `force_2_n` (or `length_1_mm` and `length_2_mm`),
//! `springs_in_parallel` (default 1), `envelope` {`max_outer_diameter_mm`,
//! `min_inner_diameter_mm`, `max_free_length_mm`, `max_solid_length_mm`}, `material`
//! {`calibration`: a path} or {`grade`: a name} (both: the calibration's E and density
//! with the grade's Rm; beside a calibration, `damping`: a damping.json of `coil-tune
//! damping` whose identified law is predicted too), `objective` (`lightest` or
//! `stress_margin`). `damping_coefficient_n_s_m` (with `weight_kg`) may replace
//! `damping_ratio`: `zeta = c / (2 sqrt(K m))` on the target rate. Optional, with the
//! defaults written into `design.json`'s `target`: `end_type` (`closed_ground`),
//! `coiling` (`cold`), `loading` (`dynamic`), `seating_coefficient` (0.5: both ends
//! fixed, the top guided, as the paper's test; 0.5 to 2), `surge_band_hz` ([lo, hi]: the
//! surge mode must stay outside), `short_list` (8, a whole number from 1 to 32),
//! `shot_peened` (false: the fatigue diagram), `quality_grade` (EN 15800 grade of the
//! tolerances, 2), `source`, `notes`, `name` and `comment` (free text: strings). A
//! `damping` beside a grade alone is refused (it needs a calibration). An unknown key, here or inside `envelope` or `material`, is
//! refused with the list of known ones; an explicit `null` is refused (leave the key out).
//!
//! Bounds checked before the search starts (docs/files.md): at most
//! [`MAX_SPRINGS_IN_PARALLEL`] springs in parallel, and the search's count of springs to
//! check (every wire, mean diameter and quarter turn within the rate tolerance, the
//! active coils capped by EN 15800's longest free length, 630 mm) at most
//! [`crate::search::MAX_TRIED`].
//!
//! The rate, the forces and the weight are the whole suspension's: `springs_in_parallel`
//! springs share them equally.

use crate::case::{read_json, CaseError};
use crate::fe::{FeSettings, SpringState};
use crate::fields::{root, FieldError, Object, Range};
use crate::sheet::en13906::{Coiling, EndType, Loading, Working};
use crate::sheet::input::{
    choice, free_text, num, opt_bool, quality_grade, seating_coefficient, working, COILING,
    END_TYPES, LOADING,
};
use crate::sheet::sig;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What the ranking maximises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
#[value(rename_all = "snake_case")]
pub enum Objective {
    /// The lightest wire first.
    Lightest,
    /// The largest working-stress margin `1 - tau / (0.5 Rm)` first.
    StressMargin,
}

/// The envelope a spring must fit (each bound optional).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Envelope {
    /// Largest outer diameter De (mm), e.g. a bore.
    pub max_outer_diameter_mm: Option<f64>,
    /// Smallest inner diameter Di (mm), e.g. a guide pin.
    pub min_inner_diameter_mm: Option<f64>,
    /// Longest free length L0 (mm).
    pub max_free_length_mm: Option<f64>,
    /// Longest solid length Lc (mm).
    pub max_solid_length_mm: Option<f64>,
}

/// Where the material comes from, as the target names it.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MaterialSource {
    /// A calibration.json (path as resolved), with an optional grade for Rm and an
    /// optional damping.json of `coil-tune damping`.
    Calibration {
        /// The file.
        calibration: PathBuf,
        /// The EN 10270-1 grade for Rm.
        grade: Option<String>,
        /// A damping.json whose identified law (if any) is predicted beside the band.
        damping: Option<PathBuf>,
    },
    /// An EN 10270-1 grade with the handbook moduli.
    Grade {
        /// The grade's name.
        grade: String,
    },
}

/// A design target.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Target {
    /// Rate of the whole suspension (N/mm).
    pub rate_n_mm: f64,
    /// Relative tolerance on the rate (%).
    pub rate_tolerance_percent: f64,
    /// The suspended mass (kg), all springs together.
    pub weight_kg: Option<f64>,
    /// The wanted damping ratio of the weight's mode (-).
    pub damping_ratio: Option<f64>,
    /// The two working points of the suspension.
    pub working: Working,
    /// Springs sharing the rate, the loads and the weight.
    pub springs_in_parallel: u32,
    /// The envelope.
    pub envelope: Envelope,
    /// The material.
    pub material: MaterialSource,
    /// The ranking.
    pub objective: Objective,
    /// End type of the springs searched.
    pub end_type: EndType,
    /// Cold or hot coiled.
    pub coiling: Coiling,
    /// Static or dynamic loading.
    pub loading: Loading,
    /// Seating coefficient for buckling.
    pub seating_coefficient: f64,
    /// A band the surge mode must avoid (Hz).
    pub surge_band_hz: Option<(f64, f64)>,
    /// How many of the best handbook candidates the FE model verifies.
    pub short_list: usize,
    /// Shot-peened springs (the fatigue diagram).
    pub shot_peened: bool,
    /// EN 15800 quality grade of the tolerances (1, 2 or 3).
    pub quality_grade: u8,
}

/// The keys of `TARGET.json`.
pub const TARGET_KEYS: [&str; 25] = [
    "rate_n_mm",
    "rate_tolerance_percent",
    "weight_kg",
    "damping_ratio",
    "damping_coefficient_n_s_m",
    "force_1_n",
    "force_2_n",
    "length_1_mm",
    "length_2_mm",
    "springs_in_parallel",
    "envelope",
    "material",
    "objective",
    "end_type",
    "coiling",
    "loading",
    "seating_coefficient",
    "surge_band_hz",
    "short_list",
    "shot_peened",
    "quality_grade",
    "source",
    "notes",
    "name",
    "comment",
];

/// The keys of `envelope`.
pub const ENVELOPE_KEYS: [&str; 4] = [
    "max_outer_diameter_mm",
    "min_inner_diameter_mm",
    "max_free_length_mm",
    "max_solid_length_mm",
];

/// The keys of `material`.
pub const MATERIAL_KEYS: [&str; 3] = ["calibration", "grade", "damping"];

/// The most springs in parallel a target may share its rate among (a suspension of more
/// is a different product; the bound keeps the search's work finite, docs/files.md).
pub const MAX_SPRINGS_IN_PARALLEL: f64 = 64.0;

/// The bounds of `weight_kg` (kg, exclusive): a gram's thousandth to a thousand tonnes
/// (the FE model carries it as a point mass; outside, the figures are a unit slip).
pub const MIN_WEIGHT_KG: f64 = 1e-6;
/// See [`MIN_WEIGHT_KG`].
pub const MAX_WEIGHT_KG: f64 = 1e6;

/// The most springs the FE verification runs (a short list of at most this many).
pub const MAX_SHORT_LIST: f64 = 32.0;

/// `source` with its calibration replaced by `file` (a grade keeps giving Rm; a
/// damping.json beside the old calibration stays).
pub fn with_calibration(source: &MaterialSource, file: PathBuf) -> MaterialSource {
    match source {
        MaterialSource::Calibration { grade, damping, .. } => MaterialSource::Calibration {
            calibration: file,
            grade: grade.clone(),
            damping: damping.clone(),
        },
        MaterialSource::Grade { grade } => MaterialSource::Calibration {
            calibration: file,
            grade: Some(grade.clone()),
            damping: None,
        },
    }
}

/// An optional whole number from 1 to `max` (`meaning` says what it counts).
fn whole(o: &Object<'_>, key: &str, max: f64, meaning: &str) -> Result<Option<f64>, FieldError> {
    let expected = format!("{meaning}, a whole number from 1 to {max}");
    match o.get(key) {
        None => Ok(None),
        Some(f) => {
            let n = f.number(Range::Count, &expected)?;
            if n > max {
                return Err(f.error(format!("{} is out of range", num(n)), expected));
            }
            Ok(Some(n))
        }
    }
}

/// The target's `envelope` (every bound optional; none: no envelope).
fn read_envelope(o: &Object<'_>) -> Result<Envelope, FieldError> {
    Ok(match o.get("envelope") {
        None => Envelope::default(),
        Some(f) => {
            let e = f.object("the envelope")?;
            e.strict(&ENVELOPE_KEYS)?;
            let bound = |key: &str, meaning: &str| e.opt_number(key, Range::Positive, meaning);
            Envelope {
                max_outer_diameter_mm: bound("max_outer_diameter_mm", "the largest De (mm)")?,
                min_inner_diameter_mm: bound("min_inner_diameter_mm", "the smallest Di (mm)")?,
                max_free_length_mm: bound("max_free_length_mm", "the longest L0 (mm)")?,
                max_solid_length_mm: bound("max_solid_length_mm", "the longest Lc (mm)")?,
            }
        }
    })
}

/// The target's `material`: a calibration (relative to the target's folder), a grade, or both.
fn read_material(o: &Object<'_>, path: &Path) -> Result<MaterialSource, FieldError> {
    let material_field = o.require("material", "{\"calibration\": path} or {\"grade\": name}")?;
    let m = material_field.object("the material")?;
    m.strict(&MATERIAL_KEYS)?;
    let grade = match m.get("grade") {
        None => None,
        Some(f) => {
            let name = f.string("an EN 10270-1 grade name, e.g. \"DH\"")?;
            Some(crate::sheet::grades::known(name).map_err(|e| {
                f.error(
                    e,
                    format!("one of {}", crate::sheet::grades::GRADES.join(", ")),
                )
            })?)
        }
    };
    let beside = |file: String| path.parent().unwrap_or(Path::new(".")).join(file);
    let calibration = m.opt_string("calibration", "a calibration.json path")?;
    Ok(match (calibration, grade) {
        (Some(file), grade) => MaterialSource::Calibration {
            calibration: beside(file),
            grade,
            damping: m
                .opt_string("damping", "a damping.json path (coil-tune damping)")?
                .map(beside),
        },
        (None, Some(grade)) => {
            if let Some(f) = m.get("damping") {
                return Err(f.error(
                    "a damping.json beside a grade alone",
                    "a damping.json only beside a calibration (its law is carried from the calibrated decay); leave `damping` out with a grade",
                ));
            }
            MaterialSource::Grade { grade }
        }
        (None, None) => {
            return Err(m.error(
                "neither a calibration nor a grade",
                "{\"calibration\": path} or {\"grade\": name}",
            ))
        }
    })
}

/// Reads `TARGET.json`; a relative calibration path is taken from the target's folder.
pub fn read_target(path: &Path) -> Result<Target, CaseError> {
    let (_, node) = read_json(path)?;
    let top = root(path, &node);
    let o = top.object("a design target (docs/spring-design.md)")?;
    o.strict(&TARGET_KEYS)?;
    free_text(&o, &["source", "notes", "name", "comment"])?;
    let working = working(&o)?.ok_or_else(|| {
        o.error(
            "no working points",
            "force_1_n and force_2_n (or length_1_mm and length_2_mm)",
        )
    })?;
    let envelope = read_envelope(&o)?;
    let material = read_material(&o, path)?;
    let rate = o.number("rate_n_mm", Range::Positive, "the target rate (N/mm)")?;
    let weight = o.opt_number(
        "weight_kg",
        Range::Open(MIN_WEIGHT_KG, MAX_WEIGHT_KG),
        "the suspended mass (kg)",
    )?;
    let mut zeta = o.opt_number("damping_ratio", Range::Open(0.0, 1.0), "a damping ratio")?;
    if let Some(c) = o.opt_number(
        "damping_coefficient_n_s_m",
        Range::Positive,
        "a damping coefficient at the weight (N s/m)",
    )? {
        // zeta = c / (2 sqrt(K m)) of the weight on the target rate.
        match (zeta, weight) {
            (None, Some(w)) => {
                let z = c / (2.0 * (rate * 1e3 * w).sqrt());
                if z >= 1.0 {
                    let field = o.require("damping_coefficient_n_s_m", "")?;
                    return Err(field
                        .error(
                            format!("c = {} N s/m gives zeta = c / (2 sqrt(K m)) = {} at K = {} N/mm and {} kg", num(c), num(z), num(rate), num(w)),
                            format!("a coefficient below critical damping, {} N s/m", num(2.0 * (rate * 1e3 * w).sqrt())),
                        )
                        .into());
                }
                zeta = Some(z)
            }
            _ => return Err(o
                .error(
                    "damping_coefficient_n_s_m needs weight_kg and excludes damping_ratio",
                    "one of damping_ratio and damping_coefficient_n_s_m, the latter with weight_kg",
                )
                .into()),
        }
    }
    let band = match o.get("surge_band_hz") {
        None => None,
        Some(f) => {
            let items = f.array("[lo, hi] in Hz")?;
            let values = items
                .iter()
                .map(|i| i.number(Range::NonNegative, "a frequency (Hz)"))
                .collect::<Result<Vec<_>, _>>()?;
            match values[..] {
                [lo, hi] if hi > lo => Some((lo, hi)),
                _ => {
                    return Err(f
                        .error("not two increasing frequencies", "[lo, hi] in Hz")
                        .into())
                }
            }
        }
    };
    Ok(Target {
        rate_n_mm: rate,
        rate_tolerance_percent: o.number(
            "rate_tolerance_percent",
            Range::Open(0.0, 50.0),
            "the rate tolerance (%)",
        )?,
        weight_kg: weight,
        damping_ratio: zeta,
        working,
        springs_in_parallel: whole(
            &o,
            "springs_in_parallel",
            MAX_SPRINGS_IN_PARALLEL,
            "the springs in parallel",
        )?
        .unwrap_or(1.0) as u32,
        envelope,
        material,
        objective: choice(
            &o,
            "objective",
            &[
                ("lightest", Objective::Lightest),
                ("stress_margin", Objective::StressMargin),
            ],
            None,
        )?,
        end_type: choice(&o, "end_type", &END_TYPES, Some(EndType::ClosedGround))?,
        coiling: choice(&o, "coiling", &COILING, Some(Coiling::Cold))?,
        loading: choice(&o, "loading", &LOADING, Some(Loading::Dynamic))?,
        seating_coefficient: seating_coefficient(&o)?,
        surge_band_hz: band,
        short_list: whole(
            &o,
            "short_list",
            MAX_SHORT_LIST,
            "how many candidates the FE verifies",
        )?
        .unwrap_or(8.0) as usize,
        shot_peened: opt_bool(&o, "shot_peened", "whether the springs are shot-peened")?
            .unwrap_or(false),
        quality_grade: quality_grade(&o)?,
    })
}

pub use crate::sheet::input::HANDBOOK_STEEL;

/// The damping a calibration identified: its spring, weight and Rayleigh pair, and the
/// measured zeta it was calibrated to.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DampingReference {
    /// The calibrated state (geometry, E, mass, alpha, beta).
    pub state: SpringState,
    /// The measured damping ratio of its weight mode (-).
    pub damping_ratio: f64,
}

/// A damping.json's identified law: its name and its parameters by their spec names.
pub type IdentifiedLaw = (String, BTreeMap<String, f64>);

/// The resolved material of a design.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Material {
    /// E (MPa).
    pub youngs_modulus_mpa: f64,
    /// G (MPa).
    pub shear_modulus_mpa: f64,
    /// Poisson's ratio of the FE model, E / (2 G) - 1.
    pub poisson_ratio: f64,
    /// Density (kg/m^3).
    pub density_kg_m3: f64,
    /// The EN 10270-1 grade giving Rm(d).
    pub grade: String,
    /// The FE settings (the calibration's mesh: its E belongs to it).
    pub fe: FeSettings,
    /// The damping reference, with a calibration.
    pub damping: Option<DampingReference>,
    /// The law a damping.json identified and its parameters (its spec names).
    pub identified_law: Option<IdentifiedLaw>,
    /// Where each value comes from, in words.
    pub source: String,
}

/// Resolves the target's material. A grade alone takes the handbook moduli and has no
/// damping reference; a calibration gives E, Poisson's ratio, density, the mesh and the
/// damping (Rm from the grade given beside it, DM otherwise: said in `source`).
pub fn material(target: &Target) -> Result<Material, crate::TuneError> {
    match &target.material {
        MaterialSource::Grade { grade } => {
            let (e, g, rho) = HANDBOOK_STEEL;
            Ok(Material {
                youngs_modulus_mpa: e,
                shear_modulus_mpa: g,
                poisson_ratio: e / (2.0 * g) - 1.0,
                density_kg_m3: rho,
                grade: grade.clone(),
                fe: FeSettings::default(),
                damping: None,
                identified_law: None,
                source: format!(
                    "EN 10270-1 {grade}: E = {e} MPa, G = {g} MPa, rho = {rho} kg/m^3 (EN 13906-1 handbook values); no damping law (give a calibration for the zeta band)"
                ),
            })
        }
        MaterialSource::Calibration {
            calibration,
            grade,
            damping,
        } => {
            let text =
                coil_io::read_bounded(calibration, coil_io::MAX_JSON_BYTES, "a calibration.json")?;
            #[derive(serde::Deserialize)]
            struct Targets {
                damping_ratio: f64,
            }
            #[derive(serde::Deserialize)]
            struct Settings {
                fe: FeSettings,
            }
            #[derive(serde::Deserialize)]
            struct File {
                state: SpringState,
                targets: Targets,
                settings: Settings,
            }
            let file: File = serde_json::from_str(&text).map_err(|e| crate::TuneError::Json {
                path: calibration.clone(),
                line: e.line(),
                message: format!(
                    "{e}; expected a calibration.json written by `coil-tune calibrate` (state, targets, settings)"
                ),
            })?;
            let s = file.state;
            let grade = grade.clone().unwrap_or_else(|| "DM".to_string());
            let identified_law = damping.as_deref().map(identified).transpose()?;
            let law_note = match (damping, &identified_law) {
                (None, _) => String::new(),
                (Some(p), Some(Some((law, _)))) => {
                    format!("; {} identified the {law} law", p.display())
                }
                (Some(p), _) => format!(
                    "; {} could not decide the law (identifiable false): the band stands",
                    p.display()
                ),
            };
            let g = s.youngs_modulus_mpa / (2.0 * (1.0 + s.poisson_ratio));
            Ok(Material {
                youngs_modulus_mpa: s.youngs_modulus_mpa,
                shear_modulus_mpa: g,
                poisson_ratio: s.poisson_ratio,
                density_kg_m3: s.density_kg_m3,
                grade: grade.clone(),
                fe: file.settings.fe.clone(),
                damping: Some(DampingReference {
                    state: s,
                    damping_ratio: file.targets.damping_ratio,
                }),
                identified_law: identified_law.flatten(),
                source: format!(
                    "{}: E = {:.1} MPa, nu = {} (G = {g:.1} MPa), rho = {} kg/m^3, {} elements per coil, Rayleigh alpha = {} 1/s, beta = {} s calibrated to zeta = {} at {} kg; Rm from EN 10270-1 {grade}{law_note}",
                    calibration.display(),
                    s.youngs_modulus_mpa,
                    sig(s.poisson_ratio, 6),
                    sig(s.density_kg_m3, 6),
                    file.settings.fe.elements_per_coil,
                    sig(s.alpha, 4),
                    sig(s.beta, 4),
                    sig(file.targets.damping_ratio, 4),
                    sig(s.mass_kg, 6)
                ),
            })
        }
    }
}

/// The law and parameters a damping.json (`coil-tune damping`) identified, `None` when
/// it could not decide.
fn identified(path: &Path) -> Result<Option<IdentifiedLaw>, crate::TuneError> {
    let text = coil_io::read_bounded(path, coil_io::MAX_JSON_BYTES, "a damping.json")?;
    #[derive(serde::Deserialize)]
    struct File {
        law: Option<String>,
        parameters: BTreeMap<String, f64>,
    }
    let file: File = serde_json::from_str(&text).map_err(|e| crate::TuneError::Json {
        path: path.to_path_buf(),
        line: e.line(),
        message: format!(
            "{e}; expected a damping.json written by `coil-tune damping` (law, parameters)"
        ),
    })?;
    Ok(file.law.map(|law| (law, file.parameters)))
}
