//! The backbone: frequency against amplitude, and the cubic stiffness it implies.
//!
//! # Formulation
//!
//! A spring force `k x + k3 x^3` (`x` compression from free length) preloaded by the weight to
//! `x_s` (`k x_s + k3 x_s^3 = m g`) has, about `x_s`, the restoring force
//! `k_t y + 3 k3 x_s y^2 + k3 y^3`, `k_t = k + 3 k3 x_s^2`. For `y'' + omega_0^2 y + alpha y^2
//! + beta y^3 = 0` the Lindstedt-Poincare expansion (Landau & Lifshitz, Mechanics, section 28;
//! Nayfeh & Mook, Nonlinear Oscillations, 4.1) gives
//! `omega = omega_0 + (3 beta / (8 omega_0) - 5 alpha^2 / (12 omega_0^3)) A^2`, so
//!
//! ```text
//! f^2 = f_0^2 (1 + b A^2),   b = 3 k3 / (4 k_t) - 5 (3 k3 x_s)^2 / (6 k_t^2)
//! ```
//!
//! The fit is `f_k^2 = c_0 + c_1 A_k^2` by least squares weighted by `(A_k / se_k)^2 / f_k^4`
//! (the crossing jitter, hence the relative frequency error, scales as `se / A`), with
//! `f_0 = sqrt(c_0)`, `b = c_1 / c_0` and standard errors by the delta method from the
//! residual-scaled covariance (neighbouring cycles share a crossing, which makes the
//! per-cycle errors negatively correlated: the standard errors are then conservative).
//! Damping lowers `f` by `sqrt(1 - zeta^2)`, constant for viscous damping and absorbed in
//! `f_0`. The next term of the expansion changes `b` by about `0.2 (k3 / k) A^2` relative.
//! [`cubic_from_backbone`] solves the quadratic in `k3` for its root that tends to
//! `4 k_t b / 3` as `x_s -> 0`.
//!
//! # Units and signs
//! The input is the axial acceleration of the weight in m/s^2 (`decay.csv`, see
//! `docs/measured-case.md`); every displacement amplitude here is in metres (SI), so
//! that the conversions below take `k` in N/m and `m` in kg. Times in s, frequencies in Hz.

use serde::Serialize;

use super::cycles::Cycle;
use crate::error::{show, PostError, Result};
use crate::fit::weighted_fit;
use crate::stats::Estimate;

/// Result of [`backbone`]: `f^2 = f_0^2 (1 + b A^2)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BackboneFit {
    /// Small-amplitude (damped) frequency, Hz.
    pub f0_hz: Estimate,
    /// 1/m^2.
    pub b_per_m2: Estimate,
    /// `b A_max^2`: the relative change of `f^2` over the record.
    pub shift_at_largest: f64,
    /// Smallest and largest amplitude, m.
    pub amplitude_range_m: (f64, f64),
    /// Cycles used.
    pub cycles: usize,
    /// Residual RMS of `f` about the fit, Hz.
    pub residual_rms_hz: f64,
}

/// Fits the backbone `f^2 = f_0^2 (1 + b A^2)` to the cycles (see the module doc).
pub fn backbone(cycles: &[Cycle]) -> Result<BackboneFit> {
    if cycles.len() < 4 {
        return Err(PostError::TooFewPoints {
            what: "backbone",
            found: cycles.len(),
            needed: 4,
            hint: "a longer record".to_string(),
        });
    }
    let basis: Vec<Vec<f64>> = cycles
        .iter()
        .map(|c| vec![1.0, c.amplitude_m * c.amplitude_m])
        .collect();
    let y: Vec<f64> = cycles.iter().map(|c| c.frequency_hz.powi(2)).collect();
    let w: Vec<f64> = cycles
        .iter()
        .map(|c| {
            let relative = c.amplitude_std_error_m / c.amplitude_m;
            (relative.max(1e-12) * c.frequency_hz.powi(2)).powi(-2)
        })
        .collect();
    let fit = weighted_fit(&basis, &y, &w).ok_or_else(|| PostError::Unidentifiable {
        what: "the backbone",
        why: "the cycles' amplitudes are all equal".to_string(),
    })?;
    let (c0, c1) = (fit.coefficients[0], fit.coefficients[1]);
    if c0 <= 0.0 {
        return Err(PostError::Unidentifiable {
            what: "the backbone",
            why: format!("the fitted f0^2 = {} Hz^2 is not positive", show(c0)),
        });
    }
    let cov = &fit.covariance;
    let f0 = c0.sqrt();
    let b = c1 / c0;
    // Delta method for b = c1 / c0.
    let var_b = cov[1][1] / (c0 * c0) + c1 * c1 * cov[0][0] / c0.powi(4)
        - 2.0 * c1 * cov[0][1] / c0.powi(3);
    let amplitudes = cycles.iter().map(|c| c.amplitude_m);
    let largest = amplitudes.clone().fold(0.0, f64::max);
    let residual_rms_hz = (cycles
        .iter()
        .zip(&fit.residuals)
        .map(|(c, r)| (r / (2.0 * c.frequency_hz)).powi(2))
        .sum::<f64>()
        / cycles.len() as f64)
        .sqrt();
    Ok(BackboneFit {
        f0_hz: Estimate {
            value: f0,
            std_error: cov[0][0].max(0.0).sqrt() / (2.0 * f0),
        },
        b_per_m2: Estimate {
            value: b,
            std_error: var_b.max(0.0).sqrt(),
        },
        shift_at_largest: b * largest * largest,
        amplitude_range_m: (amplitudes.fold(f64::INFINITY, f64::min), largest),
        cycles: cycles.len(),
        residual_rms_hz,
    })
}

/// The cubic stiffness `k3` (N/m^3) that gives the backbone coefficient `b` (1/m^2) about a
/// static compression `x_s` (m) with tangent stiffness `k_t` (N/m, e.g. `m (2 pi f_0)^2`):
/// the root of `(15/2) (x_s / k_t)^2 k3^2 - 3 k3 / (4 k_t) + b = 0` that tends to
/// `4 k_t b / 3` as `x_s -> 0`, written as `2 b / (3/(4 k_t) + sqrt(9/(16 k_t^2) - 30 b
/// x_s^2 / k_t^2))` (no cancellation). An error when `b` exceeds `3 / (160 x_s^2)`, the
/// largest value any `k3` gives.
pub fn cubic_from_backbone(
    b_per_m2: f64,
    tangent_stiffness_n_m: f64,
    static_compression_m: f64,
) -> Result<f64> {
    let (b, k_t, x_s) = (b_per_m2, tangent_stiffness_n_m, static_compression_m);
    if !(k_t > 0.0 && k_t.is_finite() && b.is_finite() && x_s.is_finite()) {
        return Err(PostError::InvalidOption(format!(
            "backbone b = {} 1/m^2, k_t = {} N/m, x_s = {} m; expected finite numbers and a \
             positive stiffness",
            show(b),
            show(k_t),
            show(x_s)
        )));
    }
    let linear = 3.0 / (4.0 * k_t);
    let discriminant = linear * linear - 30.0 * b * x_s * x_s / (k_t * k_t);
    if discriminant < 0.0 {
        return Err(PostError::Unidentifiable {
            what: "the cubic stiffness",
            why: format!(
                "b = {} 1/m^2 exceeds 3 / (160 x_s^2) = {} 1/m^2, the largest backbone bend a \
                 cubic spring preloaded to x_s = {} m can give",
                show(b),
                show(3.0 / (160.0 * x_s * x_s)),
                show(x_s)
            ),
        });
    }
    Ok(2.0 * b / (linear + discriminant.sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signature::cycles::{cycles, CycleOptions};
    use crate::signature::test_records::*;
    use std::f64::consts::TAU;

    fn backbone_of(sdof: &Sdof, lift: f64, seed: u64) -> BackboneFit {
        let accel = measured(&sdof.accel(lift, 30.0), seed);
        let time = times(accel.len());
        let series = cycles(&sig(&time, &accel), &CycleOptions::default()).unwrap();
        backbone(&series.cycles).unwrap()
    }

    #[test]
    fn duffing_without_preload_gives_b_and_k3() {
        let sdof = Sdof {
            mass: 5.0,
            k: 8000.0,
            k3: 5e6,
            c: 2.0 * 0.003 * (5.0_f64 * 8000.0).sqrt(),
            c2: 0.0,
            gravity: 0.0,
        };
        let fit = backbone_of(&sdof, 0.01, 4);
        eprintln!("duffing: {fit:?}");
        let exact = 3.0 * sdof.k3 / (4.0 * sdof.k);
        assert!(
            within(fit.b_per_m2.value, exact, 0.10),
            "{fit:?} vs {exact}"
        );
        let k_t = sdof.mass * (TAU * fit.f0_hz.value).powi(2);
        let k3 = cubic_from_backbone(fit.b_per_m2.value, k_t, 0.0).unwrap();
        assert!(within(k3, sdof.k3, 0.10), "k3 {k3}");
    }

    #[test]
    fn duffing_with_preload_gives_b_and_k3() {
        let sdof = Sdof {
            mass: 5.0,
            k: 8000.0,
            k3: 5e6,
            c: 2.0 * 0.003 * (5.0_f64 * 8540.0).sqrt(),
            c2: 0.0,
            gravity: 9.81,
        };
        let x_s = sdof.static_compression();
        let k_t = sdof.tangent_stiffness();
        let fit = backbone_of(&sdof, 0.006, 5);
        eprintln!("preloaded duffing: x_s {x_s}, k_t {k_t}, {fit:?}");
        let exact =
            3.0 * sdof.k3 / (4.0 * k_t) - 5.0 * (3.0 * sdof.k3 * x_s).powi(2) / (6.0 * k_t * k_t);
        // Without the quadratic term's correction b would be 3 k3 / (4 k_t), 20% higher:
        // the 10% tolerance tells the two apart.
        assert!(3.0 * sdof.k3 / (4.0 * k_t) > 1.2 * exact);
        assert!(
            within(fit.b_per_m2.value, exact, 0.10),
            "{fit:?} vs {exact}"
        );
        let k_t_measured = sdof.mass * (TAU * fit.f0_hz.value).powi(2);
        let k3 = cubic_from_backbone(fit.b_per_m2.value, k_t_measured, x_s).unwrap();
        assert!(within(k3, sdof.k3, 0.10), "k3 {k3}");
    }

    #[test]
    fn cubic_from_backbone_inverts_the_backbone_formula() {
        let (k_t, x_s) = (8540.0, 0.006);
        for k3 in [0.0_f64, 1e6, 5e6, -2e6] {
            let b = 3.0 * k3 / (4.0 * k_t) - 5.0 * (3.0 * k3 * x_s).powi(2) / (6.0 * k_t * k_t);
            let back = cubic_from_backbone(b, k_t, x_s).unwrap();
            assert!(
                (back - k3).abs() <= 1e-9 * k3.abs().max(1.0),
                "{k3} -> {b} -> {back}"
            );
        }
        // Largest b any k3 gives: 3 / (160 x_s^2).
        let too_bent = 1.01 * 3.0 / (160.0 * x_s * x_s);
        assert!(matches!(
            cubic_from_backbone(too_bent, k_t, x_s),
            Err(PostError::Unidentifiable { .. })
        ));
        assert!(cubic_from_backbone(1.0, 0.0, x_s).is_err());
    }
}
