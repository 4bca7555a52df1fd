//! Output-error fits of a reduced spring model to a measured decay record.
//!
//! The fitted quantities are "knobs" on the model's [`Physical`] parameters (the weight's
//! mass, Rayleigh beta, an effect's magnitude), each fitted as its logarithm so it stays
//! positive, plus the record's initial state (the record starts some time after the
//! impulse, so the weight's displacement and velocity at its first sample are unknown):
//!
//! - **linear models** (no point law): the response is linear in the initial state, so
//!   for each knob vector the state is solved exactly by linear least squares on the
//!   responses to unit initial states (variable projection, Golub & Pereyra 1973); the
//!   Levenberg-Marquardt search ([`super::lm`]) sees the knobs only;
//! - **nonlinear models**: the initial displacement and velocity are fitted together
//!   with the knobs, starting from the linear model's projected state.
//!
//! Records of displacement or velocity carry the sensor's offset and a slow drift: an
//! offset `c0` and a linear drift `c1 t` are fitted with every model, by the same
//! linear least squares (two more columns beside the unit responses of a linear model;
//! projected out of the residual of a nonlinear one), so they cost no search. The fit
//! compares the measured quantity itself (a displacement with a displacement): no
//! record is differentiated for the fit.
//!
//! Each effect is a knob: a positive one is fitted as its logarithm, one that takes
//! either sign (the cubic spring) as itself.
//!
//! Residuals are `simulated - measured` (the record's quantity, SI) on the fitted samples,
//! optionally followed by a static block (see [`StaticBlock`]), each block divided by
//! its noise level so that they weigh by their information.

use super::effects::CATALOGUE;
use super::lm::{self, LmOptions, Residuals};
use super::model::{Physical, ReducedSpring};
use crate::case::Quantity;
use std::ops::Range;

/// A quantity the fit may move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Knob {
    /// The weight's mass (kg).
    Mass,
    /// Rayleigh beta on the spring (s).
    Beta,
    /// A catalogue effect's magnitude in its SI unit (`Physical::effects[i]`).
    Effect(usize),
}

impl Knob {
    /// True when the knob is fitted as itself (either sign), not as a logarithm.
    fn signed(&self) -> bool {
        matches!(self, Knob::Effect(i) if CATALOGUE[*i].signed())
    }
}

/// A static force-compression block fitted beside the decay (cubic stiffness): the model
/// force `k x + k3 x^3` against the measured loading points.
#[derive(Debug, Clone)]
pub struct StaticBlock {
    pub displacement_m: Vec<f64>,
    pub force_n: Vec<f64>,
    /// The measured force's noise level (N).
    pub sigma_n: f64,
}

/// What to fit and on which samples.
pub struct Problem<'a> {
    pub model: &'a ReducedSpring,
    pub start: Physical,
    pub knobs: Vec<Knob>,
    pub measured: &'a [f64],
    pub step_s: f64,
    /// Samples whose residuals are fitted.
    pub range: Range<usize>,
    /// Noise level of the decay samples (m/s^2), dividing their residuals.
    pub sigma: f64,
    pub statics: Option<&'a StaticBlock>,
    /// Initial state to start a nonlinear fit from (model units).
    pub initial_state: Option<Vec<f64>>,
    /// The record's quantity.
    pub quantity: Quantity,
    /// Fit an offset and a linear drift beside the model.
    pub drift: bool,
}

/// A finished fit.
#[derive(Debug, Clone)]
pub struct Fitted {
    pub physical: Physical,
    pub initial_state: Vec<f64>,
    /// The simulated record over all samples (m/s^2).
    pub simulated: Vec<f64>,
    /// Sum of squared (unscaled) decay residuals over the fitted range.
    pub rss: f64,
    /// Fitted parameters: knobs plus the initial state's components.
    pub n_params: usize,
    /// Relative standard errors of the knobs (indicative; see `lm`).
    pub knob_rel_errors: Vec<f64>,
    /// The knobs fitted.
    pub knobs: Vec<Knob>,
    pub iterations: usize,
    pub evaluations: usize,
}

impl Problem<'_> {
    fn physical(&self, p: &[f64]) -> Physical {
        let mut phys = self.start;
        for (k, v) in self.knobs.iter().zip(p) {
            let x = if k.signed() { *v } else { v.exp() };
            match k {
                Knob::Mass => phys.mass_kg = x,
                Knob::Beta => phys.beta_s = x,
                Knob::Effect(i) => phys.effects[*i] = x,
            }
        }
        phys
    }

    fn knob_start(&self) -> Vec<f64> {
        self.knobs
            .iter()
            .map(|k| {
                let x = match k {
                    Knob::Mass => self.start.mass_kg,
                    Knob::Beta => self.start.beta_s,
                    Knob::Effect(i) => self.start.effects[*i],
                };
                if k.signed() {
                    x
                } else {
                    x.max(1e-300).ln()
                }
            })
            .collect()
    }

    /// The offset and drift columns over the first `n` samples (none for an
    /// acceleration record): 1 and the time over the record's length.
    fn drift_columns(&self, n: usize) -> Vec<Vec<f64>> {
        if !self.drift {
            return Vec::new();
        }
        let len = self.measured.len().max(1) as f64;
        vec![vec![1.0; n], (0..n).map(|i| i as f64 / len).collect()]
    }

    fn linear(&self) -> bool {
        !self.model.is_nonlinear(&self.start)
    }

    /// The simulated record and the initial state for knob values `p` (and, for a
    /// nonlinear model, the state's components after them).
    /// The simulated record over its first `n` samples and the initial state.
    fn simulate(&self, p: &[f64], n: usize) -> Result<(Vec<f64>, Vec<f64>), String> {
        let k = self.knobs.len();
        let phys = self.physical(&p[..k]);
        let drift = self.drift_columns(n);
        if self.linear() {
            let mut basis = self.model.basis(&phys, self.step_s, n, self.quantity)?;
            let states = basis.len();
            basis.extend(drift);
            let columns: Vec<Vec<f64>> = basis
                .iter()
                .map(|b| b[self.range.clone()].to_vec())
                .collect();
            let mut c = lm::linear_least_squares(&columns, &self.measured[self.range.clone()])
                .ok_or("the initial state is not identifiable from the record")?;
            let mut sim = vec![0.0; n];
            for (b, ci) in basis.iter().zip(&c) {
                for (s, x) in sim.iter_mut().zip(b) {
                    *s += ci * x;
                }
            }
            c.truncate(states);
            Ok((sim, c))
        } else {
            let state = p[k..].to_vec();
            let mut sim = self
                .model
                .simulate(&phys, &state, self.step_s, n, self.quantity)?;
            if !drift.is_empty() {
                let columns: Vec<Vec<f64>> = drift
                    .iter()
                    .map(|b| b[self.range.clone()].to_vec())
                    .collect();
                let rest: Vec<f64> = self
                    .range
                    .clone()
                    .map(|i| self.measured[i] - sim[i])
                    .collect();
                let c = lm::linear_least_squares(&columns, &rest)
                    .ok_or("the offset and drift are not identifiable from the record")?;
                for (b, ci) in drift.iter().zip(&c) {
                    for (s, x) in sim.iter_mut().zip(b) {
                        *s += ci * x;
                    }
                }
            }
            Ok((sim, state))
        }
    }

    fn static_residuals(&self, p: &[f64], out: &mut Vec<f64>) {
        if let Some(s) = self.statics {
            let phys = self.physical(&p[..self.knobs.len()]);
            let k = self.model.stiffness_n_m(&phys);
            for (x, f) in s.displacement_m.iter().zip(&s.force_n) {
                let extra: f64 = CATALOGUE
                    .iter()
                    .zip(&phys.effects)
                    .filter_map(|(e, &v)| e.static_force(v, *x))
                    .sum();
                out.push((k * x + extra - f) / s.sigma_n);
            }
        }
    }
}

impl Residuals for Problem<'_> {
    fn residuals(&self, p: &[f64]) -> Result<Vec<f64>, String> {
        // Only the fitted window is simulated: a fit on the first quarter costs a quarter.
        let (sim, _) = self.simulate(p, self.range.end)?;
        let mut r: Vec<f64> = self
            .range
            .clone()
            .map(|i| (sim[i] - self.measured[i]) / self.sigma)
            .collect();
        self.static_residuals(p, &mut r);
        Ok(r)
    }
}

/// Runs the fit of `problem`.
pub fn run(problem: &Problem<'_>, max_iterations: usize) -> Result<Fitted, String> {
    let mut start = problem.knob_start();
    let mut scale: Vec<f64> = problem
        .knobs
        .iter()
        .zip(&start)
        .map(|(k, x)| if k.signed() { x.abs().max(1e-300) } else { 1.0 })
        .collect();
    if !problem.linear() {
        let state = match &problem.initial_state {
            Some(s) => s.clone(),
            None => return Err("a nonlinear fit needs a starting initial state".into()),
        };
        for s in &state {
            scale.push(s.abs().max(1e-6));
        }
        start.extend(state);
    }
    let fit = lm::fit(
        problem,
        &start,
        &LmOptions {
            max_iterations,
            scale,
        },
    )?;
    let (simulated, initial_state) = problem.simulate(&fit.params, problem.measured.len())?;
    let k = problem.knobs.len();
    let rss = problem
        .range
        .clone()
        .map(|i| (simulated[i] - problem.measured[i]).powi(2))
        .sum();
    // Relative errors: a logarithm's standard error is one already; a signed knob's
    // is divided by its value.
    let knob_rel_errors = problem
        .knobs
        .iter()
        .zip(&fit.params)
        .zip(&fit.std_errors)
        .map(|((knob, p), se)| if knob.signed() { se / p.abs() } else { *se })
        .collect();
    Ok(Fitted {
        physical: problem.physical(&fit.params[..k]),
        n_params: k + initial_state.len() + problem.drift_columns(0).len(),
        initial_state,
        simulated,
        rss,
        knob_rel_errors,
        knobs: problem.knobs.clone(),
        iterations: fit.iterations,
        evaluations: fit.evaluations,
    })
}

/// RMS of `simulated - measured` over `range`, divided by the RMS of `measured` there
/// (the spec's `residual_rms` / `forecast_rms`).
pub fn relative_rms(simulated: &[f64], measured: &[f64], range: Range<usize>) -> f64 {
    let (mut e, mut m) = (0.0, 0.0);
    for i in range {
        e += (simulated[i] - measured[i]).powi(2);
        m += measured[i] * measured[i];
    }
    if m > 0.0 {
        (e / m).sqrt()
    } else {
        f64::NAN
    }
}
