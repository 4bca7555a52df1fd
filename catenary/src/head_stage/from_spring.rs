//! The pantograph's head stage built from a spring: a case's `pantograph.head_spring`, or
//! each file of `coil-tune catenary CASE --springs A.json B.json ...` (docs/catenary.md,
//! "The head stage from a spring").
//!
//! # Sources (recognised by their content)
//! - a **measured case** (a folder or its `case.json`, `coil-tune calibrate`'s input): loops
//!   1 and 2 set Young's modulus to the measured rate and the test weight to the measured
//!   period; the damping law is the paper's Rayleigh law recalibrated on coil's model
//!   (alpha as printed, beta to the measured zeta), and the band of laws gives zeta low,
//!   mid and high ([`super::springs`]);
//! - a **variants file** (`variants`, e.g. Table 4), calibrated through the measured
//!   `case.json` beside it: every variant, or the one named after a colon
//!   (`table4.json:#2`);
//! - a **calibration** (`calibration.json`, `coil-tune calibrate`'s output): its `state`,
//!   E, the weight, and the Rayleigh law loop 3 identified;
//! - a **SPRING.json** (EN 13906-1 input, `coil-tune check`): its geometry and material,
//!   refused when a check of its own sheet fails; it names no damping law, so the law is
//!   the 160ECT's calibrated one ([`ASSUMED_RAYLEIGH`]), said as an assumption, unless
//!   `rayleigh_alpha` / `rayleigh_beta` are given;
//! - a **design** (`design.json`, `coil-tune design`'s output): the FE-verified candidate
//!   of the rank named after a colon (`design.json:2`; every candidate without one, rank 1
//!   first), with the design's material and its FE mesh (the candidate's finest, so the
//!   rate is the design's `fe_rate_n_mm`); the damping law is the design's calibration's
//!   Rayleigh law, or with a grade (no calibration) the assumed one above.
//!
//! # The stage (lumped, the default)
//! `k` one spring's axial rate from coil's FE model, `n` springs in parallel:
//! `K = n k` (N/m); the springs' mass share `n m_s / 3` (Rayleigh's static-shape
//! estimate, `m_s` one spring's wire mass) added to the head's mass unless `mass_share`
//! is false; the dashpot from the damping law on the static shape,
//! `c = alpha n m_s / 3 + beta K` (`damping: "rayleigh"`, the default), or
//! `c = 2 zeta sqrt(K m)` with the band's zeta (`zeta_low`, `zeta_mid`, `zeta_high`, a
//! measured case or variants file only; `m` the stage's mass). docs/catenary.md, "The
//! head stage reduced", shows that inside EN 50318's 20 Hz band this lumped stage with
//! the mass share and the Rayleigh dashpot follows the reduced one within 1.1 %.
//!
//! # The stage reduced (`reduced: true`)
//! The Craig-Bampton stage of [`super::reduced`] (the surge modes below 300 Hz, the
//! springs' own mass and the Rayleigh law on the wire) scaled from four springs to `n`,
//! as the head stage's `matrix`; the head's mass stays the point mass.
//!
//! Units: N/m, N s/m, kg in the stage spec; N/mm for one spring's rate.

use super::reduced::{reduced_stage, reduced_stage_spec, ReducedStage};
use super::source::{invalid, stem, Spring};
pub use super::source::{ASSUMED_RAYLEIGH, MAX_SOURCE_BYTES, MAX_SPRINGS_IN_PARALLEL};
use super::springs::{head_stages, HeadStageSettings, SPRINGS_IN_PARALLEL};
use super::springs::{HeadStages, ZetaLevel};
use crate::model::{PantographSpec, StageSpec};
use crate::{Result, TuneError};
use coil_tuner::case::{read_case as read_measured_case, read_variants, VariantsFile};
use coil_tuner::fe::{static_stiffness, FeSettings, SpringState};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

fn default_springs() -> u32 {
    SPRINGS_IN_PARALLEL
}

fn yes() -> bool {
    true
}

/// How the stage's dashpot is set (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DampingChoice {
    /// `c = alpha n m_s / 3 + beta K`: the spring's Rayleigh law on the static shape.
    #[default]
    Rayleigh,
    /// `c = 2 zeta_low sqrt(K m)`.
    ZetaLow,
    /// `c = 2 zeta_mid sqrt(K m)` (the paper's law's zeta carried to the head).
    ZetaMid,
    /// `c = 2 zeta_high sqrt(K m)`.
    ZetaHigh,
}

impl DampingChoice {
    fn level(self) -> Option<ZetaLevel> {
        match self {
            DampingChoice::Rayleigh => None,
            DampingChoice::ZetaLow => Some(ZetaLevel::Low),
            DampingChoice::ZetaMid => Some(ZetaLevel::Mid),
            DampingChoice::ZetaHigh => Some(ZetaLevel::High),
        }
    }
}

/// `pantograph.head_spring` of a case: where the springs come from and how the stage is
/// built (module doc).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeadSpringSpec {
    /// `PATH` or `PATH:NAME` inside the case folder (a design rank or a variant's name
    /// after the colon); `--springs` replaces it.
    #[serde(default)]
    pub source: Option<String>,
    /// Springs in parallel under the head [default: 4, the paper's collector head].
    #[serde(default = "default_springs")]
    pub springs_in_parallel: u32,
    /// The head's own mass (kg) [default: the first stage's `mass_kg`].
    #[serde(default)]
    pub head_mass_kg: Option<f64>,
    /// The dashpot [default: `rayleigh`].
    #[serde(default)]
    pub damping: DampingChoice,
    /// Add a third of the springs' mass to the head [default: true].
    #[serde(default = "yes")]
    pub mass_share: bool,
    /// The Craig-Bampton stage with the surge modes instead of `(K, c)` [default: false].
    #[serde(default)]
    pub reduced: bool,
    /// Rayleigh alpha of the wire (1/s), replacing the source's.
    #[serde(default)]
    pub rayleigh_alpha: Option<f64>,
    /// Rayleigh beta of the wire (s), replacing the source's.
    #[serde(default)]
    pub rayleigh_beta: Option<f64>,
}

impl Default for HeadSpringSpec {
    fn default() -> Self {
        HeadSpringSpec {
            source: None,
            springs_in_parallel: SPRINGS_IN_PARALLEL,
            head_mass_kg: None,
            damping: DampingChoice::Rayleigh,
            mass_share: true,
            reduced: false,
            rayleigh_alpha: None,
            rayleigh_beta: None,
        }
    }
}

impl HeadSpringSpec {
    /// Checks the fields that do not need the source, naming each.
    pub fn check(&self) -> std::result::Result<(), String> {
        let n = self.springs_in_parallel;
        if !(1..=MAX_SPRINGS_IN_PARALLEL).contains(&n) {
            return Err(format!(
                "pantograph.head_spring.springs_in_parallel = {n}; expected 1 to {MAX_SPRINGS_IN_PARALLEL}"
            ));
        }
        if let Some(m) = self.head_mass_kg {
            if !(m.is_finite() && m > 0.0) {
                return Err(format!(
                    "pantograph.head_spring.head_mass_kg = {m}; expected a positive mass (kg)"
                ));
            }
        }
        let given = [
            ("rayleigh_alpha", self.rayleigh_alpha),
            ("rayleigh_beta", self.rayleigh_beta),
        ];
        for (name, v) in given.into_iter().filter_map(|(n, v)| v.map(|v| (n, v))) {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!(
                    "pantograph.head_spring.{name} = {v}; expected a finite value >= 0"
                ));
            }
        }
        if self.reduced && self.damping != DampingChoice::Rayleigh {
            return Err(
                "pantograph.head_spring: `reduced` carries the Rayleigh law on the wire; expected `damping` \"rayleigh\" with it"
                    .into(),
            );
        }
        Ok(())
    }
}

/// What a spring source is.
#[derive(Debug, Clone, PartialEq)]
enum SourceKind {
    /// A measured case (its own spring).
    Measured(PathBuf),
    /// A variants file, calibrated through the measured case beside it; `None`: every
    /// variant.
    Variants(PathBuf, Option<String>),
    /// `coil-tune calibrate`'s output.
    Calibration(PathBuf),
    /// An EN 13906-1 SPRING.json.
    Sheet(PathBuf),
    /// `coil-tune design`'s design.json; `None`: every candidate.
    Design(PathBuf, Option<String>),
}

/// What was built for the head, for report.md and catenary.json.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BuiltHead {
    /// The spring's name (`160ECT`, a variant's name, a file's stem).
    pub name: String,
    /// Where it came from (kind and file).
    pub source: String,
    /// One spring's axial rate from coil's FE model (N/mm).
    pub spring_rate_n_mm: f64,
    /// Springs in parallel.
    pub springs_in_parallel: u32,
    /// The stage's rate `K = n k` (N/m).
    pub stiffness_n_m: f64,
    /// One spring's wire mass (kg).
    pub spring_mass_kg: f64,
    /// The mass added to the head, `n m_s / 3` or 0 (kg).
    pub mass_share_kg: f64,
    /// The head's own mass (kg).
    pub head_mass_kg: f64,
    /// The stage's mass (kg): the head's and the share.
    pub stage_mass_kg: f64,
    /// The Rayleigh law of the wire `[alpha (1/s), beta (s)]`.
    pub rayleigh: [f64; 2],
    /// Where that law comes from.
    pub damping_law: String,
    /// How the dashpot was set.
    pub damping: DampingChoice,
    /// The lumped dashpot (N s/m; 0 for a reduced stage, whose damping is its matrix).
    pub damping_n_s_m: f64,
    /// The head mode's damping ratio `c / (2 sqrt(K m))` of the lumped stage (-).
    pub zeta: f64,
    /// Reduced stage: the surge modes kept, else `None`.
    pub reduced_modes: Option<usize>,
    /// Values not read from the source (assumptions).
    pub assumptions: Vec<String>,
    /// The stage spec that went into the pantograph.
    #[serde(skip)]
    pub stage: StageSpec,
}

/// Splits `PATH:NAME` (a colon after the last path separator, not a drive letter).
pub fn split_name(entry: &str) -> (&str, Option<&str>) {
    let tail = entry.rfind(['/', '\\']).map_or(0, |i| i + 1);
    match entry[tail..].rfind(':') {
        Some(i) if tail + i > 1 => (&entry[..tail + i], Some(&entry[tail + i + 1..])),
        _ => (entry, None),
    }
}

/// Recognises the source at `path` (named after a colon) by its content.
fn identify(path: &Path, name: Option<&str>) -> Result<SourceKind> {
    let file = if path.is_dir() {
        path.join("case.json")
    } else {
        path.to_path_buf()
    };
    let text = coil_io::read_bounded(&file, MAX_SOURCE_BYTES, "spring source")?;
    let value: serde_json::Value = serde_json::from_str(&text).map_err(|e| TuneError::Json {
        path: file.clone(),
        line: e.line(),
        message: format!("{e}; expected a spring source: a measured case, a variants file, calibration.json, SPRING.json or design.json (docs/catenary.md)"),
    })?;
    let has = |key: &str| value.get(key).is_some();
    let kind = if has("candidates") && has("target") && has("material") {
        SourceKind::Design(file.clone(), name.map(str::to_string))
    } else if has("variants") {
        SourceKind::Variants(file.clone(), name.map(str::to_string))
    } else if has("state") && has("targets") {
        SourceKind::Calibration(file.clone())
    } else if has("wire_diameter_mm") && (has("free_length_mm") || has("wire_grade")) {
        SourceKind::Sheet(file.clone())
    } else if has("spring") && has("targets") {
        SourceKind::Measured(file.clone())
    } else {
        return Err(invalid(format!(
            "{}: not a spring source; expected a measured case (`spring`, `targets`), a variants file (`variants`), a calibration.json (`state`, `targets`), a SPRING.json (`wire_diameter_mm`, `free_length_mm`) or a design.json (`target`, `material`, `candidates`) (docs/catenary.md, \"The head stage from a spring\")",
            file.display()
        )));
    };
    if name.is_some() && !matches!(kind, SourceKind::Variants(..) | SourceKind::Design(..)) {
        return Err(invalid(format!(
            "{}: `:{}` names a variant or a design's rank, but the file is neither a variants file nor a design.json",
            file.display(),
            name.unwrap_or_default()
        )));
    }
    Ok(kind)
}

/// The springs of a measured case and, optionally, of a variants file beside it.
fn measured_springs(
    case_file: &Path,
    variants: Option<(&VariantsFile, Option<&str>)>,
    head_mass_kg: f64,
    fe: &FeSettings,
) -> Result<Vec<Spring>> {
    let case = read_measured_case(case_file)?;
    let empty = VariantsFile {
        file: case_file.to_path_buf(),
        source: None,
        variants: Vec::new(),
    };
    let file = variants.map_or(&empty, |(v, _)| v);
    let settings = HeadStageSettings {
        fe: fe.clone(),
        ..HeadStageSettings::default()
    };
    let stages: HeadStages = head_stages(&case, file, head_mass_kg, &settings)?;
    let note = format!(
        "calibrated on {} (loops 1 and 2); {}",
        case_file.display(),
        stages.stages[0].zeta_mid_law
    );
    let mut springs = Vec::new();
    let geometry =
        std::iter::once(stages.material.spring).chain(file.variants.iter().map(|v| v.spring));
    for (stage, spring) in stages.stages.iter().zip(geometry) {
        let wanted = match variants {
            None => true,
            Some((_, None)) => stage.name != super::springs::CASE_SPRING,
            Some((_, Some(name))) => stage.name == name,
        };
        if wanted {
            springs.push(Spring {
                name: stage.name.clone(),
                source: if variants.is_some() {
                    format!("variant `{}` of {}", stage.name, file.file.display())
                } else {
                    format!("measured case {}", case_file.display())
                },
                state: stages.material.with_spring(spring),
                rayleigh: stages.rayleigh_mid,
                rayleigh_note: note.clone(),
                band: Some(stage.clone()),
                fe: None,
            });
        }
    }
    if let Some((v, Some(name))) = variants {
        if springs.is_empty() {
            let names: Vec<&str> = v.variants.iter().map(|v| v.name.as_str()).collect();
            return Err(invalid(format!(
                "{}: no variant named `{name}`; expected one of {}",
                v.file.display(),
                names.join(", ")
            )));
        }
    }
    Ok(springs)
}

fn calibration_spring(path: &Path) -> Result<Spring> {
    #[derive(Deserialize)]
    struct File {
        state: SpringState,
    }
    let text = coil_io::read_bounded(path, MAX_SOURCE_BYTES, "calibration.json")?;
    let file: File = serde_json::from_str(&text).map_err(|e| TuneError::Json {
        path: path.to_path_buf(),
        line: e.line(),
        message: format!(
            "{e}; expected a calibration.json written by `coil-tune calibrate` (with a `state`)"
        ),
    })?;
    let s = file.state;
    Ok(Spring {
        name: stem(path),
        source: format!("calibration {}", path.display()),
        rayleigh: [s.alpha, s.beta],
        rayleigh_note: format!("the Rayleigh law loop 3 identified ({})", path.display()),
        state: s,
        band: None,
        fe: None,
    })
}

fn sheet_spring(path: &Path) -> Result<Spring> {
    let spring = coil_design::sheet::input::read_spring(path)?;
    let sheet = spring.sheet();
    if !sheet.passes() {
        let failed: Vec<String> = sheet
            .checks
            .iter()
            .filter(|c| !c.passed)
            .map(|c| format!("{} ({})", c.name, c.detail))
            .collect();
        return Err(invalid(format!(
            "{}: the spring fails its own EN 13906-1 checks: {}; expected a spring that `coil-tune check` passes",
            path.display(),
            failed.join("; ")
        )));
    }
    Ok(Spring {
        name: stem(path),
        source: format!("SPRING.json {}", path.display()),
        state: coil_design::sheet::fe::state_of(&spring, &sheet),
        rayleigh: ASSUMED_RAYLEIGH,
        rayleigh_note: format!(
            "assumed: the 160ECT's calibrated Rayleigh law (alpha = {} 1/s, beta = {:e} s), the SPRING.json names none",
            ASSUMED_RAYLEIGH[0], ASSUMED_RAYLEIGH[1]
        ),
        band: None,
        fe: None,
    })
}

/// The springs an entry `PATH[:NAME]` stands for (a variants file without a name: all of
/// its variants).
fn springs_of(entry: &Path, head_mass_kg: f64, fe: &FeSettings) -> Result<Vec<Spring>> {
    let text = entry.to_string_lossy().into_owned();
    let (path, name) = split_name(&text);
    let path = Path::new(path);
    match identify(path, name)? {
        SourceKind::Measured(file) => measured_springs(&file, None, head_mass_kg, fe),
        SourceKind::Variants(file, name) => {
            let variants = read_variants(&file)?;
            let case = file.with_file_name("case.json");
            if !case.is_file() {
                return Err(invalid(format!(
                    "{}: a variants file is calibrated through the measured case beside it; expected {}",
                    file.display(),
                    case.display()
                )));
            }
            measured_springs(&case, Some((&variants, name.as_deref())), head_mass_kg, fe)
        }
        SourceKind::Calibration(file) => Ok(vec![calibration_spring(&file)?]),
        SourceKind::Sheet(file) => Ok(vec![sheet_spring(&file)?]),
        SourceKind::Design(file, rank) => super::design::design_springs(&file, rank.as_deref()),
    }
}

/// Scales a four-spring reduced stage to `n` springs.
fn scaled(stage: &ReducedStage, n: u32) -> ReducedStage {
    let f = f64::from(n) / f64::from(SPRINGS_IN_PARALLEL);
    ReducedStage {
        k: &stage.k * f,
        m: &stage.m * f,
        c: &stage.c * f,
        ..stage.clone()
    }
}

/// The stage of one spring (module doc).
fn stage_of(
    spring: &Spring,
    spec: &HeadSpringSpec,
    head_mass_kg: f64,
    fe: &FeSettings,
) -> Result<BuiltHead> {
    let n = spec.springs_in_parallel;
    let nf = f64::from(n);
    let fe = spring.fe.as_ref().unwrap_or(fe);
    let (k_n_mm, _) = static_stiffness(&spring.state, fe)?;
    let stiffness_n_m = nf * k_n_mm * 1e3;
    let spring_mass_kg = spring.state.spring_mass_kg();
    let mass_share_kg = if spec.mass_share && !spec.reduced {
        nf * spring_mass_kg / 3.0
    } else {
        0.0
    };
    let stage_mass_kg = head_mass_kg + mass_share_kg;
    let mut assumptions = Vec::new();
    let (rayleigh, damping_law) = match (spec.rayleigh_alpha, spec.rayleigh_beta) {
        (None, None) => {
            if spring.rayleigh == ASSUMED_RAYLEIGH && spring.band.is_none() {
                assumptions.push(spring.rayleigh_note.clone());
            }
            (spring.rayleigh, spring.rayleigh_note.clone())
        }
        (a, b) => (
            [
                a.unwrap_or(spring.rayleigh[0]),
                b.unwrap_or(spring.rayleigh[1]),
            ],
            "given in the case (pantograph.head_spring.rayleigh_alpha / rayleigh_beta)".to_string(),
        ),
    };
    let damping_n_s_m = match spec.damping.level() {
        None => rayleigh[0] * nf * spring_mass_kg / 3.0 + rayleigh[1] * stiffness_n_m,
        Some(level) => {
            let band = spring.band.as_ref().ok_or_else(|| {
                invalid(format!(
                    "pantograph.head_spring.damping = \"zeta_{}\" needs the damping-law band of a measured case or variants file; {} has none (expected \"rayleigh\")",
                    level.name(),
                    spring.source
                ))
            })?;
            2.0 * band.zeta(level) * (stiffness_n_m * stage_mass_kg).sqrt()
        }
    };
    if spec.damping.level().is_some() {
        assumptions.push(
            "zeta of the test's weight mode carried over to the head's mode (docs/catenary.md, \"Head stages from coil's springs\")"
                .into(),
        );
    }
    let (stage, reduced_modes, lumped_c) = if spec.reduced {
        let four = reduced_stage(&spring.state, fe, rayleigh[0], rayleigh[1])?;
        let r = scaled(&four, n);
        let stage = reduced_stage_spec(&r, head_mass_kg);
        (stage, Some(r.dim() - 2), 0.0)
    } else {
        let stage = StageSpec {
            mass_kg: stage_mass_kg,
            stiffness_n_m,
            damping_n_s_m,
            matrix: None,
        };
        (stage, None, damping_n_s_m)
    };
    Ok(BuiltHead {
        name: spring.name.clone(),
        source: spring.source.clone(),
        spring_rate_n_mm: k_n_mm,
        springs_in_parallel: n,
        stiffness_n_m,
        spring_mass_kg,
        mass_share_kg,
        head_mass_kg,
        stage_mass_kg,
        rayleigh,
        damping_law,
        damping: spec.damping,
        damping_n_s_m: lumped_c,
        zeta: damping_n_s_m / (2.0 * (stiffness_n_m * stage_mass_kg).sqrt()),
        reduced_modes,
        assumptions,
        stage,
    })
}

/// The head stages of the springs at `entries` (paths, `PATH:NAME` for a variant), built
/// as `spec` says for `pantograph`'s head (module doc), in order.
pub fn build_heads(
    entries: &[PathBuf],
    spec: &HeadSpringSpec,
    pantograph: &PantographSpec,
    fe: &FeSettings,
) -> Result<Vec<BuiltHead>> {
    spec.check().map_err(invalid)?;
    let head_mass_kg = spec
        .head_mass_kg
        .or_else(|| pantograph.stages.first().map(|s| s.mass_kg))
        .ok_or_else(|| invalid("the pantograph has no stage to put the spring in".into()))?;
    let mut heads = Vec::new();
    for entry in entries {
        for spring in springs_of(entry, head_mass_kg, fe)? {
            heads.push(stage_of(&spring, spec, head_mass_kg, fe)?);
        }
    }
    Ok(heads)
}

/// `pantograph` with its head stage (the first) replaced by `head`'s.
pub fn with_head(pantograph: &PantographSpec, head: &BuiltHead) -> PantographSpec {
    let mut p = pantograph.clone();
    if let Some(first) = p.stages.first_mut() {
        *first = head.stage.clone();
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_colon_after_the_last_separator_names_a_variant() {
        assert_eq!(
            split_name("cases/160ect/table4.json:#2"),
            ("cases/160ect/table4.json", Some("#2"))
        );
        assert_eq!(split_name("a.json"), ("a.json", None));
        assert_eq!(split_name("C:/x/a.json"), ("C:/x/a.json", None));
        assert_eq!(split_name("x:y/a.json"), ("x:y/a.json", None));
    }
}

#[cfg(test)]
mod design_tests {
    use super::{build_heads, HeadSpringSpec};
    use crate::model::CatenaryDeckSpec;
    use coil_design::target::{read_target, MaterialSource};
    use coil_design::{design, DesignSettings};
    use coil_tuner::fe::FeSettings;
    use std::path::{Path, PathBuf};

    /// A design on a wire grade (the 160ECT target, two candidates), written as
    /// `coil-tune design` writes it.
    fn design_file(dir: &Path) -> (PathBuf, Vec<f64>) {
        let cases = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/spring-design");
        let mut target = read_target(&cases.join("160ect_target.json")).unwrap();
        target.material = MaterialSource::Grade { grade: "DM".into() };
        let settings = DesignSettings {
            short_list: Some(2),
            ..DesignSettings::default()
        };
        let result = design(&target, &settings).unwrap();
        let file = dir.join("design.json");
        std::fs::write(&file, coil_design::output::json(&result).unwrap()).unwrap();
        (
            file,
            result.candidates.iter().map(|c| c.fe_rate_n_mm).collect(),
        )
    }

    #[test]
    fn a_design_rank_is_the_head_stage_at_the_designs_fe_rate() {
        let dir = tempfile::tempdir().unwrap();
        let (file, rates) = design_file(dir.path());
        assert!(rates.len() >= 2, "{rates:?}");
        let pantograph = CatenaryDeckSpec::en50318_reference(2, 0.25).pantograph;
        let spec = HeadSpringSpec::default();
        let fe = FeSettings::default();
        let entry = |rank: &str| PathBuf::from(format!("{}:{rank}", file.display()));
        // Rank 2: one stage, K = 4 k with k the design's FE rate of that candidate (the
        // same model: the design's material on the candidate's finest mesh).
        let heads = build_heads(&[entry("2")], &spec, &pantograph, &fe).unwrap();
        assert_eq!(heads.len(), 1);
        let h = &heads[0];
        println!(
            "{}: k = {} N/mm (design {} N/mm), K = {} N/m, c = {} N s/m, {}",
            h.name, h.spring_rate_n_mm, rates[1], h.stiffness_n_m, h.damping_n_s_m, h.damping_law
        );
        assert!((h.spring_rate_n_mm / rates[1] - 1.0).abs() < 1e-9);
        assert_eq!(h.stiffness_n_m, 4.0 * h.spring_rate_n_mm * 1e3);
        assert_eq!(
            h.name,
            format!(
                "{} rank 2",
                dir.path().file_name().unwrap().to_string_lossy()
            )
        );
        // A grade names no damping law: the assumed one, said so.
        assert!(
            h.assumptions.iter().any(|a| a.starts_with("assumed")),
            "{:?}",
            h.assumptions
        );
        // No rank: every candidate, rank 1 first.
        let all = build_heads(std::slice::from_ref(&file), &spec, &pantograph, &fe).unwrap();
        assert_eq!(all.len(), rates.len());
        assert!((all[0].spring_rate_n_mm / rates[0] - 1.0).abs() < 1e-9);
        // A rank that does not exist, and one that is not a number, name the file and
        // the ranks there are.
        let listed: Vec<String> = (1..=rates.len()).map(|r| r.to_string()).collect();
        for (rank, says) in [
            ("9", "no candidate of rank 9"),
            ("best", "`:best` is not a rank"),
        ] {
            let e = build_heads(&[entry(rank)], &spec, &pantograph, &fe)
                .unwrap_err()
                .to_string();
            println!("{e}");
            assert!(e.contains(says) && e.contains("design.json"), "{e}");
            assert!(e.contains(&format!("one of {}", listed.join(", "))), "{e}");
        }
    }

    #[test]
    fn a_damaged_design_is_refused_naming_the_field() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("design.json");
        let pantograph = CatenaryDeckSpec::en50318_reference(2, 0.25).pantograph;
        let fe = FeSettings::default();
        let candidate = |pitch: &str| {
            format!(
                r#"{{"rank": 1, "wire_diameter_mm": 3.0, "mean_diameter_mm": 24.0, "active_coils": 14.0,
                   "pitch_mm": {pitch}, "fe_rate_n_mm": 3.9, "fe": {{"mesh": {{"elements_per_coil": [24]}}}}}}"#
            )
        };
        let material = r#"{"youngs_modulus_mpa": 206000.0, "poisson_ratio": 0.3, "density_kg_m3": 7850.0,
            "fe": {"elements_per_coil": 24, "element": 98, "lumped_mass": false, "static_force_n": 10.0, "modes": 3}}"#;
        for (candidates, says) in [
            ("[]".to_string(), "no FE-verified candidate"),
            (
                format!("[{}]", candidate("-6.2")),
                "candidates[rank 1].pitch_mm = -6.2",
            ),
        ] {
            std::fs::write(
                &file,
                format!(
                    r#"{{"target": {{}}, "material": {material}, "candidates": {candidates}}}"#
                ),
            )
            .unwrap();
            let e = build_heads(
                std::slice::from_ref(&file),
                &HeadSpringSpec::default(),
                &pantograph,
                &fe,
            )
            .unwrap_err()
            .to_string();
            assert!(e.contains(says) && e.contains("design.json"), "{e}");
        }
    }
}
