//! The direct path of a transient case: the system's matrices handed to the stepper as
//! their upper triangles, the stepper kept between cases (refactored only when the scheme or `dt` changes), the
//! point laws bound to it, and the run loop (the "Direct integration" section of
//! [`super`]); tension links and moving contacts run in [`super::contact`].

use super::error::integrate_error;
use super::loads::LoadPatterns;
use super::modal_damping::ModalDampingTerm;
use super::recording::Recorder;
use crate::analysis::system::System;
use crate::error::solve::SolveError;
use crate::integrate::{Operators, Scheme, State, Stepper};
use crate::linalg::Cholesky;
use crate::model::Integrator;

/// The deck's integrator as the operator-level scheme (the integrators do not see
/// the model).
impl From<Integrator> for Scheme {
    fn from(integrator: Integrator) -> Self {
        match integrator {
            Integrator::AverageAcceleration => Scheme::AverageAcceleration,
            Integrator::Hht { alpha } => Scheme::Hht { alpha },
            Integrator::GeneralizedAlpha { rho_inf } => Scheme::GeneralizedAlpha { rho_inf },
        }
    }
}

/// What the direct path keeps between the transient cases of one run: the stepper with
/// its merged operators and its factored effective matrix.
#[derive(Debug, Default)]
pub(super) struct DirectCache {
    stepper: Option<Stepper>,
}

/// The system's `M`, `C` (`None` when the model has no damping), `K` as the stepper's
/// operators, upper triangles as stored (`crate::linalg`, "Triangle convention").
fn system_operators<'s>(system: &'s System) -> Operators<'s> {
    let damped = system.damping.val().iter().any(|&v| v != 0.0);
    Operators {
        m: system.mass.as_ref(),
        c: damped.then(|| system.damping.as_ref()),
        k: system.stiffness.as_ref(),
    }
}

#[allow(clippy::too_many_arguments)]
pub(super) fn run_direct(
    system: &System,
    cache: &mut DirectCache,
    factor: Option<&Cholesky>,
    title: &str,
    integrator: Integrator,
    dt: f64,
    steps: usize,
    u0: &[f64],
    v0: &[f64],
    loads: &LoadPatterns,
    recorder: &mut Recorder,
    progress: &coil_io::Progress,
) -> Result<(), SolveError> {
    let scheme = Scheme::from(integrator);
    let fail = |e| integrate_error(system, title, false, e);
    let stepper = match cache.stepper.take() {
        Some(mut stepper) => {
            stepper.set_step(scheme, dt).map_err(fail)?;
            stepper
        }
        None => Stepper::new_upper(system_operators(system), scheme, dt).map_err(fail)?,
    };
    let stepper = cache.stepper.insert(stepper);
    stepper
        .set_point_laws(&system.point_laws()?)
        .map_err(fail)?;
    let n = system.dim();
    let mut factors = vec![0.0; loads.count()];
    let mut force = |t: f64, f: &mut [f64]| {
        loads.factors(t, &mut factors);
        for (s, pattern) in factors.iter().zip(loads.patterns()) {
            if *s != 0.0 {
                for (fi, pi) in f.iter_mut().zip(pattern) {
                    *fi += s * pi;
                }
            }
        }
    };
    let model = system.model;
    if !(model.tension_links().is_empty() && model.moving_contacts().is_empty()) {
        if model.modal_damping.is_active() {
            return Err(SolveError::BadInput {
                what: format!(
                    "load case '{title}': LOSS FACTOR and MODAL DAMPING do not run with \
                     TENSION LINK or MOVING CONTACT; use Rayleigh DAMPING"
                ),
            });
        }
        return super::contact::run_unilateral(
            system, stepper, title, steps, u0, v0, &mut force, recorder, progress,
        );
    }
    let mut f0 = vec![0.0; n];
    force(0.0, &mut f0);
    if system.model.modal_damping.is_active() {
        if system.point_laws()?.iter().any(|(_, law)| !law.is_zero()) {
            return Err(SolveError::BadInput {
                what: format!(
                    "load case '{title}': LOSS FACTOR and MODAL DAMPING run by direct \
                     integration without nonlinear point elements only (the point laws' \
                     end-of-step correction is not linear); use MODAL or drop one of them"
                ),
            });
        }
        let factor = factor.ok_or_else(|| SolveError::BadInput {
            what: format!("load case '{title}': modal damping needs the stiffness factor"),
        })?;
        let mut term = ModalDampingTerm::new(system, factor, title, stepper)?;
        term.add_force(v0, &mut f0);
        let mut state: State = stepper.initial_state(0.0, u0, v0, &f0).map_err(fail)?;
        // f_n carries the modal force of the step's start, f_next the load alone: the
        // term's own end-of-step force is added by `correct` through the stepper's
        // response to it.
        let mut f_n = f0;
        let mut f_next = vec![0.0; n];
        if recorder.wants(0) {
            recorder.record_free(state.t, &state.u, &state.v, &state.a);
        }
        for k in 1..=steps {
            if k % 64 == 0 && coil_io::cancel::requested() {
                return Err(fail(crate::error::IntegrateError::Interrupted { step: k }));
            }
            let t = k as f64 * dt;
            f_next.fill(0.0);
            force(t, &mut f_next);
            stepper.step(&mut state, &f_n, &f_next, k).map_err(fail)?;
            term.correct(&mut state);
            state.t = t;
            std::mem::swap(&mut f_n, &mut f_next);
            term.add_force(&state.v, &mut f_n);
            if recorder.wants(k) {
                recorder.record_free(state.t, &state.u, &state.v, &state.a);
            }
        }
        return Ok(());
    }
    let mut state: State = stepper.initial_state(0.0, u0, v0, &f0).map_err(fail)?;
    stepper
        .run(&mut state, steps, &mut force, &mut |k, s| {
            if k % 64 == 0 {
                progress.set(k as u64);
            }
            if recorder.wants(k) {
                recorder.record_free(s.t, &s.u, &s.v, &s.a);
            }
        })
        .map_err(fail)
}
