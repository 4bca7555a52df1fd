//! The lumped oscillator driven by a sampled input: classical Runge-Kutta (RK4) on the
//! state `(z, z')`, the input joined linearly between its samples (first-order hold: a
//! record's input is its samples and the straight lines between them), each sample
//! interval cut into equal sub-steps.
//!
//! # Step size
//! RK4's phase error per step is about `(w h)^5 / 120` for an oscillation at `w`; with
//! `w h <= 0.25` (the stiffest local frequency, the cubic's at the largest displacement)
//! that is 3e-5 of a period per period, and a response that remembers `1 / (zeta w)`
//! (its damping's time) is off by at most `(w h)^4 / (120 zeta)`: 1.6e-3 at 2 % damping,
//! below the noise of the records at hand.
//! The damping terms (the drag's and the regularised friction's slopes) are kept under
//! `h c <= 0.5`, inside RK4's real stability interval (2.78). [`substeps`] returns the count.
//!
//! A reduced FE spring (model docs, "modal form") runs the same rule on every mode's
//! `(q_i, q_i')`, the step set by its stiffest mode (`w_i h <= 0.25`) and largest damping
//! slope.
//!
//! A state that leaves every finite bound (a model that diverges under the input) is an
//! error, not a number.
//!
//! Source: E. Hairer, S. P. Norsett, G. Wanner, *Solving Ordinary Differential Equations
//! I*, 2nd ed., Springer 1993, section II.1 (RK4) and IV.2 (stability).

use super::model::{ForcedModel, Lumped};

/// The sampling of a record: its step and the sub-steps per step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// Sample interval, s.
    pub dt: f64,
    /// RK4 sub-steps per sample interval.
    pub substeps: usize,
}

/// Sub-steps per sample interval for `model` at displacements up to `z_max` and velocities
/// up to `v_max` (module docs, "Step size").
pub fn substeps(model: &Lumped, dt: f64, z_max: f64, v_max: f64) -> usize {
    let w = model.natural_frequency_rad_s;
    let share = model
        .modes
        .iter()
        .map(|m| m.law_gain.abs())
        .fold(1.0f64, f64::max);
    let mut stiff = (w * w + 3.0 * share * model.cubic.abs() * z_max * z_max).sqrt();
    let (_, dv_max) = model.restoring_slopes(0.0, v_max);
    let (_, dv_0) = model.restoring_slopes(0.0, 0.0);
    let mut damp = 2.0 * model.damping_ratio * w + share * dv_max.max(dv_0);
    for m in &model.modes {
        stiff = stiff.max(m.natural_frequency_rad_s);
        damp =
            damp.max(2.0 * m.damping_ratio * m.natural_frequency_rad_s + share * dv_max.max(dv_0));
    }
    let n = (stiff * dt / 0.25).max(damp * dt / 0.5).ceil();
    if n.is_finite() {
        (n as usize).clamp(1, 4096)
    } else {
        4096
    }
}

/// The weight's motion at every sample: displacement, velocity and acceleration.
#[derive(Debug, Clone, Default)]
pub struct Motion {
    /// Displacement `z`.
    pub z: Vec<f64>,
    /// Velocity `z'`.
    pub v: Vec<f64>,
    /// Acceleration `z''`.
    pub a: Vec<f64>,
}

/// The state `(z, z')` after each sample, from `(z0, v0)` at the first.
/// Returns the displacement and velocity at every sample.
pub fn states(
    model: &Lumped,
    grid: Grid,
    input: &[f64],
    initial: (f64, f64),
    bound: f64,
) -> Result<(Vec<f64>, Vec<f64>), String> {
    let m = motion(model, grid, input, initial, bound)?;
    Ok((m.z, m.v))
}

/// The weight's motion under `input` from `(z0, v0)` at the first sample (a reduced FE
/// spring's first mode carries that state, its other modes start at rest).
pub fn motion(
    model: &Lumped,
    grid: Grid,
    input: &[f64],
    initial: (f64, f64),
    bound: f64,
) -> Result<Motion, String> {
    if !model.modes.is_empty() {
        return modal_motion(model, grid, input, initial, bound);
    }
    let (zs, vs) = single_mode(model, grid, input, initial, bound)?;
    let a = zs
        .iter()
        .zip(&vs)
        .zip(input)
        .map(|((&z, &v), &u)| model.acceleration(z, v, u))
        .collect();
    Ok(Motion { z: zs, v: vs, a })
}

fn single_mode(
    model: &Lumped,
    grid: Grid,
    input: &[f64],
    initial: (f64, f64),
    bound: f64,
) -> Result<(Vec<f64>, Vec<f64>), String> {
    let n = input.len();
    let mut zs = Vec::with_capacity(n);
    let mut vs = Vec::with_capacity(n);
    let (mut z, mut v) = initial;
    let h = grid.dt / grid.substeps as f64;
    let f = |z: f64, v: f64, u: f64| model.acceleration(z, v, u);
    if n == 0 {
        return Ok((zs, vs));
    }
    zs.push(z);
    vs.push(v);
    for (i, pair) in input.windows(2).enumerate() {
        let (u0, u1) = (pair[0], pair[1]);
        let du = (u1 - u0) / grid.substeps as f64;
        for s in 0..grid.substeps {
            let ua = u0 + du * s as f64;
            let um = ua + 0.5 * du;
            let ub = ua + du;
            let k1z = v;
            let k1v = f(z, v, ua);
            let k2z = v + 0.5 * h * k1v;
            let k2v = f(z + 0.5 * h * k1z, k2z, um);
            let k3z = v + 0.5 * h * k2v;
            let k3v = f(z + 0.5 * h * k2z, k3z, um);
            let k4z = v + h * k3v;
            let k4v = f(z + h * k3z, k4z, ub);
            z += h / 6.0 * (k1z + 2.0 * k2z + 2.0 * k3z + k4z);
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        }
        if !(z.abs() <= bound && v.is_finite()) {
            return Err(format!(
                "the model diverges under the input (displacement {z:.3e} at sample {}, beyond \
                 {bound:.3e})",
                i + 2
            ));
        }
        zs.push(z);
        vs.push(v);
    }
    Ok((zs, vs))
}

/// The modes of a reduced FE spring as arrays: `(w^2, 2 zeta w, b, a)` per mode, the
/// oscillator first.
fn mode_arrays(model: &Lumped) -> [Vec<f64>; 4] {
    let w = model.natural_frequency_rad_s;
    let mut k = vec![w * w];
    let mut c = vec![2.0 * model.damping_ratio * w];
    let mut b = vec![model.input_gain];
    let mut a = vec![1.0];
    for m in &model.modes {
        let wi = m.natural_frequency_rad_s;
        k.push(wi * wi);
        c.push(2.0 * m.damping_ratio * wi);
        b.push(m.input_gain);
        a.push(m.law_gain);
    }
    [k, c, b, a]
}

/// The accelerations of every mode at state `(q, p)` under input `u`.
fn modal_rates(
    arrays: &[Vec<f64>; 4],
    law: &Lumped,
    q: &[f64],
    p: &[f64],
    u: f64,
    out: &mut [f64],
) {
    let [k, c, b, a] = arrays;
    let z: f64 = q.iter().sum();
    let v: f64 = p.iter().sum();
    let g = law.restoring(z, v);
    for i in 0..q.len() {
        out[i] = b[i] * u - a[i] * g - c[i] * p[i] - k[i] * q[i];
    }
}

/// [`motion`] of a reduced FE spring: RK4 on every mode (module docs).
fn modal_motion(
    model: &Lumped,
    grid: Grid,
    input: &[f64],
    initial: (f64, f64),
    bound: f64,
) -> Result<Motion, String> {
    let arrays = mode_arrays(model);
    let dim = arrays[0].len();
    let n = input.len();
    let mut out = Motion::default();
    if n == 0 {
        return Ok(out);
    }
    let mut q = vec![0.0; dim];
    let mut p = vec![0.0; dim];
    q[0] = initial.0;
    p[0] = initial.1;
    let h = grid.dt / grid.substeps as f64;
    let mut acc = vec![0.0; dim];
    let (mut k1, mut k2, mut k3, mut k4) = (
        vec![0.0; dim],
        vec![0.0; dim],
        vec![0.0; dim],
        vec![0.0; dim],
    );
    let (mut qt, mut pt) = (vec![0.0; dim], vec![0.0; dim]);
    let record = |q: &[f64], p: &[f64], u: f64, acc: &mut [f64], out: &mut Motion| {
        modal_rates(&arrays, model, q, p, u, acc);
        out.z.push(q.iter().sum());
        out.v.push(p.iter().sum());
        out.a.push(acc.iter().sum());
    };
    record(&q, &p, input[0], &mut acc, &mut out);
    for (i, pair) in input.windows(2).enumerate() {
        let (u0, u1) = (pair[0], pair[1]);
        let du = (u1 - u0) / grid.substeps as f64;
        for s in 0..grid.substeps {
            let ua = u0 + du * s as f64;
            let um = ua + 0.5 * du;
            let ub = ua + du;
            // k_j holds the accelerations; the displacement rates are the velocities.
            modal_rates(&arrays, model, &q, &p, ua, &mut k1);
            for j in 0..dim {
                qt[j] = q[j] + 0.5 * h * p[j];
                pt[j] = p[j] + 0.5 * h * k1[j];
            }
            modal_rates(&arrays, model, &qt, &pt, um, &mut k2);
            let p2 = pt.clone();
            for j in 0..dim {
                qt[j] = q[j] + 0.5 * h * p2[j];
                pt[j] = p[j] + 0.5 * h * k2[j];
            }
            modal_rates(&arrays, model, &qt, &pt, um, &mut k3);
            let p3 = pt.clone();
            for j in 0..dim {
                qt[j] = q[j] + h * p3[j];
                pt[j] = p[j] + h * k3[j];
            }
            modal_rates(&arrays, model, &qt, &pt, ub, &mut k4);
            for j in 0..dim {
                q[j] += h / 6.0 * (p[j] + 2.0 * p2[j] + 2.0 * p3[j] + pt[j]);
                p[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
            }
        }
        let z: f64 = q.iter().sum();
        if !(z.abs() <= bound && p.iter().all(|v| v.is_finite())) {
            return Err(format!(
                "the model diverges under the input (displacement {z:.3e} at sample {}, beyond \
                 {bound:.3e})",
                i + 2
            ));
        }
        record(&q, &p, u1, &mut acc, &mut out);
    }
    Ok(out)
}

/// The model's output at every input sample from the initial state `(z0, v0)`.
pub fn output(
    model: &ForcedModel,
    grid: Grid,
    input: &[f64],
    initial: (f64, f64),
    bound: f64,
) -> Result<Vec<f64>, String> {
    let m = motion(&model.oscillator, grid, input, initial, bound)?;
    Ok((0..input.len())
        .map(|i| model.output(m.z[i], m.v[i], m.a[i], input[i]))
        .collect())
}

/// The initial state `(z0, v0)` whose simulation best fits the first `head.len()` output
/// samples (least squares by Levenberg-Marquardt; exact in two steps for a linear model).
pub fn fit_initial_state(
    model: &ForcedModel,
    grid: Grid,
    input: &[f64],
    head: &[f64],
    bound: f64,
) -> Result<(f64, f64), String> {
    let n = head.len();
    if n < 2 {
        return Err("at least 2 output samples are needed to fit the initial state".into());
    }
    let input = &input[..n];
    let w = model.oscillator.natural_frequency_rad_s;
    let z_scale = head
        .iter()
        .map(|y| (y - model.oscillator.output_offset).abs())
        .fold(0.0, f64::max)
        .max(1e-300);
    let (z_scale, v_scale) = match model.output_quantity {
        super::model::OutputQuantity::Displacement => (z_scale, z_scale * w),
        super::model::OutputQuantity::Velocity => (z_scale / w, z_scale),
        super::model::OutputQuantity::Acceleration => (z_scale / (w * w), z_scale / w),
    };
    let residuals = |p: &[f64]| -> Result<Vec<f64>, String> {
        let y = output(model, grid, input, (p[0] * z_scale, p[1] * v_scale), bound)?;
        Ok(y.iter().zip(head).map(|(a, b)| a - b).collect())
    };
    let options = crate::diagnose::lm::LmOptions {
        max_iterations: 50,
        scale: vec![1.0, 1.0],
    };
    let fit = crate::diagnose::lm::fit(&residuals, &[0.0, 0.0], &options)?;
    Ok((fit.params[0] * z_scale, fit.params[1] * v_scale))
}

/// The bound a state must stay within: a thousand times the largest measured output in
/// displacement terms (a model that runs away from the record by that much has diverged).
pub fn bound_for(z_max: f64) -> f64 {
    1e3 * z_max.max(1e-300)
}
