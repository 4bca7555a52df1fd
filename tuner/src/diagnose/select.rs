//! Choosing the cause: an information criterion that charges for the extra parameter,
//! the held-out forecast, and a practical-size test.
//!
//! Residuals of a fitted decay are not independent (a slightly wrong model leaves a
//! smooth, correlated misfit), so the Bayesian information criterion is taken on the
//! effective number of independent residuals, `N_eff = N (1 - rho)/(1 + rho)` with
//! `rho` the lag-one autocorrelation of the candidate's residual (the AR(1) variance
//! inflation; Bayley & Hammersley 1946). With `RSS` the sum of squared residuals and `p`
//! the fitted parameters,
//! ```text
//! BIC = N_eff ln(RSS / N) + p ln N_eff,     dBIC = BIC_reference - BIC_candidate.
//! ```
//! The reference is the linear model fitted by output error (mass, beta, initial
//! state), so a candidate is credited only with what its effect adds. A candidate is
//! **significant** when
//! - `dBIC > DELTA_BIC` (strong evidence on Kass & Raftery's scale),
//! - its residual RMS is below `RESIDUAL_RATIO` of the reference's, and
//! - its forecast of the second half (fitted on the first) is below `FORECAST_RATIO`
//!   of the reference's forecast.
//!
//! The cause is the significant candidate with the largest `dBIC`; `none` when there
//! is none.

use super::effects::{Effect, Proposal};
use super::ModelRun;

/// Strong evidence on the BIC scale.
pub const DELTA_BIC: f64 = 10.0;
/// The effect must remove at least this share of the linear model's residual RMS.
pub const RESIDUAL_RATIO: f64 = 0.9;
/// ... and forecast better by at least this factor.
pub const FORECAST_RATIO: f64 = 0.9;

/// A candidate's standing.
#[derive(Debug, Clone, Copy)]
pub struct Score {
    pub delta_bic: f64,
    pub n_eff: f64,
    /// Residual and forecast RMS over the reference's.
    pub residual_ratio: f64,
    pub forecast_ratio: f64,
    pub significant: bool,
}

/// The decision.
#[derive(Debug, Clone)]
pub struct Choice {
    /// Index of the chosen candidate.
    pub cause: Option<usize>,
    pub scores: Vec<Option<Score>>,
}

/// Effective number of independent samples of a residual series.
pub fn effective_samples(residual: &[f64]) -> f64 {
    let n = residual.len() as f64;
    let s0: f64 = residual.iter().map(|x| x * x).sum();
    if s0 <= 0.0 {
        return n;
    }
    let s1: f64 = residual.windows(2).map(|w| w[0] * w[1]).sum();
    let rho = (s1 / s0).clamp(0.0, 0.999);
    (n * (1.0 - rho) / (1.0 + rho)).max(2.0)
}

fn residual(run: &ModelRun, measured: &[f64]) -> Vec<f64> {
    run.full
        .simulated
        .iter()
        .zip(measured)
        .map(|(s, m)| s - m)
        .collect()
}

/// Scores every candidate against the reference and picks the cause.
pub fn choose(
    reference: &ModelRun,
    candidates: &[(&dyn Effect, Proposal, Result<ModelRun, String>)],
    measured: &[f64],
) -> Choice {
    let n = measured.len() as f64;
    let scores: Vec<Option<Score>> = candidates
        .iter()
        .map(|(_, _, run)| {
            let run = run.as_ref().ok()?;
            let n_eff = effective_samples(&residual(run, measured));
            let bic = |rss: f64, p: usize| n_eff * (rss / n).ln() + p as f64 * n_eff.ln();
            let delta_bic = bic(reference.full.rss, reference.full.n_params)
                - bic(run.full.rss, run.full.n_params);
            let residual_ratio = run.residual_rms / reference.residual_rms;
            let forecast_ratio = run.forecast_rms / reference.forecast_rms;
            Some(Score {
                delta_bic,
                n_eff,
                residual_ratio,
                forecast_ratio,
                significant: delta_bic > DELTA_BIC
                    && residual_ratio < RESIDUAL_RATIO
                    && forecast_ratio < FORECAST_RATIO,
            })
        })
        .collect();
    let cause = scores
        .iter()
        .enumerate()
        .filter_map(|(i, s)| s.filter(|s| s.significant).map(|s| (i, s.delta_bic)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i);
    Choice { cause, scores }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_noise_keeps_its_samples_and_a_smooth_misfit_loses_them() {
        // A deterministic white-ish sequence (lag-one correlation near 0) and a slow sine
        // (lag-one correlation near 1).
        let white: Vec<f64> = (0..10_000u64)
            .map(|i| ((i.wrapping_mul(2654435761) % 1000) as f64 / 500.0) - 1.0)
            .collect();
        let smooth: Vec<f64> = (0..10_000).map(|i| (i as f64 * 1e-3).sin()).collect();
        assert!(effective_samples(&white) > 8_000.0);
        assert!(effective_samples(&smooth) < 10.0);
    }
}
