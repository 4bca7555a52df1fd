//! A small dense Newmark integrator for reduced models (a handful of DOFs, e.g. a
//! Craig-Bampton model from [`crate::reduce`]) with nonlinear point laws, built to be
//! run thousands of times inside a fit.
//!
//! # Equation
//! `M a + C v + K u + sum_l e_{i_l} f_l(u_{i_l}, v_{i_l}) = f`, `M`, `C`, `K` dense
//! symmetric `r x r` (`M`, and the effective matrix below, positive definite), `f` a
//! constant load (the gravity preload; zero by default), `f_l` a [`PointLaw`] at DOF
//! `i_l` (at most one law per DOF). Units are the operator's (coil: mm, N, t, s).
//!
//! # Scheme: Newmark average acceleration (beta = 1/4, gamma = 1/2)
//! N. M. Newmark, J. Eng. Mech. Div. ASCE 85 (1959) 67-94. Per step:
//! - predictor `u* = u + dt v + (1/2 - beta) dt^2 a`, `v* = v + (1 - gamma) dt a`;
//! - the linear solve `S a_lin = f - C v* - K u*`, with the effective matrix
//!   `S = M + gamma dt C + beta dt^2 K` inverted once in [`DenseStepper::new`]. The
//!   inverse is formed from the Cholesky factor of `D S D`, `D = diag(S)^-1/2`, so the
//!   mixed units of reduced coordinates (mm, rad, modal) do not spoil it; the step then
//!   uses the precomputed products `S^-1 K`, `S^-1 C` and `S^-1 f` (two `r x r`
//!   products per step, nothing allocated);
//! - the law correction: with the law forces `f_L`, `a = a_lin - W f_L`, `W = S^-1 E`
//!   (`E` the unit columns of the law DOFs), so at law DOF `j`
//!   `u_j = u_lin,j - h (G f_L)_j`, `v_j = v_lin,j - g (G f_L)_j` with
//!   `G = E^T S^-1 E`, `h = beta dt^2`, `g = gamma dt` and `u_lin = u* + h a_lin`.
//!   One law is solved exactly by [`PointLaw::solve`]`(u_lin, v_lin, h G_jj, g G_jj)`;
//!   several by Gauss-Seidel sweeps over the small Schur matrix `G` (each sweep solves
//!   law `j` exactly with the others' current forces; `G` is symmetric positive definite
//!   and every law monotone, so the sweeps converge), to a relative change of
//!   [`GAUSS_SEIDEL_TOLERANCE`];
//! - corrector `u = u* + beta dt^2 a`, `v = v* + gamma dt a`.
//!
//! The scheme is unconditionally stable for the linear part and adds no numerical
//! damping; its period error is `(omega dt)^2 / 12` per mode (relative).
//!
//! # Initial acceleration
//! `M a0 = f - C v0 - K u0 - sum_l e_l f_l(u0, v0)`, the friction term taken as zero
//! when a law DOF starts at rest (`sgn(0) = 0`: its value is set by the first step's
//! implicit solve, which sticks or slips as the balance says).
//!
//! # Static equilibrium
//! [`DenseStepper::static_equilibrium`] solves `K u + sum_l e_l k3_l u_l^3 = f` (at rest
//! the velocity terms vanish and friction's force is not unique; it is taken as zero)
//! by Newton's method on the strictly convex energy
//! `1/2 u^T K u + sum_l k3_l u_l^4 / 4 - f^T u`, with step halving when the energy
//! does not decrease.

use super::{IntegrateError, PointLaw};
use nalgebra::DMatrix;

/// Newmark's beta of the average-acceleration scheme.
pub const BETA: f64 = 0.25;
/// Newmark's gamma of the average-acceleration scheme.
pub const GAMMA: f64 = 0.5;

/// Relative change of the law forces at which the Gauss-Seidel sweeps stop (several
/// laws only): a few ulp of the forces.
pub const GAUSS_SEIDEL_TOLERANCE: f64 = 1e-14;

/// Most Gauss-Seidel sweeps in one step.
pub const MAX_SWEEPS: usize = 200;

/// Errors of the dense stepper.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DenseError {
    /// Operators, state or parameters rejected (size, symmetry, definiteness, finite).
    #[error(transparent)]
    Integrate(#[from] IntegrateError),
    /// Two laws on one DOF (combine them into one law).
    #[error("two point laws act on DOF {dof}; give one law per DOF")]
    LawTwice { dof: usize },
    /// A law's implicit solve failed (a non-finite input) at this step.
    #[error("the point law at DOF {dof} could not be solved at step {step}")]
    LawSolve { step: usize, dof: usize },
    /// The Gauss-Seidel sweeps over several laws did not converge.
    #[error("the {laws} point laws did not converge in {MAX_SWEEPS} sweeps at step {step}")]
    SweepsNotConverged { step: usize, laws: usize },
    /// Newton's method for the static equilibrium did not converge.
    #[error("static equilibrium: Newton did not converge in {iterations} iterations (residual {residual:e})")]
    StaticNotConverged { iterations: usize, residual: f64 },
}

/// One sample of the observed DOF.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sample {
    pub u: f64,
    pub v: f64,
    pub a: f64,
}

/// A law at a DOF with the precomputed correction data.
#[derive(Debug, Clone)]
struct Law {
    dof: usize,
    law: PointLaw,
    /// Column `S^-1 e_dof` (length r).
    w: Vec<f64>,
}

/// Dense average-acceleration stepper with point laws (see the module docs).
#[derive(Debug, Clone)]
pub struct DenseStepper {
    r: usize,
    dt: f64,
    /// Row-major copies of the operators.
    k: Vec<f64>,
    c: Vec<f64>,
    /// `M^-1` (row-major) for the initial acceleration.
    m_inv: Vec<f64>,
    /// `S^-1`, `S^-1 K`, `S^-1 C` (row-major) and `S^-1 f`.
    s_inv: Vec<f64>,
    s_inv_k: Vec<f64>,
    s_inv_c: Vec<f64>,
    s_inv_f: Vec<f64>,
    load: Vec<f64>,
    laws: Vec<Law>,
    /// Schur matrix `G = E^T S^-1 E` of the laws (row-major, p x p).
    schur: Vec<f64>,
    // State and scratch.
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    u_star: Vec<f64>,
    v_star: Vec<f64>,
    forces: Vec<f64>,
    step_count: usize,
}

/// Checks a square, symmetric, finite matrix of size `r`.
fn check_matrix(name: &'static str, a: &DMatrix<f64>, r: usize) -> Result<(), IntegrateError> {
    if a.nrows() != r || a.ncols() != r {
        return Err(IntegrateError::DimensionMismatch {
            what: name,
            expected: r,
            found: if a.nrows() != r { a.nrows() } else { a.ncols() },
        });
    }
    let scale = a.amax();
    for j in 0..r {
        for i in 0..r {
            if !a[(i, j)].is_finite() {
                return Err(IntegrateError::NonFiniteEntry {
                    matrix: name,
                    row: i,
                    col: j,
                });
            }
            if (a[(i, j)] - a[(j, i)]).abs() > 1e-10 * scale {
                return Err(IntegrateError::NotSymmetric {
                    matrix: name,
                    row: i,
                    col: j,
                    value: a[(i, j)],
                    transposed: a[(j, i)],
                });
            }
        }
    }
    Ok(())
}

/// Inverse of a symmetric positive definite matrix through the Cholesky factor of its
/// unit-diagonal scaling `D A D`.
fn spd_inverse(name: &'static str, a: &DMatrix<f64>) -> Result<DMatrix<f64>, IntegrateError> {
    let r = a.nrows();
    let mut d = Vec::with_capacity(r);
    for i in 0..r {
        let aii = a[(i, i)];
        if !(aii > 0.0) {
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

fn row_major(a: &DMatrix<f64>) -> Vec<f64> {
    let (r, c) = a.shape();
    let mut out = Vec::with_capacity(r * c);
    for i in 0..r {
        for j in 0..c {
            out.push(a[(i, j)]);
        }
    }
    out
}

/// `y = A x` for row-major `A` (r x r).
#[inline]
fn matvec(a: &[f64], x: &[f64], y: &mut [f64]) {
    let r = x.len();
    for (row, yi) in a.chunks_exact(r).zip(y.iter_mut()) {
        *yi = row.iter().zip(x).map(|(p, q)| p * q).sum();
    }
}

fn check_vector(what: &'static str, x: &[f64], r: usize) -> Result<(), IntegrateError> {
    if x.len() != r {
        return Err(IntegrateError::DimensionMismatch {
            what,
            expected: r,
            found: x.len(),
        });
    }
    if let Some(index) = x.iter().position(|v| !v.is_finite()) {
        return Err(IntegrateError::NonFiniteInput { what, index });
    }
    Ok(())
}

impl DenseStepper {
    /// Checks the operators, forms `S^-1` and the law data for step `dt`. Laws whose
    /// coefficients are all zero are dropped.
    #[allow(non_snake_case)]
    pub fn new(
        m: &DMatrix<f64>,
        c: &DMatrix<f64>,
        k: &DMatrix<f64>,
        dt: f64,
        laws: &[(usize, PointLaw)],
    ) -> Result<Self, DenseError> {
        let r = m.nrows();
        check_matrix("M", m, r)?;
        check_matrix("C", c, r)?;
        check_matrix("K", k, r)?;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(IntegrateError::InvalidTimeStep { dt }.into());
        }
        let S = m + c * (GAMMA * dt) + k * (BETA * dt * dt);
        let s_inv = spd_inverse("M + gamma dt C + beta dt^2 K", &S)?;
        let m_inv = spd_inverse("M", m)?;
        let mut kept: Vec<Law> = Vec::with_capacity(laws.len());
        for &(dof, law) in laws {
            if dof >= r {
                return Err(IntegrateError::DofOutOfRange { dof, n_dofs: r }.into());
            }
            for (name, value) in [
                ("cubic", law.cubic),
                ("quadratic", law.quadratic),
                ("friction", law.friction),
            ] {
                if !(value.is_finite() && value >= 0.0) {
                    return Err(IntegrateError::InvalidParameter {
                        scheme: "point law",
                        name,
                        value,
                        min: 0.0,
                        max: f64::INFINITY,
                    }
                    .into());
                }
            }
            if laws.iter().filter(|(d, _)| *d == dof).count() > 1 {
                return Err(DenseError::LawTwice { dof });
            }
            if law.is_zero() {
                continue;
            }
            kept.push(Law {
                dof,
                law,
                w: s_inv.column(dof).iter().copied().collect(),
            });
        }
        let p = kept.len();
        let mut schur = vec![0.0; p * p];
        for (a, la) in kept.iter().enumerate() {
            for (b, lb) in kept.iter().enumerate() {
                schur[a * p + b] = lb.w[la.dof];
            }
        }
        Ok(DenseStepper {
            r,
            dt,
            k: row_major(k),
            c: row_major(c),
            m_inv: row_major(&m_inv),
            s_inv: row_major(&s_inv),
            s_inv_k: row_major(&(&s_inv * k)),
            s_inv_c: row_major(&(&s_inv * c)),
            s_inv_f: vec![0.0; r],
            load: vec![0.0; r],
            laws: kept,
            schur,
            u: vec![0.0; r],
            v: vec![0.0; r],
            a: vec![0.0; r],
            u_star: vec![0.0; r],
            v_star: vec![0.0; r],
            forces: vec![0.0; p],
            step_count: 0,
        })
    }

    /// Number of DOFs.
    pub fn dim(&self) -> usize {
        self.r
    }

    /// The time step.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Sets the constant external load `f` (e.g. gravity on the weight). Call
    /// [`DenseStepper::set_state`] afterwards: the initial acceleration depends on it.
    pub fn set_load(&mut self, f: &[f64]) -> Result<(), DenseError> {
        check_vector("load", f, self.r)?;
        self.load.copy_from_slice(f);
        matvec(&self.s_inv, f, &mut self.s_inv_f);
        Ok(())
    }

    /// Sets `u`, `v` and the initial acceleration (module docs).
    pub fn set_state(&mut self, u0: &[f64], v0: &[f64]) -> Result<(), DenseError> {
        check_vector("initial displacement", u0, self.r)?;
        check_vector("initial velocity", v0, self.r)?;
        self.u.copy_from_slice(u0);
        self.v.copy_from_slice(v0);
        let r = self.r;
        let mut rhs = self.load.clone();
        let mut ku = vec![0.0; r];
        let mut cv = vec![0.0; r];
        matvec(&self.k, u0, &mut ku);
        matvec(&self.c, v0, &mut cv);
        for i in 0..r {
            rhs[i] -= ku[i] + cv[i];
        }
        for law in &self.laws {
            rhs[law.dof] -= law.law.force(u0[law.dof], v0[law.dof]);
        }
        matvec(&self.m_inv, &rhs, &mut self.a);
        self.forces.fill(0.0);
        self.step_count = 0;
        Ok(())
    }

    /// The current state `(u, v, a)`.
    pub fn state(&self) -> (&[f64], &[f64], &[f64]) {
        (&self.u, &self.v, &self.a)
    }

    /// The law forces of the last step, in the order of the (non-zero) laws given.
    pub fn law_forces(&self) -> &[f64] {
        &self.forces
    }

    /// One step (module docs). Allocation-free.
    #[allow(non_snake_case)]
    pub fn step(&mut self) -> Result<(), DenseError> {
        let r = self.r;
        let dt = self.dt;
        let h = BETA * dt * dt;
        let g = GAMMA * dt;
        for i in 0..r {
            self.u_star[i] = self.u[i] + dt * self.v[i] + (0.5 - BETA) * dt * dt * self.a[i];
            self.v_star[i] = self.v[i] + (1.0 - GAMMA) * dt * self.a[i];
        }
        // a_lin = S^-1 f - S^-1 K u* - S^-1 C v*.
        for i in 0..r {
            let kr = &self.s_inv_k[i * r..(i + 1) * r];
            let cr = &self.s_inv_c[i * r..(i + 1) * r];
            let mut acc = self.s_inv_f[i];
            for j in 0..r {
                acc -= kr[j] * self.u_star[j] + cr[j] * self.v_star[j];
            }
            self.a[i] = acc;
        }
        self.step_count += 1;
        if !self.laws.is_empty() {
            self.correct_laws(h, g)?;
        }
        for i in 0..r {
            self.u[i] = self.u_star[i] + h * self.a[i];
            self.v[i] = self.v_star[i] + g * self.a[i];
        }
        if let Some(dof) = self.a.iter().position(|x| !x.is_finite()) {
            return Err(IntegrateError::NonFiniteState {
                step: self.step_count,
                time: self.step_count as f64 * dt,
                dof,
            }
            .into());
        }
        Ok(())
    }

    /// Solves the laws' forces and applies `a -= W f_L`.
    fn correct_laws(&mut self, h: f64, g: f64) -> Result<(), DenseError> {
        let p = self.laws.len();
        let step = self.step_count;
        // Linear end-of-step values at the law DOFs.
        let lin = |s: &Self, j: usize| {
            let d = s.laws[j].dof;
            (s.u_star[d] + h * s.a[d], s.v_star[d] + g * s.a[d])
        };
        if p == 1 {
            let (ul, vl) = lin(self, 0);
            let gjj = self.schur[0];
            let sol = self.laws[0]
                .law
                .solve(ul, vl, h * gjj, g * gjj)
                .ok_or(DenseError::LawSolve {
                    step,
                    dof: self.laws[0].dof,
                })?;
            self.forces[0] = sol.force;
        } else {
            // Gauss-Seidel from the previous step's forces.
            let mut converged = false;
            for _ in 0..MAX_SWEEPS {
                let mut change: f64 = 0.0;
                let mut size: f64 = 0.0;
                for j in 0..p {
                    let (ul, vl) = lin(self, j);
                    let others: f64 = (0..p)
                        .filter(|&k| k != j)
                        .map(|k| self.schur[j * p + k] * self.forces[k])
                        .sum();
                    let gjj = self.schur[j * p + j];
                    let sol = self.laws[j]
                        .law
                        .solve(ul - h * others, vl - g * others, h * gjj, g * gjj)
                        .ok_or(DenseError::LawSolve {
                            step,
                            dof: self.laws[j].dof,
                        })?;
                    change = change.max((sol.force - self.forces[j]).abs());
                    size = size.max(sol.force.abs());
                    self.forces[j] = sol.force;
                }
                if change <= GAUSS_SEIDEL_TOLERANCE * size || size == 0.0 {
                    converged = true;
                    break;
                }
            }
            if !converged {
                return Err(DenseError::SweepsNotConverged { step, laws: p });
            }
        }
        for (law, &f) in self.laws.iter().zip(&self.forces) {
            for (ai, wi) in self.a.iter_mut().zip(&law.w) {
                *ai -= wi * f;
            }
        }
        Ok(())
    }

    /// Runs from `(u0, v0)` and records DOF `observe` at the start and after every
    /// `substeps` steps: `n_samples` samples at times `k substeps dt`, `k = 0..n_samples`.
    pub fn simulate(
        &mut self,
        u0: &[f64],
        v0: &[f64],
        n_samples: usize,
        substeps: usize,
        observe: usize,
    ) -> Result<Vec<Sample>, DenseError> {
        let mut out = Vec::with_capacity(n_samples);
        self.simulate_into(u0, v0, n_samples, substeps, observe, &mut out)?;
        Ok(out)
    }

    /// As [`DenseStepper::simulate`], into a caller-owned buffer (cleared first), so a
    /// fit loop allocates nothing.
    pub fn simulate_into(
        &mut self,
        u0: &[f64],
        v0: &[f64],
        n_samples: usize,
        substeps: usize,
        observe: usize,
        out: &mut Vec<Sample>,
    ) -> Result<(), DenseError> {
        if observe >= self.r {
            return Err(IntegrateError::DofOutOfRange {
                dof: observe,
                n_dofs: self.r,
            }
            .into());
        }
        if substeps == 0 {
            return Err(IntegrateError::InvalidParameter {
                scheme: "dense simulation",
                name: "substeps",
                value: 0.0,
                min: 1.0,
                max: f64::INFINITY,
            }
            .into());
        }
        self.set_state(u0, v0)?;
        out.clear();
        for k in 0..n_samples {
            if k > 0 {
                for _ in 0..substeps {
                    self.step()?;
                }
            }
            out.push(Sample {
                u: self.u[observe],
                v: self.v[observe],
                a: self.a[observe],
            });
        }
        Ok(())
    }

    /// The static equilibrium `K u + sum_l e_l k3_l u_l^3 = f` (module docs).
    pub fn static_equilibrium(&self, f: &[f64]) -> Result<Vec<f64>, DenseError> {
        check_vector("static load", f, self.r)?;
        let r = self.r;
        let k = DMatrix::from_row_slice(r, r, &self.k);
        let energy = |u: &[f64]| -> f64 {
            let mut ku = vec![0.0; r];
            matvec(&self.k, u, &mut ku);
            let mut e: f64 = (0..r).map(|i| 0.5 * u[i] * ku[i] - f[i] * u[i]).sum();
            for law in &self.laws {
                e += 0.25 * law.law.cubic * u[law.dof].powi(4);
            }
            e
        };
        let residual = |u: &[f64]| -> Vec<f64> {
            let mut ku = vec![0.0; r];
            matvec(&self.k, u, &mut ku);
            for law in &self.laws {
                ku[law.dof] += law.law.cubic * u[law.dof].powi(3);
            }
            (0..r).map(|i| ku[i] - f[i]).collect()
        };
        let f_norm = f.iter().map(|x| x.abs()).fold(0.0, f64::max);
        let mut u = vec![0.0; r];
        const MAX_ITERATIONS: usize = 100;
        let mut res = residual(&u);
        for _ in 0..MAX_ITERATIONS {
            let res_norm = res.iter().map(|x| x.abs()).fold(0.0, f64::max);
            if res_norm <= 1e-13 * f_norm.max(f64::MIN_POSITIVE) {
                return Ok(u);
            }
            let mut kt = k.clone();
            for law in &self.laws {
                kt[(law.dof, law.dof)] += law.law.tangent_stiffness(u[law.dof]);
            }
            let inv = spd_inverse("K + tangent of the cubic laws", &kt)?;
            let du = inv * nalgebra::DVector::from_column_slice(&res);
            let e0 = energy(&u);
            let mut t = 1.0;
            let mut trial: Vec<f64>;
            loop {
                trial = (0..r).map(|i| u[i] - t * du[i]).collect();
                if energy(&trial) <= e0 || t < 1e-10 {
                    break;
                }
                t *= 0.5;
            }
            let step: f64 = du.iter().map(|x| x.abs()).fold(0.0, f64::max) * t;
            let scale = trial.iter().map(|x| x.abs()).fold(0.0, f64::max);
            u = trial;
            res = residual(&u);
            if step <= 4.0 * f64::EPSILON * scale {
                return Ok(u);
            }
        }
        let residual = res.iter().map(|x| x.abs()).fold(0.0, f64::max);
        Err(DenseError::StaticNotConverged {
            iterations: MAX_ITERATIONS,
            residual,
        })
    }
}
