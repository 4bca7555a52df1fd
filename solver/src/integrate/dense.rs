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
//! The coefficients are [`super::scheme::AVERAGE_ACCELERATION`], derived with the other
//! schemes' in `scheme`; the end-of-step law solve is [`point::solve_step`] and the
//! initial friction hold `point::hold_at_rest`, both shared with the sparse stepper.
//! N. M. Newmark, J. Eng. Mech. Div. ASCE 85 (1959) 67-94. Per step:
//! - predictor `u* = u + dt v + (1/2 - beta) dt^2 a`, `v* = v + (1 - gamma) dt a`;
//! - the linear solve `S a_lin = f - C v* - K u*`, with the effective matrix
//!   `S = M + gamma dt C + beta dt^2 K` inverted once in [`DenseStepper::new`]. The
//!   inverse is formed from the Cholesky factor of `D S D`, `D = diag(S)^-1/2`, so the
//!   mixed units of reduced coordinates (mm, rad, modal) do not spoil it; the step then
//!   uses the precomputed `[S^-1 K | S^-1 C]` and `S^-1 f` (one `r x 2r` product per
//!   step, rows zero-padded to a multiple of 4 for four partial sums; nothing
//!   allocated);
//! - the law correction: with the law forces `f_L`, `a = a_lin - W f_L`, `W = S^-1 E`
//!   (`E` the unit columns of the law DOFs), so at law DOF `j`
//!   `u_j = u_lin,j - h (G f_L)_j`, `v_j = v_lin,j - g (G f_L)_j` with
//!   `G = E^T S^-1 E`, `h = beta dt^2`, `g = gamma dt` and `u_lin = u* + h a_lin`.
//!   One law is solved exactly by [`PointLaw::solve`]`(u_lin, v_lin, h G_jj, g G_jj)`;
//!   several by Gauss-Seidel sweeps over the small Schur matrix `G` (each sweep solves
//!   law `j` exactly with the others' current forces; `G` is symmetric positive definite
//!   and every law monotone, so the sweeps converge), to a relative change of
//!   [`point::SWEEP_TOLERANCE`] (the solve shared with the
//!   Newmark stepper, [`point::solve_step`]);
//! - corrector `u = u* + beta dt^2 a`, `v = v* + gamma dt a`.
//!
//! The scheme is unconditionally stable for the linear part and adds no numerical
//! damping; its period error is `(omega dt)^2 / 12` per mode (relative).
//!
//! # Initial acceleration
//! `M a0 = f - C v0 - K u0 - sum_l e_l f_l(u0, v0)`. A friction law whose DOF starts at
//! rest takes the force that keeps it at rest (`a_i = 0`) if that force is within
//! `[-F, F]`, else `F` against the net force (projected Gauss-Seidel over
//! `E^T M^-1 E`). A wrong `a0` there would not fade: the trapezoidal rule then
//! alternates the acceleration of a stuck DOF between `a0` and `-a0` for ever. For the
//! same reason a DOF stuck for a second step in a row gets zero acceleration.
//!
//! # Static equilibrium
//! [`DenseStepper::static_equilibrium`] solves `K u + sum_l e_l k3_l u_l^3 = f` (at rest
//! the velocity terms vanish and friction's force is not unique; it is taken as zero)
//! by Newton's method on the strictly convex energy
//! `1/2 u^T K u + sum_l k3_l u_l^4 / 4 - f^T u`, with step halving when the energy
//! does not decrease.

use super::point::{self, PointLaw, MAX_SWEEPS};
use super::scheme::{check_dt, Coefficients, AVERAGE_ACCELERATION};
use crate::error::integrate::IntegrateError;
use crate::linalg::dense_spd::spd_inverse;
use nalgebra::DMatrix;

/// The dense stepper's scheme: Newmark average acceleration, from [`super::scheme`].
const SCHEME: Coefficients = AVERAGE_ACCELERATION;
/// Newmark's beta of the dense stepper's scheme.
const BETA: f64 = SCHEME.beta;
/// Newmark's gamma of the dense stepper's scheme.
const GAMMA: f64 = SCHEME.gamma;

/// Errors of the dense stepper.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DenseError {
    /// Operators, state or parameters rejected (size, symmetry, definiteness, finite).
    #[error(transparent)]
    Integrate(#[from] IntegrateError),
    /// Two laws on one DOF (combine them into one law).
    #[error("two point laws act on DOF {dof}; give one law per DOF")]
    LawTwice {
        /// The reduced DOF (0-based) both laws act on.
        dof: usize,
    },
    /// A law's implicit solve failed at this step: a non-finite input, or a softening
    /// spring that lost stability.
    #[error("the point law at DOF {dof} could not be solved at step {step}")]
    LawSolve {
        /// The step at which the solve failed.
        step: usize,
        /// The law's reduced DOF (0-based).
        dof: usize,
    },
    /// The Gauss-Seidel sweeps over several laws did not converge.
    #[error("the {laws} point laws did not converge in {MAX_SWEEPS} sweeps at step {step}")]
    SweepsNotConverged {
        /// The step whose sweeps did not converge.
        step: usize,
        /// Number of point laws.
        laws: usize,
    },
    /// Newton's method for the static equilibrium did not converge.
    #[error("static equilibrium: Newton did not converge in {iterations} iterations (residual {residual:e})")]
    StaticNotConverged {
        /// Number of Newton iterations run.
        iterations: usize,
        /// The last residual's largest entry (N in coil).
        residual: f64,
    },
}

/// One sample of the observed DOF.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sample {
    /// Displacement of the observed DOF (operator units: mm, rad, or sqrt(t) mm if modal).
    pub u: f64,
    /// Velocity of the observed DOF (displacement unit per s).
    pub v: f64,
    /// Acceleration of the observed DOF (displacement unit per s^2).
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
    /// `S^-1` (row-major), `[S^-1 K | S^-1 C | 0]` (row-major, rows padded with zeros to
    /// [`padded`]`(r)`, so one step's linear part is one product with `[u*; v*; 0]`) and
    /// `S^-1 f`.
    s_inv: Vec<f64>,
    s_inv_kc: Vec<f64>,
    s_inv_f: Vec<f64>,
    load: Vec<f64>,
    laws: Vec<Law>,
    /// The laws alone, in the order of `laws` (for [`point::solve_step`]).
    point_laws: Vec<PointLaw>,
    /// Schur matrix `G = E^T S^-1 E` of the laws (row-major, p x p).
    schur: Vec<f64>,
    // State and scratch.
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    /// The predictor `[u*; v*; 0]` (length `padded(r)`).
    star: Vec<f64>,
    forces: Vec<f64>,
    stuck: Vec<bool>,
    /// `stuck` of the step before the last.
    was_stuck: Vec<bool>,
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

/// Row length of the step's `[S^-1 K | S^-1 C]`: `2r` rounded up to a multiple of 4.
fn padded(r: usize) -> usize {
    (2 * r).div_ceil(4) * 4
}

/// `x . y` for lengths that are multiples of 4, with four partial sums: a single
/// running sum is a chain of dependent additions, which for the short rows here costs
/// more than the products.
#[inline]
fn dot(x: &[f64], y: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    for (p, q) in x.chunks_exact(4).zip(y.chunks_exact(4)) {
        for k in 0..4 {
            acc[k] += p[k] * q[k];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
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
        check_dt(dt)?;
        let (cm, cc, ck) = SCHEME.effective(dt);
        let S = m * cm + c * cc + k * ck;
        let s_inv = spd_inverse("M + gamma dt C + beta dt^2 K", &S)?;
        let m_inv = spd_inverse("M", m)?;
        let mut kept: Vec<Law> = Vec::with_capacity(laws.len());
        for &(dof, law) in laws {
            if dof >= r {
                return Err(IntegrateError::DofOutOfRange { dof, n_dofs: r }.into());
            }
            // The cubic spring takes either sign (a softening spring is guarded by
            // the solve); the dashpot and the friction must be non-negative.
            for (name, value, min) in [
                ("cubic", law.cubic, f64::NEG_INFINITY),
                ("quadratic", law.quadratic, 0.0),
                ("friction", law.friction, 0.0),
            ] {
                if !(value.is_finite() && value >= min) {
                    return Err(IntegrateError::InvalidParameter {
                        scheme: "point law",
                        name,
                        value,
                        min,
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
            s_inv_kc: {
                let (sk, sc) = (&s_inv * k, &s_inv * c);
                (0..r)
                    .flat_map(|i| {
                        let (sk, sc) = (&sk, &sc);
                        (0..padded(r)).map(move |j| match j {
                            j if j < r => sk[(i, j)],
                            j if j < 2 * r => sc[(i, j - r)],
                            _ => 0.0,
                        })
                    })
                    .collect()
            },
            s_inv_f: vec![0.0; r],
            load: vec![0.0; r],
            point_laws: kept.iter().map(|l| l.law).collect(),
            laws: kept,
            schur,
            u: vec![0.0; r],
            v: vec![0.0; r],
            a: vec![0.0; r],
            star: vec![0.0; padded(r)],
            forces: vec![0.0; p],
            stuck: vec![false; p],
            was_stuck: vec![false; p],
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
        self.stuck.fill(false);
        self.initial_friction()?;
        self.step_count = 0;
        Ok(())
    }

    /// Friction forces of the laws that start at rest: each one holds its DOF
    /// (`a_i = 0`) if it can, else slides with `F` against the net force. Solved by
    /// projected Gauss-Seidel over `E^T M^-1 E`, then `a -= M^-1 E f_F`.
    fn initial_friction(&mut self) -> Result<(), DenseError> {
        let r = self.r;
        let resting: Vec<usize> = (0..self.laws.len())
            .filter(|&j| self.laws[j].law.friction > 0.0 && self.v[self.laws[j].dof] == 0.0)
            .collect();
        if resting.is_empty() {
            return Ok(());
        }
        let mut f = vec![0.0; resting.len()];
        let (m_inv, laws, acceleration) = (&self.m_inv, &self.laws, &self.a);
        let converged = point::hold_at_rest(
            resting.len(),
            |p, q| m_inv[laws[resting[p]].dof * r + laws[resting[q]].dof],
            |p| acceleration[laws[resting[p]].dof],
            |p| laws[resting[p]].law.friction,
            point::SWEEP_TOLERANCE,
            true,
            &mut f,
        );
        if !converged {
            return Err(DenseError::SweepsNotConverged {
                step: 0,
                laws: resting.len(),
            });
        }
        for (&j, &fj) in resting.iter().zip(&f) {
            let d = self.laws[j].dof;
            for i in 0..r {
                self.a[i] -= self.m_inv[i * r + d] * fj;
            }
        }
        for &j in &resting {
            let d = self.laws[j].dof;
            if self.a[d].abs() <= 1e-14 * self.a.iter().fold(0.0f64, |m, x| m.max(x.abs())) {
                self.a[d] = 0.0;
            }
        }
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
        let (u_star, rest) = self.star.split_at_mut(r);
        let v_star = &mut rest[..r];
        for i in 0..r {
            u_star[i] = self.u[i] + dt * self.v[i] + (0.5 - BETA) * dt * dt * self.a[i];
            v_star[i] = self.v[i] + (1.0 - GAMMA) * dt * self.a[i];
        }
        // a_lin = S^-1 f - [S^-1 K | S^-1 C] [u*; v*].
        for ((ai, row), fi) in self
            .a
            .iter_mut()
            .zip(self.s_inv_kc.chunks_exact(padded(r)))
            .zip(&self.s_inv_f)
        {
            *ai = fi - dot(row, &self.star);
        }
        self.step_count += 1;
        if !self.laws.is_empty() {
            self.was_stuck.copy_from_slice(&self.stuck);
            self.correct_laws(h, g)?;
        }
        for i in 0..r {
            self.u[i] = self.star[i] + h * self.a[i];
            self.v[i] = self.star[r + i] + g * self.a[i];
        }
        // A stuck DOF is at rest exactly: v = 0 (the solve's v* - g f leaves rounding).
        // Stuck for a second step in a row, its acceleration is zero too: the step that
        // stopped it left the stopping acceleration in `a`, and the trapezoidal rule
        // with v pinned at 0 would flip its sign at every later step (a_{n+1} = -a_n),
        // feeding an alternating inertia force to the coordinates coupled to it by M.
        // From a = 0 every later held step gives a = 0 exactly. (One held step alone is
        // a turning point that friction catches for a step; its acceleration is real.)
        for ((law, &stuck), &was) in self.laws.iter().zip(&self.stuck).zip(&self.was_stuck) {
            if stuck {
                self.v[law.dof] = 0.0;
                if was {
                    self.a[law.dof] = 0.0;
                }
            }
        }
        // One sum flags any NaN or infinity (or an overflow, equally fatal).
        if !self.a.iter().sum::<f64>().is_finite() {
            let dof = self.a.iter().position(|x| !x.is_finite()).unwrap_or(0);
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
        let (star, a, r, data) = (&self.star, &self.a, self.r, &self.laws);
        let linear = |j: usize| {
            let d = data[j].dof;
            (star[d] + h * a[d], star[r + d] + g * a[d])
        };
        point::solve_step(
            &self.point_laws,
            linear,
            &self.schur,
            h,
            g,
            &mut self.forces,
            &mut self.stuck,
        )
        .map_err(|e| match e {
            point::StepLawError::Unsolvable { law } => DenseError::LawSolve {
                step,
                dof: self.laws[law].dof,
            },
            point::StepLawError::NotConverged { .. } => {
                DenseError::SweepsNotConverged { step, laws: p }
            }
        })?;
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
            // A softening law loses stability beyond the compression where its tangent
            // cancels K: the iterates stay where K + tangent is positive definite (the
            // region holding the unloaded state and the stable equilibrium), so a full
            // Newton step that jumps past the limit is shortened, not fatal.
            let stable = |u: &[f64]| -> bool {
                let mut kt = k.clone();
                for law in &self.laws {
                    kt[(law.dof, law.dof)] += law.law.tangent_stiffness(u[law.dof]);
                }
                kt.cholesky().is_some()
            };
            let du = inv * nalgebra::DVector::from_column_slice(&res);
            let e0 = energy(&u);
            let mut t = 1.0;
            let mut trial: Vec<f64>;
            loop {
                trial = (0..r).map(|i| u[i] - t * du[i]).collect();
                if (energy(&trial) <= e0 && stable(&trial)) || t < 1e-10 {
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    fn sdof(m: f64, c: f64, k: f64, dt: f64, laws: &[(usize, PointLaw)]) -> DenseStepper {
        let one = |x: f64| DMatrix::from_element(1, 1, x);
        DenseStepper::new(&one(m), &one(c), &one(k), dt, laws).unwrap()
    }

    /// Every displacement of a run, step by step.
    fn run(s: &mut DenseStepper, u0: &[f64], v0: &[f64], steps: usize) -> Vec<Vec<f64>> {
        s.set_state(u0, v0).unwrap();
        let mut out = vec![u0.to_vec()];
        for _ in 0..steps {
            s.step().unwrap();
            out.push(s.state().0.to_vec());
        }
        out
    }

    /// Times of the upward zero crossings, linearly interpolated.
    fn up_crossings(x: &[f64], dt: f64) -> Vec<f64> {
        x.windows(2)
            .enumerate()
            .filter(|(_, w)| w[0] < 0.0 && w[1] >= 0.0)
            .map(|(i, w)| (i as f64 + w[0] / (w[0] - w[1])) * dt)
            .collect()
    }

    fn mean_period(x: &[f64], dt: f64) -> f64 {
        let c = up_crossings(x, dt);
        (c[c.len() - 1] - c[0]) / (c.len() - 1) as f64
    }

    /// Average acceleration lengthens the period by (omega dt)^2 / 12 and does not damp:
    /// the damped decay follows the exact solution with that period, to a residual far
    /// below the phase error itself.
    #[test]
    fn linear_damped_decay_matches_the_exact_solution_with_the_known_period_error() {
        let (w, zeta) = (TAU, 0.01);
        let dt = 0.01; // omega dt = 0.0628: period error 3.3e-4
        let mut s = sdof(1.0, 2.0 * zeta * w, w * w, dt, &[]);
        let steps = 1000; // 10 periods
        let u: Vec<f64> = run(&mut s, &[1.0], &[0.0], steps)
            .iter()
            .map(|x| x[0])
            .collect();
        let exact = |t: f64, w: f64| {
            let wd = w * (1.0 - zeta * zeta).sqrt();
            (-zeta * w * t).exp() * ((wd * t).cos() + zeta * w / wd * (wd * t).sin())
        };
        let w_h = w / (1.0 + (w * dt).powi(2) / 12.0);
        let (mut err, mut err_shifted) = (0.0f64, 0.0f64);
        for (n, &x) in u.iter().enumerate() {
            let t = n as f64 * dt;
            err = err.max((x - exact(t, w)).abs());
            err_shifted = err_shifted.max((x - exact(t, w_h)).abs());
        }
        // The phase lag w t (w dt)^2/12 on the decaying envelope, at its largest.
        let phase = (0..=steps)
            .map(|n| {
                let t = n as f64 * dt;
                (-zeta * w * t).exp() * w * t * (w * dt).powi(2) / 12.0
            })
            .fold(0.0, f64::max);
        eprintln!(
            "max error {err:e} (phase bound {phase:e}), with the period error {err_shifted:e}"
        );
        assert!(err < 1.05 * phase && err > 0.9 * phase);
        assert!(err_shifted < 0.05 * err);
        let period = mean_period(&u, dt);
        let expected = TAU / (w * (1.0 - zeta * zeta).sqrt()) * (1.0 + (w * dt).powi(2) / 12.0);
        assert!(
            (period / expected - 1.0).abs() < 2e-5,
            "{period} vs {expected}"
        );
    }

    /// Coulomb friction: each half cycle loses 2F/k of amplitude (4F/k per cycle) at
    /// the undamped frequency, until the spring force can no longer beat F.
    #[test]
    fn coulomb_friction_loses_four_f_over_k_per_cycle_and_sticks() {
        let (k, f) = (1.0, 0.01);
        let law = PointLaw {
            friction: f,
            ..Default::default()
        };
        let dt = TAU / 4000.0;
        let mut s = sdof(1.0, 0.0, k, dt, &[(0, law)]);
        let u: Vec<f64> = run(&mut s, &[1.0], &[0.0], 4000 * 30)
            .iter()
            .map(|x| x[0])
            .collect();
        let mut peaks = vec![u[0].abs()];
        for i in 1..u.len() - 1 {
            if u[i].abs() > u[i - 1].abs() && u[i].abs() >= u[i + 1].abs() && u[i].abs() > f / k {
                peaks.push(u[i].abs());
            }
        }
        // A peak sampled off its crest is low by at most A (omega dt)^2 / 8 = 2.5e-7 A
        // (A <= 1 here).
        let worst = peaks
            .windows(2)
            .map(|p| (p[0] - p[1] - 2.0 * f / k).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "coulomb: {} peaks, worst loss error {worst:e} (2F/k = {})",
            peaks.len(),
            2.0 * f / k
        );
        for pair in peaks.windows(2) {
            let loss = pair[0] - pair[1];
            assert!(
                (loss - 2.0 * f / k).abs() < 2.5e-7,
                "{loss} vs {}",
                2.0 * f / k
            );
        }
        // 1 - 2F/k per half cycle: 50 half cycles reach 0, the last peak is within 2F/k
        // of the stop and the mass comes to rest at |u| <= F/k.
        assert_eq!(peaks.len(), 50, "{peaks:?}");
        let (u_end, v_end, _) = s.state();
        assert!(u_end[0].abs() <= f / k * (1.0 + 1e-9) && v_end[0] == 0.0);
    }

    /// A preloaded mass held by friction stays exactly where it is.
    #[test]
    fn friction_holds_a_mass_that_the_spring_cannot_move() {
        let law = PointLaw {
            friction: 0.5,
            ..Default::default()
        };
        let mut s = sdof(1.0, 0.1, 1.0, 0.01, &[(0, law)]);
        let u = run(&mut s, &[0.4], &[0.0], 1000);
        assert!(u.iter().all(|x| (x[0] - 0.4).abs() < 1e-15));
        assert_eq!(s.state().1[0], 0.0);
        assert!(s.state().2[0].abs() < 1e-15, "no acceleration ringing");
        assert!((s.law_forces()[0] + 0.4).abs() < 1e-12);
        // Two coupled DOFs, both held (the projected Gauss-Seidel start): nothing moves.
        let m = DMatrix::from_row_slice(2, 2, &[1.0, 0.3, 0.3, 1.0]);
        let k = DMatrix::from_row_slice(2, 2, &[2.0, -1.0, -1.0, 2.0]);
        let mut s = DenseStepper::new(&m, &(&k * 0.01), &k, 0.01, &[(0, law), (1, law)]).unwrap();
        let u = run(&mut s, &[0.1, 0.3], &[0.0, 0.0], 500);
        for x in &u {
            assert!(
                (x[0] - 0.1).abs() < 1e-14 && (x[1] - 0.3).abs() < 1e-14,
                "{x:?}"
            );
        }
        assert!(s.state().2.iter().all(|a| a.abs() < 1e-13));
        // DOF 1 cannot hold (spring force 1.1 > 0.5) and slides back; holding DOF 0 would
        // then take 0.4 + 0.3 * 0.6 = 0.58 > 0.5 through the mass coupling, so it slides
        // forward: M a0 = -K u - (F, -F) = (-0.1, -0.6).
        let mut s = DenseStepper::new(&m, &(&k * 0.0), &k, 0.01, &[(0, law), (1, law)]).unwrap();
        s.set_state(&[0.1, 0.6], &[0.0, 0.0]).unwrap();
        let a = s.state().2.to_vec();
        let ma = [a[0] + 0.3 * a[1], 0.3 * a[0] + a[1]];
        assert!(a[0] > 0.0 && a[1] < 0.0, "{a:?}");
        assert!(
            (ma[0] + 0.1).abs() < 1e-14 && (ma[1] + 0.6).abs() < 1e-14,
            "{ma:?}"
        );
    }

    /// Undamped cubic oscillator from rest at amplitude A: the period is the exact
    /// quadrature `T = 4 int_0^{pi/2} dtheta / sqrt(k + k3 A^2 (1 + sin^2) / 2)` (m = 1)
    /// to the scheme's (omega dt)^2/12, and the harmonic-balance backbone
    /// `w^2 = w0^2 (1 + 3 k3 A^2 / 4k)` to its own O((k3 A^2/k)^2) error.
    #[test]
    fn cubic_spring_follows_the_exact_period_and_the_backbone() {
        let (k, k3, a) = (1.0, 0.1, 1.0);
        let law = PointLaw {
            cubic: k3,
            ..Default::default()
        };
        let dt = TAU / 2000.0;
        let mut s = sdof(1.0, 0.0, k, dt, &[(0, law)]);
        let u: Vec<f64> = run(&mut s, &[a], &[0.0], 2000 * 20)
            .iter()
            .map(|x| x[0])
            .collect();
        let period = mean_period(&u, dt);
        let n = 2000;
        let h = 0.5 * PI / n as f64;
        let g = |th: f64| 1.0 / (k + k3 * a * a * (1.0 + th.sin().powi(2)) / 2.0).sqrt();
        let simpson: f64 = (0..=n)
            .map(|i| {
                let wgt = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                wgt * g(i as f64 * h)
            })
            .sum::<f64>()
            * h
            / 3.0;
        let exact = 4.0 * simpson;
        let w = TAU / exact;
        let scheme = (w * dt).powi(2) / 12.0;
        eprintln!(
            "cubic: period {period}, exact {exact}, relative {:e} (scheme {scheme:e})",
            period / exact - 1.0
        );
        assert!((period / exact - 1.0).abs() < 1.5 * scheme);
        let backbone = TAU / (k * (1.0 + 0.75 * k3 * a * a / k)).sqrt();
        let kappa = k3 * a * a / k;
        assert!((exact / backbone - 1.0).abs() < 0.02 * kappa * kappa);
    }

    /// Two coupled DOFs with a cubic spring and a velocity-squared dashpot at each (the
    /// Gauss-Seidel path) against a fine fourth-order Runge-Kutta reference: the error is
    /// second order in dt.
    #[test]
    fn two_laws_converge_at_second_order_to_a_runge_kutta_reference() {
        let m = DMatrix::from_row_slice(2, 2, &[1.0, 0.2, 0.2, 0.5]);
        let k = DMatrix::from_row_slice(2, 2, &[3.0, -1.0, -1.0, 2.0]);
        let c = &k * 0.01;
        let laws = [
            (
                0,
                PointLaw {
                    cubic: 2.0,
                    quadratic: 0.1,
                    friction: 0.0,
                },
            ),
            (
                1,
                PointLaw {
                    cubic: 1.0,
                    quadratic: 0.2,
                    friction: 0.0,
                },
            ),
        ];
        let (u0, v0) = ([0.8, -0.5], [0.0, 1.0]);
        let t_end = 5.0;
        // RK4 reference.
        let m_inv = m.clone().try_inverse().unwrap();
        let rhs = |x: &[f64; 4]| -> [f64; 4] {
            let (u, v) = ([x[0], x[1]], [x[2], x[3]]);
            let mut f = [0.0; 2];
            for i in 0..2 {
                f[i] = -(0..2)
                    .map(|j| k[(i, j)] * u[j] + c[(i, j)] * v[j])
                    .sum::<f64>();
            }
            for &(d, law) in &laws {
                f[d] -= law.force(u[d], v[d]);
            }
            let a: Vec<f64> = (0..2)
                .map(|i| (0..2).map(|j| m_inv[(i, j)] * f[j]).sum())
                .collect();
            [v[0], v[1], a[0], a[1]]
        };
        let mut x = [u0[0], u0[1], v0[0], v0[1]];
        let n_ref = 100_000;
        let h = t_end / n_ref as f64;
        for _ in 0..n_ref {
            let k1 = rhs(&x);
            let add = |x: &[f64; 4], k: &[f64; 4], s: f64| {
                [
                    x[0] + s * k[0],
                    x[1] + s * k[1],
                    x[2] + s * k[2],
                    x[3] + s * k[3],
                ]
            };
            let k2 = rhs(&add(&x, &k1, h / 2.0));
            let k3 = rhs(&add(&x, &k2, h / 2.0));
            let k4 = rhs(&add(&x, &k3, h));
            for i in 0..4 {
                x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        let errors: Vec<f64> = [500, 1000, 2000]
            .iter()
            .map(|&steps| {
                let mut s = DenseStepper::new(&m, &c, &k, t_end / steps as f64, &laws).unwrap();
                let u = run(&mut s, &u0, &v0, steps);
                let end = u.last().unwrap();
                (end[0] - x[0]).hypot(end[1] - x[1])
            })
            .collect();
        eprintln!("two laws: errors {errors:?}");
        for pair in errors.windows(2) {
            let order = (pair[0] / pair[1]).log2();
            assert!((order - 2.0).abs() < 0.1, "order {order}");
        }
        assert!(errors[2] < 1e-4);
    }

    #[test]
    fn static_equilibrium_solves_the_cubic_balance() {
        let law = PointLaw {
            cubic: 1.0,
            ..Default::default()
        };
        let s = sdof(1.0, 0.0, 1.0, 0.01, &[(0, law)]);
        // u + u^3 = 2 at u = 1.
        let u = s.static_equilibrium(&[2.0]).unwrap();
        assert!((u[0] - 1.0).abs() < 1e-14);
        let m = DMatrix::identity(2, 2);
        let k = DMatrix::from_row_slice(2, 2, &[3.0, -1.0, -1.0, 2.0]);
        let s = DenseStepper::new(&m, &(&m * 0.0), &k, 0.01, &[(1, law)]).unwrap();
        let f = [0.5, -4.0];
        let u = s.static_equilibrium(&f).unwrap();
        let r0 = 3.0 * u[0] - u[1] - f[0];
        let r1 = -u[0] + 2.0 * u[1] + u[1].powi(3) - f[1];
        assert!(r0.abs() < 1e-13 && r1.abs() < 1e-12, "{r0} {r1}");
    }

    #[test]
    fn bad_inputs_are_errors() {
        let one = DMatrix::from_element(1, 1, 1.0);
        let zero = DMatrix::from_element(1, 1, 0.0);
        assert!(DenseStepper::new(&one, &zero, &one, 0.0, &[]).is_err());
        assert!(DenseStepper::new(&zero, &zero, &zero, 0.1, &[]).is_err());
        // A negative dashpot (a softening cubic, k3 < 0, is a valid law).
        let law = PointLaw {
            quadratic: -1.0,
            ..Default::default()
        };
        assert!(DenseStepper::new(&one, &zero, &one, 0.1, &[(0, law)]).is_err());
        assert!(DenseStepper::new(&one, &zero, &one, 0.1, &[(1, PointLaw::default())]).is_err());
        let law = PointLaw {
            cubic: 1.0,
            ..Default::default()
        };
        assert!(matches!(
            DenseStepper::new(&one, &zero, &one, 0.1, &[(0, law), (0, law)]),
            Err(DenseError::LawTwice { dof: 0 })
        ));
        let asym = DMatrix::from_row_slice(2, 2, &[1.0, 0.5, 0.0, 1.0]);
        let id = DMatrix::identity(2, 2);
        assert!(DenseStepper::new(&id, &(&id * 0.0), &asym, 0.1, &[]).is_err());
        let mut s = DenseStepper::new(&one, &zero, &one, 0.1, &[]).unwrap();
        assert!(s.set_state(&[f64::NAN], &[0.0]).is_err());
        assert!(s.simulate(&[1.0], &[0.0], 3, 0, 0).is_err());
        assert!(s.simulate(&[1.0], &[0.0], 3, 1, 1).is_err());
        let samples = s.simulate(&[1.0], &[0.0], 3, 2, 0).unwrap();
        assert_eq!(samples.len(), 3);
        assert_eq!(samples[0].u, 1.0);
    }
}
