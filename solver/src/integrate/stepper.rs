//! Implicit direct integration of `M a + C v + K u = f(t)` by the generalised-alpha
//! family, of which Newmark average acceleration and HHT-alpha are members.
//!
//! # Formulation (Chung & Hulbert 1993, in their `alpha_m`, `alpha_f` notation)
//! Newmark's update (Newmark 1959) carries the state over one step `dt`:
//! ```text
//! u_{n+1} = u_n + dt v_n + dt^2 [(1/2 - beta) a_n + beta a_{n+1}]
//! v_{n+1} = v_n + dt [(1 - gamma) a_n + gamma a_{n+1}]
//! ```
//! and the balance is enforced at shifted times, `x_{n+1-a} = (1-a) x_{n+1} + a x_n`:
//! ```text
//! M a_{n+1-am} + C v_{n+1-af} + K u_{n+1-af} = f_{n+1-af} = (1-af) f(t_{n+1}) + af f(t_n)
//! ```
//! (the load blend is exact for a load linear over the step, the usual time table).
//!
//! One predictor-solve-corrector step serves all schemes; the unknown is `a_{n+1}`:
//! ```text
//! predictor  u~ = u_n + dt v_n + dt^2 (1/2 - beta) a_n,    v~ = v_n + dt (1 - gamma) a_n
//! solve      S a_{n+1} = f_{n+1-af} - am M a_n - C [(1-af) v~ + af v_n] - K [(1-af) u~ + af u_n]
//!            S = (1-am) M + (1-af) gamma dt C + (1-af) beta dt^2 K
//! corrector  u_{n+1} = u~ + beta dt^2 a_{n+1},    v_{n+1} = v~ + gamma dt a_{n+1}
//! ```
//! `S` is `(1-af) beta dt^2` times the displacement-form effective matrix
//! `(1-af) K + (1-af) gamma/(beta dt) C + (1-am)/(beta dt^2) M`. It is symmetric
//! positive definite when M, C, K are symmetric positive semi-definite and every DOF
//! has mass or stiffness; massless rotational DOFs are therefore fine. `S` is
//! factored when the stepper is built; the ordering and storage are kept, so a new
//! `dt` or scheme ([`Stepper::set_step`]) only refactors numerically. A step
//! allocates nothing.
//!
//! # Two engines
//! * **Banded** (`banded`, the usual case for beam models): the operators' envelope
//!   under the caller's order, the caller's order with rigid-tie "hub" DOFs moved
//!   last, or reverse Cuthill-McKee (whichever is smallest); envelope Cholesky;
//!   four-row block panels for the products and the triangular solves, compiled for
//!   AVX2 + FMA where the CPU has them. One operator is eliminated from the
//!   right-hand side through `S` itself, and Rayleigh damping
//!   `C = alpha M + beta K + D` (`D` diagonal) is recognised, so a step multiplies by
//!   K only (plus a diagonal). About 13 us per step on the paper's spring
//!   (2011 DOFs), 4.4 times faster than the sparse engine (`docs/integrators.md`).
//! * **Sparse** (`sparse`): faer's simplicial Cholesky under AMD and one fused pass
//!   `M x + C y + K z` over the merged pattern, for patterns whose envelope is too
//!   wide for the banded engine.
//!
//! Both compute the same step; they differ by round-off (tests against a dense
//! reference hold the banded engine to 1e-10 of the state's size on a helix-like
//! system with a hub, and as close as the sparse engine on the paper's spring).
//!
//! # Initial acceleration
//! `a_0` solves `M a_0 = f(t_0) - C v_0 - K u_0` ([`Stepper::initial_state`]). A DOF
//! whose mass column is identically zero (a lumped mass without rotary inertia) gets
//! `a_0 = 0`: its row of the balance holds no inertia, so `a_0` there is not defined
//! by the equation. Their displacements and velocities then follow the constraint
//! exactly; their accelerations carry the mismatch with the constraint's true
//! acceleration, which average acceleration keeps as a ripple alternating every step
//! (HHT and generalised-alpha damp it like any unresolved mode). The mass matrix on
//! the remaining DOFs must be positive definite; otherwise the error names the DOF
//! whose pivot failed.
//!
//! # Schemes, their numerical damping and period error
//! For the undamped oscillator `a + w^2 u = 0` with `W = w dt`, the principal root of
//! the amplification matrix solves
//! ```text
//! (L - 1)^2 [(1-am) L + am] + W^2 [(1-af) L + af] [1 + (gamma + 1/2)(L - 1) + beta (L - 1)^2] = 0
//! ```
//! Writing `L = exp(W_num (-xi_num + i))`, a series expansion in `W` (with
//! `gamma = 1/2 - am + af`, second-order accuracy) gives the algorithmic damping
//! ratio and the relative period elongation
//! ```text
//! xi_num      = (af - am) (beta - af (1 - am)) W^3 / 2           + O(W^5)
//! T_num/T - 1 = (beta/2 - 1/24 - af (af - am)/2) W^2              + O(W^4)
//! ```
//! ([`Coefficients::algorithmic_damping`], [`Coefficients::period_elongation`]). Per
//! scheme:
//!
//! * **Newmark average acceleration** (trapezoidal rule; N. M. Newmark, "A method of
//!   computation for structural dynamics", J. Eng. Mech. Div. ASCE 85 (EM3), 1959):
//!   `beta = 1/4, gamma = 1/2, am = af = 0`. `|L| = 1` for every `W`: zero amplitude
//!   decay. The numerical frequency obeys `tan(W_num/2) = W/2`, so
//!   `T_num/T - 1 = W / (2 atan(W/2)) - 1 = W^2/12 + O(W^4)`. Stiff modes
//!   (`W >> 1`) are neither damped nor resolved (`L -> -1`): a jump excitation leaves
//!   a ripple alternating every step. The default.
//! * **HHT-alpha** (H. M. Hilber, T. J. R. Hughes, R. L. Taylor, "Improved numerical
//!   dissipation for time integration algorithms in structural dynamics", Earthquake
//!   Eng. Struct. Dyn. 5, 283-292, 1977): `alpha` in `[-1/3, 0]`, `am = 0`,
//!   `af = -alpha`, `gamma = (1 - 2 alpha)/2`, `beta = (1 - alpha)^2/4`.
//!   `xi_num = -alpha (1 + alpha)^2 W^3 / 8`,
//!   `T_num/T - 1 = (1/12 - alpha/4 - 3 alpha^2/8) W^2`, spectral radius at
//!   `W -> inf` `(1 + alpha)/(1 - alpha)`. At `alpha = -0.05`:
//!   `xi_num = 5.64e-3 W^3`, `rho_inf = 0.905`.
//! * **Generalised-alpha** (J. Chung, G. M. Hulbert, "A time integration algorithm for
//!   structural dynamics with improved numerical dissipation: the generalized-alpha
//!   method", J. Appl. Mech. 60, 371-375, 1993): from the spectral radius at infinity
//!   `rho_inf` in `[0, 1]`: `am = (2 rho_inf - 1)/(rho_inf + 1)`,
//!   `af = rho_inf/(rho_inf + 1)`, `gamma = 1/2 - am + af`,
//!   `beta = (1 - am + af)^2 / 4`. `xi_num = ((1 - rho_inf)/(1 + rho_inf))^3 W^3 / 2`,
//!   `T_num/T - 1 = ((1 - rho_inf + rho_inf^2) / (2 (1 + rho_inf)^2) - 1/24) W^2`.
//!   `rho_inf = 1` is average acceleration (balance at mid-step, same solution).
//!
//! # Nonlinear point laws
//! [`Stepper::set_point_laws`] adds restoring forces `f_i = law_i(u_i, v_i)`
//! ([`PointLaw`]: cubic spring, velocity-squared dashpot, Coulomb friction) at a few
//! DOFs `i`, so that the balance reads `M a + C v + K u + sum_i e_i f_i = f(t)`. They
//! are enforced at the end of the step, which only average acceleration does
//! (`am = af = 0`; other schemes are refused with
//! [`IntegrateError::PointLawScheme`]). The step is split exactly:
//! 1. the linear step above with the laws' end-of-step forces set to zero gives the
//!    predictor `u*, v*, a*` (their start-of-step forces are in the balance at `t_n`,
//!    through `a_n`);
//! 2. an end-of-step force vector `f` changes `a` by `-S^{-1} E f`, so with the
//!    columns `w_i = S^{-1} e_i` (computed once per `(scheme, dt)`, `S` being factored
//!    already) and `H_ij = e_i^T S^{-1} e_j`:
//!    `u_i = u*_i - beta dt^2 (H f)_i`, `v_i = v*_i - gamma dt (H f)_i`;
//! 3. each law's force solves its scalar inclusion ([`PointLaw::solve`] with
//!    `h = beta dt^2 H_ii`, `g = gamma dt H_ii` and the other laws' forces held): one
//!    solve for one law, a nonlinear Gauss-Seidel sweep over the laws repeated until no
//!    force changes by more than [`point::SWEEP_TOLERANCE`] of the largest force (at
//!    most [`point::MAX_SWEEPS`] sweeps, else [`IntegrateError::PointLawsNotConverged`];
//!    a law with no stable root is [`IntegrateError::PointLawUnsolvable`]). This is
//!    [`point::solve_step`], the one solve the dense stepper uses too. `H`
//!    is symmetric positive definite and each scalar law monotone, so the sweeps
//!    contract when the laws' DOFs are weakly coupled (`|H_ij| << H_ii`, the usual
//!    case: one law, or laws far apart);
//! 4. `u -= beta dt^2 sum_j f_j w_j`, `v -= gamma dt sum_j f_j w_j`, `a -= sum_j f_j w_j`.
//!
//! Without laws the step is untouched (one branch per step). With `L` laws a step
//! costs `L` more vector updates, and each new `(scheme, dt)` `L` more solves.
//!
//! The initial acceleration includes the laws' forces at `(u0, v0)`. A friction law
//! whose DOF starts at rest takes the force the balance needs to keep it at rest
//! (`a_0 = 0` there), clamped to `[-F, F]` (several such laws: projected Gauss-Seidel
//! on `M^{-1}` restricted to their DOFs); on a massless DOF it takes zero.
//!
//! # Conventions
//! Units are whatever the operators use, consistently (coil: mm, N, t, s). DOFs are
//! the operators' rows, 0-based. Time starts at `State::t`.

use super::banded::BandedEngine;
use super::operator::{MergedOperators, Operators};
use super::point::{self, PointLaw};
use super::scheme::{check_dt, Coefficients, Scheme};
use super::sparse::SparseEngine;
use super::state::State;
use crate::error::integrate::IntegrateError;
use crate::linalg::sparse_spd::SpdFactor;

/// Most Gauss-Seidel sweeps over several point laws in one step.
pub const MAX_LAW_SWEEPS: usize = point::MAX_SWEEPS;

/// Name of the effective matrix in error messages.
const EFFECTIVE: &str = "effective matrix S = (1-am) M + (1-af) gamma dt C + (1-af) beta dt^2 K";

/// A generalised-alpha integrator bound to one set of operators, holding the factored
/// effective matrix for the current `(scheme, dt)` and all step buffers.
#[derive(Debug)]
pub struct Stepper {
    ops: MergedOperators,
    scheme: Scheme,
    coefficients: Coefficients,
    dt: f64,
    engine: Engine,
    /// Set when the last refactorisation failed; steps are refused until a
    /// successful [`Stepper::set_step`].
    factor_error: Option<IntegrateError>,
    /// Nonlinear point laws; `None` keeps the linear step untouched.
    laws: Option<Box<LawSet>>,
}

/// Nonlinear point laws bound to a stepper (module docs, "Nonlinear point laws").
#[derive(Debug)]
struct LawSet {
    /// Operator rows of the laws, ascending and unique.
    dofs: Vec<usize>,
    laws: Vec<PointLaw>,
    /// `w_j = S^{-1} e_{dofs[j]}` stored at `j n .. (j + 1) n`.
    columns: Vec<f64>,
    /// `H_ij = w_j[dofs[i]]`, row-major `L x L`.
    schur: Vec<f64>,
    /// The `(coefficients, dt)` the columns were computed for.
    valid_for: Option<(Coefficients, f64)>,
    /// End-of-step forces of the last step (the next step's starting guess).
    forces: Vec<f64>,
    /// Whether each friction law held its DOF at rest in the last step.
    stuck: Vec<bool>,
    /// The same for the step before it.
    was_stuck: Vec<bool>,
}

impl Engine {
    fn solve_in_place(&mut self, b: &mut [f64]) {
        match self {
            Engine::Banded(e) => e.solve_in_place(b),
            Engine::Sparse(e) => e.solve_in_place(b),
        }
    }
}

/// The scheme's name when it does not balance at the end of the step.
fn shifted_balance(scheme: Scheme, c: &Coefficients) -> Option<&'static str> {
    if c.alpha_m == 0.0 && c.alpha_f == 0.0 {
        return None;
    }
    Some(match scheme {
        Scheme::AverageAcceleration => "average acceleration",
        Scheme::Hht { .. } => "HHT-alpha",
        Scheme::GeneralizedAlpha { .. } => "generalised-alpha",
    })
}

/// How the step is computed: banded panels when the operators' envelope is narrow
/// (beam models), faer's general sparse factor otherwise.
#[derive(Debug)]
enum Engine {
    Banded(Box<BandedEngine>),
    Sparse(Box<SparseEngine>),
}

/// The mass matrix on its massive DOFs, factored for the initial acceleration.
#[derive(Debug)]
struct MassFactor {
    massive: Vec<usize>,
    factor: SpdFactor,
}

impl Stepper {
    /// Merges the operators, checks them (square, same size, finite, symmetric),
    /// analyses the effective matrix's pattern and factors it for `scheme` and `dt`.
    pub fn new(ops: Operators<'_>, scheme: Scheme, dt: f64) -> Result<Self, IntegrateError> {
        Self::with_engine(ops, scheme, dt, true, false)
    }

    /// As [`Stepper::new`], with `M`, `C`, `K` given as their upper triangles, the
    /// crate's convention for symmetric matrices (`crate::linalg`, "Triangle
    /// convention"): the finite-element system hands its matrices over without
    /// expanding them. The step is the one [`Stepper::new`] builds from both triangles,
    /// to the last bit.
    pub fn new_upper(ops: Operators<'_>, scheme: Scheme, dt: f64) -> Result<Self, IntegrateError> {
        Self::with_engine(ops, scheme, dt, true, true)
    }

    /// As [`Stepper::new`], on the general sparse path only (tests).
    #[cfg(test)]
    pub(crate) fn new_sparse(
        ops: Operators<'_>,
        scheme: Scheme,
        dt: f64,
    ) -> Result<Self, IntegrateError> {
        Self::with_engine(ops, scheme, dt, false, false)
    }

    fn with_engine(
        ops: Operators<'_>,
        scheme: Scheme,
        dt: f64,
        allow_banded: bool,
        upper: bool,
    ) -> Result<Self, IntegrateError> {
        let coefficients = scheme.coefficients()?;
        check_dt(dt)?;
        let ops = if upper {
            MergedOperators::new_upper(&ops)?
        } else {
            MergedOperators::new(&ops)?
        };
        let banded = allow_banded.then(|| BandedEngine::new(&ops)).flatten();
        let engine = match banded {
            Some(banded) => Engine::Banded(Box::new(banded)),
            None => Engine::Sparse(Box::new(SparseEngine::new(&ops, EFFECTIVE)?)),
        };
        let mut stepper = Self {
            ops,
            scheme,
            coefficients,
            dt,
            engine,
            factor_error: None,
            laws: None,
        };
        stepper.refactor()?;
        Ok(stepper)
    }

    /// Number of DOFs.
    pub fn n_dofs(&self) -> usize {
        self.ops.dim()
    }

    /// Whether the step runs on banded panels (else on faer's general sparse factor).
    #[cfg(test)]
    pub(crate) fn is_banded(&self) -> bool {
        matches!(self.engine, Engine::Banded(_))
    }

    /// The banded path's products per step, ordering runs and panel overhead (tests).
    #[cfg(test)]
    pub(crate) fn banded_shape(&self) -> Option<(usize, Option<usize>, f64)> {
        match &self.engine {
            Engine::Banded(e) => Some(e.shape()),
            Engine::Sparse(_) => None,
        }
    }

    /// Whether the banded path gathers vectors through its permutation (tests).
    #[cfg(test)]
    pub(crate) fn gathers(&self) -> bool {
        matches!(&self.engine, Engine::Banded(e) if e.gathers())
    }

    /// Whether the banded path uses the damping as `alpha M + beta K + D` (tests).
    #[cfg(test)]
    pub(crate) fn uses_rayleigh_split(&self) -> bool {
        matches!(&self.engine, Engine::Banded(e) if e.rayleigh())
    }

    /// The current time step.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The current scheme.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// The current scheme's parameters.
    pub fn coefficients(&self) -> Coefficients {
        self.coefficients
    }

    /// Switches to another scheme or time step. Refactors numerically (the symbolic
    /// analysis is reused) only when the effective matrix changes.
    /// With point laws, only average acceleration is accepted.
    pub fn set_step(&mut self, scheme: Scheme, dt: f64) -> Result<(), IntegrateError> {
        let coefficients = scheme.coefficients()?;
        check_dt(dt)?;
        if self.laws.is_some() {
            if let Some(scheme) = shifted_balance(scheme, &coefficients) {
                return Err(IntegrateError::PointLawScheme { scheme });
            }
        }
        let unchanged = coefficients == self.coefficients && dt == self.dt;
        self.scheme = scheme;
        self.coefficients = coefficients;
        self.dt = dt;
        if unchanged && self.factor_error.is_none() {
            return Ok(());
        }
        self.refactor()
    }

    /// Binds nonlinear point laws `(operator row, law)` to the stepper (module docs,
    /// "Nonlinear point laws"), replacing any set before. Laws on the same row add up;
    /// laws that do nothing are dropped, and an empty set restores the linear step.
    /// Refused unless the scheme is average acceleration. Takes effect from the next
    /// [`Stepper::initial_state`] or [`Stepper::step`].
    pub fn set_point_laws(&mut self, laws: &[(usize, PointLaw)]) -> Result<(), IntegrateError> {
        let n = self.n_dofs();
        let mut merged: Vec<(usize, PointLaw)> = Vec::with_capacity(laws.len());
        for (index, &(dof, law)) in laws.iter().enumerate() {
            let reason = if dof >= n {
                Some("the DOF is out of range")
            } else if !law.is_valid() {
                Some("a coefficient is not finite, or the dashpot or the friction is negative")
            } else {
                None
            };
            if let Some(reason) = reason {
                return Err(IntegrateError::InvalidPointLaw {
                    index,
                    dof,
                    n_dofs: n,
                    reason,
                });
            }
            match merged.iter_mut().find(|(d, _)| *d == dof) {
                Some((_, sum)) => {
                    sum.cubic += law.cubic;
                    sum.quadratic += law.quadratic;
                    sum.friction += law.friction;
                }
                None => merged.push((dof, law)),
            }
        }
        merged.retain(|(_, law)| !law.is_zero());
        merged.sort_by_key(|&(d, _)| d);
        if merged.is_empty() {
            self.laws = None;
            return Ok(());
        }
        if let Some(scheme) = shifted_balance(self.scheme, &self.coefficients) {
            return Err(IntegrateError::PointLawScheme { scheme });
        }
        let l = merged.len();
        self.laws = Some(Box::new(LawSet {
            dofs: merged.iter().map(|&(d, _)| d).collect(),
            laws: merged.iter().map(|&(_, law)| law).collect(),
            columns: vec![0.0; l * n],
            schur: vec![0.0; l * l],
            valid_for: None,
            forces: vec![0.0; l],
            stuck: vec![false; l],
            was_stuck: vec![false; l],
        }));
        Ok(())
    }

    /// The bound point laws' rows, their forces at the end of the last step (or at
    /// the initial state) and whether friction held each at rest, ascending by row.
    pub fn point_law_forces(&self) -> Vec<(usize, f64, bool)> {
        match &self.laws {
            Some(l) => l
                .dofs
                .iter()
                .zip(&l.forces)
                .zip(&l.stuck)
                .map(|((&d, &f), &s)| (d, f, s))
                .collect(),
            None => Vec::new(),
        }
    }

    fn refactor(&mut self) -> Result<(), IntegrateError> {
        let result = match &mut self.engine {
            Engine::Banded(engine) => engine.refactor(&self.coefficients, self.dt, EFFECTIVE),
            Engine::Sparse(engine) => {
                engine.refactor(&self.ops, self.coefficients.effective(self.dt))
            }
        };
        self.factor_error = result.clone().err();
        result
    }

    /// The state at `t0` from `u0`, `v0` and the load `f0 = f(t0)`, with `a0` solving
    /// `M a0 = f0 - C v0 - K u0` (zero on massless DOFs, see the module docs).
    pub fn initial_state(
        &mut self,
        t0: f64,
        u0: &[f64],
        v0: &[f64],
        f0: &[f64],
    ) -> Result<State, IntegrateError> {
        let n = self.n_dofs();
        check_vector("initial displacement u0", u0, n)?;
        check_vector("initial velocity v0", v0, n)?;
        check_vector("load f(t0)", f0, n)?;
        if !t0.is_finite() {
            return Err(IntegrateError::NonFiniteInput {
                what: "start time t0",
                index: 0,
            });
        }
        // Factored for this call only: the factor is as large as the step's own and
        // only the initial acceleration needs it.
        let mut mass = self.factor_mass()?;
        let xyz: Vec<[f64; 3]> = v0.iter().zip(u0).map(|(&v, &u)| [0.0, v, u]).collect();
        let mut rhs = vec![0.0; n];
        self.ops.residual_into(f0, &xyz, false, &mut rhs);
        let mut a = vec![0.0; n];
        mass.solve_into(&rhs, &mut a);
        if let Some(laws) = &mut self.laws {
            initial_law_forces(laws, &mut mass, u0, v0, &mut a);
        }
        drop(mass);
        if let Some(dof) = a.iter().position(|x| !x.is_finite()) {
            return Err(IntegrateError::NonFiniteState {
                step: 0,
                time: t0,
                dof,
            });
        }
        Ok(State {
            t: t0,
            u: u0.to_vec(),
            v: v0.to_vec(),
            a,
        })
    }

    fn factor_mass(&self) -> Result<MassFactor, IntegrateError> {
        let massless = self.ops.massless_dofs();
        let massive: Vec<usize> = (0..self.n_dofs()).filter(|&i| !massless[i]).collect();
        let m = self.ops.mass_submatrix(&massive);
        let mut factor = SpdFactor::analyse("mass matrix M (on DOFs with mass)", m.symbolic())?;
        if !massive.is_empty() {
            factor.factor(m.as_ref()).map_err(|e| match e {
                IntegrateError::NotPositiveDefinite { matrix, dof } => {
                    IntegrateError::NotPositiveDefinite {
                        matrix,
                        dof: massive[dof],
                    }
                }
                other => other,
            })?;
        }
        Ok(MassFactor { massive, factor })
    }

    /// Advances `state` by one step `dt`, given the loads `f_n = f(t)` and
    /// `f_next = f(t + dt)`. `step` only labels a non-finite-state error; after that
    /// error `state` holds the non-finite step for inspection. No allocation.
    pub fn step(
        &mut self,
        state: &mut State,
        f_n: &[f64],
        f_next: &[f64],
        step: usize,
    ) -> Result<(), IntegrateError> {
        if let Some(e) = &self.factor_error {
            return Err(e.clone());
        }
        let n = self.n_dofs();
        for (what, len) in [
            ("state.u", state.u.len()),
            ("state.v", state.v.len()),
            ("state.a", state.a.len()),
            ("load f_n", f_n.len()),
            ("load f_next", f_next.len()),
        ] {
            if len != n {
                return Err(IntegrateError::DimensionMismatch {
                    what,
                    expected: n,
                    found: len,
                });
            }
        }
        let mut finite = match &mut self.engine {
            Engine::Banded(engine) => engine.step(state, f_n, f_next),
            Engine::Sparse(engine) => {
                engine.step(&self.ops, &self.coefficients, self.dt, state, f_n, f_next)
            }
        };
        let time = state.t + self.dt;
        if finite {
            if let Some(laws) = &mut self.laws {
                if let Some(scheme) = shifted_balance(self.scheme, &self.coefficients) {
                    return Err(IntegrateError::PointLawScheme { scheme });
                }
                finite = correct_for_laws(
                    laws,
                    &mut self.engine,
                    &self.coefficients,
                    self.dt,
                    state,
                    step,
                    time,
                )?;
            }
        }
        state.t = time;
        if finite {
            return Ok(());
        }
        let dof = (0..n)
            .find(|&i| {
                !(state.u[i].is_finite() && state.v[i].is_finite() && state.a[i].is_finite())
            })
            .unwrap_or(0);
        Err(IntegrateError::NonFiniteState { step, time, dof })
    }

    /// Runs `n_steps` steps from `state`. `force(t, f)` writes the load at `t` into
    /// `f` (zeroed before each call). `observer(k, &state)` sees the state before the
    /// first step (`k = 0`) and after each step `k = 1..=n_steps`. Times are
    /// `t_k = t_0 + k dt`, computed by multiplication, not accumulation.
    pub fn run(
        &mut self,
        state: &mut State,
        n_steps: usize,
        force: &mut dyn FnMut(f64, &mut [f64]),
        observer: &mut dyn FnMut(usize, &State),
    ) -> Result<(), IntegrateError> {
        let n = self.n_dofs();
        let t0 = state.t;
        let mut f_n = vec![0.0; n];
        let mut f_next = vec![0.0; n];
        force(t0, &mut f_n);
        observer(0, state);
        for k in 1..=n_steps {
            if k % 64 == 0 && coil_io::cancel::requested() {
                return Err(IntegrateError::Interrupted { step: k });
            }
            let t = t0 + k as f64 * self.dt;
            f_next.fill(0.0);
            force(t, &mut f_next);
            self.step(state, &f_n, &f_next, k)?;
            state.t = t;
            observer(k, state);
            std::mem::swap(&mut f_n, &mut f_next);
        }
        Ok(())
    }
}

impl MassFactor {
    /// `a = M^{-1} r` on the massive DOFs, `a` untouched elsewhere.
    fn solve_into(&mut self, r: &[f64], a: &mut [f64]) {
        let mut x: Vec<f64> = self.massive.iter().map(|&i| r[i]).collect();
        if !x.is_empty() {
            self.factor.solve_in_place(&mut x);
        }
        for (&i, &xi) in self.massive.iter().zip(&x) {
            a[i] = xi;
        }
    }
}

/// Adds the point laws' forces at `(u0, v0)` to the initial acceleration `a`
/// (`M^{-1}` of the linear balance on entry): module docs, "Nonlinear point laws".
fn initial_law_forces(
    laws: &mut LawSet,
    mass: &mut MassFactor,
    u0: &[f64],
    v0: &[f64],
    a: &mut [f64],
) {
    let n = a.len();
    let l = laws.dofs.len();
    // z_j = M^{-1} e_j (zero on a massless DOF).
    let mut z = vec![0.0; l * n];
    let mut unit = vec![0.0; n];
    for (j, &d) in laws.dofs.iter().enumerate() {
        unit[d] = 1.0;
        mass.solve_into(&unit, &mut z[j * n..(j + 1) * n]);
        unit[d] = 0.0;
    }
    for (j, (&d, law)) in laws.dofs.iter().zip(&laws.laws).enumerate() {
        let f = law.force(u0[d], v0[d]);
        laws.forces[j] = f;
        laws.stuck[j] = false;
        for (ai, zi) in a.iter_mut().zip(&z[j * n..(j + 1) * n]) {
            *ai -= f * zi;
        }
    }
    // Friction at rest: the force that keeps a_0 = 0 at its DOF, within [-F, F].
    let resting: Vec<usize> = (0..l)
        .filter(|&j| {
            let d = laws.dofs[j];
            v0[d] == 0.0 && laws.laws[j].friction > 0.0 && z[j * n + d] > 0.0
        })
        .collect();
    // Not converging within the sweeps leaves the last sweep's forces (the laws are
    // then strongly coupled through M; the first step's solve takes over from there).
    let mut held_at_rest = vec![0.0; resting.len()];
    point::hold_at_rest(
        resting.len(),
        |p, q| z[resting[q] * n + laws.dofs[resting[p]]],
        |p| a[laws.dofs[resting[p]]],
        |p| laws.laws[resting[p]].friction,
        1e-12,
        false,
        &mut held_at_rest,
    );
    let mut held = vec![0.0; l];
    for (&j, &f) in resting.iter().zip(&held_at_rest) {
        held[j] = f;
    }
    for &j in &resting {
        for (ai, zi) in a.iter_mut().zip(&z[j * n..(j + 1) * n]) {
            *ai -= held[j] * zi;
        }
        laws.forces[j] += held[j];
        laws.stuck[j] = held[j].abs() < laws.laws[j].friction;
    }
}

/// The point laws' correction of a predicted step (module docs, steps 2-4); returns
/// whether the corrected state is finite.
fn correct_for_laws(
    laws: &mut LawSet,
    engine: &mut Engine,
    coefficients: &Coefficients,
    dt: f64,
    state: &mut State,
    step: usize,
    time: f64,
) -> Result<bool, IntegrateError> {
    let n = state.u.len();
    let l = laws.dofs.len();
    if laws.valid_for != Some((*coefficients, dt)) {
        for (j, &d) in laws.dofs.iter().enumerate() {
            let column = &mut laws.columns[j * n..(j + 1) * n];
            column.fill(0.0);
            column[d] = 1.0;
            engine.solve_in_place(column);
            for (i, &di) in laws.dofs.iter().enumerate() {
                laws.schur[i * l + j] = column[di];
            }
        }
        laws.valid_for = Some((*coefficients, dt));
    }
    let (hs, gs) = (coefficients.beta * dt * dt, coefficients.gamma * dt);
    laws.was_stuck.copy_from_slice(&laws.stuck);
    let (u, v, dofs) = (&state.u, &state.v, &laws.dofs);
    point::solve_step(
        &laws.laws,
        |j| (u[dofs[j]], v[dofs[j]]),
        &laws.schur,
        hs,
        gs,
        &mut laws.forces,
        &mut laws.stuck,
    )
    .map_err(|e| match e {
        point::StepLawError::Unsolvable { law } => IntegrateError::PointLawUnsolvable {
            step,
            time,
            dof: laws.dofs[law],
        },
        point::StepLawError::NotConverged { sweeps, change } => {
            IntegrateError::PointLawsNotConverged {
                step,
                time,
                sweeps,
                change,
            }
        }
    })?;
    for (j, &f) in laws.forces.iter().enumerate() {
        if f == 0.0 {
            continue;
        }
        let column = &laws.columns[j * n..(j + 1) * n];
        let (fu, fv) = (hs * f, gs * f);
        for (((u, v), a), &w) in state
            .u
            .iter_mut()
            .zip(state.v.iter_mut())
            .zip(state.a.iter_mut())
            .zip(column)
        {
            *u -= fu * w;
            *v -= fv * w;
            *a -= f * w;
        }
    }
    // A DOF that friction holds is at rest: v = 0 (the solve leaves it to rounding).
    // Held for a second step in a row, it is also without acceleration: the step that
    // stopped it left the stopping acceleration in `a`, and the trapezoidal rule with v
    // pinned at 0 would flip its sign at every later step (a_{n+1} = -a_n), feeding an
    // alternating inertia force to the DOFs coupled to it by the mass matrix. From
    // a = 0 every later held step gives a = 0 exactly. (A single held step is a turning
    // point that friction catches for one step; its acceleration is real.)
    for ((&d, &stuck), &was) in laws.dofs.iter().zip(&laws.stuck).zip(&laws.was_stuck) {
        if stuck {
            state.v[d] = 0.0;
            if was {
                state.a[d] = 0.0;
            }
        }
    }
    Ok(state
        .u
        .iter()
        .chain(&state.v)
        .chain(&state.a)
        .all(|x| x.is_finite()))
}

/// Integrates `M a + C v + K u = f(t)` from `u0`, `v0` at `t = 0`: builds a
/// [`Stepper`], computes `a_0` from `u0`, `v0` and `f(0)`, and runs `n_steps` steps of
/// `dt`. `force(t, f)` writes the load at `t` into the zeroed `f`; `observer(k, t,
/// state)` sees step `k = 0..=n_steps`. Returns the final state.
#[allow(clippy::too_many_arguments)]
pub fn integrate(
    ops: Operators<'_>,
    scheme: Scheme,
    dt: f64,
    n_steps: usize,
    u0: &[f64],
    v0: &[f64],
    force: &mut dyn FnMut(f64, &mut [f64]),
    observer: &mut dyn FnMut(usize, f64, &State),
) -> Result<State, IntegrateError> {
    let mut stepper = Stepper::new(ops, scheme, dt)?;
    let n = stepper.n_dofs();
    let mut f0 = vec![0.0; n];
    force(0.0, &mut f0);
    let mut state = stepper.initial_state(0.0, u0, v0, &f0)?;
    stepper.run(&mut state, n_steps, force, &mut |k, s| observer(k, s.t, s))?;
    Ok(state)
}

fn check_vector(what: &'static str, x: &[f64], n: usize) -> Result<(), IntegrateError> {
    if x.len() != n {
        return Err(IntegrateError::DimensionMismatch {
            what,
            expected: n,
            found: x.len(),
        });
    }
    match x.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(IntegrateError::NonFiniteInput { what, index }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests;
