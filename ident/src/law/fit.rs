//! Fitting the damping laws to a case's records: each record reduced to its mode's
//! frequency and damping ratio ([`fit_decay`], a damped sinusoid plus offset by variable
//! projection), each law fitted to all of them by weighted non-negative least squares
//! ([`fit_law`]), and the choice among the fits ([`choose`]). Formulation, weights and
//! thresholds in the parent module's documentation.

use crate::case::DecayMode;
use crate::diagnose::lm;
use crate::error::{Result, TuneError};
use crate::scatter::{FitTest, RepeatScatter, MEASURED_ZETA};
use coil_postproc::signal::Signal;
use coil_postproc::spectrum::{amplitude_spectrum, SpectrumOptions};
use coil_tuner::band::{Coefficients, Law};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A record reduced to its mode's frequency and damping ratio.
#[derive(Debug, Clone, Serialize)]
pub struct RecordFit {
    /// The record's file.
    pub file: PathBuf,
    /// The mode it records: the weight's axial mode or the coil's surge mode.
    pub mode: DecayMode,
    /// The attached mass it was taken with (kg).
    pub mass_kg: f64,
    /// The fitted undamped frequency `w / (2 pi)` (Hz).
    pub frequency_hz: f64,
    /// The fitted damping ratio zeta (-).
    pub damping_ratio: f64,
    /// Standard error of zeta from the fit alone (-).
    pub damping_ratio_se: f64,
    /// RMS of the fit's residual over the RMS of the record.
    pub residual_rms: f64,
    /// The FE coefficients of this record's mode (frequency replaced by the measured one).
    pub coefficients: Coefficients,
}

impl RecordFit {
    /// The record's file name.
    pub fn name(&self) -> String {
        self.file
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default()
    }
}

/// Fits `exp(-s t) (c1 cos w_d t + c2 sin w_d t) + c3` to a record (module docs).
/// Returns `(w, zeta, se_zeta, relative residual rms)`.
pub fn fit_decay(signal: &Signal) -> Result<(f64, f64, f64, f64)> {
    let t0 = signal.time_s().first().copied().unwrap_or(0.0);
    let t: Vec<f64> = signal.time_s().iter().map(|x| x - t0).collect();
    let y = signal.values();
    let bad = |what: String| TuneError::Invalid(format!("{}: {what}", signal.source().display()));
    if t.len() < 20 {
        return Err(bad(format!(
            "{} samples; expected a decay record of at least 20",
            t.len()
        )));
    }
    // Noise from fourth differences (the decay itself contributes (w dt)^4, negligible
    // when sampled finely), then the record is kept while a two-period window stands
    // 5 noise levels above it: a strongly damped mode leaves mostly noise behind.
    let fourth: f64 = y
        .windows(5)
        .map(|w| (w[0] - 4.0 * w[1] + 6.0 * w[2] - 4.0 * w[3] + w[4]).powi(2))
        .sum::<f64>()
        / (y.len() - 4) as f64;
    let noise = (fourth / 70.0).sqrt();
    // The spectrum of the part that stands above the noise (a strongly damped mode is
    // gone long before a long record ends).
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let strong = y
        .iter()
        .rposition(|v| (v - mean).abs() > 10.0 * noise)
        .map_or(y.len(), |i| i + 1)
        .max(256.min(y.len()));
    let spectrum = signal
        .slice(0..strong)
        .and_then(|strong| amplitude_spectrum(&strong, &SpectrumOptions::default()))
        .map_err(|source| TuneError::Post {
            context: format!("spectrum of {}", signal.source().display()),
            source,
        })?;
    let peak = spectrum
        .dominant_peak()
        .ok_or_else(|| bad("no spectral peak; expected a free decay".into()))?;
    let w0 = std::f64::consts::TAU * peak.frequency_hz;
    let rms = |s: &[f64]| {
        let m = s.iter().sum::<f64>() / s.len() as f64;
        (s.iter().map(|x| (x - m).powi(2)).sum::<f64>() / s.len() as f64).sqrt()
    };
    let dt = signal.step_s().max(f64::MIN_POSITIVE);
    let window =
        ((2.0 * std::f64::consts::TAU / (w0 * dt)).round() as usize).clamp(8, (y.len() / 4).max(8));
    let mut windows: Vec<(f64, f64)> = Vec::new();
    for (k, chunk) in y.chunks_exact(window).enumerate() {
        let r = rms(chunk);
        if k >= 4 && r < 5.0 * noise {
            break;
        }
        windows.push((
            (k as f64 + 0.5) * window as f64 * dt,
            r.max(f64::MIN_POSITIVE),
        ));
    }
    let kept = (windows.len() * window).max(4 * window).min(y.len());
    let (t, y) = (&t[..kept], &y[..kept]);
    // Decay rate: log-linear regression of the window RMS.
    let nw = windows.len() as f64;
    let (mt, ml) = windows
        .iter()
        .fold((0.0, 0.0), |(a, b), (tk, r)| (a + tk / nw, b + r.ln() / nw));
    let (sxy, sxx) = windows.iter().fold((0.0, 0.0), |(a, b), (tk, r)| {
        (a + (tk - mt) * (r.ln() - ml), b + (tk - mt).powi(2))
    });
    let s0 = if sxx > 0.0 {
        (-sxy / sxx).max(1e-6 * w0)
    } else {
        1e-3 * w0
    };
    let residuals = |p: &[f64]| -> std::result::Result<Vec<f64>, String> {
        let (wd, s) = (p[0] * w0, p[1] * w0);
        let cols: Vec<Vec<f64>> = vec![
            t.iter().map(|&x| (-s * x).exp() * (wd * x).cos()).collect(),
            t.iter().map(|&x| (-s * x).exp() * (wd * x).sin()).collect(),
            vec![1.0; t.len()],
        ];
        let c = lm::linear_least_squares(&cols, y).ok_or("singular basis")?;
        Ok((0..t.len())
            .map(|i| c[0] * cols[0][i] + c[1] * cols[1][i] + c[2] - y[i])
            .collect())
    };
    let options = lm::LmOptions {
        max_iterations: 100,
        scale: vec![1.0, 1e-3],
    };
    let fit = lm::fit(&residuals, &[1.0, s0 / w0], &options).map_err(bad)?;
    let (wd, s) = (fit.params[0] * w0, fit.params[1] * w0);
    let w = (wd * wd + s * s).sqrt();
    let zeta = s / w;
    let se = fit.std_errors[1] * w0 / w;
    let relative = (fit.cost / t.len() as f64).sqrt() / rms(y).max(f64::MIN_POSITIVE);
    if !(zeta.is_finite() && se.is_finite() && w.is_finite() && w > 0.0) {
        return Err(bad("the damped-sinusoid fit did not converge".into()));
    }
    Ok((w, zeta, se, relative))
}

/// One law fitted to every record.
#[derive(Debug, Clone, Serialize)]
pub struct Candidate {
    /// The law fitted.
    pub law: Law,
    /// Fitted parameters by the spec's names (units in the module docs).
    pub parameters: BTreeMap<String, f64>,
    /// Their standard errors, scaled by `sqrt(chi2 / (n - k))` when that exceeds 1.
    pub parameters_se: BTreeMap<String, f64>,
    /// Per parameter: relative standard error at most [`IDENTIFIED_SE`] (then 5 % is
    /// two standard errors).
    pub parameters_identified: BTreeMap<String, bool>,
    /// RMS of (predicted - measured zeta) / measured zeta over the records.
    pub residual_rms: f64,
    /// Weighted chi-square of the predicted against the measured zetas (-).
    pub chi2: f64,
    /// Records minus the parameters left free by the non-negative fit.
    pub dof: usize,
    /// Parameters the non-negative fit held at zero (the unconstrained fit wanted them
    /// negative, which no physical damping is).
    pub at_bound: Vec<String>,
    /// The test of fit against the repeat scatter ([`RepeatScatter::judge`]).
    pub test: FitTest,
    /// Bayesian information criterion `chi2 + k ln n` (-).
    pub bic: f64,
    /// Mean squared normalised held-out error, or `None` when the other records cannot
    /// determine the law.
    pub held_out: Option<f64>,
    /// Whether the test of fit and the held-out score are consistent with the records'
    /// errors and the repeat scatter, and the parameters admissible (not every one held at
    /// zero while a record measures damping).
    pub consistent: bool,
    /// Predicted zeta per record.
    pub predicted: Vec<f64>,
    /// Covariance of the parameters, scaled as `parameters_se` (not serialised).
    #[serde(skip)]
    pub covariance: Vec<Vec<f64>>,
}

impl Candidate {
    /// `name = value +- se` for every parameter.
    pub fn parameters_text(&self) -> String {
        self.parameters
            .iter()
            .map(|(k, v)| format!("{k} = {v:.5e} +- {:.2e}", self.parameters_se[k]))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The held-out score, or `-` when the records cannot give one.
    pub fn held_out_text(&self) -> String {
        self.held_out.map_or("-".to_string(), |h| format!("{h:.2}"))
    }
}

/// Weighted non-negative least squares `sum w (y - X p)^2`, with the covariance of `p`
/// (unscaled, from the active columns). Brute force over active sets (at most 2 columns),
/// the empty one included: every parameter at zero when every other set wants one negative.
fn nnls(x: &[Vec<f64>], y: &[f64], w: &[f64]) -> Option<(Vec<f64>, Vec<Vec<f64>>, f64)> {
    let k = x.first()?.len();
    let zero: f64 = y.iter().zip(w).map(|(yi, wi)| wi * yi * yi).sum();
    let mut best = Some((vec![0.0; k], vec![vec![0.0; k]; k], zero));
    for mask in 1..(1u32 << k) {
        let active: Vec<usize> = (0..k).filter(|j| mask & (1 << j) != 0).collect();
        let a = active.len();
        let mut n = nalgebra::DMatrix::<f64>::zeros(a, a);
        let mut b = nalgebra::DVector::<f64>::zeros(a);
        for ((row, &yi), &wi) in x.iter().zip(y).zip(w) {
            for (p, &i) in active.iter().enumerate() {
                b[p] += wi * row[i] * yi;
                for (q, &j) in active.iter().enumerate() {
                    n[(p, q)] += wi * row[i] * row[j];
                }
            }
        }
        let Some(inv) = n.clone().try_inverse() else {
            continue;
        };
        let sol = &inv * b;
        if sol.iter().any(|&v| v < 0.0 || !v.is_finite()) {
            continue;
        }
        let mut p = vec![0.0; k];
        let mut cov = vec![vec![0.0; k]; k];
        for (pi, &i) in active.iter().enumerate() {
            p[i] = sol[pi];
            for (qj, &j) in active.iter().enumerate() {
                cov[i][j] = inv[(pi, qj)];
            }
        }
        let chi2: f64 = x
            .iter()
            .zip(y)
            .zip(w)
            .map(|((row, yi), wi)| {
                let pred: f64 = row.iter().zip(&p).map(|(a, b)| a * b).sum();
                wi * (yi - pred).powi(2)
            })
            .sum();
        if best.as_ref().is_none_or(|b| chi2 < b.2 - 1e-12 * b.2.abs()) {
            best = Some((p, cov, chi2));
        }
    }
    best
}

/// Whether records with rows `x` (weights `w`) determine every parameter: the smallest
/// eigenvalue of the weighted normal matrix scaled to unit diagonal is at least 1e-3
/// (two columns: correlation below 0.999).
fn determines(x: &[Vec<f64>], w: &[f64]) -> bool {
    let Some(k) = x.first().map(Vec::len) else {
        return false;
    };
    if x.len() < k {
        return false;
    }
    let mut n = nalgebra::DMatrix::<f64>::zeros(k, k);
    for (row, &wi) in x.iter().zip(w) {
        for i in 0..k {
            for j in 0..k {
                n[(i, j)] += wi * row[i] * row[j];
            }
        }
    }
    let d: Vec<f64> = (0..k).map(|i| n[(i, i)].sqrt()).collect();
    if d.iter().any(|&v| v <= 0.0 || !v.is_finite()) {
        return false;
    }
    let scaled = nalgebra::DMatrix::from_fn(k, k, |i, j| n[(i, j)] / (d[i] * d[j]));
    scaled.symmetric_eigenvalues().iter().all(|&l| l >= 1e-3)
}

/// Largest relative standard error of a parameter reported as identified.
pub const IDENTIFIED_SE: f64 = 0.025;

/// A record's zeta variance: its fit error and the repeat scatter `scatter` (relative).
pub fn sigma2(r: &RecordFit, scatter: f64) -> f64 {
    r.damping_ratio_se.powi(2) + (scatter * r.damping_ratio).powi(2)
}

/// Fits one law to `records`, each zeta uncertain by its fit error and the relative
/// repeat `scatter` of a test, and judges it by [`RepeatScatter::judge`] (module docs).
pub fn fit_law(law: Law, records: &[RecordFit], scatter: &RepeatScatter) -> Option<Candidate> {
    let x: Vec<Vec<f64>> = records.iter().map(|r| r.coefficients.row(law)).collect();
    let y: Vec<f64> = records.iter().map(|r| r.damping_ratio).collect();
    let w: Vec<f64> = records
        .iter()
        .map(|r| 1.0 / sigma2(r, scatter.relative))
        .collect();
    let (p, cov, chi2) = nnls(&x, &y, &w)?;
    let n = records.len();
    let k = law.parameters().len();
    // A parameter the non-negative fit holds at zero is no longer free: the records keep
    // that degree of freedom to test the law with.
    let free = p.iter().filter(|&&v| v > 0.0).count();
    let dof = n.saturating_sub(free);
    let inflate = if dof > 0 {
        (chi2 / dof as f64).max(1.0)
    } else {
        1.0
    };
    let predicted: Vec<f64> = x
        .iter()
        .map(|row| row.iter().zip(&p).map(|(a, b)| a * b).sum())
        .collect();
    let residual_rms = (predicted
        .iter()
        .zip(&y)
        .map(|(p, m)| ((p - m) / m).powi(2))
        .sum::<f64>()
        / n as f64)
        .sqrt();
    // Held out: each record from the others, when they leave no free direction.
    let held_out = (n > k && n >= 2)
        .then(|| {
            let mut total = 0.0;
            let mut folds = 0;
            for r in 0..n {
                let keep: Vec<usize> = (0..n).filter(|&i| i != r).collect();
                let xs: Vec<Vec<f64>> = keep.iter().map(|&i| x[i].clone()).collect();
                let ys: Vec<f64> = keep.iter().map(|&i| y[i]).collect();
                let ws: Vec<f64> = keep.iter().map(|&i| w[i]).collect();
                if !determines(&xs, &ws) {
                    continue;
                }
                folds += 1;
                let (pk, ck, _) = nnls(&xs, &ys, &ws)?;
                let pred: f64 = x[r].iter().zip(&pk).map(|(a, b)| a * b).sum();
                let var: f64 = (0..k)
                    .flat_map(|i| (0..k).map(move |j| (i, j)))
                    .map(|(i, j)| x[r][i] * ck[i][j] * x[r][j])
                    .sum();
                total += (y[r] - pred).powi(2) / (1.0 / w[r] + var.max(0.0));
            }
            (folds > 0).then(|| total / folds as f64)
        })
        .flatten();
    let test = scatter.judge(chi2, dof, scatter.pure_error(&y, &w));
    // Every parameter held at zero is no damping at all: inadmissible when a record
    // measures damping well above its fit error, however wide the scatter estimate.
    let undamped = free == 0
        && records
            .iter()
            .any(|r| r.damping_ratio > MEASURED_ZETA * r.damping_ratio_se);
    let consistent = test.consistent
        && !undamped
        && held_out.is_none_or(|h| h < HELD_OUT_LIMIT * scatter.held_out_factor());
    let names = law.parameters();
    let mut parameters = BTreeMap::new();
    let mut parameters_se = BTreeMap::new();
    let mut identified = BTreeMap::new();
    for (i, name) in names.iter().enumerate() {
        let se = (cov[i][i] * inflate).max(0.0).sqrt();
        parameters.insert(name.to_string(), p[i]);
        parameters_se.insert(name.to_string(), se);
        identified.insert(name.to_string(), p[i] > 0.0 && se <= IDENTIFIED_SE * p[i]);
    }
    let covariance = (0..k)
        .map(|i| (0..k).map(|j| cov[i][j] * inflate).collect())
        .collect();
    let at_bound = names
        .iter()
        .zip(&p)
        .filter(|(_, &v)| v <= 0.0)
        .map(|(n, _)| n.to_string())
        .collect();
    Some(Candidate {
        law,
        parameters,
        parameters_se,
        parameters_identified: identified,
        residual_rms,
        chi2,
        dof,
        at_bound,
        test,
        bic: chi2 + k as f64 * (n as f64).ln(),
        held_out,
        consistent,
        predicted,
        covariance,
    })
}

/// Largest held-out score (mean squared normalised error) of a consistent law, with the
/// default scatter: 3 standard deviations.
pub const HELD_OUT_LIMIT: f64 = 9.0;

/// How far a candidate misses, in words: its test statistic against the 99.9 % point.
fn miss_text(c: &Candidate) -> String {
    let held = if c.at_bound.is_empty() {
        String::new()
    } else if c.at_bound.len() == c.law.parameters().len() {
        format!(
            ", {} held at 0: no damping, where the records measure some",
            c.at_bound.join(" and ")
        )
    } else {
        format!(", {} held at 0", c.at_bound.join(" and "))
    };
    if c.test.dof == 0 {
        format!("{}: exactly determined{held}", c.law.name())
    } else {
        format!(
            "{}: {:.1} against {:.1} at 99.9 % on {} dof, rms miss {:.1} %{held}",
            c.law.name(),
            c.test.statistic,
            c.test.critical,
            c.test.dof,
            100.0 * c.residual_rms
        )
    }
}

/// The choice among fitted candidates: the law, or `None` with the reason. A law is named
/// when it is consistent with the records (its parameters admissible, its test of fit and
/// held-out score within the repeat scatter) and every other law misses beyond it; an
/// exactly determined law is never rejected for fitting.
pub fn choose(candidates: &[Candidate], n_records: usize) -> (Option<Law>, String) {
    if n_records < 2 {
        return (
            None,
            "one record fixes one number (the mode's zeta); every law reproduces it".into(),
        );
    }
    let mut sorted: Vec<&Candidate> = candidates.iter().collect();
    sorted.sort_by(|a, b| a.bic.total_cmp(&b.bic));
    let consistent: Vec<&Candidate> = sorted.iter().copied().filter(|c| c.consistent).collect();
    let misses = |skip: Law| -> String {
        sorted
            .iter()
            .filter(|c| c.law != skip)
            .map(|c| miss_text(c))
            .collect::<Vec<_>>()
            .join("; ")
    };
    match consistent.as_slice() {
        [] => match sorted.first() {
            None => (None, "no law could be fitted".into()),
            Some(best) => (
                None,
                format!(
                    "no law is consistent with the records within the repeat scatter ({}; {})",
                    miss_text(best),
                    misses(best.law)
                ),
            ),
        },
        [only] => (
            Some(only.law),
            format!(
                "{} is consistent with the records within the repeat scatter ({}) and every other \
                 law misses beyond it ({})",
                only.law.name(),
                miss_text(only),
                misses(only.law)
            ),
        ),
        [first, second, ..] => (
            None,
            format!(
                "{} and {} both fit the records within the repeat scatter ({}; {})",
                first.law.name(),
                second.law.name(),
                miss_text(first),
                miss_text(second)
            ),
        ),
    }
}
