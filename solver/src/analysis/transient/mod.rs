//! Transient load cases (`DYNAMIC CHANGE`): `M a + C v + K u = f(t)` on the free DOFs,
//! from an initial state, at a fixed step `dt` up to the total time, by direct
//! integration or by modal superposition. The derivations and the measured numbers are
//! in `docs/transient.md`.
//!
//! # Operators
//! `K`, `M` and the Rayleigh `C` of the shared [`System`] (one pattern; `C = sum of
//! alpha M_e + beta K_e` over each `DAMPING` entry's elements, plus `alpha M_p` on the
//! point masses of the nodes it names, none otherwise). Rows are the free DOFs after
//! constraint elimination, numbered as in [`crate::dof::DofMap`]; units mm, N, t, s, so
//! `u` in mm (rad), `v` in mm/s, `a` in mm/s^2, `f` in N (N mm).
//!
//! # Loads
//! The load of a transient case is the model-definition `POINT LOAD`s plus the case's own;
//! a load with a `TABLE` is scaled by the table at the current time (piecewise linear,
//! holding its end values outside its range). Time starts at 0 in every transient case.
//! The prescribed displacements of `FIXED DISP` are constant, so they load the free DOFs
//! with the constant `-T^T K g`. Both methods take the load as linear between steps, so
//! a table whose breakpoints do not fall on multiples of `dt` (a pulse shorter than a
//! step, for instance) is misrepresented; such breakpoints are reported as warnings.
//!
//! # Initial state
//! - Displacement: when the load case immediately before is a static one, its
//!   displacement (free DOFs) is the initial displacement; otherwise the free DOFs start
//!   at zero. The static case's own history loads are not part of the transient: a
//!   load meant to act in both (the weight's own weight under gravity, say) belongs to
//!   the model definition; then the transient starts in equilibrium under it and
//!   oscillates about the loaded position. A history load of the static case alone is
//!   released at `t = 0` (a pluck test).
//! - Velocity (`INITIAL VEL`, model definition, the same for every transient case): each
//!   listed DOF must be free (a prescribed DOF may only be given 0; a tied DOF is given at
//!   its reference node). Plain groups set their DOFs and leave every other DOF at rest: a
//!   velocity jump. `QUASI STATIC` groups give the field `v = K^-1 E c`, `E` the unit
//!   vectors of their listed DOFs and `c` solving `(E^T K^-1 E) c = v_listed`, so the
//!   listed DOFs get exactly their values and the rest follows as in the static response
//!   to forces there (on a spring with a weight: the velocity profile the weight's motion
//!   induces along the wire). The plain groups are applied after the quasi-static field.
//! - Acceleration: `M a0 = f(0) - C v0 - K u0` (direct), the modal equations (modal).
//!
//! Prescribed displacements without a static case first start the free DOFs at zero,
//! out of equilibrium under `-T^T K g`: a sudden load that reaches every mode, so direct
//! integration converges at first order only (measured in the tests); a static case first
//! restores second order.
//!
//! # Direct integration
//! [`crate::integrate::Stepper`] (average acceleration, HHT-alpha or generalised-alpha)
//! on `M`, `C`, `K` as their upper triangles ([`crate::integrate::Stepper::new_upper`]);
//! the effective matrix is factored once per
//! `(scheme, dt)` and the stepper is kept in [`Context`] for the next transient case.
//! The model's nonlinear point elements (`FRICTION`, `QUADRATIC DAMPER`, `CUBIC
//! SPRING`) are bound to the stepper as [`crate::integrate::PointLaw`]s on their free
//! DOFs ([`crate::integrate::Stepper::set_point_laws`]: an exact end-of-step correction, average
//! acceleration only; other schemes are an error, and so is modal superposition).
//!
//! # Modal superposition
//! The lowest `modes` modes from [`super::modal::solve`] on the stiffness factor the
//! static and modal cases share; mass-normalised `Phi`, `Phi^T K Phi = Omega^2`. Each mode
//! gets its exact Rayleigh modal damping `zeta_i = phi_i^T C phi_i / (2 w_i)` (the formula
//! of [`crate::integrate::modal_superposition::modal_damping_ratios`], taken here from the diagonal of
//! the modal damping matrix computed anyway for the coupling below) and is
//! integrated exactly for a load linear between steps
//! ([`crate::integrate::modal_superposition::integrate_modal`]); initial modal coordinates are
//! `Phi^T M u0` and `Phi^T M v0`; outputs are `T Phi q` at the requested DOFs. What the
//! method leaves out is measured and reported in [`ModalSummary`]:
//! - the off-diagonal modal damping `Phi^T C Phi` (Rayleigh per element set is not
//!   classical damping): the largest normalised coupling `|c_ij| / sqrt(c_ii c_jj)`, and
//!   the damping ratios of the retained modes with the full modal damping matrix, from
//!   the eigenvalues of `[[0, Omega], [-Omega, -Phi^T C Phi]]`, against the diagonal ones;
//! - the modes beyond the basis: the fractions of the initial strain energy, of the
//!   initial kinetic energy and of the static compliance of the loads that the retained
//!   modes carry.
//!
//! # Output
//! A [`History`]: `time_s` and one column per requested node, DOF and quantity, named
//! `node{ID}_{ux|uy|uz|rx|ry|rz}_{disp_m|vel_m_s|accel_m_s2}` (rotations `_disp_rad`,
//! `_vel_rad_s`, `_accel_rad_s2`), in SI units, in the order of the `HISTORY OUTPUT`
//! groups, then nodes, then DOFs, then quantities (a column asked twice appears once).
//! One history has one time axis: it is sampled every `g`-th step, `g` the greatest
//! common divisor of the groups' `every`, which holds every sample each group asked for.
//!
//! # Modules
//! This root drives one case ([`solve`]: step count and limits, initial displacement,
//! dispatch) and holds the run's [`Context`]; `loads` (the load patterns and their
//! tables), `initial` (the initial velocity field), `recording` ([`History`] and its
//! columns), `direct` (the stepper path), `modal_damping` (modal damping inside the
//! direct path), `superposition` (the modal path and its [`ModalSummary`]) and `error`
//! (an integrator's error located at a node or mode). The children import one another
//! and the layers below, never this root.
//!
//! # References
//! N. M. Newmark, J. Eng. Mech. Div. ASCE 85 (1959) 67-94; H. M. Hilber, T. J. R. Hughes,
//! R. L. Taylor, Earthq. Eng. Struct. Dyn. 5 (1977) 283-292; J. Chung, G. M. Hulbert,
//! J. Appl. Mech. 60 (1993) 371-375 (the schemes, see `crate::integrate`); N. C. Nigam,
//! P. C. Jennings, Bull. Seismol. Soc. Am. 59 (1969) 909-922 (exact modal steps);
//! R. J. Guyan, AIAA J. 3 (1965) 380 (the static condensation shape behind the
//! quasi-static velocity field).

mod contact;
mod direct;
mod error;
mod initial;
mod loads;
mod modal_damping;
mod recording;
mod responses;
mod superposition;
#[cfg(test)]
mod tests;

pub use initial::VelocityField;
pub use recording::{column_name, History, HistoryColumn, MAX_HISTORY_VALUES};
pub use superposition::{ModalCapture, ModalSummary, ModalTerm};

use direct::{run_direct, DirectCache};
use initial::initial_velocity;
use loads::LoadPatterns;
use recording::Recorder;
use superposition::run_modal;

use super::static_analysis::StaticSolution;
use super::system::System;
use crate::error::solve::SolveError;
use crate::linalg::Cholesky;
use crate::model::{Analysis, Integrator, LoadCase, Model, TransientMethod};

/// Modes of a modal superposition when the command line asks for `modal` without a count
/// and the deck's method is direct.
pub const DEFAULT_MODAL_MODES: u32 = 20;

/// Most steps a transient case may take (a guard against a `dt` typo, e.g. 1e-9 s).
pub const MAX_STEPS: usize = 100_000_000;

/// Most work (steps times free DOFs) a transient case may take without the caller's
/// explicit consent ([`RunOptions::allow_large`], `coil-solve --allow-large`): 1e10 is
/// about a minute of direct Newmark on the development machine (the paper's decay,
/// 2011 DOFs x 20000 steps = 4e7, takes 0.3 s). A `dt` typo (1e-9 s for 20 s) would
/// otherwise run for hours without a word.
pub const MAX_WORK: f64 = 1e10;

/// How a run reports and what it may do.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Announce each transient's step count on stderr and show progress past a few
    /// seconds ([`coil_io::Progress`]).
    pub progress: bool,
    /// Refuse a transient above [`MAX_WORK`] unless this is set; `None` means no limit
    /// (library callers that size their own runs).
    pub allow_large: Option<bool>,
}

/// The result of a transient load case.
#[derive(Debug, Clone, PartialEq)]
pub struct TransientSolution {
    /// The method as run (after any command-line override).
    pub method: TransientMethod,
    /// The time step (s).
    pub dt_s: f64,
    /// The end time, `steps * dt` (s).
    pub total_time_s: f64,
    /// Number of time steps.
    pub steps: usize,
    /// Steps between recorded samples.
    pub output_every: usize,
    /// Title of the static load case whose displacement is the initial state.
    pub initial_displacement_from: Option<String>,
    /// How the initial velocity field was made.
    pub velocity_field: VelocityField,
    /// Present for modal superposition.
    pub modal: Option<ModalSummary>,
    /// Things the user should know (off-grid table breakpoints, a rounded end time, a
    /// missing output request).
    pub warnings: Vec<String>,
    /// The recorded signals (SI units, see [`History`]).
    pub history: History,
}

/// State kept between the transient cases of one run: the stepper with its merged
/// operators and factored effective matrix, the initial velocity.
#[derive(Debug, Default)]
pub struct Context {
    /// Reporting and limits of this run.
    pub options: RunOptions,
    direct: DirectCache,
    velocity: Option<(Vec<f64>, VelocityField)>,
}

/// A short human label: `newmark`, `hht alpha = -0.05`, `galpha rho_inf = 0.8`,
/// `modal superposition, 20 modes`.
pub fn method_label(method: &TransientMethod) -> String {
    match *method {
        TransientMethod::Direct(Integrator::AverageAcceleration) => {
            "direct, newmark average acceleration".to_string()
        }
        TransientMethod::Direct(Integrator::Hht { alpha }) => {
            format!("direct, hht alpha = {alpha}")
        }
        TransientMethod::Direct(Integrator::GeneralizedAlpha { rho_inf }) => {
            format!("direct, galpha rho_inf = {rho_inf}")
        }
        TransientMethod::Modal { modes } => format!("modal superposition, {modes} modes"),
    }
}

/// Whether a transient case of `model` with `method` needs the stiffness factor
/// (modal superposition, or a quasi-static initial velocity field).
pub fn needs_stiffness_factor(model: &Model, method: &TransientMethod) -> bool {
    matches!(method, TransientMethod::Modal { .. })
        || model.initial_velocities.iter().any(|v| v.quasi_static)
        || model.modal_damping.is_active()
}

/// How `coil-solve --method` replaces the transient method of every transient case.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MethodOverride {
    /// Direct integration: the deck's scheme if it has one, else average acceleration.
    Direct,
    /// Modal superposition with this many modes, or the deck's count, or
    /// [`DEFAULT_MODAL_MODES`].
    Modal {
        /// Number of modes to retain; `None` for the deck's count or the default.
        modes: Option<u32>,
    },
}

/// Applies a [`MethodOverride`] to every transient case of `model`.
pub fn override_method(model: &mut Model, choice: MethodOverride) {
    for case in &mut model.load_cases {
        if let Analysis::Transient { method, .. } = &mut case.analysis {
            *method = match (choice, *method) {
                (MethodOverride::Direct, TransientMethod::Direct(scheme)) => {
                    TransientMethod::Direct(scheme)
                }
                (MethodOverride::Direct, TransientMethod::Modal { .. }) => {
                    TransientMethod::Direct(Integrator::AverageAcceleration)
                }
                (MethodOverride::Modal { modes: Some(modes) }, _) => {
                    TransientMethod::Modal { modes }
                }
                (MethodOverride::Modal { modes: None }, TransientMethod::Modal { modes }) => {
                    TransientMethod::Modal { modes }
                }
                (MethodOverride::Modal { modes: None }, TransientMethod::Direct(_)) => {
                    TransientMethod::Modal {
                        modes: DEFAULT_MODAL_MODES,
                    }
                }
            };
        }
    }
}

/// The initial displacement a transient case starts from: the static load case run
/// immediately before it, with its title.
#[derive(Debug, Clone, Copy)]
pub struct StaticStart<'a> {
    /// The static load case's title.
    pub title: &'a str,
    /// Its solution, whose displacement is the initial state.
    pub solution: &'a StaticSolution,
}

/// Runs one transient load case. `factor` is the stiffness factor, needed only when
/// [`needs_stiffness_factor`] says so; `start` is the immediately preceding static case.
pub fn solve(
    system: &System,
    context: &mut Context,
    factor: Option<&Cholesky>,
    case: &LoadCase,
    start: Option<StaticStart<'_>>,
) -> Result<TransientSolution, SolveError> {
    let Analysis::Transient {
        dt,
        total_time,
        method,
    } = case.analysis
    else {
        return Err(SolveError::BadInput {
            what: format!("load case '{}' is not a transient", case.title),
        });
    };
    let title = case.title.as_str();
    let mut warnings = Vec::new();
    let steps = step_count(title, dt, total_time, &mut warnings)?;
    let work = steps as f64 * system.dim() as f64;
    if context.options.allow_large == Some(false) && work > MAX_WORK {
        return Err(SolveError::BadInput {
            what: format!(
                "load case '{title}': {steps} steps x {} DOFs = {work:.2e}, above the limit of \
                 {MAX_WORK:.0e} (about a minute; docs/files.md); check dt and the total time, or \
                 pass --allow-large to run it",
                system.dim()
            ),
        });
    }
    let progress = coil_io::Progress::new(format!("load case '{title}'"), steps as u64, "steps")
        .hidden(!context.options.progress);
    progress.announce(&format!(
        "load case '{title}': transient of {steps} steps of {dt} s, {} DOFs",
        system.dim()
    ));

    let loads = LoadPatterns::new(system, case)?;
    loads.check_grid(dt, steps, &mut warnings);

    let mut recorder = Recorder::new(system, steps, &mut warnings)?;

    let n = system.dim();
    let u0 = match start {
        Some(s) => (0..n)
            .map(|eq| s.solution.displacement[system.dofs.free_to_full(eq)])
            .collect(),
        None => vec![0.0; n],
    };
    if context.velocity.is_none() {
        context.velocity = Some(initial_velocity(system, factor)?);
    }
    let (v0, velocity_field) = match &context.velocity {
        Some((v, field)) => (v.clone(), *field),
        None => (vec![0.0; n], VelocityField::Rest),
    };

    let modal_summary = match method {
        TransientMethod::Direct(integrator) => {
            run_direct(
                system,
                &mut context.direct,
                factor,
                title,
                integrator,
                dt,
                steps,
                &u0,
                &v0,
                &loads,
                &mut recorder,
                &progress,
            )?;
            None
        }
        TransientMethod::Modal { .. }
            if !(system.point_laws()?.is_empty()
                && system.model.tension_links().is_empty()
                && system.model.moving_contacts().is_empty()) =>
        {
            return Err(SolveError::NonlinearNeedsDirect {
                case: title.to_string(),
            });
        }
        TransientMethod::Modal { modes } => {
            let factor = factor.ok_or_else(|| SolveError::BadInput {
                what: format!(
                    "load case '{title}': modal superposition needs the stiffness factor"
                ),
            })?;
            Some(run_modal(
                system,
                factor,
                title,
                modes as usize,
                dt,
                steps,
                &u0,
                &v0,
                &loads,
                &mut recorder,
                &progress,
            )?)
        }
    };
    progress.finish();

    Ok(TransientSolution {
        method,
        dt_s: dt,
        total_time_s: steps as f64 * dt,
        steps,
        output_every: recorder.every,
        initial_displacement_from: start.map(|s| s.title.to_string()),
        velocity_field,
        modal: modal_summary,
        warnings,
        history: recorder.finish(),
    })
}

/// Number of steps to reach `total_time`; a total that is not a whole number of steps
/// is reached by the next whole step, with a warning.
fn step_count(
    title: &str,
    dt: f64,
    total_time: f64,
    warnings: &mut Vec<String>,
) -> Result<usize, SolveError> {
    if !(dt.is_finite() && dt > 0.0 && total_time.is_finite() && total_time >= dt) {
        return Err(SolveError::BadInput {
            what: format!(
                "load case '{title}': time step {dt} s and total time {total_time} s; \
                 expected a finite dt > 0 and a total time of at least one step"
            ),
        });
    }
    let ratio = total_time / dt;
    // A relative 1e-9 absorbs the rounding of a decimal dt (1e-3 * 20000 != 20 exactly).
    let steps = (ratio * (1.0 - 1e-9)).ceil();
    if steps > MAX_STEPS as f64 {
        return Err(SolveError::BadInput {
            what: format!(
                "load case '{title}': {total_time} s at dt = {dt} s is {steps:.3e} steps, more \
                 than the {MAX_STEPS} coil takes; check the time step"
            ),
        });
    }
    let steps = steps as usize;
    let end = steps as f64 * dt;
    if (end - total_time).abs() > 1e-9 * total_time {
        warnings.push(format!(
            "the total time {total_time} s is not a whole number of steps of {dt} s: the \
             case runs {steps} steps, to {end} s"
        ));
    }
    Ok(steps)
}
