//! M, C and K merged onto one sparse pattern, so that the effective matrix is a
//! value-wise linear combination and the step's right-hand side is one pass over the
//! pattern.
//!
//! The pattern is the union of the three input patterns, compressed sparse column,
//! rows sorted. Values are interleaved per entry as `[m, c, k]`: the fused product
//! `M x_m + C x_c + K x_k` then streams one array instead of three, which is what
//! bounds the step time on the systems of interest (a few thousand DOFs, banded).

use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};

use super::error::IntegrateError;
use super::Operators;

/// Index of each operator in the interleaved value triple.
const M: usize = 0;
const C: usize = 1;
const K: usize = 2;

/// Relative tolerance of the symmetry check: far above the round-off of an
/// assembled element sum (~1e-16 of the largest entry), far below any genuine
/// asymmetry.
const SYMMETRY_TOLERANCE: f64 = 1e-10;

#[derive(Debug, Clone)]
pub(crate) struct MergedOperators {
    pattern: SymbolicSparseColMat<usize>,
    values: Vec<[f64; 3]>,
}

impl MergedOperators {
    pub(crate) fn new(ops: &Operators<'_>) -> Result<Self, IntegrateError> {
        let n = ops.k.nrows();
        let mut inputs: Vec<(usize, &'static str, SparseColMatRef<'_, usize, f64>)> = vec![
            (M, "mass matrix M", ops.m),
            (K, "stiffness matrix K", ops.k),
        ];
        if let Some(c) = ops.c {
            inputs.push((C, "damping matrix C", c));
        }
        for &(_, name, a) in &inputs {
            for (what, found) in [(name, a.nrows()), (name, a.ncols())] {
                if found != n {
                    return Err(IntegrateError::DimensionMismatch {
                        what,
                        expected: n,
                        found,
                    });
                }
            }
        }

        // Union pattern, column by column; `seen[i] == j` marks row i as taken in
        // column j.
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0usize);
        let mut row_idx: Vec<usize> = Vec::new();
        let mut seen = vec![usize::MAX; n];
        for j in 0..n {
            let start = row_idx.len();
            for &(_, _, a) in &inputs {
                for &i in a.symbolic().row_idx_of_col_raw(j) {
                    if seen[i] != j {
                        seen[i] = j;
                        row_idx.push(i);
                    }
                }
            }
            row_idx[start..].sort_unstable();
            col_ptr.push(row_idx.len());
        }

        let mut values = vec![[0.0; 3]; row_idx.len()];
        for &(which, name, a) in &inputs {
            for j in 0..n {
                let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
                for (&i, &v) in a
                    .symbolic()
                    .row_idx_of_col_raw(j)
                    .iter()
                    .zip(a.val_of_col(j))
                {
                    if !v.is_finite() {
                        return Err(IntegrateError::NonFiniteEntry {
                            matrix: name,
                            row: i,
                            col: j,
                        });
                    }
                    // The union holds every input entry, so the search cannot miss.
                    if let Ok(p) = rows.binary_search(&i) {
                        values[col_ptr[j] + p][which] += v;
                    }
                }
            }
        }

        // The constructor is only reached with a pattern built above: sorted, in
        // bounds, no duplicates.
        let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let merged = Self { pattern, values };
        for &(which, name, _) in &inputs {
            merged.check_symmetric(which, name)?;
        }
        Ok(merged)
    }

    pub(crate) fn dim(&self) -> usize {
        self.pattern.nrows()
    }

    pub(crate) fn pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.pattern.as_ref()
    }

    /// Value of operator `which` at (i, j), zero outside the pattern.
    fn get(&self, which: usize, i: usize, j: usize) -> f64 {
        let range = self.pattern.col_range(j);
        let rows = &self.pattern.row_idx()[range.clone()];
        match rows.binary_search(&i) {
            Ok(p) => self.values[range.start + p][which],
            Err(_) => 0.0,
        }
    }

    fn check_symmetric(&self, which: usize, name: &'static str) -> Result<(), IntegrateError> {
        let scale = self
            .values
            .iter()
            .fold(0.0f64, |s, v| s.max(v[which].abs()));
        let tol = SYMMETRY_TOLERANCE * scale;
        for j in 0..self.dim() {
            let range = self.pattern.col_range(j);
            for p in range {
                let i = self.pattern.row_idx()[p];
                if i <= j {
                    continue;
                }
                let value = self.values[p][which];
                let transposed = self.get(which, j, i);
                if (value - transposed).abs() > tol {
                    return Err(IntegrateError::NotSymmetric {
                        matrix: name,
                        row: i,
                        col: j,
                        value,
                        transposed,
                    });
                }
            }
        }
        Ok(())
    }

    /// `out = cm M + cc C + ck K` on the merged pattern.
    pub(crate) fn combine_into(&self, cm: f64, cc: f64, ck: f64, out: &mut [f64]) {
        for (o, v) in out.iter_mut().zip(&self.values) {
            *o = cm * v[M] + cc * v[C] + ck * v[K];
        }
    }

    /// A matrix view of values laid out on the merged pattern.
    pub(crate) fn view<'a>(&'a self, values: &'a [f64]) -> SparseColMatRef<'a, usize, f64> {
        SparseColMatRef::new(self.pattern.as_ref(), values)
    }

    /// `out = f - M x_m - C x_c - K x_k`. No allocation; one pass over the pattern.
    #[allow(non_snake_case)]
    pub(crate) fn residual_into(
        &self,
        f: &[f64],
        x_m: &[f64],
        x_c: &[f64],
        x_k: &[f64],
        out: &mut [f64],
    ) {
        out.copy_from_slice(f);
        let col_ptr = self.pattern.col_ptr();
        let row_idx = self.pattern.row_idx();
        for j in 0..self.dim() {
            let (xm, xc, xk) = (x_m[j], x_c[j], x_k[j]);
            let range = col_ptr[j]..col_ptr[j + 1];
            for (&i, v) in row_idx[range.clone()].iter().zip(&self.values[range]) {
                out[i] -= v[M] * xm + v[C] * xc + v[K] * xk;
            }
        }
    }

    /// True where the mass matrix's column is identically zero (a massless DOF).
    pub(crate) fn massless_dofs(&self) -> Vec<bool> {
        (0..self.dim())
            .map(|j| {
                self.values[self.pattern.col_range(j)]
                    .iter()
                    .all(|v| v[M] == 0.0)
            })
            .collect()
    }

    /// The mass matrix restricted to the DOFs `keep` (sorted), renumbered 0..keep.len().
    pub(crate) fn mass_submatrix(&self, keep: &[usize]) -> SparseColMat<usize, f64> {
        let n = self.dim();
        let mut new_index = vec![usize::MAX; n];
        for (new, &old) in keep.iter().enumerate() {
            new_index[old] = new;
        }
        let mut col_ptr = Vec::with_capacity(keep.len() + 1);
        col_ptr.push(0usize);
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        for &j in keep {
            let range = self.pattern.col_range(j);
            for p in range {
                let i = new_index[self.pattern.row_idx()[p]];
                if i != usize::MAX {
                    row_idx.push(i);
                    values.push(self.values[p][M]);
                }
            }
            col_ptr.push(row_idx.len());
        }
        // Renumbering by a sorted `keep` preserves the sorted row order.
        let m = keep.len();
        SparseColMat::new(
            SymbolicSparseColMat::new_checked(m, m, col_ptr, None, row_idx),
            values,
        )
    }
}
