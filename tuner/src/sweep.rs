//! `coil-tune sweep`: K and zeta of spring variants with the validated material (the
//! paper's Table 4): each variant keeps E, Poisson's ratio, density, the weight's mass and
//! Rayleigh alpha and beta of the calibration and changes only the geometry (n, D, d, h).
//! K is the static stiffness, zeta the paper's decrement of a decay transient, as in the
//! calibration. Variants run in parallel (rayon).

use crate::case::{Variant, VariantsFile};
use crate::damping::Simulator;
use crate::decay::{measure, DecaySettings};
use crate::error::Result;
use crate::fe::{self, FeSettings, SpringState};
use crate::output::Cell;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Table 4's sweep as tasks: variant `k` with the validated material.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VariantSweep {
    /// The material and weight.
    pub material: SpringState,
    /// The variants.
    pub variants: Vec<Variant>,
    /// Mesh and solver settings.
    pub fe: FeSettings,
    /// Decay-transient settings.
    pub decay: DecaySettings,
}

/// One variant's figures.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VariantResult {
    /// The variant's name.
    pub name: String,
    /// Number of active coils n.
    pub active_coils: f64,
    /// Mean coil diameter D, mm.
    pub mean_diameter_mm: f64,
    /// Wire diameter d, mm.
    pub wire_diameter_mm: f64,
    /// Pitch h, mm.
    pub pitch_mm: f64,
    /// Axial stiffness K, N/mm.
    pub stiffness_n_mm: f64,
    /// The paper's estimator (span mean of the decrement).
    pub damping_ratio: f64,
    /// zeta of the exponential fit (-).
    pub damping_ratio_fit: f64,
    /// Period of the decay (s).
    pub period_s: f64,
    /// The axial mode's circular frequency (rad/s).
    pub omega_rad_s: f64,
    /// The paper's K, N/mm.
    pub paper_stiffness_n_mm: Option<f64>,
    /// The paper's zeta (-).
    pub paper_damping_ratio: Option<f64>,
    /// (coil - paper) / paper.
    pub stiffness_relative_error: Option<f64>,
    /// zeta against the paper (-).
    pub damping_relative_error: Option<f64>,
}

/// The sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sweep {
    /// The material and weight.
    pub material: SpringState,
    /// The variants.
    pub variants: Vec<VariantResult>,
    /// Wall time, s.
    pub elapsed_s: f64,
}

/// The paper's validated material (Table 2: E, alpha, beta) on the case's spring, with
/// the weight's mass tuned to the case's period (the paper does not print its mass).
pub fn paper_material(
    case: &crate::case::MeasuredCase,
    settings: &crate::calibrate::CalibrateSettings,
) -> Result<SpringState> {
    let missing = |what: &str| {
        crate::TuneError::Invalid(format!(
            "{}: `paper.table3.{what}` is missing; expected the paper's validated material",
            case.file.display()
        ))
    };
    let paper = case
        .paper
        .as_ref()
        .ok_or_else(|| missing("youngs_modulus_mpa"))?;
    let mut state = SpringState::nominal(case);
    state.youngs_modulus_mpa = paper
        .youngs_modulus_mpa
        .ok_or_else(|| missing("youngs_modulus_mpa"))?;
    state.alpha = paper
        .rayleigh_alpha
        .ok_or_else(|| missing("rayleigh_alpha"))?;
    state.beta = paper
        .rayleigh_beta
        .ok_or_else(|| missing("rayleigh_beta"))?;
    crate::loops::tune_mass(
        &mut state,
        &settings.fe,
        case.target("period_s")?,
        settings.period_tolerance,
        None,
    )?;
    Ok(state)
}

/// Runs one variant.
pub fn run_variant(
    material: &SpringState,
    variant: &Variant,
    fe: &FeSettings,
    decay: &DecaySettings,
) -> Result<VariantResult> {
    let state = material.with_spring(variant.spring);
    let (run, _) = fe::static_and_modal(&state, fe)?;
    let sim = Simulator::new(&state, fe, decay)?;
    let m = measure(&sim.run(state.alpha, state.beta)?, decay)?;
    let relative = |coil: f64, paper: Option<f64>| paper.map(|p| (coil - p) / p);
    Ok(VariantResult {
        name: variant.name.clone(),
        active_coils: variant.spring.active_coils,
        mean_diameter_mm: variant.spring.mean_diameter_mm,
        wire_diameter_mm: variant.spring.wire_diameter_mm,
        pitch_mm: variant.spring.pitch_mm,
        stiffness_n_mm: run.stiffness_n_mm,
        damping_ratio: m.zeta_mean,
        damping_ratio_fit: m.zeta_fit,
        period_s: m.period_s,
        omega_rad_s: run.axial.omega_rad_s,
        paper_stiffness_n_mm: variant.paper_stiffness_n_mm,
        paper_damping_ratio: variant.paper_damping_ratio,
        stiffness_relative_error: relative(run.stiffness_n_mm, variant.paper_stiffness_n_mm),
        damping_relative_error: relative(m.zeta_mean, variant.paper_damping_ratio),
    })
}

/// Runs every variant in parallel, in the file's order.
pub fn sweep(
    material: &SpringState,
    variants: &VariantsFile,
    fe: &FeSettings,
    decay: &DecaySettings,
) -> Result<Sweep> {
    let start = std::time::Instant::now();
    let progress = coil_io::Progress::new("sweep", variants.variants.len() as u64, "variants");
    let results = variants
        .variants
        .par_iter()
        .map(|v| {
            let r = run_variant(material, v, fe, decay);
            progress.inc(1);
            r
        })
        .collect::<Result<Vec<_>>>()?;
    progress.finish();
    Ok(Sweep {
        material: *material,
        variants: results,
        elapsed_s: start.elapsed().as_secs_f64(),
    })
}

/// The columns of `sweep.csv`, in order.
pub const COLUMNS: [&str; 12] = [
    "name",
    "active_coils",
    "mean_diameter_mm",
    "wire_diameter_mm",
    "pitch_mm",
    "stiffness_n_mm",
    "damping_ratio",
    "period_s",
    "paper_stiffness_n_mm",
    "paper_damping_ratio",
    "stiffness_relative_error",
    "damping_relative_error",
];

impl VariantResult {
    /// The row of `sweep.csv` ([`COLUMNS`]).
    pub fn cells(&self) -> Vec<Cell> {
        vec![
            Cell::Text(self.name.clone()),
            Cell::Number(self.active_coils),
            Cell::Number(self.mean_diameter_mm),
            Cell::Number(self.wire_diameter_mm),
            Cell::Number(self.pitch_mm),
            Cell::Number(self.stiffness_n_mm),
            Cell::Number(self.damping_ratio),
            Cell::Number(self.period_s),
            Cell::from(self.paper_stiffness_n_mm),
            Cell::from(self.paper_damping_ratio),
            Cell::from(self.stiffness_relative_error),
            Cell::from(self.damping_relative_error),
        ]
    }
}

impl Sweep {
    /// The table as CSV.
    pub fn csv(&self) -> String {
        crate::output::csv_table(&COLUMNS, self.variants.iter().map(|v| v.cells()))
    }

    /// The table for a terminal, paper beside coil.
    pub fn table(&self) -> String {
        let mut out = format!(
            "{:<6} {:>5} {:>6} {:>5} {:>5} | {:>9} {:>9} {:>8} | {:>9} {:>9} {:>8}\n",
            "",
            "n",
            "D mm",
            "d mm",
            "h mm",
            "K coil",
            "K paper",
            "error",
            "zeta coil",
            "zeta pap",
            "error"
        );
        let pct = |x: Option<f64>| x.map_or("-".to_string(), |e| format!("{:+.2}%", 100.0 * e));
        let num =
            |x: Option<f64>, digits: usize| x.map_or("-".to_string(), |v| format!("{v:.digits$}"));
        for v in &self.variants {
            out.push_str(&format!(
                "{:<6} {:>5} {:>6} {:>5} {:>5} | {:>9.4} {:>9} {:>8} | {:>9.6} {:>9} {:>8}\n",
                v.name,
                v.active_coils,
                v.mean_diameter_mm,
                v.wire_diameter_mm,
                v.pitch_mm,
                v.stiffness_n_mm,
                num(v.paper_stiffness_n_mm, 3),
                pct(v.stiffness_relative_error),
                v.damping_ratio,
                num(v.paper_damping_ratio, 5),
                pct(v.damping_relative_error),
            ));
        }
        out
    }
}
