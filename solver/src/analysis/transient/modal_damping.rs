//! Modal damping (`LOSS FACTOR`, `MODAL DAMPING`) in direct integration: an exact
//! low-rank correction of each step (Sherman-Morrison-Woodbury) instead of a dense
//! damping matrix in the banded operator.

use super::error::integrate_error;
use crate::analysis::modal;
use crate::analysis::system::System;
use crate::error::solve::SolveError;
use crate::integrate::{State, Stepper};
use crate::linalg::{sym_upper_matvec, Cholesky};

/// Modal damping in direct integration: `C_m = U D U^T`, `U = M Phi` over the lowest
/// [`crate::model::ModalDamping::basis_modes`] modes, `D = diag(2 zeta_i w_i)`, applied as
/// the load `-C_m v` exactly and implicitly, a low-rank correction of each step
/// (Sherman-Morrison-Woodbury) instead of a dense matrix in the banded operator. A step
/// is affine in its end load `f_next`: from rest under `f_next = U e_j` it gives the
/// response columns `(u_j, v_j, a_j)` (for average acceleration `a_j = S^-1 U e_j`,
/// `S = M + dt/2 C + dt^2/4 K`; every scheme of the family likewise). The step under the
/// load alone gives `v_base`; the damped step's `z = U^T v_{n+1}` solves
/// `(I + U^T V D) z = U^T v_base` (`V` the columns `v_j`) and the state changes by
/// `-sum_j (u_j, v_j, a_j) d_j z_j`. The step's start load carries `-C_m v_n`, so schemes
/// that blend the two loads (HHT, generalised-alpha) see the term at both ends.
pub(super) struct ModalDampingTerm {
    /// Columns of `U = M Phi`.
    pub(super) u: Vec<Vec<f64>>,
    /// `2 zeta_i w_i`.
    pub(super) d: Vec<f64>,
    /// The step's response to each column of `U` as its end load: (u, v, a).
    pub(super) response: Vec<State>,
    /// LU of `I + U^T V D`.
    pub(super) lu: nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
    pub(super) z: Vec<f64>,
}

impl ModalDampingTerm {
    pub(super) fn new(
        system: &System,
        factor: &Cholesky,
        title: &str,
        stepper: &mut Stepper,
    ) -> Result<Self, SolveError> {
        let fail = |e| integrate_error(system, title, false, e);
        let n = system.dim();
        let wanted = system.model.modal_damping.basis_modes();
        let solution = modal::solve(system, factor, title, wanted)?;
        let mut u = Vec::new();
        let mut d = Vec::new();
        for (i, mode) in solution.modes.iter().enumerate() {
            let zeta = system.model.modal_damping.zeta(i);
            if zeta == 0.0 {
                continue;
            }
            let mut mphi = vec![0.0; n];
            sym_upper_matvec(system.mass.as_ref(), &mode.shape_free, 1.0, &mut mphi);
            u.push(mphi);
            d.push(2.0 * zeta * mode.omega_squared.max(0.0).sqrt());
        }
        let zero = vec![0.0; n];
        let mut response = Vec::with_capacity(u.len());
        for col in &u {
            let mut state = State::zeros(n, 0.0);
            stepper.step(&mut state, &zero, col, 0).map_err(fail)?;
            response.push(state);
        }
        let r = u.len();
        let g = nalgebra::DMatrix::from_fn(r, r, |i, j| {
            let w: f64 = u[i].iter().zip(&response[j].v).map(|(a, b)| a * b).sum();
            f64::from(u8::from(i == j)) + w * d[j]
        });
        Ok(ModalDampingTerm {
            u,
            d,
            response,
            lu: g.lu(),
            z: vec![0.0; r],
        })
    }

    /// Adds the modal damping force `-U D U^T v` to `f`.
    pub(super) fn add_force(&self, v: &[f64], f: &mut [f64]) {
        for (col, &d) in self.u.iter().zip(&self.d) {
            let z: f64 = col.iter().zip(v).map(|(a, b)| a * b).sum();
            for (fi, ci) in f.iter_mut().zip(col) {
                *fi -= d * z * ci;
            }
        }
    }

    /// Turns the step just taken under the load alone into the damped one.
    pub(super) fn correct(&mut self, state: &mut State) {
        for (zi, col) in self.z.iter_mut().zip(&self.u) {
            *zi = col.iter().zip(&state.v).map(|(a, b)| a * b).sum();
        }
        let rhs = nalgebra::DVector::from_column_slice(&self.z);
        let Some(z) = self.lu.solve(&rhs) else {
            return;
        };
        for ((col, &d), &zj) in self.response.iter().zip(&self.d).zip(z.iter()) {
            let s = -d * zj;
            for (x, c) in state.u.iter_mut().zip(&col.u) {
                *x += s * c;
            }
            for (x, c) in state.v.iter_mut().zip(&col.v) {
                *x += s * c;
            }
            for (x, c) in state.a.iter_mut().zip(&col.a) {
                *x += s * c;
            }
        }
    }
}
