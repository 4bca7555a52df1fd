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
