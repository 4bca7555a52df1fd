//! Which damping law? `coil-tune damping CASE --out DIR`: fits the three damping
//! laws of docs/measured-case.md to all decay records of a case at once, chooses by
//! an information criterion and held-out prediction, and says when the records cannot
//! decide.
//!
//! # Formulation
//! Each record r is one free decay of one mode (the weight bouncing on the spring at the
//! record's attached mass, or the coil's own surge mode with the weight held). It is
//! reduced to its undamped circular frequency `w_r` and damping ratio `zeta_r` with a
//! standard error, by a least-squares fit of a damped sinusoid plus offset
//! `y = exp(-s t) (c1 cos w_d t + c2 sin w_d t) + c3` (variable projection: the linear
//! `c` are solved inside every evaluation of the two nonlinear `(w_d, s)`; Levenberg-
//! Marquardt, `diagnose::lm`); `w = sqrt(w_d^2 + s^2)`, `zeta = s / w`.
//!
//! For small damping every law gives the mode a damping ratio linear in its parameters
//! (first-order modal damping, the mode shape `phi` mass-normalised):
//!
//! | law | zeta of mode r |
//! |---|---|
//! | `rayleigh` | `alpha d_r / (2 w_r) + beta w_r / 2`, `d_r = phi^T M_wire phi` |
//! | `hysteretic` | `loss_factor / 2` |
//! | `external_viscous` | `c phi_w^2 / (2 w_r)` (`phi_w` the weight's axial entry) |
//!
//! `beta w / 2` is exact because all the stiffness is the wire's. `d_r` and `phi_w` come
//! from coil's FE model of the case's spring at the record's mass; mode shapes do not
//! depend on Young's modulus (scaling K scales every `w^2`), so E needs no calibration
//! here and `w_r` is the measured one. A surge record is the fixed-fixed coil: `d = 1`
//! and `phi_w = 0` exactly (the held weight takes no part).
//!
//! **What the records can separate.** For the weight mode `w^2 = K / m_eff`, so
//! `beta w / 2 = beta sqrt(K / m_eff) / 2`, `c / (2 m_eff w) = c / (2 sqrt(K m_eff))` and
//! `alpha d / (2 w) = alpha (m_s / 3) / (2 sqrt(K m_eff))`: all three viscous forms fall as
//! `m_eff^{-1/2}` and are the same law to first order (a dashpot across a massless
//! spring is a dashpot to ground). Records at several masses therefore separate the
//! hysteretic law (zeta independent of the mass) from the viscous family, not the
//! members of that family from each other; a surge record does (beta gives it
//! `beta w_s / 2`, about 30 times the weight mode's zeta; the dashpot nothing).
//!
//! # Fit and choice
//! Each law is fitted by weighted non-negative least squares to all records at once,
//! weights `1 / s_r^2` with `s_r^2 = se_r^2 + (s zeta_r)^2`: the record's fit error and the
//! repeat scatter `s` of one test (default 3 %, the paper's Table 1: 0.0017-0.0018 around
//! 0.00175). A record's own fit error understates how far a repeat test lands (mounting,
//! amplitude, temperature), so the scatter dominates and sets what a mass ratio can
//! decide. `chi2 = sum ((zeta_r - zeta_hat_r) / s_r)^2`, `BIC = chi2 + k ln n`. Held
//! out: each record predicted from the others (when they still determine the law),
//! `loo = mean ((zeta_r - pred_r) / sqrt(s_r^2 + var pred_r))^2`. A law is chosen only
//! when it is consistent with the records (chi2 below the 99.9 % point of its chi-square
//! distribution, and the held-out score below 9 where it exists) and every other law's
//! BIC is at least 10 higher (very strong evidence); otherwise `law` is null,
//! `identifiable` false. Parameter standard errors from the weighted normal matrix,
//! scaled by `sqrt(chi2 / (n - k))` when that exceeds 1.
//!
//! Units: `rayleigh_alpha` 1/s, `rayleigh_beta` s, `loss_factor` -, `dashpot_n_s_m` N s/m.

use crate::case::{read_case, read_variants, DecayMode, MeasuredCase, VariantsFile};
use crate::diagnose::lm;
use crate::error::{Result, TuneError};
use crate::fe::{FeSettings, SpringState};
use coil_postproc::signal::Signal;
use coil_postproc::spectrum::{amplitude_spectrum, SpectrumOptions};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The laws and their modal coefficients live below identification, in the tuner (the
/// paper's band uses them too).
pub use coil_tuner::band::{
    band, band_markdown, mode_coefficients, spread_percent, Band, Coefficients, Law, LAWS,
};

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
    /// Bayesian information criterion `chi2 + k ln n` (-).
    pub bic: f64,
    /// Mean squared normalised held-out error, or `None` when the other records cannot
    /// determine the law.
    pub held_out: Option<f64>,
    /// Whether chi2 and the held-out score are consistent with the records' errors.
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
/// (unscaled, from the active columns). Brute force over active sets (at most 2 columns).
fn nnls(x: &[Vec<f64>], y: &[f64], w: &[f64]) -> Option<(Vec<f64>, Vec<Vec<f64>>, f64)> {
    let k = x.first()?.len();
    let mut best: Option<(Vec<f64>, Vec<Vec<f64>>, f64)> = None;
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

/// The 99.9 % point of chi-square with `dof` degrees of freedom (Wilson-Hilferty).
fn chi2_999(dof: usize) -> f64 {
    if dof == 0 {
        return 0.0;
    }
    let k = dof as f64;
    let z = 3.090;
    let h = 2.0 / (9.0 * k);
    k * (1.0 - h + z * h.sqrt()).powi(3)
}

/// Largest relative standard error of a parameter reported as identified.
pub const IDENTIFIED_SE: f64 = 0.025;

/// A record's zeta variance: its fit error and the repeat scatter `scatter` (relative).
fn sigma2(r: &RecordFit, scatter: f64) -> f64 {
    r.damping_ratio_se.powi(2) + (scatter * r.damping_ratio).powi(2)
}

/// Fits one law to `records`, each zeta uncertain by its fit error and the relative
/// repeat `scatter` of a test (module docs).
pub fn fit_law(law: Law, records: &[RecordFit], scatter: f64) -> Option<Candidate> {
    let x: Vec<Vec<f64>> = records.iter().map(|r| r.coefficients.row(law)).collect();
    let y: Vec<f64> = records.iter().map(|r| r.damping_ratio).collect();
    let w: Vec<f64> = records.iter().map(|r| 1.0 / sigma2(r, scatter)).collect();
    let (p, cov, chi2) = nnls(&x, &y, &w)?;
    let n = records.len();
    let k = law.parameters().len();
    let dof = n.saturating_sub(k);
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
    let consistent = chi2 <= chi2_999(dof).max(1e-9) + if dof == 0 { 1e-6 } else { 0.0 }
        && held_out.is_none_or(|h| h < 9.0);
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
    Some(Candidate {
        law,
        parameters,
        parameters_se,
        parameters_identified: identified,
        residual_rms,
        chi2,
        bic: chi2 + k as f64 * (n as f64).ln(),
        held_out,
        consistent,
        predicted,
        covariance,
    })
}

/// BIC margin for a choice (Kass and Raftery's "very strong").
pub const BIC_MARGIN: f64 = 10.0;

/// The choice among fitted candidates: the law, or `None` with the reason.
pub fn choose(candidates: &[Candidate], n_records: usize) -> (Option<Law>, String) {
    if n_records < 2 {
        return (
            None,
            "one record fixes one number (the mode's zeta); every law reproduces it".into(),
        );
    }
    let mut sorted: Vec<&Candidate> = candidates.iter().collect();
    sorted.sort_by(|a, b| a.bic.total_cmp(&b.bic));
    let Some(best) = sorted.first() else {
        return (None, "no law could be fitted".into());
    };
    if !best.consistent {
        return (
            None,
            format!(
                "no law is consistent with the records (best: {}, chi2 {:.1})",
                best.law.name(),
                best.chi2
            ),
        );
    }
    match sorted.get(1) {
        Some(next) if next.bic - best.bic < BIC_MARGIN => (
            None,
            format!(
                "{} and {} fit the records alike (BIC {:.1} and {:.1}, margin {:.1} < {BIC_MARGIN})",
                best.law.name(),
                next.law.name(),
                best.bic,
                next.bic,
                next.bic - best.bic
            ),
        ),
        _ => (
            Some(best.law),
            format!(
                "{} is consistent with the records and every other law's BIC is at least {BIC_MARGIN} higher",
                best.law.name()
            ),
        ),
    }
}

/// A variant's zeta predicted by a law.
#[derive(Debug, Clone, Serialize)]
pub struct VariantPrediction {
    /// The variant's name.
    pub name: String,
    /// zeta of the variant's weight mode under each candidate law (its own fit).
    pub by_law: BTreeMap<String, f64>,
    /// The chosen law's zeta and its standard error (when a law is chosen).
    pub damping_ratio: Option<f64>,
    /// Standard error of the chosen law's zeta (-).
    pub damping_ratio_se: Option<f64>,
    /// `(max - min) / min` over the laws, in percent.
    pub spread_percent: f64,
    /// The paper's printed zeta of the variant, when given (-).
    pub paper_damping_ratio: Option<f64>,
}

/// The deciding test proposed when the law is not identifiable.
#[derive(Debug, Clone, Serialize)]
pub struct DecidingTest {
    /// The repeat-to-repeat scatter of one zeta measurement assumed (relative, 1 sigma).
    pub scatter: f64,
    /// Second mass: (mass ratio, hysteretic/viscous zeta ratio, repeats per mass for a
    /// 3-sigma separation). Separates hysteretic from viscous only.
    pub second_mass: Vec<(f64, f64, usize)>,
    /// Surge-mode zeta (weight held) each calibrated law predicts.
    pub surge_zeta: BTreeMap<String, f64>,
    /// The surge mode's frequency on the calibrated spring with the weight held (Hz).
    pub surge_frequency_hz: f64,
    /// The proposal in words with its numbers.
    pub text: String,
}

/// Everything `coil-tune damping` found.
#[derive(Debug, Clone, Serialize)]
pub struct DampingReport {
    /// The case's name.
    pub case: String,
    /// The chosen law; `None` when the records cannot decide.
    pub law: Option<Law>,
    /// The chosen law's parameters by the spec's names (empty when none is chosen).
    pub parameters: BTreeMap<String, f64>,
    /// Their standard errors (empty when no law is chosen).
    pub parameters_se: BTreeMap<String, f64>,
    /// True when a law was chosen.
    pub identifiable: bool,
    /// Why the law was chosen, or why none could be.
    pub reason: String,
    /// Every decay record reduced to its frequency and damping ratio.
    pub records: Vec<RecordFit>,
    /// Every law fitted to all the records.
    pub candidates: Vec<Candidate>,
    /// The Table 4 variants' zeta under each law (empty without a variants file).
    pub table4: Vec<VariantPrediction>,
    /// The measurement that would decide, when no law is chosen.
    pub deciding_test: Option<DecidingTest>,
    /// When not identifiable: the band of section 2 for the case's spring (each law
    /// calibrated to the first weight-mode record; the variants when given, and the
    /// surge mode).
    pub band: Option<Band>,
}

/// Settings of the damping command.
#[derive(Debug, Clone)]
pub struct DampingSettings {
    /// FE settings of the spring's modal runs.
    pub fe: FeSettings,
    /// Table 4 variants (None: none predicted).
    pub variants: Option<PathBuf>,
    /// Repeat scatter of one test's zeta (relative): the fit's floor and the deciding
    /// test's (the paper's Table 1: 0.0017-0.0018 around 0.00175, about 3 %).
    pub scatter: f64,
}

impl Default for DampingSettings {
    fn default() -> Self {
        DampingSettings {
            fe: FeSettings::default(),
            variants: None,
            scatter: 0.03,
        }
    }
}

/// Reduces every decay record of `case` (module docs).
pub fn record_fits(case: &MeasuredCase, fe: &FeSettings) -> Result<Vec<RecordFit>> {
    let signals = case.decay_records()?;
    let nominal = SpringState::nominal(case);
    let mut cache: Vec<((u64, DecayMode), Coefficients)> = Vec::new();
    let mut out = Vec::with_capacity(signals.len());
    for (k, signal) in signals.iter().enumerate() {
        let info = case.decay_info.get(k).cloned().unwrap_or_default();
        let mass_kg = info.mass_kg.unwrap_or(case.mass_kg);
        let key = (mass_kg.to_bits(), info.mode);
        let coefficients = match cache.iter().find(|(k, _)| *k == key) {
            Some((_, c)) => *c,
            None => {
                let state = SpringState { mass_kg, ..nominal };
                let c = mode_coefficients(&state, fe, info.mode)?;
                cache.push((key, c));
                c
            }
        };
        let (w, zeta, se, residual_rms) = fit_decay(signal)?;
        out.push(RecordFit {
            file: case.decay_files.get(k).cloned().unwrap_or_default(),
            mode: info.mode,
            mass_kg,
            frequency_hz: w / std::f64::consts::TAU,
            damping_ratio: zeta,
            damping_ratio_se: se,
            residual_rms,
            coefficients: Coefficients {
                omega_rad_s: w,
                ..coefficients
            },
        });
    }
    Ok(out)
}

/// Runs the damping-law identification on a case folder.
pub fn identify(case_path: &Path, settings: &DampingSettings) -> Result<DampingReport> {
    let case = read_case(case_path)?;
    let records = record_fits(&case, &settings.fe)?;
    if records.is_empty() {
        return Err(TuneError::Invalid(format!(
            "{}: no decay record; expected records.decay with at least one file",
            case.file.display()
        )));
    }
    let candidates: Vec<Candidate> = LAWS
        .iter()
        .filter_map(|&law| fit_law(law, &records, settings.scatter))
        .collect();
    let (law, reason) = choose(&candidates, records.len());
    let chosen = law.and_then(|l| candidates.iter().find(|c| c.law == l));
    let variants = match &settings.variants {
        Some(p) => Some(read_variants(p)?),
        None => None,
    };
    let table4 = match &variants {
        Some(v) => predict_variants(&case, &records, &candidates, chosen, v, &settings.fe)?,
        None => Vec::new(),
    };
    let (deciding_test, band) = if law.is_none() {
        let state = calibrated_state(&case, &records, &settings.fe)?;
        let base = records
            .iter()
            .find(|r| r.mode == DecayMode::Axial)
            .unwrap_or(&records[0]);
        let none = VariantsFile {
            file: PathBuf::new(),
            source: None,
            variants: Vec::new(),
        };
        let band = band(
            &SpringState {
                mass_kg: base.mass_kg,
                ..state
            },
            variants.as_ref().unwrap_or(&none),
            &settings.fe,
            base.damping_ratio,
            settings.scatter,
        )?;
        (
            Some(deciding_test(&case, &records, &candidates, settings)?),
            Some(band),
        )
    } else {
        (None, None)
    };
    Ok(DampingReport {
        case: case.name.clone(),
        law,
        parameters: chosen.map(|c| c.parameters.clone()).unwrap_or_default(),
        parameters_se: chosen.map(|c| c.parameters_se.clone()).unwrap_or_default(),
        identifiable: law.is_some(),
        reason,
        records,
        candidates,
        table4,
        deciding_test,
        band,
    })
}

/// The state of the case's spring whose weight mode has the frequency of the first axial
/// record at its mass (E scaled: `w^2` is proportional to E at fixed shape).
fn calibrated_state(
    case: &MeasuredCase,
    records: &[RecordFit],
    fe: &FeSettings,
) -> Result<SpringState> {
    let nominal = SpringState::nominal(case);
    let Some(base) = records.iter().find(|r| r.mode == DecayMode::Axial) else {
        return Ok(nominal);
    };
    let state = SpringState {
        mass_kg: base.mass_kg,
        ..nominal
    };
    let c = mode_coefficients(&state, fe, DecayMode::Axial)?;
    let scale = (base.coefficients.omega_rad_s / c.omega_rad_s).powi(2);
    Ok(SpringState {
        youngs_modulus_mpa: nominal.youngs_modulus_mpa * scale,
        mass_kg: case.mass_kg,
        ..nominal
    })
}

fn predict_variants(
    case: &MeasuredCase,
    records: &[RecordFit],
    candidates: &[Candidate],
    chosen: Option<&Candidate>,
    variants: &VariantsFile,
    fe: &FeSettings,
) -> Result<Vec<VariantPrediction>> {
    let state = calibrated_state(case, records, fe)?;
    let mut out = Vec::new();
    for v in &variants.variants {
        let c = mode_coefficients(&state.with_spring(v.spring), fe, DecayMode::Axial)?;
        let mut by_law = BTreeMap::new();
        // A law's zeta is linear in its parameters: the row of coefficients times them.
        let zeta_of = |cand: &Candidate, row: &[f64]| -> f64 {
            let names = cand.law.parameters();
            row.iter()
                .zip(names)
                .map(|(a, n)| a * cand.parameters[*n])
                .sum()
        };
        for cand in candidates {
            by_law.insert(cand.law.name().to_string(), zeta_of(cand, &c.row(cand.law)));
        }
        let (zeta, se) = match chosen {
            Some(cand) => {
                let row = c.row(cand.law);
                let z = zeta_of(cand, &row);
                let k = row.len();
                let var: f64 = (0..k)
                    .flat_map(|i| (0..k).map(move |j| (i, j)))
                    .map(|(i, j)| row[i] * cand.covariance[i][j] * row[j])
                    .sum();
                (Some(z), Some(var.max(0.0).sqrt()))
            }
            None => (None, None),
        };
        out.push(VariantPrediction {
            name: v.name.clone(),
            spread_percent: spread_percent(by_law.values().copied()),
            by_law,
            damping_ratio: zeta,
            damping_ratio_se: se,
            paper_damping_ratio: v.paper_damping_ratio,
        });
    }
    Ok(out)
}

/// Repeats per mass so that a relative difference `delta` between two mean zetas stands
/// at 3 sigma when each measurement scatters by `scatter`: `3 scatter sqrt(2 / n) <= delta`.
pub fn repeats_needed(delta: f64, scatter: f64) -> usize {
    ((2.0 * (3.0 * scatter / delta).powi(2)).ceil() as usize).max(1)
}

fn deciding_test(
    case: &MeasuredCase,
    records: &[RecordFit],
    candidates: &[Candidate],
    settings: &DampingSettings,
) -> Result<DecidingTest> {
    let base = records
        .iter()
        .find(|r| r.mode == DecayMode::Axial)
        .unwrap_or(&records[0]);
    let m_eff = |m: f64| m + SpringState::nominal(case).spring_mass_kg() / 3.0;
    let second_mass = [1.5, 2.0, 3.0]
        .iter()
        .map(|&ratio| {
            let r = (m_eff(base.mass_kg * ratio) / m_eff(base.mass_kg)).powf(-0.5);
            (ratio, r, repeats_needed(1.0 - r, settings.scatter))
        })
        .collect();
    let surge_state = calibrated_state(case, records, &settings.fe)?;
    let surge = mode_coefficients(&surge_state, &settings.fe, DecayMode::Surge)?;
    let mut surge_zeta = BTreeMap::new();
    // Each law calibrated to the base record alone (Rayleigh at both ends of its valley).
    let zeta = base.damping_ratio;
    let c = &base.coefficients;
    let alpha_only = zeta / c.row(Law::Rayleigh)[0];
    let beta_only = zeta / c.row(Law::Rayleigh)[1];
    surge_zeta.insert(
        "rayleigh_beta_only".to_string(),
        beta_only * surge.row(Law::Rayleigh)[1],
    );
    surge_zeta.insert(
        "rayleigh_alpha_only".to_string(),
        alpha_only * surge.row(Law::Rayleigh)[0],
    );
    surge_zeta.insert("hysteretic".to_string(), zeta);
    surge_zeta.insert("external_viscous".to_string(), 0.0);
    let _ = candidates;
    let (r2, q2, n2) = [1.5, 2.0, 3.0]
        .iter()
        .map(|&ratio| {
            let r = (m_eff(base.mass_kg * ratio) / m_eff(base.mass_kg)).powf(-0.5);
            (ratio, r, repeats_needed(1.0 - r, settings.scatter))
        })
        .nth(1)
        .unwrap_or((2.0, 0.7, 1));
    let text = format!(
        "A second attached mass separates the hysteretic law (zeta independent of the mass) from \
         the viscous ones (zeta falls as m_eff^-1/2): at {r2} times the mass ({:.2} kg) a viscous law \
         gives {q2:.3} times the zeta, {:.1} % lower; against a repeat scatter of {:.0} % that needs \
         {n2} decay test(s) per mass. No mass ratio separates beta from a dashpot at the weight \
         (both give zeta proportional to w for the weight mode: a dashpot across a massless spring \
         is a dashpot to ground). The surge mode does: hold the weight and record the coil's own \
         first axial mode at mid-coil ({:.1} Hz): beta alone predicts zeta = {:.4}, alpha alone {:.4}, \
         the hysteretic law {:.5}, a dashpot at the weight 0.",
        base.mass_kg * r2,
        100.0 * (1.0 - q2),
        100.0 * settings.scatter,
        surge.omega_rad_s / std::f64::consts::TAU,
        surge_zeta["rayleigh_beta_only"],
        surge_zeta["rayleigh_alpha_only"],
        zeta
    );
    Ok(DecidingTest {
        scatter: settings.scatter,
        second_mass,
        surge_frequency_hz: surge.omega_rad_s / std::f64::consts::TAU,
        surge_zeta,
        text,
    })
}

/// damping.json (the spec's fields first, then the evidence).
pub fn report_json(r: &DampingReport) -> serde_json::Value {
    let candidates: Vec<serde_json::Value> = r
        .candidates
        .iter()
        .map(|c| {
            serde_json::json!({
                "law": c.law.name(),
                "parameters": c.parameters,
                "parameters_se": c.parameters_se,
                "parameters_identified": c.parameters_identified,
                "residual_rms": c.residual_rms,
                "chi2": c.chi2,
                "bic": c.bic,
                "held_out": c.held_out,
                "consistent": c.consistent,
                "predicted_damping_ratio": c.predicted,
            })
        })
        .collect();
    serde_json::json!({
        "law": r.law.map(Law::name),
        "parameters": r.parameters,
        "parameters_se": r.parameters_se,
        "identifiable": r.identifiable,
        "candidates": candidates,
        "reason": r.reason,
        "case": r.case,
        "records": r.records,
        "table4": r.table4,
        "deciding_test": r.deciding_test,
        "band": r.band,
    })
}

/// A terminal summary.
pub fn summary(r: &DampingReport) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    for rec in &r.records {
        let _ = writeln!(
            s,
            "record {} ({:?}, {:.3} kg): f = {:.4} Hz, zeta = {:.6} +- {:.6}",
            rec.name(),
            rec.mode,
            rec.mass_kg,
            rec.frequency_hz,
            rec.damping_ratio,
            rec.damping_ratio_se
        );
    }
    for c in &r.candidates {
        let _ = writeln!(
            s,
            "  {:17} chi2 {:10.2} BIC {:10.2} held-out {:>9} {}  {}",
            c.law.name(),
            c.chi2,
            c.bic,
            c.held_out_text(),
            if c.consistent {
                "consistent  "
            } else {
                "inconsistent"
            },
            c.parameters_text()
        );
    }
    let _ = writeln!(
        s,
        "law: {} ({})",
        r.law.map_or("null (not identifiable)", Law::name),
        r.reason
    );
    for v in &r.table4 {
        let laws: Vec<String> = v
            .by_law
            .iter()
            .map(|(k, z)| format!("{k} {z:.5}"))
            .collect();
        let _ = writeln!(
            s,
            "  {:4} {}{}  spread {:.1}%",
            v.name,
            laws.join("  "),
            match (v.damping_ratio, v.damping_ratio_se) {
                (Some(z), Some(e)) => format!("  chosen {z:.5} +- {e:.5}"),
                _ => String::new(),
            },
            v.spread_percent
        );
    }
    if let Some(t) = &r.deciding_test {
        let _ = writeln!(s, "deciding test: {}", t.text);
    }
    s
}

/// report.md: the records, the candidates, the verdict, Table 4 and the deciding test.
pub fn report_markdown(r: &DampingReport) -> String {
    use std::fmt::Write as _;
    let mut s = format!("# Which damping law? ({})\n\n", r.case);
    s.push_str("| record | mode | mass (kg) | f (Hz) | zeta | se | fit residual |\n|---|---|---:|---:|---:|---:|---:|\n");
    for rec in &r.records {
        let _ = writeln!(
            s,
            "| {} | {:?} | {:.3} | {:.4} | {:.6} | {:.2e} | {:.3} |",
            rec.name(),
            rec.mode,
            rec.mass_kg,
            rec.frequency_hz,
            rec.damping_ratio,
            rec.damping_ratio_se,
            rec.residual_rms
        );
    }
    s.push_str("\n| law | parameters (+- se) | chi2 | BIC | held-out | consistent |\n|---|---|---:|---:|---:|---|\n");
    for c in &r.candidates {
        let _ = writeln!(
            s,
            "| {} | {} | {:.2} | {:.2} | {} | {} |",
            c.law.name(),
            c.parameters_text(),
            c.chi2,
            c.bic,
            c.held_out_text(),
            c.consistent
        );
    }
    let _ = writeln!(
        s,
        "\n**Law: {}.** {}\n",
        r.law.map_or("not identifiable", Law::name),
        r.reason
    );
    if !r.table4.is_empty() {
        s.push_str("| variant | rayleigh | hysteretic | external_viscous | spread | chosen law (+- se) | paper |\n|---|---:|---:|---:|---:|---:|---:|\n");
        for v in &r.table4 {
            let g = |k: &str| {
                v.by_law
                    .get(k)
                    .map_or("-".to_string(), |z| format!("{z:.5}"))
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.1}% | {} | {} |",
                v.name,
                g("rayleigh"),
                g("hysteretic"),
                g("external_viscous"),
                v.spread_percent,
                match (v.damping_ratio, v.damping_ratio_se) {
                    (Some(z), Some(e)) => format!("{z:.5} +- {e:.5}"),
                    _ => "-".to_string(),
                },
                v.paper_damping_ratio
                    .map_or("-".to_string(), |z| format!("{z}"))
            );
        }
    }
    if let Some(b) = &r.band {
        let _ = writeln!(
            s,
            "\n## The band these records allow\n\n{}",
            band_markdown(b)
        );
    }
    if let Some(t) = &r.deciding_test {
        let _ = writeln!(s, "\n## The test that would decide\n\n{}", t.text);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(w: f64, d: f64, p: f64, zeta: f64) -> RecordFit {
        RecordFit {
            file: PathBuf::new(),
            mode: DecayMode::Axial,
            mass_kg: 1.0,
            frequency_hz: w / std::f64::consts::TAU,
            damping_ratio: zeta,
            damping_ratio_se: 1e-6,
            residual_rms: 0.0,
            coefficients: Coefficients {
                omega_rad_s: w,
                wire_share: d,
                weight_participation_per_kg: p,
            },
        }
    }

    /// Constant zeta at two masses: hysteretic, and no viscous law fits.
    #[test]
    fn constant_zeta_over_masses_is_hysteretic() {
        let recs = vec![
            record(27.0, 0.0037, 1.0 / 5.26, 0.00175),
            record(27.0 / 2f64.sqrt(), 0.0019, 1.0 / 10.5, 0.00175),
        ];
        let c: Vec<Candidate> = LAWS
            .iter()
            .filter_map(|&l| fit_law(l, &recs, 0.03))
            .collect();
        let (law, why) = choose(&c, 2);
        assert_eq!(law, Some(Law::Hysteretic), "{why}");
        let h = c.iter().find(|c| c.law == Law::Hysteretic).unwrap();
        assert!((h.parameters["loss_factor"] / 0.0035 - 1.0).abs() < 1e-9);
    }

    /// zeta proportional to w at two masses: beta and the dashpot tie.
    #[test]
    fn viscous_laws_tie_over_masses() {
        let (k, beta) = (3927.5, 1.28e-4);
        let recs: Vec<RecordFit> = [5.26, 10.5]
            .iter()
            .map(|&m: &f64| {
                let w = (k / m).sqrt();
                record(w, 0.0037 * 5.26 / m, 1.0 / m, beta * w / 2.0)
            })
            .collect();
        let c: Vec<Candidate> = LAWS
            .iter()
            .filter_map(|&l| fit_law(l, &recs, 0.03))
            .collect();
        let (law, why) = choose(&c, 2);
        assert_eq!(law, None, "{why}");
        let d = c.iter().find(|c| c.law == Law::ExternalViscous).unwrap();
        assert!((d.parameters["dashpot_n_s_m"] / (beta * k) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn repeats_follow_three_sigma() {
        // 29 % apart, 3 % scatter: one test per mass suffices; 5 % apart: 7.
        assert_eq!(repeats_needed(0.29, 0.03), 1);
        assert_eq!(repeats_needed(0.05, 0.03), 7);
    }
}
