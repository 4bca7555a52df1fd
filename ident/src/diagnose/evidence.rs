//! The records' signatures the diagnosis reads (what the linear model misses), gathered
//! from the post-processor's analyses (`coil_postproc::signature`, `static_curve`).

use serde::Serialize;

/// Per-cycle amplitude loss `dA = a0 + a1 A + a2 A^2` (A displacement amplitude, m).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct LossSummary {
    /// Constant loss per cycle `a0` (m): dry friction.
    pub a0_m: f64,
    /// Standard error of `a0` (m).
    pub a0_se: f64,
    /// Loss proportional to the amplitude, `a1` (-): viscous damping.
    pub a1: f64,
    /// Standard error of `a1` (-).
    pub a1_se: f64,
    /// Loss growing as `A^2`, `a2` (1/m): quadratic drag.
    pub a2_per_m: f64,
    /// Standard error of `a2` (1/m).
    pub a2_se: f64,
    /// `a0` over its standard error in the two-term fit `a0 + a1 A` (NaN if singular).
    pub a0_two_term_z: f64,
    /// `a2` over its standard error in the two-term fit `a1 A + a2 A^2` (NaN if singular).
    pub a2_two_term_z: f64,
}

impl LossSummary {
    /// How many standard errors the constant (friction) term stands from zero: the
    /// three-term fit's, or, when the drag term is not itself evident (not a positive
    /// loss above `limit` standard errors: a negative `a2` is no drag), the two-term
    /// fit's, whose error is not widened by the drag column.
    pub fn friction_z(&self, limit: f64) -> f64 {
        let three = self.a0_m / self.a0_se;
        if self.a2_per_m / self.a2_se < limit {
            three.max(self.a0_two_term_z)
        } else {
            three
        }
    }

    /// The same for the drag term `a2`, with the friction term left out when it is not
    /// evident.
    pub fn drag_z(&self, limit: f64) -> f64 {
        let three = self.a2_per_m / self.a2_se;
        if self.a0_m / self.a0_se < limit {
            three.max(self.a2_two_term_z)
        } else {
            three
        }
    }
}

/// Backbone `f^2 = f0^2 (1 + b A^2)` and the cubic stiffness it implies.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct BackboneSummary {
    /// Small-amplitude (damped) frequency `f0` (Hz).
    pub f0_hz: f64,
    /// Backbone slope `b` (1/m^2).
    pub b_per_m2: f64,
    /// Standard error of `b` (1/m^2).
    pub b_se: f64,
    /// The cubic stiffness `b` implies about the gravity preload (N/m^3); NaN when none can.
    pub k3_n_m3: f64,
}

/// Envelope shape.
#[derive(Debug, Clone, Serialize)]
pub struct EnvelopeSummary {
    /// `exponential`, `linear` or `beating`.
    pub kind: String,
    /// `R^2` of the exponential envelope `ln A = c - sigma t` (-); NaN when no envelope was fitted.
    pub r2_exponential: f64,
    /// `R^2` of the linear envelope `A = c - r t` (-); NaN when no envelope was fitted.
    pub r2_linear: f64,
    /// The beat period when `kind` is `beating` (s).
    pub beat_period_s: Option<f64>,
}

/// A second spectral line beside the axial one.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct PeakSummary {
    /// The line's frequency (Hz).
    pub frequency_hz: f64,
    /// Its amplitude over the axial line's.
    pub relative_amplitude: f64,
    /// Its relative amplitude over the detection threshold (2 % of the axial line).
    pub z_score: f64,
}

/// The static record's fits.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct StaticSummary {
    /// Stiffness of the straight line `F = k x + s F_f` through both branches (N/mm).
    pub linear_k_n_mm: f64,
    /// `F = k x + k3 x^3 + s Ff` (s = +1 loading, -1 unloading).
    pub k_n_mm: f64,
    /// The cubic coefficient `k3` (N/m^3).
    pub k3_n_m3: f64,
    /// Standard error of `k3` (N/m^3).
    pub k3_se: f64,
    /// The hysteresis half-width `Ff`, a friction force (N); 0 when the fit has none.
    pub friction_n: f64,
    /// Standard error of `Ff` (N); infinite when the fit has no hysteresis term.
    pub friction_se: f64,
    /// Residual RMS of the straight line and of the cubic fit with hysteresis (N).
    pub linear_rms_n: f64,
    /// Residual RMS of the cubic fit with hysteresis (N).
    pub cubic_rms_n: f64,
}

/// One cycle of the band-passed axial mode.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct CycleSummary {
    /// The cycle's centre time (s).
    pub time_s: f64,
    /// Its displacement amplitude (m).
    pub amplitude_m: f64,
    /// Its frequency, one over the time between its bounding upward zero crossings (Hz).
    pub frequency_hz: f64,
}

/// Everything the effects read.
#[derive(Debug, Clone, Serialize)]
pub struct Signatures {
    /// Frequency of the axial spectral line (Hz).
    pub axial_hz: f64,
    /// Robust estimate of the record's white noise (m/s^2; from the median absolute
    /// fourth difference, `coil_postproc::signature::cycles`; NaN if no cycles were
    /// found).
    pub noise_rms_m_s2: f64,
    /// Axial cycles the record spans: the axial frequency times the record's duration (-).
    pub cycles: f64,
    /// The loss per cycle: the windowed fit over cycles, or on a record too short for
    /// it the half-cycle fit (`half_cycle_loss`); `None` when neither can be formed.
    pub loss: Option<LossSummary>,
    /// The loss per cycle from every crest's amplitude (`halfcycle`: 16 points on 8
    /// cycles, standard errors from their scatter); `None` below 8 crests.
    pub half_cycle_loss: Option<LossSummary>,
    /// The backbone; `None` when it cannot be identified.
    pub backbone: Option<BackboneSummary>,
    /// The envelope's shape.
    pub envelope: EnvelopeSummary,
    /// A second spectral line beside the axial one, when the spectrum shows one.
    pub second_peak: Option<PeakSummary>,
    /// The static record's fits, when the case has a static record.
    pub statics: Option<StaticSummary>,
    /// Every cycle of the band-passed axial mode (not serialised).
    #[serde(skip)]
    pub per_cycle: Vec<CycleSummary>,
}

/// A linear least-squares fit `y = X c` with outlying rows removed: rows whose residual
/// exceeds [`CLIP_SIGMAS`] robust standard deviations (1.4826 times the median
/// absolute residual) are dropped and the fit repeated, twice. Returns the coefficients
/// and their standard errors (`s^2 (X^T X)^-1`), or `None` when fewer than three rows
/// per coefficient remain or `X^T X` is singular.
///
/// Why: per-cycle frequencies and amplitudes inherit every glitch of the record (a
/// position sensor's single-sample spikes, spread over a few cycles by the band-pass),
/// and one such cycle can hide a backbone slope or a loss term that every other cycle
/// shows.
pub fn robust_fit(rows: &[(Vec<f64>, f64)]) -> Option<(Vec<f64>, Vec<f64>)> {
    let p = rows.first()?.0.len();
    let mut keep: Vec<bool> = vec![true; rows.len()];
    let mut out = None;
    for round in 0..3 {
        let used: Vec<&(Vec<f64>, f64)> = rows
            .iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(r, _)| r)
            .collect();
        if used.len() < 3 * p {
            return out;
        }
        let x = nalgebra::DMatrix::from_fn(used.len(), p, |i, j| used[i].0[j]);
        let y = nalgebra::DVector::from_iterator(used.len(), used.iter().map(|r| r.1));
        let xtx = x.transpose() * &x;
        let inv = xtx.try_inverse()?;
        let c = &inv * x.transpose() * &y;
        let resid = &y - &x * &c;
        let s2 = resid.norm_squared() / (used.len() - p) as f64;
        let se: Vec<f64> = (0..p).map(|j| (s2 * inv[(j, j)]).max(0.0).sqrt()).collect();
        out = Some((c.iter().copied().collect(), se));
        if round == 2 {
            break;
        }
        let mut all: Vec<f64> = rows
            .iter()
            .map(|(xr, yr)| (yr - xr.iter().zip(c.iter()).map(|(a, b)| a * b).sum::<f64>()).abs())
            .collect();
        let mut sorted: Vec<f64> = all
            .iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(r, _)| *r)
            .collect();
        sorted.sort_by(f64::total_cmp);
        let sigma = 1.4826 * sorted[sorted.len() / 2];
        if sigma <= 0.0 {
            break;
        }
        for (k, r) in keep.iter_mut().zip(all.drain(..)) {
            *k = r <= CLIP_SIGMAS * sigma;
        }
    }
    out
}

/// Robust standard deviations beyond which a row of [`robust_fit`] is an outlier.
pub const CLIP_SIGMAS: f64 = 3.5;

/// The backbone `f^2 = f0^2 + f0^2 b A^2` refitted over the cycles with outliers
/// removed ([`robust_fit`]): `(b, se(b))` in 1/m^2.
pub fn robust_backbone(cycles: &[CycleSummary]) -> Option<(f64, f64)> {
    let rows: Vec<(Vec<f64>, f64)> = cycles
        .iter()
        .map(|c| {
            (
                vec![1.0, c.amplitude_m * c.amplitude_m],
                c.frequency_hz.powi(2),
            )
        })
        .collect();
    let (c, se) = robust_fit(&rows)?;
    (c[0] > 0.0).then(|| (c[1] / c[0], se[1] / c[0]))
}

/// The loss per cycle `dA = a0 + a1 A + a2 A^2` refitted over successive cycles with
/// outliers removed ([`robust_fit`]; `A` the pair's mean amplitude): the coefficients
/// `[a0 (m), a1, a2 (1/m)]` and their standard errors.
pub fn robust_loss(cycles: &[CycleSummary]) -> Option<(Vec<f64>, Vec<f64>)> {
    let rows: Vec<(Vec<f64>, f64)> = cycles
        .windows(2)
        .map(|w| {
            let a = 0.5 * (w[0].amplitude_m + w[1].amplitude_m);
            (vec![1.0, a, a * a], w[0].amplitude_m - w[1].amplitude_m)
        })
        .collect();
    robust_fit(&rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_outlying_cycle_does_not_hide_the_backbone() {
        // f^2 = 4 (1 - 2 A^2) with a small deterministic scatter, and one glitch.
        let mut cycles: Vec<CycleSummary> = (0..60)
            .map(|i| {
                let a = 0.05 * (1.0 - i as f64 / 80.0);
                let wiggle = 1e-4 * ((i * 7919 % 13) as f64 - 6.0);
                CycleSummary {
                    time_s: i as f64,
                    amplitude_m: a,
                    frequency_hz: (4.0 * (1.0 - 2.0 * a * a)).sqrt() + wiggle,
                }
            })
            .collect();
        cycles[5].frequency_hz += 0.05;
        let (b, se) = robust_backbone(&cycles).unwrap();
        assert!((b + 2.0).abs() < 0.1, "{b}");
        assert!(b.abs() / se > 10.0, "{b} {se}");
    }
}
