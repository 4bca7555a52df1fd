//! `coil-tune calibrate`: the paper's Figure 6 on a measured case: the nominal model,
//! loop 1 (E to K), loop 2 (mass to T), loop 3 (Rayleigh alpha and beta to zeta).
//!
//! Targets come from the case's `targets` (or are given explicitly). Everything a loop
//! runs is kept in the output folder: decks, logs, grids, figures, and
//! `calibration.json` with the final values and every loop's report.

use crate::case::MeasuredCase;
use crate::damping::{tune_damping, DampingReport, DampingSettings, RunControl};
use crate::error::{Result, TuneError};
use crate::fe::{FeSettings, SpringState};
use crate::loops::{tune_mass, tune_youngs_modulus, LoopReport};
use crate::output::OutDir;
use crate::plots;
use serde::Serialize;

/// Settings of a calibration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CalibrateSettings {
    /// Mesh and solver settings.
    pub fe: FeSettings,
    /// Loop 3 settings.
    pub damping: DampingSettings,
    /// Relative tolerance of loop 1 (the paper: 0.001% = 1e-5).
    pub stiffness_tolerance: f64,
    /// Relative tolerance of loop 2.
    pub period_tolerance: f64,
}

impl Default for CalibrateSettings {
    fn default() -> Self {
        CalibrateSettings {
            fe: FeSettings::default(),
            damping: DampingSettings::default(),
            stiffness_tolerance: 1e-5,
            period_tolerance: 1e-6,
        }
    }
}

/// The three targets of Figure 6.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Targets {
    /// Axial stiffness K, N/mm.
    pub stiffness_n_mm: f64,
    /// Period of the axial mode, s.
    pub period_s: f64,
    /// Damping ratio zeta (-).
    pub damping_ratio: f64,
}

impl Targets {
    /// The case's targets; each missing one is an error naming `targets.<field>`.
    ///
    /// The case's records are read and checked as well, whatever the targets: a case with
    /// a junk record is refused rather than calibrated beside it.
    pub fn of(case: &MeasuredCase) -> Result<Self> {
        case.static_records()?;
        case.decay_records()?;
        Ok(Targets {
            stiffness_n_mm: case.target("stiffness_n_mm")?,
            period_s: case.target("period_s")?,
            damping_ratio: case.target("damping_ratio")?,
        })
    }
}

/// A finished calibration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Calibration {
    /// The case's name.
    pub case: String,
    /// The targets.
    pub targets: Targets,
    /// The settings.
    pub settings: CalibrateSettings,
    /// The nominal values.
    pub nominal: SpringState,
    /// Loop 1 (E to K).
    pub stiffness: LoopReport,
    /// Loop 2 (mass to T).
    pub period: LoopReport,
    /// Loop 3 settings.
    pub damping: DampingReport,
    /// The validated values: E, mass, alpha, beta with the geometry.
    pub state: SpringState,
    /// Wall time, s.
    pub elapsed_s: f64,
}

/// The paper's (alpha, beta), if the case gives them.
pub fn paper_damping_point(case: &MeasuredCase) -> Option<(f64, f64)> {
    let p = case.paper.as_ref()?;
    Some((p.rayleigh_alpha?, p.rayleigh_beta?))
}

/// Runs loops 1-3 from the case's nominal values.
pub fn calibrate(
    case: &MeasuredCase,
    targets: &Targets,
    settings: &CalibrateSettings,
    out: Option<&OutDir>,
    control: &RunControl,
) -> Result<Calibration> {
    let start = std::time::Instant::now();
    let nominal = SpringState::nominal(case);
    let mut state = nominal;
    let stiffness = tune_youngs_modulus(
        &mut state,
        &settings.fe,
        targets.stiffness_n_mm,
        settings.stiffness_tolerance,
        out,
    )?;
    let period = tune_mass(
        &mut state,
        &settings.fe,
        targets.period_s,
        settings.period_tolerance,
        out,
    )?;
    let damping = tune_damping(
        &mut state,
        &settings.fe,
        &settings.damping,
        targets.damping_ratio,
        paper_damping_point(case),
        out,
        control,
    )?;
    let calibration = Calibration {
        case: case.name.clone(),
        targets: *targets,
        settings: settings.clone(),
        nominal,
        stiffness,
        period,
        damping,
        state,
        elapsed_s: start.elapsed().as_secs_f64(),
    };
    if let Some(out) = out {
        plots::loops_figure(
            &[&calibration.stiffness, &calibration.period],
            &out.staged("fig7_loops.png")?,
        )?;
        let json = serde_json::to_string_pretty(&calibration)
            .map_err(|e| TuneError::Invalid(format!("calibration.json: {e}")))?;
        out.write("calibration.json", json.as_bytes())?;
    }
    Ok(calibration)
}

impl Calibration {
    /// A few lines for the terminal.
    pub fn summary(&self) -> String {
        let s = &self.state;
        let d = &self.damping;
        let mut text = format!(
            "case: {}\n\
             loop 1: E = {:.1} MPa -> K = {:.6} N/mm (target {}, error {:+.2e}) in {} runs\n\
             loop 2: mass = {:.6} kg -> T = {:.6} s (axial mode's modal period; target {}, error {:+.2e}) in {} runs\n\
             loop 3: alpha = {}, beta = {} -> zeta = {:.6} ({} transients, method {}; target {}, error {:+.3}%)\n",
            self.case,
            s.youngs_modulus_mpa,
            self.stiffness.result,
            self.targets.stiffness_n_mm,
            self.stiffness.relative_error,
            self.stiffness.iterations.len(),
            s.mass_kg,
            self.period.result,
            self.targets.period_s,
            self.period.relative_error,
            self.period.iterations.len(),
            s.alpha,
            s.beta,
            d.chosen.zeta,
            d.grids.iter().map(|g| g.runs).sum::<usize>(),
            d.method,
            self.targets.damping_ratio,
            100.0 * (d.chosen.zeta - self.targets.damping_ratio) / self.targets.damping_ratio,
        );
        if let Some(direct) = d.chosen.direct {
            text.push_str(&format!(
                "        direct integration at the chosen point: zeta = {:.6} ({:+.3}% from {}), T = {:.6} s\n",
                direct.zeta_mean,
                100.0 * d.chosen.direct_relative_difference.unwrap_or(f64::NAN),
                d.method,
                direct.period_s
            ));
        }
        if let Some(v) = &d.valley {
            text.push_str(&format!(
                "valley: zeta = {:.4e} alpha + {:.4} beta + {:.1e}; with alpha = 0, beta = {:.5e} s; \
                 alpha's share at the chosen point {:.1}%\n",
                v.plane.a,
                v.plane.b,
                v.plane.z0,
                v.beta_alone,
                100.0 * d.chosen.alpha_share
            ));
        }
        if let Some(p) = &d.paper_point {
            text.push_str(&format!(
                "paper's point alpha = {}, beta = {}: zeta = {:.6} here\n",
                p.alpha, p.beta, p.zeta
            ));
        }
        if !d.complete {
            text.push_str("(stopped before every grid point was run; rerun to resume)\n");
        }
        text
    }
}
