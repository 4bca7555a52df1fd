//! The shape of the envelope: exponential, linear or beating.
//!
//! # Formulation
//!
//! Three fits of the per-cycle amplitudes, weighted by `1 / se^2`, each with its `R^2`:
//! `ln A = c - sigma t` (viscous, exponential), `A = c - r t` (Coulomb, linear) and a beat
//! model. The beat model is a quadratic trend in `t` plus a sinusoid at `f_b` and its second
//! harmonic; `f_b` is scanned from `1.5 / T_record` (at least one and a half beats) to
//! 0.45 times the cycle rate, 10 points per Rayleigh resolution `1 / T_record`, refined by a
//! parabola. Decision rule: **Beating** when, at the best `f_b`, adding the sinusoid cuts the
//! weighted residual of the quadratic trend by at least 4 ([`BEAT_VARIANCE_RATIO`]) in each of
//! `ln A`, `A` and `1 / A` (in one of these every monotone decay of the catalogue is nearly a
//! quadratic in `t`, so a smooth bend is never read as a beat) and the modulation depth (the
//! amplitude of the fundamental term in `ln A`) is at least 5% ([`BEAT_MIN_DEPTH`]);
//! otherwise **Exponential** when the exponential fit leaves the smaller weighted residual,
//! else **Linear**. Quadratic damping (`A = A_0 / (1 + a_2 A_0 n)`) is told apart by the loss
//! fit, not here.
//!
//! # Units and signs
//! The input is the axial acceleration of the weight in m/s^2 (`decay.csv`, see
//! `docs/measured-case.md`); every displacement amplitude here is in metres (SI), so
//! that the conversions below take `k` in N/m and `m` in kg. Times in s, frequencies in Hz.

use serde::Serialize;
use std::f64::consts::TAU;

use super::cycles::Cycle;
use crate::error::{PostError, Result};
use crate::fit::least_squares;

/// Beat decision: the sinusoid must cut the trend's residual to this fraction or less.
pub const BEAT_VARIANCE_RATIO: f64 = 0.25;

/// Beat decision: the smallest modulation depth (amplitude of the fundamental in `ln A`).
pub const BEAT_MIN_DEPTH: f64 = 0.05;

/// What the envelope looks like.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EnvelopeKind {
    /// `ln A` linear in time: viscous damping.
    Exponential,
    /// `A` linear in time: dry friction.
    Linear,
    /// Periodic envelope minima: two close modes exchanging energy.
    Beating,
}

/// Result of [`envelope_shape`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EnvelopeShape {
    /// What the envelope looks like.
    pub kind: EnvelopeKind,
    /// `R^2` (weighted, in `A`) of `ln A = c - sigma t`.
    pub r2_exponential: f64,
    /// `R^2` of `A = c - r t`.
    pub r2_linear: f64,
    /// `R^2` of the best beat model (quadratic trend plus sinusoid), if scanned.
    pub r2_beating: Option<f64>,
    /// `sigma` of the exponential fit, 1/s.
    pub decay_rate_per_s: f64,
    /// `r` of the linear fit, m/s.
    pub loss_rate_m_per_s: f64,
    /// Period of the best beat candidate, s.
    pub beat_candidate_period_s: Option<f64>,
    /// Largest (over `ln A`, `A`, `1/A`) ratio of the residual with the sinusoid to the
    /// residual of the trend alone.
    pub beat_variance_ratio: Option<f64>,
    /// Amplitude of the candidate's fundamental in `ln A`.
    pub modulation_depth: Option<f64>,
    /// The beat period when `kind` is `Beating`, s.
    pub beat_period_s: Option<f64>,
    /// Record length covered by the cycles, s.
    pub duration_s: f64,
}

/// Fewest cycles for the beat scan (a 7-parameter model with a meaningful residual).
pub const MIN_BEAT_CYCLES: usize = 16;

/// Classifies the envelope (see the module doc for the rule).
pub fn envelope_shape(cycles: &[Cycle]) -> Result<EnvelopeShape> {
    let n = cycles.len();
    if n < 4 {
        return Err(PostError::TooFewPoints {
            what: "envelope shape",
            found: n,
            needed: 4,
            hint: "a longer record".to_string(),
        });
    }
    let t: Vec<f64> = cycles.iter().map(|c| c.time_s).collect();
    let a: Vec<f64> = cycles.iter().map(|c| c.amplitude_m).collect();
    let floor = 1e-12 * a.iter().copied().fold(0.0, f64::max);
    let w: Vec<f64> = cycles
        .iter()
        .map(|c| c.amplitude_std_error_m.max(floor).powi(-2))
        .collect();
    let t_mid = 0.5 * (t[0] + t[n - 1]);
    let duration_s = cycles[n - 1].end_s - cycles[0].start_s;
    let tau: Vec<f64> = t.iter().map(|t| (t - t_mid) / duration_s).collect();
    let total: f64 = w.iter().sum();
    let mean = a.iter().zip(&w).map(|(a, w)| a * w).sum::<f64>() / total;
    let sst: f64 = a.iter().zip(&w).map(|(a, w)| w * (a - mean).powi(2)).sum();
    let r2 = |predicted: &[f64]| {
        let ss: f64 = a
            .iter()
            .zip(predicted)
            .zip(&w)
            .map(|((a, p), w)| w * (a - p).powi(2))
            .sum();
        (1.0 - ss / sst, ss)
    };
    let unidentifiable = || PostError::Unidentifiable {
        what: "the envelope shape",
        why: "the cycles' times do not spread".to_string(),
    };
    let line: Vec<Vec<f64>> = tau.iter().map(|&x| vec![1.0, x]).collect();

    let ln_a: Vec<f64> = a.iter().map(|a| a.ln()).collect();
    let w_ln: Vec<f64> = a.iter().zip(&w).map(|(a, w)| w * a * a).collect();
    let exponential = least_squares(&line, &ln_a, &w_ln).ok_or_else(unidentifiable)?;
    let predicted: Vec<f64> = tau
        .iter()
        .map(|x| (exponential[0] + exponential[1] * x).exp())
        .collect();
    let (r2_exponential, ss_exponential) = r2(&predicted);
    let linear = least_squares(&line, &a, &w).ok_or_else(unidentifiable)?;
    let predicted: Vec<f64> = tau.iter().map(|x| linear[0] + linear[1] * x).collect();
    let (r2_linear, ss_linear) = r2(&predicted);

    let mut shape = EnvelopeShape {
        kind: if ss_exponential <= ss_linear {
            EnvelopeKind::Exponential
        } else {
            EnvelopeKind::Linear
        },
        r2_exponential,
        r2_linear,
        r2_beating: None,
        decay_rate_per_s: -exponential[1] / duration_s,
        loss_rate_m_per_s: -linear[1] / duration_s,
        beat_candidate_period_s: None,
        beat_variance_ratio: None,
        modulation_depth: None,
        beat_period_s: None,
        duration_s,
    };
    if n < MIN_BEAT_CYCLES {
        return Ok(shape);
    }
    // Beat scan in ln A; frequencies in cycles per record length.
    let cycle_rate = n as f64 / duration_s;
    let (low, high) = (1.5, 0.45 * cycle_rate * duration_s);
    if high <= low {
        return Ok(shape);
    }
    let residual_at = |z: &[f64], weights: &[f64], beats: f64| beat_fit(&tau, z, weights, beats);
    let grid_step = 0.1;
    let count = ((high - low) / grid_step).floor() as usize + 1;
    let scores: Vec<f64> = (0..count)
        .map(|j| {
            residual_at(&ln_a, &w_ln, low + j as f64 * grid_step)
                .map_or(f64::INFINITY, |fit| fit.beat_residual)
        })
        .collect();
    let Some(best) = (0..count).min_by(|&i, &j| scores[i].total_cmp(&scores[j])) else {
        return Ok(shape);
    };
    let mut beats = low + best as f64 * grid_step;
    if best > 0 && best + 1 < count {
        let (l, c, r) = (scores[best - 1], scores[best], scores[best + 1]);
        let curvature = l - 2.0 * c + r;
        if curvature > 0.0 && curvature.is_finite() {
            beats += grid_step * 0.5 * (l - r) / curvature;
        }
    }
    let Some(in_log) = residual_at(&ln_a, &w_ln, beats) else {
        return Ok(shape);
    };
    let w_inverse: Vec<f64> = a.iter().zip(&w).map(|(a, w)| w * a.powi(4)).collect();
    let inverse: Vec<f64> = a.iter().map(|a| 1.0 / a).collect();
    let ratio_of = |fit: Option<BeatFit>| {
        fit.map_or(f64::INFINITY, |fit| fit.beat_residual / fit.trend_residual)
    };
    let ratio = (in_log.beat_residual / in_log.trend_residual)
        .max(ratio_of(residual_at(&a, &w, beats)))
        .max(ratio_of(residual_at(&inverse, &w_inverse, beats)));
    let predicted: Vec<f64> = in_log.predicted.iter().map(|z| z.exp()).collect();
    let period = duration_s / beats;
    shape.r2_beating = Some(r2(&predicted).0);
    shape.beat_candidate_period_s = Some(period);
    shape.beat_variance_ratio = Some(ratio);
    shape.modulation_depth = Some(in_log.depth);
    if ratio <= BEAT_VARIANCE_RATIO && in_log.depth >= BEAT_MIN_DEPTH {
        shape.kind = EnvelopeKind::Beating;
        shape.beat_period_s = Some(period);
    }
    Ok(shape)
}

#[derive(Clone)]
struct BeatFit {
    trend_residual: f64,
    beat_residual: f64,
    depth: f64,
    predicted: Vec<f64>,
}

/// Weighted fits of `z` by a quadratic in `tau` and by the quadratic plus a sinusoid of
/// `beats` periods per unit `tau` and its second harmonic.
fn beat_fit(tau: &[f64], z: &[f64], w: &[f64], beats: f64) -> Option<BeatFit> {
    let residual = |basis: &[Vec<f64>], c: &[f64]| -> (f64, Vec<f64>) {
        let predicted: Vec<f64> = basis
            .iter()
            .map(|row| row.iter().zip(c).map(|(x, c)| x * c).sum())
            .collect();
        let ss = predicted
            .iter()
            .zip(z)
            .zip(w)
            .map(|((p, z), w)| w * (z - p).powi(2))
            .sum();
        (ss, predicted)
    };
    let trend: Vec<Vec<f64>> = tau.iter().map(|&x| vec![1.0, x, x * x]).collect();
    let c = least_squares(&trend, z, w)?;
    let (trend_residual, _) = residual(&trend, &c);
    let full: Vec<Vec<f64>> = tau
        .iter()
        .map(|&x| {
            let (s1, c1) = (TAU * beats * x).sin_cos();
            let (s2, c2) = (2.0 * TAU * beats * x).sin_cos();
            vec![1.0, x, x * x, c1, s1, c2, s2]
        })
        .collect();
    let c = least_squares(&full, z, w)?;
    let (beat_residual, predicted) = residual(&full, &c);
    Some(BeatFit {
        trend_residual,
        beat_residual,
        depth: c[3].hypot(c[4]),
        predicted,
    })
}
