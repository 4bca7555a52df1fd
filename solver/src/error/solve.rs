//! [`SolveError`] of building and solving the finite-element system (returned by
//! `dof`, `assembly`, `linalg`, `analysis`, `reduce`) and the DOF labels its messages
//! use. It imports only the model's ids and the lower layers' own errors (`element`,
//! [`super::integrate`]), so no layer that returns it has to import `analysis`.

use super::integrate::IntegrateError;
use crate::element::ElementError;
use crate::model::{ElementId, NodeId};

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
        /// The element's id.
        element: ElementId,
        /// Why its matrices cannot be formed.
        #[source]
        source: ElementError,
    },
    /// A node id that the model does not define.
    #[error("{context} refers to node {node}, which does not exist")]
    UnknownNode {
        /// The node's id.
        node: NodeId,
        /// What refers to it.
        context: String,
    },
    /// An element id that the model does not define.
    #[error("{context} refers to element {element}, which does not exist")]
    UnknownElement {
        /// The element's id.
        element: ElementId,
        /// What refers to it.
        context: String,
    },
    /// A DOF number outside 1..=6.
    #[error("{context} uses DOF {dof}; DOFs are numbered 1..=6 (ux, uy, uz, rx, ry, rz)")]
    BadDof {
        /// The DOF number given.
        dof: u8,
        /// Where it is used.
        context: String,
    },
    /// Two constraints on one DOF that cannot both hold.
    #[error("node {node} {}: {reason}", dof_name(*dof))]
    ConflictingConstraint {
        /// The node's id.
        node: NodeId,
        /// The DOF number (1..=6).
        dof: u8,
        /// Why the two constraints cannot both hold.
        reason: String,
    },
    /// The stiffness is singular: a free DOF that nothing resists.
    #[error(
        "mechanism at node {node} {} (DOF {dof}): {detail}; \
         support it (FIXED DISP), tie it (RBE2) or connect it to an element",
        dof_name(*dof)
    )]
    Mechanism {
        /// The node's id.
        node: NodeId,
        /// The DOF number (1..=6).
        dof: u8,
        /// What leaves the DOF unrestrained.
        detail: String,
    },
    /// A value that must be finite is not (or a state became non-finite).
    #[error("non-finite value: {what}")]
    NonFinite {
        /// What is not finite.
        what: String,
    },
    /// An input value outside its admissible range.
    #[error("{what}")]
    BadInput {
        /// What is wrong, and what is admissible.
        what: String,
    },
    /// A table named by a load does not exist.
    #[error("{context} refers to table '{name}', which does not exist")]
    UnknownTable {
        /// The table's name.
        name: String,
        /// What refers to it.
        context: String,
    },
    /// More modes requested than the model has free DOFs.
    #[error("load case '{case}' asks for {requested} modes but the model has only {available} free DOFs")]
    TooManyModes {
        /// The load case's title.
        case: String,
        /// Number of modes asked for.
        requested: usize,
        /// Number of free DOFs of the model.
        available: usize,
    },
    /// The eigensolver did not converge.
    #[error(
        "load case '{case}': the eigensolver converged {converged} of {requested} modes; \
         ask for fewer modes or check the model for a (near) mechanism"
    )]
    EigenNotConverged {
        /// The load case's title.
        case: String,
        /// Number of modes asked for.
        requested: usize,
        /// Number of modes that converged.
        converged: usize,
    },
    /// An analysis kind that this build does not run.
    #[error("load case '{case}': {what} is not supported yet")]
    Unsupported {
        /// The load case's title.
        case: String,
        /// The analysis (or option) not supported.
        what: String,
    },
    /// Nonlinear point elements in a transient solved by modal superposition.
    #[error(
        "load case '{case}': nonlinear point elements (FRICTION, QUADRATIC DAMPER, CUBIC \
         SPRING) need --method direct; modal superposition is linear"
    )]
    NonlinearNeedsDirect {
        /// The load case's title.
        case: String,
    },
    /// The static Newton iterations of the cubic springs did not converge.
    #[error(
        "load case '{case}': the cubic springs' Newton iterations did not converge in \
         {iterations} iterations (relative residual {residual:e})"
    )]
    NewtonNotConverged {
        /// The load case's title.
        case: String,
        /// Number of Newton iterations run.
        iterations: usize,
        /// The last relative residual.
        residual: f64,
    },
    /// A failure inside the sparse linear algebra (allocation, pattern).
    #[error("linear algebra: {0}")]
    Linalg(String),
    /// A time integrator failed (operators not positive definite, non-finite state);
    /// `location` names the node and DOF (direct) or the mode (modal) where it can.
    #[error("load case '{case}': {source}{location}")]
    Integrate {
        /// The load case's title.
        case: String,
        /// The node and DOF, or the mode, it failed at (` (...)`), or empty.
        location: String,
        /// The integrator's error.
        #[source]
        source: IntegrateError,
    },
}
