//! Small weighted least-squares fits used by the estimators.
//!
//! Normal equations solved by Gaussian elimination with partial pivoting: the bases used here
//! have a handful of columns, each scaled to order one by its caller, so the normal matrix is
//! well conditioned and nothing heavier is needed.

/// Slope of a weighted least-squares line `y = a + slope x` and its standard error.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Line {
    pub slope: f64,
    pub slope_std_error: f64,
}

pub(crate) fn weighted_line(x: &[f64], y: &[f64], w: &[f64]) -> Line {
    let total: f64 = w.iter().sum();
    let x_mean = x.iter().zip(w).map(|(x, w)| x * w).sum::<f64>() / total;
    let y_mean = y.iter().zip(w).map(|(y, w)| y * w).sum::<f64>() / total;
    let (mut sxx, mut sxy) = (0.0, 0.0);
    for ((x, y), w) in x.iter().zip(y).zip(w) {
        sxx += w * (x - x_mean) * (x - x_mean);
        sxy += w * (x - x_mean) * (y - y_mean);
    }
    let slope = sxy / sxx;
    let intercept = y_mean - slope * x_mean;
    let n = x.len() as f64;
    let slope_std_error = if x.len() > 2 {
        let residual: f64 = x
            .iter()
            .zip(y)
            .zip(w)
            .map(|((x, y), w)| w * (y - intercept - slope * x).powi(2))
            .sum();
        // Weights normalised to mean 1 so that the residual variance is per point.
        let scale = n / total;
        (residual * scale / (n - 2.0) / (sxx * scale)).sqrt()
    } else {
        0.0
    };
    Line {
        slope,
        slope_std_error,
    }
}

/// Weighted least squares `sum_i w_i (y_i - sum_j c_j basis_i[j])^2 -> min`; `None` when the
/// normal matrix is singular.
pub(crate) fn least_squares(basis: &[Vec<f64>], y: &[f64], w: &[f64]) -> Option<Vec<f64>> {
    let m = basis.first()?.len();
    let mut a = vec![vec![0.0; m + 1]; m];
    for ((row, value), weight) in basis.iter().zip(y).zip(w) {
        for i in 0..m {
            for j in 0..m {
                a[i][j] += weight * row[i] * row[j];
            }
            a[i][m] += weight * row[i] * value;
        }
    }
    for column in 0..m {
        let pivot =
            (column..m).max_by(|&r, &s| a[r][column].abs().total_cmp(&a[s][column].abs()))?;
        if a[pivot][column].abs() < 1e-300 {
            return None;
        }
        a.swap(column, pivot);
        let pivot_row = a[column].clone();
        for (row, values) in a.iter_mut().enumerate() {
            if row != column {
                let factor = values[column] / pivot_row[column];
                for (value, pivot_value) in values.iter_mut().zip(&pivot_row).skip(column) {
                    *value -= factor * pivot_value;
                }
            }
        }
    }
    let solution: Vec<f64> = (0..m).map(|i| a[i][m] / a[i][i]).collect();
    solution.iter().all(|c| c.is_finite()).then_some(solution)
}

/// A weighted linear least-squares fit with its covariance.
#[derive(Debug, Clone)]
pub(crate) struct LinearFit {
    pub coefficients: Vec<f64>,
    /// Standard errors `sqrt(s^2 (X^T W X)^-1)_jj` with `s^2` the weighted residual
    /// variance per point (weights normalised to mean 1).
    pub std_errors: Vec<f64>,
    /// `s^2 (X^T W X)^-1`, same normalisation.
    pub covariance: Vec<Vec<f64>>,
    /// `(X^T W X)^-1` with the weights as given: the covariance when the weights are the
    /// inverse variances of the data.
    pub unscaled_covariance: Vec<Vec<f64>>,
    /// `sum w_i r_i^2` with the weights as given.
    pub weighted_residual_sum: f64,
    /// Residuals `y_i - x_i . c`.
    pub residuals: Vec<f64>,
    /// Points minus coefficients.
    pub dof: usize,
}

/// Weighted least squares with covariance. Each column is scaled by its weighted RMS before
/// the normal matrix is inverted (Gauss-Jordan with partial pivoting), so callers may pass
/// columns of any magnitude (`x`, `x^3` in mm). `None` when there are no more points than
/// columns, a column is zero or the normal matrix is singular.
pub(crate) fn weighted_fit(basis: &[Vec<f64>], y: &[f64], w: &[f64]) -> Option<LinearFit> {
    let m = basis.first()?.len();
    let n = basis.len();
    if n <= m || y.len() != n || w.len() != n || basis.iter().any(|row| row.len() != m) {
        return None;
    }
    let total: f64 = w.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return None;
    }
    let scale: Vec<f64> = (0..m)
        .map(|j| {
            (basis
                .iter()
                .zip(w)
                .map(|(row, w)| w * row[j] * row[j])
                .sum::<f64>()
                / total)
                .sqrt()
        })
        .collect();
    if scale.iter().any(|s| !(*s > 0.0 && s.is_finite())) {
        return None;
    }
    // Augmented [N | I | b] for Gauss-Jordan: the inverse and the solution at once.
    let width = 2 * m + 1;
    let mut a = vec![vec![0.0; width]; m];
    for ((row, value), weight) in basis.iter().zip(y).zip(w) {
        for i in 0..m {
            let xi = row[i] / scale[i];
            for j in 0..m {
                a[i][j] += weight * xi * row[j] / scale[j];
            }
            a[i][2 * m] += weight * xi * value;
        }
    }
    for (i, row) in a.iter_mut().enumerate() {
        row[m + i] = 1.0;
    }
    for column in 0..m {
        let pivot =
            (column..m).max_by(|&r, &s| a[r][column].abs().total_cmp(&a[s][column].abs()))?;
        // Columns are scaled to unit RMS, so the normal matrix has a unit diagonal: a pivot
        // this small means the columns are dependent to round-off.
        if a[pivot][column].abs() < 1e-12 * total {
            return None;
        }
        a.swap(column, pivot);
        let divisor = a[column][column];
        for value in &mut a[column] {
            *value /= divisor;
        }
        let pivot_row = a[column].clone();
        for (row, values) in a.iter_mut().enumerate() {
            if row != column {
                let factor = values[column];
                for (value, pivot_value) in values.iter_mut().zip(&pivot_row) {
                    *value -= factor * pivot_value;
                }
            }
        }
    }
    let coefficients: Vec<f64> = (0..m).map(|i| a[i][2 * m] / scale[i]).collect();
    let unscaled_covariance: Vec<Vec<f64>> = (0..m)
        .map(|i| {
            (0..m)
                .map(|j| a[i][m + j] / (scale[i] * scale[j]))
                .collect()
        })
        .collect();
    let residuals: Vec<f64> = basis
        .iter()
        .zip(y)
        .map(|(row, value)| {
            value
                - row
                    .iter()
                    .zip(&coefficients)
                    .map(|(x, c)| x * c)
                    .sum::<f64>()
        })
        .collect();
    let weighted_residual_sum: f64 = residuals.iter().zip(w).map(|(r, w)| w * r * r).sum();
    let dof = n - m;
    // Weights normalised to mean 1: the residual variance is per point.
    let variance = weighted_residual_sum / total * n as f64 / dof as f64;
    let mean_weight = total / n as f64;
    let covariance: Vec<Vec<f64>> = unscaled_covariance
        .iter()
        .map(|row| row.iter().map(|c| c * mean_weight * variance).collect())
        .collect();
    let std_errors = (0..m).map(|i| covariance[i][i].max(0.0).sqrt()).collect();
    coefficients
        .iter()
        .all(|c| c.is_finite())
        .then_some(LinearFit {
            coefficients,
            std_errors,
            covariance,
            unscaled_covariance,
            weighted_residual_sum,
            residuals,
            dof,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weighted_line_is_exact_on_a_line() {
        let x = [0.0, 1.0, 2.0, 3.0];
        let y = [1.0, 3.0, 5.0, 7.0];
        let line = weighted_line(&x, &y, &[1.0, 2.0, 3.0, 4.0]);
        assert!((line.slope - 2.0).abs() < 1e-14);
        assert!(line.slope_std_error < 1e-7);
    }

    #[test]
    fn least_squares_is_exact_on_its_basis() {
        let basis: Vec<Vec<f64>> = (0..20)
            .map(|i| {
                let t = i as f64 * 0.1;
                vec![1.0, t, t.cos(), (2.0 * t).sin()]
            })
            .collect();
        let y: Vec<f64> = basis
            .iter()
            .map(|r| 0.5 - 2.0 * r[1] + 0.25 * r[2] + 3.0 * r[3])
            .collect();
        let c = least_squares(&basis, &y, &[1.0; 20]).unwrap();
        for (got, exact) in c.iter().zip([0.5, -2.0, 0.25, 3.0]) {
            assert!((got - exact).abs() < 1e-10, "{c:?}");
        }
    }

    #[test]
    fn weighted_fit_matches_the_line_formula_and_scales_its_columns() {
        // A line through noisy-looking points: the slope's standard error must equal the
        // closed form of `weighted_line`, whatever the scale of the columns.
        let x: Vec<f64> = (0..12).map(|i| 1e3 * i as f64).collect();
        let y: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(i, x)| 2.0 + 3e-3 * x + if i % 3 == 0 { 0.1 } else { -0.05 })
            .collect();
        let w = vec![1.0; 12];
        let basis: Vec<Vec<f64>> = x.iter().map(|x| vec![1.0, *x]).collect();
        let fit = weighted_fit(&basis, &y, &w).unwrap();
        let line = weighted_line(&x, &y, &w);
        assert!((fit.coefficients[1] - line.slope).abs() < 1e-12);
        assert!(
            (fit.std_errors[1] - line.slope_std_error).abs()
                < 1e-12 * line.slope_std_error.max(1e-3)
        );
        assert_eq!(fit.dof, 10);
        // Dependent columns are refused.
        let dependent: Vec<Vec<f64>> = x.iter().map(|x| vec![*x, 2.0 * x]).collect();
        assert!(weighted_fit(&dependent, &y, &w).is_none());
    }
}
