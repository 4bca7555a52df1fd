//! What a fit of one model to the records gives the choice and the report: the
//! model's figures over every record ([`ModelRun`]), a candidate set of effects
//! ([`CandidateRun`]), and the records laid end to end for the joint fit ([`Joint`]).

use super::data::DecayData;
use super::effects::{self, CATALOGUE};
use super::fit::{self, Fitted, Knob};
use super::model::Physical;
use std::collections::BTreeMap;
use std::ops::Range;

/// Rolling origins as fractions of the record; each forecasts the next quarter
/// (`select`'s forecast test).
pub const ORIGINS: [f64; 3] = [0.25, 0.5, 0.75];

/// One fitted model's figures on the full record and on the forecasts.
#[derive(Debug, Clone)]
pub struct ModelRun {
    /// The fit on every record's whole length.
    pub full: Fitted,
    /// The fit on every record's first half (the forecast's).
    pub half: Fitted,
    /// Relative residual RMS of `full` over all the records (-).
    pub residual_rms: f64,
    /// Relative RMS of `half` on every record's second half (-).
    pub forecast_rms: f64,
    /// Forecast RMS (relative) of the quarter after each rolling origin
    /// (`ORIGINS`), fitted up to the origin; empty for the baseline.
    pub rolling: Vec<f64>,
}

/// One candidate: a set of catalogue effects (one to three), its evidence and its fit.
#[derive(Debug, Clone)]
pub struct CandidateRun {
    /// Catalogue indices, ascending.
    pub effects: Vec<usize>,
    /// What the records' signatures say about its effects, for a person.
    pub evidence: String,
    /// Each effect's signature check at the fitted values (empty if the fit failed).
    pub signatures: Vec<effects::SignatureCheck>,
    /// Its figures over the records, or why its fit failed.
    pub run: std::result::Result<ModelRun, String>,
    /// Its effects that did not move from their bound (zero), each with the reason
    /// (`effects::at_bound`); their values are reported as 0.
    pub bounds: Vec<String>,
}

impl CandidateRun {
    /// The candidate's name: its effects joined by `+`.
    pub fn label(&self) -> String {
        self.effects
            .iter()
            .map(|&i| CATALOGUE[i].name())
            .collect::<Vec<_>>()
            .join("+")
    }
}

/// The case's decay records laid end to end for the joint fit (`fit::Segment`).
pub struct Joint {
    /// The records, each scaled by its segment's weight.
    pub measured: Vec<f64>,
    /// Their layout; the first is the diagnosed record ([`super::Outcome::decay`]).
    pub segments: Vec<fit::Segment>,
    /// The other records' files, in the segments' order after the first.
    pub files: Vec<std::path::PathBuf>,
}

impl Joint {
    /// The records after the first: file, samples, and attached mass minus the first
    /// record's (kg).
    pub fn others(&self) -> Vec<(std::path::PathBuf, usize, f64)> {
        self.files
            .iter()
            .zip(&self.segments[1..])
            .map(|(f, s)| (f.clone(), s.span.len(), s.mass_delta_kg))
            .collect()
    }

    /// The linear model's knobs: the mass and beta, and the spring's stiffness when the
    /// records were taken with different weights (two frequencies separate the two).
    pub fn knobs(&self) -> Vec<Knob> {
        let mut knobs = vec![Knob::Mass, Knob::Beta];
        if self.segments.iter().any(|s| s.mass_delta_kg != 0.0) {
            knobs.push(Knob::Stiffness);
        }
        knobs
    }

    /// Lays the first record and the others (each with its mass difference to the
    /// first's weight) end to end. The first record's own difference to the case's
    /// `mass_kg` is absorbed by the fitted mass.
    pub fn lay_out(first: &DecayData, others: &[(DecayData, f64)]) -> Joint {
        let floor = |d: &DecayData| {
            let rms = (d.measured.iter().map(|x| x * x).sum::<f64>()
                / d.measured.len().max(1) as f64)
                .sqrt();
            d.measured_noise.rms.max(1e-6 * rms).max(1e-300)
        };
        let reference = floor(first);
        let mut measured = Vec::new();
        let mut segments = Vec::new();
        let mut files = Vec::new();
        for (k, (d, delta)) in std::iter::once((first, 0.0))
            .chain(others.iter().map(|(d, m)| (d, *m)))
            .enumerate()
        {
            let weight = if k == 0 { 1.0 } else { reference / floor(d) };
            let start = measured.len();
            measured.extend(d.measured.iter().map(|x| weight * x));
            segments.push(fit::Segment {
                span: start..measured.len(),
                step_s: d.signal.step_s(),
                quantity: d.quantity,
                mass_delta_kg: delta,
                weight,
                slow_line: d.slow_line.map(|l| (l.omega_rad_s, l.decay_rate_1_s)),
            });
            if k > 0 {
                files.push(d.signal.source().to_path_buf());
            }
        }
        Joint {
            measured,
            segments,
            files,
        }
    }
}

/// A model's figures over every record: residual, the forecast of each record's second
/// half from the fit on the first halves, and the rolling forecasts of the quarter after
/// each origin from the fits up to it (`rolling`, one per origin; none for the baseline).
pub fn model_run(full: Fitted, half: Fitted, joint: &Joint, rolling: &[Fitted]) -> ModelRun {
    let measured = &joint.measured;
    if std::env::var_os("COIL_DIAGNOSE_TRACE").is_some() && joint.segments.len() > 1 {
        let each: Vec<String> = joint
            .segments
            .iter()
            .map(|s| {
                let r = fit::relative_rms(&full.simulated, measured, std::slice::from_ref(&s.span));
                format!("{r:.4}")
            })
            .collect();
        eprintln!("  residual_rms of each record: {}", each.join(", "));
    }
    let over = |f: &dyn Fn(&fit::Segment) -> Range<usize>| -> Vec<Range<usize>> {
        joint.segments.iter().map(f).collect()
    };
    ModelRun {
        residual_rms: fit::relative_rms(
            &full.simulated,
            measured,
            std::slice::from_ref(&(0..measured.len())),
        ),
        forecast_rms: fit::relative_rms(&half.simulated, measured, &over(&|s| s.between(0.5, 1.0))),
        rolling: rolling
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let ranges = over(&|s| {
                    let o = s.window(ORIGINS[i]).end;
                    o..(o + s.span.len() / 4).min(s.span.end)
                });
                fit::relative_rms(&f.simulated, measured, &ranges)
            })
            .collect(),
        full,
        half,
    }
}

/// Parameters in SI by the spec's names, of the effects in `set`.
pub fn parameters(set: &[usize], phys: &Physical) -> BTreeMap<String, f64> {
    set.iter()
        .map(|&i| (CATALOGUE[i].parameter().to_string(), phys.effects[i]))
        .collect()
}
