//! M, C and K merged onto one symmetric sparse pattern: the checked form of the
//! operators every engine starts from, the effective matrix as a value-wise linear
//! combination, the right-hand side of the general sparse path as one pass over that
//! pattern, and the recognition of Rayleigh damping.
//!
//! The pattern is the union of the three input patterns. Only its lower triangle
//! (row >= column) is kept, compressed sparse column with sorted rows: the Cholesky
//! factorisation reads only that side, and the symmetric product `M x + C y + K z`
//! uses each off-diagonal entry twice (once as (i, j), once as (j, i)). The three
//! input vectors are interleaved per DOF as `[x, y, z]`, so each entry gathers one
//! 24-byte chunk; the values are one array per operator, so a product that does not
//! need M (average acceleration, HHT) or has no C does not stream it.

use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};

use crate::error::integrate::IntegrateError;

/// The structural operators of `M a + C v + K u = f(t)`.
#[derive(Debug, Clone, Copy)]
pub struct Operators<'a> {
    /// Mass matrix: symmetric positive semi-definite; zero columns mark massless DOFs.
    pub m: SparseColMatRef<'a, usize, f64>,
    /// Viscous damping matrix (symmetric positive semi-definite), or `None` for none.
    pub c: Option<SparseColMatRef<'a, usize, f64>>,
    /// Stiffness matrix: symmetric positive semi-definite.
    pub k: SparseColMatRef<'a, usize, f64>,
}

/// Index of each operator in the interleaved value triple.
pub(crate) const M: usize = 0;
pub(crate) const C: usize = 1;
pub(crate) const K: usize = 2;

/// Relative tolerance of the symmetry check: far above the round-off of an
/// assembled element sum (~1e-16 of the largest entry), far below any genuine
/// asymmetry.
const SYMMETRY_TOLERANCE: f64 = 1e-10;

/// Largest off-diagonal mismatch, relative to the largest term, for which
/// `alpha M + beta K` stands for the damping matrix: a few thousand ulps, far above
/// the round-off of summing `alpha M_e + beta K_e` element by element (measured:
/// about 1e-16 on the paper spring), far below any damping that is not of that form.
pub(crate) const RAYLEIGH_TOLERANCE: f64 = 1e-12;

/// Damping as `C = alpha M + beta K + diag(diagonal)` (see
/// [`MergedOperators::rayleigh_split`]).
#[derive(Debug, Clone)]
pub(crate) struct RayleighSplit {
    pub(crate) alpha: f64,
    pub(crate) beta: f64,
    /// Per DOF (caller's numbering).
    pub(crate) diagonal: Vec<f64>,
    /// Largest off-diagonal mismatch relative to the largest term (tests).
    #[cfg(test)]
    pub(crate) residual: f64,
}

#[derive(Debug, Clone)]
pub(crate) struct MergedOperators {
    /// Lower triangle of the union pattern.
    pattern: SymbolicSparseColMat<usize>,
    /// The pattern's row indices as `u32`, for the product's inner loop.
    rows: Vec<u32>,
    /// Values of M, C, K on the lower pattern (C empty when absent).
    values: [Vec<f64>; 3],
}

impl MergedOperators {
    /// Merges operators given with both triangles stored, checked symmetric.
    pub(crate) fn new(ops: &Operators<'_>) -> Result<Self, IntegrateError> {
        Self::merge(ops, false)
    }

    /// Merges operators given as their upper triangles (the crate's convention,
    /// `crate::linalg`): each is transposed to its lower triangle, the values unchanged,
    /// so the result is the one [`MergedOperators::new`] builds from both triangles.
    pub(crate) fn new_upper(ops: &Operators<'_>) -> Result<Self, IntegrateError> {
        let lower = |name: &'static str, a: SparseColMatRef<'_, usize, f64>| {
            for j in 0..a.ncols() {
                if let Some(&i) = a.row_idx_of_col_raw(j).iter().find(|&&i| i > j) {
                    return Err(IntegrateError::Factorization {
                        matrix: name,
                        message: format!(
                            "expected the upper triangle only, found entry ({i}, {j}) below the diagonal"
                        ),
                    });
                }
            }
            a.transpose()
                .to_col_major()
                .map_err(|e| IntegrateError::Factorization {
                    matrix: name,
                    message: format!("transposing the upper triangle: {e:?}"),
                })
        };
        let m = lower("mass matrix M", ops.m)?;
        let k = lower("stiffness matrix K", ops.k)?;
        let c = ops.c.map(|c| lower("damping matrix C", c)).transpose()?;
        let lower_ops = Operators {
            m: m.as_ref(),
            c: c.as_ref().map(|c| c.as_ref()),
            k: k.as_ref(),
        };
        Self::merge(&lower_ops, true)
    }

    /// The merge of [`MergedOperators::new`]; `lower_only` inputs hold their lower
    /// triangles (from [`MergedOperators::new_upper`]), so there is no other triangle to
    /// check symmetry against (a non-finite entry is reported at its upper position).
    fn merge(ops: &Operators<'_>, lower_only: bool) -> Result<Self, IntegrateError> {
        let n = ops.k.nrows();
        let mut inputs: Vec<(usize, &'static str, SparseColMatRef<'_, usize, f64>)> = vec![
            (M, "mass matrix M", ops.m),
            (K, "stiffness matrix K", ops.k),
        ];
        if let Some(c) = ops.c {
            inputs.push((C, "damping matrix C", c));
        }
        for &(_, name, a) in &inputs {
            for found in [a.nrows(), a.ncols()] {
                if found != n {
                    return Err(IntegrateError::DimensionMismatch {
                        what: name,
                        expected: n,
                        found,
                    });
                }
            }
        }
        if u32::try_from(n).is_err() {
            return Err(IntegrateError::Factorization {
                matrix: "operators",
                message: format!("{n} DOFs exceed the 32-bit index range"),
            });
        }

        // Full union pattern, column by column; `seen[i] == j` marks row i as taken
        // in column j.
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
                        let (row, col) = if lower_only { (j, i) } else { (i, j) };
                        return Err(IntegrateError::NonFiniteEntry {
                            matrix: name,
                            row,
                            col,
                        });
                    }
                    // The union holds every input entry, so the search cannot miss.
                    if let Ok(p) = rows.binary_search(&i) {
                        values[col_ptr[j] + p][which] += v;
                    }
                }
            }
        }
        if !lower_only {
            for &(which, name, _) in &inputs {
                check_symmetric(&col_ptr, &row_idx, &values, which, name)?;
            }
        }

        // Keep the lower triangle.
        let mut lower_ptr = Vec::with_capacity(n + 1);
        lower_ptr.push(0usize);
        let mut lower_rows = Vec::new();
        let mut lower_values: [Vec<f64>; 3] = Default::default();
        for j in 0..n {
            for p in col_ptr[j]..col_ptr[j + 1] {
                if row_idx[p] >= j {
                    lower_rows.push(row_idx[p]);
                    for (which, v) in lower_values.iter_mut().enumerate() {
                        v.push(values[p][which]);
                    }
                }
            }
            lower_ptr.push(lower_rows.len());
        }
        // Every index is below n, checked above to fit in u32.
        let rows = lower_rows.iter().map(|&i| i as u32).collect();
        // Sorted, in bounds, no duplicates by construction.
        let pattern = SymbolicSparseColMat::new_checked(n, n, lower_ptr, None, lower_rows);
        Ok(Self {
            pattern,
            rows,
            values: {
                if ops.c.is_none() {
                    lower_values[C] = Vec::new();
                }
                lower_values
            },
        })
    }

    pub(crate) fn dim(&self) -> usize {
        self.pattern.nrows()
    }

    /// Lower triangle of the merged pattern.
    pub(crate) fn pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.pattern.as_ref()
    }

    /// Whether a damping matrix was given.
    pub(crate) fn has_damping(&self) -> bool {
        !self.values[C].is_empty()
    }

    /// Values of operator `which` ([`M`], [`C`], [`K`]) on the lower pattern, or
    /// `None` for an absent damping matrix.
    pub(crate) fn values(&self, which: usize) -> Option<&[f64]> {
        let v = &self.values[which];
        (which != C || !v.is_empty()).then_some(v.as_slice())
    }

    /// Number of stored (lower-triangle) entries.
    pub(crate) fn nnz(&self) -> usize {
        self.rows.len()
    }

    /// `out = cm M + cc C + ck K` on the lower pattern.
    pub(crate) fn combine_into(&self, cm: f64, cc: f64, ck: f64, out: &mut [f64]) {
        for (p, o) in out.iter_mut().enumerate() {
            let c = self.values[C].get(p).copied().unwrap_or(0.0);
            *o = cm * self.values[M][p] + cc * c + ck * self.values[K][p];
        }
    }

    /// A lower-triangle matrix view of values laid out on the pattern.
    pub(crate) fn view<'a>(&'a self, values: &'a [f64]) -> SparseColMatRef<'a, usize, f64> {
        SparseColMatRef::new(self.pattern.as_ref(), values)
    }

    /// `out = f - (M x + C y + K z)` with `xyz[i] = [x_i, y_i, z_i]`. No allocation;
    /// one pass over the lower pattern. `with_m = false` skips M when its vector is
    /// zero (average acceleration and HHT have `alpha_m = 0`); C is skipped when
    /// absent.
    pub(crate) fn residual_into(&self, f: &[f64], xyz: &[[f64; 3]], with_m: bool, out: &mut [f64]) {
        match (with_m, self.has_damping()) {
            (true, true) => self.residual_kernel::<true, true>(f, xyz, out),
            (true, false) => self.residual_kernel::<true, false>(f, xyz, out),
            (false, true) => self.residual_kernel::<false, true>(f, xyz, out),
            (false, false) => self.residual_kernel::<false, false>(f, xyz, out),
        }
    }

    fn residual_kernel<const WITH_M: bool, const WITH_C: bool>(
        &self,
        f: &[f64],
        xyz: &[[f64; 3]],
        out: &mut [f64],
    ) {
        let [m, c, k] = &self.values;
        let apply = |p: usize, x: [f64; 3]| {
            let mut s = k[p] * x[K];
            if WITH_C {
                s += c[p] * x[C];
            }
            if WITH_M {
                s += m[p] * x[M];
            }
            s
        };
        out.copy_from_slice(f);
        let col_ptr = self.pattern.col_ptr();
        for (j, w) in col_ptr.windows(2).enumerate() {
            let xj = xyz[j];
            let (mut start, end) = (w[0], w[1]);
            let (mut row_j0, mut row_j1) = (0.0, 0.0);
            if self.rows.get(start).is_some_and(|&i| i as usize == j) {
                row_j0 = apply(start, xj);
                start += 1;
            }
            // Column j below the diagonal contributes to rows i (scatter) and, by
            // symmetry, row j gathers the same entries against x_i (dot product, two
            // partial sums against the add-latency chain).
            let mut p = start;
            while p + 1 < end {
                let (i0, i1) = (self.rows[p] as usize, self.rows[p + 1] as usize);
                out[i0] -= apply(p, xj);
                out[i1] -= apply(p + 1, xj);
                row_j0 += apply(p, xyz[i0]);
                row_j1 += apply(p + 1, xyz[i1]);
                p += 2;
            }
            if p < end {
                let i = self.rows[p] as usize;
                out[i] -= apply(p, xj);
                row_j0 += apply(p, xyz[i]);
            }
            out[j] -= row_j0 + row_j1;
        }
    }

    /// `C = alpha M + beta K + D` with `D` diagonal, when the damping matrix is
    /// Rayleigh damping up to a diagonal (coil's `DAMPING` on elements, with point
    /// masses left out or named), to round-off: every off-diagonal entry within
    /// [`RAYLEIGH_TOLERANCE`] of the largest term. `alpha`, `beta` come from a
    /// least-squares fit over the off-diagonal entries (columns scaled to unit size);
    /// `D` is the exact remainder on the diagonal. `None` without damping, for a
    /// diagonal `C` (no fit needed), or when no such split reproduces `C`.
    pub(crate) fn rayleigh_split(&self) -> Option<RayleighSplit> {
        let [m, c, k] = &self.values;
        if c.is_empty() {
            return None;
        }
        let pattern = self.pattern.as_ref();
        let off_diagonal = |f: &mut dyn FnMut(usize)| {
            for j in 0..self.dim() {
                for p in pattern.col_range(j) {
                    if self.rows[p] as usize != j {
                        f(p);
                    }
                }
            }
        };
        let (mut sm, mut sk, mut sc) = (0.0f64, 0.0f64, 0.0f64);
        off_diagonal(&mut |p| {
            sm = sm.max(m[p].abs());
            sk = sk.max(k[p].abs());
            sc = sc.max(c[p].abs());
        });
        if sc == 0.0 {
            return None;
        }
        // Normal equations of c ~ alpha' (m / sm) + beta' (k / sk).
        let (mut aa, mut ab, mut bb, mut ac, mut bc) = (0.0, 0.0, 0.0, 0.0, 0.0);
        off_diagonal(&mut |p| {
            let a = if sm > 0.0 { m[p] / sm } else { 0.0 };
            let b = if sk > 0.0 { k[p] / sk } else { 0.0 };
            aa += a * a;
            ab += a * b;
            bb += b * b;
            ac += a * c[p];
            bc += b * c[p];
        });
        let det = aa * bb - ab * ab;
        let (alpha, beta) = if aa > 0.0 && bb > 0.0 && det > 1e-8 * aa * bb {
            (
                (ac * bb - bc * ab) / det / sm,
                (bc * aa - ac * ab) / det / sk,
            )
        } else if bb > 0.0 && aa == 0.0 {
            (0.0, bc / bb / sk)
        } else if aa > 0.0 && bb == 0.0 {
            (ac / aa / sm, 0.0)
        } else {
            return None;
        };
        let mut worst = 0.0f64;
        let mut size = 0.0f64;
        off_diagonal(&mut |p| {
            worst = worst.max((c[p] - alpha * m[p] - beta * k[p]).abs());
            size = size.max(c[p].abs() + (alpha * m[p]).abs() + (beta * k[p]).abs());
        });
        // (NaN fails too.)
        if worst.partial_cmp(&(RAYLEIGH_TOLERANCE * size)) != Some(std::cmp::Ordering::Less) {
            return None;
        }
        let mut diagonal = vec![0.0; self.dim()];
        for (j, d) in diagonal.iter_mut().enumerate() {
            for p in pattern.col_range(j) {
                if self.rows[p] as usize == j {
                    *d = c[p] - alpha * m[p] - beta * k[p];
                }
            }
        }
        Some(RayleighSplit {
            alpha,
            beta,
            diagonal,
            #[cfg(test)]
            residual: worst / size,
        })
    }

    /// True where the mass matrix's row and column are identically zero (a massless
    /// DOF).
    pub(crate) fn massless_dofs(&self) -> Vec<bool> {
        let mut massless = vec![true; self.dim()];
        for (j, w) in self.pattern.col_ptr().windows(2).enumerate() {
            for p in w[0]..w[1] {
                if self.values[M][p] != 0.0 {
                    massless[j] = false;
                    massless[self.rows[p] as usize] = false;
                }
            }
        }
        massless
    }

    /// Lower triangle of the mass matrix restricted to the DOFs `keep` (sorted),
    /// renumbered `0..keep.len()`.
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
            for p in self.pattern.col_range(j) {
                let i = new_index[self.rows[p] as usize];
                if i != usize::MAX {
                    row_idx.push(i);
                    values.push(self.values[M][p]);
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

fn check_symmetric(
    col_ptr: &[usize],
    row_idx: &[usize],
    values: &[[f64; 3]],
    which: usize,
    name: &'static str,
) -> Result<(), IntegrateError> {
    let scale = values.iter().fold(0.0f64, |s, v| s.max(v[which].abs()));
    let tol = SYMMETRY_TOLERANCE * scale;
    let get = |i: usize, j: usize| {
        let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
        rows.binary_search(&i)
            .map_or(0.0, |p| values[col_ptr[j] + p][which])
    };
    for j in 0..col_ptr.len() - 1 {
        for p in col_ptr[j]..col_ptr[j + 1] {
            let i = row_idx[p];
            if i <= j {
                continue;
            }
            let (value, transposed) = (values[p][which], get(j, i));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::tests::sparse;

    #[test]
    fn fused_symmetric_product_matches_the_dense_one() {
        // Different patterns for M (diagonal), C (one coupling), K (a chain).
        let m = sparse(&[
            &[2.0, 0.0, 0.0, 0.0],
            &[0.0, 0.0, 0.0, 0.0],
            &[0.0, 0.0, 1.0, 0.0],
            &[0.0, 0.0, 0.0, 3.0],
        ]);
        let c = sparse(&[
            &[0.5, 0.0, 0.0, -0.2],
            &[0.0, 0.0, 0.0, 0.0],
            &[0.0, 0.0, 0.1, 0.0],
            &[-0.2, 0.0, 0.0, 0.4],
        ]);
        let k = sparse(&[
            &[4.0, -1.0, 0.0, 0.0],
            &[-1.0, 4.0, -1.0, 0.0],
            &[0.0, -1.0, 4.0, -1.0],
            &[0.0, 0.0, -1.0, 4.0],
        ]);
        let dense = |a: &SparseColMat<usize, f64>| a.to_dense();
        let (md, cd, kd) = (dense(&m), dense(&c), dense(&k));
        let xyz: Vec<[f64; 3]> = (0..4)
            .map(|i| [1.0 + i as f64, -0.5 * i as f64, 0.25 + i as f64 * i as f64])
            .collect();
        let f = [1.0, 2.0, 3.0, 4.0];
        for (with_c, with_m) in [(true, true), (true, false), (false, true), (false, false)] {
            let ops = Operators {
                m: m.as_ref(),
                c: with_c.then(|| c.as_ref()),
                k: k.as_ref(),
            };
            let merged = MergedOperators::new(&ops).unwrap();
            let mut out = [0.0; 4];
            merged.residual_into(&f, &xyz, with_m, &mut out);
            for i in 0..4 {
                let mut expected = f[i];
                for j in 0..4 {
                    expected -= kd[(i, j)] * xyz[j][K];
                    if with_c {
                        expected -= cd[(i, j)] * xyz[j][C];
                    }
                    if with_m {
                        expected -= md[(i, j)] * xyz[j][M];
                    }
                }
                assert!(
                    (out[i] - expected).abs() < 1e-14,
                    "c {with_c} m {with_m} row {i}: {} vs {expected}",
                    out[i]
                );
            }
        }
        let merged = MergedOperators::new(&Operators {
            m: m.as_ref(),
            c: None,
            k: k.as_ref(),
        })
        .unwrap();
        assert_eq!(merged.massless_dofs(), vec![false, true, false, false]);
    }

    /// The crate's convention (upper triangles, `Stepper::new_upper`) and full matrices
    /// (`Stepper::new`) merge to the same operators, bit for bit, and an upper input
    /// with an entry below the diagonal is refused.
    #[test]
    fn upper_triangles_merge_to_the_operators_of_both_triangles() {
        use crate::analysis::{test_support::damped_tied_frame, System};
        use crate::linalg::upper_to_full;
        let model = damped_tied_frame(0.8, 1.2e-4);
        let system = System::new(&model).unwrap();
        let full = |a: &SparseColMat<usize, f64>| upper_to_full(a.as_ref()).unwrap();
        let (kf, mf, cf) = (
            full(&system.stiffness),
            full(&system.mass),
            full(&system.damping),
        );
        for with_c in [true, false] {
            let from_full = MergedOperators::new(&Operators {
                m: mf.as_ref(),
                c: with_c.then(|| cf.as_ref()),
                k: kf.as_ref(),
            })
            .unwrap();
            let from_upper = MergedOperators::new_upper(&Operators {
                m: system.mass.as_ref(),
                c: with_c.then(|| system.damping.as_ref()),
                k: system.stiffness.as_ref(),
            })
            .unwrap();
            assert_eq!(
                from_full.pattern().col_ptr(),
                from_upper.pattern().col_ptr()
            );
            assert_eq!(
                from_full.pattern().row_idx(),
                from_upper.pattern().row_idx()
            );
            assert_eq!(from_full.rows, from_upper.rows);
            for which in [M, C, K] {
                let bits = |v: Option<&[f64]>| {
                    v.map(|v| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>())
                };
                assert_eq!(
                    bits(from_full.values(which)),
                    bits(from_upper.values(which))
                );
            }
        }
        let lower_entry = sparse(&[&[2.0, 0.0], &[-1.0, 2.0]]);
        assert!(matches!(
            MergedOperators::new_upper(&Operators {
                m: lower_entry.as_ref(),
                c: None,
                k: lower_entry.as_ref(),
            }),
            Err(IntegrateError::Factorization { .. })
        ));
    }

    #[test]
    fn rayleigh_damping_is_recognised_up_to_a_diagonal() {
        use crate::analysis::{test_support::damped_tied_frame, System};
        use crate::linalg::upper_to_full;
        let (alpha, beta) = (0.8, 1.2e-4);
        let mut model = damped_tied_frame(alpha, beta);
        for lumped in [false, true] {
            model.lumped_mass = lumped;
            let system = System::new(&model).unwrap();
            let full = |a: &SparseColMat<usize, f64>| upper_to_full(a.as_ref()).unwrap();
            let (m, c, k) = (
                full(&system.mass),
                full(&system.damping),
                full(&system.stiffness),
            );
            let ops = Operators {
                m: m.as_ref(),
                c: Some(c.as_ref()),
                k: k.as_ref(),
            };
            let split = MergedOperators::new(&ops)
                .unwrap()
                .rayleigh_split()
                .unwrap();
            eprintln!(
                "lumped {lumped}: alpha {:.17}, beta {:.17e}, residual {:.1e}",
                split.alpha, split.beta, split.residual
            );
            // Summing alpha M_e + beta K_e per element leaves round-off only.
            assert!(split.residual < 1e-14, "residual {}", split.residual);
            assert!((split.beta / beta - 1.0).abs() < 1e-12);
            // alpha M is ~1e-9 of every off-diagonal entry of these steel beams, so
            // alpha is only determined to about that: any such alpha reproduces C.
            assert!((split.alpha / alpha - 1.0).abs() < 1e-6);
            // The unnamed point mass gets no alpha: D = -alpha M_p on its free DOF.
            let weight = split.diagonal.iter().fold(0.0f64, |s, d| s.min(*d));
            assert!(weight < 0.0, "{:?}", split.diagonal);
        }
        // Two element sets with different coefficients: not one Rayleigh pair.
        model.damping[0].elements = vec![1, 2];
        model.damping.push(crate::model::Damping {
            alpha: 0.1,
            beta: 1e-3,
            elements: vec![3],
            mass_nodes: Vec::new(),
        });
        let system = System::new(&model).unwrap();
        let full = |a: &SparseColMat<usize, f64>| upper_to_full(a.as_ref()).unwrap();
        let (m, c, k) = (
            full(&system.mass),
            full(&system.damping),
            full(&system.stiffness),
        );
        let ops = Operators {
            m: m.as_ref(),
            c: Some(c.as_ref()),
            k: k.as_ref(),
        };
        assert!(MergedOperators::new(&ops)
            .unwrap()
            .rayleigh_split()
            .is_none());
    }
}
