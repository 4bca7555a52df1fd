//! Sparse assembly of dense symmetric blocks through the [`DofMap`].
//!
//! The assembler knows DOF indices and dense matrices, nothing about beams: a *block*
//! is a list of full DOFs (12 for a two-node beam, 6 for a point mass) and, at
//! assembly time, a symmetric dense matrix over them (column-major, as nalgebra stores
//! it; only its upper triangle is read).
//!
//! # Pattern built once
//! At construction every block is expanded through the DOF map's `T` (constraints
//! eliminated onto free DOFs: `A_r = T^T A T`) into *slots*: one slot is one product
//! `coefficient * A_block[i, j]` landing on an upper-triangle entry `(row <= col)` of the
//! reduced matrix. The slots' `(row, col)` pairs go once through faer's
//! `SymbolicSparseColMat::try_new_from_indices`, which returns the CSC pattern and the
//! argsort; after that any matrix on the pattern (K, M, the Rayleigh C, and later
//! `M + gamma dt C + beta dt^2 K`) is a value vector over the slots and
//! `SparseColMat::new_from_argsort` sums the duplicates. All matrices an assembler makes
//! share one symbolic structure, so linear combinations are elementwise on the values
//! and one symbolic Cholesky serves them all.
//!
//! Every equation also gets an explicit diagonal slot (value zero) so that a DOF that
//! nothing stiffens shows up as a zero pivot (a mechanism) rather than a missing entry.
//!
//! Matrices are stored as their upper triangle (faer `Side::Upper`); see
//! [`crate::linalg::sym_upper_matvec`] for products.

use crate::dof::DofMap;
use crate::error::solve::SolveError;
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat, SymbolicSparseColMatRef};

/// One slot: block entry `(i, j)` (`i <= j`) times `coefficient`.
#[derive(Debug, Clone, Copy)]
struct Slot {
    i: u16,
    j: u16,
    coefficient: f64,
}

/// A prescribed-displacement coupling of a block: equation `row` receives
/// `-coefficient * A_block[i, j]` (the product `c_a g_c` folded into `coefficient`).
#[derive(Debug, Clone, Copy)]
struct Coupling {
    row: usize,
    i: u16,
    j: u16,
    coefficient: f64,
}

#[derive(Debug, Clone)]
struct BlockPlan {
    size: usize,
    first_slot: usize,
    slots: Vec<Slot>,
    couplings: Vec<Coupling>,
}

/// Scatter plans of all blocks plus the shared sparsity pattern.
#[derive(Debug, Clone)]
pub struct Assembler {
    n: usize,
    blocks: Vec<BlockPlan>,
    n_slots: usize,
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
}

impl Assembler {
    /// Plans the assembly of the given blocks (each a list of full DOFs) and builds the
    /// reduced pattern.
    pub fn new<B: AsRef<[usize]>>(dofs: &DofMap, blocks: &[B]) -> Result<Self, SolveError> {
        let n = dofs.free_len();
        let mut plans = Vec::with_capacity(blocks.len());
        let mut pairs: Vec<Pair<usize, usize>> = Vec::new();
        for block in blocks {
            let block = block.as_ref();
            let size = block.len();
            let expansions: Vec<Vec<(usize, f64)>> =
                block.iter().map(|&d| dofs.expansion(d).collect()).collect();
            let prescribed: Vec<f64> = block.iter().map(|&d| dofs.prescribed_part(d)).collect();
            // (row, col, i, j, coefficient) for every product with row <= col.
            let mut raw: Vec<(usize, usize, u16, u16, f64)> = Vec::new();
            let mut couplings = Vec::new();
            for a in 0..size {
                for b in 0..size {
                    let (i, j) = (a.min(b) as u16, a.max(b) as u16);
                    for &(ea, ca) in &expansions[a] {
                        for &(eb, cb) in &expansions[b] {
                            if ea <= eb {
                                raw.push((ea, eb, i, j, ca * cb));
                            }
                        }
                        if prescribed[b] != 0.0 {
                            couplings.push(Coupling {
                                row: ea,
                                i,
                                j,
                                coefficient: ca * prescribed[b],
                            });
                        }
                    }
                }
            }
            raw.sort_by_key(|x| (x.0, x.1, x.2, x.3));
            let mut slots: Vec<Slot> = Vec::with_capacity(raw.len());
            let mut last: Option<(usize, usize, u16, u16)> = None;
            for (row, col, i, j, c) in raw {
                if last == Some((row, col, i, j)) {
                    if let Some(s) = slots.last_mut() {
                        s.coefficient += c;
                    }
                    continue;
                }
                last = Some((row, col, i, j));
                slots.push(Slot {
                    i,
                    j,
                    coefficient: c,
                });
                pairs.push(Pair { row, col });
            }
            plans.push(BlockPlan {
                size,
                first_slot: pairs.len() - slots.len(),
                slots,
                couplings,
            });
        }
        pairs.extend((0..n).map(|e| Pair { row: e, col: e }));
        let n_slots = pairs.len();
        let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
            .map_err(|e| SolveError::Linalg(format!("building the sparsity pattern: {e:?}")))?;
        Ok(Assembler {
            n,
            blocks: plans,
            n_slots,
            symbolic,
            argsort,
        })
    }

    /// Number of equations.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// The shared upper-triangle pattern (for the symbolic Cholesky).
    pub fn pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.symbolic.as_ref()
    }

    /// A zeroed slot-value vector, to be filled by [`Assembler::add_block`].
    pub fn new_values(&self) -> Vec<f64> {
        vec![0.0; self.n_slots]
    }

    /// Adds `scale * T^T A T` of block `block` (matrix `a`, column-major, symmetric) to
    /// the slot values.
    pub fn add_block(&self, values: &mut [f64], block: usize, a: &[f64], scale: f64) {
        let plan = &self.blocks[block];
        let n = plan.size;
        debug_assert_eq!(a.len(), n * n);
        let out = &mut values[plan.first_slot..plan.first_slot + plan.slots.len()];
        for (v, s) in out.iter_mut().zip(&plan.slots) {
            *v += scale * s.coefficient * a[s.i as usize + n * s.j as usize];
        }
    }

    /// Adds the load `-scale * T^T A g` that the prescribed displacements `g` put on the
    /// free equations through block `block` (matrix `a`).
    pub fn add_prescribed_load(&self, rhs: &mut [f64], block: usize, a: &[f64], scale: f64) {
        let plan = &self.blocks[block];
        let n = plan.size;
        for c in &plan.couplings {
            rhs[c.row] -= scale * c.coefficient * a[c.i as usize + n * c.j as usize];
        }
    }

    /// The reduced matrix (upper triangle) from slot values.
    pub fn matrix(&self, values: &[f64]) -> Result<SparseColMat<usize, f64>, SolveError> {
        SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, values)
            .map_err(|e| SolveError::Linalg(format!("assembling a sparse matrix: {e:?}")))
    }

    /// `sum_k c_k A_k` of matrices made by this assembler (same pattern), e.g. the
    /// effective matrix `M + gamma dt C + beta dt^2 K` of an implicit time step.
    pub fn combine(
        &self,
        terms: &[(f64, &SparseColMat<usize, f64>)],
    ) -> Result<SparseColMat<usize, f64>, SolveError> {
        let nnz = self.symbolic.row_idx().len();
        let mut values = vec![0.0; nnz];
        for (c, a) in terms {
            if a.symbolic().col_ptr() != self.symbolic.col_ptr()
                || a.symbolic().row_idx() != self.symbolic.row_idx()
            {
                return Err(SolveError::Linalg(
                    "combining matrices that do not share the assembler's pattern".to_string(),
                ));
            }
            for (v, x) in values.iter_mut().zip(a.val()) {
                *v += c * x;
            }
        }
        Ok(SparseColMat::new(self.symbolic.clone(), values))
    }
}

#[cfg(test)]
mod tests {
    use crate::analysis::test_support::tied_frame;
    use crate::analysis::System;
    use crate::dof::DofStatus;
    use nalgebra::{DMatrix, DVector};

    /// Dense reference: `T` (full x free) and `g` from the DOF map, `K_full` from the
    /// element blocks; the sparse reduced matrices must equal `T^T K T` and the
    /// prescribed load `-T^T K g` (to rounding, relative 1e-13).
    #[test]
    fn reduced_matrices_equal_the_dense_congruence() {
        let model = tied_frame();
        let system = System::new(&model).unwrap();
        let dofs = &system.dofs;
        let (nf, n) = (dofs.full_len(), dofs.free_len());
        let mut t = DMatrix::<f64>::zeros(nf, n);
        let mut g = DVector::<f64>::zeros(nf);
        for d in 0..nf {
            for (eq, c) in dofs.expansion(d) {
                t[(d, eq)] += c;
            }
            g[d] = dofs.prescribed_part(d);
            if let DofStatus::Free(eq) = dofs.status(d) {
                assert_eq!(t[(d, eq)], 1.0);
            }
        }
        let mut k_full = DMatrix::<f64>::zeros(nf, nf);
        let mut m_full = DMatrix::<f64>::zeros(nf, nf);
        for (b, block) in system.blocks[..model.elements().len()].iter().enumerate() {
            let (k, m) = system.element_matrices(b).unwrap();
            for (a, &da) in block.iter().enumerate() {
                for (b, &db) in block.iter().enumerate() {
                    k_full[(da, db)] += k[(a, b)];
                    m_full[(da, db)] += m[(a, b)];
                }
            }
        }
        let dense = |a: &faer::sparse::SparseColMat<usize, f64>| {
            let mut out = DMatrix::<f64>::zeros(n, n);
            for j in 0..n {
                for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                    assert!(i <= j, "upper triangle only");
                    out[(i, j)] += v;
                    if i != j {
                        out[(j, i)] += v;
                    }
                }
            }
            out
        };
        let k_r = t.transpose() * &k_full * &t;
        let m_r = t.transpose() * &m_full * &t;
        assert!((dense(&system.stiffness) - &k_r).amax() <= 1e-13 * k_r.amax());
        assert!((dense(&system.mass) - &m_r).amax() <= 1e-13 * m_r.amax());
        let f_g = -(t.transpose() * &k_full * &g);
        let diff = (DVector::from_vec(system.prescribed_load.clone()) - &f_g).amax();
        assert!(f_g.amax() > 0.0 && diff <= 1e-13 * (k_full.amax() * g.amax()));
        // Combinations act on the shared pattern.
        let c = system
            .assembler
            .combine(&[(2.0, &system.mass), (0.5, &system.stiffness)])
            .unwrap();
        let expected = &m_r * 2.0 + &k_r * 0.5;
        assert!((dense(&c) - &expected).amax() <= 1e-13 * expected.amax());
    }
}
