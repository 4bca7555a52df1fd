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
}
