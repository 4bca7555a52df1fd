//! An integrator's error located for the user: the free DOF it names turned into a node
//! and DOF label (direct path), or the mode it names (modal superposition).

use crate::analysis::system::System;
use crate::dof::dof_name;
use crate::error::solve::SolveError;
use crate::integrate::IntegrateError;

/// An integrator error with the free DOF (or mode) it names turned into a node label.
pub(super) fn integrate_error(
    system: &System,
    case: &str,
    modal: bool,
    source: IntegrateError,
) -> SolveError {
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
