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
//! defaults written into `design.json`'s `assumptions`: `end_type` (`closed_ground`),
//! `coiling` (`cold`), `loading` (`dynamic`), `seating_coefficient` (0.5: both ends
//! fixed, the top guided, as the paper's test), `surge_band_hz` ([lo, hi]: the surge
//! mode must stay outside), `short_list` (8).
//!
//! The rate, the forces and the weight are the whole suspension's: `springs_in_parallel`
//! springs share them equally.

use crate::case::{read_json, CaseError};
use crate::fe::{FeSettings, SpringState};
use crate::fields::{root, Range};
use crate::sheet::en13906::{Coiling, EndType, Loading, Working};
use crate::sheet::input::{choice, working, COILING, END_TYPES, LOADING};
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
}

/// Reads `TARGET.json`; a relative calibration path is taken from the target's folder.
pub fn read_target(path: &Path) -> Result<Target, CaseError> {
    let (_, node) = read_json(path)?;
    let top = root(path, &node);
    let o = top.object("a design target (docs/spring-design.md)")?;
    let working = working(&o)?.ok_or_else(|| {
        o.error(
            "no working points",
            "force_1_n and force_2_n (or length_1_mm and length_2_mm)",
        )
    })?;
    let envelope = match o.get("envelope") {
        None => Envelope::default(),
        Some(f) => {
            let e = f.object("the envelope")?;
            let bound = |key: &str, meaning: &str| e.opt_number(key, Range::Positive, meaning);
            Envelope {
                max_outer_diameter_mm: bound("max_outer_diameter_mm", "the largest De (mm)")?,
                min_inner_diameter_mm: bound("min_inner_diameter_mm", "the smallest Di (mm)")?,
                max_free_length_mm: bound("max_free_length_mm", "the longest L0 (mm)")?,
                max_solid_length_mm: bound("max_solid_length_mm", "the longest Lc (mm)")?,
            }
        }
    };
    let material_field = o.require("material", "{\"calibration\": path} or {\"grade\": name}")?;
    let m = material_field.object("the material")?;
    let grade = m.opt_string("grade", "an EN 10270-1 grade name, e.g. \"DH\"")?;
    let beside = |file: String| path.parent().unwrap_or(Path::new(".")).join(file);
    let material = match (
        m.opt_string("calibration", "a calibration.json path")?,
        grade,
    ) {
        (Some(file), grade) => MaterialSource::Calibration {
            calibration: beside(file),
            grade,
            damping: m
                .opt_string("damping", "a damping.json path (coil-tune damping)")?
                .map(beside),
        },
        (None, Some(grade)) => MaterialSource::Grade { grade },
        (None, None) => {
            return Err(m
                .error(
                    "neither a calibration nor a grade",
                    "{\"calibration\": path} or {\"grade\": name}",
                )
                .into())
        }
    };
    let rate = o.number("rate_n_mm", Range::Positive, "the target rate (N/mm)")?;
    let weight = o.opt_number("weight_kg", Range::Positive, "the suspended mass (kg)")?;
    let mut zeta = o.opt_number("damping_ratio", Range::Open(0.0, 1.0), "a damping ratio")?;
    if let Some(c) = o.opt_number(
        "damping_coefficient_n_s_m",
        Range::Positive,
        "a damping coefficient at the weight (N s/m)",
    )? {
        // zeta = c / (2 sqrt(K m)) of the weight on the target rate.
        match (zeta, weight) {
            (None, Some(w)) => zeta = Some(c / (2.0 * (rate * 1e3 * w).sqrt())),
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
        springs_in_parallel: o
            .opt_number(
                "springs_in_parallel",
                Range::Count,
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
        seating_coefficient: o
            .opt_number(
                "seating_coefficient",
                Range::Positive,
                "the seating coefficient",
            )?
            .unwrap_or(0.5),
        surge_band_hz: band,
        short_list: o
            .opt_number(
                "short_list",
                Range::Count,
                "how many candidates the FE verifies",
            )?
            .unwrap_or(8.0) as usize,
    })
}

/// Handbook moduli of EN 10270-1 wire (EN 13906-1's values for patented drawn steel).
pub const HANDBOOK_STEEL: (f64, f64, f64) = (206000.0, 81500.0, 7850.0);

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
                    "{}: E = {:.1} MPa, nu = {} (G = {g:.1} MPa), rho = {} kg/m^3, {} elements per coil, Rayleigh alpha = {}, beta = {} calibrated to zeta = {} at {} kg; Rm from EN 10270-1 {grade}{law_note}",
                    calibration.display(),
                    s.youngs_modulus_mpa,
                    s.poisson_ratio,
                    s.density_kg_m3,
                    file.settings.fe.elements_per_coil,
                    s.alpha,
                    s.beta,
                    file.targets.damping_ratio,
                    s.mass_kg
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
