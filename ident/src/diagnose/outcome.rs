//! Everything a diagnosis computed ([`Outcome`]): the report, the figures and the
//! terminal summary draw on it.

use super::data::DecayData;
use super::evidence::Signatures;
use super::report::{self, Diagnosis};
use super::run::{CandidateRun, ModelRun};
use crate::case::MeasuredCase;
use std::ops::Range;

/// Everything a diagnosis computed (the report and the figures draw on it).
pub struct Outcome {
    /// The measured case as read.
    pub case: MeasuredCase,
    /// The diagnosed decay record (the first axial one), conditioned.
    pub decay: DecayData,
    /// The static record used and its loading branch (sample range), if the case has one.
    pub statics: Option<(crate::case::StaticRecord, Range<usize>)>,
    /// The records' signatures.
    pub signatures: Signatures,
    /// The baseline's figures: the paper's calibration, only the initial states fitted.
    pub baseline: ModelRun,
    /// The reference's figures: the linear model refined by output error.
    pub reference: ModelRun,
    /// Every candidate and its fit, in search order.
    pub candidates: Vec<CandidateRun>,
    /// The report's data (`diagnosis.json`).
    pub diagnosis: Diagnosis,
    /// Measured amplitude spectrum (frequencies Hz, amplitudes m/s^2) for the figure.
    pub spectrum: Option<(Vec<f64>, Vec<f64>)>,
    /// Fixed-interface modes kept.
    pub modes: usize,
    /// Largest step as a fraction of the axial period.
    pub step_fraction: f64,
    /// Where the baseline's K came from.
    pub stiffness_source: report::StiffnessSource,
    /// The other axial decay records fitted jointly with the first: file, samples, and
    /// attached mass minus the first record's (kg).
    pub joint_records: Vec<(std::path::PathBuf, usize, f64)>,
}

/// A few lines for the terminal.
pub fn summary(o: &Outcome) -> String {
    let d = &o.diagnosis;
    let mut s = format!(
        "baseline: E = {:.1} MPa, mass = {:.5} kg, beta = {:.4e} s, K = {:.5} N/mm, T = {:.6} s, \
         zeta = {:.6}, residual_rms = {:.4}, forecast_rms = {:.4}\n",
        d.baseline.youngs_modulus_mpa,
        d.baseline.mass_kg,
        d.baseline.rayleigh_beta,
        d.baseline.stiffness_n_mm,
        d.baseline.period_s,
        d.baseline.damping_ratio,
        d.baseline.residual_rms,
        d.baseline.forecast_rms
    );
    for c in &d.candidates {
        let line = format!(
            "  {:<26} residual_rms {:>8} forecast_rms {:>8} dBIC {:>10} {}",
            c.effect,
            c.residual_rms.map_or("-".into(), |x| format!("{x:.4}")),
            c.forecast_rms.map_or("-".into(), |x| format!("{x:.4}")),
            c.delta_bic.map_or("-".into(), |x| format!("{x:.1}")),
            if c.significant { "significant" } else { "" }
        );
        s.push_str(line.trim_end());
        s.push('\n');
    }
    s.push_str(&format!("cause: {}", d.cause));
    if let (Some(e), g) = (&d.extended, &d.gain) {
        for (k, v) in &e.parameters {
            s.push_str(&format!(", {k} = {v:.6e}"));
        }
        s.push_str(&format!(
            "; gain: residual_rms_ratio {:.4}, forecast_rms_ratio {:.4}",
            g.residual_rms_ratio, g.forecast_rms_ratio
        ));
    }
    s.push_str(&format!(" ({:.2} s)\n", d.runtime_s));
    s
}
