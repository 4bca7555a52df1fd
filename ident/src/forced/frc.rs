//! Forced response curves: the harmonic balance ([`super::hb`]) continued in frequency by
//! pseudo-arclength through the folds, each point's stability from its Floquet
//! multipliers, and the backbone of the conservative part.
//!
//! # Continuation
//! Unknowns `X = (x / z_r, W / w0)`, `z_r` the linear peak amplitude `|F| / (w0^2 max(2 zeta,
//! 0.01))`. From a Newton solution at the first frequency, each step predicts along the unit
//! tangent `t` (the null vector of `[R_x R_W]`, oriented as the previous one) and corrects by
//! Newton on `R(X) = 0`, `t . (X - X_pred) = 0`. The step halves when Newton needs more than
//! 8 iterations and grows by 1.3 after a fast convergence, up to `1.5 / points` of the
//! frequency span (so about `points` points cover the span, more around the resonance).
//!
//! # Stability (Floquet)
//! The variational equation `d'' + (2 zeta w0 + g_v(t)) d' + (w0^2 + g_z(t)) d = 0` along the
//! harmonic-balance orbit is integrated over one period (RK4, 256 steps, more when
//! `g_v h` is large) from the identity; the solution is stable when both eigenvalues of the
//! 2 x 2 monodromy matrix lie inside the unit circle. On the Duffing oscillator a
//! multiplier crosses +1 at each fold, so the unstable middle branch is marked between them.
//!
//! # Backbone
//! The free undamped periodic solutions of `z'' + w0^2 z + kappa z^3 = 0` (friction and drag
//! left out: they dissipate): for each first-harmonic amplitude `a_1` (with `b_1 = 0` fixing
//! the phase) the frequency and the other harmonics by Newton, continued from the linear
//! frequency. For the Duffing oscillator the exact period for a peak displacement `a` is
//! `4 K(m) / sqrt(w0^2 + kappa a^2)`, `m = kappa a^2 / (2 (w0^2 + kappa a^2))` (Jacobi's
//! elliptic solution; A. H. Nayfeh, D. T. Mook, *Nonlinear Oscillations*, Wiley 1979,
//! section 2.3), against which the tests check it.
//!
//! Sources: E. L. Allgower, K. Georg, *Introduction to Numerical Continuation Methods*,
//! SIAM 2003, chapter 2; T. Detroux et al., "The harmonic balance method for bifurcation
//! analysis of large-scale nonlinear mechanical systems", CMAME 296 (2015) 18-38.

// Harmonic and sample indices are the formulation's own (x_n, tau_j, line k): the kernels
// keep them rather than zipping five slices.
#![allow(clippy::needless_range_loop)]

use super::hb::{self, Basis};
use super::model::{ForcedModel, InputQuantity, Lumped, OutputQuantity};
use nalgebra::{DMatrix, DVector};

/// A point of a forced response curve.
#[derive(Debug, Clone, PartialEq)]
pub struct FrcPoint {
    /// Excitation frequency, Hz.
    pub frequency_hz: f64,
    /// Amplitude of the first harmonic of the output, the output's unit.
    pub amplitude: f64,
    /// Stable by Floquet.
    pub stable: bool,
    /// The largest Floquet multiplier's modulus.
    pub multiplier: f64,
    /// The harmonic coefficients of the displacement.
    pub coefficients: Vec<f64>,
}

/// A point of the backbone.
#[derive(Debug, Clone, PartialEq)]
pub struct BackbonePoint {
    /// Free oscillation frequency, Hz.
    pub frequency_hz: f64,
    /// Amplitude of the first harmonic of the output, the output's unit.
    pub amplitude: f64,
    /// Peak displacement `z(0)` (the largest), displacement unit.
    pub peak_displacement: f64,
}

/// Settings of a forced response curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrcSettings {
    /// Input amplitude, the input's unit.
    pub amplitude: f64,
    /// First frequency, Hz.
    pub from_hz: f64,
    /// Last frequency, Hz.
    pub to_hz: f64,
    /// Points across the span (about).
    pub points: usize,
    /// Harmonics kept.
    pub harmonics: usize,
}

/// The first-harmonic amplitude of the output for displacement coefficients `x` at `W`.
fn output_amplitude(model: &ForcedModel, x: &[f64], w: f64, input_amplitude: f64) -> f64 {
    let a = hb::first_harmonic(x);
    match model.output_quantity {
        OutputQuantity::Displacement => a,
        OutputQuantity::Velocity => w * a,
        OutputQuantity::Acceleration => match model.input_quantity {
            InputQuantity::Force => w * w * a,
            InputQuantity::BaseAcceleration => {
                // z'' + f u (f the base feedthrough, -b for the lumped oscillator): cos
                // part -W^2 a_1 + f A, sin part -W^2 b_1.
                let f = model.base_feedthrough();
                (-w * w * x[1] + f * input_amplitude).hypot(-w * w * x[2])
            }
        },
    }
}

fn lu_solve(a: DMatrix<f64>, b: DVector<f64>) -> Option<DVector<f64>> {
    let x = a.lu().solve(&b)?;
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Newton at fixed frequency from `x`.
#[allow(non_snake_case)]
fn newton_fixed(model: &Lumped, basis: &Basis, x: &mut [f64], W: f64, force: f64) -> bool {
    let d = basis.size();
    for _ in 0..50 {
        let (r, jac, _) = hb::residual(model, basis, x, W, force);
        let a = DMatrix::from_row_slice(d, d, &jac);
        let Some(dx) = lu_solve(a, -DVector::from_vec(r)) else {
            return false;
        };
        let scale = x.iter().map(|v| v.abs()).fold(1e-300, f64::max);
        for (xi, di) in x.iter_mut().zip(dx.iter()) {
            *xi += di;
        }
        if dx.amax() <= 1e-12 * scale {
            return true;
        }
    }
    false
}

/// The largest Floquet multiplier's modulus of the orbit `x` at `W` (module docs).
#[allow(non_snake_case)]
pub fn floquet(model: &Lumped, x: &[f64], W: f64) -> f64 {
    if !model.modes.is_empty() {
        return floquet_modal(model, x, W);
    }
    let period = std::f64::consts::TAU / W;
    let w0 = model.natural_frequency_rad_s;
    let c = 2.0 * model.damping_ratio * w0;
    // Slopes along the orbit at time t.
    let slopes = |t: f64| -> (f64, f64) {
        let tau = W * t;
        let (mut z, mut dz) = (x[0], 0.0);
        for k in 1..=(x.len() - 1) / 2 {
            let kf = k as f64;
            let (s, co) = (kf * tau).sin_cos();
            z += x[2 * k - 1] * co + x[2 * k] * s;
            dz += kf * (-x[2 * k - 1] * s + x[2 * k] * co);
        }
        let (gz, gv) = model.restoring_slopes(z, W * dz);
        (w0 * w0 + gz, c + gv)
    };
    // Steps: 256 per period, more while the damping slope makes h c_max large.
    let (_, gv0) = model.restoring_slopes(0.0, 0.0);
    let steps = ((256.0f64).max(period * (c + gv0) / 0.5)).min(200_000.0) as usize;
    let h = period / steps as f64;
    let mut m = [[1.0, 0.0], [0.0, 1.0]];
    for col in 0..2 {
        let (mut d, mut v) = (m[0][col], m[1][col]);
        for s in 0..steps {
            let t = s as f64 * h;
            let f = |t: f64, d: f64, v: f64| {
                let (k, cc) = slopes(t);
                -cc * v - k * d
            };
            let k1d = v;
            let k1v = f(t, d, v);
            let k2d = v + 0.5 * h * k1v;
            let k2v = f(t + 0.5 * h, d + 0.5 * h * k1d, k2d);
            let k3d = v + 0.5 * h * k2v;
            let k3v = f(t + 0.5 * h, d + 0.5 * h * k2d, k3d);
            let k4d = v + h * k3v;
            let k4v = f(t + h, d + h * k3d, k4d);
            d += h / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        }
        m[0][col] = d;
        m[1][col] = v;
    }
    let tr = m[0][0] + m[1][1];
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let disc = tr * tr / 4.0 - det;
    if disc >= 0.0 {
        let s = disc.sqrt();
        (tr / 2.0 + s).abs().max((tr / 2.0 - s).abs())
    } else {
        det.abs().sqrt()
    }
}

/// The orbit's law slopes `(g_z, g_v)` at time `t` (harmonics `x` at `W`).
#[allow(non_snake_case)]
fn law_slopes(model: &Lumped, x: &[f64], W: f64, t: f64) -> (f64, f64) {
    let tau = W * t;
    let (mut z, mut dz) = (x[0], 0.0);
    for k in 1..=(x.len() - 1) / 2 {
        let kf = k as f64;
        let (s, co) = (kf * tau).sin_cos();
        z += x[2 * k - 1] * co + x[2 * k] * s;
        dz += kf * (-x[2 * k - 1] * s + x[2 * k] * co);
    }
    model.restoring_slopes(z, W * dz)
}

/// [`floquet`] of a reduced FE spring: the variational equation of every mode,
/// `d_i'' + 2 zeta_i w_i d_i' + w_i^2 d_i = -a_i (g_z sum d + g_v sum d')`, integrated over a
/// period from the identity (RK4, 256 steps or more so that `w_i h <= 0.5` and the
/// damping slopes' `h c <= 0.5`), and the largest modulus of the `2 N x 2 N` monodromy
/// matrix's eigenvalues.
#[allow(non_snake_case)]
fn floquet_modal(model: &Lumped, x: &[f64], W: f64) -> f64 {
    let period = std::f64::consts::TAU / W;
    let w1 = model.natural_frequency_rad_s;
    let mut k = vec![w1 * w1];
    let mut c = vec![2.0 * model.damping_ratio * w1];
    let mut a = vec![1.0];
    for m in &model.modes {
        k.push(m.natural_frequency_rad_s.powi(2));
        c.push(2.0 * m.damping_ratio * m.natural_frequency_rad_s);
        a.push(m.law_gain);
    }
    let n = k.len();
    let (_, gv0) = model.restoring_slopes(0.0, 0.0);
    let share = a.iter().fold(1.0f64, |m, v| m.max(v.abs()));
    let w_max = k.iter().fold(0.0f64, |m, v| m.max(v.sqrt()));
    let c_max = c.iter().fold(0.0f64, |m, v| m.max(*v)) + share * gv0;
    let steps = (256.0f64)
        .max(period * w_max / 0.5)
        .max(period * c_max / 0.5)
        .min(200_000.0) as usize;
    let h = period / steps as f64;
    let rates = |t: f64, y: &[f64], out: &mut [f64]| {
        let (gz, gv) = law_slopes(model, x, W, t);
        let dz: f64 = y[..n].iter().sum();
        let dv: f64 = y[n..].iter().sum();
        for i in 0..n {
            out[i] = y[n + i];
            out[n + i] = -c[i] * y[n + i] - k[i] * y[i] - a[i] * (gz * dz + gv * dv);
        }
    };
    let dim = 2 * n;
    let mut monodromy = DMatrix::<f64>::identity(dim, dim);
    let (mut k1, mut k2, mut k3, mut k4, mut tmp) = (
        vec![0.0; dim],
        vec![0.0; dim],
        vec![0.0; dim],
        vec![0.0; dim],
        vec![0.0; dim],
    );
    for col in 0..dim {
        let mut y: Vec<f64> = monodromy.column(col).iter().copied().collect();
        for s in 0..steps {
            let t = s as f64 * h;
            rates(t, &y, &mut k1);
            for j in 0..dim {
                tmp[j] = y[j] + 0.5 * h * k1[j];
            }
            rates(t + 0.5 * h, &tmp, &mut k2);
            for j in 0..dim {
                tmp[j] = y[j] + 0.5 * h * k2[j];
            }
            rates(t + 0.5 * h, &tmp, &mut k3);
            for j in 0..dim {
                tmp[j] = y[j] + h * k3[j];
            }
            rates(t + h, &tmp, &mut k4);
            for j in 0..dim {
                y[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
            }
        }
        monodromy.column_mut(col).copy_from_slice(&y);
    }
    monodromy
        .complex_eigenvalues()
        .iter()
        .map(|l| l.norm())
        .fold(0.0, f64::max)
}

/// The most points one curve may ask for (docs/files.md): about 5 ms each on the
/// development machine, so the bound keeps one call under ten minutes.
pub const MAX_POINTS: usize = 100_000;

/// The most harmonics the balance may keep (the command line's `--harmonics` range).
pub const MAX_HARMONICS: usize = 40;

/// The forced response curve of `model` (module docs).
#[allow(non_snake_case)]
pub fn frc(model: &ForcedModel, settings: &FrcSettings) -> Result<Vec<FrcPoint>, String> {
    if !(2..=MAX_POINTS).contains(&settings.points) {
        return Err(format!(
            "--points {}: expected 2 to {MAX_POINTS}",
            settings.points
        ));
    }
    if !(1..=MAX_HARMONICS).contains(&settings.harmonics) {
        return Err(format!(
            "--harmonics {}: expected 1 to {MAX_HARMONICS}",
            settings.harmonics
        ));
    }
    if !(settings.from_hz > 0.0 && settings.to_hz > settings.from_hz) {
        return Err(format!(
            "--from {} and --to {}: expected 0 < from < to (Hz)",
            settings.from_hz, settings.to_hz
        ));
    }
    if !(settings.amplitude.is_finite() && settings.amplitude > 0.0) {
        return Err(format!(
            "--amplitude {}: expected a positive input amplitude",
            settings.amplitude
        ));
    }
    let o = &model.oscillator;
    let basis = Basis::new(settings.harmonics);
    let d = basis.size();
    let w0 = o.natural_frequency_rad_s;
    let force = o.input_gain * settings.amplitude;
    let zr = force.abs() / (w0 * w0 * (2.0 * o.damping_ratio).max(0.01));
    let (w_from, w_to) = (
        std::f64::consts::TAU * settings.from_hz,
        std::f64::consts::TAU * settings.to_hz,
    );
    // Start: the linear response at the first frequency, then Newton.
    let mut x = vec![0.0; d];
    {
        let stiff = w0 * w0 - w_from * w_from;
        let damp = 2.0 * o.damping_ratio * w0 * w_from;
        let den = stiff * stiff + damp * damp;
        x[1] = force * stiff / den;
        x[2] = force * damp / den;
    }
    if !newton_fixed(o, &basis, &mut x, w_from, force) {
        return Err(format!(
            "no periodic solution found at {} Hz (Newton did not converge from the linear \
             response)",
            settings.from_hz
        ));
    }
    let start = Start {
        x,
        w_from,
        w_to,
        zr,
        force,
    };
    // A coarse pass measures the curve's length in the scaled unknowns; the fine pass then
    // steps it in about `points` equal pieces (module docs).
    let span = (w_to - w_from) / w0;
    let coarse = trace(
        o,
        &basis,
        &start,
        4.0 * span / settings.points.max(2) as f64,
        40 * settings.points.max(2),
    )?;
    let length: f64 = coarse.windows(2).map(|p| (&p[1].0 - &p[0].0).norm()).sum();
    let fine = trace(
        o,
        &basis,
        &start,
        length.max(span) / settings.points.max(2) as f64,
        40 * settings.points.max(2),
    )?;
    Ok(fine
        .iter()
        .map(|(xs, _)| {
            let (xv, w) = unscale(xs, zr, w0, d);
            point(model, o, &xv, w, settings.amplitude)
        })
        .collect())
}

/// Where a continuation starts.
struct Start {
    x: Vec<f64>,
    w_from: f64,
    w_to: f64,
    zr: f64,
    force: f64,
}

/// Pseudo-arclength continuation from `start` with steps up to `ds_max` (module docs);
/// the scaled unknowns of every point and the corrector's iterations.
#[allow(non_snake_case)]
fn trace(
    o: &Lumped,
    basis: &Basis,
    start: &Start,
    ds_max: f64,
    max_steps: usize,
) -> Result<Vec<(DVector<f64>, usize)>, String> {
    let d = basis.size();
    let w0 = o.natural_frequency_rad_s;
    let (zr, force) = (start.zr, start.force);
    let mut X = {
        let mut v: Vec<f64> = start.x.iter().map(|c| c / zr).collect();
        v.push(start.w_from / w0);
        DVector::from_vec(v)
    };
    let mut out = vec![(X.clone(), 0)];
    let mut tangent = DVector::zeros(d + 1);
    tangent[d] = 1.0;
    let mut ds = ds_max;
    for _ in 0..max_steps {
        // Tangent: null vector of [R_x zr, R_W w0].
        let (xv, w) = unscale(&X, zr, w0, d);
        let (_, jac, r_w) = hb::residual(o, basis, &xv, w, force);
        let mut a = DMatrix::zeros(d + 1, d + 1);
        for i in 0..d {
            for j in 0..d {
                a[(i, j)] = jac[i * d + j] * zr;
            }
            a[(i, d)] = r_w[i] * w0;
        }
        for j in 0..=d {
            a[(d, j)] = tangent[j];
        }
        let mut rhs = DVector::zeros(d + 1);
        rhs[d] = 1.0;
        let Some(t) = lu_solve(a, rhs) else {
            return Err("the continuation lost its tangent (a singular Jacobian)".into());
        };
        let t = t.normalize();
        tangent = if t.dot(&tangent) < 0.0 { -t } else { t };
        // Predictor and corrector, halving the step on failure.
        let mut accepted = None;
        for _ in 0..20 {
            let pred = &X + &tangent * ds;
            if let Some(found) = correct(o, basis, &pred, &tangent, zr, w0, force) {
                accepted = Some(found);
                break;
            }
            ds *= 0.5;
        }
        let Some((sol, iterations)) = accepted else {
            return Err(format!(
                "the continuation stopped near {:.6} Hz (no corrector converged)",
                X[d] * w0 / std::f64::consts::TAU
            ));
        };
        if iterations <= 3 {
            ds = (ds * 1.3).min(ds_max);
        }
        X = sol;
        let w = X[d] * w0;
        if w > start.w_to {
            break;
        }
        out.push((X.clone(), iterations));
        if w < start.w_from - 0.5 * (start.w_to - start.w_from) {
            break;
        }
    }
    Ok(out)
}

#[allow(non_snake_case)]
fn unscale(X: &DVector<f64>, zr: f64, w0: f64, d: usize) -> (Vec<f64>, f64) {
    ((0..d).map(|i| X[i] * zr).collect(), X[d] * w0)
}

fn point(model: &ForcedModel, o: &Lumped, x: &[f64], w: f64, amplitude: f64) -> FrcPoint {
    let multiplier = floquet(o, x, w);
    FrcPoint {
        frequency_hz: w / std::f64::consts::TAU,
        amplitude: output_amplitude(model, x, w, amplitude),
        stable: multiplier < 1.0,
        multiplier,
        coefficients: x.to_vec(),
    }
}

/// Newton on the arclength-augmented system from `pred`; the solution and its iterations.
#[allow(non_snake_case)]
fn correct(
    o: &Lumped,
    basis: &Basis,
    pred: &DVector<f64>,
    tangent: &DVector<f64>,
    zr: f64,
    w0: f64,
    force: f64,
) -> Option<(DVector<f64>, usize)> {
    let d = basis.size();
    let mut X = pred.clone();
    for it in 1..=8 {
        let (xv, w) = unscale(&X, zr, w0, d);
        let (r, jac, r_w) = hb::residual(o, basis, &xv, w, force);
        let mut a = DMatrix::zeros(d + 1, d + 1);
        let mut rhs = DVector::zeros(d + 1);
        for i in 0..d {
            for j in 0..d {
                a[(i, j)] = jac[i * d + j] * zr;
            }
            a[(i, d)] = r_w[i] * w0;
            rhs[i] = -r[i];
        }
        for j in 0..=d {
            a[(d, j)] = tangent[j];
        }
        rhs[d] = -tangent.dot(&(&X - pred));
        let dx = lu_solve(a, rhs)?;
        X += &dx;
        if dx.amax() < 1e-11 * X.amax().max(1.0) {
            return Some((X, it));
        }
    }
    None
}

/// The backbone at `count` first-harmonic displacement amplitudes up to `max_amplitude`
/// (module docs).
#[allow(non_snake_case)]
pub fn backbone(
    model: &ForcedModel,
    max_amplitude: f64,
    count: usize,
    harmonics: usize,
) -> Result<Vec<BackbonePoint>, String> {
    let mut conservative = model.oscillator.clone();
    conservative.damping_ratio = 0.0;
    conservative.friction = 0.0;
    conservative.drag = 0.0;
    for m in &mut conservative.modes {
        m.damping_ratio = 0.0;
    }
    let basis = Basis::new(harmonics);
    let d = basis.size();
    let w0 = conservative.natural_frequency_rad_s;
    let mut x = vec![0.0; d];
    let mut w = w0;
    let mut out = Vec::new();
    for i in 1..=count {
        let a1 = max_amplitude * i as f64 / count as f64;
        x[1] = a1;
        x[2] = 0.0;
        // Unknowns: x without x_1, x_2 (fixed) and W; equations: all but the sin-1 row.
        let free: Vec<usize> = (0..d).filter(|&n| n != 1 && n != 2).collect();
        let rows: Vec<usize> = (0..d).filter(|&n| n != 2).collect();
        let mut ok = false;
        for _ in 0..50 {
            let (r, jac, r_w) = hb::residual(&conservative, &basis, &x, w, 0.0);
            let m = rows.len();
            let mut a = DMatrix::zeros(m, m);
            let mut rhs = DVector::zeros(m);
            for (ri, &row) in rows.iter().enumerate() {
                for (ci, &col) in free.iter().enumerate() {
                    a[(ri, ci)] = jac[row * d + col];
                }
                a[(ri, m - 1)] = r_w[row];
                rhs[ri] = -r[row];
            }
            let Some(dx) = lu_solve(a, rhs) else {
                break;
            };
            for (ci, &col) in free.iter().enumerate() {
                x[col] += dx[ci];
            }
            w += dx[m - 1];
            if dx.amax() < 1e-12 * (a1 + w) {
                ok = true;
                break;
            }
        }
        if !ok || w.is_nan() || w <= 0.0 {
            return Err(format!(
                "the backbone stopped at amplitude {a1:.4e} (no free periodic solution found)"
            ));
        }
        let peak: f64 = x[0] + (1..=harmonics).map(|k| x[2 * k - 1]).sum::<f64>();
        out.push(BackbonePoint {
            frequency_hz: w / std::f64::consts::TAU,
            amplitude: output_amplitude(model, &x, w, 0.0),
            peak_displacement: peak,
        });
    }
    Ok(out)
}

/// The folds of a curve: the frequencies where the stability changes, Hz.
pub fn jumps(points: &[FrcPoint]) -> Vec<f64> {
    points
        .windows(2)
        .filter(|p| p[0].stable != p[1].stable)
        .map(|p| 0.5 * (p[0].frequency_hz + p[1].frequency_hz))
        .collect()
}
