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
mod tests;
