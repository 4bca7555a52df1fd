//! Linear static analysis: `K_r q = T^T f - T^T K g`, then `u = T q + g`.
//!
//! Outputs, all in model units (mm, rad, N, N mm):
//! - the full displacement vector (every node, including tied and prescribed DOFs);
//! - reactions at the prescribed DOFs, `T_p^T (K u - f)` (see [`crate::dof`]), so a
//!   reaction includes what rigid ties carry to a supported reference node;
//! - for every loaded DOF the load F, the displacement u and the stiffness F/u;
//! - the spring stiffness `stiffness_n_mm`: F/u of the loaded DOF at the reference
//!   node of a rigid tie (the spring's weight node), or of the only loaded DOF when no
//!   reference node is loaded. It is positive when force and displacement have the same
//!   sign, so a compressive force with its compressive displacement gives K > 0.

use super::{SolveError, System};
use crate::linalg::Cholesky;
use crate::model::{LoadCase, Model, NodeId, DOFS_PER_NODE};

/// A reaction force (N) or moment (N mm) at a prescribed DOF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reaction {
    pub node: NodeId,
    pub dof: u8,
    pub value: f64,
}

/// A loaded DOF with its load (N or N mm), displacement (mm or rad) and F/u.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoadedDof {
    pub node: NodeId,
    pub dof: u8,
    pub load: f64,
    pub displacement: f64,
    /// `load / displacement`, `None` when the displacement is exactly zero.
    pub stiffness: Option<f64>,
}

/// Result of a static load case.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticSolution {
    /// Full displacement vector (6 per node, mm and rad).
    pub displacement: Vec<f64>,
    pub reactions: Vec<Reaction>,
    pub loaded: Vec<LoadedDof>,
    /// The loaded reference node whose F/u is the stiffness, if one is identified.
    pub reference_node: Option<NodeId>,
    /// F/u at the reference node's loaded translational DOF (N/mm).
    pub stiffness_n_mm: Option<f64>,
    /// Equilibrium check `|T^T (K u - f)| / |T^T f|` over the free DOFs.
    pub relative_residual: f64,
}

impl StaticSolution {
    /// The six displacements of a node (mm, mm, mm, rad, rad, rad).
    pub fn node_displacement(&self, model: &Model, node: NodeId) -> Option<[f64; 6]> {
        let i = model.node_index(node)?;
        let mut out = [0.0; 6];
        out.copy_from_slice(&self.displacement[i * DOFS_PER_NODE..(i + 1) * DOFS_PER_NODE]);
        Some(out)
    }
}

/// Solves one static load case with a factor of the system's stiffness.
pub fn solve(
    system: &System,
    factor: &Cholesky,
    case: &LoadCase,
    time: f64,
) -> Result<StaticSolution, SolveError> {
    let model = system.model;
    let dofs = &system.dofs;
    let f_full =
        system.point_load_vector(model.point_loads.iter().chain(&case.point_loads), time)?;
    let rhs = system.free_load(&f_full);
    let mut q = rhs.clone();
    factor.solve_in_place(&mut q);
    if q.iter().any(|v| !v.is_finite()) {
        return Err(SolveError::NonFinite {
            what: format!("static displacements of load case '{}'", case.title),
        });
    }
    let displacement = dofs.expand(&q, 1.0);
    let residual = system.residual(&displacement, &f_full);

    // Equilibrium of the free equations, relative to the applied load.
    let mut free_residual = vec![0.0; dofs.free_len()];
    dofs.restrict_add(&residual, &mut free_residual);
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let load_norm = norm(&rhs);
    let relative_residual = if load_norm > 0.0 {
        norm(&free_residual) / load_norm
    } else {
        0.0
    };

    let reactions = dofs
        .reactions(&residual)
        .into_iter()
        .map(|(d, value)| {
            let (node, dof) = dofs.label(d);
            Reaction { node, dof, value }
        })
        .collect();
    let loaded: Vec<LoadedDof> = f_full
        .iter()
        .enumerate()
        .filter(|(_, f)| **f != 0.0)
        .map(|(d, &load)| {
            let (node, dof) = dofs.label(d);
            let u = displacement[d];
            LoadedDof {
                node,
                dof,
                load,
                displacement: u,
                stiffness: (u != 0.0).then(|| load / u),
            }
        })
        .collect();

    let is_reference = |node: NodeId| model.rigid_ties.iter().any(|t| t.reference == node);
    let at_reference: Vec<&LoadedDof> = loaded.iter().filter(|l| is_reference(l.node)).collect();
    let chosen = match (at_reference.as_slice(), loaded.as_slice()) {
        ([one], _) => Some(*one),
        ([], [one]) => Some(one),
        _ => None,
    };
    let reference_node = chosen.map(|l| l.node);
    let stiffness_n_mm = chosen.filter(|l| l.dof <= 3).and_then(|l| l.stiffness);
    Ok(StaticSolution {
        displacement,
        reactions,
        loaded,
        reference_node,
        stiffness_n_mm,
        relative_residual,
    })
}
