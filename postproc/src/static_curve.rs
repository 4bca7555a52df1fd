//! The static force-compression record: stiffness, cubic stiffness and friction.
//!
//! # Input
//! `static.csv` (`docs/measured-case.md`): `displacement_mm` is the compression from
//! the free length (positive = shorter), `force_n` the axial force, in the order measured
//! (usually loading, then unloading); both carry noise.
//!
//! # Branches
//! Each point is classified by the direction of the compression: the record is smoothed by a
//! centred moving mean of half-width `h = max(2, n / 50)` points, and the point is loading
//! (`s = +1`) when the smoothed compression `h` points later exceeds that `h` points earlier
//! by more than `3 sigma_x sqrt(2 / (2h + 1))` (the noise of that difference, `sigma_x` the
//! robust noise estimate of [`crate::stats::noise_rms`]), unloading (`s = -1`) when it falls
//! by as much, and left out otherwise (dwells, turning points). A record without loading
//! points is an error ([`PostError::NoLoadingBranch`]): one that only unloads or stays flat.
//!
//! # Fits
//! With `x` in mm and `F` in N, by ordinary least squares over the classified points:
//!
//! ```text
//! cubic (headline)   F = k x + k3 x^3 + s F_f
//! linear             F = k x + s F_f
//! with offset        F = F_0 + k x + k3 x^3 + s F_f
//! ```
//!
//! No offset in the headline fit: the spec measures `x` from the free length, where the
//! force is zero. The offset fit is reported beside it: an offset far from zero (many
//! standard errors) says the zero of `x` or of the load cell is off. `F_f` is the dry
//! friction (half the height of the hysteresis loop: loading needs `k x + F_f`, unloading
//! holds at `k x - F_f`); without an unloading branch it is not identifiable from the offset
//! and is not fitted. Standard errors are `sqrt(s^2 (X^T X)^-1)` with the residual variance
//! `s^2`. The linear fit's residual against the cubic fit's (RMS and `R^2`) is the evidence of
//! curvature; so is `k3 / se(k3)`. `k3` in N/mm^3 is also given in N/m^3 (times 1e9), `k` in
//! N/m (times 1e3), for the dynamic signatures ([`crate::signature`]), which work in SI.

use serde::Serialize;

use crate::error::{PostError, Result};
use crate::fit::weighted_fit;
use crate::stats::{noise_rms, Estimate};

/// Fewest points of a static record.
pub const MIN_STATIC_POINTS: usize = 8;

/// Fewest points on a branch for it to count.
pub const MIN_BRANCH_POINTS: usize = 3;

/// Residual figures of one fit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FitQuality {
    /// RMS of the force residuals, N.
    pub residual_rms_n: f64,
    /// `1 - SS_res / SS_tot` about the mean force.
    pub r2: f64,
}

/// `F = k x + s F_f`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LinearStatic {
    /// Axial stiffness K, N/mm.
    pub stiffness_n_mm: Estimate,
    /// Dry-friction force, N (when the record has an unloading branch).
    pub friction_n: Option<Estimate>,
    /// How well the fit matches.
    pub quality: FitQuality,
}

/// `F = F_0 + k x + k3 x^3 + s F_f`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OffsetStatic {
    /// Force offset F0, N.
    pub offset_n: Estimate,
    /// Axial stiffness K, N/mm.
    pub stiffness_n_mm: Estimate,
    /// Cubic stiffness k3, N/mm^3.
    pub cubic_n_mm3: Estimate,
    /// Dry-friction force, N (when the record has an unloading branch).
    pub friction_n: Option<Estimate>,
    /// How well the fit matches.
    pub quality: FitQuality,
}

/// Result of [`analyze_static`].
#[derive(Debug, Clone, Serialize)]
pub struct StaticFit {
    /// Points used.
    pub points: usize,
    /// Points on the loading branch.
    pub loading_points: usize,
    /// Points on the unloading branch.
    pub unloading_points: usize,
    /// Points on neither branch (dwells, turning points).
    pub excluded_points: usize,
    /// `k` of the cubic fit, N/mm.
    pub stiffness_n_mm: Estimate,
    /// The same, N/m.
    pub stiffness_n_m: Estimate,
    /// `k3`, N/mm^3.
    pub cubic_n_mm3: Estimate,
    /// `k3`, N/m^3.
    pub cubic_n_m3: Estimate,
    /// `F_f`, N; `None` without an unloading branch.
    pub friction_n: Option<Estimate>,
    /// The cubic fit.
    pub cubic: FitQuality,
    /// The linear fit.
    pub linear: LinearStatic,
    /// The fit with a force offset.
    pub with_offset: OffsetStatic,
}

/// Fits the static record (see the module doc).
pub fn analyze_static(displacement_mm: &[f64], force_n: &[f64]) -> Result<StaticFit> {
    let n = displacement_mm.len();
    if force_n.len() != n {
        return Err(PostError::InvalidSignal {
            index: n.min(force_n.len()),
            what: format!(
                "{n} displacements but {} forces; expected equal lengths",
                force_n.len()
            ),
        });
    }
    if let Some(index) = displacement_mm
        .iter()
        .zip(force_n)
        .position(|(x, f)| !x.is_finite() || !f.is_finite())
    {
        return Err(PostError::InvalidSignal {
            index,
            what: format!(
                "displacement {} mm, force {} N: expected finite numbers",
                displacement_mm[index], force_n[index]
            ),
        });
    }
    if n < MIN_STATIC_POINTS {
        return Err(PostError::TooFewPoints {
            what: "static record",
            found: n,
            needed: MIN_STATIC_POINTS,
            hint: "a force-compression record over the working range".to_string(),
        });
    }
    let direction = branches(displacement_mm);
    let loading = direction.iter().filter(|&&s| s > 0.0).count();
    let unloading = direction.iter().filter(|&&s| s < 0.0).count();
    if loading < MIN_BRANCH_POINTS {
        return Err(PostError::NoLoadingBranch {
            points: n,
            increasing: loading,
            needed: MIN_BRANCH_POINTS,
        });
    }
    let with_friction = unloading >= MIN_BRANCH_POINTS;
    let used: Vec<usize> = (0..n).filter(|&i| direction[i] != 0.0).collect();
    let force: Vec<f64> = used.iter().map(|&i| force_n[i]).collect();
    let mean = force.iter().sum::<f64>() / force.len() as f64;
    let total: f64 = force.iter().map(|f| (f - mean).powi(2)).sum();

    // Columns: "1", "x", "x3", "s".
    let fit = |columns: &[&str]| -> Result<(Vec<Estimate>, FitQuality)> {
        let basis: Vec<Vec<f64>> = used
            .iter()
            .map(|&i| {
                let x = displacement_mm[i];
                columns
                    .iter()
                    .map(|&c| match c {
                        "1" => 1.0,
                        "x" => x,
                        "x3" => x.powi(3),
                        _ => direction[i],
                    })
                    .collect()
            })
            .collect();
        let weights = vec![1.0; used.len()];
        let fit =
            weighted_fit(&basis, &force, &weights).ok_or_else(|| PostError::Unidentifiable {
                what: "the static stiffness",
                why: format!(
                    "the fit {} is singular; the compressions do not spread enough",
                    columns.join(", ")
                ),
            })?;
        let estimates = fit
            .coefficients
            .iter()
            .zip(&fit.std_errors)
            .map(|(&value, &std_error)| Estimate { value, std_error })
            .collect();
        let quality = FitQuality {
            residual_rms_n: (fit.weighted_residual_sum / used.len() as f64).sqrt(),
            r2: 1.0 - fit.weighted_residual_sum / total,
        };
        Ok((estimates, quality))
    };
    let friction_column: &[&str] = if with_friction { &["s"] } else { &[] };
    let columns = |head: &[&'static str]| -> Vec<&'static str> {
        let mut all = head.to_vec();
        all.extend_from_slice(friction_column);
        all
    };
    let (cubic, cubic_quality) = fit(&columns(&["x", "x3"]))?;
    let (linear, linear_quality) = fit(&columns(&["x"]))?;
    let (offset, offset_quality) = fit(&columns(&["1", "x", "x3"]))?;
    let scaled = |e: Estimate, factor: f64| Estimate {
        value: e.value * factor,
        std_error: e.std_error * factor,
    };
    Ok(StaticFit {
        points: n,
        loading_points: loading,
        unloading_points: unloading,
        excluded_points: n - used.len(),
        stiffness_n_mm: cubic[0],
        stiffness_n_m: scaled(cubic[0], 1e3),
        cubic_n_mm3: cubic[1],
        cubic_n_m3: scaled(cubic[1], 1e9),
        friction_n: with_friction.then(|| cubic[2]),
        cubic: cubic_quality,
        linear: LinearStatic {
            stiffness_n_mm: linear[0],
            friction_n: with_friction.then(|| linear[1]),
            quality: linear_quality,
        },
        with_offset: OffsetStatic {
            offset_n: offset[0],
            stiffness_n_mm: offset[1],
            cubic_n_mm3: offset[2],
            friction_n: with_friction.then(|| offset[3]),
            quality: offset_quality,
        },
    })
}

/// `+1` loading, `-1` unloading, `0` neither, per point (see the module doc).
fn branches(x: &[f64]) -> Vec<f64> {
    let n = x.len();
    let h = (n / 50).max(2);
    let smooth: Vec<f64> = (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(h), (i + h).min(n - 1));
            x[a..=b].iter().sum::<f64>() / (b - a + 1) as f64
        })
        .collect();
    let range = x.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        - x.iter().copied().fold(f64::INFINITY, f64::min);
    // The noise of a difference of two means of 2h + 1 points, and a round-off floor so that
    // a flat record stays flat.
    let threshold =
        3.0 * noise_rms(x) * (2.0 / (2 * h + 1) as f64).sqrt() + 1e-9 * range.max(1e-300);
    (0..n)
        .map(|i| {
            let change = smooth[(i + h).min(n - 1)] - smooth[i.saturating_sub(h)];
            if change > threshold {
                1.0
            } else if change < -threshold {
                -1.0
            } else {
                0.0
            }
        })
        .collect()
}

/// Reads `displacement_mm` and `force_n` of a `static.csv`.
pub fn read_static_csv(path: &std::path::Path) -> Result<(Vec<f64>, Vec<f64>)> {
    let mut fields = crate::signal::read_fields(path, &["displacement_mm", "force_n"])?;
    let force = fields.values.pop().unwrap_or_default();
    let displacement = fields.values.pop().unwrap_or_default();
    Ok((displacement, force))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_signals::Rng;

    /// Loading 0 -> 40 mm then unloading back, 200 points each, force
    /// `k x + k3 x^3 + s F_f` with noise 0.01 mm and `force_noise` N.
    fn record(k: f64, k3: f64, friction: f64, force_noise: f64, seed: u64) -> (Vec<f64>, Vec<f64>) {
        let mut rng = Rng::new(seed);
        let mut x = Vec::new();
        let mut f = Vec::new();
        for i in 0..400 {
            let (true_x, s) = if i < 200 {
                (40.0 * i as f64 / 199.0, 1.0)
            } else {
                (40.0 * (399 - i) as f64 / 199.0, -1.0)
            };
            x.push(true_x + 0.01 * rng.normal());
            f.push(k * true_x + k3 * true_x.powi(3) + s * friction + force_noise * rng.normal());
        }
        (x, f)
    }

    fn close(e: Estimate, exact: f64) -> bool {
        // Within 4 standard errors (the fits are unbiased; noise only).
        (e.value - exact).abs() <= 4.0 * e.std_error
    }

    #[test]
    fn friction_and_cubic_term_are_recovered_within_their_errors() {
        let (k, k3, friction) = (3.93, 2e-4, 1.5);
        let (x, f) = record(k, k3, friction, 0.05, 11);
        let fit = analyze_static(&x, &f).unwrap();
        eprintln!("static: {fit:#?}");
        assert!(close(fit.stiffness_n_mm, k), "{:?}", fit.stiffness_n_mm);
        assert!(close(fit.cubic_n_mm3, k3), "{:?}", fit.cubic_n_mm3);
        let friction_fit = fit.friction_n.unwrap();
        assert!(close(friction_fit, friction), "{friction_fit:?}");
        assert!(
            (fit.cubic_n_m3.value - fit.cubic_n_mm3.value * 1e9).abs()
                < 1e-6 * fit.cubic_n_m3.value.abs()
        );
        // Curvature evidence: the linear fit leaves the cubic's bend (~2e-4 * 40^3 / 10 = 1 N
        // RMS) against the 0.05 N noise of the cubic fit.
        assert!(
            fit.linear.quality.residual_rms_n > 5.0 * fit.cubic.residual_rms_n,
            "{fit:?}"
        );
        // What the cubic fit leaves is the noise: 0.05 N of force and 0.01 mm of compression
        // times the tangent stiffness (3.9 to 4.9 N/mm), sqrt(0.05^2 + 0.045^2) = 0.067 N.
        assert!(fit.cubic.residual_rms_n < 0.075, "{:?}", fit.cubic);
        assert!(
            close(fit.with_offset.offset_n, 0.0),
            "{:?}",
            fit.with_offset
        );
        assert!(
            fit.loading_points > 180 && fit.unloading_points > 180,
            "{fit:?}"
        );
    }

    #[test]
    fn linear_spring_without_friction_gives_zero_cubic_and_friction() {
        let (x, f) = record(3.93, 0.0, 0.0, 0.05, 12);
        let fit = analyze_static(&x, &f).unwrap();
        assert!(close(fit.stiffness_n_mm, 3.93), "{:?}", fit.stiffness_n_mm);
        assert!(close(fit.cubic_n_mm3, 0.0), "{:?}", fit.cubic_n_mm3);
        assert!(close(fit.friction_n.unwrap(), 0.0), "{:?}", fit.friction_n);
        // No curvature: the two fits leave the same residual to within a few percent.
        assert!(fit.linear.quality.residual_rms_n < 1.05 * fit.cubic.residual_rms_n);
    }

    #[test]
    fn loading_only_fits_without_friction_and_unloading_only_is_an_error() {
        let (x, f) = record(3.93, 1e-4, 0.0, 0.05, 13);
        let fit = analyze_static(&x[..200], &f[..200]).unwrap();
        assert!(fit.friction_n.is_none());
        assert!(close(fit.stiffness_n_mm, 3.93), "{:?}", fit.stiffness_n_mm);
        assert!(matches!(
            analyze_static(&x[200..], &f[200..]),
            Err(PostError::NoLoadingBranch { .. })
        ));
        let flat = vec![10.0; 50];
        assert!(matches!(
            analyze_static(&flat, &flat),
            Err(PostError::NoLoadingBranch { .. })
        ));
    }

    #[test]
    fn bad_static_records_are_typed_errors() {
        let (mut x, f) = record(3.93, 0.0, 0.5, 0.05, 14);
        assert!(matches!(
            analyze_static(&x[..5], &f[..5]),
            Err(PostError::TooFewPoints { .. })
        ));
        assert!(matches!(
            analyze_static(&x[..50], &f[..49]),
            Err(PostError::InvalidSignal { .. })
        ));
        x[17] = f64::NAN;
        assert!(matches!(
            analyze_static(&x, &f),
            Err(PostError::InvalidSignal { index: 17, .. })
        ));
    }
}
