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
//! on `M`, `C`, `K` with both triangles stored; the effective matrix is factored once per
//! `(scheme, dt)` and the stepper is kept in [`Context`] for the next transient case.
//! The model's nonlinear point elements (`FRICTION`, `QUADRATIC DAMPER`, `CUBIC
//! SPRING`) are bound to the stepper as [`crate::integrate::PointLaw`]s on their free
//! DOFs ([`Stepper::set_point_laws`]: an exact end-of-step correction, average
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
//! # References
//! N. M. Newmark, J. Eng. Mech. Div. ASCE 85 (1959) 67-94; H. M. Hilber, T. J. R. Hughes,
//! R. L. Taylor, Earthq. Eng. Struct. Dyn. 5 (1977) 283-292; J. Chung, G. M. Hulbert,
//! J. Appl. Mech. 60 (1993) 371-375 (the schemes, see `crate::integrate`); N. C. Nigam,
//! P. C. Jennings, Bull. Seismol. Soc. Am. 59 (1969) 909-922 (exact modal steps);
//! R. J. Guyan, AIAA J. 3 (1965) 380 (the static condensation shape behind the
//! quasi-static velocity field).

use super::modal;
use super::static_analysis::StaticSolution;
use super::system::{interpolate, table_points, System};
use crate::error::SolveError;
use crate::dof::{dof_name, DofStatus};
use crate::integrate::modal_superposition::{integrate_modal, ModalBasis, ModalState};
use crate::integrate::{IntegrateError, Operators, Scheme, State, Stepper};
use crate::linalg::{sym_upper_matvec, upper_to_full, Cholesky};
use crate::model::{
    units, Analysis, InitialVelocity, Integrator, LoadCase, Model, PointLoad, Quantity,
    TransientMethod,
};
use faer::sparse::SparseColMat;
use faer::Mat;
use std::fmt::Write as _;

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

/// Most values (rows times columns) a history may hold (800 MB in memory).
pub const MAX_HISTORY_VALUES: usize = 100_000_000;

/// One recorded signal.
#[derive(Debug, Clone, PartialEq)]
pub struct HistoryColumn {
    /// `node{ID}_{dof}_{quantity}_{unit}`, e.g. `node1_uz_accel_m_s2`.
    pub name: String,
    /// Values in the SI unit the name carries.
    pub values: Vec<f64>,
}

/// The recorded signals of a transient case.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct History {
    /// Sample times (s), `k dt` for the recorded steps `k`.
    pub time_s: Vec<f64>,
    pub columns: Vec<HistoryColumn>,
}

impl History {
    /// The values of a column.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.values.as_slice())
    }

    /// The column names, in order.
    pub fn names(&self) -> Vec<String> {
        self.columns.iter().map(|c| c.name.clone()).collect()
    }

    /// CSV text: a header `time_s,name,...` and one row per sample. Times print in
    /// plain decimal, values in scientific notation; both are the shortest text that
    /// reads back to the same `f64`.
    pub fn to_csv(&self) -> String {
        let mut out = String::with_capacity(24 * (self.columns.len() + 1) * self.time_s.len());
        out.push_str("time_s");
        for c in &self.columns {
            out.push(',');
            out.push_str(&c.name);
        }
        out.push('\n');
        for (row, t) in self.time_s.iter().enumerate() {
            // Writing to a String cannot fail.
            let _ = write!(out, "{t}");
            for c in &self.columns {
                let _ = write!(out, ",{:e}", c.values[row]);
            }
            out.push('\n');
        }
        out
    }
}

/// How the initial velocity field was made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VelocityField {
    /// No `INITIAL VEL`: everything at rest.
    Rest,
    /// Plain `INITIAL VEL` only: the listed DOFs move, the rest is at rest.
    Nodal,
    /// `INITIAL VEL, QUASI STATIC` only.
    QuasiStatic,
    /// Both kinds of groups.
    Mixed,
}

impl VelocityField {
    /// The name used in results.json.
    pub fn name(self) -> &'static str {
        match self {
            VelocityField::Rest => "rest",
            VelocityField::Nodal => "nodal",
            VelocityField::QuasiStatic => "quasi-static",
            VelocityField::Mixed => "quasi-static + nodal",
        }
    }
}

/// One retained mode of a modal superposition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalTerm {
    pub omega_rad_s: f64,
    pub frequency_hz: f64,
    /// `phi^T C phi / (2 w)`: the damping ratio the mode is integrated with.
    pub zeta: f64,
    /// The damping ratio with the full modal damping matrix of the retained modes
    /// (`None` for a mode damped critically or more, whose pair of real roots has no
    /// single ratio).
    pub zeta_coupled: Option<f64>,
    /// Effective mass along global z, the spring axis (t).
    pub axial_effective_mass: f64,
}

/// What a modal superposition kept and left out.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalSummary {
    pub modes: Vec<ModalTerm>,
    /// `max |c_ij| / sqrt(c_ii c_jj)` over `i != j` of `c = Phi^T C Phi`: the largest
    /// normalised damping coupling that the decoupled integration neglects (0 for
    /// classical damping).
    pub max_damping_coupling: f64,
    /// The two modes (1-based) of that coupling.
    pub coupling_pair: Option<(usize, usize)>,
    /// `max |zeta_coupled / zeta - 1|` over the modes with both ratios.
    pub max_zeta_shift: Option<f64>,
    /// Fraction of the initial strain energy `u0^T K u0 / 2` in the retained modes
    /// (`None` when the initial displacement is zero).
    pub initial_displacement_captured: Option<f64>,
    /// Fraction of the initial kinetic energy `v0^T M v0 / 2` in the retained modes
    /// (`None` when the initial velocity is zero).
    pub initial_velocity_captured: Option<f64>,
    /// Smallest, over the load patterns (constant part and one per table), fraction of
    /// the static compliance `f^T K^-1 f` the retained modes carry (`None` without loads).
    pub load_captured: Option<f64>,
}

/// The result of a transient load case.
#[derive(Debug, Clone, PartialEq)]
pub struct TransientSolution {
    /// The method as run (after any command-line override).
    pub method: TransientMethod,
    pub dt_s: f64,
    /// The end time, `steps * dt` (s).
    pub total_time_s: f64,
    pub steps: usize,
    /// Steps between recorded samples.
    pub output_every: usize,
    /// Title of the static load case whose displacement is the initial state.
    pub initial_displacement_from: Option<String>,
    pub velocity_field: VelocityField,
    /// Present for modal superposition.
    pub modal: Option<ModalSummary>,
    /// Things the user should know (off-grid table breakpoints, a rounded end time, a
    /// missing output request).
    pub warnings: Vec<String>,
    pub history: History,
}

/// State kept between the transient cases of one run: the operators with both
/// triangles, the stepper with its factored effective matrix, the initial velocity.
#[derive(Debug, Default)]
pub struct Context {
    /// Reporting and limits of this run.
    pub options: RunOptions,
    operators: Option<FullOperators>,
    stepper: Option<Stepper>,
    velocity: Option<(Vec<f64>, VelocityField)>,
}

#[derive(Debug)]
struct FullOperators {
    k: SparseColMat<usize, f64>,
    m: SparseColMat<usize, f64>,
    /// `None` when the model has no damping.
    c: Option<SparseColMat<usize, f64>>,
}

impl FullOperators {
    fn new(system: &System) -> Result<Self, SolveError> {
        let c = if system.damping.val().iter().any(|&v| v != 0.0) {
            Some(upper_to_full(system.damping.as_ref())?)
        } else {
            None
        };
        Ok(FullOperators {
            k: upper_to_full(system.stiffness.as_ref())?,
            m: upper_to_full(system.mass.as_ref())?,
            c,
        })
    }

    fn view(&self) -> Operators<'_> {
        Operators {
            m: self.m.as_ref(),
            c: self.c.as_ref().map(|c| c.as_ref()),
            k: self.k.as_ref(),
        }
    }
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
    Modal { modes: Option<u32> },
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
    pub title: &'a str,
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
                context,
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
        TransientMethod::Modal { .. } if !system.point_laws()?.is_empty() => {
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

/// The free-DOF load `f(t) = f_c + sum_k s_k(t) f_k`: a constant pattern (untabled loads
/// and the prescribed-displacement load) and one pattern per table.
struct LoadPatterns {
    constant: Vec<f64>,
    tabled: Vec<TabledLoad>,
}

struct TabledLoad {
    table: String,
    points: Vec<(f64, f64)>,
    load: Vec<f64>,
}

impl LoadPatterns {
    fn new(system: &System, case: &LoadCase) -> Result<Self, SolveError> {
        let model = system.model;
        let all: Vec<&PointLoad> = model.point_loads.iter().chain(&case.point_loads).collect();
        let untabled = all.iter().copied().filter(|l| l.table.is_none());
        let constant = system.free_load(&system.point_load_vector(untabled, 0.0)?);
        let mut names: Vec<&str> = all.iter().filter_map(|l| l.table.as_deref()).collect();
        names.sort_unstable_by_key(|n| n.to_ascii_lowercase());
        names.dedup_by(|a, b| a.eq_ignore_ascii_case(b));
        let mut tabled = Vec::with_capacity(names.len());
        for name in names {
            let points = table_points(model, name)?.to_vec();
            // The table's own spelling, for messages.
            let table = model
                .tables
                .iter()
                .find(|t| t.name.eq_ignore_ascii_case(name))
                .map_or(name, |t| t.name.as_str());
            let loads: Vec<PointLoad> = all
                .iter()
                .filter(|l| {
                    l.table
                        .as_deref()
                        .is_some_and(|t| t.eq_ignore_ascii_case(name))
                })
                .map(|l| PointLoad {
                    table: None,
                    ..(*l).clone()
                })
                .collect();
            let f_full = system.point_load_vector(&loads, 0.0)?;
            let mut load = vec![0.0; system.dim()];
            system.dofs.restrict_add(&f_full, &mut load);
            tabled.push(TabledLoad {
                table: table.to_string(),
                points,
                load,
            });
        }
        Ok(LoadPatterns { constant, tabled })
    }

    /// Every pattern with its time factor function.
    fn patterns(&self) -> impl Iterator<Item = &[f64]> {
        std::iter::once(self.constant.as_slice()).chain(self.tabled.iter().map(|t| &t.load[..]))
    }

    /// The factor of each pattern at `t` (1 for the constant one).
    fn factors(&self, t: f64, out: &mut [f64]) {
        out[0] = 1.0;
        for (o, tabled) in out[1..].iter_mut().zip(&self.tabled) {
            *o = interpolate(&tabled.points, t);
        }
    }

    fn count(&self) -> usize {
        1 + self.tabled.len()
    }

    /// Warns about table breakpoints inside the run that are not on the step grid: the
    /// load is sampled at the steps and taken linear in between.
    fn check_grid(&self, dt: f64, steps: usize, warnings: &mut Vec<String>) {
        let end = steps as f64 * dt;
        for tabled in &self.tabled {
            let off: Vec<f64> = tabled
                .points
                .iter()
                .map(|p| p.0)
                .filter(|&t| t > 0.0 && t < end && ((t / dt) - (t / dt).round()).abs() > 1e-6)
                .collect();
            if let Some(first) = off.first() {
                warnings.push(format!(
                    "table '{}' has {} breakpoint(s) between steps of {dt} s (first at {first} s): \
                     the load is sampled at the steps and taken linear in between, so a feature \
                     shorter than a step is misrepresented; put breakpoints on multiples of dt",
                    tabled.table,
                    off.len()
                ));
            }
        }
    }
}

/// The initial velocity on the free DOFs (see the module docs) and what kind it is.
fn initial_velocity(
    system: &System,
    factor: Option<&Cholesky>,
) -> Result<(Vec<f64>, VelocityField), SolveError> {
    let n = system.dim();
    let model = system.model;
    let mut plain: Vec<(usize, f64)> = Vec::new();
    let mut listed: Vec<(usize, f64)> = Vec::new();
    for group in &model.initial_velocities {
        let target = if group.quasi_static {
            &mut listed
        } else {
            &mut plain
        };
        free_velocities(system, group, target)?;
    }
    let field = match (
        model.initial_velocities.iter().any(|g| g.quasi_static),
        model.initial_velocities.iter().any(|g| !g.quasi_static),
    ) {
        (false, false) => VelocityField::Rest,
        (false, true) => VelocityField::Nodal,
        (true, false) => VelocityField::QuasiStatic,
        (true, true) => VelocityField::Mixed,
    };
    let mut v = vec![0.0; n];
    if !listed.is_empty() {
        let factor = factor.ok_or_else(|| SolveError::BadInput {
            what: "INITIAL VEL, QUASI STATIC needs the stiffness factor".to_string(),
        })?;
        v = quasi_static_field(factor, n, &listed)?;
    }
    for (eq, value) in plain {
        v[eq] = value;
    }
    Ok((v, field))
}

/// The free equations and values of one `INITIAL VEL` group.
fn free_velocities(
    system: &System,
    group: &InitialVelocity,
    out: &mut Vec<(usize, f64)>,
) -> Result<(), SolveError> {
    for &node in &group.nodes {
        for &(dof, value) in &group.dofs {
            let full = system.full_dof(node, dof, "INITIAL VEL")?;
            if !value.is_finite() {
                return Err(SolveError::NonFinite {
                    what: format!("INITIAL VEL at node {node} {}", dof_name(dof)),
                });
            }
            match system.dofs.status(full) {
                DofStatus::Free(eq) => out.push((eq, value)),
                DofStatus::Prescribed(_) if value == 0.0 => {}
                DofStatus::Prescribed(_) => {
                    return Err(SolveError::BadInput {
                        what: format!(
                        "INITIAL VEL gives node {node} {} a velocity of {value}, but FIXED DISP \
                             prescribes that DOF (its velocity is 0); remove it from INITIAL VEL",
                        dof_name(dof)
                    ),
                    })
                }
                DofStatus::Dependent if value == 0.0 => {}
                DofStatus::Dependent => {
                    return Err(SolveError::BadInput {
                        what: format!(
                            "INITIAL VEL gives node {node} {} a velocity of {value}, but an RBE2 \
                             ties that DOF to its reference node; give the velocity there",
                            dof_name(dof)
                        ),
                    })
                }
            }
        }
    }
    Ok(())
}

/// `v = K^-1 E c` with `(E^T K^-1 E) c = v_listed`: the smoothest (least strain energy)
/// field that takes the listed values.
fn quasi_static_field(
    factor: &Cholesky,
    n: usize,
    listed: &[(usize, f64)],
) -> Result<Vec<f64>, SolveError> {
    let k = listed.len();
    let mut columns = Vec::with_capacity(k);
    for &(eq, _) in listed {
        let mut x = vec![0.0; n];
        x[eq] = 1.0;
        factor.solve_in_place(&mut x);
        columns.push(x);
    }
    let flexibility = nalgebra::DMatrix::from_fn(k, k, |i, j| {
        0.5 * (columns[j][listed[i].0] + columns[i][listed[j].0])
    });
    let values = nalgebra::DVector::from_iterator(k, listed.iter().map(|p| p.1));
    let c = flexibility
        .cholesky()
        .ok_or_else(|| SolveError::BadInput {
            what: "INITIAL VEL, QUASI STATIC: the flexibility at the listed DOFs is singular \
                   (a DOF listed twice through a tie?)"
                .to_string(),
        })?
        .solve(&values);
    let mut v = vec![0.0; n];
    for (column, cj) in columns.iter().zip(c.iter()) {
        for (vi, xi) in v.iter_mut().zip(column) {
            *vi += cj * xi;
        }
    }
    // Exact values at the listed DOFs (the solve leaves rounding there).
    for &(eq, value) in listed {
        v[eq] = value;
    }
    if v.iter().any(|x| !x.is_finite()) {
        return Err(SolveError::NonFinite {
            what: "the quasi-static initial velocity field".to_string(),
        });
    }
    Ok(v)
}

/// One output DOF: its row of `T` and its prescribed part.
struct OutputDof {
    terms: Vec<(usize, f64)>,
    prescribed: f64,
}

struct OutputColumn {
    name: String,
    slot: usize,
    quantity: Quantity,
    /// Model units to SI (mm -> m for translations, 1 for rotations).
    scale: f64,
}

/// Collects the requested signals every `every`-th step.
struct Recorder {
    every: usize,
    dofs: Vec<OutputDof>,
    columns: Vec<OutputColumn>,
    time: Vec<f64>,
    values: Vec<Vec<f64>>,
    scratch: [Vec<f64>; 3],
}

impl Recorder {
    fn new(system: &System, steps: usize, warnings: &mut Vec<String>) -> Result<Self, SolveError> {
        let model = system.model;
        let mut every = 0usize;
        let mut slots: Vec<usize> = Vec::new();
        let mut dofs = Vec::new();
        let mut columns: Vec<OutputColumn> = Vec::new();
        for request in &model.outputs {
            if request.every == 0 {
                return Err(SolveError::BadInput {
                    what: "HISTORY OUTPUT every 0 steps; expected k >= 1".to_string(),
                });
            }
            every = gcd(every, request.every as usize);
            for &node in &request.nodes {
                for &dof in &request.dofs {
                    let full = system.full_dof(node, dof, "HISTORY OUTPUT")?;
                    let slot = match slots.iter().position(|&d| d == full) {
                        Some(s) => s,
                        None => {
                            slots.push(full);
                            dofs.push(OutputDof {
                                terms: system.dofs.expansion(full).collect(),
                                prescribed: system.dofs.prescribed_part(full),
                            });
                            slots.len() - 1
                        }
                    };
                    for &quantity in &request.quantities {
                        let name = column_name(node, dof, quantity);
                        if columns.iter().any(|c| c.name == name) {
                            continue;
                        }
                        columns.push(OutputColumn {
                            name,
                            slot,
                            quantity,
                            scale: if dof <= 3 { 1.0 / units::MM_PER_M } else { 1.0 },
                        });
                    }
                }
            }
        }
        if columns.is_empty() {
            warnings.push(
                "no HISTORY OUTPUT request: the history holds only the time column".to_string(),
            );
        }
        let every = every.max(1);
        let rows = steps / every + 1;
        if rows.saturating_mul(columns.len() + 1) > MAX_HISTORY_VALUES {
            return Err(SolveError::BadInput {
                what: format!(
                    "the history would hold {rows} rows of {} columns; record every k-th step \
                     with a larger k (HISTORY OUTPUT)",
                    columns.len() + 1
                ),
            });
        }
        let n_slots = dofs.len();
        Ok(Recorder {
            every,
            dofs,
            values: columns.iter().map(|_| Vec::with_capacity(rows)).collect(),
            columns,
            time: Vec::with_capacity(rows),
            scratch: [vec![0.0; n_slots], vec![0.0; n_slots], vec![0.0; n_slots]],
        })
    }

    /// The free DOFs whose modal shape rows the outputs need are the `terms`; this gives
    /// the rows of `T Phi` for the output slots.
    fn slot_rows(&self, shapes: &Mat<f64>) -> Mat<f64> {
        Mat::from_fn(self.dofs.len(), shapes.ncols(), |slot, mode| {
            self.dofs[slot]
                .terms
                .iter()
                .map(|&(eq, c)| c * shapes[(eq, mode)])
                .sum()
        })
    }

    fn wants(&self, step: usize) -> bool {
        step % self.every == 0
    }

    /// Records from free-DOF vectors (direct integration).
    fn record_free(&mut self, t: f64, u: &[f64], v: &[f64], a: &[f64]) {
        let [su, sv, sa] = &mut self.scratch;
        for (slot, dof) in self.dofs.iter().enumerate() {
            let (mut x, mut y, mut z) = (0.0, 0.0, 0.0);
            for &(eq, c) in &dof.terms {
                x += c * u[eq];
                y += c * v[eq];
                z += c * a[eq];
            }
            su[slot] = x;
            sv[slot] = y;
            sa[slot] = z;
        }
        let scratch = std::mem::take(&mut self.scratch);
        self.record_slots(t, &scratch[0], &scratch[1], &scratch[2]);
        self.scratch = scratch;
    }

    /// Records from values at the output slots without their prescribed part.
    fn record_slots(&mut self, t: f64, u: &[f64], v: &[f64], a: &[f64]) {
        self.time.push(t);
        for (column, values) in self.columns.iter().zip(&mut self.values) {
            let s = column.slot;
            let x = match column.quantity {
                Quantity::Displacement => u[s] + self.dofs[s].prescribed,
                Quantity::Velocity => v[s],
                Quantity::Acceleration => a[s],
            };
            values.push(x * column.scale);
        }
    }

    fn finish(self) -> History {
        History {
            time_s: self.time,
            columns: self
                .columns
                .into_iter()
                .zip(self.values)
                .map(|(c, values)| HistoryColumn {
                    name: c.name,
                    values,
                })
                .collect(),
        }
    }
}

/// `node{ID}_{dof}_{quantity}_{unit}` in SI units.
pub fn column_name(node: u32, dof: u8, quantity: Quantity) -> String {
    let rotation = dof > 3;
    let suffix = match (quantity, rotation) {
        (Quantity::Displacement, false) => "disp_m",
        (Quantity::Velocity, false) => "vel_m_s",
        (Quantity::Acceleration, false) => "accel_m_s2",
        (Quantity::Displacement, true) => "disp_rad",
        (Quantity::Velocity, true) => "vel_rad_s",
        (Quantity::Acceleration, true) => "accel_rad_s2",
    };
    format!("node{node}_{}_{suffix}", dof_name(dof))
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// An integrator error with the free DOF (or mode) it names turned into a node label.
fn integrate_error(system: &System, case: &str, modal: bool, source: IntegrateError) -> SolveError {
    let dof = match &source {
        IntegrateError::NotPositiveDefinite { dof, .. }
        | IntegrateError::NonFiniteState { dof, .. } => Some(*dof),
        _ => None,
    };
    let location = match dof {
        Some(d) if modal => format!(" (mode {})", d + 1),
        Some(d) if d < system.dim() => {
            let (node, dof) = system.dofs.free_label(d);
            format!(" (DOF {d} is node {node} {})", dof_name(dof))
        }
        _ => String::new(),
    };
    SolveError::Integrate {
        case: case.to_string(),
        location,
        source,
    }
}

#[allow(clippy::too_many_arguments)]
fn run_direct(
    system: &System,
    context: &mut Context,
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
    if context.operators.is_none() {
        context.operators = Some(FullOperators::new(system)?);
    }
    let stepper = match (context.stepper.take(), &context.operators) {
        (Some(mut stepper), _) => {
            stepper.set_step(scheme, dt).map_err(fail)?;
            stepper
        }
        (None, Some(ops)) => Stepper::new(ops.view(), scheme, dt).map_err(fail)?,
        (None, None) => {
            return Err(SolveError::Linalg(
                "the transient operators were not built".to_string(),
            ))
        }
    };
    let stepper = context.stepper.insert(stepper);
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
struct ModalDampingTerm {
    /// Columns of `U = M Phi`.
    u: Vec<Vec<f64>>,
    /// `2 zeta_i w_i`.
    d: Vec<f64>,
    /// The step's response to each column of `U` as its end load: (u, v, a).
    response: Vec<State>,
    /// LU of `I + U^T V D`.
    lu: nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
    z: Vec<f64>,
}

impl ModalDampingTerm {
    fn new(
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
    fn add_force(&self, v: &[f64], f: &mut [f64]) {
        for (col, &d) in self.u.iter().zip(&self.d) {
            let z: f64 = col.iter().zip(v).map(|(a, b)| a * b).sum();
            for (fi, ci) in f.iter_mut().zip(col) {
                *fi -= d * z * ci;
            }
        }
    }

    /// Turns the step just taken under the load alone into the damped one.
    fn correct(&mut self, state: &mut State) {
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

#[allow(clippy::too_many_arguments)]
fn run_modal(
    system: &System,
    factor: &Cholesky,
    title: &str,
    n_modes: usize,
    dt: f64,
    steps: usize,
    u0: &[f64],
    v0: &[f64],
    loads: &LoadPatterns,
    recorder: &mut Recorder,
    progress: &coil_io::Progress,
) -> Result<ModalSummary, SolveError> {
    let fail = |e| integrate_error(system, title, true, e);
    let n = system.dim();
    let solution = modal::solve(system, factor, title, n_modes)?;
    let m = solution.modes.len();
    let shapes = Mat::from_fn(n, m, |i, j| solution.modes[j].shape_free[i]);
    let omega: Vec<f64> = solution
        .modes
        .iter()
        .map(|mode| mode.omega_squared.sqrt())
        .collect();
    let coupling = damping_coupling(system, &solution.modes, &omega);
    let zeta = coupling.zeta.clone();

    // Initial modal state q = Phi^T M x and what the basis captures of it.
    let project_mass = |x: &[f64]| -> Vec<f64> {
        let mut mx = vec![0.0; n];
        sym_upper_matvec(system.mass.as_ref(), x, 1.0, &mut mx);
        project(&shapes, &mx)
    };
    let q0 = project_mass(u0);
    let qd0 = project_mass(v0);
    let strain = quadratic(&system.stiffness, u0);
    let kinetic = quadratic(&system.mass, v0);
    let initial_displacement_captured = (strain > 0.0).then(|| {
        q0.iter()
            .zip(&omega)
            .map(|(q, w)| (w * q).powi(2))
            .sum::<f64>()
            / strain
    });
    let initial_velocity_captured =
        (kinetic > 0.0).then(|| qd0.iter().map(|q| q * q).sum::<f64>() / kinetic);

    // Modal load patterns p_k = Phi^T f_k, and their captured static compliance.
    let mut modal_patterns = Vec::with_capacity(loads.count());
    let mut load_captured: Option<f64> = None;
    for pattern in loads.patterns() {
        let p = project(&shapes, pattern);
        let mut x = pattern.to_vec();
        factor.solve_in_place(&mut x);
        let compliance: f64 = x.iter().zip(pattern).map(|(a, b)| a * b).sum();
        if compliance > 0.0 {
            let kept: f64 = p.iter().zip(&omega).map(|(pj, w)| (pj / w).powi(2)).sum();
            let ratio = kept / compliance;
            load_captured = Some(load_captured.map_or(ratio, |r: f64| r.min(ratio)));
        }
        modal_patterns.push(p);
    }

    let rows = recorder.slot_rows(&shapes);
    let output_slots: Vec<usize> = (0..rows.nrows()).collect();
    let basis = ModalBasis {
        shapes: rows.as_ref(),
        omega: &omega,
        zeta: &zeta,
    };
    let initial = ModalState {
        t: 0.0,
        q: q0,
        qd: qd0,
    };
    let mut factors = vec![0.0; loads.count()];
    integrate_modal(
        basis,
        dt,
        steps,
        &initial,
        &output_slots,
        &mut |t, p| {
            loads.factors(t, &mut factors);
            for (s, pattern) in factors.iter().zip(&modal_patterns) {
                for (pi, qi) in p.iter_mut().zip(pattern) {
                    *pi += s * qi;
                }
            }
        },
        &mut |k, t, response| {
            if k % 64 == 0 {
                progress.set(k as u64);
            }
            if recorder.wants(k) {
                recorder.record_slots(t, response.u, response.v, response.a);
            }
        },
    )
    .map_err(fail)?;

    let modes = solution
        .modes
        .iter()
        .enumerate()
        .map(|(j, mode)| ModalTerm {
            omega_rad_s: omega[j],
            frequency_hz: mode.frequency_hz,
            zeta: zeta[j],
            zeta_coupled: coupling.zeta_coupled[j],
            axial_effective_mass: mode.effective_mass[2],
        })
        .collect();
    Ok(ModalSummary {
        modes,
        max_damping_coupling: coupling.max,
        coupling_pair: coupling.pair,
        max_zeta_shift: coupling.max_zeta_shift,
        initial_displacement_captured,
        initial_velocity_captured,
        load_captured,
    })
}

/// `Phi^T x`.
fn project(shapes: &Mat<f64>, x: &[f64]) -> Vec<f64> {
    (0..shapes.ncols())
        .map(|j| shapes.col(j).iter().zip(x).map(|(p, xi)| p * xi).sum())
        .collect()
}

fn quadratic(a: &SparseColMat<usize, f64>, x: &[f64]) -> f64 {
    let mut y = vec![0.0; x.len()];
    sym_upper_matvec(a.as_ref(), x, 1.0, &mut y);
    x.iter().zip(&y).map(|(p, q)| p * q).sum()
}

struct Coupling {
    /// `c_ii / (2 w_i) = phi_i^T C phi_i / (2 w_i)`.
    zeta: Vec<f64>,
    max: f64,
    pair: Option<(usize, usize)>,
    zeta_coupled: Vec<Option<f64>>,
    max_zeta_shift: Option<f64>,
}

/// The modal damping matrix `c = Phi^T C Phi`, the modal damping ratios
/// `zeta_i = c_ii / (2 w_i)` the modes are integrated with, its largest normalised
/// off-diagonal entry, and the damping ratios of the retained modes with all of `c`: the eigenvalues
/// `lambda = -zeta w +- i w sqrt(1 - zeta^2)` of `[[0, Omega], [-Omega, -c]]` (the state
/// `(Omega q, q')`, which keeps every entry of the order of a frequency), each mode taking
/// the eigenvalue nearest its decoupled one, `zeta = -Re lambda / |lambda|`.
fn damping_coupling(system: &System, modes: &[modal::Mode], omega: &[f64]) -> Coupling {
    let m = modes.len();
    let n = system.dim();
    let mut c_phi = vec![vec![0.0; n]; m];
    for (mode, out) in modes.iter().zip(&mut c_phi) {
        sym_upper_matvec(system.damping.as_ref(), &mode.shape_free, 1.0, out);
    }
    let c = nalgebra::DMatrix::from_fn(m, m, |i, j| {
        let a: f64 = modes[i]
            .shape_free
            .iter()
            .zip(&c_phi[j])
            .map(|(p, q)| p * q)
            .sum();
        let b: f64 = modes[j]
            .shape_free
            .iter()
            .zip(&c_phi[i])
            .map(|(p, q)| p * q)
            .sum();
        0.5 * (a + b)
    });
    // Modal damping (`LOSS FACTOR`, `MODAL DAMPING`) is diagonal in the modes.
    let mut c = c;
    for i in 0..m {
        c[(i, i)] += 2.0 * system.model.modal_damping.zeta(i) * omega[i];
    }
    let zeta: Vec<f64> = (0..m).map(|i| c[(i, i)] / (2.0 * omega[i])).collect();
    let mut max = 0.0;
    let mut pair = None;
    for i in 0..m {
        for j in i + 1..m {
            let d = (c[(i, i)] * c[(j, j)]).sqrt();
            if d > 0.0 {
                let r = c[(i, j)].abs() / d;
                if r > max {
                    max = r;
                    pair = Some((i + 1, j + 1));
                }
            }
        }
    }
    let mut zeta_coupled: Vec<Option<f64>> = zeta.iter().map(|&z| (z < 1.0).then_some(z)).collect();
    if c.iter().any(|&x| x != 0.0) && m > 0 {
        let mut a = nalgebra::DMatrix::<f64>::zeros(2 * m, 2 * m);
        for i in 0..m {
            a[(i, m + i)] = omega[i];
            a[(m + i, i)] = -omega[i];
            for j in 0..m {
                a[(m + i, m + j)] = -c[(i, j)];
            }
        }
        // A failed Schur iteration leaves the coupled ratios unknown, not wrong.
        let eigenvalues = nalgebra::linalg::Schur::try_new(a, f64::EPSILON, 100_000)
            .map(|s| s.complex_eigenvalues());
        match eigenvalues {
            Some(lambda) => {
                for (i, zc) in zeta_coupled.iter_mut().enumerate() {
                    if zc.is_none() {
                        continue;
                    }
                    let (w, z) = (omega[i], zeta[i]);
                    let target = nalgebra::Complex::new(-z * w, w * (1.0 - z * z).sqrt());
                    let nearest = lambda
                        .iter()
                        .filter(|l| l.im > 0.0)
                        .min_by(|a, b| (*a - target).norm().total_cmp(&(*b - target).norm()));
                    *zc = nearest.map(|l| -l.re / l.norm());
                }
            }
            None => zeta_coupled.iter_mut().for_each(|z| *z = None),
        }
    }
    let max_zeta_shift = zeta
        .iter()
        .zip(&zeta_coupled)
        .filter_map(|(&z, zc)| zc.filter(|_| z > 0.0).map(|zc| (zc / z - 1.0).abs()))
        .reduce(f64::max);
    Coupling {
        zeta,
        max,
        pair,
        zeta_coupled,
        max_zeta_shift,
    }
}

#[cfg(test)]
mod tests {
    use crate::analysis::test_support::tied_frame;
    use super::*;
    use crate::analysis::{run, CaseSolution};
    use crate::model::{Damping, OutputRequest, PointMass, Table};

    /// The tied frame with a point mass on the reference node 10 (whose u_z and theta_x
    /// are prescribed; node 4 is tied to it).
    fn frame() -> Model {
        let mut model = tied_frame();
        model.point_masses.push(PointMass {
            node: 10,
            mass: 2e-3,
            inertia: [0.5, 0.5, 0.5],
        });
        model
    }

    fn transient_case(dt: f64, total_time: f64, method: TransientMethod) -> LoadCase {
        LoadCase {
            title: "shake".to_string(),
            analysis: Analysis::Transient {
                dt,
                total_time,
                method,
            },
            point_loads: Vec::new(),
        }
    }

    fn free_eq(system: &System, node: u32, dof: u8) -> usize {
        match system
            .dofs
            .status(system.dofs.full_index(node, dof).unwrap())
        {
            DofStatus::Free(eq) => eq,
            other => panic!("node {node} DOF {dof} is {other:?}"),
        }
    }

    #[test]
    fn quasi_static_velocity_is_the_static_shape_through_the_listed_values() {
        let mut model = frame();
        model.initial_velocities = vec![
            InitialVelocity {
                dofs: vec![(2, 7.0)],
                nodes: vec![3],
                quasi_static: true,
            },
            InitialVelocity {
                dofs: vec![(1, -3.0)],
                nodes: vec![10],
                quasi_static: true,
            },
        ];
        let system = System::new(&model).unwrap();
        let factor = system.factor_stiffness().unwrap();
        let (v, field) = initial_velocity(&system, Some(&factor)).unwrap();
        assert_eq!(field, VelocityField::QuasiStatic);
        let (a, b) = (free_eq(&system, 3, 2), free_eq(&system, 10, 1));
        assert_eq!((v[a], v[b]), (7.0, -3.0));
        // K v is a force at the listed DOFs only: the static shape of two point forces.
        let mut kv = vec![0.0; v.len()];
        sym_upper_matvec(system.stiffness.as_ref(), &v, 1.0, &mut kv);
        let scale = kv[a].abs().max(kv[b].abs());
        for (eq, f) in kv.iter().enumerate() {
            if eq != a && eq != b {
                assert!(f.abs() < 1e-10 * scale, "eq {eq}: {f} vs {scale}");
            }
        }
        assert!(
            v.iter().filter(|x| **x != 0.0).count() > 2,
            "the field spreads"
        );
        // A plain group overrides its DOF after the quasi-static field.
        model.initial_velocities.push(InitialVelocity {
            dofs: vec![(6, 0.25)],
            nodes: vec![2],
            quasi_static: false,
        });
        let system = System::new(&model).unwrap();
        let (w, field) = initial_velocity(&system, Some(&factor)).unwrap();
        assert_eq!(field, VelocityField::Mixed);
        let c = free_eq(&system, 2, 6);
        assert_eq!(w[c], 0.25);
        assert_eq!(w[a], 7.0);
        // Without a factor the quasi-static field is an error, not a silent jump.
        assert!(matches!(
            initial_velocity(&system, None),
            Err(SolveError::BadInput { .. })
        ));
    }

    #[test]
    fn initial_velocity_on_constrained_dofs() {
        let mut model = frame();
        let at = |node, dof, value| InitialVelocity {
            dofs: vec![(dof, value)],
            nodes: vec![node],
            quasi_static: false,
        };
        for (group, what) in [
            (at(10, 3, 5.0), "FIXED DISP"),
            (at(4, 1, 5.0), "RBE2"),
            (at(99, 1, 5.0), "node 99"),
            (at(2, 9, 5.0), "DOF 9"),
            (at(2, 1, f64::NAN), "non-finite"),
        ] {
            model.initial_velocities = vec![group];
            let system = System::new(&model).unwrap();
            let e = initial_velocity(&system, None).unwrap_err().to_string();
            assert!(e.contains(what), "{what}: {e}");
        }
        // Zero on a prescribed or tied DOF is consistent and accepted.
        model.initial_velocities = vec![at(10, 3, 0.0), at(4, 2, 0.0), at(2, 1, 1.0)];
        let system = System::new(&model).unwrap();
        let (v, field) = initial_velocity(&system, None).unwrap();
        assert_eq!(field, VelocityField::Nodal);
        assert_eq!(v.iter().filter(|x| **x != 0.0).count(), 1);
    }

    #[test]
    fn history_columns_are_deduplicated_and_sampled_at_the_gcd() {
        let mut model = frame();
        model.outputs = vec![
            OutputRequest {
                nodes: vec![10],
                dofs: vec![1, 3],
                quantities: vec![Quantity::Displacement, Quantity::Velocity],
                every: 4,
            },
            OutputRequest {
                nodes: vec![10, 1, 4],
                dofs: vec![1],
                quantities: vec![Quantity::Displacement],
                every: 6,
            },
        ];
        model.initial_velocities = vec![InitialVelocity {
            dofs: vec![(1, 100.0)],
            nodes: vec![10],
            quasi_static: false,
        }];
        model.load_cases = vec![transient_case(
            1e-5,
            1e-4,
            TransientMethod::Direct(Integrator::AverageAcceleration),
        )];
        let cases = run(&model).unwrap();
        let CaseSolution::Transient(t) = &cases[0].solution else {
            panic!("transient expected")
        };
        assert_eq!(t.output_every, 2);
        assert_eq!(t.steps, 10);
        assert_eq!(t.history.time_s.len(), 6);
        assert!((t.history.time_s[5] - 1e-4).abs() < 1e-18);
        assert_eq!(
            t.history.names(),
            [
                "node10_ux_disp_m",
                "node10_ux_vel_m_s",
                "node10_uz_disp_m",
                "node10_uz_vel_m_s",
                "node1_ux_disp_m",
                "node4_ux_disp_m",
            ]
        );
        // The prescribed u_z = 0.25 mm of node 10, in m; the clamped node stays at 0.
        let uz = t.history.column("node10_uz_disp_m").unwrap();
        assert!(uz.iter().all(|&x| (x - 0.25e-3).abs() < 1e-15));
        assert!(t
            .history
            .column("node10_uz_vel_m_s")
            .unwrap()
            .iter()
            .all(|&x| x == 0.0));
        assert!(t
            .history
            .column("node1_ux_disp_m")
            .unwrap()
            .iter()
            .all(|&x| x == 0.0));
        assert_eq!(t.history.column("node10_ux_vel_m_s").unwrap()[0], 0.1);
        assert_eq!(t.velocity_field, VelocityField::Nodal);
        assert!(t.warnings.is_empty(), "{:?}", t.warnings);
    }

    #[test]
    fn off_grid_breakpoints_and_partial_steps_warn() {
        let mut model = frame();
        model.tables.push(Table {
            name: "kick".to_string(),
            points: vec![(0.0, 0.0), (1.5e-5, 1.0), (3e-5, 0.0)],
        });
        model.point_loads.push(PointLoad {
            dofs: vec![(2, 1.0)],
            nodes: vec![3],
            table: Some("KICK".to_string()),
        });
        model.load_cases = vec![transient_case(
            1e-5,
            1.05e-4,
            TransientMethod::Direct(Integrator::Hht { alpha: -0.1 }),
        )];
        let cases = run(&model).unwrap();
        let CaseSolution::Transient(t) = &cases[0].solution else {
            panic!("transient expected")
        };
        assert_eq!(t.steps, 11);
        assert_eq!(t.warnings.len(), 3, "{:?}", t.warnings);
        assert!(t.warnings[0].contains("11 steps"), "{}", t.warnings[0]);
        assert!(
            t.warnings[1].contains("table 'kick' has 1 breakpoint(s)"),
            "{}",
            t.warnings[1]
        );
        assert!(
            t.warnings[2].contains("HISTORY OUTPUT"),
            "{}",
            t.warnings[2]
        );
        // A step count beyond reason is an error naming it.
        model.load_cases = vec![transient_case(
            1e-12,
            10.0,
            TransientMethod::Direct(Integrator::AverageAcceleration),
        )];
        assert!(run(&model).unwrap_err().to_string().contains("steps"));
    }

    #[test]
    fn override_keeps_or_replaces_the_method() {
        let mut model = frame();
        let hht = TransientMethod::Direct(Integrator::Hht { alpha: -0.1 });
        model.load_cases = vec![
            transient_case(1e-4, 1e-3, hht),
            transient_case(1e-4, 1e-3, TransientMethod::Modal { modes: 3 }),
        ];
        let methods = |m: &Model| -> Vec<TransientMethod> {
            m.load_cases
                .iter()
                .map(|c| match c.analysis {
                    Analysis::Transient { method, .. } => method,
                    _ => panic!("transient expected"),
                })
                .collect()
        };
        let mut direct = model.clone();
        override_method(&mut direct, MethodOverride::Direct);
        assert_eq!(
            methods(&direct),
            [
                hht,
                TransientMethod::Direct(Integrator::AverageAcceleration)
            ]
        );
        let mut modal = model.clone();
        override_method(&mut modal, MethodOverride::Modal { modes: None });
        assert_eq!(
            methods(&modal),
            [
                TransientMethod::Modal {
                    modes: DEFAULT_MODAL_MODES
                },
                TransientMethod::Modal { modes: 3 }
            ]
        );
        override_method(&mut model, MethodOverride::Modal { modes: Some(5) });
        assert_eq!(methods(&model), [TransientMethod::Modal { modes: 5 }; 2]);
    }

    /// Histories of the frame by modal superposition over every mode (exact: classical
    /// damping, alpha and beta on every element and the point mass) and by direct
    /// average acceleration at `dts`; returns the largest difference of each direct run
    /// relative to the largest displacement. Outputs include a tied node (4) and a
    /// prescribed DOF (node 10 u_z = 0.25 mm).
    fn direct_against_exact_modal(pulse: bool, dts: &[f64]) -> Vec<f64> {
        let mut model = frame();
        model.damping.push(Damping {
            alpha: 50.0,
            beta: 2e-6,
            elements: vec![1, 2, 3],
            mass_nodes: vec![10],
        });
        if pulse {
            model.tables.push(Table {
                name: "pulse".to_string(),
                points: vec![(0.0, 0.0), (2e-4, 1.0), (4e-4, 0.0)],
            });
            model.point_loads.push(PointLoad {
                dofs: vec![(2, 3.0)],
                nodes: vec![10],
                table: Some("pulse".to_string()),
            });
        }
        model.initial_velocities = vec![InitialVelocity {
            dofs: vec![(1, 50.0)],
            nodes: vec![10],
            quasi_static: true,
        }];
        model.outputs = vec![OutputRequest {
            nodes: vec![4, 10],
            dofs: vec![1, 2, 3],
            quantities: vec![Quantity::Displacement],
            every: 1,
        }];
        let n = System::new(&model).unwrap().dim() as u32;
        let fine = dts.iter().copied().fold(f64::INFINITY, f64::min);
        let history = |dt: f64, method| {
            let mut m = model.clone();
            // The static case puts the frame in equilibrium under the prescribed u_z, so
            // the motion starts smoothly from the initial velocity (and the pulse).
            m.load_cases = vec![
                LoadCase {
                    title: "rest".to_string(),
                    analysis: Analysis::Static {
                        steps: 1,
                        time: 1.0,
                    },
                    point_loads: Vec::new(),
                },
                transient_case(dt, 4e-3, method),
            ];
            let cases = run(&m).unwrap();
            match &cases[1].solution {
                CaseSolution::Transient(t) => t.clone(),
                _ => panic!("transient expected"),
            }
        };
        let exact = history(fine, TransientMethod::Modal { modes: n });
        let summary = exact.modal.as_ref().unwrap();
        assert!(summary.max_damping_coupling < 1e-9);
        assert!((summary.initial_velocity_captured.unwrap() - 1.0).abs() < 1e-9);
        if pulse {
            assert!((summary.load_captured.unwrap() - 1.0).abs() < 1e-9);
        }
        let uz = exact.history.column("node10_uz_disp_m").unwrap();
        assert!(uz.iter().all(|&x| (x - 0.25e-3).abs() < 1e-15));
        dts.iter()
            .map(|&dt| {
                let direct = history(dt, TransientMethod::Direct(Integrator::AverageAcceleration));
                let stride = (dt / fine).round() as usize;
                let mut worst: f64 = 0.0;
                let mut size: f64 = 0.0;
                for (a, b) in direct.history.columns.iter().zip(&exact.history.columns) {
                    assert_eq!(a.name, b.name);
                    for (k, x) in a.values.iter().enumerate() {
                        worst = worst.max((x - b.values[k * stride]).abs());
                        size = size.max(x.abs());
                    }
                }
                worst / size
            })
            .collect()
    }

    #[test]
    fn modal_with_every_mode_matches_direct_integration() {
        let smooth = direct_against_exact_modal(false, &[4e-5, 2e-5, 1e-5]);
        let pulse = direct_against_exact_modal(true, &[4e-5, 2e-5, 1e-5]);
        eprintln!("direct vs exact modal: smooth {smooth:?}, pulse {pulse:?}");
        // Halving dt divides the error by 4: second order, also through the pulse, whose
        // breakpoints lie on every step grid (measured 3.6e-6, 9.0e-7, 2.2e-7).
        for errors in [&smooth, &pulse] {
            for pair in errors.windows(2) {
                assert!((pair[0] / pair[1] - 4.0).abs() < 0.2, "{errors:?}");
            }
            assert!(errors[2] < 1e-6, "{errors:?}");
        }
    }

    #[test]
    fn column_names_carry_si_units() {
        assert_eq!(
            column_name(1, 3, Quantity::Acceleration),
            "node1_uz_accel_m_s2"
        );
        assert_eq!(
            column_name(12, 1, Quantity::Displacement),
            "node12_ux_disp_m"
        );
        assert_eq!(column_name(7, 5, Quantity::Velocity), "node7_ry_vel_rad_s");
        assert_eq!(
            column_name(7, 6, Quantity::Acceleration),
            "node7_rz_accel_rad_s2"
        );
        assert_eq!(
            column_name(7, 4, Quantity::Displacement),
            "node7_rx_disp_rad"
        );
    }

    #[test]
    fn csv_round_trips_values_exactly() {
        let history = History {
            time_s: vec![0.0, 0.001, 0.002],
            columns: vec![HistoryColumn {
                name: "node1_uz_disp_m".to_string(),
                values: vec![1.0 / 3.0, -2.5e-300, 0.0],
            }],
        };
        let csv = history.to_csv();
        let mut lines = csv.lines();
        assert_eq!(lines.next(), Some("time_s,node1_uz_disp_m"));
        for (row, line) in lines.enumerate() {
            let fields: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
            assert_eq!(fields[0], history.time_s[row]);
            assert_eq!(fields[1], history.columns[0].values[row]);
        }
    }
}
