//! Linear algebra of the engine: every factorisation of a symmetric positive definite
//! matrix lives here, with the symmetric products and the shift-invert operator of the
//! modal analysis.
//!
//! # The factorisations, and why there are four
//! Each serves a shape of matrix the others are slow or wrong on; they are not folded
//! further because each is measured faster on its own use (`docs/integrators.md`):
//! - [`Cholesky`] / [`SymbolicFactor`] (this file): faer's sparse Cholesky of the
//!   reduced stiffness (or any SPD matrix on the assembler's pattern), simplicial or
//!   supernodal by faer's heuristic, with the pivot-ratio check below that turns a
//!   mechanism into an error naming its DOF. Static and modal cases, modal
//!   superposition, the quasi-static initial velocity, reduction (`reduce`).
//! - `sparse_spd::SpdFactor`: faer's simplicial Cholesky under AMD with hand-written
//!   dot-product solves (about twice as fast as faer's solve on narrow systems), for
//!   tens of thousands of solves per transient: the effective matrix of the general
//!   sparse stepper engine and the mass matrix of the initial acceleration.
//! - `profile::ProfileCholesky` with the block panels of `blocked`: the envelope
//!   (skyline) Cholesky under the envelope-minimising ordering, four-row panels
//!   compiled for AVX2 + FMA where the CPU has them: the banded stepper engine (beam
//!   models), about four times faster per step than the sparse one.
//! - `dense_spd::spd_inverse`: nalgebra's dense Cholesky of a handful of reduced DOFs,
//!   inverted once for the dense stepper (`crate::integrate::dense`).
//!
//! # Triangle convention
//! Symmetric sparse matrices travel between modules as their **upper** triangle,
//! compressed sparse column (`Side::Upper`): the assembler builds them so, the
//! [`crate::analysis::System`] holds `K`, `M`, `C` so, [`Cholesky`],
//! [`sym_upper_matvec`], [`ShiftInvert`] and `reduce` read them so, and the stepper
//! takes them so ([`crate::integrate::Stepper::new_upper`]); no module expands them on
//! the way from assembly to the stepper. Inside the stepper engines the merged
//! operators, `SpdFactor` and the envelope factor store the transpose, the lower
//! triangle (`Side::Lower`, row >= column), the same numbers: their kernels walk the
//! factor `L` by rows forward and by columns backward, which is that side. Two
//! exceptions at the edges, for callers outside this convention: the integrators'
//! [`crate::integrate::Stepper::new`] accepts full matrices (both triangles, checked
//! symmetric) and [`upper_to_full`] makes them.
//!
//! # Factorisation (the stiffness)
//! [`SymbolicFactor::analyze`] runs faer's symbolic Cholesky once per pattern (AMD
//! fill-reducing ordering, then simplicial or supernodal by faer's flop heuristic);
//! [`SymbolicFactor::factor`] and [`Cholesky::factor_in_place`] compute numeric
//! factors `P A P^T = L L^T` that reuse it, so a new matrix on the same pattern (a
//! tuner's new E) costs only the numeric part. Matrices are given as their upper
//! triangle (`Side::Upper`).
//!
//! # Singularity
//! A mechanism makes the reduced stiffness singular. In floating point its pivot is
//! rarely exactly zero: it comes out as rounding noise of either sign. So two checks:
//! - faer stops at a non-positive pivot; its index (in the permuted order) is mapped
//!   back through the permutation to the equation;
//! - after a successful factorisation every pivot `d_j = L_jj^2` is compared with the
//!   diagonal `A_jj` of the same equation. The ratio `d_j / A_jj` is the pivot of the
//!   unit-diagonal scaling `D^-1/2 A D^-1/2`, so it is independent of units (mm vs rad).
//!   It lies in (0, 1]; it is the fraction of its own stiffness a DOF keeps once all
//!   DOFs eliminated before it are allowed to move.
//!
//! The threshold [`PIVOT_RATIO_TOL`] = 1e-11 sits between the two populations:
//! - a zero pivot of the unit-diagonal matrix comes out as rounding noise, a sum of
//!   about (row count of L) terms each with relative error `eps`: `~ 10-100 eps`, i.e.
//!   `2e-15..2e-14`, and even with a generous growth factor below `1e-12`;
//! - real structures stay many decades above: with AMD ordering the smallest ratio
//!   measured is 0.07..0.24 on cantilevers of 10 to 200 elements and 4e-3..0.2 on the
//!   paper's spring from 8 to 192 elements per coil (3e-4..4e-3 with other supports).
//!   The unsupported beams and springs tried all stop at a negative pivot (the first
//!   check); the second one is exercised by a unit test with a pivot of 1e-14.
//!
//! With the pivot's rounding error near `1e-14` of the diagonal, a ratio of 1e-11
//! leaves about three significant digits of the DOF's stiffness; below it a linear
//! solve is no longer meaningful, so it is reported as a mechanism rather than
//! returning displacements amplified by 1e11.

pub(crate) mod blocked;
pub(crate) mod dense_spd;
pub(crate) mod profile;
pub(crate) mod sparse_spd;

use crate::error::solve::SolveError;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::matrix_free::LinOp;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMatRef, Triplet};
use faer::{Conj, MatMut, MatRef, Par, Side};
use std::sync::Arc;

/// Smallest admissible pivot ratio `d_j / A_jj` (see the module docs for why 1e-11).
pub const PIVOT_RATIO_TOL: f64 = 1e-11;

/// faer's choice between the two numeric Cholesky kernels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kernel {
    /// faer's flop-ratio heuristic.
    #[default]
    Auto,
    /// faer's simplicial (column by column) kernel, forced.
    Simplicial,
    /// faer's supernodal (dense block) kernel, forced.
    Supernodal,
}

/// Why a numeric factorisation failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FactorError {
    /// Equation `equation` (original numbering) has a non-positive or negligible pivot.
    #[error("singular matrix at equation {equation} (pivot {pivot:e}, diagonal {diagonal:e})")]
    Singular {
        /// The equation (original numbering) with the bad pivot.
        equation: usize,
        /// The pivot found there (NaN when faer stopped before it).
        pivot: f64,
        /// The matrix's diagonal entry at that equation.
        diagonal: f64,
    },
    /// faer could not allocate its workspace or the input does not fit the pattern.
    #[error("{0}")]
    Other(String),
}

/// The symbolic Cholesky of a pattern, shared by all factors on it.
#[derive(Debug, Clone)]
pub struct SymbolicFactor {
    inner: Arc<SymbolicCholesky<usize>>,
}

impl SymbolicFactor {
    /// Symbolic analysis of an upper-triangle pattern with AMD ordering.
    pub fn analyze(pattern: SymbolicSparseColMatRef<'_, usize>) -> Result<Self, SolveError> {
        Self::analyze_with(pattern, Kernel::Auto)
    }

    /// As [`SymbolicFactor::analyze`], forcing a kernel (tests use it to cover both).
    pub fn analyze_with(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        kernel: Kernel,
    ) -> Result<Self, SolveError> {
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: match kernel {
                Kernel::Auto => SupernodalThreshold::AUTO,
                Kernel::Simplicial => SupernodalThreshold::FORCE_SIMPLICIAL,
                Kernel::Supernodal => SupernodalThreshold::FORCE_SUPERNODAL,
            },
            ..Default::default()
        };
        let inner =
            factorize_symbolic_cholesky(pattern, Side::Upper, SymmetricOrdering::Amd, params)
                .map_err(|e| SolveError::Linalg(format!("symbolic Cholesky: {e:?}")))?;
        Ok(SymbolicFactor {
            inner: Arc::new(inner),
        })
    }

    /// Number of equations.
    pub fn dim(&self) -> usize {
        self.inner.nrows()
    }

    /// Whether faer chose the supernodal kernel.
    pub fn is_supernodal(&self) -> bool {
        matches!(self.inner.raw(), SymbolicCholeskyRaw::Supernodal(_))
    }

    /// Numeric factor of `a` (upper triangle, on the analysed pattern).
    pub fn factor(&self, a: SparseColMatRef<'_, usize, f64>) -> Result<Cholesky, FactorError> {
        let mut chol = Cholesky {
            symbolic: self.inner.clone(),
            values: vec![0.0; self.inner.len_val()],
            min_pivot_ratio: f64::NAN,
        };
        chol.factor_in_place(a)?;
        Ok(chol)
    }
}

/// A numeric Cholesky factor `P A P^T = L L^T`.
#[derive(Debug, Clone)]
pub struct Cholesky {
    symbolic: Arc<SymbolicCholesky<usize>>,
    values: Vec<f64>,
    min_pivot_ratio: f64,
}

/// Diagonal of a square upper-triangle CSC matrix.
fn diagonal(a: SparseColMatRef<'_, usize, f64>) -> Vec<f64> {
    let mut d = vec![0.0; a.ncols()];
    for (j, dj) in d.iter_mut().enumerate() {
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            if i == j {
                *dj += v;
            }
        }
    }
    d
}

impl Cholesky {
    /// Refactors a new matrix on the same pattern, reusing the symbolic analysis.
    pub fn factor_in_place(
        &mut self,
        a: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), FactorError> {
        let n = self.symbolic.nrows();
        if a.nrows() != n || a.ncols() != n {
            return Err(FactorError::Other(format!(
                "matrix is {}x{}, the factor is {n}x{n}",
                a.nrows(),
                a.ncols()
            )));
        }
        let diag = diagonal(a);
        let par = Par::Seq;
        let req = self
            .symbolic
            .factorize_numeric_llt_scratch::<f64>(par, Default::default());
        let mut mem =
            MemBuffer::try_new(req).map_err(|_| FactorError::Other("out of memory".to_string()))?;
        let result = self.symbolic.factorize_numeric_llt(
            &mut self.values,
            a,
            Side::Upper,
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        );
        let perm_fwd: Option<Vec<usize>> = self.symbolic.perm().map(|p| p.arrays().0.to_vec());
        let original = |j: usize| perm_fwd.as_ref().map_or(j, |p| p[j]);
        if let Err(LltError::NonPositivePivot { index }) = result {
            // faer reports the simplicial failure 1-based and the supernodal one
            // 0-based (faer 0.24 sparse/linalg/cholesky.rs); both in permuted order.
            let position = match self.symbolic.raw() {
                SymbolicCholeskyRaw::Simplicial(_) => index.saturating_sub(1),
                SymbolicCholeskyRaw::Supernodal(_) => index,
            }
            .min(n.saturating_sub(1));
            let equation = original(position);
            self.min_pivot_ratio = f64::NAN;
            return Err(FactorError::Singular {
                equation,
                pivot: f64::NAN,
                diagonal: diag.get(equation).copied().unwrap_or(f64::NAN),
            });
        }
        let pivots = self.pivots();
        let mut worst = (f64::INFINITY, 0usize);
        for (j, &l_jj) in pivots.iter().enumerate() {
            let e = original(j);
            let ratio = l_jj * l_jj / diag[e];
            if ratio.is_nan() || ratio < worst.0 {
                worst = (ratio, j);
            }
        }
        self.min_pivot_ratio = worst.0;
        if n > 0 && (worst.0.is_nan() || worst.0 < PIVOT_RATIO_TOL) {
            let e = original(worst.1);
            return Err(FactorError::Singular {
                equation: e,
                pivot: pivots[worst.1] * pivots[worst.1],
                diagonal: diag[e],
            });
        }
        Ok(())
    }

    /// Diagonal of L in the permuted order.
    fn pivots(&self) -> Vec<f64> {
        let n = self.symbolic.nrows();
        let mut out = vec![0.0; n];
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                // Each column of the simplicial L starts with its diagonal.
                let col_ptr = s.col_ptr();
                for (j, o) in out.iter_mut().enumerate() {
                    *o = self.values[col_ptr[j]];
                }
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                let l = supernodal::SupernodalLltRef::new(s, &self.values);
                for k in 0..s.n_supernodes() {
                    let node = l.supernode(k);
                    let start = node.start();
                    let val = node.val();
                    for c in 0..val.ncols() {
                        out[start + c] = val[(c, c)];
                    }
                }
            }
        }
        out
    }

    /// Number of equations.
    pub fn dim(&self) -> usize {
        self.symbolic.nrows()
    }

    /// Smallest pivot ratio `d_j / A_jj` of the last factorisation (a conditioning
    /// diagnostic; see the module docs).
    pub fn min_pivot_ratio(&self) -> f64 {
        self.min_pivot_ratio
    }

    /// Solves `A X = B` in place for the columns of `b`.
    pub fn solve_mat_in_place(&self, b: MatMut<'_, f64>) {
        let par = Par::Seq;
        let req = self.symbolic.solve_in_place_scratch::<f64>(b.ncols(), par);
        let mut mem = MemBuffer::new(req);
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            b,
            par,
            MemStack::new(&mut mem),
        );
    }

    /// Solves `A x = b` in place.
    pub fn solve_in_place(&self, x: &mut [f64]) {
        let n = x.len();
        self.solve_mat_in_place(MatMut::from_column_major_slice_mut(x, n, 1));
    }

    /// The forward permutation (`permuted[i] = original[fwd[i]]`), if any.
    fn fwd(&self) -> Option<&[usize]> {
        self.symbolic.perm().map(|p| p.arrays().0)
    }

    /// `x <- L^-1 x` in the permuted order.
    fn l_solve(&self, x: MatMut<'_, f64>) {
        let par = Par::Seq;
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                let l = SparseColMatRef::new(s.factor(), &self.values);
                faer::sparse::linalg::triangular_solve::solve_lower_triangular_in_place(
                    l,
                    Conj::No,
                    x,
                    par,
                );
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                let mut mem = MemBuffer::new(s.solve_in_place_scratch::<f64>(x.ncols(), par));
                supernodal::SupernodalLltRef::new(s, &self.values).l_solve_with_conj(
                    Conj::No,
                    x,
                    par,
                    MemStack::new(&mut mem),
                );
            }
        }
    }

    /// `x <- L^-T x` in the permuted order.
    fn lt_solve(&self, x: MatMut<'_, f64>) {
        let par = Par::Seq;
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                let l = SparseColMatRef::new(s.factor(), &self.values);
                faer::sparse::linalg::triangular_solve::solve_lower_triangular_transpose_in_place(
                    l,
                    Conj::No,
                    x,
                    par,
                );
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                let mut mem = MemBuffer::new(s.solve_in_place_scratch::<f64>(x.ncols(), par));
                supernodal::SupernodalLltRef::new(s, &self.values).l_transpose_solve_with_conj(
                    Conj::No,
                    x,
                    par,
                    MemStack::new(&mut mem),
                );
            }
        }
    }

    /// `x <- P^T L^-T y`: from the shift-invert operator's space back to equations.
    pub fn back_transform(&self, y: &[f64], x: &mut [f64]) {
        let mut z = y.to_vec();
        let n = z.len();
        self.lt_solve(MatMut::from_column_major_slice_mut(&mut z, n, 1));
        permute_back(self.fwd(), &z, x);
    }
}

/// `out[fwd[i]] = z[i]` (identity without a permutation).
fn permute_back(fwd: Option<&[usize]>, z: &[f64], out: &mut [f64]) {
    match fwd {
        Some(p) => {
            for (i, &f) in p.iter().enumerate() {
                out[f] = z[i];
            }
        }
        None => out.copy_from_slice(z),
    }
}

/// Both triangles of a symmetric matrix stored as its upper triangle: the one triangle
/// conversion, from the system's matrices to the integrators' operators (module docs,
/// "Triangle convention").
pub fn upper_to_full(
    a: SparseColMatRef<'_, usize, f64>,
) -> Result<SparseColMat<usize, f64>, SolveError> {
    let mut triplets = Vec::with_capacity(2 * a.val().len());
    for j in 0..a.ncols() {
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            triplets.push(Triplet::new(i, j, v));
            if i != j {
                triplets.push(Triplet::new(j, i, v));
            }
        }
    }
    SparseColMat::try_new_from_triplets(a.nrows(), a.ncols(), &triplets)
        .map_err(|e| SolveError::Linalg(format!("symmetric expansion: {e:?}")))
}

/// `y += alpha A x` for a symmetric matrix stored as its upper triangle.
pub fn sym_upper_matvec(a: SparseColMatRef<'_, usize, f64>, x: &[f64], alpha: f64, y: &mut [f64]) {
    for j in 0..a.ncols() {
        let xj = alpha * x[j];
        let mut acc = 0.0;
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            y[i] += v * xj;
            if i != j {
                acc += v * x[i];
            }
        }
        y[j] += alpha * acc;
    }
}

/// The symmetric shift-invert operator `scale L^-1 P M P^T L^-T` of `K = P^T L L^T P`,
/// whose eigenvalues are `scale / omega^2` of `K phi = omega^2 M phi`, with
/// eigenvectors `y` giving `phi = P^T L^-T y`.
#[derive(Debug)]
pub struct ShiftInvert<'a> {
    /// The Cholesky factor of K.
    pub factor: &'a Cholesky,
    /// The mass matrix M (its upper triangle is read).
    pub mass: SparseColMatRef<'a, usize, f64>,
    /// The factor multiplying the operator (1 in coil's eigensolves).
    pub scale: f64,
}

impl ShiftInvert<'_> {
    /// Applies the operator to one vector.
    pub fn apply_vec(&self, x: &[f64], out: &mut [f64]) {
        let n = x.len();
        let mut z = x.to_vec();
        self.factor
            .lt_solve(MatMut::from_column_major_slice_mut(&mut z, n, 1));
        let mut w = vec![0.0; n];
        permute_back(self.factor.fwd(), &z, &mut w);
        let mut v = vec![0.0; n];
        sym_upper_matvec(self.mass, &w, self.scale, &mut v);
        match self.factor.fwd() {
            Some(p) => {
                for (o, &f) in out.iter_mut().zip(p) {
                    *o = v[f];
                }
            }
            None => out.copy_from_slice(&v),
        }
        self.factor
            .l_solve(MatMut::from_column_major_slice_mut(out, n, 1));
    }
}

impl LinOp<f64> for ShiftInvert<'_> {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> faer::dyn_stack::StackReq {
        faer::dyn_stack::StackReq::EMPTY
    }

    fn nrows(&self) -> usize {
        self.factor.dim()
    }

    fn ncols(&self) -> usize {
        self.factor.dim()
    }

    fn apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _par: Par, _stack: &mut MemStack) {
        let n = self.factor.dim();
        let mut out = out;
        let mut x = vec![0.0; n];
        let mut y = vec![0.0; n];
        for j in 0..rhs.ncols() {
            for (i, xi) in x.iter_mut().enumerate() {
                *xi = rhs[(i, j)];
            }
            self.apply_vec(&x, &mut y);
            for (i, &yi) in y.iter().enumerate() {
                out[(i, j)] = yi;
            }
        }
    }

    fn conj_apply(
        &self,
        out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        par: Par,
        stack: &mut MemStack,
    ) {
        // Real operator: conjugation is the identity.
        self.apply(out, rhs, par, stack);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Upper triangle of a dense symmetric matrix as a faer CSC matrix.
    fn upper(a: &[&[f64]]) -> SparseColMat<usize, f64> {
        let n = a.len();
        let mut t = Vec::new();
        for (i, row) in a.iter().enumerate() {
            for (j, &v) in row.iter().enumerate().skip(i) {
                if v != 0.0 || i == j {
                    t.push(Triplet::new(i, j, v));
                }
            }
        }
        SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
    }

    /// A 1D Laplacian-like SPD band matrix with a spread of diagonal scales.
    fn spd(n: usize) -> Vec<Vec<f64>> {
        let mut a = vec![vec![0.0; n]; n];
        for i in 0..n {
            let s = 10f64.powi((i % 5) as i32);
            a[i][i] = 4.0 * s;
            if i + 1 < n {
                let c = -(s * 10f64.powi(((i + 1) % 5) as i32)).sqrt();
                a[i][i + 1] = c;
                a[i + 1][i] = c;
            }
        }
        a
    }

    const KERNELS: [Kernel; 2] = [Kernel::Simplicial, Kernel::Supernodal];

    #[test]
    fn solves_match_the_matrix_for_both_kernels() {
        let n = 40;
        let dense = spd(n);
        let rows: Vec<&[f64]> = dense.iter().map(|r| r.as_slice()).collect();
        let a = upper(&rows);
        for kernel in KERNELS {
            let symbolic = SymbolicFactor::analyze_with(a.symbolic(), kernel).unwrap();
            assert_eq!(symbolic.is_supernodal(), kernel == Kernel::Supernodal);
            let chol = symbolic.factor(a.as_ref()).unwrap();
            let x_true: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
            let mut b = vec![0.0; n];
            sym_upper_matvec(a.as_ref(), &x_true, 1.0, &mut b);
            chol.solve_in_place(&mut b);
            let err = b
                .iter()
                .zip(&x_true)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e-12, "{kernel:?}: {err:e}");
            assert!(chol.min_pivot_ratio() > 0.1);
        }
    }

    #[test]
    fn negative_pivot_names_its_equation_for_both_kernels() {
        // Equation 3 is indefinite; AMD may order it anywhere, the name must survive.
        let mut dense = spd(12);
        dense[3][3] = -1.0;
        let rows: Vec<&[f64]> = dense.iter().map(|r| r.as_slice()).collect();
        let a = upper(&rows);
        for kernel in KERNELS {
            let symbolic = SymbolicFactor::analyze_with(a.symbolic(), kernel).unwrap();
            match symbolic.factor(a.as_ref()) {
                Err(FactorError::Singular { equation, .. }) => {
                    assert_eq!(equation, 3, "{kernel:?}")
                }
                other => panic!("{kernel:?}: {other:?}"),
            }
        }
    }

    #[test]
    fn negligible_positive_pivot_is_singular() {
        // Rows 5 and 6 are equal up to 1e-14 relative: the second pivot is 1e-14 of its
        // diagonal, a mechanism in floating point, though positive.
        let mut dense = spd(10);
        for row in dense.iter_mut() {
            row[5] = 0.0;
            row[6] = 0.0;
        }
        dense[5] = vec![0.0; 10];
        dense[6] = vec![0.0; 10];
        dense[5][5] = 1.0;
        dense[5][6] = 1.0;
        dense[6][5] = 1.0;
        dense[6][6] = 1.0 + 1e-14;
        let rows: Vec<&[f64]> = dense.iter().map(|r| r.as_slice()).collect();
        let a = upper(&rows);
        for kernel in KERNELS {
            let symbolic = SymbolicFactor::analyze_with(a.symbolic(), kernel).unwrap();
            match symbolic.factor(a.as_ref()) {
                Err(FactorError::Singular {
                    equation,
                    pivot,
                    diagonal,
                }) => {
                    assert!(equation == 5 || equation == 6);
                    assert!(pivot > 0.0 && pivot / diagonal < PIVOT_RATIO_TOL);
                }
                other => panic!("{kernel:?}: {other:?}"),
            }
        }
    }

    #[test]
    fn refactoring_reuses_the_symbolic_analysis() {
        let dense = spd(20);
        let rows: Vec<&[f64]> = dense.iter().map(|r| r.as_slice()).collect();
        let a = upper(&rows);
        let symbolic = SymbolicFactor::analyze(a.symbolic()).unwrap();
        let mut chol = symbolic.factor(a.as_ref()).unwrap();
        let scaled = SparseColMat::new(
            a.symbolic().to_owned().unwrap(),
            a.val().iter().map(|v| 3.0 * v).collect(),
        );
        chol.factor_in_place(scaled.as_ref()).unwrap();
        let mut x = vec![3.0; 20];
        let mut b = vec![0.0; 20];
        sym_upper_matvec(a.as_ref(), &x, 1.0, &mut b);
        chol.solve_in_place(&mut b);
        x.iter_mut().for_each(|v| *v = 1.0);
        assert!(b.iter().zip(&x).all(|(p, q)| (p - q).abs() < 1e-13));
    }

    #[test]
    fn full_expansion_matches_the_symmetric_product() {
        let dense = spd(9);
        let rows: Vec<&[f64]> = dense.iter().map(|r| r.as_slice()).collect();
        let a = upper(&rows);
        let full = upper_to_full(a.as_ref()).unwrap();
        let x: Vec<f64> = (0..9).map(|i| 1.0 + i as f64).collect();
        let mut y = vec![0.0; 9];
        sym_upper_matvec(a.as_ref(), &x, 1.0, &mut y);
        let z = &full * faer::ColRef::from_slice(&x);
        for i in 0..9 {
            assert!((y[i] - z[i]).abs() < 1e-12 * y[i].abs().max(1.0));
        }
        assert_eq!(full.val().len(), 2 * a.val().len() - 9);
    }

    /// The shift-invert operator is symmetric, and its eigenvector maps back to a
    /// solution of the generalised problem.
    #[test]
    fn shift_invert_operator_is_symmetric() {
        let n = 15;
        let k = spd(n);
        let m: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        if i == j {
                            2.0
                        } else if i.abs_diff(j) == 1 {
                            0.5
                        } else {
                            0.0
                        }
                    })
                    .collect()
            })
            .collect();
        let (kr, mr): (Vec<&[f64]>, Vec<&[f64]>) = (
            k.iter().map(|r| r.as_slice()).collect(),
            m.iter().map(|r| r.as_slice()).collect(),
        );
        let (k, m) = (upper(&kr), upper(&mr));
        for kernel in KERNELS {
            let chol = SymbolicFactor::analyze_with(k.symbolic(), kernel)
                .unwrap()
                .factor(k.as_ref())
                .unwrap();
            let op = ShiftInvert {
                factor: &chol,
                mass: m.as_ref(),
                scale: 1.0,
            };
            let x: Vec<f64> = (0..n).map(|i| (i as f64).cos()).collect();
            let y: Vec<f64> = (0..n).map(|i| (1.7 * i as f64).sin()).collect();
            let (mut ax, mut ay) = (vec![0.0; n], vec![0.0; n]);
            op.apply_vec(&x, &mut ax);
            op.apply_vec(&y, &mut ay);
            let d1: f64 = y.iter().zip(&ax).map(|(a, b)| a * b).sum();
            let d2: f64 = x.iter().zip(&ay).map(|(a, b)| a * b).sum();
            assert!(
                (d1 - d2).abs() < 1e-13 * d1.abs().max(1e-3),
                "{kernel:?}: {d1} vs {d2}"
            );
        }
    }
}
