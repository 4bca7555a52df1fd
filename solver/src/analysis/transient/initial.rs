//! The initial state of a transient: the initial velocity field of `INITIAL VEL`
//! (plain groups and the quasi-static field `v = K^-1 E c`), the "Initial state"
//! section of [`super`].

use crate::analysis::system::System;
use crate::dof::{dof_name, DofStatus};
use crate::error::solve::SolveError;
use crate::linalg::Cholesky;
use crate::model::InitialVelocity;

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

/// The initial velocity on the free DOFs (see the module docs) and what kind it is.
pub(super) fn initial_velocity(
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
pub(super) fn free_velocities(
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
pub(super) fn quasi_static_field(
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
