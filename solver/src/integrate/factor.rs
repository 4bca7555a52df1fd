//! Sparse Cholesky factor of a symmetric positive definite matrix, with the symbolic
//! analysis done once and every numeric (re)factorisation and solve running in
//! buffers allocated up front.
//!
//! This is the integrators' only contact with the sparse direct solver, kept behind
//! three calls (`analyse`, `factor`, `solve_in_place`) so that it can be swapped for
//! the engine's `linalg` wrapper without touching the schemes.
//!
//! faer's `SymbolicCholesky` computes an AMD fill-reducing ordering and picks a
//! simplicial or supernodal factor; `factorize_numeric_llt` then only needs the values.
//! Only the lower triangle of the matrix is read (`Side::Lower`); the caller passes a
//! symmetric matrix with both triangles stored. Everything runs sequentially
//! (`Par::Seq`): the systems here are banded and small enough that threading costs
//! more than it gains, and the machine is shared.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use super::error::IntegrateError;

/// An SPD factor `A = P^T L L^T P` whose symbolic part is reused across values.
pub(crate) struct SpdFactor {
    /// What is factored, for error messages ("effective matrix", "mass matrix").
    name: &'static str,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    factor_mem: MemBuffer,
    solve_mem: MemBuffer,
    /// False until a numeric factorisation has succeeded, and again after one fails.
    factored: bool,
}

impl std::fmt::Debug for SpdFactor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SpdFactor")
            .field("name", &self.name)
            .field("n", &self.symbolic.nrows())
            .field("l_nnz", &self.l_values.len())
            .field("factored", &self.factored)
            .finish()
    }
}

impl SpdFactor {
    /// Symbolic analysis (ordering, elimination tree, factor pattern) of `pattern`.
    pub(crate) fn analyse(
        name: &'static str,
        pattern: SymbolicSparseColMatRef<'_, usize>,
    ) -> Result<Self, IntegrateError> {
        Self::analyse_with(name, pattern, SupernodalThreshold::AUTO)
    }

    pub(crate) fn analyse_with(
        name: &'static str,
        pattern: SymbolicSparseColMatRef<'_, usize>,
        supernodal: SupernodalThreshold,
    ) -> Result<Self, IntegrateError> {
        let generic = |e: &dyn std::fmt::Debug| IntegrateError::Factorization {
            matrix: name,
            message: format!("{e:?}"),
        };
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: supernodal,
            ..Default::default()
        };
        let symbolic =
            factorize_symbolic_cholesky(pattern, Side::Lower, SymmetricOrdering::Amd, params)
                .map_err(|e| generic(&e))?;
        let factor_req =
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default());
        let solve_req = symbolic.solve_in_place_scratch::<f64>(1, Par::Seq);
        let factor_mem = MemBuffer::try_new(factor_req).map_err(|e| generic(&e))?;
        let solve_mem =
            MemBuffer::try_new(StackReq::any_of(&[solve_req])).map_err(|e| generic(&e))?;
        let l_values = vec![0.0; symbolic.len_val()];
        Ok(Self {
            name,
            symbolic,
            l_values,
            factor_mem,
            solve_mem,
            factored: false,
        })
    }

    /// Order of the matrix.
    pub(crate) fn dim(&self) -> usize {
        self.symbolic.nrows()
    }

    /// Numeric factorisation of `a`, which must have the analysed pattern.
    /// No allocation.
    pub(crate) fn factor(
        &mut self,
        a: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), IntegrateError> {
        self.factored = false;
        let result = self.symbolic.factorize_numeric_llt::<f64>(
            &mut self.l_values,
            a,
            Side::Lower,
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut self.factor_mem),
            Default::default(),
        );
        match result {
            Ok(_) => {
                self.factored = true;
                Ok(())
            }
            Err(LltError::NonPositivePivot { index }) => Err(IntegrateError::NotPositiveDefinite {
                matrix: self.name,
                dof: self.original_index(index),
            }),
        }
    }

    /// Solves `A x = rhs` in place. No allocation.
    ///
    /// Only called after a successful [`SpdFactor::factor`]; the schemes check that
    /// first, so a stale factor is a logic error, reported by a debug assertion.
    pub(crate) fn solve_in_place(&mut self, rhs: &mut [f64]) {
        debug_assert!(
            self.factored,
            "solve with a failed or missing factorisation"
        );
        let n = rhs.len();
        let llt = LltRef::<'_, usize, f64>::new(&self.symbolic, &self.l_values);
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            Par::Seq,
            MemStack::new(&mut self.solve_mem),
        );
    }

    #[cfg(test)]
    pub(crate) fn is_factored(&self) -> bool {
        self.factored
    }

    /// Maps the failed pivot's position in the permuted elimination order back to the
    /// caller's numbering. faer reports it 1-based from the simplicial kernel and
    /// 0-based from the supernodal (dense block) kernel.
    fn original_index(&self, index: usize) -> usize {
        let n = self.dim();
        let position = match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => index.saturating_sub(1),
            SymbolicCholeskyRaw::Supernodal(_) => index,
        }
        .min(n.saturating_sub(1));
        match self.symbolic.perm() {
            Some(perm) => perm.arrays().0[position],
            None => position,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::{SparseColMat, Triplet};

    fn tridiagonal(n: usize, diag: impl Fn(usize) -> f64) -> SparseColMat<usize, f64> {
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, diag(i)));
            if i + 1 < n {
                t.push(Triplet::new(i, i + 1, -1.0));
                t.push(Triplet::new(i + 1, i, -1.0));
            }
        }
        SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
    }

    #[test]
    fn solves_and_refactors_with_the_same_symbolic() {
        let n = 50;
        for threshold in [
            SupernodalThreshold::FORCE_SIMPLICIAL,
            SupernodalThreshold::FORCE_SUPERNODAL,
        ] {
            let a = tridiagonal(n, |_| 4.0);
            let mut f = SpdFactor::analyse_with("test", a.symbolic(), threshold).unwrap();
            for scale in [1.0, 3.0] {
                let a = tridiagonal(n, |_| 4.0 * scale);
                f.factor(a.as_ref()).unwrap();
                let x: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
                let mut b = vec![0.0; n];
                for (i, bi) in b.iter_mut().enumerate() {
                    *bi = 4.0 * scale * x[i];
                    if i > 0 {
                        *bi -= x[i - 1];
                    }
                    if i + 1 < n {
                        *bi -= x[i + 1];
                    }
                }
                f.solve_in_place(&mut b);
                // Diagonally dominant, condition number < 3: round-off level.
                for i in 0..n {
                    assert!((b[i] - x[i]).abs() < 1e-13, "{i}: {} vs {}", b[i], x[i]);
                }
            }
        }
    }

    #[test]
    fn failed_pivot_names_the_offending_dof() {
        // Diagonal matrix with one negative entry: whatever the ordering, the pivot of
        // that DOF is the first (and only) one to fail.
        let n = 40;
        for threshold in [
            SupernodalThreshold::FORCE_SIMPLICIAL,
            SupernodalThreshold::FORCE_SUPERNODAL,
        ] {
            for bad in [0, 17, n - 1] {
                let t: Vec<_> = (0..n)
                    .map(|i| Triplet::new(i, i, if i == bad { -1.0 } else { 2.0 }))
                    .collect();
                let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
                let mut f = SpdFactor::analyse_with("test", a.symbolic(), threshold).unwrap();
                match f.factor(a.as_ref()) {
                    Err(IntegrateError::NotPositiveDefinite { dof, .. }) => assert_eq!(dof, bad),
                    other => panic!("expected a pivot failure, got {other:?}"),
                }
                assert!(!f.is_factored());
            }
        }
    }
}
