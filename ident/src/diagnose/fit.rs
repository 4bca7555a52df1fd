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
//! projected out of the residual of a nonlinear one), so they cost no search. A record
//! holding a slow line (another mode of the rig, `data::slow_line`) has its damped
//! cosine and sine fitted the same way. The fit
//! compares the measured quantity itself (a displacement with a displacement): no
//! record is differentiated for the fit.
//!
//! Each effect is a knob: a positive one is fitted as its logarithm, one that takes
//! either sign (the cubic spring) as itself.
//!
//! Residuals are `simulated - measured` (the record's quantity, SI) on the fitted samples,
//! optionally followed by a static block (see [`StaticBlock`]), each block divided by
//! its noise level so that they weigh by their information.

use super::data::SlowLine;
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
    /// The spring's stiffness, as a factor on the calibrated one (`Physical::k_scale`):
    /// fitted when records at two or more masses separate it from the mass (one
    /// frequency fixes only their ratio).
    Stiffness,
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
    /// Measured compressions from the free length (m).
    pub displacement_m: Vec<f64>,
    /// Measured axial forces (N).
    pub force_n: Vec<f64>,
    /// The measured force's noise level (N).
    pub sigma_n: f64,
}

/// One decay record in the fit's layout: the records of a case are laid end to end in
/// one vector, each with its own initial state and (for displacement and velocity) its
/// own offset and drift, while the mass, the spring and the effects are shared (a joint
/// fit: one mass, one spring).
#[derive(Debug, Clone)]
pub struct Segment {
    /// This record's samples in the concatenated vector.
    pub span: Range<usize>,
    /// Its sampling step (s).
    pub step_s: f64,
    /// The quantity it records.
    pub quantity: Quantity,
    /// Its attached mass minus the case's `mass_kg` (kg): a record taken with another
    /// weight on the same spring (the fitted mass absorbs what the weights share, the
    /// spring's effective mass among it).
    pub mass_delta_kg: f64,
    /// The factor its samples (and its simulation) carry in the concatenated vector: the
    /// first record's noise floor over this one's, so that records of different
    /// quantities or sensors weigh by their information.
    pub weight: f64,
    /// A slow line in this record (another mode of the rig, `data::slow_line`): its
    /// angular frequency (rad/s) and decay rate (1/s); its form is fitted beside the
    /// model as the offset and drift are.
    pub slow_line: Option<(f64, f64)>,
}

impl Segment {
    /// A single record of `n` samples.
    pub fn single(n: usize, step_s: f64, quantity: Quantity) -> Self {
        Segment {
            span: 0..n,
            step_s,
            quantity,
            mass_delta_kg: 0.0,
            weight: 1.0,
            slow_line: None,
        }
    }

    /// A displacement or velocity record carries the sensor's offset and drift.
    fn drift(&self) -> bool {
        self.quantity != Quantity::Acceleration
    }

    /// The first `fraction` of this record (at least one sample).
    pub fn window(&self, fraction: f64) -> Range<usize> {
        let len = self.span.len();
        let m = ((fraction * len as f64) as usize).clamp(1, len.max(1));
        self.span.start..self.span.start + m
    }

    /// The samples of this record from `from` up to `to` (fractions of its length).
    pub fn between(&self, from: f64, to: f64) -> Range<usize> {
        let len = self.span.len() as f64;
        let a = self.span.start + ((from * len) as usize).min(self.span.len());
        let b = self.span.start + ((to * len) as usize).min(self.span.len());
        a..b.max(a)
    }
}

/// What to fit and on which samples.
pub struct Problem<'a> {
    /// The reduced spring simulated.
    pub model: &'a ReducedSpring,
    /// Starting parameters; those no knob moves stay as they are.
    pub start: Physical,
    /// The parameters the fit moves.
    pub knobs: Vec<Knob>,
    /// The records laid end to end, each scaled by its segment's weight.
    pub measured: &'a [f64],
    /// The records' layout in `measured`.
    pub segments: &'a [Segment],
    /// The fitted window: the first `fraction` of every record.
    pub fraction: f64,
    /// Noise level of the decay samples (the records' unit, SI), dividing their residuals.
    pub sigma: f64,
    /// A static block fitted beside the decay, for effects that show in the static record.
    pub statics: Option<&'a StaticBlock>,
    /// Initial state to start a nonlinear fit from (model units), every record's in turn.
    pub initial_state: Option<Vec<f64>>,
}

/// A finished fit.
#[derive(Debug, Clone)]
pub struct Fitted {
    /// The fitted parameters (SI).
    pub physical: Physical,
    /// Every record's fitted initial state, in turn.
    pub initial_state: Vec<f64>,
    /// The simulated records over all their samples, laid out as the measured ones.
    pub simulated: Vec<f64>,
    /// Sum of squared (unscaled) decay residuals over the fitted windows.
    pub rss: f64,
    /// Fitted parameters: knobs, the initial states' components, offsets and drifts.
    pub n_params: usize,
    /// Relative standard errors of the knobs (indicative; see `lm`).
    pub knob_rel_errors: Vec<f64>,
    /// The knobs fitted.
    pub knobs: Vec<Knob>,
    /// Levenberg-Marquardt iterations spent.
    pub iterations: usize,
    /// Model runs spent.
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
                Knob::Stiffness => phys.k_scale = x,
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
                    Knob::Stiffness => self.start.k_scale,
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

    /// The columns fitted beside the model over the first `n` samples of `segment`:
    /// the offset and drift (1 and the time over the record's length; none for an
    /// acceleration record), and a slow line's damped cosine and sine.
    fn drift_columns(segment: &Segment, n: usize) -> Vec<Vec<f64>> {
        let mut columns = Vec::new();
        if segment.drift() {
            let len = segment.span.len().max(1) as f64;
            columns.push(vec![1.0; n]);
            columns.push((0..n).map(|i| i as f64 / len).collect());
        }
        if let Some((omega, sigma)) = segment.slow_line {
            columns.extend(SlowLine::columns(omega, sigma, segment.step_s, n));
        }
        columns
    }

    fn linear(&self) -> bool {
        !self.model.is_nonlinear(&self.start)
    }

    /// The fitted windows, one per record.
    fn windows(&self) -> Vec<Range<usize>> {
        self.segments
            .iter()
            .map(|s| s.window(self.fraction))
            .collect()
    }

    /// The simulated records for knob values `p` (and, for a nonlinear model, every
    /// record's initial state after them), each over its samples up to its window's end
    /// (`whole`: over all its samples), and every record's initial state.
    fn simulate(&self, p: &[f64], whole: bool) -> Result<(Vec<f64>, Vec<f64>), String> {
        if coil_io::cancel::requested() {
            return Err(coil_io::cancel::INTERRUPTED.into());
        }
        let k = self.knobs.len();
        let phys = self.physical(&p[..k]);
        let mut sim = vec![0.0; self.measured.len()];
        let mut states_out = Vec::new();
        let per_record = p.len().saturating_sub(k) / self.segments.len().max(1);
        for (r, seg) in self.segments.iter().enumerate() {
            let window = seg.window(self.fraction);
            let local = (window.start - seg.span.start)..(window.end - seg.span.start);
            let n = if whole { seg.span.len() } else { local.end };
            let mut phys_r = phys;
            phys_r.mass_kg += seg.mass_delta_kg;
            let measured = &self.measured[seg.span.clone()];
            let out = &mut sim[seg.span.start..seg.span.start + n];
            let drift = Self::drift_columns(seg, n);
            if self.linear() {
                let mut basis = self.model.basis(&phys_r, seg.step_s, n, seg.quantity)?;
                let states = basis.len();
                for b in &mut basis {
                    b.iter_mut().for_each(|x| *x *= seg.weight);
                }
                basis.extend(drift);
                let columns: Vec<Vec<f64>> =
                    basis.iter().map(|b| b[local.clone()].to_vec()).collect();
                let mut c = lm::linear_least_squares(&columns, &measured[local.clone()])
                    .ok_or("the initial state is not identifiable from the record")?;
                for (b, ci) in basis.iter().zip(&c) {
                    for (s, x) in out.iter_mut().zip(b) {
                        *s += ci * x;
                    }
                }
                c.truncate(states);
                states_out.extend(c);
            } else {
                let state = &p[k + r * per_record..k + (r + 1) * per_record];
                let simulated = self
                    .model
                    .simulate(&phys_r, state, seg.step_s, n, seg.quantity)?;
                for (s, x) in out.iter_mut().zip(simulated) {
                    *s = seg.weight * x;
                }
                if !drift.is_empty() {
                    let columns: Vec<Vec<f64>> =
                        drift.iter().map(|b| b[local.clone()].to_vec()).collect();
                    let rest: Vec<f64> = local.clone().map(|i| measured[i] - out[i]).collect();
                    let c = lm::linear_least_squares(&columns, &rest).ok_or(
                        "the offset, drift and slow line are not identifiable from the record",
                    )?;
                    for (b, ci) in drift.iter().zip(&c) {
                        for (s, x) in out.iter_mut().zip(b) {
                            *s += ci * x;
                        }
                    }
                }
                states_out.extend_from_slice(state);
            }
        }
        Ok((sim, states_out))
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
        // Only the fitted windows are simulated: a fit on the first quarter costs a quarter.
        let (sim, _) = self.simulate(p, false)?;
        let mut r: Vec<f64> = self
            .windows()
            .into_iter()
            .flatten()
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
    let (simulated, initial_state) = problem.simulate(&fit.params, true)?;
    let k = problem.knobs.len();
    let rss = problem
        .windows()
        .into_iter()
        .flatten()
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
        n_params: k
            + initial_state.len()
            + problem
                .segments
                .iter()
                .map(|s| Problem::drift_columns(s, 0).len())
                .sum::<usize>(),
        initial_state,
        simulated,
        rss,
        knob_rel_errors,
        knobs: problem.knobs.clone(),
        iterations: fit.iterations,
        evaluations: fit.evaluations,
    })
}

/// RMS of `simulated - measured` over `ranges`, divided by the RMS of `measured` there
/// (the spec's `residual_rms` / `forecast_rms`).
pub fn relative_rms(simulated: &[f64], measured: &[f64], ranges: &[Range<usize>]) -> f64 {
    let (mut e, mut m) = (0.0, 0.0);
    for i in ranges.iter().cloned().flatten() {
        e += (simulated[i] - measured[i]).powi(2);
        m += measured[i] * measured[i];
    }
    if m > 0.0 {
        (e / m).sqrt()
    } else {
        f64::NAN
    }
}
