//! The inverse of a small dense symmetric positive definite matrix (a reduced model's
//! effective and mass matrices, a handful of DOFs, inverted once per stepper), through
//! nalgebra's Cholesky factor of the unit-diagonal scaling `D A D`,
//! `D = diag(A)^-1/2`, so that the mixed units of reduced coordinates (mm, rad, modal)
//! do not spoil it.

use crate::error::integrate::IntegrateError;
use nalgebra::DMatrix;

/// Inverse of a symmetric positive definite matrix through the Cholesky factor of its
/// unit-diagonal scaling `D A D`.
pub(crate) fn spd_inverse(
    name: &'static str,
    a: &DMatrix<f64>,
) -> Result<DMatrix<f64>, IntegrateError> {
    let r = a.nrows();
    let mut d = Vec::with_capacity(r);
    for i in 0..r {
        let aii = a[(i, i)];
        if aii.is_nan() || aii <= 0.0 {
            return Err(IntegrateError::NotPositiveDefinite {
                matrix: name,
                dof: i,
            });
        }
        d.push(1.0 / aii.sqrt());
    }
    let scaled = DMatrix::from_fn(r, r, |i, j| d[i] * 0.5 * (a[(i, j)] + a[(j, i)]) * d[j]);
    let chol = scaled
        .cholesky()
        .ok_or(IntegrateError::NotPositiveDefinite {
            matrix: name,
            dof: 0,
        })?;
    let inv = chol.inverse();
    Ok(DMatrix::from_fn(r, r, |i, j| d[i] * inv[(i, j)] * d[j]))
}
