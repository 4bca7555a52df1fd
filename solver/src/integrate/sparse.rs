//! The generalised-alpha step on general sparse operators: the effective matrix
//! factored by faer (AMD ordering, simplicial, see `factor`), the right-hand side one
//! fused symmetric pass `M x + C y + K z` over the merged lower pattern (`operator`).
//! Used when the pattern's envelope is too wide for the banded path (`banded`); the
//! step is the unreduced predictor-solve-corrector of `stepper`'s module docs, in the
//! caller's numbering.

use super::operator::MergedOperators;
use super::scheme::Coefficients;
use super::state::State;
use crate::error::integrate::IntegrateError;
use crate::linalg::sparse_spd::SpdFactor;

#[derive(Debug)]
pub(crate) struct SparseEngine {
    s_values: Vec<f64>,
    factor: SpdFactor,
    // Step buffers: load blend, the vectors multiplying [M, C, K] interleaved per
    // DOF, right-hand side / a_{n+1}.
    f_blend: Vec<f64>,
    xyz: Vec<[f64; 3]>,
    rhs: Vec<f64>,
}

impl SparseEngine {
    /// Symbolic analysis of the merged pattern.
    pub(crate) fn new(ops: &MergedOperators, name: &'static str) -> Result<Self, IntegrateError> {
        let n = ops.dim();
        Ok(Self {
            s_values: vec![0.0; ops.nnz()],
            factor: SpdFactor::analyse(name, ops.pattern())?,
            f_blend: vec![0.0; n],
            xyz: vec![[0.0; 3]; n],
            rhs: vec![0.0; n],
        })
    }

    /// Forms and factors `S = cm M + cc C + ck K`.
    pub(crate) fn refactor(
        &mut self,
        ops: &MergedOperators,
        (cm, cc, ck): (f64, f64, f64),
    ) -> Result<(), IntegrateError> {
        ops.combine_into(cm, cc, ck, &mut self.s_values);
        self.factor.factor(ops.view(&self.s_values))
    }

    /// Solves `S x = b` in place (the current factor).
    pub(crate) fn solve_in_place(&mut self, b: &mut [f64]) {
        self.factor.solve_in_place(b);
    }

    /// One step; returns false when the new state is not finite.
    pub(crate) fn step(
        &mut self,
        ops: &MergedOperators,
        coefficients: &Coefficients,
        dt: f64,
        state: &mut State,
        f_n: &[f64],
        f_next: &[f64],
    ) -> bool {
        let n = self.rhs.len();
        let Coefficients {
            alpha_m: am,
            alpha_f: af,
            beta,
            gamma,
        } = *coefficients;

        // Predictor, folded into the shifted-time combinations of the balance.
        let du = 1.0 - af;
        let c_uv = du * dt;
        let c_ua = du * dt * dt * (0.5 - beta);
        let c_va = du * dt * (1.0 - gamma);
        for i in 0..n {
            let (u, v, a) = (state.u[i], state.v[i], state.a[i]);
            self.xyz[i] = [am * a, v + c_va * a, u + c_uv * v + c_ua * a];
            self.f_blend[i] = du * f_next[i] + af * f_n[i];
        }
        ops.residual_into(&self.f_blend, &self.xyz, am != 0.0, &mut self.rhs);
        self.factor.solve_in_place(&mut self.rhs);

        // Corrector. The finiteness check is folded into the sweep without a branch.
        let (dt2_old, dt2_new) = (dt * dt * (0.5 - beta), dt * dt * beta);
        let (dt_old, dt_new) = (dt * (1.0 - gamma), dt * gamma);
        let mut finite = true;
        for i in 0..n {
            let (u, v, a) = (state.u[i], state.v[i], state.a[i]);
            let a_new = self.rhs[i];
            let u_new = u + dt * v + dt2_old * a + dt2_new * a_new;
            let v_new = v + dt_old * a + dt_new * a_new;
            finite &= u_new.is_finite() & v_new.is_finite() & a_new.is_finite();
            state.u[i] = u_new;
            state.v[i] = v_new;
            state.a[i] = a_new;
        }
        finite
    }
}
