//! Amplitude loss per cycle against amplitude: which damping law the decay follows.
//!
//! # Formulation
//!
//! For weak damping, the energy lost per cycle by harmonic balance (`x = A cos(omega t)`)
//! gives the amplitude loss per cycle `dA = dE / (k A)`:
//!
//! ```text
//! viscous c v          dA = 2 pi zeta A            a_1 = 2 pi zeta (the log decrement delta)
//! Coulomb F sgn(v)     dA = 4 F / k                a_0 = 4 F / k,  k = m omega^2
//! quadratic c2 v|v|    dA = (8/3) (c2 / m) A^2     a_2 = (8/3) c2 / m
//! ```
//!
//! (Coulomb: two half-cycles, each about a centre shifted by `F / k`, each losing `2 F / k`,
//! exact; quadratic: `int c2 |v|^3 dt = (8/3) c2 omega^2 A^3` per cycle.) The fit
//! `dA = a_0 + a_1 A + a_2 A^2` uses the local slope of `A(t)`, not raw differences
//! `A_k - A_{k+1}`, whose noise is `sqrt 2` times an amplitude's: the cycles are cut into
//! disjoint windows of `m` cycles (`m = n / 8` clamped to 3..16), a weighted line
//! `A = A_c + s (t - t_c)` is fitted in each (weights `1 / se^2`), and the window gives the
//! loss per cycle `y = -s T` (`T` its mean period) at amplitude `A_c`, with the standard error
//! of `s` from the amplitudes' standard errors. Disjoint windows keep the `y` independent. The
//! three-term fit is weighted by `1 / var(y)`; its standard errors are those of the weights,
//! scaled by the reduced chi-square when that exceeds 1 (model error or noise above the
//! estimate), never shrunk below the noise. Over a short range of amplitudes the three basis
//! functions are nearly collinear and the standard errors say so; single-term fits
//! ([`LossFit::single`]) are reported beside it. The conversions are [`friction_force`],
//! [`quadratic_coefficient`] and [`zeta_from_a1`].
//!
//! # Units and signs
//! The input is the axial acceleration of the weight in m/s^2 (`decay.csv`, see
//! `docs/measured-case.md`); every displacement amplitude here is in metres (SI), so
//! that the conversions below take `k` in N/m and `m` in kg. Times in s, frequencies in Hz.

use serde::Serialize;

use super::cycles::Cycle;
use crate::decrement::zeta_from_decrement;
use crate::error::{PostError, Result};
use crate::fit::weighted_fit;
use crate::stats::Estimate;

/// One window of the loss fit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LossPoint {
    /// Window centre (weighted mean time), s.
    pub time_s: f64,
    /// Amplitude at the centre, m.
    pub amplitude_m: f64,
    /// Amplitude loss per cycle, m.
    pub loss_m: f64,
    /// Its standard error, m.
    pub loss_std_error_m: f64,
}

/// A one-term fit `dA = a_j phi_j(A)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TermFit {
    /// The coefficient.
    pub coefficient: Estimate,
    /// Weighted residual per degree of freedom (1 when the term explains the loss to the
    /// noise).
    pub reduced_chi2: f64,
}

/// The three one-term fits.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SingleTermFits {
    /// `dA = a_0` (Coulomb), m.
    pub coulomb_a0_m: TermFit,
    /// `dA = a_1 A` (viscous), dimensionless.
    pub viscous_a1: TermFit,
    /// `dA = a_2 A^2` (velocity squared), 1/m.
    pub quadratic_a2_per_m: TermFit,
}

/// Result of [`loss_per_cycle`]: `dA = a_0 + a_1 A + a_2 A^2` per cycle.
#[derive(Debug, Clone, Serialize)]
pub struct LossFit {
    /// m.
    pub a0_m: Estimate,
    /// Dimensionless (the log decrement of the viscous part).
    pub a1: Estimate,
    /// 1/m.
    pub a2_per_m: Estimate,
    /// Weighted residual of the three-term fit per degree of freedom.
    pub reduced_chi2: f64,
    /// Cycles per window.
    pub cycles_per_window: usize,
    /// Smallest and largest window amplitude, m.
    pub amplitude_range_m: (f64, f64),
    /// The one-term fits.
    pub single: SingleTermFits,
    /// `a0` of the two-term fit `a0 + a1 A` (m): dry friction beside viscous damping,
    /// without the drag term that widens `a0`'s error in the three-term fit; `None` when
    /// singular.
    pub a0_without_drag_m: Option<Estimate>,
    /// `a2` of the two-term fit `a1 A + a2 A^2` (1/m): drag beside viscous damping,
    /// without the friction term; `None` when singular.
    pub a2_without_friction_per_m: Option<Estimate>,
    /// The windows of the fit.
    pub points: Vec<LossPoint>,
}

/// Loss per cycle against amplitude with `m = n / 8` cycles per window, clamped to 3..16.
pub fn loss_per_cycle(cycles: &[Cycle]) -> Result<LossFit> {
    loss_per_cycle_windowed(cycles, (cycles.len() / 8).clamp(3, 16))
}

/// Smallest number of windows of the loss fit (three coefficients and two degrees of
/// freedom).
pub const MIN_LOSS_WINDOWS: usize = 5;

/// [`loss_per_cycle`] with `cycles_per_window` cycles in each window (at least 3).
pub fn loss_per_cycle_windowed(cycles: &[Cycle], cycles_per_window: usize) -> Result<LossFit> {
    let m = cycles_per_window;
    if m < 3 {
        return Err(PostError::InvalidOption(format!(
            "{m} cycles per loss window; need at least 3 for a slope with an error"
        )));
    }
    let windows = cycles.len() / m;
    if windows < MIN_LOSS_WINDOWS {
        return Err(PostError::TooFewPoints {
            what: "loss per cycle",
            found: windows,
            needed: MIN_LOSS_WINDOWS,
            hint: format!(
                "{} cycles make {windows} windows of {m}; a longer record or fewer cycles per \
                 window",
                cycles.len()
            ),
        });
    }
    let floor = 1e-12 * cycles.iter().map(|c| c.amplitude_m).fold(0.0, f64::max);
    let mut points = Vec::with_capacity(windows);
    for block in cycles.chunks_exact(m) {
        let w: Vec<f64> = block
            .iter()
            .map(|c| c.amplitude_std_error_m.max(floor).powi(-2))
            .collect();
        let total: f64 = w.iter().sum();
        let t_c = block.iter().zip(&w).map(|(c, w)| w * c.time_s).sum::<f64>() / total;
        let a_c = block
            .iter()
            .zip(&w)
            .map(|(c, w)| w * c.amplitude_m)
            .sum::<f64>()
            / total;
        let (mut sxx, mut sxy) = (0.0, 0.0);
        for (c, w) in block.iter().zip(&w) {
            sxx += w * (c.time_s - t_c).powi(2);
            sxy += w * (c.time_s - t_c) * (c.amplitude_m - a_c);
        }
        let slope = sxy / sxx;
        let period = block.len() as f64 / block.iter().map(|c| c.frequency_hz).sum::<f64>();
        points.push(LossPoint {
            time_s: t_c,
            amplitude_m: a_c,
            loss_m: -slope * period,
            // With known variances, var(slope) = 1 / sum w (t - t_c)^2.
            loss_std_error_m: period / sxx.sqrt(),
        });
    }
    let y: Vec<f64> = points.iter().map(|p| p.loss_m).collect();
    let w: Vec<f64> = points
        .iter()
        .map(|p| p.loss_std_error_m.max(f64::MIN_POSITIVE).powi(-2))
        .collect();
    let fit_terms = |columns: &[usize]| {
        let basis: Vec<Vec<f64>> = points
            .iter()
            .map(|p| {
                columns
                    .iter()
                    .map(|&j| p.amplitude_m.powi(j as i32))
                    .collect()
            })
            .collect();
        weighted_fit(&basis, &y, &w).map(|fit| {
            let reduced_chi2 = fit.weighted_residual_sum / fit.dof as f64;
            let scale = reduced_chi2.max(1.0);
            let estimates: Vec<Estimate> = (0..columns.len())
                .map(|j| Estimate {
                    value: fit.coefficients[j],
                    std_error: (fit.unscaled_covariance[j][j].max(0.0) * scale).sqrt(),
                })
                .collect();
            (estimates, reduced_chi2)
        })
    };
    let singular = || PostError::Unidentifiable {
        what: "the loss per cycle",
        why: "the windows' amplitudes do not spread enough to separate the terms".to_string(),
    };
    let (full, reduced_chi2) = fit_terms(&[0, 1, 2]).ok_or_else(singular)?;
    let single = |j: usize| {
        fit_terms(&[j]).map(|(e, reduced_chi2)| TermFit {
            coefficient: e[0],
            reduced_chi2,
        })
    };
    let single = SingleTermFits {
        coulomb_a0_m: single(0).ok_or_else(singular)?,
        viscous_a1: single(1).ok_or_else(singular)?,
        quadratic_a2_per_m: single(2).ok_or_else(singular)?,
    };
    let a0_without_drag_m = fit_terms(&[0, 1]).map(|(e, _)| e[0]);
    let a2_without_friction_per_m = fit_terms(&[1, 2]).map(|(e, _)| e[1]);
    let amplitudes = points.iter().map(|p| p.amplitude_m);
    let amplitude_range_m = (
        amplitudes.clone().fold(f64::INFINITY, f64::min),
        amplitudes.fold(0.0, f64::max),
    );
    Ok(LossFit {
        a0_m: full[0],
        a1: full[1],
        a2_per_m: full[2],
        reduced_chi2,
        cycles_per_window: m,
        amplitude_range_m,
        single,
        a0_without_drag_m,
        a2_without_friction_per_m,
        points,
    })
}

/// Coulomb friction force from the constant loss per cycle: `F = a_0 k / 4` (N, with `a_0`
/// in m and `k = m omega^2` in N/m). Standard errors scale the same way.
pub fn friction_force(a0_m: f64, stiffness_n_m: f64) -> f64 {
    a0_m * stiffness_n_m / 4.0
}

/// Velocity-squared damping coefficient from the quadratic loss: `c2 = 3 a_2 m / 8`
/// (N s^2/m^2, with `a_2` in 1/m and the mass in kg). Standard errors scale the same way.
pub fn quadratic_coefficient(a2_per_m: f64, mass_kg: f64) -> f64 {
    3.0 * a2_per_m * mass_kg / 8.0
}

/// Viscous damping ratio from the linear loss: `a_1` is the logarithmic decrement, so
/// `zeta = a_1 / sqrt(4 pi^2 + a_1^2)` (the paper's Eq. 3).
pub fn zeta_from_a1(a1: f64) -> f64 {
    zeta_from_decrement(a1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signature::cycles::{cycles, CycleOptions};
    use crate::signature::shape::{envelope_shape, EnvelopeKind};
    use crate::signature::test_records::*;
    use std::f64::consts::TAU;

    #[test]
    fn coulomb_decay_gives_a0_of_4f_over_k() {
        let (mass, f) = (5.0, 5.0);
        let omega = TAU * f;
        let k = mass * omega * omega;
        let friction = 0.11; // N: 4F/k = 0.09 mm per cycle from 10 mm
        let accel = measured(&coulomb_accel(omega, friction / k, 0.01, 25.0), 2);
        let time = times(accel.len());
        let series = cycles(&sig(&time, &accel), &CycleOptions::default()).unwrap();
        let loss = loss_per_cycle(&series.cycles).unwrap();
        eprintln!("coulomb: {loss:#?}");
        let exact = 4.0 * friction / k;
        assert!(
            within(loss.a0_m.value, exact, 0.05),
            "{:?} vs {exact}",
            loss.a0_m
        );
        assert!(within(friction_force(loss.a0_m.value, k), friction, 0.05));
        assert!(
            loss.a1.value.abs() < 3.0 * loss.a1.std_error,
            "{:?}",
            loss.a1
        );
        let shape = envelope_shape(&series.cycles).unwrap();
        eprintln!("coulomb shape: {shape:?}");
        assert_eq!(shape.kind, EnvelopeKind::Linear, "{shape:?}");
        assert!(shape.r2_linear > shape.r2_exponential);
    }

    #[test]
    fn quadratic_damping_gives_a2_of_8_c2_over_3m() {
        let sdof = Sdof {
            mass: 5.0,
            k: 5.0 * (TAU * 5.0_f64).powi(2),
            k3: 0.0,
            c: 0.0,
            c2: 7.5,
            gravity: 0.0,
        };
        let accel = measured(&sdof.accel(0.01, 30.0), 3);
        let time = times(accel.len());
        let series = cycles(&sig(&time, &accel), &CycleOptions::default()).unwrap();
        let loss = loss_per_cycle(&series.cycles).unwrap();
        eprintln!("quadratic: {loss:#?}");
        let exact = 8.0 * sdof.c2 / (3.0 * sdof.mass);
        assert!(
            within(loss.a2_per_m.value, exact, 0.10),
            "{:?} vs {exact}",
            loss.a2_per_m
        );
        assert!(within(
            quadratic_coefficient(loss.a2_per_m.value, sdof.mass),
            sdof.c2,
            0.10
        ));
    }
}
