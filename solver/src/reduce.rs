//! Craig-Bampton reduction of a coil [`Model`]: the linear finite-element spring reduced
//! to a few *boundary* DOFs (the weight's) plus a few fixed-interface normal modes, for
//! the small dense models that `coil-tune diagnose` integrates thousands of times.
//!
//! # Formulation (R. R. Craig & M. C. C. Bampton, AIAA J. 6 (1968) 1313-1319)
//! The free DOFs of the model (after constraint elimination, [`crate::dof`]) are split
//! into the boundary DOFs `b` (chosen by the caller, e.g. the weight's `u_z`) and the
//! interior `i` (all other free DOFs). The free displacement is approximated by
//! ```text
//! [u_b]   [ I    0  ] [q_b]
//! [u_i] = [ Psi  Phi] [eta]  = T q,     Psi = -K_ii^-1 K_ib,
//! ```
//! - `Psi`: static constraint modes, the interior's static response to a unit
//!   displacement of each boundary DOF with the others held (the same shape as the
//!   transient's quasi-static velocity field). They make the reduction exact in
//!   statics: the reduced boundary stiffness is the Schur complement
//!   `K_bb - K_bi K_ii^-1 K_ib`, i.e. the full model's static stiffness at the boundary.
//! - `Phi`: the lowest `n_modes` modes of the model with the boundary held,
//!   `K_ii phi = omega^2 M_ii phi`, mass-normalised (`phi^T M_ii phi = 1`).
//!
//! Reduced matrices are the Galerkin projections `T^T A T` (`A` = K, the beam elements'
//! mass, the point masses' and matrix elements' mass), so every reduced eigenvalue is an upper bound of the
//! full model's (Rayleigh-Ritz) and the bound tightens with `n_modes` (nested bases).
//! `K_r` is block diagonal in exact arithmetic: `[[K_bb - K_bi K_ii^-1 K_ib, 0],
//! [0, Omega^2]]`; it is computed as `T^T K T` all the same (the coupling blocks come
//! out at rounding level) so no block is assumed.
//!
//! The held-boundary problems reuse the engine: the model is copied with `FIXED DISP 0`
//! on the boundary DOFs, [`System::new`] assembles it, [`System::factor_stiffness`]
//! factors `K_ii` and [`crate::analysis::modal::solve`] gives `Phi` (shift-invert
//! Lanczos). Interior equations of the copy map to the original's through their full
//! DOF index.
//!
//! # Reduced coordinates and their order
//! `q = [q_b (boundary, in the order given), eta (modes by ascending frequency)]`,
//! `r = n_b + n_modes`. `q_b` *is* the physical displacement of boundary DOF `b` (mm or
//! rad): `T` has the identity on the boundary rows. `eta` are modal amplitudes
//! (sqrt(t) mm, the mass-normalised scale). [`Reduction::expand`] gives the full
//! displacement field of any `q`.
//!
//! # Separated matrices, re-parameterisation
//! [`Reduction`] keeps `k` (at the model's E), `m_elements` (consistent or lumped mass of
//! the beams, what Rayleigh alpha acts on) and `m_points` (the point masses: the weight
//! and its rotary inertia) apart. Scaling E (with a fixed Poisson ratio) scales every
//! element stiffness, hence `K`, by the same factor and leaves `Psi` and `Phi` unchanged,
//! so [`Reduction::operators`] re-parameterises stiffness, added boundary mass and
//! Rayleigh damping exactly without reducing again:
//! `M = m_elements + m_points + diag(extra on the boundary rows)`,
//! `C = alpha m_elements + beta s k`, `K = s k`. (Mass added at the boundary changes
//! the fixed-interface modes not at all: they hold the boundary still.)
//!
//! # Dense storage
//! Reduced matrices are `nalgebra::DMatrix<f64>` (r is small; nalgebra's dense
//! Cholesky and symmetric eigensolver serve the reduced checks). Units: solver units,
//! mm, N, t, s (rad and N mm for rotations).

use crate::analysis::{modal, System};
use crate::dof::{dof_name, DofMap, DofStatus};
use crate::error::solve::SolveError;
use crate::linalg::sym_upper_matvec;
use crate::model::{FixedDisp, MatrixElement, Model, NodeId};
use faer::sparse::SparseColMat;
use nalgebra::{DMatrix, DVector};

/// Why a reduction or a reduced operator cannot be formed.
#[derive(Debug, thiserror::Error)]
pub enum ReduceError {
    /// No boundary DOF was given.
    #[error("a Craig-Bampton reduction needs at least one boundary DOF")]
    NoBoundary,
    /// A boundary node that the model does not define.
    #[error("boundary DOF {index}: node {node} does not exist")]
    UnknownNode {
        /// The DOF's position in the boundary list (0-based).
        index: usize,
        /// The node's id.
        node: NodeId,
    },
    /// A boundary DOF number outside 1..=6.
    #[error("boundary DOF {index}: node {node} DOF {dof}; DOFs are numbered 1..=6")]
    BadDof {
        /// The DOF's position in the boundary list (0-based).
        index: usize,
        /// The node's id.
        node: NodeId,
        /// The DOF number given.
        dof: u8,
    },
    /// A boundary DOF that is not a free unknown of the model.
    #[error(
        "boundary DOF {index}: node {node} {} is {reason}; a boundary DOF must be free \
         (give a tied DOF at its reference node, or release a FIXED DISP)",
        dof_name(*dof)
    )]
    NotFree {
        /// The DOF's position in the boundary list (0-based).
        index: usize,
        /// The node's id.
        node: NodeId,
        /// The DOF number (1..=6).
        dof: u8,
        /// Why it is not free (fixed or tied).
        reason: &'static str,
    },
    /// The same boundary DOF twice.
    #[error("boundary DOF {index}: node {node} {} is listed twice", dof_name(*dof))]
    Duplicate {
        /// The DOF's position in the boundary list (0-based) of its second listing.
        index: usize,
        /// The node's id.
        node: NodeId,
        /// The DOF number (1..=6).
        dof: u8,
    },
    /// More fixed-interface modes than interior DOFs.
    #[error("{requested} fixed-interface modes asked for, but the interior has {available} DOFs")]
    TooManyModes {
        /// Number of fixed-interface modes asked for.
        requested: usize,
        /// Number of interior DOFs.
        available: usize,
    },
    /// A vector of the wrong length.
    #[error("{what} has length {found}, expected {expected}")]
    Dimension {
        /// Which vector.
        what: &'static str,
        /// The length it must have.
        expected: usize,
        /// The length it has.
        found: usize,
    },
    /// A parameter or a result that must be finite (and positive where said) is not.
    #[error("{what}")]
    BadValue {
        /// What is wrong.
        what: String,
    },
    /// A failure while assembling or solving the full or the held-boundary model.
    #[error("{context}: {source}")]
    Solve {
        /// Which step failed.
        context: &'static str,
        /// The solver's error.
        #[source]
        source: Box<SolveError>,
    },
}

fn solve_err(context: &'static str) -> impl FnOnce(SolveError) -> ReduceError {
    move |source| ReduceError::Solve {
        context,
        source: Box::new(source),
    }
}

/// A Craig-Bampton reduced model (see the module docs for the formulation and units).
#[derive(Debug, Clone)]
pub struct Reduction {
    /// Boundary DOFs `(node id, dof 1..=6)`; boundary `i` is reduced coordinate `i`.
    pub boundary: Vec<(NodeId, u8)>,
    /// Number of fixed-interface modes (coordinates `boundary.len()..`).
    pub n_modes: usize,
    /// Reduced stiffness at the model's Young's modulus (N/mm, N, N mm per unit q).
    pub k: DMatrix<f64>,
    /// Reduced mass of the beam elements (what Rayleigh alpha acts on).
    pub m_elements: DMatrix<f64>,
    /// Reduced mass of the point masses (the weight and its rotary inertia) and of any
    /// matrix element (`DMIG`).
    pub m_points: DMatrix<f64>,
    /// Frequencies (Hz) of the fixed-interface modes, ascending.
    pub fixed_interface_hz: Vec<f64>,
    /// `T^T M r_d` for the rigid translation `r_d` of every free DOF along axis `d`
    /// (x, y, z): the reduced inertial load of a unit base acceleration along `d`
    /// (t mm/s^2 per mm/s^2, i.e. t), at the model's point masses.
    translation_loads: Vec<DVector<f64>>,
    /// `T` on the model's free DOFs (free DOFs x r).
    basis: DMatrix<f64>,
    dofs: DofMap,
}

/// The dense operators `(M, C, K)` of a re-parameterised reduced model.
#[derive(Debug, Clone, PartialEq)]
pub struct ReducedOperators {
    /// Reduced mass matrix, in the reduced coordinates `[q_b, eta]`.
    pub m: DMatrix<f64>,
    /// Reduced damping matrix, in the reduced coordinates `[q_b, eta]`.
    pub c: DMatrix<f64>,
    /// Reduced stiffness matrix, in the reduced coordinates `[q_b, eta]`.
    pub k: DMatrix<f64>,
}

/// The free equation of each boundary DOF, in the caller's order; an unknown node, a
/// DOF out of range, a prescribed or tied DOF, or a repeat is an error naming its
/// position in `boundary`.
fn boundary_equations(
    model: &Model,
    system: &System,
    boundary: &[(NodeId, u8)],
) -> Result<Vec<usize>, ReduceError> {
    let mut boundary_eq = Vec::with_capacity(boundary.len());
    for (index, &(node, dof)) in boundary.iter().enumerate() {
        if model.node_index(node).is_none() {
            return Err(ReduceError::UnknownNode { index, node });
        }
        let full = system
            .dofs
            .full_index(node, dof)
            .ok_or(ReduceError::BadDof { index, node, dof })?;
        let eq = match system.dofs.status(full) {
            DofStatus::Free(eq) => eq,
            DofStatus::Prescribed(_) => {
                return Err(ReduceError::NotFree {
                    index,
                    node,
                    dof,
                    reason: "prescribed by FIXED DISP",
                })
            }
            DofStatus::Dependent => {
                return Err(ReduceError::NotFree {
                    index,
                    node,
                    dof,
                    reason: "tied by a rigid tie",
                })
            }
        };
        if boundary_eq.contains(&eq) {
            return Err(ReduceError::Duplicate { index, node, dof });
        }
        boundary_eq.push(eq);
    }
    Ok(boundary_eq)
}

/// Reduces `model` to the `boundary` DOFs plus `n_modes` fixed-interface modes
/// (Craig-Bampton; `n_modes = 0` is Guyan's static condensation).
pub fn craig_bampton(
    model: &Model,
    boundary: &[(NodeId, u8)],
    n_modes: usize,
) -> Result<Reduction, ReduceError> {
    if boundary.is_empty() {
        return Err(ReduceError::NoBoundary);
    }
    let system = System::new(model).map_err(solve_err("assembling the model"))?;
    let n = system.dim();
    let boundary_eq = boundary_equations(model, &system, boundary)?;
    let nb = boundary.len();
    let n_interior = n - nb;
    if n_modes > n_interior {
        return Err(ReduceError::TooManyModes {
            requested: n_modes,
            available: n_interior,
        });
    }

    // The held-boundary model: the same model with the boundary DOFs prescribed to 0.
    let mut held = model.clone();
    held.load_cases.clear();
    held.outputs.clear();
    held.initial_velocities.clear();
    held.point_loads.clear();
    for &(node, dof) in boundary {
        held.fixed_disp.push(FixedDisp {
            dofs: vec![(dof, 0.0)],
            nodes: vec![node],
        });
    }
    let interior =
        System::new(&held).map_err(solve_err("assembling the model with the boundary held"))?;
    // Interior equation j of the held model is equation interior_eq[j] of the model.
    let mut interior_eq = vec![usize::MAX; interior.dim()];
    for eq in 0..n {
        if let DofStatus::Free(j) = interior.dofs.status(system.dofs.free_to_full(eq)) {
            interior_eq[j] = eq;
        }
    }
    if interior.dim() != n_interior || interior_eq.contains(&usize::MAX) {
        return Err(ReduceError::BadValue {
            what: format!(
                "holding {nb} boundary DOFs left {} interior equations of {n}, expected {n_interior}",
                interior.dim()
            ),
        });
    }
    let factor = interior.factor_stiffness().map_err(solve_err(
        "factoring K_ii (the model with the boundary held)",
    ))?;

    let r = nb + n_modes;
    let mut basis = DMatrix::<f64>::zeros(n, r);
    let mut unit = vec![0.0; n];
    let mut k_col = vec![0.0; n];
    let mut psi = vec![0.0; n_interior];
    for (c, &eq) in boundary_eq.iter().enumerate() {
        unit.fill(0.0);
        unit[eq] = 1.0;
        k_col.fill(0.0);
        sym_upper_matvec(system.stiffness.as_ref(), &unit, 1.0, &mut k_col);
        for (p, &e) in psi.iter_mut().zip(&interior_eq) {
            *p = -k_col[e];
        }
        factor.solve_in_place(&mut psi);
        basis[(eq, c)] = 1.0;
        for (&p, &e) in psi.iter().zip(&interior_eq) {
            basis[(e, c)] = p;
        }
    }
    let mut fixed_interface_hz = Vec::with_capacity(n_modes);
    if n_modes > 0 {
        let modes = modal::solve(
            &interior,
            &factor,
            "Craig-Bampton fixed-interface modes",
            n_modes,
        )
        .map_err(solve_err("fixed-interface modes"))?;
        for (k, mode) in modes.modes.iter().enumerate() {
            for (&x, &e) in mode.shape_free.iter().zip(&interior_eq) {
                basis[(e, nb + k)] = x;
            }
            fixed_interface_hz.push(mode.frequency_hz);
        }
    }
    if basis.iter().any(|x| !x.is_finite()) {
        return Err(ReduceError::BadValue {
            what: "the Craig-Bampton basis holds a non-finite value".to_string(),
        });
    }

    // Element and point masses assembled apart (the system's M is their sum).
    let n_elements = model.elements().len();
    let mut me = system.assembler.new_values();
    for b in 0..n_elements {
        let (_, m) = system
            .element_matrices(b)
            .map_err(solve_err("the element masses"))?;
        system.assembler.add_block(&mut me, b, m.as_slice(), 1.0);
    }
    let mut mp = system.assembler.new_values();
    for (p, m) in system.point_mass_blocks.iter().enumerate() {
        system
            .assembler
            .add_block(&mut mp, n_elements + p, m.as_slice(), 1.0);
    }
    for (i, e) in model.matrix_elements().iter().enumerate() {
        let b = system.matrix_first + i;
        system.assembler.add_block(&mut mp, b, &e.mass, 1.0);
    }
    let me = system
        .assembler
        .matrix(&me)
        .map_err(solve_err("element mass"))?;
    let mp = system
        .assembler
        .matrix(&mp)
        .map_err(solve_err("point mass"))?;

    let translation_loads = (1..=3u8)
        .map(|d| {
            let r: Vec<f64> = (0..n)
                .map(|eq| f64::from(u8::from(system.dofs.free_label(eq).1 == d)))
                .collect();
            let mut y = vec![0.0; n];
            sym_upper_matvec(me.as_ref(), &r, 1.0, &mut y);
            sym_upper_matvec(mp.as_ref(), &r, 1.0, &mut y);
            basis.transpose() * DVector::from_vec(y)
        })
        .collect();
    Ok(Reduction {
        boundary: boundary.to_vec(),
        n_modes,
        k: project(&system.stiffness, &basis),
        m_elements: project(&me, &basis),
        m_points: project(&mp, &basis),
        fixed_interface_hz,
        translation_loads,
        basis,
        dofs: system.dofs.clone(),
    })
}

/// `T^T A T` for `A` stored as its upper triangle, symmetrised.
fn project(a: &SparseColMat<usize, f64>, basis: &DMatrix<f64>) -> DMatrix<f64> {
    let (n, r) = basis.shape();
    let mut at = DMatrix::<f64>::zeros(n, r);
    for j in 0..r {
        let x: Vec<f64> = basis.column(j).iter().copied().collect();
        let mut y = vec![0.0; n];
        sym_upper_matvec(a.as_ref(), &x, 1.0, &mut y);
        at.column_mut(j).copy_from_slice(&y);
    }
    let p = basis.transpose() * at;
    (&p + p.transpose()) * 0.5
}

impl Reduction {
    /// Number of reduced coordinates `r = boundary.len() + n_modes`.
    pub fn dim(&self) -> usize {
        self.k.nrows()
    }

    /// The reduced coordinate of a boundary DOF (its physical displacement).
    pub fn boundary_index(&self, node: NodeId, dof: u8) -> Option<usize> {
        self.boundary.iter().position(|&b| b == (node, dof))
    }

    /// Total reduced mass `m_elements + m_points`.
    pub fn mass(&self) -> DMatrix<f64> {
        &self.m_elements + &self.m_points
    }

    /// The operators of the re-parameterised model (module docs): `K = k_scale k`,
    /// `M = m_elements + m_points + diag(extra_boundary_mass on the boundary rows)`,
    /// `C = alpha m_elements + beta K`. `extra_boundary_mass[i]` (t, or t mm^2 for a
    /// rotation) is added at boundary `i`; it may be negative (a lighter weight) as long
    /// as `M` stays positive definite, which the integrator checks.
    pub fn operators(
        &self,
        k_scale: f64,
        extra_boundary_mass: &[f64],
        alpha: f64,
        beta: f64,
    ) -> Result<ReducedOperators, ReduceError> {
        if extra_boundary_mass.len() != self.boundary.len() {
            return Err(ReduceError::Dimension {
                what: "extra boundary mass",
                expected: self.boundary.len(),
                found: extra_boundary_mass.len(),
            });
        }
        let all_finite = [k_scale, alpha, beta]
            .iter()
            .chain(extra_boundary_mass)
            .all(|x| x.is_finite());
        if !all_finite || k_scale <= 0.0 {
            return Err(ReduceError::BadValue {
                what: format!(
                    "reduced operators need a finite k_scale > 0 and finite masses, alpha, beta; \
                     got k_scale {k_scale}, extra mass {extra_boundary_mass:?}, alpha {alpha}, beta {beta}"
                ),
            });
        }
        let k = &self.k * k_scale;
        let mut m = self.mass();
        for (i, &extra) in extra_boundary_mass.iter().enumerate() {
            m[(i, i)] += extra;
        }
        let c = &self.m_elements * alpha + &k * beta;
        Ok(ReducedOperators { m, c, k })
    }

    /// The reduced inertial load `T^T M r` of a unit acceleration of the base along axis
    /// `direction` (1, 2, 3 = x, y, z), `r` the rigid translation of every free DOF, with
    /// `extra_boundary_mass` as in [`Reduction::operators`] (its rows that translate along
    /// `direction` carry it). In relative coordinates a base acceleration `a_b` loads the
    /// reduced model with `-a_b` times this vector (t; N per mm/s^2).
    pub fn translation_load(
        &self,
        direction: u8,
        extra_boundary_mass: &[f64],
    ) -> Result<DVector<f64>, ReduceError> {
        if extra_boundary_mass.len() != self.boundary.len() || !(1..=3).contains(&direction) {
            return Err(ReduceError::Dimension {
                what: "extra boundary mass (or a direction other than 1, 2, 3)",
                expected: self.boundary.len(),
                found: extra_boundary_mass.len(),
            });
        }
        let mut load = self.translation_loads[usize::from(direction) - 1].clone();
        for (i, (&(_, dof), &extra)) in self.boundary.iter().zip(extra_boundary_mass).enumerate() {
            if dof == direction {
                load[i] += extra;
            }
        }
        Ok(load)
    }

    /// Undamped eigenfrequencies (Hz, ascending) of the re-parameterised reduced model.
    pub fn frequencies_hz(
        &self,
        k_scale: f64,
        extra_boundary_mass: &[f64],
    ) -> Result<Vec<f64>, ReduceError> {
        let ops = self.operators(k_scale, extra_boundary_mass, 0.0, 0.0)?;
        let omega2 = generalized_eigenvalues(&ops.k, &ops.m).ok_or(ReduceError::BadValue {
            what: "the reduced mass is not positive definite".to_string(),
        })?;
        Ok(omega2
            .iter()
            .map(|w2| w2.max(0.0).sqrt() / std::f64::consts::TAU)
            .collect())
    }

    /// The reduced model as a matrix element (`DMIG`) of another model: boundary `i`
    /// on `boundary_dofs[i]` (a (node, DOF) of that model), mode `k` on DOF 1 of
    /// `modal_nodes[k]` (nodes whose other DOFs that model holds), with the operators
    /// of [`Reduction::operators`] (`k_scale`, no added mass, Rayleigh `alpha`, `beta`;
    /// no damping matrix when both are zero).
    pub fn matrix_element(
        &self,
        name: &str,
        boundary_dofs: &[(NodeId, u8)],
        modal_nodes: &[NodeId],
        k_scale: f64,
        alpha: f64,
        beta: f64,
    ) -> Result<MatrixElement, ReduceError> {
        for (what, expected, found) in [
            ("boundary DOFs", self.boundary.len(), boundary_dofs.len()),
            ("modal nodes", self.n_modes, modal_nodes.len()),
        ] {
            if found != expected {
                return Err(ReduceError::Dimension {
                    what,
                    expected,
                    found,
                });
            }
        }
        let ops = self.operators(k_scale, &vec![0.0; self.boundary.len()], alpha, beta)?;
        let row_major = |a: &DMatrix<f64>| a.transpose().as_slice().to_vec();
        let mut dofs = boundary_dofs.to_vec();
        dofs.extend(modal_nodes.iter().map(|&n| (n, 1)));
        Ok(MatrixElement {
            name: name.to_string(),
            dofs,
            stiffness: row_major(&ops.k),
            mass: row_major(&ops.m),
            damping: if alpha == 0.0 && beta == 0.0 {
                Vec::new()
            } else {
                row_major(&ops.c)
            },
        })
    }

    /// The full displacement field (every node, six DOFs, mm and rad; prescribed DOFs
    /// zero) of the reduced coordinates `q`.
    pub fn expand(&self, q: &[f64]) -> Result<Vec<f64>, ReduceError> {
        if q.len() != self.dim() {
            return Err(ReduceError::Dimension {
                what: "reduced coordinates",
                expected: self.dim(),
                found: q.len(),
            });
        }
        let free = &self.basis * nalgebra::DVector::from_column_slice(q);
        Ok(self.dofs.expand(free.as_slice(), 0.0))
    }
}

impl ReducedOperators {
    /// Adds modal damping (`LOSS FACTOR`, `MODAL DAMPING`) to `c`: the reduced model's
    /// own modes `x_i` (`K x = w^2 M x`, mass-normalised, ascending) each get
    /// `zeta(i)`, i.e. `C += M X diag(2 zeta_i w_i) X^T M` over all `r` modes, the
    /// exact modal damping of the reduced model (dense, like the operators). Computed as
    /// `L Y D Y^T L^T` with `M = L L^T` and `Y` the eigenvectors of `L^-1 K L^-T`.
    pub fn add_modal_damping(&mut self, zeta: impl Fn(usize) -> f64) -> Result<(), ReduceError> {
        let bad = || ReduceError::BadValue {
            what: "modal damping needs a positive definite reduced mass".to_string(),
        };
        let n = self.m.nrows();
        let l = self.m.clone().cholesky().ok_or_else(bad)?.l();
        let l_inv = l.clone().try_inverse().ok_or_else(bad)?;
        let a = &l_inv * &self.k * l_inv.transpose();
        let a = (&a + a.transpose()) * 0.5;
        let eigen = a.symmetric_eigen();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
        let ly = &l * &eigen.eigenvectors;
        for (rank, &j) in order.iter().enumerate() {
            let z = zeta(rank);
            if z == 0.0 {
                continue;
            }
            if !(z.is_finite() && z >= 0.0) {
                return Err(ReduceError::BadValue {
                    what: format!("modal damping ratio {z} of mode {}", rank + 1),
                });
            }
            let d = 2.0 * z * eigen.eigenvalues[j].max(0.0).sqrt();
            let col = ly.column(j);
            self.c += col * col.transpose() * d;
        }
        Ok(())
    }

    /// Adds a linear dashpot `c_n_s_mm` (N s/mm) on reduced coordinate `i` (a boundary
    /// DOF, e.g. the weight's axial translation).
    pub fn add_dashpot(&mut self, i: usize, c_n_s_mm: f64) -> Result<(), ReduceError> {
        if i >= self.c.nrows() || !(c_n_s_mm.is_finite() && c_n_s_mm >= 0.0) {
            return Err(ReduceError::BadValue {
                what: format!("dashpot {c_n_s_mm} N s/mm on reduced coordinate {i}"),
            });
        }
        self.c[(i, i)] += c_n_s_mm;
        Ok(())
    }
}

/// Eigenvalues `omega^2` (ascending) of `K x = omega^2 M x` for symmetric `K` and
/// symmetric positive definite `M`, or `None` if `M` is not positive definite.
/// Both are first scaled by `D = diag(M)^-1/2` (the reduced coordinates mix mm, rad
/// and modal units), then `L^-1 K L^-T` with `M = L L^T` is solved symmetrically.
pub fn generalized_eigenvalues(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Option<Vec<f64>> {
    let n = m.nrows();
    if k.shape() != (n, n) || m.ncols() != n {
        return None;
    }
    let mut d = Vec::with_capacity(n);
    for i in 0..n {
        let mii = m[(i, i)];
        if !(mii > 0.0 && mii.is_finite()) {
            return None;
        }
        d.push(1.0 / mii.sqrt());
    }
    let ms = DMatrix::from_fn(n, n, |i, j| d[i] * m[(i, j)] * d[j]);
    let ks = DMatrix::from_fn(n, n, |i, j| d[i] * k[(i, j)] * d[j]);
    let l = ms.cholesky()?.l();
    let l_inv = l.try_inverse()?;
    let a = &l_inv * ks * l_inv.transpose();
    let a = (&a + a.transpose()) * 0.5;
    let mut w: Vec<f64> = a.symmetric_eigenvalues().iter().copied().collect();
    w.sort_by(f64::total_cmp);
    Some(w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::test_support::damped_tied_frame;
    use crate::analysis::System;

    fn frame() -> Model {
        // Weight on node 10 (tie reference), its u_z prescribed in the fixture: free it.
        let mut model = damped_tied_frame(0.5, 1e-4);
        model.fixed_disp[1].dofs = vec![(4, 0.0)];
        model
    }

    #[test]
    fn reduced_modal_damping_gives_each_mode_its_ratio() {
        let model = frame();
        let red = craig_bampton(&model, &[(10, 3)], 4).unwrap();
        let mut ops = red.operators(1.0, &[0.0], 0.0, 0.0).unwrap();
        ops.add_modal_damping(|i| 0.001 * (i + 1) as f64).unwrap();
        // The state matrix's eigenvalues -zeta w +- i w sqrt(1 - zeta^2), per mode.
        let w2 = generalized_eigenvalues(&ops.k, &ops.m).unwrap();
        let n = ops.m.nrows();
        let m_inv = ops.m.clone().try_inverse().unwrap();
        let mut a = DMatrix::<f64>::zeros(2 * n, 2 * n);
        for i in 0..n {
            a[(i, n + i)] = 1.0;
        }
        let mk = -&m_inv * &ops.k;
        let mc = -&m_inv * &ops.c;
        for i in 0..n {
            for j in 0..n {
                a[(n + i, j)] = mk[(i, j)];
                a[(n + i, n + j)] = mc[(i, j)];
            }
        }
        let mut lambda: Vec<_> = a
            .complex_eigenvalues()
            .iter()
            .copied()
            .filter(|l| l.im > 0.0)
            .collect();
        lambda.sort_by(|x, y| x.norm().total_cmp(&y.norm()));
        for (i, l) in lambda.iter().enumerate() {
            let zeta = -l.re / l.norm();
            assert!((l.norm() / w2[i].sqrt() - 1.0).abs() < 1e-8);
            assert!(
                (zeta / (0.001 * (i + 1) as f64) - 1.0).abs() < 1e-6,
                "mode {i}: {zeta}"
            );
        }
    }

    #[test]
    fn boundary_errors_are_typed() {
        let model = frame();
        assert!(matches!(
            craig_bampton(&model, &[], 1),
            Err(ReduceError::NoBoundary)
        ));
        assert!(matches!(
            craig_bampton(&model, &[(99, 3)], 1),
            Err(ReduceError::UnknownNode { node: 99, .. })
        ));
        assert!(matches!(
            craig_bampton(&model, &[(10, 7)], 1),
            Err(ReduceError::BadDof { dof: 7, .. })
        ));
        assert!(matches!(
            craig_bampton(&model, &[(10, 4)], 1),
            Err(ReduceError::NotFree { .. })
        ));
        assert!(matches!(
            craig_bampton(&model, &[(4, 3)], 1),
            Err(ReduceError::NotFree { .. })
        ));
        assert!(matches!(
            craig_bampton(&model, &[(10, 3), (10, 3)], 1),
            Err(ReduceError::Duplicate { index: 1, .. })
        ));
        assert!(matches!(
            craig_bampton(&model, &[(10, 3)], 10_000),
            Err(ReduceError::TooManyModes { .. })
        ));
        let red = craig_bampton(&model, &[(10, 3)], 2).unwrap();
        assert!(matches!(
            red.operators(1.0, &[], 0.0, 0.0),
            Err(ReduceError::Dimension { .. })
        ));
        assert!(red.operators(f64::NAN, &[0.0], 0.0, 0.0).is_err());
    }

    /// With every interior DOF kept as a mode the basis spans the whole space, so the
    /// reduced eigenvalues are the full ones. The dense reduced eigensolve is accurate
    /// to about `eps omega_max^2` absolute (the reduced K holds the stiffest
    /// fixed-interface mode), hence the tolerance `100 eps omega_max^2 / omega^2`.
    #[test]
    fn a_complete_basis_reproduces_the_full_spectrum() {
        let model = frame();
        let system = System::new(&model).unwrap();
        let n = system.dim();
        let red = craig_bampton(&model, &[(10, 3), (10, 6)], n - 2).unwrap();
        let factor = system.factor_stiffness().unwrap();
        let full = modal::solve(&system, &factor, "full", 6).unwrap();
        let reduced = red.frequencies_hz(1.0, &[0.0, 0.0]).unwrap();
        let top = red
            .fixed_interface_hz
            .last()
            .copied()
            .unwrap_or(0.0)
            .powi(2);
        for (mode, f) in full.modes.iter().zip(&reduced) {
            let tolerance = 100.0 * f64::EPSILON * top / mode.frequency_hz.powi(2);
            eprintln!("{f} vs {}: tolerance {tolerance:e}", mode.frequency_hz);
            assert!(
                (f / mode.frequency_hz - 1.0).abs() < tolerance.max(1e-12),
                "{f} vs {}, tolerance {tolerance:e}",
                mode.frequency_hz
            );
        }
    }

    /// K_r is block diagonal with Omega^2 on the modal block; the modal mass block is
    /// the identity; the boundary rows of T are the identity.
    #[test]
    fn reduced_matrices_have_the_craig_bampton_structure() {
        let model = frame();
        let red = craig_bampton(&model, &[(10, 3)], 3).unwrap();
        let m = red.mass();
        let kmax = red.k.amax();
        for a in 0..3 {
            let w2 = (std::f64::consts::TAU * red.fixed_interface_hz[a]).powi(2);
            assert!((red.k[(1 + a, 1 + a)] / w2 - 1.0).abs() < 1e-9);
            assert!(red.k[(0, 1 + a)].abs() < 1e-9 * kmax);
            for b in 0..3 {
                let target = if a == b { 1.0 } else { 0.0 };
                assert!((m[(1 + a, 1 + b)] - target).abs() < 1e-9);
            }
        }
        let mut q = vec![0.0; 4];
        q[0] = 0.7;
        let u = red.expand(&q).unwrap();
        let full = red.dofs.full_index(10, 3).unwrap();
        assert_eq!(u[full], 0.7);
        // Operators: scaling and damping compose as documented.
        let ops = red.operators(2.0, &[1e-3], 0.3, 1e-4).unwrap();
        assert!((ops.k[(0, 0)] - 2.0 * red.k[(0, 0)]).abs() < 1e-12 * ops.k[(0, 0)]);
        assert!((ops.m[(0, 0)] - m[(0, 0)] - 1e-3).abs() < 1e-15);
        let c00 = 0.3 * red.m_elements[(0, 0)] + 1e-4 * ops.k[(0, 0)];
        assert!((ops.c[(0, 0)] - c00).abs() < 1e-12 * c00);
    }
}
