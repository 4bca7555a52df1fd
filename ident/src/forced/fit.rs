//! Output-error fits of the lumped oscillator to forced records: the model is simulated
//! under each record's measured input from a fitted initial state, and the squared
//! difference between simulated and measured output is minimised (Levenberg-Marquardt,
//! `crate::diagnose::lm`).
//!
//! # Steps
//! 1. **Start**: an ARX(2, 3) equation-error fit of the sampled data gives the poles,
//!    hence `w0` and `zeta` (`s = ln(z) / dt`); with them fixed the linear model's output
//!    is linear in the gain, the offset and each record's initial state, solved by linear
//!    least squares on the superposed responses.
//! 2. **Linear output error**: `ln w0`, `ln zeta`, the gain, the offset and the initial
//!    states refined together.
//! 3. **An effect**: its parameter added (starting from 0, any sign: a negative friction or
//!    drag is reported as inadmissible, not clipped) and everything refitted.
//!
//! On a reduced FE spring (module `super::spring`) the three linear parameters are the
//! spring's instead: `ln s` (stiffness scale), `ln beta` and, under a force, `ln (m / m_n)`
//! (the weight's mass against the case's); the law's parameters are then the physical
//! force's (per the start's reference mass), so a change of the modal reference mass
//! during the fit does not move them.
//!
//! Parameters are scaled to order one: the effects by the displacement scale `z_s` (RMS of
//! the linear model's displacement) and `w_s` (the start's `w0`): `kappa = p w_s^2 / z_s^2`,
//! `phi = p w_s^2 z_s`, `delta = p / z_s`; the friction's regularisation velocity is
//! `v_f = 0.01 w_s z_s`.
//!
//! Sources: L. Ljung, *System Identification*, 2nd ed., Prentice Hall 1999, sections 4.2
//! (ARX) and 7.3 (output error); J. Schoukens, L. Ljung, "Nonlinear system identification:
//! a user-oriented road map", IEEE Control Systems 39 (2019) 28-99.

use super::model::{ForcedModel, InputQuantity, Lumped, OutputQuantity};
use super::simulate::{self, Grid};
use super::spring::{SpringParameters, SpringStructure};
use crate::diagnose::lm::{self, LmOptions};

/// One record's samples as the fits see them.
#[derive(Debug, Clone, Copy)]
pub struct Series<'a> {
    /// Sample interval, s.
    pub dt: f64,
    /// Input samples.
    pub input: &'a [f64],
    /// Output samples (as many as the input's).
    pub output: &'a [f64],
}

/// An effect of the catalogue.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Effect {
    /// `kappa z^3`.
    Cubic,
    /// `phi tanh(z' / v_f)`.
    Friction,
    /// `delta z' |z'|`.
    Drag,
}

impl Effect {
    /// Every effect of the lumped catalogue.
    pub const ALL: [Effect; 3] = [Effect::Friction, Effect::Drag, Effect::Cubic];

    /// The diagnosis's name.
    pub fn name(self) -> &'static str {
        match self {
            Effect::Cubic => "cubic_stiffness",
            Effect::Friction => "coulomb_friction",
            Effect::Drag => "quadratic_damping",
        }
    }

    /// The physical parameter's name (units in the name: SI when the records are in N, m).
    pub fn parameter(self) -> &'static str {
        match self {
            Effect::Cubic => "cubic_stiffness_n_m3",
            Effect::Friction => "friction_force_n",
            Effect::Drag => "quadratic_damping_n_s2_m2",
        }
    }

    /// The effect's value per unit mass in `model`.
    pub fn value(self, model: &Lumped) -> f64 {
        match self {
            Effect::Cubic => model.cubic,
            Effect::Friction => model.friction,
            Effect::Drag => model.drag,
        }
    }

    fn set(self, model: &mut Lumped, value: f64) {
        match self {
            Effect::Cubic => model.cubic = value,
            Effect::Friction => model.friction = value,
            Effect::Drag => model.drag = value,
        }
    }

    /// Factor from the scaled fit parameter to the value per unit mass.
    fn scale(self, scales: &Scales) -> f64 {
        let (w, z) = (scales.w, scales.z);
        match self {
            Effect::Cubic => w * w / (z * z),
            Effect::Friction => w * w * z,
            Effect::Drag => 1.0 / z,
        }
    }
}

/// The scales of a fit (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scales {
    /// Frequency scale w_s, rad/s.
    pub w: f64,
    /// Displacement scale z_s, output units of displacement.
    pub z: f64,
    /// Output scale (RMS of the measured output).
    pub y: f64,
    /// Gain scale.
    pub b: f64,
    /// RK4 sub-steps per sample.
    pub substeps: usize,
}

/// A finished fit.
#[derive(Debug, Clone)]
pub struct Fitted {
    /// The model.
    pub model: ForcedModel,
    /// The initial state `(z0, v0)` of each record.
    pub initial: Vec<(f64, f64)>,
    /// Sum of squared output errors.
    pub cost: f64,
    /// Number of residuals.
    pub count: usize,
    /// Each record's RMS output error, output unit.
    pub rms: Vec<f64>,
    /// Each record's residuals.
    pub residuals: Vec<Vec<f64>>,
    /// The effects fitted, with their value per unit mass and its standard error.
    pub effects: Vec<(Effect, f64, f64)>,
    /// Standard errors of `w0` (rad/s), `zeta`, `b`; of a spring's stiffness scale, beta
    /// (s) and mass (kg, 0 when held).
    pub linear_se: [f64; 3],
    /// The scales used.
    pub scales: Scales,
}

/// What the model's input and output are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setup {
    /// What drives the weight.
    pub input: InputQuantity,
    /// What the output measures.
    pub output: OutputQuantity,
    /// The nominal mass for a base input.
    pub base_mass: Option<f64>,
}

fn model_of(setup: &Setup, units: (&str, &str), oscillator: Lumped) -> ForcedModel {
    ForcedModel::new(
        setup.input,
        setup.output,
        units,
        setup.base_mass,
        oscillator,
    )
}

/// Poles of an ARX(2,3) fit of one record: `(w0, zeta)`, or `None` when they are not a
/// stable complex pair.
fn arx_poles(s: &Series<'_>) -> Option<(f64, f64)> {
    let n = s.output.len();
    if n < 16 {
        return None;
    }
    let y = s.output;
    let u = s.input;
    let rows = 2..n;
    let col = |f: &dyn Fn(usize) -> f64| rows.clone().map(f).collect::<Vec<f64>>();
    let columns = vec![
        col(&|i| y[i - 1]),
        col(&|i| y[i - 2]),
        col(&|i| u[i]),
        col(&|i| u[i - 1]),
        col(&|i| u[i - 2]),
        col(&|_| 1.0),
    ];
    let target = col(&|i| y[i]);
    let c = lm::linear_least_squares(&columns, &target)?;
    // z^2 - a1 z - a2 = 0.
    let (a1, a2) = (c[0], c[1]);
    let disc = a1 * a1 + 4.0 * a2;
    if disc >= 0.0 || -a2 <= 0.0 {
        return None;
    }
    let r = (-a2).sqrt();
    let theta = (0.5 * a1 / r).clamp(-1.0, 1.0).acos();
    let sigma = r.ln() / s.dt;
    let omega = theta / s.dt;
    let w0 = (sigma * sigma + omega * omega).sqrt();
    let zeta = -sigma / w0;
    (w0.is_finite() && zeta > 0.0 && zeta < 1.0).then_some((w0, zeta))
}

/// The displacement-like scale of the measured output for a model at `w0`.
fn displacement_scale(setup: &Setup, y_rms: f64, w0: f64) -> f64 {
    match setup.output {
        OutputQuantity::Displacement => y_rms,
        OutputQuantity::Velocity => y_rms / w0,
        OutputQuantity::Acceleration => y_rms / (w0 * w0),
    }
}

fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len().max(1) as f64).sqrt()
}

/// Runs every record with `model` from `initial`; the residuals (simulated - measured).
fn residuals_of(
    model: &ForcedModel,
    series: &[Series<'_>],
    initial: &[(f64, f64)],
    substeps: usize,
    bound: f64,
) -> Result<Vec<Vec<f64>>, String> {
    series
        .iter()
        .zip(initial)
        .map(|(s, &x0)| {
            let grid = Grid { dt: s.dt, substeps };
            let y = simulate::output(model, grid, s.input, x0, bound)?;
            Ok(y.iter().zip(s.output).map(|(a, b)| a - b).collect())
        })
        .collect()
}

/// A fit's starting point: the model, each record's initial state `(z0, v0)`, the scales.
pub type Start = (ForcedModel, Vec<(f64, f64)>, Scales);

/// The linear start (module docs, step 1).
pub fn linear_start(
    series: &[Series<'_>],
    setup: &Setup,
    units: (&str, &str),
) -> Result<Start, String> {
    let longest = series
        .iter()
        .max_by_key(|s| s.output.len())
        .ok_or("no forced record")?;
    let dt = longest.dt;
    // Without a clear complex pole pair, a resonance at a tenth of the sampling rate.
    let (w0, zeta) = arx_poles(longest).unwrap_or((std::f64::consts::TAU * 0.1 / dt, 0.05));
    let y_all: Vec<f64> = series
        .iter()
        .flat_map(|s| s.output.iter().copied())
        .collect();
    let y_rms = rms(&y_all).max(1e-300);
    let z_s = displacement_scale(setup, y_rms, w0);
    let bound = simulate::bound_for(1e3 * z_s);
    let unit = model_of(setup, units, Lumped::linear(w0, zeta, 1.0));
    let substeps = simulate::substeps(&unit.oscillator, dt, z_s, w0 * z_s);
    // Superposition: the unit-gain response, the two free responses and the offset.
    let mut columns: Vec<Vec<f64>> = Vec::new();
    let total: usize = series.iter().map(|s| s.output.len()).sum();
    let mut gain_column = Vec::with_capacity(total);
    let mut offset_column = Vec::with_capacity(total);
    let free = |s: &Series<'_>, x0: (f64, f64)| {
        let zero = vec![0.0; s.input.len()];
        simulate::output(&unit, Grid { dt: s.dt, substeps }, &zero, x0, bound)
    };
    let mut state_columns = Vec::new();
    let mut start = 0;
    for s in series {
        let grid = Grid { dt: s.dt, substeps };
        gain_column.extend(simulate::output(&unit, grid, s.input, (0.0, 0.0), bound)?);
        offset_column.extend(std::iter::repeat_n(1.0, s.output.len()));
        for x0 in [(z_s, 0.0), (0.0, w0 * z_s)] {
            let mut c = vec![0.0; total];
            c[start..start + s.output.len()].copy_from_slice(&free(s, x0)?);
            state_columns.push(c);
        }
        start += s.output.len();
    }
    columns.push(gain_column);
    columns.push(offset_column);
    columns.extend(state_columns);
    let c = lm::linear_least_squares(&columns, &y_all)
        .ok_or("the linear model's start cannot be solved (an input that never moves?)")?;
    let mut oscillator = Lumped::linear(w0, zeta, c[0]);
    oscillator.output_offset = c[1];
    oscillator.friction_velocity = 0.01 * w0 * z_s;
    let initial = (0..series.len())
        .map(|k| (c[2 + 2 * k] * z_s, c[3 + 2 * k] * w0 * z_s))
        .collect();
    let scales = Scales {
        w: w0,
        z: z_s,
        y: y_rms,
        b: c[0].abs().max(1e-300),
        substeps,
    };
    Ok((model_of(setup, units, oscillator), initial, scales))
}

/// The structural parameters of `start` as the fit's first entries (module docs).
fn structural(start: &ForcedModel, spring: Option<&SpringStructure>, scales: &Scales) -> Vec<f64> {
    let o = &start.oscillator;
    match (spring, &start.spring) {
        (Some(s), Some(f)) => {
            let mut p = vec![
                (f.youngs_modulus_mpa / s.youngs_modulus_mpa).ln(),
                f.rayleigh_beta_s.max(1e-12).ln(),
            ];
            if s.input == InputQuantity::Force {
                p.push((f.mass_kg / s.nominal_mass_kg).ln());
            }
            p
        }
        _ => vec![
            o.natural_frequency_rad_s.ln(),
            o.damping_ratio.max(1e-6).ln(),
            o.input_gain / scales.b,
        ],
    }
}

/// A spring model at the parameters `p` (the structural ones first): the oscillator with
/// its modes and the reference mass, the model's figures set.
pub fn spring_model(
    spring: &SpringStructure,
    template: &ForcedModel,
    p: &[f64],
) -> Result<ForcedModel, String> {
    let params = SpringParameters {
        k_scale: p[0].exp(),
        beta_s: p[1].exp(),
        mass_kg: if spring.input == InputQuantity::Force {
            p[2].exp() * spring.nominal_mass_kg
        } else {
            spring.nominal_mass_kg
        },
    };
    let (mut osc, m_ref) = spring.modal(&params)?;
    let o = &template.oscillator;
    osc.output_offset = o.output_offset;
    osc.friction_velocity = o.friction_velocity;
    osc.cubic = o.cubic;
    osc.friction = o.friction;
    osc.drag = o.drag;
    let mut model = template.clone();
    model.kind = super::model::SPRING_KIND.into();
    model.oscillator = osc;
    model.mass = m_ref;
    model.spring = Some(spring.figures(&params));
    Ok(model)
}

/// Fits the model with `effects` by output error from `start` (module docs, steps 2-3);
/// `spring` the case's reduced FE spring when `start` is one.
#[allow(clippy::too_many_arguments)]
pub fn fit(
    series: &[Series<'_>],
    start: &ForcedModel,
    initial: &[(f64, f64)],
    scales: &Scales,
    effects: &[Effect],
    max_iterations: usize,
    spring: Option<&SpringStructure>,
) -> Result<Fitted, String> {
    let setup = Setup {
        input: start.input_quantity,
        output: start.output_quantity,
        base_mass: Some(start.mass),
    };
    let spring = spring.filter(|_| start.is_spring());
    let units = (start.input_unit.as_str(), start.output_unit.as_str());
    let o = &start.oscillator;
    let z_s = scales.z;
    let v_s = scales.w * z_s;
    let bound = simulate::bound_for(1e3 * z_s);
    let ne = effects.len();
    let mut p0 = structural(start, spring, scales);
    let ns = p0.len();
    p0.push(o.output_offset / scales.y);
    // The law per unit reference mass of the start (module docs).
    let m_ref0 = start.mass;
    for e in effects {
        p0.push(e.value(o) / e.scale(scales));
    }
    for &(z0, v0) in initial {
        p0.push(z0 / z_s);
        p0.push(v0 / v_s);
    }
    let unpack = |p: &[f64]| -> Result<(ForcedModel, Vec<(f64, f64)>), String> {
        let mut model = match spring {
            Some(s) => spring_model(s, start, p)?,
            None => {
                let mut m = o.clone();
                m.natural_frequency_rad_s = p[0].exp();
                m.damping_ratio = p[1].exp();
                m.input_gain = p[2] * scales.b;
                model_of(&setup, units, m)
            }
        };
        let per_mass = if spring.is_some() {
            m_ref0 / model.mass
        } else {
            1.0
        };
        let m = &mut model.oscillator;
        m.output_offset = p[ns] * scales.y;
        m.cubic = 0.0;
        m.friction = 0.0;
        m.drag = 0.0;
        for (j, e) in effects.iter().enumerate() {
            e.set(m, p[ns + 1 + j] * e.scale(scales) * per_mass);
        }
        let init = (0..series.len())
            .map(|k| (p[ns + 1 + ne + 2 * k] * z_s, p[ns + 2 + ne + 2 * k] * v_s))
            .collect();
        Ok((model, init))
    };
    let residuals = |p: &[f64]| -> Result<Vec<f64>, String> {
        let (m, init) = unpack(p)?;
        Ok(residuals_of(&m, series, &init, scales.substeps, bound)?.concat())
    };
    let options = LmOptions {
        max_iterations,
        scale: vec![1.0; p0.len()],
    };
    let out = lm::fit(&residuals, &p0, &options)?;
    let (model, init) = unpack(&out.params)?;
    let per_record = residuals_of(&model, series, &init, scales.substeps, bound)?;
    let se = &out.std_errors;
    let per_mass = if spring.is_some() {
        m_ref0 / model.mass
    } else {
        1.0
    };
    let linear_se = match (spring, &model.spring) {
        (Some(_), Some(f)) => [
            se[0] * out.params[0].exp(),
            se[1] * f.rayleigh_beta_s,
            if ns == 3 { se[2] * f.mass_kg } else { 0.0 },
        ],
        _ => [
            se[0] * model.oscillator.natural_frequency_rad_s,
            se[1] * model.oscillator.damping_ratio,
            se[2] * scales.b,
        ],
    };
    Ok(Fitted {
        effects: effects
            .iter()
            .enumerate()
            .map(|(j, e)| {
                (
                    *e,
                    e.value(&model.oscillator),
                    se[ns + 1 + j] * e.scale(scales) * per_mass,
                )
            })
            .collect(),
        linear_se,
        rms: per_record.iter().map(|r| rms(r)).collect(),
        count: out.residuals.len(),
        cost: out.cost,
        residuals: per_record,
        model,
        initial: init,
        scales: *scales,
    })
}

/// The forecast test's error: the RMS of the forecast errors relative to the RMS of the
/// measured output over the forecast windows.
///
/// With two records or more, each record is forecast whole by the model fitted on the
/// others (from `fitted`'s parameters; the held-out record starts from `fitted`'s state
/// for it, two numbers that only set its opening transient). With one record, fits on
/// its first quarter, half and three quarters are each simulated through the next
/// quarter. Why records first: a record's later quarters may hold what its head never
/// reached (a sweep's resonance, and its fold's jump, whose place a law fitted on the
/// small amplitudes before it cannot know), so a head fit forecasts them no better than
/// the linear model even when the law is right; another record driven over the same band
/// asks the law to reproduce a different excitation, which is what a physical model
/// must do.
pub fn forecast(
    series: &[Series<'_>],
    fitted: &Fitted,
    effects: &[Effect],
    max_iterations: usize,
    spring: Option<&SpringStructure>,
) -> Result<f64, String> {
    let bound = simulate::bound_for(1e3 * fitted.scales.z);
    let (mut err2, mut ref2) = (0.0, 0.0);
    let mut add = |model: &ForcedModel, s: &Series<'_>, x0, a: usize, b: usize| {
        let grid = Grid {
            dt: s.dt,
            substeps: fitted.scales.substeps,
        };
        let y = simulate::output(model, grid, &s.input[..b], x0, bound)?;
        for (yi, mi) in y[a..b].iter().zip(&s.output[a..b]) {
            err2 += (yi - mi).powi(2);
            ref2 += mi.powi(2);
        }
        Ok::<(), String>(())
    };
    if series.len() >= 2 {
        for held in 0..series.len() {
            let others: Vec<usize> = (0..series.len()).filter(|&i| i != held).collect();
            let rest: Vec<Series<'_>> = others.iter().map(|&i| series[i]).collect();
            let initial: Vec<(f64, f64)> = others.iter().map(|&i| fitted.initial[i]).collect();
            let rest_fit = fit(
                &rest,
                &fitted.model,
                &initial,
                &fitted.scales,
                effects,
                max_iterations,
                spring,
            )?;
            let s = &series[held];
            add(&rest_fit.model, s, fitted.initial[held], 0, s.output.len())?;
        }
    } else {
        for k in 1..=3 {
            let heads: Vec<Series<'_>> = series
                .iter()
                .map(|s| {
                    let n = s.output.len() * k / 4;
                    Series {
                        dt: s.dt,
                        input: &s.input[..n],
                        output: &s.output[..n],
                    }
                })
                .collect();
            let head_fit = fit(
                &heads,
                &fitted.model,
                &fitted.initial,
                &fitted.scales,
                effects,
                max_iterations,
                spring,
            )?;
            for (s, &x0) in series.iter().zip(&head_fit.initial) {
                let (a, b) = (s.output.len() * k / 4, s.output.len() * (k + 1) / 4);
                add(&head_fit.model, s, x0, a, b)?;
            }
        }
    }
    Ok((err2 / ref2.max(1e-300)).sqrt())
}
