//! `diagnosis.json` (field names and units exactly as `docs/measured-case.md`),
//! `report.md` with its figures and tables, written through temporary files with
//! `diagnosis.json` last: a failed run leaves no diagnosis behind.

use super::effects::CATALOGUE;
use super::evidence::Signatures;
use super::model::Physical;
use super::run::{CandidateRun, ModelRun};
use super::select::{Choice, Tests};
use crate::case::Quantity;
use crate::fe::SpringState;
use serde::Serialize;
use std::collections::BTreeMap;

/// The reference's residual RMS beyond which, with no cause named, the misfit is
/// reported as unexplained: three times the noise floor.
pub const UNEXPLAINED_NOISE: f64 = 3.0;

/// The paper's model calibrated to the records.
#[derive(Debug, Clone, Serialize)]
pub struct Baseline {
    /// Young's modulus calibrated to the measured stiffness by the paper's loop 1 (MPa).
    pub youngs_modulus_mpa: f64,
    /// The weight's mass tuned to the measured period by the paper's loop 2 (kg).
    pub mass_kg: f64,
    /// Rayleigh alpha (1/s); always 0: the baseline's damping is stiffness-proportional.
    pub rayleigh_alpha: f64,
    /// Rayleigh beta `2 zeta / w` from the paper's decrement (s).
    pub rayleigh_beta: f64,
    /// Axial stiffness K of the calibrated model (N/mm).
    pub stiffness_n_mm: f64,
    /// Damped period T by the paper's logarithmic decrement (s).
    pub period_s: f64,
    /// Damping ratio zeta by the paper's logarithmic decrement (-).
    pub damping_ratio: f64,
    /// RMS of simulated minus measured over the records, over the measured RMS (-).
    pub residual_rms: f64,
    /// The same figure on the second halves, calibrated on the first halves only (-).
    pub forecast_rms: f64,
}

/// The linear model refined by output error (coil's addition).
#[derive(Debug, Clone, Serialize)]
pub struct Reference {
    /// The weight's mass refined by output error (kg).
    pub mass_kg: f64,
    /// Rayleigh beta refined by output error (s).
    pub rayleigh_beta: f64,
    /// Its residual RMS over the records, relative as in [`Baseline::residual_rms`] (-).
    pub residual_rms: f64,
    /// Its relative RMS on the second halves, fitted on the first halves only (-).
    pub forecast_rms: f64,
}

/// The chosen extension.
#[derive(Debug, Clone, Serialize)]
pub struct Extended {
    /// The candidate's name: its effects joined by `+` (one effect: its name).
    pub effect: String,
    /// The names of its effects, in catalogue order.
    pub effects: Vec<String>,
    /// Every kept effect's parameters (SI, the spec's names) and standard errors.
    pub parameters: BTreeMap<String, f64>,
    /// Each parameter's standard error, inflated for the residuals' correlation (same units).
    pub parameters_se: BTreeMap<String, f64>,
    /// Its residual RMS over the records, relative as in [`Baseline::residual_rms`] (-).
    pub residual_rms: f64,
    /// Its relative RMS on the second halves, fitted on the first halves only (-).
    pub forecast_rms: f64,
    /// The weight's mass fitted with the effects (kg).
    pub mass_kg: f64,
    /// Rayleigh beta fitted with the effects (s).
    pub rayleigh_beta: f64,
    /// The largest relative standard error of its parameters: the fit's, inflated by
    /// `sqrt(N / N_eff)` for the residuals' correlation (indicative; the mesh and the
    /// model's form bias it more, see docs/diagnose.md).
    pub parameter_relative_error: f64,
}

/// One effect the extended model keeps (spec: "Several effects at once").
#[derive(Debug, Clone, Serialize)]
pub struct Cause {
    /// The effect's name in the spec's catalogue.
    pub effect: String,
    /// Its parameters by the spec's names (SI, the unit in the name).
    pub parameters: BTreeMap<String, f64>,
    /// Their standard errors, inflated for the residuals' correlation (same units).
    pub parameters_se: BTreeMap<String, f64>,
    /// Its part of the explained misfit (drop-one increase of the residual sum of
    /// squares, normalised over the kept effects).
    pub share: f64,
}

/// One tried candidate: an effect, or up to three together.
#[derive(Debug, Clone, Serialize)]
pub struct Candidate {
    /// Its effects joined by `+`.
    pub effect: String,
    /// The names of its effects, in catalogue order.
    pub effects: Vec<String>,
    /// Its relative residual RMS over the records (-); `None` when its fit failed.
    pub residual_rms: Option<f64>,
    /// What the records' signatures say about its effects, for a person.
    pub evidence: String,
    /// Its relative RMS on the second halves, fitted on the first halves (-); `None` if failed.
    pub forecast_rms: Option<f64>,
    /// Forecast RMS of the quarter after each rolling origin (`select::ORIGINS`).
    pub rolling_forecast_rms: Vec<f64>,
    /// Its effects' fitted parameters by the spec's names (SI, the unit in the name).
    pub parameters: BTreeMap<String, f64>,
    /// Their standard errors, inflated for the residuals' correlation; empty if the fit failed.
    pub parameters_se: BTreeMap<String, f64>,
    /// Its BIC gain over the reference on `N_eff` residuals (`select`); `None` if the fit failed.
    pub delta_bic: Option<f64>,
    /// The effective number of independent residuals `N_eff`; `None` if the fit failed.
    pub effective_samples: Option<f64>,
    /// True when every test held (`tests`).
    pub significant: bool,
    /// Each test with its number, its limit and whether it held.
    pub tests: Option<Tests>,
    /// The fitted weight's mass (kg) and Rayleigh beta (s).
    pub mass_kg: Option<f64>,
    /// The fitted Rayleigh beta (s).
    pub rayleigh_beta: Option<f64>,
    /// The fitted state at the record's first sample about the static equilibrium:
    /// per boundary DOF, displacement (mm or rad) then velocity (mm/s or rad/s).
    pub initial_state: Vec<f64>,
    /// Why its fit failed, when it did.
    pub fit_error: Option<String>,
    /// Its effects that did not move from their bound (zero), with the reason; their
    /// parameters are reported as 0 and carry no standard error.
    pub bounds: Vec<String>,
}

/// Extended over baseline figures.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Gain {
    /// Extended over baseline `residual_rms` (-; smaller is better).
    pub residual_rms_ratio: f64,
    /// Extended over baseline `forecast_rms` (-; smaller is better).
    pub forecast_rms_ratio: f64,
    /// The same ratio with the record's noise removed from both figures,
    /// `sqrt((e^2 - n^2) / (b^2 - n^2))`, `n` = `noise_floor_rms`: the share of the
    /// baseline's model error that the extension leaves. `residual_rms_ratio` cannot
    /// fall below `n / b`, however right the extension is.
    pub model_error_ratio: f64,
}

/// The whole `diagnosis.json`.
#[derive(Debug, Clone, Serialize)]
pub struct Diagnosis {
    /// The dominant cause (the first of `causes`), or `none`.
    pub cause: String,
    /// Every effect the extended model keeps, by share, largest first.
    pub causes: Vec<Cause>,
    /// When the linear model misses beyond the noise and no candidate passes: what
    /// the records show, in words with numbers.
    pub unexplained: Option<String>,
    /// When a cause is named but its extended model still misses the records by more
    /// than `UNEXPLAINED_NOISE` times the noise floor: how much is left, in words with
    /// numbers (the cause explains part of the misfit, not all of it).
    pub remaining_misfit: Option<String>,
    /// The quantity the decay record measures; the fit and `residual_rms` compare it.
    pub quantity: Quantity,
    /// The paper's model calibrated to the records.
    pub baseline: Baseline,
    /// The chosen extension; `None` when the cause is `none`.
    pub extended: Option<Extended>,
    /// Every candidate tried, with its figures and tests.
    pub candidates: Vec<Candidate>,
    /// Extended over baseline figures; all 1 when the cause is `none`.
    pub gain: Gain,
    /// The linear model refined by output error (coil's addition).
    pub reference: Reference,
    /// The records' signatures the candidates were proposed and checked with.
    pub signatures: Signatures,
    /// The record's noise as a `residual_rms`: noise RMS over the record's RMS. No
    /// model's residual can go below it.
    pub noise_floor_rms: f64,
    /// What a person should check: records ignored, calibrated values far from the
    /// nominal ones, a misfit no effect explains.
    pub warnings: Vec<String>,
    /// Wall-clock time of the diagnosis (s).
    pub runtime_s: f64,
}

/// What [`assemble`] reads about the baseline.
pub struct BaselineInputs<'a> {
    /// The spring, its Young's modulus calibrated to the measured stiffness.
    pub state: &'a SpringState,
    /// The paper's linear model (mass, beta) calibrated to the decay.
    pub physical: &'a Physical,
    /// Damped period by the paper's logarithmic decrement (s).
    pub period_s: f64,
    /// Damping ratio by the paper's logarithmic decrement (-).
    pub damping_ratio: f64,
    /// Axial stiffness of the calibrated model (N/mm).
    pub stiffness_n_mm: f64,
    /// The baseline's figures over the records.
    pub run: &'a ModelRun,
    /// Where the stiffness the modulus was tuned to came from.
    pub stiffness_source: StiffnessSource,
}

/// Where the baseline's K came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StiffnessSource {
    /// The static record's straight line.
    StaticRecord,
    /// The case's `targets.stiffness_n_mm`.
    Target,
    /// No static record and no target: the nominal E on the FE model (the weight's
    /// mass is then tuned to the period).
    Nominal,
}

impl StiffnessSource {
    /// Where K comes from: the static record when there is one, else the case's target,
    /// else the nominal FE model.
    pub fn of(static_record: bool, target: bool) -> Self {
        match (static_record, target) {
            (true, _) => StiffnessSource::StaticRecord,
            (false, true) => StiffnessSource::Target,
            (false, false) => StiffnessSource::Nominal,
        }
    }
}

/// Parameters and standard errors of the effects in `set` of a fitted run.
fn with_errors(
    set: &[usize],
    physical: &Physical,
    rel_se: &[f64],
) -> (BTreeMap<String, f64>, BTreeMap<String, f64>) {
    let values = super::run::parameters(set, physical);
    // A parameter at its bound or not identifiable has no standard error (JSON has no
    // NaN or infinity): it is left out, and the candidate's `bounds` say why.
    let errors = set
        .iter()
        .zip(rel_se)
        .map(|(&i, r)| {
            (
                CATALOGUE[i].parameter().to_string(),
                r * physical.effects[i].abs(),
            )
        })
        .filter(|(_, se)| se.is_finite() && *se > 0.0)
        .collect();
    (values, errors)
}

/// The names of the catalogue effects `set`.
fn effect_names(set: &[usize]) -> Vec<String> {
    set.iter()
        .map(|&i| CATALOGUE[i].name().to_string())
        .collect()
}

/// Every candidate tried as the report lists it, with its figures and tests.
fn candidate_list(candidates: &[CandidateRun], choice: &Choice) -> Vec<Candidate> {
    candidates
        .iter()
        .zip(&choice.scores)
        .map(|(c, score)| {
            let ok = c.run.as_ref().ok();
            let (parameters, parameters_se) = match (ok, score) {
                (Some(r), Some(s)) => with_errors(&c.effects, &r.full.physical, &s.rel_se),
                (Some(r), None) => (
                    super::run::parameters(&c.effects, &r.full.physical),
                    BTreeMap::new(),
                ),
                _ => (BTreeMap::new(), BTreeMap::new()),
            };
            Candidate {
                effect: c.label(),
                effects: effect_names(&c.effects),
                residual_rms: ok.map(|r| r.residual_rms),
                evidence: c.evidence.clone(),
                forecast_rms: ok.map(|r| r.forecast_rms),
                rolling_forecast_rms: ok.map(|r| r.rolling.clone()).unwrap_or_default(),
                parameters,
                parameters_se,
                delta_bic: score.as_ref().map(|s| s.delta_bic),
                effective_samples: score.as_ref().map(|s| s.n_eff),
                significant: score.as_ref().is_some_and(|s| s.tests.passed()),
                tests: score.as_ref().map(|s| s.tests.clone()),
                mass_kg: ok.map(|r| r.full.physical.mass_kg),
                rayleigh_beta: ok.map(|r| r.full.physical.beta_s),
                initial_state: ok.map(|r| r.full.initial_state.clone()).unwrap_or_default(),
                fit_error: c.run.as_ref().err().cloned(),
                bounds: c.bounds.clone(),
            }
        })
        .collect()
}

/// Builds the report's data.
#[allow(clippy::too_many_arguments)]
pub fn assemble(
    base: &BaselineInputs<'_>,
    reference: &ModelRun,
    candidates: &[CandidateRun],
    choice: &Choice,
    signatures: &Signatures,
    noise_floor_rms: f64,
    unexplained: Option<String>,
    quantity: Quantity,
    warnings: Vec<String>,
    runtime_s: f64,
) -> Diagnosis {
    let baseline = Baseline {
        youngs_modulus_mpa: base.state.youngs_modulus_mpa,
        mass_kg: base.physical.mass_kg,
        rayleigh_alpha: 0.0,
        rayleigh_beta: base.physical.beta_s,
        stiffness_n_mm: base.stiffness_n_mm,
        period_s: base.period_s,
        damping_ratio: base.damping_ratio,
        residual_rms: base.run.residual_rms,
        forecast_rms: base.run.forecast_rms,
    };
    let list = candidate_list(candidates, choice);
    let chosen = choice.cause.and_then(|i| {
        let c = &candidates[i];
        let score = choice.scores[i].as_ref()?;
        c.run.as_ref().ok().map(|r| (c, r, score))
    });
    let extended = chosen.map(|(c, run, score)| {
        let (parameters, parameters_se) =
            with_errors(&c.effects, &run.full.physical, &score.rel_se);
        Extended {
            effect: c.label(),
            effects: effect_names(&c.effects),
            parameters,
            parameters_se,
            residual_rms: run.residual_rms,
            forecast_rms: run.forecast_rms,
            mass_kg: run.full.physical.mass_kg,
            rayleigh_beta: run.full.physical.beta_s,
            parameter_relative_error: score.rel_se.iter().fold(0.0, |m: f64, x| m.max(*x)),
        }
    });
    let causes: Vec<Cause> = chosen.map_or(Vec::new(), |(c, run, score)| {
        choice
            .shares
            .iter()
            .map(|&(e, share)| {
                let k = c.effects.iter().position(|&x| x == e).unwrap_or(0);
                let (parameters, parameters_se) =
                    with_errors(&[e], &run.full.physical, &score.rel_se[k..=k]);
                Cause {
                    effect: CATALOGUE[e].name().to_string(),
                    parameters,
                    parameters_se,
                    share,
                }
            })
            .collect()
    });
    let floor = noise_floor_rms;
    // Without an extension the model stays the baseline: every ratio is 1.
    let gain = extended.as_ref().map_or(
        Gain {
            residual_rms_ratio: 1.0,
            forecast_rms_ratio: 1.0,
            model_error_ratio: 1.0,
        },
        |e| Gain {
            residual_rms_ratio: e.residual_rms / baseline.residual_rms,
            forecast_rms_ratio: e.forecast_rms / baseline.forecast_rms,
            model_error_ratio: ((e.residual_rms.powi(2) - floor * floor).max(0.0)
                / (baseline.residual_rms.powi(2) - floor * floor).max(1e-300))
            .sqrt(),
        },
    );
    let remaining_misfit = extended
        .as_ref()
        .filter(|e| e.residual_rms > UNEXPLAINED_NOISE * floor)
        .map(|e| {
            format!(
                "the extended model ({}) still misses the records by a residual RMS of {:.4}, \
                 {:.1} times the noise floor of {:.4}; it leaves {:.0} % of the linear model's \
                 error (model error ratio {:.3}): the named cause explains part of the misfit, \
                 and something the catalogue does not hold may remain",
                e.effect,
                e.residual_rms,
                e.residual_rms / floor.max(1e-300),
                floor,
                100.0 * gain.model_error_ratio,
                gain.model_error_ratio
            )
        });
    Diagnosis {
        cause: causes.first().map_or("none".into(), |c| c.effect.clone()),
        causes,
        unexplained,
        remaining_misfit,
        quantity,
        baseline,
        extended,
        candidates: list,
        gain,
        reference: Reference {
            mass_kg: reference.full.physical.mass_kg,
            rayleigh_beta: reference.full.physical.beta_s,
            residual_rms: reference.residual_rms,
            forecast_rms: reference.forecast_rms,
        },
        signatures: signatures.clone(),
        noise_floor_rms: floor,
        warnings,
        runtime_s,
    }
}

/// What the records show when the linear model misses beyond the noise and no
/// candidate passes, in plain words with the numbers and their uncertainty.
pub fn unexplained(
    s: &Signatures,
    reference: &ModelRun,
    noise_floor_rms: f64,
    candidates: &[CandidateRun],
    choice: &Choice,
) -> String {
    let mut parts = vec![format!(
        "the linear model misses the record by a residual RMS of {:.4}, against a noise floor \
         of {:.4}, and no catalogue effect or combination passes every test",
        reference.residual_rms, noise_floor_rms
    )];
    if let Some(bb) = &s.backbone {
        // Frequency change over the record's amplitude range, from the backbone.
        let (a_hi, a_lo) = s
            .per_cycle
            .iter()
            .fold((0.0_f64, f64::INFINITY), |(h, l), c| {
                (h.max(c.amplitude_m), l.min(c.amplitude_m))
            });
        let change = 0.5 * bb.b_per_m2 * (a_lo * a_lo - a_hi * a_hi) * 100.0;
        parts.push(format!(
            "the frequency {} as the amplitude falls from {:.3} to {:.3} mm ({:+.2} % from the \
             backbone f^2 = f0^2 (1 + b A^2), b = {:.3e} +- {:.1e} 1/m^2: {})",
            if change > 0.0 { "rises" } else { "falls" },
            1e3 * a_hi,
            1e3 * a_lo,
            change,
            bb.b_per_m2,
            bb.b_se,
            if bb.b_per_m2 < 0.0 {
                "a softening trend"
            } else {
                "a hardening trend"
            }
        ));
    }
    if let Some(l) = &s.loss {
        parts.push(format!(
            "the loss per cycle dA = a0 + a1 A + a2 A^2 has a0 = {:.3e} +- {:.1e} m (constant, \
             dry friction), a1 = {:.3e} +- {:.1e} (viscous), a2 = {:.3e} +- {:.1e} 1/m (growing \
             with amplitude, drag)",
            l.a0_m, l.a0_se, l.a1, l.a1_se, l.a2_per_m, l.a2_se
        ));
    }
    parts.push(match &s.second_peak {
        Some(p) => format!(
            "a second spectral line at {:.4} Hz, {:.1} % of the axial one",
            p.frequency_hz,
            100.0 * p.relative_amplitude
        ),
        None => format!("one spectral line at {:.4} Hz", s.axial_hz),
    });
    if let Some(st) = &s.statics {
        parts.push(format!(
            "the static record bends with k3 = {:.3e} +- {:.1e} N/m^3 and shows a hysteresis \
             half-width of {:.3e} +- {:.1e} N",
            st.k3_n_m3, st.k3_se, st.friction_n, st.friction_se
        ));
    }
    // The closest candidate and what stopped it.
    if let Some((c, sc)) = candidates
        .iter()
        .zip(&choice.scores)
        .filter_map(|(c, s)| s.as_ref().map(|s| (c, s)))
        .max_by(|a, b| a.1.delta_bic.total_cmp(&b.1.delta_bic))
    {
        parts.push(format!(
            "the closest candidate, {} (dBIC {:.1}), fails: {}",
            c.label(),
            sc.delta_bic,
            sc.tests.failed().join(", ")
        ));
    }
    let mut text = parts.join("; ");
    text.push('.');
    text
}
