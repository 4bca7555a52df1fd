//! Choosing the cause: four tests every candidate (one effect, or up to three together)
//! must pass, each reported with its numbers, against the reference (the linear model
//! fitted by output error: mass, beta, initial state, and offset and drift for
//! displacement records), so a candidate is credited only with what its effects add.
//!
//! 1. **Significance**, valid for correlated, band-limited residuals. A fitted decay's
//!    residual is not white: a slightly wrong model leaves a smooth misfit, and a record
//!    filtered before it reached us has band-limited noise. The information in `N`
//!    residuals is that of `N_eff` independent ones, from the residual's own
//!    autocorrelation `rho_k` (the variance of a sum of squares of a stationary Gaussian
//!    series is inflated by `1 + 2 sum rho_k^2`; Bartlett 1946, Priestley 1981 section
//!    5.3):
//!    ```text
//!    N_eff = N / (1 + 2 sum_{k=1}^{L} (rho_k^2 - 1/N))
//!    dBIC  = N_eff ln(RSS_reference / RSS_candidate) - (p_candidate - p_reference) ln N_eff
//!    ```
//!    `L` spans [`ACF_PERIODS`] periods of the axial mode (at most `N/4` and
//!    [`MAX_LAGS`]); `1/N`
//!    removes the estimator's own bias. For band-limited white noise of bandwidth `B`
//!    sampled at `fs` this gives `N_eff = 2 B N / fs`, the number of independent
//!    samples the band holds; no noise-floor estimate enters. Passed when
//!    `dBIC > DELTA_BIC` (strong evidence on Kass & Raftery's scale) and the residual
//!    RMS falls below [`RESIDUAL_RATIO`] of the reference's (an effect worth naming).
//! 2. **Forecasts from rolling origins**: fitted on the first quarter, half and three
//!    quarters of the record ([`ORIGINS`]), each model forecasts the next quarter.
//!    Passed when the candidate's forecast RMS is below [`FORECAST_RATIO`] of the
//!    reference's on at least [`FORECASTS_NEEDED`] of the three.
//! 3. **Identified**: the relative standard error of every effect parameter, the fit's
//!    `(J^T J)^-1` error inflated by `sqrt(N / N_eff)`, is at most [`REL_SE_LIMIT`] =
//!    1/3: the parameter stands three standard errors from zero (the effect's presence is
//!    then as certain as a 99.7 % interval makes it, and its magnitude is known within a
//!    factor of two at two standard errors). A model that only mimics another effect
//!    (two modes imitating a frequency drift) fails here with errors many times its
//!    value.
//! 4. **Signature**: each effect's own signature in the records agrees
//!    (`Effect::signature`: friction a constant loss per cycle, drag a loss growing as
//!    `A^2`, a cubic spring a backbone slope of its sign or static curvature, coupling a
//!    second spectral line or a beat).
//!
//! A combination must also **need every part**: removing any one of its effects (the
//! sub-combination is fitted too) must cost more than `DELTA_BIC`, so each effect kept
//! pays for its parameter on the same scale. The cost is the nested comparison on the
//! combination's own `N_eff` (`N_eff ln(RSS_sub / RSS_combination) - dp ln N_eff`,
//! [`nested_delta_bic`]), not the difference of the two models' `dBIC`s: those stand on
//! two `N_eff`s, and a part that lowers the residual by 0.3 % while whitening it
//! (a larger `N_eff`) would otherwise be credited hundreds of BIC units it did not earn.
//!
//! The cause is the passing candidate with the largest `dBIC`; `none` when none
//! passes. Its effects' shares of the explained misfit are the drop-one increases of
//! the residual sum of squares, normalised.

use super::run::{CandidateRun, ModelRun};
use serde::Serialize;

/// Strong evidence on the BIC scale.
pub const DELTA_BIC: f64 = 10.0;
/// The effect must remove at least this share of the linear model's residual RMS.
pub const RESIDUAL_RATIO: f64 = 0.9;
/// ... and forecast better by at least this factor ...
pub const FORECAST_RATIO: f64 = 0.9;
/// ... from this many of the rolling origins.
pub const FORECASTS_NEEDED: usize = 2;
pub use super::run::ORIGINS;
/// Largest relative standard error of an identified parameter.
pub const REL_SE_LIMIT: f64 = 1.0 / 3.0;
/// Axial periods spanned by the autocorrelation sum of `N_eff` ...
pub const ACF_PERIODS: f64 = 20.0;
/// ... and at most this many lags (a bound on the cost, `N` times the lags; 20 periods
/// of a 5 Hz mode at 1 kHz is 4000 lags, whose autocorrelation of a smooth misfit has
/// long settled on the scale that sets `N_eff`).
pub const MAX_LAGS: usize = 1500;

/// One test's outcome, with its number and its limit.
#[derive(Debug, Clone, Serialize)]
pub struct Test {
    /// True when the test held.
    pub passed: bool,
    /// The test's number.
    pub value: f64,
    /// The limit the number is held against.
    pub limit: f64,
    /// The test in words with its numbers, for the report.
    pub text: String,
}

/// The four tests (and, for a combination, the need for every part).
#[derive(Debug, Clone, Serialize)]
pub struct Tests {
    /// Test 1: dBIC and the residual RMS against the reference.
    pub significance: Test,
    /// Test 2: forecasts from the rolling origins against the reference's.
    pub forecasts: Test,
    /// Test 3: every effect parameter's inflated relative standard error.
    pub identified: Test,
    /// Test 4: each effect's own signature in the records.
    pub signature: Test,
    /// For a combination: removing any one of its effects costs more than [`DELTA_BIC`].
    pub every_part_needed: Option<Test>,
}

impl Tests {
    /// True when every test held.
    pub fn passed(&self) -> bool {
        self.significance.passed
            && self.forecasts.passed
            && self.identified.passed
            && self.signature.passed
            && self.every_part_needed.as_ref().is_none_or(|t| t.passed)
    }

    /// Every test held or failed, by name, in report order.
    pub fn each(&self) -> Vec<(&'static str, &Test)> {
        let mut out = vec![
            ("significance", &self.significance),
            ("forecasts", &self.forecasts),
            ("identified", &self.identified),
            ("signature", &self.signature),
        ];
        if let Some(t) = &self.every_part_needed {
            out.push(("every part needed", t));
        }
        out
    }

    /// The names of the tests that failed.
    pub fn failed(&self) -> Vec<&'static str> {
        self.each()
            .into_iter()
            .filter(|(_, t)| !t.passed)
            .map(|(name, _)| name)
            .collect()
    }
}

/// A candidate's standing.
#[derive(Debug, Clone)]
pub struct Score {
    /// BIC gain over the reference on `n_eff` residuals (module docs).
    pub delta_bic: f64,
    /// Effective number of independent residuals `N_eff` (module docs).
    pub n_eff: f64,
    /// Residual and forecast RMS over the reference's.
    pub residual_ratio: f64,
    /// Its forecast RMS of the second halves over the reference's (-).
    pub forecast_ratio: f64,
    /// Each effect parameter's relative standard error, inflated for correlation.
    pub rel_se: Vec<f64>,
    /// The four tests (the parts test is added by [`choose`]).
    pub tests: Tests,
}

/// The decision.
#[derive(Debug, Clone)]
pub struct Choice {
    /// Index of the chosen candidate.
    pub cause: Option<usize>,
    /// Each candidate's score; `None` where its fit failed.
    pub scores: Vec<Option<Score>>,
    /// The chosen candidate's effects (catalogue indices) with their shares, largest
    /// first.
    pub shares: Vec<(usize, f64)>,
}

/// Effective number of independent samples of a residual series (module docs): `lag`
/// is the largest lag summed.
pub fn effective_samples(residual: &[f64], lag: usize) -> f64 {
    let n = residual.len();
    let mean = residual.iter().sum::<f64>() / n.max(1) as f64;
    let x: Vec<f64> = residual.iter().map(|r| r - mean).collect();
    let s0: f64 = x.iter().map(|v| v * v).sum();
    if s0 <= 0.0 || n < 4 {
        return n as f64;
    }
    let lag = lag.clamp(1, n / 4);
    let inv_n = 1.0 / n as f64;
    let products = lagged_products(&x, lag);
    let sum: f64 = products[1..=lag]
        .iter()
        .map(|p| {
            let r = p / s0;
            r * r - inv_n
        })
        .sum();
    (n as f64 / (1.0 + 2.0 * sum.max(0.0))).max(2.0)
}

/// The lagged products `sum_i x_i x_(i+k)` for `k = 0..=lag`, by the FFT of `x`
/// padded with zeros to at least `n + lag` points (so no product wraps around):
/// `|X|^2` transformed back is the autocorrelation, in `O(n log n)` where the direct
/// sums cost `n lag` (1e8 products for 70 000 samples at the 1 500-lag cap). Equal to
/// the direct sums to rounding (`select::tests`).
fn lagged_products(x: &[f64], lag: usize) -> Vec<f64> {
    use rustfft::num_complex::Complex;
    let len = (x.len() + lag + 1).next_power_of_two();
    let mut buffer: Vec<Complex<f64>> = x
        .iter()
        .map(|&v| Complex::new(v, 0.0))
        .chain(std::iter::repeat(Complex::new(0.0, 0.0)))
        .take(len)
        .collect();
    let mut planner = rustfft::FftPlanner::new();
    planner.plan_fft_forward(len).process(&mut buffer);
    buffer
        .iter_mut()
        .for_each(|c| *c = Complex::new(c.norm_sqr(), 0.0));
    planner.plan_fft_inverse(len).process(&mut buffer);
    buffer[..=lag].iter().map(|c| c.re / len as f64).collect()
}

fn residual(run: &ModelRun, measured: &[f64]) -> Vec<f64> {
    run.full
        .simulated
        .iter()
        .zip(measured)
        .map(|(s, m)| s - m)
        .collect()
}

/// What the scoring reads beyond the candidates.
pub struct Context<'a> {
    /// The reference the candidates are scored against.
    pub reference: &'a ModelRun,
    /// The records laid end to end, as fitted.
    pub measured: &'a [f64],
    /// Samples per axial period.
    pub samples_per_period: f64,
}

/// Scores one candidate against the reference (the four tests; the parts test is
/// added by [`choose`]).
pub fn score(ctx: &Context<'_>, candidate: &CandidateRun) -> Option<Score> {
    let run = candidate.run.as_ref().ok()?;
    let reference = ctx.reference;
    let n = ctx.measured.len() as f64;
    let lag = ((ACF_PERIODS * ctx.samples_per_period).ceil() as usize).min(MAX_LAGS);
    let n_eff = effective_samples(&residual(run, ctx.measured), lag);
    let extra = run.full.n_params as f64 - reference.full.n_params as f64;
    let delta_bic = n_eff * (reference.full.rss / run.full.rss).ln() - extra * n_eff.ln();
    let residual_ratio = run.residual_rms / reference.residual_rms;
    let forecast_ratio = run.forecast_rms / reference.forecast_rms;
    let significance = Test {
        passed: delta_bic > DELTA_BIC && residual_ratio < RESIDUAL_RATIO,
        value: delta_bic,
        limit: DELTA_BIC,
        text: format!(
            "dBIC {delta_bic:.1} on N_eff = {n_eff:.0} of {n:.0} residuals (limit {DELTA_BIC}); \
             residual RMS {residual_ratio:.3} of the linear model's (limit {RESIDUAL_RATIO})"
        ),
    };
    let ratios: Vec<f64> = run
        .rolling
        .iter()
        .zip(&reference.rolling)
        .map(|(c, r)| c / r)
        .collect();
    let better = ratios.iter().filter(|r| **r < FORECAST_RATIO).count();
    let forecasts = Test {
        passed: better >= FORECASTS_NEEDED,
        value: better as f64,
        limit: FORECASTS_NEEDED as f64,
        text: format!(
            "forecast RMS over the linear model's from origins at {}: {} ({} of {} below \
             {FORECAST_RATIO}, {FORECASTS_NEEDED} needed)",
            ORIGINS
                .iter()
                .map(|o| format!("{o}"))
                .collect::<Vec<_>>()
                .join(", "),
            ratios
                .iter()
                .map(|r| format!("{r:.3}"))
                .collect::<Vec<_>>()
                .join(", "),
            better,
            ratios.len()
        ),
    };
    let inflate = (n / n_eff).sqrt();
    let rel_se: Vec<f64> = candidate
        .effects
        .iter()
        .map(|&i| {
            run.full
                .knobs
                .iter()
                .position(|k| *k == super::fit::Knob::Effect(i))
                .map_or(f64::NAN, |j| inflate * run.full.knob_rel_errors[j])
        })
        .collect();
    let worst = rel_se.iter().fold(
        0.0_f64,
        |m, x| if x.is_nan() { f64::INFINITY } else { m.max(*x) },
    );
    let identified = Test {
        passed: worst <= REL_SE_LIMIT,
        value: worst,
        limit: REL_SE_LIMIT,
        text: format!(
            "relative standard error {} (inflated by sqrt(N/N_eff) = {inflate:.2}; limit {:.3})",
            candidate
                .effects
                .iter()
                .zip(&rel_se)
                .map(|(&i, se)| {
                    let parameter = super::effects::CATALOGUE[i].parameter();
                    if se.is_finite() {
                        format!("{parameter} {se:.3}")
                    } else {
                        format!("{parameter} not defined (at its bound or not identifiable)")
                    }
                })
                .collect::<Vec<_>>()
                .join(", "),
            REL_SE_LIMIT
        ),
    };
    let checks = &candidate.signatures;
    let signature = Test {
        passed: checks.iter().all(|c| c.passed),
        value: checks.iter().map(|c| c.value).fold(f64::INFINITY, f64::min),
        limit: checks.iter().map(|c| c.limit).fold(0.0, f64::max),
        text: checks
            .iter()
            .map(|c| c.text.clone())
            .collect::<Vec<_>>()
            .join("; "),
    };
    Some(Score {
        delta_bic,
        n_eff,
        residual_ratio,
        forecast_ratio,
        rel_se,
        tests: Tests {
            significance,
            forecasts,
            identified,
            signature,
            every_part_needed: None,
        },
    })
}

/// The BIC gain of `larger` over the nested `smaller` on `n_eff` residuals, the
/// larger model's (module docs, the parts test): both sides on one scale, so a part
/// that barely lowers the residual cannot borrow evidence from a larger `N_eff`.
pub fn nested_delta_bic(
    n_eff: f64,
    smaller: &super::fit::Fitted,
    larger: &super::fit::Fitted,
) -> f64 {
    let extra = larger.n_params as f64 - smaller.n_params as f64;
    n_eff * (smaller.rss / larger.rss).ln() - extra * n_eff.ln()
}

/// Scores every candidate, adds the parts test to combinations and picks the cause.
pub fn choose(ctx: &Context<'_>, candidates: &[CandidateRun]) -> Choice {
    let mut scores: Vec<Option<Score>> = candidates.iter().map(|c| score(ctx, c)).collect();
    let rss = |i: usize| candidates[i].run.as_ref().map_or(f64::NAN, |r| r.full.rss);
    let find = |set: &[usize]| candidates.iter().position(|c| c.effects == set);
    // Drop-one sub-combinations of every combination.
    for i in 0..candidates.len() {
        let set = &candidates[i].effects;
        if set.len() < 2 || scores[i].is_none() {
            continue;
        }
        let n_eff = scores[i].as_ref().map_or(f64::NAN, |s| s.n_eff);
        let full = candidates[i].run.as_ref().ok().map(|r| &r.full);
        let mut costs = Vec::new();
        for &drop in set {
            let sub: Vec<usize> = set.iter().copied().filter(|&e| e != drop).collect();
            let sub_full = find(&sub).and_then(|j| candidates[j].run.as_ref().ok());
            let cost = match (full, sub_full) {
                (Some(f), Some(s)) => nested_delta_bic(n_eff, &s.full, f),
                // A sub-combination whose fit failed explains nothing: the part is needed.
                _ => f64::INFINITY,
            };
            costs.push((drop, cost));
        }
        let least = costs.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
        if let Some(s) = scores[i].as_mut() {
            s.tests.every_part_needed = Some(Test {
                passed: least > DELTA_BIC,
                value: least,
                limit: DELTA_BIC,
                text: format!(
                    "dBIC lost by removing each effect: {} (each above {DELTA_BIC})",
                    costs
                        .iter()
                        .map(|(e, c)| format!("{} {c:.1}", super::effects::CATALOGUE[*e].name()))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            });
        }
    }
    let cause = scores
        .iter()
        .enumerate()
        .filter_map(|(i, s)| {
            s.as_ref()
                .filter(|s| s.tests.passed())
                .map(|s| (i, s.delta_bic))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i);
    let shares = cause.map_or(Vec::new(), |i| {
        let set = &candidates[i].effects;
        if set.len() == 1 {
            return vec![(set[0], 1.0)];
        }
        let gains: Vec<(usize, f64)> = set
            .iter()
            .map(|&drop| {
                let sub: Vec<usize> = set.iter().copied().filter(|&e| e != drop).collect();
                let gain = find(&sub).map_or(0.0, |j| (rss(j) - rss(i)).max(0.0));
                (drop, gain)
            })
            .collect();
        let total: f64 = gains.iter().map(|g| g.1).sum();
        let mut shares: Vec<(usize, f64)> = gains
            .into_iter()
            .map(|(e, g)| {
                (
                    e,
                    if total > 0.0 {
                        g / total
                    } else {
                        1.0 / set.len() as f64
                    },
                )
            })
            .collect();
        shares.sort_by(|a, b| b.1.total_cmp(&a.1));
        shares
    });
    Choice {
        cause,
        scores,
        shares,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        }
    }

    #[test]
    fn white_noise_keeps_its_samples_and_a_smooth_misfit_loses_them() {
        let mut r = lcg(3);
        let white: Vec<f64> = (0..10_000).map(|_| r()).collect();
        let smooth: Vec<f64> = (0..10_000).map(|i| (i as f64 * 1e-2).sin()).collect();
        assert!(effective_samples(&white, 500) > 8_000.0);
        assert!(effective_samples(&smooth, 2_000) < 100.0);
    }

    #[test]
    fn the_lagged_products_by_fft_are_the_direct_sums() {
        let mut r = lcg(5);
        let x: Vec<f64> = (0..3_001).map(|i| r() + (i as f64 * 0.05).sin()).collect();
        let fast = lagged_products(&x, 700);
        let scale: f64 = x.iter().map(|v| v * v).sum();
        for (k, p) in fast.iter().enumerate() {
            let direct: f64 = x[..x.len() - k]
                .iter()
                .zip(&x[k..])
                .map(|(a, b)| a * b)
                .sum();
            // Rounding of sums over 3 000 products and a 4 096-point FFT: 1e-13 of the
            // zero lag's sum.
            assert!(
                (p - direct).abs() < 1e-13 * scale,
                "lag {k}: {p} vs {direct}"
            );
        }
    }

    #[test]
    fn band_limited_noise_counts_the_samples_its_band_holds() {
        // White noise through a moving average of 8 samples: bandwidth about fs/16, so
        // N_eff should be near N/8 (the estimator of the sum of rho^2 for an MA(7)
        // process: 1 + 2 sum rho_k^2 = (2 m^2 + 1)/(3 m) = 5.4 for m = 8, N_eff = N/5.4).
        let mut r = lcg(11);
        let white: Vec<f64> = (0..40_007).map(|_| r()).collect();
        let band: Vec<f64> = white.windows(8).map(|w| w.iter().sum::<f64>()).collect();
        let n = band.len() as f64;
        let ratio = n / effective_samples(&band, 400);
        let expected = (2.0 * 64.0 + 1.0) / 24.0;
        assert!(
            (ratio / expected - 1.0).abs() < 0.1,
            "{ratio} vs {expected}"
        );
    }
}
