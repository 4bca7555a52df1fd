//! The crate's error types, below every module that returns them: [`SolveError`] of
//! building and solving the finite-element system (used by `dof`, `assembly`,
//! `linalg`, `analysis`, `reduce`), the DOF labels its messages use, and [`Error`],
//! which gathers each stage's typed error for callers that drive several stages.
//! This module imports only the model's ids and the lower layers' own errors
//! (`element`), so no layer that returns a [`SolveError`] has to import `analysis`.
//! [`IntegrateError`] of the time integrators and of the factorisations in
//! [`crate::linalg`] lives here too, below both.

use crate::element::ElementError;
use crate::model::{ElementId, NodeId};
use std::path::PathBuf;

/// Short names of DOFs 1..=6, used in messages and result files.
pub const DOF_NAMES: [&str; 6] = ["ux", "uy", "uz", "rx", "ry", "rz"];

/// Name of a DOF number 1..=6 (`"?"` outside, which validated models never contain).
pub fn dof_name(dof: u8) -> &'static str {
    match dof {
        1..=6 => DOF_NAMES[dof as usize - 1],
        _ => "?",
    }
}

/// Errors from building or solving the finite-element system.
#[derive(Debug, thiserror::Error)]
pub enum SolveError {
    /// An element's matrices cannot be formed.
    #[error("element {element}: {source}")]
    Element {
        element: ElementId,
        #[source]
        source: ElementError,
    },
    /// A node id that the model does not define.
    #[error("{context} refers to node {node}, which does not exist")]
    UnknownNode { node: NodeId, context: String },
    /// An element id that the model does not define.
    #[error("{context} refers to element {element}, which does not exist")]
    UnknownElement { element: ElementId, context: String },
    /// A DOF number outside 1..=6.
    #[error("{context} uses DOF {dof}; DOFs are numbered 1..=6 (ux, uy, uz, rx, ry, rz)")]
    BadDof { dof: u8, context: String },
    /// Two constraints on one DOF that cannot both hold.
    #[error("node {node} {}: {reason}", dof_name(*dof))]
    ConflictingConstraint {
        node: NodeId,
        dof: u8,
        reason: String,
    },
    /// The stiffness is singular: a free DOF that nothing resists.
    #[error(
        "mechanism at node {node} {} (DOF {dof}): {detail}; \
         support it (FIXED DISP), tie it (RBE2) or connect it to an element",
        dof_name(*dof)
    )]
    Mechanism {
        node: NodeId,
        dof: u8,
        detail: String,
    },
    /// A value that must be finite is not (or a state became non-finite).
    #[error("non-finite value: {what}")]
    NonFinite { what: String },
    /// An input value outside its admissible range.
    #[error("{what}")]
    BadInput { what: String },
    /// A table named by a load does not exist.
    #[error("{context} refers to table '{name}', which does not exist")]
    UnknownTable { name: String, context: String },
    /// More modes requested than the model has free DOFs.
    #[error("load case '{case}' asks for {requested} modes but the model has only {available} free DOFs")]
    TooManyModes {
        case: String,
        requested: usize,
        available: usize,
    },
    /// The eigensolver did not converge.
    #[error(
        "load case '{case}': the eigensolver converged {converged} of {requested} modes; \
         ask for fewer modes or check the model for a (near) mechanism"
    )]
    EigenNotConverged {
        case: String,
        requested: usize,
        converged: usize,
    },
    /// An analysis kind that this build does not run.
    #[error("load case '{case}': {what} is not supported yet")]
    Unsupported { case: String, what: String },
    /// Nonlinear point elements in a transient solved by modal superposition.
    #[error(
        "load case '{case}': nonlinear point elements (FRICTION, QUADRATIC DAMPER, CUBIC \
         SPRING) need --method direct; modal superposition is linear"
    )]
    NonlinearNeedsDirect { case: String },
    /// The static Newton iterations of the cubic springs did not converge.
    #[error(
        "load case '{case}': the cubic springs' Newton iterations did not converge in \
         {iterations} iterations (relative residual {residual:e})"
    )]
    NewtonNotConverged {
        case: String,
        iterations: usize,
        residual: f64,
    },
    /// A failure inside the sparse linear algebra (allocation, pattern).
    #[error("linear algebra: {0}")]
    Linalg(String),
    /// A time integrator failed (operators not positive definite, non-finite state);
    /// `location` names the node and DOF (direct) or the mode (modal) where it can.
    #[error("load case '{case}': {source}{location}")]
    Integrate {
        case: String,
        location: String,
        #[source]
        source: IntegrateError,
    },
}

/// Any error of coil-solver.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Reading or validating a deck failed.
    #[error(transparent)]
    Deck(#[from] crate::deck::DeckError),
    /// An analysis failed (mechanism, failed eigensolve, non-finite state, ...).
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// The output folder is held by another run, or a file cannot be put there.
    #[error(transparent)]
    Output(#[from] coil_io::SetError),
    /// A result holds a non-finite number: nothing is written.
    #[error("{file}: a non-finite number (NaN or inf) at byte {at} of the results; nothing was written (the model or its loads are out of range)")]
    NonFinite { file: String, at: usize },
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// Any failure of a time integrator or of the factorisations it runs ([`crate::linalg`]).
/// Each variant says where it happened and what to check next; none of them is a panic.
/// DOF indices are the operator's rows, 0-based (the free-DOF numbering after
/// constraint elimination); times are in the operator's unit (s in coil).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IntegrateError {
    /// The time step is zero, negative or not finite.
    #[error("time step dt = {dt} must be finite and > 0")]
    InvalidTimeStep { dt: f64 },

    /// A scheme parameter lies outside the range where the scheme is unconditionally
    /// stable and second-order accurate.
    #[error("{scheme}: {name} = {value} is outside [{min}, {max}]")]
    InvalidParameter {
        scheme: &'static str,
        name: &'static str,
        value: f64,
        min: f64,
        max: f64,
    },

    /// A matrix or vector has the wrong size.
    #[error("{what} has size {found}, expected {expected}")]
    DimensionMismatch {
        what: &'static str,
        expected: usize,
        found: usize,
    },

    /// An operator matrix is not symmetric: entry (row, col) differs from (col, row)
    /// by more than round-off.
    #[error(
        "{matrix} is not symmetric: entry ({row}, {col}) = {value:e} but ({col}, {row}) = \
         {transposed:e}; the integrators need symmetric M, C, K with both triangles stored"
    )]
    NotSymmetric {
        matrix: &'static str,
        row: usize,
        col: usize,
        value: f64,
        transposed: f64,
    },

    /// An input holds NaN or infinity.
    #[error("{what} holds a non-finite value at index {index}")]
    NonFiniteInput { what: &'static str, index: usize },

    /// An operator matrix holds NaN or infinity.
    #[error("{matrix} holds a non-finite value at ({row}, {col})")]
    NonFiniteEntry {
        matrix: &'static str,
        row: usize,
        col: usize,
    },

    /// A Cholesky pivot was not positive: the matrix is singular or indefinite.
    #[error(
        "{matrix} is not positive definite (Cholesky pivot failed at DOF {dof}); look for an \
         unconstrained mechanism, a DOF with neither mass nor stiffness, or negative \
         mass/stiffness near that DOF"
    )]
    NotPositiveDefinite { matrix: &'static str, dof: usize },

    /// The sparse factorisation could not run (out of memory, index overflow).
    #[error("sparse factorisation of {matrix} failed: {message}")]
    Factorization {
        matrix: &'static str,
        message: String,
    },

    /// The state became NaN or infinite during stepping (diverging force, overflow).
    #[error(
        "non-finite state at t = {time} (step {step}), DOF {dof}; check the applied force \
         history at that time"
    )]
    NonFiniteState { step: usize, time: f64, dof: usize },

    /// A modal frequency or damping ratio is negative or not finite.
    #[error("mode {mode}: {name} = {value} must be finite and >= 0")]
    InvalidMode {
        mode: usize,
        name: &'static str,
        value: f64,
    },

    /// A requested output DOF lies outside the mode shapes.
    #[error("output DOF {dof} is out of range (mode shapes have {n_dofs} rows)")]
    DofOutOfRange { dof: usize, n_dofs: usize },

    /// Nonlinear point laws were given to a scheme whose balance is not at the end of
    /// the step (`alpha_m`, `alpha_f` not both zero).
    #[error(
        "nonlinear point laws need Newmark average acceleration (alpha_m = alpha_f = 0); \
         {scheme} balances the forces at a shifted time, where the one-DOF implicit solve \
         of a law does not apply"
    )]
    PointLawScheme { scheme: &'static str },

    /// A point law's DOF is out of range or a coefficient is negative or not finite.
    #[error(
        "point law {index} on DOF {dof}: {reason}; coefficients must be finite, the dashpot's and the friction's >= 0, \
         DOFs below the operator size {n_dofs}"
    )]
    InvalidPointLaw {
        index: usize,
        dof: usize,
        n_dofs: usize,
        reason: &'static str,
    },

    /// A point law's implicit solve failed: a non-finite input, or a softening cubic
    /// spring that lost stability (its tangent stiffness turned negative within the
    /// step's reach).
    #[error(
        "the point law on DOF {dof} has no stable solution at step {step} (t = {time}): \
         a non-finite state, or a softening spring driven beyond its stable amplitude"
    )]
    PointLawUnsolvable { step: usize, time: f64, dof: usize },

    /// The Gauss-Seidel sweeps over several point laws of one step did not converge.
    #[error(
        "the point laws of step {step} (t = {time}) did not converge in {sweeps} \
         Gauss-Seidel sweeps (last change {change:e} N); the laws' DOFs are strongly \
         coupled: try a smaller dt"
    )]
    PointLawsNotConverged {
        step: usize,
        time: f64,
        sweeps: usize,
        change: f64,
    },
}
